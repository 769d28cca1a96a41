/*
 * Console output and exit for the emulated MPS2 AN386 (Cortex-M4) through
 * Arm semihosting, without newlib's stdio: a product image that prints with
 * these links neither printf nor malloc.
 *
 * Output goes to QEMU's semihosting console: its stdout as scripts/run_m4.sh
 * starts it (-semihosting-config enable=on,target=native,chardev=... on a
 * stdio chardev), its stderr when no chardev is given. Without semihosting
 * enabled, every call below ends in a HardFault, and then in a lockup: these
 * functions are for the emulator and for debug probes with semihosting on,
 * never for a deployed ECU.
 *
 * All functions are blocking (the emulator writes synchronously), keep no
 * state, use at most 48 bytes of stack, and are safe to call from an
 * exception handler. None allocates.
 */
#ifndef HAL_MPS2_SEMIHOST_H
#define HAL_MPS2_SEMIHOST_H

#include <stdint.h>

/* Write a NUL-terminated string as is (no newline added). s must not be
 * NULL. */
void hal_mps2_write_str(const char *s);

/* Write an integer in decimal, without padding or separators; negative
 * values get a leading '-'. At most 20 characters (INT64_MIN). */
void hal_mps2_write_u32(uint32_t value);
void hal_mps2_write_i32(int32_t value);
void hal_mps2_write_u64(uint64_t value);
void hal_mps2_write_i64(int64_t value);

/* Write an integer in hexadecimal with a "0x" prefix, zero-padded to its full
 * width (8 digits for 32 bits, 16 for 64 bits), lower case. */
void hal_mps2_write_hex32(uint32_t value);
void hal_mps2_write_hex64(uint64_t value);

/* Write one benchmark line in the project's format,
 *   "bench: <name> <value> <unit>\n"
 * which `make bench` collects. name and unit must not be NULL and should
 * contain no spaces. */
void hal_mps2_write_bench(const char *name, uint64_t value, const char *unit);

/* Host files, through the emulator (QEMU -semihosting-config target=native
 * opens them relative to its working directory). Handles are the host's. */
#define HAL_MPS2_FILE_READ 1U          /* SYS_OPEN mode "rb" */
#define HAL_MPS2_FILE_WRITE 5U         /* SYS_OPEN mode "wb": created or truncated */

/* Opens path (NUL-terminated) with one of the modes above: a handle >= 0, or
 * -1 when the host refuses. */
int32_t hal_mps2_file_open(const char *path, uint32_t mode);

/* Reads up to len bytes: how many (0 at the end of the file), or -1. */
int32_t hal_mps2_file_read(int32_t handle, void *buf, uint32_t len);

/* Writes len bytes: 0 when all were written, else -1. */
int32_t hal_mps2_file_write(int32_t handle, const void *buf, uint32_t len);

/* Closes a handle: 0 or -1. */
int32_t hal_mps2_file_close(int32_t handle);

/* The program's command line as the emulator was given it (QEMU:
 * -semihosting-config ...,arg=PROG,arg=A1,...; scripts/run_m4.sh passes
 * them), arguments separated by single spaces, NUL-terminated. Returns its
 * length, or -1 when there is none or it does not fit in cap bytes. */
int32_t hal_mps2_get_cmdline(char *buf, uint32_t cap);

/* End the program: QEMU exits with status as its own exit code (the host
 * sees status & 0xFF, so use 0..255; negative values wrap, -1 gives 255).
 * Uses SYS_EXIT_EXTENDED; where a semihosting host lacks it, falls back to
 * SYS_EXIT, which can only tell success (status 0) from failure (host code
 * 1). Never returns. */
_Noreturn void hal_mps2_exit(int32_t status);

#endif /* HAL_MPS2_SEMIHOST_H */
