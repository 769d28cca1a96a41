/*
 * Tests of the CAN log reader and writer (sim_host/lib/log/log.h) and of the
 * lateness histogram (sim_host/lib/lateness.h).
 *
 *     test_canlog [DRIVE_LOG]
 *
 * DRIVE_LOG (or the environment variable DRIVE_LOG) is a candump log of a
 * drive, build/e2e/payload/drive.log (`make build/e2e/payload/drive.log`):
 * it is read, written again as Vector ASC and as candump's printed output
 * and read back to the same frames. Without it that test fails saying so.
 *
 * Every format is read from hand-written lines in the layouts can-utils
 * (candump.c, lib.c, log2asc.c of can-utils 2020.11) and Vector write, and
 * compared with literal frames; every bad-input class is checked for its
 * exact message (file, line, reason) in stop mode and for its count in
 * skip mode. Outputs are filled with 0xA5 before each call. Files are
 * written under a fresh mkdtemp() directory, removed at the end.
 */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "../test_assert.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lib/log/log.h"
#include "lib/lateness.h"

#define MAX_FRAMES 64
#define PATH_LEN 4096

static canlog_reader_t g_reader; /* about 70 KiB: not on the stack */
static canlog_frame_t g_frames[MAX_FRAMES];
static const char *g_drive_log;
static char g_dir[PATH_LEN - 64];

/* ---- helpers ------------------------------------------------------------ */

/* Reads every frame of TEXT in stop mode; fails the test on an error. */
static int read_text(const char *text, canlog_format_t fmt)
{
    canlog_reader_t *r = &g_reader;
    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_mem(r, text, strlen(text), "t.log", fmt, CANLOG_ON_ERROR_STOP),
                     0);
    memset(g_frames, 0xA5, sizeof g_frames);
    int n = 0;
    for (;;) {
        const int rc = canlog_next(r, &g_frames[n]);
        if (rc < 0) {
            print_error("unexpected error: %s\n", canlog_message(r));
        }
        ASSERT_GE(rc, 0);
        if (rc == 0) {
            break;
        }
        n++;
        ASSERT_LT(n, MAX_FRAMES);
    }
    return n;
}

/* Data bytes from a hex string "0011AA". */
static void hex_bytes(const char *hex, uint8_t *out, size_t *n)
{
    size_t k = 0U;
    for (; hex[2U * k] != '\0'; k++) {
        unsigned v = 0U;
        assert_int_equal(sscanf(hex + (2U * k), "%2x", &v), 1);
        out[k] = (uint8_t)v;
    }
    *n = k;
}

static void expect_frame(const canlog_frame_t *f, uint64_t time_us, const char *iface, uint32_t id,
                         bool fd, uint8_t fd_flags, uint8_t len, const char *hex)
{
    assert_int_equal(f->time_us, time_us);
    assert_string_equal(f->iface, iface);
    assert_int_equal(f->id, id);
    assert_int_equal(f->fd, fd);
    assert_int_equal(f->fd_flags, fd_flags);
    assert_int_equal(f->len, len);
    if (hex != NULL) {
        uint8_t want[64];
        size_t n = 0U;
        hex_bytes(hex, want, &n);
        assert_int_equal(n, len);
        assert_memory_equal(f->data, want, n);
    }
}

/* Expects TEXT to fail in stop mode with exactly MESSAGE, returning -REASON,
 * after GOOD frames; then in skip mode to give GOOD + AFTER frames and count
 * the line under REASON once. */
static void expect_bad(const char *text, canlog_format_t fmt, int good, int reason,
                       const char *message, int after)
{
    canlog_reader_t *r = &g_reader;
    canlog_frame_t f;
    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_mem(r, text, strlen(text), "t.log", fmt, CANLOG_ON_ERROR_STOP),
                     0);
    for (int i = 0; i < good; i++) {
        assert_int_equal(canlog_next(r, &f), 1);
    }
    memset(&f, 0xA5, sizeof f);
    canlog_frame_t untouched;
    memset(&untouched, 0xA5, sizeof untouched);
    assert_int_equal(canlog_next(r, &f), -reason);
    assert_string_equal(canlog_message(r), message);
    assert_memory_equal(&f, &untouched, sizeof f);
    assert_int_equal(r->errors[reason], 1U);
    assert_int_equal(r->error_lines, 1U);
    /* stop mode goes on after the bad line */
    for (int i = 0; i < after; i++) {
        assert_int_equal(canlog_next(r, &f), 1);
    }
    assert_int_equal(canlog_next(r, &f), 0);

    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_mem(r, text, strlen(text), "t.log", fmt, CANLOG_ON_ERROR_SKIP),
                     0);
    int n = 0;
    int rc;
    while ((rc = canlog_next(r, &f)) == 1) {
        n++;
    }
    assert_int_equal(rc, 0);
    assert_int_equal(n, good + after);
    assert_int_equal(r->errors[reason], 1U);
    assert_int_equal(r->error_lines, 1U);
    assert_int_equal(r->frames, (uint64_t)(good + after));
    assert_string_equal(r->first_msg[reason], message);
}

static const char *write_file(const char *name, const char *data, size_t len)
{
    static char path[PATH_LEN + 64];
    (void)snprintf(path, sizeof path, "%s/%s", g_dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1U, len, f), len);
    assert_int_equal(fclose(f), 0);
    return path;
}

/* ---- candump log -------------------------------------------------------- */

static void test_log_frames(void **state)
{
    (void)state;
    const int n = read_text("(1700000000.000000) vcan0 123#DEADBEEF\n"
                            "(1700000000.010000) vcan0 18FEF100#0011223344556677\n"
                            "(1700000000.020000123) can1 7FF#\n"
                            "(1700000000.030000) vcan0 123#R\n"
                            "(1700000000.040000) vcan0 00000123#R4\n"
                            "(1700000000.050000) vcan1 123##1000102030405060708090A0B\n"
                            "(1700000000.060000) vcan1 18FEF100##3\n"
                            "(1700000000.070000) vcan0 20000080#0000000000000000\n"
                            "(1700000000.080000) vcan0 123#11.22.33 R\n"
                            "(1700000000.090000) vcan0 1abcdef0#aabb T\n",
                            CANLOG_FMT_AUTO);
    assert_int_equal(n, 10);
    assert_int_equal(canlog_format(&g_reader), CANLOG_FMT_LOG);
    assert_int_equal(canlog_time_base(&g_reader), CANLOG_TB_EPOCH);
    expect_frame(&g_frames[0], 1700000000000000ULL, "vcan0", 0x123U, false, 0, 4, "DEADBEEF");
    expect_frame(&g_frames[1], 1700000000010000ULL, "vcan0", 0x98FEF100U, false, 0, 8,
                 "0011223344556677");
    expect_frame(&g_frames[2], 1700000000020000ULL, "can1", 0x7FFU, false, 0, 0, "");
    expect_frame(&g_frames[3], 1700000000030000ULL, "vcan0", 0x40000123U, false, 0, 0, NULL);
    expect_frame(&g_frames[4], 1700000000040000ULL, "vcan0", 0xC0000123U, false, 0, 4, NULL);
    expect_frame(&g_frames[5], 1700000000050000ULL, "vcan1", 0x123U, true, 1, 12,
                 "000102030405060708090A0B");
    expect_frame(&g_frames[6], 1700000000060000ULL, "vcan1", 0x98FEF100U, true, 3, 0, "");
    expect_frame(&g_frames[7], 1700000000070000ULL, "vcan0", 0x20000080U, false, 0, 8,
                 "0000000000000000");
    expect_frame(&g_frames[8], 1700000000080000ULL, "vcan0", 0x123U, false, 0, 3, "112233");
    assert_int_equal(g_frames[8].dir, 'R');
    expect_frame(&g_frames[9], 1700000000090000ULL, "vcan0", 0x9ABCDEF0U, false, 0, 2, "AABB");
    assert_int_equal(g_frames[9].dir, 'T');
    assert_int_equal(g_frames[0].dir, 0);
    assert_int_equal(g_frames[0].line, 1U);
    assert_int_equal(g_frames[9].line, 10U);
    assert_int_equal(g_reader.comments, 0U);
}

