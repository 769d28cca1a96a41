/*
 * fuzz_nvm.c - libFuzzer target: the NVM image loader (firmware/pfe_nvm.h:
 * pfe_nvm_decode(), pfe_nvm_pick()) and the ECU started from what it picks.
 *
 * Input: byte 0: bits 0, 1 give slot 0, 1 a correct CRC (computed over the
 * bytes given, so that records with any content are read, not only the
 * rare ones whose random CRC matches); bits 2, 3 give the slot magic;
 * bits 4, 5 make slot 0, 1 unreadable (NULL); bit 6: the first layout
 * ("PFN1", CRC of 24 bytes) instead of the current one ("PFN2", CRC of 36
 * bytes); then PFE_NVM_RECORD_SIZE bytes of slot 0 and as many of slot 1
 * (missing bytes are 0xFF, erased flash).
 *
 * Invariants (abort on failure): decode accepts exactly the records with
 * the magic and their CRC, and then re-encodes them byte for byte (a
 * record of the first layout: its totals, nothing identified); pick
 * returns -1 (and zeros) when neither slot decodes, else the slot that
 * decodes, or of two the newer by serial number arithmetic (ties: slot
 * 0), with that slot's values; the next slot is the other one; the ECU
 * starts from any picked record, gives back the totals restored (up to
 * what its estimator holds: 2^64 - 1 in 10 pL) and never lets them fall
 * in 1.5 s of driving (one save included).
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "fuzz_check.h"
#include "pfe_calib.h"
#include "pfe_ecu.h"
#include "pfe_fixed.h"
#include "pfe_nvm.h"

#define ESTIMATOR_MAX_UL 184467440737095ULL /* floor((2^64 - 1) / 10^5): 10 pL in uL */

static pfe_ecu_t g_ecu;

static uint32_t le32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

static uint64_t le64(const uint8_t *p)
{
    return (uint64_t)le32(p) | ((uint64_t)le32(p + 4) << 32);
}

/* Decodes one slot and checks decode against the layout of pfe_nvm.h. */
static bool check_slot(const uint8_t rec[PFE_NVM_RECORD_SIZE], pfe_nvm_state_t *out)
{
    pfe_nvm_state_t s;
    memset(&s, 0xA5, sizeof s);
    const int rc = pfe_nvm_decode(rec, &s);
    const bool v2 = (memcmp(rec, "PFN2", 4U) == 0) && (le32(&rec[36]) == pfe_crc32(rec, 36U));
    const bool v1 = (memcmp(rec, "PFN1", 4U) == 0) && (le32(&rec[24]) == pfe_crc32(rec, 24U));
    const bool valid = v1 || v2;
    FUZZ_CHECK((rc == PFE_OK) == valid);
    FUZZ_CHECK((rc == PFE_OK) || (rc == PFE_EINVAL));
    if (!valid) {
        return false;
    }
    FUZZ_CHECK(s.sequence == le32(&rec[4]));
    FUZZ_CHECK(s.own_fuel_ul == le64(&rec[8]));
    FUZZ_CHECK(s.platoon_fuel_ul == le64(&rec[16]));
    if (v2) {
        FUZZ_CHECK(s.id_mass_kg == le32(&rec[24]));
        FUZZ_CHECK(s.id_aux_w == le32(&rec[28]));
        FUZZ_CHECK(s.id_flags == le32(&rec[32]));
        uint8_t again[PFE_NVM_RECORD_SIZE];
        pfe_nvm_encode(&s, again);
        FUZZ_CHECK(memcmp(again, rec, sizeof again) == 0);
    } else {
        FUZZ_CHECK((s.id_flags == 0U) && (s.id_mass_kg == 0U) && (s.id_aux_w == 0U));
    }
    *out = s;
    return true;
}

