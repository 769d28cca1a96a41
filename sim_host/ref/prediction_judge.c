/* prediction_judge.c - the prediction against the fuel used (contract in prediction_judge.h). */
#include "ref/prediction_judge.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/pfe_can.h"
#include "firmware/pfe_codec.h"
#include "ref/bus_ref.h"
#include "hal/replay/hal_replay_ecu.h"

#define TICK_S 0.01                     /* the module's tick (pfe_ecu.h) */
#define SPEED_GAP_MAX_US 1000000U       /* longer without CCVS1: no distance counted (as run_report) */
#define CANDIDATE_WINDOW_S 2.0          /* starts this long before a frame are candidates */
#define MIN_LATENCY_S 0.04              /* a prediction's three runs need a set-up call each: 4 ticks */
#define PREDICTION_STEP_L 0.01          /* PFE_FuelPrediction's resolution */
#define NONE ((double)NAN)
#define ENDLESS ((double)INFINITY)

typedef struct {
    double t_s, x_m;                    /* distance driven at t */
} pos_t;

typedef struct {
    double t_s, fuel_l;
} fuel_t;

typedef struct {
    double header_s, complete_s, end_m; /* end_m: the horizon's end, in distance driven */
} preview_t;

typedef struct {
    void *p;
    size_t n, room, size;
} vec_t;

static int push(vec_t *v, const void *item)
{
    if (v->n == v->room) {
        const size_t room = (v->room == 0U) ? 256U : (2U * v->room);
        void *p = realloc(v->p, room * v->size);
        if (p == NULL) {
            return -1;
        }
        v->p = p;
        v->room = room;
    }
    memcpy((char *)v->p + (v->n * v->size), item, v->size);
    v->n++;
    return 0;
}

