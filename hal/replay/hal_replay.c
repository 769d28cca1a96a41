/* hal_replay.c - a CAN bus replayed from a candump log (contract in hal_replay.h). */
#include "hal/replay/hal_replay.h"

#include <stddef.h>
#include <string.h>

#include "hal/hal_can_mem.h"

#define CAN_ERR_FLAG_ID 0x20000000UL   /* Linux can.h CAN_ERR_FLAG, as candump prints it */
#define MAX_SECONDS_DIGITS 12U         /* < 10^12 s: the microsecond count fits 64 bits */

/* ------------------------------------------------------------------ record */

static void record_write(hal_replay_bus_t *bus, const char *s, uint32_t n)
{
    if ((bus->write == NULL) || bus->stats.record_failed) {
        return;
    }
    if ((bus->out_len + n) > HAL_REPLAY_OUT_BUF) {
        if (bus->write(bus->write_ctx, (const uint8_t *)bus->out, bus->out_len) < 0) {
            bus->stats.record_failed = true;
            return;
        }
        bus->out_len = 0U;
    }
    (void)memcpy(&bus->out[bus->out_len], s, n);
    bus->out_len += n;
}

/* Decimal digits of v backwards from end; returns the first digit. */
static char *put_u64(uint64_t v, char *end)
{
    char *p = end;
    uint64_t rest = v;
    do {
        --p;
        *p = (char)('0' + (int)(rest % 10U));
        rest /= 10U;
    } while (rest != 0U);
    return p;
}

static void put_hex(char *p, uint32_t v, uint32_t digits)
{
    static const char hex[16] = {'0', '1', '2', '3', '4', '5', '6', '7',
                                 '8', '9', 'A', 'B', 'C', 'D', 'E', 'F'};
    for (uint32_t k = 0U; k < digits; k++) {
        p[k] = hex[(v >> (4U * (digits - 1U - k))) & 0xFU];
    }
}

/* "(sec.usec) IFACE ID#DATA\n": at most 1 + 20 + 1 + 6 + 2 + 15 + 1 + 8 + 1 + 16 + 1 characters. */
static void record_frame(hal_replay_bus_t *bus, const pfe_can_frame_t *f, uint64_t t_us)
{
    if (bus->write == NULL) {
        return;
    }
    char buf[80];
    char digits[21];
    uint32_t n = 0U;
    buf[n++] = '(';
    const char *sec = put_u64(t_us / 1000000U, &digits[20]);
    const uint32_t sec_len = (uint32_t)(&digits[20] - sec);
    (void)memcpy(&buf[n], sec, sec_len);
    n += sec_len;
    buf[n++] = '.';
    uint32_t usec = (uint32_t)(t_us % 1000000U);
    for (uint32_t k = 6U; k > 0U; k--) {
        buf[n + k - 1U] = (char)('0' + (int)(usec % 10U));
        usec /= 10U;
    }
    n += 6U;
    buf[n++] = ')';
    buf[n++] = ' ';
    const uint32_t if_len = (uint32_t)strlen(bus->ifname);
    (void)memcpy(&buf[n], bus->ifname, if_len);
    n += if_len;
    buf[n++] = ' ';
    if ((f->id & PFE_CAN_EFF_FLAG) != 0U) {
        put_hex(&buf[n], f->id & PFE_CAN_ID_MASK, 8U);
        n += 8U;
    } else {
        put_hex(&buf[n], f->id, 3U);
        n += 3U;
    }
    buf[n++] = '#';
    for (uint8_t k = 0U; k < f->dlc; k++) {
        put_hex(&buf[n], f->data[k], 2U);
        n += 2U;
    }
    buf[n++] = '\n';
    record_write(bus, buf, n);
    bus->stats.recorded++;
}

/* ------------------------------------------------------------------ bus */

/* Puts one frame on the bus: every open handle but `from` whose filters
 * accept it receives it, stamped t_us; the record gets it. */
