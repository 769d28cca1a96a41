/* hal_fake.c - the test backend (contract in hal_fake.h). */
#include "hal/fake/hal_fake.h"

#include "hal/hal_can_mem.h"

#include <stddef.h>
#include <string.h>

void hal_fake_bus_init(hal_fake_bus_t *bus)
{
    memset(bus, 0, sizeof *bus);
    bus->time.bus = bus;
}

hal_time_t *hal_fake_time(hal_fake_bus_t *bus)
{
    return &bus->time;
}

uint64_t hal_time_now_us(hal_time_t *time)
{
    return time->bus->now_us;
}

int hal_time_wait_until_us(hal_time_t *time, uint64_t deadline_us)
{
    if (deadline_us > time->bus->now_us) {
        time->bus->now_us = deadline_us;
    }
    return 0;
}

hal_can_t *hal_fake_open(hal_fake_bus_t *bus)
{
    for (uint32_t k = 0U; k < HAL_FAKE_MAX_HANDLES; k++) {
        hal_can_t *h = &bus->handle[k];
        if (!h->open) {
            memset(h, 0, sizeof *h);
            h->bus = bus;
            h->open = true;
            h->tx_space = UINT32_MAX;
            hal_can_mem_port_init(&h->port, h->rx, HAL_FAKE_RX_QUEUE);
            return h;
        }
    }
    return NULL;
}

void hal_fake_close(hal_can_t *can)
{
    if (can != NULL) {
        can->open = false;
    }
}

void hal_fake_set_tx_space(hal_can_t *can, uint32_t frames)
{
    can->tx_space = frames;
}

void hal_fake_advance_us(hal_fake_bus_t *bus, uint64_t us)
{
    bus->now_us += us;
}

uint64_t hal_fake_now_us(const hal_fake_bus_t *bus)
{
    return bus->now_us;
}

int hal_can_send(hal_can_t *can, const pfe_can_frame_t *frame)
{
    if ((can == NULL) || !can->open || (frame == NULL) || !hal_can_mem_frame_valid(frame)) {
        return HAL_EINVAL;
    }
    if (can->tx_space == 0U) {
        return HAL_EAGAIN;
    }
    if (can->tx_space != UINT32_MAX) {
        can->tx_space--;
    }
    hal_fake_bus_t *bus = can->bus;
    for (uint32_t k = 0U; k < HAL_FAKE_MAX_HANDLES; k++) {
        hal_can_t *h = &bus->handle[k];
        if (h->open && (h != can)) {
            hal_can_mem_port_offer(&h->port, frame, bus->now_us);
        }
    }
    can->port.stats.tx_frames++;
    return 0;
}

hal_can_mem_port_t *hal_can_mem_port_of(hal_can_t *can, bool *open)
{
    *open = can->open;
    return &can->port;
}

void hal_can_get_stats(const hal_can_t *can, hal_can_stats_t *out)
{
    *out = can->port.stats;
}

void hal_fake_nvm_init(hal_nvm_t *nvm)
{
    memset(nvm->slot, 0xFF, sizeof nvm->slot);
    nvm->tear_after = -1;
    nvm->writes = 0U;
    nvm->fail_writes = 0U;
    nvm->fail_bytes = 0U;
    nvm->failed = 0U;
    nvm->last_slot = 0U;
    memset(nvm->last_buf, 0xFF, sizeof nvm->last_buf);
    nvm->last_result = 0;
}

void hal_fake_nvm_fail_next_writes(hal_nvm_t *nvm, uint32_t count, uint32_t bytes)
{
    nvm->fail_writes = count;
    nvm->fail_bytes = (bytes < PFE_NVM_RECORD_SIZE) ? bytes : PFE_NVM_RECORD_SIZE;
}

void hal_fake_nvm_tear_next_write(hal_nvm_t *nvm, uint32_t bytes)
{
    nvm->tear_after = (int32_t)((bytes < PFE_NVM_RECORD_SIZE) ? bytes : PFE_NVM_RECORD_SIZE);
}

int hal_nvm_read(hal_nvm_t *nvm, uint32_t slot, uint8_t buf[PFE_NVM_RECORD_SIZE])
{
    if ((nvm == NULL) || (slot >= PFE_NVM_SLOTS) || (buf == NULL)) {
        return HAL_EINVAL;
    }
    memcpy(buf, nvm->slot[slot], PFE_NVM_RECORD_SIZE);
    return 0;
}

int hal_nvm_write(hal_nvm_t *nvm, uint32_t slot, const uint8_t buf[PFE_NVM_RECORD_SIZE])
{
    if ((nvm == NULL) || (slot >= PFE_NVM_SLOTS) || (buf == NULL)) {
        return HAL_EINVAL;
    }
    nvm->writes++;
    nvm->last_slot = slot;
    memcpy(nvm->last_buf, buf, PFE_NVM_RECORD_SIZE);
    int32_t partial = -1;
    if (nvm->tear_after >= 0) {
        partial = nvm->tear_after;
        nvm->tear_after = -1;
    } else if (nvm->fail_writes > 0U) {
        partial = (int32_t)nvm->fail_bytes;
        nvm->fail_writes--;
    } else {
        /* a complete write */
    }
    if (partial >= 0) {
        /* The bytes a reset or a failed program leaves: the head new, the
         * tail as erased flash. */
        const uint32_t n = (uint32_t)partial;
        memcpy(nvm->slot[slot], buf, n);
        memset(&nvm->slot[slot][n], 0xFF, PFE_NVM_RECORD_SIZE - n);
        nvm->failed++;
        nvm->last_result = HAL_EIO;
        return HAL_EIO;
    }
    memcpy(nvm->slot[slot], buf, PFE_NVM_RECORD_SIZE);
    nvm->last_result = 0;
    return 0;
}
