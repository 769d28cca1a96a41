/* pfe_ecu.c - the module as a J1939 ECU (contract in pfe_ecu.h). */
#include "pfe_ecu.h"

#include <stddef.h>
#include <string.h>

#include "pfe_fixed.h"

#define ARBITRARY_FIRST 128U       /* J1939 self-configurable address range */
#define ARBITRARY_LAST 247U

/* Output messages, one bit each in request_pending. */
enum {
    OUT_LFE1,
    OUT_PLATOON_FUEL,
    OUT_HRLFC,
    OUT_PREDICTION,
    OUT_STATUS,
    OUT_OWN_FUEL,
    OUT_INPUT_STATUS,
    OUT_DEVICE_STATUS,
    OUT_COUNT
};

/* Each output's message, with its period from the DBC (pfe_codec_messages[]),
 * and its PGN for requests: the PGN macros, which the generated tables hold
 * equal to the DBC's when they compile (sim_host/tools/dbc2c.c). */
static const pfe_msg_index_t k_out_msg[OUT_COUNT] = {
    PFE_MSG_LFE1,   PFE_MSG_PLATOON_FUEL, PFE_MSG_HRLFC,        PFE_MSG_FUEL_PREDICTION,
    PFE_MSG_STATUS, PFE_MSG_OWN_FUEL,     PFE_MSG_INPUT_STATUS, PFE_MSG_DEVICE_STATUS};
static const uint32_t k_out_pgn[OUT_COUNT] = {
    PFE_PGN_LFE1,     PFE_PGN_PLATOON_FUEL, PFE_PGN_HRLFC,        PFE_PGN_FUEL_PREDICTION,
    PFE_PGN_STATUS,   PFE_PGN_OWN_FUEL,     PFE_PGN_INPUT_STATUS, PFE_PGN_DEVICE_STATUS};

/* A message's period (GenMsgCycleTime) in us; 0 for one sent on event or request. */
static uint32_t period_us(pfe_msg_index_t msg)
{
    return (uint32_t)pfe_codec_messages[msg].cycle_ms * 1000U;
}

/* Whether an output is due at this tick: every GenMsgCycleTime, in the
 * phase-th tick of its period (the outputs are spread over ticks); never
 * for a message without a period (sent on request only). */
static bool out_due(uint32_t tick, uint32_t out, uint32_t phase)
{
    const uint32_t ticks = period_us(k_out_msg[out]) / PFE_ECU_TICK_US;
    return (ticks != 0U) && ((tick % ticks) == (phase % ticks));
}

/* pfe_ecu_rx_filters[] is written from can_dbc/pfe.dbc at build time by
 * sim_host/tools/dbc2c.c (build/gen/pfe_dbc.c): one filter per message whose
 * PFEReceivedFrom is AnySourceAddress. */

static void count_up(uint32_t *c, uint32_t n)
{
    *c = (*c > (UINT32_MAX - n)) ? UINT32_MAX : (*c + n);
}

/* The platoon's calibrations: each position's, the own truck's at its own. */
static void platoon_config(const pfe_ecu_t *ecu, pfe_platoon_config_t *pc, uint32_t n,
                           uint32_t position, uint32_t gap_mm)
{
    pfe_platoon_config_uniform(pc, n, gap_mm, ecu->cfg.vehicle, ecu->cfg.env, ecu->cfg.drag);
    for (uint32_t k = 0U; k < pc->n_vehicles; k++) {
        if (ecu->cfg.vehicle_at[k] != NULL) {
            pc->vehicle[k] = ecu->cfg.vehicle_at[k];
        }
    }
    if (position < pc->n_vehicles) {
        pc->vehicle[position] = &ecu->own_calib;
    }
}

/* The drag reduction of the own truck's position, for identification. */
static void identify_position(pfe_ecu_t *ecu)
{
    (void)pfe_identify_set_drag_reduction(
        &ecu->identify, pfe_drag_reduction_bp(ecu->cfg.drag, ecu->own_position,
                                              ecu->platoon.n_vehicles, ecu->platoon.gap_mm));
}

/* The platoon at once (start-up). Totals carry over: the own truck's to
 * its new position. */
static int configure(pfe_ecu_t *ecu, uint32_t n, uint32_t position, uint32_t gap_mm)
{
    const uint64_t own = pfe_ecu_own_fuel_ul(ecu);
    const uint64_t platoon = pfe_ecu_platoon_fuel_ul(ecu);
    pfe_platoon_config_t pc;
    platoon_config(ecu, &pc, n, position, gap_mm);
    if ((pc.n_vehicles != n) || (position >= n) || (pfe_platoon_init(&ecu->platoon, &pc) != PFE_OK)) {
        return PFE_EINVAL;
    }
    /* The prediction in progress was for the old platoon. */
    pfe_predict_cancel(&ecu->predict);
    (void)pfe_estimator_init(&ecu->est, &ecu->platoon);
    ecu->own_position = position;
    (void)pfe_estimator_set_fuel_used_ul(&ecu->est, (int32_t)position, own);
    (void)pfe_estimator_set_fuel_used_ul(&ecu->est, PFE_EST_PLATOON, platoon);
    identify_position(ecu);
    return PFE_OK;
}

/*
 * The platoon of a PFE_PlatoonConfig, built in place over the next ticks
 * (rebuild_step()): the estimator would start again on it anyway, so it
 * pauses meanwhile (outputs not available, totals held as they were at the
 * start); the prediction in progress is abandoned. A second configuration
 * during the build starts it again, the totals kept.
 */
static int rebuild_start(pfe_ecu_t *ecu, uint32_t n, uint32_t position, uint32_t gap_mm)
{
    pfe_platoon_config_t pc;
    platoon_config(ecu, &pc, n, position, gap_mm);
    if ((pc.n_vehicles != n) || (position >= n) || (pfe_platoon_init_begin(&pc) != PFE_OK)) {
        return PFE_EINVAL;
    }
    if (!ecu->platoon_building) {
        ecu->build_own_ul = pfe_ecu_own_fuel_ul(ecu);
        ecu->build_platoon_ul = pfe_ecu_platoon_fuel_ul(ecu);
        ecu->build_old_n = ecu->platoon.n_vehicles;
        ecu->build_old_position = ecu->own_position;
        ecu->build_old_gap_mm = ecu->platoon.gap_mm;
        pfe_predict_cancel(&ecu->predict);
    }
    ecu->build_n = n;
    ecu->build_position = position;
    ecu->build_gap_mm = gap_mm;
    ecu->build_done = 0U;
    ecu->platoon_building = true;
    return PFE_OK;
}

/* One tick's share of the build: PFE_ECU_REBUILD_PER_TICK positions, or the
 * aggregates and the estimator started on them (PFE_ECU_REBUILD_PER_TICK
 * trucks: about 5,000 Cortex-M4 instructions; the aggregates 3,000). A
 * configuration that fails half-way brings the old platoon back at once.
 * Returns whether it did any work. */
