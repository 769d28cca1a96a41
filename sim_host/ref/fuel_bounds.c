/* fuel_bounds.c - thesis 5.1 fuel bounds (contract in fuel_bounds.h). */
#include "ref/fuel_bounds.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define MS_TO_KMH 3.6

static size_t sample_at(const ref_road_t *road, double position_m)
{
    if (!(position_m > 0.0)) {
        return 0U;
    }
    const double k = floor(position_m / road->spacing);
    return (k >= (double)(road->n_samples - 1U)) ? (road->n_samples - 1U) : (size_t)k;
}

void fuel_bounds_grade_window(const ref_road_t *road, double centre_m, double half_window_m,
                              double *min_out, double *max_out)
{
    const size_t a = sample_at(road, centre_m - half_window_m);
    const size_t b = sample_at(road, centre_m + half_window_m);
    double lo = road->grade[a];
    double hi = road->grade[a];
    for (size_t k = a + 1U; k <= b; k++) {
        lo = fmin(lo, road->grade[k]);
        hi = fmax(hi, road->grade[k]);
    }
    *min_out = lo;
    *max_out = hi;
}

static int fail(char *err, size_t err_len, int rc, const char *what)
{
    if ((err != NULL) && (err_len > 0U)) {
        (void)snprintf(err, err_len, "%s", what);
    }
    return rc;
}

/* Which window grade a bound takes. */
typedef enum { USE_MIN_GRADE, USE_MAX_GRADE } grade_pick_t;

/*
 * One bound's work terms along one object-model run: air drag with the
 * bound's own coefficient (air_k, N per (m/s)^2), rolling and grade over the
 * steps where the run burns fuel.
 */
static int bound_run(const node_config_t *cfg, object_choice_t choice, const ref_road_t *road,
                     double air_k, grade_pick_t pick, double half_window_m,
                     fuel_bound_terms_t *terms, model_summary_t *summary)
{
    static ref_platoon_t pl;
    static object_sim_t sim;
    if ((object_platoon_build(&pl, cfg, choice) != 0) ||
        (object_sim_init(&sim, &pl, cfg->cruise, road, cfg->set_speed_m_s, cfg->initial_speed_m_s,
                         cfg->step_s) != 0)) {
        return -1;
    }
    const double roll_n = pl.object.roll_mass * pl.gravity;  /* g sum cr_i m_i */
    const double weight_n = pl.object.mass * pl.gravity;     /* M g */
    *terms = (fuel_bound_terms_t){0};
    int rc;
    while ((rc = object_sim_step(&sim)) == 1) {
        if (!sim.last_fuel_on || !(sim.last_on_road > 0.0)) {
            continue;
        }
        const double ds = sim.last_ds_m * sim.last_on_road;
        const double v = sim.last_speed_m_s;
        double g_lo, g_hi;
        fuel_bounds_grade_window(road, sim.last_mid_m, half_window_m, &g_lo, &g_hi);
        terms->work_air_j += air_k * v * v * ds;                            /* eq. 5.5 */
        terms->work_roll_j += roll_n * ds;                                  /* eq. 5.7 */
        terms->work_grade_j += weight_n * ((pick == USE_MIN_GRADE) ? g_lo : g_hi) * ds; /* 5.10 */
        terms->time_on_s += sim.last_dt_s * sim.last_on_road;
    }
    object_sim_summary(&sim, summary);
    return (rc == 0) ? 0 : -2;
}

