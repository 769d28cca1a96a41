/*
 * Unit tests: the ECU on a real truck's bus (can_dbc/pfe.dbc, docs/j1939.md):
 * several senders of one PGN, one of them "not available"; no slope sensor;
 * grade from altitude; the mass from CVW; the engine's own LFE1 and HRLFC;
 * a node that uses the module's address; implausible and random inputs.
 * Frames built with the codec; 10 ms ticks; times in us.
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
#include "pfe_vehicle.h"

#include "ecu_harness.h"

#define ENGINE 0x00U
#define CAB 0x31U
#define GNSS 0x1CU
#define US PFE_ECU_DEFAULT_ADDRESS

static void ccvs1(uint8_t sa, pfe_sig_state_t st, int32_t mm_s)
{
    pfe_can_frame_t f;
    const pfe_msg_ccvs1_t m = {{mm_s, st}};
    ASSERT_GE(pfe_codec_encode_ccvs1(&f, &m, sa), 0);
    receive(&f);
}

static void ssi(uint8_t sa, int32_t pitch_udeg)
{
    pfe_can_frame_t f;
    const pfe_msg_ssi_t m = {{pitch_udeg, PFE_SIG_VALID}, {0, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_ssi(&f, &m, sa), 0);
    receive(&f);
}

static void lfe1(uint8_t sa, pfe_sig_state_t st, uint32_t nl_s)
{
    pfe_can_frame_t f;
    const pfe_msg_lfe1_t m = {{nl_s, st}};
    ASSERT_GE(pfe_codec_encode_lfe1(&f, &m, sa), 0);
    receive(&f);
}

/* What one tick of the bus carries: the engine's CCVS1 every 100 ms (speed),
 * the cab's CCVS1 "not available" 5 ms later, SSI every 10 ms when pitch is
 * set, the engine's LFE1 when engine_lfe1 is set. */
typedef struct {
    int32_t speed_mm_s;
    bool cab;
    bool slope_sensor;
    bool engine_lfe1;
} bus_t;

static void tick_bus(const bus_t *b)
{
    const bool t100 = ((g_now / 10000U) % 10U) == 0U;
    if (t100) {
        ccvs1(ENGINE, PFE_SIG_VALID, b->speed_mm_s);
        if (b->cab) {
            ccvs1(CAB, PFE_SIG_NOT_AVAILABLE, 0);
            lfe1(CAB, PFE_SIG_NOT_AVAILABLE, 0U);
        }
        if (b->engine_lfe1) {
            lfe1(ENGINE, PFE_SIG_VALID, 8000U);
        }
    }
    if (b->slope_sensor) {
        ssi(ENGINE, 0);
    }
    g_ntx = pfe_ecu_tick(&g_ecu, g_now, g_tx, PFE_ECU_TX_MAX);
    g_now += PFE_ECU_TICK_US;
}

static void run(const bus_t *b, uint32_t ticks)
{
    for (uint32_t k = 0U; k < ticks; k++) {
        tick_bus(b);
    }
}

/* Runs until a frame of pgn goes out; fails after max_ticks. */
static const pfe_can_frame_t *run_until(const bus_t *b, uint32_t pgn, uint32_t max_ticks)
{
    for (uint32_t k = 0U; k < max_ticks; k++) {
        tick_bus(b);
        const pfe_can_frame_t *f = sent(pgn);
        if (f != NULL) {
            return f;
        }
    }
    fail_msg("no PGN %u in %u ticks", (unsigned)pgn, (unsigned)max_ticks);
    return NULL;
}

static pfe_msg_input_status_t input_status(const bus_t *b)
{
    pfe_msg_input_status_t m;
    assert_int_equal(pfe_codec_decode_input_status(run_until(b, PFE_PGN_INPUT_STATUS, 110U), &m),
                     PFE_OK);
    return m;
}

static pfe_msg_status_t status(const bus_t *b)
{
    pfe_msg_status_t m;
    assert_int_equal(pfe_codec_decode_status(run_until(b, PFE_PGN_STATUS, 110U), &m), PFE_OK);
    return m;
}

