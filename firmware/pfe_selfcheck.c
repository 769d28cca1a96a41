/* pfe_selfcheck.c - known-answer run of the whole model (contract in pfe_selfcheck.h). */
#include "pfe_selfcheck.h"

#include <stdbool.h>
#include <stddef.h>

#include "pfe_calib.h"
#include "pfe_estimator.h"
#include "pfe_fixed.h"
#include "pfe_platoon.h"

#define FNV_OFFSET 14695981039346656037ULL
#define FNV_PRIME 1099511628211ULL
#define STEP_MM 10000U
#define GAP_MM 10000U

static pfe_platoon_t s_platoon;
static pfe_estimator_t s_est;

static uint64_t fold(uint64_t h, uint64_t value)
{
    uint64_t acc = h;
    for (uint32_t k = 0U; k < 8U; k++) {
        const uint32_t shift = 8U * k;
        acc ^= (value >> shift) & 0xFFU;
        acc *= FNV_PRIME;
    }
    return acc;
}

int32_t pfe_selfcheck_spn84_mm_s(int32_t speed_mm_s)
{
    /* raw = v [mm/s] * 3.6 * 256 / 1000 = v * 1152 / 1250; back: raw * 1250 / 1152 */
    const int32_t v = pfe_clamp_i32(speed_mm_s, 0, PFE_SPEED_MAX_MM_S);
    const int32_t raw = ((v * 1152) + 625) / 1250;
    return ((raw * 1250) + 576) / 1152;
}

int pfe_selfcheck_run(const pfe_road_t *road, uint32_t n_vehicles, int32_t set_speed_mm_s,
                      pfe_selfcheck_result_t *out)
{
    if ((road == NULL) || (out == NULL) || (n_vehicles < 1U) || (n_vehicles > PFE_MAX_VEHICLES)) {
        return PFE_EINVAL;
    }
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, n_vehicles, GAP_MM, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    pfe_sim_t sim;
    if ((pfe_platoon_init(&s_platoon, &cfg) != PFE_OK) ||
        (pfe_estimator_init(&s_est, &s_platoon) != PFE_OK) ||
        (pfe_sim_init(&sim, &s_platoon, &pfe_default_cruise, road, set_speed_mm_s, set_speed_mm_s,
                      STEP_MM) != PFE_OK)) {
        return PFE_EINVAL;
    }
    uint64_t h = FNV_OFFSET;
    uint32_t ticks = 0U;
    int32_t vmin = INT32_MAX;
    int32_t vmax = 0;
    int32_t bus_speed = pfe_selfcheck_spn84_mm_s(set_speed_mm_s);
    int rc = PFE_SIM_RUNNING;
    for (;;) {
        rc = pfe_sim_step(&sim, road);
        if (rc != PFE_SIM_RUNNING) {
            break;
        }
        h = fold(h, (uint64_t)(uint32_t)sim.speed_um_s);
        h = fold(h, (uint64_t)(uint32_t)sim.wheel_force_n);
        h = fold(h, (uint64_t)(uint32_t)sim.accel_um_s2);
        h = fold(h, sim.fuel_step_nl);
        h = fold(h, sim.time_q16);
        const int32_t v = pfe_sim_speed_mm_s(&sim);
        vmin = (v < vmin) ? v : vmin;
        vmax = (v > vmax) ? v : vmax;
        /* Every 10 ms tick up to the end of this step: tick k is at
         * k * 10 ms = k * 655.36 s * 2^16 / 100, compared without division. */
        while (((uint64_t)ticks * 65536U) <= (sim.time_q16 * 100U)) {
            const bool fresh = (ticks % PFE_EST_TICKS_PER_SPEED_PERIOD) == 0U;
            if (fresh) {
                bus_speed = pfe_selfcheck_spn84_mm_s(v);
            }
            const pfe_est_input_t in = {bus_speed, true, fresh, sim.grade_ppm, true};
            const pfe_est_output_t *o = pfe_estimator_step(&s_est, &in);
            h = fold(h, o->flags);
            h = fold(h, (uint64_t)(uint32_t)o->speed_mm_s);
            h = fold(h, (uint64_t)(uint32_t)o->accel_um_s2);
            h = fold(h, (uint64_t)(uint32_t)o->wheel_force_n);
            h = fold(h, o->fuel_rate_nl_s);
            for (uint32_t i = 0U; i < n_vehicles; i++) {
                h = fold(h, o->pos_fuel_rate_nl_s[i]);
            }
            ticks++;
        }
    }
    if (rc != PFE_SIM_DONE) {
        return rc;
    }
    out->est_fuel_ul = pfe_estimator_fuel_used_ul(&s_est, PFE_EST_PLATOON);
    out->est_pos0_fuel_ul = pfe_estimator_fuel_used_ul(&s_est, 0);
    h = fold(h, sim.fuel_nl);
    h = fold(h, out->est_fuel_ul);
    out->digest = h;
    out->steps = sim.steps;
    out->ticks = ticks;
    out->sim_fuel_nl = sim.fuel_nl;
    out->sim_time_q16 = sim.time_q16;
    out->sim_min_speed_mm_s = vmin;
    out->sim_max_speed_mm_s = vmax;
    return PFE_OK;
}
