/* hal_can_mem.c - a node's port on an in-memory bus (contract in hal_can_mem.h). */
#include "hal/hal_can_mem.h"

#include <stddef.h>
#include <string.h>

bool hal_can_mem_frame_valid(const pfe_can_frame_t *f)
{
    if (f->dlc > PFE_CAN_MAX_DLC) {
        return false;
    }
    if ((f->id & PFE_CAN_EFF_FLAG) != 0U) {
        return (f->id & ~(PFE_CAN_EFF_FLAG | PFE_CAN_ID_MASK)) == 0U;
    }
    return f->id <= 0x7FFU;
}

void hal_can_mem_port_init(hal_can_mem_port_t *port, hal_can_rx_t *rx, uint32_t rx_cap)
{
    (void)memset(port, 0, sizeof *port);
    port->rx = rx;
    port->rx_cap = rx_cap;
}

static bool accepts(const hal_can_mem_port_t *port, uint32_t id)
{
    bool any = false;
    for (uint32_t k = 0U; k < HAL_CAN_MAX_FILTERS; k++) {
        if (port->filter_used[k]) {
            any = true;
            if ((id & port->filter_mask[k]) == (port->filter_id[k] & port->filter_mask[k])) {
                return true;
            }
        }
    }
    return !any;
}

void hal_can_mem_port_offer(hal_can_mem_port_t *port, const pfe_can_frame_t *f, uint64_t t_us)
{
    if (!accepts(port, f->id)) {
        return;
    }
    if (port->rx_count == port->rx_cap) {
        port->stats.rx_dropped++;
        return;
    }
    uint32_t tail = port->rx_head + port->rx_count;
    if (tail >= port->rx_cap) {
        tail -= port->rx_cap;
    }
    hal_can_rx_t *slot = &port->rx[tail];
    slot->frame = *f;
    slot->timestamp_us = t_us;
    port->rx_count++;
}

int hal_can_mem_port_receive(hal_can_mem_port_t *port, hal_can_rx_t *out)
{
    if (port->rx_count == 0U) {
        return HAL_EAGAIN;
    }
    *out = port->rx[port->rx_head];
    port->rx_head++;
    if (port->rx_head == port->rx_cap) {
        port->rx_head = 0U;
    }
    port->rx_count--;
    port->stats.rx_frames++;
    return 0;
}

int hal_can_mem_port_add_filter(hal_can_mem_port_t *port, uint32_t id, uint32_t mask)
{
    for (uint32_t k = 0U; k < HAL_CAN_MAX_FILTERS; k++) {
        if (!port->filter_used[k]) {
            port->filter_used[k] = true;
            port->filter_id[k] = id;
            port->filter_mask[k] = mask;
            return (int)k;
        }
    }
    return HAL_ENOSPC;
}

int hal_can_mem_port_remove_filter(hal_can_mem_port_t *port, int index)
{
    if ((index < 0) || ((uint32_t)index >= HAL_CAN_MAX_FILTERS) || !port->filter_used[index]) {
        return HAL_EINVAL;
    }
    port->filter_used[index] = false;
    return 0;
}
