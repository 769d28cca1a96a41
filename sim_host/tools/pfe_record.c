/*
 * pfe_record - record CAN frames from SocketCAN interfaces to a candump log,
 * line for line as can-utils' candump -L writes it (lib.c's sprint_canframe,
 * candump.c's log line). It only listens.
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#define _GNU_SOURCE /* struct ifreq, SO_RXQ_OVFL */
#include <errno.h>
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/uio.h>
#include <time.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/raw.h>
#include <linux/sock_diag.h>
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: pfe_record [-o FILE] [-n COUNT] [--ns] [--rcvbuf BYTES] IF [IF ...]\n"
    "\n"
    "Records CAN frames from SocketCAN interfaces to a candump log. It only\n"
    "listens: no socket it opens is ever written to, so it may record a real bus.\n"
    "\n"
    "  IF             an interface to record; \"any\": every CAN interface\n"
    "  -o FILE        the log (default standard output), fully buffered\n"
    "  -n COUNT       stop after COUNT frames (default: never)\n"
    "  --ns           timestamps with 9 digits (nanoseconds) instead of 6\n"
    "  --rcvbuf BYTES each socket's receive buffer, 4096 .. 268435456 (default\n"
    "                 8 MiB: SO_RCVBUFFORCE as root, else SO_RCVBUF up to the\n"
    "                 system's rmem_max; it says when it got less), room for\n"
    "                 about 10,000 frames\n"
    "  -h, --help     this help\n"
    "\n"
    "Every frame received is written as one line of candump's log format, as\n"
    "can-utils' candump -L prints it:\n"
    "\n"
    "    (1700000000.123456) vcan0 18FEF100#FF005AFFFFFFFFFF\n"
    "\n"
    "  - the kernel's receive timestamp, microseconds truncated from nanoseconds\n"
    "    as the kernel does for candump, seconds padded to 10 digits;\n"
    "  - the interface name right-aligned to the longest name on the command line\n"
    "    (as candump; \"any\" counts as 3);\n"
    "  - 3 hex digits for an 11-bit id, 8 for a 29-bit one; error frames (every\n"
    "    error class) with the error flag in the 8 digits; R and a DLC for a\n"
    "    remote frame; ## and the flags nibble for CAN FD; _L after 8 data bytes\n"
    "    when the frame carries a raw DLC of 9 to 15.\n"
    "Once every interface is open it says \"pfe_record: recording IF... to FILE\"\n"
    "on standard error (a script can wait for that line before it sends). It\n"
    "stops after COUNT frames, or on SIGINT or SIGTERM, and then flushes and\n"
    "closes FILE. On standard error at the end: frames recorded, and frames the\n"
    "kernel dropped because the recorder's receive queue was full, per\n"
    "interface; a drop is also reported when it is noticed. Unlike candump, no\n"
    "DROPCOUNT lines go into the log, which stays a plain list of frames.\n"
    "\n"
    "Exit status: 0 after a clean stop; 1 on a runtime failure (an interface\n"
    "going away, a write error); 2 on bad arguments or an interface that cannot\n"
    "be opened.\n"
    "\n"
    "Examples:\n"
    "  pfe_record -o capture.log vcan0        # until Ctrl-C\n"
    "  pfe_record -n 1000 --ns can0 can1      # 1000 frames of two buses, to standard output\n";

#ifndef SO_RXQ_OVFL
#define SO_RXQ_OVFL 40
#endif
#ifndef SO_MEMINFO
#define SO_MEMINFO 55
#endif

#define MAX_IFACES 16
#define ANY_IFACE "any"
/* Longest line: "(" 10 "." 9 ") " name " " 8 "##" 1 128 "\n" */
#define LINE_MAX_LEN (32 + IFNAMSIZ + 8 + 3 + (2 * CANFD_MAX_DLEN) + 8)

static volatile sig_atomic_t g_stop;

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

/* The receive buffer asked for: the kernel charges a CAN frame about 800
 * bytes of socket memory (sk_buff and data) on 64-bit Linux. */
#define RCVBUF_BYTES (8 * 1024 * 1024)

