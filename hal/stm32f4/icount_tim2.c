/*
 * icount_tim2.c - hal/mps2/icount.h's instruction counter on the STM32F405
 * image under QEMU's netduinoplus2, so that the bench's ECU replay
 * (hal/mps2/main_ecu.c) runs unchanged on this board.
 *
 * QEMU 7.2 clocks the STM32F405's TIM2 at 1 GHz of virtual time; under
 * `-icount shift=0` that is one count per instruction, so TIM2 with
 * prescaler 0, extended to 64 bits by hal_stm32_time.c, counts
 * instructions exactly (on silicon it would count 84 MHz timer clocks).
 * SysTick is not used.
 */
#include "hal/mps2/icount.h"

#include "hal/stm32f4/hal_stm32_time.h"

#define TIM2 ((stm32_tim_t *)STM32_TIM2_BASE)

static hal_time_t s_count;

void TIM2_IRQHandler(void);
void TIM2_IRQHandler(void)
{
    hal_stm32_time_isr(&s_count);
}

void hal_mps2_icount_start(void)
{
    /* A "clock" of 1 MHz gives prescaler 0: one count per timer clock. */
    hal_stm32_time_init(&s_count, TIM2, 1000000U, 0U);
    hal_stm32_time_use(&s_count);
    STM32_NVIC_ISER0 = 1U << STM32_IRQ_TIM2;
}

uint64_t hal_mps2_icount_now(void)
{
    return hal_stm32_now_us();
}
