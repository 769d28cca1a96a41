/*
 * Unit tests: the arithmetic at the edges of every input and calibration.
 * Zero and maximum speed, +-30 % grade and the codec's extremes, the
 * largest platoon (PFE_MAX_VEHICLES), masses from 1 t to 100 t, the power
 * limit as speed tends to zero, totals near their maximum, the simulation
 * and the predictor at the extremes. Run under UBSan on the host (an
 * overflow anywhere fails) and on the Cortex-M4. Where a result saturates,
 * the test checks that the output says so (estimator flags, codec clamps,
 * PFE_Status).
 *
 * Expected values are hand-computed from the physics (g = 9.81 m/s^2 and
 * the calibrations below); tolerances state the arithmetic's resolution.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "pfe_calib.h"
#include "pfe_can.h"
#include "pfe_codec.h"
#include "pfe_ecu.h"
#include "pfe_estimator.h"
#include "pfe_fixed.h"
#include "pfe_nvm.h"
#include "pfe_platoon.h"
#include "pfe_predict.h"
#include "pfe_sim.h"
#include "pfe_vehicle.h"

/* The lightest truck the checks accept: 1 t, 30 kg rotating, cw Af 0.6 m^2,
 * cr 0.01, 100 kW, 10 kN of traction and of brake, 500 W of auxiliaries,
 * eta 0.30. */
static const pfe_vehicle_calib_t k_light = {1000U, 30U, 600000U, 10000U, 100000U, 10000U, 10000U,
                                            500U, 300000U};
/* The heaviest, every value at its limit: 100 t, 3 t rotating, cw Af 20 m^2,
 * cr 0.1, 2 MW, 1 MN of traction and of brake, 100 kW of auxiliaries, eta
 * 0.05 (the fuel hungriest). */
static const pfe_vehicle_calib_t k_heavy = {PFE_MASS_MAX_KG, 3000U, PFE_DRAG_AREA_MAX_MM2, 100000U,
                                            PFE_POWER_MAX_W, PFE_FORCE_MAX_N, PFE_FORCE_MAX_N,
                                            100000U, 50000U};

#define ESTIMATOR_MAX_UL 184467440737095ULL /* floor((2^64 - 1) 10 pL / 10^5) */
#define TOTAL_MAX_UL 4211081215000ULL       /* 0xFAFFFFFF * 0.001 L (HRLFC, PlatoonFuel) */

static pfe_platoon_t g_platoon;
static pfe_estimator_t g_est;
static pfe_preview_t g_pv;
static pfe_predict_t g_pred;
static pfe_ecu_t g_ecu;
static int32_t g_road[1000];

static void platoon_of(uint32_t n, const pfe_vehicle_calib_t *v, const pfe_drag_table_t *drag)
{
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, n, 10000U, v, &pfe_default_env, drag);
    memset(&g_platoon, 0xA5, sizeof g_platoon);
    assert_int_equal(pfe_platoon_init(&g_platoon, &cfg), PFE_OK);
}

/* ticks of 10 ms at constant speed and grade, a fresh speed every 10th. */
static const pfe_est_output_t *run_estimator(uint32_t ticks, int32_t speed_mm_s, int32_t grade_ppm)
{
    const pfe_est_output_t *out = NULL;
    for (uint32_t k = 0U; k < ticks; k++) {
        const pfe_est_input_t in = {speed_mm_s, true, (k % 10U) == 0U, grade_ppm, true};
        out = pfe_estimator_step(&g_est, &in);
    }
    return out;
}

static const pfe_est_output_t *estimate(uint32_t n, const pfe_vehicle_calib_t *v,
                                        const pfe_drag_table_t *drag, int32_t speed_mm_s,
                                        int32_t grade_ppm)
{
    platoon_of(n, v, drag);
    memset(&g_est, 0xA5, sizeof g_est);
    assert_int_equal(pfe_estimator_init(&g_est, &g_platoon), PFE_OK);
    /* 1 s: past the filter's warm-up, at a constant speed (a = 0). */
    const pfe_est_output_t *out = run_estimator(100U, speed_mm_s, grade_ppm);
    assert_int_not_equal(out->flags & PFE_EST_VALID, 0U);
    assert_int_equal(out->accel_um_s2, 0);
    return out;
}

/* ------------------------------------------------------------ calibration */

