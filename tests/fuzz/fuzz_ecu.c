/*
 * fuzz_ecu.c - libFuzzer target: sequences of CAN frames and time steps into
 * the ECU (firmware/pfe_ecu.h), grade previews and platoon configurations
 * included so that the predictor (firmware/pfe_predict.h) runs.
 *
 * Input (every field little endian; missing bytes read as 0):
 *   4 bytes   start-up: default vehicles - 1 (mod 32); default position
 *             (mod n, bits 0-4), save interval (bits 5-6: 1, 2, 10, 3600 s),
 *             arbitrary address capable (bit 7); default gap in 0.5 m;
 *             bit 0: restore fuel totals (16 bytes follow: own, platoon uL)
 *   then operations, each an op byte (bits 0-2 the kind, 3-7 a parameter p):
 *     0 RAW      id (4), dlc (mod 9), 8 data bytes: any frame at all
 *     1 PGN      an id of the module's PGNs (p), source, destination, dlc
 *                (mod 9), 8 data bytes: right PGN, any content (VDS, CVW,
 *                another node's LFE1 and HRLFC, and the module's own
 *                address as a source among them)
 *     2 SPEED    CCVS1 with the raw 16-bit speed given (2 bytes)
 *     3 PITCH    SSI with the raw 16-bit pitch given (2 bytes), states (p)
 *     4 CONFIG   PFE_PlatoonConfig: vehicles, position, gap (2, 10 mm),
 *                time gap (2, ms), set speed (2, raw), states (p)
 *     5 PREVIEW  a whole PFE_GradePreview burst, two frames per tick:
 *                count (2), spacing, first grade (int8, 2000 ppm), slope
 *                (int8, 20 ppm per sample), faults (a frame dropped,
 *                repeated, a sample not available, cut short, id changed)
 *     6 RUN      1 + byte + 256 * (p & 3) ticks; p & 4: speed and pitch
 *                sent on their schedule meanwhile (the last values given)
 *     7 MISC     p & 7: 0 time jump (4 bytes, us) and a tick; 1, 2, 3 the
 *                main loop reports overruns, tx drops, rx drops (1 byte);
 *                4 a flood of 70 frames in one tick; 5 set the speed and
 *                pitch sent by RUN (4 bytes); 6 a tick with a small tx
 *                capacity (mod 17); 7 a reset: the ECU restarts from what
 *                it saved in NVM
 *
 * Invariants (abort on failure): a tick sends at most its capacity and at
 * most PFE_ECU_TX_MAX frames; every frame sent is one of the module's
 * outputs, 29-bit, with its DBC length, from its address, and decodes;
 * HRLFC and PFE_OwnFuel carry the own truck's total rounded to 0.001 L (or
 * its limit, and then every status after it says OutputSaturated);
 * PFE_InputStatus and PFE_DeviceStatus decode, and the mass in use stays in
 * the calibration's range;
 * a prediction sent lies within its own bounds;
 * total fuel (own truck and platoon) never decreases between resets, and a
 * reset restores exactly the last record saved; every NVM record decodes
 * back to what was saved.
 *
 * With FUZZ_TRACE set in the environment it prints every prediction sent.
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "fuzz_check.h"
#include "pfe_calib.h"
#include "pfe_can.h"
#include "pfe_codec.h"
#include "pfe_ecu.h"
#include "pfe_fixed.h"
#include "pfe_nvm.h"

#define MAX_TICKS 6000U        /* per input: keeps an execution short */
#define OTHER_SA 0x00U
#define NAME_BASE 0x00A0000012345678ULL
#define HRLFC_MAX_UL 4211081215000ULL /* 0xFAFFFFFF * 0.001 L */

typedef struct {
    pfe_ecu_t ecu;
    pfe_ecu_config_t cfg;
    uint64_t now_us;
    uint32_t ticks;
    uint64_t own_ul;           /* totals after the last tick */
    uint64_t platoon_ul;
    uint8_t nvm[PFE_NVM_SLOTS][PFE_NVM_RECORD_SIZE];
    bool nvm_written;
    pfe_nvm_state_t saved;     /* the last record written */
    uint16_t auto_speed_raw;
    uint16_t auto_pitch_raw;
    bool hrlfc_clamped;        /* an HRLFC went out clamped since the start */
} fz_t;

