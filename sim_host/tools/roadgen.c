/*
 * roadgen - writes the thesis's three test roads as road profile CSV
 * (format in sim_host/lib/road_csv.h). hilly is built the way a motorway's
 * vertical alignment is designed: constant-grade tangents joined by
 * parabolic vertical curves (rate 1/R for a curve of radius R), from a
 * fixed-seed integer generator, all in integer arithmetic, then scaled to
 * span exactly -3 % to +4 % and checked (hilly_check()).
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: roadgen NAME [--out FILE]\n"
    "\n"
    "Writes one of the thesis's three test roads as road profile CSV\n"
    "(distance_m,grade_percent).\n"
    "\n"
    "  NAME        flat (0 %), uphill (a constant 2 % upgrade) or hilly\n"
    "              (synthetic, -3 % to +4 %): 1000 samples at 12 m (0 to 11988 m),\n"
    "              as in thesis section 6.1\n"
    "  --out FILE  write to FILE instead of standard output (under a temporary\n"
    "              name, renamed at the end: a failed run leaves no partial file)\n"
    "  -h, --help  this help\n"
    "\n"
    "The thesis's third road is a measured E4 profile between -3 % and +4 % whose\n"
    "data is not public; hilly is a synthetic stand-in with the same grade range,\n"
    "drawn the way a motorway's vertical alignment is designed (constant-grade\n"
    "stretches joined by vertical curves) by a fixed-seed integer generator, so\n"
    "the output is byte-identical on every machine; sim_host/data/roads/README.md\n"
    "describes it.\n"
    "\n"
    "Exit status: 0 done, 1 write failure or failed check, 2 usage error.\n"
    "\n"
    "Example:\n"
    "  roadgen hilly --out hilly.csv\n";

#define N_SAMPLES 1000
#define SPACING_M 12

/* Grades inside the generator are integers in micro-percent (1e-6 %). */
#define UPCT_PER_PCT INT64_C(1000000)
/* Grades written out are integers in milli-percent (1e-3 %), printed "%.3f". */
#define MPCT_PER_PCT 1000

/* hilly: the final grade range, in milli-percent. */
#define HILLY_MIN_MPCT (-3000)
#define HILLY_MAX_MPCT 4000

/* hilly: generator parameters (before the final scaling). */
/* Of seeds 1 to 20, 17 give a road that passes hilly_check(); 9 is the one
 * whose end lies closest to the height of its start (9 m higher), as on a
 * long through road rather than a climb out of a valley. */
#define HILLY_SEED UINT64_C(9)
#define TANGENT_MIN_M 180           /* constant-grade stretch, shortest */
#define TANGENT_MAX_M 1300          /* ... and longest */
#define RADIUS_MIN_M 6000           /* vertical curve radius, smallest */
#define RADIUS_MAX_M 14000          /* ... and largest */
#define UPGRADE_MIN_UPCT 500000     /* an upgrade tangent: +0.5 % ... */
#define UPGRADE_MAX_UPCT 4500000    /* ... to +4.5 % */
#define DOWNGRADE_MIN_UPCT -3500000 /* a downgrade tangent: -3.5 % ... */
#define DOWNGRADE_MAX_UPCT -500000  /* ... to -0.5 % */
#define SAME_SIDE_PER_MILLE 200     /* chance that an upgrade follows an upgrade, etc. */
#define MIN_STEP_UPCT 1000000       /* consecutive tangents differ by 1 % or more */

/* hilly: properties checked on the final profile. */
#define CHECK_LONG_GRADE_MPCT 2000  /* a long upgrade of at least 2 % ... */
#define CHECK_LONG_LEN_M 1000       /* ... lasting at least 1 km */
#define CHECK_MAX_STEP_MPCT 250     /* grade change per sample: radius >= 4.8 km */
#define CHECK_MIN_CRESTS 3          /* at least this many hill tops */

/* 64-bit linear congruential generator (Knuth's MMIX constants); the upper
 * 32 bits of the state are the output, as its low bits have short periods. */
typedef struct {
    uint64_t state;
} prng_t;

static uint32_t prng_next(prng_t *p)
{
    p->state = p->state * UINT64_C(6364136223846793005) + UINT64_C(1442695040888963407);
    return (uint32_t)(p->state >> 32);
}

/* Uniform integer in [lo, hi], hi - lo < 2^32. */
static int64_t prng_range(prng_t *p, int64_t lo, int64_t hi)
{
    const uint64_t span = (uint64_t)(hi - lo) + 1u;
    return lo + (int64_t)(((uint64_t)prng_next(p) * span) >> 32);
}

/* Draws the grade of the next tangent: usually on the other side of zero
 * (a crest follows an upgrade, a sag a downgrade), and never within
 * MIN_STEP_UPCT of the current one. */
