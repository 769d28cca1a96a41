/*
 * ecu_offline - the bus a drive log would give with the module on it, made
 * without a bus: the firmware's ECU loop (firmware/pfe_ecu.h) run in
 * simulated time on the log's frames.
 *
 *   ecu_offline DRIVE.log CAPTURE.log [--phase-us P] [--scale-fuel F]
 *
 * Writes CAPTURE.log in candump's log format: every frame of DRIVE.log
 * (J1939 frames only, read by sim_host/lib/capture.h) at its own time, and the
 * module's answers (source address 0x8C) 100 us after each tick. The ECU
 * starts 1 s before the first frame, ticks every 10 ms with its first tick P
 * microseconds after that (default 3000), receives each frame at the first
 * tick after it, and stops 1.5 s after the last frame, as scripts/run_drive.sh
 * runs the real one. --scale-fuel F multiplies every fuel rate and total the
 * module sends, and its predicted fuel and bounds, by F (default 1): a module that is F - 1 wrong, for the tests
 * that must see run_report fail.
 *
 * For tests of run_report (tests/host/run_report_test.sh): no vcan, no
 * timing noise, the same capture on every run. Exit status 0, 2 on bad input.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/pfe_calib.h"
#include "firmware/pfe_codec.h"
#include "firmware/pfe_ecu.h"
#include "lib/capture.h"

#define START_BEFORE_US 1000000U
#define STOP_AFTER_US 1500000U
#define TX_DELAY_US 100U

static void print_frame(FILE *out, uint64_t t_us, const pfe_can_frame_t *f)
{
    fprintf(out, "(%010llu.%06llu) vcan0 %08lX#", (unsigned long long)(t_us / 1000000U),
            (unsigned long long)(t_us % 1000000U), (unsigned long)(f->id & PFE_CAN_ID_MASK));
    for (uint8_t k = 0U; k < f->dlc; k++) {
        fprintf(out, "%02X", f->data[k]);
    }
    fputc('\n', out);
}

/* A module that is wrong by a factor: fuel fields re-encoded scaled. */
static void scale_fuel(pfe_can_frame_t *f, double k)
{
    const uint32_t pgn = pfe_j1939_pgn(f->id);
    const uint8_t sa = pfe_j1939_source(f->id);
    if (pgn == PFE_PGN_LFE1) {
        pfe_msg_lfe1_t m;
        if ((pfe_codec_decode_lfe1(f, &m) >= 0) && (m.fuel_rate_nl_s.state == PFE_SIG_VALID)) {
            m.fuel_rate_nl_s.value = (uint32_t)lround(m.fuel_rate_nl_s.value * k);
            (void)pfe_codec_encode_lfe1(f, &m, sa);
        }
    } else if (pgn == PFE_PGN_HRLFC) {
        pfe_msg_hrlfc_t m;
        if ((pfe_codec_decode_hrlfc(f, &m) >= 0) && (m.total_fuel_ul.state == PFE_SIG_VALID)) {
            m.total_fuel_ul.value = (uint64_t)llround((double)m.total_fuel_ul.value * k);
            (void)pfe_codec_encode_hrlfc(f, &m, sa);
        }
    } else if (pgn == PFE_PGN_OWN_FUEL) {
        pfe_msg_own_fuel_t m;
        if (pfe_codec_decode_own_fuel(f, &m) >= 0) {
            m.fuel_rate_nl_s.value = (uint32_t)lround(m.fuel_rate_nl_s.value * k);
            m.fuel_used_ul.value = (uint64_t)llround((double)m.fuel_used_ul.value * k);
            (void)pfe_codec_encode_own_fuel(f, &m, sa);
        }
    } else if (pgn == PFE_PGN_PLATOON_FUEL) {
        pfe_msg_platoon_fuel_t m;
        if (pfe_codec_decode_platoon_fuel(f, &m) >= 0) {
            m.fuel_rate_nl_s.value = (uint32_t)lround(m.fuel_rate_nl_s.value * k);
            m.fuel_used_ul.value = (uint64_t)llround((double)m.fuel_used_ul.value * k);
            (void)pfe_codec_encode_platoon_fuel(f, &m, sa);
        }
    } else if (pgn == PFE_PGN_FUEL_PREDICTION) {
        pfe_msg_fuel_prediction_t m;
        if ((pfe_codec_decode_fuel_prediction(f, &m) >= 0) && (m.fuel_ul.state == PFE_SIG_VALID)) {
            m.fuel_ul.value = (uint32_t)lround(m.fuel_ul.value * k);
            m.fuel_lower_ul.value = (uint32_t)lround(m.fuel_lower_ul.value * k);
            m.fuel_upper_ul.value = (uint32_t)lround(m.fuel_upper_ul.value * k);
            (void)pfe_codec_encode_fuel_prediction(f, &m, sa);
        }
    }
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: ecu_offline DRIVE.log CAPTURE.log [--phase-us P] [--scale-fuel F]\n");
        return 2;
    }
    unsigned long phase_us = 3000U;
    double scale = 1.0;
    for (int i = 3; i + 1 < argc; i += 2) {
        char *end = NULL;
        if (strcmp(argv[i], "--phase-us") == 0) {
            phase_us = strtoul(argv[i + 1], &end, 10);
            if ((*end != '\0') || (phase_us >= PFE_ECU_TICK_US)) {
                fprintf(stderr, "ecu_offline: bad --phase-us '%s'\n", argv[i + 1]);
                return 2;
            }
        } else if (strcmp(argv[i], "--scale-fuel") == 0) {
            scale = strtod(argv[i + 1], &end);
            if ((*end != '\0') || !(scale > 0.0) || !(scale < 10.0)) {
                fprintf(stderr, "ecu_offline: bad --scale-fuel '%s'\n", argv[i + 1]);
                return 2;
            }
        } else {
            fprintf(stderr, "ecu_offline: unknown option '%s'\n", argv[i]);
            return 2;
        }
    }
    char err[512];
    capture_t drive;
    if (capture_load(argv[1], &drive, err, sizeof err) != 0) {
        fprintf(stderr, "ecu_offline: %s\n", err);
        return 2;
    }
    if (drive.n == 0U) {
        fprintf(stderr, "ecu_offline: %s: no J1939 frames\n", argv[1]);
        capture_free(&drive);
        return 2;
    }
    FILE *out = fopen(argv[2], "w");
    if (out == NULL) {
        perror(argv[2]);
        capture_free(&drive);
        return 2;
    }
    const pfe_ecu_config_t cfg = {
        .preferred_address = PFE_ECU_DEFAULT_ADDRESS,
        .name = 0x80A0000000000001ULL | ((uint64_t)PFE_ECU_DEFAULT_ADDRESS << 1),
        .save_interval_ms = 10000U,
        .vehicle = &pfe_default_vehicle,
        .env = &pfe_default_env,
        .drag = &pfe_default_drag,
        .default_vehicles = 1U,
        .default_position = 0U,
        .default_gap_mm = 10000U,
        .cruise = &pfe_default_cruise,
        .default_set_speed_mm_s = PFE_ECU_DEFAULT_SET_SPEED_MM_S,
    };
    static pfe_ecu_t ecu;
    const uint64_t start_us = drive.recs[0].t_us - START_BEFORE_US;
    const uint64_t end_us = drive.recs[drive.n - 1U].t_us + STOP_AFTER_US;
    if (pfe_ecu_init(&ecu, &cfg, NULL, -1, start_us) != PFE_OK) {
        fprintf(stderr, "ecu_offline: invalid configuration\n");
        fclose(out);
        capture_free(&drive);
        return 2;
    }
    size_t next = 0U, printed = 0U;
    unsigned long sent = 0U;
    for (uint64_t tick_us = start_us + phase_us; tick_us <= end_us; tick_us += PFE_ECU_TICK_US) {
        while ((next < drive.n) && (drive.recs[next].t_us < tick_us)) {
            pfe_ecu_receive(&ecu, &drive.recs[next].f, tick_us);
            next++;
        }
        pfe_can_frame_t tx[PFE_ECU_TX_MAX];
        const uint32_t n = pfe_ecu_tick(&ecu, tick_us, tx, PFE_ECU_TX_MAX);
        /* Lines in time order: inputs up to the answers' time first. */
        while ((printed < drive.n) && (drive.recs[printed].t_us <= tick_us + TX_DELAY_US)) {
            print_frame(out, drive.recs[printed].t_us, &drive.recs[printed].f);
            printed++;
        }
        for (uint32_t k = 0U; k < n; k++) {
            if (scale != 1.0) {
                scale_fuel(&tx[k], scale);
            }
            print_frame(out, tick_us + TX_DELAY_US, &tx[k]);
            sent++;
        }
    }
    const int bad = ferror(out) | fclose(out);
    fprintf(stderr, "ecu_offline: %zu input frames, %lu module frames, %llu uL own fuel\n", drive.n,
            sent, (unsigned long long)pfe_ecu_own_fuel_ul(&ecu));
    capture_free(&drive);
    if (bad != 0) {
        fprintf(stderr, "ecu_offline: cannot write %s\n", argv[2]);
        return 2;
    }
    return 0;
}
