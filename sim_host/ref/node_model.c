/* node_model.c - node model and time-stepped object model (contract in node_model.h). */
#include "ref/node_model.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "lib/road_csv.h"

#define ACCEL_MAX 20.0 /* m/s^2, as ref_model and the firmware */
#define SPEED_MAX 70.0 /* m/s */
#define STALL 1.0      /* m/s */
#define MS_TO_KMH 3.6

static double clamp(double x, double lo, double hi)
{
    return (x < lo) ? lo : ((x > hi) ? hi : x);
}

void node_config_default(node_config_t *cfg, unsigned n_vehicles)
{
    const unsigned n = (n_vehicles < 1U) ? 1U : ((n_vehicles > NODE_MAX_VEHICLES) ? NODE_MAX_VEHICLES : n_vehicles);
    *cfg = (node_config_t){0};
    cfg->n_vehicles = n;
    for (unsigned i = 0U; i < n; i++) {
        cfg->vehicle[i] = &pfe_default_vehicle;
    }
    cfg->env = &pfe_default_env;
    cfg->drag = &pfe_default_drag;
    cfg->cruise = &pfe_default_cruise;
    cfg->set_speed_m_s = 25.0;
    cfg->initial_speed_m_s = 25.0;
    cfg->time_gap_s = 0.4;
    cfg->standstill_m = 10.0 - (0.4 * 25.0); /* 10 m at 90 km/h: 0 m */
    cfg->length_m = 16.5;
    cfg->spacing = NODE_SPACING_GAP;
    cfg->headway_floor_m = 3.0;
    cfg->follow_kp_s2 = 1.0;
    cfg->follow_ki_s3 = 0.1;
    cfg->follow_kv_s = 1.0 / 0.4;
    cfg->follow_margin_m_s = 2.0 / 3.6;
    cfg->step_s = 0.1;
}

static int bad(char *err, size_t err_len, const char *what)
{
    if ((err != NULL) && (err_len > 0U)) {
        (void)snprintf(err, err_len, "invalid platoon configuration: %s", what);
    }
    return -1;
}

static bool in_range(double x, double lo, double hi)
{
    return isfinite(x) && (x >= lo) && (x <= hi);
}

int node_config_check(const node_config_t *cfg, char *err, size_t err_len)
{
    if (cfg == NULL) {
        return bad(err, err_len, "none given");
    }
    if ((cfg->n_vehicles < 1U) || (cfg->n_vehicles > NODE_MAX_VEHICLES)) {
        return bad(err, err_len, "number of vehicles outside 1 .. 64");
    }
    for (unsigned i = 0U; i < cfg->n_vehicles; i++) {
        if (pfe_calib_check_vehicle(cfg->vehicle[i]) != 0) {
            return bad(err, err_len, "a vehicle calibration is missing or out of range");
        }
    }
    if (pfe_calib_check_env(cfg->env) != 0) {
        return bad(err, err_len, "environment calibration");
    }
    if (pfe_calib_check_drag(cfg->drag) != 0) {
        return bad(err, err_len, "drag-reduction table");
    }
    if (pfe_calib_check_cruise(cfg->cruise) != 0) {
        return bad(err, err_len, "cruise-control gains");
    }
    if (!in_range(cfg->set_speed_m_s, STALL, SPEED_MAX) ||
        !in_range(cfg->initial_speed_m_s, STALL, SPEED_MAX)) {
        return bad(err, err_len, "set or initial speed outside 1 .. 70 m/s");
    }
    if (!in_range(cfg->time_gap_s, 0.0, 10.0)) {
        return bad(err, err_len, "time gap outside 0 .. 10 s");
    }
    if (!in_range(cfg->standstill_m, 0.0, 100.0)) {
        return bad(err, err_len, "standstill distance outside 0 .. 100 m");
    }
    if (!in_range(cfg->length_m, 0.0, 30.0)) {
        return bad(err, err_len, "truck length outside 0 .. 30 m");
    }
    if ((cfg->spacing != NODE_SPACING_GAP) && (cfg->spacing != NODE_SPACING_HEADWAY)) {
        return bad(err, err_len, "spacing policy unknown");
    }
    if (!in_range(cfg->headway_floor_m, 0.0, 100.0)) {
        return bad(err, err_len, "headway policy's smallest gap outside 0 .. 100 m");
    }
    if (!in_range(cfg->follow_kp_s2, 1e-9, 1000.0) || !in_range(cfg->follow_ki_s3, 1e-9, 1000.0) ||
        !in_range(cfg->follow_kv_s, 0.0, 1000.0)) {
        return bad(err, err_len, "follower gains not in (0, 1000]");
    }
    if (!in_range(cfg->follow_margin_m_s, 0.0, 10.0)) {
        return bad(err, err_len, "follower speed margin outside 0 .. 10 m/s");
    }
    if (!in_range(cfg->step_s, 0.001, 1.0)) {
        return bad(err, err_len, "time step outside 0.001 .. 1 s");
    }
    if (cfg->step_s * (cfg->follow_kv_s + (cfg->time_gap_s * cfg->follow_kp_s2)) > 1.0) {
        return bad(err, err_len, "time step too long for the follower gains: dt (kv + h kp) > 1");
    }
    return 0;
}

