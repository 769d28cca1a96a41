/*
 * pfe_predict.h - fuel and time over the road ahead, on the module.
 *
 * The object model (pfe_sim.h) runs over the grade preview received on CAN
 * (PFE_GradePreview, pfe_codec.h), from the current speed and the point the
 * vehicle has reached since the preview's header to the end of the horizon,
 * under the PI cruise control to the set speed. Two more runs give the
 * thesis's bounds (chapter 5.1): a slowest and a fastest platoon whose speed
 * trajectories bound the work done against air drag, rolling and grade (see
 * pfe_predict.c for the choices, every one of them on the side that keeps the
 * bound a bound).
 *
 * The work is split across the ECU's ticks: pfe_predict_run() takes a
 * budget of work units (one simulation step, PFE_PREDICT_LOAD_PER_UNIT
 * preview samples copied with the windows' first pass, or
 * PFE_PREDICT_WINDOW_PER_UNIT positions of their second pass: each about
 * the instructions of a step) and returns when it is spent, so that no
 * tick exceeds its own budget. Setting up a simulation run
 * (pfe_sim_init(): every sample read once, a few 64-bit divisions) takes a
 * call of its own.
 *
 * A prediction goes through
 *   LOADING      copy the preview's samples, clamped, and  } once per preview
 *                the first pass of the grade windows       } (and platoon
 *   WINDOWS      their second pass: the smallest and the   }  length, 5.10)
 *                largest grade around each sample          }
 *   NOMINAL      the object model with the platoon's own parameters
 *   SLOW         the slowest platoon (no drag reduction): v_min, lower bound
 *   FAST         the fastest platoon (drag reduction at half the gap):
 *                v_max, upper bound
 *   DONE         the result is published, the predictor idle
 * The first two prepare the preview, O(n) for any window (n + w positions
 * a pass, w the window's half-width in samples): about 58,000 instructions
 * on the Cortex-M4 for 1000 samples and 5 trucks (tests/bench/m4_bench.c,
 * predict_first_n5 less predict_whole_n5), against about 518,000 for the
 * three runs. A later prediction over the same preview (the caller says so
 * with its serial number) for the same window starts at NOMINAL, from the
 * sample the vehicle has reached; another platoon length prepares it anew.
 * pfe_predict_start() abandons a prediction in progress, at any phase, and
 * starts anew (a new preview, a new platoon): nothing of the old one
 * survives.
 *
 * Memory: all in pfe_predict_t (about 10.5 KB: the preview's grade, 4 KB,
 * its window extremes at the preview's own 20 ppm resolution, 2 x 2 KB, and
 * one platoon).
 * Units: fuel nL internally, uL in the result; time ms; speed mm/s.
 */
#ifndef PFE_PREDICT_H
#define PFE_PREDICT_H

#include <stdbool.h>
#include <stdint.h>

#include "pfe_calib.h"
#include "pfe_codec.h"
#include "pfe_platoon.h"
#include "pfe_sim.h"

#define PFE_PREDICT_LOAD_PER_UNIT 8U    /* preview samples copied (first pass) per work unit */
#define PFE_PREDICT_WINDOW_PER_UNIT 10U /* positions of the windows' second pass per work unit */
#define PFE_PREDICT_STEP_MAX_MM 16000U  /* simulation step: the preview's spacing, at most this */

typedef enum {
    PFE_PREDICT_IDLE = 0,
    PFE_PREDICT_LOADING,
    PFE_PREDICT_WINDOWS,
    PFE_PREDICT_NOMINAL,
    PFE_PREDICT_SLOW,
    PFE_PREDICT_FAST,
    PFE_PREDICT_DONE,
} pfe_predict_phase_t;

/* A published prediction. */
typedef struct {
    bool valid;
    uint32_t generation;               /* counts published predictions */
    uint64_t fuel_ul;                  /* platoon fuel to the end of the horizon */
    uint64_t fuel_lower_ul;
    uint64_t fuel_upper_ul;
    uint32_t time_ms;                  /* time to the end of the horizon */
    uint32_t distance_m;               /* length predicted over */
    int32_t end_speed_mm_s;
} pfe_predict_result_t;

/* Why a prediction could not be made (pfe_predict_start()). */
#define PFE_PREDICT_ENOPREVIEW (-301)  /* no complete preview, or it holds unusable samples */
#define PFE_PREDICT_EPASSED (-302)     /* the vehicle is past the preview's end */
#define PFE_PREDICT_ESTALL (-303)      /* a run stalled: the platoon cannot climb the road */

