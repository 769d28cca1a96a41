/*
 * Property test: the NVM save path (pfe_ecu_nvm_*, hal/hal_ecu_loop.c) under
 * resets at any point of a write, torn writes and failed writes, on the test
 * backend (hal/fake).
 *
 * A sequence starts from erased NVM and runs up to LIVES_MAX lives of the
 * module: boot (hal_ecu_loop_init()), 10 ms passes of hal_ecu_loop_step()
 * fed speed and pitch by another node on the fake bus, then a reset, either
 * between two passes or in the middle of a write (torn). During a life the
 * flash may fail a run of writes without a reset. The test keeps its own
 * record of what the flash holds, from the bytes each write was asked to
 * store and the bytes it left, never from the module's bookkeeping:
 *   - a write is completed when the slot holds all of its bytes;
 *   - a boot restores exactly the last completed write (sequence and both
 *     totals; nothing, and zero totals, before the first);
 *   - totals never go backwards from one boot to the next, and never jump
 *     forward: a boot's total is at most the total at the reset before it;
 *   - the fuel lost at a reset is at most one save interval (and one pass)
 *     at the largest rate, when no write failed since the last completed
 *     one; otherwise at most the largest rate over the time since;
 *   - on the way (path checks, off with --boot-checks-only): a failed write
 *     is retried on the next pass to the same slot, the ECU counts the
 *     failures (count.nvm_write_failures) and says nvm_failing after
 *     PFE_ECU_NVM_FAILING_AFTER in a row, until a write completes; and
 *     every PFE_DeviceStatus on the bus says so (NvmWriteFailing,
 *     NvmWriteFailures), as of the pass that sent it.
 * A failing check prints the seed, the sequence and the values, and fails.
 *
 *   test_nvm_faults [--boot-checks-only] [SEQUENCES_PER_SEED [SEED...]]
 *
 * Defaults: 2500 sequences for each of seeds 1, 2, 3 and 4 (10,000).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "firmware/pfe_calib.h"
#include "firmware/pfe_can.h"
#include "firmware/pfe_codec.h"
#include "firmware/pfe_ecu.h"
#include "firmware/pfe_fixed.h"
#include "firmware/pfe_nvm.h"
#include "hal/fake/hal_fake.h"
#include "hal/hal_ecu_loop.h"

#define OTHER_SA 0x00U
#define SAVE_INTERVAL_MS 1000U
#define INTERVAL_TICKS (SAVE_INTERVAL_MS * 1000U / PFE_ECU_TICK_US)
#define LIVES_MAX 6U
#define LIFE_TICKS_MAX 400U
#define SPEED_MM_S 25000 /* 90 km/h, steady: no acceleration term */

/* Pitches the other node sends, udeg; the largest, 3 deg, sets the largest
 * rate. Default truck (firmware/pfe_calib.c), 25 m/s on 3 deg, double
 * precision: F = m g (sin a + c_r cos a) + rho cwA v^2 / 2
 *   = 40000 * 9.81 * (0.0523360 + 0.007 * 0.9986295) + 1.29 * 6 * 625 / 2
 *   = 25698.4 N; (F v + Paux) / (eta rho_d) = (642460 + 4000) W / 14320 J/mL
 *   = 45.144 mL/s. The bound: 45.2 mL/s (the estimator's rounding and the
 * filter's settling stay below it; the test checks the rates it sees). */
static const int32_t k_pitch_udeg[5] = {0, 1000000, 2000000, 3000000, -2000000};
#define RATE_MAX_NL_S 45200000ULL
/* One save interval and one pass at RATE_MAX_NL_S: 45.2 mL/s * 1.01 s. */
#define LOSS_MAX_UL 45652ULL

typedef struct {
    uint32_t seed;
    uint32_t rng;
    bool boot_checks_only;
    /* counts over the run */
    uint32_t sequences;
    uint32_t boots;
    uint32_t resets_between;
    uint32_t resets_in_write;
    uint32_t writes;
    uint32_t failed_writes;
    uint32_t completed_writes;
    uint32_t failing_seen;
    uint32_t device_status_frames;
    uint32_t device_status_failing;    /* of them, with NvmWriteFailing set */
    uint64_t worst_loss_ul;            /* at a reset with no failed write since the last completed one */
    uint64_t worst_loss_failing_ul;    /* with failed writes since */
    uint32_t worst_rate_nl_s;
} run_t;

