/* disturb.c - the spans a judge leaves out of a capture (contract in disturb.h). */
#include "lib/disturb.h"

#include <stdlib.h>
#include <string.h>

#include "firmware/pfe_can.h"
#include "firmware/pfe_codec.h"

static void disturb_add(disturb_t *d, uint64_t from_us, uint64_t to_us)
{
    if (d->n == d->room) {
        const size_t want = (d->room == 0U) ? 64U : (d->room * 2U);
        disturb_span_t *grown = realloc(d->spans, want * sizeof *grown);
        if (grown == NULL) {
            return; /* out of memory: the span is judged like any other */
        }
        d->spans = grown;
        d->room = want;
    }
    d->spans[d->n].from_us = from_us;
    d->spans[d->n].to_us = to_us;
    d->n++;
}

/* A periodic frame at t_us after the one at *last_us (if *have): whether
 * its gap is outside the 100 ms period's 50 to 150 ms. Updates *last_us. */
static bool off_period(uint64_t *last_us, bool *have, uint64_t t_us, uint64_t *prev_us)
{
    const bool off = *have && (((t_us - *last_us) < DISTURB_PERIODIC_GAP_MIN_US) ||
                               ((t_us - *last_us) > DISTURB_PERIODIC_GAP_MAX_US));
    *prev_us = *last_us;
    *have = true;
    *last_us = t_us;
    return off;
}

/* The module's own frames: LFE1 and PFE_OwnFuel, each on its own period. */
static void module_frame(disturb_t *d, const capture_rec_t *r, uint32_t pgn, uint64_t last[2],
                         bool have[2])
{
    const int k = (pgn == PFE_PGN_LFE1) ? 0 : ((pgn == PFE_PGN_OWN_FUEL) ? 1 : -1);
    uint64_t prev = 0U;
    if ((k >= 0) && off_period(&last[k], &have[k], r->t_us, &prev)) {
        disturb_add(d, prev, r->t_us);
        d->output_events++;
    }
}

void disturb_find(const capture_t *cap, uint8_t module_sa, disturb_t *d)
{
    memset(d, 0, sizeof *d);
    /* each sender's own timing: two senders of CCVS1 interleave */
    static uint64_t last_ssi[256], last_ccvs1[256];
    static bool have_ssi[256], have_ccvs1[256];
    memset(have_ssi, 0, sizeof have_ssi);
    memset(have_ccvs1, 0, sizeof have_ccvs1);
    uint64_t last_out[2] = {0U, 0U};
    bool have_out[2] = {false, false};
    uint64_t last_status = 0U;
    bool have_status = false;
    uint32_t overruns = 0U;
    for (size_t k = 0U; k < cap->n; k++) {
        const capture_rec_t *r = &cap->recs[k];
        const uint32_t pgn = pfe_j1939_pgn(r->f.id);
        const uint8_t sa = pfe_j1939_source(r->f.id);
        uint64_t prev = 0U;
        if (sa != module_sa) {
            if (pgn == PFE_PGN_SSI) {
                if (have_ssi[sa] && ((r->t_us - last_ssi[sa]) > DISTURB_SSI_GAP_MAX_US)) {
                    disturb_add(d, last_ssi[sa], r->t_us + DISTURB_RECOVERY_US);
                    d->input_events++;
                }
                have_ssi[sa] = true;
                last_ssi[sa] = r->t_us;
            } else if ((pgn == PFE_PGN_CCVS1) &&
                       off_period(&last_ccvs1[sa], &have_ccvs1[sa], r->t_us, &prev)) {
                disturb_add(d, prev, r->t_us + DISTURB_RECOVERY_US);
                d->input_events++;
            } else {
                /* another input: no timing of its own to judge */
            }
            continue;
        }
        module_frame(d, r, pgn, last_out, have_out);
        pfe_msg_status_t m;
        if ((pgn == PFE_PGN_STATUS) && (pfe_codec_decode_status(&r->f, &m) >= 0) &&
            (m.tick_overruns.state == PFE_SIG_VALID)) {
            if (m.tick_overruns.value >= overruns + DISTURB_LOST_TICKS_MIN) {
                disturb_add(d, have_status ? last_status : cap->recs[0].t_us,
                            r->t_us + DISTURB_RECOVERY_US);
                d->overrun_events++;
            }
            overruns = m.tick_overruns.value;
            have_status = true;
            last_status = r->t_us;
        }
    }
}

