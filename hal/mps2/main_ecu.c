/*
 * main_ecu.c - the module's firmware image on the emulated Cortex-M4
 * (mps2-an386) running a drive from a CAN log.
 *
 *   scripts/run_m4.sh build/m4/pfe_ecu_mps2.elf --log LOG [--record OUT] [options]
 *
 * The same run as the host's pfe_ecu_replay (hal/replay/hal_replay_ecu.h,
 * same options): LOG is read and OUT written on the host through
 * semihosting (hal/mps2/semihost.h), the ECU ticks in the log's time; LOG
 * is candump -L or candump's printed output with timestamps (hal/replay's
 * own parser, held to the host's by tests/replay/log_vectors.h). Prints
 * the run's summary line, then the instructions (QEMU -icount, 40 a count)
 * of the ECU's tick (hal_ecu_loop_step(): receive, decode, estimate,
 * encode, send, NVM) and of feeding the bus (reading and parsing the log,
 * writing the record) apart, mean and worst per 10 ms:
 *   "m4: ticks K ecu_tick_insn_mean M ecu_tick_insn_max X feed_insn_mean F feed_insn_max G"
 * The truck calibration is compiled in (hal/mps2/image_calib.h): the
 * image built with CALIB=FILE runs as pfe_ecu_replay --calib FILE.
 * Exit status as pfe_ecu_replay: 0; 1 bad log lines or a failed record; 2
 * bad arguments, an unreadable log or one without frames.
 */
#include <stddef.h>
#include <stdint.h>

#include "hal/mps2/icount.h"
#include "hal/mps2/image_calib.h"
#include "hal/mps2/semihost.h"
#include "hal/replay/hal_replay_ecu.h"

#define CMDLINE_MAX 512U
#define ARGS_MAX 24U

static hal_replay_ecu_t s_run;

static int32_t read_host(void *ctx, uint8_t *buf, uint32_t len)
{
    return hal_mps2_file_read(*(const int32_t *)ctx, buf, len);
}

static int32_t write_host(void *ctx, const uint8_t *buf, uint32_t len)
{
    return hal_mps2_file_write(*(const int32_t *)ctx, buf, len);
}

static void say(const char *a, const char *b, const char *c)
{
    hal_mps2_write_str("pfe_ecu_mps2: ");
    hal_mps2_write_str(a);
    hal_mps2_write_str(b);
    hal_mps2_write_str(c);
    hal_mps2_write_str("\n");
}

/* Splits the command line at spaces, in place. */
static int split(char *line, char *argv[], int max)
{
    int argc = 0;
    char *p = line;
    while (*p != '\0') {
        while (*p == ' ') {
            *p++ = '\0';
        }
        if (*p == '\0') {
            break;
        }
        if (argc == max) {
            return -1;
        }
        argv[argc++] = p;
        while ((*p != ' ') && (*p != '\0')) {
            p++;
        }
    }
    return argc;
}