static bool rebuild_step(pfe_ecu_t *ecu)
{
    if (!ecu->platoon_building) {
        return false;
    }
    pfe_platoon_config_t pc;
    platoon_config(ecu, &pc, ecu->build_n, ecu->build_position, ecu->build_gap_mm);
    int rc = PFE_OK;
    bool finished = false;
    if (ecu->build_done < ecu->build_n) {
        rc = pfe_platoon_init_positions(&ecu->platoon, &pc, ecu->build_done, PFE_ECU_REBUILD_PER_TICK);
        const uint32_t left = ecu->build_n - ecu->build_done;
        ecu->build_done += (left < PFE_ECU_REBUILD_PER_TICK) ? left : PFE_ECU_REBUILD_PER_TICK;
    } else {
        rc = pfe_platoon_init_finish(&ecu->platoon, &pc);
        finished = true;
    }
    if (rc != PFE_OK) {
        ecu->platoon_building = false;
        ecu->config.state = PFE_SIG_OUT_OF_RANGE;
        (void)configure(ecu, ecu->build_old_n, ecu->build_old_position, ecu->build_old_gap_mm);
        (void)pfe_estimator_set_fuel_used_ul(&ecu->est, (int32_t)ecu->own_position, ecu->build_own_ul);
        (void)pfe_estimator_set_fuel_used_ul(&ecu->est, PFE_EST_PLATOON, ecu->build_platoon_ul);
    } else if (finished) {
        ecu->platoon_building = false;
        (void)pfe_estimator_init(&ecu->est, &ecu->platoon);
        ecu->own_position = ecu->build_position;
        (void)pfe_estimator_set_fuel_used_ul(&ecu->est, (int32_t)ecu->build_position, ecu->build_own_ul);
        (void)pfe_estimator_set_fuel_used_ul(&ecu->est, PFE_EST_PLATOON, ecu->build_platoon_ul);
        identify_position(ecu);
        ecu->degraded = false;
    } else {
        /* positions built, more to come */
    }
    return true;
}

/* The own truck's mass or auxiliary power changed (CVW, identification):
 * the own truck's position of the same platoon built again with it, and
 * the aggregates (about 3,600 Cortex-M4 instructions); the estimator keeps
 * its filter and totals, the prediction restarts. During a build, the build
 * starts again with it. Returns whether the model changed. */
static bool remodel_own_truck(pfe_ecu_t *ecu, uint32_t mass_kg, uint32_t aux_w)
{
    pfe_vehicle_calib_t c = ecu->own_calib;
    c.mass_kg = mass_kg;
    c.power_aux_w = aux_w;
    if ((pfe_calib_check_vehicle(&c) != PFE_OK) ||
        ((mass_kg == ecu->own_calib.mass_kg) && (aux_w == ecu->own_calib.power_aux_w))) {
        return false;
    }
    const pfe_vehicle_calib_t old = ecu->own_calib;
    ecu->own_calib = c;
    if (ecu->platoon_building) {
        (void)rebuild_start(ecu, ecu->build_n, ecu->build_position, ecu->build_gap_mm);
        return true;
    }
    pfe_platoon_config_t pc;
    platoon_config(ecu, &pc, ecu->platoon.n_vehicles, ecu->own_position, ecu->platoon.gap_mm);
    if ((pfe_platoon_init_positions(&ecu->platoon, &pc, ecu->own_position, 1U) != PFE_OK) ||
        (pfe_platoon_init_finish(&ecu->platoon, &pc) != PFE_OK)) {
        ecu->own_calib = old; /* a platoon the old values built: build it again */
        platoon_config(ecu, &pc, ecu->platoon.n_vehicles, ecu->own_position, ecu->platoon.gap_mm);
        (void)pfe_platoon_init(&ecu->platoon, &pc);
        return false;
    }
    pfe_predict_cancel(&ecu->predict);
    return true;
}

/* CVW's mass: the last of a tick waits for apply_own_mass() after the queue. */
static void note_own_mass(pfe_ecu_t *ecu, uint32_t mass_kg)
{
    ecu->mass_next_kg = mass_kg;
    ecu->mass_next_pending = true;
}

/* The tick's last CVW mass, once (remodel_own_truck()). */
static void apply_own_mass(pfe_ecu_t *ecu)
{
    if (!ecu->mass_next_pending) {
        return;
    }
    ecu->mass_next_pending = false;
    (void)remodel_own_truck(ecu, ecu->mass_next_kg, ecu->own_calib.power_aux_w);
}

/* Identified values differ from those in use by this much before the model
 * is rebuilt, and at most once per PFE_ECU_REMODEL_MIN_US. */
#define REMODEL_MASS_KG 200U
#define REMODEL_AUX_W 1000U
#define PFE_ECU_REMODEL_MIN_US 10000000U

static uint32_t abs_diff_u32(uint32_t a, uint32_t b)
{
    return (a > b) ? (a - b) : (b - a);
}

/* Once identification has converged, the own truck's model takes its mass
 * (unless CVW gave one) and its auxiliary power. */
static void use_identified(pfe_ecu_t *ecu)
{
    if (!pfe_identify_converged(&ecu->identify)) {
        return;
    }
    const uint32_t mass = ecu->cvw_mass ? ecu->own_calib.mass_kg : pfe_identify_mass_kg(&ecu->identify);
    const uint32_t aux = pfe_identify_aux_power_w(&ecu->identify);
    const bool differs = (abs_diff_u32(mass, ecu->own_calib.mass_kg) >= REMODEL_MASS_KG) ||
                         (abs_diff_u32(aux, ecu->own_calib.power_aux_w) >= REMODEL_AUX_W);
    const bool first = !ecu->aux_identified;
    const bool due = !ecu->remodelled || ((ecu->now_us - ecu->remodel_us) >= PFE_ECU_REMODEL_MIN_US);
    if ((first || (differs && due)) && remodel_own_truck(ecu, mass, aux)) {
        ecu->remodel_us = ecu->now_us;
        ecu->remodelled = true;
    }
    ecu->aux_identified = true;
    if (!ecu->cvw_mass) {
        ecu->mass_source = (uint8_t)PFE_MASS_SOURCE_IDENTIFIED;
    }
}

