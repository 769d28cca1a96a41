/*
 * The flash NVM (hal/stm32f4/hal_stm32_nvm.c) against the flash model
 * (tests/stm32/flash_model.h): layout in flash, sector switch, and a power
 * cut after every single program or erase of a run of saves that crosses a
 * sector switch, each followed by a restart that must find the last
 * completed save or the one cut short, never anything else, and must be
 * able to save again.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "firmware/pfe_nvm.h"
#include "hal/hal_can.h"
#include "hal/stm32f4/hal_stm32_nvm.h"
#include "tests/stm32/flash_model.h"

static hal_nvm_t g_nvm;

static void mount(void)
{
    hal_stm32_nvm_init(&g_nvm, &flash_model.regs, flash_model.mem[0], 1U, flash_model.mem[1], 2U);
}

static void record(uint32_t seq, uint8_t out[PFE_NVM_RECORD_SIZE])
{
    const pfe_nvm_state_t s = {seq, (uint64_t)seq * 1000U, (uint64_t)seq * 5000U, 0U, 0U, 0U};
    pfe_nvm_encode(&s, out);
}

static int save(uint32_t seq)
{
    uint8_t b[PFE_NVM_RECORD_SIZE];
    record(seq, b);
    return hal_nvm_write(&g_nvm, seq % 2U, b);
}

/* What the firmware restores: pfe_nvm_pick() over both slots. */
static int restored(pfe_nvm_state_t *st)
{
    uint8_t s0[PFE_NVM_RECORD_SIZE];
    uint8_t s1[PFE_NVM_RECORD_SIZE];
    memset(s0, 0xA5, sizeof s0);
    memset(s1, 0xA5, sizeof s1);
    assert_int_equal(hal_nvm_read(&g_nvm, 0U, s0), 0);
    assert_int_equal(hal_nvm_read(&g_nvm, 1U, s1), 0);
    return pfe_nvm_pick(s0, s1, st);
}

static int setup(void **state)
{
    (void)state;
    flash_model_reset(1U);
    mount();
    return 0;
}

static void test_blank_flash_reads_erased(void **state)
{
    (void)state;
    uint8_t b[PFE_NVM_RECORD_SIZE];
    memset(b, 0xA5, sizeof b);
    assert_int_equal(hal_nvm_read(&g_nvm, 1U, b), 0);
    for (uint32_t k = 0U; k < PFE_NVM_RECORD_SIZE; k++) {
        assert_int_equal(b[k], 0xFFU);
    }
    assert_int_equal(hal_nvm_read(&g_nvm, 2U, b), HAL_EINVAL);
    assert_int_equal(hal_nvm_write(&g_nvm, 2U, b), HAL_EINVAL);
    assert_int_equal(flash_model.ops, 0U); /* mounting and reading touch nothing */
}

static void test_records_in_flash(void **state)
{
    (void)state;
    assert_int_equal(save(0U), 0);
    assert_int_equal(save(1U), 0);
    const uint32_t *s = flash_model.mem[0];
    assert_int_equal(s[0], 0x5046454EU);   /* sector magic */
    assert_int_equal(s[1], 1U);            /* generation */
    assert_int_equal(s[2], 0xA55A0000U);   /* slot 0's tag */
    assert_int_equal(s[3], 0x324E4650U);   /* "PFN2", the record's first word */
    assert_int_equal(s[13], 0x5AA5C33CU);  /* commit */
    assert_int_equal(s[14], 0xA55A0001U);  /* slot 1's tag */
    assert_int_equal(s[26], 0xFFFFFFFFU);  /* free */
    /* One erase, 2 sector words, 2 x 12 record words. */
    assert_int_equal(flash_model.erases, 1U);
    assert_int_equal(flash_model.ops, 1U + 2U + 24U);
    assert_int_equal(flash_model.misuse, 0U);
    assert_int_equal(flash_model.regs.cr, FLASH_CR_LOCK); /* locked again */
    pfe_nvm_state_t st;
    assert_int_equal(restored(&st), 1);
    assert_int_equal(st.sequence, 1U);
    assert_int_equal(st.own_fuel_ul, 1000U);
    /* A restart finds the same. */
    flash_model_power_on();
    mount();
    assert_int_equal(restored(&st), 1);
    assert_int_equal(st.platoon_fuel_ul, 5000U);
}

/* (4096 - 2) / 12 = 341 records a sector: the 342nd save (to slot 1)
 * formats sector 2, carries slot 0's latest over and appends; each later sector takes 340
 * new records after the one carried over. */
