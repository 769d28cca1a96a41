/* hal_socketcan.c - the SocketCAN backend (contract in hal_socketcan.h). */
#define _DEFAULT_SOURCE /* SOCK_NONBLOCK, SOCK_CLOEXEC, clock_nanosleep */

#include "hal/socketcan/hal_socketcan.h"

#include <errno.h>
#include <net/if.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/raw.h>
#include <linux/if_arp.h>
#include <linux/netlink.h>
#include <linux/rtnetlink.h>

/* Frames skipped in one hal_can_receive call (remote requests, bad sizes)
 * before it returns HAL_EAGAIN, so that a flood of them cannot keep the ECU
 * loop inside this function. */
#define SKIP_LIMIT 64U

/* Longest link kind kept ("vcan", "vxcan", "can"); longer ones are cut. */
#define KIND_LEN 16U

typedef struct {
    bool used;
    uint32_t id;   /* as given: PFE_CAN_EFF_FLAG | 29 bits, or 11 bits */
    uint32_t mask;
} filter_t;

struct hal_can {
    int fd;
    unsigned flags;
    filter_t filter[HAL_CAN_MAX_FILTERS];
    hal_can_stats_t stats;         /* rx_dropped is rebuilt from the two below */
    uint32_t kernel_drops;         /* last SO_RXQ_OVFL value: the socket's total */
    uint32_t local_drops;          /* received, but not a classic data frame */
    uint64_t last_rx_us;           /* keeps timestamps from going backwards */
};

/* ------------------------------------------------------------------ helpers */

static int hal_error(int e)
{
    switch (e) {
    case EAGAIN:
#if EWOULDBLOCK != EAGAIN
    case EWOULDBLOCK:
#endif
    case ENOBUFS:
        return HAL_EAGAIN;
    case EINVAL:
        return HAL_EINVAL;
    case ENODEV:
    case ENXIO:
    case EAFNOSUPPORT:
    case EPROTONOSUPPORT:
        return HAL_ENODEV;
    case EPERM:
    case EACCES:
        return HAL_EPERM;
    default:
        return HAL_EIO;
    }
}

static uint64_t timespec_us(const struct timespec *ts)
{
    return ((uint64_t)ts->tv_sec * 1000000U) + ((uint64_t)ts->tv_nsec / 1000U);
}

static uint64_t now_us(clockid_t clock)
{
    struct timespec ts;
    if (clock_gettime(clock, &ts) != 0) {
        return 0U;
    }
    return timespec_us(&ts);
}

static bool name_ok(const char *ifname)
{
    return (ifname != NULL) && (ifname[0] != '\0') && (strnlen(ifname, IFNAMSIZ) < IFNAMSIZ);
}

/* A HAL identifier or mask (PFE_CAN_EFF_FLAG | 29 bits) in SocketCAN's
 * encoding: the same EFF bit, under its own name. */
static canid_t to_canid(uint32_t id)
{
    canid_t k = (canid_t)(id & CAN_EFF_MASK);
    if ((id & PFE_CAN_EFF_FLAG) != 0U) {
        k |= CAN_EFF_FLAG;
    }
    return k;
}

/* ------------------------------------------------------------------ real-bus guard */

/* Reads the rtnetlink attributes of the link with index IFINDEX: its hardware
 * type and, if it has one, its link kind (IFLA_LINKINFO / IFLA_INFO_KIND). */