double node_headway_s(const node_config_t *cfg)
{
    return (cfg->length_m + cfg->standstill_m + (cfg->time_gap_s * cfg->set_speed_m_s)) / cfg->set_speed_m_s;
}

double node_desired_gap_m(const node_config_t *cfg, double speed_m_s)
{
    if (cfg->spacing == NODE_SPACING_HEADWAY) {
        return fmax(cfg->headway_floor_m, (node_headway_s(cfg) * speed_m_s) - cfg->length_m);
    }
    return cfg->standstill_m + (cfg->time_gap_s * speed_m_s);
}

/* ---------------------------------------------------------------- roads */

int node_road_from_percent(const double *grade_pct, size_t n, double spacing_m, node_road_t *r)
{
    *r = (node_road_t){0};
    if ((grade_pct == NULL) || (n < 1U) || !(spacing_m > 0.0) || !isfinite(spacing_m)) {
        return -1;
    }
    double *g = malloc(n * sizeof *g);
    if (g == NULL) {
        return -1;
    }
    for (size_t k = 0U; k < n; k++) {
        if (!isfinite(grade_pct[k])) {
            free(g);
            return -1;
        }
        g[k] = grade_pct[k] / 100.0;
    }
    r->grade = g;
    r->road = (ref_road_t){g, n, spacing_m};
    return 0;
}

int node_road_load(const char *path, node_road_t *r, char *err, size_t err_len)
{
    *r = (node_road_t){0};
    road_profile_t p;
    if (road_profile_load(path, &p, err, err_len) != 0) {
        return -1;
    }
    const int rc = node_road_from_percent(p.grade_percent, p.n_samples, p.spacing_m, r);
    road_profile_free(&p);
    if ((rc != 0) && (err != NULL) && (err_len > 0U)) {
        (void)snprintf(err, err_len, "%s: out of memory", path);
    }
    return rc;
}

void node_road_free(node_road_t *r)
{
    if (r != NULL) {
        free(r->grade);
        *r = (node_road_t){0};
    }
}

double node_road_length_m(const ref_road_t *road)
{
    return (double)road->n_samples * road->spacing;
}

double node_road_grade(const ref_road_t *road, double position_m)
{
    if (!(position_m > 0.0)) {
        return road->grade[0];
    }
    const double k = floor(position_m / road->spacing);
    if (k >= (double)(road->n_samples - 1U)) {
        return road->grade[road->n_samples - 1U];
    }
    return road->grade[(size_t)k];
}

/* Fraction of [x, x + ds] that lies on the road [0, end]. */
static double on_road(double x, double ds, double end)
{
    const double lo = fmax(x, 0.0);
    const double hi = fmin(x + ds, end);
    if (!(hi > lo)) {
        return 0.0;
    }
    return (ds > 0.0) ? (hi - lo) / ds : 1.0;
}

/* ---------------------------------------------------------------- node model */

/* Gap in front of follower i (i >= 1), bumper to bumper. */
static double gap_ahead(const node_sim_t *s, unsigned i)
{
    return s->position_m[i - 1U] - s->position_m[i] - s->cfg->length_m;
}

/* A truck's cruise and spacing controllers in equilibrium: each integral
 * holds the force that keeps the speed v0 against the resistance hold,
 * within the force limits. */
static void controllers_init(const node_config_t *cfg, const ref_vehicle_t *t, double v0, double hold,
                             ref_pi_t *cruise, ref_pi_t *spacing)
{
    const double f0 = clamp(hold, -t->brake_max, ref_wheel_force_max(t->power_max, t->traction_max, v0));
    const double m = t->mass;
    ref_pi_init(cruise, m * cfg->cruise->kp_milli_per_s / 1000.0, m * cfg->cruise->ki_milli_per_s2 / 1000.0, f0);
    ref_pi_init(spacing, m * cfg->follow_kp_s2, m * cfg->follow_ki_s3, f0);
}