typedef struct {
    const char *name;          /* as given */
    int fd;
    uint32_t drops;            /* last SO_RXQ_OVFL value: the socket's total */
    unsigned long frames;
} source_t;

typedef struct {
    const char *out_path;
    unsigned long count;       /* 0: no limit */
    bool ns;
    int rcvbuf;                /* bytes of receive buffer each socket asks for */
    int n_src;
    source_t src[MAX_IFACES];
} options_t;

static void usage(FILE *f)
{
    /* --help: the whole manual; a usage error: its synopsis. */
    if (f == stdout) {
        cli_help(k_manual);
    } else {
        cli_usage(f, k_manual, "pfe_record");
    }
}

static int parse_args(int argc, char **argv, options_t *o)
{
    memset(o, 0, sizeof *o);
    o->rcvbuf = RCVBUF_BYTES;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if ((strcmp(a, "-h") == 0) || (strcmp(a, "--help") == 0)) {
            usage(stdout);
            exit(0);
        } else if (strcmp(a, "--ns") == 0) {
            o->ns = true;
        } else if (strcmp(a, "--rcvbuf") == 0) {
            const char *v = (i + 1 < argc) ? argv[++i] : "";
            char *end = NULL;
            errno = 0;
            const long b = strtol(v, &end, 10);
            if ((errno != 0) || (end == v) || (*end != '\0') || (b < 4096L) || (b > 268435456L)) {
                fprintf(stderr, "pfe_record: --rcvbuf '%s': bytes, 4096 to 268435456\n", v);
                return 2;
            }
            o->rcvbuf = (int)b;
        } else if ((strcmp(a, "-o") == 0) || (strcmp(a, "-n") == 0)) {
            if (i + 1 >= argc) {
                fprintf(stderr, "pfe_record: %s wants a value\n", a);
                return 2;
            }
            const char *v = argv[++i];
            if (a[1] == 'o') {
                o->out_path = v;
            } else {
                char *end = NULL;
                errno = 0;
                o->count = strtoul(v, &end, 10);
                if ((errno != 0) || (end == v) || (*end != '\0') || (v[0] == '-') || (o->count == 0U)) {
                    fprintf(stderr, "pfe_record: bad count '%s'\n", v);
                    return 2;
                }
            }
        } else if (a[0] == '-') {
            fprintf(stderr, "pfe_record: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        } else {
            if (o->n_src == MAX_IFACES) {
                fprintf(stderr, "pfe_record: more than %d interfaces\n", MAX_IFACES);
                return 2;
            }
            if ((strlen(a) >= IFNAMSIZ) || (strpbrk(a, " \t,") != NULL)) {
                fprintf(stderr, "pfe_record: bad interface name '%s'\n", a);
                return 2;
            }
            o->src[o->n_src].name = a;
            o->src[o->n_src].fd = -1;
            o->n_src++;
        }
    }
    if (o->n_src == 0) {
        usage(stderr);
        return 2;
    }
    return 0;
}

/* Asks for `want` bytes of receive buffer on fd; says on stderr when the
 * socket got less (the kernel doubles the value it is given and reports
 * the double). */
static void size_rcvbuf(int fd, const char *name, int want)
{
    if (setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &want, sizeof want) != 0) {
        (void)setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &want, sizeof want);
    }
    int got = 0;
    socklen_t len = sizeof got;
    if ((getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &got, &len) != 0) || (got < want)) {
        fprintf(stderr, "pfe_record: %s: receive buffer %d bytes, asked for %d (frames may be dropped "
                        "and are counted)\n", name, got, want);
    }
}

