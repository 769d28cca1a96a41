/*
 * hal_can_mem.h - what every in-memory backend (hal/fake, hal/replay) does
 * the same way: which frames can exist, and one node's port on a simulated
 * bus: its filters, its bounded receive queue, its counters, with
 * hal_can.h's semantics (filters per hal_can_add_filter(), frames in bus
 * order, overflow counted in rx_dropped).
 *
 * The port keeps no storage of its own for frames: the backend hands it an
 * array (its queue length is the backend's to choose).
 */
#ifndef HAL_CAN_MEM_H
#define HAL_CAN_MEM_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_can.h"

typedef struct {
    hal_can_rx_t *rx;                  /* the backend's queue storage */
    uint32_t rx_cap;
    uint32_t rx_head;
    uint32_t rx_count;
    uint32_t filter_id[HAL_CAN_MAX_FILTERS];
    uint32_t filter_mask[HAL_CAN_MAX_FILTERS];
    bool filter_used[HAL_CAN_MAX_FILTERS];
    hal_can_stats_t stats;
} hal_can_mem_port_t;

/* A frame hal_can_send() may take: dlc 0..8; a 29-bit id with
 * PFE_CAN_EFF_FLAG and no other flag bit, or an 11-bit id. */
bool hal_can_mem_frame_valid(const pfe_can_frame_t *f);

/* An empty port on rx[0 .. rx_cap - 1], no filter, counters at zero. */
void hal_can_mem_port_init(hal_can_mem_port_t *port, hal_can_rx_t *rx, uint32_t rx_cap);

/* A frame on the bus at t_us: queued if the filters accept it, counted in
 * rx_dropped if the queue is full. */
void hal_can_mem_port_offer(hal_can_mem_port_t *port, const pfe_can_frame_t *f, uint64_t t_us);

/* hal_can_receive(), hal_can_add_filter(), hal_can_remove_filter() on a port. */
int hal_can_mem_port_receive(hal_can_mem_port_t *port, hal_can_rx_t *out);
int hal_can_mem_port_add_filter(hal_can_mem_port_t *port, uint32_t id, uint32_t mask);
int hal_can_mem_port_remove_filter(hal_can_mem_port_t *port, int index);

/*
 * The in-memory backends (hal/fake, hal/replay) share hal_can_receive(),
 * hal_can_add_filter() and hal_can_remove_filter() (hal/hal_can_mem_api.c),
 * each built on the handle's port: a backend linking that file defines
 * this one function, which gives its handle's port (can is not NULL) and
 * whether the handle is open.
 */
hal_can_mem_port_t *hal_can_mem_port_of(hal_can_t *can, bool *open);

#endif /* HAL_CAN_MEM_H */
