/*
 * drivegen - a drive as the module would see it on the bus, as a candump log.
 *
 *   drivegen (--road FILE.csv | --segment LEN_M:GRADE_PCT ...) [--set-speed-kmh V]
 *            [--iface IF] [--source SA] [--out LOG]
 *
 * One truck (the double-precision reference model, pfe default calibration)
 * drives the road at its set speed under cruise control; every 100 ms a
 * CCVS1 frame carries its speed (SPN 84, 1/256 km/h) and every 10 ms an SSI
 * frame the road's pitch (SPN 3318, 0.002 deg), encoded with the firmware's
 * codec (can_dbc/pfe.dbc). Lines are candump's log format,
 * "(seconds.micro) IF ID#DATA", starting at 1700000000.000000.
 * Exit status 0, 2 on bad arguments or input.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../firmware/pfe_calib.h"
#include "../firmware/pfe_codec.h"
#include "../firmware/pfe_platoon.h"
#include "drive_trace.h"
#include "road_csv.h"

#define MAX_SEGMENTS 64
#define SEGMENT_SPACING_MM 10000U
#define T0_S 1700000000ULL

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

int main(int argc, char **argv)
{
    const char *road_path = NULL, *out_path = NULL, *ifname = "vcan0";
    double set_kmh = 90.0;
    unsigned long source = 0U;
    double seg_len[MAX_SEGMENTS], seg_grade[MAX_SEGMENTS];
    int n_seg = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
        const char *a = argv[i], *v = argv[i + 1];
        char *end = NULL;
        if (strcmp(a, "--road") == 0) {
            road_path = v;
        } else if (strcmp(a, "--out") == 0) {
            out_path = v;
        } else if (strcmp(a, "--iface") == 0) {
            ifname = v;
        } else if (strcmp(a, "--source") == 0) {
            source = strtoul(v, &end, 0);
            if ((*end != '\0') || (source > 253U)) {
                fprintf(stderr, "drivegen: bad --source '%s'\n", v);
                return 2;
            }
        } else if (strcmp(a, "--set-speed-kmh") == 0) {
            set_kmh = strtod(v, &end);
            if ((*end != '\0') || !(set_kmh >= 5.0) || !(set_kmh <= 250.0)) {
                fprintf(stderr, "drivegen: bad --set-speed-kmh '%s'\n", v);
                return 2;
            }
        } else if ((strcmp(a, "--segment") == 0) && (n_seg < MAX_SEGMENTS)) {
            if ((sscanf(v, "%lf:%lf", &seg_len[n_seg], &seg_grade[n_seg]) != 2) ||
                !(seg_len[n_seg] >= 10.0) || !(fabs(seg_grade[n_seg]) <= 30.0)) {
                fprintf(stderr, "drivegen: bad --segment '%s' (LEN_M:GRADE_PCT)\n", v);
                return 2;
            }
            n_seg++;
        } else {
            fprintf(stderr, "drivegen: unknown option '%s'\n", a);
            return 2;
        }
    }
    if ((road_path == NULL) == (n_seg == 0)) {
        fprintf(stderr, "usage: drivegen (--road FILE.csv | --segment LEN_M:GRADE_PCT ...) "
                        "[--set-speed-kmh V] [--iface IF] [--source SA] [--out LOG]\n");
        return 2;
    }
    char err[512];
    road_ppm_t road = {NULL, 0U, 0U};
    if (road_path != NULL) {
        if (road_ppm_load(road_path, &road, err, sizeof err) != 0) {
            fprintf(stderr, "drivegen: %s\n", err);
            return 2;
        }
    } else {
        double total = 0.0;
        for (int s = 0; s < n_seg; s++) {
            total += seg_len[s];
        }
        road.n_samples = (uint32_t)ceil(total / (SEGMENT_SPACING_MM / 1000.0));
        road.spacing_mm = SEGMENT_SPACING_MM;
        road.grade_ppm = malloc(sizeof(int32_t) * road.n_samples);
        if (road.grade_ppm == NULL) {
            fprintf(stderr, "drivegen: out of memory\n");
            return 2;
        }
        for (uint32_t k = 0U; k < road.n_samples; k++) {
            double at = k * (SEGMENT_SPACING_MM / 1000.0), edge = 0.0;
            int s = 0;
            while ((s < n_seg - 1) && (at >= edge + seg_len[s])) {
                edge += seg_len[s];
                s++;
            }
            road.grade_ppm[k] = (int32_t)lround(seg_grade[s] * 10000.0);
        }
    }
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, 1U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    drive_trace_t drive;
    if (drive_trace_make(road.grade_ppm, road.n_samples, road.spacing_mm, &cfg,
                         (int32_t)lround(set_kmh / 3.6 * 1000.0), &drive, err, sizeof err) != 0) {
        fprintf(stderr, "drivegen: %s\n", err);
        road_ppm_free(&road);
        return 2;
    }
    FILE *out = (out_path != NULL) ? fopen(out_path, "w") : stdout;
    if (out == NULL) {
        fprintf(stderr, "drivegen: cannot write %s: %s\n", out_path, strerror(errno));
        return 2;
    }
    for (size_t k = 0U; k < drive.n_ticks; k++) {
        const drive_tick_t *t = &drive.ticks[k];
        const uint64_t t_us = (uint64_t)k * 10000U;
        pfe_can_frame_t f;
        if (t->speed_fresh) {
            const pfe_msg_ccvs1_t m = {{t->speed_mm_s, PFE_SIG_VALID}};
            (void)pfe_codec_encode_ccvs1(&f, &m, (uint8_t)source);
            print_frame(out, t_us, ifname, &f);
        }
        const double pitch_deg = atan(t->grade_ppm / 1e6) * 180.0 / 3.14159265358979323846;
        const pfe_msg_ssi_t s = {{(int32_t)lround(pitch_deg * 1e6), PFE_SIG_VALID},
                                 {0, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}};
        (void)pfe_codec_encode_ssi(&f, &s, (uint8_t)source);
        print_frame(out, t_us, ifname, &f);
    }
    if (out != stdout) {
        fclose(out);
    }
    fprintf(stderr, "drivegen: %zu ticks, %.1f s, %u road samples\n", drive.n_ticks,
            (double)drive.n_ticks / 100.0, road.n_samples);
    drive_trace_free(&drive);
    road_ppm_free(&road);
    return 0;
}
