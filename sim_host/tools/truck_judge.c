/*
 * truck_judge - judges the module's record of a foreign truck's log
 * (truckgen replayed by pfe_ecu_replay --record): availability, hostile
 * frames, identification.
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lib/cli_args.h"
#include "lib/log/log.h"
#include "firmware/pfe_codec.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: truck_judge avail RECORD [--name NAME] [--module-sa SA] [--warmup-s S]\n"
    "                         [--min-pct P] [--grade-source N] [--min-module-lfe1 N]\n"
    "                         [--truth CSV [--max-fuel-err-pct E]]\n"
    "       truck_judge hostile CLEAN HOSTILE --bursts N [--name NAME] [--module-sa SA]\n"
    "                         [--expect conflicts|rejected [--frames F [--exact]]]\n"
    "       truck_judge same LOG_A LOG_B\n"
    "       truck_judge identify RECORD --truth CSV --from S --mass KG [--for S] [--name NAME]\n"
    "                         [--module-sa SA] [--max-mass-err-pct E] [--max-fuel-err-pct E]\n"
    "                         [--off]\n"
    "\n"
    "Judges the module's record of a foreign truck's log (a truckgen log replayed\n"
    "by pfe_ecu_replay --record). --module-sa is the module's source address\n"
    "(default 0x8C); --name names the figures in the bench: lines.\n"
    "\n"
    "same: two logs of one drive (truckgen's printed form and its -L form)\n"
    "hold the same frames at the same times from their first frame.\n"
    "\n"
    "avail: of the module's PFE_OwnFuel frames (PGN 0xFF05, every 100 ms, the\n"
    "LFE1 period) later than --warmup-s (default 10 s) after the record's first\n"
    "frame and not after the log's end (its last LFE1 or HRLFC from another\n"
    "node; the replay's last second, in which the inputs time out, is not the\n"
    "drive), the share whose OwnFuelRate is valid must be at least --min-pct\n"
    "(default 95); with --grade-source, every PFE_InputStatus after the\n"
    "warm-up must say that GradeSource (0 slope sensor, 1 altitude, 2 assumed\n"
    "flat); the module must never send LFE1 (HRLFC) while another node sends\n"
    "it: no module LFE1 within three LFE1 periods (300 ms) after another\n"
    "node's, no HRLFC within 3 s after another's; with --min-module-lfe1, it\n"
    "must have sent at least N LFE1 (the engine's stopped: the module's own\n"
    "estimate takes its place). With --truth (truckgen --truth: the true fuel\n"
    "used every 100 ms of log time, read against the record's time from its\n"
    "first frame), the module's own fuel used (PFE_OwnFuel OwnTotalFuelUsed)\n"
    "from the end of the warm-up to the log's end against the truth's over the\n"
    "same span, \"bench: foreign_NAME_fuel_err_pct X pct\"; with\n"
    "--max-fuel-err-pct, |X| must not exceed E. Prints the figures, the last\n"
    "PFE_Status counters, and \"bench: foreign_NAME_available_pct X pct\".\n"
    "\n"
    "hostile: HOSTILE is the record of CLEAN's log with hostile frames added\n"
    "(truckgen --hostile, N bursts). Each valid rate the module sent in\n"
    "HOSTILE (PFE_OwnFuel OwnFuelRate, LFE1 EngineFuelRate, PFE_PlatoonFuel\n"
    "FuelRate) must be the one it sent at the same instant in CLEAN, valid:\n"
    "a valid rate that differs or that CLEAN did not have is one computed from\n"
    "a hostile input, and at most N are allowed per PGN (one tick per burst).\n"
    "Rates that HOSTILE sends not available where CLEAN has them are counted\n"
    "(the price of rejecting). --expect conflicts (rejected): PFE_Status\n"
    "AddressConflicts (InputsRejected) at the end of HOSTILE must exceed\n"
    "CLEAN's; with --frames F (the hostile frames in the log), by at most F,\n"
    "and with --exact by F exactly (every spoofed or implausible frame\n"
    "counted; the counter holds at 250). Prints \"bench: hostile_NAME_bad_frames X frames\".\n"
    "\n"
    "identify: RECORD is the replay, with a calibration that is not the\n"
    "truck's (the default one), of a log whose engine LFE1 stops at --from S\n"
    "(truckgen --engine-fuel-stop-s S; seconds from the record's first frame);\n"
    "the truck's true mass is --mass KG. No other node's LFE1 with a value may\n"
    "come after S (else the log is not what it is said to be). At S, the\n"
    "module's last PFE_InputStatus must say MassSource 2 (identified) and\n"
    "IdentificationState 1 (converged), and its VehicleMass must be within\n"
    "--max-mass-err-pct (default 15) of KG; the module's own fuel used\n"
    "(PFE_OwnFuel OwnTotalFuelUsed) over the --for seconds (default 300) from\n"
    "S on, against the truth's (--truth, as for avail) over the same span, must\n"
    "be within --max-fuel-err-pct (default 10), and the record must cover the\n"
    "span. With --off, the contrast: the same drive replayed with no engine\n"
    "LFE1 at all (truckgen --engine-fuel-stop-s 0), so nothing to identify\n"
    "from; the figures are printed and the only checks are MassSource 0 (the\n"
    "calibration) and IdentificationState 0 (learning) at S. Prints when\n"
    "IdentificationState first said converged,\n"
    "\"bench: identify_mass_err_pct_NAME X pct\" and\n"
    "\"bench: identify_fuel_err_pct_NAME X pct\" (identify_off_... with --off).\n"
    "\n"
    "Exit status 0 when every check holds, 1 when one fails, 2 on bad arguments\n"
    "or an unreadable record.\n"
    "\n"
    "Examples:\n"
    "  truck_judge avail t12.bus --name t12 --truth truth.csv --max-fuel-err-pct 10\n"
    "  truck_judge hostile t12.bus t12_spoof.bus --bursts 10 --expect conflicts\n";

typedef struct {
    uint64_t t_us;
    uint32_t pgn;
    uint8_t sa;
    pfe_can_frame_t f;
} rec_t;

typedef struct {
    rec_t *r;
    size_t n, cap;
    uint64_t first_us;
    uint64_t last_us;          /* the last frame of the record */
    bool any;
} record_t;

