/* Unit tests: chapter 3 vehicle (pfe_vehicle) and chapter 4 aggregates (pfe_platoon).
 * Expected values are hand-computed from the default calibration (docs/model.md). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "pfe_calib.h"
#include "pfe_fixed.h"
#include "pfe_platoon.h"
#include "pfe_vehicle.h"

static pfe_vehicle_t truck(uint32_t reduction_bp)
{
    pfe_vehicle_t v;
    memset(&v, 0xA5, sizeof v);
    assert_int_equal(pfe_vehicle_init(&v, &pfe_default_vehicle, &pfe_default_env, reduction_bp), PFE_OK);
    return v;
}

static void test_one_truck_flat_90_kmh_needs_129_kw(void **state)
{
    (void)state;
    const pfe_vehicle_t v = truck(0U);
    pfe_grade_accel_t g;
    pfe_grade_accel(0, pfe_default_env.gravity_um_s2, &g);
    /* Fa = 0.5 * 1.29 * 0.6 * 10 * 25^2 = 2418.75 N; Fr = 0.007 * 40000 * 9.81 = 2746.8 N */
    assert_int_equal(pfe_vehicle_air_n(&v, 25000), 2419);
    const int32_t f = pfe_vehicle_resistance_n(&v, 25000, &g);
    assert_int_equal(f, 5166);
    /* P = 5165.55 N * 25 m/s = 129.14 kW; the bound is 129 kW +- 2 %. */
    const int64_t p_w = ((int64_t)f * 25000) / 1000;
    assert_in_range(p_w, 126420, 131580);
    assert_in_range(p_w, 129138 - 15, 129138 + 15);
}

static void test_grade_split_is_exact_trigonometry(void **state)
{
    (void)state;
    pfe_grade_accel_t g;
    /* 9.81 sin(atan G), 9.81 cos(atan G) in um/s^2, from a calculator. */
    pfe_grade_accel(20000, 9810000U, &g);
    assert_in_range(g.along_um_s2, 196161 - 1, 196161 + 1);
    assert_in_range(g.normal_um_s2, 9808039 - 1, 9808039 + 1);
    pfe_grade_accel(300000, 9810000U, &g);
    assert_in_range(g.along_um_s2, 2818883 - 1, 2818883 + 1);
    assert_in_range(g.normal_um_s2, 9396276 - 1, 9396276 + 1);
    pfe_grade_accel(-60000, 9810000U, &g);
    assert_in_range(g.along_um_s2, -587543 - 1, -587543 + 1);
    assert_in_range(g.normal_um_s2, 9792390 - 1, 9792390 + 1);
    /* Clamped at 50 %. */
    pfe_grade_accel(900000, 9810000U, &g);
    assert_in_range(g.along_um_s2, 4387165 - 1, 4387165 + 1);
    assert_in_range(g.normal_um_s2, 8774331 - 1, 8774331 + 1);
}

/* sqrt(s) for s in [1, 1.25] in double, by Heron's iteration from 1 (the
 * Cortex-M4 tests have no libm): eight steps reach double precision. */
static double sqrt_near_one(double s)
{
    double y = 1.0;
    for (int k = 0; k < 8; k++) {
        y = 0.5 * (y + (s / y));
    }
    return y;
}

/* The table's chord and one Newton step against double trigonometry over
 * the whole grade range (every 97 ppm and both ends): within the rounding
 * of the result, 0.5 um/s^2, plus the Q30 error (2e-9 of g, 0.02 um/s^2). */
static void test_grade_split_over_the_range(void **state)
{
    (void)state;
    const double g = 9810000.0;
    double worst = 0.0;
    for (int32_t grade = -PFE_GRADE_MAX_PPM; grade <= PFE_GRADE_MAX_PPM; grade += 97) {
        const int32_t at = (grade > (PFE_GRADE_MAX_PPM - 97)) ? PFE_GRADE_MAX_PPM : grade;
        pfe_grade_accel_t out;
        pfe_grade_accel(at, 9810000U, &out);
        const double t = (double)at / 1e6;
        const double c = 1.0 / sqrt_near_one(1.0 + (t * t));
        ASSERT_NEAR((double)out.along_um_s2, g * t * c, 0.53);
        ASSERT_NEAR((double)out.normal_um_s2, g * c, 0.53);
        const double d = (double)out.normal_um_s2 - (g * c);
        const double e = (d < 0.0) ? -d : d;
        worst = (e > worst) ? e : worst;
    }
    /* the rounding to whole um/s^2 is reached: the test can fail */
    ASSERT_GT(worst, 0.4);
}

