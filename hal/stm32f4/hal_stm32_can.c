/* hal_stm32_can.c - hal/hal_can.h on bxCAN (contract in hal_stm32_can.h). */
#include "hal/stm32f4/hal_stm32_can.h"

#include <stddef.h>
#include <string.h>

#include "hal/hal_can_mem.h"
#include "hal/stm32f4/hal_stm32_time.h"
#include "hal/stm32f4/stm32f4_irq.h"


/*
 * Bit timing (RM0090 32.7.7). The CAN clock is APB1, 42 MHz. A bit is
 * 1 (sync) + BS1 + BS2 time quanta of BRP clocks each, 8 to 25 quanta,
 * BS1 1..16, BS2 1..8; the sample point sits after sync + BS1.
 *
 *   250 kbit/s: 42 MHz / 250 kHz = 168 clocks a bit = BRP x quanta, so
 *   quanta in {8, 12, 14, 21, 24}. 87.5 % exactly needs 8 quanta with
 *   BS2 = 1 quantum, under the 2 quanta of information processing time
 *   the CAN protocol needs after the sample point; 24 quanta would need
 *   BS1 = 20 > 16. The nearest with BS2 >= 2: 14 quanta, BRP 12, BS1 11,
 *   BS2 2: sample point 12/14 = 85.7 %.
 *   500 kbit/s: 84 clocks a bit, quanta in {7, 12, 14, 21}: again 14
 *   quanta, BRP 6, BS1 11, BS2 2, 85.7 %.
 *   SJW 1 quantum. Oscillator tolerance this allows (ISO 11898-1):
 *   min(SJW / (20 x 14), min(BS1, BS2) / (2 x (13 x 14 - BS2))) =
 *   min(0.357 %, 0.556 %) = 0.357 %, far above the crystal's 50 ppm, and
 *   below the HSI's 1 % (hal_stm32_board.h: the HSI fallback).
 *
 *   BTR = (SJW - 1) << 24 | (BS2 - 1) << 20 | (BS1 - 1) << 16 | (BRP - 1)
 *   250 kbit/s: 0 << 24 | 1 << 20 | 10 << 16 | 11 = 0x001A000B
 *   500 kbit/s: 0 << 24 | 1 << 20 | 10 << 16 |  5 = 0x001A0005
 */
#define BTR_SEGMENTS (((uint32_t)1U << 20) | ((uint32_t)10U << 16))

int hal_stm32_can_btr(uint32_t bitrate_bps, uint32_t *btr)
{
    if (bitrate_bps == 250000U) {
        *btr = BTR_SEGMENTS | (12U - 1U);
        return 0;
    }
    if (bitrate_bps == 500000U) {
        *btr = BTR_SEGMENTS | (6U - 1U);
        return 0;
    }
    return HAL_EINVAL;
}

/* Waits until (MSR & mask) == want, HAL_STM32_CAN_MODE_TIMEOUT_US at most. */
static int wait_msr(const hal_can_t *can, uint32_t mask, uint32_t want)
{
    const uint64_t t0 = hal_stm32_now_us();
    while ((can->regs->msr & mask) != want) {
        if ((hal_stm32_now_us() - t0) > HAL_STM32_CAN_MODE_TIMEOUT_US) {
            return HAL_EIO;
        }
    }
    return 0;
}

/* The register form of a frame's identifier (TIR, RIR, filter banks). */
static uint32_t reg_id(uint32_t id)
{
    if ((id & PFE_CAN_EFF_FLAG) != 0U) {
        return (((uint32_t)(id & PFE_CAN_ID_MASK)) << CAN_TIR_EXID_SHIFT) | CAN_TIR_IDE;
    }
    return (id & 0x7FFU) << CAN_TIR_STID_SHIFT;
}

static uint32_t frame_id(uint32_t rir)
{
    if ((rir & CAN_TIR_IDE) != 0U) {
        return ((rir >> CAN_TIR_EXID_SHIFT) & PFE_CAN_ID_MASK) | PFE_CAN_EFF_FLAG;
    }
    return (rir >> CAN_TIR_STID_SHIFT) & 0x7FFU;
}

