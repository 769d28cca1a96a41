/*
 * ecu_check - judge a module's answers on a recorded bus against the
 * double-precision reference (sim_host/ref/bus_ref.h, its BUS_REF_HISTORY
 * ticks), for the end-to-end runs on vcan.
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/pfe_can.h"
#include "firmware/pfe_codec.h"
#include "ref/bus_ref.h"

#define RELATIVE_FROM_L_S (5.0 / 3600.0) /* rates judged relatively from 5 L/h */
#include "hal/replay/hal_replay_ecu.h"
#include "lib/capture.h"
#include "lib/disturb.h"

#define TAIL_US ((uint64_t)HAL_REPLAY_ECU_TAIL_US)
#define GAP_US ((uint64_t)HAL_REPLAY_ECU_GAP_US)
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: ecu_check CAPTURE.log [--module-sa SA] [--warmup-s S]\n"
    "\n"
    "Judges a module's answers on a recorded bus against the double-precision\n"
    "reference (the end-to-end runs on vcan).\n"
    "\n"
    "CAPTURE is one candump log (candump -L) of\n"
    "everything on the bus: the drive's CCVS1, SSI and PFE_PlatoonConfig\n"
    "frames and the module's answers (source address SA, default 0x8C). The\n"
    "reference estimator steps every 10 ms on the same input frames, handling\n"
    "them as the module does (one truck until a\n"
    "PFE_PlatoonConfig says otherwise, default calibration).\n"
    "Checked from the warm-up to the last input frame (after it the module's\n"
    "inputs time out, as they should):\n"
    "  every LFE1 fuel rate within 1 % of the reference at its time, where\n"
    "    the reference is at least 5 L/h (below, near fuel cut, the frames are\n"
    "    counted, not judged: LFE1's own step, 0.05 L/h, is 1 % of 5 L/h): the best\n"
    "    of the reference ticks in the 60 ms before it and of what a module tick\n"
    "    right after each input frame of those 60 ms, or at the LFE1 frame's\n"
    "    own time, would answer, since the module's tick phase is not in the\n"
    "    capture (an input frame that reached the module just before its tick\n"
    "    is in its answer, and in none of the reference's own ticks before it)\n"
    "    and a late tick of a loaded host sends a frame up to a few ticks after\n"
    "    its estimate; and never \"not available\";\n"
    "  except where the capture cannot say what the module received or did\n"
    "    when (lib/disturb.h: the inputs stalled or bunched, the module reported\n"
    "    5 or more lost ticks, or its own 100 ms frames bunched as a loop\n"
    "    catching up after a stall sends them): those rates (and \"not\n"
    "    available\" there, from inputs a stalled replay let go stale) are left\n"
    "    out and counted, and at least a quarter of the rates must be judged;\n"
    "  the last HRLFC total fuel used within 0.5 % of the reference's.\n"
    "Prints the figures; exit status 0 pass, 1 fail, 2 bad input.\n"
    "\n"
    "The warm-up is --warmup-s S seconds after the first input frame (default 5).\n"
    "A silence of more than 11 s without any frame (a logger whose clock\n"
    "jumped) is crossed in one jump, as pfe_ecu_replay crosses it, and counted.\n";

/* What a module tick right after each input frame would answer
 * (bus_ref_peek), one per input frame of the capture, in time order: the
 * candidates beside the reference's own ticks (k_manual). Room for every
 * record, so that no busy stretch of bus pushes a candidate out of the
 * window. */
#define WINDOW_US ((uint64_t)BUS_REF_HISTORY * BUS_REF_TICK_US)

typedef struct {
    uint64_t t_us;
    double own_l_s;
} peek_t;

typedef struct {
    peek_t *at; /* owned, room for the capture's records */
    size_t n;
} peeks_t;

static void peek_after_input(peeks_t *p, const bus_ref_t *ref, uint64_t t_us)
{
    double platoon = 0.0;
    p->at[p->n].t_us = t_us;
    (void)bus_ref_peek(ref, t_us, &p->at[p->n].own_l_s, &platoon);
    p->n++;
}

/* The reference's own-truck rate nearest to got_l_s for a module frame sent
 * at t_us: its last ticks, the peeks within WINDOW_US before t_us, and a
 * tick at t_us itself with every input so far. */
