/* pfe_ecu.c - the module as a J1939 ECU (contract in pfe_ecu.h). */
#include "pfe_ecu.h"

#include <stddef.h>
#include <string.h>

#include "pfe_fixed.h"

#define SPEED_PERIOD_US 100000U    /* CCVS1 */
#define GRADE_PERIOD_US 10000U     /* SSI */
#define CONFIG_PERIOD_US 1000000U  /* PFE_PlatoonConfig */
#define TICKS_PER_100MS 10U
#define TICKS_PER_1S 100U
#define ARBITRARY_FIRST 128U       /* J1939 self-configurable address range */
#define ARBITRARY_LAST 247U

/* Output messages, one bit each in request_pending. */
enum { OUT_LFE1, OUT_PLATOON_FUEL, OUT_HRLFC, OUT_PREDICTION, OUT_STATUS, OUT_COUNT };

static const uint32_t k_out_pgn[OUT_COUNT] = {PFE_PGN_LFE1, PFE_PGN_PLATOON_FUEL, PFE_PGN_HRLFC,
                                              PFE_PGN_FUEL_PREDICTION, PFE_PGN_STATUS};

#define PDU2_MASK (PFE_CAN_EFF_FLAG | 0x03FFFF00UL) /* EDP, DP, PF, PS */
#define PDU1_MASK (PFE_CAN_EFF_FLAG | 0x03FF0000UL) /* EDP, DP, PF: any destination */

const pfe_ecu_filter_t pfe_ecu_rx_filters[PFE_ECU_RX_FILTERS] = {
    {PFE_CAN_EFF_FLAG | (PFE_PGN_CCVS1 << 8), PDU2_MASK},
    {PFE_CAN_EFF_FLAG | (PFE_PGN_SSI << 8), PDU2_MASK},
    {PFE_CAN_EFF_FLAG | (PFE_PGN_PLATOON_CONFIG << 8), PDU2_MASK},
    {PFE_CAN_EFF_FLAG | (PFE_PGN_GRADE_PREVIEW << 8), PDU2_MASK},
    {PFE_CAN_EFF_FLAG | (PFE_PGN_REQUEST << 8), PDU1_MASK},
    {PFE_CAN_EFF_FLAG | (PFE_PGN_ADDRESS_CLAIMED << 8), PDU1_MASK},
};

static void count_up(uint32_t *c, uint32_t n)
{
    *c = (*c > (UINT32_MAX - n)) ? UINT32_MAX : (*c + n);
}

/* Makes ecu->platoon_next (built) the model, the own truck at `position`.
 * Totals carry over a change of platoon: the own truck's to its new
 * position. Read before the platoon changes: the estimator reads a
 * position's total only below the platoon's size. */
static void adopt_platoon(pfe_ecu_t *ecu, const pfe_platoon_t *next, uint32_t position)
{
    const uint64_t own = pfe_ecu_own_fuel_ul(ecu);
    const uint64_t platoon = pfe_ecu_platoon_fuel_ul(ecu);
    if (next != &ecu->platoon) {
        ecu->platoon = *next;
    }
    /* The prediction in progress was for the old platoon. */
    pfe_predict_cancel(&ecu->predict);
    (void)pfe_estimator_init(&ecu->est, &ecu->platoon);
    ecu->own_position = position;
    (void)pfe_estimator_set_fuel_used_ul(&ecu->est, (int32_t)position, own);
    (void)pfe_estimator_set_fuel_used_ul(&ecu->est, PFE_EST_PLATOON, platoon);
}

/* The platoon at once (start-up). */
static int configure(pfe_ecu_t *ecu, uint32_t n, uint32_t position, uint32_t gap_mm)
{
    pfe_platoon_config_t pc;
    pfe_platoon_config_uniform(&pc, n, gap_mm, ecu->cfg.vehicle, ecu->cfg.env, ecu->cfg.drag);
    if ((pc.n_vehicles != n) || (position >= n) || (pfe_platoon_init(&ecu->platoon_next, &pc) != PFE_OK)) {
        return PFE_EINVAL;
    }
    adopt_platoon(ecu, &ecu->platoon_next, position);
    return PFE_OK;
}

