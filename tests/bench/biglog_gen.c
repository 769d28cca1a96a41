/*
 * biglog_gen - a candump log of N frames for the log parsing benchmark
 * (make bench: log_parse_fps, log_parse_ratio_vs_canplayer).
 *
 *   biglog_gen N > big.log
 *
 * The traffic of a J1939 bus: SSI every 10 ms, CCVS1 every 100 ms, and in
 * between 11-bit frames of 0 to 8 bytes and a few 29-bit ones, one frame per
 * 500 us from (1700000000.000000), on vcan0. Contents come from a fixed
 * linear congruential sequence: the same N gives the same file, byte for
 * byte. Exit status 0, 2 on a bad argument.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static uint32_t lcg_state = 12345U;

static uint32_t lcg_next(void)
{
    lcg_state = (lcg_state * 1103515245U) + 12345U;
    return lcg_state >> 8;
}

int main(int argc, char **argv)
{
    char *end = NULL;
    const unsigned long n = (argc == 2) ? strtoul(argv[1], &end, 10) : 0UL;
    if ((argc != 2) || (*end != '\0') || (n == 0UL) || (n > 100000000UL)) {
        fprintf(stderr, "usage: biglog_gen N   (1 <= N <= 100000000)\n");
        return 2;
    }
    static char out[1 << 16];
    (void)setvbuf(stdout, out, _IOFBF, sizeof out);
    for (unsigned long i = 0UL; i < n; i++) {
        const uint64_t t_us = 1700000000000000ULL + ((uint64_t)i * 500U);
        unsigned len = 8U;
        char id[9];
        if ((i % 20UL) == 0UL) {
            (void)snprintf(id, sizeof id, "0CF01300");
        } else if ((i % 200UL) == 1UL) {
            (void)snprintf(id, sizeof id, "18FEF100");
        } else if ((i % 7UL) == 3UL) {
            (void)snprintf(id, sizeof id, "18FF%02X%02X", (unsigned)(lcg_next() & 0xFFU),
                           (unsigned)(lcg_next() & 0xFFU));
        } else {
            (void)snprintf(id, sizeof id, "%03X", (unsigned)(lcg_next() & 0x7FFU));
            len = lcg_next() % 9U;
        }
        printf("(%llu.%06llu) vcan0 %s#", (unsigned long long)(t_us / 1000000U),
               (unsigned long long)(t_us % 1000000U), id);
        for (unsigned k = 0U; k < len; k++) {
            printf("%02X", (unsigned)(lcg_next() & 0xFFU));
        }
        putchar('\n');
    }
    return (fflush(stdout) == 0) ? 0 : 1;
}