bool disturbed(const disturb_t *d, uint64_t t_us)
{
    for (size_t k = 0U; k < d->n; k++) {
        if ((t_us >= d->spans[k].from_us) && (t_us <= d->spans[k].to_us)) {
            return true;
        }
    }
    return false;
}

void disturb_free(disturb_t *d)
{
    free(d->spans);
    d->spans = NULL;
    d->n = 0U;
    d->room = 0U;
}

/* One run of a periodic message's frames, their send times t[0 .. n-1]:
 * the run's base, then the made times (disturb.h). */
static void made_times_run(const uint64_t *t, const size_t *at, size_t n, uint64_t p_us,
                           uint64_t *made_us, uint64_t *late_max_us)
{
    int64_t base = INT64_MAX;
    for (size_t j = 0U; j < n; j++) {
        const int64_t b = (int64_t)t[j] - (int64_t)(j * p_us);
        base = (b < base) ? b : base;
    }
    for (size_t j = 0U; j < n; j++) {
        made_us[at[j]] = (uint64_t)(base + (int64_t)(j * p_us));
        const uint64_t late = t[j] - made_us[at[j]];
        *late_max_us = (late > *late_max_us) ? late : *late_max_us;
    }
}

/* One periodic message's frames, run by run. */
static void made_times_of(const capture_t *cap, uint8_t module_sa, uint32_t pgn, uint64_t p_us,
                          uint64_t *t, size_t *at, uint64_t *made_us, uint64_t *late_max_us)
{
    if (p_us == 0U) {
        return; /* sent on request only: no schedule */
    }
    size_t n = 0U;
    for (size_t k = 0U; k < cap->n; k++) {
        const capture_rec_t *r = &cap->recs[k];
        if ((pfe_j1939_source(r->f.id) != module_sa) || (pfe_j1939_pgn(r->f.id) != pgn)) {
            continue;
        }
        if ((n > 0U) && ((r->t_us - t[n - 1U]) > ((3U * p_us) / 2U))) {
            made_times_run(t, at, n, p_us, made_us, late_max_us);
            n = 0U;
        }
        t[n] = r->t_us;
        at[n] = k;
        n++;
    }
    if (n > 0U) {
        made_times_run(t, at, n, p_us, made_us, late_max_us);
    }
}

int disturb_made_times(const capture_t *cap, uint8_t module_sa, uint64_t *made_us,
                       uint64_t *late_max_us)
{
    *late_max_us = 0U;
    for (size_t k = 0U; k < cap->n; k++) {
        made_us[k] = cap->recs[k].t_us;
    }
    uint64_t *t = malloc((cap->n + 1U) * sizeof *t);
    size_t *at = malloc((cap->n + 1U) * sizeof *at);
    const int ok = (t != NULL) && (at != NULL);
    if (ok) {
        made_times_of(cap, module_sa, PFE_PGN_OWN_FUEL,
                      (uint64_t)pfe_codec_messages[PFE_MSG_OWN_FUEL].cycle_ms * 1000U, t, at, made_us,
                      late_max_us);
        made_times_of(cap, module_sa, PFE_PGN_PLATOON_FUEL,
                      (uint64_t)pfe_codec_messages[PFE_MSG_PLATOON_FUEL].cycle_ms * 1000U, t, at,
                      made_us, late_max_us);
    }
    free(t);
    free(at);
    return ok ? 0 : -1;
}
