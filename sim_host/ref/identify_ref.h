/*
 * identify_ref.h - double-precision reference of firmware/pfe_identify, and
 * a drive that exercises it.
 *
 * identify_ref_*: the same gates, windows, means and scalar least squares as
 * pfe_identify.h describes, in SI units and double precision with no
 * rounding, fed the same integer samples: the difference between the two is
 * the cost of the firmware's integers alone.
 *
 * id_drive_*: one truck driven in 10 ms steps over a road of sinusoidal
 * grades, its speed following a target that changes every minute (the
 * chapter 3 model of sim_host/ref/ref_model: eq. 3.2 to 3.11, force limits
 * Pmax / v and -Fb_max), giving every 100 ms the samples the module would
 * see: speed quantised to SPN 84's 1/256 km/h with noise, grade with pitch
 * noise, and the engine's fuel rate (the reference's eq. 3.11) with noise
 * and LFE1's 0.05 L/h quantisation.
 */
#ifndef IDENTIFY_REF_H
#define IDENTIFY_REF_H

#include <stdbool.h>
#include <stdint.h>

#include "firmware/pfe_calib.h"
#include "firmware/pfe_identify.h"
#include "ref/ref_model.h"

typedef struct {
    double fuel_power_per_nl; /* W per nL/s: eta rho_d */
    double air_k;             /* N per (m/s)^2 */
    double roll;              /* cr */
    double gravity;
    double rot_mass;
    double mass0;
    bool have_time, have_prev;
    uint64_t last_us;
    double prev_v, prev_fuel_w, prev_air_w, prev_spec;
    unsigned win_n;
    bool win_on, pend_on;       /* a window in progress; one waiting for its end speed */
    double win_t, win_v0, win_fuel, win_air, win_spec; /* s, m/s, J, J, J/kg */
    double pend_t, pend_v0, pend_fuel, pend_air, pend_spec;
    double hist[PFE_ID_SPEED_AVG]; /* the last speeds of the run, m/s, ring */
    unsigned hist_n, hist_i;
    bool have_mean;
    double mean_x, mean_y, since_window;
    double sxx, sxy, var;
    unsigned n_mass;
    double stop;
    double mass, aux;
    bool converged;
    unsigned long windows_used, mass_updates;
} identify_ref_t;

void identify_ref_init(identify_ref_t *r, const pfe_vehicle_calib_t *seed,
                       const pfe_env_calib_t *env);
void identify_ref_step(identify_ref_t *r, const pfe_identify_sample_t *s);

typedef struct {
    ref_vehicle_t truck;      /* the truth */
    double gravity;
    double speed, accel, position, grade, force, time; /* SI */
    double target;            /* m/s */
    double fuel_rate;         /* L/s, eq. 3.11, the truth */
    double fuel_used;         /* L */
    bool braking;
    double speed_noise_kmh, pitch_noise_deg, fuel_noise_rel;
    uint64_t rng;
    unsigned long steps;
} id_drive_t;

/* A truck of calib (mass as given) on env, noise as given, from 70 km/h. */
void id_drive_init(id_drive_t *d, const pfe_vehicle_calib_t *calib, const pfe_env_calib_t *env,
                   double speed_noise_kmh, double pitch_noise_deg, double fuel_noise_rel,
                   uint64_t seed);
/* Road grade (tan alpha) at a position, m: +-3 %, wavelengths 1.5 km and 430 m. */
double id_drive_grade(double position_m);
/* 100 ms of driving (ten 10 ms steps); *s receives the samples at its end. */
void id_drive_advance(id_drive_t *d, pfe_identify_sample_t *s);
/* Fuel rate, L/s, eq. 3.11 for the drive's current state with another
 * truck's mass and aux power (the same drag, rolling, efficiency). */
double id_drive_fuel_rate_with(const id_drive_t *d, double mass_kg, double aux_w);

#endif /* IDENTIFY_REF_H */
