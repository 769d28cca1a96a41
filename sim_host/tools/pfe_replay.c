/*
 * pfe_replay - replay a CAN log onto SocketCAN interfaces, paced by its
 * timestamps on CLOCK_MONOTONIC absolute deadlines; canplayer's options and
 * more. The manual (every option, the exit status, examples) is its --help,
 * k_manual below; docs/harness.md says how its pacing was chosen and tested.
 */
#define _GNU_SOURCE /* clock_nanosleep, sigaction */

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/raw.h>

#include "hal/socketcan/hal_socketcan.h"
#include "firmware/pfe_can.h"
#include "lib/log/log.h"
#include "lib/lateness.h"
#include "lib/cli_help.h"

#define EXIT_INPUT 1
#define EXIT_REFUSED 2
#define EXIT_USAGE 3
#define EXIT_DROPPED 4
#define EXIT_STOPPED 130

#define MAX_TARGETS 32U
#define MAX_FILTERS 32U
#define OUT_BUF_SIZE 65536U
#define PROGRESS_PERIOD_NS 250000000LL

typedef struct {
    char log_if[CANLOG_IFNAME_MAX];
    char tx_if[CANLOG_IFNAME_MAX];
    int ifindex;
    bool to_stdout;
    bool skip; /* unknown interface, --skip-unknown */
} target_t;

typedef struct {
    uint32_t id;   /* with CANLOG_EFF_FLAG for 29-bit */
    uint32_t mask;
    bool pgn;      /* match the J1939 PGN instead */
} filter_t;

typedef struct {
    /* options */
    const char *path;
    unsigned long loops;     /* 0: endless */
    bool ignore_ts;
    int64_t gap_ns;
    int64_t skip_gap_us;     /* 0: off */
    uint64_t max_frames;     /* 0: no limit */
    bool no_loopback;
    bool verbose;
    double speed;
    int64_t start_us;
    int64_t end_us;          /* < 0: none */
    filter_t filters[MAX_FILTERS];
    unsigned n_filters;
    bool dry_run;
    canlog_format_t format;
    bool skip_errors;
    bool skip_unknown;
    int64_t tx_wait_ns;
    int64_t spin_ns;
    int64_t poll_ns;
    bool allow_real_bus;
    bool quiet;
    target_t targets[MAX_TARGETS];
    unsigned n_targets;
    bool assigned;           /* targets came from the command line */
    /* state */
    int sock;
    bool fd_enabled;
    unsigned last_target;
    char out[OUT_BUF_SIZE];
    size_t out_len;
    bool progress;
    off_t file_size;
    int64_t next_progress_ns;
    unsigned long pass;
    /* results */
    uint64_t sent;
    uint64_t written;
    uint64_t skipped;
    uint64_t dropped;
    uint64_t dropped_down;  /* of dropped: the interface was down */
    lateness_hist_t late;
} replay_t;

static volatile sig_atomic_t g_stop;

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

/* ------------------------------------------------------------------ helpers */

