/*
 * log.h - a streaming reader of CAN log files, and a writer of candump's
 * log line: the one log parser of every host tool (pfe_replay, pfe_decode,
 * pfe_ecu_replay, pfe_faults, run_report and ecu_check through capture.h,
 * truck_judge) and their tests. One file per format: log_candump.c,
 * log_printed.c, log_asc.c, over log_core.c (lines, numbers, ids, time,
 * detection); log_parse.h is what they share. The Cortex-M4 image reads
 * logs through hal/replay's heap-free parser instead; both are held to the
 * vectors of tests/replay/log_vectors.h.
 *
 * Formats read (detected from the first meaningful line, or forced):
 *
 *   CANLOG_FMT_LOG      candump's log file (candump -l, -L; canplayer's input):
 *                         (1700000000.010000) vcan0 18FEF100#0011223344556677
 *                       6 or 9 fraction digits; id 3 hex digits (11-bit) or 8
 *                       (29-bit, or an error frame when CAN_ERR_FLAG is set);
 *                       data as hex pairs, '.' allowed between bytes;
 *                       remote frames "123#R" or "123#R4" (requested length);
 *                       "..#<8 bytes>_C": the raw DLC (9..F) of candump -8;
 *                       CAN FD "123##1" + data (the digit after ## is the FD
 *                       flags nibble: 1 BRS, 2 ESI). A trailing " R" or " T"
 *                       (candump -x direction) is accepted. Blank lines,
 *                       lines starting with '#' or "//" and candump's
 *                       "DROPCOUNT:" lines are skipped and counted as
 *                       comments (a DROPCOUNT's N is added to dropped, in
 *                       the printed formats too); any other line that does not start with
 *                       '(' is an error (canplayer silently ignores them).
 *   CANLOG_FMT_PRINTED  candump's printed output, default view (no -c
 *                       colours, no -b binary, no -8 DLC), with or without -t:
 *                         (1700000000.010000)  vcan0  18FEF100   [8]  00 11 22 33 44 55 66 77
 *                         (2024-01-02 10:11:12.123456)  vcan0  123   [2]  0A 0B
 *                         (000.010000)  vcan0       123   [4]  remote request
 *                         vcan0  18FEF100  [12]  00 11 ... (two-digit length: CAN FD,
 *                                                        except "[04]  remote request")
 *                       -x's "RX - -" / "TX B E" columns, -a's ASCII column
 *                       and -e's ERRORFRAME marker are accepted; the lines
 *                       -e adds after an error frame (they start with a tab)
 *                       are skipped as comments. Without -x, FD flags are
 *                       not in the output and read as 0.
 *   CANLOG_FMT_PRINTED_DELTA  the same, for `candump -t d`: the timestamps
 *                       are deltas from the previous frame. `-t d` and `-t z`
 *                       look alike, so detection assumes `-t z`; force this
 *                       format for `-t d` output.
 *   CANLOG_FMT_ASC      Vector ASC: header lines (date, base hex|dec
 *                       timestamps absolute|relative, [no] internal events
 *                       logged, Begin/End Triggerblock, // comments), and
 *                         0.010000 1  18FEF100x       Rx   d 8 00 11 22 33 44 55 66 77
 *                         0.020000 1  123             Tx   r 4
 *                         0.030000 1  ErrorFrame
 *                         0.040000 CANFD   1 Rx 18FEF100x  [name]  1 0 9 12 00 .. 0B  <trailer>
 *                       Classic frames may be followed by Vector's trailer
 *                       ("Length = ... BitCount = ... ID = ..."). A CANFD
 *                       line whose flags field (third trailer number) lacks
 *                       0x1000 (FDF) is a classic frame, with 0x10 a remote
 *                       one, as log2asc writes them. Channel N is named
 *                       "can<N-1>" (as asc2log does): replay it with a
 *                       mapping such as vcan0=can0. Other event lines (bus
 *                       statistics, status, signals, "Start of measurement")
 *                       are skipped and counted as comments. An ErrorFrame
 *                       becomes an error frame with CAN_ERR_BUSERROR (0x80)
 *                       and 8 zero data bytes, as asc2log writes it.
 *
 * Time (canlog_frame_t.time_us, microseconds, 64 bits; 9-digit fractions are
 * truncated to the microsecond). What it counts from depends on the format
 * and is given by canlog_time_base() once a frame was read:
 *   CANLOG_TB_EPOCH    since 1970-01-01 UTC: candump log, printed with -t a
 *   CANLOG_TB_DATE     the wall-clock date and time printed by -t A, read as
 *                      if it were UTC (the output does not say the recording
 *                      machine's time zone): intervals are exact
 *   CANLOG_TB_START    since the start of the recording: printed with -t z,
 *                      -t d (deltas added up by the reader), ASC (absolute
 *                      timestamps as they are, relative ones added up; the
 *                      `date` header is not used)
 *   CANLOG_TB_NONE     printed without -t: every frame has time 0
 * Within a file time must not go backwards (checked to the microsecond): a
 * frame earlier than the one before is CANLOG_E_BACKWARDS. candump writes
 * each socket's frames in its own order, so a log of several interfaces
 * may step back by a few microseconds; such a log needs
 * CANLOG_ON_ERROR_SKIP (the out-of-order frames are dropped and counted).
 *
 * Errors: each bad line gives a reason (canlog_reason_t) and a message that
 * names the file, the line number and the reason, e.g.
 *     drive.log:12: bad hex: 'G' in the data
 * With CANLOG_ON_ERROR_STOP, canlog_next() returns the reason (negative) at
 * the first bad line; calling it again goes on with the next line. With
 * CANLOG_ON_ERROR_SKIP it skips the line, counts it in errors[reason] (and
 * remembers the message of the first error of each reason) and goes on.
 * Two reasons concern the whole file and are returned in both modes: an
 * empty file (no bytes, or only blank and comment lines: CANLOG_E_EMPTY at
 * end of file) and a read error (CANLOG_E_IO). A file with frames whose
 * every other line was skipped ends normally (1 ... 1, 0).
 * Binary content (a NUL or a control character other than tab, CR, FF, VT,
 * in a line that does not parse) is reported as CANLOG_E_BINARY rather than
 * as the syntax error it also is.
 *
 * Lines: at most CANLOG_LINE_MAX characters before the newline (CR LF line
 * ends and a UTF-8 byte order mark at the start of the file are accepted). A longer line is CANLOG_E_LINE_TOO_LONG, and its rest
 * is skipped up to its newline. A last line without a newline is read.
 *
 * Memory: a canlog_reader_t holds its whole state, a read buffer of
 * CANLOG_BUF_SIZE bytes included (about 64 KiB: allocate it statically or on
 * the heap rather than on a small stack). No allocation, no global state:
 * reentrant; one thread per reader. Each canlog_next() is O(line length).
 * Reads with read(2) from a file descriptor, or from a caller's memory.
 */
