/*
 * hal_time.h - the clock every backend provides: monotonic microseconds,
 * and waiting for the next tick.
 *
 * Backends: hal/posix (CLOCK_MONOTONIC, clock_nanosleep on absolute
 * deadlines), hal/fake (a clock that moves only when told or waited on),
 * hal/replay (the log's time: waiting puts the log's frames on the bus).
 */
#ifndef HAL_TIME_H
#define HAL_TIME_H

#include <stdint.h>

#define HAL_EINTR (-4)      /* the wait was interrupted (a signal): check why, then wait again */

typedef struct hal_time hal_time_t;

/* Microseconds since an arbitrary origin; never decreases. */
uint64_t hal_time_now_us(hal_time_t *time);

/* Returns once the clock has reached deadline_us (at once when it has
 * already): 0, or HAL_EINTR. Absolute deadlines: a late return does not
 * shift the next one. */
int hal_time_wait_until_us(hal_time_t *time, uint64_t deadline_us);

#endif /* HAL_TIME_H */
