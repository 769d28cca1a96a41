/*
 * Tests of the capture reader (sim_host/lib/capture.h), the reference fed a
 * capture's inputs (sim_host/ref/bus_ref.h) and the drive noise generator
 * (sim_host/ref/drive_trace.h).
 *
 *     test_capture
 *
 * Input files are written to a fresh directory from mkdtemp() under $TMPDIR
 * (default /tmp), removed at the end. Expected values are hand-computed
 * literals (the SplitMix64 outputs from its published definition, the fuel
 * rate from the default truck, docs/model.md).
 */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "../test_assert.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "firmware/pfe_codec.h"
#include "ref/bus_ref.h"
#include "lib/capture.h"
#include "ref/drive_trace.h"

#define PATH_LEN 4096
#define DIR_LEN 1024
#define ERR_LEN 512

static char g_dir[DIR_LEN];
static char g_path[PATH_LEN];

/* ---- helpers ------------------------------------------------------------ */

/* Writes n bytes to the test directory's file `name`; returns its path. */
static const char *write_file(const char *name, const char *bytes, size_t n)
{
    ASSERT_LT(strlen(name), 64U);
    snprintf(g_path, sizeof g_path, "%s/%.63s", g_dir, name);
    FILE *f = fopen(g_path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(bytes, 1U, n, f), n);
    assert_int_equal(fclose(f), 0);
    return g_path;
}

static const char *write_text(const char *name, const char *text)
{
    return write_file(name, text, strlen(text));
}

/* Parses a line expected to be a frame. */
static capture_line_t parse_ok(const char *line)
{
    capture_line_t l;
    memset(&l, 0xA5, sizeof l);
    unsigned long drops = 0xA5A5U;
    char why[ERR_LEN] = "";
    const int rc = capture_parse_line(line, &l, &drops, why, sizeof why);
    if (rc != CAPTURE_LINE_FRAME) {
        fail_msg("'%s': %d %s", line, rc, why);
    }
    return l;
}

/* Parses a line expected to be rejected with exactly `reason`. */
static void parse_bad(const char *line, const char *reason)
{
    capture_line_t l;
    unsigned long drops = 0U;
    char why[ERR_LEN] = "";
    assert_int_equal(capture_parse_line(line, &l, &drops, why, sizeof why), -1);
    assert_string_equal(why, reason);
}

/* Loads a file expected to be rejected with exactly "PATH<suffix>". */
static void load_bad(const char *path, const char *suffix)
{
    capture_t cap;
    memset(&cap, 0xA5, sizeof cap);
    char err[ERR_LEN] = "";
    char want[PATH_LEN + ERR_LEN];
    snprintf(want, sizeof want, "%s%s", path, suffix);
    assert_int_equal(capture_load(path, &cap, err, sizeof err), -1);
    assert_string_equal(err, want);
    assert_null(cap.recs);
    assert_int_equal(cap.n, 0);
}

/* ---- the line format ---------------------------------------------------- */

static void test_classic_frames(void **state)
{
    (void)state;
    capture_line_t l = parse_ok("(1700000000.010000) vcan0 18FEF100#FF005AFFFFFFFFFF");
    assert_int_equal(l.t_us, 1700000000010000ULL);
    assert_string_equal(l.iface, "vcan0");
    assert_int_equal(l.kind, CAPTURE_CLASSIC);
    assert_true(l.extended);
    assert_int_equal(l.id, 0x18FEF100U);
    assert_int_equal(l.len, 8);
    assert_int_equal(l.len8_dlc, 0);
    assert_int_equal(l.data[0], 0xFF);
    assert_int_equal(l.data[2], 0x5A);
    assert_int_equal(l.data[7], 0xFF);

    l = parse_ok("(0000000001.000002)   can0 7FF#");
    assert_int_equal(l.t_us, 1000002U);
    assert_string_equal(l.iface, "can0");
    assert_false(l.extended);
    assert_int_equal(l.id, 0x7FFU);
    assert_int_equal(l.len, 0);

    /* Lower case, '.' separators, CRLF, candump -x's trailing R. */
    l = parse_ok("(1.123456) vcan1 123#de.ad.BE.ef R\r");
    assert_int_equal(l.t_us, 1123456U);
    assert_int_equal(l.len, 4);
    assert_int_equal(l.data[0], 0xDE);
    assert_int_equal(l.data[3], 0xEF);

    /* Nanoseconds are truncated to microseconds. */
    l = parse_ok("(1700000000.123456789) vcan0 00000001#01");
    assert_int_equal(l.t_us, 1700000000123456ULL);
    assert_true(l.extended);
    assert_int_equal(l.id, 1U);

    /* A raw DLC after 8 bytes. */
    l = parse_ok("(1.000000) vcan0 123#0011223344556677_C");
    assert_int_equal(l.len, 8);
    assert_int_equal(l.len8_dlc, 12);
}

