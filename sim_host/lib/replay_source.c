/* replay_source.c - a canlog reader as a replay bus's frame source (contract in replay_source.h). */
#define _POSIX_C_SOURCE 200809L
#include "lib/replay_source.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int replay_source_open(replay_source_t *src, const char *path, canlog_format_t format, char *err,
                       size_t err_len)
{
    src->fd = -1;
    src->any_bad = false;
    src->first_bad[0] = '\0';
    const int fd = open(path, O_RDONLY);
    if (fd < 0) {
        (void)snprintf(err, err_len, "%s: %s", path, strerror(errno));
        return -1;
    }
    struct stat st;
    if (fstat(fd, &st) != 0) {
        (void)snprintf(err, err_len, "%s: %s", path, strerror(errno));
        (void)close(fd);
        return -1;
    }
    if (S_ISDIR(st.st_mode)) {
        (void)snprintf(err, err_len, "%s: is a directory, not a CAN log", path);
        (void)close(fd);
        return -1;
    }
    (void)canlog_open_fd(&src->reader, fd, path, format, CANLOG_ON_ERROR_STOP);
    canlog_allow_backwards(&src->reader, true);
    src->fd = fd;
    return 0;
}

static hal_replay_reason_t reason_of(int canlog_reason)
{
    switch (canlog_reason) {
    case CANLOG_E_LINE_TOO_LONG:
        return HAL_REPLAY_LINE_TOO_LONG;
    case CANLOG_E_BAD_TIME:
        return HAL_REPLAY_BAD_TIME;
    case CANLOG_E_BAD_ID:
        return HAL_REPLAY_BAD_ID;
    case CANLOG_E_BAD_HEX:
    case CANLOG_E_TRUNCATED:
        return HAL_REPLAY_BAD_DATA;
    case CANLOG_E_DLC:
        return HAL_REPLAY_BAD_LENGTH;
    case CANLOG_E_SYNTAX:
    case CANLOG_E_FORMAT:
        return HAL_REPLAY_BAD_SYNTAX;
    default:
        return HAL_REPLAY_BAD_OTHER;
    }
}

static void bad_line(replay_source_t *src, hal_replay_stats_t *stats, hal_replay_reason_t why,
                     const char *msg)
{
    stats->bad_lines++;
    if (!src->any_bad) {
        src->any_bad = true;
        stats->first_bad_line = (uint32_t)src->reader.line_no;
        stats->first_bad_reason = why;
        (void)snprintf(src->first_bad, sizeof src->first_bad, "%s", msg);
    }
}

int32_t replay_source_next(void *ctx, pfe_can_frame_t *f, uint64_t *t_us,
                           char ifname[HAL_REPLAY_IFNAME_MAX + 1U], hal_replay_stats_t *stats)
{
    replay_source_t *src = ctx;
    canlog_reader_t *r = &src->reader;
    for (;;) {
        canlog_frame_t cf;
        const int rc = canlog_next(r, &cf);
        stats->lines = (uint32_t)r->lines;
        if (rc == 0) {
            return 0;
        }
        if (rc == -(int)CANLOG_E_EMPTY) {
            return 0;
        }
        if (rc == -(int)CANLOG_E_IO) {
            stats->read_failed = true;
            return 0;
        }
        if (rc < 0) {
            bad_line(src, stats, reason_of(-rc), canlog_message(r));
            continue;
        }
        if (canlog_time_base(r) == CANLOG_TB_NONE) {
            char msg[CANLOG_MSG_MAX];
            (void)snprintf(msg, sizeof msg, "%.200s:%llu: no timestamp: candump output needs "
                           "-t a, z, d or A to be replayed", r->name,
                           (unsigned long long)r->line_no);
            bad_line(src, stats, HAL_REPLAY_BAD_NO_TIME, msg);
            continue;
        }
        if (cf.fd || ((cf.id & (CANLOG_RTR_FLAG | CANLOG_ERR_FLAG)) != 0U)) {
            stats->skipped_not_classic++;
            continue;
        }
        (void)memset(f, 0, sizeof *f);
        f->id = cf.id; /* CANLOG_EFF_FLAG is PFE_CAN_EFF_FLAG */
        f->dlc = cf.len;
        (void)memcpy(f->data, cf.data, cf.len);
        *t_us = cf.time_us;
        (void)snprintf(ifname, HAL_REPLAY_IFNAME_MAX + 1U, "%s", cf.iface);
        return 1;
    }
}

const char *replay_source_first_bad(const replay_source_t *src)
{
    return src->first_bad;
}

const char *replay_source_message(const replay_source_t *src)
{
    return canlog_message(&src->reader);
}

void replay_source_close(replay_source_t *src)
{
    if (src->fd >= 0) {
        (void)close(src->fd);
        src->fd = -1;
    }
}