static void test_force_limits(void **state)
{
    (void)state;
    /* 250 kW / 25 m/s = 10 kN; at 1 m/s Pmax / v = 250 kN is above traction. */
    assert_int_equal(pfe_wheel_force_max_n(250000U, 100000U, 25000), 10000);
    assert_int_equal(pfe_wheel_force_max_n(250000U, 100000U, 1000), 100000);
    assert_int_equal(pfe_wheel_force_max_n(250000U, 100000U, 0), 100000);
    assert_int_equal(pfe_wheel_force_max_n(250000U, 100000U, -5), 100000);
    /* 250000 / 7 = 35714.28 N, rounded down. */
    assert_int_equal(pfe_wheel_force_max_n(250U, 100000U, 7), 35714);
}

static void test_fuel_rate_and_fuel_cut(void **state)
{
    (void)state;
    const pfe_vehicle_t v = truck(0U);
    /* (5166 N * 25 m/s + 4 kW) / (0.40 * 35800 J/mL) = 9.298184 mL/s; the
     * coefficient 1 / (eta rho_d) has 2^-20 nL/mJ steps: 1e-5 relative here. */
    assert_in_range(pfe_fuel_rate_nl_s(5166, 25000, 4000U, v.fuel_q20), 9298184 - 93, 9298184 + 93);
    /* eq. 3.9: no fuel, not even for Paux, when Fw <= 0. */
    assert_int_equal(pfe_fuel_rate_nl_s(0, 25000, 4000U, v.fuel_q20), 0);
    assert_int_equal(pfe_fuel_rate_nl_s(-30000, 25000, 4000U, v.fuel_q20), 0);
    /* Saturates instead of wrapping. */
    assert_int_equal(pfe_fuel_rate_nl_s(INT32_MAX, 70000, 100000U, v.fuel_q20), UINT32_MAX);
    /* A speed below 0 counts as 0: 100 kW alone at 73224 / 2^20 nL/mJ,
     * 10^8 mW * 73224 / 2^20 = 6983184.8 nL/s. */
    assert_int_equal(pfe_fuel_rate_nl_s(1000, -5, 100000U, 73224), 6983185);
    assert_int_equal(pfe_fuel_rate_nl_s(1000, 0, 100000U, 73224), 6983185);
}

static void test_fuel_force_includes_rotating_mass(void **state)
{
    (void)state;
    const pfe_vehicle_t v = truck(0U);
    pfe_grade_accel_t g;
    pfe_grade_accel(0, 9810000U, &g);
    /* (40000 + 1200) kg * 0.5 m/s^2 = 20600 N on top of 5166 N. */
    assert_int_equal(pfe_vehicle_fuel_force_n(&v, 25000, 500000, &g), 25766);
    /* Air drag with 35 % reduction: 2418.75 * 0.65 = 1572.19 N. */
    const pfe_vehicle_t third = truck(3500U);
    assert_int_equal(pfe_vehicle_air_n(&third, 25000), 1572);
}

/* The step-time forms for one truck and for the object model give the
 * general functions' forces, at hand-computed points and at the corners of
 * their ranges (the heaviest, largest truck at full speed, the largest
 * accelerations and grades). */
