/* log_asc.c - Vector ASC (contract in log.h). */
#define _POSIX_C_SOURCE 200809L

#include "lib/log/log_parse.h"

#include <stdio.h>
#include <string.h>

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
            return log_fail(r, CANLOG_E_TRUNCATED, "no id");
        }
        return log_fail(r, r->asc_decimal ? CANLOG_E_SYNTAX : CANLOG_E_BAD_HEX, "%s in the id",
                    log_show_char(*bad, cbuf));
    }
    if (ext) {
        if (v > CANLOG_EFF_MASK) {
            return log_fail(r, CANLOG_E_BAD_ID, "29-bit id %X over 1FFFFFFF", (unsigned)v);
        }
        *id = v | CANLOG_EFF_FLAG;
    } else {
        if (v > CANLOG_SFF_MASK) {
            return log_fail(r, CANLOG_E_BAD_ID, "11-bit id %X over 7FF (29-bit ids end in 'x')",
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
            return log_fail(r, CANLOG_E_TRUNCATED, "%u data bytes of %u", i, len);
        }
        const char *e = token_end(p);
        uint32_t v;
        const char *bad = NULL;
        if ((e - p > 3) || (asc_number(r, p, e, &v, &bad) != 0) || (v > 0xFFU)) {
            return log_fail(r, CANLOG_E_BAD_HEX, "%s in data byte %u",
                        log_show_char((bad != NULL) ? *bad : *p, cbuf), i);
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
        return log_fail(r, CANLOG_E_SYNTAX, "channel must be 1 to 255");
    }
    for (; p < e; p++) {
        if (!is_digit(*p)) {
            return log_fail(r, CANLOG_E_SYNTAX, "channel must be 1 to 255");
        }
        v = (v * 10U) + (unsigned)(*p - '0');
    }
    if ((v < 1U) || (v > 255U)) {
        return log_fail(r, CANLOG_E_SYNTAX, "channel %u; 1 to 255 expected", v);
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
        return log_fail(r, (*p == '\0') ? CANLOG_E_TRUNCATED : CANLOG_E_SYNTAX,
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
            return log_fail(r, (*q == '\0') ? CANLOG_E_TRUNCATED : CANLOG_E_SYNTAX,
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
            return log_fail(r, CANLOG_E_SYNTAX, "data length must be decimal");
        }
        len = (len * 10U) + (unsigned)(*c - '0');
    }
    p = e;
    rc = log_check_len(r, true, len);
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
            return log_fail(r, CANLOG_E_SYNTAX, "flags field %s is not hex", log_show_char(*t3, cbuf));
        }
        classic = (flags & 0x1000U) == 0U;
        remote = classic && ((flags & 0x10U) != 0U);
    }
    /* A classic remote frame has length 0 and its requested length as DLC
     * (log2asc); every other frame's DLC gives its length. */
    if (remote ? (len != 0U) : (canlog_fd_dlc_to_len((uint8_t)dlc) != len)) {
        return log_fail(r, CANLOG_E_DLC, "DLC %X does not give %u data bytes", dlc, len);
    }
    if (remote) {
        if (dlc > 8U) {
            return log_fail(r, CANLOG_E_DLC, "remote frame DLC %X over 8", dlc);
        }
        f->id = id | CANLOG_RTR_FLAG;
        f->len = (uint8_t)dlc;
        f->fd = false;
        f->fd_flags = 0U;
    } else {
        if (classic) {
            rc = log_check_len(r, false, len);
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
            return idlike ? log_fail(r, CANLOG_E_TRUNCATED, "no direction (Rx/Tx) after the id") : 1;
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
                return log_fail(r, CANLOG_E_BAD_HEX, "%s as the remote frame's DLC",
                            log_show_char(*p, cbuf));
            }
            len = (unsigned)h;
            p = skip_blanks(p + 1);
        }
        if (len > CANLOG_MAX_DLEN) {
            return log_fail(r, CANLOG_E_DLC, "remote frame DLC %X over 8", len);
        }
        f->id = id | CANLOG_RTR_FLAG;
        f->len = (uint8_t)len;
        return txrq ? 1 : 0;
    }
    if (!token_is(p, "d")) {
        if (*p == '\0') {
            return log_fail(r, CANLOG_E_TRUNCATED, "no 'd DLC' after the direction");
        }
        return log_fail(r, CANLOG_E_SYNTAX, "%s where 'd' (data) or 'r' (remote) should be",
                    log_show_char(*p, cbuf));
    }
    p = skip_blanks(p + 1);
    if (*p == '\0') {
        return log_fail(r, CANLOG_E_TRUNCATED, "no DLC after 'd'");
    }
    const int dlc = hex_digit(*p);
    if ((dlc < 0) || !is_end(p[1])) {
        return log_fail(r, CANLOG_E_BAD_HEX, "%s as the DLC", log_show_char((dlc < 0) ? *p : p[1], cbuf));
    }
    rc = log_check_len(r, false, (unsigned)dlc);
    if (rc != 0) {
        return rc;
    }
    p = skip_blanks(p + 1);
    rc = asc_data(r, &p, (unsigned)dlc, f);
    if (rc != 0) {
        return rc;
    }
    if ((*p != '\0') && looks_like_byte(p)) {
        return log_fail(r, CANLOG_E_DLC, "more data bytes than DLC %d", dlc);
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
            return log_fail(r, CANLOG_E_SYNTAX, "base must be hex or dec");
        }
        p = skip_blanks(token_end(p));
        if (!token_is(p, "timestamps")) {
            return log_fail(r, CANLOG_E_SYNTAX, "expected 'timestamps absolute|relative' after base");
        }
        p = skip_blanks(p + 10);
        if (token_is(p, "absolute")) {
            r->asc_relative = false;
        } else if (token_is(p, "relative")) {
            r->asc_relative = true;
        } else {
            return log_fail(r, CANLOG_E_SYNTAX, "timestamps must be absolute or relative");
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
    return log_fail(r, CANLOG_E_SYNTAX, "%s: not an ASC header, comment or event line",
                log_show_char(*p, cbuf));
}

int log_parse_asc_line(canlog_reader_t *r, const char *line, canlog_frame_t *f)
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
    if ((log_parse_seconds(&p, &t, &sd, &nf) != 0) || !is_end(*p)) {
        return log_fail(r, CANLOG_E_BAD_TIME, "expected SECONDS.FRACTION at the start of an event");
    }
    if (r->asc_relative) {
        t += r->acc_time_us;
        r->acc_time_us = t;
    }
    p = skip_blanks(p);
    if (*p == '\0') {
        return log_fail(r, CANLOG_E_TRUNCATED, "nothing after the time");
    }
    int rc;
    if (token_is(p, "CANFD")) {
        rc = parse_asc_fd(r, p, f);
    } else if (token_is(p, "CANXL")) {
        return log_fail(r, CANLOG_E_SYNTAX, "CAN XL events are not supported");
    } else {
        rc = parse_asc_classic(r, p, f);
    }
    if (rc != 0) {
        return rc;
    }
    return log_accept_time(r, CANLOG_TB_START, t, &f->time_us);
}