int node_sim_init(node_sim_t *s, const node_config_t *cfg, const ref_road_t *road)
{
    if ((node_config_check(cfg, NULL, 0U) != 0) || (road == NULL) || (road->n_samples < 1U) ||
        !(road->spacing > 0.0)) {
        return -1;
    }
    *s = (node_sim_t){0};
    s->cfg = cfg;
    s->road = road;
    s->end_m = node_road_length_m(road);
    s->gravity = cfg->env->gravity_um_s2 / 1e6;
    const unsigned n = cfg->n_vehicles;
    const double v0 = cfg->initial_speed_m_s;
    const double gap0 = node_desired_gap_m(cfg, v0);
    for (unsigned i = 0U; i < n; i++) {
        ref_vehicle_init(&s->truck[i], cfg->vehicle[i], cfg->env, 0.0);
        s->air_k0[i] = s->truck[i].air_k;
        const double phi = ref_drag_reduction_pct(cfg->drag, i, n, gap0);
        s->truck[i].air_k = s->air_k0[i] * (1.0 - (phi / 100.0));
        s->truck[i].reduction = phi;
        s->position_m[i] = -(double)i * (cfg->length_m + gap0);
        s->speed_m_s[i] = v0;
        const ref_vehicle_t *t = &s->truck[i];
        const double hold = ref_vehicle_resistance(t, v0, node_road_grade(road, s->position_m[i]),
                                                   s->gravity);
        controllers_init(cfg, t, v0, hold, &s->cruise[i], &s->spacing[i]);
    }
    s->min_speed_m_s = INFINITY;
    s->max_speed_m_s = -INFINITY;
    s->min_gap_m = (n > 1U) ? gap0 : 0.0;
    s->max_gap_m = (n > 1U) ? gap0 : 0.0;
    return 0;
}

/* The follower's force (the law in node_model.h): spacing PI with a
 * relative-speed term, or its own cruise control, whichever asks for less. */
static double follower_force(const node_config_t *cfg, double dt, const ref_vehicle_t *t, ref_pi_t *cruise,
                             ref_pi_t *spacing, double v, double v_ahead, double gap, double f_max)
{
    const double lo = -t->brake_max;
    const double e = gap - node_desired_gap_m(cfg, v);
    const double p = t->mass * ((cfg->follow_kp_s2 * e) + (cfg->follow_kv_s * (v_ahead - v)));
    const double step = spacing->ki * e * dt;
    const double trial = p + spacing->integral + step;
    if (!((trial > f_max) && (step > 0.0)) && !((trial < lo) && (step < 0.0))) {
        spacing->integral = clamp(spacing->integral + step, lo, t->traction_max);
    }
    const double f_gap = clamp(p + spacing->integral, lo, f_max);
    const double f_cruise = ref_pi_step(cruise, cfg->set_speed_m_s + cfg->follow_margin_m_s - v, dt, lo, f_max);
    if (f_gap <= f_cruise) {
        cruise->integral = f_gap;
        return f_gap;
    }
    spacing->integral = clamp(f_cruise - p, lo, t->traction_max);
    return f_cruise;
}

int node_sim_step(node_sim_t *s)
{
    const node_config_t *cfg = s->cfg;
    const unsigned n = cfg->n_vehicles;
    if (s->position_m[n - 1U] >= s->end_m) {
        return 0;
    }
    const double dt = cfg->step_s;
    /* The leader's drag depends on the gap behind it: read it before the
     * follower moves. Trucks are updated from the back so that each reads
     * the position of the truck ahead from the start of the step. */
    const double lead_gap = (n > 1U) ? gap_ahead(s, 1U) : 0.0;
    for (unsigned j = n; j-- > 0U;) {
        const double v = s->speed_m_s[j];
        if (v < STALL) {
            return -1;
        }
        const double gap = (j == 0U) ? lead_gap : gap_ahead(s, j);
        ref_vehicle_t *t = &s->truck[j];
        if (n > 1U) {
            s->min_gap_m = fmin(s->min_gap_m, gap);
            s->max_gap_m = fmax(s->max_gap_m, gap);
            const double phi = ref_drag_reduction_pct(cfg->drag, j, n, gap);
            t->air_k = s->air_k0[j] * (1.0 - (phi / 100.0));
            t->reduction = phi;
        }
        const double x = s->position_m[j];
        const double grade = node_road_grade(s->road, x + (v * dt / 2.0));
        const double resist = ref_vehicle_resistance(t, v, grade, s->gravity);
        const double f_max = ref_wheel_force_max(t->power_max, t->traction_max, v);
        const double force = (j == 0U)
            ? ref_pi_step(&s->cruise[0], cfg->set_speed_m_s - v, dt, -t->brake_max, f_max)
            : follower_force(cfg, dt, t, &s->cruise[j], &s->spacing[j], v, s->speed_m_s[j - 1U], gap, f_max);
        const double accel = clamp((force - resist) / t->mass, -ACCEL_MAX, ACCEL_MAX);
        const double v1 = clamp(v + (accel * dt), 0.0, SPEED_MAX);
        const double ds = (v + v1) * dt / 2.0;
        const double w = on_road(x, ds, s->end_m);
        if (w > 0.0) {
            s->brake_j[j] += (force < 0.0) ? -w * force * ds : 0.0;
            const double fuel_force = (t->mass_fuel * accel) + resist; /* eq. 3.7 */
            if (fuel_force > 0.0) {                                   /* eq. 3.9 */
                s->fuel_l[j] += w * ((fuel_force * ds) + (t->power_aux * dt)) * t->fuel_per_j;
            }
            s->time_on_s[j] += w * dt;
            s->min_speed_m_s = fmin(s->min_speed_m_s, fmin(v, v1));
            s->max_speed_m_s = fmax(s->max_speed_m_s, fmax(v, v1));
            if ((x + ds) >= s->end_m) {
                s->exit_speed_m_s[j] = v1;
            }
        }
        s->speed_m_s[j] = v1;
        s->position_m[j] = x + ds;
    }
    s->time_s += dt;
    s->steps++;
    return 1;
}