static void test_log_comments_crlf_bom(void **state)
{
    (void)state;
    const int n = read_text("\xEF\xBB\xBF# recorded on the bench\r\n"
                            "\r\n"
                            "// another comment\n"
                            "DROPCOUNT: dropped 2 CAN frames on 'vcan0' socket (total drops 2)\n"
                            "   (1700000000.000000)\tvcan0\t123#01\r\n"
                            "(1700000000.000001) vcan0 124#02",
                            CANLOG_FMT_AUTO);
    assert_int_equal(n, 2);
    expect_frame(&g_frames[0], 1700000000000000ULL, "vcan0", 0x123U, false, 0, 1, "01");
    expect_frame(&g_frames[1], 1700000000000001ULL, "vcan0", 0x124U, false, 0, 1, "02");
    assert_int_equal(g_frames[0].line, 5U);
    assert_int_equal(g_frames[1].line, 6U);
    assert_int_equal(g_reader.comments, 4U);
    assert_int_equal(g_reader.lines, 6U);
}

/* ---- candump printed output (can-utils 2020.11 layout) ------------------ */

static void test_printed_absolute(void **state)
{
    (void)state;
    /* candump -t a vcan0 vcan1 */
    const int n = read_text(" (1700000000.000000)  vcan0  18FEF100   [8]  00 11 22 33 44 55 66 77\n"
                            " (1700000000.010000)  vcan0       123   [2]  0A 0B\n"
                            " (1700000000.020000)  vcan0       123   [4]  remote request\n"
                            " (1700000000.030000)  vcan1       123  [12]  00 01 02 03 04 05 06 07 08 09 0A 0B\n"
                            " (1700000000.040000)  vcan0  20000080   [8]  00 00 00 00 00 00 00 00   ERRORFRAME\n"
                            "\tbus-error\n"
                            " (1700000000.050000)  vcan0       7FF   [0] \n",
                            CANLOG_FMT_AUTO);
    assert_int_equal(n, 6);
    assert_int_equal(canlog_format(&g_reader), CANLOG_FMT_PRINTED);
    assert_int_equal(canlog_time_base(&g_reader), CANLOG_TB_EPOCH);
    expect_frame(&g_frames[0], 1700000000000000ULL, "vcan0", 0x98FEF100U, false, 0, 8,
                 "0011223344556677");
    expect_frame(&g_frames[1], 1700000000010000ULL, "vcan0", 0x123U, false, 0, 2, "0A0B");
    expect_frame(&g_frames[2], 1700000000020000ULL, "vcan0", 0x40000123U, false, 0, 4, NULL);
    expect_frame(&g_frames[3], 1700000000030000ULL, "vcan1", 0x123U, true, 0, 12,
                 "000102030405060708090A0B");
    expect_frame(&g_frames[4], 1700000000040000ULL, "vcan0", 0x20000080U, false, 0, 8,
                 "0000000000000000");
    expect_frame(&g_frames[5], 1700000000050000ULL, "vcan0", 0x7FFU, false, 0, 0, "");
    assert_int_equal(g_reader.comments, 1U);
}

static void test_printed_date_zero_none(void **state)
{
    (void)state;
    /* candump -t A: local wall-clock time, read as UTC; 1700000000 is
     * 2023-11-14 22:13:20 UTC. */
    int n = read_text(" (2023-11-14 22:13:20.250000)  vcan0  123   [1]  01\n"
                      " (2023-11-14 22:13:21.000001)  vcan0  123   [1]  02\n",
                      CANLOG_FMT_AUTO);
    assert_int_equal(n, 2);
    assert_int_equal(canlog_time_base(&g_reader), CANLOG_TB_DATE);
    expect_frame(&g_frames[0], 1700000000250000ULL, "vcan0", 0x123U, false, 0, 1, "01");
    expect_frame(&g_frames[1], 1700000001000001ULL, "vcan0", 0x123U, false, 0, 1, "02");

    /* candump -t z: from the first frame */
    n = read_text(" (000.000000)  vcan0  123   [1]  01\n"
                  " (000.010000)  vcan0  123   [1]  02\n"
                  " (1234.500000)  vcan0  123   [1]  03\n",
                  CANLOG_FMT_AUTO);
    assert_int_equal(n, 3);
    assert_int_equal(canlog_time_base(&g_reader), CANLOG_TB_START);
    assert_int_equal(g_frames[0].time_us, 0U);
    assert_int_equal(g_frames[1].time_us, 10000U);
    assert_int_equal(g_frames[2].time_us, 1234500000U);

    /* candump -t d, forced: deltas added up */
    n = read_text(" (000.000000)  vcan0  123   [1]  01\n"
                  " (000.010000)  vcan0  123   [1]  02\n"
                  " (000.005000)  vcan0  123   [1]  03\n",
                  CANLOG_FMT_PRINTED_DELTA);
    assert_int_equal(n, 3);
    assert_int_equal(g_frames[0].time_us, 0U);
    assert_int_equal(g_frames[1].time_us, 10000U);
    assert_int_equal(g_frames[2].time_us, 15000U);

    /* no -t: no time at all; -x columns; -a ASCII column */
    n = read_text("  vcan0  123   [2]  41 42                     'AB'\n"
                  "  vcan1  RX B -  18FEF100  [12]  00 01 02 03 04 05 06 07 08 09 0A 0B\n"
                  "  vcan1  TX - E       123  [08]  FF FF FF FF FF FF FF FF\n"
                  "  vcan0  RX - -       321   [1]  7F\n"
                  "  vcan0  123  [04]  remote request\n",
                  CANLOG_FMT_AUTO);
    assert_int_equal(n, 5);
    assert_int_equal(canlog_format(&g_reader), CANLOG_FMT_PRINTED);
    assert_int_equal(canlog_time_base(&g_reader), CANLOG_TB_NONE);
    expect_frame(&g_frames[0], 0U, "vcan0", 0x123U, false, 0, 2, "4142");
    expect_frame(&g_frames[1], 0U, "vcan1", 0x98FEF100U, true, CANLOG_FD_BRS, 12,
                 "000102030405060708090A0B");
    assert_int_equal(g_frames[1].dir, 'R');
    expect_frame(&g_frames[2], 0U, "vcan1", 0x123U, true, CANLOG_FD_ESI, 8, "FFFFFFFFFFFFFFFF");
    assert_int_equal(g_frames[2].dir, 'T');
    expect_frame(&g_frames[3], 0U, "vcan0", 0x321U, false, 0, 1, "7F");
    expect_frame(&g_frames[4], 0U, "vcan0", 0x40000123U, false, 0, 4, NULL);
}

/* ---- Vector ASC ---------------------------------------------------------- */

