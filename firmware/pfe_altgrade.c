/* pfe_altgrade.c - road grade from altitude over distance (contract in pfe_altgrade.h). */
#include "pfe_altgrade.h"

#include <stddef.h>
#include <string.h>

#include "pfe_calib.h"
#include "pfe_fixed.h"

void pfe_altgrade_init(pfe_altgrade_t *ag)
{
    (void)memset(ag, 0, sizeof *ag);
}

void pfe_altgrade_reset(pfe_altgrade_t *ag)
{
    pfe_altgrade_init(ag);
}

static void push_node(pfe_altgrade_t *ag, uint64_t x_mm, int32_t alt_mm)
{
    ag->head = (ag->head + 1U) % PFE_ALTGRADE_NODES;
    ag->node_x_mm[ag->head] = x_mm;
    ag->node_alt_mm[ag->head] = alt_mm;
    if (ag->n_nodes < PFE_ALTGRADE_NODES) {
        ag->n_nodes++;
    }
}

/* Newest node at least PFE_ALTGRADE_BASE_MM behind the newest one. */
static void update_grade(pfe_altgrade_t *ag)
{
    ag->valid = false;
    ag->grade_ppm = 0;
    const uint64_t x_now = ag->node_x_mm[ag->head];
    const int32_t alt_now = ag->node_alt_mm[ag->head];
    for (uint32_t k = 1U; k < ag->n_nodes; k++) {
        const uint32_t i = (ag->head + PFE_ALTGRADE_NODES - k) % PFE_ALTGRADE_NODES;
        const uint64_t run_mm = x_now - ag->node_x_mm[i];
        if (run_mm >= PFE_ALTGRADE_BASE_MM) {
            /* rise < 2^24 mm, run < 2^40 mm: rise * 1e6 fits in 64 bits */
            const int64_t rise_mm = (int64_t)alt_now - (int64_t)ag->node_alt_mm[i];
            const int64_t ppm = (rise_mm * 1000000) / (int64_t)run_mm;
            ag->grade_ppm = (int32_t)pfe_clamp_i64(ppm, -PFE_GRADE_MAX_PPM, PFE_GRADE_MAX_PPM);
            ag->valid = true;
            return;
        }
    }
}

void pfe_altgrade_sample(pfe_altgrade_t *ag, uint64_t x_mm, int32_t altitude_mm)
{
    const int64_t alt_q8 = (int64_t)altitude_mm * 256;
    if (ag->started && ((x_mm < ag->last_x_mm) || ((x_mm - ag->last_x_mm) > PFE_ALTGRADE_GAP_MM))) {
        pfe_altgrade_init(ag); /* a gap (or an odometer that went back): start again */
    }
    if (!ag->started) {
        ag->started = true;
        ag->last_x_mm = x_mm;
        ag->filtered_q8_mm = alt_q8;
        push_node(ag, x_mm, altitude_mm);
        return;
    }
    const uint64_t dx_mm = x_mm - ag->last_x_mm; /* <= PFE_ALTGRADE_GAP_MM */
    ag->last_x_mm = x_mm;
    /* filtered += (alt - filtered) * min(1, dx / L); |alt - filtered| < 2^33 q8, dx < 2^16 */
    const int64_t diff_q8 = alt_q8 - ag->filtered_q8_mm;
    if (dx_mm >= PFE_ALTGRADE_FILTER_MM) {
        ag->filtered_q8_mm = alt_q8;
    } else {
        ag->filtered_q8_mm += (diff_q8 * (int64_t)dx_mm) / (int64_t)PFE_ALTGRADE_FILTER_MM;
    }
    if ((x_mm - ag->node_x_mm[ag->head]) >= PFE_ALTGRADE_STEP_MM) {
        push_node(ag, x_mm, (int32_t)(ag->filtered_q8_mm / 256));
        update_grade(ag);
    }
}

bool pfe_altgrade_grade(const pfe_altgrade_t *ag, int32_t *grade_ppm)
{
    *grade_ppm = ag->valid ? ag->grade_ppm : 0;
    return ag->valid;
}
