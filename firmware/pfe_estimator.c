/* pfe_estimator.c - the 10 ms fuel estimator (contract in pfe_estimator.h). */
#include "pfe_estimator.h"

#include <stddef.h>

#include "pfe_fixed.h"

#define TEN_PL_PER_UL 100000U

int pfe_estimator_init(pfe_estimator_t *est, const pfe_platoon_t *platoon)
{
    if ((est == NULL) || (platoon == NULL)) {
        return PFE_EINVAL;
    }
    est->platoon = platoon;
    pfe_accel_reset(&est->filter);
    est->ticks_since_sample = 0U;
    est->trig_grade_ppm = 0;
    pfe_grade_accel(0, platoon->gravity_um_s2, &est->trig);
    est->object_along_um_s2 = 0;
    est->fuel_used_10pl = 0U;
    for (uint32_t i = 0U; i < PFE_MAX_VEHICLES; i++) {
        est->pos_fuel_used_10pl[i] = 0U;
        est->out.pos_fuel_rate_nl_s[i] = 0U;
    }
    est->out.flags = PFE_EST_SPEED_MISSING | PFE_EST_GRADE_MISSING;
    est->out.speed_mm_s = 0;
    est->out.accel_um_s2 = 0;
    est->out.grade_ppm = 0;
    est->out.wheel_force_n = 0;
    est->out.fuel_rate_nl_s = 0U;
    return PFE_OK;
}

static void clear_rates(pfe_estimator_t *est)
{
    est->out.wheel_force_n = 0;
    est->out.fuel_rate_nl_s = 0U;
    for (uint32_t i = 0U; i < PFE_MAX_VEHICLES; i++) {
        est->out.pos_fuel_rate_nl_s[i] = 0U;
    }
}

/* Feeds the speed filter; returns the flags it raises. */
static uint32_t track_speed(pfe_estimator_t *est, const pfe_est_input_t *in)
{
    uint32_t flags = 0U;
    if ((in->speed_mm_s < 0) || (in->speed_mm_s > PFE_SPEED_MAX_MM_S)) {
        flags |= PFE_EST_SPEED_CLAMPED;
    }
    if (est->ticks_since_sample < UINT32_MAX) {
        est->ticks_since_sample++;
    }
    if (in->speed_fresh) {
        const uint32_t periods = (est->ticks_since_sample + (PFE_EST_TICKS_PER_SPEED_PERIOD / 2U)) /
                                 PFE_EST_TICKS_PER_SPEED_PERIOD;
        if (periods > PFE_EST_STALE_PERIODS) {
            pfe_accel_reset(&est->filter); /* too long a gap to predict across */
        }
        pfe_accel_update(&est->filter, in->speed_mm_s, periods);
        est->ticks_since_sample = 0U;
    } else if (est->ticks_since_sample > (PFE_EST_STALE_PERIODS * PFE_EST_TICKS_PER_SPEED_PERIOD)) {
        flags |= PFE_EST_SPEED_MISSING;
    } else {
        /* held between samples */
    }
    return flags;
}

/* total + rate saturated at UINT64_MAX, PFE_EST_SATURATED raised when the
 * sum reaches it (total + rate >= UINT64_MAX). Below 2^64 - 2^32 a total
 * plus a rate (< 2^32) stays below UINT64_MAX: the high word alone rules
 * that out on every step but the last few before saturation. */
static uint64_t accumulate(uint64_t total, uint32_t rate, uint32_t *flags)
{
    uint64_t sum = total + rate;
    if (((total >> 32) == 0xFFFFFFFFU) && (total >= (UINT64_MAX - rate))) {
        *flags |= PFE_EST_SATURATED;
        sum = UINT64_MAX;
    }
    return sum;
}