static uint32_t pgn_of(uint32_t id)
{
    const uint32_t pf = (id >> 16) & 0xFFU;
    const uint32_t pgn = (id >> 8) & 0x3FFFFU;
    return (pf < 240U) ? (pgn & 0x3FF00U) : pgn;
}

static bool wanted(uint32_t pgn)
{
    return (pgn == PFE_PGN_OWN_FUEL) || (pgn == PFE_PGN_LFE1) || (pgn == PFE_PGN_HRLFC) ||
           (pgn == PFE_PGN_PLATOON_FUEL) || (pgn == PFE_PGN_STATUS) || (pgn == PFE_PGN_INPUT_STATUS);
}

static int load(const char *path, record_t *rec)
{
    memset(rec, 0, sizeof *rec);
    const int fd = open(path, O_RDONLY);
    if (fd < 0) {
        fprintf(stderr, "truck_judge: cannot read %s: %s\n", path, strerror(errno));
        return -1;
    }
    static canlog_reader_t rd;
    (void)canlog_open_fd(&rd, fd, path, CANLOG_FMT_AUTO, CANLOG_ON_ERROR_STOP);
    canlog_frame_t fr;
    int rc;
    while ((rc = canlog_next(&rd, &fr)) == 1) {
        if (!rec->any) {
            rec->first_us = fr.time_us;
            rec->any = true;
        }
        rec->last_us = fr.time_us;
        if (((fr.id & CANLOG_EFF_FLAG) == 0U) || fr.fd || ((fr.id & CANLOG_RTR_FLAG) != 0U) ||
            ((fr.id & CANLOG_ERR_FLAG) != 0U) || (fr.len > 8U)) {
            continue;
        }
        const uint32_t pgn = pgn_of(fr.id & CANLOG_EFF_MASK);
        if (!wanted(pgn)) {
            continue;
        }
        if (rec->n == rec->cap) {
            rec->cap = (rec->cap == 0U) ? 4096U : (rec->cap * 2U);
            rec_t *p = realloc(rec->r, rec->cap * sizeof *p);
            if (p == NULL) {
                fprintf(stderr, "truck_judge: out of memory\n");
                close(fd);
                return -1;
            }
            rec->r = p;
        }
        rec_t *x = &rec->r[rec->n++];
        x->t_us = fr.time_us;
        x->pgn = pgn;
        x->sa = (uint8_t)(fr.id & 0xFFU);
        memset(&x->f, 0, sizeof x->f);
        x->f.id = (fr.id & CANLOG_EFF_MASK) | PFE_CAN_EFF_FLAG;
        x->f.dlc = fr.len;
        memcpy(x->f.data, fr.data, fr.len);
    }
    close(fd);
    if (rc < 0) {
        fprintf(stderr, "truck_judge: %s\n", canlog_message(&rd));
        return -1;
    }
    if (!rec->any) {
        fprintf(stderr, "truck_judge: %s: no frame\n", path);
        return -1;
    }
    return 0;
}

/* A rate output of the module: valid, and its value (nL/s as decoded). */
static bool rate_of(const rec_t *x, uint32_t *value)
{
    int rc = PFE_EINVAL;
    pfe_sig_u32_t s = {0U, PFE_SIG_NOT_AVAILABLE};
    if (x->pgn == PFE_PGN_OWN_FUEL) {
        pfe_msg_own_fuel_t m;
        rc = pfe_codec_decode_own_fuel(&x->f, &m);
        s = m.fuel_rate_nl_s;
    } else if (x->pgn == PFE_PGN_LFE1) {
        pfe_msg_lfe1_t m;
        rc = pfe_codec_decode_lfe1(&x->f, &m);
        s = m.fuel_rate_nl_s;
    } else if (x->pgn == PFE_PGN_PLATOON_FUEL) {
        pfe_msg_platoon_fuel_t m;
        rc = pfe_codec_decode_platoon_fuel(&x->f, &m);
        s = m.fuel_rate_nl_s;
    }
    *value = s.value;
    return (rc == PFE_OK) && (s.state == PFE_SIG_VALID);
}

