/* pfe_input.c - sender arbitration and plausibility of one input (contract in pfe_input.h). */
#include "pfe_input.h"

#include <stddef.h>
#include <string.h>

#include "pfe_calib.h"

/* Plausibility table (pfe_input.h gives the reasons for each figure). The
 * PGNs and periods are the DBC's (pfe_dbc.h). */
const pfe_input_rule_t pfe_input_rules[PFE_IN_COUNT] = {
    /* CCVS1 speed, mm/s: 0 .. 150 km/h, 10 m/s^2 + 1 m/s a frame */
    [PFE_IN_SPEED] = {PFE_PGN_CCVS1, PFE_RX_PERIOD_MS_CCVS1 * 1000U, 0, 41667, 10000U, 1000U, 0U},
    /* SSI pitch as grade, ppm: +-50 %, 20 %/s + 0.5 % a frame */
    [PFE_IN_GRADE] = {PFE_PGN_SSI, PFE_RX_PERIOD_MS_SSI * 1000U, -PFE_GRADE_MAX_PPM, PFE_GRADE_MAX_PPM, 200000U, 5000U, 0U},
    /* VDS altitude, mm: the signal's range, 15 m/s + 10 m a frame (J1939-71: every 1 s) */
    [PFE_IN_ALTITUDE] = {PFE_PGN_VDS, PFE_RX_PERIOD_MS_VDS * 1000U, PFE_CSIG_VDS_ALTITUDE_MIN,
                         PFE_CSIG_VDS_ALTITUDE_MAX, 15000U, 10000U, 0U},
    /* CVW gross combination weight, kg: the calibration's range */
    [PFE_IN_MASS] = {PFE_PGN_CVW, PFE_RX_PERIOD_MS_CVW * 1000U, (int32_t)PFE_MASS_MIN_KG, (int32_t)PFE_MASS_MAX_KG, 0U, 0U, 0U},
    /* LFE1 engine fuel rate, nL/s: 0 .. 250 L/h */
    [PFE_IN_ENGINE_FUEL] = {PFE_PGN_LFE1, PFE_RX_PERIOD_MS_LFE1 * 1000U, 0, 69444444, 0U, 0U, 60000U},
};

void pfe_input_init(pfe_input_t *in, pfe_input_kind_t kind, uint8_t fixed_source)
{
    (void)memset(in, 0, sizeof *in);
    in->kind = kind;
    in->fixed = fixed_source != PFE_INPUT_NO_SOURCE;
    in->locked = fixed_source;
    in->state = PFE_SIG_NOT_AVAILABLE;
}

static uint64_t stale_us(const pfe_input_t *in)
{
    return (uint64_t)PFE_INPUT_STALE_PERIODS * pfe_input_rules[in->kind].period_us;
}

static void note_sender(pfe_input_t *in, uint8_t source)
{
    for (uint32_t k = 0U; k < in->n_senders; k++) {
        if (in->senders[k] == source) {
            return;
        }
    }
    if (in->n_senders < PFE_INPUT_MAX_SENDERS) {
        in->senders[in->n_senders] = source;
        in->n_senders++;
    }
}

static bool in_range(const pfe_input_t *in, int32_t value)
{
    const pfe_input_rule_t *r = &pfe_input_rules[in->kind];
    return (value >= r->min) && (value <= r->max);
}

/* Step 1: is the frame the input's? A new sender is taken only with a
 * valid value inside the plausible range. */
static bool arbitrate(pfe_input_t *in, uint8_t source, pfe_sig_state_t state, int32_t value,
                      uint64_t rx_us)
{
    if (in->fixed) {
        return source == in->locked;
    }
    if (source == in->locked) {
        return true;
    }
    const bool none = in->locked == PFE_INPUT_NO_SOURCE;
    const bool stale = none || ((rx_us - in->locked_valid_us) > stale_us(in));
    if ((state == PFE_SIG_VALID) && stale && in_range(in, value)) {
        /* a new sender: its value has no rate reference from the old one */
        in->locked = source;
        in->have_ref = false;
        return true;
    }
    return false;
}

static uint32_t abs_diff(int32_t a, int32_t b)
{
    const int64_t d = (int64_t)a - (int64_t)b;
    return (uint32_t)((d < 0) ? -d : d);
}

typedef enum { PLAUSIBLE, OUT_OF_RANGE, TOO_FAST, TOO_EARLY } plausibility_t;

/* floor(rate * dt_us / 10^6), exact, in 32-bit operations (a 64-bit
 * division is a libgcc call on the Cortex-M4, on every frame: a call of
 * pfe_input_take() went from 158 to 129 instructions, docs/bench.md). For
 * rate < 2^18 and any dt_us < 2^32: with dt_us = q 10^6 +
 * r1 10^3 + r0 (r1, r0 < 1000),
 *     rate dt_us / 10^6 = rate q + (rate r1 + rate r0 / 10^3) / 10^3,
 * and the floor of the inner quotient may be taken first (the outer
 * division's result moves at whole numbers only). Every product and sum is
 * below 2^31; the result is below rate * 4295 < 2^31. A larger rate takes
 * the 64-bit division. */
static uint64_t rate_times_dt(uint32_t rate_per_s, uint64_t dt_us)
{
    if ((rate_per_s >= (1UL << 18)) || (dt_us > UINT32_MAX)) {
        return ((uint64_t)rate_per_s * dt_us) / 1000000U;
    }
    const uint32_t dt = (uint32_t)dt_us;
    const uint32_t q = dt / 1000000U;
    const uint32_t rem = dt - (q * 1000000U);
    const uint32_t r1 = rem / 1000U;
    const uint32_t r0 = rem - (r1 * 1000U);
    const uint32_t inner = (rate_per_s * r1) + ((rate_per_s * r0) / 1000U);
    const uint32_t whole = rate_per_s * q;
    const uint32_t part = inner / 1000U;
    return (uint64_t)whole + part;
}

