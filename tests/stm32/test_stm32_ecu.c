/*
 * The STM32 module's main loop on the register models: the ECU
 * (hal_ecu_loop) over the bxCAN driver and the flash NVM, with the main
 * loop's reports (hal/stm32f4/hal_stm32_ecu.h). What the controller and the
 * flash go through (error counters, a bus-off and its recovery, a FIFO
 * overrun, a failing save, a watchdog reset) must come out on the bus in
 * PFE_DeviceStatus, read by another node; and the pacing feeds the
 * watchdog only after passes that ended in time.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "firmware/pfe_codec.h"
#include "hal/hal_ecu_loop.h"
#include "hal/stm32f4/hal_stm32_ecu.h"
#include "tests/stm32/bxcan_model.h"
#include "tests/stm32/flash_model.h"

static hal_can_t g_module;
static hal_can_t g_tester;
static bxcan_node_t *g_nm;
static hal_nvm_t g_nvm;
static pfe_ecu_t g_ecu;
static hal_ecu_loop_t g_loop;
static hal_stm32_ecu_marks_t g_marks;
static uint64_t g_t_us;

/* Ticks the module n times, the bus carrying its frames after each; the
 * last PFE_DeviceStatus the tester received, or -1 in *seen if none. */
static void run_ticks(uint32_t n, pfe_msg_device_status_t *last, int *seen)
{
    *seen = -1;
    for (uint32_t k = 0U; k < n; k++) {
        (void)hal_ecu_loop_step(&g_loop, g_t_us);
        hal_stm32_ecu_report(&g_ecu, &g_module, &g_nvm, &g_marks);
        g_t_us += PFE_ECU_TICK_US;
        (void)bxcan_bus_run(64U);
        hal_can_rx_t rx;
        while (hal_can_receive(&g_tester, &rx) == 0) {
            if ((pfe_j1939_pgn(rx.frame.id) == PFE_PGN_DEVICE_STATUS) &&
                (pfe_j1939_source(rx.frame.id) == PFE_ECU_DEFAULT_ADDRESS)) {
                memset(last, 0xA5, sizeof *last);
                assert_int_equal(pfe_codec_decode_device_status(&rx.frame, last), 0);
                *seen = (int)k;
            }
        }
    }
}

static void test_device_status_reports_the_controller_and_the_flash(void **state)
{
    (void)state;
    bxcan_bus_reset(false);
    flash_model_reset(5U);
    g_nm = bxcan_node_add();
    bxcan_node_t *nt = bxcan_node_add();
    bxcan_node_attach(g_nm, &g_module);
    bxcan_node_attach(nt, &g_tester);
    assert_int_equal(hal_stm32_can_init(&g_module, &g_nm->regs, 250000U), 0);
    assert_int_equal(hal_stm32_can_init(&g_tester, &nt->regs, 250000U), 0);
    hal_stm32_nvm_init(&g_nvm, &flash_model.regs, flash_model.mem[0], 1U, flash_model.mem[1], 2U);
    pfe_ecu_config_t cfg;
    hal_ecu_loop_config(&cfg, PFE_ECU_DEFAULT_ADDRESS, 1000U, 1U, 0U, 10000U);
    g_t_us = 0U;
    assert_int_equal(hal_ecu_loop_init(&g_loop, &g_ecu, &cfg, &g_module, &g_nvm, g_t_us), PFE_OK);
    pfe_ecu_note_reset_cause(&g_ecu, PFE_RESET_WATCHDOG);
    hal_stm32_ecu_marks_init(&g_marks, &g_nvm);

    /* Two seconds of a quiet bus: the first saves work, all counters 0. */
    pfe_msg_device_status_t st;
    int seen;
    run_ticks(200U, &st, &seen);
    ASSERT_GE(seen, 0);
    assert_int_equal(st.reset_cause.value, 1U);
    assert_int_equal(st.reset_cause.state, PFE_SIG_VALID);
    assert_int_equal(st.bus_off_events.value, 0U);
    assert_int_equal(st.bus_off_events.state, PFE_SIG_VALID);
    assert_int_equal(st.nvm_write_failing.value, 0U);
    assert_int_equal(st.nvm_write_failures.value, 0U);
    assert_in_range(g_nvm.saves, 1U, 3U);

    /* A bus-off and its recovery, a FIFO overrun, 130 receive errors, and
     * the flash gone (every program fails to verify). */
    bxcan_node_tx_errors(g_nm, 33U);
    run_ticks(1U, &st, &seen);
    bxcan_bus_idle_bits(128U * 11U);
    g_nm->irq_enabled = false;
    static const uint8_t d[8] = {0};
    for (uint32_t k = 0U; k < 5U; k++) {
        bxcan_bus_inject(PFE_CAN_EFF_FLAG | 0x18FEF117U, 8U, d); /* CCVS1 from 0x17 */
    }
    g_nm->irq_enabled = true;
    bxcan_node_irq(g_nm);
    bxcan_node_rx_errors(g_nm, 130U);
    flash_model.powered = false;
    run_ticks(150U, &st, &seen);
    ASSERT_GE(seen, 0);
    assert_int_equal(st.bus_off_events.value, 1U);
    assert_int_equal(st.bus_off.value, 0U);               /* recovered */
    assert_int_equal(st.rx_fifo_overruns.value, 1U);
    assert_int_equal(st.rx_error_counter.value, 130U);    /* nothing received since */
    assert_int_equal(st.error_passive.value, 1U);         /* REC > 127 */
    assert_int_equal(st.error_warning.value, 1U);
    assert_int_equal(st.nvm_write_failing.value, 1U);
    /* retried each tick (pfe_ecu_nvm_written()): at least the failures that set the bit */
    assert_in_range(st.nvm_write_failures.value, PFE_ECU_NVM_FAILING_AFTER, 150U);
    assert_int_equal(st.reset_cause.value, 1U);
    assert_int_equal(g_nm->misuse, 0U);
    assert_int_equal(nt->misuse, 0U);

    /* The flash back: the next save clears NvmWriteFailing. */
    flash_model_power_on();
    run_ticks(150U, &st, &seen);
    assert_int_equal(st.nvm_write_failing.value, 0U);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_device_status_reports_the_controller_and_the_flash),
    };
    return cmocka_run_group_tests_name("STM32 main loop on the register models", tests, NULL, NULL);
}
