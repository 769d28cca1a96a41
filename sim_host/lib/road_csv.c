/*
 * Road profile loader: CSV text to grade samples, and the conversion to the
 * firmware's fixed-point grade (ppm) and spacing (mm). Format and error
 * contract are in road_csv.h.
 */
#include "lib/road_csv.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(__GNUC__)
#define ROAD_CSV_PRINTF(fmt_idx, arg_idx) __attribute__((format(printf, fmt_idx, arg_idx)))
#else
#define ROAD_CSV_PRINTF(fmt_idx, arg_idx)
#endif

/* Longest excerpt of a bad field or line quoted in a message. */
#define QUOTE_MAX 40

/* Slack on the 1 mm tolerance for the rounding of decimal distances, so that
 * a distance exactly 1 mm off (24.001 for 24) is accepted. */
#define DISTANCE_SLACK_M 1e-9

/* Initial capacity of the sample array; it doubles up to ROAD_CSV_MAX_ROWS. */
#define INITIAL_CAPACITY 1024u

static const char HEADER_DISTANCE[] = "distance_m";
static const char HEADER_GRADE[] = "grade_percent";

ROAD_CSV_PRINTF(3, 4)
static void set_err(char *err, size_t err_len, const char *fmt, ...)
{
    if (err == NULL || err_len == 0u) {
        return;
    }
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(err, err_len, fmt, ap);
    va_end(ap);
}

/* Line reader state: one line at a time into a fixed buffer. */
typedef struct {
    FILE *f;
    const char *path;
    size_t line_no;                       /* 1-based number of the line in buf */
    char buf[ROAD_CSV_MAX_LINE + 2u];     /* line + possible CR, then NUL */
    size_t len;
    char *err;
    size_t err_len;
} reader_t;

/*
 * Reads the next line into r->buf without its LF or CRLF (and without a
 * UTF-8 byte-order mark on line 1). Returns 1 when a line was read, 0 at the
 * end of the file, -1 on a NUL byte, an over-long line or a read error.
 */
static int read_line(reader_t *r)
{
    size_t n = 0u;
    int got_any = 0;
    int c;

    r->line_no++;
    for (;;) {
        c = getc(r->f);
        if (c == EOF || c == '\n') {
            got_any |= (c == '\n');
            break;
        }
        got_any = 1;
        if (c == '\0') {
            set_err(r->err, r->err_len, "%s:%zu: binary data (NUL byte)", r->path, r->line_no);
            return -1;
        }
        if (n == ROAD_CSV_MAX_LINE + 1u) {
            /* Even if the next byte were the CR of a CRLF, the line is too long. */
            set_err(r->err, r->err_len, "%s:%zu: line longer than %u characters",
                    r->path, r->line_no, ROAD_CSV_MAX_LINE);
            return -1;
        }
        r->buf[n++] = (char)c;
        if (r->line_no == 1u && n == 3u && memcmp(r->buf, "\xEF\xBB\xBF", 3u) == 0) {
            n = 0u;   /* byte-order mark, not part of the line */
        }
    }
    if (c == EOF && ferror(r->f)) {
        set_err(r->err, r->err_len, "%s: read error: %s", r->path, strerror(errno));
        return -1;
    }
    if (!got_any) {
        return 0;
    }
    if (n > 0u && r->buf[n - 1u] == '\r') {
        n--;
    }
    if (n > ROAD_CSV_MAX_LINE) {
        set_err(r->err, r->err_len, "%s:%zu: line longer than %u characters",
                r->path, r->line_no, ROAD_CSV_MAX_LINE);
        return -1;
    }
    r->buf[n] = '\0';
    r->len = n;
    return 1;
}

static int is_blank_char(char c)
{
    return c == ' ' || c == '\t';
}

/* Strips spaces and tabs from both ends of s, in place. */
static char *trim(char *s)
{
    while (is_blank_char(*s)) {
        s++;
    }
    size_t n = strlen(s);
    while (n > 0u && is_blank_char(s[n - 1u])) {
        n--;
    }
    s[n] = '\0';
    return s;
}

static int is_letter(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}

/* Case-insensitive prefix test for the spellings strtod would take as nan/inf. */
static int starts_with_nocase(const char *s, const char *prefix)
{
    for (; *prefix != '\0'; s++, prefix++) {
        char a = *s;
        if (a >= 'A' && a <= 'Z') {
            a = (char)(a - 'A' + 'a');
        }
        if (a != *prefix) {
            return 0;
        }
    }
    return 1;
}

