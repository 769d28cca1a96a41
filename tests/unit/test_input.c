/*
 * Unit tests: one input on a real bus (pfe_input.h) and grade from altitude
 * (pfe_altgrade.h). Values are hand-computed from the rules in the headers:
 * speed 10 m/s^2 + 1000 mm/s a frame, grade 20 %/s + 5000 ppm a frame,
 * three periods stale, three rejections to error, three frames to confirm.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "pfe_altgrade.h"
#include "pfe_input.h"

#define ENGINE 0x00U
#define CAB 0x31U
#define OK_ PFE_SIG_VALID
#define NA PFE_SIG_NOT_AVAILABLE
#define ERR PFE_SIG_ERROR
#define T0 1000000U
#define P 100000U /* CCVS1 period, us */

static pfe_input_t g_in;

static pfe_input_verdict_t speed(uint8_t sa, pfe_sig_state_t st, int32_t mm_s, uint64_t t)
{
    return pfe_input_take(&g_in, sa, st, mm_s, t);
}

/* The engine and the cab both send CCVS1, the cab "not available": the
 * engine's speed stays the input's, and the cab is counted as a sender. */
static void test_locks_onto_the_first_valid_sender(void **state)
{
    (void)state;
    pfe_input_init(&g_in, PFE_IN_SPEED, PFE_INPUT_NO_SOURCE);
    assert_int_equal(pfe_input_source(&g_in), PFE_INPUT_NO_SOURCE);
    assert_int_equal(speed(CAB, NA, 0, T0), PFE_INPUT_IGNORED);
    assert_int_equal(g_in.state, NA);
    assert_int_equal(speed(ENGINE, OK_, 20000, T0 + 1000U), PFE_INPUT_ACCEPTED);
    assert_int_equal(pfe_input_source(&g_in), ENGINE);
    for (uint32_t k = 1U; k <= 20U; k++) {
        const uint64_t t = T0 + (k * P);
        assert_int_equal(speed(CAB, NA, 0, t), PFE_INPUT_IGNORED);
        assert_int_equal(speed(ENGINE, OK_, 20000, t + 1000U), PFE_INPUT_ACCEPTED);
        assert_int_equal(g_in.state, OK_);
        assert_int_equal(g_in.value, 20000);
    }
    assert_true(pfe_input_age(&g_in, T0 + (20U * P) + 1000U));
    assert_int_equal(g_in.n_senders, 2);
    /* error from the cab: never replaces the engine's value either */
    assert_int_equal(speed(CAB, ERR, 0, T0 + (21U * P)), PFE_INPUT_IGNORED);
    assert_int_equal(g_in.state, OK_);
}

/* The locked sender falls silent: another takes over only after three
 * periods without a valid value; an error from the locked one frees it at once. */
static void test_switches_after_three_periods_or_an_error(void **state)
{
    (void)state;
    pfe_input_init(&g_in, PFE_IN_SPEED, PFE_INPUT_NO_SOURCE);
    assert_int_equal(speed(ENGINE, OK_, 20000, T0), PFE_INPUT_ACCEPTED);
    /* 300 ms later: not yet stale (> 3 periods needed) */
    assert_int_equal(speed(CAB, OK_, 20100, T0 + (3U * P)), PFE_INPUT_IGNORED);
    assert_int_equal(speed(CAB, OK_, 20100, T0 + (3U * P) + 1U), PFE_INPUT_ACCEPTED);
    assert_int_equal(pfe_input_source(&g_in), CAB);
    /* the engine is now another sender */
    assert_int_equal(speed(ENGINE, OK_, 20000, T0 + (4U * P)), PFE_INPUT_IGNORED);
    /* the cab sends error: the input says so, and the engine may take over */
    assert_int_equal(speed(CAB, ERR, 0, T0 + (5U * P)), PFE_INPUT_ACCEPTED);
    assert_int_equal(g_in.state, ERR);
    assert_int_equal(speed(ENGINE, OK_, 20000, T0 + (5U * P) + 10U), PFE_INPUT_ACCEPTED);
    assert_int_equal(pfe_input_source(&g_in), ENGINE);
    assert_int_equal(g_in.state, OK_);
    /* a locked sender's "not available" is the input's state */
    assert_int_equal(speed(ENGINE, NA, 0, T0 + (6U * P)), PFE_INPUT_ACCEPTED);
    assert_int_equal(g_in.state, NA);
}

