/*
 * fuzz_capture.c - libFuzzer target: the capture reader of the judge and
 * the checkers (sim_host/lib/capture.h), through capture_load() on a file.
 *
 * Input: the file (held in a memfd, read through its /proc/self/fd path).
 *
 * Invariants (abort on failure): it loads or fails with a message that
 * names the file; loaded, every record is a classic J1939 frame (29-bit id,
 * at most 8 bytes, unused bytes zero) in time order with increasing line
 * numbers, and the counts add up (records and skipped frames at most the
 * lines read); a failure leaves the capture empty; each record's frame, as
 * a line capture_parse_line() reads, is the same frame.
 */
#define _GNU_SOURCE

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include "lib/capture.h"
#include "fuzz_check.h"

static int g_fd = -1;
static char g_path[64];

static void check_record(const capture_rec_t *r)
{
    FUZZ_CHECK((r->f.id & PFE_CAN_EFF_FLAG) != 0U);
    FUZZ_CHECK((r->f.id & ~(PFE_CAN_EFF_FLAG | PFE_CAN_ID_MASK)) == 0U);
    FUZZ_CHECK(r->f.dlc <= PFE_CAN_MAX_DLC);
    for (uint32_t k = r->f.dlc; k < PFE_CAN_MAX_DLC; k++) {
        FUZZ_CHECK(r->f.data[k] == 0U);
    }
    /* The same frame written as a candump -L line parses back to it. */
    char line[96];
    int n = snprintf(line, sizeof line, "(%llu.%06llu) can0 %08lX#",
                     (unsigned long long)(r->t_us / 1000000U), (unsigned long long)(r->t_us % 1000000U),
                     (unsigned long)(r->f.id & PFE_CAN_ID_MASK));
    for (uint32_t k = 0U; k < r->f.dlc; k++) {
        n += snprintf(line + n, sizeof line - (size_t)n, "%02X", r->f.data[k]);
    }
    capture_line_t l;
    char why[160];
    const int kind = capture_parse_line(line, &l, NULL, why, sizeof why);
    if (kind != CAPTURE_LINE_FRAME) {
        fprintf(stderr, "%s: %s\n", line, why);
    }
    FUZZ_CHECK(kind == CAPTURE_LINE_FRAME);
    FUZZ_CHECK(l.kind == CAPTURE_CLASSIC);
    FUZZ_CHECK(l.extended);
    FUZZ_CHECK(l.t_us == r->t_us);
    FUZZ_CHECK((l.id | PFE_CAN_EFF_FLAG) == r->f.id);
    FUZZ_CHECK(l.len == r->f.dlc);
    FUZZ_CHECK(memcmp(l.data, r->f.data, l.len) == 0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (g_fd < 0) {
        g_fd = memfd_create("fuzz_capture", 0U);
        FUZZ_CHECK(g_fd >= 0);
        snprintf(g_path, sizeof g_path, "/proc/self/fd/%d", g_fd);
    }
    FUZZ_CHECK(ftruncate(g_fd, 0) == 0);
    FUZZ_CHECK(pwrite(g_fd, data, size, 0) == (ssize_t)size);

    capture_t cap;
    char err[512];
    err[0] = '\0';
    const int rc = capture_load(g_path, &cap, err, sizeof err);
    if (rc != 0) {
        FUZZ_CHECK(rc == -1);
        FUZZ_CHECK(strncmp(err, g_path, strlen(g_path)) == 0);
        FUZZ_CHECK((cap.recs == NULL) && (cap.n == 0U));
        return 0;
    }
    FUZZ_CHECK(cap.n + cap.skipped_standard + cap.skipped_remote + cap.skipped_fd +
                   cap.skipped_error <= cap.lines);
    FUZZ_CHECK((cap.n + cap.skipped_standard + cap.skipped_remote + cap.skipped_fd +
                cap.skipped_error) > 0U);
    for (size_t k = 0U; k < cap.n; k++) {
        check_record(&cap.recs[k]);
        FUZZ_CHECK(cap.recs[k].line <= cap.lines);
        if (k > 0U) {
            FUZZ_CHECK(cap.recs[k].t_us >= cap.recs[k - 1U].t_us);
            FUZZ_CHECK(cap.recs[k].line > cap.recs[k - 1U].line);
        }
    }
    capture_free(&cap);
    FUZZ_CHECK((cap.recs == NULL) && (cap.n == 0U));
    return 0;
}
