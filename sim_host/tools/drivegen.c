/*
 * drivegen - a drive as the module would see it on the bus, as a candump log:
 * the reference object model drives a road, each frame encoded with the
 * firmware's codec.
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
#include "firmware/pfe_platoon.h"
#include "ref/drive_trace.h"
#include "lib/road_csv.h"
#include "lib/truck_cal.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: drivegen (--road FILE.csv | --segment LEN_M:GRADE_PCT ...) [--set-speed-kmh V]\n"
    "                [--vehicles N] [--position P] [--gap-m D]\n"
    "                [--seed S] [--speed-noise-kmh SD] [--pitch-noise-deg SD]\n"
    "                [--no-config] [--no-preview] [--preview-period-s S]\n"
    "                [--preview-samples N] [--preview-spacing-m M]\n"
    "                [--iface IF] [--source SA] [--config-source SA] [--preview-source SA]\n"
    "                [--out LOG] [--calib FILE]\n"
    "\n"
    "Writes a drive as the module would see it on the bus, as a candump log: a\n"
    "platoon (the double-precision reference object model) drives the road at\n"
    "its set speed under cruise control, and every frame is encoded with the\n"
    "firmware's codec (can_dbc/pfe.dbc).\n"
    "\n"
    "The road and the platoon:\n"
    "  --road FILE.csv        a road profile (grades at a fixed spacing)\n"
    "  --segment LEN_M:GRADE_PCT\n"
    "                         or a road of segments, each LEN_M metres (10 ..\n"
    "                         1e6) at GRADE_PCT percent (within +-30); repeatable\n"
    "  --set-speed-kmh V      set speed, 5 .. 250 (default 90)\n"
    "  --vehicles N           trucks, 1 .. 32 (default 1)\n"
    "  --position P           the module's truck, 0 (lead) .. N - 1 (default 0)\n"
    "  --gap-m D              gap between trucks, 0 .. 642.55 m (default 10)\n"
    "  --calib FILE           the trucks' calibration: the own truck's at position\n"
    "                         P, a [position k] section's at k, else the default\n"
    "\n"
    "On the bus:\n"
    "  CCVS1 every 100 ms: the speed (SPN 84, 1/256 km/h), from --source SA\n"
    "  (default 0); SSI every 10 ms: the pitch of the road under the platoon\n"
    "  (SPN 3318, 0.002 deg), from --source SA;\n"
    "  --speed-phase-ms P     CCVS1 sent P ms after its period's start, 0 .. 99\n"
    "                         (default 0), with the speed at that start: a\n"
    "                         speed sender on a schedule of its own\n"
    "  --no-config            no PFE_PlatoonConfig (default: every 1000 ms, its\n"
    "                         DBC period: N, position P, gap D, the time gap D /\n"
    "                         set speed and the set speed)\n"
    "  --config-source SA     its sender (default 0xE0)\n"
    "  --no-preview           no PFE_GradePreview (default: a burst of one header\n"
    "                         and ceil(count / 3) data frames, 5 ms apart, starting\n"
    "                         2.5 ms after a 10 ms tick; PreviewId counts up\n"
    "                         modulo 16)\n"
    "  --preview-period-s S   a burst every S seconds, 0.5 .. 3600 (default 10)\n"
    "  --preview-samples N    grades per preview, 1 .. 1000 (default 1000, at\n"
    "                         most what is left of the road)\n"
    "  --preview-spacing-m M  their spacing, 1 .. 250 m (default 12), from the\n"
    "                         platoon's position at that tick\n"
    "  --preview-source SA    its sender (default 0xE1)\n"
    "  --iface IF             the interface name in the log (default vcan0)\n"
    "  --out LOG              the log (default standard output)\n"
    "\n"
    "Sensor noise, off by default, drawn from two SplitMix64 streams seeded from\n"
    "--seed S (default 1), so that a log is the same file on every machine:\n"
    "  --speed-noise-kmh SD   a normal-like deviate of standard deviation SD\n"
    "                         (0 .. 20) added to each speed sample before SPN 84's\n"
    "                         quantisation (then clamped to 0 .. 250.996 km/h)\n"
    "  --pitch-noise-deg SD   one of SD (0 .. 5) added to each pitch\n"
    "\n"
    "Lines are candump's log format, \"(seconds.micro) IF ID#DATA\", starting at\n"
    "1700000000.000000, in time order (frames of one instant: CCVS1, SSI,\n"
    "PFE_PlatoonConfig).\n"
    "\n"
    "Exit status 0; 1 when the output cannot be written; 2 on bad arguments or\n"
    "input (message on standard error).\n"
    "\n"
    "Examples:\n"
    "  drivegen --road sim_host/data/roads/hilly.csv --vehicles 5 --position 1 --out hilly.log\n"
    "  drivegen --segment 600:0 --segment 750:2 --no-preview --out climb.log\n";

#define MAX_SEGMENTS 64
#define SEGMENT_SPACING_MM 10000U
#define T0_S 1700000000ULL
#define TICK_US 10000U
#define CONFIG_PERIOD_TICKS 100U      /* PFE_PlatoonConfig, 1000 ms */
/* A burst starts between two ticks, its frames 5 ms apart, never on a tick:
 * 1 ms apart, a burst would take half of a 250 kbit/s J1939 bus (a 29-bit
 * frame with 8 bytes is 128 bits before stuffing). */
