/* Unit tests: J1939 ids (pfe_can) and the frame codec (pfe_codec).
 * Expected bytes and values are hand-computed from can_dbc/pfe.dbc and
 * docs/j1939.md (signals and value states); tangents from a 40-digit reference. Runs on the
 * host and on the Cortex-M4: no files, large objects static, and no float
 * but the double-precision tangent that the pitch-to-grade conversion is
 * checked against. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "pfe_can.h"
#include "pfe_codec.h"
#include "pfe_fixed.h"

#define NA PFE_SIG_NOT_AVAILABLE
#define ERR PFE_SIG_ERROR
#define OOR PFE_SIG_OUT_OF_RANGE
#define OK_ PFE_SIG_VALID

static pfe_can_frame_t frame8(uint32_t id, uint8_t b0, uint8_t b1, uint8_t b2, uint8_t b3, uint8_t b4,
                              uint8_t b5, uint8_t b6, uint8_t b7)
{
    pfe_can_frame_t f;
    f.id = id;
    f.dlc = 8U;
    f.data[0] = b0;
    f.data[1] = b1;
    f.data[2] = b2;
    f.data[3] = b3;
    f.data[4] = b4;
    f.data[5] = b5;
    f.data[6] = b6;
    f.data[7] = b7;
    return f;
}

static void assert_payload(const pfe_can_frame_t *f, uint8_t b0, uint8_t b1, uint8_t b2, uint8_t b3,
                           uint8_t b4, uint8_t b5, uint8_t b6, uint8_t b7)
{
    const uint8_t expected[8] = {b0, b1, b2, b3, b4, b5, b6, b7};
    assert_memory_equal(f->data, expected, 8U);
}

static pfe_can_frame_t poisoned_frame(void)
{
    pfe_can_frame_t f;
    memset(&f, 0xA5, sizeof f);
    return f;
}

/* ------------------------------------------------------------ J1939 ids */

static void test_j1939_pgn_source_destination(void **state)
{
    (void)state;
    /* PDU2: CCVS1 from 0xAB, with and without the EFF flag */
    assert_int_equal(pfe_j1939_pgn(0x98FEF1ABUL), 65265);
    assert_int_equal(pfe_j1939_pgn(0x18FEF1ABUL), 65265);
    assert_int_equal(pfe_j1939_source(0x98FEF1ABUL), 0xAB);
    assert_int_equal(pfe_j1939_destination(0x98FEF1ABUL), PFE_J1939_ADDR_GLOBAL);
    /* SSI at priority 3 */
    assert_int_equal(pfe_j1939_pgn(0x8CF01300UL), 61459);
    /* PDU1: Request to 0x8C from 0x00; Address Claimed to global from 0x8C */
    assert_int_equal(pfe_j1939_pgn(0x98EA8C00UL), 59904);
    assert_int_equal(pfe_j1939_destination(0x98EA8C00UL), 0x8C);
    assert_int_equal(pfe_j1939_source(0x98EA8C00UL), 0x00);
    assert_int_equal(pfe_j1939_pgn(0x98EEFF8CUL), 60928);
    assert_int_equal(pfe_j1939_destination(0x98EEFF8CUL), 0xFF);
    /* PF 239 is the last PDU1 format, 240 the first PDU2 */
    assert_int_equal(pfe_j1939_pgn(0x18EF1234UL), 0xEF00);
    assert_int_equal(pfe_j1939_destination(0x18EF1234UL), 0x12);
    assert_int_equal(pfe_j1939_pgn(0x18F01234UL), 0xF012);
    assert_int_equal(pfe_j1939_destination(0x18F01234UL), 0xFF);
    /* data page and extended data page belong to the PGN */
    assert_int_equal(pfe_j1939_pgn(0x19FEF100UL), 0x1FEF1);
    assert_int_equal(pfe_j1939_pgn(0x1BFEF100UL), 0x3FEF1);
    assert_int_equal(pfe_j1939_pgn(0x1AEA0000UL), 0x2EA00);
}

static void test_j1939_id_builds_identifiers(void **state)
{
    (void)state;
    assert_int_equal(pfe_j1939_id(6U, 65265U, 0x55U, 0x00U), 0x98FEF100UL); /* PDU2: destination unused */
    assert_int_equal(pfe_j1939_id(3U, 61459U, 0xFFU, 0x00U), 0x8CF01300UL);
    assert_int_equal(pfe_j1939_id(6U, 59904U, 0x8CU, 0x00U), 0x98EA8C00UL);
    assert_int_equal(pfe_j1939_id(6U, 0xEA12U, 0x8CU, 0x01U), 0x98EA8C01UL); /* PS replaced by destination */
    assert_int_equal(pfe_j1939_id(6U, 60928U, 0xFFU, 0x8CU), 0x98EEFF8CUL);
    assert_int_equal(pfe_j1939_id(7U, 0x3FFFFU, 0U, 0xFEU), 0x9FFFFFFEUL);
    assert_int_equal(pfe_j1939_id(0U, 0U, 0x20U, 0x00U), 0x80002000UL);   /* PGN 0 (TSC1) is PDU1 */
    /* out-of-contract bits are masked, never spill into other fields */
    assert_int_equal(pfe_j1939_id(9U, 0x7FEF1U, 0U, 0x11U), 0x87FEF111UL);
    /* round trip */
    const uint32_t id = pfe_j1939_id(6U, 64777U, 0U, 0x8CU);
    assert_int_equal(id, 0x98FD098CUL);
    assert_int_equal(pfe_j1939_pgn(id), 64777);
    assert_int_equal(pfe_j1939_source(id), 0x8C);
}

static void test_find_message_masks_priority_and_addresses(void **state)
{
    (void)state;
    assert_ptr_equal(pfe_codec_find_message(0x98FEF1ABUL), &pfe_codec_messages[PFE_MSG_CCVS1]);
    assert_ptr_equal(pfe_codec_find_message(0x8CFEF100UL), &pfe_codec_messages[PFE_MSG_CCVS1]);
    assert_ptr_equal(pfe_codec_find_message(0x98EA8C17UL), &pfe_codec_messages[PFE_MSG_REQUEST]);
    assert_ptr_equal(pfe_codec_find_message(0x98EA3117UL), &pfe_codec_messages[PFE_MSG_REQUEST]);
    assert_ptr_equal(pfe_codec_find_message(0x98FF0442UL), &pfe_codec_messages[PFE_MSG_STATUS]);
    assert_null(pfe_codec_find_message(0x18FEF100UL));  /* no EFF flag: an 11-bit id */
    assert_null(pfe_codec_find_message(0x98FEF300UL));  /* PGN 65267 is not ours */
    assert_null(pfe_codec_find_message(0x99FEF100UL));  /* data page 1 */
}

/* ------------------------------------------------------------ tables */

static void test_message_table(void **state)
{
    (void)state;
    static const struct {
        uint32_t pgn;
        uint8_t dlc;
        uint16_t cycle_ms;
        uint8_t first;
        uint8_t n;
    } expected[PFE_MSG_COUNT] = {
        {65265U, 8U, 100U, 0U, 1U},   {61459U, 8U, 10U, 1U, 3U},    {65280U, 8U, 1000U, 4U, 5U},
        {65281U, 8U, 0U, 9U, 8U},     {65266U, 8U, 100U, 17U, 1U},  {65282U, 8U, 100U, 18U, 2U},
        {64777U, 8U, 1000U, 20U, 2U}, {65283U, 8U, 1000U, 22U, 4U}, {65284U, 8U, 1000U, 26U, 14U},
        {60928U, 8U, 0U, 40U, 10U},   {59904U, 3U, 0U, 50U, 1U},    {65256U, 8U, 1000U, 51U, 4U},
        {65136U, 8U, 0U, 55U, 2U},    {65285U, 8U, 100U, 57U, 3U},  {65286U, 8U, 1000U, 60U, 9U},
        {65287U, 8U, 1000U, 69U, 10U},
    };
    uint32_t covered = 0U;
    for (uint32_t m = 0U; m < (uint32_t)PFE_MSG_COUNT; m++) {
        const pfe_codec_message_t *msg = &pfe_codec_messages[m];
        assert_int_equal(msg->pgn, expected[m].pgn);
        assert_int_equal(msg->dlc, expected[m].dlc);
        assert_int_equal(msg->cycle_ms, expected[m].cycle_ms);
        assert_int_equal(msg->first_signal, expected[m].first);
        assert_int_equal(msg->n_signals, expected[m].n);
        assert_int_equal(msg->first_signal, covered); /* contiguous, in order */
        covered += msg->n_signals;
        for (uint32_t i = msg->first_signal; i < (uint32_t)msg->first_signal + msg->n_signals; i++) {
#ifndef PFE_CODEC_NO_NAMES /* the images keep no names (pfe_codec.h) */
            assert_int_equal(pfe_codec_signals[i].pgn, msg->pgn);
            assert_string_equal(pfe_codec_signals[i].message, msg->name);
#endif
        }
    }
    assert_int_equal(covered, PFE_CODEC_SIGNAL_COUNT);
    assert_int_equal(pfe_codec_signal_count, 79);
}

/* Signals of one message never share a bit unless they belong to different
 * values of the multiplexer; each fits its message and its raw range fits
 * its length. */
static void test_signal_table_is_consistent(void **state)
{
    (void)state;
    for (uint32_t m = 0U; m < (uint32_t)PFE_MSG_COUNT; m++) {
        const pfe_codec_message_t *msg = &pfe_codec_messages[m];
        for (uint32_t i = msg->first_signal; i < (uint32_t)msg->first_signal + msg->n_signals; i++) {
            const pfe_codec_signal_t *a = &pfe_codec_signals[i];
            assert_in_range(a->length, 1, 32);
            ASSERT_LE((uint32_t)a->start_bit + a->length, 8U * msg->dlc);
            assert_int_equal(a->byte_order, PFE_CODEC_LITTLE_ENDIAN);
            assert_false(a->is_signed);
#ifndef PFE_CODEC_NO_NAMES
            ASSERT_GT(a->scale_den, 0);
            ASSERT_GT(a->offset_den, 0);
#endif
            ASSERT_GT(a->fw_den, 0);
            ASSERT_LE(a->raw_min, a->raw_max);
            if (a->length < 32U) {
                ASSERT_LT(a->raw_max, 1UL << a->length);
            }
            const uint64_t ma = (((uint64_t)1 << a->length) - 1U) << a->start_bit;
            for (uint32_t k = i + 1U; k < (uint32_t)msg->first_signal + msg->n_signals; k++) {
                const pfe_codec_signal_t *b = &pfe_codec_signals[k];
                const uint64_t mb = (((uint64_t)1 << b->length) - 1U) << b->start_bit;
                const bool exclusive = (a->mux >= 0) && (b->mux >= 0) && (a->mux != b->mux);
                if (!exclusive) {
                    assert_int_equal(ma & mb, 0U);
                }
            }
        }
    }
}

typedef struct {
    pfe_sig_index_t sig;
    uint32_t raw_max;
    pfe_sig_state_t at_zero;
    bool has_above;           /* raw_max + 1 fits in the signal's length */
    pfe_sig_state_t above_max;
    uint32_t code_na;
    pfe_sig_state_t at_na;
    uint32_t code_err;
    pfe_sig_state_t at_err;
} sig_case_t;

/* Every signal: 0, the valid maximum, one above it, the not-available and
 * error codes a sender writes, and how a receiver classifies them. */
