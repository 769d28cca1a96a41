/*
 * node_model.h - the platoon node model (thesis chapter 5.2) and the object
 * model (chapter 4) stepped the same way, in double precision.
 *
 * Node model: N point masses, truck 0 in front. Each is the chapter 3 model
 * (eq. 3.2 to 3.11, exact trigonometry, ref_vehicle_resistance) at its own
 * position on the road, with the air-drag reduction phi_i(d) of its actual
 * gap (eq. 3.4: the leader's gap is the one to its follower, a follower's
 * the one to the truck ahead). The leader runs the cruise PI to the set
 * speed, with the gains per unit mass of the object model
 * (pfe_cruise_calib_t). Follower i runs a PI of its spacing error with a
 * relative-speed term, the law of an adaptive cruise control, all per unit
 * mass:
 *
 *     e_i = gap_i - (d0 + h v_i),
 *     F_gap = m_i (kp e_i + kv (v_(i-1) - v_i)) + I_i,   dI_i/dt = m_i ki e_i,
 *
 * and keeps its own cruise control to the set speed plus a margin (2 km/h):
 * the smaller of the two forces is applied, within the chapter 3 limits
 * (-Fb_max, min(Pmax / v, traction)). The integral stops when it would push
 * a saturated force further, stays within the truck's force range, and in
 * the controller that is not in command it follows the applied force, so
 * that handing over does not jump.
 *
 * Gains (the thesis does not publish its own). Linearised, with the truck
 * ahead at speed r and the follower at speed y:
 *
 *     y / r = (kv s^2 + kp s + ki) / (s^3 + (kv + h kp) s^2 + (kp + h ki) s + ki).
 *
 * |y / r| <= 1 at every frequency (string stability: a speed change is not
 * amplified down the platoon) exactly when 2 kv h + kp h^2 >= 2. The
 * defaults kp = 1 /s^2, kv = 2.5 /s (= 1 / h) and ki = 0.1 /s^3 give
 * 2.16 and place the poles at -2.5 /s and -0.2 /s (twice, a 5 s time
 * constant for the gap), and with 0.1 s steps the explicit update is inside
 * its stability region (|1 + s dt| <= 0.98).
 *
 * Why not a PI alone: without the relative-speed term string stability
 * needs kp h^2 > 2 (kp > 12.5 /s^2 at h = 0.4 s), so that 1 m of spacing
 * error asks for more than 12.5 m/s^2; the force limits then clip nearly
 * every transient and the linear result no longer holds. Tried with
 * kp = 20 /s^2, ki = 5 /s^3: on the hilly road 5 trucks collided (gap
 * -46 m) and 50 trucks stopped. Why the followers' own cruise control:
 * without it a follower left behind on a crest chases the platoon down the
 * next slope at full power; on the hilly road 5 trucks then reach 106 km/h,
 * 10 trucks 116 km/h with gaps down to 2.1 m, and 20 or 50 trucks pile up
 * and stop (platoon_compare --margin-kmh 36). The margin changes the node
 * model's fuel on the hilly road by 0.4 to 0.7 % per km/h (fuel spent
 * catching up is braked away again): 26.60 L at 0, 26.89 L at 2 km/h, the
 * default, which closes a 10 m gap in about 20 s.
 *
 * Spacing policy (node_spacing_t; the gap is rear bumper to front bumper,
 * trucks have a length L, default 16.5 m, the EU limit for a tractor and
 * semitrailer, so that position to position is L + gap):
 *
 *   NODE_SPACING_GAP      d = d0 + h v, h = 0.4 s (thesis 6.4), d0 chosen so
 *                         that d = 10 m at the 90 km/h set speed: d0 = 0 m.
 *                         The default.
 *   NODE_SPACING_HEADWAY  a constant time headway T between two trucks'
 *                         fronts passing the same point (traffic
 *                         engineering's time headway), T = (L + d0 + h v_set)
 *                         / v_set: the same gap as above at the set speed
 *                         (10 m), and at speed v the gap d = T v - L, never
 *                         below headway_floor_m (default 3 m). Followers then
 *                         ride the leader's speed profile in space: each
 *                         truck meets every grade at the speed the leader
 *                         met it, which is what the object model's one speed
 *                         and one grade describe (eq. 4.9 summed over the
 *                         platoon's passage of a point x: each truck's grade
 *                         force there is m_i g alpha(x), so the sum is
 *                         M g alpha(x), eq. 4.10 with alpha_p = alpha(x)).
 *
 * The thesis's node model has point masses (L = 0, d0 = 0), for which the
 * two are the same policy, d = h v (T = h), above the floor's h v = 3 m
 * (27 km/h): platoon_compare's table 5.1 to 5.5 analogue uses that.
 *
 * Why two, measured with 5 trucks of 16.5 m (tests/host/test_truck_length.c,
 * platoon_compare --length-m 16.5 [--spacing headway]). Under the gap
 * policy the time between two trucks passing a point, (L + d0) / v + h,
 * changes with speed, so the followers must fall back before every climb
 * and close up after it, and the fuel spent catching up is braked away: on
 * the hilly road the followers burn 3.75 % more than point masses and each
 * brakes away 1.3 to 2.2 MJ more (81.7 against 74.5 MJ for the four),
 * gaps open to 21 m; the object model, which cannot represent this, is
 * -2.80 % from the node model (-2.97 % with the grade under each truck,
 * object_sim_truck_grades), and on 250 random routes (route_gen_hilly) 1.38 %
 * off on average, at worst -3.2 %. Under the headway policy there is no such
 * catching up (the four followers brake 71.7 MJ, less than point masses),
 * but the gap closes as the platoon slows, faster than h v does (dd/dv =
 * T = 1.06 s against 0.4 s): 5.51 m at 74.7 km/h on the uphill road, 2.85 m
 * on the hilly road (lowest speed 65.9 km/h), and without a floor 0 at
 * L / T = 56 km/h (on the random routes, without the floor, the gap fell
 * below 2 m on 137 of 250 and the trucks touched on one, -0.22 m). The followers
 * then get more slipstream on every climb than the object model's gap at
 * the set speed gives (eq. 4.7), and the object model burns more than the
 * node model: flat 0.000 %, uphill +0.76 %, hilly +1.31 % (+1.13 % with the
 * grade under each truck); random routes 0.36 % on average, at worst
 * -1.14 %, within 0.3 % on 112 of 250, smallest gap 2.56 m. With the drag
 * reduction of the policy's gap at the platoon's speed instead of eq. 4.7's
 * (object_sim_policy_drag, not the firmware's model) the uphill road is
 * -0.07 % (its difference is the gap's drag) and the hilly +0.70 % (the
 * rest there is the followers' gap tracking on the steep part of phi at 3
 * to 5 m: with follower gains kp 3 /s^2, ki 0.3 /s^3 it is +0.42 %); on the
 * random routes it is no better (0.41 % on average, at
 * worst -1.77 %, seed 5): there the platoon slows to 52 km/h, below the
 * floor's (L + 3 m) / T = 66 km/h, where the gap is held at 3 m and the
 * followers fall back (to 21 m) and catch up again. Neither policy brings
 * the object model within 0.3 % of the node model for trucks of length;
 * the headway policy is the one whose kinematics the object model
 * describes, and the one platoon_compare's length tables use. The default
 * stays the gap policy: it is how an adaptive cruise control keeps its
 * distance (rear to front, growing with speed), and with it the node model
 * shows what the object model misses for such a platoon. The 3 m
 * floor is the model's own choice (the drag table's data starts at 2 m),
 * not a safety figure: a lower floor keeps more routes free of catching up
 * but lets the trucks nearly touch (no floor: below 2 m on 137 of 250).
 *
 * Each position's fuel (object_sim_position_fuel, eq. 4.11 with each
 * truck's own delta_i), measured with the same 5 trucks, headway policy,
 * the policy's drag in the dynamics (tests/host/test_truck_length.c):
 * clipping each position at the point changes little (hilly +0.72 %, 250
 * routes 0.40 % on average): with the same speed, acceleration and grade
 * the trucks differ only in phi_i, so they coast together. The followers
 * where the policy puts them (each speed a first-order lag, time constant
 * T, of the speed ahead) give uphill -0.05 %, hilly +0.52 %, routes 0.33 %
 * (146 within 0.3 %, worst -1.47 %); within their force limits and speed
 * cap uphill +0.01 %, hilly +0.84 %, routes 0.19 % on average, 208 of 250
 * within 0.3 %, worst +0.84 % (seed 210). Where the rest lies: on 176 of
 * the 250 routes the platoon drops below the floor's 66 km/h (97 of them
 * outside 0.3 % with the unlimited followers, against 7 of the other 74);
 * on the hilly road the node's followers, lagging their policy on every
 * change of speed, ride 0.2 to 0.6 m closer than the policy while the
 * platoon re-accelerates after a crest (the steep part of phi) and burn
 * 0.3 to 0.9 % less than followers that hold it exactly. That is the
 * followers' controller, not the object model: with kp 25 /s^2, ki 2.5
 * /s^3, kv 10 /s at 0.02 s the hilly road comes to +0.25 % (unlimited
 * followers), but those gains take the random routes to 1.15 % on
 * average. Even point masses, the thesis's own case, are within 0.3 % on
 * 245 of the 250 routes with eq. 4.14 (worst -0.42 %, seed 92) and on 244
 * with the limited followers.
 *
 * The followers driven by their own controller
 * (OBJECT_FUEL_FOLLOWERS_CONTROLLED, same 5 trucks, headway policy, the
 * policy's drag in the point's dynamics): flat 0.000 %, uphill +0.014 %,
 * hilly +0.011 %, 250 routes 0.048 % on average, 247 within 0.3 %, worst
 * +0.52 % (seed 172); the three that miss (31 -0.52 %, 172 +0.52 %, 200
 * +0.31 %) all drop below the floor's 66 km/h (to 61, 59 and 61 km/h):
 * a follower left behind on a crest hands over to its own cruise control
 * (set speed + margin), and whether it then rejoins before the next climb
 * (object model) or chases the platoon over it 12 to 22 m behind (node
 * model) turns on a few tenths of a km/h in what position 0 passes on,
 * the point's speed instead of the node leader's. With 2, 10 and 20
 * trucks: hilly +0.017, -0.016 and -0.012 %, 249, 247 and 246 routes
 * within 0.3 %. The floor held in the policy's kinematics instead (below
 * it the gap held at the floor, each follower's time headway growing as
 * (L + floor) / v, and the catch-up within the followers' limits) is what
 * _FOLLOWERS and _LIMITED already do: 208 routes. The grade force is the
 * sum of each position's (eq. 4.9 at each truck's own place, in each
 * position's fuel and in each follower's dynamics); the point itself keeps
 * eq. 4.10 at its place, position 0: with the mean of the grades under the
 * trucks instead (object_sim_truck_grades) hilly +0.043 %, 246 routes
 * within 0.3 %, mean 0.108 %. With eq. 4.7's drag in the point's dynamics
 * instead of the policy's: uphill -0.17 %, hilly -0.13 %, 243 routes
 * within 0.3 %. The same with the gap policy: hilly +0.033 %, 245 within
 * 0.3 %, worst +0.40 %; with point masses all 250 within 0.3 % (worst
 * +0.056 %). What decides it is each follower's own grade acting through
 * its controller: the linearised loop above (y / r, no disturbance) with
 * the floor, the force limits (the integral held while saturated) and
 * the speed cap gives hilly -0.11 %, 148 routes within 0.3 %, worst
 * -1.05 %, further off than the policy held exactly (_LIMITED, 208). With
 * the object model's step (point and followers) 0.2 s, the node model's
 * kept at 0.1 s: hilly +0.050 %, 249
 * within 0.3 %; 0.25 s: +0.066 %, 242: which routes miss moves with the
 * step, the mean stays below 0.09 %. This object model needs the
 * followers' controller (gains, margin, floor), which the bus does not
 * carry (PFE_PlatoonConfig: size, position, gap, time gap, set speed), and
 * its cost is the node model's: 19.4 million host instructions for the
 * hilly road against the node model's 17.1 million and the object
 * model's 1.8 million (callgrind in make bench's thesis-bench,
 * followers_12km_insn_n5_length and its neighbours).
 *
 * At the start every
 * truck drives at the initial speed at its desired gap, truck i at
 * -i (length + d(v0)); the road's first grade extends behind its start and
 * its last grade past its end. Each truck's fuel, time and speeds are
 * counted while it is on the road, [0, road length]: every truck drives the
 * whole road once, as the object model's point mass does, and a run ends
 * when the last truck leaves the road. A step that crosses either end counts
 * for the fraction of its distance that lies on the road.
 *
 * Object model, stepped the same way: one point mass with the aggregates of
 * eq. 4.3 to 4.14 (object_platoon_build), small-angle forces
 * (ref_object_resistance), the cruise PI, and the drag reduction of the
 * desired gap at the set speed (eq. 4.7). It uses the same fixed time step
 * as the node model, so a step of one costs what one truck-step of the other
 * does and the comparison of their costs is fair; ref_sim (the firmware's
 * reference) steps 10 m of distance instead.
 *
 * Both models: explicit update over a fixed time step dt: the grade at the
 * predicted mid-step position x + v dt / 2, the force and acceleration from
 * the state at the start of the step, v' = v + a dt, x' = x + (v + v') dt / 2.
 * Fuel (eq. 3.7 to 3.11 and 4.14): when (m + mj) a + resistance > 0, the
 * step burns ((m + mj) a + resistance) ds + Paux dt, times 1 / (eta rho_d).
 * In the node model every truck is updated from the state at the start of
 * the step (a synchronous update), so the order of trucks does not matter.
 *
 * No I/O, no allocation except node_road_*; every struct is caller-owned.
 */