static int64_t next_tangent_grade(prng_t *p, int64_t g_upct)
{
    const int64_t same_side = prng_range(p, 0, 999) < SAME_SIDE_PER_MILLE;
    const int up = (g_upct >= 0) ? (int)same_side : (int)!same_side;
    for (;;) {
        const int64_t t = up ? prng_range(p, UPGRADE_MIN_UPCT, UPGRADE_MAX_UPCT)
                             : prng_range(p, DOWNGRADE_MIN_UPCT, DOWNGRADE_MAX_UPCT);
        const int64_t step = (t > g_upct) ? t - g_upct : g_upct - t;
        if (step >= MIN_STEP_UPCT) {
            return t;
        }
    }
}

/* Fills raw[] (micro-percent) with tangents and vertical curves. */
static void hilly_raw(int64_t raw[N_SAMPLES])
{
    prng_t p = {HILLY_SEED};
    int64_t g = prng_range(&p, -UPCT_PER_PCT / 2, UPCT_PER_PCT / 2);
    int i = 0;
    while (i < N_SAMPLES) {
        const int64_t tangent = prng_range(&p, TANGENT_MIN_M / SPACING_M, TANGENT_MAX_M / SPACING_M);
        for (int64_t k = 0; k < tangent && i < N_SAMPLES; k++) {
            raw[i++] = g;
        }
        const int64_t target = next_tangent_grade(&p, g);
        const int64_t radius_m = prng_range(&p, RADIUS_MIN_M, RADIUS_MAX_M);
        const int64_t step = target - g;
        const int64_t abs_step = (step < 0) ? -step : step;
        /* Curve length = R * (grade change as a fraction); in samples, rounded. */
        const int64_t len_m_x_upct = abs_step * radius_m;            /* m * 1e-6 % */
        const int64_t unit = 100 * UPCT_PER_PCT * SPACING_M;          /* one sample */
        int64_t curve = (len_m_x_upct + unit / 2) / unit;
        if (curve < 2) {
            curve = 2;
        }
        for (int64_t k = 1; k <= curve && i < N_SAMPLES; k++) {
            raw[i++] = g + step * k / curve;
        }
        g = target;
    }
}

/* Scales raw[] linearly onto [HILLY_MIN_MPCT, HILLY_MAX_MPCT], rounding to
 * the nearest milli-percent; the raw minimum and maximum land exactly on the
 * ends. */
static void hilly_scale(const int64_t raw[N_SAMPLES], int32_t mpct[N_SAMPLES])
{
    int64_t lo = raw[0];
    int64_t hi = raw[0];
    for (int i = 1; i < N_SAMPLES; i++) {
        lo = (raw[i] < lo) ? raw[i] : lo;
        hi = (raw[i] > hi) ? raw[i] : hi;
    }
    const int64_t span_in = hi - lo;             /* > 0: tangents differ by >= 1 % */
    const int64_t span_out = HILLY_MAX_MPCT - HILLY_MIN_MPCT;
    for (int i = 0; i < N_SAMPLES; i++) {
        const int64_t num = (raw[i] - lo) * span_out;   /* >= 0, so rounding is simple */
        mpct[i] = (int32_t)(HILLY_MIN_MPCT + (num + span_in / 2) / span_in);
    }
}

/* Checks the properties hilly is meant to have; prints the first failure. */
static int hilly_check(const int32_t mpct[N_SAMPLES])
{
    int32_t lo = mpct[0];
    int32_t hi = mpct[0];
    int run = 0;
    int longest = 0;
    int crests = 0;
    for (int i = 0; i < N_SAMPLES; i++) {
        lo = (mpct[i] < lo) ? mpct[i] : lo;
        hi = (mpct[i] > hi) ? mpct[i] : hi;
        run = (mpct[i] >= CHECK_LONG_GRADE_MPCT) ? run + 1 : 0;
        longest = (run > longest) ? run : longest;
        if (i > 0) {
            const int32_t d = mpct[i] - mpct[i - 1];
            if (d > CHECK_MAX_STEP_MPCT || d < -CHECK_MAX_STEP_MPCT) {
                fprintf(stderr, "roadgen: hilly: grade changes by %d m%% at sample %d\n", d, i);
                return -1;
            }
            crests += (mpct[i - 1] > 0 && mpct[i] <= 0) ? 1 : 0;
        }
    }
    if (lo != HILLY_MIN_MPCT || hi != HILLY_MAX_MPCT) {
        fprintf(stderr, "roadgen: hilly: range %d..%d m%%\n", lo, hi);
        return -1;
    }
    if (longest * SPACING_M < CHECK_LONG_LEN_M) {
        fprintf(stderr, "roadgen: hilly: longest upgrade of 2 %% or more is %d m\n",
                longest * SPACING_M);
        return -1;
    }
    if (crests < CHECK_MIN_CRESTS) {
        fprintf(stderr, "roadgen: hilly: only %d hill tops\n", crests);
        return -1;
    }
    return 0;
}

typedef struct {
    const char *name;
    const char *description;   /* comment lines, each starting "# " */
} road_def_t;

