/* pfe_identify.c - mass and aux power from the engine's fuel rate (contract in pfe_identify.h). */
#include "pfe_identify.h"

#include <stddef.h>

#include "pfe_fixed.h"
#include "pfe_vehicle.h" /* pfe_vehicle_init: the drag coefficient as the estimator holds it */

#define Q24_ONE 16777216ULL          /* 2^24 */
#define Q32_ONE 4294967296ULL        /* 2^32 */
#define UW_PER_NW_Q32 4294967LL      /* round(2^32 / 1000) */
#define VAR_MAX_W2 17592186044416LL  /* 2^44 */
#define SXX_MAX 17592186044416LL     /* 2^44 > (2 * 10^5)^2 * 2^8: the bound of Sxx */
#define SXY_MAX 281474976710656LL    /* 2^48 > 2 * 10^5 * 4 * 10^6 * 2^8: the bound of |Sxy| */
/* (PFE_ID_CONVERGED_INV_REL^2 * 10^6) / 2^16, rounded up (6104): the
 * convergence test with both sides divided by 2^16 (see converged_now). */
#define CONV_LHS_SCALE ((((uint64_t)PFE_ID_CONVERGED_INV_REL * PFE_ID_CONVERGED_INV_REL * 1000000ULL) + 65535ULL) >> 16U)

/* num / den rounded to nearest, halves away from zero; den in
 * [1, PFE_UDIV_SMALL_MAX] takes pfe_udiv_u64's cheap path. */
static int64_t sdiv_round(int64_t num, uint32_t den)
{
    if (num < 0) {
        return -(int64_t)pfe_udiv_round_u64((uint64_t)(-num), den);
    }
    return (int64_t)pfe_udiv_round_u64((uint64_t)num, den);
}

/* num / den rounded, den >= 1, with both shifted right until den < 2^16
 * so that the division takes pfe_udiv_u64's 32-bit path: relative error
 * below 2^-15 for a den that started at 2^15 or more, exact below. The
 * shift is found on 32 bits (a binary search of five steps) and applied
 * once. Used for the mass, where den < 2^45. */
static uint64_t udiv_norm(uint64_t num, uint64_t den)
{
    uint64_t n = num;
    uint64_t d = den;
    if (d > 0xFFFFFFFFULL) {
        d >>= 16U;
        n >>= 16U;
    }
    uint32_t d32 = (uint32_t)d; /* den < 2^45: d < 2^29 here */
    uint32_t sh = 0U;
    if (d32 >= 0x1000000U) {
        d32 >>= 8U;
        sh += 8U;
    }
    if (d32 >= 0x100000U) {
        d32 >>= 4U;
        sh += 4U;
    }
    if (d32 >= 0x40000U) {
        d32 >>= 2U;
        sh += 2U;
    }
    if (d32 >= 0x20000U) {
        d32 >>= 1U;
        sh += 1U;
    }
    if (d32 >= 0x10000U) {
        d32 >>= 1U;
        sh += 1U;
    }
    return pfe_udiv_round_u64(n >> sh, d32);
}

/* x / 1000 rounded, by round(2^32 / 1000) and a shift: relative error
 * below 8e-8, for |x| < 2^40 (product below 2^63). */
static int64_t div1000(int64_t x)
{
    return pfe_rshift_round(x * UW_PER_NW_Q32, 32U);
}

static uint32_t sat_inc(uint32_t n)
{
    return (n < UINT32_MAX) ? (n + 1U) : n;
}

static uint32_t clamp_mass(int64_t m)
{
    return (uint32_t)pfe_clamp_i64(m, (int64_t)PFE_MASS_MIN_KG, (int64_t)PFE_MASS_MAX_KG);
}

/* The information back to the prior, around the current mass. */
static void reset_information(pfe_identify_t *id)
{
    id->mass0_kg = (int64_t)id->mass_kg;
    id->sxx = 0;
    id->sxy = 0;
    id->var_w2 = 0;
    id->n_mass = 0U;
    id->have_mean = false;
    id->have_prev = false;
    id->win_on = false;
    id->pend_on = false;
}