static void test_asc_log2asc_layout(void **state)
{
    (void)state;
    /* as log2asc (can-utils 2020.11) writes it; -f writes the CANFD line
     * for classic frames too, with flags 0 (data) or 10 (remote) */
    const int n = read_text(
        "date Tue Nov 14 22:13:20 2023\n"
        "base hex  timestamps absolute\n"
        "no internal events logged\n"
        "   0.000000 1  18FEF100x       Rx   d 8 00 11 22 33 44 55 66 77\n"
        "   0.010000 1  123             Rx   d 2 0A 0B\n"
        "   0.020000 2  123             Tx   r 4\n"
        "   0.030000 1  ErrorFrame\n"
        "   0.040000 CANFD   2 Rx         123                                  1 0 9 12 00 01 02 03 04 05 06 07 08 09 0A 0B   130000  130     3000 0 0 0 0 0\n"
        "   0.050000 CANFD   1 Rx   18FEF100x                                  0 0 2  2 AA BB   130000  130        0 0 0 0 0 0\n"
        "   0.060000 CANFD   1 Rx         7FF                                  0 0 3  0   130000  130       10 0 0 0 0 0\n",
        CANLOG_FMT_AUTO);
    assert_int_equal(n, 7);
    assert_int_equal(canlog_format(&g_reader), CANLOG_FMT_ASC);
    assert_int_equal(canlog_time_base(&g_reader), CANLOG_TB_START);
    expect_frame(&g_frames[0], 0U, "can0", 0x98FEF100U, false, 0, 8, "0011223344556677");
    assert_int_equal(g_frames[0].channel, 1U);
    assert_int_equal(g_frames[0].dir, 'R');
    expect_frame(&g_frames[1], 10000U, "can0", 0x123U, false, 0, 2, "0A0B");
    expect_frame(&g_frames[2], 20000U, "can1", 0x40000123U, false, 0, 4, NULL);
    assert_int_equal(g_frames[2].dir, 'T');
    assert_int_equal(g_frames[2].channel, 2U);
    expect_frame(&g_frames[3], 30000U, "can0", 0x20000080U, false, 0, 8, "0000000000000000");
    expect_frame(&g_frames[4], 40000U, "can1", 0x123U, true, CANLOG_FD_BRS, 12,
                 "000102030405060708090A0B");
    expect_frame(&g_frames[5], 50000U, "can0", 0x98FEF100U, false, 0, 2, "AABB");
    expect_frame(&g_frames[6], 60000U, "can0", 0x400007FFU, false, 0, 3, NULL);
    assert_int_equal(g_reader.comments, 3U);
}

static void test_asc_vector_layout(void **state)
{
    (void)state;
    /* as Vector tools write it: trigger blocks, comments, statistics and
     * status events, the trailer after a frame's data, symbolic names */
    const int n = read_text(
        "date Tue Jan 2 10:11:12.123 am 2024\n"
        "base hex  timestamps relative\n"
        "internal events logged\n"
        "// version 13.0.0\n"
        "Begin Triggerblock Tue Jan 2 10:11:12.123 am 2024\n"
        "   0.000000 Start of measurement\n"
        "   0.001000 1  Statistic: D 0 R 0 XD 0 XR 0 E 0 O 0 B 0.00%\n"
        "   0.009000 1  18FEF100x       Rx   d 8 00 11 22 33 44 55 66 77  Length = 272000 BitCount = 137 ID = 419361024x\n"
        "   0.010000 1  123             Rx   d 1 0A  Length = 0 BitCount = 0 ID = 291\n"
        "   0.005000 CANFD   1 Rx 18FEF100x  EngineTemp  1 1 a 16 00 01 02 03 04 05 06 07 08 09 0A 0B 0C 0D 0E 0F 100000 214 00007000 0 0 0 0 0\n"
        "   0.001000 1  123             TxRq d 1 0A\n"
        "   0.001000 CAN 1 Status:chip status error active\n"
        "End TriggerBlock\n",
        CANLOG_FMT_AUTO);
    assert_int_equal(n, 3);
    assert_int_equal(canlog_format(&g_reader), CANLOG_FMT_ASC);
    /* relative: 0.001 + 0.009, + 0.010, + 0.005 */
    expect_frame(&g_frames[0], 10000U, "can0", 0x98FEF100U, false, 0, 8, "0011223344556677");
    expect_frame(&g_frames[1], 20000U, "can0", 0x123U, false, 0, 1, "0A");
    expect_frame(&g_frames[2], 25000U, "can0", 0x98FEF100U, true, CANLOG_FD_BRS | CANLOG_FD_ESI,
                 16, "000102030405060708090A0B0C0D0E0F");
    assert_int_equal(g_reader.comments, 10U);
}

static void test_asc_decimal(void **state)
{
    (void)state;
    const int n = read_text("base dec  timestamps absolute\n"
                            "   1.5 1  291             Rx   d 3 1 2 255\n"
                            "   2.25 1  419361024x      Rx   d 1 16\n",
                            CANLOG_FMT_AUTO);
    assert_int_equal(n, 2);
    expect_frame(&g_frames[0], 1500000U, "can0", 0x123U, false, 0, 3, "0102FF");
    expect_frame(&g_frames[1], 2250000U, "can0", 0x98FEF100U, false, 0, 1, "10");
}

/* ---- detection ----------------------------------------------------------- */

static void test_forced_format_refuses_another(void **state)
{
    (void)state;
    expect_bad("(1700000000.000000) vcan0 123#01\n", CANLOG_FMT_ASC, 0, CANLOG_E_SYNTAX,
               "t.log:1: syntax error: '(': not an ASC header, comment or event line", 0);
    expect_bad("   0.010000 1  123  Rx   d 1 0A\n", CANLOG_FMT_LOG, 0, CANLOG_E_SYNTAX,
               "t.log:1: syntax error: '0': a candump log line starts with '('", 0);
    expect_bad("hello world\n", CANLOG_FMT_AUTO, 0, CANLOG_E_FORMAT,
               "t.log:1: unknown format: neither a candump log, candump output nor Vector ASC line",
               0);
    canlog_format_t fmt = CANLOG_FMT_ASC;
    assert_int_equal(canlog_format_parse("printed-delta", &fmt), 0);
    assert_int_equal(fmt, CANLOG_FMT_PRINTED_DELTA);
    assert_int_equal(canlog_format_parse("csv", &fmt), -1);
    assert_int_equal(fmt, CANLOG_FMT_PRINTED_DELTA);
}

/* ---- bad input (must-show 5) --------------------------------------------- */

#define L0 "(1700000000.000000) vcan0 123#01\n"
#define L2 "(1700000000.020000) vcan0 123#03\n"

static void test_bad_truncated(void **state)
{
    (void)state;
    expect_bad(L0 "(1700000000.010000) vcan0 123#0102030\n" L2, CANLOG_FMT_AUTO, 1,
               CANLOG_E_TRUNCATED, "t.log:2: truncated line: half a byte at the end of the data", 1);
    expect_bad(L0 "(1700000000.010000) vcan0\n" L2, CANLOG_FMT_AUTO, 1, CANLOG_E_TRUNCATED,
               "t.log:2: truncated line: no frame after the interface", 1);
    expect_bad(L0 "(1700000000.0100\n" L2, CANLOG_FMT_AUTO, 1, CANLOG_E_TRUNCATED,
               "t.log:2: truncated line: line ends in the timestamp", 1);
    expect_bad(L0 "(1700000000.010000) vcan0 123\n" L2, CANLOG_FMT_AUTO, 1, CANLOG_E_TRUNCATED,
               "t.log:2: truncated line: no '#' after the id", 1);
    expect_bad(" (1700000000.000000)  vcan0  123   [8]  00 11 22\n", CANLOG_FMT_AUTO, 0,
               CANLOG_E_TRUNCATED, "t.log:1: truncated line: 3 data bytes of [8]", 0);
    expect_bad("   0.010000 1  123             Rx   d 4 0A 0B\n", CANLOG_FMT_AUTO, 0,
               CANLOG_E_TRUNCATED, "t.log:1: truncated line: 2 data bytes of 4", 0);
}

static void test_bad_hex(void **state)
{
    (void)state;
    expect_bad(L0 "(1700000000.010000) vcan0 123#01G2\n" L2, CANLOG_FMT_AUTO, 1, CANLOG_E_BAD_HEX,
               "t.log:2: bad hex: 'G' in the data", 1);
    expect_bad(L0 "(1700000000.010000) vcan0 1X3#01\n" L2, CANLOG_FMT_AUTO, 1, CANLOG_E_BAD_HEX,
               "t.log:2: bad hex: 'X' in the id", 1);
    expect_bad(" (1700000000.000000)  vcan0  123   [2]  0A 0Z\n", CANLOG_FMT_AUTO, 0,
               CANLOG_E_BAD_HEX, "t.log:1: bad hex: 'Z' in data byte 1", 0);
    expect_bad("   0.010000 1  18FEG100x       Rx   d 1 0A\n", CANLOG_FMT_AUTO, 0, CANLOG_E_BAD_HEX,
               "t.log:1: bad hex: 'G' in the id", 0);
    expect_bad("   0.010000 1  123             Rx   d 2 0A QQ\n", CANLOG_FMT_AUTO, 0,
               CANLOG_E_BAD_HEX, "t.log:1: bad hex: 'Q' in data byte 1", 0);
}

