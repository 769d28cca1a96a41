/*
 * Unit tests: the J1939 ECU loop (pfe_ecu) driven tick by tick, frames built
 * with the codec, NVM on the test backend (hal/fake). Times are in us.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "hal/fake/hal_fake.h"
#include "pfe_calib.h"
#include "pfe_can.h"
#include "pfe_codec.h"
#include "pfe_ecu.h"
#include "pfe_fixed.h"
#include "pfe_nvm.h"

#include "ecu_harness.h"

#define OTHER_SA 0x00U

static void send_speed(int32_t speed_mm_s, pfe_sig_state_t st)
{
    pfe_can_frame_t f;
    const pfe_msg_ccvs1_t m = {{speed_mm_s, st}};
    ASSERT_GE(pfe_codec_encode_ccvs1(&f, &m, OTHER_SA), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
}

static void send_pitch(int32_t pitch_udeg)
{
    pfe_can_frame_t f;
    const pfe_msg_ssi_t m = {{pitch_udeg, PFE_SIG_VALID}, {0, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_ssi(&f, &m, OTHER_SA), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
}

/* One tick; speed every 100 ms and pitch every 10 ms when asked. */
static void tick(bool speed, bool pitch)
{
    if (speed && ((g_now / 10000U) % 10U == 0U)) {
        send_speed(25000, PFE_SIG_VALID);
    }
    if (pitch) {
        send_pitch(0);
    }
    g_ntx = pfe_ecu_tick(&g_ecu, g_now, g_tx, PFE_ECU_TX_MAX);
    g_now += PFE_ECU_TICK_US;
}

static void test_claims_address_then_keeps_schedule(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    tick(true, true);
    const pfe_can_frame_t *claim = sent(PFE_PGN_ADDRESS_CLAIMED);
    assert_non_null(claim);
    assert_int_equal(claim->id, 0x98EEFF8CUL); /* prio 6, PGN 0xEE00 to global, SA 0x8C */
    static const uint8_t name_bytes[8] = {0x78, 0x56, 0x34, 0x12, 0x00, 0x00, 0xA0, 0x80};
    assert_memory_equal(claim->data, name_bytes, 8);
    assert_int_equal(g_ntx, 1);
    /* Nothing else for 250 ms. */
    for (uint32_t k = 1U; k < 25U; k++) {
        tick(true, true);
        assert_int_equal(g_ntx, 0);
    }
    uint32_t lfe1 = 0U, pf = 0U, hrlfc = 0U, pred = 0U, status = 0U, own = 0U, input = 0U, device = 0U;
    for (uint32_t k = 0U; k < 1000U; k++) { /* 10 s */
        tick(true, true);
        assert_in_range(g_ntx, 0U, 2U);
        lfe1 += (sent(PFE_PGN_LFE1) != NULL) ? 1U : 0U;
        pf += (sent(PFE_PGN_PLATOON_FUEL) != NULL) ? 1U : 0U;
        hrlfc += (sent(PFE_PGN_HRLFC) != NULL) ? 1U : 0U;
        pred += (sent(PFE_PGN_FUEL_PREDICTION) != NULL) ? 1U : 0U;
        status += (sent(PFE_PGN_STATUS) != NULL) ? 1U : 0U;
        own += (sent(PFE_PGN_OWN_FUEL) != NULL) ? 1U : 0U;
        input += (sent(PFE_PGN_INPUT_STATUS) != NULL) ? 1U : 0U;
        device += (sent(PFE_PGN_DEVICE_STATUS) != NULL) ? 1U : 0U;
    }
    /* LFE1 and HRLFC wait three of their periods for another sender: the
     * first LFE1 slot (250 ms after start) and HRLFC's at 0.27, 1.27 and
     * 2.27 s stay silent. */
    assert_int_equal(lfe1, 99);
    assert_int_equal(pf, 100);
    assert_int_equal(hrlfc, 7);
    assert_int_equal(pred, 10);
    assert_int_equal(status, 10);
    assert_int_equal(own, 100);
    assert_int_equal(input, 10);
    assert_int_equal(device, 10);
}

/* Runs until an LFE1 goes out and decodes it. */
static pfe_msg_lfe1_t next_lfe1(bool speed, bool pitch)
{
    for (uint32_t k = 0U; k < 20U; k++) {
        tick(speed, pitch);
        const pfe_can_frame_t *f = sent(PFE_PGN_LFE1);
        if (f != NULL) {
            pfe_msg_lfe1_t m;
            ASSERT_GE(pfe_codec_decode_lfe1(f, &m), 0);
            return m;
        }
    }
    fail_msg("no LFE1 within 200 ms");
    const pfe_msg_lfe1_t none = {{0U, PFE_SIG_ERROR}};
    return none;
}

