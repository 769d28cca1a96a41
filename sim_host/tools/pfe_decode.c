/*
 * pfe_decode - a CAN log decoded through the DBC (sim_host/lib/dbc.h): one
 * line, or one CSV row, per frame; J1939 not-available, error and
 * out-of-range values shown as such, never as numbers.
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "firmware/pfe_can.h"
#include "lib/log/log.h"
#include "lib/dbc.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: pfe_decode [--dbc FILE] [--csv] [--message NAME]...\n"
    "                  [--format auto|log|printed|printed-delta|asc] [--skip-errors] [LOG | -]\n"
    "\n"
    "Decodes a CAN log through the DBC: one line, or one CSV row, per frame.\n"
    "\n"
    "LOG: a candump log, candump's printed output or a Vector ASC file, detected\n"
    "from its first lines unless --format says which; default, or \"-\", standard\n"
    "input.\n"
    "\n"
    "Options:\n"
    "  --dbc FILE      the DBC (default can_dbc/pfe.dbc, else the one next to\n"
    "                  this program's build folder)\n"
    "  --csv           CSV instead of text (below)\n"
    "  --message NAME  only this message (repeatable)\n"
    "  --format F      auto (default), log, printed, printed-delta, asc\n"
    "  --skip-errors   skip bad lines and count them (default: stop at the first)\n"
    "  -h, --help      this help\n"
    "\n"
    "Matching: a 29-bit frame matches a 29-bit DBC message of the same J1939 PGN,\n"
    "priority and source address masked, and for a PDU1 PGN (PF < 240) the\n"
    "destination too; an 11-bit frame matches an 11-bit message of the same id.\n"
    "\n"
    "Values: raw * factor + offset, computed exactly from the factor and offset\n"
    "as written in the DBC and printed with as many decimals as they need. Shown\n"
    "instead of a number:\n"
    "  NA     not available (J1939-71: all ones; a 2-bit state 11b; a field of 1,\n"
    "         2 or 4 bytes whose top byte is 0xFF)\n"
    "  ERR    error indicator (2-bit 10b; top byte 0xFE)\n"
    "  OOR    outside the signal's DBC [min|max], or a J1939 parameter-specific or\n"
    "         reserved value (top byte 0xFB to 0xFD); text lines add the raw value:\n"
    "         OOR(raw 64256)\n"
    "  SHORT  the frame is too short to hold the signal\n"
    "J1939 ranges apply to a signal of 2, 8, 16 or 32 bits that is not a\n"
    "multiplexer and whose all-ones raw value lies outside its [min|max]. A\n"
    "signal whose [min|max] is [0|0] has no range.\n"
    "\n"
    "Text output (default), one line per frame:\n"
    "  TIME IFACE ID MESSAGE SIGNAL=VALUE [UNIT] ...\n"
    "  1700000000.100000 vcan0 18FEF100 CCVS1 WheelBasedVehicleSpeed=90 km/h\n"
    "with a value's VAL_ description in parentheses, \"remote request\" for a\n"
    "remote frame, \"ERRORFRAME\" and the data for an error frame, and \"?\" and the\n"
    "data for a frame no message matches. TIME is seconds with 6 decimals in the\n"
    "log's time base. Multiplexed messages show the multiplexer and the signals\n"
    "its value selects.\n"
    "\n"
    "CSV (--csv): a header \"time_s,iface,id,message\" and one column per signal of\n"
    "every message kept, named MESSAGE.SIGNAL[UNIT]; then one row per decoded\n"
    "data frame, with the cells of its message's signals filled (those a\n"
    "multiplexer does not select left empty). Frames no message matches, remote\n"
    "and error frames are not in the CSV.\n"
    "\n"
    "A summary on standard error: frames read, decoded, not matched, parse\n"
    "errors.\n"
    "\n"
    "Exit status: 0; 1 unreadable DBC or log, a DBC without a message (an empty\n"
    "file: nothing to decode with), or a bad line (without --skip-errors:\n"
    "decoding stops there); 3 usage error.\n"
    "\n"
    "Examples:\n"
    "  pfe_decode drive.log                        # time iface id message signal=value unit ...\n"
    "  pfe_decode --csv --message CCVS1 drive.log  # one row per frame, one column per signal\n";

#define EXIT_INPUT 1
#define EXIT_USAGE 3
#define MAX_SELECTED 64U

typedef enum { ST_VALID = 0, ST_NA, ST_ERR, ST_OOR, ST_SHORT } sig_state_t;

/* What decoding one signal needs, computed once from the DBC. */
typedef struct {
    const dbc_signal_t *sig;
    bool exact;          /* factor and offset as exact decimal fractions */
    int64_t fnum, fden;  /* factor = fnum / fden */
    int64_t onum, oden;  /* offset = onum / oden */
    int decimals;        /* of the product den fden * oden (a power of ten) */
    bool j1939;          /* J1939-71 special ranges */
    bool has_range;
    unsigned column;     /* CSV column (0-based among signal columns) */
} sig_info_t;

