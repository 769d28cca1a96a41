/*
 * The STM32F405 board code on register structs: the time base's 64-bit
 * extension of TIM2 (hal/stm32f4/hal_stm32_time.c), reset causes from
 * RCC_CSR, the clock set-up with and without a crystal, the watchdog's
 * key sequence (hal/stm32f4/hal_stm32_board.c). Expected values are
 * literals from RM0090.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "hal/stm32f4/hal_stm32_board.h"
#include "hal/stm32f4/hal_stm32_time.h"
#include "tests/stm32/reg_model.h"

static stm32_tim_t g_tim;
static hal_time_t g_time;

static void test_time_base_setup(void **state)
{
    (void)state;
    memset(&g_tim, 0xA5, sizeof g_tim);
    reg_model_rc_w0 = NULL;
    hal_stm32_time_init(&g_time, &g_tim, 84000000U, 0U);
    assert_int_equal(g_tim.psc, 83U);          /* 84 MHz / 84 = 1 MHz */
    assert_int_equal(g_tim.arr, 0xFFFFFFFFU);
    assert_int_equal(g_tim.dier, 1U);          /* UIE */
    assert_int_equal(g_tim.cr1, 1U);           /* CEN */
    assert_int_equal(g_tim.cnt, 0U);
}

static void test_extension_to_64_bits(void **state)
{
    (void)state;
    memset(&g_tim, 0, sizeof g_tim);
    /* No wrap pending: high word and counter as they are. */
    g_tim.cnt = 0xFFFFFFF0U;
    assert_int_equal(hal_stm32_time_read(&g_tim, 2U), 0x00000002FFFFFFF0ULL);
    /* Wrapped, interrupt not yet run (UIF pending): the high word plus one,
     * and the counter read again after the flag. */
    g_tim.sr = TIM_SR_UIF;
    g_tim.cnt = 0x00000005U;
    assert_int_equal(hal_stm32_time_read(&g_tim, 2U), 0x0000000300000005ULL);
    /* The interrupt: one wrap counted, flag cleared (written 0: rc_w0). */
    reg_model_rc_w0 = &g_tim.sr;
    g_time.tim = &g_tim;
    g_time.wraps = 2U;
    hal_stm32_time_isr(&g_time);
    assert_int_equal(g_time.wraps, 3U);
    assert_int_equal(g_tim.sr, 0U);
    assert_int_equal(hal_stm32_time_read(&g_tim, g_time.wraps), 0x0000000300000005ULL);
    /* A compare flag alone counts no wrap. */
    g_tim.sr = TIM_SR_CC1IF;
    hal_stm32_time_isr(&g_time);
    assert_int_equal(g_time.wraps, 3U);
    assert_int_equal(g_tim.sr, 0U);
    reg_model_rc_w0 = NULL;
    /* hal_stm32_now_us() reads the clock in use; a late wait returns at once. */
    hal_stm32_time_use(&g_time);
    g_tim.cnt = 1000U;
    assert_int_equal(hal_stm32_now_us(), 0x00000003000003E8ULL);
    assert_int_equal(hal_time_wait_until_us(&g_time, 5U), 0);
    assert_int_equal(g_time.waits_late, 1U);
    assert_int_equal(reg_model_irq_depth, 0U); /* every mask undone */
}

static void test_reset_causes(void **state)
{
    (void)state;
    static const struct {
        uint32_t csr;
        uint32_t cause;
    } cases[] = {
        {0x0C000000U, 0U}, /* POR + PIN: power-on */
        {0x06000000U, 0U}, /* BOR + PIN: brown-out counts as power-on */
        {0x24000000U, 1U}, /* IWDG + PIN */
        {0x44000000U, 1U}, /* WWDG + PIN */
        {0x2C000000U, 1U}, /* IWDG after a power-on whose flags stayed */
        {0x14000000U, 2U}, /* SFT + PIN */
        {0x04000000U, 3U}, /* PIN alone: the reset button */
        {0x84000000U, 3U}, /* low-power */
    };
    for (uint32_t k = 0U; k < sizeof cases / sizeof cases[0]; k++) {
        stm32_rcc_t rcc;
        memset(&rcc, 0, sizeof rcc);
        rcc.csr = cases[k].csr | RCC_CSR_LSION;
        assert_int_equal(hal_stm32_reset_cause(&rcc), cases[k].cause);
        assert_int_equal(rcc.csr, cases[k].csr | RCC_CSR_LSION | RCC_CSR_RMVF); /* flags removed */
    }
}

