/* hal_replay_ecu.c - the ECU run over a replayed log (contract in hal_replay_ecu.h). */
#include "hal/replay/hal_replay_ecu.h"

#include <stddef.h>
#include <string.h>

#include "firmware/pfe_fixed.h"
#include "firmware/pfe_platoon.h"

/* The ECU's start on a bus already opened on its log. */
static int start_on_bus(hal_replay_ecu_t *run, const pfe_ecu_config_t *cfg)
{
    hal_replay_nvm_init(&run->nvm);
    uint64_t first_us = 0U;
    if (!hal_replay_next_us(&run->bus, &first_us)) {
        return HAL_ENODEV;
    }
    run->can = hal_replay_open(&run->bus);
    run->now_us = first_us;
    return hal_ecu_loop_init(&run->loop, &run->ecu, cfg, run->can, &run->nvm, first_us);
}

int hal_replay_ecu_init(hal_replay_ecu_t *run, hal_replay_read_fn read, void *read_ctx,
                        hal_replay_write_fn write, void *write_ctx, const pfe_ecu_config_t *cfg)
{
    (void)memset(run, 0, sizeof *run);
    hal_replay_init(&run->bus, read, read_ctx, write, write_ctx, NULL);
    return start_on_bus(run, cfg);
}

int hal_replay_ecu_init_source(hal_replay_ecu_t *run, hal_replay_source_fn source, void *source_ctx,
                               hal_replay_write_fn write, void *write_ctx,
                               const pfe_ecu_config_t *cfg)
{
    (void)memset(run, 0, sizeof *run);
    hal_replay_init_source(&run->bus, source, source_ctx, write, write_ctx, NULL);
    return start_on_bus(run, cfg);
}

bool hal_replay_ecu_feed(hal_replay_ecu_t *run)
{
    uint64_t next_us = 0U;
    const bool more = hal_replay_next_us(&run->bus, &next_us);
    if (!more && (run->now_us > (run->bus.last_log_us + HAL_REPLAY_ECU_TAIL_US))) {
        return false;
    }
    if (more && (next_us > (run->now_us + HAL_REPLAY_ECU_TAIL_US + HAL_REPLAY_ECU_GAP_US))) {
        /* Jump to a whole number of ticks, a tail's length before the next frame. */
        const uint64_t ticks = (next_us - HAL_REPLAY_ECU_TAIL_US - run->now_us) / PFE_ECU_TICK_US;
        run->now_us += ticks * PFE_ECU_TICK_US;
        run->gaps_skipped++;
    }
    (void)hal_time_wait_until_us(hal_replay_time(&run->bus), run->now_us);
    return true;
}

void hal_replay_ecu_tick(hal_replay_ecu_t *run)
{
    run->frames_sent += hal_ecu_loop_step(&run->loop, run->now_us);
    run->now_us += PFE_ECU_TICK_US;
    run->ticks++;
}

bool hal_replay_ecu_step(hal_replay_ecu_t *run)
{
    if (!hal_replay_ecu_feed(run)) {
        return false;
    }
    hal_replay_ecu_tick(run);
    return true;
}

int hal_replay_ecu_finish(hal_replay_ecu_t *run)
{
    (void)hal_ecu_loop_save(&run->loop);
    return hal_replay_flush(&run->bus);
}

/* Appends text to buf at *n, keeping room for the NUL. */
static void put_str(char *buf, uint32_t cap, uint32_t *n, const char *s)
{
    while ((*s != '\0') && ((*n + 1U) < cap)) {
        buf[(*n)++] = *s++;
    }
}

static void put_dec_u64(char *buf, uint32_t cap, uint32_t *n, uint64_t v)
{
    char digits[21];
    char *p = &digits[20];
    uint64_t rest = v;
    *p = '\0';
    do {
        --p;
        *p = (char)('0' + (int)(rest % 10U));
        rest /= 10U;
    } while (rest != 0U);
    put_str(buf, cap, n, p);
}

static void put_field(char *buf, uint32_t cap, uint32_t *n, const char *name, uint64_t v)
{
    put_str(buf, cap, n, " ");
    put_str(buf, cap, n, name);
    put_str(buf, cap, n, " ");
    put_dec_u64(buf, cap, n, v);
}

