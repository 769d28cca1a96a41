/*
 * Unit tests: the firmware refuses what its headers call invalid. NULL
 * arguments to every codec function, calibrations one step outside each
 * limit (and on it), and the argument checks of the vehicle, platoon,
 * estimator, simulation and prediction set-up; the saturating helpers at
 * their lower ends.
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
#include "pfe_can.h"
#include "pfe_codec.h"
#include "pfe_estimator.h"
#include "pfe_fixed.h"
#include "pfe_platoon.h"
#include "pfe_predict.h"
#include "pfe_sim.h"
#include "pfe_vehicle.h"

static void test_codec_decoders_refuse_null(void **state)
{
    (void)state;
    pfe_can_frame_t f;
    memset(&f, 0, sizeof f);
    assert_int_equal(pfe_codec_decode_ccvs1(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_ssi(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_platoon_config(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_grade_preview(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_lfe1(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_platoon_fuel(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_hrlfc(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_fuel_prediction(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_status(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_address_claimed(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_request(&f, NULL), PFE_EINVAL);
    /* A NULL frame is refused too, the outputs left not available. */
    pfe_msg_ccvs1_t speed;
    memset(&speed, 0xA5, sizeof speed);
    assert_int_equal(pfe_codec_decode_ccvs1(NULL, &speed), PFE_EINVAL);
    assert_int_equal(speed.speed_mm_s.state, PFE_SIG_NOT_AVAILABLE);
}