static pfe_msg_own_fuel_t own_fuel(const bus_t *b)
{
    pfe_msg_own_fuel_t m;
    assert_int_equal(pfe_codec_decode_own_fuel(run_until(b, PFE_PGN_OWN_FUEL, 12U), &m), PFE_OK);
    return m;
}

/* The engine sends the speed, the cab "not available" in the same PGN: the
 * module uses the engine's, and says so. */
static void test_two_senders_one_not_available(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    const bus_t b = {25000, true, true, false};
    run(&b, 300U);
    for (uint32_t k = 0U; k < 20U; k++) {
        const pfe_msg_own_fuel_t o = own_fuel(&b);
        assert_int_equal(o.fuel_rate_nl_s.state, PFE_SIG_VALID);
        assert_int_equal(g_ecu.in[PFE_IN_SPEED].state, PFE_SIG_VALID);
    }
    const pfe_msg_input_status_t is = input_status(&b);
    assert_int_equal(is.speed_source.value, ENGINE);
    assert_int_equal(is.speed_senders.value, 2);
    assert_int_equal(is.grade_source.value, PFE_GRADE_SOURCE_SLOPE_SENSOR);
    assert_int_equal(is.grade_source_address.value, ENGINE);
    assert_int_equal(is.mass_source.value, PFE_MASS_SOURCE_CALIBRATION);
    assert_int_equal(is.vehicle_mass_kg.value, 40000);
    assert_int_equal(status(&b).mode.value, PFE_MODE_DEGRADED); /* no platoon config, no preview */
}

/* No slope sensor: the road is assumed flat and the estimate is available;
 * a calibration that forbids it gets no estimate. */
static void test_no_slope_sensor(void **state)
{
    (void)state;
    pfe_ecu_config_t c = config();
    start(&c);
    const bus_t b = {25000, true, false, false};
    run(&b, 300U);
    assert_int_equal(own_fuel(&b).fuel_rate_nl_s.state, PFE_SIG_VALID);
    pfe_msg_input_status_t is = input_status(&b);
    assert_int_equal(is.grade_source.value, PFE_GRADE_SOURCE_ASSUMED_FLAT);
    assert_int_equal(is.grade_source_address.value, 0U); /* raw 255 "None": out of [0, 253] */
    assert_int_equal(is.grade_source_address.state, PFE_SIG_OUT_OF_RANGE);
    pfe_msg_status_t st = status(&b);
    assert_int_equal(st.mode.value, PFE_MODE_DEGRADED);
    assert_int_equal(st.grade_input, PFE_SIG_NOT_AVAILABLE);

    c.flat_grade_forbidden = true;
    start(&c);
    run(&b, 300U);
    assert_int_equal(own_fuel(&b).fuel_rate_nl_s.state, PFE_SIG_NOT_AVAILABLE);
    is = input_status(&b);
    assert_int_equal(is.grade_source.value, PFE_GRADE_SOURCE_NONE);
    assert_int_equal(status(&b).mode.value, PFE_MODE_NO_ESTIMATE);
}

/* No SSI but VDS altitude rising 2 % of the distance driven: after 100 m
 * and more of road the grade in use is 2 % (VDS every second, as J1939-71
 * sends it, at 25 m/s). */