static void deliver(hal_replay_bus_t *bus, const pfe_can_frame_t *f, uint64_t t_us,
                    const hal_can_t *from)
{
    for (uint32_t k = 0U; k < HAL_REPLAY_MAX_HANDLES; k++) {
        hal_can_t *h = &bus->handle[k];
        if (h->open && (h != from)) {
            hal_can_mem_port_offer(&h->port, f, t_us);
        }
    }
    record_frame(bus, f, t_us);
}

/* ------------------------------------------------------------------ log input */

static int hex_digit(char c)
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

typedef enum { LINE_FRAME, LINE_EMPTY, LINE_NOT_CLASSIC, LINE_BAD } line_kind_t;

static bool is_blank(char c)
{
    return (c == ' ') || (c == '\t');
}

/* The first index at or after i that is not a blank (n at the end). */
static size_t skip_blanks(const char *s, size_t i, size_t n)
{
    size_t k = i;
    while ((k < n) && is_blank(s[k])) {
        k++;
    }
    return k;
}

/* The first index at or after i that is a blank (n at the end). */
static size_t token_end(const char *s, size_t i, size_t n)
{
    size_t k = i;
    while ((k < n) && !is_blank(s[k])) {
        k++;
    }
    return k;
}

/* Whether the len characters at a are those of b (no memcmp: MISRA 21.14). */
static bool same_chars(const char *a, const char *b, size_t len)
{
    for (size_t k = 0U; k < len; k++) {
        if (a[k] != b[k]) {
            return false;
        }
    }
    return true;
}

/* Whether the token at i (up to a blank or the end) is word. */
static bool token_is(const char *s, size_t i, size_t n, const char *word)
{
    const size_t len = strlen(word);
    return ((i + len) <= n) && same_chars(&s[i], word, len) &&
           (((i + len) == n) || is_blank(s[i + len]));
}

static bool starts_with(const char *s, size_t i, size_t n, const char *prefix)
{
    const size_t len = strlen(prefix);
    return ((i + len) <= n) && same_chars(&s[i], prefix, len);
}

/* count decimal digits at s[*i] into *v; false if any is missing. */
static bool digits_n(const char *s, size_t *i, size_t n, uint32_t count, uint32_t *v)
{
    uint32_t x = 0U;
    for (uint32_t k = 0U; k < count; k++) {
        if ((*i >= n) || !is_digit(s[*i])) {
            return false;
        }
        x = (x * 10U) + (uint32_t)(s[*i] - '0');
        (*i)++;
    }
    *v = x;
    return true;
}

/* Days from 1970-01-01 to y-m-d of the proleptic Gregorian calendar, for
 * y >= 1970 (the civil-from-days inverse by eras of 400 years). */
static uint64_t days_from_civil(uint32_t y, uint32_t m, uint32_t d)
{
    const uint32_t yy = (m <= 2U) ? (y - 1U) : y;
    const uint32_t era = yy / 400U;
    const uint32_t yoe = yy - (era * 400U);                         /* 0 .. 399 */
    const uint32_t mp = (m > 2U) ? (m - 3U) : (m + 9U);            /* March = 0 */
    const uint32_t doy = ((((153U * mp) + 2U) / 5U) + d) - 1U;     /* 0 .. 365 */
    const uint32_t doe = (((yoe * 365U) + (yoe / 4U)) - (yoe / 100U)) + doy;
    return (((uint64_t)era * 146097U) + doe) - 719468U;
}

/* "SECONDS.FRACTION" at s[*i]: 1 to MAX_SECONDS_DIGITS digits, then 6 or 9
 * fraction digits (nine truncated to microseconds). */
static bool parse_seconds(const char *s, size_t *i, size_t n, uint64_t *us, uint32_t *sec_digits)
{
    uint64_t sec = 0U;
    uint32_t digits = 0U;
    while ((*i < n) && is_digit(s[*i])) {
        if (digits == MAX_SECONDS_DIGITS) {
            return false;
        }
        sec = (sec * 10U) + (uint64_t)(s[*i] - '0');
        digits++;
        (*i)++;
    }
    if ((digits == 0U) || (*i >= n) || (s[*i] != '.')) {
        return false;
    }
    (*i)++;
    uint32_t frac = 0U;
    uint32_t fdigits = 0U;
    while ((*i < n) && is_digit(s[*i]) && (fdigits < 9U)) {
        frac = (frac * 10U) + (uint32_t)(s[*i] - '0');
        fdigits++;
        (*i)++;
    }
    if ((fdigits != 6U) && (fdigits != 9U)) {
        return false;
    }
    *us = (sec * 1000000U) + ((fdigits == 9U) ? (frac / 1000U) : frac);
    *sec_digits = digits;
    return true;
}

