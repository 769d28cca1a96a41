/* pfe_accel.c - alpha-beta speed filter (contract in pfe_accel.h). */
#include "pfe_accel.h"

#include <stddef.h>

#include "pfe_calib.h"
#include "pfe_fixed.h"
#include "pfe_vehicle.h"

void pfe_accel_reset(pfe_accel_filter_t *f)
{
    f->speed_um_s = 0;
    f->accel_um_s2 = 0;
    f->samples = 0U;
}

/* Division rounded to nearest, halves away from zero; den > 0. 32-bit on
 * purpose: the Cortex-M4 divides 32-bit values in one instruction. */
static int32_t div_round(int32_t num, int32_t den)
{
    return (num >= 0) ? ((num + (den / 2)) / den) : -((-num + (den / 2)) / den);
}

void pfe_accel_update(pfe_accel_filter_t *f, int32_t speed_mm_s, uint32_t periods)
{
    const int32_t z = pfe_clamp_i32(speed_mm_s, 0, PFE_SPEED_MAX_MM_S) * 1000;
    if (f->samples == 0U) {
        f->speed_um_s = z;
        f->accel_um_s2 = 0;
        f->samples = 1U;
        return;
    }
    const int32_t k = (periods < 1U) ? 1 : ((periods > 10U) ? 10 : (int32_t)periods);
    /* v' = v + a k T with T = 1/10 s. |a| <= 2^24.3 and k <= 10 keep a k
     * below 2^28; v, z <= 7e7 keep r below 2^28.2 and 3 r below 2^30. The
     * new speed, below 7e7 + 2.1e7 + 4.8e7 < 2^28, and the new
     * acceleration, below 2.1e7 + 8e7 < 2^27, fit 32 bits before their
     * clamps. */
    const int32_t predicted = f->speed_um_s + div_round(f->accel_um_s2 * k, 10);
    const int32_t r = z - predicted;
    const int32_t v = predicted + div_round(r * 3, 10);
    /* beta / (k T) = (1/20) / (k / 10) = 1 / (2 k) */
    const int32_t a = f->accel_um_s2 + div_round(r, 2 * k);
    f->speed_um_s = pfe_clamp_i32(v, 0, PFE_SPEED_MAX_MM_S * 1000);
    f->accel_um_s2 = pfe_clamp_i32(a, -PFE_ACCEL_MAX_UM_S2, PFE_ACCEL_MAX_UM_S2);
    if (f->samples < UINT32_MAX) {
        f->samples++;
    }
}