static void test_codec_encoders_refuse_null(void **state)
{
    (void)state;
    pfe_can_frame_t f;
    assert_int_equal(pfe_codec_encode_ccvs1(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_ssi(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_platoon_config(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_grade_preview(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_lfe1(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_platoon_fuel(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_hrlfc(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_fuel_prediction(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_status(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_address_claimed(&f, NULL, 0U), PFE_EINVAL);
    /* And a NULL frame, with a message that would be fine. */
    const pfe_msg_ssi_t ssi = {{0, PFE_SIG_VALID}, {0, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}};
    assert_int_equal(pfe_codec_encode_ssi(NULL, &ssi, 0U), PFE_EINVAL);
    const pfe_msg_lfe1_t lfe1 = {{0U, PFE_SIG_VALID}};
    assert_int_equal(pfe_codec_encode_lfe1(NULL, &lfe1, 0U), PFE_EINVAL);
    const pfe_msg_hrlfc_t hrlfc = {{0U, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}};
    assert_int_equal(pfe_codec_encode_hrlfc(NULL, &hrlfc, 0U), PFE_EINVAL);
    pfe_msg_status_t status;
    memset(&status, 0, sizeof status);
    assert_int_equal(pfe_codec_encode_status(NULL, &status, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_request(NULL, PFE_PGN_LFE1, 0xFFU, 0U), PFE_EINVAL);
}

static void test_codec_helpers_with_null(void **state)
{
    (void)state;
    const pfe_codec_signal_t *speed = &pfe_codec_signals[PFE_CSIG_CCVS1_WHEEL_BASED_VEHICLE_SPEED];
    uint8_t data[PFE_CAN_MAX_DLC] = {1U, 2U, 3U, 4U, 5U, 6U, 7U, 8U};
    assert_int_equal(pfe_codec_raw_get(NULL, speed), 0);
    assert_int_equal(pfe_codec_raw_get(data, NULL), 0);
    pfe_codec_raw_put(data, NULL, 0xFFFFU);
    pfe_codec_raw_put(NULL, speed, 0xFFFFU);
    static const uint8_t same[PFE_CAN_MAX_DLC] = {1U, 2U, 3U, 4U, 5U, 6U, 7U, 8U};
    assert_memory_equal(data, same, sizeof data);
    assert_int_equal(pfe_codec_raw_state(NULL, 0U), PFE_SIG_NOT_AVAILABLE);

    uint32_t gap_mm = 7U;
    assert_int_equal(pfe_codec_platoon_gap_mm(NULL, &gap_mm), PFE_SIG_NOT_AVAILABLE);
    assert_int_equal(gap_mm, 0);
    const pfe_msg_platoon_config_t pc = {{2U, PFE_SIG_VALID}, {0U, PFE_SIG_VALID},
                                         {10000U, PFE_SIG_VALID}, {0U, PFE_SIG_NOT_AVAILABLE},
                                         {0, PFE_SIG_NOT_AVAILABLE}};
    assert_int_equal(pfe_codec_platoon_gap_mm(&pc, NULL), PFE_SIG_NOT_AVAILABLE);

    uint64_t packed = 0U;
    assert_int_equal(pfe_j1939_name_pack(NULL, &packed), PFE_EINVAL);
    pfe_j1939_name_unpack(0U, NULL);

    pfe_preview_init(NULL);
    assert_int_equal(pfe_preview_push(NULL, NULL), PFE_EINVAL);
    int32_t grade[4] = {1, 2, 3, 4};
    assert_int_equal(pfe_preview_copy_ppm(NULL, 0U, 4U, grade), 0);
    pfe_preview_t pv;
    pfe_preview_init(&pv);
    assert_int_equal(pfe_preview_copy_ppm(&pv, 0U, 4U, grade), 0); /* EMPTY, not READY */
    assert_int_equal(pfe_preview_copy_ppm(&pv, 0U, 4U, NULL), 0);
    assert_int_equal(grade[0], 1);
}

/* Limits of pfe_calib.h and pfe_calib.c, each one step beyond. */
static void test_vehicle_calibration_limits(void **state)
{
    (void)state;
    assert_int_equal(pfe_calib_check_vehicle(NULL), PFE_EINVAL);
    assert_int_equal(pfe_calib_check_vehicle(&pfe_default_vehicle), PFE_OK);
    pfe_vehicle_calib_t v = pfe_default_vehicle;
    v.mass_kg = 999U;
    v.rot_mass_kg = 0U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v.mass_kg = 1000U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_OK);
    v.mass_kg = 100001U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v = pfe_default_vehicle;
    v.rot_mass_kg = v.mass_kg + 1U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v = pfe_default_vehicle;
    v.drag_area_mm2 = 20000001U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v = pfe_default_vehicle;
    v.roll_coef_ppm = 100001U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v = pfe_default_vehicle;
    v.power_max_w = 0U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v.power_max_w = 2000001U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v = pfe_default_vehicle;
    v.traction_max_n = 0U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v.traction_max_n = 1000001U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v = pfe_default_vehicle;
    v.brake_max_n = 1000001U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v = pfe_default_vehicle;
    v.power_aux_w = 100001U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v = pfe_default_vehicle;
    v.eta_ppm = 49999U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v.eta_ppm = 1000001U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_EINVAL);
    v.eta_ppm = 1000000U;
    assert_int_equal(pfe_calib_check_vehicle(&v), PFE_OK);
}

static void test_env_drag_and_cruise_limits(void **state)
{
    (void)state;
    assert_int_equal(pfe_calib_check_env(NULL), PFE_EINVAL);
    pfe_env_calib_t e = pfe_default_env;
    e.air_density_g_m3 = 499U;
    assert_int_equal(pfe_calib_check_env(&e), PFE_EINVAL);
    e.air_density_g_m3 = 2001U;
    assert_int_equal(pfe_calib_check_env(&e), PFE_EINVAL);
    e = pfe_default_env;
    e.gravity_um_s2 = 9699999U;
    assert_int_equal(pfe_calib_check_env(&e), PFE_EINVAL);
    e.gravity_um_s2 = 9900001U;
    assert_int_equal(pfe_calib_check_env(&e), PFE_EINVAL);
    e = pfe_default_env;
    e.fuel_energy_j_ml = 9999U;
    assert_int_equal(pfe_calib_check_env(&e), PFE_EINVAL);
    e.fuel_energy_j_ml = 60001U;
    assert_int_equal(pfe_calib_check_env(&e), PFE_EINVAL);
    e.fuel_energy_j_ml = 60000U;
    assert_int_equal(pfe_calib_check_env(&e), PFE_OK);

    assert_int_equal(pfe_calib_check_drag(NULL), PFE_EINVAL);
    pfe_drag_table_t d = pfe_default_drag;
    d.gap_mm[3] = d.gap_mm[2]; /* gaps must rise */
    assert_int_equal(pfe_calib_check_drag(&d), PFE_EINVAL);
    d = pfe_default_drag;
    d.reduction_bp[2][10] = 10001U; /* above 100 % */
    assert_int_equal(pfe_calib_check_drag(&d), PFE_EINVAL);

    assert_int_equal(pfe_calib_check_cruise(NULL), PFE_EINVAL);
    pfe_cruise_calib_t c = {5000U, 5000U};
    assert_int_equal(pfe_calib_check_cruise(&c), PFE_OK);
    c.kp_milli_per_s = 5001U;
    assert_int_equal(pfe_calib_check_cruise(&c), PFE_EINVAL);
    c.kp_milli_per_s = 0U;
    assert_int_equal(pfe_calib_check_cruise(&c), PFE_EINVAL);
    c.kp_milli_per_s = 1U;
    c.ki_milli_per_s2 = 5001U;
    assert_int_equal(pfe_calib_check_cruise(&c), PFE_EINVAL);
}

static void test_model_set_up_refuses_bad_arguments(void **state)
{
    (void)state;
    pfe_vehicle_t veh;
    assert_int_equal(pfe_vehicle_init(NULL, &pfe_default_vehicle, &pfe_default_env, 0U), PFE_EINVAL);
    assert_int_equal(pfe_vehicle_init(&veh, &pfe_default_vehicle, &pfe_default_env, 10001U),
                     PFE_EINVAL);
    assert_int_equal(pfe_vehicle_init(&veh, &pfe_default_vehicle, &pfe_default_env, 10000U), PFE_OK);
    assert_int_equal(pfe_vehicle_init(&veh, &pfe_default_vehicle, NULL, 0U), PFE_EINVAL);

    static pfe_platoon_t pl;
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, 2U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    assert_int_equal(pfe_platoon_init(NULL, &cfg), PFE_EINVAL);
    assert_int_equal(pfe_platoon_init(&pl, NULL), PFE_EINVAL);
    cfg.env = NULL;
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_EINVAL);
    /* 0 and 33 vehicles are clamped to 1 and 32 by the uniform builder. */
    pfe_platoon_config_uniform(&cfg, 0U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    assert_int_equal(cfg.n_vehicles, 1);
    pfe_platoon_config_uniform(&cfg, 33U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    assert_int_equal(cfg.n_vehicles, 32);
    cfg.n_vehicles = 33U;
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_EINVAL);
    cfg.n_vehicles = 2U;
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);

    static pfe_estimator_t est;
    assert_int_equal(pfe_estimator_init(NULL, &pl), PFE_EINVAL);
    assert_int_equal(pfe_estimator_init(&est, NULL), PFE_EINVAL);
    assert_int_equal(pfe_estimator_init(&est, &pl), PFE_OK);
    assert_int_equal(pfe_estimator_set_fuel_used_ul(&est, 2, 5U), PFE_EINVAL); /* of 2: 0, 1 */
    assert_int_equal(pfe_estimator_set_fuel_used_ul(&est, -2, 5U), PFE_EINVAL);
    assert_int_equal(pfe_estimator_fuel_used_ul(&est, 2), 0);
    assert_int_equal(pfe_estimator_fuel_used_ul(&est, -2), 0);

    /* Simulation: 2 samples of 3000 km are longer than 4294 km. */
    static const int32_t grade[2] = {0, 0};
    const pfe_road_t too_long = {grade, 2U, 3000000000U};
    const pfe_road_t road = {grade, 2U, 10000U};
    const pfe_road_t no_grades = {NULL, 2U, 10000U};
    pfe_sim_t sim;
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &too_long, 25000, 25000, 10000U),
                     PFE_EINVAL);
    assert_int_equal(pfe_sim_init(NULL, &pl, &pfe_default_cruise, &road, 25000, 25000, 10000U),
                     PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, NULL, &pfe_default_cruise, &road, 25000, 25000, 10000U),
                     PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, NULL, 25000, 25000, 10000U),
                     PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &no_grades, 25000, 25000, 10000U),
                     PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, 16001U),
                     PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 70001, 25000, 10000U),
                     PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 999, 10000U),
                     PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, 10000U),
                     PFE_OK);
}

