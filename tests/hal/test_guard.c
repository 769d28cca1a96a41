/*
 * test_guard.c - the SocketCAN backend's real-bus guard (hal_socketcan.h):
 * sending is allowed on virtual CAN only, unless the caller allows a real bus.
 *
 *   test_guard [VCAN]      (default vcan0)
 *
 * Runs on any Linux kernel: the loopback interface lo (not CAN at all) must
 * be refused, an interface that does not exist is HAL_ENODEV. Where the kernel
 * has them (scripts/vcan_vm.sh), VCAN must be allowed, and an slcan interface
 * on a pseudo-terminal, the driver of USB-serial CAN adapters and so as real
 * as CAN gets without hardware, must be refused. Nothing is ever sent on it.
 * Tests that need what this kernel lacks are skipped, not failed, except
 * inside scripts/vcan_vm.sh's VM (its init exports VCAN_VM=1), whose kernel
 * has vcan and slcan: there a missing one fails the test.
 */
#define _GNU_SOURCE

#include <errno.h>
#include <fcntl.h>
#include <net/if.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <linux/sockios.h>
#include <linux/tty.h>

#include <cmocka.h>

#include "hal/socketcan/hal_socketcan.h"

static const char *vcan = "vcan0";

/* What the test needs is missing: skipped on this kernel, a failure in the
 * VM, where it must be there. */
static void missing(const char *what)
{
    const char *vm = getenv("VCAN_VM");
    if ((vm != NULL) && (strcmp(vm, "1") == 0)) {
        fail_msg("%s inside the vcan VM (VCAN_VM=1), whose kernel must have it", what);
    }
    print_message("%s on this kernel: skipped\n", what);
    skip();
}

static void test_loopback_is_not_can_and_refused_for_sending(void **state)
{
    (void)state;
    assert_int_equal(hal_socketcan_classify("lo"), HAL_SOCKETCAN_IF_NOT_CAN);
    assert_int_equal(hal_socketcan_check_send("lo", 0U), HAL_EPERM);
    hal_can_t *h = NULL;
    assert_int_equal(hal_socketcan_open(&h, "lo", 0U), HAL_EPERM);
    assert_null(h);
    /* The guard has nothing against receiving, or an explicit permission. */
    assert_int_equal(hal_socketcan_check_send("lo", HAL_SOCKETCAN_RX_ONLY), 0);
    assert_int_equal(hal_socketcan_check_send("lo", HAL_SOCKETCAN_ALLOW_REAL_BUS), 0);
}

static void test_missing_interface_is_enodev(void **state)
{
    (void)state;
    assert_int_equal(hal_socketcan_classify("nosuchcan7"), HAL_ENODEV);
    assert_int_equal(hal_socketcan_check_send("nosuchcan7", 0U), HAL_ENODEV);
    assert_int_equal(hal_socketcan_check_send("nosuchcan7", HAL_SOCKETCAN_ALLOW_REAL_BUS),
                     HAL_ENODEV);
}

static void test_bad_names_are_einval(void **state)
{
    (void)state;
    assert_int_equal(hal_socketcan_classify(NULL), HAL_EINVAL);
    assert_int_equal(hal_socketcan_classify(""), HAL_EINVAL);
    assert_int_equal(hal_socketcan_classify("abcdefghijklmnop"), HAL_EINVAL); /* 16 chars */
    assert_int_equal(hal_socketcan_check_send(NULL, 0U), HAL_EINVAL);
}

static void test_vcan_is_virtual_and_allowed(void **state)
{
    (void)state;
    if (if_nametoindex(vcan) == 0U) {
        char what[64];
        (void)snprintf(what, sizeof what, "no interface %s", vcan);
        missing(what);
    }
    assert_int_equal(hal_socketcan_classify(vcan), HAL_SOCKETCAN_IF_VIRTUAL_CAN);
    assert_int_equal(hal_socketcan_check_send(vcan, 0U), 0);
    hal_can_t *h = NULL;
    assert_int_equal(hal_socketcan_open(&h, vcan, 0U), 0);
    hal_socketcan_close(h);
}

/* An slcan interface: a pseudo-terminal switched to the slcan line
 * discipline, as slcand does with a USB-serial adapter. Type CAN, kind not
 * vcan: a real bus as far as the guard can tell. */
static void test_slcan_is_real_and_refused_without_permission(void **state)
{
    (void)state;
    const int master = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
    if ((master < 0) || (grantpt(master) != 0) || (unlockpt(master) != 0)) {
        if (master >= 0) {
            (void)close(master);
        }
        missing("no pseudo-terminals");
    }
    const int tty = ioctl(master, TIOCGPTPEER, O_RDWR | O_NOCTTY | O_CLOEXEC);
    const int disc = N_SLCAN;
    char name[IFNAMSIZ + 1];
    memset(name, 0, sizeof name);
    if ((tty < 0) || (ioctl(tty, TIOCSETD, &disc) != 0) || (ioctl(tty, SIOCGIFNAME, name) != 0)) {
        const int e = errno;
        if (tty >= 0) {
            (void)close(tty);
        }
        (void)close(master);
        char what[96];
        (void)snprintf(what, sizeof what, "no slcan line discipline (%s)", strerror(e));
        missing(what);
    }

    const int kind = hal_socketcan_classify(name);
    const int send = hal_socketcan_check_send(name, 0U);
    hal_can_t *h = NULL;
    const int open_tx = hal_socketcan_open(&h, name, 0U);
    hal_can_t *ro = NULL;
    const int open_rx = hal_socketcan_open(&ro, name, HAL_SOCKETCAN_RX_ONLY);
    int ro_send = 0;
    if (ro != NULL) {
        /* Refused by the handle itself, before anything reaches the driver. */
        const pfe_can_frame_t f = {0x123U, 1U, {0x55U}};
        ro_send = hal_can_send(ro, &f);
        hal_socketcan_close(ro);
    }
    (void)close(tty); /* the line discipline goes, and the interface with it */
    (void)close(master);

    print_message("%s: kind %d, check_send %d, open %d, open RX_ONLY %d\n", name, kind, send,
                  open_tx, open_rx);
    assert_int_equal(kind, HAL_SOCKETCAN_IF_REAL_CAN);
    assert_int_equal(send, HAL_EPERM);
    assert_int_equal(open_tx, HAL_EPERM);
    assert_null(h);
    assert_int_equal(open_rx, 0);
    assert_int_equal(ro_send, HAL_EPERM);
}

int main(int argc, char **argv)
{
    if (argc > 2) {
        fprintf(stderr, "usage: %s [VCAN]\n", argv[0]);
        return 2;
    }
    if (argc == 2) {
        vcan = argv[1];
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_loopback_is_not_can_and_refused_for_sending),
        cmocka_unit_test(test_missing_interface_is_enodev),
        cmocka_unit_test(test_bad_names_are_einval),
        cmocka_unit_test(test_vcan_is_virtual_and_allowed),
        cmocka_unit_test(test_slcan_is_real_and_refused_without_permission),
    };
    return cmocka_run_group_tests_name("hal_socketcan_guard", tests, NULL, NULL);
}
