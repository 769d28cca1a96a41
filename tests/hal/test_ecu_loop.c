/*
 * The ECU's main loop (hal/hal_ecu_loop.h) on the test backend: which frames
 * a pass gives the ECU. A pass that runs late (its deadline already past,
 * as when the loop catches up on a missed deadline) takes the frames
 * received by its deadline and holds the later ones for the next pass, in
 * bus order. The pacing (hal_ecu_loop_pace()) runs the ticks a stalled loop
 * missed, so that a stall changes no total, up to its catch-up limit.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"
#include "firmware/pfe_codec.h"
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

/* The node (source 0x00) sends CCVS1 with a wheel-based speed of
 * speed_mm_s at t_us, encoded by the codec (CCVS1.WheelBasedVehicleSpeed). */
static void send_speed_at(rig_t *r, uint64_t t_us, int32_t speed_mm_s)
{
    const uint64_t now = hal_fake_now_us(&r->bus);
    assert_in_range(t_us, now, UINT64_MAX);
    hal_fake_advance_us(&r->bus, t_us - now);
    pfe_can_frame_t f;
    const pfe_msg_ccvs1_t m = {{speed_mm_s, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_ccvs1(&f, &m, 0x00U), 0);
    assert_int_equal(hal_can_send(r->node, &f), 0);
}

/* Deadline arithmetic: on time, late by less than a tick, late by more
 * (one overrun a pass, every tick run), and a stall beyond the catch-up. */
static void test_pace_catches_up_tick_by_tick(void **state)
{
    (void)state;
    rig_t *r = &g_rig;
    rig_start(r);
    const uint64_t d0 = BOOT_US;
    uint64_t deadline = d0;
    assert_int_equal(hal_ecu_loop_pace(&r->loop, &deadline, d0 + 5000U), HAL_ECU_PACE_ON_TIME);
    assert_int_equal(deadline, d0 + 10000U);
    /* Exactly at the next deadline is on time. */
    assert_int_equal(hal_ecu_loop_pace(&r->loop, &deadline, d0 + 20000U), HAL_ECU_PACE_ON_TIME);
    assert_int_equal(deadline, d0 + 20000U);
    /* Half a tick past the next deadline (30 ms): run it now, nothing counted. */
    assert_int_equal(hal_ecu_loop_pace(&r->loop, &deadline, d0 + 35000U), HAL_ECU_PACE_CATCH_UP);
    assert_int_equal(deadline, d0 + 30000U);
    assert_int_equal(r->ecu.count.overruns, 0U);
    /* The pass for 30 ms ends at 75 ms: 40, 50, 60 and 70 ms all run, the
     * first three more than a tick late (one overrun each). */
    const uint64_t now = d0 + 75000U;
    assert_int_equal(hal_ecu_loop_pace(&r->loop, &deadline, now), HAL_ECU_PACE_CATCH_UP);
    assert_int_equal(deadline, d0 + 40000U);
    assert_int_equal(hal_ecu_loop_pace(&r->loop, &deadline, now), HAL_ECU_PACE_CATCH_UP);
    assert_int_equal(deadline, d0 + 50000U);
    assert_int_equal(hal_ecu_loop_pace(&r->loop, &deadline, now), HAL_ECU_PACE_CATCH_UP);
    assert_int_equal(deadline, d0 + 60000U);
    assert_int_equal(hal_ecu_loop_pace(&r->loop, &deadline, now), HAL_ECU_PACE_CATCH_UP);
    assert_int_equal(deadline, d0 + 70000U);
    assert_int_equal(r->ecu.count.overruns, 3U);
    assert_int_equal(hal_ecu_loop_pace(&r->loop, &deadline, now), HAL_ECU_PACE_ON_TIME);
    assert_int_equal(deadline, d0 + 80000U);
    assert_int_equal(r->loop.skipped_ticks, 0U);
    /* The pass for 80 ms ends at 80 + 1025 ms: 101 whole ticks past 90 ms,
     * more than the catch-up's 100: skipped, the next deadline the last tick
     * boundary before now (1100 ms). */
    const uint64_t stall_end = d0 + 80000U + 1025000U;
    assert_int_equal(hal_ecu_loop_pace(&r->loop, &deadline, stall_end), HAL_ECU_PACE_SKIPPED);
    assert_int_equal(r->loop.skipped_ticks, 101U);
    assert_int_equal(r->ecu.count.overruns, 3U + 101U);
    assert_int_equal(deadline, d0 + 1100000U);
    assert_in_range(deadline, stall_end - 10000U, stall_end);
}

/*
 * Drives rig r for `ticks` ticks from BOOT_US: the node sends a speed 2 ms
 * before each deadline, rising from 60 km/h by 1.08 km/h a second; from tick
 * stall_from for stall_ticks ticks the loop runs no pass (a stalled
 * process), then paces as the mains do. Returns the own fuel total, uL.
 */
static uint64_t drive(rig_t *r, uint32_t ticks, uint32_t stall_from, uint32_t stall_ticks)
{
    rig_start(r);
    uint64_t deadline = BOOT_US + 10000U;
    uint32_t sent = 0U;
    while (sent < ticks) {
        /* The node's frames up to the present (a stall does not stop the bus). */
        const uint32_t upto = (sent >= stall_from) && (sent < (stall_from + stall_ticks))
                                  ? (stall_from + stall_ticks)
                                  : (sent + 1U);
        while ((sent < upto) && (sent < ticks)) {
            const uint64_t t = BOOT_US + 10000U * ((uint64_t)sent + 1U) - 2000U;
            send_speed_at(r, t, 16667 + (int32_t)(3U * sent)); /* 60 km/h + 1.08 km/h/s */
            sent++;
        }
        const uint64_t now = BOOT_US + 10000U * (uint64_t)sent;
        hal_fake_advance_us(&r->bus, now - hal_fake_now_us(&r->bus));
        /* Passes due by now, as a main runs them: step, pace, wait. */
        while (deadline <= now) {
            (void)hal_ecu_loop_step(&r->loop, deadline);
            (void)hal_ecu_loop_pace(&r->loop, &deadline, now);
        }
    }
    return pfe_ecu_own_fuel_ul(&r->ecu);
}

/* A 500 ms stall of the loop changes no total: the missed ticks run when it
 * ends, each with the frames received by its own deadline. A 2 s stall is
 * given up on after 1 s: its ticks are skipped, counted, and their fuel is
 * missing. */
static void test_a_stall_loses_no_fuel(void **state)
{
    (void)state;
    static rig_t on_time, stalled, long_stall;
    const uint64_t ref_ul = drive(&on_time, 3000U, UINT32_MAX, 0U);
    const uint64_t stalled_ul = drive(&stalled, 3000U, 1500U, 50U);
    const uint64_t long_ul = drive(&long_stall, 3000U, 1500U, 200U);
    print_message("own fuel: on time %llu uL, 0.5 s stall %llu uL (overruns %u), 2 s stall %llu "
                  "uL (skipped %u)\n",
                  (unsigned long long)ref_ul, (unsigned long long)stalled_ul,
                  (unsigned)stalled.ecu.count.overruns, (unsigned long long)long_ul,
                  (unsigned)long_stall.loop.skipped_ticks);
    assert_in_range(ref_ul, 1U, UINT64_MAX); /* the drive burns fuel */
    assert_int_equal(on_time.ecu.count.overruns, 0U);
    assert_int_equal(stalled_ul, ref_ul);
    assert_int_equal(stalled.loop.skipped_ticks, 0U);
    /* Passes 1502 to 1549 find themselves a tick or more late: 48 overruns
     * (the pass of 1501 was paced before the stall began, 1550 is on time). */
    assert_int_equal(stalled.ecu.count.overruns, 48U);
    assert_int_equal(stalled.ecu.count.rx_frames, on_time.ecu.count.rx_frames);
    /* After the pass of 1501 the loop is 198 ticks behind (1502 to 1699),
     * more than the catch-up's 100: all 198 skipped, about 2 s of fuel at
     * 24.6 L/h missing (13.5 mL). */
    assert_int_equal(long_stall.loop.skipped_ticks, 198U);
    assert_in_range(ref_ul - long_ul, 13000U, 14000U);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_on_time_pass_takes_all),
        cmocka_unit_test(test_late_pass_holds_later_frames),
        cmocka_unit_test(test_no_receive_time_never_held),
        cmocka_unit_test(test_pace_catches_up_tick_by_tick),
        cmocka_unit_test(test_a_stall_loses_no_fuel),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
