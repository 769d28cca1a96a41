/*
 * CMocka on the Cortex-M4: every test here passes, so QEMU exits with 0.
 * Exercises what target tests rely on: 64-bit integer messages, strings,
 * memory, mocks, and CMocka's leak-checking allocator on newlib's heap.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static int32_t read_sensor(void)
{
    return (int32_t)mock();
}

static void test_integers(void **state)
{
    (void)state;
    int64_t big = INT64_MIN;
    assert_int_equal(big, INT64_MIN);
    assert_int_not_equal(UINT32_MAX, 0);
    assert_in_range(42, 40, 50);
}

static void test_strings_and_memory(void **state)
{
    (void)state;
    const uint8_t expected[4] = {0xDEU, 0xADU, 0xBEU, 0xEFU};
    uint8_t actual[4];
    memset(actual, 0xA5, sizeof actual);
    memcpy(actual, expected, sizeof actual);
    assert_memory_equal(actual, expected, sizeof expected);
    assert_string_equal("cortex-m4", "cortex-m4");
}

static void test_mock(void **state)
{
    (void)state;
    will_return(read_sensor, -1200);
    assert_int_equal(read_sensor(), -1200);
}

static void test_heap(void **state)
{
    (void)state;
    uint32_t *words = test_malloc(64U * sizeof *words);
    assert_non_null(words);
    words[63] = 7U;
    assert_int_equal(words[63], 7U);
    test_free(words);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_integers),
        cmocka_unit_test(test_strings_and_memory),
        cmocka_unit_test(test_mock),
        cmocka_unit_test(test_heap),
    };
    return cmocka_run_group_tests_name("m4_demo_pass", tests, NULL, NULL);
}