/* Step 2: within range, and within rate * dt + margin of the reference. */
static plausibility_t plausible(const pfe_input_t *in, int32_t value, uint64_t rx_us)
{
    const pfe_input_rule_t *r = &pfe_input_rules[in->kind];
    if (!in_range(in, value)) {
        return OUT_OF_RANGE;
    }
    if (!in->have_ref) {
        return PLAUSIBLE;
    }
    uint64_t dt_us = rx_us - in->last_us;
    if (dt_us < r->min_interval_us) {
        return TOO_EARLY; /* a second node with the same address, or a sender gone wild */
    }
    if (r->max_rate_per_s == 0U) {
        return PLAUSIBLE;
    }
    if (dt_us > stale_us(in)) {
        dt_us = stale_us(in);
    }
    const uint64_t allowed = rate_times_dt(r->max_rate_per_s, dt_us) + r->margin;
    return ((uint64_t)abs_diff(value, in->last_value) <= allowed) ? PLAUSIBLE : TOO_FAST;
}

static void count_reject(pfe_input_t *in)
{
    if (in->rejected < UINT32_MAX) {
        in->rejected++;
    }
}

static pfe_input_verdict_t take_valid(pfe_input_t *in, int32_t value, uint64_t rx_us)
{
    const plausibility_t p = plausible(in, value, rx_us);
    if (p != PLAUSIBLE) {
        count_reject(in);
        if (in->rejects_in_row < UINT8_MAX) {
            in->rejects_in_row++;
        }
        if (in->error) {
            /* Still in error, and current: confirmation starts again, from
             * this frame when only its change was too fast. */
            in->rx_us = rx_us;
            in->have_ref = p != OUT_OF_RANGE;
            in->confirm_left = (uint8_t)PFE_INPUT_CONFIRM_FRAMES;
            if (p != OUT_OF_RANGE) {
                in->confirm_left = (uint8_t)(PFE_INPUT_CONFIRM_FRAMES - 1U);
            }
            in->last_value = value;
            in->last_us = rx_us;
        } else if (in->rejects_in_row >= PFE_INPUT_REJECTS_TO_ERROR) {
            in->error = true;
            in->state = PFE_SIG_ERROR;
            in->value = 0;
            in->rx_us = rx_us;
            in->confirm_left = (uint8_t)PFE_INPUT_CONFIRM_FRAMES;
            in->have_ref = false;
        } else {
            /* keep the last accepted value and its reference */
        }
        return PFE_INPUT_REJECTED;
    }
    in->rejects_in_row = 0U;
    in->last_value = value;
    in->last_us = rx_us;
    in->have_ref = true;
    in->locked_valid_us = rx_us;
    if (in->error) {
        if (in->confirm_left > 1U) {
            in->confirm_left--;
            in->rx_us = rx_us; /* an input in error is current, not stale */
            return PFE_INPUT_CONFIRMING;
        }
        in->error = false;
        in->confirm_left = 0U;
    }
    in->state = PFE_SIG_VALID;
    in->value = value;
    in->rx_us = rx_us;
    return PFE_INPUT_ACCEPTED;
}

pfe_input_verdict_t pfe_input_take(pfe_input_t *in, uint8_t source, pfe_sig_state_t state,
                                   int32_t value, uint64_t rx_us)
{
    note_sender(in, source);
    if (!arbitrate(in, source, state, value, rx_us)) {
        if ((in->locked == PFE_INPUT_NO_SOURCE) && (state == PFE_SIG_ERROR)) {
            /* no sender in use, and one says its sensor failed: the input is
             * an error (not absent) until a valid sender comes */
            in->state = PFE_SIG_ERROR;
            in->value = 0;
            in->rx_us = rx_us;
            return PFE_INPUT_ACCEPTED;
        }
        return PFE_INPUT_IGNORED;
    }
    if (state == PFE_SIG_VALID) {
        return take_valid(in, value, rx_us);
    }
    /* Too soon after the last accepted value, whatever it says: not the
     * sender's own frame (a second node with its address, or garbage). */
    const uint32_t min_us = pfe_input_rules[in->kind].min_interval_us;
    if (in->have_ref && ((rx_us - in->last_us) < min_us)) {
        count_reject(in);
        return PFE_INPUT_REJECTED;
    }
    /* The locked sender says not available, error or out of range. */
    in->state = state;
    in->value = 0;
    in->rx_us = rx_us;
    if ((state == PFE_SIG_ERROR) && !in->fixed) {
        /* any other sender with a valid value may take over at once */
        in->locked_valid_us = rx_us - stale_us(in) - 1U;
    }
    return PFE_INPUT_ACCEPTED;
}

bool pfe_input_age(pfe_input_t *in, uint64_t now_us)
{
    if ((in->state != PFE_SIG_NOT_AVAILABLE) && ((now_us - in->rx_us) > stale_us(in))) {
        in->state = PFE_SIG_NOT_AVAILABLE;
        in->value = 0;
        in->have_ref = false;
        in->error = false;
        in->confirm_left = 0U;
        in->rejects_in_row = 0U;
    }
    return in->state == PFE_SIG_VALID;
}

uint8_t pfe_input_source(const pfe_input_t *in)
{
    return in->locked;
}
