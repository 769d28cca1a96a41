/*
 * m4_bench.c - instruction counts of the model on the Cortex-M4.
 *
 * Runs on QEMU's mps2-an386 with -icount shift=0, where the SysTick counter
 * counts instructions (hal/mps2/icount.h, 40 instructions per tick). Prints
 * `bench: <name> <value> <unit>` lines:
 *   est_step_n5_mean / _max   one 10 ms estimator step, 5 trucks, on a drive
 *   est_step_n32_mean / _max  the same with the largest platoon
 *   sim_12km_hilly_n5         the object model over the 12 km hilly road,
 *                             10 m steps, including the cruise control
 *   sim_step_mean             the same per step
 *   stack_used                deepest stack seen (painted-stack method)
 * Means are over many steps, so their resolution is far below the 40
 * instructions of one reading; a max is a single reading (+-40).
 */
#include <stdint.h>

#include "firmware/pfe_calib.h"
#include "firmware/pfe_estimator.h"
#include "firmware/pfe_fixed.h"
#include "firmware/pfe_platoon.h"
#include "firmware/pfe_selfcheck.h"
#include "firmware/pfe_sim.h"
#include "hal/mps2/icount.h"
#include "hal/mps2/semihost.h"
#include "hal/mps2/startup.h"

extern const int32_t road_hilly_grade_ppm[];
extern const uint32_t road_hilly_n_samples;
extern const uint32_t road_hilly_spacing_mm;

#define MEASURED_TICKS 2000U

/* Every result is folded in and printed, so that no computation measured
 * here can be optimised away. */
static uint64_t s_sink;

static void sink(uint64_t value)
{
    s_sink = (s_sink ^ value) * 1099511628211ULL;
}

static pfe_platoon_t s_platoon;
static pfe_estimator_t s_est;

static int setup(uint32_t n)
{
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, n, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    if ((pfe_platoon_init(&s_platoon, &cfg) != PFE_OK) ||
        (pfe_estimator_init(&s_est, &s_platoon) != PFE_OK)) {
        return -1;
    }
    return 0;
}

/* A drive that changes every input: speed ramps 20 -> 26 m/s and back,
 * grade sweeps -4 % .. +4 %, a new CCVS1 sample every 10th tick. */
static pfe_est_input_t drive_input(uint32_t tick)
{
    const int32_t phase = (int32_t)(tick % 1200U);
    const int32_t ramp = (phase < 600) ? phase : (1200 - phase);
    const int32_t grade = (int32_t)((tick * 37U) % 80001U) - 40000;
    const pfe_est_input_t in = {pfe_selfcheck_spn84_mm_s(20000 + (ramp * 10)), true,
                                (tick % 10U) == 0U, grade, true};
    return in;
}

static int bench_estimator(uint32_t n, const char *mean_name, const char *max_name)
{
    if (setup(n) != 0) {
        return -1;
    }
    uint32_t tick = 0U;
    for (; tick < 100U; tick++) { /* warm up the speed filter */
        const pfe_est_input_t in = drive_input(tick);
        (void)pfe_estimator_step(&s_est, &in);
    }
    uint64_t total = 0U;
    uint64_t worst = 0U;
    for (uint32_t k = 0U; k < MEASURED_TICKS; k++, tick++) {
        const pfe_est_input_t in = drive_input(tick);
        const uint64_t t0 = hal_mps2_icount_now();
        const pfe_est_output_t *out = pfe_estimator_step(&s_est, &in);
        const uint64_t t1 = hal_mps2_icount_now();
        if ((out->flags & PFE_EST_VALID) == 0U) {
            return -1;
        }
        sink(out->fuel_rate_nl_s);
        for (uint32_t i = 0U; i < n; i++) {
            sink(out->pos_fuel_rate_nl_s[i]);
        }
        const uint64_t d = t1 - t0;
        const uint64_t insns = (d > HAL_MPS2_ICOUNT_OVERHEAD_INSNS) ? (d - HAL_MPS2_ICOUNT_OVERHEAD_INSNS) : 0U;
        total += insns;
        worst = (insns > worst) ? insns : worst;
    }
    sink(pfe_estimator_fuel_used_ul(&s_est, PFE_EST_PLATOON));
    hal_mps2_write_bench(mean_name, total / MEASURED_TICKS, "insn");
    hal_mps2_write_bench(max_name, worst, "insn");
    return 0;
}

static int bench_sim(void)
{
    if (setup(5U) != 0) {
        return -1;
    }
    const pfe_road_t road = {road_hilly_grade_ppm, road_hilly_n_samples, road_hilly_spacing_mm};
    pfe_sim_t sim;
    if (pfe_sim_init(&sim, &s_platoon, &pfe_default_cruise, &road, 25000, 25000, 10000U) != PFE_OK) {
        return -1;
    }
    const uint64_t t0 = hal_mps2_icount_now();
    int rc;
    while ((rc = pfe_sim_step(&sim, &road)) == PFE_SIM_RUNNING) {
    }
    const uint64_t t1 = hal_mps2_icount_now();
    if ((rc != PFE_SIM_DONE) || (sim.steps == 0U)) {
        return -1;
    }
    const uint64_t insns = t1 - t0 - HAL_MPS2_ICOUNT_OVERHEAD_INSNS;
    hal_mps2_write_bench("sim_12km_hilly_n5", insns, "insn");
    hal_mps2_write_bench("sim_steps", sim.steps, "steps");
    hal_mps2_write_bench("sim_step_mean", insns / sim.steps, "insn");
    hal_mps2_write_bench("sim_12km_hilly_n5_fuel", sim.fuel_nl, "nL");
    sink(sim.time_q16);
    return 0;
}

int main(void)
{
    hal_mps2_icount_start();
    if ((bench_estimator(5U, "est_step_n5_mean", "est_step_n5_max") != 0) ||
        (bench_estimator(PFE_MAX_VEHICLES, "est_step_n32_mean", "est_step_n32_max") != 0) ||
        (bench_sim() != 0)) {
        hal_mps2_write_str("bench: failed\n");
        return 1;
    }
    hal_mps2_write_bench("stack_used", hal_mps2_stack_used_bytes(), "bytes");
    hal_mps2_write_str("m4_bench: results digest ");
    hal_mps2_write_hex64(s_sink);
    hal_mps2_write_str("\n");
    return 0;
}