#define PREVIEW_OFFSET_US 2500U
#define PREVIEW_FRAME_GAP_US 5000U
#define SPEED_MAX_KMH 250.99609375    /* SPN 84's largest valid value */
#define PITCH_MIN_DEG (-64.0)         /* SPN 3318's valid range */
#define PITCH_MAX_DEG 64.51
#define PI 3.14159265358979323846

typedef struct {
    const char *road_path, *out_path, *ifname;
    double set_kmh;
    unsigned long source, config_source, preview_source;
    double seg_len[MAX_SEGMENTS], seg_grade[MAX_SEGMENTS];
    int n_seg;
    unsigned long vehicles, position;
    double gap_m;
    unsigned long long seed;
    double speed_noise_kmh, pitch_noise_deg;
    int config, preview;
    unsigned long preview_period_ticks, preview_samples, preview_spacing_m;
    unsigned long speed_phase_ms;
} options_t;

static void print_frame(FILE *out, uint64_t t_us, const char *ifname, const pfe_can_frame_t *f)
{
    fprintf(out, "(%llu.%06llu) %s %08lX#", (unsigned long long)(T0_S + (t_us / 1000000U)),
            (unsigned long long)(t_us % 1000000U), ifname,
            (unsigned long)(f->id & PFE_CAN_ID_MASK));
    for (uint8_t k = 0U; k < f->dlc; k++) {
        fprintf(out, "%02X", f->data[k]);
    }
    fputc('\n', out);
}

static void usage(void)
{
    cli_usage(stderr, k_manual, "drivegen");
}