typedef struct {
    const dbc_message_t *msg;
    bool ext;
    uint32_t raw_id;     /* 11 or 29 bits */
    uint32_t pgn;        /* 29-bit: J1939 PGN */
    bool selected;
    sig_info_t *sigs;
    int mux_index;       /* index of the multiplexer in sigs, or -1 */
} msg_info_t;

typedef struct {
    dbc_t *dbc;
    msg_info_t *msgs;
    size_t n_msgs;
    unsigned n_columns;
    bool csv;
    uint64_t decoded;
    uint64_t unknown;
} decoder_t;

/* ------------------------------------------------------------------ helpers */

static int decimals_of(int64_t den)
{
    int n = 0;
    while (den > 1) {
        den /= 10;
        n++;
    }
    return n;
}

/* Raw bits of SIG from DATA[0 .. len): returns false when the frame is too
 * short. Intel (@1): start is the least significant bit, numbered byte by
 * byte from bit 0 of byte 0. Motorola (@0): start is the most significant
 * bit, and the following bits run down a byte, then on to the next byte's
 * bit 7. */
static bool raw_bits(const dbc_signal_t *sig, const uint8_t *data, unsigned len, uint64_t *raw)
{
    uint64_t v = 0U;
    if (sig->little_endian) {
        for (uint32_t i = sig->length; i > 0U; i--) {
            const uint32_t pos = sig->start_bit + i - 1U;
            if ((pos / 8U) >= len) {
                return false;
            }
            v = (v << 1) | (((uint64_t)data[pos / 8U] >> (pos % 8U)) & 1U);
        }
    } else {
        uint32_t pos = sig->start_bit;
        for (uint32_t i = 0U; i < sig->length; i++) {
            if ((pos / 8U) >= len) {
                return false;
            }
            v = (v << 1) | (((uint64_t)data[pos / 8U] >> (pos % 8U)) & 1U);
            pos = ((pos % 8U) == 0U) ? (pos + 15U) : (pos - 1U);
        }
    }
    *raw = v;
    return true;
}

static int64_t raw_signed(const dbc_signal_t *sig, uint64_t raw)
{
    if (sig->is_signed && (sig->length < 64U) && (((raw >> (sig->length - 1U)) & 1U) != 0U)) {
        return (int64_t)(raw | ~((UINT64_C(1) << sig->length) - 1U));
    }
    return (int64_t)raw;
}

static double phys_double(const sig_info_t *si, uint64_t raw)
{
    const dbc_signal_t *s = si->sig;
    const double r = s->is_signed ? (double)raw_signed(s, raw) : (double)raw;
    return (r * s->factor) + s->offset;
}

static sig_state_t state_of(const sig_info_t *si, uint64_t raw)
{
    const dbc_signal_t *s = si->sig;
    if (si->j1939) {
        if (s->length == 2U) {
            if (raw == 3U) {
                return ST_NA;
            }
            if (raw == 2U) {
                return ST_ERR;
            }
        } else {
            const uint64_t top = raw >> (s->length - 8U);
            if (top == 0xFFU) {
                return ST_NA;
            }
            if (top == 0xFEU) {
                return ST_ERR;
            }
            if (top >= 0xFBU) {
                return ST_OOR;
            }
        }
    }
    if (si->has_range) {
        const double v = phys_double(si, raw);
        const double tol = 1e-9 * ((s->max - s->min) + 1.0);
        if ((v < s->min - tol) || (v > s->max + tol)) {
            return ST_OOR;
        }
    }
    return ST_VALID;
}

