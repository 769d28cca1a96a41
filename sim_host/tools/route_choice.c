/*
 * route_choice - which route burns the least fuel, and whether that is
 * guaranteed (thesis 5.1 and the rule of its chapter 7; the bounds of
 * sim_host/ref/fuel_bounds.h).
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lib/cli_args.h"
#include "ref/fuel_bounds.h"
#include "ref/node_model.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: route_choice [--vehicles N | --truck MASS_KG:PMAX_KW:CWAF_M2:ETA ...]\n"
    "                    [--set-speed-kmh V] [--time-gap-s H] ROUTE.csv ROUTE.csv ...\n"
    "\n"
    "Which route burns the least fuel, and whether that is guaranteed (thesis 5.1\n"
    "and the rule of its chapter 7).\n"
    "\n"
    "  --vehicles N         N default trucks, 1 to 64 (default 5)\n"
    "  --truck M:P:A:E      one truck: mass kg, wheel power kW, cw*Af m^2, efficiency\n"
    "                       (repeat, lead truck first; replaces --vehicles)\n"
    "  --set-speed-kmh V    set speed (default 90)\n"
    "  --time-gap-s H       followers' time gap (default 0.4)\n"
    "  ROUTE.csv            a route: at least 2 and at most 16\n"
    "  -h, --help           this help\n"
    "\n"
    "For each route (a road CSV) the object model predicts the\n"
    "platoon's fuel and travel time, and the fuel bounds give the lower and\n"
    "upper bound. Routes are ranked by predicted fuel. The best one is called\n"
    "\"guaranteed best\" only when every bound the claim relies on holds its\n"
    "assumptions and the numbers agree: the best route's upper bound (thesis\n"
    "5.1: same speed at the start and the end, an upgrade that slows the\n"
    "platoon) is below every other route's lower bound. The other routes'\n"
    "lower bound is the thesis's where its assumptions hold, and the energy\n"
    "bound where they do not, which holds without them (docs/thesis.md).\n"
    "Otherwise the verdict is \"best by estimate, not guaranteed\" with the\n"
    "reason: the route whose bounds overlap the best's, or the assumption the\n"
    "best route's upper bound misses.\n"
    "\n"
    "--truck adds one truck (in platoon order, the first leads) with the\n"
    "default calibration (docs/model.md) but this mass, wheel power, cw Af and\n"
    "efficiency; without --truck the platoon is N default trucks (default 5).\n"
    "A route on which the thesis's bounds' assumptions do not hold is marked\n"
    "in the table, and its lower bound is the energy bound.\n"
    "\n"
    "Exit status: 0 guaranteed best, 3 best by estimate, not guaranteed, 1 when\n"
    "the platoon stalls on a route, 2 on bad arguments or input (the message\n"
    "names the file, line and reason).\n"
    "\n"
    "Example:\n"
    "  route_choice sim_host/data/routes/ridge.csv sim_host/data/routes/detour.csv\n";

#define MAX_ROUTES 16
#define EXIT_NOT_GUARANTEED 3

static void usage(FILE *f)
{
    /* --help: the whole manual; a usage error: its synopsis. */
    if (f == stdout) {
        cli_help(k_manual);
    } else {
        cli_usage(f, k_manual, "route_choice");
    }
}

