/* hal_conformance.c - the CAN backend conformance suite (hal_conformance.h).
 * Expected frames are literals; every output is filled with 0xA5 before the
 * call that must write it. */
#include "tests/hal/hal_conformance.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#define EFF PFE_CAN_EFF_FLAG
/* J1939: the 18 PGN bits, priority and source address masked out. */
#define PGN_MASK (0x03FFFF00UL | EFF)
#define CCVS1_SA00 (0x18FEF100UL | EFF) /* PGN 65265, priority 6, source 0x00 */
#define LFE1_SA00 (0x18FEF200UL | EFF)  /* PGN 65266 */
#define SSI_SA13 (0x0CF01313UL | EFF)   /* PGN 61459, priority 3, source 0x13 */

static const hal_conformance_backend_t *backend;

typedef struct {
    hal_can_t *tx;
    hal_can_t *rx;
} pair_t;

static pair_t pair;

/* ------------------------------------------------------------------ helpers */

static pfe_can_frame_t frame(uint32_t id, uint8_t dlc, uint8_t first)
{
    pfe_can_frame_t f;
    memset(&f, 0xA5, sizeof f);
    f.id = id;
    f.dlc = dlc;
    for (uint8_t k = 0U; k < dlc; k++) {
        f.data[k] = (uint8_t)(first + k);
    }
    return f;
}

static void send_ok(hal_can_t *can, uint32_t id, uint8_t dlc, uint8_t first)
{
    const pfe_can_frame_t f = frame(id, dlc, first);
    assert_int_equal(hal_can_send(can, &f), 0);
}

/* Receives one frame, letting the backend deliver for up to max_idle idles. */
static int receive_wait(hal_can_t *can, hal_can_rx_t *out)
{
    for (uint32_t k = 0U;; k++) {
        memset(out, 0xA5, sizeof *out);
        const int rc = hal_can_receive(can, out);
        if ((rc != HAL_EAGAIN) || (k >= backend->max_idle)) {
            return rc;
        }
        if (backend->idle != NULL) {
            backend->idle(backend->ctx);
        }
    }
}

/* The next frame must be ID with DLC bytes FIRST, FIRST + 1, ... */
static hal_can_rx_t expect_frame(hal_can_t *can, uint32_t id, uint8_t dlc, uint8_t first)
{
    hal_can_rx_t rx;
    assert_int_equal(receive_wait(can, &rx), 0);
    assert_int_equal(rx.frame.id, id);
    assert_int_equal(rx.frame.dlc, dlc);
    for (uint8_t k = 0U; k < dlc; k++) {
        assert_int_equal(rx.frame.data[k], (uint8_t)(first + k));
    }
    return rx;
}

static void expect_empty(hal_can_t *can)
{
    hal_can_rx_t rx;
    memset(&rx, 0xA5, sizeof rx);
    assert_int_equal(hal_can_receive(can, &rx), HAL_EAGAIN);
}

static hal_can_stats_t stats_of(const hal_can_t *can)
{
    hal_can_stats_t s;
    memset(&s, 0xA5, sizeof s);
    hal_can_get_stats(can, &s);
    return s;
}

static int open_pair(void **state)
{
    pair.tx = NULL;
    pair.rx = NULL;
    int rc = backend->open(backend->ctx, &pair.tx);
    if (rc == 0) {
        rc = backend->open(backend->ctx, &pair.rx);
    }
    if (rc != 0) {
        print_error("%s: opening a handle failed: %d\n", backend->name, rc);
        if (pair.tx != NULL) {
            backend->close(backend->ctx, pair.tx);
            pair.tx = NULL;
        }
        return -1;
    }
    *state = &pair;
    return 0;
}

static int close_pair(void **state)
{
    (void)state;
    if (pair.rx != NULL) {
        backend->close(backend->ctx, pair.rx);
    }
    if (pair.tx != NULL) {
        backend->close(backend->ctx, pair.tx);
    }
    pair.tx = NULL;
    pair.rx = NULL;
    return 0;
}

/* ------------------------------------------------------------------ receive, send */

static void test_receive_empty_is_eagain(void **state)
{
    const pair_t *p = *state;
    expect_empty(p->rx);
    expect_empty(p->rx);
    expect_empty(p->tx);
}

