/*
 * hal_fake.h - the test backend: an in-memory CAN bus, a clock that moves
 * only when told, and NVM whose writes can be torn.
 *
 * Everything lives in structs the test owns; nothing is global, nothing
 * blocks, nothing depends on the host's clock, so every run is the same.
 *
 * Bus semantics follow SocketCAN's defaults: a frame sent on one handle is
 * received by every other handle on the same bus whose filters accept it,
 * not by the sender; each handle has its own receive queue of
 * HAL_FAKE_RX_QUEUE frames and counts what overflows.
 */
#ifndef HAL_FAKE_H
#define HAL_FAKE_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_can.h"
#include "hal/hal_can_mem.h"
#include "hal/hal_nvm.h"
#include "hal/hal_time.h"

#define HAL_FAKE_RX_QUEUE 256U
#define HAL_FAKE_MAX_HANDLES 4U

typedef struct hal_fake_bus hal_fake_bus_t;

struct hal_can {
    hal_fake_bus_t *bus;
    bool open;
    hal_can_mem_port_t port;         /* filters, receive queue, counters */
    hal_can_rx_t rx[HAL_FAKE_RX_QUEUE];
    uint32_t tx_space;               /* frames the transmit queue takes before HAL_EAGAIN */
};

/* The bus's clock as a hal_time_t (hal_fake_time()). */
struct hal_time {
    hal_fake_bus_t *bus;
};

struct hal_fake_bus {
    uint64_t now_us;                 /* the clock: moves only with hal_fake_advance_us() or a wait */
    struct hal_time time;
    struct hal_can handle[HAL_FAKE_MAX_HANDLES];
};

/* Starts an empty bus at time 0. */
void hal_fake_bus_init(hal_fake_bus_t *bus);
/* Opens a handle on the bus; NULL when HAL_FAKE_MAX_HANDLES are open. */
hal_can_t *hal_fake_open(hal_fake_bus_t *bus);
void hal_fake_close(hal_can_t *can);
/* Limits how many more frames a handle may send before HAL_EAGAIN
 * (UINT32_MAX: unlimited, the default). */
void hal_fake_set_tx_space(hal_can_t *can, uint32_t frames);
void hal_fake_advance_us(hal_fake_bus_t *bus, uint64_t us);
uint64_t hal_fake_now_us(const hal_fake_bus_t *bus);
/* The bus's clock through hal/hal_time.h: hal_time_wait_until_us() moves it
 * to the deadline at once. */
hal_time_t *hal_fake_time(hal_fake_bus_t *bus);

struct hal_nvm {
    uint8_t slot[PFE_NVM_SLOTS][PFE_NVM_RECORD_SIZE];
    int32_t tear_after;              /* < 0: writes complete; else bytes written before a "reset" */
    uint32_t writes;
    uint32_t fail_writes;            /* writes still to fail (hal_fake_nvm_fail_next_writes()) */
    uint32_t fail_bytes;             /* bytes each failing write programs */
    uint32_t failed;                 /* writes that returned an error */
    /* The last write as asked for, for a test to judge what it left. */
    uint32_t last_slot;
    uint8_t last_buf[PFE_NVM_RECORD_SIZE];
    int last_result;
};

/* All slots erased (0xFF), writes complete. */
void hal_fake_nvm_init(hal_nvm_t *nvm);
/* The next write stops after `bytes` bytes and fails with HAL_EIO, as a
 * reset in the middle of the write would leave it. */
void hal_fake_nvm_tear_next_write(hal_nvm_t *nvm, uint32_t bytes);
/* The next `count` writes fail with HAL_EIO without a reset, as flash that
 * does not verify: each erases the slot and programs its first `bytes`
 * bytes (at most PFE_NVM_RECORD_SIZE), the rest reads 0xFF. A pending tear
 * goes first. */
void hal_fake_nvm_fail_next_writes(hal_nvm_t *nvm, uint32_t count, uint32_t bytes);

#endif /* HAL_FAKE_H */
