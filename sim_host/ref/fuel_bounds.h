/*
 * fuel_bounds.h - lower and upper bounds on a platoon's fuel over a route
 * (thesis 5.1, eq. 5.1 to 5.10, restated in docs/model.md), with the object
 * model's prediction between them.
 *
 * Fuel is work over eta rho_d, counted only where the wheel force is
 * positive (eq. 3.9). Each bound adds four terms over the parts of a
 * trajectory where fuel is on:
 *
 *   efficiency (5.1)  lower: 1 / (max_i eta_i rho_d); upper: 1 / (min_i eta_i rho_d)
 *   acceleration (5.3) 0: start and end speed equal (the route's assumption)
 *   air drag (5.5)    lower: 1/2 rho_air (cw Af)_min sum_i (1 - phi_i(d/2)/100) v^2 ds
 *                           along the v_min trajectory
 *                     upper: 1/2 rho_air (cw Af)_max N v^2 ds along the v_max
 *                           trajectory (no reduction at all)
 *   rolling (5.7)     g sum_i cr_i m_i ds along v_min (lower) or v_max (upper)
 *   grade (5.10)      M g alpha_s ds (lower) or M g alpha_l ds (upper), alpha_s and
 *                     alpha_l the smallest and largest grade within +-(N - 1) dp of
 *                     the platoon's centre
 *
 * plus the auxiliary power, sum_i Paux_i times the time fuel is on.
 *
 * The choices the thesis leaves open, and what this module does:
 *
 * - v_min and v_max (5.1.2): object-model runs (node_model.h, same time step
 *   as the node model) with the parameters that make the platoon slowest
 *   (OBJECT_SLOWEST: largest cw Af on every truck, no drag reduction, the
 *   weakest Pmax / m) and fastest (OBJECT_FASTEST: smallest cw Af, phi_i(d/2),
 *   the strongest Pmax / m). "Where Fw > 0" is read on the same run: the
 *   lower bound sums over the steps where the v_min run burns fuel, the
 *   upper bound over those where the v_max run does (delta of eq. 3.9, with
 *   the fuel model's force (m + mj) a + resistance).
 * - cw Af: the model has the product only (pfe_vehicle_calib_t), so "the
 *   smallest and largest frontal area" are the smallest and largest cw Af.
 * - The platoon's centre is the object model's point mass; dp is the
 *   desired spacing of successive trucks at the set speed, bumper to bumper
 *   plus one truck length (d0 + h v_set + length: 26.5 m by default): the
 *   thesis's trucks are points, and twice the half-length of a real platoon
 *   is (N - 1) (gap + length). The window is cut by the road's ends, where
 *   the road's first and last grades extend it, as in the node model.
 * - Grade and rolling keep the thesis's small angles (sin alpha ~ alpha,
 *   cos alpha ~ 1); the node model uses exact ones. At a 5 % grade both
 *   differ from the exact forms by 0.125 % (1 - 1 / sqrt(1.0025)).
 * - Auxiliary power (the thesis leaves it out: it is the same in both
 *   models): the time with fuel on is not, so the lower bound takes the
 *   shorter of the two runs' fuel-on times and the upper bound the longer.
 * - The bounds are on the fuel of the whole platoon over the route, the
 *   quantity the node model gives (each truck over the whole road).
 * - A lower bound below zero (a long platoon on a hilly road, whose window
 *   holds a steep downgrade nearly everywhere) is raised to zero.
 *
 * They hold when the route meets the thesis's assumptions (5.1.2, 5.1.4):
 * the platoon ends at the speed it started with (eq. 5.3: the acceleration
 * force does no net work where fuel is on), and the route has at least one
 * upgrade on which the platoon cannot hold its set speed (otherwise the
 * v_min and v_max runs are not slower and faster than the platoon: the
 * controllers' ripple decides). fuel_bounds_t reports whether the
 * object-model run meets them (lower_holds, upper_holds).
 *
 * The energy lower bound, for where they do not (fuel_energy_bound_t). On
 * a climb the platoon cannot hold, it slows with fuel on: the kinetic
 * energy it gives up does part of the climbing, and eq. 5.3's zero
 * overstates the work (uphill road: 49.58 L against the node model's
 * 48.80 L). Truck i's wheel force Fw does, where fuel is on, at least the
 * work it does over the whole road, since fuel is off only where Fw <= 0
 * (eq. 3.9). Over the road that work is exact:
 *
 *   W_i = (m_i + mj_i) (v_exit^2 - v_entry^2) / 2        kinetic energy
 *       + m_i g sum_k sin(alpha_k) ds_k                  grade (exact, the height gained)
 *       + cr_i m_i g sum_k cos(alpha_k) ds_k             rolling (exact)
 *       + integral of air drag                           >= 1/2 rho cwAf_i (1 - phi_i(d/2)) v_floor^2 L
 *
 * and the time with fuel on is at least W_i / Pmax_i (the wheel power never
 * exceeds Pmax), so
 *
 *   fuel_i >= max(0, W_i) (1 + Paux_i / Pmax_i) / (eta_i rho_d).
 *
 * It assumes speeds only, each with a margin of FUEL_BOUNDS_SAME_SPEED_KMH:
 * no truck drives slower than the v_min run's lowest speed less the margin
 * (v_floor), leaves the road slower than the v_min run's end speed less
 * the margin, or enters it faster than the followers' set speed plus their
 * margin (node_config_t), and no gap closes below half the desired gap
 * (the thesis's own assumption for the air drag, 5.1.2). No upgrade and no
 * equal end speeds are needed. It is below the thesis's lower bound where
 * both hold (it counts the downgrades the thesis's window leaves out), so
 * fuel_bounds_t's sound_lower_l takes the larger of the two where the
 * thesis's assumptions hold and the energy bound alone where they do not.
 */
