/*
 * sensitivity - the thesis's sensitivity analysis (chapter 6): the steps of
 * each input are in sim_host/ref/sensitivity_run.h.
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include "lib/cli_args.h"
#include "lib/plot.h"
#include "lib/road_csv.h"
#include "ref/sensitivity_run.h"
#include "lib/cli_help.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: sensitivity [--out DIR] [--vehicles N] [--set-speed-kmh V] [--no-plot]\n"
    "                   [--gnuplot PROG] ROAD.csv...\n"
    "\n"
    "The thesis's sensitivity analysis (chapter 6) on road profiles: grade,\n"
    "cw * Af, Pmax, time gap and mass changed one at a time by the thesis's steps,\n"
    "the platoon object model in double precision, N = 5 at 90 km/h unless told\n"
    "otherwise.\n"
    "\n"
    "  --out DIR           where NAME.csv, NAME.gp and NAME.png go (default build/sensitivity)\n"
    "  --vehicles N        platoon size, 1 to 32 (default 5)\n"
    "  --set-speed-kmh V   cruise set speed and start speed, 5 to 250 (default 90)\n"
    "  --no-plot           write the CSV only\n"
    "  --gnuplot PROG      the gnuplot to run (default: gnuplot on PATH)\n"
    "  -h, --help          this help\n"
    "\n"
    "For each road (named after its file, without \".csv\") it prints a table of\n"
    "every case (fuel, change against the nominal case, time, mean, min and max\n"
    "speed, share of time at the power limit), writes DIR/NAME.csv with the same\n"
    "rows and DIR/NAME.png (gnuplot, through the script it leaves in DIR/NAME.gp),\n"
    "and prints their paths. Then come the analogues of thesis tables 6.1 to 6.3\n"
    "(and of 6.4, 6.5, lost from the thesis's text): fuel change in percent, one\n"
    "row per road. The steps of each input: docs/thesis.md.\n"
    "\n"
    "Exit status: 0 on success; 1 when a case stalled (the platoon fell below\n"
    "1 m/s: its row says where, its fuel stops there and it is left out of the\n"
    "plot) or gnuplot failed; 2 on bad arguments, an unreadable or bad road, or\n"
    "an output that cannot be written.\n"
    "\n"
    "Example:\n"
    "  sensitivity --out build/sensitivity sim_host/data/roads/flat.csv sim_host/data/roads/hilly.csv\n";

extern char **environ;

#define MAX_ROADS 16U
#define MAX_STEPS 16U
#define NAME_LEN 64U

/* The parameters in the thesis's order (6.1 to 6.5). */
static const sens_param_t params[] = {SENS_GRADE, SENS_DRAG_AREA, SENS_POWER, SENS_TIME_GAP,
                                      SENS_MASS};
#define N_PARAMS (sizeof(params) / sizeof(params[0]))

typedef struct {
    char name[NAME_LEN];
    const char *path;
    double length_m;
    sens_result_t nominal;
    size_t n_steps[N_PARAMS];
    const int32_t *steps[N_PARAMS];
    sens_result_t result[N_PARAMS][MAX_STEPS];
} road_run_t;

static void usage(FILE *f)
{
    /* --help: the whole manual; a usage error: its synopsis. */
    if (f == stdout) {
        cli_help(k_manual);
    } else {
        cli_usage(f, k_manual, "sensitivity");
    }
}

/* NAME from .../NAME.csv; -1 when empty or too long. */
static int road_name(const char *path, char *name)
{
    const char *base = strrchr(path, '/');
    base = (base == NULL) ? path : base + 1;
    size_t len = strlen(base);
    if ((len > 4U) && (strcmp(base + len - 4U, ".csv") == 0)) {
        len -= 4U;
    }
    if ((len == 0U) || (len >= NAME_LEN)) {
        return -1;
    }
    memcpy(name, base, len);
    name[len] = '\0';
    return 0;
}

/* mkdir -p; 0 or -1 with errno. */
static int make_dirs(const char *dir)
{
    char buf[1024];
    const size_t len = strlen(dir);
    if ((len == 0U) || (len >= sizeof buf)) {
        errno = ENAMETOOLONG;
        return -1;
    }
    memcpy(buf, dir, len + 1U);
    for (size_t i = 1U; i <= len; i++) {
        if ((buf[i] == '/') || (buf[i] == '\0')) {
            const char c = buf[i];
            buf[i] = '\0';
            if ((mkdir(buf, 0777) != 0) && (errno != EEXIST)) {
                return -1;
            }
            buf[i] = c;
        }
    }
    struct stat st;
    if ((stat(dir, &st) != 0) || !S_ISDIR(st.st_mode)) {
        errno = ENOTDIR;
        return -1;
    }
    return 0;
}

