/*
 * Host tests of the sensitivity analysis (sim_host/ref/sensitivity_run.h): what
 * the physics says must happen when one parameter changes, checked on the
 * thesis's roads with the platoon of the thesis (N = 5, 90 km/h, 0.4 s),
 * the default calibration of firmware/pfe_calib.c.
 *
 * The flat and uphill roads are built here (1000 samples, 12 m apart, 0 %
 * and 2 %, as sim_host/data/roads/ holds them); the hilly road is read from
 * ROADS_DIR/hilly.csv.
 *
 * Hand figures used below, for the nominal platoon:
 *   drag: 1/2 * 1.29 kg/m3 * 6.0 m2 = 3.87 N/(m/s)^2 per truck; phi at 10 m
 *         is 8, 31, 35, 35, 35 %, so the platoon has 3.87 * (0.92 + 0.69 +
 *         3 * 0.65) = 3.87 * 3.56 = 13.7772 N/(m/s)^2; at 25 m/s 8610.75 N.
 *   rolling: 0.007 * 5 * 40000 kg * 9.81 m/s2 = 13734 N.
 *   fuel energy: 0.40 * 35800 J/mL * 1000 mL/L = 14 320 000 J per L.
 *
 * Usage: test_sensitivity ROADS_DIR (or PFE_ROADS_DIR in the environment).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "lib/road_csv.h"
#include "ref/sensitivity_run.h"

static const char *g_roads_dir;

#define N_SAMPLES 1000U

static double g_flat_pct[N_SAMPLES];
static double g_uphill_pct[N_SAMPLES];
static road_profile_t g_flat = {N_SAMPLES, 12.0, g_flat_pct};
static road_profile_t g_uphill = {N_SAMPLES, 12.0, g_uphill_pct};

static int setup_roads(void **state)
{
    (void)state;
    for (size_t k = 0U; k < N_SAMPLES; k++) {
        g_flat_pct[k] = 0.0;
        g_uphill_pct[k] = 2.0;
    }
    return 0;
}

static sens_result_t run(const road_profile_t *road, sens_param_t p, int32_t amount)
{
    sens_setup_t s;
    sens_setup_default(&s);
    sens_result_t r;
    memset(&r, 0xA5, sizeof r);
    char err[256];
    if (sens_run(&s, road, p, amount, &r, err, sizeof err) != 0) {
        fail_msg("%s %ld: %s", sens_param_name(p), (long)amount, err);
    }
    assert_int_equal(r.stalled, 0);
    return r;
}

static void assert_rel_near(double x, double expected, double rel)
{
    if (!(fabs(x - expected) <= rel * fabs(expected))) {
        fail_msg("%.12g is not within %.1e of %.12g", x, rel, expected);
    }
}

static void assert_same_result(const sens_result_t *a, const sens_result_t *b)
{
    /* Exact equality: the same calibration must give the same run. */
    ASSERT_EQ(a->fuel_l, b->fuel_l);
    ASSERT_EQ(a->time_s, b->time_s);
    ASSERT_EQ(a->mean_kmh, b->mean_kmh);
    ASSERT_EQ(a->min_kmh, b->min_kmh);
    ASSERT_EQ(a->max_kmh, b->max_kmh);
    ASSERT_EQ(a->power_limited_pct, b->power_limited_pct);
    assert_int_equal(a->steps, b->steps);
}

/* The steps of thesis chapter 6 (tables 6.1 to 6.3, section 6.4), and the
 * ones chosen for mass (section 6.5 is lost from the text). */
static void test_steps_are_the_thesis_steps(void **state)
{
    (void)state;
    static const int32_t pct70[] = {-70, -50, -30, 0, 30, 50, 70};
    static const int32_t pct30[] = {-30, -20, -10, 0, 10, 20, 30};
    static const int32_t gap_ms[] = {100, 130, 200, 400, 800, 1200, 1600};
    const int32_t *steps = NULL;
    assert_int_equal(sens_steps(SENS_GRADE, &steps), 7);
    assert_memory_equal(steps, pct70, sizeof pct70);
    assert_int_equal(sens_steps(SENS_DRAG_AREA, &steps), 7);
    assert_memory_equal(steps, pct70, sizeof pct70);
    assert_int_equal(sens_steps(SENS_POWER, &steps), 7);
    assert_memory_equal(steps, pct30, sizeof pct30);
    assert_int_equal(sens_steps(SENS_TIME_GAP, &steps), 7);
    assert_memory_equal(steps, gap_ms, sizeof gap_ms);
    assert_int_equal(sens_steps(SENS_MASS, &steps), 7);
    assert_memory_equal(steps, pct30, sizeof pct30);
    assert_int_equal(sens_steps(SENS_NOMINAL, &steps), 0);
}