uint32_t hal_replay_ecu_summary(const hal_replay_ecu_t *run, char *buf, uint32_t cap)
{
    if ((buf == NULL) || (cap == 0U)) {
        return 0U;
    }
    const hal_replay_stats_t *st = hal_replay_stats(&run->bus);
    uint32_t n = 0U;
    put_str(buf, cap, &n, "replay:");
    put_field(buf, cap, &n, "lines", st->lines);
    put_field(buf, cap, &n, "frames", st->frames);
    put_field(buf, cap, &n, "not_classic", st->skipped_not_classic);
    put_field(buf, cap, &n, "bad", st->bad_lines);
    put_field(buf, cap, &n, "first_bad_line", st->first_bad_line);
    put_field(buf, cap, &n, "time_backwards", st->time_backwards);
    put_field(buf, cap, &n, "gaps_skipped", run->gaps_skipped);
    put_field(buf, cap, &n, "ticks", run->ticks);
    put_field(buf, cap, &n, "sent", run->frames_sent);
    put_field(buf, cap, &n, "own_fuel_ul", pfe_ecu_own_fuel_ul(&run->ecu));
    put_field(buf, cap, &n, "platoon_fuel_ul", pfe_ecu_platoon_fuel_ul(&run->ecu));
    put_field(buf, cap, &n, "rx_dropped", run->ecu.count.rx_dropped);
    put_field(buf, cap, &n, "tx_dropped", run->ecu.count.tx_dropped);
    put_str(buf, cap, &n, "\n");
    buf[n] = '\0';
    return n;
}

/* Decimal, or hex after "0x": 0 and *out within lo .. hi, else -1. */
static int parse_u32(const char *text, uint32_t lo, uint32_t hi, uint32_t *out)
{
    const char *s = text;
    uint32_t base = 10U;
    if ((s[0] == '0') && ((s[1] == 'x') || (s[1] == 'X'))) {
        base = 16U;
        s = &text[2];
    }
    if (*s == '\0') {
        return -1;
    }
    uint64_t v = 0U;
    for (; *s != '\0'; s++) {
        uint32_t d;
        if ((*s >= '0') && (*s <= '9')) {
            d = (uint32_t)(*s - '0');
        } else if ((base == 16U) && (*s >= 'a') && (*s <= 'f')) {
            d = (uint32_t)(*s - 'a') + 10U;
        } else if ((base == 16U) && (*s >= 'A') && (*s <= 'F')) {
            d = (uint32_t)(*s - 'A') + 10U;
        } else {
            return -1;
        }
        if (d >= base) {
            return -1;
        }
        v = (v * base) + d;
        if (v > hi) {
            return -1;
        }
    }
    if (v < lo) {
        return -1;
    }
    *out = (uint32_t)v;
    return 0;
}

static int arg_error(char *err, uint32_t cap, const char *what, const char *arg)
{
    uint32_t n = 0U;
    if ((err != NULL) && (cap > 0U)) {
        put_str(err, cap, &n, what);
        put_str(err, cap, &n, arg);
        err[n] = '\0';
    }
    return -1;
}

int hal_replay_ecu_args(int argc, char *const argv[], hal_replay_ecu_args_t *out, char *err,
                        uint32_t cap)
{
    uint32_t address = PFE_ECU_DEFAULT_ADDRESS;
    uint32_t interval_ms = 10000U;
    uint32_t vehicles = 1U;
    uint32_t position = 0U;
    uint32_t gap_cm = 1000U;
    out->log_path = NULL;
    out->record_path = NULL;
    for (int i = 1; i < argc; i += 2) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0) {
            return 1;
        }
        if ((i + 1) >= argc) {
            return arg_error(err, cap, "missing value after ", a);
        }
        const char *v = argv[i + 1];
        int bad = 0;
        if (strcmp(a, "--log") == 0) {
            out->log_path = v;
        } else if (strcmp(a, "--record") == 0) {
            out->record_path = v;
        } else if (strcmp(a, "--address") == 0) {
            bad = parse_u32(v, 0U, 253U, &address);
        } else if (strcmp(a, "--save-interval-ms") == 0) {
            bad = parse_u32(v, 1000U, 3600000U, &interval_ms);
        } else if (strcmp(a, "--vehicles") == 0) {
            bad = parse_u32(v, 1U, PFE_MAX_VEHICLES, &vehicles);
        } else if (strcmp(a, "--position") == 0) {
            bad = parse_u32(v, 0U, PFE_MAX_VEHICLES - 1U, &position);
        } else if (strcmp(a, "--gap-cm") == 0) {
            bad = parse_u32(v, 0U, 100000U, &gap_cm);
        } else {
            return arg_error(err, cap, "unknown option ", a);
        }
        if (bad != 0) {
            return arg_error(err, cap, "out of range or not a number: ", a);
        }
    }
    if (out->log_path == NULL) {
        return arg_error(err, cap, "--log LOG is required", "");
    }
    if (position >= vehicles) {
        return arg_error(err, cap, "--position must be below --vehicles", "");
    }
    hal_ecu_loop_config(&out->cfg, (uint8_t)address, interval_ms, vehicles, position,
                        gap_cm * 10U);
    return 0;
}
