/*
 * Host test: can_dbc/pfe.dbc against the firmware codec, and the DBC reader.
 *
 *   test_dbc_codec <path of pfe.dbc>
 *
 * The codec's tables are generated from the DBC (sim_host/tools/dbc2c.c);
 * this test reads the DBC on its own and holds the tables to it. Every
 * signal of pfe_codec_signals[] must be in the DBC with the same
 * message id, PGN, DLC, cycle time, start bit, length, byte order, sign,
 * scale, offset, [min|max], unit and SPN, and every DBC message and signal
 * must be in the codec's tables; a signal with J1939 value states names its
 * not-available and error codes in its VAL_. Scales, offsets and limits are compared as exact
 * fractions of the numbers written in the DBC, never as doubles. Then the
 * codec's bit placement and unit conversions are checked against an
 * independent reading of the DBC, the generated header's PGNs, periods,
 * receive-filter count and ranges (and pfe_input's periods) against the DBC,
 * the pitch-to-grade tangent against libm
 * over every SPN 3318 value, and the reader against malformed snippets
 * written to a temporary folder.
 */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "../test_assert.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lib/dbc.h"
#include "pfe_can.h"
#include "pfe_codec.h"
#include "pfe_ecu.h"
#include "pfe_input.h"

static const char *g_dbc_path;
static dbc_t *g_dbc;
static char g_tmpdir[256];

/* ------------------------------------------------------------ exact fractions */

/* a/b == c/d for b, d > 0, without overflow for |values| < 2^62. */
static bool frac_equal(int64_t a, int64_t b, int64_t c, int64_t d)
{
    return ((__int128)a * d) == ((__int128)c * b);
}

/* The DBC number text as a fraction. */
static void dbc_frac(const char *text, int64_t *num, int64_t *den)
{
    if (dbc_decimal_to_rational(text, num, den) != 0) {
        fail_msg("'%s' is not an exact decimal", text);
    }
}

/* raw * scale + offset as a fraction (denominator scale_den * offset_den). */
static void phys_of_raw(const pfe_codec_signal_t *s, uint32_t raw, int64_t *num, int64_t *den)
{
    *den = (int64_t)s->scale_den * s->offset_den;
    *num = ((int64_t)raw * s->scale_num * s->offset_den) + ((int64_t)s->offset_num * s->scale_den);
}

static uint32_t dbc_id_of(const pfe_codec_message_t *m)
{
    return pfe_j1939_id(m->priority, m->pgn, PFE_J1939_ADDR_GLOBAL, m->dbc_address);
}

/* ------------------------------------------------------------ set-up */

static int load_dbc(void **state)
{
    (void)state;
    dbc_error_t err;
    if (dbc_parse_file(g_dbc_path, &g_dbc, &err) != 0) {
        fprintf(stderr, "%s:%d: %s\n", g_dbc_path, err.line, err.message);
        return -1;
    }
    return 0;
}

static int free_dbc(void **state)
{
    (void)state;
    dbc_free(g_dbc);
    g_dbc = NULL;
    return 0;
}

/* ------------------------------------------------------------ the generated header */

/* A received message's period in the DBC, read here on its own:
 * GenMsgCycleTime, or PFEInputPeriod when that is 0. */
static int64_t dbc_rx_period_ms(const char *message)
{
    const dbc_message_t *d = dbc_message_by_name(g_dbc, message);
    if (d == NULL) {
        fail_msg("no message %s in the DBC", message);
    }
    int64_t cycle = -1;
    int64_t assumed = -1;
    assert_int_equal(dbc_message_attr_int(g_dbc, d, "GenMsgCycleTime", &cycle), 0);
    assert_int_equal(dbc_message_attr_int(g_dbc, d, "PFEInputPeriod", &assumed), 0);
    return (cycle != 0) ? cycle : assumed;
}

/* pfe_dbc.h's PGN and period macros, PFE_ECU_RX_FILTERS and the ranges in
 * firmware units, against the DBC read here; and the inputs' periods in
 * pfe_input_rules[] are the DBC's. */
