/*
 * Vector table and reset code of the STM32F405 (RM0090 table 61: 82
 * interrupts). Reset_Handler copies .data, zeroes .bss, fills the free
 * stack with HAL_STM32_STACK_FILL, calls hal_stm32_pre_main(), main() and
 * hal_stm32_post_main() with main's result; the FPU is left off.
 * An interrupt or fault without a handler of its own ends in
 * hal_stm32_unhandled(): a loop the watchdog ends, unless the image
 * supplies its own (the QEMU image reports and exits).
 */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "hal/stm32f4/startup.h"

extern uint32_t __data_start__[];
extern uint32_t __data_end__[];
extern const uint32_t __data_load_start__[];
extern uint32_t __bss_start__[];
extern uint32_t __bss_end__[];
extern uint32_t __stack_start__[];
extern uint32_t __stack_end__[];

int main(void);

#define CORE_VECTORS 15U
#define EXTERNAL_IRQS 82U

typedef void (*vector_fn)(void);

typedef struct {
    uint32_t *initial_sp;
    vector_fn handler[CORE_VECTORS + EXTERNAL_IRQS];
} vector_table;

#define WEAK_HANDLER(name) void name(void) __attribute__((weak, alias("hal_stm32_default_handler")))
WEAK_HANDLER(NMI_Handler);
WEAK_HANDLER(HardFault_Handler);
WEAK_HANDLER(MemManage_Handler);
WEAK_HANDLER(BusFault_Handler);
WEAK_HANDLER(UsageFault_Handler);
WEAK_HANDLER(SVC_Handler);
WEAK_HANDLER(DebugMon_Handler);
WEAK_HANDLER(PendSV_Handler);
WEAK_HANDLER(SysTick_Handler);
WEAK_HANDLER(CAN1_TX_IRQHandler);
WEAK_HANDLER(CAN1_RX0_IRQHandler);
WEAK_HANDLER(CAN1_SCE_IRQHandler);
WEAK_HANDLER(TIM2_IRQHandler);

#define D hal_stm32_default_handler

__attribute__((section(".isr_vector"), used))
static const vector_table s_vectors = {
    .initial_sp = __stack_end__,
    .handler = {
        Reset_Handler, NMI_Handler, HardFault_Handler, MemManage_Handler, BusFault_Handler,
        UsageFault_Handler, NULL, NULL, NULL, NULL, SVC_Handler, DebugMon_Handler, NULL,
        PendSV_Handler, SysTick_Handler,
        /* 0..9 */ D, D, D, D, D, D, D, D, D, D,
        /* 10..18 */ D, D, D, D, D, D, D, D, D,
        /* 19 */ CAN1_TX_IRQHandler,
        /* 20 */ CAN1_RX0_IRQHandler,
        /* 21 */ D,
        /* 22 */ CAN1_SCE_IRQHandler,
        /* 23..27 */ D, D, D, D, D,
        /* 28 */ TIM2_IRQHandler,
        /* 29..39 */ D, D, D, D, D, D, D, D, D, D, D,
        /* 40..59 */ D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D,
        /* 60..81 */ D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D, D,
    },
};

__attribute__((weak)) void hal_stm32_unhandled(uint32_t exception)
{
    (void)exception;
    for (;;) {
        /* the watchdog resets the MCU */
    }
}

void hal_stm32_default_handler(void)
{
    uint32_t ipsr;
    __asm__ volatile("mrs %0, ipsr" : "=r"(ipsr));
    hal_stm32_unhandled(ipsr & 0x1FFU);
}

static uint32_t read_sp(void)
{
    uint32_t sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

void Reset_Handler(void)
{
    const size_t data_bytes = (size_t)((uintptr_t)__data_end__ - (uintptr_t)__data_start__);
    const size_t bss_bytes = (size_t)((uintptr_t)__bss_end__ - (uintptr_t)__bss_start__);
    (void)memcpy(__data_start__, __data_load_start__, data_bytes);
    (void)memset(__bss_start__, 0, bss_bytes);
    const uintptr_t fill_end = (uintptr_t)read_sp() - 64U;
    for (uintptr_t addr = (uintptr_t)__stack_start__; addr < fill_end; addr += sizeof(uint32_t)) {
        *(volatile uint32_t *)addr = HAL_STM32_STACK_FILL;
    }
    hal_stm32_pre_main();
    hal_stm32_post_main(main());
}

__attribute__((weak)) void hal_stm32_pre_main(void)
{
}

__attribute__((weak)) void hal_stm32_post_main(int rc)
{
    (void)rc;
    hal_stm32_unhandled(0U);
}

uint32_t hal_stm32_stack_used_bytes(void)
{
    const uintptr_t end = (uintptr_t)__stack_end__;
    uintptr_t addr = (uintptr_t)__stack_start__;
    while ((addr < end) && (*(const volatile uint32_t *)addr == HAL_STM32_STACK_FILL)) {
        addr += sizeof(uint32_t);
    }
    return (uint32_t)(end - addr);
}
