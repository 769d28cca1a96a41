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
 *   ecu_tick_mean / _max      one 10 ms ECU tick with its decode and encode
 *                             (pfe_ecu_receive of the tick's frames, then
 *                             pfe_ecu_tick), CCVS1 every 10th tick, SSI every tick
 *   ecu_tick_burst            a tick with a full receive queue: every input
 *                             message and requests at once
 *   ecu_tick_burst_max        the worst tick of bursts of every mix (platoon
 *                             configurations up to 32 trucks, preview headers
 *                             and data, requests, floods of PGNs the module
 *                             does not read, and random mixes of them), each
 *                             a full receive queue while a prediction runs,
 *                             the burst's tick and the five after it
 *   predict_whole_n5          one whole prediction with its bounds (three runs
 *                             of the object model) over the 12 km hilly road
 *                             as a grade preview, 5 trucks, as the module
 *                             makes one every second
 *   predict_first_n5          the first over a new preview, which prepares it
 *                             first (copy, grade windows)
 *   ecu_tick_predicting_max   the worst ECU tick while the module receives that
 *                             preview and predicts over it, ticks as above
 *   predict_ticks             ticks from the preview's last frame to the
 *                             first prediction published
 *   identify_step_mean / _max one identification step (pfe_identify), one per
 *                             LFE1 frame, on a 12 t truck's drive (speed
 *                             ramps 15 -> 25 m/s and back at 0.3 m/s^2 over
 *                             the hilly road, the engine's fuel rate from the
 *                             integer model); the max is a window's end with
 *                             a mass update (its 64-bit division
 *                             normalised to a 32-bit one)
 *   identify_bench_mass       the mass identified there, kg (seed 40 t)
 *   ecu_real_bus_inputs_mean / _max  what a steady tick spends on a truck's
 *                             bus on sender arbitration, plausibility and
 *                             identification (two senders of CCVS1 and LFE1)
 *   est_step_per_truck        each truck beyond the fifth: the n32 and n5
 *                             totals' difference over 27 trucks and the ticks
 *   stack_used                deepest stack seen (painted-stack method)
 * After the results digest (so that it compares with earlier builds):
 *   est_step_n1_mean / _max   the estimator step with one truck
 *   est_step_n5_mixed_mean / _max  five trucks of different masses, so that
 *                             no position reuses the one before it's rate
 *   part_*                    the steps' parts timed alone (docs/bench.md,
 *                             the floor analysis), with a digest of their own
 * Means are over many steps, so their resolution is far below the 40
 * instructions of one reading; a max is a single reading (+-40).
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "firmware/pfe_calib.h"
#include "firmware/pfe_codec.h"
#include "firmware/pfe_ecu.h"
#include "firmware/pfe_estimator.h"
#include "firmware/pfe_fixed.h"
#include "firmware/pfe_identify.h"
#include "firmware/pfe_input.h"
#include "firmware/pfe_platoon.h"
#include "firmware/pfe_predict.h"
#include "firmware/pfe_selfcheck.h"
#include "firmware/pfe_sim.h"
#include "firmware/pfe_vehicle.h"
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

/* Trucks of different masses, for a platoon in which no position has the
 * fuel model of the one before it (est_step_n5_mixed). */
static pfe_vehicle_calib_t s_mixed[PFE_MAX_VEHICLES];
static bool s_use_mixed;