static void test_bad_length(void **state)
{
    (void)state;
    /* classic: 9 bytes */
    expect_bad(L0 "(1700000000.010000) vcan0 123#001122334455667788\n" L2, CANLOG_FMT_AUTO, 1,
               CANLOG_E_DLC, "t.log:2: bad length: 9 data bytes, over 8 for classic CAN", 1);
    /* FD: 65 bytes, and 9 (not a CAN FD length) */
    char line[256];
    int o = snprintf(line, sizeof line, "(1700000000.010000) vcan0 123##0");
    for (int i = 0; i < 65; i++) {
        o += snprintf(line + o, sizeof line - (size_t)o, "AA");
    }
    (void)snprintf(line + o, sizeof line - (size_t)o, "\n");
    char text[512];
    (void)snprintf(text, sizeof text, "%s%s%s", L0, line, L2);
    expect_bad(text, CANLOG_FMT_AUTO, 1, CANLOG_E_DLC,
               "t.log:2: bad length: 65 data bytes, over 64 for CAN FD", 1);
    expect_bad(L0 "(1700000000.010000) vcan0 123##0001122334455667788\n" L2, CANLOG_FMT_AUTO, 1,
               CANLOG_E_DLC,
               "t.log:2: bad length: 9 data bytes is not a CAN FD length (0-8, 12, 16, 20, 24, 32, 48, 64)",
               1);
    expect_bad(L0 "(1700000000.010000) vcan0 123#R9\n" L2, CANLOG_FMT_AUTO, 1, CANLOG_E_DLC,
               "t.log:2: bad length: remote frame length 9 over 8", 1);
    /* printed [9], [65], more bytes than [2] */
    expect_bad(" (1700000000.000000)  vcan0  123   [9]  00 11 22 33 44 55 66 77 88\n",
               CANLOG_FMT_AUTO, 0, CANLOG_E_DLC,
               "t.log:1: bad length: 9 data bytes, over 8 for classic CAN", 0);
    expect_bad(" (1700000000.000000)  vcan0  123  [65]  00\n", CANLOG_FMT_AUTO, 0, CANLOG_E_DLC,
               "t.log:1: bad length: 65 data bytes, over 64 for CAN FD", 0);
    expect_bad(" (1700000000.000000)  vcan0  123   [2]  00 11 22\n", CANLOG_FMT_AUTO, 0,
               CANLOG_E_DLC, "t.log:1: bad length: more data bytes than [2]", 0);
    /* ASC: DLC 9 on a classic line, DLC F that is not 16 bytes on an FD line */
    expect_bad("   0.010000 1  123             Rx   d 9 00 11 22 33 44 55 66 77\n", CANLOG_FMT_AUTO,
               0, CANLOG_E_DLC, "t.log:1: bad length: 9 data bytes, over 8 for classic CAN", 0);
    expect_bad("   0.010000 CANFD   1 Rx 123 1 0 f 16 00 01 02 03 04 05 06 07 08 09 0A 0B 0C 0D 0E 0F\n",
               CANLOG_FMT_AUTO, 0, CANLOG_E_DLC, "t.log:1: bad length: DLC F does not give 16 data bytes",
               0);
    expect_bad("   0.010000 1  123             Rx   d 1 00 11\n", CANLOG_FMT_AUTO, 0, CANLOG_E_DLC,
               "t.log:1: bad length: more data bytes than DLC 1", 0);
}

static void test_bad_id(void **state)
{
    (void)state;
    expect_bad(L0 "(1700000000.010000) vcan0 800#01\n" L2, CANLOG_FMT_AUTO, 1, CANLOG_E_BAD_ID,
               "t.log:2: bad id: 11-bit id 800 over 7FF", 1);
    expect_bad(L0 "(1700000000.010000) vcan0 1234#01\n" L2, CANLOG_FMT_AUTO, 1, CANLOG_E_BAD_ID,
               "t.log:2: bad id: id of 4 hex digits; 3 (11-bit) or 8 (29-bit) expected", 1);
    expect_bad(L0 "(1700000000.010000) vcan0 C0000000#01\n" L2, CANLOG_FMT_AUTO, 1,
               CANLOG_E_BAD_ID, "t.log:2: bad id: 29-bit id C0000000 over 1FFFFFFF", 1);
}

static void test_bad_time(void **state)
{
    (void)state;
    expect_bad(L0 "(1700000000.0100) vcan0 123#02\n" L2, CANLOG_FMT_AUTO, 1, CANLOG_E_BAD_TIME,
               "t.log:2: bad timestamp: 4 fraction digits; 6 or 9 expected", 1);
    expect_bad(L0 "(1700000000,010000) vcan0 123#02\n" L2, CANLOG_FMT_AUTO, 1, CANLOG_E_BAD_TIME,
               "t.log:2: bad timestamp: expected (SECONDS.FRACTION)", 1);
}

static void test_bad_backwards(void **state)
{
    (void)state;
    expect_bad(L0 "(1700000000.020000) vcan0 123#02\n"
                  "(1700000000.010000) vcan0 123#03\n"
                  "(1700000000.020000) vcan0 123#04\n",
               CANLOG_FMT_AUTO, 2, CANLOG_E_BACKWARDS,
               "t.log:3: timestamp going backwards: 1700000000.010000 s is before the previous "
               "frame's 1700000000.020000 s",
               1);
    /* equal times are fine */
    assert_int_equal(read_text(L0 L0, CANLOG_FMT_AUTO), 2);
    /* a candump -t d output read as -t z: the message says what to do */
    expect_bad(" (000.000000)  vcan0  123   [1]  01\n"
               " (000.010000)  vcan0  123   [1]  02\n"
               " (000.005000)  vcan0  123   [1]  03\n",
               CANLOG_FMT_AUTO, 2, CANLOG_E_BACKWARDS,
               "t.log:3: timestamp going backwards: 0.005000 s is before the previous frame's "
               "0.010000 s (candump -t d output? read it as printed-delta)",
               0);
}

static void test_bad_empty(void **state)
{
    (void)state;
    canlog_reader_t *r = &g_reader;
    canlog_frame_t f;
    const char *texts[] = {"", "\n\n", "# only a comment\n// and another\n"};
    const char *messages[] = {"t.log: empty file: no CAN frames (0 lines)",
                              "t.log: empty file: no CAN frames (2 lines)",
                              "t.log: empty file: no CAN frames (2 lines)"};
    for (size_t i = 0U; i < 3U; i++) {
        for (int mode = 0; mode < 2; mode++) {
            memset(r, 0xA5, sizeof *r);
            assert_int_equal(canlog_open_mem(r, texts[i], strlen(texts[i]), "t.log",
                                             CANLOG_FMT_AUTO, (canlog_error_mode_t)mode),
                             0);
            assert_int_equal(canlog_next(r, &f), -(int)CANLOG_E_EMPTY);
            assert_string_equal(canlog_message(r), messages[i]);
            assert_int_equal(r->errors[CANLOG_E_EMPTY], 1U);
            assert_int_equal(canlog_next(r, &f), 0);
        }
    }
    /* a real empty file, through a file descriptor */
    const char *path = write_file("empty.log", "", 0U);
    const int fd = open(path, O_RDONLY);
    ASSERT_GE(fd, 0);
    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_fd(r, fd, "empty.log", CANLOG_FMT_AUTO, CANLOG_ON_ERROR_STOP), 0);
    assert_int_equal(canlog_next(r, &f), -(int)CANLOG_E_EMPTY);
    assert_string_equal(canlog_message(r), "empty.log: empty file: no CAN frames (0 lines)");
    assert_int_equal(close(fd), 0);
}

