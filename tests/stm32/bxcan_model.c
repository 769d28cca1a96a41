/* bxcan_model.c - bxCAN register model (bxcan_model.h). */
#include "tests/stm32/bxcan_model.h"

#include <stddef.h>
#include <string.h>

bxcan_bus_t bxcan_bus;

#define TSR_MB_BITS(m) (0xFFU << (8U * (m)))
#define TSR_TME(m) (CAN_TSR_TME0 << (m))
#define RF0R_W1C (CAN_RF0R_FULL0 | CAN_RF0R_FOVR0)
#define MSR_W1C (CAN_MSR_ERRI | (1U << 3) | (1U << 4))

void bxcan_bus_reset(bool auto_transmit)
{
    (void)memset(&bxcan_bus, 0, sizeof bxcan_bus);
    bxcan_bus.auto_transmit = auto_transmit;
}

static void node_reset_regs(bxcan_node_t *n)
{
    (void)memset(&n->regs, 0, sizeof n->regs);
    n->regs.mcr = 0x00010002U;
    n->regs.msr = 0x00000C02U;
    n->regs.tsr = 0x1C000000U;
    n->regs.btr = 0x01230000U;
    n->regs.fmr = 0x2A1C0E01U; /* FINIT, CAN2SB 14 */
    n->fifo_count = 0U;
}

bxcan_node_t *bxcan_node_add(void)
{
    for (uint32_t k = 0U; k < BXCAN_MODEL_NODES; k++) {
        bxcan_node_t *n = &bxcan_bus.node[k];
        if (!n->used) {
            (void)memset(n, 0, sizeof *n);
            n->used = true;
            n->irq_enabled = true;
            node_reset_regs(n);
            return n;
        }
    }
    return NULL;
}

void bxcan_node_remove(bxcan_node_t *n)
{
    n->used = false;
    n->driver = NULL;
}

void bxcan_node_attach(bxcan_node_t *n, hal_can_t *driver)
{
    n->driver = driver;
}

bxcan_node_t *bxcan_model_node_of(const volatile uint32_t *reg)
{
    for (uint32_t k = 0U; k < BXCAN_MODEL_NODES; k++) {
        const bxcan_node_t *n = &bxcan_bus.node[k];
        const char *lo = (const char *)&n->regs;
        const char *p = (const char *)(uintptr_t)reg;
        if (n->used && (p >= lo) && (p < (lo + sizeof n->regs))) {
            return &bxcan_bus.node[k];
        }
    }
    return NULL;
}

static bool in_normal_mode(const bxcan_node_t *n)
{
    return n->used && ((n->regs.msr & (CAN_MSR_INAK | CAN_MSR_SLAK)) == 0U) && !n->bus_off;
}

/* FIFO 0's state into RF0R and the output mailbox. */
static void sync_fifo(bxcan_node_t *n)
{
    n->regs.rf0r = (n->regs.rf0r & RF0R_W1C) | n->fifo_count;
    if (n->fifo_count == 3U) {
        n->regs.rf0r |= CAN_RF0R_FULL0;
    }
    if (n->fifo_count > 0U) {
        n->regs.rx[0].rir = n->fifo[0].rir;
        n->regs.rx[0].rdtr = n->fifo[0].rdtr;
        n->regs.rx[0].rdlr = n->fifo[0].rdlr;
        n->regs.rx[0].rdhr = n->fifo[0].rdhr;
    }
}

static void sync_esr(bxcan_node_t *n)
{
    const uint32_t before = n->regs.esr & (CAN_ESR_EWGF | CAN_ESR_EPVF | CAN_ESR_BOFF);
    uint32_t flags = 0U;
    if ((n->tec >= 96U) || (n->rec >= 96U)) {
        flags |= CAN_ESR_EWGF;
    }
    if ((n->tec > 127U) || (n->rec > 127U)) {
        flags |= CAN_ESR_EPVF;
    }
    if (n->bus_off) {
        flags |= CAN_ESR_BOFF;
    }
    const uint32_t tec = (n->tec > 255U) ? 255U : n->tec;
    const uint32_t rec = (n->rec > 255U) ? 255U : n->rec;
    n->regs.esr = flags | (tec << CAN_ESR_TEC_SHIFT) | (rec << CAN_ESR_REC_SHIFT) |
                  (n->regs.esr & 0x70U);
    const uint32_t changed = (before ^ flags) & flags; /* flags that came on */
    const uint32_t ier = n->regs.ier;
    if (((ier & CAN_IER_ERRIE) != 0U) &&
        ((((changed & CAN_ESR_EWGF) != 0U) && ((ier & CAN_IER_EWGIE) != 0U)) ||
         (((changed & CAN_ESR_EPVF) != 0U) && ((ier & CAN_IER_EPVIE) != 0U)) ||
         (((changed & CAN_ESR_BOFF) != 0U) && ((ier & CAN_IER_BOFIE) != 0U)))) {
        n->regs.msr |= CAN_MSR_ERRI;
    }
}