/* A calibration names the sender: nobody else is ever used. */
static void test_fixed_sender(void **state)
{
    (void)state;
    pfe_input_init(&g_in, PFE_IN_SPEED, CAB);
    assert_int_equal(speed(ENGINE, OK_, 20000, T0), PFE_INPUT_IGNORED);
    assert_int_equal(g_in.state, NA);
    assert_int_equal(speed(ENGINE, OK_, 20000, T0 + (10U * P)), PFE_INPUT_IGNORED);
    assert_int_equal(speed(CAB, OK_, 21000, T0 + (11U * P)), PFE_INPUT_ACCEPTED);
    assert_int_equal(speed(CAB, ERR, 0, T0 + (12U * P)), PFE_INPUT_ACCEPTED);
    assert_int_equal(speed(ENGINE, OK_, 20000, T0 + (12U * P) + 10U), PFE_INPUT_IGNORED);
    assert_int_equal(pfe_input_source(&g_in), CAB);
}

/* Speed: 10 m/s^2 * 0.1 s + 1000 mm/s = 2000 mm/s allowed between frames
 * 100 ms apart; 150 km/h = 41667 mm/s the most. */
static void test_speed_plausibility(void **state)
{
    (void)state;
    pfe_input_init(&g_in, PFE_IN_SPEED, PFE_INPUT_NO_SOURCE);
    /* no lock on a value out of the plausible range */
    assert_int_equal(speed(ENGINE, OK_, 41668, T0), PFE_INPUT_IGNORED);
    assert_int_equal(pfe_input_source(&g_in), PFE_INPUT_NO_SOURCE);
    assert_int_equal(speed(ENGINE, OK_, 20000, T0), PFE_INPUT_ACCEPTED);
    assert_int_equal(speed(ENGINE, OK_, 22000, T0 + P), PFE_INPUT_ACCEPTED);      /* +2000: the limit */
    assert_int_equal(speed(ENGINE, OK_, 24001, T0 + (2U * P)), PFE_INPUT_REJECTED); /* +2001 */
    assert_int_equal(g_in.value, 22000);
    assert_int_equal(g_in.state, OK_);
    /* 200 ms after the last accepted: 3000 allowed */
    assert_int_equal(speed(ENGINE, OK_, 25000, T0 + (3U * P)), PFE_INPUT_ACCEPTED);
    assert_int_equal(g_in.rejected, 1);
    assert_int_equal(speed(ENGINE, OK_, 41668, T0 + (4U * P)), PFE_INPUT_REJECTED);
    assert_int_equal(g_in.rejected, 2);
    assert_int_equal(g_in.rejects_in_row, 1);
}

/* Garbage between the real frames from the same address (a second node
 * using it, or a sender gone wild): an engine LFE1 less than 0.6 of its
 * period after the last accepted one is rejected, whatever it carries. */
