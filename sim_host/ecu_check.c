/*
 * ecu_check - judge a module's answers on a recorded bus against the
 * double-precision reference.
 *
 *   ecu_check CAPTURE.log [--module-sa SA] [--warmup-s S]
 *
 * CAPTURE is one candump log (`candump -L`) of everything on the bus: the
 * drive's CCVS1 and SSI frames and the module's answers (source address
 * SA, default 0x8C). The reference estimator (sim_host/ref_model.c, one
 * truck, default calibration) steps every 10 ms on the same input frames.
 * Checked from the warm-up to the last input frame (after it the module's
 * inputs time out, as they should):
 *   every LFE1 fuel rate within 1 % of the reference at its time: the best
 *     of the reference ticks in the HISTORY_TICKS * 10 ms before it, since
 *     the module's tick phase is not in the capture and a late tick of a
 *     loaded host sends a frame up to a few ticks after its estimate; and
 *     never "not available";
 *   the last HRLFC total fuel used within 0.5 % of the reference's.
 * Prints the figures; exit status 0 pass, 1 fail, 2 bad input.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../firmware/pfe_calib.h"
#include "../firmware/pfe_can.h"
#include "../firmware/pfe_codec.h"
#include "../firmware/pfe_platoon.h"
#include "ref_model.h"

#define MAX_FRAMES 200000U
#define HISTORY_TICKS 6U

typedef struct {
    uint64_t t_us;
    pfe_can_frame_t f;
} cap_t;

static int hexval(char c)
{
    if ((c >= '0') && (c <= '9')) {
        return c - '0';
    }
    if ((c >= 'A') && (c <= 'F')) {
        return c - 'A' + 10;
    }
    if ((c >= 'a') && (c <= 'f')) {
        return c - 'a' + 10;
    }
    return -1;
}

/* "(sec.usec) iface ID#DATA": 0 or -1. */
static int parse_line(const char *line, cap_t *out)
{
    unsigned long long sec = 0U, usec = 0U;
    char ifname[32], frame[64];
    if (sscanf(line, "(%llu.%6llu) %31s %63s", &sec, &usec, ifname, frame) != 4) {
        return -1;
    }
    const char *hash = strchr(frame, '#');
    if ((hash == NULL) || ((hash - frame) != 8)) {
        return -1;
    }
    uint32_t id = 0U;
    for (const char *p = frame; p < hash; p++) {
        const int h = hexval(*p);
        if (h < 0) {
            return -1;
        }
        id = (id << 4) | (uint32_t)h;
    }
    const char *d = hash + 1;
    const size_t n = strlen(d);
    if (((n % 2U) != 0U) || (n > 16U) || (id > PFE_CAN_ID_MASK)) {
        return -1;
    }
    out->f.id = id | PFE_CAN_EFF_FLAG;
    out->f.dlc = (uint8_t)(n / 2U);
    for (size_t k = 0U; k < n / 2U; k++) {
        const int hi = hexval(d[2U * k]), lo = hexval(d[(2U * k) + 1U]);
        if ((hi < 0) || (lo < 0)) {
            return -1;
        }
        out->f.data[k] = (uint8_t)((hi << 4) | lo);
    }
    out->t_us = (sec * 1000000U) + usec;
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: ecu_check CAPTURE.log [--module-sa SA] [--warmup-s S]\n");
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
    FILE *in = fopen(argv[1], "r");
    if (in == NULL) {
        perror(argv[1]);
        return 2;
    }
    cap_t *cap = malloc(sizeof(cap_t) * MAX_FRAMES);
    size_t n = 0U;
    char line[256];
    unsigned long lineno = 0U;
    while ((cap != NULL) && (fgets(line, sizeof line, in) != NULL) && (n < MAX_FRAMES)) {
        lineno++;
        if (parse_line(line, &cap[n]) != 0) {
            fprintf(stderr, "ecu_check: %s:%lu: not a candump log line\n", argv[1], lineno);
            fclose(in);
            free(cap);
            return 2;
        }
        n++;
    }
    fclose(in);
    if ((cap == NULL) || (n == 0U)) {
        fprintf(stderr, "ecu_check: %s: no frames\n", argv[1]);
        free(cap);
        return 2;
    }
    uint64_t t_last_input = 0U;
    for (size_t k = 0U; k < n; k++) {
        if (pfe_j1939_source(cap[k].f.id) != module_sa) {
            t_last_input = cap[k].t_us;
        }
    }
    /* The reference on the input frames, one tick every 10 ms from the first. */
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, 1U, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    static ref_platoon_t rpl;
    static ref_estimator_t ref;
    (void)ref_platoon_init(&rpl, &cfg);
    ref_estimator_init(&ref, &rpl);
    uint64_t t0 = 0U;
    bool started = false;
    double speed = 0.0, grade = 0.0;
    bool have_speed = false, have_grade = false, fresh = false;
    double history[HISTORY_TICKS] = {0.0};
    uint32_t ticks = 0U;
    double used = 0.0, tick_t = 0.0;
    size_t lfe1 = 0U, lfe1_na = 0U, hrlfc = 0U;
    double worst = 0.0, last_total_l = -1.0, ref_at_total = 0.0;
    for (size_t k = 0U; k < n; k++) {
        const cap_t *c = &cap[k];
        const uint8_t sa = pfe_j1939_source(c->f.id);
        const uint32_t pgn = pfe_j1939_pgn(c->f.id);
        if (sa != module_sa) {
            if (!started) {
                t0 = c->t_us;
                started = true;
                tick_t = 0.0;
            }
            /* Step the reference up to this frame's time. */
            const double t = (double)(c->t_us - t0) / 1e6;
            while (tick_t + 0.01 <= t + 1e-9) {
                ref_estimator_step(&ref, speed, have_speed, fresh, grade, have_grade);
                fresh = false;
                history[ticks % HISTORY_TICKS] = ref.pos_fuel_rate[0];
                ticks++;
                used = ref.pos_fuel_used[0];
                tick_t += 0.01;
            }
            if (pgn == PFE_PGN_CCVS1) {
                pfe_msg_ccvs1_t m;
                if ((pfe_codec_decode_ccvs1(&c->f, &m) >= 0) && (m.speed_mm_s.state == PFE_SIG_VALID)) {
                    speed = m.speed_mm_s.value / 1000.0;
                    have_speed = true;
                    fresh = true;
                }
            } else if (pgn == PFE_PGN_SSI) {
                pfe_msg_ssi_t m;
                if ((pfe_codec_decode_ssi(&c->f, &m) >= 0) && (m.pitch_udeg.state == PFE_SIG_VALID)) {
                    grade = tan(m.pitch_udeg.value / 1e6 * 3.14159265358979323846 / 180.0);
                    have_grade = true;
                }
            }
            continue;
        }
        if (!started || ((double)(c->t_us - t0) / 1e6 < warmup_s) || (c->t_us > t_last_input)) {
            continue;
        }
        if (pgn == PFE_PGN_LFE1) {
            pfe_msg_lfe1_t m;
            if (pfe_codec_decode_lfe1(&c->f, &m) < 0) {
                continue;
            }
            lfe1++;
            if (m.fuel_rate_nl_s.state != PFE_SIG_VALID) {
                lfe1_na++;
                continue;
            }
            const double got = m.fuel_rate_nl_s.value / 1e9; /* L/s */
            double e = INFINITY;
            for (uint32_t h = 0U; h < HISTORY_TICKS; h++) {
                if (history[h] > 0.0) {
                    e = fmin(e, fabs(got - history[h]) / history[h]);
                }
            }
            worst = fmax(worst, e);
        } else if (pgn == PFE_PGN_HRLFC) {
            pfe_msg_hrlfc_t m;
            if ((pfe_codec_decode_hrlfc(&c->f, &m) >= 0) && (m.total_fuel_ul.state == PFE_SIG_VALID)) {
                hrlfc++;
                last_total_l = (double)m.total_fuel_ul.value / 1e6;
                ref_at_total = used;
            }
        }
    }
    free(cap);
    const double total_err = (ref_at_total > 0.0) ? fabs(last_total_l - ref_at_total) / ref_at_total : 1.0;
    printf("ecu_check: %zu frames; after %.1f s warm-up: %zu LFE1 (%zu not available), worst rate "
           "error %.3f %% (limit 1 %%); last HRLFC %.3f L against reference %.4f L, error %.3f %% "
           "(limit 0.5 %%, %zu HRLFC frames)\n",
           n, warmup_s, lfe1, lfe1_na, 100.0 * worst, last_total_l, ref_at_total,
           100.0 * total_err, hrlfc);
    const bool pass = (lfe1 > 0U) && (lfe1_na == 0U) && (worst <= 0.01) && (hrlfc > 0U) &&
                      (total_err <= 0.005);
    printf("ecu_check: %s\n", pass ? "PASS" : "FAIL");
    return pass ? 0 : 1;
}