#ifndef CANLOG_H
#define CANLOG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Flags in canlog_frame_t.id, the same bits as SocketCAN's can_id. */
#define CANLOG_EFF_FLAG 0x80000000UL /* 29-bit identifier */
#define CANLOG_RTR_FLAG 0x40000000UL /* remote transmission request */
#define CANLOG_ERR_FLAG 0x20000000UL /* error message frame */
#define CANLOG_SFF_MASK 0x000007FFUL
#define CANLOG_EFF_MASK 0x1FFFFFFFUL

/* canlog_frame_t.fd_flags, SocketCAN's canfd_frame.flags. */
#define CANLOG_FD_BRS 0x01U
#define CANLOG_FD_ESI 0x02U

#define CANLOG_MAX_DLEN 8U     /* classic CAN data bytes */
#define CANLOG_FD_MAX_DLEN 64U /* CAN FD */
#define CANLOG_IFNAME_MAX 16U  /* with the terminating NUL, as IFNAMSIZ */
#define CANLOG_LINE_MAX 4095U  /* longest line accepted, newline excluded */
#define CANLOG_BUF_SIZE 65536U /* read buffer, > CANLOG_LINE_MAX */
#define CANLOG_NAME_MAX 256U   /* file name kept for messages (longer: cut) */
#define CANLOG_MSG_MAX 512U    /* one error message */

/* The longest line canlog_write_log() writes, NUL included: a 20-digit
 * second count, an interface of 15 characters, a CAN FD frame of 64 bytes. */
#define CANLOG_LOG_LINE_MAX 192U

