/*
 * pfe_predict.c - fuel and time over the road ahead (contract in pfe_predict.h).
 *
 * The bounds (thesis 5.1, eq. 5.1 to 5.10, restated in docs/model.md):
 *
 *   fuel_lower = [sum over the steps of the SLOW run with Fw > 0 of
 *                 (Fa_lower(v_min) + Fr + M g alpha_s) ds] / (eta_max rho_d)
 *                + aux / (eta_max rho_d) + dKE / (eta_max rho_d)
 *   fuel_upper = [sum over the steps of the FAST run with Fw > 0 of
 *                 (Fa_upper(v_max) + Fr + M g alpha_l) ds] / (eta_min rho_d)
 *                + aux / (eta_min rho_d) + dKE / (eta_min rho_d)
 *   (each at least 0, and never across the prediction, see publish())
 *
 *   - speed trajectories (5.5, 5.7): v_min is the SLOW run, the object model
 *     with every truck given the largest drag area and no drag reduction;
 *     v_max the FAST run, the smallest drag area with the reduction at half
 *     the gap; "Fw > 0" is the run's own controller output;
 *   - air drag (5.5): the lower bound takes cw Af_min sum (1 - phi_i(d / 2))
 *     at v_min, the upper bound cw Af_max N at v_max;
 *   - rolling M g cr (5.7) over the same steps;
 *   - grade (5.10): alpha_l and alpha_s are the largest and smallest preview
 *     samples within (N - 1) * gap ahead of and behind the platoon's
 *     position (the object model's point mass is its centre), taken per
 *     sample: the window around any point of sample k lies within samples
 *     k - w .. k + w, w = ceil((N - 1) * gap / spacing);
 *   - auxiliary power is not bounded (the thesis: the same in both models):
 *     the nominal run's auxiliary energy, with each bound's efficiency;
 *   - the acceleration work (5.2) is the nominal run's change of kinetic
 *     energy, dKE = m (v_end^2 - v_start^2) / 2, in both bounds. The thesis
 *     (5.3) sets it to zero because its routes start and end at the set
 *     speed, where this is zero too; a horizon that ends in a climb ends
 *     slower, and the energy the platoon gives back would otherwise push
 *     the prediction below the lower bound. The nominal fuel counts this
 *     work with the rotating parts, (M + Mj) a (eq. 3.7), so m is M or
 *     M + Mj, whichever keeps the bound a bound: the lower bound takes the
 *     smaller term (M when the platoon gains speed, M + Mj when it loses
 *     it), the upper bound the larger.
 * The step work is summed by pfe_sim itself (pfe_sim_sums_t), in N * 2^2
 * and nL as its own fuel.
 */
#include "pfe_predict.h"

#include <stddef.h>
#include <string.h>

#include "pfe_fixed.h"

void pfe_predict_init(pfe_predict_t *p)
{
    (void)memset(p, 0, sizeof *p);
    p->phase = PFE_PREDICT_IDLE;
}

void pfe_predict_cancel(pfe_predict_t *p)
{
    p->phase = PFE_PREDICT_IDLE;
    p->sim_ready = false;
}

const pfe_predict_result_t *pfe_predict_result(const pfe_predict_t *p)
{
    return &p->result;
}

static void abandon(pfe_predict_t *p, int why)
{
    p->phase = PFE_PREDICT_IDLE;
    p->sim_ready = false;
    p->last_error = why;
    p->result.valid = false;
}

static void loading_begin(pfe_predict_t *p);

/* cw Af 1/2 rho of position i without its drag reduction: air_q32 /
 * (1 - phi_i). A reduction of 100 % (not in any real table) keeps air_q32. */
static int64_t air_unreduced_q32(const pfe_vehicle_t *v)
{
    const uint32_t keep_bp = (v->reduction_bp < 10000U) ? (10000U - v->reduction_bp) : 10000U;
    return (int64_t)pfe_udiv_round_u64((uint64_t)v->air_q32 * 10000U, keep_bp);
}