/* The energy lower bound (fuel_bounds.h): every truck over the whole road. */
static void energy_bound(const node_config_t *cfg, const ref_road_t *road, double floor_m_s,
                         double exit_floor_m_s, fuel_energy_bound_t *e)
{
    const unsigned n = cfg->n_vehicles;
    const double g = cfg->env->gravity_um_s2 / 1e6;
    const double rho = cfg->env->air_density_g_m3 / 1000.0;
    const double rho_d = cfg->env->fuel_energy_j_ml * 1000.0;
    const double half_gap = node_desired_gap_m(cfg, cfg->set_speed_m_s) / 2.0;
    const double entry_m_s = fmax(cfg->initial_speed_m_s, cfg->set_speed_m_s + cfg->follow_margin_m_s);
    double rise_m = 0.0, level_m = 0.0; /* sum sin(alpha) ds, sum cos(alpha) ds */
    for (size_t k = 0U; k < road->n_samples; k++) {
        const double alpha = atan(fmax(-0.5, fmin(0.5, road->grade[k]))); /* as ref_vehicle_resistance */
        rise_m += sin(alpha) * road->spacing;
        level_m += cos(alpha) * road->spacing;
    }
    const double length_m = node_road_length_m(road);
    const double v_floor = fmax(0.0, floor_m_s);
    const double v_exit = fmax(0.0, exit_floor_m_s);
    *e = (fuel_energy_bound_t){0};
    e->floor_kmh = v_floor * MS_TO_KMH;
    e->exit_floor_kmh = v_exit * MS_TO_KMH;
    e->entry_ceiling_kmh = entry_m_s * MS_TO_KMH;
    double fuel_l = 0.0;
    for (unsigned i = 0U; i < n; i++) {
        const pfe_vehicle_calib_t *c = cfg->vehicle[i];
        const double m = (double)c->mass_kg;
        const double kin = 0.5 * (m + (double)c->rot_mass_kg) * ((v_exit * v_exit) - (entry_m_s * entry_m_s));
        const double grade = m * g * rise_m;
        const double roll = (c->roll_coef_ppm / 1e6) * m * g * level_m;
        const double keep = 1.0 - (ref_drag_reduction_pct(cfg->drag, i, n, half_gap) / 100.0);
        const double air = 0.5 * rho * (c->drag_area_mm2 / 1e6) * keep * v_floor * v_floor * length_m;
        const double w = fmax(0.0, kin + grade + roll + air);
        const double aux = (double)c->power_aux_w * w / (double)c->power_max_w; /* time on >= W / Pmax */
        e->work_kinetic_j += kin;
        e->work_grade_j += grade;
        e->work_roll_j += roll;
        e->work_air_j += air;
        e->aux_j += aux;
        fuel_l += (w + aux) / ((c->eta_ppm / 1e6) * rho_d);
    }
    e->fuel_l = fuel_l;
}

const char *fuel_bounds_why_not(const fuel_bounds_t *b, char *buf, size_t len)
{
    if ((buf == NULL) || (len == 0U)) {
        return "";
    }
    buf[0] = '\0';
    size_t used = 0U;
    if (!b->same_speed) {
        (void)snprintf(buf, len, "the platoon ends at %.1f km/h, not its start speed %.1f km/h (eq. 5.3)",
                       b->end_kmh, b->start_kmh);
        used = strlen(buf);
    }
    if (!b->upgrade && (used + 1U < len)) {
        (void)snprintf(buf + used, len - used,
                       "%sno upgrade slows the platoon (lowest %.1f km/h), so the v_min and v_max runs "
                       "need not bracket its speed (5.1.2)",
                       (used > 0U) ? "; " : "", b->min_kmh);
    }
    return buf;
}