#ifndef NODE_MODEL_H
#define NODE_MODEL_H

#include <stdbool.h>
#include <stddef.h>

#include "firmware/pfe_calib.h"
#include "ref/ref_model.h"

/* Largest node-model platoon (the object model's firmware stops at 32). */
#define NODE_MAX_VEHICLES 64U

/* The followers' spacing policy (above). */
typedef enum { NODE_SPACING_GAP = 0, NODE_SPACING_HEADWAY } node_spacing_t;

typedef struct {
    unsigned n_vehicles;                                   /* 1 .. NODE_MAX_VEHICLES */
    const pfe_vehicle_calib_t *vehicle[NODE_MAX_VEHICLES]; /* 0 = lead; entries may share */
    const pfe_env_calib_t *env;
    const pfe_drag_table_t *drag;
    const pfe_cruise_calib_t *cruise; /* speed PI, per unit mass: leader and object model */
    double set_speed_m_s;
    double initial_speed_m_s;
    double time_gap_s;                /* h */
    double standstill_m;              /* d0 */
    double length_m;                  /* of every truck */
    node_spacing_t spacing;           /* the followers' spacing policy */
    double headway_floor_m;           /* NODE_SPACING_HEADWAY: the smallest desired gap */
    double follow_kp_s2;              /* follower: per unit mass, per m of spacing error */
    double follow_ki_s3;              /* ... per m of spacing error and s */
    double follow_kv_s;               /* ... per m/s of relative speed */
    double follow_margin_m_s;         /* followers' own cruise control: set speed + this */
    double step_s;                    /* fixed time step of both models */
} node_config_t;

