/* pfe_sim.c - the platoon object model over a road (contract in pfe_sim.h). */
#include "pfe_sim.h"

#include <stdbool.h>
#include <stddef.h>

#include "pfe_fixed.h"

/* 10^9 = 2^9 * 5^9 */
#define POW5_9 1953125ULL
#define FUEL_FORCE_MAX_Q2 ((int32_t)1 << 27) /* 33.5 MN: above any platoon's traction */
/* Steps whose times (each at most 2^20 in s * 2^16) a 32-bit sum holds. */
#define PFE_SIM_BLOCK_STEPS 4095U

/* Air drag and rolling resistance in N * 2^2 (eq. 4.6, 4.8): air_q32 [N
 * per (mm/s)^2 * 2^32] below 2^22 (a platoon's sum, as unsigned 32 bits)
 * times v2 < 2^33, over 2^30, rounded, plus cr M g: held at init as
 * air_x4_q32 = 4 air_q32 (< 2^24) and air_bias = cr M g [N * 2^2] * 2^32 +
 * 2^31, so that the sum is the high word of one multiply-accumulate onto
 * the bias and one multiply (v2's high word), below 2^57: exactly the
 * rounded air drag plus the rolling part. */
static inline int32_t air_roll_q2(const pfe_sim_t *sim, uint64_t v2)
{
    return (int32_t)(uint32_t)((((uint64_t)sim->air_x4_q32 * v2) + sim->air_bias) >> 32);
}

/* Fg = M g grade in N * 2^2 (eq. 4.10, small angle): |grade| <= 5 * 10^5
 * (checked at init) times weight_scale <= 2^10 is below 2^29, times
 * |weight_m| < 2^31 below 2^60: one 32 x 32 -> 64 bit multiply, its rounded
 * high word. */
static inline int32_t grade_q2(const pfe_sim_t *sim, int32_t grade_ppm)
{
    return pfe_mulhr_i32(sim->weight_m, grade_ppm * sim->weight_scale);
}

/* Fa + Fr + Fg of the object model at speed v and grade (eq. 4.6 to 4.10),
 * N * 2^2 (finer than whole newtons, whose rounding bias would add up over a
 * route): the sum of pfe_vehicle_resistance_n() with the small-angle grade of
 * pfe_platoon_grade_accel(), its constant and linear parts folded at init.
 * air_q32 < 2^22 and v < 2^17: below 2^56. The sum, at most about 3.4e7 N,
 * fits 32 bits in N * 2^2. */
static int32_t resistance_q2(const pfe_sim_t *sim, uint64_t v2, int32_t grade_ppm)
{
    return air_roll_q2(sim, v2) + grade_q2(sim, grade_ppm);
}

/* pfe_platoon_force_max_v2_n() for the simulation's speeds, v >= the stall
 * speed (1000 mm/s): min(Pmax / v, traction) - c v^2, never below
 * -brake_max, in N. Pmax [W] * 1000 / v is at most Pmax there, so its two
 * parts (the quotient's thousands and the remainder's share) and their sum
 * fit 32 bits; the traction is held at most INT32_MAX (traction_cap_n) and
 * the brake negated (brake_min_n) at init. The same result. */
static inline int32_t force_max_n(const pfe_sim_t *sim, uint32_t v, uint64_t v2)
{
    const uint32_t q = sim->power_max_w / v;
    const uint32_t r = sim->power_max_w - (q * v);
    const uint32_t power_n = (q * 1000U) + ((r * 1000U) / v);
    const uint32_t cap = (uint32_t)sim->traction_cap_n;
    const int32_t wheel = (int32_t)((power_n < cap) ? power_n : cap);
    const uint64_t drag = (v2 * sim->formation_air_q32) + 2147483648U;
    const int32_t f = wheel - (int32_t)(uint32_t)(drag >> 32);
    return (f < sim->brake_min_n) ? sim->brake_min_n : f;
}

/* Per-kg gain [1/s * 1000] to N per um/s * 2^32: M * k * 2^32 / 10^9. */
static int64_t gain_q32(uint32_t mass_kg, uint32_t milli)
{
    return (int64_t)pfe_udiv_round_u64(((uint64_t)mass_kg * milli) << 23, POW5_9);
}

