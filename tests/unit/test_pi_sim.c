/* Unit tests: PI controller (pfe_pi) and the object model over a road (pfe_sim).
 * Roads are built here; expected values are hand-computed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "pfe_calib.h"
#include "pfe_fixed.h"
#include "pfe_pi.h"
#include "pfe_platoon.h"
#include "pfe_sim.h"

#define ONE_Q32 ((int64_t)1 << 32)
#define ONE_S_Q16 65536U
#define ROAD_SAMPLES 1000U

static int32_t road_buf[ROAD_SAMPLES];

/* 12 km at 12 m, like the thesis's roads, of one constant grade. */
static pfe_road_t constant_road(int32_t grade_ppm)
{
    for (uint32_t k = 0U; k < ROAD_SAMPLES; k++) {
        road_buf[k] = grade_ppm;
    }
    const pfe_road_t r = {road_buf, ROAD_SAMPLES, 12000U};
    return r;
}

static pfe_platoon_t platoon_of(uint32_t n, const pfe_drag_table_t *drag)
{
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, n, 10000U, &pfe_default_vehicle, &pfe_default_env, drag);
    pfe_platoon_t pl;
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);
    return pl;
}

static void test_pi_proportional_and_integral(void **state)
{
    (void)state;
    pfe_pi_t pi;
    pfe_pi_init(&pi, ONE_Q32, 0, 7);
    assert_int_equal(pfe_pi_step(&pi, 100, ONE_S_Q16, -1000, 1000), 107);
    pfe_pi_init(&pi, 0, ONE_Q32, 0);
    assert_int_equal(pfe_pi_step(&pi, 10, ONE_S_Q16, -1000, 1000), 10);
    assert_int_equal(pfe_pi_step(&pi, 10, ONE_S_Q16, -1000, 1000), 20);
    assert_int_equal(pfe_pi_step(&pi, 10, ONE_S_Q16 / 2U, -1000, 1000), 25);
    assert_int_equal(pfe_pi_step(&pi, -40, ONE_S_Q16, -1000, 1000), -15);
}

static void test_pi_saturates_without_windup(void **state)
{
    (void)state;
    pfe_pi_t pi;
    pfe_pi_init(&pi, 0, ONE_Q32, 0);
    for (int k = 0; k < 20; k++) {
        (void)pfe_pi_step(&pi, 10, ONE_S_Q16, -50, 50);
    }
    assert_int_equal(pfe_pi_step(&pi, 10, ONE_S_Q16, -50, 50), 50);
    /* 20 s of error 10 would be 210 without anti-windup: it leaves at once. */
    assert_int_equal(pfe_pi_step(&pi, -10, ONE_S_Q16, -50, 50), 40);

    /* Conditional integration: the P part alone saturates, I must not grow. */
    pfe_pi_init(&pi, ONE_Q32, ONE_Q32, 0);
    assert_int_equal(pfe_pi_step(&pi, 60, ONE_S_Q16, -50, 50), 50);
    assert_int_equal(pfe_pi_step(&pi, -5, ONE_S_Q16, -50, 50), -10);

    /* A limit that moves pulls the integrator along (Pmax / v falls). */
    pfe_pi_init(&pi, 0, ONE_Q32, 45);
    assert_int_equal(pfe_pi_step(&pi, 0, ONE_S_Q16, -50, 20), 20);
    assert_int_equal(pfe_pi_step(&pi, 0, ONE_S_Q16, -50, 50), 20);
    /* Reversed limits: the upper one wins. */
    assert_int_equal(pfe_pi_step(&pi, 0, ONE_S_Q16, 30, 10), 10);
}