static void test_frames_between_the_real_ones(void **state)
{
    (void)state;
    pfe_input_init(&g_in, PFE_IN_ENGINE_FUEL, PFE_INPUT_NO_SOURCE);
    assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 9000000, T0), PFE_INPUT_ACCEPTED);
    assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 9000000, T0 + 50000U), PFE_INPUT_REJECTED);
    assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 9000000, T0 + P), PFE_INPUT_ACCEPTED);
    assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 9000000, T0 + P + 59999U), PFE_INPUT_REJECTED);
    assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 9000000, T0 + P + 60000U), PFE_INPUT_ACCEPTED);
    /* "error" or "not available" that soon is no more the sender's own */
    assert_int_equal(pfe_input_take(&g_in, ENGINE, ERR, 0, T0 + P + 90000U), PFE_INPUT_REJECTED);
    assert_int_equal(g_in.state, OK_);
    assert_int_equal(pfe_input_take(&g_in, ENGINE, NA, 0, T0 + P + 120000U), PFE_INPUT_ACCEPTED);
    assert_int_equal(g_in.state, NA);
    assert_int_equal(g_in.rejected, 3);
    /* CCVS1 and altitude have no such rule: frames as close as a late tick
     * brings them are taken */
    pfe_input_init(&g_in, PFE_IN_SPEED, PFE_INPUT_NO_SOURCE);
    assert_int_equal(speed(ENGINE, OK_, 20000, T0), PFE_INPUT_ACCEPTED);
    assert_int_equal(speed(ENGINE, OK_, 20100, T0 + 10000U), PFE_INPUT_ACCEPTED);
    pfe_input_init(&g_in, PFE_IN_ALTITUDE, PFE_INPUT_NO_SOURCE);
    for (uint32_t k = 0U; k < 20U; k++) {
        assert_int_equal(pfe_input_take(&g_in, 0x1CU, OK_, 100000 + (int32_t)k, T0 + (k * 100000U)),
                         PFE_INPUT_ACCEPTED);
    }
}

/* 0 -> 250 km/h in one frame, then garbage: three rejections make the input
 * an error; it takes three agreeing frames to be valid again. */
static void test_persistent_rejection_is_an_error_until_confirmed(void **state)
{
    (void)state;
    pfe_input_init(&g_in, PFE_IN_SPEED, PFE_INPUT_NO_SOURCE);
    assert_int_equal(speed(ENGINE, OK_, 0, T0), PFE_INPUT_ACCEPTED);
    assert_int_equal(speed(ENGINE, OK_, 69444, T0 + P), PFE_INPUT_REJECTED);
    assert_int_equal(speed(ENGINE, OK_, 30000, T0 + (2U * P)), PFE_INPUT_REJECTED);
    assert_int_equal(g_in.state, OK_);
    assert_int_equal(g_in.value, 0);
    assert_int_equal(speed(ENGINE, OK_, 5000, T0 + (3U * P)), PFE_INPUT_REJECTED);
    assert_int_equal(g_in.state, ERR);
    assert_true(g_in.error);
    /* three agreeing frames: 10000, 11000, 12000 */
    assert_int_equal(speed(ENGINE, OK_, 10000, T0 + (4U * P)), PFE_INPUT_CONFIRMING);
    assert_int_equal(g_in.state, ERR);
    assert_int_equal(speed(ENGINE, OK_, 11000, T0 + (5U * P)), PFE_INPUT_CONFIRMING);
    /* one that disagrees starts the count again from itself */
    assert_int_equal(speed(ENGINE, OK_, 20000, T0 + (6U * P)), PFE_INPUT_REJECTED);
    assert_int_equal(g_in.state, ERR);
    assert_int_equal(speed(ENGINE, OK_, 20500, T0 + (7U * P)), PFE_INPUT_CONFIRMING);
    assert_int_equal(speed(ENGINE, OK_, 21000, T0 + (8U * P)), PFE_INPUT_ACCEPTED);
    assert_int_equal(g_in.state, OK_);
    assert_int_equal(g_in.value, 21000);
    assert_int_equal(g_in.rejected, 4);
    /* an input in error stays current: it does not age into "not available" */
    pfe_input_init(&g_in, PFE_IN_SPEED, PFE_INPUT_NO_SOURCE);
    assert_int_equal(speed(ENGINE, OK_, 0, T0), PFE_INPUT_ACCEPTED);
    for (uint32_t k = 1U; k <= 30U; k++) {
        const int32_t junk = ((k % 2U) == 0U) ? 20000 : 40000;
        (void)speed(ENGINE, OK_, junk, T0 + (k * P));
        (void)pfe_input_age(&g_in, T0 + (k * P) + 5000U);
        if (k >= 3U) {
            assert_int_equal(g_in.state, ERR);
        }
    }
}

