/*
 * pfe_faults - input faults in a drive log (k_faults below), and the verdict
 * on how the module answered them.
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/pfe_can.h"
#include "firmware/pfe_codec.h"
#include "hal/replay/hal_replay.h"
#include "lib/replay_source.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: pfe_faults inject DRIVE.log OUT.log\n"
    "       pfe_faults judge CAPTURE.log [--module-sa SA] [--slack-ms MS]\n"
    "\n"
    "Input faults in a drive log, and the verdict on how the module answered\n"
    "them.\n"
    "\n"
    "inject copies a drive (candump -L, CCVS1 and SSI frames, as drivegen\n"
    "writes it) with these faults, at fixed times after its\n"
    "first frame: CCVS1 stops for 5 s; SSI stops for 2 s; CCVS1 and SSI each\n"
    "carry a parameter-specific out-of-range raw value (0xFB00) for 2 s, then\n"
    "their sender's J1939 error value for 2 s. The drive must last past the\n"
    "last fault (60 s).\n"
    "\n"
    "judge reads a capture of the bus (the faulty inputs and the module's\n"
    "answers, source address SA, default 0x8C) and checks each fault:\n"
    "  - onset: for a silence, the input's last frame before the gap; for a\n"
    "    bad value, the first frame that carries it (both found by content\n"
    "    from 0.5 s before the fault's nominal time: a capture's clock drifts\n"
    "    from the log's). The input returns with the first frame after the\n"
    "    gap, or the first valid value. The deadline is onset + three periods of\n"
    "    the input (CCVS1 100 ms, SSI 10 ms) + one 10 ms tick for a silence,\n"
    "    onset + one tick for a bad value;\n"
    "  - the module's last LFE1 before the onset was valid (else the check\n"
    "    proves nothing);\n"
    "  - every LFE1, PFE_OwnFuel and PFE_PlatoonFuel fuel rate sent after deadline + slack\n"
    "    until the input returns is \"not available\", and there is at least\n"
    "    one;\n"
    "  - every PFE_Status sent in that time gives the input's state (not\n"
    "    available, error, out of range) and mode \"no estimate\", and there is\n"
    "    at least one;\n"
    "  - after the input returns, an LFE1 is valid again within 1 s, and the\n"
    "    next PFE_Status gives the input as valid.\n"
    "A silent SSI is the exception: the module then assumes the road flat\n"
    "(can_dbc/pfe.dbc, PFE_InputStatus GradeSource), so its rates stay\n"
    "available; the judge checks that none is \"not available\", that every\n"
    "PFE_Status in the window gives the grade input not available and mode\n"
    "\"degraded\", and every PFE_InputStatus grade source \"assumed flat\".\n"
    "Slack (default 0) allows for a tick phase the capture does not show: 0\n"
    "for a replay in logical time, a tick or two over a real bus.\n"
    "Prints a line per fault; exit status 0 pass, 1 fail, 2 bad input.\n"
    "\n"
    "Example:\n"
    "  pfe_faults inject drive.log faults.log\n"
    "  pfe_ecu_replay --log faults.log --record bus.log && pfe_faults judge bus.log\n";

#define MAX_FRAMES 400000U
#define TICK_US 10000U
#define RECOVERY_US 1000000U
#define SEARCH_US 500000U   /* how far before its nominal time a fault is looked for */

typedef enum { INPUT_SPEED, INPUT_GRADE } input_t;
typedef enum { FAULT_SILENT, FAULT_OUT_OF_RANGE, FAULT_ERROR } fault_kind_t;

typedef struct {
    const char *name;
    input_t input;
    fault_kind_t kind;
    uint32_t from_ms;   /* after the drive's first frame */
    uint32_t to_ms;     /* the input is back to normal from here */
} fault_t;

static const fault_t k_faults[] = {
    {"CCVS1 stops", INPUT_SPEED, FAULT_SILENT, 20000U, 25000U},
    {"SSI stops", INPUT_GRADE, FAULT_SILENT, 30000U, 32000U},
    {"CCVS1 out of range", INPUT_SPEED, FAULT_OUT_OF_RANGE, 36000U, 38000U},
    {"CCVS1 error value", INPUT_SPEED, FAULT_ERROR, 42000U, 44000U},
    {"SSI out of range", INPUT_GRADE, FAULT_OUT_OF_RANGE, 48000U, 50000U},
    {"SSI error value", INPUT_GRADE, FAULT_ERROR, 54000U, 56000U},
};
#define N_FAULTS (sizeof k_faults / sizeof k_faults[0])

typedef struct {
    uint64_t t_us;
    pfe_can_frame_t f;
} cap_t;

