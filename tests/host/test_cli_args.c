/*
 * Tests of the host tools' option tables (sim_host/lib/cli_args.c,
 * cli_parse_options): values set from a command line, and each kind of bad
 * command line refused with exit status 2 and what was read before it.
 *
 *     test_cli_args
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "../test_assert.h"

#include <stdbool.h>
#include <string.h>

#include "lib/cli_args.h"

#define MAX_POS 2

/* One tool's options, as a tool declares them. */
typedef struct {
    bool quiet, quiet_seen;
    const char *name;
    unsigned long sa;
    bool sa_seen;
    double mass_kg;
    const char *items[3];
    cli_list_t list;
    const char *pos[MAX_POS];
    int n_pos;
} opts_t;

static int parse(opts_t *o, int argc, const char *const *args)
{
    memset(o, 0, sizeof *o);
    o->name = "log";
    o->sa = 0x8CU;
    o->mass_kg = 40000.0;
    o->list.items = o->items;
    o->list.cap = 3U;
    const cli_option_t table[] = {
        {"--quiet", CLI_FLAG, 0.0, 0.0, &o->quiet, &o->quiet_seen},
        {"--name", CLI_TEXT, 0.0, 0.0, &o->name, NULL},
        {"--module-sa", CLI_UL, 0.0, 253.0, &o->sa, &o->sa_seen},
        {"--mass", CLI_DOUBLE, 1000.0, 100000.0, &o->mass_kg, NULL},
        {"--truck", CLI_LIST, 0.0, 0.0, &o->list, NULL},
    };
    char *argv[16];
    for (int i = 0; i < argc; i++) {
        argv[i] = (char *)(uintptr_t)args[i];
    }
    return cli_parse_options("tool", argc, argv, 1, table, sizeof table / sizeof table[0], o->pos,
                             MAX_POS, &o->n_pos);
}

static void test_every_kind_is_read(void **state)
{
    (void)state;
    static const char *const args[] = {"tool", "a.log", "--quiet", "--name", "run 1",
                                       "--module-sa", "0x8d", "--mass", "12500.5",
                                       "--truck", "t1", "--truck", "t2", "-"};
    opts_t o;
    assert_int_equal(parse(&o, 14, args), 0);
    assert_true(o.quiet);
    assert_true(o.quiet_seen);
    assert_string_equal(o.name, "run 1");
    assert_int_equal(o.sa, 0x8DU);
    assert_true(o.sa_seen);
    ASSERT_NEAR(o.mass_kg, 12500.5, 0.0);
    assert_int_equal(o.list.n, 2U);
    assert_string_equal(o.items[0], "t1");
    assert_string_equal(o.items[1], "t2");
    /* A lone "-" is positional (standard input). */
    assert_int_equal(o.n_pos, 2);
    assert_string_equal(o.pos[0], "a.log");
    assert_string_equal(o.pos[1], "-");
}

static void test_defaults_stay_when_not_given(void **state)
{
    (void)state;
    static const char *const args[] = {"tool"};
    opts_t o;
    assert_int_equal(parse(&o, 1, args), 0);
    assert_false(o.quiet_seen);
    assert_false(o.sa_seen);
    assert_string_equal(o.name, "log");
    assert_int_equal(o.sa, 0x8CU);
    ASSERT_NEAR(o.mass_kg, 40000.0, 0.0);
    assert_int_equal(o.n_pos, 0);
}

static void test_unknown_option_is_refused(void **state)
{
    (void)state;
    static const char *const args[] = {"tool", "--name", "x", "--frobnicate", "--quiet"};
    opts_t o;
    assert_int_equal(parse(&o, 5, args), 2);
    assert_string_equal(o.name, "x");
    assert_false(o.quiet); /* not read: the parse stops at the error */
}

static void test_missing_value_is_refused(void **state)
{
    (void)state;
    static const char *const args[] = {"tool", "--mass"};
    opts_t o;
    assert_int_equal(parse(&o, 2, args), 2);
    ASSERT_NEAR(o.mass_kg, 40000.0, 0.0);
}

static void test_numbers_out_of_range_or_malformed_are_refused(void **state)
{
    (void)state;
    static const char *const bad[][3] = {
        {"tool", "--module-sa", "254"},   {"tool", "--module-sa", "-1"},
        {"tool", "--module-sa", "12abc"}, {"tool", "--module-sa", ""},
        {"tool", "--mass", "999.9"},      {"tool", "--mass", "100000.1"},
        {"tool", "--mass", "nan"},        {"tool", "--mass", "1e5x"},
    };
    for (size_t k = 0U; k < sizeof bad / sizeof bad[0]; k++) {
        opts_t o;
        const int rc = parse(&o, 3, bad[k]);
        if (rc != 2) {
            print_message("%s '%s' gave %d\n", bad[k][1], bad[k][2], rc);
        }
        assert_int_equal(rc, 2);
        assert_false(o.sa_seen);
        ASSERT_NEAR(o.mass_kg, 40000.0, 0.0);
    }
    /* The ends of the ranges are in. */
    static const char *const ends[] = {"tool", "--module-sa", "253", "--mass", "1000"};
    opts_t o;
    assert_int_equal(parse(&o, 5, ends), 0);
    assert_int_equal(o.sa, 253U);
    ASSERT_NEAR(o.mass_kg, 1000.0, 0.0);
}

static void test_too_many_list_values_or_positionals_are_refused(void **state)
{
    (void)state;
    static const char *const list[] = {"tool", "--truck", "a", "--truck", "b",
                                       "--truck", "c", "--truck", "d"};
    opts_t o;
    assert_int_equal(parse(&o, 9, list), 2);
    assert_int_equal(o.list.n, 3U);
    static const char *const pos[] = {"tool", "a", "b", "c"};
    assert_int_equal(parse(&o, 4, pos), 2);
    assert_int_equal(o.n_pos, MAX_POS);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_kind_is_read),
        cmocka_unit_test(test_defaults_stay_when_not_given),
        cmocka_unit_test(test_unknown_option_is_refused),
        cmocka_unit_test(test_missing_value_is_refused),
        cmocka_unit_test(test_numbers_out_of_range_or_malformed_are_refused),
        cmocka_unit_test(test_too_many_list_values_or_positionals_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