static int64_t now_ns(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return ((int64_t)ts.tv_sec * 1000000000LL) + ts.tv_nsec;
}

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
        "usage: pfe_replay [-I FILE] [-l N|i] [-t] [-g MS] [-s S] [-n COUNT] [-x] [-v]\n"
        "                  [--speed F] [--start S] [--end S] [--filter ID[:MASK]]...\n"
        "                  [--pgn PGN]... [--dry-run] [--format auto|log|printed|printed-delta|asc]\n"
        "                  [--skip-errors] [--skip-unknown] [--tx-wait-ms MS] [--spin-us US] [--poll-us US]\n"
        "                  [--allow-real-bus] [--quiet] [TX=LOG | stdout=LOG]...\n"
        "\n"
        "Replays a CAN log onto SocketCAN interfaces, paced by its timestamps on\n"
        "CLOCK_MONOTONIC absolute deadlines. The log: a candump log, candump's printed\n"
        "output or a Vector ASC file, detected from its first lines.\n"
        "\n"
        "canplayer's options (same letters and meaning, -g as said below):\n"
        "  -I FILE     the log; default, or \"-\": standard input\n"
        "  -l N | -l i play the log N times, or endlessly; not with standard input\n"
        "  -t          ignore timestamps: frames go one after another, -g apart\n"
        "  -g MS       with -t, the gap between frames in milliseconds (decimals\n"
        "              allowed; default 0: as fast as the kernel takes them).\n"
        "              Without -t it is accepted and unused: frames are paced by\n"
        "              deadlines, not by a polling period.\n"
        "  -s S        skip gaps: a pause of more than S seconds between two frames\n"
        "              of the log is cut out (the next frame goes at once)\n"
        "  -n COUNT    stop after COUNT frames sent or written\n"
        "  -x          disable local loopback of the frames sent (CAN_RAW_LOOPBACK\n"
        "              off: other programs of this machine do not see them)\n"
        "  -v          print each frame sent on standard output, as a candump log\n"
        "              line with the interface it went to\n"
        "  -h, --help  this help\n"
        "\n"
        "TX=LOG assignments: frames logged on interface LOG are sent on TX\n"
        "(vcan0=can0: a log of can0 onto vcan0); TX \"stdout\" writes them to standard\n"
        "output as candump log lines with LOG as interface (canplayer's extra hook;\n"
        "in canonical form: upper-case hex, no '.' between bytes). With assignments,\n"
        "frames of interfaces not assigned are skipped; without, each frame goes to\n"
        "the interface it was logged on. An ASC file's channel N is interface can<N-1>.\n"
        "\n"
        "Options of this tool:\n"
        "  --speed F         F times as fast as logged (0.5: half speed); default 1\n"
        "  --start S         only frames from S seconds after the log's first frame\n"
        "  --end S           ... up to S seconds after it (reading stops there)\n"
        "  --filter ID[:MASK]  only frames whose id matches: (id & MASK) == (ID & MASK),\n"
        "                    hex; an ID of more than 3 digits or over 7FF is 29-bit and\n"
        "                    matches 29-bit frames only. Repeatable.\n"
        "  --pgn PGN         only 29-bit frames of J1939 PGN (decimal, or hex with 0x),\n"
        "                    priority, source and PDU1 destination ignored. Repeatable;\n"
        "                    a frame passes if it matches any --filter or --pgn.\n"
        "  --dry-run         send nothing: write each frame to standard output as a\n"
        "                    candump log line, with the interface it would go to\n"
        "                    (with -t, a converter: ASC or printed output to log)\n"
        "  --format F        auto (default), log, printed, printed-delta, asc\n"
        "  --skip-errors     skip bad lines and count them (default: stop at the first,\n"
        "                    with its file, line and reason, exit 1; frames before it\n"
        "                    have been sent)\n"
        "  --skip-unknown    skip frames for interfaces that do not exist, instead of\n"
        "                    stopping\n"
        "  --tx-wait-ms MS   how long one frame may wait for room when the kernel's\n"
        "                    transmit queue is full (ENOBUFS, EAGAIN) before it is\n"
        "                    dropped and counted; default 100\n"
        "  --spin-us US      sleep until US microseconds before each deadline, then\n"
        "                    busy-wait for it: lateness of a few microseconds where the\n"
        "                    kernel wakes sleepers late (virtual machines), for a CPU\n"
        "                    kept busy up to US per frame; default 200; 0 sleeps only\n"
        "  --poll-us US      sleep in steps of at most US microseconds (each to an\n"
        "                    absolute time) up to the spin; default 0 (one sleep)\n"
        "  --allow-real-bus  allow sending on CAN interfaces that are not virtual\n"
        "  --quiet           no progress line\n"
        "\n"
        "Real-bus guard: a frame goes only to a virtual CAN interface (vcan, vxcan),\n"
        "unless --allow-real-bus. Any other interface (a CAN adapter, slcan, or not\n"
        "CAN at all, e.g. lo) is refused before a single frame goes to it (exit 2).\n"
        "\n"
        "Pacing: frame k is due at T0 + (t_k - t_first - start - cut gaps) / speed,\n"
        "T0 the CLOCK_MONOTONIC time the pass began; the replayer sleeps until\n"
        "--spin-us before then (clock_nanosleep, TIMER_ABSTIME), busy-waits the rest\n"
        "and sends. Lateness is the CLOCK_MONOTONIC time after the send returned minus\n"
        "the deadline; with -t and no -g there is no deadline and no lateness. Each\n"
        "pass of -l starts afresh. A log without timestamps (candump output without\n"
        "-t) is sent as with -t.\n"
        "\n"
        "At the end (also after Ctrl-C), a summary on standard error: frames sent,\n"
        "written to standard output, skipped (filters, --start, unassigned or unknown\n"
        "interfaces), dropped (transmit queue full, or the interface down), parse\n"
        "errors by reason with the first of each, and lateness p50 / p99 / max. While\n"
        "it runs, a progress line on standard error when that is a terminal.\n"
        "\n"
        "Exit status:\n"
        "  0    done: every frame sent or written (lines skipped by --skip-errors do\n"
        "       not change it, unless no frame at all could be read: 1)\n"
        "  1    input or system error: unreadable or empty log, a bad line (without\n"
        "       --skip-errors), no such interface, a socket error\n"
        "  2    refused: an interface that is not virtual CAN, without --allow-real-bus\n"
        "  3    usage error\n"
        "  4    done, but frames were dropped (transmit queue full beyond --tx-wait-ms,\n"
        "       or the interface down: counted, the run goes on)\n"
        "  130  stopped by SIGINT or SIGTERM (the summary is printed)\n"
        "\n"
        "Examples:\n"
        "  pfe_replay -I drive.log                  # onto the interfaces it was logged on\n"
        "  pfe_replay -I trip.asc vcan0=can0 --speed 2\n"
        "                                           # ASC channel 1 (can0) onto vcan0, twice as fast\n"
        "  pfe_replay -I drive.log --pgn 65265 --start 60 --end 120 --dry-run\n"
        "                                           # CCVS1 of the second minute, to standard output\n"
        "  pfe_replay -I trip.asc -t --dry-run > trip.log\n"
        "                                           # any format to a candump log\n"
        "\n"
        "More: docs/harness.md (pacing, how it is tested).\n";

static void usage(FILE *f)
{
    cli_usage(f, k_manual, "pfe_replay");
}

/* A decimal number (digits, optional fraction) >= 0 into *out. */
static int parse_nonneg(const char *s, double *out)
{
    if ((s == NULL) || (*s == '\0') || (*s == '-') || (*s == '+')) {
        return -1;
    }
    char *end = NULL;
    errno = 0;
    const double v = strtod(s, &end);
    if ((errno != 0) || (*end != '\0') || !(v >= 0.0) || (v > 1e12)) {
        return -1;
    }
    *out = v;
    return 0;
}

