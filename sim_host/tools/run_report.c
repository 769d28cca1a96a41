/*
 * run_report - judge a module from a capture of its bus: summary, CSV, plot,
 * and with --expect a verdict. The reference is sim_host/ref/bus_ref.h's;
 * how the capture is read: sim_host/lib/capture.h; docs/harness.md, "The
 * judge".
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>

#include "lib/cli_args.h"
#include "lib/plot.h"
#include "firmware/pfe_can.h"
#include "firmware/pfe_codec.h"
#include "ref/bus_ref.h"
#include "lib/capture.h"
#include "lib/disturb.h"
#include "hal/replay/hal_replay_ecu.h"
#include "ref/prediction_judge.h"
#include "lib/truck_cal.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: run_report CAPTURE.log [--module-sa SA] [--warmup-s S] [--rate-floor-l-h F]\n"
    "                  [--vehicles N] [--position P] [--gap-m D]\n"
    "                  [--out PREFIX] [--no-plot] [--gnuplot PROG] [--title TEXT]\n"
    "                  [--expect FILE] [--junit FILE] [--calib FILE]\n"
    "\n"
    "Judges a module from a capture of its bus: a summary, a CSV, a plot, and\n"
    "with --expect a verdict.\n"
    "\n"
    "CAPTURE: any log the host tools read (candump -L as pfe_record writes it,\n"
    "candump's printed output with -t a, z or A, Vector ASC) of one bus: the\n"
    "inputs (CCVS1, SSI, PFE_PlatoonConfig, PFE_GradePreview, anything\n"
    "not from the module) and the module's answers. It may start mid-drive and\n"
    "carry several senders and PGNs the module does not read. The reference is\n"
    "the double-precision estimator fed the capture's input frames as the module\n"
    "handles them (one sender per input, staleness, a flat road without SSI,\n"
    "platoon changes from PFE_PlatoonConfig). A silence of over 11 s (a logger\n"
    "whose clock jumps) is crossed in one jump, as pfe_ecu_replay crosses it.\n"
    "\n"
    "Options:\n"
    "  --module-sa SA      the module's source address (default 0x8C)\n"
    "  --warmup-s S        rates are judged from S seconds after the first input\n"
    "                      frame (default 5) to the last one\n"
    "  --rate-floor-l-h F  relative rate errors only where the reference is at\n"
    "                      least F L/h (default 5: below it the 0.05 L/h step of\n"
    "                      the signal alone is 1 %); absolute errors everywhere\n"
    "  --vehicles N, --position P, --gap-m D\n"
    "                      the platoon the module was started with, used until a\n"
    "                      PFE_PlatoonConfig says otherwise (default 1, 0, 10 m)\n"
    "  --calib FILE        the trucks' calibration the module ran with, for the\n"
    "                      reference too (default: the default calibration)\n"
    "  --out PREFIX        where the outputs go (default build/run/report;\n"
    "                      folders are created)\n"
    "  --no-plot           no gnuplot run\n"
    "  --gnuplot PROG      the gnuplot to run (default: gnuplot on PATH)\n"
    "  --title TEXT        the plot's title\n"
    "  --expect FILE       expected values (below); the exit status gives the verdict\n"
    "  --junit FILE        a JUnit XML report: one testcase per expectation\n"
    "  -h, --help          this help\n"
    "\n"
    "Compared: each fuel rate of the module (own truck: PFE_OwnFuel, else, in\n"
    "older captures, LFE1; the platoon: PFE_PlatoonFuel) with what the reference\n"
    "answers at an instant in the 5 ms before the frame (the module's tick phase\n"
    "is not in the capture); fuel used between the module's first and last\n"
    "totals (PFE_OwnFuel or HRLFC, PFE_PlatoonFuel) against the reference's\n"
    "between the same instants. Rates within 2 s after the capture shows the\n"
    "replay stalling or bunching (SSI more than 30 ms apart, CCVS1 outside 50 to\n"
    "150 ms) or after the module reports 5 or more lost ticks, and rates among\n"
    "the module's own bunched frames (LFE1 or PFE_OwnFuel outside 50 to 150 ms:\n"
    "a loop catching up after a stall) are left out and counted\n"
    "(rate_frames_disturbed_pct). PFE_OwnFuel and PFE_PlatoonFuel are judged at\n"
    "the tick that made each, by their 100 ms schedule (frame n of a run at the\n"
    "run's least late frame + n periods), not at its send time: a loop catching\n"
    "up sends right values late. When another node sends LFE1 (the\n"
    "engine's measured fuel rate), the module's own-truck rate is judged against\n"
    "it too (engine_rate_r, engine_fuel_ratio, overall and split by PFE_OwnFuel's\n"
    "ModelIdentified). The predictions (PFE_FuelPrediction) are judged against\n"
    "the fuel used over each one's horizon, where the capture drives to its end.\n"
    "\n"
    "Outputs: PREFIX.csv (time_s, speed_kmh, grade_pct, module_rate_l_h,\n"
    "ref_rate_l_h, module_total_l, ref_total_l; NA where there is no value),\n"
    "PREFIX.metrics (every quantity below, \"name value\"), PREFIX.prediction.csv\n"
    "(one row per prediction), PREFIX.gp and, through gnuplot, PREFIX.png (speed,\n"
    "grade, fuel rate, fuel used, and the predictions with their bounds; a panel\n"
    "with nothing to plot says so).\n"
    "\n"
    "--expect FILE: one expectation per line, '#' starts a comment:\n"
    "    NAME VALUE TOL   |measured - VALUE| <= TOL; TOL absolute, or with '%' a\n"
    "                     percentage of VALUE (total_fuel_l 1.090 1%)\n"
    "    NAME LIMIT       measured <= LIMIT (max_rate_error_pct 1.0)\n"
    "    NAME <= LIMIT    the same\n"
    "    NAME >= LIMIT    measured >= LIMIT (lfe1_frames >= 1140)\n"
    "A quantity that could not be measured fails its expectation.\n"
    "\n"
    "Exit status: 0 (no --expect, or every expectation met), 1 (an expectation\n"
    "not met), 2 (bad arguments, bad capture or expectation file, a file that\n"
    "cannot be written, gnuplot failed); messages name the file and line.\n"
    "\n"
    "Examples:\n"
    "  run_report build/run/capture.log --expect sim_host/data/logs/hilly_run.expect\n"
    "  run_report bench.log --module-sa 0x8D --calib mytruck.cal --out build/bench/report\n"
    "\n"
    "Quantities (PREFIX.metrics, and names for --expect):\n";

extern char **environ;

#define PI 3.14159265358979323846
#define L_S_TO_L_H 3600.0
#define SPEED_GAP_MAX_US 1000000U   /* longer without CCVS1: no distance counted */
/* A silence pfe_ecu_replay crosses in one jump (hal/replay/hal_replay_ecu.h). */
#define REPLAY_TAIL_US ((uint64_t)HAL_REPLAY_ECU_TAIL_US)
#define REPLAY_GAP_US ((uint64_t)HAL_REPLAY_ECU_GAP_US)
#define MAX_EXPECT 64U
#define PATH_MAX_LEN 4096U

/* ------------------------------------------------------------ quantities */

enum {
    Q_DURATION, Q_DISTANCE, Q_MEAN_SPEED, Q_INPUT_FRAMES, Q_MODULE_FRAMES, Q_LFE1, Q_LFE1_NA,
    Q_MAX_RATE_PCT, Q_MAX_RATE_LH, Q_MAX_PRATE_PCT, Q_MAX_PRATE_LH, Q_TOTAL, Q_REF_TOTAL,
    Q_TOTAL_ERR, Q_PTOTAL, Q_REF_PTOTAL, Q_PTOTAL_ERR, Q_OVERRUNS, Q_RX_DROPPED, Q_TX_DROPPED,
    Q_NORMAL_PCT, Q_CAPTURE_DROPPED, Q_INPUT_EVENTS, Q_DISTURBED_PCT, Q_GAPS,
    Q_ENGINE_FRAMES, Q_ENGINE_PAIRS, Q_ENGINE_R, Q_ENGINE_RATIO, Q_ENGINE_R_IDENT,
    Q_ENGINE_RATIO_IDENT, Q_ENGINE_R_CALIB, Q_ENGINE_RATIO_CALIB, Q_COUNT
};
#define Q_ALL (Q_COUNT + PJ_Q_COUNT) /* the prediction's after them (prediction_judge.h) */

typedef struct {
    const char *name;
    const char *what;
    double value;
    bool measured;
    const char *why_not;    /* when not measured */
} quantity_t;

