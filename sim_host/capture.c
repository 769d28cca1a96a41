/* capture.c - candump log files (contract in capture.h). */
#include "capture.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int fail(char *why, size_t why_len, const char *fmt, ...)
{
    if ((why != NULL) && (why_len > 0U)) {
        va_list ap;
        va_start(ap, fmt);
        (void)vsnprintf(why, why_len, fmt, ap);
        va_end(ap);
    }
    return -1;
}

static int hexval(char c)
{
    if ((c >= '0') && (c <= '9')) {
        return c - '0';
    }
    if ((c >= 'A') && (c <= 'F')) {
        return c - 'A' + 10;
    }
    if ((c >= 'a') && (c <= 'f')) {
        return c - 'a' + 10;
    }
    return -1;
}

static bool is_digit(char c)
{
    return (c >= '0') && (c <= '9');
}

/* The printable form of a character for a message. */
static const char *show(char c, char buf[8])
{
    if (c == '\0') {
        return "end of line";
    }
    if ((unsigned char)c < 0x20U || (unsigned char)c >= 0x7FU) {
        (void)snprintf(buf, 8, "0x%02X", (unsigned)(unsigned char)c);
    } else {
        buf[0] = '\'';
        buf[1] = c;
        buf[2] = '\'';
        buf[3] = '\0';
    }
    return buf;
}

/* "(SECONDS.FRACTION)": advances *p past it. */
static int parse_time(const char **p, uint64_t *t_us, char *why, size_t why_len)
{
    const char *s = *p;
    if (*s != '(') {
        return fail(why, why_len, "expected '(' and a timestamp at the start of the line");
    }
    s++;
    uint64_t sec = 0U;
    int n = 0;
    while (is_digit(*s)) {
        if (n == 10) {
            return fail(why, why_len, "timestamp seconds longer than 10 digits");
        }
        sec = (sec * 10U) + (uint64_t)(*s - '0');
        s++;
        n++;
    }
    if ((n == 0) || (*s != '.')) {
        return fail(why, why_len, "timestamp: expected (SECONDS.FRACTION)");
    }
    s++;
    uint64_t frac = 0U;
    int m = 0;
    while (is_digit(*s) && (m < 10)) {
        frac = (frac * 10U) + (uint64_t)(*s - '0');
        s++;
        m++;
    }
    if ((m != 6) && (m != 9)) {
        return fail(why, why_len, "timestamp fraction has %d digits, not 6 or 9", m);
    }
    if (*s != ')') {
        return fail(why, why_len, "timestamp: expected ')' after the fraction");
    }
    *t_us = (sec * 1000000U) + ((m == 9) ? (frac / 1000U) : frac);
    *p = s + 1;
    return 0;
}

/* Hex bytes, optionally split by '.', up to max; advances *p. */
static int parse_data(const char **p, uint8_t *data, uint8_t max, uint8_t *len, const char *what,
                      char *why, size_t why_len)
{
    const char *s = *p;
    unsigned n = 0U;
    char b[8];
    for (;;) {
        if (*s == '.') {
            s++;
            continue;
        }
        const int hi = hexval(*s);
        if (hi < 0) {
            break;
        }
        const int lo = hexval(s[1]);
        if (lo < 0) {
            if ((s[1] == '\0') || (s[1] == ' ') || (s[1] == '\t') || (s[1] == '\r') || (s[1] == '_')) {
                return fail(why, why_len, "odd number of hex digits in the data");
            }
            return fail(why, why_len, "bad hex digit %s in the data", show(s[1], b));
        }
        if (n == max) {
            return fail(why, why_len, "more than %u data bytes (%s)", (unsigned)max, what);
        }
        data[n++] = (uint8_t)((hi << 4) | lo);
        s += 2;
    }
    *len = (uint8_t)n;
    *p = s;
    return 0;
}

