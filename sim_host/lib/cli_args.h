/*
 * cli_args.h - command-line numbers for the host tools, checked whole: the
 * text must be one number and nothing else, within [lo, hi] (both finite).
 * 0 and *out set, or -1 and *out untouched; the caller names the option in
 * its own message.
 */
#ifndef CLI_ARGS_H
#define CLI_ARGS_H

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdlib.h>

/* A decimal number (strtod syntax), not NaN nor infinite. */
static inline int cli_parse_double(const char *s, double lo, double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    const double v = strtod(s, &end);
    if ((errno != 0) || (end == s) || (*end != '\0') || !isfinite(v) || (v < lo) || (v > hi)) {
        return -1;
    }
    *out = v;
    return 0;
}

/* An unsigned integer, decimal or 0x hex (strtoul base 0); a sign is refused. */
static inline int cli_parse_ul(const char *s, unsigned long lo, unsigned long hi, unsigned long *out)
{
    char *end = NULL;
    errno = 0;
    const unsigned long v = strtoul(s, &end, 0);
    if ((errno != 0) || (end == s) || (*end != '\0') || (s[0] == '-') || (v < lo) || (v > hi)) {
        return -1;
    }
    *out = v;
    return 0;
}

/*
 * The platoon options of the tools that build one (drivegen, run_report,
 * pfe_ecu): --vehicles N (1 .. PFE_MAX_VEHICLES), --position P (0 ..
 * PFE_MAX_VEHICLES - 1; below N is the caller's check, once every option
 * is read) and, when gap_m is not NULL, --gap-m D (0 .. 642.55 m, what
 * PFE_PlatoonConfig carries). Returns 1 when option a is one of them, with
 * *bad set to whether its value v is bad (and the field untouched), else 0
 * with nothing changed (cli_args.c).
 */
int cli_platoon_option(const char *a, const char *v, unsigned long *vehicles,
                       unsigned long *position, double *gap_m, int *bad);

/*
 * A tool's options as a table, read by cli_parse_options():
 *   CLI_FLAG    no value; *(bool *)out = true
 *   CLI_TEXT    the next argument, any text; *(const char **)out = it
 *   CLI_UL      the next argument by cli_parse_ul within [lo, hi]
 *               (unsigned long *out)
 *   CLI_DOUBLE  the next argument by cli_parse_double within [lo, hi]
 *               (double *out)
 *   CLI_LIST    the next argument, any text, appended to a cli_list_t
 *               (out); one more than its capacity is an error
 * seen, when not NULL, is set true when the option is given.
 */
typedef enum { CLI_FLAG, CLI_TEXT, CLI_UL, CLI_DOUBLE, CLI_LIST } cli_kind_t;

/* The values of a CLI_LIST option, in the order given. */
typedef struct {
    const char **items;
    unsigned cap;
    unsigned n;
} cli_list_t;

typedef struct {
    const char *name; /* with its dashes: "--mass" */
    cli_kind_t kind;
    double lo, hi;    /* CLI_UL and CLI_DOUBLE only */
    void *out;
    bool *seen;       /* may be NULL */
} cli_option_t;

/*
 * Reads argv[first .. argc-1]: each argument that starts with '-' must be
 * one of opts[0 .. n_opts-1] (with its value when it takes one), every
 * other argument is positional and goes to pos[*n_pos] (at most max_pos).
 * Returns 0, or 2 after one line on stderr naming prog and the argument:
 * "PROG: unknown option '-x'", "PROG: option --x needs a value",
 * "PROG: option --x needs a number from LO to HI (got 'v')" (a whole
 * number for CLI_UL), "PROG: at most N arguments ('a' is one more)",
 * "PROG: option --x at most N times". A
 * lone "-" is positional (standard input, for tools that take it). What was read
 * before an error is set; the caller prints its usage if it wants.
 */
int cli_parse_options(const char *prog, int argc, char **argv, int first, const cli_option_t *opts,
                      size_t n_opts, const char **pos, int max_pos, int *n_pos);

#endif /* CLI_ARGS_H */
