/* pfe_pi.c - PI controller (contract in pfe_pi.h). */
#include "pfe_pi.h"

#include "pfe_fixed.h"

void pfe_pi_init(pfe_pi_t *pi, int64_t kp_q32, int64_t ki_q32, int32_t initial_output)
{
    pi->kp_q32 = pfe_clamp_i64(kp_q32, -PFE_PI_GAIN_MAX_Q32, PFE_PI_GAIN_MAX_Q32);
    pi->ki_q32 = pfe_clamp_i64(ki_q32, -PFE_PI_GAIN_MAX_Q32, PFE_PI_GAIN_MAX_Q32);
    pi->integral_q4 = pfe_clamp_i32(initial_output, -PFE_PI_OUT_MAX, PFE_PI_OUT_MAX) * 16;
}

int32_t pfe_pi_step(pfe_pi_t *pi, int32_t error, uint32_t dt_q16, int32_t out_min, int32_t out_max)
{
    const int32_t hi = pfe_clamp_i32(out_max, -PFE_PI_OUT_MAX, PFE_PI_OUT_MAX);
    const int32_t lo = pfe_clamp_i32((out_min <= out_max) ? out_min : out_max, -PFE_PI_OUT_MAX, hi);
    const int32_t e = pfe_clamp_i32(error, -PFE_PI_ERROR_MAX, PFE_PI_ERROR_MAX);
    const uint32_t dt = (dt_q16 > PFE_PI_DT_MAX_Q16) ? PFE_PI_DT_MAX_Q16 : dt_q16;

    /* kp < 2^35 and |e| <= 2^25: below 2^60; P clamped to +-2^27. */
    const int32_t p = (int32_t)pfe_clamp_i64(pfe_mul_q(pi->kp_q32, e, 32U), -(1 << 27), 1 << 27);
    /* ki * e / 2^24 is U/s * 2^8 (< 2^36); times dt (<= 2^20) / 2^20 is
     * U * 2^4 (< 2^36), clamped to +-2^29 so that I + step fits 32 bits. */
    const int64_t rate_q8 = pfe_mul_q(pi->ki_q32, e, 24U);
    const int32_t step_q4 = (int32_t)pfe_clamp_i64(pfe_rshift_round(rate_q8 * (int64_t)dt, 20U),
                                                   -(1 << 29), 1 << 29);

    /* |I| <= 2^30, |step| <= 2^29, |P| <= 2^27: every sum below 2^31. */
    const int32_t trial_q4 = pi->integral_q4 + step_q4;
    const int32_t trial = p + ((trial_q4 + 8) >> 4);
    const int winding_up = (trial > hi) && (step_q4 > 0);
    const int winding_down = (trial < lo) && (step_q4 < 0);
    const int32_t integral = (winding_up || winding_down) ? pi->integral_q4 : trial_q4;
    pi->integral_q4 = pfe_clamp_i32(integral, lo * 16, hi * 16);
    return pfe_clamp_i32(p + ((pi->integral_q4 + 8) >> 4), lo, hi);
}