void node_sim_summary(const node_sim_t *s, model_summary_t *out)
{
    const unsigned n = s->cfg->n_vehicles;
    *out = (model_summary_t){0};
    double mean_kmh = 0.0;
    for (unsigned i = 0U; i < n; i++) {
        out->fuel_l += s->fuel_l[i];
        out->time_s += s->time_on_s[i] / n;
        out->end_speed_kmh += s->exit_speed_m_s[i] * MS_TO_KMH / n;
        if (s->time_on_s[i] > 0.0) {
            mean_kmh += (s->end_m / s->time_on_s[i]) * MS_TO_KMH / n;
        }
    }
    out->mean_kmh = mean_kmh;
    out->min_kmh = s->min_speed_m_s * MS_TO_KMH;
    out->max_kmh = s->max_speed_m_s * MS_TO_KMH;
    out->min_gap_m = s->min_gap_m;
    out->max_gap_m = s->max_gap_m;
    out->steps = s->steps;
    out->evaluations = s->steps * n;
}

int node_sim_run(node_sim_t *s, model_summary_t *out)
{
    int rc;
    while ((rc = node_sim_step(s)) == 1) {
    }
    node_sim_summary(s, out);
    return (rc == 0) ? 0 : -1;
}

/* ---------------------------------------------------------------- object model */

int object_platoon_build(ref_platoon_t *pl, const node_config_t *cfg, object_choice_t choice)
{
    if (node_config_check(cfg, NULL, 0U) != 0) {
        return -1;
    }
    *pl = (ref_platoon_t){0};
    const unsigned n = cfg->n_vehicles;
    const double gap = node_desired_gap_m(cfg, cfg->set_speed_m_s);
    pl->n_vehicles = n;
    pl->gap = gap;
    pl->gravity = cfg->env->gravity_um_s2 / 1e6;
    const double rho = cfg->env->air_density_g_m3 / 1000.0;
    ref_vehicle_t *o = &pl->object;
    double eta_sum = 0.0;
    double p_lo = INFINITY, p_hi = 0.0, t_lo = INFINITY, t_hi = 0.0;
    double area_lo = INFINITY, area_hi = 0.0, keep_half = 0.0, most = 0.0;
    for (unsigned i = 0U; i < n; i++) {
        const pfe_vehicle_calib_t *c = cfg->vehicle[i];
        ref_vehicle_t v;
        ref_vehicle_init(&v, c, cfg->env, ref_drag_reduction_pct(cfg->drag, i, n, gap));
        /* formation drag (below): the largest drag per kilogram */
        most = fmax(most, ((choice == OBJECT_SLOWEST) ? 0.5 * rho : v.air_k) / v.mass);
        o->air_k += v.air_k;              /* eq. 4.6 */
        o->mass += v.mass;                /* eq. 4.3 */
        o->mass_fuel += v.mass_fuel;
        o->roll_mass += v.roll_mass;      /* eq. 4.8 */
        o->brake_max += v.brake_max;      /* eq. 4.5 */
        o->power_aux += v.power_aux;      /* eq. 4.14 */
        eta_sum += c->eta_ppm / 1e6;
        p_lo = fmin(p_lo, v.power_max / v.mass);
        p_hi = fmax(p_hi, v.power_max / v.mass);
        t_lo = fmin(t_lo, v.traction_max / v.mass);
        t_hi = fmax(t_hi, v.traction_max / v.mass);
        area_lo = fmin(area_lo, c->drag_area_mm2 / 1e6);
        area_hi = fmax(area_hi, c->drag_area_mm2 / 1e6);
        keep_half += 1.0 - (ref_drag_reduction_pct(cfg->drag, i, n, gap / 2.0) / 100.0);
    }
    double p_per_kg = p_lo; /* eq. 4.4 */
    double t_per_kg = t_lo;
    if (choice == OBJECT_SLOWEST) {
        o->air_k = 0.5 * rho * area_hi * n;
    } else if (choice == OBJECT_FASTEST) {
        o->air_k = 0.5 * rho * area_lo * keep_half;
        p_per_kg = p_hi;
        t_per_kg = t_hi;
    }
    /* Formation drag (pfe_platoon.h), of the trucks as this choice sees
     * them; the slowest platoon's every truck has the largest frontal area,
     * the fastest platoon has none. */
    most = (choice == OBJECT_SLOWEST) ? most * area_hi : most;
    pl->formation_air_k = (choice == OBJECT_FASTEST) ? 0.0 : fmax(0.0, (most * o->mass) - o->air_k);
    o->power_max = p_per_kg * o->mass;
    o->traction_max = t_per_kg * o->mass;
    o->fuel_per_j = 1.0 / ((eta_sum / n) * (cfg->env->fuel_energy_j_ml * 1000.0));
    o->reduction = 0.0;
    return 0;
}

