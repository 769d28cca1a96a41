/* log_printed.c - candump's printed output, with or without -t (contract in log.h). */
#define _POSIX_C_SOURCE 200809L

#include "lib/log/log_parse.h"

#include <stdio.h>
#include <string.h>

/* ------------------------------------------------------------------ candump printed output */

/* The optional timestamp at *pp: "(YYYY-MM-DD HH:MM:SS.FRACTION)" (-t A),
 * "(SECONDS.FRACTION)" with 10 or more digits of seconds (-t a, since the
 * epoch) or fewer (-t z, d: since the start), or none (*tb CANLOG_TB_NONE).
 * *pp then at the interface. 0, or -reason. */
static int printed_time(canlog_reader_t *r, const char **pp, canlog_time_base_t *tb, uint64_t *t)
{
    const char *p = *pp;
    *tb = CANLOG_TB_NONE;
    *t = 0U;
    if (*p != '(') {
        return 0;
    }
    p++;
    int rc;
    if (is_digit(p[0]) && is_digit(p[1]) && is_digit(p[2]) && is_digit(p[3]) && (p[4] == '-')) {
        int nf;
        if (log_parse_date(&p, t, &nf) != 0) {
            return log_fail(r, CANLOG_E_BAD_TIME, "expected (YYYY-MM-DD HH:MM:SS.FRACTION)");
        }
        *tb = CANLOG_TB_DATE;
        rc = log_paren_close(r, &p, nf);
    } else {
        int sd = 0;
        rc = log_paren_seconds(r, &p, t, &sd);
        *tb = (sd >= 10) ? CANLOG_TB_EPOCH : CANLOG_TB_START;
    }
    *pp = p;
    return rc;
}

/* candump -x's columns at *pp: "RX" or "TX", then '-' or 'B' (BRS), '-' or
 * 'E' (ESI), into f->dir and f->fd_flags; *have_x says whether they were
 * there. 0, or -reason. */
static int printed_direction(canlog_reader_t *r, const char **pp, canlog_frame_t *f, bool *have_x)
{
    const char *p = *pp;
    f->dir = 0;
    f->fd_flags = 0U;
    *have_x = false;
    if (!token_is(p, "RX") && !token_is(p, "TX")) {
        return 0;
    }
    f->dir = p[0] == 'R' ? 'R' : 'T';
    p = skip_blanks(p + 2);
    if (!(((*p == '-') || (*p == 'B')) && is_blank(p[1]))) {
        return log_fail(r, CANLOG_E_SYNTAX, "expected '-' or 'B' after %s", f->dir == 'R' ? "RX" : "TX");
    }
    const bool brs = *p == 'B';
    p = skip_blanks(p + 1);
    if (!(((*p == '-') || (*p == 'E')) && is_blank(p[1]))) {
        return log_fail(r, CANLOG_E_SYNTAX, "expected '-' or 'E' after the BRS column");
    }
    const bool esi = *p == 'E';
    *pp = skip_blanks(p + 1);
    f->fd_flags = (uint8_t)((brs ? CANLOG_FD_BRS : 0U) | (esi ? CANLOG_FD_ESI : 0U));
    *have_x = true;
    return 0;
}

/* The id's hex digits at *pp (3 for 11 bits, 8 for 29), *pp then past the
 * blanks after it. 0, or -reason. */
static int printed_id(canlog_reader_t *r, const char **pp, uint32_t *id)
{
    char cbuf[16];
    const char *p = *pp;
    uint32_t v = 0U;
    int digits = 0;
    for (; !is_end(*p); p++) {
        const int h = hex_digit(*p);
        if (h < 0) {
            return log_fail(r, CANLOG_E_BAD_HEX, "%s in the id", log_show_char(*p, cbuf));
        }
        if (digits < 8) {
            v = (v << 4) | (uint32_t)h;
        }
        digits++;
    }
    if (digits == 0) {
        return log_fail(r, CANLOG_E_TRUNCATED, "no id");
    }
    const int rc = log_make_id(r, digits, v, id);
    if (rc != 0) {
        return rc;
    }
    *pp = skip_blanks(p);
    return 0;
}

/* "[LEN]" at *pp: one digit classic, two CAN FD; *len_digits says which.
 * *pp then past the blanks after it. 0, or -reason. */
static int printed_len(canlog_reader_t *r, const char **pp, unsigned *len, int *len_digits)
{
    char cbuf[16];
    const char *p = *pp;
    if (*p != '[') {
        if (*p == '\0') {
            return log_fail(r, CANLOG_E_TRUNCATED, "no [length] after the id");
        }
        return log_fail(r, CANLOG_E_SYNTAX, "%s where [length] should follow the id",
                        log_show_char(*p, cbuf));
    }
    p++;
    unsigned n = 0U;
    int ld = 0;
    while (is_digit(*p)) {
        if (ld < 3) {
            n = (n * 10U) + (unsigned)(*p - '0');
        }
        ld++;
        p++;
    }
    if ((ld == 0) || (*p != ']')) {
        if (*p == '\0') {
            return log_fail(r, CANLOG_E_TRUNCATED, "line ends in the [length]");
        }
        return log_fail(r, CANLOG_E_SYNTAX, "[length] must be decimal digits");
    }
    if (ld > 2) {
        return log_fail(r, CANLOG_E_DLC, "length of %d digits", ld);
    }
    *len = n;
    *len_digits = ld;
    *pp = skip_blanks(p + 1);
    return 0;
}

