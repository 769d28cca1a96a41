/*
 * pfe_nvm.h - fuel totals that survive a reset.
 *
 * The module keeps two record slots in non-volatile memory and writes them
 * in turn, each record carrying a sequence number and a CRC-32. At start-up
 * the newest record whose CRC checks is used. A reset at any instant can
 * spoil at most the slot being written; the other slot still holds the
 * previous record, so at most one save interval of fuel is lost, and a
 * total never goes backwards past the last completed save.
 *
 * This file only builds and checks the bytes; a HAL backend stores them.
 *
 * Record layout (PFE_NVM_RECORD_SIZE bytes, little endian):
 *   0  magic "PFN2"      4  sequence (uint32, wraps; compared by serial
 *   8  own fuel used, uL (uint64)          number arithmetic, RFC 1982)
 *   16 platoon fuel used, uL (uint64)
 *   24 identified mass, kg (uint32)   28 identified aux power, W (uint32)
 *   32 identification flags (uint32): PFE_NVM_ID_* (0: nothing identified)
 *   36 CRC-32 (IEEE 802.3, reflected, init and final xor 0xFFFFFFFF) of bytes 0..35
 * A record of the first layout ("PFN1": totals, CRC-32 of bytes 0..23 at
 * 24) is still read: its totals restore, with nothing identified.
 */
#ifndef PFE_NVM_H
#define PFE_NVM_H

#include <stdint.h>

#define PFE_NVM_RECORD_SIZE 40U
#define PFE_NVM_ID_VALID 1U       /* mass and aux power hold an identification */
#define PFE_NVM_ID_CONVERGED 2U   /* it had converged (pfe_identify.h) */
#define PFE_NVM_SLOTS 2U

typedef struct {
    uint32_t sequence;
    uint64_t own_fuel_ul;
    uint64_t platoon_fuel_ul;
    uint32_t id_mass_kg;        /* identified mass, when id_flags has PFE_NVM_ID_VALID */
    uint32_t id_aux_w;          /* identified auxiliary power */
    uint32_t id_flags;          /* PFE_NVM_ID_* */
} pfe_nvm_state_t;

/* CRC-32 (IEEE) of len bytes; nibble table, no large tables. */
uint32_t pfe_crc32(const uint8_t *data, uint32_t len);

/* Serialises a record. */
void pfe_nvm_encode(const pfe_nvm_state_t *state, uint8_t out[PFE_NVM_RECORD_SIZE]);

/* Parses a record: PFE_OK, or PFE_EINVAL when the magic or the CRC is wrong
 * (blank, torn or foreign data). */
int pfe_nvm_decode(const uint8_t in[PFE_NVM_RECORD_SIZE], pfe_nvm_state_t *state);

/*
 * The newest valid record of the two slots (either pointer may be NULL for
 * an unreadable slot). Returns the slot index 0 or 1 it came from, or -1 when
 * neither is valid (then *state is all zero). The next save goes to the
 * other slot: pfe_nvm_next_slot().
 */
int pfe_nvm_pick(const uint8_t *slot0, const uint8_t *slot1, pfe_nvm_state_t *state);

/* Slot to write after the record found in slot `current` (-1: none). */
uint32_t pfe_nvm_next_slot(int current);

#endif /* PFE_NVM_H */