static double rel_pct(double x, double nominal)
{
    return (nominal != 0.0) ? (100.0 * (x - nominal) / nominal) : 0.0;
}

/* The change of a case against the nominal one, in percent: the step
 * itself, or for the gap the change of the time gap. */
static double change_pct(sens_param_t p, int32_t amount, uint32_t nominal_gap_ms)
{
    return (p == SENS_TIME_GAP) ? (100.0 * ((double)amount - nominal_gap_ms) / nominal_gap_ms)
                                : (double)amount;
}

/* "±0" only when the figure is bit for bit the nominal one. */
static void format_change(char *buf, size_t len, double x, double nominal, int decimals)
{
    if (x == nominal) {
        snprintf(buf, len, "±0");
    } else {
        snprintf(buf, len, "%+.*f", decimals, rel_pct(x, nominal));
    }
}

static void format_value(char *buf, size_t len, const sens_setup_t *s, sens_param_t p, int32_t a)
{
    uint32_t v = 0U;
    switch (p) {
    case SENS_GRADE:
        snprintf(buf, len, "grade x%.2f", 1.0 + (a / 100.0));
        break;
    case SENS_DRAG_AREA:
        v = (uint32_t)((((uint64_t)s->vehicle->drag_area_mm2 * (uint64_t)(100 + a)) + 50U) / 100U);
        snprintf(buf, len, "%.2f m2", v / 1e6);
        break;
    case SENS_POWER:
        v = (uint32_t)((((uint64_t)s->vehicle->power_max_w * (uint64_t)(100 + a)) + 50U) / 100U);
        snprintf(buf, len, "%.0f kW", v / 1e3);
        break;
    case SENS_TIME_GAP:
        snprintf(buf, len, "%.2f s", a / 1000.0);
        break;
    case SENS_MASS:
        v = (uint32_t)((((uint64_t)s->vehicle->mass_kg * (uint64_t)(100 + a)) + 50U) / 100U);
        snprintf(buf, len, "%.1f t", v / 1e3);
        break;
    case SENS_NOMINAL:
    case SENS_N_PARAMS:
    default:
        snprintf(buf, len, "-");
        break;
    }
}

static const char *param_title(sens_param_t p)
{
    switch (p) {
    case SENS_GRADE:
        return "grade";
    case SENS_DRAG_AREA:
        return "cw*Af";
    case SENS_POWER:
        return "Pmax";
    case SENS_TIME_GAP:
        return "time gap";
    case SENS_MASS:
        return "mass";
    case SENS_NOMINAL:
    case SENS_N_PARAMS:
    default:
        return "nominal";
    }
}

/* Prints s right-aligned in width characters: "±" is two bytes, one character. */
static void put_cell(const char *s, int width)
{
    int chars = 0;
    for (const char *c = s; *c != '\0'; c++) {
        chars += ((((unsigned char)*c) & 0xC0U) != 0x80U) ? 1 : 0;
    }
    for (; chars < width; chars++) {
        putchar(' ');
    }
    fputs(s, stdout);
}

static void print_row(const char *param, const char *chg, const char *value,
                      const sens_result_t *r, const sens_result_t *nom)
{
    char fuel_chg[32];
    char time_chg[32];
    format_change(fuel_chg, sizeof fuel_chg, r->fuel_l, nom->fuel_l, 2);
    format_change(time_chg, sizeof time_chg, r->time_s, nom->time_s, 2);
    printf("%-9s", param);
    put_cell(chg, 7);
    printf(" %-12s %9.4f", value, r->fuel_l);
    put_cell(fuel_chg, 9);
    printf(" %8.2f", r->time_s);
    put_cell(time_chg, 9);
    printf(" %7.2f %7.2f %7.2f %6.1f", r->mean_kmh, r->min_kmh, r->max_kmh, r->power_limited_pct);
    if (r->stalled) {
        printf("  STALLED at %.0f m", r->stall_position_m);
    }
    printf("\n");
}

