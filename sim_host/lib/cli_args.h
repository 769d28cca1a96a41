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

#endif /* CLI_ARGS_H */
