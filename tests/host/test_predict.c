/*
 * The module's prediction over a grade preview (firmware/pfe_predict.h)
 * against the double-precision object model (sim_host/ref/ref_model.h) on the
 * same preview, as it arrives on CAN: each road of sim_host/data/roads encoded as
 * PFE_GradePreview frames, reassembled by pfe_preview_push(), then predicted
 * in slices of work as the ECU does. Fuel and time within 1 % of the
 * reference; the bounds around the prediction; hand-computed literals on the
 * flat road.
 *
 *   test_predict ROADS_DIR
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "firmware/pfe_calib.h"
#include "firmware/pfe_codec.h"
#include "firmware/pfe_ecu.h"
#include "firmware/pfe_platoon.h"
#include "firmware/pfe_predict.h"
#include "ref/ref_model.h"
#include "lib/road_csv.h"

#define BUDGET PFE_ECU_PREDICT_UNITS /* work units per tick, as the ECU gives */

static const char *g_roads;
static pfe_preview_t g_pv;
static pfe_predict_t g_pred;
static uint32_t g_serial; /* counts previews sent, as the ECU does */

/* Sends road (spacing a whole number of metres) as one preview, frame by frame. */
static void send_preview(const int32_t *grade_ppm, uint32_t n, uint32_t spacing_m, uint8_t id)
{
    pfe_can_frame_t f;
    pfe_msg_grade_preview_t m;
    memset(&m, 0, sizeof m);
    m.frame_type.value = PFE_PREVIEW_FRAME_HEADER;
    m.preview_id.value = id;
    m.sample_count.value = n;
    m.spacing_m.value = spacing_m;
    ASSERT_GE(pfe_codec_encode_grade_preview(&f, &m, 0x33U), 0);
    ASSERT_GE(pfe_preview_push(&g_pv, &f), 0);
    for (uint32_t k = 0U; k < n; k += PFE_PREVIEW_SAMPLES_PER_FRAME) {
        memset(&m, 0, sizeof m);
        m.frame_type.value = PFE_PREVIEW_FRAME_DATA;
        m.preview_id.value = id;
        m.first_index.value = k;
        for (uint32_t j = 0U; j < PFE_PREVIEW_SAMPLES_PER_FRAME; j++) {
            if ((k + j) < n) {
                m.grade_ppm[j].value = grade_ppm[k + j];
            } else {
                m.grade_ppm[j].state = PFE_SIG_NOT_AVAILABLE;
            }
        }
        ASSERT_GE(pfe_codec_encode_grade_preview(&f, &m, 0x33U), 0);
        ASSERT_GE(pfe_preview_push(&g_pv, &f), 0);
    }
    assert_int_equal(g_pv.phase, PFE_PREVIEW_READY);
    g_serial++;
}

