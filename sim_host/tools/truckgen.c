/*
 * truckgen - a foreign truck's J1939 bus as a bench records it (another mass,
 * two senders of the inputs, the engine's own fuel rate, unread PGNs, hostile
 * variants), to test the module against. Randomness from SplitMix64 streams,
 * so a log is the same file on every machine.
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lib/cli_args.h"
#include "firmware/pfe_calib.h"
#include "firmware/pfe_codec.h"
#include "ref/drive_trace.h"
#include "ref/ref_model.h"
#include "lib/road_csv.h"
#include "lib/truck_cal.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: truckgen [--calib FILE] [--profile KMH:S,...] [--road FILE.csv] [--start-s S]\n"
    "                [--seed N] [--speed-noise-kmh SD] [--fuel-noise-pct P]\n"
    "                [--ssi] [--ssi-source SA] [--vds] [--vds-period-ms MS] [--alt-noise-m SD]\n"
    "                [--engine-fuel-stop-s S] [--hostile spoof|jump|random]\n"
    "                [--hostile-period-s S] [--module-sa SA] [--others N]\n"
    "                [--format printed|log] [--iface IF] [--truth CSV] [--out LOG]\n"
    "\n"
    "Writes a foreign truck's J1939 bus as a bench records it, to test the module\n"
    "against: a truck of another mass, two senders of the inputs, the engine's\n"
    "own fuel rate, hundreds of PGNs the module does not read, no address claims,\n"
    "starting mid-drive.\n"
    "\n"
    "The truck (--calib FILE: the own truck's calibration file;\n"
    "default: the default calibration) drives a speed profile (--profile): each KMH:S phase\n"
    "aims at KMH for S seconds, from standstill (default\n"
    "0:5,80:80,50:45,85:90,0:35,60:60,85:80,0:25: 0 to 80 km/h, cruise, slow to\n"
    "50, back to 85, a stop, 60, 85, a stop; 420 s). Driver: the acceleration\n"
    "asked for is (target - v) / 2 s within -1.2 .. +1.0 m/s^2 (-1 m/s^2 to a\n"
    "stop, and zero wheel force at standstill); the wheel force\n"
    "(m + mj) a + resistance (thesis eq. 3.7, the reference model, on the road\n"
    "of --road, default flat) is held within the truck's traction and power\n"
    "limit and its brake limit, and the speed follows (explicit Euler, 10 ms).\n"
    "Frames (every frame of the log written from --start-s on, default 15 s, in\n"
    "time order, with a few hundred microseconds of jitter):\n"
    "  - CCVS1 from the engine (SA 0x00) every 100 ms: the speed plus a normal\n"
    "    deviate of --speed-noise-kmh (default 0.3), quantised to SPN 84;\n"
    "  - CCVS1 from the cab controller (SA 0x31) every 100 ms, speed not\n"
    "    available; LFE1 from it, fuel rate not available;\n"
    "  - LFE1 from the engine every 100 ms (until --engine-fuel-stop-s of log\n"
    "    time, default never): the reference's fuel rate for the true truck\n"
    "    (zero, a fuel cut, at zero or negative wheel force)\n"
    "    times 1 + a normal deviate of --fuel-noise-pct (default 2) percent,\n"
    "    quantised to SPN 183's 0.05 L/h; HRLFC from the engine every 1 s,\n"
    "    its total fuel used (0.001 L, from 123456.000 L);\n"
    "  - with --ssi, SSI every 10 ms from --ssi-source (default 0x2A): the\n"
    "    road's pitch; without, no SSI at all;\n"
    "  - with --vds, VDS every --vds-period-ms (default 1000, J1939-71's rate\n"
    "    for PGN 65256) from SA 0x1C: altitude (road profile from\n"
    "    400 m) plus a normal deviate of --alt-noise-m (default 1.5 m), GNSS\n"
    "    speed, bearing 90 deg;\n"
    "  - --others (default 220) PGNs the module does not read from 14 senders:\n"
    "    EEC1, EEC2, ETC1, TSC1 (to the engine), EBC1, ET1, EFL/P1, AMB, DM1 of\n"
    "    several ECUs, then PDU2 PGNs of 0xFC00 .. 0xFEFF (less those the\n"
    "    module reads) at 0.1 to 5 s (most at 1 s), with junk payloads;\n"
    "  - no address claim, no request.\n"
    "Hostile variants (--hostile), every --hostile-period-s (default 40 s) from\n"
    "30 s of log time, extra frames on top of the same log (every other frame\n"
    "is that of the log without --hostile, byte for byte), 50 ms after a\n"
    "regular CCVS1:\n"
    "  spoof   CCVS1 from --module-sa (default 0x8C) at 200 km/h, every 100 ms\n"
    "          for 2 s (20 frames);\n"
    "  jump    one CCVS1 from the engine at 250 km/h, the next regular one\n"
    "          back at the true speed;\n"
    "  random  10 frames over 1 s from the senders in use: CCVS1 and LFE1 from\n"
    "          the engine, SSI from its sender (--ssi), 8 random bytes each.\n"
    "The number of bursts and of hostile frames is printed on standard error\n"
    "(\"truckgen: B hostile bursts, F hostile frames\").\n"
    "Output: candump's printed form, -t z (\"(000.011063)  can0  18FEF100\n"
    "[8]  FF 12 ...\"), or with --format log candump -L (\"(1700000015.011063)\n"
    "can0 18FEF100#FF12...\"); interface --iface (default can0). --truth writes\n"
    "one CSV line per 100 ms of log time: t_s, speed_kmh, grade_pct,\n"
    "force_n, fuel_l_h (the true rate before noise), fuel_l (true total).\n"
    "Randomness: SplitMix64 streams from --seed (default 1), so a log is the\n"
    "same file on every machine for the same options.\n"
    "Exit status 0; 1 when the output cannot be written; 2 on bad arguments.\n"
    "\n"
    "Examples:\n"
    "  truckgen --calib sim_host/data/trucks/truck12t.cal --truth truth.csv --out t12.txt\n"
    "  truckgen --calib sim_host/data/trucks/truck60t.cal --hostile spoof --out t60_spoof.txt\n";

#define TICK_US 10000U
#define T0_S 1700000000ULL
#define MAX_PHASES 32
#define MAX_OTHERS 400U
#define SA_ENGINE 0x00U
#define SA_CAB 0x31U
#define SA_GNSS 0x1CU
#define ALT0_M 400.0
#define HRLFC_START_L 123456.0

typedef struct {
    double kmh[MAX_PHASES], dur_s[MAX_PHASES];
    int n;
} profile_t;

typedef enum { HOSTILE_NONE = 0, HOSTILE_SPOOF, HOSTILE_JUMP, HOSTILE_RANDOM } hostile_t;

typedef struct {
    const char *calib_path, *road_path, *truth_path, *out_path, *ifname;
    profile_t profile;
    double start_s, speed_noise_kmh, fuel_noise_pct, alt_noise_m, fuel_stop_s, hostile_period_s;
    unsigned long long seed;
    unsigned long ssi_source, module_sa, others, vds_period_ms;
    int ssi, vds, printed;
    hostile_t hostile;
} options_t;

typedef struct {
    uint64_t t_us;     /* since the start of the simulation */
    uint32_t seq;      /* order among frames of one instant: generation order */
    pfe_can_frame_t f;
} ev_t;

