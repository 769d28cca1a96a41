/* pfe_vehicle.c - one truck: forces and fuel (contract in pfe_vehicle.h). */
#include "pfe_vehicle.h"

#include <stddef.h>

#include "pfe_fixed.h"

/* 10^6 = 2^6 * 15625; 10^12 = 2^12 * 244140625; 2 * 10^19 = 2^20 * 5^19. */
#define POW5_6 15625U
#define POW5_12 244140625ULL
#define POW5_19 19073486328125ULL

int pfe_vehicle_init(pfe_vehicle_t *veh, const pfe_vehicle_calib_t *calib,
                     const pfe_env_calib_t *env, uint32_t reduction_bp)
{
    if ((veh == NULL) || (pfe_calib_check_vehicle(calib) != PFE_OK) ||
        (pfe_calib_check_env(env) != PFE_OK) || (reduction_bp > 10000U)) {
        return PFE_EINVAL;
    }
    /* rho [g/m^3] * A [mm^2] * (1 - phi) [1e-4] <= 2000 * 2e7 * 1e4 = 4e14;
     * k [N/(mm/s)^2] = that / (2 * 10^19); times 2^32 = that * 2^12 / 5^19. */
    const uint32_t keep_bp = 10000U - reduction_bp;
    const uint64_t rho_a = (uint64_t)env->air_density_g_m3 * (uint64_t)calib->drag_area_mm2 *
                           (uint64_t)keep_bp;
    veh->air_q32 = (int64_t)pfe_udiv_round_u64(rho_a << 12, POW5_19);
    /* kg * 2^32 / 10^6 = kg * 2^26 / 5^6 = kg * 4295; m + mj <= 2e5 kg keeps it below 2^30. */
    veh->mass_q32 = (int64_t)pfe_udiv_round_u64((uint64_t)calib->mass_kg << 26, POW5_6);
    veh->mass_fuel_q32 = (int64_t)pfe_udiv_round_u64(
        ((uint64_t)calib->mass_kg + (uint64_t)calib->rot_mass_kg) << 26, POW5_6);
    /* cr [ppm] * m [kg] <= 1e10; * 2^32 / 10^12 = * 2^20 / 5^12. */
    veh->roll_q32 = (int64_t)pfe_udiv_round_u64(
        ((uint64_t)calib->roll_coef_ppm * (uint64_t)calib->mass_kg) << 20, POW5_12);
    /* nL per mJ = 10^3 / (eta rho_d) = 10^9 / (eta_ppm * rho_d); times 2^20. */
    veh->fuel_q20 = (int64_t)pfe_udiv_round_u64(
        1000000000ULL << 20, (uint64_t)calib->eta_ppm * (uint64_t)env->fuel_energy_j_ml);
    veh->power_max_w = calib->power_max_w;
    veh->traction_max_n = calib->traction_max_n;
    veh->brake_max_n = calib->brake_max_n;
    veh->power_aux_w = calib->power_aux_w;
    veh->reduction_bp = reduction_bp;
    return PFE_OK;
}

/* (a * b) / 2^shift rounded to nearest as pfe_mul_q(), for a caller whose
 * result fits 32 bits: one 32 x 32 -> 64 bit multiply and the low word of
 * the shifted sum (the same value as narrowing the full result). */
static inline int32_t mul_q_i32(int32_t a, int32_t b, uint32_t shift)
{
    const int64_t product = (int64_t)a * b;
    const uint32_t half_bit = shift - 1U;
    const uint64_t half = (uint64_t)1 << half_bit;
    const uint64_t sum = (uint64_t)product + half;
    return (int32_t)(uint32_t)(sum >> shift);
}