static void make_platoon(pfe_platoon_t *pl, pfe_platoon_config_t *cfg, uint32_t n)
{
    pfe_platoon_config_uniform(cfg, n, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    assert_int_equal(pfe_platoon_init(pl, cfg), PFE_OK);
}

/* Runs a started prediction to its end in slices; returns the slices. */
static uint32_t run_to_end(void)
{
    uint32_t slices = 0U;
    pfe_predict_phase_t ph;
    do {
        ph = pfe_predict_run(&g_pred, &g_pv, BUDGET);
        slices++;
        ASSERT_LT(slices, 100000U);
    } while ((ph != PFE_PREDICT_DONE) && (ph != PFE_PREDICT_IDLE));
    return slices;
}

typedef struct {
    double fuel_l;
    double time_s;
} ref_result_t;

/* The double-precision object model over samples first .. n - 1 as the preview holds them. */
static ref_result_t reference(const pfe_platoon_config_t *cfg, uint32_t first, double speed)
{
    const uint32_t n = g_pv.sample_count - first;
    double *grade = malloc(sizeof(double) * n);
    assert_non_null(grade);
    for (uint32_t k = 0U; k < n; k++) {
        int32_t g = 0;
        assert_int_equal(pfe_preview_grade_ppm(&g_pv, first + k, &g), PFE_SIG_VALID);
        grade[k] = g / 1e6;
    }
    static ref_platoon_t rpl;
    assert_int_equal(ref_platoon_init(&rpl, cfg), 0);
    const ref_road_t road = {grade, n, g_pv.spacing_m};
    ref_sim_t sim;
    const double step = (g_pv.spacing_m < 16.0) ? g_pv.spacing_m : 16.0; /* as the module */
    assert_int_equal(ref_sim_init(&sim, &rpl, &pfe_default_cruise, &road, 25.0, speed, step), 0);
    int r;
    while ((r = ref_sim_step(&sim, &road)) == 1) {
    }
    assert_int_equal(r, 0);
    free(grade);
    const ref_result_t out = {sim.fuel, sim.time};
    return out;
}

/* A road of sim_host/data/roads as a preview: samples quantised to the message's
 * 20 ppm on the way. */
static void load_road(const char *name, road_ppm_t *road)
{
    char path[512], err[256];
    (void)snprintf(path, sizeof path, "%s/%s.csv", g_roads, name);
    assert_int_equal(road_ppm_load(path, road, err, sizeof err), 0);
    ASSERT_LE(road->n_samples, PFE_PREVIEW_MAX_SAMPLES);
    assert_int_equal(road->spacing_mm % 1000U, 0U);
}

static void check_road(const char *name, uint32_t n_vehicles, uint32_t travelled_m)
{
    road_ppm_t road;
    load_road(name, &road);
    pfe_preview_init(&g_pv);
    send_preview(road.grade_ppm, road.n_samples, road.spacing_mm / 1000U, 3U);
    pfe_platoon_t pl;
    pfe_platoon_config_t cfg;
    make_platoon(&pl, &cfg, n_vehicles);
    pfe_predict_init(&g_pred);
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, travelled_m * 1000U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_OK);
    const uint32_t slices = run_to_end();
    const pfe_predict_result_t *r = pfe_predict_result(&g_pred);
    assert_true(r->valid);
    const uint32_t first = (travelled_m * 1000U) / road.spacing_mm;
    const ref_result_t ref = reference(&cfg, first, 25.0);
    const double fuel = (double)r->fuel_ul / 1e6, time = (double)r->time_ms / 1e3;
    const double e_fuel = (fuel - ref.fuel_l) / ref.fuel_l * 100.0;
    const double e_time = (time - ref.time_s) / ref.time_s * 100.0;
    printf("predict %-6s N=%u from %5u m: fuel %.4f L (ref %.4f L, %+.4f %%), time %.1f s "
           "(ref %.1f s, %+.4f %%), bounds [%.4f, %.4f] L, %u slices of %u units\n",
           name, n_vehicles, travelled_m, fuel, ref.fuel_l, e_fuel, time, ref.time_s, e_time,
           (double)r->fuel_lower_ul / 1e6, (double)r->fuel_upper_ul / 1e6, slices, BUDGET);
    ASSERT_LT(fabs(e_fuel), 1.0);
    ASSERT_LT(fabs(e_time), 1.0);
    ASSERT_LE(r->fuel_lower_ul, r->fuel_ul);
    ASSERT_LE(r->fuel_ul, r->fuel_upper_ul);
    assert_int_equal(r->distance_m, ((road.n_samples - first) * road.spacing_mm) / 1000U);
    road_ppm_free(&road);
}

static void test_hilly_n5_within_one_percent(void **state)
{
    (void)state;
    check_road("hilly", 5U, 0U);
}

static void test_uphill_n5_within_one_percent(void **state)
{
    (void)state;
    check_road("uphill", 5U, 0U);
}

static void test_flat_n5_within_one_percent(void **state)
{
    (void)state;
    check_road("flat", 5U, 0U);
}

static void test_hilly_from_halfway(void **state)
{
    (void)state;
    check_road("hilly", 5U, 6000U);
}

/* One truck, flat 12 km at 90 km/h (default calibration, docs/model.md): 5166 N of
 * resistance over 12000 m is 61.99 MJ, 4 kW of auxiliaries over 480 s 1.92
 * MJ; (61.99 + 1.92) MJ / (0.40 * 35800 J/mL) = 4.463 L. With one truck and
 * no grade the bounds' runs equal the nominal one: the bounds lie within
 * 500 uL of each other, around the prediction. */