static void print_road_table(const road_run_t *rr, const sens_setup_t *s)
{
    printf("\n== %s (%s): %.3f km, N = %lu, %.1f km/h, time gap %.2f s (%.2f m), %.0f m steps\n",
           rr->name, rr->path, rr->length_m / 1000.0, (unsigned long)s->n_vehicles,
           s->set_speed_mm_s * 0.0036, s->time_gap_ms / 1000.0, rr->nominal.gap_m,
           s->step_mm / 1000.0);
    printf("%-9s%7s %-12s %9s %9s %8s %9s %7s %7s %7s %6s\n", "parameter", "change", "value",
           "fuel [L]", "fuel [%]", "time [s]", "time [%]", "mean", "min", "max", "at lim");
    printf("%-9s%7s %-12s %9s %9s %8s %9s %7s %7s %7s %6s\n", "", "", "", "", "", "", "",
           "[km/h]", "[km/h]", "[km/h]", "[%]");
    print_row("nominal", "", "", &rr->nominal, &rr->nominal);
    for (size_t p = 0U; p < N_PARAMS; p++) {
        for (size_t k = 0U; k < rr->n_steps[p]; k++) {
            const int32_t a = rr->steps[p][k];
            char chg[32];
            char value[32];
            const double c = change_pct(params[p], a, s->time_gap_ms);
            if (c == 0.0) {
                snprintf(chg, sizeof chg, "±0%%");
            } else {
                snprintf(chg, sizeof chg, "%+.0f%%", c);
            }
            format_value(value, sizeof value, s, params[p], a);
            print_row(param_title(params[p]), chg, value, &rr->result[p][k], &rr->nominal);
        }
    }
}

static int write_csv(const char *path, const road_run_t *rr, const sens_setup_t *s)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        fprintf(stderr, "sensitivity: cannot write %s: %s\n", path, strerror(errno));
        return -1;
    }
    fprintf(f, "# Sensitivity of the platoon object model on road %s (%s): N = %lu, "
               "set speed %.1f km/h, nominal time gap %.2f s\n",
            rr->name, rr->path, (unsigned long)s->n_vehicles, s->set_speed_mm_s * 0.0036,
            s->time_gap_ms / 1000.0);
    fprintf(f, "parameter,change_pct,time_gap_s,fuel_l,fuel_change_pct,time_s,time_change_pct,"
               "mean_kmh,min_kmh,max_kmh,power_limited_pct,stalled\n");
    const sens_result_t *nom = &rr->nominal;
    fprintf(f, "nominal,0,%.3f,%.6f,0,%.3f,0,%.4f,%.4f,%.4f,%.2f,%d\n", s->time_gap_ms / 1000.0,
            nom->fuel_l, nom->time_s, nom->mean_kmh, nom->min_kmh, nom->max_kmh,
            nom->power_limited_pct, nom->stalled);
    for (size_t p = 0U; p < N_PARAMS; p++) {
        for (size_t k = 0U; k < rr->n_steps[p]; k++) {
            const int32_t a = rr->steps[p][k];
            const sens_result_t *r = &rr->result[p][k];
            const double gap_s = (params[p] == SENS_TIME_GAP) ? (a / 1000.0)
                                                               : (s->time_gap_ms / 1000.0);
            fprintf(f, "%s,%.2f,%.3f,%.6f,%.4f,%.3f,%.4f,%.4f,%.4f,%.4f,%.2f,%d\n",
                    sens_param_name(params[p]), change_pct(params[p], a, s->time_gap_ms), gap_s,
                    r->fuel_l, rel_pct(r->fuel_l, nom->fuel_l), r->time_s,
                    rel_pct(r->time_s, nom->time_s), r->mean_kmh, r->min_kmh, r->max_kmh,
                    r->power_limited_pct, r->stalled);
        }
    }
    if ((fflush(f) != 0) || ferror(f)) {
        fprintf(stderr, "sensitivity: write error on %s\n", path);
        fclose(f);
        return -1;
    }
    if (fclose(f) != 0) {
        fprintf(stderr, "sensitivity: cannot close %s: %s\n", path, strerror(errno));
        return -1;
    }
    return 0;
}

/* One curve: the rows of parameter name, x and y columns of the CSV, rows
 * of stalled cases left out. */
static void gp_series(FILE *f, int first, const char *name, int x_col, int y_col, int point,
                      const char *title)
{
    fprintf(f, "%s", first ? "plot csv" : ", \\\n     csv");
    fprintf(f, " using (ok('%s') ? column(%d) : NaN):(ok('%s') ? column(%d) : NaN)"
               " with linespoints lw 2 pt %d ps 1.2 title ",
            name, x_col, name, y_col, point);
    plot_quoted(f, title);
}

