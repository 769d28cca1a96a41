/*
 * pfe_ecu_replay - the module's firmware run over a CAN log on the host, in
 * logical time (hal/replay/hal_replay_ecu.h).
 *
 *   pfe_ecu_replay --log LOG [--record OUT] [--address SA] [--save-interval-ms MS]
 *                  [--vehicles N] [--position P] [--gap-cm D] [--calib FILE]
 *
 * FILE is the truck's calibration (sim_host/truck_cal.h; default: the
 * default calibration); the Cortex-M4 image has it compiled in instead
 * (sim_host/cal2c.c). LOG is a candump log (`candump -L`). The ECU ticks every 10 ms of log
 * time from the first frame to one second after the last, with NVM erased at
 * start; OUT (default: none) receives the bus as candump -L would show it,
 * the log's frames and the module's. The Cortex-M4 image
 * build/m4/pfe_ecu_mps2.elf runs the same code on the same log with the
 * same options and must write the same OUT byte for byte (make
 * check-replay).
 *
 * Prints one summary line on standard output (hal_replay_ecu_summary()).
 * Exit status: 0; 1 when the log had bad lines (each counted and skipped,
 * the first named on standard error) or OUT could not be written; 2 on bad
 * arguments, an unreadable log or one with no frame.
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "hal/replay/hal_replay_ecu.h"
#include "sim_host/truck_cal.h"

static int32_t read_file(void *ctx, uint8_t *buf, uint32_t len)
{
    FILE *f = ctx;
    const size_t got = fread(buf, 1U, len, f);
    if ((got == 0U) && ferror(f)) {
        return -1;
    }
    return (int32_t)got;
}

static int32_t write_file(void *ctx, const uint8_t *buf, uint32_t len)
{
    return (fwrite(buf, 1U, len, (FILE *)ctx) == len) ? 0 : -1;
}

int main(int argc, char **argv)
{
    static truck_cal_t cal;
    bool have_cal = false;
    char cal_err[TRUCK_CAL_ERR_MAX];
    if (truck_cal_take_arg(&argc, argv, &cal, &have_cal, cal_err, sizeof cal_err) != 0) {
        fprintf(stderr, "pfe_ecu_replay: %s\n", cal_err);
        return 2;
    }
    hal_replay_ecu_args_t args;
    char err[160];
    const int arc = hal_replay_ecu_args(argc, argv, &args, err, sizeof err);
    if (arc != 0) {
        FILE *f = (arc > 0) ? stdout : stderr;
        if (arc < 0) {
            fprintf(stderr, "pfe_ecu_replay: %s\n", err);
        }
        fprintf(f, "usage: pfe_ecu_replay " HAL_REPLAY_ECU_USAGE " [--calib FILE]\n");
        return (arc > 0) ? 0 : 2;
    }
    if (have_cal) {
        truck_cal_apply(&cal, &args.cfg);
    }
    FILE *in = fopen(args.log_path, "rb");
    if (in == NULL) {
        fprintf(stderr, "pfe_ecu_replay: cannot read %s: %s\n", args.log_path, strerror(errno));
        return 2;
    }
    FILE *out = NULL;
    if (args.record_path != NULL) {
        out = fopen(args.record_path, "wb");
        if (out == NULL) {
            fprintf(stderr, "pfe_ecu_replay: cannot write %s: %s\n", args.record_path,
                    strerror(errno));
            fclose(in);
            return 2;
        }
    }
    static hal_replay_ecu_t run;
    int status = 0;
    const int rc = hal_replay_ecu_init(&run, read_file, in, (out != NULL) ? write_file : NULL, out,
                                       &args.cfg);
    const hal_replay_stats_t *st = hal_replay_stats(&run.bus);
    if (rc == HAL_ENODEV) {
        fprintf(stderr, "pfe_ecu_replay: %s: no classic CAN frame in the log (%lu lines, %lu bad)\n",
                args.log_path, (unsigned long)st->lines, (unsigned long)st->bad_lines);
        status = 2;
    } else if (rc != 0) {
        fprintf(stderr, "pfe_ecu_replay: the ECU refuses this configuration\n");
        status = 2;
    } else {
        while (hal_replay_ecu_step(&run)) {
        }
        if (hal_replay_ecu_finish(&run) != 0) {
            fprintf(stderr, "pfe_ecu_replay: cannot write %s\n", args.record_path);
            status = 1;
        }
        char summary[HAL_REPLAY_ECU_SUMMARY_MAX];
        (void)hal_replay_ecu_summary(&run, summary, sizeof summary);
        fputs(summary, stdout);
        const pfe_identify_t *id = &run.ecu.identify;
        const pfe_identify_counters_t *ic = pfe_identify_counters(id);
        printf("pfe_ecu_replay: identification: mass %lu kg, aux power %lu W, %s; samples %lu used, "
               "%lu rejected; windows %lu used, %lu rejected; %lu mass updates\n",
               (unsigned long)pfe_identify_mass_kg(id), (unsigned long)pfe_identify_aux_power_w(id),
               pfe_identify_converged(id) ? "converged" : "not converged",
               (unsigned long)ic->samples_used, (unsigned long)ic->samples_rejected,
               (unsigned long)ic->windows_used, (unsigned long)ic->windows_rejected,
               (unsigned long)ic->mass_updates);
    }
    if (st->read_failed) {
        fprintf(stderr, "pfe_ecu_replay: %s: read error after line %lu\n", args.log_path,
                (unsigned long)st->lines);
        status = (status == 0) ? 1 : status;
    }
    if (st->bad_lines > 0U) {
        fprintf(stderr, "pfe_ecu_replay: %s: %lu bad lines skipped; the first, line %lu: %s\n",
                args.log_path, (unsigned long)st->bad_lines, (unsigned long)st->first_bad_line,
                hal_replay_reason_text(st->first_bad_reason));
        status = (status == 0) ? 1 : status;
    }
    fclose(in);
    if ((out != NULL) && (fclose(out) != 0) && (status == 0)) {
        fprintf(stderr, "pfe_ecu_replay: cannot write %s: %s\n", args.record_path, strerror(errno));
        status = 1;
    }
    return status;
}
