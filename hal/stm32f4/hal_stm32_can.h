/*
 * hal_stm32_can.h - hal/hal_can.h on the STM32F4's bxCAN (CAN1), RM0090
 * chapter 32.
 *
 * Receive: the hardware filter banks (32-bit mask mode, FIFO 0) hold the
 * filters hal_can_add_filter() installs (hal_ecu_loop_init() installs the
 * ECU's pfe_ecu_rx_filters[]), so frames the module does not read never
 * reach software. The FIFO 0 interrupt (hal_stm32_can_rx0_isr()) moves each
 * frame into a single-producer single-consumer ring of HAL_STM32_CAN_RX_LEN
 * entries that hal_can_receive() empties from the main loop: no lock, the
 * interrupt writes only the head index, the main loop only the tail. A
 * frame lost in the FIFO (overrun: 3 frames arrived faster than the
 * interrupt ran) or in the ring (the main loop did not keep up) is counted.
 *
 * Transmit: a bounded queue of HAL_STM32_CAN_TXQ_LEN frames in front of the
 * three mailboxes. The hardware picks among pending mailboxes in
 * identifier order (MCR.TXFP = 0, as bus arbitration does); the driver
 * loads a mailbox only with a frame whose identifier comes after those of
 * the pending ones, so the module's frames still leave in the order they
 * were sent (hal_can.h's contract, and J1939-21 transport packets of one
 * identifier keep their sequence). The transmit-mailbox-empty interrupt
 * (hal_stm32_can_tx_isr()) refills them.
 *
 * Errors: the status-change interrupt (hal_stm32_can_sce_isr()) counts
 * entries into bus-off; error-warning, error-passive, bus-off and the two
 * error counters are read from ESR by hal_stm32_can_state(), which the
 * main loop hands to the ECU (pfe_ecu_note_bus_state(), PFE_DeviceStatus).
 * Bus-off recovery is the hardware's (MCR.ABOM: after 128 x 11 recessive
 * bits the controller rejoins the bus by itself); frames queued meanwhile
 * wait, and are refused with HAL_EAGAIN once the queue is full.
 *
 * Timeouts of the mode changes are measured with hal_stm32_now_us()
 * (hal/stm32f4/hal_stm32_time.h). Reentrancy: the three handlers may
 * interrupt any function here; everything else is for the main loop only.
 */
#ifndef HAL_STM32_CAN_H
#define HAL_STM32_CAN_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_can.h"
#include "hal/stm32f4/stm32f4_regs.h"

#define HAL_STM32_CAN_RX_LEN 128U        /* a power of two */
#define HAL_STM32_CAN_TXQ_LEN 32U        /* two ticks of the ECU's frames */
#define HAL_STM32_CAN_MAILBOXES 3U
#define HAL_STM32_CAN_MODE_TIMEOUT_US 10000U  /* INAK/SLAK acknowledge */
/* Filter banks of CAN1: CAN2 gets none (FMR.CAN2SB = 27, RM0090 32.7.4:
 * banks 0..26 belong to CAN1). Bank k holds filter k; the last one
 * accepts everything while no filter is installed. */
#define HAL_STM32_CAN_BANKS 27U
#define HAL_STM32_CAN_ACCEPT_ALL_BANK 26U

_Static_assert((HAL_STM32_CAN_RX_LEN & (HAL_STM32_CAN_RX_LEN - 1U)) == 0U, "ring size");
_Static_assert(HAL_CAN_MAX_FILTERS < HAL_STM32_CAN_ACCEPT_ALL_BANK, "banks");

/* One received frame as the interrupt stores it: the identifier in
 * pfe_can_frame_t's form, the low 32 bits of the microsecond clock. */
typedef struct {
    uint32_t id;
    uint32_t t_us;
    uint8_t dlc;
    uint8_t data[PFE_CAN_MAX_DLC];
} hal_stm32_can_entry_t;