void bxcan_node_irq(bxcan_node_t *n)
{
    if (!n->irq_enabled || (n->driver == NULL)) {
        return;
    }
    const uint32_t ier = n->regs.ier;
    if ((((ier & CAN_IER_FMPIE0) != 0U) && ((n->regs.rf0r & CAN_RF0R_FMP0) != 0U)) ||
        (((ier & CAN_IER_FOVIE0) != 0U) && ((n->regs.rf0r & CAN_RF0R_FOVR0) != 0U))) {
        hal_stm32_can_rx0_isr(n->driver);
    }
    if (((ier & CAN_IER_TMEIE) != 0U) &&
        ((n->regs.tsr & (CAN_TSR_RQCP0 | CAN_TSR_RQCP1 | CAN_TSR_RQCP2)) != 0U)) {
        hal_stm32_can_tx_isr(n->driver);
    }
    if ((n->regs.msr & CAN_MSR_ERRI) != 0U) {
        hal_stm32_can_sce_isr(n->driver);
    }
}

/* Delivers a frame (TIR form, TXRQ clear) to node n if it listens. */
static void deliver(bxcan_node_t *n, uint32_t tir, uint32_t dlc, uint32_t lo, uint32_t hi)
{
    if (!in_normal_mode(n) || ((n->regs.fmr & CAN_FMR_FINIT) != 0U)) {
        return;
    }
    const uint32_t can2sb = (n->regs.fmr & CAN_FMR_CAN2SB_MASK) >> CAN_FMR_CAN2SB_SHIFT;
    uint32_t bank = 28U;
    for (uint32_t b = 0U; (b < can2sb) && (bank == 28U); b++) {
        const uint32_t bit = 1U << b;
        if (((n->regs.fa1r & bit) == 0U) || ((n->regs.fm1r & bit) != 0U) ||
            ((n->regs.fs1r & bit) == 0U) || ((n->regs.ffa1r & bit) != 0U)) {
            continue; /* off, list mode, 16-bit or FIFO 1: not modelled, not used */
        }
        if (((tir ^ n->regs.filter[b].fr1) & n->regs.filter[b].fr2) == 0U) {
            bank = b;
        }
    }
    if (bank == 28U) {
        n->filtered_out++;
        return;
    }
    n->rec = (n->rec > 0U) ? (n->rec - 1U) : 0U;
    const bxcan_model_msg_t m = {tir, dlc | (bank << 8), lo, hi};
    if (n->fifo_count == 3U) {
        n->fifo[2] = m;  /* RFLM = 0: the newest overwrites the last */
        n->fifo_lost++;
        n->regs.rf0r |= CAN_RF0R_FOVR0;
    } else {
        n->fifo[n->fifo_count] = m;
        n->fifo_count++;
    }
    sync_fifo(n);
    sync_esr(n);
}

static void log_frame(uint32_t tir, uint32_t node)
{
    if (bxcan_bus.log_n < BXCAN_MODEL_LOG) {
        bxcan_bus.log_tir[bxcan_bus.log_n] = tir;
        bxcan_bus.log_node[bxcan_bus.log_n] = node;
    }
    bxcan_bus.log_n++;
}

/* Mailbox m of node s goes on the bus: delivered, completed. */
static void transmit(uint32_t s, uint32_t m)
{
    bxcan_node_t *src = &bxcan_bus.node[s];
    const stm32_can_txmb_t *mb = &src->regs.tx[m];
    const uint32_t tir = mb->tir & ~CAN_TIR_TXRQ;
    log_frame(tir, s);
    for (uint32_t k = 0U; k < BXCAN_MODEL_NODES; k++) {
        if (k != s) {
            deliver(&bxcan_bus.node[k], tir, mb->tdtr & 0xFU, mb->tdlr, mb->tdhr);
        }
    }
    src->regs.tx[m].tir = tir;
    src->regs.tsr |= TSR_TME(m) | ((CAN_TSR_RQCP0 | CAN_TSR_TXOK0) << (8U * m));
    src->tec = (src->tec > 0U) ? (src->tec - 1U) : 0U;
    sync_esr(src);
}

