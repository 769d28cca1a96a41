/*
 * The HAL conformance suite (tests/hal/hal_conformance.h) on the bxCAN
 * driver (hal/stm32f4/hal_stm32_can.c): every handle is a bxCAN node of
 * the register model (tests/stm32/bxcan_model.h) on one bus, in the mode
 * where a requested mailbox goes on the bus at once and receivers'
 * interrupts run at once.
 */
#include <stddef.h>
#include <stdio.h>

#include "hal/stm32f4/hal_stm32_can.h"
#include "tests/hal/hal_conformance.h"
#include "hal/stm32f4/hal_stm32_time.h"
#include "tests/stm32/bxcan_model.h"
#include "tests/stm32/reg_model.h"

static hal_can_t g_drivers[BXCAN_MODEL_NODES];
static unsigned g_misuse;

static int model_open(void *ctx, hal_can_t **out)
{
    (void)ctx;
    bxcan_node_t *n = bxcan_node_add();
    if (n == NULL) {
        return HAL_ENOSPC;
    }
    hal_can_t *can = &g_drivers[n - bxcan_bus.node];
    bxcan_node_attach(n, can);
    const int rc = hal_stm32_can_init(can, &n->regs, 250000U);
    if (rc != 0) {
        bxcan_node_remove(n);
        return rc;
    }
    *out = can;
    return 0;
}

static void model_close(void *ctx, hal_can_t *can)
{
    (void)ctx;
    bxcan_node_t *n = bxcan_model_node_of(&can->regs->mcr);
    if (n != NULL) {
        if (n->misuse != 0U) {
            fprintf(stderr, "test_hal_stm32: the driver wrote %u registers RM0090 forbids\n",
                    (unsigned)n->misuse);
            g_misuse += n->misuse;
        }
        bxcan_node_remove(n);
    }
}

static stm32_tim_t g_tim;
static hal_time_t g_time;

int main(void)
{
    bxcan_bus_reset(true);
    /* The real time base over a timer that moves with the bus; its waits
     * are not run here (the timer would not move while one spins). */
    hal_stm32_time_init(&g_time, &g_tim, 84000000U, 0U);
    hal_stm32_time_use(&g_time);
    reg_model_tim = &g_tim;
    const hal_conformance_backend_t backend = {"hal_stm32_can(bxCAN model)", NULL, model_open,
                                               model_close, NULL, 0U, NULL};
    const int failed = hal_conformance_run(&backend);
    return (failed != 0) ? failed : ((g_misuse != 0U) ? 1 : 0);
}
