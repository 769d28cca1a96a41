/*
 * Unit tests: the extreme grades around each preview sample that bound the
 * prediction (pfe_predict.h, window_low_20ppm / window_high_20ppm), for a
 * narrow window and for a wide one (which the block method of
 * pfe_predict.c handles at the same cost per sample), on a preview with
 * one bump and one dip whose windows can be drawn by hand.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "pfe_calib.h"
#include "pfe_codec.h"
#include "pfe_fixed.h"
#include "pfe_platoon.h"
#include "pfe_predict.h"

#define SAMPLES 100U
#define SPACING_M 10U
#define BUMP 50U   /* +2 % */
#define DIP 20U    /* -1 % */

static pfe_preview_t g_pv;
static pfe_predict_t g_pred;
static pfe_platoon_t g_pl;

static void send_preview(void)
{
    int32_t grade[SAMPLES];
    for (uint32_t k = 0U; k < SAMPLES; k++) {
        grade[k] = 0;
    }
    grade[BUMP] = 20000;
    grade[DIP] = -10000;
    pfe_preview_init(&g_pv);
    pfe_can_frame_t f;
    pfe_msg_grade_preview_t m;
    memset(&m, 0, sizeof m);
    m.frame_type.value = PFE_PREVIEW_FRAME_HEADER;
    m.preview_id.value = 5U;
    m.sample_count.value = SAMPLES;
    m.spacing_m.value = SPACING_M;
    ASSERT_GE(pfe_codec_encode_grade_preview(&f, &m, 0x33U), 0);
    ASSERT_GE(pfe_preview_push(&g_pv, &f), 0);
    for (uint32_t k = 0U; k < SAMPLES; k += PFE_PREVIEW_SAMPLES_PER_FRAME) {
        memset(&m, 0, sizeof m);
        m.frame_type.value = PFE_PREVIEW_FRAME_DATA;
        m.preview_id.value = 5U;
        m.first_index.value = k;
        for (uint32_t j = 0U; j < PFE_PREVIEW_SAMPLES_PER_FRAME; j++) {
            if ((k + j) < SAMPLES) {
                m.grade_ppm[j].value = grade[k + j];
            } else {
                m.grade_ppm[j].state = PFE_SIG_NOT_AVAILABLE;
            }
        }
        ASSERT_GE(pfe_codec_encode_grade_preview(&f, &m, 0x33U), 0);
        ASSERT_GE(pfe_preview_push(&g_pv, &f), 0);
    }
    assert_int_equal(g_pv.phase, PFE_PREVIEW_READY);
}

/* Five trucks gap_mm apart; predicts to the end in slices of 36 units. */
static void predict(uint32_t gap_mm)
{
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, 5U, gap_mm, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    assert_int_equal(pfe_platoon_init(&g_pl, &cfg), PFE_OK);
    send_preview();
    pfe_predict_init(&g_pred);
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, 1U, 0U, &g_pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_OK);
    pfe_predict_phase_t ph;
    uint32_t slices = 0U;
    do {
        ph = pfe_predict_run(&g_pred, &g_pv, 36U);
        slices++;
        ASSERT_LT(slices, 10000U);
    } while ((ph != PFE_PREDICT_DONE) && (ph != PFE_PREDICT_IDLE));
    assert_int_equal(ph, PFE_PREDICT_DONE);
    const pfe_predict_result_t *r = pfe_predict_result(&g_pred);
    assert_true(r->valid);
    ASSERT_LE(r->fuel_lower_ul, r->fuel_ul);
    ASSERT_LE(r->fuel_ul, r->fuel_upper_ul);
}

/* Window of half-width w samples: the bump's 2 % (1000 in 20 ppm) within w
 * of sample 50, the dip's -1 % (-500) within w of sample 20, 0 elsewhere. */
static void check_windows(uint32_t w)
{
    assert_int_equal(g_pred.window_samples, w);
    for (uint32_t k = 0U; k < SAMPLES; k++) {
        const bool near_bump = (k + w >= BUMP) && (k <= BUMP + w);
        const bool near_dip = (k + w >= DIP) && (k <= DIP + w);
        if (near_bump) {
            assert_int_equal(g_pred.window_high_20ppm[k], 1000);
        } else {
            assert_int_equal(g_pred.window_high_20ppm[k], 0);
        }
        if (near_dip) {
            assert_int_equal(g_pred.window_low_20ppm[k], -500);
        } else {
            assert_int_equal(g_pred.window_low_20ppm[k], 0);
        }
    }
}

/* 4 gaps of 20 m over 10 m samples: w = 8, the queue of 64 holds 17. */
static void test_narrow_window(void **state)
{
    (void)state;
    predict(20000U);
    check_windows(8U);
}

/* 4 gaps of 80 m: w = 32, 65 samples: more than the queue; every window
 * is scanned whole instead. */
static void test_window_wider_than_the_queue(void **state)
{
    (void)state;
    predict(80000U);
    check_windows(32U);
}

/* 4 gaps of 75 m: 300 m over 10 m samples rounds up to w = 30. */
static void test_window_rounds_up(void **state)
{
    (void)state;
    predict(75000U);
    check_windows(30U);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_narrow_window),
        cmocka_unit_test(test_window_wider_than_the_queue),
        cmocka_unit_test(test_window_rounds_up),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
