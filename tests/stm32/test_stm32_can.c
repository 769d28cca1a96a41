/*
 * The bxCAN driver (hal/stm32f4/hal_stm32_can.c) against the register
 * model (tests/stm32/bxcan_model.h), stepped one frame at a time: init
 * sequence and register values, bit timing, mode changes and their
 * timeouts, the ECU's filters in the hardware banks, mailbox order, FIFO
 * overrun and ring overflow, error states, bus-off and its recovery.
 * Expected register values are literals derived by hand from RM0090.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "firmware/pfe_ecu.h"
#include "hal/hal_ecu_loop.h"
#include "hal/stm32f4/hal_stm32_can.h"
#include "tests/stm32/bxcan_model.h"

#define EFF PFE_CAN_EFF_FLAG

static hal_can_t g_a;
static hal_can_t g_b;
static bxcan_node_t *g_na;
static bxcan_node_t *g_nb;

static int setup(void **state)
{
    (void)state;
    bxcan_bus_reset(false);
    g_na = bxcan_node_add();
    g_nb = bxcan_node_add();
    bxcan_node_attach(g_na, &g_a);
    bxcan_node_attach(g_nb, &g_b);
    if ((hal_stm32_can_init(&g_a, &g_na->regs, 250000U) != 0) ||
        (hal_stm32_can_init(&g_b, &g_nb->regs, 250000U) != 0)) {
        return -1;
    }
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    assert_int_equal(g_na->misuse, 0U);
    assert_int_equal(g_nb->misuse, 0U);
    return 0;
}

static void send(hal_can_t *can, uint32_t id, uint8_t first)
{
    pfe_can_frame_t f;
    memset(&f, 0xA5, sizeof f);
    f.id = id;
    f.dlc = 8U;
    for (uint8_t k = 0U; k < 8U; k++) {
        f.data[k] = (uint8_t)(first + k);
    }
    assert_int_equal(hal_can_send(can, &f), 0);
}

static void expect_rx(hal_can_t *can, uint32_t id, uint8_t first)
{
    hal_can_rx_t rx;
    memset(&rx, 0xA5, sizeof rx);
    assert_int_equal(hal_can_receive(can, &rx), 0);
    assert_int_equal(rx.frame.id, id);
    assert_int_equal(rx.frame.dlc, 8U);
    assert_int_equal(rx.frame.data[0], first);
    assert_int_equal(rx.frame.data[7], (uint8_t)(first + 7U));
}

static void expect_rx_empty(hal_can_t *can)
{
    hal_can_rx_t rx;
    assert_int_equal(hal_can_receive(can, &rx), HAL_EAGAIN);
}

/* ------------------------------------------------------------------ timing, init */

static void test_bit_timing_register_values(void **state)
{
    (void)state;
    uint32_t btr = 0xA5A5A5A5U;
    assert_int_equal(hal_stm32_can_btr(250000U, &btr), 0);
    assert_int_equal(btr, 0x001A000BU);
    btr = 0xA5A5A5A5U;
    assert_int_equal(hal_stm32_can_btr(500000U, &btr), 0);
    assert_int_equal(btr, 0x001A0005U);
    btr = 0xA5A5A5A5U;
    assert_int_equal(hal_stm32_can_btr(125000U, &btr), HAL_EINVAL);
    assert_int_equal(btr, 0xA5A5A5A5U);
    /* Back from the fields, in double precision: rate and sample point. */
    const uint32_t rates[2] = {250000U, 500000U};
    for (uint32_t k = 0U; k < 2U; k++) {
        assert_int_equal(hal_stm32_can_btr(rates[k], &btr), 0);
        const double brp = (double)((btr & 0x3FFU) + 1U);
        const double ts1 = (double)(((btr >> 16) & 0xFU) + 1U);
        const double ts2 = (double)(((btr >> 20) & 0x7U) + 1U);
        const double rate = 42.0e6 / (brp * (1.0 + ts1 + ts2));
        const double sample_pct = 100.0 * (1.0 + ts1) / (1.0 + ts1 + ts2);
        assert_int_equal((uint32_t)(rate + 0.5), rates[k]);
        assert_in_range((uint32_t)(sample_pct * 10.0 + 0.5), 850U, 880U); /* 85.7 % */
        assert_int_equal((btr >> 24) & 3U, 0U);                          /* SJW 1 */
    }
}

