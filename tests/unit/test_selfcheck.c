/*
 * Unit tests: the known-answer run (pfe_selfcheck) on small roads whose
 * results can be worked out by hand, its argument checks, and the SPN 84
 * round trip it feeds the estimator with.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "pfe_fixed.h"
#include "pfe_selfcheck.h"

/* 1 km of road in 10 m samples. */
#define SAMPLES 100U
#define SPACING_MM 10000U

static int32_t g_flat[SAMPLES];
static int32_t g_grade[SAMPLES];

static pfe_road_t road_of(const int32_t *grade_ppm)
{
    const pfe_road_t r = {grade_ppm, SAMPLES, SPACING_MM};
    return r;
}

static void fill(int32_t *grade_ppm, int32_t value)
{
    for (uint32_t k = 0U; k < SAMPLES; k++) {
        grade_ppm[k] = value;
    }
}

static void test_spn84_round_trip(void **state)
{
    (void)state;
    /* raw = (v * 1152 + 625) / 1250, back (raw * 1250 + 576) / 1152 */
    assert_int_equal(pfe_selfcheck_spn84_mm_s(25000), 25000); /* raw 23040 */
    assert_int_equal(pfe_selfcheck_spn84_mm_s(1000), 1000);   /* raw 922: 1000.4 */
    assert_int_equal(pfe_selfcheck_spn84_mm_s(6), 7);         /* raw 6: 6.51 -> 7 */
    assert_int_equal(pfe_selfcheck_spn84_mm_s(1), 1);         /* raw 1: 1.09 */
    assert_int_equal(pfe_selfcheck_spn84_mm_s(0), 0);
    /* Clamped to 0 .. PFE_SPEED_MAX_MM_S first (70000: raw 64512, exact). */
    assert_int_equal(pfe_selfcheck_spn84_mm_s(-5), 0);
    assert_int_equal(pfe_selfcheck_spn84_mm_s(90000), 70000);
}

static void test_refuses_bad_arguments(void **state)
{
    (void)state;
    fill(g_flat, 0);
    const pfe_road_t flat = road_of(g_flat);
    pfe_selfcheck_result_t r;
    assert_int_equal(pfe_selfcheck_run(NULL, 1U, 25000, &r), PFE_EINVAL);
    assert_int_equal(pfe_selfcheck_run(&flat, 1U, 25000, NULL), PFE_EINVAL);
    assert_int_equal(pfe_selfcheck_run(&flat, 0U, 25000, &r), PFE_EINVAL);
    assert_int_equal(pfe_selfcheck_run(&flat, PFE_MAX_VEHICLES + 1U, 25000, &r), PFE_EINVAL);
    /* Below the stall speed, 1000 mm/s: the simulation refuses to start. */
    assert_int_equal(pfe_selfcheck_run(&flat, 1U, 999, &r), PFE_EINVAL);
    /* A grade sample beyond +-50 %. */
    fill(g_grade, 0);
    g_grade[SAMPLES - 1U] = 500001;
    const pfe_road_t bad = road_of(g_grade);
    assert_int_equal(pfe_selfcheck_run(&bad, 1U, 25000, &r), PFE_EINVAL);
}

/*
 * One default truck (pfe_calib.c: 40 t, cw A 6 m^2, cr 0.007, eta 0.40,
 * 4 kW auxiliaries; air 1.290 kg/m^3, g 9.81, diesel 35.8 kJ/mL) over 1 km
 * flat at 25 m/s, started at that speed: it holds it exactly.
 *   air     0.5 * 1.290 * 6 * 25^2     = 2418.75 N
 *   rolling 0.007 * 40000 * 9.81       = 2746.8 N
 *   work    5165.55 N * 1000 m         = 5165550 J
 *   aux     4000 W * 40 s              = 160000 J
 *   fuel    5325550 J / (0.40 * 35800 J/mL) = 371.896 mL
 * Steps: 100 of 10 m, each dt = 0.4 s = 26214.4 / 2^16, rounded to 26214:
 * time 2621400; ticks k * 65536 <= 2621400 * 100: k = 0 .. 3999.
 */
static void test_flat_road_by_hand(void **state)
{
    (void)state;
    fill(g_flat, 0);
    const pfe_road_t flat = road_of(g_flat);
    pfe_selfcheck_result_t r;
    memset(&r, 0xA5, sizeof r);
    assert_int_equal(pfe_selfcheck_run(&flat, 1U, 25000, &r), PFE_OK);
    assert_int_equal(r.steps, 100);
    assert_int_equal(r.sim_time_q16, 2621400);
    assert_int_equal(r.ticks, 4000);
    assert_int_equal(r.sim_min_speed_mm_s, 25000);
    assert_int_equal(r.sim_max_speed_mm_s, 25000);
    /* The model to 0.01 %; the estimator, which sees the speed quantised
     * on the bus and 10 ms ticks, to 2 %. One truck: platoon = lead. */
    assert_in_range(r.sim_fuel_nl, 371896089U - 37190U, 371896089U + 37190U);
    assert_in_range(r.est_fuel_ul, 371896U - 7438U, 371896U + 7438U);
    assert_int_equal(r.est_pos0_fuel_ul, r.est_fuel_ul);
}

static void test_digest_is_deterministic_and_sees_the_platoon(void **state)
{
    (void)state;
    fill(g_flat, 0);
    const pfe_road_t flat = road_of(g_flat);
    pfe_selfcheck_result_t a;
    pfe_selfcheck_result_t b;
    pfe_selfcheck_result_t three;
    assert_int_equal(pfe_selfcheck_run(&flat, 1U, 25000, &a), PFE_OK);
    assert_int_equal(pfe_selfcheck_run(&flat, 3U, 25000, &three), PFE_OK);
    /* Static state is reset: the second run of the same drive agrees. */
    assert_int_equal(pfe_selfcheck_run(&flat, 1U, 25000, &b), PFE_OK);
    assert_int_equal(a.digest, b.digest);
    assert_int_not_equal(a.digest, three.digest);
    /* Three trucks: the lead, in clean air, burns more than a third of the
     * platoon's fuel (2 and 3 draft), and less than half. */
    ASSERT_GT(three.est_pos0_fuel_ul * 3U, three.est_fuel_ul);
    ASSERT_LT(three.est_pos0_fuel_ul * 2U, three.est_fuel_ul);
}

/*
 * 30 % up: the grade force, 40000 * 9.81 * 0.3 / sqrt(1.09) = 112.7 kN,
 * exceeds the truck's traction limit of 100 kN: it slows to a stall.
 */
static void test_too_steep_a_road_stalls(void **state)
{
    (void)state;
    fill(g_grade, 300000);
    const pfe_road_t steep = road_of(g_grade);
    pfe_selfcheck_result_t r;
    assert_int_equal(pfe_selfcheck_run(&steep, 1U, 25000, &r), PFE_ESTALL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_spn84_round_trip),
        cmocka_unit_test(test_refuses_bad_arguments),
        cmocka_unit_test(test_flat_road_by_hand),
        cmocka_unit_test(test_digest_is_deterministic_and_sees_the_platoon),
        cmocka_unit_test(test_too_steep_a_road_stalls),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