typedef enum {
    NUM_OK = 0,
    NUM_EMPTY,
    NUM_BAD,
    NUM_RANGE
} num_status_t;

/*
 * Parses a trimmed field as a finite decimal number. Only digits, signs, a
 * point and an exponent letter may appear, which keeps out hex floats, nan
 * and inf that strtod would otherwise accept; strtod must then consume the
 * whole field.
 */
static num_status_t parse_number(const char *s, double *out)
{
    if (*s == '\0') {
        return NUM_EMPTY;
    }
    int digits = 0;
    for (const char *p = s; *p != '\0'; p++) {
        char c = *p;
        if (c >= '0' && c <= '9') {
            digits = 1;
        } else if (c != '+' && c != '-' && c != '.' && c != 'e' && c != 'E') {
            return NUM_BAD;
        }
    }
    if (!digits) {
        return NUM_BAD;
    }
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0') {
        return NUM_BAD;
    }
    if (!isfinite(v)) {
        return NUM_RANGE;   /* overflow; underflow to a tiny value is kept */
    }
    *out = v;
    return NUM_OK;
}

static const char *const COLUMN_NAMES[2] = {HEADER_DISTANCE, HEADER_GRADE};

/* Reports a field that failed parse_number(); column is 1 or 2. */
static void report_number(const reader_t *r, num_status_t st, unsigned column, const char *field)
{
    const char *name = COLUMN_NAMES[column - 1u];
    switch (st) {
    case NUM_EMPTY:
        set_err(r->err, r->err_len, "%s:%zu: missing value in column %u (%s)",
                r->path, r->line_no, column, name);
        break;
    case NUM_RANGE:
        set_err(r->err, r->err_len, "%s:%zu: bad number '%.*s' in column %u (%s): out of range",
                r->path, r->line_no, QUOTE_MAX, field, column, name);
        break;
    case NUM_BAD:
    case NUM_OK:
        set_err(r->err, r->err_len, "%s:%zu: bad number '%.*s' in column %u (%s)",
                r->path, r->line_no, QUOTE_MAX, field, column, name);
        break;
    }
}

/* Sample array under construction. */
typedef struct {
    double *v;
    size_t n;
    size_t cap;
} samples_t;

static int samples_push(samples_t *s, double value)
{
    if (s->n == s->cap) {
        size_t cap = (s->cap == 0u) ? INITIAL_CAPACITY : 2u * s->cap;
        if (cap > ROAD_CSV_MAX_ROWS) {
            cap = ROAD_CSV_MAX_ROWS;
        }
        double *v = realloc(s->v, cap * sizeof *v);
        if (v == NULL) {
            return -1;
        }
        s->v = v;
        s->cap = cap;
    }
    s->v[s->n++] = value;
    return 0;
}

/* Parser state carried from row to row. */
typedef struct {
    int seen_content;     /* a header or data row has been read */
    double first_m;       /* distance of row 0 */
    double prev_m;        /* distance of the previous row */
    double spacing_m;     /* row 1 - row 0, once row 1 is read */
} parse_state_t;

/*
 * Handles one content line (not blank, not a comment). Returns 0 when the
 * line was a header or a good data row, -1 with the error set otherwise.
 */