static quantity_t g_q[Q_ALL] = {
    [Q_DURATION] = {"duration_s", "first to last input frame, s", 0.0, false, NULL},
    [Q_DISTANCE] = {"distance_km", "distance driven (CCVS1 speed over time), km", 0.0, false, NULL},
    [Q_MEAN_SPEED] = {"mean_speed_kmh", "distance / duration, km/h", 0.0, false, NULL},
    [Q_INPUT_FRAMES] = {"input_frames", "J1939 frames not from the module", 0.0, false, NULL},
    [Q_MODULE_FRAMES] = {"module_frames", "J1939 frames from the module", 0.0, false, NULL},
    [Q_LFE1] = {"lfe1_frames", "own-truck rate frames judged (PFE_OwnFuel, else the module's "
                "LFE1; after warm-up, up to the last input)", 0.0,
                false, NULL},
    [Q_LFE1_NA] = {"lfe1_not_available",
                   "of those, fuel rate not available where the reference has one", 0.0, false,
                   NULL},
    [Q_MAX_RATE_PCT] = {"max_rate_error_pct", "largest own-truck fuel rate error, % of reference", 0.0,
                        false, NULL},
    [Q_MAX_RATE_LH] = {"max_rate_error_l_h", "largest own-truck fuel rate error, L/h", 0.0, false,
                       NULL},
    [Q_MAX_PRATE_PCT] = {"max_platoon_rate_error_pct",
                         "largest PFE_PlatoonFuel rate error, % of reference", 0.0, false, NULL},
    [Q_MAX_PRATE_LH] = {"max_platoon_rate_error_l_h", "largest PFE_PlatoonFuel rate error, L/h",
                        0.0, false, NULL},
    [Q_TOTAL] = {"total_fuel_l", "own truck's fuel used by the module (PFE_OwnFuel, else HRLFC: "
                 "last - first), L",
                 0.0, false, NULL},
    [Q_REF_TOTAL] = {"ref_total_fuel_l", "the same by the reference, L", 0.0, false, NULL},
    [Q_TOTAL_ERR] = {"total_fuel_error_pct", "their difference, % of the reference", 0.0, false,
                     NULL},
    [Q_PTOTAL] = {"platoon_fuel_l", "platoon's fuel used by the module (PFE_PlatoonFuel), L", 0.0,
                  false, NULL},
    [Q_REF_PTOTAL] = {"ref_platoon_fuel_l", "the same by the reference, L", 0.0, false, NULL},
    [Q_PTOTAL_ERR] = {"platoon_fuel_error_pct", "their difference, % of the reference", 0.0, false,
                      NULL},
    [Q_OVERRUNS] = {"tick_overruns", "PFE_Status TickOverruns, last sent", 0.0, false, NULL},
    [Q_RX_DROPPED] = {"rx_frames_dropped", "PFE_Status RxFramesDropped, last sent", 0.0, false,
                      NULL},
    [Q_TX_DROPPED] = {"tx_frames_dropped", "PFE_Status TxFramesDropped, last sent", 0.0, false,
                      NULL},
    [Q_NORMAL_PCT] = {"normal_mode_pct", "PFE_Status frames judged with DegradedMode 0, %", 0.0,
                      false, NULL},
    [Q_CAPTURE_DROPPED] = {"capture_dropped", "frames the recorder reported dropped (DROPCOUNT)",
                           0.0, false, NULL},
    [Q_INPUT_EVENTS] = {"input_timing_events",
                        "SSI more than 30 ms apart, CCVS1 outside 50 to 150 ms apart", 0.0, false,
                        NULL},
    [Q_DISTURBED_PCT] = {"rate_frames_disturbed_pct",
                         "LFE1 and PFE_PlatoonFuel not judged: 2 s after an input timing event "
                         "or 5 lost module ticks, %", 0.0, false, NULL},
    [Q_GAPS] = {"gaps_skipped", "silences over 11 s the reference crossed in one jump "
                "(as pfe_ecu_replay does)", 0.0, false, NULL},
    [Q_ENGINE_FRAMES] = {"engine_lfe1_frames", "valid LFE1 frames from the engine (a node other "
                         "than the module)", 0.0, false, NULL},
    [Q_ENGINE_PAIRS] = {"engine_pairs", "module own-truck rates with an engine LFE1 at most "
                        "300 ms older", 0.0, false, NULL},
    [Q_ENGINE_R] = {"engine_rate_r", "Pearson r, module own-truck rate against the engine's LFE1",
                    0.0, false, NULL},
    [Q_ENGINE_RATIO] = {"engine_fuel_ratio", "module's integrated own fuel / the engine's over "
                        "the pairs", 0.0, false, NULL},
    [Q_ENGINE_R_IDENT] = {"engine_rate_r_identified", "the same r, PFE_OwnFuel ModelIdentified 1",
                          0.0, false, NULL},
    [Q_ENGINE_RATIO_IDENT] = {"engine_fuel_ratio_identified",
                              "the same ratio, PFE_OwnFuel ModelIdentified 1", 0.0, false, NULL},
    [Q_ENGINE_R_CALIB] = {"engine_rate_r_unidentified",
                          "the same r, ModelIdentified 0 (calibrated model)", 0.0, false, NULL},
    [Q_ENGINE_RATIO_CALIB] = {"engine_fuel_ratio_unidentified",
                              "the same ratio, ModelIdentified 0 (calibrated model)", 0.0, false,
                              NULL},
    PREDICTION_JUDGE_QUANTITIES(Q_COUNT),
};

static void set_q(int k, double v)
{
    g_q[k].value = v;
    g_q[k].measured = true;
}

static void unset_q(int k, const char *why)
{
    g_q[k].measured = false;
    g_q[k].why_not = why;
}

static int find_q(const char *name)
{
    for (int k = 0; k < Q_ALL; k++) {
        if (strcmp(g_q[k].name, name) == 0) {
            return k;
        }
    }
    return -1;
}

/* ------------------------------------------------------------ options */

typedef struct {
    const char *capture, *prefix, *expect, *junit, *gnuplot, *title;
    unsigned long module_sa, vehicles, position;
    double warmup_s, floor_l_h, gap_m;
    bool plot;
    const truck_cal_t *cal;            /* --calib, or NULL */
} options_t;

static void usage(FILE *f)
{
    /* --help: the whole manual with the quantities; a usage error: its synopsis. */
    if (f != stdout) {
        cli_usage(f, k_manual, "run_report");
        return;
    }
    cli_help(k_manual);
    for (int k = 0; k < Q_ALL; k++) {
        fprintf(f, "  %-28s %s\n", g_q[k].name, g_q[k].what);
    }
}

