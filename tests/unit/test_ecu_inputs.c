/*
 * Unit tests: what the J1939 ECU loop (pfe_ecu) does with a configuration
 * it must refuse, with frames it must reject, with a platoon configuration
 * it cannot use, and when it cannot send: each case counted where pfe_ecu.h
 * says. Frames built with the codec; times in us.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "pfe_calib.h"
#include "pfe_can.h"
#include "pfe_codec.h"
#include "pfe_ecu.h"
#include "pfe_fixed.h"

#include "ecu_harness.h"

#define OTHER_SA 0x00U
#define FIXED_NAME 0x00A0000012345678ULL /* not arbitrary address capable */

static void tick(void)
{
    g_ntx = pfe_ecu_tick(&g_ecu, g_now, g_tx, PFE_ECU_TX_MAX);
    g_now += PFE_ECU_TICK_US;
}

/* Past the claim (250 ms) with nothing else on the bus. */
static void start_claimed(const pfe_ecu_config_t *c)
{
    start(c);
    for (uint32_t k = 0U; k < 26U; k++) {
        tick();
    }
    assert_int_equal(g_ecu.addr_state, PFE_ECU_ADDR_CLAIMED);
}

static pfe_msg_platoon_config_t platoon_config(uint32_t n, uint32_t position, uint32_t gap_mm)
{
    const pfe_msg_platoon_config_t m = {{n, PFE_SIG_VALID}, {position, PFE_SIG_VALID},
                                        {gap_mm, PFE_SIG_VALID}, {0U, PFE_SIG_NOT_AVAILABLE},
                                        {25000, PFE_SIG_VALID}};
    return m;
}

static void send_platoon_config(const pfe_msg_platoon_config_t *m)
{
    pfe_can_frame_t f;
    ASSERT_GE(pfe_codec_encode_platoon_config(&f, m, OTHER_SA), 0);
    receive(&f);
}

static void test_refuses_bad_configurations(void **state)
{
    (void)state;
    pfe_ecu_config_t c = config();
    assert_int_equal(pfe_ecu_init(NULL, &c, NULL, -1, 0U), PFE_EINVAL);
    assert_int_equal(pfe_ecu_init(&g_ecu, NULL, NULL, -1, 0U), PFE_EINVAL);
    c.save_interval_ms = 999U;
    assert_int_equal(pfe_ecu_init(&g_ecu, &c, NULL, -1, 0U), PFE_EINVAL);
    c = config();
    c.save_interval_ms = 3600001U;
    assert_int_equal(pfe_ecu_init(&g_ecu, &c, NULL, -1, 0U), PFE_EINVAL);
    c = config();
    c.preferred_address = 254U; /* the null address */
    assert_int_equal(pfe_ecu_init(&g_ecu, &c, NULL, -1, 0U), PFE_EINVAL);
    c = config();
    const pfe_cruise_calib_t no_gain = {0U, 20U};
    c.cruise = &no_gain;
    assert_int_equal(pfe_ecu_init(&g_ecu, &c, NULL, -1, 0U), PFE_EINVAL);
    c = config();
    c.default_set_speed_mm_s = 999; /* below the stall speed */
    assert_int_equal(pfe_ecu_init(&g_ecu, &c, NULL, -1, 0U), PFE_EINVAL);
    c.default_set_speed_mm_s = 70001;
    assert_int_equal(pfe_ecu_init(&g_ecu, &c, NULL, -1, 0U), PFE_EINVAL);
    c = config();
    c.default_position = 1U; /* of a platoon of 1 */
    assert_int_equal(pfe_ecu_init(&g_ecu, &c, NULL, -1, 0U), PFE_EINVAL);
    c = config();
    c.vehicle = NULL;
    assert_int_equal(pfe_ecu_init(&g_ecu, &c, NULL, -1, 0U), PFE_EINVAL);
}

static void test_defaults_for_cruise_and_set_speed(void **state)
{
    (void)state;
    pfe_ecu_config_t c = config();
    c.cruise = NULL;
    c.default_set_speed_mm_s = 0;
    start(&c);
    assert_ptr_equal(g_ecu.cfg.cruise, &pfe_default_cruise);
    assert_int_equal(g_ecu.cfg.default_set_speed_mm_s, 25000);
}