static uint32_t bytes_le(const uint8_t *b)
{
    return (uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16) |
           ((uint32_t)b[3] << 24);
}

static void store_le32(uint8_t *b, uint32_t w)
{
    b[0] = (uint8_t)w;
    b[1] = (uint8_t)(w >> 8);
    b[2] = (uint8_t)(w >> 16);
    b[3] = (uint8_t)(w >> 24);
}

/* ------------------------------------------------------------------ filters */

/* Filter banks are changed in filter initialisation mode (FMR.FINIT);
 * reception pauses meanwhile. */
static void apply_filters(hal_can_t *can)
{
    stm32_can_t *r = can->regs;
    HAL_STM32_WR(r->fmr, CAN_FMR_FINIT | ((uint32_t)27U << CAN_FMR_CAN2SB_SHIFT));
    HAL_STM32_WR(r->fm1r, 0U);                           /* mask mode */
    HAL_STM32_WR(r->fs1r, ((uint32_t)1U << HAL_STM32_CAN_BANKS) - 1U); /* 32-bit scale */
    HAL_STM32_WR(r->ffa1r, 0U);                          /* FIFO 0 */
    uint32_t active = 0U;
    for (uint32_t k = 0U; k < HAL_CAN_MAX_FILTERS; k++) {
        if (!can->filter_used[k]) {
            continue;
        }
        const uint32_t id = can->filter_id[k];
        const uint32_t mask = can->filter_mask[k];
        if (can->filter_loose[k]) {
            /* Either format: no bank can say it; accept all here, decide
             * in the interrupt. */
            HAL_STM32_WR(r->filter[k].fr1, 0U);
            HAL_STM32_WR(r->filter[k].fr2, 0U);
        } else if (((id & PFE_CAN_EFF_FLAG) == 0U) && ((id & mask & 0x1FFFF800U) != 0U)) {
            /* A standard-frame filter on bits a standard id cannot have:
             * it matches nothing, so its bank stays off. */
            continue;
        } else {
            /* Mask bits in register form; IDE always compared, RTR too:
             * remote frames never match. */
            const uint32_t m = ((id & PFE_CAN_EFF_FLAG) != 0U)
                                   ? (((uint32_t)(mask & PFE_CAN_ID_MASK)) << CAN_TIR_EXID_SHIFT)
                                   : ((mask & 0x7FFU) << CAN_TIR_STID_SHIFT);
            HAL_STM32_WR(r->filter[k].fr1, reg_id(id));
            HAL_STM32_WR(r->filter[k].fr2, m | CAN_TIR_IDE | CAN_RIR_RTR);
        }
        active |= (uint32_t)1U << k;
    }
    bool any = false;
    for (uint32_t k = 0U; k < HAL_CAN_MAX_FILTERS; k++) {
        any = any || can->filter_used[k];
    }
    if (!any) {
        HAL_STM32_WR(r->filter[HAL_STM32_CAN_ACCEPT_ALL_BANK].fr1, 0U);
        HAL_STM32_WR(r->filter[HAL_STM32_CAN_ACCEPT_ALL_BANK].fr2, 0U);
        active = (uint32_t)1U << HAL_STM32_CAN_ACCEPT_ALL_BANK;
    }
    HAL_STM32_WR(r->fa1r, active);
    HAL_STM32_WR(r->fmr, (uint32_t)27U << CAN_FMR_CAN2SB_SHIFT);
}

int hal_can_add_filter(hal_can_t *can, uint32_t id, uint32_t mask)
{
    for (uint32_t k = 0U; k < HAL_CAN_MAX_FILTERS; k++) {
        if (!can->filter_used[k]) {
            can->filter_id[k] = id;
            can->filter_mask[k] = mask;
            can->filter_loose[k] = (mask & PFE_CAN_EFF_FLAG) == 0U;
            can->filter_used[k] = true;
            apply_filters(can);
            return (int)k;
        }
    }
    return HAL_ENOSPC;
}

