/* log_candump.c - the candump log form, "(SECONDS) IFACE ID#DATA", read and written (contract in log.h). */
#define _POSIX_C_SOURCE 200809L

#include "lib/log/log_parse.h"

#include <stdio.h>
#include <string.h>

/* ------------------------------------------------------------------ candump log */

/* The frame part "ID#DATA" (and its variants) at *pp, up to a blank or the
 * end of the line. */
static int parse_compact_frame(canlog_reader_t *r, const char **pp, canlog_frame_t *f)
{
    const char *p = *pp;
    char cbuf[16];
    uint32_t v = 0U;
    int digits = 0;
    for (;; p++) {
        const char c = *p;
        if (c == '#') {
            break;
        }
        const int h = hex_digit(c);
        if (h < 0) {
            if (is_end(c)) {
                return log_fail(r, CANLOG_E_TRUNCATED, "no '#' after the id");
            }
            return log_fail(r, CANLOG_E_BAD_HEX, "%s in the id", log_show_char(c, cbuf));
        }
        if (digits < 8) {
            v = (v << 4) | (uint32_t)h;
        }
        digits++;
    }
    p++; /* '#' */
    uint32_t id;
    int rc = log_make_id(r, digits, v, &id);
    if (rc != 0) {
        return rc;
    }
    f->fd = false;
    f->fd_flags = 0U;
    if ((*p == 'R') || (*p == 'r')) {
        p++;
        unsigned len = 0U;
        if (!is_end(*p)) {
            const int h = hex_digit(*p);
            if (h < 0) {
                return log_fail(r, CANLOG_E_BAD_HEX, "%s after 'R'", log_show_char(*p, cbuf));
            }
            len = (unsigned)h;
            p++;
            if (!is_end(*p)) {
                return log_fail(r, CANLOG_E_SYNTAX, "%s after the remote frame's length",
                            log_show_char(*p, cbuf));
            }
            if (len > CANLOG_MAX_DLEN) {
                return log_fail(r, CANLOG_E_DLC, "remote frame length %u over 8", len);
            }
        }
        f->id = id | CANLOG_RTR_FLAG;
        f->len = (uint8_t)len;
        *pp = p;
        return 0;
    }
    unsigned max = CANLOG_MAX_DLEN;
    if (*p == '#') {
        p++;
        const int h = hex_digit(*p);
        if (h < 0) {
            if (is_end(*p)) {
                return log_fail(r, CANLOG_E_TRUNCATED, "no FD flags digit after '##'");
            }
            return log_fail(r, CANLOG_E_BAD_HEX, "%s as the FD flags digit", log_show_char(*p, cbuf));
        }
        p++;
        f->fd = true;
        f->fd_flags = (uint8_t)h;
        max = CANLOG_FD_MAX_DLEN;
    }
    unsigned n = 0U;
    for (;;) {
        char c = *p;
        if (c == '.') {
            p++;
            continue;
        }
        if (is_end(c) || ((c == '_') && !f->fd)) {
            break;
        }
        const int hi = hex_digit(c);
        if (hi < 0) {
            return log_fail(r, CANLOG_E_BAD_HEX, "%s in the data", log_show_char(c, cbuf));
        }
        c = p[1];
        const int lo = hex_digit(c);
        if (lo < 0) {
            if (is_end(c) || (c == '.')) {
                return log_fail(r, CANLOG_E_TRUNCATED, "half a byte at the end of the data");
            }
            return log_fail(r, CANLOG_E_BAD_HEX, "%s in the data", log_show_char(c, cbuf));
        }
        if (n < max) {
            f->data[n] = (uint8_t)((hi << 4) | lo);
        }
        n++;
        p += 2;
    }
    if ((*p == '_') && !f->fd) {
        /* candump -8: the raw DLC 9..F of an 8-byte classic frame */
        const int d = hex_digit(p[1]);
        if ((n != CANLOG_MAX_DLEN) || (d < 9) || !is_end(p[2])) {
            return log_fail(r, CANLOG_E_DLC, "a raw DLC after '_' needs 8 data bytes and a DLC of 9 to F");
        }
        f->len8_dlc = (uint8_t)d;
        p += 2;
    }
    rc = log_check_len(r, f->fd, n);
    if (rc != 0) {
        return rc;
    }
    f->id = id;
    f->len = (uint8_t)n;
    *pp = p;
    return 0;
}

