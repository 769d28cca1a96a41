/*
 * Host tests of the road import (sim_host/lib/road_import.h) on made-up tracks
 * with known answers, and on bad input.
 *
 *     test_road_import TMP_DIR
 *
 * Known answers (hand-computed):
 *   one degree of a great circle: 6 371 008.8 m x pi / 180 = 111 195.080 m;
 *   0.0001 deg of latitude: 11.119508 m, 1000 of them 11 119.508 m;
 *   a straight line in (distance, elevation) is its own least-squares fit:
 *   a 2 % track gives 2.000 % in every sample, a ramp 0 / 3 / 0 % gives 3 %
 *   in every sample whose window lies on the climb, 0 % off it;
 *   uniform elevation noise of +-5 m (deviation 2.89 m) every 10 m over a
 *   400 m window: grade deviation 2.89 sqrt(120) / 8000 = 0.40 % (at the
 *   road's ends, where the window is cut to half, 2.8 times that).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "lib/road_import.h"

static const char *g_dir;

static const char *path_of(const char *name)
{
    static char buf[4][1024];
    static int k;
    k = (k + 1) % 4;
    (void)snprintf(buf[k], sizeof buf[k], "%s/%s", g_dir, name);
    return buf[k];
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    assert_int_equal(fclose(f), 0);
}

/* GPX along the meridian 16 deg E from 58 deg N, n points 0.0001 deg apart,
 * elevation 100 m + rise_m per point; each point written `copies` times. */
static void write_meridian_gpx(const char *path, size_t n, double rise_m, int copies)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<gpx version=\"1.1\" creator=\"test\">\n"
               "<trk><name>meridian</name><trkseg>\n");
    for (size_t k = 0U; k < n; k++) {
        for (int c = 0; c < copies; c++) {
            fprintf(f, "  <trkpt lon=\"16.0\" lat=\"%.7f\"><ele>%.6f</ele></trkpt>\n", 58.0 + (1e-4 * (double)k),
                    100.0 + (rise_m * (double)k));
        }
    }
    fprintf(f, "</trkseg></trk>\n</gpx>\n");
    assert_int_equal(fclose(f), 0);
}

static void expect_error(const char *name, const char *text, const char *want)
{
    const char *p = path_of(name);
    write_file(p, text);
    road_track_t t;
    char err[512] = "";
    assert_int_equal(road_import_load(p, &t, err, sizeof err), -1);
    print_message("%s: %s\n", name, err);
    if (strstr(err, want) == NULL) {
        fail_msg("'%s' not in '%s'", want, err);
    }
    assert_null(t.distance_m);
}

static void test_great_circle(void **state)
{
    (void)state;
    assert_in_range(lround(road_import_distance_m(0.0, 0.0, 0.0, 1.0) * 1000.0), 111195079, 111195081);
    assert_in_range(lround(road_import_distance_m(58.0, 16.0, 58.0001, 16.0) * 1e6), 11119507, 11119509);
    assert_int_equal(lround(road_import_distance_m(58.0, 16.0, 58.0, 16.0) * 1e6), 0);
}

static void test_gpx_two_percent(void **state)
{
    (void)state;
    const char *p = path_of("meridian.gpx");
    write_meridian_gpx(p, 1001U, 0.02 * 11.119508023, 1);
    road_track_t t;
    char err[512] = "";
    assert_int_equal(road_import_load(p, &t, err, sizeof err), 0);
    assert_int_equal(t.n, 1001U);
    assert_int_equal(t.duplicates, 0U);
    assert_in_range(lround(t.distance_m[1000] * 1000.0), 11119507, 11119509);
    double *g = NULL;
    size_t n = 0U;
    assert_int_equal(road_import_grade(&t, 10.0, 400.0, &g, &n, err, sizeof err), 0);
    assert_int_equal(n, 1111U);
    for (size_t k = 0U; k < n; k++) {
        assert_in_range(lround(g[k] * 1e6), 1999990, 2000010); /* elevations to 1 um */
    }
    free(g);
    road_import_free(&t);
}

