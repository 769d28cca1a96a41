/* ref_model.c - double-precision reference (contract in ref_model.h). */
#include "ref/ref_model.h"

#include <math.h>

#define ACCEL_MAX 20.0      /* m/s^2, as PFE_ACCEL_MAX_UM_S2 */
#define GRADE_MAX 0.5       /* as PFE_GRADE_MAX_PPM */
#define SPEED_MAX 70.0      /* m/s, as PFE_SPEED_MAX_MM_S */
#define STALL 1.0           /* m/s, as PFE_SIM_STALL_MM_S */

static double clamp(double x, double lo, double hi)
{
    return (x < lo) ? lo : ((x > hi) ? hi : x);
}

double ref_drag_reduction_pct(const pfe_drag_table_t *drag, unsigned position, unsigned n,
                              double gap_m)
{
    if (n < 2U) {
        return 0.0;
    }
    const unsigned row = (position < PFE_DRAG_ROWS) ? position : (PFE_DRAG_ROWS - 1U);
    const double d = gap_m * 1000.0;
    if (d <= (double)drag->gap_mm[0]) {
        return drag->reduction_bp[row][0] / 100.0;
    }
    for (unsigned k = 1U; k < PFE_DRAG_POINTS; k++) {
        const double d1 = (double)drag->gap_mm[k];
        if (d <= d1) {
            const double d0 = (double)drag->gap_mm[k - 1U];
            const double y0 = drag->reduction_bp[row][k - 1U];
            const double y1 = drag->reduction_bp[row][k];
            return (y0 + ((y1 - y0) * (d - d0) / (d1 - d0))) / 100.0;
        }
    }
    return drag->reduction_bp[row][PFE_DRAG_POINTS - 1U] / 100.0;
}

void ref_vehicle_init(ref_vehicle_t *v, const pfe_vehicle_calib_t *c, const pfe_env_calib_t *env,
                      double reduction_pct)
{
    const double rho = env->air_density_g_m3 / 1000.0;
    const double cw_af = c->drag_area_mm2 / 1e6;
    v->air_k = 0.5 * rho * cw_af * (1.0 - (reduction_pct / 100.0));
    v->mass = c->mass_kg;
    v->mass_fuel = (double)c->mass_kg + (double)c->rot_mass_kg;
    v->roll_mass = (c->roll_coef_ppm / 1e6) * c->mass_kg;
    v->fuel_per_j = 1.0 / ((c->eta_ppm / 1e6) * (env->fuel_energy_j_ml * 1000.0));
    v->power_max = c->power_max_w;
    v->traction_max = c->traction_max_n;
    v->brake_max = c->brake_max_n;
    v->power_aux = c->power_aux_w;
    v->reduction = reduction_pct;
}

int ref_platoon_init(ref_platoon_t *pl, const pfe_platoon_config_t *cfg)
{
    if ((cfg->n_vehicles < 1U) || (cfg->n_vehicles > PFE_MAX_VEHICLES) ||
        (pfe_calib_check_env(cfg->env) != 0) || (pfe_calib_check_drag(cfg->drag) != 0)) {
        return -1;
    }
    const unsigned n = cfg->n_vehicles;
    pl->n_vehicles = n;
    pl->gap = cfg->gap_mm / 1000.0;
    pl->gravity = cfg->env->gravity_um_s2 / 1e6;
    ref_vehicle_t *o = &pl->object;
    *o = (ref_vehicle_t){0};
    double eta_sum = 0.0;
    double p_per_kg = INFINITY;
    double t_per_kg = INFINITY;
    double most = 0.0; /* formation drag: the largest k_i / m_i */
    for (unsigned i = 0U; i < n; i++) {
        const pfe_vehicle_calib_t *c = cfg->vehicle[i];
        if (pfe_calib_check_vehicle(c) != 0) {
            return -1;
        }
        ref_vehicle_init(&pl->position[i], c, cfg->env,
                         ref_drag_reduction_pct(cfg->drag, i, n, pl->gap));
        const ref_vehicle_t *v = &pl->position[i];
        o->air_k += v->air_k;                        /* eq. 4.6 */
        o->mass += v->mass;                          /* eq. 4.3 */
        o->mass_fuel += v->mass_fuel;
        o->roll_mass += v->roll_mass;                /* eq. 4.8 */
        o->brake_max += v->brake_max;                /* eq. 4.5 */
        o->power_aux += v->power_aux;                /* eq. 4.14 */
        eta_sum += c->eta_ppm / 1e6;
        p_per_kg = fmin(p_per_kg, v->power_max / v->mass);
        t_per_kg = fmin(t_per_kg, v->traction_max / v->mass);
        most = fmax(most, v->air_k / v->mass);
    }
    pl->formation_air_k = fmax(0.0, (most * o->mass) - o->air_k);
    o->power_max = p_per_kg * o->mass;               /* eq. 4.4 */
    o->traction_max = t_per_kg * o->mass;
    o->fuel_per_j = 1.0 / ((eta_sum / n) * (cfg->env->fuel_energy_j_ml * 1000.0));
    return 0;
}

