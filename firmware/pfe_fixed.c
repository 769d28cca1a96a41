/* pfe_fixed.c - saturating integer arithmetic (contract in pfe_fixed.h). */
#include "pfe_fixed.h"

#include <stddef.h>

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

/* Long division by 16-bit digits: each partial dividend r * 2^16 + digit is
 * below den * 2^16 <= 2^32, so every step is a 32-bit division. */
static uint64_t udiv_small(uint64_t num, uint32_t den, uint32_t *rem)
{
    const uint32_t hi = (uint32_t)(num >> 32);
    const uint32_t lo = (uint32_t)num;
    const uint32_t q_hi = hi / den;
    uint32_t r = hi - (q_hi * den);
    const uint32_t d1 = (r << 16) | (lo >> 16);
    const uint32_t q1 = d1 / den;
    r = d1 - (q1 * den);
    const uint32_t d0 = (r << 16) | (lo & 0xFFFFU);
    const uint32_t q0 = d0 / den;
    *rem = d0 - (q0 * den);
    return ((uint64_t)q_hi << 32) | ((uint64_t)q1 << 16) | q0;
}

uint64_t pfe_udiv_u64(uint64_t num, uint64_t den, uint64_t *rem)
{
    uint64_t q = 0U;
    uint64_t r = 0U;
    if ((den != 0U) && (den <= PFE_UDIV_SMALL_MAX)) {
        uint32_t r32;
        q = udiv_small(num, (uint32_t)den, &r32);
        r = r32;
    } else if (den != 0U) {
        q = num / den;
        r = num % den;
    } else {
        /* division by zero: 0, remainder 0, by contract */
    }
    if (rem != NULL) {
        *rem = r;
    }
    return q;
}

uint64_t pfe_udiv_round_u64(uint64_t num, uint64_t den)
{
    if (den == 0U) {
        return 0U;
    }
    uint64_t r;
    const uint64_t q = pfe_udiv_u64(num, den, &r);
    return (r >= (den - r)) ? (q + 1U) : q;
}

uint64_t pfe_mul_shift_round_u64(uint64_t a, uint64_t b, uint32_t shift)
{
    const uint64_t mask = 0xFFFFFFFFU;
    const uint64_t a0 = a & mask;
    const uint64_t a1 = a >> 32;
    const uint64_t b0 = b & mask;
    const uint64_t b1 = b >> 32;
    const uint64_t p00 = a0 * b0;
    const uint64_t p01 = a0 * b1;
    const uint64_t p10 = a1 * b0;
    /* each part below 2^64, their middle sum below 3 * 2^32 */
    const uint64_t mid = (p00 >> 32) + (p01 & mask) + (p10 & mask);
    uint64_t hi = (a1 * b1) + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
    const uint64_t lo = (mid << 32) | (p00 & mask);
    const uint32_t half_bit = shift - 1U;
    const uint64_t half = (uint64_t)1 << half_bit;
    const uint64_t lo_half = lo + half;
    hi += (lo_half < lo) ? 1U : 0U;
    uint64_t q = UINT64_MAX;
    if ((hi >> shift) == 0U) {
        const uint32_t hi_up = 64U - shift;
        q = (lo_half >> shift) | (hi << hi_up);
    }
    return q;
}

int32_t pfe_mantissa_i32(int64_t x, uint32_t min_shift, uint32_t *shift)
{
    const uint64_t mag = (x < 0) ? (0U - (uint64_t)x) : (uint64_t)x;
    uint32_t s = min_shift;
    uint64_t m = mag;
    if (s > 0U) {
        m = pfe_udiv_round_u64(mag, (uint64_t)1 << s);
    }
    while (m >= ((uint64_t)1 << 31)) {
        s++;
        m = pfe_udiv_round_u64(mag, (uint64_t)1 << s);
    }
    *shift = s;
    const int32_t m32 = (int32_t)m;
    return (x < 0) ? -m32 : m32;
}
