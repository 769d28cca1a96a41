/* Unit tests: speed filter (pfe_accel) and the 10 ms estimator (pfe_estimator).
 * Expected values are hand-computed from REFERENCE.md section 2 defaults. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "pfe_accel.h"
#include "pfe_calib.h"
#include "pfe_estimator.h"
#include "pfe_fixed.h"
#include "pfe_platoon.h"

static pfe_platoon_t g_platoon;
static pfe_estimator_t g_est;

static pfe_estimator_t *estimator_of(uint32_t n, const pfe_drag_table_t *drag)
{
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, n, 10000U, &pfe_default_vehicle, &pfe_default_env, drag);
    assert_int_equal(pfe_platoon_init(&g_platoon, &cfg), PFE_OK);
    memset(&g_est, 0xA5, sizeof g_est);
    assert_int_equal(pfe_estimator_init(&g_est, &g_platoon), PFE_OK);
    return &g_est;
}

/* Runs ticks of 10 ms at constant speed and grade, speed fresh every 10th tick. */
static const pfe_est_output_t *run(pfe_estimator_t *est, uint32_t ticks, int32_t speed_mm_s,
                                   int32_t grade_ppm, uint32_t *valid_ticks)
{
    const pfe_est_output_t *out = NULL;
    static uint32_t tick;
    for (uint32_t k = 0U; k < ticks; k++) {
        const pfe_est_input_t in = {speed_mm_s, true, (tick % 10U) == 0U, grade_ppm, true};
        out = pfe_estimator_step(est, &in);
        tick++;
        if ((valid_ticks != NULL) && ((out->flags & PFE_EST_VALID) != 0U)) {
            (*valid_ticks)++;
        }
    }
    return out;
}

static void test_filter_tracks_a_ramp_without_lag_error(void **state)
{
    (void)state;
    pfe_accel_filter_t f;
    pfe_accel_reset(&f);
    /* 0.5 m/s^2: +50 mm/s every 100 ms */
    for (int32_t k = 0; k < 60; k++) {
        pfe_accel_update(&f, 20000 + (50 * k), 1U);
    }
    assert_in_range(f.accel_um_s2, 500000 - 50, 500000 + 50);
    assert_in_range(f.speed_um_s, 22950000 - 500, 22950000 + 500);
    assert_int_equal(f.samples, 60);
}

static void test_filter_on_quantised_j1939_speed(void **state)
{
    (void)state;
    pfe_accel_filter_t f;
    pfe_accel_reset(&f);
    /* 0.3 m/s^2 from 15 m/s, sent as SPN 84 in 1/256 km/h and decoded back
     * to mm/s: the quantisation step is 1.085 mm/s. */
    int32_t worst = 0;
    for (int32_t k = 0; k < 200; k++) {
        const int64_t true_um_s = 15000000 + (30000 * (int64_t)k);
        const int64_t raw = (true_um_s * 256 * 36) / 10000000; /* km/h * 256 */
        const int32_t decoded_mm_s = (int32_t)((raw * 10000 + (256 * 36 / 2)) / (256 * 36));
        pfe_accel_update(&f, decoded_mm_s, 1U);
        if (k >= 40) {
            const int32_t err = f.accel_um_s2 - 300000;
            worst = (err > worst) ? err : ((-err > worst) ? -err : worst);
        }
    }
    /* 1 % of 0.3 m/s^2 */
    assert_in_range(worst, 0, 3000);
}

static void test_steady_flat_road_fuel_rate_and_total(void **state)
{
    (void)state;
    pfe_estimator_t *est = estimator_of(1U, &pfe_default_drag);
    uint32_t valid = 0U;
    const pfe_est_output_t *out = run(est, 1000U, 25000, 0, &valid);
    assert_int_not_equal(out->flags & PFE_EST_VALID, 0U);
    assert_int_equal(out->flags, PFE_EST_VALID);
    assert_int_equal(out->speed_mm_s, 25000);
    assert_int_equal(out->accel_um_s2, 0);
    assert_int_equal(out->wheel_force_n, 5166);
    /* 9.298184 mL/s, see test_vehicle_platoon.c */
    assert_in_range(out->fuel_rate_nl_s, 9298184 - 93, 9298184 + 93);
    assert_int_equal(out->pos_fuel_rate_nl_s[0], out->fuel_rate_nl_s);
    /* Warm-up: 5 samples at ticks 0, 10, .., 40: valid from tick 40 on. */
    assert_int_equal(valid, 960);
    /* 960 ticks of 10 ms at rate r nL/s: r * 9.6 nL = r * 0.0096 uL */
    const uint64_t expect_ul = ((uint64_t)out->fuel_rate_nl_s * 96U) / 10000U;
    assert_int_equal(pfe_estimator_fuel_used_ul(est, PFE_EST_PLATOON), expect_ul);
    assert_int_equal(pfe_estimator_fuel_used_ul(est, 0), expect_ul);
    assert_int_equal(pfe_estimator_fuel_used_ul(est, 1), 0U);
}