static int parse_content_line(reader_t *r, parse_state_t *ps, samples_t *s)
{
    char *line = r->buf;
    char *comma1 = strchr(line, ',');
    char *comma2 = (comma1 != NULL) ? strchr(comma1 + 1, ',') : NULL;

    if (!ps->seen_content) {
        ps->seen_content = 1;
        if (comma1 != NULL && comma2 == NULL) {
            char tmp[sizeof r->buf];
            memcpy(tmp, line, r->len + 1u);
            tmp[comma1 - line] = '\0';
            const char *f1 = trim(tmp);
            const char *f2 = trim(tmp + (comma1 - line) + 1);
            if (strcmp(f1, HEADER_DISTANCE) == 0 && strcmp(f2, HEADER_GRADE) == 0) {
                return 0;
            }
        }
        const char *first = line;
        while (is_blank_char(*first)) {
            first++;
        }
        if (is_letter(*first) && !starts_with_nocase(first, "nan") &&
            !starts_with_nocase(first, "inf")) {
            set_err(r->err, r->err_len,
                    "%s:%zu: unrecognised header '%.*s' (expected %s,%s)",
                    r->path, r->line_no, QUOTE_MAX, first, HEADER_DISTANCE, HEADER_GRADE);
            return -1;
        }
    }

    if (s->n == ROAD_CSV_MAX_ROWS) {
        set_err(r->err, r->err_len, "%s:%zu: too many rows (limit %u)",
                r->path, r->line_no, ROAD_CSV_MAX_ROWS);
        return -1;
    }

    if (comma1 == NULL || comma2 != NULL) {
        unsigned found = 1u;
        for (const char *p = line; *p != '\0'; p++) {
            found += (*p == ',') ? 1u : 0u;
        }
        set_err(r->err, r->err_len, "%s:%zu: %s: expected 2 columns (%s,%s), found %u",
                r->path, r->line_no, (found < 2u) ? "missing column" : "extra columns",
                HEADER_DISTANCE, HEADER_GRADE, found);
        return -1;
    }

    *comma1 = '\0';
    const char *f_dist = trim(line);
    const char *f_grade = trim(comma1 + 1);
    double dist_m = 0.0;
    double grade = 0.0;
    num_status_t st = parse_number(f_dist, &dist_m);
    if (st != NUM_OK) {
        report_number(r, st, 1u, f_dist);
        return -1;
    }

    const size_t k = s->n;
    if (k == 0u) {
        if (fabs(dist_m) > ROAD_CSV_DISTANCE_TOL_M + DISTANCE_SLACK_M) {
            set_err(r->err, r->err_len, "%s:%zu: first distance is %.10g m, must be 0",
                    r->path, r->line_no, dist_m);
            return -1;
        }
        ps->first_m = dist_m;
    } else {
        if (!(dist_m > ps->prev_m)) {
            set_err(r->err, r->err_len,
                    "%s:%zu: distance %.10g m is not greater than the previous row's %.10g m",
                    r->path, r->line_no, dist_m, ps->prev_m);
            return -1;
        }
        if (k == 1u) {
            ps->spacing_m = dist_m - ps->first_m;
        }
        const double expected_m = (double)k * ps->spacing_m;
        if (fabs(dist_m - expected_m) > ROAD_CSV_DISTANCE_TOL_M + DISTANCE_SLACK_M) {
            set_err(r->err, r->err_len,
                    "%s:%zu: non-uniform distance %.10g m, expected %.10g m "
                    "(spacing %.10g m from the first two rows, tolerance 1 mm)",
                    r->path, r->line_no, dist_m, expected_m, ps->spacing_m);
            return -1;
        }
    }

    st = parse_number(f_grade, &grade);
    if (st != NUM_OK) {
        report_number(r, st, 2u, f_grade);
        return -1;
    }
    if (fabs(grade) > ROAD_CSV_MAX_GRADE_PERCENT) {
        set_err(r->err, r->err_len, "%s:%zu: grade %.10g %% outside [-30, 30] %%",
                r->path, r->line_no, grade);
        return -1;
    }

    if (samples_push(s, grade) != 0) {
        set_err(r->err, r->err_len, "%s:%zu: out of memory", r->path, r->line_no);
        return -1;
    }
    ps->prev_m = dist_m;
    return 0;
}

/* Reads every line of an open, non-empty file into s and *spacing_m. */
static int parse_file(reader_t *r, samples_t *s, double *spacing_m)
{
    parse_state_t ps = {0, 0.0, 0.0, 0.0};
    for (;;) {
        int got = read_line(r);
        if (got < 0) {
            return -1;
        }
        if (got == 0) {
            break;
        }
        const char *p = r->buf;
        while (is_blank_char(*p)) {
            p++;
        }
        if (*p == '\0' || *p == '#') {
            continue;
        }
        if (parse_content_line(r, &ps, s) != 0) {
            return -1;
        }
    }
    if (s->n < 2u) {
        if (s->n == 0u) {
            set_err(r->err, r->err_len, "%s: no data rows (need at least 2)", r->path);
        } else {
            set_err(r->err, r->err_len, "%s: only 1 data row (need at least 2)", r->path);
        }
        return -1;
    }
    *spacing_m = ps.spacing_m;
    return 0;
}

