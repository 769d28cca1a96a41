/*
 * CMocka on the Cortex-M4, failing on purpose: two of three tests fail, the
 * runner returns the number of failures, and QEMU exits with 2. Proves that
 * a failing target test cannot look like a passing one.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>

#include <cmocka.h>

static void test_passes(void **state)
{
    (void)state;
    assert_true(1);
}

static void test_wrong_integer(void **state)
{
    (void)state;
    uint64_t fuel_ul = 0x100000000ULL;
    assert_int_equal(fuel_ul, 1U);
}

static void test_wrong_string(void **state)
{
    (void)state;
    assert_string_equal("platoon", "convoy");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_passes),
        cmocka_unit_test(test_wrong_integer),
        cmocka_unit_test(test_wrong_string),
    };
    return cmocka_run_group_tests_name("m4_demo_fail", tests, NULL, NULL);
}
