/*
 * test_hal_socketcan.c - the SocketCAN backend on a virtual CAN interface:
 * the conformance suite (hal_conformance.h), then what only this backend
 * promises (hal_socketcan.h): open errors, RX_ONLY, kernel timestamps on
 * CLOCK_MONOTONIC, receive-queue overflow counting, the socket for poll().
 *
 *   test_hal_socketcan [IFNAME]      (default vcan0)
 *
 * The interface must be a quiet vcan: the tests send on it and expect to
 * receive exactly their own frames. Exit status: 0 all passed, 77 skipped
 * (no such interface: this kernel has no vcan0, see scripts/vcan_vm.sh; inside
 * that script's VM, VCAN_VM=1, no interface is a failure, 1), else the number
 * of failed tests.
 */
#define _GNU_SOURCE

#include <net/if.h>
#include <poll.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "hal/posix/hal_time_posix.h"
#include "hal/socketcan/hal_socketcan.h"
#include "tests/hal/hal_conformance.h"

#define EFF PFE_CAN_EFF_FLAG

static const char *ifname = "vcan0";

/* ------------------------------------------------------------------ the backend factory */

static int sc_open(void *ctx, hal_can_t **out)
{
    return hal_socketcan_open(out, (const char *)ctx, 0U);
}

static void sc_close(void *ctx, hal_can_t *can)
{
    (void)ctx;
    hal_socketcan_close(can);
}

/* The kernel delivers a looped-back frame from a soft interrupt, usually
 * before send() returns, at worst a scheduler tick later. */
static void sc_idle(void *ctx)
{
    (void)ctx;
    const struct timespec ms = {0, 1000000L};
    (void)nanosleep(&ms, NULL);
}

/* ------------------------------------------------------------------ helpers */

static uint64_t mono_us(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return ((uint64_t)ts.tv_sec * 1000000U) + ((uint64_t)ts.tv_nsec / 1000U);
}

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

static int receive_wait(hal_can_t *can, hal_can_rx_t *out)
{
    for (uint32_t k = 0U;; k++) {
        memset(out, 0xA5, sizeof *out);
        const int rc = hal_can_receive(can, out);
        if ((rc != HAL_EAGAIN) || (k >= 2000U)) {
            return rc;
        }
        sc_idle(NULL);
    }
}

static hal_can_t *open_ok(unsigned flags)
{
    hal_can_t *h = NULL;
    assert_int_equal(hal_socketcan_open(&h, ifname, flags), 0);
    assert_non_null(h);
    return h;
}

/* ------------------------------------------------------------------ tests */

static void test_open_refuses_bad_arguments(void **state)
{
    (void)state;
    hal_can_t *h = (hal_can_t *)(uintptr_t)0xA5A5A5A5U;
    assert_int_equal(hal_socketcan_open(NULL, ifname, 0U), HAL_EINVAL);
    assert_int_equal(hal_socketcan_open(&h, NULL, 0U), HAL_EINVAL);
    assert_int_equal(hal_socketcan_open(&h, "", 0U), HAL_EINVAL);
    assert_int_equal(hal_socketcan_open(&h, "vcan0123456789ab", 0U), HAL_EINVAL); /* 16 chars */
    assert_int_equal(hal_socketcan_open(&h, ifname, 0x80U), HAL_EINVAL);
    assert_int_equal(hal_socketcan_open(&h, "nosuchcan7", 0U), HAL_ENODEV);
    assert_int_equal(hal_socketcan_open(&h, "nosuchcan7", HAL_SOCKETCAN_RX_ONLY), HAL_ENODEV);
    /* lo exists but is no CAN interface: refused for sending by the guard,
     * and the kernel will not bind a CAN socket to it either. */
    assert_int_equal(hal_socketcan_open(&h, "lo", 0U), HAL_EPERM);
    assert_int_equal(hal_socketcan_open(&h, "lo", HAL_SOCKETCAN_RX_ONLY), HAL_ENODEV);
    assert_ptr_equal(h, (hal_can_t *)(uintptr_t)0xA5A5A5A5U); /* untouched on error */
    hal_socketcan_close(NULL);
}

static void test_virtual_interface_is_classified_virtual(void **state)
{
    (void)state;
    assert_int_equal(hal_socketcan_classify(ifname), HAL_SOCKETCAN_IF_VIRTUAL_CAN);
    assert_int_equal(hal_socketcan_check_send(ifname, 0U), 0);
}