int pfe_predict_start(pfe_predict_t *p, const pfe_preview_t *pv, uint32_t preview_serial,
                      uint32_t travelled_mm,
                      const pfe_platoon_t *platoon, const pfe_drag_table_t *drag,
                      const pfe_cruise_calib_t *cruise, int32_t set_speed_mm_s,
                      int32_t start_speed_mm_s)
{
    if ((p == NULL) || (pv == NULL) || (platoon == NULL) || (drag == NULL) || (cruise == NULL) ||
        (platoon->n_vehicles == 0U) || (platoon->n_vehicles > PFE_MAX_VEHICLES) ||
        (pfe_calib_check_cruise(cruise) != PFE_OK) || (set_speed_mm_s < PFE_SIM_STALL_MM_S) ||
        (set_speed_mm_s > PFE_SPEED_MAX_MM_S)) {
        if (p != NULL) {
            abandon(p, PFE_EINVAL);
        }
        return PFE_EINVAL;
    }
    if ((pv->phase != PFE_PREVIEW_READY) || (pv->unusable_samples != 0U) || (pv->spacing_m == 0U) ||
        (pv->sample_count == 0U)) {
        abandon(p, PFE_PREDICT_ENOPREVIEW);
        return PFE_PREDICT_ENOPREVIEW;
    }
    const uint32_t spacing_mm = (uint32_t)pv->spacing_m * 1000U;
    const uint32_t first = travelled_mm / spacing_mm;
    if (first >= pv->sample_count) {
        abandon(p, PFE_PREDICT_EPASSED);
        return PFE_PREDICT_EPASSED;
    }
    p->platoon = platoon;
    p->cruise = *cruise;
    p->set_speed_mm_s = set_speed_mm_s;
    /* The simulation needs a moving platoon: a start below its stall speed
     * starts at the stall speed (the prediction then slightly short in time). */
    p->start_speed_mm_s = pfe_clamp_i32(start_speed_mm_s, PFE_SIM_STALL_MM_S, PFE_SPEED_MAX_MM_S);
    p->first_sample = first;
    p->road.grade_ppm = &p->grade_ppm[first];
    p->road.n_samples = (uint32_t)pv->sample_count - first;
    p->road.spacing_mm = spacing_mm;
    p->sim_ready = false;
    p->lower_nl = 0;
    /* Bound platoons' air drag and efficiencies from the nominal one. */
    const uint32_t n = platoon->n_vehicles;
    int64_t air_max = 0;
    int64_t air_min = INT64_MAX;
    int64_t fq_max = 0;
    int64_t fq_min = INT64_MAX;
    int64_t mass_min_q32 = INT64_MAX;
    uint64_t keep_sum_bp = 0U;
    for (uint32_t i = 0U; i < n; i++) {
        const pfe_vehicle_t *v = &platoon->position[i];
        mass_min_q32 = (v->mass_q32 < mass_min_q32) ? v->mass_q32 : mass_min_q32;
        const int64_t a = air_unreduced_q32(v);
        air_max = (a > air_max) ? a : air_max;
        air_min = (a < air_min) ? a : air_min;
        fq_max = (v->fuel_q20 > fq_max) ? v->fuel_q20 : fq_max;
        fq_min = (v->fuel_q20 < fq_min) ? v->fuel_q20 : fq_min;
        keep_sum_bp += 10000U - pfe_drag_reduction_bp(drag, i, n, platoon->gap_mm / 2U);
    }
    /* air < 2^22 (pfe_sim.c), times N <= 32 or times keep_sum <= 32e4: below 2^41. */
    p->air_slow_q32 = air_max * (int64_t)n;
    p->air_fast_q32 = (int64_t)pfe_udiv_round_u64((uint64_t)air_min * keep_sum_bp, 10000U);
    /* Every truck of the slow platoon has the drag air_max; the lightest has
     * the most per kg. air_max < 2^17 per truck times M < 2^35 (as
     * mass_q32): below 2^52; mass_min_q32 > 0 (a checked calibration). */
    const int64_t most = (int64_t)pfe_udiv_round_u64(
        (uint64_t)air_max * (uint64_t)platoon->object.mass_q32, (uint64_t)mass_min_q32);
    const int64_t c = (most > p->air_slow_q32) ? (most - p->air_slow_q32) : 0;
    p->formation_slow_q32 = (uint32_t)((c < (int64_t)PFE_FORMATION_AIR_MAX_Q32) ? c
                                                                               : (int64_t)PFE_FORMATION_AIR_MAX_Q32);
    p->fuel_upper_q20 = fq_max;
    p->fuel_lower_q20 = fq_min;
    const uint32_t followers = n - 1U;
    const uint64_t window_mm = (uint64_t)followers * platoon->gap_mm;
    const uint64_t w = (window_mm + spacing_mm - 1U) / spacing_mm;
    p->window_samples = (w > PFE_PREVIEW_MAX_SAMPLES) ? PFE_PREVIEW_MAX_SAMPLES : (uint32_t)w;
    if (!p->prepared || (p->prepared_serial != preview_serial) ||
        (p->n_samples != (uint32_t)pv->sample_count) || (p->spacing_mm != spacing_mm) ||
        (p->prepared_window != p->window_samples)) {
        /* A new preview, or another platoon length (5.10): copied anew
         * with the first pass of the windows. */
        p->prepared = false;
        p->prepared_serial = preview_serial;
        p->prepared_window = p->window_samples;
        p->n_samples = pv->sample_count;
        p->spacing_mm = spacing_mm;
        loading_begin(p);
    } else {
        p->phase = PFE_PREDICT_NOMINAL;
    }
    return PFE_OK;
}

