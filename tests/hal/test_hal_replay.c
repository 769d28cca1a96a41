/*
 * The replay backend (hal/replay): the HAL conformance suite on a bus with
 * no log, then what only this backend does: log frames at their times, the
 * record, and every kind of bad line. Runs on the host (ASan, UBSan) and on
 * the emulated Cortex-M4, where this backend is the one the firmware image
 * runs drives on.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "hal/replay/hal_replay.h"
#include "tests/hal/hal_conformance.h"

/* ------------------------------------------------------------------ streams */

typedef struct {
    const char *text;
    size_t len;
    size_t pos;
    uint32_t max_chunk;   /* bytes per read at most (0: as asked) */
    bool fail_at_end;     /* report a read error instead of the end */
} text_in_t;

static int32_t text_read(void *ctx, uint8_t *buf, uint32_t len)
{
    text_in_t *in = ctx;
    if (in->pos == in->len) {
        return in->fail_at_end ? -1 : 0;
    }
    size_t n = in->len - in->pos;
    if (n > len) {
        n = len;
    }
    if ((in->max_chunk != 0U) && (n > in->max_chunk)) {
        n = in->max_chunk;
    }
    memcpy(buf, &in->text[in->pos], n);
    in->pos += n;
    return (int32_t)n;
}

typedef struct {
    char buf[4096];
    size_t len;
    bool fail;
} text_out_t;

static int32_t text_write(void *ctx, const uint8_t *buf, uint32_t len)
{
    text_out_t *out = ctx;
    if (out->fail || ((out->len + len) >= sizeof out->buf)) {
        return -1;
    }
    memcpy(&out->buf[out->len], buf, len);
    out->len += len;
    out->buf[out->len] = '\0';
    return 0;
}

static hal_replay_bus_t g_bus;
static text_in_t g_in;
static text_out_t g_out;

static void start(const char *log, uint32_t max_chunk)
{
    memset(&g_in, 0, sizeof g_in);
    memset(&g_out, 0, sizeof g_out);
    g_in.text = log;
    g_in.len = strlen(log);
    g_in.max_chunk = max_chunk;
    hal_replay_init(&g_bus, text_read, &g_in, text_write, &g_out, NULL);
}

/* ------------------------------------------------------------------ conformance */

static int bus_open(void *ctx, hal_can_t **out)
{
    hal_can_t *h = hal_replay_open((hal_replay_bus_t *)ctx);
    if (h == NULL) {
        return HAL_ENOSPC;
    }
    *out = h;
    return 0;
}

static void bus_close(void *ctx, hal_can_t *can)
{
    (void)ctx;
    hal_replay_close(can);
}

static void bus_idle(void *ctx)
{
    hal_replay_bus_t *bus = ctx;
    hal_replay_advance_to(bus, hal_replay_now_us(bus) + 1000U);
}

/* ------------------------------------------------------------------ log frames */

static const char k_drive[] =
    "(1700000000.000000) vcan0 18FEF100#FF005AFFFFFFFFFF\n"
    "(1700000000.005000) vcan0 0CF01300#007D007DFFFFFCFF\n"
    "(1700000000.010000) vcan0 123#0102\n";

static void test_log_frames_arrive_at_their_time(void **state)
{
    (void)state;
    start(k_drive, 0U);
    hal_can_t *h = hal_replay_open(&g_bus);
    assert_non_null(h);
    uint64_t t = 0U;
    assert_true(hal_replay_next_us(&g_bus, &t));
    assert_int_equal(t, 1700000000000000ULL);
    assert_int_equal(hal_replay_now_us(&g_bus), 1700000000000000ULL);
    hal_replay_advance_to(&g_bus, 1700000000004999ULL);
    hal_can_rx_t rx;
    assert_int_equal(hal_can_receive(h, &rx), 0);
    assert_int_equal(rx.frame.id, 0x18FEF100UL | PFE_CAN_EFF_FLAG);
    assert_int_equal(rx.frame.dlc, 8);
    assert_int_equal(rx.frame.data[0], 0xFF);
    assert_int_equal(rx.frame.data[2], 0x5A);
    assert_int_equal(rx.timestamp_us, 1700000000000000ULL);
    assert_int_equal(hal_can_receive(h, &rx), HAL_EAGAIN);
    hal_replay_advance_to(&g_bus, 1700000000010000ULL);
    assert_int_equal(hal_can_receive(h, &rx), 0);
    assert_int_equal(rx.timestamp_us, 1700000000005000ULL);
    assert_int_equal(hal_can_receive(h, &rx), 0);
    assert_int_equal(rx.frame.id, 0x123U);
    assert_int_equal(rx.frame.dlc, 2);
    assert_int_equal(rx.frame.data[1], 0x02);
    assert_false(hal_replay_next_us(&g_bus, &t));
    assert_int_equal(hal_replay_stats(&g_bus)->frames, 3);
    assert_int_equal(hal_replay_stats(&g_bus)->lines, 3);
}