static cap_t *g_cap;
static size_t g_n;

/* Reads a CAN log (any form sim_host/lib/log/log.h reads) through the replay
 * bus into g_cap. */
static int load(const char *path)
{
    static replay_source_t src;
    char err[CANLOG_MSG_MAX];
    if (replay_source_open(&src, path, CANLOG_FMT_AUTO, err, sizeof err) != 0) {
        fprintf(stderr, "pfe_faults: cannot read %s\n", err);
        return -1;
    }
    static hal_replay_bus_t bus;
    hal_replay_init_source(&bus, replay_source_next, &src, NULL, NULL, NULL);
    hal_can_t *h = hal_replay_open(&bus);
    g_cap = malloc(sizeof(cap_t) * MAX_FRAMES);
    if (g_cap == NULL) {
        replay_source_close(&src);
        fprintf(stderr, "pfe_faults: out of memory\n");
        return -1;
    }
    g_n = 0U;
    uint64_t t = 0U;
    while (hal_replay_next_us(&bus, &t)) {
        hal_replay_advance_to(&bus, t);
        hal_can_rx_t rx;
        while (hal_can_receive(h, &rx) == 0) {
            if (g_n == MAX_FRAMES) {
                fprintf(stderr, "pfe_faults: %s: more than %u frames\n", path, MAX_FRAMES);
                replay_source_close(&src);
                return -1;
            }
            g_cap[g_n].t_us = rx.timestamp_us;
            g_cap[g_n].f = rx.frame;
            g_n++;
        }
    }
    const hal_replay_stats_t *st = hal_replay_stats(&bus);
    hal_can_stats_t hs;
    hal_can_get_stats(h, &hs);
    replay_source_close(&src);
    if ((st->bad_lines > 0U) || st->read_failed || (hs.rx_dropped > 0U)) {
        fprintf(stderr, "pfe_faults: %s: %u bad lines (the first: %s), %u frames lost%s\n", path,
                st->bad_lines, (st->bad_lines > 0U) ? replay_source_first_bad(&src) : "none",
                hs.rx_dropped, st->read_failed ? ", a read error" : "");
        return -1;
    }
    if (g_n == 0U) {
        fprintf(stderr, "pfe_faults: %s: no frames\n", path);
        return -1;
    }
    return 0;
}

static void print_frame(FILE *out, const cap_t *c)
{
    const bool eff = (c->f.id & PFE_CAN_EFF_FLAG) != 0U;
    fprintf(out, eff ? "(%llu.%06llu) vcan0 %08lX#" : "(%llu.%06llu) vcan0 %03lX#",
            (unsigned long long)(c->t_us / 1000000U), (unsigned long long)(c->t_us % 1000000U),
            (unsigned long)(c->f.id & PFE_CAN_ID_MASK));
    for (uint8_t k = 0U; k < c->f.dlc; k++) {
        fprintf(out, "%02X", c->f.data[k]);
    }
    fputc('\n', out);
}

static bool is_pgn(const pfe_can_frame_t *f, uint32_t pgn)
{
    return ((f->id & PFE_CAN_EFF_FLAG) != 0U) && (pfe_j1939_pgn(f->id) == pgn);
}

static uint32_t input_pgn(input_t in)
{
    return (in == INPUT_SPEED) ? PFE_PGN_CCVS1 : PFE_PGN_SSI;
}

/* The fault active on this frame of input `in` at time rel_ms, or NULL. */
static const fault_t *fault_at(input_t in, uint64_t rel_us)
{
    for (size_t k = 0U; k < N_FAULTS; k++) {
        const fault_t *ft = &k_faults[k];
        if ((ft->input == in) && (rel_us >= (uint64_t)ft->from_ms * 1000U) &&
            (rel_us < (uint64_t)ft->to_ms * 1000U)) {
            return ft;
        }
    }
    return NULL;
}