static bool pending(const bxcan_node_t *n, uint32_t m)
{
    return (n->regs.tsr & TSR_TME(m)) == 0U;
}

bool bxcan_bus_step(void)
{
    uint32_t best_node = BXCAN_MODEL_NODES;
    uint32_t best_mb = 0U;
    uint32_t best_key = 0U;
    uint32_t best_seq = 0U;
    for (uint32_t k = 0U; k < BXCAN_MODEL_NODES; k++) {
        const bxcan_node_t *n = &bxcan_bus.node[k];
        if (!in_normal_mode(n)) {
            continue;
        }
        const bool fifo_prio = (n->regs.mcr & CAN_MCR_TXFP) != 0U;
        for (uint32_t m = 0U; m < 3U; m++) {
            if (!pending(n, m)) {
                continue;
            }
            /* Within a node: TXFP chooses; across nodes: arbitration. */
            const uint32_t key = n->regs.tx[m].tir & ~CAN_TIR_TXRQ;
            bool better = best_node == BXCAN_MODEL_NODES;
            if (!better && (best_node == k) && fifo_prio) {
                better = n->tx_seq[m] < best_seq;
            } else if (!better) {
                better = key < best_key;
            } else {
                /* first candidate */
            }
            if (better) {
                best_node = k;
                best_mb = m;
                best_key = key;
                best_seq = n->tx_seq[m];
            }
        }
    }
    if (best_node == BXCAN_MODEL_NODES) {
        return false;
    }
    transmit(best_node, best_mb);
    for (uint32_t k = 0U; k < BXCAN_MODEL_NODES; k++) {
        if (bxcan_bus.node[k].used) {
            bxcan_node_irq(&bxcan_bus.node[k]);
        }
    }
    bxcan_bus.now_us += 500U; /* a 29-bit 8-byte frame at 250 kbit/s */
    return true;
}

uint32_t bxcan_bus_run(uint32_t max)
{
    uint32_t n = 0U;
    while ((n < max) && bxcan_bus_step()) {
        n++;
    }
    return n;
}

void bxcan_bus_inject(uint32_t id, uint8_t dlc, const uint8_t *data)
{
    uint32_t tir;
    if ((id & PFE_CAN_EFF_FLAG) != 0U) {
        tir = (((uint32_t)(id & PFE_CAN_ID_MASK)) << CAN_TIR_EXID_SHIFT) | CAN_TIR_IDE;
    } else {
        tir = (id & 0x7FFU) << CAN_TIR_STID_SHIFT;
    }
    uint8_t b[8] = {0};
    (void)memcpy(b, data, dlc);
    const uint32_t lo = (uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16) |
                        ((uint32_t)b[3] << 24);
    const uint32_t hi = (uint32_t)b[4] | ((uint32_t)b[5] << 8) | ((uint32_t)b[6] << 16) |
                        ((uint32_t)b[7] << 24);
    log_frame(tir, BXCAN_MODEL_NODES);
    for (uint32_t k = 0U; k < BXCAN_MODEL_NODES; k++) {
        deliver(&bxcan_bus.node[k], tir, dlc, lo, hi);
    }
    for (uint32_t k = 0U; k < BXCAN_MODEL_NODES; k++) {
        if (bxcan_bus.node[k].used) {
            bxcan_node_irq(&bxcan_bus.node[k]);
        }
    }
    bxcan_bus.now_us += 500U;
}

void bxcan_node_tx_errors(bxcan_node_t *n, uint32_t count)
{
    n->tec += 8U * count;
    if (n->tec > 255U) {
        n->bus_off = true;
        n->recessive_runs = 0U;
    }
    sync_esr(n);
    bxcan_node_irq(n);
}

void bxcan_node_rx_errors(bxcan_node_t *n, uint32_t count)
{
    n->rec += count;
    sync_esr(n);
    bxcan_node_irq(n);
}

void bxcan_bus_idle_bits(uint32_t bits)
{
    for (uint32_t k = 0U; k < BXCAN_MODEL_NODES; k++) {
        bxcan_node_t *n = &bxcan_bus.node[k];
        if (!n->used || !n->bus_off || ((n->regs.mcr & CAN_MCR_ABOM) == 0U)) {
            continue;
        }
        n->recessive_runs += bits / 11U;
        if (n->recessive_runs >= 128U) {
            n->bus_off = false;
            n->tec = 0U;
            n->rec = 0U;
            sync_esr(n);
        }
    }
}

/* ------------------------------------------------------------------ writes */