typedef struct {
    pfe_predict_phase_t phase;
    /* inputs of the prediction in progress */
    const pfe_platoon_t *platoon;      /* nominal, kept by pointer */
    pfe_platoon_t bound;               /* the slow, then the fast platoon */
    int64_t air_slow_q32;              /* cw Af_max N: object air drag (pfe_vehicle_t.air_q32) */
    int64_t air_fast_q32;              /* cw Af_min sum (1 - phi_i(d / 2)) */
    uint32_t formation_slow_q32;       /* the slow platoon's formation drag (pfe_platoon.h):
                                        * cw Af_max (M / m_min - N); the fast one has none */
    int64_t fuel_upper_q20;            /* 1 / (eta_min rho_d), pfe_vehicle_t.fuel_q20 */
    int64_t fuel_lower_q20;            /* 1 / (eta_max rho_d) */
    uint32_t window_samples;           /* grade window half-width in samples, (N - 1) * gap */
    pfe_cruise_calib_t cruise;
    int32_t set_speed_mm_s;
    int32_t start_speed_mm_s;
    uint32_t first_sample;             /* preview sample under the vehicle at the start */
    /* the prepared preview */
    bool prepared;
    uint32_t prepared_serial;          /* the caller's number of the preview prepared */
    uint32_t prepared_window;          /* window_samples the extremes were made for */
    uint32_t n_samples;                /* samples of the preview */
    uint32_t spacing_mm;
    uint32_t n_done;                   /* samples loaded */
    uint32_t win_pos;                  /* WINDOWS: positions left (pfe_predict.c) */
    uint32_t win_block_left;           /* positions left in the current block */
    int32_t win_low;                   /* the pass's running extremes, 20 ppm */
    int32_t win_high;
    int32_t grade_ppm[PFE_PREVIEW_MAX_SAMPLES];
    int16_t window_low_20ppm[PFE_PREVIEW_MAX_SAMPLES];  /* extreme grade around each sample, */
    int16_t window_high_20ppm[PFE_PREVIEW_MAX_SAMPLES]; /* 20 ppm */
    pfe_road_t road;
    pfe_sim_t sim;
    pfe_sim_sums_t sums;
    bool sim_ready;                    /* the phase's run is initialised */
    /* partial results */
    uint64_t nominal_fuel_nl;
    uint64_t nominal_aux_nl;
    uint64_t nominal_time_q16;
    int32_t nominal_end_speed_mm_s;
    int64_t lower_nl;
    int last_error;                    /* why the last prediction was abandoned: PFE_PREDICT_E* */
    pfe_predict_result_t result;
} pfe_predict_t;

/* Empty: no result, idle. */
void pfe_predict_init(pfe_predict_t *p);

/*
 * Starts a prediction over preview pv (READY), whose serial number the
 * caller changes whenever a new preview completes (the same number: the
 * preview prepared before, unchanged), the vehicle having travelled
 * travelled_mm since its header, at start_speed_mm_s, for the platoon (kept
 * by pointer until the prediction ends; its drag table drag gives the bounds'
 * drag reduction at half the gap), the cruise calibration and set speed.
 * Returns PFE_OK (LOADING), or PFE_EINVAL / PFE_PREDICT_E* (the predictor is
 * then IDLE and its result invalid: a prediction for an older position would
 * mislead). Cost: O(N) with N 64-bit divisions (the bound platoons' air
 * drag), about 2000 instructions for N = 5.
 */
int pfe_predict_start(pfe_predict_t *p, const pfe_preview_t *pv, uint32_t preview_serial,
                      uint32_t travelled_mm,
                      const pfe_platoon_t *platoon, const pfe_drag_table_t *drag,
                      const pfe_cruise_calib_t *cruise, int32_t set_speed_mm_s,
                      int32_t start_speed_mm_s);

/*
 * Does at most budget units of work on the prediction in progress (pv must
 * be the preview given to pfe_predict_start() and unchanged since). Returns
 * the phase after it: DONE once the result is published (then IDLE on the
 * next call), IDLE when nothing is in progress. A run that stalls abandons
 * the prediction (last_error PFE_PREDICT_ESTALL).
 */
pfe_predict_phase_t pfe_predict_run(pfe_predict_t *p, const pfe_preview_t *pv, uint32_t budget);

/* Abandons the prediction in progress (IDLE); the last result stays. */
void pfe_predict_cancel(pfe_predict_t *p);

/* The last published prediction (valid false before the first). */
const pfe_predict_result_t *pfe_predict_result(const pfe_predict_t *p);

#endif /* PFE_PREDICT_H */