static void test_mass_range_is_1_t_to_100_t(void **state)
{
    (void)state;
    pfe_vehicle_calib_t c = k_light;
    assert_int_equal(pfe_calib_check_vehicle(&c), PFE_OK);
    c.mass_kg = PFE_MASS_MIN_KG - 1U;
    assert_int_equal(pfe_calib_check_vehicle(&c), PFE_EINVAL);
    c = k_heavy;
    assert_int_equal(pfe_calib_check_vehicle(&c), PFE_OK);
    c.mass_kg = PFE_MASS_MAX_KG + 1U;
    assert_int_equal(pfe_calib_check_vehicle(&c), PFE_EINVAL);
    /* Each other limit of the heavy truck, one step past it. */
    c = k_heavy;
    c.drag_area_mm2++;
    assert_int_equal(pfe_calib_check_vehicle(&c), PFE_EINVAL);
    c = k_heavy;
    c.power_max_w++;
    assert_int_equal(pfe_calib_check_vehicle(&c), PFE_EINVAL);
    c = k_heavy;
    c.traction_max_n++;
    assert_int_equal(pfe_calib_check_vehicle(&c), PFE_EINVAL);
    c = k_heavy;
    c.brake_max_n++;
    assert_int_equal(pfe_calib_check_vehicle(&c), PFE_EINVAL);
    c = k_heavy;
    c.power_aux_w++;
    assert_int_equal(pfe_calib_check_vehicle(&c), PFE_EINVAL);
    c = k_heavy;
    c.roll_coef_ppm++;
    assert_int_equal(pfe_calib_check_vehicle(&c), PFE_EINVAL);
    c = k_heavy;
    c.eta_ppm--;
    assert_int_equal(pfe_calib_check_vehicle(&c), PFE_EINVAL);
    c = k_heavy;
    c.rot_mass_kg = c.mass_kg + 1U;
    assert_int_equal(pfe_calib_check_vehicle(&c), PFE_EINVAL);

    /* Masses in Q32 (kg * 2^32 / 10^6 = kg * 2^26 / 15625), rounded:
     * 1000 kg 4294967.296, 1030 kg 4423816.315, 100 t 429496729.6,
     * 103 t 442381631.488. */
    pfe_vehicle_t v;
    memset(&v, 0xA5, sizeof v);
    assert_int_equal(pfe_vehicle_init(&v, &k_light, &pfe_default_env, 0U), PFE_OK);
    assert_int_equal(v.mass_q32, 4294967);
    assert_int_equal(v.mass_fuel_q32, 4423816);
    pfe_grade_accel_t flat;
    pfe_grade_accel(0, pfe_default_env.gravity_um_s2, &flat);
    /* Standing, at the filter's largest acceleration (20 m/s^2):
     * 1030 kg * 20 + 0.01 * 1000 * 9.81 = 20698.1 N. */
    assert_int_equal(pfe_vehicle_fuel_force_n(&v, 0, PFE_ACCEL_MAX_UM_S2, &flat), 20698);
    /* Standing on the flat, only the auxiliaries burn: 500 W / (0.30 *
     * 35800 J/mL) = 46554.9 nL/s (fuel coefficient to 1e-5). */
    assert_in_range(pfe_fuel_rate_nl_s(98, 0, k_light.power_aux_w, v.fuel_q20), 46554 - 1, 46555 + 1);

    memset(&v, 0xA5, sizeof v);
    assert_int_equal(pfe_vehicle_init(&v, &k_heavy, &pfe_default_env, 0U), PFE_OK);
    assert_int_equal(v.mass_q32, 429496730);
    assert_int_equal(v.mass_fuel_q32, 442381631);
    /* Every term at once: 70 m/s, 20 m/s^2, +50 % (sin 0.4472136, cos
     * 0.8944272): air 0.5 * 1.29 * 20 * 70^2 = 63210 N, inertia 103000 * 20
     * = 2060000 N, grade 100000 * 9.81 * 0.4472136 = 438716.5 N, rolling
     * 0.1 * 100000 * 9.81 * 0.8944272 = 87743.3 N: 2649669.8 N. */
    pfe_grade_accel_t steep;
    pfe_grade_accel(PFE_GRADE_MAX_PPM, pfe_default_env.gravity_um_s2, &steep);
    const int32_t f = pfe_vehicle_fuel_force_n(&v, PFE_SPEED_MAX_MM_S, PFE_ACCEL_MAX_UM_S2, &steep);
    assert_in_range(f, 2649669, 2649671);
    /* (2649670 N * 70 m/s + 100 kW) / (0.05 * 35800 J/mL) = 1.04e11 nL/s:
     * beyond 32 bits, the rate saturates. */
    assert_int_equal(pfe_fuel_rate_nl_s(f, PFE_SPEED_MAX_MM_S, k_heavy.power_aux_w, v.fuel_q20),
                     UINT32_MAX);
}

/* ------------------------------------------------------------ speed */

static void test_speed_zero_and_maximum(void **state)
{
    (void)state;
    /* Standing on the flat: Fw = Fr = 0.007 * 40000 * 9.81 = 2746.8 N, no
     * power at the wheels, the auxiliaries' 4 kW / (0.40 * 35800 J/mL) =
     * 279329.6 nL/s. */
    const pfe_est_output_t *out = estimate(1U, &pfe_default_vehicle, &pfe_default_drag, 0, 0);
    assert_int_equal(out->speed_mm_s, 0);
    assert_int_equal(out->wheel_force_n, 2747);
    assert_in_range(out->fuel_rate_nl_s, 279330 - 3, 279330 + 3);
    assert_int_equal(out->flags & (PFE_EST_SPEED_CLAMPED | PFE_EST_SATURATED), 0U);

    /* 70 m/s (PFE_SPEED_MAX_MM_S): air 0.5 * 1.29 * 6 * 4900 = 18963 N plus
     * 2746.8 N; (21709.8 N * 70 m/s + 4 kW) / 14320 J/mL = 106402654 nL/s;
     * the force is rounded to the newton first (0.5 N * 70 m/s is 2444
     * nL/s), the fuel coefficient to 1e-5 (1064 nL/s). */
    out = estimate(1U, &pfe_default_vehicle, &pfe_default_drag, PFE_SPEED_MAX_MM_S, 0);
    assert_int_equal(out->speed_mm_s, PFE_SPEED_MAX_MM_S);
    assert_int_equal(out->wheel_force_n, 21710);
    assert_in_range(out->fuel_rate_nl_s, 106402654 - 3508, 106402654 + 3508);
    assert_int_equal(out->flags & PFE_EST_SPEED_CLAMPED, 0U);
    /* One mm/s more is clamped, and flagged. */
    out = run_estimator(20U, PFE_SPEED_MAX_MM_S + 1, 0);
    assert_int_equal(out->speed_mm_s, PFE_SPEED_MAX_MM_S);
    assert_int_not_equal(out->flags & PFE_EST_SPEED_CLAMPED, 0U);

    /* CCVS1's largest valid raw speed, 0xFAFF / 256 km/h = 250.996 km/h =
     * 69721.1 mm/s, is inside the model's range; 0xFB00 is out of range and
     * decodes to no value. */
    pfe_can_frame_t f = {0x98FEF100UL, 8U, {0xFF, 0xFF, 0xFA, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF}};
    pfe_msg_ccvs1_t m;
    ASSERT_GE(pfe_codec_decode_ccvs1(&f, &m), 0);
    assert_int_equal(m.speed_mm_s.state, PFE_SIG_VALID);
    assert_int_equal(m.speed_mm_s.value, 69721);
    f.data[1] = 0x00U;
    f.data[2] = 0xFBU;
    ASSERT_GE(pfe_codec_decode_ccvs1(&f, &m), 0);
    assert_int_equal(m.speed_mm_s.state, PFE_SIG_OUT_OF_RANGE);
    assert_int_equal(m.speed_mm_s.value, 0);
}

/* ------------------------------------------------------------ grade */