int pfe_ecu_init(pfe_ecu_t *ecu, const pfe_ecu_config_t *cfg, const pfe_nvm_state_t *restored,
                 int restored_slot, uint64_t now_us)
{
    if ((ecu == NULL) || (cfg == NULL) || (cfg->save_interval_ms < 1000U) ||
        (cfg->save_interval_ms > 3600000U) || (cfg->preferred_address > 253U)) {
        return PFE_EINVAL;
    }
    (void)memset(ecu, 0, sizeof *ecu);
    ecu->cfg = *cfg;
    if (ecu->cfg.cruise == NULL) {
        ecu->cfg.cruise = &pfe_default_cruise;
    }
    if (ecu->cfg.default_set_speed_mm_s == 0) {
        ecu->cfg.default_set_speed_mm_s = PFE_ECU_DEFAULT_SET_SPEED_MM_S;
    }
    if ((pfe_calib_check_cruise(ecu->cfg.cruise) != PFE_OK) ||
        (ecu->cfg.default_set_speed_mm_s < PFE_SIM_STALL_MM_S) ||
        (ecu->cfg.default_set_speed_mm_s > PFE_SPEED_MAX_MM_S)) {
        return PFE_EINVAL;
    }
    const pfe_vehicle_calib_t *own = (cfg->own_vehicle != NULL) ? cfg->own_vehicle : cfg->vehicle;
    if ((own == NULL) || (pfe_calib_check_vehicle(own) != PFE_OK) ||
        ((uint32_t)cfg->j1939_fuel > (uint32_t)PFE_ECU_J1939_FUEL_NEVER)) {
        return PFE_EINVAL;
    }
    ecu->own_calib = *own;
    ecu->mass_source = (uint8_t)PFE_MASS_SOURCE_CALIBRATION;
    if (pfe_identify_init(&ecu->identify, own, cfg->env) != PFE_OK) {
        return PFE_EINVAL;
    }
    for (uint32_t k = 0U; k < (uint32_t)PFE_IN_COUNT; k++) {
        pfe_input_init(&ecu->in[k], (pfe_input_kind_t)k,
                       cfg->input_source_fixed[k] ? cfg->input_source[k] : (uint8_t)PFE_INPUT_NO_SOURCE);
    }
    pfe_altgrade_init(&ecu->altgrade);
    ecu->grade_source = (uint8_t)PFE_GRADE_SOURCE_NONE;
    pfe_predict_init(&ecu->predict);
    ecu->own_position = 0U;
    /* Fuel used before the first configure() is zero; configure() re-applies it. */
    pfe_platoon_config_t pc;
    platoon_config(ecu, &pc, 1U, 0U, cfg->default_gap_mm);
    if ((pfe_platoon_init(&ecu->platoon, &pc) != PFE_OK) ||
        (pfe_estimator_init(&ecu->est, &ecu->platoon) != PFE_OK)) {
        return PFE_EINVAL;
    }
    if (restored != NULL) {
        (void)pfe_estimator_set_fuel_used_ul(&ecu->est, 0, restored->own_fuel_ul);
        (void)pfe_estimator_set_fuel_used_ul(&ecu->est, PFE_EST_PLATOON, restored->platoon_fuel_ul);
        ecu->nvm_sequence = restored->sequence;
        if (((restored->id_flags & PFE_NVM_ID_VALID) != 0U) && !cfg->identification_off) {
            /* a record out of range restores nothing (pfe_identify_restore()) */
            (void)pfe_identify_restore(&ecu->identify, restored->id_mass_kg, restored->id_aux_w,
                                       (restored->id_flags & PFE_NVM_ID_CONVERGED) != 0U);
        }
    }
    if (configure(ecu, cfg->default_vehicles, cfg->default_position, cfg->default_gap_mm) != PFE_OK) {
        return PFE_EINVAL;
    }
    ecu->degraded = true;
    ecu->nvm_last_slot = restored_slot;
    ecu->address = cfg->preferred_address;
    ecu->addr_state = PFE_ECU_ADDR_CLAIMING;
    ecu->claim_pending = true;
    ecu->claim_us = now_us;
    ecu->now_us = now_us;
    ecu->last_save_us = now_us;
    ecu->start_us = now_us;
    ecu->config.state = PFE_SIG_NOT_AVAILABLE;
    ecu->preview.state = PFE_SIG_NOT_AVAILABLE;
    pfe_preview_init(&ecu->preview_buf);
    ecu->out = NULL;
    use_identified(ecu); /* a converged identification restored from NVM */
    return PFE_OK;
}

void pfe_ecu_receive(pfe_ecu_t *ecu, const pfe_can_frame_t *frame, uint64_t rx_us)
{
    if (ecu->rxq_count == PFE_ECU_RX_QUEUE_LEN) {
        count_up(&ecu->count.rx_dropped, 1U);
        return;
    }
    const uint32_t slot = (ecu->rxq_head + ecu->rxq_count) % PFE_ECU_RX_QUEUE_LEN;
    ecu->rxq[slot] = *frame;
    ecu->rxq_us[slot] = rx_us;
    ecu->rxq_count++;
}

static void input_update(pfe_ecu_input_t *in, pfe_sig_state_t state, uint64_t rx_us)
{
    in->state = state;
    in->fresh = true;
    in->rx_us = rx_us;
    in->seen = true;
}

/* J1939-81: the lower NAME keeps the address. */
static void on_address_claimed(pfe_ecu_t *ecu, const pfe_can_frame_t *f)
{
    pfe_j1939_name_t theirs;
    uint64_t their_name = 0U;
    if ((pfe_codec_decode_address_claimed(f, &theirs) < 0) ||
        (pfe_j1939_name_pack(&theirs, &their_name) != PFE_OK) ||
        (pfe_j1939_source(f->id) != ecu->address) || (ecu->addr_state == PFE_ECU_ADDR_LOST) ||
        (their_name == ecu->cfg.name)) {
        return;
    }
    count_up(&ecu->conflicts, 1U);
    if (ecu->cfg.name < their_name) {
        ecu->claim_pending = true; /* we keep it: say so again */
        return;
    }
    count_up(&ecu->count.claims_lost, 1U);
    const bool arbitrary = (ecu->cfg.name >> 63) != 0U;
    if (arbitrary && (ecu->address < ARBITRARY_LAST)) {
        ecu->address = (ecu->address < ARBITRARY_FIRST) ? (uint8_t)ARBITRARY_FIRST
                                                        : (uint8_t)(ecu->address + 1U);
        ecu->addr_state = PFE_ECU_ADDR_CLAIMING;
        ecu->claim_pending = true;
        ecu->claim_us = ecu->now_us;
    } else {
        ecu->addr_state = PFE_ECU_ADDR_LOST;
        ecu->claim_pending = false;
        ecu->cannot_claim_pending = true;
        ecu->request_pending = 0U;
    }
}

static void on_request(pfe_ecu_t *ecu, const pfe_can_frame_t *f)
{
    pfe_msg_request_t req;
    if ((pfe_codec_decode_request(f, &req) < 0) || (req.pgn.state != PFE_SIG_VALID)) {
        count_up(&ecu->count.rx_rejected, 1U);
        return;
    }
    if ((req.destination != PFE_J1939_ADDR_GLOBAL) && (req.destination != ecu->address)) {
        return; /* for someone else */
    }
    if (req.pgn.value == PFE_PGN_ADDRESS_CLAIMED) {
        if (ecu->addr_state == PFE_ECU_ADDR_LOST) {
            ecu->cannot_claim_pending = true;
        } else {
            ecu->claim_pending = true;
        }
        count_up(&ecu->count.requests_answered, 1U);
        return;
    }
    for (uint32_t k = 0U; k < OUT_COUNT; k++) {
        if (req.pgn.value == k_out_pgn[k]) {
            ecu->request_pending |= 1U << k;
            count_up(&ecu->count.requests_answered, 1U);
        }
    }
}

/* The last PFE_PlatoonConfig of a tick wins: the frame waits, undecoded,
 * for apply_platoon_config() after the queue, which rebuilds the model at
 * most once per tick. */
static void on_platoon_config(pfe_ecu_t *ecu, const pfe_can_frame_t *f, uint64_t rx_us)
{
    ecu->config_frame = *f;
    ecu->config_frame_us = rx_us;
    ecu->config_frame_pending = true;
}

/* The tick's last PFE_PlatoonConfig: decoded, and when it changes the
 * platoon, a rebuild started (rebuild_start()). */
