/*
 * bad_image_float.c - an image that must fail scripts/check_image.sh: it
 * does floating-point arithmetic, which on a soft-float Cortex-M4 links the
 * __aeabi_f* helpers. `make test` links it and expects the check to refuse
 * it, which shows that the check can fail.
 */
#include <stdint.h>

volatile float g_value = 1.5f;

int main(void)
{
    g_value = g_value * 3.25f;
    return (int)(int32_t)g_value;
}
