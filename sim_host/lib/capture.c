/* capture.c - recorded CAN buses, read through sim_host/lib/log/ (contract in capture.h). */
#include "lib/capture.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "lib/log/log.h"

#define LINE_NAME "line"   /* the name canlog gives a single line, cut from its messages */

static int fail(char *why, size_t why_len, const char *fmt, ...)
{
    if ((why != NULL) && (why_len > 0U)) {
        va_list ap;
        va_start(ap, fmt);
        (void)vsnprintf(why, why_len, fmt, ap);
        va_end(ap);
    }
    return -1;
}

/* A canlog frame as a capture line. */
static void from_canlog(const canlog_frame_t *f, capture_line_t *out)
{
    memset(out, 0, sizeof *out);
    out->t_us = f->time_us;
    (void)snprintf(out->iface, sizeof out->iface, "%s", f->iface);
    out->len = f->len;
    out->len8_dlc = f->len8_dlc;
    if ((f->id & CANLOG_ERR_FLAG) != 0U) {
        out->kind = CAPTURE_ERROR;
        out->extended = true;
        out->id = f->id & CANLOG_EFF_MASK;
    } else {
        out->extended = (f->id & CANLOG_EFF_FLAG) != 0U;
        out->id = f->id & (out->extended ? CANLOG_EFF_MASK : CANLOG_SFF_MASK);
        if (f->fd) {
            out->kind = CAPTURE_FD;
            out->fd_flags = f->fd_flags;
        } else if ((f->id & CANLOG_RTR_FLAG) != 0U) {
            out->kind = CAPTURE_REMOTE;
        } else {
            out->kind = CAPTURE_CLASSIC;
        }
    }
    const size_t n = f->fd ? f->len : ((out->kind == CAPTURE_REMOTE) ? 0U : f->len);
    memcpy(out->data, f->data, (n <= sizeof out->data) ? n : sizeof out->data);
}

int capture_parse_line(const char *line, capture_line_t *out, unsigned long *dropped, char *why,
                       size_t why_len)
{
    canlog_reader_t *r = malloc(sizeof *r);
    if (r == NULL) {
        return fail(why, why_len, "out of memory");
    }
    int result;
    (void)canlog_open_mem(r, line, strlen(line), LINE_NAME, CANLOG_FMT_LOG, CANLOG_ON_ERROR_STOP);
    canlog_frame_t f;
    const int rc = canlog_next(r, &f);
    if (rc == 1) {
        from_canlog(&f, out);
        result = CAPTURE_LINE_FRAME;
    } else if (rc == -(int)CANLOG_E_EMPTY) {
        /* blank, a comment, or a DROPCOUNT line (its N counted) */
        if (r->dropped > 0U || (strstr(line, "DROPCOUNT:") != NULL)) {
            if (dropped != NULL) {
                *dropped = (unsigned long)r->dropped;
            }
            result = CAPTURE_LINE_DROPS;
        } else {
            result = CAPTURE_LINE_SKIP;
        }
    } else {
        /* "line:1: reason: detail" without its "line:1: " */
        const char *msg = canlog_message(r);
        const size_t skip = strlen(LINE_NAME ":1: ");
        result = fail(why, why_len, "%s", (strlen(msg) > skip) ? (msg + skip) : msg);
    }
    free(r);
    return result;
}

void capture_free(capture_t *cap)
{
    if (cap == NULL) {
        return;
    }
    free(cap->recs);
    memset(cap, 0, sizeof *cap);
}

/* Adds one record; 0, or -1 out of memory. */
static int add_record(capture_t *cap, size_t *room, const canlog_frame_t *f)
{
    if (cap->n == *room) {
        const size_t want = (*room == 0U) ? 4096U : (*room * 2U);
        capture_rec_t *grown = realloc(cap->recs, want * sizeof *grown);
        if (grown == NULL) {
            return -1;
        }
        cap->recs = grown;
        *room = want;
    }
    capture_rec_t *rec = &cap->recs[cap->n++];
    rec->t_us = f->time_us;
    rec->line = (unsigned long)f->line;
    rec->f.id = (f->id & CANLOG_EFF_MASK) | PFE_CAN_EFF_FLAG;
    rec->f.dlc = f->len;
    memset(rec->f.data, 0, sizeof rec->f.data);
    memcpy(rec->f.data, f->data, f->len);
    return 0;
}

/* Counts a frame that is not J1939 (not a classic 29-bit data frame):
 * true; or false for a J1939 frame. */
static bool skipped(capture_t *cap, const canlog_frame_t *f)
{
    if ((f->id & CANLOG_ERR_FLAG) != 0U) {
        cap->skipped_error++;
    } else if (f->fd) {
        cap->skipped_fd++;
    } else if ((f->id & CANLOG_RTR_FLAG) != 0U) {
        cap->skipped_remote++;
    } else if ((f->id & CANLOG_EFF_FLAG) == 0U) {
        cap->skipped_standard++;
    } else {
        return false;
    }
    return true;
}

int capture_load(const char *path, capture_t *cap, char *err, size_t err_len)
{
    memset(cap, 0, sizeof *cap);
    if (path == NULL) {
        return fail(err, err_len, "no file name");
    }
    const int fd = open(path, O_RDONLY);
    if (fd < 0) {
        return fail(err, err_len, "%s: %s", path, strerror(errno));
    }
    struct stat st;
    if ((fstat(fd, &st) == 0) && S_ISDIR(st.st_mode)) {
        (void)close(fd);
        return fail(err, err_len, "%s: is a directory, not a CAN log", path);
    }
    canlog_reader_t *r = malloc(sizeof *r);
    if (r == NULL) {
        (void)close(fd);
        return fail(err, err_len, "%s: out of memory", path);
    }
    (void)canlog_open_fd(r, fd, path, CANLOG_FMT_AUTO, CANLOG_ON_ERROR_STOP);
    size_t room = 0U;
    int rc = 0;
    for (;;) {
        canlog_frame_t f;
        const int got = canlog_next(r, &f);
        if (got == 0) {
            break;
        }
        if (got < 0) {
            rc = fail(err, err_len, "%s", canlog_message(r));
            break;
        }
        if (canlog_time_base(r) == CANLOG_TB_NONE) {
            rc = fail(err, err_len, "%s:%llu: no timestamp: candump output without -t cannot be "
                      "judged in time (record with candump -L, or -t a, z or A)", path,
                      (unsigned long long)f.line);
            break;
        }
        if (skipped(cap, &f)) {
            continue;
        }
        if (add_record(cap, &room, &f) != 0) {
            rc = fail(err, err_len, "%s:%llu: out of memory", path, (unsigned long long)f.line);
            break;
        }
    }
    cap->lines = (size_t)r->lines;
    cap->dropped = (unsigned long)r->dropped;
    free(r);
    (void)close(fd);
    if (rc != 0) {
        capture_free(cap);
        return -1;
    }
    return 0;
}