/* The largest r with r^k <= x (k 2 or 3), by bisection: init time only. */
static uint32_t iroot(uint64_t x, uint32_t k)
{
    uint64_t lo = 0U;
    uint64_t hi = (k == 2U) ? 0xFFFFFFFFULL : 0x1FFFFFULL; /* hi^k < 2^64 */
    while (lo < hi) {
        const uint64_t mid = (lo + hi + 1U) / 2U;
        const uint64_t p = (k == 2U) ? (mid * mid) : (mid * mid * mid);
        if (p <= x) {
            lo = mid;
        } else {
            hi = mid - 1U;
        }
    }
    return (uint32_t)lo;
}

/* A step of v * tau at most (pfe_sim.h, stability): tau the controller's,
 * or at the power limit M v^2 / P, here in us: v^2 [(mm/s)^2] M [kg] / P
 * [W] (< 4.9e9 * 3.2e6 < 2^54); held below 2^40 before the product with
 * v < 2^17. */
static uint32_t stable_step_mm(const pfe_sim_t *sim, uint32_t v, uint32_t ds)
{
    const pfe_platoon_t *pl = sim->platoon;
    const uint64_t ctrl_mm = ((uint64_t)v * sim->ctrl_tau_ms) / 1000U;
    uint64_t tau_us = ((uint64_t)v * v * pl->mass_kg) / pl->object.power_max_w;
    tau_us = (tau_us < ((uint64_t)1 << 40)) ? tau_us : ((uint64_t)1 << 40);
    const uint64_t power_mm = (tau_us * v) / 1000000U;
    uint64_t cap = (ctrl_mm < power_mm) ? ctrl_mm : power_mm;
    cap = (cap > PFE_SIM_STEP_MIN_MM) ? cap : PFE_SIM_STEP_MIN_MM;
    return (ds < cap) ? ds : (uint32_t)cap;
}

int32_t pfe_sim_speed_mm_s(const pfe_sim_t *sim)
{
    return (sim->speed_um_s + 500) / 1000;
}

