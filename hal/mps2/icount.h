/*
 * Instruction counter for the emulated MPS2 AN386 (Cortex-M4), built on the
 * SysTick timer.
 *
 * Under `qemu-system-arm -icount shift=0` (scripts/run_m4.sh) virtual time
 * advances 1 ns per executed instruction, and SysTick on the processor clock
 * (25 MHz on this board) decrements once every 40 instructions. The count is
 * therefore exact and deterministic to within one tick, independent of the
 * host's speed. It counts instructions, not cycles: a Cortex-M4 spends more
 * than one cycle on loads, taken branches and divisions, so real-time cost
 * on a given part is higher; use the counts to compare code, not to
 * predict microseconds.
 *
 * Without -icount the virtual clock follows host time and the numbers are
 * meaningless.
 *
 * Resolution: HAL_MPS2_ICOUNT_INSNS_PER_TICK instructions. A measurement
 * (two calls of hal_mps2_icount_now() around code) includes the overhead of
 * one call, about HAL_MPS2_ICOUNT_OVERHEAD_INSNS instructions; subtract a
 * measurement of empty code when that matters. The SysTick interrupt, which
 * runs once every 2^24 ticks (671 million instructions), adds a few
 * instructions to the code it interrupts.
 *
 * The counter takes over SysTick and its exception (SysTick_Handler). Not
 * reentrant with hal_mps2_icount_start(); hal_mps2_icount_now() may be
 * called from any context.
 */
#ifndef HAL_MPS2_ICOUNT_H
#define HAL_MPS2_ICOUNT_H

#include <stdint.h>

/* Instructions per SysTick decrement under -icount shift=0: 1 GHz virtual
 * instruction clock / 25 MHz processor clock. Measured, not only derived:
 * tests/m4/demo_image.c times loops of known length on every test-m4-selftest. */
#define HAL_MPS2_ICOUNT_INSNS_PER_TICK 40U

/* What two back-to-back calls of hal_mps2_icount_now() measure (-Os, GCC
 * 12): one call is about 30 instructions, rounded to a tick. */
#define HAL_MPS2_ICOUNT_OVERHEAD_INSNS 40U

/* (Re)start counting from zero: programs SysTick for the processor clock,
 * the largest reload value and its interrupt. O(1). */
void hal_mps2_icount_start(void);

/* Instructions executed since hal_mps2_icount_start(), a multiple of
 * HAL_MPS2_ICOUNT_INSNS_PER_TICK. Correct when interrupts have not been
 * masked (PRIMASK) for more than 2^24 ticks at a stretch; wraps after 2^56
 * ticks (2.9e18 instructions). Returns 0 before hal_mps2_icount_start().
 * O(1), about 30 instructions with the call. */
uint64_t hal_mps2_icount_now(void);

/* The SysTick exception handler, referenced by the vector table
 * (hal/mps2/startup.c); counts counter wraps. Not for calling. */
void SysTick_Handler(void);

#endif /* HAL_MPS2_ICOUNT_H */