typedef struct {
    ev_t *ev;
    size_t n, cap;
    uint32_t seq;
} evlist_t;

static int push(evlist_t *l, uint64_t t_us, const pfe_can_frame_t *f)
{
    if (l->n == l->cap) {
        const size_t cap = (l->cap == 0U) ? 65536U : (l->cap * 2U);
        ev_t *p = realloc(l->ev, cap * sizeof *p);
        if (p == NULL) {
            return -1;
        }
        l->ev = p;
        l->cap = cap;
    }
    l->ev[l->n].t_us = t_us;
    l->ev[l->n].seq = l->seq++;
    l->ev[l->n].f = *f;
    l->n++;
    return 0;
}

static int ev_cmp(const void *a, const void *b)
{
    const ev_t *x = a, *y = b;
    if (x->t_us != y->t_us) {
        return (x->t_us < y->t_us) ? -1 : 1;
    }
    return (x->seq < y->seq) ? -1 : ((x->seq > y->seq) ? 1 : 0);
}

static int parse_profile(const char *s, profile_t *p)
{
    p->n = 0;
    const char *q = s;
    while (*q != '\0') {
        if (p->n == MAX_PHASES) {
            return -1;
        }
        char *end = NULL;
        const double kmh = strtod(q, &end);
        if ((end == q) || (*end != ':') || !(kmh >= 0.0) || (kmh > 150.0)) {
            return -1;
        }
        q = end + 1;
        const double dur = strtod(q, &end);
        if ((end == q) || !(dur > 0.0) || (dur > 36000.0) || ((*end != ',') && (*end != '\0'))) {
            return -1;
        }
        p->kmh[p->n] = kmh;
        p->dur_s[p->n] = dur;
        p->n++;
        q = (*end == ',') ? end + 1 : end;
    }
    return (p->n > 0) ? 0 : -1;
}