/* candump -t A's "YYYY-MM-DD HH:MM:SS.FRACTION", read as UTC (the output
 * does not say the recording machine's zone; intervals are exact). */
static bool parse_date(const char *s, size_t *i, size_t n, uint64_t *us)
{
    uint32_t y = 0U;
    uint32_t mo = 0U;
    uint32_t d = 0U;
    uint32_t h = 0U;
    uint32_t mi = 0U;
    uint32_t sd = 0U;
    uint64_t sec_us = 0U;
    bool ok = digits_n(s, i, n, 4U, &y) && (*i < n) && (s[*i] == '-');
    if (ok) {
        (*i)++;
        ok = digits_n(s, i, n, 2U, &mo) && (*i < n) && (s[*i] == '-');
    }
    if (ok) {
        (*i)++;
        ok = digits_n(s, i, n, 2U, &d) && (*i < n) && (s[*i] == ' ');
    }
    if (ok) {
        (*i)++;
        ok = digits_n(s, i, n, 2U, &h) && (*i < n) && (s[*i] == ':');
    }
    if (ok) {
        (*i)++;
        ok = digits_n(s, i, n, 2U, &mi) && (*i < n) && (s[*i] == ':');
    }
    if (ok) {
        (*i)++;
        ok = parse_seconds(s, i, n, &sec_us, &sd) && (sd == 2U) && (sec_us < 61000000U);
    }
    if (!ok || (y < 1970U) || (mo < 1U) || (mo > 12U) || (d < 1U) || (d > 31U) || (h > 23U) ||
        (mi > 59U)) {
        return false;
    }
    const uint64_t s_of_day = ((uint64_t)h * 3600U) + ((uint64_t)mi * 60U);
    *us = (((days_from_civil(y, mo, d) * 86400U) + s_of_day) * 1000000U) + sec_us;
    return true;
}

/* A hex id of 3 digits (11-bit, up to 7FF) or 8 (29-bit, or an error frame
 * with CAN_ERR_FLAG) in s[from, to): LINE_FRAME with *id (| PFE_CAN_EFF_FLAG),
 * LINE_NOT_CLASSIC for an error frame, or LINE_BAD. */
static line_kind_t parse_id(const char *s, size_t from, size_t to, uint32_t *id,
                            hal_replay_reason_t *why)
{
    const size_t len = to - from;
    uint32_t v = 0U;
    *why = HAL_REPLAY_BAD_ID;
    if ((len != 3U) && (len != 8U)) {
        return LINE_BAD;
    }
    for (size_t k = from; k < to; k++) {
        const int h = hex_digit(s[k]);
        if (h < 0) {
            return LINE_BAD;
        }
        v = (v << 4) | (uint32_t)h;
    }
    if ((len == 8U) && ((v & CAN_ERR_FLAG_ID) != 0U) && ((v & 0xC0000000UL) == 0U)) {
        return LINE_NOT_CLASSIC; /* error frame */
    }
    if (((len == 3U) && (v > 0x7FFU)) || ((len == 8U) && (v > PFE_CAN_ID_MASK))) {
        return LINE_BAD;
    }
    *id = (len == 8U) ? (v | PFE_CAN_EFF_FLAG) : v;
    return LINE_FRAME;
}

/* candump -L's frame "ID#DATA" at s[*i] (and its remote, FD and error
 * forms, skipped), then an optional direction R or T. */
