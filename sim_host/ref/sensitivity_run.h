/*
 * sensitivity_run.h - the thesis's sensitivity analysis (chapter 6): one
 * input or parameter of the platoon object model changed, everything else
 * nominal, the platoon driven over a road, fuel and speeds summarised.
 *
 * The model is the double-precision object model of ref_model.h (thesis
 * chapter 4, eq. 4.3 to 4.14) with its PI cruise control, in 10 m distance
 * steps, starting at the set speed in equilibrium, as platoon_sim runs it.
 * What a case changes, and the thesis's steps for it (sens_steps()):
 *
 *   SENS_GRADE      every grade sample times (1 + change/100): eq. 4.10.
 *                   Steps -70 -50 -30 +30 +50 +70 % (thesis 6.1, table 6.1).
 *   SENS_DRAG_AREA  cw * Af of every truck: eq. 4.6.
 *                   Steps -70 -50 -30 +30 +50 +70 % (thesis table 6.2 and
 *                   6.2.2; the thesis's figures 6.4 to 6.6 show 10 to 30 %).
 *   SENS_POWER      Pmax of every truck, hence of the platoon: eq. 4.4.
 *                   Steps -30 -20 -10 +10 +20 +30 % (thesis 6.3, table 6.3).
 *   SENS_TIME_GAP   the gap, as a time at the set speed, through phi_i(d):
 *                   eq. 4.6 and 4.7. Steps 0.1 0.13 0.2 0.8 1.2 1.6 s around
 *                   the nominal 0.4 s (thesis 6.4; its table 6.4 was lost).
 *   SENS_MASS       the mass m of every truck: eq. 4.3, 4.4 (Pmax_i / m_i),
 *                   4.8, 4.10. mj, the rotating parts, stays as it is: load
 *                   does not turn. Steps -30 -20 -10 +10 +20 +30 %: the
 *                   thesis's section 6.5 was lost from the text; these are
 *                   the steps of its other vehicle parameter (Pmax), and
 *                   28 t to 52 t per truck spans a part-laden to an
 *                   overloaded combination.
 *
 * A change to a calibration value is applied in integers, value * (100 +
 * change) / 100 rounded to nearest, so that 0 % gives back the very same
 * calibration and every run of a 0 % change is bit for bit the nominal run.
 */
#ifndef SENSITIVITY_RUN_H
#define SENSITIVITY_RUN_H

#include <stddef.h>
#include <stdint.h>

#include "firmware/pfe_calib.h"
#include "lib/road_csv.h"

typedef enum {
    SENS_NOMINAL = 0,
    SENS_GRADE,
    SENS_DRAG_AREA,
    SENS_POWER,
    SENS_TIME_GAP,
    SENS_MASS,
    SENS_N_PARAMS
} sens_param_t;

/* The nominal case: platoon, speed and calibrations. */
typedef struct {
    uint32_t n_vehicles;          /* 1 .. PFE_MAX_VEHICLES, identical trucks */
    int32_t set_speed_mm_s;       /* cruise set speed; also the start speed */
    uint32_t time_gap_ms;         /* gap = time gap * set speed */
    uint32_t step_mm;             /* simulation distance step, 100 .. 10000 */
    const pfe_vehicle_calib_t *vehicle;
    const pfe_env_calib_t *env;
    const pfe_drag_table_t *drag;
    const pfe_cruise_calib_t *cruise;
} sens_setup_t;

/* The thesis's case: N = 5, 90 km/h, 0.4 s, 10 m steps, the default
 * calibration of pfe_calib.h. */
void sens_setup_default(sens_setup_t *setup);

typedef struct {
    double fuel_l;            /* platoon fuel over the road, L */
    double time_s;            /* travel time, s */
    double mean_kmh;          /* mean of the speed after each distance step */
    double min_kmh, max_kmh;
    double power_limited_pct; /* share of the travel time with the wheel force at
                                 its upper limit (Pmax / v or traction), % */
    double gap_m;             /* the gap this case used */
    unsigned long steps;
    int stalled;              /* 1: speed fell below 1 m/s; the sums stop there */
    double stall_position_m;
} sens_result_t;

/*
 * Drives the platoon of *setup over *road with one parameter changed.
 * amount: for SENS_TIME_GAP the time gap in ms; for the others the change
 * in whole percent (> -100); SENS_NOMINAL takes 0 only.
 *
 * Returns 0 with *out filled (out->stalled says whether the platoon made it
 * to the end), or -1 with a message in err for an amount out of range, a
 * changed calibration that fails its range check, a bad setup or road, or
 * no memory. Time O(road length / step); allocates one copy of the grades.
 * Reentrant.
 */
int sens_run(const sens_setup_t *setup, const road_profile_t *road, sens_param_t param,
             int32_t amount, sens_result_t *out, char *err, size_t err_len);

/* The thesis's steps for param, ascending, the nominal point included (0 %,
 * or 400 ms for SENS_TIME_GAP). *steps points at static storage. Returns
 * the count, 0 for SENS_NOMINAL or an unknown param. */
size_t sens_steps(sens_param_t param, const int32_t **steps);

/* The amount that is the nominal case: 0, or setup->time_gap_ms. */
int32_t sens_nominal_amount(const sens_setup_t *setup, sens_param_t param);

/* Short name ("grade", "cw_af", "pmax", "time_gap", "mass", "nominal"). */
const char *sens_param_name(sens_param_t param);

#endif /* SENSITIVITY_RUN_H */
