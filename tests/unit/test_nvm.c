/* Unit tests: NVM records (pfe_nvm). Expected bytes and CRCs are literals. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "pfe_fixed.h"
#include "pfe_nvm.h"

static void test_crc32_check_value(void **state)
{
    (void)state;
    /* The CRC-32/IEEE check value of "123456789". */
    static const uint8_t digits[9] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
    assert_int_equal(pfe_crc32(digits, 9U), 0xCBF43926UL);
    assert_int_equal(pfe_crc32(digits, 0U), 0x00000000UL);
}

static void test_record_layout_and_round_trip(void **state)
{
    (void)state;
    const pfe_nvm_state_t s = {0x01020304UL, 2000000000000ULL, 0x1122334455667788ULL, 12345U, 4000U, 3U};
    uint8_t rec[PFE_NVM_RECORD_SIZE];
    memset(rec, 0xA5, sizeof rec);
    pfe_nvm_encode(&s, rec);
    static const uint8_t head[16] = {'P', 'F', 'N', '2', 0x04, 0x03, 0x02, 0x01,
                                     /* 2e12 = 0x1D1A94A2000 */
                                     0x00, 0x20, 0x4A, 0xA9, 0xD1, 0x01, 0x00, 0x00};
    assert_memory_equal(rec, head, sizeof head);
    assert_int_equal(rec[16], 0x88);
    assert_int_equal(rec[23], 0x11);
    /* identification: 12345 kg = 0x3039, 4000 W = 0x0FA0, flags 3 */
    static const uint8_t ident[12] = {0x39, 0x30, 0, 0, 0xA0, 0x0F, 0, 0, 3, 0, 0, 0};
    assert_memory_equal(&rec[24], ident, sizeof ident);
    pfe_nvm_state_t back;
    memset(&back, 0xA5, sizeof back);
    assert_int_equal(pfe_nvm_decode(rec, &back), PFE_OK);
    assert_int_equal(back.sequence, s.sequence);
    assert_int_equal(back.own_fuel_ul, s.own_fuel_ul);
    assert_int_equal(back.platoon_fuel_ul, s.platoon_fuel_ul);
    assert_int_equal(back.id_mass_kg, 12345);
    assert_int_equal(back.id_aux_w, 4000);
    assert_int_equal(back.id_flags, PFE_NVM_ID_VALID | PFE_NVM_ID_CONVERGED);
    /* Any flipped bit is caught. */
    for (uint32_t k = 0U; k < PFE_NVM_RECORD_SIZE * 8U; k++) {
        uint8_t bad[PFE_NVM_RECORD_SIZE];
        memcpy(bad, rec, sizeof bad);
        bad[k / 8U] ^= (uint8_t)(1U << (k % 8U));
        assert_int_equal(pfe_nvm_decode(bad, &back), PFE_EINVAL);
    }
}

/* A record of the first layout ("PFN1", CRC of bytes 0..23 at 24) still
 * restores its totals, with nothing identified. */
static void test_reads_the_first_layout(void **state)
{
    (void)state;
    uint8_t rec[PFE_NVM_RECORD_SIZE];
    memset(rec, 0xFF, sizeof rec);
    static const uint8_t v1[24] = {'P', 'F', 'N', '1', 9, 0, 0, 0, 0x10, 0x27, 0, 0, 0, 0, 0, 0,
                                   0x20, 0x4E, 0, 0, 0, 0, 0, 0};
    memcpy(rec, v1, sizeof v1);
    const uint32_t crc = pfe_crc32(rec, 24U);
    for (uint32_t k = 0U; k < 4U; k++) {
        rec[24U + k] = (uint8_t)(crc >> (8U * k));
    }
    pfe_nvm_state_t back;
    memset(&back, 0xA5, sizeof back);
    assert_int_equal(pfe_nvm_decode(rec, &back), PFE_OK);
    assert_int_equal(back.sequence, 9);
    assert_int_equal(back.own_fuel_ul, 10000);
    assert_int_equal(back.platoon_fuel_ul, 20000);
    assert_int_equal(back.id_flags, 0);
    assert_int_equal(back.id_mass_kg, 0);
    rec[8] ^= 1U;
    assert_int_equal(pfe_nvm_decode(rec, &back), PFE_EINVAL);
}

static void test_pick_newest_valid_slot(void **state)
{
    (void)state;
    uint8_t a[PFE_NVM_RECORD_SIZE], b[PFE_NVM_RECORD_SIZE], erased[PFE_NVM_RECORD_SIZE];
    memset(erased, 0xFF, sizeof erased);
    pfe_nvm_state_t s = {7U, 100U, 500U, 0U, 0U, 0U};
    pfe_nvm_encode(&s, a);
    s = (pfe_nvm_state_t){8U, 150U, 700U, 0U, 0U, 0U};
    pfe_nvm_encode(&s, b);
    pfe_nvm_state_t got;
    assert_int_equal(pfe_nvm_pick(a, b, &got), 1);
    assert_int_equal(got.own_fuel_ul, 150U);
    assert_int_equal(pfe_nvm_next_slot(1), 0);
    assert_int_equal(pfe_nvm_pick(b, a, &got), 0);
    /* A torn newer slot: the older one wins. */
    b[20] ^= 0x40U;
    assert_int_equal(pfe_nvm_pick(a, b, &got), 0);
    assert_int_equal(got.own_fuel_ul, 100U);
    /* Nothing valid: zeros and -1. */
    assert_int_equal(pfe_nvm_pick(erased, NULL, &got), -1);
    assert_int_equal(got.sequence, 0U);
    assert_int_equal(got.own_fuel_ul, 0U);
    assert_int_equal(got.platoon_fuel_ul, 0U);
    assert_int_equal(pfe_nvm_next_slot(-1), 0);
    /* Sequence wrap: 0 is newer than 0xFFFFFFFF. */
    s = (pfe_nvm_state_t){0xFFFFFFFFUL, 1U, 1U, 0U, 0U, 0U};
    pfe_nvm_encode(&s, a);
    s = (pfe_nvm_state_t){0U, 2U, 2U, 0U, 0U, 0U};
    pfe_nvm_encode(&s, b);
    assert_int_equal(pfe_nvm_pick(a, b, &got), 1);
    assert_int_equal(got.own_fuel_ul, 2U);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crc32_check_value),
        cmocka_unit_test(test_record_layout_and_round_trip),
        cmocka_unit_test(test_reads_the_first_layout),
        cmocka_unit_test(test_pick_newest_valid_slot),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
