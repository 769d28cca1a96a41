/*
 * stm32f4_regs.h - the STM32F405/407 registers the backend uses, as
 * RM0090 (STM32F405/415/407/417 reference manual, rev. 19) lays them out:
 * bxCAN (ch. 32), flash interface (ch. 3), RCC (ch. 7), TIM2/5 (ch. 18),
 * IWDG (ch. 21), USART (ch. 30), and the Cortex-M4 NVIC.
 *
 * Every register write of the drivers goes through HAL_STM32_WR(): on the
 * MCU a plain volatile store; in the host tests (HAL_STM32_REG_MODEL
 * defined) a call into a register model (tests/stm32/), which applies the
 * register's write semantics (write-1-to-clear flags, requests the hardware
 * acknowledges) to the same struct the driver reads. Reads are plain
 * volatile loads on both.
 */
#ifndef HAL_STM32F4_REGS_H
#define HAL_STM32F4_REGS_H

#include <stdint.h>

#ifdef HAL_STM32_REG_MODEL
void hal_stm32_reg_write(volatile uint32_t *reg, uint32_t value);
#define HAL_STM32_WR(reg, value) hal_stm32_reg_write(&(reg), (value))
#else
#define HAL_STM32_WR(reg, value) ((reg) = (value))
#endif

/* ------------------------------------------------------------- bxCAN */

typedef struct {
    volatile uint32_t tir;   /* identifier, TXRQ */
    volatile uint32_t tdtr;  /* DLC */
    volatile uint32_t tdlr;  /* data bytes 0..3 */
    volatile uint32_t tdhr;  /* data bytes 4..7 */
} stm32_can_txmb_t;

typedef struct {
    volatile uint32_t rir;
    volatile uint32_t rdtr;  /* DLC, filter match index */
    volatile uint32_t rdlr;
    volatile uint32_t rdhr;
} stm32_can_rxmb_t;

typedef struct {
    volatile uint32_t fr1;
    volatile uint32_t fr2;
} stm32_can_filter_t;

typedef struct {
    volatile uint32_t mcr;        /* 0x000 */
    volatile uint32_t msr;        /* 0x004 */
    volatile uint32_t tsr;        /* 0x008 */
    volatile uint32_t rf0r;       /* 0x00C */
    volatile uint32_t rf1r;       /* 0x010 */
    volatile uint32_t ier;        /* 0x014 */
    volatile uint32_t esr;        /* 0x018 */
    volatile uint32_t btr;        /* 0x01C */
    uint32_t reserved0[88];       /* 0x020 .. 0x17F */
    stm32_can_txmb_t tx[3];       /* 0x180 */
    stm32_can_rxmb_t rx[2];       /* 0x1B0 */
    uint32_t reserved1[12];       /* 0x1D0 .. 0x1FF */
    volatile uint32_t fmr;        /* 0x200 */
    volatile uint32_t fm1r;       /* 0x204 */
    uint32_t reserved2;
    volatile uint32_t fs1r;       /* 0x20C */
    uint32_t reserved3;
    volatile uint32_t ffa1r;      /* 0x214 */
    uint32_t reserved4;
    volatile uint32_t fa1r;       /* 0x21C */
    uint32_t reserved5[8];        /* 0x220 .. 0x23F */
    stm32_can_filter_t filter[28]; /* 0x240 */
} stm32_can_t;

#define STM32_CAN1_BASE 0x40006400U

#define CAN_MCR_INRQ ((uint32_t)1U << 0)
#define CAN_MCR_SLEEP ((uint32_t)1U << 1)
#define CAN_MCR_TXFP ((uint32_t)1U << 2)
#define CAN_MCR_RFLM ((uint32_t)1U << 3)
#define CAN_MCR_NART ((uint32_t)1U << 4)
#define CAN_MCR_AWUM ((uint32_t)1U << 5)
#define CAN_MCR_ABOM ((uint32_t)1U << 6)
#define CAN_MCR_RESET ((uint32_t)1U << 15)