static int parse_args(int argc, char **argv, options_t *o)
{
    memset(o, 0, sizeof *o);
    o->prefix = "build/run/report";
    o->gnuplot = "gnuplot";
    o->module_sa = PFE_CODEC_DEFAULT_ADDRESS;
    o->vehicles = 1U;
    o->gap_m = 10.0;
    o->warmup_s = 5.0;
    o->floor_l_h = 5.0;
    o->plot = true;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if ((strcmp(a, "--help") == 0) || (strcmp(a, "-h") == 0)) {
            usage(stdout);
            exit(0);
        }
        if (strcmp(a, "--no-plot") == 0) {
            o->plot = false;
            continue;
        }
        if (a[0] != '-') {
            if (o->capture != NULL) {
                fprintf(stderr, "run_report: more than one capture ('%s', '%s')\n", o->capture, a);
                return 2;
            }
            o->capture = a;
            continue;
        }
        if (i + 1 >= argc) {
            fprintf(stderr, "run_report: option '%s' wants a value (or is unknown)\n", a);
            return 2;
        }
        const char *v = argv[++i];
        int bad = 0;
        if (strcmp(a, "--module-sa") == 0) {
            bad = cli_parse_ul(v, 0U, 253U, &o->module_sa);
        } else if (strcmp(a, "--warmup-s") == 0) {
            bad = cli_parse_double(v, 0.0, 1e6, &o->warmup_s);
        } else if (strcmp(a, "--rate-floor-l-h") == 0) {
            bad = cli_parse_double(v, 0.0, 3212.75, &o->floor_l_h);
        } else if (cli_platoon_option(a, v, &o->vehicles, &o->position, &o->gap_m, &bad)) {
            /* --vehicles, --position, --gap-m */
        } else if (strcmp(a, "--out") == 0) {
            o->prefix = v;
            bad = (v[0] == '\0') || (strlen(v) > PATH_MAX_LEN - 16U);
        } else if (strcmp(a, "--gnuplot") == 0) {
            o->gnuplot = v;
        } else if (strcmp(a, "--title") == 0) {
            o->title = v;
        } else if (strcmp(a, "--expect") == 0) {
            o->expect = v;
        } else if (strcmp(a, "--junit") == 0) {
            o->junit = v;
        } else {
            fprintf(stderr, "run_report: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        }
        if (bad) {
            fprintf(stderr, "run_report: bad value '%s' for %s\n", v, a);
            return 2;
        }
    }
    if (o->capture == NULL) {
        usage(stderr);
        return 2;
    }
    if (o->position >= o->vehicles) {
        fprintf(stderr, "run_report: --position %lu is not below --vehicles %lu\n", o->position,
                o->vehicles);
        return 2;
    }
    if ((o->junit != NULL) && (o->expect == NULL)) {
        fprintf(stderr, "run_report: --junit needs --expect (one testcase per expectation)\n");
        return 2;
    }
    return 0;
}

/* ------------------------------------------------------------ expectations */

typedef enum { EXP_NEAR, EXP_AT_MOST, EXP_AT_LEAST } exp_kind_t;

typedef struct {
    int q;
    exp_kind_t kind;
    double value, tol;      /* tol: absolute */
    bool tol_pct;
    double tol_given;
    unsigned long line;
} expect_t;

static int parse_number(const char *s, double *out)
{
    char *end = NULL;
    errno = 0;
    const double v = strtod(s, &end);
    if ((errno != 0) || (end == s) || (*end != '\0') || !isfinite(v)) {
        return -1;
    }
    for (const char *p = s; *p != '\0'; p++) {
        if ((*p == 'x') || (*p == 'X') || (*p == 'n') || (*p == 'N') || (*p == 'i') || (*p == 'I')) {
            return -1; /* hex, nan, inf */
        }
    }
    *out = v;
    return 0;
}

/* Returns the number read, or -1 after a message. */
static int load_expect(const char *path, expect_t *ex, unsigned max)
{
    FILE *in = fopen(path, "r");
    if (in == NULL) {
        fprintf(stderr, "run_report: %s: %s\n", path, strerror(errno));
        return -1;
    }
    char line[512];
    unsigned long lineno = 0U;
    unsigned n = 0U;
    int rc = 0;
    while (fgets(line, sizeof line, in) != NULL) {
        lineno++;
        const size_t len = strlen(line);
        if ((len == sizeof line - 1U) && (line[len - 1U] != '\n')) {
            fprintf(stderr, "run_report: %s:%lu: line longer than %zu characters\n", path, lineno,
                    sizeof line - 2U);
            rc = -1;
            break;
        }
        if (memchr(line, '\0', len) != NULL) {
            rc = -1;
            break;
        }
        char *hash = strchr(line, '#');
        if (hash != NULL) {
            *hash = '\0';
        }
        char *tok[5];
        int nt = 0;
        for (char *t = strtok(line, " \t\r\n"); t != NULL; t = strtok(NULL, " \t\r\n")) {
            if (nt == 5) {
                break;
            }
            tok[nt++] = t;
        }
        if (nt == 0) {
            continue;
        }
        expect_t e;
        memset(&e, 0, sizeof e);
        e.line = lineno;
        e.q = find_q(tok[0]);
        const char *bad = NULL;
        if (e.q < 0) {
            fprintf(stderr, "run_report: %s:%lu: unknown quantity '%s' (run_report --help lists them)\n",
                    path, lineno, tok[0]);
            rc = -1;
            break;
        }
        if (nt == 2) {
            e.kind = EXP_AT_MOST;
            bad = (parse_number(tok[1], &e.value) != 0) ? tok[1] : NULL;
        } else if ((nt == 3) && ((strcmp(tok[1], "<=") == 0) || (strcmp(tok[1], ">=") == 0))) {
            e.kind = (tok[1][0] == '<') ? EXP_AT_MOST : EXP_AT_LEAST;
            bad = (parse_number(tok[2], &e.value) != 0) ? tok[2] : NULL;
        } else if (nt == 3) {
            e.kind = EXP_NEAR;
            if (parse_number(tok[1], &e.value) != 0) {
                bad = tok[1];
            } else {
                const size_t tl = strlen(tok[2]);
                e.tol_pct = (tl > 1U) && (tok[2][tl - 1U] == '%');
                if (e.tol_pct) {
                    tok[2][tl - 1U] = '\0';
                }
                if ((parse_number(tok[2], &e.tol_given) != 0) || (e.tol_given < 0.0)) {
                    bad = tok[2];
                }
                e.tol = e.tol_pct ? (fabs(e.value) * e.tol_given / 100.0) : e.tol_given;
            }
        } else {
            fprintf(stderr, "run_report: %s:%lu: expected 'NAME VALUE TOLERANCE', 'NAME LIMIT', "
                            "'NAME <= LIMIT' or 'NAME >= LIMIT'\n", path, lineno);
            rc = -1;
            break;
        }
        if (bad != NULL) {
            fprintf(stderr, "run_report: %s:%lu: bad number '%s'\n", path, lineno, bad);
            rc = -1;
            break;
        }
        if (n == max) {
            fprintf(stderr, "run_report: %s:%lu: more than %u expectations\n", path, lineno, max);
            rc = -1;
            break;
        }
        ex[n++] = e;
    }
    if ((rc == 0) && ferror(in)) {
        fprintf(stderr, "run_report: %s: read error\n", path);
        rc = -1;
    }
    fclose(in);
    if ((rc == 0) && (n == 0U)) {
        fprintf(stderr, "run_report: %s: no expectations\n", path);
        rc = -1;
    }
    return (rc == 0) ? (int)n : -1;
}

/* Whether e holds; msg gets what was measured against what was expected. */
static bool judge(const expect_t *e, char *msg, size_t len)
{
    const quantity_t *q = &g_q[e->q];
    char want[96];
    if (e->kind == EXP_NEAR) {
        snprintf(want, sizeof want, "%g +- %g%s", e->value, e->tol_given, e->tol_pct ? " %" : "");
    } else {
        snprintf(want, sizeof want, "%s %g", (e->kind == EXP_AT_MOST) ? "<=" : ">=", e->value);
    }
    if (!q->measured) {
        snprintf(msg, len, "%s not measured (%s), expected %s", q->name,
                 (q->why_not != NULL) ? q->why_not : "no data", want);
        return false;
    }
    bool ok;
    if (e->kind == EXP_NEAR) {
        ok = fabs(q->value - e->value) <= e->tol * (1.0 + 1e-12);
    } else if (e->kind == EXP_AT_MOST) {
        ok = q->value <= e->value;
    } else {
        ok = q->value >= e->value;
    }
    snprintf(msg, len, "%s = %.6g, expected %s", q->name, q->value, want);
    return ok;
}

static void xml_escaped(FILE *f, const char *s)
{
    for (; *s != '\0'; s++) {
        switch (*s) {
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '&': fputs("&amp;", f); break;
        case '"': fputs("&quot;", f); break;
        case '\'': fputs("&apos;", f); break;
        default:
            if ((unsigned char)*s >= 0x20U || (*s == '\t')) {
                fputc(*s, f);
            }
        }
    }
}

static int write_junit(const char *path, const options_t *o, const expect_t *ex, unsigned n,
                       const bool *ok, char msgs[][256])
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        fprintf(stderr, "run_report: cannot write %s: %s\n", path, strerror(errno));
        return -1;
    }
    unsigned failures = 0U;
    for (unsigned k = 0U; k < n; k++) {
        failures += ok[k] ? 0U : 1U;
    }
    const char *base = strrchr(o->capture, '/');
    base = (base != NULL) ? base + 1 : o->capture;
    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    fprintf(f, "<testsuites tests=\"%u\" failures=\"%u\" errors=\"0\">\n", n, failures);
    fprintf(f, "  <testsuite name=\"run_report\" tests=\"%u\" failures=\"%u\" errors=\"0\" "
               "skipped=\"0\" time=\"0\">\n", n, failures);
    fprintf(f, "    <properties>\n      <property name=\"capture\" value=\"");
    xml_escaped(f, o->capture);
    fprintf(f, "\"/>\n      <property name=\"expect\" value=\"");
    xml_escaped(f, o->expect);
    fprintf(f, "\"/>\n    </properties>\n");
    for (unsigned k = 0U; k < n; k++) {
        fprintf(f, "    <testcase classname=\"run_report.");
        xml_escaped(f, base);
        fprintf(f, "\" name=\"%s\" time=\"0\">\n", g_q[ex[k].q].name);
        fprintf(f, "      <system-out>");
        xml_escaped(f, msgs[k]);
        fprintf(f, " (%s:%lu)</system-out>\n", o->expect, ex[k].line);
        if (!ok[k]) {
            fprintf(f, "      <failure type=\"expectation\" message=\"");
            xml_escaped(f, msgs[k]);
            fprintf(f, "\"/>\n");
        }
        fprintf(f, "    </testcase>\n");
    }
    fprintf(f, "  </testsuite>\n</testsuites>\n");
    if (ferror(f) | (fclose(f) != 0)) {
        fprintf(stderr, "run_report: cannot write %s\n", path);
        return -1;
    }
    return 0;
}

/* ------------------------------------------------------------ files */

/* mkdir -p of the folder part of path. */
static int make_parent(const char *path)
{
    char dir[PATH_MAX_LEN];
    if (strlen(path) >= sizeof dir) {
        return -1;
    }
    strcpy(dir, path);
    char *slash = strrchr(dir, '/');
    if (slash == NULL || slash == dir) {
        return 0;
    }
    *slash = '\0';
    for (char *p = dir + 1; ; p++) {
        if ((*p == '/') || (*p == '\0')) {
            const char c = *p;
            *p = '\0';
            if ((mkdir(dir, 0777) != 0) && (errno != EEXIST)) {
                fprintf(stderr, "run_report: cannot create folder %s: %s\n", dir, strerror(errno));
                return -1;
            }
            *p = c;
            if (c == '\0') {
                break;
            }
        }
    }
    return 0;
}

static FILE *open_out(const char *prefix, const char *ext, char *path, size_t len)
{
    snprintf(path, len, "%s%s", prefix, ext);
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        fprintf(stderr, "run_report: cannot write %s: %s\n", path, strerror(errno));
    }
    return f;
}

static int close_out(FILE *f, const char *path)
{
    if (ferror(f) | (fclose(f) != 0)) {
        fprintf(stderr, "run_report: cannot write %s\n", path);
        return -1;
    }
    return 0;
}

/* What the CSV holds, for a plot of what is there: values per column
 * (speed, grade, module rate, reference rate, module total, reference
 * total) and the span of its times. */
#define CSV_COLS 6
typedef struct {
    size_t have[CSV_COLS];
    size_t rows;
    double t_first, t_last;
} plot_data_t;

static void plot_note(plot_data_t *pd, double t_s, const bool have[CSV_COLS])
{
    if (pd->rows == 0U) {
        pd->t_first = t_s;
    }
    pd->t_last = t_s;
    pd->rows++;
    for (int c = 0; c < CSV_COLS; c++) {
        pd->have[c] += have[c] ? 1U : 0U;
    }
}

/* One panel: the curves whose column has values; a panel with none says
 * so instead (gnuplot stops on a plot with no point: "x range is
 * invalid"). */
static void plot_panel(FILE *f, const plot_data_t *pd, const char *ylabel, int n,
                       const int cols[], const char *const styles[], const char *none)
{
    fprintf(f, "set ylabel '%s'\n", ylabel);
    bool any = false;
    for (int k = 0; k < n; k++) {
        any = any || (pd->have[cols[k] - 2] > 0U);
    }
    if (!any) {
        fprintf(f, "set label 1 '%s' at graph 0.5, 0.5 center\nset yrange [0:1]\nunset key\n"
                   "plot 2 notitle\nunset label 1\nset autoscale y\nset key\n", none);
        return;
    }
    const char *sep = "plot ";
    for (int k = 0; k < n; k++) {
        if (pd->have[cols[k] - 2] > 0U) {
            fprintf(f, "%scsv skip 1 using 1:%d %s", sep, cols[k], styles[k]);
            sep = ", \\\n     ";
        }
    }
    fprintf(f, "\n");
}