static void test_rx_only_handle_receives_but_never_sends(void **state)
{
    (void)state;
    hal_can_t *tx = open_ok(0U);
    hal_can_t *ro = open_ok(HAL_SOCKETCAN_RX_ONLY);
    const pfe_can_frame_t f = frame(0x18FEF100UL | EFF, 8U, 0x30U);
    assert_int_equal(hal_can_send(ro, &f), HAL_EPERM);
    assert_int_equal(hal_can_send(tx, &f), 0);
    hal_can_rx_t rx;
    assert_int_equal(receive_wait(ro, &rx), 0);
    assert_int_equal(rx.frame.id, 0x98FEF100UL);
    assert_int_equal(rx.frame.data[7], 0x37U);
    hal_can_stats_t s;
    hal_can_get_stats(ro, &s);
    assert_int_equal(s.tx_frames, 0U);
    assert_int_equal(s.rx_frames, 1U);
    hal_socketcan_close(ro);
    hal_socketcan_close(tx);
}

static void test_filter_refuses_bits_outside_the_identifier(void **state)
{
    (void)state;
    hal_can_t *h = open_ok(0U);
    assert_int_equal(hal_can_add_filter(h, 0x40000000UL, 0x1FFFFFFFUL), HAL_EINVAL); /* RTR bit */
    assert_int_equal(hal_can_add_filter(h, 0x18FEF100UL | EFF, 0x20000000UL), HAL_EINVAL);
    assert_int_equal(hal_can_add_filter(NULL, 0U, 0U), HAL_EINVAL);
    assert_int_equal(hal_can_remove_filter(NULL, 0), HAL_EINVAL);
    hal_socketcan_close(h);
}

/* The kernel's receive time lies between the clock before send and the start
 * of the read 20 ms later (1 ms allowed for moving it from CLOCK_REALTIME),
 * and well before that read: stamped on arrival, not when read.
 *
 * Linux turns its receive stamping on for the first socket that asks for it
 * through a deferred work item (net_enable_timestamp(), net/core/dev.c): a
 * frame that reaches the socket before that work has run carries no stamp
 * and recvmsg() stamps it when read. On a busy machine the work runs late
 * (seen under make test-loaded: a frame stamped 0.14 ms before its read), so
 * probes are sent, each read 20 ms later, until one is stamped on arrival,
 * for up to 2 s; then the measured frame must be. A backend that used the
 * time of the read would never get past the probes. */
static uint32_t stamped_on_arrival(hal_can_t *tx, hal_can_t *rx, uint64_t *before_us,
                                   uint64_t *sent_us, uint64_t *read_us, uint64_t *stamp_us)
{
    const pfe_can_frame_t f = frame(0x0CF01300UL | EFF, 8U, 0U);
    const struct timespec pause = {0, 20000000L}; /* 20 ms */
    *before_us = mono_us();
    assert_int_equal(hal_can_send(tx, &f), 0);
    *sent_us = mono_us();
    (void)nanosleep(&pause, NULL);
    *read_us = mono_us();
    hal_can_rx_t r;
    assert_int_equal(receive_wait(rx, &r), 0);
    *stamp_us = r.timestamp_us;
    return (r.timestamp_us + 10000U <= *read_us) ? 1U : 0U;
}

static void test_timestamp_is_kernel_time_on_the_monotonic_clock(void **state)
{
    (void)state;
    hal_can_t *tx = open_ok(0U);
    hal_can_t *rx = open_ok(0U);
    uint64_t before = 0U;
    uint64_t sent = 0U;
    uint64_t read_start = 0U;
    uint64_t stamp = 0U;
    uint32_t probes = 0U;
    while ((stamped_on_arrival(tx, rx, &before, &sent, &read_start, &stamp) == 0U) &&
           (probes < 100U)) {
        probes++;
    }
    if (probes > 0U) {
        printf("# kernel receive stamping on after %u probe(s) stamped at their read\n",
               (unsigned)probes);
    }
    (void)stamped_on_arrival(tx, rx, &before, &sent, &read_start, &stamp);
    printf("# sent %llu..%llu us, stamped %llu us, read from %llu us\n",
           (unsigned long long)before, (unsigned long long)sent, (unsigned long long)stamp,
           (unsigned long long)read_start);
    ASSERT_GE(stamp + 1000U, before);
    ASSERT_LE(stamp + 10000U, read_start);
    hal_socketcan_close(rx);
    hal_socketcan_close(tx);
}

static void test_socket_polls_readable_when_a_frame_waits(void **state)
{
    (void)state;
    hal_can_t *tx = open_ok(0U);
    hal_can_t *rx = open_ok(0U);
    struct pollfd p = {hal_socketcan_fd(rx), POLLIN, 0};
    ASSERT_GE(p.fd, 0);
    assert_int_equal(poll(&p, 1U, 0), 0);
    const pfe_can_frame_t f = frame(0x123U, 0U, 0U);
    assert_int_equal(hal_can_send(tx, &f), 0);
    assert_int_equal(poll(&p, 1U, 2000), 1);
    assert_int_not_equal(p.revents & POLLIN, 0);
    assert_int_equal(hal_socketcan_fd(NULL), -1);
    hal_socketcan_close(rx);
    hal_socketcan_close(tx);
}

