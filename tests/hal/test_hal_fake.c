/*
 * The HAL conformance suite (tests/hal/hal_conformance.h) on the test
 * backend (hal/fake), so that every backend the ECU tests rely on behaves
 * like the SocketCAN one.
 */
#include <stddef.h>

#include "hal/fake/hal_fake.h"
#include "tests/hal/hal_conformance.h"

static hal_fake_bus_t g_bus;

static int fake_open(void *ctx, hal_can_t **out)
{
    hal_can_t *h = hal_fake_open((hal_fake_bus_t *)ctx);
    if (h == NULL) {
        return HAL_ENOSPC;
    }
    *out = h;
    return 0;
}

static void fake_close(void *ctx, hal_can_t *can)
{
    (void)ctx;
    hal_fake_close(can);
}

/* The clock moves only when told: a millisecond per idle call keeps the
 * timestamps the suite compares increasing. */
static void fake_idle(void *ctx)
{
    hal_fake_advance_us((hal_fake_bus_t *)ctx, 1000U);
}

int main(void)
{
    hal_fake_bus_init(&g_bus);
    const hal_conformance_backend_t backend = {"hal_fake", &g_bus, fake_open, fake_close,
                                               fake_idle, 0U, hal_fake_time(&g_bus)};
    return hal_conformance_run(&backend);
}
