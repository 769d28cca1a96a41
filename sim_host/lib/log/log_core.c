/* canlog.c - CAN log reader and candump log writer (contract in canlog.h). */
#define _POSIX_C_SOURCE 200809L

#include "lib/log/log.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

/* ------------------------------------------------------------------ characters */

/* Value of a hex digit, or -1. */
static const int8_t hexval[256] = {
    ['0'] = 1, ['1'] = 2, ['2'] = 3, ['3'] = 4, ['4'] = 5, ['5'] = 6, ['6'] = 7, ['7'] = 8,
    ['8'] = 9, ['9'] = 10, ['A'] = 11, ['B'] = 12, ['C'] = 13, ['D'] = 14, ['E'] = 15,
    ['F'] = 16, ['a'] = 11, ['b'] = 12, ['c'] = 13, ['d'] = 14, ['e'] = 15, ['f'] = 16,
};
/* The table holds value + 1 so that every other entry can stay 0. */
static inline int hex_digit(char c)
{
    return (int)hexval[(unsigned char)c] - 1;
}

static inline bool is_digit(char c)
{
    return (c >= '0') && (c <= '9');
}

static inline bool is_blank(char c)
{
    return (c == ' ') || (c == '\t');
}

/* End of a token: blank or the end of the line (lines are NUL-terminated). */
static inline bool is_end(char c)
{
    return (c == '\0') || is_blank(c);
}

static inline const char *skip_blanks(const char *p)
{
    while (is_blank(*p)) {
        p++;
    }
    return p;
}

static inline const char *token_end(const char *p)
{
    while (!is_end(*p)) {
        p++;
    }
    return p;
}

static bool token_is(const char *p, const char *word)
{
    const size_t n = strlen(word);
    return (strncmp(p, word, n) == 0) && is_end(p[n]);
}

static bool starts_with(const char *p, const char *prefix)
{
    return strncmp(p, prefix, strlen(prefix)) == 0;
}

static bool starts_with_nocase(const char *p, const char *prefix)
{
    for (; *prefix != '\0'; p++, prefix++) {
        char a = *p;
        char b = *prefix;
        if ((a >= 'A') && (a <= 'Z')) {
            a = (char)(a - 'A' + 'a');
        }
        if ((b >= 'A') && (b <= 'Z')) {
            b = (char)(b - 'A' + 'a');
        }
        if (a != b) {
            return false;
        }
    }
    return true;
}

/* ------------------------------------------------------------------ errors */

static const char *const reason_texts[CANLOG_REASON_COUNT] = {
    [CANLOG_OK] = "ok",
    [CANLOG_E_LINE_TOO_LONG] = "line too long",
    [CANLOG_E_TRUNCATED] = "truncated line",
    [CANLOG_E_BAD_HEX] = "bad hex",
    [CANLOG_E_BAD_TIME] = "bad timestamp",
    [CANLOG_E_BAD_ID] = "bad id",
    [CANLOG_E_DLC] = "bad length",
    [CANLOG_E_BACKWARDS] = "timestamp going backwards",
    [CANLOG_E_SYNTAX] = "syntax error",
    [CANLOG_E_BINARY] = "binary content",
    [CANLOG_E_EMPTY] = "empty file",
    [CANLOG_E_FORMAT] = "unknown format",
    [CANLOG_E_IO] = "read error",
};

const char *canlog_reason_text(int reason)
{
    if (reason < 0) {
        reason = -reason;
    }
    if (reason >= (int)CANLOG_REASON_COUNT) {
        return "unknown error";
    }
    return reason_texts[reason];
}

const char *canlog_format_text(canlog_format_t format)
{
    switch (format) {
    case CANLOG_FMT_LOG:
        return "candump log";
    case CANLOG_FMT_PRINTED:
        return "candump output";
    case CANLOG_FMT_PRINTED_DELTA:
        return "candump output, delta timestamps";
    case CANLOG_FMT_ASC:
        return "Vector ASC";
    case CANLOG_FMT_AUTO:
    default:
        return "auto";
    }
}

const char *canlog_time_base_text(canlog_time_base_t tb)
{
    switch (tb) {
    case CANLOG_TB_EPOCH:
        return "seconds since 1970 (UTC)";
    case CANLOG_TB_DATE:
        return "printed date and time, read as UTC";
    case CANLOG_TB_START:
        return "seconds since the start of the recording";
    case CANLOG_TB_NONE:
        return "no timestamps";
    case CANLOG_TB_UNKNOWN:
    default:
        return "unknown";
    }
}

int canlog_format_parse(const char *text, canlog_format_t *out)
{
    static const struct {
        const char *name;
        canlog_format_t fmt;
    } names[] = {
        {"auto", CANLOG_FMT_AUTO},       {"log", CANLOG_FMT_LOG},
        {"printed", CANLOG_FMT_PRINTED}, {"printed-delta", CANLOG_FMT_PRINTED_DELTA},
        {"asc", CANLOG_FMT_ASC},
    };
    if ((text == NULL) || (out == NULL)) {
        return -1;
    }
    for (size_t i = 0U; i < sizeof names / sizeof names[0]; i++) {
        if (strcmp(text, names[i].name) == 0) {
            *out = names[i].fmt;
            return 0;
        }
    }
    return -1;
}

const char *canlog_message(const canlog_reader_t *r)
{
    return (r == NULL) ? "" : r->msg;
}

canlog_format_t canlog_format(const canlog_reader_t *r)
{
    return r->format;
}

void canlog_allow_backwards(canlog_reader_t *r, bool allow)
{
    r->backwards_ok = allow;
}

canlog_time_base_t canlog_time_base(const canlog_reader_t *r)
{
    return r->time_base;
}

/* Records a bad line: message, counters. Returns -reason. */
__attribute__((format(printf, 3, 4))) static int fail(canlog_reader_t *r, canlog_reason_t reason,
                                                      const char *fmt, ...)
{
    char detail[CANLOG_MSG_MAX / 2];
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(detail, sizeof detail, fmt, ap);
    va_end(ap);
    if ((reason == CANLOG_E_EMPTY) || (reason == CANLOG_E_IO)) {
        (void)snprintf(r->msg, sizeof r->msg, "%.200s: %s: %.200s", r->name,
                       reason_texts[reason], detail);
    } else {
        (void)snprintf(r->msg, sizeof r->msg, "%.200s:%llu: %s: %.200s", r->name,
                       (unsigned long long)r->line_no, reason_texts[reason], detail);
    }
    if (r->errors[reason] == 0U) {
        memcpy(r->first_msg[reason], r->msg, sizeof r->msg);
    }
    r->errors[reason]++;
    r->error_lines++;
    return -(int)reason;
}

/* A printable form of character C for messages. */
static const char *show_char(char c, char out[16])
{
    const unsigned char u = (unsigned char)c;
    if (c == '\0') {
        (void)snprintf(out, 16, "end of line");
    } else if ((u < 0x20U) || (u >= 0x7FU)) {
        (void)snprintf(out, 16, "\\x%02X", u);
    } else {
        (void)snprintf(out, 16, "'%c'", c);
    }
    return out;
}

