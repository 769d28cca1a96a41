/*
 * routegen - writes a route profile as road CSV (format in
 * sim_host/lib/road_csv.h): a bundled route or a seeded random one
 * (sim_host/lib/route_gen.h).
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lib/route_gen.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: routegen NAME [--out FILE]\n"
    "\n"
    "Writes a route profile as road CSV.\n"
    "\n"
    "  NAME        a bundled route (the list at the end; sim_host/data/routes/),\n"
    "              or hilly:SEED, the random hilly route\n"
    "              of the fuel bounds' property test with that seed (SEED a\n"
    "              decimal number below 2^64), so that any route the test names\n"
    "              can be looked at and run through the other tools\n"
    "  --out FILE  write to FILE instead of standard output (under a temporary\n"
    "              name, renamed at the end: a failed run leaves no partial file)\n"
    "  -h, --help  this help\n"
    "\n"
    "Exit status: 0 done, 1 write failure, 2 usage error.\n"
    "\n"
    "Example:\n"
    "  routegen hilly:42 --out hilly42.csv\n";

static void usage(FILE *f)
{
    /* --help: the whole manual and the bundled routes; a usage error: its synopsis. */
    if (f != stdout) {
        cli_usage(f, k_manual, "routegen");
        return;
    }
    cli_help(k_manual);
    fprintf(f, "\nbundled routes:");
    for (size_t k = 0U; k < route_named_count; k++) {
        fprintf(f, " %s", route_named[k].name);
    }
    fprintf(f, "\n");
}

int main(int argc, char **argv)
{
    const char *name = NULL;
    const char *out = NULL;
    for (int i = 1; i < argc; i++) {
        if ((strcmp(argv[i], "--out") == 0) && (i + 1 < argc)) {
            out = argv[++i];
        } else if ((strcmp(argv[i], "--help") == 0) || (strcmp(argv[i], "-h") == 0)) {
            usage(stdout);
            return 0;
        } else if ((argv[i][0] != '-') && (name == NULL)) {
            name = argv[i];
        } else {
            fprintf(stderr, "routegen: unexpected argument '%s'\n", argv[i]);
            usage(stderr);
            return 2;
        }
    }
    if (name == NULL) {
        usage(stderr);
        return 2;
    }
    static int32_t grade[ROUTE_MAX_SAMPLES];
    size_t n = 0U;
    int spacing_m = 10;
    char comment[200];
    if (strncmp(name, "hilly:", 6) == 0) {
        const char *s = name + 6;
        char *end = NULL;
        errno = 0;
        const unsigned long long seed = strtoull(s, &end, 10);
        if ((*s < '0') || (*s > '9') || (errno != 0) || (end == s) || (*end != '\0')) {
            fprintf(stderr, "routegen: bad seed in '%s'\n", name);
            return 2;
        }
        route_gen_hilly((uint64_t)seed, grade);
        n = ROUTE_HILLY_SAMPLES;
        spacing_m = ROUTE_HILLY_SPACING_M;
        (void)snprintf(comment, sizeof comment, "Random hilly route, seed %" PRIu64 " (route_gen.h)",
                       (uint64_t)seed);
    } else {
        for (size_t k = 0U; k < route_named_count; k++) {
            if (strcmp(name, route_named[k].name) == 0) {
                n = route_gen_named(name, grade);
                (void)snprintf(comment, sizeof comment, "Route \"%s\": %s", name, route_named[k].what);
            }
        }
        if (n == 0U) {
            fprintf(stderr, "routegen: unknown route '%s'\n", name);
            usage(stderr);
            return 2;
        }
    }
    if (out == NULL) {
        return (route_write_csv(stdout, comment, grade, n, spacing_m) == 0) ? 0 : 1;
    }
    char tmp[4096];
    if (snprintf(tmp, sizeof tmp, "%s.tmp", out) >= (int)sizeof tmp) {
        fprintf(stderr, "routegen: output path too long\n");
        return 2;
    }
    FILE *f = fopen(tmp, "w");
    if (f == NULL) {
        fprintf(stderr, "routegen: cannot write %s: %s\n", tmp, strerror(errno));
        return 1;
    }
    const int rc = route_write_csv(f, comment, grade, n, spacing_m);
    if ((fclose(f) != 0) || (rc != 0) || (rename(tmp, out) != 0)) {
        fprintf(stderr, "routegen: writing %s failed: %s\n", out, strerror(errno));
        (void)remove(tmp);
        return 1;
    }
    return 0;
}
