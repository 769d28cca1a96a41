/* drive_trace.c - a time-domain drive from a simulation (contract in drive_trace.h). */
#include "ref/drive_trace.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "ref/ref_model.h"

int32_t drive_spn84_quantise_mm_s(double speed_m_s)
{
    const double raw = floor((speed_m_s * 3.6 * 256.0) + 0.5); /* 1/256 km/h */
    return (int32_t)lround(raw * 1000.0 / (3.6 * 256.0));
}

int drive_trace_make(const int32_t *grade_ppm, uint32_t n_samples, uint32_t spacing_mm,
                     const pfe_platoon_config_t *cfg, int32_t set_speed_mm_s, drive_trace_t *out,
                     char *err, size_t err_len)
{
    out->ticks = NULL;
    out->n_ticks = 0U;
    static ref_platoon_t pl;
    if (ref_platoon_init(&pl, cfg) != 0) {
        snprintf(err, err_len, "invalid platoon configuration");
        return -1;
    }
    double *grade = malloc(sizeof(double) * (n_samples ? n_samples : 1U));
    if (grade == NULL) {
        snprintf(err, err_len, "out of memory");
        return -1;
    }
    for (uint32_t k = 0U; k < n_samples; k++) {
        grade[k] = grade_ppm[k] / 1e6;
    }
    const ref_road_t road = {grade, n_samples, spacing_mm / 1000.0};
    ref_sim_t sim;
    const double v0 = set_speed_mm_s / 1000.0;
    /* A fine step (1 m) so that linear interpolation in time is close. */
    if (ref_sim_init(&sim, &pl, &pfe_default_cruise, &road, v0, v0, 1.0) != 0) {
        free(grade);
        snprintf(err, err_len, "invalid road or speed");
        return -1;
    }
    size_t cap = 1024U;
    drive_tick_t *ticks = malloc(sizeof(drive_tick_t) * cap);
    size_t n = 0U;
    double t_prev = 0.0, v_prev = v0, x_prev = 0.0;
    int rc = 0;
    while ((ticks != NULL) && ((rc = ref_sim_step(&sim, &road)) == 1)) {
        /* Emit every 10 ms tick in (t_prev, sim.time]. */
        while ((double)n * 0.01 <= sim.time) {
            const double t = (double)n * 0.01;
            const double w = (sim.time > t_prev) ? ((t - t_prev) / (sim.time - t_prev)) : 1.0;
            const double v = v_prev + (w * (sim.speed - v_prev));
            if (n == cap) {
                cap *= 2U;
                drive_tick_t *grown = realloc(ticks, sizeof(drive_tick_t) * cap);
                if (grown == NULL) {
                    free(ticks);
                    ticks = NULL;
                    break;
                }
                ticks = grown;
            }
            ticks[n].true_speed = v;
            ticks[n].position_m = x_prev + (w * (sim.position - x_prev));
            ticks[n].speed_fresh = (n % 10U) == 0U;
            ticks[n].speed_mm_s = ticks[n].speed_fresh ? drive_spn84_quantise_mm_s(v)
                                                       : ticks[n - 1U].speed_mm_s;
            ticks[n].grade_ppm = (int32_t)lround(sim.grade * 1e6);
            n++;
        }
        t_prev = sim.time;
        v_prev = sim.speed;
        x_prev = sim.position;
    }
    free(grade);
    if (ticks == NULL) {
        snprintf(err, err_len, "out of memory");
        return -1;
    }
    if (rc < 0) {
        free(ticks);
        snprintf(err, err_len, "platoon stalled at %.0f m", sim.position);
        return -1;
    }
    out->ticks = ticks;
    out->n_ticks = n;
    return 0;
}

void drive_trace_free(drive_trace_t *t)
{
    free(t->ticks);
    t->ticks = NULL;
    t->n_ticks = 0U;
}

void drive_noise_seed(drive_noise_t *n, uint64_t seed)
{
    n->state = seed;
}

uint64_t drive_noise_u64(drive_noise_t *n)
{
    n->state += 0x9E3779B97F4A7C15ULL;
    uint64_t z = n->state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

double drive_noise_uniform(drive_noise_t *n)
{
    return (double)(drive_noise_u64(n) >> 11) * 0x1.0p-53;
}

double drive_noise_gauss(drive_noise_t *n)
{
    double sum = 0.0;
    for (int k = 0; k < 12; k++) {
        sum += drive_noise_uniform(n);
    }
    return sum - 6.0;
}