static int query_link(int ifindex, unsigned short *type, char kind[KIND_LEN])
{
    struct {
        struct nlmsghdr nh;
        struct ifinfomsg ifi;
    } req;
    memset(&req, 0, sizeof req);
    req.nh.nlmsg_len = (uint32_t)NLMSG_LENGTH(sizeof req.ifi);
    req.nh.nlmsg_type = RTM_GETLINK;
    req.nh.nlmsg_flags = NLM_F_REQUEST;
    req.nh.nlmsg_seq = 1U;
    req.ifi.ifi_family = AF_UNSPEC;
    req.ifi.ifi_index = ifindex;

    int fd = socket(AF_NETLINK, SOCK_RAW | SOCK_CLOEXEC, NETLINK_ROUTE);
    if (fd < 0) {
        return HAL_EIO;
    }
    /* The kernel answers at once; a limit keeps a broken kernel from hanging
     * the caller. */
    const struct timeval limit = {1, 0};
    (void)setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &limit, sizeof limit);

    struct sockaddr_nl kernel;
    memset(&kernel, 0, sizeof kernel);
    kernel.nl_family = AF_NETLINK;
    if (sendto(fd, &req, req.nh.nlmsg_len, 0, (const struct sockaddr *)&kernel,
               sizeof kernel) != (ssize_t)req.nh.nlmsg_len) {
        (void)close(fd);
        return HAL_EIO;
    }

    /* One RTM_NEWLINK message of a few kilobytes (statistics included). */
    union {
        struct nlmsghdr align;
        unsigned char bytes[32768];
    } buf;
    int rc = HAL_EIO;
    kind[0] = '\0';
    for (;;) {
        ssize_t got = recv(fd, buf.bytes, sizeof buf.bytes, 0);
        if (got < 0) {
            if (errno == EINTR) {
                continue;
            }
            break;
        }
        size_t left = (size_t)got;
        const unsigned char *p = buf.bytes;
        bool done = false;
        while (left >= sizeof(struct nlmsghdr)) {
            struct nlmsghdr nh;
            memcpy(&nh, p, sizeof nh);
            if ((nh.nlmsg_len < sizeof nh) || (nh.nlmsg_len > left)) {
                break;
            }
            if (nh.nlmsg_seq == 1U) {
                if (nh.nlmsg_type == NLMSG_ERROR) {
                    struct nlmsgerr err;
                    if (nh.nlmsg_len >= NLMSG_LENGTH(sizeof err)) {
                        memcpy(&err, p + NLMSG_HDRLEN, sizeof err);
                        rc = (err.error == -ENODEV) ? HAL_ENODEV : HAL_EIO;
                    }
                    done = true;
                    break;
                }
                if ((nh.nlmsg_type == RTM_NEWLINK) &&
                    (nh.nlmsg_len >= NLMSG_LENGTH(sizeof(struct ifinfomsg)))) {
                    struct ifinfomsg ifi;
                    memcpy(&ifi, p + NLMSG_HDRLEN, sizeof ifi);
                    *type = ifi.ifi_type;
                    /* Attributes follow the ifinfomsg, each 4-byte aligned. */
                    size_t off = NLMSG_HDRLEN + NLMSG_ALIGN(sizeof ifi);
                    while (off + sizeof(struct rtattr) <= nh.nlmsg_len) {
                        struct rtattr a;
                        memcpy(&a, p + off, sizeof a);
                        if ((a.rta_len < sizeof a) || (off + a.rta_len > nh.nlmsg_len)) {
                            break;
                        }
                        if (a.rta_type == IFLA_LINKINFO) {
                            size_t in = off + RTA_ALIGN(sizeof a);
                            const size_t end = off + a.rta_len;
                            while (in + sizeof(struct rtattr) <= end) {
                                struct rtattr b;
                                memcpy(&b, p + in, sizeof b);
                                if ((b.rta_len < sizeof b) || (in + b.rta_len > end)) {
                                    break;
                                }
                                if (b.rta_type == IFLA_INFO_KIND) {
                                    size_t n = b.rta_len - RTA_ALIGN(sizeof b);
                                    if (n > KIND_LEN - 1U) {
                                        n = KIND_LEN - 1U;
                                    }
                                    memcpy(kind, p + in + RTA_ALIGN(sizeof b), n);
                                    kind[n] = '\0';
                                }
                                in += RTA_ALIGN(b.rta_len);
                            }
                        }
                        off += RTA_ALIGN(a.rta_len);
                    }
                    rc = 0;
                    done = true;
                    break;
                }
            }
            const size_t step = NLMSG_ALIGN(nh.nlmsg_len);
            if (step >= left) {
                break;
            }
            p += step;
            left -= step;
        }
        if (done) {
            break;
        }
    }
    (void)close(fd);
    return rc;
}

static int classify_index(int ifindex)
{
    unsigned short type = 0U;
    char kind[KIND_LEN];
    const int rc = query_link(ifindex, &type, kind);
    if (rc < 0) {
        return rc;
    }
    if (type != ARPHRD_CAN) {
        return HAL_SOCKETCAN_IF_NOT_CAN;
    }
    /* Only a kind that is known to have no bus behind it counts as virtual:
     * a CAN adapter's driver reports "can", slcan none at all. */
    if ((strcmp(kind, "vcan") == 0) || (strcmp(kind, "vxcan") == 0)) {
        return HAL_SOCKETCAN_IF_VIRTUAL_CAN;
    }
    return HAL_SOCKETCAN_IF_REAL_CAN;
}

