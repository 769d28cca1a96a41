/*
 * hal_nvm.h - non-volatile record slots, as every backend provides them.
 *
 * PFE_NVM_SLOTS slots of PFE_NVM_RECORD_SIZE bytes (firmware/pfe_nvm.h
 * decides what goes in them). A write may be cut short by a reset: the
 * firmware's two-slot scheme tolerates a torn slot. Returns 0 or a HAL_E*
 * code (hal/hal_can.h).
 */
#ifndef HAL_NVM_H
#define HAL_NVM_H

#include <stdint.h>

#include "firmware/pfe_nvm.h"

typedef struct hal_nvm hal_nvm_t;

/* Reads a whole slot into buf (PFE_NVM_RECORD_SIZE bytes). A slot never
 * written reads as 0xFF bytes. */
int hal_nvm_read(hal_nvm_t *nvm, uint32_t slot, uint8_t buf[PFE_NVM_RECORD_SIZE]);

/* Writes a whole slot and makes it durable before returning 0. */
int hal_nvm_write(hal_nvm_t *nvm, uint32_t slot, const uint8_t buf[PFE_NVM_RECORD_SIZE]);

#endif /* HAL_NVM_H */
