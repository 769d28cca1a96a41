/*
 * hal_can_mem.h - the parts of hal_can.h's contract that every in-memory
 * backend (hal/fake, hal/replay) implements the same way: which frames can
 * exist, and which frames a handle's filters accept.
 */
#ifndef HAL_CAN_MEM_H
#define HAL_CAN_MEM_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_can.h"

/* A frame hal_can_send() may take: dlc 0..8; a 29-bit id with
 * PFE_CAN_EFF_FLAG and no other flag bit, or an 11-bit id. */
static inline bool hal_can_mem_frame_valid(const pfe_can_frame_t *f)
{
    if (f->dlc > PFE_CAN_MAX_DLC) {
        return false;
    }
    if ((f->id & PFE_CAN_EFF_FLAG) != 0U) {
        return (f->id & ~(PFE_CAN_EFF_FLAG | PFE_CAN_ID_MASK)) == 0U;
    }
    return f->id <= 0x7FFU;
}

/* hal_can_add_filter()'s rule over n filter slots: (id & mask) == (filter
 * id & mask) for one used slot, or no slot used at all. */
static inline bool hal_can_mem_accepts(const bool *used, const uint32_t *filter_id,
                                       const uint32_t *filter_mask, uint32_t n, uint32_t id)
{
    bool any = false;
    for (uint32_t k = 0U; k < n; k++) {
        if (used[k]) {
            any = true;
            if ((id & filter_mask[k]) == (filter_id[k] & filter_mask[k])) {
                return true;
            }
        }
    }
    return !any;
}

#endif /* HAL_CAN_MEM_H */