/* Sets up the run of the current phase: the nominal platoon, or a bound
 * platoon with its work summed by the simulation. */
static int start_run(pfe_predict_t *p)
{
    const pfe_platoon_t *pl = p->platoon;
    const bool bound = p->phase != PFE_PREDICT_NOMINAL;
    const bool upper = p->phase == PFE_PREDICT_FAST;
    if (bound) {
        p->bound = *p->platoon;
        p->bound.object.air_q32 = upper ? p->air_fast_q32 : p->air_slow_q32;
        p->bound.formation_air_q32 = upper ? 0U : p->formation_slow_q32;
        pl = &p->bound;
    }
    const uint32_t step = (p->road.spacing_mm < PFE_PREDICT_STEP_MAX_MM) ? p->road.spacing_mm
                                                                          : PFE_PREDICT_STEP_MAX_MM;
    const int rc = pfe_sim_init(&p->sim, pl, &p->cruise, &p->road, p->set_speed_mm_s,
                                p->start_speed_mm_s,
                                (step < PFE_SIM_STEP_MIN_MM) ? PFE_SIM_STEP_MIN_MM : step);
    (void)memset(&p->sums, 0, sizeof p->sums);
    if (bound) {
        /* The upper bound's drag is the slow platoon's, at the fast run's
         * speed; the lower bound's the fast platoon's at the slow run's. */
        p->sums.bound_grade_20ppm = upper ? &p->window_high_20ppm[p->first_sample]
                                          : &p->window_low_20ppm[p->first_sample];
        p->sums.bound_air_q32 = upper ? p->air_slow_q32 : p->air_fast_q32;
        p->sums.bound_fuel_q20 = upper ? p->fuel_upper_q20 : p->fuel_lower_q20;
    }
    p->sim_ready = rc == PFE_OK;
    return rc;
}