static int write_plot_script(const char *gp_path, const char *csv_path, const char *png_path,
                             const char *title, const plot_data_t *pd,
                             const char *prediction_csv)
{
    FILE *f = fopen(gp_path, "w");
    if (f == NULL) {
        fprintf(stderr, "run_report: cannot write %s: %s\n", gp_path, strerror(errno));
        return -1;
    }
    fprintf(f, "# Written by run_report: gnuplot %s\n", gp_path);
    fprintf(f, "set terminal pngcairo noenhanced size 1100,%d font 'sans,10'\nset output ",
            (prediction_csv != NULL) ? 1750 : 1400);
    plot_quoted(f, png_path);
    fprintf(f, "\nset datafile separator ','\nset datafile missing 'NA'\n");
    fprintf(f, "set grid\nset key top right opaque box\nset lmargin 12\nset xlabel 'time (s)'\n");
    /* an explicit time range: one row, or none with values, is a range too */
    const double span = pd->t_last - pd->t_first;
    fprintf(f, "set xrange [%.3f:%.3f]\n", (span > 0.0) ? pd->t_first : (pd->t_first - 1.0),
            (span > 0.0) ? pd->t_last : (pd->t_last + 1.0));
    fprintf(f, "set multiplot layout %d,1 title ", (prediction_csv != NULL) ? 5 : 4);
    plot_quoted(f, title);
    fprintf(f, " font 'sans,12'\ncsv = ");
    plot_quoted(f, csv_path);
    fprintf(f, "\n");
    static const int speed[] = {2};
    static const char *const speed_st[] = {
        "with lines lw 1.5 lc rgb '#1f77b4' title 'CCVS1 wheel-based speed (input)'"};
    plot_panel(f, pd, "speed (km/h)", 1, speed, speed_st, "no valid CCVS1 speed in the capture");
    static const int grade[] = {3};
    static const char *const grade_st[] = {
        "with lines lw 1.2 lc rgb '#2ca02c' title 'SSI road grade, tan(pitch) (input)'"};
    plot_panel(f, pd, "grade (%)", 1, grade, grade_st, "no SSI pitch in the capture");
    static const int rate[] = {4, 5};
    static const char *const rate_st[] = {
        "with lines lw 2.5 lc rgb '#d62728' title 'module (own truck)'",
        "with lines lw 1.2 dt 2 lc rgb '#000000' title 'reference (double precision)'"};
    plot_panel(f, pd, "fuel rate (L/h)", 2, rate, rate_st,
               "no fuel rate: neither the module nor the reference has one");
    static const int used[] = {6, 7};
    static const char *const used_st[] = {
        "with steps lw 2.5 lc rgb '#d62728' title 'module (own truck total)'",
        "with lines lw 1.2 dt 2 lc rgb '#000000' title 'reference'"};
    plot_panel(f, pd, "fuel used (L)", 2, used, used_st, "no fuel total from the module");
    if (prediction_csv != NULL) {
        prediction_judge_plot(f, prediction_csv);
    }
    fprintf(f, "unset multiplot\n");
    return close_out(f, gp_path);
}

static int run_gnuplot(const char *prog, const char *gp_path)
{
    char *argv[3];
    argv[0] = (char *)(uintptr_t)prog;
    argv[1] = (char *)(uintptr_t)gp_path;
    argv[2] = NULL;
    pid_t pid;
    const int e = posix_spawnp(&pid, prog, NULL, NULL, argv, environ);
    if (e != 0) {
        fprintf(stderr, "run_report: cannot run %s: %s (plot script left at %s)\n", prog,
                strerror(e), gp_path);
        return -1;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) {
            fprintf(stderr, "run_report: waiting for %s: %s\n", prog, strerror(errno));
            return -1;
        }
    }
    if (!WIFEXITED(status) || (WEXITSTATUS(status) != 0)) {
        fprintf(stderr, "run_report: %s %s failed (%s %d)\n", prog, gp_path,
                WIFEXITED(status) ? "exit" : "signal",
                WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
        return -1;
    }
    return 0;
}

/* ------------------------------------------------------------ the analysis */

typedef struct {
    double worst_pct, worst_pct_t, worst_l_h, worst_l_h_t;
    size_t judged_pct;
} rate_err_t;

static void rate_compare(rate_err_t *e, double got_l_s, double ref_l_s, double t_s, double floor_l_h)
{
    const double err_l_h = fabs(got_l_s - ref_l_s) * L_S_TO_L_H;
    if (err_l_h > e->worst_l_h) {
        e->worst_l_h = err_l_h;
        e->worst_l_h_t = t_s;
    }
    if (ref_l_s * L_S_TO_L_H >= floor_l_h) {
        const double pct = 100.0 * fabs(got_l_s - ref_l_s) / ref_l_s;
        e->judged_pct++;
        if (pct > e->worst_pct) {
            e->worst_pct = pct;
            e->worst_pct_t = t_s;
        }
    }
}

typedef struct {
    bool have;
    double first, last;            /* L, module */
    double ref_first, ref_last;    /* L, reference at the same instants */
} totals_t;

static void totals_note(totals_t *t, double module_l, double ref_l)
{
    if (!t->have) {
        t->have = true;
        t->first = module_l;
        t->ref_first = ref_l;
    }
    t->last = module_l;
    t->ref_last = ref_l;
}

static void csv_value(FILE *f, bool have, double v, int decimals)
{
    if (have) {
        fprintf(f, ",%.*f", decimals, v);
    } else {
        fputs(",NA", f);
    }
}

/* One reference tick. */
typedef struct {
    uint64_t t_us;
    double own_used, platoon_used;  /* L */
} tick_t;

/* What a module ticking right after an input frame would answer. */
typedef struct {
    uint64_t t_us;                  /* the frame's time */
    double own_rate, platoon_rate;  /* L/s */
    bool valid;
} state_t;

typedef struct {
    tick_t *ticks;                  /* owned: the ticks some record asks for */
    size_t n_ticks;
    size_t gaps_skipped;            /* silences crossed in one jump */
    uint64_t ticks_skipped;
    state_t *states;                /* owned, one per input frame */
    size_t n_states;
    unsigned n_vehicles, position, reconfigurations;
    uint32_t gap_mm;
    bool configured;                /* by a PFE_PlatoonConfig */
} ref_run_t;

static int grow(void **p, size_t *room, size_t n, size_t size)
{
    if (n < *room) {
        return 0;
    }
    const size_t want = (*room == 0U) ? 16384U : (*room * 2U);
    void *q = realloc(*p, want * size);
    if (q == NULL) {
        return -1;
    }
    *p = q;
    *room = want;
    return 0;
}

/* Stores tick tt of ref when a capture record is waiting for it: the
 * first tick at or after each record's time is all the analysis asks for
 * (tick_at()), so the ticks kept are at most the records, whatever the
 * capture's time span. *pending: the first record not yet given a tick. */
static int keep_tick(const capture_t *cap, const bus_ref_t *ref, uint64_t tt, size_t *pending,
                     ref_run_t *run, size_t *room)
{
    if ((*pending >= cap->n) || (cap->recs[*pending].t_us > tt)) {
        return 0;
    }
    while ((*pending < cap->n) && (cap->recs[*pending].t_us <= tt)) {
        (*pending)++;
    }
    if (grow((void **)&run->ticks, room, run->n_ticks, sizeof(tick_t)) != 0) {
        return -1;
    }
    tick_t *t = &run->ticks[run->n_ticks++];
    t->t_us = tt;
    t->own_used = bus_ref_own_used(ref);
    t->platoon_used = bus_ref_platoon_used(ref);
    return 0;
}

/*
 * The reference over the capture's inputs (sim_host/ref/bus_ref.h): fuel used
 * at the first tick at or after each record, and after every input frame
 * what a module tick at that instant would answer (bus_ref_peek()), to
 * match the module's rates whatever its tick phase. Runs until 20 ms after
 * the capture's last frame. A silence of more than REPLAY_GAP_US
 * (HAL_REPLAY_ECU_TAIL_US + HAL_REPLAY_ECU_GAP_US) without any frame is
 * crossed in one jump to REPLAY_TAIL_US before the next frame, as
 * pfe_ecu_replay crosses it (a logger whose clock jumps by years must not
 * be ticked through): time and memory follow the frames, not the span.
 * Returns 0, or -1 out of memory.
 */
static int ref_run(const capture_t *cap, const options_t *o, ref_run_t *run)
{
    memset(run, 0, sizeof *run);
    static bus_ref_t ref;
    const pfe_vehicle_calib_t *at[PFE_MAX_VEHICLES] = {NULL};
    for (unsigned k = 0U; (o->cal != NULL) && (k < PFE_MAX_VEHICLES); k++) {
        at[k] = o->cal->at_set[k] ? &o->cal->at[k] : NULL;
    }
    if (bus_ref_init_vehicles(&ref, (unsigned)o->vehicles, (unsigned)o->position,
                              (uint32_t)lround(o->gap_m * 1000.0),
                              (o->cal != NULL) ? &o->cal->own : NULL, at) != 0) {
        return -1;
    }
    size_t room_t = 0U, room_s = 0U, pending = 0U;
    bool started = false;
    const uint64_t end_us = cap->recs[cap->n - 1U].t_us + (2U * BUS_REF_TICK_US);
    for (size_t k = 0U; k <= cap->n; k++) {
        const bool last = k == cap->n;
        const bool input = !last && (pfe_j1939_source(cap->recs[k].f.id) != o->module_sa);
        if (!started && !input) {
            if (last) {
                break;
            }
            continue; /* the module's frames before the first input */
        }
        const uint64_t t_us = last ? end_us : cap->recs[k].t_us;
        started = true;
        if (ref.started && (t_us > ref.next_tick_us + REPLAY_TAIL_US + REPLAY_GAP_US)) {
            run->ticks_skipped += bus_ref_skip_to(&ref, t_us - REPLAY_TAIL_US);
            run->gaps_skipped++;
        }
        while (bus_ref_due(&ref, t_us)) {
            const uint64_t tt = bus_ref_tick(&ref);
            if (keep_tick(cap, &ref, tt, &pending, run, &room_t) != 0) {
                return -1;
            }
        }
        if (!input) {
            continue; /* a module frame: the clock moved on to it */
        }
        bus_ref_input(&ref, &cap->recs[k].f, t_us);
        if (grow((void **)&run->states, &room_s, run->n_states, sizeof(state_t)) != 0) {
            return -1;
        }
        state_t *st = &run->states[run->n_states++];
        st->t_us = t_us;
        st->valid = bus_ref_peek(&ref, t_us, &st->own_rate, &st->platoon_rate);
    }
    run->n_vehicles = ref.n_vehicles;
    run->position = ref.position;
    run->gap_mm = ref.gap_mm;
    run->reconfigurations = ref.reconfigurations;
    run->configured = ref.reconfigurations > 0U;
    return 0;
}

