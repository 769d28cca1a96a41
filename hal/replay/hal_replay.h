/*
 * hal_replay.h - a CAN bus replayed from a candump log, for running the ECU
 * over a recorded drive in logical time, on any machine.
 *
 * The bus carries the log's frames and the frames its handles send:
 *   - each log frame appears on the bus when the bus clock reaches its
 *     timestamp (hal_replay_advance_to()), and is received by every open
 *     handle whose filters accept it;
 *   - a frame sent on a handle is received by the other open handles, not
 *     by the sender (SocketCAN's default), stamped with the bus clock;
 *   - every frame on the bus, in bus order, is written to the record as a
 *     candump log line, as `candump -L` on that bus would show it: log
 *     frames with their own timestamps, sent frames with the bus clock.
 * The clock moves only with hal_replay_advance_to(): a replay is the same
 * on every machine, whatever its speed, so two builds of the ECU fed the
 * same log must write the same record byte for byte.
 *
 * Portable C without heap or floating point: the Cortex-M4 image
 * (hal/mps2/main_ecu.c) reads and writes through semihosting, the host tool
 * (sim_host/tools/pfe_ecu_replay.c) through stdio. The platform hands in two byte
 * streams, an input log and an output record.
 *
 * Input: candump's log format (`candump -L`), one frame a line,
 *     (1700000000.123456) vcan0 18FEF100#0011223344556677
 * or candump's printed output with a timestamp (-t a, z, d or A):
 *     (1700000000.123456)  vcan0  18FEF100   [8]  00 11 22 33 44 55 66 77
 *     (000.011063)  can0  18FEF100   [8]  FF 12 34 56 78 9A BC DE
 *     (2026-12-01 10:00:00.123456)  can0  123   [2]  0A 0B
 * (a -t A date is read as UTC; -t d's deltas are read as times since the
 * start, as sim_host/lib/log/log.h reads them unless told otherwise), each line
 * on its own, so that the two forms may even be mixed. Timestamps have 6 or
 * 9 fraction digits (nine are truncated to microseconds); ids are 3 hex
 * digits (11-bit) or 8 (29-bit); data are 0 to 8 bytes as pairs of hex
 * digits (either case; '.' may split a log line's bytes, blanks separate
 * the printed ones). candump -x's direction columns and -a's quoted ASCII
 * column are accepted. A trailing CR is accepted; blank lines, comments
 * ('#', "//"), candump's "DROPCOUNT:" lines and the tab-indented lines -e
 * writes under an error frame are ignored. Lines that are valid candump but
 * not classic data frames (CAN FD `##` or a two-digit [length], remote
 * `#R` or "remote request", error frames with CAN_ERR_FLAG in the id) are
 * skipped and counted: the module's bus is classic J1939. Any other line
 * is bad (printed output without a timestamp too: there is no time to
 * replay it at): skipped, counted, and the first one kept by number and
 * reason. A frame earlier than the one before it is delivered at once and
 * counted. Lines longer than HAL_REPLAY_LINE_MAX characters are bad (a
 * binary file ends up there or as a syntax error, never as a frame).
 * tests/replay/log_vectors.h holds the lines this reader and the host's
 * (sim_host/lib/log/log.h) are both tested on.
 *
 * A host may hand in frames instead of text (hal_replay_init_source()):
 * the host tools read logs through sim_host/lib/log/log.h, one parser for
 * every format, and the bus does the rest as for a text log.
 *
 * Output: `(seconds.microseconds) IFACE ID#DATA\n`, ids as 3 or 8 upper-case
 * hex digits, data as upper-case pairs: candump -L's own format. IFACE is
 * the record interface name given to hal_replay_init(), else the first log
 * line's interface, else "can0".
 */
#ifndef HAL_REPLAY_H
#define HAL_REPLAY_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_can.h"
#include "hal/hal_can_mem.h"
#include "hal/hal_nvm.h"
#include "hal/hal_time.h"

#define HAL_REPLAY_MAX_HANDLES 2U
#define HAL_REPLAY_RX_QUEUE 128U     /* frames per handle between two receives; more are dropped */
#define HAL_REPLAY_LINE_MAX 400U     /* characters of one log line, without its newline:
                                        a printed CAN FD frame of 64 bytes with -x and -a */
#define HAL_REPLAY_IN_CHUNK 256U     /* bytes asked of the input at a time */
#define HAL_REPLAY_OUT_BUF 512U      /* record bytes buffered before a write */
#define HAL_REPLAY_IFNAME_MAX 15U    /* as Linux's IFNAMSIZ - 1 */

/* Reads up to len bytes into buf: how many (> 0), 0 at the end, < 0 on error. */
typedef int32_t (*hal_replay_read_fn)(void *ctx, uint8_t *buf, uint32_t len);
/* Writes all len bytes: 0, or < 0 on error. */
typedef int32_t (*hal_replay_write_fn)(void *ctx, const uint8_t *buf, uint32_t len);

/* Why a line was bad. */
typedef enum {
    HAL_REPLAY_LINE_OK = 0,
    HAL_REPLAY_BAD_SYNTAX,           /* not "(sec.frac) iface id#data" */
    HAL_REPLAY_BAD_TIME,             /* timestamp: not digits, not 6 or 9 fraction digits, too large */
    HAL_REPLAY_BAD_ID,               /* id: not 3 or 8 hex digits, or 11-bit id over 0x7FF */
    HAL_REPLAY_BAD_DATA,             /* data: bad hex or odd number of digits */
    HAL_REPLAY_BAD_LENGTH,           /* more than 8 data bytes */
    HAL_REPLAY_LINE_TOO_LONG,        /* over HAL_REPLAY_LINE_MAX characters */
    HAL_REPLAY_BAD_NO_TIME,          /* candump's printed output without a timestamp */
    HAL_REPLAY_BAD_OTHER,            /* a reason a frame source gives (hal_replay_init_source()) */
} hal_replay_reason_t;