int pfe_identify_init(pfe_identify_t *id, const pfe_vehicle_calib_t *seed,
                      const pfe_env_calib_t *env)
{
    if (id == NULL) {
        return PFE_EINVAL;
    }
    *id = (pfe_identify_t){0};
    id->mass_kg = pfe_default_vehicle.mass_kg;
    id->aux_w = pfe_default_vehicle.power_aux_w;
    pfe_vehicle_t veh;
    if (pfe_vehicle_init(&veh, seed, env, 0U) != PFE_OK) {
        return PFE_EINVAL;
    }
    /* eta rho_d in mW per nL/s: eta_ppm * rho_d [J/mL] / 10^9; times 2^24.
     * eta_ppm * rho_d <= 10^6 * 60000 < 2^36: the shifted product < 2^60,
     * the result < 60 * 2^24 < 2^30. */
    id->fuel_power_q24 = (uint32_t)pfe_udiv_round_u64(
        ((uint64_t)seed->eta_ppm * (uint64_t)env->fuel_energy_j_ml) * Q24_ONE, 1000000000ULL);
    /* < 2^17 for a calibration that passed its check (pfe_vehicle.h). */
    id->air_full_q32 = (uint32_t)veh.air_q32;
    id->air_q32 = id->air_full_q32;
    /* cr [ppm] * 2^32 / 10^6, cr <= 0.1: < 2^29. */
    id->roll_q32 = (uint32_t)pfe_udiv_round_u64((uint64_t)seed->roll_coef_ppm * Q32_ONE, 1000000ULL);
    id->gravity_um_s2 = env->gravity_um_s2;
    id->rot_mass_kg = seed->rot_mass_kg;
    id->mass_kg = seed->mass_kg;
    id->aux_w = seed->power_aux_w;
    id->mass0_kg = (int64_t)seed->mass_kg;
    id->ready = true;
    return PFE_OK;
}

int pfe_identify_set_drag_reduction(pfe_identify_t *id, uint32_t reduction_bp)
{
    if ((id == NULL) || !id->ready || (reduction_bp > 10000U)) {
        return PFE_EINVAL;
    }
    /* air_full_q32 < 2^17 times (10000 - phi) <= 10^4: < 2^31. */
    const uint32_t keep_bp = 10000U - reduction_bp;
    id->air_q32 = (uint32_t)pfe_udiv_round_u64((uint64_t)id->air_full_q32 * keep_bp, 10000U);
    id->have_prev = false;
    id->win_on = false;
    id->pend_on = false;
    return PFE_OK;
}

/* Gates of one sample apart from time and speed change (header). */
static pfe_id_result_t gate(const pfe_identify_sample_t *s, int64_t fuel_mw)
{
    if (!s->speed_valid || !s->grade_valid || !s->fuel_valid) {
        return PFE_ID_REJ_INVALID;
    }
    if ((s->speed_mm_s < PFE_ID_SPEED_MIN_MM_S) || (s->speed_mm_s > PFE_ID_SPEED_MAX_MM_S)) {
        return PFE_ID_REJ_SPEED;
    }
    if ((s->grade_ppm < -PFE_ID_GRADE_MAX_PPM) || (s->grade_ppm > PFE_ID_GRADE_MAX_PPM)) {
        return PFE_ID_REJ_GRADE;
    }
    if (s->braking) {
        return PFE_ID_REJ_BRAKE;
    }
    if ((fuel_mw < ((int64_t)PFE_ID_FUEL_POWER_MIN_W * 1000)) ||
        (fuel_mw > ((int64_t)PFE_POWER_MAX_W * 1000))) {
        return PFE_ID_REJ_FUEL;
    }
    return PFE_ID_USED;
}

/* Standard error of the mass within 1 / PFE_ID_CONVERGED_INV_REL of it:
 * var(m) = sigma^2 * 10^6 / (Sxx + I0) kg^2 <= (m / 20)^2, both sides
 * divided by 2^16: sigma^2 <= 2^44 times 6104 < 2^57; m^2 <= 10^10 < 2^34
 * times (Sxx + I0) / 2^16 < 2^29: < 2^63. */