static void test_record_is_the_bus_in_candump_format(void **state)
{
    (void)state;
    start(k_drive, 0U);
    hal_can_t *h = hal_replay_open(&g_bus);
    hal_replay_advance_to(&g_bus, 1700000000007000ULL);
    const pfe_can_frame_t f = {0x18FEF28CUL | PFE_CAN_EFF_FLAG, 8U, {0xFF, 0xFF, 0x2A, 0x01, 0xFF, 0xFF, 0xFF, 0xFF}};
    assert_int_equal(hal_can_send(h, &f), 0);
    const pfe_can_frame_t empty = {0x7FFU, 0U, {0}};
    assert_int_equal(hal_can_send(h, &empty), 0);
    hal_replay_advance_to(&g_bus, 1700000000020000ULL);
    assert_int_equal(hal_replay_flush(&g_bus), 0);
    assert_string_equal(g_out.buf,
                        "(1700000000.000000) vcan0 18FEF100#FF005AFFFFFFFFFF\n"
                        "(1700000000.005000) vcan0 0CF01300#007D007DFFFFFCFF\n"
                        "(1700000000.007000) vcan0 18FEF28C#FFFF2A01FFFFFFFF\n"
                        "(1700000000.007000) vcan0 7FF#\n"
                        "(1700000000.010000) vcan0 123#0102\n");
    assert_int_equal(hal_replay_stats(&g_bus)->recorded, 5);
    assert_int_equal(hal_replay_stats(&g_bus)->sent_frames, 2);
}

static void test_one_byte_reads_give_the_same_record(void **state)
{
    (void)state;
    text_out_t whole;
    start(k_drive, 0U);
    hal_replay_advance_to(&g_bus, UINT64_MAX);
    assert_int_equal(hal_replay_flush(&g_bus), 0);
    whole = g_out;
    start(k_drive, 1U);
    hal_replay_advance_to(&g_bus, UINT64_MAX);
    assert_int_equal(hal_replay_flush(&g_bus), 0);
    assert_string_equal(g_out.buf, whole.buf);
}

static void test_nine_digits_lower_case_cr_and_empty_lines(void **state)
{
    (void)state;
    start("\n(12.345678999) can1 1abcdef0#0a0B\r\n\r\n(13.000000) can1 000# T\n", 0U);
    hal_can_t *h = hal_replay_open(&g_bus);
    hal_replay_advance_to(&g_bus, UINT64_MAX);
    hal_can_rx_t rx;
    assert_int_equal(hal_can_receive(h, &rx), 0);
    assert_int_equal(rx.timestamp_us, 12345678U);
    assert_int_equal(rx.frame.id, 0x1ABCDEF0UL | PFE_CAN_EFF_FLAG);
    assert_int_equal(rx.frame.dlc, 2);
    assert_int_equal(rx.frame.data[0], 0x0A);
    assert_int_equal(rx.frame.data[1], 0x0B);
    assert_int_equal(hal_can_receive(h, &rx), 0);
    assert_int_equal(rx.frame.id, 0U);
    assert_int_equal(rx.frame.dlc, 0);
    const hal_replay_stats_t *st = hal_replay_stats(&g_bus);
    assert_int_equal(st->lines, 4);
    assert_int_equal(st->frames, 2);
    assert_int_equal(st->bad_lines, 0);
    assert_int_equal(hal_replay_flush(&g_bus), 0);
    assert_string_equal(g_out.buf, "(12.345678) can1 1ABCDEF0#0A0B\n"
                                   "(13.000000) can1 000#\n");
}