static void test_standard_frame_round_trip(void **state)
{
    const pair_t *p = *state;
    send_ok(p->tx, 0x123U, 8U, 0x11U);
    send_ok(p->tx, 0x7FFU, 2U, 0xFEU);
    send_ok(p->tx, 0x000U, 1U, 0x00U);
    expect_frame(p->rx, 0x123U, 8U, 0x11U);
    expect_frame(p->rx, 0x7FFU, 2U, 0xFEU);
    expect_frame(p->rx, 0x000U, 1U, 0x00U);
    expect_empty(p->rx);
}

static void test_extended_frame_round_trip(void **state)
{
    const pair_t *p = *state;
    send_ok(p->tx, CCVS1_SA00, 8U, 0x20U);
    send_ok(p->tx, 0x1FFFFFFFUL | EFF, 8U, 0xF8U);
    /* Extended id 0 is not standard id 0: the flag survives. */
    send_ok(p->tx, EFF, 3U, 0x01U);
    send_ok(p->tx, 0x000U, 3U, 0x01U);
    expect_frame(p->rx, 0x98FEF100UL, 8U, 0x20U);
    expect_frame(p->rx, 0x9FFFFFFFUL, 8U, 0xF8U);
    expect_frame(p->rx, 0x80000000UL, 3U, 0x01U);
    expect_frame(p->rx, 0x00000000UL, 3U, 0x01U);
    expect_empty(p->rx);
}

static void test_every_length_in_send_order(void **state)
{
    const pair_t *p = *state;
    for (uint8_t dlc = 0U; dlc <= 8U; dlc++) {
        send_ok(p->tx, 0x100U + dlc, dlc, (uint8_t)(0x10U * dlc));
        send_ok(p->tx, (0x18FF0000UL + dlc) | EFF, dlc, (uint8_t)(0x80U + dlc));
    }
    for (uint8_t dlc = 0U; dlc <= 8U; dlc++) {
        expect_frame(p->rx, 0x100U + dlc, dlc, (uint8_t)(0x10U * dlc));
        expect_frame(p->rx, (0x18FF0000UL + dlc) | EFF, dlc, (uint8_t)(0x80U + dlc));
    }
    expect_empty(p->rx);
}

/* 100 frames sent back to back arrive complete and in order. */
static void test_burst_keeps_order(void **state)
{
    const pair_t *p = *state;
    for (uint32_t k = 0U; k < 100U; k++) {
        send_ok(p->tx, (0x18FF0000UL + k) | EFF, 8U, (uint8_t)k);
    }
    for (uint32_t k = 0U; k < 100U; k++) {
        expect_frame(p->rx, (0x18FF0000UL + k) | EFF, 8U, (uint8_t)k);
    }
    expect_empty(p->rx);
}

static void test_sender_does_not_receive_its_own_frames(void **state)
{
    const pair_t *p = *state;
    send_ok(p->tx, CCVS1_SA00, 8U, 0x00U);
    expect_frame(p->rx, CCVS1_SA00, 8U, 0x00U);
    expect_empty(p->tx);
}

static void test_send_refuses_impossible_frames(void **state)
{
    const pair_t *p = *state;
    pfe_can_frame_t f = frame(0x123U, 8U, 0U);
    f.dlc = 9U;
    assert_int_equal(hal_can_send(p->tx, &f), HAL_EINVAL);
    f = frame(0x800U, 1U, 0U);                  /* 12 bits without the EFF flag */
    assert_int_equal(hal_can_send(p->tx, &f), HAL_EINVAL);
    f = frame(0x20000000UL | EFF, 1U, 0U);      /* 30 bits */
    assert_int_equal(hal_can_send(p->tx, &f), HAL_EINVAL);
    assert_int_equal(stats_of(p->tx).tx_frames, 0U);
    /* None of them reached the bus: the next frame is the first to arrive. */
    send_ok(p->tx, 0x321U, 1U, 0x42U);
    expect_frame(p->rx, 0x321U, 1U, 0x42U);
    expect_empty(p->rx);
}

/* ------------------------------------------------------------------ filters */