/* The defaults above: n identical default trucks (pfe_calib.h), 90 km/h,
 * h 0.4 s, d0 0 m, 16.5 m, NODE_SPACING_GAP (headway floor 3 m), kp 1 /s^2, ki 0.1 /s^3, kv 2.5 /s, margin
 * 2 km/h, dt 0.1 s; n is clamped to [1, NODE_MAX_VEHICLES]. */
void node_config_default(node_config_t *cfg, unsigned n_vehicles);

/* Returns 0, or -1 naming the first bad field in err: a calibration that
 * fails its pfe_calib_check_*, speeds outside [1, 70] m/s, h outside
 * [0, 10] s, d0 outside [0, 100] m, a length outside [0, 30] m, a spacing
 * policy not in node_spacing_t, a headway floor outside [0, 100] m, gains not
 * positive or above 1000 (kv may be 0), a margin outside [0, 10] m/s, dt
 * outside [0.001, 1] s, or dt (kv + h kp) > 1: the followers' fast pole
 * lies near -(kv + h kp), and a longer step takes the explicit update to
 * the edge of its stability (0.34 s with the defaults; at 0.5 s the hilly
 * road's node fuel is off by 0.8 %). err may be NULL. */
int node_config_check(const node_config_t *cfg, char *err, size_t err_len);