/* Window extremes, both at once and in O(1) per sample for any window
 * (van Herk / Gil-Werman). With m = 2 w + 1, sample i at position
 * u = i + w of a preview padded by w neutral samples on either side, and
 * the positions cut into blocks of m, the window of sample k is
 * u = k .. k + m - 1: the tail of one block and the head of the next (or
 * one whole block). Its extreme is that of the prefix extreme P[k + m - 1]
 * within the second block and the suffix extreme S[k] within the first.
 * LOADING computes P while it copies the samples and writes P[k + m - 1]
 * to the outputs; WINDOWS computes S from the last position down and folds
 * it in. Preview grades are multiples of 20 ppm within +-PFE_GRADE_MAX_PPM:
 * the division is exact, every extreme fits int16_t, and the neutral values
 * lie beyond every grade (each window holds its own sample: no output is
 * neutral). */
#define WIN_NEUTRAL_HIGH (-32768)
#define WIN_NEUTRAL_LOW 32767

/* Sets up the first pass at position w (sample 0); LOADING. */
static void loading_begin(pfe_predict_t *p)
{
    const uint32_t m = (2U * p->window_samples) + 1U;
    p->n_done = 0U;
    p->win_low = WIN_NEUTRAL_LOW;
    p->win_high = WIN_NEUTRAL_HIGH;
    p->win_block_left = m - (p->window_samples % m); /* positions w .. m - 1 */
    p->phase = PFE_PREDICT_LOADING;
}

/* First pass over the copied samples i0 .. i1 - 1: clamps them in place and
 * writes P[u] to output u - 2 w (sample i - w). Past the last sample, the
 * padding's positions n + w .. n + 2 w - 1 complete the outputs. The loops
 * run a block's stretch at a time (win_block_left positions to its end). */
static void window_prefix(pfe_predict_t *p, uint32_t i0, uint32_t i1)
{
    int32_t *grade = p->grade_ppm;
    int16_t *out_low = p->window_low_20ppm;
    int16_t *out_high = p->window_high_20ppm;
    const uint32_t n = p->n_samples;
    const uint32_t w = p->window_samples;
    const uint32_t m = (2U * w) + 1U;
    int32_t low = p->win_low;
    int32_t high = p->win_high;
    uint32_t left = p->win_block_left;
    uint32_t i = i0;
    while (i < i1) {
        const uint32_t end = ((i1 - i) < left) ? i1 : (i + left);
        left -= end - i;
        /* samples before w: positions before the first window's end */
        const uint32_t quiet_end = (end < w) ? end : w;
        for (; i < quiet_end; i++) {
            const int32_t g = pfe_clamp_i32(grade[i], -PFE_GRADE_MAX_PPM, PFE_GRADE_MAX_PPM);
            grade[i] = g;
            low = ((g / 20) < low) ? (g / 20) : low;
            high = ((g / 20) > high) ? (g / 20) : high;
        }
        for (; i < end; i++) {
            const int32_t g = pfe_clamp_i32(grade[i], -PFE_GRADE_MAX_PPM, PFE_GRADE_MAX_PPM);
            grade[i] = g;
            low = ((g / 20) < low) ? (g / 20) : low;
            high = ((g / 20) > high) ? (g / 20) : high;
            out_low[i - w] = (int16_t)low;
            out_high[i - w] = (int16_t)high;
        }
        if (left == 0U) {
            low = WIN_NEUTRAL_LOW;
            high = WIN_NEUTRAL_HIGH;
            left = m;
        }
    }
    if (i1 == n) {
        for (uint32_t u = n + w; u < (n + (2U * w)); u++) {
            if (u >= (2U * w)) {
                out_low[u - (2U * w)] = (int16_t)low;
                out_high[u - (2U * w)] = (int16_t)high;
            }
            left--;
            if (left == 0U) {
                low = WIN_NEUTRAL_LOW;
                high = WIN_NEUTRAL_HIGH;
                left = m;
            }
        }
        /* the second pass starts at the last sample's position */
        low = WIN_NEUTRAL_LOW;
        high = WIN_NEUTRAL_HIGH;
        p->win_pos = n + w;
        left = ((n - 1U + w) % m) + 1U;
    }
    p->win_block_left = left;
    p->win_low = low;
    p->win_high = high;
}