/* Index of the first tick at or after t_us (n_ticks when none), from a
 * hint that only moves forward. */
static size_t tick_at(const ref_run_t *run, uint64_t t_us, size_t *hint)
{
    size_t k = *hint;
    while ((k < run->n_ticks) && (run->ticks[k].t_us < t_us)) {
        k++;
    }
    *hint = k;
    return k;
}

/* Index of the last state before t_us (n_states when none), from a hint. */
static size_t state_before(const ref_run_t *run, uint64_t t_us, size_t *hint)
{
    size_t k = *hint;
    while ((k < run->n_states) && (run->states[k].t_us < t_us)) {
        k++;
    }
    *hint = k;
    return (k == 0U) ? run->n_states : (k - 1U);
}

/* The module's tick came at most MODULE_LATENCY_US before its frame: of
 * the states a tick in that span could have seen, the valid rate nearest to
 * got. Returns false when none of them is valid (the reference has no
 * estimate there either). */
#define MODULE_LATENCY_US 5000U
static bool nearest_rate(const ref_run_t *run, size_t last, uint64_t t_us, bool platoon,
                         double got, double *best)
{
    double best_d = INFINITY;
    bool any = false;
    *best = 0.0;
    for (size_t k = last; k < run->n_states; k--) {
        const state_t *st = &run->states[k];
        const double r = platoon ? st->platoon_rate : st->own_rate;
        if (st->valid && (fabs(got - r) < best_d)) {
            best_d = fabs(got - r);
            *best = r;
            any = true;
        }
        if (st->t_us + MODULE_LATENCY_US <= t_us) {
            break; /* in effect from before the span: the oldest candidate */
        }
    }
    return any;
}

/*
 * The module's own-truck figures: since the module learned to leave LFE1
 * and HRLFC to the engine, its estimate goes out in PFE_OwnFuel (rate,
 * total, whether the model is identified); it sends LFE1 and HRLFC only
 * when no other node does. A capture holding any PFE_OwnFuel from the
 * module is judged on it, an older one on the module's LFE1 and HRLFC.
 * Frames from other addresses are never the module's, whatever their PGN
 * (another node's LFE1 is the engine's measured fuel rate).
 */
typedef enum { OWN_FROM_LFE1_HRLFC = 0, OWN_FROM_OWN_FUEL = 1 } own_source_t;

static own_source_t own_source(const capture_t *cap, uint8_t module_sa)
{
    for (size_t k = 0U; k < cap->n; k++) {
        const pfe_can_frame_t *f = &cap->recs[k].f;
        if ((pfe_j1939_source(f->id) == module_sa) && (pfe_j1939_pgn(f->id) == PFE_PGN_OWN_FUEL)) {
            return OWN_FROM_OWN_FUEL;
        }
    }
    return OWN_FROM_LFE1_HRLFC;
}

typedef struct {
    bool has_rate, rate_valid;      /* a rate frame; its rate valid */
    double rate_l_s;
    bool total_valid;
    double total_l;
    int identified;                 /* PFE_OwnFuel ModelIdentified: 1, 0, or -1 unknown */
} own_sample_t;

/* Whether f (already known to be the module's) carries an own-truck
 * figure from src; fills *out. */
static bool own_sample(const pfe_can_frame_t *f, own_source_t src, own_sample_t *out)
{
    memset(out, 0, sizeof *out);
    out->identified = -1;
    const uint32_t pgn = pfe_j1939_pgn(f->id);
    if ((src == OWN_FROM_OWN_FUEL) && (pgn == PFE_PGN_OWN_FUEL)) {
        pfe_msg_own_fuel_t m;
        if (pfe_codec_decode_own_fuel(f, &m) < 0) {
            return false;
        }
        out->has_rate = true;
        out->rate_valid = m.fuel_rate_nl_s.state == PFE_SIG_VALID;
        out->rate_l_s = m.fuel_rate_nl_s.value / 1e9;
        out->total_valid = m.fuel_used_ul.state == PFE_SIG_VALID;
        out->total_l = (double)m.fuel_used_ul.value / 1e6;
        if (m.model_identified.state == PFE_SIG_VALID) {
            out->identified = (m.model_identified.value != 0U) ? 1 : 0;
        }
        return true;
    }
    if ((src == OWN_FROM_LFE1_HRLFC) && (pgn == PFE_PGN_LFE1)) {
        pfe_msg_lfe1_t m;
        if (pfe_codec_decode_lfe1(f, &m) < 0) {
            return false;
        }
        out->has_rate = true;
        out->rate_valid = m.fuel_rate_nl_s.state == PFE_SIG_VALID;
        out->rate_l_s = m.fuel_rate_nl_s.value / 1e9;
        return true;
    }
    if ((src == OWN_FROM_LFE1_HRLFC) && (pgn == PFE_PGN_HRLFC)) {
        pfe_msg_hrlfc_t m;
        if (pfe_codec_decode_hrlfc(f, &m) < 0) {
            return false;
        }
        out->total_valid = m.total_fuel_ul.state == PFE_SIG_VALID;
        out->total_l = (double)m.total_fuel_ul.value / 1e6;
        return true;
    }
    return false;
}

/*
 * The module against the engine: when a node other than the module sends
 * LFE1, that is the engine's measured fuel rate (the first such sender
 * with a valid rate is used: a cab controller may send LFE1 not available).
 * Each valid own-truck rate of the module is paired with the engine's
 * latest valid rate if that is at most ENGINE_MAX_AGE_US old (three LFE1
 * periods). Over the pairs: Pearson's r, and the integrated ratio
 * sum(module * dt) / sum(engine * dt), dt the time since the module's
 * previous own-truck rate frame (0 for the first, and after more than
 * ENGINE_MAX_AGE_US). Split by PFE_OwnFuel ModelIdentified (calibrated
 * model, identified model); without PFE_OwnFuel the split is unknown.
 */
#define ENGINE_MAX_AGE_US 300000U
#define ENGINE_MIN_PAIRS 3U

typedef struct {
    size_t n;
    double sx, sy, sxx, syy, sxy;   /* x module, y engine, L/h */
    double ix, iy;                  /* integrals, L */
} pairs_t;

typedef struct {
    size_t engine_frames;
    bool have_engine;
    uint8_t engine_sa;
    pairs_t all, ident, calib;      /* calib: ModelIdentified 0 */
} engine_judge_t;

static void pairs_add(pairs_t *p, double x_l_h, double y_l_h, double dt_s)
{
    p->n++;
    p->sx += x_l_h;
    p->sy += y_l_h;
    p->sxx += x_l_h * x_l_h;
    p->syy += y_l_h * y_l_h;
    p->sxy += x_l_h * y_l_h;
    p->ix += x_l_h * dt_s / L_S_TO_L_H;
    p->iy += y_l_h * dt_s / L_S_TO_L_H;
}

static void engine_judge(const capture_t *cap, uint8_t module_sa, own_source_t src,
                         engine_judge_t *ej)
{
    memset(ej, 0, sizeof *ej);
    bool engine_now = false, have_prev = false;
    uint64_t engine_us = 0U, prev_us = 0U;
    double engine_l_h = 0.0;
    for (size_t k = 0U; k < cap->n; k++) {
        const capture_rec_t *r = &cap->recs[k];
        const uint8_t sa = pfe_j1939_source(r->f.id);
        if (sa != module_sa) {
            pfe_msg_lfe1_t m;
            if ((pfe_j1939_pgn(r->f.id) == PFE_PGN_LFE1) && (pfe_codec_decode_lfe1(&r->f, &m) >= 0) &&
                (m.fuel_rate_nl_s.state == PFE_SIG_VALID) && (!ej->have_engine || (sa == ej->engine_sa))) {
                ej->have_engine = true;
                ej->engine_sa = sa;
                ej->engine_frames++;
                engine_now = true;
                engine_us = r->t_us;
                engine_l_h = m.fuel_rate_nl_s.value / 1e9 * L_S_TO_L_H;
            }
            continue;
        }
        own_sample_t own;
        if (!own_sample(&r->f, src, &own) || !own.has_rate) {
            continue;
        }
        const double dt_s = (have_prev && ((r->t_us - prev_us) <= ENGINE_MAX_AGE_US))
                                ? (double)(r->t_us - prev_us) / 1e6
                                : 0.0;
        have_prev = true;
        prev_us = r->t_us;
        if (!own.rate_valid || !engine_now || ((r->t_us - engine_us) > ENGINE_MAX_AGE_US)) {
            continue;
        }
        const double x = own.rate_l_s * L_S_TO_L_H;
        pairs_add(&ej->all, x, engine_l_h, dt_s);
        if (own.identified == 1) {
            pairs_add(&ej->ident, x, engine_l_h, dt_s);
        } else if (own.identified == 0) {
            pairs_add(&ej->calib, x, engine_l_h, dt_s);
        }
    }
}

/* r and the ratio of one set of pairs into quantities qr and qratio. */
static void engine_quantities(const pairs_t *p, int qr, int qratio, const char *none)
{
    if (p->n < ENGINE_MIN_PAIRS) {
        unset_q(qr, none);
        unset_q(qratio, none);
        return;
    }
    const double n = (double)p->n;
    const double vx = p->sxx - (p->sx * p->sx / n);
    const double vy = p->syy - (p->sy * p->sy / n);
    if ((vx > 0.0) && (vy > 0.0)) {
        set_q(qr, (p->sxy - (p->sx * p->sy / n)) / sqrt(vx * vy));
    } else {
        unset_q(qr, "a constant rate: no correlation to measure");
    }
    if (p->iy > 0.0) {
        set_q(qratio, p->ix / p->iy);
    } else {
        unset_q(qratio, "the engine burned nothing over the pairs");
    }
}