static void test_remote_fd_error_frames(void **state)
{
    (void)state;
    capture_line_t l = parse_ok("(1.000000) vcan0 123#R");
    assert_int_equal(l.kind, CAPTURE_REMOTE);
    assert_int_equal(l.len, 0);
    l = parse_ok("(1.000000) vcan0 1ABCDEF0#R8");
    assert_int_equal(l.kind, CAPTURE_REMOTE);
    assert_true(l.extended);
    assert_int_equal(l.len, 8);

    l = parse_ok("(1.000000) vcan0 321##1");
    assert_int_equal(l.kind, CAPTURE_FD);
    assert_int_equal(l.fd_flags, 1);
    assert_int_equal(l.len, 0);
    l = parse_ok("(1.000000) vcan0 321##4112233445566778899AABBCC");
    assert_int_equal(l.fd_flags, 4);
    assert_int_equal(l.len, 12);
    assert_int_equal(l.data[11], 0xCC);
    char line[256] = "(1.000000) vcan0 12345678##0";
    for (int k = 0; k < 64; k++) {
        strcat(line, "5A");
    }
    l = parse_ok(line);
    assert_int_equal(l.len, 64);
    assert_int_equal(l.data[63], 0x5A);

    l = parse_ok("(1.000000) vcan0 20000004#0004000000000000");
    assert_int_equal(l.kind, CAPTURE_ERROR);
    assert_int_equal(l.id, 4U);
    assert_int_equal(l.len, 8);
}

static void test_lines_skipped(void **state)
{
    (void)state;
    capture_line_t l;
    unsigned long drops = 0U;
    char why[ERR_LEN];
    assert_int_equal(capture_parse_line("", &l, &drops, why, sizeof why), CAPTURE_LINE_SKIP);
    assert_int_equal(capture_parse_line("  \r", &l, &drops, why, sizeof why), CAPTURE_LINE_SKIP);
    assert_int_equal(capture_parse_line("# a comment", &l, &drops, why, sizeof why),
                     CAPTURE_LINE_SKIP);
    assert_int_equal(capture_parse_line("DROPCOUNT: dropped 3 CAN frames on 'vcan0' socket "
                                        "(total drops 7)", &l, &drops, why, sizeof why),
                     CAPTURE_LINE_DROPS);
    assert_int_equal(drops, 3);
}