static int inject(const char *in_path, const char *out_path)
{
    if (load(in_path) != 0) {
        return 2;
    }
    const uint64_t t0 = g_cap[0].t_us;
    const uint64_t last_fault_us = (uint64_t)k_faults[N_FAULTS - 1U].to_ms * 1000U;
    if ((g_cap[g_n - 1U].t_us - t0) < (last_fault_us + RECOVERY_US)) {
        fprintf(stderr, "pfe_faults: %s lasts %.1f s; the faults need %.1f s\n", in_path,
                (double)(g_cap[g_n - 1U].t_us - t0) / 1e6, (double)(last_fault_us + RECOVERY_US) / 1e6);
        return 2;
    }
    FILE *out = fopen(out_path, "w");
    if (out == NULL) {
        fprintf(stderr, "pfe_faults: cannot write %s: %s\n", out_path, strerror(errno));
        return 2;
    }
    uint32_t dropped = 0U, changed = 0U;
    for (size_t k = 0U; k < g_n; k++) {
        cap_t c = g_cap[k];
        const bool speed = is_pgn(&c.f, PFE_PGN_CCVS1);
        const bool grade = is_pgn(&c.f, PFE_PGN_SSI);
        const fault_t *ft = (speed || grade) ? fault_at(speed ? INPUT_SPEED : INPUT_GRADE, c.t_us - t0)
                                             : NULL;
        if (ft != NULL) {
            if (ft->kind == FAULT_SILENT) {
                dropped++;
                continue;
            }
            /* SPN 84 in bytes 2-3, SPN 3318 in bytes 1-2 (can_dbc/pfe.dbc). */
            const uint32_t lsb = speed ? 1U : 0U;
            c.f.data[lsb] = 0x00U;
            c.f.data[lsb + 1U] = (ft->kind == FAULT_ERROR) ? 0xFEU : 0xFBU;
            changed++;
        }
        print_frame(out, &c);
    }
    if (fclose(out) != 0) {
        fprintf(stderr, "pfe_faults: cannot write %s: %s\n", out_path, strerror(errno));
        return 2;
    }
    fprintf(stderr, "pfe_faults: %zu frames in, %u dropped, %u changed\n", g_n, dropped, changed);
    return 0;
}

/* A module's output frame: LFE1, PlatoonFuel or Status, decoded. */
static bool module_frame(const cap_t *c, uint8_t sa)
{
    return ((c->f.id & PFE_CAN_EFF_FLAG) != 0U) && (pfe_j1939_source(c->f.id) == sa);
}

static bool rate_na(const cap_t *c, bool *is_rate)
{
    *is_rate = false;
    if (is_pgn(&c->f, PFE_PGN_LFE1)) {
        pfe_msg_lfe1_t m;
        *is_rate = pfe_codec_decode_lfe1(&c->f, &m) == PFE_OK;
        return m.fuel_rate_nl_s.state != PFE_SIG_VALID;
    }
    if (is_pgn(&c->f, PFE_PGN_OWN_FUEL)) {
        pfe_msg_own_fuel_t m;
        *is_rate = pfe_codec_decode_own_fuel(&c->f, &m) == PFE_OK;
        return m.fuel_rate_nl_s.state != PFE_SIG_VALID;
    }
    if (is_pgn(&c->f, PFE_PGN_PLATOON_FUEL)) {
        pfe_msg_platoon_fuel_t m;
        *is_rate = pfe_codec_decode_platoon_fuel(&c->f, &m) == PFE_OK;
        return m.fuel_rate_nl_s.state != PFE_SIG_VALID;
    }
    return false;
}

/* The state of the input signal a frame carries: SPN 84 or SPN 3318. */
static pfe_sig_state_t input_state(input_t in, const pfe_can_frame_t *f)
{
    if (in == INPUT_SPEED) {
        pfe_msg_ccvs1_t m;
        return (pfe_codec_decode_ccvs1(f, &m) == PFE_OK) ? m.speed_mm_s.state : PFE_SIG_ERROR;
    }
    pfe_msg_ssi_t m;
    return (pfe_codec_decode_ssi(f, &m) == PFE_OK) ? m.pitch_udeg.state : PFE_SIG_ERROR;
}

static const char *state_name(pfe_sig_state_t s)
{
    switch (s) {
    case PFE_SIG_VALID:
        return "valid";
    case PFE_SIG_NOT_AVAILABLE:
        return "not available";
    case PFE_SIG_ERROR:
        return "error";
    case PFE_SIG_OUT_OF_RANGE:
        return "out of range";
    default:
        return "?";
    }
}

