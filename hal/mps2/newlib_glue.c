/*
 * Test images only (M4_LDFLAGS_TEST): before main(), bounds newlib's heap
 * to the .heap section and connects newlib's stdio, through librdimon, to
 * semihosting; after main() returns, flushes stdio before hal_mps2_exit().
 * Product images must not link this file.
 *
 * A test that calls exit() itself (CMocka does on some errors) leaves
 * through newlib's exit(), which flushes stdio and ends in librdimon's
 * _exit(): that also passes the status to QEMU with SYS_EXIT_EXTENDED.
 */
#include <stdint.h>
#include <stdio.h>

#include "hal/mps2/startup.h"

/* librdimon; no header declares these. _sbrk grows the heap from `end`
 * up to the stack pointer, and also up to __heap_limit once that is set from
 * its "unset" value. */
void initialise_monitor_handles(void);
extern uint32_t __heap_limit;

/* linker/mps2_an386_test.ld */
extern uint8_t __heap_end__[];

/* newlib's __libc_init_array and __libc_fini_array (reached through exit())
 * call these; crti.o, left out with the other start files, would define
 * them. Constructors and destructors are in .init_array/.fini_array, which
 * hal/mps2/startup.c and newlib walk themselves, so there is nothing to do. */
void _init(void);
void _fini(void);

void _init(void)
{
}

void _fini(void)
{
}

void hal_mps2_pre_main(void)
{
    /* Keep malloc inside the .heap section, so that it fails (returns NULL)
     * instead of growing into the stack. */
    __heap_limit = (uint32_t)(uintptr_t)__heap_end__;
    initialise_monitor_handles();
}

int hal_mps2_post_main(int rc)
{
    (void)fflush(NULL);
    return rc;
}
