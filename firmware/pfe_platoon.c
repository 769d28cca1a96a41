/* pfe_platoon.c - the platoon object model (contract in pfe_platoon.h). */
#include "pfe_platoon.h"

#include <stdbool.h>
#include <stddef.h>

#include "pfe_fixed.h"

#define POW5_6 15625U

void pfe_platoon_config_uniform(pfe_platoon_config_t *cfg, uint32_t n_vehicles, uint32_t gap_mm,
                                const pfe_vehicle_calib_t *vehicle, const pfe_env_calib_t *env,
                                const pfe_drag_table_t *drag)
{
    uint32_t n = (n_vehicles < 1U) ? 1U : n_vehicles;
    n = (n > PFE_MAX_VEHICLES) ? PFE_MAX_VEHICLES : n;
    cfg->n_vehicles = n;
    cfg->gap_mm = gap_mm;
    for (uint32_t i = 0U; i < PFE_MAX_VEHICLES; i++) {
        cfg->vehicle[i] = (i < n) ? vehicle : NULL;
    }
    cfg->env = env;
    cfg->drag = drag;
}

/* Index of the vehicle with the smallest value_i / m_i (eq. 4.4), compared
 * by cross-multiplication so that no ratio is rounded. */
static uint32_t weakest(const pfe_platoon_config_t *cfg, int use_power)
{
    uint32_t best = 0U;
    for (uint32_t i = 1U; i < cfg->n_vehicles; i++) {
        const pfe_vehicle_calib_t *a = cfg->vehicle[i];
        const pfe_vehicle_calib_t *b = cfg->vehicle[best];
        const uint64_t va = use_power ? a->power_max_w : a->traction_max_n;
        const uint64_t vb = use_power ? b->power_max_w : b->traction_max_n;
        if ((va * b->mass_kg) < (vb * a->mass_kg)) {
            best = i;
        }
    }
    return best;
}

/* Whether two positions' fuel rates are the same function of speed,
 * acceleration and grade (every coefficient pfe_vehicle_truck_fuel_force_n()
 * and pfe_fuel_rate_nl_s() read). */
static bool same_fuel_model(const pfe_vehicle_t *a, const pfe_vehicle_t *b)
{
    return (a->air_q32 == b->air_q32) && (a->mass_q32 == b->mass_q32) &&
           (a->mass_fuel_q32 == b->mass_fuel_q32) && (a->roll_q32 == b->roll_q32) &&
           (a->fuel_q20 == b->fuel_q20) && (a->power_aux_w == b->power_aux_w);
}

int pfe_platoon_init_begin(const pfe_platoon_config_t *cfg)
{
    if ((cfg == NULL) || (cfg->n_vehicles < 1U) || (cfg->n_vehicles > PFE_MAX_VEHICLES) ||
        (pfe_calib_check_env(cfg->env) != PFE_OK) || (pfe_calib_check_drag(cfg->drag) != PFE_OK)) {
        return PFE_EINVAL;
    }
    return PFE_OK;
}

int pfe_platoon_init_positions(pfe_platoon_t *pl, const pfe_platoon_config_t *cfg, uint32_t first,
                               uint32_t count)
{
    if ((pl == NULL) || (pfe_platoon_init_begin(cfg) != PFE_OK)) {
        return PFE_EINVAL;
    }
    const uint32_t n = cfg->n_vehicles;
    const uint32_t left = (first < n) ? (n - first) : 0U;
    const uint32_t end = first + ((count < left) ? count : left);
    for (uint32_t i = first; i < end; i++) {
        const pfe_vehicle_calib_t *c = cfg->vehicle[i];
        const uint32_t phi = (c == NULL) ? 0U : pfe_drag_reduction_bp(cfg->drag, i, n, cfg->gap_mm);
        if (pfe_vehicle_init(&pl->position[i], c, cfg->env, phi) != PFE_OK) {
            return PFE_EINVAL;
        }
    }
    return PFE_OK;
}

int pfe_platoon_init(pfe_platoon_t *pl, const pfe_platoon_config_t *cfg)
{
    if (pfe_platoon_init_positions(pl, cfg, 0U, PFE_MAX_VEHICLES) != PFE_OK) {
        return PFE_EINVAL;
    }
    return pfe_platoon_init_finish(pl, cfg);
}