static void test_prediction_set_up_refuses_bad_arguments(void **state)
{
    (void)state;
    static pfe_platoon_t pl;
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, 2U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);
    static pfe_preview_t pv;
    pfe_preview_init(&pv);
    static pfe_predict_t p;
    pfe_predict_init(&p);
    const pfe_cruise_calib_t no_gain = {0U, 20U};
    assert_int_equal(pfe_predict_start(NULL, &pv, 1U, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_EINVAL);
    assert_int_equal(pfe_predict_start(&p, NULL, 1U, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_EINVAL);
    assert_int_equal(p.last_error, PFE_EINVAL);
    assert_int_equal(pfe_predict_start(&p, &pv, 1U, 0U, NULL, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_EINVAL);
    assert_int_equal(pfe_predict_start(&p, &pv, 1U, 0U, &pl, NULL, &pfe_default_cruise, 25000,
                                       25000),
                     PFE_EINVAL);
    assert_int_equal(pfe_predict_start(&p, &pv, 1U, 0U, &pl, &pfe_default_drag, NULL, 25000,
                                       25000),
                     PFE_EINVAL);
    assert_int_equal(pfe_predict_start(&p, &pv, 1U, 0U, &pl, &pfe_default_drag, &no_gain, 25000,
                                       25000),
                     PFE_EINVAL);
    assert_int_equal(pfe_predict_start(&p, &pv, 1U, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 999, 25000),
                     PFE_EINVAL);
    assert_int_equal(pfe_predict_start(&p, &pv, 1U, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 70001, 25000),
                     PFE_EINVAL);
    /* Arguments fine, but no preview yet. */
    assert_int_equal(pfe_predict_start(&p, &pv, 1U, 0U, &pl, &pfe_default_drag,
                                       &pfe_default_cruise, 25000, 25000),
                     PFE_PREDICT_ENOPREVIEW);
    assert_int_equal(p.phase, PFE_PREDICT_IDLE);
    assert_false(pfe_predict_result(&p)->valid);
}

static void test_saturating_helpers_at_their_lower_ends(void **state)
{
    (void)state;
    assert_int_equal(pfe_clamp_i64(-5, -3, 3), -3);
    assert_int_equal(pfe_clamp_i64(INT64_MIN, 0, 1), 0);
    assert_int_equal(pfe_sat_add_i64(INT64_MIN + 5, -6), INT64_MIN);
    assert_int_equal(pfe_sat_add_i64(INT64_MIN + 5, -5), INT64_MIN);
    assert_int_equal(pfe_sat_add_i64(INT64_MIN + 5, -4), INT64_MIN + 1);
    assert_int_equal(pfe_sat_add_i64(-7, -8), -15);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_codec_decoders_refuse_null),
        cmocka_unit_test(test_codec_encoders_refuse_null),
        cmocka_unit_test(test_codec_helpers_with_null),
        cmocka_unit_test(test_vehicle_calibration_limits),
        cmocka_unit_test(test_env_drag_and_cruise_limits),
        cmocka_unit_test(test_model_set_up_refuses_bad_arguments),
        cmocka_unit_test(test_prediction_set_up_refuses_bad_arguments),
        cmocka_unit_test(test_saturating_helpers_at_their_lower_ends),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