int pfe_sim_init(pfe_sim_t *sim, const pfe_platoon_t *platoon, const pfe_cruise_calib_t *cruise,
                 const pfe_road_t *road, int32_t set_speed_mm_s, int32_t initial_speed_mm_s,
                 uint32_t step_mm)
{
    if ((sim == NULL) || (platoon == NULL) || (road == NULL) || (road->grade_ppm == NULL) ||
        (road->n_samples == 0U) || (road->spacing_mm == 0U) ||
        (pfe_calib_check_cruise(cruise) != PFE_OK) || (step_mm < PFE_SIM_STEP_MIN_MM) ||
        (step_mm > PFE_SIM_STEP_MAX_MM) || (set_speed_mm_s < PFE_SIM_STALL_MM_S) ||
        (set_speed_mm_s > PFE_SPEED_MAX_MM_S) || (initial_speed_mm_s < PFE_SIM_STALL_MM_S) ||
        (initial_speed_mm_s > PFE_SPEED_MAX_MM_S)) {
        return PFE_EINVAL;
    }
    const uint64_t end = (uint64_t)road->n_samples * road->spacing_mm;
    if (end > UINT32_MAX) {
        return PFE_EINVAL;
    }
    sim->platoon = platoon;
    sim->step_mm = step_mm;
    sim->end_mm = (uint32_t)end;
    sim->set_speed_um_s = set_speed_mm_s * 1000;
    sim->speed_um_s = initial_speed_mm_s * 1000;
    sim->position_mm = 0U;
    sim->steps = 0U;
    sim->time_q16 = 0U;
    sim->fuel_nl = 0U;
    sim->work_q2_mm = 0U;
    sim->pull_time_q16 = 0U;
    sim->grade_ppm = road->grade_ppm[0];
    sim->accel_um_s2 = 0;
    sim->fuel_step_nl = 0U;
    const pfe_vehicle_t *obj = &platoon->object;
    sim->formation_air_q32 = platoon->formation_air_q32;
    sim->power_max_w = obj->power_max_w;
    sim->traction_cap_n = (obj->traction_max_n > (uint32_t)INT32_MAX) ? INT32_MAX
                                                                      : (int32_t)obj->traction_max_n;
    sim->brake_min_n = -(int32_t)obj->brake_max_n;
    /* cr M g: roll_q32 < 2^31 times g < 2^24, over 2^30. */
    sim->roll_q2 = pfe_rshift_round(obj->roll_q32 * (int64_t)platoon->gravity_um_s2, 30U);
    /* roll_q2 < 2^25 (pfe_vehicle.c's bounds, 32 trucks): the bias below 2^57. */
    sim->air_bias = ((uint64_t)sim->roll_q2 << 32) + 2147483648U;
    sim->air_x4_q32 = (uint32_t)obj->air_q32 * 4U;
    /* M g [N] * 2^36 / 10^6 = mass_q32 [kg * 2^32 / 10^6] * g [um/s^2] * 2^4
     * / 10^6; mass_q32 * g < 2^57, times 2^4 below 2^61; the quotient below
     * 2^42 (3200 t), so its shift is 2 .. 12. */
    const int64_t weight_q36 = (int64_t)pfe_udiv_round_u64(
        ((uint64_t)obj->mass_q32 * platoon->gravity_um_s2) << 4, 1000000U);
    uint32_t shift = 0U;
    sim->weight_m = pfe_mantissa_i32(weight_q36, 2U, &shift);
    const uint32_t weight_shift = shift - 2U;
    const uint32_t weight_scale = 1U << weight_shift;
    sim->weight_scale = (int32_t)weight_scale;
    /* mass_fuel_q32 < 2^35 (M + Mj <= 2 M <= 6.4e6 kg: below 2^34.7): shift
     * 0 .. 4, the scale 2^2 .. 2^6, so |a| 2^6 <= 2^30.3. */
    sim->mass_fuel_m = pfe_mantissa_i32(obj->mass_fuel_q32, 0U, &shift);
    const uint32_t mass_fuel_scale = 4U << shift;
    sim->mass_fuel_scale = (int32_t)mass_fuel_scale;
    /* Paux [mW] * fuel_q20 [nL/mJ * 2^20] / 2^12 = nL/s * 2^8; Paux <= 3.2e9 mW
     * and fuel_q20 < 2^22 keep it below 2^41. */
    sim->aux_fuel_q8 = pfe_rshift_round((int64_t)obj->power_aux_w * 1000 * obj->fuel_q20, 12U);
    /* Time constants (pfe_sim.h, stability): 1 / kp = 10^6 / kp_milli ms,
     * 1 / sqrt(ki) = sqrt(10^9 / ki_milli) ms. A step of step_mm lasts
     * longer than the controller's below step_mm / tau, and longer than
     * the power limit's (M v^2 / P) below cbrt(step_mm P 10^6 / M) mm/s
     * (16000 * 6.4e7 * 10^6 < 2^60). */
    uint32_t tau_ms = 1000000U / cruise->kp_milli_per_s;
    if (cruise->ki_milli_per_s2 > 0U) {
        const uint32_t tau_i_ms = iroot(1000000000ULL / cruise->ki_milli_per_s2, 2U);
        tau_ms = (tau_i_ms < tau_ms) ? tau_i_ms : tau_ms;
    }
    sim->ctrl_tau_ms = tau_ms;
    const uint64_t v_ctrl = ((uint64_t)step_mm * 1000U) / tau_ms;
    const uint64_t v_power = iroot(((uint64_t)step_mm * obj->power_max_w * 1000000U) / platoon->mass_kg, 3U);
    const uint64_t v_stiff = ((v_ctrl > v_power) ? v_ctrl : v_power) + 1U;
    sim->stiff_below_mm_s = (v_stiff < UINT32_MAX) ? (uint32_t)v_stiff : UINT32_MAX;
    for (uint32_t k = 0U; k < road->n_samples; k++) {
        if ((road->grade_ppm[k] < -PFE_GRADE_MAX_PPM) || (road->grade_ppm[k] > PFE_GRADE_MAX_PPM)) {
            return PFE_EINVAL;
        }
    }
    const uint64_t v2_init = (uint64_t)initial_speed_mm_s * (uint32_t)initial_speed_mm_s;
    const int32_t hold = (resistance_q2(sim, v2_init, road->grade_ppm[0]) + 2) / 4;
    /* the initial speed is at least the stall speed (checked above) */
    const int32_t f_max = force_max_n(sim, (uint32_t)initial_speed_mm_s, v2_init);
    sim->wheel_force_n = pfe_clamp_i32(hold, sim->brake_min_n, f_max);
    pfe_pi_init(&sim->pi, gain_q32(platoon->mass_kg, cruise->kp_milli_per_s),
                gain_q32(platoon->mass_kg, cruise->ki_milli_per_s2), sim->wheel_force_n);
    return PFE_OK;
}

