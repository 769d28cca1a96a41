/*
 * pfe_ecu_replay - the module's firmware run over a CAN log on the host, in
 * logical time (hal/replay/hal_replay_ecu.h), the log read through
 * sim_host/lib/replay_source.h; its twin on the Cortex-M4 is
 * hal/mps2/main_ecu.c.
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "hal/replay/hal_replay_ecu.h"
#include "lib/replay_source.h"
#include "lib/truck_cal.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: pfe_ecu_replay --log LOG [--record OUT] [--address SA] [--save-interval-ms MS]\n"
    "                      [--vehicles N] [--position P] [--gap-cm D]\n"
    "                      [--format auto|log|printed|printed-delta|asc] [--calib FILE]\n"
    "\n"
    "The module's firmware run over a CAN log on the host, in the log's own time:\n"
    "no bus, no real time, the same result on every machine.\n"
    "\n"
    "  --log LOG              the CAN log\n"
    "  --record OUT           the bus as candump -L would show it, the log's\n"
    "                         frames and the module's (default: none)\n"
    "  --address SA, --save-interval-ms MS, --vehicles N, --position P, --gap-cm D\n"
    "                         as pfe_ecu's (defaults 0x8C, 10000 ms, 1 truck,\n"
    "                         position 0, 1000 cm)\n"
    "  --format F             auto (default: detected from the first lines), log,\n"
    "                         printed, printed-delta, asc\n"
    "  --calib FILE           the truck's calibration file (default: the default\n"
    "                         calibration)\n"
    "  --help                 this help\n"
    "\n"
    "LOG is a CAN log as benches record it: candump -L, candump's printed output\n"
    "with timestamps (-t a, z, A; -t d with --format printed-delta, since it looks\n"
    "like -t z), or Vector ASC. A log recorded mid-drive (no address claims,\n"
    "hundreds of PGNs the module does not read) replays as it is. The ECU ticks\n"
    "every 10 ms of log time from the first frame to one second after the last,\n"
    "with NVM erased at start; a silence of over 10 s (a logger whose clock\n"
    "jumps) is crossed in one jump.\n"
    "FD, remote and error frames are skipped and counted.\n"
    "\n"
    "The Cortex-M4 image build/m4/pfe_ecu_mps2.elf runs the same code on the same\n"
    "log with the same options (scripts/run_m4.sh) and must write the same OUT\n"
    "byte for byte (make check-replay; the image reads candump -L and the printed\n"
    "form, and has its calibration compiled in: make firmware CALIB=FILE).\n"
    "\n"
    "Prints one summary line on standard output, then what identification found\n"
    "(mass, aux power, converged, samples).\n"
    "\n"
    "Exit status: 0; 1 when the log had bad lines (each counted and skipped, the\n"
    "first named on standard error with its file, line and reason) or OUT could\n"
    "not be written; 2 on bad arguments, a log that cannot be read (no such\n"
    "file, a directory, printed output without timestamps) or one with no\n"
    "classic CAN frame (the reason named).\n"
    "\n"
    "Examples:\n"
    "  pfe_ecu_replay --log drive.log --record bus.log\n"
    "  pfe_ecu_replay --log mytruck.log --record bus.log --calib mytruck.cal\n";

#define MAX_ARGS 64

static int32_t write_file(void *ctx, const uint8_t *buf, uint32_t len)
{
    return (fwrite(buf, 1U, len, (FILE *)ctx) == len) ? 0 : -1;
}

/* Takes --format F out of argv (into *format, *kept and argv_kept): the
 * rest is the options every replay of hal_replay_ecu_args() takes. */
