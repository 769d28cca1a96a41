/*
 * hal_ecu_loop.h - the ECU's main loop over the HAL, the same for every
 * backend: the Linux process on SocketCAN (sim_host/tools/pfe_ecu.c), a replay of
 * a log on the host (sim_host/tools/pfe_ecu_replay.c) and on the emulated Cortex-M4
 * (hal/mps2/main_ecu.c). Because they share this code, a replay on the host
 * and on the Cortex-M4 must send the same frames.
 *
 * hal_ecu_loop_init() installs the ECU's receive filters
 * (pfe_ecu_rx_filters) on the handle, so that other traffic stays out.
 * One pass, hal_ecu_loop_step(), at each 10 ms deadline:
 *   1. the frames waiting on the CAN handle that were received by the
 *      deadline go into the ECU, stamped with the deadline, at most
 *      HAL_ECU_LOOP_RX_MAX of them: a flood cannot hold the tick (the rest
 *      waits, and what the backend then drops is counted). A frame received
 *      after the deadline (its timestamp_us on the backend's clock, which is
 *      the caller's clock of now_us) is held for the next pass: a pass that
 *      runs late, catching up on a missed deadline, must not show the ECU
 *      a frame from its future (the speed of 10 ms later at this deadline
 *      is a false acceleration). A backend without receive times (0) never
 *      holds;
 *   2. frames the backend dropped since the last pass are reported;
 *   3. the ECU ticks; what it sends goes to the handle, refusals are
 *      reported as transmit drops;
 *   4. fuel totals are saved to NVM when due, the result reported to the
 *      ECU (pfe_ecu_nvm_written()): a failed write is retried on the next
 *      pass, to the same slot.
 * The caller owns the waiting; hal_ecu_loop_pace() says when the next pass
 * is due.
 *
 * Pacing, hal_ecu_loop_pace(), after each pass: the model is fixed-step
 * (each tick is PFE_ECU_TICK_US of fuel and distance), so a tick that is
 * skipped is fuel never counted. A pass that ends after the next deadline
 * (a stalled host process, a long flash erase) therefore does not skip
 * ticks: the missed ticks run back to back, each with the frames received
 * by its own deadline (step 1 above), until the loop is on time again. Only
 * a stall longer than HAL_ECU_LOOP_CATCH_UP_TICKS ticks is given up on: the
 * ticks beyond it are skipped, counted (pfe_ecu_note_overrun() and
 * hal_ecu_loop_t.skipped_ticks), and the deadlines restart from now. Every
 * tick run after its next deadline is counted as an overrun too, so the bus
 * sees (PFE_Status) that outputs came late.
 */
#ifndef HAL_ECU_LOOP_H
#define HAL_ECU_LOOP_H

#include <stdbool.h>
#include <stdint.h>

#include "firmware/pfe_ecu.h"
#include "hal/hal_can.h"
#include "hal/hal_nvm.h"

#define HAL_ECU_LOOP_RX_MAX (2U * PFE_ECU_RX_QUEUE_LEN)
/* Ticks a late loop runs back to back to catch up: 1 s. A longer stall is
 * a fault (the STM32's watchdog fires from 1.6 s without an on-time pass),
 * not a load to ride out. */
#define HAL_ECU_LOOP_CATCH_UP_TICKS 100U

typedef enum {
    HAL_ECU_PACE_ON_TIME,    /* wait for the next deadline */
    HAL_ECU_PACE_CATCH_UP,   /* the next deadline is past: run its pass now */
    HAL_ECU_PACE_SKIPPED     /* too far behind: ticks skipped, deadlines from now */
} hal_ecu_pace_t;

typedef struct {
    pfe_ecu_t *ecu;
    hal_can_t *can;
    hal_nvm_t *nvm;
    hal_can_stats_t last;              /* backend counters at the previous pass */
    hal_can_rx_t held;                 /* received after the last pass's deadline */
    bool have_held;
    uint32_t nvm_failures;             /* saves the backend refused */
    uint32_t skipped_ticks;            /* ticks given up on by hal_ecu_loop_pace(), saturating */
    int restored_slot;                 /* NVM slot restored from, -1 for none */
    uint32_t filters;                  /* receive filters the backend took */
    pfe_nvm_state_t restored;          /* totals restored at start-up */
} hal_ecu_loop_t;

/*
 * The module's configuration as every main builds it: default calibration,
 * J1939 NAME 0x80A0000000000001 with the preferred address in its identity
 * field (bit 63: arbitrary address capable), default platoon of `vehicles`
 * trucks, own position `position`, gap `gap_mm`.
 */
void hal_ecu_loop_config(pfe_ecu_config_t *cfg, uint8_t address, uint32_t save_interval_ms,
                         uint32_t vehicles, uint32_t position, uint32_t gap_mm);

/*
 * Restores the fuel totals from nvm's two slots (pfe_nvm_pick()) and starts
 * the ECU at now_us. The loop keeps the three pointers. Returns PFE_OK, or
 * PFE_EINVAL for a configuration pfe_ecu_init() refuses.
 */
int hal_ecu_loop_init(hal_ecu_loop_t *loop, pfe_ecu_t *ecu, const pfe_ecu_config_t *cfg,
                      hal_can_t *can, hal_nvm_t *nvm, uint64_t now_us);

/* One pass at deadline now_us (see above). Returns how many frames it sent. */
uint32_t hal_ecu_loop_step(hal_ecu_loop_t *loop, uint64_t now_us);

/*
 * After the pass for *deadline_us, at now_us (the same clock): advances
 * *deadline_us to the next pass's deadline and says whether to wait for it
 * (see Pacing above). now_us no later than the next deadline is on time
 * (the STM32 feeds its watchdog only then). Late by more than a tick, the
 * next deadline stays the next tick's (CATCH_UP, one overrun counted),
 * unless more than HAL_ECU_LOOP_CATCH_UP_TICKS ticks are missed: then the
 * ticks up to now are skipped and counted, and the next deadline is the
 * last tick boundary before now (SKIPPED). Late by less than a tick is
 * on time's neighbour: the next pass runs at once with no count (CATCH_UP
 * with nothing counted). O(1); the skip count saturates at UINT32_MAX.
 */
hal_ecu_pace_t hal_ecu_loop_pace(hal_ecu_loop_t *loop, uint64_t *deadline_us, uint64_t now_us);

/* Writes the fuel totals now (when due, and at the end of a run) and
 * reports the result to the ECU: 0 or the backend's HAL_E* code. */
int hal_ecu_loop_save(hal_ecu_loop_t *loop);

#endif /* HAL_ECU_LOOP_H */
