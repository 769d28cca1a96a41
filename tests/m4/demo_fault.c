/*
 * An image that crashes on purpose: an undefined instruction escalates to a
 * HardFault (exception 3, UsageFault is not enabled), which the HAL reports
 * and turns into exit status HAL_MPS2_EXIT_EXCEPTION_BASE + 3 = 131.
 */
#include "hal/mps2/semihost.h"

int main(void)
{
    hal_mps2_write_str("m4 fault demo: executing an undefined instruction\n");
    __asm__ volatile("udf #0");
    hal_mps2_write_str("m4 fault demo: still running, the fault was lost\n");
    return 0;
}
