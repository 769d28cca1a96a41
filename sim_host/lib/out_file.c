/* out_file.c - a generated file written whole or not at all (contract in out_file.h). */
#include "lib/out_file.h"

#include <stdlib.h>
#include <string.h>

int out_file_write(const char *path, const char *prog, int (*fill)(FILE *f, const void *ctx),
                   const void *ctx)
{
    const size_t len = strlen(path);
    char *tmp_path = malloc(len + sizeof ".tmp");
    if (tmp_path == NULL) {
        fprintf(stderr, "%s: out of memory\n", prog);
        return -1;
    }
    memcpy(tmp_path, path, len);
    memcpy(tmp_path + len, ".tmp", sizeof ".tmp");
    int rc = -1;
    FILE *out = fopen(tmp_path, "wb");
    if (out == NULL) {
        perror(tmp_path);
    } else {
        int bad = fill(out, ctx) != 0;
        bad |= fclose(out) != 0;
        if (bad || rename(tmp_path, path) != 0) {
            fprintf(stderr, "%s: cannot write %s\n", prog, path);
            (void)remove(tmp_path);
        } else {
            rc = 0;
        }
    }
    free(tmp_path);
    return rc;
}