struct hal_can {
    stm32_can_t *regs;
    uint32_t btr;
    /* Receive ring: head written by hal_stm32_can_rx0_isr() only, tail by
     * hal_can_receive() only; both count up and wrap. */
    hal_stm32_can_entry_t rx[HAL_STM32_CAN_RX_LEN];
    volatile uint32_t rx_head;
    volatile uint32_t rx_tail;
    volatile uint32_t rx_ring_drops;     /* interrupt: ring full */
    volatile uint32_t rx_fifo_overruns;  /* interrupt: FOVR0 seen */
    volatile uint32_t rx_remote_skipped; /* interrupt: remote frames (J1939 has none) */
    uint32_t rx_frames;
    /* Transmit queue and mailboxes: changed with interrupts masked. */
    pfe_can_frame_t txq[HAL_STM32_CAN_TXQ_LEN];
    uint32_t txq_head;
    uint32_t txq_count;
    uint32_t tx_done;                    /* mailbox completions acknowledged */
    uint32_t tx_failed;                  /* completions without TXOK */
    uint32_t tx_dropped;
    /* Filters as hal_can_add_filter() took them; loose ones (no EFF bit in
     * the mask: both frame formats) are checked again in software. */
    uint32_t filter_id[HAL_CAN_MAX_FILTERS];
    uint32_t filter_mask[HAL_CAN_MAX_FILTERS];
    bool filter_used[HAL_CAN_MAX_FILTERS];
    bool filter_loose[HAL_CAN_MAX_FILTERS];
    /* Error state as the status-change interrupt last saw it. */
    volatile bool bus_off_seen;
    volatile uint32_t bus_off_events;
    volatile uint32_t sce_interrupts;
};

/*
 * The bit timing register for bitrate_bps (250000: J1939-11, 500000:
 * J1939-14) from the 42 MHz APB1 clock: *btr and 0, or HAL_EINVAL for any
 * other rate. Derivation in hal_stm32_can.c.
 */
int hal_stm32_can_btr(uint32_t bitrate_bps, uint32_t *btr);

/*
 * Takes the controller at regs out of sleep into initialisation mode,
 * programs bit timing, filters (none: everything accepted), interrupts,
 * automatic bus-off recovery, and starts it on the bus. The caller owns
 * *can; its clock (RCC) must be on and its interrupts enabled in the NVIC.
 * Returns 0; HAL_EINVAL for an unsupported bitrate; HAL_EIO when the
 * controller did not acknowledge initialisation or normal mode within
 * HAL_STM32_CAN_MODE_TIMEOUT_US (no clock, or the RX pin held dominant).
 */
int hal_stm32_can_init(hal_can_t *can, stm32_can_t *regs, uint32_t bitrate_bps);

/* Sleep mode (MCR.SLEEP, waits for SLAK) and back to normal mode (waits
 * for SLAK and INAK to clear): 0 or HAL_EIO on timeout. Frames queued stay
 * queued across sleep. */
int hal_stm32_can_sleep(hal_can_t *can);
int hal_stm32_can_wake(hal_can_t *can);

/* The controller's error state, for pfe_ecu_note_bus_state():
 * rx_overruns counts FIFO overruns and ring overflows. Call it every tick:
 * it also notes the end of a bus-off (no interrupt says so), so that two
 * bus-off periods count two events when a tick lies between them. O(1). */
typedef struct {
    uint32_t rx_overruns;
    uint32_t bus_off_events;
    uint8_t tx_error_counter;
    uint8_t rx_error_counter;
    bool error_warning;
    bool error_passive;
    bool bus_off;
} hal_stm32_can_state_t;
void hal_stm32_can_state(hal_can_t *can, hal_stm32_can_state_t *out);

/* Interrupt handlers' bodies: CAN1_RX0 (FIFO 0 pending or overrun),
 * CAN1_TX (a mailbox emptied), CAN1_SCE (error status changed). */
void hal_stm32_can_rx0_isr(hal_can_t *can);
void hal_stm32_can_tx_isr(hal_can_t *can);
void hal_stm32_can_sce_isr(hal_can_t *can);

#endif /* HAL_STM32_CAN_H */