static bool converged_now(const pfe_identify_t *id)
{
    const uint64_t lhs = (uint64_t)id->var_w2 * CONV_LHS_SCALE;
    const int64_t den = id->sxx + PFE_ID_PRIOR_INFO;
    const uint64_t info = (uint64_t)den >> 16U;
    const uint64_t m = (uint64_t)id->mass_kg;
    return lhs <= ((m * m) * info);
}

/* Residual e = dy - m dx of a window (W), squared and clipped to 2^44:
 * |dx| < 2^18, |dy| < 2^22, m <= 10^5: |m dx| / 1000 < 2^25, |e| < 2^26. */
static int64_t residual2(const pfe_identify_t *id, int64_t dx, int64_t dy)
{
    const int64_t e = dy - div1000((int64_t)id->mass_kg * dx);
    return pfe_clamp_i64(e * e, 0, VAR_MAX_W2);
}

/* One mass update from a window's dx [mW/kg], dy [W] and squared residual
 * (header, 3.). */
static void update_mass(pfe_identify_t *id, int64_t dx, int64_t dy, int64_t e2)
{
    if (id->n_mass == 0U) {
        id->var_w2 = e2;
    } else {
        id->var_w2 += pfe_rshift_round(e2 - id->var_w2, 4U);
    }
    /* Sxx <= 2^36 * 2^8 = 2^44, |Sxy| < 2^40 * 2^8 = 2^48 at steady state. */
    id->sxx = (id->sxx - pfe_rshift_round(id->sxx, PFE_ID_MASS_SHIFT)) + (dx * dx);
    id->sxy = (id->sxy - pfe_rshift_round(id->sxy, PFE_ID_MASS_SHIFT)) + (dx * dy);
    /* m = (1000 Sxy + I0 m0) / (Sxx + I0): |1000 Sxy| < 2^58, I0 m0 < 2^39. */
    const int64_t num = (1000 * id->sxy) + (PFE_ID_PRIOR_INFO * id->mass0_kg);
    const int64_t den = id->sxx + PFE_ID_PRIOR_INFO;
    id->mass_kg = (num <= 0) ? PFE_MASS_MIN_KG
                             : clamp_mass((int64_t)udiv_norm((uint64_t)num, (uint64_t)den));
    id->n_mass = sat_inc(id->n_mass);
    id->counters.mass_updates = sat_inc(id->counters.mass_updates);
    if (id->n_mass >= PFE_ID_CONVERGED_UPDATES) {
        id->converged = converged_now(id);
    }
}

/* Paux = mean(y) - m mean(x): m mean_x_q4 <= 10^5 * 1.6 * 10^6 < 2^38. */
static void update_aux(pfe_identify_t *id)
{
    const int64_t p_q4 = id->mean_y_q4 - div1000((int64_t)id->mass_kg * id->mean_x_q4);
    const int64_t p = pfe_rshift_round(p_q4, 4U);
    id->aux_w = (uint32_t)pfe_clamp_i64(p, 0, (int64_t)PFE_ID_AUX_MAX_W);
}

/* A state outside the bounds the updates keep (memory corrupted): the
 * means within the window bounds (times 16), the sums within theirs. */
static bool information_corrupted(const pfe_identify_t *id)
{
    const int64_t mx = 16LL * PFE_ID_X_MAX_MW_KG;
    const int64_t my = 16LL * (int64_t)PFE_POWER_MAX_W;
    return (id->sxx < 0) || (id->sxx > SXX_MAX) || (id->sxy > SXY_MAX) || (id->sxy < -SXY_MAX) ||
           (id->var_w2 < 0) || (id->var_w2 > VAR_MAX_W2) || (id->mean_x_q4 > mx) ||
           (id->mean_x_q4 < -mx) || (id->mean_y_q4 > my) || (id->mean_y_q4 < -my);
}

/* A window w is complete (header, 1. and 2.); s_mm_s is the sum of the
 * PFE_ID_SPEED_AVG speeds around its last sample. */
