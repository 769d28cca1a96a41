/* hal_time_posix.c - the monotonic clock on Linux (contract in hal_time_posix.h). */
#define _POSIX_C_SOURCE 200809L
#include "hal/posix/hal_time_posix.h"

#include <errno.h>
#include <time.h>

struct hal_time {
    int unused;
};

static struct hal_time g_clock;

hal_time_t *hal_time_posix(void)
{
    return &g_clock;
}

uint64_t hal_time_now_us(hal_time_t *time)
{
    (void)time;
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return ((uint64_t)ts.tv_sec * 1000000U) + ((uint64_t)ts.tv_nsec / 1000U);
}

int hal_time_wait_until_us(hal_time_t *time, uint64_t deadline_us)
{
    (void)time;
    struct timespec ts;
    ts.tv_sec = (time_t)(deadline_us / 1000000U);
    ts.tv_nsec = (long)((deadline_us % 1000000U) * 1000U);
    const int rc = clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
    return (rc == EINTR) ? HAL_EINTR : 0;
}
