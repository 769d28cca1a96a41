/*
 * hal_stm32_ecu.h - what the STM32F405 main loop (main_ecu.c) does after
 * each pass of hal_ecu_loop_step(), apart so that the host tests run it
 * over the register models:
 *   - hands the ECU the CAN controller's error state
 *     (pfe_ecu_note_bus_state()) and the NVM's health (nvm_failing: the
 *     last save failed; count.nvm_write_failures), sent in PFE_DeviceStatus;
 * The deadlines themselves are paced by hal_ecu_loop_pace() (a late loop
 * catches up tick by tick); main_ecu.c feeds the watchdog only after an
 * on-time pass.
 */
#ifndef HAL_STM32_ECU_H
#define HAL_STM32_ECU_H

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

#endif /* HAL_STM32_ECU_H */
