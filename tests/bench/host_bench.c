/*
 * host_bench.c - accuracy figures for `make bench`: the fixed-point object
 * model against the double-precision reference on the three thesis roads,
 * N = 1 and N = 5, 90 km/h, 10 m steps.
 *
 *   host_bench ROADS_DIR
 *
 * Prints `bench: fuel_error_<road>_n<N> <value> %` (fixed minus reference,
 * relative) and `bench: speed_rms_<road>_n<N> <value> km/h`.
 * Exit status 0, or 1 if a road cannot be loaded or simulated.
 */
#include <stdio.h>

#include "firmware/pfe_calib.h"
#include "firmware/pfe_platoon.h"
#include "lib/road_csv.h"
#include "ref/sim_compare.h"

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: host_bench ROADS_DIR\n");
        return 1;
    }
    static const char *const roads[3] = {"flat", "uphill", "hilly"};
    static const unsigned sizes[2] = {1U, 5U};
    for (unsigned r = 0U; r < 3U; r++) {
        char path[1024];
        char err[512];
        snprintf(path, sizeof path, "%s/%s.csv", argv[1], roads[r]);
        road_ppm_t road;
        if (road_ppm_load(path, &road, err, sizeof err) != 0) {
            fprintf(stderr, "host_bench: %s\n", err);
            return 1;
        }
        for (unsigned k = 0U; k < 2U; k++) {
            pfe_platoon_config_t cfg;
            pfe_platoon_config_uniform(&cfg, sizes[k], 10000U, &pfe_default_vehicle,
                                       &pfe_default_env, &pfe_default_drag);
            const sim_compare_args_t args = {road.grade_ppm, road.n_samples, road.spacing_mm, &cfg,
                                             &pfe_default_cruise, 25000, 10000U, NULL};
            sim_compare_t c;
            if (sim_compare_run(&args, &c, err, sizeof err) != 0) {
                fprintf(stderr, "host_bench: %s: %s\n", roads[r], err);
                return 1;
            }
            printf("bench: fuel_error_%s_n%u %+.5f %%\n", roads[r], sizes[k], 100.0 * c.fuel_rel_err);
            printf("bench: speed_rms_%s_n%u %.5f km/h\n", roads[r], sizes[k], c.speed_rms_kmh);
        }
        road_ppm_free(&road);
    }
    return 0;
}