static void apply_platoon_config(pfe_ecu_t *ecu)
{
    if (!ecu->config_frame_pending) {
        return;
    }
    ecu->config_frame_pending = false;
    pfe_msg_platoon_config_t m;
    if (pfe_codec_decode_platoon_config(&ecu->config_frame, &m) < 0) {
        count_up(&ecu->count.rx_rejected, 1U);
        return;
    }
    uint32_t gap_mm = 0U;
    pfe_sig_state_t st = m.n_vehicles.state;
    if (st == PFE_SIG_VALID) {
        st = m.own_position.state;
    }
    if ((st == PFE_SIG_VALID) && (pfe_codec_platoon_gap_mm(&m, &gap_mm) != PFE_SIG_VALID)) {
        st = PFE_SIG_NOT_AVAILABLE;
    }
    input_update(&ecu->config, st, ecu->config_frame_us);
    if (st != PFE_SIG_VALID) {
        return;
    }
    /* Against the platoon being built, if one is, else the one running. */
    const bool building = ecu->platoon_building;
    const uint32_t n = building ? ecu->build_n : ecu->platoon.n_vehicles;
    const uint32_t position = building ? ecu->build_position : ecu->own_position;
    const uint32_t gap = building ? ecu->build_gap_mm : ecu->platoon.gap_mm;
    const bool changed = (ecu->degraded && !building) || (m.n_vehicles.value != n) ||
                         (m.own_position.value != position) || (gap_mm != gap);
    ecu->platoon_msg = m;
    if (changed && (rebuild_start(ecu, m.n_vehicles.value, m.own_position.value, gap_mm) != PFE_OK)) {
        ecu->config.state = PFE_SIG_OUT_OF_RANGE;
    }
}

/* A frame from another node carrying our source address (J1939-81): never
 * an input. Counted; the module claims its address again, at most once per
 * PFE_ECU_RECLAIM_MIN_US so that a flood of them cannot make it flood. */
static void on_conflict(pfe_ecu_t *ecu)
{
    count_up(&ecu->conflicts, 1U);
    if (!ecu->reclaimed || ((ecu->now_us - ecu->reclaim_us) >= PFE_ECU_RECLAIM_MIN_US)) {
        ecu->claim_pending = true;
        ecu->reclaim_us = ecu->now_us;
        ecu->reclaimed = true;
    }
}

/* One arbitrated input's frame; returns whether the input took a new value or state. */
static bool take_input(pfe_ecu_t *ecu, pfe_input_kind_t kind, uint8_t sa, pfe_sig_state_t state,
                       int32_t value, uint64_t rx_us)
{
    const pfe_input_verdict_t v = pfe_input_take(&ecu->in[kind], sa, state, value, rx_us);
    return v == PFE_INPUT_ACCEPTED;
}

static void on_ccvs1(pfe_ecu_t *ecu, const pfe_can_frame_t *f, uint8_t sa, uint64_t rx_us)
{
    pfe_msg_ccvs1_t m;
    if (pfe_codec_decode_ccvs1(f, &m) < 0) {
        count_up(&ecu->count.rx_rejected, 1U);
        return;
    }
    if (take_input(ecu, PFE_IN_SPEED, sa, m.speed_mm_s.state, m.speed_mm_s.value, rx_us) &&
        (ecu->in[PFE_IN_SPEED].state == PFE_SIG_VALID)) {
        ecu->speed_mm_s = m.speed_mm_s.value;
        ecu->speed_fresh = true;
    }
}

static void on_ssi(pfe_ecu_t *ecu, const pfe_can_frame_t *f, uint8_t sa, uint64_t rx_us)
{
    pfe_msg_ssi_t m;
    if (pfe_codec_decode_ssi(f, &m) < 0) {
        count_up(&ecu->count.rx_rejected, 1U);
        return;
    }
    bool saturated = false;
    const int32_t grade = pfe_codec_grade_ppm_from_pitch(m.pitch_udeg.value, &saturated);
    if (take_input(ecu, PFE_IN_GRADE, sa, m.pitch_udeg.state, grade, rx_us)) {
        ecu->grade_saturated = saturated && (m.pitch_udeg.state == PFE_SIG_VALID);
    }
}

static void on_vds(pfe_ecu_t *ecu, const pfe_can_frame_t *f, uint8_t sa, uint64_t rx_us)
{
    pfe_msg_vds_t m;
    if (pfe_codec_decode_vds(f, &m) < 0) {
        count_up(&ecu->count.rx_rejected, 1U);
        return;
    }
    if (take_input(ecu, PFE_IN_ALTITUDE, sa, m.altitude_mm.state, m.altitude_mm.value, rx_us)) {
        if (ecu->in[PFE_IN_ALTITUDE].state == PFE_SIG_VALID) {
            pfe_altgrade_sample(&ecu->altgrade, ecu->odometer_um / 1000U, m.altitude_mm.value);
        } else {
            pfe_altgrade_reset(&ecu->altgrade);
        }
    }
}

static void on_cvw(pfe_ecu_t *ecu, const pfe_can_frame_t *f, uint8_t sa, uint64_t rx_us)
{
    pfe_msg_cvw_t m;
    if (pfe_codec_decode_cvw(f, &m) < 0) {
        count_up(&ecu->count.rx_rejected, 1U);
        return;
    }
    const pfe_sig_u32_t gcw = m.gross_combination_kg;
    if (take_input(ecu, PFE_IN_MASS, sa, gcw.state, (int32_t)gcw.value, rx_us) &&
        (ecu->in[PFE_IN_MASS].state == PFE_SIG_VALID)) {
        note_own_mass(ecu, gcw.value);
        ecu->cvw_mass = true;
        ecu->mass_source = (uint8_t)PFE_MASS_SOURCE_CVW;
    }
}

/* Another node's LFE1: the engine's measured fuel rate. */
static void on_lfe1(pfe_ecu_t *ecu, const pfe_can_frame_t *f, uint8_t sa, uint64_t rx_us)
{
    pfe_msg_lfe1_t m;
    if (pfe_codec_decode_lfe1(f, &m) < 0) {
        count_up(&ecu->count.rx_rejected, 1U);
        return;
    }
    /* A node that sends LFE1 with the rate "not available" (a cab
     * controller) reports no fuel rate: only one with a value is shadowed. */
    if (m.fuel_rate_nl_s.state != PFE_SIG_NOT_AVAILABLE) {
        ecu->other_lfe1_us = rx_us;
        ecu->other_lfe1_seen = true;
    }
    if (!take_input(ecu, PFE_IN_ENGINE_FUEL, sa, m.fuel_rate_nl_s.state,
                    (int32_t)m.fuel_rate_nl_s.value, rx_us) ||
        ecu->cfg.identification_off) {
        return;
    }
    /* One identification sample per accepted LFE1 of the engine, with the
     * speed and grade in use at that instant (the grade of the last tick). */
    const bool measured = ecu->grade_source <= (uint8_t)PFE_GRADE_SOURCE_ALTITUDE;
    const bool flat = ecu->grade_source == (uint8_t)PFE_GRADE_SOURCE_ASSUMED_FLAT;
    pfe_identify_sample_t smp;
    smp.now_us = rx_us;
    smp.speed_mm_s = ecu->speed_mm_s;
    smp.grade_ppm = ecu->grade_ppm;
    smp.fuel_rate_nl_s = m.fuel_rate_nl_s.value;
    smp.speed_valid = ecu->in[PFE_IN_SPEED].state == PFE_SIG_VALID;
    smp.grade_valid = measured || (flat && !ecu->cfg.identification_needs_grade);
    smp.fuel_valid = ecu->in[PFE_IN_ENGINE_FUEL].state == PFE_SIG_VALID;
    smp.braking = false; /* the module reads no brake signal */
    (void)pfe_identify_step(&ecu->identify, &smp);
    use_identified(ecu);
}

