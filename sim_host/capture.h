/*
 * capture.h - a recorded CAN bus: candump log files.
 *
 * The format candump -L and sim_host/pfe_record write, one frame per line:
 *
 *     (1700000000.010000) vcan0 0CF01300#C67C007DFFFFFCFF
 *     (SECONDS.FRACTION) IFACE FRAME [R|T]
 *
 * - SECONDS: 1 to 10 digits; FRACTION: 6 digits (microseconds) or 9
 *   (nanoseconds, truncated to microseconds here).
 * - IFACE: 1 to 15 characters, no blanks; any number of spaces before it
 *   (candump right-aligns names to the longest one it was given).
 * - FRAME, as can-utils' lib.c prints it:
 *     III#DD..          classic frame, 11-bit id (3 hex digits), 0 to 8 bytes
 *     IIIIIIII#DD..     classic frame, 29-bit id (8 hex digits); an id with
 *                       bit 29 (0x20000000) set is an error frame, whose
 *                       low 29 bits are the error class
 *     ...#DD.._L        8 bytes with a raw DLC L of 9 to F (len8_dlc)
 *     ...#R, ...#RL     remote frame, DLC L 0 to 8 (omitted when 0)
 *     ...##FDD..        CAN FD: F the flags nibble, 0 to 64 bytes
 *   Data bytes are pairs of hex digits, either case, optionally split by '.'.
 * - An optional last field R or T (candump -x: received, transmitted).
 * - Blank lines and lines starting with '#' are skipped; so are candump's
 *   "DROPCOUNT: dropped N CAN frame(s) on 'IF' socket (total drops T)"
 *   lines, whose N is added up (capture_t.dropped).
 * - LF or CRLF line ends; a line holds at most CAPTURE_MAX_LINE characters.
 *
 * A bad line, a NUL or control character (a binary file), or a timestamp
 * earlier than the line before it is an error naming the file, the line and
 * the reason: "FILE:LINE: reason". A file without a single frame is an error
 * too. Nothing after the first error is read.
 */
#ifndef CAPTURE_H
#define CAPTURE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../firmware/pfe_can.h"

#define CAPTURE_MAX_LINE 1023U
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
 * Parses one line (without its line end; a trailing CR is allowed). Returns
 * CAPTURE_LINE_*, or -1 with the reason in why (NUL-terminated, truncated to
 * why_len - 1). *out is written only for CAPTURE_LINE_FRAME, *dropped only
 * for CAPTURE_LINE_DROPS. No state; reentrant; O(length).
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
 * capture_free()), or -1 with *cap empty and "PATH:LINE: reason" or
 * "PATH: reason" in err (truncated to err_len - 1; err may be NULL when
 * err_len is 0). Memory: 32 bytes or so per J1939 frame.
 */
int capture_load(const char *path, capture_t *cap, char *err, size_t err_len);

/* Empties *cap; safe on an empty one and on NULL. */
void capture_free(capture_t *cap);

#endif /* CAPTURE_H */