static void test_rejects_and_counts_bad_frames(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start_claimed(&c);
    pfe_can_frame_t f;

    /* An 11-bit frame. */
    memset(&f, 0, sizeof f);
    f.id = 0x123U;
    f.dlc = 8U;
    receive(&f);
    tick();
    assert_int_equal(g_ecu.count.rx_rejected, 1);

    /* CCVS1, SSI, PFE_PlatoonConfig and a Request one byte short. */
    const pfe_msg_ccvs1_t speed = {{25000, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_ccvs1(&f, &speed, OTHER_SA), 0);
    f.dlc = 7U;
    receive(&f);
    const pfe_msg_ssi_t ssi = {{0, PFE_SIG_VALID}, {0, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_ssi(&f, &ssi, OTHER_SA), 0);
    f.dlc = 7U;
    receive(&f);
    const pfe_msg_platoon_config_t pc = platoon_config(2U, 1U, 10000U);
    ASSERT_GE(pfe_codec_encode_platoon_config(&f, &pc, OTHER_SA), 0);
    f.dlc = 7U;
    receive(&f);
    assert_int_equal(pfe_codec_encode_request(&f, PFE_PGN_LFE1, PFE_J1939_ADDR_GLOBAL, OTHER_SA),
                     PFE_OK);
    f.dlc = 2U;
    receive(&f);
    tick();
    assert_int_equal(g_ecu.count.rx_rejected, 5);
    /* None of them touched an input. */
    assert_int_equal(g_ecu.in[PFE_IN_SPEED].state, PFE_SIG_NOT_AVAILABLE);
    assert_int_equal(g_ecu.in[PFE_IN_GRADE].state, PFE_SIG_NOT_AVAILABLE);
    assert_int_equal(g_ecu.config.state, PFE_SIG_NOT_AVAILABLE);
    assert_int_equal(g_ecu.count.requests_answered, 0);

    /* A PGN the module does not read: ETC1 (0xF002). */
    memset(&f, 0xFF, sizeof f);
    f.id = pfe_j1939_id(3U, 0xF002U, PFE_J1939_ADDR_GLOBAL, OTHER_SA);
    f.dlc = 8U;
    receive(&f);
    tick();
    assert_int_equal(g_ecu.count.rx_rejected, 6);
    assert_int_equal(g_ecu.count.rx_frames, 6);
}

static void test_platoon_config_it_cannot_use(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start_claimed(&c);
    assert_true(g_ecu.degraded);

    /* No gap and no time gap: not available, the module stays degraded on
     * its default platoon. */
    pfe_msg_platoon_config_t m = platoon_config(3U, 1U, 0U);
    m.gap_mm.state = PFE_SIG_NOT_AVAILABLE;
    send_platoon_config(&m);
    tick();
    assert_int_equal(g_ecu.config.state, PFE_SIG_NOT_AVAILABLE);
    assert_int_equal(g_ecu.platoon.n_vehicles, 1);
    assert_true(g_ecu.degraded);

    /* A valid one: 3 trucks 12 m apart, ours second; built in two ticks
     * (PFE_ECU_REBUILD_PER_TICK trucks, then the switch). */
    m = platoon_config(3U, 1U, 12000U);
    send_platoon_config(&m);
    tick();
    assert_int_equal(g_ecu.platoon.n_vehicles, 1);
    tick();
    assert_int_equal(g_ecu.config.state, PFE_SIG_VALID);
    assert_int_equal(g_ecu.platoon.n_vehicles, 3);
    assert_int_equal(g_ecu.platoon.gap_mm, 12000);
    assert_int_equal(g_ecu.own_position, 1);
    assert_false(g_ecu.degraded);

    /* The same again changes nothing. */
    send_platoon_config(&m);
    tick();
    assert_int_equal(g_ecu.config.state, PFE_SIG_VALID);
    assert_int_equal(g_ecu.platoon.gap_mm, 12000);

    /* Our position 3 of 3 trucks: out of range; the platoon is kept. */
    m = platoon_config(3U, 3U, 20000U);
    send_platoon_config(&m);
    tick();
    assert_int_equal(g_ecu.config.state, PFE_SIG_OUT_OF_RANGE);
    assert_int_equal(g_ecu.platoon.gap_mm, 12000);
    assert_int_equal(g_ecu.own_position, 1);

    /* No gap but a time gap: 800 ms at 25000 mm/s is 20000 mm. */
    m = platoon_config(3U, 2U, 0U);
    m.gap_mm.state = PFE_SIG_NOT_AVAILABLE;
    m.time_gap_ms.value = 800U;
    m.time_gap_ms.state = PFE_SIG_VALID;
    send_platoon_config(&m);
    tick();
    tick();
    assert_int_equal(g_ecu.config.state, PFE_SIG_VALID);
    assert_int_equal(g_ecu.platoon.gap_mm, 20000);
    assert_int_equal(g_ecu.own_position, 2);
}

static void test_frames_it_cannot_send_are_counted(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    /* The first tick sends the address claim: with room for none, it is
     * dropped and counted. */
    g_ntx = pfe_ecu_tick(&g_ecu, g_now, g_tx, 0U);
    assert_int_equal(g_ntx, 0);
    assert_int_equal(g_ecu.count.tx_dropped, 1);
    assert_int_equal(g_ecu.count.tx_frames, 0);
}

static void test_reported_drops_saturate(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    pfe_ecu_note_rx_dropped(&g_ecu, 7U);
    assert_int_equal(g_ecu.count.rx_dropped, 7);
    pfe_ecu_note_rx_dropped(&g_ecu, UINT32_MAX - 3U);
    assert_int_equal(g_ecu.count.rx_dropped, UINT32_MAX);
    pfe_ecu_note_rx_dropped(&g_ecu, 1U);
    assert_int_equal(g_ecu.count.rx_dropped, UINT32_MAX);
}

/* A module that cannot pick another address loses it to a lower NAME, then
 * answers a request for Address Claimed with "cannot claim" (source 254). */
static void test_lost_address_answers_cannot_claim(void **state)
{
    (void)state;
    pfe_ecu_config_t c = config();
    c.name = FIXED_NAME;
    start_claimed(&c);
    pfe_can_frame_t f;
    pfe_j1939_name_t lower;
    pfe_j1939_name_unpack(FIXED_NAME - 1U, &lower);
    assert_int_equal(pfe_codec_encode_address_claimed(&f, &lower, PFE_ECU_DEFAULT_ADDRESS), PFE_OK);
    receive(&f);
    tick();
    assert_int_equal(g_ecu.addr_state, PFE_ECU_ADDR_LOST);
    assert_int_equal(g_ecu.count.claims_lost, 1);
    const pfe_can_frame_t *cannot = sent(PFE_PGN_ADDRESS_CLAIMED);
    assert_non_null(cannot);
    assert_int_equal(pfe_j1939_source(cannot->id), PFE_J1939_ADDR_NULL);

    assert_int_equal(pfe_codec_encode_request(&f, PFE_PGN_ADDRESS_CLAIMED, PFE_J1939_ADDR_GLOBAL,
                                              OTHER_SA),
                     PFE_OK);
    receive(&f);
    tick();
    assert_int_equal(g_ecu.count.requests_answered, 1);
    assert_int_equal(g_ntx, 1);
    assert_int_equal(pfe_j1939_pgn(g_tx[0].id), PFE_PGN_ADDRESS_CLAIMED);
    assert_int_equal(pfe_j1939_source(g_tx[0].id), PFE_J1939_ADDR_NULL);
    /* A second claim for the same address from yet another NAME changes
     * nothing: the module no longer holds it. */
    assert_int_equal(pfe_codec_encode_address_claimed(&f, &lower, PFE_ECU_DEFAULT_ADDRESS), PFE_OK);
    receive(&f);
    tick();
    assert_int_equal(g_ecu.count.claims_lost, 1);
    assert_int_equal(g_ntx, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refuses_bad_configurations),
        cmocka_unit_test(test_defaults_for_cruise_and_set_speed),
        cmocka_unit_test(test_rejects_and_counts_bad_frames),
        cmocka_unit_test(test_platoon_config_it_cannot_use),
        cmocka_unit_test(test_frames_it_cannot_send_are_counted),
        cmocka_unit_test(test_reported_drops_saturate),
        cmocka_unit_test(test_lost_address_answers_cannot_claim),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