static void test_filter_matches_pgn_any_priority_and_source(void **state)
{
    const pair_t *p = *state;
    const int idx = hal_can_add_filter(p->rx, CCVS1_SA00, PGN_MASK);
    ASSERT_GE(idx, 0);
    send_ok(p->tx, LFE1_SA00, 8U, 0x01U);            /* another PGN */
    send_ok(p->tx, 0x18FEF117UL | EFF, 8U, 0x02U);   /* CCVS1 from source 0x17 */
    send_ok(p->tx, 0x100U, 8U, 0x03U);               /* standard frame */
    send_ok(p->tx, 0x0CFEF100UL | EFF, 8U, 0x04U);   /* CCVS1 at priority 3 */
    send_ok(p->tx, 0x19FEF100UL | EFF, 8U, 0x05U);   /* data page 1: another PGN */
    send_ok(p->tx, 0x18FEF000UL | EFF, 8U, 0x06U);   /* PGN 65264 */
    send_ok(p->tx, CCVS1_SA00, 8U, 0x07U);           /* exact */
    expect_frame(p->rx, 0x98FEF117UL, 8U, 0x02U);
    expect_frame(p->rx, 0x8CFEF100UL, 8U, 0x04U);
    expect_frame(p->rx, 0x98FEF100UL, 8U, 0x07U);
    expect_empty(p->rx);
}

/* The EFF flag in the mask makes it part of the match. */
static void test_filter_on_standard_id_checks_the_eff_flag(void **state)
{
    const pair_t *p = *state;
    ASSERT_GE(hal_can_add_filter(p->rx, 0x123U, 0x7FFUL | EFF), 0);
    send_ok(p->tx, 0x123UL | EFF, 1U, 0x01U);        /* extended 0x123 */
    send_ok(p->tx, 0x124U, 1U, 0x02U);
    send_ok(p->tx, 0x123U, 1U, 0x03U);
    expect_frame(p->rx, 0x123U, 1U, 0x03U);
    expect_empty(p->rx);
}

static void test_frame_passes_if_any_filter_accepts(void **state)
{
    const pair_t *p = *state;
    const int a = hal_can_add_filter(p->rx, CCVS1_SA00, PGN_MASK);
    const int b = hal_can_add_filter(p->rx, LFE1_SA00, PGN_MASK);
    ASSERT_GE(a, 0);
    ASSERT_GE(b, 0);
    assert_int_not_equal(a, b);
    send_ok(p->tx, 0x18FEF203UL | EFF, 2U, 0x01U);
    send_ok(p->tx, SSI_SA13, 2U, 0x02U);
    send_ok(p->tx, 0x18FEF103UL | EFF, 2U, 0x03U);
    expect_frame(p->rx, 0x98FEF203UL, 2U, 0x01U);
    expect_frame(p->rx, 0x98FEF103UL, 2U, 0x03U);
    expect_empty(p->rx);
}

static void test_removed_filter_no_longer_accepts(void **state)
{
    const pair_t *p = *state;
    const int a = hal_can_add_filter(p->rx, CCVS1_SA00, PGN_MASK);
    const int b = hal_can_add_filter(p->rx, LFE1_SA00, PGN_MASK);
    ASSERT_GE(a, 0);
    ASSERT_GE(b, 0);
    assert_int_equal(hal_can_remove_filter(p->rx, a), 0);
    assert_int_equal(hal_can_remove_filter(p->rx, a), HAL_EINVAL);
    send_ok(p->tx, CCVS1_SA00, 1U, 0x01U);
    send_ok(p->tx, LFE1_SA00, 1U, 0x02U);
    expect_frame(p->rx, 0x98FEF200UL, 1U, 0x02U);
    expect_empty(p->rx);
    /* No filter left: every frame again. */
    assert_int_equal(hal_can_remove_filter(p->rx, b), 0);
    send_ok(p->tx, CCVS1_SA00, 1U, 0x03U);
    send_ok(p->tx, 0x055U, 1U, 0x04U);
    expect_frame(p->rx, 0x98FEF100UL, 1U, 0x03U);
    expect_frame(p->rx, 0x055U, 1U, 0x04U);
    expect_empty(p->rx);
}