static void test_generated_header_matches_the_dbc(void **state)
{
    (void)state;
    static const struct {
        const char *message;
        uint32_t pgn;
        int64_t period_ms;
        pfe_input_kind_t input;
    } k_inputs[] = {
        {"CCVS1", PFE_PGN_CCVS1, PFE_RX_PERIOD_MS_CCVS1, PFE_IN_SPEED},
        {"SSI", PFE_PGN_SSI, PFE_RX_PERIOD_MS_SSI, PFE_IN_GRADE},
        {"VDS", PFE_PGN_VDS, PFE_RX_PERIOD_MS_VDS, PFE_IN_ALTITUDE},
        {"CVW", PFE_PGN_CVW, PFE_RX_PERIOD_MS_CVW, PFE_IN_MASS},
        {"LFE1", PFE_PGN_LFE1, PFE_RX_PERIOD_MS_LFE1, PFE_IN_ENGINE_FUEL},
    };
    for (size_t k = 0U; k < sizeof k_inputs / sizeof k_inputs[0]; k++) {
        const dbc_message_t *d = dbc_message_by_name(g_dbc, k_inputs[k].message);
        assert_non_null(d);
        print_message("%s: PGN %u, period %lld ms (DBC %lld ms)\n", k_inputs[k].message,
                      (unsigned)k_inputs[k].pgn, (long long)k_inputs[k].period_ms,
                      (long long)dbc_rx_period_ms(k_inputs[k].message));
        assert_int_equal(pfe_j1939_pgn(d->id), k_inputs[k].pgn);
        assert_int_equal(k_inputs[k].period_ms, dbc_rx_period_ms(k_inputs[k].message));
        assert_int_not_equal(k_inputs[k].period_ms, 0);
        assert_int_equal(pfe_input_rules[k_inputs[k].input].pgn, k_inputs[k].pgn);
        assert_int_equal(pfe_input_rules[k_inputs[k].input].period_us, 1000 * k_inputs[k].period_ms);
    }
    /* CVW has no cycle time: its period is the DBC's PFEInputPeriod, 1 s */
    assert_int_equal(PFE_RX_PERIOD_MS_CVW, 1000);
    size_t received = 0U;
    for (size_t i = 0U; i < g_dbc->n_messages; i++) {
        int64_t rx = 0;
        assert_int_equal(dbc_message_attr_int(g_dbc, &g_dbc->messages[i], "PFEReceivedFrom", &rx), 0);
        received += (rx == 1) ? 1U : 0U;
    }
    assert_int_equal(PFE_ECU_RX_FILTERS, received);
    /* ranges: [min|max] of the DBC text times the unit's factor */
    static const struct {
        const char *message, *signal;
        int64_t fw_min, fw_max;
        int64_t per_unit; /* firmware units per DBC unit */
    } k_ranges[] = {
        {"VDS", "Altitude", PFE_CSIG_VDS_ALTITUDE_MIN, PFE_CSIG_VDS_ALTITUDE_MAX, 1000},  /* m -> mm */
        {"SSI", "PitchAngle", PFE_CSIG_SSI_PITCH_ANGLE_MIN, PFE_CSIG_SSI_PITCH_ANGLE_MAX, 1000000}, /* deg -> udeg */
        {"CVW", "GrossCombinationVehicleWeight", PFE_CSIG_CVW_GROSS_COMBINATION_WEIGHT_MIN,
         PFE_CSIG_CVW_GROSS_COMBINATION_WEIGHT_MAX, 1},                                     /* kg */
        {"PFE_FuelPrediction", "PredictedFuel", PFE_CSIG_FP_PREDICTED_FUEL_MIN, PFE_CSIG_FP_PREDICTED_FUEL_MAX,
         1000000},                                                                          /* L -> uL */
    };
    for (size_t k = 0U; k < sizeof k_ranges / sizeof k_ranges[0]; k++) {
        const dbc_message_t *m = dbc_message_by_name(g_dbc, k_ranges[k].message);
        assert_non_null(m);
        const dbc_signal_t *d = dbc_signal_by_name(m, k_ranges[k].signal);
        assert_non_null(d);
        int64_t n;
        int64_t den;
        dbc_frac(d->min_text, &n, &den);
        print_message("%s.%s: [%lld|%lld] in firmware units, DBC [%s|%s]\n", k_ranges[k].message,
                      k_ranges[k].signal, (long long)k_ranges[k].fw_min, (long long)k_ranges[k].fw_max,
                      d->min_text, d->max_text);
        assert_true(frac_equal(n * k_ranges[k].per_unit, den, k_ranges[k].fw_min, 1));
        dbc_frac(d->max_text, &n, &den);
        assert_true(frac_equal(n * k_ranges[k].per_unit, den, k_ranges[k].fw_max, 1));
    }
}

/* ------------------------------------------------------------ DBC against the codec */

static void test_every_codec_message_is_in_the_dbc(void **state)
{
    (void)state;
    assert_int_equal(g_dbc->n_messages, PFE_MSG_COUNT);
    for (uint32_t i = 0U; i < (uint32_t)PFE_MSG_COUNT; i++) {
        const pfe_codec_message_t *m = &pfe_codec_messages[i];
        const dbc_message_t *d = dbc_message_by_name(g_dbc, m->name);
        if (d == NULL) {
            fail_msg("codec message %s is not in the DBC", m->name);
        }
        assert_int_equal(d->id, dbc_id_of(m));
        assert_int_not_equal(d->id & DBC_EXTENDED_ID_FLAG, 0U);
        assert_int_equal(pfe_j1939_pgn(d->id), m->pgn);
        assert_int_equal(pfe_j1939_source(d->id), m->dbc_address);
        assert_int_equal(d->dlc, m->dlc);
        int64_t cycle = -1;
        assert_int_equal(dbc_message_attr_int(g_dbc, d, "GenMsgCycleTime", &cycle), 0);
        assert_int_equal(cycle, m->cycle_ms);
        int64_t format = -1;
        assert_int_equal(dbc_message_attr_int(g_dbc, d, "VFrameFormat", &format), 0);
        assert_int_equal(format, 3); /* J1939PG */
        assert_int_equal(d->n_signals, m->n_signals);
        assert_non_null(d->comment);
        /* the DBC shows the module's frames from its address, the others' from 0x00 */
        if (strcmp(d->transmitter, "PFE") == 0) {
            assert_int_not_equal(m->direction & PFE_CODEC_DIR_TX, 0U);
            assert_int_equal(m->dbc_address, PFE_CODEC_DEFAULT_ADDRESS);
        } else {
            assert_int_not_equal(m->direction & PFE_CODEC_DIR_RX, 0U);
            assert_int_equal(m->dbc_address, 0x00);
            for (size_t k = 0U; k < d->n_signals; k++) {
                bool to_pfe = false;
                for (size_t r = 0U; r < d->signals[k].n_receivers; r++) {
                    to_pfe = to_pfe || (strcmp(d->signals[k].receivers[r], "PFE") == 0);
                }
                assert_true(to_pfe);
            }
        }
    }
    /* the module's address */
    int64_t sa = -1;
    const dbc_node_t *pfe = NULL;
    for (size_t i = 0U; i < g_dbc->n_nodes; i++) {
        if (strcmp(g_dbc->nodes[i].name, "PFE") == 0) {
            pfe = &g_dbc->nodes[i];
        }
    }
    assert_non_null(pfe);
    assert_int_equal(dbc_node_attr_int(g_dbc, pfe, "NmStationAddress", &sa), 0);
    assert_int_equal(sa, PFE_CODEC_DEFAULT_ADDRESS);
}

