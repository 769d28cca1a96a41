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

static void test_rounded_high_word(void **state)
{
    (void)state;
    /* pfe_mulhr_i32(): SMMULR on the Cortex-M4, the 64-bit product on the
     * host; both give a * b / 2^32 rounded, halves up. */
    assert_int_equal(pfe_mulhr_i32(1 << 16, 1 << 15), 1);        /* 0.5 -> 1 */
    assert_int_equal(pfe_mulhr_i32(-(1 << 16), 1 << 15), 0);     /* -0.5 -> 0 */
    assert_int_equal(pfe_mulhr_i32(0x40000000, 3), 1);           /* 0.75 -> 1 */
    assert_int_equal(pfe_mulhr_i32(-0x40000000, 3), -1);         /* -0.75 -> -1 */
    assert_int_equal(pfe_mulhr_i32(0x40000000, 1), 0);           /* 0.25 -> 0 */
    assert_int_equal(pfe_mulhr_i32(INT32_MIN, INT32_MIN), 1073741824);  /* 2^62 / 2^32 */
    assert_int_equal(pfe_mulhr_i32(INT32_MIN, INT32_MAX), -1073741823); /* -2^30 + 0.5 -> -2^30 + 1 */
    assert_int_equal(pfe_mulhr_i32(INT32_MAX, INT32_MAX), 1073741823);  /* 2^30 - 1 + 2^-32 */
    assert_int_equal(pfe_mulhr_i32(123456789, -987654321), -28389653); /* -28389652.98 */
    /* The same as the rounded shift of the product over a spread of both
     * signs and magnitudes (on the Cortex-M4: the instruction against C). */
    uint32_t x = 2463534242U;
    for (int k = 0; k < 5000; k++) {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        const int32_t a = (int32_t)x >> (k % 31);
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        const int32_t b = (int32_t)x >> ((k / 31) % 31);
        const int64_t expect = pfe_rshift_round((int64_t)a * b, 32U);
        if (pfe_mulhr_i32(a, b) != (int32_t)expect) {
            print_error("pfe_mulhr_i32(%ld, %ld) = %ld, expected %lld\n", (long)a, (long)b,
                        (long)pfe_mulhr_i32(a, b), (long long)expect);
            fail();
        }
    }
}

static void test_wide_products_and_mantissas(void **state)
{
    (void)state;
    /* a * b / 2^shift from the 128-bit product, rounded halves up. */
    assert_int_equal(pfe_mul_shift_round_u64(3U, 5U, 1U), 8U);  /* 7.5 -> 8 */
    assert_int_equal(pfe_mul_shift_round_u64(3U, 3U, 2U), 2U);  /* 2.25 -> 2 */
    assert_int_equal(pfe_mul_shift_round_u64((uint64_t)1 << 40, (uint64_t)1 << 40, 40U),
                     (uint64_t)1 << 40);
    /* (2^33 + 1) 2^33 / 2^3 = 2^63 + 2^30: the product beyond 64 bits */
    assert_int_equal(pfe_mul_shift_round_u64(((uint64_t)1 << 33) + 1U, (uint64_t)1 << 33, 3U),
                     9223372037928517632U);
    /* (2^64 - 1) / 2 = 2^63 - 0.5 -> 2^63: the rounding carries into the high part */
    assert_int_equal(pfe_mul_shift_round_u64(UINT64_MAX, 1U, 1U), 9223372036854775808U);
    /* the largest work of a road (2^59 mJ * 2^2) at 2^22 nL/mJ * 2^20 */
    assert_int_equal(pfe_mul_shift_round_u64((uint64_t)1 << 59, (uint64_t)1 << 22, 22U),
                     (uint64_t)1 << 59);
    assert_int_equal(pfe_mul_shift_round_u64(UINT64_MAX, UINT64_MAX, 1U), UINT64_MAX);
    assert_int_equal(pfe_mul_shift_round_u64((uint64_t)1 << 40, (uint64_t)1 << 40, 16U), UINT64_MAX);

    /* x = m * 2^shift, |m| < 2^31, the smallest shift from min_shift. */
    uint32_t shift = 99U;
    assert_int_equal(pfe_mantissa_i32(1000, 0U, &shift), 1000);
    assert_int_equal(shift, 0U);
    assert_int_equal(pfe_mantissa_i32(2147483647, 0U, &shift), 2147483647);
    assert_int_equal(shift, 0U);
    assert_int_equal(pfe_mantissa_i32((int64_t)1 << 32, 0U, &shift), 1073741824);
    assert_int_equal(shift, 2U);
    /* 2^32 - 1: at shift 1 it rounds to 2^31, which does not fit */
    assert_int_equal(pfe_mantissa_i32(((int64_t)1 << 32) - 1, 0U, &shift), 1073741824);
    assert_int_equal(shift, 2U);
    assert_int_equal(pfe_mantissa_i32(-((int64_t)1 << 35), 0U, &shift), -1073741824);
    assert_int_equal(shift, 5U);
    assert_int_equal(pfe_mantissa_i32(5, 2U, &shift), 1);   /* 1.25 -> 1 */
    assert_int_equal(pfe_mantissa_i32(6, 2U, &shift), 2);   /* 1.5 -> 2 */
    assert_int_equal(pfe_mantissa_i32(-6, 2U, &shift), -2);
    assert_int_equal(shift, 2U);
}

static void test_drag_reduction_table(void **state)
{
    (void)state;
    const pfe_drag_table_t *d = &pfe_default_drag;
    /* The default drag table (docs/model.md), at table points. */
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
        cmocka_unit_test(test_rounded_high_word),
        cmocka_unit_test(test_wide_products_and_mantissas),
        cmocka_unit_test(test_drag_reduction_table),
        cmocka_unit_test(test_calibration_checks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