static void on_hrlfc(pfe_ecu_t *ecu, const pfe_can_frame_t *f, uint64_t rx_us)
{
    pfe_msg_hrlfc_t m;
    if (pfe_codec_decode_hrlfc(f, &m) < 0) {
        count_up(&ecu->count.rx_rejected, 1U);
        return;
    }
    if (m.total_fuel_ul.state != PFE_SIG_NOT_AVAILABLE) {
        ecu->other_hrlfc_us = rx_us;
        ecu->other_hrlfc_seen = true;
    }
}

static void on_preview(pfe_ecu_t *ecu, const pfe_can_frame_t *f, uint64_t rx_us)
{
    const int r = pfe_preview_push(&ecu->preview_buf, f);
    if (r < 0) {
        count_up(&ecu->count.rx_rejected, 1U);
    } else if ((ecu->preview_buf.phase == PFE_PREVIEW_RECEIVING) &&
               (ecu->preview_buf.next_index == 0U)) {
        /* A header: the preview's sample 0 is under the vehicle now, and
         * the prediction in progress was over the old one. */
        ecu->preview_travelled_um = 0U;
        pfe_predict_cancel(&ecu->predict);
    } else if (r == PFE_PREVIEW_COMPLETE) {
        ecu->preview_new = true;
        ecu->preview_serial++;
    } else {
        /* a data frame of a preview in progress */
    }
    input_update(&ecu->preview, (ecu->preview_buf.phase == PFE_PREVIEW_READY)
                                    ? PFE_SIG_VALID : PFE_SIG_NOT_AVAILABLE, rx_us);
}

static void on_frame(pfe_ecu_t *ecu, const pfe_can_frame_t *f, uint64_t rx_us)
{
    count_up(&ecu->count.rx_frames, 1U);
    if ((f->id & PFE_CAN_EFF_FLAG) == 0U) {
        count_up(&ecu->count.rx_rejected, 1U);
        return;
    }
    /* PGN with priority masked (and a PDU1 destination), then the sender. */
    const uint32_t pgn = pfe_j1939_pgn(f->id);
    const uint8_t sa = pfe_j1939_source(f->id);
    if (pgn == PFE_PGN_ADDRESS_CLAIMED) {
        on_address_claimed(ecu, f);
        return;
    }
    if ((sa == ecu->address) && (ecu->addr_state != PFE_ECU_ADDR_LOST)) {
        on_conflict(ecu);
        return;
    }
    if (pgn == PFE_PGN_CCVS1) {
        on_ccvs1(ecu, f, sa, rx_us);
    } else if (pgn == PFE_PGN_SSI) {
        on_ssi(ecu, f, sa, rx_us);
    } else if (pgn == PFE_PGN_PLATOON_CONFIG) {
        on_platoon_config(ecu, f, rx_us);
    } else if (pgn == PFE_PGN_GRADE_PREVIEW) {
        on_preview(ecu, f, rx_us);
    } else if (pgn == PFE_PGN_REQUEST) {
        on_request(ecu, f);
    } else if (pgn == PFE_PGN_VDS) {
        on_vds(ecu, f, sa, rx_us);
    } else if (pgn == PFE_PGN_CVW) {
        on_cvw(ecu, f, sa, rx_us);
    } else if (pgn == PFE_PGN_LFE1) {
        on_lfe1(ecu, f, sa, rx_us);
    } else if (pgn == PFE_PGN_HRLFC) {
        on_hrlfc(ecu, f, rx_us);
    } else {
        count_up(&ecu->count.rx_rejected, 1U);
    }
}

/* Not available once older than PFE_ECU_STALE_PERIODS periods. */
static void age(pfe_ecu_input_t *in, uint64_t now_us, uint32_t period_us)
{
    if (!in->seen || ((now_us - in->rx_us) > ((uint64_t)PFE_ECU_STALE_PERIODS * period_us))) {
        in->state = PFE_SIG_NOT_AVAILABLE;
        in->seen = false;
    }
}

static uint32_t clamp_counter(uint32_t c)
{
    return (c > PFE_STATUS_COUNTER_MAX) ? PFE_STATUS_COUNTER_MAX : c;
}

static pfe_sig_u32_t sig_u32(uint32_t v, bool ok)
{
    const pfe_sig_u32_t s = {v, ok ? PFE_SIG_VALID : PFE_SIG_NOT_AVAILABLE};
    return s;
}

static pfe_sig_u64_t sig_u64(uint64_t v)
{
    const pfe_sig_u64_t s = {v, PFE_SIG_VALID};
    return s;
}

static uint32_t sat_u32(uint64_t v)
{
    return (v > UINT32_MAX) ? UINT32_MAX : (uint32_t)v;
}

/* Step 5 of the tick: the prediction's share of work. */
static void predict(pfe_ecu_t *ecu, uint64_t now_us, bool work)
{
    const bool speed_ok = ecu->in[PFE_IN_SPEED].state == PFE_SIG_VALID;
    if (speed_ok && (ecu->speed_mm_s > 0)) {
        /* mm/s over 10 ms = 10 um per mm/s */
        ecu->preview_travelled_um += (uint64_t)ecu->speed_mm_s * (PFE_ECU_TICK_US / 1000U);
    }
    if (!work) {
        return; /* a burst's tick: the prediction goes on at the next */
    }
    if ((ecu->predict.phase == PFE_PREDICT_IDLE) && speed_ok &&
        (ecu->preview_buf.phase == PFE_PREVIEW_READY) &&
        (ecu->preview_new || ((now_us - ecu->predict_start_us) >= PFE_ECU_PREDICT_PERIOD_US))) {
        const int32_t set_speed = ((ecu->platoon_msg.set_speed_mm_s.state == PFE_SIG_VALID) &&
                                   !ecu->degraded)
                                      ? ecu->platoon_msg.set_speed_mm_s.value
                                      : ecu->cfg.default_set_speed_mm_s;
        const uint64_t travelled_mm = ecu->preview_travelled_um / 1000U;
        (void)pfe_predict_start(&ecu->predict, &ecu->preview_buf, ecu->preview_serial,
                                (travelled_mm > UINT32_MAX) ? UINT32_MAX : (uint32_t)travelled_mm,
                                &ecu->platoon, ecu->cfg.drag, ecu->cfg.cruise,
                                pfe_clamp_i32(set_speed, PFE_SIM_STALL_MM_S, PFE_SPEED_MAX_MM_S),
                                ecu->speed_mm_s);
        ecu->predict_start_us = now_us;
        ecu->preview_new = false;
    }
    (void)pfe_predict_run(&ecu->predict, &ecu->preview_buf, PFE_ECU_PREDICT_UNITS);
    const pfe_predict_result_t *r = pfe_predict_result(&ecu->predict);
    if (r->valid && (r->generation != ecu->predict_generation)) {
        ecu->predict_generation = r->generation;
        ecu->predict_result_us = now_us;
    }
}

static pfe_sig_u32_t sig_bit(bool on)
{
    return sig_u32(on ? 1U : 0U, true);
}