static void check_signal(const pfe_codec_signal_t *s, const dbc_signal_t *d)
{
    int64_t n;
    int64_t q;
    int64_t pn;
    int64_t pq;
    assert_int_equal(d->start_bit, s->start_bit);
    assert_int_equal(d->length, s->length);
    assert_int_equal(d->little_endian, s->byte_order == PFE_CODEC_LITTLE_ENDIAN);
    assert_int_equal(d->is_signed, s->is_signed);
    dbc_frac(d->factor_text, &n, &q);
    if (!frac_equal(n, q, s->scale_num, s->scale_den)) {
        fail_msg("%s.%s: scale %s in the DBC, %ld/%ld in the codec", s->message, s->name, d->factor_text,
                 (long)s->scale_num, (long)s->scale_den);
    }
    dbc_frac(d->offset_text, &n, &q);
    if (!frac_equal(n, q, s->offset_num, s->offset_den)) {
        fail_msg("%s.%s: offset %s in the DBC, %ld/%ld in the codec", s->message, s->name, d->offset_text,
                 (long)s->offset_num, (long)s->offset_den);
    }
    dbc_frac(d->min_text, &n, &q);
    phys_of_raw(s, s->raw_min, &pn, &pq);
    if (!frac_equal(n, q, pn, pq)) {
        fail_msg("%s.%s: min %s in the DBC, raw %lu in the codec", s->message, s->name, d->min_text,
                 (unsigned long)s->raw_min);
    }
    dbc_frac(d->max_text, &n, &q);
    phys_of_raw(s, s->raw_max, &pn, &pq);
    if (!frac_equal(n, q, pn, pq)) {
        fail_msg("%s.%s: max %s in the DBC, raw %lu in the codec", s->message, s->name, d->max_text,
                 (unsigned long)s->raw_max);
    }
    switch (s->mux) {
    case PFE_CODEC_MUX_NONE:
        assert_int_equal(d->mux_kind, DBC_MUX_NONE);
        break;
    case PFE_CODEC_MUXER:
        assert_int_equal(d->mux_kind, DBC_MUX_MULTIPLEXOR);
        break;
    default:
        assert_int_equal(d->mux_kind, DBC_MUX_MULTIPLEXED);
        assert_int_equal(d->mux_value, s->mux);
        break;
    }
    int64_t spn = -1;
    assert_int_equal(dbc_signal_attr_int(g_dbc, d, "SPN", &spn), 0);
    if (spn != (int64_t)s->spn) {
        fail_msg("%s.%s: SPN %ld in the DBC, %lu in the codec", s->message, s->name, (long)spn,
                 (unsigned long)s->spn);
    }
    if (strcmp(s->unit, d->unit) != 0) {
        fail_msg("%s.%s: unit \"%s\" in the DBC, \"%s\" in the codec", s->message, s->name, d->unit,
                 s->unit);
    }
    /* J1939 special ranges apply to whole bytes and 2-bit states only, and
     * the DBC names their codes for generic tools */
    bool named_na = false;
    bool named_error = false;
    const uint64_t all_ones = (d->length >= 64U) ? UINT64_MAX : ((UINT64_C(1) << d->length) - 1U);
    for (size_t k = 0U; k < d->n_values; k++) {
        named_na = named_na || (((uint64_t)d->values[k].value == all_ones) &&
                                (strcmp(d->values[k].text, "NotAvailable") == 0));
        named_error = named_error ||
                      (((uint64_t)d->values[k].value == (uint64_t)pfe_codec_raw_code(s, PFE_SIG_ERROR)) &&
                       (strcmp(d->values[k].text, "Error") == 0));
    }
    if (s->ranges == PFE_CODEC_RANGES_J1939) {
        if ((s->length != 2U) && ((s->length % 8U) != 0U)) {
            fail_msg("%s.%s: J1939 ranges on a %u-bit signal (2 bits or whole bytes only)",
                     s->message, s->name, (unsigned)s->length);
        }
        if (!named_na || !named_error) {
            fail_msg("%s.%s: J1939 value states, but VAL_ names not-available %s, error %s", s->message,
                     s->name, named_na ? "yes" : "no", named_error ? "yes" : "no");
        }
    } else if (named_na) {
        fail_msg("%s.%s: VAL_ NotAvailable, but no J1939 value states in the codec", s->message, s->name);
    }
}

static void test_every_codec_signal_matches_the_dbc(void **state)
{
    (void)state;
    for (uint32_t i = 0U; i < pfe_codec_signal_count; i++) {
        const pfe_codec_signal_t *s = &pfe_codec_signals[i];
        const dbc_message_t *m = dbc_message_by_name(g_dbc, s->message);
        if (m == NULL) {
            fail_msg("message %s of signal %s is not in the DBC", s->message, s->name);
        }
        assert_int_equal(pfe_j1939_pgn(m->id), s->pgn);
        const dbc_signal_t *d = dbc_signal_by_name(m, s->name);
        if (d == NULL) {
            fail_msg("codec signal %s.%s is not in the DBC", s->message, s->name);
        }
        check_signal(s, d);
    }
}

static void test_every_dbc_signal_is_in_the_codec(void **state)
{
    (void)state;
    size_t total = 0U;
    for (size_t i = 0U; i < g_dbc->n_messages; i++) {
        const dbc_message_t *m = &g_dbc->messages[i];
        const pfe_codec_message_t *cm = pfe_codec_find_message(m->id);
        if (cm == NULL) {
            fail_msg("DBC message %s (PGN %lu) is not in the codec", m->name, (unsigned long)pfe_j1939_pgn(m->id));
        }
        assert_string_equal(cm->name, m->name);
        for (size_t k = 0U; k < m->n_signals; k++) {
            bool found = false;
            for (uint32_t j = cm->first_signal; j < (uint32_t)cm->first_signal + cm->n_signals; j++) {
                found = found || (strcmp(pfe_codec_signals[j].name, m->signals[k].name) == 0);
            }
            if (!found) {
                fail_msg("DBC signal %s.%s is not in the codec table", m->name, m->signals[k].name);
            }
            total++;
        }
    }
    assert_int_equal(total, pfe_codec_signal_count);
}

static const char *value_text(const dbc_signal_t *s, int64_t v)
{
    for (size_t i = 0U; i < s->n_values; i++) {
        if (s->values[i].value == v) {
            return s->values[i].text;
        }
    }
    return "";
}