static void test_bad_binary(void **state)
{
    (void)state;
    /* a NUL inside a line that would otherwise read */
    static const char nul_text[] = "(1700000000.000000) vcan0 123#01\n"
                                   "(1700000000.010000) vcan0 123#02\0junk\n"
                                   "(1700000000.020000) vcan0 123#03\n";
    canlog_reader_t *r = &g_reader;
    canlog_frame_t f;
    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_mem(r, nul_text, sizeof nul_text - 1U, "t.log", CANLOG_FMT_AUTO,
                                     CANLOG_ON_ERROR_STOP),
                     0);
    assert_int_equal(canlog_next(r, &f), 1);
    assert_int_equal(canlog_next(r, &f), -(int)CANLOG_E_BINARY);
    assert_string_equal(canlog_message(r), "t.log:2: binary content: NUL byte in the line");
    assert_int_equal(canlog_next(r, &f), 1);
    assert_int_equal(f.data[0], 3U);
    assert_int_equal(canlog_next(r, &f), 0);

    /* control characters in a line that does not read */
    expect_bad(L0 "(1700000000.010000) vcan0 12\x01#02\n" L2, CANLOG_FMT_AUTO, 1, CANLOG_E_BINARY,
               "t.log:2: binary content: control characters or NUL bytes in the line", 1);

    /* a binary file from its first byte: an ELF header */
    static const char elf[] = "\x7F" "ELF\x02\x01\x01\0\0\0\0\0\0\0\0\0\x03\0>\0\x01\0\0\0\n\x10\x20";
    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_mem(r, elf, sizeof elf - 1U, "prog", CANLOG_FMT_AUTO,
                                     CANLOG_ON_ERROR_STOP),
                     0);
    assert_int_equal(canlog_next(r, &f), -(int)CANLOG_E_BINARY);
    assert_string_equal(
        canlog_message(r),
        "prog:1: binary content: neither a candump log, candump output nor Vector ASC line");
    /* skip mode: every line skipped and counted, no frame, no crash */
    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_mem(r, elf, sizeof elf - 1U, "prog", CANLOG_FMT_AUTO,
                                     CANLOG_ON_ERROR_SKIP),
                     0);
    assert_int_equal(canlog_next(r, &f), 0);
    assert_int_equal(r->errors[CANLOG_E_BINARY], 2U);
    assert_int_equal(r->frames, 0U);

    /* random bytes, no newline for 8 KiB: one line too long, judged binary */
    static char noise[8192];
    uint32_t x = 1U;
    for (size_t i = 0U; i < sizeof noise; i++) {
        x = (x * 1103515245U) + 12345U;
        noise[i] = (char)((x >> 16) & 0xFFU);
        if (noise[i] == '\n') {
            noise[i] = 0;
        }
    }
    const char *path = write_file("noise.bin", noise, sizeof noise);
    const int fd = open(path, O_RDONLY);
    ASSERT_GE(fd, 0);
    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_fd(r, fd, "noise.bin", CANLOG_FMT_AUTO, CANLOG_ON_ERROR_STOP), 0);
    assert_int_equal(canlog_next(r, &f), -(int)CANLOG_E_BINARY);
    assert_string_equal(canlog_message(r),
                        "noise.bin:1: binary content: 8192 characters, more than 4095");
    assert_int_equal(canlog_next(r, &f), 0);
    assert_int_equal(close(fd), 0);
}

static void test_line_length_limit(void **state)
{
    (void)state;
    static char text[3 * 4200];
    /* a comment line of exactly 4095 characters is read ... */
    size_t o = 0U;
    text[o++] = '#';
    memset(text + o, 'x', 4094U);
    o += 4094U;
    text[o++] = '\n';
    o += (size_t)snprintf(text + o, sizeof text - o, "%s", L0);
    /* ... one of 4096 is not, and the line after it is */
    text[o++] = '#';
    memset(text + o, 'y', 4095U);
    o += 4095U;
    text[o++] = '\n';
    (void)snprintf(text + o, sizeof text - o, "%s", L2);
    expect_bad(text, CANLOG_FMT_AUTO, 1, CANLOG_E_LINE_TOO_LONG,
               "t.log:3: line too long: 4096 characters, more than 4095", 1);
}

/* ---- streaming, files, rewind -------------------------------------------- */

static void test_streaming_large_file(void **state)
{
    (void)state;
    /* 20000 lines (about 760 KiB), many times the read buffer, through a file */
    const size_t n_lines = 20000U;
    char *text = malloc(n_lines * 40U);
    assert_non_null(text);
    size_t o = 0U;
    for (size_t i = 0U; i < n_lines; i++) {
        o += (size_t)sprintf(text + o, "(1700000000.%06zu) vcan0 18FEF1%02zX#%02zX\n", i,
                             i & 0xFFU, (i >> 8) & 0xFFU);
    }
    const char *path = write_file("large.log", text, o);
    free(text);
    const int fd = open(path, O_RDONLY);
    ASSERT_GE(fd, 0);
    canlog_reader_t *r = &g_reader;
    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_fd(r, fd, "large.log", CANLOG_FMT_AUTO, CANLOG_ON_ERROR_STOP), 0);
    for (int pass = 0; pass < 2; pass++) {
        canlog_frame_t f;
        size_t i = 0U;
        int rc;
        while ((rc = canlog_next(r, &f)) == 1) {
            assert_int_equal(f.time_us, 1700000000000000ULL + i);
            assert_int_equal(f.id, 0x98FEF100U | (uint32_t)(i & 0xFFU));
            assert_int_equal(f.data[0], (i >> 8) & 0xFFU);
            assert_int_equal(f.line, i + 1U);
            i++;
        }
        assert_int_equal(rc, 0);
        assert_int_equal(i, n_lines);
        assert_int_equal(canlog_rewind(r), 0);
    }
    assert_int_equal(r->frames, 2U * n_lines);
    assert_int_equal(close(fd), 0);

    /* a pipe cannot go back */
    int p[2];
    assert_int_equal(pipe(p), 0);
    assert_int_equal(write(p[1], L0, strlen(L0)), (ssize_t)strlen(L0));
    assert_int_equal(close(p[1]), 0);
    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_fd(r, p[0], "pipe", CANLOG_FMT_AUTO, CANLOG_ON_ERROR_STOP), 0);
    canlog_frame_t f;
    assert_int_equal(canlog_next(r, &f), 1);
    assert_int_equal(canlog_next(r, &f), 0);
    assert_int_equal(canlog_rewind(r), -(int)CANLOG_E_IO);
    assert_string_equal(canlog_message(r), "pipe: read error: cannot go back to the start (Illegal seek)");
    assert_int_equal(close(p[0]), 0);
}

/* ---- writer ---------------------------------------------------------------- */

static void expect_line(const canlog_frame_t *f, const char *iface, const char *want)
{
    char buf[CANLOG_LOG_LINE_MAX];
    memset(buf, 0xA5, sizeof buf);
    assert_int_equal(canlog_write_log(buf, sizeof buf, f, iface), strlen(want));
    assert_string_equal(buf, want);
}

static void test_writer(void **state)
{
    (void)state;
    canlog_frame_t f;
    char buf[CANLOG_LOG_LINE_MAX];
    memset(&f, 0xA5, sizeof f);
    f.time_us = 1700000000123456ULL;
    (void)snprintf(f.iface, sizeof f.iface, "vcan0");
    f.id = 0x98FEF100U;
    f.fd = false;
    f.fd_flags = 0U;
    f.len = 3U;
    f.data[0] = 0x00U;
    f.data[1] = 0xABU;
    f.data[2] = 0xFFU;
    expect_line(&f, NULL, "(1700000000.123456) vcan0 18FEF100#00ABFF\n");
    f.id = 0x7FFU;
    f.len = 0U;
    f.time_us = 12U;
    expect_line(&f, "can1", "(0000000000.000012) can1 7FF#\n");
    f.id = 0x40000123U;
    f.len = 4U;
    expect_line(&f, NULL, "(0000000000.000012) vcan0 123#R4\n");
    f.id = 0x20000004U;
    f.len = 1U;
    expect_line(&f, NULL, "(0000000000.000012) vcan0 20000004#00\n");
    f.id = 0x123U;
    f.fd = true;
    f.fd_flags = CANLOG_FD_BRS;
    f.len = 12U;
    for (uint8_t i = 0U; i < 12U; i++) {
        f.data[i] = i;
    }
    expect_line(&f, NULL, "(0000000000.000012) vcan0 123##1000102030405060708090A0B\n");
    assert_int_equal(canlog_write_log(buf, sizeof buf, &f, NULL), 57U);
    /* a buffer too small gets "" and 0 */
    char small[20];
    memset(small, 0xA5, sizeof small);
    assert_int_equal(canlog_write_log(small, sizeof small, &f, NULL), 0U);
    assert_string_equal(small, "");
    /* what it writes reads back */
    assert_int_equal(read_text(buf, CANLOG_FMT_AUTO), 1);
    expect_frame(&g_frames[0], 12U, "vcan0", 0x123U, true, CANLOG_FD_BRS, 12,
                 "000102030405060708090A0B");
}