/* "remote request" at p (a classic frame's [len] read), the rest of the
 * line: f gets the remote frame. 0, or -reason. */
static int printed_remote(canlog_reader_t *r, const char *p, uint32_t id, unsigned len, canlog_frame_t *f)
{
    char cbuf[16];
    if (len > CANLOG_MAX_DLEN) {
        return log_fail(r, CANLOG_E_DLC, "remote frame length %u over 8", len);
    }
    p = skip_blanks(p + 6);
    if (!token_is(p, "request")) {
        return log_fail(r, CANLOG_E_SYNTAX, "expected 'remote request'");
    }
    p = skip_blanks(p + 7);
    if (*p != '\0') {
        return log_fail(r, CANLOG_E_SYNTAX, "%s after 'remote request'", log_show_char(*p, cbuf));
    }
    f->id = id | CANLOG_RTR_FLAG;
    f->len = (uint8_t)len;
    return 0;
}

/* LEN data bytes at p, and what may follow them to the end of the line (an
 * ERRORFRAME mark, candump -a's ASCII column): f gets the data frame. 0, or
 * -reason. */
static int printed_data(canlog_reader_t *r, const char *p, uint32_t id, unsigned len, canlog_frame_t *f)
{
    char cbuf[16];
    const int rc = log_check_len(r, f->fd, len);
    if (rc != 0) {
        return rc;
    }
    for (unsigned i = 0U; i < len; i++) {
        if (*p == '\0') {
            return log_fail(r, CANLOG_E_TRUNCATED, "%u data bytes of [%u]", i, len);
        }
        const int hi = hex_digit(p[0]);
        const int lo = hex_digit(p[1]);
        if ((hi < 0) || (lo < 0) || !is_end(p[2])) {
            if ((*p == '\'') || token_is(p, "ERRORFRAME")) {
                return log_fail(r, CANLOG_E_TRUNCATED, "%u data bytes of [%u]", i, len);
            }
            const char *bad = (hi < 0) ? p : ((lo < 0) ? p + 1 : p + 2);
            return log_fail(r, CANLOG_E_BAD_HEX, "%s in data byte %u", log_show_char(*bad, cbuf), i);
        }
        f->data[i] = (uint8_t)((hi << 4) | lo);
        p = skip_blanks(p + 2);
    }
    f->id = id;
    f->len = (uint8_t)len;
    if (token_is(p, "ERRORFRAME")) {
        p = skip_blanks(p + 10);
    }
    if ((*p != '\0') && (*p != '\'') && (*p != '`')) {
        if ((hex_digit(p[0]) >= 0) && (hex_digit(p[1]) >= 0) && is_end(p[2])) {
            return log_fail(r, CANLOG_E_DLC, "more data bytes than [%u]", len);
        }
        return log_fail(r, CANLOG_E_SYNTAX, "%s after the data", log_show_char(*p, cbuf));
    }
    return 0;
}

/* The frame's time: -t d's deltas summed; a line without a timestamp only
 * where no earlier line had one. 0, or -reason. */
static int printed_timed(canlog_reader_t *r, canlog_time_base_t tb, uint64_t t, canlog_frame_t *f)
{
    f->channel = 0U;
    if (tb == CANLOG_TB_START && r->format == CANLOG_FMT_PRINTED_DELTA) {
        t += r->acc_time_us;
        r->acc_time_us = t;
    }
    if (tb == CANLOG_TB_NONE) {
        if ((r->time_base != CANLOG_TB_UNKNOWN) && (r->time_base != tb)) {
            return log_fail(r, CANLOG_E_BAD_TIME, "no timestamp where earlier lines had one");
        }
        r->time_base = tb;
        f->time_us = 0U;
        return 0;
    }
    return log_accept_time(r, tb, t, &f->time_us);
}

int log_parse_printed_line(canlog_reader_t *r, const char *line, canlog_frame_t *f)
{
    if (line[0] == '\t') {
        return 1; /* -e: the description lines under an error frame */
    }
    const char *p = skip_blanks(line);
    if (log_is_comment(p) || log_note_dropcount(r, p)) {
        return 1;
    }
    canlog_time_base_t tb;
    uint64_t t;
    int rc = printed_time(r, &p, &tb, &t);
    if (rc != 0) {
        return rc;
    }
    const char *e = token_end(p);
    if (*e == '\0') {
        return log_fail(r, CANLOG_E_TRUNCATED, "no id and length after the interface");
    }
    rc = log_take_iface(r, p, e, f);
    if (rc != 0) {
        return rc;
    }
    p = skip_blanks(e);
    bool have_x = false;
    uint32_t id = 0U;
    unsigned len = 0U;
    int len_digits = 0;
    if (((rc = printed_direction(r, &p, f, &have_x)) != 0) || ((rc = printed_id(r, &p, &id)) != 0) ||
        ((rc = printed_len(r, &p, &len, &len_digits)) != 0)) {
        return rc;
    }
    /* Two digits mean CAN FD, except before "remote request": CAN FD has no
     * remote frames, so that is a classic one written as [04]. */
    f->fd = (len_digits == 2) && !token_is(p, "remote");
    if (!f->fd && have_x && (f->fd_flags != 0U)) {
        return log_fail(r, CANLOG_E_SYNTAX, "FD flags on a classic frame");
    }
    if (!f->fd && token_is(p, "remote")) {
        rc = printed_remote(r, p, id, len, f);
    } else {
        rc = printed_data(r, p, id, len, f);
    }
    if (rc != 0) {
        return rc;
    }
    return printed_timed(r, tb, t, f);
}
