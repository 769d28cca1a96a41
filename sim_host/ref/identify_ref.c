/* identify_ref.c - double reference of pfe_identify and a drive (contract in identify_ref.h). */
#include "ref/identify_ref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define KMH 3.6

void identify_ref_init(identify_ref_t *r, const pfe_vehicle_calib_t *seed,
                       const pfe_env_calib_t *env)
{
    memset(r, 0, sizeof *r);
    r->fuel_power_per_nl = (seed->eta_ppm / 1e6) * env->fuel_energy_j_ml * 1e-6;
    r->air_k = 0.5 * (env->air_density_g_m3 / 1000.0) * (seed->drag_area_mm2 / 1e6);
    r->roll = seed->roll_coef_ppm / 1e6;
    r->gravity = env->gravity_um_s2 / 1e6;
    r->rot_mass = seed->rot_mass_kg;
    r->mass0 = seed->mass_kg;
    r->mass = seed->mass_kg;
    r->aux = seed->power_aux_w;
}

static double clampd(double x, double lo, double hi)
{
    return (x < lo) ? lo : ((x > hi) ? hi : x);
}

static void reset_information(identify_ref_t *r)
{
    r->mass0 = r->mass;
    r->sxx = r->sxy = r->var = 0.0;
    r->n_mass = 0U;
    r->have_mean = false;
    r->have_prev = false;
    r->win_on = r->pend_on = false;
}

static void update_mass(identify_ref_t *r, double dx, double dy, double e2)
{
    /* dx in W/kg, dy in W; the prior I0 is PFE_ID_PRIOR_INFO (mW/kg)^2. */
    const double i0 = (double)PFE_ID_PRIOR_INFO / 1e6;
    if (r->n_mass == 0U) {
        r->var = e2;
    } else {
        r->var += (e2 - r->var) / 16.0;
    }
    const double lambda = 1.0 - 1.0 / (double)(1U << PFE_ID_MASS_SHIFT);
    r->sxx = lambda * r->sxx + dx * dx;
    r->sxy = lambda * r->sxy + dx * dy;
    r->mass = clampd((r->sxy + i0 * r->mass0) / (r->sxx + i0), PFE_MASS_MIN_KG, PFE_MASS_MAX_KG);
    r->n_mass++;
    r->mass_updates++;
    if (r->n_mass >= PFE_ID_CONVERGED_UPDATES) {
        const double rel = 1.0 / PFE_ID_CONVERGED_INV_REL;
        r->converged = (r->var / (r->sxx + i0)) <= (rel * r->mass) * (rel * r->mass);
    }
}

/* The pending window, complete with v, the mean speed around its end. */
static void close_window(identify_ref_t *r, double v)
{
    const double ke = 0.5 * (v * v - r->pend_v0 * r->pend_v0);
    const double x = (ke + r->pend_spec) / r->pend_t;
    const double y = (r->pend_fuel - r->pend_air - r->rot_mass * ke) / r->pend_t;
    if ((fabs(x) > PFE_ID_X_MAX_MW_KG / 1000.0) || (fabs(y) > PFE_POWER_MAX_W)) {
        return;
    }
    if (!r->have_mean) {
        r->mean_x = x;
        r->mean_y = y;
        r->have_mean = true;
    } else {
        const double dx = x - r->mean_x;
        const double dy = y - r->mean_y;
        const double e = dy - (r->mass * dx);
        const double e2 = e * e;
        const double floor_w2 = (double)PFE_ID_RESIDUAL_FLOOR_W * PFE_ID_RESIDUAL_FLOOR_W;
        if ((r->n_mass >= PFE_ID_OUTLIER_AFTER) && (e2 > 16.0 * fmax(r->var, floor_w2))) {
            r->var = fmin(r->var + (15.0 * r->var) / 16.0, 17592186044416.0);
            return;
        }
        const double a = 1.0 / (double)(1U << PFE_ID_MEAN_SHIFT);
        r->mean_x += a * dx;
        r->mean_y += a * dy;
        if (fabs(dx) >= PFE_ID_EXCITE_MW_KG / 1000.0) {
            update_mass(r, dx, dy, e2);
        }
    }
    r->windows_used++;
    r->since_window = 0.0;
    r->aux = clampd(r->mean_y - r->mass * r->mean_x, 0.0, PFE_ID_AUX_MAX_W);
}

static double hist_mean(const identify_ref_t *r)
{
    double sum = 0.0;
    for (unsigned k = 0U; k < PFE_ID_SPEED_AVG; k++) {
        sum += r->hist[k];
    }
    return sum / PFE_ID_SPEED_AVG;
}

static void hist_push(identify_ref_t *r, double v)
{
    r->hist[r->hist_i] = v;
    r->hist_i = (r->hist_i + 1U) % PFE_ID_SPEED_AVG;
    r->hist_n += (r->hist_n < PFE_ID_SPEED_AVG) ? 1U : 0U;
}