static void test_pi_integral_rate_limit(void **state)
{
    (void)state;
    pfe_pi_t pi;
    /* The largest gain, 2^35 (8 U per E per s): the rate's error is held
     * at 2^53 / 2^35 = 2^18, so one second of an error of 2^25 adds
     * 2^35 * 2^18 / 2^32 = 2^21 to I (not 2^24, the gain's own rate); the
     * rate, 2^29 U/s * 2^8 exactly, is held at 2^29 - 1: I gains
     * (2^29 - 1) / 2^8 = 2097151.996, 2097152 rounded. */
    pfe_pi_init(&pi, 0, PFE_PI_GAIN_MAX_Q32, 0);
    assert_true(pi.rate_limited);
    assert_int_equal(pi.rate_error_max, (int32_t)1 << 18);
    assert_int_equal(pfe_pi_step(&pi, PFE_PI_ERROR_MAX, ONE_S_Q16, -PFE_PI_OUT_MAX, PFE_PI_OUT_MAX),
                     2097152);
    /* Below the limit the rate is the gain's: 2^35 * 2^17 / 2^32 = 2^20 more. */
    assert_int_equal(pfe_pi_step(&pi, (int32_t)1 << 17, ONE_S_Q16, -PFE_PI_OUT_MAX, PFE_PI_OUT_MAX),
                     2097152 + 1048576);
    /* The largest error the largest platoon's default gain integrates
     * unlimited: 3200 t at 20 milli / s^2 per kg is 2^28.03 * 2^32 / 2^32,
     * limited only past 2^53 / gain, 32.6 m/s; 1600 t never. */
    pfe_pi_init(&pi, 0, (int64_t)pfe_udiv_round_u64((3200000ULL * 20U) << 32, 1000000000U), 0);
    assert_true(pi.rate_limited);
    ASSERT_GT(pi.rate_error_max, 32000000);
    pfe_pi_init(&pi, 0, (int64_t)pfe_udiv_round_u64((1600000ULL * 20U) << 32, 1000000000U), 0);
    assert_false(pi.rate_limited);
    assert_int_equal(pi.rate_error_max, PFE_PI_ERROR_MAX);
    /* A gain above 2^31, 2^32 + 2^30 (1.25): its mantissa keeps it exactly. */
    pfe_pi_init(&pi, ONE_Q32 + (ONE_Q32 / 4), 0, 0);
    assert_int_equal(pfe_pi_step(&pi, 1000, ONE_S_Q16, -100000, 100000), 1250);
}

static void test_pi_in_range_is_the_checked_step(void **state)
{
    (void)state;
    /* For limits in order and within range and dt <= 16 s the unchecked
     * step gives the checked one's output and integrator, bit for bit. */
    uint32_t x = 12345U;
    for (int k = 0; k < 20000; k++) {
        pfe_pi_t a;
        pfe_pi_t b;
        x = (x * 1103515245U) + 12345U;
        const int32_t lo = -(int32_t)(x % 4000000U);
        x = (x * 1103515245U) + 12345U;
        const int32_t hi = lo + (int32_t)(x % 8000000U);
        x = (x * 1103515245U) + 12345U;
        const int32_t start = (int32_t)(x % 8000000U) - 4000000;
        x = (x * 1103515245U) + 12345U;
        const int32_t err = (int32_t)(x % 80000000U) - 40000000;
        x = (x * 1103515245U) + 12345U;
        const uint32_t dt = x % (PFE_PI_DT_MAX_Q16 + 1U);
        pfe_pi_init(&a, (int64_t)(x % 1000U) << 30, (int64_t)(x % 777U) << 28, start);
        b = a;
        assert_int_equal(pfe_pi_step_in_range(&a, err, dt, lo, hi), pfe_pi_step(&b, err, dt, lo, hi));
        assert_int_equal(a.integral_q4, b.integral_q4);
    }
}

/* A rolling road of ROAD_SAMPLES 12 m samples: +-3 % in a 2.4 km period,
 * enough to make the controller pull, brake and coast. */
static pfe_road_t rolling_road(void)
{
    static const int32_t quarter[5] = {0, 15000, 30000, 15000, 0};
    for (uint32_t k = 0U; k < ROAD_SAMPLES; k++) {
        const uint32_t phase = (k / 10U) % 20U; /* 20 parts of 120 m */
        const int32_t g = quarter[(phase % 10U < 5U) ? (phase % 5U) : (4U - (phase % 5U))];
        road_buf[k] = (phase < 10U) ? g : -g;
    }
    const pfe_road_t r = {road_buf, ROAD_SAMPLES, 12000U};
    return r;
}