static void test_clock_from_the_crystal(void **state)
{
    (void)state;
    stm32_rcc_t rcc;
    stm32_flash_t flash;
    memset(&rcc, 0, sizeof rcc);
    memset(&flash, 0, sizeof flash);
    /* Every ready flag already up, the switch already reported. */
    rcc.cr = RCC_CR_HSERDY | RCC_CR_PLLRDY | RCC_CR_HSIRDY | RCC_CR_HSION;
    rcc.cfgr = RCC_CFGR_SWS_PLL;
    reg_model_ro = &rcc.cfgr; /* SWS: the hardware's */
    reg_model_ro_mask = RCC_CFGR_SWS_MASK;
    hal_stm32_clock_t c;
    memset(&c, 0xA5, sizeof c);
    hal_stm32_clock_init(&rcc, &flash, &c);
    assert_true(c.hse);
    assert_true(c.pll);
    /* PLLM 8, PLLN 336, PLLP 2 (field 0), SRC HSE, PLLQ 7:
     * 8 | 336 << 6 | 1 << 22 | 7 << 24 = 0x07405408. */
    assert_int_equal(rcc.pllcfgr, 0x07405408U);
    /* PPRE1 /4 (5 << 10), PPRE2 /2 (4 << 13), SW PLL (2) = 0x9402. */
    assert_int_equal(rcc.cfgr & 0xFFFFU, 0x940AU); /* and SWS 2: switched */
    reg_model_ro = NULL;
    assert_int_equal(flash.acr, 0x00000705U); /* 5 wait states, prefetch, I and D cache */
    assert_int_equal(rcc.cr & RCC_CR_HSEON, RCC_CR_HSEON);
}

static void test_clock_falls_back_to_the_hsi(void **state)
{
    (void)state;
    stm32_rcc_t rcc;
    stm32_flash_t flash;
    memset(&rcc, 0, sizeof rcc);
    memset(&flash, 0, sizeof flash);
    rcc.cr = RCC_CR_PLLRDY | RCC_CR_HSIRDY | RCC_CR_HSION; /* the crystal never starts */
    rcc.cfgr = RCC_CFGR_SWS_PLL;
    reg_model_ro = &rcc.cfgr;
    reg_model_ro_mask = RCC_CFGR_SWS_MASK;
    hal_stm32_clock_t c;
    hal_stm32_clock_init(&rcc, &flash, &c);
    reg_model_ro = NULL;
    assert_false(c.hse);
    assert_true(c.pll);
    /* PLLM 16 from the 16 MHz HSI, same N, P, Q; SRC HSI: 0x07005410. */
    assert_int_equal(rcc.pllcfgr, 0x07005410U);
    assert_int_equal(rcc.cr & RCC_CR_HSEON, 0U); /* the crystal's oscillator off again */
    /* And when the PLL does not lock either: still on the boot HSI. */
    memset(&rcc, 0, sizeof rcc);
    memset(&flash, 0, sizeof flash);
    hal_stm32_clock_init(&rcc, &flash, &c);
    assert_false(c.hse);
    assert_false(c.pll);
    assert_int_equal(rcc.cfgr, 0U);  /* never switched */
    assert_int_equal(flash.acr, 0U); /* no wait states needed at 16 MHz */
}

static void test_watchdog_keys(void **state)
{
    (void)state;
    stm32_iwdg_t w;
    memset(&w, 0, sizeof w);
    hal_stm32_watchdog_start(&w);
    assert_int_equal(w.pr, 4U);      /* /64 */
    assert_int_equal(w.rlr, 1200U);  /* 1200 / (47 kHz / 64) = 1.63 s at the fastest LSI */
    assert_int_equal(w.kr, 0xAAAAU); /* last key written: a feed */
    w.kr = 0U;
    hal_stm32_watchdog_feed(&w);
    assert_int_equal(w.kr, 0xAAAAU);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_time_base_setup),
        cmocka_unit_test(test_extension_to_64_bits),
        cmocka_unit_test(test_reset_causes),
        cmocka_unit_test(test_clock_from_the_crystal),
        cmocka_unit_test(test_clock_falls_back_to_the_hsi),
        cmocka_unit_test(test_watchdog_keys),
    };
    return cmocka_run_group_tests_name("STM32F405 board: time base, resets, clocks, watchdog",
                                       tests, NULL, NULL);
}