typedef struct {
    uint32_t lines;                  /* lines read, empty ones included */
    uint32_t frames;                 /* log frames put on the bus */
    uint32_t skipped_not_classic;    /* CAN FD, remote and error frames */
    uint32_t bad_lines;
    uint32_t first_bad_line;         /* line number (from 1), 0 when none */
    hal_replay_reason_t first_bad_reason;
    uint32_t time_backwards;         /* frames earlier than the frame before */
    uint32_t sent_frames;            /* frames the handles sent */
    uint32_t recorded;               /* record lines written */
    bool read_failed;                /* the input stream reported an error (the log ends there) */
    bool record_failed;              /* a record write failed (later lines are lost) */
} hal_replay_stats_t;

typedef struct hal_replay_bus hal_replay_bus_t;

/* A frame source: the next classic data frame of the log into *f, its time
 * into *t_us and its interface name into ifname (NUL-terminated), and 1; or
 * 0 at the end of the log. It counts what it reads and skips in *stats:
 * lines, skipped_not_classic, bad_lines, first_bad_line, first_bad_reason
 * and read_failed (the bus counts frames and time_backwards itself). */
typedef int32_t (*hal_replay_source_fn)(void *ctx, pfe_can_frame_t *f, uint64_t *t_us,
                                        char ifname[HAL_REPLAY_IFNAME_MAX + 1U],
                                        hal_replay_stats_t *stats);

/* A handle: one node's view of the bus. Fields are the backend's. */
struct hal_can {
    hal_replay_bus_t *bus;
    bool open;
    hal_can_mem_port_t port;         /* filters, receive queue, counters */
    hal_can_rx_t rx[HAL_REPLAY_RX_QUEUE];
};

/* The bus's clock as a hal_time_t (hal_replay_time()). */
struct hal_time {
    hal_replay_bus_t *bus;
};

/* The bus. Fields are the backend's; the caller owns the storage. */
struct hal_replay_bus {
    uint64_t now_us;                 /* bus clock: log time, microseconds */
    struct hal_time time;
    struct hal_can handle[HAL_REPLAY_MAX_HANDLES];
    /* input */
    hal_replay_read_fn read;
    void *read_ctx;
    hal_replay_source_fn source;     /* NULL: parse what read gives */
    void *source_ctx;
    uint8_t in[HAL_REPLAY_IN_CHUNK];
    uint32_t in_pos;
    uint32_t in_len;
    bool in_end;
    char line[HAL_REPLAY_LINE_MAX + 1U];
    bool have_next;                  /* `next` holds the next log frame */
    hal_can_rx_t next;
    uint64_t last_log_us;
    bool any_log_frame;
    /* record */
    hal_replay_write_fn write;
    void *write_ctx;
    char ifname[HAL_REPLAY_IFNAME_MAX + 1U];
    bool ifname_fixed;
    char out[HAL_REPLAY_OUT_BUF];
    uint32_t out_len;
    hal_replay_stats_t stats;
};

/*
 * Starts a bus with no handle open. read may be NULL (no log: the bus then
 * carries only what handles send), write may be NULL (no record).
 * record_ifname: the interface name in the record, NULL to take the log's.
 * Reads ahead to the first log frame. The clock starts at that frame's time
 * (0 with no frame); see hal_replay_next_us().
 */
void hal_replay_init(hal_replay_bus_t *bus, hal_replay_read_fn read, void *read_ctx,
                     hal_replay_write_fn write, void *write_ctx, const char *record_ifname);

/* The same with frames from source (not NULL) instead of text. */
void hal_replay_init_source(hal_replay_bus_t *bus, hal_replay_source_fn source, void *source_ctx,
                            hal_replay_write_fn write, void *write_ctx, const char *record_ifname);

/* Time of the next log frame not yet on the bus: true and *t_us, or false
 * when the log is exhausted. */
bool hal_replay_next_us(const hal_replay_bus_t *bus, uint64_t *t_us);

/* Moves the clock to now_us (never backwards: an earlier time is ignored)
 * and puts every log frame due by then on the bus. */
void hal_replay_advance_to(hal_replay_bus_t *bus, uint64_t now_us);

uint64_t hal_replay_now_us(const hal_replay_bus_t *bus);

/* The bus clock through hal/hal_time.h: hal_time_wait_until_us() is
 * hal_replay_advance_to() (it returns at once, the log's frames due by
 * then on the bus). */
hal_time_t *hal_replay_time(hal_replay_bus_t *bus);

/* Opens a handle: NULL when HAL_REPLAY_MAX_HANDLES are open. */
hal_can_t *hal_replay_open(hal_replay_bus_t *bus);
void hal_replay_close(hal_can_t *can);

/* Writes out what the record buffer holds: 0, or HAL_EIO if the record
 * failed at any time. Call at the end of a replay. */
int hal_replay_flush(hal_replay_bus_t *bus);

const hal_replay_stats_t *hal_replay_stats(const hal_replay_bus_t *bus);

/* A short English text for a reason ("bad hex in data", ...). */
const char *hal_replay_reason_text(hal_replay_reason_t reason);

/* NVM for a replay: two slots in RAM, erased (0xFF) at init; nothing
 * survives the program. Writes complete. */
struct hal_nvm {
    uint8_t slot[PFE_NVM_SLOTS][PFE_NVM_RECORD_SIZE];
    uint32_t writes;
};
void hal_replay_nvm_init(hal_nvm_t *nvm);

#endif /* HAL_REPLAY_H */