static const sig_case_t sig_cases[PFE_CODEC_SIGNAL_COUNT] = {
    {PFE_CSIG_CCVS1_WHEEL_BASED_VEHICLE_SPEED, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_SSI_PITCH_ANGLE, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_SSI_ROLL_ANGLE, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_SSI_PITCH_ANGLE_FOM, 1U, OK_, true, ERR, 3U, NA, 2U, ERR},
    {PFE_CSIG_PC_NUMBER_OF_VEHICLES, 32U, OOR, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_PC_OWN_POSITION, 31U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_PC_GAP, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_PC_TIME_GAP, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_PC_SET_SPEED, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_GP_FRAME_TYPE, 1U, OK_, true, OOR, 3U, OOR, 3U, OOR},
    {PFE_CSIG_GP_PREVIEW_ID, 15U, OK_, false, OOR, 15U, OK_, 15U, OK_},
    {PFE_CSIG_GP_SAMPLE_COUNT, 1000U, OOR, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_GP_SAMPLE_SPACING, 250U, OOR, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_GP_SAMPLE_INDEX, 999U, OK_, true, OOR, 0x3FFU, OOR, 0x3FFU, OOR},
    {PFE_CSIG_GP_GRADE_SAMPLE0, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_GP_GRADE_SAMPLE1, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_GP_GRADE_SAMPLE2, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_LFE1_ENGINE_FUEL_RATE, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_PF_PLATOON_FUEL_RATE, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_PF_PLATOON_TOTAL_FUEL_USED, 0xFAFFFFFFUL, OK_, true, OOR, 0xFFFFFFFFUL, NA, 0xFEFFFFFFUL, ERR},
    {PFE_CSIG_HRLFC_TRIP_FUEL, 0xFAFFFFFFUL, OK_, true, OOR, 0xFFFFFFFFUL, NA, 0xFEFFFFFFUL, ERR},
    {PFE_CSIG_HRLFC_TOTAL_FUEL_USED, 0xFAFFFFFFUL, OK_, true, OOR, 0xFFFFFFFFUL, NA, 0xFEFFFFFFUL, ERR},
    {PFE_CSIG_FP_PREDICTED_FUEL, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_FP_PREDICTED_FUEL_LOWER, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_FP_PREDICTED_FUEL_UPPER, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_FP_PREDICTED_TIME, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_ST_SPEED_INPUT, 3U, OK_, false, OOR, 3U, OK_, 3U, OK_},
    {PFE_CSIG_ST_GRADE_INPUT, 3U, OK_, false, OOR, 3U, OK_, 3U, OK_},
    {PFE_CSIG_ST_PLATOON_CONFIG_INPUT, 3U, OK_, false, OOR, 3U, OK_, 3U, OK_},
    {PFE_CSIG_ST_GRADE_PREVIEW_INPUT, 3U, OK_, false, OOR, 3U, OK_, 3U, OK_},
    {PFE_CSIG_ST_DEGRADED_MODE, 2U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_ST_RX_FRAMES_DROPPED, 250U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_ST_TICK_OVERRUNS, 250U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_ST_TX_FRAMES_DROPPED, 250U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_ST_WARMING_UP, 1U, OK_, true, ERR, 3U, NA, 2U, ERR},
    {PFE_CSIG_ST_SPEED_CLAMPED, 1U, OK_, true, ERR, 3U, NA, 2U, ERR},
    {PFE_CSIG_ST_GRADE_CLAMPED, 1U, OK_, true, ERR, 3U, NA, 2U, ERR},
    {PFE_CSIG_ST_OUTPUT_SATURATED, 1U, OK_, true, ERR, 3U, NA, 2U, ERR},
    {PFE_CSIG_ST_INPUTS_REJECTED, 250U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_ST_ADDRESS_CONFLICTS, 250U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_AC_IDENTITY_NUMBER, 0x1FFFFFUL, OK_, false, OOR, 0x1FFFFFUL, OK_, 0x1FFFFFUL, OK_},
    {PFE_CSIG_AC_MANUFACTURER_CODE, 0x7FFU, OK_, false, OOR, 0x7FFU, OK_, 0x7FFU, OK_},
    {PFE_CSIG_AC_ECU_INSTANCE, 7U, OK_, false, OOR, 7U, OK_, 7U, OK_},
    {PFE_CSIG_AC_FUNCTION_INSTANCE, 31U, OK_, false, OOR, 31U, OK_, 31U, OK_},
    {PFE_CSIG_AC_FUNCTION, 255U, OK_, false, OOR, 255U, OK_, 255U, OK_},
    {PFE_CSIG_AC_RESERVED, 1U, OK_, false, OOR, 1U, OK_, 1U, OK_},
    {PFE_CSIG_AC_VEHICLE_SYSTEM, 127U, OK_, false, OOR, 127U, OK_, 127U, OK_},
    {PFE_CSIG_AC_VEHICLE_SYSTEM_INSTANCE, 15U, OK_, false, OOR, 15U, OK_, 15U, OK_},
    {PFE_CSIG_AC_INDUSTRY_GROUP, 7U, OK_, false, OOR, 7U, OK_, 7U, OK_},
    {PFE_CSIG_AC_ARBITRARY_ADDRESS_CAPABLE, 1U, OK_, false, OOR, 1U, OK_, 1U, OK_},
    {PFE_CSIG_RQST_REQUESTED_PGN, 0x3FFFFUL, OK_, true, OOR, 0xFFFFFFUL, OOR, 0xFFFFFFUL, OOR},
    {PFE_CSIG_VDS_COMPASS_BEARING, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_VDS_NAV_SPEED, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_VDS_PITCH, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_VDS_ALTITUDE, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_CVW_POWERED_VEHICLE_WEIGHT, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_CVW_GROSS_COMBINATION_WEIGHT, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_OF_OWN_FUEL_RATE, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_OF_OWN_TOTAL_FUEL_USED, 0xFAFFFFFFUL, OK_, true, OOR, 0xFFFFFFFFUL, NA, 0xFEFFFFFFUL, ERR},
    {PFE_CSIG_OF_MODEL_IDENTIFIED, 1U, OK_, true, ERR, 3U, NA, 2U, ERR},
    {PFE_CSIG_IS_SPEED_SOURCE, 253U, OK_, true, OOR, 0xFFU, OOR, 0xFFU, OOR},
    {PFE_CSIG_IS_GRADE_SOURCE_ADDRESS, 253U, OK_, true, OOR, 0xFFU, OOR, 0xFFU, OOR},
    {PFE_CSIG_IS_FUEL_RATE_SOURCE, 253U, OK_, true, OOR, 0xFFU, OOR, 0xFFU, OOR},
    {PFE_CSIG_IS_SPEED_SENDERS, 15U, OK_, false, OOR, 15U, OK_, 15U, OK_},
    {PFE_CSIG_IS_GRADE_SENDERS, 15U, OK_, false, OOR, 15U, OK_, 15U, OK_},
    {PFE_CSIG_IS_GRADE_SOURCE, 3U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_IS_MASS_SOURCE, 2U, OK_, true, OOR, 15U, OOR, 15U, OOR},
    {PFE_CSIG_IS_IDENTIFICATION_STATE, 1U, OK_, true, ERR, 3U, NA, 2U, ERR},
    {PFE_CSIG_IS_VEHICLE_MASS, 0xFAFFU, OK_, true, OOR, 0xFFFFU, NA, 0xFEFFU, ERR},
    {PFE_CSIG_DS_RX_FIFO_OVERRUNS, 250U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_DS_BUS_OFF_EVENTS, 250U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_DS_ERROR_WARNING, 1U, OK_, true, ERR, 3U, NA, 2U, ERR},
    {PFE_CSIG_DS_ERROR_PASSIVE, 1U, OK_, true, ERR, 3U, NA, 2U, ERR},
    {PFE_CSIG_DS_BUS_OFF, 1U, OK_, true, ERR, 3U, NA, 2U, ERR},
    {PFE_CSIG_DS_NVM_WRITE_FAILING, 1U, OK_, true, ERR, 3U, NA, 2U, ERR},
    {PFE_CSIG_DS_RESET_CAUSE, 3U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_DS_TX_ERROR_COUNTER, 250U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_DS_RX_ERROR_COUNTER, 250U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
    {PFE_CSIG_DS_NVM_WRITE_FAILURES, 250U, OK_, true, OOR, 0xFFU, NA, 0xFEU, ERR},
};

static void test_every_signal_boundaries_and_codes(void **state)
{
    (void)state;
    for (uint32_t k = 0U; k < (uint32_t)PFE_CODEC_SIGNAL_COUNT; k++) {
        const sig_case_t *c = &sig_cases[k];
        assert_int_equal(c->sig, k);
        const pfe_codec_signal_t *sig = &pfe_codec_signals[c->sig];
        assert_int_equal(sig->raw_max, c->raw_max);
        assert_int_equal(pfe_codec_raw_state(sig, 0U), c->at_zero);
        assert_int_equal(pfe_codec_raw_state(sig, sig->raw_min), PFE_SIG_VALID);
        assert_int_equal(pfe_codec_raw_state(sig, c->raw_max), PFE_SIG_VALID);
        if (c->has_above) {
            assert_int_equal(pfe_codec_raw_state(sig, c->raw_max + 1U), c->above_max);
        }
        assert_int_equal(pfe_codec_raw_code(sig, PFE_SIG_NOT_AVAILABLE), c->code_na);
        assert_int_equal(pfe_codec_raw_state(sig, c->code_na), c->at_na);
        assert_int_equal(pfe_codec_raw_code(sig, PFE_SIG_ERROR), c->code_err);
        assert_int_equal(pfe_codec_raw_state(sig, c->code_err), c->at_err);

        /* put/get touch the signal's bits only */
        uint8_t data[8];
        memset(data, 0xA5, sizeof data);
        const uint32_t before = pfe_codec_raw_get(data, sig);
        pfe_codec_raw_put(data, sig, c->raw_max);
        assert_int_equal(pfe_codec_raw_get(data, sig), c->raw_max);
        pfe_codec_raw_put(data, sig, before);
        for (uint32_t i = 0U; i < 8U; i++) {
            assert_int_equal(data[i], 0xA5);
        }
        memset(data, 0, sizeof data);
        pfe_codec_raw_put(data, sig, 0xFFFFFFFFUL); /* masked to the length */
        assert_int_equal(pfe_codec_raw_get(data, sig), (sig->length == 32U) ? 0xFFFFFFFFUL
                                                                              : ((1UL << sig->length) - 1UL));
    }
}

/* Signals of any position, including across the middle of the payload,
 * where the codec splits it into two 32-bit words. `field` is the payload
 * with the signal's bits set and no other. */
static void check_put_get(uint32_t start_bit, uint32_t length, uint32_t raw, const uint8_t expected[8],
                          const uint8_t field[8])
{
    pfe_codec_signal_t sig;
    memset(&sig, 0, sizeof sig);
    sig.start_bit = (uint8_t)start_bit;
    sig.length = (uint8_t)length;
    uint8_t data[8];
    memset(data, 0, sizeof data);
    pfe_codec_raw_put(data, &sig, raw);
    assert_memory_equal(data, expected, 8U);
    assert_int_equal(pfe_codec_raw_get(data, &sig), raw);
    /* clearing the signal in a payload of ones leaves every other bit set */
    memset(data, 0xFF, sizeof data);
    pfe_codec_raw_put(data, &sig, 0U);
    for (uint32_t i = 0U; i < 8U; i++) {
        assert_int_equal(data[i], (uint8_t)~field[i]);
    }
    assert_int_equal(pfe_codec_raw_get(data, &sig), 0U);
    pfe_codec_raw_put(data, &sig, raw);
    assert_int_equal(pfe_codec_raw_get(data, &sig), raw);
}

static void test_raw_put_get_any_position(void **state)
{
    (void)state;
    static const uint8_t lo32[8] = {0x78, 0x56, 0x34, 0x12, 0x00, 0x00, 0x00, 0x00};
    static const uint8_t lo32_field[8] = {0xFF, 0xFF, 0xFF, 0xFF, 0x00, 0x00, 0x00, 0x00};
    check_put_get(0U, 32U, 0x12345678UL, lo32, lo32_field);
    static const uint8_t hi32[8] = {0x00, 0x00, 0x00, 0x00, 0xEF, 0xCD, 0xAB, 0x89};
    static const uint8_t hi32_field[8] = {0x00, 0x00, 0x00, 0x00, 0xFF, 0xFF, 0xFF, 0xFF};
    check_put_get(32U, 32U, 0x89ABCDEFUL, hi32, hi32_field);
    /* bit 31 and bit 32: the top of byte 3 and the bottom of byte 4 */
    static const uint8_t mid2[8] = {0x00, 0x00, 0x00, 0x80, 0x01, 0x00, 0x00, 0x00};
    check_put_get(31U, 2U, 3U, mid2, mid2);
    /* 0xABCDEF << 20 = 0x0ABCDEF00000, 0xFFFFFF << 20 = 0x0FFFFFF00000 */
    static const uint8_t mid24[8] = {0x00, 0x00, 0xF0, 0xDE, 0xBC, 0x0A, 0x00, 0x00};
    static const uint8_t mid24_field[8] = {0x00, 0x00, 0xF0, 0xFF, 0xFF, 0x0F, 0x00, 0x00};
    check_put_get(20U, 24U, 0xABCDEFUL, mid24, mid24_field);
    static const uint8_t from1[8] = {0xFE, 0xFF, 0xFF, 0xFF, 0x01, 0x00, 0x00, 0x00};
    check_put_get(1U, 32U, 0xFFFFFFFFUL, from1, from1);
    static const uint8_t top31[8] = {0x00, 0x00, 0x00, 0x00, 0xFE, 0xFF, 0xFF, 0xFF};
    check_put_get(33U, 31U, 0x7FFFFFFFUL, top31, top31);
    static const uint8_t bit63[8] = {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80};
    check_put_get(63U, 1U, 1U, bit63, bit63);
    static const uint8_t bit0[8] = {0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00};
    check_put_get(0U, 1U, 1U, bit0, bit0);
    /* signals that do not fit: get reads 0, put changes nothing */
    static const uint8_t shapes[3][2] = {{0U, 0U}, {0U, 33U}, {40U, 25U}};
    for (uint32_t k = 0U; k < 3U; k++) {
        pfe_codec_signal_t sig;
        memset(&sig, 0, sizeof sig);
        sig.start_bit = shapes[k][0];
        sig.length = shapes[k][1];
        uint8_t data[8];
        memset(data, 0x5A, sizeof data);
        assert_int_equal(pfe_codec_raw_get(data, &sig), 0U);
        pfe_codec_raw_put(data, &sig, 0U);
        for (uint32_t i = 0U; i < 8U; i++) {
            assert_int_equal(data[i], 0x5A);
        }
    }
}

static void test_j1939_ranges_by_length(void **state)
{
    (void)state;
    const pfe_codec_signal_t *s8 = &pfe_codec_signals[PFE_CSIG_ST_RX_FRAMES_DROPPED];
    const pfe_codec_signal_t *s16 = &pfe_codec_signals[PFE_CSIG_CCVS1_WHEEL_BASED_VEHICLE_SPEED];
    const pfe_codec_signal_t *s32 = &pfe_codec_signals[PFE_CSIG_HRLFC_TOTAL_FUEL_USED];
    /* 1 byte: FB parameter-specific, FC-FD reserved, FE error, FF not available */
    assert_int_equal(pfe_codec_raw_state(s8, 0xFAU), OK_);
    assert_int_equal(pfe_codec_raw_state(s8, 0xFBU), OOR);
    assert_int_equal(pfe_codec_raw_state(s8, 0xFCU), OOR);
    assert_int_equal(pfe_codec_raw_state(s8, 0xFDU), OOR);
    assert_int_equal(pfe_codec_raw_state(s8, 0xFEU), ERR);
    assert_int_equal(pfe_codec_raw_state(s8, 0xFFU), NA);
    /* 2 bytes */
    assert_int_equal(pfe_codec_raw_state(s16, 0xFAFFU), OK_);
    assert_int_equal(pfe_codec_raw_state(s16, 0xFB00U), OOR);
    assert_int_equal(pfe_codec_raw_state(s16, 0xFBFFU), OOR);
    assert_int_equal(pfe_codec_raw_state(s16, 0xFC00U), OOR);
    assert_int_equal(pfe_codec_raw_state(s16, 0xFDFFU), OOR);
    assert_int_equal(pfe_codec_raw_state(s16, 0xFE00U), ERR);
    assert_int_equal(pfe_codec_raw_state(s16, 0xFEFFU), ERR);
    assert_int_equal(pfe_codec_raw_state(s16, 0xFF00U), NA);
    assert_int_equal(pfe_codec_raw_state(s16, 0xFFFFU), NA);
    /* 4 bytes */
    assert_int_equal(pfe_codec_raw_state(s32, 0xFAFFFFFFUL), OK_);
    assert_int_equal(pfe_codec_raw_state(s32, 0xFB000000UL), OOR);
    assert_int_equal(pfe_codec_raw_state(s32, 0xFDFFFFFFUL), OOR);
    assert_int_equal(pfe_codec_raw_state(s32, 0xFE000000UL), ERR);
    assert_int_equal(pfe_codec_raw_state(s32, 0xFEFFFFFFUL), ERR);
    assert_int_equal(pfe_codec_raw_state(s32, 0xFF000000UL), NA);
    assert_int_equal(pfe_codec_raw_state(s32, 0xFFFFFFFFUL), NA);
    assert_int_equal(pfe_codec_raw_state(NULL, 0U), NA);
}

/* ------------------------------------------------------------ CCVS1 */

static void test_ccvs1_decode(void **state)
{
    (void)state;
    pfe_msg_ccvs1_t m;
    /* 90 km/h = 23040 / 256 km/h: bytes 2-3 = 0x00 0x5A -> 25000 mm/s */
    pfe_can_frame_t f = frame8(0x98FEF100UL, 0xFF, 0x00, 0x5A, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    memset(&m, 0xA5, sizeof m);
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_OK);
    assert_int_equal(m.speed_mm_s.state, OK_);
    assert_int_equal(m.speed_mm_s.value, 25000);
    /* 1/256 km/h = 1.085 mm/s -> 1 */
    f.data[1] = 0x01;
    f.data[2] = 0x00;
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_OK);
    assert_int_equal(m.speed_mm_s.value, 1);
    /* 288 / 256 km/h = 312.5 mm/s: halves round up */
    f.data[1] = 0x20;
    f.data[2] = 0x01;
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_OK);
    assert_int_equal(m.speed_mm_s.value, 313);
    /* 0 */
    f.data[1] = 0x00;
    f.data[2] = 0x00;
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_OK);
    assert_int_equal(m.speed_mm_s.state, OK_);
    assert_int_equal(m.speed_mm_s.value, 0);
    /* valid max 0xFAFF = 250.996 km/h = 69721.14 mm/s */
    f.data[1] = 0xFF;
    f.data[2] = 0xFA;
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_OK);
    assert_int_equal(m.speed_mm_s.state, OK_);
    assert_int_equal(m.speed_mm_s.value, 69721);
    /* max + 1: parameter-specific */
    f.data[1] = 0x00;
    f.data[2] = 0xFB;
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_OK);
    assert_int_equal(m.speed_mm_s.state, OOR);
    assert_int_equal(m.speed_mm_s.value, 0);
    /* error and not available */
    f.data[2] = 0xFE;
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_OK);
    assert_int_equal(m.speed_mm_s.state, ERR);
    f.data[1] = 0xFF;
    f.data[2] = 0xFF;
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_OK);
    assert_int_equal(m.speed_mm_s.state, NA);
    /* any priority and source address */
    f = frame8(0x8CFEF1C3UL, 0xFF, 0x00, 0x5A, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_OK);
    assert_int_equal(m.speed_mm_s.value, 25000);
}

