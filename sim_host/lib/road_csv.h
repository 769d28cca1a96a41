/*
 * Road profile loader for the host tools.
 *
 * A road profile is the road grade sampled at a uniform spacing along the
 * road, as the thesis's test roads are (1000 samples, 12 m apart). The models
 * read the grade angle alpha from it: Fg = m*g*sin(alpha) (3.6) for a single
 * vehicle, Fg_tot = M*g*alpha_p (4.10) for the platoon object.
 *
 * File format (CSV text, see sim_host/data/roads/README.md):
 *
 *     # comment lines start with '#'; blank lines are ignored
 *     distance_m,grade_percent        <- optional header, first content line
 *     0.000,0.000
 *     12.000,0.150
 *     ...
 *
 * - distance_m: metres from the start of the road. The first row is 0 (within
 *   1 mm), every row is strictly greater than the previous one, and row k lies
 *   within 1 mm of k * spacing_m, where spacing_m is the difference between the
 *   first two rows. Checking against k * spacing_m rather than against the
 *   previous row keeps a file's distances from drifting away from the
 *   positions the firmware computes from the spacing alone.
 * - grade_percent: road grade in percent (100 * rise / run), positive uphill,
 *   within [-30, 30].
 * - Decimal numbers only (no hex, nan or inf), spaces or tabs around a field
 *   allowed, LF or CRLF line ends, an optional UTF-8 byte-order mark.
 * - At least 2 and at most ROAD_CSV_MAX_ROWS data rows; a line holds at most
 *   ROAD_CSV_MAX_LINE characters, not counting its line end.
 *
 * Errors are reported as text in a caller-supplied buffer: "FILE:LINE: reason"
 * for a problem on a line (LINE counts physical lines from 1, comments and
 * blank lines included), "FILE: reason" for a problem with the whole file.
 */
#ifndef ROAD_CSV_H
#define ROAD_CSV_H

#include <stddef.h>
#include <stdint.h>

/** Most data rows a profile may hold. */
#define ROAD_CSV_MAX_ROWS 1000000u
/** Longest line in characters, not counting the LF or CRLF that ends it. */
#define ROAD_CSV_MAX_LINE 255u
/** Largest magnitude of a grade sample, in percent. */
#define ROAD_CSV_MAX_GRADE_PERCENT 30.0
/** Tolerance on every distance, in metres (1 mm). */
#define ROAD_CSV_DISTANCE_TOL_M 0.001

typedef struct {
    size_t n_samples;        /* number of grade samples, >= 2 after a load */
    double spacing_m;        /* distance between consecutive samples, > 0 */
    double *grade_percent;   /* n_samples values, owned by the struct */
} road_profile_t;

/**
 * Loads the road profile in the CSV file at path into *road.
 *
 * Returns 0 on success: road->grade_percent then holds n_samples values in
 * file order, sample k at k * spacing_m metres, and the caller releases it
 * with road_profile_free(). Returns -1 on any failure (bad arguments, file
 * not readable, bad content, out of memory): *road is then left empty
 * (n_samples 0, spacing_m 0, grade_percent NULL) and err holds a
 * NUL-terminated message, truncated to err_len - 1 characters. err may be
 * NULL or err_len 0 when the caller wants no message.
 *
 * The first problem in file order is reported; nothing after it is read.
 *
 * Time O(file size). Memory: up to 2 * n_samples doubles while loading
 * (the array grows by doubling), n_samples doubles once loaded.
 * Reentrant: no global state, except that a failing open or read puts
 * strerror() text in the message. The C locale's decimal point is expected
 * (the host tools never call setlocale).
 */
int road_profile_load(const char *path, road_profile_t *road, char *err, size_t err_len);

/**
 * Releases the samples of *road and leaves it empty. Safe on an empty
 * profile, on a profile that failed to load, twice in a row, and on NULL.
 */
void road_profile_free(road_profile_t *road);

/**
 * Converts a profile to the firmware's fixed-point form:
 * grade_ppm_out[k] = round(grade_percent[k] * 10000), grade in parts per
 * million (1 % = 10 000 ppm), rounded half away from zero; *spacing_mm_out =
 * round(spacing_m * 1000), spacing in millimetres.
 *
 * grade_ppm_out must hold road->n_samples values. Returns 0, or -1 with err
 * filled (as for road_profile_load, naming the sample index) when an argument
 * is NULL, a grade is not finite or does not fit an int32_t, or the spacing
 * is not finite or does not round to 1 .. UINT32_MAX mm. On failure the
 * outputs may be partly written and must not be used.
 *
 * Time O(n_samples), no allocation, reentrant.
 */
int road_profile_to_ppm(const road_profile_t *road, int32_t *grade_ppm_out,
                        uint32_t *spacing_mm_out, char *err, size_t err_len);

/*
 * A road as the firmware reads it (pfe_road_t): grade in ppm and spacing in
 * mm, loaded in one call. Owns grade_ppm.
 */
typedef struct {
    int32_t *grade_ppm;
    uint32_t n_samples;
    uint32_t spacing_mm;
} road_ppm_t;

/* road_profile_load() then road_profile_to_ppm(). Returns 0, or -1 with the
 * message in err and *road empty. Errors from the conversion name the file. */
int road_ppm_load(const char *path, road_ppm_t *road, char *err, size_t err_len);
void road_ppm_free(road_ppm_t *road);

#endif /* ROAD_CSV_H */