static void test_grade_from_altitude(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    const bus_t b = {25000, false, false, false};
    bool seen = false;
    for (uint32_t k = 0U; k < 1500U; k++) { /* 15 s, 375 m */
        if (((g_now / 10000U) % 100U) == 5U) {
            pfe_can_frame_t f;
            const int32_t alt_mm = 200000 + (int32_t)((g_ecu.odometer_um / 1000U) / 50U);
            const pfe_msg_vds_t m = {{0U, PFE_SIG_NOT_AVAILABLE}, {0, PFE_SIG_NOT_AVAILABLE},
                                     {0, PFE_SIG_NOT_AVAILABLE}, {alt_mm, PFE_SIG_VALID}};
            ASSERT_GE(pfe_codec_encode_vds(&f, &m, GNSS), 0);
            receive(&f);
        }
        tick_bus(&b);
        const pfe_can_frame_t *f = sent(PFE_PGN_INPUT_STATUS);
        if ((f != NULL) && (k > 1000U)) {
            pfe_msg_input_status_t is;
            assert_int_equal(pfe_codec_decode_input_status(f, &is), PFE_OK);
            assert_int_equal(is.grade_source.value, PFE_GRADE_SOURCE_ALTITUDE);
            assert_int_equal(is.grade_source_address.value, GNSS);
            seen = true;
        }
    }
    assert_true(seen);
    assert_int_equal(g_ecu.grade_source, PFE_GRADE_SOURCE_ALTITUDE);
    assert_in_range(g_ecu.grade_ppm, 19000, 21000);
    /* VDS stops: after three periods (3 s) the road is assumed flat */
    run(&b, 301U);
    assert_int_equal(g_ecu.grade_source, PFE_GRADE_SOURCE_ASSUMED_FLAT);
}

/* CVW says 12 t: the own truck's model takes it, the rate falls, the
 * estimator keeps running (no warm-up again). */
