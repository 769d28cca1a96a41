/*
 * pfe_sim.h - the platoon object model driven over a road (thesis 5.2).
 *
 * The platoon (one point mass, eq. 4.3) under the PI cruise control runs
 * over a road profile in fixed distance steps: this is what the module uses
 * to predict fuel over the road ahead, and what the host simulator compares
 * with the double-precision reference.
 *
 * Discretisation (explicit Euler in distance; the reference uses the same):
 *   dt      = ds / v                         (v at the start of the step)
 *   grade   = road sample holding at the step's midpoint (zero-order hold)
 *   Fw      = PI(v_set - v), within [-Fb_max, min(Pmax / v, traction) - c v^2]
 *             (c: the formation drag of pfe_platoon.h)
 *   a       = (Fw - Fa(v) - Fr - Fg) / M     eq. 4.3
 *   v      += a dt
 *   fuel   += delta (Fw' ds + Paux dt) / (eta rho_d), Fw' = (M + Mj) a +
 *             Fa + Fr + Fg (eq. 3.7, 4.14: work Fw' v dt = Fw' ds)
 * The fuel is summed as work and time: each step adds its Fw' ds and its
 * dt (where delta is 1) to two exact integer sums, and the fuel is made
 * from them, rounded once, when pfe_sim_run() returns (not rounded a step
 * at a time, which added up to half a nL a step).
 * A step in distance rather than time keeps the cost of a route to its
 * length / ds steps whatever the speed (1200 steps for 12 km at 10 m).
 *
 * Units: position mm (uint32: routes up to 4294 km), speed um/s internally
 * and mm/s at the interface, time s * 2^16, fuel nL (uint64), force N.
 * The distance step is PFE_SIM_STEP_MIN_MM .. PFE_SIM_STEP_MAX_MM; below
 * PFE_SIM_STALL_MM_S the platoon is considered stalled (it cannot climb the
 * grade) and the simulation stops with PFE_ESTALL.
 *
 * Stability: an explicit Euler step follows the speed only while it lasts
 * less than the speed's time constant, and diverges beyond twice that: the
 * controller's, min(1 / kp, 1 / sqrt(ki)), and at the power limit, where
 * Fw = Pmax / v stiffens as the speed falls, M v^2 / Pmax (a 40 t truck
 * crawling up 20 % at 3.08 m/s: 1.5 s, while a 12 m step lasts 3.9 s). A
 * step is therefore shortened to v times the shorter of the two (at least
 * PFE_SIM_STEP_MIN_MM). Only slow or stiff runs are concerned: below
 * stiff_below_mm_s, computed once at init (4.2 m/s for the default truck
 * with 12 m steps); faster steps are exactly as above, with no extra cost.
 */
#ifndef PFE_SIM_H
#define PFE_SIM_H

#include <stdint.h>

#include "pfe_calib.h"
#include "pfe_pi.h"
#include "pfe_platoon.h"

#define PFE_SIM_STEP_MIN_MM 100U
#define PFE_SIM_STEP_MAX_MM 16000U
#define PFE_SIM_STALL_MM_S 1000 /* 3.6 km/h */

/* Return codes of pfe_sim_step(). */
#define PFE_SIM_DONE 0        /* the end of the road was reached before this call */
#define PFE_SIM_RUNNING 1     /* one step was taken */
#define PFE_ESTALL (-11)      /* speed fell below PFE_SIM_STALL_MM_S */

/* A road profile: grade_ppm[k] holds on [k * spacing, (k + 1) * spacing). */
typedef struct {
    const int32_t *grade_ppm;
    uint32_t n_samples;
    uint32_t spacing_mm;
} pfe_road_t;

typedef struct {
    const pfe_platoon_t *platoon;
    pfe_pi_t pi;
    uint32_t step_mm;
    uint32_t end_mm;
    int32_t set_speed_um_s;
    /* Object-model resistance split for the step (eq. 4.8, 4.10): the
     * rolling part is constant, the grade part linear in the grade. */
    int64_t roll_q2;         /* cr M g, N * 2^2 */
    uint64_t air_bias;       /* roll_q2 * 2^32 + 2^31: air drag and rolling summed with one
                              * multiply-accumulate (pfe_sim.c) */
    uint32_t air_x4_q32;     /* the object's air_q32 * 4, below 2^24 */
    int32_t weight_m;        /* M g in N * 2^36 / 10^6 (below 2^42) = weight_m * 2^s, s >= 2
                              * (pfe_mantissa_i32()): Fg [N * 2^2] = weight_m *
                              * (grade_ppm * weight_scale) / 2^32 */
    int32_t weight_scale;    /* 2^(s - 2), at most 2^10 */
    int32_t mass_fuel_m;     /* (M + Mj) as pfe_vehicle_t.mass_fuel_q32 (< 2^35) = mass_fuel_m
                              * * 2^s: (M + Mj) a [N * 2^2] = mass_fuel_m * (a *
                              * mass_fuel_scale) / 2^32 */
    int32_t mass_fuel_scale; /* 2^(s + 2), at most 2^6 */
    int64_t aux_fuel_q8;     /* fuel for sum Paux, nL/s * 2^8 (eq. 4.14) */
    uint32_t ctrl_tau_ms;    /* the controller's time constant, min(1 / kp, 1 / sqrt(ki)) */
    uint32_t stiff_below_mm_s; /* below this speed a step may be shortened (see the top) */
    uint32_t formation_air_q32; /* the platoon's formation drag (pfe_platoon.h), held here */
    uint32_t power_max_w;    /* the object's Pmax, held here */
    int32_t traction_cap_n;  /* the object's traction, at most INT32_MAX */
    int32_t brake_min_n;     /* -Fb_max of the object: the controller's lower limit */
    /* State after the last step. */
    int32_t speed_um_s;
    uint32_t position_mm;
    uint32_t steps;
    uint64_t time_q16;       /* s * 2^16 */
    uint64_t fuel_nl;        /* platoon total, eq. 4.14: the fuel of the two sums below,
                              * each rounded to the nL */
    uint64_t work_q2_mm;     /* sum of Fw' ds over the steps with Fw' > 0, N * 2^2 * mm
                              * (each Fw' at most 2^27, so below 2^59 for any road) */
    uint64_t pull_time_q16;  /* sum of dt over the same steps, s * 2^16 */
    /* What the last step used and produced. */
    int32_t grade_ppm;
    int32_t wheel_force_n;   /* controller output */
    int32_t accel_um_s2;
    uint64_t fuel_step_nl;   /* what the last call's steps added to fuel_nl: pfe_sim_step()'s,
                              * its step's */
} pfe_sim_t;