/* NUL or a control character other than tab, CR, VT, FF in LEN bytes. */
static bool looks_binary(const char *s, size_t len)
{
    for (size_t i = 0U; i < len; i++) {
        const unsigned char u = (unsigned char)s[i];
        if (((u < 0x20U) && (u != '\t') && (u != '\r') && (u != '\v') && (u != '\f')) ||
            (u == 0x7FU)) {
            return true;
        }
    }
    return false;
}

/* ------------------------------------------------------------------ open, read */

static void reset_parse(canlog_reader_t *r)
{
    r->pos = 0U;
    r->end = 0U;
    r->eof = false;
    r->consumed_bytes = 0U;
    r->line_no = 0U;
    r->have_time = false;
    r->last_time_us = 0U;
    r->acc_time_us = 0U;
    r->saw_content = false;
    /* ASC header settings hold from their line on: a new pass starts
     * without them, as the first did. */
    r->asc_relative = false;
    r->asc_decimal = false;
}

static void set_name(canlog_reader_t *r, const char *name)
{
    (void)snprintf(r->name, sizeof r->name, "%s", (name != NULL) ? name : "<fd>");
}

static int open_common(canlog_reader_t *r, const char *name, canlog_format_t format,
                       canlog_error_mode_t mode)
{
    r->format = format;
    r->mode = mode;
    r->time_base = CANLOG_TB_UNKNOWN;
    r->lines = 0U;
    r->frames = 0U;
    r->comments = 0U;
    memset(r->errors, 0, sizeof r->errors);
    r->error_lines = 0U;
    r->dropped = 0U;
    r->backwards = 0U;
    r->backwards_ok = false;
    r->msg[0] = '\0';
    for (size_t i = 0U; i < (size_t)CANLOG_REASON_COUNT; i++) {
        r->first_msg[i][0] = '\0';
    }
    set_name(r, name);
    reset_parse(r);
    return 0;
}

int canlog_open_fd(canlog_reader_t *r, int fd, const char *name, canlog_format_t format,
                   canlog_error_mode_t mode)
{
    if ((r == NULL) || (fd < 0)) {
        return -(int)CANLOG_E_SYNTAX;
    }
    r->fd = fd;
    r->mem = NULL;
    r->mem_len = 0U;
    r->mem_pos = 0U;
    return open_common(r, name, format, mode);
}

int canlog_open_mem(canlog_reader_t *r, const char *text, size_t len, const char *name,
                    canlog_format_t format, canlog_error_mode_t mode)
{
    if ((r == NULL) || ((text == NULL) && (len != 0U))) {
        return -(int)CANLOG_E_SYNTAX;
    }
    r->fd = -1;
    r->mem = text;
    r->mem_len = len;
    r->mem_pos = 0U;
    return open_common(r, (name != NULL) ? name : "<memory>", format, mode);
}

int canlog_rewind(canlog_reader_t *r)
{
    if (r->fd >= 0) {
        if (lseek(r->fd, 0, SEEK_SET) != 0) {
            return fail(r, CANLOG_E_IO, "cannot go back to the start (%s)", strerror(errno));
        }
    } else {
        r->mem_pos = 0U;
    }
    reset_parse(r);
    return 0;
}

/* Moves the unconsumed bytes to the front and reads more after them, keeping
 * one byte free for a NUL after the last line. Returns the number of bytes
 * read, 0 at end of file, -1 on a read error. */
static ssize_t fill(canlog_reader_t *r)
{
    if (r->pos > 0U) {
        memmove(r->buf, r->buf + r->pos, r->end - r->pos);
        r->end -= r->pos;
        r->pos = 0U;
    }
    const size_t room = CANLOG_BUF_SIZE - 1U - r->end;
    if (r->fd >= 0) {
        ssize_t n;
        do {
            n = read(r->fd, r->buf + r->end, room);
        } while ((n < 0) && (errno == EINTR));
        if (n > 0) {
            r->end += (size_t)n;
        }
        return n;
    }
    size_t n = r->mem_len - r->mem_pos;
    if (n > room) {
        n = room;
    }
    memcpy(r->buf + r->end, r->mem + r->mem_pos, n);
    r->mem_pos += n;
    r->end += n;
    return (ssize_t)n;
}

/* The next line, NUL-terminated in place (a CR before the newline removed).
 * Returns 1 with *line and *len, 0 at end of file, or a negative reason
 * (line too long, read error). */
static int next_line(canlog_reader_t *r, char **line, size_t *len)
{
    for (;;) {
        char *s = r->buf + r->pos;
        const size_t avail = r->end - r->pos;
        char *nl = memchr(s, '\n', avail);
        if ((nl != NULL) || (r->eof && (avail > 0U))) {
            size_t n = (nl != NULL) ? (size_t)(nl - s) : avail;
            r->pos += (nl != NULL) ? (n + 1U) : n;
            r->consumed_bytes += (nl != NULL) ? (n + 1U) : n;
            r->line_no++;
            r->lines++;
            if (n > CANLOG_LINE_MAX) {
                return fail(r, looks_binary(s, CANLOG_LINE_MAX) ? CANLOG_E_BINARY
                                                                : CANLOG_E_LINE_TOO_LONG,
                            "%zu characters, more than %u", n, CANLOG_LINE_MAX);
            }
            if ((n > 0U) && (s[n - 1U] == '\r')) {
                n--;
            }
            s[n] = '\0';
            if ((r->line_no == 1U) && (n >= 3U) && (memcmp(s, "\xEF\xBB\xBF", 3U) == 0)) {
                /* a UTF-8 byte order mark, as Windows tools write */
                s += 3;
                n -= 3U;
            }
            *line = s;
            *len = n;
            return 1;
        }
        if (r->eof) {
            return 0;
        }
        if (avail > CANLOG_LINE_MAX) {
            /* No newline within the limit: report it, then drop the rest of
             * the line as it comes. */
            const bool binary = looks_binary(s, CANLOG_LINE_MAX);
            r->line_no++;
            r->lines++;
            uint64_t n = avail;
            r->pos = r->end;
            for (;;) {
                const ssize_t got = fill(r);
                if (got < 0) {
                    return fail(r, CANLOG_E_IO, "%s", strerror(errno));
                }
                if (got == 0) {
                    r->eof = true;
                    n += r->end - r->pos;
                    r->pos = r->end;
                    break;
                }
                char *e = memchr(r->buf + r->pos, '\n', r->end - r->pos);
                if (e != NULL) {
                    n += (uint64_t)(e - (r->buf + r->pos));
                    r->pos = (size_t)(e - r->buf) + 1U;
                    break;
                }
                n += r->end - r->pos;
                r->pos = r->end;
            }
            r->consumed_bytes += n + 1U;
            return fail(r, binary ? CANLOG_E_BINARY : CANLOG_E_LINE_TOO_LONG,
                        "%llu characters, more than %u", (unsigned long long)n,
                        CANLOG_LINE_MAX);
        }
        const ssize_t got = fill(r);
        if (got < 0) {
            return fail(r, CANLOG_E_IO, "%s", strerror(errno));
        }
        if (got == 0) {
            r->eof = true;
        }
    }
}

