/* pfe_pi.c - PI controller (contract in pfe_pi.h). */
#include "pfe_pi.h"

#include "pfe_fixed.h"

void pfe_pi_init(pfe_pi_t *pi, int64_t kp_q32, int64_t ki_q32, int32_t initial_output)
{
    pi->kp_q32 = pfe_clamp_i64(kp_q32, -PFE_PI_GAIN_MAX_Q32, PFE_PI_GAIN_MAX_Q32);
    pi->ki_q32 = pfe_clamp_i64(ki_q32, -PFE_PI_GAIN_MAX_Q32, PFE_PI_GAIN_MAX_Q32);
    pi->integral_q16 = (int64_t)initial_output * 65536;
}

int32_t pfe_pi_step(pfe_pi_t *pi, int32_t error, uint32_t dt_q16, int32_t out_min, int32_t out_max)
{
    const int32_t lo = (out_min <= out_max) ? out_min : out_max;
    const int64_t lo_q16 = (int64_t)lo * 65536;
    const int64_t hi_q16 = (int64_t)out_max * 65536;
    const int32_t e = pfe_clamp_i32(error, -PFE_PI_ERROR_MAX, PFE_PI_ERROR_MAX);
    const uint32_t dt = (dt_q16 > PFE_PI_DT_MAX_Q16) ? PFE_PI_DT_MAX_Q16 : dt_q16;

    /* kp, ki < 2^35 and |e| <= 2^25: below 2^60. */
    const int64_t p_q16 = pfe_mul_q(pi->kp_q32, e, 16U);
    /* ki * e / 2^24 is U/s * 2^8 (< 2^36); times dt (< 2^21) / 2^8: U * 2^16. */
    const int64_t rate_q8 = pfe_mul_q(pi->ki_q32, e, 24U);
    const int64_t step_q16 = pfe_rshift_round(rate_q8 * (int64_t)dt, 8U);

    const int64_t trial = p_q16 + pi->integral_q16 + step_q16;
    const int winding_up = (trial > hi_q16) && (step_q16 > 0);
    const int winding_down = (trial < lo_q16) && (step_q16 < 0);
    if (!winding_up && !winding_down) {
        pi->integral_q16 += step_q16;
    }
    pi->integral_q16 = pfe_clamp_i64(pi->integral_q16, lo_q16, hi_q16);

    const int64_t out_q16 = pfe_clamp_i64(p_q16 + pi->integral_q16, lo_q16, hi_q16);
    return (int32_t)pfe_clamp_i64(pfe_rshift_round(out_q16, 16U), lo, out_max);
}