/* 0, or 2 after a message. */
static int parse_args(int argc, char **argv, options_t *o)
{
    memset(o, 0, sizeof *o);
    o->ifname = "vcan0";
    o->set_kmh = 90.0;
    o->config_source = 0xE0U;
    o->preview_source = 0xE1U;
    o->vehicles = 1U;
    o->gap_m = 10.0;
    o->seed = 1U;
    o->config = 1;
    o->preview = 1;
    o->preview_period_ticks = 1000U;
    o->preview_samples = PFE_PREVIEW_MAX_SAMPLES;
    o->preview_spacing_m = 12U;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--no-config") == 0) {
            o->config = 0;
            continue;
        }
        if (strcmp(a, "--no-preview") == 0) {
            o->preview = 0;
            continue;
        }
        if (i + 1 >= argc) {
            fprintf(stderr, "drivegen: option '%s' wants a value (or is unknown)\n", a);
            return 2;
        }
        const char *v = argv[++i];
        int bad = 0;
        double d = 0.0;
        if (strcmp(a, "--road") == 0) {
            o->road_path = v;
        } else if (strcmp(a, "--out") == 0) {
            o->out_path = v;
        } else if (strcmp(a, "--iface") == 0) {
            o->ifname = v;
            bad = (v[0] == '\0') || (strlen(v) > 15U) || (strpbrk(v, " \t()#") != NULL);
        } else if (strcmp(a, "--source") == 0) {
            bad = cli_parse_ul(v, 0U, 253U, &o->source);
        } else if (strcmp(a, "--config-source") == 0) {
            bad = cli_parse_ul(v, 0U, 253U, &o->config_source);
        } else if (strcmp(a, "--preview-source") == 0) {
            bad = cli_parse_ul(v, 0U, 253U, &o->preview_source);
        } else if (strcmp(a, "--set-speed-kmh") == 0) {
            bad = cli_parse_double(v, 5.0, 250.0, &o->set_kmh);
        } else if (cli_platoon_option(a, v, &o->vehicles, &o->position, &o->gap_m, &bad)) {
            /* --vehicles, --position, --gap-m */
        } else if (strcmp(a, "--seed") == 0) {
            char *end = NULL;
            errno = 0;
            o->seed = strtoull(v, &end, 0);
            bad = (errno != 0) || (end == v) || (*end != '\0') || (v[0] == '-');
        } else if (strcmp(a, "--speed-noise-kmh") == 0) {
            bad = cli_parse_double(v, 0.0, 20.0, &o->speed_noise_kmh);
        } else if (strcmp(a, "--pitch-noise-deg") == 0) {
            bad = cli_parse_double(v, 0.0, 5.0, &o->pitch_noise_deg);
        } else if (strcmp(a, "--preview-period-s") == 0) {
            bad = cli_parse_double(v, 0.5, 3600.0, &d);
            o->preview_period_ticks = (unsigned long)lround(d * 100.0);
        } else if (strcmp(a, "--speed-phase-ms") == 0) {
            bad = cli_parse_ul(v, 0U, 99U, &o->speed_phase_ms);
        } else if (strcmp(a, "--preview-samples") == 0) {
            bad = cli_parse_ul(v, 1U, PFE_PREVIEW_MAX_SAMPLES, &o->preview_samples);
        } else if (strcmp(a, "--preview-spacing-m") == 0) {
            bad = cli_parse_ul(v, 1U, 250U, &o->preview_spacing_m);
        } else if (strcmp(a, "--segment") == 0) {
            if (o->n_seg == MAX_SEGMENTS) {
                fprintf(stderr, "drivegen: more than %d --segment options\n", MAX_SEGMENTS);
                return 2;
            }
            char tail = '\0';
            bad = (sscanf(v, "%lf:%lf%c", &o->seg_len[o->n_seg], &o->seg_grade[o->n_seg], &tail) != 2) ||
                  !(o->seg_len[o->n_seg] >= 10.0) || !(o->seg_len[o->n_seg] <= 1e6) ||
                  !(fabs(o->seg_grade[o->n_seg]) <= 30.0);
            o->n_seg++;
        } else {
            fprintf(stderr, "drivegen: unknown option '%s'\n", a);
            usage();
            return 2;
        }
        if (bad) {
            fprintf(stderr, "drivegen: bad value '%s' for %s\n", v, a);
            return 2;
        }
    }
    if ((o->road_path == NULL) == (o->n_seg == 0)) {
        usage();
        return 2;
    }
    if (o->position >= o->vehicles) {
        fprintf(stderr, "drivegen: --position %lu is not below --vehicles %lu\n", o->position,
                o->vehicles);
        return 2;
    }
    /* A burst must end before the next one starts. */
    const unsigned long burst_us = PREVIEW_OFFSET_US +
        (((o->preview_samples + 2U) / 3U) * PREVIEW_FRAME_GAP_US);
    if (o->preview && ((o->preview_period_ticks * TICK_US) <= burst_us)) {
        fprintf(stderr, "drivegen: --preview-period-s too short for a burst of %lu samples "
                        "(%lu ms)\n", o->preview_samples, burst_us / 1000U);
        return 2;
    }
    return 0;
}

/* Road grade at distance x, as the reference model looks it up: the sample
 * the point lies in, the last one beyond the end. */