static void test_step_forms_match_the_general_forces(void **state)
{
    (void)state;
    const pfe_vehicle_t v = truck(0U);
    pfe_grade_accel_t flat;
    pfe_grade_accel(0, 9810000U, &flat);
    /* 5166 N (above) + 41200 kg * 0.5 m/s^2 = 25766 N, as the general form. */
    assert_int_equal(pfe_vehicle_truck_fuel_force_n(&v, 625000000U, 500000, &flat), 25766);
    assert_int_equal(pfe_vehicle_truck_fuel_force_n(&v, 625000000U, 0, &flat), 5166);
    pfe_vehicle_calib_t big = pfe_default_vehicle;
    big.mass_kg = PFE_MASS_MAX_KG;
    big.rot_mass_kg = PFE_MASS_MAX_KG;
    big.drag_area_mm2 = PFE_DRAG_AREA_MAX_MM2;
    big.roll_coef_ppm = 100000U;
    pfe_vehicle_t heavy;
    assert_int_equal(pfe_vehicle_init(&heavy, &big, &pfe_default_env, 0U), PFE_OK);
    const pfe_vehicle_t *trucks[] = {&v, &heavy};
    const int32_t speeds[] = {0, 1, 25000, PFE_SPEED_MAX_MM_S};
    const int32_t accels[] = {-PFE_ACCEL_MAX_UM_S2, -1, 0, 300000, PFE_ACCEL_MAX_UM_S2};
    const int32_t grades[] = {-PFE_GRADE_MAX_PPM, -40000, 0, 30000, PFE_GRADE_MAX_PPM};
    for (uint32_t t = 0U; t < 2U; t++) {
        for (uint32_t i = 0U; i < 4U; i++) {
            const uint64_t v2 = (uint64_t)(uint32_t)speeds[i] * (uint32_t)speeds[i];
            for (uint32_t j = 0U; j < 5U; j++) {
                for (uint32_t k = 0U; k < 5U; k++) {
                    pfe_grade_accel_t g;
                    pfe_grade_accel(grades[k], 9810000U, &g);
                    assert_int_equal(pfe_vehicle_truck_fuel_force_n(trucks[t], v2, accels[j], &g),
                                     pfe_vehicle_fuel_force_n(trucks[t], speeds[i], accels[j], &g));
                }
            }
        }
    }
    /* The object model: 5 default trucks and 32 of the largest. */
    pfe_platoon_config_t cfg;
    pfe_platoon_t pl;
    for (uint32_t t = 0U; t < 2U; t++) {
        pfe_platoon_config_uniform(&cfg, (t == 0U) ? 5U : PFE_MAX_VEHICLES, 10000U,
                                   (t == 0U) ? &pfe_default_vehicle : &big, &pfe_default_env,
                                   &pfe_default_drag);
        assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);
        for (uint32_t i = 0U; i < 4U; i++) {
            const uint64_t v2 = (uint64_t)(uint32_t)speeds[i] * (uint32_t)speeds[i];
            for (uint32_t j = 0U; j < 5U; j++) {
                for (uint32_t k = 0U; k < 5U; k++) {
                    pfe_grade_accel_t g;
                    pfe_platoon_grade_accel(&pl, grades[k], &g);
                    assert_int_equal(pfe_platoon_fuel_force_n(&pl, v2, accels[j], g.along_um_s2),
                                     pfe_vehicle_fuel_force_n(&pl.object, speeds[i], accels[j], &g));
                }
            }
        }
    }
    /* 5 default trucks at 25 m/s, flat: 8610.75 N of air (below) and
     * 5 * 2746.8 N of rolling, 22344.75 N. */
    pfe_platoon_config_uniform(&cfg, 5U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);
    assert_in_range(pfe_platoon_fuel_force_n(&pl, 625000000U, 0, 0), 22344, 22345);
}

static void test_platoon_aggregates(void **state)
{
    (void)state;
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, 5U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    pfe_platoon_t pl;
    memset(&pl, 0xA5, sizeof pl);
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);
    assert_int_equal(pl.n_vehicles, 5);
    assert_int_equal(pl.mass_kg, 200000);
    assert_int_equal(pl.object.power_max_w, 1250000);  /* eq. 4.4 */
    assert_int_equal(pl.object.brake_max_n, 300000);   /* eq. 4.5 */
    assert_int_equal(pl.object.power_aux_w, 20000);
    assert_int_equal(pl.position[0].reduction_bp, 800);
    assert_int_equal(pl.position[1].reduction_bp, 3100);
    assert_int_equal(pl.position[4].reduction_bp, 3500);
    /* The third truck's reduction holds for every one behind it: the fourth
     * and fifth have the third's fuel model; the first three differ. */
    assert_int_equal(pl.same_as_previous, (1U << 3) | (1U << 4));
    /* eq. 4.6: 2418.75 N * (0.92 + 0.69 + 3 * 0.65) = 8610.75 N at 25 m/s. */
    assert_in_range(pfe_vehicle_air_n(&pl.object, 25000), 8610, 8611);
    /* eq. 4.8 and 4.10, small angle: 5 * 2746.8 N + 200 t * 9.81 * 0.02. */
    pfe_grade_accel_t g;
    pfe_platoon_grade_accel(&pl, 20000, &g);
    assert_int_equal(g.along_um_s2, 196200);
    assert_int_equal(g.normal_um_s2, 9810000);
    assert_in_range(pfe_vehicle_resistance_n(&pl.object, 0, &g), 52974 - 1, 52974 + 1);
    /* Formation drag: the lead truck has the most drag per kg, so
     * c = 5 * 0.92 k - (0.92 + 0.69 + 3 * 0.65) k = 1.04 k, k = 3.87 N/(m/s)^2:
     * 4.0248e-6 N/(mm/s)^2 * 2^32 = 17286.4; at 25 m/s 2515.5 N off
     * 1.25 MW / 25 m/s = 50000 N. */
    assert_in_range(pl.formation_air_q32, 17286 - 2, 17286 + 2);
    assert_in_range(pfe_platoon_force_max_n(&pl, 25000), 47484, 47485);
    /* At 0 m/s the traction limit is left whole; far above any cruise
     * speed the limit never falls below -Fb_max. */
    assert_int_equal(pfe_platoon_force_max_n(&pl, 0), (int32_t)pl.object.traction_max_n);
    /* 1250000 W / 70 m/s = 17857 N less 17286 * 4.9e9 / 2^32 = 19721 N. */
    assert_in_range(pfe_platoon_force_max_n(&pl, PFE_SPEED_MAX_MM_S), 17857 - 19721 - 1,
                    17857 - 19721 + 1);
    pfe_platoon_t steep = pl;
    steep.formation_air_q32 = PFE_FORMATION_AIR_MAX_Q32; /* the documented largest c */
    assert_int_equal(pfe_platoon_force_max_n(&steep, PFE_SPEED_MAX_MM_S), -300000);
    /* eq. 4.3: 2000 N on 200 t is 0.01 m/s^2. */
    assert_int_equal(pfe_platoon_accel_um_s2(&pl, 2000 * 4), 10000);
    assert_int_equal(pfe_platoon_accel_um_s2(&pl, -2000 * 4), -10000);
    /* 0.25 N on 200 t: 1.25 um/s^2, rounds to 1; 128 N: 640 um/s^2. */
    assert_int_equal(pfe_platoon_accel_um_s2(&pl, 1), 1);
    assert_int_equal(pfe_platoon_accel_um_s2(&pl, 128 * 4), 640);
    /* The force is clamped at M * 20 m/s^2. */
    assert_int_equal(pfe_platoon_accel_um_s2(&pl, INT32_MAX), PFE_ACCEL_MAX_UM_S2);
    assert_int_equal(pfe_platoon_accel_um_s2(&pl, INT32_MIN), -PFE_ACCEL_MAX_UM_S2);
}