/*
 * Starts a run at position 0 with speed initial_speed_mm_s and the
 * controller's integrator preset to the force that holds that speed on the
 * first grade sample (a start at equilibrium). The platoon and road must
 * outlive the run. Returns PFE_OK or PFE_EINVAL (NULL argument, empty road,
 * spacing 0, road longer than 4294 km, a grade sample beyond
 * +-PFE_GRADE_MAX_PPM, step out of range, speeds outside
 * [PFE_SIM_STALL_MM_S, PFE_SPEED_MAX_MM_S], cruise calibration invalid).
 */
int pfe_sim_init(pfe_sim_t *sim, const pfe_platoon_t *platoon, const pfe_cruise_calib_t *cruise,
                 const pfe_road_t *road, int32_t set_speed_mm_s, int32_t initial_speed_mm_s,
                 uint32_t step_mm);

/*
 * One distance step (the last one is shortened to end exactly at the end of
 * the road, a slow one as the top says). Returns PFE_SIM_RUNNING,
 * PFE_SIM_DONE, or PFE_ESTALL. Cost: a fixed number of operations (four
 * 32-bit divisions; below stiff_below_mm_s two more and a 64-bit one), no
 * loop: about 160 Cortex-M4 instructions inside pfe_sim_run() (docs/bench.md).
 */
int pfe_sim_step(pfe_sim_t *sim, const pfe_road_t *road);

/*
 * Sums over a run besides its fuel (pfe_sim_run()), for the prediction's
 * bounds (pfe_predict.h). A run with a bound sums the bound alone: its own
 * fuel is not summed (fuel_nl, work_q2_mm, pull_time_q16 and aux_nl stay
 * as they were, fuel_step_nl is 0); its trajectory (speed, position, time,
 * the controller) is the same as without sums.
 *   aux_nl    the auxiliaries' part of fuel_nl (the steps' time summed, its
 *             fuel rounded once: pfe_sim_t.pull_time_q16);
 *   bound_*   when bound_grade_20ppm is not NULL, the work of a fuel bound
 *             over the steps where the controller pulls (Fw > 0),
 *             sum (bound_air v^2 + Fr + M g bound_grade[k]) ds, v the step's
 *             starting speed, k the sample of its midpoint, negative
 *             downhill: linear in v^2, 1 and the grade, it is summed as
 *             three sums, sum v^2 ds / 2 (v^2 / 2 rounded down), sum ds and
 *             sum bound_grade ds, each exact;
 *   bound_nl  that work's fuel at bound_fuel, made from the three sums
 *             when pfe_sim_run() returns and rounded once to the nearest nL
 *             (halves away from zero).
 */
typedef struct {
    const int16_t *bound_grade_20ppm; /* one per road sample, in 20 ppm (+-25000); NULL: no bound */
    int64_t bound_air_q32;            /* as pfe_vehicle_t.air_q32, at most
                                       * PFE_FORMATION_AIR_MAX_Q32 (a platoon's) */
    int64_t bound_fuel_q20;           /* as pfe_vehicle_t.fuel_q20 */
    uint64_t bound_v2_ds;             /* sum v^2 / 2 ds, (mm/s)^2 * mm: below 2^63 for any road */
    uint64_t bound_ds_mm;             /* sum ds, mm */
    int64_t bound_grade_ds;           /* sum bound_grade ds, 20 ppm * mm: below 2^47 */
    int64_t bound_nl;
    uint64_t aux_nl;
} pfe_sim_sums_t;

/*
 * Up to max_steps steps (the same as calling pfe_sim_step() that often, at
 * less cost per step, but for fuel_step_nl: what this call's steps added),
 * adding to *sums unless it is NULL: stops early at the
 * end of the road or on a stall; max_steps UINT32_MAX runs to the end.
 * Returns PFE_SIM_RUNNING (max_steps taken, more to go), PFE_SIM_DONE or
 * PFE_ESTALL.
 */
int pfe_sim_run(pfe_sim_t *sim, const pfe_road_t *road, uint32_t max_steps, pfe_sim_sums_t *sums);

/* Speed in mm/s, rounded. */
int32_t pfe_sim_speed_mm_s(const pfe_sim_t *sim);

#endif /* PFE_SIM_H */