/* ------------------------------------------------------------------ numbers */

/* Whole seconds, '.', fraction: "SEC.FRAC" with 1..12 second digits. Sets
 * *us (fraction truncated to microseconds), *sec_digits, *frac_digits and
 * moves *pp past it. Returns 0, or -1 if it is not such a number. */
static int parse_seconds(const char **pp, uint64_t *us, int *sec_digits, int *frac_digits)
{
    const char *p = *pp;
    uint64_t sec = 0U;
    int ns = 0;
    while (is_digit(*p)) {
        if (ns == 12) {
            return -1;
        }
        sec = (sec * 10U) + (uint64_t)(*p - '0');
        ns++;
        p++;
    }
    if ((ns == 0) || (*p != '.')) {
        return -1;
    }
    p++;
    uint64_t frac = 0U;
    int nf = 0;
    while (is_digit(*p)) {
        if (nf < 6) {
            frac = (frac * 10U) + (uint64_t)(*p - '0');
        }
        nf++;
        p++;
        if (nf > 9) {
            return -1;
        }
    }
    if (nf == 0) {
        return -1;
    }
    for (int i = nf; i < 6; i++) {
        frac *= 10U;
    }
    *us = (sec * 1000000U) + frac;
    *sec_digits = ns;
    *frac_digits = nf;
    *pp = p;
    return 0;
}

/* Days from 1970-01-01 to Y-M-D of the proleptic Gregorian calendar. */
static int64_t days_from_civil(int64_t y, int64_t m, int64_t d)
{
    y -= (m <= 2) ? 1 : 0;
    const int64_t era = ((y >= 0) ? y : (y - 399)) / 400;
    const int64_t yoe = y - (era * 400);                                   /* 0 .. 399 */
    const int64_t mp = (m > 2) ? (m - 3) : (m + 9);                        /* March = 0 */
    const int64_t doy = ((153 * mp) + 2) / 5 + d - 1;                      /* 0 .. 365 */
    const int64_t doe = (yoe * 365) + (yoe / 4) - (yoe / 100) + doy;       /* 0 .. 146096 */
    return (era * 146097) + doe - 719468;
}

/* N decimal digits at p into *v; -1 if any is not a digit. */
static int digits_n(const char *p, int n, int64_t *v)
{
    int64_t x = 0;
    for (int i = 0; i < n; i++) {
        if (!is_digit(p[i])) {
            return -1;
        }
        x = (x * 10) + (p[i] - '0');
    }
    *v = x;
    return 0;
}

/* "YYYY-MM-DD HH:MM:SS.ffffff" (6 or 9 fraction digits) at *pp. */
static int parse_date(const char **pp, uint64_t *us, int *frac_digits)
{
    const char *p = *pp;
    int64_t y, mo, d, h, mi;
    if ((digits_n(p, 4, &y) != 0) || (p[4] != '-') || (digits_n(p + 5, 2, &mo) != 0) ||
        (p[7] != '-') || (digits_n(p + 8, 2, &d) != 0) || (p[10] != ' ') ||
        (digits_n(p + 11, 2, &h) != 0) || (p[13] != ':') || (digits_n(p + 14, 2, &mi) != 0) ||
        (p[16] != ':')) {
        return -1;
    }
    if ((y < 1970) || (mo < 1) || (mo > 12) || (d < 1) || (d > 31) || (h > 23) || (mi > 59)) {
        return -1;
    }
    p += 17;
    uint64_t sec_us;
    int sd, nf;
    if ((parse_seconds(&p, &sec_us, &sd, &nf) != 0) || (sd != 2) || (sec_us >= 61000000U)) {
        return -1;
    }
    const int64_t days = days_from_civil(y, mo, d);
    *us = ((uint64_t)((days * 86400) + (h * 3600) + (mi * 60)) * 1000000U) + sec_us;
    *frac_digits = nf;
    *pp = p;
    return 0;
}

/* ------------------------------------------------------------------ lengths */

static const uint8_t fd_dlc2len[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64};

uint8_t canlog_fd_dlc_to_len(uint8_t dlc)
{
    return fd_dlc2len[dlc & 0x0FU];
}

uint8_t canlog_fd_len_to_dlc(uint8_t len)
{
    if (len > 64U) {
        return 0xFFU;
    }
    for (uint8_t dlc = 0U; dlc < 16U; dlc++) {
        if (fd_dlc2len[dlc] >= len) {
            return dlc;
        }
    }
    return 15U;
}

static bool fd_len_valid(unsigned len)
{
    return (len <= 8U) || (len == 12U) || (len == 16U) || (len == 20U) || (len == 24U) ||
           (len == 32U) || (len == 48U) || (len == 64U);
}

/* Checks LEN bytes of data for a classic (FD false) or FD frame. */
static int check_len(canlog_reader_t *r, bool fd, unsigned len)
{
    if (!fd && (len > CANLOG_MAX_DLEN)) {
        return fail(r, CANLOG_E_DLC, "%u data bytes, over 8 for classic CAN", len);
    }
    if (fd && (len > CANLOG_FD_MAX_DLEN)) {
        return fail(r, CANLOG_E_DLC, "%u data bytes, over 64 for CAN FD", len);
    }
    if (fd && !fd_len_valid(len)) {
        return fail(r, CANLOG_E_DLC,
                    "%u data bytes is not a CAN FD length (0-8, 12, 16, 20, 24, 32, 48, 64)",
                    len);
    }
    return 0;
}

/* ------------------------------------------------------------------ ids */

/* Hex id of DIGITS digits with value V (3: 11 bits; 8: 29 bits or an error
 * frame) to *id with its flags. */
static int make_id(canlog_reader_t *r, int digits, uint32_t v, uint32_t *id)
{
    if (digits == 3) {
        if (v > CANLOG_SFF_MASK) {
            return fail(r, CANLOG_E_BAD_ID, "11-bit id %03X over 7FF", (unsigned)v);
        }
        *id = v;
        return 0;
    }
    if (digits == 8) {
        if ((v & CANLOG_ERR_FLAG) != 0U) {
            if ((v & (CANLOG_EFF_FLAG | CANLOG_RTR_FLAG)) != 0U) {
                return fail(r, CANLOG_E_BAD_ID, "error frame id %08X with bits over 1FFFFFFF",
                            (unsigned)v);
            }
            *id = v;
            return 0;
        }
        if (v > CANLOG_EFF_MASK) {
            return fail(r, CANLOG_E_BAD_ID, "29-bit id %08X over 1FFFFFFF", (unsigned)v);
        }
        *id = v | CANLOG_EFF_FLAG;
        return 0;
    }
    return fail(r, CANLOG_E_BAD_ID, "id of %d hex digits; 3 (11-bit) or 8 (29-bit) expected",
                digits);
}

/* ------------------------------------------------------------------ time */

/* Accepts time T (in the base TB) for the frame of this line: checks the
 * order, fixes the time base. */