double ref_vehicle_resistance(const ref_vehicle_t *v, double speed, double grade, double g)
{
    const double alpha = atan(clamp(grade, -GRADE_MAX, GRADE_MAX));
    return (v->air_k * speed * speed) + (v->roll_mass * g * cos(alpha)) +
           (v->mass * g * sin(alpha));
}

double ref_object_resistance(const ref_platoon_t *pl, double speed, double grade)
{
    const ref_vehicle_t *o = &pl->object;
    return (o->air_k * speed * speed) + (o->roll_mass * pl->gravity) +
           (o->mass * pl->gravity * clamp(grade, -GRADE_MAX, GRADE_MAX));
}

double ref_wheel_force_max(double power_max, double traction_max, double speed)
{
    return (speed <= 0.0) ? traction_max : fmin(power_max / speed, traction_max);
}

double ref_platoon_force_max(const ref_platoon_t *pl, double speed)
{
    const ref_vehicle_t *o = &pl->object;
    const double f = ref_wheel_force_max(o->power_max, o->traction_max, speed) -
                     (pl->formation_air_k * speed * speed);
    return fmax(f, -o->brake_max);
}

double ref_fuel_rate(double force, double speed, double power_aux, double fuel_per_j)
{
    return (force > 0.0) ? (((force * speed) + power_aux) * fuel_per_j) : 0.0;
}

void ref_pi_init(ref_pi_t *pi, double kp, double ki, double initial_output)
{
    pi->kp = kp;
    pi->ki = ki;
    pi->integral = initial_output;
}

double ref_pi_step(ref_pi_t *pi, double error, double dt, double out_min, double out_max)
{
    const double lo = fmin(out_min, out_max);
    const double p = pi->kp * error;
    const double step = pi->ki * error * dt;
    const double trial = p + pi->integral + step;
    const bool winding_up = (trial > out_max) && (step > 0.0);
    const bool winding_down = (trial < lo) && (step < 0.0);
    if (!winding_up && !winding_down) {
        pi->integral += step;
    }
    pi->integral = clamp(pi->integral, lo, out_max);
    return clamp(p + pi->integral, lo, out_max);
}

static double road_grade(const ref_road_t *road, double position)
{
    size_t k = (size_t)(position / road->spacing);
    if (k >= road->n_samples) {
        k = road->n_samples - 1U;
    }
    return road->grade[k];
}

int ref_sim_init(ref_sim_t *sim, const ref_platoon_t *pl, const pfe_cruise_calib_t *cruise,
                 const ref_road_t *road, double set_speed, double initial_speed, double step)
{
    if ((road->n_samples == 0U) || (road->spacing <= 0.0) || (pfe_calib_check_cruise(cruise) != 0) ||
        (step < 0.1) || (step > 16.0) || (set_speed < STALL) || (set_speed > SPEED_MAX) ||
        (initial_speed < STALL) || (initial_speed > SPEED_MAX)) {
        return -1;
    }
    sim->pl = pl;
    sim->step = step;
    sim->end = (double)road->n_samples * road->spacing;
    sim->set_speed = set_speed;
    sim->speed = initial_speed;
    sim->position = 0.0;
    sim->time = 0.0;
    sim->fuel = 0.0;
    sim->steps = 0UL;
    sim->grade = road->grade[0];
    sim->accel = 0.0;
    const ref_vehicle_t *o = &pl->object;
    const double hold = ref_object_resistance(pl, initial_speed, road->grade[0]);
    sim->wheel_force = clamp(hold, -o->brake_max, ref_platoon_force_max(pl, initial_speed));
    ref_pi_init(&sim->pi, o->mass * cruise->kp_milli_per_s / 1000.0,
                o->mass * cruise->ki_milli_per_s2 / 1000.0, sim->wheel_force);
    return 0;
}