static void test_platoon_takes_weakest_power_to_mass(void **state)
{
    (void)state;
    pfe_vehicle_calib_t light = pfe_default_vehicle;
    light.mass_kg = 20000U;       /* 12.5 W/kg: stronger than 6.25 W/kg */
    pfe_vehicle_calib_t weak = pfe_default_vehicle;
    weak.power_max_w = 200000U;   /* 5 W/kg: the weakest */
    weak.eta_ppm = 300000U;
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, 3U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    cfg.vehicle[1] = &light;
    cfg.vehicle[2] = &weak;
    pfe_platoon_t pl;
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);
    assert_int_equal(pl.mass_kg, 100000);
    assert_int_equal(pl.object.power_max_w, 500000); /* 5 W/kg * 100 t */
    /* eta_mean = (0.4 + 0.4 + 0.3) / 3: 10^9 * 2^20 / (0.366667e6 * 35800) = 79881.4 */
    assert_in_range(pl.object.fuel_q20, 79881 - 1, 79881 + 1);
}

/* A position reuses the fuel rate of the one before it only when every
 * coefficient of the fuel model is the same: an efficiency of its own
 * breaks the chain, a power limit of its own (not in the fuel model) does
 * not. */
static void test_platoon_marks_repeated_fuel_models(void **state)
{
    (void)state;
    pfe_vehicle_calib_t thrifty = pfe_default_vehicle;
    thrifty.eta_ppm = 420000U;
    pfe_vehicle_calib_t strong = pfe_default_vehicle;
    strong.power_max_w = 400000U;
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, 6U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    cfg.vehicle[3] = &thrifty;
    cfg.vehicle[5] = &strong;
    pfe_platoon_t pl;
    memset(&pl, 0xA5, sizeof pl);
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);
    assert_int_equal(pl.same_as_previous, 1U << 5);
    /* One truck: no position repeats another. */
    pfe_platoon_config_uniform(&cfg, 1U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);
    assert_int_equal(pl.same_as_previous, 0U);
}

static void test_platoon_rejects_bad_configuration(void **state)
{
    (void)state;
    pfe_platoon_config_t cfg;
    pfe_platoon_t pl;
    pfe_platoon_config_uniform(&cfg, 5U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    cfg.n_vehicles = 0U;
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_EINVAL);
    cfg.n_vehicles = PFE_MAX_VEHICLES + 1U;
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_EINVAL);
    cfg.n_vehicles = 5U;
    cfg.vehicle[3] = NULL;
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_EINVAL);
    assert_int_equal(pfe_platoon_init(NULL, &cfg), PFE_EINVAL);
    assert_int_equal(pfe_platoon_init(&pl, NULL), PFE_EINVAL);
    /* The largest platoon is accepted. */
    pfe_platoon_config_uniform(&cfg, PFE_MAX_VEHICLES, 10000U, &pfe_default_vehicle,
                               &pfe_default_env, &pfe_default_drag);
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);
    assert_int_equal(pl.mass_kg, 40000U * PFE_MAX_VEHICLES);
}

