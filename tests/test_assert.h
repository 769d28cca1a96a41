/*
 * test_assert.h - CMocka asserts for orderings, floating-point equality and
 * tolerances that print both sides when they fail (CMocka's assert_true
 * prints only the text of its condition).
 *
 *   ASSERT_LT(a, b)   a <  b          ASSERT_GT(a, b)   a >  b
 *   ASSERT_LE(a, b)   a <= b          ASSERT_GE(a, b)   a >= b
 *   ASSERT_EQ(a, b)   a == b          ASSERT_NE(a, b)   a != b
 *   ASSERT_NEAR(a, b, tol)      |a - b| <= tol, in double
 *   ASSERT_NEAR_LT(a, b, tol)   |a - b| <  tol, in double
 *
 * a and b: any integer or floating type (a pointer, struct or array does not
 * compile). Each is evaluated once. The comparison is C's own operator on
 * the two values with their promoted types, so ASSERT_LE(a, b) passes exactly
 * when `a <= b` is true: the same usual arithmetic conversions, and a NaN
 * compares false. Integer equality: CMocka's assert_int_equal; ASSERT_EQ is
 * for floating point, where an exact value is the point of the test.
 *
 * ASSERT_NEAR and ASSERT_NEAR_LT convert a, b and tol to double (write them
 * with doubles: the warning flags refuse an int64_t or a float); a NaN fails.
 *
 * On failure it prints, e.g.
 *   [ ERROR    ] --- fuel_ul <= limit_ul: fuel_ul = 12, limit_ul = 10
 * then fails the test at the caller's file and line, as fail() does.
 *
 * Include after <cmocka.h>. Prints through CMocka's print_error with %lld,
 * %llu and %.17g only (the Cortex-M4's newlib has no %jd).
 */
#ifndef PFE_TEST_ASSERT_H
#define PFE_TEST_ASSERT_H

#include <stdbool.h>
#include <stdint.h>

/* One operand's value, kept in the widest type of its kind for printing. */
typedef struct {
    char kind; /* 's' signed, 'u' unsigned, 'd' floating */
    long long s;
    unsigned long long u;
    double d;
} test_value_t;

static inline test_value_t test_value_s_(long long v)
{
    const test_value_t t = {'s', v, 0U, 0.0};
    return t;
}

static inline test_value_t test_value_u_(unsigned long long v)
{
    const test_value_t t = {'u', 0, v, 0.0};
    return t;
}

static inline test_value_t test_value_d_(double v)
{
    const test_value_t t = {'d', 0, 0U, v};
    return t;
}

static inline test_value_t test_value_f_(float v)
{
    return test_value_d_((double)v);
}

static inline test_value_t test_value_ld_(long double v)
{
    return test_value_d_((double)v);
}

/* v has already been promoted (test_cmp_ adds 0): int or wider, or floating. */
#define TEST_VALUE_(v)                                                                      \
    _Generic((v), int: test_value_s_, long: test_value_s_, long long: test_value_s_,       \
             unsigned int: test_value_u_, unsigned long: test_value_u_,                    \
             unsigned long long: test_value_u_, float: test_value_f_, double: test_value_d_, \
             long double: test_value_ld_)(v)

static inline void test_print_value_(const char *text, test_value_t v)
{
    if (v.kind == 's') {
        print_error("%s = %lld", text, v.s);
    } else if (v.kind == 'u') {
        print_error("%s = %llu", text, v.u);
    } else {
        print_error("%s = %.17g", text, v.d);
    }
}

static inline void test_cmp_fail_(const char *a_text, const char *op, const char *b_text,
                                  test_value_t a, test_value_t b, const char *file, int line)
{
    print_error("%s %s %s: ", a_text, op, b_text);
    test_print_value_(a_text, a);
    print_error(", ");
    test_print_value_(b_text, b);
    print_error("\n");
    _fail(file, line);
}

/* Adding 0 promotes as the comparison itself would (bool, char, short, enum
 * to int; a bit-field to its type) and makes an array a pointer, which
 * TEST_VALUE_ then refuses. */
#define TEST_CMP_(a, op, b)                                                                 \
    do {                                                                                    \
        __typeof__((a) + 0) test_a_ = (a);                                                  \
        __typeof__((b) + 0) test_b_ = (b);                                                  \
        if (!(test_a_ op test_b_)) {                                                        \
            test_cmp_fail_(#a, #op, #b, TEST_VALUE_(test_a_), TEST_VALUE_(test_b_), __FILE__, \
                           __LINE__);                                                       \
        }                                                                                   \
    } while (0)

#define ASSERT_LT(a, b) TEST_CMP_(a, <, b)
#define ASSERT_LE(a, b) TEST_CMP_(a, <=, b)
#define ASSERT_GT(a, b) TEST_CMP_(a, >, b)
#define ASSERT_GE(a, b) TEST_CMP_(a, >=, b)
#define ASSERT_EQ(a, b) TEST_CMP_(a, ==, b)
#define ASSERT_NE(a, b) TEST_CMP_(a, !=, b)

static inline void test_near_fail_(const char *a_text, const char *b_text, const char *tol_text,
                                   const char *op, double a, double b, double diff, double tol,
                                   const char *file, int line)
{
    print_error("|%s - %s| %s %s: %s = %.17g, %s = %.17g, |difference| = %.17g, %s = %.17g\n",
                a_text, b_text, op, tol_text, a_text, a, b_text, b, diff, tol_text, tol);
    _fail(file, line);
}

/* |a - b| without <math.h>; a NaN stays a NaN and fails the comparison. */
#define TEST_NEAR_(a, b, tol, op)                                                           \
    do {                                                                                    \
        const double test_a_ = (a);                                                         \
        const double test_b_ = (b);                                                         \
        const double test_t_ = (tol);                                                       \
        const double test_d_ = (test_a_ < test_b_) ? (test_b_ - test_a_) : (test_a_ - test_b_); \
        if (!(test_d_ op test_t_)) {                                                        \
            test_near_fail_(#a, #b, #tol, #op, test_a_, test_b_, test_d_, test_t_, __FILE__,  \
                            __LINE__);                                                      \
        }                                                                                   \
    } while (0)

#define ASSERT_NEAR(a, b, tol) TEST_NEAR_(a, b, tol, <=)
#define ASSERT_NEAR_LT(a, b, tol) TEST_NEAR_(a, b, tol, <)

#endif /* PFE_TEST_ASSERT_H */