/* The physical value of RAW as text: exact when the DBC numbers allow. */
static void format_value(const sig_info_t *si, uint64_t raw, char *buf, size_t size)
{
    const dbc_signal_t *s = si->sig;
    if (!si->exact) {
        (void)snprintf(buf, size, "%.17g", phys_double(si, raw));
        return;
    }
    const __int128 r = s->is_signed ? (__int128)raw_signed(s, raw) : (__int128)raw;
    /* value = (r * fnum * oden + onum * fden) / (fden * oden) */
    __int128 num = (r * si->fnum * si->oden) + ((__int128)si->onum * si->fden);
    const __int128 den = (__int128)si->fden * si->oden;
    const bool neg = num < 0;
    if (neg) {
        num = -num;
    }
    const __int128 ip = num / den;
    __int128 fp = num % den;
    char digits[48];
    int n = 0;
    __int128 x = ip;
    do {
        digits[n++] = (char)('0' + (int)(x % 10));
        x /= 10;
    } while ((x != 0) && (n < 40));
    size_t o = 0U;
    if (neg && (size > 1U)) {
        buf[o++] = '-';
    }
    while ((n > 0) && (o + 1U < size)) {
        buf[o++] = digits[--n];
    }
    int dec = si->decimals;
    if ((fp != 0) && (o + 1U < size)) {
        buf[o++] = '.';
        __int128 scale = den / 10;
        while ((dec > 0) && (fp != 0) && (o + 1U < size)) {
            buf[o++] = (char)('0' + (int)(fp / scale));
            fp %= scale;
            scale /= 10;
            dec--;
        }
    }
    buf[o] = '\0';
}

static const char *value_text(const dbc_signal_t *s, uint64_t raw)
{
    for (size_t i = 0U; i < s->n_values; i++) {
        if ((uint64_t)s->values[i].value == raw) {
            return s->values[i].text;
        }
    }
    return NULL;
}

/* ------------------------------------------------------------------ set-up */

static int prepare(decoder_t *d, char **selected, unsigned n_selected)
{
    d->n_msgs = d->dbc->n_messages;
    d->msgs = calloc((d->n_msgs > 0U) ? d->n_msgs : 1U, sizeof *d->msgs);
    if (d->msgs == NULL) {
        return -1;
    }
    for (unsigned k = 0U; k < n_selected; k++) {
        if (dbc_message_by_name(d->dbc, selected[k]) == NULL) {
            fprintf(stderr, "pfe_decode: --message %s: no such message in the DBC\n", selected[k]);
            return -1;
        }
    }
    unsigned column = 0U;
    for (size_t m = 0U; m < d->n_msgs; m++) {
        msg_info_t *mi = &d->msgs[m];
        const dbc_message_t *msg = &d->dbc->messages[m];
        mi->msg = msg;
        mi->ext = (msg->id & DBC_EXTENDED_ID_FLAG) != 0U;
        mi->raw_id = msg->id & 0x1FFFFFFFU;
        mi->pgn = mi->ext ? pfe_j1939_pgn(mi->raw_id) : 0U;
        mi->selected = n_selected == 0U;
        for (unsigned k = 0U; k < n_selected; k++) {
            mi->selected = mi->selected || (strcmp(selected[k], msg->name) == 0);
        }
        mi->mux_index = -1;
        mi->sigs = calloc((msg->n_signals > 0U) ? msg->n_signals : 1U, sizeof *mi->sigs);
        if (mi->sigs == NULL) {
            return -1;
        }
        for (size_t i = 0U; i < msg->n_signals; i++) {
            const dbc_signal_t *s = &msg->signals[i];
            sig_info_t *si = &mi->sigs[i];
            si->sig = s;
            si->exact = (dbc_decimal_to_rational(s->factor_text, &si->fnum, &si->fden) == 0) &&
                        (dbc_decimal_to_rational(s->offset_text, &si->onum, &si->oden) == 0) &&
                        (si->fden <= 1000000000000LL) && (si->oden <= 1000000000000LL);
            si->decimals = si->exact ? decimals_of(si->fden) + decimals_of(si->oden) : 0;
            si->has_range = !((s->min == 0.0) && (s->max == 0.0));
            if (s->mux_kind == DBC_MUX_MULTIPLEXOR) {
                mi->mux_index = (int)i;
            }
            const bool j_len = (s->length == 2U) || (s->length == 8U) || (s->length == 16U) ||
                               (s->length == 32U);
            if (j_len && (s->mux_kind != DBC_MUX_MULTIPLEXOR) && si->has_range) {
                const uint64_t ones = (UINT64_C(1) << s->length) - 1U;
                const double v = phys_double(si, ones);
                si->j1939 = (v > s->max) || (v < s->min);
            }
            if (mi->selected) {
                si->column = column++;
            }
        }
    }
    d->n_columns = column;
    return 0;
}