static double nearest_own(const bus_ref_t *ref, const peeks_t *p, uint64_t t_us, double got_l_s)
{
    double best = bus_ref_nearest(ref, false, got_l_s);
    double own = 0.0, platoon = 0.0;
    (void)bus_ref_peek(ref, t_us, &own, &platoon);
    if (fabs(own - got_l_s) < fabs(best - got_l_s)) {
        best = own;
    }
    for (size_t i = p->n; (i > 0U) && ((p->at[i - 1U].t_us + WINDOW_US) >= t_us); i--) {
        if (fabs(p->at[i - 1U].own_l_s - got_l_s) < fabs(best - got_l_s)) {
            best = p->at[i - 1U].own_l_s;
        }
    }
    return best;
}

int main(int argc, char **argv)
{
    if (cli_help_asked(argc, argv)) {
        cli_help(k_manual);
        return 0;
    }
    if (argc < 2) {
        cli_usage(stderr, k_manual, "ecu_check");
        return 2;
    }
    unsigned long module_sa = PFE_CODEC_DEFAULT_ADDRESS;
    double warmup_s = 5.0;
    for (int i = 2; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--module-sa") == 0) {
            module_sa = strtoul(argv[i + 1], NULL, 0);
        } else if (strcmp(argv[i], "--warmup-s") == 0) {
            warmup_s = strtod(argv[i + 1], NULL);
        } else {
            fprintf(stderr, "ecu_check: unknown option '%s'\n", argv[i]);
            return 2;
        }
    }
    char err[512];
    capture_t cap;
    if (capture_load(argv[1], &cap, err, sizeof err) != 0) {
        fprintf(stderr, "ecu_check: %s\n", err);
        return 2;
    }
    uint64_t t_last_input = 0U;
    for (size_t k = 0U; k < cap.n; k++) {
        if (pfe_j1939_source(cap.recs[k].f.id) != module_sa) {
            t_last_input = cap.recs[k].t_us;
        }
    }
    static bus_ref_t ref;
    (void)bus_ref_init(&ref, 1U, 0U, 10000U);
    peeks_t peeks = {calloc(cap.n + 1U, sizeof(peek_t)), 0U};
    if (peeks.at == NULL) {
        fprintf(stderr, "ecu_check: out of memory for %zu records\n", cap.n);
        capture_free(&cap);
        return 2;
    }
    uint64_t t0 = 0U;
    bool started = false;
    size_t lfe1 = 0U, lfe1_na = 0U, hrlfc = 0U, gaps_skipped = 0U;
    double worst = 0.0, last_total_l = -1.0, ref_at_total = 0.0;
    double worst_t_s = 0.0, worst_got = 0.0, worst_want = 0.0;
    size_t lfe1_low = 0U, lfe1_disturbed = 0U, lfe1_na_disturbed = 0U;
    static disturb_t dist;
    disturb_find(&cap, (uint8_t)module_sa, &dist);
    for (size_t k = 0U; k < cap.n; k++) {
        const capture_rec_t *c = &cap.recs[k];
        const uint8_t sa = pfe_j1939_source(c->f.id);
        const uint32_t pgn = pfe_j1939_pgn(c->f.id);
        /* A silence of more than GAP_US is crossed in one jump, as
         * pfe_ecu_replay crosses it: a logger whose clock jumps by years
         * must not be ticked through. */
        if (ref.started && (c->t_us > ref.next_tick_us + TAIL_US + GAP_US)) {
            gaps_skipped++;
            (void)bus_ref_skip_to(&ref, c->t_us - TAIL_US);
        }
        if (sa != module_sa) {
            /* The reference's ticks start at the first input frame; after
             * that a frame at a tick's very time is that tick's, as the
             * module takes every frame received by its deadline (a capture
             * may start at time 0: no tick is due before the first). */
            bus_ref_advance(&ref, (started && (c->t_us > 0U)) ? (c->t_us - 1U) : c->t_us);
            if (!started) {
                t0 = c->t_us;
                started = true;
            }
            bus_ref_input(&ref, &c->f, c->t_us);
            peek_after_input(&peeks, &ref, c->t_us);
            continue;
        }
        if (!started || ((double)(c->t_us - t0) / 1e6 < warmup_s) || (c->t_us > t_last_input)) {
            continue;
        }
        bus_ref_advance(&ref, c->t_us);
        if (pgn == PFE_PGN_LFE1) {
            pfe_msg_lfe1_t m;
            if (pfe_codec_decode_lfe1(&c->f, &m) < 0) {
                continue;
            }
            lfe1++;
            const bool calm = !disturbed(&dist, c->t_us);
            if (m.fuel_rate_nl_s.state != PFE_SIG_VALID) {
                lfe1_na += calm ? 1U : 0U;
                lfe1_na_disturbed += calm ? 0U : 1U;
                continue;
            }
            if (!calm) {
                lfe1_disturbed++;
                continue;
            }
            const double got = m.fuel_rate_nl_s.value / 1e9; /* L/s */
            const double want = nearest_own(&ref, &peeks, c->t_us, got);
            if (want < RELATIVE_FROM_L_S) {
                /* Near fuel cut a relative error says nothing: LFE1's own
                 * step, 0.05 L/h, is 1 % of 5 L/h (as run_report judges). */
                lfe1_low++;
                continue;
            }
            const double rel = fabs(got - want) / want;
            if (rel > worst) {
                worst = rel;
                worst_t_s = (double)(c->t_us - t0) / 1e6;
                worst_got = got;
                worst_want = want;
            }
        } else if (pgn == PFE_PGN_HRLFC) {
            pfe_msg_hrlfc_t m;
            if ((pfe_codec_decode_hrlfc(&c->f, &m) >= 0) && (m.total_fuel_ul.state == PFE_SIG_VALID)) {
                hrlfc++;
                last_total_l = (double)m.total_fuel_ul.value / 1e6;
                ref_at_total = bus_ref_own_used(&ref);
            }
        }
    }
    const size_t n = cap.n;
    capture_free(&cap);
    free(peeks.at);
    const size_t left_out = lfe1_disturbed + lfe1_na_disturbed;
    /* At least a quarter judged: under make test-loaded 45 % were left out
     * (254 of 566); a capture that leaves fewer than a quarter cannot say
     * the module's rates are right. */
    const bool enough = (4U * left_out) <= (3U * lfe1);
    const double total_err = (ref_at_total > 0.0) ? fabs(last_total_l - ref_at_total) / ref_at_total : 1.0;
    printf("ecu_check: %zu frames; after %.1f s warm-up: %zu LFE1 (%zu not available, %zu below "
           "5 L/h), worst rate error %.3f %% (limit 1 %%); last HRLFC %.3f L against reference "
           "%.4f L, error %.3f %% (limit 0.5 %%, %zu HRLFC frames)\n",
           n, warmup_s, lfe1, lfe1_na, lfe1_low, 100.0 * worst, last_total_l, ref_at_total,
           100.0 * total_err, hrlfc);
    printf("ecu_check: left out %zu of %zu LFE1 (%zu of them not available) within %.0f s after %zu "
           "input timing events, %zu reports of %u or more lost ticks and among %zu timing events of "
           "the module's own frames; at most three quarters may be%s\n",
           left_out, lfe1, lfe1_na_disturbed, DISTURB_RECOVERY_US / 1e6, dist.input_events,
           dist.overrun_events, DISTURB_LOST_TICKS_MIN, dist.output_events,
           enough ? "" : ": too disturbed a capture to judge");
    disturb_free(&dist);
    if (gaps_skipped > 0U) {
        printf("ecu_check: %zu silence(s) of over %.0f s crossed in one jump\n", gaps_skipped,
               (double)(TAIL_US + GAP_US) / 1e6);
    }
    const bool pass = (lfe1 > 0U) && enough && (lfe1_na == 0U) && (worst <= 0.01) &&
                      (hrlfc > 0U) && (total_err <= 0.005);
    if (worst > 0.01) {
        printf("ecu_check: the worst rate at %.3f s after the first input: module %.4f L/h, "
               "reference %.4f L/h\n", worst_t_s, worst_got * 3600.0, worst_want * 3600.0);
    }
    printf("ecu_check: %s\n", pass ? "PASS" : "FAIL");
    return pass ? 0 : 1;
}