static void test_init_programs_the_controller(void **state)
{
    (void)state;
    /* The register block as RM0090 32.9.5 lays it out. */
    assert_int_equal(offsetof(stm32_can_t, tx), 0x180U);
    assert_int_equal(offsetof(stm32_can_t, rx), 0x1B0U);
    assert_int_equal(offsetof(stm32_can_t, fmr), 0x200U);
    assert_int_equal(offsetof(stm32_can_t, fa1r), 0x21CU);
    assert_int_equal(offsetof(stm32_can_t, filter), 0x240U);
    assert_int_equal(sizeof(stm32_can_t), 0x320U);
    const stm32_can_t *r = &g_na->regs;
    assert_int_equal(r->mcr, 0x00000040U);             /* ABOM; TXFP 0; out of init and sleep */
    assert_int_equal(r->msr & 3U, 0U);                 /* INAK, SLAK clear: normal mode */
    assert_int_equal(r->btr, 0x001A000BU);
    assert_int_equal(r->ier, 0x0000870BU);             /* TME FMP0 FOV0 EWG EPV BOF ERR */
    assert_int_equal(r->fmr, 0x00001B00U);             /* CAN2SB 27, FINIT clear */
    assert_int_equal(r->fm1r, 0U);                     /* mask mode */
    assert_int_equal(r->fs1r, 0x07FFFFFFU);            /* 32-bit, banks 0..26 */
    assert_int_equal(r->ffa1r, 0U);                    /* FIFO 0 */
    assert_int_equal(r->fa1r, 0x04000000U);            /* bank 26: accept all */
    assert_int_equal(r->filter[26].fr2, 0U);
    /* Set-up in initialisation mode, then one write to leave it: the
     * mode-changing writes were INRQ, INRQ | ABOM, ABOM. */
    assert_int_equal(g_na->mode_changes, 3U);
}

static void test_init_refuses_other_bitrates(void **state)
{
    (void)state;
    hal_can_t c;
    assert_int_equal(hal_stm32_can_init(&c, &g_na->regs, 1000000U), HAL_EINVAL);
}

static void test_init_times_out_when_the_controller_does_not_acknowledge(void **state)
{
    (void)state;
    bxcan_node_t *n = bxcan_node_add();
    hal_can_t c;
    n->hang_init = true;
    const uint64_t t0 = bxcan_bus.now_us;
    assert_int_equal(hal_stm32_can_init(&c, &n->regs, 250000U), HAL_EIO);
    /* It waited its timeout and no longer. */
    assert_in_range(bxcan_bus.now_us - t0, HAL_STM32_CAN_MODE_TIMEOUT_US,
                    HAL_STM32_CAN_MODE_TIMEOUT_US + 10U);
    bxcan_node_remove(n);
}

static void test_sleep_and_wake(void **state)
{
    (void)state;
    assert_int_equal(hal_stm32_can_sleep(&g_a), 0);
    assert_int_equal(g_na->regs.msr & 3U, 2U);          /* SLAK */
    assert_int_equal(g_na->regs.mcr, 0x00000042U);      /* ABOM | SLEEP */
    /* Asleep it takes no frame from the bus. */
    send(&g_b, 0x123U, 1U);
    assert_int_equal(bxcan_bus_run(10U), 1U);
    expect_rx_empty(&g_a);
    assert_int_equal(hal_stm32_can_wake(&g_a), 0);
    assert_int_equal(g_na->regs.msr & 3U, 0U);
    send(&g_b, 0x124U, 2U);
    assert_int_equal(bxcan_bus_run(10U), 1U);
    expect_rx(&g_a, 0x124U, 2U);
    /* A controller that never acknowledges sleep: HAL_EIO after the timeout. */
    g_na->hang_sleep = true;
    assert_int_equal(hal_stm32_can_sleep(&g_a), HAL_EIO);
    g_na->hang_sleep = false;
    assert_int_equal(hal_stm32_can_wake(&g_a), 0);
}