#define CAN_MSR_INAK ((uint32_t)1U << 0)
#define CAN_MSR_SLAK ((uint32_t)1U << 1)
#define CAN_MSR_ERRI ((uint32_t)1U << 2)

#define CAN_TSR_RQCP0 ((uint32_t)1U << 0)
#define CAN_TSR_TXOK0 ((uint32_t)1U << 1)
#define CAN_TSR_RQCP1 ((uint32_t)1U << 8)
#define CAN_TSR_RQCP2 ((uint32_t)1U << 16)
#define CAN_TSR_TME0 ((uint32_t)1U << 26)

#define CAN_RF0R_FMP0 ((uint32_t)3U << 0)
#define CAN_RF0R_FULL0 ((uint32_t)1U << 3)
#define CAN_RF0R_FOVR0 ((uint32_t)1U << 4)
#define CAN_RF0R_RFOM0 ((uint32_t)1U << 5)

#define CAN_IER_TMEIE ((uint32_t)1U << 0)
#define CAN_IER_FMPIE0 ((uint32_t)1U << 1)
#define CAN_IER_FOVIE0 ((uint32_t)1U << 3)
#define CAN_IER_EWGIE ((uint32_t)1U << 8)
#define CAN_IER_EPVIE ((uint32_t)1U << 9)
#define CAN_IER_BOFIE ((uint32_t)1U << 10)
#define CAN_IER_ERRIE ((uint32_t)1U << 15)

#define CAN_ESR_EWGF ((uint32_t)1U << 0)
#define CAN_ESR_EPVF ((uint32_t)1U << 1)
#define CAN_ESR_BOFF ((uint32_t)1U << 2)
#define CAN_ESR_TEC_SHIFT 16U
#define CAN_ESR_REC_SHIFT 24U

#define CAN_TIR_TXRQ ((uint32_t)1U << 0)
#define CAN_TIR_IDE ((uint32_t)1U << 2)
#define CAN_TIR_EXID_SHIFT 3U
#define CAN_TIR_STID_SHIFT 21U
#define CAN_RIR_RTR ((uint32_t)1U << 1)

#define CAN_FMR_FINIT ((uint32_t)1U << 0)
#define CAN_FMR_CAN2SB_SHIFT 8U
#define CAN_FMR_CAN2SB_MASK ((uint32_t)0x3FU << 8)

/* ------------------------------------------------------------- flash interface */

typedef struct {
    volatile uint32_t acr;
    volatile uint32_t keyr;
    volatile uint32_t optkeyr;
    volatile uint32_t sr;
    volatile uint32_t cr;
    volatile uint32_t optcr;
} stm32_flash_t;

#define STM32_FLASH_R_BASE 0x40023C00U

#define FLASH_ACR_LATENCY_5WS 5U
#define FLASH_ACR_PRFTEN ((uint32_t)1U << 8)
#define FLASH_ACR_ICEN ((uint32_t)1U << 9)
#define FLASH_ACR_DCEN ((uint32_t)1U << 10)
#define FLASH_KEY1 0x45670123U
#define FLASH_KEY2 0xCDEF89ABU
#define FLASH_SR_EOP ((uint32_t)1U << 0)
#define FLASH_SR_OPERR ((uint32_t)1U << 1)
#define FLASH_SR_WRPERR ((uint32_t)1U << 4)
#define FLASH_SR_PGAERR ((uint32_t)1U << 5)
#define FLASH_SR_PGPERR ((uint32_t)1U << 6)
#define FLASH_SR_PGSERR ((uint32_t)1U << 7)
#define FLASH_SR_BSY ((uint32_t)1U << 16)
#define FLASH_SR_ERRORS (FLASH_SR_OPERR | FLASH_SR_WRPERR | FLASH_SR_PGAERR | \
                         FLASH_SR_PGPERR | FLASH_SR_PGSERR)