/* Flat road, nominal case, by hand: the platoon starts in equilibrium at
 * 25 m/s and, with no grade, stays there exactly: 12 000 m in 480 s.
 * Work (8610.75 + 13734) N * 12 000 m = 268 137 000 J, auxiliaries
 * 5 * 4000 W * 480 s = 9 600 000 J: 277 737 000 J / 14 320 000 J/L =
 * 19.395 041 9 L. */
static void test_flat_nominal_by_hand(void **state)
{
    (void)state;
    const sens_result_t r = run(&g_flat, SENS_NOMINAL, 0);
    assert_rel_near(r.fuel_l, 19.3950419, 1e-8);
    assert_rel_near(r.time_s, 480.0, 1e-12);
    ASSERT_EQ(r.min_kmh, 90.0);
    ASSERT_EQ(r.max_kmh, 90.0);
    ASSERT_EQ(r.power_limited_pct, 0.0);
    assert_int_equal(r.steps, 1200);
    assert_rel_near(r.gap_m, 10.0, 0.0);
}

/* A 0 % change (or the nominal 0.4 s gap) gives the same calibration, so
 * bit for bit the nominal run, on every road. */
static void check_zero_change(const road_profile_t *road)
{
    const sens_result_t nom = run(road, SENS_NOMINAL, 0);
    for (int p = SENS_GRADE; p < SENS_N_PARAMS; p++) {
        const int32_t zero = (p == SENS_TIME_GAP) ? 400 : 0;
        const sens_result_t r = run(road, (sens_param_t)p, zero);
        assert_same_result(&r, &nom);
    }
}