static int accept_time(canlog_reader_t *r, canlog_time_base_t tb, uint64_t t, uint64_t *out)
{
    if ((r->time_base != CANLOG_TB_UNKNOWN) && (r->time_base != tb)) {
        return fail(r, CANLOG_E_BAD_TIME, "timestamp of another kind (%s) than earlier lines (%s)",
                    canlog_time_base_text(tb), canlog_time_base_text(r->time_base));
    }
    if (r->have_time && (t < r->last_time_us) && r->backwards_ok) {
        r->time_base = tb;
        r->backwards++;
        *out = t;
        return 0;
    }
    if (r->have_time && (t < r->last_time_us)) {
        const bool printed_z = (r->format == CANLOG_FMT_PRINTED) && (tb == CANLOG_TB_START);
        return fail(r, CANLOG_E_BACKWARDS, "%llu.%06llu s is before the previous frame's %llu.%06llu s%s",
                    (unsigned long long)(t / 1000000U), (unsigned long long)(t % 1000000U),
                    (unsigned long long)(r->last_time_us / 1000000U),
                    (unsigned long long)(r->last_time_us % 1000000U),
                    printed_z ? " (candump -t d output? read it as printed-delta)" : "");
    }
    r->time_base = tb;
    r->have_time = true;
    r->last_time_us = t;
    *out = t;
    return 0;
}

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
                return fail(r, CANLOG_E_TRUNCATED, "no '#' after the id");
            }
            return fail(r, CANLOG_E_BAD_HEX, "%s in the id", show_char(c, cbuf));
        }
        if (digits < 8) {
            v = (v << 4) | (uint32_t)h;
        }
        digits++;
    }
    p++; /* '#' */
    uint32_t id;
    int rc = make_id(r, digits, v, &id);
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
                return fail(r, CANLOG_E_BAD_HEX, "%s after 'R'", show_char(*p, cbuf));
            }
            len = (unsigned)h;
            p++;
            if (!is_end(*p)) {
                return fail(r, CANLOG_E_SYNTAX, "%s after the remote frame's length",
                            show_char(*p, cbuf));
            }
            if (len > CANLOG_MAX_DLEN) {
                return fail(r, CANLOG_E_DLC, "remote frame length %u over 8", len);
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
                return fail(r, CANLOG_E_TRUNCATED, "no FD flags digit after '##'");
            }
            return fail(r, CANLOG_E_BAD_HEX, "%s as the FD flags digit", show_char(*p, cbuf));
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
            return fail(r, CANLOG_E_BAD_HEX, "%s in the data", show_char(c, cbuf));
        }
        c = p[1];
        const int lo = hex_digit(c);
        if (lo < 0) {
            if (is_end(c) || (c == '.')) {
                return fail(r, CANLOG_E_TRUNCATED, "half a byte at the end of the data");
            }
            return fail(r, CANLOG_E_BAD_HEX, "%s in the data", show_char(c, cbuf));
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
            return fail(r, CANLOG_E_DLC, "a raw DLC after '_' needs 8 data bytes and a DLC of 9 to F");
        }
        f->len8_dlc = (uint8_t)d;
        p += 2;
    }
    rc = check_len(r, f->fd, n);
    if (rc != 0) {
        return rc;
    }
    f->id = id;
    f->len = (uint8_t)n;
    *pp = p;
    return 0;
}

/* Copies the interface token [p, e) into f->iface. */
static int take_iface(canlog_reader_t *r, const char *p, const char *e, canlog_frame_t *f)
{
    const size_t n = (size_t)(e - p);
    if (n == 0U) {
        return fail(r, CANLOG_E_TRUNCATED, "no interface name");
    }
    if (n >= CANLOG_IFNAME_MAX) {
        return fail(r, CANLOG_E_SYNTAX, "interface name of %zu characters, over %u", n,
                    CANLOG_IFNAME_MAX - 1U);
    }
    memcpy(f->iface, p, n);
    f->iface[n] = '\0';
    return 0;
}

static bool is_comment(const char *p)
{
    return (*p == '\0') || (*p == '#') || ((p[0] == '/') && (p[1] == '/'));
}

/* candump's "DROPCOUNT: dropped N CAN frame(s) on 'IF' socket (total drops T)":
 * true, and N added to r->dropped, when P starts with "DROPCOUNT:". */
static bool note_dropcount(canlog_reader_t *r, const char *p)
{
    if (!starts_with(p, "DROPCOUNT:")) {
        return false;
    }
    const char *q = skip_blanks(p + 10);
    if (starts_with(q, "dropped")) {
        q = skip_blanks(q + 7);
        uint64_t n = 0U;
        int digits = 0;
        while (is_digit(*q) && (digits < 19)) {
            n = (n * 10U) + (uint64_t)(*q - '0');
            q++;
            digits++;
        }
        r->dropped += n;
    }
    return true;
}

static int parse_log_line(canlog_reader_t *r, const char *line, canlog_frame_t *f)
{
    const char *p = skip_blanks(line);
    char cbuf[16];
    if (*p != '(') {
        if (is_comment(p) || note_dropcount(r, p)) {
            return 1;
        }
        return fail(r, CANLOG_E_SYNTAX, "%s: a candump log line starts with '('",
                    show_char(*p, cbuf));
    }
    p++;
    uint64_t t;
    int sd, nf;
    if (parse_seconds(&p, &t, &sd, &nf) != 0) {
        if (*p == '\0') {
            return fail(r, CANLOG_E_TRUNCATED, "line ends in the timestamp");
        }
        return fail(r, CANLOG_E_BAD_TIME, "expected (SECONDS.FRACTION)");
    }
    if (*p != ')') {
        if (*p == '\0') {
            return fail(r, CANLOG_E_TRUNCATED, "line ends in the timestamp");
        }
        return fail(r, CANLOG_E_BAD_TIME, "%s where ')' should close the timestamp",
                    show_char(*p, cbuf));
    }
    if ((nf != 6) && (nf != 9)) {
        return fail(r, CANLOG_E_BAD_TIME, "%d fraction digits; 6 or 9 expected", nf);
    }
    p = skip_blanks(p + 1);
    const char *e = token_end(p);
    if (*e == '\0') {
        return fail(r, CANLOG_E_TRUNCATED, (e == p) ? "no interface and frame after the timestamp"
                                                    : "no frame after the interface");
    }
    int rc = take_iface(r, p, e, f);
    if (rc != 0) {
        return rc;
    }
    p = skip_blanks(e);
    if (*p == '\0') {
        return fail(r, CANLOG_E_TRUNCATED, "no frame after the interface");
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
        return fail(r, CANLOG_E_SYNTAX, "%s after the frame", show_char(*p, cbuf));
    }
    f->channel = 0U;
    return accept_time(r, CANLOG_TB_EPOCH, t, &f->time_us);
}

/* ------------------------------------------------------------------ candump printed output */

