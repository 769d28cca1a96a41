/*
 * capture.h - a recorded CAN bus, for the judge (run_report) and the
 * checkers (ecu_check, ecu_offline).
 *
 * A capture is any log sim_host/lib/log/log.h reads, through that one parser:
 * candump -L (and pfe_record's output), candump's printed output with
 * timestamps (-t a, z, A; -t d reads as -t z, see lib/log/log.h) and Vector
 * ASC, the form detected from the first lines. For example
 *
 *     (1700000000.010000) vcan0 0CF01300#C67C007DFFFFFCFF
 *     (000.011063)  can0  18FEF100   [8]  FF 12 34 56 78 9A BC DE
 *
 * Every line is read as lib/log/log.h describes, blank and comment lines
 * skipped; candump's "DROPCOUNT: dropped N ..." lines add N to
 * capture_t.dropped. Classic frames with 29-bit ids (J1939) become records;
 * 11-bit, remote, CAN FD and error frames are counted and skipped. A log
 * that starts mid-drive, with no address claims and any number of PGNs
 * nobody here reads, is a capture like any other.
 *
 * The first bad line ends the load with an error naming the file, the
 * line and the reason (canlog's "FILE:LINE: reason: detail"), so do a
 * timestamp earlier than the line before, printed output without
 * timestamps (nothing to judge in time) and a file without a single frame.
 */
#ifndef CAPTURE_H
#define CAPTURE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "firmware/pfe_can.h"

#define CAPTURE_MAX_LINE 4095U          /* as CANLOG_LINE_MAX */
#define CAPTURE_IFNAME_MAX 15U
#define CAPTURE_FD_MAX_LEN 64U
#define CAPTURE_ERR_FLAG 0x20000000UL    /* as SocketCAN's CAN_ERR_FLAG */

typedef enum {
    CAPTURE_CLASSIC = 0,
    CAPTURE_REMOTE = 1,
    CAPTURE_FD = 2,
    CAPTURE_ERROR = 3
} capture_kind_t;

/* One line's frame, every field as the line gave it. */
typedef struct {
    uint64_t t_us;                  /* seconds * 1e6 + microseconds */
    char iface[CAPTURE_IFNAME_MAX + 1U];
    capture_kind_t kind;
    bool extended;                  /* 8-digit id */
    uint32_t id;                    /* 11 or 29 bits; an error frame's error class */
    uint8_t len;                    /* data bytes; a remote frame's DLC */
    uint8_t len8_dlc;               /* 9 .. 15 when given with _L, else 0 */
    uint8_t fd_flags;               /* CAN FD only */
    uint8_t data[CAPTURE_FD_MAX_LEN];
} capture_line_t;

#define CAPTURE_LINE_SKIP 0        /* blank or comment */
#define CAPTURE_LINE_FRAME 1       /* *out holds a frame */
#define CAPTURE_LINE_DROPS 2       /* a DROPCOUNT line: *dropped holds its N */

/*
 * Parses one candump -L line (without its line end; a trailing CR is
 * allowed) through canlog. Returns CAPTURE_LINE_*, or -1 with canlog's
 * "reason: detail" in why (NUL-terminated, truncated to why_len - 1). *out
 * is written only for CAPTURE_LINE_FRAME, *dropped (may be NULL) only for
 * CAPTURE_LINE_DROPS. No state; reentrant; O(length) plus a reader of
 * about 70 KiB taken from the heap for the call.
 */
int capture_parse_line(const char *line, capture_line_t *out, unsigned long *dropped, char *why,
                       size_t why_len);

/* A classic data frame with a 29-bit id: what J1939 is made of. */
typedef struct {
    uint64_t t_us;
    pfe_can_frame_t f;              /* id | PFE_CAN_EFF_FLAG */
    unsigned long line;             /* in the file, from 1 */
} capture_rec_t;

typedef struct {
    capture_rec_t *recs;            /* J1939 frames in file order, owned */
    size_t n;
    size_t lines;                   /* lines read */
    /* Frames that are not J1939, skipped and counted. */
    size_t skipped_standard;        /* 11-bit classic data frames */
    size_t skipped_remote;
    size_t skipped_fd;
    size_t skipped_error;
    unsigned long dropped;          /* sum of DROPCOUNT lines */
} capture_t;

/*
 * Reads the log at path. Returns 0 with *cap filled (release with
 * capture_free()), or -1 with *cap empty and "PATH:LINE: reason: detail" or
 * "PATH: reason" in err (truncated to err_len - 1; err may be NULL when
 * err_len is 0). Memory: 32 bytes or so per J1939 frame, and 70 KiB while
 * reading.
 */
int capture_load(const char *path, capture_t *cap, char *err, size_t err_len);

/* Empties *cap; safe on an empty one and on NULL. */
void capture_free(capture_t *cap);

#endif /* CAPTURE_H */