static const msg_info_t *find_message(const decoder_t *d, uint32_t id)
{
    const bool ext = (id & CANLOG_EFF_FLAG) != 0U;
    const uint32_t raw = id & (ext ? CANLOG_EFF_MASK : CANLOG_SFF_MASK);
    const uint32_t pgn = ext ? pfe_j1939_pgn(raw) : 0U;
    for (size_t m = 0U; m < d->n_msgs; m++) {
        const msg_info_t *mi = &d->msgs[m];
        if (mi->ext != ext) {
            continue;
        }
        if (ext ? (mi->pgn == pgn) : (mi->raw_id == raw)) {
            return mi;
        }
    }
    return NULL;
}

/* ------------------------------------------------------------------ output */

static void print_time(const canlog_frame_t *f)
{
    printf("%llu.%06llu", (unsigned long long)(f->time_us / 1000000U),
           (unsigned long long)(f->time_us % 1000000U));
}

static void print_id(const canlog_frame_t *f)
{
    if ((f->id & (CANLOG_EFF_FLAG | CANLOG_ERR_FLAG)) != 0U) {
        printf("%08lX", (unsigned long)(f->id & (CANLOG_EFF_MASK | CANLOG_ERR_FLAG)));
    } else {
        printf("%03lX", (unsigned long)(f->id & CANLOG_SFF_MASK));
    }
}

static void print_data(const canlog_frame_t *f)
{
    printf("data=");
    for (unsigned i = 0U; i < f->len; i++) {
        printf("%02X", f->data[i]);
    }
}

/* Whether signal I of MI is in frame F (multiplexing), given the
 * multiplexer's raw value. */
static bool sig_present(const msg_info_t *mi, size_t i, bool mux_ok, uint64_t mux_raw)
{
    const dbc_signal_t *s = mi->sigs[i].sig;
    if (s->mux_kind != DBC_MUX_MULTIPLEXED) {
        return true;
    }
    return mux_ok && (mux_raw == s->mux_value);
}

static void decode_text(decoder_t *d, const msg_info_t *mi, const canlog_frame_t *f)
{
    print_time(f);
    printf(" %s ", f->iface);
    print_id(f);
    printf(" %s", mi->msg->name);
    if ((f->id & CANLOG_RTR_FLAG) != 0U) {
        printf(" remote request\n");
        return;
    }
    uint64_t mux_raw = 0U;
    bool mux_ok = false;
    if (mi->mux_index >= 0) {
        mux_ok = raw_bits(mi->sigs[mi->mux_index].sig, f->data, f->len, &mux_raw);
    }
    for (size_t i = 0U; i < mi->msg->n_signals; i++) {
        if (!sig_present(mi, i, mux_ok, mux_raw)) {
            continue;
        }
        const sig_info_t *si = &mi->sigs[i];
        const dbc_signal_t *s = si->sig;
        uint64_t raw = 0U;
        printf(" %s=", s->name);
        if (!raw_bits(s, f->data, f->len, &raw)) {
            printf("SHORT");
            continue;
        }
        const sig_state_t st = state_of(si, raw);
        if (st == ST_NA) {
            printf("NA");
        } else if (st == ST_ERR) {
            printf("ERR");
        } else if (st == ST_OOR) {
            printf("OOR(raw %llu)", (unsigned long long)raw);
        } else {
            char v[64];
            format_value(si, raw, v, sizeof v);
            printf("%s", v);
            if ((s->unit != NULL) && (s->unit[0] != '\0')) {
                printf(" %s", s->unit);
            }
            const char *desc = value_text(s, raw);
            if (desc != NULL) {
                printf(" (%s)", desc);
            }
        }
    }
    putchar('\n');
    d->decoded++;
}

