/*
 * platoon_sim - a platoon over a road profile, the firmware's fixed-point
 * object model beside the double-precision reference.
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lib/cli_args.h"
#include "firmware/pfe_calib.h"
#include "firmware/pfe_platoon.h"
#include "lib/road_csv.h"
#include "ref/sim_compare.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: platoon_sim --road FILE.csv [--vehicles N] [--set-speed-kmh V]\n"
    "                   [--gap-m D | --time-gap-s T] [--step-m S]\n"
    "                   [--no-drag-reduction] [--trace OUT.csv]\n"
    "\n"
    "Drives a platoon over a road profile with the firmware's fixed-point object\n"
    "model and the double-precision reference, and prints both summaries side by\n"
    "side.\n"
    "\n"
    "  --road FILE.csv     the road profile\n"
    "  --vehicles N        platoon size, 1 to 32 (default 5)\n"
    "  --set-speed-kmh V   cruise set speed (default 90)\n"
    "  --gap-m D           gap between trucks in m\n"
    "  --time-gap-s T      gap as time at set speed (default 0.4 s)\n"
    "  --step-m S          distance step, 0.1 to 10 m (default 10)\n"
    "  --no-drag-reduction trucks without slipstream (phi = 0)\n"
    "  --trace OUT.csv     write one row per step for both models\n"
    "  -h, --help          this help\n"
    "\n"
    "Exit status: 0 on success, 1 on a simulation failure (stall), 2 on bad\n"
    "arguments or input.\n"
    "\n"
    "Example:\n"
    "  platoon_sim --road sim_host/data/roads/hilly.csv --vehicles 5 --trace hilly.csv\n";

static void usage(FILE *f)
{
    /* --help: the whole manual; a usage error: its synopsis. */
    if (f == stdout) {
        cli_help(k_manual);
    } else {
        cli_usage(f, k_manual, "platoon_sim");
    }
}

int main(int argc, char **argv)
{
    const char *road_path = NULL;
    const char *trace_path = NULL;
    double n = 5.0, set_kmh = 90.0, gap_m = -1.0, time_gap = 0.4, step_m = 10.0;
    int no_drag = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
        int bad = 0;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--no-drag-reduction") == 0) {
            no_drag = 1;
            continue;
        } else if (v == NULL) {
            bad = 1;
        } else if (strcmp(a, "--road") == 0) {
            road_path = v;
        } else if (strcmp(a, "--trace") == 0) {
            trace_path = v;
        } else if (strcmp(a, "--vehicles") == 0) {
            bad = cli_parse_double(v, 1.0, PFE_MAX_VEHICLES, &n) || (n != floor(n));
        } else if (strcmp(a, "--set-speed-kmh") == 0) {
            bad = cli_parse_double(v, 5.0, 250.0, &set_kmh);
        } else if (strcmp(a, "--gap-m") == 0) {
            bad = cli_parse_double(v, 0.0, 1000.0, &gap_m);
        } else if (strcmp(a, "--time-gap-s") == 0) {
            bad = cli_parse_double(v, 0.0, 60.0, &time_gap);
        } else if (strcmp(a, "--step-m") == 0) {
            bad = cli_parse_double(v, 0.1, 10.0, &step_m);
        } else {
            fprintf(stderr, "platoon_sim: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        }
        if (bad) {
            fprintf(stderr, "platoon_sim: option %s needs a valid value (got '%s')\n", a,
                    v ? v : "nothing");
            return 2;
        }
        i++;
    }
    if (road_path == NULL) {
        fprintf(stderr, "platoon_sim: --road FILE.csv is required\n");
        usage(stderr);
        return 2;
    }
    char err[512];
    road_ppm_t road;
    if (road_ppm_load(road_path, &road, err, sizeof err) != 0) {
        fprintf(stderr, "platoon_sim: %s\n", err);
        return 2;
    }
    if (gap_m < 0.0) {
        gap_m = time_gap * set_kmh / 3.6;
    }
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, (uint32_t)n, (uint32_t)lround(gap_m * 1000.0),
                               &pfe_default_vehicle, &pfe_default_env,
                               no_drag ? &pfe_no_drag_reduction : &pfe_default_drag);
    FILE *trace = NULL;
    if (trace_path != NULL) {
        trace = fopen(trace_path, "w");
        if (trace == NULL) {
            fprintf(stderr, "platoon_sim: cannot write %s: %s\n", trace_path, strerror(errno));
            road_ppm_free(&road);
            return 2;
        }
    }
    const sim_compare_args_t args = {
        .grade_ppm = road.grade_ppm, .n_samples = road.n_samples, .spacing_mm = road.spacing_mm,
        .config = &cfg, .cruise = &pfe_default_cruise,
        .set_speed_mm_s = (int32_t)lround(set_kmh / 3.6 * 1000.0),
        .step_mm = (uint32_t)lround(step_m * 1000.0), .trace = trace,
    };
    sim_compare_t r;
    const int rc = sim_compare_run(&args, &r, err, sizeof err);
    if (trace != NULL) {
        fclose(trace);
    }
    printf("road      %s: %u samples at %.3f m, %.3f km\n", road_path, road.n_samples,
           road.spacing_mm / 1000.0, (double)road.n_samples * road.spacing_mm / 1e6);
    printf("platoon   %u vehicles, gap %.2f m, set speed %.1f km/h, step %.2f m%s\n",
           cfg.n_vehicles, cfg.gap_mm / 1000.0, set_kmh, step_m,
           no_drag ? ", no drag reduction" : "");
    road_ppm_free(&road);
    if (rc != 0) {
        fprintf(stderr, "platoon_sim: %s\n", err);
        return 1;
    }
    printf("%-22s %14s %14s %12s\n", "", "fixed point", "double", "difference");
    printf("%-22s %14.4f %14.4f %+11.4f%%\n", "fuel [L]", r.fixed.fuel_l, r.ref.fuel_l,
           100.0 * r.fuel_rel_err);
    printf("%-22s %14.2f %14.2f %+12.3f\n", "time [s]", r.fixed.time_s, r.ref.time_s,
           r.fixed.time_s - r.ref.time_s);
    printf("%-22s %14.3f %14.3f %+12.4f\n", "mean speed [km/h]", r.fixed.mean_kmh, r.ref.mean_kmh,
           r.fixed.mean_kmh - r.ref.mean_kmh);
    printf("%-22s %14.3f %14.3f %+12.4f\n", "min speed [km/h]", r.fixed.min_kmh, r.ref.min_kmh,
           r.fixed.min_kmh - r.ref.min_kmh);
    printf("%-22s %14.3f %14.3f %+12.4f\n", "max speed [km/h]", r.fixed.max_kmh, r.ref.max_kmh,
           r.fixed.max_kmh - r.ref.max_kmh);
    printf("%-22s %14s %14s %12.5f\n", "speed rms diff [km/h]", "", "", r.speed_rms_kmh);
    printf("%-22s %14s %14s %12.5f\n", "speed max diff [km/h]", "", "", r.speed_max_kmh);
    printf("%-22s %14lu\n", "steps", r.steps);
    return 0;
}
