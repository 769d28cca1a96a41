/* road_import.c - GPX and distance/elevation tables to road grades (contract in road_import.h). */
#include "lib/road_import.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define SAME_PLACE_M 0.001
#define GRADE_LIMIT_PCT 30.0

static int fail(char *err, size_t len, const char *path, size_t line, const char *what)
{
    if ((err != NULL) && (len > 0U)) {
        if (line > 0U) {
            (void)snprintf(err, len, "%s:%zu: %s", path, line, what);
        } else {
            (void)snprintf(err, len, "%s: %s", path, what);
        }
    }
    return -1;
}

void road_import_free(road_track_t *t)
{
    if (t != NULL) {
        free(t->distance_m);
        free(t->elevation_m);
        memset(t, 0, sizeof *t);
    }
}

/* Appends a point at cumulative distance d, dropping one at the previous one's place. */
static int add_point(road_track_t *t, size_t *room, double d, double h)
{
    if ((t->n > 0U) && (fabs(d - t->distance_m[t->n - 1U]) < SAME_PLACE_M)) {
        t->duplicates++;
        return 0;
    }
    if (t->n == ROAD_IMPORT_MAX_POINTS) {
        return -2;
    }
    if (t->n == *room) {
        const size_t want = (*room == 0U) ? 1024U : (2U * *room);
        double *a = realloc(t->distance_m, want * sizeof *a);
        if (a == NULL) {
            return -1;
        }
        t->distance_m = a;
        double *b = realloc(t->elevation_m, want * sizeof *b);
        if (b == NULL) {
            return -1;
        }
        t->elevation_m = b;
        *room = want;
    }
    t->distance_m[t->n] = d;
    t->elevation_m[t->n] = h;
    t->n++;
    return 0;
}

double road_import_distance_m(double lat1_deg, double lon1_deg, double lat2_deg, double lon2_deg)
{
    const double p1 = lat1_deg * PI / 180.0;
    const double p2 = lat2_deg * PI / 180.0;
    const double dp = p2 - p1;
    const double dl = (lon2_deg - lon1_deg) * PI / 180.0;
    const double a = (sin(dp / 2.0) * sin(dp / 2.0)) + (cos(p1) * cos(p2) * sin(dl / 2.0) * sin(dl / 2.0));
    return 2.0 * ROAD_IMPORT_EARTH_RADIUS_M * asin(sqrt(fmin(1.0, a)));
}

/* A decimal number (no hex, inf, nan) filling [s, end); returns 0 or -1. */
static int number(const char *s, const char *end, double *out)
{
    while ((s < end) && ((*s == ' ') || (*s == '\t') || (*s == '\r') || (*s == '\n'))) {
        s++;
    }
    while ((end > s) && ((end[-1] == ' ') || (end[-1] == '\t') || (end[-1] == '\r') || (end[-1] == '\n'))) {
        end--;
    }
    char buf[64];
    const size_t len = (size_t)(end - s);
    if ((len == 0U) || (len >= sizeof buf)) {
        return -1;
    }
    memcpy(buf, s, len);
    buf[len] = '\0';
    for (size_t k = 0U; k < len; k++) {
        if (strchr("0123456789+-.eE", buf[k]) == NULL) {
            return -1;
        }
    }
    char *stop = NULL;
    errno = 0;
    const double v = strtod(buf, &stop);
    if ((errno != 0) || (stop != buf + len) || !isfinite(v)) {
        return -1;
    }
    *out = v;
    return 0;
}

