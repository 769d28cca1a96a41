/*
 * Planted MISRA C:2012 violations: `make misra` runs its check over this
 * file, with the project's deviations, and must fail naming each line marked
 * "planted" with its rule, and nothing else (tests/misra/planted_test.sh).
 */
#include <stdint.h>
#include <string.h>

void planted_clear(uint8_t *buf, uint32_t len, int flag);

void planted_clear(uint8_t *buf, uint32_t len, int flag)
{
    if (flag) { /* planted: 14.4 */
        memset(buf, 0, len); /* planted: 17.7 */
    }
}