/* The enumerations the codec hard-codes are those the DBC names. */
static void test_value_tables_match_the_codec(void **state)
{
    (void)state;
    const dbc_message_t *st = dbc_message_by_name(g_dbc, "PFE_Status");
    static const char *const inputs[] = {"SpeedInputState", "GradeInputState", "PlatoonConfigInputState",
                                         "GradePreviewInputState"};
    for (size_t i = 0U; i < 4U; i++) {
        const dbc_signal_t *s = dbc_signal_by_name(st, inputs[i]);
        assert_non_null(s);
        assert_int_equal(s->n_values, 4);
        assert_string_equal(value_text(s, PFE_STATUS_INPUT_VALID), "Valid");
        assert_string_equal(value_text(s, PFE_STATUS_INPUT_OUT_OF_RANGE), "OutOfRange");
        assert_string_equal(value_text(s, PFE_STATUS_INPUT_ERROR), "Error");
        assert_string_equal(value_text(s, PFE_STATUS_INPUT_NOT_AVAILABLE), "NotAvailableOrTimedOut");
    }
    const dbc_signal_t *mode = dbc_signal_by_name(st, "DegradedMode");
    assert_string_equal(value_text(mode, PFE_MODE_NORMAL), "Normal");
    assert_string_equal(value_text(mode, PFE_MODE_DEGRADED), "Degraded");
    assert_string_equal(value_text(mode, PFE_MODE_NO_ESTIMATE), "NoEstimate");
    const dbc_signal_t *ft = dbc_signal_by_name(dbc_message_by_name(g_dbc, "PFE_GradePreview"), "PreviewFrameType");
    assert_string_equal(value_text(ft, PFE_PREVIEW_FRAME_HEADER), "Header");
    assert_string_equal(value_text(ft, PFE_PREVIEW_FRAME_DATA), "Data");
    const dbc_signal_t *fom = dbc_signal_by_name(dbc_message_by_name(g_dbc, "SSI"), "PitchAngleFigureOfMerit");
    assert_string_equal(value_text(fom, PFE_SSI_FOM_FULLY_FUNCTIONAL), "FullyFunctional");
    assert_string_equal(value_text(fom, PFE_SSI_FOM_DEGRADED), "Degraded");
}

/* Raw value of a DBC signal, bit by bit, from the DBC's own description. */
static uint64_t dbc_raw(const dbc_signal_t *s, const uint8_t *data)
{
    uint64_t v = 0U;
    for (uint32_t i = 0U; i < s->length; i++) {
        const uint32_t bit = s->start_bit + i;
        v |= (uint64_t)((data[bit / 8U] >> (bit % 8U)) & 1U) << i;
    }
    return v;
}

static uint32_t g_lcg = 12345U;
static uint8_t rand8(void)
{
    g_lcg = (g_lcg * 1103515245U) + 12345U;
    return (uint8_t)(g_lcg >> 16);
}

/* The codec reads every signal where the DBC puts it, and writes only there. */
static void test_codec_bits_follow_the_dbc(void **state)
{
    (void)state;
    for (uint32_t i = 0U; i < pfe_codec_signal_count; i++) {
        const pfe_codec_signal_t *s = &pfe_codec_signals[i];
        const dbc_signal_t *d = dbc_signal_by_name(dbc_message_by_name(g_dbc, s->message), s->name);
        for (int trial = 0; trial < 200; trial++) {
            uint8_t data[8];
            for (size_t k = 0U; k < 8U; k++) {
                data[k] = rand8();
            }
            assert_int_equal(pfe_codec_raw_get(data, s), dbc_raw(d, data));
            uint8_t before[8];
            memcpy(before, data, 8U);
            const uint32_t raw = ((uint32_t)rand8() << 24) | ((uint32_t)rand8() << 16) |
                                 ((uint32_t)rand8() << 8) | rand8();
            pfe_codec_raw_put(data, s, raw);
            const uint64_t mask = (s->length == 32U) ? 0xFFFFFFFFULL : ((1ULL << s->length) - 1U);
            assert_int_equal(dbc_raw(d, data), raw & mask);
            for (uint32_t bit = 0U; bit < 64U; bit++) {
                const bool inside = (bit >= d->start_bit) && (bit < (d->start_bit + d->length));
                const unsigned a = ((unsigned)data[bit / 8U] >> (bit % 8U)) & 1U;
                const unsigned b = ((unsigned)before[bit / 8U] >> (bit % 8U)) & 1U;
                if (!inside) {
                    assert_int_equal(a, b);
                }
            }
        }
    }
}

static double dbc_phys(const dbc_signal_t *d, uint64_t raw)
{
    return ((double)raw * d->factor) + d->offset;
}

static pfe_can_frame_t frame_with(const char *message, const char *signal, uint32_t raw)
{
    const dbc_message_t *m = dbc_message_by_name(g_dbc, message);
    pfe_can_frame_t f;
    f.id = m->id;
    f.dlc = (uint8_t)m->dlc;
    memset(f.data, 0xFF, sizeof f.data);
    for (uint32_t i = 0U; i < pfe_codec_signal_count; i++) {
        if ((strcmp(pfe_codec_signals[i].message, message) == 0) &&
            (strcmp(pfe_codec_signals[i].name, signal) == 0)) {
            pfe_codec_raw_put(f.data, &pfe_codec_signals[i], raw);
            return f;
        }
    }
    fail_msg("no signal %s.%s", message, signal);
    return f;
}

/* Firmware units against the DBC's physical values: |fw - phys * k| <= 0.5 + 1e-6 */
static void check_units(const char *message, const char *signal, double per_unit, double fw_value,
                        uint32_t raw)
{
    const dbc_signal_t *d = dbc_signal_by_name(dbc_message_by_name(g_dbc, message), signal);
    const double expected = dbc_phys(d, raw) * per_unit;
    if (fabs(fw_value - expected) > 0.500001) {
        fail_msg("%s.%s raw %lu: firmware %.3f, DBC %.6f", message, signal, (unsigned long)raw, fw_value, expected);
    }
}