static char *read_all(const char *path, size_t *len, char *err, size_t err_len)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        (void)fail(err, err_len, path, 0U, strerror(errno));
        return NULL;
    }
    size_t room = 65536U, n = 0U;
    char *buf = malloc(room + 1U);
    while (buf != NULL) {
        const size_t got = fread(buf + n, 1U, room - n, f);
        n += got;
        if (n < room) {
            break;
        }
        if (room >= ROAD_IMPORT_MAX_BYTES) {
            free(buf);
            buf = NULL;
            (void)fail(err, err_len, path, 0U, "larger than 256 MiB");
            break;
        }
        char *b = realloc(buf, (2U * room) + 1U);
        if (b == NULL) {
            free(buf);
            buf = NULL;
            (void)fail(err, err_len, path, 0U, "out of memory");
            break;
        }
        buf = b;
        room *= 2U;
    }
    const bool bad = ferror(f) != 0;
    fclose(f);
    if ((buf != NULL) && bad) {
        free(buf);
        (void)fail(err, err_len, path, 0U, "read error");
        return NULL;
    }
    if (buf == NULL) {
        if ((err != NULL) && (err_len > 0U) && (err[0] == '\0')) {
            (void)fail(err, err_len, path, 0U, "out of memory");
        }
        return NULL;
    }
    if (memchr(buf, '\0', n) != NULL) {
        free(buf);
        (void)fail(err, err_len, path, 0U, "NUL byte: not a text file");
        return NULL;
    }
    buf[n] = '\0';
    *len = n;
    return buf;
}

static size_t line_of(const char *start, const char *at)
{
    size_t line = 1U;
    for (const char *p = start; p < at; p++) {
        line += (*p == '\n') ? 1U : 0U;
    }
    return line;
}

/* The value of attribute name="..." (or '...') within [tag, tag_end). */
static int attribute(const char *tag, const char *tag_end, const char *name, const char **v, const char **v_end)
{
    const size_t nl = strlen(name);
    for (const char *p = tag; p + nl + 2 < tag_end; p++) {
        if ((strncmp(p, name, nl) == 0) && ((p == tag) || (p[-1] == ' ') || (p[-1] == '\t') ||
                                             (p[-1] == '\n') || (p[-1] == '\r'))) {
            const char *q = p + nl;
            while ((q < tag_end) && ((*q == ' ') || (*q == '\t'))) {
                q++;
            }
            if ((q >= tag_end) || (*q != '=')) {
                continue;
            }
            q++;
            while ((q < tag_end) && ((*q == ' ') || (*q == '\t'))) {
                q++;
            }
            if ((q >= tag_end) || ((*q != '"') && (*q != '\''))) {
                return -1;
            }
            const char quote = *q;
            const char *e = memchr(q + 1, quote, (size_t)(tag_end - (q + 1)));
            if (e == NULL) {
                return -1;
            }
            *v = q + 1;
            *v_end = e;
            return 0;
        }
    }
    return -1;
}

/* The next <trkpt or <rtept at or after p, or NULL. */
static const char *next_point(const char *p)
{
    const char *a = strstr(p, "<trkpt");
    const char *b = strstr(p, "<rtept");
    if (a == NULL) {
        return b;
    }
    return ((b != NULL) && (b < a)) ? b : a;
}