static void test_runs_of_many_blocks_are_the_steps(void **state)
{
    (void)state;
    /* 12 km in 1 m steps, 12000 of them: pfe_sim_run() sums the steps'
     * times in 32-bit blocks of 4095 steps; to the end in one call, or in
     * calls of 5000 steps, it gives what 12000 calls of pfe_sim_step()
     * give, step count, time, fuel and speed alike. */
    const pfe_platoon_t pl = platoon_of(3U, &pfe_default_drag);
    const pfe_road_t road = rolling_road();
    pfe_sim_t a;
    pfe_sim_t b;
    pfe_sim_t c;
    assert_int_equal(pfe_sim_init(&a, &pl, &pfe_default_cruise, &road, 25000, 24000, 1000U), PFE_OK);
    b = a;
    c = a;
    assert_int_equal(pfe_sim_run(&a, &road, UINT32_MAX, NULL), PFE_SIM_DONE);
    int r = PFE_SIM_RUNNING;
    while (r == PFE_SIM_RUNNING) {
        r = pfe_sim_step(&b, &road);
    }
    assert_int_equal(r, PFE_SIM_DONE);
    pfe_sim_sums_t sums;
    memset(&sums, 0, sizeof sums);
    assert_int_equal(pfe_sim_run(&c, &road, 5000U, &sums), PFE_SIM_RUNNING);
    assert_int_equal(c.steps, 5000U);
    assert_int_equal(pfe_sim_run(&c, &road, 5000U, &sums), PFE_SIM_RUNNING);
    assert_int_equal(pfe_sim_run(&c, &road, 5000U, &sums), PFE_SIM_DONE);
    assert_int_equal(a.steps, 12000U);
    assert_int_equal(b.steps, 12000U);
    assert_int_equal(c.steps, 12000U);
    assert_int_equal(a.position_mm, 12000000U);
    assert_int_equal(a.time_q16, b.time_q16);
    assert_int_equal(a.time_q16, c.time_q16);
    assert_int_equal(a.pull_time_q16, b.pull_time_q16);
    assert_int_equal(a.fuel_nl, b.fuel_nl);
    assert_int_equal(a.fuel_nl, c.fuel_nl);
    assert_int_equal(a.speed_um_s, b.speed_um_s);
    /* about 25 m/s: 480 s, summed over three blocks */
    ASSERT_GT(a.time_q16, (uint64_t)470 << 16);
    ASSERT_LT(a.time_q16, (uint64_t)500 << 16);
    ASSERT_LT(a.pull_time_q16, a.time_q16);
    ASSERT_GT(a.pull_time_q16, 0U);
}

static void test_a_bound_run_sums_the_bound_alone(void **state)
{
    (void)state;
    /* A run with a bound follows the same trajectory as one without, but
     * sums the bound's work, not its own fuel (the prediction reads only
     * the bound from it: pfe_predict.c). */
    const pfe_platoon_t pl = platoon_of(5U, &pfe_default_drag);
    const pfe_road_t road = rolling_road();
    static int16_t grade_20ppm[ROAD_SAMPLES];
    for (uint32_t k = 0U; k < ROAD_SAMPLES; k++) {
        grade_20ppm[k] = (int16_t)(road_buf[k] / 20);
    }
    pfe_sim_t nominal;
    pfe_sim_t bound;
    assert_int_equal(pfe_sim_init(&nominal, &pl, &pfe_default_cruise, &road, 25000, 25000, 12000U), PFE_OK);
    bound = nominal;
    pfe_sim_sums_t ns;
    pfe_sim_sums_t bs;
    memset(&ns, 0, sizeof ns);
    memset(&bs, 0, sizeof bs);
    bs.bound_grade_20ppm = grade_20ppm;
    bs.bound_air_q32 = pl.object.air_q32;
    bs.bound_fuel_q20 = pl.object.fuel_q20;
    assert_int_equal(pfe_sim_run(&nominal, &road, UINT32_MAX, &ns), PFE_SIM_DONE);
    assert_int_equal(pfe_sim_run(&bound, &road, UINT32_MAX, &bs), PFE_SIM_DONE);
    assert_int_equal(bound.steps, nominal.steps);
    assert_int_equal(bound.time_q16, nominal.time_q16);
    assert_int_equal(bound.speed_um_s, nominal.speed_um_s);
    assert_int_equal(bound.wheel_force_n, nominal.wheel_force_n);
    assert_int_equal(bound.fuel_nl, 0U);
    assert_int_equal(bs.aux_nl, 0U);
    ASSERT_GT(nominal.fuel_nl, 0U);
    ASSERT_GT(ns.aux_nl, 0U);
    assert_int_equal(ns.bound_nl, 0);
    /* The bound of the platoon's own drag, its own grade, over its pulling
     * steps: within the work the run's fuel left out (the kinetic energy
     * that fuel_nl books with Mj, the fuel cut's steps) and the auxiliaries,
     * 10 % on this road. */
    const int64_t without_aux = (int64_t)(nominal.fuel_nl - ns.aux_nl);
    ASSERT_GT(bs.bound_nl, without_aux - (without_aux / 10));
    ASSERT_LT(bs.bound_nl, without_aux + (without_aux / 10));
}

