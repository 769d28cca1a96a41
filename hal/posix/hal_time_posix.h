/*
 * hal_time_posix.h - hal/hal_time.h on Linux: CLOCK_MONOTONIC, waits with
 * clock_nanosleep(TIMER_ABSTIME), which a signal interrupts (HAL_EINTR).
 */
#ifndef HAL_TIME_POSIX_H
#define HAL_TIME_POSIX_H

#include "hal/hal_time.h"

/* The process's clock (one for all callers; it keeps no state). */
hal_time_t *hal_time_posix(void);

#endif /* HAL_TIME_POSIX_H */