/* ------------------------------------------------------------------ filters */

/* The ECU's receive list as hal_ecu_loop_init() installs it: each PGN in
 * the list reaches the ring from any source, a PGN not in it never does. */
static void test_ecu_filters_are_hardware_banks(void **state)
{
    (void)state;
    static pfe_ecu_t ecu;
    static hal_ecu_loop_t loop;
    pfe_ecu_config_t cfg;
    hal_ecu_loop_config(&cfg, PFE_ECU_DEFAULT_ADDRESS, 60000U, 1U, 0U, 10000U);
    /* No NVM: the loop reads its two slots through hal_nvm_read (below). */
    assert_int_equal(hal_ecu_loop_init(&loop, &ecu, &cfg, &g_a, NULL, 0U), PFE_OK);
    assert_int_equal(loop.filters, PFE_ECU_RX_FILTERS);
    const stm32_can_t *r = &g_na->regs;
    assert_int_equal(r->fa1r, (1U << PFE_ECU_RX_FILTERS) - 1U);
    /* Bank 0, CCVS1 (PGN 65265 = 0xFEF1), any priority and source:
     * FR1 = 0x00FEF100 << 3 | IDE = 0x07F78804,
     * FR2 = 0x03FFFF00 << 3 | IDE | RTR = 0x1FFFF806. */
    assert_int_equal(r->filter[0].fr1, 0x07F78804U);
    assert_int_equal(r->filter[0].fr2, 0x1FFFF806U);
    for (uint32_t k = 0U; k < PFE_ECU_RX_FILTERS; k++) {
        const uint8_t d[8] = {(uint8_t)k, 0, 0, 0, 0, 0, 0, 0};
        /* Priority 7 and source 0x2A, whatever the filter's own. */
        const uint32_t id = EFF | 0x1C000000U | (pfe_ecu_rx_filters[k].id & 0x03FFFF00U) | 0x2AU;
        bxcan_bus_inject(0x0CF00400U | EFF, 8U, d); /* EEC1: the ECU does not read it */
        bxcan_bus_inject(id, 8U, d);
    }
    assert_int_equal(g_na->filtered_out, PFE_ECU_RX_FILTERS);
    for (uint32_t k = 0U; k < PFE_ECU_RX_FILTERS; k++) {
        hal_can_rx_t rx;
        assert_int_equal(hal_can_receive(&g_a, &rx), 0);
        assert_int_equal(rx.frame.data[0], k);
        assert_int_equal(rx.frame.id & 0x03FFFF00U, pfe_ecu_rx_filters[k].id & 0x03FFFF00U);
    }
    expect_rx_empty(&g_a);
}

/* A filter without the EFF flag in its mask takes both formats: no bank
 * can say that, so its bank passes everything and the interrupt decides. */
static void test_filter_for_both_frame_formats(void **state)
{
    (void)state;
    assert_int_equal(hal_can_add_filter(&g_a, 0x123U, 0x7FFU), 0);
    assert_int_equal(g_na->regs.fa1r, 1U);
    assert_int_equal(g_na->regs.filter[0].fr2, 0U);
    const uint8_t d[8] = {0x55U, 0, 0, 0, 0, 0, 0, 0};
    bxcan_bus_inject(0x124U, 8U, d);
    bxcan_bus_inject(EFF | 0x00000123U, 8U, d);
    bxcan_bus_inject(0x123U, 8U, d);
    bxcan_bus_inject(EFF | 0x18FEF123U, 8U, d); /* low 11 bits 0x123 too */
    const uint32_t want[3] = {EFF | 0x00000123U, 0x123U, EFF | 0x18FEF123U};
    for (uint32_t k = 0U; k < 3U; k++) {
        hal_can_rx_t rx;
        memset(&rx, 0xA5, sizeof rx);
        assert_int_equal(hal_can_receive(&g_a, &rx), 0);
        assert_int_equal(rx.frame.id, want[k]);
    }
    expect_rx_empty(&g_a);
    /* An exact filter beside it keeps its own bank. */
    assert_int_equal(hal_can_add_filter(&g_a, EFF | 0x18FEF100U, EFF | 0x03FFFF00U), 1);
    assert_int_equal(g_na->regs.fa1r, 3U);
    assert_int_equal(g_na->regs.filter[1].fr1, 0xC7F78804U);
}

