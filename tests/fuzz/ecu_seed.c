/*
 * ecu_seed.c - turns the start of a candump log into an input of fuzz_ecu
 * (tests/fuzz/fuzz_ecu.c): its frames as RAW operations, 10 ms ticks
 * between them as the log's timestamps say, then RUN_TICKS more ticks with
 * speed and pitch fed (90 km/h, level), so that a prediction over a preview
 * in the log completes.
 *
 *     ecu_seed LOG MAX_FRAMES RUN_TICKS OUT
 *
 * Start-up bytes: 5 vehicles, position 1, 10 m gap, arbitrary address
 * capable, 1 s save interval, no restore. Lines that are not classic
 * frames are skipped. Exit status 0, or 1 (with the reason) on bad
 * arguments, an unreadable log, a bad line.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lib/capture.h"

#define OP_RAW 0U
#define OP_RUN 6U
#define RUN_FEED 4U

static void put_run(FILE *out, uint32_t ticks, uint32_t feed)
{
    while (ticks > 0U) {
        const uint32_t n = (ticks > 1024U) ? 1024U : ticks;
        const uint32_t p = feed | ((n - 1U) / 256U);
        fputc((int)(OP_RUN | (p << 3)), out);
        fputc((int)((n - 1U) % 256U), out);
        ticks -= n;
    }
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: ecu_seed LOG MAX_FRAMES RUN_TICKS OUT\n");
        return 1;
    }
    const unsigned long max_frames = strtoul(argv[2], NULL, 10);
    const unsigned long run_ticks = strtoul(argv[3], NULL, 10);
    FILE *in = fopen(argv[1], "r");
    if (in == NULL) {
        perror(argv[1]);
        return 1;
    }
    FILE *out = fopen(argv[4], "wb");
    if (out == NULL) {
        perror(argv[4]);
        fclose(in);
        return 1;
    }
    static const uint8_t head[4] = {4U, 0x80U | 1U, 20U, 0U};
    fwrite(head, 1U, sizeof head, out);
    char line[CAPTURE_MAX_LINE + 2U];
    unsigned long lineno = 0U, frames = 0U;
    uint64_t t0 = 0U, ticks = 0U;
    int rc = 0;
    while ((frames < max_frames) && (fgets(line, sizeof line, in) != NULL)) {
        lineno++;
        line[strcspn(line, "\n")] = '\0';
        capture_line_t l;
        char why[160];
        const int kind = capture_parse_line(line, &l, NULL, why, sizeof why);
        if (kind < 0) {
            fprintf(stderr, "%s:%lu: %s\n", argv[1], lineno, why);
            rc = 1;
            break;
        }
        if ((kind != CAPTURE_LINE_FRAME) || (l.kind != CAPTURE_CLASSIC)) {
            continue;
        }
        if (frames == 0U) {
            t0 = l.t_us;
        }
        const uint64_t due = (l.t_us - t0) / 10000U;
        if (due > ticks) {
            put_run(out, (uint32_t)(due - ticks), 0U);
            ticks = due;
        }
        const uint32_t id = l.id | (l.extended ? 0x80000000UL : 0U);
        uint8_t rec[14] = {OP_RAW, (uint8_t)id, (uint8_t)(id >> 8), (uint8_t)(id >> 16),
                           (uint8_t)(id >> 24), l.len};
        memcpy(&rec[6], l.data, l.len);
        fwrite(rec, 1U, sizeof rec, out);
        frames++;
    }
    put_run(out, (uint32_t)run_ticks, RUN_FEED);
    fclose(in);
    if (fclose(out) != 0) {
        perror(argv[4]);
        rc = 1;
    }
    return rc;
}