/* A second prediction over the same preview starts from the prepared one
 * (no copy, no windows) and gives exactly what a fresh preparation gives. */
static void test_prepared_preview_is_reused(void **state)
{
    (void)state;
    road_ppm_t road;
    load_road("hilly", &road);
    pfe_preview_init(&g_pv);
    send_preview(road.grade_ppm, road.n_samples, road.spacing_mm / 1000U, 4U);
    pfe_platoon_t pl;
    pfe_platoon_config_t cfg;
    make_platoon(&pl, &cfg, 5U);
    pfe_predict_init(&g_pred);
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_OK);
    assert_int_equal(g_pred.phase, PFE_PREDICT_LOADING);
    (void)run_to_end();
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 3000000U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 24000),
                     PFE_OK);
    assert_int_equal(g_pred.phase, PFE_PREDICT_NOMINAL);
    const uint32_t slices_again = run_to_end();
    const pfe_predict_result_t again = *pfe_predict_result(&g_pred);
    /* The same preview under a new serial number: prepared anew. */
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial + 100U, 3000000U, &pl,
                                       &pfe_default_drag, &pfe_default_cruise, 25000, 24000),
                     PFE_OK);
    assert_int_equal(g_pred.phase, PFE_PREDICT_LOADING);
    const uint32_t slices_fresh = run_to_end();
    const pfe_predict_result_t *fresh = pfe_predict_result(&g_pred);
    ASSERT_LT(slices_again, slices_fresh);
    assert_int_equal(again.fuel_ul, fresh->fuel_ul);
    assert_int_equal(again.fuel_lower_ul, fresh->fuel_lower_ul);
    assert_int_equal(again.fuel_upper_ul, fresh->fuel_upper_ul);
    assert_int_equal(again.time_ms, fresh->time_ms);
    assert_int_equal(again.distance_m, 9000U);
    /* Another platoon length: prepared anew (its windows are wider). */
    make_platoon(&pl, &cfg, 8U);
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial + 100U, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_OK);
    assert_int_equal(g_pred.phase, PFE_PREDICT_LOADING);
    road_ppm_free(&road);
}

/* Grades for the window tests: a fixed pseudo-random walk over the whole
 * signal range (+-64 %, beyond the module's +-50 % clamp), in 20 ppm steps. */
static void walk_grades(int32_t *grade, uint32_t n, uint32_t seed)
{
    uint32_t x = seed;
    int32_t g = 0;
    for (uint32_t k = 0U; k < n; k++) {
        x = (x * 1103515245U) + 12345U;
        const int32_t step = (int32_t)((x >> 16) % 2001U) - 1000; /* +-2 % */
        g += step * 20;
        g = (g > 640000) ? (640000 - ((g - 640000) * 2)) : g;
        g = (g < -640000) ? (-640000 + ((-640000 - g) * 2)) : g;
        grade[k] = ((k % 37U) == 5U) ? 600000 : g; /* now and then beyond the clamp */
    }
}

/* The module's grade range, +-50 %. */
static int32_t clamped(int32_t g)
{
    return (g > 500000) ? 500000 : ((g < -500000) ? -500000 : g);
}

/* Each window extreme by a plain scan of the clamped preview: the largest
 * and smallest grade of samples k - w .. k + w within the preview. */
static void check_windows_by_scan(const pfe_predict_t *p, const int32_t *grade, uint32_t n, uint32_t w)
{
    assert_int_equal(p->window_samples, w);
    for (uint32_t k = 0U; k < n; k++) {
        int32_t lo = INT32_MAX, hi = INT32_MIN;
        for (uint32_t j = (k > w) ? (k - w) : 0U; (j <= (k + w)) && (j < n); j++) {
            lo = (clamped(grade[j]) < lo) ? clamped(grade[j]) : lo;
            hi = (clamped(grade[j]) > hi) ? clamped(grade[j]) : hi;
        }
        assert_int_equal(p->window_low_20ppm[k], lo / 20);
        assert_int_equal(p->window_high_20ppm[k], hi / 20);
        assert_int_equal(p->grade_ppm[k], clamped(grade[k]));
    }
}

