/*
 * Vector table and reset code for the emulated MPS2 AN386 (Cortex-M4).
 * QEMU loads the ELF, then the core takes its initial SP and reset vector from
 * the first two words of flash, as on the real board.
 */
#include "hal/mps2/startup.h"

#include <stddef.h>
#include <string.h>

#include "hal/mps2/icount.h"
#include "hal/mps2/semihost.h"

/* Section bounds from linker/mps2_an386_sections.ld; only their addresses
 * mean anything. */
extern uint32_t __data_start__[];
extern uint32_t __data_end__[];
extern const uint32_t __data_load_start__[];
extern uint32_t __bss_start__[];
extern uint32_t __bss_end__[];
extern uint32_t __stack_start__[];
extern uint32_t __stack_end__[];
extern void (*const __preinit_array_start[])(void);
extern void (*const __preinit_array_end[])(void);
extern void (*const __init_array_start[])(void);
extern void (*const __init_array_end[])(void);

int main(void);

/* Exceptions 1..15 of the ARMv7-M core, then the board's interrupts. QEMU's
 * mps2-an386 wires 32 external interrupts to the NVIC. */
#define CORE_VECTORS 15U
#define EXTERNAL_IRQS 32U

typedef void (*vector_fn)(void);

typedef struct {
    uint32_t *initial_sp;
    vector_fn handler[CORE_VECTORS + EXTERNAL_IRQS];
} vector_table;

/* Handlers a program may define; all default to hal_mps2_default_handler. */
#define WEAK_HANDLER(name) \
    void name(void) __attribute__((weak, alias("hal_mps2_default_handler")))
WEAK_HANDLER(NMI_Handler);
WEAK_HANDLER(HardFault_Handler);
WEAK_HANDLER(MemManage_Handler);
WEAK_HANDLER(BusFault_Handler);
WEAK_HANDLER(UsageFault_Handler);
WEAK_HANDLER(SVC_Handler);
WEAK_HANDLER(DebugMon_Handler);
WEAK_HANDLER(PendSV_Handler);
/* icount.c supplies the real one; this keeps images without it linking. */
void SysTick_Handler(void) __attribute__((weak, alias("hal_mps2_default_handler")));

#define IRQ_DEFAULTS_8                                                   \
    hal_mps2_default_handler, hal_mps2_default_handler,                  \
        hal_mps2_default_handler, hal_mps2_default_handler,              \
        hal_mps2_default_handler, hal_mps2_default_handler,              \
        hal_mps2_default_handler, hal_mps2_default_handler
_Static_assert(EXTERNAL_IRQS == (4U * 8U), "one IRQ_DEFAULTS_8 per 8 interrupts");

__attribute__((section(".isr_vector"), used))
static const vector_table s_vectors = {
    .initial_sp = __stack_end__,
    .handler = {
        [0] = Reset_Handler,        /* 1 */
        [1] = NMI_Handler,          /* 2 */
        [2] = HardFault_Handler,    /* 3 */
        [3] = MemManage_Handler,    /* 4 */
        [4] = BusFault_Handler,     /* 5 */
        [5] = UsageFault_Handler,   /* 6 */
        [10] = SVC_Handler,         /* 11 */
        [11] = DebugMon_Handler,    /* 12 */
        [13] = PendSV_Handler,      /* 14 */
        [14] = SysTick_Handler,     /* 15 */
        /* 16..47: external interrupts 0..31 */
        IRQ_DEFAULTS_8, IRQ_DEFAULTS_8, IRQ_DEFAULTS_8, IRQ_DEFAULTS_8,
    },
};

__attribute__((weak)) void hal_mps2_pre_main(void)
{
}

__attribute__((weak)) int hal_mps2_post_main(int rc)
{
    return rc;
}

static uint32_t read_sp(void)
{
    uint32_t sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

static void run_array(void (*const *first)(void), void (*const *last)(void))
{
    for (void (*const *f)(void) = first; f < last; ++f) {
        (*f)();
    }
}

void Reset_Handler(void)
{
    /* memcpy/memset from the C library use neither .data nor .bss. */
    size_t data_bytes = (size_t)((uintptr_t)__data_end__ - (uintptr_t)__data_start__);
    size_t bss_bytes = (size_t)((uintptr_t)__bss_end__ - (uintptr_t)__bss_start__);
    (void)memcpy(__data_start__, __data_load_start__, data_bytes);
    (void)memset(__bss_start__, 0, bss_bytes);

    /* Fill the free stack, leaving 64 bytes below the current SP for this
     * function's callees. Volatile, so the compiler keeps the loop rather
     * than calling memset, whose own frame would sit in the filled area. */
    uintptr_t fill_end = (uintptr_t)read_sp() - 64U;
    for (uintptr_t addr = (uintptr_t)__stack_start__; addr < fill_end; addr += sizeof(uint32_t)) {
        *(volatile uint32_t *)addr = HAL_MPS2_STACK_FILL;
    }

    hal_mps2_pre_main();
    run_array(__preinit_array_start, __preinit_array_end);
    run_array(__init_array_start, __init_array_end);
    int rc = hal_mps2_post_main(main());
    hal_mps2_exit((int32_t)rc);
}

uint32_t hal_mps2_stack_size_bytes(void)
{
    return (uint32_t)((uintptr_t)__stack_end__ - (uintptr_t)__stack_start__);
}

uint32_t hal_mps2_stack_used_bytes(void)
{
    /* Addresses compared as integers: the linker symbols are distinct
     * objects to the compiler. */
    uintptr_t end = (uintptr_t)__stack_end__;
    uintptr_t addr = (uintptr_t)__stack_start__;
    while ((addr < end) && (*(const volatile uint32_t *)addr == HAL_MPS2_STACK_FILL)) {
        addr += sizeof(uint32_t);
    }
    return (uint32_t)(end - addr);
}

/* Called with the exception frame the core pushed on the main stack: r0-r3,
 * r12, lr, pc, xpsr. Only MSP is in use, so the frame is there. */
__attribute__((used, noreturn)) static void report_exception(const uint32_t *frame)
{
    uint32_t ipsr;
    __asm__ volatile("mrs %0, ipsr" : "=r"(ipsr));
    uint32_t exception = ipsr & 0x1FFU;
    hal_mps2_write_str("\nhal_mps2: unhandled exception ");
    hal_mps2_write_u32(exception);
    hal_mps2_write_str(", pc ");
    hal_mps2_write_hex32(frame[6]);
    hal_mps2_write_str(", lr ");
    hal_mps2_write_hex32(frame[5]);
    hal_mps2_write_str("\n");
    hal_mps2_exit(HAL_MPS2_EXIT_EXCEPTION_BASE + (int32_t)exception);
}

/* Naked, so that MSP still points at the exception frame. */
__attribute__((naked)) void hal_mps2_default_handler(void)
{
    __asm__ volatile("mrs r0, msp\n\t"
                     "b report_exception\n\t");
}