static void test_decoders_reject_wrong_frames(void **state)
{
    (void)state;
    pfe_msg_ccvs1_t m;
    pfe_can_frame_t f = frame8(0x98FEF100UL, 0xFF, 0x00, 0x5A, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    f.dlc = 7U;
    memset(&m, 0xA5, sizeof m);
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_CODEC_EDLC);
    assert_int_equal(m.speed_mm_s.state, NA);
    assert_int_equal(m.speed_mm_s.value, 0);
    f.dlc = 0U;
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_CODEC_EDLC);
    f.dlc = 8U;
    f.id = 0x18FEF100UL; /* no EFF flag */
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_CODEC_EID);
    f.id = 0x98FEF200UL; /* LFE1 */
    assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_CODEC_EID);
    assert_int_equal(pfe_codec_decode_ccvs1(NULL, &m), PFE_EINVAL);
    f.id = 0x98FEF100UL;
    assert_int_equal(pfe_codec_decode_ccvs1(&f, NULL), PFE_EINVAL);

    /* each decoder checks its own PGN and DLC */
    pfe_msg_ssi_t ssi;
    pfe_msg_platoon_config_t pc;
    pfe_msg_grade_preview_t gp;
    pfe_msg_lfe1_t lfe;
    pfe_msg_platoon_fuel_t pf;
    pfe_msg_hrlfc_t hr;
    pfe_msg_fuel_prediction_t fp;
    pfe_msg_status_t st;
    pfe_j1939_name_t name;
    pfe_msg_request_t rq;
    f = frame8(0x8CF01300UL, 0, 0, 0, 0, 0, 0, 0, 0);
    f.dlc = 4U;
    assert_int_equal(pfe_codec_decode_ssi(&f, &ssi), PFE_CODEC_EDLC);
    assert_int_equal(ssi.pitch_udeg.state, NA);
    assert_int_equal(ssi.pitch_fom.state, NA);
    f.id = 0x98FF0000UL;
    assert_int_equal(pfe_codec_decode_platoon_config(&f, &pc), PFE_CODEC_EDLC);
    assert_int_equal(pc.set_speed_mm_s.state, NA);
    f.id = 0x98FF0100UL;
    assert_int_equal(pfe_codec_decode_grade_preview(&f, &gp), PFE_CODEC_EDLC);
    f.id = 0x98FEF28CUL;
    assert_int_equal(pfe_codec_decode_lfe1(&f, &lfe), PFE_CODEC_EDLC);
    f.id = 0x98FF028CUL;
    assert_int_equal(pfe_codec_decode_platoon_fuel(&f, &pf), PFE_CODEC_EDLC);
    f.id = 0x98FD098CUL;
    assert_int_equal(pfe_codec_decode_hrlfc(&f, &hr), PFE_CODEC_EDLC);
    f.id = 0x98FF038CUL;
    assert_int_equal(pfe_codec_decode_fuel_prediction(&f, &fp), PFE_CODEC_EDLC);
    f.id = 0x98FF048CUL;
    assert_int_equal(pfe_codec_decode_status(&f, &st), PFE_CODEC_EDLC);
    assert_int_equal(st.speed_input, NA);
    f.id = 0x98EEFF8CUL;
    assert_int_equal(pfe_codec_decode_address_claimed(&f, &name), PFE_CODEC_EDLC);
    f.id = 0x98EA8C00UL;
    assert_int_equal(pfe_codec_decode_request(&f, &rq), PFE_CODEC_EDLC); /* 4 bytes */
    f.dlc = 8U;
    assert_int_equal(pfe_codec_decode_request(&f, &rq), PFE_CODEC_EDLC); /* padded to 8 */
    f.dlc = 3U;
    assert_int_equal(pfe_codec_decode_request(&f, &rq), PFE_OK);
    f.id = 0x98FEF100UL;
    assert_int_equal(pfe_codec_decode_request(&f, &rq), PFE_CODEC_EID);
    assert_int_equal(pfe_codec_decode_ssi(&f, &ssi), PFE_CODEC_EID);
}

static void test_ccvs1_encode(void **state)
{
    (void)state;
    pfe_can_frame_t f = poisoned_frame();
    pfe_msg_ccvs1_t in = {{25000, OK_}};
    assert_int_equal(pfe_codec_encode_ccvs1(&f, &in, 0x17U), 0);
    assert_int_equal(f.id, 0x98FEF117UL);
    assert_int_equal(f.dlc, 8);
    assert_payload(&f, 0xFF, 0x00, 0x5A, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    /* 1 mm/s = 0.92 / 256 km/h -> 1; 0 -> 0 */
    in.speed_mm_s.value = 1;
    assert_int_equal(pfe_codec_encode_ccvs1(&f, &in, 0U), 0);
    assert_payload(&f, 0xFF, 0x01, 0x00, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    /* above the valid range: clamped to 0xFAFF, and reported */
    in.speed_mm_s.value = 70000;
    assert_int_equal(pfe_codec_encode_ccvs1(&f, &in, 0U), 0x1);
    assert_payload(&f, 0xFF, 0xFF, 0xFA, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    in.speed_mm_s.value = -5;
    assert_int_equal(pfe_codec_encode_ccvs1(&f, &in, 0U), 0x1);
    assert_payload(&f, 0xFF, 0x00, 0x00, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    /* an out-of-range input is clamped too */
    in.speed_mm_s = (pfe_sig_i32_t){INT32_MAX, OOR};
    assert_int_equal(pfe_codec_encode_ccvs1(&f, &in, 0U), 0x1);
    assert_payload(&f, 0xFF, 0xFF, 0xFA, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    /* not available, error */
    in.speed_mm_s = (pfe_sig_i32_t){25000, NA};
    assert_int_equal(pfe_codec_encode_ccvs1(&f, &in, 0U), 0);
    assert_payload(&f, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    in.speed_mm_s.state = ERR;
    assert_int_equal(pfe_codec_encode_ccvs1(&f, &in, 0U), 0);
    assert_payload(&f, 0xFF, 0xFF, 0xFE, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_encode_ccvs1(NULL, &in, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_ccvs1(&f, NULL, 0U), PFE_EINVAL);
}

/* Every valid raw speed survives raw -> mm/s -> raw unchanged. */
static void test_ccvs1_round_trip_every_raw(void **state)
{
    (void)state;
    pfe_can_frame_t f = frame8(0x98FEF100UL, 0xFF, 0, 0, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    pfe_can_frame_t g;
    pfe_msg_ccvs1_t m;
    for (uint32_t raw = 0U; raw <= 0xFAFFU; raw++) {
        f.data[1] = (uint8_t)raw;
        f.data[2] = (uint8_t)(raw >> 8);
        assert_int_equal(pfe_codec_decode_ccvs1(&f, &m), PFE_OK);
        assert_int_equal(pfe_codec_encode_ccvs1(&g, &m, 0U), 0);
        if (memcmp(f.data, g.data, 8U) != 0) {
            fail_msg("raw %u came back as %u", (unsigned)raw, (unsigned)(g.data[1] | (g.data[2] << 8)));
        }
    }
}

/* ------------------------------------------------------------ SSI and grade */

static void test_ssi_decode_encode(void **state)
{
    (void)state;
    pfe_msg_ssi_t m;
    /* pitch raw 0x7D00 = 32000 -> 0 deg; roll raw 0 -> -64 deg; FOM 0 (byte 7 = 0xFC) */
    pfe_can_frame_t f = frame8(0x8CF01300UL, 0x00, 0x7D, 0x00, 0x00, 0xFF, 0xFF, 0xFC, 0xFF);
    memset(&m, 0xA5, sizeof m);
    assert_int_equal(pfe_codec_decode_ssi(&f, &m), PFE_OK);
    assert_int_equal(m.pitch_udeg.state, OK_);
    assert_int_equal(m.pitch_udeg.value, 0);
    assert_int_equal(m.roll_udeg.state, OK_);
    assert_int_equal(m.roll_udeg.value, -64000000);
    assert_int_equal(m.pitch_fom.state, OK_);
    assert_int_equal(m.pitch_fom.value, PFE_SSI_FOM_FULLY_FUNCTIONAL);
    /* pitch max 0xFAFF -> 64.51 deg; roll 0xFB00 out of range; FOM 01 degraded */
    f = frame8(0x8CF01300UL, 0xFF, 0xFA, 0x00, 0xFB, 0xFF, 0xFF, 0xFD, 0xFF);
    assert_int_equal(pfe_codec_decode_ssi(&f, &m), PFE_OK);
    assert_int_equal(m.pitch_udeg.value, 64510000);
    assert_int_equal(m.roll_udeg.state, OOR);
    assert_int_equal(m.pitch_fom.value, PFE_SSI_FOM_DEGRADED);
    /* pitch error, roll not available, FOM 10 error then 11 not available */
    f = frame8(0x8CF01300UL, 0x00, 0xFE, 0xFF, 0xFF, 0xFF, 0xFF, 0xFE, 0xFF);
    assert_int_equal(pfe_codec_decode_ssi(&f, &m), PFE_OK);
    assert_int_equal(m.pitch_udeg.state, ERR);
    assert_int_equal(m.roll_udeg.state, NA);
    assert_int_equal(m.pitch_fom.state, ERR);
    f.data[6] = 0xFF;
    assert_int_equal(pfe_codec_decode_ssi(&f, &m), PFE_OK);
    assert_int_equal(m.pitch_fom.state, NA);
    /* 0.002 deg steps: raw 32001 -> 2000 udeg */
    f = frame8(0x8CF013AAUL, 0x01, 0x7D, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_decode_ssi(&f, &m), PFE_OK);
    assert_int_equal(m.pitch_udeg.value, 2000);

    /* encode: 2 deg -> 33000 = 0x80E8; -1.1458 deg -> 31427.1 -> 0x7AC3; FOM degraded */
    pfe_msg_ssi_t in = {{2000000, OK_}, {-1145800, OK_}, {PFE_SSI_FOM_DEGRADED, OK_}};
    f = poisoned_frame();
    assert_int_equal(pfe_codec_encode_ssi(&f, &in, 0x33U), 0);
    assert_int_equal(f.id, 0x8CF01333UL);
    assert_payload(&f, 0xE8, 0x80, 0xC3, 0x7A, 0xFF, 0xFF, 0xFD, 0xFF);
    /* clamps: 70 deg, -70 deg, FOM 3 (the top valid code is 1); pitch rate bytes stay 0xFF */
    in = (pfe_msg_ssi_t){{70000000, OK_}, {-70000000, OK_}, {3U, OK_}};
    assert_int_equal(pfe_codec_encode_ssi(&f, &in, 0U), 0x7);
    assert_payload(&f, 0xFF, 0xFA, 0x00, 0x00, 0xFF, 0xFF, 0xFD, 0xFF);
    in = (pfe_msg_ssi_t){{0, NA}, {0, ERR}, {0U, ERR}};
    assert_int_equal(pfe_codec_encode_ssi(&f, &in, 0U), 0);
    assert_payload(&f, 0xFF, 0xFF, 0xFF, 0xFE, 0xFF, 0xFF, 0xFE, 0xFF);
}

static void assert_grade(int32_t pitch_udeg, int64_t exact_milli_ppm, bool expect_saturated)
{
    bool sat = !expect_saturated;
    const int32_t g = pfe_codec_grade_ppm_from_pitch(pitch_udeg, &sat);
    const int64_t err = ((int64_t)g * 1000) - exact_milli_ppm;
    if ((err > 600) || (err < -600) || (sat != expect_saturated)) {
        fail_msg("pitch %ld udeg: grade %ld ppm (saturated %d), exact %ld.%03ld", (long)pitch_udeg, (long)g,
                 (int)sat, (long)(exact_milli_ppm / 1000), (long)((exact_milli_ppm < 0 ? -exact_milli_ppm
                                                                                    : exact_milli_ppm) % 1000));
    }
}

static void test_grade_from_pitch(void **state)
{
    (void)state;
    bool sat = true;
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(0, &sat), 0);
    assert_false(sat);
    /* 2 %: atan(0.02) = 1.145763 deg; tan(1.1458 deg) = 0.020000649 */
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(1145800, &sat), 20001);
    assert_false(sat);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(-1145800, &sat), -20001);
    assert_false(sat);
    /* 50 %: atan(0.5) = 26.5650512 deg */
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(26565051, &sat), 500000); /* 499999.996 */
    assert_false(sat);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(-26565051, &sat), -500000);
    assert_false(sat);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(26565100, &sat), 500000); /* 500001.07: beyond */
    assert_true(sat);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(-26565100, &sat), -500000);
    assert_true(sat);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(26564000, &sat), 499977); /* 499977.067 */
    assert_false(sat);
    /* far beyond, and the ends of SPN 3318 and of int32 */
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(30000000, &sat), 500000);
    assert_true(sat);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(64510000, &sat), 500000);
    assert_true(sat);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(-64000000, &sat), -500000);
    assert_true(sat);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(INT32_MIN, &sat), -500000);
    assert_true(sat);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(INT32_MAX, NULL), 500000);
    /* accuracy across the range (exact tangents in milli-ppm) */
    assert_grade(2000, 34907, false);             /* one SPN 3318 step */
    assert_grade(5000, 87266, false);
    assert_grade(500000, 8726868, false);
    assert_grade(1000000, 17455065, false);
    assert_grade(3000000, 52407779, false);
    assert_grade(7777777, 136587839, false);
    assert_grade(10000000, 176326981, false);
    assert_grade(12345678, 218870537, false);
    assert_grade(-15000000, -267949192, false);
    assert_grade(20000000, 363970234, false);
    assert_grade(25000000, 466307658, false);
    assert_grade(-26000000, -487732589, false);
    assert_grade(26500000, 498581608, false);
    /* odd symmetry */
    for (int32_t u = 0; u <= 26565051; u += 1234567) {
        assert_int_equal(pfe_codec_grade_ppm_from_pitch(-u, NULL), -pfe_codec_grade_ppm_from_pitch(u, NULL));
    }
    /* monotonic over SPN 3318 steps up to 50 % */
    int32_t prev = -1;
    for (int32_t u = 0; u <= 26564000; u += 2000) {
        const int32_t g = pfe_codec_grade_ppm_from_pitch(u, NULL);
        ASSERT_GE(g, prev);
        prev = g;
    }
}