/* ------------------------------------------------------------------ transmit */

static uint32_t std_tir(uint32_t id)
{
    return id << 21;
}

static void test_mailboxes_in_identifier_order_frames_in_send_order(void **state)
{
    (void)state;
    bxcan_node_t *nc = bxcan_node_add();
    static hal_can_t c;
    bxcan_node_attach(nc, &c);
    assert_int_equal(hal_stm32_can_init(&c, &nc->regs, 250000U), 0);
    /* Ascending identifiers: all three mailboxes at once. */
    send(&g_a, 0x100U, 0x10U);
    send(&g_a, 0x200U, 0x20U);
    send(&g_a, 0x300U, 0x30U);
    assert_int_equal(g_na->regs.tsr & 0x1C000000U, 0U); /* TME0..2 clear: all pending */
    send(&c, 0x180U, 0x18U);                             /* another node's frame */
    assert_int_equal(bxcan_bus_run(10U), 4U);
    assert_int_equal(bxcan_bus.log_n, 4U);
    assert_int_equal(bxcan_bus.log_tir[0], std_tir(0x100U));
    assert_int_equal(bxcan_bus.log_tir[1], std_tir(0x180U)); /* arbitration between nodes */
    assert_int_equal(bxcan_bus.log_tir[2], std_tir(0x200U));
    assert_int_equal(bxcan_bus.log_tir[3], std_tir(0x300U));
    /* Descending: a frame never overtakes the module's earlier ones. */
    bxcan_bus.log_n = 0U;
    send(&g_a, 0x300U, 0x31U);
    send(&g_a, 0x100U, 0x11U);
    send(&g_a, 0x200U, 0x21U);
    send(&g_a, 0x200U, 0x22U); /* same identifier twice: in order too */
    assert_int_equal(bxcan_bus_run(10U), 4U);
    assert_int_equal(bxcan_bus.log_tir[0], std_tir(0x300U));
    assert_int_equal(bxcan_bus.log_tir[1], std_tir(0x100U));
    assert_int_equal(bxcan_bus.log_tir[2], std_tir(0x200U));
    assert_int_equal(bxcan_bus.log_tir[3], std_tir(0x200U));
    expect_rx(&g_b, 0x100U, 0x10U);
    expect_rx(&g_b, 0x180U, 0x18U);
    expect_rx(&g_b, 0x200U, 0x20U);
    expect_rx(&g_b, 0x300U, 0x30U);
    expect_rx(&g_b, 0x300U, 0x31U);
    expect_rx(&g_b, 0x100U, 0x11U);
    expect_rx(&g_b, 0x200U, 0x21U);
    expect_rx(&g_b, 0x200U, 0x22U);
    expect_rx_empty(&g_b);
    hal_can_stats_t st;
    hal_can_get_stats(&g_a, &st);
    assert_int_equal(st.tx_frames, 7U);
    assert_int_equal(nc->misuse, 0U);
    bxcan_node_remove(nc);
}