static int judge_one(const fault_t *ft, uint64_t t0, uint8_t sa, uint64_t slack_us)
{
    const uint32_t pgn = input_pgn(ft->input);
    const uint64_t period_us = (ft->input == INPUT_SPEED) ? 100000U : 10000U;
    const uint64_t from = t0 + ((uint64_t)ft->from_ms * 1000U);
    const uint64_t to = t0 + ((uint64_t)ft->to_ms * 1000U);
    const pfe_sig_state_t want = (ft->kind == FAULT_SILENT)        ? PFE_SIG_NOT_AVAILABLE
                                 : (ft->kind == FAULT_ERROR)        ? PFE_SIG_ERROR
                                                                    : PFE_SIG_OUT_OF_RANGE;
    /* Onset and return from the input frames as captured, found by what
     * they carry (a gap, a bad value) near the fault's nominal time: over a
     * real bus the capture's clock drifts from the log's. */
    const uint64_t search_from = (from > (t0 + SEARCH_US)) ? (from - SEARCH_US) : t0;
    uint64_t onset = 0U, back = 0U, prev = 0U;
    bool have_onset = false, have_back = false, have_prev = false;
    /* A silence is the longest gap of the input near the fault's time, not
     * the first one: a loaded machine stalls the replay for tens of ms
     * before the fault's seconds. */
    for (size_t k = 0U; (k < g_n) && ((ft->kind == FAULT_SILENT) || !have_back); k++) {
        const cap_t *c = &g_cap[k];
        if (!is_pgn(&c->f, pgn) || module_frame(c, sa)) {
            continue;
        }
        const pfe_sig_state_t got = input_state(ft->input, &c->f);
        if (ft->kind == FAULT_SILENT) {
            if (have_prev && (prev >= search_from) && (prev < to) &&
                ((c->t_us - prev) > (2U * period_us)) &&
                (!have_back || ((c->t_us - prev) > (back - onset)))) {
                onset = prev;
                back = c->t_us;
                have_onset = true;
                have_back = true;
            }
            prev = c->t_us;
            have_prev = true;
        } else if (!have_onset) {
            if ((c->t_us >= search_from) && (c->t_us < to) && (got == want)) {
                onset = c->t_us;
                have_onset = true;
            }
        } else if (got == PFE_SIG_VALID) {
            back = c->t_us;
            have_back = true;
        }
    }
    if (!have_onset || !have_back) {
        printf("fault %-19s FAIL: the fault is not in the capture's inputs\n", ft->name);
        return 1;
    }
    const uint64_t deadline = onset + ((ft->kind == FAULT_SILENT) ? (3U * period_us) : 0U) + TICK_US;
    /* a silent slope sensor: the road is assumed flat, the estimate goes on */
    const bool flat = (ft->input == INPUT_GRADE) && (ft->kind == FAULT_SILENT);
    const uint32_t want_mode = flat ? PFE_MODE_DEGRADED : PFE_MODE_NO_ESTIMATE;
    uint32_t n_flat = 0U, n_flat_bad = 0U;
    int fail = 0;
    bool valid_before = false, seen_before = false;
    uint32_t n_na = 0U, n_not_na = 0U, n_status = 0U, n_status_bad = 0U;
    uint64_t first_na = 0U, recovered = 0U;
    bool have_first_na = false, have_recovered = false, status_after_ok = false, status_after_seen = false;
    for (size_t k = 0U; k < g_n; k++) {
        const cap_t *c = &g_cap[k];
        if (!module_frame(c, sa)) {
            continue;
        }
        bool is_rate = false;
        const bool na = rate_na(c, &is_rate);
        if (is_rate && is_pgn(&c->f, PFE_PGN_LFE1) && (c->t_us < onset)) {
            seen_before = true;
            valid_before = !na;
        }
        if (is_rate && na && (c->t_us >= onset) && (c->t_us < back) && !have_first_na) {
            first_na = c->t_us;
            have_first_na = true;
        }
        const bool in_window = (c->t_us > (deadline + slack_us)) && (c->t_us < back);
        if (is_rate && in_window) {
            if (na) {
                n_na++;
            } else {
                n_not_na++;
            }
        }
        if (is_pgn(&c->f, PFE_PGN_STATUS)) {
            pfe_msg_status_t st;
            if (pfe_codec_decode_status(&c->f, &st) != PFE_OK) {
                continue;
            }
            const pfe_sig_state_t got = (ft->input == INPUT_SPEED) ? st.speed_input : st.grade_input;
            if (in_window) {
                n_status++;
                if ((got != want) || (st.mode.state != PFE_SIG_VALID) ||
                    (st.mode.value != want_mode)) {
                    n_status_bad++;
                    printf("fault %-19s   status at +%.3f s: input %s, mode %u\n", ft->name,
                           (double)(c->t_us - t0) / 1e6, state_name(got), (unsigned)st.mode.value);
                }
            }
            if (have_recovered && !status_after_seen && (c->t_us >= recovered)) {
                status_after_seen = true;
                status_after_ok = got == PFE_SIG_VALID;
            }
        }
        if (flat && in_window && is_pgn(&c->f, PFE_PGN_INPUT_STATUS)) {
            pfe_msg_input_status_t is;
            n_flat++;
            if ((pfe_codec_decode_input_status(&c->f, &is) != PFE_OK) ||
                (is.grade_source.state != PFE_SIG_VALID) ||
                (is.grade_source.value != PFE_GRADE_SOURCE_ASSUMED_FLAT)) {
                n_flat_bad++;
            }
        }
        if (is_rate && is_pgn(&c->f, PFE_PGN_LFE1) && !na && (c->t_us >= back) && !have_recovered) {
            recovered = c->t_us;
            have_recovered = true;
        }
    }
    printf("fault %-19s at %6.3f s: onset %6.3f s, deadline %6.3f s, first not available %6.3f s; "
           "%u rates not available, %u available after the deadline; %u status frames say %s; ",
           ft->name, (double)(from - t0) / 1e6, (double)(onset - t0) / 1e6,
           (double)(deadline - t0) / 1e6, have_first_na ? (double)(first_na - t0) / 1e6 : -1.0,
           n_na, n_not_na, n_status - n_status_bad, state_name(want));
    if (have_recovered) {
        printf("valid again %.3f s after the input returned\n", (double)(recovered - back) / 1e6);
    } else {
        printf("never valid again\n");
    }
    if (!seen_before || !valid_before) {
        printf("fault %-19s FAIL: the output was not valid before the fault\n", ft->name);
        fail = 1;
    }
    if (flat) {
        printf("fault %-19s   road assumed flat: %u of %u input-status frames say so\n", ft->name,
               n_flat - n_flat_bad, n_flat);
        if ((n_na > 0U) || (n_not_na == 0U) || (n_flat == 0U) || (n_flat_bad > 0U)) {
            printf("fault %-19s FAIL: the estimate did not go on with the road assumed flat\n",
                   ft->name);
            fail = 1;
        }
    } else if ((n_na == 0U) || (n_not_na > 0U) || !have_first_na ||
               (first_na > (deadline + slack_us + 100000U))) {
        printf("fault %-19s FAIL: fuel rates not \"not available\" from the deadline on\n", ft->name);
        fail = 1;
    }
    if ((n_status == 0U) || (n_status_bad > 0U)) {
        printf("fault %-19s FAIL: status does not say why\n", ft->name);
        fail = 1;
    }
    if (!have_recovered || ((recovered - back) > RECOVERY_US) || !status_after_seen || !status_after_ok) {
        printf("fault %-19s FAIL: no recovery within %.1f s, or status not valid after it\n",
               ft->name, RECOVERY_US / 1e6);
        fail = 1;
    }
    return fail;
}