/* tan x in double precision for |x| <= 0.5: sine and cosine by their Taylor
 * series to x^25 and x^24 (the first terms left out are below 1e-23 there),
 * then their ratio: a few units in the last place of the exact tangent.
 * The unit tests link no libm; tests/host/test_dbc_codec.c checks the codec
 * against libm's tan() as well, at every SPN 3318 value. */
static double ref_tan(double x)
{
    /* 1 / ((2k)(2k + 1)) and 1 / ((2k - 1)(2k)), k = 1 .. 12 */
    static const double sin_inv[12] = {1.0 / 6.0,   1.0 / 20.0,  1.0 / 42.0,  1.0 / 72.0,
                                       1.0 / 110.0, 1.0 / 156.0, 1.0 / 210.0, 1.0 / 272.0,
                                       1.0 / 342.0, 1.0 / 420.0, 1.0 / 506.0, 1.0 / 600.0};
    static const double cos_inv[12] = {1.0 / 2.0,   1.0 / 12.0,  1.0 / 30.0,  1.0 / 56.0,
                                       1.0 / 90.0,  1.0 / 132.0, 1.0 / 182.0, 1.0 / 240.0,
                                       1.0 / 306.0, 1.0 / 380.0, 1.0 / 462.0, 1.0 / 552.0};
    const double x2 = x * x;
    double s = 1.0;
    double c = 1.0;
    for (uint32_t k = 12U; k > 0U; k--) {
        s = 1.0 - (x2 * s * sin_inv[k - 1U]);
        c = 1.0 - (x2 * c * cos_inv[k - 1U]);
    }
    return (x * s) / c;
}

static double ref_grade_ppm(int32_t pitch_udeg)
{
    const double pi = 3.14159265358979323846;
    return ref_tan((double)pitch_udeg * (pi / 180e6)) * 1e6;
}

static double abs_d(double v)
{
    return (v < 0.0) ? -v : v;
}

/* Worst error over the whole valid range: 0.5010 ppm, measured at every
 * micro-degree of 0 .. 26565051 against long double tanl() (0.5 of it is
 * the rounding to whole ppm, 0.0012 the series and its fixed point). */
#define GRADE_WORST_ERROR_PPM 0.501

static void test_grade_from_pitch_against_double(void **state)
{
    (void)state;
    /* the reference against 40-digit tangents (ppm) */
    static const struct {
        int32_t pitch_udeg;
        double exact_ppm;
    } known[] = {
        {28, 0.4886921905584512},        {29, 0.5061454830783988},
        {1145800, 20000.648855647392},   {13000000, 230868.19112556311},
        {20000000, 363970.23426620236},  {24609319, 458032.50093660603},
        {26382906, 496032.50171777650},  {26565051, 499999.99613675757},
    };
    for (uint32_t k = 0U; k < sizeof known / sizeof known[0]; k++) {
        const double r = ref_grade_ppm(known[k].pitch_udeg);
        ASSERT_NEAR(r, known[k].exact_ppm, 1e-9 * known[k].exact_ppm);
    }
    /* hand-computed results: rounding to whole ppm, either side of a half */
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(28, NULL), 0);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(29, NULL), 1);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(-29, NULL), -1);
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(13000000, NULL), 230868);
    /* 496032.5017: 0.0017 above the half, rounds up */
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(26382906, NULL), 496033);
    /* 458032.50094: the worst point, whose fixed-point value (0.0012 low at
     * most) lies just below the half */
    assert_int_equal(pfe_codec_grade_ppm_from_pitch(24609319, NULL), 458032);

    /* Every SPN 3318 value (0.002 deg) up to 50 %, and a 1999 udeg stride
     * between them, both signs. */
    double worst = 0.0;
    for (uint32_t pass = 0U; pass < 2U; pass++) {
        const int32_t step = (pass == 0U) ? 2000 : 1999;
        for (int32_t u = 0; u <= 26565051; u += step) {
            bool sat = true;
            const int32_t g = pfe_codec_grade_ppm_from_pitch(u, &sat);
            const double err = abs_d((double)g - ref_grade_ppm(u));
            worst = (err > worst) ? err : worst;
            if ((err > GRADE_WORST_ERROR_PPM) || sat) {
                fail_msg("pitch %ld udeg: %ld ppm, saturated %d", (long)u, (long)g, (int)sat);
            }
            assert_int_equal(pfe_codec_grade_ppm_from_pitch(-u, NULL), -g);
        }
    }
    print_message("grade from pitch: worst error %ld.%04ld ppm against double\n", (long)worst,
                  (long)((worst - (double)(long)worst) * 10000.0));
}

/* ------------------------------------------------------------ PFE_PlatoonConfig */

static void test_platoon_config(void **state)
{
    (void)state;
    pfe_msg_platoon_config_t m;
    /* 5 trucks, position 2, gap 10.00 m, time gap 0.400 s, set speed 90 km/h */
    pfe_can_frame_t f = frame8(0x98FF0021UL, 0x05, 0x02, 0xE8, 0x03, 0x90, 0x01, 0x00, 0x5A);
    memset(&m, 0xA5, sizeof m);
    assert_int_equal(pfe_codec_decode_platoon_config(&f, &m), PFE_OK);
    assert_int_equal(m.n_vehicles.state, OK_);
    assert_int_equal(m.n_vehicles.value, 5);
    assert_int_equal(m.own_position.state, OK_);
    assert_int_equal(m.own_position.value, 2);
    assert_int_equal(m.gap_mm.value, 10000);
    assert_int_equal(m.time_gap_ms.value, 400);
    assert_int_equal(m.set_speed_mm_s.value, 25000);
    uint32_t gap_mm = 1U;
    assert_int_equal(pfe_codec_platoon_gap_mm(&m, &gap_mm), OK_);
    assert_int_equal(gap_mm, 10000);
    /* gap not available: time gap x set speed = 0.4 s x 25 m/s */
    f.data[2] = 0xFF;
    f.data[3] = 0xFF;
    assert_int_equal(pfe_codec_decode_platoon_config(&f, &m), PFE_OK);
    assert_int_equal(m.gap_mm.state, NA);
    assert_int_equal(pfe_codec_platoon_gap_mm(&m, &gap_mm), OK_);
    assert_int_equal(gap_mm, 10000);
    /* 0.333 s x 25 m/s = 8.325 m */
    f.data[4] = 0x4D;
    f.data[5] = 0x01;
    assert_int_equal(pfe_codec_decode_platoon_config(&f, &m), PFE_OK);
    assert_int_equal(pfe_codec_platoon_gap_mm(&m, &gap_mm), OK_);
    assert_int_equal(gap_mm, 8325);
    /* neither: not available */
    f.data[4] = 0xFF;
    f.data[5] = 0xFF;
    assert_int_equal(pfe_codec_decode_platoon_config(&f, &m), PFE_OK);
    assert_int_equal(pfe_codec_platoon_gap_mm(&m, &gap_mm), NA);
    assert_int_equal(gap_mm, 0);
    /* time gap valid but set speed in error */
    f = frame8(0x98FF0000UL, 0x05, 0x02, 0xFF, 0xFF, 0x90, 0x01, 0x00, 0xFE);
    assert_int_equal(pfe_codec_decode_platoon_config(&f, &m), PFE_OK);
    assert_int_equal(m.set_speed_mm_s.state, ERR);
    assert_int_equal(pfe_codec_platoon_gap_mm(&m, &gap_mm), NA);
    assert_int_equal(pfe_codec_platoon_gap_mm(NULL, &gap_mm), NA);
    assert_int_equal(pfe_codec_platoon_gap_mm(&m, NULL), NA);

    /* boundaries: 0 trucks, 32 trucks at position 31, 33 trucks, position out of the platoon */
    f = frame8(0x98FF0000UL, 0x00, 0x00, 0xFF, 0xFA, 0xFF, 0xFA, 0xFF, 0xFA);
    assert_int_equal(pfe_codec_decode_platoon_config(&f, &m), PFE_OK);
    assert_int_equal(m.n_vehicles.state, OOR);
    assert_int_equal(m.own_position.state, OK_);
    assert_int_equal(m.gap_mm.value, 642550);         /* 642.55 m */
    assert_int_equal(m.time_gap_ms.value, 64255);     /* 64.255 s */
    assert_int_equal(m.set_speed_mm_s.value, 69721);
    f = frame8(0x98FF0000UL, 0x20, 0x1F, 0x00, 0xFB, 0x00, 0xFB, 0x00, 0xFB);
    assert_int_equal(pfe_codec_decode_platoon_config(&f, &m), PFE_OK);
    assert_int_equal(m.n_vehicles.value, 32);
    assert_int_equal(m.own_position.state, OK_);
    assert_int_equal(m.own_position.value, 31);
    assert_int_equal(m.gap_mm.state, OOR);
    assert_int_equal(m.time_gap_ms.state, OOR);
    assert_int_equal(m.set_speed_mm_s.state, OOR);
    f = frame8(0x98FF0000UL, 0x21, 0x20, 0x00, 0xFE, 0x00, 0xFF, 0x00, 0x00);
    assert_int_equal(pfe_codec_decode_platoon_config(&f, &m), PFE_OK);
    assert_int_equal(m.n_vehicles.state, OOR);
    assert_int_equal(m.own_position.state, OOR);
    assert_int_equal(m.gap_mm.state, ERR);
    assert_int_equal(m.time_gap_ms.state, NA);
    f = frame8(0x98FF0000UL, 0x05, 0x05, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00);
    assert_int_equal(pfe_codec_decode_platoon_config(&f, &m), PFE_OK);
    assert_int_equal(m.own_position.state, OOR);      /* position 5 of 5 trucks */
    f = frame8(0x98FF0000UL, 0xFE, 0xFF, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00);
    assert_int_equal(pfe_codec_decode_platoon_config(&f, &m), PFE_OK);
    assert_int_equal(m.n_vehicles.state, ERR);
    assert_int_equal(m.own_position.state, NA);
    f.data[0] = 0xFB;
    f.data[1] = 0xFC;
    assert_int_equal(pfe_codec_decode_platoon_config(&f, &m), PFE_OK);
    assert_int_equal(m.n_vehicles.state, OOR);
    assert_int_equal(m.own_position.state, OOR);

    /* encode, and clamping of each signal (bits 0..4) */
    pfe_msg_platoon_config_t in = {{5U, OK_}, {2U, OK_}, {10000U, OK_}, {0U, NA}, {25000, OK_}};
    f = poisoned_frame();
    assert_int_equal(pfe_codec_encode_platoon_config(&f, &in, 0x21U), 0);
    assert_int_equal(f.id, 0x98FF0021UL);
    assert_payload(&f, 0x05, 0x02, 0xE8, 0x03, 0xFF, 0xFF, 0x00, 0x5A);
    in = (pfe_msg_platoon_config_t){{40U, OK_}, {40U, OK_}, {700000U, OK_}, {70000U, OK_}, {80000, OK_}};
    assert_int_equal(pfe_codec_encode_platoon_config(&f, &in, 0U), 0x1F);
    assert_payload(&f, 0x20, 0x1F, 0xFF, 0xFA, 0xFF, 0xFA, 0xFF, 0xFA);
    in = (pfe_msg_platoon_config_t){{0U, OK_}, {0U, ERR}, {5U, OK_}, {400U, ERR}, {0, NA}};
    assert_int_equal(pfe_codec_encode_platoon_config(&f, &in, 0U), 0x1); /* 0 trucks -> 1 */
    assert_payload(&f, 0x01, 0xFE, 0x01, 0x00, 0xFF, 0xFE, 0xFF, 0xFF); /* 5 mm -> 0.01 m (halves up) */
}

