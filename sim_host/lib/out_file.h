/*
 * out_file.h - a generated file written whole or not at all, for the host
 * tools that write C source for the firmware (road2c, dbc2c).
 */
#ifndef OUT_FILE_H
#define OUT_FILE_H

#include <stdio.h>

/* fill(f, ctx) fills PATH.tmp, which is then renamed to path. fill
 * returns 0, or nonzero on failure. Returns 0 done; -1 when the file cannot
 * be opened, written, closed or renamed, after one line on stderr prefixed
 * with prog, and with neither PATH.tmp nor a partial path left. */
int out_file_write(const char *path, const char *prog, int (*fill)(FILE *f, const void *ctx),
                   const void *ctx);

#endif /* OUT_FILE_H */