static int check_send_index(int ifindex, unsigned flags)
{
    const int kind = classify_index(ifindex);
    if (kind < 0) {
        return kind;
    }
    if ((flags & (HAL_SOCKETCAN_RX_ONLY | HAL_SOCKETCAN_ALLOW_REAL_BUS)) != 0U) {
        return 0;
    }
    return (kind == HAL_SOCKETCAN_IF_VIRTUAL_CAN) ? 0 : HAL_EPERM;
}

static int index_of(const char *ifname)
{
    if (!name_ok(ifname)) {
        return HAL_EINVAL;
    }
    const unsigned idx = if_nametoindex(ifname);
    if ((idx == 0U) || (idx > (unsigned)INT32_MAX)) {
        return HAL_ENODEV;
    }
    return (int)idx;
}

int hal_socketcan_classify(const char *ifname)
{
    const int idx = index_of(ifname);
    return (idx < 0) ? idx : classify_index(idx);
}

int hal_socketcan_check_send(const char *ifname, unsigned flags)
{
    const int idx = index_of(ifname);
    return (idx < 0) ? idx : check_send_index(idx, flags);
}

/* ------------------------------------------------------------------ open, close */

static int apply_filters(hal_can_t *can)
{
    struct can_filter f[HAL_CAN_MAX_FILTERS];
    size_t n = 0U;
    for (uint32_t k = 0U; k < HAL_CAN_MAX_FILTERS; k++) {
        if (can->filter[k].used) {
            f[n].can_id = to_canid(can->filter[k].id);
            /* The RTR bit in every mask, clear in every id: remote requests
             * never match (pfe_can_frame_t cannot carry them). */
            f[n].can_mask = to_canid(can->filter[k].mask) | CAN_RTR_FLAG;
            n++;
        }
    }
    if (n == 0U) {
        /* No filter: every data frame. (An empty CAN_RAW_FILTER list would
         * receive nothing at all.) */
        f[0].can_id = 0U;
        f[0].can_mask = CAN_RTR_FLAG;
        n = 1U;
    }
    if (setsockopt(can->fd, SOL_CAN_RAW, CAN_RAW_FILTER, f, (socklen_t)(n * sizeof f[0])) != 0) {
        return HAL_EIO;
    }
    return 0;
}