/* The desired gap at a speed under cfg's spacing policy, m: d0 + h v, or
 * max(headway_floor_m, T v - L) with T = node_headway_s(cfg). Both give d0 + h v_set at
 * the set speed. */
double node_desired_gap_m(const node_config_t *cfg, double speed_m_s);
/* Time between two trucks' fronts passing a point at the set speed, s:
 * (L + d0 + h v_set) / v_set (the headway policy's T). */
double node_headway_s(const node_config_t *cfg);

/* ---------------------------------------------------------------- roads */

/* A road for both models: ref_road_t (grade as a fraction) owning its
 * samples. */
typedef struct {
    ref_road_t road;
    double *grade;
} node_road_t;

/* Loads a road CSV (road_csv.h). Returns 0, or -1 with the loader's message
 * ("FILE:LINE: reason") in err and *r empty. */
int node_road_load(const char *path, node_road_t *r, char *err, size_t err_len);
/* From grades in percent. Returns 0, or -1 (n < 1, spacing not > 0, a grade
 * not finite, out of memory) with *r empty. */
int node_road_from_percent(const double *grade_pct, size_t n, double spacing_m, node_road_t *r);
void node_road_free(node_road_t *r);

/* n_samples * spacing: sample k covers [k spacing, (k + 1) spacing). */
double node_road_length_m(const ref_road_t *road);
/* Grade (fraction) at a position; the first grade extends before 0, the
 * last past the end. */
