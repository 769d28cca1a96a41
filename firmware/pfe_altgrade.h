/*
 * pfe_altgrade.h - road grade from altitude over distance travelled, for a
 * truck without a slope sensor.
 *
 * J1939 VDS (PGN 65256) carries the GNSS altitude (SPN 580, 0.125 m). Grade
 * is rise over run: the change of altitude over the distance the truck
 * travelled, which the ECU integrates from CCVS1 speed. Raw GNSS altitude is
 * noisy (metres, sample to sample); differenced over a few metres it would
 * become grades of +-10 % and more. So:
 *   1. altitude is low-pass filtered over distance, not time: each sample
 *      moves the filtered altitude towards itself by the fraction
 *      dx / PFE_ALTGRADE_FILTER_MM of the way (at most all of it), so a
 *      standing truck's noise never moves it and the filter spans the same
 *      road at any speed;
 *   2. the filtered altitude is stored every PFE_ALTGRADE_STEP_MM of travel
 *      in a ring of PFE_ALTGRADE_NODES entries;
 *   3. grade = (filtered now - filtered at least PFE_ALTGRADE_BASE_MM ago)
 *      / distance between them, in ppm, clamped to +-PFE_GRADE_MAX_PPM.
 * With white noise of sigma metres per sample and samples every s metres of
 * road, the filter averages about 2 * 50 m / s samples, so the grade's noise
 * is about sigma * sqrt(2 / (100 m / s)) / 100 m: for sigma = 2 m at 10 Hz
 * and 25 m/s (s = 2.5 m) about 0.45 %. The price is lag: the grade given is
 * that of the road about 100 m behind the truck, which is why a slope
 * sensor is preferred whenever one sends (docs/j1939.md).
 *
 * A grade is available once PFE_ALTGRADE_BASE_MM of road has been filtered
 * with no gap in the samples longer than PFE_ALTGRADE_GAP_MM of travel (a
 * longer gap restarts). Integer only; distances mm, altitude mm, grade ppm.
 */
#ifndef PFE_ALTGRADE_H
#define PFE_ALTGRADE_H

#include <stdbool.h>
#include <stdint.h>

#define PFE_ALTGRADE_FILTER_MM 50000U   /* low-pass length over distance */
#define PFE_ALTGRADE_STEP_MM 10000U     /* a node every 10 m */
#define PFE_ALTGRADE_BASE_MM 100000U    /* grade over 100 m */
#define PFE_ALTGRADE_GAP_MM 50000U      /* more travel than this without a sample restarts */
#define PFE_ALTGRADE_NODES 16U          /* covers 150 m: enough for the base */

typedef struct {
    bool started;
    uint64_t last_x_mm;                 /* odometer at the last sample */
    int64_t filtered_q8_mm;             /* filtered altitude, mm * 2^8 */
    uint64_t node_x_mm[PFE_ALTGRADE_NODES];
    int32_t node_alt_mm[PFE_ALTGRADE_NODES];
    uint32_t n_nodes;                   /* stored so far, up to PFE_ALTGRADE_NODES */
    uint32_t head;                      /* index of the newest node */
    int32_t grade_ppm;
    bool valid;
} pfe_altgrade_t;

void pfe_altgrade_init(pfe_altgrade_t *ag);

/* One altitude sample (mm) taken with the odometer at x_mm (non-decreasing).
 * Updates the grade. O(PFE_ALTGRADE_NODES) at most, usually O(1). */
void pfe_altgrade_sample(pfe_altgrade_t *ag, uint64_t x_mm, int32_t altitude_mm);

/* Forgets everything (altitude input lost). */
void pfe_altgrade_reset(pfe_altgrade_t *ag);

/* The grade in ppm; false (and *grade_ppm = 0) until one is available. */
bool pfe_altgrade_grade(const pfe_altgrade_t *ag, int32_t *grade_ppm);

#endif /* PFE_ALTGRADE_H */
