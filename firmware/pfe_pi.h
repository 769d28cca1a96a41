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
 * both with magnitude below 2^35; error clamped to [-2^25, 2^25 - 1]; dt_q16 = dt [s]
 * * 2^16, at most 2^20 (16 s); output limits clamped to +-PFE_PI_OUT_MAX.
 * Then every product stays below 2^61 and the integrator, held as U * 2^4
 * (1/16 of an output unit), in 32 bits: this runs in every simulation step
 * on a 32-bit core, so its state and comparisons are 32-bit.
 *
 * Each gain is held as a 32-bit mantissa and a power of two, gain_q32 =
 * m * 2^shift with shift 0 .. 5 (pfe_mantissa_i32(): m = gain exactly below
 * 2^31, else rounded to 2^-31 of the gain), and the error is
 * multiplied by 2^shift (|e| 2^shift <= 2^30), so that each product is one
 * 32 x 32 -> 64 bit multiply. The integral's rate ki e is held at most
 * 2^53 (|rate| U/s * 2^8 at most 2^29, and clamped to [-2^29, 2^29 - 1]
 * so that its product with dt is the rounded high word of 32-bit
 * operands): its error is clamped to 2^53 / |ki| when that is below
 * PFE_PI_ERROR_MAX (rate_limited; in the simulation's newtons, a rate of
 * 2.1 MN/s: with the largest gain, 2^35, past 0.26 m/s of error; the
 * default cruise calibration's gain, 20 milli / s^2 per kg, stays below the
 * limit for any platoon up to 1600 t, and up to 3200 t for any error below
 * 32 m/s).
 */
#ifndef PFE_PI_H
#define PFE_PI_H

#include <stdbool.h>
#include <stdint.h>

#include "pfe_fixed.h"

#define PFE_PI_ERROR_MAX (((int32_t)1 << 25) - 1)
#define PFE_PI_DT_MAX_Q16 ((uint32_t)1 << 20)
#define PFE_PI_GAIN_MAX_Q32 ((int64_t)1 << 35)
#define PFE_PI_OUT_MAX ((int32_t)1 << 26)

typedef struct {
    int32_t kp_m;           /* kp_q32 = kp_m * kp_scale */
    int32_t kp_scale;       /* 2^0 .. 2^5 */
    int32_t ki_m;           /* ki_q32 = ki_m * ki_scale */
    int32_t ki_scale;
    int32_t rate_error_max; /* the integral's error limit: |ki| e at most 2^53 */
    bool rate_limited;      /* rate_error_max below PFE_PI_ERROR_MAX: the limit applies */
    int32_t integral_q4;    /* I, output units * 2^4 */
} pfe_pi_t;

/* Sets gains (clamped to +-PFE_PI_GAIN_MAX_Q32) and presets I to
 * initial_output (clamped to +-PFE_PI_OUT_MAX), so that a controller started
 * at equilibrium starts without a bump. */
void pfe_pi_init(pfe_pi_t *pi, int64_t kp_q32, int64_t ki_q32, int32_t initial_output);

/* pfe_pi_step() for a caller that guarantees its limits and step:
 * -PFE_PI_OUT_MAX <= lo <= hi <= PFE_PI_OUT_MAX and dt_q16 <=
 * PFE_PI_DT_MAX_Q16 (the simulation's are, by construction: pfe_sim.c).
 * The same result as pfe_pi_step() for such arguments, without clamping
 * them again. The error is still clamped. */
static inline int32_t pfe_pi_step_in_range(pfe_pi_t *pi, int32_t error, uint32_t dt, int32_t lo,
                                           int32_t hi)
{
    /* Each fixed clamp is to [-2^k, 2^k - 1], a single saturating
     * instruction on the Cortex-M4 (SSAT). */
    const int32_t e = pfe_clamp_i32(error, -PFE_PI_ERROR_MAX - 1, PFE_PI_ERROR_MAX);

    /* |kp_m| < 2^31 times |e| 2^shift <= 2^30: below 2^61, so kp e / 2^32
     * (the product's rounded high word) fits 32 bits; P clamped to 2^27
     * there. */
    const int32_t p = pfe_clamp_i32(pfe_mulhr_i32(pi->kp_m, e * pi->kp_scale), -(1 << 27),
                                    (1 << 27) - 1);
    /* ki * e / 2^24 is U/s * 2^8, at most 2^29 with the rate's error
     * limit (which only a large gain needs: rate_limited); times dt over
     * 2^20 is U * 2^4: rate * 4 < 2^31 and dt * 2^10 <= 2^30, so it is their
     * product's rounded high word, below 2^29 (I + step fits 32 bits). */
    const int32_t e_rate = pi->rate_limited ? pfe_clamp_i32(e, -pi->rate_error_max, pi->rate_error_max)
                                            : e;
    const int32_t rate_q8 = pfe_clamp_i32((int32_t)pfe_mul_q(pi->ki_m, e_rate * pi->ki_scale, 24U),
                                          -(1 << 29), (1 << 29) - 1);
    const int32_t step_q4 = pfe_mulhr_i32(rate_q8 * 4, (int32_t)(dt << 10));

    /* |I| <= 2^30, |step| <= 2^29, |P| <= 2^27: every sum below 2^31. */
    const int32_t trial_q4 = pi->integral_q4 + step_q4;
    const int32_t trial = p + ((trial_q4 + 8) >> 4);
    const bool winding_up = (trial > hi) && (step_q4 > 0);
    const bool winding_down = (trial < lo) && (step_q4 < 0);
    const int32_t integral = (winding_up || winding_down) ? pi->integral_q4 : trial_q4;
    pi->integral_q4 = pfe_clamp_i32(integral, lo * 16, hi * 16);
    return pfe_clamp_i32(p + ((pi->integral_q4 + 8) >> 4), lo, hi);
}

/* One step; returns the output, rounded, within [out_min, out_max]
 * (out_min <= out_max required; if not, out_max wins). Inline: it runs in
 * every step of the simulation (pfe_sim.c), whose loops it must not leave. */
static inline int32_t pfe_pi_step(pfe_pi_t *pi, int32_t error, uint32_t dt_q16, int32_t out_min,
                                  int32_t out_max)
{
    const int32_t hi = pfe_clamp_i32(out_max, -PFE_PI_OUT_MAX, PFE_PI_OUT_MAX);
    const int32_t lo = pfe_clamp_i32((out_min <= out_max) ? out_min : out_max, -PFE_PI_OUT_MAX, hi);
    const uint32_t dt = (dt_q16 > PFE_PI_DT_MAX_Q16) ? PFE_PI_DT_MAX_Q16 : dt_q16;
    return pfe_pi_step_in_range(pi, error, dt, lo, hi);
}


#endif /* PFE_PI_H */
