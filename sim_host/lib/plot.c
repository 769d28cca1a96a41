/* plot.c - gnuplot strings (contract in plot.h). */
#include "lib/plot.h"

void plot_quoted(FILE *f, const char *s)
{
    (void)fputc('\'', f);
    for (; *s != '\0'; s++) {
        if (*s == '\'') {
            (void)fputc('\'', f);
        }
        (void)fputc(*s, f);
    }
    (void)fputc('\'', f);
}