static void csv_header(const decoder_t *d)
{
    printf("time_s,iface,id,message");
    for (size_t m = 0U; m < d->n_msgs; m++) {
        const msg_info_t *mi = &d->msgs[m];
        if (!mi->selected) {
            continue;
        }
        for (size_t i = 0U; i < mi->msg->n_signals; i++) {
            const dbc_signal_t *s = mi->sigs[i].sig;
            printf(",%s.%s", mi->msg->name, s->name);
            if ((s->unit != NULL) && (s->unit[0] != '\0')) {
                printf("[%s]", s->unit);
            }
        }
    }
    putchar('\n');
}

static void decode_csv(decoder_t *d, const msg_info_t *mi, const canlog_frame_t *f, char **cells,
                       size_t cell_size)
{
    if ((f->id & CANLOG_RTR_FLAG) != 0U) {
        return;
    }
    for (unsigned c = 0U; c < d->n_columns; c++) {
        cells[c][0] = '\0';
    }
    uint64_t mux_raw = 0U;
    bool mux_ok = false;
    if (mi->mux_index >= 0) {
        mux_ok = raw_bits(mi->sigs[mi->mux_index].sig, f->data, f->len, &mux_raw);
    }
    for (size_t i = 0U; i < mi->msg->n_signals; i++) {
        if (!sig_present(mi, i, mux_ok, mux_raw)) {
            continue;
        }
        const sig_info_t *si = &mi->sigs[i];
        char *cell = cells[si->column];
        uint64_t raw = 0U;
        if (!raw_bits(si->sig, f->data, f->len, &raw)) {
            (void)snprintf(cell, cell_size, "SHORT");
            continue;
        }
        const sig_state_t st = state_of(si, raw);
        if (st == ST_NA) {
            (void)snprintf(cell, cell_size, "NA");
        } else if (st == ST_ERR) {
            (void)snprintf(cell, cell_size, "ERR");
        } else if (st == ST_OOR) {
            (void)snprintf(cell, cell_size, "OOR");
        } else {
            format_value(si, raw, cell, cell_size);
        }
    }
    print_time(f);
    printf(",%s,", f->iface);
    print_id(f);
    printf(",%s", mi->msg->name);
    for (unsigned c = 0U; c < d->n_columns; c++) {
        printf(",%s", cells[c]);
    }
    putchar('\n');
    d->decoded++;
}

/* ------------------------------------------------------------------ main */

static void usage(FILE *f)
{
    /* --help: the whole manual; a usage error: its synopsis. */
    if (f == stdout) {
        cli_help(k_manual);
    } else {
        cli_usage(f, k_manual, "pfe_decode");
    }
}

/* can_dbc/pfe.dbc here, else next to the build folder of this program
 * (build/host/pfe_decode -> ../../can_dbc/pfe.dbc). */
static const char *default_dbc(char *buf, size_t size)
{
    if (access("can_dbc/pfe.dbc", R_OK) == 0) {
        return "can_dbc/pfe.dbc";
    }
    char exe[PATH_MAX];
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1U);
    if (n > 0) {
        exe[n] = '\0';
        char *slash = strrchr(exe, '/');
        if (slash != NULL) {
            *slash = '\0';
            (void)snprintf(buf, size, "%s/../../can_dbc/pfe.dbc", exe);
            if (access(buf, R_OK) == 0) {
                return buf;
            }
        }
    }
    return "can_dbc/pfe.dbc";
}

typedef struct {
    const char *dbc_path;   /* NULL: default_dbc() */
    const char *log_path;   /* NULL or "-": standard input */
    bool csv;
    bool skip;              /* --skip-errors */
    canlog_format_t format;
    char *selected[MAX_SELECTED];
    unsigned n_selected;
} options_t;

/* The command line into *o. Returns -1 to go on, else the exit status
 * (0 after --help, EXIT_USAGE with the reason printed). */