/* Distance driven at t (linear in the samples, held past the last). */
static double x_at(const pos_t *pos, size_t n, double t)
{
    if ((n == 0U) || (t <= pos[0].t_s)) {
        return (n == 0U) ? 0.0 : pos[0].x_m;
    }
    size_t lo = 0U, hi = n - 1U;
    if (t >= pos[hi].t_s) {
        return pos[hi].x_m;
    }
    while (hi - lo > 1U) {
        const size_t mid = (lo + hi) / 2U;
        if (pos[mid].t_s <= t) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    const double f = (t - pos[lo].t_s) / (pos[hi].t_s - pos[lo].t_s);
    return pos[lo].x_m + (f * (pos[hi].x_m - pos[lo].x_m));
}

/* First time the distance driven reaches x, or NaN when the capture ends before. */
static double t_reaching(const pos_t *pos, size_t n, double x)
{
    if ((n == 0U) || (pos[n - 1U].x_m < x)) {
        return NONE;
    }
    size_t lo = 0U, hi = n - 1U;
    if (pos[0].x_m >= x) {
        return pos[0].t_s;
    }
    while (hi - lo > 1U) {
        const size_t mid = (lo + hi) / 2U;
        if (pos[mid].x_m < x) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    const double dx = pos[hi].x_m - pos[lo].x_m;
    const double f = (dx > 0.0) ? ((x - pos[lo].x_m) / dx) : 1.0;
    return pos[lo].t_s + (f * (pos[hi].t_s - pos[lo].t_s));
}

static double fuel_at(const fuel_t *fu, size_t n, double t)
{
    if (n == 0U) {
        return NONE;
    }
    if ((t < fu[0].t_s) || (t > fu[n - 1U].t_s)) {
        return NONE;
    }
    size_t lo = 0U, hi = n - 1U;
    while (hi - lo > 1U) {
        const size_t mid = (lo + hi) / 2U;
        if (fu[mid].t_s <= t) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    const double span = fu[hi].t_s - fu[lo].t_s;
    const double f = (span > 0.0) ? ((t - fu[lo].t_s) / span) : 0.0;
    return fu[lo].fuel_l + (f * (fu[hi].fuel_l - fu[lo].fuel_l));
}

static int add_row(pj_result_t *r, const pj_row_t *row)
{
    if (r->n_rows == r->room) {
        const size_t room = (r->room == 0U) ? 64U : (2U * r->room);
        pj_row_t *p = realloc(r->rows, room * sizeof *p);
        if (p == NULL) {
            return -1;
        }
        r->rows = p;
        r->room = room;
    }
    r->rows[r->n_rows++] = *row;
    return 0;
}

/* The stretch of one prediction: the candidate start that fits PredictedTime best. */
static void place(const preview_t *pv, size_t n_pv, const pos_t *pos, size_t n_pos, pj_row_t *row)
{
    const double last_s = (n_pos > 0U) ? pos[n_pos - 1U].t_s : 0.0;
    double best = ENDLESS;
    row->complete = false;
    row->start_s = NONE;
    row->end_s = NONE;
    bool any = false;
    for (size_t p = (n_pv > 2U) ? (n_pv - 2U) : 0U; p < n_pv; p++) {
        if (!(pv[p].complete_s < row->frame_s)) {
            continue;
        }
        const double until = (p + 1U < n_pv) ? pv[p + 1U].complete_s : ENDLESS;
        const double first = pv[p].complete_s + TICK_S;
        for (double k = fmax(0.0, floor((row->frame_s - CANDIDATE_WINDOW_S - first))); ; k += 1.0) {
            const double s = first + k;
            if ((s > row->frame_s - MIN_LATENCY_S) || (s >= until)) {
                break;
            }
            if (s < row->frame_s - CANDIDATE_WINDOW_S) {
                continue;
            }
            const double end = t_reaching(pos, n_pos, pv[p].end_m);
            /* a horizon the capture does not finish fits when it would take at least as long
             * as the capture has left */
            const double fit = isnan(end) ? fmax(0.0, (last_s - s) - row->predicted_time_s)
                                          : fabs((end - s) - row->predicted_time_s);
            if (!any || (fit < best)) {
                any = true;
                best = fit;
                row->start_s = s;
                row->end_s = end;
                row->horizon_m = pv[p].end_m - x_at(pos, n_pos, s);
                row->complete = !isnan(end);
            }
        }
    }
}

int prediction_judge_run(const capture_t *cap, uint8_t module_sa, unsigned n_vehicles, unsigned position,
                         uint32_t gap_mm, pj_result_t *out)
{
    memset(out, 0, sizeof *out);
    vec_t pos = {NULL, 0U, 0U, sizeof(pos_t)};
    vec_t fuel = {NULL, 0U, 0U, sizeof(fuel_t)};
    vec_t pvs = {NULL, 0U, 0U, sizeof(preview_t)};
    static pfe_preview_t buf;
    pfe_preview_init(&buf);
    static bus_ref_t ref;
    if (bus_ref_init(&ref, n_vehicles, position, gap_mm) != 0) {
        out->why_not = "bad platoon for the reference";
        return 0;
    }
    bool have_t0 = false, have_speed = false;
    uint64_t t0 = 0U, last_speed_us = 0U;
    double speed_m_s = 0.0, x_m = 0.0, header_s = NONE, header_x = 0.0;
    pfe_msg_fuel_prediction_t last = {{0U, PFE_SIG_NOT_AVAILABLE}, {0U, PFE_SIG_NOT_AVAILABLE},
                                      {0U, PFE_SIG_NOT_AVAILABLE}, {0U, PFE_SIG_NOT_AVAILABLE}};
    vec_t rows = {NULL, 0U, 0U, sizeof(pj_row_t)};
    int rc = 0;
    for (size_t k = 0U; (k < cap->n) && (rc == 0); k++) {
        const capture_rec_t *rec = &cap->recs[k];
        const bool from_module = pfe_j1939_source(rec->f.id) == module_sa;
        if (!from_module && !have_t0) {
            have_t0 = true;
            t0 = rec->t_us;
        }
        if (!have_t0) {
            continue;
        }
        const double t_s = (rec->t_us >= t0) ? ((double)(rec->t_us - t0) / 1e6) : 0.0;
        const uint32_t pgn = pfe_j1939_pgn(rec->f.id);
        if (!from_module) {
            /* the reference's platoon fuel used at each of its ticks up to
             * this input; a silence crossed in one jump, as run_report and
             * pfe_ecu_replay cross it (memory by frames, not by time span) */
            if (ref.started && (rec->t_us > (ref.next_tick_us + (uint64_t)HAL_REPLAY_ECU_TAIL_US +
                                             (uint64_t)HAL_REPLAY_ECU_GAP_US))) {
                (void)bus_ref_skip_to(&ref, rec->t_us - (uint64_t)HAL_REPLAY_ECU_TAIL_US);
            }
            while ((rc == 0) && bus_ref_due(&ref, rec->t_us)) {
                const uint64_t tt = bus_ref_tick(&ref);
                const fuel_t f = {(tt >= t0) ? ((double)(tt - t0) / 1e6) : 0.0, bus_ref_platoon_used(&ref)};
                rc = push(&fuel, &f);
            }
            bus_ref_input(&ref, &rec->f, rec->t_us);
        }
        if (!from_module && (pgn == PFE_PGN_CCVS1)) {
            pfe_msg_ccvs1_t m;
            const bool ok = (pfe_codec_decode_ccvs1(&rec->f, &m) == 0) && (m.speed_mm_s.state == PFE_SIG_VALID);
            if (have_speed && ((rec->t_us - last_speed_us) <= SPEED_GAP_MAX_US)) {
                x_m += speed_m_s * ((double)(rec->t_us - last_speed_us) / 1e6);
            }
            have_speed = ok;
            speed_m_s = ok ? (m.speed_mm_s.value / 1000.0) : 0.0;
            last_speed_us = rec->t_us;
            const pos_t p = {t_s, x_m};
            rc = push(&pos, &p);
        } else if (!from_module && (pgn == PFE_PGN_GRADE_PREVIEW)) {
            const int r = pfe_preview_push(&buf, &rec->f);
            const double here = x_m + (have_speed ? (speed_m_s * ((double)(rec->t_us - last_speed_us) / 1e6)) : 0.0);
            if ((r >= 0) && (buf.phase == PFE_PREVIEW_RECEIVING) && (buf.next_index == 0U)) {
                header_s = t_s;
                header_x = here;
            } else if ((r == PFE_PREVIEW_COMPLETE) && !isnan(header_s)) {
                const preview_t v = {header_s, t_s, header_x + ((double)buf.sample_count * buf.spacing_m)};
                rc = push(&pvs, &v);
            } else {
                /* a data frame of a preview in progress, or one the module refuses too */
            }
        } else if (from_module && (pgn == PFE_PGN_FUEL_PREDICTION)) {
            pfe_msg_fuel_prediction_t m;
            if (pfe_codec_decode_fuel_prediction(&rec->f, &m) != 0) {
                continue;
            }
            const bool valid = (m.fuel_ul.state == PFE_SIG_VALID) && (m.fuel_lower_ul.state == PFE_SIG_VALID) &&
                               (m.fuel_upper_ul.state == PFE_SIG_VALID) && (m.time_ms.state == PFE_SIG_VALID);
            const bool same = (m.fuel_ul.value == last.fuel_ul.value) &&
                              (m.fuel_lower_ul.value == last.fuel_lower_ul.value) &&
                              (m.fuel_upper_ul.value == last.fuel_upper_ul.value) &&
                              (m.time_ms.value == last.time_ms.value) &&
                              (last.fuel_ul.state == PFE_SIG_VALID);
            last = m;
            if (!valid || same) {
                continue;
            }
            pj_row_t row;
            memset(&row, 0, sizeof row);
            row.frame_s = t_s;
            row.predicted_l = m.fuel_ul.value / 1e6;
            row.lower_l = m.fuel_lower_ul.value / 1e6;
            row.upper_l = m.fuel_upper_ul.value / 1e6;
            row.predicted_time_s = m.time_ms.value / 1000.0;
            rc = push(&rows, &row);
        } else {
            /* not used here */
        }
    }
    if (rc == 0) {
        const pos_t *pp = pos.p;
        const fuel_t *ff = fuel.p;
        const preview_t *vv = pvs.p;
        pj_row_t *rr = rows.p;
        out->previews = pvs.n;
        double sum = 0.0, sum_abs = 0.0;
        for (size_t k = 0U; (k < rows.n) && (rc == 0); k++) {
            pj_row_t row = rr[k];
            /* only the previews completed before the frame */
            size_t n_pv = 0U;
            while ((n_pv < pvs.n) && (vv[n_pv].complete_s < row.frame_s)) {
                n_pv++;
            }
            place(vv, n_pv, pp, pos.n, &row);
            row.realized_l = NONE;
            row.driven_time_s = NONE;
            if (isnan(row.start_s)) {
                out->unmatched++;
            } else if (row.complete) {
                const double a = fuel_at(ff, fuel.n, row.start_s);
                const double b = fuel_at(ff, fuel.n, row.end_s);
                if (isnan(a) || isnan(b)) {
                    row.complete = false; /* no reference across the stretch */
                    out->incomplete++;
                } else {
                    row.realized_l = b - a;
                    row.driven_time_s = row.end_s - row.start_s;
                    const double slack = PREDICTION_STEP_L / 2.0;
                    row.within = (row.realized_l >= row.lower_l - slack) && (row.realized_l <= row.upper_l + slack);
                    out->complete++;
                    out->outside += row.within ? 0U : 1U;
                    if (row.realized_l > 0.0) {
                        const double e = 100.0 * (row.predicted_l - row.realized_l) / row.realized_l;
                        sum += e;
                        sum_abs += fabs(e);
                        if (fabs(e) > out->max_abs_err_pct) {
                            out->max_abs_err_pct = fabs(e);
                            out->max_abs_err_start_s = row.start_s;
                        }
                    }
                    out->max_time_err_s = fmax(out->max_time_err_s, fabs(row.predicted_time_s - row.driven_time_s));
                }
            } else {
                out->incomplete++;
            }
            rc = add_row(out, &row);
        }
        if (out->complete > 0U) {
            out->mean_err_pct = sum / (double)out->complete;
            out->mean_abs_err_pct = sum_abs / (double)out->complete;
        }
        if (rows.n == 0U) {
            out->why_not = (pvs.n == 0U) ? "no complete PFE_GradePreview in the capture"
                                         : "no PFE_FuelPrediction value from the module";
        } else if (out->complete == 0U) {
            out->why_not = "no prediction's horizon ends within the capture";
        } else {
            out->why_not = NULL;
        }
    }
    free(pos.p);
    free(fuel.p);
    free(pvs.p);
    free(rows.p);
    return (rc == 0) ? 0 : -1;
}

bool prediction_judge_value(const pj_result_t *r, int k, double *v, const char **why)
{
    *why = r->why_not;
    if (k == PJ_Q_PREDICTIONS) {
        *v = (double)r->n_rows;
        return true;
    }
    if (k == PJ_Q_HORIZONS) {
        *v = (double)r->complete;
        return true;
    }
    if (k == PJ_Q_INCOMPLETE) {
        *v = (double)r->incomplete;
        return true;
    }
    if (r->complete == 0U) {
        return false;
    }
    switch (k) {
    case PJ_Q_OUTSIDE:
        *v = (double)r->outside;
        return true;
    case PJ_Q_MEAN_ERR:
        *v = r->mean_err_pct;
        return true;
    case PJ_Q_MEAN_ABS_ERR:
        *v = r->mean_abs_err_pct;
        return true;
    case PJ_Q_MAX_ABS_ERR:
        *v = r->max_abs_err_pct;
        return true;
    case PJ_Q_MAX_TIME_ERR:
        *v = r->max_time_err_s;
        return true;
    default:
        *why = "unknown quantity";
        return false;
    }
}

void prediction_judge_print(const pj_result_t *r)
{
    printf("\n  prediction (PFE_FuelPrediction) against the platoon fuel used over its horizon "
           "(the reference's):\n");
    printf("    %zu predictions over %zu previews: %zu horizons complete, %zu end after the capture",
           r->n_rows, r->previews, r->complete, r->incomplete);
    if (r->unmatched > 0U) {
        printf(", %zu without a start", r->unmatched);
    }
    printf("\n");
    if (r->complete == 0U) {
        printf("    not judged: %s\n", (r->why_not != NULL) ? r->why_not : "no data");
        return;
    }
    const pj_row_t *first = NULL;
    for (size_t k = 0U; (k < r->n_rows) && (first == NULL); k++) {
        first = r->rows[k].complete ? &r->rows[k] : NULL;
    }
    printf("    realized fuel within the bounds on %zu of %zu; error (predicted - realized) mean "
           "%+.2f %%, mean magnitude %.2f %%, largest %.2f %% (start %.1f s); time error up to %.1f s\n",
           r->complete - r->outside, r->complete, r->mean_err_pct, r->mean_abs_err_pct,
           r->max_abs_err_pct, r->max_abs_err_start_s, r->max_time_err_s);
    if (first != NULL) {
        printf("    first: from %.1f s, %.0f m: predicted %.2f L [%.2f, %.2f], realized %.3f L in %.1f s "
               "(predicted %.1f s)\n",
               first->start_s, first->horizon_m, first->predicted_l, first->lower_l, first->upper_l,
               first->realized_l, first->driven_time_s, first->predicted_time_s);
    }
}

static void csv_num(FILE *f, double v, int decimals, const char *sep)
{
    if (isnan(v)) {
        fprintf(f, "NA%s", sep);
    } else {
        fprintf(f, "%.*f%s", decimals, v, sep);
    }
}

int prediction_judge_write_csv(const pj_result_t *r, const char *path)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        fprintf(stderr, "run_report: cannot write %s: %s\n", path, strerror(errno));
        return -1;
    }
    fprintf(f, "frame_s,start_s,end_s,predicted_l,lower_l,upper_l,realized_l,horizon_m,"
               "predicted_time_s,driven_time_s,within\n");
    for (size_t k = 0U; k < r->n_rows; k++) {
        const pj_row_t *w = &r->rows[k];
        csv_num(f, w->frame_s, 2, ",");
        csv_num(f, w->start_s, 2, ",");
        csv_num(f, w->end_s, 2, ",");
        csv_num(f, w->predicted_l, 2, ",");
        csv_num(f, w->lower_l, 2, ",");
        csv_num(f, w->upper_l, 2, ",");
        csv_num(f, w->realized_l, 4, ",");
        csv_num(f, w->complete ? w->horizon_m : NONE, 1, ",");
        csv_num(f, w->predicted_time_s, 1, ",");
        csv_num(f, w->driven_time_s, 2, ",");
        fprintf(f, "%s\n", w->complete ? (w->within ? "1" : "0") : "NA");
    }
    const bool bad = ferror(f) != 0;
    if ((fclose(f) != 0) || bad) {
        fprintf(stderr, "run_report: write error on %s\n", path);
        return -1;
    }
    return 0;
}

void prediction_judge_plot(FILE *gp, const char *csv_path)
{
    fprintf(gp, "pcsv = '");
    for (const char *s = csv_path; *s != '\0'; s++) {
        if (*s == '\'') {
            fputc('\'', gp);
        }
        fputc(*s, gp);
    }
    fprintf(gp, "'\n"
                "set ylabel 'fuel to horizon end (L)'\n"
                "set xlabel 'time the prediction starts from (s)'\n"
                "plot pcsv skip 1 using 2:5:6 with filledcurves lc rgb '#c6dbef' title 'predicted bounds (PFE_FuelPrediction)', \\\n"
                "     pcsv skip 1 using 2:4 with lines lw 2.0 lc rgb '#1f77b4' title 'predicted platoon fuel', \\\n"
                "     pcsv skip 1 using 2:7 with points pt 7 ps 0.6 lc rgb '#d62728' title 'realized over the same stretch (reference)'\n"
                "set xlabel 'time (s)'\n");
}

void prediction_judge_free(pj_result_t *r)
{
    free(r->rows);
    memset(r, 0, sizeof *r);
}