static void test_fd_remote_and_error_frames_are_skipped_and_counted(void **state)
{
    (void)state;
    start("(1.000000) can0 123##1AABB\n"
          "(1.000000) can0 123#R\n"
          "(1.000000) can0 18FEF100#R8\n"
          "(1.000000) can0 20000080#0000000000000000\n"
          "(1.000000) can0 321#11\n",
          0U);
    hal_can_t *h = hal_replay_open(&g_bus);
    hal_replay_advance_to(&g_bus, UINT64_MAX);
    hal_can_rx_t rx;
    assert_int_equal(hal_can_receive(h, &rx), 0);
    assert_int_equal(rx.frame.id, 0x321U);
    assert_int_equal(hal_can_receive(h, &rx), HAL_EAGAIN);
    assert_int_equal(hal_replay_stats(&g_bus)->skipped_not_classic, 4);
    assert_int_equal(hal_replay_stats(&g_bus)->bad_lines, 0);
}

typedef struct {
    const char *line;
    hal_replay_reason_t why;
} bad_case_t;

static void test_each_bad_line_is_counted_with_its_reason(void **state)
{
    (void)state;
    static const bad_case_t cases[] = {
        {"garbage", HAL_REPLAY_BAD_SYNTAX},
        {"(1.000000)can0 123#11", HAL_REPLAY_BAD_SYNTAX},
        {"(1.000000) can0", HAL_REPLAY_BAD_SYNTAX},
        {"(1.000000) can0 123", HAL_REPLAY_BAD_SYNTAX},
        {"(1.000000) can0 1234 [1] 11", HAL_REPLAY_BAD_ID},
        {"(1.000000) can0 123 [9] 11 22 33 44 55 66 77 88 99", HAL_REPLAY_BAD_LENGTH},
        {"(1.000000) can0 123 [2] 11", HAL_REPLAY_BAD_DATA},
        {"(1.000000) can0 123 [1] 11 22", HAL_REPLAY_BAD_LENGTH},
        {"(1.000000) can0 123 [1] 1G", HAL_REPLAY_BAD_DATA},
        {"(1.000000) can0 123 [1] 11 extra", HAL_REPLAY_BAD_SYNTAX},
        {"(1.000000) can0 123 [100] 11", HAL_REPLAY_BAD_LENGTH},
        {"(1.000000) can0 123 [x] 11", HAL_REPLAY_BAD_SYNTAX},
        {"(2026-13-01 10:00:00.000000) can0 123 [1] 11", HAL_REPLAY_BAD_TIME},
        {"(1969-12-31 23:59:59.000000) can0 123 [1] 11", HAL_REPLAY_BAD_TIME},
        {"can0 123 [1] 11", HAL_REPLAY_BAD_NO_TIME},
        {"(1.5) can0 123#11", HAL_REPLAY_BAD_TIME},
        {"(x.000000) can0 123#11", HAL_REPLAY_BAD_TIME},
        {"(1.0000000) can0 123#11", HAL_REPLAY_BAD_TIME},
        {"(1234567890123.000000) can0 123#11", HAL_REPLAY_BAD_TIME},
        {"(1.000000) can0 1234#11", HAL_REPLAY_BAD_ID},
        {"(1.000000) can0 800#11", HAL_REPLAY_BAD_ID},
        {"(1.000000) can0 12G#11", HAL_REPLAY_BAD_ID},
        {"(1.000000) can0 E0000000#11", HAL_REPLAY_BAD_ID},
        {"(1.000000) can0 123#1G", HAL_REPLAY_BAD_DATA},
        {"(1.000000) can0 123#112", HAL_REPLAY_BAD_DATA},
        {"(1.000000) can0 123#11 extra", HAL_REPLAY_BAD_SYNTAX},
        {"(1.000000) can0 123#112233445566778899", HAL_REPLAY_BAD_LENGTH},
        {"(1.000000) a_name_too_long_for_linux 123#11", HAL_REPLAY_BAD_SYNTAX},
        {"(1.000000) can0 123#11\x01\x02", HAL_REPLAY_BAD_DATA},
    };
    for (size_t k = 0U; k < sizeof cases / sizeof cases[0]; k++) {
        char log[160];
        /* A good line, the bad one as line 2, a good one after it. */
        const int n = snprintf(log, sizeof log, "(1.000000) can0 100#01\n%s\n(2.000000) can0 101#02\n",
                               cases[k].line);
        ASSERT_GT(n, 0);
        ASSERT_LT((size_t)n, sizeof log);
        start(log, 0U);
        hal_can_t *h = hal_replay_open(&g_bus);
        hal_replay_advance_to(&g_bus, UINT64_MAX);
        const hal_replay_stats_t *st = hal_replay_stats(&g_bus);
        if ((st->bad_lines != 1U) || (st->first_bad_reason != cases[k].why)) {
            print_error("case %u '%s': %u bad lines, reason %d\n", (unsigned)k, cases[k].line,
                        (unsigned)st->bad_lines, (int)st->first_bad_reason);
        }
        assert_int_equal(st->bad_lines, 1);
        assert_int_equal(st->first_bad_line, 2);
        assert_int_equal(st->first_bad_reason, cases[k].why);
        assert_int_equal(st->frames, 2);
        hal_can_rx_t rx;
        assert_int_equal(hal_can_receive(h, &rx), 0);
        assert_int_equal(hal_can_receive(h, &rx), 0);
        assert_int_equal(rx.frame.id, 0x101U);
        assert_string_not_equal(hal_replay_reason_text(cases[k].why), "unknown");
    }
}