void identify_ref_step(identify_ref_t *r, const pfe_identify_sample_t *s)
{
    double dt = 0.0;
    bool dt_ok = false;
    if (!r->have_time || (s->now_us < r->last_us)) {
        r->have_time = true;
    } else {
        dt = (double)(s->now_us - r->last_us) / 1e6;
        dt_ok = (dt >= PFE_ID_DT_MIN_MS / 1000.0) && (dt <= (PFE_ID_DT_MAX_MS + 1) / 1000.0 - 1e-9);
    }
    r->last_us = s->now_us;
    const double dt_seen = fmin(dt, PFE_ID_DT_MAX_MS / 1000.0);
    if (s->speed_valid && (s->speed_mm_s < PFE_ID_STOP_MM_S)) {
        const double was = r->stop;
        r->stop += dt_seen;
        if ((was < PFE_ID_STOP_RESET_MS / 1000.0) && (r->stop >= PFE_ID_STOP_RESET_MS / 1000.0)) {
            reset_information(r);
            r->converged = false;
        }
    } else {
        r->stop = 0.0;
    }
    r->since_window += dt_seen;
    if (r->since_window > PFE_ID_MEAN_RESTART_MS / 1000.0) {
        r->have_mean = false;
    }
    const double fuel_w = s->fuel_rate_nl_s * r->fuel_power_per_nl;
    const bool ok = s->speed_valid && s->grade_valid && s->fuel_valid &&
                    (s->speed_mm_s >= PFE_ID_SPEED_MIN_MM_S) && (s->speed_mm_s <= PFE_ID_SPEED_MAX_MM_S) &&
                    (abs(s->grade_ppm) <= PFE_ID_GRADE_MAX_PPM) && !s->braking &&
                    (fuel_w >= PFE_ID_FUEL_POWER_MIN_W) && (fuel_w <= PFE_POWER_MAX_W);
    if (!ok) {
        r->have_prev = false;
        r->win_on = r->pend_on = false;
        return;
    }
    const double v = s->speed_mm_s / 1000.0;
    const double alpha = atan(s->grade_ppm / 1e6);
    const double air_w = r->air_k * v * v * v;
    const double spec = v * r->gravity * (r->roll * cos(alpha) + sin(alpha));
    if (!dt_ok || !r->have_prev) {
        r->win_on = r->pend_on = false;
        r->hist_n = 0U;
        hist_push(r, v);
    } else if (fabs(v - r->prev_v) > (PFE_ID_ACCEL_MAX_UM_S2 / 1e6) * dt + PFE_ID_SPEED_MARGIN_MM_S / 1e3) {
        r->have_prev = false;
        r->win_on = r->pend_on = false;
        return;
    } else {
        hist_push(r, v);
        if (!r->win_on && (r->hist_n >= PFE_ID_SPEED_HALF + 2U)) {
            r->win_on = true;
            r->win_n = 0U;
            r->win_t = r->win_fuel = r->win_air = r->win_spec = 0.0;
        }
        if (r->win_on) {
            r->win_fuel += 0.5 * (r->prev_fuel_w + fuel_w) * dt;
            r->win_air += 0.5 * (r->prev_air_w + air_w) * dt;
            r->win_spec += 0.5 * (r->prev_spec + spec) * dt;
            r->win_t += dt;
            r->win_n++;
            if (r->win_n == PFE_ID_SPEED_HALF) {
                r->win_v0 = hist_mean(r);
                if (r->pend_on) {
                    close_window(r, r->win_v0);
                    r->pend_on = false;
                }
            }
            if (r->win_n >= PFE_ID_WINDOW_INTERVALS) {
                r->pend_t = r->win_t;
                r->pend_v0 = r->win_v0;
                r->pend_fuel = r->win_fuel;
                r->pend_air = r->win_air;
                r->pend_spec = r->win_spec;
                r->pend_on = true;
                r->win_n = 0U;
                r->win_t = r->win_fuel = r->win_air = r->win_spec = 0.0;
            }
        }
    }
    r->have_prev = true;
    r->prev_v = v;
    r->prev_fuel_w = fuel_w;
    r->prev_air_w = air_w;
    r->prev_spec = spec;
}

/* ---------------------------------------------------------------- the drive */

static double uniform(id_drive_t *d)
{
    d->rng ^= d->rng << 13;
    d->rng ^= d->rng >> 7;
    d->rng ^= d->rng << 17;
    return ((double)(d->rng >> 11) + 0.5) / 9007199254740992.0;
}