static int parse_u64(const char *s, int base, uint64_t max, uint64_t *out)
{
    if ((s == NULL) || (*s == '\0') || (*s == '-') || (*s == '+')) {
        return -1;
    }
    char *end = NULL;
    errno = 0;
    const unsigned long long v = strtoull(s, &end, base);
    if ((errno != 0) || (*end != '\0') || (v > max)) {
        return -1;
    }
    *out = v;
    return 0;
}

static bool frame_selected(const replay_t *rp, const canlog_frame_t *f)
{
    if (rp->n_filters == 0U) {
        return true;
    }
    if ((f->id & CANLOG_ERR_FLAG) != 0U) {
        return false;
    }
    const bool eff = (f->id & CANLOG_EFF_FLAG) != 0U;
    const uint32_t raw = f->id & (eff ? CANLOG_EFF_MASK : CANLOG_SFF_MASK);
    for (unsigned i = 0U; i < rp->n_filters; i++) {
        const filter_t *flt = &rp->filters[i];
        if (flt->pgn) {
            if (eff && (pfe_j1939_pgn(raw) == flt->id)) {
                return true;
            }
        } else if ((eff == ((flt->id & CANLOG_EFF_FLAG) != 0U)) &&
                   ((raw & flt->mask) == (flt->id & ~CANLOG_EFF_FLAG & flt->mask))) {
            return true;
        }
    }
    return false;
}

/* ------------------------------------------------------------------ output */

static void out_flush(replay_t *rp)
{
    size_t done = 0U;
    while (done < rp->out_len) {
        const ssize_t n = write(STDOUT_FILENO, rp->out + done, rp->out_len - done);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            /* standard output gone (a closed pipe): nothing more to show */
            break;
        }
        done += (size_t)n;
    }
    rp->out_len = 0U;
}

static void out_frame(replay_t *rp, const canlog_frame_t *f, const char *iface)
{
    if (rp->out_len + CANLOG_LOG_LINE_MAX > OUT_BUF_SIZE) {
        out_flush(rp);
    }
    rp->out_len += canlog_write_log(rp->out + rp->out_len, OUT_BUF_SIZE - rp->out_len, f, iface);
}

static void progress(replay_t *rp, const canlog_reader_t *r, int64_t now, bool final)
{
    if (!rp->progress) {
        return;
    }
    if (!final && (now < rp->next_progress_ns)) {
        return;
    }
    rp->next_progress_ns = now + PROGRESS_PERIOD_NS;
    char pct[16] = "";
    if (rp->file_size > 0) {
        (void)snprintf(pct, sizeof pct, "%3.0f%% ",
                       100.0 * (double)r->consumed_bytes / (double)rp->file_size);
    }
    fprintf(stderr, "\rpfe_replay: pass %lu %s%llu sent, %llu skipped, %llu dropped   ", rp->pass,
            pct, (unsigned long long)rp->sent, (unsigned long long)rp->skipped,
            (unsigned long long)rp->dropped);
    if (final) {
        fputc('\n', stderr);
    }
}

/* ------------------------------------------------------------------ targets */

/* Parses "TX=LOG". */
static int add_assignment(replay_t *rp, const char *arg)
{
    const char *eq = strchr(arg, '=');
    if ((eq == NULL) || (eq == arg) || (eq[1] == '\0')) {
        fprintf(stderr, "pfe_replay: '%s': an assignment is TX=LOG, e.g. vcan0=can0\n", arg);
        return -1;
    }
    const size_t txlen = (size_t)(eq - arg);
    const size_t loglen = strlen(eq + 1);
    if ((txlen >= CANLOG_IFNAME_MAX) || (loglen >= CANLOG_IFNAME_MAX)) {
        fprintf(stderr, "pfe_replay: '%s': interface names have at most %u characters\n", arg,
                CANLOG_IFNAME_MAX - 1U);
        return -1;
    }
    if (rp->n_targets == MAX_TARGETS) {
        fprintf(stderr, "pfe_replay: more than %u assignments\n", MAX_TARGETS);
        return -1;
    }
    target_t *t = &rp->targets[rp->n_targets];
    memset(t, 0, sizeof *t);
    memcpy(t->tx_if, arg, txlen);
    memcpy(t->log_if, eq + 1, loglen);
    for (unsigned i = 0U; i < rp->n_targets; i++) {
        if (strcmp(rp->targets[i].log_if, t->log_if) == 0) {
            fprintf(stderr, "pfe_replay: log interface %s assigned twice\n", t->log_if);
            return -1;
        }
    }
    t->to_stdout = strcmp(t->tx_if, "stdout") == 0;
    rp->n_targets++;
    rp->assigned = true;
    return 0;
}

static int open_socket(replay_t *rp)
{
    rp->sock = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
    if (rp->sock < 0) {
        fprintf(stderr, "pfe_replay: cannot open a CAN socket: %s%s\n", strerror(errno),
                (errno == EAFNOSUPPORT) ? " (this kernel has no SocketCAN)" : "");
        return EXIT_INPUT;
    }
    /* never receives: no filter at all */
    (void)setsockopt(rp->sock, SOL_CAN_RAW, CAN_RAW_FILTER, NULL, 0);
    const int on = 1;
    rp->fd_enabled =
        setsockopt(rp->sock, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) == 0;
    if (rp->no_loopback) {
        const int off = 0;
        if (setsockopt(rp->sock, SOL_CAN_RAW, CAN_RAW_LOOPBACK, &off, sizeof off) != 0) {
            fprintf(stderr, "pfe_replay: cannot disable loopback: %s\n", strerror(errno));
            return EXIT_INPUT;
        }
    }
    struct sockaddr_can addr;
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    addr.can_ifindex = 0; /* any interface: sendto names each */
    if (bind(rp->sock, (const struct sockaddr *)&addr, sizeof addr) != 0) {
        fprintf(stderr, "pfe_replay: cannot bind the CAN socket: %s\n", strerror(errno));
        return EXIT_INPUT;
    }
    return 0;
}