typedef struct {
    bool have;
    uint32_t rejected, conflicts;
} counters_t;

static counters_t last_status(const record_t *rec, uint8_t module_sa)
{
    counters_t c = {false, 0U, 0U};
    for (size_t k = 0U; k < rec->n; k++) {
        const rec_t *x = &rec->r[k];
        pfe_msg_status_t m;
        if ((x->pgn == PFE_PGN_STATUS) && (x->sa == module_sa) &&
            (pfe_codec_decode_status(&x->f, &m) == PFE_OK)) {
            c.have = true;
            c.rejected = m.inputs_rejected.value;
            c.conflicts = m.address_conflicts.value;
        }
    }
    return c;
}

/* Whether another node's LFE1 or HRLFC carries a value: a node that sends
 * the PGN with it "not available" (a cab controller) reports no fuel, and
 * the module does not stay off the PGN for it (can_dbc/pfe.dbc). */
static bool carries_value(const rec_t *x)
{
    if (x->pgn == PFE_PGN_LFE1) {
        pfe_msg_lfe1_t m;
        return (pfe_codec_decode_lfe1(&x->f, &m) == PFE_OK) &&
               (m.fuel_rate_nl_s.state != PFE_SIG_NOT_AVAILABLE);
    }
    pfe_msg_hrlfc_t h;
    return (pfe_codec_decode_hrlfc(&x->f, &h) == PFE_OK) &&
           (h.total_fuel_ul.state != PFE_SIG_NOT_AVAILABLE);
}

/* Module frames of pgn sent while another node's were on the bus with a
 * value: within window_us after one of theirs. */
static unsigned shadowing(const record_t *rec, uint8_t module_sa, uint32_t pgn, uint64_t window_us,
                          unsigned *theirs, unsigned *ours)
{
    bool seen = false;
    uint64_t last_other = 0U;
    unsigned bad = 0U;
    *theirs = 0U;
    *ours = 0U;
    for (size_t k = 0U; k < rec->n; k++) {
        const rec_t *x = &rec->r[k];
        if (x->pgn != pgn) {
            continue;
        }
        if (x->sa != module_sa) {
            if (carries_value(x)) {
                seen = true;
                last_other = x->t_us;
                (*theirs)++;
            }
            continue;
        }
        (*ours)++;
        if (seen && (x->t_us - last_other <= window_us)) {
            bad++;
        }
    }
    return bad;
}

/* The truth's fuel used (L) at t_s, linear between its 100 ms rows. */
static double truth_at(const double *t, const double *l, size_t n, double t_s)
{
    if (t_s <= t[0]) {
        return l[0];
    }
    for (size_t k = 1U; k < n; k++) {
        if (t_s <= t[k]) {
            return l[k - 1U] + ((l[k] - l[k - 1U]) * (t_s - t[k - 1U]) / (t[k] - t[k - 1U]));
        }
    }
    return l[n - 1U];
}

/* 0 and *err_pct, 1 when there is nothing to compare, 2 on a bad file. */
static int fuel_against_truth(const record_t *rec, uint8_t sa, uint64_t from_us, uint64_t to_us,
                              const char *path, const char *name, double *err_pct)
{
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        fprintf(stderr, "truck_judge: cannot read %s: %s\n", path, strerror(errno));
        return 2;
    }
    static double t[200000], l[200000];
    size_t n = 0U;
    char line[256];
    unsigned long lineno = 0U;
    while (fgets(line, sizeof line, f) != NULL) {
        lineno++;
        double a = 0.0, b = 0.0, c = 0.0, d = 0.0, e = 0.0, g = 0.0;
        if (lineno == 1U) {
            continue; /* header */
        }
        if ((sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf", &a, &b, &c, &d, &e, &g) != 6) ||
            (n == (sizeof t / sizeof t[0])) || ((n > 0U) && !(a > t[n - 1U]))) {
            fprintf(stderr, "truck_judge: %s:%lu: expected t_s,speed_kmh,grade_pct,force_n,"
                            "fuel_l_h,fuel_l with t_s increasing\n", path, lineno);
            fclose(f);
            return 2;
        }
        t[n] = a;
        l[n] = g;
        n++;
    }
    fclose(f);
    bool have = false;
    uint64_t t0 = 0U, t1 = 0U, u0 = 0U, u1 = 0U;
    for (size_t k = 0U; k < rec->n; k++) {
        const rec_t *x = &rec->r[k];
        pfe_msg_own_fuel_t m;
        if ((x->sa != sa) || (x->pgn != PFE_PGN_OWN_FUEL) || (x->t_us < from_us) ||
            (x->t_us > to_us) || (pfe_codec_decode_own_fuel(&x->f, &m) != PFE_OK) ||
            (m.fuel_used_ul.state != PFE_SIG_VALID)) {
            continue;
        }
        if (!have) {
            t0 = x->t_us;
            u0 = m.fuel_used_ul.value;
            have = true;
        }
        t1 = x->t_us;
        u1 = m.fuel_used_ul.value;
    }
    if (!have || (n < 2U) || (t1 <= t0)) {
        printf("truck_judge %s: no own fuel used to compare with the truth\n", name);
        return 1;
    }
    const double module_l = (double)(u1 - u0) / 1e6;
    const double truth_l = truth_at(t, l, n, (double)(t1 - rec->first_us) / 1e6) -
                           truth_at(t, l, n, (double)(t0 - rec->first_us) / 1e6);
    *err_pct = (truth_l > 0.0) ? (100.0 * (module_l - truth_l) / truth_l) : 0.0;
    printf("truck_judge %s: own fuel used from %.1f s to %.1f s: module %.3f L, truth %.3f L "
           "(%+.2f %%)\n", name, (double)(t0 - rec->first_us) / 1e6,
           (double)(t1 - rec->first_us) / 1e6, module_l, truth_l, *err_pct);
    return (truth_l > 0.0) ? 0 : 1;
}

