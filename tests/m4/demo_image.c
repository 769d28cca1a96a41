/*
 * Product-style image for the MPS2 AN386 backend: prints through semihosting
 * without newlib stdio, and checks the SysTick instruction counter against
 * loops whose instruction counts are known exactly.
 *
 * Returns 0 when every check holds, 1 otherwise (QEMU's exit code).
 */
#include <stdint.h>

#include "hal/mps2/icount.h"
#include "hal/mps2/semihost.h"
#include "hal/mps2/startup.h"

/* Loops written in assembly so that the compiler cannot change their
 * length. Each runs `iterations` times (iterations > 0); the instructions
 * per iteration are in the name. */
static void loop_2_insns(uint32_t iterations)
{
    __asm__ volatile("1:\n\t"
                     "subs %0, %0, #1\n\t"
                     "bne 1b\n\t"
                     : "+r"(iterations)
                     :
                     : "cc");
}

/* A load and a division: several cycles each on a real Cortex-M4, one
 * instruction each for the counter. */
static void loop_4_insns_slow(uint32_t iterations)
{
    uint32_t scratch = 7U;
    uint32_t divisor = 3U;
    __asm__ volatile("1:\n\t"
                     "ldr %1, [sp]\n\t"
                     "udiv %1, %1, %2\n\t"
                     "subs %0, %0, #1\n\t"
                     "bne 1b\n\t"
                     : "+r"(iterations), "+r"(scratch)
                     : "r"(divisor)
                     : "cc", "memory");
}

static uint64_t measure(void (*loop)(uint32_t), uint32_t iterations)
{
    uint64_t start = hal_mps2_icount_now();
    loop(iterations);
    return hal_mps2_icount_now() - start;
}

static uint64_t diff_abs(uint64_t a, uint64_t b)
{
    return (a > b) ? (a - b) : (b - a);
}

/* Checks that the difference between two runs of a loop, which cancels the
 * call overhead, matches the known instruction count within two ticks. */
static int check_loop(const char *name, void (*loop)(uint32_t), uint32_t insns_per_iteration)
{
    const uint32_t short_run = 100000U;
    const uint32_t long_run = 1100000U;
    uint64_t short_insns = measure(loop, short_run);
    uint64_t long_insns = measure(loop, long_run);
    uint64_t expected = (uint64_t)(long_run - short_run) * insns_per_iteration;
    uint64_t measured = long_insns - short_insns;
    /* The counter assumes HAL_MPS2_ICOUNT_INSNS_PER_TICK; the factor the
     * emulator really has is that value times expected / measured. */
    uint64_t ticks = measured / HAL_MPS2_ICOUNT_INSNS_PER_TICK;
    uint64_t factor_milli = (ticks == 0U) ? 0U : (expected * 1000U) / ticks;

    hal_mps2_write_str("icount ");
    hal_mps2_write_str(name);
    hal_mps2_write_str(": expected ");
    hal_mps2_write_u64(expected);
    hal_mps2_write_str(" measured ");
    hal_mps2_write_u64(measured);
    hal_mps2_write_str(" insns, ");
    hal_mps2_write_u64(ticks);
    hal_mps2_write_str(" ticks, insns per tick x1000 = ");
    hal_mps2_write_u64(factor_milli);
    hal_mps2_write_str("\n");

    if (diff_abs(measured, expected) > 2U * HAL_MPS2_ICOUNT_INSNS_PER_TICK) {
        hal_mps2_write_str("icount: FAIL: off by more than two ticks\n");
        return 1;
    }
    return 0;
}

/* Instructions from hal_mps2_icount_start() to the first SysTick wrap:
 * 2^24 ticks of 40 instructions. */
#define FIRST_WRAP_INSNS 671088640U
#define WRAP_SAMPLES 256U

static uint64_t s_wrap_samples[WRAP_SAMPLES];

/* Reads the counter back to back, storing every value, from about 100 ticks
 * before the first SysTick wrap to about 100 after it. One read and store
 * takes about 31 instructions, less than a tick, so every tick is seen, the
 * one where the hardware counter shows 0 included. The values must never go
 * back and never jump by more than the SysTick exception's cost. */