/* Checks a CAN target against the real-bus guard and finds its index.
 * Returns 0, or an exit status. */
static int check_target(replay_t *rp, target_t *t)
{
    const unsigned flags = rp->allow_real_bus ? HAL_SOCKETCAN_ALLOW_REAL_BUS : 0U;
    const int rc = hal_socketcan_check_send(t->tx_if, flags);
    if (rc == HAL_EPERM) {
        const int kind = hal_socketcan_classify(t->tx_if);
        fprintf(stderr,
                "pfe_replay: refusing to send on %s: %s. Only virtual CAN (vcan, vxcan) is "
                "allowed unless --allow-real-bus is given.\n",
                t->tx_if,
                (kind == HAL_SOCKETCAN_IF_NOT_CAN) ? "it is not a CAN interface"
                                                   : "it is a real CAN bus, not a virtual one");
        return EXIT_REFUSED;
    }
    if (rc == 0) {
        if (hal_socketcan_classify(t->tx_if) == HAL_SOCKETCAN_IF_NOT_CAN) {
            fprintf(stderr, "pfe_replay: %s is not a CAN interface\n", t->tx_if);
            return EXIT_INPUT;
        }
        const unsigned idx = if_nametoindex(t->tx_if);
        if ((idx == 0U) || (idx > (unsigned)INT_MAX)) {
            fprintf(stderr, "pfe_replay: %s: %s\n", t->tx_if, strerror(errno));
            return EXIT_INPUT;
        }
        t->ifindex = (int)idx;
        if (rp->sock < 0) {
            return open_socket(rp);
        }
        return 0;
    }
    if ((rc == HAL_ENODEV) && rp->skip_unknown) {
        fprintf(stderr, "pfe_replay: no interface %s: its frames are skipped\n", t->tx_if);
        t->skip = true;
        return 0;
    }
    fprintf(stderr, "pfe_replay: cannot send on %s: %s\n", t->tx_if,
            (rc == HAL_ENODEV) ? "no such interface (or no SocketCAN in this kernel); "
                                 "map the log's interfaces with TX=LOG, e.g. vcan0=can0"
            : (rc == HAL_EINVAL) ? "bad interface name"
                                 : "cannot query the interface (rtnetlink)");
    return EXIT_INPUT;
}

/* The target of frame F, or NULL when its interface is not assigned. Sets
 * *status on an error (a refused or unknown interface). */
static target_t *find_target(replay_t *rp, const canlog_frame_t *f, int *status)
{
    *status = 0;
    if (rp->last_target < rp->n_targets) {
        target_t *t = &rp->targets[rp->last_target];
        if (strcmp(t->log_if, f->iface) == 0) {
            return t;
        }
    }
    for (unsigned i = 0U; i < rp->n_targets; i++) {
        if (strcmp(rp->targets[i].log_if, f->iface) == 0) {
            rp->last_target = i;
            return &rp->targets[i];
        }
    }
    if (rp->assigned) {
        return NULL;
    }
    /* no assignments: the frame goes where it was logged */
    if (rp->n_targets == MAX_TARGETS) {
        fprintf(stderr, "pfe_replay: the log has more than %u interfaces\n", MAX_TARGETS);
        *status = EXIT_INPUT;
        return NULL;
    }
    target_t *t = &rp->targets[rp->n_targets];
    memset(t, 0, sizeof *t);
    memcpy(t->log_if, f->iface, sizeof t->log_if);
    memcpy(t->tx_if, f->iface, sizeof t->tx_if);
    rp->last_target = rp->n_targets;
    rp->n_targets++;
    if (!rp->dry_run) {
        *status = check_target(rp, t);
        if (*status != 0) {
            return NULL;
        }
    }
    return t;
}

/* ------------------------------------------------------------------ send */

/* Sends F on T. Returns 1 sent, 0 dropped (queue full for too long), or an
 * exit status (negated) on a socket error. */