int road_profile_load(const char *path, road_profile_t *road, char *err, size_t err_len)
{
    if (err != NULL && err_len > 0u) {
        err[0] = '\0';
    }
    if (road == NULL) {
        set_err(err, err_len, "%s: no profile to load into", (path != NULL) ? path : "(null)");
        return -1;
    }
    road->n_samples = 0u;
    road->spacing_m = 0.0;
    road->grade_percent = NULL;
    if (path == NULL) {
        set_err(err, err_len, "(null): no file name");
        return -1;
    }

    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        set_err(err, err_len, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }

    int rc = -1;
    double spacing_m = 0.0;
    samples_t s = {NULL, 0u, 0u};
    reader_t rd;
    reader_t *r = &rd;
    r->f = f;
    r->path = path;
    r->line_no = 0u;
    r->len = 0u;
    r->err = err;
    r->err_len = err_len;

    int c = getc(f);
    if (c == EOF) {
        if (ferror(f)) {
            set_err(err, err_len, "%s: read error: %s", path, strerror(errno));
        } else {
            set_err(err, err_len, "%s: empty file", path);
        }
    } else if (ungetc(c, f) == EOF) {
        set_err(err, err_len, "%s: read error", path);
    } else if (parse_file(r, &s, &spacing_m) == 0) {
        rc = 0;
    }

    if (rc == 0) {
        road->n_samples = s.n;
        road->spacing_m = spacing_m;
        road->grade_percent = s.v;
        s.v = NULL;
    }
    free(s.v);
    (void)fclose(f);
    return rc;
}

void road_profile_free(road_profile_t *road)
{
    if (road == NULL) {
        return;
    }
    free(road->grade_percent);
    road->grade_percent = NULL;
    road->n_samples = 0u;
    road->spacing_m = 0.0;
}

int road_profile_to_ppm(const road_profile_t *road, int32_t *grade_ppm_out,
                        uint32_t *spacing_mm_out, char *err, size_t err_len)
{
    if (err != NULL && err_len > 0u) {
        err[0] = '\0';
    }
    if (road == NULL || grade_ppm_out == NULL || spacing_mm_out == NULL ||
        (road->n_samples > 0u && road->grade_percent == NULL)) {
        set_err(err, err_len, "road_profile_to_ppm: missing profile or output");
        return -1;
    }

    const double spacing_mm = round(road->spacing_m * 1000.0);
    if (!isfinite(spacing_mm) || spacing_mm < 1.0 || spacing_mm > 4294967295.0) {
        set_err(err, err_len, "spacing %.10g m does not round to 1 .. 4294967295 mm",
                road->spacing_m);
        return -1;
    }
    *spacing_mm_out = (uint32_t)spacing_mm;

    for (size_t k = 0u; k < road->n_samples; k++) {
        const double ppm = round(road->grade_percent[k] * 10000.0);
        if (!isfinite(ppm) || ppm < -2147483648.0 || ppm > 2147483647.0) {
            set_err(err, err_len, "sample %zu: grade %.10g %% does not fit int32 as ppm",
                    k, road->grade_percent[k]);
            return -1;
        }
        grade_ppm_out[k] = (int32_t)ppm;
    }
    return 0;
}

int road_ppm_load(const char *path, road_ppm_t *road, char *err, size_t err_len)
{
    road->grade_ppm = NULL;
    road->n_samples = 0u;
    road->spacing_mm = 0u;
    road_profile_t prof;
    if (road_profile_load(path, &prof, err, err_len) != 0) {
        return -1;
    }
    int32_t *grade = malloc(sizeof(int32_t) * prof.n_samples);
    char why[256];
    int rc = -1;
    if (grade == NULL) {
        set_err(err, err_len, "%s: out of memory", path);
    } else if (road_profile_to_ppm(&prof, grade, &road->spacing_mm, why, sizeof why) != 0) {
        set_err(err, err_len, "%s: %s", path, why);
    } else {
        road->grade_ppm = grade;
        road->n_samples = (uint32_t)prof.n_samples; /* <= ROAD_CSV_MAX_ROWS */
        grade = NULL;
        rc = 0;
    }
    free(grade);
    road_profile_free(&prof);
    return rc;
}

void road_ppm_free(road_ppm_t *road)
{
    free(road->grade_ppm);
    road->grade_ppm = NULL;
    road->n_samples = 0u;
    road->spacing_mm = 0u;
}