static void usage(void)
{
    cli_usage(stderr, k_manual, "truckgen");
}

static int parse_args(int argc, char **argv, options_t *o)
{
    memset(o, 0, sizeof *o);
    o->ifname = "can0";
    (void)parse_profile("0:5,80:80,50:45,85:90,0:35,60:60,85:80,0:25", &o->profile);
    o->start_s = 15.0;
    o->seed = 1U;
    o->speed_noise_kmh = 0.3;
    o->fuel_noise_pct = 2.0;
    o->alt_noise_m = 1.5;
    o->fuel_stop_s = -1.0;
    o->hostile_period_s = 40.0;
    o->ssi_source = 0x2AU;
    o->module_sa = 0x8CU;
    o->others = 220U;
    o->vds_period_ms = 1000U;
    o->printed = 1;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--ssi") == 0) {
            o->ssi = 1;
            continue;
        }
        if (strcmp(a, "--vds") == 0) {
            o->vds = 1;
            continue;
        }
        if ((strcmp(a, "--help") == 0) || (i + 1 >= argc)) {
            usage();
            return (strcmp(a, "--help") == 0) ? 1 : 2;
        }
        const char *v = argv[++i];
        int bad = 0;
        unsigned long long seed = 0U;
        if (strcmp(a, "--calib") == 0) {
            o->calib_path = v;
        } else if (strcmp(a, "--road") == 0) {
            o->road_path = v;
        } else if (strcmp(a, "--truth") == 0) {
            o->truth_path = v;
        } else if (strcmp(a, "--out") == 0) {
            o->out_path = v;
        } else if (strcmp(a, "--iface") == 0) {
            o->ifname = v;
            bad = (strlen(v) == 0U) || (strlen(v) > 15U) || (strpbrk(v, " \t()#") != NULL);
        } else if (strcmp(a, "--profile") == 0) {
            bad = parse_profile(v, &o->profile);
        } else if (strcmp(a, "--start-s") == 0) {
            bad = cli_parse_double(v, 0.0, 36000.0, &o->start_s);
        } else if (strcmp(a, "--seed") == 0) {
            char *end = NULL;
            errno = 0;
            seed = strtoull(v, &end, 0);
            bad = (errno != 0) || (end == v) || (*end != '\0') || (v[0] == '-');
            o->seed = seed;
        } else if (strcmp(a, "--speed-noise-kmh") == 0) {
            bad = cli_parse_double(v, 0.0, 20.0, &o->speed_noise_kmh);
        } else if (strcmp(a, "--fuel-noise-pct") == 0) {
            bad = cli_parse_double(v, 0.0, 50.0, &o->fuel_noise_pct);
        } else if (strcmp(a, "--alt-noise-m") == 0) {
            bad = cli_parse_double(v, 0.0, 100.0, &o->alt_noise_m);
        } else if (strcmp(a, "--engine-fuel-stop-s") == 0) {
            bad = cli_parse_double(v, 0.0, 36000.0, &o->fuel_stop_s);
        } else if (strcmp(a, "--hostile-period-s") == 0) {
            bad = cli_parse_double(v, 5.0, 3600.0, &o->hostile_period_s);
        } else if (strcmp(a, "--ssi-source") == 0) {
            bad = cli_parse_ul(v, 0U, 253U, &o->ssi_source);
        } else if (strcmp(a, "--vds-period-ms") == 0) {
            bad = cli_parse_ul(v, 10U, 10000U, &o->vds_period_ms);
            bad = bad || ((o->vds_period_ms % 10U) != 0U);
        } else if (strcmp(a, "--module-sa") == 0) {
            bad = cli_parse_ul(v, 0U, 253U, &o->module_sa);
        } else if (strcmp(a, "--others") == 0) {
            bad = cli_parse_ul(v, 0U, MAX_OTHERS, &o->others);
        } else if (strcmp(a, "--format") == 0) {
            bad = (strcmp(v, "printed") != 0) && (strcmp(v, "log") != 0);
            o->printed = strcmp(v, "printed") == 0;
        } else if (strcmp(a, "--hostile") == 0) {
            o->hostile = (strcmp(v, "spoof") == 0)    ? HOSTILE_SPOOF
                         : (strcmp(v, "jump") == 0)   ? HOSTILE_JUMP
                         : (strcmp(v, "random") == 0) ? HOSTILE_RANDOM
                                                      : HOSTILE_NONE;
            bad = o->hostile == HOSTILE_NONE;
        } else {
            fprintf(stderr, "truckgen: unknown option '%s'\n", a);
            usage();
            return 2;
        }
        if (bad) {
            fprintf(stderr, "truckgen: option %s needs a valid value (got '%s')\n", a, v);
            return 2;
        }
    }
    if ((o->hostile == HOSTILE_SPOOF) && ((o->module_sa == SA_ENGINE) || (o->module_sa == SA_CAB))) {
        fprintf(stderr, "truckgen: --module-sa must not be a sender of the log (0x00, 0x31)\n");
        return 2;
    }
    return 0;
}

