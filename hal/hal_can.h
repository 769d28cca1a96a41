/*
 * hal_can.h - the CAN interface every backend implements.
 *
 * A backend is one folder under hal/ (socketcan/, fake/, mps2/ ...). The ECU
 * loop polls: it never gets a callback. One conformance suite
 * (tests/hal/) runs against every backend that can run on a machine.
 *
 * Return values: 0 or a negated errno-style code (HAL_E*). Time is
 * microseconds of a monotonic clock chosen by the backend.
 */
#ifndef HAL_CAN_H
#define HAL_CAN_H

#include <stdint.h>

#include "firmware/pfe_can.h"

#define HAL_EAGAIN (-11)   /* nothing to receive / transmit queue full, try later */
#define HAL_EINVAL (-22)   /* bad argument */
#define HAL_ENOSPC (-28)   /* no filter slot left */
#define HAL_EIO (-5)       /* the bus or the interface failed */
#define HAL_ENODEV (-19)   /* no such interface */
#define HAL_EPERM (-1)     /* refused: e.g. sending on a real bus without permission */

#define HAL_CAN_MAX_FILTERS 16U

typedef struct hal_can hal_can_t; /* backend state, owned by the backend's open function */

typedef struct {
    pfe_can_frame_t frame;
    uint64_t timestamp_us;        /* receive time (kernel timestamp where the backend has one) */
} hal_can_rx_t;

/* Sends one frame without blocking. HAL_EAGAIN when the transmit queue is full. */
int hal_can_send(hal_can_t *can, const pfe_can_frame_t *frame);

/* Takes one received frame without blocking. 0 and *out filled, or HAL_EAGAIN
 * when none is waiting. Frames arrive in bus order. */
int hal_can_receive(hal_can_t *can, hal_can_rx_t *out);

/* Accepts frames with (frame.id & mask) == (id & mask), the EFF flag included
 * in both. Returns the filter's index (>= 0) or HAL_ENOSPC. With no filter
 * added every frame is accepted. */
int hal_can_add_filter(hal_can_t *can, uint32_t id, uint32_t mask);

/* Removes a filter by index; HAL_EINVAL if there is none. */
int hal_can_remove_filter(hal_can_t *can, int index);

/* Counters that only count up. */
typedef struct {
    uint32_t rx_frames;
    uint32_t tx_frames;
    uint32_t rx_dropped;          /* lost before the ECU saw them (overflow) */
    uint32_t tx_dropped;          /* not sent: queue full after retries */
} hal_can_stats_t;
void hal_can_get_stats(const hal_can_t *can, hal_can_stats_t *out);

#endif /* HAL_CAN_H */