double node_road_grade(const ref_road_t *road, double position_m);

/* ---------------------------------------------------------------- results */

typedef struct {
    double fuel_l;        /* the whole platoon over the road */
    double time_s;        /* on the road; node model: mean over trucks */
    double mean_kmh;      /* road length / time on it; node model: mean over trucks */
    double min_kmh;       /* lowest and highest speed on the road; node: of any truck */
    double max_kmh;
    double end_speed_kmh; /* speed on leaving the road; node model: mean over trucks */
    double min_gap_m;     /* node model: smallest and largest gap of any pair at any step */
    double max_gap_m;     /* (object model: the constant gap of eq. 4.7) */
    unsigned long steps;
    unsigned long evaluations; /* truck-steps: force, controller and fuel evaluations */
} model_summary_t;

/* ---------------------------------------------------------------- node model */

typedef struct {
    const node_config_t *cfg;
    const ref_road_t *road;
    double end_m, gravity;
    double air_k0[NODE_MAX_VEHICLES];       /* 1/2 rho cw Af, no reduction */
    ref_vehicle_t truck[NODE_MAX_VEHICLES]; /* chapter 3 coefficients; air_k of the actual gap */
    ref_pi_t cruise[NODE_MAX_VEHICLES];     /* every truck's cruise control (the leader's rules) */
    ref_pi_t spacing[NODE_MAX_VEHICLES];    /* followers' spacing control; its integral */
    double position_m[NODE_MAX_VEHICLES];
    double speed_m_s[NODE_MAX_VEHICLES];
    double fuel_l[NODE_MAX_VEHICLES];       /* on the road */
    double brake_j[NODE_MAX_VEHICLES];      /* on the road: work of negative wheel force, J */
    double time_on_s[NODE_MAX_VEHICLES];    /* on the road */
    double exit_speed_m_s[NODE_MAX_VEHICLES];
    double min_speed_m_s, max_speed_m_s;    /* on the road, any truck */
    double min_gap_m, max_gap_m;
    double time_s;
    unsigned long steps;
} node_sim_t;

/* Returns 0, or -1 for a configuration that fails node_config_check or an
 * empty road. */
int node_sim_init(node_sim_t *s, const node_config_t *cfg, const ref_road_t *road);
/* Returns 1 (a step taken), 0 (the last truck has left the road) or -1 (a
 * truck stalled below 1 m/s: the road is too steep for it; the state is then
 * part-way through a step and only good for reporting). */
int node_sim_step(node_sim_t *s);
/* Steps to the end and summarises. Returns 0 or -1 (stalled). */
int node_sim_run(node_sim_t *s, model_summary_t *out);
void node_sim_summary(const node_sim_t *s, model_summary_t *out);

/* ---------------------------------------------------------------- object model */

