/*
 * pfe_vehicle.h - one truck: forces and fuel (thesis chapter 3).
 *
 * pfe_vehicle_init() turns a calibration into integer coefficients once;
 * the step-time functions then need only multiplications and shifts.
 *
 *   air drag      eq. 3.4   Fa = 1/2 rho cw Af v^2 (1 - phi_i(d)/100)
 *   rolling       eq. 3.5   Fr = cr m g cos(alpha)
 *   grade         eq. 3.6   Fg = m g sin(alpha)
 *   fuel force    eq. 3.7   Fw = (m + mj) a + Fa + Fr + Fg
 *   fuel rate     eq. 3.8 to 3.11   fc = delta (Fw v + Paux) / (eta rho_d),
 *                           delta = 1 if Fw > 0 else 0 (fuel cut)
 *   force limits  Fw <= min(Pmax / v, traction_max), Fw >= -Fb_max
 *
 * Units: speed mm/s in [0, PFE_SPEED_MAX_MM_S]; acceleration um/s^2 in
 * [-PFE_ACCEL_MAX_UM_S2, PFE_ACCEL_MAX_UM_S2]; grade ppm (grade = tan alpha)
 * in [-PFE_GRADE_MAX_PPM, PFE_GRADE_MAX_PPM]; forces N; power mW or W as
 * named; fuel rate nL/s. Inputs outside those ranges are clamped by the
 * caller (the estimator clamps and flags); inside them no intermediate
 * exceeds 2^60, which each function body shows.
 */
#ifndef PFE_VEHICLE_H
#define PFE_VEHICLE_H

#include <stdint.h>

#include "pfe_calib.h"
#include "pfe_fixed.h"

#define PFE_ACCEL_MAX_UM_S2 20000000 /* 20 m/s^2, beyond any truck */
#define PFE_FUEL_POWER_MAX_MW 1099511627776LL /* 2^40 mW: pfe_fuel_rate_nl_s() clamps to it */

/* Coefficients of one vehicle at one platoon position. Q32 mass-like
 * coefficients hold kg * 2^32 / 10^6, so (coef * accel_um_s2) >> 32 is N. */
typedef struct {
    int64_t air_q32;        /* N per (mm/s)^2 * 2^32, including (1 - phi/100) */
    int64_t mass_q32;       /* m */
    int64_t mass_fuel_q32;  /* m + mj (eq. 3.7) */
    int64_t roll_q32;       /* cr * m */
    int64_t fuel_q20;       /* nL of fuel per mJ of work, * 2^20: 1 / (eta rho_d);
                             * 73224 for the defaults, so 1e-5 relative resolution */
    uint32_t power_max_w;
    uint32_t traction_max_n;
    uint32_t brake_max_n;
    uint32_t power_aux_w;
    uint32_t reduction_bp;  /* phi_i(d) used, 0.01 % */
} pfe_vehicle_t;

/* Gravity split along and across the road for one grade (eq. 3.5, 3.6). */
typedef struct {
    int32_t along_um_s2;    /* g sin(alpha) */
    int32_t normal_um_s2;   /* g cos(alpha) */
} pfe_grade_accel_t;

/*
 * Builds the coefficients. reduction_bp is phi_i(d) in 0.01 % (from
 * pfe_drag_reduction_bp()). Returns PFE_OK, or PFE_EINVAL for a NULL
 * argument, a calibration that fails its check, or reduction_bp > 10000.
 * Uses 64-bit division: call at configuration time, not in the step.
 */
int pfe_vehicle_init(pfe_vehicle_t *veh, const pfe_vehicle_calib_t *calib,
                     const pfe_env_calib_t *env, uint32_t reduction_bp);

/*
 * g sin(alpha) and g cos(alpha) for grade = tan(alpha), exactly (not the
 * small-angle forms): cos = 1 / sqrt(1 + grade^2) from a 17-entry table's
 * chord and one Newton step in Q30, error below 2e-9 over the grade range.
 * grade_ppm is clamped to +-PFE_GRADE_MAX_PPM.
 */
void pfe_grade_accel(int32_t grade_ppm, uint32_t gravity_um_s2, pfe_grade_accel_t *out);

/* Fa, rounded to the nearest N (eq. 3.4). */
int32_t pfe_vehicle_air_n(const pfe_vehicle_t *veh, int32_t speed_mm_s);

