/*
 * hal_conformance.h - one CMocka suite that every CAN backend of
 * hal/hal_can.h must pass (SocketCAN on vcan0, the fake bus, an MCU).
 *
 * A backend test fills a hal_conformance_backend_t and calls
 * hal_conformance_run() from its main(). Each test opens two handles on the
 * same bus, one that sends and one that receives, and closes them at its end:
 * so the bus must deliver a frame sent on one handle to the other, and must
 * carry no other traffic while the suite runs.
 *
 * What the suite checks: round trips of standard and extended frames of 0 to
 * 8 bytes in send order; HAL_EAGAIN from an empty receive queue; that a sender
 * does not receive its own frames; HAL_EINVAL for frames that cannot exist;
 * filters (a J1939 PGN with priority and source address masked, several
 * filters, removal, HAL_ENOSPC after HAL_CAN_MAX_FILTERS); non-decreasing
 * timestamps; statistics; the clock: never decreasing, waits that reach
 * their deadline, a deadline in the past returning at once.
 *
 * A filter test never waits for a frame that must not come: it sends the
 * rejected frames, then one that is accepted, and checks that the accepted
 * one arrives first (frames arrive in bus order).
 */
#ifndef HAL_CONFORMANCE_H
#define HAL_CONFORMANCE_H

#include <stdint.h>

#include "hal/hal_can.h"
#include "hal/hal_time.h"

typedef struct {
    const char *name;   /* the CMocka group's name, e.g. "hal_socketcan(vcan0)" */
    void *ctx;          /* passed to every hook below */
    /* Opens one more handle on the shared bus: 0 and *out, or a HAL_E* code. */
    int (*open)(void *ctx, hal_can_t **out);
    void (*close)(void *ctx, hal_can_t *can);
    /* Called while a test waits for a frame that is on its way: sleep a
     * little (a kernel delivers in a soft interrupt), or move a simulated
     * bus on. NULL: the backend delivers during hal_can_send. */
    void (*idle)(void *ctx);
    /* How many idle calls a frame may take to arrive before the test counts
     * it lost (0: must be there right after hal_can_send). */
    uint32_t max_idle;
    /* The backend's clock (hal/hal_time.h), checked too when not NULL. */
    hal_time_t *time;
} hal_conformance_backend_t;

/*
 * Runs the whole suite on BACKEND and prints CMocka's report. Returns the
 * number of failed tests (0: conforms). Not reentrant: one run at a time.
 */
int hal_conformance_run(const hal_conformance_backend_t *backend);

#endif /* HAL_CONFORMANCE_H */