static void test_zero_change_is_nominal(void **state)
{
    (void)state;
    check_zero_change(&g_flat);
    check_zero_change(&g_uphill);
    char path[512];
    char err[512];
    snprintf(path, sizeof path, "%s/hilly.csv", g_roads_dir);
    road_profile_t hilly;
    if (road_profile_load(path, &hilly, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    check_zero_change(&hilly);
    /* ... and a change that is not zero does show (the check can fail). */
    const sens_result_t nom = run(&hilly, SENS_NOMINAL, 0);
    const sens_result_t heavier = run(&hilly, SENS_MASS, 1);
    ASSERT_GT(heavier.fuel_l, nom.fuel_l);
    road_profile_free(&hilly);
}

/* Flat road: the platoon needs (8610.75 + 13734) N * 25 m/s = 558.6 kW,
 * 111.7 kW a truck. Every Pmax of the thesis's steps (175 to 325 kW a
 * truck) stays above it: the force never meets its limit and the run is
 * the nominal one, bit for bit (thesis table 6.3, flat road: +-0). */
static void test_flat_power_above_need_leaves_fuel_unchanged(void **state)
{
    (void)state;
    const sens_result_t nom = run(&g_flat, SENS_NOMINAL, 0);
    const int32_t *steps = NULL;
    const size_t n = sens_steps(SENS_POWER, &steps);
    for (size_t k = 0U; k < n; k++) {
        const sens_result_t r = run(&g_flat, SENS_POWER, steps[k]);
        ASSERT_EQ(r.power_limited_pct, 0.0);
        assert_same_result(&r, &nom);
    }
    /* Below the need (-60 %: 100 kW a truck) the limit binds: the platoon
     * slows and the fuel changes. */
    const sens_result_t weak = run(&g_flat, SENS_POWER, -60);
    ASSERT_GT(weak.power_limited_pct, 50.0);
    ASSERT_GT(weak.time_s, nom.time_s + 1.0);
    ASSERT_NE(weak.fuel_l, nom.fuel_l);
}

/* Flat road: 0 % grade times any scale is 0 %: nothing changes. */
static void test_flat_grade_scale_changes_nothing(void **state)
{
    (void)state;
    const sens_result_t nom = run(&g_flat, SENS_NOMINAL, 0);
    const sens_result_t up = run(&g_flat, SENS_GRADE, 70);
    const sens_result_t down = run(&g_flat, SENS_GRADE, -70);
    assert_same_result(&up, &nom);
    assert_same_result(&down, &nom);
}

/* Flat road at constant speed, fuel is linear in cw*Af: a change of x %
 * adds x/100 * 8610.75 N * 12 000 m / 14 320 000 J/L of fuel, 2.164 713 7 L
 * for 30 % and 5.050 999 L for 70 %, up or down alike (thesis table 6.2,
 * flat road: symmetric). */
static void test_flat_drag_area_linear(void **state)
{
    (void)state;
    const sens_result_t nom = run(&g_flat, SENS_NOMINAL, 0);
    assert_rel_near(run(&g_flat, SENS_DRAG_AREA, 30).fuel_l - nom.fuel_l, 2.1647137, 1e-7);
    assert_rel_near(nom.fuel_l - run(&g_flat, SENS_DRAG_AREA, -30).fuel_l, 2.1647137, 1e-7);
    assert_rel_near(run(&g_flat, SENS_DRAG_AREA, 70).fuel_l - nom.fuel_l, 5.0509986, 1e-7);
    assert_rel_near(nom.fuel_l - run(&g_flat, SENS_DRAG_AREA, -70).fuel_l, 5.0509986, 1e-7);
}

/* Flat road: phi_i(d) falls as the gap grows, so fuel rises with every
 * longer time gap, at an unchanged 90 km/h (thesis 6.4.1). */
static void test_flat_fuel_rises_with_gap(void **state)
{
    (void)state;
    const int32_t *steps = NULL;
    const size_t n = sens_steps(SENS_TIME_GAP, &steps);
    double last = 0.0;
    for (size_t k = 0U; k < n; k++) {
        const sens_result_t r = run(&g_flat, SENS_TIME_GAP, steps[k]);
        ASSERT_GT(r.fuel_l, last);
        ASSERT_EQ(r.min_kmh, 90.0);
        last = r.fuel_l;
    }
}

/* Uphill (2 %), nominal: the platoon runs at its power limit, lowered by
 * the formation drag 1.04 * 3.87 v^2 (the lead truck's 8 % reduction
 * against the platoon's mean), and settles where 5 * 250 kW / v =
 * (13.7772 + 4.0248) v^2 + 13734 + 5 * 40000 * 9.81 * 0.02, v = 20.6411
 * m/s = 74.31 km/h (solved by bisection by hand). */
static void test_uphill_nominal_power_limited(void **state)
{
    (void)state;
    const sens_result_t r = run(&g_uphill, SENS_NOMINAL, 0);
    ASSERT_GT(r.power_limited_pct, 99.0);
    ASSERT_NEAR_LT(r.min_kmh, 74.31, 0.02);
    ASSERT_LT(r.max_kmh, 90.0);
}

/* Uphill: fuel rises at every step of cw*Af, of mass and of grade: more
 * resistance at the power limit means a slower platoon burning at the same
 * rate for longer (thesis 6.1.1, 6.2.2). A stronger engine holds a higher
 * speed at a higher rate and burns more in all (thesis 6.3.2, table 6.3). */
static void check_uphill_rising(sens_param_t p)
{
    const int32_t *steps = NULL;
    const size_t n = sens_steps(p, &steps);
    sens_result_t last = run(&g_uphill, p, steps[0]);
    for (size_t k = 1U; k < n; k++) {
        const sens_result_t r = run(&g_uphill, p, steps[k]);
        if (!(r.fuel_l > last.fuel_l)) {
            fail_msg("%s %+ld %%: fuel %.6f L not above %.6f L", sens_param_name(p),
                     (long)steps[k], r.fuel_l, last.fuel_l);
        }
        if (p == SENS_POWER) {
            ASSERT_LE(r.time_s, last.time_s);
        } else {
            ASSERT_GE(r.time_s, last.time_s);
        }
        last = r;
    }
}

static void test_uphill_fuel_rises_with_drag_area(void **state)
{
    (void)state;
    check_uphill_rising(SENS_DRAG_AREA);
}

static void test_uphill_fuel_rises_with_mass(void **state)
{
    (void)state;
    check_uphill_rising(SENS_MASS);
}

static void test_uphill_fuel_rises_with_grade(void **state)
{
    (void)state;
    check_uphill_rising(SENS_GRADE);
}

static void test_uphill_fuel_rises_with_power(void **state)
{
    (void)state;
    check_uphill_rising(SENS_POWER);
}

static void test_bad_amounts_are_refused(void **state)
{
    (void)state;
    sens_setup_t s;
    sens_setup_default(&s);
    sens_result_t r;
    char err[256];
    err[0] = '\0';
    assert_int_equal(sens_run(&s, &g_flat, SENS_MASS, -100, &r, err, sizeof err), -1);
    assert_non_null(strstr(err, "mass"));
    assert_int_equal(sens_run(&s, &g_flat, SENS_NOMINAL, 5, &r, err, sizeof err), -1);
    assert_int_equal(sens_run(&s, &g_flat, SENS_TIME_GAP, -1, &r, err, sizeof err), -1);
    assert_int_equal(sens_run(&s, &g_flat, SENS_N_PARAMS, 0, &r, err, sizeof err), -1);
    /* 40 t * 3.5 = 140 t: past PFE_MASS_MAX_KG (100 t), the calibration check. */
    err[0] = '\0';
    assert_int_equal(sens_run(&s, &g_flat, SENS_MASS, 250, &r, err, sizeof err), -1);
    assert_non_null(strstr(err, "out of range"));
    const road_profile_t empty = {0U, 0.0, NULL};
    assert_int_equal(sens_run(&s, &empty, SENS_NOMINAL, 0, &r, err, sizeof err), -1);
    s.n_vehicles = 0U;
    assert_int_equal(sens_run(&s, &g_flat, SENS_NOMINAL, 0, &r, err, sizeof err), -1);
}

/* A road too steep for the platoon (30 % scaled by +50 %, 45 %: 5 trucks
 * need 0.45 * 200 t * 9.81 m/s2 = 883 kN against a traction limit of
 * 5 * 100 kN, so the speed falls below 1 m/s) is reported as a stall with
 * its position, not as a result. */
static void test_stall_is_reported(void **state)
{
    (void)state;
    static double steep_pct[N_SAMPLES];
    for (size_t k = 0U; k < N_SAMPLES; k++) {
        steep_pct[k] = 30.0;
    }
    const road_profile_t steep = {N_SAMPLES, 12.0, steep_pct};
    sens_setup_t s;
    sens_setup_default(&s);
    sens_result_t r;
    char err[256];
    assert_int_equal(sens_run(&s, &steep, SENS_GRADE, 50, &r, err, sizeof err), 0);
    assert_int_equal(r.stalled, 1);
    ASSERT_GT(r.stall_position_m, 0.0);
    ASSERT_LT(r.stall_position_m, 12000.0);
}

int main(int argc, char **argv)
{
    g_roads_dir = (argc > 1) ? argv[1] : getenv("PFE_ROADS_DIR");
    if (g_roads_dir == NULL) {
        fprintf(stderr, "usage: %s ROADS_DIR (or set PFE_ROADS_DIR)\n", argv[0]);
        return 2;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_steps_are_the_thesis_steps),
        cmocka_unit_test(test_flat_nominal_by_hand),
        cmocka_unit_test(test_zero_change_is_nominal),
        cmocka_unit_test(test_flat_power_above_need_leaves_fuel_unchanged),
        cmocka_unit_test(test_flat_grade_scale_changes_nothing),
        cmocka_unit_test(test_flat_drag_area_linear),
        cmocka_unit_test(test_flat_fuel_rises_with_gap),
        cmocka_unit_test(test_uphill_nominal_power_limited),
        cmocka_unit_test(test_uphill_fuel_rises_with_drag_area),
        cmocka_unit_test(test_uphill_fuel_rises_with_mass),
        cmocka_unit_test(test_uphill_fuel_rises_with_grade),
        cmocka_unit_test(test_uphill_fuel_rises_with_power),
        cmocka_unit_test(test_bad_amounts_are_refused),
        cmocka_unit_test(test_stall_is_reported),
    };
    return cmocka_run_group_tests(tests, setup_roads, NULL);
}