#define FLASH_CR_PG ((uint32_t)1U << 0)
#define FLASH_CR_SER ((uint32_t)1U << 1)
#define FLASH_CR_SNB_SHIFT 3U
#define FLASH_CR_PSIZE_X32 ((uint32_t)2U << 8)
#define FLASH_CR_STRT ((uint32_t)1U << 16)
#define FLASH_CR_LOCK ((uint32_t)1U << 31)

/* ------------------------------------------------------------- RCC */

typedef struct {
    volatile uint32_t cr;          /* 0x00 */
    volatile uint32_t pllcfgr;     /* 0x04 */
    volatile uint32_t cfgr;        /* 0x08 */
    volatile uint32_t cir;         /* 0x0C */
    volatile uint32_t ahb1rstr;    /* 0x10 */
    volatile uint32_t ahb2rstr;
    volatile uint32_t ahb3rstr;
    uint32_t reserved0;
    volatile uint32_t apb1rstr;    /* 0x20 */
    volatile uint32_t apb2rstr;
    uint32_t reserved1[2];
    volatile uint32_t ahb1enr;     /* 0x30 */
    volatile uint32_t ahb2enr;
    volatile uint32_t ahb3enr;
    uint32_t reserved2;
    volatile uint32_t apb1enr;     /* 0x40 */
    volatile uint32_t apb2enr;
    uint32_t reserved3[2];
    volatile uint32_t ahb1lpenr;   /* 0x50 */
    volatile uint32_t ahb2lpenr;
    volatile uint32_t ahb3lpenr;
    uint32_t reserved4;
    volatile uint32_t apb1lpenr;   /* 0x60 */
    volatile uint32_t apb2lpenr;
    uint32_t reserved5[2];
    volatile uint32_t bdcr;        /* 0x70 */
    volatile uint32_t csr;         /* 0x74 */
} stm32_rcc_t;

#define STM32_RCC_BASE 0x40023800U

#define RCC_CR_HSION ((uint32_t)1U << 0)
#define RCC_CR_HSIRDY ((uint32_t)1U << 1)
#define RCC_CR_HSEON ((uint32_t)1U << 16)
#define RCC_CR_HSERDY ((uint32_t)1U << 17)
#define RCC_CR_PLLON ((uint32_t)1U << 24)
#define RCC_CR_PLLRDY ((uint32_t)1U << 25)
#define RCC_PLLCFGR_SRC_HSE ((uint32_t)1U << 22)
#define RCC_CFGR_SW_PLL 2U
#define RCC_CFGR_SWS_MASK ((uint32_t)3U << 2)
#define RCC_CFGR_SWS_PLL ((uint32_t)2U << 2)
#define RCC_CFGR_PPRE1_DIV4 ((uint32_t)5U << 10)
#define RCC_CFGR_PPRE2_DIV2 ((uint32_t)4U << 13)
#define RCC_AHB1ENR_GPIOA ((uint32_t)1U << 0)
#define RCC_AHB1ENR_GPIOB ((uint32_t)1U << 1)
#define RCC_APB1ENR_TIM2 ((uint32_t)1U << 0)
#define RCC_APB1ENR_CAN1 ((uint32_t)1U << 25)
#define RCC_APB1ENR_PWR ((uint32_t)1U << 28)
#define RCC_APB2ENR_USART1 ((uint32_t)1U << 4)
#define RCC_CSR_LSION ((uint32_t)1U << 0)
#define RCC_CSR_RMVF ((uint32_t)1U << 24)
#define RCC_CSR_BORRSTF ((uint32_t)1U << 25)
#define RCC_CSR_PINRSTF ((uint32_t)1U << 26)
#define RCC_CSR_PORRSTF ((uint32_t)1U << 27)
#define RCC_CSR_SFTRSTF ((uint32_t)1U << 28)
#define RCC_CSR_IWDGRSTF ((uint32_t)1U << 29)
#define RCC_CSR_WWDGRSTF ((uint32_t)1U << 30)
#define RCC_CSR_LPWRRSTF ((uint32_t)1U << 31)