static int setup(uint32_t n)
{
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, n, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    for (uint32_t i = 0U; s_use_mixed && (i < n); i++) {
        s_mixed[i] = pfe_default_vehicle;
        s_mixed[i].mass_kg = 40000U - (1000U * i);
        cfg.vehicle[i] = &s_mixed[i];
    }
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

/* The total instructions of the last bench_estimator() run, for the
 * per-truck increment (est_step_per_truck). */
static uint64_t s_est_total;

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
    s_est_total = total;
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
    const int rc = pfe_sim_run(&sim, &road, UINT32_MAX, NULL);
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

#define IDENTIFY_STEPS 6000U

static pfe_identify_t s_id;

static int bench_identify(void)
{
    pfe_vehicle_calib_t truck = pfe_default_vehicle;
    truck.mass_kg = 12000U;
    pfe_vehicle_t veh;
    if ((pfe_vehicle_init(&veh, &truck, &pfe_default_env, 0U) != PFE_OK) ||
        (pfe_identify_init(&s_id, &pfe_default_vehicle, &pfe_default_env) != PFE_OK)) {
        return -1;
    }
    int32_t v = 15000;
    int32_t a = 300000;
    uint64_t pos_mm = 0U;
    uint64_t total = 0U;
    uint64_t worst = 0U;
    for (uint32_t k = 0U; k < IDENTIFY_STEPS; k++) {
        const uint32_t i = (uint32_t)((pos_mm / road_hilly_spacing_mm) % road_hilly_n_samples);
        const int32_t grade = road_hilly_grade_ppm[i];
        pfe_grade_accel_t ga;
        pfe_grade_accel(grade, pfe_default_env.gravity_um_s2, &ga);
        const int32_t f = pfe_vehicle_fuel_force_n(&veh, v, a, &ga);
        const pfe_identify_sample_t smp = {
            100000ULL * k, v, grade, pfe_fuel_rate_nl_s(f, v, veh.power_aux_w, veh.fuel_q20),
            true, true, true, false};
        const uint64_t t0 = hal_mps2_icount_now();
        (void)pfe_identify_step(&s_id, &smp);
        const uint64_t t1 = hal_mps2_icount_now();
        const uint64_t d = t1 - t0;
        const uint64_t insns = (d > HAL_MPS2_ICOUNT_OVERHEAD_INSNS) ? (d - HAL_MPS2_ICOUNT_OVERHEAD_INSNS) : 0U;
        total += insns;
        worst = (insns > worst) ? insns : worst;
        pos_mm += (uint64_t)v * 100U / 1000U;
        v += a / 10000; /* a [um/s^2] over 100 ms, in mm/s */
        a = (v >= 25000) ? -300000 : ((v <= 15000) ? 300000 : a);
    }
    if (pfe_identify_counters(&s_id)->mass_updates == 0U) {
        return -1;
    }
    sink(pfe_identify_mass_kg(&s_id));
    sink(pfe_identify_aux_power_w(&s_id));
    hal_mps2_write_bench("identify_step_mean", total / IDENTIFY_STEPS, "insn");
    hal_mps2_write_bench("identify_step_max", worst, "insn");
    hal_mps2_write_bench("identify_bench_mass", pfe_identify_mass_kg(&s_id), "kg");
    return 0;
}

/* The real-bus work a steady tick adds (firmware/pfe_input.h,
 * pfe_identify.h), as the ECU does it on a truck's bus: every tick the SSI
 * pitch arbitrated and checked and the five inputs aged; every 10th tick
 * the engine's CCVS1 and LFE1 and the cab's "not available" CCVS1 and LFE1
 * arbitrated and checked, and one identification step. Mean and worst per
 * tick over INPUT_TICKS ticks. */
#define INPUT_TICKS 3000U
static pfe_input_t s_in[PFE_IN_COUNT];

static uint64_t input_tick(uint32_t tick, uint64_t now_us)
{
    const pfe_est_input_t in = drive_input(tick);
    const uint64_t t0 = hal_mps2_icount_now();
    (void)pfe_input_take(&s_in[PFE_IN_GRADE], 0x00U, PFE_SIG_VALID, in.grade_ppm, now_us);
    if ((tick % 10U) == 0U) {
        (void)pfe_input_take(&s_in[PFE_IN_SPEED], 0x00U, PFE_SIG_VALID, in.speed_mm_s, now_us);
        (void)pfe_input_take(&s_in[PFE_IN_SPEED], 0x31U, PFE_SIG_NOT_AVAILABLE, 0, now_us + 5000U);
        const uint32_t fuel = 8000000U + ((tick * 7919U) % 4000000U);
        (void)pfe_input_take(&s_in[PFE_IN_ENGINE_FUEL], 0x00U, PFE_SIG_VALID, (int32_t)fuel, now_us);
        (void)pfe_input_take(&s_in[PFE_IN_ENGINE_FUEL], 0x31U, PFE_SIG_NOT_AVAILABLE, 0, now_us + 5000U);
        const pfe_identify_sample_t smp = {now_us, in.speed_mm_s, in.grade_ppm, fuel,
                                           true, true, true, false};
        (void)pfe_identify_step(&s_id, &smp);
    }
    for (uint32_t k = 0U; k < (uint32_t)PFE_IN_COUNT; k++) {
        (void)pfe_input_age(&s_in[k], now_us + 5000U);
    }
    const uint64_t d = hal_mps2_icount_now() - t0;
    return (d > HAL_MPS2_ICOUNT_OVERHEAD_INSNS) ? (d - HAL_MPS2_ICOUNT_OVERHEAD_INSNS) : 0U;
}

static int bench_inputs(void)
{
    for (uint32_t k = 0U; k < (uint32_t)PFE_IN_COUNT; k++) {
        pfe_input_init(&s_in[k], (pfe_input_kind_t)k, PFE_INPUT_NO_SOURCE);
    }
    if (pfe_identify_init(&s_id, &pfe_default_vehicle, &pfe_default_env) != PFE_OK) {
        return -1;
    }
    uint64_t total = 0U;
    uint64_t worst = 0U;
    uint64_t now = 1000000U;
    for (uint32_t tick = 0U; tick < INPUT_TICKS; tick++, now += PFE_ECU_TICK_US) {
        const uint64_t insns = input_tick(tick, now);
        total += insns;
        worst = (insns > worst) ? insns : worst;
    }
    if ((s_in[PFE_IN_SPEED].state != PFE_SIG_VALID) || (s_in[PFE_IN_SPEED].rejected != 0U)) {
        return -1; /* the measured path is the steady one: nothing rejected */
    }
    sink(pfe_identify_mass_kg(&s_id));
    hal_mps2_write_bench("ecu_real_bus_inputs_mean", total / INPUT_TICKS, "insn");
    hal_mps2_write_bench("ecu_real_bus_inputs_max", worst, "insn");
    return 0;
}

static pfe_ecu_t s_ecu;

static uint64_t ecu_tick(uint64_t now_us, const pfe_can_frame_t *rx, uint32_t n_rx)
{
    pfe_can_frame_t tx[PFE_ECU_TX_MAX];
    const uint64_t t0 = hal_mps2_icount_now();
    for (uint32_t k = 0U; k < n_rx; k++) {
        pfe_ecu_receive(&s_ecu, &rx[k], now_us);
    }
    const uint32_t n = pfe_ecu_tick(&s_ecu, now_us, tx, PFE_ECU_TX_MAX);
    const uint64_t t1 = hal_mps2_icount_now();
    for (uint32_t k = 0U; k < n; k++) {
        sink(tx[k].id);
        sink(tx[k].data[0] | ((uint64_t)tx[k].data[1] << 8));
    }
    return t1 - t0 - HAL_MPS2_ICOUNT_OVERHEAD_INSNS;
}

static int bench_ecu(void)
{
    const pfe_ecu_config_t cfg = {
        .preferred_address = PFE_ECU_DEFAULT_ADDRESS,
        .name = 0x80A0000000000001ULL,
        .save_interval_ms = 10000U,
        .vehicle = &pfe_default_vehicle,
        .env = &pfe_default_env,
        .drag = &pfe_default_drag,
        .default_vehicles = 5U,
        .default_position = 0U,
        .default_gap_mm = 10000U,
        .cruise = &pfe_default_cruise,
        .default_set_speed_mm_s = 25000,
    };
    uint64_t now = 1000000U;
    if (pfe_ecu_init(&s_ecu, &cfg, NULL, -1, now) != PFE_OK) {
        return -1;
    }
    uint64_t total = 0U;
    uint64_t worst = 0U;
    uint32_t measured = 0U;
    for (uint32_t tick = 0U; tick < 1100U; tick++, now += PFE_ECU_TICK_US) {
        const pfe_est_input_t in = drive_input(tick);
        pfe_can_frame_t rx[2];
        uint32_t n_rx = 0U;
        const pfe_msg_ssi_t ssi = {{in.grade_ppm / 20, PFE_SIG_VALID}, {0, PFE_SIG_VALID},
                                   {0U, PFE_SIG_VALID}}; /* about the same pitch in udeg */
        (void)pfe_codec_encode_ssi(&rx[n_rx++], &ssi, 0x00U);
        if (in.speed_fresh) {
            const pfe_msg_ccvs1_t v = {{in.speed_mm_s, PFE_SIG_VALID}};
            (void)pfe_codec_encode_ccvs1(&rx[n_rx++], &v, 0x00U);
        }
        const uint64_t insns = ecu_tick(now, rx, n_rx);
        if (tick >= 100U) { /* after the claim and the warm-up */
            total += insns;
            worst = (insns > worst) ? insns : worst;
            measured++;
        }
    }
    hal_mps2_write_bench("ecu_tick_mean", total / measured, "insn");
    hal_mps2_write_bench("ecu_tick_max", worst, "insn");
    /* Everything at once: a full receive queue of CCVS1, SSI, requests for each
     * output and the platoon configuration (which rebuilds the model). */
    static pfe_can_frame_t burst[PFE_ECU_RX_QUEUE_LEN];
    for (uint32_t k = 0U; k < PFE_ECU_RX_QUEUE_LEN; k++) {
        const uint32_t kind = k % 4U;
        if (kind == 0U) {
            const pfe_msg_ccvs1_t v = {{25000, PFE_SIG_VALID}};
            (void)pfe_codec_encode_ccvs1(&burst[k], &v, 0x00U);
        } else if (kind == 1U) {
            const pfe_msg_ssi_t ssi = {{1000, PFE_SIG_VALID}, {0, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}};
            (void)pfe_codec_encode_ssi(&burst[k], &ssi, 0x00U);
        } else if (kind == 2U) {
            (void)pfe_codec_encode_request(&burst[k], PFE_PGN_HRLFC + ((k / 4U) % 2U),
                                           PFE_J1939_ADDR_GLOBAL, 0x00U);
        } else {
            const pfe_msg_platoon_config_t pc = {{5U + ((k / 4U) % 2U), PFE_SIG_VALID},
                                                 {1U, PFE_SIG_VALID}, {10000U, PFE_SIG_VALID},
                                                 {0U, PFE_SIG_NOT_AVAILABLE}, {25000, PFE_SIG_VALID}};
            (void)pfe_codec_encode_platoon_config(&burst[k], &pc, 0x00U);
        }
    }
    const uint64_t burst_insns = ecu_tick(now, burst, PFE_ECU_RX_QUEUE_LEN);
    hal_mps2_write_bench("ecu_tick_burst", burst_insns, "insn");
    return 0;
}

/* Frame k of the hilly road as one grade preview (20 ppm resolution):
 * 0 the header, then data frames; false past the last. */
static bool preview_frame(uint32_t k, pfe_can_frame_t *out)
{
    const uint32_t n = (road_hilly_n_samples < PFE_PREVIEW_MAX_SAMPLES) ? road_hilly_n_samples
                                                                        : PFE_PREVIEW_MAX_SAMPLES;
    const uint32_t n_data = (n + PFE_PREVIEW_SAMPLES_PER_FRAME - 1U) / PFE_PREVIEW_SAMPLES_PER_FRAME;
    if (k > n_data) {
        return false;
    }
    pfe_msg_grade_preview_t m;
    for (uint32_t i = 0U; i < (sizeof m); i++) {
        ((uint8_t *)&m)[i] = 0U;
    }
    m.preview_id.value = 5U;
    if (k == 0U) {
        m.frame_type.value = PFE_PREVIEW_FRAME_HEADER;
        m.sample_count.value = n;
        m.spacing_m.value = road_hilly_spacing_mm / 1000U;
    } else {
        const uint32_t first = (k - 1U) * PFE_PREVIEW_SAMPLES_PER_FRAME;
        m.frame_type.value = PFE_PREVIEW_FRAME_DATA;
        m.first_index.value = first;
        for (uint32_t j = 0U; j < PFE_PREVIEW_SAMPLES_PER_FRAME; j++) {
            const bool in = (first + j) < n;
            m.grade_ppm[j].value = in ? road_hilly_grade_ppm[first + j] : 0;
            m.grade_ppm[j].state = in ? PFE_SIG_VALID : PFE_SIG_NOT_AVAILABLE;
        }
    }
    return pfe_codec_encode_grade_preview(out, &m, 0x00U) >= 0;
}

static int bench_predict(void)
{
    /* One whole prediction, in one go: every call of pfe_predict_run(). The
     * ECU's own preview and predictor serve as storage before it starts. */
    pfe_preview_t *pv = &s_ecu.preview_buf;
    pfe_predict_t *pred = &s_ecu.predict;
    pfe_preview_init(pv);
    pfe_can_frame_t f;
    for (uint32_t k = 0U; preview_frame(k, &f); k++) {
        (void)pfe_preview_push(pv, &f);
    }
    if ((setup(5U) != 0) || (pv->phase != PFE_PREVIEW_READY)) {
        return -1;
    }
    pfe_predict_init(pred);
    const uint64_t t0 = hal_mps2_icount_now();
    if (pfe_predict_start(pred, pv, 1U, 0U, &s_platoon, &pfe_default_drag, &pfe_default_cruise,
                          25000, 25000) != PFE_OK) {
        return -1;
    }
    while (pfe_predict_run(pred, pv, UINT32_MAX) != PFE_PREDICT_DONE) {
        if (pred->phase == PFE_PREDICT_IDLE) {
            return -1;
        }
    }
    const uint64_t insns = hal_mps2_icount_now() - t0 - HAL_MPS2_ICOUNT_OVERHEAD_INSNS;
    const pfe_predict_result_t whole = *pfe_predict_result(pred);
    const pfe_predict_result_t *r = &whole;
    /* The next prediction over the same preview: already prepared. */
    const uint64_t t1 = hal_mps2_icount_now();
    if (pfe_predict_start(pred, pv, 1U, 0U, &s_platoon, &pfe_default_drag, &pfe_default_cruise,
                          25000, 25000) != PFE_OK) {
        return -1;
    }
    while (pfe_predict_run(pred, pv, UINT32_MAX) != PFE_PREDICT_DONE) {
        if (pred->phase == PFE_PREDICT_IDLE) {
            return -1;
        }
    }
    const uint64_t again = hal_mps2_icount_now() - t1 - HAL_MPS2_ICOUNT_OVERHEAD_INSNS;
    if (pfe_predict_result(pred)->fuel_ul != whole.fuel_ul) {
        return -1;
    }
    hal_mps2_write_bench("predict_whole_n5", again, "insn");
    hal_mps2_write_bench("predict_first_n5", insns, "insn");
    hal_mps2_write_bench("predict_hilly_n5_fuel", r->fuel_ul, "uL");
    hal_mps2_write_bench("predict_hilly_n5_lower", r->fuel_lower_ul, "uL");
    hal_mps2_write_bench("predict_hilly_n5_upper", r->fuel_upper_ul, "uL");
    hal_mps2_write_bench("predict_hilly_n5_time", r->time_ms, "ms");

    /* The ECU receiving the preview (ten frames a tick with the drive's) and
     * predicting over it, 5 trucks. */
    const pfe_ecu_config_t cfg = {
        .preferred_address = PFE_ECU_DEFAULT_ADDRESS,
        .name = 0x80A0000000000001ULL,
        .save_interval_ms = 10000U,
        .vehicle = &pfe_default_vehicle,
        .env = &pfe_default_env,
        .drag = &pfe_default_drag,
        .default_vehicles = 5U,
        .default_position = 0U,
        .default_gap_mm = 10000U,
        .cruise = &pfe_default_cruise,
        .default_set_speed_mm_s = 25000,
    };
    uint64_t now = 1000000U;
    if (pfe_ecu_init(&s_ecu, &cfg, NULL, -1, now) != PFE_OK) {
        return -1;
    }
    uint64_t worst = 0U;
    uint32_t sent_frames = 0U, done_at = 0U, last_frame_at = 0U;
    bool more = true;
    for (uint32_t tick = 0U; tick < 700U; tick++, now += PFE_ECU_TICK_US) {
        const pfe_est_input_t in = drive_input(tick);
        pfe_can_frame_t rx[12];
        uint32_t n_rx = 0U;
        const pfe_msg_ssi_t ssi = {{in.grade_ppm / 20, PFE_SIG_VALID}, {0, PFE_SIG_VALID},
                                   {0U, PFE_SIG_VALID}};
        (void)pfe_codec_encode_ssi(&rx[n_rx++], &ssi, 0x00U);
        if (in.speed_fresh) {
            const pfe_msg_ccvs1_t v = {{in.speed_mm_s, PFE_SIG_VALID}};
            (void)pfe_codec_encode_ccvs1(&rx[n_rx++], &v, 0x00U);
        }
        for (uint32_t j = 0U; (j < 10U) && (tick >= 100U) && more; j++) {
            more = preview_frame(sent_frames, &rx[n_rx]);
            if (more) {
                n_rx++;
                sent_frames++;
                last_frame_at = tick;
            }
        }
        const uint64_t insns = ecu_tick(now, rx, n_rx);
        if (tick >= 100U) {
            worst = (insns > worst) ? insns : worst;
        }
        if ((done_at == 0U) && pfe_predict_result(&s_ecu.predict)->valid) {
            done_at = tick;
        }
    }
    if (done_at == 0U) {
        return -1;
    }
    hal_mps2_write_bench("ecu_tick_predicting_max", worst, "insn");
    hal_mps2_write_bench("predict_ticks", done_at - last_frame_at, "ticks");
    sink(r->fuel_ul);
    return 0;
}

/* Frame `kind` of a burst: 0 CCVS1, 1 SSI, 2 a request for an output, 3 a
 * platoon configuration (2 .. 32 trucks, a new one each time), 4 a preview
 * header, 5 a preview data frame, 6 a PGN the module does not read, 7 VDS,
 * 8 CVW (a new mass each time), 9 another node's LFE1, 10 its HRLFC; from
 * two senders. */
#define BURST_KINDS 11U
static void burst_frame(uint32_t kind, uint32_t k, pfe_can_frame_t *f)
{
    if (kind == 0U) {
        const pfe_msg_ccvs1_t v = {{25000, PFE_SIG_VALID}};
        (void)pfe_codec_encode_ccvs1(f, &v, 0x00U);
    } else if (kind == 1U) {
        const pfe_msg_ssi_t ssi = {{1000, PFE_SIG_VALID}, {0, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}};
        (void)pfe_codec_encode_ssi(f, &ssi, 0x00U);
    } else if (kind == 2U) {
        static const uint32_t pgn[5] = {PFE_PGN_LFE1, PFE_PGN_PLATOON_FUEL, PFE_PGN_HRLFC,
                                        PFE_PGN_FUEL_PREDICTION, PFE_PGN_STATUS};
        (void)pfe_codec_encode_request(f, pgn[k % 5U], PFE_J1939_ADDR_GLOBAL, 0x00U);
    } else if (kind == 3U) {
        const uint32_t n = ((k % 2U) == 0U) ? PFE_MAX_VEHICLES : (2U + (k % 30U));
        const pfe_msg_platoon_config_t pc = {{n, PFE_SIG_VALID}, {k % n, PFE_SIG_VALID},
                                             {8000U + (k * 100U), PFE_SIG_VALID},
                                             {0U, PFE_SIG_NOT_AVAILABLE}, {25000, PFE_SIG_VALID}};
        (void)pfe_codec_encode_platoon_config(f, &pc, 0x00U);
    } else if ((kind == 4U) || (kind == 5U)) {
        (void)preview_frame((kind == 4U) ? 0U : (1U + (k % 8U)), f);
    } else if (kind == 7U) {
        const pfe_msg_vds_t v = {{90000U, PFE_SIG_VALID}, {25000, PFE_SIG_VALID},
                                 {(int32_t)(k % 3000U), PFE_SIG_VALID}, {100000 + (int32_t)(k * 10U), PFE_SIG_VALID}};
        (void)pfe_codec_encode_vds(f, &v, (uint8_t)(k % 2U));
    } else if (kind == 8U) {
        const pfe_msg_cvw_t w = {{20000U + ((k % 200U) * 100U), PFE_SIG_VALID},
                                 {30000U + ((k % 200U) * 100U), PFE_SIG_VALID}};
        (void)pfe_codec_encode_cvw(f, &w, (uint8_t)(k % 2U));
    } else if (kind == 9U) {
        const pfe_msg_lfe1_t l = {{9000000U + k, PFE_SIG_VALID}};
        (void)pfe_codec_encode_lfe1(f, &l, (uint8_t)(k % 2U));
    } else if (kind == 10U) {
        const pfe_msg_hrlfc_t h = {{0U, PFE_SIG_NOT_AVAILABLE}, {1000000U + k, PFE_SIG_VALID}};
        (void)pfe_codec_encode_hrlfc(f, &h, (uint8_t)(k % 2U));
    } else {
        /* EEC1 (PGN 61444), read by nobody here */
        f->id = PFE_CAN_EFF_FLAG | 0x0CF00400UL;
        f->dlc = 8U;
        for (uint32_t j = 0U; j < 8U; j++) {
            f->data[j] = (uint8_t)(k + j);
        }
    }
}

static int bench_burst(void)
{
    const pfe_ecu_config_t cfg = {
        .preferred_address = PFE_ECU_DEFAULT_ADDRESS,
        .name = 0x80A0000000000001ULL,
        .save_interval_ms = 10000U,
        .vehicle = &pfe_default_vehicle,
        .env = &pfe_default_env,
        .drag = &pfe_default_drag,
        .default_vehicles = PFE_MAX_VEHICLES, /* the dearest rebuild */
        .default_position = 0U,
        .default_gap_mm = 10000U,
        .cruise = &pfe_default_cruise,
        .default_set_speed_mm_s = 25000,
    };
    uint64_t now = 1000000U;
    if (pfe_ecu_init(&s_ecu, &cfg, NULL, -1, now) != PFE_OK) {
        return -1;
    }
    static pfe_can_frame_t burst[PFE_ECU_RX_QUEUE_LEN];
    uint64_t worst = 0U;
    uint32_t rng = 1U;
    /* Mixes 0 .. BURST_KINDS - 1: all of one kind; then random kinds. */
    for (uint32_t mix = 0U; mix < (BURST_KINDS + 60U); mix++) {
        /* Back to a module that predicts: speed and grade, a whole preview,
         * ticks until a prediction runs. */
        uint32_t sent_frames = 0U;
        bool more = true;
        for (uint32_t tick = 0U; tick < 150U; tick++, now += PFE_ECU_TICK_US) {
            pfe_can_frame_t rx[12];
            uint32_t n_rx = 0U;
            burst_frame(1U, tick, &rx[n_rx++]);
            if ((tick % 10U) == 0U) {
                burst_frame(0U, tick, &rx[n_rx++]);
            }
            for (uint32_t j = 0U; (j < 10U) && more; j++) {
                more = preview_frame(sent_frames, &rx[n_rx]);
                if (more) {
                    n_rx++;
                    sent_frames++;
                }
            }
            (void)ecu_tick(now, rx, n_rx);
        }
        for (uint32_t k = 0U; k < PFE_ECU_RX_QUEUE_LEN; k++) {
            uint32_t kind = mix;
            if (mix >= BURST_KINDS) {
                rng = (rng * 1103515245U) + 12345U;
                kind = (rng >> 16) % BURST_KINDS;
            }
            burst_frame(kind, k + (mix * PFE_ECU_RX_QUEUE_LEN), &burst[k]);
        }
        /* Random mixes come in three sizes: the most frames a tick that also
         * predicts decodes, one more, and a full queue. */
        const uint32_t len = (mix < BURST_KINDS) ? PFE_ECU_RX_QUEUE_LEN
                             : (((mix % 3U) == 0U) ? PFE_ECU_RX_LIGHT
                                : (((mix % 3U) == 1U) ? (PFE_ECU_RX_LIGHT + 1U) : PFE_ECU_RX_QUEUE_LEN));
        for (uint32_t tick = 0U; tick < 6U; tick++, now += PFE_ECU_TICK_US) {
            const uint64_t insns = (tick == 0U) ? ecu_tick(now, burst, len) : ecu_tick(now, burst, 2U);
            worst = (insns > worst) ? insns : worst;
        }
    }
    hal_mps2_write_bench("ecu_tick_burst_max", worst, "insn");
    return 0;
}

/* Parts of the steps above, each timed alone over PART_CALLS calls with
 * the inputs of the drives above (docs/bench.md, the floor analysis): the
 * mean of a part is its cost inside the step, within a few instructions
 * (a part inlined in its step shares registers there). Their results go to
 * a digest of their own, so that the results digest above compares with
 * earlier builds. */
#define PART_CALLS 2000U
static uint64_t s_part_sink;

static uint64_t part_insns(uint64_t t0, uint64_t t1)
{
    const uint64_t d = t1 - t0;
    return (d > HAL_MPS2_ICOUNT_OVERHEAD_INSNS) ? (d - HAL_MPS2_ICOUNT_OVERHEAD_INSNS) : 0U;
}

static int bench_parts(void)
{
    if (setup(5U) != 0) {
        return -1;
    }
    const pfe_vehicle_t *truck = &s_platoon.position[1];
    const pfe_vehicle_t *obj = &s_platoon.object;
    pfe_accel_filter_t filter;
    pfe_accel_reset(&filter);
    pfe_pi_t pi;
    pfe_pi_init(&pi, (int64_t)1 << 34, (int64_t)1 << 30, 20000);
    uint64_t grade_total = 0U;
    uint64_t truck_total = 0U;
    uint64_t object_total = 0U;
    uint64_t filter_total = 0U;
    uint64_t limit_total = 0U;
    uint64_t pi_total = 0U;
    uint64_t accel_total = 0U;
    for (uint32_t k = 0U; k < PART_CALLS; k++) {
        const pfe_est_input_t in = drive_input(k * 10U);
        const int32_t v = in.speed_mm_s;
        const uint64_t v2 = (uint64_t)(uint32_t)v * (uint32_t)v;
        const int32_t a = ((int32_t)(k % 200U) - 100) * 3000;
        pfe_grade_accel_t ga;
        uint64_t t0 = hal_mps2_icount_now();
        pfe_grade_accel(in.grade_ppm, s_platoon.gravity_um_s2, &ga);
        uint64_t t1 = hal_mps2_icount_now();
        grade_total += part_insns(t0, t1);
        t0 = hal_mps2_icount_now();
        const int32_t f = pfe_vehicle_truck_fuel_force_n(truck, v2, a, &ga);
        const uint32_t rate = pfe_fuel_rate_nl_s(f, v, truck->power_aux_w, truck->fuel_q20);
        t1 = hal_mps2_icount_now();
        truck_total += part_insns(t0, t1);
        pfe_grade_accel_t small;
        t0 = hal_mps2_icount_now();
        pfe_platoon_grade_accel(&s_platoon, in.grade_ppm, &small);
        const int32_t fo = pfe_platoon_fuel_force_n(&s_platoon, v2, a, small.along_um_s2);
        const uint32_t rate_o = pfe_fuel_rate_nl_s(fo, v, obj->power_aux_w, obj->fuel_q20);
        t1 = hal_mps2_icount_now();
        object_total += part_insns(t0, t1);
        t0 = hal_mps2_icount_now();
        pfe_accel_update(&filter, v, 1U);
        t1 = hal_mps2_icount_now();
        filter_total += part_insns(t0, t1);
        t0 = hal_mps2_icount_now();
        const int32_t f_max = pfe_platoon_force_max_v2_n(obj, s_platoon.formation_air_q32, v, v2);
        t1 = hal_mps2_icount_now();
        limit_total += part_insns(t0, t1);
        t0 = hal_mps2_icount_now();
        const int32_t u = pfe_pi_step_in_range(&pi, (25000 - v) * 1000, 26214U,
                                               -(int32_t)obj->brake_max_n, f_max);
        t1 = hal_mps2_icount_now();
        pi_total += part_insns(t0, t1);
        t0 = hal_mps2_icount_now();
        const int32_t acc = pfe_platoon_accel_um_s2(&s_platoon, (u * 4) - (f / 4));
        t1 = hal_mps2_icount_now();
        accel_total += part_insns(t0, t1);
        s_part_sink = (s_part_sink ^ (uint64_t)ga.along_um_s2 ^ ((uint64_t)rate << 7) ^
                       ((uint64_t)rate_o << 13) ^ (uint64_t)filter.accel_um_s2 ^
                       ((uint64_t)(uint32_t)acc << 21)) * 1099511628211ULL;
    }
    hal_mps2_write_bench("part_grade_accel", grade_total / PART_CALLS, "insn");
    hal_mps2_write_bench("part_truck_fuel", truck_total / PART_CALLS, "insn");
    hal_mps2_write_bench("part_object_fuel", object_total / PART_CALLS, "insn");
    hal_mps2_write_bench("part_speed_filter", filter_total / PART_CALLS, "insn");
    hal_mps2_write_bench("part_force_limit", limit_total / PART_CALLS, "insn");
    hal_mps2_write_bench("part_pi_step", pi_total / PART_CALLS, "insn");
    hal_mps2_write_bench("part_platoon_accel", accel_total / PART_CALLS, "insn");
    return 0;
}

int main(void)
{
    hal_mps2_icount_start();
    uint64_t n5_total = 0U;
    int rc = bench_estimator(5U, "est_step_n5_mean", "est_step_n5_max");
    n5_total = s_est_total;
    if ((rc != 0) ||
        (bench_estimator(PFE_MAX_VEHICLES, "est_step_n32_mean", "est_step_n32_max") != 0) ||
        (bench_sim() != 0) || (bench_ecu() != 0) || (bench_predict() != 0) ||
        (bench_identify() != 0) || (bench_inputs() != 0) || (bench_burst() != 0)) {
        hal_mps2_write_str("bench: failed\n");
        return 1;
    }
    /* Each truck beyond the fifth, over the 27 of the largest platoon. */
    const uint64_t n32_total = s_est_total;
    const uint64_t extra = (n32_total > n5_total) ? (n32_total - n5_total) : 0U;
    hal_mps2_write_bench("est_step_per_truck",
                         (extra + ((MEASURED_TICKS * (PFE_MAX_VEHICLES - 5U)) / 2U)) /
                             (MEASURED_TICKS * (PFE_MAX_VEHICLES - 5U)),
                         "insn");
    hal_mps2_write_bench("stack_used", hal_mps2_stack_used_bytes(), "bytes");
    hal_mps2_write_str("m4_bench: results digest ");
    hal_mps2_write_hex64(s_sink);
    hal_mps2_write_str("\n");
    int later = bench_estimator(1U, "est_step_n1_mean", "est_step_n1_max");
    s_use_mixed = true;
    later |= bench_estimator(5U, "est_step_n5_mixed_mean", "est_step_n5_mixed_max");
    s_use_mixed = false;
    if ((later != 0) || (bench_parts() != 0)) {
        hal_mps2_write_str("bench: failed\n");
        return 1;
    }
    hal_mps2_write_str("m4_bench: parts digest ");
    hal_mps2_write_hex64(s_part_sink);
    hal_mps2_write_str("\n");
    return 0;
}