static void test_fd_lengths(void **state)
{
    (void)state;
    assert_int_equal(canlog_fd_dlc_to_len(8U), 8U);
    assert_int_equal(canlog_fd_dlc_to_len(9U), 12U);
    assert_int_equal(canlog_fd_dlc_to_len(13U), 32U);
    assert_int_equal(canlog_fd_dlc_to_len(15U), 64U);
    assert_int_equal(canlog_fd_len_to_dlc(8U), 8U);
    assert_int_equal(canlog_fd_len_to_dlc(9U), 9U);
    assert_int_equal(canlog_fd_len_to_dlc(12U), 9U);
    assert_int_equal(canlog_fd_len_to_dlc(33U), 14U);
    assert_int_equal(canlog_fd_len_to_dlc(64U), 15U);
    assert_int_equal(canlog_fd_len_to_dlc(65U), 0xFFU);
}

/* ---- must-show 3: one drive in three formats ------------------------------ */

/* Test-side writers, each in the layout of the tool it stands for (can-utils
 * 2020.11: candump.c and lib.c for the log and the printed output, log2asc.c
 * for ASC), independent of canlog_write_log. */

static size_t put_log(char *out, const canlog_frame_t *f)
{
    int n = sprintf(out, "(%010llu.%06llu) %s ", (unsigned long long)(f->time_us / 1000000U),
                    (unsigned long long)(f->time_us % 1000000U), f->iface);
    if ((f->id & CANLOG_EFF_FLAG) != 0U) {
        n += sprintf(out + n, "%08X#", (unsigned)(f->id & CANLOG_EFF_MASK));
    } else {
        n += sprintf(out + n, "%03X#", (unsigned)(f->id & CANLOG_SFF_MASK));
    }
    if ((f->id & CANLOG_RTR_FLAG) != 0U) {
        n += sprintf(out + n, "R");
        if (f->len > 0U) {
            n += sprintf(out + n, "%X", f->len);
        }
    } else {
        if (f->fd) {
            n += sprintf(out + n, "#%X", f->fd_flags);
        }
        for (unsigned i = 0U; i < f->len; i++) {
            n += sprintf(out + n, "%02X", f->data[i]);
        }
    }
    n += sprintf(out + n, "\n");
    return (size_t)n;
}

/* candump -t a, view with INDENT_SFF once a 29-bit frame was seen. */
static size_t put_printed(char *out, const canlog_frame_t *f, bool *indent)
{
    int n = sprintf(out, " (%010llu.%06llu)  %s  ", (unsigned long long)(f->time_us / 1000000U),
                    (unsigned long long)(f->time_us % 1000000U), f->iface);
    const bool eff = (f->id & CANLOG_EFF_FLAG) != 0U;
    if (eff) {
        *indent = true;
        n += sprintf(out + n, "%08X  ", (unsigned)(f->id & CANLOG_EFF_MASK));
    } else if (*indent) {
        n += sprintf(out + n, "     %03X  ", (unsigned)(f->id & CANLOG_SFF_MASK));
    } else {
        n += sprintf(out + n, "%03X  ", (unsigned)(f->id & CANLOG_SFF_MASK));
    }
    if (f->fd) {
        n += sprintf(out + n, "[%02u] ", f->len);
    } else {
        n += sprintf(out + n, " [%u] ", f->len);
    }
    if ((f->id & CANLOG_RTR_FLAG) != 0U) {
        n += sprintf(out + n, " remote request");
    } else {
        for (unsigned i = 0U; i < f->len; i++) {
            n += sprintf(out + n, " %02X", f->data[i]);
        }
    }
    n += sprintf(out + n, "\n");
    return (size_t)n;
}

/* log2asc: classic frames on the "d"/"r" line, FD frames on the CANFD line. */
static size_t put_asc(char *out, const canlog_frame_t *f, uint64_t t0_us)
{
    const uint64_t t = f->time_us - t0_us;
    int n = sprintf(out, "%4llu.%06llu ", (unsigned long long)(t / 1000000U),
                    (unsigned long long)(t % 1000000U));
    char id[16];
    if ((f->id & CANLOG_EFF_FLAG) != 0U) {
        (void)snprintf(id, sizeof id, "%Xx", (unsigned)(f->id & CANLOG_EFF_MASK));
    } else {
        (void)snprintf(id, sizeof id, "%X", (unsigned)(f->id & CANLOG_SFF_MASK));
    }
    if (!f->fd) {
        n += sprintf(out + n, "%-2d %-15s %s   ", 1, id, "Rx");
        if ((f->id & CANLOG_RTR_FLAG) != 0U) {
            n += sprintf(out + n, "r %d", f->len);
        } else {
            n += sprintf(out + n, "d %d", f->len);
            for (unsigned i = 0U; i < f->len; i++) {
                n += sprintf(out + n, " %02X", f->data[i]);
            }
        }
    } else {
        n += sprintf(out + n, "CANFD %3d %s %11s                                  %c %c %x %2d",
                     1, "Rx", id, ((f->fd_flags & CANLOG_FD_BRS) != 0U) ? '1' : '0',
                     ((f->fd_flags & CANLOG_FD_ESI) != 0U) ? '1' : '0',
                     canlog_fd_len_to_dlc(f->len), f->len);
        for (unsigned i = 0U; i < f->len; i++) {
            n += sprintf(out + n, " %02X", f->data[i]);
        }
        unsigned flags = 0x1000U;
        flags |= ((f->fd_flags & CANLOG_FD_BRS) != 0U) ? 0x2000U : 0U;
        flags |= ((f->fd_flags & CANLOG_FD_ESI) != 0U) ? 0x4000U : 0U;
        n += sprintf(out + n, " %8d %4d %8X 0 0 0 0 0", 130000, 130, flags);
    }
    n += sprintf(out + n, "\n");
    return (size_t)n;
}

/* Reads TEXT (a whole file in memory) and checks its frames against WANT:
 * same ids, lengths, data, FD flags and interface; times shifted by
 * MINUS_US (ASC counts from the first frame). */
static void same_frames(const char *text, size_t len, const canlog_frame_t *want, size_t n,
                        uint64_t minus_us, const char *iface, canlog_format_t expect_fmt)
{
    canlog_reader_t *r = &g_reader;
    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_mem(r, text, len, "drive", CANLOG_FMT_AUTO, CANLOG_ON_ERROR_STOP),
                     0);
    canlog_frame_t f;
    for (size_t i = 0U; i < n; i++) {
        memset(&f, 0xA5, sizeof f);
        const int rc = canlog_next(r, &f);
        if (rc != 1) {
            print_error("frame %zu: %s\n", i, canlog_message(r));
        }
        assert_int_equal(rc, 1);
        assert_int_equal(f.time_us, want[i].time_us - minus_us);
        assert_int_equal(f.id, want[i].id);
        assert_int_equal(f.fd, want[i].fd);
        assert_int_equal(f.fd_flags, want[i].fd_flags);
        assert_int_equal(f.len, want[i].len);
        if ((f.id & CANLOG_RTR_FLAG) == 0U) {
            assert_memory_equal(f.data, want[i].data, f.len);
        }
        assert_string_equal(f.iface, iface);
    }
    assert_int_equal(canlog_next(r, &f), 0);
    assert_int_equal(canlog_format(r), expect_fmt);
}