static void close_window(pfe_identify_t *id, const pfe_id_window_t *w, int32_t s_mm_s)
{
    /* T <= 20 * 250 ms: 2 T <= 10000, a 16-bit divisor; the sums are twice the trapezoids. */
    const uint32_t t2 = 2U * w->ms;
    /* The mean speeds' v^2 - v0^2 in (mm/s)^2 = 2 uJ/kg: the sums are below
     * 7 * 36000 < 2^18, their squares' difference below 2^36, divided by
     * PFE_ID_SPEED_AVG^2 (49) below 2^31, as for single speeds; in
     * nJ/kg * 2 it is 1000 times that. */
    const int64_t ke2 = sdiv_round(((int64_t)s_mm_s * s_mm_s) - ((int64_t)w->s0_mm_s * w->s0_mm_s),
                                   PFE_ID_SPEED_AVG * PFE_ID_SPEED_AVG);
    /* x: (nJ/kg * 2) / (ms * 2) = uW/kg, then mW/kg. |1000 ke2| < 2^41. */
    const int64_t x = div1000(sdiv_round((1000 * ke2) + w->spec2_nj_kg, t2));
    /* y: (uJ * 2) / (ms * 2) = mW, then W. mj ke2 <= 10^5 * 2^31 < 2^48. */
    const int64_t y2 = (w->fuel2_uj - w->air2_uj) - ((int64_t)id->rot_mass_kg * ke2);
    const int64_t y = div1000(sdiv_round(y2, t2));
    if ((x > PFE_ID_X_MAX_MW_KG) || (x < -PFE_ID_X_MAX_MW_KG) ||
        (y > (int64_t)PFE_POWER_MAX_W) || (y < -(int64_t)PFE_POWER_MAX_W)) {
        id->counters.windows_rejected = sat_inc(id->counters.windows_rejected);
        return;
    }
    if (!id->have_mean) {
        id->mean_x_q4 = 16 * x;
        id->mean_y_q4 = 16 * y;
        id->have_mean = true;
    } else {
        if (information_corrupted(id)) {
            reset_information(id); /* the bounds kept below cannot be left */
            return;
        }
        /* |dx| <= 2 * 10^5 < 2^18, |dy| <= 4 * 10^6 < 2^22. */
        const int64_t dx = x - pfe_rshift_round(id->mean_x_q4, 4U);
        const int64_t dy = y - pfe_rshift_round(id->mean_y_q4, 4U);
        const int64_t e2 = residual2(id, dx, dy);
        const int64_t floor_w2 = (int64_t)PFE_ID_RESIDUAL_FLOOR_W * PFE_ID_RESIDUAL_FLOOR_W;
        const int64_t var_w2 = (id->var_w2 > floor_w2) ? id->var_w2 : floor_w2;
        if ((id->n_mass >= PFE_ID_OUTLIER_AFTER) && (e2 > (16 * var_w2))) {
            /* An outlier: neither in the means nor in the mass; sigma^2
             * still learns of it (clipped to 16 sigma^2, at most 2^44), so
             * that residuals that stay large are accepted again. */
            const int64_t grown = id->var_w2 + pfe_rshift_round(15 * id->var_w2, 4U);
            id->var_w2 = (grown < VAR_MAX_W2) ? grown : VAR_MAX_W2;
            id->counters.windows_rejected = sat_inc(id->counters.windows_rejected);
            return;
        }
        id->mean_x_q4 += x - pfe_rshift_round(id->mean_x_q4, PFE_ID_MEAN_SHIFT);
        id->mean_y_q4 += y - pfe_rshift_round(id->mean_y_q4, PFE_ID_MEAN_SHIFT);
        if ((dx >= PFE_ID_EXCITE_MW_KG) || (dx <= -PFE_ID_EXCITE_MW_KG)) {
            update_mass(id, dx, dy, e2);
        }
    }
    id->counters.windows_used = sat_inc(id->counters.windows_used);
    id->since_window_ms = 0U;
    update_aux(id);
}