static int take_format(int argc, char **argv, char **kept, int *n_kept, canlog_format_t *format)
{
    *format = CANLOG_FMT_AUTO;
    *n_kept = 0;
    for (int i = 0; i < argc; i++) {
        if ((i > 0) && (strcmp(argv[i], "--format") == 0)) {
            if ((i + 1 >= argc) || (canlog_format_parse(argv[i + 1], format) != 0)) {
                fprintf(stderr, "pfe_ecu_replay: --format wants auto, log, printed, "
                                "printed-delta or asc\n");
                return -1;
            }
            i++;
            continue;
        }
        if (*n_kept == MAX_ARGS) {
            fprintf(stderr, "pfe_ecu_replay: more than %d arguments\n", MAX_ARGS);
            return -1;
        }
        kept[(*n_kept)++] = argv[i];
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (cli_help_asked(argc, argv)) {
        cli_help(k_manual);
        return 0;
    }
    static truck_cal_t cal;
    bool have_cal = false;
    char cal_err[TRUCK_CAL_ERR_MAX];
    if (truck_cal_take_arg(&argc, argv, &cal, &have_cal, cal_err, sizeof cal_err) != 0) {
        fprintf(stderr, "pfe_ecu_replay: %s\n", cal_err);
        return 2;
    }
    static char *kept[MAX_ARGS + 1];
    int n_kept = 0;
    canlog_format_t format = CANLOG_FMT_AUTO;
    if (take_format(argc, argv, kept, &n_kept, &format) != 0) {
        cli_usage(stderr, k_manual, "pfe_ecu_replay");
        return 2;
    }
    hal_replay_ecu_args_t args;
    char err[CANLOG_MSG_MAX];
    const int arc = hal_replay_ecu_args(n_kept, kept, &args, err, sizeof err);
    if (arc != 0) {
        if (arc < 0) {
            fprintf(stderr, "pfe_ecu_replay: %s\n", err);
            cli_usage(stderr, k_manual, "pfe_ecu_replay");
        } else {
            cli_help(k_manual);
        }
        return (arc > 0) ? 0 : 2;
    }
    if (have_cal) {
        truck_cal_apply(&cal, &args.cfg);
    }
    static replay_source_t src;
    if (replay_source_open(&src, args.log_path, format, err, sizeof err) != 0) {
        fprintf(stderr, "pfe_ecu_replay: cannot read %s\n", err);
        return 2;
    }
    FILE *out = NULL;
    if (args.record_path != NULL) {
        out = fopen(args.record_path, "wb");
        if (out == NULL) {
            fprintf(stderr, "pfe_ecu_replay: cannot write %s: %s\n", args.record_path,
                    strerror(errno));
            replay_source_close(&src);
            return 2;
        }
    }
    static hal_replay_ecu_t run;
    int status = 0;
    const int rc = hal_replay_ecu_init_source(&run, replay_source_next, &src,
                                              (out != NULL) ? write_file : NULL, out, &args.cfg);
    const hal_replay_stats_t *st = hal_replay_stats(&run.bus);
    if (rc == HAL_ENODEV) {
        fprintf(stderr, "pfe_ecu_replay: %s: no classic CAN frame in the log (%lu lines, %lu bad, "
                        "%lu not classic CAN)%s%s\n",
                args.log_path, (unsigned long)st->lines, (unsigned long)st->bad_lines,
                (unsigned long)st->skipped_not_classic, (st->bad_lines > 0U) ? "; the first bad line: " : "",
                (st->bad_lines > 0U) ? replay_source_first_bad(&src) : "");
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
        if (st->bad_lines > 0U) {
            fprintf(stderr, "pfe_ecu_replay: %lu bad lines skipped; the first: %s\n",
                    (unsigned long)st->bad_lines, replay_source_first_bad(&src));
            status = (status == 0) ? 1 : status;
        }
    }
    if (st->read_failed) {
        fprintf(stderr, "pfe_ecu_replay: %s: read error after line %lu (%s)\n", args.log_path,
                (unsigned long)st->lines, replay_source_message(&src));
        status = (status == 0) ? 1 : status;
    }
    replay_source_close(&src);
    if ((out != NULL) && (fclose(out) != 0) && (status == 0)) {
        fprintf(stderr, "pfe_ecu_replay: cannot write %s: %s\n", args.record_path, strerror(errno));
        status = 1;
    }
    return status;
}
