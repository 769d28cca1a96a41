/* flash_model.c - STM32F4 flash interface and two sectors (flash_model.h). */
#include "tests/stm32/flash_model.h"

#include <stddef.h>
#include <string.h>

flash_model_t flash_model;

static uint32_t next_random(void)
{
    /* xorshift32: the torn bits and words, repeatable from the seed. */
    uint32_t x = flash_model.rng;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    flash_model.rng = x;
    return x;
}

void flash_model_reset(uint32_t seed)
{
    (void)memset(&flash_model, 0, sizeof flash_model);
    (void)memset(flash_model.mem, 0xFF, sizeof flash_model.mem);
    flash_model.rng = (seed == 0U) ? 0x9E3779B9U : seed;
    flash_model_power_on();
}

void flash_model_power_on(void)
{
    flash_model.regs.cr = FLASH_CR_LOCK;
    flash_model.regs.sr = 0U;
    flash_model.key_step = 0U;
    flash_model.key_locked_out = false;
    flash_model.powered = true;
    flash_model.ops_left = -1;
}

bool flash_model_owns(const volatile uint32_t *reg)
{
    const char *p = (const char *)(uintptr_t)reg;
    const char *r = (const char *)&flash_model.regs;
    const char *m = (const char *)flash_model.mem;
    return ((p >= r) && (p < (r + sizeof flash_model.regs))) ||
           ((p >= m) && (p < (m + sizeof flash_model.mem)));
}

/* One program or erase: false when the power fails during it. */
static bool op_survives(void)
{
    flash_model.ops++;
    if (flash_model.ops_left < 0) {
        return true;
    }
    flash_model.ops_left--;
    if (flash_model.ops_left == 0) {
        flash_model.powered = false;
        return false;
    }
    return true;
}

static void erase(uint32_t snb)
{
    if ((snb != 1U) && (snb != 2U)) {
        flash_model.regs.sr |= FLASH_SR_WRPERR; /* not a sector the model has */
        flash_model.misuse++;
        return;
    }
    uint32_t *s = flash_model.mem[snb - 1U];
    flash_model.erases++;
    if (!op_survives()) {
        for (uint32_t k = 0U; k < FLASH_MODEL_WORDS; k++) {
            if ((next_random() & 1U) != 0U) {
                s[k] = 0xFFFFFFFFU;
            }
        }
        return;
    }
    (void)memset(s, 0xFF, FLASH_MODEL_WORDS * sizeof(uint32_t));
    if (flash_model.fail_next_erase) {
        flash_model.fail_next_erase = false;
        s[FLASH_MODEL_WORDS / 2U] = 0U;
    }
    flash_model.regs.sr |= FLASH_SR_EOP;
}

void flash_model_write(volatile uint32_t *reg, uint32_t value)
{
    if (!flash_model.powered) {
        return;
    }
    stm32_flash_t *f = &flash_model.regs;
    if (reg == &f->keyr) {
        const uint32_t want = (flash_model.key_step == 0U) ? FLASH_KEY1 : FLASH_KEY2;
        if (flash_model.key_locked_out || (value != want)) {
            flash_model.key_locked_out = true;
            flash_model.misuse++;
        } else if (flash_model.key_step == 1U) {
            f->cr &= ~FLASH_CR_LOCK;
            flash_model.key_step = 0U;
        } else {
            flash_model.key_step = 1U;
        }
    } else if (reg == &f->sr) {
        f->sr &= ~(value & (FLASH_SR_ERRORS | FLASH_SR_EOP));
    } else if (reg == &f->cr) {
        if ((f->cr & FLASH_CR_LOCK) != 0U) {
            flash_model.misuse++;
            return;
        }
        f->cr = value & ~FLASH_CR_STRT;
        if (((value & FLASH_CR_STRT) != 0U) && ((value & FLASH_CR_SER) != 0U)) {
            erase((value >> FLASH_CR_SNB_SHIFT) & 0xFU);
        }
    } else if ((reg == &f->acr) || (reg == &f->optkeyr) || (reg == &f->optcr)) {
        *reg = value;
    } else {
        /* A store into a sector. */
        if (((f->cr & FLASH_CR_PG) == 0U) || ((f->cr & FLASH_CR_LOCK) != 0U)) {
            f->sr |= FLASH_SR_PGSERR;
            flash_model.misuse++;
            return;
        }
        if ((f->cr & (3U << 8)) != FLASH_CR_PSIZE_X32) {
            f->sr |= FLASH_SR_PGPERR;
            flash_model.misuse++;
            return;
        }
        if (!op_survives()) {
            *reg &= value | next_random(); /* some bits never got there */
            return;
        }
        *reg &= value;
        f->sr |= FLASH_SR_EOP;
    }
}
