/* sensitivity_run.c - one sensitivity case (contract in sensitivity_run.h). */
#include "ref/sensitivity_run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "firmware/pfe_fixed.h"
#include "firmware/pfe_platoon.h"
#include "ref/ref_model.h"

static const int32_t grade_steps[] = {-70, -50, -30, 0, 30, 50, 70};
static const int32_t drag_steps[] = {-70, -50, -30, 0, 30, 50, 70};
static const int32_t power_steps[] = {-30, -20, -10, 0, 10, 20, 30};
static const int32_t gap_steps_ms[] = {100, 130, 200, 400, 800, 1200, 1600};
static const int32_t mass_steps[] = {-30, -20, -10, 0, 10, 20, 30};

#define N_OF(a) (sizeof(a) / sizeof((a)[0]))

void sens_setup_default(sens_setup_t *setup)
{
    *setup = (sens_setup_t){
        .n_vehicles = 5U,
        .set_speed_mm_s = 25000,   /* 90 km/h */
        .time_gap_ms = 400U,       /* thesis 6.4 */
        .step_mm = 10000U,
        .vehicle = &pfe_default_vehicle,
        .env = &pfe_default_env,
        .drag = &pfe_default_drag,
        .cruise = &pfe_default_cruise,
    };
}

size_t sens_steps(sens_param_t param, const int32_t **steps)
{
    switch (param) {
    case SENS_GRADE:
        *steps = grade_steps;
        return N_OF(grade_steps);
    case SENS_DRAG_AREA:
        *steps = drag_steps;
        return N_OF(drag_steps);
    case SENS_POWER:
        *steps = power_steps;
        return N_OF(power_steps);
    case SENS_TIME_GAP:
        *steps = gap_steps_ms;
        return N_OF(gap_steps_ms);
    case SENS_MASS:
        *steps = mass_steps;
        return N_OF(mass_steps);
    case SENS_NOMINAL:
    case SENS_N_PARAMS:
    default:
        *steps = NULL;
        return 0U;
    }
}

int32_t sens_nominal_amount(const sens_setup_t *setup, sens_param_t param)
{
    return (param == SENS_TIME_GAP) ? (int32_t)setup->time_gap_ms : 0;
}

const char *sens_param_name(sens_param_t param)
{
    switch (param) {
    case SENS_NOMINAL:
        return "nominal";
    case SENS_GRADE:
        return "grade";
    case SENS_DRAG_AREA:
        return "cw_af";
    case SENS_POWER:
        return "pmax";
    case SENS_TIME_GAP:
        return "time_gap";
    case SENS_MASS:
        return "mass";
    case SENS_N_PARAMS:
    default:
        return "?";
    }
}

/* value * (100 + pct) / 100, rounded to nearest; -1 when it leaves uint32_t. */
static int scale_u32(uint32_t value, int32_t pct, uint32_t *out)
{
    const int64_t num = (int64_t)value * (100 + (int64_t)pct);
    const int64_t r = (num + 50) / 100;
    if ((num < 0) || (r > (int64_t)UINT32_MAX)) {
        return -1;
    }
    *out = (uint32_t)r;
    return 0;
}

/* Percent changes above -100 % (a value must stay positive) and up to
 * +1000 %; time gaps 0 to 60 s; the nominal case takes 0 only. */
static int amount_ok(sens_param_t param, int32_t amount)
{
    switch (param) {
    case SENS_NOMINAL:
        return amount == 0;
    case SENS_TIME_GAP:
        return (amount >= 0) && (amount <= 60000);
    case SENS_GRADE:
    case SENS_DRAG_AREA:
    case SENS_POWER:
    case SENS_MASS:
        return (amount > -100) && (amount <= 1000);
    case SENS_N_PARAMS:
    default:
        return 0;
    }
}