static void test_grade_30_percent_both_ways(void **state)
{
    (void)state;
    /* +30 % at 25 m/s, one 40 t truck, air 0.5 * 1.29 * 6 * 625 = 2418.75 N.
     * Object model (small angle): 40000 * 9.81 * 0.3 = 117720 N, rolling
     * 2746.8 N: 122885.55 N; (122885.55 * 25 + 4000) W / 14320 J/mL =
     * 214814159 nL/s. The truck itself (sin 0.2873479, cos 0.9578263):
     * 112755.3 + 2630.96 + 2418.75 = 117805.0 N, 205944514 nL/s. */
    const pfe_est_output_t *out = estimate(1U, &pfe_default_vehicle, &pfe_no_drag_reduction, 25000,
                                           300000);
    assert_int_equal(out->grade_ppm, 300000);
    assert_int_equal(out->wheel_force_n, 122886);
    assert_in_range(out->fuel_rate_nl_s, 214814159 - 2148, 214814159 + 2148);
    assert_in_range(out->pos_fuel_rate_nl_s[0], 205944514 - 2059, 205944514 + 2059);
    assert_int_equal(out->flags & (PFE_EST_GRADE_CLAMPED | PFE_EST_SATURATED), 0U);
    /* -30 %: gravity pulls harder than anything resists: fuel cut. */
    out = estimate(1U, &pfe_default_vehicle, &pfe_no_drag_reduction, 25000, -300000);
    ASSERT_LT(out->wheel_force_n, 0);
    assert_int_equal(out->fuel_rate_nl_s, 0);
    assert_int_equal(out->pos_fuel_rate_nl_s[0], 0);
    assert_int_not_equal(out->flags & PFE_EST_VALID, 0U);
}

static void test_grade_codec_extremes(void **state)
{
    (void)state;
    bool sat = true;
    /* atan(0.3) = 16.699244 deg. */
    assert_in_range(pfe_codec_grade_ppm_from_pitch(16699244, &sat), 300000 - 1, 300000 + 1);
    assert_false(sat);
    assert_in_range(pfe_codec_grade_ppm_from_pitch(-16699244, &sat), -300000 - 1, -300000 + 1);
    assert_false(sat);
    /* SSI's own extremes, raw 0 (-64 deg) and 0xFAFF (64.51 deg): beyond
     * 26.565 deg (50 %) the grade saturates and says so. */
    pfe_can_frame_t f = {0x8CF01300UL, 8U, {0x00, 0x00, 0x00, 0x7D, 0xFF, 0xFF, 0xFC, 0xFF}};
    pfe_msg_ssi_t m;
    ASSERT_GE(pfe_codec_decode_ssi(&f, &m), 0);
    assert_int_equal(m.pitch_udeg.state, PFE_SIG_VALID);
    assert_int_equal(m.pitch_udeg.value, -64000000);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(m.pitch_udeg.value, &sat), -PFE_GRADE_MAX_PPM);
    assert_true(sat);
    f.data[0] = 0xFFU;
    f.data[1] = 0xFAU;
    ASSERT_GE(pfe_codec_decode_ssi(&f, &m), 0);
    assert_int_equal(m.pitch_udeg.value, 64510000);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(m.pitch_udeg.value, &sat), PFE_GRADE_MAX_PPM);
    assert_true(sat);
    /* The preview's extremes, raw 0 and 0xFAFF at 0.002 % - 64 %: -640000
     * and +645100 ppm, valid on the wire (the predictor clamps them). */
    pfe_msg_grade_preview_t p;
    memset(&p, 0, sizeof p);
    p.frame_type.value = PFE_PREVIEW_FRAME_DATA;
    p.grade_ppm[0].value = -640000;
    p.grade_ppm[1].value = 645100;
    p.grade_ppm[2].value = 0;
    assert_int_equal(pfe_codec_encode_grade_preview(&f, &p, 0x33U), 0);
    assert_int_equal(f.data[2], 0x00);
    assert_int_equal(f.data[3], 0x00);
    assert_int_equal(f.data[4], 0xFF);
    assert_int_equal(f.data[5], 0xFA);
    /* One step beyond is clamped, and the encoder says which signals. */
    p.grade_ppm[0].value = -640020;
    p.grade_ppm[1].value = 645120;
    ASSERT_GT(pfe_codec_encode_grade_preview(&f, &p, 0x33U), 0);
}

/* ------------------------------------------------------------ the largest platoon */

static void test_largest_platoon_of_heaviest_trucks(void **state)
{
    (void)state;
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, PFE_MAX_VEHICLES, 10000U, &k_heavy, &pfe_default_env,
                               &pfe_no_drag_reduction);
    cfg.n_vehicles = PFE_MAX_VEHICLES + 1U;
    assert_int_equal(pfe_platoon_init(&g_platoon, &cfg), PFE_EINVAL);
    platoon_of(PFE_MAX_VEHICLES, &k_heavy, &pfe_no_drag_reduction);
    /* 32 * 100 t; 20 W/kg * 3200 t = 64 MW; 32 MN traction and brake;
     * 3.2 MW of auxiliaries. */
    assert_int_equal(g_platoon.mass_kg, 3200000);
    assert_int_equal(g_platoon.object.power_max_w, 64000000);
    assert_int_equal(g_platoon.object.traction_max_n, 32000000);
    assert_int_equal(g_platoon.object.brake_max_n, 32000000);
    assert_int_equal(g_platoon.object.power_aux_w, 3200000);
    /* Any force beyond 3200 t * 20 m/s^2 gives exactly +-20 m/s^2. */
    assert_int_equal(pfe_platoon_accel_um_s2(&g_platoon, INT32_MAX), PFE_ACCEL_MAX_UM_S2);
    assert_int_equal(pfe_platoon_accel_um_s2(&g_platoon, INT32_MIN), -PFE_ACCEL_MAX_UM_S2);

    /* 70 m/s on +50 %, object model: air 0.5 * 1.29 * 640 * 4900 = 2022720
     * N, rolling 0.1 * 3.2e6 * 9.81 = 3139200 N, grade 3.2e6 * 9.81 * 0.5 =
     * 15696000 N: 20857920 N (each truck's air coefficient is held to
     * 2^-32 N/(mm/s)^2, 1.8e-5 of it: 37 N of the air). 1.46 GW / 1790
     * J/mL: every rate saturates, and says so. */
    const pfe_est_output_t *out = estimate(PFE_MAX_VEHICLES, &k_heavy, &pfe_no_drag_reduction,
                                           PFE_SPEED_MAX_MM_S, PFE_GRADE_MAX_PPM);
    assert_in_range(out->wheel_force_n, 20857920 - 38, 20857920 + 38);
    assert_int_equal(out->fuel_rate_nl_s, UINT32_MAX);
    for (uint32_t i = 0U; i < PFE_MAX_VEHICLES; i++) {
        assert_int_equal(out->pos_fuel_rate_nl_s[i], UINT32_MAX);
    }
    assert_int_not_equal(out->flags & PFE_EST_SATURATED, 0U);
    /* The totals take UINT32_MAX * 10 pL a tick: 60 valid ticks of the 100
     * (the first 40 warm the filter up: 5 samples 100 ms apart) are 60 *
     * 4294967295 * 10 pL = 2576980.377 uL. */
    assert_int_equal(pfe_estimator_fuel_used_ul(&g_est, PFE_EST_PLATOON), 2576980U);
    assert_int_equal(pfe_estimator_fuel_used_ul(&g_est, 31), 2576980U);
}