static void test_long_and_binary_lines_never_become_frames(void **state)
{
    (void)state;
    static char log[2048];
    memset(log, 0, sizeof log);
    /* A line of 500 characters, then 600 bytes of binary without a newline. */
    memset(log, '1', 500U);
    log[500] = '\n';
    for (size_t k = 0U; k < 600U; k++) {
        log[501U + k] = (char)(((k * 37U) % 255U) + 1U);
        if (log[501U + k] == '\n') {
            log[501U + k] = '\x7F';
        }
    }
    start(log, 7U);
    hal_replay_advance_to(&g_bus, UINT64_MAX);
    const hal_replay_stats_t *st = hal_replay_stats(&g_bus);
    assert_int_equal(st->frames, 0);
    assert_int_equal(st->lines, 2);
    assert_int_equal(st->bad_lines, 2);
    assert_int_equal(st->first_bad_line, 1);
    assert_int_equal(st->first_bad_reason, HAL_REPLAY_LINE_TOO_LONG);
    uint64_t t = 0U;
    assert_false(hal_replay_next_us(&g_bus, &t));
}

static void test_empty_log_has_no_frame(void **state)
{
    (void)state;
    start("", 0U);
    uint64_t t = 1U;
    assert_false(hal_replay_next_us(&g_bus, &t));
    assert_int_equal(hal_replay_now_us(&g_bus), 0);
    assert_int_equal(hal_replay_stats(&g_bus)->lines, 0);
}

static void test_time_going_backwards_is_delivered_at_once_and_counted(void **state)
{
    (void)state;
    start("(5.000000) can0 100#01\n(4.000000) can0 101#02\n(6.000000) can0 102#03\n", 0U);
    hal_can_t *h = hal_replay_open(&g_bus);
    hal_replay_advance_to(&g_bus, 5000000U);
    hal_can_rx_t rx;
    assert_int_equal(hal_can_receive(h, &rx), 0);
    assert_int_equal(hal_can_receive(h, &rx), 0);
    assert_int_equal(rx.frame.id, 0x101U);
    assert_int_equal(rx.timestamp_us, 5000000U);
    assert_int_equal(hal_can_receive(h, &rx), HAL_EAGAIN);
    assert_int_equal(hal_replay_stats(&g_bus)->time_backwards, 1);
    assert_int_equal(hal_replay_stats(&g_bus)->bad_lines, 0);
}

static void test_full_receive_queue_drops_and_counts(void **state)
{
    (void)state;
    static char log[40U * 140U];
    size_t n = 0U;
    for (uint32_t k = 0U; k < 140U; k++) {
        n += (size_t)snprintf(&log[n], sizeof log - n, "(1.000000) can0 %03X#00\n", (unsigned)k);
    }
    start(log, 0U);
    hal_can_t *h = hal_replay_open(&g_bus);
    hal_replay_advance_to(&g_bus, UINT64_MAX);
    hal_can_stats_t s;
    hal_can_get_stats(h, &s);
    assert_int_equal(s.rx_dropped, 140U - HAL_REPLAY_RX_QUEUE);
    hal_can_rx_t rx;
    uint32_t got = 0U;
    while (hal_can_receive(h, &rx) == 0) {
        assert_int_equal(rx.frame.id, got);
        got++;
    }
    assert_int_equal(got, HAL_REPLAY_RX_QUEUE);
}

static void test_failed_record_and_failed_read_are_reported(void **state)
{
    (void)state;
    start(k_drive, 0U);
    g_out.fail = true;
    g_in.fail_at_end = true;
    hal_replay_advance_to(&g_bus, UINT64_MAX);
    assert_int_equal(hal_replay_stats(&g_bus)->frames, 3);
    assert_true(hal_replay_stats(&g_bus)->read_failed);
    assert_int_equal(hal_replay_flush(&g_bus), HAL_EIO);
    assert_true(hal_replay_stats(&g_bus)->record_failed);
}

