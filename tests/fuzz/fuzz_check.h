/*
 * fuzz_check.h - what the fuzz targets share: an invariant check that
 * aborts (libFuzzer then keeps the input as a crash), and a cursor over the
 * fuzzer's bytes that reads zeros once they run out.
 */
#ifndef FUZZ_CHECK_H
#define FUZZ_CHECK_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

/* An invariant of the code under test: on failure names it and aborts. */
#define FUZZ_CHECK(cond)                                                                  \
    do {                                                                                  \
        if (!(cond)) {                                                                    \
            fprintf(stderr, "%s:%d: invariant broken: %s\n", __FILE__, __LINE__, #cond); \
            abort();                                                                      \
        }                                                                                 \
    } while (0)

typedef struct {
    const uint8_t *p;
    size_t n;
} fuzz_in_t;

static inline int fuzz_left(const fuzz_in_t *in)
{
    return in->n > 0U;
}

static inline uint8_t fuzz_u8(fuzz_in_t *in)
{
    if (in->n == 0U) {
        return 0U;
    }
    const uint8_t b = in->p[0];
    in->p++;
    in->n--;
    return b;
}

static inline uint16_t fuzz_u16(fuzz_in_t *in)
{
    const uint16_t lo = fuzz_u8(in);
    return (uint16_t)(lo | ((uint16_t)fuzz_u8(in) << 8));
}

static inline uint32_t fuzz_u32(fuzz_in_t *in)
{
    const uint32_t lo = fuzz_u16(in);
    return lo | ((uint32_t)fuzz_u16(in) << 16);
}

static inline uint64_t fuzz_u64(fuzz_in_t *in)
{
    const uint64_t lo = fuzz_u32(in);
    return lo | ((uint64_t)fuzz_u32(in) << 32);
}

#endif /* FUZZ_CHECK_H */