/* The frame field "ID#..." up to the next blank; advances *p. */
static int parse_frame(const char **p, capture_line_t *out, char *why, size_t why_len)
{
    const char *s = *p;
    char b[8];
    uint32_t id = 0U;
    int digits = 0;
    while (hexval(*s) >= 0) {
        if (digits == 8) {
            return fail(why, why_len, "CAN id longer than 8 hex digits");
        }
        id = (id << 4) | (uint32_t)hexval(*s);
        s++;
        digits++;
    }
    if (digits == 0) {
        return fail(why, why_len, "bad CAN id: %s is not a hex digit", show(*s, b));
    }
    if (*s != '#') {
        return fail(why, why_len, "expected '#' after the CAN id, found %s", show(*s, b));
    }
    if (digits == 3) {
        if (id > 0x7FFU) {
            return fail(why, why_len, "11-bit CAN id %03X above 7FF", (unsigned)id);
        }
        out->extended = false;
    } else if (digits == 8) {
        if (id > (CAPTURE_ERR_FLAG | PFE_CAN_ID_MASK)) {
            return fail(why, why_len, "CAN id %08lX above 3FFFFFFF", (unsigned long)id);
        }
        out->extended = true;
    } else {
        return fail(why, why_len, "CAN id has %d hex digits, not 3 or 8", digits);
    }
    s++;
    out->len8_dlc = 0U;
    out->fd_flags = 0U;
    out->len = 0U;
    if (out->extended && ((id & CAPTURE_ERR_FLAG) != 0U)) {
        out->kind = CAPTURE_ERROR;
        id &= PFE_CAN_ID_MASK;
    } else if (*s == '#') {
        out->kind = CAPTURE_FD;
        s++;
        const int fl = hexval(*s);
        if (fl < 0) {
            return fail(why, why_len, "CAN FD: expected a flags hex digit after '##', found %s",
                        show(*s, b));
        }
        out->fd_flags = (uint8_t)fl;
        s++;
    } else if ((*s == 'R') || (*s == 'r')) {
        out->kind = CAPTURE_REMOTE;
        s++;
        if (is_digit(*s)) {
            if (*s > '8') {
                return fail(why, why_len, "remote frame DLC %c above 8", *s);
            }
            out->len = (uint8_t)(*s - '0');
            s++;
        }
    } else {
        out->kind = CAPTURE_CLASSIC;
    }
    out->id = id;
    if ((out->kind == CAPTURE_CLASSIC) || (out->kind == CAPTURE_ERROR)) {
        if (parse_data(&s, out->data, 8U, &out->len, "classic CAN", why, why_len) != 0) {
            return -1;
        }
    } else if (out->kind == CAPTURE_FD) {
        if (parse_data(&s, out->data, (uint8_t)CAPTURE_FD_MAX_LEN, &out->len, "CAN FD", why,
                       why_len) != 0) {
            return -1;
        }
    }
    if ((*s == '_') && (out->kind != CAPTURE_FD)) {
        const int d = hexval(s[1]);
        if ((out->len != 8U) || (d < 9)) {
            return fail(why, why_len, "raw DLC '_%c' needs 8 data bytes and a DLC of 9 to F",
                        (s[1] != '\0') ? s[1] : '?');
        }
        out->len8_dlc = (uint8_t)d;
        s += 2;
    }
    if ((*s != '\0') && (*s != ' ') && (*s != '\t') && (*s != '\r')) {
        return fail(why, why_len, "bad character %s in the frame", show(*s, b));
    }
    *p = s;
    return 0;
}

static const char *skip_blanks(const char *s)
{
    while ((*s == ' ') || (*s == '\t')) {
        s++;
    }
    return s;
}

int capture_parse_line(const char *line, capture_line_t *out, unsigned long *dropped, char *why,
                       size_t why_len)
{
    const char *s = skip_blanks(line);
    if ((*s == '\0') || (*s == '\r') || (*s == '#')) {
        return CAPTURE_LINE_SKIP;
    }
    if (strncmp(s, "DROPCOUNT:", 10U) == 0) {
        unsigned long n = 0U;
        if (sscanf(s, "DROPCOUNT: dropped %lu", &n) != 1) {
            return fail(why, why_len, "DROPCOUNT line without a count");
        }
        *dropped = n;
        return CAPTURE_LINE_DROPS;
    }
    capture_line_t l;
    if (parse_time(&s, &l.t_us, why, why_len) != 0) {
        return -1;
    }
    if ((*s != ' ') && (*s != '\t')) {
        return fail(why, why_len, "expected a blank after the timestamp");
    }
    s = skip_blanks(s);
    size_t n = 0U;
    while ((s[n] != '\0') && (s[n] != ' ') && (s[n] != '\t') && (s[n] != '\r')) {
        n++;
    }
    if (n == 0U) {
        return fail(why, why_len, "truncated line: no interface name");
    }
    if (n > CAPTURE_IFNAME_MAX) {
        return fail(why, why_len, "interface name longer than %u characters",
                    (unsigned)CAPTURE_IFNAME_MAX);
    }
    memcpy(l.iface, s, n);
    l.iface[n] = '\0';
    s = skip_blanks(s + n);
    if ((*s == '\0') || (*s == '\r')) {
        return fail(why, why_len, "truncated line: no frame after the interface name");
    }
    if (parse_frame(&s, &l, why, why_len) != 0) {
        return -1;
    }
    s = skip_blanks(s);
    if (((*s == 'R') || (*s == 'T')) && ((s[1] == '\0') || (s[1] == '\r') || (s[1] == ' '))) {
        s = skip_blanks(s + 1);
    }
    if (*s == '\r') {
        s++;
    }
    if (*s != '\0') {
        return fail(why, why_len, "unexpected text after the frame");
    }
    *out = l;
    return CAPTURE_LINE_FRAME;
}

