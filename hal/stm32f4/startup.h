/*
 * Reset and exception entry of the STM32F405 image (hal/stm32f4/startup.c,
 * linker/stm32f405.ld).
 */
#ifndef HAL_STM32F4_STARTUP_H
#define HAL_STM32F4_STARTUP_H

#include <stdint.h>

#define HAL_STM32_STACK_FILL 0xA5A5A5A5U

/* Where an unhandled exception (or main returning, exception 0) ends. Weak:
 * the default loops until the watchdog resets the MCU. Never returns. */
void hal_stm32_unhandled(uint32_t exception);

/* Hooks around main(), weak: the defaults do nothing before it and end in
 * hal_stm32_unhandled(0) after it (the product's main never returns). */
void hal_stm32_pre_main(void);
void hal_stm32_post_main(int rc);

/* Deepest stack use since reset, bytes (high-water mark of the fill). */
uint32_t hal_stm32_stack_used_bytes(void);

void Reset_Handler(void);
void hal_stm32_default_handler(void);

#endif /* HAL_STM32F4_STARTUP_H */
