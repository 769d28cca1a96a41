/*
 * roadimport - a road profile (sim_host/lib/road_csv.h) from a GPX track with
 * elevations or a distance/elevation CSV (the rules:
 * sim_host/lib/road_import.h).
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
#include "lib/road_import.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: roadimport [--spacing-m S] [--smooth-m W] [--elevation-out FILE.csv] INPUT --out ROAD.csv\n"
    "\n"
    "A road profile from a GPX track with elevations or a distance/elevation CSV,\n"
    "as a route planner has them.\n"
    "\n"
    "  INPUT            GPX 1.1 track (<trkpt> with <ele>) or CSV distance_m,elevation_m\n"
    "  --spacing-m S    grade sample spacing, 1 to 250 m (default 10)\n"
    "  --smooth-m W     least-squares window for the grade, S to 20000 m (default 400)\n"
    "  --elevation-out  also write distance_m,elevation_m,road_elevation_m per sample\n"
    "  --out ROAD.csv   the road profile\n"
    "  -h, --help       this help\n"
    "\n"
    "INPUT is GPX when its first character is '<', else a CSV of\n"
    "\"distance_m,elevation_m\". ROAD.csv gets the grade every S metres (default\n"
    "10) as the least-squares slope of the elevations within W / 2 of each\n"
    "sample's middle (default 400 m): GNSS or DEM elevation noise would otherwise\n"
    "become grades of +-10 % and more. It carries comment lines naming the input,\n"
    "its points, the duplicates dropped and the smoothing. With --elevation-out,\n"
    "FILE.csv gets \"distance_m,elevation_m,road_elevation_m\" at each sample's\n"
    "start: the input's elevation (linear between points) and the elevation the\n"
    "road's grades add up to, from the first sample's least-squares line at 0 m.\n"
    "Duplicated points are dropped and counted; a track without elevations, of\n"
    "one point, or with a non-numeric field is refused with its line.\n"
    "\n"
    "Exit status: 0, 2 on bad arguments or input (the message names the file,\n"
    "the line and the reason), nothing written then.\n"
    "\n"
    "Example:\n"
    "  roadimport track.gpx --out road.csv --elevation-out elevation.csv\n";

static void usage(FILE *f)
{
    /* --help: the whole manual; a usage error: its synopsis. */
    if (f == stdout) {
        cli_help(k_manual);
    } else {
        cli_usage(f, k_manual, "roadimport");
    }
}

static double elevation_at(const road_track_t *t, double x)
{
    if (x <= t->distance_m[0]) {
        return t->elevation_m[0];
    }
    size_t lo = 0U, hi = t->n - 1U;
    if (x >= t->distance_m[hi]) {
        return t->elevation_m[hi];
    }
    while (hi - lo > 1U) {
        const size_t mid = (lo + hi) / 2U;
        if (t->distance_m[mid] <= x) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    const double f = (x - t->distance_m[lo]) / (t->distance_m[hi] - t->distance_m[lo]);
    return t->elevation_m[lo] + (f * (t->elevation_m[hi] - t->elevation_m[lo]));
}

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return (s != NULL) ? s + 1 : path;
}