/* "M:P:A:E" into a calibration; returns 0 or -1 with the reason in err. */
static int parse_truck(const char *spec, pfe_vehicle_calib_t *c, char *err, size_t err_len)
{
    char buf[128];
    if (strlen(spec) >= sizeof buf) {
        (void)snprintf(err, err_len, "too long");
        return -1;
    }
    strcpy(buf, spec);
    const char *names[4] = {"mass", "power", "cw*Af", "efficiency"};
    const double lo[4] = {PFE_MASS_MIN_KG, 1.0, 0.0, 0.05};
    const double hi[4] = {PFE_MASS_MAX_KG, PFE_POWER_MAX_W / 1000.0, PFE_DRAG_AREA_MAX_MM2 / 1e6, 1.0};
    double v[4];
    char *p = buf;
    for (int k = 0; k < 4; k++) {
        char *colon = (k < 3) ? strchr(p, ':') : NULL;
        if ((k < 3) && (colon == NULL)) {
            (void)snprintf(err, err_len, "expected 4 fields MASS_KG:PMAX_KW:CWAF_M2:ETA");
            return -1;
        }
        if (colon != NULL) {
            *colon = '\0';
        }
        if (cli_parse_double(p, lo[k], hi[k], &v[k]) != 0) {
            (void)snprintf(err, err_len, "%s '%s' is not a number in [%g, %g]", names[k], p, lo[k], hi[k]);
            return -1;
        }
        p = (colon != NULL) ? colon + 1 : p;
    }
    *c = pfe_default_vehicle;
    c->mass_kg = (uint32_t)lround(v[0]);
    c->rot_mass_kg = (uint32_t)lround(v[0] * pfe_default_vehicle.rot_mass_kg / pfe_default_vehicle.mass_kg);
    c->power_max_w = (uint32_t)lround(v[1] * 1000.0);
    c->drag_area_mm2 = (uint32_t)lround(v[2] * 1e6);
    c->eta_ppm = (uint32_t)lround(v[3] * 1e6);
    if (pfe_calib_check_vehicle(c) != 0) {
        (void)snprintf(err, err_len, "out of the calibration's range");
        return -1;
    }
    return 0;
}

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return (s != NULL) ? s + 1 : path;
}

