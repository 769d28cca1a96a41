/*
 * bxcan_model.h - a register-level model of STM32F4 bxCAN controllers on
 * one bus, for driving hal/stm32f4/hal_stm32_can.c on the host.
 *
 * Each node is a register block (stm32_can_t) the driver is given as its
 * CAN1. Writes reach the model through hal_stm32_reg_write()
 * (tests/stm32/reg_model.c) and get RM0090's semantics: INRQ/SLEEP
 * acknowledged in MSR (unless a node is told to hang), write-1-to-clear
 * flags, TXRQ making a mailbox pending, RFOM0 releasing FIFO 0's output
 * mailbox, bit timing and filters writable only in their init modes
 * (a violation is counted in `misuse`).
 *
 * The bus: in stepped mode bxcan_bus_step() puts one frame on the bus, the
 * pending mailbox of lowest identifier over all nodes (TXFP = 0; TXFP = 1:
 * the oldest request), delivers it to every other node in normal mode
 * through its filter banks (32-bit mask mode, first matching bank's number
 * in RDTR.FMI) into its 3-deep FIFO 0 (full: the last entry is
 * overwritten, FOVR0 set), then runs the interrupts the driver enabled
 * (FMPIE0/FOVIE0 -> rx0 handler, TMEIE -> tx handler, ERRIE -> sce). In
 * auto mode a mailbox goes on the bus the moment it is requested and the
 * receivers' interrupts run at once (the conformance suite's bus).
 * Error counters move as ISO 11898-1 has them (+8 per transmit error,
 * -1 per success); above 255 the node is bus-off, and with MCR.ABOM it
 * recovers after 128 x 11 recessive bits (bxcan_bus_idle_bits()).
 */
#ifndef BXCAN_MODEL_H
#define BXCAN_MODEL_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/stm32f4/hal_stm32_can.h"

#define BXCAN_MODEL_NODES 4U
#define BXCAN_MODEL_LOG 512U

typedef struct {
    uint32_t rir;
    uint32_t rdtr;
    uint32_t rdlr;
    uint32_t rdhr;
} bxcan_model_msg_t;

typedef struct {
    stm32_can_t regs;
    hal_can_t *driver;           /* whose handlers the interrupts call */
    bool used;
    bool irq_enabled;            /* false: interrupts held pending */
    bool hang_init;              /* never acknowledges INRQ */
    bool hang_sleep;             /* never acknowledges SLEEP */
    bxcan_model_msg_t fifo[3];
    uint32_t fifo_count;
    uint32_t tx_seq[3];          /* request order, for TXFP = 1 */
    uint32_t tec;
    uint32_t rec;
    bool bus_off;
    uint32_t recessive_runs;     /* 11-bit recessive sequences seen in bus-off */
    uint32_t fifo_lost;          /* frames the model overwrote */
    uint32_t filtered_out;       /* frames no bank accepted */
    uint32_t misuse;             /* writes RM0090 forbids in that mode */
    uint32_t mode_changes;       /* writes of MCR */
} bxcan_node_t;

typedef struct {
    bxcan_node_t node[BXCAN_MODEL_NODES];
    bool auto_transmit;
    uint32_t seq;
    uint32_t log_tir[BXCAN_MODEL_LOG];  /* frames on the bus, TIR form, in order */
    uint32_t log_node[BXCAN_MODEL_LOG];
    uint32_t log_n;
    uint64_t now_us;                    /* the model's clock (hal_stm32_now_us()) */
} bxcan_bus_t;

extern bxcan_bus_t bxcan_bus;

void bxcan_bus_reset(bool auto_transmit);
/* A node in its reset state (sleep mode, RM0090 32.4): MCR 0x00010002,
 * MSR 0x00000C02, TSR 0x1C000000, all mailboxes empty. */
bxcan_node_t *bxcan_node_add(void);
void bxcan_node_remove(bxcan_node_t *n);
/* Which driver instance the node's interrupts are for. */
void bxcan_node_attach(bxcan_node_t *n, hal_can_t *driver);
/* Runs the node's pending interrupts now (after irq_enabled became true). */
void bxcan_node_irq(bxcan_node_t *n);
/* One frame on the bus; false when no mailbox is pending. */
bool bxcan_bus_step(void);
/* Steps until no mailbox is pending (at most max frames): frames sent. */
uint32_t bxcan_bus_run(uint32_t max);
/* A frame from a node outside the model (another ECU): delivered to all. */
void bxcan_bus_inject(uint32_t id, uint8_t dlc, const uint8_t *data);
/* n transmit errors on node (TEC + 8 each), or n receive errors (REC + 1). */
void bxcan_node_tx_errors(bxcan_node_t *n, uint32_t count);
void bxcan_node_rx_errors(bxcan_node_t *n, uint32_t count);
/* bits recessive bits on the bus: bus-off recovery under ABOM. */
void bxcan_bus_idle_bits(uint32_t bits);

void bxcan_model_write(bxcan_node_t *n, volatile uint32_t *reg, uint32_t value);
bxcan_node_t *bxcan_model_node_of(const volatile uint32_t *reg);

#endif /* BXCAN_MODEL_H */