/* ------------------------------------------------------------ power limit */

static void test_power_limit_as_speed_tends_to_zero(void **state)
{
    (void)state;
    /* min(P / v, traction): one heavy truck, 2 MW and 1 MN, meet at 2 m/s. */
    assert_int_equal(pfe_wheel_force_max_n(PFE_POWER_MAX_W, PFE_FORCE_MAX_N, 0), 1000000);
    assert_int_equal(pfe_wheel_force_max_n(PFE_POWER_MAX_W, PFE_FORCE_MAX_N, 1), 1000000);
    assert_int_equal(pfe_wheel_force_max_n(PFE_POWER_MAX_W, PFE_FORCE_MAX_N, 1999), 1000000);
    assert_int_equal(pfe_wheel_force_max_n(PFE_POWER_MAX_W, PFE_FORCE_MAX_N, 2000), 1000000);
    assert_int_equal(pfe_wheel_force_max_n(PFE_POWER_MAX_W, PFE_FORCE_MAX_N, 2001), 999500);
    assert_int_equal(pfe_wheel_force_max_n(PFE_POWER_MAX_W, PFE_FORCE_MAX_N, PFE_SPEED_MAX_MM_S), 28571);
    /* The largest platoon's object: 64 MW and 32 MN. 64e6 / 2.001 =
     * 31984007.996 N; 64e6 / 70 = 914285.7 N. */
    platoon_of(PFE_MAX_VEHICLES, &k_heavy, &pfe_no_drag_reduction);
    const uint32_t p = g_platoon.object.power_max_w, t = g_platoon.object.traction_max_n;
    assert_int_equal(pfe_wheel_force_max_n(p, t, 1), 32000000);
    assert_int_equal(pfe_wheel_force_max_n(p, t, 2000), 32000000);
    assert_int_equal(pfe_wheel_force_max_n(p, t, 2001), 31984007);
    assert_int_equal(pfe_wheel_force_max_n(p, t, PFE_SPEED_MAX_MM_S), 914285);
    /* The default truck: 250 kW and 100 kN meet at 2.5 m/s. */
    assert_int_equal(pfe_wheel_force_max_n(250000U, 100000U, 1), 100000);
    assert_int_equal(pfe_wheel_force_max_n(250000U, 100000U, 2500), 100000);
    assert_int_equal(pfe_wheel_force_max_n(250000U, 100000U, 2501), 99960);
    /* Traction beyond int32 is held at INT32_MAX. */
    assert_int_equal(pfe_wheel_force_max_n(UINT32_MAX, UINT32_MAX, 1), INT32_MAX);
}

/* ------------------------------------------------------------ totals near their maximum */

static void test_fuel_used_near_its_maximum(void **state)
{
    (void)state;
    platoon_of(1U, &pfe_default_vehicle, &pfe_default_drag);
    assert_int_equal(pfe_estimator_init(&g_est, &g_platoon), PFE_OK);
    /* 1 uL below the largest total read back: 184467440737094e5 10 pL, and
     * 151615 10 pL of room; the first valid tick (9.3 mL/s at 25 m/s is
     * 9298184 10 pL) fills it. */
    assert_int_equal(pfe_estimator_set_fuel_used_ul(&g_est, PFE_EST_PLATOON, ESTIMATOR_MAX_UL - 1U), PFE_OK);
    assert_int_equal(pfe_estimator_set_fuel_used_ul(&g_est, 0, ESTIMATOR_MAX_UL - 1U), PFE_OK);
    const pfe_est_output_t *out = run_estimator(4U * 10U, 25000, 0);
    assert_int_equal(out->flags & PFE_EST_SATURATED, 0U); /* warming up: nothing added */
    out = run_estimator(10U, 25000, 0);
    assert_int_not_equal(out->flags & PFE_EST_SATURATED, 0U);
    assert_int_equal(pfe_estimator_fuel_used_ul(&g_est, PFE_EST_PLATOON), ESTIMATOR_MAX_UL);
    assert_int_equal(pfe_estimator_fuel_used_ul(&g_est, 0), ESTIMATOR_MAX_UL);
    out = run_estimator(100U, 25000, 0);
    assert_int_not_equal(out->flags & PFE_EST_SATURATED, 0U);
    assert_int_equal(pfe_estimator_fuel_used_ul(&g_est, PFE_EST_PLATOON), ESTIMATOR_MAX_UL);
    /* A restored total beyond what the estimator holds reads back as its
     * largest, never wrapped. */
    assert_int_equal(pfe_estimator_set_fuel_used_ul(&g_est, 0, UINT64_MAX), PFE_OK);
    assert_int_equal(pfe_estimator_fuel_used_ul(&g_est, 0), ESTIMATOR_MAX_UL);
}