static int open_source(source_t *s, int rcvbuf)
{
    s->fd = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
    if (s->fd < 0) {
        fprintf(stderr, "pfe_record: CAN socket: %s%s\n", strerror(errno),
                (errno == EAFNOSUPPORT) ? " (this kernel has no CAN support)" : "");
        return -1;
    }
    struct sockaddr_can addr;
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    if (strcmp(s->name, ANY_IFACE) != 0) {
        const unsigned idx = if_nametoindex(s->name);
        if (idx == 0U) {
            fprintf(stderr, "pfe_record: no interface '%s': %s\n", s->name, strerror(errno));
            return -1;
        }
        addr.can_ifindex = (int)idx;
    }
    const int on = 1;
    const can_err_mask_t err_mask = CAN_ERR_MASK;
    if (setsockopt(s->fd, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) != 0) {
        fprintf(stderr, "pfe_record: %s: no CAN FD frames (CAN_RAW_FD_FRAMES: %s)\n", s->name,
                strerror(errno));
    }
    if ((setsockopt(s->fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof err_mask) != 0) ||
        (setsockopt(s->fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) != 0)) {
        fprintf(stderr, "pfe_record: %s: socket option: %s\n", s->name, strerror(errno));
        return -1;
    }
    if (setsockopt(s->fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) != 0) {
        fprintf(stderr, "pfe_record: %s: drops will not be counted (SO_RXQ_OVFL: %s)\n", s->name,
                strerror(errno));
    }
    size_rcvbuf(s->fd, s->name, rcvbuf);
    if (bind(s->fd, (struct sockaddr *)&addr, sizeof addr) != 0) {
        fprintf(stderr, "pfe_record: bind to '%s': %s\n", s->name, strerror(errno));
        return -1;
    }
    return 0;
}

static const char k_hex[] = "0123456789ABCDEF";

static char *put_hex(char *p, uint32_t v, int digits)
{
    for (int k = digits - 1; k >= 0; k--) {
        p[k] = k_hex[v & 0xFU];
        v >>= 4;
    }
    return p + digits;
}

/* The frame field as can-utils' lib.c prints it (no separators). */
static char *put_frame(char *p, const struct canfd_frame *cf, bool fd)
{
    const uint8_t max = fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN;
    const uint8_t len = (cf->len > max) ? max : cf->len;
    if ((cf->can_id & CAN_ERR_FLAG) != 0U) {
        p = put_hex(p, cf->can_id & (CAN_ERR_MASK | CAN_ERR_FLAG), 8);
    } else if ((cf->can_id & CAN_EFF_FLAG) != 0U) {
        p = put_hex(p, cf->can_id & CAN_EFF_MASK, 8);
    } else {
        p = put_hex(p, cf->can_id & CAN_SFF_MASK, 3);
    }
    *p++ = '#';
    /* A classic frame's raw DLC 9..15 travels in the byte FD uses for flags. */
    const uint8_t len8_dlc = fd ? 0U : cf->__res1;
    if (!fd && ((cf->can_id & CAN_RTR_FLAG) != 0U)) {
        *p++ = 'R';
        if ((len > 0U) && (len <= CAN_MAX_DLEN)) {
            *p++ = k_hex[len];
            if ((len == CAN_MAX_DLEN) && (len8_dlc > CAN_MAX_DLEN) && (len8_dlc <= 15U)) {
                *p++ = '_';
                *p++ = k_hex[len8_dlc];
            }
        }
        return p;
    }
    if (fd) {
        *p++ = '#';
        *p++ = k_hex[cf->flags & 0xFU];
    }
    for (uint8_t k = 0U; k < len; k++) {
        p = put_hex(p, cf->data[k], 2);
    }
    if (!fd && (len == CAN_MAX_DLEN) && (len8_dlc > CAN_MAX_DLEN) && (len8_dlc <= 15U)) {
        *p++ = '_';
        *p++ = k_hex[len8_dlc];
    }
    return p;
}

/* Interface names by index, looked up once each. */
static struct {
    int index;
    char name[IF_NAMESIZE];
} g_names[64];
static unsigned g_n_names;

static const char *iface_name(int index, const char *fallback)
{
    for (unsigned k = 0U; k < g_n_names; k++) {
        if (g_names[k].index == index) {
            return g_names[k].name;
        }
    }
    char name[IF_NAMESIZE];
    if ((index <= 0) || (if_indextoname((unsigned)index, name) == NULL)) {
        return fallback;
    }
    if (g_n_names == (sizeof g_names / sizeof g_names[0])) {
        g_n_names = 0U; /* forget them all: names are only a cache */
    }
    g_names[g_n_names].index = index;
    memcpy(g_names[g_n_names].name, name, sizeof name);
    return g_names[g_n_names++].name;
}

