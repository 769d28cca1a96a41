/*
 * flash_model.h - the STM32F4 flash interface (RM0090 chapter 3) and two
 * 16 KiB sectors (numbers 1 and 2) as they behave, for
 * hal/stm32f4/hal_stm32_nvm.c on the host:
 *   - locked after reset; KEYR's two keys in order unlock CR, a wrong key
 *     locks it until reset (counted in misuse);
 *   - a sector erase (CR.SER, SNB, STRT) sets every word to 0xFFFFFFFF;
 *   - with CR.PG a 32-bit store into a sector programs it: bits only go
 *     from 1 to 0 (the stored value is old & new); a store without PG sets
 *     PGSERR and changes nothing;
 *   - power can fail after any operation: with ops_left = k the k-th
 *     program or erase from now is torn and nothing after it happens. A
 *     torn program leaves a random subset of the bits that should have gone
 *     to 0 still at 1; a torn erase leaves each word either erased or as it
 *     was (seeded, so runs repeat). Then `powered` is false until the test
 *     "restarts" (flash_model_power_on()).
 */
#ifndef FLASH_MODEL_H
#define FLASH_MODEL_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/stm32f4/stm32f4_regs.h"

#define FLASH_MODEL_WORDS 4096U

typedef struct {
    stm32_flash_t regs;
    uint32_t mem[2][FLASH_MODEL_WORDS];  /* sectors 1 and 2 */
    uint32_t key_step;
    bool key_locked_out;
    bool powered;
    int64_t ops_left;                    /* < 0: no power cut planned */
    uint32_t ops;                        /* programs and erases done */
    uint32_t erases;
    uint32_t misuse;
    uint32_t rng;
    bool fail_next_erase;                /* the next erase leaves a word at 0 */
} flash_model_t;

extern flash_model_t flash_model;

/* Fresh chip: both sectors erased, controller locked, power on, no cut. */
void flash_model_reset(uint32_t seed);
/* Power back after a cut (memory as the cut left it; controller locked). */
void flash_model_power_on(void);

bool flash_model_owns(const volatile uint32_t *reg);
void flash_model_write(volatile uint32_t *reg, uint32_t value);

#endif /* FLASH_MODEL_H */