typedef struct {
    uint64_t time_us;   /* see the time base above */
    uint64_t line;      /* 1-based line of the file it came from */
    uint32_t id;        /* 11 or 29 bits | CANLOG_EFF_FLAG, _RTR_FLAG, _ERR_FLAG */
    uint8_t len;        /* data bytes: 0..8, FD 0..64; remote frame: requested length */
    uint8_t fd_flags;   /* CANLOG_FD_BRS | CANLOG_FD_ESI (FD frames only) */
    bool fd;            /* a CAN FD frame */
    char dir;           /* 'R', 'T' when the log says so, else 0 */
    uint8_t channel;    /* ASC channel (1..255); 0 in the other formats */
    uint8_t len8_dlc;   /* candump log "#..._L": raw DLC 9..15 of an 8-byte classic frame, else 0 */
    char iface[CANLOG_IFNAME_MAX]; /* interface name as logged ("can0" for ASC channel 1) */
    uint8_t data[CANLOG_FD_MAX_DLEN]; /* len bytes; the rest is left as it was */
} canlog_frame_t;

typedef enum {
    CANLOG_FMT_AUTO = 0,
    CANLOG_FMT_LOG,
    CANLOG_FMT_PRINTED,
    CANLOG_FMT_PRINTED_DELTA,
    CANLOG_FMT_ASC
} canlog_format_t;

typedef enum {
    CANLOG_TB_UNKNOWN = 0, /* no frame read yet */
    CANLOG_TB_EPOCH,
    CANLOG_TB_DATE,
    CANLOG_TB_START,
    CANLOG_TB_NONE
} canlog_time_base_t;

typedef enum {
    CANLOG_ON_ERROR_STOP = 0,
    CANLOG_ON_ERROR_SKIP
} canlog_error_mode_t;

/* Reasons, returned negated by canlog_next(). */
typedef enum {
    CANLOG_OK = 0,
    CANLOG_E_LINE_TOO_LONG, /* more than CANLOG_LINE_MAX characters */
    CANLOG_E_TRUNCATED,     /* the line ends before the frame does (missing field, half a byte) */
    CANLOG_E_BAD_HEX,       /* a character that is not a hex digit where one must be */
    CANLOG_E_BAD_TIME,      /* a malformed timestamp (e.g. not 6 or 9 fraction digits) */
    CANLOG_E_BAD_ID,        /* id of the wrong width, 11-bit over 7FF, 29-bit over 1FFFFFFF */
    CANLOG_E_DLC,           /* length over 8 (classic), over 64 or not a CAN FD length, or
                               not matching the [len] / DLC the line states */
    CANLOG_E_BACKWARDS,     /* time earlier than the frame before */
    CANLOG_E_SYNTAX,        /* any other malformed line (unknown token, text after the frame) */
    CANLOG_E_BINARY,        /* NUL or control characters: not a text log */
    CANLOG_E_EMPTY,         /* no frame and no line but blank or comment ones */
    CANLOG_E_FORMAT,        /* the first meaningful line is in none of the formats */
    CANLOG_E_IO,            /* read(2) failed */
    CANLOG_REASON_COUNT
} canlog_reason_t;

typedef struct {
    /* source */
    int fd;                    /* -1 when reading memory */
    const char *mem;
    size_t mem_len;
    size_t mem_pos;
    char name[CANLOG_NAME_MAX];
    canlog_format_t format;    /* as asked; then as detected */
    canlog_error_mode_t mode;
    /* buffer: bytes [pos, end) not yet consumed */
    size_t pos;
    size_t end;
    bool eof;
    uint64_t consumed_bytes;   /* bytes of the file consumed so far (progress) */
    /* parse state */
    uint64_t line_no;
    bool have_time;
    uint64_t last_time_us;
    uint64_t acc_time_us;      /* relative ASC, printed -t d: running sum */
    canlog_time_base_t time_base;
    bool asc_relative;         /* ASC "timestamps relative" */
    bool asc_decimal;          /* ASC "base dec" */
    bool saw_content;          /* a non-blank, non-comment line was seen */
    /* counters (never reset, also not by canlog_rewind) */
    uint64_t lines;            /* lines read */
    uint64_t frames;           /* frames returned */
    uint64_t comments;         /* blank, comment and ignored event lines */
    uint64_t errors[CANLOG_REASON_COUNT]; /* bad lines by reason */
    uint64_t error_lines;      /* sum of errors[] */
    uint64_t dropped;          /* sum of the N of candump's "DROPCOUNT: dropped N ..." lines */
    uint64_t backwards;        /* frames returned although earlier (canlog_allow_backwards) */
    bool backwards_ok;         /* canlog_allow_backwards() */
    /* messages */
    char msg[CANLOG_MSG_MAX];  /* the last error */
    char first_msg[CANLOG_REASON_COUNT][CANLOG_MSG_MAX]; /* first error of each reason */
    canlog_frame_t scratch;    /* the frame being parsed */
    char buf[CANLOG_BUF_SIZE];
} canlog_reader_t;

