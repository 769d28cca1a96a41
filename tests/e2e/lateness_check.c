/*
 * lateness_check - how late a replay's frames reached the bus, from what a
 * receiver recorded: the same measure for pfe_replay and for canplayer.
 *
 *   lateness_check SCHEDULE CAPTURE
 *
 * SCHEDULE is the log that was replayed, CAPTURE what `candump -L` recorded
 * on the receiving side (kernel receive timestamps), both read with
 * sim_host/lib/log/log.h. The two must hold the same frames in the same order
 * (id, length, data, FD flags; interfaces and timestamps aside), else the
 * first difference is reported and the exit status is 1.
 *
 * Lateness of frame k: (rx_k - s_k) - min over all frames j of (rx_j - s_j),
 * rx the receive time, s the log time: how much later than the best-placed
 * frame, relative to the schedule, it arrived. A replayer that sends no
 * frame early has its best frame at about its own latency, so this is its
 * lateness against its deadlines plus the receive path's jitter. Printed:
 *   lateness p50 P us p99 Q us max M us (N frames)
 * Exit status: 0; 1 frames differ or a log does not read; 2 usage.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lib/log/log.h"
#include "lib/lateness.h"

static int open_log(canlog_reader_t *r, const char *path)
{
    const int fd = open(path, O_RDONLY);
    if (fd < 0) {
        fprintf(stderr, "lateness_check: cannot open %s: %s\n", path, strerror(errno));
        return -1;
    }
    (void)canlog_open_fd(r, fd, path, CANLOG_FMT_AUTO, CANLOG_ON_ERROR_STOP);
    return 0;
}

static int same_frame(const canlog_frame_t *a, const canlog_frame_t *b)
{
    if ((a->id != b->id) || (a->len != b->len) || (a->fd != b->fd) ||
        (a->fd_flags != b->fd_flags)) {
        return 0;
    }
    if ((a->id & CANLOG_RTR_FLAG) != 0U) {
        return 1;
    }
    return memcmp(a->data, b->data, a->len) == 0;
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: lateness_check SCHEDULE CAPTURE\n");
        return 2;
    }
    static canlog_reader_t sched;
    static canlog_reader_t cap;
    static lateness_hist_t hist;
    if ((open_log(&sched, argv[1]) != 0) || (open_log(&cap, argv[2]) != 0)) {
        return 1;
    }
    /* First pass: compare, and find the smallest offset. */
    int64_t min_off = INT64_MAX;
    uint64_t n = 0U;
    canlog_frame_t a;
    canlog_frame_t b;
    for (;;) {
        const int ra = canlog_next(&sched, &a);
        const int rb = canlog_next(&cap, &b);
        if ((ra < 0) || (rb < 0)) {
            fprintf(stderr, "lateness_check: %s\n", canlog_message((ra < 0) ? &sched : &cap));
            return 1;
        }
        if ((ra == 0) || (rb == 0)) {
            if (ra != rb) {
                fprintf(stderr, "lateness_check: %s has %s frames than %s (%llu in common)\n",
                        argv[2], (ra == 0) ? "more" : "fewer", argv[1], (unsigned long long)n);
                return 1;
            }
            break;
        }
        if (!same_frame(&a, &b)) {
            char la[CANLOG_LOG_LINE_MAX];
            char lb[CANLOG_LOG_LINE_MAX];
            (void)canlog_write_log(la, sizeof la, &a, NULL);
            (void)canlog_write_log(lb, sizeof lb, &b, NULL);
            fprintf(stderr, "lateness_check: frame %llu differs:\n  %s:%llu: %s  %s:%llu: %s",
                    (unsigned long long)n + 1U, argv[1], (unsigned long long)a.line, la, argv[2],
                    (unsigned long long)b.line, lb);
            return 1;
        }
        const int64_t off = (int64_t)b.time_us - (int64_t)a.time_us;
        if (off < min_off) {
            min_off = off;
        }
        n++;
    }
    if (n == 0U) {
        fprintf(stderr, "lateness_check: no frames\n");
        return 1;
    }
    /* Second pass: the histogram. */
    lateness_init(&hist);
    if ((canlog_rewind(&sched) != 0) || (canlog_rewind(&cap) != 0)) {
        fprintf(stderr, "lateness_check: cannot read the logs twice\n");
        return 1;
    }
    while ((canlog_next(&sched, &a) == 1) && (canlog_next(&cap, &b) == 1)) {
        const int64_t off = (int64_t)b.time_us - (int64_t)a.time_us;
        lateness_add(&hist, (uint64_t)(off - min_off));
    }
    printf("lateness p50 %llu us p99 %llu us max %llu us (%llu frames)\n",
           (unsigned long long)lateness_percentile_us(&hist, 500U),
           (unsigned long long)lateness_percentile_us(&hist, 990U),
           (unsigned long long)hist.max_us, (unsigned long long)hist.count);
    return 0;
}