/* ------------------------------------------------------------ PFE_GradePreview */

static void test_grade_preview_frames(void **state)
{
    (void)state;
    pfe_msg_grade_preview_t m;
    /* header: type 0, id 5, 1000 samples, 12 m */
    pfe_can_frame_t f = frame8(0x98FF0100UL, 0xD4, 0xE8, 0x03, 0x0C, 0xFF, 0xFF, 0xFF, 0xFF);
    memset(&m, 0xA5, sizeof m);
    assert_int_equal(pfe_codec_decode_grade_preview(&f, &m), PFE_OK);
    assert_int_equal(m.frame_type.value, PFE_PREVIEW_FRAME_HEADER);
    assert_int_equal(m.preview_id.value, 5);
    assert_int_equal(m.sample_count.state, OK_);
    assert_int_equal(m.sample_count.value, 1000);
    assert_int_equal(m.spacing_m.value, 12);
    assert_int_equal(m.first_index.state, NA);        /* other multiplexer value */
    assert_int_equal(m.grade_ppm[0].state, NA);
    /* data: type 1, id 5, index 3; +2 %, 0 %, -3 % */
    f = frame8(0x98FF0100UL, 0xD5, 0x00, 0xE8, 0x80, 0x00, 0x7D, 0x24, 0x77);
    assert_int_equal(pfe_codec_decode_grade_preview(&f, &m), PFE_OK);
    assert_int_equal(m.frame_type.value, PFE_PREVIEW_FRAME_DATA);
    assert_int_equal(m.preview_id.value, 5);
    assert_int_equal(m.first_index.value, 3);
    assert_int_equal(m.grade_ppm[0].value, 20000);
    assert_int_equal(m.grade_ppm[1].value, 0);
    assert_int_equal(m.grade_ppm[2].value, -30000);
    assert_int_equal(m.sample_count.state, NA);
    /* index 999 (bits 6..15), samples at the ends of the range, not available, error */
    f = frame8(0x98FF0100UL, 0xC1, 0xF9, 0x00, 0x00, 0xFF, 0xFA, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_decode_grade_preview(&f, &m), PFE_OK);
    assert_int_equal(m.preview_id.value, 0);
    assert_int_equal(m.first_index.value, 999);
    assert_int_equal(m.grade_ppm[0].value, -640000);
    assert_int_equal(m.grade_ppm[1].value, 645100);
    assert_int_equal(m.grade_ppm[2].state, NA);
    f = frame8(0x98FF0100UL, 0x01, 0xFA, 0x00, 0xFB, 0x00, 0xFE, 0x00, 0xFC);
    assert_int_equal(pfe_codec_decode_grade_preview(&f, &m), PFE_OK);
    assert_int_equal(m.first_index.state, OOR);       /* 1000 */
    assert_int_equal(m.grade_ppm[0].state, OOR);
    assert_int_equal(m.grade_ppm[1].state, ERR);
    assert_int_equal(m.grade_ppm[2].state, OOR);
    /* header limits: 0 and 1001 samples, spacing 0 and 251 */
    f = frame8(0x98FF0100UL, 0xC0, 0x00, 0x00, 0x00, 0xFF, 0xFF, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_decode_grade_preview(&f, &m), PFE_OK);
    assert_int_equal(m.sample_count.state, OOR);
    assert_int_equal(m.spacing_m.state, OOR);
    f = frame8(0x98FF0100UL, 0xC0, 0xE9, 0x03, 0xFB, 0xFF, 0xFF, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_decode_grade_preview(&f, &m), PFE_OK);
    assert_int_equal(m.sample_count.state, OOR);
    assert_int_equal(m.spacing_m.state, OOR);
    f = frame8(0x98FF0100UL, 0xC0, 0x01, 0x00, 0xFA, 0xFF, 0xFF, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_decode_grade_preview(&f, &m), PFE_OK);
    assert_int_equal(m.sample_count.value, 1);
    assert_int_equal(m.spacing_m.value, 250);
    /* frame type 2: out of range, nothing else decoded but the id */
    f.data[0] = 0xC2;
    assert_int_equal(pfe_codec_decode_grade_preview(&f, &m), PFE_OK);
    assert_int_equal(m.frame_type.state, OOR);
    assert_int_equal(m.sample_count.state, NA);

    /* encode a header and a data frame */
    pfe_msg_grade_preview_t in;
    memset(&in, 0, sizeof in);
    in.frame_type = (pfe_sig_u32_t){PFE_PREVIEW_FRAME_HEADER, OK_};
    in.preview_id = (pfe_sig_u32_t){5U, OK_};
    in.sample_count = (pfe_sig_u32_t){1000U, OK_};
    in.spacing_m = (pfe_sig_u32_t){12U, OK_};
    f = poisoned_frame();
    assert_int_equal(pfe_codec_encode_grade_preview(&f, &in, 0x40U), 0);
    assert_int_equal(f.id, 0x98FF0140UL);
    assert_payload(&f, 0xD4, 0xE8, 0x03, 0x0C, 0xFF, 0xFF, 0xFF, 0xFF);
    in.frame_type.value = PFE_PREVIEW_FRAME_DATA;
    in.first_index = (pfe_sig_u32_t){3U, OK_};
    in.grade_ppm[0] = (pfe_sig_i32_t){20000, OK_};
    in.grade_ppm[1] = (pfe_sig_i32_t){0, OK_};
    in.grade_ppm[2] = (pfe_sig_i32_t){-30000, OK_};
    assert_int_equal(pfe_codec_encode_grade_preview(&f, &in, 0x40U), 0);
    assert_payload(&f, 0xD5, 0x00, 0xE8, 0x80, 0x00, 0x7D, 0x24, 0x77);
    /* clamps: index 1000 (bit 4), grade +70 % (bit 5), -65 % (bit 6); 10 ppm rounds up to 1 step */
    in.first_index.value = 1000U;
    in.grade_ppm[0].value = 700000;
    in.grade_ppm[1].value = -650000;
    in.grade_ppm[2] = (pfe_sig_i32_t){10, OK_};
    assert_int_equal(pfe_codec_encode_grade_preview(&f, &in, 0U), 0x70);
    assert_payload(&f, 0xD5, 0xF9, 0xFF, 0xFA, 0x00, 0x00, 0x01, 0x7D);
    in.grade_ppm[0].state = NA;
    in.grade_ppm[1].state = ERR;
    in.first_index.value = 0U;
    in.grade_ppm[2].value = 9; /* 0.45 step: rounds down */
    assert_int_equal(pfe_codec_encode_grade_preview(&f, &in, 0U), 0);
    assert_payload(&f, 0x15, 0x00, 0xFF, 0xFF, 0xFF, 0xFE, 0x00, 0x7D);
    in.frame_type.value = 2U;
    assert_int_equal(pfe_codec_encode_grade_preview(&f, &in, 0U), PFE_EINVAL);
    in.frame_type = (pfe_sig_u32_t){0U, NA};
    assert_int_equal(pfe_codec_encode_grade_preview(&f, &in, 0U), PFE_EINVAL);
}

/* A header with raw fields as given (the encoder would clamp them). */
static pfe_can_frame_t preview_header(uint32_t id, uint32_t count, uint32_t spacing_m)
{
    return frame8(0x98FF0100UL, (uint8_t)(0xC0U | (id << 2)), (uint8_t)count, (uint8_t)(count >> 8),
                  (uint8_t)spacing_m, 0xFF, 0xFF, 0xFF, 0xFF);
}

/* Sample k of the test road: (k * 37 mod 201) - 100 steps of 0.002 % (20 ppm). */
static int32_t road_ppm(uint32_t k)
{
    return (((int32_t)((k * 37U) % 201U)) - 100) * 20;
}

/* A data frame as a sender builds it (the encoder is tested above). */
static pfe_can_frame_t preview_data(uint32_t id, uint32_t first, uint32_t count)
{
    pfe_msg_grade_preview_t in;
    pfe_can_frame_t f;
    memset(&in, 0, sizeof in);
    in.frame_type = (pfe_sig_u32_t){PFE_PREVIEW_FRAME_DATA, OK_};
    in.preview_id = (pfe_sig_u32_t){id, OK_};
    in.first_index = (pfe_sig_u32_t){first, OK_};
    for (uint32_t k = 0U; k < 3U; k++) {
        const uint32_t index = first + k;
        in.grade_ppm[k] = (pfe_sig_i32_t){road_ppm(index), (index < count) ? OK_ : NA};
    }
    (void)pfe_codec_encode_grade_preview(&f, &in, 0U);
    return f;
}

static pfe_preview_t g_pv;