/* Second pass: up to count positions, from win_pos - 1 down; folds S[u]
 * into output u. Returns the positions done. */
static uint32_t window_suffix(pfe_predict_t *p, uint32_t count)
{
    const int32_t *grade = p->grade_ppm;
    int16_t *out_low = p->window_low_20ppm;
    int16_t *out_high = p->window_high_20ppm;
    const uint32_t n = p->n_samples;
    const uint32_t w = p->window_samples;
    const uint32_t m = (2U * w) + 1U;
    int32_t low = p->win_low;
    int32_t high = p->win_high;
    uint32_t left = p->win_block_left;
    uint32_t u = p->win_pos;
    const uint32_t stop = (u > count) ? (u - count) : 0U;
    /* positions of samples: u - 1 >= w */
    const uint32_t sample_stop = (stop > w) ? stop : w;
    while (u > sample_stop) {
        const uint32_t end = ((u - sample_stop) < left) ? sample_stop : (u - left);
        left -= u - end;
        /* positions past the last output */
        const uint32_t quiet_end = (end > n) ? end : n;
        for (; u > quiet_end; u--) {
            const int32_t g20 = grade[u - 1U - w] / 20;
            low = (g20 < low) ? g20 : low;
            high = (g20 > high) ? g20 : high;
        }
        for (; u > end; u--) {
            const int32_t g20 = grade[u - 1U - w] / 20;
            low = (g20 < low) ? g20 : low;
            high = (g20 > high) ? g20 : high;
            out_low[u - 1U] = (low < out_low[u - 1U]) ? (int16_t)low : out_low[u - 1U];
            out_high[u - 1U] = (high > out_high[u - 1U]) ? (int16_t)high : out_high[u - 1U];
        }
        if (left == 0U) {
            low = WIN_NEUTRAL_LOW;
            high = WIN_NEUTRAL_HIGH;
            left = m;
        }
    }
    if (u <= w) {
        /* Positions below w: padding, within block 0 (0 .. 2 w) with sample
         * 0: S stays that of position w. Those of no sample are skipped. */
        const uint32_t top = (u < n) ? u : n;
        u = (top > stop) ? top : stop;
        for (; u > stop; u--) {
            out_low[u - 1U] = (low < out_low[u - 1U]) ? (int16_t)low : out_low[u - 1U];
            out_high[u - 1U] = (high > out_high[u - 1U]) ? (int16_t)high : out_high[u - 1U];
        }
    }
    const uint32_t done = p->win_pos - u;
    p->win_low = low;
    p->win_high = high;
    p->win_block_left = left;
    p->win_pos = u;
    return done;
}

/* m (v_end^2 - v_start^2) / 2 as fuel at fq [nL/mJ * 2^20], m = M or
 * M + Mj as the bound needs (see the top): in mJ it is m [kg] * dv2
 * [(mm/s)^2] / 2000, m < 6.4e6 kg (M + Mj <= 2 M) and |dv2| < 4.9e9, so
 * |m dv2| < 2^55, the quotient is below 2^44 and, shifted by 2^-4, times
 * fq < 2^22 below 2^62. M + Mj comes from the object's Q32 mass, to the
 * kilogram. */
static int64_t kinetic_nl(const pfe_predict_t *p, int64_t fq, bool upper)
{
    const int64_t v1 = p->nominal_end_speed_mm_s;
    const int64_t v0 = p->start_speed_mm_s;
    const int64_t dv2 = (v1 * v1) - (v0 * v0);
    /* kg * 2^32 / 10^6 = kg * 2^26 / 5^6 (pfe_vehicle.c), back to kg */
    const uint64_t mass_fuel_kg =
        pfe_udiv_round_u64((uint64_t)p->platoon->object.mass_fuel_q32 * 15625U, (uint64_t)1 << 26);
    const int64_t mass_kg = ((dv2 >= 0) == upper) ? (int64_t)mass_fuel_kg
                                                   : (int64_t)p->platoon->mass_kg;
    const int64_t ke_mj = (mass_kg * dv2) / 2000;
    return pfe_rshift_round(pfe_rshift_round(ke_mj, 4U) * fq, 16U);
}

