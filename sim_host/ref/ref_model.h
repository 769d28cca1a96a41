/*
 * ref_model.h - double-precision reference of the firmware model.
 *
 * The test oracle: the same equations and the same discretisation as
 * firmware/ (pfe_vehicle, pfe_platoon, pfe_pi, pfe_sim, pfe_accel,
 * pfe_estimator), in SI units and double precision, with no rounding
 * anywhere. The difference between the two is the cost of the integer
 * arithmetic alone. It shares only the calibration: the firmware's
 * calibration structs, read as data, and their range checks.
 */
#ifndef REF_MODEL_H
#define REF_MODEL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "firmware/pfe_calib.h"
#include "firmware/pfe_platoon.h" /* pfe_platoon_config_t, as data */

typedef struct {
    double air_k;       /* N per (m/s)^2, with (1 - phi/100) */
    double mass;        /* kg */
    double mass_fuel;   /* m + mj */
    double roll_mass;   /* cr * m, kg */
    double fuel_per_j;  /* L of fuel per J of work: 1 / (eta rho_d) */
    double power_max;   /* W */
    double traction_max;/* N */
    double brake_max;   /* N */
    double power_aux;   /* W */
    double reduction;   /* phi in percent */
} ref_vehicle_t;

typedef struct {
    unsigned n_vehicles;
    double gap;         /* m */
    double gravity;     /* m/s^2 */
    double formation_air_k; /* N per (m/s)^2: M max_i(k_i / m_i) - sum k_i (pfe_platoon.h) */
    ref_vehicle_t object;
    ref_vehicle_t position[PFE_MAX_VEHICLES];
} ref_platoon_t;

/* phi_i(d) in percent, linear interpolation in the table, held outside. */
double ref_drag_reduction_pct(const pfe_drag_table_t *drag, unsigned position, unsigned n,
                              double gap_m);
void ref_vehicle_init(ref_vehicle_t *v, const pfe_vehicle_calib_t *c, const pfe_env_calib_t *env,
                      double reduction_pct);
/* Returns 0, or -1 for an invalid configuration (same checks as the firmware). */
int ref_platoon_init(ref_platoon_t *pl, const pfe_platoon_config_t *cfg);

/* Chapter 3 forces, exact trigonometry; grade as a fraction (tan alpha). */
double ref_vehicle_resistance(const ref_vehicle_t *v, double speed, double grade, double g);
/* Object model resistance, small-angle (eq. 4.6 to 4.10). */
double ref_object_resistance(const ref_platoon_t *pl, double speed, double grade);
double ref_wheel_force_max(double power_max, double traction_max, double speed);
/* The object model's force limit: ref_wheel_force_max of the platoon minus
 * the formation drag formation_air_k v^2, at least -brake_max. */
double ref_platoon_force_max(const ref_platoon_t *pl, double speed);
/* eq. 3.8 to 3.11 in L/s; 0 when force <= 0. */
double ref_fuel_rate(double force, double speed, double power_aux, double fuel_per_j);

typedef struct {
    double kp, ki, integral; /* output per error unit, per s; output units */
} ref_pi_t;
void ref_pi_init(ref_pi_t *pi, double kp, double ki, double initial_output);
double ref_pi_step(ref_pi_t *pi, double error, double dt, double out_min, double out_max);

typedef struct {
    const double *grade;      /* fraction */
    size_t n_samples;
    double spacing;           /* m */
} ref_road_t;

typedef struct {
    const ref_platoon_t *pl;
    ref_pi_t pi;
    double step, end, set_speed;
    double speed, position, time, fuel; /* m/s, m, s, L */
    double grade, wheel_force, accel;
    unsigned long steps;
} ref_sim_t;

/* Same arguments and checks as pfe_sim_init, SI units. Returns 0 or -1. */
int ref_sim_init(ref_sim_t *sim, const ref_platoon_t *pl, const pfe_cruise_calib_t *cruise,
                 const ref_road_t *road, double set_speed, double initial_speed, double step);
/* Returns 1 (step taken), 0 (done) or -1 (stalled below 1 m/s). */
int ref_sim_step(ref_sim_t *sim, const ref_road_t *road);

typedef struct {
    double speed, accel;
    unsigned long samples;
} ref_accel_t;
void ref_accel_reset(ref_accel_t *f);
void ref_accel_update(ref_accel_t *f, double speed, unsigned periods);

typedef struct {
    const ref_platoon_t *pl;
    ref_accel_t filter;
    unsigned long ticks_since_sample;
    bool valid;
    double fuel_rate;                       /* L/s, object model */
    double pos_fuel_rate[PFE_MAX_VEHICLES]; /* L/s */
    double fuel_used;                       /* L */
    double pos_fuel_used[PFE_MAX_VEHICLES];
} ref_estimator_t;

void ref_estimator_init(ref_estimator_t *est, const ref_platoon_t *pl);
/* One 10 ms step with the same validity rules as pfe_estimator_step. */
void ref_estimator_step(ref_estimator_t *est, double speed, bool speed_valid, bool speed_fresh,
                        double grade, bool grade_valid);

#endif /* REF_MODEL_H */