static fz_t g;
static bool g_trace; /* FUZZ_TRACE set: print each prediction sent */

static void receive(fz_t *z, const pfe_can_frame_t *f)
{
    pfe_ecu_receive(&z->ecu, f, z->now_us);
}

static void check_output(fz_t *z, const pfe_can_frame_t *f)
{
    FUZZ_CHECK((f->id & PFE_CAN_EFF_FLAG) != 0U);
    FUZZ_CHECK(f->dlc <= PFE_CAN_MAX_DLC);
    const pfe_codec_message_t *m = pfe_codec_find_message(f->id);
    FUZZ_CHECK(m != NULL);
    FUZZ_CHECK((m->direction & PFE_CODEC_DIR_TX) != 0U);
    FUZZ_CHECK(f->dlc == m->dlc);
    const uint32_t pgn = pfe_j1939_pgn(f->id);
    const uint8_t sa = pfe_j1939_source(f->id);
    if (pgn == PFE_PGN_ADDRESS_CLAIMED) {
        pfe_j1939_name_t name;
        FUZZ_CHECK(pfe_codec_decode_address_claimed(f, &name) >= 0);
        FUZZ_CHECK((sa == z->ecu.address) || (sa == PFE_J1939_ADDR_NULL));
        return;
    }
    FUZZ_CHECK(sa == z->ecu.address);
    FUZZ_CHECK(z->ecu.addr_state == PFE_ECU_ADDR_CLAIMED);
    if (pgn == PFE_PGN_LFE1) {
        pfe_msg_lfe1_t d;
        FUZZ_CHECK(pfe_codec_decode_lfe1(f, &d) >= 0);
    } else if (pgn == PFE_PGN_PLATOON_FUEL) {
        pfe_msg_platoon_fuel_t d;
        FUZZ_CHECK(pfe_codec_decode_platoon_fuel(f, &d) >= 0);
    } else if ((pgn == PFE_PGN_HRLFC) || (pgn == PFE_PGN_OWN_FUEL)) {
        pfe_msg_hrlfc_t d;
        pfe_msg_own_fuel_t o;
        if (pgn == PFE_PGN_HRLFC) {
            FUZZ_CHECK(pfe_codec_decode_hrlfc(f, &d) >= 0);
        } else {
            FUZZ_CHECK(pfe_codec_decode_own_fuel(f, &o) >= 0);
            d.total_fuel_ul = o.fuel_used_ul;
        }
        FUZZ_CHECK(d.total_fuel_ul.state == PFE_SIG_VALID);
        const uint64_t own = pfe_ecu_own_fuel_ul(&z->ecu);
        const uint64_t rounded = ((own / 1000U) + (((own % 1000U) >= 500U) ? 1U : 0U)) * 1000U;
        FUZZ_CHECK(d.total_fuel_ul.value == ((rounded < HRLFC_MAX_UL) ? rounded : HRLFC_MAX_UL));
        z->hrlfc_clamped = z->hrlfc_clamped || (rounded > HRLFC_MAX_UL);
    } else if (pgn == PFE_PGN_INPUT_STATUS) {
        pfe_msg_input_status_t d;
        FUZZ_CHECK(pfe_codec_decode_input_status(f, &d) >= 0);
        FUZZ_CHECK(d.vehicle_mass_kg.state == PFE_SIG_VALID);
        FUZZ_CHECK((d.vehicle_mass_kg.value >= PFE_MASS_MIN_KG) &&
                   (d.vehicle_mass_kg.value <= PFE_MASS_MAX_KG));
        FUZZ_CHECK((d.grade_source.state == PFE_SIG_VALID) &&
                   (d.grade_source.value <= PFE_GRADE_SOURCE_NONE));
    } else if (pgn == PFE_PGN_DEVICE_STATUS) {
        pfe_msg_device_status_t d;
        FUZZ_CHECK(pfe_codec_decode_device_status(f, &d) >= 0);
    } else if (pgn == PFE_PGN_FUEL_PREDICTION) {
        pfe_msg_fuel_prediction_t d;
        FUZZ_CHECK(pfe_codec_decode_fuel_prediction(f, &d) >= 0);
        /* All four signals are available together, or none. */
        FUZZ_CHECK(d.fuel_lower_ul.state == d.fuel_ul.state);
        FUZZ_CHECK(d.fuel_upper_ul.state == d.fuel_ul.state);
        FUZZ_CHECK(d.time_ms.state == d.fuel_ul.state);
        /* The thesis's bounds hold the prediction (5.1). */
        FUZZ_CHECK((d.fuel_ul.state != PFE_SIG_VALID) ||
                   ((d.fuel_lower_ul.value <= d.fuel_ul.value) && (d.fuel_ul.value <= d.fuel_upper_ul.value)));
        if (g_trace) {
            fprintf(stderr, "tick %u: prediction %s %u uL [%u, %u] %u ms\n", z->ticks,
                    (d.fuel_ul.state == PFE_SIG_VALID) ? "valid" : "n/a", d.fuel_ul.value,
                    d.fuel_lower_ul.value, d.fuel_upper_ul.value, d.time_ms.value);
        }
    } else if (pgn == PFE_PGN_STATUS) {
        pfe_msg_status_t d;
        FUZZ_CHECK(pfe_codec_decode_status(f, &d) >= 0);
        /* A total clamped on the wire stays clamped (it never decreases),
         * and the status says so. */
        FUZZ_CHECK(!z->hrlfc_clamped || (d.output_saturated.value == 1U));
    } else {
        FUZZ_CHECK(false); /* not an output */
    }
}

