/* hal_nvm_file.c - NVM slots in a file (contract in hal_nvm_file.h). */
#define _POSIX_C_SOURCE 200809L
#include "hal/posix/hal_nvm_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hal/hal_can.h"

struct hal_nvm {
    int fd;
};

int hal_nvm_file_open(hal_nvm_t **out, const char *path)
{
    if ((out == NULL) || (path == NULL)) {
        return HAL_EINVAL;
    }
    const int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) {
        return HAL_EIO;
    }
    hal_nvm_t *nvm = malloc(sizeof *nvm);
    if (nvm == NULL) {
        (void)close(fd);
        return HAL_EIO;
    }
    nvm->fd = fd;
    *out = nvm;
    return 0;
}

void hal_nvm_file_close(hal_nvm_t *nvm)
{
    if (nvm != NULL) {
        (void)close(nvm->fd);
        free(nvm);
    }
}

int hal_nvm_read(hal_nvm_t *nvm, uint32_t slot, uint8_t buf[PFE_NVM_RECORD_SIZE])
{
    if ((nvm == NULL) || (slot >= PFE_NVM_SLOTS) || (buf == NULL)) {
        return HAL_EINVAL;
    }
    memset(buf, 0xFF, PFE_NVM_RECORD_SIZE);
    const off_t at = (off_t)slot * (off_t)PFE_NVM_RECORD_SIZE;
    const ssize_t n = pread(nvm->fd, buf, PFE_NVM_RECORD_SIZE, at);
    if (n < 0) {
        return HAL_EIO;
    }
    if ((size_t)n < PFE_NVM_RECORD_SIZE) {
        memset(&buf[n], 0xFF, PFE_NVM_RECORD_SIZE - (size_t)n); /* short file: erased tail */
    }
    return 0;
}

int hal_nvm_write(hal_nvm_t *nvm, uint32_t slot, const uint8_t buf[PFE_NVM_RECORD_SIZE])
{
    if ((nvm == NULL) || (slot >= PFE_NVM_SLOTS) || (buf == NULL)) {
        return HAL_EINVAL;
    }
    const off_t at = (off_t)slot * (off_t)PFE_NVM_RECORD_SIZE;
    const ssize_t n = pwrite(nvm->fd, buf, PFE_NVM_RECORD_SIZE, at);
    if ((n != (ssize_t)PFE_NVM_RECORD_SIZE) || (fsync(nvm->fd) != 0)) {
        return HAL_EIO;
    }
    return 0;
}