/* Prepares a preview of n samples 10 m apart for n_vehicles gap_mm apart,
 * budget units per call, and checks the windows (window w). */
static void prepare_and_check(uint32_t n, uint32_t n_vehicles, uint32_t gap_mm, uint32_t budget,
                              uint32_t w)
{
    static int32_t grade[PFE_PREVIEW_MAX_SAMPLES];
    walk_grades(grade, n, n * 7U + w);
    pfe_preview_init(&g_pv);
    send_preview(grade, n, 10U, 6U);
    pfe_platoon_t pl;
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, n_vehicles, gap_mm, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);
    pfe_predict_init(&g_pred);
    (void)memset(g_pred.window_low_20ppm, 0xA5, sizeof g_pred.window_low_20ppm);
    (void)memset(g_pred.window_high_20ppm, 0xA5, sizeof g_pred.window_high_20ppm);
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_OK);
    uint32_t calls = 0U;
    while ((g_pred.phase == PFE_PREDICT_LOADING) || (g_pred.phase == PFE_PREDICT_WINDOWS)) {
        (void)pfe_predict_run(&g_pred, &g_pv, budget);
        calls++;
        ASSERT_LT(calls, 100000U);
    }
    assert_int_equal(g_pred.phase, PFE_PREDICT_NOMINAL);
    check_windows_by_scan(&g_pred, grade, n, w);
}

/* Windows narrow and wide, one truck (w = 0), windows wider than the
 * preview, a preview of one sample; one unit a call (every resumption
 * point of both passes) and all at once. 10 m samples: 4 gaps of g metres
 * give w = ceil(4 g / 10). */
static void test_windows_match_a_plain_scan(void **state)
{
    (void)state;
    static const struct {
        uint32_t n, vehicles, gap_mm, w;
    } cases[] = {
        {1000U, 5U, 10000U, 4U},   /* the bench's */
        {1000U, 5U, 20000U, 8U},
        {997U, 5U, 75000U, 30U},
        {1000U, 5U, 80000U, 32U},  /* 65 samples a window */
        {500U, 5U, 2500000U, 1000U}, /* every window the whole preview */
        {300U, 1U, 10000U, 0U},    /* one truck: each sample its own window */
        {1U, 5U, 10000U, 4U},
        {2U, 2U, 10000U, 1U},
        {9U, 5U, 10000U, 4U},      /* one block exactly */
        {10U, 5U, 10000U, 4U},
    };
    for (size_t c = 0U; c < (sizeof cases / sizeof cases[0]); c++) {
        prepare_and_check(cases[c].n, cases[c].vehicles, cases[c].gap_mm, 1U, cases[c].w);
        prepare_and_check(cases[c].n, cases[c].vehicles, cases[c].gap_mm, UINT32_MAX, cases[c].w);
    }
}

/* A restart in the middle of either pass leaves nothing of the old
 * preparation: the result equals a fresh predictor's on the same inputs. */
