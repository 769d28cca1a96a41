/*
 * main_ecu.c - the module on an STM32F405 board: clocks, watchdog, time
 * base, CAN1 at 250 kbit/s (J1939-11) on PB8 (RX) / PB9 (TX), NVM in flash
 * sectors 1 and 2, and the ECU's 10 ms loop (hal/hal_ecu_loop.h) in the
 * main loop; interrupts only move frames and count time.
 *
 * Each pass: wait for the tick's deadline (TIM2 compare, WFI), run
 * hal_ecu_loop_step(), hand the controller's error state and the NVM's
 * health to the ECU (PFE_DeviceStatus), then feed the watchdog only if the
 * pass finished before the next deadline (hal_ecu_loop_pace(), as
 * sim_host/tools/pfe_ecu.c paces): a late pass (a flash erase, say) is
 * followed by the missed ticks back to back, at most 1 s of them; ticks
 * that stay late stop feeding the watchdog, which then resets the module
 * (hal_stm32_board.h: 1.6 to 4.5 s), and the next start reports it
 * (ResetCause 1).
 *
 * QEMU's netduinoplus2 models neither bxCAN nor the flash controller: its
 * image (build/stm32/pfe_stm32_qemu.elf) is built from main_qemu.c instead.
 */
#include <stdbool.h>
#include <stdint.h>

#include "firmware/pfe_ecu.h"
#include "hal/hal_ecu_loop.h"
#include "hal/stm32f4/hal_stm32_board.h"
#include "hal/stm32f4/hal_stm32_can.h"
#include "hal/stm32f4/hal_stm32_ecu.h"
#include "hal/stm32f4/hal_stm32_nvm.h"
#include "hal/stm32f4/hal_stm32_time.h"
#include "hal/stm32f4/startup.h"

#define CAN_BITRATE_BPS 250000U
#define SAVE_INTERVAL_MS 60000U

#define RCC ((stm32_rcc_t *)STM32_RCC_BASE)
#define FLASH_R ((stm32_flash_t *)STM32_FLASH_R_BASE)
#define IWDG ((stm32_iwdg_t *)STM32_IWDG_BASE)
#define TIM2 ((stm32_tim_t *)STM32_TIM2_BASE)
#define CAN1 ((stm32_can_t *)STM32_CAN1_BASE)
#define GPIOB ((stm32_gpio_t *)(STM32_GPIOA_BASE + 0x400U))

extern uint32_t __nvm_sector1[];
extern uint32_t __nvm_sector2[];

static hal_can_t s_can;
static hal_time_t s_time;

void CAN1_TX_IRQHandler(void);
void CAN1_RX0_IRQHandler(void);
void CAN1_SCE_IRQHandler(void);
void TIM2_IRQHandler(void);

void CAN1_TX_IRQHandler(void)
{
    hal_stm32_can_tx_isr(&s_can);
}

void CAN1_RX0_IRQHandler(void)
{
    hal_stm32_can_rx0_isr(&s_can);
}

void CAN1_SCE_IRQHandler(void)
{
    hal_stm32_can_sce_isr(&s_can);
}

void TIM2_IRQHandler(void)
{
    hal_stm32_time_isr(&s_time);
}

static void can_pins(void)
{
    HAL_STM32_WR(RCC->ahb1enr, RCC->ahb1enr | RCC_AHB1ENR_GPIOB);
    /* PB8, PB9: alternate function 9 (CAN1), pull-up on RX. */
    HAL_STM32_WR(GPIOB->moder, (GPIOB->moder & ~((uint32_t)0xFU << 16)) | ((uint32_t)0xAU << 16));
    HAL_STM32_WR(GPIOB->pupdr, (GPIOB->pupdr & ~((uint32_t)3U << 16)) | ((uint32_t)1U << 16));
    HAL_STM32_WR(GPIOB->afr[1], (GPIOB->afr[1] & ~0xFFU) | 0x99U);
}

int main(void)
{
    static hal_nvm_t s_nvm;
    static hal_ecu_loop_t s_loop;
    static pfe_ecu_t s_ecu;
    hal_stm32_clock_t clock;
    hal_stm32_clock_init(RCC, FLASH_R, &clock);
    const uint32_t cause = hal_stm32_reset_cause(RCC);
    /* A debugger that halts the core (openocd, docs/stm32_bench.md) halts
     * the watchdog and CAN1 too, instead of being reset under its feet. */
    HAL_STM32_WR(STM32_DBGMCU_APB1_FZ, STM32_DBGMCU_APB1_FZ | DBG_IWDG_STOP | DBG_CAN1_STOP);
    hal_stm32_watchdog_start(IWDG);

    HAL_STM32_WR(RCC->apb1enr, RCC->apb1enr | RCC_APB1ENR_TIM2 | RCC_APB1ENR_CAN1);
    hal_stm32_time_init(&s_time, TIM2, HAL_STM32_APB1_TIMER_HZ, 1U);
    hal_stm32_time_use(&s_time);
    can_pins();
    /* A controller that does not start leaves the module off the bus; the
     * ECU still runs and saves, and the watchdog still guards it. */
    (void)hal_stm32_can_init(&s_can, CAN1, CAN_BITRATE_BPS);
    STM32_NVIC_ISER0 = ((uint32_t)1U << STM32_IRQ_CAN1_TX) | ((uint32_t)1U << STM32_IRQ_CAN1_RX0) |
                       ((uint32_t)1U << STM32_IRQ_CAN1_SCE) | ((uint32_t)1U << STM32_IRQ_TIM2);
    hal_stm32_nvm_init(&s_nvm, FLASH_R, __nvm_sector1, 1U, __nvm_sector2, 2U);

    pfe_ecu_config_t cfg;
    hal_ecu_loop_config(&cfg, PFE_ECU_DEFAULT_ADDRESS, SAVE_INTERVAL_MS, 1U, 0U, 10000U);
    uint64_t deadline = hal_stm32_now_us();
    if (hal_ecu_loop_init(&s_loop, &s_ecu, &cfg, &s_can, &s_nvm, deadline) != PFE_OK) {
        hal_stm32_unhandled(0U);
    }
    pfe_ecu_note_reset_cause(&s_ecu, (pfe_reset_cause_t)cause);
    hal_stm32_ecu_marks_t marks;
    hal_stm32_ecu_marks_init(&marks, &s_nvm);
    for (;;) {
        (void)hal_time_wait_until_us(&s_time, deadline);
        (void)hal_ecu_loop_step(&s_loop, deadline);
        hal_stm32_ecu_report(&s_ecu, &s_can, &s_nvm, &marks);
        if (hal_ecu_loop_pace(&s_loop, &deadline, hal_stm32_now_us()) == HAL_ECU_PACE_ON_TIME) {
            hal_stm32_watchdog_feed(IWDG);
        }
    }
}