static int parse_printed_line(canlog_reader_t *r, const char *line, canlog_frame_t *f)
{
    char cbuf[16];
    if (line[0] == '\t') {
        return 1; /* -e: the description lines under an error frame */
    }
    const char *p = skip_blanks(line);
    if (is_comment(p) || note_dropcount(r, p)) {
        return 1;
    }
    canlog_time_base_t tb = CANLOG_TB_NONE;
    uint64_t t = 0U;
    if (*p == '(') {
        p++;
        int nf, sd;
        if (is_digit(p[0]) && is_digit(p[1]) && is_digit(p[2]) && is_digit(p[3]) &&
            (p[4] == '-')) {
            if (parse_date(&p, &t, &nf) != 0) {
                return fail(r, CANLOG_E_BAD_TIME, "expected (YYYY-MM-DD HH:MM:SS.FRACTION)");
            }
            tb = CANLOG_TB_DATE;
        } else {
            if (parse_seconds(&p, &t, &sd, &nf) != 0) {
                if (*p == '\0') {
                    return fail(r, CANLOG_E_TRUNCATED, "line ends in the timestamp");
                }
                return fail(r, CANLOG_E_BAD_TIME, "expected (SECONDS.FRACTION)");
            }
            tb = (sd >= 10) ? CANLOG_TB_EPOCH : CANLOG_TB_START;
        }
        if (*p != ')') {
            if (*p == '\0') {
                return fail(r, CANLOG_E_TRUNCATED, "line ends in the timestamp");
            }
            return fail(r, CANLOG_E_BAD_TIME, "%s where ')' should close the timestamp",
                        show_char(*p, cbuf));
        }
        if ((nf != 6) && (nf != 9)) {
            return fail(r, CANLOG_E_BAD_TIME, "%d fraction digits; 6 or 9 expected", nf);
        }
        p = skip_blanks(p + 1);
    }
    const char *e = token_end(p);
    if (*e == '\0') {
        return fail(r, CANLOG_E_TRUNCATED, "no id and length after the interface");
    }
    int rc = take_iface(r, p, e, f);
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
            return fail(r, CANLOG_E_SYNTAX, "expected '-' or 'B' after %s",
                        f->dir == 'R' ? "RX" : "TX");
        }
        const bool brs = *p == 'B';
        p = skip_blanks(p + 1);
        if (!(((*p == '-') || (*p == 'E')) && is_blank(p[1]))) {
            return fail(r, CANLOG_E_SYNTAX, "expected '-' or 'E' after the BRS column");
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
            return fail(r, CANLOG_E_BAD_HEX, "%s in the id", show_char(*p, cbuf));
        }
        if (digits < 8) {
            v = (v << 4) | (uint32_t)h;
        }
        digits++;
    }
    if (digits == 0) {
        return fail(r, CANLOG_E_TRUNCATED, "no id");
    }
    uint32_t id;
    rc = make_id(r, digits, v, &id);
    if (rc != 0) {
        return rc;
    }
    p = skip_blanks(p);
    /* [len]: one digit classic, two digits CAN FD */
    if (*p != '[') {
        if (*p == '\0') {
            return fail(r, CANLOG_E_TRUNCATED, "no [length] after the id");
        }
        return fail(r, CANLOG_E_SYNTAX, "%s where [length] should follow the id",
                    show_char(*p, cbuf));
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
            return fail(r, CANLOG_E_TRUNCATED, "line ends in the [length]");
        }
        return fail(r, CANLOG_E_SYNTAX, "[length] must be decimal digits");
    }
    if (ld > 2) {
        return fail(r, CANLOG_E_DLC, "length of %d digits", ld);
    }
    p = skip_blanks(p + 1);
    /* Two digits mean CAN FD, except before "remote request": CAN FD has no
     * remote frames, so that is a classic one written as [04]. */
    f->fd = (ld == 2) && !token_is(p, "remote");
    if (!f->fd) {
        if (have_x && (f->fd_flags != 0U)) {
            return fail(r, CANLOG_E_SYNTAX, "FD flags on a classic frame");
        }
        if (token_is(p, "remote")) {
            if (len > CANLOG_MAX_DLEN) {
                return fail(r, CANLOG_E_DLC, "remote frame length %u over 8", len);
            }
            p = skip_blanks(p + 6);
            if (!token_is(p, "request")) {
                return fail(r, CANLOG_E_SYNTAX, "expected 'remote request'");
            }
            p = skip_blanks(p + 7);
            if (*p != '\0') {
                return fail(r, CANLOG_E_SYNTAX, "%s after 'remote request'", show_char(*p, cbuf));
            }
            f->id = id | CANLOG_RTR_FLAG;
            f->len = (uint8_t)len;
            goto timed;
        }
    }
    rc = check_len(r, f->fd, len);
    if (rc != 0) {
        return rc;
    }
    for (unsigned i = 0U; i < len; i++) {
        if (*p == '\0') {
            return fail(r, CANLOG_E_TRUNCATED, "%u data bytes of [%u]", i, len);
        }
        const int hi = hex_digit(p[0]);
        const int lo = hex_digit(p[1]);
        if ((hi < 0) || (lo < 0) || !is_end(p[2])) {
            if ((*p == '\'') || token_is(p, "ERRORFRAME")) {
                return fail(r, CANLOG_E_TRUNCATED, "%u data bytes of [%u]", i, len);
            }
            const char *bad = (hi < 0) ? p : ((lo < 0) ? p + 1 : p + 2);
            return fail(r, CANLOG_E_BAD_HEX, "%s in data byte %u", show_char(*bad, cbuf), i);
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
            return fail(r, CANLOG_E_DLC, "more data bytes than [%u]", len);
        }
        return fail(r, CANLOG_E_SYNTAX, "%s after the data", show_char(*p, cbuf));
    }
timed:
    f->channel = 0U;
    if (tb == CANLOG_TB_START && r->format == CANLOG_FMT_PRINTED_DELTA) {
        t += r->acc_time_us;
        r->acc_time_us = t;
    }
    if (tb == CANLOG_TB_NONE) {
        if ((r->time_base != CANLOG_TB_UNKNOWN) && (r->time_base != tb)) {
            return fail(r, CANLOG_E_BAD_TIME, "no timestamp where earlier lines had one");
        }
        r->time_base = tb;
        f->time_us = 0U;
        return 0;
    }
    return accept_time(r, tb, t, &f->time_us);
}

/* ------------------------------------------------------------------ Vector ASC */

/* An ASC number token [p, e): hex (or decimal with base dec) into *v. */
static int asc_number(const canlog_reader_t *r, const char *p, const char *e, uint32_t *v,
                      const char **bad)
{
    uint64_t x = 0U;
    if (p == e) {
        *bad = p;
        return -1;
    }
    for (; p < e; p++) {
        if (r->asc_decimal) {
            if (!is_digit(*p)) {
                *bad = p;
                return -1;
            }
            x = (x * 10U) + (uint64_t)(*p - '0');
        } else {
            const int h = hex_digit(*p);
            if (h < 0) {
                *bad = p;
                return -1;
            }
            x = (x << 4) | (uint64_t)h;
        }
        if (x > 0xFFFFFFFFULL) {
            *bad = p;
            return -1;
        }
    }
    *v = (uint32_t)x;
    return 0;
}