static int avail(int argc, char **argv)
{
    const char *path = NULL, *name = "log";
    unsigned long module_sa = 0x8CU, grade_source = 99U, min_lfe1 = 0U;
    double warmup_s = 10.0, min_pct = 95.0, max_err_pct = -1.0;
    const char *truth_path = NULL;
    const cli_option_t opts[] = {
        {"--name", CLI_TEXT, 0.0, 0.0, &name, NULL},
        {"--module-sa", CLI_UL, 0.0, 253.0, &module_sa, NULL},
        {"--warmup-s", CLI_DOUBLE, 0.0, 3600.0, &warmup_s, NULL},
        {"--min-pct", CLI_DOUBLE, 0.0, 100.0, &min_pct, NULL},
        {"--grade-source", CLI_UL, 0.0, 3.0, &grade_source, NULL},
        {"--truth", CLI_TEXT, 0.0, 0.0, &truth_path, NULL},
        {"--max-fuel-err-pct", CLI_DOUBLE, 0.0, 1000.0, &max_err_pct, NULL},
        {"--min-module-lfe1", CLI_UL, 0.0, 10000000.0, &min_lfe1, NULL},
    };
    int np = 0;
    if (cli_parse_options("truck_judge avail", argc, argv, 2, opts, sizeof opts / sizeof opts[0],
                          &path, 1, &np) != 0) {
        return 2;
    }
    if (path == NULL) {
        fprintf(stderr, "truck_judge: avail needs a RECORD\n");
        return 2;
    }
    static record_t rec;
    if (load(path, &rec) != 0) {
        return 2;
    }
    const uint8_t sa = (uint8_t)module_sa;
    const uint64_t from_us = rec.first_us + (uint64_t)(warmup_s * 1e6);
    /* The replay runs on a second past the log (its inputs time out): the
     * drive ends with the last input frame, the last frame of another node
     * among those kept (LFE1, HRLFC from the engine). */
    uint64_t to_us = rec.first_us;
    for (size_t k = 0U; k < rec.n; k++) {
        to_us = (rec.r[k].sa != sa) ? rec.r[k].t_us : to_us;
    }
    unsigned n = 0U, valid = 0U, st_n = 0U, st_ok = 0U;
    unsigned grade_seen[4] = {0U, 0U, 0U, 0U};
    for (size_t k = 0U; k < rec.n; k++) {
        const rec_t *x = &rec.r[k];
        if ((x->sa != sa) || (x->t_us < from_us) || (x->t_us > to_us)) {
            continue;
        }
        uint32_t v = 0U;
        if (x->pgn == PFE_PGN_OWN_FUEL) {
            n++;
            valid += rate_of(x, &v) ? 1U : 0U;
        } else if (x->pgn == PFE_PGN_INPUT_STATUS) {
            pfe_msg_input_status_t m;
            if (pfe_codec_decode_input_status(&x->f, &m) == PFE_OK) {
                st_n++;
                const uint32_t gs = (m.grade_source.state == PFE_SIG_VALID) ? m.grade_source.value : 3U;
                grade_seen[(gs < 4U) ? gs : 3U]++;
                st_ok += (gs == grade_source) ? 1U : 0U;
            }
        }
    }
    int fail = 0;
    const double pct = (n > 0U) ? (100.0 * valid / n) : 0.0;
    printf("truck_judge %s: PFE_OwnFuel from %.0f s to the log's end: %u frames, %u with a valid rate: %.2f %% "
           "(at least %.1f %%)\n", name, warmup_s, n, valid, pct, min_pct);
    if ((n == 0U) || (pct < min_pct)) {
        printf("truck_judge %s: FAIL: estimate available in %.2f %% of the frames\n", name, pct);
        fail = 1;
    }
    printf("truck_judge %s: PFE_InputStatus GradeSource: slope sensor %u, altitude %u, assumed flat "
           "%u, none %u (of %u)\n", name, grade_seen[0], grade_seen[1], grade_seen[2], grade_seen[3],
           st_n);
    if ((grade_source < 4U) && ((st_n == 0U) || (st_ok != st_n))) {
        printf("truck_judge %s: FAIL: GradeSource %lu expected in every PFE_InputStatus\n", name,
               grade_source);
        fail = 1;
    }
    unsigned theirs = 0U, ours = 0U;
    const unsigned lfe1_bad = shadowing(&rec, sa, PFE_PGN_LFE1, 300000U, &theirs, &ours);
    printf("truck_judge %s: LFE1: %u from other nodes, %u from the module, %u of them while another "
           "node sent LFE1\n", name, theirs, ours, lfe1_bad);
    if (ours < min_lfe1) {
        printf("truck_judge %s: FAIL: the module sent %u LFE1, at least %lu expected once the engine's "
               "stopped\n", name, ours, min_lfe1);
        fail = 1;
    }
    const unsigned hr_bad = shadowing(&rec, sa, PFE_PGN_HRLFC, 3000000U, &theirs, &ours);
    printf("truck_judge %s: HRLFC: %u from other nodes, %u from the module, %u of them while another "
           "node sent HRLFC\n", name, theirs, ours, hr_bad);
    if ((lfe1_bad > 0U) || (hr_bad > 0U)) {
        printf("truck_judge %s: FAIL: the module shadowed the engine's fuel PGNs\n", name);
        fail = 1;
    }
    if (truth_path != NULL) {
        double err_pct = 0.0;
        const int trc = fuel_against_truth(&rec, sa, from_us, to_us, truth_path, name, &err_pct);
        if (trc == 2) {
            return 2;
        }
        printf("bench: foreign_%s_fuel_err_pct %.2f pct\n", name, err_pct);
        if ((trc != 0) || ((max_err_pct >= 0.0) && (fabs(err_pct) > max_err_pct))) {
            printf("truck_judge %s: FAIL: own fuel used %.2f %% off the truth (at most %.1f %%)\n",
                   name, err_pct, max_err_pct);
            fail = 1;
        }
    }
    const counters_t c = last_status(&rec, sa);
    printf("truck_judge %s: last PFE_Status: InputsRejected %lu, AddressConflicts %lu%s\n", name,
           (unsigned long)c.rejected, (unsigned long)c.conflicts, c.have ? "" : " (none sent)");
    printf("bench: foreign_%s_available_pct %.2f pct\n", name, pct);
    if (!fail) {
        printf("truck_judge %s: pass\n", name);
    }
    return fail;
}