static void encode_status(const pfe_ecu_t *ecu, pfe_can_frame_t *f)
{
    const pfe_est_output_t *o = ecu->out;
    const uint32_t flags = (o != NULL) ? o->flags : 0U;
    const bool estimate = (flags & PFE_EST_VALID) != 0U;
    pfe_msg_status_t m;
    m.speed_input = ecu->in[PFE_IN_SPEED].state;
    m.grade_input = ecu->in[PFE_IN_GRADE].state;
    m.platoon_config_input = ecu->config.state;
    m.grade_preview_input = ecu->preview.state;
    const bool measured_grade = ecu->grade_source != (uint8_t)PFE_GRADE_SOURCE_ASSUMED_FLAT;
    m.mode = sig_u32(!estimate ? PFE_MODE_NO_ESTIMATE
                               : ((ecu->degraded || (ecu->preview.state != PFE_SIG_VALID) ||
                                   !measured_grade)
                                      ? PFE_MODE_DEGRADED : PFE_MODE_NORMAL), true);
    m.rx_frames_dropped = sig_u32(clamp_counter(ecu->count.rx_dropped), true);
    m.tick_overruns = sig_u32(clamp_counter(ecu->count.overruns), true);
    m.tx_frames_dropped = sig_u32(clamp_counter(ecu->count.tx_dropped), true);
    m.warming_up = sig_bit((flags & PFE_EST_WARMING_UP) != 0U);
    m.speed_clamped = sig_bit((flags & PFE_EST_SPEED_CLAMPED) != 0U);
    /* The pitch's grade saturates before the estimator sees it. */
    m.grade_clamped = sig_bit(((flags & PFE_EST_GRADE_CLAMPED) != 0U) ||
                              (ecu->grade_saturated &&
                               (ecu->grade_source == (uint8_t)PFE_GRADE_SOURCE_SLOPE_SENSOR)));
    m.output_saturated = sig_bit(((flags & PFE_EST_SATURATED) != 0U) || (ecu->outputs_clamped != 0U));
    uint32_t rejected = 0U;
    for (uint32_t k = 0U; k < (uint32_t)PFE_IN_COUNT; k++) {
        rejected = (ecu->in[k].rejected > (UINT32_MAX - rejected)) ? UINT32_MAX
                                                                    : (rejected + ecu->in[k].rejected);
    }
    m.inputs_rejected = sig_u32(clamp_counter(rejected), true);
    m.address_conflicts = sig_u32(clamp_counter(ecu->conflicts), true);
    (void)pfe_codec_encode_status(f, &m, ecu->address);
}

static pfe_sig_u32_t source_of(const pfe_input_t *in)
{
    const uint8_t sa = pfe_input_source(in);
    return sig_u32(sa, sa <= 253U);
}

static void encode_input_status(const pfe_ecu_t *ecu, pfe_can_frame_t *f)
{
    const pfe_input_t *grade_in = (ecu->grade_source == (uint8_t)PFE_GRADE_SOURCE_ALTITUDE)
                                      ? &ecu->in[PFE_IN_ALTITUDE] : &ecu->in[PFE_IN_GRADE];
    const bool grade_from_bus = ecu->grade_source <= (uint8_t)PFE_GRADE_SOURCE_ALTITUDE;
    pfe_msg_input_status_t m;
    m.speed_source = source_of(&ecu->in[PFE_IN_SPEED]);
    m.grade_source_address = grade_from_bus ? source_of(grade_in) : sig_u32(0U, false);
    m.fuel_rate_source = source_of(&ecu->in[PFE_IN_ENGINE_FUEL]);
    m.speed_senders = sig_u32(ecu->in[PFE_IN_SPEED].n_senders, true);
    m.grade_senders = sig_u32(ecu->in[PFE_IN_GRADE].n_senders, true);
    m.grade_source = sig_u32(ecu->grade_source, true);
    m.mass_source = sig_u32(ecu->mass_source, true);
    m.identification = sig_u32(pfe_identify_converged(&ecu->identify) ? 1U : 0U,
                               !ecu->cfg.identification_off);
    m.vehicle_mass_kg = sig_u32(ecu->own_calib.mass_kg, true);
    (void)pfe_codec_encode_input_status(f, &m, ecu->address);
}

static pfe_sig_u32_t bus_sig(const pfe_ecu_t *ecu, uint32_t v)
{
    return sig_u32(clamp_counter(v), ecu->bus_known);
}

static void encode_device_status(const pfe_ecu_t *ecu, pfe_can_frame_t *f)
{
    const pfe_ecu_bus_state_t *b = &ecu->bus;
    pfe_msg_device_status_t m;
    m.rx_fifo_overruns = bus_sig(ecu, b->rx_overruns);
    m.bus_off_events = bus_sig(ecu, b->bus_off_events);
    m.error_warning = bus_sig(ecu, b->error_warning ? 1U : 0U);
    m.error_passive = bus_sig(ecu, b->error_passive ? 1U : 0U);
    m.bus_off = bus_sig(ecu, b->bus_off ? 1U : 0U);
    m.nvm_write_failing = sig_bit(ecu->nvm_failing);
    m.reset_cause = sig_u32((uint32_t)ecu->reset_cause, ecu->reset_cause_known);
    m.tx_error_counter = bus_sig(ecu, b->tx_error_counter);
    m.rx_error_counter = bus_sig(ecu, b->rx_error_counter);
    m.nvm_write_failures = sig_u32(clamp_counter(ecu->count.nvm_write_failures), true);
    (void)pfe_codec_encode_device_status(f, &m, ecu->address);
}

/* The own truck's rate, or not available. */
static pfe_sig_u32_t own_rate(const pfe_ecu_t *ecu)
{
    const pfe_est_output_t *o = ecu->out;
    const bool ok = (o != NULL) && ((o->flags & PFE_EST_VALID) != 0U);
    return sig_u32(ok ? o->pos_fuel_rate_nl_s[ecu->own_position] : 0U, ok);
}

/* Returns the mask of signals the codec clamped. */
static int encode_fuel_output(pfe_ecu_t *ecu, uint32_t which, pfe_can_frame_t *f)
{
    const pfe_est_output_t *o = ecu->out;
    const bool ok = (o != NULL) && ((o->flags & PFE_EST_VALID) != 0U);
    const uint8_t sa = ecu->address;
    int r = 0;
    if (which == OUT_LFE1) {
        const pfe_msg_lfe1_t m = {own_rate(ecu)};
        r = pfe_codec_encode_lfe1(f, &m, sa);
    } else if (which == OUT_PLATOON_FUEL) {
        const pfe_msg_platoon_fuel_t m = {sig_u32(ok ? o->fuel_rate_nl_s : 0U, ok),
                                          sig_u64(pfe_ecu_platoon_fuel_ul(ecu))};
        r = pfe_codec_encode_platoon_fuel(f, &m, sa);
    } else if (which == OUT_HRLFC) {
        const pfe_msg_hrlfc_t m = {{0U, PFE_SIG_NOT_AVAILABLE}, sig_u64(pfe_ecu_own_fuel_ul(ecu))};
        r = pfe_codec_encode_hrlfc(f, &m, sa);
    } else if (which == OUT_OWN_FUEL) {
        pfe_msg_own_fuel_t m;
        m.fuel_rate_nl_s = own_rate(ecu);
        m.fuel_used_ul = sig_u64(pfe_ecu_own_fuel_ul(ecu));
        m.model_identified = sig_u32(ecu->aux_identified ? 1U : 0U, true);
        r = pfe_codec_encode_own_fuel(f, &m, sa);
    } else {
        const pfe_predict_result_t *p = pfe_predict_result(&ecu->predict);
        const bool fresh = p->valid && (ecu->preview.state == PFE_SIG_VALID) &&
                           ((ecu->now_us - ecu->predict_result_us) <= PFE_ECU_PREDICT_MAX_AGE_US);
        const pfe_msg_fuel_prediction_t m = {
            sig_u32(fresh ? sat_u32(p->fuel_ul) : 0U, fresh),
            sig_u32(fresh ? sat_u32(p->fuel_lower_ul) : 0U, fresh),
            sig_u32(fresh ? sat_u32(p->fuel_upper_ul) : 0U, fresh),
            sig_u32(fresh ? p->time_ms : 0U, fresh),
        };
        r = pfe_codec_encode_fuel_prediction(f, &m, sa);
    }
    return r;
}