/*
 * Starts reading file descriptor FD (not closed by canlog; a pipe is fine
 * but cannot be rewound), named NAME in messages (NULL: "<fd>"). FORMAT:
 * CANLOG_FMT_AUTO or the format to read. Returns 0, or -CANLOG_E_SYNTAX for a
 * NULL reader or a negative fd. Counters start at 0.
 */
int canlog_open_fd(canlog_reader_t *r, int fd, const char *name, canlog_format_t format,
                   canlog_error_mode_t mode);

/* The same over LEN bytes of memory at TEXT (kept by the caller while reading). */
int canlog_open_mem(canlog_reader_t *r, const char *text, size_t len, const char *name,
                    canlog_format_t format, canlog_error_mode_t mode);

/*
 * Reads the next frame into *out (out must not be NULL). Returns 1 with a
 * frame, 0 at end of file, or a negative reason (see the top; the message is
 * canlog_message()). *out is written only when 1 is returned.
 */
int canlog_next(canlog_reader_t *r, canlog_frame_t *out);

/*
 * Back to the first line, for another pass over the same file: the position,
 * line numbers and time checks restart; the detected format and the counters
 * stay. Returns 0, or -CANLOG_E_IO when the file cannot seek (a pipe).
 */
int canlog_rewind(canlog_reader_t *r);

/*
 * Lets frames earlier than the one before through instead of failing them
 * with CANLOG_E_BACKWARDS: each is returned with its own time and counted in
 * r->backwards (for a replay that delivers it at once, as hal/replay does).
 * Call after opening; kept by canlog_rewind().
 */
void canlog_allow_backwards(canlog_reader_t *r, bool allow);

/* The format read (after detection: never CANLOG_FMT_AUTO once a frame came). */
canlog_format_t canlog_format(const canlog_reader_t *r);
canlog_time_base_t canlog_time_base(const canlog_reader_t *r);

/* "FILE:LINE: reason: detail" of the last error ("" if none). */
const char *canlog_message(const canlog_reader_t *r);

/* Short text of a reason ("bad hex"), of a format ("candump log"), of a
 * time base ("seconds since 1970"). Never NULL. */
const char *canlog_reason_text(int reason);
const char *canlog_format_text(canlog_format_t format);
const char *canlog_time_base_text(canlog_time_base_t tb);

/* Parses a format name: "auto", "log", "printed", "printed-delta", "asc".
 * Returns 0 and *out, or -1. */
int canlog_format_parse(const char *text, canlog_format_t *out);

/*
 * Writes FRAME as one candump log line, "(SEC.USEC) IFACE ID#DATA\n", with
 * IFACE instead of frame->iface unless it is NULL, into BUF of SIZE bytes
 * (CANLOG_LOG_LINE_MAX always suffices). Ids: 3 hex digits for 11 bits,
 * 8 for 29 bits and error frames; data upper-case hex, no separators;
 * remote frames "ID#R" (with the length when not 0); FD "ID##F" + data.
 * Returns the line's length without the NUL, or 0 if it does not fit (BUF
 * then holds ""). canplayer and canlog read the line back to the same frame
 * (the time to the microsecond, relative to whatever base the frame had).
 */
size_t canlog_write_log(char *buf, size_t size, const canlog_frame_t *frame, const char *iface);

/* Data length of an FD DLC (0..15), and the smallest DLC for a length
 * (0..64; 0xFF for a length over 64). */
uint8_t canlog_fd_dlc_to_len(uint8_t dlc);
uint8_t canlog_fd_len_to_dlc(uint8_t len);

#endif /* CANLOG_H */