static int32_t road_grade_at(const road_ppm_t *road, double x_m)
{
    const double k = floor(x_m * 1000.0 / road->spacing_mm);
    size_t i = (k > 0.0) ? (size_t)k : 0U;
    if (i >= road->n_samples) {
        i = road->n_samples - 1U;
    }
    return road->grade_ppm[i];
}

typedef struct {
    bool active;
    uint8_t id;            /* PreviewId, modulo 16 */
    uint32_t count;        /* samples */
    uint32_t next;         /* next frame: 0 header, then data frame k at k */
    uint32_t frames;       /* 1 + ceil(count / 3) */
    uint64_t t0_us;        /* the header's time */
    int32_t grade_ppm[PFE_PREVIEW_MAX_SAMPLES];
} burst_t;

static void burst_start(burst_t *b, const options_t *o, const road_ppm_t *road, double pos_m,
                        uint64_t t0_us)
{
    const double road_m = (double)road->n_samples * road->spacing_mm / 1000.0;
    const double left = floor((road_m - pos_m) / (double)o->preview_spacing_m);
    uint32_t count = (uint32_t)o->preview_samples;
    if (left + 1.0 < (double)count) {
        count = (left >= 0.0) ? (uint32_t)left + 1U : 1U;
    }
    b->active = true;
    b->count = count;
    b->next = 0U;
    b->frames = 1U + ((count + 2U) / 3U);
    b->t0_us = t0_us;
    for (uint32_t k = 0U; k < count; k++) {
        b->grade_ppm[k] = road_grade_at(road, pos_m + ((double)k * (double)o->preview_spacing_m));
    }
}

/* Emits the burst's frames due before until_us. */
static void burst_emit(burst_t *b, const options_t *o, FILE *out, uint64_t until_us)
{
    while (b->active && ((b->t0_us + ((uint64_t)b->next * PREVIEW_FRAME_GAP_US)) < until_us)) {
        pfe_msg_grade_preview_t m;
        memset(&m, 0, sizeof m);
        m.preview_id.value = b->id;
        m.preview_id.state = PFE_SIG_VALID;
        if (b->next == 0U) {
            m.frame_type.value = PFE_PREVIEW_FRAME_HEADER;
            m.sample_count.value = b->count;
            m.spacing_m.value = (uint32_t)o->preview_spacing_m;
            m.sample_count.state = PFE_SIG_VALID;
            m.spacing_m.state = PFE_SIG_VALID;
        } else {
            const uint32_t first = (b->next - 1U) * PFE_PREVIEW_SAMPLES_PER_FRAME;
            m.frame_type.value = PFE_PREVIEW_FRAME_DATA;
            m.first_index.value = first;
            m.first_index.state = PFE_SIG_VALID;
            for (uint32_t s = 0U; s < PFE_PREVIEW_SAMPLES_PER_FRAME; s++) {
                const bool in = (first + s) < b->count;
                m.grade_ppm[s].value = in ? b->grade_ppm[first + s] : 0;
                m.grade_ppm[s].state = in ? PFE_SIG_VALID : PFE_SIG_NOT_AVAILABLE;
            }
        }
        m.frame_type.state = PFE_SIG_VALID;
        pfe_can_frame_t f;
        (void)pfe_codec_encode_grade_preview(&f, &m, (uint8_t)o->preview_source);
        print_frame(out, b->t0_us + ((uint64_t)b->next * PREVIEW_FRAME_GAP_US), o->ifname, &f);
        b->next++;
        if (b->next == b->frames) {
            b->active = false;
            b->id = (uint8_t)((b->id + 1U) % 16U);
        }
    }
}

/* The gap as PFE_PlatoonConfig carries it (0.01 m): the simulation uses the same. */
static uint32_t gap_mm_of(const options_t *o)
{
    return (uint32_t)lround(o->gap_m * 100.0) * 10U;
}