void capture_free(capture_t *cap)
{
    if (cap == NULL) {
        return;
    }
    free(cap->recs);
    memset(cap, 0, sizeof *cap);
}

/* One line into buf (without the LF). 1 line, 0 end of file, -1 error. */
static int read_line(FILE *in, char *buf, size_t cap, char *why, size_t why_len)
{
    size_t n = 0U;
    int c;
    while ((c = getc(in)) != EOF) {
        if (c == '\n') {
            break;
        }
        if (c == '\0') {
            return fail(why, why_len, "NUL byte: not a text log");
        }
        if ((c < 0x20) && (c != '\t') && (c != '\r')) {
            return fail(why, why_len, "control character 0x%02X: not a text log", (unsigned)c);
        }
        if (n == cap - 1U) {
            return fail(why, why_len, "line longer than %zu characters", cap - 1U);
        }
        buf[n++] = (char)c;
    }
    if (ferror(in)) {
        return fail(why, why_len, "read error: %s", strerror(errno));
    }
    buf[n] = '\0';
    return ((c == EOF) && (n == 0U)) ? 0 : 1;
}

int capture_load(const char *path, capture_t *cap, char *err, size_t err_len)
{
    memset(cap, 0, sizeof *cap);
    if (path == NULL) {
        return fail(err, err_len, "no file name");
    }
    FILE *in = fopen(path, "r");
    if (in == NULL) {
        return fail(err, err_len, "%s: %s", path, strerror(errno));
    }
    char buf[CAPTURE_MAX_LINE + 1U];
    char why[160];
    size_t room = 0U;
    unsigned long lineno = 0U;
    uint64_t last_us = 0U;
    size_t frames = 0U;
    int rc = 0;
    for (;;) {
        const int r = read_line(in, buf, sizeof buf, why, sizeof why);
        if (r == 0) {
            break;
        }
        lineno++;
        if (r < 0) {
            rc = fail(err, err_len, "%s:%lu: %s", path, lineno, why);
            break;
        }
        capture_line_t l;
        unsigned long drops = 0U;
        const int kind = capture_parse_line(buf, &l, &drops, why, sizeof why);
        if (kind < 0) {
            rc = fail(err, err_len, "%s:%lu: %s", path, lineno, why);
            break;
        }
        if (kind == CAPTURE_LINE_DROPS) {
            cap->dropped += drops;
        }
        if (kind != CAPTURE_LINE_FRAME) {
            continue;
        }
        if ((frames > 0U) && (l.t_us < last_us)) {
            rc = fail(err, err_len,
                      "%s:%lu: timestamp goes backwards (%llu.%06llu after %llu.%06llu)", path,
                      lineno, (unsigned long long)(l.t_us / 1000000U),
                      (unsigned long long)(l.t_us % 1000000U),
                      (unsigned long long)(last_us / 1000000U),
                      (unsigned long long)(last_us % 1000000U));
            break;
        }
        last_us = l.t_us;
        frames++;
        if ((l.kind == CAPTURE_CLASSIC) && !l.extended) {
            cap->skipped_standard++;
            continue;
        }
        if (l.kind == CAPTURE_REMOTE) {
            cap->skipped_remote++;
            continue;
        }
        if (l.kind == CAPTURE_FD) {
            cap->skipped_fd++;
            continue;
        }
        if (l.kind == CAPTURE_ERROR) {
            cap->skipped_error++;
            continue;
        }
        if (cap->n == room) {
            room = (room == 0U) ? 4096U : (room * 2U);
            capture_rec_t *grown = realloc(cap->recs, room * sizeof *grown);
            if (grown == NULL) {
                rc = fail(err, err_len, "%s:%lu: out of memory", path, lineno);
                break;
            }
            cap->recs = grown;
        }
        capture_rec_t *rec = &cap->recs[cap->n++];
        rec->t_us = l.t_us;
        rec->line = lineno;
        rec->f.id = l.id | PFE_CAN_EFF_FLAG;
        rec->f.dlc = l.len;
        memset(rec->f.data, 0, sizeof rec->f.data);
        memcpy(rec->f.data, l.data, l.len);
    }
    fclose(in);
    if ((rc == 0) && (frames == 0U)) {
        rc = fail(err, err_len, "%s: no CAN frames (%lu lines)", path, lineno);
    }
    if (rc != 0) {
        capture_free(cap);
        return -1;
    }
    cap->lines = lineno;
    return 0;
}