static pfe_msg_status_t next_status(bool speed, bool pitch)
{
    for (uint32_t k = 0U; k < 110U; k++) {
        tick(speed, pitch);
        const pfe_can_frame_t *f = sent(PFE_PGN_STATUS);
        if (f != NULL) {
            pfe_msg_status_t m;
            ASSERT_GE(pfe_codec_decode_status(f, &m), 0);
            return m;
        }
    }
    fail_msg("no status within 1.1 s");
    pfe_msg_status_t none;
    memset(&none, 0, sizeof none);
    return none;
}

static void test_fuel_rate_on_flat_road(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    for (uint32_t k = 0U; k < 100U; k++) {
        tick(true, true);
    }
    const pfe_msg_lfe1_t m = next_lfe1(true, true);
    assert_int_equal(m.fuel_rate_nl_s.state, PFE_SIG_VALID);
    /* 9.298 mL/s = 33.47 L/h: raw 669 or 670 of 0.05 L/h, decoded back to nL/s. */
    assert_in_range(m.fuel_rate_nl_s.value, 9291666U, 9305556U);
    const pfe_msg_status_t st = next_status(true, true);
    assert_int_equal(st.speed_input, PFE_SIG_VALID);
    assert_int_equal(st.grade_input, PFE_SIG_VALID);
    assert_int_equal(st.platoon_config_input, PFE_SIG_NOT_AVAILABLE);
    assert_int_equal(st.mode.value, PFE_MODE_DEGRADED);
}

static void test_speed_timeout_within_three_periods_and_recovery(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    for (uint32_t k = 0U; k < 100U; k++) {
        tick(true, true);
    }
    /* Last CCVS1 at this tick; then none. */
    while ((g_now / 10000U) % 10U != 0U) {
        tick(true, true);
    }
    const uint64_t last_rx = g_now;
    tick(true, true);
    uint64_t na_at = 0U;
    for (uint32_t k = 0U; (k < 100U) && (na_at == 0U); k++) {
        const uint64_t t = g_now;
        tick(false, true);
        if ((g_ecu.out->flags & PFE_EST_VALID) == 0U) {
            na_at = t;
        }
    }
    ASSERT_GT(na_at, last_rx);
    /* Three periods plus one tick. */
    ASSERT_LE(na_at - last_rx, 300000U + PFE_ECU_TICK_US);
    assert_int_equal(next_lfe1(false, true).fuel_rate_nl_s.state, PFE_SIG_NOT_AVAILABLE);
    pfe_msg_status_t st = next_status(false, true);
    assert_int_equal(st.speed_input, PFE_SIG_NOT_AVAILABLE);
    assert_int_equal(st.mode.value, PFE_MODE_NO_ESTIMATE);
    /* Back: valid again after the filter's warm-up (5 samples). */
    for (uint32_t k = 0U; k < 60U; k++) {
        tick(true, true);
    }
    assert_int_equal(next_lfe1(true, true).fuel_rate_nl_s.state, PFE_SIG_VALID);
}