/* The nominal run's auxiliary fuel at another efficiency: aux * fq /
 * fq_nominal, rounded, for any aux: (aux / fq_nominal) * fq plus the
 * remainder's share. fq_nominal >= 2^14 (eta 1, rho_d 60000 J/mL) and fq
 * < 2^22 keep both products below 2^63 for aux below 2^55 nL (36 million
 * litres: 3.2 MW of auxiliaries for 250000 s, the longest preview at the
 * stall speed, at the lowest efficiency and energy density, is 1.6 million). */
static int64_t aux_nl(const pfe_predict_t *p, int64_t fq)
{
    const uint64_t fq_nominal = (uint64_t)p->platoon->object.fuel_q20;
    uint64_t rem = 0U;
    const uint64_t whole = pfe_udiv_u64(p->nominal_aux_nl, fq_nominal, &rem);
    const uint64_t scaled = (whole * (uint64_t)fq) + pfe_udiv_round_u64(rem * (uint64_t)fq, fq_nominal);
    return (int64_t)scaled;
}

static void publish(pfe_predict_t *p)
{
    pfe_predict_result_t *r = &p->result;
    const int64_t upper_nl = p->sums.bound_nl + aux_nl(p, p->fuel_upper_q20) +
                             kinetic_nl(p, p->fuel_upper_q20, true);
    /* Each bound at least 0, and never across the prediction. The bounds'
     * simplifications can put one on the wrong side of the nominal fuel:
     * the kinetic term counted whole while the nominal run's fuel cut
     * leaves the speed gained downhill to gravity (a long descent: nominal
     * 0, lower bound > 0), the runs' discretisation (Euler steps, the cut
     * decided per step: a few ppm). Widening a bound to the prediction
     * keeps it a bound. */
    uint64_t lower = (p->lower_nl > 0) ? (uint64_t)p->lower_nl : 0U;
    uint64_t upper = (upper_nl > 0) ? (uint64_t)upper_nl : 0U;
    lower = (lower < p->nominal_fuel_nl) ? lower : p->nominal_fuel_nl;
    upper = (upper > p->nominal_fuel_nl) ? upper : p->nominal_fuel_nl;
    r->fuel_ul = pfe_udiv_round_u64(p->nominal_fuel_nl, 1000U);
    r->fuel_upper_ul = pfe_udiv_round_u64(upper, 1000U);
    r->fuel_lower_ul = pfe_udiv_round_u64(lower, 1000U);
    const uint64_t ms = ((p->nominal_time_q16 * 1000U) + 32768U) >> 16;
    r->time_ms = (ms > UINT32_MAX) ? UINT32_MAX : (uint32_t)ms;
    r->distance_m = (p->road.n_samples * p->road.spacing_mm) / 1000U;
    r->end_speed_mm_s = p->nominal_end_speed_mm_s;
    r->generation++;
    r->valid = true;
    p->last_error = PFE_OK;
    p->phase = PFE_PREDICT_DONE;
}