static const rec_t *find_at(const record_t *rec, size_t *hint, uint64_t t_us, uint32_t pgn,
                            uint8_t sa)
{
    size_t k = *hint;
    while ((k < rec->n) && (rec->r[k].t_us < t_us)) {
        k++;
    }
    *hint = k;
    for (; (k < rec->n) && (rec->r[k].t_us == t_us); k++) {
        if ((rec->r[k].pgn == pgn) && (rec->r[k].sa == sa)) {
            return &rec->r[k];
        }
    }
    return NULL;
}

static int hostile(int argc, char **argv)
{
    const char *paths[2] = {NULL, NULL};
    const char *name = "log", *expect = NULL;
    unsigned long module_sa = 0x8CU, bursts = 0U, frames = 0U;
    int np = 0;
    bool have_bursts = false, have_frames = false, exact = false;
    const cli_option_t opts[] = {
        {"--exact", CLI_FLAG, 0.0, 0.0, &exact, NULL},
        {"--name", CLI_TEXT, 0.0, 0.0, &name, NULL},
        {"--module-sa", CLI_UL, 0.0, 253.0, &module_sa, NULL},
        {"--frames", CLI_UL, 1.0, 10000000.0, &frames, &have_frames},
        {"--bursts", CLI_UL, 1.0, 100000.0, &bursts, &have_bursts},
        {"--expect", CLI_TEXT, 0.0, 0.0, &expect, NULL},
    };
    if (cli_parse_options("truck_judge hostile", argc, argv, 2, opts, sizeof opts / sizeof opts[0],
                          paths, 2, &np) != 0) {
        return 2;
    }
    if ((expect != NULL) && (strcmp(expect, "conflicts") != 0) && (strcmp(expect, "rejected") != 0)) {
        fprintf(stderr, "truck_judge hostile: --expect takes conflicts or rejected (got '%s')\n",
                expect);
        return 2;
    }
    if ((np != 2) || !have_bursts || ((have_frames || exact) && (expect == NULL)) ||
        (exact && !have_frames)) {
        fprintf(stderr, "truck_judge: hostile needs CLEAN HOSTILE --bursts N, and --frames and "
                        "--exact go with --expect\n");
        return 2;
    }
    static record_t clean, host;
    if ((load(paths[0], &clean) != 0) || (load(paths[1], &host) != 0)) {
        return 2;
    }
    const uint8_t sa = (uint8_t)module_sa;
    static const uint32_t pgns[3] = {PFE_PGN_OWN_FUEL, PFE_PGN_LFE1, PFE_PGN_PLATOON_FUEL};
    static const char *const names[3] = {"PFE_OwnFuel", "LFE1", "PFE_PlatoonFuel"};
    int fail = 0;
    unsigned total_bad = 0U;
    for (unsigned p = 0U; p < 3U; p++) {
        unsigned sent = 0U, valid = 0U, bad = 0U, lost = 0U;
        double worst_l_h = 0.0;
        size_t hint = 0U;
        for (size_t k = 0U; k < host.n; k++) {
            const rec_t *x = &host.r[k];
            if ((x->pgn != pgns[p]) || (x->sa != sa)) {
                continue;
            }
            sent++;
            uint32_t hv = 0U, cv = 0U;
            const bool h_ok = rate_of(x, &hv);
            const rec_t *y = find_at(&clean, &hint, x->t_us, pgns[p], sa);
            const bool c_ok = (y != NULL) && rate_of(y, &cv);
            valid += h_ok ? 1U : 0U;
            if (h_ok && (!c_ok || (hv != cv))) {
                if (bad < 5U) {
                    printf("truck_judge %s: %s at %.3f s: valid %.2f L/h, clean run %s%.2f L/h\n",
                           name, names[p], (double)(x->t_us - host.first_us) / 1e6,
                           hv * 3.6e-6, c_ok ? "" : "not available, ", cv * 3.6e-6);
                }
                bad++;
                const double d = fabs(((double)hv - (c_ok ? (double)cv : 0.0)) * 3.6e-6);
                worst_l_h = (d > worst_l_h) ? d : worst_l_h;
            }
            lost += (!h_ok && c_ok) ? 1U : 0U;
        }
        printf("truck_judge %s: %s: %u sent, %u valid, %u valid and unlike the clean run (at most "
               "%lu; worst by %.2f L/h), %u not available where the clean run had a rate\n",
               name, names[p], sent, valid, bad, bursts, worst_l_h, lost);
        total_bad += bad;
        if (bad > bursts) {
            printf("truck_judge %s: FAIL: %s rates computed from hostile input\n", name, names[p]);
            fail = 1;
        }
    }
    const counters_t cc = last_status(&clean, sa);
    const counters_t hc = last_status(&host, sa);
    printf("truck_judge %s: PFE_Status at the end: InputsRejected %lu (clean %lu), "
           "AddressConflicts %lu (clean %lu), %lu bursts\n",
           name, (unsigned long)hc.rejected, (unsigned long)cc.rejected, (unsigned long)hc.conflicts,
           (unsigned long)cc.conflicts, bursts);
    if (expect != NULL) {
        const bool conflicts = strcmp(expect, "conflicts") == 0;
        const uint32_t before = conflicts ? cc.conflicts : cc.rejected;
        const uint32_t after = conflicts ? hc.conflicts : hc.rejected;
        const unsigned long rise = (after > before) ? (unsigned long)(after - before) : 0UL;
        /* the counter holds at PFE_STATUS_COUNTER_MAX */
        const unsigned long room = PFE_STATUS_COUNTER_MAX - before;
        const unsigned long want = (frames < room) ? frames : room;
        const bool ok = (rise > 0UL) && (!have_frames || (rise <= want)) && (!exact || (rise == want));
        printf("truck_judge %s: %s rose by %lu for %lu hostile frames%s\n", name,
               conflicts ? "AddressConflicts" : "InputsRejected", rise, frames,
               exact ? " (each one expected counted)" : "");
        if (!ok) {
            printf("truck_judge %s: FAIL: %s did not count the hostile frames\n", name,
                   conflicts ? "AddressConflicts" : "InputsRejected");
            fail = 1;
        }
    }
    printf("bench: hostile_%s_bad_frames %u frames\n", name, total_bad);
    printf("bench: hostile_%s_inputs_rejected %lu frames\n", name, (unsigned long)hc.rejected);
    printf("bench: hostile_%s_address_conflicts %lu frames\n", name, (unsigned long)hc.conflicts);
    if (!fail) {
        printf("truck_judge %s: pass\n", name);
    }
    return fail;
}

