/*
 * hal_socketcan.h - the Linux SocketCAN backend of hal/hal_can.h.
 *
 * One handle is one CAN_RAW socket bound to one interface (vcan0, can0 ...),
 * non-blocking, so every hal_can_* call of this backend returns without
 * waiting for the bus (hal_can_send may sleep for a bounded time, below).
 * Several handles on the same interface see each other's frames, as separate
 * ECUs on one bus would; a handle does not receive the frames it sent itself
 * (SocketCAN's defaults: CAN_RAW_LOOPBACK on, CAN_RAW_RECV_OWN_MSGS off).
 *
 * Real-bus guard: a program under test must not put frames on a truck's bus
 * by mistake. Opening for sending is allowed only on virtual CAN interfaces
 * (rtnetlink link kind "vcan" or "vxcan"); anything else, a CAN adapter, an
 * slcan line or a non-CAN interface, needs HAL_SOCKETCAN_ALLOW_REAL_BUS.
 * HAL_SOCKETCAN_RX_ONLY opens any interface, but hal_can_send then refuses.
 * Note that a CAN controller still acknowledges frames on the bus unless the
 * interface itself is configured listen-only (`ip link set can0 type can
 * listen-only on`); that is the interface's setting, not this backend's.
 *
 * Time: hal_can_rx_t.timestamp_us is the kernel's receive timestamp
 * (SO_TIMESTAMP, taken when the frame reached the socket layer), moved from
 * CLOCK_REALTIME to CLOCK_MONOTONIC microseconds by the offset between the two
 * clocks read at hal_can_receive, and never smaller than the handle's previous
 * timestamp: so a step of the wall clock (NTP, date) neither breaks the
 * ordering nor shifts the time base. It is comparable with
 * clock_gettime(CLOCK_MONOTONIC) of the same machine. When no socket of the
 * machine had asked for receive stamps before, Linux turns them on a moment
 * after hal_socketcan_open (a deferred work item, net_enable_timestamp());
 * frames that reach the socket before then are stamped when read, which on
 * a busy machine can be some milliseconds after they arrived.
 *
 * Counters (hal_can_stats_t): rx_dropped is the socket's receive queue
 * overflow count (SO_RXQ_OVFL; the kernel reports it with the next frame that
 * gets through, so drops after the last received frame show up later) plus
 * frames this backend received but cannot represent (remote requests, frames
 * of the wrong size). tx_dropped counts frames given up after
 * HAL_SOCKETCAN_SEND_RETRIES retries.
 *
 * Filters (hal_can_add_filter) are the kernel's CAN_RAW_FILTER: rejected
 * frames never reach the socket. A filter acts on frames that arrive after
 * the call; frames already waiting in the socket are still received. Remote
 * requests (RTR) are never received: pfe_can_frame_t cannot carry them.
 * hal_can_add_filter also returns HAL_EINVAL for id or mask bits outside
 * PFE_CAN_EFF_FLAG | PFE_CAN_ID_MASK, and HAL_EIO if the kernel refuses.
 *
 * Memory: hal_socketcan_open allocates one handle (malloc); close frees it.
 * Not reentrant per handle: one thread uses a handle at a time; different
 * handles are independent.
 *
 * Uses only libc and the Linux uapi headers (linux/can.h, linux/can/raw.h,
 * linux/rtnetlink.h).
 */
#ifndef HAL_SOCKETCAN_H
#define HAL_SOCKETCAN_H

#include "hal/hal_can.h"

/* Receive buffer each handle asks for (SO_RCVBUFFORCE, else SO_RCVBUF). */
#define HAL_SOCKETCAN_RCVBUF_BYTES (1024 * 1024)

/* Flags of hal_socketcan_open. */
#define HAL_SOCKETCAN_ALLOW_REAL_BUS 0x1U /* allow sending on a non-virtual interface */
#define HAL_SOCKETCAN_RX_ONLY 0x2U        /* never send: any interface, send refused */

/* hal_can_send: when the kernel's queue is full (ENOBUFS or EAGAIN), retry up
 * to this many times, sleeping HAL_SOCKETCAN_RETRY_WAIT_us before each retry;
 * then count a tx drop and return HAL_EAGAIN. Worst case a send call takes
 * about 4 x 250 us = 1 ms. */
#define HAL_SOCKETCAN_SEND_RETRIES 4U
#define HAL_SOCKETCAN_RETRY_WAIT_us 250U

/* What an interface is, for the real-bus guard. */
typedef enum {
    HAL_SOCKETCAN_IF_NOT_CAN = 0,     /* exists, not a CAN interface (lo, eth0) */
    HAL_SOCKETCAN_IF_VIRTUAL_CAN = 1, /* CAN with no bus behind it: vcan, vxcan */
    HAL_SOCKETCAN_IF_REAL_CAN = 2,    /* any other CAN interface: a bus, maybe a truck's */
} hal_socketcan_if_kind_t;

/*
 * Opens a handle on interface IFNAME (shorter than IFNAMSIZ, 16 bytes).
 * FLAGS: 0 or HAL_SOCKETCAN_ALLOW_REAL_BUS / HAL_SOCKETCAN_RX_ONLY.
 * On success *out is the new handle and the result is 0; with no filter added
 * it receives every data frame of the interface from now on.
 * Errors (*out untouched):
 *   HAL_EINVAL  out or ifname NULL, name too long, unknown flag
 *   HAL_ENODEV  no such interface, not a CAN interface (RX_ONLY), or a kernel
 *               without SocketCAN (socket(PF_CAN) fails with EAFNOSUPPORT)
 *   HAL_EPERM   sending requested on an interface that is not virtual CAN,
 *               without HAL_SOCKETCAN_ALLOW_REAL_BUS
 *   HAL_EIO     any other failure of socket, setsockopt, bind or malloc
 */
int hal_socketcan_open(hal_can_t **out, const char *ifname, unsigned flags);

/* Closes the socket and frees the handle. NULL is ignored. */
void hal_socketcan_close(hal_can_t *can);

/*
 * Classifies interface IFNAME by its rtnetlink link info: hardware type
 * ARPHRD_CAN (280, /sys/class/net/IF/type) and link kind (IFLA_INFO_KIND).
 * Returns a hal_socketcan_if_kind_t (>= 0), or HAL_ENODEV (no such
 * interface), HAL_EINVAL (NULL or too long a name), HAL_EIO (rtnetlink
 * failed). Opens and closes a netlink socket; works on kernels without CAN.
 */
int hal_socketcan_classify(const char *ifname);

/*
 * The real-bus guard alone: 0 when hal_socketcan_open(…, ifname, flags)
 * may send on IFNAME, HAL_EPERM when it must not, or the errors of
 * hal_socketcan_classify. Always 0 with HAL_SOCKETCAN_RX_ONLY (nothing is
 * sent) or HAL_SOCKETCAN_ALLOW_REAL_BUS (the caller said so), once the
 * interface exists.
 */
int hal_socketcan_check_send(const char *ifname, unsigned flags);

/* The handle's socket, for poll()/select() in a host program's event loop
 * (readable: a frame is waiting). Do not read, write or close it. */
int hal_socketcan_fd(const hal_can_t *can);

#endif /* HAL_SOCKETCAN_H */