/* Writes FRAMES as a candump log, candump -t a output and log2asc's ASC, and
 * reads each back to the same frames. */
static void three_formats(const canlog_frame_t *frames, size_t n)
{
    const size_t cap = (n * 400U) + 256U;
    char *log = malloc(cap);
    char *printed = malloc(cap);
    char *asc = malloc(cap);
    assert_non_null(log);
    assert_non_null(printed);
    assert_non_null(asc);
    size_t nl = 0U;
    size_t np = 0U;
    size_t na = (size_t)sprintf(asc, "date Tue Nov 14 22:13:20 2023\n"
                                     "base hex  timestamps absolute\n"
                                     "no internal events logged\n");
    bool indent = false;
    for (size_t i = 0U; i < n; i++) {
        nl += put_log(log + nl, &frames[i]);
        np += put_printed(printed + np, &frames[i], &indent);
        na += put_asc(asc + na, &frames[i], frames[0].time_us);
        ASSERT_LT(nl, cap - 400U);
        ASSERT_LT(np, cap - 400U);
        ASSERT_LT(na, cap - 400U);
    }
    same_frames(log, nl, frames, n, 0U, frames[0].iface, CANLOG_FMT_LOG);
    same_frames(printed, np, frames, n, 0U, frames[0].iface, CANLOG_FMT_PRINTED);
    same_frames(asc, na, frames, n, frames[0].time_us, "can0", CANLOG_FMT_ASC);
    free(log);
    free(printed);
    free(asc);
}

static canlog_frame_t make(uint64_t t, uint32_t id, bool fd, uint8_t flags, uint8_t len,
                           const char *hex)
{
    canlog_frame_t f;
    memset(&f, 0, sizeof f);
    f.time_us = t;
    (void)snprintf(f.iface, sizeof f.iface, "vcan0");
    f.id = id;
    f.fd = fd;
    f.fd_flags = flags;
    f.len = len;
    if (hex != NULL) {
        size_t k = 0U;
        hex_bytes(hex, f.data, &k);
        assert_int_equal(k, len);
    }
    return f;
}

static void test_same_frames_three_formats(void **state)
{
    (void)state;
    /* every kind of frame the three formats share (FD flags are not in
     * candump's default printed output: 0 here) */
    const canlog_frame_t frames[] = {
        make(1700000000000000ULL, 0x123U, false, 0, 4, "DEADBEEF"),
        make(1700000000000000ULL, 0x7FFU, false, 0, 0, ""),
        make(1700000000010000ULL, 0x98FEF100U, false, 0, 8, "00C0160000000000"),
        make(1700000000020000ULL, 0x8CF01300U, false, 0, 8, "007D007DFFFFFCFF"),
        make(1700000000030000ULL, 0x40000321U, false, 0, 2, NULL),
        make(1700000000040000ULL, 0xC0000001U, false, 0, 0, NULL),
        make(1700000000050000ULL, 0x123U, true, 0, 12, "000102030405060708090A0B"),
        make(1700000000060000ULL, 0x98FEF100U, true, 0, 64,
             "000102030405060708090A0B0C0D0E0F101112131415161718191A1B1C1D1E1F"
             "202122232425262728292A2B2C2D2E2F303132333435363738393A3B3C3D3E3F"),
        make(1700000001234567ULL, 0x001U, false, 0, 1, "FF"),
    };
    three_formats(frames, sizeof frames / sizeof frames[0]);
}

static void test_drive_log_three_formats(void **state)
{
    (void)state;
    if (g_drive_log == NULL) {
        fail_msg("no drive log: pass build/e2e/payload/drive.log (make build/e2e/payload/drive.log)");
    }
    const int fd = open(g_drive_log, O_RDONLY);
    if (fd < 0) {
        fail_msg("cannot open %s: %s", g_drive_log, strerror(errno));
    }
    canlog_reader_t *r = &g_reader;
    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_fd(r, fd, g_drive_log, CANLOG_FMT_AUTO, CANLOG_ON_ERROR_STOP), 0);
    size_t cap = 1024U;
    size_t n = 0U;
    canlog_frame_t *frames = malloc(cap * sizeof *frames);
    assert_non_null(frames);
    int rc;
    while ((rc = canlog_next(r, &frames[n])) == 1) {
        n++;
        if (n == cap) {
            cap *= 2U;
            frames = realloc(frames, cap * sizeof *frames);
            assert_non_null(frames);
        }
    }
    if (rc != 0) {
        print_error("%s\n", canlog_message(r));
    }
    assert_int_equal(rc, 0);
    assert_int_equal(close(fd), 0);
    ASSERT_GT(n, 1000U);
    assert_int_equal(canlog_format(r), CANLOG_FMT_LOG);
    print_message("%zu frames of %s in three formats\n", n, g_drive_log);
    three_formats(frames, n);
    free(frames);
}

/* ---- lateness histogram ---------------------------------------------------- */

/* ---- the lines the replay bus (hal/replay) is held to as well ----------- */

typedef enum { LV_FRAME, LV_SKIP, LV_COMMENT, LV_BAD, LV_NO_TIME } lv_kind_t;
typedef struct {
    const char *line;
    lv_kind_t kind;
    uint64_t t_us;
    uint32_t id;
    uint8_t len;
    const char *hex;
} log_vector_t;

static const log_vector_t k_vectors[] = {
#define LOG_VECTOR(line, kind, t_us, id, len, hex) {line, kind, t_us, id, len, hex},
#include "tests/replay/log_vectors.h"
#undef LOG_VECTOR
};

static uint8_t hex_byte(const char *p)
{
    unsigned v = 0U;
    for (int k = 0; k < 2; k++) {
        const char c = p[k];
        v = (v << 4) | (unsigned)((c <= '9') ? (c - '0') : (c - 'A' + 10));
    }
    return (uint8_t)v;
}

/* Each line of tests/replay/log_vectors.h alone, format detected, as
 * tests/hal/test_hal_replay.c reads it through the replay bus. */
static void test_shared_log_vectors(void **state)
{
    (void)state;
    canlog_reader_t *r = &g_reader;
    static char text[CANLOG_LINE_MAX + 2U];
    for (size_t k = 0U; k < sizeof k_vectors / sizeof k_vectors[0]; k++) {
        const log_vector_t *v = &k_vectors[k];
        const int n = snprintf(text, sizeof text, "%s\n", v->line);
        ASSERT_GT(n, 0);
        ASSERT_LT((size_t)n, sizeof text);
        memset(r, 0xA5, sizeof *r);
        assert_int_equal(canlog_open_mem(r, text, (size_t)n, "v.log", CANLOG_FMT_AUTO,
                                         CANLOG_ON_ERROR_STOP), 0);
        canlog_frame_t f;
        memset(&f, 0xA5, sizeof f);
        const int rc = canlog_next(r, &f);
        const bool frame = (v->kind == LV_FRAME) || (v->kind == LV_SKIP) || (v->kind == LV_NO_TIME);
        const bool ok = frame ? (rc == 1)
                              : ((v->kind == LV_COMMENT) ? ((rc == -(int)CANLOG_E_EMPTY) &&
                                                            (r->comments == 1U))
                                                         : ((rc < 0) && (rc != -(int)CANLOG_E_EMPTY)));
        if (!ok) {
            print_error("vector %u '%s': canlog_next %d, %llu comments: %s\n", (unsigned)k, v->line,
                        rc, (unsigned long long)r->comments, canlog_message(r));
        }
        assert_true(ok);
        if (v->kind == LV_SKIP) {
            const bool not_classic = f.fd || ((f.id & (CANLOG_RTR_FLAG | CANLOG_ERR_FLAG)) != 0U);
            if (!not_classic) {
                print_error("vector %u '%s': read as a classic data frame %08lX\n", (unsigned)k,
                            v->line, (unsigned long)f.id);
            }
            assert_true(not_classic);
        }
        if ((v->kind != LV_FRAME) && (v->kind != LV_NO_TIME)) {
            continue;
        }
        assert_false(f.fd);
        assert_int_equal(canlog_time_base(r) == CANLOG_TB_NONE, v->kind == LV_NO_TIME);
        assert_int_equal(f.time_us, v->t_us);
        assert_int_equal(f.id, v->id);
        assert_int_equal(f.len, v->len);
        for (uint8_t b = 0U; b < v->len; b++) {
            assert_int_equal(f.data[b], hex_byte(&v->hex[2U * b]));
        }
        assert_int_equal(canlog_next(r, &f), 0);
    }
}

