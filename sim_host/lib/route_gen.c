/* route_gen.c - deterministic route profiles (contract in route_gen.h). */
#include "lib/route_gen.h"

#include <string.h>

#define MPCT_PER_FRACTION 100000 /* milli-percent in a grade of 1 (100 %) */

void route_rng_seed(route_rng_t *r, uint64_t seed)
{
    r->state = seed;
}

uint64_t route_rng_next(route_rng_t *r)
{
    r->state += UINT64_C(0x9E3779B97F4A7C15);
    uint64_t z = r->state;
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

int64_t route_rng_range(route_rng_t *r, int64_t lo, int64_t hi)
{
    const uint64_t span = (uint64_t)(hi - lo) + 1U;
    return lo + (int64_t)(((route_rng_next(r) >> 32) * span) >> 32);
}

/* Appends samples, never past n. */
typedef struct {
    int32_t *g;
    size_t i, n;
} track_t;

static void put(track_t *t, int32_t mpct, int64_t length_m, int spacing_m)
{
    const int64_t count = (length_m + (spacing_m / 2)) / spacing_m;
    for (int64_t k = 0; (k < count) && (t->i < t->n); k++) {
        t->g[t->i++] = mpct;
    }
}

/* A vertical curve of radius radius_m from the last grade to target: the
 * grade changes by spacing / radius per sample (at least one sample). */
static void curve(track_t *t, int32_t from, int32_t target, int64_t radius_m, int spacing_m)
{
    const int64_t step = (int64_t)target - from;
    const int64_t abs_step = (step < 0) ? -step : step;
    const int64_t unit = (int64_t)MPCT_PER_FRACTION * spacing_m;
    int64_t count = ((abs_step * radius_m) + (unit / 2)) / unit;
    if (count < 1) {
        count = 1;
    }
    for (int64_t k = 1; (k <= count) && (t->i < t->n); k++) {
        t->g[t->i++] = (int32_t)(from + ((step * k) / count));
    }
}

/* Random hilly: lead-in flat, body, curve back to 0 %, flat run-out. */
static void hilly(uint64_t seed, int32_t *g, size_t n, int spacing_m)
{
    route_rng_t r;
    route_rng_seed(&r, seed);
    track_t t = {g, 0U, n};
    put(&t, 0, 1000, spacing_m);
    /* The body stops early enough for the last curve (at most 4 % at a
     * 15 km radius: 600 m) and the flat run-out. */
    track_t body = {g, t.i, n - (size_t)((ROUTE_HILLY_RUNOUT_M + 600) / spacing_m)};
    const int64_t forced = route_rng_range(&r, 0, 2);
    int32_t grade = 0;
    for (int64_t k = 0; body.i < body.n; k++) {
        int32_t target;
        int64_t length_m;
        if (k == forced) {
            target = (int32_t)route_rng_range(&r, 2000, 4000);
            length_m = route_rng_range(&r, 600, 1500);
        } else {
            const int other_side = route_rng_range(&r, 0, 999) < 800;
            const int up = (grade > 0) ? !other_side : ((grade < 0) ? other_side : (int)route_rng_range(&r, 0, 1));
            target = up ? (int32_t)route_rng_range(&r, 500, 4000) : (int32_t)route_rng_range(&r, -3000, -500);
            length_m = route_rng_range(&r, 200, 1500);
        }
        curve(&body, grade, target, route_rng_range(&r, 4000, 15000), spacing_m);
        grade = target;
        put(&body, grade, length_m, spacing_m);
    }
    t.i = body.i;
    curve(&t, g[t.i - 1U], 0, route_rng_range(&r, 4000, 15000), spacing_m);
    while (t.i < n) {
        g[t.i++] = 0;
    }
}

void route_gen_hilly(uint64_t seed, int32_t grade_mpct[ROUTE_HILLY_SAMPLES])
{
    hilly(seed, grade_mpct, ROUTE_HILLY_SAMPLES, ROUTE_HILLY_SPACING_M);
}

const route_named_t route_named[] = {
    {"ridge", "18 km straight over a ridge: 2 km flat, 3.5 % up for 2.8 km, 3.5 % down for 2.8 km, flat"},
    {"detour", "24 km around the ridge, flat all the way"},
    {"rolling", "21 km of rolling hills, -3 % to +4 % (random hilly route, seed 2013)"},
    {"bypass", "30 km, the long way round the ridge, flat all the way"},
};
const size_t route_named_count = sizeof route_named / sizeof route_named[0];

#define NAMED_SPACING_M 10

size_t route_gen_named(const char *name, int32_t grade_mpct[ROUTE_MAX_SAMPLES])
{
    if (strcmp(name, "ridge") == 0) {
        const size_t n = 1800U;
        track_t t = {grade_mpct, 0U, n};
        put(&t, 0, 2000, NAMED_SPACING_M);
        curve(&t, 0, 3500, 10000, NAMED_SPACING_M);
        put(&t, 3500, 2800, NAMED_SPACING_M);
        curve(&t, 3500, -3500, 10000, NAMED_SPACING_M);
        put(&t, -3500, 2800, NAMED_SPACING_M);
        curve(&t, -3500, 0, 10000, NAMED_SPACING_M);
        while (t.i < n) {
            grade_mpct[t.i++] = 0;
        }
        return n;
    }
    if (strcmp(name, "detour") == 0) {
        const size_t n = 2400U;
        memset(grade_mpct, 0, n * sizeof grade_mpct[0]);
        return n;
    }
    if (strcmp(name, "bypass") == 0) {
        const size_t n = 3000U;
        memset(grade_mpct, 0, n * sizeof grade_mpct[0]);
        return n;
    }
    if (strcmp(name, "rolling") == 0) {
        const size_t n = 2100U;
        hilly(2013U, grade_mpct, n, NAMED_SPACING_M);
        return n;
    }
    return 0U;
}

int route_write_csv(FILE *f, const char *comment, const int32_t *grade_mpct, size_t n, int spacing_m)
{
    int bad = fprintf(f, "# %s\n# Written by routegen (sim_host/tools/routegen.c); every byte is reproducible.\n"
                         "distance_m,grade_percent\n", comment) < 0;
    for (size_t k = 0U; (k < n) && !bad; k++) {
        const int32_t g = grade_mpct[k];
        const int32_t a = (g < 0) ? -g : g;
        bad = fprintf(f, "%lu.000,%s%d.%03d\n", (unsigned long)k * (unsigned long)spacing_m,
                      (g < 0) ? "-" : "", a / 1000, a % 1000) < 0;
    }
    return (bad || (fflush(f) != 0) || ferror(f)) ? -1 : 0;
}
