/*
 * ecu_harness.h - what the ECU loop tests (test_ecu.c, test_ecu_inputs.c,
 * test_ecu_bus.c) share: one module under test with the default truck, its
 * clock, the frames its last tick sent, and the calls that start it, feed it
 * a frame and find a frame it sent.
 *
 * Include once per test program, after <cmocka.h>: it holds that program's
 * state (static) and small static inline functions, so that the three tests
 * keep their build rule (one source file each, on the host and on the
 * Cortex-M4). Times are in us.
 */
#ifndef PFE_TESTS_ECU_HARNESS_H
#define PFE_TESTS_ECU_HARNESS_H

#include <stdint.h>
#include <string.h>

#include "pfe_calib.h"
#include "pfe_can.h"
#include "pfe_ecu.h"
#include "pfe_nvm.h"

#define OUR_NAME 0x80A0000012345678ULL /* arbitrary address capable */
#define START_US 1000000U              /* the time start() sets: 1 s */

static pfe_ecu_t g_ecu;
static uint64_t g_now;
static pfe_can_frame_t g_tx[PFE_ECU_TX_MAX];
static uint32_t g_ntx;

/* The bundled default truck at the default address, one truck, 90 km/h set. */
static inline pfe_ecu_config_t config(void)
{
    const pfe_ecu_config_t c = {
        .preferred_address = PFE_ECU_DEFAULT_ADDRESS,
        .name = OUR_NAME,
        .save_interval_ms = 1000U,
        .vehicle = &pfe_default_vehicle,
        .env = &pfe_default_env,
        .drag = &pfe_default_drag,
        .default_vehicles = 1U,
        .default_position = 0U,
        .default_gap_mm = 10000U,
        .cruise = &pfe_default_cruise,
        .default_set_speed_mm_s = 25000,
    };
    return c;
}

/* pfe_ecu_init at START_US from a restored NVM state (NULL, slot -1: none),
 * on a module filled with 0xA5 so that a field init forgets shows. */
static inline void start_restored(const pfe_ecu_config_t *c, const pfe_nvm_state_t *restored,
                                  int slot)
{
    g_now = START_US;
    memset(&g_ecu, 0xA5, sizeof g_ecu);
    assert_int_equal(pfe_ecu_init(&g_ecu, c, restored, slot, g_now), PFE_OK);
}

/* A first start: nothing restored. */
static inline void start(const pfe_ecu_config_t *c)
{
    start_restored(c, NULL, -1);
}

/* One frame received now. */
static inline void receive(const pfe_can_frame_t *f)
{
    pfe_ecu_receive(&g_ecu, f, g_now);
}

/* The first frame of PGN pgn the last tick sent, or NULL. */
static inline const pfe_can_frame_t *sent(uint32_t pgn)
{
    for (uint32_t k = 0U; k < g_ntx; k++) {
        if (pfe_j1939_pgn(g_tx[k].id) == pgn) {
            return &g_tx[k];
        }
    }
    return NULL;
}

#endif /* PFE_TESTS_ECU_HARNESS_H */