static line_kind_t parse_compact(const char *s, size_t i, size_t n, pfe_can_frame_t *f,
                                 hal_replay_reason_t *why)
{
    size_t k = i;
    while ((k < n) && (s[k] != '#')) {
        k++;
    }
    uint32_t id = 0U;
    const line_kind_t idk = parse_id(s, i, k, &id, why);
    if (idk != LINE_FRAME) {
        return idk;
    }
    k++; /* '#' */
    if ((k < n) && ((s[k] == '#') || (s[k] == 'R') || (s[k] == 'r'))) {
        return LINE_NOT_CLASSIC; /* CAN FD or remote */
    }
    *why = HAL_REPLAY_BAD_DATA;
    uint32_t len = 0U;
    while ((k < n) && !is_blank(s[k])) {
        if (s[k] == '.') {
            k++;
            continue;
        }
        if ((k + 1U) >= n) {
            return LINE_BAD; /* odd number of digits */
        }
        const int hi = hex_digit(s[k]);
        const int lo = hex_digit(s[k + 1U]);
        if ((hi < 0) || (lo < 0)) {
            return LINE_BAD;
        }
        if (len == PFE_CAN_MAX_DLC) {
            *why = HAL_REPLAY_BAD_LENGTH;
            return LINE_BAD;
        }
        f->data[len] = (uint8_t)(((uint32_t)hi << 4) | (uint32_t)lo);
        len++;
        k += 2U;
    }
    k = skip_blanks(s, k, n);
    /* candump -x may end a line with its direction flag: " R" or " T". */
    if ((k < n) && (token_is(s, k, n, "R") || token_is(s, k, n, "T"))) {
        k = skip_blanks(s, k + 1U, n);
    }
    if (k < n) {
        *why = HAL_REPLAY_BAD_SYNTAX;
        return LINE_BAD;
    }
    f->id = id;
    f->dlc = (uint8_t)len;
    return LINE_FRAME;
}

/* candump's printed frame at s[i]: [RX|TX B|- E|-] ID [LEN] XX XX ...
 * [ERRORFRAME] ['ascii'], or "[LEN] remote request"; a two-digit length
 * is CAN FD. */
static line_kind_t parse_printed(const char *s, size_t i, size_t n, pfe_can_frame_t *f,
                                 hal_replay_reason_t *why)
{
    size_t k = i;
    *why = HAL_REPLAY_BAD_SYNTAX;
    if (token_is(s, k, n, "RX") || token_is(s, k, n, "TX")) {
        k = skip_blanks(s, k + 2U, n);
        if (!(token_is(s, k, n, "-") || token_is(s, k, n, "B"))) {
            return LINE_BAD;
        }
        const bool brs = s[k] == 'B';
        k = skip_blanks(s, k + 1U, n);
        if (!(token_is(s, k, n, "-") || token_is(s, k, n, "E"))) {
            return LINE_BAD;
        }
        k = skip_blanks(s, k + 1U, n);
        if (brs) {
            return LINE_NOT_CLASSIC; /* bit rate switch: CAN FD */
        }
    }
    const size_t id_end = token_end(s, k, n);
    uint32_t id = 0U;
    const line_kind_t idk = parse_id(s, k, id_end, &id, why);
    if (idk == LINE_BAD) {
        return LINE_BAD;
    }
    k = skip_blanks(s, id_end, n);
    *why = HAL_REPLAY_BAD_SYNTAX;
    if ((k >= n) || (s[k] != '[')) {
        return LINE_BAD;
    }
    k++;
    uint32_t len = 0U;
    uint32_t ld = 0U;
    while ((k < n) && is_digit(s[k]) && (ld < 3U)) {
        len = (len * 10U) + (uint32_t)(s[k] - '0');
        ld++;
        k++;
    }
    if ((ld == 0U) || (ld > 2U) || (k >= n) || (s[k] != ']')) {
        *why = (ld > 2U) ? HAL_REPLAY_BAD_LENGTH : HAL_REPLAY_BAD_SYNTAX;
        return LINE_BAD;
    }
    k = skip_blanks(s, k + 1U, n);
    if (token_is(s, k, n, "remote")) {
        k = skip_blanks(s, k + 6U, n);
        if (!token_is(s, k, n, "request") || (len > PFE_CAN_MAX_DLC) ||
            (skip_blanks(s, k + 7U, n) < n)) {
            *why = (len > PFE_CAN_MAX_DLC) ? HAL_REPLAY_BAD_LENGTH : HAL_REPLAY_BAD_SYNTAX;
            return LINE_BAD;
        }
        return LINE_NOT_CLASSIC;
    }
    if ((ld == 2U) || (idk == LINE_NOT_CLASSIC)) {
        return LINE_NOT_CLASSIC; /* CAN FD, or an error frame */
    }
    if (len > PFE_CAN_MAX_DLC) {
        *why = HAL_REPLAY_BAD_LENGTH;
        return LINE_BAD;
    }
    *why = HAL_REPLAY_BAD_DATA;
    for (uint32_t b = 0U; b < len; b++) {
        if (((k + 2U) > n) || (((k + 2U) < n) && !is_blank(s[k + 2U]))) {
            return LINE_BAD;
        }
        const int hi = hex_digit(s[k]);
        const int lo = hex_digit(s[k + 1U]);
        if ((hi < 0) || (lo < 0)) {
            return LINE_BAD;
        }
        f->data[b] = (uint8_t)(((uint32_t)hi << 4) | (uint32_t)lo);
        k = skip_blanks(s, k + 2U, n);
    }
    /* -a's ASCII column follows in quotes; anything else is an error
     * (more bytes than the length says, or text). */
    if ((k < n) && (s[k] != '\'') && (s[k] != '`')) {
        *why = ((hex_digit(s[k]) >= 0) && ((k + 1U) < n) && (hex_digit(s[k + 1U]) >= 0))
                   ? HAL_REPLAY_BAD_LENGTH
                   : HAL_REPLAY_BAD_SYNTAX;
        return LINE_BAD;
    }
    f->id = id;
    f->dlc = (uint8_t)len;
    return LINE_FRAME;
}

