/*
 * route_gen.h - deterministic route profiles: seeded random hilly routes for
 * the fuel-bound property test, and the bundled routes of sim_host/data/routes/.
 *
 * Every route is integer arithmetic only (grades in milli-percent, lengths
 * in whole metres, a 64-bit generator), so any machine produces the same
 * samples and the same CSV bytes.
 *
 * Random hilly route (route_gen_hilly), built the way a motorway's vertical
 * alignment is: constant-grade stretches joined by vertical curves over
 * which the grade changes linearly with distance. From one seed:
 *
 *   0 .. 1000 m            flat (0 %): the platoon starts at its set speed
 *   1000 m .. body end     stretches of 200 .. 1500 m at grades drawn from
 *                          -3.0 .. +4.0 % (the thesis's real road's range),
 *                          each on the other side of 0 % from the last with
 *                          probability 0.8, joined by curves of radius
 *                          4 .. 15 km; one of the first three stretches is an
 *                          upgrade of +2.0 .. +4.0 % over 600 .. 1500 m,
 *                          which the default platoon cannot climb at 90 km/h
 *   body end .. end        a curve back to 0 % and flat road for at least
 *                          2500 m, so that the platoon is back at its set
 *                          speed when the route ends
 *
 * These are the thesis's two assumptions for its bounds (5.1.2): at least
 * one upgrade, and the same speed at the start and the end. The generator
 * makes them hold by construction; the test that uses the routes checks
 * them on each run and reports any route where they do not hold.
 *
 * Generator: SplitMix64 (Steele, Lea and Flood 2014): state += 0x9E3779B97F4A7C15,
 * then two xor-shift-multiply rounds; integers in a range by the top 32 bits
 * times the span, shifted down 32 (no modulo bias worth the name for spans
 * below 2^16).
 */
#ifndef ROUTE_GEN_H
#define ROUTE_GEN_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef struct {
    uint64_t state;
} route_rng_t;

void route_rng_seed(route_rng_t *r, uint64_t seed);
uint64_t route_rng_next(route_rng_t *r);
/* Uniform in [lo, hi]; hi - lo < 2^32. */
int64_t route_rng_range(route_rng_t *r, int64_t lo, int64_t hi);

/* Random hilly routes: 12 km at 10 m (1200 samples). */
#define ROUTE_HILLY_SPACING_M 10
#define ROUTE_HILLY_SAMPLES 1200U
#define ROUTE_HILLY_RUNOUT_M 2500 /* flat at the end, at least */

/* Fills grade_mpct[0 .. ROUTE_HILLY_SAMPLES - 1] (milli-percent) from seed. */
void route_gen_hilly(uint64_t seed, int32_t grade_mpct[ROUTE_HILLY_SAMPLES]);

/* The bundled routes (sim_host/data/routes/README.md), 10 m samples. */
#define ROUTE_MAX_SAMPLES 4000U
typedef struct {
    const char *name;
    const char *what;        /* one line, written into the CSV's header comment */
} route_named_t;
extern const route_named_t route_named[];
extern const size_t route_named_count;

/* Fills grade_mpct with the named route; returns its number of samples, or
 * 0 for an unknown name. grade_mpct must hold ROUTE_MAX_SAMPLES. */
size_t route_gen_named(const char *name, int32_t grade_mpct[ROUTE_MAX_SAMPLES]);

/* Writes a road CSV (road_csv.h format): comment lines, the header, then
 * "%d.000,%d.%03d" rows. Returns 0 or -1 (write error). */
int route_write_csv(FILE *f, const char *comment, const int32_t *grade_mpct, size_t n,
                    int spacing_m);

#endif /* ROUTE_GEN_H */
