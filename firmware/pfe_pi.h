/*
 * pfe_pi.h - PI controller with output limits and anti-windup.
 *
 * The cruise control of the platoon simulation (thesis 5.2: the leader runs a
 * PI speed controller to the set speed). Generic in its units: the error in
 * some unit E, the output in some unit U (the model uses um/s and N).
 *
 *   u = clamp(kp * e + I, out_min, out_max)
 *   I += ki * e * dt, except while the output is saturated and the error
 *   would push it further (conditional integration); I itself is kept
 *   within [out_min, out_max], so a limit that moves (Pmax / v) cannot leave
 *   a wound-up integrator behind.
 *
 * Scaling: kp_q32 = kp [U per E] * 2^32, ki_q32 = ki [U per E per s] * 2^32,
 * both with magnitude below 2^35; error clamped to +-2^25; dt_q16 = dt [s]
 * * 2^16, at most 2^20 (16 s); output limits clamped to +-PFE_PI_OUT_MAX.
 * Then every product stays below 2^61 and the integrator, held as U * 2^4
 * (1/16 of an output unit), in 32 bits: this runs in every simulation step
 * on a 32-bit core, so its state and comparisons are 32-bit.
 */
#ifndef PFE_PI_H
#define PFE_PI_H

#include <stdint.h>

#define PFE_PI_ERROR_MAX ((int32_t)1 << 25)
#define PFE_PI_DT_MAX_Q16 ((uint32_t)1 << 20)
#define PFE_PI_GAIN_MAX_Q32 ((int64_t)1 << 35)
#define PFE_PI_OUT_MAX ((int32_t)1 << 26)

typedef struct {
    int64_t kp_q32;
    int64_t ki_q32;
    int32_t integral_q4;  /* I, output units * 2^4 */
} pfe_pi_t;

/* Sets gains (clamped to +-PFE_PI_GAIN_MAX_Q32) and presets I to
 * initial_output (clamped to +-PFE_PI_OUT_MAX), so that a controller started
 * at equilibrium starts without a bump. */
void pfe_pi_init(pfe_pi_t *pi, int64_t kp_q32, int64_t ki_q32, int32_t initial_output);

/* One step; returns the output, rounded, within [out_min, out_max]
 * (out_min <= out_max required; if not, out_max wins). */
int32_t pfe_pi_step(pfe_pi_t *pi, int32_t error, uint32_t dt_q16, int32_t out_min, int32_t out_max);

#endif /* PFE_PI_H */