/* Reads one frame from s and writes its line. 1 written, 0 nothing (EAGAIN,
 * EINTR, a malformed read counted), -1 fatal. */
static int record_one(source_t *s, FILE *out, int name_width, bool ns, unsigned long *malformed)
{
    struct canfd_frame cf;
    struct sockaddr_can addr;
    char ctrl[CMSG_SPACE(sizeof(struct timespec)) + CMSG_SPACE(sizeof(uint32_t)) + 64];
    struct iovec iov = {&cf, sizeof cf};
    struct msghdr msg;
    memset(&msg, 0, sizeof msg);
    msg.msg_name = &addr;
    msg.msg_namelen = sizeof addr;
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = ctrl;
    msg.msg_controllen = sizeof ctrl;
    const ssize_t n = recvmsg(s->fd, &msg, MSG_DONTWAIT);
    if (n < 0) {
        if ((errno == EAGAIN) || (errno == EWOULDBLOCK) || (errno == EINTR)) {
            return 0;
        }
        fprintf(stderr, "pfe_record: %s: receive: %s\n", s->name, strerror(errno));
        return -1;
    }
    bool fd;
    if ((size_t)n == CAN_MTU) {
        fd = false;
    } else if ((size_t)n == CANFD_MTU) {
        fd = true;
    } else {
        (*malformed)++;
        return 0;
    }
    struct timespec ts = {0, 0};
    for (struct cmsghdr *c = CMSG_FIRSTHDR(&msg); c != NULL; c = CMSG_NXTHDR(&msg, c)) {
        if (c->cmsg_level != SOL_SOCKET) {
            continue;
        }
        if (c->cmsg_type == SO_TIMESTAMPNS) {
            memcpy(&ts, CMSG_DATA(c), sizeof ts);
        } else if (c->cmsg_type == SO_RXQ_OVFL) {
            uint32_t total = 0U;
            memcpy(&total, CMSG_DATA(c), sizeof total);
            if (total != s->drops) {
                fprintf(stderr, "pfe_record: %s: %u frame(s) dropped (receive queue full), %u in all\n",
                        s->name, (unsigned)(total - s->drops), (unsigned)total);
                s->drops = total;
            }
        }
    }
    const char *ifname = iface_name(addr.can_ifindex, s->name);
    char line[LINE_MAX_LEN];
    int k = ns ? snprintf(line, sizeof line, "(%010llu.%09ld) %*s ", (unsigned long long)ts.tv_sec,
                          ts.tv_nsec, name_width, ifname)
               : snprintf(line, sizeof line, "(%010llu.%06ld) %*s ", (unsigned long long)ts.tv_sec,
                          ts.tv_nsec / 1000L, name_width, ifname);
    char *p = put_frame(line + k, &cf, fd);
    *p++ = '\n';
    if (fwrite(line, 1U, (size_t)(p - line), out) != (size_t)(p - line)) {
        fprintf(stderr, "pfe_record: write: %s\n", strerror(errno));
        return -1;
    }
    s->frames++;
    return 1;
}

