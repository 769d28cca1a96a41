/*
 * replay_source.h - a CAN log read through sim_host/lib/log/log.h as the frame
 * source of a replay bus (hal/replay/hal_replay.h), so that the host tools
 * that run the firmware over a log (pfe_ecu_replay, pfe_faults) read every
 * form the host's other tools read: candump -L, candump's printed output
 * with -t a, z, d or A, and Vector ASC, through the one host parser.
 *
 * The bus gets the log's classic data frames in file order; CAN FD,
 * remote and error frames are counted as skipped (stats.skipped_not_classic),
 * as the bus's own text parser counts them. A bad line is skipped and
 * counted (stats.bad_lines; the first one's number, and canlog's message
 * "FILE:LINE: reason: detail" from replay_source_first_bad()). Printed output
 * without timestamps is bad too: there is no time to replay it at. A frame
 * earlier than the one before is handed on (the bus delivers it at once and
 * counts it), as the bus's parser does. tests/replay/log_vectors.h holds the
 * lines this reading and the bus's own parser must agree on, so that the
 * host and the Cortex-M4 image replay a log alike.
 *
 * Memory: a replay_source_t holds a canlog reader (about 70 KiB: static or
 * heap, not a small stack). Not reentrant across sources; one per log.
 */
#ifndef REPLAY_SOURCE_H
#define REPLAY_SOURCE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hal/replay/hal_replay.h"
#include "lib/log/log.h"

typedef struct {
    canlog_reader_t reader;
    int fd;
    bool any_bad;
    char first_bad[CANLOG_MSG_MAX];  /* message of the first bad line, "" when none */
} replay_source_t;

/*
 * Opens the log at path, in format (CANLOG_FMT_AUTO: detected). Returns 0,
 * or -1 with "PATH: reason" in err (err_len bytes with the NUL): no such
 * file, a directory, unreadable.
 */
int replay_source_open(replay_source_t *src, const char *path, canlog_format_t format, char *err,
                       size_t err_len);

/* The hal_replay_source_fn: ctx is a replay_source_t. */
int32_t replay_source_next(void *ctx, pfe_can_frame_t *f, uint64_t *t_us,
                           char ifname[HAL_REPLAY_IFNAME_MAX + 1U], hal_replay_stats_t *stats);

/* The first bad line's message ("" when every line was good). */
const char *replay_source_first_bad(const replay_source_t *src);

/* The canlog message of a read error or an empty log ("" when none). */
const char *replay_source_message(const replay_source_t *src);

/* Closes the file; safe twice. */
void replay_source_close(replay_source_t *src);

#endif /* REPLAY_SOURCE_H */