/* The y range of one panel: the curves' own, widened to at least 2 units
 * around its middle so that a flat curve (speed on the flat road) still
 * gets an axis. gap: the time-gap panel or the other one; speed: mean speed
 * or fuel change. */
static void gp_yrange(FILE *f, const road_run_t *rr, int gap, int speed)
{
    double lo = INFINITY;
    double hi = -INFINITY;
    for (size_t p = 0U; p < N_PARAMS; p++) {
        if ((params[p] == SENS_TIME_GAP) != (gap != 0)) {
            continue;
        }
        for (size_t k = 0U; k < rr->n_steps[p]; k++) {
            const sens_result_t *r = &rr->result[p][k];
            if (r->stalled) {
                continue;
            }
            const double y = speed ? r->mean_kmh : rel_pct(r->fuel_l, rr->nominal.fuel_l);
            lo = fmin(lo, y);
            hi = fmax(hi, y);
        }
    }
    if (!(lo <= hi) || (hi - lo >= 2.0)) {
        fprintf(f, "set yrange [*:*]\n");
    } else {
        const double mid = 0.5 * (lo + hi);
        fprintf(f, "set yrange [%.3f:%.3f]\n", mid - 1.0, mid + 1.0);
    }
}

/* Four panels: fuel change and mean speed, against the relative change of
 * grade, cw*Af, Pmax and mass (left) and against the time gap (right). */
static int write_gp(const char *path, const char *csv, const char *png, const road_run_t *rr,
                    const sens_setup_t *s)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        fprintf(stderr, "sensitivity: cannot write %s: %s\n", path, strerror(errno));
        return -1;
    }
    fprintf(f, "# Written by sensitivity; run with: gnuplot %s\n", path);
    fprintf(f, "set terminal pngcairo size 1400,1000 font 'sans,11'\nset output ");
    plot_quoted(f, png);
    fprintf(f, "\ncsv = ");
    plot_quoted(f, csv);
    /* Column 1 is the parameter's name, column 12 says whether the case stalled. */
    fprintf(f, "\nset datafile separator ','\nset grid\nset key below horizontal\n"
               "set offsets 0, 0, graph 0.05, graph 0.05\n"
               "ok(p) = (strcol(1) eq p && column(12) == 0)\n");
    char title[256];
    if (snprintf(title, sizeof title,
                 "Sensitivity on road %s: object model, N = %lu, %.0f km/h, nominal time gap %.1f s",
                 rr->name, (unsigned long)s->n_vehicles, s->set_speed_mm_s * 0.0036,
                 s->time_gap_ms / 1000.0) >= (int)sizeof title) {
        title[sizeof title - 1U] = '\0'; /* a long title is cut, not an error */
    }
    fprintf(f, "set multiplot layout 2,2 title ");
    plot_quoted(f, title);
    fprintf(f, " font 'sans,14'\n");
    static const struct {
        const char *name, *title;
    } rel[] = {
        {"grade", "grade (every sample scaled)"},
        {"cw_af", "cw·Af"},
        {"pmax", "Pmax"},
        {"mass", "mass m"},
    };
    /* CSV columns: 2 change_pct, 3 time_gap_s, 5 fuel_change_pct, 8 mean_kmh. */
    static const struct {
        int column;
        const char *ylabel;
    } panels[2] = {{5, "fuel change against nominal [%]"}, {8, "mean speed [km/h]"}};
    for (size_t row = 0U; row < 2U; row++) {
        fprintf(f, "set xlabel 'change of the parameter against nominal [%%]'\n"
                   "set ylabel '%s'\nunset arrow\nset xrange [-75:75]\n",
                panels[row].ylabel);
        gp_yrange(f, rr, 0, row == 1U);
        for (size_t i = 0U; i < sizeof rel / sizeof rel[0]; i++) {
            gp_series(f, i == 0U, rel[i].name, 2, panels[row].column, 5 + (2 * (int)i),
                      rel[i].title);
        }
        fprintf(f, "\nset xlabel 'time gap [s]'\nset xrange [0:1.7]\n"
                   "set arrow from %.3f, graph 0 to %.3f, graph 1 nohead dt 2 lc 'gray40'\n",
                s->time_gap_ms / 1000.0, s->time_gap_ms / 1000.0);
        gp_yrange(f, rr, 1, row == 1U);
        gp_series(f, 1, "time_gap", 3, panels[row].column, 7, "time gap (dashed line: nominal)");
        fprintf(f, "\n");
    }
    fprintf(f, "unset multiplot\n");
    if ((fflush(f) != 0) || ferror(f) || (fclose(f) != 0)) {
        fprintf(stderr, "sensitivity: write error on %s\n", path);
        return -1;
    }
    return 0;
}