static void test_codec_limits_of_every_output(void **state)
{
    (void)state;
    pfe_can_frame_t f;
    /* Totals, 0.001 L: 4211081215499 uL rounds to the top raw 0xFAFFFFFF;
     * 500 more round past it and are clamped (signal 1 of each message). */
    pfe_msg_platoon_fuel_t pf = {{0U, PFE_SIG_VALID}, {TOTAL_MAX_UL + 499U, PFE_SIG_VALID}};
    assert_int_equal(pfe_codec_encode_platoon_fuel(&f, &pf, 0x8CU), 0);
    pf.fuel_used_ul.value = TOTAL_MAX_UL + 500U;
    assert_int_equal(pfe_codec_encode_platoon_fuel(&f, &pf, 0x8CU), 2);
    pfe_msg_platoon_fuel_t back;
    ASSERT_GE(pfe_codec_decode_platoon_fuel(&f, &back), 0);
    assert_int_equal(back.fuel_used_ul.value, TOTAL_MAX_UL);
    pfe_msg_hrlfc_t h = {{0U, PFE_SIG_NOT_AVAILABLE}, {TOTAL_MAX_UL + 499U, PFE_SIG_VALID}};
    assert_int_equal(pfe_codec_encode_hrlfc(&f, &h, 0x8CU), 0);
    h.total_fuel_ul.value = UINT64_MAX;
    assert_int_equal(pfe_codec_encode_hrlfc(&f, &h, 0x8CU), 2);
    /* Rates, 0.05 L/h = 125000/9 nL/s: raw 64255 (0xFAFF) up to 64255.5 *
     * 125000 / 9 = 892437500 nL/s, exclusive. */
    pfe_msg_lfe1_t l = {{892437499U, PFE_SIG_VALID}};
    assert_int_equal(pfe_codec_encode_lfe1(&f, &l, 0x8CU), 0);
    assert_int_equal(f.data[0], 0xFF);
    assert_int_equal(f.data[1], 0xFA);
    l.fuel_rate_nl_s.value = 892437500U;
    assert_int_equal(pfe_codec_encode_lfe1(&f, &l, 0x8CU), 1);
    l.fuel_rate_nl_s.value = UINT32_MAX;
    assert_int_equal(pfe_codec_encode_lfe1(&f, &l, 0x8CU), 1);
    /* Prediction, 0.01 L and 0.1 s: 642554999 uL and 6425549 ms are the
     * last values that fit. */
    pfe_msg_fuel_prediction_t p = {{642554999U, PFE_SIG_VALID}, {0U, PFE_SIG_VALID},
                                   {UINT32_MAX, PFE_SIG_VALID}, {6425549U, PFE_SIG_VALID}};
    assert_int_equal(pfe_codec_encode_fuel_prediction(&f, &p, 0x8CU), 4);
    p.fuel_upper_ul.value = 642554999U;
    assert_int_equal(pfe_codec_encode_fuel_prediction(&f, &p, 0x8CU), 0);
    p.fuel_ul.value = 642555000U;
    p.time_ms.value = 6425550U;
    assert_int_equal(pfe_codec_encode_fuel_prediction(&f, &p, 0x8CU), 1 | 8);
}

/* ------------------------------------------------------------ the ECU says so */

static pfe_can_frame_t g_tx[PFE_ECU_TX_MAX];
static uint32_t g_ntx;
static uint64_t g_now;

static void ecu_start(uint32_t n, uint32_t position, const pfe_vehicle_calib_t *v,
                      const pfe_nvm_state_t *restored)
{
    const pfe_ecu_config_t c = {
        .preferred_address = PFE_ECU_DEFAULT_ADDRESS,
        .name = 0x80A0000012345678ULL,
        .save_interval_ms = 1000U,
        .vehicle = v,
        .env = &pfe_default_env,
        .drag = &pfe_default_drag,
        .default_vehicles = n,
        .default_position = position,
        .default_gap_mm = 10000U,
        .cruise = &pfe_default_cruise,
        .default_set_speed_mm_s = 25000,
    };
    g_now = 1000000U;
    memset(&g_ecu, 0xA5, sizeof g_ecu);
    assert_int_equal(pfe_ecu_init(&g_ecu, &c, restored, (restored != NULL) ? 0 : -1, g_now), PFE_OK);
}

/* One tick; CCVS1 every 100 ms unless speed_raw is 0, SSI every tick unless
 * pitch_raw is 0 (raw values: 1/256 km/h; 0.002 deg - 64 deg). */
static void ecu_tick(uint16_t speed_raw, uint16_t pitch_raw)
{
    if ((speed_raw != 0U) && (((g_now / 10000U) % 10U) == 0U)) {
        const pfe_can_frame_t f = {0x98FEF100UL, 8U, {0xFF, (uint8_t)speed_raw, (uint8_t)(speed_raw >> 8),
                                                      0xFF, 0xFF, 0xFF, 0xFF, 0xFF}};
        pfe_ecu_receive(&g_ecu, &f, g_now);
    }
    if (pitch_raw != 0U) {
        const pfe_can_frame_t f = {0x8CF01300UL, 8U, {(uint8_t)pitch_raw, (uint8_t)(pitch_raw >> 8), 0x00,
                                                      0x7D, 0xFF, 0xFF, 0xFC, 0xFF}};
        pfe_ecu_receive(&g_ecu, &f, g_now);
    }
    g_ntx = pfe_ecu_tick(&g_ecu, g_now, g_tx, PFE_ECU_TX_MAX);
    g_now += PFE_ECU_TICK_US;
}

static const pfe_can_frame_t *sent(uint32_t pgn)
{
    for (uint32_t k = 0U; k < g_ntx; k++) {
        if (pfe_j1939_pgn(g_tx[k].id) == pgn) {
            return &g_tx[k];
        }
    }
    return NULL;
}

/* Ticks until a status goes out (within 1.1 s) and decodes it. */
static pfe_msg_status_t next_status(uint16_t speed_raw, uint16_t pitch_raw)
{
    pfe_msg_status_t m;
    memset(&m, 0xA5, sizeof m);
    for (uint32_t k = 0U; k < 110U; k++) {
        ecu_tick(speed_raw, pitch_raw);
        const pfe_can_frame_t *f = sent(PFE_PGN_STATUS);
        if (f != NULL) {
            ASSERT_GE(pfe_codec_decode_status(f, &m), 0);
            return m;
        }
    }
    fail_msg("no PFE_Status within 1.1 s");
    return m;
}

static void test_ecu_status_says_grade_clamped(void **state)
{
    (void)state;
    ecu_start(1U, 0U, &pfe_default_vehicle, NULL);
    /* 90 km/h (raw 0x5A00); pitch 20 deg (raw (20 + 64) / 0.002 = 42000 =
     * 0xA410): tan 20 deg = 36.4 %, inside the model's range. */
    pfe_msg_status_t m = next_status(0x5A00U, 0xA410U);
    m = next_status(0x5A00U, 0xA410U);
    assert_int_equal(m.mode.value, PFE_MODE_DEGRADED);
    assert_int_equal(m.grade_clamped.value, 0U);
    /* Pitch 40 deg (raw 52000 = 0xCB20): tan 40 deg = 83.9 %, used as 50 %:
     * the status says the grade was clamped. */
    m = next_status(0x5A00U, 0xCB20U);
    assert_int_equal(m.grade_clamped.value, 1U);
    /* -40 deg (raw 12000 = 0x2EE0) likewise. */
    m = next_status(0x5A00U, 0x2EE0U);
    assert_int_equal(m.grade_clamped.value, 1U);
    m = next_status(0x5A00U, 0xA410U);
    assert_int_equal(m.grade_clamped.value, 0U);
}