static void test_flat_road_needs_129_kw(void **state)
{
    (void)state;
    const pfe_platoon_t pl = platoon_of(1U, &pfe_default_drag);
    const pfe_road_t road = constant_road(0);
    pfe_sim_t sim;
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, 10000U), PFE_OK);
    int rc;
    while ((rc = pfe_sim_step(&sim, &road)) == PFE_SIM_RUNNING) {
    }
    assert_int_equal(rc, PFE_SIM_DONE);
    assert_int_equal(sim.steps, 1200);
    assert_int_equal(sim.position_mm, 12000000);
    assert_in_range(pfe_sim_speed_mm_s(&sim), 24999, 25001);
    /* 129.14 kW +- 2 % at the wheels */
    const int64_t p_w = ((int64_t)sim.wheel_force_n * pfe_sim_speed_mm_s(&sim)) / 1000;
    assert_in_range(p_w, 126558, 131721);
    /* 12 km at 25 m/s = 480 s; fuel 480 s * 9.298 mL/s = 4.463 L */
    assert_in_range(sim.time_q16, 480U * 65536U - 65536U, 480U * 65536U + 65536U);
    assert_in_range(sim.fuel_nl, 4463000000U - 5000000U, 4463000000U + 5000000U);
}

static void test_two_percent_upgrade_settles_at_73_7_kmh(void **state)
{
    (void)state;
    const pfe_platoon_t pl = platoon_of(1U, &pfe_default_drag);
    const pfe_road_t road = constant_road(20000);
    pfe_sim_t sim;
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, 10000U), PFE_OK);
    while (pfe_sim_step(&sim, &road) == PFE_SIM_RUNNING) {
    }
    /* 250 kW / v = 3.87 v^2 + 2746.8 + 7848 N at v = 20.466 m/s = 73.68 km/h;
     * 73.7 +- 0.5 km/h is 20333 .. 20611 mm/s. */
    assert_in_range(pfe_sim_speed_mm_s(&sim), 20333, 20611);
    /* At full power: Pmax / v (v of the step start, within a mm/s of the end). */
    const int32_t f_max = pfe_wheel_force_max_n(250000U, 100000U, pfe_sim_speed_mm_s(&sim));
    assert_in_range(sim.wheel_force_n, f_max - 2, f_max + 2);
}

static void test_platoon_climbs_at_its_lead_trucks_pace(void **state)
{
    (void)state;
    /* Five trucks 10 m apart: the lead truck, with 8 % less drag against
     * the followers' 31 to 35 %, holds 250 kW / v = 3.87 * 0.92 v^2 +
     * 2746.8 + 7848 N at v = 20.641 m/s (74.31 km/h); the platoon keeps its
     * formation at that speed. With the average drag (3.56 / 5 of a truck's)
     * it would climb at 21.140 m/s (76.10 km/h). */
    const pfe_platoon_t pl = platoon_of(5U, &pfe_default_drag);
    const pfe_road_t road = constant_road(20000);
    pfe_sim_t sim;
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, 10000U), PFE_OK);
    while (pfe_sim_step(&sim, &road) == PFE_SIM_RUNNING) {
    }
    assert_in_range(pfe_sim_speed_mm_s(&sim), 20641 - 5, 20641 + 5);
    /* At the limit: 1.25 MW / v less 1.04 * 3.87 v^2 = 58844 N. */
    assert_in_range(sim.wheel_force_n, 58844 - 20, 58844 + 20);
    assert_in_range(pfe_platoon_force_max_n(&pl, pfe_sim_speed_mm_s(&sim)), sim.wheel_force_n - 3,
                    sim.wheel_force_n + 3);
}

static void test_no_fuel_while_coasting_downhill(void **state)
{
    (void)state;
    const pfe_platoon_t pl = platoon_of(5U, &pfe_default_drag);
    const pfe_road_t road = constant_road(-60000);
    pfe_sim_t sim;
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, 10000U), PFE_OK);
    while (pfe_sim_step(&sim, &road) == PFE_SIM_RUNNING) {
        assert_int_equal(sim.fuel_step_nl, 0U);
        ASSERT_LT(sim.wheel_force_n, 0);
    }
    assert_int_equal(sim.fuel_nl, 0U);
    assert_in_range(pfe_sim_speed_mm_s(&sim), 24900, 25100);
}