static void test_bad_lines(void **state)
{
    (void)state;
    /* canlog's reasons (sim_host/lib/log/log.h), the line's file and number cut */
    parse_bad("(1700000000.000000) vcan0", "truncated line: no frame after the interface");
    parse_bad("(1700000000.000000)", "truncated line: no interface and frame after the timestamp");
    parse_bad("(1700000000.00000", "truncated line: line ends in the timestamp");
    parse_bad("(1700000000.0000000) vcan0 123#", "bad timestamp: 7 fraction digits; 6 or 9 expected");
    parse_bad("(1700000000.000000 vcan0 123#", "bad timestamp: ' ' where ')' should close the timestamp");
    parse_bad("1700000000.000000 vcan0 123#", "syntax error: '1': a candump log line starts with '('");
    parse_bad("(1234567890123.000000) vcan0 123#", "bad timestamp: expected (SECONDS.FRACTION)");
    parse_bad("(1.000000) vcan0 123#GG", "bad hex: 'G' in the data");
    parse_bad("(1.000000) vcan0 123#0G", "bad hex: 'G' in the data");
    parse_bad("(1.000000) vcan0 123#ABC", "truncated line: half a byte at the end of the data");
    parse_bad("(1.000000) vcan0 123#001122334455667788", "bad length: 9 data bytes, over 8 for classic CAN");
    parse_bad("(1.000000) vcan0 1234#00", "bad id: id of 4 hex digits; 3 (11-bit) or 8 (29-bit) expected");
    parse_bad("(1.000000) vcan0 800#00", "bad id: 11-bit id 800 over 7FF");
    parse_bad("(1.000000) vcan0 40000000#00", "bad id: 29-bit id 40000000 over 1FFFFFFF");
    parse_bad("(1.000000) vcan0 123-00", "bad hex: '-' in the id");
    parse_bad("(1.000000) vcan0 123#R9", "bad length: remote frame length 9 over 8");
    parse_bad("(1.000000) vcan0 123##", "truncated line: no FD flags digit after '##'");
    parse_bad("(1.000000) vcan0 123#0011_9",
              "bad length: a raw DLC after '_' needs 8 data bytes and a DLC of 9 to F");
    parse_bad("(1.000000) vcan0 123#00 extra", "syntax error: 'e' after the frame");
    parse_bad("(1.000000) averyveryverylongname 123#00",
              "syntax error: interface name of 21 characters, over 15");
    char line[256] = "(1.000000) vcan0 123##0";
    for (int k = 0; k < 65; k++) {
        strcat(line, "00");
    }
    parse_bad(line, "bad length: 65 data bytes, over 64 for CAN FD");
}

/* ---- files -------------------------------------------------------------- */

static void test_load_counts_and_skips(void **state)
{
    (void)state;
    const char *p = write_text("good.log",
                               "# recorded on a bench\n"
                               "(1700000000.000000) vcan0 18FEF100#FF005AFFFFFFFFFF\n"
                               "(1700000000.000000) vcan0 0CF01300#007D007DFFFFFCFF\n"
                               "\n"
                               "(1700000000.001000) vcan0 123#00\n"
                               "(1700000000.002000) vcan0 123#R\n"
                               "(1700000000.003000) vcan0 123##100\n"
                               "DROPCOUNT: dropped 2 CAN frames on 'vcan0' socket (total drops 2)\n"
                               "(1700000000.004000) vcan0 20000004#0004000000000000\n"
                               "(1700000000.010000) vcan0 18FEF28C#4C02FFFFFFFFFFFF\r\n");
    capture_t cap;
    memset(&cap, 0xA5, sizeof cap);
    char err[ERR_LEN] = "";
    assert_int_equal(capture_load(p, &cap, err, sizeof err), 0);
    assert_int_equal(cap.n, 3);
    assert_int_equal(cap.lines, 10);
    assert_int_equal(cap.skipped_standard, 1);
    assert_int_equal(cap.skipped_remote, 1);
    assert_int_equal(cap.skipped_fd, 1);
    assert_int_equal(cap.skipped_error, 1);
    assert_int_equal(cap.dropped, 2);
    assert_int_equal(cap.recs[0].line, 2);
    assert_int_equal(cap.recs[0].f.id, 0x98FEF100U);
    assert_int_equal(cap.recs[1].f.dlc, 8);
    assert_int_equal(cap.recs[2].t_us, 1700000000010000ULL);
    assert_int_equal(cap.recs[2].line, 10);
    assert_int_equal(cap.recs[2].f.data[0], 0x4C);
    capture_free(&cap);
    assert_null(cap.recs);
    capture_free(&cap);
    capture_free(NULL);
}