int object_sim_init(object_sim_t *s, const ref_platoon_t *pl, const pfe_cruise_calib_t *cruise,
                    const ref_road_t *road, double set_speed_m_s, double initial_speed_m_s,
                    double step_s)
{
    if ((pl == NULL) || (road == NULL) || (road->n_samples < 1U) || !(road->spacing > 0.0) ||
        (pfe_calib_check_cruise(cruise) != 0) || !in_range(set_speed_m_s, STALL, SPEED_MAX) ||
        !in_range(initial_speed_m_s, STALL, SPEED_MAX) || !in_range(step_s, 0.001, 1.0)) {
        return -1;
    }
    *s = (object_sim_t){0};
    s->pl = pl;
    s->road = road;
    s->end_m = node_road_length_m(road);
    s->step_s = step_s;
    s->set_speed_m_s = set_speed_m_s;
    s->speed_m_s = initial_speed_m_s;
    s->min_speed_m_s = INFINITY;
    s->max_speed_m_s = -INFINITY;
    s->grade_points = 1U;
    const ref_vehicle_t *o = &pl->object;
    const double hold = ref_object_resistance(pl, initial_speed_m_s, road->grade[0]);
    const double f0 = clamp(hold, -o->brake_max, ref_platoon_force_max(pl, initial_speed_m_s));
    ref_pi_init(&s->pi, o->mass * cruise->kp_milli_per_s / 1000.0,
                o->mass * cruise->ki_milli_per_s2 / 1000.0, f0);
    return 0;
}

void object_sim_truck_grades(object_sim_t *s, unsigned n_points, double pitch_m)
{
    s->grade_points = (n_points < 1U) ? 1U : n_points;
    s->grade_pitch_m = pitch_m;
}

void object_sim_policy_drag(object_sim_t *s, const node_config_t *cfg)
{
    s->policy_drag = cfg;
}

/* eq. 4.6 with phi_i of the policy's gap at speed v: the air drag
 * coefficient (N per (m/s)^2) and the formation drag's (pfe_platoon.h). */
static void policy_air_k(const node_config_t *cfg, double mass, double v, double *air_k, double *formation)
{
    const unsigned n = cfg->n_vehicles;
    const double gap = node_desired_gap_m(cfg, v);
    double k = 0.0, most = 0.0;
    for (unsigned i = 0U; i < n; i++) {
        ref_vehicle_t t;
        ref_vehicle_init(&t, cfg->vehicle[i], cfg->env,
                         (n > 1U) ? ref_drag_reduction_pct(cfg->drag, i, n, gap) : 0.0);
        k += t.air_k;
        most = fmax(most, t.air_k / t.mass);
    }
    *air_k = k;
    *formation = fmax(0.0, (most * mass) - k);
}

static double position_resistance(const node_config_t *cfg, unsigned i, double gap_m, double v, double grade,
                                  ref_vehicle_t *t);

/* OBJECT_FUEL_FOLLOWERS_CONTROLLED: follower i's controllers in
 * equilibrium at speed v0 on a grade, at the policy's gap. */
static void follower_control_init(const node_config_t *cfg, unsigned i, double v0, double grade, ref_pi_t *cruise,
                                  ref_pi_t *spacing)
{
    ref_vehicle_t t;
    const double hold = position_resistance(cfg, i, node_desired_gap_m(cfg, v0), v0, grade, &t);
    controllers_init(cfg, &t, v0, hold, cruise, spacing);
}

void object_sim_position_fuel(object_sim_t *s, const node_config_t *cfg, object_fuel_t how)
{
    s->fuel_by = (cfg == NULL) ? OBJECT_FUEL_AGGREGATE : how;
    s->fuel_cfg = cfg;
    if (s->fuel_by >= OBJECT_FUEL_FOLLOWERS) {
        const double spacing = cfg->length_m + node_desired_gap_m(cfg, s->speed_m_s);
        for (unsigned i = 0U; i < cfg->n_vehicles; i++) {
            s->pos_x_m[i] = s->position_m - ((double)i * spacing);
            s->pos_v_m_s[i] = s->speed_m_s;
        }
    }
    for (unsigned i = 1U; (s->fuel_by == OBJECT_FUEL_FOLLOWERS_CONTROLLED) && (i < cfg->n_vehicles); i++) {
        follower_control_init(cfg, i, s->speed_m_s, node_road_grade(s->road, s->pos_x_m[i]), &s->pos_cruise[i],
                              &s->pos_spacing[i]);
    }
}

/* One position's chapter 3 coefficients with the drag reduction of its gap,
 * and its resistance at speed v on a grade in the small angles of eq. 4.8
 * and 4.9, N. */