/*
 * Which parameters the point mass gets (thesis 5.1, docs/model.md):
 * NOMINAL  eq. 4.3 to 4.14, phi_i of the desired gap at the set speed.
 * SLOWEST  the v_min run: every truck with the largest cw Af and no drag
 *          reduction (the factor N of eq. 5.5), Pmax and traction per unit
 *          mass of the weakest truck (eq. 4.4).
 * FASTEST  the v_max run: every truck with the smallest cw Af and the drag
 *          reduction of half the desired gap, phi_i(d / 2); Pmax and
 *          traction per unit mass of the strongest truck.
 * Mass, rolling, brake, auxiliary power and efficiency are the nominal
 * aggregates in all three (they are known exactly; the bounds handle eta).
 */
typedef enum { OBJECT_NOMINAL, OBJECT_SLOWEST, OBJECT_FASTEST } object_choice_t;

/* Fills pl->n_vehicles, gap, gravity and object (positions are left zero):
 * the same sums as ref_platoon_init for up to NODE_MAX_VEHICLES trucks.
 * Returns 0 or -1 (configuration fails node_config_check). */
int object_platoon_build(ref_platoon_t *pl, const node_config_t *cfg, object_choice_t choice);

/* How the object model counts fuel: object_sim_position_fuel below. */
typedef enum {
    OBJECT_FUEL_AGGREGATE = 0,
    OBJECT_FUEL_POSITIONS,
    OBJECT_FUEL_FOLLOWERS,
    OBJECT_FUEL_FOLLOWERS_LIMITED,
    OBJECT_FUEL_FOLLOWERS_CONTROLLED
} object_fuel_t;

typedef struct {
    const ref_platoon_t *pl;
    const ref_road_t *road;
    double end_m, step_s, set_speed_m_s;
    ref_pi_t pi;
    double position_m, speed_m_s, time_s, fuel_l;
    double min_speed_m_s, max_speed_m_s;
    unsigned long steps;
    unsigned grade_points;  /* 1: the grade at the position (eq. 4.10); see object_sim_truck_grades */
    double grade_pitch_m;
    const node_config_t *policy_drag; /* NULL, or see object_sim_policy_drag */
    object_fuel_t fuel_by;            /* see object_sim_position_fuel */
    const node_config_t *fuel_cfg;    /* its platoon (NULL with OBJECT_FUEL_AGGREGATE) */
    double pos_x_m[NODE_MAX_VEHICLES];   /* OBJECT_FUEL_FOLLOWERS: each position's place, */
    double pos_v_m_s[NODE_MAX_VEHICLES]; /* speed */
    double pos_fuel_l[NODE_MAX_VEHICLES];/* and fuel on the road (also OBJECT_FUEL_POSITIONS) */
    ref_pi_t pos_cruise[NODE_MAX_VEHICLES];  /* OBJECT_FUEL_FOLLOWERS_CONTROLLED: each follower's */
    ref_pi_t pos_spacing[NODE_MAX_VEHICLES]; /* cruise and spacing control */
    /* The last step, for fuel_bounds: start speed, distance, time, the
     * mid-step position (where its grade was read), the fraction of it on
     * the road, whether fuel was on (delta of eq. 3.9). */
    double last_speed_m_s, last_ds_m, last_dt_s, last_mid_m, last_on_road;
    bool last_fuel_on;
} object_sim_t;

/* Returns 0, or -1 (empty road, a speed outside [1, 70] m/s, a step outside
 * [0.001, 1] s, bad cruise gains). */
int object_sim_init(object_sim_t *s, const ref_platoon_t *pl, const pfe_cruise_calib_t *cruise,
                    const ref_road_t *road, double set_speed_m_s, double initial_speed_m_s,
                    double step_s);
/*
 * The grade under each truck instead of at one point (eq. 4.9 with the
 * trucks of a rigid formation, equal masses): the mean of the grades at
 * n_points places pitch_m apart, centred on the position (for the node
 * model's trucks at the set speed, pitch = L + d(v_set)). Under the headway
 * policy this is not what the derivation gives (node_model.h: every truck
 * meets each grade at the leader's speed, eq. 4.10); platoon_compare shows
 * it beside for what it changes. Call after object_sim_init; n_points 0 is
 * taken as 1. Costs n_points grade reads per step.
 */
