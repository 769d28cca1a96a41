/*
 * fuzz_canlog.c - libFuzzer target: the CAN log reader of the host tools
 * (sim_host/lib/log/log.h): candump log, candump's printed output, Vector ASC.
 *
 * Input: byte 0 chooses the format asked for (bits 0-2: auto, log, printed,
 * printed-delta, asc; others auto) and the error mode (bit 3: skip, else
 * stop); the rest is the file.
 *
 * Invariants (abort on failure): the reader ends (each call consumes a
 * line, so there are at most lines + 2 calls) with end of file or, in stop
 * mode, errors it can go on from; every error has a message naming the
 * file; every frame is well formed (id within its width, length within
 * classic or CAN FD lengths, interface name terminated), lines and time
 * never go backwards; written back as a candump log line and read again,
 * a frame is the same; a second pass after canlog_rewind() gives the same
 * frames.
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "lib/log/log.h"
#include "fuzz_check.h"

static canlog_reader_t g_reader;  /* about 100 KiB each: not on the stack */
static canlog_reader_t g_back;

static void check_frame(const canlog_frame_t *f)
{
    FUZZ_CHECK(memchr(f->iface, '\0', sizeof f->iface) != NULL);
    if ((f->id & CANLOG_ERR_FLAG) != 0U) {
        FUZZ_CHECK((f->id & ~(CANLOG_EFF_MASK | CANLOG_ERR_FLAG | CANLOG_EFF_FLAG | CANLOG_RTR_FLAG)) == 0U);
    } else if ((f->id & CANLOG_EFF_FLAG) != 0U) {
        FUZZ_CHECK((f->id & ~(CANLOG_EFF_MASK | CANLOG_EFF_FLAG | CANLOG_RTR_FLAG)) == 0U);
    } else {
        FUZZ_CHECK((f->id & ~(CANLOG_SFF_MASK | CANLOG_RTR_FLAG)) == 0U);
    }
    if (f->fd) {
        FUZZ_CHECK(f->len <= CANLOG_FD_MAX_DLEN);
        FUZZ_CHECK(canlog_fd_dlc_to_len(canlog_fd_len_to_dlc(f->len)) == f->len);
        FUZZ_CHECK((f->id & CANLOG_RTR_FLAG) == 0U);
    } else {
        FUZZ_CHECK(f->len <= CANLOG_MAX_DLEN);
        FUZZ_CHECK(f->fd_flags == 0U);
    }
}

/* The frame written as a candump log line reads back the same. */
static void check_round_trip(const canlog_frame_t *f)
{
    char line[CANLOG_LOG_LINE_MAX];
    const size_t n = canlog_write_log(line, sizeof line, f, (f->iface[0] != '\0') ? NULL : "can0");
    if (n == 0U) {
        /* Only an interface name it cannot write (empty or too long) fails. */
        FUZZ_CHECK(f->iface[0] != '\0');
        return;
    }
    FUZZ_CHECK(n < sizeof line);
    FUZZ_CHECK(canlog_open_mem(&g_back, line, n, "back.log", CANLOG_FMT_LOG, CANLOG_ON_ERROR_STOP) == 0);
    canlog_frame_t b;
    const int rc = canlog_next(&g_back, &b);
    if (rc != 1) {
        fprintf(stderr, "written: %s", line);
        fprintf(stderr, "read back: %d %s\n", rc, canlog_message(&g_back));
    }
    FUZZ_CHECK(rc == 1);
    FUZZ_CHECK(b.time_us == f->time_us);
    FUZZ_CHECK(b.id == f->id);
    FUZZ_CHECK(b.len == f->len);
    FUZZ_CHECK(b.fd == f->fd);
    FUZZ_CHECK(b.fd_flags == f->fd_flags);
    if (!(f->id & CANLOG_RTR_FLAG) || f->fd) {
        FUZZ_CHECK(memcmp(b.data, f->data, f->len) == 0);
    }
    FUZZ_CHECK(canlog_next(&g_back, &b) == 0);
}

