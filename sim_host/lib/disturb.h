/*
 * disturb.h - the spans of a capture in which it cannot say what the module
 * saw or did when, so that the judges (run_report, ecu_check) do not hold
 * its rates against a reference ticking on ideal time there. The events:
 *
 *   - input timing: SSI frames more than 30 ms apart, or CCVS1 frames less
 *     than 50 or more than 150 ms apart, each sender's apart from the
 *     others' (a stalled or bunched replay: a bunch reaches the module
 *     later than its timestamps say, and the speed filter counts the
 *     periods between samples). Span: from the last good frame to
 *     DISTURB_RECOVERY_US after the event, the time the speed filter takes
 *     to forget it (its acceleration gain is 0.05 per 100 ms sample);
 *   - lost ticks: PFE_Status TickOverruns went up by DISTURB_LOST_TICKS_MIN
 *     or more since the previous PFE_Status (its estimator ran steps late or
 *     skipped them). Span: from the previous PFE_Status to
 *     DISTURB_RECOVERY_US after this one;
 *   - the module's own frames bunched: two of its LFE1 or PFE_OwnFuel
 *     frames (100 ms apart, can_dbc/pfe.dbc) less than 50 or more than
 *     150 ms apart. A loop that catches up after a stall
 *     (hal/hal_ecu_loop.h) sends the ticks' frames back to back: their
 *     values are right, but the capture no longer shows which tick made
 *     them. Span: from the PGN's previous frame to this one (the values
 *     need no recovery: only their time is unknown), and TickOverruns,
 *     which saturates at 250, is not needed to see it.
 *
 * Memory: the spans grow with the capture's events (realloc); out of
 * memory a span is dropped and its frames judged like any other.
 */
#ifndef DISTURB_H
#define DISTURB_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lib/capture.h"

#define DISTURB_RECOVERY_US 2000000U
#define DISTURB_LOST_TICKS_MIN 5U
#define DISTURB_SSI_GAP_MAX_US 30000U
#define DISTURB_PERIODIC_GAP_MIN_US 50000U  /* CCVS1, and the module's 100 ms frames */
#define DISTURB_PERIODIC_GAP_MAX_US 150000U

typedef struct {
    uint64_t from_us, to_us;
} disturb_span_t;

typedef struct {
    disturb_span_t *spans;  /* owned: disturb_free() */
    size_t n, room;
    size_t input_events, overrun_events, output_events;
} disturb_t;

/* Finds the spans of cap (module at module_sa) into *d, which it resets. */
void disturb_find(const capture_t *cap, uint8_t module_sa, disturb_t *d);

/* Whether t_us lies in any span. O(spans). */
bool disturbed(const disturb_t *d, uint64_t t_us);

void disturb_free(disturb_t *d);

/*
 * When the module made each of its periodic frames, by its own schedule:
 * PFE_OwnFuel and PFE_PlatoonFuel go out every period P (GenMsgCycleTime,
 * 100 ms) at a fixed tick, so within a run of them (frames at most 1.5 P
 * apart) frame n was made at base + n P, base the smallest send - n P of
 * the run (its least late frame). A loop catching up after a stall sends
 * its ticks' frames late, with each tick's values: judged at its send time
 * such a frame meets a reference that moved on. A gap of over 1.5 P (a
 * stall's start, frames missing from the capture, a restart) starts a new
 * run, numbered from its first frame and based on its own least late one,
 * so that a missing frame shifts nothing. made_us[k] (cap->n of them) is
 * that time for those frames, the record's own time for every other;
 * *late_max_us the largest send - made. 0, or -1 out of memory (made_us
 * then the records' own times).
 */
int disturb_made_times(const capture_t *cap, uint8_t module_sa, uint64_t *made_us,
                       uint64_t *late_max_us);

#endif /* DISTURB_H */
