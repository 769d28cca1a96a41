/* sim_compare.c - fixed point against double on one road (contract in sim_compare.h). */
#include "ref/sim_compare.h"

#include <math.h>
#include <stdlib.h>

#include "firmware/pfe_fixed.h"
#include "firmware/pfe_sim.h"
#include "ref/ref_model.h"

static void summary_add(sim_summary_t *s, double kmh, unsigned long n)
{
    s->mean_kmh += (kmh - s->mean_kmh) / (double)n;
    s->min_kmh = fmin(s->min_kmh, kmh);
    s->max_kmh = fmax(s->max_kmh, kmh);
}

int sim_compare_run(const sim_compare_args_t *args, sim_compare_t *out, char *err, size_t err_len)
{
    *out = (sim_compare_t){0};
    static pfe_platoon_t pl;
    static ref_platoon_t rpl;
    if ((pfe_platoon_init(&pl, args->config) != PFE_OK) || (ref_platoon_init(&rpl, args->config) != 0)) {
        snprintf(err, err_len, "invalid platoon configuration");
        return -1;
    }
    const pfe_road_t road = {args->grade_ppm, args->n_samples, args->spacing_mm};
    double *grade = malloc(sizeof(double) * (args->n_samples ? args->n_samples : 1U));
    if (grade == NULL) {
        snprintf(err, err_len, "out of memory");
        return -1;
    }
    for (uint32_t k = 0U; k < args->n_samples; k++) {
        grade[k] = args->grade_ppm[k] / 1e6;
    }
    const ref_road_t rroad = {grade, args->n_samples, args->spacing_mm / 1000.0};
    pfe_sim_t sim;
    ref_sim_t ref;
    const double v0 = args->set_speed_mm_s / 1000.0;
    if ((pfe_sim_init(&sim, &pl, args->cruise, &road, args->set_speed_mm_s, args->set_speed_mm_s,
                      args->step_mm) != PFE_OK) ||
        (ref_sim_init(&ref, &rpl, args->cruise, &rroad, v0, v0, args->step_mm / 1000.0) != 0)) {
        free(grade);
        snprintf(err, err_len, "invalid simulation arguments (road, step or speed)");
        return -1;
    }
    out->fixed.min_kmh = out->ref.min_kmh = INFINITY;
    out->fixed.max_kmh = out->ref.max_kmh = -INFINITY;
    if (args->trace != NULL) {
        fprintf(args->trace, "distance_m,grade_pct,speed_kmh_fixed,speed_kmh_ref,force_n_fixed,"
                             "force_n_ref,fuel_l_fixed,fuel_l_ref,time_s_fixed,time_s_ref\n");
    }
    double sq = 0.0;
    int rc = 0;
    for (;;) {
        const int a = pfe_sim_step(&sim, &road);
        const int b = ref_sim_step(&ref, &rroad);
        if ((a == PFE_SIM_DONE) && (b == 0)) {
            break;
        }
        if ((a < 0) || (b < 0)) {
            snprintf(err, err_len, "platoon stalled at %.0f m (speed below %.1f km/h)",
                     sim.position_mm / 1000.0, PFE_SIM_STALL_MM_S * 0.0036);
            rc = -1;
            break;
        }
        if (a != b) {
            snprintf(err, err_len, "fixed and reference step counts differ at %.0f m",
                     sim.position_mm / 1000.0);
            rc = -1;
            break;
        }
        out->steps++;
        const double vf = sim.speed_um_s * 3.6e-6;
        const double vr = ref.speed * 3.6;
        summary_add(&out->fixed, vf, out->steps);
        summary_add(&out->ref, vr, out->steps);
        sq += (vf - vr) * (vf - vr);
        out->speed_max_kmh = fmax(out->speed_max_kmh, fabs(vf - vr));
        if (args->trace != NULL) {
            fprintf(args->trace, "%.3f,%.4f,%.4f,%.4f,%d,%.1f,%.6f,%.6f,%.3f,%.3f\n",
                    sim.position_mm / 1000.0, sim.grade_ppm / 1e4, vf, vr, sim.wheel_force_n,
                    ref.wheel_force, (double)sim.fuel_nl / 1e9, ref.fuel, (double)sim.time_q16 / 65536.0, ref.time);
        }
    }
    free(grade);
    out->fixed.fuel_l = (double)sim.fuel_nl / 1e9;
    out->fixed.time_s = (double)sim.time_q16 / 65536.0;
    out->ref.fuel_l = ref.fuel;
    out->ref.time_s = ref.time;
    out->fuel_rel_err = (ref.fuel > 0.0) ? ((out->fixed.fuel_l - ref.fuel) / ref.fuel) : 0.0;
    out->speed_rms_kmh = (out->steps > 0UL) ? sqrt(sq / (double)out->steps) : 0.0;
    return rc;
}