/* Parses one line (NUL-terminated, no newline): candump -L's log line or
 * candump's printed line with a timestamp. LINE_FRAME fills *f, *t_us and,
 * for the first frame, the record interface name. */
static line_kind_t parse_line(hal_replay_bus_t *bus, const char *s, pfe_can_frame_t *f,
                              uint64_t *t_us, hal_replay_reason_t *why)
{
    size_t n = strlen(s);
    if ((n > 0U) && (s[n - 1U] == '\r')) {
        n--;
    }
    size_t i = skip_blanks(s, 0U, n);
    if ((i == n) || (s[i] == '#') || starts_with(s, i, n, "//") ||
        starts_with(s, i, n, "DROPCOUNT:") || ((s[0] == '\t') && (s[i] != '('))) {
        return LINE_EMPTY; /* blank, comment, candump's drop report, -e's detail lines */
    }
    if (s[i] != '(') {
        /* candump's printed output without -t has no time to replay at */
        *why = (memchr(s, '[', n) != NULL) ? HAL_REPLAY_BAD_NO_TIME : HAL_REPLAY_BAD_SYNTAX;
        return LINE_BAD;
    }
    i++;
    *why = HAL_REPLAY_BAD_TIME;
    uint64_t t = 0U;
    uint32_t sec_digits = 0U;
    const bool date = ((i + 4U) < n) && is_digit(s[i]) && is_digit(s[i + 1U]) &&
                      is_digit(s[i + 2U]) && is_digit(s[i + 3U]) && (s[i + 4U] == '-');
    const bool time_ok = date ? parse_date(s, &i, n, &t) : parse_seconds(s, &i, n, &t, &sec_digits);
    if (!time_ok || (i >= n) || (s[i] != ')')) {
        return LINE_BAD;
    }
    i++;
    *why = HAL_REPLAY_BAD_SYNTAX;
    if ((i >= n) || !is_blank(s[i])) {
        return LINE_BAD;
    }
    i = skip_blanks(s, i, n);
    const size_t if_start = i;
    while ((i < n) && !is_blank(s[i]) && ((unsigned char)s[i] > 0x20U) &&
           ((unsigned char)s[i] < 0x7FU)) {
        i++;
    }
    const size_t if_len = i - if_start;
    if ((if_len == 0U) || (if_len > HAL_REPLAY_IFNAME_MAX) || (i >= n) || !is_blank(s[i])) {
        return LINE_BAD;
    }
    i = skip_blanks(s, i, n);
    const size_t frame_end = token_end(s, i, n);
    const bool compact = memchr(&s[i], '#', frame_end - i) != NULL;
    const line_kind_t kind = compact ? parse_compact(s, i, n, f, why) : parse_printed(s, i, n, f, why);
    if (kind != LINE_FRAME) {
        return kind;
    }
    for (uint32_t k = f->dlc; k < PFE_CAN_MAX_DLC; k++) {
        f->data[k] = 0U;
    }
    *t_us = t;
    if (!bus->ifname_fixed && !bus->any_log_frame) {
        (void)memcpy(bus->ifname, &s[if_start], if_len);
        bus->ifname[if_len] = '\0';
    }
    return LINE_FRAME;
}