static void test_remove_filter_refuses_bad_index(void **state)
{
    const pair_t *p = *state;
    assert_int_equal(hal_can_remove_filter(p->rx, 0), HAL_EINVAL);
    assert_int_equal(hal_can_remove_filter(p->rx, -1), HAL_EINVAL);
    assert_int_equal(hal_can_remove_filter(p->rx, (int)HAL_CAN_MAX_FILTERS), HAL_EINVAL);
}

static void test_filters_run_out_with_enospc(void **state)
{
    const pair_t *p = *state;
    int idx[HAL_CAN_MAX_FILTERS];
    /* Proprietary B PGNs 0xFF00.., one per filter. */
    for (uint32_t k = 0U; k < HAL_CAN_MAX_FILTERS; k++) {
        idx[k] = hal_can_add_filter(p->rx, (0x18FF0000UL + (k << 8)) | EFF, PGN_MASK);
        ASSERT_GE(idx[k], 0);
        for (uint32_t j = 0U; j < k; j++) {
            assert_int_not_equal(idx[j], idx[k]);
        }
    }
    assert_int_equal(hal_can_add_filter(p->rx, CCVS1_SA00, PGN_MASK), HAL_ENOSPC);
    /* Freeing one slot makes room for exactly one. */
    assert_int_equal(hal_can_remove_filter(p->rx, idx[5]), 0);
    ASSERT_GE(hal_can_add_filter(p->rx, CCVS1_SA00, PGN_MASK), 0);
    assert_int_equal(hal_can_add_filter(p->rx, LFE1_SA00, PGN_MASK), HAL_ENOSPC);
    /* All of them still work: the first, the last, the replacement; not the
     * removed one nor the refused one. */
    send_ok(p->tx, 0x18FF0500UL | EFF, 1U, 0x01U);
    send_ok(p->tx, LFE1_SA00, 1U, 0x02U);
    send_ok(p->tx, 0x18FF0021UL | EFF, 1U, 0x03U);
    send_ok(p->tx, 0x18FF0F22UL | EFF, 1U, 0x04U);
    send_ok(p->tx, 0x18FEF123UL | EFF, 1U, 0x05U);
    expect_frame(p->rx, 0x98FF0021UL, 1U, 0x03U);
    expect_frame(p->rx, 0x98FF0F22UL, 1U, 0x04U);
    expect_frame(p->rx, 0x98FEF123UL, 1U, 0x05U);
    expect_empty(p->rx);
}

/* ------------------------------------------------------------------ time, counters */

static void test_timestamps_never_decrease(void **state)
{
    const pair_t *p = *state;
    uint64_t last = 0U;
    for (uint32_t k = 0U; k < 32U; k++) {
        send_ok(p->tx, (0x18FF0000UL + k) | EFF, 1U, (uint8_t)k);
        if ((k % 4U) == 3U && backend->idle != NULL) {
            backend->idle(backend->ctx);
        }
    }
    for (uint32_t k = 0U; k < 32U; k++) {
        const hal_can_rx_t rx = expect_frame(p->rx, (0x18FF0000UL + k) | EFF, 1U, (uint8_t)k);
        ASSERT_GE(rx.timestamp_us, last);
        last = rx.timestamp_us;
    }
    /* A later frame is not stamped earlier, whatever happened in between. */
    if (backend->idle != NULL) {
        backend->idle(backend->ctx);
    }
    send_ok(p->tx, 0x001U, 0U, 0U);
    const hal_can_rx_t rx = expect_frame(p->rx, 0x001U, 0U, 0U);
    ASSERT_GE(rx.timestamp_us, last);
}