/* One CAN frame, 29-bit, priority p, PGN (PDU2, or PDU1 with its DA), SA. */
static void raw_frame(pfe_can_frame_t *f, uint32_t prio, uint32_t pgn, uint8_t sa, drive_noise_t *rnd)
{
    memset(f, 0, sizeof *f);
    f->id = PFE_CAN_EFF_FLAG | (prio << 26) | (pgn << 8) | sa;
    f->dlc = 8U;
    const uint64_t r = drive_noise_u64(rnd);
    for (unsigned k = 0U; k < 8U; k++) {
        f->data[k] = (uint8_t)(r >> (8U * k));
    }
}

/* A PGN the module reads, or one this tool sends as an input or names. */
static int module_reads(uint32_t pgn)
{
    static const uint32_t k[] = {PFE_PGN_CCVS1, PFE_PGN_SSI, PFE_PGN_LFE1, PFE_PGN_HRLFC, PFE_PGN_VDS,
                                 PFE_PGN_CVW, 0xF004U, 0xF003U, 0xF002U, 0xF001U, 0xFEEEU, 0xFEEFU,
                                 0xFEF5U, 0xFECAU};
    for (size_t i = 0U; i < sizeof k / sizeof k[0]; i++) {
        if (k[i] == pgn) {
            return 1;
        }
    }
    return 0;
}

typedef struct {
    uint32_t prio, pgn, period_us, phase_us;
    uint8_t sa;
} other_t;

/* The unrelated traffic: named PGNs first, then PDU2 PGNs stepped through
 * 0xFC00 .. 0xFEFF. */
static size_t make_others(other_t *o, unsigned long n, drive_noise_t *rnd)
{
    static const other_t named[] = {
        {3U, 0xF004U, 20000U, 0U, 0x00U},  /* EEC1, engine speed */
        {3U, 0xF003U, 50000U, 0U, 0x00U},  /* EEC2 */
        {3U, 0xF002U, 10000U, 0U, 0x03U},  /* ETC1, transmission */
        {3U, 0x0000U, 10000U, 0U, 0x03U},  /* TSC1 to the engine (PDU1, DA 0x00) */
        {6U, 0xF001U, 100000U, 0U, 0x0BU}, /* EBC1, brakes */
        {6U, 0xFEEEU, 1000000U, 0U, 0x00U}, /* ET1 */
        {6U, 0xFEEFU, 500000U, 0U, 0x00U}, /* EFL/P1 */
        {6U, 0xFEF5U, 1000000U, 0U, 0x00U}, /* AMB */
        {6U, 0xFECAU, 1000000U, 0U, 0x00U}, /* DM1 of several ECUs */
        {6U, 0xFECAU, 1000000U, 0U, 0x03U},
        {6U, 0xFECAU, 1000000U, 0U, 0x0BU},
        {6U, 0xFECAU, 1000000U, 0U, 0x31U},
        {6U, 0xFECAU, 1000000U, 0U, 0x17U},
    };
    static const uint8_t sas[] = {0x00U, 0x03U, 0x0BU, 0x17U, 0x21U, 0x27U, 0x28U,
                                  0x31U, 0x33U, 0x4AU, 0xEEU, 0x1CU, 0x10U, 0x05U};
    static const uint32_t periods[] = {1000000U, 1000000U, 5000000U, 500000U, 1000000U,
                                       2000000U, 5000000U, 1000000U, 100000U, 1000000U};
    size_t m = 0U;
    for (size_t k = 0U; (k < sizeof named / sizeof named[0]) && (m < n); k++) {
        o[m++] = named[k];
    }
    uint32_t pgn = 0xFC00U;
    for (size_t k = 0U; m < n; k++) {
        pgn += 3U;
        if (pgn > 0xFEFFU) {
            pgn = 0xFC01U + (uint32_t)(k % 3U);
        }
        if (module_reads(pgn)) {
            continue;
        }
        o[m].prio = 6U;
        o[m].pgn = pgn;
        o[m].sa = sas[k % (sizeof sas / sizeof sas[0])];
        o[m].period_us = periods[k % (sizeof periods / sizeof periods[0])];
        m++;
    }
    for (size_t k = 0U; k < m; k++) {
        o[k].phase_us = (uint32_t)(drive_noise_u64(rnd) % o[k].period_us);
    }
    return m;
}