/* Next input byte: 1 and *c, or 0 at the end (or after a read error). */
static int next_byte(hal_replay_bus_t *bus, char *c)
{
    if (bus->in_pos == bus->in_len) {
        if (bus->in_end || (bus->read == NULL)) {
            return 0;
        }
        const int32_t got = bus->read(bus->read_ctx, bus->in, HAL_REPLAY_IN_CHUNK);
        if (got <= 0) {
            bus->in_end = true;
            bus->stats.read_failed = bus->stats.read_failed || (got < 0);
            return 0;
        }
        bus->in_pos = 0U;
        bus->in_len = ((uint32_t)got > HAL_REPLAY_IN_CHUNK) ? HAL_REPLAY_IN_CHUNK : (uint32_t)got;
    }
    *c = (char)bus->in[bus->in_pos++];
    return 1;
}

/* Reads one line into bus->line: false at the end of the input. *too_long
 * when it had more than HAL_REPLAY_LINE_MAX characters (the rest is read
 * and dropped). */
static bool read_line(hal_replay_bus_t *bus, bool *too_long)
{
    uint32_t n = 0U;
    bool any = false;
    char c = '\0';
    *too_long = false;
    while (next_byte(bus, &c) != 0) {
        any = true;
        if (c == '\n') {
            break;
        }
        if (n < HAL_REPLAY_LINE_MAX) {
            /* A NUL would cut the line short: keep it visible as a bad byte. */
            bus->line[n++] = (c == '\0') ? '\x01' : c;
        } else {
            *too_long = true;
        }
    }
    bus->line[n] = '\0';
    return any;
}

static void bad_line(hal_replay_bus_t *bus, hal_replay_reason_t why)
{
    bus->stats.bad_lines++;
    if (bus->stats.first_bad_line == 0U) {
        bus->stats.first_bad_line = bus->stats.lines;
        bus->stats.first_bad_reason = why;
    }
}

/* bus->next.frame, read at t_us, is the next log frame. */
static void accept_next(hal_replay_bus_t *bus, uint64_t t_us)
{
    uint64_t t = t_us;
    if (bus->any_log_frame && (t < bus->last_log_us)) {
        bus->stats.time_backwards++;
        t = bus->last_log_us;
    }
    bus->any_log_frame = true;
    bus->last_log_us = t;
    bus->next.timestamp_us = t;
    bus->have_next = true;
}

