/*
 * pfe_ecu - the module's firmware as a Linux process on SocketCAN: the ECU
 * loop (firmware/pfe_ecu.h, through hal/hal_ecu_loop.h) every 10 ms on
 * CLOCK_MONOTONIC absolute deadlines (hal/posix/hal_time_posix.h), fuel
 * totals in a file.
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lib/cli_args.h"
#include "firmware/pfe_calib.h"
#include "firmware/pfe_ecu.h"
#include "firmware/pfe_fixed.h"
#include "firmware/pfe_nvm.h"
#include "hal/hal_can.h"
#include "hal/hal_ecu_loop.h"
#include "hal/posix/hal_nvm_file.h"
#include "hal/posix/hal_time_posix.h"
#include "hal/socketcan/hal_socketcan.h"
#include "lib/truck_cal.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: pfe_ecu --iface IF --nvm FILE [--address SA] [--save-interval-ms MS]\n"
    "               [--vehicles N --position P --gap-cm D] [--allow-real-bus]\n"
    "               [--duration-s S] [--calib FILE]\n"
    "\n"
    "The module's firmware as a Linux process on SocketCAN.\n"
    "\n"
    "  --iface IF             the CAN interface (virtual CAN: vcan, vxcan)\n"
    "  --nvm FILE             where the fuel totals are kept (created when missing)\n"
    "  --address SA           the source address claimed at start-up (default 0x8C)\n"
    "  --save-interval-ms MS  how often the totals are saved, 1000 .. 3600000\n"
    "                         (default 10000)\n"
    "  --vehicles N, --position P, --gap-cm D\n"
    "                         the platoon until a PFE_PlatoonConfig arrives\n"
    "                         (default 1 truck, position 0, 1000 cm)\n"
    "  --allow-real-bus       allow an interface that is not virtual CAN\n"
    "  --duration-s S         stop after S seconds (default: run until stopped)\n"
    "  --calib FILE           the truck's calibration file (default: the default\n"
    "                         calibration)\n"
    "  --help                 this help\n"
    "\n"
    "Every 10 ms, on CLOCK_MONOTONIC absolute deadlines, it receives every frame\n"
    "waiting on IF, ticks the ECU, sends what the tick produced and saves the fuel\n"
    "totals to FILE when due. After a stall (a busy machine) the missed ticks\n"
    "run at once, each with the frames received by its own deadline, so no fuel\n"
    "is lost; each tick run more than 10 ms late counts as an overrun. A stall of\n"
    "more than 1 s is given up on: its ticks are skipped and counted (\"ticks\n"
    "skipped\" at the end), and the schedule restarts from now. A frame the\n"
    "kernel would not take counts as a transmit drop. SIGINT or SIGTERM (Ctrl-C)\n"
    "stop it cleanly with a final save.\n"
    "\n"
    "It refuses an interface that is not virtual CAN unless given\n"
    "--allow-real-bus, and says which case it is: an empty name, no such\n"
    "interface, not a CAN interface (lo, eth0: refused even with\n"
    "--allow-real-bus), a real CAN bus without --allow-real-bus.\n"
    "\n"
    "Exit status: 0 after a clean stop; 1 on a runtime failure or a refused\n"
    "interface (missing, not CAN, a real bus without --allow-real-bus); 2 on bad\n"
    "arguments (an empty or over-long interface name too).\n"
    "\n"
    "Examples:\n"
    "  pfe_ecu --iface vcan0 --nvm fuel.nvm\n"
    "  pfe_ecu --iface can0 --nvm fuel.nvm --allow-real-bus --calib mytruck.cal\n";

static volatile sig_atomic_t g_stop;

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

/* Waits for the deadline; a signal cuts the wait short only to stop. */
static void sleep_until_us(hal_time_t *clock, uint64_t deadline)
{
    while ((hal_time_wait_until_us(clock, deadline) == HAL_EINTR) && !g_stop) {
    }
}

