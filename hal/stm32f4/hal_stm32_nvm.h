/*
 * hal_stm32_nvm.h - hal/hal_nvm.h in two sectors of the STM32F4's own
 * flash (RM0090 chapter 3), programmed 32 bits at a time (2.7 to 3.6 V).
 *
 * Flash is erased to 1s a sector at a time and programming only turns 1s
 * into 0s, so records are appended, never rewritten in place:
 *
 *   sector: word 0 magic HAL_STM32_NVM_SECTOR_MAGIC, word 1 generation
 *           (the sector written last has the higher one), then records;
 *   record: 12 words: slot tag (HAL_STM32_NVM_RECORD_TAG | slot), the
 *           40 bytes of the slot (firmware/pfe_nvm.h's record, with its own
 *           CRC-32), commit word HAL_STM32_NVM_COMMIT, programmed last.
 *
 * A record counts only once its commit word reads back exactly; a slot
 * reads as its last committed record in the newest sector, else in the
 * other one, else as 0xFF bytes. When the active sector is full, the other
 * is retired (its magic programmed to 0), erased, blank-checked, given
 * generation + 1 and magic (in that order), and the other slot's latest
 * record is copied in before the new record: the old sector keeps
 * everything until the new one holds both slots. So a reset at any point
 * of a program or an erase loses at most the record being written, which
 * the firmware's two slots (pfe_nvm_pick()) turn into at most one save
 * interval of fuel. tests/stm32/test_stm32_nvm.c cuts the power after
 * every single flash operation of a save sequence, sector switch included.
 *
 * Wear: a 16 KiB sector holds (4096 - 2) / 12 = 341 records; the two
 * sectors take turns, so each is erased about once every 682 saves. At the
 * STM32 image's 60 s save interval, driving 24 h a day: 1440 saves, 2.1
 * erases per sector a day; the datasheet's 10 000 cycles last 13 years.
 * (At 10 s, the host tool's default: 12.7 erases a day, 2.2 years.)
 *
 * The core stalls while flash is busy (one bank): a word takes ~16 us, a
 * 16 KiB sector erase 250 ms typical and 500 ms at most (datasheet,
 * x32); interrupts and the CAN FIFO wait meanwhile, so a sector switch
 * costs up to 50 ticks and some frames (counted as late ticks and FIFO
 * overruns), once every 341 saves. HAL_STM32_NVM_ERASE_TIMEOUT_US bounds
 * the wait; the watchdog (hal_stm32_board.h) is longer.
 */
#ifndef HAL_STM32_NVM_H
#define HAL_STM32_NVM_H

#include <stdint.h>

#include "hal/hal_nvm.h"
#include "hal/stm32f4/stm32f4_regs.h"

#define HAL_STM32_NVM_SECTOR_WORDS 4096U            /* 16 KiB */
#define HAL_STM32_NVM_RECORD_WORDS 12U
#define HAL_STM32_NVM_FIRST_RECORD 2U               /* after magic, generation */
#define HAL_STM32_NVM_RECORDS \
    ((HAL_STM32_NVM_SECTOR_WORDS - HAL_STM32_NVM_FIRST_RECORD) / HAL_STM32_NVM_RECORD_WORDS)
#define HAL_STM32_NVM_SECTOR_MAGIC 0x5046454EU     /* "PFEN" */
#define HAL_STM32_NVM_RECORD_TAG 0xA55A0000U
#define HAL_STM32_NVM_COMMIT 0x5AA5C33CU
#define HAL_STM32_NVM_PROGRAM_TIMEOUT_US 1000U
#define HAL_STM32_NVM_ERASE_TIMEOUT_US 1000000U

_Static_assert(PFE_NVM_RECORD_SIZE == 40U, "a record is 10 words of data");

struct hal_nvm {
    stm32_flash_t *regs;
    uint32_t *sector[2];      /* memory-mapped sectors, word aligned */
    uint32_t snb[2];          /* their sector numbers, for erasing */
    int active;               /* sector appended to, -1 before the first save */
    uint32_t generation;      /* the active sector's */
    uint32_t next;            /* word index of the next free record in it */
    uint32_t erases;
    uint32_t saves;
    uint32_t failures;        /* programs or erases that did not verify */
};

/*
 * Mounts the two sectors (no flash operation): finds the newest formatted
 * one and its first free record. The STM32 image uses sectors 1 and 2
 * (0x08004000, 0x08008000; linker/stm32f405.ld keeps code out of them).
 */
void hal_stm32_nvm_init(hal_nvm_t *nvm, stm32_flash_t *regs, uint32_t *sector0, uint32_t snb0,
                        uint32_t *sector1, uint32_t snb1);

#endif /* HAL_STM32_NVM_H */