/* ------------------------------------------------------------------ shared vectors */

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

/* Each line of tests/replay/log_vectors.h alone, as sim_host/lib/log/ is
 * tested on it (tests/host/test_canlog.c). */
static void test_shared_log_vectors(void **state)
{
    (void)state;
    static char log[HAL_REPLAY_LINE_MAX + 2U];
    for (size_t k = 0U; k < sizeof k_vectors / sizeof k_vectors[0]; k++) {
        const log_vector_t *v = &k_vectors[k];
        const int n = snprintf(log, sizeof log, "%s\n", v->line);
        ASSERT_GT(n, 0);
        ASSERT_LT((size_t)n, sizeof log);
        start(log, 0U);
        hal_can_t *h = hal_replay_open(&g_bus);
        hal_replay_advance_to(&g_bus, UINT64_MAX);
        const hal_replay_stats_t *st = hal_replay_stats(&g_bus);
        const uint32_t frames = (v->kind == LV_FRAME) ? 1U : 0U;
        const uint32_t skipped = (v->kind == LV_SKIP) ? 1U : 0U;
        const uint32_t bad = ((v->kind == LV_BAD) || (v->kind == LV_NO_TIME)) ? 1U : 0U;
        if ((st->frames != frames) || (st->skipped_not_classic != skipped) ||
            (st->bad_lines != bad) || (st->lines != 1U)) {
            print_error("vector %u '%s': lines %u frames %u not classic %u bad %u (reason %d)\n",
                        (unsigned)k, v->line, (unsigned)st->lines, (unsigned)st->frames,
                        (unsigned)st->skipped_not_classic, (unsigned)st->bad_lines,
                        (int)st->first_bad_reason);
        }
        assert_int_equal(st->lines, 1U);
        assert_int_equal(st->frames, frames);
        assert_int_equal(st->skipped_not_classic, skipped);
        assert_int_equal(st->bad_lines, bad);
        if (v->kind == LV_NO_TIME) {
            assert_int_equal(st->first_bad_reason, HAL_REPLAY_BAD_NO_TIME);
        }
        hal_can_rx_t rx;
        if (v->kind != LV_FRAME) {
            assert_int_equal(hal_can_receive(h, &rx), HAL_EAGAIN);
            continue;
        }
        memset(&rx, 0xA5, sizeof rx);
        assert_int_equal(hal_can_receive(h, &rx), 0);
        if ((rx.timestamp_us != v->t_us) || (rx.frame.id != v->id) || (rx.frame.dlc != v->len)) {
            print_error("vector %u '%s': t %llu id %08lX dlc %u\n", (unsigned)k, v->line,
                        (unsigned long long)rx.timestamp_us, (unsigned long)rx.frame.id,
                        (unsigned)rx.frame.dlc);
        }
        assert_int_equal(rx.timestamp_us, v->t_us);
        assert_int_equal(rx.frame.id, v->id);
        assert_int_equal(rx.frame.dlc, v->len);
        for (uint8_t b = 0U; b < v->len; b++) {
            assert_int_equal(rx.frame.data[b], hex_byte(&v->hex[2U * b]));
        }
        assert_int_equal(hal_can_receive(h, &rx), HAL_EAGAIN);
    }
}

/* The printed form as a bench records it: the record is candump -L. */
static void test_printed_form_replays_as_the_log_form(void **state)
{
    (void)state;
    start("(000.000000)  can0  18FEF100   [8]  FF 12 34 56 78 9A BC DE\n"
          "\tcontroller-problem{rx-error-warning}\n"
          "(000.011063)  can0  0CF00400   [3]  F0 FF 7D\n"
          "(2026-12-01 10:00:00.123456)  can0  123   [0]\n",
          5U);
    hal_replay_advance_to(&g_bus, UINT64_MAX);
    assert_int_equal(hal_replay_flush(&g_bus), 0);
    assert_string_equal(g_out.buf, "(0.000000) can0 18FEF100#FF123456789ABCDE\n"
                                   "(0.011063) can0 0CF00400#F0FF7D\n"
                                   "(1796119200.123456) can0 123#\n");
    assert_int_equal(hal_replay_stats(&g_bus)->bad_lines, 0);
    assert_int_equal(hal_replay_stats(&g_bus)->lines, 4);
}

/* A frame source instead of text: the bus counts and delivers as for text. */
typedef struct {
    uint32_t n;
} fake_source_t;

