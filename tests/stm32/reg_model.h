/* reg_model.h - the host tests' register write hook (reg_model.c). */
#ifndef REG_MODEL_H
#define REG_MODEL_H

#include <stdint.h>

#include "hal/stm32f4/stm32f4_regs.h"

extern uint32_t reg_model_irq_depth;   /* nesting of hal_stm32_irq_save() */
extern uint32_t reg_model_writes;
extern volatile uint32_t *reg_model_rc_w0;
extern volatile uint32_t *reg_model_w1c;
extern volatile uint32_t *reg_model_ro;    /* its reg_model_ro_mask bits ignore writes */
extern uint32_t reg_model_ro_mask;
/* With STM32_MODEL_OWN_CLOCK (the real hal_stm32_time.c linked): a timer
 * whose counter moves one per register write, when set. */
extern stm32_tim_t *reg_model_tim;

#endif /* REG_MODEL_H */