/* What interface IFACE is, said before anything is opened: 0 when the ECU
 * may send on it (virtual CAN, or real CAN with allow_real); else 2 for a
 * name that cannot be one, 1 for an interface that is missing or not CAN
 * or a real bus refused, each with its own message. */
static int check_iface(const char *iface, bool allow_real)
{
    if (iface[0] == '\0') {
        fprintf(stderr, "pfe_ecu: --iface needs an interface name, e.g. vcan0 (got an empty one)\n");
        return 2;
    }
    const int kind = hal_socketcan_classify(iface);
    switch (kind) {
    case HAL_SOCKETCAN_IF_VIRTUAL_CAN:
        return 0;
    case HAL_SOCKETCAN_IF_REAL_CAN:
        if (allow_real) {
            return 0;
        }
        fprintf(stderr, "pfe_ecu: refusing %s: it is a real CAN bus, not a virtual one (vcan, "
                        "vxcan); sending on a real bus needs --allow-real-bus\n", iface);
        return 1;
    case HAL_SOCKETCAN_IF_NOT_CAN:
        fprintf(stderr, "pfe_ecu: %s is not a CAN interface (the module needs vcan or vxcan; "
                        "with --allow-real-bus, a CAN bus)\n", iface);
        return 1;
    case HAL_ENODEV:
        fprintf(stderr, "pfe_ecu: no such interface %s (e.g. ip link add dev vcan0 type vcan)\n",
                iface);
        return 1;
    case HAL_EINVAL:
        fprintf(stderr, "pfe_ecu: '%s' cannot be an interface name (at most 15 characters)\n",
                iface);
        return 2;
    default:
        fprintf(stderr, "pfe_ecu: cannot ask the kernel what %s is (rtnetlink failed)\n", iface);
        return 1;
    }
}

static void usage(FILE *f)
{
    /* --help: the whole manual; a usage error: its synopsis. */
    if (f == stdout) {
        cli_help(k_manual);
    } else {
        cli_usage(f, k_manual, "pfe_ecu");
    }
}