int hal_can_remove_filter(hal_can_t *can, int index)
{
    if ((index < 0) || (index >= (int)HAL_CAN_MAX_FILTERS) || !can->filter_used[index]) {
        return HAL_EINVAL;
    }
    can->filter_used[index] = false;
    apply_filters(can);
    return 0;
}

/* ------------------------------------------------------------------ init, modes */

int hal_stm32_can_init(hal_can_t *can, stm32_can_t *regs, uint32_t bitrate_bps)
{
    uint32_t btr = 0U;
    if (hal_stm32_can_btr(bitrate_bps, &btr) != 0) {
        return HAL_EINVAL;
    }
    (void)memset(can, 0, sizeof *can);
    can->regs = regs;
    can->btr = btr;
    /* Out of sleep (the reset state) into initialisation mode. */
    HAL_STM32_WR(regs->mcr, CAN_MCR_INRQ);
    if (wait_msr(can, CAN_MSR_INAK | CAN_MSR_SLAK, CAN_MSR_INAK) != 0) {
        return HAL_EIO;
    }
    /* Automatic bus-off recovery, identifier-order mailboxes (TXFP = 0),
     * FIFO not locked, automatic retransmission. */
    HAL_STM32_WR(regs->mcr, CAN_MCR_INRQ | CAN_MCR_ABOM);
    HAL_STM32_WR(regs->btr, btr);
    apply_filters(can);
    HAL_STM32_WR(regs->ier, CAN_IER_TMEIE | CAN_IER_FMPIE0 | CAN_IER_FOVIE0 | CAN_IER_EWGIE |
                                CAN_IER_EPVIE | CAN_IER_BOFIE | CAN_IER_ERRIE);
    HAL_STM32_WR(regs->mcr, CAN_MCR_ABOM);
    return wait_msr(can, CAN_MSR_INAK | CAN_MSR_SLAK, 0U);
}

int hal_stm32_can_sleep(hal_can_t *can)
{
    HAL_STM32_WR(can->regs->mcr, CAN_MCR_ABOM | CAN_MCR_SLEEP);
    return wait_msr(can, CAN_MSR_INAK | CAN_MSR_SLAK, CAN_MSR_SLAK);
}

int hal_stm32_can_wake(hal_can_t *can)
{
    HAL_STM32_WR(can->regs->mcr, CAN_MCR_ABOM);
    return wait_msr(can, CAN_MSR_INAK | CAN_MSR_SLAK, 0U);
}

/* ------------------------------------------------------------------ transmit */

/* Acknowledges finished mailboxes and loads the queue's head into free
 * ones while it comes after every pending frame in identifier order.
 * Interrupts masked by the caller. */
static void tx_service(hal_can_t *can)
{
    stm32_can_t *r = can->regs;
    const uint32_t tsr = r->tsr;
    for (uint32_t m = 0U; m < HAL_STM32_CAN_MAILBOXES; m++) {
        const uint32_t rqcp = CAN_TSR_RQCP0 << (8U * m);
        if ((tsr & rqcp) != 0U) {
            if ((tsr & (CAN_TSR_TXOK0 << (8U * m))) != 0U) {
                can->tx_done++;
            } else {
                can->tx_failed++;
            }
            HAL_STM32_WR(r->tsr, rqcp); /* write 1 to clear RQCP, TXOK, ALST, TERR */
        }
    }
    while (can->txq_count > 0U) {
        const uint32_t now = r->tsr;
        const pfe_can_frame_t *f = &can->txq[can->txq_head];
        const uint32_t key = reg_id(f->id);
        uint32_t free_mb = HAL_STM32_CAN_MAILBOXES;
        bool blocked = false;
        for (uint32_t m = 0U; m < HAL_STM32_CAN_MAILBOXES; m++) {
            if ((now & (CAN_TSR_TME0 << m)) != 0U) {
                free_mb = (free_mb == HAL_STM32_CAN_MAILBOXES) ? m : free_mb;
            } else if ((r->tx[m].tir & ~CAN_TIR_TXRQ) >= key) {
                blocked = true; /* it would overtake a pending frame */
            } else {
                /* pending, before this frame: fine */
            }
        }
        if (blocked || (free_mb == HAL_STM32_CAN_MAILBOXES)) {
            break;
        }
        stm32_can_txmb_t *mb = &r->tx[free_mb];
        HAL_STM32_WR(mb->tdtr, f->dlc);
        HAL_STM32_WR(mb->tdlr, bytes_le(&f->data[0]));
        HAL_STM32_WR(mb->tdhr, bytes_le(&f->data[4]));
        HAL_STM32_WR(mb->tir, key | CAN_TIR_TXRQ);
        can->txq_head = (can->txq_head + 1U) % HAL_STM32_CAN_TXQ_LEN;
        can->txq_count--;
    }
}