static void test_grade_timeout_and_sender_error_values(void **state)
{
    (void)state;
    /* With the flat road forbidden, a missing grade means no estimate. */
    pfe_ecu_config_t c = config();
    c.flat_grade_forbidden = true;
    start(&c);
    for (uint32_t k = 0U; k < 100U; k++) {
        tick(true, true);
    }
    /* SSI stops: 3 x 10 ms, plus one tick. */
    tick(true, false);
    tick(true, false);
    tick(true, false);
    assert_int_not_equal(g_ecu.out->flags & PFE_EST_VALID, 0U);
    tick(true, false);
    assert_int_not_equal(g_ecu.out->flags & PFE_EST_GRADE_MISSING, 0U);
    pfe_msg_status_t st = next_status(true, false);
    assert_int_equal(st.grade_input, PFE_SIG_NOT_AVAILABLE);
    /* The sender reports an error in SPN 84: error, no estimate. */
    for (uint32_t k = 0U; k < 50U; k++) {
        if ((g_now / 10000U) % 10U == 0U) {
            send_speed(0, PFE_SIG_ERROR);
        }
        tick(false, true);
    }
    assert_int_equal(g_ecu.out->flags & PFE_EST_VALID, 0U);
    assert_int_equal(g_ecu.in[PFE_IN_SPEED].state, PFE_SIG_ERROR);
    /* Out of range (parameter-specific raw 0xFB00): out of range. */
    pfe_can_frame_t f;
    const pfe_msg_ccvs1_t m = {{25000, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_ccvs1(&f, &m, OTHER_SA), 0);
    f.data[1] = 0x00U;
    f.data[2] = 0xFBU;
    pfe_ecu_receive(&g_ecu, &f, g_now);
    tick(false, true);
    assert_int_equal(g_ecu.in[PFE_IN_SPEED].state, PFE_SIG_OUT_OF_RANGE);
    assert_int_equal(g_ecu.out->flags & PFE_EST_VALID, 0U);
}

static void test_requests(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    for (uint32_t k = 0U; k < 330U; k++) { /* HRLFC is sent 3 s after start, none other sending */
        tick(true, true);
    }
    while ((g_now / 10000U) % 100U != 50U) {
        tick(true, true);
    }
    pfe_can_frame_t f;
    ASSERT_GE(pfe_codec_encode_request(&f, PFE_PGN_HRLFC, PFE_J1939_ADDR_GLOBAL, OTHER_SA), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
    tick(true, true);
    assert_non_null(sent(PFE_PGN_HRLFC));
    /* Addressed to someone else: ignored. */
    ASSERT_GE(pfe_codec_encode_request(&f, PFE_PGN_HRLFC, 0x33U, OTHER_SA), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
    tick(true, true);
    assert_null(sent(PFE_PGN_HRLFC));
    /* Addressed to us, for the address claim. */
    ASSERT_GE(pfe_codec_encode_request(&f, PFE_PGN_ADDRESS_CLAIMED, PFE_ECU_DEFAULT_ADDRESS,
                                       OTHER_SA),
              0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
    tick(true, true);
    assert_non_null(sent(PFE_PGN_ADDRESS_CLAIMED));
    assert_int_equal(g_ecu.count.requests_answered, 2);
}

static void claim_from_other(uint64_t name_value)
{
    pfe_j1939_name_t name;
    pfe_j1939_name_unpack(name_value, &name);
    pfe_can_frame_t f;
    ASSERT_GE(pfe_codec_encode_address_claimed(&f, &name, PFE_ECU_DEFAULT_ADDRESS), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
}

static void test_address_claim_conflicts(void **state)
{
    (void)state;
    pfe_ecu_config_t c = config();
    start(&c);
    tick(true, true);
    /* A higher NAME claims our address: we keep it and say so again. */
    claim_from_other(OUR_NAME + 1U);
    tick(true, true);
    assert_int_equal(pfe_j1939_source(sent(PFE_PGN_ADDRESS_CLAIMED)->id), 0x8C);
    /* A lower NAME: we are arbitrary address capable, so we move to the next
     * self-configurable address (128 .. 247). */
    claim_from_other(0x0000000000000001ULL);
    tick(true, true);
    assert_int_equal(pfe_j1939_source(sent(PFE_PGN_ADDRESS_CLAIMED)->id), 0x8D);
    for (uint32_t k = 0U; k < 40U; k++) {
        tick(true, true);
    }
    assert_int_equal(g_ecu.addr_state, PFE_ECU_ADDR_CLAIMED);

    /* Not arbitrary address capable: cannot claim, then silence. */
    c.name = OUR_NAME & ~(1ULL << 63);
    start(&c);
    tick(true, true);
    claim_from_other(0x0000000000000001ULL);
    tick(true, true);
    const pfe_can_frame_t *cc = sent(PFE_PGN_ADDRESS_CLAIMED);
    assert_non_null(cc);
    assert_int_equal(pfe_j1939_source(cc->id), PFE_J1939_ADDR_NULL);
    for (uint32_t k = 0U; k < 200U; k++) {
        tick(true, true);
        assert_int_equal(g_ntx, 0);
    }
    assert_int_equal(g_ecu.addr_state, PFE_ECU_ADDR_LOST);
}

static void test_counters_reach_the_status_message(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    for (uint32_t k = 0U; k < 30U; k++) {
        tick(true, true);
    }
    for (uint32_t k = 0U; k < PFE_ECU_RX_QUEUE_LEN + 6U; k++) {
        send_pitch(0);
    }
    tick(false, false);
    pfe_ecu_note_overrun(&g_ecu, 3U);
    pfe_ecu_note_tx_dropped(&g_ecu, 2U);
    const pfe_msg_status_t st = next_status(true, true);
    assert_int_equal(st.rx_frames_dropped.value, 6);
    assert_int_equal(st.tick_overruns.value, 3);
    assert_int_equal(st.tx_frames_dropped.value, 2);
    pfe_ecu_note_overrun(&g_ecu, 1000U);
    assert_int_equal(next_status(true, true).tick_overruns.value, PFE_STATUS_COUNTER_MAX);
}

static pfe_msg_fuel_prediction_t next_prediction(void)
{
    for (uint32_t k = 0U; k < 110U; k++) {
        tick(true, true);
        const pfe_can_frame_t *f = sent(PFE_PGN_FUEL_PREDICTION);
        if (f != NULL) {
            pfe_msg_fuel_prediction_t m;
            ASSERT_GE(pfe_codec_decode_fuel_prediction(f, &m), 0);
            return m;
        }
    }
    fail_msg("no prediction within 1.1 s");
    pfe_msg_fuel_prediction_t none;
    memset(&none, 0, sizeof none);
    return none;
}

/* A flat preview of n samples at spacing_m, ten frames a tick with the
 * drive's own frames. */
static void send_flat_preview(uint32_t n, uint32_t spacing_m, uint8_t id)
{
    pfe_can_frame_t f;
    pfe_msg_grade_preview_t m;
    memset(&m, 0, sizeof m);
    m.frame_type.value = PFE_PREVIEW_FRAME_HEADER;
    m.preview_id.value = id;
    m.sample_count.value = n;
    m.spacing_m.value = spacing_m;
    ASSERT_GE(pfe_codec_encode_grade_preview(&f, &m, OTHER_SA), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
    for (uint32_t k = 0U; k < n; k += PFE_PREVIEW_SAMPLES_PER_FRAME) {
        memset(&m, 0, sizeof m);
        m.frame_type.value = PFE_PREVIEW_FRAME_DATA;
        m.preview_id.value = id;
        m.first_index.value = k;
        for (uint32_t j = 0U; j < PFE_PREVIEW_SAMPLES_PER_FRAME; j++) {
            m.grade_ppm[j].state = ((k + j) < n) ? PFE_SIG_VALID : PFE_SIG_NOT_AVAILABLE;
        }
        ASSERT_GE(pfe_codec_encode_grade_preview(&f, &m, OTHER_SA), 0);
        pfe_ecu_receive(&g_ecu, &f, g_now);
        if ((k % 30U) == 27U) {
            tick(true, true);
        }
    }
}

/* One truck, flat 12 km at 90 km/h: (5166 N x 12000 m + 4 kW x 480 s) /
 * (0.40 x 35800 J/mL) = 4.463 L in 480 s; the prediction covers what is left
 * of the preview when it starts, so per metre 0.3719 mL and 40 ms. */
static void test_prediction_over_a_preview(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    for (uint32_t k = 0U; k < 100U; k++) {
        tick(true, true);
    }
    /* No preview: not available. */
    pfe_msg_fuel_prediction_t p = next_prediction();
    assert_int_equal(p.fuel_ul.state, PFE_SIG_NOT_AVAILABLE);
    assert_int_equal(p.time_ms.state, PFE_SIG_NOT_AVAILABLE);
    send_flat_preview(1000U, 12U, 1U);
    /* A prediction is published within two seconds and sent at 1 Hz. */
    for (uint32_t k = 0U; (k < 200U) && !pfe_predict_result(&g_ecu.predict)->valid; k++) {
        tick(true, true);
    }
    const pfe_predict_result_t *r = pfe_predict_result(&g_ecu.predict);
    assert_true(r->valid);
    p = next_prediction();
    assert_int_equal(p.fuel_ul.state, PFE_SIG_VALID);
    assert_int_equal(p.time_ms.state, PFE_SIG_VALID);
    assert_int_equal(p.fuel_lower_ul.state, PFE_SIG_VALID);
    assert_int_equal(p.fuel_upper_ul.state, PFE_SIG_VALID);
    const uint32_t left_m = r->distance_m;
    ASSERT_GT(left_m, 11800U);
    ASSERT_LE(left_m, 12000U);
    /* 0.01 L and 0.1 s on the bus. */
    ASSERT_LE(labs((long)p.fuel_ul.value - (long)(left_m * 371.9)), 10000L);
    ASSERT_LE(labs((long)p.time_ms.value - (long)(left_m * 40U)), 200L);
    /* One truck on a flat road: both bounds are the prediction. */
    ASSERT_LE(labs((long)p.fuel_lower_ul.value - (long)p.fuel_ul.value), 10000L);
    ASSERT_LE(labs((long)p.fuel_upper_ul.value - (long)p.fuel_ul.value), 10000L);
    /* Later predictions start further along. */
    for (uint32_t k = 0U; k < 300U; k++) {
        tick(true, true);
    }
    ASSERT_LT(pfe_predict_result(&g_ecu.predict)->distance_m, left_m - 50U);
    /* A new preview's header abandons the prediction in progress. */
    while (g_ecu.predict.phase == PFE_PREDICT_IDLE) {
        tick(true, true);
    }
    pfe_can_frame_t f;
    pfe_msg_grade_preview_t m;
    memset(&m, 0, sizeof m);
    m.frame_type.value = PFE_PREVIEW_FRAME_HEADER;
    m.preview_id.value = 2U;
    m.sample_count.value = 100U;
    m.spacing_m.value = 10U;
    ASSERT_GE(pfe_codec_encode_grade_preview(&f, &m, OTHER_SA), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
    tick(true, true);
    assert_int_equal(g_ecu.predict.phase, PFE_PREDICT_IDLE);
    assert_int_equal(g_ecu.preview_travelled_um / 1000U, 250U); /* one tick at 25 m/s */
    /* Without a complete preview the prediction is no longer sent. */
    p = next_prediction();
    assert_int_equal(p.fuel_ul.state, PFE_SIG_NOT_AVAILABLE);
}

static bool passes_filters(uint32_t id)
{
    for (uint32_t k = 0U; k < PFE_ECU_RX_FILTERS; k++) {
        if ((id & pfe_ecu_rx_filters[k].mask) ==
            (pfe_ecu_rx_filters[k].id & pfe_ecu_rx_filters[k].mask)) {
            return true;
        }
    }
    return false;
}

/* The receive filters: the ECU's own inputs from any source and priority,
 * requests and claims to any destination; nothing else. */
static void test_receive_filters(void **state)
{
    (void)state;
    assert_true(passes_filters(0x98FEF100UL));  /* CCVS1, priority 6, source 0x00 */
    assert_true(passes_filters(0x8CFEF1FEUL));  /* CCVS1, priority 3, source 0xFE */
    assert_true(passes_filters(0x8CF01313UL));  /* SSI */
    assert_true(passes_filters(0x98FF0017UL));  /* PFE_PlatoonConfig */
    assert_true(passes_filters(0x98FF0133UL));  /* PFE_GradePreview */
    assert_true(passes_filters(0x98EA8C00UL));  /* Request to 0x8C */
    assert_true(passes_filters(0x98EAFF00UL));  /* Request to all */
    assert_true(passes_filters(0x98EEFF10UL));  /* Address Claimed */
    assert_true(passes_filters(0x98FEF200UL));  /* LFE1 of the engine */
    assert_true(passes_filters(0x98FD0900UL));  /* HRLFC of the engine */
    assert_true(passes_filters(0x98FEE817UL));  /* VDS */
    assert_true(passes_filters(0x98FE7027UL));  /* CVW */
    assert_false(passes_filters(0x98FF058CUL)); /* PFE_OwnFuel: an output */
    assert_false(passes_filters(0x98FF0400UL)); /* PFE_Status: an output */
    assert_false(passes_filters(0x18FEF100UL)); /* no EFF flag: an 11-bit id */
    assert_false(passes_filters(0x000007FFUL)); /* 11-bit */
    assert_false(passes_filters(0x99FEF100UL)); /* CCVS1 in data page 1: another PGN */
}

static void test_platoon_config_switches_the_model(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    pfe_can_frame_t f;
    const pfe_msg_platoon_config_t m = {{5U, PFE_SIG_VALID}, {2U, PFE_SIG_VALID},
                                        {10000U, PFE_SIG_VALID}, {0U, PFE_SIG_NOT_AVAILABLE},
                                        {25000, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_platoon_config(&f, &m, OTHER_SA), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
    for (uint32_t k = 0U; k < 100U; k++) {
        tick(true, true);
    }
    assert_int_equal(g_ecu.platoon.n_vehicles, 5);
    assert_int_equal(g_ecu.own_position, 2);
    assert_false(g_ecu.degraded);
    /* The own rate is the third truck's, 35 % drag reduction: below a lone truck's. */
    const pfe_msg_lfe1_t own = next_lfe1(true, true);
    assert_int_equal(own.fuel_rate_nl_s.state, PFE_SIG_VALID);
    ASSERT_LT(own.fuel_rate_nl_s.value, 9291666U);
    /* The config is not repeated: after 3 s it is stale, the module degraded. */
    for (uint32_t k = 0U; k < 300U; k++) {
        tick(true, true);
    }
    assert_true(g_ecu.degraded);
    assert_int_equal(next_status(true, true).platoon_config_input, PFE_SIG_NOT_AVAILABLE);
}

/* A burst of configurations in one tick: the last one wins, decoded once,
 * and its platoon is built over the next ticks (PFE_ECU_REBUILD_PER_TICK
 * trucks a tick, then the switch) while the old one runs; a malformed last
 * one changes nothing. */
static void test_platoon_config_burst_last_wins(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    for (uint32_t k = 0U; k < 16U; k++) {
        pfe_can_frame_t f;
        const pfe_msg_platoon_config_t m = {{3U + (k % 4U), PFE_SIG_VALID}, {k % 3U, PFE_SIG_VALID},
                                            {10000U, PFE_SIG_VALID}, {0U, PFE_SIG_NOT_AVAILABLE},
                                            {25000, PFE_SIG_VALID}};
        ASSERT_GE(pfe_codec_encode_platoon_config(&f, &m, OTHER_SA), 0);
        pfe_ecu_receive(&g_ecu, &f, g_now);
    }
    tick(false, false);
    assert_int_equal(g_ecu.count.rx_frames, 16);
    /* decoded, started and its 6 trucks built; the default platoon (1
     * truck) still runs */
    assert_int_equal(g_ecu.platoon.n_vehicles, 1);
    assert_true(g_ecu.platoon_building);
    tick(false, false); /* the aggregates, and the switch */
    /* the 16th: 3 + 15 % 4 = 6 trucks, position 15 % 3 = 0 */
    assert_false(g_ecu.platoon_building);
    assert_int_equal(g_ecu.platoon.n_vehicles, 6);
    assert_int_equal(g_ecu.own_position, 0);
    assert_false(g_ecu.degraded);
    assert_int_equal(g_ecu.config.state, PFE_SIG_VALID);
    /* The same platoon, built at once, is the same model. */
    pfe_platoon_t once;
    pfe_platoon_config_t pc;
    pfe_platoon_config_uniform(&pc, 6U, 10000U, &pfe_default_vehicle, &pfe_default_env, &pfe_default_drag);
    memset(&once, 0, sizeof once);
    assert_int_equal(pfe_platoon_init(&once, &pc), PFE_OK);
    assert_memory_equal(&once, &g_ecu.platoon, sizeof once);
    const uint32_t rejected = g_ecu.count.rx_rejected;
    pfe_can_frame_t f;
    const pfe_msg_platoon_config_t m = {{4U, PFE_SIG_VALID}, {1U, PFE_SIG_VALID},
                                        {10000U, PFE_SIG_VALID}, {0U, PFE_SIG_NOT_AVAILABLE},
                                        {25000, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_platoon_config(&f, &m, OTHER_SA), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
    f.dlc = 3U;
    pfe_ecu_receive(&g_ecu, &f, g_now);
    for (uint32_t k = 0U; k < 3U; k++) {
        tick(true, true);
    }
    assert_int_equal(g_ecu.count.rx_rejected, rejected + 1U);
    assert_false(g_ecu.platoon_building);
    assert_int_equal(g_ecu.platoon.n_vehicles, 6);
    assert_int_equal(g_ecu.own_position, 0);
}

/* A configuration whose trucks cannot all be built (a calibration of
 * position 5 the platoon refuses): the old platoon comes back, totals kept,
 * the configuration said out of range. */
static void test_platoon_build_that_fails_keeps_the_old_one(void **state)
{
    (void)state;
    pfe_ecu_config_t c = config();
    static pfe_vehicle_calib_t bad;
    bad = pfe_default_vehicle;
    bad.mass_kg = 0U;
    c.vehicle_at[5] = &bad;
    start(&c);
    for (uint32_t k = 0U; k < 100U; k++) {
        tick(true, true);
    }
    const uint64_t own = pfe_ecu_own_fuel_ul(&g_ecu);
    assert_in_range(own, 1000U, 20000U);
    pfe_can_frame_t f;
    const pfe_msg_platoon_config_t m = {{6U, PFE_SIG_VALID}, {0U, PFE_SIG_VALID},
                                        {10000U, PFE_SIG_VALID}, {0U, PFE_SIG_NOT_AVAILABLE},
                                        {25000, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_platoon_config(&f, &m, OTHER_SA), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
    tick(true, true);
    assert_false(g_ecu.platoon_building);
    assert_int_equal(g_ecu.config.state, PFE_SIG_OUT_OF_RANGE);
    assert_int_equal(g_ecu.platoon.n_vehicles, 1);
    assert_int_equal(g_ecu.own_position, 0);
    assert_true(g_ecu.degraded);
    assert_int_equal(pfe_ecu_own_fuel_ul(&g_ecu), own);
}

/* The own truck's mass (CVW) during a build: the build starts again with
 * it, and the platoon it ends with has it. */
static void test_mass_during_a_build(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    pfe_can_frame_t f;
    const pfe_msg_platoon_config_t m = {{20U, PFE_SIG_VALID}, {3U, PFE_SIG_VALID},
                                        {10000U, PFE_SIG_VALID}, {0U, PFE_SIG_NOT_AVAILABLE},
                                        {25000, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_platoon_config(&f, &m, OTHER_SA), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
    tick(false, false); /* started, trucks 0 .. 7 */
    assert_true(g_ecu.platoon_building);
    assert_int_equal(g_ecu.build_done, 8);
    const pfe_msg_cvw_t w = {{8000U, PFE_SIG_VALID}, {30000U, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_cvw(&f, &w, OTHER_SA), 0);
    pfe_ecu_receive(&g_ecu, &f, g_now);
    tick(false, false); /* the mass: started again, trucks 0 .. 7 */
    assert_true(g_ecu.platoon_building);
    assert_int_equal(g_ecu.build_done, 8);
    assert_int_equal(g_ecu.own_calib.mass_kg, 30000);
    tick(false, false); /* 8 .. 15 */
    tick(false, false); /* 16 .. 19 */
    assert_true(g_ecu.platoon_building);
    tick(false, false); /* the aggregates */
    assert_false(g_ecu.platoon_building);
    assert_int_equal(g_ecu.platoon.n_vehicles, 20);
    assert_int_equal(g_ecu.own_position, 3);
    /* 19 trucks of 40 t and ours of 30 t */
    assert_int_equal(g_ecu.platoon.mass_kg, 19U * 40000U + 30000U);
    assert_int_equal(g_ecu.mass_source, PFE_MASS_SOURCE_CVW);
}

/* A failed NVM write: retried on the next tick, to the same slot, with the
 * same sequence; the third failure in a row sets nvm_failing, a completed
 * write clears it and moves on. */
static void test_nvm_write_failure_is_retried(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config(); /* saves every 1 s */
    const pfe_nvm_state_t restored = {7U, 5000U, 6000U, 0U, 0U, 0U};
    start_restored(&c, &restored, 1);
    for (uint32_t k = 0U; (k < 200U) && !pfe_ecu_nvm_due(&g_ecu); k++) {
        tick(true, true);
    }
    assert_true(pfe_ecu_nvm_due(&g_ecu));
    assert_int_equal(pfe_ecu_nvm_slot(&g_ecu), 0);
    for (uint32_t fail = 1U; fail <= 4U; fail++) {
        pfe_nvm_state_t rec;
        memset(&rec, 0xA5, sizeof rec);
        pfe_ecu_nvm_take(&g_ecu, &rec);
        assert_int_equal(rec.sequence, 8);
        pfe_ecu_nvm_written(&g_ecu, HAL_EIO);
        assert_int_equal(g_ecu.count.nvm_write_failures, fail);
        assert_int_equal(g_ecu.nvm_failing, fail >= 3U);
        assert_true(pfe_ecu_nvm_due(&g_ecu));
        assert_int_equal(pfe_ecu_nvm_slot(&g_ecu), 0);
        tick(true, true);
    }
    pfe_nvm_state_t rec;
    pfe_ecu_nvm_take(&g_ecu, &rec);
    assert_int_equal(rec.sequence, 8);
    pfe_ecu_nvm_written(&g_ecu, 0);
    assert_false(g_ecu.nvm_failing);
    assert_false(pfe_ecu_nvm_due(&g_ecu));
    assert_int_equal(pfe_ecu_nvm_slot(&g_ecu), 1);
    assert_int_equal(g_ecu.count.nvm_write_failures, 4);
    pfe_ecu_nvm_take(&g_ecu, &rec);
    assert_int_equal(rec.sequence, 9);
}

/* A full queue: PFE_ECU_RX_PER_TICK frames this tick, the rest the next. */
static void test_full_queue_spreads_over_two_ticks(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    for (uint32_t k = 0U; k < PFE_ECU_RX_QUEUE_LEN; k++) {
        send_pitch(0);
    }
    const uint32_t before = g_ecu.count.rx_frames;
    tick(false, false);
    assert_int_equal(g_ecu.count.rx_frames - before, 32); /* PFE_ECU_RX_PER_TICK */
    tick(false, false);
    assert_int_equal(g_ecu.count.rx_frames - before, 64);
    assert_int_equal(g_ecu.count.rx_dropped, 0);
}

/* 1000 resets at pseudo-random instants, some in the middle of an NVM write. */
static void test_resets_never_lose_more_than_one_save_interval(void **state)
{
    (void)state;
    static hal_nvm_t nvm;
    hal_fake_nvm_init(&nvm);
    const pfe_ecu_config_t c = config(); /* saves every 1 s */
    uint32_t rng = 12345U;
    uint64_t last_restored = 0U;
    uint64_t worst_loss = 0U;
    uint32_t torn = 0U;
    for (uint32_t reset = 0U; reset < 1000U; reset++) {
        uint8_t s0[PFE_NVM_RECORD_SIZE], s1[PFE_NVM_RECORD_SIZE];
        assert_int_equal(hal_nvm_read(&nvm, 0U, s0), 0);
        assert_int_equal(hal_nvm_read(&nvm, 1U, s1), 0);
        pfe_nvm_state_t restored;
        const int slot = pfe_nvm_pick(s0, s1, &restored);
        ASSERT_GE(restored.own_fuel_ul, last_restored);     /* never backwards */
        last_restored = restored.own_fuel_ul;
        start_restored(&c, &restored, slot);
        assert_int_equal(pfe_ecu_own_fuel_ul(&g_ecu), restored.own_fuel_ul);
        rng = (rng * 1103515245U) + 12345U;
        const uint32_t ticks = 1U + ((rng >> 8) % 300U); /* up to 3 s of driving */
        rng = (rng * 1103515245U) + 12345U;
        const bool tear_last = ((rng >> 8) % 4U) == 0U;
        uint64_t saved = restored.own_fuel_ul;
        /* Drive `ticks`; for a quarter of the resets, go on to the next save
         * and reset in the middle of writing it. */
        for (uint32_t k = 0U; (k < ticks) || tear_last; k++) {
            tick(true, true);
            if (pfe_ecu_nvm_due(&g_ecu)) {
                pfe_nvm_state_t rec;
                uint8_t bytes[PFE_NVM_RECORD_SIZE];
                const uint32_t to = pfe_ecu_nvm_slot(&g_ecu);
                pfe_ecu_nvm_take(&g_ecu, &rec);
                pfe_nvm_encode(&rec, bytes);
                if (tear_last && (k >= ticks)) {
                    hal_fake_nvm_tear_next_write(&nvm, (rng >> 12) % PFE_NVM_RECORD_SIZE);
                    assert_int_equal(hal_nvm_write(&nvm, to, bytes), HAL_EIO);
                    torn++;
                    break;
                }
                assert_int_equal(hal_nvm_write(&nvm, to, bytes), 0);
                pfe_ecu_nvm_written(&g_ecu, 0);
                saved = rec.own_fuel_ul;
            }
        }
        const uint64_t at_reset = pfe_ecu_own_fuel_ul(&g_ecu);
        ASSERT_GE(at_reset, saved);
        const uint64_t loss = at_reset - saved;
        worst_loss = (loss > worst_loss) ? loss : worst_loss;
    }
    /* One save interval (1 s) at 9.3 mL/s, plus a tick: 9.4 mL. */
    print_message("resets 1000, torn writes %lu, worst loss %llu uL, final total %llu uL\n", (unsigned long)torn,
                  (unsigned long long)worst_loss, (unsigned long long)last_restored);
    ASSERT_GT(torn, 100U);
    ASSERT_LE(worst_loss, 9400U);
    ASSERT_GT(last_restored, 1000000U);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_claims_address_then_keeps_schedule),
        cmocka_unit_test(test_fuel_rate_on_flat_road),
        cmocka_unit_test(test_speed_timeout_within_three_periods_and_recovery),
        cmocka_unit_test(test_grade_timeout_and_sender_error_values),
        cmocka_unit_test(test_requests),
        cmocka_unit_test(test_address_claim_conflicts),
        cmocka_unit_test(test_counters_reach_the_status_message),
        cmocka_unit_test(test_receive_filters),
        cmocka_unit_test(test_platoon_config_switches_the_model),
        cmocka_unit_test(test_platoon_config_burst_last_wins),
        cmocka_unit_test(test_full_queue_spreads_over_two_ticks),
        cmocka_unit_test(test_platoon_build_that_fails_keeps_the_old_one),
        cmocka_unit_test(test_mass_during_a_build),
        cmocka_unit_test(test_nvm_write_failure_is_retried),
        cmocka_unit_test(test_prediction_over_a_preview),
        cmocka_unit_test(test_resets_never_lose_more_than_one_save_interval),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