/* The 32-bit sums of a block of at most PFE_SIM_BLOCK_STEPS steps, which
 * pfe_sim_run() adds to the 64-bit ones at the block's end: each step's dt
 * is at most 2^20 and its ds below 2^14. */
typedef struct {
    uint32_t time_q16;  /* sum dt: pfe_sim_t.time_q16 */
    uint32_t pull_q16;  /* sum dt of the pulling steps: pfe_sim_t.pull_time_q16 */
    uint32_t bound_ds;  /* sum ds of the bound's steps: pfe_sim_sums_t.bound_ds_mm */
} block_sums_t;

/* One step (pfe_sim_step()), inline in pfe_sim_run()'s loop: its time,
 * pulling time and bound distance go to the block's sums *b. */
static PFE_ALWAYS_INLINE int step(pfe_sim_t *sim, const pfe_road_t *road, pfe_sim_sums_t *sums,
                                  block_sums_t *b, bool with_fuel, bool with_bound)
{
    if (sim->position_mm >= sim->end_mm) {
        return PFE_SIM_DONE;
    }
    /* The speed is never negative (clamped below): an unsigned rounding. */
    const uint32_t v = ((uint32_t)sim->speed_um_s + 500U) / 1000U;
    if (v < (uint32_t)PFE_SIM_STALL_MM_S) {
        return PFE_ESTALL;
    }
    const uint32_t left = sim->end_mm - sim->position_mm;
    uint32_t ds = (left < sim->step_mm) ? left : sim->step_mm;
    if (v < sim->stiff_below_mm_s) {
        ds = stable_step_mm(sim, v, ds);
    }
    /* ds <= 16000 mm: ds * 2^16 < 2^30; v >= 1000 mm/s: dt <= 16 s (2^20 in Q16). */
    const uint32_t dt_q16 = ((ds << 16) + (v >> 1)) / v;

    /* The sample of the step's midpoint: 1 <= ds <= end - position, so the
     * midpoint lies before the road's end (n_samples * spacing_mm) and its
     * sample is one of the road's. */
    const uint32_t sample = (sim->position_mm + (ds / 2U)) / road->spacing_mm;
    const int32_t grade = road->grade_ppm[sample];
    const uint64_t v2u = (uint64_t)v * v;
    const int32_t resist_q2 = resistance_q2(sim, v2u, grade);
    const int32_t f_max = force_max_n(sim, v, v2u);
    const int32_t force = pfe_pi_step_in_range(&sim->pi, sim->set_speed_um_s - sim->speed_um_s,
                                               dt_q16, sim->brake_min_n, f_max);
    /* |force| <= 2^26 (PFE_PI_OUT_MAX), |resistance| < 2^27 in N * 2^2: fits. */
    const int32_t accel = pfe_platoon_accel_um_s2(sim->platoon, (force * 4) - resist_q2);
    /* dv = a dt / 2^16, rounded: |a| <= PFE_ACCEL_MAX_UM_S2 (2e7) times 2^6
     * and dt <= 2^20 times 2^10 both fit int32, so it is their product's
     * rounded high word; below 2^28.3, and the sum with a speed <= 7e7 um/s
     * stays inside int32. */
    const int32_t dv = pfe_mulhr_i32(accel * 64, (int32_t)(dt_q16 << 10));
    sim->speed_um_s = pfe_clamp_i32(sim->speed_um_s + dv, 0, PFE_SPEED_MAX_MM_S * 1000);

    if (with_fuel) {
        /* eq. 3.7 / 4.14 in N * 2^2: (M + Mj) a is within M * 20 m/s^2 * 2
         * (|a| * mass_fuel_scale <= 2^30.3 times |mass_fuel_m| < 2^31: the
         * rounded high word of a 32 x 32 bit product), the sum below 2^30. */
        const int32_t fuel_force_q2 =
            pfe_mulhr_i32(sim->mass_fuel_m, accel * sim->mass_fuel_scale) + resist_q2;
        /* The work Fw' ds of a pulling step, Fw' [N * 2^2] held within
         * [0, 2^27 - 1] (one USAT: 33.5 MN, above any platoon's traction)
         * times ds < 2^14: one 32 x 32 -> 64 bit multiply-accumulate; the
         * fuel is made from the sums (sim_fuel_nl()). */
        const uint32_t f = (uint32_t)pfe_clamp_i32(fuel_force_q2, 0, FUEL_FORCE_MAX_Q2 - 1);
        sim->work_q2_mm += (uint64_t)f * ds;
        if (f != 0U) {
            b->pull_q16 += dt_q16;
        }
    }
    if (with_bound && (force > 0)) {
        /* The bound's three sums (pfe_sim.h): v^2 / 2 < 2^32 times ds, the
         * bound's grade (|g| <= 25000) times ds: two multiply-accumulates. */
        const uint32_t v2_half = (uint32_t)(v2u >> 1);
        sums->bound_v2_ds += (uint64_t)v2_half * ds;
        b->bound_ds += ds;
        sums->bound_grade_ds += (int64_t)sums->bound_grade_20ppm[sample] * (int32_t)ds;
    }
    b->time_q16 += dt_q16;
    sim->position_mm += ds;
    sim->grade_ppm = grade;
    sim->wheel_force_n = force;
    sim->accel_um_s2 = accel;
    return PFE_SIM_RUNNING;
}

