/*
 * fuzz_replay.c - libFuzzer target: the replay bus's candump parser
 * (hal/replay/hal_replay.h), fed through its read callback.
 *
 * Input: byte 0: bytes per read (1 + b0); byte 1: bit 7 the read fails
 * (returns -1) once (b1 & 0x7F) * 32 bytes were read, bit 6 every record
 * write fails, bits 0-5 a frame sent by a second node every that many log
 * frames (0: never); byte 2: the clock's step in ms (0: from log frame to
 * log frame; a gap of more than 64 steps is crossed in
 * one, to its last step); the rest is the log.
 *
 * Invariants (abort on failure): the replay ends; every frame received is a
 * valid classic frame, in time order; lines are counted as the input has
 * them, each one a frame, skipped, bad or empty; the first bad line is
 * named when there is one; a read error is reported; the record, read
 * back by a second bus, gives the same frames at the same times, with no
 * bad or skipped line; a failing record is reported by hal_replay_flush().
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "fuzz_check.h"
#include "hal/hal_can_mem.h"
#include "hal/replay/hal_replay.h"

#define MAX_RX 4096U
#define RECORD_MAX (1U << 20)

typedef struct {
    const uint8_t *p;
    uint32_t n;
    uint32_t pos;
    uint32_t chunk;
    bool fail;
    uint32_t fail_at;
} src_t;

typedef struct {
    uint8_t *buf;
    uint32_t len;
    bool fail;
} sink_t;

static hal_replay_bus_t g_bus, g_back;
static hal_can_rx_t g_rx[MAX_RX];
static uint8_t g_record[RECORD_MAX];

static int32_t src_read(void *ctx, uint8_t *buf, uint32_t len)
{
    src_t *s = ctx;
    if (s->fail && (s->pos >= s->fail_at)) {
        return -1;
    }
    uint32_t n = s->n - s->pos;
    n = (n < len) ? n : len;
    n = (n < s->chunk) ? n : s->chunk;
    memcpy(buf, s->p + s->pos, n);
    s->pos += n;
    return (int32_t)n;
}

static int32_t sink_write(void *ctx, const uint8_t *buf, uint32_t len)
{
    sink_t *s = ctx;
    if (s->fail) {
        return -1;
    }
    FUZZ_CHECK((s->len + len) <= RECORD_MAX);
    memcpy(s->buf + s->len, buf, len);
    s->len += len;
    return 0;
}

/* Drains a handle into g_rx from *n on; checks each frame. */
static void drain(hal_can_t *h, uint32_t *n, uint64_t now_us)
{
    hal_can_rx_t rx;
    while (hal_can_receive(h, &rx) == 0) {
        FUZZ_CHECK(hal_can_mem_frame_valid(&rx.frame));
        FUZZ_CHECK(rx.timestamp_us <= now_us);
        FUZZ_CHECK((*n == 0U) || (rx.timestamp_us >= g_rx[*n - 1U].timestamp_us));
        if (*n < MAX_RX) {
            g_rx[*n] = rx;
        }
        (*n)++;
    }
}

