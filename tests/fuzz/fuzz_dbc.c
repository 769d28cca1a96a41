/*
 * fuzz_dbc.c - libFuzzer target: the DBC reader of the host tools and tests
 * (sim_host/lib/dbc.h), seeded with can_dbc/pfe.dbc.
 *
 * Input: the DBC text.
 *
 * Invariants (abort on failure): it parses or fails with a sentence and a
 * line within the text (or 0); a failure gives no database; a database
 * holds what dbc.h promises: 1 to 64 bit signals inside their message's
 * length (0 to 64 bytes), unique message ids and names, unique signal
 * names in a message, a multiplexed signal only in a message with exactly
 * one multiplexer; every message is found by its id and its name, every
 * signal by its name; the attribute accessors answer without fault.
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "lib/dbc.h"
#include "fuzz_check.h"

/* Last bit (as the DBC numbers them) of a big-endian signal: the start bit
 * is its most significant bit, counting goes down within a byte and on to
 * the next byte's bit 7. -1 when it runs past bit 511. */
static int64_t motorola_last(uint32_t start, uint32_t length)
{
    int64_t bit = start;
    for (uint32_t k = 1U; k < length; k++) {
        bit = ((bit % 8) == 0) ? (bit + 15) : (bit - 1);
        if (bit > 511) {
            return -1;
        }
    }
    return bit;
}

static void check_message(const dbc_t *dbc, const dbc_message_t *m)
{
    FUZZ_CHECK(m->name != NULL);
    FUZZ_CHECK(m->dlc <= 64U);
    FUZZ_CHECK(dbc_message_by_id(dbc, m->id) == m);
    FUZZ_CHECK(dbc_message_by_name(dbc, m->name) == m);
    size_t muxers = 0U, muxed = 0U;
    for (size_t k = 0U; k < m->n_signals; k++) {
        const dbc_signal_t *s = &m->signals[k];
        FUZZ_CHECK(s->name != NULL);
        FUZZ_CHECK((s->length >= 1U) && (s->length <= 64U));
        const uint64_t bits = (uint64_t)m->dlc * 8U;
        if (s->little_endian) {
            FUZZ_CHECK(((uint64_t)s->start_bit + s->length) <= bits);
        } else {
            const int64_t last = motorola_last(s->start_bit, s->length);
            FUZZ_CHECK((s->start_bit < bits) && (last >= 0) && ((uint64_t)last < bits));
        }
        FUZZ_CHECK(dbc_signal_by_name(m, s->name) == s);
        muxers += (s->mux_kind == DBC_MUX_MULTIPLEXOR) ? 1U : 0U;
        muxed += (s->mux_kind == DBC_MUX_MULTIPLEXED) ? 1U : 0U;
        for (size_t a = 0U; a < s->n_attrs; a++) {
            int64_t v;
            (void)dbc_signal_attr_int(dbc, s, s->attrs[a].name, &v);
        }
        int64_t num, den;
        if (s->factor_text != NULL) {
            (void)dbc_decimal_to_rational(s->factor_text, &num, &den);
        }
    }
    FUZZ_CHECK(muxers <= 1U);
    FUZZ_CHECK((muxed == 0U) || (muxers == 1U));
    for (size_t a = 0U; a < m->n_attrs; a++) {
        int64_t v;
        (void)dbc_message_attr_int(dbc, m, m->attrs[a].name, &v);
    }
    for (size_t d = 0U; d < dbc->n_attr_defs; d++) {
        int64_t v;
        (void)dbc_message_attr_int(dbc, m, dbc->attr_defs[d].name, &v);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    dbc_t *dbc = (dbc_t *)1;
    dbc_error_t err;
    memset(&err, 0xA5, sizeof err);
    const int rc = dbc_parse_text((const char *)data, size, &dbc, &err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1);
        FUZZ_CHECK(dbc == NULL);
        FUZZ_CHECK(memchr(err.message, '\0', sizeof err.message) != NULL);
        FUZZ_CHECK(err.message[0] != '\0');
        size_t lines = 1U;
        for (size_t k = 0U; k < size; k++) {
            lines += (data[k] == '\n') ? 1U : 0U;
        }
        FUZZ_CHECK((err.line >= 0) && ((size_t)err.line <= lines));
        return 0;
    }
    FUZZ_CHECK(dbc != NULL);
    for (size_t k = 0U; k < dbc->n_messages; k++) {
        check_message(dbc, &dbc->messages[k]);
    }
    for (size_t k = 0U; k < dbc->n_nodes; k++) {
        FUZZ_CHECK(dbc->nodes[k].name != NULL);
        for (size_t d = 0U; d < dbc->n_attr_defs; d++) {
            int64_t v;
            (void)dbc_node_attr_int(dbc, &dbc->nodes[k], dbc->attr_defs[d].name, &v);
        }
    }
    for (size_t d = 0U; d < dbc->n_attr_defs; d++) {
        FUZZ_CHECK(dbc_attr_def(dbc, dbc->attr_defs[d].object, dbc->attr_defs[d].name) != NULL);
    }
    dbc_free(dbc);
    return 0;
}