static void test_duplicated_points_are_dropped(void **state)
{
    (void)state;
    const char *p = path_of("twice.gpx");
    write_meridian_gpx(p, 301U, 0.02 * 11.119508023, 2);
    road_track_t t;
    char err[512] = "";
    assert_int_equal(road_import_load(p, &t, err, sizeof err), 0);
    assert_int_equal(t.n, 301U);
    assert_int_equal(t.duplicates, 301U);
    double *g = NULL;
    size_t n = 0U;
    assert_int_equal(road_import_grade(&t, 10.0, 400.0, &g, &n, err, sizeof err), 0);
    assert_int_equal(n, 333U);
    assert_in_range(lround(g[0] * 1e6), 1999990, 2000010);
    assert_in_range(lround(g[332] * 1e6), 1999990, 2000010);
    free(g);
    road_import_free(&t);
}

static void test_csv_ramp(void **state)
{
    (void)state;
    const char *p = path_of("ramp.csv");
    FILE *f = fopen(p, "w");
    assert_non_null(f);
    fprintf(f, "# flat, 3 %% for 2 km, flat\ndistance_m,elevation_m\n");
    for (int d = 0; d <= 6000; d += 10) {
        const double h = (d < 2000) ? 50.0 : ((d < 4000) ? 50.0 + (0.03 * (d - 2000)) : 110.0);
        fprintf(f, "%d,%.3f\n", d, h);
    }
    assert_int_equal(fclose(f), 0);
    road_track_t t;
    char err[512] = "";
    assert_int_equal(road_import_load(p, &t, err, sizeof err), 0);
    assert_int_equal(t.n, 601U);
    double *g = NULL;
    size_t n = 0U;
    assert_int_equal(road_import_grade(&t, 12.0, 400.0, &g, &n, err, sizeof err), 0);
    assert_int_equal(n, 500U);
    for (size_t k = 0U; k < n; k++) {
        const double mid = ((double)k + 0.5) * 12.0;
        if (((mid > 2200.0) && (mid < 3800.0))) {
            assert_in_range(lround(g[k] * 1e6), 2999999, 3000001);
        } else if ((mid < 1800.0) || (mid > 4200.0)) {
            assert_in_range(lround(fabs(g[k]) * 1e6), 0, 1);
        } else {
            assert_in_range(lround(g[k] * 1e6), 0, 3000001); /* on the curve: between */
        }
    }
    free(g);
    road_import_free(&t);
}

static void test_noise_is_smoothed(void **state)
{
    (void)state;
    const char *p = path_of("noisy.csv");
    FILE *f = fopen(p, "w");
    assert_non_null(f);
    uint32_t s = 12345U;
    for (int d = 0; d <= 12000; d += 10) {
        s = (s * 1664525U) + 1013904223U;                        /* LCG, top bits uniform */
        const double noise = (((double)(s >> 8) / 16777216.0) * 10.0) - 5.0; /* -5 .. +5 m */
        fprintf(f, "%d,%.3f\n", d, 200.0 + (0.02 * d) + noise);
    }
    assert_int_equal(fclose(f), 0);
    road_track_t t;
    char err[512] = "";
    assert_int_equal(road_import_load(p, &t, err, sizeof err), 0);
    double *g = NULL;
    size_t n = 0U;
    /* unsmoothed (the window one sample): the noise makes grades beyond 30 %, refused */
    assert_int_equal(road_import_grade(&t, 10.0, 10.0, &g, &n, err, sizeof err), -1);
    print_message("unsmoothed: %s\n", err);
    assert_non_null(strstr(err, "beyond +-30 %"));
    assert_int_equal(road_import_grade(&t, 10.0, 400.0, &g, &n, err, sizeof err), 0);
    double worst = 0.0, mean = 0.0, var = 0.0;
    for (size_t k = 0U; k < n; k++) {
        worst = fmax(worst, fabs(g[k] - 2.0));
        mean += g[k] / (double)n;
    }
    for (size_t k = 0U; k < n; k++) {
        var += (g[k] - mean) * (g[k] - mean) / (double)n;
    }
    print_message("noise +-5 m every 10 m, 400 m window: %zu samples, mean %.4f %%, deviation %.3f %%, "
                  "largest error %.3f %%\n", n, mean, sqrt(var), worst);
    /* no +-10 % grades: within 3 % (the largest at the road's ends, where the window holds half
     * its points) */
    assert_in_range(lround(worst * 1000.0), 0, 3000);
    assert_in_range(lround(sqrt(var) * 1000.0), 200, 600);   /* about the 0.40 % above */
    assert_in_range(lround(mean * 1000.0), 1950, 2050);
    free(g);
    road_import_free(&t);
}

