/*
 * fuel_bounds.h - lower and upper bounds on a platoon's fuel over a route
 * (thesis 5.1, as REFERENCE.md section 1 restates them), with the object
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
 * the platoon ends at the speed it started with, and the route has at least
 * one upgrade on which the platoon cannot hold its set speed.
 * fuel_bounds_t reports whether the object-model run meets them.
 */
#ifndef FUEL_BOUNDS_H
#define FUEL_BOUNDS_H

#include <stdbool.h>
#include <stddef.h>

#include "node_model.h"

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
} fuel_bounds_t;

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

typedef struct {
    double fuel_l, lower_l, upper_l;
} route_estimate_t;

/*
 * Ranks n routes by predicted fuel (ties by index): order[0 .. n-1] receives
 * route indices, best first. Returns 1 when the best route is guaranteed
 * best (thesis 5.1: its upper bound is below the lower bound of every other
 * route), 0 when it is not, and then *blocker (if not NULL) is a route whose
 * lower bound is at or below the best's upper bound, the lowest such; -1
 * for n < 2 or a NULL argument. O(n^2), no allocation.
 */
int route_rank(const route_estimate_t *est, size_t n, size_t *order, size_t *blocker);

#endif /* FUEL_BOUNDS_H */