/* An ASC id token "18FEF100x" or "123". */
static int asc_id(canlog_reader_t *r, const char *p, const char *e, uint32_t *id)
{
    char cbuf[16];
    bool ext = false;
    if ((e > p) && ((e[-1] == 'x') || (e[-1] == 'X'))) {
        ext = true;
        e--;
    }
    uint32_t v;
    const char *bad = NULL;
    if (asc_number(r, p, e, &v, &bad) != 0) {
        if (bad == e) {
            return fail(r, CANLOG_E_TRUNCATED, "no id");
        }
        return fail(r, r->asc_decimal ? CANLOG_E_SYNTAX : CANLOG_E_BAD_HEX, "%s in the id",
                    show_char(*bad, cbuf));
    }
    if (ext) {
        if (v > CANLOG_EFF_MASK) {
            return fail(r, CANLOG_E_BAD_ID, "29-bit id %X over 1FFFFFFF", (unsigned)v);
        }
        *id = v | CANLOG_EFF_FLAG;
    } else {
        if (v > CANLOG_SFF_MASK) {
            return fail(r, CANLOG_E_BAD_ID, "11-bit id %X over 7FF (29-bit ids end in 'x')",
                        (unsigned)v);
        }
        *id = v;
    }
    return 0;
}

/* LEN data bytes as tokens from *pp. */
static int asc_data(canlog_reader_t *r, const char **pp, unsigned len, canlog_frame_t *f)
{
    const char *p = *pp;
    char cbuf[16];
    for (unsigned i = 0U; i < len; i++) {
        p = skip_blanks(p);
        if (*p == '\0') {
            return fail(r, CANLOG_E_TRUNCATED, "%u data bytes of %u", i, len);
        }
        const char *e = token_end(p);
        uint32_t v;
        const char *bad = NULL;
        if ((e - p > 3) || (asc_number(r, p, e, &v, &bad) != 0) || (v > 0xFFU)) {
            return fail(r, CANLOG_E_BAD_HEX, "%s in data byte %u",
                        show_char((bad != NULL) ? *bad : *p, cbuf), i);
        }
        f->data[i] = (uint8_t)v;
        p = e;
    }
    *pp = skip_blanks(p);
    return 0;
}

/* A token of 1 or 2 hex digits (a data byte more than the DLC said). */
static bool looks_like_byte(const char *p)
{
    return (hex_digit(p[0]) >= 0) && (is_end(p[1]) || ((hex_digit(p[1]) >= 0) && is_end(p[2])));
}

static void asc_iface(canlog_frame_t *f, unsigned channel)
{
    f->channel = (uint8_t)channel;
    (void)snprintf(f->iface, sizeof f->iface, "can%u", channel - 1U);
}

static int asc_channel(canlog_reader_t *r, const char *p, const char *e, unsigned *ch)
{
    unsigned v = 0U;
    if ((p == e) || (e - p > 3)) {
        return fail(r, CANLOG_E_SYNTAX, "channel must be 1 to 255");
    }
    for (; p < e; p++) {
        if (!is_digit(*p)) {
            return fail(r, CANLOG_E_SYNTAX, "channel must be 1 to 255");
        }
        v = (v * 10U) + (unsigned)(*p - '0');
    }
    if ((v < 1U) || (v > 255U)) {
        return fail(r, CANLOG_E_SYNTAX, "channel %u; 1 to 255 expected", v);
    }
    *ch = v;
    return 0;
}

static void asc_error_frame(canlog_frame_t *f)
{
    f->id = CANLOG_ERR_FLAG | 0x80U; /* CAN_ERR_BUSERROR: all the line says is "error" */
    f->len = CANLOG_MAX_DLEN;
    memset(f->data, 0, CANLOG_MAX_DLEN);
    f->fd = false;
    f->fd_flags = 0U;
    f->dir = 0;
}

static bool is_dir(const char *p)
{
    return token_is(p, "Rx") || token_is(p, "Tx") || token_is(p, "TxRq");
}

/* "CANFD CH DIR ID [NAME] BRS ESI DLC LEN DATA... [DURATION BITS FLAGS ...]" after the time. */
static int parse_asc_fd(canlog_reader_t *r, const char *p, canlog_frame_t *f)
{
    char cbuf[16];
    p = skip_blanks(p + 5);
    const char *e = token_end(p);
    unsigned ch;
    int rc = asc_channel(r, p, e, &ch);
    if (rc != 0) {
        return rc;
    }
    p = skip_blanks(e);
    if (!is_dir(p)) {
        return fail(r, (*p == '\0') ? CANLOG_E_TRUNCATED : CANLOG_E_SYNTAX,
                    "expected Rx or Tx after the channel");
    }
    const bool txrq = token_is(p, "TxRq");
    f->dir = p[0] == 'R' ? 'R' : 'T';
    p = skip_blanks(token_end(p));
    asc_iface(f, ch);
    if (token_is(p, "ErrorFrame")) {
        asc_error_frame(f);
        return txrq ? 1 : 0;
    }
    e = token_end(p);
    uint32_t id;
    rc = asc_id(r, p, e, &id);
    if (rc != 0) {
        return rc;
    }
    p = skip_blanks(e);
    /* BRS ESI DLC LEN, perhaps after a symbolic name */
    const char *q = p;
    for (int attempt = 0; attempt < 2; attempt++) {
        /* each test reads a character only after the ones before it matched,
         * so none reads past the end of the line */
        const char *b = q;
        bool ok = ((*b == '0') || (*b == '1')) && is_blank(b[1]);
        const char *s = ok ? skip_blanks(b + 1) : b;
        ok = ok && ((*s == '0') || (*s == '1')) && is_blank(s[1]);
        const char *d = ok ? skip_blanks(s + 1) : b;
        ok = ok && (hex_digit(*d) >= 0) && is_blank(d[1]);
        const char *l = ok ? skip_blanks(d + 1) : b;
        ok = ok && is_digit(*l);
        if (ok) {
            p = b;
            break;
        }
        if ((attempt == 1) || (*q == '\0')) {
            return fail(r, (*q == '\0') ? CANLOG_E_TRUNCATED : CANLOG_E_SYNTAX,
                        "expected BRS ESI DLC LENGTH after the id");
        }
        q = skip_blanks(token_end(q)); /* skip the symbolic name */
    }
    const bool brs = *p == '1';
    p = skip_blanks(p + 1);
    const bool esi = *p == '1';
    p = skip_blanks(p + 1);
    const unsigned dlc = (unsigned)hex_digit(*p);
    p = skip_blanks(p + 1);
    unsigned len = 0U;
    e = token_end(p);
    for (const char *c = p; c < e; c++) {
        if (!is_digit(*c) || (e - p > 3)) {
            return fail(r, CANLOG_E_SYNTAX, "data length must be decimal");
        }
        len = (len * 10U) + (unsigned)(*c - '0');
    }
    p = e;
    rc = check_len(r, true, len);
    if (rc != 0) {
        return rc;
    }
    rc = asc_data(r, &p, len, f);
    if (rc != 0) {
        return rc;
    }
    /* Trailer: message duration, bit count, flags (hex), ... */
    bool classic = false;
    bool remote = false;
    const char *t1 = p;
    const char *t2 = skip_blanks(token_end(t1));
    const char *t3 = skip_blanks(token_end(t2));
    if (*t3 != '\0') {
        const char *t3e = token_end(t3);
        uint64_t flags = 0U;
        bool ok = (t3e - t3) <= 8;
        for (const char *c = t3; ok && (c < t3e); c++) {
            const int h = hex_digit(*c);
            ok = h >= 0;
            flags = (flags << 4) | (uint64_t)((h >= 0) ? h : 0);
        }
        if (!ok) {
            return fail(r, CANLOG_E_SYNTAX, "flags field %s is not hex", show_char(*t3, cbuf));
        }
        classic = (flags & 0x1000U) == 0U;
        remote = classic && ((flags & 0x10U) != 0U);
    }
    /* A classic remote frame has length 0 and its requested length as DLC
     * (log2asc); every other frame's DLC gives its length. */
    if (remote ? (len != 0U) : (canlog_fd_dlc_to_len((uint8_t)dlc) != len)) {
        return fail(r, CANLOG_E_DLC, "DLC %X does not give %u data bytes", dlc, len);
    }
    if (remote) {
        if (dlc > 8U) {
            return fail(r, CANLOG_E_DLC, "remote frame DLC %X over 8", dlc);
        }
        f->id = id | CANLOG_RTR_FLAG;
        f->len = (uint8_t)dlc;
        f->fd = false;
        f->fd_flags = 0U;
    } else {
        if (classic) {
            rc = check_len(r, false, len);
            if (rc != 0) {
                return rc;
            }
        }
        f->id = id;
        f->len = (uint8_t)len;
        f->fd = !classic;
        f->fd_flags = classic ? 0U : (uint8_t)((brs ? CANLOG_FD_BRS : 0U) | (esi ? CANLOG_FD_ESI : 0U));
    }
    return txrq ? 1 : 0;
}