static void test_transmit_queue_is_bounded(void **state)
{
    (void)state;
    /* Three mailboxes and the queue, then HAL_EAGAIN, counted. */
    for (uint32_t k = 0U; k < (HAL_STM32_CAN_TXQ_LEN + 3U); k++) {
        send(&g_a, EFF | (0x18FF0000U + k), (uint8_t)k);
    }
    pfe_can_frame_t f = {EFF | 0x18FFFFFFU, 0U, {0}};
    assert_int_equal(hal_can_send(&g_a, &f), HAL_EAGAIN);
    hal_can_stats_t st;
    hal_can_get_stats(&g_a, &st);
    assert_int_equal(st.tx_dropped, 1U);
    assert_int_equal(bxcan_bus_run(100U), HAL_STM32_CAN_TXQ_LEN + 3U);
    for (uint32_t k = 0U; k < (HAL_STM32_CAN_TXQ_LEN + 3U); k++) {
        expect_rx(&g_b, EFF | (0x18FF0000U + k), (uint8_t)k);
    }
    hal_can_get_stats(&g_a, &st);
    assert_int_equal(st.tx_frames, HAL_STM32_CAN_TXQ_LEN + 3U);
}

/* ------------------------------------------------------------------ receive losses */

static void test_fifo_overrun_is_counted(void **state)
{
    (void)state;
    const uint8_t d[8] = {0};
    g_na->irq_enabled = false; /* the interrupt held off (a flash erase, say) */
    for (uint32_t k = 0U; k < 5U; k++) {
        uint8_t b[8];
        memcpy(b, d, sizeof b);
        b[0] = (uint8_t)k;
        bxcan_bus_inject(0x100U + k, 8U, b);
    }
    assert_int_equal(g_na->fifo_lost, 2U);
    g_na->irq_enabled = true;
    bxcan_node_irq(g_na);
    /* Three frames survive: the first two and the last, which overwrote
     * the third slot twice. */
    const uint32_t ids[3] = {0x100U, 0x101U, 0x104U};
    for (uint32_t k = 0U; k < 3U; k++) {
        hal_can_rx_t rx;
        assert_int_equal(hal_can_receive(&g_a, &rx), 0);
        assert_int_equal(rx.frame.id, ids[k]);
    }
    expect_rx_empty(&g_a);
    hal_stm32_can_state_t s;
    memset(&s, 0xA5, sizeof s);
    hal_stm32_can_state(&g_a, &s);
    assert_int_equal(s.rx_overruns, 1U); /* one overrun; the hardware does not say how many */
    hal_can_stats_t st;
    hal_can_get_stats(&g_a, &st);
    assert_int_equal(st.rx_dropped, 1U);
    assert_int_equal(st.rx_frames, 3U);
    assert_int_equal(g_na->regs.rf0r, 0U); /* FOVR0 and FULL0 cleared, FIFO empty */
}

static void test_ring_overflow_is_counted(void **state)
{
    (void)state;
    for (uint32_t k = 0U; k < (HAL_STM32_CAN_RX_LEN + 2U); k++) {
        const uint8_t d[8] = {(uint8_t)k, (uint8_t)(k + 1U), (uint8_t)(k + 2U), (uint8_t)(k + 3U),
                              (uint8_t)(k + 4U), (uint8_t)(k + 5U), (uint8_t)(k + 6U),
                              (uint8_t)(k + 7U)};
        bxcan_bus_inject(EFF | (0x18FEF100U + (k & 0xFFU)), 8U, d);
    }
    for (uint32_t k = 0U; k < HAL_STM32_CAN_RX_LEN; k++) {
        expect_rx(&g_a, EFF | (0x18FEF100U + (k & 0xFFU)), (uint8_t)k);
    }
    expect_rx_empty(&g_a);
    hal_can_stats_t st;
    hal_can_get_stats(&g_a, &st);
    assert_int_equal(st.rx_dropped, 2U);
    assert_int_equal(g_na->fifo_lost, 0U);
}

/* ------------------------------------------------------------------ errors, bus-off */