static int send_frame(replay_t *rp, const target_t *t, const canlog_frame_t *f)
{
    struct canfd_frame fr;
    memset(&fr, 0, sizeof fr);
    fr.can_id = f->id;
    size_t mtu = CAN_MTU;
    if (f->fd) {
        if (!rp->fd_enabled) {
            fprintf(stderr, "pfe_replay: line %llu: CAN FD frame, but the socket has no CAN FD\n",
                    (unsigned long long)f->line);
            return -EXIT_INPUT;
        }
        mtu = CANFD_MTU;
        fr.flags = f->fd_flags;
        fr.len = f->len;
        memcpy(fr.data, f->data, f->len);
    } else {
        fr.len = f->len;
        if ((f->id & CAN_RTR_FLAG) == 0U) {
            memcpy(fr.data, f->data, f->len);
        }
    }
    struct sockaddr_can addr;
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    addr.can_ifindex = t->ifindex;
    int64_t give_up_ns = -1;
    for (;;) {
        const ssize_t n = sendto(rp->sock, &fr, mtu, MSG_DONTWAIT, (const struct sockaddr *)&addr,
                                 sizeof addr);
        if (n == (ssize_t)mtu) {
            return 1;
        }
        if (n >= 0) {
            fprintf(stderr, "pfe_replay: short send on %s\n", t->tx_if);
            return -EXIT_INPUT;
        }
        if (errno == EINTR) {
            if (g_stop) {
                return 0;
            }
            continue;
        }
        if (errno == ENETDOWN) {
            /* The interface is down (it may come back): the frame is lost
             * like one that found the queue full, and the run goes on. */
            if (rp->dropped_down == 0U) {
                fprintf(stderr, "pfe_replay: %s is down (line %llu): dropping frames until it is up\n",
                        t->tx_if, (unsigned long long)f->line);
            }
            rp->dropped_down++;
            return 0;
        }
        if ((errno != ENOBUFS) && (errno != EAGAIN)) {
            fprintf(stderr, "pfe_replay: send on %s failed (line %llu): %s\n", t->tx_if,
                    (unsigned long long)f->line, strerror(errno));
            return -EXIT_INPUT;
        }
        /* transmit queue full: wait for room, a bounded time in all */
        const int64_t now = now_ns();
        if (give_up_ns < 0) {
            give_up_ns = now + rp->tx_wait_ns;
        }
        if ((now >= give_up_ns) || g_stop) {
            return 0;
        }
        int wait_ms = (int)((give_up_ns - now + 999999LL) / 1000000LL);
        if (wait_ms > 1) {
            wait_ms = 1;
        }
        struct pollfd pfd = {rp->sock, POLLOUT, 0};
        const int pr = poll(&pfd, 1U, wait_ms);
        if (pr > 0) {
            /* The socket may report room while the interface's queue is
             * still full (ENOBUFS comes from there): do not spin. */
            const struct timespec pause = {0, 100000L};
            (void)nanosleep(&pause, NULL);
        }
    }
}

/* Sleeps until DEADLINE_NS (CLOCK_MONOTONIC), the last SPIN_NS of it
 * busy-waiting, or until a signal stops the run. With POLL_NS > 0 the sleep
 * goes in steps of at most POLL_NS, each to an absolute time. */
static void sleep_until(int64_t deadline_ns, int64_t spin_ns, int64_t poll_ns)
{
    const int64_t wake_ns = deadline_ns - spin_ns;
    while (!g_stop) {
        int64_t until_ns = wake_ns;
        if (poll_ns > 0) {
            const int64_t step_ns = now_ns() + poll_ns;
            until_ns = (step_ns < wake_ns) ? step_ns : wake_ns;
        }
        struct timespec ts;
        ts.tv_sec = (time_t)(until_ns / 1000000000LL);
        ts.tv_nsec = (long)(until_ns % 1000000000LL);
        const int rc = clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
        if ((rc != EINTR) && (until_ns == wake_ns)) {
            break;
        }
    }
    if (spin_ns > 0) {
        while (!g_stop && (now_ns() < deadline_ns)) {
        }
    }
}

/* ------------------------------------------------------------------ one pass */

typedef enum { PASS_DONE = 0, PASS_STOP = 1 } pass_end_t;

/* One pass over the log. Returns PASS_DONE at its end, PASS_STOP when the
 * run must end (signal, -n reached), or a negated exit status. */
static int run_pass(replay_t *rp, canlog_reader_t *r)
{
    canlog_frame_t f;
    bool first = true;
    bool anchored = false;
    uint64_t log_anchor_us = 0U;
    uint64_t prev_t = 0U;
    int64_t cut_us = 0;
    int64_t t0_ns = now_ns();
    int64_t prev_deadline = t0_ns;
    bool sent_any = false;
    for (;;) {
        if (g_stop) {
            return PASS_STOP;
        }
        const int rc = canlog_next(r, &f);
        if (rc == 0) {
            return PASS_DONE;
        }
        if (rc < 0) {
            fprintf(stderr, "pfe_replay: %s\n", canlog_message(r));
            return -EXIT_INPUT;
        }
        if (first) {
            first = false;
            log_anchor_us = f.time_us + (uint64_t)rp->start_us;
            prev_t = f.time_us;
        }
        /* Gaps are judged between consecutive frames of the log; only the
         * part after the start point is cut (the schedule begins there). */
        if ((rp->skip_gap_us > 0) && ((int64_t)(f.time_us - prev_t) > rp->skip_gap_us) &&
            (f.time_us > log_anchor_us)) {
            cut_us += (int64_t)(f.time_us - ((prev_t > log_anchor_us) ? prev_t : log_anchor_us));
        }
        prev_t = f.time_us;
        if (f.time_us < log_anchor_us) {
            rp->skipped++;
            continue;
        }
        if ((rp->end_us >= 0) &&
            ((f.time_us - (log_anchor_us - (uint64_t)rp->start_us)) > (uint64_t)rp->end_us)) {
            return PASS_DONE;
        }
        if (!frame_selected(rp, &f)) {
            rp->skipped++;
            continue;
        }
        const char *out_if = f.iface;
        target_t *t = NULL;
        if (!rp->dry_run || rp->assigned) {
            int status = 0;
            t = find_target(rp, &f, &status);
            if (status != 0) {
                return -status;
            }
            if ((t == NULL) || t->skip) {
                rp->skipped++;
                continue;
            }
            out_if = t->to_stdout ? f.iface : t->tx_if;
        }
        /* when */
        const bool timed = !rp->ignore_ts && (canlog_time_base(r) != CANLOG_TB_NONE);
        int64_t deadline;
        if (timed) {
            if (!anchored) {
                anchored = true;
                t0_ns = now_ns();
            }
            const int64_t dt_us = (int64_t)(f.time_us - log_anchor_us) - cut_us;
            const double scaled_ns = (double)dt_us * 1000.0 / rp->speed;
            deadline = t0_ns + (int64_t)scaled_ns;
        } else {
            deadline = sent_any ? (prev_deadline + rp->gap_ns) : now_ns();
        }
        prev_deadline = deadline;
        const bool measured = timed || (rp->gap_ns > 0);
        int64_t now = 0;
        if (measured) {
            now = now_ns();
            progress(rp, r, now, false);
            if (deadline > now) {
                if (rp->out_len > 0U) {
                    out_flush(rp);
                }
                sleep_until(deadline, rp->spin_ns, rp->poll_ns);
                if (g_stop) {
                    return PASS_STOP;
                }
            }
        } else if (rp->progress && ((rp->sent + rp->written) % 1024U == 0U)) {
            progress(rp, r, now_ns(), false);
        }
        /* send */
        bool done = true;
        if (rp->dry_run || t->to_stdout) {
            out_frame(rp, &f, out_if);
            rp->written++;
        } else {
            const int s = send_frame(rp, t, &f);
            if (s < 0) {
                return s;
            }
            if (s == 0) {
                rp->dropped++;
                done = false;
            } else {
                rp->sent++;
                if (rp->verbose) {
                    out_frame(rp, &f, t->tx_if);
                }
            }
        }
        sent_any = true;
        if (done && measured) {
            const int64_t late = now_ns() - deadline;
            lateness_add(&rp->late, (late > 0) ? (uint64_t)(late / 1000) : 0U);
        }
        if ((rp->max_frames > 0U) && ((rp->sent + rp->written) >= rp->max_frames)) {
            return PASS_STOP;
        }
    }
}