static void test_firmware_units_follow_the_dbc(void **state)
{
    (void)state;
    for (uint32_t raw = 0U; raw <= 0xFAFFU; raw += 13U) {
        pfe_can_frame_t f = frame_with("CCVS1", "WheelBasedVehicleSpeed", raw);
        pfe_msg_ccvs1_t c;
        assert_int_equal(pfe_codec_decode_ccvs1(&f, &c), 0);
        check_units("CCVS1", "WheelBasedVehicleSpeed", 1e6 / 3600.0, c.speed_mm_s.value, raw); /* km/h -> mm/s */

        f = frame_with("SSI", "PitchAngle", raw);
        pfe_msg_ssi_t s;
        assert_int_equal(pfe_codec_decode_ssi(&f, &s), 0);
        check_units("SSI", "PitchAngle", 1e6, s.pitch_udeg.value, raw);

        f = frame_with("LFE1", "EngineFuelRate", raw);
        pfe_msg_lfe1_t l;
        assert_int_equal(pfe_codec_decode_lfe1(&f, &l), 0);
        check_units("LFE1", "EngineFuelRate", 1e9 / 3600.0, l.fuel_rate_nl_s.value, raw); /* L/h -> nL/s */

        f = frame_with("PFE_PlatoonConfig", "Gap", raw);
        pfe_msg_platoon_config_t pc;
        assert_int_equal(pfe_codec_decode_platoon_config(&f, &pc), 0);
        check_units("PFE_PlatoonConfig", "Gap", 1e3, pc.gap_mm.value, raw);
        f = frame_with("PFE_PlatoonConfig", "TimeGap", raw);
        assert_int_equal(pfe_codec_decode_platoon_config(&f, &pc), 0);
        check_units("PFE_PlatoonConfig", "TimeGap", 1e3, pc.time_gap_ms.value, raw);

        f = frame_with("PFE_FuelPrediction", "PredictedFuel", raw);
        pfe_msg_fuel_prediction_t fp;
        assert_int_equal(pfe_codec_decode_fuel_prediction(&f, &fp), 0);
        check_units("PFE_FuelPrediction", "PredictedFuel", 1e6, fp.fuel_ul.value, raw);
        f = frame_with("PFE_FuelPrediction", "PredictedTime", raw);
        assert_int_equal(pfe_codec_decode_fuel_prediction(&f, &fp), 0);
        check_units("PFE_FuelPrediction", "PredictedTime", 1e3, fp.time_ms.value, raw);

        f = frame_with("PFE_GradePreview", "GradeSample1", raw);
        f.data[0] = 0x01; /* data frame, index 0 */
        f.data[1] = 0x00;
        pfe_msg_grade_preview_t gp;
        assert_int_equal(pfe_codec_decode_grade_preview(&f, &gp), 0);
        check_units("PFE_GradePreview", "GradeSample1", 1e4, gp.grade_ppm[1].value, raw); /* % -> ppm */
    }
    for (uint64_t raw64 = 0U; raw64 <= 0xFAFFFFFFULL; raw64 += 9876543U) {
        const uint32_t raw = (uint32_t)raw64;
        pfe_can_frame_t f = frame_with("HRLFC", "HighResolutionEngineTotalFuelUsed", raw);
        pfe_msg_hrlfc_t h;
        assert_int_equal(pfe_codec_decode_hrlfc(&f, &h), 0);
        check_units("HRLFC", "HighResolutionEngineTotalFuelUsed", 1e6, (double)h.total_fuel_ul.value, raw);
    }
}

/* tan(pitch) over every valid SPN 3318 value, against libm. */
static void test_grade_from_pitch_every_raw(void **state)
{
    (void)state;
    const double pi = 3.14159265358979323846;
    double worst = 0.0;
    for (uint32_t raw = 0U; raw <= 0xFAFFU; raw++) {
        const int32_t udeg = ((int32_t)raw * 2000) - 64000000;
        bool sat = false;
        const int32_t g = pfe_codec_grade_ppm_from_pitch(udeg, &sat);
        const double exact = tan((double)udeg * 1e-6 * pi / 180.0) * 1e6;
        if (fabs(exact) <= 499999.0) {
            const double err = fabs((double)g - exact);
            worst = (err > worst) ? err : worst;
            if ((err > 0.6) || sat) {
                fail_msg("pitch %ld udeg: %ld ppm, exact %.4f", (long)udeg, (long)g, exact);
            }
        } else if (fabs(exact) >= 500001.0) {
            assert_true(sat);
            assert_int_equal(g, (exact > 0.0) ? 500000 : -500000);
        } else {
            assert_in_range(g + 500000, 0, 1000000);
        }
    }
    print_message("grade from pitch: worst error %.3f ppm over SPN 3318\n", worst);
}

/* ------------------------------------------------------------ the reader */

static int parse_snippet(const char *text, dbc_error_t *err)
{
    char path[300];
    (void)snprintf(path, sizeof path, "%s/snippet.dbc", g_tmpdir);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1U, strlen(text), f), strlen(text));
    assert_int_equal(fclose(f), 0);
    dbc_t *d = NULL;
    memset(err, 0, sizeof *err);
    const int rc = dbc_parse_file(path, &d, err);
    (void)remove(path);
    if (rc == 0) {
        assert_non_null(d);
        dbc_free(d);
    } else {
        assert_null(d);
    }
    return rc;
}

/* Nine lines; a snippet after it starts on line 10. */
#define HEAD "VERSION \"\"\n\nNS_ :\n\tCM_\n\tBA_\n\nBS_:\n\nBU_: A B\n"

static void expect_error(const char *text, int line, const char *fragment)
{
    dbc_error_t err;
    if (parse_snippet(text, &err) == 0) {
        fail_msg("accepted a malformed snippet (expected line %d: %s)", line, fragment);
    }
    if ((err.line != line) || (strstr(err.message, fragment) == NULL)) {
        fail_msg("line %d: \"%s\"; expected line %d with \"%s\"", err.line, err.message, line, fragment);
    }
}