static void write_mcr(bxcan_node_t *n, uint32_t value)
{
    n->mode_changes++;
    if ((value & CAN_MCR_RESET) != 0U) {
        node_reset_regs(n);
        return;
    }
    n->regs.mcr = value & 0x000100FFU;
    uint32_t msr = n->regs.msr & ~(CAN_MSR_INAK | CAN_MSR_SLAK);
    if ((value & CAN_MCR_INRQ) != 0U) {
        msr |= n->hang_init ? (n->regs.msr & (CAN_MSR_INAK | CAN_MSR_SLAK)) : CAN_MSR_INAK;
    } else if ((value & CAN_MCR_SLEEP) != 0U) {
        msr |= n->hang_sleep ? (n->regs.msr & (CAN_MSR_INAK | CAN_MSR_SLAK)) : CAN_MSR_SLAK;
    } else if (n->hang_init) {
        msr |= n->regs.msr & (CAN_MSR_INAK | CAN_MSR_SLAK);
    } else {
        /* normal mode */
    }
    n->regs.msr = msr;
}

static void write_tsr(bxcan_node_t *n, uint32_t value)
{
    for (uint32_t m = 0U; m < 3U; m++) {
        if ((value & (CAN_TSR_RQCP0 << (8U * m))) != 0U) {
            n->regs.tsr &= ~(0x0FU << (8U * m)); /* RQCP, TXOK, ALST, TERR */
        }
        if (((value & ((1U << 7) << (8U * m))) != 0U) && pending(n, m)) {
            n->regs.tx[m].tir &= ~CAN_TIR_TXRQ; /* abort */
            n->regs.tsr |= TSR_TME(m) | (CAN_TSR_RQCP0 << (8U * m));
        }
    }
}

static void write_tir(bxcan_node_t *n, uint32_t m, uint32_t value)
{
    if (pending(n, m)) {
        n->misuse++; /* written while pending: RM0090 forbids */
        return;
    }
    n->regs.tx[m].tir = value;
    if ((value & CAN_TIR_TXRQ) != 0U) {
        n->regs.tsr &= ~(TSR_TME(m) | TSR_MB_BITS(m));
        n->tx_seq[m] = ++bxcan_bus.seq;
        if (bxcan_bus.auto_transmit && in_normal_mode(n)) {
            transmit((uint32_t)(n - bxcan_bus.node), m);
            for (uint32_t k = 0U; k < BXCAN_MODEL_NODES; k++) {
                bxcan_node_t *o = &bxcan_bus.node[k];
                if (o->used && (o != n)) {
                    bxcan_node_irq(o);
                }
            }
        }
    }
}

void bxcan_model_write(bxcan_node_t *n, volatile uint32_t *reg, uint32_t value)
{
    stm32_can_t *r = &n->regs;
    const bool init = (r->msr & CAN_MSR_INAK) != 0U;
    const bool finit = (r->fmr & CAN_FMR_FINIT) != 0U;
    if (reg == &r->mcr) {
        write_mcr(n, value);
    } else if (reg == &r->msr) {
        r->msr &= ~(value & MSR_W1C);
    } else if (reg == &r->tsr) {
        write_tsr(n, value);
    } else if (reg == &r->rf0r) {
        r->rf0r &= ~(value & RF0R_W1C);
        if (((value & CAN_RF0R_RFOM0) != 0U) && (n->fifo_count > 0U)) {
            n->fifo[0] = n->fifo[1];
            n->fifo[1] = n->fifo[2];
            n->fifo_count--;
        }
        sync_fifo(n);
    } else if (reg == &r->btr) {
        if (!init) {
            n->misuse++;
            return;
        }
        r->btr = value;
    } else if ((reg == &r->fm1r) || (reg == &r->fs1r) || (reg == &r->ffa1r)) {
        if (!finit) {
            n->misuse++;
            return;
        }
        *reg = value;
    } else if ((reg >= &r->filter[0].fr1) && (reg <= &r->filter[27].fr2)) {
        const uint32_t bank = (uint32_t)(reg - &r->filter[0].fr1) / 2U;
        if (!finit && ((r->fa1r & (1U << bank)) != 0U)) {
            n->misuse++; /* an active bank outside filter init mode */
            return;
        }
        *reg = value;
    } else {
        for (uint32_t m = 0U; m < 3U; m++) {
            if (reg == &r->tx[m].tir) {
                write_tir(n, m, value);
                return;
            }
            if ((reg == &r->tx[m].tdtr) || (reg == &r->tx[m].tdlr) || (reg == &r->tx[m].tdhr)) {
                if (pending(n, m)) {
                    n->misuse++;
                    return;
                }
            }
        }
        *reg = value; /* IER, FMR, FA1R, data registers */
    }
}