static void engine_set_quantities(const engine_judge_t *ej, own_source_t src)
{
    set_q(Q_ENGINE_FRAMES, (double)ej->engine_frames);
    set_q(Q_ENGINE_PAIRS, (double)ej->all.n);
    const char *none = !ej->have_engine ? "no LFE1 from a node other than the module"
                                        : "fewer than 3 module rates with an engine rate beside them";
    engine_quantities(&ej->all, Q_ENGINE_R, Q_ENGINE_RATIO, none);
    if (src != OWN_FROM_OWN_FUEL) {
        const char *unknown = "no PFE_OwnFuel from the module: identification unknown";
        engine_quantities(&ej->ident, Q_ENGINE_R_IDENT, Q_ENGINE_RATIO_IDENT, unknown);
        engine_quantities(&ej->calib, Q_ENGINE_R_CALIB, Q_ENGINE_RATIO_CALIB, unknown);
        return;
    }
    engine_quantities(&ej->ident, Q_ENGINE_R_IDENT, Q_ENGINE_RATIO_IDENT,
                      !ej->have_engine ? none : "fewer than 3 pairs with the model identified");
    engine_quantities(&ej->calib, Q_ENGINE_R_CALIB, Q_ENGINE_RATIO_CALIB,
                      !ej->have_engine ? none : "fewer than 3 pairs before identification");
}

typedef struct {
    rate_err_t own, platoon;
    totals_t own_total, platoon_total;
    size_t status_judged, status_normal;
    size_t lfe1, lfe1_na;
    size_t rate_frames, rate_disturbed; /* LFE1 and PFE_PlatoonFuel after warm-up */
    size_t input_events, overrun_events, output_events;
    uint64_t late_max_us;   /* the latest a periodic frame went out after its tick */
    size_t csv_rows;
    plot_data_t plot;               /* what the CSV holds */
    size_t n_in, n_mod;
    uint64_t t_first_in, t_last_in;
    double distance_m;
    own_source_t own_src;           /* where the module's own-truck figures are */
} analysis_t;

/* Frames counted by sender (the module, the inputs) and the inputs' first
 * and last times. */
static void count_frames(const capture_t *cap, const options_t *o, analysis_t *a)
{
    for (size_t k = 0U; k < cap->n; k++) {
        const capture_rec_t *r = &cap->recs[k];
        if (pfe_j1939_source(r->f.id) == o->module_sa) {
            a->n_mod++;
        } else {
            if (a->n_in == 0U) {
                a->t_first_in = r->t_us;
            }
            a->t_last_in = r->t_us;
            a->n_in++;
        }
    }
}

/* The inputs as last seen in the capture, for the CSV and the distance. */
typedef struct {
    double speed_kmh, grade_pct, last_speed_m_s;
    bool have_speed, have_grade;
    uint64_t last_speed_us;
} inputs_t;

/* An input frame (not the module's): CCVS1's speed (and the distance
 * driven), SSI's grade. */
static void note_input(analysis_t *a, inputs_t *in, const capture_rec_t *r, uint32_t pgn)
{
    if (pgn == PFE_PGN_CCVS1) {
        pfe_msg_ccvs1_t m;
        if ((pfe_codec_decode_ccvs1(&r->f, &m) >= 0) && (m.speed_mm_s.state == PFE_SIG_VALID)) {
            const double v = m.speed_mm_s.value / 1000.0;
            if (in->have_speed && ((r->t_us - in->last_speed_us) <= SPEED_GAP_MAX_US)) {
                a->distance_m += in->last_speed_m_s * (double)(r->t_us - in->last_speed_us) / 1e6;
            }
            in->have_speed = true;
            in->last_speed_m_s = v;
            in->last_speed_us = r->t_us;
            in->speed_kmh = v * 3.6;
        }
    } else if (pgn == PFE_PGN_SSI) {
        pfe_msg_ssi_t m;
        if ((pfe_codec_decode_ssi(&r->f, &m) >= 0) && (m.pitch_udeg.state == PFE_SIG_VALID)) {
            in->grade_pct = 100.0 * tan(m.pitch_udeg.value / 1e6 * PI / 180.0);
            in->have_grade = true;
        }
    }
}

/* The reference at a module frame's instant. */
typedef struct {
    size_t st;              /* state a module tick just before it could have seen */
    bool have_tick;
    double own_used;        /* fuel used at the first tick at or after it, L */
    double platoon_used;
    bool judged;            /* after warm-up, within the inputs */
    double t_s;             /* since the first input */
    uint64_t t_us;          /* the instant: the frame's, or when the module made it */
} ref_at_t;

static void ref_at(const ref_run_t *run, const analysis_t *a, uint64_t warm_us, uint64_t t_us,
                   size_t *hint, size_t *shint, ref_at_t *ra)
{
    /* None before the first input: nothing used yet. */
    const bool started = t_us >= a->t_first_in;
    ra->t_us = t_us;
    ra->t_s = started ? (double)(t_us - a->t_first_in) / 1e6 : 0.0;
    const size_t at = started ? tick_at(run, t_us, hint) : 0U;
    ra->st = started ? state_before(run, t_us, shint) : run->n_states;
    ra->have_tick = started && (at < run->n_ticks) && (ra->st < run->n_states);
    const tick_t *tk = ra->have_tick ? &run->ticks[at] : NULL;
    ra->own_used = (tk != NULL) ? tk->own_used : 0.0;
    ra->platoon_used = (tk != NULL) ? tk->platoon_used : 0.0;
    ra->judged = ra->have_tick && (t_us >= warm_us) && (t_us <= a->t_last_in);
}

/* PFE_PlatoonFuel: its total, and its rate where the bus was calm. */
static void note_platoon_fuel(analysis_t *a, const options_t *o, const ref_run_t *run,
                              const disturb_t *dist, const capture_rec_t *r, const ref_at_t *ra)
{
    pfe_msg_platoon_fuel_t m;
    if (pfe_codec_decode_platoon_fuel(&r->f, &m) < 0) {
        return;
    }
    if (m.fuel_used_ul.state == PFE_SIG_VALID) {
        totals_note(&a->platoon_total, (double)m.fuel_used_ul.value / 1e6, ra->platoon_used);
    }
    const bool calm = ra->judged && !disturbed(dist, r->t_us);
    a->rate_frames += ra->judged ? 1U : 0U;
    a->rate_disturbed += (ra->judged && !calm) ? 1U : 0U;
    if (calm && (m.fuel_rate_nl_s.state == PFE_SIG_VALID)) {
        const double got = m.fuel_rate_nl_s.value / 1e9;
        double want = 0.0;
        (void)nearest_rate(run, ra->st, ra->t_us, true, got, &want);
        rate_compare(&a->platoon, got, want, ra->t_s, o->floor_l_h);
    }
}

/* PFE_DeviceStatus: the module's counters, and its mode once judged. */
static void note_status(analysis_t *a, const capture_rec_t *r, bool judged)
{
    pfe_msg_status_t m;
    if (pfe_codec_decode_status(&r->f, &m) < 0) {
        return;
    }
    if (m.tick_overruns.state == PFE_SIG_VALID) {
        set_q(Q_OVERRUNS, m.tick_overruns.value);
    }
    if (m.rx_frames_dropped.state == PFE_SIG_VALID) {
        set_q(Q_RX_DROPPED, m.rx_frames_dropped.value);
    }
    if (m.tx_frames_dropped.state == PFE_SIG_VALID) {
        set_q(Q_TX_DROPPED, m.tx_frames_dropped.value);
    }
    if (judged) {
        a->status_judged++;
        a->status_normal += ((m.mode.state == PFE_SIG_VALID) && (m.mode.value == PFE_MODE_NORMAL)) ? 1U : 0U;
    }
}

/* The own truck's rate (PFE_OwnFuel, else LFE1): judged against the
 * reference, and a CSV row. */
static void note_own_rate(analysis_t *a, const options_t *o, const ref_run_t *run, const disturb_t *dist,
                          const inputs_t *in, const own_sample_t *own, const capture_rec_t *r,
                          const ref_at_t *ra, FILE *csv)
{
    const bool valid = own->rate_valid;
    const double got = own->rate_l_s;
    if (ra->judged) {
        /* Not available is right where the reference has no
         * estimate either; a rate is compared with 0 there. */
        const bool calm = !disturbed(dist, r->t_us);
        double want = 0.0;
        const bool ref_valid = ra->have_tick && nearest_rate(run, ra->st, ra->t_us, false, got, &want);
        a->lfe1++;
        a->rate_frames++;
        if (!calm) {
            a->rate_disturbed++;
        } else if (!valid) {
            a->lfe1_na += ref_valid ? 1U : 0U;
        } else {
            rate_compare(&a->own, got, want, ra->t_s, o->floor_l_h);
        }
    }
    if (ra->have_tick && (r->t_us <= a->t_last_in)) {
        const bool have[CSV_COLS] = {in->have_speed, in->have_grade, valid, run->states[ra->st].valid,
                                     a->own_total.have, a->own_total.have};
        fprintf(csv, "%.3f", ra->t_s);
        csv_value(csv, have[0], in->speed_kmh, 3);
        csv_value(csv, have[1], in->grade_pct, 4);
        csv_value(csv, have[2], got * L_S_TO_L_H, 2);
        csv_value(csv, have[3], run->states[ra->st].own_rate * L_S_TO_L_H, 3);
        csv_value(csv, have[4], a->own_total.last - a->own_total.first, 3);
        csv_value(csv, have[5], ra->own_used - a->own_total.ref_first, 5);
        fputc('\n', csv);
        a->csv_rows++;
        plot_note(&a->plot, ra->t_s, have);
    }
}