/* The fuel of the sums (pfe_sim.h): the work Fw' ds [N * 2^2 * mm = mJ *
 * 2^2] times fuel_q20 [nL/mJ * 2^20] over 2^22, and the time [s * 2^16]
 * times aux_fuel_q8 [nL/s * 2^8] over 2^24, each rounded once: products
 * below 2^81 and 2^79, exact (pfe_mul_shift_round_u64()). */
static uint64_t work_fuel_nl(uint64_t work_q2_mm, int64_t fuel_q20)
{
    return pfe_mul_shift_round_u64(work_q2_mm, (uint64_t)fuel_q20, 22U);
}

static uint64_t aux_fuel_nl(const pfe_sim_t *sim, uint64_t pull_time_q16)
{
    return pfe_mul_shift_round_u64(pull_time_q16, (uint64_t)sim->aux_fuel_q8, 24U);
}

static uint64_t sim_fuel_nl(const pfe_sim_t *sim, uint64_t work_q2_mm, uint64_t pull_time_q16)
{
    return pfe_sat_add_u64(work_fuel_nl(work_q2_mm, sim->platoon->object.fuel_q20),
                           aux_fuel_nl(sim, pull_time_q16));
}

/* The bound's fuel (pfe_sim_sums_t): its work in N * 2^2 * mm, the air
 * part bound_air [N per (mm/s)^2 * 2^32] * 2 sum v^2 ds / 2 / 2^30 (below
 * 2^22 * 2^63 / 2^29), the rolling part roll_q2 (< 2^25) * sum ds (< 2^32),
 * the grade part M g [as weight_m * 2^(2 + s) per ppm] * 20 * sum g20 ds
 * / 2^32 (below 2^45.4 * 2^47 / 2^32); each below 2^60, rounded once, and
 * the work's fuel rounded halves away from zero. */