static uint64_t held_ul(uint64_t ul)
{
    return (ul > ESTIMATOR_MAX_UL) ? ESTIMATOR_MAX_UL : ul;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t slot[PFE_NVM_SLOTS][PFE_NVM_RECORD_SIZE];
    memset(slot, 0xFF, sizeof slot);
    const uint8_t flags = (size > 0U) ? data[0] : 0U;
    if (size > 1U) {
        const size_t n = ((size - 1U) < sizeof slot) ? (size - 1U) : sizeof slot;
        memcpy(slot, data + 1, n);
    }
    for (uint32_t k = 0U; k < PFE_NVM_SLOTS; k++) {
        const bool first_layout = (flags & 64U) != 0U;
        const uint32_t body = first_layout ? 24U : 36U;
        if ((flags & (4U << k)) != 0U) {
            memcpy(slot[k], first_layout ? "PFN1" : "PFN2", 4U);
        }
        if ((flags & (1U << k)) != 0U) {
            const uint32_t crc = pfe_crc32(slot[k], body);
            for (uint32_t b = 0U; b < 4U; b++) {
                slot[k][body + b] = (uint8_t)(crc >> (8U * b));
            }
        }
    }
    const bool readable0 = (flags & 16U) == 0U;
    const bool readable1 = (flags & 32U) == 0U;
    pfe_nvm_state_t s0, s1;
    const bool ok0 = check_slot(slot[0], &s0) && readable0;
    const bool ok1 = check_slot(slot[1], &s1) && readable1;

    pfe_nvm_state_t got;
    memset(&got, 0xA5, sizeof got);
    int pick = pfe_nvm_pick(readable0 ? slot[0] : NULL, readable1 ? slot[1] : NULL, &got);
    int want = -1;
    if (ok0 && ok1) {
        const uint32_t d = s1.sequence - s0.sequence;
        want = ((d != 0U) && (d < 0x80000000UL)) ? 1 : 0;
    } else if (ok0 || ok1) {
        want = ok0 ? 0 : 1;
    }
    FUZZ_CHECK(pick == want);
    if (pick < 0) {
        FUZZ_CHECK((got.sequence == 0U) && (got.own_fuel_ul == 0U) && (got.platoon_fuel_ul == 0U));
    } else {
        const pfe_nvm_state_t *w = (pick == 0) ? &s0 : &s1;
        FUZZ_CHECK((got.sequence == w->sequence) && (got.own_fuel_ul == w->own_fuel_ul) &&
                   (got.platoon_fuel_ul == w->platoon_fuel_ul));
    }
    FUZZ_CHECK(pfe_nvm_next_slot(pick) == ((pick == 0) ? 1U : 0U));

    /* The ECU from the record: totals back as saved (or held at the
     * estimator's limit), then 1.5 s of a truck at 90 km/h on a 2 % grade. */
    const pfe_ecu_config_t cfg = {
        .preferred_address = PFE_ECU_DEFAULT_ADDRESS,
        .name = 0x80A0000012345678ULL,
        .save_interval_ms = 1000U,
        .vehicle = &pfe_default_vehicle,
        .env = &pfe_default_env,
        .drag = &pfe_default_drag,
        .default_vehicles = 1U,
        .default_position = 0U,
        .default_gap_mm = 10000U,
        .cruise = &pfe_default_cruise,
        .default_set_speed_mm_s = 25000,
    };
    FUZZ_CHECK(pfe_ecu_init(&g_ecu, &cfg, (pick >= 0) ? &got : NULL, pick, 1000000U) == PFE_OK);
    uint64_t own = pfe_ecu_own_fuel_ul(&g_ecu);
    uint64_t platoon = pfe_ecu_platoon_fuel_ul(&g_ecu);
    FUZZ_CHECK(own == ((pick >= 0) ? held_ul(got.own_fuel_ul) : 0U));
    FUZZ_CHECK(platoon == ((pick >= 0) ? held_ul(got.platoon_fuel_ul) : 0U));
    uint64_t now = 1000000U;
    for (uint32_t k = 0U; k < 150U; k++) {
        if ((k % 10U) == 0U) {
            /* CCVS1 90 km/h (0x5A00 / 256); SSI pitch 0x7F3D: 1.146 deg, 2 % */
            const pfe_can_frame_t speed = {0x98FEF100UL, 8U, {0xFF, 0x00, 0x5A, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF}};
            pfe_ecu_receive(&g_ecu, &speed, now);
        }
        const pfe_can_frame_t pitch = {0x8CF01300UL, 8U, {0x3D, 0x7F, 0x00, 0x7D, 0xFF, 0xFF, 0xFC, 0xFF}};
        pfe_ecu_receive(&g_ecu, &pitch, now);
        pfe_can_frame_t tx[PFE_ECU_TX_MAX];
        (void)pfe_ecu_tick(&g_ecu, now, tx, PFE_ECU_TX_MAX);
        const uint64_t o = pfe_ecu_own_fuel_ul(&g_ecu);
        const uint64_t p = pfe_ecu_platoon_fuel_ul(&g_ecu);
        FUZZ_CHECK((o >= own) && (p >= platoon));
        own = o;
        platoon = p;
        if (pfe_ecu_nvm_due(&g_ecu)) {
            pfe_nvm_state_t s;
            const uint32_t next = pfe_ecu_nvm_slot(&g_ecu);
            FUZZ_CHECK(next == pfe_nvm_next_slot(pick));
            pfe_ecu_nvm_take(&g_ecu, &s);
            FUZZ_CHECK(s.sequence == ((pick >= 0) ? got.sequence + 1U : 1U));
            FUZZ_CHECK((s.own_fuel_ul == own) && (s.platoon_fuel_ul == platoon));
            pfe_ecu_nvm_written(&g_ecu, 0);
            pick = (int)next;
            got = s;
        }
        now += PFE_ECU_TICK_US;
    }
    return 0;
}