/* A stale input forgets its reference: after a gap the first value is taken
 * on its range alone. */
static void test_stale_input_restarts(void **state)
{
    (void)state;
    pfe_input_init(&g_in, PFE_IN_SPEED, PFE_INPUT_NO_SOURCE);
    assert_int_equal(speed(ENGINE, OK_, 20000, T0), PFE_INPUT_ACCEPTED);
    assert_true(pfe_input_age(&g_in, T0 + (3U * P)));
    assert_false(pfe_input_age(&g_in, T0 + (3U * P) + 1U));
    assert_int_equal(g_in.state, NA);
    assert_int_equal(speed(ENGINE, OK_, 30000, T0 + (50U * P)), PFE_INPUT_ACCEPTED);
    assert_int_equal(g_in.value, 30000);
    /* not aged in between: the rate is checked over three periods at most
     * (3 m/s + 1 m/s allowed, however long the gap) */
    assert_int_equal(speed(ENGINE, OK_, 34000, T0 + (60U * P)), PFE_INPUT_ACCEPTED);
    assert_int_equal(speed(ENGINE, OK_, 38001, T0 + (70U * P)), PFE_INPUT_REJECTED);
}

/* Grade: 20 %/s over 10 ms = 2000 ppm, plus 5000 ppm. */
static void test_grade_plausibility(void **state)
{
    (void)state;
    pfe_input_init(&g_in, PFE_IN_GRADE, PFE_INPUT_NO_SOURCE);
    assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 20000, T0), PFE_INPUT_ACCEPTED);
    assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 27000, T0 + 10000U), PFE_INPUT_ACCEPTED);
    assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 34001, T0 + 20000U), PFE_INPUT_REJECTED);
    assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 500001, T0 + 30000U), PFE_INPUT_REJECTED);
    assert_int_equal(g_in.value, 27000);
}

/* The rate bound rounds rate * dt down, exactly, at any interval: grade
 * 200000 ppm/s, margin 5000 ppm. dt 12345 us: 2469 + 5000 = 7469 allowed;
 * dt 29999 us (below the stale cap of 3 periods, 30000 us): 5999 + 5000 =
 * 10999; dt 1 us: 0 + 5000; and an interval of over a second below. */
static void test_grade_rate_bound_exact(void **state)
{
    (void)state;
    static const struct {
        uint32_t dt_us;
        int32_t allowed;
    } k_cases[] = {{12345U, 7469}, {29999U, 10999}, {1U, 5000}, {10000U, 7000}, {30000U, 11000}};
    for (size_t k = 0U; k < sizeof k_cases / sizeof k_cases[0]; k++) {
        for (int32_t extra = 0; extra <= 1; extra++) {
            pfe_input_init(&g_in, PFE_IN_GRADE, PFE_INPUT_NO_SOURCE);
            assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 0, T0), PFE_INPUT_ACCEPTED);
            const pfe_input_verdict_t v =
                pfe_input_take(&g_in, ENGINE, OK_, k_cases[k].allowed + extra, T0 + k_cases[k].dt_us);
            print_message("dt %u us, change %d ppm: verdict %d\n", (unsigned)k_cases[k].dt_us,
                          (int)(k_cases[k].allowed + extra), (int)v);
            assert_int_equal(v, (extra == 0) ? PFE_INPUT_ACCEPTED : PFE_INPUT_REJECTED);
        }
    }
    /* over a second: altitude 15000 mm/s, margin 10000 mm, stale after 3 s;
     * dt 2345678 us: floor(35185.17) + 10000 = 45185 */
    for (int32_t extra = 0; extra <= 1; extra++) {
        pfe_input_init(&g_in, PFE_IN_ALTITUDE, PFE_INPUT_NO_SOURCE);
        assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 100000, T0), PFE_INPUT_ACCEPTED);
        const pfe_input_verdict_t v = pfe_input_take(&g_in, ENGINE, OK_, 100000 + 45185 + extra, T0 + 2345678U);
        print_message("altitude, dt 2345678 us, change %d mm: verdict %d\n", (int)(45185 + extra), (int)v);
        assert_int_equal(v, (extra == 0) ? PFE_INPUT_ACCEPTED : PFE_INPUT_REJECTED);
    }
}

