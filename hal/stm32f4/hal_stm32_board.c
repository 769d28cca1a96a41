/* hal_stm32_board.c - clocks, watchdog, reset cause, console (hal_stm32_board.h). */
#include "hal/stm32f4/hal_stm32_board.h"

/* Polls until (*reg & bit) != 0, at most n times. */
static bool wait_set(const volatile uint32_t *reg, uint32_t bit, uint32_t n)
{
    for (uint32_t k = 0U; k < n; k++) {
        if ((*reg & bit) != 0U) {
            return true;
        }
    }
    return false;
}

void hal_stm32_clock_init(stm32_rcc_t *rcc, stm32_flash_t *flash, hal_stm32_clock_t *out)
{
    out->hse = false;
    out->pll = false;
    HAL_STM32_WR(rcc->cr, rcc->cr | RCC_CR_HSEON);
    out->hse = wait_set(&rcc->cr, RCC_CR_HSERDY, HAL_STM32_HSE_TIMEOUT);
    /* PLLCFGR: PLLM 5:0, PLLN 14:6, PLLP 17:16 ((P / 2) - 1), SRC 22, PLLQ 27:24. */
    const uint32_t common = ((uint32_t)336U << 6) | ((uint32_t)0U << 16) | ((uint32_t)7U << 24);
    if (out->hse) {
        HAL_STM32_WR(rcc->pllcfgr, common | 8U | RCC_PLLCFGR_SRC_HSE);
    } else {
        HAL_STM32_WR(rcc->cr, rcc->cr & ~RCC_CR_HSEON);
        HAL_STM32_WR(rcc->pllcfgr, common | 16U);
    }
    HAL_STM32_WR(rcc->cr, rcc->cr | RCC_CR_PLLON);
    if (!wait_set(&rcc->cr, RCC_CR_PLLRDY, HAL_STM32_PLL_TIMEOUT)) {
        return;
    }
    /* Wait states before the faster clock, buses divided before the switch. */
    HAL_STM32_WR(flash->acr, FLASH_ACR_LATENCY_5WS | FLASH_ACR_PRFTEN | FLASH_ACR_ICEN |
                                 FLASH_ACR_DCEN);
    HAL_STM32_WR(rcc->cfgr, RCC_CFGR_PPRE1_DIV4 | RCC_CFGR_PPRE2_DIV2);
    HAL_STM32_WR(rcc->cfgr, RCC_CFGR_PPRE1_DIV4 | RCC_CFGR_PPRE2_DIV2 | RCC_CFGR_SW_PLL);
    for (uint32_t k = 0U; k < HAL_STM32_PLL_TIMEOUT; k++) {
        if ((rcc->cfgr & RCC_CFGR_SWS_MASK) == RCC_CFGR_SWS_PLL) {
            out->pll = true;
            break;
        }
    }
}

uint32_t hal_stm32_reset_cause(stm32_rcc_t *rcc)
{
    const uint32_t csr = rcc->csr;
    HAL_STM32_WR(rcc->csr, csr | RCC_CSR_RMVF);
    uint32_t cause = 3U;
    /* A power-on sets the pin flag too; a watchdog reset can follow a
     * power-on without clearing, so watchdog first. */
    if ((csr & (RCC_CSR_IWDGRSTF | RCC_CSR_WWDGRSTF)) != 0U) {
        cause = 1U;
    } else if ((csr & RCC_CSR_SFTRSTF) != 0U) {
        cause = 2U;
    } else if ((csr & (RCC_CSR_PORRSTF | RCC_CSR_BORRSTF)) != 0U) {
        cause = 0U;
    } else {
        /* pin or low-power reset */
    }
    return cause;
}

void hal_stm32_watchdog_start(stm32_iwdg_t *iwdg)
{
    HAL_STM32_WR(iwdg->kr, IWDG_KEY_START);   /* starts the LSI and the counter */
    HAL_STM32_WR(iwdg->kr, IWDG_KEY_UNLOCK);
    HAL_STM32_WR(iwdg->pr, HAL_STM32_IWDG_PRESCALER_64);
    HAL_STM32_WR(iwdg->rlr, HAL_STM32_IWDG_RELOAD);
    HAL_STM32_WR(iwdg->kr, IWDG_KEY_FEED);
}

void hal_stm32_watchdog_feed(stm32_iwdg_t *iwdg)
{
    HAL_STM32_WR(iwdg->kr, IWDG_KEY_FEED);
}

void hal_stm32_console_init(stm32_rcc_t *rcc, stm32_gpio_t *gpioa, stm32_usart_t *usart,
                            uint32_t apb2_hz)
{
    HAL_STM32_WR(rcc->ahb1enr, rcc->ahb1enr | RCC_AHB1ENR_GPIOA);
    HAL_STM32_WR(rcc->apb2enr, rcc->apb2enr | RCC_APB2ENR_USART1);
    /* PA9 alternate function 7 (USART1_TX). */
    HAL_STM32_WR(gpioa->moder, (gpioa->moder & ~((uint32_t)3U << 18)) | ((uint32_t)2U << 18));
    HAL_STM32_WR(gpioa->afr[1], (gpioa->afr[1] & ~((uint32_t)0xFU << 4)) | ((uint32_t)7U << 4));
    HAL_STM32_WR(usart->brr, (apb2_hz + (115200U / 2U)) / 115200U);
    HAL_STM32_WR(usart->cr1, USART_CR1_UE | USART_CR1_TE);
}

void hal_stm32_console_write(stm32_usart_t *usart, const char *s)
{
    for (const char *p = s; *p != '\0'; p++) {
        uint32_t n = 0U;
        while (((usart->sr & USART_SR_TXE) == 0U) && (n < 100000U)) {
            n++;
        }
        HAL_STM32_WR(usart->dr, (uint32_t)(uint8_t)*p);
    }
}