/* The totals never go down between resets. */
static void check_totals(fz_t *z)
{
    const uint64_t own = pfe_ecu_own_fuel_ul(&z->ecu);
    const uint64_t platoon = pfe_ecu_platoon_fuel_ul(&z->ecu);
    FUZZ_CHECK(own >= z->own_ul);
    FUZZ_CHECK(platoon >= z->platoon_ul);
    z->own_ul = own;
    z->platoon_ul = platoon;
}

static void save_if_due(fz_t *z)
{
    if (!pfe_ecu_nvm_due(&z->ecu)) {
        return;
    }
    const uint32_t slot = pfe_ecu_nvm_slot(&z->ecu);
    FUZZ_CHECK(slot < PFE_NVM_SLOTS);
    pfe_nvm_state_t s;
    pfe_ecu_nvm_take(&z->ecu, &s);
    FUZZ_CHECK(s.own_fuel_ul == z->own_ul);
    FUZZ_CHECK(s.platoon_fuel_ul == z->platoon_ul);
    pfe_nvm_encode(&s, z->nvm[slot]);
    pfe_nvm_state_t back;
    FUZZ_CHECK(pfe_nvm_decode(z->nvm[slot], &back) == PFE_OK);
    FUZZ_CHECK((back.sequence == s.sequence) && (back.own_fuel_ul == s.own_fuel_ul) &&
               (back.platoon_fuel_ul == s.platoon_fuel_ul));
    pfe_ecu_nvm_written(&z->ecu, 0);
    FUZZ_CHECK(!pfe_ecu_nvm_due(&z->ecu));
    z->saved = s;
    z->nvm_written = true;
}

static void tick_cap(fz_t *z, uint32_t cap)
{
    pfe_can_frame_t tx[PFE_ECU_TX_MAX + 1U];
    memset(tx, 0xA5, sizeof tx);
    const uint32_t n = pfe_ecu_tick(&z->ecu, z->now_us, tx, cap);
    FUZZ_CHECK(n <= cap);
    FUZZ_CHECK(n <= PFE_ECU_TX_MAX);
    check_totals(z);
    for (uint32_t k = 0U; k < n; k++) {
        check_output(z, &tx[k]);
    }
    save_if_due(z);
    z->now_us += PFE_ECU_TICK_US;
    z->ticks++;
}

static void tick(fz_t *z)
{
    tick_cap(z, PFE_ECU_TX_MAX);
}