static void test_restart_mid_preparation(void **state)
{
    (void)state;
    static int32_t grade[600], other[600];
    walk_grades(grade, 600U, 11U);
    walk_grades(other, 600U, 12U);
    for (uint32_t k = 0U; k < 600U; k++) { /* drivable: within +-3 % */
        grade[k] = (grade[k] / 20 % 1500) * 20;
        other[k] = (other[k] / 20 % 1500) * 20;
    }
    pfe_platoon_t pl5, pl8;
    pfe_platoon_config_t cfg;
    make_platoon(&pl5, &cfg, 5U);
    make_platoon(&pl8, &cfg, 8U);
    /* The reference: the second preview, 8 trucks, on a fresh predictor. */
    pfe_preview_init(&g_pv);
    send_preview(other, 600U, 10U, 7U);
    pfe_predict_init(&g_pred);
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 0U, &pl8, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_OK);
    (void)run_to_end();
    const pfe_predict_result_t fresh = *pfe_predict_result(&g_pred);
    assert_true(fresh.valid);
    static int16_t low[600], high[600];
    (void)memcpy(low, g_pred.window_low_20ppm, sizeof low);
    (void)memcpy(high, g_pred.window_high_20ppm, sizeof high);
    for (uint32_t stop = 0U; stop < 2U; stop++) {
        const pfe_predict_phase_t where = (stop == 0U) ? PFE_PREDICT_LOADING : PFE_PREDICT_WINDOWS;
        /* The first preview, 5 trucks, stopped mid-way through a pass. */
        pfe_preview_init(&g_pv);
        send_preview(grade, 600U, 10U, 8U);
        pfe_predict_init(&g_pred);
        assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 0U, &pl5, &pfe_default_drag,
                                           &pfe_default_cruise, 25000, 25000),
                         PFE_OK);
        while (g_pred.phase != where) {
            (void)pfe_predict_run(&g_pred, &g_pv, 1U);
        }
        for (uint32_t k = 0U; k < 20U; k++) {
            assert_int_equal(pfe_predict_run(&g_pred, &g_pv, 1U), where);
        }
        /* Same preview, another platoon length: prepared anew. */
        assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 0U, &pl8, &pfe_default_drag,
                                           &pfe_default_cruise, 25000, 25000),
                         PFE_OK);
        assert_int_equal(g_pred.phase, PFE_PREDICT_LOADING);
        while (g_pred.phase != where) {
            (void)pfe_predict_run(&g_pred, &g_pv, 1U);
        }
        for (uint32_t k = 0U; k < 20U; k++) {
            (void)pfe_predict_run(&g_pred, &g_pv, 1U);
        }
        /* A new preview arrives: the predictor restarts on it. */
        send_preview(other, 600U, 10U, 9U);
        assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 0U, &pl8, &pfe_default_drag,
                                           &pfe_default_cruise, 25000, 25000),
                         PFE_OK);
        assert_int_equal(g_pred.phase, PFE_PREDICT_LOADING);
        (void)run_to_end();
        const pfe_predict_result_t *r = pfe_predict_result(&g_pred);
        assert_true(r->valid);
        assert_int_equal(r->fuel_ul, fresh.fuel_ul);
        assert_int_equal(r->fuel_lower_ul, fresh.fuel_lower_ul);
        assert_int_equal(r->fuel_upper_ul, fresh.fuel_upper_ul);
        assert_int_equal(r->time_ms, fresh.time_ms);
        assert_memory_equal(g_pred.window_low_20ppm, low, sizeof low);
        assert_memory_equal(g_pred.window_high_20ppm, high, sizeof high);
    }
}

static void test_flat_one_truck_literals(void **state)
{
    (void)state;
    road_ppm_t road;
    load_road("flat", &road);
    pfe_preview_init(&g_pv);
    send_preview(road.grade_ppm, road.n_samples, road.spacing_mm / 1000U, 0U);
    pfe_platoon_t pl;
    pfe_platoon_config_t cfg;
    make_platoon(&pl, &cfg, 1U);
    pfe_predict_init(&g_pred);
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_OK);
    (void)run_to_end();
    const pfe_predict_result_t *r = pfe_predict_result(&g_pred);
    assert_true(r->valid);
    ASSERT_LT(labs((long)r->time_ms - 480000L), 100L);     /* 480.0 s */
    ASSERT_LT(labs((long)r->fuel_ul - 4463000L), 4500L);   /* 4.463 L within 0.1 % */
    /* The bounds' runs are the nominal one: the bounds differ from it by
     * the runs' discretisation only, and are widened to the prediction. */
    ASSERT_LE(r->fuel_lower_ul, r->fuel_ul);
    ASSERT_LE(r->fuel_ul, r->fuel_upper_ul);
    ASSERT_LT(r->fuel_upper_ul - r->fuel_lower_ul, 500U);
    printf("predict flat   N=1: fuel %llu uL, bounds [%llu, %llu] uL\n",
           (unsigned long long)r->fuel_ul, (unsigned long long)r->fuel_lower_ul,
           (unsigned long long)r->fuel_upper_ul);
    road_ppm_free(&road);
}