static void test_mass_from_cvw(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    const bus_t b = {25000, false, true, false};
    run(&b, 300U);
    const uint32_t rate_40t = own_fuel(&b).fuel_rate_nl_s.value;
    pfe_can_frame_t f;
    const pfe_msg_cvw_t m = {{8000U, PFE_SIG_VALID}, {12000U, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_cvw(&f, &m, 0x27U), 0);
    receive(&f);
    const pfe_msg_own_fuel_t o = own_fuel(&b);
    assert_int_equal(o.fuel_rate_nl_s.state, PFE_SIG_VALID);
    print_message("flat 90 km/h: 40 t %u nL/s, 12 t %u nL/s\n", (unsigned)rate_40t,
                  (unsigned)o.fuel_rate_nl_s.value);
    assert_in_range(o.fuel_rate_nl_s.value, rate_40t / 2U, (rate_40t * 9U) / 10U);
    const pfe_msg_input_status_t is = input_status(&b);
    assert_int_equal(is.mass_source.value, PFE_MASS_SOURCE_CVW);
    assert_int_equal(is.vehicle_mass_kg.value, 12000);
    /* an implausible weight is rejected and changes nothing */
    const pfe_msg_cvw_t bad = {{8000U, PFE_SIG_VALID}, {500U, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_cvw(&f, &bad, 0x27U), 0);
    receive(&f);
    run(&b, 2U);
    assert_int_equal(g_ecu.own_calib.mass_kg, 12000);
}

/* The engine sends LFE1 and HRLFC: the module does not shadow them, and
 * its own estimate goes on in PFE_OwnFuel. */
static void test_does_not_shadow_the_engine(void **state)
{
    (void)state;
    pfe_ecu_config_t c = config();
    start(&c);
    bus_t b = {25000, true, true, true};
    uint32_t lfe1_out = 0U, own = 0U;
    for (uint32_t k = 0U; k < 600U; k++) {
        tick_bus(&b);
        if ((k % 100U) == 50U) {
            pfe_can_frame_t f;
            const pfe_msg_hrlfc_t h = {{0U, PFE_SIG_NOT_AVAILABLE}, {123000U, PFE_SIG_VALID}};
            ASSERT_GE(pfe_codec_encode_hrlfc(&f, &h, ENGINE), 0);
            receive(&f);
        }
        lfe1_out += (sent(PFE_PGN_LFE1) != NULL) ? 1U : 0U;
        assert_null(sent(PFE_PGN_HRLFC));
        own += (sent(PFE_PGN_OWN_FUEL) != NULL) ? 1U : 0U;
    }
    assert_int_equal(lfe1_out, 0);
    assert_int_equal(own, 58);
    assert_int_equal(input_status(&b).fuel_rate_source.value, ENGINE);
    /* the other LFE1 senders stop: after three periods the module sends its own */
    b.engine_lfe1 = false;
    b.cab = false;
    const pfe_can_frame_t *f = run_until(&b, PFE_PGN_LFE1, 50U);
    pfe_msg_lfe1_t m;
    assert_int_equal(pfe_codec_decode_lfe1(f, &m), PFE_OK);
    assert_int_equal(m.fuel_rate_nl_s.state, PFE_SIG_VALID);
    /* a calibration may say never, or always */
    c.j1939_fuel = PFE_ECU_J1939_FUEL_NEVER;
    start(&c);
    b.engine_lfe1 = false;
    for (uint32_t k = 0U; k < 500U; k++) {
        tick_bus(&b);
        assert_null(sent(PFE_PGN_LFE1));
        assert_null(sent(PFE_PGN_HRLFC));
    }
    c.j1939_fuel = PFE_ECU_J1939_FUEL_ALWAYS;
    start(&c);
    b.engine_lfe1 = true;
    (void)run_until(&b, PFE_PGN_LFE1, 40U);
    c.j1939_fuel = (pfe_ecu_j1939_fuel_t)3;
    memset(&g_ecu, 0, sizeof g_ecu);
    assert_int_equal(pfe_ecu_init(&g_ecu, &c, NULL, -1, g_now), PFE_EINVAL);
}

/* Another node sends CCVS1 from the module's own address at 200 km/h: never
 * an input; counted; the module claims its address again, at most once a
 * second however many there are. */
static void test_own_address_from_another_node(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    const bus_t b = {25000, false, true, false};
    run(&b, 300U);
    const uint32_t before = own_fuel(&b).fuel_rate_nl_s.value;
    uint32_t claims = 0U;
    for (uint32_t k = 0U; k < 200U; k++) { /* 2 s of a spoof every 10 ms */
        ccvs1(US, PFE_SIG_VALID, 55556);
        tick_bus(&b);
        claims += (sent(PFE_PGN_ADDRESS_CLAIMED) != NULL) ? 1U : 0U;
        assert_int_equal(g_ecu.speed_mm_s, 25000);
        const pfe_can_frame_t *o = sent(PFE_PGN_OWN_FUEL);
        if (o != NULL) {
            pfe_msg_own_fuel_t m;
            assert_int_equal(pfe_codec_decode_own_fuel(o, &m), PFE_OK);
            assert_int_equal(m.fuel_rate_nl_s.value, before);
        }
    }
    assert_int_equal(claims, 2);
    assert_int_equal(g_ecu.conflicts, 200);
    assert_int_equal(status(&b).address_conflicts.value, 200);
    assert_int_equal(g_ecu.addr_state, PFE_ECU_ADDR_CLAIMED);
}

/* 0 -> 250 km/h in one frame and back: rejected, counted, never used. */
static void test_speed_jump_is_rejected(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    bus_t b = {0, false, true, false};
    run(&b, 300U);
    b.speed_mm_s = 69444; /* 250 km/h */
    run(&b, 20U);         /* two frames: rejected, the old value ages on */
    assert_int_equal(g_ecu.speed_mm_s, 0);
    assert_int_equal(g_ecu.in[PFE_IN_SPEED].rejected, 2);
    b.speed_mm_s = 0;
    run(&b, 100U);
    assert_int_equal(status(&b).inputs_rejected.value, 2);
    assert_int_equal(own_fuel(&b).fuel_rate_nl_s.state, PFE_SIG_VALID);
}

/* Random payloads in CCVS1 from the engine: after three rejections the
 * speed is an error and the fuel rates are not available; no valid rate is
 * ever computed from more than one random sample. */
static void test_random_payloads(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    const bus_t quiet = {25000, false, true, false};
    run(&quiet, 300U);
    uint32_t lcg = 7U;
    uint32_t valid_after = 0U, na = 0U;
    for (uint32_t k = 0U; k < 1000U; k++) {
        if (((g_now / 10000U) % 10U) == 0U) {
            pfe_can_frame_t f;
            f.id = pfe_j1939_id(6U, PFE_PGN_CCVS1, PFE_J1939_ADDR_GLOBAL, ENGINE);
            f.dlc = 8U;
            for (uint32_t i = 0U; i < 8U; i++) {
                lcg = (lcg * 1103515245U) + 12345U;
                f.data[i] = (uint8_t)(lcg >> 24);
            }
            receive(&f);
        }
        if (((g_now / 10000U) % 10U) != 0U) {
            ssi(ENGINE, 0);
        }
        g_ntx = pfe_ecu_tick(&g_ecu, g_now, g_tx, PFE_ECU_TX_MAX);
        g_now += PFE_ECU_TICK_US;
        const pfe_can_frame_t *o = sent(PFE_PGN_OWN_FUEL);
        if ((o != NULL) && (k > 50U)) {
            pfe_msg_own_fuel_t m;
            assert_int_equal(pfe_codec_decode_own_fuel(o, &m), PFE_OK);
            valid_after += (m.fuel_rate_nl_s.state == PFE_SIG_VALID) ? 1U : 0U;
            na += (m.fuel_rate_nl_s.state != PFE_SIG_VALID) ? 1U : 0U;
        }
    }
    print_message("random CCVS1 for 10 s: %u own-fuel frames valid, %u not available, %u rejected\n",
                  (unsigned)valid_after, (unsigned)na, (unsigned)g_ecu.in[PFE_IN_SPEED].rejected);
    assert_in_range(valid_after, 0U, 1U);
    assert_in_range(g_ecu.in[PFE_IN_SPEED].rejected, 50U, 100U);
}

/* The HAL's reports of the CAN controller and the reset cause go out in
 * PFE_DeviceStatus; before the first report they are not available. */
static void test_device_status_reports(void **state)
{
    (void)state;
    const pfe_ecu_config_t c = config();
    start(&c);
    const bus_t b = {25000, false, true, false};
    pfe_msg_device_status_t d;
    assert_int_equal(pfe_codec_decode_device_status(run_until(&b, PFE_PGN_DEVICE_STATUS, 110U), &d),
                     PFE_OK);
    assert_int_equal(d.bus_off.state, PFE_SIG_NOT_AVAILABLE);
    assert_int_equal(d.reset_cause.state, PFE_SIG_NOT_AVAILABLE);
    assert_int_equal(d.nvm_write_failing.value, 0);
    const pfe_ecu_bus_state_t off = {0U, 1U, 255U, 0U, true, true, true};
    pfe_ecu_note_bus_state(&g_ecu, &off);
    assert_int_equal(pfe_codec_decode_device_status(run_until(&b, PFE_PGN_DEVICE_STATUS, 110U), &d),
                     PFE_OK);
    assert_int_equal(d.bus_off.value, 1);
    assert_int_equal(d.tx_error_counter.value, 250);
    const pfe_ecu_bus_state_t bus = {300U, 2U, 130U, 7U, true, true, false};
    pfe_ecu_note_bus_state(&g_ecu, &bus);
    pfe_ecu_note_bus_state(&g_ecu, NULL); /* ignored */
    pfe_ecu_note_reset_cause(&g_ecu, PFE_RESET_WATCHDOG);
    assert_int_equal(pfe_codec_decode_device_status(run_until(&b, PFE_PGN_DEVICE_STATUS, 110U), &d),
                     PFE_OK);
    assert_int_equal(d.rx_fifo_overruns.value, 250); /* held at 250 */
    assert_int_equal(d.bus_off_events.value, 2);
    assert_int_equal(d.error_warning.value, 1);
    assert_int_equal(d.error_passive.value, 1);
    assert_int_equal(d.bus_off.value, 0);
    assert_int_equal(d.tx_error_counter.value, 130);
    assert_int_equal(d.rx_error_counter.value, 7);
    assert_int_equal(d.reset_cause.value, PFE_RESET_WATCHDOG);
    pfe_ecu_note_reset_cause(&g_ecu, (pfe_reset_cause_t)9);
    assert_int_equal(pfe_codec_decode_device_status(run_until(&b, PFE_PGN_DEVICE_STATUS, 110U), &d),
                     PFE_OK);
    assert_int_equal(d.reset_cause.value, PFE_RESET_OTHER);
}

/* A 12 t truck's engine sends its fuel rate (chapter 3 model of the true
 * truck) while it drives rolling speeds on the flat; the module, calibrated
 * for 40 t, identifies the mass, switches its model to it and says so. */
static void test_identifies_the_truck_from_the_engine(void **state)
{
    (void)state;
    pfe_ecu_config_t c = config();
    start(&c);
    pfe_vehicle_calib_t truth = pfe_default_vehicle;
    truth.mass_kg = 12000U;
    pfe_vehicle_t veh;
    assert_int_equal(pfe_vehicle_init(&veh, &truth, &pfe_default_env, 0U), PFE_OK);
    pfe_grade_accel_t flat;
    pfe_grade_accel(0, pfe_default_env.gravity_um_s2, &flat);
    int32_t v = 15000;
    int32_t a = 400000;
    bool identified = false;
    for (uint32_t k = 0U; (k < 40000U) && !identified; k++) { /* up to 400 s */
        if (((g_now / 10000U) % 10U) == 0U) {
            v += a / 10000; /* um/s^2 over 100 ms in mm/s */
            a = (v >= 24000) ? -400000 : ((v <= 14000) ? 400000 : a);
            ccvs1(ENGINE, PFE_SIG_VALID, v);
            const int32_t f = pfe_vehicle_fuel_force_n(&veh, v, a, &flat);
            lfe1(ENGINE, PFE_SIG_VALID, pfe_fuel_rate_nl_s(f, v, veh.power_aux_w, veh.fuel_q20));
        }
        ssi(ENGINE, 0);
        g_ntx = pfe_ecu_tick(&g_ecu, g_now, g_tx, PFE_ECU_TX_MAX);
        g_now += PFE_ECU_TICK_US;
        const pfe_can_frame_t *f = sent(PFE_PGN_OWN_FUEL);
        if (f != NULL) {
            pfe_msg_own_fuel_t o;
            assert_int_equal(pfe_codec_decode_own_fuel(f, &o), PFE_OK);
            identified = o.model_identified.value == 1U;
        }
    }
    assert_true(identified);
    print_message("identified after %.1f s: %u kg, aux %u W\n",
                  (double)(g_now - START_US) / 1e6, (unsigned)g_ecu.own_calib.mass_kg,
                  (unsigned)g_ecu.own_calib.power_aux_w);
    assert_int_equal(g_ecu.mass_source, PFE_MASS_SOURCE_IDENTIFIED);
    assert_in_range(g_ecu.own_calib.mass_kg, 10200U, 13800U); /* +-15 % */
    const bus_t b = {20000, false, true, false};
    const pfe_msg_input_status_t is = input_status(&b);
    assert_int_equal(is.mass_source.value, PFE_MASS_SOURCE_IDENTIFIED);
    assert_int_equal(is.identification.value, 1);
    assert_int_equal(is.vehicle_mass_kg.value, (g_ecu.own_calib.mass_kg + 5U) / 10U * 10U);
    /* NVM keeps the identification across a reset: the module starts with it */
    pfe_nvm_state_t rec;
    pfe_ecu_nvm_take(&g_ecu, &rec);
    assert_int_equal(rec.id_flags, PFE_NVM_ID_VALID | PFE_NVM_ID_CONVERGED);
    assert_int_equal(rec.id_mass_kg, pfe_identify_mass_kg(&g_ecu.identify));
    uint8_t bytes[PFE_NVM_RECORD_SIZE];
    pfe_nvm_encode(&rec, bytes);
    pfe_nvm_state_t back;
    assert_int_equal(pfe_nvm_pick(bytes, NULL, &back), 0);
    const uint32_t mass_before = g_ecu.own_calib.mass_kg;
    const uint64_t now_before = g_now;
    memset(&g_ecu, 0xA5, sizeof g_ecu);
    assert_int_equal(pfe_ecu_init(&g_ecu, &c, &back, 0, g_now), PFE_OK);
    assert_int_equal(g_ecu.mass_source, PFE_MASS_SOURCE_IDENTIFIED);
    assert_int_equal(g_ecu.own_calib.mass_kg, mass_before);
    assert_true(pfe_identify_converged(&g_ecu.identify));
    g_now = now_before;
    /* CVW's mass comes first; the identified aux power stays */
    pfe_can_frame_t cf;
    const pfe_msg_cvw_t w = {{8000U, PFE_SIG_VALID}, {15000U, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_cvw(&cf, &w, 0x27U), 0);
    receive(&cf);
    for (uint32_t k = 0U; k < 1500U; k++) { /* 15 s more of the engine's LFE1 */
        if (((g_now / 10000U) % 10U) == 0U) {
            v += a / 10000;
            a = (v >= 24000) ? -400000 : ((v <= 14000) ? 400000 : a);
            ccvs1(ENGINE, PFE_SIG_VALID, v);
            const int32_t f = pfe_vehicle_fuel_force_n(&veh, v, a, &flat);
            lfe1(ENGINE, PFE_SIG_VALID, pfe_fuel_rate_nl_s(f, v, veh.power_aux_w, veh.fuel_q20));
        }
        ssi(ENGINE, 0);
        g_ntx = pfe_ecu_tick(&g_ecu, g_now, g_tx, PFE_ECU_TX_MAX);
        g_now += PFE_ECU_TICK_US;
    }
    assert_int_equal(g_ecu.mass_source, PFE_MASS_SOURCE_CVW);
    assert_int_equal(g_ecu.own_calib.mass_kg, 15000);
    assert_int_equal(input_status(&b).mass_source.value, PFE_MASS_SOURCE_CVW);
    /* identification off: the calibration stays, and the state is not available */
    c.identification_off = true;
    start(&c);
    for (uint32_t k = 0U; k < 300U; k++) {
        if (((g_now / 10000U) % 10U) == 0U) {
            lfe1(ENGINE, PFE_SIG_VALID, 9000000U);
        }
        tick_bus(&b);
    }
    assert_int_equal(input_status(&b).identification.state, PFE_SIG_NOT_AVAILABLE);
    assert_int_equal(g_ecu.own_calib.mass_kg, 40000);
    /* on measured grade only: a road assumed flat gives identification nothing */
    c.identification_off = false;
    c.identification_needs_grade = true;
    start(&c);
    const bus_t no_ssi = {20000, false, false, false};
    for (uint32_t k = 0U; k < 300U; k++) {
        if (((g_now / 10000U) % 10U) == 0U) {
            lfe1(ENGINE, PFE_SIG_VALID, 9000000U);
        }
        tick_bus(&no_ssi);
    }
    assert_int_equal(pfe_identify_counters(&g_ecu.identify)->samples_used, 0);
}

/* Frames of the new inputs that cannot be decoded are counted and change
 * nothing; a platoon's other trucks may have calibrations of their own; a
 * configuration the module cannot use is refused. */
static void test_bad_frames_and_configurations(void **state)
{
    (void)state;
    pfe_ecu_config_t c = config();
    pfe_vehicle_calib_t heavy = pfe_default_vehicle;
    heavy.mass_kg = 60000U;
    c.vehicle_at[1] = &heavy;
    c.default_vehicles = 2U;
    start(&c);
    assert_int_equal(g_ecu.platoon.n_vehicles, 2);
    assert_int_equal(g_ecu.platoon.mass_kg, 100000); /* 40 t own truck + 60 t behind it */
    const bus_t b = {25000, false, true, false};
    run(&b, 300U);
    static const uint32_t pgns[] = {PFE_PGN_VDS, PFE_PGN_CVW, PFE_PGN_LFE1, PFE_PGN_HRLFC,
                                    PFE_PGN_SSI};
    const uint32_t before = g_ecu.count.rx_rejected;
    for (uint32_t k = 0U; k < 5U; k++) {
        pfe_can_frame_t f;
        memset(&f, 0xFF, sizeof f);
        f.id = pfe_j1939_id(6U, pgns[k], PFE_J1939_ADDR_GLOBAL, 0x27U);
        f.dlc = 5U;
        receive(&f);
    }
    run(&b, 1U);
    assert_int_equal(g_ecu.count.rx_rejected - before, 5);
    /* VDS with the altitude not available from the sender in use */
    pfe_can_frame_t f;
    const pfe_msg_vds_t up = {{0U, PFE_SIG_NOT_AVAILABLE}, {0, PFE_SIG_NOT_AVAILABLE},
                              {0, PFE_SIG_NOT_AVAILABLE}, {100000, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_vds(&f, &up, GNSS), 0);
    receive(&f);
    run(&b, 100U);
    const pfe_msg_vds_t na = {{0U, PFE_SIG_NOT_AVAILABLE}, {0, PFE_SIG_NOT_AVAILABLE},
                              {0, PFE_SIG_NOT_AVAILABLE}, {0, PFE_SIG_NOT_AVAILABLE}};
    ASSERT_GE(pfe_codec_encode_vds(&f, &na, GNSS), 0);
    receive(&f);
    run(&b, 1U);
    assert_int_equal(g_ecu.in[PFE_IN_ALTITUDE].state, PFE_SIG_NOT_AVAILABLE);
    assert_false(g_ecu.altgrade.started);
    /* a calibration names the speed's sender: the engine's is ignored */
    c = config();
    c.input_source_fixed[PFE_IN_SPEED] = true;
    c.input_source[PFE_IN_SPEED] = CAB;
    start(&c);
    run(&b, 100U);
    assert_int_equal(g_ecu.in[PFE_IN_SPEED].state, PFE_SIG_NOT_AVAILABLE);
    assert_int_equal(pfe_input_source(&g_ecu.in[PFE_IN_SPEED]), CAB);
    /* an HRLFC "not available" from another node does not keep the module off it */
    c = config();
    start(&c);
    bool hrlfc = false;
    for (uint32_t k = 0U; (k < 500U) && !hrlfc; k++) {
        if ((k % 100U) == 50U) {
            const pfe_msg_hrlfc_t h = {{0U, PFE_SIG_NOT_AVAILABLE}, {0U, PFE_SIG_NOT_AVAILABLE}};
            ASSERT_GE(pfe_codec_encode_hrlfc(&f, &h, ENGINE), 0);
            receive(&f);
        }
        tick_bus(&b);
        hrlfc = sent(PFE_PGN_HRLFC) != NULL;
    }
    assert_true(hrlfc);
    /* an own truck whose calibration fails its check */
    pfe_vehicle_calib_t bad = pfe_default_vehicle;
    bad.mass_kg = 10U;
    c = config();
    c.own_vehicle = &bad;
    memset(&g_ecu, 0, sizeof g_ecu);
    assert_int_equal(pfe_ecu_init(&g_ecu, &c, NULL, -1, g_now), PFE_EINVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_two_senders_one_not_available),
        cmocka_unit_test(test_no_slope_sensor),
        cmocka_unit_test(test_grade_from_altitude),
        cmocka_unit_test(test_mass_from_cvw),
        cmocka_unit_test(test_does_not_shadow_the_engine),
        cmocka_unit_test(test_own_address_from_another_node),
        cmocka_unit_test(test_speed_jump_is_rejected),
        cmocka_unit_test(test_random_payloads),
        cmocka_unit_test(test_device_status_reports),
        cmocka_unit_test(test_bad_frames_and_configurations),
        cmocka_unit_test(test_identifies_the_truck_from_the_engine),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