static void send_ccvs1_raw(fz_t *z, uint16_t raw)
{
    /* CCVS1: SPN 84 in bytes 2-3 (1-based); the rest not available. */
    pfe_can_frame_t f = {pfe_j1939_id(6U, PFE_PGN_CCVS1, 0U, OTHER_SA), 8U,
                         {0xFFU, (uint8_t)raw, (uint8_t)(raw >> 8), 0xFFU, 0xFFU, 0xFFU, 0xFFU, 0xFFU}};
    receive(z, &f);
}

static void send_ssi_raw(fz_t *z, uint16_t raw, uint8_t states)
{
    /* SSI: SPN 3318 pitch in bytes 1-2, roll 3-4 (0 deg), the pitch's
     * figure of merit in bits 48-49 (can_dbc/pfe.dbc). */
    pfe_can_frame_t f = {pfe_j1939_id(3U, PFE_PGN_SSI, 0U, OTHER_SA), 8U,
                         {(uint8_t)raw, (uint8_t)(raw >> 8), 0x00U, 0x7DU, 0xFFU, 0xFFU,
                          (uint8_t)(0xFCU | (states & 3U)), 0xFFU}};
    receive(z, &f);
}

static pfe_sig_state_t state_of(uint32_t bits)
{
    /* Mostly valid: 0, 4, 5, 6, 7 valid; 1, 2, 3 the other states. */
    const uint32_t s = bits & 7U;
    return (s >= 1U && s <= 3U) ? (pfe_sig_state_t)s : PFE_SIG_VALID;
}

static void op_pgn(fz_t *z, fuzz_in_t *in, uint32_t p)
{
    static const uint32_t pgns[] = {PFE_PGN_CCVS1, PFE_PGN_SSI, PFE_PGN_PLATOON_CONFIG,
                                    PFE_PGN_GRADE_PREVIEW, PFE_PGN_REQUEST, PFE_PGN_ADDRESS_CLAIMED,
                                    PFE_PGN_LFE1, PFE_PGN_STATUS, PFE_PGN_VDS, PFE_PGN_CVW,
                                    PFE_PGN_HRLFC, PFE_PGN_OWN_FUEL};
    const uint8_t sa = fuzz_u8(in);
    const uint8_t da = fuzz_u8(in);
    pfe_can_frame_t f;
    f.id = pfe_j1939_id((uint8_t)(p >> 3) & 7U, pgns[p % (sizeof pgns / sizeof pgns[0])], da, sa);
    f.dlc = (uint8_t)(fuzz_u8(in) % 9U);
    for (uint32_t k = 0U; k < 8U; k++) {
        f.data[k] = fuzz_u8(in);
    }
    receive(z, &f);
}

static void op_config(fz_t *z, fuzz_in_t *in, uint32_t p)
{
    pfe_msg_platoon_config_t m;
    m.n_vehicles.value = fuzz_u8(in);
    m.n_vehicles.state = state_of(p);
    m.own_position.value = fuzz_u8(in);
    m.own_position.state = state_of(p >> 1);
    m.gap_mm.value = (uint32_t)fuzz_u16(in) * 10U;
    m.gap_mm.state = state_of(p >> 2);
    m.time_gap_ms.value = fuzz_u16(in);
    m.time_gap_ms.state = state_of(p >> 3);
    const uint16_t raw = fuzz_u16(in);
    m.set_speed_mm_s.value = (int32_t)(((uint32_t)raw * 625U + 288U) / 576U);
    m.set_speed_mm_s.state = state_of(p >> 4);
    pfe_can_frame_t f;
    if (pfe_codec_encode_platoon_config(&f, &m, OTHER_SA) >= 0) {
        receive(z, &f);
    }
}