static void test_load_errors(void **state)
{
    (void)state;
    load_bad(write_text("back.log", "(1700000000.010000) vcan0 123#00\n"
                                    "(1700000000.009999) vcan0 123#00\n"),
             ":2: timestamp going backwards: 1700000000.009999 s is before the previous frame's "
             "1700000000.010000 s");
    load_bad(write_text("empty.log", ""), ": empty file: no CAN frames (0 lines)");
    load_bad(write_text("comments.log", "# nothing\n\n"), ": empty file: no CAN frames (2 lines)");
    load_bad(write_file("binary.log", "(1.000000) vcan0 123#00\n\x7F" "ELF\0\x01\x02", 32U),
             ":2: binary content: control characters or NUL bytes in the line");
    load_bad(write_text("ctrl.log", "(1.000000) vcan0 123#00\x1B[0m\n"),
             ":1: binary content: control characters or NUL bytes in the line");
    load_bad(write_text("hex.log", "(1.000000) vcan0 123#00\n(1.000001) vcan0 123#0Z\n"),
             ":2: bad hex: 'Z' in the data");
    load_bad(write_text("trunc.log", "(1.000000) vcan0 123#00\n(1.000001) vca"),
             ":2: truncated line: no frame after the interface");
    load_bad(write_text("dlc.log", "(1.000000) vcan0 123#000000000000000000\n"),
             ":1: bad length: 9 data bytes, over 8 for classic CAN");
    /* candump's printed output without -t: no time to judge by */
    load_bad(write_text("notime.txt", "  can0  18FEF100   [8]  FF 12 34 56 78 9A BC DE\n"),
             ":1: no timestamp: candump output without -t cannot be judged in time (record with "
             "candump -L, or -t a, z or A)");
    static char big[CAPTURE_MAX_LINE + 8U];
    memset(big, 'A', sizeof big);
    big[sizeof big - 1U] = '\n';
    load_bad(write_file("long.log", big, sizeof big), ":1: line too long: 4102 characters, more than 4095");
    capture_t cap;
    char err[ERR_LEN] = "";
    snprintf(g_path, sizeof g_path, "%s/missing.log", g_dir);
    assert_int_equal(capture_load(g_path, &cap, err, sizeof err), -1);
    assert_non_null(strstr(err, "missing.log: No such file or directory"));
    assert_int_equal(capture_load(g_dir, &cap, err, sizeof err), -1);
    char want[PATH_LEN + 64];
    snprintf(want, sizeof want, "%s: is a directory, not a CAN log", g_dir);
    assert_string_equal(err, want);
}

/* Benches record with candump's printed form, start mid-drive with no
 * address claims, carry PGNs nobody here reads and several senders: all
 * J1939 records, times since the first frame (-t z), drops counted. */