/* DROPCOUNT's count in every form candump writes it in; raw DLCs. */
static void test_dropcount_and_raw_dlc(void **state)
{
    (void)state;
    canlog_reader_t *r = &g_reader;
    assert_int_equal(read_text("DROPCOUNT: dropped 2 CAN frames on 'can0' socket (total drops 2)\n"
                               "(1.000000) can0 123#0011223344556677_C\n"
                               "DROPCOUNT: dropped 5 CAN frames on 'can0' socket (total drops 7)\n"
                               "(1.000001) can0 123#00\n", CANLOG_FMT_AUTO), 2);
    assert_int_equal(r->dropped, 7);
    assert_int_equal(g_frames[0].len, 8);
    assert_int_equal(g_frames[0].len8_dlc, 12);
    assert_int_equal(g_frames[1].len8_dlc, 0);
    char buf[CANLOG_LOG_LINE_MAX];
    assert_int_equal(canlog_write_log(buf, sizeof buf, &g_frames[0], NULL), 48U);
    assert_string_equal(buf, "(0000000001.000000) can0 123#0011223344556677_C\n");
    assert_int_equal(read_text("(000.000000)  can0  123   [1]  01\n"
                               "DROPCOUNT: dropped 4 CAN frames on 'can0' socket (total drops 4)\n"
                               "(000.100000)  can0  123   [1]  02\n", CANLOG_FMT_AUTO), 2);
    assert_int_equal(r->dropped, 4);
    memset(r, 0xA5, sizeof *r);
    const char *bad = "(1.000000) can0 123#0011_9\n";
    assert_int_equal(canlog_open_mem(r, bad, strlen(bad), "t.log", CANLOG_FMT_AUTO,
                                     CANLOG_ON_ERROR_STOP), 0);
    canlog_frame_t f;
    assert_int_equal(canlog_next(r, &f), -(int)CANLOG_E_DLC);
    assert_string_equal(canlog_message(r), "t.log:1: bad length: a raw DLC after '_' needs 8 data "
                                           "bytes and a DLC of 9 to F");
}

/* With canlog_allow_backwards(), a frame earlier than the one before comes
 * with its own time, counted. */
static void test_backwards_allowed(void **state)
{
    (void)state;
    canlog_reader_t *r = &g_reader;
    const char *text = "(5.000000) can0 100#01\n(4.000000) can0 101#02\n(6.000000) can0 102#03\n";
    memset(r, 0xA5, sizeof *r);
    assert_int_equal(canlog_open_mem(r, text, strlen(text), "t.log", CANLOG_FMT_AUTO,
                                     CANLOG_ON_ERROR_STOP), 0);
    canlog_allow_backwards(r, true);
    canlog_frame_t f;
    assert_int_equal(canlog_next(r, &f), 1);
    assert_int_equal(canlog_next(r, &f), 1);
    assert_int_equal(f.time_us, 4000000U);
    assert_int_equal(canlog_next(r, &f), 1);
    assert_int_equal(f.time_us, 6000000U);
    assert_int_equal(canlog_next(r, &f), 0);
    assert_int_equal(r->backwards, 1);
    assert_int_equal(r->error_lines, 0);
}

static void test_lateness(void **state)
{
    (void)state;
    static lateness_hist_t h;
    memset(&h, 0xA5, sizeof h);
    lateness_init(&h);
    assert_int_equal(lateness_percentile_us(&h, 500U), 0U);
    /* 1 .. 100 us: median 50, p99 99, max 100 */
    for (uint64_t v = 1U; v <= 100U; v++) {
        lateness_add(&h, v);
    }
    assert_int_equal(h.count, 100U);
    assert_int_equal(lateness_percentile_us(&h, 500U), 50U);
    assert_int_equal(lateness_percentile_us(&h, 990U), 99U);
    assert_int_equal(lateness_percentile_us(&h, 1000U), 100U);
    assert_int_equal(h.max_us, 100U);
    /* one large value: 10000 us falls in the bin 9984 .. 10111 (128 us wide
     * from 2^13), capped by the maximum */
    lateness_add(&h, 10000U);
    assert_int_equal(lateness_percentile_us(&h, 1000U), 10000U);
    lateness_add(&h, 10040U);
    assert_int_equal(lateness_percentile_us(&h, 995U), 10040U);
    assert_int_equal(h.max_us, 10040U);
    /* a year of lateness lands in the last bin, the maximum stays exact */
    lateness_add(&h, 31536000000000ULL);
    assert_int_equal(h.max_us, 31536000000000ULL);
    assert_int_equal(lateness_percentile_us(&h, 1000U), 31536000000000ULL);
    assert_int_equal(lateness_percentile_us(&h, 500U), 52U);
}

/* ---- set-up ---------------------------------------------------------------- */

static int make_dir(void **state)
{
    (void)state;
    const char *tmp = getenv("TMPDIR");
    (void)snprintf(g_dir, sizeof g_dir, "%s/test_canlog.XXXXXX", (tmp != NULL) ? tmp : "/tmp");
    return (mkdtemp(g_dir) != NULL) ? 0 : -1;
}

static int remove_dir(void **state)
{
    (void)state;
    const char *names[] = {"empty.log", "noise.bin", "large.log"};
    char path[PATH_LEN + 32];
    for (size_t i = 0U; i < sizeof names / sizeof names[0]; i++) {
        (void)snprintf(path, sizeof path, "%s/%s", g_dir, names[i]);
        (void)unlink(path);
    }
    return rmdir(g_dir);
}

int main(int argc, char **argv)
{
    g_drive_log = getenv("DRIVE_LOG");
    if (argc == 2) {
        g_drive_log = argv[1];
    } else if (argc != 1) {
        fprintf(stderr, "usage: %s [DRIVE_LOG]\n", argv[0]);
        return 2;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_log_frames),
        cmocka_unit_test(test_log_comments_crlf_bom),
        cmocka_unit_test(test_printed_absolute),
        cmocka_unit_test(test_printed_date_zero_none),
        cmocka_unit_test(test_asc_log2asc_layout),
        cmocka_unit_test(test_asc_vector_layout),
        cmocka_unit_test(test_asc_decimal),
        cmocka_unit_test(test_forced_format_refuses_another),
        cmocka_unit_test(test_bad_truncated),
        cmocka_unit_test(test_bad_hex),
        cmocka_unit_test(test_bad_length),
        cmocka_unit_test(test_bad_id),
        cmocka_unit_test(test_bad_time),
        cmocka_unit_test(test_bad_backwards),
        cmocka_unit_test(test_bad_empty),
        cmocka_unit_test(test_bad_binary),
        cmocka_unit_test(test_line_length_limit),
        cmocka_unit_test(test_streaming_large_file),
        cmocka_unit_test(test_writer),
        cmocka_unit_test(test_fd_lengths),
        cmocka_unit_test(test_same_frames_three_formats),
        cmocka_unit_test(test_drive_log_three_formats),
        cmocka_unit_test(test_lateness),
        cmocka_unit_test(test_shared_log_vectors),
        cmocka_unit_test(test_dropcount_and_raw_dlc),
        cmocka_unit_test(test_backwards_allowed),
    };
    return cmocka_run_group_tests_name("canlog", tests, make_dir, remove_dir);
}