static void test_reader_reports_errors_with_lines(void **state)
{
    (void)state;
    expect_error("VERSION \"abc\n\n", 1, "unterminated string");
    expect_error(HEAD " SG_ S : 0|8@1+ (1,0) [0|0] \"\" A\n", 10, "SG_ outside a message");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|8@2+ (1,0) [0|0] \"\" B\n", 11, "byte order");
    expect_error(HEAD "BO_ 100 M: 2 A\n SG_ S : 8|16@1+ (1,0) [0|0] \"\" B\n", 11, "does not fit");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|0@1+ (1,0) [0|0] \"\" B\n", 11, "length 0");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|65@1+ (1,0) [0|0] \"\" B\n", 11, "out of range");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" B\nBO_ 100 N: 8 A\n", 12,
                 "already used");
    expect_error(HEAD "BO_ 100 M: 8 A\nBO_ 101 M: 8 A\n", 11, "message name M already used");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" B\n SG_ S : 8|8@1+ (1,0) [0|0] \"\" B\n",
                 12, "appears twice");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S m1 : 0|8@1+ (1,0) [0|0] \"\" B\n", 11, "no multiplexer");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S M : 0|8@1+ (1,0) [0|0] \"\" B\n SG_ T M : 8|8@1+ (1,0) [0|0] \"\" B\n",
                 12, "second multiplexer");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S M : 0|8@1+ (1,0) [0|0] \"\" B\n SG_ T m1M : 8|8@1+ (1,0) [0|0] \"\" B\n",
                 12, "extended multiplexing");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S x1 : 0|8@1+ (1,0) [0|0] \"\" B\n", 11, "multiplexer indicator");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" C\n", 11, "receiver 'C'");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|8@1+ (1,0) [0|0] \"\"\n SG_ T : 8|8@1+ (1,0) [0|0] \"\" B\n", 12,
                 "expected a receiver");
    expect_error(HEAD "BO_ 100 M: 8 X\n", 10, "transmitter 'X'");
    expect_error(HEAD "BO_ 100 M: 65 A\n", 10, "larger than 64");
    expect_error(HEAD "BO_ 100 M 8 A\n", 10, "expected ':' after the message name");
    expect_error(HEAD "BO_ 4294967296 M: 8 A\n", 10, "out of range");
    expect_error(HEAD "BO_ -1 M: 8 A\n", 10, "whole number");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" B\n\nCM_ BO_ 101 \"x\";\n", 13,
                 "no BO_ defines");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" B\n\nCM_ SG_ 100 T \"x\";\n", 13,
                 "does not have");
    expect_error(HEAD "CM_ BU_ Z \"x\";\n", 10, "BU_ does not list");
    expect_error(HEAD "CM_ \"network\"\nBO_ 100 M: 8 A\n", 11, "expected ';' after the comment");
    expect_error(HEAD "BO_ 100 M: 8 A\n\nBA_ \"GenMsgCycleTime\" BO_ 100 10;\n", 12, "not defined for messages");
    expect_error(HEAD "BO_ 100 M: 8 A\n\nBA_DEF_ BO_ \"C\" INT 0 1000;\nBA_ \"C\" BO_ 100 1001;\n", 13, "outside");
    expect_error(HEAD "BO_ 100 M: 8 A\n\nBA_DEF_ BO_ \"C\" INT 0 1000;\nBA_ \"C\" BO_ 100 \"x\";\n", 13,
                 "takes a number");
    expect_error(HEAD "BO_ 100 M: 8 A\n\nBA_DEF_ BO_ \"C\" INT 0 1000;\nBA_ \"C\" BO_ 100 1.5;\n", 13,
                 "whole number");
    expect_error(HEAD "BO_ 100 M: 8 A\n\nBA_DEF_ BO_ \"E\" ENUM \"a\",\"b\";\nBA_ \"E\" BO_ 100 2;\n", 13,
                 "outside the enumeration");
    expect_error(HEAD "BA_DEF_ \"E\" ENUM \"a\",\"b\";\nBA_DEF_DEF_ \"E\" \"c\";\n", 11, "not a value");
    expect_error(HEAD "BA_DEF_DEF_ \"Q\" 1;\n", 10, "no BA_DEF_ defines");
    expect_error(HEAD "BA_DEF_ BO_ \"C\" INT 0 1;\nBA_DEF_ BO_ \"C\" INT 0 1;\n", 11, "defined twice");
    expect_error(HEAD "BA_DEF_ BO_ \"C\" NUMBER 0 1;\n", 10, "INT, HEX, FLOAT, STRING or ENUM");
    expect_error(HEAD "BA_DEF_ BO_ \"C\" INT 0 1\n", 11, "expected ';'");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" B\n\nVAL_ 100 T 0 \"x\" ;\n", 13,
                 "does not have");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" B\n\nVAL_ 100 S 0 \"x\" 1 ;\n", 13,
                 "value description");
    expect_error(HEAD "FOO_ 1 2 3;\n", 10, "unknown keyword 'FOO_'");
    expect_error(HEAD "VAL_TABLE_ T 1 \"a\"\n", 10, "no closing ';'");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|8@1+ (1x,0) [0|0] \"\" B\n", 11, "malformed number");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|8@1+ (1e999,0) [0|0] \"\" B\n", 11, "out of range");
    expect_error(HEAD "BO_ 100 M: 8 A # x\n", 10, "unexpected character '#'");
    expect_error(HEAD "BO_ 100 M: 8 A\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" B\n SG_ T : 7|9@0+ (1,0) [0|0] \"\" B\n"
                      "BO_ 101 N: 1 A\n SG_ U : 0|2@0+ (1,0) [0|0] \"\" B\n",
                 14, "does not fit");
    expect_error("VERSION \"\"\nVERSION \"\"\n", 2, "second VERSION");
    expect_error(HEAD "BU_: A\n", 10, "listed twice");
    expect_error("\n\n\"dangling\"", 3, "expected a keyword");

    dbc_error_t err;
    char nul[] = "VERSION \"\"\nBU_: A\0B\n";
    dbc_t *d = NULL;
    assert_int_equal(dbc_parse_text(nul, sizeof nul - 1U, &d, &err), -1);
    assert_null(d);
    assert_int_equal(err.line, 2);
    assert_non_null(strstr(err.message, "NUL byte"));
    char path[300];
    (void)snprintf(path, sizeof path, "%s/no-such-file.dbc", g_tmpdir);
    assert_int_equal(dbc_parse_file(path, &d, &err), -1);
    assert_int_equal(err.line, 0);
    assert_non_null(strstr(err.message, "cannot open"));
    assert_int_equal(dbc_parse_text("", 0U, NULL, &err), -1);
    assert_int_equal(dbc_parse_text("", 0U, &d, NULL), 0); /* an empty file is an empty network */
    assert_int_equal(d->n_messages, 0);
    dbc_free(d);
    dbc_free(NULL);
}