static void test_coasting_downhill_burns_nothing(void **state)
{
    (void)state;
    pfe_estimator_t *est = estimator_of(5U, &pfe_default_drag);
    const pfe_est_output_t *out = run(est, 500U, 25000, -60000, NULL);
    assert_int_not_equal(out->flags & PFE_EST_VALID, 0U);
    assert_int_equal(out->fuel_rate_nl_s, 0);
    for (uint32_t i = 0U; i < 5U; i++) {
        assert_int_equal(out->pos_fuel_rate_nl_s[i], 0);
        assert_int_equal(pfe_estimator_fuel_used_ul(est, (int32_t)i), 0U);
    }
    assert_int_equal(pfe_estimator_fuel_used_ul(est, PFE_EST_PLATOON), 0U);
}

static void test_identical_trucks_without_slipstream(void **state)
{
    (void)state;
    pfe_estimator_t *est = estimator_of(1U, &pfe_no_drag_reduction);
    const uint32_t one = run(est, 200U, 22000, 15000, NULL)->fuel_rate_nl_s;
    est = estimator_of(5U, &pfe_no_drag_reduction);
    const pfe_est_output_t *out = run(est, 200U, 22000, 15000, NULL);
    uint64_t sum = 0U;
    for (uint32_t i = 0U; i < 5U; i++) {
        sum += out->pos_fuel_rate_nl_s[i];
    }
    /* Each position is one truck, exactly; the platoon object is the small-angle
     * model, which differs from cos/sin at 1.5 % grade by under 0.02 %. */
    assert_int_equal(sum, 5U * (uint64_t)out->pos_fuel_rate_nl_s[0]);
    assert_in_range(out->fuel_rate_nl_s, 5U * one - 5U, 5U * one + 5U);
    assert_in_range(sum, (5U * (uint64_t)one * 9998U) / 10000U, (5U * (uint64_t)one * 10002U) / 10000U);
}

static void test_missing_and_stale_inputs(void **state)
{
    (void)state;
    pfe_estimator_t *est = estimator_of(2U, &pfe_default_drag);
    (void)run(est, 100U, 25000, 0, NULL);
    const uint64_t before = pfe_estimator_fuel_used_ul(est, PFE_EST_PLATOON);
    ASSERT_GT(before, 0U);

    /* Speed not valid: not available, nothing accumulates. */
    pfe_est_input_t in = {25000, false, true, 0, true};
    const pfe_est_output_t *out = pfe_estimator_step(est, &in);
    assert_int_equal(out->flags, PFE_EST_SPEED_MISSING);
    assert_int_equal(out->fuel_rate_nl_s, 0);
    assert_int_equal(out->pos_fuel_rate_nl_s[1], 0);
    assert_int_equal(pfe_estimator_fuel_used_ul(est, PFE_EST_PLATOON), before);

    /* Grade not valid. */
    in = (pfe_est_input_t){25000, true, true, 0, false};
    out = pfe_estimator_step(est, &in);
    assert_int_not_equal(out->flags & PFE_EST_GRADE_MISSING, 0U);
    assert_int_equal(out->flags & PFE_EST_VALID, 0U);

    /* No input at all. */
    out = pfe_estimator_step(est, NULL);
    assert_int_equal(out->flags, PFE_EST_SPEED_MISSING | PFE_EST_GRADE_MISSING);

    /* Back: the filter restarted, so warm-up first. */
    in = (pfe_est_input_t){25000, true, true, 0, true};
    out = pfe_estimator_step(est, &in);
    assert_int_equal(out->flags, PFE_EST_WARMING_UP);
    (void)run(est, 60U, 25000, 0, NULL);

    /* Valid but no new sample for more than 3 periods: stale. */
    in.speed_fresh = false;
    for (uint32_t k = 0U; k < 31U; k++) {
        out = pfe_estimator_step(est, &in);
    }
    assert_int_not_equal(out->flags & PFE_EST_SPEED_MISSING, 0U);
    assert_int_equal(out->flags & PFE_EST_VALID, 0U);
}

static void test_out_of_range_inputs_clamp_and_say_so(void **state)
{
    (void)state;
    pfe_estimator_t *est = estimator_of(1U, &pfe_default_drag);
    const pfe_est_output_t *out = run(est, 100U, 25000, 600000, NULL);
    assert_int_equal(out->grade_ppm, 500000);
    assert_int_not_equal(out->flags & PFE_EST_GRADE_CLAMPED, 0U);
    est = estimator_of(1U, &pfe_default_drag);
    out = run(est, 100U, 80000, 0, NULL);
    assert_int_equal(out->speed_mm_s, PFE_SPEED_MAX_MM_S);
    assert_int_not_equal(out->flags & PFE_EST_SPEED_CLAMPED, 0U);
}