/* Sum of the PFE_ID_SPEED_AVG speeds in the ring, mm/s: < 7 * 36000 < 2^18. */
static int32_t hist_sum(const pfe_identify_t *id)
{
    int32_t sum = 0;
    for (uint32_t k = 0U; k < PFE_ID_SPEED_AVG; k++) {
        sum += id->hist_mm_s[k];
    }
    return sum;
}

static void hist_push(pfe_identify_t *id, int32_t v_mm_s)
{
    id->hist_mm_s[id->hist_i] = v_mm_s;
    id->hist_i = (id->hist_i + 1U) % PFE_ID_SPEED_AVG;
    id->hist_n = (id->hist_n < PFE_ID_SPEED_AVG) ? (id->hist_n + 1U) : PFE_ID_SPEED_AVG;
}

/* The interval from the previous sample to this one (speed v_mm_s and
 * the trapezoid terms), in a run of consecutive samples (header, 1.). */
static void add_interval(pfe_identify_t *id, int32_t v_mm_s, uint32_t dt_ms, int64_t fuel_mw,
                         int64_t air_mw, int64_t spec_uw)
{
    hist_push(id, v_mm_s);
    if (!id->win_on) {
        /* the previous sample starts a window once PFE_ID_SPEED_HALF come
         * before it: the ring holds those, it and this one */
        if (id->hist_n < (PFE_ID_SPEED_HALF + 2U)) {
            return;
        }
        id->win_on = true;
        id->win = (pfe_id_window_t){0};
    }
    /* (a + b) * dt: fuel and air < 2^32 * 250 < 2^40, spec < 2^27 * 250
     * < 2^35, per interval; PFE_ID_WINDOW_INTERVALS (20) add 4.4 bits. */
    const int64_t dt = (int64_t)dt_ms;
    pfe_id_window_t *w = &id->win;
    w->fuel2_uj += (id->prev_fuel_mw + fuel_mw) * dt;
    w->air2_uj += (id->prev_air_mw + air_mw) * dt;
    w->spec2_nj_kg += (id->prev_spec_uw_kg + spec_uw) * dt;
    w->ms += dt_ms;
    w->n++;
    if (w->n == PFE_ID_SPEED_HALF) {
        /* the ring is full (PFE_ID_SPEED_HALF + 2 + 3 - 1 >= 7 speeds) and
         * centred on this window's first sample, the last one of the
         * window before it */
        w->s0_mm_s = hist_sum(id);
        if (id->pend_on) {
            close_window(id, &id->pend, w->s0_mm_s);
            id->pend_on = false;
        }
    }
    if (w->n >= PFE_ID_WINDOW_INTERVALS) {
        id->pend = *w;
        id->pend_on = true;
        id->win = (pfe_id_window_t){0};
    }
}

/* Interval time in ms from the sample times, sub-millisecond rest carried;
 * returns false for time going back or an interval out of range. */
static bool interval_ms(pfe_identify_t *id, uint64_t now_us, uint32_t *dt_ms)
{
    if (!id->have_time || (now_us < id->last_us)) {
        id->have_time = true;
        id->last_us = now_us;
        id->frac_us = 0U;
        return false;
    }
    const uint64_t d = now_us - id->last_us;
    id->last_us = now_us;
    if (d > ((uint64_t)PFE_ID_DT_MAX_MS * 1000U)) {
        id->frac_us = 0U;
        *dt_ms = PFE_ID_DT_MAX_MS + 1U;
        return false;
    }
    const uint32_t total = (uint32_t)d + id->frac_us;
    *dt_ms = total / 1000U;
    id->frac_us = total % 1000U;
    return (*dt_ms >= PFE_ID_DT_MIN_MS) && (*dt_ms <= PFE_ID_DT_MAX_MS);
}

static void track_stop(pfe_identify_t *id, const pfe_identify_sample_t *s, uint32_t dt_ms)
{
    if (s->speed_valid && (s->speed_mm_s < PFE_ID_STOP_MM_S)) {
        const uint32_t was = id->stop_ms;
        id->stop_ms = ((UINT32_MAX - was) > dt_ms) ? (was + dt_ms) : UINT32_MAX;
        if ((was < PFE_ID_STOP_RESET_MS) && (id->stop_ms >= PFE_ID_STOP_RESET_MS)) {
            reset_information(id);
            id->converged = false;
        }
    } else {
        id->stop_ms = 0U;
    }
}