int hal_socketcan_open(hal_can_t **out, const char *ifname, unsigned flags)
{
    if ((out == NULL) ||
        ((flags & ~(HAL_SOCKETCAN_ALLOW_REAL_BUS | HAL_SOCKETCAN_RX_ONLY)) != 0U)) {
        return HAL_EINVAL;
    }
    /* By index from here on: a rename between check and bind cannot swap in
     * another interface. */
    const int idx = index_of(ifname);
    if (idx < 0) {
        return idx;
    }
    int rc = check_send_index(idx, flags);
    if (rc < 0) {
        return rc;
    }

    hal_can_t *can = calloc(1U, sizeof *can);
    if (can == NULL) {
        return HAL_EIO;
    }
    can->flags = flags;
    can->fd = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (can->fd < 0) {
        rc = hal_error(errno);
        free(can);
        return (rc == HAL_EAGAIN) ? HAL_EIO : rc;
    }

    const int on = 1;
    rc = 0;
    if ((setsockopt(can->fd, SOL_SOCKET, SO_TIMESTAMP, &on, sizeof on) != 0) ||
        (setsockopt(can->fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) != 0)) {
        rc = HAL_EIO;
    }
    /* Room for about HAL_SOCKETCAN_RCVBUF_BYTES / 800 frames (the kernel's
     * charge per CAN frame on 64-bit Linux): with the loop reading every
     * 10 ms, a stall of a second at a full bus's rate. As root the system's
     * rmem_max does not cap it; what is still lost is counted
     * (SO_RXQ_OVFL, rx_dropped). */
    const int rcvbuf = HAL_SOCKETCAN_RCVBUF_BYTES;
    if ((rc == 0) && (setsockopt(can->fd, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf, sizeof rcvbuf) != 0)) {
        (void)setsockopt(can->fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
    }
    if (rc == 0) {
        rc = apply_filters(can);
    }
    if (rc == 0) {
        struct sockaddr_can addr;
        memset(&addr, 0, sizeof addr);
        addr.can_family = AF_CAN;
        addr.can_ifindex = idx;
        if (bind(can->fd, (const struct sockaddr *)&addr, sizeof addr) != 0) {
            rc = hal_error(errno);
            rc = ((rc == HAL_ENODEV) || (rc == HAL_EPERM)) ? rc : HAL_EIO;
        }
    }
    if (rc != 0) {
        (void)close(can->fd);
        free(can);
        return rc;
    }
    *out = can;
    return 0;
}

void hal_socketcan_close(hal_can_t *can)
{
    if (can != NULL) {
        (void)close(can->fd);
        free(can);
    }
}

int hal_socketcan_fd(const hal_can_t *can)
{
    return (can != NULL) ? can->fd : -1;
}

/* ------------------------------------------------------------------ hal_can.h */

static void sleep_us(uint32_t us)
{
    struct timespec ts = {0, (long)us * 1000L};
    while (clock_nanosleep(CLOCK_MONOTONIC, 0, &ts, &ts) == EINTR) {
    }
}

int hal_can_send(hal_can_t *can, const pfe_can_frame_t *frame)
{
    if ((can == NULL) || (frame == NULL) || (frame->dlc > PFE_CAN_MAX_DLC)) {
        return HAL_EINVAL;
    }
    if ((can->flags & HAL_SOCKETCAN_RX_ONLY) != 0U) {
        return HAL_EPERM;
    }
    struct can_frame cf;
    memset(&cf, 0, sizeof cf);
    if ((frame->id & PFE_CAN_EFF_FLAG) != 0U) {
        if ((frame->id & ~(uint32_t)(PFE_CAN_EFF_FLAG | PFE_CAN_ID_MASK)) != 0U) {
            return HAL_EINVAL;
        }
        cf.can_id = (frame->id & CAN_EFF_MASK) | CAN_EFF_FLAG;
    } else {
        if (frame->id > CAN_SFF_MASK) {
            return HAL_EINVAL;
        }
        cf.can_id = frame->id;
    }
    cf.len = frame->dlc;
    memcpy(cf.data, frame->data, frame->dlc);

    for (uint32_t attempt = 0U;; attempt++) {
        const ssize_t n = send(can->fd, &cf, sizeof cf, MSG_DONTWAIT);
        if (n == (ssize_t)sizeof cf) {
            can->stats.tx_frames++;
            return 0;
        }
        if (n >= 0) {
            return HAL_EIO; /* a CAN_RAW socket writes whole frames or nothing */
        }
        const int rc = (errno == EINTR) ? HAL_EAGAIN : hal_error(errno);
        if (rc != HAL_EAGAIN) {
            return rc;
        }
        if (attempt == HAL_SOCKETCAN_SEND_RETRIES) {
            can->stats.tx_dropped++;
            return HAL_EAGAIN;
        }
        sleep_us(HAL_SOCKETCAN_RETRY_WAIT_us);
    }
}

/* The kernel's CLOCK_REALTIME receive time on CLOCK_MONOTONIC, never before
 * the previous frame's and never after now (see hal_socketcan.h). */
static uint64_t rx_time_us(hal_can_t *can, const struct timeval *stamp)
{
    const uint64_t mono = now_us(CLOCK_MONOTONIC);
    uint64_t t = mono;
    if (stamp != NULL) {
        const uint64_t real = now_us(CLOCK_REALTIME);
        const uint64_t when = ((uint64_t)stamp->tv_sec * 1000000U) + (uint64_t)stamp->tv_usec;
        /* age: how long ago the kernel took the frame; 0 if the wall clock
         * moved back in between. */
        const uint64_t age = (real > when) ? (real - when) : 0U;
        t = (mono > age) ? (mono - age) : 0U;
    }
    if (t < can->last_rx_us) {
        t = can->last_rx_us;
    }
    can->last_rx_us = t;
    return t;
}

int hal_can_receive(hal_can_t *can, hal_can_rx_t *out)
{
    if ((can == NULL) || (out == NULL)) {
        return HAL_EINVAL;
    }
    for (uint32_t skipped = 0U; skipped < SKIP_LIMIT; skipped++) {
        struct can_frame cf;
        union {
            struct cmsghdr align;
            unsigned char bytes[CMSG_SPACE(sizeof(struct timeval)) + CMSG_SPACE(sizeof(uint32_t))];
        } ctrl;
        struct iovec iov = {&cf, sizeof cf};
        struct msghdr msg;
        memset(&msg, 0, sizeof msg);
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1U;
        msg.msg_control = ctrl.bytes;
        msg.msg_controllen = sizeof ctrl.bytes;

        const ssize_t n = recvmsg(can->fd, &msg, MSG_DONTWAIT);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            const int rc = hal_error(errno);
            return ((rc == HAL_EAGAIN) || (rc == HAL_ENODEV)) ? rc : HAL_EIO;
        }

        struct timeval stamp;
        bool have_stamp = false;
        for (struct cmsghdr *c = CMSG_FIRSTHDR(&msg); c != NULL; c = CMSG_NXTHDR(&msg, c)) {
            if (c->cmsg_level != SOL_SOCKET) {
                continue;
            }
            if ((c->cmsg_type == SCM_TIMESTAMP) && (c->cmsg_len >= CMSG_LEN(sizeof stamp))) {
                memcpy(&stamp, CMSG_DATA(c), sizeof stamp);
                have_stamp = true;
            } else if ((c->cmsg_type == SO_RXQ_OVFL) && (c->cmsg_len >= CMSG_LEN(sizeof(uint32_t)))) {
                uint32_t drops;
                memcpy(&drops, CMSG_DATA(c), sizeof drops);
                can->kernel_drops = drops; /* a running total, not an increment */
            }
        }

        if ((n != (ssize_t)sizeof cf) || ((msg.msg_flags & MSG_TRUNC) != 0) ||
            ((cf.can_id & (CAN_RTR_FLAG | CAN_ERR_FLAG)) != 0U) || (cf.len > PFE_CAN_MAX_DLC)) {
            can->local_drops++;
            continue;
        }

        memset(out, 0, sizeof *out);
        if ((cf.can_id & CAN_EFF_FLAG) != 0U) {
            out->frame.id = (uint32_t)(cf.can_id & CAN_EFF_MASK) | (uint32_t)PFE_CAN_EFF_FLAG;
        } else {
            out->frame.id = cf.can_id & CAN_SFF_MASK;
        }
        out->frame.dlc = cf.len;
        memcpy(out->frame.data, cf.data, cf.len);
        out->timestamp_us = rx_time_us(can, have_stamp ? &stamp : NULL);
        can->stats.rx_frames++;
        return 0;
    }
    return HAL_EAGAIN;
}