/* Mass and engine fuel rate: range only. */
static void test_range_only_inputs(void **state)
{
    (void)state;
    pfe_input_init(&g_in, PFE_IN_MASS, PFE_INPUT_NO_SOURCE);
    assert_int_equal(pfe_input_take(&g_in, 0x27U, OK_, 999, T0), PFE_INPUT_IGNORED);
    assert_int_equal(pfe_input_take(&g_in, 0x27U, OK_, 12000, T0 + 1U), PFE_INPUT_ACCEPTED);
    assert_int_equal(pfe_input_take(&g_in, 0x27U, OK_, 60000, T0 + 2U), PFE_INPUT_ACCEPTED);
    assert_int_equal(pfe_input_take(&g_in, 0x27U, OK_, 100001, T0 + 3U), PFE_INPUT_REJECTED);
    pfe_input_init(&g_in, PFE_IN_ENGINE_FUEL, PFE_INPUT_NO_SOURCE);
    assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 0, T0), PFE_INPUT_ACCEPTED);
    assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 69444444, T0 + P), PFE_INPUT_ACCEPTED); /* 250 L/h */
    assert_int_equal(pfe_input_take(&g_in, ENGINE, OK_, 69444445, T0 + (2U * P)), PFE_INPUT_REJECTED);
}

/* The sender count holds at PFE_INPUT_MAX_SENDERS. */
static void test_counts_senders(void **state)
{
    (void)state;
    pfe_input_init(&g_in, PFE_IN_SPEED, PFE_INPUT_NO_SOURCE);
    for (uint32_t sa = 0U; sa < 40U; sa++) {
        (void)speed((uint8_t)sa, NA, 0, T0 + sa);
        (void)speed((uint8_t)sa, NA, 0, T0 + sa + 1U);
    }
    assert_int_equal(g_in.n_senders, PFE_INPUT_MAX_SENDERS);
}

/* ------------------------------------------------------------ grade from altitude */

/* A 3 % climb sampled every 2.5 m (25 m/s at 10 Hz): after the filter has
 * settled the grade is 3 % within the rounding of 1 mm in 100 m (10 ppm). */
static void test_altitude_grade_of_a_steady_climb(void **state)
{
    (void)state;
    pfe_altgrade_t ag;
    pfe_altgrade_init(&ag);
    int32_t g = 1;
    assert_false(pfe_altgrade_grade(&ag, &g));
    assert_int_equal(g, 0);
    for (uint32_t k = 0U; k <= 400U; k++) {
        const uint64_t x = (uint64_t)k * 2500U;
        pfe_altgrade_sample(&ag, x, 100000 + (int32_t)((x * 3U) / 100U));
        if (x < PFE_ALTGRADE_BASE_MM) {
            assert_false(pfe_altgrade_grade(&ag, &g));
        }
    }
    assert_true(pfe_altgrade_grade(&ag, &g));
    assert_in_range(g, 29990, 30010);
}

/* GNSS-like noise of +-2 m (a fixed pseudo-random sequence) on a flat road
 * becomes a grade of well under 1 %; differenced sample to sample it would
 * be +-160 %. */
