/*
 * road_import.h - road profiles from what a route planner has: a GPX track
 * with elevations, or a table of distance and elevation; resampled to the
 * road format of road_csv.h (grade in percent at a uniform spacing).
 *
 * Inputs:
 *   GPX 1.1: every <trkpt lat=".." lon=".."> (and <rtept>) in file order,
 *     each with its <ele> in metres; distance along the track is the sum of
 *     great-circle steps between points (haversine on a sphere of the
 *     IUGG mean Earth radius, 6 371 008.8 m: within 0.5 % of the WGS-84
 *     ellipsoid's distances, well below what a track's own errors are).
 *   CSV: "distance_m,elevation_m" rows (an optional header line of text,
 *     '#' comments, blank lines), distances not decreasing.
 * A point at the distance of the point before it (within 1 mm: a GNSS
 * receiver standing still, a repeated row) is dropped and counted; the
 * first one's elevation is kept. At least two points must remain.
 *
 * Grade, and why it is smoothed: elevations from GNSS (metres of noise
 * from point to point) or a DEM (a metre or so, and steps at tile edges)
 * differentiated over 10 to 20 m become grades of +-10 % and more. So the
 * grade of output sample k, covering [k s, (k + 1) s), is the least-squares
 * slope of the input points within smooth_m / 2 of the sample's middle (the
 * window widened until it holds two points at different distances). A
 * straight line in (distance, elevation) comes out exact; white elevation
 * noise of deviation sigma over points p metres apart leaves a grade
 * deviation of about sigma sqrt(12 p) / smooth_m^1.5 (0.40 % for sigma 2.9 m,
 * p 10 m, the default 400 m); a grade change is spread over about smooth_m.
 * The resampled road covers floor(length / s) samples; a grade beyond
 * +-30 % (road_csv.h's limit) is an error: the elevations are not a road's.
 *
 * Errors: a message "FILE:LINE: reason" or "FILE: reason" in err; nothing
 * is written then. Memory: malloc, released with road_import_free().
 */
#ifndef ROAD_IMPORT_H
#define ROAD_IMPORT_H

#include <stddef.h>

#define ROAD_IMPORT_EARTH_RADIUS_M 6371008.8
#define ROAD_IMPORT_DEFAULT_SMOOTH_M 400.0
#define ROAD_IMPORT_MAX_POINTS 2000000U
#define ROAD_IMPORT_MAX_BYTES (256U * 1024U * 1024U)

typedef struct {
    double *distance_m;   /* along the track, from 0, strictly increasing */
    double *elevation_m;
    size_t n;
    size_t duplicates;    /* points dropped at the distance of the one before */
} road_track_t;

/* Reads a GPX file (format above). Returns 0, or -1 with err. */
int road_import_gpx(const char *path, road_track_t *t, char *err, size_t err_len);
/* Reads a distance/elevation CSV. Returns 0, or -1 with err. */
int road_import_csv(const char *path, road_track_t *t, char *err, size_t err_len);
/* By its first non-blank character: '<' GPX, else CSV. */
int road_import_load(const char *path, road_track_t *t, char *err, size_t err_len);

/* Great-circle distance (haversine), m; degrees in. */
double road_import_distance_m(double lat1_deg, double lon1_deg, double lat2_deg, double lon2_deg);

/*
 * Grades of the samples of spacing_m (> 0) along t, smoothed over smooth_m
 * (>= spacing_m): *grade_pct receives a malloc'ed array of *n_out values.
 * Returns 0, or -1 with err (track shorter than one sample, bad arguments,
 * a grade beyond 30 %, out of memory).
 */
int road_import_grade(const road_track_t *t, double spacing_m, double smooth_m, double **grade_pct,
                      size_t *n_out, char *err, size_t err_len);

void road_import_free(road_track_t *t);

#endif /* ROAD_IMPORT_H */
