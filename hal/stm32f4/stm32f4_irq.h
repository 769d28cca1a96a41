/*
 * stm32f4_irq.h - masking interrupts around the few sections the main
 * loop shares with an interrupt handler (PRIMASK on the Cortex-M4).
 *
 * hal_stm32_irq_save() masks every configurable interrupt and returns the
 * previous mask; hal_stm32_irq_restore() puts it back, so sections nest.
 * The host tests (HAL_STM32_REG_MODEL) supply both from the register
 * model, where "interrupts" are handler calls the model makes.
 */
#ifndef HAL_STM32F4_IRQ_H
#define HAL_STM32F4_IRQ_H

#include <stdint.h>

#ifdef HAL_STM32_REG_MODEL
uint32_t hal_stm32_irq_save(void);
void hal_stm32_irq_restore(uint32_t primask);
#else
static inline uint32_t hal_stm32_irq_save(void)
{
    uint32_t primask;
    __asm__ volatile("mrs %0, primask\n\tcpsid i" : "=r"(primask)::"memory");
    return primask;
}

static inline void hal_stm32_irq_restore(uint32_t primask)
{
    (void)primask; /* used by the asm, which the MISRA checker does not read */
    __asm__ volatile("msr primask, %0" ::"r"(primask) : "memory");
}
#endif

#endif /* HAL_STM32F4_IRQ_H */
