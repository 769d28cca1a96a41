/*
 * selfcheck - the model's known-answer run on the host, printed as the
 * mps2-an386 image (hal/mps2/main_selfcheck.c) prints it.
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#include <inttypes.h>
#include <stdio.h>

#include "firmware/pfe_fixed.h"
#include "firmware/pfe_selfcheck.h"
#include "lib/road_csv.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: selfcheck ROAD.csv\n"
    "\n"
    "The model's known-answer run on the host. Prints what the mps2-an386 image\n"
    "prints for the same road, in the same format, so that make test can compare\n"
    "the two byte for byte: the same inputs must give bit-identical outputs on the\n"
    "host and on the Cortex-M4.\n"
    "\n"
    "Exit status 0, 1 if a run fails, 2 on bad input.\n"
    "\n"
    "Example:\n"
    "  selfcheck sim_host/data/roads/hilly.csv\n";

int main(int argc, char **argv)
{
    if (cli_help_asked(argc, argv)) {
        cli_help(k_manual);
        return 0;
    }
    if (argc != 2) {
        cli_usage(stderr, k_manual, "selfcheck");
        return 2;
    }
    char err[512];
    road_ppm_t prof;
    if (road_ppm_load(argv[1], &prof, err, sizeof err) != 0) {
        fprintf(stderr, "selfcheck: %s\n", err);
        return 2;
    }
    const pfe_road_t road = {prof.grade_ppm, prof.n_samples, prof.spacing_mm};
    static const uint32_t sizes[2] = {1U, 5U};
    int status = 0;
    for (uint32_t k = 0U; k < 2U; k++) {
        pfe_selfcheck_result_t r;
        const int rc = pfe_selfcheck_run(&road, sizes[k], 25000, &r);
        printf("selfcheck: road hilly vehicles %" PRIu32 " set_speed_mm_s 25000\n", sizes[k]);
        if (rc != PFE_OK) {
            printf("selfcheck:   error %d\n", rc);
            status = 1;
            continue;
        }
        printf("selfcheck:   digest 0x%016" PRIx64 "\n", r.digest);
        printf("selfcheck:   steps %" PRIu32 "\n", r.steps);
        printf("selfcheck:   ticks %" PRIu32 "\n", r.ticks);
        printf("selfcheck:   sim_fuel_nl %" PRIu64 "\n", r.sim_fuel_nl);
        printf("selfcheck:   sim_time_q16 %" PRIu64 "\n", r.sim_time_q16);
        printf("selfcheck:   sim_min_speed_mm_s %" PRId32 "\n", r.sim_min_speed_mm_s);
        printf("selfcheck:   sim_max_speed_mm_s %" PRId32 "\n", r.sim_max_speed_mm_s);
        printf("selfcheck:   est_fuel_ul %" PRIu64 "\n", r.est_fuel_ul);
        printf("selfcheck:   est_pos0_fuel_ul %" PRIu64 "\n", r.est_pos0_fuel_ul);
    }
    road_ppm_free(&prof);
    return status;
}