int main(int argc, char **argv)
{
    static options_t o;
    const int prc = parse_args(argc, argv, &o);
    if (prc != 0) {
        return prc;
    }
    int width = 0;
    for (int k = 0; k < o.n_src; k++) {
        if (open_source(&o.src[k], o.rcvbuf) != 0) {
            for (int j = 0; j <= k; j++) {
                if (o.src[j].fd >= 0) {
                    close(o.src[j].fd);
                }
            }
            return 2;
        }
        const int len = (int)strlen(o.src[k].name);
        width = (len > width) ? len : width;
    }
    FILE *out = stdout;
    if (o.out_path != NULL) {
        out = fopen(o.out_path, "w");
        if (out == NULL) {
            fprintf(stderr, "pfe_record: cannot write %s: %s\n", o.out_path, strerror(errno));
            return 2;
        }
    }
    static char buf[1U << 16];
    (void)setvbuf(out, buf, _IOFBF, sizeof buf);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);
    (void)signal(SIGPIPE, SIG_IGN);
    /* The signals stay blocked but inside ppoll(), so that one arriving
     * between the g_stop test and the wait cannot be missed. */
    sigset_t stop_set, wait_set;
    sigemptyset(&stop_set);
    sigaddset(&stop_set, SIGINT);
    sigaddset(&stop_set, SIGTERM);
    (void)sigprocmask(SIG_BLOCK, &stop_set, &wait_set);
    sigdelset(&wait_set, SIGINT);
    sigdelset(&wait_set, SIGTERM);

    struct pollfd pfd[MAX_IFACES];
    for (int k = 0; k < o.n_src; k++) {
        pfd[k].fd = o.src[k].fd;
        pfd[k].events = POLLIN;
    }
    /* Scripts wait for this line before they start sending. */
    fprintf(stderr, "pfe_record: recording");
    for (int k = 0; k < o.n_src; k++) {
        fprintf(stderr, " %s", o.src[k].name);
    }
    fprintf(stderr, " to %s\n", (o.out_path != NULL) ? o.out_path : "standard output");
    unsigned long total = 0U, malformed = 0U;
    int rc = 0;
    while (!g_stop && (rc == 0) && ((o.count == 0U) || (total < o.count))) {
        const int r = ppoll(pfd, (nfds_t)o.n_src, NULL, &wait_set);
        if (r < 0) {
            if (errno == EINTR) {
                continue;
            }
            fprintf(stderr, "pfe_record: ppoll: %s\n", strerror(errno));
            rc = 1;
            break;
        }
        /* One frame per ready interface per round, as candump does. */
        for (int k = 0; (k < o.n_src) && ((o.count == 0U) || (total < o.count)); k++) {
            if ((pfd[k].revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
                fprintf(stderr, "pfe_record: %s: the interface went away\n", o.src[k].name);
                rc = 1;
                break;
            }
            if ((pfd[k].revents & POLLIN) == 0) {
                continue;
            }
            const int w = record_one(&o.src[k], out, width, o.ns, &malformed);
            if (w < 0) {
                rc = 1;
                break;
            }
            total += (unsigned long)w;
        }
    }
    if (((out != stdout) ? fclose(out) : fflush(out)) != 0) {
        fprintf(stderr, "pfe_record: write %s: %s\n", (o.out_path != NULL) ? o.out_path : "stdout",
                strerror(errno));
        rc = 1;
    }
    unsigned long dropped = 0U;
    for (int k = 0; k < o.n_src; k++) {
        /* SO_RXQ_OVFL comes with the frames queued after a drop: when none
         * came, the socket's own count (Linux 4.12 and later) says it. */
        uint32_t mem[SK_MEMINFO_VARS];
        socklen_t len = sizeof mem;
        if ((getsockopt(o.src[k].fd, SOL_SOCKET, SO_MEMINFO, mem, &len) == 0) &&
            (len > (socklen_t)(SK_MEMINFO_DROPS * sizeof mem[0])) &&
            (mem[SK_MEMINFO_DROPS] > o.src[k].drops)) {
            o.src[k].drops = mem[SK_MEMINFO_DROPS];
        }
        dropped += o.src[k].drops;
        close(o.src[k].fd);
    }
    fprintf(stderr, "pfe_record: %lu frames recorded, %lu dropped (receive queue full)", total,
            dropped);
    if (o.n_src > 1) {
        for (int k = 0; k < o.n_src; k++) {
            fprintf(stderr, "%s %s %lu/%u", (k == 0) ? ":" : ",", o.src[k].name, o.src[k].frames,
                    (unsigned)o.src[k].drops);
        }
    }
    if (malformed > 0U) {
        fprintf(stderr, "; %lu reads of an unknown size skipped", malformed);
    }
    fprintf(stderr, "%s\n", g_stop ? "; stopped by a signal" : "");
    return rc;
}