/* g (cr cos(alpha) + sin(alpha)) in um/s^2 for |grade| <= PFE_ID_GRADE_MAX_PPM
 * (eq. 3.5, 3.6): cos = 1 / sqrt(1 + t^2) ~ 1 - t^2/2 + 3 t^4/8, error below
 * 5 t^6 / 16 = 8e-8 at 8 %, and sin = t cos; in Q30. Cheaper than
 * pfe_grade_accel's table and Newton step, which the whole grade range needs. */
static int64_t specific_force_um_s2(const pfe_identify_t *id, int32_t grade_ppm)
{
    /* grade * 2^30 / 10^6 = grade * round(2^50 / 10^6) / 2^20; |grade| <=
     * 8e4: below 2^27. t^2 < 2^23, t^4 term < 2^15. */
    const int64_t t_q30 = pfe_rshift_round((int64_t)grade_ppm * 1125899907LL, 20U);
    const int64_t x = pfe_rshift_round(t_q30 * t_q30, 30U);
    const int64_t cos_q30 = (1073741824LL - (x / 2)) + pfe_rshift_round(3 * x * x, 33U);
    const int64_t sin_q30 = pfe_rshift_round(t_q30 * cos_q30, 30U);
    /* g < 2^24 times cos, |sin| <= 2^30: < 2^54; cr_q32 < 2^29 times
     * g cos < 2^24: < 2^53. */
    const int32_t cos32 = (int32_t)cos_q30;
    const int32_t sin32 = (int32_t)sin_q30;
    const int64_t g = (int64_t)id->gravity_um_s2;
    const int32_t normal = (int32_t)pfe_rshift_round(g * cos32, 30U);
    const int64_t along = pfe_rshift_round(g * sin32, 30U);
    return along + pfe_rshift_round((int64_t)id->roll_q32 * normal, 32U);
}

/* |v - v_prev| beyond PFE_ID_ACCEL_MAX_UM_S2 * dt + PFE_ID_SPEED_MARGIN_MM_S:
 * |dv| [mm/s] * 1000 against a_max [mm/s^2] * dt [ms] + margin [mm/s] * 1000;
 * both below 2^30. */
static bool speed_jump(int32_t v_prev, int32_t v, uint32_t dt_ms)
{
    const int64_t dv = (v > v_prev) ? ((int64_t)v - v_prev) : ((int64_t)v_prev - v);
    return (dv * 1000) > ((((int64_t)PFE_ID_ACCEL_MAX_UM_S2 / 1000) * (int64_t)dt_ms) +
                          ((int64_t)PFE_ID_SPEED_MARGIN_MM_S * 1000));
}

static pfe_id_result_t reject(pfe_identify_t *id, pfe_id_result_t why)
{
    id->counters.samples_rejected = sat_inc(id->counters.samples_rejected);
    return why;
}