int main(void)
{
    static char cmdline[CMDLINE_MAX];
    char *argv[ARGS_MAX];
    int argc = -1;
    if (hal_mps2_get_cmdline(cmdline, CMDLINE_MAX) >= 0) {
        argc = split(cmdline, argv, (int)ARGS_MAX);
    }
    if (argc < 0) {
        say("no command line from the emulator, or too long", "", "");
        return 2;
    }
    hal_replay_ecu_args_t args;
    char err[160];
    const int arc = hal_replay_ecu_args(argc, argv, &args, err, sizeof err);
    if (arc != 0) {
        if (arc < 0) {
            say(err, "", "");
        }
        say("usage: pfe_ecu_mps2 ", HAL_REPLAY_ECU_USAGE, "");
        return (arc > 0) ? 0 : 2;
    }
    /* The truck's calibration is compiled in (make firmware CALIB=FILE). */
    image_calib_apply(&args.cfg);
    static int32_t in;
    static int32_t out = -1;
    in = hal_mps2_file_open(args.log_path, HAL_MPS2_FILE_READ);
    if (in < 0) {
        say("cannot read ", args.log_path, "");
        return 2;
    }
    if (args.record_path != NULL) {
        out = hal_mps2_file_open(args.record_path, HAL_MPS2_FILE_WRITE);
        if (out < 0) {
            say("cannot write ", args.record_path, "");
            return 2;
        }
    }
    int status = 0;
    const int rc = hal_replay_ecu_init(&s_run, read_host, &in, (out >= 0) ? write_host : NULL,
                                       &out, &args.cfg);
    const hal_replay_stats_t *st = hal_replay_stats(&s_run.bus);
    if (rc == HAL_ENODEV) {
        hal_mps2_write_str("pfe_ecu_mps2: ");
        hal_mps2_write_str(args.log_path);
        hal_mps2_write_str(": no classic CAN frame in the log (");
        hal_mps2_write_u32(st->lines);
        hal_mps2_write_str(" lines, ");
        hal_mps2_write_u32(st->bad_lines);
        hal_mps2_write_str(" bad");
        if (st->bad_lines > 0U) {
            hal_mps2_write_str("; the first, line ");
            hal_mps2_write_u32(st->first_bad_line);
            hal_mps2_write_str(": ");
            hal_mps2_write_str(hal_replay_reason_text(st->first_bad_reason));
        }
        hal_mps2_write_str(")\n");
        status = 2;
    } else if (rc != 0) {
        say("the ECU refuses this configuration", "", "");
        status = 2;
    } else {
        uint64_t feed_total = 0U;
        uint64_t feed_worst = 0U;
        uint64_t tick_total = 0U;
        uint64_t tick_worst = 0U;
        hal_mps2_icount_start();
        for (;;) {
            const uint64_t t0 = hal_mps2_icount_now();
            if (!hal_replay_ecu_feed(&s_run)) {
                break;
            }
            const uint64_t t1 = hal_mps2_icount_now();
            hal_replay_ecu_tick(&s_run);
            const uint64_t t2 = hal_mps2_icount_now();
            feed_total += t1 - t0;
            feed_worst = ((t1 - t0) > feed_worst) ? (t1 - t0) : feed_worst;
            tick_total += t2 - t1;
            tick_worst = ((t2 - t1) > tick_worst) ? (t2 - t1) : tick_worst;
        }
        if (hal_replay_ecu_finish(&s_run) != 0) {
            say("cannot write ", args.record_path, "");
            status = 1;
        }
        static char summary[HAL_REPLAY_ECU_SUMMARY_MAX];
        (void)hal_replay_ecu_summary(&s_run, summary, sizeof summary);
        hal_mps2_write_str(summary);
        const uint32_t n = (s_run.ticks > 0U) ? s_run.ticks : 1U;
        hal_mps2_write_str("m4: ticks ");
        hal_mps2_write_u32(s_run.ticks);
        hal_mps2_write_str(" ecu_tick_insn_mean ");
        hal_mps2_write_u64(tick_total / n);
        hal_mps2_write_str(" ecu_tick_insn_max ");
        hal_mps2_write_u64(tick_worst);
        hal_mps2_write_str(" feed_insn_mean ");
        hal_mps2_write_u64(feed_total / n);
        hal_mps2_write_str(" feed_insn_max ");
        hal_mps2_write_u64(feed_worst);
        hal_mps2_write_str("\n");
    }
    if (st->read_failed) {
        say(args.log_path, ": read error", "");
        status = (status == 0) ? 1 : status;
    }
    if (st->bad_lines > 0U) {
        hal_mps2_write_str("pfe_ecu_mps2: ");
        hal_mps2_write_str(args.log_path);
        hal_mps2_write_str(": ");
        hal_mps2_write_u32(st->bad_lines);
        hal_mps2_write_str(" bad lines skipped; the first, line ");
        hal_mps2_write_u32(st->first_bad_line);
        hal_mps2_write_str(": ");
        hal_mps2_write_str(hal_replay_reason_text(st->first_bad_reason));
        hal_mps2_write_str("\n");
        status = (status == 0) ? 1 : status;
    }
    (void)hal_mps2_file_close(in);
    if ((out >= 0) && (hal_mps2_file_close(out) != 0) && (status == 0)) {
        status = 1;
    }
    return status;
}