static uint64_t hilly_fuel(uint32_t n)
{
    /* 2 km blocks: 0, +3 %, -2 %, +1 %, -4 %, +2 % */
    static const int32_t block[6] = {0, 30000, -20000, 10000, -40000, 20000};
    for (uint32_t k = 0U; k < ROAD_SAMPLES; k++) {
        road_buf[k] = block[(k * 12U) / 2000U];
    }
    const pfe_road_t road = {road_buf, ROAD_SAMPLES, 12000U};
    const pfe_platoon_t pl = platoon_of(n, &pfe_no_drag_reduction);
    pfe_sim_t sim;
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, 10000U), PFE_OK);
    while (pfe_sim_step(&sim, &road) == PFE_SIM_RUNNING) {
    }
    assert_int_equal(sim.position_mm, 12000000);
    return sim.fuel_nl;
}

static void test_n_identical_trucks_without_slipstream_burn_n_times_one(void **state)
{
    (void)state;
    const uint64_t one = hilly_fuel(1U);
    const uint64_t five = hilly_fuel(5U);
    ASSERT_GT(one, 1000000000U);    /* more than 1 L */
    /* Identical up to rounding: the force and step computations see speed in
     * whole mm/s (2.4e-5 of 21 m/s at most), so within 3e-5 of 5 x one truck. */
    const uint64_t expect = 5U * one;
    const uint64_t diff = (five > expect) ? (five - expect) : (expect - five);
    ASSERT_LE(diff, (expect * 3U) / 100000U);
}

static void test_too_steep_stalls_with_error(void **state)
{
    (void)state;
    const pfe_platoon_t pl = platoon_of(1U, &pfe_default_drag);
    const pfe_road_t road = constant_road(300000); /* 117.7 kN of grade > 100 kN traction */
    pfe_sim_t sim;
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, 10000U), PFE_OK);
    int rc;
    while ((rc = pfe_sim_step(&sim, &road)) == PFE_SIM_RUNNING) {
    }
    assert_int_equal(rc, PFE_ESTALL);
    ASSERT_LT(sim.position_mm, 12000000U);
    assert_int_equal(pfe_sim_step(&sim, &road), PFE_ESTALL);
}

static void test_sim_arguments_and_last_short_step(void **state)
{
    (void)state;
    const pfe_platoon_t pl = platoon_of(1U, &pfe_default_drag);
    static const int32_t short_grades[3] = {0, 0, 0};
    const pfe_road_t road = {short_grades, 3U, 7000U}; /* 21 m */
    pfe_sim_t sim;
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, 10000U), PFE_OK);
    assert_int_equal(pfe_sim_step(&sim, &road), PFE_SIM_RUNNING);
    assert_int_equal(pfe_sim_step(&sim, &road), PFE_SIM_RUNNING);
    assert_int_equal(pfe_sim_step(&sim, &road), PFE_SIM_RUNNING);
    assert_int_equal(sim.position_mm, 21000);
    assert_int_equal(pfe_sim_step(&sim, &road), PFE_SIM_DONE);
    assert_int_equal(sim.steps, 3);

    const pfe_road_t empty = {short_grades, 0U, 7000U};
    const pfe_road_t no_spacing = {short_grades, 3U, 0U};
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &empty, 25000, 25000, 10000U), PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &no_spacing, 25000, 25000, 10000U), PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, PFE_SIM_STEP_MAX_MM + 1U), PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, 99U), PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 999, 25000, 10000U), PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 70001, 10000U), PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, NULL, &pfe_default_cruise, &road, 25000, 25000, 10000U), PFE_EINVAL);
    assert_int_equal(pfe_sim_init(&sim, &pl, NULL, &road, 25000, 25000, 10000U), PFE_EINVAL);
    /* pfe_sim_run() is the same as that many pfe_sim_step(), result by result. */
    pfe_sim_t a, b;
    assert_int_equal(pfe_sim_init(&a, &pl, &pfe_default_cruise, &road, 25000, 20000, 5000U), PFE_OK);
    b = a;
    pfe_sim_sums_t sums;
    memset(&sums, 0, sizeof sums);
    assert_int_equal(pfe_sim_run(&a, &road, 2U, &sums), PFE_SIM_RUNNING);
    assert_int_equal(pfe_sim_step(&b, &road), PFE_SIM_RUNNING);
    assert_int_equal(pfe_sim_step(&b, &road), PFE_SIM_RUNNING);
    assert_int_equal(a.position_mm, b.position_mm);
    assert_int_equal(a.speed_um_s, b.speed_um_s);
    assert_int_equal(a.fuel_nl, b.fuel_nl);
    assert_int_equal(pfe_sim_run(&a, &road, 100U, &sums), PFE_SIM_DONE);
    assert_int_equal(a.steps, 5);
    /* The auxiliaries' part: Paux over the whole time (fuel flows in every
     * step here), at the platoon's nL per mJ: within a nL of rounding a step. */
    const uint64_t aux_expected = (a.time_q16 * ((uint64_t)pl.object.power_aux_w * 1000U) *
                                   (uint64_t)pl.object.fuel_q20) >> 36;
    ASSERT_LT(sums.aux_nl, a.fuel_nl);
    assert_in_range(sums.aux_nl, aux_expected - 5U, aux_expected + 5U);
}