static int check_wrap(void)
{
    uint64_t now = hal_mps2_icount_now();
    const uint64_t approach = FIRST_WRAP_INSNS - 100U * HAL_MPS2_ICOUNT_INSNS_PER_TICK;
    if (now < approach) {
        loop_2_insns((uint32_t)((approach - now) / 2U));
    }
    for (uint32_t i = 0U; i < WRAP_SAMPLES; ++i) {
        s_wrap_samples[i] = hal_mps2_icount_now();
    }

    uint64_t largest_step = 0U;
    int failures = 0;
    for (uint32_t i = 1U; i < WRAP_SAMPLES; ++i) {
        if (s_wrap_samples[i] < s_wrap_samples[i - 1U]) {
            failures = 1;
        } else if (s_wrap_samples[i] - s_wrap_samples[i - 1U] > largest_step) {
            largest_step = s_wrap_samples[i] - s_wrap_samples[i - 1U];
        }
    }
    hal_mps2_write_str("icount wrap: samples from ");
    hal_mps2_write_u64(s_wrap_samples[0]);
    hal_mps2_write_str(" to ");
    hal_mps2_write_u64(s_wrap_samples[WRAP_SAMPLES - 1U]);
    hal_mps2_write_str(" insns, largest step ");
    hal_mps2_write_u64(largest_step);
    hal_mps2_write_str("\n");
    if ((s_wrap_samples[0] >= FIRST_WRAP_INSNS) ||
        (s_wrap_samples[WRAP_SAMPLES - 1U] <= FIRST_WRAP_INSNS)) {
        hal_mps2_write_str("icount: FAIL: samples do not span the wrap\n");
        return 1;
    }
    if ((failures != 0) || (largest_step > 3U * HAL_MPS2_ICOUNT_INSNS_PER_TICK)) {
        hal_mps2_write_str("icount: FAIL: counter went back or jumped at a wrap\n");
        return 1;
    }
    return 0;
}

static void print_formats(void)
{
    hal_mps2_write_str("fmt:");
    hal_mps2_write_str(" ");
    hal_mps2_write_u32(0U);
    hal_mps2_write_str(" ");
    hal_mps2_write_u32(UINT32_MAX);
    hal_mps2_write_str(" ");
    hal_mps2_write_i32(INT32_MIN);
    hal_mps2_write_str(" ");
    hal_mps2_write_i32(-7);
    hal_mps2_write_str(" ");
    hal_mps2_write_u64(UINT64_MAX);
    hal_mps2_write_str(" ");
    hal_mps2_write_i64(INT64_MIN);
    hal_mps2_write_str(" ");
    hal_mps2_write_i64(1234567890123LL);
    hal_mps2_write_str(" ");
    hal_mps2_write_hex32(0xABCDU);
    hal_mps2_write_str(" ");
    hal_mps2_write_hex64(0x0123456789ABCDEFULL);
    hal_mps2_write_str("\n");
}

/* Initialised data, so that the startup's .data copy is exercised. */
static volatile uint32_t s_data_word = 0x5EED1234U;
static volatile uint32_t s_bss_word;

int main(void)
{
    int failures = 0;
    hal_mps2_write_str("m4 demo: hello from the Cortex-M4\n");
    print_formats();

    if ((s_data_word != 0x5EED1234U) || (s_bss_word != 0U)) {
        hal_mps2_write_str("startup: FAIL: .data or .bss not initialised\n");
        failures++;
    }

    hal_mps2_icount_start();
    uint64_t first = hal_mps2_icount_now();
    uint64_t overhead = hal_mps2_icount_now() - first;
    hal_mps2_write_bench("m4_icount_overhead", overhead, "insns");

    failures += check_loop("loop_2_insns", loop_2_insns, 2U);
    failures += check_loop("loop_4_insns_slow", loop_4_insns_slow, 4U);

    failures += check_wrap();

    /* Past the second wrap, with a loop of known length. */
    const uint32_t wrap_iterations = 350000000U;
    uint64_t wrap_insns = measure(loop_2_insns, wrap_iterations);
    hal_mps2_write_str("icount across a wrap: expected ");
    hal_mps2_write_u64(2U * (uint64_t)wrap_iterations);
    hal_mps2_write_str(" + overhead, measured ");
    hal_mps2_write_u64(wrap_insns);
    hal_mps2_write_str("\n");
    if (diff_abs(wrap_insns, 2U * (uint64_t)wrap_iterations) > 2U * HAL_MPS2_ICOUNT_INSNS_PER_TICK) {
        hal_mps2_write_str("icount: FAIL across a SysTick wrap\n");
        failures++;
    }

    hal_mps2_write_bench("m4_demo_stack_used", hal_mps2_stack_used_bytes(), "bytes");
    hal_mps2_write_str((failures == 0) ? "m4 demo: ok\n" : "m4 demo: FAILED\n");
    return (failures == 0) ? 0 : 1;
}
