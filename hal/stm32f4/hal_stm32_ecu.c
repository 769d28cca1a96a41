/* hal_stm32_ecu.c - the STM32 main loop's reports and pacing (hal_stm32_ecu.h). */
#include "hal/stm32f4/hal_stm32_ecu.h"

void hal_stm32_ecu_marks_init(hal_stm32_ecu_marks_t *marks, const hal_nvm_t *nvm)
{
    marks->saves = nvm->saves;
    marks->failures = nvm->failures;
}

void hal_stm32_ecu_report(pfe_ecu_t *ecu, hal_can_t *can, const hal_nvm_t *nvm,
                          hal_stm32_ecu_marks_t *marks)
{
    hal_stm32_can_state_t st;
    hal_stm32_can_state(can, &st);
    const pfe_ecu_bus_state_t bus = {st.rx_overruns, st.bus_off_events, st.tx_error_counter,
                                     st.rx_error_counter, st.error_warning, st.error_passive,
                                     st.bus_off};
    pfe_ecu_note_bus_state(ecu, &bus);
    if (nvm->failures != marks->failures) {
        ecu->nvm_failing = true;
    } else if (nvm->saves != marks->saves) {
        ecu->nvm_failing = false;
    } else {
        /* no save since the last report */
    }
    marks->saves = nvm->saves;
    marks->failures = nvm->failures;
    ecu->count.nvm_write_failures = nvm->failures;
}
