/* pfe_calib.c - default calibration and range checks (contract in pfe_calib.h). */
#include "pfe_calib.h"

#include <stdbool.h>
#include <stddef.h>

#include "pfe_fixed.h"

/* docs/model.md, "The default calibration": each value's source; estimates
 * are marked there and here. */
const pfe_vehicle_calib_t pfe_default_vehicle = {
    .mass_kg = 40000U,
    .rot_mass_kg = 1200U,        /* estimate, about 3 % of m */
    .drag_area_mm2 = 6000000U,   /* cw 0.6 * Af 10 m^2 */
    .roll_coef_ppm = 7000U,      /* 0.007 */
    .power_max_w = 250000U,      /* estimate: holds about 73.7 km/h on 2 % */
    .traction_max_n = 100000U,   /* estimate: about a quarter of the weight of 40 t */
    .brake_max_n = 60000U,       /* thesis 3.1.1 */
    .power_aux_w = 4000U,        /* estimate */
    .eta_ppm = 400000U,          /* estimate, 0.40 */
};

const pfe_env_calib_t pfe_default_env = {
    .air_density_g_m3 = 1290U,
    .gravity_um_s2 = 9810000U,
    .fuel_energy_j_ml = 35800U,  /* about 43 MJ/kg * 0.835 kg/L */
};

/* docs/model.md: an estimated fit to published track results. */
const pfe_drag_table_t pfe_default_drag = {
    .gap_mm = {2000U, 4000U, 6000U, 8000U, 10000U, 15000U, 20000U, 30000U, 40000U, 60000U, 80000U},
    .reduction_bp = {
        {2800U, 1700U, 1200U, 900U, 800U, 500U, 400U, 300U, 200U, 100U, 100U},
        {4900U, 4300U, 3800U, 3400U, 3100U, 2500U, 2100U, 1600U, 1300U, 900U, 700U},
        {5400U, 4800U, 4200U, 3800U, 3500U, 2800U, 2400U, 1800U, 1500U, 1100U, 800U},
    },
};

/* Same gaps, no reduction anywhere: N separate trucks. */
const pfe_drag_table_t pfe_no_drag_reduction = {
    .gap_mm = {2000U, 4000U, 6000U, 8000U, 10000U, 15000U, 20000U, 30000U, 40000U, 60000U, 80000U},
    .reduction_bp = {{0U}},
};

const pfe_cruise_calib_t pfe_default_cruise = {
    .kp_milli_per_s = 300U,
    .ki_milli_per_s2 = 20U,
};

int pfe_calib_check_vehicle(const pfe_vehicle_calib_t *v)
{
    if (v == NULL) {
        return PFE_EINVAL;
    }
    const bool ok = (v->mass_kg >= PFE_MASS_MIN_KG) && (v->mass_kg <= PFE_MASS_MAX_KG) &&
                   (v->rot_mass_kg <= v->mass_kg) &&
                   (v->drag_area_mm2 <= PFE_DRAG_AREA_MAX_MM2) &&
                   (v->roll_coef_ppm <= 100000U) &&
                   (v->power_max_w > 0U) && (v->power_max_w <= PFE_POWER_MAX_W) &&
                   (v->traction_max_n > 0U) && (v->traction_max_n <= PFE_FORCE_MAX_N) &&
                   (v->brake_max_n <= PFE_FORCE_MAX_N) &&
                   (v->power_aux_w <= 100000U) &&
                   (v->eta_ppm >= 50000U) && (v->eta_ppm <= 1000000U);
    return ok ? PFE_OK : PFE_EINVAL;
}

int pfe_calib_check_env(const pfe_env_calib_t *env)
{
    if (env == NULL) {
        return PFE_EINVAL;
    }
    const bool ok = (env->air_density_g_m3 >= 500U) && (env->air_density_g_m3 <= 2000U) &&
                   (env->gravity_um_s2 >= 9700000U) && (env->gravity_um_s2 <= 9900000U) &&
                   (env->fuel_energy_j_ml >= 10000U) && (env->fuel_energy_j_ml <= 60000U);
    return ok ? PFE_OK : PFE_EINVAL;
}

int pfe_calib_check_drag(const pfe_drag_table_t *drag)
{
    if (drag == NULL) {
        return PFE_EINVAL;
    }
    for (uint32_t k = 0U; k < PFE_DRAG_POINTS; k++) {
        if ((k > 0U) && (drag->gap_mm[k] <= drag->gap_mm[k - 1U])) {
            return PFE_EINVAL;
        }
        for (uint32_t row = 0U; row < PFE_DRAG_ROWS; row++) {
            if (drag->reduction_bp[row][k] > 10000U) {
                return PFE_EINVAL;
            }
        }
    }
    return PFE_OK;
}

int pfe_calib_check_cruise(const pfe_cruise_calib_t *cruise)
{
    if (cruise == NULL) {
        return PFE_EINVAL;
    }
    const bool ok = (cruise->kp_milli_per_s > 0U) && (cruise->kp_milli_per_s <= 5000U) &&
                   (cruise->ki_milli_per_s2 <= 5000U);
    return ok ? PFE_OK : PFE_EINVAL;
}

uint32_t pfe_drag_reduction_bp(const pfe_drag_table_t *drag, uint32_t position,
                               uint32_t n_vehicles, uint32_t gap_mm)
{
    if (n_vehicles < 2U) {
        return 0U;
    }
    const uint32_t row = (position < PFE_DRAG_ROWS) ? position : (PFE_DRAG_ROWS - 1U);
    const uint16_t *r = drag->reduction_bp[row];
    if (gap_mm <= drag->gap_mm[0]) {
        return r[0];
    }
    for (uint32_t k = 1U; k < PFE_DRAG_POINTS; k++) {
        if (gap_mm <= drag->gap_mm[k]) {
            const uint32_t d0 = drag->gap_mm[k - 1U];
            const uint32_t span = drag->gap_mm[k] - d0;
            const int64_t dy = (int64_t)r[k] - (int64_t)r[k - 1U];
            /* |dy| <= 10000 and gap_mm - d0 < 2^32: product below 2^46. */
            const uint32_t into_mm = gap_mm - d0;
            const uint32_t half_span = span / 2U;
            const int64_t num = dy * (int64_t)into_mm;
            const int64_t half = (int64_t)half_span;
            const int64_t step = (num >= 0) ? ((num + half) / (int64_t)span)
                                            : -((-num + half) / (int64_t)span);
            const int64_t y = (int64_t)r[k - 1U] + step;
            return (uint32_t)y;
        }
    }
    return r[PFE_DRAG_POINTS - 1U];
}