PFE_FLATTEN const pfe_est_output_t *pfe_estimator_step(pfe_estimator_t *est, const pfe_est_input_t *in)
{
    uint32_t flags = 0U;
    if ((in == NULL) || !in->speed_valid) {
        flags |= PFE_EST_SPEED_MISSING;
    }
    if ((in == NULL) || !in->grade_valid) {
        flags |= PFE_EST_GRADE_MISSING;
    }
    if ((flags & PFE_EST_SPEED_MISSING) != 0U) {
        pfe_accel_reset(&est->filter);
        est->ticks_since_sample = 0U;
    } else {
        flags |= track_speed(est, in);
    }
    if ((flags & PFE_EST_SPEED_MISSING) == 0U) {
        /* the filter keeps its speed within 0 .. PFE_SPEED_MAX_MM_S * 1000:
         * an unsigned division */
        const uint32_t speed_um_s = (uint32_t)est->filter.speed_um_s;
        const uint32_t speed_mm_s = (speed_um_s + 500U) / 1000U;
        est->out.speed_mm_s = (int32_t)speed_mm_s;
        est->out.accel_um_s2 = est->filter.accel_um_s2;
        if (est->filter.samples < PFE_EST_WARMUP_SAMPLES) {
            flags |= PFE_EST_WARMING_UP;
        }
    }
    if ((flags & PFE_EST_GRADE_MISSING) == 0U) {
        if ((in->grade_ppm < -PFE_GRADE_MAX_PPM) || (in->grade_ppm > PFE_GRADE_MAX_PPM)) {
            flags |= PFE_EST_GRADE_CLAMPED;
        }
        est->out.grade_ppm = pfe_clamp_i32(in->grade_ppm, -PFE_GRADE_MAX_PPM, PFE_GRADE_MAX_PPM);
    }
    if ((flags & (PFE_EST_SPEED_MISSING | PFE_EST_GRADE_MISSING | PFE_EST_WARMING_UP)) != 0U) {
        clear_rates(est);
        est->out.flags = flags;
        return &est->out;
    }

    const pfe_platoon_t *pl = est->platoon;
    const int32_t v = est->out.speed_mm_s;
    const int32_t a = est->out.accel_um_s2;
    const int32_t grade = est->out.grade_ppm;
    if (grade != est->trig_grade_ppm) { /* SSI repeats its value often: reuse */
        pfe_grade_accel(grade, pl->gravity_um_s2, &est->trig);
        pfe_grade_accel_t small;
        pfe_platoon_grade_accel(pl, grade, &small);
        est->object_along_um_s2 = small.along_um_s2;
        est->trig_grade_ppm = grade;
    }

    /* v <= PFE_SPEED_MAX_MM_S and a within +-PFE_ACCEL_MAX_UM_S2, as the
     * filter keeps them: what the inline forces below require. */
    const uint64_t v2 = (uint64_t)(uint32_t)v * (uint32_t)v;
    const int32_t force = pfe_platoon_fuel_force_n(pl, v2, a, est->object_along_um_s2);
    est->out.wheel_force_n = force;
    const uint32_t object_rate = pfe_fuel_rate_nl_s(force, v, pl->object.power_aux_w, pl->object.fuel_q20);
    est->out.fuel_rate_nl_s = object_rate;
    est->fuel_used_10pl = accumulate(est->fuel_used_10pl, object_rate, &flags);

    /* Each position: what differs is its coefficients; v^2, a and the
     * grade split are shared, and a position with the coefficients of the
     * one before it (pfe_platoon_t.same_as_previous) has its fuel rate. */
    /* In locals: the stores below could otherwise alias them. */
    const pfe_grade_accel_t trig = est->trig;
    const uint32_t n = pl->n_vehicles;
    uint32_t twins = pl->same_as_previous;
    uint32_t rate = 0U;
    for (uint32_t i = 0U; i < n; i++) {
        if ((twins & 1U) == 0U) {
            const pfe_vehicle_t *veh = &pl->position[i];
            const int32_t f = pfe_vehicle_truck_fuel_force_n(veh, v2, a, &trig);
            rate = pfe_fuel_rate_nl_s(f, v, veh->power_aux_w, veh->fuel_q20);
            if (rate == UINT32_MAX) {
                flags |= PFE_EST_SATURATED;
            }
        }
        twins >>= 1;
        est->out.pos_fuel_rate_nl_s[i] = rate;
        est->pos_fuel_used_10pl[i] = accumulate(est->pos_fuel_used_10pl[i], rate, &flags);
    }
    if (object_rate == UINT32_MAX) {
        flags |= PFE_EST_SATURATED;
    }
    est->out.flags = flags | PFE_EST_VALID;
    return &est->out;
}

/* 10 pL to uL, rounded down. 100000 is above the divisor of the cheap 32-bit
 * path of pfe_udiv_u64(), so it divides by 1000 and then by 100 (the same
 * result as one division: floor(floor(n / a) / b) = floor(n / (a b))). */
static uint64_t ul_of_10pl(uint64_t fuel_10pl)
{
    return pfe_udiv_u64(pfe_udiv_u64(fuel_10pl, 1000U, NULL), TEN_PL_PER_UL / 1000U, NULL);
}

uint64_t pfe_estimator_fuel_used_ul(const pfe_estimator_t *est, int32_t position)
{
    if (position == PFE_EST_PLATOON) {
        return ul_of_10pl(est->fuel_used_10pl);
    }
    if ((position < 0) || ((uint32_t)position >= est->platoon->n_vehicles)) {
        return 0U;
    }
    return ul_of_10pl(est->pos_fuel_used_10pl[position]);
}

int pfe_estimator_set_fuel_used_ul(pfe_estimator_t *est, int32_t position, uint64_t fuel_ul)
{
    const uint64_t value = (fuel_ul > (UINT64_MAX / TEN_PL_PER_UL)) ? UINT64_MAX
                                                                     : (fuel_ul * TEN_PL_PER_UL);
    if (position == PFE_EST_PLATOON) {
        est->fuel_used_10pl = value;
        return PFE_OK;
    }
    if ((position < 0) || ((uint32_t)position >= est->platoon->n_vehicles)) {
        return PFE_EINVAL;
    }
    est->pos_fuel_used_10pl[position] = value;
    return PFE_OK;
}