/* The platoon of a PFE_PlatoonConfig, built over the next ticks
 * (rebuild_step()) into platoon_next while the old one runs. */
static int rebuild_start(pfe_ecu_t *ecu, uint32_t n, uint32_t position, uint32_t gap_mm)
{
    pfe_platoon_config_t *pc = &ecu->platoon_next_cfg;
    pfe_platoon_config_uniform(pc, n, gap_mm, ecu->cfg.vehicle, ecu->cfg.env, ecu->cfg.drag);
    ecu->platoon_building = false;
    if ((pc->n_vehicles != n) || (position >= n) || (pfe_platoon_init_begin(pc) != PFE_OK)) {
        return PFE_EINVAL;
    }
    ecu->platoon_next_position = position;
    ecu->platoon_next_built = 0U;
    ecu->platoon_building = true;
    return PFE_OK;
}

/* One tick's share of the rebuild: PFE_ECU_REBUILD_PER_TICK positions, or
 * the aggregates and the switch. Returns whether it did any work. */
static bool rebuild_step(pfe_ecu_t *ecu)
{
    if (!ecu->platoon_building) {
        return false;
    }
    const pfe_platoon_config_t *pc = &ecu->platoon_next_cfg;
    int rc = PFE_OK;
    if (ecu->platoon_next_built < pc->n_vehicles) {
        rc = pfe_platoon_init_positions(&ecu->platoon_next, pc, ecu->platoon_next_built,
                                        PFE_ECU_REBUILD_PER_TICK);
        ecu->platoon_next_built += PFE_ECU_REBUILD_PER_TICK;
    } else {
        rc = pfe_platoon_init_finish(&ecu->platoon_next, pc);
        if (rc == PFE_OK) {
            adopt_platoon(ecu, &ecu->platoon_next, ecu->platoon_next_position);
            ecu->degraded = false;
        }
        ecu->platoon_building = false;
    }
    if (rc != PFE_OK) {
        ecu->platoon_building = false;
        ecu->config.state = PFE_SIG_OUT_OF_RANGE;
    }
    return true;
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
    pfe_predict_init(&ecu->predict);
    ecu->own_position = 0U;
    /* Fuel used before the first configure() is zero; configure() re-applies it. */
    pfe_platoon_config_t pc;
    pfe_platoon_config_uniform(&pc, 1U, cfg->default_gap_mm, cfg->vehicle, cfg->env, cfg->drag);
    if ((pfe_platoon_init(&ecu->platoon, &pc) != PFE_OK) ||
        (pfe_estimator_init(&ecu->est, &ecu->platoon) != PFE_OK)) {
        return PFE_EINVAL;
    }
    if (restored != NULL) {
        (void)pfe_estimator_set_fuel_used_ul(&ecu->est, 0, restored->own_fuel_ul);
        (void)pfe_estimator_set_fuel_used_ul(&ecu->est, PFE_EST_PLATOON, restored->platoon_fuel_ul);
        ecu->nvm_sequence = restored->sequence;
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
    ecu->speed.state = PFE_SIG_NOT_AVAILABLE;
    ecu->grade.state = PFE_SIG_NOT_AVAILABLE;
    ecu->config.state = PFE_SIG_NOT_AVAILABLE;
    ecu->preview.state = PFE_SIG_NOT_AVAILABLE;
    pfe_preview_init(&ecu->preview_buf);
    ecu->out = NULL;
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
    const uint32_t n = building ? ecu->platoon_next_cfg.n_vehicles : ecu->platoon.n_vehicles;
    const uint32_t position = building ? ecu->platoon_next_position : ecu->own_position;
    const uint32_t gap = building ? ecu->platoon_next_cfg.gap_mm : ecu->platoon.gap_mm;
    const bool changed = (ecu->degraded && !building) || (m.n_vehicles.value != n) ||
                         (m.own_position.value != position) || (gap_mm != gap);
    ecu->platoon_msg = m;
    if (changed && (rebuild_start(ecu, m.n_vehicles.value, m.own_position.value, gap_mm) != PFE_OK)) {
        ecu->config.state = PFE_SIG_OUT_OF_RANGE;
    }
}

static void on_frame(pfe_ecu_t *ecu, const pfe_can_frame_t *f, uint64_t rx_us)
{
    count_up(&ecu->count.rx_frames, 1U);
    if ((f->id & PFE_CAN_EFF_FLAG) == 0U) {
        count_up(&ecu->count.rx_rejected, 1U);
        return;
    }
    /* PGN with priority and source masked (J1939-21). */
    const uint32_t pgn = pfe_j1939_pgn(f->id);
    if (pgn == PFE_PGN_CCVS1) {
        pfe_msg_ccvs1_t m;
        if (pfe_codec_decode_ccvs1(f, &m) < 0) {
            count_up(&ecu->count.rx_rejected, 1U);
            return;
        }
        input_update(&ecu->speed, m.speed_mm_s.state, rx_us);
        ecu->speed_mm_s = m.speed_mm_s.value;
    } else if (pgn == PFE_PGN_SSI) {
        pfe_msg_ssi_t m;
        if (pfe_codec_decode_ssi(f, &m) < 0) {
            count_up(&ecu->count.rx_rejected, 1U);
            return;
        }
        bool saturated = false;
        ecu->grade_ppm = pfe_codec_grade_ppm_from_pitch(m.pitch_udeg.value, &saturated);
        ecu->grade_saturated = saturated;
        input_update(&ecu->grade, m.pitch_udeg.state, rx_us);
    } else if (pgn == PFE_PGN_PLATOON_CONFIG) {
        on_platoon_config(ecu, f, rx_us);
    } else if (pgn == PFE_PGN_GRADE_PREVIEW) {
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
    } else if (pgn == PFE_PGN_REQUEST) {
        on_request(ecu, f);
    } else if (pgn == PFE_PGN_ADDRESS_CLAIMED) {
        on_address_claimed(ecu, f);
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
    const bool speed_ok = ecu->speed.state == PFE_SIG_VALID;
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

static void encode_output(pfe_ecu_t *ecu, uint32_t which, pfe_can_frame_t *f)
{
    const pfe_est_output_t *o = ecu->out;
    const bool ok = (o != NULL) && ((o->flags & PFE_EST_VALID) != 0U);
    const uint8_t sa = ecu->address;
    int r = 0;
    if (which == OUT_LFE1) {
        const pfe_msg_lfe1_t m = {sig_u32(ok ? o->pos_fuel_rate_nl_s[ecu->own_position] : 0U, ok)};
        r = pfe_codec_encode_lfe1(f, &m, sa);
    } else if (which == OUT_PLATOON_FUEL) {
        const pfe_msg_platoon_fuel_t m = {sig_u32(ok ? o->fuel_rate_nl_s : 0U, ok),
                                          sig_u64(pfe_ecu_platoon_fuel_ul(ecu))};
        r = pfe_codec_encode_platoon_fuel(f, &m, sa);
    } else if (which == OUT_HRLFC) {
        const pfe_msg_hrlfc_t m = {{0U, PFE_SIG_NOT_AVAILABLE}, sig_u64(pfe_ecu_own_fuel_ul(ecu))};
        r = pfe_codec_encode_hrlfc(f, &m, sa);
    } else if (which == OUT_PREDICTION) {
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
    } else {
        const uint32_t flags = (o != NULL) ? o->flags : 0U;
        const bool estimate = ok;
        pfe_msg_status_t m;
        m.speed_input = ecu->speed.state;
        m.grade_input = ecu->grade.state;
        m.platoon_config_input = ecu->config.state;
        m.grade_preview_input = ecu->preview.state;
        m.mode = sig_u32(!estimate ? PFE_MODE_NO_ESTIMATE
                                   : ((ecu->degraded || (ecu->preview.state != PFE_SIG_VALID))
                                          ? PFE_MODE_DEGRADED : PFE_MODE_NORMAL), true);
        m.rx_frames_dropped = sig_u32(clamp_counter(ecu->count.rx_dropped), true);
        m.tick_overruns = sig_u32(clamp_counter(ecu->count.overruns), true);
        m.tx_frames_dropped = sig_u32(clamp_counter(ecu->count.tx_dropped), true);
        m.warming_up = sig_u32(((flags & PFE_EST_WARMING_UP) != 0U) ? 1U : 0U, true);
        m.speed_clamped = sig_u32(((flags & PFE_EST_SPEED_CLAMPED) != 0U) ? 1U : 0U, true);
        /* The pitch's grade saturates before the estimator sees it. */
        const bool grade_clamped = ((flags & PFE_EST_GRADE_CLAMPED) != 0U) ||
                                   (ecu->grade_saturated && (ecu->grade.state == PFE_SIG_VALID));
        m.grade_clamped = sig_u32(grade_clamped ? 1U : 0U, true);
        const bool saturated = ((flags & PFE_EST_SATURATED) != 0U) || (ecu->outputs_clamped != 0U);
        m.output_saturated = sig_u32(saturated ? 1U : 0U, true);
        r = pfe_codec_encode_status(f, &m, sa);
    }
    /* An encoder returns the signals it clamped: the status says so until
     * that output's next frame goes out unclamped. The status's own
     * counters are clamped before encoding. */
    if (which != OUT_STATUS) {
        if (r > 0) {
            ecu->outputs_clamped |= 1U << which;
        } else {
            ecu->outputs_clamped &= ~(1U << which);
        }
    }
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

uint32_t pfe_ecu_tick(pfe_ecu_t *ecu, uint64_t now_us, pfe_can_frame_t *tx, uint32_t tx_cap)
{
    ecu->now_us = now_us;
    ecu->speed.fresh = false;
    ecu->grade.fresh = false;
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
    const bool light = drained <= PFE_ECU_RX_LIGHT;
    const bool rebuilt = light && rebuild_step(ecu);
    age(&ecu->speed, now_us, SPEED_PERIOD_US);
    age(&ecu->grade, now_us, GRADE_PERIOD_US);
    age(&ecu->config, now_us, CONFIG_PERIOD_US);
    if ((ecu->config.state != PFE_SIG_VALID) && !ecu->degraded) {
        /* Keep the last platoon; say that it is no longer confirmed. */
        ecu->degraded = true;
    }

    const pfe_est_input_t in = {
        ecu->speed_mm_s, ecu->speed.state == PFE_SIG_VALID, ecu->speed.fresh,
        ecu->grade_ppm, ecu->grade.state == PFE_SIG_VALID,
    };
    ecu->out = pfe_estimator_step(&ecu->est, &in);
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
        const uint32_t t100 = ecu->tick % TICKS_PER_100MS;
        const uint32_t t1s = ecu->tick % TICKS_PER_1S;
        uint32_t due = ecu->request_pending;
        due |= (t100 == 0U) ? (1U << (uint32_t)OUT_LFE1) : 0U;
        due |= (t100 == 1U) ? (1U << (uint32_t)OUT_PLATOON_FUEL) : 0U;
        due |= (t1s == 2U) ? (1U << (uint32_t)OUT_HRLFC) : 0U;
        due |= (t1s == 3U) ? (1U << (uint32_t)OUT_PREDICTION) : 0U;
        due |= (t1s == 4U) ? (1U << (uint32_t)OUT_STATUS) : 0U;
        for (uint32_t k = 0U; k < OUT_COUNT; k++) {
            if ((due & (1U << k)) != 0U) {
                encode_output(ecu, k, &f);
                n = emit(ecu, tx, n, tx_cap, &f);
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
    return pfe_estimator_fuel_used_ul(&ecu->est, (int32_t)ecu->own_position);
}

uint64_t pfe_ecu_platoon_fuel_ul(const pfe_ecu_t *ecu)
{
    return pfe_estimator_fuel_used_ul(&ecu->est, PFE_EST_PLATOON);
}