int main(int argc, char **argv)
{
    const char *iface = NULL;
    const char *nvm_path = NULL;
    unsigned long address = PFE_ECU_DEFAULT_ADDRESS, interval = 10000U, vehicles = 1U;
    unsigned long position = 0U, gap_cm = 1000U, duration = 0U;
    unsigned flags = 0U;
    static truck_cal_t cal;
    bool have_cal = false;
    char cal_err[TRUCK_CAL_ERR_MAX];
    if (truck_cal_take_arg(&argc, argv, &cal, &have_cal, cal_err, sizeof cal_err) != 0) {
        fprintf(stderr, "pfe_ecu: %s\n", cal_err);
        return 2;
    }
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
        int bad = 0;
        if (strcmp(a, "--help") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--allow-real-bus") == 0) {
            flags |= HAL_SOCKETCAN_ALLOW_REAL_BUS;
            continue;
        } else if (v == NULL) {
            bad = 1;
        } else if (strcmp(a, "--iface") == 0) {
            iface = v;
        } else if (strcmp(a, "--nvm") == 0) {
            nvm_path = v;
        } else if (strcmp(a, "--address") == 0) {
            bad = cli_parse_ul(v, 0U, 253U, &address);
        } else if (strcmp(a, "--save-interval-ms") == 0) {
            bad = cli_parse_ul(v, 1000U, 3600000U, &interval);
        } else if (cli_platoon_option(a, v, &vehicles, &position, NULL, &bad)) {
            /* --vehicles, --position */
        } else if (strcmp(a, "--gap-cm") == 0) {
            bad = cli_parse_ul(v, 0U, 100000U, &gap_cm);
        } else if (strcmp(a, "--duration-s") == 0) {
            bad = cli_parse_ul(v, 1U, 86400U * 365U, &duration);
        } else {
            fprintf(stderr, "pfe_ecu: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        }
        if (bad) {
            fprintf(stderr, "pfe_ecu: option %s needs a valid value (got '%s')\n", a, v ? v : "nothing");
            return 2;
        }
        i++;
    }
    if ((iface == NULL) || (nvm_path == NULL) || (position >= vehicles)) {
        fprintf(stderr, "pfe_ecu: --iface and --nvm are required, and --position below --vehicles\n");
        usage(stderr);
        return 2;
    }
    const int if_rc = check_iface(iface, (flags & HAL_SOCKETCAN_ALLOW_REAL_BUS) != 0U);
    if (if_rc != 0) {
        return if_rc;
    }
    hal_can_t *can = NULL;
    int rc = hal_socketcan_open(&can, iface, flags);
    if (rc != 0) {
        fprintf(stderr, "pfe_ecu: cannot open %s: %s\n", iface,
                (rc == HAL_EPERM) ? "not a virtual CAN interface; sending on a real bus needs "
                                    "--allow-real-bus"
                : (rc == HAL_ENODEV) ? "no SocketCAN in this kernel (socket(PF_CAN) refused)"
                                     : "socket error (socket, setsockopt or bind failed)");
        return 1;
    }
    hal_nvm_t *nvm = NULL;
    if (hal_nvm_file_open(&nvm, nvm_path) != 0) {
        fprintf(stderr, "pfe_ecu: cannot open NVM file %s: %s\n", nvm_path, strerror(errno));
        hal_socketcan_close(can);
        return 1;
    }
    pfe_ecu_config_t cfg;
    hal_ecu_loop_config(&cfg, (uint8_t)address, (uint32_t)interval, (uint32_t)vehicles,
                        (uint32_t)position, (uint32_t)gap_cm * 10U);
    if (have_cal) {
        truck_cal_apply(&cal, &cfg);
    }
    static pfe_ecu_t ecu;
    static hal_ecu_loop_t loop;
    hal_time_t *clock = hal_time_posix();
    uint64_t t = hal_time_now_us(clock);
    if (hal_ecu_loop_init(&loop, &ecu, &cfg, can, nvm, t) != PFE_OK) {
        fprintf(stderr, "pfe_ecu: invalid configuration\n");
        hal_nvm_file_close(nvm);
        hal_socketcan_close(can);
        return 2;
    }
    fprintf(stderr, "pfe_ecu: %s, address 0x%02lX, restored %llu uL own / %llu uL platoon%s\n",
            iface, address, (unsigned long long)loop.restored.own_fuel_ul,
            (unsigned long long)loop.restored.platoon_fuel_ul,
            (loop.restored_slot < 0) ? " (no valid record)" : "");

    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);

    const uint64_t end = (duration > 0U) ? (t + ((uint64_t)duration * 1000000U)) : UINT64_MAX;
    uint64_t deadline = t;
    int status = 0;
    while (!g_stop && (deadline < end)) {
        (void)hal_ecu_loop_step(&loop, deadline);
        /* A late pass runs the missed ticks at once (hal_ecu_loop_pace()):
         * the wait below returns at once for a deadline already past. */
        (void)hal_ecu_loop_pace(&loop, &deadline, hal_time_now_us(clock));
        sleep_until_us(clock, deadline);
    }
    if (hal_ecu_loop_save(&loop) != 0) {
        fprintf(stderr, "pfe_ecu: final NVM write failed: %s\n", strerror(errno));
        status = 1;
    }
    fprintf(stderr, "pfe_ecu: stopped; %llu uL own / %llu uL platoon saved; rx %lu, tx %lu, "
                    "overruns %lu (ticks skipped %lu), rx dropped %lu, tx dropped %lu, NVM saves failed %lu\n",
            (unsigned long long)pfe_ecu_own_fuel_ul(&ecu),
            (unsigned long long)pfe_ecu_platoon_fuel_ul(&ecu), (unsigned long)ecu.count.rx_frames,
            (unsigned long)ecu.count.tx_frames, (unsigned long)ecu.count.overruns,
            (unsigned long)loop.skipped_ticks,
            (unsigned long)ecu.count.rx_dropped, (unsigned long)ecu.count.tx_dropped,
            (unsigned long)loop.nvm_failures);
    hal_nvm_file_close(nvm);
    hal_socketcan_close(can);
    return status;
}