static double position_resistance(const node_config_t *cfg, unsigned i, double gap_m, double v, double grade,
                                  ref_vehicle_t *t)
{
    const unsigned n = cfg->n_vehicles;
    ref_vehicle_init(t, cfg->vehicle[i], cfg->env, (n > 1U) ? ref_drag_reduction_pct(cfg->drag, i, n, gap_m) : 0.0);
    const double g = cfg->env->gravity_um_s2 / 1e6;
    return (t->air_k * v * v) + (t->roll_mass * g) + (t->mass * g * clamp(grade, -0.5, 0.5));
}

/* Eq. 3.7 to 3.11 of one position over a step of ds and dt, L; 0 when
 * coasting (eq. 3.9). */
static double position_fuel_l(const ref_vehicle_t *t, double resist, double a, double ds, double dt)
{
    const double f = (t->mass_fuel * a) + resist;                                  /* eq. 3.7 */
    return (f > 0.0) ? ((f * ds) + (t->power_aux * dt)) * t->fuel_per_j : 0.0;   /* eq. 3.11 */
}

/* OBJECT_FUEL_FOLLOWERS(_LIMITED): the followers' new places and speeds
 * (the policy's kinematics in object_sim_position_fuel),
 * given the point's new place x1 and speed v1, and every position's fuel
 * over the step. Returns the fuel. */
static double followers_step(object_sim_t *s, double x1, double v1, double dt)
{
    const node_config_t *cfg = s->fuel_cfg;
    const unsigned n = cfg->n_vehicles;
    const bool headway = cfg->spacing == NODE_SPACING_HEADWAY;
    const bool limited = s->fuel_by == OBJECT_FUEL_FOLLOWERS_LIMITED;
    const bool controlled = s->fuel_by == OBJECT_FUEL_FOLLOWERS_CONTROLLED;
    const double tau = headway ? node_headway_s(cfg) : cfg->time_gap_s;
    const double c = headway ? 0.0 : (cfg->length_m + cfg->standstill_m);
    const double v_floor = headway ? ((cfg->length_m + cfg->headway_floor_m) / tau) : 0.0;
    double x_new[NODE_MAX_VEHICLES], v_new[NODE_MAX_VEHICLES], resist[NODE_MAX_VEHICLES];
    ref_vehicle_t t[NODE_MAX_VEHICLES];
    x_new[0] = x1;
    v_new[0] = v1;
    for (unsigned i = 0U; i < n; i++) {
        const double x = s->pos_x_m[i];
        const double v = s->pos_v_m_s[i];
        const double gap = (n < 2U) ? 0.0
            : ((i == 0U) ? (x - s->pos_x_m[1] - cfg->length_m) : (s->pos_x_m[i - 1U] - x - cfg->length_m));
        resist[i] = position_resistance(cfg, i, gap, v, node_road_grade(s->road, x + (v * dt / 2.0)), &t[i]);
        if (i == 0U) {
            continue;
        }
        if (controlled) {
            /* the followers' own law (node_model.h), from the state at the
             * start of the step, as the node model's synchronous update */
            const double f_max = ref_wheel_force_max(t[i].power_max, t[i].traction_max, v);
            const double force = follower_force(cfg, dt, &t[i], &s->pos_cruise[i], &s->pos_spacing[i], v,
                                                s->pos_v_m_s[i - 1U], gap, f_max);
            const double accel = clamp((force - resist[i]) / t[i].mass, -ACCEL_MAX, ACCEL_MAX);
            v_new[i] = clamp(v + (accel * dt), 0.0, SPEED_MAX);
            x_new[i] = x + ((v + v_new[i]) * dt / 2.0);
            continue;
        }
        double vi = v_new[i - 1U];
        if (tau > 0.0) {
            /* x' = x + dt / 2 (v + (x_(i-1)' - x' - c) / tau), solved for x' */
            const double xi = (x + ((dt / 2.0) * (v + ((x_new[i - 1U] - c) / tau)))) / (1.0 + (dt / (2.0 * tau)));
            vi = (x_new[i - 1U] - xi - c) / tau;
        }
        if (vi < v_floor) {
            vi = fmin(v_new[i - 1U], v_floor);
        }
        if (limited) {
            /* the followers' own speed cap, and the truck's force limits,
             * -Fb_max .. min(Pmax / v, traction) */
            const double a_hi = (ref_wheel_force_max(t[i].power_max, t[i].traction_max, v) - resist[i]) / t[i].mass;
            const double a_lo = (-t[i].brake_max - resist[i]) / t[i].mass;
            vi = clamp(fmin(vi, cfg->set_speed_m_s + cfg->follow_margin_m_s), v + (a_lo * dt), v + (a_hi * dt));
        }
        v_new[i] = fmax(vi, 0.0);
        x_new[i] = x + ((v + v_new[i]) * dt / 2.0);
    }
    double fuel = 0.0;
    for (unsigned i = 0U; i < n; i++) {
        const double x = s->pos_x_m[i];
        const double v = s->pos_v_m_s[i];
        const double ds = x_new[i] - x;
        const double w = on_road(x, ds, s->end_m);
        const double f = (w > 0.0) ? w * position_fuel_l(&t[i], resist[i], (v_new[i] - v) / dt, ds, dt) : 0.0;
        s->pos_fuel_l[i] += f;
        fuel += f;
        s->pos_x_m[i] = x_new[i];
        s->pos_v_m_s[i] = v_new[i];
    }
    return fuel;
}

