/* pfe_pi.c - PI controller (contract in pfe_pi.h). */
#include "pfe_pi.h"

#include "pfe_fixed.h"

/* A gain within +-2^35 as m * 2^shift (pfe_pi.h, pfe_mantissa_i32()):
 * shift 0 .. 5, *scale 2^shift. */
static int32_t gain_mantissa(int64_t gain_q32, int32_t *scale)
{
    uint32_t shift = 0U;
    const int32_t m = pfe_mantissa_i32(gain_q32, 0U, &shift);
    const uint32_t sc = 1U << shift;
    *scale = (int32_t)sc;
    return m;
}

void pfe_pi_init(pfe_pi_t *pi, int64_t kp_q32, int64_t ki_q32, int32_t initial_output)
{
    const int64_t kp = pfe_clamp_i64(kp_q32, -PFE_PI_GAIN_MAX_Q32, PFE_PI_GAIN_MAX_Q32);
    const int64_t ki = pfe_clamp_i64(ki_q32, -PFE_PI_GAIN_MAX_Q32, PFE_PI_GAIN_MAX_Q32);
    pi->kp_m = gain_mantissa(kp, &pi->kp_scale);
    pi->ki_m = gain_mantissa(ki, &pi->ki_scale);
    /* |ki| e <= 2^53: e <= 2^53 / |ki|, at most PFE_PI_ERROR_MAX; |ki| >= 2^28
     * below that limit, so the quotient fits 32 bits. */
    const uint64_t ki_abs = (ki < 0) ? (uint64_t)(-ki) : (uint64_t)ki;
    const uint64_t e_max = (ki_abs > 0U) ? (((uint64_t)1 << 53) / ki_abs) : (uint64_t)PFE_PI_ERROR_MAX;
    pi->rate_limited = e_max < (uint64_t)PFE_PI_ERROR_MAX;
    pi->rate_error_max = pi->rate_limited ? (int32_t)e_max : PFE_PI_ERROR_MAX;
    pi->integral_q4 = pfe_clamp_i32(initial_output, -PFE_PI_OUT_MAX, PFE_PI_OUT_MAX) * 16;
}
