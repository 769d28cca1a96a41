/* log_core.c - the CAN log reader's core: lines, numbers, ids, lengths,
 * time, format detection (contract in log.h; the formats in log_candump.c,
 * log_printed.c, log_asc.c). */
#define _POSIX_C_SOURCE 200809L

#include "lib/log/log_parse.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

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
__attribute__((format(printf, 3, 4))) int log_fail(canlog_reader_t *r, canlog_reason_t reason,
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
const char *log_show_char(char c, char out[16])
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
bool log_looks_binary(const char *s, size_t len)
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
            return log_fail(r, CANLOG_E_IO, "cannot go back to the start (%s)", strerror(errno));
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
                return log_fail(r, log_looks_binary(s, CANLOG_LINE_MAX) ? CANLOG_E_BINARY
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
            const bool binary = log_looks_binary(s, CANLOG_LINE_MAX);
            r->line_no++;
            r->lines++;
            uint64_t n = avail;
            r->pos = r->end;
            for (;;) {
                const ssize_t got = fill(r);
                if (got < 0) {
                    return log_fail(r, CANLOG_E_IO, "%s", strerror(errno));
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
            return log_fail(r, binary ? CANLOG_E_BINARY : CANLOG_E_LINE_TOO_LONG,
                        "%llu characters, more than %u", (unsigned long long)n,
                        CANLOG_LINE_MAX);
        }
        const ssize_t got = fill(r);
        if (got < 0) {
            return log_fail(r, CANLOG_E_IO, "%s", strerror(errno));
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
int log_parse_seconds(const char **pp, uint64_t *us, int *sec_digits, int *frac_digits)
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
int log_parse_date(const char **pp, uint64_t *us, int *frac_digits)
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
    if ((log_parse_seconds(&p, &sec_us, &sd, &nf) != 0) || (sd != 2) || (sec_us >= 61000000U)) {
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

bool log_fd_len_valid(unsigned len)
{
    return (len <= 8U) || (len == 12U) || (len == 16U) || (len == 20U) || (len == 24U) ||
           (len == 32U) || (len == 48U) || (len == 64U);
}

/* Checks LEN bytes of data for a classic (FD false) or FD frame. */
int log_check_len(canlog_reader_t *r, bool fd, unsigned len)
{
    if (!fd && (len > CANLOG_MAX_DLEN)) {
        return log_fail(r, CANLOG_E_DLC, "%u data bytes, over 8 for classic CAN", len);
    }
    if (fd && (len > CANLOG_FD_MAX_DLEN)) {
        return log_fail(r, CANLOG_E_DLC, "%u data bytes, over 64 for CAN FD", len);
    }
    if (fd && !log_fd_len_valid(len)) {
        return log_fail(r, CANLOG_E_DLC,
                    "%u data bytes is not a CAN FD length (0-8, 12, 16, 20, 24, 32, 48, 64)",
                    len);
    }
    return 0;
}

/* ------------------------------------------------------------------ ids */

/* Hex id of DIGITS digits with value V (3: 11 bits; 8: 29 bits or an error
 * frame) to *id with its flags. */
int log_make_id(canlog_reader_t *r, int digits, uint32_t v, uint32_t *id)
{
    if (digits == 3) {
        if (v > CANLOG_SFF_MASK) {
            return log_fail(r, CANLOG_E_BAD_ID, "11-bit id %03X over 7FF", (unsigned)v);
        }
        *id = v;
        return 0;
    }
    if (digits == 8) {
        if ((v & CANLOG_ERR_FLAG) != 0U) {
            if ((v & (CANLOG_EFF_FLAG | CANLOG_RTR_FLAG)) != 0U) {
                return log_fail(r, CANLOG_E_BAD_ID, "error frame id %08X with bits over 1FFFFFFF",
                            (unsigned)v);
            }
            *id = v;
            return 0;
        }
        if (v > CANLOG_EFF_MASK) {
            return log_fail(r, CANLOG_E_BAD_ID, "29-bit id %08X over 1FFFFFFF", (unsigned)v);
        }
        *id = v | CANLOG_EFF_FLAG;
        return 0;
    }
    return log_fail(r, CANLOG_E_BAD_ID, "id of %d hex digits; 3 (11-bit) or 8 (29-bit) expected",
                digits);
}

/* ------------------------------------------------------------------ time */

/* Accepts time T (in the base TB) for the frame of this line: checks the
 * order, fixes the time base. */
int log_accept_time(canlog_reader_t *r, canlog_time_base_t tb, uint64_t t, uint64_t *out)
{
    if ((r->time_base != CANLOG_TB_UNKNOWN) && (r->time_base != tb)) {
        return log_fail(r, CANLOG_E_BAD_TIME, "timestamp of another kind (%s) than earlier lines (%s)",
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
        return log_fail(r, CANLOG_E_BACKWARDS, "%llu.%06llu s is before the previous frame's %llu.%06llu s%s",
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

int log_paren_close(canlog_reader_t *r, const char **pp, int frac_digits)
{
    char cbuf[16];
    const char *p = *pp;
    if (*p != ')') {
        if (*p == '\0') {
            return log_fail(r, CANLOG_E_TRUNCATED, "line ends in the timestamp");
        }
        return log_fail(r, CANLOG_E_BAD_TIME, "%s where ')' should close the timestamp",
                        log_show_char(*p, cbuf));
    }
    if ((frac_digits != 6) && (frac_digits != 9)) {
        return log_fail(r, CANLOG_E_BAD_TIME, "%d fraction digits; 6 or 9 expected", frac_digits);
    }
    *pp = skip_blanks(p + 1);
    return 0;
}

int log_paren_seconds(canlog_reader_t *r, const char **pp, uint64_t *us, int *sec_digits)
{
    int nf;
    if (log_parse_seconds(pp, us, sec_digits, &nf) != 0) {
        if (**pp == '\0') {
            return log_fail(r, CANLOG_E_TRUNCATED, "line ends in the timestamp");
        }
        return log_fail(r, CANLOG_E_BAD_TIME, "expected (SECONDS.FRACTION)");
    }
    return log_paren_close(r, pp, nf);
}

/* Copies the interface token [p, e) into f->iface. */
int log_take_iface(canlog_reader_t *r, const char *p, const char *e, canlog_frame_t *f)
{
    const size_t n = (size_t)(e - p);
    if (n == 0U) {
        return log_fail(r, CANLOG_E_TRUNCATED, "no interface name");
    }
    if (n >= CANLOG_IFNAME_MAX) {
        return log_fail(r, CANLOG_E_SYNTAX, "interface name of %zu characters, over %u", n,
                    CANLOG_IFNAME_MAX - 1U);
    }
    memcpy(f->iface, p, n);
    f->iface[n] = '\0';
    return 0;
}

bool log_is_comment(const char *p)
{
    return (*p == '\0') || (*p == '#') || ((p[0] == '/') && (p[1] == '/'));
}

/* candump's "DROPCOUNT: dropped N CAN frame(s) on 'IF' socket (total drops T)":
 * true, and N added to r->dropped, when P starts with "DROPCOUNT:". */
bool log_note_dropcount(canlog_reader_t *r, const char *p)
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
                return log_fail(r, CANLOG_E_EMPTY, "no CAN frames (%llu line%s)",
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
                rc = log_fail(r, log_looks_binary(line, len) ? CANLOG_E_BINARY : CANLOG_E_FORMAT,
                          "neither a candump log, candump output nor Vector ASC line");
                if (r->mode == CANLOG_ON_ERROR_SKIP) {
                    continue;
                }
                return rc;
            }
            if ((fmt == (int)CANLOG_FMT_AUTO) && log_looks_binary(line, len)) {
                /* a NUL first looks like a blank line: it is not text */
                r->saw_content = true;
                rc = log_fail(r, CANLOG_E_BINARY, "control characters or NUL bytes in the line");
                if (r->mode == CANLOG_ON_ERROR_SKIP) {
                    continue;
                }
                return rc;
            }
            if (fmt == (int)CANLOG_FMT_AUTO) {
                (void)log_note_dropcount(r, skip_blanks(line));
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
            rc = log_parse_log_line(r, line, f);
            break;
        case CANLOG_FMT_PRINTED:
        case CANLOG_FMT_PRINTED_DELTA:
            rc = log_parse_printed_line(r, line, f);
            break;
        case CANLOG_FMT_ASC:
        default:
            rc = log_parse_asc_line(r, line, f);
            break;
        }
        if ((rc == 0) && (memchr(line, '\0', len) != NULL)) {
            /* a NUL cut the line short: what follows it was not read */
            r->saw_content = true;
            rc = log_fail(r, CANLOG_E_BINARY, "NUL byte in the line");
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
        if ((rc > 0) && log_looks_binary(line, len)) {
            r->saw_content = true;
            rc = log_fail(r, CANLOG_E_BINARY, "control characters or NUL bytes in the line");
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
        if ((rc != -(int)CANLOG_E_BINARY) && log_looks_binary(line, len)) {
            r->errors[-rc]--;
            r->error_lines--;
            if (r->errors[-rc] == 0U) {
                r->first_msg[-rc][0] = '\0';
            }
            rc = log_fail(r, CANLOG_E_BINARY, "control characters or NUL bytes in the line");
        }
        if (r->mode == CANLOG_ON_ERROR_SKIP) {
            continue;
        }
        return rc;
    }
}