static void test_error_states_bus_off_and_recovery(void **state)
{
    (void)state;
    hal_stm32_can_state_t s;
    bxcan_node_tx_errors(g_na, 12U); /* TEC 96 */
    memset(&s, 0xA5, sizeof s);
    hal_stm32_can_state(&g_a, &s);
    assert_int_equal(s.tx_error_counter, 96U);
    assert_true(s.error_warning);
    assert_false(s.error_passive);
    assert_false(s.bus_off);
    bxcan_node_tx_errors(g_na, 4U); /* TEC 128 */
    hal_stm32_can_state(&g_a, &s);
    assert_int_equal(s.tx_error_counter, 128U);
    assert_true(s.error_passive);
    bxcan_node_tx_errors(g_na, 17U); /* 264 > 255: bus-off */
    hal_stm32_can_state(&g_a, &s);
    assert_true(s.bus_off);
    assert_int_equal(s.bus_off_events, 1U);
    /* Frames sent meanwhile wait; the bus carries nothing of this node. */
    send(&g_a, 0x0CF00300U | EFF, 0x40U);
    assert_int_equal(bxcan_bus_run(10U), 0U);
    /* 127 sequences of 11 recessive bits: still off; the 128th: back. */
    bxcan_bus_idle_bits(127U * 11U);
    hal_stm32_can_state(&g_a, &s);
    assert_true(s.bus_off);
    bxcan_bus_idle_bits(11U);
    hal_stm32_can_state(&g_a, &s);
    assert_false(s.bus_off);
    assert_false(s.error_passive);
    assert_int_equal(s.tx_error_counter, 0U);
    assert_int_equal(bxcan_bus_run(10U), 1U);
    expect_rx(&g_b, 0x0CF00300U | EFF, 0x40U);
    /* A second bus-off counts a second event. */
    bxcan_node_tx_errors(g_na, 33U);
    hal_stm32_can_state(&g_a, &s);
    assert_int_equal(s.bus_off_events, 2U);
    /* Receive errors: REC in the state. */
    bxcan_node_rx_errors(g_nb, 100U);
    hal_stm32_can_state(&g_b, &s);
    assert_int_equal(s.rx_error_counter, 100U);
    assert_true(s.error_warning);
}

/* hal_ecu_loop_init() above reads the NVM: slots never written. */
int hal_nvm_read(hal_nvm_t *nvm, uint32_t slot, uint8_t buf[PFE_NVM_RECORD_SIZE])
{
    (void)nvm;
    (void)slot;
    memset(buf, 0xFF, PFE_NVM_RECORD_SIZE);
    return 0;
}

int hal_nvm_write(hal_nvm_t *nvm, uint32_t slot, const uint8_t buf[PFE_NVM_RECORD_SIZE])
{
    (void)nvm;
    (void)slot;
    (void)buf;
    return HAL_EIO;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bit_timing_register_values),
        cmocka_unit_test_setup_teardown(test_init_programs_the_controller, setup, teardown),
        cmocka_unit_test_setup_teardown(test_init_refuses_other_bitrates, setup, teardown),
        cmocka_unit_test_setup_teardown(test_init_times_out_when_the_controller_does_not_acknowledge,
                                        setup, teardown),
        cmocka_unit_test_setup_teardown(test_sleep_and_wake, setup, teardown),
        cmocka_unit_test_setup_teardown(test_ecu_filters_are_hardware_banks, setup, teardown),
        cmocka_unit_test_setup_teardown(test_filter_for_both_frame_formats, setup, teardown),
        cmocka_unit_test_setup_teardown(test_mailboxes_in_identifier_order_frames_in_send_order,
                                        setup, teardown),
        cmocka_unit_test_setup_teardown(test_transmit_queue_is_bounded, setup, teardown),
        cmocka_unit_test_setup_teardown(test_fifo_overrun_is_counted, setup, teardown),
        cmocka_unit_test_setup_teardown(test_ring_overflow_is_counted, setup, teardown),
        cmocka_unit_test_setup_teardown(test_error_states_bus_off_and_recovery, setup, teardown),
    };
    return cmocka_run_group_tests_name("hal_stm32_can on the bxCAN model", tests, NULL, NULL);
}