int sens_run(const sens_setup_t *setup, const road_profile_t *road, sens_param_t param,
             int32_t amount, sens_result_t *out, char *err, size_t err_len)
{
    *out = (sens_result_t){0};
    if ((road == NULL) || (road->n_samples == 0U) || (road->grade_percent == NULL) ||
        !(road->spacing_m > 0.0)) {
        snprintf(err, err_len, "empty road");
        return -1;
    }
    if ((setup->set_speed_mm_s < 1000) || (setup->set_speed_mm_s > PFE_SPEED_MAX_MM_S) ||
        (setup->step_mm < 100U) || (setup->step_mm > 10000U)) {
        snprintf(err, err_len, "set speed or step out of range");
        return -1;
    }
    if ((setup->n_vehicles < 1U) || (setup->n_vehicles > PFE_MAX_VEHICLES)) {
        snprintf(err, err_len, "%lu vehicles: must be 1 to %u", (unsigned long)setup->n_vehicles,
                 PFE_MAX_VEHICLES);
        return -1;
    }
    if (!amount_ok(param, amount)) {
        snprintf(err, err_len, "%s: amount %ld out of range", sens_param_name(param), (long)amount);
        return -1;
    }
    pfe_vehicle_calib_t veh = *setup->vehicle;
    uint32_t time_gap_ms = setup->time_gap_ms;
    int bad = 0;
    switch (param) {
    case SENS_DRAG_AREA:
        bad = scale_u32(veh.drag_area_mm2, amount, &veh.drag_area_mm2);
        break;
    case SENS_POWER:
        bad = scale_u32(veh.power_max_w, amount, &veh.power_max_w);
        break;
    case SENS_MASS:
        bad = scale_u32(veh.mass_kg, amount, &veh.mass_kg);
        break;
    case SENS_TIME_GAP:
        time_gap_ms = (uint32_t)amount;
        break;
    case SENS_NOMINAL:
    case SENS_GRADE:
    case SENS_N_PARAMS:
    default:
        break;
    }
    if ((bad != 0) || (pfe_calib_check_vehicle(&veh) != PFE_OK)) {
        snprintf(err, err_len, "%s %+ld %%: the changed vehicle calibration is out of range",
                 sens_param_name(param), (long)amount);
        return -1;
    }
    /* Gap in whole mm, as the firmware's configuration holds it. */
    const uint64_t gap_um = (uint64_t)time_gap_ms * (uint64_t)setup->set_speed_mm_s;
    const uint32_t gap_mm = (uint32_t)((gap_um + 500U) / 1000U);
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, setup->n_vehicles, gap_mm, &veh, setup->env, setup->drag);
    ref_platoon_t pl;
    if (ref_platoon_init(&pl, &cfg) != 0) {
        snprintf(err, err_len, "invalid platoon configuration");
        return -1;
    }
    const double scale = (param == SENS_GRADE) ? (1.0 + (amount / 100.0)) : 1.0;
    double *grade = malloc(sizeof(double) * road->n_samples);
    if (grade == NULL) {
        snprintf(err, err_len, "out of memory for %zu grade samples", road->n_samples);
        return -1;
    }
    for (size_t k = 0U; k < road->n_samples; k++) {
        grade[k] = (road->grade_percent[k] / 100.0) * scale;
    }
    const ref_road_t rroad = {grade, road->n_samples, road->spacing_m};
    const double v0 = setup->set_speed_mm_s / 1000.0;
    ref_sim_t sim;
    if (ref_sim_init(&sim, &pl, setup->cruise, &rroad, v0, v0, setup->step_mm / 1000.0) != 0) {
        free(grade);
        snprintf(err, err_len, "invalid simulation arguments (cruise calibration, speed or step)");
        return -1;
    }
    out->gap_m = gap_mm / 1000.0;
    out->min_kmh = INFINITY;
    out->max_kmh = -INFINITY;
    double limited_s = 0.0;
    for (;;) {
        const double v = sim.speed;
        const double f_max = ref_platoon_force_max(&pl, v);
        const double t0 = sim.time;
        const int rc = ref_sim_step(&sim, &rroad);
        if (rc == 0) {
            break;
        }
        if (rc < 0) {
            out->stalled = 1;
            out->stall_position_m = sim.position;
            break;
        }
        out->steps++;
        if (sim.wheel_force >= f_max) {
            limited_s += sim.time - t0;
        }
        const double kmh = sim.speed * 3.6;
        out->mean_kmh += (kmh - out->mean_kmh) / (double)out->steps;
        out->min_kmh = fmin(out->min_kmh, kmh);
        out->max_kmh = fmax(out->max_kmh, kmh);
    }
    free(grade);
    out->fuel_l = sim.fuel;
    out->time_s = sim.time;
    out->power_limited_pct = (sim.time > 0.0) ? (100.0 * limited_s / sim.time) : 0.0;
    return 0;
}