static uint32_t next(run_t *r)
{
    /* xorshift32 */
    uint32_t x = r->rng;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    r->rng = x;
    return x;
}

static uint32_t below(run_t *r, uint32_t n)
{
    return next(r) % n;
}

#define CHECK(r, seq, cond, ...)                                                              \
    do {                                                                                      \
        if (!(cond)) {                                                                        \
            print_error("seed %lu sequence %lu: ", (unsigned long)(r)->seed, (unsigned long)(seq)); \
            print_error(__VA_ARGS__);                                                         \
            print_error("\n");                                                                \
            fail();                                                                           \
        }                                                                                     \
    } while (0)

static void send(hal_can_t *node, uint64_t tick, int32_t pitch_udeg)
{
    pfe_can_frame_t f;
    if ((tick % 10U) == 0U) {
        const pfe_msg_ccvs1_t speed = {{SPEED_MM_S, PFE_SIG_VALID}};
        ASSERT_GE(pfe_codec_encode_ccvs1(&f, &speed, OTHER_SA), 0);
        assert_int_equal(hal_can_send(node, &f), 0);
    }
    const pfe_msg_ssi_t pitch = {{pitch_udeg, PFE_SIG_VALID}, {0, PFE_SIG_VALID}, {0U, PFE_SIG_VALID}};
    ASSERT_GE(pfe_codec_encode_ssi(&f, &pitch, OTHER_SA), 0);
    assert_int_equal(hal_can_send(node, &f), 0);
}