static int identify(int argc, char **argv)
{
    const char *path = NULL, *name = "log", *truth_path = NULL;
    unsigned long module_sa = 0x8CU;
    double from_s = -1.0, for_s = 300.0, mass_kg = 0.0, max_mass_pct = 15.0, max_fuel_pct = 10.0;
    bool off = false;
    const cli_option_t opts[] = {
        {"--off", CLI_FLAG, 0.0, 0.0, &off, NULL},
        {"--name", CLI_TEXT, 0.0, 0.0, &name, NULL},
        {"--module-sa", CLI_UL, 0.0, 253.0, &module_sa, NULL},
        {"--truth", CLI_TEXT, 0.0, 0.0, &truth_path, NULL},
        {"--from", CLI_DOUBLE, 0.0, 36000.0, &from_s, NULL},
        {"--for", CLI_DOUBLE, 1.0, 36000.0, &for_s, NULL},
        {"--mass", CLI_DOUBLE, 1000.0, 100000.0, &mass_kg, NULL},
        {"--max-mass-err-pct", CLI_DOUBLE, 0.0, 1000.0, &max_mass_pct, NULL},
        {"--max-fuel-err-pct", CLI_DOUBLE, 0.0, 1000.0, &max_fuel_pct, NULL},
    };
    int np = 0;
    if (cli_parse_options("truck_judge identify", argc, argv, 2, opts, sizeof opts / sizeof opts[0],
                          &path, 1, &np) != 0) {
        return 2;
    }
    if ((path == NULL) || (truth_path == NULL) || (from_s < 0.0) || (mass_kg <= 0.0)) {
        fprintf(stderr, "truck_judge: identify needs RECORD --truth CSV --from S --mass KG\n");
        return 2;
    }
    static record_t rec;
    if (load(path, &rec) != 0) {
        return 2;
    }
    const uint8_t sa = (uint8_t)module_sa;
    const uint64_t from_us = rec.first_us + (uint64_t)llround(from_s * 1e6);
    const uint64_t to_us = from_us + (uint64_t)llround(for_s * 1e6);
    const char *tag = off ? "identify_off" : "identify";
    int fail = 0;
    /* The state at the end of the identification phase, and when the
     * module first said converged. */
    bool have_st = false;
    double converged_s = -1.0;
    unsigned engine_after = 0U, engine_before = 0U;
    uint32_t st_source = 99U, st_ident = 99U, st_mass = 0U;
    bool st_ident_valid = false;
    for (size_t k = 0U; k < rec.n; k++) {
        const rec_t *x = &rec.r[k];
        if ((x->pgn == PFE_PGN_LFE1) && (x->sa != sa) && carries_value(x)) {
            engine_after += (x->t_us > from_us) ? 1U : 0U;
            engine_before += (x->t_us <= from_us) ? 1U : 0U;
        }
        pfe_msg_input_status_t m;
        if ((x->pgn != PFE_PGN_INPUT_STATUS) || (x->sa != sa) ||
            (pfe_codec_decode_input_status(&x->f, &m) != PFE_OK)) {
            continue;
        }
        const bool conv = (m.identification.state == PFE_SIG_VALID) && (m.identification.value == 1U);
        if (conv && (converged_s < 0.0)) {
            converged_s = (double)(x->t_us - rec.first_us) / 1e6;
        }
        if (x->t_us <= from_us) {
            have_st = true;
            st_source = (m.mass_source.state == PFE_SIG_VALID) ? m.mass_source.value : 99U;
            st_ident_valid = m.identification.state == PFE_SIG_VALID;
            st_ident = st_ident_valid ? m.identification.value : 99U;
            st_mass = (m.vehicle_mass_kg.state == PFE_SIG_VALID) ? m.vehicle_mass_kg.value : 0U;
        }
    }
    printf("truck_judge %s: engine LFE1 with a value: %u up to %.1f s, %u after it\n", name,
           engine_before, from_s, engine_after);
    if (engine_after > 0U) {
        printf("truck_judge %s: FAIL: the engine's LFE1 goes on after %.1f s\n", name, from_s);
        fail = 1;
    }
    if (!off && (engine_before == 0U)) {
        printf("truck_judge %s: FAIL: no engine LFE1 to identify from before %.1f s\n", name, from_s);
        fail = 1;
    }
    if (!have_st) {
        printf("truck_judge %s: FAIL: no PFE_InputStatus from the module before %.1f s\n", name, from_s);
        return 1;
    }
    const double mass_err = 100.0 * ((double)st_mass - mass_kg) / mass_kg;
    if (converged_s >= 0.0) {
        printf("truck_judge %s: IdentificationState first converged at %.1f s\n", name, converged_s);
    } else {
        printf("truck_judge %s: IdentificationState never converged\n", name);
    }
    printf("truck_judge %s: at %.1f s: MassSource %lu, IdentificationState %s%lu, VehicleMass %lu kg "
           "for %.0f kg (%+.2f %%)\n", name, from_s, (unsigned long)st_source,
           st_ident_valid ? "" : "not available ", st_ident_valid ? (unsigned long)st_ident : 0UL,
           (unsigned long)st_mass, mass_kg, mass_err);
    if (off) {
        if ((st_source != PFE_MASS_SOURCE_CALIBRATION) || (st_ident != 0U)) {
            printf("truck_judge %s: FAIL: MassSource 0 and IdentificationState 0 expected without "
                   "the engine's LFE1\n", name);
            fail = 1;
        }
    } else {
        if ((st_source != PFE_MASS_SOURCE_IDENTIFIED) || (st_ident != 1U)) {
            printf("truck_judge %s: FAIL: MassSource 2 (identified) and IdentificationState 1 "
                   "(converged) expected at %.1f s\n", name, from_s);
            fail = 1;
        }
        if (fabs(mass_err) > max_mass_pct) {
            printf("truck_judge %s: FAIL: identified mass %+.2f %% off (at most %.1f %%)\n", name,
                   mass_err, max_mass_pct);
            fail = 1;
        }
    }
    double fuel_err = 0.0;
    uint64_t last_own_us = 0U;
    for (size_t k = 0U; k < rec.n; k++) {
        if ((rec.r[k].sa == sa) && (rec.r[k].pgn == PFE_PGN_OWN_FUEL)) {
            last_own_us = rec.r[k].t_us;
        }
    }
    /* one LFE1 period of slack at the end */
    if (last_own_us + 100000U < to_us) {
        printf("truck_judge %s: FAIL: the record ends at %.1f s, before %.1f s\n", name,
               (double)(last_own_us - rec.first_us) / 1e6, from_s + for_s);
        fail = 1;
    }
    const int trc = fuel_against_truth(&rec, sa, from_us, to_us, truth_path, name, &fuel_err);
    if (trc == 2) {
        return 2;
    }
    if ((trc != 0) || (!off && (fabs(fuel_err) > max_fuel_pct))) {
        printf("truck_judge %s: FAIL: own fuel used over %.0f s %+.2f %% off the truth (at most "
               "%.1f %%)\n", name, for_s, fuel_err, max_fuel_pct);
        fail = 1;
    }
    printf("bench: %s_mass_err_pct_%s %.2f pct\n", tag, name, mass_err);
    printf("bench: %s_fuel_err_pct_%s %.2f pct\n", tag, name, fuel_err);
    if (!fail) {
        printf("truck_judge %s: pass\n", name);
    }
    return fail;
}