static void test_bound_sums_of_a_steady_run(void **state)
{
    (void)state;
    /* One default truck holding 25 m/s on a flat 21 m road, a bound with
     * the truck's own drag: its work is (2418.75 N of air + 2746.8 N of
     * rolling) * 21 m = 108476.55 J, its fuel at 1 / (0.40 * 35800 J/mL)
     * 7575178.1 nL (within the coefficients' 2^-20 nL/mJ steps, 1e-5). */
    const pfe_platoon_t pl = platoon_of(1U, &pfe_no_drag_reduction);
    static const int32_t flat[3] = {0, 0, 0};
    static const int16_t flat_20ppm[3] = {0, 0, 0};
    const pfe_road_t road = {flat, 3U, 7000U};
    pfe_sim_t sim;
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, 7000U), PFE_OK);
    pfe_sim_sums_t sums;
    memset(&sums, 0, sizeof sums);
    sums.bound_grade_20ppm = flat_20ppm;
    sums.bound_air_q32 = pl.object.air_q32;
    sums.bound_fuel_q20 = pl.object.fuel_q20;
    assert_int_equal(pfe_sim_run(&sim, &road, UINT32_MAX, &sums), PFE_SIM_DONE);
    assert_int_equal(sim.steps, 3U);
    assert_int_equal(sums.bound_ds_mm, 21000U);
    /* v^2 / 2 = 312500000 (mm/s)^2 times 21000 mm */
    assert_int_equal(sums.bound_v2_ds, 6562500000000U);
    assert_int_equal(sums.bound_grade_ds, 0);
    assert_in_range(sums.bound_nl, 7575178 - 76, 7575178 + 76);
    /* A grade of 20 ppm units (+1 %) on the bound's window: 40000 kg *
     * 9.81 * 0.01 * 21 m = 82404 J more, 5754469.3 nL at that efficiency. */
    static const int16_t up_20ppm[3] = {500, 500, 500};
    assert_int_equal(pfe_sim_init(&sim, &pl, &pfe_default_cruise, &road, 25000, 25000, 7000U), PFE_OK);
    memset(&sums, 0, sizeof sums);
    sums.bound_grade_20ppm = up_20ppm;
    sums.bound_air_q32 = pl.object.air_q32;
    sums.bound_fuel_q20 = pl.object.fuel_q20;
    assert_int_equal(pfe_sim_run(&sim, &road, UINT32_MAX, &sums), PFE_SIM_DONE);
    assert_int_equal(sums.bound_grade_ds, 10500000);
    assert_in_range(sums.bound_nl, 7575178 + 5754469 - 133, 7575178 + 5754469 + 133);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pi_proportional_and_integral),
        cmocka_unit_test(test_pi_saturates_without_windup),
        cmocka_unit_test(test_pi_integral_rate_limit),
        cmocka_unit_test(test_pi_in_range_is_the_checked_step),
        cmocka_unit_test(test_runs_of_many_blocks_are_the_steps),
        cmocka_unit_test(test_a_bound_run_sums_the_bound_alone),
        cmocka_unit_test(test_flat_road_needs_129_kw),
        cmocka_unit_test(test_two_percent_upgrade_settles_at_73_7_kmh),
        cmocka_unit_test(test_platoon_climbs_at_its_lead_trucks_pace),
        cmocka_unit_test(test_no_fuel_while_coasting_downhill),
        cmocka_unit_test(test_n_identical_trucks_without_slipstream_burn_n_times_one),
        cmocka_unit_test(test_too_steep_stalls_with_error),
        cmocka_unit_test(test_sim_arguments_and_last_short_step),
        cmocka_unit_test(test_bound_sums_of_a_steady_run),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