static void encode_output(pfe_ecu_t *ecu, uint32_t which, pfe_can_frame_t *f)
{
    if (which == OUT_STATUS) {
        encode_status(ecu, f); /* its counters are clamped before encoding */
        return;
    }
    if (which == OUT_INPUT_STATUS) {
        encode_input_status(ecu, f);
        return;
    }
    if (which == OUT_DEVICE_STATUS) {
        encode_device_status(ecu, f);
        return;
    }
    /* An encoder returns the signals it clamped: the status says so until
     * that output's next frame goes out unclamped. */
    if (encode_fuel_output(ecu, which, f) > 0) {
        ecu->outputs_clamped |= 1U << which;
    } else {
        ecu->outputs_clamped &= ~(1U << which);
    }
}

/* LFE1 and HRLFC are the engine's PGNs: sent (AUTO) only after listening
 * three periods with no other sender, and not while another node sent it in
 * the last three periods (can_dbc/pfe.dbc). */
static bool j1939_fuel_due(const pfe_ecu_t *ecu, bool seen, uint64_t last_us, uint32_t period_us)
{
    if (ecu->cfg.j1939_fuel == PFE_ECU_J1939_FUEL_ALWAYS) {
        return true;
    }
    if (ecu->cfg.j1939_fuel == PFE_ECU_J1939_FUEL_NEVER) {
        return false;
    }
    const uint64_t window_us = (uint64_t)PFE_INPUT_STALE_PERIODS * period_us;
    const bool listened = (ecu->now_us - ecu->start_us) >= window_us;
    const bool other = seen && ((ecu->now_us - last_us) <= window_us);
    return listened && !other;
}

static uint32_t emit(pfe_ecu_t *ecu, pfe_can_frame_t *tx, uint32_t n, uint32_t cap,
                     const pfe_can_frame_t *f)
{
    if (n < cap) {
        tx[n] = *f;
        count_up(&ecu->count.tx_frames, 1U);
        return n + 1U;
    }
    count_up(&ecu->count.tx_dropped, 1U);
    return n;
}

/* Address Claimed (or, from PFE_J1939_ADDR_NULL, "cannot claim") with our NAME. */
static void encode_claim(const pfe_ecu_t *ecu, pfe_can_frame_t *f, uint8_t source)
{
    pfe_j1939_name_t name;
    pfe_j1939_name_unpack(ecu->cfg.name, &name);
    (void)pfe_codec_encode_address_claimed(f, &name, source);
}

/* The grade the estimator gets: SSI pitch, else the altitude's grade, else
 * flat (unless the calibration forbids it). Sets ecu->grade_source. */
static bool grade_in_use(pfe_ecu_t *ecu, int32_t *grade_ppm)
{
    const pfe_input_t *ssi = &ecu->in[PFE_IN_GRADE];
    if (ssi->state == PFE_SIG_VALID) {
        ecu->grade_source = (uint8_t)PFE_GRADE_SOURCE_SLOPE_SENSOR;
        *grade_ppm = ssi->value;
        return true;
    }
    if ((ecu->in[PFE_IN_ALTITUDE].state == PFE_SIG_VALID) &&
        pfe_altgrade_grade(&ecu->altgrade, grade_ppm)) {
        ecu->grade_source = (uint8_t)PFE_GRADE_SOURCE_ALTITUDE;
        return true;
    }
    *grade_ppm = 0;
    /* A slope sensor in error is a fault, not an absent sensor: no estimate. */
    if (!ecu->cfg.flat_grade_forbidden && (ssi->state != PFE_SIG_ERROR) &&
        (ssi->state != PFE_SIG_OUT_OF_RANGE)) {
        ecu->grade_source = (uint8_t)PFE_GRADE_SOURCE_ASSUMED_FLAT;
        return true;
    }
    ecu->grade_source = (uint8_t)PFE_GRADE_SOURCE_NONE;
    return false;
}

static void age_inputs(pfe_ecu_t *ecu, uint64_t now_us)
{
    for (uint32_t k = 0U; k < (uint32_t)PFE_IN_COUNT; k++) {
        const bool was = ecu->in[k].state == PFE_SIG_VALID;
        if (!pfe_input_age(&ecu->in[k], now_us) && was && (k == (uint32_t)PFE_IN_ALTITUDE)) {
            pfe_altgrade_reset(&ecu->altgrade);
        }
    }
    age(&ecu->config, now_us, period_us(PFE_MSG_PLATOON_CONFIG));
    if ((ecu->config.state != PFE_SIG_VALID) && !ecu->degraded) {
        /* Keep the last platoon; say that it is no longer confirmed. */
        ecu->degraded = true;
    }
}