void pfe_grade_accel(int32_t grade_ppm, uint32_t gravity_um_s2, pfe_grade_accel_t *out)
{
    /* 1 / sqrt(1 + k / 64) in Q30, k = 0 .. 16: round(2^30 / sqrt(1 + k / 64)),
     * the first guess below, by linear interpolation over x =
     * grade^2 in 0 .. 0.25 (segments of 1/64: the chord of this convex function
     * lies above it by h^2 f'' / 8 <= (1/64)^2 * 0.75 / 8 = 2.3e-5 at most). */
    static const int32_t k_inv_sqrt_q30[17] = {
        1073741824, 1065450257, 1057347856, 1049427536, 1041682578, 1034106604,
        1026693558, 1019437682, 1012333500, 1005375799, 998559613,  991880210,
        985333074,  978913898,  972618566,  966443148,  960383883,
    };
    /* Every operand and result below fits 32 bits (the bounds beside each),
     * so each product is one 32 x 32 -> 64 bit multiply. */
    const int32_t one_q30 = (int32_t)1 << 30;
    const int32_t grade = pfe_clamp_i32(grade_ppm, -PFE_GRADE_MAX_PPM, PFE_GRADE_MAX_PPM);
    /* grade * 2^30 / 10^6 = grade * round(2^50 / 10^6) / 2^20; |grade| <= 5e5
     * keeps the product below 2^50 and the result below 2^29.1. */
    const int32_t g_q30 = mul_q_i32(grade, 1125899907, 20U);
    const int32_t x = mul_q_i32(g_q30, g_q30, 30U); /* grade^2 <= 0.25: <= 2^28 */
    const int32_t s = one_q30 + x;                /* 1 + grade^2 < 2^30.4 */
    /* 1/sqrt(1 + x): the table's chord (relative error <= 2.3e-5, the
     * difference of two entries below 2^23 times the offset in its segment
     * below 2^24: below 2^47), then one Newton step y <- y (3 - s y^2) / 2,
     * which squares the relative error (1.5 e^2: 8e-10, with the Q30
     * roundings below 2e-9). y stays within 2^30 (1 + 1e-8), so y^2 and
     * s y^2 are below 2^31, and 3 - s y^2, within 2^31 (1 +- 0.02), fits 32
     * bits unsigned: y times it is below 2^62. */
    const uint32_t top = (uint32_t)x >> 24; /* x <= 2^28: 0 .. 16 */
    const uint32_t seg = (top < 15U) ? top : 15U;
    const int32_t offset = x - (int32_t)(seg << 24);
    const int32_t y0 = k_inv_sqrt_q30[seg];
    const int32_t y0_step = k_inv_sqrt_q30[seg + 1U] - y0;
    const int32_t y = y0 + mul_q_i32(y0_step, offset, 24U);
    const int32_t y2 = mul_q_i32(y, y, 30U);
    const int32_t sy2 = mul_q_i32(s, y2, 30U);
    const uint32_t t = (3U * (uint32_t)one_q30) - (uint32_t)sy2;
    const uint64_t yt = ((uint64_t)(uint32_t)y * t) + ((uint64_t)1 << 30);
    const int32_t y_newton = (int32_t)(uint32_t)(yt >> 31);
    const int32_t sin_q30 = mul_q_i32(g_q30, y_newton, 30U);
    /* g < 2^24 and |sin|, cos <= 2^30: products below 2^54. */
    out->normal_um_s2 = mul_q_i32((int32_t)gravity_um_s2, y_newton, 30U);
    out->along_um_s2 = mul_q_i32((int32_t)gravity_um_s2, sin_q30, 30U);
}

int32_t pfe_vehicle_air_n(const pfe_vehicle_t *veh, int32_t speed_mm_s)
{
    /* air_q32 < 2^17 per vehicle, < 2^22 for a platoon; v <= 70000 < 2^17:
     * product below 2^56. */
    return pfe_sat_i32(pfe_mul_q(veh->air_q32 * (int64_t)speed_mm_s, speed_mm_s, 32U));
}

/* Fa + Fr + Fg in N * 2^32, one sum so that the result is rounded once.
 * air: < 2^56; roll_q32 < 2^26, mass_q32 < 2^30 per vehicle (2^31, 2^35 for
 * a platoon of PFE_MAX_VEHICLES) times g cos < 2^23.3 and |g sin| < 2^22.1:
 * the sum stays below 2^58. */
static int64_t resistance_q32(const pfe_vehicle_t *veh, int32_t speed_mm_s,
                              const pfe_grade_accel_t *grade)
{
    return (veh->air_q32 * (int64_t)speed_mm_s * (int64_t)speed_mm_s) +
           (veh->roll_q32 * (int64_t)grade->normal_um_s2) +
           (veh->mass_q32 * (int64_t)grade->along_um_s2);
}

int32_t pfe_vehicle_resistance_n(const pfe_vehicle_t *veh, int32_t speed_mm_s,
                                 const pfe_grade_accel_t *grade)
{
    return pfe_sat_i32(pfe_rshift_round(resistance_q32(veh, speed_mm_s, grade), 32U));
}

int32_t pfe_vehicle_fuel_force_n(const pfe_vehicle_t *veh, int32_t speed_mm_s,
                                 int32_t accel_um_s2, const pfe_grade_accel_t *grade)
{
    const int32_t a = pfe_clamp_i32(accel_um_s2, -PFE_ACCEL_MAX_UM_S2, PFE_ACCEL_MAX_UM_S2);
    /* One sum, rounded once: the resistance (< 2^58, see resistance_q32) plus
     * (m + mj) a with mass_fuel_q32 < 2^30 per vehicle (2^35 for a platoon)
     * and |a| <= 2^24.3, below 2^59.3: the total stays below 2^60. */
    const int64_t inertia = veh->mass_fuel_q32 * (int64_t)a;
    return pfe_sat_i32(pfe_rshift_round(inertia + resistance_q32(veh, speed_mm_s, grade), 32U));
}

int32_t pfe_wheel_force_max_n(uint32_t power_max_w, uint32_t traction_max_n, int32_t speed_mm_s)
{
    const uint32_t cap = (traction_max_n > (uint32_t)INT32_MAX) ? (uint32_t)INT32_MAX
                                                                 : traction_max_n;
    if (speed_mm_s <= 0) {
        return (int32_t)cap;
    }
    /* P [W] * 1000 / v [mm/s], split so every operand stays in 32 bits:
     * q kN exactly, then the remainder (< v <= 70000) times 1000. */
    const uint32_t v = (uint32_t)speed_mm_s;
    const uint32_t q = power_max_w / v;
    const uint32_t r = power_max_w % v;
    const uint32_t rest_n = (r * 1000U) / v;
    const uint64_t force = ((uint64_t)q * 1000U) + (uint64_t)rest_n;
    return (force < (uint64_t)cap) ? (int32_t)force : (int32_t)cap;
}