/* The module's frames against the reference run: quantities and CSV rows. */
static void analyse(const capture_t *cap, const options_t *o, const ref_run_t *run, FILE *csv,
                    analysis_t *a)
{
    memset(a, 0, sizeof *a);
    count_frames(cap, o, a);
    a->own_src = own_source(cap, (uint8_t)o->module_sa);
    const uint64_t warm_us = a->t_first_in + (uint64_t)llround(o->warmup_s * 1e6);
    static disturb_t dist;
    disturb_find(cap, (uint8_t)o->module_sa, &dist);
    a->input_events = dist.input_events;
    a->overrun_events = dist.overrun_events;
    a->output_events = dist.output_events;
    /* the module's periodic frames judged at the ticks that made them */
    uint64_t *made = malloc((cap->n + 1U) * sizeof *made);
    if ((made != NULL) && (disturb_made_times(cap, (uint8_t)o->module_sa, made, &a->late_max_us) != 0)) {
        free(made);
        made = NULL; /* out of memory: judged at the frames' own times */
    }
    inputs_t in = {0};
    size_t hint = 0U, shint = 0U;
    size_t made_hint[2] = {0U, 0U}, made_shint[2] = {0U, 0U}; /* PFE_OwnFuel, PFE_PlatoonFuel */
    fprintf(csv, "time_s,speed_kmh,grade_pct,module_rate_l_h,ref_rate_l_h,module_total_l,ref_total_l\n");
    for (size_t k = 0U; k < cap->n; k++) {
        const capture_rec_t *r = &cap->recs[k];
        const uint32_t pgn = pfe_j1939_pgn(r->f.id);
        if (pfe_j1939_source(r->f.id) != o->module_sa) {
            note_input(a, &in, r, pgn);
            continue;
        }
        ref_at_t ra;
        const int sched = (pgn == PFE_PGN_OWN_FUEL) ? 0 : ((pgn == PFE_PGN_PLATOON_FUEL) ? 1 : -1);
        if ((sched >= 0) && (made != NULL)) {
            ref_at(run, a, warm_us, made[k], &made_hint[sched], &made_shint[sched], &ra);
        } else {
            ref_at(run, a, warm_us, r->t_us, &hint, &shint, &ra);
        }
        /* the own truck's figures: PFE_OwnFuel, else LFE1 and HRLFC */
        own_sample_t own;
        if (own_sample(&r->f, a->own_src, &own) && own.total_valid) {
            totals_note(&a->own_total, own.total_l, ra.own_used);
        }
        if (pgn == PFE_PGN_PLATOON_FUEL) {
            note_platoon_fuel(a, o, run, &dist, r, &ra);
        } else if (pgn == PFE_PGN_STATUS) {
            note_status(a, r, ra.judged);
        } else if (own.has_rate) {
            note_own_rate(a, o, run, &dist, &in, &own, r, &ra, csv);
        }
    }
    disturb_free(&dist);
    free(made);
}

static void set_quantities(const analysis_t *a, const capture_t *cap, const ref_run_t *run)
{
    set_q(Q_GAPS, (double)run->gaps_skipped);
    set_q(Q_INPUT_FRAMES, (double)a->n_in);
    set_q(Q_MODULE_FRAMES, (double)a->n_mod);
    set_q(Q_CAPTURE_DROPPED, (double)cap->dropped);
    const double dur = (double)(a->t_last_in - a->t_first_in) / 1e6;
    set_q(Q_DURATION, dur);
    set_q(Q_DISTANCE, a->distance_m / 1000.0);
    if (dur > 0.0) {
        set_q(Q_MEAN_SPEED, a->distance_m / dur * 3.6);
    } else {
        unset_q(Q_MEAN_SPEED, "the inputs last no time");
    }
    set_q(Q_INPUT_EVENTS, (double)a->input_events);
    if (a->rate_frames > 0U) {
        set_q(Q_DISTURBED_PCT, 100.0 * (double)a->rate_disturbed / (double)a->rate_frames);
    } else {
        unset_q(Q_DISTURBED_PCT, "no own-truck rate (PFE_OwnFuel, LFE1) or PFE_PlatoonFuel frame after warm-up");
    }
    set_q(Q_LFE1, (double)a->lfe1);
    set_q(Q_LFE1_NA, (double)a->lfe1_na);
    if (a->lfe1 > a->lfe1_na) {
        set_q(Q_MAX_RATE_LH, a->own.worst_l_h);
    } else {
        unset_q(Q_MAX_RATE_LH, "no own-truck fuel rate judged");
    }
    if (a->own.judged_pct > 0U) {
        set_q(Q_MAX_RATE_PCT, a->own.worst_pct);
    } else {
        unset_q(Q_MAX_RATE_PCT, "no own-truck fuel rate judged where the reference is above the floor");
    }
    if (a->platoon.judged_pct > 0U) {
        set_q(Q_MAX_PRATE_PCT, a->platoon.worst_pct);
        set_q(Q_MAX_PRATE_LH, a->platoon.worst_l_h);
    } else {
        unset_q(Q_MAX_PRATE_PCT, "no PFE_PlatoonFuel rate judged");
        unset_q(Q_MAX_PRATE_LH, "no PFE_PlatoonFuel rate judged");
    }
    const struct {
        const totals_t *t;
        int m, r, e;
        const char *none;
    } tot[2] = {{&a->own_total, Q_TOTAL, Q_REF_TOTAL, Q_TOTAL_ERR,
                 "no own-truck total (PFE_OwnFuel, HRLFC) from the module"},
                {&a->platoon_total, Q_PTOTAL, Q_REF_PTOTAL, Q_PTOTAL_ERR,
                 "no PFE_PlatoonFuel total from the module"}};
    for (int k = 0; k < 2; k++) {
        if (!tot[k].t->have) {
            unset_q(tot[k].m, tot[k].none);
            unset_q(tot[k].r, tot[k].none);
            unset_q(tot[k].e, tot[k].none);
            continue;
        }
        const double m = tot[k].t->last - tot[k].t->first;
        const double r = tot[k].t->ref_last - tot[k].t->ref_first;
        set_q(tot[k].m, m);
        set_q(tot[k].r, r);
        if (r > 0.0) {
            set_q(tot[k].e, 100.0 * fabs(m - r) / r);
        } else {
            unset_q(tot[k].e, "the reference used no fuel between the first and last total");
        }
    }
    if (a->status_judged > 0U) {
        set_q(Q_NORMAL_PCT, 100.0 * (double)a->status_normal / (double)a->status_judged);
    } else {
        unset_q(Q_NORMAL_PCT, "no PFE_Status frame judged");
    }
    const char *no_status = "no PFE_Status frame from the module";
    if (!g_q[Q_OVERRUNS].measured) {
        unset_q(Q_OVERRUNS, no_status);
    }
    if (!g_q[Q_RX_DROPPED].measured) {
        unset_q(Q_RX_DROPPED, no_status);
    }
    if (!g_q[Q_TX_DROPPED].measured) {
        unset_q(Q_TX_DROPPED, no_status);
    }
}

/* "%.*f unit" or "n/a". */
static const char *fmt_q(int k, int decimals, const char *unit, char *buf, size_t len)
{
    if (!g_q[k].measured) {
        snprintf(buf, len, "n/a");
    } else {
        snprintf(buf, len, "%.*f%s%s", decimals, g_q[k].value, (unit[0] != '\0') ? " " : "", unit);
    }
    return buf;
}

static void engine_print(const engine_judge_t *ej)
{
    char b1[64], b2[64], b3[64], b4[64], b5[64], b6[64];
    if (!ej->have_engine) {
        printf("  engine's LFE1: none on the bus (no LFE1 from a node other than the module)\n");
        return;
    }
    printf("  against the engine's LFE1 (SA 0x%02X, %zu frames): %zu rates paired; r %s, "
           "integrated ratio %s; model identified: r %s, ratio %s (%zu); calibrated: r %s, "
           "ratio %s (%zu)\n", ej->engine_sa, ej->engine_frames, ej->all.n,
           fmt_q(Q_ENGINE_R, 4, "", b1, sizeof b1), fmt_q(Q_ENGINE_RATIO, 4, "", b2, sizeof b2),
           fmt_q(Q_ENGINE_R_IDENT, 4, "", b3, sizeof b3),
           fmt_q(Q_ENGINE_RATIO_IDENT, 4, "", b4, sizeof b4), ej->ident.n,
           fmt_q(Q_ENGINE_R_CALIB, 4, "", b5, sizeof b5),
           fmt_q(Q_ENGINE_RATIO_CALIB, 4, "", b6, sizeof b6), ej->calib.n);
}