/* ------------------------------------------------------------- general-purpose timer (TIM2) */

typedef struct {
    volatile uint32_t cr1;   /* 0x00 */
    volatile uint32_t cr2;
    volatile uint32_t smcr;
    volatile uint32_t dier;  /* 0x0C */
    volatile uint32_t sr;    /* 0x10 */
    volatile uint32_t egr;   /* 0x14 */
    volatile uint32_t ccmr1;
    volatile uint32_t ccmr2;
    volatile uint32_t ccer;  /* 0x20 */
    volatile uint32_t cnt;   /* 0x24 */
    volatile uint32_t psc;   /* 0x28 */
    volatile uint32_t arr;   /* 0x2C */
    uint32_t reserved0;
    volatile uint32_t ccr1;  /* 0x34 */
} stm32_tim_t;

#define STM32_TIM2_BASE 0x40000000U
#define TIM_CR1_CEN ((uint32_t)1U << 0)
#define TIM_DIER_UIE ((uint32_t)1U << 0)
#define TIM_DIER_CC1IE ((uint32_t)1U << 1)
#define TIM_SR_UIF ((uint32_t)1U << 0)
#define TIM_SR_CC1IF ((uint32_t)1U << 1)
#define TIM_EGR_UG ((uint32_t)1U << 0)

/* ------------------------------------------------------------- IWDG, GPIO, USART */

typedef struct {
    volatile uint32_t kr;
    volatile uint32_t pr;
    volatile uint32_t rlr;
    volatile uint32_t sr;
} stm32_iwdg_t;
#define STM32_IWDG_BASE 0x40003000U
#define IWDG_KEY_FEED 0xAAAAU
#define IWDG_KEY_UNLOCK 0x5555U
#define IWDG_KEY_START 0xCCCCU

typedef struct {
    volatile uint32_t moder;
    volatile uint32_t otyper;
    volatile uint32_t ospeedr;
    volatile uint32_t pupdr;
    volatile uint32_t idr;
    volatile uint32_t odr;
    volatile uint32_t bsrr;
    volatile uint32_t lckr;
    volatile uint32_t afr[2];
} stm32_gpio_t;
#define STM32_GPIOA_BASE 0x40020000U

typedef struct {
    volatile uint32_t sr;
    volatile uint32_t dr;
    volatile uint32_t brr;
    volatile uint32_t cr1;
} stm32_usart_t;
#define STM32_USART1_BASE 0x40011000U
#define USART_SR_TXE ((uint32_t)1U << 7)
#define USART_CR1_TE ((uint32_t)1U << 3)
#define USART_CR1_UE ((uint32_t)1U << 13)

/* ------------------------------------------------------------- Cortex-M4 core */

#define STM32_NVIC_ISER0 (*(volatile uint32_t *)0xE000E100U)
#define STM32_SCB_AIRCR (*(volatile uint32_t *)0xE000ED0CU)
#define STM32_AIRCR_SYSRESETREQ 0x05FA0004U

/* Debug freeze (RM0090 38.16.4): the watchdog and CAN1 stop while a
 * debugger holds the core. */
#define STM32_DBGMCU_APB1_FZ (*(volatile uint32_t *)0xE0042008U)
#define DBG_IWDG_STOP ((uint32_t)1U << 12)
#define DBG_CAN1_STOP ((uint32_t)1U << 25)

/* Interrupt numbers (RM0090 table 61). */
#define STM32_IRQ_TIM2 28U
#define STM32_IRQ_CAN1_TX 19U
#define STM32_IRQ_CAN1_RX0 20U
#define STM32_IRQ_CAN1_SCE 22U

#endif /* HAL_STM32F4_REGS_H */