static void run_sequence(run_t *r, uint32_t seq)
{
    static hal_nvm_t nvm;
    static hal_fake_bus_t bus;
    static pfe_ecu_t ecu;
    static hal_ecu_loop_t loop;
    pfe_ecu_config_t cfg;
    hal_ecu_loop_config(&cfg, PFE_ECU_DEFAULT_ADDRESS, SAVE_INTERVAL_MS, 1U, 0U, 10000U);
    hal_fake_nvm_init(&nvm);

    /* What the flash holds, as this test sees it. */
    bool have_completed = false;
    pfe_nvm_state_t completed = {0U, 0U, 0U, 0U, 0U, 0U};
    /* The life before the boot. */
    bool reset_seen = false;
    uint64_t total_at_reset_ul = 0U;
    uint64_t ticks_since_completed = 0U;
    bool failed_since_completed = false;
    uint64_t last_boot_total_ul = 0U;
    uint64_t tick = 0U;

    const uint32_t lives = 1U + below(r, LIVES_MAX);
    for (uint32_t life = 0U; life < lives; life++) {
        hal_fake_bus_init(&bus);
        hal_can_t *can = hal_fake_open(&bus);
        hal_can_t *node = hal_fake_open(&bus);
        assert_non_null(can);
        assert_non_null(node);
        const uint64_t boot_us = 1000000U + (tick * PFE_ECU_TICK_US);
        memset(&ecu, 0xA5, sizeof ecu);
        assert_int_equal(hal_ecu_loop_init(&loop, &ecu, &cfg, can, &nvm, boot_us), PFE_OK);
        r->boots++;

        /* The boot restores exactly the last completed write. */
        const pfe_nvm_state_t *got = &loop.restored;
        if (have_completed) {
            CHECK(r, seq, (loop.restored_slot >= 0) && (got->sequence == completed.sequence) &&
                              (got->own_fuel_ul == completed.own_fuel_ul) &&
                              (got->platoon_fuel_ul == completed.platoon_fuel_ul),
                  "boot %lu restores the last completed write: slot %d sequence %lu own %llu uL "
                  "platoon %llu uL, last completed: sequence %lu own %llu uL platoon %llu uL",
                  (unsigned long)life, loop.restored_slot, (unsigned long)got->sequence,
                  (unsigned long long)got->own_fuel_ul, (unsigned long long)got->platoon_fuel_ul,
                  (unsigned long)completed.sequence, (unsigned long long)completed.own_fuel_ul,
                  (unsigned long long)completed.platoon_fuel_ul);
        } else {
            CHECK(r, seq, (loop.restored_slot == -1) && (got->own_fuel_ul == 0U) && (got->platoon_fuel_ul == 0U),
                  "boot %lu restores the last completed write: none was, restored slot %d own %llu uL",
                  (unsigned long)life, loop.restored_slot, (unsigned long long)got->own_fuel_ul);
        }
        const uint64_t boot_total_ul = pfe_ecu_own_fuel_ul(&ecu);
        CHECK(r, seq, boot_total_ul == got->own_fuel_ul, "boot %lu: the ECU starts at %llu uL, restored %llu uL",
              (unsigned long)life, (unsigned long long)boot_total_ul, (unsigned long long)got->own_fuel_ul);
        CHECK(r, seq, boot_total_ul >= last_boot_total_ul, "boot %lu: total went backwards, %llu uL after %llu uL",
              (unsigned long)life, (unsigned long long)boot_total_ul, (unsigned long long)last_boot_total_ul);
        if (reset_seen) {
            CHECK(r, seq, boot_total_ul <= total_at_reset_ul,
                  "boot %lu: total jumped forward, %llu uL restored, %llu uL at the reset", (unsigned long)life,
                  (unsigned long long)boot_total_ul, (unsigned long long)total_at_reset_ul);
            const uint64_t loss_ul = total_at_reset_ul - boot_total_ul;
            const uint64_t bound_ul = failed_since_completed
                                          ? ((RATE_MAX_NL_S * ticks_since_completed) / 100000U) + 1U
                                          : LOSS_MAX_UL;
            CHECK(r, seq, loss_ul <= bound_ul,
                  "boot %lu: lost %llu uL, bound %llu uL (%llu passes since the last completed write, %s)",
                  (unsigned long)life, (unsigned long long)loss_ul, (unsigned long long)bound_ul,
                  (unsigned long long)ticks_since_completed,
                  failed_since_completed ? "writes failed since" : "no write failed since");
            uint64_t *worst = failed_since_completed ? &r->worst_loss_failing_ul : &r->worst_loss_ul;
            if (loss_ul > *worst) {
                *worst = loss_ul;
            }
        }
        last_boot_total_ul = boot_total_ul;
        ticks_since_completed = 0U;
        failed_since_completed = false;

        /* This life: its length, its road, a run of failing writes, and how it ends. */
        const uint32_t ticks = 1U + below(r, LIFE_TICKS_MAX);
        const int32_t pitch = k_pitch_udeg[below(r, 5U)];
        const bool plan_failures = below(r, 3U) == 0U;
        const uint32_t fail_at = below(r, ticks);
        /* a few failures in a row, or (one run in four) flash that fails
         * for seconds: the status on the bus must say so */
        const uint32_t fail_count = (below(r, 4U) == 0U) ? (100U + below(r, 300U)) : (1U + below(r, 6U));
        /* A failed write leaves at most 24 bytes: byte 23 (the platoon
         * total's top byte, 0 here) then reads 0xFF, so such a slot never
         * holds its whole record by chance. */
        const uint32_t fail_bytes = below(r, 24U);
        const bool end_in_write = below(r, 2U) == 0U;
        const uint32_t tear_bytes = below(r, PFE_NVM_RECORD_SIZE);
        uint32_t streak = 0U;
        uint32_t failed_this_life = 0U;
        bool retry_due = false;
        uint32_t retry_slot = 0U;
        bool torn = false;
        for (uint32_t k = 0U; (k < ticks) || (end_in_write && !torn); k++) {
            if (plan_failures && (k == fail_at)) {
                hal_fake_nvm_fail_next_writes(&nvm, fail_count, fail_bytes);
            }
            const bool tear_now = end_in_write && (k >= ticks);
            if (tear_now) {
                hal_fake_nvm_tear_next_write(&nvm, tear_bytes);
            }
            const uint32_t writes_before = nvm.writes;
            send(node, tick, pitch);
            (void)hal_ecu_loop_step(&loop, 1000000U + (tick * PFE_ECU_TICK_US));
            /* The pass's frames went out before its write: its status is
             * as of the writes before. */
            hal_can_rx_t rx;
            while (hal_can_receive(node, &rx) == 0) {
                pfe_msg_device_status_t ds;
                if ((pfe_j1939_pgn(rx.frame.id) != PFE_PGN_DEVICE_STATUS) ||
                    (pfe_codec_decode_device_status(&rx.frame, &ds) < 0)) {
                    continue;
                }
                r->device_status_frames++;
                const uint32_t want_count = (failed_this_life > PFE_STATUS_COUNTER_MAX) ? PFE_STATUS_COUNTER_MAX
                                                                                         : failed_this_life;
                const bool want_failing = streak >= PFE_ECU_NVM_FAILING_AFTER;
                if (ds.nvm_write_failing.value != 0U) {
                    r->device_status_failing++;
                }
                if (!r->boot_checks_only) {
                    CHECK(r, seq, (ds.nvm_write_failing.state == PFE_SIG_VALID) &&
                                      (ds.nvm_write_failing.value == (want_failing ? 1U : 0U)) &&
                                      (ds.nvm_write_failures.value == want_count),
                          "PFE_DeviceStatus says NvmWriteFailing %lu (state %d), NvmWriteFailures %lu; "
                          "%lu failed writes in a row, %lu this life",
                          (unsigned long)ds.nvm_write_failing.value, (int)ds.nvm_write_failing.state,
                          (unsigned long)ds.nvm_write_failures.value, (unsigned long)streak,
                          (unsigned long)failed_this_life);
                }
            }
            tick++;
            ticks_since_completed++;
            if ((ecu.out != NULL) && ((ecu.out->flags & PFE_EST_VALID) != 0U) &&
                (ecu.out->pos_fuel_rate_nl_s[0] > r->worst_rate_nl_s)) {
                r->worst_rate_nl_s = ecu.out->pos_fuel_rate_nl_s[0];
            }
            const uint32_t wrote = nvm.writes - writes_before;
            CHECK(r, seq, wrote <= 1U, "one pass wrote %lu times", (unsigned long)wrote);
            if (!r->boot_checks_only && retry_due) {
                CHECK(r, seq, (wrote == 1U) && (nvm.last_slot == retry_slot),
                      "a failed write to slot %lu is retried on the next pass to the same slot: "
                      "%lu writes, slot %lu", (unsigned long)retry_slot, (unsigned long)wrote,
                      (unsigned long)nvm.last_slot);
            }
            retry_due = false;
            if (wrote == 0U) {
                continue;
            }
            r->writes++;
            pfe_nvm_state_t rec;
            CHECK(r, seq, pfe_nvm_decode(nvm.last_buf, &rec) == PFE_OK, "a write asked for a record that does not decode");
            CHECK(r, seq, rec.own_fuel_ul == pfe_ecu_own_fuel_ul(&ecu),
                  "a write holds %llu uL, the ECU %llu uL", (unsigned long long)rec.own_fuel_ul,
                  (unsigned long long)pfe_ecu_own_fuel_ul(&ecu));
            const bool done = memcmp(nvm.slot[nvm.last_slot], nvm.last_buf, PFE_NVM_RECORD_SIZE) == 0;
            if (tear_now) {
                /* The reset hits this write: the module never sees its end. */
                torn = true;
                r->resets_in_write++;
                if (done) {
                    have_completed = true;
                    completed = rec;
                    ticks_since_completed = 0U;
                    failed_since_completed = false;
                }
                break;
            }
            if (done) {
                r->completed_writes++;
                have_completed = true;
                completed = rec;
                ticks_since_completed = 0U;
                failed_since_completed = false;
                streak = 0U;
            } else {
                r->failed_writes++;
                failed_this_life++;
                failed_since_completed = true;
                streak++;
                retry_due = true;
                retry_slot = nvm.last_slot;
            }
            if (!r->boot_checks_only) {
                CHECK(r, seq, ecu.count.nvm_write_failures == failed_this_life,
                      "the ECU counts %lu failed writes, there were %lu",
                      (unsigned long)ecu.count.nvm_write_failures, (unsigned long)failed_this_life);
                CHECK(r, seq, ecu.nvm_failing == (streak >= PFE_ECU_NVM_FAILING_AFTER),
                      "nvm_failing %d after %lu failed writes in a row", (int)ecu.nvm_failing,
                      (unsigned long)streak);
            }
            if (ecu.nvm_failing) {
                r->failing_seen++;
            }
        }
        if (!torn) {
            r->resets_between++;
        }
        /* The reset. */
        reset_seen = true;
        total_at_reset_ul = pfe_ecu_own_fuel_ul(&ecu);
        hal_fake_close(can);
        hal_fake_close(node);
    }
    r->sequences++;
}