/* ------------------------------------------------------------------ summary */

static void summary(const replay_t *rp, const canlog_reader_t *r, double elapsed_s)
{
    fprintf(stderr,
            "pfe_replay: %llu sent, %llu written to stdout, %llu skipped, %llu dropped (%llu with "
            "the interface down), %llu parse errors (%llu line%s, %lu pass%s, %.1f s)\n",
            (unsigned long long)rp->sent, (unsigned long long)rp->written,
            (unsigned long long)rp->skipped, (unsigned long long)rp->dropped,
            (unsigned long long)rp->dropped_down,
            (unsigned long long)r->error_lines, (unsigned long long)r->lines,
            (r->lines == 1U) ? "" : "s", rp->pass,
            (rp->pass == 1U) ? "" : "es", elapsed_s);
    for (int i = 1; i < (int)CANLOG_REASON_COUNT; i++) {
        if (r->errors[i] > 0U) {
            fprintf(stderr, "pfe_replay:   %llu x %s, the first: %s\n",
                    (unsigned long long)r->errors[i], canlog_reason_text(i), r->first_msg[i]);
        }
    }
    if (rp->late.count > 0U) {
        fprintf(stderr, "pfe_replay: lateness p50 %llu us, p99 %llu us, max %llu us (%llu frames)\n",
                (unsigned long long)lateness_percentile_us(&rp->late, 500U),
                (unsigned long long)lateness_percentile_us(&rp->late, 990U),
                (unsigned long long)rp->late.max_us, (unsigned long long)rp->late.count);
    } else {
        fprintf(stderr, "pfe_replay: lateness not measured (no paced frames)\n");
    }
}

/* ------------------------------------------------------------------ options */

static int parse_filter(replay_t *rp, const char *arg, bool pgn)
{
    if (rp->n_filters == MAX_FILTERS) {
        fprintf(stderr, "pfe_replay: more than %u filters\n", MAX_FILTERS);
        return -1;
    }
    filter_t *flt = &rp->filters[rp->n_filters];
    uint64_t v = 0U;
    if (pgn) {
        const bool hex = (arg[0] == '0') && ((arg[1] == 'x') || (arg[1] == 'X'));
        if (parse_u64(hex ? arg + 2 : arg, hex ? 16 : 10, 0x3FFFFU, &v) != 0) {
            fprintf(stderr, "pfe_replay: --pgn %s: a PGN is 0 to 262143 (0x3FFFF)\n", arg);
            return -1;
        }
        flt->pgn = true;
        flt->id = (((v >> 8) & 0xFFU) < 240U) ? (uint32_t)(v & 0x3FF00U) : (uint32_t)v;
        flt->mask = 0U;
    } else {
        char idtext[16];
        const char *colon = strchr(arg, ':');
        const size_t idlen = (colon != NULL) ? (size_t)(colon - arg) : strlen(arg);
        if ((idlen == 0U) || (idlen >= sizeof idtext)) {
            fprintf(stderr, "pfe_replay: --filter %s: expected ID[:MASK] in hex\n", arg);
            return -1;
        }
        memcpy(idtext, arg, idlen);
        idtext[idlen] = '\0';
        uint64_t mask = 0x1FFFFFFFU;
        if ((parse_u64(idtext, 16, 0x1FFFFFFFU, &v) != 0) ||
            ((colon != NULL) && (parse_u64(colon + 1, 16, 0x1FFFFFFFU, &mask) != 0))) {
            fprintf(stderr, "pfe_replay: --filter %s: expected ID[:MASK] in hex, at most 1FFFFFFF\n",
                    arg);
            return -1;
        }
        const bool eff = (idlen > 3U) || (v > 0x7FFU);
        flt->pgn = false;
        flt->id = (uint32_t)v | (eff ? CANLOG_EFF_FLAG : 0U);
        flt->mask = (uint32_t)mask & (eff ? CANLOG_EFF_MASK : CANLOG_SFF_MASK);
    }
    rp->n_filters++;
    return 0;
}