int hal_can_send(hal_can_t *can, const pfe_can_frame_t *frame)
{
    if (!hal_can_mem_frame_valid(frame)) {
        return HAL_EINVAL;
    }
    const uint32_t primask = hal_stm32_irq_save();
    int rc = 0;
    if (can->txq_count == HAL_STM32_CAN_TXQ_LEN) {
        can->tx_dropped++;
        rc = HAL_EAGAIN;
    } else {
        const uint32_t tail = (can->txq_head + can->txq_count) % HAL_STM32_CAN_TXQ_LEN;
        pfe_can_frame_t *slot = &can->txq[tail];
        (void)memset(slot, 0, sizeof *slot);
        slot->id = frame->id;
        slot->dlc = frame->dlc;
        (void)memcpy(slot->data, frame->data, frame->dlc);
        can->txq_count++;
    }
    tx_service(can);
    hal_stm32_irq_restore(primask);
    return rc;
}

void hal_stm32_can_tx_isr(hal_can_t *can)
{
    const uint32_t primask = hal_stm32_irq_save();
    tx_service(can);
    hal_stm32_irq_restore(primask);
}

/* ------------------------------------------------------------------ receive */

static bool loose_accepts(const hal_can_t *can, uint32_t bank, uint32_t id)
{
    if ((bank >= HAL_CAN_MAX_FILTERS) || !can->filter_loose[bank]) {
        return true; /* the bank's own match was exact */
    }
    for (uint32_t k = 0U; k < HAL_CAN_MAX_FILTERS; k++) {
        if (can->filter_used[k] &&
            ((id & can->filter_mask[k]) == (can->filter_id[k] & can->filter_mask[k]))) {
            return true;
        }
    }
    return false;
}

void hal_stm32_can_rx0_isr(hal_can_t *can)
{
    stm32_can_t *r = can->regs;
    if ((r->rf0r & CAN_RF0R_FOVR0) != 0U) {
        can->rx_fifo_overruns = can->rx_fifo_overruns + 1U;
        HAL_STM32_WR(r->rf0r, CAN_RF0R_FOVR0 | CAN_RF0R_FULL0);
    }
    const uint32_t now_us = (uint32_t)hal_stm32_now_us();
    while ((r->rf0r & CAN_RF0R_FMP0) != 0U) {
        const uint32_t rir = r->rx[0].rir;
        const uint32_t rdtr = r->rx[0].rdtr;
        const uint32_t id = frame_id(rir);
        const uint32_t head = can->rx_head;
        if ((rir & CAN_RIR_RTR) != 0U) {
            can->rx_remote_skipped = can->rx_remote_skipped + 1U;
        } else if (!loose_accepts(can, (rdtr >> 8) & 0xFFU, id)) {
            /* a loose filter's bank let it in, no filter wants it */
        } else if ((head - can->rx_tail) >= HAL_STM32_CAN_RX_LEN) {
            can->rx_ring_drops = can->rx_ring_drops + 1U;
        } else {
            hal_stm32_can_entry_t *e = &can->rx[head % HAL_STM32_CAN_RX_LEN];
            e->id = id;
            e->t_us = now_us;
            const uint32_t dlc = rdtr & 0xFU;
            e->dlc = (uint8_t)((dlc > PFE_CAN_MAX_DLC) ? PFE_CAN_MAX_DLC : dlc);
            store_le32(&e->data[0], r->rx[0].rdlr);
            store_le32(&e->data[4], r->rx[0].rdhr);
            /* The entry is complete before the main loop can see it. */
            __atomic_thread_fence(__ATOMIC_RELEASE);
            can->rx_head = head + 1U;
        }
        HAL_STM32_WR(r->rf0r, CAN_RF0R_RFOM0); /* release the output mailbox */
    }
    if ((r->rf0r & CAN_RF0R_FULL0) != 0U) {
        HAL_STM32_WR(r->rf0r, CAN_RF0R_FULL0); /* drained: write 1 to clear */
    }
}