int main(int argc, char **argv)
{
    if (cli_help_asked(argc, argv)) {
        cli_help(k_manual);
        return 0;
    }
    if ((argc == 4) && (strcmp(argv[1], "inject") == 0)) {
        return inject(argv[2], argv[3]);
    }
    if ((argc < 3) || (strcmp(argv[1], "judge") != 0)) {
        cli_usage(stderr, k_manual, "pfe_faults");
        return 2;
    }
    unsigned long sa = 0x8CU, slack_ms = 0U;
    for (int i = 3; i < argc; i += 2) {
        char *end = NULL;
        unsigned long v = (i + 1 < argc) ? strtoul(argv[i + 1], &end, 0) : 0U;
        const bool ok = (i + 1 < argc) && (end != argv[i + 1]) && (*end == '\0');
        if (ok && (strcmp(argv[i], "--module-sa") == 0) && (v <= 253U)) {
            sa = v;
        } else if (ok && (strcmp(argv[i], "--slack-ms") == 0) && (v <= 1000U)) {
            slack_ms = v;
        } else {
            fprintf(stderr, "pfe_faults: bad option '%s'\n", argv[i]);
            return 2;
        }
    }
    if (load(argv[2]) != 0) {
        return 2;
    }
    /* The drive's first input frame is the faults' time origin. */
    uint64_t t0 = 0U;
    bool have_t0 = false;
    for (size_t k = 0U; (k < g_n) && !have_t0; k++) {
        if (is_pgn(&g_cap[k].f, PFE_PGN_CCVS1) || is_pgn(&g_cap[k].f, PFE_PGN_SSI)) {
            t0 = g_cap[k].t_us;
            have_t0 = true;
        }
    }
    if (!have_t0) {
        fprintf(stderr, "pfe_faults: %s: no CCVS1 or SSI frame\n", argv[2]);
        return 2;
    }
    int fail = 0;
    for (size_t k = 0U; k < N_FAULTS; k++) {
        fail |= judge_one(&k_faults[k], t0, (uint8_t)sa, (uint64_t)slack_ms * 1000U);
    }
    printf("pfe_faults: %s\n", fail ? "FAIL" : "PASS");
    free(g_cap);
    return fail ? 1 : 0;
}