pfe_id_result_t pfe_identify_step(pfe_identify_t *id, const pfe_identify_sample_t *s)
{
    if (id == NULL) {
        return PFE_ID_REJ_INVALID;
    }
    if ((s == NULL) || !id->ready) {
        id->have_prev = false;
        id->win_on = false;
        id->pend_on = false;
        return reject(id, PFE_ID_REJ_INVALID);
    }
    uint32_t dt_ms = 0U;
    const bool dt_ok = interval_ms(id, s->now_us, &dt_ms);
    const uint32_t dt_seen = (dt_ms <= PFE_ID_DT_MAX_MS) ? dt_ms : PFE_ID_DT_MAX_MS;
    track_stop(id, s, dt_seen);
    id->since_window_ms = ((UINT32_MAX - id->since_window_ms) > dt_seen)
                              ? (id->since_window_ms + dt_seen) : UINT32_MAX;
    if (id->since_window_ms > PFE_ID_MEAN_RESTART_MS) {
        id->have_mean = false;
    }
    /* eta rho_d fc in mW: fc clamped to 2^30 (LFE1 ends at 8.9 * 10^8 nL/s)
     * times fuel_power_q24 < 2^30: < 2^60. */
    const uint32_t fc = (s->fuel_rate_nl_s < (1UL << 30U)) ? s->fuel_rate_nl_s : (1UL << 30U);
    const uint64_t fuel_q24 = (uint64_t)fc * id->fuel_power_q24;
    const int64_t fuel_mw = pfe_rshift_round((int64_t)fuel_q24, 24U);
    const pfe_id_result_t g = gate(s, fuel_mw);
    if (g != PFE_ID_USED) {
        id->have_prev = false;
        id->win_on = false;
        id->pend_on = false;
        return reject(id, g);
    }
    const int32_t v = s->speed_mm_s; /* in [8000, 36000] from here */
    /* k v^3 in mW: air_q32 < 2^17 times v^2 < 2^31 is < 2^48, / 2^16 < 2^32;
     * times v < 2^16: < 2^48, / 2^16: < 2^32. */
    const uint32_t v2 = (uint32_t)v * (uint32_t)v;
    const uint64_t f_q32 = (uint64_t)id->air_q32 * v2;
    const int64_t f_q16 = pfe_rshift_round((int64_t)f_q32, 16U);
    const int64_t air_mw = pfe_mul_q(f_q16, v, 16U);
    /* v g (cr cos + sin) in uW/kg: |g sin| < 8 * 10^5, cr g cos < 10^6 um/s^2;
     * times v: < 2^36; times round(2^32 / 1000) < 2^23: < 2^59. */
    const int64_t resist_um_s2 = specific_force_um_s2(id, s->grade_ppm);
    const int64_t spec_uw = pfe_rshift_round(((int64_t)v * resist_um_s2) * UW_PER_NW_Q32, 32U);

    pfe_id_result_t result = PFE_ID_USED;
    if (!dt_ok || !id->have_prev) {
        /* a new run of consecutive samples starts here */
        result = id->have_prev ? PFE_ID_REJ_TIME : PFE_ID_USED;
        id->win_on = false;
        id->pend_on = false;
        id->hist_n = 0U;
        hist_push(id, v);
    } else if (speed_jump(id->prev_speed_mm_s, v, dt_ms)) {
        id->have_prev = false;
        id->win_on = false;
        id->pend_on = false;
        return reject(id, PFE_ID_REJ_ACCEL);
    } else {
        add_interval(id, v, dt_ms, fuel_mw, air_mw, spec_uw);
    }
    id->have_prev = true;
    id->prev_speed_mm_s = v;
    id->prev_fuel_mw = fuel_mw;
    id->prev_air_mw = air_mw;
    id->prev_spec_uw_kg = spec_uw;
    if (result == PFE_ID_USED) {
        id->counters.samples_used = sat_inc(id->counters.samples_used);
        return result;
    }
    return reject(id, result);
}

uint32_t pfe_identify_mass_kg(const pfe_identify_t *id)
{
    return (id != NULL) ? id->mass_kg : 0U;
}

uint32_t pfe_identify_aux_power_w(const pfe_identify_t *id)
{
    return (id != NULL) ? id->aux_w : 0U;
}

bool pfe_identify_converged(const pfe_identify_t *id)
{
    return (id != NULL) && id->converged;
}

const pfe_identify_counters_t *pfe_identify_counters(const pfe_identify_t *id)
{
    return (id != NULL) ? &id->counters : NULL;
}

int pfe_identify_restore(pfe_identify_t *id, uint32_t mass_kg, uint32_t aux_w, bool converged)
{
    if ((id == NULL) || !id->ready || (mass_kg < PFE_MASS_MIN_KG) || (mass_kg > PFE_MASS_MAX_KG) ||
        (aux_w > PFE_ID_AUX_MAX_W)) {
        return PFE_EINVAL;
    }
    id->mass_kg = mass_kg;
    id->aux_w = aux_w;
    id->converged = converged;
    reset_information(id);
    return PFE_OK;
}