int hal_can_add_filter(hal_can_t *can, uint32_t id, uint32_t mask)
{
    const uint32_t valid = (uint32_t)(PFE_CAN_EFF_FLAG | PFE_CAN_ID_MASK);
    if ((can == NULL) || (((id | mask) & ~valid) != 0U)) {
        return HAL_EINVAL;
    }
    for (uint32_t k = 0U; k < HAL_CAN_MAX_FILTERS; k++) {
        if (!can->filter[k].used) {
            can->filter[k].used = true;
            can->filter[k].id = id;
            can->filter[k].mask = mask;
            if (apply_filters(can) != 0) {
                can->filter[k].used = false;
                (void)apply_filters(can);
                return HAL_EIO;
            }
            return (int)k;
        }
    }
    return HAL_ENOSPC;
}

int hal_can_remove_filter(hal_can_t *can, int index)
{
    if ((can == NULL) || (index < 0) || ((uint32_t)index >= HAL_CAN_MAX_FILTERS) ||
        !can->filter[index].used) {
        return HAL_EINVAL;
    }
    can->filter[index].used = false;
    if (apply_filters(can) != 0) {
        can->filter[index].used = true;
        (void)apply_filters(can);
        return HAL_EIO;
    }
    return 0;
}

void hal_can_get_stats(const hal_can_t *can, hal_can_stats_t *out)
{
    if ((can == NULL) || (out == NULL)) {
        return;
    }
    *out = can->stats;
    const uint32_t sum = can->kernel_drops + can->local_drops;
    /* Saturates: a counter that wrapped would look like fewer drops. */
    out->rx_dropped = (sum < can->kernel_drops) ? UINT32_MAX : sum;
}
