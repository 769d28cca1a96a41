/*
 * hal_nvm_file.h - hal/hal_nvm.h on a file, for host processes.
 *
 * The file holds PFE_NVM_SLOTS slots of PFE_NVM_RECORD_SIZE bytes, in order.
 * A write is pwrite() of one slot then fsync(): a crash during it can spoil
 * only that slot, which the firmware's two-slot records tolerate. A missing
 * or short file reads as erased (0xFF).
 */
#ifndef HAL_NVM_FILE_H
#define HAL_NVM_FILE_H

#include "hal/hal_nvm.h"

/* Opens (creating it with mode 0644 if needed) the file at path.
 * 0, HAL_EINVAL (NULL) or HAL_EIO (with errno set). */
int hal_nvm_file_open(hal_nvm_t **out, const char *path);
void hal_nvm_file_close(hal_nvm_t *nvm);

#endif /* HAL_NVM_FILE_H */
