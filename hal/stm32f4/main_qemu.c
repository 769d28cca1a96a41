/*
 * main_qemu.c - the STM32F405 image's bring-up under QEMU's netduinoplus2
 * (build/stm32/pfe_stm32_qemu.elf), around the model's known-answer run
 * (hal/mps2/main_selfcheck.c, printed through semihosting exactly as the
 * host tool and the mps2 image print it, so that the three can be
 * compared byte for byte).
 *
 * QEMU 7.2 models the STM32F405's core, TIM2 and USART1 but neither the
 * RCC's oscillators, bxCAN nor the flash controller. So this image is the
 * product's startup, vector table, clock set-up (whose ready flags never
 * come: it takes the timeouts and the HSI fallback), reset cause, time base
 * and console, without CAN and NVM (this image only). Over
 * USART1 it prints
 *   "stm32: clock hse H pll P reset_cause C"   before the run,
 *   "stm32: ticks_10ms N ticks_us U"                then ten 10 ms waits,
 *   "stm32: selfcheck_us T timer_ok K stack_used S" after it,
 * timer_ok 1 when the time base moved forward during the run, N the waits
 * that returned at or after their deadline (10), U their total time
 * (100000 and a little more); and exits
 * through semihosting with the run's status (an unhandled exception: 128 +
 * its number).
 */
#include <stdint.h>

#include "hal/mps2/semihost.h"
#include "hal/stm32f4/hal_stm32_board.h"
#include "hal/stm32f4/hal_stm32_time.h"
#include "hal/stm32f4/startup.h"

#define RCC ((stm32_rcc_t *)STM32_RCC_BASE)
#define FLASH_R ((stm32_flash_t *)STM32_FLASH_R_BASE)
#define TIM2 ((stm32_tim_t *)STM32_TIM2_BASE)
#define GPIOA ((stm32_gpio_t *)STM32_GPIOA_BASE)
#define USART1 ((stm32_usart_t *)STM32_USART1_BASE)

static hal_time_t s_time;
static uint64_t s_start_us;

void TIM2_IRQHandler(void);
void TIM2_IRQHandler(void)
{
    hal_stm32_time_isr(&s_time);
}

static void put_u64(uint64_t v)
{
    char buf[21];
    uint32_t n = 20U;
    buf[20] = '\0';
    uint64_t x = v;
    do {
        n--;
        buf[n] = (char)('0' + (char)(x % 10U));
        x /= 10U;
    } while ((x != 0U) && (n > 0U));
    hal_stm32_console_write(USART1, &buf[n]);
}

void hal_stm32_pre_main(void)
{
    hal_stm32_clock_t clock;
    hal_stm32_clock_init(RCC, FLASH_R, &clock);
    const uint32_t cause = hal_stm32_reset_cause(RCC);
    HAL_STM32_WR(RCC->apb1enr, RCC->apb1enr | RCC_APB1ENR_TIM2);
    hal_stm32_time_init(&s_time, TIM2, HAL_STM32_APB1_TIMER_HZ, 0U);
    hal_stm32_time_use(&s_time);
    STM32_NVIC_ISER0 = 1U << STM32_IRQ_TIM2;
    hal_stm32_console_init(RCC, GPIOA, USART1, 84000000U);
    hal_stm32_console_write(USART1, "stm32: clock hse ");
    put_u64(clock.hse ? 1U : 0U);
    hal_stm32_console_write(USART1, " pll ");
    put_u64(clock.pll ? 1U : 0U);
    hal_stm32_console_write(USART1, " reset_cause ");
    put_u64(cause);
    hal_stm32_console_write(USART1, "\n");
    s_start_us = hal_stm32_now_us();
}

void hal_stm32_post_main(int rc)
{
    const uint64_t end = hal_stm32_now_us();
    /* Ten 10 ms ticks on absolute deadlines, as the product's loop waits. */
    uint64_t deadline = end;
    uint32_t reached = 0U;
    for (uint32_t k = 0U; k < 10U; k++) {
        deadline += 10000U;
        if ((hal_time_wait_until_us(&s_time, deadline) == 0) && (hal_stm32_now_us() >= deadline)) {
            reached++;
        }
    }
    hal_stm32_console_write(USART1, "stm32: ticks_10ms ");
    put_u64(reached);
    hal_stm32_console_write(USART1, " ticks_us ");
    put_u64(hal_stm32_now_us() - end);
    hal_stm32_console_write(USART1, "\n");
    hal_stm32_console_write(USART1, "stm32: selfcheck_us ");
    put_u64(end - s_start_us);
    hal_stm32_console_write(USART1, " timer_ok ");
    put_u64((end > s_start_us) ? 1U : 0U);
    hal_stm32_console_write(USART1, " stack_used ");
    put_u64(hal_stm32_stack_used_bytes());
    hal_stm32_console_write(USART1, "\n");
    hal_mps2_exit((int32_t)rc);
}

void hal_stm32_unhandled(uint32_t exception)
{
    hal_stm32_console_write(USART1, "stm32: unhandled exception ");
    put_u64(exception);
    hal_stm32_console_write(USART1, "\n");
    hal_mps2_exit(128 + (int32_t)exception);
}
