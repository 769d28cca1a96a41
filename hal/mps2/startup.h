/*
 * Reset and exception entry for the emulated MPS2 AN386 (Cortex-M4).
 *
 * Reset_Handler copies .data from flash, zeroes .bss, fills the unused part
 * of the stack with HAL_MPS2_STACK_FILL (for hal_mps2_stack_used_bytes()),
 * calls hal_mps2_pre_main(), runs constructors, calls main(), passes main's
 * return value through hal_mps2_post_main() and exits QEMU with the result
 * as exit code (hal_mps2_exit()). Needs linker/mps2_an386.ld or
 * linker/mps2_an386_test.ld, which provide the section symbols.
 *
 * Any exception without a handler of its own (a fault, an unexpected
 * interrupt) prints its number and the faulting PC and exits with status
 * HAL_MPS2_EXIT_EXCEPTION_BASE + exception number, so that a crashing test
 * fails at once instead of hanging until the run's timeout.
 */
#ifndef HAL_MPS2_STARTUP_H
#define HAL_MPS2_STARTUP_H

#include <stdint.h>

/* Exit status for an unhandled exception n: base + n (HardFault: 131). */
#define HAL_MPS2_EXIT_EXCEPTION_BASE 128

/* Word written over the free stack at reset. */
#define HAL_MPS2_STACK_FILL 0xA5A5A5A5U

/* Hooks around main(). The defaults do nothing and return rc unchanged;
 * hal/mps2/newlib_glue.c replaces them in test images to set up and flush
 * newlib's stdio. pre_main runs after .data and .bss are ready. */
void hal_mps2_pre_main(void);
int hal_mps2_post_main(int rc);

/* Deepest stack use since reset, in bytes: the size of the part of the stack
 * region no longer holding HAL_MPS2_STACK_FILL. A high-water mark, exact to
 * the word unless code stored the fill value itself at the deepest point.
 * Returns the whole stack size when the stack has overflowed (its lowest
 * word was overwritten). O(stack size). */
uint32_t hal_mps2_stack_used_bytes(void);

/* Size of the stack region in bytes (__stack_size in the linker script). */
uint32_t hal_mps2_stack_size_bytes(void);

/* Entry points named by the vector table; not for calling. */
void Reset_Handler(void);
void hal_mps2_default_handler(void);

#endif /* HAL_MPS2_STARTUP_H */