static void test_load_printed_form(void **state)
{
    (void)state;
    const char *p = write_text("bench.txt",
                               "(000.000000)  can0  18FEF100   [8]  FF 00 5A FF FF FF FF FF\n"
                               "(000.001200)  can0  18FEF131   [8]  FF FF FF FF FF FF FF FF\n"
                               "(000.002500)  can0  0CF00400   [8]  F0 FF 7D 20 1A FF FF FF\n"
                               "(000.003000)  can0  18FECA00   [8]  00 FF 00 00 00 00 FF FF\n"
                               "(000.004000)  can0  123   [2]  0A 0B\n"
                               "(000.005000)  can0  18EAFF31   [3]  E8 FE 00   '...'\n"
                               "DROPCOUNT: dropped 4 CAN frames on 'can0' socket (total drops 4)\n"
                               "(000.100000)  can0  18FEF100   [8]  FF 80 5A FF FF FF FF FF\n");
    capture_t cap;
    memset(&cap, 0xA5, sizeof cap);
    char err[ERR_LEN] = "";
    if (capture_load(p, &cap, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    assert_int_equal(cap.n, 6);
    assert_int_equal(cap.lines, 8);
    assert_int_equal(cap.skipped_standard, 1);
    assert_int_equal(cap.dropped, 4);
    assert_int_equal(cap.recs[0].t_us, 0U);
    assert_int_equal(cap.recs[1].f.id, 0x98FEF131U);
    assert_int_equal(cap.recs[2].t_us, 2500U);
    assert_int_equal(cap.recs[4].f.dlc, 3);
    assert_int_equal(cap.recs[4].f.data[1], 0xFE);
    assert_int_equal(cap.recs[4].f.data[3], 0x00); /* unused bytes are zero */
    assert_int_equal(cap.recs[5].t_us, 100000U);
    assert_int_equal(cap.recs[5].line, 8);
    assert_int_equal(cap.recs[5].f.data[1], 0x80);
    capture_free(&cap);
}

/* ---- the reference on a capture's inputs --------------------------------- */

static void frame_ccvs1(pfe_can_frame_t *f, int32_t speed_mm_s)
{
    const pfe_msg_ccvs1_t m = {{speed_mm_s, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_ccvs1(f, &m, 0U), 0);
}

static void frame_ssi(pfe_can_frame_t *f, int32_t pitch_udeg)
{
    const pfe_msg_ssi_t m = {{pitch_udeg, PFE_SIG_VALID}, {0, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_ssi(f, &m, 0U), 0);
}

/* 90 km/h on the flat for ms milliseconds from t0_us: CCVS1 every 100 ms,
 * SSI every 10 ms, 3 ms after the reference's ticks. */
static void drive_flat(bus_ref_t *r, uint64_t t0_us, unsigned ms)
{
    for (unsigned t = 0U; t < ms; t += 10U) {
        const uint64_t now = t0_us + (t * 1000U);
        pfe_can_frame_t f;
        bus_ref_advance(r, now);
        if ((t % 100U) == 0U) {
            frame_ccvs1(&f, 25000);
            bus_ref_input(r, &f, now);
        }
        frame_ssi(&f, 0);
        bus_ref_input(r, &f, now);
    }
}

static void test_bus_ref_flat(void **state)
{
    (void)state;
    static bus_ref_t r;
    assert_int_equal(bus_ref_init(&r, 1U, 0U, 10000U), 0);
    drive_flat(&r, 1000003U, 2000U);
    assert_true(bus_ref_valid(&r));
    /* docs/model.md: 129.14 kW at the wheels (air 2418.75 N + rolling
     * 2746.8 N at 25 m/s) + 4 kW auxiliary, / (0.40 * 35.8 MJ/L) =
     * 9.2974e-3 L/s = 33.4707 L/h. */
    ASSERT_NEAR_LT(bus_ref_own_rate(&r) * 3600.0, 33.4707, 0.005);
    ASSERT_NEAR_LT(bus_ref_platoon_rate(&r) * 3600.0, 33.4707, 0.005);
    /* A peek sees what a tick would, and changes nothing. */
    const uint64_t ticks = r.ticks;
    double own = 0.0, platoon = 0.0;
    assert_true(bus_ref_peek(&r, 3000003U, &own, &platoon));
    ASSERT_NEAR_LT(own * 3600.0, 33.4707, 0.005);
    assert_int_equal(r.ticks, ticks);
    /* The SSI stops: 30 ms later the road is assumed flat, as the module
     * assumes it; the CCVS1 stops too: 300 ms later no estimate. */
    bus_ref_advance(&r, 3000003U + 40000U);
    assert_true(r.grade_flat);
    assert_true(bus_ref_valid(&r));
    ASSERT_NEAR_LT(bus_ref_own_rate(&r) * 3600.0, 33.4707, 0.005);
    bus_ref_advance(&r, 2900003U + 310000U);
    assert_false(bus_ref_valid(&r));
    ASSERT_EQ(bus_ref_own_rate(&r), 0.0);
}

static void frame_ccvs1_from(pfe_can_frame_t *f, int32_t speed_mm_s, pfe_sig_state_t st, uint8_t sa)
{
    const pfe_msg_ccvs1_t m = {{speed_mm_s, st}};
    ASSERT_GE(pfe_codec_encode_ccvs1(f, &m, sa), 0);
}

/* Two senders of CCVS1, one not available: the reference locks onto the
 * valid one, as the module does; a slope sensor in error is no flat road. */
static void test_bus_ref_senders_and_flat(void **state)
{
    (void)state;
    static bus_ref_t r;
    assert_int_equal(bus_ref_init(&r, 1U, 0U, 10000U), 0);
    pfe_can_frame_t f;
    for (unsigned t = 0U; t < 3000U; t += 100U) {
        const uint64_t now = 1000000U + (t * 1000U);
        bus_ref_advance(&r, now);
        frame_ccvs1_from(&f, 25000, PFE_SIG_VALID, 0x00U);
        bus_ref_input(&r, &f, now);
        frame_ccvs1_from(&f, 0, PFE_SIG_NOT_AVAILABLE, 0x31U);
        bus_ref_input(&r, &f, now + 4000U);
    }
    bus_ref_advance(&r, 4000000U);
    assert_int_equal(pfe_input_source(&r.speed_in), 0x00);
    assert_true(r.grade_flat);
    assert_true(bus_ref_valid(&r));
    /* no SSI at all: 90 km/h on a road assumed flat, 33.4707 L/h as above */
    ASSERT_NEAR_LT(bus_ref_own_rate(&r) * 3600.0, 33.4707, 0.005);
    /* the engine stops; the cab controller's valid speed takes over after
     * three periods (300 ms) without a valid value from the engine */
    for (unsigned t = 0U; t < 1000U; t += 100U) {
        const uint64_t now = 4000000U + (t * 1000U);
        bus_ref_advance(&r, now);
        frame_ccvs1_from(&f, 20000, PFE_SIG_VALID, 0x31U);
        bus_ref_input(&r, &f, now + 4000U);
    }
    assert_int_equal(pfe_input_source(&r.speed_in), 0x31);
    ASSERT_NEAR_LT(r.speed_m_s, 20.0, 1e-9);
    /* a slope sensor sending error: no flat road, no estimate */
    const pfe_msg_ssi_t e = {{0, PFE_SIG_ERROR}, {0, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_ssi(&f, &e, 0x00U), 0);
    bus_ref_advance(&r, 5000000U);
    bus_ref_input(&r, &f, 5000000U);
    bus_ref_advance(&r, 5020000U);
    assert_false(r.grade_flat);
    assert_false(bus_ref_valid(&r));
}

static void test_bus_ref_platoon_config(void **state)
{
    (void)state;
    static bus_ref_t r;
    assert_int_equal(bus_ref_init(&r, 1U, 0U, 10000U), 0);
    drive_flat(&r, 0U, 2000U);
    const double alone_l = bus_ref_own_used(&r);
    ASSERT_GT(alone_l, 0.0);
    pfe_msg_platoon_config_t c = {{5U, PFE_SIG_VALID}, {1U, PFE_SIG_VALID}, {10000U, PFE_SIG_VALID},
                                  {400U, PFE_SIG_VALID}, {25000, PFE_SIG_VALID}};
    pfe_can_frame_t f;
    ASSERT_GE(pfe_codec_encode_platoon_config(&f, &c, 0xE0U), 0);
    bus_ref_input(&r, &f, 2000000U);
    assert_int_equal(r.n_vehicles, 5);
    assert_int_equal(r.position, 1);
    assert_int_equal(r.gap_mm, 10000);
    assert_int_equal(r.reconfigurations, 1);
    assert_false(r.degraded);
    /* Fuel used carries over to the new position; the filter restarts. */
    ASSERT_EQ(bus_ref_own_used(&r), alone_l);
    /* The same configuration again changes nothing. */
    bus_ref_input(&r, &f, 2000500U);
    assert_int_equal(r.reconfigurations, 1);
    /* A position outside the platoon is refused. */
    c.own_position.value = 5U;
    ASSERT_GE(pfe_codec_encode_platoon_config(&f, &c, 0xE0U), 0);
    bus_ref_input(&r, &f, 2001000U);
    assert_int_equal(r.position, 1);
    assert_false(r.config_ok);
    /* The second truck, 10 m behind the lead, uses less than one alone. */
    drive_flat(&r, 2010000U, 2000U);
    assert_true(bus_ref_valid(&r));
    ASSERT_LT(bus_ref_own_rate(&r) * 3600.0, 33.0);
}

/* ---- drive noise -------------------------------------------------------- */

static void test_noise_splitmix64(void **state)
{
    (void)state;
    drive_noise_t n;
    drive_noise_seed(&n, 0U);
    assert_int_equal(drive_noise_u64(&n), 0xE220A8397B1DCDAFULL);
    assert_int_equal(drive_noise_u64(&n), 0x6E789E6AA1B965F4ULL);
    assert_int_equal(drive_noise_u64(&n), 0x06C45D188009454FULL);
    assert_int_equal(drive_noise_u64(&n), 0xF88BB8A8724C81ECULL);
    drive_noise_seed(&n, 12345U);
    assert_int_equal(drive_noise_u64(&n), 0x22118258A9D111A0ULL);
    assert_int_equal(drive_noise_u64(&n), 0x346EDCE5F713F8EDULL);
    /* 0xE220A8397B1DCDAF >> 11, times 2^-53. */
    drive_noise_seed(&n, 0U);
    ASSERT_EQ(drive_noise_uniform(&n), 0.8833108082136426);
}

static void test_noise_gauss(void **state)
{
    (void)state;
    drive_noise_t n;
    drive_noise_seed(&n, 1U);
    const int count = 200000;
    double sum = 0.0, sum2 = 0.0, lo = 0.0, hi = 0.0;
    for (int k = 0; k < count; k++) {
        const double x = drive_noise_gauss(&n);
        sum += x;
        sum2 += x * x;
        lo = fmin(lo, x);
        hi = fmax(hi, x);
    }
    const double mean = sum / count;
    const double sd = sqrt((sum2 / count) - (mean * mean));
    ASSERT_LT(fabs(mean), 0.01);
    ASSERT_NEAR_LT(sd, 1.0, 0.01);
    ASSERT_GT(lo, -6.0);
    ASSERT_LT(hi, 6.0);
    ASSERT_LT(lo, -3.5);
    ASSERT_GT(hi, 3.5);
}

/* ---- main --------------------------------------------------------------- */

int main(void)
{
    const char *tmp = getenv("TMPDIR");
    if ((tmp == NULL) || (strlen(tmp) > DIR_LEN - 32U)) {
        tmp = "/tmp";
    }
    snprintf(g_dir, sizeof g_dir, "%s/test_capture.XXXXXX", tmp);
    if (mkdtemp(g_dir) == NULL) {
        perror("mkdtemp");
        return 1;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_classic_frames),
        cmocka_unit_test(test_remote_fd_error_frames),
        cmocka_unit_test(test_lines_skipped),
        cmocka_unit_test(test_bad_lines),
        cmocka_unit_test(test_load_counts_and_skips),
        cmocka_unit_test(test_load_errors),
        cmocka_unit_test(test_load_printed_form),
        cmocka_unit_test(test_bus_ref_flat),
        cmocka_unit_test(test_bus_ref_senders_and_flat),
        cmocka_unit_test(test_bus_ref_platoon_config),
        cmocka_unit_test(test_noise_splitmix64),
        cmocka_unit_test(test_noise_gauss),
    };
    const int failed = cmocka_run_group_tests(tests, NULL, NULL);
    char cmd[PATH_LEN + 16];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", g_dir);
    if (system(cmd) != 0) {
        fprintf(stderr, "test_capture: could not remove %s\n", g_dir);
    }
    return failed;
}
