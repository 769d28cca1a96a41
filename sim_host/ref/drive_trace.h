/*
 * drive_trace.h - a time-domain drive from a platoon simulation.
 *
 * Turns the reference object-model run over a road (distance steps) into
 * what the module sees on the bus: speed and grade every 10 ms, the speed
 * quantised to SPN 84's 1/256 km/h and fresh every 100 ms (CCVS1), the grade
 * as the road under the platoon at that instant (SSI every 10 ms).
 */
#ifndef DRIVE_TRACE_H
#define DRIVE_TRACE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "firmware/pfe_calib.h"
#include "firmware/pfe_platoon.h"

typedef struct {
    int32_t speed_mm_s;  /* as decoded from SPN 84 (1/256 km/h), held between samples */
    bool speed_fresh;    /* a CCVS1 sample arrived at this tick */
    int32_t grade_ppm;   /* grade under the platoon */
    double true_speed;   /* m/s, unquantised */
    double position_m;   /* distance driven along the road, interpolated as the speed */
} drive_tick_t;

typedef struct {
    drive_tick_t *ticks; /* one per 10 ms, owned */
    size_t n_ticks;
} drive_trace_t;

/* Simulates the platoon (reference model) over the road and samples it.
 * Returns 0, or -1 with err filled (invalid configuration, stall, memory). */
int drive_trace_make(const int32_t *grade_ppm, uint32_t n_samples, uint32_t spacing_mm,
                     const pfe_platoon_config_t *cfg, int32_t set_speed_mm_s, drive_trace_t *out,
                     char *err, size_t err_len);
void drive_trace_free(drive_trace_t *t);

/* SPN 84 round trip: m/s to the 1/256 km/h raw value (rounded) and back to
 * mm/s (rounded). */
int32_t drive_spn84_quantise_mm_s(double speed_m_s);

/*
 * Reproducible sensor noise for generated drives.
 *
 * A seeded generator whose output depends on nothing but the seed: SplitMix64
 * (Steele, Lea and Flood, "Fast splittable pseudorandom number generators",
 * OOPSLA 2014) for the integers, and an approximately normal deviate made of
 * additions only (Irwin-Hall: the sum of 12 uniforms minus 6), so that no
 * libm function whose last bit may differ between C libraries decides a
 * sample: a drive generated with noise is the same file on every machine.
 * The caller owns the state; all functions are O(1), reentrant on distinct
 * states, and cannot fail.
 */
typedef struct {
    uint64_t state;
} drive_noise_t;

/* Any seed is valid, 0 included. */
void drive_noise_seed(drive_noise_t *n, uint64_t seed);

/* Next SplitMix64 output (seed 0 gives 0xE220A8397B1DCDAF first). */
uint64_t drive_noise_u64(drive_noise_t *n);

/* Uniform in [0, 1): the top 53 bits of the next output times 2^-53. */
double drive_noise_uniform(drive_noise_t *n);

/* Mean 0, standard deviation 1, always within (-6, 6): the sum of the next
 * 12 uniforms minus 6. Its tails are lighter than a normal's beyond about 3
 * standard deviations, which suits a sensor's noise (no wild outliers). */
double drive_noise_gauss(drive_noise_t *n);

#endif /* DRIVE_TRACE_H */
