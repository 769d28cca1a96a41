/* cli_args.c - the platoon options of the host tools (contract in cli_args.h). */
#include "lib/cli_args.h"

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