/* Runs PROG SCRIPT; 0 when it exits 0. */
static int run_gnuplot(const char *prog, const char *script)
{
    char *const argv[] = {(char *)(uintptr_t)prog, (char *)(uintptr_t)script, NULL};
    pid_t pid;
    const int rc = posix_spawnp(&pid, prog, NULL, NULL, argv, environ);
    if (rc != 0) {
        fprintf(stderr, "sensitivity: cannot run %s: %s (install gnuplot-nox, or use --no-plot)\n",
                prog, strerror(rc));
        return -1;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) {
            fprintf(stderr, "sensitivity: waiting for %s: %s\n", prog, strerror(errno));
            return -1;
        }
    }
    if (!WIFEXITED(status) || (WEXITSTATUS(status) != 0)) {
        fprintf(stderr, "sensitivity: %s %s failed (status %d)\n", prog, script, status);
        return -1;
    }
    return 0;
}

static void print_thesis_tables(const road_run_t *runs, size_t n_roads)
{
    static const char *const captions[N_PARAMS] = {
        "table 6.1 analogue: every grade sample scaled",
        "table 6.2 analogue: air drag coefficient times frontal area",
        "table 6.3 analogue: maximum power to the wheels",
        "table 6.4 analogue (lost from the thesis's text): time gap",
        "table 6.5 analogue (lost from the thesis's text): mass of every truck",
    };
    for (size_t p = 0U; p < N_PARAMS; p++) {
        printf("\nFuel change against the nominal case [%%], %s\n", captions[p]);
        printf("%-10s", "road");
        const size_t n = runs[0].n_steps[p];
        for (size_t k = 0U; k < n; k++) {
            const int32_t a = runs[0].steps[p][k];
            char head[32];
            if (params[p] == SENS_TIME_GAP) {
                snprintf(head, sizeof head, "%.2f s", a / 1000.0);
            } else if (a == 0) {
                snprintf(head, sizeof head, "±0%%");
            } else {
                snprintf(head, sizeof head, "%+d%%", (int)a);
            }
            put_cell(head, 9);
        }
        printf("\n");
        for (size_t r = 0U; r < n_roads; r++) {
            printf("%-10s", runs[r].name);
            for (size_t k = 0U; k < n; k++) {
                const sens_result_t *x = &runs[r].result[p][k];
                char cell[32];
                if (x->stalled) {
                    snprintf(cell, sizeof cell, "stall");
                } else {
                    format_change(cell, sizeof cell, x->fuel_l, runs[r].nominal.fuel_l, 2);
                }
                put_cell(cell, 9);
            }
            printf("\n");
        }
    }
}

