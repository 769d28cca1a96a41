/* cli_args.c - the option tables and platoon options of the host tools (contract in
 * cli_args.h). */
#include "lib/cli_args.h"

#include <stdio.h>
#include <string.h>

#include "firmware/pfe_platoon.h"

int cli_platoon_option(const char *a, const char *v, unsigned long *vehicles,
                       unsigned long *position, double *gap_m, int *bad)
{
    if (strcmp(a, "--vehicles") == 0) {
        *bad = cli_parse_ul(v, 1U, PFE_MAX_VEHICLES, vehicles);
    } else if (strcmp(a, "--position") == 0) {
        *bad = cli_parse_ul(v, 0U, PFE_MAX_VEHICLES - 1U, position);
    } else if ((gap_m != NULL) && (strcmp(a, "--gap-m") == 0)) {
        *bad = cli_parse_double(v, 0.0, 642.55, gap_m);
    } else {
        return 0;
    }
    return 1;
}

static const cli_option_t *find_option(const cli_option_t *opts, size_t n_opts, const char *a)
{
    for (size_t k = 0U; k < n_opts; k++) {
        if (strcmp(opts[k].name, a) == 0) {
            return &opts[k];
        }
    }
    return NULL;
}

/* One option's value v into o->out: 0, or -1 when v is not valid. */
static int set_option(const cli_option_t *o, const char *v)
{
    int bad = 0;
    switch (o->kind) {
    case CLI_FLAG:
        *(bool *)o->out = true;
        break;
    case CLI_TEXT:
        *(const char **)o->out = v;
        break;
    case CLI_LIST: {
        cli_list_t *l = (cli_list_t *)o->out;
        bad = (l->n < l->cap) ? 0 : 1;
        if (bad == 0) {
            l->items[l->n++] = v;
        }
        break;
    }
    case CLI_UL:
        bad = cli_parse_ul(v, (unsigned long)o->lo, (unsigned long)o->hi, (unsigned long *)o->out);
        break;
    default:
        bad = cli_parse_double(v, o->lo, o->hi, (double *)o->out);
        break;
    }
    if ((bad == 0) && (o->seen != NULL)) {
        *o->seen = true;
    }
    return bad;
}

int cli_parse_options(const char *prog, int argc, char **argv, int first, const cli_option_t *opts,
                      size_t n_opts, const char **pos, int max_pos, int *n_pos)
{
    *n_pos = 0;
    for (int i = first; i < argc; i++) {
        const char *a = argv[i];
        if ((a[0] != '-') || (a[1] == '\0')) {
            if (*n_pos == max_pos) {
                fprintf(stderr, "%s: at most %d argument%s ('%s' is one more)\n", prog, max_pos,
                        (max_pos == 1) ? "" : "s", a);
                return 2;
            }
            pos[(*n_pos)++] = a;
            continue;
        }
        const cli_option_t *o = find_option(opts, n_opts, a);
        if (o == NULL) {
            fprintf(stderr, "%s: unknown option '%s'\n", prog, a);
            return 2;
        }
        const char *v = NULL;
        if (o->kind != CLI_FLAG) {
            if (i + 1 >= argc) {
                fprintf(stderr, "%s: option %s needs a value\n", prog, a);
                return 2;
            }
            v = argv[++i];
        }
        if (set_option(o, v) != 0) {
            if (o->kind == CLI_LIST) {
                fprintf(stderr, "%s: option %s at most %u times\n", prog, a,
                        ((const cli_list_t *)o->out)->cap);
            } else if (o->kind == CLI_UL) {
                fprintf(stderr, "%s: option %s needs a whole number from %lu to %lu (got '%s')\n", prog,
                        a, (unsigned long)o->lo, (unsigned long)o->hi, v);
            } else {
                fprintf(stderr, "%s: option %s needs a number from %g to %g (got '%s')\n", prog, a,
                        o->lo, o->hi, v);
            }
            return 2;
        }
    }
    return 0;
}