/* One pass: returns a digest of the frames read and their count. */
static uint64_t pass(canlog_reader_t *r, size_t size, bool stop_mode, uint64_t *frames, bool checks)
{
    uint64_t digest = 1469598103934665603ULL; /* FNV-1a */
    uint64_t calls = 0U;
    uint64_t last_line = 0U;
    uint64_t last_time = 0U;
    *frames = 0U;
    for (;;) {
        canlog_frame_t f;
        const int rc = canlog_next(r, &f);
        calls++;
        FUZZ_CHECK(calls <= (uint64_t)size + 2U);
        if (rc == 0) {
            break;
        }
        if (rc < 0) {
            FUZZ_CHECK(rc > -(int)CANLOG_REASON_COUNT);
            FUZZ_CHECK(strncmp(canlog_message(r), "fuzz.log", 8U) == 0);
            FUZZ_CHECK(stop_mode || (rc == -(int)CANLOG_E_EMPTY) || (rc == -(int)CANLOG_E_IO));
            if ((rc == -(int)CANLOG_E_EMPTY) || (rc == -(int)CANLOG_E_IO)) {
                break;
            }
            continue;
        }
        FUZZ_CHECK(rc == 1);
        if (checks) {
            check_frame(&f);
            FUZZ_CHECK(f.line > last_line);
            FUZZ_CHECK((*frames == 0U) || (f.time_us >= last_time));
            check_round_trip(&f);
        }
        last_line = f.line;
        last_time = f.time_us;
        const uint64_t fields[5] = {f.time_us, f.line, f.id, ((uint64_t)f.len << 8) | f.fd_flags,
                                    ((uint64_t)f.fd << 8) | (uint8_t)f.dir};
        const uint8_t *bytes[3] = {(const uint8_t *)fields, f.data, (const uint8_t *)f.iface};
        /* A remote frame's data bytes are not written (lib/log/log.h). */
        const bool remote = ((f.id & CANLOG_RTR_FLAG) != 0U) && !f.fd;
        const size_t lens[3] = {sizeof fields, remote ? 0U : f.len, strlen(f.iface)};
        for (uint32_t k = 0U; k < 3U; k++) {
            for (size_t i = 0U; i < lens[k]; i++) {
                digest = (digest ^ bytes[k][i]) * 1099511628211ULL;
            }
        }
        (*frames)++;
    }
    return digest;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1U) {
        return 0;
    }
    static const canlog_format_t formats[8] = {CANLOG_FMT_AUTO, CANLOG_FMT_LOG, CANLOG_FMT_PRINTED,
                                               CANLOG_FMT_PRINTED_DELTA, CANLOG_FMT_ASC,
                                               CANLOG_FMT_AUTO, CANLOG_FMT_AUTO, CANLOG_FMT_AUTO};
    const canlog_format_t fmt = formats[data[0] & 7U];
    const bool skip = (data[0] & 8U) != 0U;
    const char *text = (const char *)data + 1;
    const size_t len = size - 1U;
    canlog_reader_t *r = &g_reader;
    FUZZ_CHECK(canlog_open_mem(r, text, len, "fuzz.log", fmt,
                               skip ? CANLOG_ON_ERROR_SKIP : CANLOG_ON_ERROR_STOP) == 0);
    uint64_t n1 = 0U, n2 = 0U;
    const uint64_t d1 = pass(r, len, !skip, &n1, true);
    const canlog_format_t detected = canlog_format(r);
    FUZZ_CHECK((n1 == 0U) || (detected != CANLOG_FMT_AUTO));
    FUZZ_CHECK(r->frames == n1);
    FUZZ_CHECK(canlog_rewind(r) == 0);
    const uint64_t d2 = pass(r, len, !skip, &n2, false);
    FUZZ_CHECK(n2 == n1);
    FUZZ_CHECK(d2 == d1);
    return 0;
}
