/*
 * pfe_estimator.h - the 10 ms fuel estimator.
 *
 * Every 10 ms the ECU loop hands over the latest measured speed (CCVS1,
 * SPN 84, every 100 ms) and road grade (from SSI pitch, every 10 ms). The
 * estimator filters speed into speed and acceleration (pfe_accel.h), then
 * computes for the same instant:
 *   - the platoon's fuel rate with the object model (eq. 3.7, 4.13, 4.14,
 *     small-angle grade as in chapter 4);
 *   - each position's fuel rate with the chapter 3 model and that
 *     position's phi_i (eq. 3.4 to 3.11, exact sin and cos of the grade);
 * and integrates each rate into fuel used.
 *
 * Validity: outputs are available (PFE_EST_VALID) only while speed and grade
 * are valid, speed samples keep coming (a gap of more than
 * PFE_EST_STALE_PERIODS periods counts as missing) and the filter has seen
 * PFE_EST_WARMUP_SAMPLES samples since it last restarted. While not
 * available, rates read 0, fuel used does not advance, and the flags say why.
 *
 * Units: fuel rate nL/s (uint32, saturating, flagged), fuel used integrated
 * in units of 1 nL/s * 10 ms = 10 pL (uint64: 1.8e8 L before it saturates,
 * far past 2,000,000 L). Cost: O(n_vehicles) multiplications, no division
 * except on speed updates (32-bit), no loop other than over positions.
 */
#ifndef PFE_ESTIMATOR_H
#define PFE_ESTIMATOR_H

#include <stdbool.h>
#include <stdint.h>

#include "pfe_accel.h"
#include "pfe_calib.h"
#include "pfe_platoon.h"
#include "pfe_vehicle.h"

#define PFE_EST_STEP_MS 10U
#define PFE_EST_TICKS_PER_SPEED_PERIOD (PFE_SPEED_PERIOD_MS / PFE_EST_STEP_MS)
#define PFE_EST_WARMUP_SAMPLES 5U
#define PFE_EST_STALE_PERIODS 3U

/* Output flags. */
#define PFE_EST_VALID          (1U << 0) /* rates and fuel used are current */
#define PFE_EST_SPEED_MISSING  (1U << 1) /* speed not valid or stale */
#define PFE_EST_GRADE_MISSING  (1U << 2) /* grade not valid */
#define PFE_EST_WARMING_UP     (1U << 3) /* filter restarted, too few samples */
#define PFE_EST_SPEED_CLAMPED  (1U << 4) /* speed outside [0, PFE_SPEED_MAX_MM_S] */
#define PFE_EST_GRADE_CLAMPED  (1U << 5) /* grade outside +-PFE_GRADE_MAX_PPM */
#define PFE_EST_SATURATED      (1U << 6) /* a rate or a total hit its limit */

/* Position index of the platoon as a whole in the fuel-used accessors. */
#define PFE_EST_PLATOON (-1)

typedef struct {
    int32_t speed_mm_s;   /* last received wheel-based speed */
    bool speed_valid;     /* the ECU holds a valid, current speed */
    bool speed_fresh;     /* a new speed sample arrived since the last step */
    int32_t grade_ppm;    /* road grade, tan(pitch), ppm */
    bool grade_valid;
} pfe_est_input_t;

typedef struct {
    uint32_t flags;
    int32_t speed_mm_s;       /* filtered */
    int32_t accel_um_s2;      /* filtered */
    int32_t grade_ppm;        /* as used (after clamping) */
    int32_t wheel_force_n;    /* platoon, eq. 3.7 summed (object model) */
    uint32_t fuel_rate_nl_s;  /* platoon, object model (eq. 4.14) */
    uint32_t pos_fuel_rate_nl_s[PFE_MAX_VEHICLES]; /* each position (eq. 3.11) */
} pfe_est_output_t;

typedef struct {
    const pfe_platoon_t *platoon;
    pfe_accel_filter_t filter;
    uint32_t ticks_since_sample;
    int32_t trig_grade_ppm;           /* grade the cached split belongs to */
    pfe_grade_accel_t trig;           /* exact split for the chapter 3 model */
    int32_t object_along_um_s2;       /* the object model's small-angle g * grade for
                                       * the same grade (pfe_platoon_grade_accel()) */
    uint64_t fuel_used_10pl;          /* platoon */
    uint64_t pos_fuel_used_10pl[PFE_MAX_VEHICLES];
    pfe_est_output_t out;
} pfe_estimator_t;

/* Starts with empty history and zero fuel used. The platoon must outlive the
 * estimator. Returns PFE_OK or PFE_EINVAL (NULL). */
int pfe_estimator_init(pfe_estimator_t *est, const pfe_platoon_t *platoon);

/* One 10 ms step; returns the outputs (owned by est, valid until the next
 * call). in == NULL counts as every input missing. */
const pfe_est_output_t *pfe_estimator_step(pfe_estimator_t *est, const pfe_est_input_t *in);

/* Fuel used in uL (rounded down) for a position 0 .. n-1, or PFE_EST_PLATOON.
 * Other positions read 0. */
uint64_t pfe_estimator_fuel_used_ul(const pfe_estimator_t *est, int32_t position);

/* Restores fuel used (for example from non-volatile memory after a reset).
 * Returns PFE_OK, or PFE_EINVAL for a position out of range. */
int pfe_estimator_set_fuel_used_ul(pfe_estimator_t *est, int32_t position, uint64_t fuel_ul);

#endif /* PFE_ESTIMATOR_H */