static void print_summary(const options_t *o, const capture_t *cap, const analysis_t *a,
                          const ref_run_t *ref)
{
    char b1[64], b2[64], b3[64], b4[64];
    printf("run_report: %s: %zu J1939 frames, %zu inputs, %zu from the module (0x%02lX)",
           o->capture, cap->n, a->n_in, a->n_mod, o->module_sa);
    const size_t skipped = cap->skipped_standard + cap->skipped_remote + cap->skipped_fd +
                           cap->skipped_error;
    if (skipped > 0U) {
        printf("; %zu other frames skipped (%zu 11-bit, %zu remote, %zu FD, %zu error)", skipped,
               cap->skipped_standard, cap->skipped_remote, cap->skipped_fd, cap->skipped_error);
    }
    if (cap->dropped > 0U) {
        printf("; the recorder dropped %lu", cap->dropped);
    }
    printf("\n");
    if (ref->gaps_skipped > 0U) {
        printf("  %zu silence%s of over %.0f s crossed in one jump (%llu ticks, as pfe_ecu_replay "
               "skips them)\n", ref->gaps_skipped, (ref->gaps_skipped == 1U) ? "" : "s",
               (double)(REPLAY_TAIL_US + REPLAY_GAP_US) / 1e6, (unsigned long long)ref->ticks_skipped);
    }
    printf("  platoon %u truck%s, own position %u, gap %.2f m (%s)\n", ref->n_vehicles,
           (ref->n_vehicles == 1U) ? "" : "s", ref->position, ref->gap_mm / 1000.0,
           ref->configured ? "from PFE_PlatoonConfig" : "default: no PFE_PlatoonConfig");
    printf("\n");
    printf("  %-34s %14s %14s %10s\n", "", "module", "reference", "error");
    printf("  %-34s %14s\n", "distance", fmt_q(Q_DISTANCE, 3, "km", b1, sizeof b1));
    printf("  %-34s %14s\n", "duration", fmt_q(Q_DURATION, 2, "s", b1, sizeof b1));
    printf("  %-34s %14s\n", "mean speed", fmt_q(Q_MEAN_SPEED, 2, "km/h", b1, sizeof b1));
    const bool of = a->own_src == OWN_FROM_OWN_FUEL;
    printf("  %-34s %14s %14s %10s\n", of ? "own truck fuel used (PFE_OwnFuel)"
                                         : "own truck fuel used (HRLFC)",
           fmt_q(Q_TOTAL, 3, "L", b1, sizeof b1), fmt_q(Q_REF_TOTAL, 4, "L", b2, sizeof b2),
           fmt_q(Q_TOTAL_ERR, 3, "%", b3, sizeof b3));
    printf("  %-34s %14s %14s %10s\n", "platoon fuel used (PFE_PlatoonFuel)",
           fmt_q(Q_PTOTAL, 3, "L", b1, sizeof b1), fmt_q(Q_REF_PTOTAL, 4, "L", b2, sizeof b2),
           fmt_q(Q_PTOTAL_ERR, 3, "%", b3, sizeof b3));
    printf("  %-34s %29s %10s", of ? "largest own rate error (OwnFuel)" : "largest fuel rate error (LFE1)",
           fmt_q(Q_MAX_RATE_LH, 3, "L/h", b1, sizeof b1), fmt_q(Q_MAX_RATE_PCT, 3, "%", b2, sizeof b2));
    if (g_q[Q_MAX_RATE_PCT].measured) {
        printf("  at %.2f s", a->own.worst_pct_t);
    }
    printf("\n");
    printf("  %-34s %29s %10s\n", "largest platoon fuel rate error",
           fmt_q(Q_MAX_PRATE_LH, 3, "L/h", b1, sizeof b1), fmt_q(Q_MAX_PRATE_PCT, 3, "%", b2, sizeof b2));
    printf("\n");
    printf("  %s judged: %.0f (%.0f not available), from %.1f s after the first input to the "
           "last; relative errors where the reference is at least %.1f L/h (%zu frames)\n",
           of ? "PFE_OwnFuel" : "LFE1", g_q[Q_LFE1].value, g_q[Q_LFE1_NA].value, o->warmup_s, o->floor_l_h, a->own.judged_pct);
    printf("  rates not judged: %zu of %zu (%s), within %.0f s after %zu input timing events and "
           "%zu PFE_Status reports of %u or more lost ticks, and among %zu timing events of the "
           "module's own frames\n", a->rate_disturbed, a->rate_frames,
           fmt_q(Q_DISTURBED_PCT, 1, "%", b1, sizeof b1), DISTURB_RECOVERY_US / 1e6, a->input_events,
           a->overrun_events, DISTURB_LOST_TICKS_MIN, a->output_events);
    printf("  PFE_OwnFuel and PFE_PlatoonFuel judged at the ticks that made them (their 100 ms "
           "schedule): sent up to %.1f ms after them\n", (double)a->late_max_us / 1000.0);
    printf("  module status: tick overruns %s, rx dropped %s, tx dropped %s, normal mode %s\n",
           fmt_q(Q_OVERRUNS, 0, "", b1, sizeof b1), fmt_q(Q_RX_DROPPED, 0, "", b2, sizeof b2),
           fmt_q(Q_TX_DROPPED, 0, "", b3, sizeof b3), fmt_q(Q_NORMAL_PCT, 1, "%", b4, sizeof b4));
}

int main(int argc, char **argv)
{
    static options_t o;
    static truck_cal_t cal;
    bool have_cal = false;
    char cal_err[TRUCK_CAL_ERR_MAX];
    if (truck_cal_take_arg(&argc, argv, &cal, &have_cal, cal_err, sizeof cal_err) != 0) {
        fprintf(stderr, "run_report: %s\n", cal_err);
        return 2;
    }
    const int prc = parse_args(argc, argv, &o);
    if (prc != 0) {
        return prc;
    }
    o.cal = have_cal ? &cal : NULL;
    static expect_t ex[MAX_EXPECT];
    int n_ex = 0;
    if (o.expect != NULL) {
        n_ex = load_expect(o.expect, ex, MAX_EXPECT);
        if (n_ex < 0) {
            return 2;
        }
    }
    char err[512];
    capture_t cap;
    if (capture_load(o.capture, &cap, err, sizeof err) != 0) {
        fprintf(stderr, "run_report: %s\n", err);
        return 2;
    }
    size_t n_in = 0U;
    for (size_t k = 0U; k < cap.n; k++) {
        n_in += (pfe_j1939_source(cap.recs[k].f.id) != o.module_sa) ? 1U : 0U;
    }
    if (n_in == 0U) {
        fprintf(stderr, "run_report: %s: no input frames (none with a source address other than "
                        "the module's 0x%02lX)\n", o.capture, o.module_sa);
        capture_free(&cap);
        return 2;
    }
    static ref_run_t run;
    if (ref_run(&cap, &o, &run) != 0) {
        fprintf(stderr, "run_report: out of memory\n");
        capture_free(&cap);
        return 2;
    }
    char csv_path[PATH_MAX_LEN], gp_path[PATH_MAX_LEN], png_path[PATH_MAX_LEN], m_path[PATH_MAX_LEN];
    if (make_parent(o.prefix) != 0) {
        capture_free(&cap);
        return 2;
    }
    FILE *csv = open_out(o.prefix, ".csv", csv_path, sizeof csv_path);
    if (csv == NULL) {
        capture_free(&cap);
        return 2;
    }
    static analysis_t a;
    analyse(&cap, &o, &run, csv, &a);
    int rc = close_out(csv, csv_path);
    set_quantities(&a, &cap, &run);
    static engine_judge_t ej;
    engine_judge(&cap, (uint8_t)o.module_sa, a.own_src, &ej);
    engine_set_quantities(&ej, a.own_src);
    print_summary(&o, &cap, &a, &run);
    static pj_result_t pj;
    if (prediction_judge_run(&cap, (uint8_t)o.module_sa, (unsigned)o.vehicles, (unsigned)o.position,
                             (uint32_t)lround(o.gap_m * 1000.0), &pj) != 0) {
        fprintf(stderr, "run_report: out of memory\n");
        rc = -1;
    }
    for (int k = 0; k < PJ_Q_COUNT; k++) {
        double v;
        const char *why;
        if (prediction_judge_value(&pj, k, &v, &why)) {
            set_q(Q_COUNT + k, v);
        } else {
            unset_q(Q_COUNT + k, why);
        }
    }
    prediction_judge_print(&pj);
    char pj_path[PATH_MAX_LEN];
    snprintf(pj_path, sizeof pj_path, "%s.prediction.csv", o.prefix);
    rc |= prediction_judge_write_csv(&pj, pj_path);
    const bool pj_plot = pj.n_rows > 0U;
    prediction_judge_free(&pj);
    engine_print(&ej);
    capture_free(&cap);
    free(run.ticks);
    free(run.states);

    FILE *mf = open_out(o.prefix, ".metrics", m_path, sizeof m_path);
    if (mf == NULL) {
        return 2;
    }
    for (int k = 0; k < Q_ALL; k++) {
        if (g_q[k].measured) {
            fprintf(mf, "%s %.6g\n", g_q[k].name, g_q[k].value);
        } else {
            fprintf(mf, "%s NA # %s\n", g_q[k].name, g_q[k].why_not);
        }
    }
    rc |= close_out(mf, m_path);
    printf("\n  CSV:     %s\n  metrics: %s\n  predictions: %s\n", csv_path, m_path, pj_path);
    if (o.plot && (a.csv_rows == 0U)) {
        printf("  plot:    none, no own-truck rate frame (PFE_OwnFuel, LFE1) from the module to plot\n");
    } else if (o.plot) {
        snprintf(gp_path, sizeof gp_path, "%s.gp", o.prefix);
        snprintf(png_path, sizeof png_path, "%s.png", o.prefix);
        char title[512];
        const char *base = strrchr(o.capture, '/');
        snprintf(title, sizeof title, "%s: %.2f km, %.0f s; module (0x%02lX) against the reference",
                 (o.title != NULL) ? o.title : ((base != NULL) ? base + 1 : o.capture),
                 g_q[Q_DISTANCE].value, g_q[Q_DURATION].value, o.module_sa);
        if ((write_plot_script(gp_path, csv_path, png_path, title, &a.plot, pj_plot ? pj_path : NULL) != 0) ||
            (run_gnuplot(o.gnuplot, gp_path) != 0)) {
            rc = -1;
        } else {
            printf("  plot:    %s\n", png_path);
        }
    }
    if (rc != 0) {
        return 2;
    }
    if (n_ex == 0) {
        return 0;
    }
    static bool ok[MAX_EXPECT];
    static char msgs[MAX_EXPECT][256];
    unsigned passed = 0U;
    printf("\n");
    for (int k = 0; k < n_ex; k++) {
        ok[k] = judge(&ex[k], msgs[k], sizeof msgs[k]);
        passed += ok[k] ? 1U : 0U;
        printf("  %s  %s\n", ok[k] ? "pass" : "FAIL", msgs[k]);
    }
    if ((o.junit != NULL) &&
        ((make_parent(o.junit) != 0) ||
         (write_junit(o.junit, &o, ex, (unsigned)n_ex, ok, msgs) != 0))) {
        return 2;
    }
    const bool all = passed == (unsigned)n_ex;
    printf("run_report: verdict %s: %u of %d expectations met (%s)%s%s\n", all ? "PASS" : "FAIL",
           passed, n_ex, o.expect, (o.junit != NULL) ? "; JUnit report " : "",
           (o.junit != NULL) ? o.junit : "");
    return all ? 0 : 1;
}