static void test_bound_platoons_formation_drag(void **state)
{
    (void)state;
    road_ppm_t road;
    load_road("flat", &road);
    pfe_preview_init(&g_pv);
    send_preview(road.grade_ppm, road.n_samples, road.spacing_mm / 1000U, 0U);
    /* Four default trucks and a 30 t one: M = 190 t. The slow platoon gives
     * every truck the unreduced 3.87 N/(m/s)^2 (16621.6 * 2^-32 N/(mm/s)^2),
     * and the 30 t truck has the most per kg: c = 16621.6 (190 / 30 - 5) =
     * 22162. The nominal platoon's lead truck has 0.92 of it on 40 t, more
     * per kg than the 30 t follower's 0.65 (0.023 against 0.0217), so
     * c = 16621.6 (0.92 * 190 / 40 - (0.92 + 0.69 + 3 * 0.65)) = 13463.
     * The fast platoon has none. */
    static const pfe_vehicle_calib_t light = {30000U, 1200U, 6000000U, 7000U, 250000U, 100000U,
                                              60000U, 4000U, 400000U};
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, 5U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    cfg.vehicle[4] = &light;
    pfe_platoon_t pl;
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);
    assert_in_range(pl.formation_air_q32, 13463 - 3, 13463 + 3);
    pfe_predict_init(&g_pred);
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_OK);
    assert_in_range(g_pred.formation_slow_q32, 22162 - 3, 22162 + 3);
    (void)run_to_end();
    assert_true(pfe_predict_result(&g_pred)->valid);
    assert_int_equal(g_pred.bound.formation_air_q32, 0); /* the fast run was the last */
    road_ppm_free(&road);
}

static void test_refusals_and_restart(void **state)
{
    (void)state;
    pfe_platoon_t pl;
    pfe_platoon_config_t cfg;
    make_platoon(&pl, &cfg, 5U);
    pfe_preview_init(&g_pv);
    pfe_predict_init(&g_pred);
    /* No preview yet. */
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_PREDICT_ENOPREVIEW);
    static int32_t grade[300];
    for (uint32_t k = 0U; k < 300U; k++) {
        grade[k] = 10000;
    }
    send_preview(grade, 300U, 10U, 1U);
    /* Past its 3000 m. */
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 3000000U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_PREDICT_EPASSED);
    assert_false(pfe_predict_result(&g_pred)->valid);
    /* Start, then a new preview arrives mid-way: the old one is abandoned. */
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_OK);
    (void)pfe_predict_run(&g_pred, &g_pv, 5U);
    grade[0] = 20000;
    send_preview(grade, 150U, 10U, 2U);
    assert_int_equal(pfe_predict_run(&g_pred, &g_pv, BUDGET), PFE_PREDICT_IDLE);
    assert_int_equal(g_pred.last_error, PFE_PREDICT_ENOPREVIEW);
    assert_false(pfe_predict_result(&g_pred)->valid);
    /* Restarted on the new preview, it completes: 1500 m. */
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_OK);
    (void)run_to_end();
    assert_true(pfe_predict_result(&g_pred)->valid);
    assert_int_equal(pfe_predict_result(&g_pred)->generation, 1U);
    assert_int_equal(pfe_predict_result(&g_pred)->distance_m, 1500U);
    /* A wall the platoon cannot climb: stalls, no result. */
    for (uint32_t k = 0U; k < 300U; k++) {
        grade[k] = 300000;
    }
    send_preview(grade, 300U, 10U, 3U);
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, g_serial, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_OK);
    (void)run_to_end();
    assert_int_equal(g_pred.last_error, PFE_PREDICT_ESTALL);
    assert_false(pfe_predict_result(&g_pred)->valid);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: test_predict ROADS_DIR\n");
        return 2;
    }
    g_roads = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_flat_one_truck_literals),
        cmocka_unit_test(test_flat_n5_within_one_percent),
        cmocka_unit_test(test_uphill_n5_within_one_percent),
        cmocka_unit_test(test_hilly_n5_within_one_percent),
        cmocka_unit_test(test_hilly_from_halfway),
        cmocka_unit_test(test_prepared_preview_is_reused),
        cmocka_unit_test(test_bound_platoons_formation_drag),
        cmocka_unit_test(test_refusals_and_restart),
        cmocka_unit_test(test_windows_match_a_plain_scan),
        cmocka_unit_test(test_restart_mid_preparation),
    };
    return cmocka_run_group_tests_name("predict", tests, NULL, NULL);
}