static void test_altitude_noise_is_not_grade(void **state)
{
    (void)state;
    pfe_altgrade_t ag;
    pfe_altgrade_init(&ag);
    uint32_t lcg = 12345U;
    int32_t worst = 0;
    for (uint32_t k = 0U; k <= 2000U; k++) {
        lcg = (lcg * 1103515245U) + 12345U;
        const int32_t noise_mm = (int32_t)((lcg >> 16) % 4001U) - 2000;
        pfe_altgrade_sample(&ag, (uint64_t)k * 2500U, 300000 + noise_mm);
        int32_t g = 0;
        if (pfe_altgrade_grade(&ag, &g) && (k > 200U)) {
            const int32_t a = (g < 0) ? -g : g;
            worst = (a > worst) ? a : worst;
        }
    }
    print_message("altitude noise +-2 m: worst grade %d ppm\n", (int)worst);
    assert_in_range(worst, 0, 10000);
}

/* A standing truck's noise does not move the filter; a gap restarts. */
static void test_altitude_standing_and_gaps(void **state)
{
    (void)state;
    pfe_altgrade_t ag;
    pfe_altgrade_init(&ag);
    for (uint32_t k = 0U; k <= 80U; k++) {
        pfe_altgrade_sample(&ag, (uint64_t)k * 2500U, 50000);
    }
    int32_t g = 1;
    assert_true(pfe_altgrade_grade(&ag, &g));
    assert_int_equal(g, 0);
    for (uint32_t k = 0U; k < 100U; k++) {
        pfe_altgrade_sample(&ag, 200000U, ((k % 2U) == 0U) ? 60000 : 40000);
    }
    assert_true(pfe_altgrade_grade(&ag, &g));
    assert_int_equal(g, 0);
    /* a sample 50 m on (the longest step that does not restart) takes the
     * filter all the way */
    pfe_altgrade_sample(&ag, 250000U, 50000);
    assert_true(pfe_altgrade_grade(&ag, &g));
    assert_int_equal(ag.filtered_q8_mm, 50000 * 256);
    /* 60 m without a sample: start again */
    pfe_altgrade_sample(&ag, 310001U, 50000);
    assert_false(pfe_altgrade_grade(&ag, &g));
    /* an odometer that went back: start again */
    pfe_altgrade_sample(&ag, 100U, 50000);
    assert_false(pfe_altgrade_grade(&ag, &g));
}

/* A 50 % slope's altitude beyond the model's range is clamped to it. */
static void test_altitude_grade_clamped(void **state)
{
    (void)state;
    pfe_altgrade_t ag;
    pfe_altgrade_init(&ag);
    for (uint32_t k = 0U; k <= 100U; k++) {
        const uint64_t x = (uint64_t)k * 2500U;
        pfe_altgrade_sample(&ag, x, (int32_t)x); /* 100 % */
    }
    int32_t g = 0;
    assert_true(pfe_altgrade_grade(&ag, &g));
    assert_int_equal(g, 500000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_locks_onto_the_first_valid_sender),
        cmocka_unit_test(test_switches_after_three_periods_or_an_error),
        cmocka_unit_test(test_fixed_sender),
        cmocka_unit_test(test_speed_plausibility),
        cmocka_unit_test(test_frames_between_the_real_ones),
        cmocka_unit_test(test_persistent_rejection_is_an_error_until_confirmed),
        cmocka_unit_test(test_stale_input_restarts),
        cmocka_unit_test(test_grade_plausibility),
        cmocka_unit_test(test_range_only_inputs),
        cmocka_unit_test(test_counts_senders),
        cmocka_unit_test(test_altitude_grade_of_a_steady_climb),
        cmocka_unit_test(test_grade_rate_bound_exact),
        cmocka_unit_test(test_altitude_noise_is_not_grade),
        cmocka_unit_test(test_altitude_standing_and_gaps),
        cmocka_unit_test(test_altitude_grade_clamped),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