/* A run's steps within the budget left; moves to `next` at its end. */
static uint32_t run_steps(pfe_predict_t *p, uint32_t units, pfe_predict_phase_t next)
{
    const int r = pfe_sim_run(&p->sim, &p->road, units, &p->sums);
    if (r == PFE_ESTALL) {
        abandon(p, PFE_PREDICT_ESTALL);
    } else if (r == PFE_SIM_DONE) {
        if (p->phase == PFE_PREDICT_NOMINAL) {
            p->nominal_fuel_nl = p->sim.fuel_nl;
            p->nominal_aux_nl = p->sums.aux_nl;
            p->nominal_time_q16 = p->sim.time_q16;
            p->nominal_end_speed_mm_s = pfe_sim_speed_mm_s(&p->sim);
        } else if (p->phase == PFE_PREDICT_SLOW) {
            p->lower_nl = p->sums.bound_nl + aux_nl(p, p->fuel_lower_q20) +
                          kinetic_nl(p, p->fuel_lower_q20, false);
        } else {
            /* FAST: publish() reads the sum from the simulation */
        }
        p->sim_ready = false;
        p->n_done = 0U;
        if (next == PFE_PREDICT_DONE) {
            publish(p);
        } else {
            p->phase = next;
        }
    } else {
        /* budget spent, run continues */
    }
    return units;
}

pfe_predict_phase_t pfe_predict_run(pfe_predict_t *p, const pfe_preview_t *pv, uint32_t budget)
{
    if (p->phase == PFE_PREDICT_DONE) {
        p->phase = PFE_PREDICT_IDLE;
    }
    uint32_t cost = 0U;
    while ((cost < budget) && (p->phase != PFE_PREDICT_IDLE) && (p->phase != PFE_PREDICT_DONE)) {
        const uint32_t left = budget - cost;
        if (p->phase == PFE_PREDICT_LOADING) {
            if ((pv->phase != PFE_PREVIEW_READY) || ((uint32_t)pv->sample_count != p->n_samples)) {
                abandon(p, PFE_PREDICT_ENOPREVIEW); /* the preview changed under us */
                break;
            }
            const uint32_t rest = p->n_samples - p->n_done;
            uint32_t want = rest;
            if (left <= (rest / PFE_PREDICT_LOAD_PER_UNIT)) {
                want = left * PFE_PREDICT_LOAD_PER_UNIT;
            }
            const uint32_t got = pfe_preview_copy_ppm(pv, p->n_done, want, &p->grade_ppm[p->n_done]);
            if (got != want) {
                abandon(p, PFE_PREDICT_ENOPREVIEW);
                break;
            }
            window_prefix(p, p->n_done, p->n_done + got);
            p->n_done += got;
            cost += (got + PFE_PREDICT_LOAD_PER_UNIT - 1U) / PFE_PREDICT_LOAD_PER_UNIT;
            if (p->n_done == p->n_samples) {
                p->n_done = 0U;
                p->phase = PFE_PREDICT_WINDOWS;
            }
        } else if (p->phase == PFE_PREDICT_WINDOWS) {
            uint32_t most = UINT32_MAX;
            if (left < (UINT32_MAX / PFE_PREDICT_WINDOW_PER_UNIT)) {
                most = left * PFE_PREDICT_WINDOW_PER_UNIT;
            }
            const uint32_t done = window_suffix(p, most);
            cost += (done + PFE_PREDICT_WINDOW_PER_UNIT - 1U) / PFE_PREDICT_WINDOW_PER_UNIT;
            if (p->win_pos == 0U) {
                p->prepared = true;
                p->phase = PFE_PREDICT_NOMINAL;
            }
        } else if (!p->sim_ready) {
            /* Setting up a run reads every sample once and divides: it takes
             * a call of its own. */
            if (cost > 0U) {
                break;
            }
            if (start_run(p) != PFE_OK) {
                abandon(p, PFE_EINVAL);
                break;
            }
            break;
        } else if (p->phase == PFE_PREDICT_NOMINAL) {
            cost += run_steps(p, left, PFE_PREDICT_SLOW);
        } else if (p->phase == PFE_PREDICT_SLOW) {
            cost += run_steps(p, left, PFE_PREDICT_FAST);
        } else {
            cost += run_steps(p, left, PFE_PREDICT_DONE);
        }
    }
    return p->phase;
}