int fuel_bounds_compute(const node_config_t *cfg, const ref_road_t *road, fuel_bounds_t *out,
                        char *err, size_t err_len)
{
    *out = (fuel_bounds_t){0};
    if ((node_config_check(cfg, err, err_len) != 0)) {
        return -1;
    }
    if ((road == NULL) || (road->n_samples < 1U) || !(road->spacing > 0.0)) {
        return fail(err, err_len, -1, "empty road");
    }
    const unsigned n = cfg->n_vehicles;
    const double rho = cfg->env->air_density_g_m3 / 1000.0;
    const double rho_d = cfg->env->fuel_energy_j_ml * 1000.0; /* J per L */
    const double gap = node_desired_gap_m(cfg, cfg->set_speed_m_s);
    double area_lo = INFINITY, area_hi = 0.0, keep_half = 0.0, aux_w = 0.0;
    out->eta_min = INFINITY;
    out->eta_max = 0.0;
    for (unsigned i = 0U; i < n; i++) {
        const pfe_vehicle_calib_t *c = cfg->vehicle[i];
        area_lo = fmin(area_lo, c->drag_area_mm2 / 1e6);
        area_hi = fmax(area_hi, c->drag_area_mm2 / 1e6);
        out->eta_min = fmin(out->eta_min, c->eta_ppm / 1e6);
        out->eta_max = fmax(out->eta_max, c->eta_ppm / 1e6);
        keep_half += 1.0 - (ref_drag_reduction_pct(cfg->drag, i, n, gap / 2.0) / 100.0);
        aux_w += c->power_aux_w;
    }
    out->window_m = (double)(n - 1U) * (gap + cfg->length_m);

    static ref_platoon_t pl;
    static object_sim_t sim;
    model_summary_t nominal;
    if ((object_platoon_build(&pl, cfg, OBJECT_NOMINAL) != 0) ||
        (object_sim_init(&sim, &pl, cfg->cruise, road, cfg->set_speed_m_s, cfg->initial_speed_m_s,
                         cfg->step_s) != 0)) {
        return fail(err, err_len, -1, "invalid simulation arguments");
    }
    if (object_sim_run(&sim, &nominal) != 0) {
        return fail(err, err_len, -2, "the platoon stalls on this road (object model, nominal)");
    }
    out->fuel_l = nominal.fuel_l;
    out->time_s = nominal.time_s;
    out->start_kmh = cfg->initial_speed_m_s * MS_TO_KMH;
    out->end_kmh = nominal.end_speed_kmh;
    out->min_kmh = nominal.min_kmh;

    model_summary_t slow, fast;
    const int a = bound_run(cfg, OBJECT_SLOWEST, road, 0.5 * rho * area_lo * keep_half, USE_MIN_GRADE,
                            out->window_m, &out->lower, &slow);
    const int b = bound_run(cfg, OBJECT_FASTEST, road, 0.5 * rho * area_hi * n, USE_MAX_GRADE,
                            out->window_m, &out->upper, &fast);
    if ((a != 0) || (b != 0)) {
        return fail(err, err_len, (a == -1) || (b == -1) ? -1 : -2,
                    "the platoon stalls on this road (object model, slowest or fastest)");
    }
    out->slow_time_s = slow.time_s;
    out->slow_min_kmh = slow.min_kmh;
    out->fast_time_s = fast.time_s;
    out->fast_max_kmh = fast.max_kmh;

    const double t_short = fmin(out->lower.time_on_s, out->upper.time_on_s);
    const double t_long = fmax(out->lower.time_on_s, out->upper.time_on_s);
    out->lower.aux_j = aux_w * t_short;
    out->upper.aux_j = aux_w * t_long;
    fuel_bound_terms_t *lo = &out->lower;
    fuel_bound_terms_t *hi = &out->upper;
    lo->fuel_l = (lo->work_air_j + lo->work_roll_j + lo->work_grade_j + lo->aux_j) /
                 (out->eta_max * rho_d);                                   /* eq. 5.1 */
    hi->fuel_l = (hi->work_air_j + hi->work_roll_j + hi->work_grade_j + hi->aux_j) /
                 (out->eta_min * rho_d);
    lo->fuel_l = fmax(lo->fuel_l, 0.0); /* the window can make the grade term very negative */
    out->lower_l = lo->fuel_l;
    out->upper_l = hi->fuel_l;
    out->same_speed = fabs(out->end_kmh - out->start_kmh) <= FUEL_BOUNDS_SAME_SPEED_KMH;
    out->upgrade = out->min_kmh <= (cfg->set_speed_m_s * MS_TO_KMH) - FUEL_BOUNDS_UPGRADE_DROP_KMH;
    out->lower_holds = out->same_speed && out->upgrade;
    out->upper_holds = out->lower_holds;
    const double margin_m_s = FUEL_BOUNDS_SAME_SPEED_KMH / MS_TO_KMH;
    energy_bound(cfg, road, (slow.min_kmh / MS_TO_KMH) - margin_m_s,
                 (slow.end_speed_kmh / MS_TO_KMH) - margin_m_s, &out->energy);
    out->sound_lower_energy = !out->lower_holds || (out->energy.fuel_l > out->lower_l);
    out->sound_lower_l = out->sound_lower_energy ? out->energy.fuel_l : out->lower_l;
    return 0;
}

int route_rank(const route_estimate_t *est, size_t n, size_t *order, size_t *blocker)
{
    if ((est == NULL) || (order == NULL) || (n < 2U)) {
        return -1;
    }
    for (size_t k = 0U; k < n; k++) {
        order[k] = k;
    }
    for (size_t k = 1U; k < n; k++) { /* insertion sort: stable, so ties keep index order */
        const size_t v = order[k];
        size_t j = k;
        while ((j > 0U) && (est[order[j - 1U]].fuel_l > est[v].fuel_l)) {
            order[j] = order[j - 1U];
            j--;
        }
        order[j] = v;
    }
    const route_estimate_t *best = &est[order[0]];
    size_t lowest = n; /* the other route with the lowest lower bound not above best's upper */
    for (size_t k = 1U; k < n; k++) {
        const size_t r = order[k];
        if (!(best->upper_l < est[r].lower_l) && ((lowest == n) || (est[r].lower_l < est[lowest].lower_l))) {
            lowest = r;
        }
    }
    if (lowest == n) {
        return (best->upper_fails == NULL) ? 1 : 2;
    }
    if (blocker != NULL) {
        *blocker = lowest;
    }
    return 0;
}
