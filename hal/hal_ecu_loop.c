/* hal_ecu_loop.c - the ECU's main loop over the HAL (contract in hal_ecu_loop.h). */
#include "hal/hal_ecu_loop.h"

#include <stddef.h>
#include <string.h>

#include "firmware/pfe_calib.h"
#include "firmware/pfe_fixed.h"

void hal_ecu_loop_config(pfe_ecu_config_t *cfg, uint8_t address, uint32_t save_interval_ms,
                         uint32_t vehicles, uint32_t position, uint32_t gap_mm)
{
    (void)memset(cfg, 0, sizeof *cfg);
    cfg->preferred_address = address;
    cfg->name = 0x80A0000000000001ULL | ((uint64_t)address << 1);
    cfg->save_interval_ms = save_interval_ms;
    cfg->vehicle = &pfe_default_vehicle;
    cfg->env = &pfe_default_env;
    cfg->drag = &pfe_default_drag;
    cfg->default_vehicles = vehicles;
    cfg->default_position = position;
    cfg->default_gap_mm = gap_mm;
    cfg->cruise = &pfe_default_cruise;
    cfg->default_set_speed_mm_s = PFE_ECU_DEFAULT_SET_SPEED_MM_S;
}

int hal_ecu_loop_init(hal_ecu_loop_t *loop, pfe_ecu_t *ecu, const pfe_ecu_config_t *cfg,
                      hal_can_t *can, hal_nvm_t *nvm, uint64_t now_us)
{
    (void)memset(loop, 0, sizeof *loop);
    loop->ecu = ecu;
    loop->can = can;
    loop->nvm = nvm;
    uint8_t s0[PFE_NVM_RECORD_SIZE];
    uint8_t s1[PFE_NVM_RECORD_SIZE];
    const bool ok0 = hal_nvm_read(nvm, 0U, s0) == 0;
    const bool ok1 = hal_nvm_read(nvm, 1U, s1) == 0;
    loop->restored_slot = pfe_nvm_pick(ok0 ? s0 : NULL, ok1 ? s1 : NULL, &loop->restored);
    /* A backend without filter slots for all of them gets none (it then
     * passes everything, and the ECU sorts). */
    for (uint32_t k = 0U; k < PFE_ECU_RX_FILTERS; k++) {
        if (hal_can_add_filter(can, pfe_ecu_rx_filters[k].id, pfe_ecu_rx_filters[k].mask) >= 0) {
            loop->filters++;
        }
    }
    if (loop->filters != PFE_ECU_RX_FILTERS) {
        for (int k = 0; k < (int)HAL_CAN_MAX_FILTERS; k++) {
            (void)hal_can_remove_filter(can, k);
        }
        loop->filters = 0U;
    }
    hal_can_get_stats(can, &loop->last);
    return pfe_ecu_init(ecu, cfg, &loop->restored, loop->restored_slot, now_us);
}

uint32_t hal_ecu_loop_step(hal_ecu_loop_t *loop, uint64_t now_us)
{
    pfe_ecu_t *ecu = loop->ecu;
    /* A frame received after this deadline belongs to a later pass. */
    bool more = true;
    for (uint32_t k = 0U; more && (k < HAL_ECU_LOOP_RX_MAX); k++) {
        if (!loop->have_held) {
            loop->have_held = hal_can_receive(loop->can, &loop->held) == 0;
        }
        more = loop->have_held && (loop->held.timestamp_us <= now_us);
        if (more) {
            loop->have_held = false;
            pfe_ecu_receive(ecu, &loop->held.frame, now_us);
        }
    }
    hal_can_stats_t st;
    hal_can_get_stats(loop->can, &st);
    if (st.rx_dropped != loop->last.rx_dropped) {
        pfe_ecu_note_rx_dropped(ecu, st.rx_dropped - loop->last.rx_dropped);
    }
    loop->last = st;
    pfe_can_frame_t tx[PFE_ECU_TX_MAX];
    const uint32_t n = pfe_ecu_tick(ecu, now_us, tx, PFE_ECU_TX_MAX);
    uint32_t sent = 0U;
    for (uint32_t k = 0U; k < n; k++) {
        if (hal_can_send(loop->can, &tx[k]) == 0) {
            sent++;
        } else {
            pfe_ecu_note_tx_dropped(ecu, 1U);
        }
    }
    if (pfe_ecu_nvm_due(ecu) && (hal_ecu_loop_save(loop) != 0) &&
        (loop->nvm_failures < UINT32_MAX)) {
        loop->nvm_failures++;
    }
    return sent;
}

hal_ecu_pace_t hal_ecu_loop_pace(hal_ecu_loop_t *loop, uint64_t *deadline_us, uint64_t now_us)
{
    const uint64_t next = *deadline_us + PFE_ECU_TICK_US;
    *deadline_us = next;
    hal_ecu_pace_t pace = HAL_ECU_PACE_ON_TIME;
    if (now_us > next) {
        pace = HAL_ECU_PACE_CATCH_UP;
        const uint64_t behind = (now_us - next) / PFE_ECU_TICK_US; /* whole ticks missed */
        if (behind > HAL_ECU_LOOP_CATCH_UP_TICKS) {
            const uint32_t lost = (behind > UINT32_MAX) ? UINT32_MAX : (uint32_t)behind;
            pfe_ecu_note_overrun(loop->ecu, lost);
            loop->skipped_ticks = ((UINT32_MAX - loop->skipped_ticks) < lost) ? UINT32_MAX
                                                                               : (loop->skipped_ticks + lost);
            *deadline_us = next + (behind * PFE_ECU_TICK_US);
            pace = HAL_ECU_PACE_SKIPPED;
        } else if (behind > 0U) {
            pfe_ecu_note_overrun(loop->ecu, 1U);
        } else {
            /* less than a tick late: run the next pass now, nothing counted */
        }
    }
    return pace;
}

int hal_ecu_loop_save(hal_ecu_loop_t *loop)
{
    pfe_nvm_state_t rec;
    uint8_t bytes[PFE_NVM_RECORD_SIZE];
    const uint32_t slot = pfe_ecu_nvm_slot(loop->ecu);
    pfe_ecu_nvm_take(loop->ecu, &rec);
    pfe_nvm_encode(&rec, bytes);
    const int r = hal_nvm_write(loop->nvm, slot, bytes);
    pfe_ecu_nvm_written(loop->ecu, r);
    return r;
}