void object_sim_truck_grades(object_sim_t *s, unsigned n_points, double pitch_m);
/*
 * The drag reduction of the spacing policy's gap at the platoon's speed,
 * phi_i(d(v)) in eq. 4.6 and in the formation drag, instead of the set
 * speed's gap (eq. 4.7), for the nominal platoon of cfg (kept by pointer;
 * identical trucks, as object_platoon_build's NOMINAL with cfg). Not the
 * object model of the firmware: platoon_compare shows it beside to tell how
 * much of the difference from the node model is the gap's change with
 * speed. Costs N table look-ups per step. Call after object_sim_init.
 */
void object_sim_policy_drag(object_sim_t *s, const node_config_t *cfg);
/*
 * Each position's fuel with its own clipping, for trucks of length (thesis
 * eq. 4.11 without the assumption that turns it into eq. 4.12 and 4.14).
 *
 * Eq. 4.11 sums each truck's fuel, delta_i (P_i + Paux_i) / (eta_i rho_d),
 * with delta_i of its own driving force (eq. 3.9); eq. 4.12 assumes every
 * F_w,i > 0 and so clips the platoon's summed force once. A truck coasting
 * while another still pulls then costs the pulling one's fuel less the
 * coasting one's negative force, and the coasting one's Paux is counted.
 * The speed stays the object model's (eq. 4.3: the summed force, one
 * acceleration, the cruise PI); only the fuel is counted per position:
 *
 *   OBJECT_FUEL_AGGREGATE  eq. 4.14, the default (object_sim_init).
 *   OBJECT_FUEL_POSITIONS  every position at the platoon's place, speed and
 *                          acceleration, with its own phi_i of the policy's
 *                          gap at that speed, its own eta_i, Paux_i and
 *                          delta_i: F_w,i = (m_i + mj_i) a_p + k_i(d(v_p))
 *                          v_p^2 + m_i g (cr + alpha_p). Under the headway
 *                          policy this is each truck's passage of the point
 *                          (node_model.h: every truck meets a grade at the
 *                          speed the leader met it), so alpha_p is the one
 *                          grade of eq. 4.10.
 *   OBJECT_FUEL_FOLLOWERS  position 0 is the platoon's point; position i >= 1
 *                          is where the spacing policy puts it behind
 *                          position i - 1, holding its gap exactly:
 *                          x_(i-1) - x_i = L + d(v_i), so that
 *                            headway: v_i = (x_(i-1) - x_i) / T, while the
 *                                     gap is above the floor; at the floor
 *                                     v_i = min(v_(i-1), (L + floor) / T);
 *                            gap:     v_i = (x_(i-1) - x_i - L - d0) / h
 *                                     (v_i = v_(i-1) for h = 0).
 *                          Each speed is thus a first-order lag of the
 *                          speed ahead, time constant T (or h): the platoon
 *                          is not rigid, in space or in time. The update is
 *                          the trapezoid x_i' = x_i + (v_i + v_i') dt / 2
 *                          with v_i' from x_i' (implicit, stable for any
 *                          dt). Each position's fuel is eq. 3.7 to 3.11 in
 *                          the small angles of eq. 4.8 and 4.9 at its own
 *                          place, speed, acceleration (v_i' - v_i) / dt and
 *                          actual gap (the leader's: to position 1), with
 *                          its own delta_i, counted while it is on the road;
 *                          a run ends when the last position leaves the
 *                          road (the point runs on over the last grade).
 *                          No force limits: the policy held exactly.
 *   OBJECT_FUEL_FOLLOWERS_LIMITED  as above, each follower's speed held
 *                          within what its own forces reach over the step
 *                          (-Fb_max to min(Pmax / v, traction) against its
 *                          resistance, over its mass) and below the
 *                          followers' cap, set speed + follow_margin_m_s
 *                          (node_model.h): a follower the policy asks for
 *                          more than it can give falls back, and catches up
 *                          at the speed the policy's gap then asks for.
 *   OBJECT_FUEL_FOLLOWERS_CONTROLLED  position 0 as above; each follower a
 *                          truck at its own place driven by the followers'
 *                          law of the node model (above: the spacing PI
 *                          with the relative-speed term to the policy's
 *                          gap, its floor included, its own cruise control
 *                          to the set speed + follow_margin_m_s, the
 *                          smaller force within -Fb_max .. min(Pmax / v,
 *                          traction), the same anti-windup), its gains from
 *                          cfg (follow_kp_s2, follow_ki_s3, follow_kv_s,
 *                          cruise), not fitted; its acceleration (F - R_i)
 *                          / m_i with R_i its resistance in the small
 *                          angles at its own place, speed and actual gap,
 *                          all from the state at the start of the step (the
 *                          node model's synchronous update); started in
 *                          equilibrium, as the node model's trucks. Why:
 *                          the node model's followers do not hold their
 *                          policy; their gap is the output of that
 *                          controller, driven by the speed ahead and
 *                          disturbed by the grade under each truck, and
 *                          below the floor and at the cap they fall back
 *                          and catch up as the controller, not the policy,
 *                          decides. The explicit update needs step (kv +
 *                          T kp) < 1, T the policy's dd/dv (h, or 1.06 s
 *                          under the headway policy: steps up to 0.28 s
 *                          with the default gains).
 *
 * cfg is the nominal platoon (kept by pointer, identical trucks as for
 * object_sim_policy_drag). Cost per step: one fuel evaluation and one
 * drag-table look-up per position; OBJECT_FUEL_FOLLOWERS adds a grade read
 * and the kinematic update per follower (a division; _LIMITED: one more
 * for the force limits; _CONTROLLED instead the follower's two PI steps,
 * its force limit and its acceleration, a node-model truck-step). What each variant
 * reaches against the node model: tests/host/test_truck_length.c. Call
 * after object_sim_init.
 */