/* More frames than the receiver's socket buffer holds: the kernel drops the
 * excess and the handle counts it (SO_RXQ_OVFL), once a later frame gets
 * through. Every frame is either received or counted as dropped. */
static void test_receive_overflow_is_counted(void **state)
{
    (void)state;
    hal_can_t *tx = open_ok(0U);
    hal_can_t *rx = open_ok(0U);
    const uint32_t burst = 4000U;
    uint32_t sent = 0U;
    for (uint32_t k = 0U; k < burst; k++) {
        const pfe_can_frame_t f = frame(0x18FF0000UL | EFF, 4U, (uint8_t)k);
        const int rc = hal_can_send(tx, &f);
        if ((rc != 0) && (rc != HAL_EAGAIN)) {
            fail_msg("frame %u: hal_can_send returned %d, expected 0 or HAL_EAGAIN (%d)",
                     (unsigned)k, rc, HAL_EAGAIN);
        }
        sent += (rc == 0) ? 1U : 0U;
    }
    hal_can_rx_t r;
    uint32_t got = 0U;
    while (hal_can_receive(rx, &r) == 0) {
        got++;
    }
    /* One more frame, to carry the drop count. */
    const pfe_can_frame_t last = frame(0x7FFU, 1U, 0xEEU);
    assert_int_equal(hal_can_send(tx, &last), 0);
    assert_int_equal(receive_wait(rx, &r), 0);
    assert_int_equal(r.frame.id, 0x7FFU);
    got++;
    sent++;

    hal_can_stats_t srx;
    hal_can_stats_t stx;
    hal_can_get_stats(rx, &srx);
    hal_can_get_stats(tx, &stx);
    print_message("overflow: sent %u, received %u, rx_dropped %u, tx_dropped %u\n",
                  (unsigned)sent, (unsigned)got, (unsigned)srx.rx_dropped,
                  (unsigned)stx.tx_dropped);
    assert_int_equal(stx.tx_frames, sent);
    assert_int_equal(stx.tx_frames + stx.tx_dropped, burst + 1U);
    assert_int_equal(srx.rx_frames, got);
    ASSERT_GT(srx.rx_dropped, 0U);
    ASSERT_LT(got, sent);
    ASSERT_LE(got + srx.rx_dropped, sent);
    hal_socketcan_close(rx);
    hal_socketcan_close(tx);
}

int main(int argc, char **argv)
{
    if (argc > 2) {
        fprintf(stderr, "usage: %s [IFNAME]\n", argv[0]);
        return 2;
    }
    if (argc == 2) {
        ifname = argv[1];
    }
    if (if_nametoindex(ifname) == 0U) {
        const char *vm = getenv("VCAN_VM");
        if ((vm != NULL) && (strcmp(vm, "1") == 0)) {
            /* scripts/vcan_vm.sh's VM brings vcan0 and vcan1 up: not a skip. */
            printf("test_hal_socketcan: FAIL: no interface %s inside the vcan VM\n", ifname);
            return 1;
        }
        printf("test_hal_socketcan: SKIP: no interface %s here (a kernel without vcan?"
               " run it through scripts/vcan_vm.sh)\n", ifname);
        return 77;
    }

    char name[64];
    (void)snprintf(name, sizeof name, "hal_conformance(socketcan %s)", ifname);
    const hal_conformance_backend_t backend = {
        .name = name,
        .ctx = (void *)(uintptr_t)ifname,
        .open = sc_open,
        .close = sc_close,
        .idle = sc_idle,
        .max_idle = 2000U, /* 2 s: generous for a kernel under QEMU's TCG */
        .time = hal_time_posix(),
    };
    int failed = hal_conformance_run(&backend);

    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_open_refuses_bad_arguments),
        cmocka_unit_test(test_virtual_interface_is_classified_virtual),
        cmocka_unit_test(test_rx_only_handle_receives_but_never_sends),
        cmocka_unit_test(test_filter_refuses_bits_outside_the_identifier),
        cmocka_unit_test(test_timestamp_is_kernel_time_on_the_monotonic_clock),
        cmocka_unit_test(test_socket_polls_readable_when_a_frame_waits),
        cmocka_unit_test(test_receive_overflow_is_counted),
    };
    failed += cmocka_run_group_tests_name("hal_socketcan", tests, NULL, NULL);
    return failed;
}