int pfe_platoon_init_finish(pfe_platoon_t *pl, const pfe_platoon_config_t *cfg)
{
    if ((pl == NULL) || (pfe_platoon_init_begin(cfg) != PFE_OK)) {
        return PFE_EINVAL;
    }
    for (uint32_t i = 0U; i < cfg->n_vehicles; i++) {
        if (cfg->vehicle[i] == NULL) {
            return PFE_EINVAL;
        }
    }
    const uint32_t n = cfg->n_vehicles;
    uint64_t mass = 0U;
    uint64_t eta_sum = 0U;
    uint64_t brake = 0U;
    uint64_t aux = 0U;
    pfe_vehicle_t *obj = &pl->object;
    obj->air_q32 = 0;
    obj->mass_fuel_q32 = 0;
    obj->roll_q32 = 0;
    for (uint32_t i = 0U; i < n; i++) {
        const pfe_vehicle_calib_t *c = cfg->vehicle[i];
        /* Sums of per-vehicle coefficients (eq. 4.6, 4.8, 3.7): the per-vehicle
         * bounds of pfe_vehicle.c times 32 stay below 2^36. */
        obj->air_q32 += pl->position[i].air_q32;
        obj->mass_fuel_q32 += pl->position[i].mass_fuel_q32;
        obj->roll_q32 += pl->position[i].roll_q32;
        mass += c->mass_kg;
        eta_sum += c->eta_ppm;
        brake += c->brake_max_n;
        aux += c->power_aux_w;
    }
    pl->same_as_previous = 0U;
    for (uint32_t i = 1U; i < n; i++) {
        if (same_fuel_model(&pl->position[i], &pl->position[i - 1U])) {
            pl->same_as_previous |= 1U << i;
        }
    }
    for (uint32_t i = n; i < PFE_MAX_VEHICLES; i++) {
        pl->position[i] = pl->position[0];
        pl->position[i].power_aux_w = 0U;
    }
    /* Formation drag: the position with the largest air_i / m_i, compared
     * by cross-multiplication (air_q32 < 2^17, m <= 1e5 < 2^17). */
    uint32_t most = 0U;
    for (uint32_t i = 1U; i < n; i++) {
        if (((uint64_t)pl->position[i].air_q32 * cfg->vehicle[most]->mass_kg) >
            ((uint64_t)pl->position[most].air_q32 * cfg->vehicle[i]->mass_kg)) {
            most = i;
        }
    }
    /* air < 2^17 times M < 2^22: below 2^39; c <= N max air <= 2^22. */
    const int64_t formation = (int64_t)pfe_udiv_round_u64((uint64_t)pl->position[most].air_q32 * mass,
                                                          cfg->vehicle[most]->mass_kg) - obj->air_q32;
    const int64_t c_max = (int64_t)PFE_FORMATION_AIR_MAX_Q32;
    pl->formation_air_q32 = (uint32_t)((formation < 0) ? 0 : ((formation > c_max) ? c_max : formation));
    const pfe_vehicle_calib_t *wp = cfg->vehicle[weakest(cfg, 1)];
    const pfe_vehicle_calib_t *wt = cfg->vehicle[weakest(cfg, 0)];
    pl->n_vehicles = n;
    pl->gap_mm = cfg->gap_mm;
    pl->mass_kg = (uint32_t)mass; /* <= 32 * 1e5 */
    pl->gravity_um_s2 = cfg->env->gravity_um_s2;
    pl->gravity_q32 = (int64_t)pfe_udiv_round_u64((uint64_t)cfg->env->gravity_um_s2 << 26, POW5_6);
    pl->roll_force_q32 = obj->roll_q32 * (int64_t)cfg->env->gravity_um_s2;
    /* 10^6 * 2^30 / M <= 2^40 (M >= PFE_MASS_MIN_KG): shift 0 .. 10 */
    uint32_t inv_shift = 0U;
    pl->inv_mass_m = pfe_mantissa_i32((int64_t)pfe_udiv_round_u64(1000000ULL << 30, mass), 0U,
                                      &inv_shift);
    const uint32_t inv_scale = 1U << inv_shift;
    pl->inv_mass_scale = (int32_t)inv_scale;
    /* M [kg] * 20 m/s^2 * 4 <= 3.2e6 * 80 < 2^28 */
    pl->force_limit_q2 = (int32_t)mass * (PFE_ACCEL_MAX_UM_S2 / 1000000) * 4;
    obj->mass_q32 = (int64_t)pfe_udiv_round_u64(mass << 26, POW5_6);
    /* eq. 4.14 with eta_mean = eta_sum / n: 10^9 * 2^20 * n / (eta_sum * rho_d). */
    obj->fuel_q20 = (int64_t)pfe_udiv_round_u64((1000000000ULL << 20) * n,
                                                eta_sum * cfg->env->fuel_energy_j_ml);
    /* eq. 4.4: (P_k / m_k) * M, rounded down; <= 2e6 * 32 fits 32 bits. */
    obj->power_max_w = (uint32_t)(((uint64_t)wp->power_max_w * mass) / wp->mass_kg);
    obj->traction_max_n = (uint32_t)(((uint64_t)wt->traction_max_n * mass) / wt->mass_kg);
    obj->brake_max_n = (uint32_t)brake; /* eq. 4.5 */
    obj->power_aux_w = (uint32_t)aux;
    obj->reduction_bp = 0U;
    return PFE_OK;
}

int32_t pfe_platoon_force_max_n(const pfe_platoon_t *pl, int32_t speed_mm_s)
{
    const int32_t v = pfe_clamp_i32(speed_mm_s, 0, PFE_SPEED_MAX_MM_S);
    return pfe_platoon_force_max_v2_n(&pl->object, pl->formation_air_q32, v, (uint64_t)v * (uint32_t)v);
}

void pfe_platoon_grade_accel(const pfe_platoon_t *pl, int32_t grade_ppm, pfe_grade_accel_t *out)
{
    const int32_t grade = pfe_clamp_i32(grade_ppm, -PFE_GRADE_MAX_PPM, PFE_GRADE_MAX_PPM);
    /* gravity_q32 < 2^36, |grade| < 2^19: product below 2^55. */
    out->along_um_s2 = (int32_t)pfe_mul_q(pl->gravity_q32, grade, 32U);
    out->normal_um_s2 = (int32_t)pl->gravity_um_s2;
}

int32_t pfe_platoon_accel_um_s2(const pfe_platoon_t *pl, int32_t net_force_q2)
{
    const int32_t f = pfe_clamp_i32(net_force_q2, -pl->force_limit_q2, pl->force_limit_q2);
    /* inv_mass_scale <= 2 * 10^6 / M (the mantissa at least 2^30), so
     * |f| * scale <= M * 80 * 2 * 10^6 / M < 2^28: one 32 x 32 -> 64 bit
     * multiply, below 2^59; f / M * 10^6 * 4 over 2^2 is the acceleration */
    const int32_t f_scaled = f * pl->inv_mass_scale;
    return pfe_mulhr_i32(f_scaled, pl->inv_mass_m);
}
