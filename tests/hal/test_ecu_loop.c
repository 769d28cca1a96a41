/*
 * The ECU's main loop (hal/hal_ecu_loop.h) on the test backend: which frames
 * a pass gives the ECU. A pass that runs late (its deadline already past,
 * as when the loop catches up on a missed deadline) takes the frames
 * received by its deadline and holds the later ones for the next pass, in
 * bus order.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "firmware/pfe_ecu.h"
#include "hal/fake/hal_fake.h"
#include "hal/hal_ecu_loop.h"

#define BOOT_US 1000000U
#define CCVS1_FROM_00 (PFE_CAN_EFF_FLAG | 0x18FEF100U) /* CCVS1, source 0x00 */

typedef struct {
    hal_fake_bus_t bus;
    hal_nvm_t nvm;
    pfe_ecu_t ecu;
    hal_ecu_loop_t loop;
    hal_can_t *node;                   /* another node on the bus */
} rig_t;

static rig_t g_rig;

static void rig_start(rig_t *r)
{
    hal_fake_bus_init(&r->bus);
    hal_fake_nvm_init(&r->nvm);
    hal_can_t *can = hal_fake_open(&r->bus);
    r->node = hal_fake_open(&r->bus);
    assert_non_null(can);
    assert_non_null(r->node);
    pfe_ecu_config_t cfg;
    hal_ecu_loop_config(&cfg, 0x80U, 60000U, 5U, 0U, 10000U);
    hal_fake_advance_us(&r->bus, BOOT_US);
    assert_int_equal(hal_ecu_loop_init(&r->loop, &r->ecu, &cfg, can, &r->nvm, BOOT_US), PFE_OK);
}

/* The node sends a CCVS1 frame (speed byte `tag`) at bus time t_us. */
static void send_ccvs1_at(rig_t *r, uint64_t t_us, uint8_t tag)
{
    const uint64_t now = hal_fake_now_us(&r->bus);
    assert_in_range(t_us, now, UINT64_MAX);
    hal_fake_advance_us(&r->bus, t_us - now);
    pfe_can_frame_t f;
    (void)memset(&f, 0, sizeof f);
    f.id = CCVS1_FROM_00;
    f.dlc = 8U;
    (void)memset(f.data, 0xFF, sizeof f.data);
    f.data[2] = tag;
    assert_int_equal(hal_can_send(r->node, &f), 0);
}

static uint32_t taken(const rig_t *r)
{
    return r->ecu.count.rx_frames;
}

/* On time: every frame received since the last deadline goes in. */
static void test_on_time_pass_takes_all(void **state)
{
    (void)state;
    rig_t *r = &g_rig;
    rig_start(r);
    (void)hal_ecu_loop_step(&r->loop, BOOT_US + 10000U);
    const uint32_t before = taken(r);
    send_ccvs1_at(r, BOOT_US + 12000U, 1U);
    send_ccvs1_at(r, BOOT_US + 20000U, 2U); /* at the deadline itself: in */
    (void)hal_ecu_loop_step(&r->loop, BOOT_US + 20000U);
    assert_int_equal(taken(r) - before, 2);
    assert_false(r->loop.have_held);
}

/* Late: the pass for 20 ms runs at 25 ms. The frame of 23 ms is the next
 * pass's; the one of 15 ms is this one's. */
static void test_late_pass_holds_later_frames(void **state)
{
    (void)state;
    rig_t *r = &g_rig;
    rig_start(r);
    (void)hal_ecu_loop_step(&r->loop, BOOT_US + 10000U);
    const uint32_t before = taken(r);
    send_ccvs1_at(r, BOOT_US + 15000U, 1U);
    send_ccvs1_at(r, BOOT_US + 23000U, 2U);
    send_ccvs1_at(r, BOOT_US + 24000U, 3U);
    (void)hal_ecu_loop_step(&r->loop, BOOT_US + 20000U);
    assert_int_equal(taken(r) - before, 1);
    assert_true(r->loop.have_held);
    assert_int_equal(r->loop.held.frame.data[2], 2);
    assert_int_equal(r->loop.held.timestamp_us, BOOT_US + 23000U);
    /* A second late pass before 23 ms still holds it. */
    (void)hal_ecu_loop_step(&r->loop, BOOT_US + 22000U);
    assert_int_equal(taken(r) - before, 1);
    /* The pass for 30 ms takes the held frame and the one after it, in order. */
    (void)hal_ecu_loop_step(&r->loop, BOOT_US + 30000U);
    assert_int_equal(taken(r) - before, 3);
    assert_false(r->loop.have_held);
}

/* A backend that gives no receive time (0) is never held back. */
static void test_no_receive_time_never_held(void **state)
{
    (void)state;
    rig_t *r = &g_rig;
    rig_start(r);
    (void)hal_ecu_loop_step(&r->loop, BOOT_US + 10000U);
    const uint32_t before = taken(r);
    hal_can_rx_t rx;
    (void)memset(&rx, 0, sizeof rx);
    rx.frame.id = CCVS1_FROM_00;
    rx.frame.dlc = 8U;
    r->loop.held = rx; /* as if received with timestamp 0 */
    r->loop.have_held = true;
    (void)hal_ecu_loop_step(&r->loop, BOOT_US + 20000U);
    assert_int_equal(taken(r) - before, 1);
    assert_false(r->loop.have_held);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_on_time_pass_takes_all),
        cmocka_unit_test(test_late_pass_holds_later_frames),
        cmocka_unit_test(test_no_receive_time_never_held),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