static double road_grade(const road_ppm_t *road, double x_m)
{
    if (road->n_samples == 0U) {
        return 0.0;
    }
    const double k = floor(x_m * 1000.0 / road->spacing_mm);
    size_t i = (k > 0.0) ? (size_t)k : 0U;
    if (i >= road->n_samples) {
        i = road->n_samples - 1U;
    }
    return road->grade_ppm[i] / 1e6;
}

static void print_ev(FILE *out, const options_t *o, uint64_t t_us, const pfe_can_frame_t *f)
{
    const uint32_t id = f->id & PFE_CAN_ID_MASK;
    if (o->printed) {
        fprintf(out, "(%03llu.%06llu)  %s  %08lX   [%u] ", (unsigned long long)(t_us / 1000000U),
                (unsigned long long)(t_us % 1000000U), o->ifname, (unsigned long)id,
                (unsigned)f->dlc);
        for (uint8_t k = 0U; k < f->dlc; k++) {
            fprintf(out, " %02X", f->data[k]);
        }
    } else {
        fprintf(out, "(%llu.%06llu) %s %08lX#", (unsigned long long)(T0_S + (t_us / 1000000U)),
                (unsigned long long)(t_us % 1000000U), o->ifname, (unsigned long)id);
        for (uint8_t k = 0U; k < f->dlc; k++) {
            fprintf(out, "%02X", f->data[k]);
        }
    }
    fputc('\n', out);
}

/* A few hundred microseconds of jitter around a nominal instant. */
static uint64_t jitter(uint64_t t_us, drive_noise_t *rnd)
{
    return t_us + (drive_noise_u64(rnd) % 400U);
}

