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

/* Parses one line (NUL-terminated, no newline). LINE_FRAME fills *f, *t_us
 * and, for the first frame, the record interface name. */
static line_kind_t parse_line(hal_replay_bus_t *bus, const char *s, pfe_can_frame_t *f,
                              uint64_t *t_us, hal_replay_reason_t *why)
{
    size_t n = strlen(s);
    if ((n > 0U) && (s[n - 1U] == '\r')) {
        n--;
    }
    if (n == 0U) {
        return LINE_EMPTY;
    }
    size_t i = 0U;
    *why = HAL_REPLAY_BAD_SYNTAX;
    if (s[i] != '(') {
        return LINE_BAD;
    }
    i++;
    *why = HAL_REPLAY_BAD_TIME;
    uint64_t sec = 0U;
    uint32_t digits = 0U;
    while ((i < n) && is_digit(s[i])) {
        if (digits == MAX_SECONDS_DIGITS) {
            return LINE_BAD;
        }
        sec = (sec * 10U) + (uint64_t)(s[i] - '0');
        digits++;
        i++;
    }
    if ((digits == 0U) || (i >= n) || (s[i] != '.')) {
        return LINE_BAD;
    }
    i++;
    uint32_t frac = 0U;
    digits = 0U;
    while ((i < n) && is_digit(s[i]) && (digits < 9U)) {
        frac = (frac * 10U) + (uint32_t)(s[i] - '0');
        digits++;
        i++;
    }
    if (((digits != 6U) && (digits != 9U)) || (i >= n) || (s[i] != ')')) {
        return LINE_BAD;
    }
    const uint32_t usec = (digits == 9U) ? (frac / 1000U) : frac;
    i++;
    *why = HAL_REPLAY_BAD_SYNTAX;
    if ((i >= n) || (s[i] != ' ')) {
        return LINE_BAD;
    }
    i++;
    const size_t if_start = i;
    while ((i < n) && (s[i] != ' ') && ((unsigned char)s[i] > 0x20U) && ((unsigned char)s[i] < 0x7FU)) {
        i++;
    }
    const size_t if_len = i - if_start;
    if ((if_len == 0U) || (if_len > HAL_REPLAY_IFNAME_MAX) || (i >= n) || (s[i] != ' ')) {
        return LINE_BAD;
    }
    i++;
    *why = HAL_REPLAY_BAD_ID;
    uint32_t id = 0U;
    const size_t id_start = i;
    while ((i < n) && (s[i] != '#')) {
        const int h = hex_digit(s[i]);
        if ((h < 0) || ((i - id_start) >= 8U)) {
            return LINE_BAD;
        }
        id = (id << 4) | (uint32_t)h;
        i++;
    }
    const size_t id_len = i - id_start;
    if (i >= n) {
        *why = (id_len == 0U) ? HAL_REPLAY_BAD_SYNTAX : HAL_REPLAY_BAD_ID;
        return LINE_BAD;
    }
    if ((id_len != 3U) && (id_len != 8U)) {
        return LINE_BAD;
    }
    i++; /* '#' */
    if ((id_len == 8U) && ((id & CAN_ERR_FLAG_ID) != 0U) && ((id & 0xC0000000UL) == 0U)) {
        return LINE_NOT_CLASSIC; /* error frame */
    }
    if (((id_len == 3U) && (id > 0x7FFU)) || ((id_len == 8U) && (id > PFE_CAN_ID_MASK))) {
        return LINE_BAD;
    }
    if ((i < n) && ((s[i] == '#') || (s[i] == 'R') || (s[i] == 'r'))) {
        return LINE_NOT_CLASSIC; /* CAN FD or remote */
    }
    *why = HAL_REPLAY_BAD_DATA;
    uint32_t len = 0U;
    while ((i < n) && (s[i] != ' ')) {
        if ((i + 1U) >= n) {
            return LINE_BAD; /* odd number of digits */
        }
        const int hi = hex_digit(s[i]);
        const int lo = hex_digit(s[i + 1U]);
        if ((hi < 0) || (lo < 0)) {
            return LINE_BAD;
        }
        if (len == PFE_CAN_MAX_DLC) {
            *why = HAL_REPLAY_BAD_LENGTH;
            return LINE_BAD;
        }
        f->data[len] = (uint8_t)(((uint32_t)hi << 4) | (uint32_t)lo);
        len++;
        i += 2U;
    }
    /* candump may end a line with its direction flag: " R" or " T". */
    if ((i < n) && !(((n - i) == 2U) && ((s[i + 1U] == 'R') || (s[i + 1U] == 'T')))) {
        return LINE_BAD;
    }
    f->id = (id_len == 8U) ? (id | PFE_CAN_EFF_FLAG) : id;
    f->dlc = (uint8_t)len;
    for (uint32_t k = len; k < PFE_CAN_MAX_DLC; k++) {
        f->data[k] = 0U;
    }
    *t_us = (sec * 1000000U) + usec;
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

/* Reads ahead to the next log frame. */
static void load_next(hal_replay_bus_t *bus)
{
    bus->have_next = false;
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
        if (bus->any_log_frame && (t_us < bus->last_log_us)) {
            bus->stats.time_backwards++;
            t_us = bus->last_log_us;
        }
        bus->any_log_frame = true;
        bus->last_log_us = t_us;
        bus->next.timestamp_us = t_us;
        bus->have_next = true;
        return;
    }
}

/* ------------------------------------------------------------------ public */

void hal_replay_init(hal_replay_bus_t *bus, hal_replay_read_fn read, void *read_ctx,
                     hal_replay_write_fn write, void *write_ctx, const char *record_ifname)
{
    (void)memset(bus, 0, sizeof *bus);
    bus->time.bus = bus;
    bus->read = read;
    bus->read_ctx = read_ctx;
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
        return "not a candump log line: (seconds.fraction) interface id#data";
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

int hal_can_receive(hal_can_t *can, hal_can_rx_t *out)
{
    if ((can == NULL) || !can->open || (out == NULL)) {
        return HAL_EINVAL;
    }
    return hal_can_mem_port_receive(&can->port, out);
}

int hal_can_add_filter(hal_can_t *can, uint32_t id, uint32_t mask)
{
    if ((can == NULL) || !can->open) {
        return HAL_EINVAL;
    }
    return hal_can_mem_port_add_filter(&can->port, id, mask);
}

int hal_can_remove_filter(hal_can_t *can, int index)
{
    if (can == NULL) {
        return HAL_EINVAL;
    }
    return hal_can_mem_port_remove_filter(&can->port, index);
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