static int64_t bound_fuel_nl(const pfe_sim_t *sim, const pfe_sim_sums_t *sums)
{
    const int64_t air = (int64_t)pfe_mul_shift_round_u64((uint64_t)sums->bound_air_q32,
                                                         sums->bound_v2_ds, 29U);
    const int64_t roll = sim->roll_q2 * (int64_t)sums->bound_ds_mm;
    const uint64_t weight_20 = (uint64_t)(int64_t)sim->weight_m * 20U * (uint64_t)sim->weight_scale;
    const int64_t g_ds = sums->bound_grade_ds;
    const uint64_t g_mag = (g_ds < 0) ? (0U - (uint64_t)g_ds) : (uint64_t)g_ds;
    const int64_t grade_mag = (int64_t)pfe_mul_shift_round_u64(weight_20, g_mag, 32U);
    const int64_t work = air + roll + ((g_ds < 0) ? -grade_mag : grade_mag);
    const uint64_t magnitude = (work < 0) ? (0U - (uint64_t)work) : (uint64_t)work;
    const int64_t nl = (int64_t)work_fuel_nl(magnitude, sums->bound_fuel_q20); /* below 2^60 */
    return (work < 0) ? -nl : nl;
}

/* The results of the sums after a call's steps: fuel_nl and what they added
 * to it, and the sums' fuel. */
static void finish_run(pfe_sim_t *sim, uint64_t pull_before_q16, pfe_sim_sums_t *sums)
{
    const uint64_t fuel = sim_fuel_nl(sim, sim->work_q2_mm, sim->pull_time_q16);
    sim->fuel_step_nl = fuel - sim->fuel_nl;
    sim->fuel_nl = fuel;
    if (sums != NULL) {
        sums->aux_nl += aux_fuel_nl(sim, sim->pull_time_q16) - aux_fuel_nl(sim, pull_before_q16);
        sums->bound_nl = bound_fuel_nl(sim, sums);
    }
}

/* The steps of one kind of run, up to max_steps (UINT32_MAX: to the end),
 * in blocks of at most PFE_SIM_BLOCK_STEPS whose time sums fit 32 bits. */
static PFE_ALWAYS_INLINE int run_blocks(pfe_sim_t *s, const pfe_road_t *rd, uint32_t max_steps,
                                       pfe_sim_sums_t *t, bool with_fuel, bool with_bound)
{
    int r = PFE_SIM_RUNNING;
    uint32_t left = max_steps;
    while ((left != 0U) && (r == PFE_SIM_RUNNING)) {
        const uint32_t block = (left < PFE_SIM_BLOCK_STEPS) ? left : PFE_SIM_BLOCK_STEPS;
        block_sums_t b = {0U, 0U, 0U};
        uint32_t k = block;
        do {
            r = step(s, rd, t, &b, with_fuel, with_bound);
            k--;
        } while ((k != 0U) && (r == PFE_SIM_RUNNING));
        /* the last call took no step unless it ran */
        k += (r == PFE_SIM_RUNNING) ? 0U : 1U;
        k = block - k;
        s->steps += k;
        s->time_q16 += b.time_q16;
        s->pull_time_q16 += b.pull_q16;
        if (with_bound) {
            t->bound_ds_mm += b.bound_ds;
        }
        left -= (max_steps != UINT32_MAX) ? k : 0U;
    }
    return r;
}

int pfe_sim_run(pfe_sim_t *sim, const pfe_road_t *road, uint32_t max_steps, pfe_sim_sums_t *sums)
{
    /* The state in locals the compiler can keep in registers across steps
     * (through the pointers it would have to assume aliasing); one loop per
     * kind of run, so that a run carries the cost of what it sums alone. */
    pfe_sim_t s = *sim;
    const pfe_road_t rd = *road;
    int r;
    if (sums == NULL) {
        r = run_blocks(&s, &rd, max_steps, NULL, true, false);
    } else {
        pfe_sim_sums_t t = *sums;
        if (t.bound_grade_20ppm == NULL) {
            r = run_blocks(&s, &rd, max_steps, &t, true, false);
        } else {
            r = run_blocks(&s, &rd, max_steps, &t, false, true);
        }
        *sums = t;
    }
    const uint64_t pull_before = sim->pull_time_q16;
    *sim = s;
    finish_run(sim, pull_before, sums);
    return r;
}

int pfe_sim_step(pfe_sim_t *sim, const pfe_road_t *road)
{
    return pfe_sim_run(sim, road, 1U, NULL);
}