int main(int argc, char **argv)
{
    static pfe_vehicle_calib_t trucks[NODE_MAX_VEHICLES];
    unsigned n_trucks = 0U;
    const char *routes[MAX_ROUTES];
    int n_routes = 0;
    unsigned long n = 5U;
    double set_kmh = 90.0, time_gap = 0.4;
    char err[512];
    if (cli_help_asked(argc, argv)) {
        usage(stdout);
        return 0;
    }
    const char *truck_args[NODE_MAX_VEHICLES];
    cli_list_t truck_list = {truck_args, NODE_MAX_VEHICLES, 0U};
    bool vehicles_given = false;
    const cli_option_t opts[] = {
        {"--vehicles", CLI_UL, 1.0, NODE_MAX_VEHICLES, &n, &vehicles_given},
        {"--set-speed-kmh", CLI_DOUBLE, 5.0, 250.0, &set_kmh, NULL},
        {"--time-gap-s", CLI_DOUBLE, 0.0, 10.0, &time_gap, NULL},
        {"--truck", CLI_LIST, 0.0, 0.0, &truck_list, NULL},
    };
    if (cli_parse_options("route_choice", argc, argv, 1, opts, sizeof opts / sizeof opts[0], routes,
                          MAX_ROUTES, &n_routes) != 0) {
        usage(stderr);
        return 2;
    }
    for (unsigned k = 0U; k < truck_list.n; k++) {
        if (parse_truck(truck_args[k], &trucks[n_trucks], err, sizeof err) != 0) {
            fprintf(stderr, "route_choice: --truck %s: %s\n", truck_args[k], err);
            return 2;
        }
        n_trucks++;
    }
    if (n_routes < 2) {
        fprintf(stderr, "route_choice: give at least two routes to choose from\n");
        usage(stderr);
        return 2;
    }
    if ((n_trucks > 0U) && vehicles_given) {
        fprintf(stderr, "route_choice: --vehicles and --truck exclude each other\n");
        return 2;
    }
    static node_config_t cfg;
    node_config_default(&cfg, (n_trucks > 0U) ? n_trucks : (unsigned)n);
    for (unsigned i = 0U; i < n_trucks; i++) {
        cfg.vehicle[i] = &trucks[i];
    }
    cfg.set_speed_m_s = set_kmh / 3.6;
    cfg.initial_speed_m_s = cfg.set_speed_m_s;
    cfg.time_gap_s = time_gap;
    if (node_config_check(&cfg, err, sizeof err) != 0) {
        fprintf(stderr, "route_choice: %s\n", err);
        return 2;
    }

    static fuel_bounds_t b[MAX_ROUTES];
    static char why[MAX_ROUTES][256];
    route_estimate_t est[MAX_ROUTES];
    double length_km[MAX_ROUTES];
    for (int r = 0; r < n_routes; r++) {
        node_road_t road;
        if (node_road_load(routes[r], &road, err, sizeof err) != 0) {
            fprintf(stderr, "route_choice: %s\n", err);
            return 2;
        }
        length_km[r] = node_road_length_m(&road.road) / 1000.0;
        const int rc = fuel_bounds_compute(&cfg, &road.road, &b[r], err, sizeof err);
        node_road_free(&road);
        if (rc != 0) {
            fprintf(stderr, "route_choice: %s: %s\n", routes[r], err);
            return (rc == -2) ? 1 : 2;
        }
        (void)fuel_bounds_why_not(&b[r], why[r], sizeof why[r]);
        est[r] = (route_estimate_t){b[r].fuel_l, b[r].sound_lower_l, b[r].upper_l,
                                    b[r].upper_holds ? NULL : why[r]};
    }
    size_t order[MAX_ROUTES];
    size_t blocker = 0U;
    const int guaranteed = route_rank(est, (size_t)n_routes, order, &blocker);

    printf("route_choice: %u trucks", cfg.n_vehicles);
    if (n_trucks > 0U) {
        printf(" (");
        for (unsigned i = 0U; i < n_trucks; i++) {
            printf("%s%u kg %u kW %.2f m^2 %.3f", (i > 0U) ? ", " : "", trucks[i].mass_kg,
                   trucks[i].power_max_w / 1000U, trucks[i].drag_area_mm2 / 1e6, trucks[i].eta_ppm / 1e6);
        }
        printf(")");
    }
    printf(", set speed %.1f km/h, time gap %.2f s\n", set_kmh, cfg.time_gap_s);
    printf("fuel: object model prediction; bounds: thesis 5.1, lower: the thesis's (5.1) or the "
           "energy bound (E) where the thesis's does not hold (fuel_bounds.h)\n\n");
    printf("%-4s %-14s %8s %12s %12s %10s %12s  %s\n", "rank", "route", "km", "fuel [L]", "lower [L]",
           "upper [L]", "time [min]", "thesis's bounds' assumptions");
    for (int k = 0; k < n_routes; k++) {
        const size_t r = order[k];
        const fuel_bounds_t *x = &b[r];
        printf("%-4d %-14s %8.2f %12.3f %8.3f %-3s %10.3f %12.2f  %s\n", k + 1, base_name(routes[r]),
               length_km[r], x->fuel_l, x->sound_lower_l, x->sound_lower_energy ? "E" : "5.1", x->upper_l,
               x->time_s / 60.0, (why[r][0] != '\0') ? why[r] : "hold");
    }
    const size_t best = order[0];
    printf("\n");
    if (guaranteed == 1) {
        size_t lowest = order[1];
        for (int k = 2; k < n_routes; k++) {
            lowest = (b[order[k]].sound_lower_l < b[lowest].sound_lower_l) ? order[k] : lowest;
        }
        printf("guaranteed best: %s (its upper bound %.3f L is below every other route's lower bound; "
               "the lowest of those is %s, %.3f L)\n",
               base_name(routes[best]), b[best].upper_l, base_name(routes[lowest]), b[lowest].sound_lower_l);
        return 0;
    }
    if (guaranteed == 2) {
        printf("best by estimate, not guaranteed: %s (its upper bound %.3f L is below every other "
               "route's lower bound, but it does not hold on %s: %s)\n",
               base_name(routes[best]), b[best].upper_l, base_name(routes[best]), why[best]);
    } else {
        printf("best by estimate, not guaranteed: %s (its upper bound %.3f L is not below the "
               "lower bound of %s, %.3f L%s%s)\n",
               base_name(routes[best]), b[best].upper_l, base_name(routes[blocker]),
               b[blocker].sound_lower_l, b[best].upper_holds ? "" : "; nor does that upper bound hold: ",
               b[best].upper_holds ? "" : why[best]);
    }
    return EXIT_NOT_GUARANTEED;
}