static void test_bad_input(void **state)
{
    (void)state;
    expect_error("noele.gpx", "<gpx><trk><trkseg>\n<trkpt lat=\"58\" lon=\"16\"></trkpt>\n"
                              "<trkpt lat=\"58.001\" lon=\"16\"></trkpt></trkseg></trk></gpx>\n",
                 "noele.gpx:2: a track point without <ele>: the track has no elevation");
    expect_error("one.gpx", "<gpx><trk><trkseg>\n<trkpt lat=\"58\" lon=\"16\"><ele>12</ele></trkpt>\n"
                            "</trkseg></trk></gpx>\n",
                 "one.gpx: a track of 1 point at one place: at least two needed");
    expect_error("still.gpx", "<gpx><trk><trkseg>\n<trkpt lat=\"58\" lon=\"16\"><ele>12</ele></trkpt>\n"
                              "<trkpt lat=\"58\" lon=\"16\"><ele>13</ele></trkpt>\n</trkseg></trk></gpx>\n",
                 "still.gpx: a track of 2 points at one place");
    expect_error("lat.gpx", "<gpx>\n\n<trkpt lat=\"abc\" lon=\"16\"><ele>12</ele></trkpt>\n</gpx>\n",
                 "lat.gpx:3: a track point without a numeric lat in [-90, 90]");
    expect_error("ele.gpx", "<gpx>\n<trkpt lat=\"58\" lon=\"16\">\n<ele>high</ele></trkpt>\n</gpx>\n",
                 "ele.gpx:3: <ele> is not a number of metres");
    expect_error("hex.gpx", "<gpx>\n<trkpt lat=\"0x3A\" lon=\"16\"><ele>1</ele></trkpt>\n</gpx>\n",
                 "hex.gpx:2: a track point without a numeric lat");
    expect_error("none.gpx", "<gpx><metadata/></gpx>\n", "none.gpx: no <trkpt> or <rtept>: not a GPX track");
    expect_error("word.csv", "distance_m,elevation_m\n0,10\n100,abc\n", "word.csv:3: elevation is not a number");
    expect_error("dist.csv", "0,10\nten,11\n", "dist.csv:2: distance is not a number");
    expect_error("back.csv", "0,10\n100,11\n50,12\n", "back.csv:3: distance decreases");
    expect_error("three.csv", "0,10,1\n", "three.csv:1: more than two fields");
    expect_error("row.csv", "# one row\n0,10\n", "row.csv: 1 row at one place: at least two places needed");
    expect_error("nan.csv", "0,10\n10,nan\n", "nan.csv:2: elevation is not a number");
    road_track_t t;
    char err[512] = "";
    assert_int_equal(road_import_load(path_of("missing.gpx"), &t, err, sizeof err), -1);
    assert_non_null(strstr(err, "No such file"));
    /* a track shorter than one sample */
    write_file(path_of("short.csv"), "0,10\n5,10.1\n");
    assert_int_equal(road_import_load(path_of("short.csv"), &t, err, sizeof err), 0);
    double *g = NULL;
    size_t n = 0U;
    assert_int_equal(road_import_grade(&t, 10.0, 400.0, &g, &n, err, sizeof err), -1);
    assert_non_null(strstr(err, "shorter than one 10.0 m sample"));
    assert_null(g);
    assert_int_equal(road_import_grade(&t, 1.0, 0.5, &g, &n, err, sizeof err), -1);
    road_import_free(&t);
}

int main(int argc, char **argv)
{
    g_dir = (argc > 1) ? argv[1] : "/tmp";
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_great_circle),
        cmocka_unit_test(test_gpx_two_percent),
        cmocka_unit_test(test_duplicated_points_are_dropped),
        cmocka_unit_test(test_csv_ramp),
        cmocka_unit_test(test_noise_is_smoothed),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
