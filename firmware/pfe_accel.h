/*
 * pfe_accel.h - speed and acceleration from J1939 wheel speed.
 *
 * CCVS1 (SPN 84) arrives every 100 ms quantised to 1/256 km/h (1.085 mm/s).
 * Differencing such samples gives an acceleration that is mostly
 * quantisation noise (1 LSB per 100 ms is 11 mm/s^2, 450 N on 40 t), so the
 * estimator tracks speed with an alpha-beta filter (a steady-state Kalman
 * filter for constant acceleration), updated once per received sample:
 *
 *   predict   v' = v + a k T            (k periods T = 100 ms since the last sample)
 *   residual  r  = z - v'
 *   correct   v  = v' + alpha r,   a = a + beta r / (k T)
 *
 * alpha = 0.3, beta = 0.05: poles at |z| = 0.84 per period (time constant
 * about 0.56 s), no steady-state error on a constant acceleration, and
 * quantisation noise on a of about 0.2 mm/s^2 rms.
 * Scaling: speed um/s, acceleration um/s^2, both int32; alpha and beta are
 * exact rationals (3/10, 1/20), so v and a are rounded to 1 um/s and
 * 1 um/s^2 once per update. Inputs are clamped to [0, PFE_SPEED_MAX_MM_S].
 */
#ifndef PFE_ACCEL_H
#define PFE_ACCEL_H

#include <stdint.h>

#define PFE_SPEED_PERIOD_MS 100U /* CCVS1 transmission rate */

typedef struct {
    int32_t speed_um_s;
    int32_t accel_um_s2;
    uint32_t samples; /* since reset, saturating at UINT32_MAX */
} pfe_accel_filter_t;

/* Forgets all history: the next sample starts the filter at a = 0. */
void pfe_accel_reset(pfe_accel_filter_t *f);

/* One received sample; periods = nominal periods since the previous sample,
 * clamped to [1, 10] (the caller resets on longer gaps). */
void pfe_accel_update(pfe_accel_filter_t *f, int32_t speed_mm_s, uint32_t periods);

#endif /* PFE_ACCEL_H */