static bool takes_value(const char *opt)
{
    static const char *const names[] = {"-I",      "-l",       "-g",    "-s",
                                        "-n",      "--speed",  "--start", "--end",
                                        "--filter", "--pgn",   "--format", "--tx-wait-ms",
                                        "--spin-us", "--poll-us"};
    for (size_t i = 0U; i < sizeof names / sizeof names[0]; i++) {
        if (strcmp(opt, names[i]) == 0) {
            return true;
        }
    }
    return false;
}

/* Parses the command line into rp. Returns 0, 1 for -h (done), or -1. */
/* A flag without a value (-t, -x, -v, --dry-run, --skip-errors,
 * --skip-unknown, --allow-real-bus, --quiet): true, and set, when a is one. */
static bool set_flag(replay_t *rp, const char *a)
{
    const struct {
        const char *name;
        bool *field;
    } flags[] = {
        {"-t", &rp->ignore_ts},           {"-x", &rp->no_loopback},
        {"-v", &rp->verbose},             {"--dry-run", &rp->dry_run},
        {"--skip-errors", &rp->skip_errors}, {"--skip-unknown", &rp->skip_unknown},
        {"--allow-real-bus", &rp->allow_real_bus}, {"--quiet", &rp->quiet},
    };
    for (size_t k = 0U; k < sizeof flags / sizeof flags[0]; k++) {
        if (strcmp(a, flags[k].name) == 0) {
            *flags[k].field = true;
            return true;
        }
    }
    return false;
}

/* A time option (-g, -s, --start, --end, --poll-us, --spin-us,
 * --tx-wait-ms) with its value v: 1 when a is one and v is taken, 0 when a
 * is none of them, -1 when v is out of the option's range (said on stderr). */
static int set_time_option(replay_t *rp, const char *a, const char *v)
{
    const struct {
        const char *name;
        const char *range;   /* for the message */
        bool above_zero;     /* 0 refused too */
        double max;          /* in the option's unit; 0: none */
        double scale;        /* from the option's unit to the field's */
        int64_t *field;
    } opts[] = {
        {"-g", "milliseconds, 0 to 3600000", false, 3600000.0, 1e6, &rp->gap_ns},
        {"-s", "seconds, more than 0", true, 0.0, 1e6, &rp->skip_gap_us},
        {"--start", "seconds, 0 or more", false, 0.0, 1e6, &rp->start_us},
        {"--end", "seconds, 0 or more", false, 0.0, 1e6, &rp->end_us},
        {"--poll-us", "microseconds, 0 to 1000000", false, 1000000.0, 1e3, &rp->poll_ns},
        {"--spin-us", "microseconds, 0 to 1000000", false, 1000000.0, 1e3, &rp->spin_ns},
        {"--tx-wait-ms", "milliseconds, 0 to 60000", false, 60000.0, 1e6, &rp->tx_wait_ns},
    };
    for (size_t k = 0U; k < sizeof opts / sizeof opts[0]; k++) {
        if (strcmp(a, opts[k].name) != 0) {
            continue;
        }
        double d = 0.0;
        if ((parse_nonneg(v, &d) != 0) || (opts[k].above_zero && (d <= 0.0)) ||
            ((opts[k].max > 0.0) && (d > opts[k].max))) {
            fprintf(stderr, "pfe_replay: %s %s: %s\n", a, v, opts[k].range);
            return -1;
        }
        *opts[k].field = (int64_t)(d * opts[k].scale);
        return 1;
    }
    return 0;
}

/* An option that takes a value (takes_value(a)) with its value v: 0, or -1
 * with the reason on stderr. */
static int set_option(replay_t *rp, const char *a, const char *v)
{
    const int timed = set_time_option(rp, a, v);
    if (timed != 0) {
        return (timed > 0) ? 0 : -1;
    }
    double d = 0.0;
    uint64_t u = 0U;
    if (strcmp(a, "-I") == 0) {
        rp->path = v;
    } else if (strcmp(a, "-l") == 0) {
        if (strcmp(v, "i") == 0) {
            rp->loops = 0U;
        } else if ((parse_u64(v, 10, ULONG_MAX, &u) != 0) || (u == 0U)) {
            fprintf(stderr, "pfe_replay: -l %s: a count of 1 or more, or i\n", v);
            return -1;
        } else {
            rp->loops = (unsigned long)u;
        }
    } else if (strcmp(a, "-n") == 0) {
        if ((parse_u64(v, 10, UINT64_MAX, &u) != 0) || (u == 0U)) {
            fprintf(stderr, "pfe_replay: -n %s: a count of 1 or more\n", v);
            return -1;
        }
        rp->max_frames = u;
    } else if (strcmp(a, "--speed") == 0) {
        if ((parse_nonneg(v, &d) != 0) || (d < 0.001) || (d > 1000.0)) {
            fprintf(stderr, "pfe_replay: --speed %s: a factor from 0.001 to 1000\n", v);
            return -1;
        }
        rp->speed = d;
    } else if ((strcmp(a, "--filter") == 0) || (strcmp(a, "--pgn") == 0)) {
        return parse_filter(rp, v, strcmp(a, "--pgn") == 0);
    } else if (strcmp(a, "--format") == 0) {
        if (canlog_format_parse(v, &rp->format) != 0) {
            fprintf(stderr, "pfe_replay: --format %s: auto, log, printed, printed-delta or asc\n", v);
            return -1;
        }
    } else {
        return -1; /* not reached: takes_value() knows the same names */
    }
    return 0;
}