static int parse_args(int argc, char **argv, options_t *o)
{
    memset(o, 0, sizeof *o);
    o->format = CANLOG_FMT_AUTO;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
        if ((strcmp(a, "-h") == 0) || (strcmp(a, "--help") == 0)) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--csv") == 0) {
            o->csv = true;
        } else if (strcmp(a, "--skip-errors") == 0) {
            o->skip = true;
        } else if ((a[0] != '-') || (strcmp(a, "-") == 0)) {
            if (o->log_path != NULL) {
                fprintf(stderr, "pfe_decode: one log at a time\n");
                usage(stderr);
                return EXIT_USAGE;
            }
            o->log_path = a;
        } else if (v == NULL) {
            fprintf(stderr, "pfe_decode: %s needs a value\n", a);
            usage(stderr);
            return EXIT_USAGE;
        } else if (strcmp(a, "--dbc") == 0) {
            o->dbc_path = v;
            i++;
        } else if (strcmp(a, "--message") == 0) {
            if (o->n_selected == MAX_SELECTED) {
                fprintf(stderr, "pfe_decode: more than %u --message\n", MAX_SELECTED);
                return EXIT_USAGE;
            }
            o->selected[o->n_selected++] = argv[i + 1];
            i++;
        } else if (strcmp(a, "--format") == 0) {
            if (canlog_format_parse(v, &o->format) != 0) {
                fprintf(stderr, "pfe_decode: --format %s: auto, log, printed, printed-delta or asc\n", v);
                return EXIT_USAGE;
            }
            i++;
        } else {
            fprintf(stderr, "pfe_decode: unknown option %s\n", a);
            usage(stderr);
            return EXIT_USAGE;
        }
    }
    return -1;
}

/* The DBC at path into d->dbc: 0, or EXIT_INPUT with the reason printed
 * (a DBC without a message decodes nothing, and is refused). */
static int load_dbc(decoder_t *d, const char *path)
{
    dbc_error_t err;
    if (dbc_parse_file(path, &d->dbc, &err) != 0) {
        if (err.line > 0) {
            fprintf(stderr, "pfe_decode: %s:%d: %s\n", path, err.line, err.message);
        } else {
            fprintf(stderr, "pfe_decode: %s: %s\n", path, err.message);
        }
        return EXIT_INPUT;
    }
    if (d->dbc->n_messages == 0U) {
        /* an empty or comment-only file parses, but decodes nothing */
        fprintf(stderr, "pfe_decode: %s: no message (BO_) in the DBC: nothing to decode with\n", path);
        dbc_free(d->dbc);
        return EXIT_INPUT;
    }
    return 0;
}

static void free_decoder(decoder_t *d)
{
    if (d->msgs != NULL) {
        for (size_t m = 0U; m < d->n_msgs; m++) {
            free(d->msgs[m].sigs);
        }
        free(d->msgs);
    }
    dbc_free(d->dbc);
}

/* The CSV's cells: n columns of size bytes each, or NULL (nothing left
 * allocated) when memory runs out. */
static char **alloc_cells(unsigned n, size_t size)
{
    char **cells = calloc((n > 0U) ? n : 1U, sizeof *cells);
    if (cells == NULL) {
        return NULL;
    }
    for (unsigned c = 0U; c < n; c++) {
        cells[c] = calloc(size, 1U);
        if (cells[c] == NULL) {
            for (unsigned k = 0U; k < c; k++) {
                free(cells[k]);
            }
            free(cells);
            return NULL;
        }
    }
    return cells;
}

static void free_cells(char **cells, unsigned n)
{
    if (cells != NULL) {
        for (unsigned c = 0U; c < n; c++) {
            free(cells[c]);
        }
        free(cells);
    }
}

/* A frame of no message of the DBC (or an error frame), in the text output. */
static void print_unknown(const canlog_frame_t *f, bool error_frame)
{
    print_time(f);
    printf(" %s ", f->iface);
    print_id(f);
    printf(error_frame ? " ERRORFRAME " : " ? ");
    if ((f->id & CANLOG_RTR_FLAG) != 0U) {
        printf("remote request\n");
    } else {
        print_data(f);
        putchar('\n');
    }
}

