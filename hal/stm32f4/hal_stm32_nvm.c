/* hal_stm32_nvm.c - hal/hal_nvm.h in flash (contract in hal_stm32_nvm.h). */
#include "hal/stm32f4/hal_stm32_nvm.h"

#include <stdbool.h>
#include <stddef.h>
#include <string.h>

#include "hal/hal_can.h"
#include "hal/stm32f4/hal_stm32_time.h"

#define ERASED 0xFFFFFFFFU
#define DATA_WORDS 10U

static bool blank(const uint32_t *w, uint32_t n)
{
    for (uint32_t k = 0U; k < n; k++) {
        if (w[k] != ERASED) {
            return false;
        }
    }
    return true;
}

static bool formatted(const uint32_t *s)
{
    return s[0] == HAL_STM32_NVM_SECTOR_MAGIC;
}

/* First record index whose 9 words are all erased, from the start. */
static uint32_t first_free(const uint32_t *s)
{
    uint32_t w = HAL_STM32_NVM_FIRST_RECORD;
    while (((w + HAL_STM32_NVM_RECORD_WORDS) <= HAL_STM32_NVM_SECTOR_WORDS) &&
           !blank(&s[w], HAL_STM32_NVM_RECORD_WORDS)) {
        w += HAL_STM32_NVM_RECORD_WORDS;
    }
    return w;
}

void hal_stm32_nvm_init(hal_nvm_t *nvm, stm32_flash_t *regs, uint32_t *sector0, uint32_t snb0,
                        uint32_t *sector1, uint32_t snb1)
{
    (void)memset(nvm, 0, sizeof *nvm);
    nvm->regs = regs;
    nvm->sector[0] = sector0;
    nvm->sector[1] = sector1;
    nvm->snb[0] = snb0;
    nvm->snb[1] = snb1;
    nvm->active = -1;
    for (uint32_t k = 0U; k < 2U; k++) {
        const uint32_t *s = nvm->sector[k];
        if (formatted(s) && ((nvm->active < 0) || (s[1] > nvm->generation))) {
            nvm->active = (int)k;
            nvm->generation = s[1];
        }
    }
    if (nvm->active >= 0) {
        nvm->next = first_free(nvm->sector[nvm->active]);
    }
}

/* The last committed record of slot in sector s, or NULL. */
static const uint32_t *find(const uint32_t *s, uint32_t slot)
{
    const uint32_t *found = NULL;
    if (!formatted(s)) {
        return NULL;
    }
    for (uint32_t w = HAL_STM32_NVM_FIRST_RECORD;
         (w + HAL_STM32_NVM_RECORD_WORDS) <= HAL_STM32_NVM_SECTOR_WORDS;
         w += HAL_STM32_NVM_RECORD_WORDS) {
        const uint32_t *r = &s[w];
        if (blank(r, HAL_STM32_NVM_RECORD_WORDS)) {
            break;
        }
        if ((r[0] == (HAL_STM32_NVM_RECORD_TAG | slot)) &&
            (r[HAL_STM32_NVM_RECORD_WORDS - 1U] == HAL_STM32_NVM_COMMIT)) {
            found = r;
        }
    }
    return found;
}

static const uint32_t *find_any(const hal_nvm_t *nvm, uint32_t slot)
{
    if (nvm->active < 0) {
        return NULL;
    }
    const uint32_t *r = find(nvm->sector[nvm->active], slot);
    if (r == NULL) {
        r = find(nvm->sector[1 - nvm->active], slot);
    }
    return r;
}

/* A record's 40 bytes as 10 little-endian words, and back. */
static void to_words(const uint8_t *b, uint32_t w[DATA_WORDS])
{
    for (uint32_t k = 0U; k < DATA_WORDS; k++) {
        const uint8_t *p = &b[4U * k];
        w[k] = (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) |
               ((uint32_t)p[3] << 24);
    }
}

static void to_bytes(const uint32_t *w, uint8_t *b)
{
    for (uint32_t k = 0U; k < DATA_WORDS; k++) {
        b[4U * k] = (uint8_t)w[k];
        b[(4U * k) + 1U] = (uint8_t)(w[k] >> 8);
        b[(4U * k) + 2U] = (uint8_t)(w[k] >> 16);
        b[(4U * k) + 3U] = (uint8_t)(w[k] >> 24);
    }
}

int hal_nvm_read(hal_nvm_t *nvm, uint32_t slot, uint8_t buf[PFE_NVM_RECORD_SIZE])
{
    if (slot >= PFE_NVM_SLOTS) {
        return HAL_EINVAL;
    }
    const uint32_t *r = find_any(nvm, slot);
    if (r == NULL) {
        (void)memset(buf, 0xFF, PFE_NVM_RECORD_SIZE);
    } else {
        to_bytes(&r[1], buf);
    }
    return 0;
}

/* ------------------------------------------------------------------ flash controller */

static int wait_idle(const hal_nvm_t *nvm, uint32_t timeout_us)
{
    const uint64_t t0 = hal_stm32_now_us();
    while ((nvm->regs->sr & FLASH_SR_BSY) != 0U) {
        if ((hal_stm32_now_us() - t0) > timeout_us) {
            return HAL_EIO;
        }
    }
    return ((nvm->regs->sr & FLASH_SR_ERRORS) != 0U) ? HAL_EIO : 0;
}

