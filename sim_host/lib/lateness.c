/* lateness.c - lateness histogram (contract in lateness.h). */
#include "lib/lateness.h"

#include <string.h>

void lateness_init(lateness_hist_t *h)
{
    memset(h, 0, sizeof *h);
}

/* Position of the highest set bit of v > 0. */
static unsigned top_bit(uint64_t v)
{
    return 63U - (unsigned)__builtin_clzll(v);
}

static uint32_t bin_of(uint64_t v)
{
    if (v < LATENESS_EXACT_US) {
        return (uint32_t)v;
    }
    const unsigned b = top_bit(v); /* >= 12 */
    if (b >= 12U + LATENESS_OCTAVES) {
        return LATENESS_BINS - 1U;
    }
    const uint64_t sub = (v >> (b - 6U)) & (LATENESS_SUB_BINS - 1U); /* 6 = log2(SUB_BINS) */
    return LATENESS_EXACT_US + ((b - 12U) * LATENESS_SUB_BINS) + (uint32_t)sub;
}

/* Largest value that falls in bin i. */
static uint64_t bin_top(uint32_t i)
{
    if (i < LATENESS_EXACT_US) {
        return i;
    }
    if (i == LATENESS_BINS - 1U) {
        return UINT64_MAX; /* shared by everything from 2^40 up */
    }
    const uint32_t k = i - LATENESS_EXACT_US;
    const unsigned b = 12U + (k / LATENESS_SUB_BINS);
    const uint64_t sub = k % LATENESS_SUB_BINS;
    const uint64_t lo = ((uint64_t)1U << b) + (sub << (b - 6U));
    return lo + ((uint64_t)1U << (b - 6U)) - 1U;
}

void lateness_add(lateness_hist_t *h, uint64_t lateness_us)
{
    h->bins[bin_of(lateness_us)]++;
    h->count++;
    h->sum_us += lateness_us;
    if (lateness_us > h->max_us) {
        h->max_us = lateness_us;
    }
}

uint64_t lateness_percentile_us(const lateness_hist_t *h, unsigned permille)
{
    if (h->count == 0U) {
        return 0U;
    }
    if (permille > 1000U) {
        permille = 1000U;
    }
    /* rank = ceil(count * permille / 1000), at least 1 */
    uint64_t rank = ((h->count * permille) + 999U) / 1000U;
    if (rank == 0U) {
        rank = 1U;
    }
    uint64_t seen = 0U;
    for (uint32_t i = 0U; i < LATENESS_BINS; i++) {
        seen += h->bins[i];
        if (seen >= rank) {
            const uint64_t top = bin_top(i);
            return (top < h->max_us) ? top : h->max_us;
        }
    }
    return h->max_us;
}