/* Every frame of the log decoded and printed, as text or CSV (cells given).
 * Returns 0, or EXIT_INPUT at a line that stops the reader. */
static int decode_log(decoder_t *d, canlog_reader_t *reader, const options_t *o, char **cells,
                      size_t cell_size)
{
    canlog_frame_t f;
    for (;;) {
        const int rc = canlog_next(reader, &f);
        if (rc == 0) {
            return 0;
        }
        if (rc < 0) {
            fprintf(stderr, "pfe_decode: %s\n", canlog_message(reader));
            return EXIT_INPUT;
        }
        const bool error_frame = (f.id & CANLOG_ERR_FLAG) != 0U;
        const msg_info_t *mi = error_frame ? NULL : find_message(d, f.id);
        if ((mi != NULL) && !mi->selected) {
            continue;
        }
        if (mi == NULL) {
            d->unknown++;
            if (!o->csv && (o->n_selected == 0U)) {
                print_unknown(&f, error_frame);
            }
        } else if (o->csv) {
            decode_csv(d, mi, &f, cells, cell_size);
        } else {
            decode_text(d, mi, &f);
        }
    }
}

/* The counts on stderr; with --skip-errors, the first line of each kind of error. */
static void print_summary(const decoder_t *d, const canlog_reader_t *reader, bool skip)
{
    fprintf(stderr, "pfe_decode: %llu frames, %llu decoded, %llu not in the DBC, %llu parse errors\n",
            (unsigned long long)reader->frames, (unsigned long long)d->decoded,
            (unsigned long long)d->unknown, (unsigned long long)reader->error_lines);
    for (int i = 1; i < (int)CANLOG_REASON_COUNT; i++) {
        if ((reader->errors[i] > 0U) && skip) {
            fprintf(stderr, "pfe_decode:   %llu x %s, the first: %s\n",
                    (unsigned long long)reader->errors[i], canlog_reason_text(i),
                    reader->first_msg[i]);
        }
    }
}

/* The log of o decoded through d's DBC: the exit status. */
static int run(decoder_t *d, options_t *o)
{
    if (prepare(d, o->selected, o->n_selected) != 0) {
        return EXIT_INPUT;
    }
    int fd = STDIN_FILENO;
    const char *name = "<stdin>";
    if ((o->log_path != NULL) && (strcmp(o->log_path, "-") != 0)) {
        fd = open(o->log_path, O_RDONLY | O_CLOEXEC);
        if (fd < 0) {
            fprintf(stderr, "pfe_decode: cannot open %s: %s\n", o->log_path, strerror(errno));
            return EXIT_INPUT;
        }
        name = o->log_path;
    }
    static canlog_reader_t reader;
    (void)canlog_open_fd(&reader, fd, name, o->format, o->skip ? CANLOG_ON_ERROR_SKIP : CANLOG_ON_ERROR_STOP);
    const size_t cell_size = 64U;
    char **cells = NULL;
    int status = 0;
    if (o->csv) {
        cells = alloc_cells(d->n_columns, cell_size);
        if (cells == NULL) {
            status = EXIT_INPUT;
        } else {
            csv_header(d);
        }
    }
    if (status == 0) {
        status = decode_log(d, &reader, o, cells, cell_size);
        if (fflush(stdout) != 0) {
            fprintf(stderr, "pfe_decode: writing the output failed\n");
            status = EXIT_INPUT;
        }
        print_summary(d, &reader, o->skip);
    }
    free_cells(cells, d->n_columns);
    if (fd != STDIN_FILENO) {
        (void)close(fd);
    }
    return status;
}

int main(int argc, char **argv)
{
    static options_t o;
    const int rc = parse_args(argc, argv, &o);
    if (rc >= 0) {
        return rc;
    }
    char dbc_buf[PATH_MAX + 32];
    const char *dbc_path = (o.dbc_path != NULL) ? o.dbc_path : default_dbc(dbc_buf, sizeof dbc_buf);
    decoder_t d;
    memset(&d, 0, sizeof d);
    d.csv = o.csv;
    if (load_dbc(&d, dbc_path) != 0) {
        return EXIT_INPUT;
    }
    const int status = run(&d, &o);
    free_decoder(&d);
    return status;
}