static int32_t fake_source(void *ctx, pfe_can_frame_t *f, uint64_t *t_us,
                           char ifname[HAL_REPLAY_IFNAME_MAX + 1U], hal_replay_stats_t *stats)
{
    fake_source_t *src = ctx;
    if (src->n == 3U) {
        return 0;
    }
    stats->lines += 2U; /* a comment line before each frame */
    memset(f, 0, sizeof *f);
    f->id = 0x100U + src->n;
    f->dlc = 1U;
    f->data[0] = (uint8_t)src->n;
    *t_us = (src->n == 2U) ? 500U : (1000U * (src->n + 1U)); /* the third goes back */
    (void)snprintf(ifname, HAL_REPLAY_IFNAME_MAX + 1U, "slcan%u", (unsigned)src->n);
    src->n++;
    return 1;
}

static void test_frame_source_feeds_the_bus(void **state)
{
    (void)state;
    memset(&g_out, 0, sizeof g_out);
    fake_source_t src = {0U};
    hal_replay_init_source(&g_bus, fake_source, &src, text_write, &g_out, NULL);
    uint64_t t = 0U;
    assert_true(hal_replay_next_us(&g_bus, &t));
    assert_int_equal(t, 1000U);
    hal_replay_advance_to(&g_bus, UINT64_MAX);
    assert_int_equal(hal_replay_flush(&g_bus), 0);
    assert_string_equal(g_out.buf, "(0.001000) slcan0 100#00\n"
                                   "(0.002000) slcan0 101#01\n"
                                   "(0.002000) slcan0 102#02\n");
    const hal_replay_stats_t *st = hal_replay_stats(&g_bus);
    assert_int_equal(st->frames, 3);
    assert_int_equal(st->lines, 6);
    assert_int_equal(st->time_backwards, 1);
}

static void test_nvm_starts_erased_and_keeps_writes(void **state)
{
    (void)state;
    hal_nvm_t nvm;
    hal_replay_nvm_init(&nvm);
    uint8_t buf[PFE_NVM_RECORD_SIZE];
    assert_int_equal(hal_nvm_read(&nvm, 1U, buf), 0);
    assert_int_equal(buf[0], 0xFF);
    assert_int_equal(buf[PFE_NVM_RECORD_SIZE - 1U], 0xFF);
    memset(buf, 0x5A, sizeof buf);
    assert_int_equal(hal_nvm_write(&nvm, 1U, buf), 0);
    memset(buf, 0, sizeof buf);
    assert_int_equal(hal_nvm_read(&nvm, 1U, buf), 0);
    assert_int_equal(buf[PFE_NVM_RECORD_SIZE - 1U], 0x5A);
    assert_int_equal(hal_nvm_read(&nvm, PFE_NVM_SLOTS, buf), HAL_EINVAL);
    assert_int_equal(hal_nvm_write(&nvm, PFE_NVM_SLOTS, buf), HAL_EINVAL);
}

int main(void)
{
    hal_replay_init(&g_bus, NULL, NULL, NULL, NULL, NULL);
    const hal_conformance_backend_t backend = {"hal_replay", &g_bus, bus_open, bus_close, bus_idle,
                                               0U, hal_replay_time(&g_bus)};
    int failed = hal_conformance_run(&backend);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_log_frames_arrive_at_their_time),
        cmocka_unit_test(test_record_is_the_bus_in_candump_format),
        cmocka_unit_test(test_one_byte_reads_give_the_same_record),
        cmocka_unit_test(test_nine_digits_lower_case_cr_and_empty_lines),
        cmocka_unit_test(test_fd_remote_and_error_frames_are_skipped_and_counted),
        cmocka_unit_test(test_each_bad_line_is_counted_with_its_reason),
        cmocka_unit_test(test_long_and_binary_lines_never_become_frames),
        cmocka_unit_test(test_empty_log_has_no_frame),
        cmocka_unit_test(test_time_going_backwards_is_delivered_at_once_and_counted),
        cmocka_unit_test(test_full_receive_queue_drops_and_counts),
        cmocka_unit_test(test_failed_record_and_failed_read_are_reported),
        cmocka_unit_test(test_nvm_starts_erased_and_keeps_writes),
        cmocka_unit_test(test_shared_log_vectors),
        cmocka_unit_test(test_printed_form_replays_as_the_log_form),
        cmocka_unit_test(test_frame_source_feeds_the_bus),
    };
    failed += cmocka_run_group_tests_name("hal_replay backend", tests, NULL, NULL);
    return failed;
}
