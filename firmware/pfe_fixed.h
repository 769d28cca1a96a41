/*
 * pfe_fixed.h - saturating integer arithmetic shared by the model.
 *
 * The module has no floating point. Every quantity is an integer in a unit
 * named in its identifier (speed_mm_s, force_n, ...) or a binary-scaled
 * coefficient named with its shift (_q32: value * 2^32). These helpers are the
 * only places where a wide result is narrowed, so that narrowing always
 * saturates and never wraps.
 *
 * All functions are reentrant, O(1), use no memory beyond the stack and
 * their outputs, and have no side effect but pfe_udiv_u64()'s remainder.
 */
#ifndef PFE_FIXED_H
#define PFE_FIXED_H

#include <stdint.h>

/* Error codes: functions that can fail return 0 or one of these (negative). */
#define PFE_OK 0
#define PFE_EINVAL (-22) /* an argument or calibration is out of its range */

/* Clamps x to [INT32_MIN, INT32_MAX]. */
int32_t pfe_sat_i32(int64_t x);

/* Clamps x to [lo, hi]; requires lo <= hi. */
int32_t pfe_clamp_i32(int32_t x, int32_t lo, int32_t hi);
int64_t pfe_clamp_i64(int64_t x, int64_t lo, int64_t hi);

/* a + b, saturated to [INT64_MIN, INT64_MAX]. */
int64_t pfe_sat_add_i64(int64_t a, int64_t b);

/* a + b for unsigned 64-bit, saturated at UINT64_MAX. */
uint64_t pfe_sat_add_u64(uint64_t a, uint64_t b);

/* Forces a function inline where the compiler can (GCC, Clang): for a hot
 * function whose calls pass constants that fold away once inlined.
 * PFE_NO_FORCE_INLINE leaves the choice to the compiler: the coverage build
 * (mk/hardening.mk) defines it, so that such a function's branches count
 * once, not once per call site, where its constant arguments make one
 * direction of a branch impossible. */
#if defined(__GNUC__) && !defined(PFE_NO_FORCE_INLINE)
#define PFE_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define PFE_ALWAYS_INLINE inline
#endif

/* Inlines every call in a function's body where the compiler can (GCC,
 * Clang): for the 10 ms estimator step, whose calls (the speed filter, the
 * grade split, the clamps) would otherwise each pay their call and register
 * saves every tick. PFE_NO_FORCE_INLINE leaves the choice to the compiler,
 * as for PFE_ALWAYS_INLINE. */
#if defined(__GNUC__) && !defined(PFE_NO_FORCE_INLINE)
#define PFE_FLATTEN __attribute__((flatten))
#else
#define PFE_FLATTEN
#endif

/*
 * x / 2^shift rounded to nearest (halves toward plus infinity),
 * 1 <= shift <= 62, for |x| < 2^62 (every caller states its bound).
 * These two run in every model step, so they are inline: a call would cost
 * more than the arithmetic on the Cortex-M4. Right shift of a negative value
 * is arithmetic on every compiler this project supports (GCC, Clang:
 * documented implementation-defined behaviour); a unit test pins it.
 */
static inline int64_t pfe_rshift_round(int64_t x, uint32_t shift)
{
    return (x + ((int64_t)1 << (shift - 1U))) >> shift;
}

/* (a * b) / 2^shift rounded to nearest, for |a * b| < 2^62. */
static inline int64_t pfe_mul_q(int64_t a, int32_t b, uint32_t shift)
{
    return pfe_rshift_round(a * (int64_t)b, shift);
}

/*
 * a * b / 2^32 rounded to nearest (halves up): exactly
 * pfe_rshift_round((int64_t)a * b, 32U), for any a and b; the result lies
 * within [-2^30, 2^30]. On a core with the DSP extension (the Cortex-M4:
 * __ARM_FEATURE_DSP) one instruction, SMMULR (ARMv7-M Architecture
 * Reference Manual: the most significant word of the product, rounded by
 * adding 0x80000000 first); elsewhere the 64-bit product and its rounding. The
 * simulation's step makes most of its products with it (pfe_sim.c).
 */
static inline int32_t pfe_mulhr_i32(int32_t a, int32_t b)
{
#if defined(__GNUC__) && defined(__ARM_FEATURE_DSP)
    int32_t r;
    __asm__("smmulr %0, %1, %2" : "=r"(r) : "r"(a), "r"(b));
    return r;
#else
    return (int32_t)pfe_rshift_round((int64_t)a * b, 32U);
#endif
}

/*
 * x as m * 2^shift with |m| < 2^31, for a coefficient to be multiplied 32 x
 * 32 -> 64 bits in a step: the smallest shift >= min_shift, m = x / 2^shift
 * rounded to nearest (|x| halves up, the sign kept), so m = x exactly when
 * the shift is 0 or x's low shift bits are 0. |x| < 2^62, min_shift <= 31.
 * Configuration time only (a loop over the shifts).
 */
int32_t pfe_mantissa_i32(int64_t x, uint32_t min_shift, uint32_t *shift);

/*
 * a * b / 2^shift rounded to nearest (halves up), 1 <= shift <= 63, from the
 * exact 128-bit product (four 32 x 32 -> 64 bit multiplies); saturates at
 * UINT64_MAX. For sums turned into results once per call, not per step.
 */
uint64_t pfe_mul_shift_round_u64(uint64_t a, uint64_t b, uint32_t shift);

/*
 * num / den rounded down (truncated), any num; *rem (may be NULL) receives
 * num % den. 0 and remainder 0 when den is 0. Exact for every input.
 * Cost: for den <= PFE_UDIV_SMALL_MAX, three 32-bit divisions (long division
 * by 16-bit digits; the Cortex-M4 divides 32 by 32 bits in one instruction):
 * about 25 instructions with the call. Above, one 64-bit division, a
 * library call on the Cortex-M4 (__aeabi_uldivmod): 60 to 80 instructions
 * for a divisor of 1000 (measured under QEMU -icount). For a constant den
 * above the limit, divide twice by factors of it:
 * floor(floor(n / a) / b) = floor(n / (a b)).
 */
#define PFE_UDIV_SMALL_MAX 0xFFFFU
uint64_t pfe_udiv_u64(uint64_t num, uint64_t den, uint64_t *rem);

/*
 * num / den rounded to nearest (halves up), any num, den > 0 (0 when den
 * is 0). Never overflows: the quotient is at most num. Cost as
 * pfe_udiv_u64(): cheap for den <= PFE_UDIV_SMALL_MAX, a 64-bit division
 * above (init-time scaling).
 */
uint64_t pfe_udiv_round_u64(uint64_t num, uint64_t den);

#endif /* PFE_FIXED_H */