static void op_preview(fz_t *z, fuzz_in_t *in, uint32_t p)
{
    const uint32_t count = 1U + (fuzz_u16(in) % PFE_PREVIEW_MAX_SAMPLES);
    const uint32_t spacing = fuzz_u8(in);          /* 0 and over 250 are refused */
    const int32_t first = (int8_t)fuzz_u8(in) * 2000;
    const int32_t slope = (int8_t)fuzz_u8(in) * 20;
    const uint8_t faults = fuzz_u8(in);
    const uint32_t fault_at = fuzz_u16(in);
    const uint32_t id = p & 15U;
    pfe_msg_grade_preview_t m;
    memset(&m, 0, sizeof m);
    m.frame_type.value = PFE_PREVIEW_FRAME_HEADER;
    m.preview_id.value = id;
    m.sample_count.value = count;
    m.spacing_m.value = spacing;
    pfe_can_frame_t f;
    if (pfe_codec_encode_grade_preview(&f, &m, OTHER_SA) >= 0) {
        receive(z, &f);
    }
    const uint32_t frames = (count + 2U) / 3U;
    for (uint32_t k = 0U; (k < frames) && (z->ticks < MAX_TICKS); k++) {
        if (((faults & 8U) != 0U) && (k == (fault_at % frames))) {
            break; /* cut short */
        }
        m.frame_type.value = PFE_PREVIEW_FRAME_DATA;
        m.preview_id.value = (((faults & 16U) != 0U) && (k == (fault_at % frames))) ? (id + 1U) & 15U : id;
        m.first_index.value = k * 3U;
        for (uint32_t s = 0U; s < 3U; s++) {
            const int64_t grade = (int64_t)first + ((int64_t)slope * (int64_t)(k * 3U + s));
            m.grade_ppm[s].value = (int32_t)pfe_clamp_i64(grade, -640000, 645100);
            m.grade_ppm[s].state = (((faults & 4U) != 0U) && (k == (fault_at % frames)) && (s == 1U))
                                       ? PFE_SIG_NOT_AVAILABLE : PFE_SIG_VALID;
        }
        if (pfe_codec_encode_grade_preview(&f, &m, OTHER_SA) < 0) {
            continue;
        }
        const bool drop = ((faults & 1U) != 0U) && (k == (fault_at % frames));
        if (!drop) {
            receive(z, &f);
        }
        if (((faults & 2U) != 0U) && (k == (fault_at % frames))) {
            receive(z, &f);
        }
        if ((k % 2U) == 1U) {
            /* 5 ms apart as drivegen sends them: two a tick, speed and pitch on time. */
            if ((z->ticks % 10U) == 0U) {
                send_ccvs1_raw(z, z->auto_speed_raw);
            }
            send_ssi_raw(z, z->auto_pitch_raw, 0U);
            tick(z);
        }
    }
}

static void op_run(fz_t *z, fuzz_in_t *in, uint32_t p)
{
    const uint32_t n = 1U + fuzz_u8(in) + (256U * (p & 3U));
    const bool feed = (p & 4U) != 0U;
    for (uint32_t k = 0U; (k < n) && (z->ticks < MAX_TICKS); k++) {
        if (feed) {
            if ((z->ticks % 10U) == 0U) {
                send_ccvs1_raw(z, z->auto_speed_raw);
            }
            send_ssi_raw(z, z->auto_pitch_raw, 0U);
        }
        tick(z);
    }
}

static void start(fz_t *z, const pfe_nvm_state_t *restored, int slot)
{
    FUZZ_CHECK(pfe_ecu_init(&z->ecu, &z->cfg, restored, slot, z->now_us) == PFE_OK);
    z->hrlfc_clamped = false;
    z->own_ul = pfe_ecu_own_fuel_ul(&z->ecu);
    z->platoon_ul = pfe_ecu_platoon_fuel_ul(&z->ecu);
}

/* A reset: the ECU restarts from its NVM, as the main loop does it. */
static void op_reset(fz_t *z)
{
    pfe_nvm_state_t s;
    const int slot = pfe_nvm_pick(z->nvm[0], z->nvm[1], &s);
    if (z->nvm_written) {
        FUZZ_CHECK(slot >= 0);
        FUZZ_CHECK((s.sequence == z->saved.sequence) && (s.own_fuel_ul == z->saved.own_fuel_ul) &&
                   (s.platoon_fuel_ul == z->saved.platoon_fuel_ul));
    }
    start(z, (slot >= 0) ? &s : NULL, slot);
    if (slot >= 0) {
        /* What was saved comes back, unless it exceeds what the estimator holds. */
        FUZZ_CHECK(z->own_ul <= s.own_fuel_ul);
        FUZZ_CHECK(z->platoon_ul <= s.platoon_fuel_ul);
    }
}