static void test_reader_accepts_the_whole_format(void **state)
{
    (void)state;
    static const char text[] =
        "VERSION \"v \\\"2\\\"\"\n"
        "NS_ :\n\tNS_DESC_\n\tCM_\n\tBA_DEF_\n\tVAL_\n\n"
        "BS_: 500 : 12,34\n"
        "BU_: A B\n"
        "VAL_TABLE_ Onoff 1 \"On\" 0 \"Off\" ;\n"
        "BO_ 3221225472 VECTOR__INDEPENDENT_SIG_MSG: 0 Vector__XXX\n"
        " SG_ Free : 0|8@1+ (1,0) [0|0] \"\" Vector__XXX\n"
        "BO_ 2566844672 M1: 8 A\n"
        " SG_ Moto : 7|12@0- (1E-3,-0.5) [-1.5|+2.5] \"m/s\" A,B\n"
        " SG_ Spaced : 16|8@1+ (.5,0) [0|127.5] \"%\" A B\n"
        " SG_ Sel M : 24|2@1+ (1,0) [0|3] \"\" B\n"
        " SG_ Sel2 m2 : 26|6@1+ (1,0) [0|63] \"\" B\n"
        "BO_ 17 Std: 1 B\n"
        " SG_ Bit : 0|1@1+ (1,0) [0|1] \"\" A\n"
        "BO_TX_BU_ 2566844672 : A,B;\n"
        "EV_ Env: 0 [0|1] \"\" 0 1 DUMMY_NODE_VECTOR0 Vector__XXX;\n"
        "CM_ \"net\nwork\";\n"
        "CM_ BO_ 17 \"std\";\n"
        "CM_ EV_ Env \"env\";\n"
        "BA_DEF_ BU_ \"Addr\" HEX 0 255;\n"
        "BA_DEF_ \"Name\" STRING ;\n"
        "BA_DEF_ SG_ \"Gain\" FLOAT -1 1.5;\n"
        "BA_DEF_ BO_ \"Kind\" ENUM \"x\",\"y\",\"z\";\n"
        "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 0;\n"
        "BA_DEF_REL_ BU_SG_REL_ \"R\" INT 0 1;\n"
        "BA_DEF_DEF_ \"Kind\" \"y\";\n"
        "BA_DEF_DEF_ \"Name\" \"n\";\n"
        "BA_ \"Name\" \"pfe\";\n"
        "BA_ \"Addr\" BU_ A 140;\n"
        "BA_ \"Gain\" SG_ 2566844672 Moto 0.25;\n"
        "BA_ \"GenMsgCycleTime\" BO_ 17 123456;\n"
        "BA_ \"Kind\" BO_ 17 2;\n"
        "BA_ \"GenMsgCycleTime\" BO_ 17 50;\n"
        "VAL_ 2566844672 Sel 3 \"three\" 0 \"zero\" -1 \"minus\" ;\n"
        "VAL_ Env 0 \"a\" ;\n"
        "SIG_VALTYPE_ 2566844672 Spaced : 1;\n";
    dbc_t *d = NULL;
    dbc_error_t err;
    if (dbc_parse_text(text, sizeof text - 1U, &d, &err) != 0) {
        fail_msg("line %d: %s", err.line, err.message);
    }
    assert_string_equal(d->version, "v \"2\"");
    assert_string_equal(d->comment, "net\nwork");
    assert_int_equal(d->n_nodes, 2);
    assert_int_equal(d->n_messages, 3);
    const dbc_message_t *m = dbc_message_by_id(d, 2566844672UL);
    assert_non_null(m);
    assert_ptr_equal(m, dbc_message_by_name(d, "M1"));
    assert_int_equal(m->n_signals, 4);
    const dbc_signal_t *s = dbc_signal_by_name(m, "Moto");
    assert_false(s->little_endian);
    assert_true(s->is_signed);
    assert_string_equal(s->factor_text, "1E-3");
    ASSERT_EQ(s->factor, 1e-3);
    ASSERT_EQ(s->offset, -0.5);
    ASSERT_EQ(s->max, 2.5);
    assert_string_equal(s->unit, "m/s");
    assert_int_equal(s->n_receivers, 2);
    s = dbc_signal_by_name(m, "Spaced");
    assert_int_equal(s->n_receivers, 2);
    assert_string_equal(s->receivers[1], "B");
    ASSERT_EQ(s->factor, 0.5);
    s = dbc_signal_by_name(m, "Sel");
    assert_int_equal(s->mux_kind, DBC_MUX_MULTIPLEXOR);
    assert_int_equal(s->n_values, 3);
    assert_int_equal(s->values[2].value, -1);
    assert_string_equal(s->values[0].text, "three");
    s = dbc_signal_by_name(m, "Sel2");
    assert_int_equal(s->mux_kind, DBC_MUX_MULTIPLEXED);
    assert_int_equal(s->mux_value, 2);
    assert_null(dbc_signal_by_name(m, "Nope"));
    const dbc_message_t *std_msg = dbc_message_by_name(d, "Std");
    assert_int_equal(std_msg->id, 17);
    assert_string_equal(std_msg->comment, "std");
    int64_t v = -1;
    assert_int_equal(dbc_message_attr_int(d, std_msg, "GenMsgCycleTime", &v), 0);
    assert_int_equal(v, 50);                            /* last value wins; INT 0 0 has no bound */
    assert_int_equal(dbc_message_attr_int(d, std_msg, "Kind", &v), 0);
    assert_int_equal(v, 2);
    assert_int_equal(dbc_message_attr_int(d, m, "Kind", &v), 0);
    assert_int_equal(v, 1);                             /* default "y" */
    assert_int_equal(dbc_message_attr_int(d, m, "GenMsgCycleTime", &v), -1); /* no value, no default */
    assert_int_equal(dbc_message_attr_int(d, m, "Nope", &v), -1);
    assert_int_equal(dbc_node_attr_int(d, &d->nodes[0], "Addr", &v), 0);
    assert_int_equal(v, 140);
    assert_int_equal(dbc_signal_attr_int(d, dbc_signal_by_name(m, "Moto"), "Gain", &v), -1); /* FLOAT */
    assert_non_null(dbc_attr_def(d, DBC_OBJ_NETWORK, "Name"));
    assert_null(dbc_attr_def(d, DBC_OBJ_MESSAGE, "Name"));
    dbc_free(d);
}