/* The options together: --end not before --start, -l only on a file. */
static int check_args(const replay_t *rp)
{
    if ((rp->end_us >= 0) && (rp->end_us < rp->start_us)) {
        fprintf(stderr, "pfe_replay: --end before --start\n");
        return -1;
    }
    const bool from_stdin = (rp->path == NULL) || (strcmp(rp->path, "-") == 0);
    if (from_stdin && (rp->loops != 1U)) {
        fprintf(stderr, "pfe_replay: -l needs a file (-I FILE): standard input cannot be replayed twice\n");
        return -1;
    }
    return 0;
}

static int parse_args(replay_t *rp, int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
        if ((strcmp(a, "-h") == 0) || (strcmp(a, "--help") == 0)) {
            cli_help(k_manual);
            return 1;
        }
        if (set_flag(rp, a)) {
            continue;
        }
        if (a[0] != '-') {
            if (add_assignment(rp, a) != 0) {
                return -1;
            }
            continue;
        }
        if (!takes_value(a)) {
            fprintf(stderr, "pfe_replay: unknown option %s\n", a);
            return -1;
        }
        if (v == NULL) {
            fprintf(stderr, "pfe_replay: %s needs a value\n", a);
            return -1;
        }
        if (set_option(rp, a, v) != 0) {
            return -1;
        }
        i++;
    }
    return check_args(rp);
}

/* ------------------------------------------------------------------ main */

int main(int argc, char **argv)
{
    static replay_t rp;
    static canlog_reader_t reader;
    rp.loops = 1U;
    rp.speed = 1.0;
    rp.end_us = -1;
    rp.tx_wait_ns = 100000000LL;
    rp.spin_ns = 200000LL;
    rp.sock = -1;
    rp.format = CANLOG_FMT_AUTO;
    lateness_init(&rp.late);

    const int pa = parse_args(&rp, argc, argv);
    if (pa != 0) {
        if (pa < 0) {
            usage(stderr);
            return EXIT_USAGE;
        }
        return 0;
    }

    int fd = STDIN_FILENO;
    const char *name = "<stdin>";
    if ((rp.path != NULL) && (strcmp(rp.path, "-") != 0)) {
        fd = open(rp.path, O_RDONLY | O_CLOEXEC);
        if (fd < 0) {
            fprintf(stderr, "pfe_replay: cannot open %s: %s\n", rp.path, strerror(errno));
            return EXIT_INPUT;
        }
        name = rp.path;
    }
    struct stat st;
    if ((fstat(fd, &st) == 0) && S_ISREG(st.st_mode)) {
        rp.file_size = st.st_size;
    }
    (void)canlog_open_fd(&reader, fd, name, rp.format,
                         rp.skip_errors ? CANLOG_ON_ERROR_SKIP : CANLOG_ON_ERROR_STOP);

    /* Explicit assignments are checked before anything is sent. */
    if (!rp.dry_run) {
        for (unsigned i = 0U; i < rp.n_targets; i++) {
            if (!rp.targets[i].to_stdout) {
                const int rc = check_target(&rp, &rp.targets[i]);
                if (rc != 0) {
                    return rc;
                }
            }
        }
    }

    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    (void)sigemptyset(&sa.sa_mask);
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);
    (void)signal(SIGPIPE, SIG_IGN);

    /* Wake up at the deadline, not up to the default 50 us after it. */
    (void)prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
    rp.progress = !rp.quiet && (isatty(STDERR_FILENO) == 1);
    const int64_t t_start = now_ns();
    int status = 0;
    for (rp.pass = 1U;; rp.pass++) {
        if (rp.pass > 1U) {
            if (canlog_rewind(&reader) != 0) {
                fprintf(stderr, "pfe_replay: %s\n", canlog_message(&reader));
                status = EXIT_INPUT;
                break;
            }
        }
        const int rc = run_pass(&rp, &reader);
        if (rc < 0) {
            status = -rc;
            break;
        }
        if ((rc == PASS_STOP) || ((rp.loops != 0U) && (rp.pass >= rp.loops))) {
            break;
        }
    }
    out_flush(&rp);
    progress(&rp, &reader, now_ns(), true);
    summary(&rp, &reader, (double)(now_ns() - t_start) * 1e-9);
    if (rp.sock >= 0) {
        (void)close(rp.sock);
    }
    if (fd != STDIN_FILENO) {
        (void)close(fd);
    }
    if ((status == 0) && (reader.frames == 0U) && (reader.error_lines > 0U)) {
        fprintf(stderr, "pfe_replay: no frame could be read\n");
        status = EXIT_INPUT;
    }
    if ((status == 0) && (rp.dropped > 0U)) {
        status = EXIT_DROPPED;
    }
    if ((status == 0) && g_stop) {
        status = EXIT_STOPPED;
    }
    return status;
}