/* Two logs of one drive in two forms (candump printed -t z and -L): the
 * same frames, at the same times from their first frame. */
static int same(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "truck_judge: same needs two logs\n");
        return 2;
    }
    static canlog_reader_t ra, rb;
    const int fa = open(argv[2], O_RDONLY);
    const int fb = open(argv[3], O_RDONLY);
    if ((fa < 0) || (fb < 0)) {
        fprintf(stderr, "truck_judge: cannot read %s\n", (fa < 0) ? argv[2] : argv[3]);
        return 2;
    }
    (void)canlog_open_fd(&ra, fa, argv[2], CANLOG_FMT_AUTO, CANLOG_ON_ERROR_STOP);
    (void)canlog_open_fd(&rb, fb, argv[3], CANLOG_FMT_AUTO, CANLOG_ON_ERROR_STOP);
    canlog_frame_t a, b;
    uint64_t n = 0U, a0 = 0U, b0 = 0U;
    int status = 0;
    for (;;) {
        const int ka = canlog_next(&ra, &a);
        const int kb = canlog_next(&rb, &b);
        if ((ka < 0) || (kb < 0)) {
            fprintf(stderr, "truck_judge: %s\n", canlog_message((ka < 0) ? &ra : &rb));
            status = 2;
            break;
        }
        if ((ka == 0) || (kb == 0)) {
            if (ka != kb) {
                printf("truck_judge same: %s ends after %llu frames, the other does not\n",
                       (ka == 0) ? argv[2] : argv[3], (unsigned long long)n);
                status = 1;
            }
            break;
        }
        if (n == 0U) {
            a0 = a.time_us;
            b0 = b.time_us;
        }
        n++;
        if ((a.id != b.id) || (a.len != b.len) || (memcmp(a.data, b.data, a.len) != 0) ||
            ((a.time_us - a0) != (b.time_us - b0))) {
            printf("truck_judge same: frame %llu differs (lines %llu and %llu)\n",
                   (unsigned long long)n, (unsigned long long)a.line, (unsigned long long)b.line);
            status = 1;
            break;
        }
    }
    close(fa);
    close(fb);
    if (status == 0) {
        printf("truck_judge same: %llu frames, the same in both forms\n", (unsigned long long)n);
    }
    return status;
}

int main(int argc, char **argv)
{
    if (cli_help_asked(argc, argv)) {
        cli_help(k_manual);
        return 0;
    }
    if ((argc >= 2) && (strcmp(argv[1], "same") == 0)) {
        return same(argc, argv);
    }
    if ((argc >= 2) && (strcmp(argv[1], "avail") == 0)) {
        return avail(argc, argv);
    }
    if ((argc >= 2) && (strcmp(argv[1], "hostile") == 0)) {
        return hostile(argc, argv);
    }
    if ((argc >= 2) && (strcmp(argv[1], "identify") == 0)) {
        return identify(argc, argv);
    }
    cli_usage(stderr, k_manual, "truck_judge");
    return 2;
}
