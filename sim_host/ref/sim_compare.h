/*
 * sim_compare.h - one platoon over one road, fixed point against double.
 *
 * Runs the firmware's object-model simulation (pfe_sim) and the
 * double-precision reference (ref_model) side by side on the same road and
 * configuration, step for step (both step in distance, so step k of one is at
 * the same position as step k of the other), and summarises both.
 */
#ifndef SIM_COMPARE_H
#define SIM_COMPARE_H

#include <stdint.h>
#include <stdio.h>

#include "firmware/pfe_calib.h"
#include "firmware/pfe_platoon.h"

typedef struct {
    double fuel_l, time_s, mean_kmh, min_kmh, max_kmh;
} sim_summary_t;

typedef struct {
    sim_summary_t fixed, ref;
    double fuel_rel_err;      /* (fixed - ref) / ref */
    double speed_rms_kmh;     /* rms over steps of fixed - ref speed */
    double speed_max_kmh;     /* largest |fixed - ref| */
    unsigned long steps;
} sim_compare_t;

typedef struct {
    const int32_t *grade_ppm; /* the road as the firmware reads it */
    uint32_t n_samples;
    uint32_t spacing_mm;
    const pfe_platoon_config_t *config;
    const pfe_cruise_calib_t *cruise;
    int32_t set_speed_mm_s;
    uint32_t step_mm;
    FILE *trace;              /* optional CSV, one row per step; NULL for none */
} sim_compare_args_t;

/* Returns 0, or -1 with a message in err (invalid configuration, or a
 * platoon that stalls: the road is too steep for it). */
int sim_compare_run(const sim_compare_args_t *args, sim_compare_t *out, char *err, size_t err_len);

#endif /* SIM_COMPARE_H */