static void test_preview_complete_small(void **state)
{
    (void)state;
    pfe_preview_t *pv = &g_pv;
    memset(pv, 0xA5, sizeof *pv);
    pfe_preview_init(pv);
    assert_int_equal(pv->phase, PFE_PREVIEW_EMPTY);
    int32_t ppm = 1;
    assert_int_equal(pfe_preview_grade_ppm(pv, 0U, &ppm), NA);
    assert_int_equal(ppm, 0);
    pfe_can_frame_t f = preview_header(3U, 7U, 12U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    assert_int_equal(pv->phase, PFE_PREVIEW_RECEIVING);
    assert_int_equal(pv->sample_count, 7);
    assert_int_equal(pv->spacing_m, 12);
    f = preview_data(3U, 0U, 7U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    assert_int_equal(pfe_preview_grade_ppm(pv, 0U, &ppm), NA); /* not complete yet */
    f = preview_data(3U, 3U, 7U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(3U, 6U, 7U); /* one sample, two not available */
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_COMPLETE);
    assert_int_equal(pv->phase, PFE_PREVIEW_READY);
    assert_int_equal(pv->unusable_samples, 0);
    /* road: k = 0..6 -> -100, -63, -26, 11, 48, 85, -79 steps */
    static const int32_t expected[7] = {-2000, -1260, -520, 220, 960, 1700, -1580};
    for (uint32_t k = 0U; k < 7U; k++) {
        assert_int_equal(pfe_preview_grade_ppm(pv, k, &ppm), OK_);
        assert_int_equal(ppm, expected[k]);
    }
    assert_int_equal(pfe_preview_grade_ppm(pv, 7U, &ppm), NA);
    assert_int_equal(pfe_preview_grade_ppm(NULL, 0U, &ppm), NA);
    assert_int_equal(pfe_preview_grade_ppm(pv, 1U, NULL), OK_);
    assert_int_equal(pv->frames_rejected, 0);
    /* a repeat of the last frame after completion is refused; the preview stays */
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_EORDER);
    assert_int_equal(pv->phase, PFE_PREVIEW_READY);
    assert_int_equal(pv->frames_rejected, 1);
}

static void test_preview_complete_1000_samples(void **state)
{
    (void)state;
    pfe_preview_t *pv = &g_pv;
    pfe_preview_init(pv);
    pfe_can_frame_t f = preview_header(15U, 1000U, 12U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    uint32_t frames = 0U;
    for (uint32_t first = 0U; first < 1000U; first += 3U) {
        f = preview_data(15U, first, 1000U);
        const int rc = pfe_preview_push(pv, &f);
        frames++;
        assert_int_equal(rc, (first == 999U) ? PFE_PREVIEW_COMPLETE : PFE_PREVIEW_INCOMPLETE);
    }
    assert_int_equal(frames, 334);
    int32_t ppm;
    assert_int_equal(pfe_preview_grade_ppm(pv, 999U, &ppm), OK_);
    assert_int_equal(ppm, 1600);                      /* 36963 mod 201 = 180: 80 steps */
    assert_int_equal(pfe_preview_grade_ppm(pv, 500U, &ppm), OK_);
    assert_int_equal(ppm, -1840);                     /* 18500 mod 201 = 8: -92 steps */
    for (uint32_t k = 0U; k < 1000U; k++) {
        assert_int_equal(pfe_preview_grade_ppm(pv, k, &ppm), OK_);
        assert_int_equal(ppm, road_ppm(k));
    }
}

static void test_preview_rejects_gaps_and_order(void **state)
{
    (void)state;
    pfe_preview_t *pv = &g_pv;
    pfe_preview_init(pv);
    pfe_can_frame_t f = preview_header(1U, 30U, 10U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(1U, 0U, 30U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    /* frame 3 lost: 6 arrives */
    f = preview_data(1U, 6U, 30U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_EGAP);
    assert_int_equal(pv->phase, PFE_PREVIEW_EMPTY);
    /* the rest of that preview is refused until a new header */
    f = preview_data(1U, 9U, 30U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_ENOHEADER);
    assert_int_equal(pv->frames_rejected, 2);

    /* repeated frame */
    f = preview_header(2U, 30U, 10U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(2U, 0U, 30U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(2U, 3U, 30U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(2U, 3U, 30U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_EORDER);
    assert_int_equal(pv->phase, PFE_PREVIEW_EMPTY);

    /* out of order: 0, 6, 3 (6 is a gap already) and 3, 0 (backwards) */
    f = preview_header(2U, 30U, 10U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(2U, 3U, 30U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_EGAP); /* the first frame was lost */
    f = preview_header(2U, 30U, 10U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(2U, 0U, 30U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(2U, 3U, 30U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(2U, 0U, 30U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_EORDER);

    /* an index that is not a multiple of 3 is a gap or a step back */
    f = preview_header(2U, 30U, 10U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(2U, 1U, 30U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_EGAP);

    /* data frame of another preview (its header was lost) */
    f = preview_header(4U, 30U, 10U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(5U, 0U, 30U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_ENOHEADER);
    assert_int_equal(pv->phase, PFE_PREVIEW_EMPTY);

    /* bad frames: wrong DLC, not our PGN, frame type 3, NULL */
    f = preview_header(6U, 30U, 10U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(6U, 0U, 30U);
    f.dlc = 6U;
    assert_int_equal(pfe_preview_push(pv, &f), PFE_CODEC_EDLC);
    assert_int_equal(pv->phase, PFE_PREVIEW_EMPTY);
    f = preview_data(6U, 0U, 30U);
    f.id = 0x98FF0200UL;
    assert_int_equal(pfe_preview_push(pv, &f), PFE_CODEC_EID);
    f = preview_data(6U, 0U, 30U);
    f.data[0] |= 0x03U;
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_EFIELD);
    assert_int_equal(pfe_preview_push(pv, NULL), PFE_EINVAL);
    assert_int_equal(pfe_preview_push(NULL, &f), PFE_EINVAL);
}

static void test_preview_restart_and_counts(void **state)
{
    (void)state;
    pfe_preview_t *pv = &g_pv;
    pfe_preview_init(pv);
    int32_t ppm;
    /* restart while receiving */
    pfe_can_frame_t f = preview_header(1U, 9U, 20U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(1U, 0U, 9U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_header(2U, 4U, 25U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_RESTARTED);
    assert_int_equal(pv->preview_id, 2);
    assert_int_equal(pv->sample_count, 4);
    assert_int_equal(pv->spacing_m, 25);
    f = preview_data(2U, 0U, 4U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = preview_data(2U, 3U, 4U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_COMPLETE);
    assert_int_equal(pfe_preview_grade_ppm(pv, 3U, &ppm), OK_);
    assert_int_equal(ppm, 220);
    /* a data index past the count of a complete preview: refused, preview kept */
    f = preview_data(2U, 6U, 9U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_EORDER);
    assert_int_equal(pv->phase, PFE_PREVIEW_READY);
    /* invalid headers do not replace a complete preview */
    f = preview_header(3U, 1001U, 25U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_ECOUNT);
    f = preview_header(3U, 0U, 25U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_ECOUNT);
    f = preview_header(3U, 10U, 0U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_ECOUNT);
    assert_int_equal(pv->phase, PFE_PREVIEW_READY);
    assert_int_equal(pfe_preview_grade_ppm(pv, 3U, &ppm), OK_);
    /* a new preview replaces a complete one */
    f = preview_header(3U, 6U, 25U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_RESTARTED);
    assert_int_equal(pfe_preview_grade_ppm(pv, 3U, &ppm), NA);
    /* data beyond the count while receiving */
    f = preview_data(3U, 6U, 9U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_ECOUNT);
    assert_int_equal(pv->phase, PFE_PREVIEW_EMPTY);
    /* samples the sender marks not available inside the count */
    f = preview_header(7U, 3U, 25U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_INCOMPLETE);
    f = frame8(0x98FF0100UL, 0x1D, 0x00, 0xFF, 0xFF, 0x00, 0x7D, 0x00, 0xFE); /* id 7, index 0 */
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_COMPLETE);
    assert_int_equal(pv->unusable_samples, 2);
    assert_int_equal(pfe_preview_grade_ppm(pv, 0U, &ppm), NA);
    assert_int_equal(ppm, 0);
    assert_int_equal(pfe_preview_grade_ppm(pv, 1U, &ppm), OK_);
    assert_int_equal(ppm, 0);
    assert_int_equal(pfe_preview_grade_ppm(pv, 2U, &ppm), ERR);
    /* the rejection counter saturates */
    pv->frames_rejected = UINT32_MAX - 1U;
    f = preview_data(9U, 0U, 3U);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_ENOHEADER);
    assert_int_equal(pfe_preview_push(pv, &f), PFE_PREVIEW_ENOHEADER);
    assert_int_equal(pv->frames_rejected, UINT32_MAX);
}

/* ------------------------------------------------------------ outputs */

static void test_lfe1(void **state)
{
    (void)state;
    pfe_can_frame_t f = poisoned_frame();
    /* 30 L/h = 600 x 0.05 L/h = 8333333.3 nL/s */
    pfe_msg_lfe1_t in = {{8333333U, OK_}};
    assert_int_equal(pfe_codec_encode_lfe1(&f, &in, PFE_CODEC_DEFAULT_ADDRESS), 0);
    assert_int_equal(f.id, 0x98FEF28CUL);
    assert_int_equal(f.dlc, 8);
    assert_payload(&f, 0x58, 0x02, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    /* raw = round(nl_s * 9 / 125000): 6944 -> 0.49997 -> 0, 6945 -> 0.50004 -> 1 */
    in.fuel_rate_nl_s.value = 6944U;
    assert_int_equal(pfe_codec_encode_lfe1(&f, &in, 0x8CU), 0);
    assert_payload(&f, 0x00, 0x00, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    in.fuel_rate_nl_s.value = 6945U;
    assert_int_equal(pfe_codec_encode_lfe1(&f, &in, 0x8CU), 0);
    assert_payload(&f, 0x01, 0x00, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    /* 3212.75 L/h = 892430555.6 nL/s is the top; beyond is clamped */
    in.fuel_rate_nl_s.value = 892430555U;
    assert_int_equal(pfe_codec_encode_lfe1(&f, &in, 0x8CU), 0);
    assert_payload(&f, 0xFF, 0xFA, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    in.fuel_rate_nl_s.value = 892500000U;
    assert_int_equal(pfe_codec_encode_lfe1(&f, &in, 0x8CU), 0x1);
    assert_payload(&f, 0xFF, 0xFA, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    in.fuel_rate_nl_s.value = UINT32_MAX;
    assert_int_equal(pfe_codec_encode_lfe1(&f, &in, 0x8CU), 0x1);
    in.fuel_rate_nl_s.state = NA;
    assert_int_equal(pfe_codec_encode_lfe1(&f, &in, 0x8CU), 0);
    assert_payload(&f, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    in.fuel_rate_nl_s.state = ERR;
    assert_int_equal(pfe_codec_encode_lfe1(&f, &in, 0x8CU), 0);
    assert_payload(&f, 0xFF, 0xFE, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);

    pfe_msg_lfe1_t m;
    f = frame8(0x98FEF28CUL, 0x58, 0x02, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_decode_lfe1(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_rate_nl_s.value, 8333333);
    f.data[0] = 0x01;
    f.data[1] = 0x00;
    assert_int_equal(pfe_codec_decode_lfe1(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_rate_nl_s.value, 13889);  /* 125000 / 9 */
    f.data[0] = 0xFF;
    f.data[1] = 0xFA;
    assert_int_equal(pfe_codec_decode_lfe1(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_rate_nl_s.value, 892430556);
    f.data[1] = 0xFB;
    assert_int_equal(pfe_codec_decode_lfe1(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_rate_nl_s.state, OOR);
    f.data[1] = 0xFF;
    assert_int_equal(pfe_codec_decode_lfe1(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_rate_nl_s.state, NA);
    /* round trip of every raw value */
    pfe_can_frame_t g;
    for (uint32_t raw = 0U; raw <= 0xFAFFU; raw += 7U) {
        f.data[0] = (uint8_t)raw;
        f.data[1] = (uint8_t)(raw >> 8);
        assert_int_equal(pfe_codec_decode_lfe1(&f, &m), PFE_OK);
        assert_int_equal(pfe_codec_encode_lfe1(&g, &m, 0x8CU), 0);
        assert_memory_equal(f.data, g.data, 8U);
    }
}

static void test_platoon_fuel(void **state)
{
    (void)state;
    pfe_can_frame_t f = poisoned_frame();
    /* 150 L/h (raw 3000 = 0x0BB8) and 12345.678 L (raw 0x00BC614E) */
    pfe_msg_platoon_fuel_t in = {{41666667U, OK_}, {12345678000ULL, OK_}};
    assert_int_equal(pfe_codec_encode_platoon_fuel(&f, &in, 0x8CU), 0);
    assert_int_equal(f.id, 0x98FF028CUL);
    assert_payload(&f, 0xB8, 0x0B, 0x4E, 0x61, 0xBC, 0x00, 0xFF, 0xFF);
    /* 0.001 L rounding: 1499 uL -> 1, 1500 uL -> 2 */
    in.fuel_used_ul.value = 1499U;
    assert_int_equal(pfe_codec_encode_platoon_fuel(&f, &in, 0x8CU), 0);
    assert_payload(&f, 0xB8, 0x0B, 0x01, 0x00, 0x00, 0x00, 0xFF, 0xFF);
    in.fuel_used_ul.value = 1500U;
    assert_int_equal(pfe_codec_encode_platoon_fuel(&f, &in, 0x8CU), 0);
    assert_payload(&f, 0xB8, 0x0B, 0x02, 0x00, 0x00, 0x00, 0xFF, 0xFF);
    /* top of the range, clamped beyond (bit 1), and both clamped */
    in.fuel_used_ul.value = 4211081215000ULL;
    assert_int_equal(pfe_codec_encode_platoon_fuel(&f, &in, 0x8CU), 0);
    assert_payload(&f, 0xB8, 0x0B, 0xFF, 0xFF, 0xFF, 0xFA, 0xFF, 0xFF);
    in.fuel_used_ul.value = 4211081215500ULL;
    assert_int_equal(pfe_codec_encode_platoon_fuel(&f, &in, 0x8CU), 0x2);
    in = (pfe_msg_platoon_fuel_t){{UINT32_MAX, OK_}, {UINT64_MAX, OK_}};
    assert_int_equal(pfe_codec_encode_platoon_fuel(&f, &in, 0x8CU), 0x3);
    assert_payload(&f, 0xFF, 0xFA, 0xFF, 0xFF, 0xFF, 0xFA, 0xFF, 0xFF);
    in = (pfe_msg_platoon_fuel_t){{0U, NA}, {0U, ERR}};
    assert_int_equal(pfe_codec_encode_platoon_fuel(&f, &in, 0x8CU), 0);
    assert_payload(&f, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFE, 0xFF, 0xFF);

    pfe_msg_platoon_fuel_t m;
    f = frame8(0x98FF028CUL, 0xB8, 0x0B, 0x4E, 0x61, 0xBC, 0x00, 0xFF, 0xFF);
    memset(&m, 0xA5, sizeof m);
    assert_int_equal(pfe_codec_decode_platoon_fuel(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_rate_nl_s.value, 41666667);
    assert_int_equal(m.fuel_used_ul.value, 12345678000ULL);
    assert_int_equal(m.fuel_used_ul.state, OK_);
    f = frame8(0x98FF028CUL, 0x00, 0x00, 0xFF, 0xFF, 0xFF, 0xFA, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_decode_platoon_fuel(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_rate_nl_s.value, 0);
    assert_int_equal(m.fuel_used_ul.value, 4211081215000ULL);
    f.data[5] = 0xFB;
    assert_int_equal(pfe_codec_decode_platoon_fuel(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_used_ul.state, OOR);
    f.data[5] = 0xFE;
    assert_int_equal(pfe_codec_decode_platoon_fuel(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_used_ul.state, ERR);
    f.data[2] = 0x00; /* 0xFE000000 is error too */
    f.data[3] = 0x00;
    f.data[4] = 0x00;
    assert_int_equal(pfe_codec_decode_platoon_fuel(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_used_ul.state, ERR);
    f.data[5] = 0xFF;
    assert_int_equal(pfe_codec_decode_platoon_fuel(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_used_ul.state, NA);
}

static void test_hrlfc(void **state)
{
    (void)state;
    pfe_can_frame_t f = poisoned_frame();
    /* trip not available; total 1234.567 mL -> 1.235 L (raw 1235 = 0x04D3) */
    pfe_msg_hrlfc_t in = {{0U, NA}, {1234567U, OK_}};
    assert_int_equal(pfe_codec_encode_hrlfc(&f, &in, 0x8CU), 0);
    assert_int_equal(f.id, 0x98FD098CUL);
    assert_payload(&f, 0xFF, 0xFF, 0xFF, 0xFF, 0xD3, 0x04, 0x00, 0x00);
    in.total_fuel_ul.value = 5000000000000ULL; /* 5e6 L: clamped, bit 1 */
    assert_int_equal(pfe_codec_encode_hrlfc(&f, &in, 0x8CU), 0x2);
    assert_payload(&f, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFA);
    in = (pfe_msg_hrlfc_t){{1000U, OK_}, {0U, OK_}};
    assert_int_equal(pfe_codec_encode_hrlfc(&f, &in, 0x8CU), 0);
    assert_payload(&f, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00);

    pfe_msg_hrlfc_t m;
    f = frame8(0x98FD0900UL, 0xFF, 0xFF, 0xFF, 0xFF, 0xD3, 0x04, 0x00, 0x00);
    memset(&m, 0xA5, sizeof m);
    assert_int_equal(pfe_codec_decode_hrlfc(&f, &m), PFE_OK);
    assert_int_equal(m.trip_fuel_ul.state, NA);
    assert_int_equal(m.trip_fuel_ul.value, 0U);
    assert_int_equal(m.total_fuel_ul.state, OK_);
    assert_int_equal(m.total_fuel_ul.value, 1235000U);
    f = frame8(0x98FD0900UL, 0x00, 0x00, 0x00, 0xFB, 0x00, 0x00, 0x00, 0xFE);
    assert_int_equal(pfe_codec_decode_hrlfc(&f, &m), PFE_OK);
    assert_int_equal(m.trip_fuel_ul.state, OOR);
    assert_int_equal(m.total_fuel_ul.state, ERR);
}

static void test_fuel_prediction(void **state)
{
    (void)state;
    pfe_can_frame_t f = poisoned_frame();
    /* until predicted: all not available */
    pfe_msg_fuel_prediction_t in = {{0U, NA}, {0U, NA}, {0U, NA}, {0U, NA}};
    assert_int_equal(pfe_codec_encode_fuel_prediction(&f, &in, 0x8CU), 0);
    assert_int_equal(f.id, 0x98FF038CUL);
    assert_payload(&f, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    /* 21.37 L (2137 = 0x0859), 20.00 L (0x07D0), 23.50 L (0x092E), 480.0 s (4800 = 0x12C0) */
    in = (pfe_msg_fuel_prediction_t){{21370000U, OK_}, {20000000U, OK_}, {23500000U, OK_}, {480000U, OK_}};
    assert_int_equal(pfe_codec_encode_fuel_prediction(&f, &in, 0x8CU), 0);
    assert_payload(&f, 0x59, 0x08, 0xD0, 0x07, 0x2E, 0x09, 0xC0, 0x12);
    /* 700 L and 7000 s are beyond 642.55 L and 6425.5 s */
    in = (pfe_msg_fuel_prediction_t){{700000000U, OK_}, {4999U, OK_}, {5000U, OK_}, {7000000U, OK_}};
    assert_int_equal(pfe_codec_encode_fuel_prediction(&f, &in, 0x8CU), 0x9);
    assert_payload(&f, 0xFF, 0xFA, 0x00, 0x00, 0x01, 0x00, 0xFF, 0xFA);

    pfe_msg_fuel_prediction_t m;
    f = frame8(0x98FF038CUL, 0x59, 0x08, 0xD0, 0x07, 0x2E, 0x09, 0xC0, 0x12);
    memset(&m, 0xA5, sizeof m);
    assert_int_equal(pfe_codec_decode_fuel_prediction(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_ul.value, 21370000);
    assert_int_equal(m.fuel_lower_ul.value, 20000000);
    assert_int_equal(m.fuel_upper_ul.value, 23500000);
    assert_int_equal(m.time_ms.value, 480000);
    f = frame8(0x98FF038CUL, 0xFF, 0xFA, 0x00, 0xFB, 0x00, 0xFE, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_decode_fuel_prediction(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_ul.value, 642550000);
    assert_int_equal(m.fuel_lower_ul.state, OOR);
    assert_int_equal(m.fuel_upper_ul.state, ERR);
    assert_int_equal(m.time_ms.state, NA);
}

/* ------------------------------------------------------------ real-bus inputs and outputs */

/* VDS: altitude 100 m = (100 + 2500) / 0.125 = raw 20800 = 0x5140 in bytes
 * 7-8; bearing 90 deg = raw 11520 = 0x2D00; pitch 0 = raw 25600 = 0x6400. */
static void test_vds(void **state)
{
    (void)state;
    pfe_can_frame_t f = poisoned_frame();
    const pfe_msg_vds_t in = {{90000U, OK_}, {0, NA}, {0, OK_}, {100000, OK_}};
    assert_int_equal(pfe_codec_encode_vds(&f, &in, 0x1CU), 0);
    assert_int_equal(f.id, 0x98FEE81CUL);
    assert_payload(&f, 0x00, 0x2D, 0xFF, 0xFF, 0x00, 0x64, 0x40, 0x51);
    pfe_msg_vds_t m;
    memset(&m, 0xA5, sizeof m);
    assert_int_equal(pfe_codec_decode_vds(&f, &m), PFE_OK);
    assert_int_equal(m.bearing_mdeg.value, 90000);
    assert_int_equal(m.nav_speed_mm_s.state, NA);
    assert_int_equal(m.pitch_mdeg.value, 0);
    assert_int_equal(m.altitude_mm.value, 100000);
    /* raw 0: -2500 m; raw 0xFAFF: 5531.875 m; raw 0xFEFF: error */
    f = frame8(0x98FEE800UL, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x00, 0x00);
    assert_int_equal(pfe_codec_decode_vds(&f, &m), PFE_OK);
    assert_int_equal(m.altitude_mm.value, -2500000);
    f.data[6] = 0xFF;
    f.data[7] = 0xFA;
    assert_int_equal(pfe_codec_decode_vds(&f, &m), PFE_OK);
    assert_int_equal(m.altitude_mm.value, 5531875);
    f.data[7] = 0xFE;
    assert_int_equal(pfe_codec_decode_vds(&f, &m), PFE_OK);
    assert_int_equal(m.altitude_mm.state, ERR);
    f.dlc = 7U;
    assert_int_equal(pfe_codec_decode_vds(&f, &m), PFE_CODEC_EDLC);
}

/* CVW: 12000 kg = raw 1200 = 0x04B0 in bytes 3-4; 8000 kg = 0x0320. */
static void test_cvw(void **state)
{
    (void)state;
    pfe_can_frame_t f = poisoned_frame();
    const pfe_msg_cvw_t in = {{8000U, OK_}, {12000U, OK_}};
    assert_int_equal(pfe_codec_encode_cvw(&f, &in, 0x27U), 0);
    assert_int_equal(f.id, 0x98FE7027UL);
    assert_payload(&f, 0x20, 0x03, 0xB0, 0x04, 0xFF, 0xFF, 0xFF, 0xFF);
    pfe_msg_cvw_t m;
    assert_int_equal(pfe_codec_decode_cvw(&f, &m), PFE_OK);
    assert_int_equal(m.powered_vehicle_kg.value, 8000);
    assert_int_equal(m.gross_combination_kg.value, 12000);
    f.data[3] = 0xFF;
    assert_int_equal(pfe_codec_decode_cvw(&f, &m), PFE_OK);
    assert_int_equal(m.gross_combination_kg.state, NA);
}

/* PFE_OwnFuel: 9291667 nL/s * 9 / 125000 = 669.0 = 0x029D; 1.5 L = 0x05DC;
 * identified: bits 48-49 = 01, the rest of byte 7 ones = 0xFD. */
static void test_own_fuel(void **state)
{
    (void)state;
    pfe_can_frame_t f = poisoned_frame();
    const pfe_msg_own_fuel_t in = {{9291667U, OK_}, {1500000U, OK_}, {1U, OK_}};
    assert_int_equal(pfe_codec_encode_own_fuel(&f, &in, 0x8CU), 0);
    assert_int_equal(f.id, 0x98FF058CUL);
    assert_payload(&f, 0x9D, 0x02, 0xDC, 0x05, 0x00, 0x00, 0xFD, 0xFF);
    pfe_msg_own_fuel_t m;
    assert_int_equal(pfe_codec_decode_own_fuel(&f, &m), PFE_OK);
    assert_int_equal(m.fuel_rate_nl_s.value, 9291667);
    assert_int_equal(m.fuel_used_ul.value, 1500000);
    assert_int_equal(m.model_identified.value, 1);
    const pfe_msg_own_fuel_t na = {{0U, NA}, {0U, OK_}, {0U, OK_}};
    assert_int_equal(pfe_codec_encode_own_fuel(&f, &na, 0x8CU), 0);
    assert_payload(&f, 0xFF, 0xFF, 0x00, 0x00, 0x00, 0x00, 0xFC, 0xFF);
}

/* PFE_InputStatus: speed from 0x00, grade from 0x1C, no fuel-rate sender
 * (0xFF), 2 speed and 1 grade senders (0x12), grade from altitude (1), mass
 * identified (2) and converged (1): byte 6 = 11 01 0010 = 0xD2; 12000 kg =
 * 0x04B0. */
static void test_input_status(void **state)
{
    (void)state;
    pfe_can_frame_t f = poisoned_frame();
    const pfe_msg_input_status_t in = {{0x00U, OK_}, {0x1CU, OK_}, {0U, NA},
                                       {2U, OK_},    {1U, OK_},    {1U, OK_},
                                       {2U, OK_},    {1U, OK_},    {12000U, OK_}};
    assert_int_equal(pfe_codec_encode_input_status(&f, &in, 0x8CU), 0);
    assert_int_equal(f.id, 0x98FF068CUL);
    assert_payload(&f, 0x00, 0x1C, 0xFF, 0x12, 0x01, 0xD2, 0xB0, 0x04);
    pfe_msg_input_status_t m;
    assert_int_equal(pfe_codec_decode_input_status(&f, &m), PFE_OK);
    assert_int_equal(m.grade_source_address.value, 0x1C);
    assert_int_equal(m.fuel_rate_source.state, OOR); /* 255: none */
    assert_int_equal(m.speed_senders.value, 2);
    assert_int_equal(m.mass_source.value, 2);
    assert_int_equal(m.identification.value, 1);
    assert_int_equal(m.vehicle_mass_kg.value, 12000);
}

/* PFE_DeviceStatus: 3 overruns, 1 bus-off, warning on, NVM failing: byte 3 =
 * 01 00 00 01 = 0x41; watchdog reset; TEC 97 = 0x61, REC 5, 2 NVM failures. */
static void test_device_status(void **state)
{
    (void)state;
    pfe_can_frame_t f = poisoned_frame();
    const pfe_msg_device_status_t in = {{3U, OK_}, {1U, OK_}, {1U, OK_}, {0U, OK_}, {0U, OK_},
                                        {1U, OK_}, {1U, OK_}, {97U, OK_}, {5U, OK_}, {2U, OK_}};
    assert_int_equal(pfe_codec_encode_device_status(&f, &in, 0x8CU), 0);
    assert_int_equal(f.id, 0x98FF078CUL);
    assert_payload(&f, 0x03, 0x01, 0x41, 0x01, 0x61, 0x05, 0x02, 0xFF);
    pfe_msg_device_status_t m;
    assert_int_equal(pfe_codec_decode_device_status(&f, &m), PFE_OK);
    assert_int_equal(m.tx_error_counter.value, 97);
    assert_int_equal(m.reset_cause.value, 1);
    assert_int_equal(m.nvm_write_failing.value, 1);
    /* counters clamp at 250 and say so */
    pfe_msg_device_status_t big = in;
    big.tx_error_counter.value = 255U;
    assert_int_equal(pfe_codec_encode_device_status(&f, &big, 0x8CU), 1 << 7);
    assert_int_equal(f.data[4], 0xFA);
}

/* The new messages' decoders and encoders refuse NULL and another PGN. */
static void test_new_messages_refuse_bad_arguments(void **state)
{
    (void)state;
    pfe_can_frame_t f = frame8(0x98FEF100UL, 0, 0, 0, 0, 0, 0, 0, 0); /* CCVS1: another PGN */
    pfe_msg_vds_t vds;
    pfe_msg_cvw_t cvw;
    pfe_msg_own_fuel_t of;
    pfe_msg_input_status_t is;
    pfe_msg_device_status_t ds;
    assert_int_equal(pfe_codec_decode_vds(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_cvw(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_own_fuel(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_input_status(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_device_status(&f, NULL), PFE_EINVAL);
    assert_int_equal(pfe_codec_decode_vds(&f, &vds), PFE_CODEC_EID);
    assert_int_equal(vds.altitude_mm.state, NA);
    assert_int_equal(pfe_codec_decode_cvw(&f, &cvw), PFE_CODEC_EID);
    assert_int_equal(pfe_codec_decode_own_fuel(&f, &of), PFE_CODEC_EID);
    assert_int_equal(pfe_codec_decode_input_status(&f, &is), PFE_CODEC_EID);
    assert_int_equal(pfe_codec_decode_device_status(&f, &ds), PFE_CODEC_EID);
    assert_int_equal(ds.reset_cause.state, NA);
    assert_int_equal(pfe_codec_encode_vds(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_cvw(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_own_fuel(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_input_status(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_device_status(&f, NULL, 0U), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_vds(NULL, &vds, 0U), PFE_EINVAL);
}

static void test_status(void **state)
{
    (void)state;
    pfe_can_frame_t f = poisoned_frame();
    pfe_msg_status_t in = {
        OK_, NA, ERR, OOR, {PFE_MODE_DEGRADED, OK_}, {3U, OK_}, {0U, OK_}, {250U, OK_},
        {1U, OK_}, {0U, OK_}, {0U, NA}, {0U, OK_}, {7U, OK_}, {0U, NA},
    };
    assert_int_equal(pfe_codec_encode_status(&f, &in, 0x8CU), 0);
    assert_int_equal(f.id, 0x98FF048CUL);
    /* byte 1: 01 (preview out of range) 10 (config error) 11 (grade n/a) 00 (speed valid);
     * byte 7: 7 inputs rejected; byte 8: conflicts not available */
    assert_payload(&f, 0x6C, 0x01, 0x03, 0x00, 0xFA, 0x31, 0x07, 0xFF);
    in.inputs_rejected.state = NA;
    /* counters hold at 250 (bits 5..7), mode 3 clamps to 2 (bit 4), flag 2 clamps to 1 (bit 8) */
    in.rx_frames_dropped.value = 251U;
    in.tick_overruns.value = 100000U;
    in.tx_frames_dropped.value = UINT32_MAX;
    in.mode.value = 3U;
    in.warming_up.value = 2U;
    assert_int_equal(pfe_codec_encode_status(&f, &in, 0x8CU), 0x1F0);
    assert_payload(&f, 0x6C, 0x02, 0xFA, 0xFA, 0xFA, 0x31, 0xFF, 0xFF);
    in.mode.state = ERR;
    in.rx_frames_dropped.state = NA;
    in.output_saturated.state = ERR;
    assert_int_equal(pfe_codec_encode_status(&f, &in, 0x8CU), 0x1C0);
    assert_payload(&f, 0x6C, 0xFE, 0xFF, 0xFA, 0xFA, 0xB1, 0xFF, 0xFF);
    in.speed_input = (pfe_sig_state_t)7;
    assert_int_equal(pfe_codec_encode_status(&f, &in, 0x8CU), PFE_EINVAL);

    pfe_msg_status_t m;
    f = frame8(0x98FF048CUL, 0x6C, 0x01, 0x03, 0x00, 0xFA, 0x31, 0x07, 0xFB);
    memset(&m, 0xA5, sizeof m);
    assert_int_equal(pfe_codec_decode_status(&f, &m), PFE_OK);
    assert_int_equal(m.speed_input, OK_);
    assert_int_equal(m.grade_input, NA);
    assert_int_equal(m.platoon_config_input, ERR);
    assert_int_equal(m.grade_preview_input, OOR);
    assert_int_equal(m.mode.value, PFE_MODE_DEGRADED);
    assert_int_equal(m.rx_frames_dropped.value, 3);
    assert_int_equal(m.tick_overruns.value, 0);
    assert_int_equal(m.tx_frames_dropped.value, 250);
    assert_int_equal(m.warming_up.value, 1);
    assert_int_equal(m.speed_clamped.value, 0);
    assert_int_equal(m.grade_clamped.state, NA);
    assert_int_equal(m.output_saturated.state, OK_);
    assert_int_equal(m.inputs_rejected.value, 7);
    assert_int_equal(m.address_conflicts.state, OOR); /* 0xFB: above 250 */
    f = frame8(0x98FF048CUL, 0x00, 0x03, 0xFB, 0xFE, 0xFF, 0x0E, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_decode_status(&f, &m), PFE_OK);
    assert_int_equal(m.mode.state, OOR);
    assert_int_equal(m.rx_frames_dropped.state, OOR);
    assert_int_equal(m.tick_overruns.state, ERR);
    assert_int_equal(m.tx_frames_dropped.state, NA);
    assert_int_equal(m.warming_up.state, ERR);        /* 10b */
    assert_int_equal(m.speed_clamped.state, NA);      /* 11b */
    assert_int_equal(m.grade_clamped.value, 0);
}

/* ------------------------------------------------------------ NAME, AddressClaimed, Request */

static const pfe_j1939_name_t k_name = {
    0x1ABCDEUL, 0x123U, 5U, 17U, 130U, 0U, 100U, 9U, 2U, true,
};

static void test_name_pack_unpack(void **state)
{
    (void)state;
    uint64_t v = 0U;
    assert_int_equal(pfe_j1939_name_pack(&k_name, &v), PFE_OK);
    assert_int_equal(v, 0xA9C8828D247ABCDEULL);
    pfe_j1939_name_t n;
    memset(&n, 0xA5, sizeof n);
    pfe_j1939_name_unpack(v, &n);
    assert_int_equal(n.identity_number, 0x1ABCDE);
    assert_int_equal(n.manufacturer_code, 0x123);
    assert_int_equal(n.ecu_instance, 5);
    assert_int_equal(n.function_instance, 17);
    assert_int_equal(n.function, 130);
    assert_int_equal(n.reserved, 0);
    assert_int_equal(n.vehicle_system, 100);
    assert_int_equal(n.vehicle_system_instance, 9);
    assert_int_equal(n.industry_group, 2);
    assert_true(n.arbitrary_address_capable);
    /* every bit set, and back */
    pfe_j1939_name_unpack(UINT64_MAX, &n);
    assert_int_equal(n.identity_number, 0x1FFFFF);
    assert_int_equal(n.manufacturer_code, 0x7FF);
    assert_int_equal(n.reserved, 1);
    assert_int_equal(pfe_j1939_name_pack(&n, &v), PFE_OK);
    assert_int_equal(v, UINT64_MAX);
    /* fields wider than their bits are refused */
    n = k_name;
    n.identity_number = 0x200000UL;
    assert_int_equal(pfe_j1939_name_pack(&n, &v), PFE_EINVAL);
    n = k_name;
    n.manufacturer_code = 0x800U;
    assert_int_equal(pfe_j1939_name_pack(&n, &v), PFE_EINVAL);
    n = k_name;
    n.ecu_instance = 8U;
    assert_int_equal(pfe_j1939_name_pack(&n, &v), PFE_EINVAL);
    n = k_name;
    n.function_instance = 32U;
    assert_int_equal(pfe_j1939_name_pack(&n, &v), PFE_EINVAL);
    n = k_name;
    n.vehicle_system = 128U;
    assert_int_equal(pfe_j1939_name_pack(&n, &v), PFE_EINVAL);
    n = k_name;
    n.vehicle_system_instance = 16U;
    assert_int_equal(pfe_j1939_name_pack(&n, &v), PFE_EINVAL);
    n = k_name;
    n.industry_group = 8U;
    assert_int_equal(pfe_j1939_name_pack(&n, &v), PFE_EINVAL);
    n = k_name;
    n.reserved = 2U;
    assert_int_equal(pfe_j1939_name_pack(&n, &v), PFE_EINVAL);
    assert_int_equal(pfe_j1939_name_pack(NULL, &v), PFE_EINVAL);
    assert_int_equal(pfe_j1939_name_pack(&k_name, NULL), PFE_EINVAL);
}

static void test_address_claimed(void **state)
{
    (void)state;
    pfe_can_frame_t f = poisoned_frame();
    assert_int_equal(pfe_codec_encode_address_claimed(&f, &k_name, PFE_CODEC_DEFAULT_ADDRESS), 0);
    assert_int_equal(f.id, 0x98EEFF8CUL);
    assert_int_equal(f.dlc, 8);
    assert_payload(&f, 0xDE, 0xBC, 0x7A, 0x24, 0x8D, 0x82, 0xC8, 0xA9); /* NAME, LSB first */
    pfe_j1939_name_t n;
    memset(&n, 0xA5, sizeof n);
    assert_int_equal(pfe_codec_decode_address_claimed(&f, &n), PFE_OK);
    assert_memory_equal(&n, &k_name, sizeof n);
    assert_int_equal(pfe_j1939_source(f.id), 0x8C);
    /* another node's claim, from 0x80 */
    f = frame8(0x98EEFF80UL, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80);
    assert_int_equal(pfe_codec_decode_address_claimed(&f, &n), PFE_OK);
    assert_int_equal(n.identity_number, 1);
    assert_int_equal(n.function, 0);
    assert_true(n.arbitrary_address_capable);
    pfe_j1939_name_t bad = k_name;
    bad.industry_group = 9U;
    assert_int_equal(pfe_codec_encode_address_claimed(&f, &bad, 0x8CU), PFE_EINVAL);
}

static void test_request(void **state)
{
    (void)state;
    pfe_msg_request_t m;
    /* request for LFC (65257 = 0xFEE9) to the module, from 0x00 */
    pfe_can_frame_t f = frame8(0x98EA8C00UL, 0xE9, 0xFE, 0x00, 0xA5, 0xA5, 0xA5, 0xA5, 0xA5);
    f.dlc = 3U;
    memset(&m, 0xA5, sizeof m);
    assert_int_equal(pfe_codec_decode_request(&f, &m), PFE_OK);
    assert_int_equal(m.pgn.state, OK_);
    assert_int_equal(m.pgn.value, 65257);
    assert_int_equal(m.destination, 0x8C);
    assert_int_equal(m.source, 0x00);
    /* request for Address Claimed, global */
    f = frame8(0x98EAFF00UL, 0x00, 0xEE, 0x00, 0, 0, 0, 0, 0);
    f.dlc = 3U;
    assert_int_equal(pfe_codec_decode_request(&f, &m), PFE_OK);
    assert_int_equal(m.pgn.value, 60928);
    assert_int_equal(m.destination, 0xFF);
    /* top PGN, one past it, all ones */
    f.data[0] = 0xFF;
    f.data[1] = 0xFF;
    f.data[2] = 0x03;
    assert_int_equal(pfe_codec_decode_request(&f, &m), PFE_OK);
    assert_int_equal(m.pgn.value, 0x3FFFF);
    f.data[0] = 0x00;
    f.data[1] = 0x00;
    f.data[2] = 0x04;
    assert_int_equal(pfe_codec_decode_request(&f, &m), PFE_OK);
    assert_int_equal(m.pgn.state, OOR);
    f.data[2] = 0xFF;
    assert_int_equal(pfe_codec_decode_request(&f, &m), PFE_OK);
    assert_int_equal(m.pgn.state, OOR);

    f = poisoned_frame();
    assert_int_equal(pfe_codec_encode_request(&f, 60928U, 0xFFU, 0x8CU), 0);
    assert_int_equal(f.id, 0x98EAFF8CUL);
    assert_int_equal(f.dlc, 3);
    assert_payload(&f, 0x00, 0xEE, 0x00, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_encode_request(&f, 64777U, 0x21U, 0x8CU), 0);
    assert_int_equal(f.id, 0x98EA218CUL);
    assert_payload(&f, 0x09, 0xFD, 0x00, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF);
    assert_int_equal(pfe_codec_encode_request(&f, 0x40000U, 0xFFU, 0x8CU), PFE_EINVAL);
    assert_int_equal(pfe_codec_encode_request(NULL, 60928U, 0xFFU, 0x8CU), PFE_EINVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_j1939_pgn_source_destination),
        cmocka_unit_test(test_j1939_id_builds_identifiers),
        cmocka_unit_test(test_find_message_masks_priority_and_addresses),
        cmocka_unit_test(test_message_table),
        cmocka_unit_test(test_signal_table_is_consistent),
        cmocka_unit_test(test_every_signal_boundaries_and_codes),
        cmocka_unit_test(test_raw_put_get_any_position),
        cmocka_unit_test(test_j1939_ranges_by_length),
        cmocka_unit_test(test_ccvs1_decode),
        cmocka_unit_test(test_decoders_reject_wrong_frames),
        cmocka_unit_test(test_ccvs1_encode),
        cmocka_unit_test(test_ccvs1_round_trip_every_raw),
        cmocka_unit_test(test_ssi_decode_encode),
        cmocka_unit_test(test_grade_from_pitch),
        cmocka_unit_test(test_grade_from_pitch_against_double),
        cmocka_unit_test(test_platoon_config),
        cmocka_unit_test(test_grade_preview_frames),
        cmocka_unit_test(test_preview_complete_small),
        cmocka_unit_test(test_preview_complete_1000_samples),
        cmocka_unit_test(test_preview_rejects_gaps_and_order),
        cmocka_unit_test(test_preview_restart_and_counts),
        cmocka_unit_test(test_lfe1),
        cmocka_unit_test(test_platoon_fuel),
        cmocka_unit_test(test_hrlfc),
        cmocka_unit_test(test_fuel_prediction),
        cmocka_unit_test(test_status),
        cmocka_unit_test(test_vds),
        cmocka_unit_test(test_cvw),
        cmocka_unit_test(test_own_fuel),
        cmocka_unit_test(test_input_status),
        cmocka_unit_test(test_device_status),
        cmocka_unit_test(test_new_messages_refuse_bad_arguments),
        cmocka_unit_test(test_name_pack_unpack),
        cmocka_unit_test(test_address_claimed),
        cmocka_unit_test(test_request),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