static double gauss(id_drive_t *d)
{
    const double u1 = uniform(d);
    const double u2 = uniform(d);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

void id_drive_init(id_drive_t *d, const pfe_vehicle_calib_t *calib, const pfe_env_calib_t *env,
                   double speed_noise_kmh, double pitch_noise_deg, double fuel_noise_rel,
                   uint64_t seed)
{
    memset(d, 0, sizeof *d);
    ref_vehicle_init(&d->truck, calib, env, 0.0);
    d->gravity = env->gravity_um_s2 / 1e6;
    d->speed = 70.0 / KMH;
    d->target = d->speed;
    d->speed_noise_kmh = speed_noise_kmh;
    d->pitch_noise_deg = pitch_noise_deg;
    d->fuel_noise_rel = fuel_noise_rel;
    d->rng = seed | 1U;
}

double id_drive_grade(double position_m)
{
    return 0.02 * sin(6.283185307179586 * position_m / 1500.0) +
           0.01 * sin((6.283185307179586 * position_m / 430.0) + 1.0);
}

static double force_with(const ref_vehicle_t *v, double accel, double speed, double grade, double g)
{
    return (v->mass_fuel * accel) + ref_vehicle_resistance(v, speed, grade, g);
}

/* One 10 ms step: a speed target from a fixed sequence, changed every 60 s;
 * a P controller of 0.1 /s to it, acceleration within -0.6 .. +0.4 m/s^2,
 * then the force limits; brakes when the force is below -2 kN. */
static void step(id_drive_t *d)
{
    static const double targets_kmh[] = {70.0, 85.0, 60.0, 80.0, 50.0, 88.0, 65.0, 75.0};
    const unsigned k = (unsigned)(d->time / 60.0) % (sizeof targets_kmh / sizeof targets_kmh[0]);
    d->target = targets_kmh[k] / KMH;
    const double dt = 0.01;
    const ref_vehicle_t *v = &d->truck;
    d->grade = id_drive_grade(d->position);
    const double a_cmd = clampd(0.1 * (d->target - d->speed), -0.6, 0.4);
    const double res = ref_vehicle_resistance(v, d->speed, d->grade, d->gravity);
    const double f_max = ref_wheel_force_max(v->power_max, v->traction_max, d->speed);
    const double f = clampd((v->mass_fuel * a_cmd) + res, -v->brake_max, f_max);
    d->force = f;
    d->accel = (f - res) / v->mass_fuel;
    d->braking = f < -2000.0;
    d->fuel_rate = ref_fuel_rate(f, d->speed, v->power_aux, v->fuel_per_j);
    d->fuel_used += d->fuel_rate * dt;
    d->position += d->speed * dt + 0.5 * d->accel * dt * dt;
    d->speed = fmax(0.0, d->speed + d->accel * dt);
    d->time += dt;
    d->steps++;
}

void id_drive_advance(id_drive_t *d, pfe_identify_sample_t *s)
{
    for (int i = 0; i < 10; i++) {
        step(d);
    }
    /* The engine's rate at the frame: the state after the last step's
     * speed update, its force recomputed there (eq. 3.7). */
    const ref_vehicle_t *v = &d->truck;
    const double grade = id_drive_grade(d->position);
    const double f = force_with(v, d->accel, d->speed, grade, d->gravity);
    const double fc = ref_fuel_rate(f, d->speed, v->power_aux, v->fuel_per_j); /* L/s */
    const double fc_noisy = fmax(0.0, fc * (1.0 + d->fuel_noise_rel * gauss(d)));
    const double lfe1_raw = floor((fc_noisy * 3600.0 / 0.05) + 0.5); /* SPN 183 counts */
    const double kmh = d->speed * KMH + d->speed_noise_kmh * gauss(d);
    const double spn84 = floor(fmax(0.0, kmh) * 256.0 + 0.5);
    const double pitch = atan(grade) * 180.0 / 3.141592653589793 + d->pitch_noise_deg * gauss(d);
    const double spn3318 = floor((pitch / 0.002) + 0.5) * 0.002;
    s->now_us = (uint64_t)llround(d->time * 1e6);
    s->speed_mm_s = (int32_t)llround(spn84 / 256.0 / KMH * 1000.0);
    s->grade_ppm = (int32_t)llround(tan(spn3318 * 3.141592653589793 / 180.0) * 1e6);
    s->fuel_rate_nl_s = (uint32_t)llround(lfe1_raw * 0.05 / 3600.0 * 1e9);
    s->speed_valid = true;
    s->grade_valid = true;
    s->fuel_valid = true;
    s->braking = d->braking;
}

double id_drive_fuel_rate_with(const id_drive_t *d, double mass_kg, double aux_w)
{
    ref_vehicle_t v = d->truck;
    const double mj = v.mass_fuel - v.mass;
    const double cr = v.roll_mass / v.mass;
    v.mass = mass_kg;
    v.mass_fuel = mass_kg + mj;
    v.roll_mass = cr * mass_kg;
    const double grade = id_drive_grade(d->position);
    const double f = force_with(&v, d->accel, d->speed, grade, d->gravity);
    return ref_fuel_rate(f, d->speed, aux_w, v.fuel_per_j);
}