static void test_ecu_status_says_output_clamped(void **state)
{
    (void)state;
    /* A restored total of 4211081215499 uL still fits HRLFC (4211081.215 L)
     * and PlatoonFuel; without speed the estimate stands still. */
    pfe_nvm_state_t r = {1U, TOTAL_MAX_UL + 499U, TOTAL_MAX_UL + 499U, 0U, 0U, 0U};
    ecu_start(1U, 0U, &pfe_default_vehicle, &r);
    pfe_msg_status_t m = next_status(0U, 0U);
    m = next_status(0U, 0U);
    assert_int_equal(m.output_saturated.value, 0U);
    /* 500 uL more and the total is clamped on the wire: HRLFC sends its top
     * value and the status says an output saturated. */
    r.own_fuel_ul = TOTAL_MAX_UL + 500U;
    ecu_start(1U, 0U, &pfe_default_vehicle, &r);
    bool hrlfc = false;
    for (uint32_t k = 0U; (k < 450U) && !hrlfc; k++) { /* HRLFC from 3 s on */
        ecu_tick(0U, 0U);
        const pfe_can_frame_t *f = sent(PFE_PGN_HRLFC);
        if (f != NULL) {
            pfe_msg_hrlfc_t d;
            ASSERT_GE(pfe_codec_decode_hrlfc(f, &d), 0);
            assert_int_equal(d.total_fuel_ul.state, PFE_SIG_VALID);
            assert_int_equal(d.total_fuel_ul.value, TOTAL_MAX_UL);
            hrlfc = true;
        }
    }
    assert_true(hrlfc);
    m = next_status(0U, 0U);
    assert_int_equal(m.output_saturated.value, 1U);
    /* A total at the estimator's own largest (far beyond the codec's),
     * driving on: it stays there, and the status says so. */
    r.own_fuel_ul = ESTIMATOR_MAX_UL;
    r.platoon_fuel_ul = ESTIMATOR_MAX_UL;
    ecu_start(1U, 0U, &pfe_default_vehicle, &r);
    for (uint32_t k = 0U; k < 3U; k++) {
        m = next_status(0x5A00U, 0x7D00U);
    }
    assert_int_equal(m.mode.value, PFE_MODE_DEGRADED);
    assert_int_equal(m.output_saturated.value, 1U);
    assert_int_equal(pfe_ecu_own_fuel_ul(&g_ecu), ESTIMATOR_MAX_UL);
}

/* The largest platoon, the own truck last, then a platoon of one: the own
 * truck's total goes along to its new position. */