/* "CH ID DIR d DLC DATA..." or "CH ID DIR r [DLC]" or "CH ErrorFrame" after
 * the time. Returns 0 with a frame, 1 for an event line that is not a frame. */
static int parse_asc_classic(canlog_reader_t *r, const char *p, canlog_frame_t *f)
{
    char cbuf[16];
    const char *e = token_end(p);
    for (const char *c = p; c < e; c++) {
        if (!is_digit(*c)) {
            return 1; /* not "TIME CHANNEL ...": another kind of event */
        }
    }
    const char *ch_p = p;
    const char *ch_e = e;
    p = skip_blanks(e);
    if (token_is(p, "ErrorFrame")) {
        unsigned ch;
        const int rc = asc_channel(r, ch_p, ch_e, &ch);
        if (rc != 0) {
            return rc;
        }
        asc_iface(f, ch);
        asc_error_frame(f);
        return 0;
    }
    const char *id_p = p;
    const char *id_e = token_end(p);
    p = skip_blanks(id_e);
    if (!is_dir(p)) {
        if (*p == '\0') {
            /* "TIME CH ID" and nothing more: a frame cut short, or an event */
            const bool idlike = (id_p != id_e) && (hex_digit(*id_p) >= 0);
            return idlike ? fail(r, CANLOG_E_TRUNCATED, "no direction (Rx/Tx) after the id") : 1;
        }
        return 1; /* statistics, status and other events */
    }
    const bool txrq = token_is(p, "TxRq");
    unsigned ch;
    int rc = asc_channel(r, ch_p, ch_e, &ch);
    if (rc != 0) {
        return rc;
    }
    asc_iface(f, ch);
    f->dir = p[0] == 'R' ? 'R' : 'T';
    uint32_t id;
    rc = asc_id(r, id_p, id_e, &id);
    if (rc != 0) {
        return rc;
    }
    p = skip_blanks(token_end(p));
    f->fd = false;
    f->fd_flags = 0U;
    if (token_is(p, "r")) {
        p = skip_blanks(p + 1);
        unsigned len = 0U;
        if (*p != '\0') {
            const int h = hex_digit(*p);
            if ((h < 0) || !is_end(p[1])) {
                return fail(r, CANLOG_E_BAD_HEX, "%s as the remote frame's DLC",
                            show_char(*p, cbuf));
            }
            len = (unsigned)h;
            p = skip_blanks(p + 1);
        }
        if (len > CANLOG_MAX_DLEN) {
            return fail(r, CANLOG_E_DLC, "remote frame DLC %X over 8", len);
        }
        f->id = id | CANLOG_RTR_FLAG;
        f->len = (uint8_t)len;
        return txrq ? 1 : 0;
    }
    if (!token_is(p, "d")) {
        if (*p == '\0') {
            return fail(r, CANLOG_E_TRUNCATED, "no 'd DLC' after the direction");
        }
        return fail(r, CANLOG_E_SYNTAX, "%s where 'd' (data) or 'r' (remote) should be",
                    show_char(*p, cbuf));
    }
    p = skip_blanks(p + 1);
    if (*p == '\0') {
        return fail(r, CANLOG_E_TRUNCATED, "no DLC after 'd'");
    }
    const int dlc = hex_digit(*p);
    if ((dlc < 0) || !is_end(p[1])) {
        return fail(r, CANLOG_E_BAD_HEX, "%s as the DLC", show_char((dlc < 0) ? *p : p[1], cbuf));
    }
    rc = check_len(r, false, (unsigned)dlc);
    if (rc != 0) {
        return rc;
    }
    p = skip_blanks(p + 1);
    rc = asc_data(r, &p, (unsigned)dlc, f);
    if (rc != 0) {
        return rc;
    }
    if ((*p != '\0') && looks_like_byte(p)) {
        return fail(r, CANLOG_E_DLC, "more data bytes than DLC %d", dlc);
    }
    /* Anything else is Vector's trailer (Length = ..., BitCount = ..., ID = ...). */
    f->id = id;
    f->len = (uint8_t)dlc;
    return txrq ? 1 : 0;
}

static int parse_asc_header(canlog_reader_t *r, const char *p)
{
    if (starts_with(p, "base ")) {
        p = skip_blanks(p + 5);
        if (token_is(p, "hex")) {
            r->asc_decimal = false;
        } else if (token_is(p, "dec")) {
            r->asc_decimal = true;
        } else {
            return fail(r, CANLOG_E_SYNTAX, "base must be hex or dec");
        }
        p = skip_blanks(token_end(p));
        if (!token_is(p, "timestamps")) {
            return fail(r, CANLOG_E_SYNTAX, "expected 'timestamps absolute|relative' after base");
        }
        p = skip_blanks(p + 10);
        if (token_is(p, "absolute")) {
            r->asc_relative = false;
        } else if (token_is(p, "relative")) {
            r->asc_relative = true;
        } else {
            return fail(r, CANLOG_E_SYNTAX, "timestamps must be absolute or relative");
        }
        return 1;
    }
    if (starts_with(p, "date ") || starts_with(p, "internal events logged") ||
        starts_with(p, "no internal events logged") ||
        starts_with_nocase(p, "begin triggerblock") || starts_with_nocase(p, "end triggerblock") ||
        starts_with(p, "Start of measurement")) {
        return 1;
    }
    char cbuf[16];
    return fail(r, CANLOG_E_SYNTAX, "%s: not an ASC header, comment or event line",
                show_char(*p, cbuf));
}