/* Reads ahead to the next log frame. */
static void load_next(hal_replay_bus_t *bus)
{
    bus->have_next = false;
    if (bus->source != NULL) {
        char name[HAL_REPLAY_IFNAME_MAX + 1U];
        uint64_t t_us = 0U;
        name[0] = '\0';
        if (bus->source(bus->source_ctx, &bus->next.frame, &t_us, name, &bus->stats) <= 0) {
            return;
        }
        name[HAL_REPLAY_IFNAME_MAX] = '\0';
        if (!bus->ifname_fixed && !bus->any_log_frame && (name[0] != '\0')) {
            (void)memcpy(bus->ifname, name, sizeof name);
        }
        accept_next(bus, t_us);
        return;
    }
    bool too_long = false;
    while (read_line(bus, &too_long)) {
        bus->stats.lines++;
        if (too_long) {
            bad_line(bus, HAL_REPLAY_LINE_TOO_LONG);
            continue;
        }
        hal_replay_reason_t why = HAL_REPLAY_LINE_OK;
        uint64_t t_us = 0U;
        const line_kind_t kind = parse_line(bus, bus->line, &bus->next.frame, &t_us, &why);
        if (kind == LINE_EMPTY) {
            continue;
        }
        if (kind == LINE_NOT_CLASSIC) {
            bus->stats.skipped_not_classic++;
            continue;
        }
        if (kind == LINE_BAD) {
            bad_line(bus, why);
            continue;
        }
        accept_next(bus, t_us);
        return;
    }
}

/* ------------------------------------------------------------------ public */

static void init_bus(hal_replay_bus_t *bus, hal_replay_read_fn read, void *read_ctx,
                     hal_replay_source_fn source, void *source_ctx, hal_replay_write_fn write,
                     void *write_ctx, const char *record_ifname)
{
    (void)memset(bus, 0, sizeof *bus);
    bus->time.bus = bus;
    bus->read = read;
    bus->read_ctx = read_ctx;
    bus->source = source;
    bus->source_ctx = source_ctx;
    bus->write = write;
    bus->write_ctx = write_ctx;
    const char *name = "can0";
    if (record_ifname != NULL) {
        name = record_ifname;
        bus->ifname_fixed = true;
    }
    size_t len = strlen(name);
    if (len > HAL_REPLAY_IFNAME_MAX) {
        len = HAL_REPLAY_IFNAME_MAX;
    }
    (void)memcpy(bus->ifname, name, len);
    bus->ifname[len] = '\0';
    load_next(bus);
    if (bus->have_next) {
        bus->now_us = bus->next.timestamp_us;
    }
}

void hal_replay_init(hal_replay_bus_t *bus, hal_replay_read_fn read, void *read_ctx,
                     hal_replay_write_fn write, void *write_ctx, const char *record_ifname)
{
    init_bus(bus, read, read_ctx, NULL, NULL, write, write_ctx, record_ifname);
}

void hal_replay_init_source(hal_replay_bus_t *bus, hal_replay_source_fn source, void *source_ctx,
                            hal_replay_write_fn write, void *write_ctx, const char *record_ifname)
{
    init_bus(bus, NULL, NULL, source, source_ctx, write, write_ctx, record_ifname);
}

bool hal_replay_next_us(const hal_replay_bus_t *bus, uint64_t *t_us)
{
    if (bus->have_next && (t_us != NULL)) {
        *t_us = bus->next.timestamp_us;
    }
    return bus->have_next;
}

void hal_replay_advance_to(hal_replay_bus_t *bus, uint64_t now_us)
{
    if (now_us > bus->now_us) {
        bus->now_us = now_us;
    }
    while (bus->have_next && (bus->next.timestamp_us <= bus->now_us)) {
        deliver(bus, &bus->next.frame, bus->next.timestamp_us, NULL);
        bus->stats.frames++;
        load_next(bus);
    }
}

uint64_t hal_replay_now_us(const hal_replay_bus_t *bus)
{
    return bus->now_us;
}

hal_time_t *hal_replay_time(hal_replay_bus_t *bus)
{
    return &bus->time;
}

uint64_t hal_time_now_us(hal_time_t *time)
{
    return time->bus->now_us;
}

int hal_time_wait_until_us(hal_time_t *time, uint64_t deadline_us)
{
    hal_replay_advance_to(time->bus, deadline_us);
    return 0;
}