static const road_def_t ROADS[] = {
    {"flat",
     "# Road profile \"flat\": synthetic, 0 % grade throughout; the thesis's flat\n"
     "# test road (section 6.1), which is defined rather than measured.\n"},
    {"uphill",
     "# Road profile \"uphill\": synthetic, a constant 2 % upgrade throughout; the\n"
     "# thesis's uphill test road (section 6.1.1), defined rather than measured.\n"},
    {"hilly",
     "# Road profile \"hilly\": synthetic, NOT measured. It stands in for the\n"
     "# thesis's real E4 road profile (grade between -3 % and +4 %), whose data is\n"
     "# not public. Constant-grade stretches joined by vertical curves (radius\n"
     "# about 6 to 15 km), drawn from a fixed-seed integer generator, then scaled\n"
     "# linearly to span exactly -3 % to +4 %. Deterministic: the same bytes on\n"
     "# every machine.\n"},
};
#define N_ROADS (sizeof ROADS / sizeof ROADS[0])

static int write_road(FILE *out, const road_def_t *road, const int32_t mpct[N_SAMPLES])
{
    if (fputs(road->description, out) == EOF) {
        return -1;
    }
    if (fprintf(out,
                "# Generated by: roadgen %s (sim_host/tools/roadgen.c).\n"
                "# The thesis's real E4 road profile is not public.\n"
                "# %d samples, %d m apart (0 to %d m); grade in percent, positive uphill.\n"
                "distance_m,grade_percent\n",
                road->name, N_SAMPLES, SPACING_M, (N_SAMPLES - 1) * SPACING_M) < 0) {
        return -1;
    }
    for (int i = 0; i < N_SAMPLES; i++) {
        /* Both values are exact multiples of 1e-3, so "%.3f" prints them exactly. */
        const double distance_m = (double)(i * SPACING_M);
        const double grade_pct = (double)mpct[i] / (double)MPCT_PER_PCT;
        if (fprintf(out, "%.3f,%.3f\n", distance_m, grade_pct) < 0) {
            return -1;
        }
    }
    return 0;
}

static void usage(FILE *to)
{
    /* --help: the whole manual; a usage error: its synopsis. */
    if (to == stdout) {
        cli_help(k_manual);
    } else {
        cli_usage(to, k_manual, "roadgen");
    }
}

int main(int argc, char **argv)
{
    const char *name = NULL;
    const char *out_path = NULL;
    for (int a = 1; a < argc; a++) {
        if (strcmp(argv[a], "-h") == 0 || strcmp(argv[a], "--help") == 0) {
            usage(stdout);
            return 0;
        }
        if (strcmp(argv[a], "--out") == 0) {
            if (a + 1 >= argc || out_path != NULL) {
                usage(stderr);
                return 2;
            }
            out_path = argv[++a];
        } else if (argv[a][0] == '-' || name != NULL) {
            usage(stderr);
            return 2;
        } else {
            name = argv[a];
        }
    }
    if (name == NULL) {
        usage(stderr);
        return 2;
    }

    const road_def_t *road = NULL;
    for (size_t r = 0; r < N_ROADS; r++) {
        if (strcmp(name, ROADS[r].name) == 0) {
            road = &ROADS[r];
        }
    }
    if (road == NULL) {
        fprintf(stderr, "roadgen: unknown road '%s' (flat, uphill, hilly)\n", name);
        return 2;
    }

    static int32_t mpct[N_SAMPLES];
    if (strcmp(road->name, "flat") == 0) {
        for (int i = 0; i < N_SAMPLES; i++) {
            mpct[i] = 0;
        }
    } else if (strcmp(road->name, "uphill") == 0) {
        for (int i = 0; i < N_SAMPLES; i++) {
            mpct[i] = 2 * MPCT_PER_PCT;
        }
    } else {
        static int64_t raw[N_SAMPLES];
        hilly_raw(raw);
        hilly_scale(raw, mpct);
        if (hilly_check(mpct) != 0) {
            return 1;
        }
    }

    if (out_path == NULL) {
        if (write_road(stdout, road, mpct) != 0 || fflush(stdout) != 0) {
            fprintf(stderr, "roadgen: write to stdout failed\n");
            return 1;
        }
        return 0;
    }

    const size_t len = strlen(out_path);
    char *tmp_path = malloc(len + sizeof ".tmp");
    if (tmp_path == NULL) {
        fprintf(stderr, "roadgen: out of memory\n");
        return 1;
    }
    memcpy(tmp_path, out_path, len);
    memcpy(tmp_path + len, ".tmp", sizeof ".tmp");
    FILE *out = fopen(tmp_path, "wb");
    if (out == NULL) {
        perror(tmp_path);
        free(tmp_path);
        return 1;
    }
    int bad = write_road(out, road, mpct) != 0;
    bad |= fclose(out) != 0;
    if (bad || rename(tmp_path, out_path) != 0) {
        fprintf(stderr, "roadgen: cannot write %s\n", out_path);
        (void)remove(tmp_path);
        free(tmp_path);
        return 1;
    }
    free(tmp_path);
    return 0;
}