static void op_misc(fz_t *z, fuzz_in_t *in, uint32_t p)
{
    switch (p & 7U) {
    case 0U:
        z->now_us += fuzz_u32(in);
        tick(z);
        break;
    case 1U:
        pfe_ecu_note_overrun(&z->ecu, fuzz_u8(in));
        break;
    case 2U:
        pfe_ecu_note_tx_dropped(&z->ecu, fuzz_u8(in));
        break;
    case 3U:
        pfe_ecu_note_rx_dropped(&z->ecu, fuzz_u8(in));
        break;
    case 4U:
        for (uint32_t k = 0U; k < 70U; k++) {
            send_ssi_raw(z, z->auto_pitch_raw, 0U);
        }
        tick(z);
        break;
    case 5U:
        z->auto_speed_raw = fuzz_u16(in);
        z->auto_pitch_raw = fuzz_u16(in);
        break;
    case 6U:
        tick_cap(z, fuzz_u8(in) % (PFE_ECU_TX_MAX + 1U));
        break;
    default:
        op_reset(z);
        break;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_t *z = &g;
    fuzz_in_t in = {data, size};
    g_trace = getenv("FUZZ_TRACE") != NULL;
    memset(z, 0, sizeof *z);
    memset(z->nvm, 0xFF, sizeof z->nvm);
    z->now_us = 1000000U;
    z->auto_speed_raw = 0x5A00U; /* 90 km/h */
    z->auto_pitch_raw = 0x7D00U; /* 0 deg */

    static const uint32_t save_s[4] = {1U, 2U, 10U, 3600U};
    const uint8_t b0 = fuzz_u8(&in), b1 = fuzz_u8(&in), b2 = fuzz_u8(&in), b3 = fuzz_u8(&in);
    const uint32_t n = 1U + (b0 % PFE_MAX_VEHICLES);
    z->cfg.preferred_address = PFE_ECU_DEFAULT_ADDRESS;
    z->cfg.name = NAME_BASE | (((b1 & 0x80U) != 0U) ? (1ULL << 63) : 0U);
    z->cfg.save_interval_ms = save_s[(b1 >> 5) & 3U] * 1000U;
    z->cfg.vehicle = &pfe_default_vehicle;
    z->cfg.env = &pfe_default_env;
    z->cfg.drag = &pfe_default_drag;
    z->cfg.default_vehicles = n;
    z->cfg.default_position = (b1 & 0x1FU) % n;
    z->cfg.default_gap_mm = (uint32_t)b2 * 500U;
    z->cfg.cruise = &pfe_default_cruise;
    z->cfg.default_set_speed_mm_s = 0;
    if ((b3 & 1U) != 0U) {
        pfe_nvm_state_t r;
        r.sequence = 1U;
        r.own_fuel_ul = fuzz_u64(&in);
        r.platoon_fuel_ul = fuzz_u64(&in);
        start(z, &r, 0);
    } else {
        start(z, NULL, -1);
    }

    while (fuzz_left(&in) && (z->ticks < MAX_TICKS)) {
        const uint8_t op = fuzz_u8(&in);
        const uint32_t p = op >> 3;
        switch (op & 7U) {
        case 0U: {
            pfe_can_frame_t f;
            f.id = fuzz_u32(&in);
            f.dlc = (uint8_t)(fuzz_u8(&in) % 9U);
            for (uint32_t k = 0U; k < 8U; k++) {
                f.data[k] = fuzz_u8(&in);
            }
            receive(z, &f);
            break;
        }
        case 1U:
            op_pgn(z, &in, p);
            break;
        case 2U:
            send_ccvs1_raw(z, fuzz_u16(&in));
            break;
        case 3U:
            send_ssi_raw(z, fuzz_u16(&in), (uint8_t)p);
            break;
        case 4U:
            op_config(z, &in, p);
            break;
        case 5U:
            op_preview(z, &in, p);
            break;
        case 6U:
            op_run(z, &in, p);
            break;
        default:
            op_misc(z, &in, p);
            break;
        }
    }
    return 0;
}
