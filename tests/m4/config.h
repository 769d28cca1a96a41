/*
 * CMocka build configuration for arm-none-eabi with full newlib and
 * librdimon (semihosting), in place of the config.h that CMocka's CMake
 * generates. Used only to compile cmocka.c for test images (mk/m4.mk).
 *
 * Left undefined on purpose:
 * - HAVE_STRUCT_TIMESPEC / HAVE_CLOCK_REALTIME: newlib declares
 *   clock_gettime() but librdimon does not implement it; test run times are
 *   then reported as 0.
 * - HAVE_SIGLONGJMP: newlib has sigsetjmp only for Cygwin and RTEMS; plain
 *   setjmp/longjmp is enough on a single-threaded core.
 * - HAVE_GCC_THREAD_LOCAL_STORAGE: no TLS on bare metal, and none needed.
 * - HAVE_MALLOC_H: unused.
 */
#ifndef CMOCKA_M4_CONFIG_H
#define CMOCKA_M4_CONFIG_H

#define PACKAGE "cmocka"

#define HAVE_ASSERT_H 1
#define HAVE_INTTYPES_H 1
#define HAVE_SETJMP_H 1
#define HAVE_SIGNAL_H 1
#define HAVE_STDARG_H 1
#define HAVE_STDDEF_H 1
#define HAVE_STDINT_H 1
#define HAVE_STDIO_H 1
#define HAVE_STDLIB_H 1
#define HAVE_STRINGS_H 1
#define HAVE_STRING_H 1
#define HAVE_SYS_TYPES_H 1
#define HAVE_TIME_H 1
#define HAVE_UNISTD_H 1

#define HAVE_CALLOC 1
#define HAVE_EXIT 1
#define HAVE_FPRINTF 1
#define HAVE_FREE 1
#define HAVE_LONGJMP 1
#define HAVE_MALLOC 1
#define HAVE_MEMCPY 1
#define HAVE_MEMSET 1
#define HAVE_PRINTF 1
#define HAVE_SETJMP 1
#define HAVE_SIGNAL 1
#define HAVE_SNPRINTF 1
#define HAVE_STRCMP 1
#define HAVE_STRCPY 1
#define HAVE_STRSIGNAL 1
#define HAVE_VSNPRINTF 1

/* Debian's newlib is built without C99 printf conversions: %zd, %zu, %jd,
 * %td and %hhd print literally (%lld and %llx work). CMocka prints its
 * test counts with PRIdS, "zd" by default; size_t is unsigned int on
 * arm-none-eabi, so "d" prints it correctly. One message, CMocka's report of
 * leaked blocks, has a literal %zu and shows "zu" instead of the count. */
#define PRIdS "d"

/* Cortex-M4: 32-bit pointers, little endian (WORDS_BIGENDIAN undefined). */
#define WORDS_SIZEOF_VOID_P 4

#endif /* CMOCKA_M4_CONFIG_H */