static void test_decimal_to_rational(void **state)
{
    (void)state;
    int64_t n;
    int64_t q;
    assert_int_equal(dbc_decimal_to_rational("0.00390625", &n, &q), 0);
    assert_int_equal(n, 390625);
    assert_int_equal(q, 100000000);
    assert_int_equal(dbc_decimal_to_rational("-64", &n, &q), 0);
    assert_int_equal(n, -64);
    assert_int_equal(q, 1);
    assert_int_equal(dbc_decimal_to_rational("64.510", &n, &q), 0);
    assert_int_equal(n, 6451);
    assert_int_equal(q, 100);
    assert_int_equal(dbc_decimal_to_rational("1E-3", &n, &q), 0);
    assert_int_equal(n, 1);
    assert_int_equal(q, 1000);
    assert_int_equal(dbc_decimal_to_rational("2.5e2", &n, &q), 0);
    assert_int_equal(n, 250);
    assert_int_equal(q, 1);
    assert_int_equal(dbc_decimal_to_rational("+.5", &n, &q), 0);
    assert_int_equal(n, 5);
    assert_int_equal(q, 10);
    assert_int_equal(dbc_decimal_to_rational("4211081.215", &n, &q), 0);
    assert_int_equal(n, 4211081215LL);
    assert_int_equal(q, 1000);
    assert_int_equal(dbc_decimal_to_rational("0", &n, &q), 0);
    assert_int_equal(n, 0);
    assert_int_equal(q, 1);
    assert_int_equal(dbc_decimal_to_rational("1.2.3", &n, &q), -1);
    assert_int_equal(dbc_decimal_to_rational("abc", &n, &q), -1);
    assert_int_equal(dbc_decimal_to_rational("", &n, &q), -1);
    assert_int_equal(dbc_decimal_to_rational("1e", &n, &q), -1);
    assert_int_equal(dbc_decimal_to_rational("1234567890123456789", &n, &q), -1);
    assert_int_equal(dbc_decimal_to_rational("1e30", &n, &q), -1);
}

/* Every prefix of pfe.dbc, and copies with bytes replaced, either parse or
 * fail cleanly (the sanitizers watch memory and leaks). */
static void test_reader_survives_damaged_input(void **state)
{
    (void)state;
    FILE *f = fopen(g_dbc_path, "rb");
    assert_non_null(f);
    static char buf[1 << 17];
    const size_t len = fread(buf, 1U, sizeof buf, f);
    (void)fclose(f);
    ASSERT_GT(len, 1000U);
    ASSERT_LT(len, sizeof buf);
    size_t failures = 0U;
    for (size_t cut = 0U; cut <= len; cut += 3U) {
        dbc_t *d = NULL;
        dbc_error_t err;
        if (dbc_parse_text(buf, cut, &d, &err) != 0) {
            assert_null(d);
            assert_int_not_equal(err.message[0], '\0');
            failures++;
        } else {
            dbc_free(d);
        }
    }
    ASSERT_GT(failures, 0U);
    static char copy[1 << 17];
    static const char junk[] = {'"', ';', ':', '|', '@', '(', ')', '[', ']', ',', '-', '+', '0', '9', 'M',
                                'm', ' ', '\n', '\t', '\0', '\x80', '\xFF', '.', 'e', 'Z'};
    for (int trial = 0; trial < 3000; trial++) {
        memcpy(copy, buf, len);
        const int edits = 1 + (rand8() % 4);
        for (int e = 0; e < edits; e++) {
            const size_t at = (((size_t)rand8() << 16) | ((size_t)rand8() << 8) | rand8()) % len;
            copy[at] = junk[rand8() % sizeof junk];
        }
        dbc_t *d = NULL;
        dbc_error_t err;
        if (dbc_parse_text(copy, len, &d, &err) == 0) {
            dbc_free(d);
        } else {
            assert_null(d);
            ASSERT_GE(err.line, 0);
        }
    }
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s can_dbc/pfe.dbc\n", argv[0]);
        return 2;
    }
    g_dbc_path = argv[1];
    const char *tmp = getenv("TMPDIR");
    (void)snprintf(g_tmpdir, sizeof g_tmpdir, "%s/pfe_dbc_XXXXXX", (tmp != NULL) ? tmp : "/tmp");
    if (mkdtemp(g_tmpdir) == NULL) {
        perror("mkdtemp");
        return 2;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_codec_message_is_in_the_dbc),
        cmocka_unit_test(test_generated_header_matches_the_dbc),
        cmocka_unit_test(test_every_codec_signal_matches_the_dbc),
        cmocka_unit_test(test_every_dbc_signal_is_in_the_codec),
        cmocka_unit_test(test_value_tables_match_the_codec),
        cmocka_unit_test(test_codec_bits_follow_the_dbc),
        cmocka_unit_test(test_firmware_units_follow_the_dbc),
        cmocka_unit_test(test_grade_from_pitch_every_raw),
        cmocka_unit_test(test_reader_reports_errors_with_lines),
        cmocka_unit_test(test_reader_accepts_the_whole_format),
        cmocka_unit_test(test_decimal_to_rational),
        cmocka_unit_test(test_reader_survives_damaged_input),
    };
    const int rc = cmocka_run_group_tests(tests, load_dbc, free_dbc);
    (void)rmdir(g_tmpdir);
    return rc;
}
