/*
 * reg_model.c - where the drivers' register writes and interrupt masking
 * go in the host tests (hal/stm32f4/stm32f4_regs.h, stm32f4_irq.h): to the
 * bxCAN model, the flash model, or, for any other register (timer, RCC,
 * watchdog structs a test owns), its own write semantics below.
 */
#include <stddef.h>
#include <stdint.h>

#include "hal/stm32f4/stm32f4_irq.h"
#include "hal/stm32f4/stm32f4_regs.h"
#include "tests/stm32/bxcan_model.h"
#include "tests/stm32/flash_model.h"
#include "tests/stm32/reg_model.h"

uint32_t reg_model_irq_depth;
uint32_t reg_model_writes;
volatile uint32_t *reg_model_rc_w0;  /* a register whose flags clear by writing 0 */
volatile uint32_t *reg_model_w1c;    /* a register whose flags clear by writing 1 */
volatile uint32_t *reg_model_ro;     /* a register with read-only bits */
uint32_t reg_model_ro_mask;

stm32_tim_t *reg_model_tim;

void hal_stm32_reg_write(volatile uint32_t *reg, uint32_t value)
{
    reg_model_writes++;
    if (reg_model_tim != NULL) {
        /* Time passes with bus activity: a microsecond per register write. */
        reg_model_tim->cnt = reg_model_tim->cnt + 1U;
    }
    bxcan_node_t *n = bxcan_model_node_of(reg);
    if (n != NULL) {
        bxcan_model_write(n, reg, value);
    } else if (flash_model_owns(reg)) {
        flash_model_write(reg, value);
    } else if (reg == reg_model_rc_w0) {
        *reg &= value;
    } else if (reg == reg_model_w1c) {
        *reg &= ~value;
    } else if (reg == reg_model_ro) {
        *reg = (*reg & reg_model_ro_mask) | (value & ~reg_model_ro_mask);
    } else {
        *reg = value;
    }
}

uint32_t hal_stm32_irq_save(void)
{
    reg_model_irq_depth++;
    return reg_model_irq_depth - 1U;
}

void hal_stm32_irq_restore(uint32_t primask)
{
    reg_model_irq_depth = primask;
}

#ifndef STM32_MODEL_OWN_CLOCK
/* The drivers' clock: the bus model's, a microsecond per reading, so that
 * every wait with a timeout ends. */
uint64_t hal_stm32_now_us(void)
{
    bxcan_bus.now_us++;
    return bxcan_bus.now_us;
}
#endif