static void test_sector_switch(void **state)
{
    (void)state;
    assert_int_equal(HAL_STM32_NVM_RECORDS, 341U);
    for (uint32_t k = 0U; k < 341U; k++) {
        assert_int_equal(save(k), 0);
    }
    assert_int_equal(flash_model.erases, 1U);
    assert_int_equal(save(341U), 0);
    assert_int_equal(flash_model.erases, 2U);
    assert_int_equal(flash_model.mem[1][0], 0x5046454EU);
    assert_int_equal(flash_model.mem[1][1], 2U);
    assert_int_equal(flash_model.mem[1][2], 0xA55A0000U); /* slot 0 carried over */
    assert_int_equal(flash_model.mem[1][14], 0xA55A0001U); /* then slot 1's new record */
    pfe_nvm_state_t st;
    assert_int_equal(restored(&st), 1);
    assert_int_equal(st.sequence, 341U);
    for (uint32_t k = 342U; k < 2000U; k++) {
        assert_int_equal(save(k), 0);
    }
    /* Switches at saves 341, 681, 1021, 1361 and 1701: six erases in all. */
    assert_int_equal(flash_model.erases, 6U);
    flash_model_power_on();
    mount();
    assert_int_equal(g_nvm.generation, 6U);
    assert_int_equal(restored(&st), 1);
    assert_int_equal(st.sequence, 1999U);
    assert_int_equal(flash_model.misuse, 0U);
}

static void test_erase_that_does_not_verify_is_reported(void **state)
{
    (void)state;
    flash_model.fail_next_erase = true;
    assert_int_equal(save(0U), HAL_EIO);
    assert_int_equal(g_nvm.failures, 1U);
    assert_int_equal(save(0U), 0); /* tried again: the erase works now */
    pfe_nvm_state_t st;
    assert_int_equal(restored(&st), 0);
    assert_int_equal(st.sequence, 0U);
}

/* Saves PREFILL .. PREFILL + SAVES - 1 after PREFILL saves: sector 1 full,
 * sector 2 holding 338 of its 341 records (the one carried over and saves
 * 341 .. 677), so that the run crosses a switch back to sector 1 (at save
 * 681), retiring it first. */
#define PREFILL 678U
#define SAVES 10U

static uint32_t run_saves(uint32_t *completed)
{
    uint32_t ok = 0U;
    for (uint32_t k = 0U; k < SAVES; k++) {
        if (save(PREFILL + k) == 0) {
            ok = k + 1U;
        } else {
            break;
        }
    }
    *completed = ok;
    return flash_model.ops;
}

static void test_power_cut_after_every_flash_operation(void **state)
{
    (void)state;
    static uint32_t snapshot[2][FLASH_MODEL_WORDS];
    for (uint32_t k = 0U; k < PREFILL; k++) {
        assert_int_equal(save(k), 0);
    }
    memcpy(snapshot, flash_model.mem, sizeof snapshot);
    /* The uncut run: how many operations it takes. */
    const uint32_t ops0 = flash_model.ops;
    uint32_t completed = 0U;
    const uint32_t total = run_saves(&completed) - ops0;
    assert_int_equal(completed, SAVES);
    /* 10 saves of 12 words, one switch: retire, erase, 2 sector words, 12 carried. */
    assert_int_equal(flash_model.erases, 3U);
    assert_int_equal(total, (SAVES * 12U) + 1U + 1U + 2U + 12U);
    for (uint32_t cut = 1U; cut <= total; cut++) {
        for (uint32_t seed = 1U; seed <= 3U; seed++) {
            flash_model_reset(seed * 7919U + cut);
            memcpy(flash_model.mem, snapshot, sizeof snapshot);
            mount();
            flash_model.ops_left = (int64_t)cut;
            (void)run_saves(&completed);
            assert_false(flash_model.powered);
            flash_model_power_on();
            mount();
            pfe_nvm_state_t st;
            const int slot = restored(&st);
            /* The last completed save, or the one cut short. */
            const uint32_t last_done = PREFILL + completed - 1U;
            if ((slot < 0) || (st.sequence < last_done) || (st.sequence > (last_done + 1U)) ||
                (st.own_fuel_ul != (uint64_t)st.sequence * 1000U)) {
                fail_msg("cut after operation %u (seed %u): restored slot %d sequence %u, "
                         "own %llu uL; last completed save %u",
                         (unsigned)cut, (unsigned)seed, slot, (unsigned)st.sequence,
                         (unsigned long long)st.own_fuel_ul, (unsigned)last_done);
            }
            /* And it saves again, and that save is what a restart finds. */
            const uint32_t next = st.sequence + 1U;
            int rc = save(next);
            if (rc != 0) {
                rc = save(next); /* a position torn by the cut costs one try */
            }
            assert_int_equal(rc, 0);
            flash_model_power_on();
            mount();
            assert_int_equal(restored(&st), (int)(next % 2U));
            assert_int_equal(st.sequence, next);
        }
    }
    assert_int_equal(flash_model.misuse, 0U);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_blank_flash_reads_erased, setup),
        cmocka_unit_test_setup(test_records_in_flash, setup),
        cmocka_unit_test_setup(test_sector_switch, setup),
        cmocka_unit_test_setup(test_erase_that_does_not_verify_is_reported, setup),
        cmocka_unit_test_setup(test_power_cut_after_every_flash_operation, setup),
    };
    return cmocka_run_group_tests_name("hal_stm32_nvm on the flash model", tests, NULL, NULL);
}