/* OBJECT_FUEL_POSITIONS: every position at the point, each with its own
 * clipping; w the fraction of the step on the road. */
static double positions_at_point(object_sim_t *s, double v, double a, double grade, double ds, double dt, double w)
{
    const node_config_t *cfg = s->fuel_cfg;
    const double gap = node_desired_gap_m(cfg, v);
    double fuel = 0.0;
    for (unsigned i = 0U; (i < cfg->n_vehicles) && (w > 0.0); i++) {
        ref_vehicle_t t;
        const double resist = position_resistance(cfg, i, gap, v, grade, &t);
        const double f = w * position_fuel_l(&t, resist, a, ds, dt);
        s->pos_fuel_l[i] += f;
        fuel += f;
    }
    return fuel;
}

static double object_grade(const object_sim_t *s, double at_m)
{
    if (s->grade_points <= 1U) {
        return node_road_grade(s->road, at_m);
    }
    const double first = at_m + (((double)s->grade_points - 1.0) * s->grade_pitch_m / 2.0);
    double sum = 0.0;
    for (unsigned i = 0U; i < s->grade_points; i++) {
        sum += node_road_grade(s->road, first - ((double)i * s->grade_pitch_m));
    }
    return sum / (double)s->grade_points;
}

int object_sim_step(object_sim_t *s)
{
    const bool followers = s->fuel_by >= OBJECT_FUEL_FOLLOWERS;
    if ((followers ? s->pos_x_m[s->fuel_cfg->n_vehicles - 1U] : s->position_m) >= s->end_m) {
        return 0;
    }
    const double v = s->speed_m_s;
    if (v < STALL) {
        return -1;
    }
    const ref_platoon_t *pl = s->pl;
    const ref_vehicle_t *o = &pl->object;
    const double dt = s->step_s;
    const double x = s->position_m;
    const double mid = x + (v * dt / 2.0);
    const double grade = object_grade(s, mid);
    double resist = ref_object_resistance(pl, v, grade);
    double f_max = ref_platoon_force_max(pl, v);
    if (s->policy_drag != NULL) {
        double k, formation;
        policy_air_k(s->policy_drag, o->mass, v, &k, &formation);
        resist += (k - o->air_k) * v * v;
        f_max = fmax(ref_wheel_force_max(o->power_max, o->traction_max, v) - (formation * v * v), -o->brake_max);
    }
    const double force = ref_pi_step(&s->pi, s->set_speed_m_s - v, dt, -o->brake_max, f_max);
    const double accel = clamp((force - resist) / o->mass, -ACCEL_MAX, ACCEL_MAX);
    const double v1 = clamp(v + (accel * dt), 0.0, SPEED_MAX);
    const double ds = (v + v1) * dt / 2.0;
    const double w = on_road(x, ds, s->end_m);
    const double fuel_force = (o->mass_fuel * accel) + resist;           /* eq. 3.7 */
    const bool on = fuel_force > 0.0;                                     /* eq. 3.9 */
    if (followers) {
        s->fuel_l += followers_step(s, x + ds, v1, dt);
    } else if (s->fuel_by == OBJECT_FUEL_POSITIONS) {
        s->fuel_l += positions_at_point(s, v, accel, grade, ds, dt, w);       /* eq. 4.11 */
    } else if (on) {
        s->fuel_l += w * ((fuel_force * ds) + (o->power_aux * dt)) * o->fuel_per_j; /* eq. 4.14 */
    } else {
        /* coasting: no fuel */
    }
    s->time_s += w * dt;
    if (w > 0.0) {
        s->min_speed_m_s = fmin(s->min_speed_m_s, fmin(v, v1));
        s->max_speed_m_s = fmax(s->max_speed_m_s, fmax(v, v1));
    }
    s->last_speed_m_s = v;
    s->last_ds_m = ds;
    s->last_dt_s = dt;
    s->last_mid_m = mid;
    s->last_on_road = w;
    s->last_fuel_on = on;
    s->speed_m_s = v1;
    s->position_m = x + ds;
    s->steps++;
    return 1;
}

void object_sim_summary(const object_sim_t *s, model_summary_t *out)
{
    *out = (model_summary_t){0};
    out->fuel_l = s->fuel_l;
    out->time_s = s->time_s;
    out->mean_kmh = (s->time_s > 0.0) ? s->end_m / s->time_s * MS_TO_KMH : 0.0;
    out->min_kmh = s->min_speed_m_s * MS_TO_KMH;
    out->max_kmh = s->max_speed_m_s * MS_TO_KMH;
    out->end_speed_kmh = s->speed_m_s * MS_TO_KMH;
    out->min_gap_m = s->pl->gap;
    out->max_gap_m = s->pl->gap;
    out->steps = s->steps;
    /* with the followers: one evaluation per position and step */
    out->evaluations = s->steps * ((s->fuel_by >= OBJECT_FUEL_FOLLOWERS) ? s->fuel_cfg->n_vehicles : 1U);
}