int road_import_gpx(const char *path, road_track_t *t, char *err, size_t err_len)
{
    memset(t, 0, sizeof *t);
    if (err != NULL && err_len > 0U) {
        err[0] = '\0';
    }
    size_t len = 0U;
    char *text = read_all(path, &len, err, err_len);
    if (text == NULL) {
        return -1;
    }
    size_t room = 0U;
    double lat0 = 0.0, lon0 = 0.0, dist = 0.0;
    size_t points = 0U;
    int rc = 0;
    for (const char *p = next_point(text); (p != NULL) && (rc == 0); p = next_point(p + 1)) {
        const size_t line = line_of(text, p);
        const char *tag_end = strchr(p, '>');
        if (tag_end == NULL) {
            rc = fail(err, err_len, path, line, "a track point's tag does not end");
            break;
        }
        const char *v, *ve;
        double lat, lon, ele;
        if ((attribute(p, tag_end, "lat", &v, &ve) != 0) || (number(v, ve, &lat) != 0) ||
            !(fabs(lat) <= 90.0)) {
            rc = fail(err, err_len, path, line, "a track point without a numeric lat in [-90, 90]");
            break;
        }
        if ((attribute(p, tag_end, "lon", &v, &ve) != 0) || (number(v, ve, &lon) != 0) ||
            !(fabs(lon) <= 180.0)) {
            rc = fail(err, err_len, path, line, "a track point without a numeric lon in [-180, 180]");
            break;
        }
        const char *close = (tag_end[-1] == '/') ? tag_end : strstr(tag_end, (p[1] == 't') ? "</trkpt" : "</rtept");
        const char *e = strstr(tag_end, "<ele>");
        if ((close == NULL) || (e == NULL) || (e > close)) {
            rc = fail(err, err_len, path, line, "a track point without <ele>: the track has no elevation");
            break;
        }
        const char *ee = strstr(e, "</ele>");
        if ((ee == NULL) || (ee > close) || (number(e + 5, ee, &ele) != 0) || !(fabs(ele) < 20000.0)) {
            rc = fail(err, err_len, path, line_of(text, e), "<ele> is not a number of metres");
            break;
        }
        if (points > 0U) {
            dist += road_import_distance_m(lat0, lon0, lat, lon);
        }
        lat0 = lat;
        lon0 = lon;
        points++;
        const int a = add_point(t, &room, dist, ele);
        if (a != 0) {
            rc = fail(err, err_len, path, line, (a == -2) ? "more than 2000000 points" : "out of memory");
        }
    }
    free(text);
    if ((rc == 0) && (points == 0U)) {
        rc = fail(err, err_len, path, 0U, "no <trkpt> or <rtept>: not a GPX track");
    } else if ((rc == 0) && (t->n < 2U)) {
        char why[96];
        (void)snprintf(why, sizeof why, "a track of %zu point%s at one place: at least two needed",
                       points, (points == 1U) ? "" : "s");
        rc = fail(err, err_len, path, 0U, why);
    }
    if (rc != 0) {
        road_import_free(t);
    }
    return rc;
}

int road_import_csv(const char *path, road_track_t *t, char *err, size_t err_len)
{
    memset(t, 0, sizeof *t);
    size_t len = 0U;
    char *text = read_all(path, &len, err, err_len);
    if (text == NULL) {
        return -1;
    }
    size_t room = 0U, line = 0U, rows = 0U;
    bool first_content = true;
    int rc = 0;
    double last = -INFINITY;
    char *p = text;
    while ((rc == 0) && (*p != '\0')) {
        line++;
        char *nl = strchr(p, '\n');
        char *end = (nl != NULL) ? nl : (p + strlen(p));
        char *next = (nl != NULL) ? (nl + 1) : end;
        char *s = p;
        while ((s < end) && ((*s == ' ') || (*s == '\t') || (*s == '\r'))) {
            s++;
        }
        if ((s == end) || (*s == '#')) {
            p = next;
            continue;
        }
        const bool header = first_content && (strchr("0123456789+-.", *s) == NULL);
        first_content = false;
        if (header) {
            p = next;
            continue;
        }
        char *comma = memchr(s, ',', (size_t)(end - s));
        double d, h;
        if (comma == NULL) {
            rc = fail(err, err_len, path, line, "expected 'distance_m,elevation_m'");
        } else if (memchr(comma + 1, ',', (size_t)(end - (comma + 1))) != NULL) {
            rc = fail(err, err_len, path, line, "more than two fields");
        } else if (number(s, comma, &d) != 0) {
            rc = fail(err, err_len, path, line, "distance is not a number");
        } else if (number(comma + 1, end, &h) != 0) {
            rc = fail(err, err_len, path, line, "elevation is not a number");
        } else if (!(fabs(h) < 20000.0) || !(d >= 0.0)) {
            rc = fail(err, err_len, path, line, "distance below 0 or elevation beyond 20 km");
        } else if (d < last - SAME_PLACE_M) {
            rc = fail(err, err_len, path, line, "distance decreases");
        } else {
            last = d;
            rows++;
            const int a = add_point(t, &room, d, h);
            if (a != 0) {
                rc = fail(err, err_len, path, line, (a == -2) ? "more than 2000000 points" : "out of memory");
            }
        }
        p = next;
    }
    free(text);
    if ((rc == 0) && (t->n < 2U)) {
        char why[96];
        (void)snprintf(why, sizeof why, "%zu row%s at %s place: at least two places needed", rows,
                       (rows == 1U) ? "" : "s", (rows == 1U) ? "one" : "no more than one");
        rc = fail(err, err_len, path, 0U, why);
    }
    if (rc == 0) {
        /* distances from the first point */
        const double d0 = t->distance_m[0];
        for (size_t k = 0U; k < t->n; k++) {
            t->distance_m[k] -= d0;
        }
    } else {
        road_import_free(t);
    }
    return rc;
}

