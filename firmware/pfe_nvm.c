/* pfe_nvm.c - fuel totals that survive a reset (contract in pfe_nvm.h). */
#include "pfe_nvm.h"

#include <stdbool.h>
#include <stddef.h>

#include "pfe_fixed.h"

static const uint8_t k_magic[4] = {(uint8_t)'P', (uint8_t)'F', (uint8_t)'N', (uint8_t)'2'};

uint32_t pfe_crc32(const uint8_t *data, uint32_t len)
{
    /* Reflected polynomial 0xEDB88320, four bits at a time. */
    static const uint32_t nibble[16] = {
        0x00000000UL, 0x1DB71064UL, 0x3B6E20C8UL, 0x26D930ACUL, 0x76DC4190UL, 0x6B6B51F4UL,
        0x4DB26158UL, 0x5005713CUL, 0xEDB88320UL, 0xF00F9344UL, 0xD6D6A3E8UL, 0xCB61B38CUL,
        0x9B64C2B0UL, 0x86D3D2D4UL, 0xA00AE278UL, 0xBDBDF21CUL,
    };
    uint32_t crc = 0xFFFFFFFFUL;
    for (uint32_t k = 0U; k < len; k++) {
        crc ^= data[k];
        crc = (crc >> 4) ^ nibble[crc & 0x0FU];
        crc = (crc >> 4) ^ nibble[crc & 0x0FU];
    }
    return crc ^ 0xFFFFFFFFUL;
}

static void put_le(uint8_t *p, uint64_t v, uint32_t n)
{
    for (uint32_t k = 0U; k < n; k++) {
        const uint32_t shift = 8U * k;
        p[k] = (uint8_t)(v >> shift);
    }
}

static uint64_t get_le(const uint8_t *p, uint32_t n)
{
    uint64_t v = 0U;
    for (uint32_t k = 0U; k < n; k++) {
        const uint32_t shift = 8U * k;
        v |= (uint64_t)p[k] << shift;
    }
    return v;
}

void pfe_nvm_encode(const pfe_nvm_state_t *state, uint8_t out[PFE_NVM_RECORD_SIZE])
{
    for (uint32_t k = 0U; k < 4U; k++) {
        out[k] = k_magic[k];
    }
    put_le(&out[4], state->sequence, 4U);
    put_le(&out[8], state->own_fuel_ul, 8U);
    put_le(&out[16], state->platoon_fuel_ul, 8U);
    put_le(&out[24], state->id_mass_kg, 4U);
    put_le(&out[28], state->id_aux_w, 4U);
    put_le(&out[32], state->id_flags, 4U);
    put_le(&out[36], pfe_crc32(out, 36U), 4U);
}

static bool magic_is(const uint8_t in[PFE_NVM_RECORD_SIZE], const uint8_t magic[4])
{
    bool same = true;
    for (uint32_t k = 0U; k < 4U; k++) {
        same = same && (in[k] == magic[k]);
    }
    return same;
}

int pfe_nvm_decode(const uint8_t in[PFE_NVM_RECORD_SIZE], pfe_nvm_state_t *state)
{
    static const uint8_t k_magic_v1[4] = {(uint8_t)'P', (uint8_t)'F', (uint8_t)'N', (uint8_t)'1'};
    const bool v2 = magic_is(in, k_magic);
    const bool v1 = magic_is(in, k_magic_v1);
    uint32_t body = 24U; /* the first layout's CRC offset */
    if (v2) {
        body = 36U;
    }
    if ((!v1 && !v2) || ((uint32_t)get_le(&in[body], 4U) != pfe_crc32(in, body))) {
        return PFE_EINVAL;
    }
    state->sequence = (uint32_t)get_le(&in[4], 4U);
    state->own_fuel_ul = get_le(&in[8], 8U);
    state->platoon_fuel_ul = get_le(&in[16], 8U);
    state->id_mass_kg = v2 ? (uint32_t)get_le(&in[24], 4U) : 0U;
    state->id_aux_w = v2 ? (uint32_t)get_le(&in[28], 4U) : 0U;
    state->id_flags = v2 ? (uint32_t)get_le(&in[32], 4U) : 0U;
    return PFE_OK;
}

int pfe_nvm_pick(const uint8_t *slot0, const uint8_t *slot1, pfe_nvm_state_t *state)
{
    pfe_nvm_state_t s[2];
    const bool ok0 = (slot0 != NULL) && (pfe_nvm_decode(slot0, &s[0]) == PFE_OK);
    const bool ok1 = (slot1 != NULL) && (pfe_nvm_decode(slot1, &s[1]) == PFE_OK);
    int pick = -1;
    if (ok0 && ok1) {
        /* Serial number arithmetic: slot 1 is newer when (s1 - s0) mod 2^32
         * lies in (0, 2^31). */
        const uint32_t d = s[1].sequence - s[0].sequence;
        if ((d != 0U) && (d < 0x80000000UL)) {
            pick = 1;
        } else {
            pick = 0;
        }
    } else if (ok0) {
        pick = 0;
    } else if (ok1) {
        pick = 1;
    } else {
        state->sequence = 0U;
        state->own_fuel_ul = 0U;
        state->platoon_fuel_ul = 0U;
        state->id_mass_kg = 0U;
        state->id_aux_w = 0U;
        state->id_flags = 0U;
        return -1;
    }
    *state = s[pick];
    return pick;
}

uint32_t pfe_nvm_next_slot(int current)
{
    return (current == 0) ? 1U : 0U;
}