int object_sim_run(object_sim_t *s, model_summary_t *out)
{
    int rc;
    while ((rc = object_sim_step(s)) == 1) {
    }
    object_sim_summary(s, out);
    return (rc == 0) ? 0 : -1;
}

/* ---------------------------------------------------------------- fed one trajectory */

static size_t profile_points(const ref_road_t *road, double step_m)
{
    return (size_t)floor((node_road_length_m(road) / step_m) + 1e-9) + 1U;
}

int node_mean_speed_profile(const node_config_t *cfg, const ref_road_t *road, double step_m,
                            double *speed_m_s, size_t n_points, node_sim_t *s)
{
    if ((speed_m_s == NULL) || (s == NULL) || !(step_m > 0.0) || (road == NULL) || (road->n_samples < 1U) ||
        (n_points != profile_points(road, step_m)) || (node_sim_init(s, cfg, road) != 0)) {
        return -1;
    }
    const unsigned n = cfg->n_vehicles;
    for (size_t k = 0U; k < n_points; k++) {
        speed_m_s[k] = 0.0;
    }
    for (unsigned j = 0U; j < n; j++) {
        /* trucks start at or behind 0: one exactly there has passed x_0 */
        speed_m_s[0] += (s->position_m[j] == 0.0) ? (s->speed_m_s[j] / n) : 0.0;
    }
    double x0[NODE_MAX_VEHICLES], v0[NODE_MAX_VEHICLES];
    int rc;
    do {
        for (unsigned j = 0U; j < n; j++) {
            x0[j] = s->position_m[j];
            v0[j] = s->speed_m_s[j];
        }
        rc = node_sim_step(s);
        for (unsigned j = 0U; (j < n) && (rc == 1); j++) {
            const double x1 = s->position_m[j];
            if (!(x1 > x0[j]) || (x1 < 0.0)) {
                continue;
            }
            /* grid points x0 < k step <= x1 */
            double first = ceil(fmax(x0[j], 0.0) / step_m);
            first += ((first * step_m) <= x0[j]) ? 1.0 : 0.0;
            for (double kk = first; (kk * step_m <= x1) && (kk < (double)n_points); kk += 1.0) {
                const double f = ((kk * step_m) - x0[j]) / (x1 - x0[j]);
                speed_m_s[(size_t)kk] += (v0[j] + (f * (s->speed_m_s[j] - v0[j]))) / n;
            }
        }
    } while (rc == 1);
    return (rc == 0) ? 0 : -2;
}

int node_fuel_fed(const node_config_t *cfg, const ref_road_t *road, double step_m,
                  const double *speed_m_s, size_t n_points, bool gap_at_set_speed, double *node_l,
                  double *object_l)
{
    static ref_platoon_t pl;
    if ((speed_m_s == NULL) || (node_l == NULL) || (object_l == NULL) || !(step_m > 0.0) ||
        (road == NULL) || (road->n_samples < 1U) || (n_points != profile_points(road, step_m)) ||
        (object_platoon_build(&pl, cfg, OBJECT_NOMINAL) != 0)) {
        return -1;
    }
    const unsigned n = cfg->n_vehicles;
    const ref_vehicle_t *o = &pl.object;
    double node = 0.0, object = 0.0;
    for (size_t k = 0U; k + 1U < n_points; k++) {
        const double va = speed_m_s[k];
        const double vb = speed_m_s[k + 1U];
        const double v = (va + vb) / 2.0;
        if (!(v > 0.0)) {
            return -1;
        }
        const double dt = step_m / v;
        const double a = ((vb * vb) - (va * va)) / (2.0 * step_m);
        const double grade = node_road_grade(road, ((double)k + 0.5) * step_m);
        const double gap = node_desired_gap_m(cfg, gap_at_set_speed ? cfg->set_speed_m_s : v);
        for (unsigned i = 0U; i < n; i++) {
            ref_vehicle_t t;
            ref_vehicle_init(&t, cfg->vehicle[i], cfg->env,
                             (n > 1U) ? ref_drag_reduction_pct(cfg->drag, i, n, gap) : 0.0);
            const double f = (t.mass_fuel * a) + ref_vehicle_resistance(&t, v, grade, pl.gravity);
            if (f > 0.0) {                                          /* eq. 3.9 */
                node += ((f * step_m) + (t.power_aux * dt)) * t.fuel_per_j;
            }
        }
        const double f = (o->mass_fuel * a) + ref_object_resistance(&pl, v, grade);
        if (f > 0.0) {
            object += ((f * step_m) + (o->power_aux * dt)) * o->fuel_per_j; /* eq. 4.14 */
        }
    }
    *node_l = node;
    *object_l = object;
    return 0;
}