static int make_segment_road(const options_t *o, road_ppm_t *road)
{
    double total = 0.0;
    for (int s = 0; s < o->n_seg; s++) {
        total += o->seg_len[s];
    }
    road->n_samples = (uint32_t)ceil(total / (SEGMENT_SPACING_MM / 1000.0));
    road->spacing_mm = SEGMENT_SPACING_MM;
    road->grade_ppm = malloc(sizeof(int32_t) * road->n_samples);
    if (road->grade_ppm == NULL) {
        return -1;
    }
    for (uint32_t k = 0U; k < road->n_samples; k++) {
        double at = k * (SEGMENT_SPACING_MM / 1000.0), edge = 0.0;
        int s = 0;
        while ((s < o->n_seg - 1) && (at >= edge + o->seg_len[s])) {
            edge += o->seg_len[s];
            s++;
        }
        road->grade_ppm[k] = (int32_t)lround(o->seg_grade[s] * 10000.0);
    }
    return 0;
}

static int write_drive(const options_t *o, const road_ppm_t *road, const drive_trace_t *drive,
                       FILE *out)
{
    drive_noise_t speed_noise, pitch_noise;
    drive_noise_seed(&speed_noise, (uint64_t)o->seed);
    drive_noise_seed(&pitch_noise, ~(uint64_t)o->seed);
    static burst_t burst;
    memset(&burst, 0, sizeof burst);
    const uint64_t end_us = (uint64_t)drive->n_ticks * TICK_US;
    const uint64_t burst_us = PREVIEW_OFFSET_US +
        ((uint64_t)(1U + ((o->preview_samples + 2U) / 3U)) * PREVIEW_FRAME_GAP_US);
    const int32_t set_mm_s = drive_spn84_quantise_mm_s(o->set_kmh / 3.6);
    const uint32_t gap_mm = gap_mm_of(o);
    /* CCVS1 waits here until its time (--speed-phase-ms); one at a time,
     * since the phase is shorter than its period */
    pfe_can_frame_t speed_frame;
    bool speed_pending = false;
    uint64_t speed_at_us = 0U;
    for (size_t k = 0U; k < drive->n_ticks; k++) {
        const drive_tick_t *t = &drive->ticks[k];
        const uint64_t t_us = (uint64_t)k * TICK_US;
        pfe_can_frame_t f;
        if (speed_pending && (speed_at_us <= t_us)) {
            print_frame(out, speed_at_us, o->ifname, &speed_frame);
            speed_pending = false;
        }
        if (t->speed_fresh) {
            int32_t speed_mm_s = t->speed_mm_s;
            if (o->speed_noise_kmh > 0.0) {
                double kmh = (t->true_speed * 3.6) + (o->speed_noise_kmh * drive_noise_gauss(&speed_noise));
                kmh = fmin(fmax(kmh, 0.0), SPEED_MAX_KMH);
                speed_mm_s = drive_spn84_quantise_mm_s(kmh / 3.6);
            }
            const pfe_msg_ccvs1_t m = {{speed_mm_s, PFE_SIG_VALID}};
            (void)pfe_codec_encode_ccvs1(&speed_frame, &m, (uint8_t)o->source);
            speed_at_us = t_us + ((uint64_t)o->speed_phase_ms * 1000U);
            speed_pending = speed_at_us > t_us;
            if (!speed_pending) {
                print_frame(out, t_us, o->ifname, &speed_frame);
            }
        }
        double pitch_deg = atan(t->grade_ppm / 1e6) * 180.0 / PI;
        if (o->pitch_noise_deg > 0.0) {
            pitch_deg += o->pitch_noise_deg * drive_noise_gauss(&pitch_noise);
            pitch_deg = fmin(fmax(pitch_deg, PITCH_MIN_DEG), PITCH_MAX_DEG);
        }
        const pfe_msg_ssi_t s = {{(int32_t)lround(pitch_deg * 1e6), PFE_SIG_VALID},
                                 {0, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}};
        (void)pfe_codec_encode_ssi(&f, &s, (uint8_t)o->source);
        print_frame(out, t_us, o->ifname, &f);
        if (o->config && ((k % CONFIG_PERIOD_TICKS) == 0U)) {
            pfe_msg_platoon_config_t c;
            c.n_vehicles.value = (uint32_t)o->vehicles;
            c.own_position.value = (uint32_t)o->position;
            c.gap_mm.value = gap_mm;
            c.time_gap_ms.value = (uint32_t)lround(o->gap_m / (o->set_kmh / 3.6) * 1000.0);
            c.set_speed_mm_s.value = set_mm_s;
            c.n_vehicles.state = PFE_SIG_VALID;
            c.own_position.state = PFE_SIG_VALID;
            c.gap_mm.state = PFE_SIG_VALID;
            c.time_gap_ms.state = (c.time_gap_ms.value <= 64255U) ? PFE_SIG_VALID
                                                                  : PFE_SIG_NOT_AVAILABLE;
            c.set_speed_mm_s.state = PFE_SIG_VALID;
            (void)pfe_codec_encode_platoon_config(&f, &c, (uint8_t)o->config_source);
            print_frame(out, t_us, o->ifname, &f);
        }
        if (o->preview && !burst.active && ((k % o->preview_period_ticks) == 0U) &&
            (t_us + burst_us <= end_us)) {
            burst_start(&burst, o, road, t->position_m, t_us + PREVIEW_OFFSET_US);
        }
        if (speed_pending && (speed_at_us < (t_us + TICK_US))) {
            burst_emit(&burst, o, out, speed_at_us);
            print_frame(out, speed_at_us, o->ifname, &speed_frame);
            speed_pending = false;
        }
        burst_emit(&burst, o, out, t_us + TICK_US);
    }
    if (speed_pending) {
        print_frame(out, speed_at_us, o->ifname, &speed_frame);
    }
    return ferror(out) ? -1 : 0;
}