int main(int argc, char **argv)
{
    const char *out_dir = "build/sensitivity";
    const char *gnuplot = "gnuplot";
    const char *road_paths[MAX_ROADS];
    size_t n_roads = 0U;
    int plot = 1;
    double n = 5.0;
    double set_kmh = 90.0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
        int bad = 0;
        if ((strcmp(a, "--help") == 0) || (strcmp(a, "-h") == 0)) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--no-plot") == 0) {
            plot = 0;
            continue;
        } else if (strncmp(a, "--", 2) != 0) {
            if (n_roads == MAX_ROADS) {
                fprintf(stderr, "sensitivity: at most %u roads\n", MAX_ROADS);
                return 2;
            }
            road_paths[n_roads++] = a;
            continue;
        } else if ((strcmp(a, "--out") != 0) && (strcmp(a, "--gnuplot") != 0) &&
                   (strcmp(a, "--vehicles") != 0) && (strcmp(a, "--set-speed-kmh") != 0)) {
            fprintf(stderr, "sensitivity: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        } else if (v == NULL) {
            bad = 1;
        } else if (strcmp(a, "--out") == 0) {
            out_dir = v;
            bad = (*v == '\0');
        } else if (strcmp(a, "--gnuplot") == 0) {
            gnuplot = v;
            bad = (*v == '\0');
        } else if (strcmp(a, "--vehicles") == 0) {
            bad = cli_parse_double(v, 1.0, PFE_MAX_VEHICLES, &n) || (n != floor(n));
        } else {
            bad = cli_parse_double(v, 5.0, 250.0, &set_kmh); /* --set-speed-kmh */
        }
        if (bad) {
            fprintf(stderr, "sensitivity: option %s needs a valid value (got '%s')\n", a,
                    v ? v : "nothing");
            return 2;
        }
        i++;
    }
    if (n_roads == 0U) {
        fprintf(stderr, "sensitivity: give at least one ROAD.csv\n");
        usage(stderr);
        return 2;
    }
    sens_setup_t setup;
    sens_setup_default(&setup);
    setup.n_vehicles = (uint32_t)n;
    setup.set_speed_mm_s = (int32_t)lround(set_kmh / 3.6 * 1000.0);

    static road_run_t runs[MAX_ROADS];
    char err[512];
    for (size_t r = 0U; r < n_roads; r++) {
        road_run_t *rr = &runs[r];
        rr->path = road_paths[r];
        if (road_name(rr->path, rr->name) != 0) {
            fprintf(stderr, "sensitivity: %s: cannot name a road after this file name\n", rr->path);
            return 2;
        }
        for (size_t q = 0U; q < r; q++) {
            if (strcmp(runs[q].name, rr->name) == 0) {
                fprintf(stderr, "sensitivity: %s and %s would both write %s/%s.csv\n",
                        runs[q].path, rr->path, out_dir, rr->name);
                return 2;
            }
        }
    }
    if (make_dirs(out_dir) != 0) {
        fprintf(stderr, "sensitivity: cannot create %s: %s\n", out_dir, strerror(errno));
        return 2;
    }
    printf("Sensitivity of the platoon object model (double precision, thesis chapter 6).\n"
           "fuel [%%], time [%%]: change against the nominal case; ±0 means bit for bit the\n"
           "nominal figure. mean: mean of the speed after each 10 m step. at lim: share of the\n"
           "travel time with the wheel force at its upper limit (Pmax / v).\n");
    int status = 0;
    for (size_t r = 0U; r < n_roads; r++) {
        road_run_t *rr = &runs[r];
        road_profile_t road;
        if (road_profile_load(rr->path, &road, err, sizeof err) != 0) {
            fprintf(stderr, "sensitivity: %s\n", err);
            return 2;
        }
        rr->length_m = (double)road.n_samples * road.spacing_m;
        if (sens_run(&setup, &road, SENS_NOMINAL, 0, &rr->nominal, err, sizeof err) != 0) {
            fprintf(stderr, "sensitivity: %s: nominal case: %s\n", rr->path, err);
            road_profile_free(&road);
            return 2;
        }
        status |= rr->nominal.stalled;
        for (size_t p = 0U; p < N_PARAMS; p++) {
            rr->n_steps[p] = sens_steps(params[p], &rr->steps[p]);
            for (size_t k = 0U; k < rr->n_steps[p]; k++) {
                if (sens_run(&setup, &road, params[p], rr->steps[p][k], &rr->result[p][k], err,
                             sizeof err) != 0) {
                    fprintf(stderr, "sensitivity: %s: %s\n", rr->path, err);
                    road_profile_free(&road);
                    return 2;
                }
                status |= rr->result[p][k].stalled;
            }
        }
        road_profile_free(&road);
        print_road_table(rr, &setup);

        char csv[1024];
        char gp[1024];
        char png[1024];
        if ((snprintf(csv, sizeof csv, "%s/%s.csv", out_dir, rr->name) >= (int)sizeof csv) ||
            (snprintf(gp, sizeof gp, "%s/%s.gp", out_dir, rr->name) >= (int)sizeof gp) ||
            (snprintf(png, sizeof png, "%s/%s.png", out_dir, rr->name) >= (int)sizeof png)) {
            fprintf(stderr, "sensitivity: output path too long under %s\n", out_dir);
            return 2;
        }
        if (write_csv(csv, rr, &setup) != 0) {
            return 2;
        }
        printf("csv: %s\n", csv);
        if (plot) {
            if (write_gp(gp, csv, png, rr, &setup) != 0) {
                return 2;
            }
            if (run_gnuplot(gnuplot, gp) != 0) {
                status = 1;
            } else {
                printf("png: %s (gnuplot script %s)\n", png, gp);
            }
        }
    }
    print_thesis_tables(runs, n_roads);
    if (status != 0) {
        fprintf(stderr, "sensitivity: a case stalled or a plot failed (see above)\n");
    }
    return status;
}