static void test_ecu_total_survives_the_largest_platoon_shrinking(void **state)
{
    (void)state;
    ecu_start(PFE_MAX_VEHICLES, PFE_MAX_VEHICLES - 1U, &pfe_default_vehicle, NULL);
    for (uint32_t k = 0U; k < 300U; k++) {
        ecu_tick(0x5A00U, 0x7D00U);
    }
    const uint64_t own = pfe_ecu_own_fuel_ul(&g_ecu);
    const uint64_t platoon = pfe_ecu_platoon_fuel_ul(&g_ecu);
    /* 2.6 s of estimates (3 s less 0.4 s of warm-up) of the last truck at
     * 90 km/h on the flat, 35 % less air drag: (0.65 * 2418.75 + 2746.8) N *
     * 25 m/s + 4 kW over 14320 J/mL is 7.82 mL/s, some 20 mL. */
    assert_in_range(own, 10000U, 30000U);
    pfe_msg_platoon_config_t c = {{1U, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}, {10000U, PFE_SIG_VALID},
                                  {400U, PFE_SIG_VALID}, {25000, PFE_SIG_VALID}};
    pfe_can_frame_t f;
    assert_int_equal(pfe_codec_encode_platoon_config(&f, &c, 0x00U), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
    /* Built in two ticks: the truck, then the switch. */
    g_ntx = pfe_ecu_tick(&g_ecu, g_now, g_tx, PFE_ECU_TX_MAX);
    assert_int_equal(g_ecu.platoon.n_vehicles, PFE_MAX_VEHICLES);
    /* One more tick of the old platoon: a tick's fuel at most (7.82 mL/s * 10 ms). */
    const uint64_t own_before = pfe_ecu_own_fuel_ul(&g_ecu);
    const uint64_t platoon_before = pfe_ecu_platoon_fuel_ul(&g_ecu);
    assert_in_range(own_before - own, 0U, 100U);
    g_ntx = pfe_ecu_tick(&g_ecu, g_now, g_tx, PFE_ECU_TX_MAX);
    assert_int_equal(g_ecu.platoon.n_vehicles, 1U);
    assert_int_equal(g_ecu.own_position, 0U);
    assert_int_equal(pfe_ecu_own_fuel_ul(&g_ecu), own_before);
    assert_int_equal(pfe_ecu_platoon_fuel_ul(&g_ecu), platoon_before);
    assert_in_range(platoon_before - platoon, 0U, 3000U);
}

/* ------------------------------------------------------------ simulation */

static pfe_road_t constant_road(int32_t grade_ppm, uint32_t n, uint32_t spacing_mm)
{
    for (uint32_t k = 0U; k < n; k++) {
        g_road[k] = grade_ppm;
    }
    const pfe_road_t r = {g_road, n, spacing_mm};
    return r;
}

static int sim_to_end(pfe_sim_t *sim, const pfe_road_t *road, int32_t *max_speed_mm_s)
{
    int rc;
    *max_speed_mm_s = 0;
    while ((rc = pfe_sim_step(sim, road)) == PFE_SIM_RUNNING) {
        const int32_t v = pfe_sim_speed_mm_s(sim);
        *max_speed_mm_s = (v > *max_speed_mm_s) ? v : *max_speed_mm_s;
    }
    return rc;
}

static void test_simulation_at_the_extremes(void **state)
{
    (void)state;
    pfe_sim_t sim;
    int32_t vmax = 0;
    /* The largest, heaviest platoon from 70 m/s on 50 km of flat road at
     * the largest step: it cannot hold 70 m/s and settles where 2 MW / v =
     * 12.9 v^2 + 98100 N per truck, v = 19.424 m/s. */
    platoon_of(PFE_MAX_VEHICLES, &k_heavy, &pfe_no_drag_reduction);
    pfe_road_t road = constant_road(0, 1000U, 50000U);
    assert_int_equal(pfe_sim_init(&sim, &g_platoon, &pfe_default_cruise, &road, PFE_SPEED_MAX_MM_S,
                                  PFE_SPEED_MAX_MM_S, PFE_SIM_STEP_MAX_MM),
                     PFE_OK);
    assert_int_equal(sim_to_end(&sim, &road, &vmax), PFE_SIM_DONE);
    ASSERT_LE(vmax, PFE_SPEED_MAX_MM_S);
    assert_in_range(pfe_sim_speed_mm_s(&sim), 19424 - 20, 19424 + 20);
    /* At full power: (64 MW + 3.2 MW) / (0.05 * 35800 J/mL) = 37541.9 mL/s
     * over 50 km at 19.42 m/s (2574 s), less the start: about 96.6 kL. */
    assert_in_range(sim.fuel_nl / 1000000000U, 90000U, 97000U);

    /* The same on +50 %: it crawls where 2 MW / v = 12.9 v^2 + 588600 N,
     * v = 3.3970 m/s, and does not stall. */
    road = constant_road(PFE_GRADE_MAX_PPM, 100U, 10000U);
    assert_int_equal(pfe_sim_init(&sim, &g_platoon, &pfe_default_cruise, &road, 25000, 25000,
                                  PFE_SIM_STEP_MAX_MM),
                     PFE_OK);
    assert_int_equal(sim_to_end(&sim, &road, &vmax), PFE_SIM_DONE);
    assert_in_range(pfe_sim_speed_mm_s(&sim), 3397 - 4, 3397 + 4);

    /* One 40 t truck up +20 % with the thesis's 12 m samples: it crawls
     * where 250 kW / v = 3.87 v^2 + 2746.8 + 78480 N, v = 3.0764 m/s. A
     * 12 m step would last 3.9 s there, the speed's time constant at the
     * power limit (M v^2 / P) is 1.5 s: the steps shorten to stay stable
     * (pfe_sim.h); with whole 12 m steps the speed swung between 2.6 and
     * 4.4 m/s. */
    platoon_of(1U, &pfe_default_vehicle, &pfe_default_drag);
    road = constant_road(200000, 200U, 12000U);
    assert_int_equal(pfe_sim_init(&sim, &g_platoon, &pfe_default_cruise, &road, 25000, 25000, 12000U),
                     PFE_OK);
    int32_t late_min = INT32_MAX, late_max = 0;
    int rc;
    while ((rc = pfe_sim_step(&sim, &road)) == PFE_SIM_RUNNING) {
        if (sim.position_mm > 1200000U) {
            const int32_t v = pfe_sim_speed_mm_s(&sim);
            late_min = (v < late_min) ? v : late_min;
            late_max = (v > late_max) ? v : late_max;
        }
    }
    assert_int_equal(rc, PFE_SIM_DONE);
    assert_in_range(late_min, 3076 - 2, 3076 + 2);
    assert_in_range(late_max, 3076 - 2, 3076 + 2);

    /* Default 40 t trucks on +30 %: gravity alone, 0.3 * 40000 * 9.81 =
     * 117720 N a truck, beats the 100 kN of traction: they stall. */
    platoon_of(PFE_MAX_VEHICLES, &pfe_default_vehicle, &pfe_default_drag);
    road = constant_road(300000, 100U, 10000U);
    assert_int_equal(pfe_sim_init(&sim, &g_platoon, &pfe_default_cruise, &road, 25000, 25000, 10000U),
                     PFE_OK);
    assert_int_equal(sim_to_end(&sim, &road, &vmax), PFE_ESTALL);

    /* ... and on -50 %: 196200 N of gravity against 60 kN of brake: they
     * run away to the model's top speed, which holds them, burning nothing. */
    road = constant_road(-PFE_GRADE_MAX_PPM, 1000U, 10000U);
    assert_int_equal(pfe_sim_init(&sim, &g_platoon, &pfe_default_cruise, &road, 25000, 25000, 10000U),
                     PFE_OK);
    assert_int_equal(sim_to_end(&sim, &road, &vmax), PFE_SIM_DONE);
    assert_int_equal(vmax, PFE_SPEED_MAX_MM_S);
    assert_int_equal(pfe_sim_speed_mm_s(&sim), PFE_SPEED_MAX_MM_S);
    assert_int_equal(sim.fuel_nl, 0U);

    /* The heavy truck on -30 %: 294300 N of gravity, 1 MN of brake: it
     * holds 25 m/s, burning nothing. */
    platoon_of(1U, &k_heavy, &pfe_default_drag);
    road = constant_road(-300000, 100U, 10000U);
    assert_int_equal(pfe_sim_init(&sim, &g_platoon, &pfe_default_cruise, &road, 25000, 25000, 10000U),
                     PFE_OK);
    assert_int_equal(sim_to_end(&sim, &road, &vmax), PFE_SIM_DONE);
    assert_in_range(pfe_sim_speed_mm_s(&sim), 24900, 25100);
    assert_int_equal(sim.fuel_nl, 0U);
}

/* ------------------------------------------------------------ predictor */

static void send_preview(int32_t grade_ppm, uint32_t n, uint32_t spacing_m)
{
    pfe_preview_init(&g_pv);
    pfe_can_frame_t f;
    pfe_msg_grade_preview_t m;
    memset(&m, 0, sizeof m);
    m.frame_type.value = PFE_PREVIEW_FRAME_HEADER;
    m.sample_count.value = n;
    m.spacing_m.value = spacing_m;
    assert_int_equal(pfe_codec_encode_grade_preview(&f, &m, 0x33U), 0);
    ASSERT_GE(pfe_preview_push(&g_pv, &f), 0);
    for (uint32_t k = 0U; k < n; k += PFE_PREVIEW_SAMPLES_PER_FRAME) {
        memset(&m, 0, sizeof m);
        m.frame_type.value = PFE_PREVIEW_FRAME_DATA;
        m.first_index.value = k;
        for (uint32_t j = 0U; j < PFE_PREVIEW_SAMPLES_PER_FRAME; j++) {
            m.grade_ppm[j].value = ((k + j) < n) ? g_road[k + j] : grade_ppm;
            m.grade_ppm[j].state = ((k + j) < n) ? PFE_SIG_VALID : PFE_SIG_NOT_AVAILABLE;
        }
        assert_int_equal(pfe_codec_encode_grade_preview(&f, &m, 0x33U), 0);
        ASSERT_GE(pfe_preview_push(&g_pv, &f), 0);
    }
    assert_int_equal(g_pv.phase, PFE_PREVIEW_READY);
}

static const pfe_predict_result_t *predict_all(int32_t start_speed_mm_s)
{
    pfe_predict_init(&g_pred);
    assert_int_equal(pfe_predict_start(&g_pred, &g_pv, 1U, 0U, &g_platoon, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, start_speed_mm_s),
                     PFE_OK);
    uint32_t calls = 0U;
    pfe_predict_phase_t ph;
    do {
        ph = pfe_predict_run(&g_pred, &g_pv, PFE_ECU_PREDICT_UNITS);
        calls++;
        ASSERT_LT(calls, 100000U);
    } while ((ph != PFE_PREDICT_DONE) && (ph != PFE_PREDICT_IDLE));
    assert_int_equal(ph, PFE_PREDICT_DONE);
    const pfe_predict_result_t *r = pfe_predict_result(&g_pred);
    assert_true(r->valid);
    ASSERT_LE(r->fuel_lower_ul, r->fuel_ul);
    ASSERT_LE(r->fuel_ul, r->fuel_upper_ul);
    return r;
}

/* The longest preview (1000 samples, 250 m apart: 250 km) at +50 % for the
 * largest, heaviest platoon: it crawls at 3.3970 m/s (see the simulation
 * above) for 250000 / 3.3970 = 73594 s at full power, (64 + 3.2) MW /
 * 1790 J/mL = 37541.9 mL/s: 2762.84 kL. The start (25 m/s) costs little
 * of either. Air drag is nothing at that speed and the grade the same
 * everywhere: the lower bound lies within 0.5 % of the prediction, its
 * auxiliaries' part (3.2 MW for 73594 s: 131.6 kL) counted whole. */
static void test_predictor_longest_steepest_preview_heaviest_platoon(void **state)
{
    (void)state;
    platoon_of(PFE_MAX_VEHICLES, &k_heavy, &pfe_no_drag_reduction);
    (void)constant_road(PFE_GRADE_MAX_PPM, PFE_PREVIEW_MAX_SAMPLES, 250000U);
    send_preview(PFE_GRADE_MAX_PPM, PFE_PREVIEW_MAX_SAMPLES, 250U);
    const pfe_predict_result_t *r = predict_all(25000);
    printf("predict 250 km at +50 %%, 32 x 100 t: fuel %llu uL [%llu, %llu], %lu ms\n",
           (unsigned long long)r->fuel_ul, (unsigned long long)r->fuel_lower_ul,
           (unsigned long long)r->fuel_upper_ul, (unsigned long)r->time_ms);
    assert_int_equal(r->distance_m, 250000U);
    assert_in_range(r->time_ms, 73594000U - 73594U, 73594000U + 73594U);
    assert_in_range(r->fuel_ul / 1000000U, 2762840U - 13814U, 2762840U + 13814U);
    ASSERT_GE(r->fuel_lower_ul, r->fuel_ul - (r->fuel_ul / 200U));
    assert_in_range(r->end_speed_mm_s, 3397 - 4, 3397 + 4);
    /* The preview's own extremes (-64 %, +64.51 %) are clamped to +-50 %:
     * the same prediction. */
    (void)constant_road(645100, PFE_PREVIEW_MAX_SAMPLES, 250000U);
    send_preview(645100, PFE_PREVIEW_MAX_SAMPLES, 250U);
    const uint64_t fuel = r->fuel_ul;
    r = predict_all(25000);
    assert_int_equal(r->fuel_ul, fuel);
    /* From standing: the run starts at its stall speed, 1 m/s. */
    r = predict_all(0);
    assert_in_range(r->time_ms, 73594000U - 73594U, 73594000U + 73594U);
}

/* One truck, 600 m flat then 2 %: the horizon ends slower than it starts
 * (the nominal run gives back kinetic energy), and the bound runs are the
 * nominal run itself: the bounds hold the prediction, the lower one within
 * 0.05 % (it counts the kinetic energy with the rotating parts, as the
 * nominal run's fuel does). Going down 6 %, the nominal run burns nothing,
 * nor does the lower bound. */
static void test_predictor_bounds_hold_the_prediction(void **state)
{
    (void)state;
    platoon_of(1U, &pfe_default_vehicle, &pfe_default_drag);
    for (uint32_t k = 0U; k < 126U; k++) {
        g_road[k] = (k < 50U) ? 0 : 20000;
    }
    send_preview(0, 126U, 12U);
    const pfe_predict_result_t *r = predict_all(25000);
    ASSERT_LT(r->end_speed_mm_s, 25000);
    ASSERT_GE(r->fuel_lower_ul, r->fuel_ul - (r->fuel_ul / 2000U));
    (void)constant_road(-60000, 126U, 12000U);
    send_preview(-60000, 126U, 12U);
    r = predict_all(25000);
    assert_int_equal(r->fuel_ul, 0U);
    assert_int_equal(r->fuel_lower_ul, 0U);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mass_range_is_1_t_to_100_t),
        cmocka_unit_test(test_speed_zero_and_maximum),
        cmocka_unit_test(test_grade_30_percent_both_ways),
        cmocka_unit_test(test_grade_codec_extremes),
        cmocka_unit_test(test_largest_platoon_of_heaviest_trucks),
        cmocka_unit_test(test_power_limit_as_speed_tends_to_zero),
        cmocka_unit_test(test_fuel_used_near_its_maximum),
        cmocka_unit_test(test_codec_limits_of_every_output),
        cmocka_unit_test(test_ecu_status_says_grade_clamped),
        cmocka_unit_test(test_ecu_status_says_output_clamped),
        cmocka_unit_test(test_ecu_total_survives_the_largest_platoon_shrinking),
        cmocka_unit_test(test_simulation_at_the_extremes),
        cmocka_unit_test(test_predictor_longest_steepest_preview_heaviest_platoon),
        cmocka_unit_test(test_predictor_bounds_hold_the_prediction),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