int main(int argc, char **argv)
{
    if (cli_help_asked(argc, argv)) {
        cli_help(k_manual);
        return 0;
    }
    static options_t o;
    static truck_cal_t cal;
    bool have_cal = false;
    char err[512];
    if (truck_cal_take_arg(&argc, argv, &cal, &have_cal, err, sizeof err) != 0) {
        fprintf(stderr, "drivegen: %s\n", err);
        return 2;
    }
    const int prc = parse_args(argc, argv, &o);
    if (prc != 0) {
        return prc;
    }
    road_ppm_t road = {NULL, 0U, 0U};
    if (o.road_path != NULL) {
        if (road_ppm_load(o.road_path, &road, err, sizeof err) != 0) {
            fprintf(stderr, "drivegen: %s\n", err);
            return 2;
        }
    } else if (make_segment_road(&o, &road) != 0) {
        fprintf(stderr, "drivegen: out of memory\n");
        return 2;
    }
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, (uint32_t)o.vehicles, gap_mm_of(&o),
                               &pfe_default_vehicle, &pfe_default_env, &pfe_default_drag);
    for (uint32_t k = 0U; have_cal && (k < cfg.n_vehicles); k++) {
        cfg.vehicle[k] = truck_cal_vehicle(&cal, k, (uint32_t)o.position);
    }
    drive_trace_t drive;
    if (drive_trace_make(road.grade_ppm, road.n_samples, road.spacing_mm, &cfg,
                         (int32_t)lround(o.set_kmh / 3.6 * 1000.0), &drive, err, sizeof err) != 0) {
        fprintf(stderr, "drivegen: %s\n", err);
        road_ppm_free(&road);
        return 2;
    }
    FILE *out = (o.out_path != NULL) ? fopen(o.out_path, "w") : stdout;
    if (out == NULL) {
        fprintf(stderr, "drivegen: cannot write %s: %s\n", o.out_path, strerror(errno));
        drive_trace_free(&drive);
        road_ppm_free(&road);
        return 1;
    }
    int rc = write_drive(&o, &road, &drive, out);
    if (((out != stdout) ? fclose(out) : fflush(out)) != 0) {
        rc = -1;
    }
    if (rc != 0) {
        fprintf(stderr, "drivegen: cannot write %s: %s\n",
                (o.out_path != NULL) ? o.out_path : "standard output", strerror(errno));
    } else if (drive.n_ticks > 0U) {
        fprintf(stderr, "drivegen: %zu ticks, %.2f s, %.1f m, %u road samples\n", drive.n_ticks,
                (double)drive.n_ticks / 100.0, drive.ticks[drive.n_ticks - 1U].position_m,
                road.n_samples);
    }
    drive_trace_free(&drive);
    road_ppm_free(&road);
    return (rc != 0) ? 1 : 0;
}