static int unlock(const hal_nvm_t *nvm)
{
    stm32_flash_t *f = nvm->regs;
    if ((f->cr & FLASH_CR_LOCK) != 0U) {
        HAL_STM32_WR(f->keyr, FLASH_KEY1);
        HAL_STM32_WR(f->keyr, FLASH_KEY2);
    }
    if ((f->cr & FLASH_CR_LOCK) != 0U) {
        return HAL_EIO;
    }
    HAL_STM32_WR(f->sr, FLASH_SR_ERRORS | FLASH_SR_EOP); /* write 1 to clear */
    return wait_idle(nvm, HAL_STM32_NVM_PROGRAM_TIMEOUT_US);
}

static void lock(hal_nvm_t *nvm)
{
    HAL_STM32_WR(nvm->regs->cr, FLASH_CR_LOCK);
}

/* Programs one word and reads it back. */
static int program(const hal_nvm_t *nvm, uint32_t *addr, uint32_t value)
{
    stm32_flash_t *f = nvm->regs;
    HAL_STM32_WR(f->cr, FLASH_CR_PSIZE_X32 | FLASH_CR_PG);
    HAL_STM32_WR(*(volatile uint32_t *)addr, value);
    const int rc = wait_idle(nvm, HAL_STM32_NVM_PROGRAM_TIMEOUT_US);
    HAL_STM32_WR(f->cr, 0U);
    if ((rc != 0) || (*(volatile const uint32_t *)addr != value)) {
        HAL_STM32_WR(f->sr, FLASH_SR_ERRORS | FLASH_SR_EOP);
        return HAL_EIO;
    }
    return 0;
}

static int erase(hal_nvm_t *nvm, uint32_t k)
{
    stm32_flash_t *f = nvm->regs;
    const uint32_t cr = FLASH_CR_PSIZE_X32 | FLASH_CR_SER | (nvm->snb[k] << FLASH_CR_SNB_SHIFT);
    HAL_STM32_WR(f->cr, cr);
    HAL_STM32_WR(f->cr, cr | FLASH_CR_STRT);
    const int rc = wait_idle(nvm, HAL_STM32_NVM_ERASE_TIMEOUT_US);
    HAL_STM32_WR(f->cr, 0U);
    nvm->erases++;
    if ((rc != 0) || !blank(nvm->sector[k], HAL_STM32_NVM_SECTOR_WORDS)) {
        HAL_STM32_WR(f->sr, FLASH_SR_ERRORS | FLASH_SR_EOP);
        return HAL_EIO;
    }
    return 0;
}

/* Appends one record at nvm->next of the active sector; the position is
 * used up whether or not it verifies. */
static int append(hal_nvm_t *nvm, uint32_t slot, const uint32_t data[DATA_WORDS])
{
    uint32_t *s = nvm->sector[nvm->active];
    uint32_t *r = &s[nvm->next];
    nvm->next += HAL_STM32_NVM_RECORD_WORDS;
    if (!blank(r, HAL_STM32_NVM_RECORD_WORDS)) {
        return HAL_EIO;
    }
    int rc = program(nvm, &r[0], HAL_STM32_NVM_RECORD_TAG | slot);
    for (uint32_t k = 0U; (rc == 0) && (k < DATA_WORDS); k++) {
        rc = program(nvm, &r[1U + k], data[k]);
    }
    if (rc == 0) {
        rc = program(nvm, &r[HAL_STM32_NVM_RECORD_WORDS - 1U], HAL_STM32_NVM_COMMIT);
    }
    return rc;
}

/* Formats the sector other than the active one and makes it active,
 * carrying over the latest record of `keep_slot`. */
static int switch_sector(hal_nvm_t *nvm, uint32_t keep_slot)
{
    uint32_t k = 0U; /* none active yet: sector 0 */
    if (nvm->active == 0) {
        k = 1U;
    }
    uint32_t *s = nvm->sector[k];
    uint32_t kept[DATA_WORDS];
    const uint32_t *old = find_any(nvm, keep_slot);
    const bool keep = old != NULL;
    if (keep) {
        (void)memcpy(kept, &old[1], sizeof kept);
    }
    /* Retired first, so that an erase cut short cannot leave a sector that
     * still looks formatted with stale contents. */
    if (formatted(s) && (program(nvm, &s[0], 0U) != 0)) {
        return HAL_EIO;
    }
    if ((erase(nvm, k) != 0) || (program(nvm, &s[1], nvm->generation + 1U) != 0) ||
        (program(nvm, &s[0], HAL_STM32_NVM_SECTOR_MAGIC) != 0)) {
        return HAL_EIO;
    }
    nvm->active = (int)k;
    nvm->generation++;
    nvm->next = HAL_STM32_NVM_FIRST_RECORD;
    return keep ? append(nvm, keep_slot, kept) : 0;
}

int hal_nvm_write(hal_nvm_t *nvm, uint32_t slot, const uint8_t buf[PFE_NVM_RECORD_SIZE])
{
    if (slot >= PFE_NVM_SLOTS) {
        return HAL_EINVAL;
    }
    uint32_t data[DATA_WORDS];
    to_words(buf, data);
    int rc = unlock(nvm);
    /* No room for this record: the other sector, which has room for it
     * and the one carried over. */
    if ((rc == 0) && ((nvm->active < 0) ||
                      ((nvm->next + HAL_STM32_NVM_RECORD_WORDS) > HAL_STM32_NVM_SECTOR_WORDS))) {
        rc = switch_sector(nvm, 1U - slot);
    }
    if (rc == 0) {
        rc = append(nvm, slot, data);
    }
    lock(nvm);
    if (rc == 0) {
        nvm->saves++;
    } else {
        nvm->failures++;
    }
    return rc;
}