static void test_fuel_used_holds_a_trucks_lifetime(void **state)
{
    (void)state;
    pfe_estimator_t *est = estimator_of(32U, &pfe_default_drag);
    /* 2,000,000 L = 2e12 uL in every counter, then keep driving. */
    assert_int_equal(pfe_estimator_set_fuel_used_ul(est, PFE_EST_PLATOON, 2000000000000ULL), PFE_OK);
    for (int32_t i = 0; i < 32; i++) {
        assert_int_equal(pfe_estimator_set_fuel_used_ul(est, i, 2000000000000ULL), PFE_OK);
    }
    assert_int_equal(pfe_estimator_set_fuel_used_ul(est, 32, 0U), PFE_EINVAL);
    const pfe_est_output_t *out = run(est, 200U, 25000, 20000, NULL);
    assert_int_equal(out->flags & PFE_EST_SATURATED, 0U);
    ASSERT_GT(pfe_estimator_fuel_used_ul(est, PFE_EST_PLATOON), 2000000000000ULL);
    ASSERT_GT(pfe_estimator_fuel_used_ul(est, 31), 2000000000000ULL);
    /* At the very top it saturates and says so, never wraps. */
    assert_int_equal(pfe_estimator_set_fuel_used_ul(est, PFE_EST_PLATOON, UINT64_MAX), PFE_OK);
    out = run(est, 20U, 25000, 20000, NULL);
    assert_int_not_equal(out->flags & PFE_EST_SATURATED, 0U);
    assert_int_equal(pfe_estimator_fuel_used_ul(est, PFE_EST_PLATOON), UINT64_MAX / 100000U);
}

/* Fuel used is read out in uL through a division by 100000 that the
 * Cortex-M4 does as two 32-bit long divisions (pfe_udiv_u64()). */
static void test_udiv_u64_exact(void **state)
{
    (void)state;
    uint64_t r = 1U;
    /* 2^64 - 1 = 18446744073709551615 */
    assert_int_equal(pfe_udiv_u64(UINT64_MAX, 1000U, &r), 18446744073709551ULL);
    assert_int_equal(r, 615U);
    /* 2^64 - 1 = (2^16 - 1)(2^48 + 2^32 + 2^16 + 1) */
    assert_int_equal(pfe_udiv_u64(UINT64_MAX, 0xFFFFU, &r), 281479271743489ULL);
    assert_int_equal(r, 0U);
    /* above the 32-bit path: 2^16 */
    assert_int_equal(pfe_udiv_u64(UINT64_MAX, 0x10000U, &r), 281474976710655ULL);
    assert_int_equal(r, 65535U);
    assert_int_equal(pfe_udiv_u64(12345678901234567890ULL, 7U, &r), 1763668414462081127ULL);
    assert_int_equal(r, 1U);
    assert_int_equal(pfe_udiv_u64(12345678901234567890ULL, 65521U, &r), 188423236843677ULL);
    assert_int_equal(r, 7173U);
    assert_int_equal(pfe_udiv_u64(12345678901234567890ULL, 100000U, &r), 123456789012345ULL);
    assert_int_equal(r, 67890U);
    assert_int_equal(pfe_udiv_u64(12345678901234567890ULL, 1U, NULL), 12345678901234567890ULL);
    assert_int_equal(pfe_udiv_u64(99U, 100U, &r), 0U);
    assert_int_equal(r, 99U);
    r = 1U;
    assert_int_equal(pfe_udiv_u64(5U, 0U, &r), 0U); /* by contract */
    assert_int_equal(r, 0U);
    /* rounded: halves up */
    assert_int_equal(pfe_udiv_round_u64(2499U, 1000U), 2U);
    assert_int_equal(pfe_udiv_round_u64(2500U, 1000U), 3U);
    assert_int_equal(pfe_udiv_round_u64(UINT64_MAX, 2U), 9223372036854775808ULL);
    assert_int_equal(pfe_udiv_round_u64(UINT64_MAX, 0U), 0U);
    /* against the compiler's 64-bit division, divisors both sides of 2^16 */
    uint64_t x = 0x9E3779B97F4A7C15ULL;
    for (uint32_t k = 0U; k < 20000U; k++) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        const uint64_t num = x >> (k % 40U);
        const uint64_t den = 1U + ((x >> 40) % 0x1FFFFU);
        assert_int_equal(pfe_udiv_u64(num, den, &r), num / den);
        assert_int_equal(r, num % den);
    }
    /* fuel used reads back what was set, up to the largest value it holds */
    pfe_estimator_t *est = estimator_of(2U, &pfe_default_drag);
    static const uint64_t ul[] = {0U, 1U, 99999U, 100000U, 123456789012345ULL, 184467440737095ULL};
    for (uint32_t k = 0U; k < sizeof ul / sizeof ul[0]; k++) {
        assert_int_equal(pfe_estimator_set_fuel_used_ul(est, 1, ul[k]), PFE_OK);
        assert_int_equal(pfe_estimator_fuel_used_ul(est, 1), ul[k]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_filter_tracks_a_ramp_without_lag_error),
        cmocka_unit_test(test_filter_on_quantised_j1939_speed),
        cmocka_unit_test(test_steady_flat_road_fuel_rate_and_total),
        cmocka_unit_test(test_coasting_downhill_burns_nothing),
        cmocka_unit_test(test_identical_trucks_without_slipstream),
        cmocka_unit_test(test_missing_and_stale_inputs),
        cmocka_unit_test(test_out_of_range_inputs_clamp_and_say_so),
        cmocka_unit_test(test_fuel_used_holds_a_trucks_lifetime),
        cmocka_unit_test(test_udiv_u64_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