int log_parse_log_line(canlog_reader_t *r, const char *line, canlog_frame_t *f)
{
    const char *p = skip_blanks(line);
    char cbuf[16];
    if (*p != '(') {
        if (log_is_comment(p) || log_note_dropcount(r, p)) {
            return 1;
        }
        return log_fail(r, CANLOG_E_SYNTAX, "%s: a candump log line starts with '('",
                    log_show_char(*p, cbuf));
    }
    p++;
    uint64_t t;
    int sd;
    int rc = log_paren_seconds(r, &p, &t, &sd);
    if (rc != 0) {
        return rc;
    }
    const char *e = token_end(p);
    if (*e == '\0') {
        return log_fail(r, CANLOG_E_TRUNCATED, (e == p) ? "no interface and frame after the timestamp"
                                                    : "no frame after the interface");
    }
    rc = log_take_iface(r, p, e, f);
    if (rc != 0) {
        return rc;
    }
    p = skip_blanks(e);
    if (*p == '\0') {
        return log_fail(r, CANLOG_E_TRUNCATED, "no frame after the interface");
    }
    rc = parse_compact_frame(r, &p, f);
    if (rc != 0) {
        return rc;
    }
    p = skip_blanks(p);
    f->dir = 0;
    if (((*p == 'R') || (*p == 'T')) && is_end(p[1])) {
        f->dir = *p;
        p = skip_blanks(p + 1);
    }
    if (*p != '\0') {
        return log_fail(r, CANLOG_E_SYNTAX, "%s after the frame", log_show_char(*p, cbuf));
    }
    f->channel = 0U;
    return log_accept_time(r, CANLOG_TB_EPOCH, t, &f->time_us);
}

/* ------------------------------------------------------------------ writer */

static const char hexdig[16] = {'0', '1', '2', '3', '4', '5', '6', '7',
                                '8', '9', 'A', 'B', 'C', 'D', 'E', 'F'};

/* Decimal of V with at least MIN digits, at p; returns the end. */
static char *put_dec(char *p, uint64_t v, int min)
{
    char tmp[24];
    int n = 0;
    do {
        tmp[n++] = (char)('0' + (v % 10U));
        v /= 10U;
    } while (v != 0U);
    while (n < min) {
        tmp[n++] = '0';
    }
    while (n > 0) {
        *p++ = tmp[--n];
    }
    return p;
}

size_t canlog_write_log(char *buf, size_t size, const canlog_frame_t *frame, const char *iface)
{
    if ((buf == NULL) || (frame == NULL)) {
        return 0U;
    }
    if (size < CANLOG_LOG_LINE_MAX) {
        /* write in a scratch line and copy what fits */
        char tmp[CANLOG_LOG_LINE_MAX];
        const size_t n = canlog_write_log(tmp, sizeof tmp, frame, iface);
        if ((n == 0U) || (n + 1U > size)) {
            if (size > 0U) {
                buf[0] = '\0';
            }
            return 0U;
        }
        memcpy(buf, tmp, n + 1U);
        return n;
    }
    const char *name = (iface != NULL) ? iface : frame->iface;
    const size_t nlen = strnlen(name, CANLOG_IFNAME_MAX);
    if ((nlen == 0U) || (nlen >= CANLOG_IFNAME_MAX)) {
        buf[0] = '\0';
        return 0U;
    }
    char *p = buf;
    *p++ = '(';
    p = put_dec(p, frame->time_us / 1000000U, 10);
    *p++ = '.';
    p = put_dec(p, frame->time_us % 1000000U, 6);
    *p++ = ')';
    *p++ = ' ';
    memcpy(p, name, nlen);
    p += nlen;
    *p++ = ' ';
    uint32_t id = frame->id;
    if ((id & CANLOG_ERR_FLAG) != 0U) {
        id &= CANLOG_EFF_MASK | CANLOG_ERR_FLAG;
        for (int s = 28; s >= 0; s -= 4) {
            *p++ = hexdig[(id >> s) & 0xFU];
        }
    } else if ((id & CANLOG_EFF_FLAG) != 0U) {
        id &= CANLOG_EFF_MASK;
        for (int s = 28; s >= 0; s -= 4) {
            *p++ = hexdig[(id >> s) & 0xFU];
        }
    } else {
        id &= CANLOG_SFF_MASK;
        *p++ = hexdig[(id >> 8) & 0xFU];
        *p++ = hexdig[(id >> 4) & 0xFU];
        *p++ = hexdig[id & 0xFU];
    }
    *p++ = '#';
    unsigned len = frame->len;
    if (!frame->fd && ((frame->id & CANLOG_RTR_FLAG) != 0U) && ((frame->id & CANLOG_ERR_FLAG) == 0U)) {
        *p++ = 'R';
        if ((len > 0U) && (len <= CANLOG_MAX_DLEN)) {
            *p++ = hexdig[len];
        }
    } else {
        if (frame->fd) {
            *p++ = '#';
            *p++ = hexdig[frame->fd_flags & 0xFU];
            if (len > CANLOG_FD_MAX_DLEN) {
                len = CANLOG_FD_MAX_DLEN;
            }
        } else if (len > CANLOG_MAX_DLEN) {
            len = CANLOG_MAX_DLEN;
        }
        for (unsigned i = 0U; i < len; i++) {
            *p++ = hexdig[frame->data[i] >> 4];
            *p++ = hexdig[frame->data[i] & 0xFU];
        }
        if (!frame->fd && (len == CANLOG_MAX_DLEN) && (frame->len8_dlc >= 9U) &&
            (frame->len8_dlc <= 15U)) {
            *p++ = '_';
            *p++ = hexdig[frame->len8_dlc];
        }
    }
    *p++ = '\n';
    *p = '\0';
    return (size_t)(p - buf);
}

