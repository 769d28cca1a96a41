/*
 * road2c - turns a road profile CSV into C source for the firmware, with
 * the conversion of road_profile_to_ppm().
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#include "lib/road_csv.h"

#include <inttypes.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "lib/cli_help.h"
#include "lib/out_file.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: road2c NAME CSV OUT.c\n"
    "\n"
    "Turns a road profile CSV into C source for the firmware, which has no file\n"
    "system and embeds its roads as const tables. OUT.c defines, for a profile of\n"
    "N samples:\n"
    "\n"
    "    const int32_t  road_NAME_grade_ppm[N];    grade, 1 % = 10 000 ppm, positive uphill\n"
    "    const uint32_t road_NAME_n_samples;       N\n"
    "    const uint32_t road_NAME_spacing_mm;      distance between samples\n"
    "\n"
    "NAME must be a C identifier. The file is written under a temporary name and\n"
    "renamed, so a failed run leaves no partial file.\n"
    "\n"
    "Exit status: 0 done, 1 bad CSV or write failure (the loader's message on\n"
    "standard error), 2 usage error.\n"
    "\n"
    "Example:\n"
    "  road2c hilly sim_host/data/roads/hilly.csv build/gen/road_hilly.c\n";

#define NAME_MAX_LEN 64u
#define VALUES_PER_LINE 10u

static int is_identifier(const char *s)
{
    const size_t len = strlen(s);
    if (len == 0u || len > NAME_MAX_LEN) {
        return 0;
    }
    for (size_t i = 0; i < len; i++) {
        const char c = s[i];
        const int letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
        const int digit = c >= '0' && c <= '9';
        if (!letter && !(digit && i > 0u)) {
            return 0;
        }
    }
    return 1;
}

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return (slash != NULL) ? slash + 1 : path;
}

typedef struct {
    const char *name;
    const char *csv_path;
    size_t n;
    const int32_t *ppm;
    uint32_t spacing_mm;
} road_source_t;

static int write_source(FILE *out, const void *ctx)
{
    const road_source_t *r = ctx;
    const char *name = r->name;
    const char *csv_path = r->csv_path;
    const size_t n = r->n;
    const int32_t *ppm = r->ppm;
    const uint32_t spacing_mm = r->spacing_mm;
    int bad = 0;
    bad |= fprintf(out,
                   "/*\n"
                   " * Road profile \"%s\" for the firmware, from %s: %zu grade samples\n"
                   " * in parts per million (1 %% = 10000 ppm, positive uphill), one every\n"
                   " * %" PRIu32 " mm. Written by road2c from the CSV: change the CSV, not this file.\n"
                   " */\n"
                   "#include <stdint.h>\n"
                   "\n"
                   "extern const uint32_t road_%s_n_samples;\n"
                   "extern const uint32_t road_%s_spacing_mm;\n"
                   "extern const int32_t road_%s_grade_ppm[%zu];\n"
                   "\n"
                   "const uint32_t road_%s_n_samples = %zuu;\n"
                   "const uint32_t road_%s_spacing_mm = %" PRIu32 "u;\n"
                   "const int32_t road_%s_grade_ppm[%zu] = {\n",
                   name, base_name(csv_path), n, spacing_mm, name, name, name, n, name, n,
                   name, spacing_mm, name, n) < 0;
    for (size_t k = 0; k < n && !bad; k++) {
        const char *sep = (k % VALUES_PER_LINE == 0u) ? "   " : "";
        const char *end = (k + 1u == n || (k + 1u) % VALUES_PER_LINE == 0u) ? ",\n" : ",";
        if (ppm[k] == INT32_MIN) {
            /* -2147483648 would be a negated long constant, not an int. */
            bad |= fprintf(out, "%s (-2147483647 - 1)%s", sep, end) < 0;
        } else {
            bad |= fprintf(out, "%s %8" PRId32 "%s", sep, ppm[k], end) < 0;
        }
    }
    if (!bad) {
        bad |= fputs("};\n", out) == EOF;
    }
    return bad ? -1 : 0;
}

int main(int argc, char **argv)
{
    if (cli_help_asked(argc, argv)) {
        cli_help(k_manual);
        return 0;
    }
    if (argc != 4) {
        cli_usage(stderr, k_manual, "road2c");
        return 2;
    }
    const char *name = argv[1];
    const char *csv_path = argv[2];
    const char *out_path = argv[3];
    if (!is_identifier(name)) {
        fprintf(stderr, "road2c: NAME '%s' is not a C identifier of 1 to %u characters\n",
                name, NAME_MAX_LEN);
        return 2;
    }

    char err[512];
    road_profile_t road;
    if (road_profile_load(csv_path, &road, err, sizeof err) != 0) {
        fprintf(stderr, "road2c: %s\n", err);
        return 1;
    }
    int32_t *ppm = malloc(road.n_samples * sizeof *ppm);
    uint32_t spacing_mm = 0u;
    if (ppm == NULL) {
        fprintf(stderr, "road2c: out of memory\n");
        road_profile_free(&road);
        return 1;
    }
    if (road_profile_to_ppm(&road, ppm, &spacing_mm, err, sizeof err) != 0) {
        fprintf(stderr, "road2c: %s: %s\n", csv_path, err);
        free(ppm);
        road_profile_free(&road);
        return 1;
    }

    const road_source_t src = {name, csv_path, road.n_samples, ppm, spacing_mm};
    const int rc = (out_file_write(out_path, "road2c", write_source, &src) == 0) ? 0 : 1;
    free(ppm);
    road_profile_free(&road);
    return rc;
}
