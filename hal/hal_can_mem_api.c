/*
 * hal_can_mem_api.c - hal_can.h's receive and filter calls of the in-memory
 * backends (hal/fake, hal/replay), once for both: each backend gives its
 * handle's port through hal_can_mem_port_of() (hal_can_mem.h) and keeps its
 * own open, close, send and statistics.
 */
#include "hal/hal_can_mem.h"

#include <stddef.h>

int hal_can_receive(hal_can_t *can, hal_can_rx_t *out)
{
    bool open = false;
    hal_can_mem_port_t *port = (can != NULL) ? hal_can_mem_port_of(can, &open) : NULL;
    if ((port == NULL) || !open || (out == NULL)) {
        return HAL_EINVAL;
    }
    return hal_can_mem_port_receive(port, out);
}

int hal_can_add_filter(hal_can_t *can, uint32_t id, uint32_t mask)
{
    bool open = false;
    hal_can_mem_port_t *port = (can != NULL) ? hal_can_mem_port_of(can, &open) : NULL;
    if ((port == NULL) || !open) {
        return HAL_EINVAL;
    }
    return hal_can_mem_port_add_filter(port, id, mask);
}

int hal_can_remove_filter(hal_can_t *can, int index)
{
    bool open = false;
    hal_can_mem_port_t *port = (can != NULL) ? hal_can_mem_port_of(can, &open) : NULL;
    if (port == NULL) {
        return HAL_EINVAL;
    }
    return hal_can_mem_port_remove_filter(port, index);
}
