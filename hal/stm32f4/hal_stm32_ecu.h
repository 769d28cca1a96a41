/*
 * hal_stm32_ecu.h - what the STM32F405 main loop (main_ecu.c) does after
 * each pass of hal_ecu_loop_step(), apart so that the host tests run it
 * over the register models:
 *   - hands the ECU the CAN controller's error state
 *     (pfe_ecu_note_bus_state()) and the NVM's health (nvm_failing: the
 *     last save failed; count.nvm_write_failures), sent in PFE_DeviceStatus;
 *   - paces the deadlines: a pass that ended by its next deadline feeds the
 *     watchdog; one later than a whole tick counts the ticks lost
 *     (pfe_ecu_note_overrun()) and restarts the deadlines from now.
 */
#ifndef HAL_STM32_ECU_H
#define HAL_STM32_ECU_H

#include <stdbool.h>
#include <stdint.h>

#include "firmware/pfe_ecu.h"
#include "hal/stm32f4/hal_stm32_can.h"
#include "hal/stm32f4/hal_stm32_nvm.h"

typedef struct {
    uint32_t saves;       /* the NVM's counters at the previous report */
    uint32_t failures;
} hal_stm32_ecu_marks_t;

void hal_stm32_ecu_marks_init(hal_stm32_ecu_marks_t *marks, const hal_nvm_t *nvm);

void hal_stm32_ecu_report(pfe_ecu_t *ecu, hal_can_t *can, const hal_nvm_t *nvm,
                          hal_stm32_ecu_marks_t *marks);

/* *deadline_us is the deadline the pass just ran for; advances it to the
 * next one (and past lost ticks). Returns true when the watchdog may be
 * fed: now_us no later than the next deadline. */
bool hal_stm32_ecu_pace(pfe_ecu_t *ecu, uint64_t *deadline_us, uint64_t now_us);

#endif /* HAL_STM32_ECU_H */
