/* log_printed.c - candump's printed output, with or without -t (contract in log.h). */
#define _POSIX_C_SOURCE 200809L

#include "lib/log/log_parse.h"

#include <stdio.h>
#include <string.h>

/* ------------------------------------------------------------------ candump printed output */

int log_parse_printed_line(canlog_reader_t *r, const char *line, canlog_frame_t *f)
{
    char cbuf[16];
    if (line[0] == '\t') {
        return 1; /* -e: the description lines under an error frame */
    }
    const char *p = skip_blanks(line);
    if (log_is_comment(p) || log_note_dropcount(r, p)) {
        return 1;
    }
    canlog_time_base_t tb = CANLOG_TB_NONE;
    uint64_t t = 0U;
    if (*p == '(') {
        p++;
        int nf, sd;
        if (is_digit(p[0]) && is_digit(p[1]) && is_digit(p[2]) && is_digit(p[3]) &&
            (p[4] == '-')) {
            if (log_parse_date(&p, &t, &nf) != 0) {
                return log_fail(r, CANLOG_E_BAD_TIME, "expected (YYYY-MM-DD HH:MM:SS.FRACTION)");
            }
            tb = CANLOG_TB_DATE;
        } else {
            if (log_parse_seconds(&p, &t, &sd, &nf) != 0) {
                if (*p == '\0') {
                    return log_fail(r, CANLOG_E_TRUNCATED, "line ends in the timestamp");
                }
                return log_fail(r, CANLOG_E_BAD_TIME, "expected (SECONDS.FRACTION)");
            }
            tb = (sd >= 10) ? CANLOG_TB_EPOCH : CANLOG_TB_START;
        }
        if (*p != ')') {
            if (*p == '\0') {
                return log_fail(r, CANLOG_E_TRUNCATED, "line ends in the timestamp");
            }
            return log_fail(r, CANLOG_E_BAD_TIME, "%s where ')' should close the timestamp",
                        log_show_char(*p, cbuf));
        }
        if ((nf != 6) && (nf != 9)) {
            return log_fail(r, CANLOG_E_BAD_TIME, "%d fraction digits; 6 or 9 expected", nf);
        }
        p = skip_blanks(p + 1);
    }
    const char *e = token_end(p);
    if (*e == '\0') {
        return log_fail(r, CANLOG_E_TRUNCATED, "no id and length after the interface");
    }
    int rc = log_take_iface(r, p, e, f);
    if (rc != 0) {
        return rc;
    }
    p = skip_blanks(e);
    f->dir = 0;
    f->fd_flags = 0U;
    bool have_x = false;
    if ((token_is(p, "RX") || token_is(p, "TX"))) {
        /* -x: direction, then the BRS and ESI columns */
        f->dir = p[0] == 'R' ? 'R' : 'T';
        p = skip_blanks(p + 2);
        if (!(((*p == '-') || (*p == 'B')) && is_blank(p[1]))) {
            return log_fail(r, CANLOG_E_SYNTAX, "expected '-' or 'B' after %s",
                        f->dir == 'R' ? "RX" : "TX");
        }
        const bool brs = *p == 'B';
        p = skip_blanks(p + 1);
        if (!(((*p == '-') || (*p == 'E')) && is_blank(p[1]))) {
            return log_fail(r, CANLOG_E_SYNTAX, "expected '-' or 'E' after the BRS column");
        }
        const bool esi = *p == 'E';
        p = skip_blanks(p + 1);
        f->fd_flags = (uint8_t)((brs ? CANLOG_FD_BRS : 0U) | (esi ? CANLOG_FD_ESI : 0U));
        have_x = true;
    }
    /* id */
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
    uint32_t id;
    rc = log_make_id(r, digits, v, &id);
    if (rc != 0) {
        return rc;
    }
    p = skip_blanks(p);
    /* [len]: one digit classic, two digits CAN FD */
    if (*p != '[') {
        if (*p == '\0') {
            return log_fail(r, CANLOG_E_TRUNCATED, "no [length] after the id");
        }
        return log_fail(r, CANLOG_E_SYNTAX, "%s where [length] should follow the id",
                    log_show_char(*p, cbuf));
    }
    p++;
    unsigned len = 0U;
    int ld = 0;
    while (is_digit(*p)) {
        if (ld < 3) {
            len = (len * 10U) + (unsigned)(*p - '0');
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
    p = skip_blanks(p + 1);
    /* Two digits mean CAN FD, except before "remote request": CAN FD has no
     * remote frames, so that is a classic one written as [04]. */
    f->fd = (ld == 2) && !token_is(p, "remote");
    if (!f->fd) {
        if (have_x && (f->fd_flags != 0U)) {
            return log_fail(r, CANLOG_E_SYNTAX, "FD flags on a classic frame");
        }
        if (token_is(p, "remote")) {
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
            goto timed;
        }
    }
    rc = log_check_len(r, f->fd, len);
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
timed:
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