/* Fa + Fr + Fg, rounded N (eq. 3.4 to 3.6). */
int32_t pfe_vehicle_resistance_n(const pfe_vehicle_t *veh, int32_t speed_mm_s,
                                 const pfe_grade_accel_t *grade);

/* Fw of the fuel model, eq. 3.7, rounded N. */
int32_t pfe_vehicle_fuel_force_n(const pfe_vehicle_t *veh, int32_t speed_mm_s,
                                 int32_t accel_um_s2, const pfe_grade_accel_t *grade);

/*
 * pfe_vehicle_fuel_force_n() for one truck (coefficients from
 * pfe_vehicle_init(), not a platoon's sums), for a caller that holds
 * v2 = v * v with v in [0, PFE_SPEED_MAX_MM_S] and an acceleration already
 * within +-PFE_ACCEL_MAX_UM_S2: the same result, at less cost. One truck's
 * coefficients fit 32 bits (air_q32 < 2^17, mass_q32 and mass_fuel_q32 <
 * 2^30, roll_q32 < 2^26: pfe_vehicle.c), so each product is a single
 * 32 x 32 -> 64 bit multiply (air_q32 times v2 < 2^33: one multiply and one
 * multiply-accumulate). The sum stays below 2^60 (pfe_vehicle.c); its
 * rounded high word is the force, so no saturation is needed. Inline: the
 * estimator calls it for every position every 10 ms.
 */
static inline int32_t pfe_vehicle_truck_fuel_force_n(const pfe_vehicle_t *veh, uint64_t v2,
                                                     int32_t accel_um_s2,
                                                     const pfe_grade_accel_t *grade)
{
    const uint64_t air = (uint64_t)(uint32_t)veh->air_q32 * v2;
    const int64_t sum = ((int64_t)(int32_t)veh->mass_fuel_q32 * accel_um_s2) +
                        ((int64_t)(int32_t)veh->roll_q32 * grade->normal_um_s2) +
                        ((int64_t)(int32_t)veh->mass_q32 * grade->along_um_s2) + (int64_t)air;
    return (int32_t)pfe_rshift_round(sum, 32U);
}

/*
 * Largest wheel force: min(Pmax / v, traction_max) in N, Pmax / v rounded
 * down; at v = 0 the traction limit. Uses two 32-bit divisions.
 */
int32_t pfe_wheel_force_max_n(uint32_t power_max_w, uint32_t traction_max_n, int32_t speed_mm_s);

/*
 * Fuel rate, eq. 3.8 to 3.11: 0 when force_n <= 0 (fuel cut), else
 * (force_n * v + Paux) / (eta rho_d), in nL/s, rounded, saturating at
 * UINT32_MAX (4.29 L/s). fuel_q20 comes from pfe_vehicle_t. A speed below
 * 0 (outside the range above) counts as 0: the rate of Paux alone.
 */
static inline uint32_t pfe_fuel_rate_nl_s(int32_t force_n, int32_t speed_mm_s,
                                          uint32_t power_aux_w, int64_t fuel_q20)
{
    if (force_n <= 0) {
        return 0U; /* eq. 3.9: fuel cut */
    }
    /* N * mm/s = mW; 0 < force < 2^31 and 0 <= v < 2^31: unsigned, one
     * multiply-accumulate onto Paux (< 2^42 mW), below 2^63; clamped to 2^40
     * mW (1.1 GW) before scaling: with fuel_q20 < 2^22 the product stays
     * below 2^62. Inline: it runs for the platoon and every position every
     * 10 ms. */
    const uint32_t v = (speed_mm_s > 0) ? (uint32_t)speed_mm_s : 0U;
    const uint64_t power_mw = ((uint64_t)(uint32_t)force_n * v) + ((uint64_t)power_aux_w * 1000U);
    const uint64_t p = (power_mw < (uint64_t)PFE_FUEL_POWER_MAX_MW) ? power_mw
                                                                      : (uint64_t)PFE_FUEL_POWER_MAX_MW;
    /* p >= 0 and 0 < fuel_q20 < 2^22: an unsigned 64 x 32 bit product. */
    const uint64_t rate = ((p * (uint32_t)fuel_q20) + ((uint64_t)1 << 19)) >> 20;
    return (rate > (uint64_t)UINT32_MAX) ? UINT32_MAX : (uint32_t)rate;
}

#endif /* PFE_VEHICLE_H */
