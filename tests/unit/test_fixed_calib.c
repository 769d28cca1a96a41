/* Unit tests: saturating arithmetic (pfe_fixed) and calibration (pfe_calib). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "pfe_calib.h"
#include "pfe_fixed.h"

static void test_saturation_limits(void **state)
{
    (void)state;
    assert_int_equal(pfe_sat_i32((int64_t)INT32_MAX + 1), INT32_MAX);
    assert_int_equal(pfe_sat_i32((int64_t)INT32_MIN - 1), INT32_MIN);
    assert_int_equal(pfe_sat_i32(-12345), -12345);
    assert_int_equal(pfe_sat_add_i64(INT64_MAX, 1), INT64_MAX);
    assert_int_equal(pfe_sat_add_i64(INT64_MIN, -1), INT64_MIN);
    assert_int_equal(pfe_sat_add_i64(-5, 3), -2);
    assert_int_equal(pfe_sat_add_u64(UINT64_MAX - 1U, 5U), UINT64_MAX);
    assert_int_equal(pfe_sat_add_u64(7U, 5U), 12U);
    assert_int_equal(pfe_clamp_i32(5, 10, 20), 10);
    assert_int_equal(pfe_clamp_i32(25, 10, 20), 20);
}

static void test_rounding_shift_is_to_nearest_for_both_signs(void **state)
{
    (void)state;
    /* Pins arithmetic right shift of negative values (pfe_fixed.h). */
    assert_int_equal(pfe_rshift_round(5, 1U), 3);    /* 2.5 -> 3 */
    assert_int_equal(pfe_rshift_round(-5, 1U), -2);  /* -2.5 -> -2 (halves up) */
    assert_int_equal(pfe_rshift_round(-7, 2U), -2);  /* -1.75 -> -2 */
    assert_int_equal(pfe_rshift_round(-6, 2U), -1);  /* -1.5 -> -1 */
    assert_int_equal(pfe_rshift_round(((int64_t)1 << 40) + ((int64_t)1 << 31), 32U), 257);
    assert_int_equal(pfe_mul_q(3, -3, 2U), -2);      /* -9/4 = -2.25 */
    assert_int_equal(pfe_udiv_round_u64(7U, 2U), 4U);
    assert_int_equal(pfe_udiv_round_u64(10U, 4U), 3U);
    assert_int_equal(pfe_udiv_round_u64(9U, 4U), 2U);
    assert_int_equal(pfe_udiv_round_u64(9U, 0U), 0U);
}

static void test_drag_reduction_table(void **state)
{
    (void)state;
    const pfe_drag_table_t *d = &pfe_default_drag;
    /* REFERENCE.md section 2, at table points. */
    assert_int_equal(pfe_drag_reduction_bp(d, 0U, 5U, 10000U), 800);
    assert_int_equal(pfe_drag_reduction_bp(d, 1U, 5U, 10000U), 3100);
    assert_int_equal(pfe_drag_reduction_bp(d, 2U, 5U, 10000U), 3500);
    /* Positions after the third use the third's curve. */
    assert_int_equal(pfe_drag_reduction_bp(d, 4U, 5U, 10000U), 3500);
    assert_int_equal(pfe_drag_reduction_bp(d, 31U, 32U, 10000U), 3500);
    /* Linear between points: 2nd at 12.5 m is (31 + 25) / 2 %. */
    assert_int_equal(pfe_drag_reduction_bp(d, 1U, 5U, 12500U), 2800);
    /* Lead at 3 m: 28 - (28 - 17) / 2 = 22.5 %. */
    assert_int_equal(pfe_drag_reduction_bp(d, 0U, 2U, 3000U), 2250);
    /* Held outside the table. */
    assert_int_equal(pfe_drag_reduction_bp(d, 2U, 5U, 0U), 5400);
    assert_int_equal(pfe_drag_reduction_bp(d, 2U, 5U, 500000U), 800);
    /* A lone truck has no slipstream. */
    assert_int_equal(pfe_drag_reduction_bp(d, 0U, 1U, 10000U), 0);
}

static void test_calibration_checks(void **state)
{
    (void)state;
    assert_int_equal(pfe_calib_check_vehicle(&pfe_default_vehicle), PFE_OK);
    assert_int_equal(pfe_calib_check_env(&pfe_default_env), PFE_OK);
    assert_int_equal(pfe_calib_check_drag(&pfe_default_drag), PFE_OK);
    assert_int_equal(pfe_calib_check_drag(&pfe_no_drag_reduction), PFE_OK);
    assert_int_equal(pfe_calib_check_cruise(&pfe_default_cruise), PFE_OK);
    assert_int_equal(pfe_calib_check_vehicle(NULL), PFE_EINVAL);

    pfe_vehicle_calib_t v = pfe_default_vehicle;
    v.mass_kg = 999U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v = pfe_default_vehicle;
    v.mass_kg = 100001U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v = pfe_default_vehicle;
    v.eta_ppm = 0U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v = pfe_default_vehicle;
    v.power_max_w = 0U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);

    pfe_drag_table_t d = pfe_default_drag;
    d.gap_mm[3] = d.gap_mm[2];
    assert_int_equal(pfe_calib_check_drag(&d), PFE_EINVAL);
    d = pfe_default_drag;
    d.reduction_bp[1][0] = 10001U;
    assert_int_equal(pfe_calib_check_drag(&d), PFE_EINVAL);

    pfe_env_calib_t e = pfe_default_env;
    e.fuel_energy_j_ml = 0U;
    assert_int_equal(pfe_calib_check_env(&e), PFE_EINVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_saturation_limits),
        cmocka_unit_test(test_rounding_shift_is_to_nearest_for_both_signs),
        cmocka_unit_test(test_drag_reduction_table),
        cmocka_unit_test(test_calibration_checks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