uint32_t pfe_ecu_tick(pfe_ecu_t *ecu, uint64_t now_us, pfe_can_frame_t *tx, uint32_t tx_cap)
{
    ecu->now_us = now_us;
    /* A speed sample that comes while a platoon is built (the estimator
     * paused) waits for the estimator's next step: warm-up loses none. */
    if (!ecu->platoon_building) {
        ecu->speed_fresh = false;
    }
    /* Bounded work: PFE_ECU_RX_PER_TICK frames (PFE_ECU_RX_LIGHT while a
     * platoon is being built), then either a share of the rebuild or of the
     * prediction, only in a tick that decoded at most PFE_ECU_RX_LIGHT.
     * What a burst leaves waits for the next tick. */
    const uint32_t cap = ecu->platoon_building ? PFE_ECU_RX_LIGHT : PFE_ECU_RX_PER_TICK;
    uint32_t drained = 0U;
    while ((ecu->rxq_count > 0U) && (drained < cap)) {
        const uint32_t k = ecu->rxq_head;
        ecu->rxq_head = (ecu->rxq_head + 1U) % PFE_ECU_RX_QUEUE_LEN;
        ecu->rxq_count--;
        on_frame(ecu, &ecu->rxq[k], ecu->rxq_us[k]);
        drained++;
    }
    apply_platoon_config(ecu);
    apply_own_mass(ecu);
    const bool light = drained <= PFE_ECU_RX_LIGHT;
    const bool rebuilt = light && rebuild_step(ecu);
    age_inputs(ecu, now_us);
    const bool speed_ok = ecu->in[PFE_IN_SPEED].state == PFE_SIG_VALID;
    if (speed_ok && (ecu->speed_mm_s > 0)) {
        /* mm/s over 10 ms = 10 um per mm/s */
        ecu->odometer_um += (uint64_t)ecu->speed_mm_s * (PFE_ECU_TICK_US / 1000U);
    }
    int32_t grade_ppm = 0;
    const bool grade_ok = grade_in_use(ecu, &grade_ppm);
    ecu->grade_ppm = grade_ppm;

    const pfe_est_input_t in = {
        ecu->speed_mm_s, speed_ok, ecu->speed_fresh, grade_ppm, grade_ok,
    };
    /* While a platoon is being built the estimator pauses: not available. */
    ecu->out = ecu->platoon_building ? NULL : pfe_estimator_step(&ecu->est, &in);
    predict(ecu, now_us, light && !rebuilt);

    uint32_t n = 0U;
    pfe_can_frame_t f;
    if (ecu->cannot_claim_pending) {
        encode_claim(ecu, &f, PFE_J1939_ADDR_NULL);
        n = emit(ecu, tx, n, tx_cap, &f);
        ecu->cannot_claim_pending = false;
    }
    if (ecu->claim_pending && (ecu->addr_state != PFE_ECU_ADDR_LOST)) {
        encode_claim(ecu, &f, ecu->address);
        n = emit(ecu, tx, n, tx_cap, &f);
        ecu->claim_pending = false;
    }
    if ((ecu->addr_state == PFE_ECU_ADDR_CLAIMING) &&
        ((now_us - ecu->claim_us) >= PFE_ECU_CLAIM_WAIT_US)) {
        ecu->addr_state = PFE_ECU_ADDR_CLAIMED;
    }
    if (ecu->addr_state == PFE_ECU_ADDR_CLAIMED) {
        /* Schedule (can_dbc/pfe.dbc GenMsgCycleTime), spread over ticks. */
        const uint32_t t = ecu->tick;
        uint32_t due = ecu->request_pending;
        due |= out_due(t, OUT_LFE1, 0U) ? (1U << (uint32_t)OUT_LFE1) : 0U;
        due |= out_due(t, OUT_PLATOON_FUEL, 1U) ? (1U << (uint32_t)OUT_PLATOON_FUEL) : 0U;
        due |= out_due(t, OUT_HRLFC, 2U) ? (1U << (uint32_t)OUT_HRLFC) : 0U;
        due |= out_due(t, OUT_PREDICTION, 3U) ? (1U << (uint32_t)OUT_PREDICTION) : 0U;
        due |= out_due(t, OUT_STATUS, 4U) ? (1U << (uint32_t)OUT_STATUS) : 0U;
        due |= out_due(t, OUT_OWN_FUEL, 2U) ? (1U << (uint32_t)OUT_OWN_FUEL) : 0U;
        due |= out_due(t, OUT_INPUT_STATUS, 5U) ? (1U << (uint32_t)OUT_INPUT_STATUS) : 0U;
        due |= out_due(t, OUT_DEVICE_STATUS, 6U) ? (1U << (uint32_t)OUT_DEVICE_STATUS) : 0U;
        /* most ticks send nothing: each test below only when it can matter */
        if (((due & (1U << (uint32_t)OUT_LFE1)) != 0U) &&
            !j1939_fuel_due(ecu, ecu->other_lfe1_seen, ecu->other_lfe1_us, period_us(PFE_MSG_LFE1))) {
            due &= ~(1U << (uint32_t)OUT_LFE1);
        }
        if (((due & (1U << (uint32_t)OUT_HRLFC)) != 0U) &&
            !j1939_fuel_due(ecu, ecu->other_hrlfc_seen, ecu->other_hrlfc_us, period_us(PFE_MSG_HRLFC))) {
            due &= ~(1U << (uint32_t)OUT_HRLFC);
        }
        if (due != 0U) {
            for (uint32_t k = 0U; k < OUT_COUNT; k++) {
                if ((due & (1U << k)) != 0U) {
                    encode_output(ecu, k, &f);
                    n = emit(ecu, tx, n, tx_cap, &f);
                }
            }
        }
        ecu->request_pending = 0U;
        ecu->tick++;
    }
    return n;
}

void pfe_ecu_note_overrun(pfe_ecu_t *ecu, uint32_t ticks)
{
    count_up(&ecu->count.overruns, ticks);
}

void pfe_ecu_note_tx_dropped(pfe_ecu_t *ecu, uint32_t frames)
{
    count_up(&ecu->count.tx_dropped, frames);
}

void pfe_ecu_note_rx_dropped(pfe_ecu_t *ecu, uint32_t frames)
{
    count_up(&ecu->count.rx_dropped, frames);
}

void pfe_ecu_note_bus_state(pfe_ecu_t *ecu, const pfe_ecu_bus_state_t *bus)
{
    if (bus != NULL) {
        ecu->bus = *bus;
        ecu->bus_known = true;
    }
}

void pfe_ecu_note_reset_cause(pfe_ecu_t *ecu, pfe_reset_cause_t cause)
{
    const bool known = (cause == PFE_RESET_POWER_ON) || (cause == PFE_RESET_WATCHDOG) ||
                       (cause == PFE_RESET_SOFTWARE);
    ecu->reset_cause = known ? cause : PFE_RESET_OTHER;
    ecu->reset_cause_known = true;
}

bool pfe_ecu_nvm_due(const pfe_ecu_t *ecu)
{
    return (ecu->now_us - ecu->last_save_us) >= ((uint64_t)ecu->cfg.save_interval_ms * 1000U);
}

uint32_t pfe_ecu_nvm_slot(const pfe_ecu_t *ecu)
{
    return pfe_nvm_next_slot(ecu->nvm_last_slot);
}

void pfe_ecu_nvm_take(const pfe_ecu_t *ecu, pfe_nvm_state_t *out)
{
    out->sequence = ecu->nvm_sequence + 1U;
    out->own_fuel_ul = pfe_ecu_own_fuel_ul(ecu);
    out->platoon_fuel_ul = pfe_ecu_platoon_fuel_ul(ecu);
    /* identification once it has learnt something: kept across a reset */
    const bool learnt = pfe_identify_counters(&ecu->identify)->mass_updates > 0U;
    const bool converged = pfe_identify_converged(&ecu->identify);
    out->id_mass_kg = learnt ? pfe_identify_mass_kg(&ecu->identify) : 0U;
    out->id_aux_w = learnt ? pfe_identify_aux_power_w(&ecu->identify) : 0U;
    out->id_flags = 0U;
    if (learnt) {
        out->id_flags |= PFE_NVM_ID_VALID;
    }
    if (converged) {
        out->id_flags |= PFE_NVM_ID_CONVERGED;
    }
}

void pfe_ecu_nvm_written(pfe_ecu_t *ecu, int result)
{
    const bool completed = result == 0;
    if (completed) {
        ecu->nvm_sequence++;
        ecu->nvm_last_slot = (int)pfe_nvm_next_slot(ecu->nvm_last_slot);
        ecu->last_save_us = ecu->now_us;
        ecu->nvm_fail_streak = 0U;
        ecu->nvm_failing = false;
    } else {
        /* Slot, sequence and interval stay: the next tick writes the same
         * slot again, and the other slot keeps the last completed record. */
        count_up(&ecu->count.nvm_write_failures, 1U);
        count_up(&ecu->nvm_fail_streak, 1U);
        if (ecu->nvm_fail_streak >= PFE_ECU_NVM_FAILING_AFTER) {
            ecu->nvm_failing = true;
        }
    }
}

uint64_t pfe_ecu_own_fuel_ul(const pfe_ecu_t *ecu)
{
    if (ecu->platoon_building) {
        return ecu->build_own_ul;
    }
    return pfe_estimator_fuel_used_ul(&ecu->est, (int32_t)ecu->own_position);
}

uint64_t pfe_ecu_platoon_fuel_ul(const pfe_ecu_t *ecu)
{
    if (ecu->platoon_building) {
        return ecu->build_platoon_ul;
    }
    return pfe_estimator_fuel_used_ul(&ecu->est, PFE_EST_PLATOON);
}