hal_can_t *hal_replay_open(hal_replay_bus_t *bus)
{
    for (uint32_t k = 0U; k < HAL_REPLAY_MAX_HANDLES; k++) {
        hal_can_t *h = &bus->handle[k];
        if (!h->open) {
            (void)memset(h, 0, sizeof *h);
            h->bus = bus;
            h->open = true;
            hal_can_mem_port_init(&h->port, h->rx, HAL_REPLAY_RX_QUEUE);
            return h;
        }
    }
    return NULL;
}

void hal_replay_close(hal_can_t *can)
{
    if (can != NULL) {
        can->open = false;
    }
}

int hal_replay_flush(hal_replay_bus_t *bus)
{
    if ((bus->write != NULL) && !bus->stats.record_failed && (bus->out_len > 0U)) {
        if (bus->write(bus->write_ctx, (const uint8_t *)bus->out, bus->out_len) < 0) {
            bus->stats.record_failed = true;
        }
        bus->out_len = 0U;
    }
    return bus->stats.record_failed ? HAL_EIO : 0;
}

const hal_replay_stats_t *hal_replay_stats(const hal_replay_bus_t *bus)
{
    return &bus->stats;
}

const char *hal_replay_reason_text(hal_replay_reason_t reason)
{
    switch (reason) {
    case HAL_REPLAY_LINE_OK:
        return "no error";
    case HAL_REPLAY_BAD_SYNTAX:
        return "not a candump line: (seconds.fraction) interface id#data, or candump's printed "
               "(time) interface id [length] bytes";
    case HAL_REPLAY_BAD_TIME:
        return "bad timestamp: digits, then 6 or 9 fraction digits";
    case HAL_REPLAY_BAD_ID:
        return "bad CAN id: 3 hex digits up to 7FF or 8 up to 1FFFFFFF";
    case HAL_REPLAY_BAD_DATA:
        return "bad data: pairs of hex digits";
    case HAL_REPLAY_BAD_LENGTH:
        return "more than 8 data bytes";
    case HAL_REPLAY_LINE_TOO_LONG:
        return "line too long";
    case HAL_REPLAY_BAD_NO_TIME:
        return "no timestamp: candump output needs -t a, z, d or A to be replayed";
    case HAL_REPLAY_BAD_OTHER:
        return "not a CAN frame line";
    default:
        return "unknown";
    }
}

/* ------------------------------------------------------------------ hal_can.h */

int hal_can_send(hal_can_t *can, const pfe_can_frame_t *frame)
{
    if ((can == NULL) || !can->open || (frame == NULL) || !hal_can_mem_frame_valid(frame)) {
        return HAL_EINVAL;
    }
    hal_replay_bus_t *bus = can->bus;
    deliver(bus, frame, bus->now_us, can);
    can->port.stats.tx_frames++;
    bus->stats.sent_frames++;
    return 0;
}

hal_can_mem_port_t *hal_can_mem_port_of(hal_can_t *can, bool *open)
{
    *open = can->open;
    return &can->port;
}

void hal_can_get_stats(const hal_can_t *can, hal_can_stats_t *out)
{
    *out = can->port.stats;
}

/* ------------------------------------------------------------------ hal_nvm.h */

void hal_replay_nvm_init(hal_nvm_t *nvm)
{
    (void)memset(nvm->slot, 0xFF, sizeof nvm->slot);
    nvm->writes = 0U;
}

int hal_nvm_read(hal_nvm_t *nvm, uint32_t slot, uint8_t buf[PFE_NVM_RECORD_SIZE])
{
    if ((nvm == NULL) || (slot >= PFE_NVM_SLOTS) || (buf == NULL)) {
        return HAL_EINVAL;
    }
    (void)memcpy(buf, nvm->slot[slot], PFE_NVM_RECORD_SIZE);
    return 0;
}

int hal_nvm_write(hal_nvm_t *nvm, uint32_t slot, const uint8_t buf[PFE_NVM_RECORD_SIZE])
{
    if ((nvm == NULL) || (slot >= PFE_NVM_SLOTS) || (buf == NULL)) {
        return HAL_EINVAL;
    }
    (void)memcpy(nvm->slot[slot], buf, PFE_NVM_RECORD_SIZE);
    nvm->writes++;
    return 0;
}
