/*
 * main_bench_glue.c - the STM32F405 bench image's start and end around
 * hal/mps2/main_ecu.c (build/stm32/pfe_stm32_bench.elf, QEMU netduinoplus2):
 * the product's clock set-up and TIM2 enabled before main(), the exit
 * status through semihosting after it.
 */
#include <stdint.h>

#include "hal/mps2/semihost.h"
#include "hal/stm32f4/hal_stm32_board.h"
#include "hal/stm32f4/startup.h"

void hal_stm32_pre_main(void)
{
    hal_stm32_clock_t clock;
    hal_stm32_clock_init((stm32_rcc_t *)STM32_RCC_BASE, (stm32_flash_t *)STM32_FLASH_R_BASE,
                         &clock);
    stm32_rcc_t *rcc = (stm32_rcc_t *)STM32_RCC_BASE;
    HAL_STM32_WR(rcc->apb1enr, rcc->apb1enr | RCC_APB1ENR_TIM2);
}

void hal_stm32_post_main(int rc)
{
    hal_mps2_exit((int32_t)rc);
}

void hal_stm32_unhandled(uint32_t exception)
{
    hal_mps2_write_str("stm32: unhandled exception ");
    hal_mps2_write_u32(exception);
    hal_mps2_write_str("\n");
    hal_mps2_exit(128 + (int32_t)exception);
}
