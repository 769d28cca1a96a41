/*
 * plot.h - what the host tools that write gnuplot scripts share
 * (run_report, sensitivity).
 */
#ifndef PLOT_H
#define PLOT_H

#include <stdio.h>

/* Writes s to f as a gnuplot single-quoted string: in quotes, each quote
 * inside doubled (gnuplot's only escape in such strings). */
void plot_quoted(FILE *f, const char *s);

#endif /* PLOT_H */
