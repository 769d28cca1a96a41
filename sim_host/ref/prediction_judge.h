/*
 * prediction_judge.h - the module's prediction (PFE_FuelPrediction) held
 * against the fuel the platoon then used over the same stretch, from a
 * capture of its bus (sim_host/lib/capture.h); for run_report.
 *
 * What a prediction covers (firmware/pfe_ecu.h, pfe_predict.h): the road
 * from where the vehicle is when the prediction starts to the end of the
 * grade preview it was computed over, n x spacing past the point the
 * vehicle was at when the preview's header was sent. The capture holds the
 * previews (PFE_GradePreview, read with the module's own pfe_preview_push,
 * so a preview counts as complete exactly when the module's does) and the
 * speed (CCVS1: the distance driven, the last speed held until the next
 * frame as the module holds it).
 *
 * When a prediction started is not in the capture. The module starts one
 * at the first tick after a preview is complete and then every
 * PFE_ECU_PREDICT_PERIOD_US (1 s) until the next preview, and sends the
 * latest result once a second. For each new PFE_FuelPrediction value the
 * judge takes the candidate starts (completion + 10 ms + k s) of the last
 * two previews within the 2 s before the frame and at least 40 ms before it
 * (a prediction's three runs need a set-up call each, pfe_predict.h), and
 * of those the one from which the vehicle's actual time to the horizon's
 * end is closest to PredictedTime; a horizon that ends after the capture
 * fits when PredictedTime is at least the time the capture has left.
 * Candidates are 1 s apart, so the time error is measured only to within
 * about 0.5 s (PredictedTime is not judged, only reported).
 *
 * A horizon is complete when the capture's speed reaches its end. For each
 * complete one the realized fuel is the platoon's fuel used over it by the
 * reference (sim_host/ref/bus_ref.h: the double-precision estimator on the
 * captured speed and grade, linear between its ticks): what the platoon
 * burned on the road it drove, whatever the module's own ticks did. It
 * must lie within [lower, upper], widened by half of PFE_FuelPrediction's
 * 0.01 L step.
 *
 * The module counts the distance since a preview's header tick by tick
 * (10 ms of its speed a tick): a module that loses ticks starts its
 * predictions from behind where the vehicle is, and over-predicts by the
 * road it thinks is still ahead; the error shows it.
 *
 * Memory: arrays grown with realloc, freed by prediction_judge_free.
 */
#ifndef PREDICTION_JUDGE_H
#define PREDICTION_JUDGE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "lib/capture.h"

/* Quantities, in run_report's table after its own (index base + PJ_Q_*). */
enum {
    PJ_Q_PREDICTIONS, PJ_Q_HORIZONS, PJ_Q_INCOMPLETE, PJ_Q_OUTSIDE, PJ_Q_MEAN_ERR, PJ_Q_MEAN_ABS_ERR,
    PJ_Q_MAX_ABS_ERR, PJ_Q_MAX_TIME_ERR, PJ_Q_COUNT
};

/* run_report's quantity_t initialisers, {name, what, 0.0, false, NULL}, at base. */
#define PREDICTION_JUDGE_QUANTITIES(base)                                                           \
    [(base) + PJ_Q_PREDICTIONS] = {"predictions", "PFE_FuelPrediction values sent (each new one)",    \
                                   0.0, false, NULL},                                                \
    [(base) + PJ_Q_HORIZONS] = {"prediction_horizons",                                               \
                                "predictions whose horizon the capture drives to its end", 0.0,      \
                                false, NULL},                                                        \
    [(base) + PJ_Q_INCOMPLETE] = {"prediction_horizons_incomplete",                                  \
                                  "predictions whose horizon ends after the capture", 0.0, false,    \
                                  NULL},                                                             \
    [(base) + PJ_Q_OUTSIDE] = {"prediction_outside_bounds",                                          \
                               "complete horizons whose realized fuel is outside the bounds", 0.0,   \
                               false, NULL},                                                         \
    [(base) + PJ_Q_MEAN_ERR] = {"prediction_mean_error_pct",                                         \
                                "mean of (predicted - realized) / realized, %", 0.0, false, NULL},   \
    [(base) + PJ_Q_MEAN_ABS_ERR] = {"prediction_mean_abs_error_pct",                                 \
                                    "mean of its magnitude, %", 0.0, false, NULL},                   \
    [(base) + PJ_Q_MAX_ABS_ERR] = {"prediction_max_abs_error_pct", "largest magnitude, %", 0.0,     \
                                   false, NULL},                                                     \
    [(base) + PJ_Q_MAX_TIME_ERR] = {"prediction_max_time_error_s",                                   \
                                    "largest |PredictedTime - time driven|, s (to about 0.5 s)",    \
                                    0.0, false, NULL}

/* One new prediction. */
typedef struct {
    double frame_s;              /* its first frame, s after the first input */
    double start_s, end_s;       /* the stretch, s after the first input (end: NAN if incomplete) */
    double predicted_l, lower_l, upper_l, predicted_time_s;
    double realized_l, driven_time_s; /* NAN if incomplete */
    double horizon_m;            /* start to the horizon's end */
    bool complete, within;
} pj_row_t;

typedef struct {
    pj_row_t *rows;
    size_t n_rows, room;
    size_t previews, complete, incomplete, outside, unmatched;
    double mean_err_pct, mean_abs_err_pct, max_abs_err_pct, max_abs_err_start_s, max_time_err_s;
    const char *why_not;         /* when nothing could be judged */
} pj_result_t;

/*
 * Judges the predictions from module_sa in cap; the reference starts with
 * the platoon n_vehicles, position, gap_mm until a PFE_PlatoonConfig says
 * otherwise, as run_report's (bus_ref_init). Returns 0 (even when
 * nothing could be judged: then why_not says why), -1 out of memory.
 */
int prediction_judge_run(const capture_t *cap, uint8_t module_sa, unsigned n_vehicles, unsigned position,
                         uint32_t gap_mm, pj_result_t *out);

/* Quantity k (PJ_Q_*): returns true with *v, or false with *why. */
bool prediction_judge_value(const pj_result_t *r, int k, double *v, const char **why);

/* The summary's lines (stdout). */
void prediction_judge_print(const pj_result_t *r);

/* PREFIX.prediction.csv: frame_s, start_s, end_s, predicted_l, lower_l, upper_l, realized_l,
 * horizon_m, predicted_time_s, driven_time_s, within (NA where there is no value). Returns 0
 * or -1 after a message. */
int prediction_judge_write_csv(const pj_result_t *r, const char *path);

/* The plot's panel: predicted, bounds and realized fuel against the start time, from the CSV. */
void prediction_judge_plot(FILE *gp, const char *csv_path);

void prediction_judge_free(pj_result_t *r);

#endif /* PREDICTION_JUDGE_H */