static bool same(const hal_can_rx_t *a, const hal_can_rx_t *b)
{
    return (a->timestamp_us == b->timestamp_us) && (a->frame.id == b->frame.id) &&
           (a->frame.dlc == b->frame.dlc) && (memcmp(a->frame.data, b->frame.data, a->frame.dlc) == 0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 3U) {
        return 0;
    }
    const uint8_t b1 = data[1];
    src_t src = {data + 3, (uint32_t)(size - 3U), 0U, 1U + (uint32_t)data[0], (b1 & 0x80U) != 0U,
                 (uint32_t)(b1 & 0x7FU) * 32U};
    sink_t sink = {g_record, 0U, (b1 & 0x40U) != 0U};
    const uint32_t send_every = b1 & 0x3FU;
    const uint64_t step_us = (uint64_t)data[2] * 1000U;

    hal_replay_bus_t *bus = &g_bus;
    hal_replay_init(bus, src_read, &src, sink_write, &sink, NULL);
    hal_can_t *a = hal_replay_open(bus);
    hal_can_t *b = hal_replay_open(bus);
    FUZZ_CHECK((a != NULL) && (b != NULL));
    FUZZ_CHECK(hal_replay_open(bus) == NULL);
    uint32_t n = 0U;
    uint32_t delivered = 0U;
    uint64_t t = 0U;
    uint32_t rounds = 0U;
    while (hal_replay_next_us(bus, &t)) {
        rounds++;
        FUZZ_CHECK(rounds <= 70U * ((uint32_t)size + 1U));
        const uint64_t now = hal_replay_now_us(bus);
        uint64_t to = (step_us == 0U) ? t : ((now + step_us < t) ? (now + step_us) : t);
        if ((step_us != 0U) && ((t - now) > (64U * step_us))) {
            to = t - step_us; /* a long gap: close to its end in one step */
        }
        const uint32_t before = hal_replay_stats(bus)->frames;
        hal_replay_advance_to(bus, to);
        FUZZ_CHECK(hal_replay_now_us(bus) >= now);
        const uint32_t after = hal_replay_stats(bus)->frames;
        FUZZ_CHECK((to < t) ? (after == before) : (after > before));
        delivered += after - before;
        if ((send_every != 0U) && ((after / send_every) != (before / send_every))) {
            const pfe_can_frame_t f = {0x98FEF2AAUL, 8U, {1U, 2U, 3U, 4U, 5U, 6U, 7U, (uint8_t)after}};
            FUZZ_CHECK(hal_can_send(b, &f) == 0);
            delivered++;
        }
        drain(a, &n, hal_replay_now_us(bus));
        hal_can_rx_t junk;
        while (hal_can_receive(b, &junk) == 0) {
        }
    }
    const hal_replay_stats_t *st = hal_replay_stats(bus);
    const int flushed = hal_replay_flush(bus);
    FUZZ_CHECK((flushed == 0) == !st->record_failed);
    FUZZ_CHECK(!sink.fail || (st->recorded == 0U) || st->record_failed);
    FUZZ_CHECK(st->read_failed == (src.fail && (src.fail_at <= src.n)));

    /* Lines as the input has them, up to where it could be read. */
    const uint32_t read_bytes = src.pos;
    uint32_t lines = 0U;
    for (uint32_t k = 0U; k < read_bytes; k++) {
        lines += (src.p[k] == '\n') ? 1U : 0U;
    }
    lines += ((read_bytes > 0U) && (src.p[read_bytes - 1U] != '\n')) ? 1U : 0U;
    FUZZ_CHECK(st->lines == lines);
    FUZZ_CHECK(((uint64_t)st->frames + st->skipped_not_classic + st->bad_lines) <= st->lines);
    FUZZ_CHECK((st->bad_lines == 0U) == (st->first_bad_line == 0U));
    FUZZ_CHECK(st->first_bad_line <= st->lines);
    FUZZ_CHECK(strcmp(hal_replay_reason_text(st->first_bad_reason), "unknown") != 0);
    FUZZ_CHECK(st->sent_frames + st->frames == delivered);

    hal_can_stats_t sa;
    hal_can_get_stats(a, &sa);
    FUZZ_CHECK(n + sa.rx_dropped == delivered);
    if (sink.fail || (sa.rx_dropped != 0U) || (n > MAX_RX)) {
        return 0;
    }
    /* The record read back: the same frames at the same times. */
    FUZZ_CHECK(st->recorded == delivered);
    src_t back = {g_record, sink.len, 0U, HAL_REPLAY_IN_CHUNK, false, 0U};
    hal_replay_init(&g_back, src_read, &back, NULL, NULL, NULL);
    hal_can_t *c = hal_replay_open(&g_back);
    FUZZ_CHECK(c != NULL);
    uint32_t m = 0U;
    while (hal_replay_next_us(&g_back, &t)) {
        hal_replay_advance_to(&g_back, t);
        hal_can_rx_t rx;
        while (hal_can_receive(c, &rx) == 0) {
            FUZZ_CHECK(m < n);
            if (!same(&rx, &g_rx[m])) {
                fprintf(stderr, "record frame %u differs\n", m);
            }
            FUZZ_CHECK(same(&rx, &g_rx[m]));
            m++;
        }
    }
    const hal_replay_stats_t *bs = hal_replay_stats(&g_back);
    FUZZ_CHECK(m == n);
    FUZZ_CHECK(bs->bad_lines == 0U);
    FUZZ_CHECK(bs->skipped_not_classic == 0U);
    FUZZ_CHECK(bs->time_backwards == 0U);
    return 0;
}