int main(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *elev_out = NULL;
    double spacing = 10.0, smooth = ROAD_IMPORT_DEFAULT_SMOOTH_M;
    if (cli_help_asked(argc, argv)) {
        usage(stdout);
        return 0;
    }
    const cli_option_t opts[] = {
        {"--out", CLI_TEXT, 0.0, 0.0, &out, NULL},
        {"--elevation-out", CLI_TEXT, 0.0, 0.0, &elev_out, NULL},
        {"--spacing-m", CLI_DOUBLE, 1.0, 250.0, &spacing, NULL},
        {"--smooth-m", CLI_DOUBLE, 1.0, 20000.0, &smooth, NULL},
    };
    int n_in = 0;
    if (cli_parse_options("roadimport", argc, argv, 1, opts, sizeof opts / sizeof opts[0], &in, 1,
                          &n_in) != 0) {
        usage(stderr);
        return 2;
    }
    if ((in == NULL) || (out == NULL)) {
        fprintf(stderr, "roadimport: give an INPUT and --out ROAD.csv\n");
        usage(stderr);
        return 2;
    }
    if (smooth < spacing) {
        fprintf(stderr, "roadimport: --smooth-m %g is below --spacing-m %g\n", smooth, spacing);
        return 2;
    }
    char err[512] = "";
    road_track_t t;
    if (road_import_load(in, &t, err, sizeof err) != 0) {
        fprintf(stderr, "roadimport: %s\n", err);
        return 2;
    }
    double *g = NULL;
    size_t n = 0U;
    if (road_import_grade(&t, spacing, smooth, &g, &n, err, sizeof err) != 0) {
        fprintf(stderr, "roadimport: %s: %s\n", in, err + strlen("road_import: "));
        road_import_free(&t);
        return 2;
    }
    FILE *f = fopen(out, "w");
    if (f == NULL) {
        fprintf(stderr, "roadimport: cannot write %s: %s\n", out, strerror(errno));
        free(g);
        road_import_free(&t);
        return 2;
    }
    const double length = t.distance_m[t.n - 1U];
    fprintf(f, "# Road imported by roadimport (sim_host/lib/road_import.h) from %s:\n", base_name(in));
    fprintf(f, "# %zu points (%zu at the place of the one before dropped), %.1f m; grade: least-squares\n",
            t.n, t.duplicates, length);
    fprintf(f, "# slope of the elevations within %.0f m of each sample's middle; %zu samples, %g m apart.\n",
            smooth / 2.0, n, spacing);
    fprintf(f, "distance_m,grade_percent\n");
    double lo = 0.0, hi = 0.0;
    for (size_t k = 0U; k < n; k++) {
        fprintf(f, "%.3f,%.3f\n", (double)k * spacing, g[k]);
        lo = (k == 0U) ? g[k] : fmin(lo, g[k]);
        hi = (k == 0U) ? g[k] : fmax(hi, g[k]);
    }
    int rc = (ferror(f) != 0) ? 2 : 0;
    if ((fclose(f) != 0) || (rc != 0)) {
        fprintf(stderr, "roadimport: write error on %s\n", out);
        rc = 2;
    }
    if ((rc == 0) && (elev_out != NULL)) {
        FILE *e = fopen(elev_out, "w");
        if (e == NULL) {
            fprintf(stderr, "roadimport: cannot write %s: %s\n", elev_out, strerror(errno));
            rc = 2;
        } else {
            fprintf(e, "distance_m,elevation_m,road_elevation_m\n");
            /* from the first sample's least-squares line at 0, not from the first (noisy) point */
            double sx = 0.0, sy = 0.0, cnt = 0.0;
            for (size_t k = 0U; (k < t.n) && (t.distance_m[k] <= (spacing / 2.0) + (smooth / 2.0)); k++) {
                sx += t.distance_m[k];
                sy += t.elevation_m[k];
                cnt += 1.0;
            }
            double h = (cnt > 0.0) ? ((sy / cnt) - ((g[0] / 100.0) * (sx / cnt))) : t.elevation_m[0];
            for (size_t k = 0U; k <= n; k++) {
                const double x = (double)k * spacing;
                fprintf(e, "%.1f,%.2f,%.2f\n", x, elevation_at(&t, x), h);
                h += (k < n) ? (g[k] * spacing / 100.0) : 0.0;
            }
            if ((ferror(e) != 0) || (fclose(e) != 0)) {
                fprintf(stderr, "roadimport: write error on %s\n", elev_out);
                rc = 2;
            }
        }
    }
    if (rc == 0) {
        printf("roadimport: %s: %zu points (%zu duplicates dropped), %.1f m -> %s: %zu samples of %g m, "
               "grade %.2f to %.2f %% (smoothed over %g m)\n",
               in, t.n, t.duplicates, length, out, n, spacing, lo, hi, smooth);
    }
    free(g);
    road_import_free(&t);
    return rc;
}