#ifndef FUEL_BOUNDS_H
#define FUEL_BOUNDS_H

#include <stdbool.h>
#include <stddef.h>

#include "ref/node_model.h"

/* A run falls this far below the set speed on an upgrade it cannot hold. */
#define FUEL_BOUNDS_UPGRADE_DROP_KMH 2.0
/* End and start speed are "the same" within this. */
#define FUEL_BOUNDS_SAME_SPEED_KMH 1.0

typedef struct {
    double work_air_j, work_roll_j, work_grade_j; /* over the fuel-on steps */
    double time_on_s;                             /* time with fuel on */
    double aux_j;                                 /* sum Paux times the chosen fuel-on time */
    double fuel_l;                                /* the bound */
} fuel_bound_terms_t;

/* The energy lower bound (above): its terms summed over the trucks. */
typedef struct {
    double work_kinetic_j, work_grade_j, work_roll_j, work_air_j;
    double aux_j;                                 /* sum Paux_i W_i / Pmax_i */
    double floor_kmh, exit_floor_kmh, entry_ceiling_kmh; /* the speeds it assumes */
    double fuel_l;
} fuel_energy_bound_t;

typedef struct {
    /* The object model's prediction (OBJECT_NOMINAL). */
    double fuel_l, time_s, start_kmh, end_kmh, min_kmh;
    double lower_l, upper_l;
    fuel_bound_terms_t lower, upper;
    /* The v_min (OBJECT_SLOWEST) and v_max (OBJECT_FASTEST) runs. */
    double slow_time_s, slow_min_kmh, fast_time_s, fast_max_kmh;
    double eta_min, eta_max;
    double window_m;             /* (N - 1) dp each side of the centre */
    bool same_speed;             /* |end - start| <= FUEL_BOUNDS_SAME_SPEED_KMH */
    bool upgrade;                /* the prediction drops FUEL_BOUNDS_UPGRADE_DROP_KMH below set */
    /* Whether the thesis's bounds (lower_l, upper_l) hold their
     * assumptions: same_speed and upgrade, for both. */
    bool lower_holds, upper_holds;
    fuel_energy_bound_t energy;  /* holds without them */
    /* The lower bound to rely on: max(lower_l, energy) where lower_holds,
     * else the energy bound; sound_lower_energy says which one it is. */
    double sound_lower_l;
    bool sound_lower_energy;
} fuel_bounds_t;

/* Why a bound's assumptions fail, as a phrase ("the platoon ends at 74.3 km/h,
 * not its start speed 90.0 km/h (eq. 5.3)"), or "" when they hold; b is a
 * filled fuel_bounds_t. Returns buf. */
const char *fuel_bounds_why_not(const fuel_bounds_t *b, char *buf, size_t len);

/* Smallest and largest grade (fraction) over the samples that
 * [centre - half_window, centre + half_window] touches, the road's end
 * samples standing for everything beyond them. */
void fuel_bounds_grade_window(const ref_road_t *road, double centre_m, double half_window_m,
                              double *min_out, double *max_out);

/*
 * Runs the object model three times over the road (nominal, slowest,
 * fastest) and fills *out. Returns 0; -1 for a configuration that fails
 * node_config_check or an empty road; -2 when a run stalls (the road is too
 * steep for the platoon). err (may be NULL) says which. Time O(steps *
 * (1 + window samples)); no allocation; not reentrant on the same *out.
 */
int fuel_bounds_compute(const node_config_t *cfg, const ref_road_t *road, fuel_bounds_t *out,
                        char *err, size_t err_len);

/* ---------------------------------------------------------------- route choice */

/* lower_l must be a lower bound that holds (sound_lower_l); upper_fails is
 * NULL when upper_l holds its assumptions, else why it does not. */
typedef struct {
    double fuel_l, lower_l, upper_l;
    const char *upper_fails;
} route_estimate_t;

/*
 * Ranks n routes by predicted fuel (ties by index): order[0 .. n-1] receives
 * route indices, best first. Returns 1 when the best route is guaranteed
 * best (thesis 5.1: its upper bound holds its assumptions and is below the
 * lower bound of every other route); 0 when the bounds overlap, and then
 * *blocker (if not NULL) is a route whose lower bound is at or below the
 * best's upper bound, the lowest such; 2 when the numbers would guarantee
 * it but the best route's upper bound does not hold its assumptions
 * (upper_fails); -1 for n < 2 or a NULL argument. O(n^2), no allocation.
 */
int route_rank(const route_estimate_t *est, size_t n, size_t *order, size_t *blocker);

#endif /* FUEL_BOUNDS_H */