static uint32_t g_sequences_per_seed = 2500U;
static bool g_boot_checks_only;

static void test_seed(void **state)
{
    static run_t r;
    memset(&r, 0, sizeof r);
    r.seed = (uint32_t)(uintptr_t)*state;
    r.rng = (r.seed * 2654435761UL) | 1U;
    r.boot_checks_only = g_boot_checks_only;
    for (uint32_t s = 0U; s < g_sequences_per_seed; s++) {
        run_sequence(&r, s);
    }
    print_message("seed %lu: sequences %lu, boots %lu, resets between passes %lu, resets in a write %lu, "
                  "writes %lu (completed %lu, failed %lu), passes with nvm_failing after a write %lu, "
                  "PFE_DeviceStatus frames %lu (%lu with NvmWriteFailing), "
                  "worst loss %llu uL (bound %llu; %llu uL with failed writes since the last completed), "
                  "largest rate %lu nL/s (bound %llu)\n",
                  (unsigned long)r.seed, (unsigned long)r.sequences, (unsigned long)r.boots,
                  (unsigned long)r.resets_between, (unsigned long)r.resets_in_write, (unsigned long)r.writes,
                  (unsigned long)r.completed_writes, (unsigned long)r.failed_writes,
                  (unsigned long)r.failing_seen, (unsigned long)r.device_status_frames,
                  (unsigned long)r.device_status_failing, (unsigned long long)r.worst_loss_ul,
                  (unsigned long long)LOSS_MAX_UL, (unsigned long long)r.worst_loss_failing_ul,
                  (unsigned long)r.worst_rate_nl_s,
                  (unsigned long long)RATE_MAX_NL_S);
    assert_in_range(r.worst_rate_nl_s, 1U, RATE_MAX_NL_S);
    /* The faults happened: the run is not a quiet one. */
    assert_in_range(r.resets_in_write, g_sequences_per_seed / 4U, UINT32_MAX);
    assert_in_range(r.failed_writes, g_sequences_per_seed / 4U, UINT32_MAX);
    if (!g_boot_checks_only) {
        assert_in_range(r.failing_seen, 1U, UINT32_MAX);
        assert_in_range(r.device_status_failing, 1U, UINT32_MAX);
    }
}

