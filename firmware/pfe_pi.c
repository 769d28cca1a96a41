/* pfe_pi.c - PI controller (contract in pfe_pi.h). */
#include "pfe_pi.h"

#include "pfe_fixed.h"

void pfe_pi_init(pfe_pi_t *pi, int64_t kp_q32, int64_t ki_q32, int32_t initial_output)
{
    pi->kp_q32 = pfe_clamp_i64(kp_q32, -PFE_PI_GAIN_MAX_Q32, PFE_PI_GAIN_MAX_Q32);
    pi->ki_q32 = pfe_clamp_i64(ki_q32, -PFE_PI_GAIN_MAX_Q32, PFE_PI_GAIN_MAX_Q32);
    pi->integral_q4 = pfe_clamp_i32(initial_output, -PFE_PI_OUT_MAX, PFE_PI_OUT_MAX) * 16;
}