void object_sim_position_fuel(object_sim_t *s, const node_config_t *cfg, object_fuel_t how);
/* Returns 1, 0 (past the end of the road; OBJECT_FUEL_FOLLOWERS(_LIMITED): the last
 * position past it) or -1 (stalled below 1 m/s). */
int object_sim_step(object_sim_t *s);
int object_sim_run(object_sim_t *s, model_summary_t *out);
void object_sim_summary(const object_sim_t *s, model_summary_t *out);

/* ---------------------------------------------------------------- fed one trajectory */

/*
 * Thesis table 5.4: the two fuel models fed the same speed trajectory (the
 * mean of the node model's speeds) and the same grades, so that only the
 * fuel models differ, not the speeds they simulate.
 *
 * node_mean_speed_profile runs the node model over the road and returns at
 * x_k = k step_m (k = 0 .. n_points - 1, n_points = road length / step_m +
 * 1) the mean over trucks of each one's speed as it passes x_k (linear
 * between its steps). Returns 0, -1 (bad arguments: a configuration that
 * fails node_config_check, n_points not matching, step_m not > 0) or -2
 * (the node model stalled). s is the caller's (large) node_sim_t.
 *
 * node_fuel_fed drives that profile over the road in steps of step_m: the
 * speed the mean of the step's ends, the acceleration (v1^2 - v0^2) /
 * (2 step_m), the time step_m / speed, the grade at the step's middle.
 *   node:   each truck's chapter 3 fuel model (eq. 3.7 to 3.11, exact
 *           trigonometry, its own efficiency), with the drag reduction of
 *           the desired gap at that speed, d0 + h v (the gaps themselves
 *           are not in the trajectory), fuel where its own wheel force is
 *           positive; with gap_at_set_speed the reduction of the desired
 *           gap at the set speed instead, as the object model's (to show
 *           how much of the difference the gap makes);
 *   object: eq. 4.14 with the aggregates of object_platoon_build
 *           (OBJECT_NOMINAL: small angles, the reduction of the desired
 *           gap at the set speed, the mean efficiency), fuel where the
 *           platoon's force is positive.
 * Returns 0 or -1 (bad arguments).
 */
int node_mean_speed_profile(const node_config_t *cfg, const ref_road_t *road, double step_m,
                            double *speed_m_s, size_t n_points, node_sim_t *s);
int node_fuel_fed(const node_config_t *cfg, const ref_road_t *road, double step_m,
                  const double *speed_m_s, size_t n_points, bool gap_at_set_speed, double *node_l,
                  double *object_l);

#endif /* NODE_MODEL_H */
