/* pfe_fixed.c - saturating integer arithmetic (contract in pfe_fixed.h). */
#include "pfe_fixed.h"

int32_t pfe_sat_i32(int64_t x)
{
    if (x > (int64_t)INT32_MAX) {
        return INT32_MAX;
    }
    if (x < (int64_t)INT32_MIN) {
        return INT32_MIN;
    }
    return (int32_t)x;
}

int32_t pfe_clamp_i32(int32_t x, int32_t lo, int32_t hi)
{
    if (x < lo) {
        return lo;
    }
    if (x > hi) {
        return hi;
    }
    return x;
}

int64_t pfe_clamp_i64(int64_t x, int64_t lo, int64_t hi)
{
    if (x < lo) {
        return lo;
    }
    if (x > hi) {
        return hi;
    }
    return x;
}

int64_t pfe_sat_add_i64(int64_t a, int64_t b)
{
    if ((b > 0) && (a > (INT64_MAX - b))) {
        return INT64_MAX;
    }
    if ((b < 0) && (a < (INT64_MIN - b))) {
        return INT64_MIN;
    }
    return a + b;
}

uint64_t pfe_sat_add_u64(uint64_t a, uint64_t b)
{
    return (a > (UINT64_MAX - b)) ? UINT64_MAX : (a + b);
}

uint64_t pfe_udiv_round_u64(uint64_t num, uint64_t den)
{
    if (den == 0U) {
        return 0U;
    }
    const uint64_t q = num / den;
    const uint64_t r = num % den;
    return (r >= (den - r)) ? (q + 1U) : q;
}
