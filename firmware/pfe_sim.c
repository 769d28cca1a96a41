/* pfe_sim.c - the platoon object model over a road (contract in pfe_sim.h). */
#include "pfe_sim.h"

#include <stddef.h>

#include "pfe_fixed.h"

/* 10^9 = 2^9 * 5^9 */
#define POW5_9 1953125ULL
#define ENERGY_MAX_MJ ((int64_t)1 << 40)

static int32_t grade_at(const pfe_road_t *road, uint32_t position_mm)
{
    uint32_t k = position_mm / road->spacing_mm;
    if (k >= road->n_samples) {
        k = road->n_samples - 1U;
    }
    return road->grade_ppm[k];
}

/* Fa + Fr + Fg of the object model at speed v and grade (eq. 4.6 to 4.10),
 * N * 2^8. */
static int64_t resistance_q8(const pfe_platoon_t *pl, int32_t speed_mm_s, int32_t grade_ppm)
{
    pfe_grade_accel_t g;
    pfe_platoon_grade_accel(pl, grade_ppm, &g);
    return pfe_vehicle_resistance_q8(&pl->object, speed_mm_s, &g);
}

/* Per-kg gain [1/s * 1000] to N per um/s * 2^32: M * k * 2^32 / 10^9. */
static int64_t gain_q32(uint32_t mass_kg, uint32_t milli)
{
    return (int64_t)pfe_udiv_round_u64(((uint64_t)mass_kg * milli) << 23, POW5_9);
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
    sim->grade_ppm = road->grade_ppm[0];
    sim->accel_um_s2 = 0;
    sim->fuel_step_nl = 0U;
    const pfe_vehicle_t *obj = &platoon->object;
    const int32_t hold = pfe_sat_i32(
        pfe_rshift_round(resistance_q8(platoon, initial_speed_mm_s, road->grade_ppm[0]), 8U));
    const int32_t f_max = pfe_wheel_force_max_n(obj->power_max_w, obj->traction_max_n,
                                                initial_speed_mm_s);
    sim->wheel_force_n = pfe_clamp_i32(hold, -(int32_t)obj->brake_max_n, f_max);
    pfe_pi_init(&sim->pi, gain_q32(platoon->mass_kg, cruise->kp_milli_per_s),
                gain_q32(platoon->mass_kg, cruise->ki_milli_per_s2), sim->wheel_force_n);
    return PFE_OK;
}

int pfe_sim_step(pfe_sim_t *sim, const pfe_road_t *road)
{
    if (sim->position_mm >= sim->end_mm) {
        return PFE_SIM_DONE;
    }
    const int32_t v_mm_s = pfe_sim_speed_mm_s(sim);
    if (v_mm_s < PFE_SIM_STALL_MM_S) {
        return PFE_ESTALL;
    }
    const pfe_platoon_t *pl = sim->platoon;
    const pfe_vehicle_t *obj = &pl->object;
    const uint32_t left = sim->end_mm - sim->position_mm;
    const uint32_t ds = (left < sim->step_mm) ? left : sim->step_mm;
    const uint32_t v = (uint32_t)v_mm_s;
    /* ds <= 10^4 mm: ds * 2^16 < 2^30; v >= 1000 mm/s: dt <= 10 s. */
    const uint32_t dt_q16 = ((ds << 16) + (v / 2U)) / v;

    const int32_t grade = grade_at(road, sim->position_mm + (ds / 2U));
    const int64_t resist_q8 = resistance_q8(pl, v_mm_s, grade);
    const int32_t f_max = pfe_wheel_force_max_n(obj->power_max_w, obj->traction_max_n, v_mm_s);
    const int32_t force = pfe_pi_step(&sim->pi, sim->set_speed_um_s - sim->speed_um_s, dt_q16,
                                      -(int32_t)obj->brake_max_n, f_max);
    const int32_t accel = pfe_platoon_accel_um_s2(pl, ((int64_t)force * 256) - resist_q8);
    /* |a| <= 2^24.3, dt <= 2^19.4: product below 2^44. */
    const int64_t speed = (int64_t)sim->speed_um_s + pfe_mul_q((int64_t)accel, (int32_t)dt_q16, 16U);
    sim->speed_um_s = (int32_t)pfe_clamp_i64(speed, 0, (int64_t)PFE_SPEED_MAX_MM_S * 1000);

    /* eq. 3.7 / 4.14 in N * 2^8: mass_fuel_q32 < 2^35, |a| < 2^25. */
    const int64_t fuel_force_q8 = pfe_mul_q(obj->mass_fuel_q32, accel, 24U) + resist_q8;
    uint64_t fuel_step = 0U;
    if (fuel_force_q8 > 0) {
        /* N * mm = mJ (< 2^39 * 2^14 / 2^8); Paux [W] * dt [s * 2^16] * 1000 / 2^16
         * = mJ (< 2^22 * 2^20 * 2^10). Clamped to 2^40 mJ; fuel_q20 < 2^22. */
        const int64_t work = pfe_rshift_round(fuel_force_q8 * (int64_t)ds, 8U);
        const int64_t aux = pfe_rshift_round((int64_t)obj->power_aux_w * (int64_t)dt_q16 * 1000, 16U);
        const int64_t energy = pfe_clamp_i64(work + aux, 0, ENERGY_MAX_MJ);
        fuel_step = (uint64_t)pfe_rshift_round(energy * obj->fuel_q20, 20U);
    }
    sim->fuel_nl = pfe_sat_add_u64(sim->fuel_nl, fuel_step);
    sim->fuel_step_nl = fuel_step;
    sim->time_q16 += dt_q16;
    sim->position_mm += ds;
    sim->steps++;
    sim->grade_ppm = grade;
    sim->wheel_force_n = force;
    sim->accel_um_s2 = accel;
    return PFE_SIM_RUNNING;
}