int road_import_load(const char *path, road_track_t *t, char *err, size_t err_len)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        memset(t, 0, sizeof *t);
        return fail(err, err_len, path, 0U, strerror(errno));
    }
    int c;
    do {
        c = fgetc(f);
    } while ((c == ' ') || (c == '\t') || (c == '\r') || (c == '\n') || (c == 0xEF) || (c == 0xBB) ||
             (c == 0xBF));
    fclose(f);
    return (c == '<') ? road_import_gpx(path, t, err, err_len) : road_import_csv(path, t, err, err_len);
}

/* Least-squares slope of the points with distance in [lo, hi]; false when fewer than two distinct. */
static bool slope_in(const road_track_t *t, size_t *from, double lo, double hi, double *slope)
{
    while ((*from < t->n) && (t->distance_m[*from] < lo)) {
        (*from)++;
    }
    double n = 0.0, sx = 0.0, sy = 0.0;
    size_t k = *from;
    for (; (k < t->n) && (t->distance_m[k] <= hi); k++) {
        n += 1.0;
        sx += t->distance_m[k];
        sy += t->elevation_m[k];
    }
    if (n < 2.0) {
        return false;
    }
    const double mx = sx / n, my = sy / n;
    double sxx = 0.0, sxy = 0.0;
    for (size_t j = *from; j < k; j++) {
        const double dx = t->distance_m[j] - mx;
        sxx += dx * dx;
        sxy += dx * (t->elevation_m[j] - my);
    }
    if (!(sxx > 0.0)) {
        return false;
    }
    *slope = sxy / sxx;
    return true;
}

int road_import_grade(const road_track_t *t, double spacing_m, double smooth_m, double **grade_pct,
                      size_t *n_out, char *err, size_t err_len)
{
    *grade_pct = NULL;
    *n_out = 0U;
    if ((t == NULL) || (t->n < 2U) || !(spacing_m > 0.0) || !(smooth_m >= spacing_m) || !isfinite(smooth_m)) {
        return fail(err, err_len, "road_import", 0U, "bad arguments (a track of 2 points or more, "
                                                     "spacing > 0, smoothing >= spacing)");
    }
    const double length = t->distance_m[t->n - 1U];
    const double samples = floor((length / spacing_m) + 1e-9);
    if (samples < 1.0) {
        char why[128];
        (void)snprintf(why, sizeof why, "the track is %.1f m long, shorter than one %.1f m sample", length,
                       spacing_m);
        return fail(err, err_len, "road_import", 0U, why);
    }
    if (samples > 1000000.0) {
        return fail(err, err_len, "road_import", 0U, "more than 1000000 samples");
    }
    const size_t n = (size_t)samples;
    double *g = malloc(n * sizeof *g);
    if (g == NULL) {
        return fail(err, err_len, "road_import", 0U, "out of memory");
    }
    size_t from = 0U;
    for (size_t k = 0U; k < n; k++) {
        const double mid = ((double)k + 0.5) * spacing_m;
        double half = smooth_m / 2.0;
        double slope = 0.0;
        size_t start = from; /* windows move forward: the search starts where the last one did */
        if (slope_in(t, &start, mid - half, mid + half, &slope)) {
            from = start;
        } else {
            do {             /* sparse points: widen the window until it holds two */
                start = 0U;
                half *= 2.0;
            } while (!slope_in(t, &start, mid - half, mid + half, &slope));
        }
        g[k] = 100.0 * slope;
        if (!(fabs(g[k]) <= GRADE_LIMIT_PCT)) {
            char why[160];
            (void)snprintf(why, sizeof why,
                           "grade %.1f %% at %.0f m is beyond +-30 %%: not a road's elevations (or too "
                           "little smoothing)", g[k], mid);
            free(g);
            return fail(err, err_len, "road_import", 0U, why);
        }
    }
    *grade_pct = g;
    *n_out = n;
    return 0;
}
