/*
 * lateness.h - a fixed-size histogram of lateness in microseconds, for the
 * replayer's summary (pfe_replay) and the pacing check of its tests.
 *
 * Values below LATENESS_EXACT_US are counted exactly (one bin per
 * microsecond); larger ones in LATENESS_SUB_BINS bins per power of two, so a
 * percentile above LATENESS_EXACT_US is within 1/LATENESS_SUB_BINS (1.6 %)
 * of the true value, and never above the maximum, which is kept exactly.
 * Values from 2^40 us (12.7 days) up share the last bin.
 *
 * Memory: the struct itself, about 47 KiB (no allocation); every call is
 * O(1) except lateness_percentile_us, O(number of bins). Not reentrant per
 * histogram.
 */
#ifndef LATENESS_H
#define LATENESS_H

#include <stdint.h>

#define LATENESS_EXACT_US 4096U /* 2^12 */
#define LATENESS_SUB_BINS 64U
#define LATENESS_OCTAVES 28U    /* 2^12 .. 2^40 */
#define LATENESS_BINS (LATENESS_EXACT_US + (LATENESS_OCTAVES * LATENESS_SUB_BINS))

typedef struct {
    uint64_t count;
    uint64_t max_us;
    uint64_t sum_us;
    uint64_t bins[LATENESS_BINS];
} lateness_hist_t;

void lateness_init(lateness_hist_t *h);
void lateness_add(lateness_hist_t *h, uint64_t lateness_us);

/* The smallest value v such that at least PERMILLE / 1000 of the samples are
 * <= v (500: median, 990: p99), as the upper end of its bin, capped at the
 * maximum; 0 for an empty histogram. */
uint64_t lateness_percentile_us(const lateness_hist_t *h, unsigned permille);

#endif /* LATENESS_H */