static void test_stats_count_frames(void **state)
{
    const pair_t *p = *state;
    const hal_can_stats_t tx0 = stats_of(p->tx);
    const hal_can_stats_t rx0 = stats_of(p->rx);
    assert_int_equal(tx0.tx_frames, 0U);
    assert_int_equal(tx0.rx_frames, 0U);
    assert_int_equal(rx0.tx_frames, 0U);
    assert_int_equal(rx0.rx_frames, 0U);

    for (uint32_t k = 0U; k < 10U; k++) {
        send_ok(p->tx, (0x18FEF100UL + k) | EFF, 8U, (uint8_t)k);
    }
    for (uint32_t k = 0U; k < 10U; k++) {
        expect_frame(p->rx, (0x18FEF100UL + k) | EFF, 8U, (uint8_t)k);
    }
    expect_empty(p->rx);   /* an empty receive counts nothing */

    const hal_can_stats_t tx1 = stats_of(p->tx);
    const hal_can_stats_t rx1 = stats_of(p->rx);
    assert_int_equal(tx1.tx_frames, 10U);
    assert_int_equal(tx1.rx_frames, 0U);
    assert_int_equal(tx1.tx_dropped, tx0.tx_dropped);
    assert_int_equal(rx1.rx_frames, 10U);
    assert_int_equal(rx1.tx_frames, 0U);
    assert_int_equal(rx1.rx_dropped, rx0.rx_dropped);
}

/* ------------------------------------------------------------------ run */

static void test_clock_waits_reach_their_deadline(void **state)
{
    (void)state;
    hal_time_t *clock = backend->time;
    const uint64_t t0 = hal_time_now_us(clock);
    assert_int_equal(hal_time_wait_until_us(clock, t0 + 2000U), 0);
    const uint64_t t1 = hal_time_now_us(clock);
    ASSERT_GE(t1, t0 + 2000U);
    /* A deadline in the past: at once, and the clock does not go back. */
    assert_int_equal(hal_time_wait_until_us(clock, t0), 0);
    const uint64_t t2 = hal_time_now_us(clock);
    ASSERT_GE(t2, t1);
    ASSERT_LT(t2 - t1, 1000000U);
    /* Ten 10 ms ticks on absolute deadlines take at least 100 ms. */
    uint64_t deadline = t2;
    for (uint32_t k = 0U; k < 10U; k++) {
        deadline += 10000U;
        assert_int_equal(hal_time_wait_until_us(clock, deadline), 0);
    }
    ASSERT_GE(hal_time_now_us(clock), t2 + 100000U);
}

int hal_conformance_run(const hal_conformance_backend_t *b)
{
    backend = b;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_receive_empty_is_eagain, open_pair, close_pair),
        cmocka_unit_test_setup_teardown(test_standard_frame_round_trip, open_pair, close_pair),
        cmocka_unit_test_setup_teardown(test_extended_frame_round_trip, open_pair, close_pair),
        cmocka_unit_test_setup_teardown(test_every_length_in_send_order, open_pair, close_pair),
        cmocka_unit_test_setup_teardown(test_burst_keeps_order, open_pair, close_pair),
        cmocka_unit_test_setup_teardown(test_sender_does_not_receive_its_own_frames, open_pair,
                                        close_pair),
        cmocka_unit_test_setup_teardown(test_send_refuses_impossible_frames, open_pair, close_pair),
        cmocka_unit_test_setup_teardown(test_filter_matches_pgn_any_priority_and_source, open_pair,
                                        close_pair),
        cmocka_unit_test_setup_teardown(test_filter_on_standard_id_checks_the_eff_flag, open_pair,
                                        close_pair),
        cmocka_unit_test_setup_teardown(test_frame_passes_if_any_filter_accepts, open_pair,
                                        close_pair),
        cmocka_unit_test_setup_teardown(test_removed_filter_no_longer_accepts, open_pair,
                                        close_pair),
        cmocka_unit_test_setup_teardown(test_remove_filter_refuses_bad_index, open_pair, close_pair),
        cmocka_unit_test_setup_teardown(test_filters_run_out_with_enospc, open_pair, close_pair),
        cmocka_unit_test_setup_teardown(test_timestamps_never_decrease, open_pair, close_pair),
        cmocka_unit_test_setup_teardown(test_stats_count_frames, open_pair, close_pair),
    };
    int failed = cmocka_run_group_tests_name(b->name, tests, NULL, NULL);
    if (b->time != NULL) {
        const struct CMUnitTest clock_tests[] = {
            cmocka_unit_test(test_clock_waits_reach_their_deadline),
        };
        failed += cmocka_run_group_tests_name(b->name, clock_tests, NULL, NULL);
    }
    return failed;
}