static int generate(const options_t *o, const pfe_vehicle_calib_t *veh, const road_ppm_t *road,
                    evlist_t *l, FILE *truth)
{
    ref_vehicle_t v;
    ref_vehicle_init(&v, veh, &pfe_default_env, 0.0);
    const double g = pfe_default_env.gravity_um_s2 / 1e6;
    drive_noise_t n_speed, n_fuel, n_alt, n_jit, n_other, n_host;
    drive_noise_seed(&n_speed, o->seed);
    drive_noise_seed(&n_fuel, o->seed ^ 0x1111111111111111ULL);
    drive_noise_seed(&n_alt, o->seed ^ 0x2222222222222222ULL);
    drive_noise_seed(&n_jit, o->seed ^ 0x3333333333333333ULL);
    drive_noise_seed(&n_other, o->seed ^ 0x4444444444444444ULL);
    drive_noise_seed(&n_host, o->seed ^ 0x5555555555555555ULL);
    static other_t others[MAX_OTHERS];
    const size_t n_others = make_others(others, o->others, &n_other);

    double total_s = 0.0;
    for (int p = 0; p < o->profile.n; p++) {
        total_s += o->profile.dur_s[p];
    }
    const uint64_t start_us = (uint64_t)llround(o->start_s * 1e6);
    const uint64_t end_us = (uint64_t)llround(total_s * 1e6);
    if (start_us + 1000000U > end_us) {
        fprintf(stderr, "truckgen: --start-s leaves less than 1 s of the %.0f s profile\n", total_s);
        return 2;
    }
    double speed = 0.0, pos = 0.0, alt = ALT0_M, fuel_l = 0.0;
    int phase = 0;
    double phase_end_s = o->profile.dur_s[0];
    uint64_t next_burst_us = start_us + 30000000U;
    unsigned burst_left = 0U;
    uint64_t burst_next_us = 0U;
    unsigned bursts = 0U, hostile_frames = 0U;
    for (uint64_t t_us = 0U; t_us < end_us; t_us += TICK_US) {
        const double t_s = (double)t_us / 1e6;
        while ((phase < o->profile.n - 1) && (t_s >= phase_end_s)) {
            phase++;
            phase_end_s += o->profile.dur_s[phase];
        }
        const double target = o->profile.kmh[phase] / 3.6;
        const double grade = road_grade(road, pos);
        const double resist = ref_vehicle_resistance(&v, speed, grade, g);
        /* to a stop: braking at 1 m/s^2 until standstill, not creeping */
        double a_want = (target <= 0.0) ? -1.0 : fmin(fmax((target - speed) / 2.0, -1.2), 1.0);
        double force = (v.mass_fuel * a_want) + resist;
        force = fmin(force, ref_wheel_force_max(v.power_max, v.traction_max, speed));
        force = fmax(force, -v.brake_max);
        double a = (force - resist) / v.mass_fuel;
        if ((speed <= 0.0) && (a < 0.0)) {
            /* standing: the brakes hold it, no force at the wheels */
            a = 0.0;
            force = 0.0;
        }
        const double fuel_l_s = ref_fuel_rate(force, speed, v.power_aux, v.fuel_per_j);
        fuel_l += fuel_l_s * (TICK_US / 1e6);
        const bool logged = t_us >= start_us;
        const uint64_t rel = t_us - (logged ? start_us : 0U);
        const bool on_100ms = (t_us % 100000U) == 0U;
        pfe_can_frame_t f;
        if (logged && on_100ms) {
            /* CCVS1 from the engine, 3 ms into the period */
            double kmh = (speed * 3.6) + (o->speed_noise_kmh * drive_noise_gauss(&n_speed));
            kmh = fmin(fmax(kmh, 0.0), 250.99609375);
            const pfe_msg_ccvs1_t c = {{drive_spn84_quantise_mm_s(kmh / 3.6), PFE_SIG_VALID}};
            (void)pfe_codec_encode_ccvs1(&f, &c, SA_ENGINE);
            if (push(l, jitter(t_us + 3000U, &n_jit), &f) != 0) {
                return -1;
            }
            /* the cab controller's CCVS1 and LFE1, not available */
            const pfe_msg_ccvs1_t na = {{0, PFE_SIG_NOT_AVAILABLE}};
            (void)pfe_codec_encode_ccvs1(&f, &na, SA_CAB);
            if (push(l, jitter(t_us + 47000U, &n_jit), &f) != 0) {
                return -1;
            }
            const pfe_msg_lfe1_t lna = {{0U, PFE_SIG_NOT_AVAILABLE}};
            (void)pfe_codec_encode_lfe1(&f, &lna, SA_CAB);
            if (push(l, jitter(t_us + 49000U, &n_jit), &f) != 0) {
                return -1;
            }
            /* the engine's LFE1: the reference for the true truck, noise, 0.05 L/h */
            const double noise = 1.0 + ((o->fuel_noise_pct / 100.0) * drive_noise_gauss(&n_fuel));
            const double l_h = fmax(fuel_l_s * 3600.0 * noise, 0.0);
            const long raw = (l_h / 0.05 < 64255.0) ? lround(l_h / 0.05) : 64255L;
            if ((o->fuel_stop_s < 0.0) || ((double)rel / 1e6 < o->fuel_stop_s)) {
                const pfe_msg_lfe1_t e = {{(uint32_t)lround((double)raw * 125000.0 / 9.0),
                                           PFE_SIG_VALID}};
                (void)pfe_codec_encode_lfe1(&f, &e, SA_ENGINE);
                if (push(l, jitter(t_us + 23000U, &n_jit), &f) != 0) {
                    return -1;
                }
            }
            if (truth != NULL) {
                fprintf(truth, "%.2f,%.4f,%.4f,%.1f,%.4f,%.6f\n", (double)rel / 1e6, speed * 3.6,
                        grade * 100.0, force, fuel_l_s * 3600.0, fuel_l);
            }
        }
        if (logged && ((t_us % 1000000U) == 0U)) {
            pfe_msg_hrlfc_t h;
            h.trip_fuel_ul.state = PFE_SIG_NOT_AVAILABLE;
            h.trip_fuel_ul.value = 0U;
            h.total_fuel_ul.state = PFE_SIG_VALID;
            h.total_fuel_ul.value = (uint64_t)llround((HRLFC_START_L + fuel_l) * 1000.0) * 1000U;
            (void)pfe_codec_encode_hrlfc(&f, &h, SA_ENGINE);
            if (push(l, jitter(t_us + 61000U, &n_jit), &f) != 0) {
                return -1;
            }
        }
        if (logged && o->vds && ((t_us % (o->vds_period_ms * 1000U)) == 0U)) {
            {
                pfe_msg_vds_t d;
                d.bearing_mdeg.value = 90000U;
                d.bearing_mdeg.state = PFE_SIG_VALID;
                d.nav_speed_mm_s.value = drive_spn84_quantise_mm_s(speed);
                d.nav_speed_mm_s.state = PFE_SIG_VALID;
                d.pitch_mdeg.value = 0;
                d.pitch_mdeg.state = PFE_SIG_NOT_AVAILABLE;
                const double alt_m = alt + (o->alt_noise_m * drive_noise_gauss(&n_alt));
                d.altitude_mm.value = (int32_t)(lround(alt_m / 0.125) * 125L);
                d.altitude_mm.state = PFE_SIG_VALID;
                (void)pfe_codec_encode_vds(&f, &d, SA_GNSS);
                if (push(l, jitter(t_us + 7000U, &n_jit), &f) != 0) {
                    return -1;
                }
            }
        }
        if (logged && o->ssi) {
            const pfe_msg_ssi_t s = {{(int32_t)lround(atan(grade) * 180.0 / 3.14159265358979323846 * 1e6),
                                      PFE_SIG_VALID},
                                     {0, PFE_SIG_VALID},
                                     {PFE_SSI_FOM_FULLY_FUNCTIONAL, PFE_SIG_VALID}};
            (void)pfe_codec_encode_ssi(&f, &s, (uint8_t)o->ssi_source);
            if (push(l, jitter(t_us + 5000U, &n_jit), &f) != 0) {
                return -1;
            }
        }
        for (size_t k = 0U; logged && (k < n_others); k++) {
            const other_t *x = &others[k];
            /* due in this tick: phase + j * period in [t, t + tick) */
            const uint64_t off = (t_us + x->period_us - x->phase_us) % x->period_us;
            if ((off == 0U) || (x->period_us - off < TICK_US)) {
                const uint64_t at = t_us + ((off == 0U) ? 0U : (x->period_us - off));
                raw_frame(&f, x->prio, x->pgn, x->sa, &n_other);
                if (push(l, at, &f) != 0) {
                    return -1;
                }
            }
        }
        /* hostile frames, on top, 50 ms after a regular CCVS1 */
        if (logged && on_100ms && (o->hostile != HOSTILE_NONE)) {
            if ((burst_left == 0U) && (t_us >= next_burst_us)) {
                burst_left = (o->hostile == HOSTILE_SPOOF) ? 20U : (o->hostile == HOSTILE_JUMP) ? 1U : 10U;
                burst_next_us = t_us;
                next_burst_us += (uint64_t)llround(o->hostile_period_s * 1e6);
                bursts++;
            }
            if ((burst_left > 0U) && (t_us >= burst_next_us)) {
                const uint64_t at = t_us + 53000U;
                if (o->hostile == HOSTILE_SPOOF) {
                    const pfe_msg_ccvs1_t c = {{drive_spn84_quantise_mm_s(200.0 / 3.6), PFE_SIG_VALID}};
                    (void)pfe_codec_encode_ccvs1(&f, &c, (uint8_t)o->module_sa);
                } else if (o->hostile == HOSTILE_JUMP) {
                    const pfe_msg_ccvs1_t c = {{drive_spn84_quantise_mm_s(250.0 / 3.6), PFE_SIG_VALID}};
                    (void)pfe_codec_encode_ccvs1(&f, &c, SA_ENGINE);
                } else {
                    const unsigned which = burst_left % (o->ssi ? 3U : 2U);
                    const uint32_t pgn = (which == 0U) ? PFE_PGN_CCVS1
                                         : (which == 1U) ? PFE_PGN_LFE1 : PFE_PGN_SSI;
                    const uint8_t sa = (which == 2U) ? (uint8_t)o->ssi_source : SA_ENGINE;
                    raw_frame(&f, (pgn == PFE_PGN_SSI) ? 3U : 6U, pgn, sa, &n_host);
                }
                if (push(l, at, &f) != 0) {
                    return -1;
                }
                hostile_frames++;
                burst_left--;
                burst_next_us = t_us + 100000U;
            }
        }
        speed = fmax(speed + (a * (TICK_US / 1e6)), 0.0);
        pos += speed * (TICK_US / 1e6);
        alt += speed * (TICK_US / 1e6) * grade;
    }
    if (o->hostile != HOSTILE_NONE) {
        fprintf(stderr, "truckgen: %u hostile bursts, %u hostile frames\n", bursts, hostile_frames);
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (cli_help_asked(argc, argv)) {
        cli_help(k_manual);
        return 0;
    }
    static options_t o;
    const int prc = parse_args(argc, argv, &o);
    if (prc != 0) {
        return (prc == 1) ? 0 : prc;
    }
    static truck_cal_t cal;
    char err[TRUCK_CAL_ERR_MAX];
    truck_cal_default(&cal);
    if ((o.calib_path != NULL) && (truck_cal_load(o.calib_path, &cal, err, sizeof err) != 0)) {
        fprintf(stderr, "truckgen: %s\n", err);
        return 2;
    }
    road_ppm_t road = {NULL, 0U, 0U};
    if ((o.road_path != NULL) && (road_ppm_load(o.road_path, &road, err, sizeof err) != 0)) {
        fprintf(stderr, "truckgen: %s\n", err);
        return 2;
    }
    FILE *truth = NULL;
    if (o.truth_path != NULL) {
        truth = fopen(o.truth_path, "w");
        if (truth == NULL) {
            fprintf(stderr, "truckgen: cannot write %s: %s\n", o.truth_path, strerror(errno));
            road_ppm_free(&road);
            return 1;
        }
        fprintf(truth, "t_s,speed_kmh,grade_pct,force_n,fuel_l_h,fuel_l\n");
    }
    evlist_t l = {NULL, 0U, 0U, 0U};
    int rc = generate(&o, &cal.own, &road, &l, truth);
    road_ppm_free(&road);
    if ((truth != NULL) && (fclose(truth) != 0) && (rc == 0)) {
        fprintf(stderr, "truckgen: cannot write %s\n", o.truth_path);
        rc = 1;
    }
    if (rc != 0) {
        if (rc < 0) {
            fprintf(stderr, "truckgen: out of memory\n");
        }
        free(l.ev);
        return (rc == 2) ? 2 : 1;
    }
    qsort(l.ev, l.n, sizeof l.ev[0], ev_cmp);
    FILE *out = (o.out_path != NULL) ? fopen(o.out_path, "w") : stdout;
    if (out == NULL) {
        fprintf(stderr, "truckgen: cannot write %s: %s\n", o.out_path, strerror(errno));
        free(l.ev);
        return 1;
    }
    const uint64_t start_us = (uint64_t)llround(o.start_s * 1e6);
    for (size_t k = 0U; k < l.n; k++) {
        print_ev(out, &o, l.ev[k].t_us - start_us, &l.ev[k].f);
    }
    int status = 0;
    if (ferror(out) || (((out != stdout) ? fclose(out) : fflush(out)) != 0)) {
        fprintf(stderr, "truckgen: cannot write %s\n", (o.out_path != NULL) ? o.out_path : "stdout");
        status = 1;
    }
    fprintf(stderr, "truckgen: %zu frames, %.1f s, truck %lu kg\n", l.n,
            (l.n > 0U) ? (double)(l.ev[l.n - 1U].t_us - start_us) / 1e6 : 0.0,
            (unsigned long)cal.own.mass_kg);
    free(l.ev);
    return status;
}