static int parse_asc_line(canlog_reader_t *r, const char *line, canlog_frame_t *f)
{
    const char *p = skip_blanks(line);
    if ((*p == '\0') || ((p[0] == '/') && (p[1] == '/'))) {
        return 1;
    }
    if (!is_digit(*p)) {
        return parse_asc_header(r, p);
    }
    uint64_t t;
    int sd, nf;
    if ((parse_seconds(&p, &t, &sd, &nf) != 0) || !is_end(*p)) {
        return fail(r, CANLOG_E_BAD_TIME, "expected SECONDS.FRACTION at the start of an event");
    }
    if (r->asc_relative) {
        t += r->acc_time_us;
        r->acc_time_us = t;
    }
    p = skip_blanks(p);
    if (*p == '\0') {
        return fail(r, CANLOG_E_TRUNCATED, "nothing after the time");
    }
    int rc;
    if (token_is(p, "CANFD")) {
        rc = parse_asc_fd(r, p, f);
    } else if (token_is(p, "CANXL")) {
        return fail(r, CANLOG_E_SYNTAX, "CAN XL events are not supported");
    } else {
        rc = parse_asc_classic(r, p, f);
    }
    if (rc != 0) {
        return rc;
    }
    return accept_time(r, CANLOG_TB_START, t, &f->time_us);
}

/* ------------------------------------------------------------------ detection */

/* The format of the first meaningful line P, or AUTO when it is blank or a
 * comment, or -1 when it is no format at all. */
static int detect(const char *line)
{
    const char *p = skip_blanks(line);
    if ((*p == '\0') || (*p == '#') || ((p[0] == '/') && (p[1] == '/')) ||
        starts_with(p, "DROPCOUNT:")) {
        return (int)CANLOG_FMT_AUTO;
    }
    if (starts_with(p, "date ") || starts_with(p, "base ") ||
        starts_with(p, "internal events logged") || starts_with(p, "no internal events logged") ||
        starts_with_nocase(p, "begin triggerblock") || is_digit(*p)) {
        return (int)CANLOG_FMT_ASC;
    }
    if (*p == '(') {
        const char *c = strchr(p, ')');
        if (c == NULL) {
            return (int)CANLOG_FMT_LOG; /* let the log parser say what is wrong */
        }
        const char *q = skip_blanks(token_end(skip_blanks(c + 1)));
        const char *qe = token_end(q);
        const char *hash = memchr(q, '#', (size_t)(qe - q));
        return (hash != NULL) ? (int)CANLOG_FMT_LOG : (int)CANLOG_FMT_PRINTED;
    }
    /* printed output without timestamps: "IFACE ID [LEN] ..." */
    const char *q = skip_blanks(token_end(p));
    if ((*q == 'R' || *q == 'T') && (q[1] == 'X') && is_blank(q[2])) {
        return (int)CANLOG_FMT_PRINTED;
    }
    const char *qe = token_end(q);
    if ((qe > q) && (*skip_blanks(qe) == '[')) {
        return (int)CANLOG_FMT_PRINTED;
    }
    return -1;
}

/* ------------------------------------------------------------------ next */

int canlog_next(canlog_reader_t *r, canlog_frame_t *out)
{
    for (;;) {
        char *line = NULL;
        size_t len = 0U;
        int rc = next_line(r, &line, &len);
        if (rc == 0) {
            if (!r->saw_content) {
                r->saw_content = true; /* reported once per pass */
                return fail(r, CANLOG_E_EMPTY, "no CAN frames (%llu line%s)",
                            (unsigned long long)r->line_no, (r->line_no == 1U) ? "" : "s");
            }
            return 0;
        }
        if (rc < 0) {
            r->saw_content = true;
            if ((r->mode == CANLOG_ON_ERROR_SKIP) && (rc != -(int)CANLOG_E_IO)) {
                continue;
            }
            return rc;
        }
        if (r->format == CANLOG_FMT_AUTO) {
            const int fmt = detect(line);
            if (fmt < 0) {
                r->saw_content = true;
                rc = fail(r, looks_binary(line, len) ? CANLOG_E_BINARY : CANLOG_E_FORMAT,
                          "neither a candump log, candump output nor Vector ASC line");
                if (r->mode == CANLOG_ON_ERROR_SKIP) {
                    continue;
                }
                return rc;
            }
            if ((fmt == (int)CANLOG_FMT_AUTO) && looks_binary(line, len)) {
                /* a NUL first looks like a blank line: it is not text */
                r->saw_content = true;
                rc = fail(r, CANLOG_E_BINARY, "control characters or NUL bytes in the line");
                if (r->mode == CANLOG_ON_ERROR_SKIP) {
                    continue;
                }
                return rc;
            }
            if (fmt == (int)CANLOG_FMT_AUTO) {
                (void)note_dropcount(r, skip_blanks(line));
                r->comments++;
                continue;
            }
            r->format = (canlog_format_t)fmt;
        }
        /* parsed into the reader's own frame: *out changes only on success */
        canlog_frame_t *f = &r->scratch;
        f->len8_dlc = 0U;
        switch (r->format) {
        case CANLOG_FMT_LOG:
            rc = parse_log_line(r, line, f);
            break;
        case CANLOG_FMT_PRINTED:
        case CANLOG_FMT_PRINTED_DELTA:
            rc = parse_printed_line(r, line, f);
            break;
        case CANLOG_FMT_ASC:
        default:
            rc = parse_asc_line(r, line, f);
            break;
        }
        if ((rc == 0) && (memchr(line, '\0', len) != NULL)) {
            /* a NUL cut the line short: what follows it was not read */
            r->saw_content = true;
            rc = fail(r, CANLOG_E_BINARY, "NUL byte in the line");
            if (r->mode == CANLOG_ON_ERROR_SKIP) {
                continue;
            }
            return rc;
        }
        if (rc == 0) {
            r->saw_content = true;
            f->line = r->line_no;
            r->frames++;
            memcpy(out, f, sizeof *out);
            return 1;
        }
        if ((rc > 0) && looks_binary(line, len)) {
            r->saw_content = true;
            rc = fail(r, CANLOG_E_BINARY, "control characters or NUL bytes in the line");
            if (r->mode == CANLOG_ON_ERROR_SKIP) {
                continue;
            }
            return rc;
        }
        if (rc > 0) {
            r->comments++;
            continue;
        }
        r->saw_content = true;
        /* A line that does not parse and holds control characters is binary. */
        if ((rc != -(int)CANLOG_E_BINARY) && looks_binary(line, len)) {
            r->errors[-rc]--;
            r->error_lines--;
            if (r->errors[-rc] == 0U) {
                r->first_msg[-rc][0] = '\0';
            }
            rc = fail(r, CANLOG_E_BINARY, "control characters or NUL bytes in the line");
        }
        if (r->mode == CANLOG_ON_ERROR_SKIP) {
            continue;
        }
        return rc;
    }
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
