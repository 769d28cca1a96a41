/*
 * hal_stm32_board.h - the STM32F405's clocks, watchdog, reset cause and
 * console: what the image's main() sets up before the ECU runs.
 *
 * Clock tree (RM0090 6.2): 8 MHz HSE crystal / PLLM 8 = 1 MHz into the PLL,
 * x PLLN 336 = 336 MHz VCO, / PLLP 2 = 168 MHz SYSCLK and HCLK, / PLLQ 7 =
 * 48 MHz for USB; APB1 = HCLK / 4 = 42 MHz (bxCAN; its timers run at twice
 * that, 84 MHz), APB2 = HCLK / 2 = 84 MHz. Flash at 5 wait states (168 MHz
 * at 2.7 to 3.6 V), prefetch and caches on.
 *
 * HSI fallback: when the HSE is not ready within HAL_STM32_HSE_TIMEOUT
 * polls (no crystal, a broken one), the PLL runs from the 16 MHz internal
 * oscillator with PLLM 16, giving the same 168/42/84 MHz. The HSI is only
 * 1 % accurate (datasheet, over temperature more), beyond the 0.36 % the
 * CAN bit timing tolerates (hal_stm32_can.c): the module still runs, and
 * a bus that suffers shows in the error counters it reports
 * (PFE_DeviceStatus). When the PLL does not lock either, the core stays on
 * the 16 MHz HSI it booted from; hal_stm32_clock_t says what happened.
 *
 * Independent watchdog: LSI (32 kHz nominal, 17 to 47 kHz) / 64, reload
 * 1200: it resets the MCU 1.6 s (fastest LSI) to 4.5 s (slowest) after the
 * last feed, longer than a flash sector erase (500 ms at most). The main
 * loop feeds it only after a tick that finished before its next deadline.
 */
#ifndef HAL_STM32_BOARD_H
#define HAL_STM32_BOARD_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/stm32f4/stm32f4_regs.h"

/* Status polls: 40 to 80 ms at the 16 MHz HSI (3 to 6 cycles a poll), far
 * above a crystal's few milliseconds of start-up. */
#define HAL_STM32_HSE_TIMEOUT 200000U
#define HAL_STM32_PLL_TIMEOUT 200000U
#define HAL_STM32_APB1_HZ 42000000U
#define HAL_STM32_APB1_TIMER_HZ 84000000U
#define HAL_STM32_IWDG_PRESCALER_64 4U
#define HAL_STM32_IWDG_RELOAD 1200U

typedef struct {
    bool hse;            /* the PLL runs from the crystal */
    bool pll;            /* SYSCLK is the PLL's 168 MHz */
} hal_stm32_clock_t;

void hal_stm32_clock_init(stm32_rcc_t *rcc, stm32_flash_t *flash, hal_stm32_clock_t *out);

/* Reset cause from RCC_CSR, flags then cleared (RMVF): the values of
 * firmware/pfe_ecu.h's pfe_reset_cause_t (0 power-on or brown-out,
 * 1 independent or window watchdog, 2 software reset, 3 other: the reset
 * pin alone, low-power). */
uint32_t hal_stm32_reset_cause(stm32_rcc_t *rcc);

void hal_stm32_watchdog_start(stm32_iwdg_t *iwdg);
void hal_stm32_watchdog_feed(stm32_iwdg_t *iwdg);

/* USART1 on PA9 (TX) at 115200 bit/s from APB2, for the console. */
void hal_stm32_console_init(stm32_rcc_t *rcc, stm32_gpio_t *gpioa, stm32_usart_t *usart,
                            uint32_t apb2_hz);
void hal_stm32_console_write(stm32_usart_t *usart, const char *s);

#endif /* HAL_STM32_BOARD_H */