/* pfe_platoon_init() in pieces, positions in any order, is the same model;
 * each piece refuses what pfe_platoon_init() refuses. */
static void test_platoon_init_in_pieces(void **state)
{
    (void)state;
    static const uint32_t sizes[3] = {1U, 20U, PFE_MAX_VEHICLES};
    for (uint32_t k = 0U; k < 3U; k++) {
        pfe_platoon_config_t cfg;
        pfe_platoon_config_uniform(&cfg, sizes[k], 8000U, &pfe_default_vehicle, &pfe_default_env,
                                   &pfe_default_drag);
        static pfe_platoon_t once;
        static pfe_platoon_t pieces;
        memset(&once, 0, sizeof once);
        memset(&pieces, 0, sizeof pieces);
        assert_int_equal(pfe_platoon_init(&once, &cfg), PFE_OK);
        assert_int_equal(pfe_platoon_init_begin(&cfg), PFE_OK);
        /* the last positions first, 8 at a time, then the first 8; past the end is a no-op */
        assert_int_equal(pfe_platoon_init_positions(&pieces, &cfg, 8U, 8U), PFE_OK);
        assert_int_equal(pfe_platoon_init_positions(&pieces, &cfg, 16U, 8U), PFE_OK);
        assert_int_equal(pfe_platoon_init_positions(&pieces, &cfg, 24U, 100U), PFE_OK);
        assert_int_equal(pfe_platoon_init_positions(&pieces, &cfg, 0U, 8U), PFE_OK);
        assert_int_equal(pfe_platoon_init_positions(&pieces, &cfg, 40U, 8U), PFE_OK);
        assert_int_equal(pfe_platoon_init_finish(&pieces, &cfg), PFE_OK);
        assert_memory_equal(&once, &pieces, sizeof once);
    }
    pfe_platoon_config_t cfg;
    pfe_platoon_t pl;
    pfe_platoon_config_uniform(&cfg, 5U, 10000U, &pfe_default_vehicle, &pfe_default_env, &pfe_default_drag);
    assert_int_equal(pfe_platoon_init_begin(NULL), PFE_EINVAL);
    assert_int_equal(pfe_platoon_init_positions(NULL, &cfg, 0U, 5U), PFE_EINVAL);
    assert_int_equal(pfe_platoon_init_finish(NULL, &cfg), PFE_EINVAL);
    assert_int_equal(pfe_platoon_init_finish(&pl, NULL), PFE_EINVAL);
    cfg.vehicle[3] = NULL;
    assert_int_equal(pfe_platoon_init_begin(&cfg), PFE_OK); /* begin checks the platoon, not each truck */
    assert_int_equal(pfe_platoon_init_positions(&pl, &cfg, 0U, 5U), PFE_EINVAL);
    assert_int_equal(pfe_platoon_init_finish(&pl, &cfg), PFE_EINVAL);
    cfg.vehicle[3] = &pfe_default_vehicle;
    cfg.n_vehicles = PFE_MAX_VEHICLES + 1U;
    assert_int_equal(pfe_platoon_init_begin(&cfg), PFE_EINVAL);
    assert_int_equal(pfe_platoon_init_positions(&pl, &cfg, 0U, 5U), PFE_EINVAL);
    assert_int_equal(pfe_platoon_init_finish(&pl, &cfg), PFE_EINVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_one_truck_flat_90_kmh_needs_129_kw),
        cmocka_unit_test(test_grade_split_is_exact_trigonometry),
        cmocka_unit_test(test_grade_split_over_the_range),
        cmocka_unit_test(test_force_limits),
        cmocka_unit_test(test_fuel_rate_and_fuel_cut),
        cmocka_unit_test(test_fuel_force_includes_rotating_mass),
        cmocka_unit_test(test_step_forms_match_the_general_forces),
        cmocka_unit_test(test_platoon_aggregates),
        cmocka_unit_test(test_platoon_takes_weakest_power_to_mass),
        cmocka_unit_test(test_platoon_marks_repeated_fuel_models),
        cmocka_unit_test(test_platoon_rejects_bad_configuration),
        cmocka_unit_test(test_platoon_init_in_pieces),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
