/*
 * Arm semihosting calls on M-profile (BKPT 0xAB; operation in r0, argument in
 * r1, result in r0), following the "Semihosting for AArch32 and AArch64"
 * specification, version 2.
 */
#include "hal/mps2/semihost.h"

#include <stddef.h>

enum {
    SYS_OPEN = 0x01,
    SYS_CLOSE = 0x02,
    SYS_WRITE0 = 0x04,
    SYS_WRITE = 0x05,
    SYS_READ = 0x06,
    SYS_GET_CMDLINE = 0x15,
    SYS_EXIT = 0x18,
    SYS_EXIT_EXTENDED = 0x20,
};

/* Reason codes for SYS_EXIT / SYS_EXIT_EXTENDED. */
enum {
    ADP_STOPPED_RUNTIME_ERROR_UNKNOWN = 0x20023,
    ADP_STOPPED_APPLICATION_EXIT = 0x20026,
};

static uint32_t semihost_call(uint32_t op, const void *arg)
{
    register uint32_t r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    /* "memory": the host reads the argument block and the string. */
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void hal_mps2_write_str(const char *s)
{
    (void)semihost_call(SYS_WRITE0, s);
}

/* Digits are written backwards from the end of a caller's buffer; returns
 * the first digit. buf_end points at the terminating NUL. */
static char *format_u32(uint32_t value, char *buf_end)
{
    char *p = buf_end;
    uint32_t rest = value;
    do {
        --p;
        *p = (char)('0' + (rest % 10U));
        rest /= 10U;
    } while (rest != 0U);
    return p;
}

static char *format_u64(uint64_t value, char *buf_end)
{
    /* The 64-bit path costs a libgcc division per digit: take the 32-bit one
     * as soon as the value fits. */
    char *p = buf_end;
    uint64_t rest = value;
    while (rest > UINT32_MAX) {
        --p;
        *p = (char)('0' + (uint32_t)(rest % 10U));
        rest /= 10U;
    }
    return format_u32((uint32_t)rest, p);
}

void hal_mps2_write_u32(uint32_t value)
{
    hal_mps2_write_u64(value);
}

void hal_mps2_write_i32(int32_t value)
{
    hal_mps2_write_i64(value);
}

void hal_mps2_write_u64(uint64_t value)
{
    char buf[21];
    buf[20] = '\0';
    hal_mps2_write_str(format_u64(value, &buf[20]));
}

void hal_mps2_write_i64(int64_t value)
{
    char buf[22];
    buf[21] = '\0';
    uint64_t magnitude = (value < 0) ? (0U - (uint64_t)value) : (uint64_t)value;
    char *p = format_u64(magnitude, &buf[21]);
    if (value < 0) {
        --p;
        *p = '-';
    }
    hal_mps2_write_str(p);
}

static void write_hex(uint64_t value, uint32_t digits)
{
    static const char hex_digits[16] = {
        '0', '1', '2', '3', '4', '5', '6', '7',
        '8', '9', 'a', 'b', 'c', 'd', 'e', 'f',
    };
    char buf[2U + 16U + 1U];
    buf[0] = '0';
    buf[1] = 'x';
    for (uint32_t i = 0U; i < digits; ++i) {
        uint32_t shift = 4U * (digits - 1U - i);
        buf[2U + i] = hex_digits[(uint32_t)(value >> shift) & 0xFU];
    }
    buf[2U + digits] = '\0';
    hal_mps2_write_str(buf);
}

void hal_mps2_write_hex32(uint32_t value)
{
    write_hex(value, 8U);
}

void hal_mps2_write_hex64(uint64_t value)
{
    write_hex(value, 16U);
}

void hal_mps2_write_bench(const char *name, uint64_t value, const char *unit)
{
    hal_mps2_write_str("bench: ");
    hal_mps2_write_str(name);
    hal_mps2_write_str(" ");
    hal_mps2_write_u64(value);
    hal_mps2_write_str(" ");
    hal_mps2_write_str(unit);
    hal_mps2_write_str("\n");
}

int32_t hal_mps2_file_open(const char *path, uint32_t mode)
{
    uint32_t len = 0U;
    while (path[len] != '\0') {
        len++;
    }
    const uint32_t block[3] = {(uint32_t)(uintptr_t)path, mode, len};
    return (int32_t)semihost_call(SYS_OPEN, block);
}

int32_t hal_mps2_file_read(int32_t handle, void *buf, uint32_t len)
{
    const uint32_t block[3] = {(uint32_t)handle, (uint32_t)(uintptr_t)buf, len};
    /* SYS_READ returns the number of bytes NOT read. */
    const uint32_t left = semihost_call(SYS_READ, block);
    if (left > len) {
        return -1;
    }
    const uint32_t got = len - left;
    return (int32_t)got;
}

int32_t hal_mps2_file_write(int32_t handle, const void *buf, uint32_t len)
{
    const uint32_t block[3] = {(uint32_t)handle, (uint32_t)(uintptr_t)buf, len};
    /* SYS_WRITE returns the number of bytes NOT written. */
    return (semihost_call(SYS_WRITE, block) == 0U) ? 0 : -1;
}

int32_t hal_mps2_file_close(int32_t handle)
{
    const uint32_t block[1] = {(uint32_t)handle};
    return (semihost_call(SYS_CLOSE, block) == 0U) ? 0 : -1;
}

int32_t hal_mps2_get_cmdline(char *buf, uint32_t cap)
{
    if (cap == 0U) {
        return -1;
    }
    uint32_t block[2] = {(uint32_t)(uintptr_t)buf, cap};
    if (semihost_call(SYS_GET_CMDLINE, block) != 0U) {
        return -1;
    }
    /* On success the host puts the length, without the NUL, in the block. */
    if (block[1] >= cap) {
        return -1;
    }
    buf[block[1]] = '\0';
    return (int32_t)block[1];
}

_Noreturn void hal_mps2_exit(int32_t status)
{
    /* SYS_EXIT_EXTENDED takes a two-word block: reason, then the subcode
     * that QEMU turns into its exit code. QEMU has it since version 4.2. */
    uint32_t block[2] = {ADP_STOPPED_APPLICATION_EXIT, (uint32_t)status};
    (void)semihost_call(SYS_EXIT_EXTENDED, block);

    /* A host without SYS_EXIT_EXTENDED returns: plain SYS_EXIT on AArch32
     * passes only the reason, so the status degrades to success/failure. */
    uint32_t reason = (status == 0) ? (uint32_t)ADP_STOPPED_APPLICATION_EXIT
                                    : (uint32_t)ADP_STOPPED_RUNTIME_ERROR_UNKNOWN;
    (void)semihost_call(SYS_EXIT, (const void *)(uintptr_t)reason);

    for (;;) {
        __asm__ volatile("wfi");
    }
}