int main(int argc, char **argv)
{
    int a = 1;
    if ((a < argc) && (strcmp(argv[a], "--boot-checks-only") == 0)) {
        g_boot_checks_only = true;
        a++;
    }
    if (a < argc) {
        char *end = NULL;
        const unsigned long n = strtoul(argv[a], &end, 10);
        if ((end == argv[a]) || (*end != '\0') || (n == 0UL) || (n > 1000000UL)) {
            fprintf(stderr, "test_nvm_faults: sequences per seed must be 1 .. 1000000, not '%s'\n", argv[a]);
            return 2;
        }
        g_sequences_per_seed = (uint32_t)n;
        a++;
    }
    static void *seeds[16] = {(void *)1, (void *)2, (void *)3, (void *)4};
    size_t n_seeds = 4U;
    if (a < argc) {
        n_seeds = 0U;
        for (; (a < argc) && (n_seeds < 16U); a++) {
            char *end = NULL;
            const unsigned long s = strtoul(argv[a], &end, 10);
            if ((end == argv[a]) || (*end != '\0') || (s == 0UL) || (s > UINT32_MAX)) {
                fprintf(stderr, "test_nvm_faults: a seed must be 1 .. 4294967295, not '%s'\n", argv[a]);
                return 2;
            }
            seeds[n_seeds++] = (void *)(uintptr_t)s;
        }
    }
    struct CMUnitTest tests[16];
    for (size_t k = 0U; k < n_seeds; k++) {
        const struct CMUnitTest t = cmocka_unit_test_prestate(test_seed, seeds[k]);
        tests[k] = t;
    }
    return _cmocka_run_group_tests("nvm_faults", tests, n_seeds, NULL, NULL);
}