int hal_can_receive(hal_can_t *can, hal_can_rx_t *out)
{
    const uint32_t tail = can->rx_tail;
    if (can->rx_head == tail) {
        return HAL_EAGAIN;
    }
    __atomic_thread_fence(__ATOMIC_ACQUIRE);
    const hal_stm32_can_entry_t *e = &can->rx[tail % HAL_STM32_CAN_RX_LEN];
    (void)memset(out, 0, sizeof *out);
    out->frame.id = e->id;
    out->frame.dlc = e->dlc;
    (void)memcpy(out->frame.data, e->data, e->dlc);
    /* The 64-bit time of a stamp at most 2^32 us (71 min) old. */
    const uint64_t now = hal_stm32_now_us();
    out->timestamp_us = now - (uint64_t)((uint32_t)now - e->t_us);
    __atomic_thread_fence(__ATOMIC_RELEASE);
    can->rx_tail = tail + 1U;
    can->rx_frames++;
    return 0;
}

/* ------------------------------------------------------------------ errors, counters */

void hal_stm32_can_sce_isr(hal_can_t *can)
{
    stm32_can_t *r = can->regs;
    can->sce_interrupts = can->sce_interrupts + 1U;
    const bool off = (r->esr & CAN_ESR_BOFF) != 0U;
    if (off && !can->bus_off_seen) {
        can->bus_off_events = can->bus_off_events + 1U;
    }
    can->bus_off_seen = off;
    HAL_STM32_WR(r->msr, CAN_MSR_ERRI); /* write 1 to clear */
}

void hal_stm32_can_state(hal_can_t *can, hal_stm32_can_state_t *out)
{
    const uint32_t esr = can->regs->esr;
    /* ERRI comes only when a flag is set, never when bus-off ends: the
     * main loop sees the recovery, so that the next entry counts. */
    if ((esr & CAN_ESR_BOFF) == 0U) {
        const uint32_t primask = hal_stm32_irq_save();
        if ((can->regs->esr & CAN_ESR_BOFF) == 0U) {
            can->bus_off_seen = false;
        }
        hal_stm32_irq_restore(primask);
    }
    out->rx_overruns = can->rx_fifo_overruns + can->rx_ring_drops;
    out->bus_off_events = can->bus_off_events;
    out->tx_error_counter = (uint8_t)(esr >> CAN_ESR_TEC_SHIFT);
    out->rx_error_counter = (uint8_t)(esr >> CAN_ESR_REC_SHIFT);
    out->error_warning = (esr & CAN_ESR_EWGF) != 0U;
    out->error_passive = (esr & CAN_ESR_EPVF) != 0U;
    out->bus_off = (esr & CAN_ESR_BOFF) != 0U;
}

void hal_can_get_stats(const hal_can_t *can, hal_can_stats_t *out)
{
    /* Mailboxes finished but not yet acknowledged count as sent. */
    const uint32_t tsr = can->regs->tsr;
    uint32_t unacked = 0U;
    for (uint32_t m = 0U; m < HAL_STM32_CAN_MAILBOXES; m++) {
        if ((tsr & ((CAN_TSR_RQCP0 | CAN_TSR_TXOK0) << (8U * m))) ==
            ((CAN_TSR_RQCP0 | CAN_TSR_TXOK0) << (8U * m))) {
            unacked++;
        }
    }
    out->rx_frames = can->rx_frames;
    out->tx_frames = can->tx_done + unacked;
    /* A FIFO overrun loses at least one frame; how many the hardware does
     * not say. */
    out->rx_dropped = can->rx_fifo_overruns + can->rx_ring_drops;
    out->tx_dropped = can->tx_dropped + can->tx_failed;
}
