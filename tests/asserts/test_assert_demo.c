/*
 * The asserts of tests/test_assert.h against C's own comparisons.
 *
 *   test_assert_demo pass   every assert holds: exit 0
 *   test_assert_demo fail   each test fails once: exit = number of tests,
 *                           and tests/asserts/check_asserts_test.sh checks
 *                           the values each one printed
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

static int g_calls;

static int counted(int v)
{
    g_calls++;
    return v;
}

/* The same answers as the operators, types and promotions included. */
static void test_same_as_the_operators(void **state)
{
    (void)state;
    ASSERT_LE(3, 3);
    ASSERT_LT(-1, 0);
    ASSERT_GT(INT64_MAX, INT64_MAX - 1);
    ASSERT_GT(UINT64_MAX, (uint64_t)INT64_MAX);
    ASSERT_GE(INT64_MIN, INT64_MIN);
    /* Unsigned arithmetic wraps before the comparison, as in C. */
    const uint32_t u = 5U;
    ASSERT_GT(u - 6U, u);
    /* uint8_t operands are promoted to int first: 400, not 144. */
    const uint8_t b = 200U;
    ASSERT_GT(b + b, 255);
    ASSERT_EQ(0.5, 0.5);
    ASSERT_NE(NAN, NAN); /* a NaN is unequal to everything */
    ASSERT_NE(0.1 + 0.2, 0.3);
    ASSERT_NEAR(0.1 + 0.2, 0.3, 1e-15);
    ASSERT_NEAR(1.0, 1.5, 0.5);
    ASSERT_NEAR_LT(1.0, 1.25, 0.5);
    ASSERT_LT(1.0f, 1.5f);
}

static void test_each_operand_evaluated_once(void **state)
{
    (void)state;
    g_calls = 0;
    ASSERT_LE(counted(1), counted(2));
    ASSERT_NEAR(counted(1), 1.0, 0.0);
    assert_int_equal(g_calls, 3);
}

static void test_fails_le_int(void **state)
{
    (void)state;
    const int fuel_ul = 12;
    const int limit_ul = 10;
    ASSERT_LE(fuel_ul, limit_ul);
}

static void test_fails_ge_negative_int64(void **state)
{
    (void)state;
    const int64_t t_us = -5;
    ASSERT_GE(t_us, 0);
}

static void test_fails_lt_uint64(void **state)
{
    (void)state;
    const uint64_t big = UINT64_MAX;
    ASSERT_LT(big, 1U);
}

static void test_fails_gt_double(void **state)
{
    (void)state;
    const double x = 1.25;
    ASSERT_GT(x, 1.5);
}

static void test_fails_eq_double(void **state)
{
    (void)state;
    ASSERT_EQ(0.1 + 0.2, 0.3);
}

static void test_fails_near(void **state)
{
    (void)state;
    const double a = 1.5;
    ASSERT_NEAR(a, 1.0, 0.25);
}

static void test_fails_near_lt_at_the_limit(void **state)
{
    (void)state;
    ASSERT_NEAR_LT(1.0, 1.5, 0.5);
}

static void test_fails_near_nan(void **state)
{
    (void)state;
    const double r = NAN;
    ASSERT_NEAR(r, 0.0, 1.0);
}

static void test_fails_le_nan(void **state)
{
    (void)state;
    const double r = NAN;
    ASSERT_LE(r, 1.0);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest pass[] = {
        cmocka_unit_test(test_same_as_the_operators),
        cmocka_unit_test(test_each_operand_evaluated_once),
    };
    const struct CMUnitTest fail[] = {
        cmocka_unit_test(test_fails_le_int),
        cmocka_unit_test(test_fails_ge_negative_int64),
        cmocka_unit_test(test_fails_lt_uint64),
        cmocka_unit_test(test_fails_gt_double),
        cmocka_unit_test(test_fails_eq_double),
        cmocka_unit_test(test_fails_near),
        cmocka_unit_test(test_fails_near_lt_at_the_limit),
        cmocka_unit_test(test_fails_near_nan),
        cmocka_unit_test(test_fails_le_nan),
    };
    if ((argc == 2) && (strcmp(argv[1], "pass") == 0)) {
        return cmocka_run_group_tests_name("test_assert_pass", pass, NULL, NULL);
    }
    if ((argc == 2) && (strcmp(argv[1], "fail") == 0)) {
        return cmocka_run_group_tests_name("test_assert_fail", fail, NULL, NULL);
    }
    print_error("usage: %s pass|fail\n", argv[0]);
    return 2;
}