int ref_sim_step(ref_sim_t *sim, const ref_road_t *road)
{
    /* Positions are whole millimetres in the firmware: compare with a margin. */
    if (sim->position >= sim->end - 1e-6) {
        return 0;
    }
    const double v = sim->speed;
    if (v < STALL) {
        return -1;
    }
    const ref_platoon_t *pl = sim->pl;
    const ref_vehicle_t *o = &pl->object;
    const double ds = fmin(sim->step, sim->end - sim->position);
    const double dt = ds / v;
    const double grade = road_grade(road, sim->position + (ds / 2.0));
    const double resist = ref_object_resistance(pl, v, grade);
    const double f_max = ref_platoon_force_max(pl, v);
    const double force = ref_pi_step(&sim->pi, sim->set_speed - v, dt, -o->brake_max, f_max);
    const double accel = clamp((force - resist) / o->mass, -ACCEL_MAX, ACCEL_MAX);
    sim->speed = clamp(v + (accel * dt), 0.0, SPEED_MAX);
    const double fuel_force = (o->mass_fuel * accel) + resist;          /* eq. 3.7 */
    if (fuel_force > 0.0) {
        sim->fuel += ((fuel_force * ds) + (o->power_aux * dt)) * o->fuel_per_j; /* eq. 4.14 */
    }
    sim->time += dt;
    sim->position += ds;
    sim->steps++;
    sim->grade = grade;
    sim->wheel_force = force;
    sim->accel = accel;
    return 1;
}

void ref_accel_reset(ref_accel_t *f)
{
    f->speed = 0.0;
    f->accel = 0.0;
    f->samples = 0UL;
}

void ref_accel_update(ref_accel_t *f, double speed, unsigned periods)
{
    const double z = clamp(speed, 0.0, SPEED_MAX);
    if (f->samples == 0UL) {
        f->speed = z;
        f->accel = 0.0;
        f->samples = 1UL;
        return;
    }
    const double kt = (periods < 1U ? 1U : (periods > 10U ? 10U : periods)) * 0.1;
    const double predicted = f->speed + (f->accel * kt);
    const double r = z - predicted;
    f->speed = clamp(predicted + (0.3 * r), 0.0, SPEED_MAX);
    f->accel = clamp(f->accel + (0.05 * r / kt), -ACCEL_MAX, ACCEL_MAX);
    f->samples++;
}

void ref_estimator_init(ref_estimator_t *est, const ref_platoon_t *pl)
{
    *est = (ref_estimator_t){0};
    est->pl = pl;
    ref_accel_reset(&est->filter);
}

void ref_estimator_step(ref_estimator_t *est, double speed, bool speed_valid, bool speed_fresh,
                        double grade, bool grade_valid)
{
    bool speed_ok = speed_valid;
    est->valid = false;
    est->fuel_rate = 0.0;
    for (unsigned i = 0U; i < PFE_MAX_VEHICLES; i++) {
        est->pos_fuel_rate[i] = 0.0;
    }
    if (!speed_ok) {
        ref_accel_reset(&est->filter);
        est->ticks_since_sample = 0UL;
    } else {
        est->ticks_since_sample++;
        if (speed_fresh) {
            const unsigned long periods = (est->ticks_since_sample + 5UL) / 10UL;
            if (periods > 3UL) {
                ref_accel_reset(&est->filter);
            }
            ref_accel_update(&est->filter, speed, (unsigned)periods);
            est->ticks_since_sample = 0UL;
        } else if (est->ticks_since_sample > 30UL) {
            speed_ok = false;
        }
    }
    if (!speed_ok || !grade_valid || (est->filter.samples < 5UL)) {
        return;
    }
    const ref_platoon_t *pl = est->pl;
    const double v = est->filter.speed;
    const double a = est->filter.accel;
    const double g = clamp(grade, -GRADE_MAX, GRADE_MAX);
    const ref_vehicle_t *o = &pl->object;
    const double force = (o->mass_fuel * a) + ref_object_resistance(pl, v, g);
    est->fuel_rate = ref_fuel_rate(force, v, o->power_aux, o->fuel_per_j);
    est->fuel_used += est->fuel_rate * 0.01;
    for (unsigned i = 0U; i < pl->n_vehicles; i++) {
        const ref_vehicle_t *veh = &pl->position[i];
        const double f = (veh->mass_fuel * a) + ref_vehicle_resistance(veh, v, g, pl->gravity);
        est->pos_fuel_rate[i] = ref_fuel_rate(f, v, veh->power_aux, veh->fuel_per_j);
        est->pos_fuel_used[i] += est->pos_fuel_rate[i] * 0.01;
    }
    est->valid = true;
}
