/*
 * Tests of the road profile loader (sim_host/lib/road_csv.c) and of the three
 * committed roads (sim_host/data/roads/).
 *
 *     test_road_csv [ROADS_DIR ROADGEN]
 *
 * ROADS_DIR is the directory of the committed road CSVs and ROADGEN the
 * roadgen binary; either may also come from the environment variables
 * ROADS_DIR and ROADGEN (the command line wins). Without them the tests of
 * the committed roads fail with a message saying so.
 *
 * Input files are written to a fresh directory from mkdtemp() under $TMPDIR
 * (default /tmp), removed at the end. Expected values are hand-computed
 * literals.
 */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "../test_assert.h"

#include <errno.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "lib/road_csv.h"

extern char **environ;

#define PATH_LEN 4096
#define ERR_LEN 512
#define MAX_CREATED 512

static char g_dir[PATH_LEN];
static const char *g_roads_dir;
static const char *g_roadgen;
static char *g_created[MAX_CREATED];
static size_t g_n_created;

/* ---- helpers ------------------------------------------------------------ */

/* Returns tmpdir/name, remembered for removal at the end. */
static const char *tmp_path(const char *name)
{
    ASSERT_LT(g_n_created, (size_t)MAX_CREATED);
    char *p = malloc(PATH_LEN);
    assert_non_null(p);
    const int n = snprintf(p, PATH_LEN, "%s/%s", g_dir, name);
    ASSERT_GT(n, 0);
    ASSERT_LT(n, PATH_LEN);
    g_created[g_n_created++] = p;
    return p;
}

/* Writes len bytes to tmpdir/name; returns the path. */
static const char *write_bytes(const char *name, const char *data, size_t len)
{
    const char *path = tmp_path(name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, len, f), len);
    assert_int_equal(fclose(f), 0);
    return path;
}

static const char *write_text(const char *name, const char *text)
{
    return write_bytes(name, text, strlen(text));
}

/* Loads path, expecting failure with the message "<path><suffix>" and an
 * empty profile. */
static void expect_error(const char *path, const char *suffix)
{
    char expected[ERR_LEN];
    char err[ERR_LEN];
    road_profile_t road;
    memset(&road, 0xA5, sizeof road);
    memset(err, 0xA5, sizeof err);
    (void)snprintf(expected, sizeof expected, "%s%s", path, suffix);
    assert_int_equal(road_profile_load(path, &road, err, sizeof err), -1);
    assert_string_equal(err, expected);
    assert_int_equal(road.n_samples, 0);
    assert_null(road.grade_percent);
    ASSERT_EQ(road.spacing_m, 0.0);
    road_profile_free(&road);
}

/* Writes text to a file and expects it to fail with "<path><suffix>". */
static void expect_text_error(const char *name, const char *text, const char *suffix)
{
    expect_error(write_text(name, text), suffix);
}

/* Loads path, expecting success. */
static void load_ok(const char *path, road_profile_t *road)
{
    char err[ERR_LEN];
    memset(road, 0xA5, sizeof *road);
    err[0] = '\0';
    const int rc = road_profile_load(path, road, err, sizeof err);
    if (rc != 0) {
        print_error("unexpected load error: %s\n", err);
    }
    assert_int_equal(rc, 0);
    assert_non_null(road->grade_percent);
}

/* ---- good files ---------------------------------------------------------- */

static void test_good_with_header(void **state)
{
    (void)state;
    road_profile_t road;
    load_ok(write_text("good_header.csv",
                       "distance_m,grade_percent\n"
                       "0,0\n"
                       "12.5,1.25\n"
                       "25.000, -0.5\n"
                       "37.5,30\n"
                       "50,-30\n"),
            &road);
    assert_int_equal(road.n_samples, 5);
    ASSERT_EQ(road.spacing_m, 12.5);
    ASSERT_EQ(road.grade_percent[0], 0.0);
    ASSERT_EQ(road.grade_percent[1], 1.25);
    ASSERT_EQ(road.grade_percent[2], -0.5);
    ASSERT_EQ(road.grade_percent[3], 30.0);
    ASSERT_EQ(road.grade_percent[4], -30.0);
    road_profile_free(&road);
    assert_int_equal(road.n_samples, 0);
    assert_null(road.grade_percent);
}

static void test_good_without_header_spaces_tabs(void **state)
{
    (void)state;
    road_profile_t road;
    load_ok(write_text("good_noheader.csv",
                       " 0 , 0.001 \n"
                       "\t12\t,\t-0.002\t\n"
                       "+24,+3.5e-1\n"
                       "36.0009,2E0\n"),
            &road);
    assert_int_equal(road.n_samples, 4);
    ASSERT_EQ(road.spacing_m, 12.0);
    ASSERT_EQ(road.grade_percent[0], 0.001);
    ASSERT_EQ(road.grade_percent[1], -0.002);
    ASSERT_EQ(road.grade_percent[2], 0.35);
    ASSERT_EQ(road.grade_percent[3], 2.0);
    road_profile_free(&road);
}

static void test_crlf(void **state)
{
    (void)state;
    road_profile_t road;
    load_ok(write_text("crlf.csv",
                       "# comment\r\n"
                       "distance_m,grade_percent\r\n"
                       "\r\n"
                       "0,1\r\n"
                       "10,-2\r\n"),
            &road);
    assert_int_equal(road.n_samples, 2);
    ASSERT_EQ(road.spacing_m, 10.0);
    ASSERT_EQ(road.grade_percent[0], 1.0);
    ASSERT_EQ(road.grade_percent[1], -2.0);
    road_profile_free(&road);

    expect_text_error("crlf_bad.csv", "0,1\r\n12,2\r\n25,3\r\n",
                      ":3: non-uniform distance 25 m, expected 24 m "
                      "(spacing 12 m from the first two rows, tolerance 1 mm)");
}

static void test_comments_and_blank_lines(void **state)
{
    (void)state;
    road_profile_t road;
    load_ok(write_text("comments.csv",
                       "# road\n"
                       "\n"
                       "   \n"
                       "\t# indented comment\n"
                       "distance_m , grade_percent\n"
                       "# between header and data\n"
                       "0,1\n"
                       "\n"
                       "2,2\n"
                       "  # another\n"
                       "4,3\n"
                       "\n"),
            &road);
    assert_int_equal(road.n_samples, 3);
    ASSERT_EQ(road.spacing_m, 2.0);
    ASSERT_EQ(road.grade_percent[0], 1.0);
    ASSERT_EQ(road.grade_percent[1], 2.0);
    ASSERT_EQ(road.grade_percent[2], 3.0);
    road_profile_free(&road);

    /* Line numbers count comment and blank lines. */
    expect_text_error("comments_bad.csv",
                      "# a\n"
                      "\n"
                      "distance_m,grade_percent\n"
                      "# b\n"
                      "0,1\n"
                      "\n"
                      "2,x\n",
                      ":7: bad number 'x' in column 2 (grade_percent)");
}

static void test_bom_and_no_final_newline(void **state)
{
    (void)state;
    road_profile_t road;
    load_ok(write_text("bom.csv", "\xEF\xBB\xBF" "distance_m,grade_percent\n0,1\n1,2"), &road);
    assert_int_equal(road.n_samples, 2);
    ASSERT_EQ(road.spacing_m, 1.0);
    ASSERT_EQ(road.grade_percent[1], 2.0);
    road_profile_free(&road);
}

/* ---- whole-file errors --------------------------------------------------- */

static void test_missing_file(void **state)
{
    (void)state;
    expect_error(tmp_path("does_not_exist.csv"), ": cannot open: No such file or directory");
}

static void test_directory(void **state)
{
    (void)state;
    expect_error(g_dir, ": read error: Is a directory");
}

static void test_empty_file(void **state)
{
    (void)state;
    expect_text_error("empty.csv", "", ": empty file");
}

static void test_too_few_rows(void **state)
{
    (void)state;
    expect_text_error("only_comments.csv", "# nothing\n\n", ": no data rows (need at least 2)");
    expect_text_error("only_header.csv", "distance_m,grade_percent\n",
                      ": no data rows (need at least 2)");
    expect_text_error("only_bom.csv", "\xEF\xBB\xBF", ": no data rows (need at least 2)");
    expect_text_error("one_row.csv", "distance_m,grade_percent\n0,1\n",
                      ": only 1 data row (need at least 2)");
}

/* ---- line errors ------------------------------------------------------- */

static void test_nul_byte(void **state)
{
    (void)state;
    static const char data[] = "0,1\n12,2\n2\0,3\n";
    expect_error(write_bytes("nul.csv", data, sizeof data - 1u), ":3: binary data (NUL byte)");
    static const char first[] = "\0\0\0\0";
    expect_error(write_bytes("nul_first.csv", first, sizeof first - 1u),
                 ":1: binary data (NUL byte)");
}

/* "0." followed by zeros to width characters, then ",1". */
static void long_row(char *buf, size_t width)
{
    buf[0] = '0';
    buf[1] = '.';
    for (size_t i = 2; i < width - 2u; i++) {
        buf[i] = '0';
    }
    buf[width - 2u] = ',';
    buf[width - 1u] = '1';
    buf[width] = '\0';
}

static void test_line_length(void **state)
{
    (void)state;
    char row[300];
    char text[700];
    road_profile_t road;

    long_row(row, 255);
    assert_int_equal(strlen(row), 255);
    (void)snprintf(text, sizeof text, "%s\n1,2\n", row);
    load_ok(write_text("len255.csv", text), &road);
    assert_int_equal(road.n_samples, 2);
    road_profile_free(&road);

    (void)snprintf(text, sizeof text, "%s\r\n1,2\r\n", row);
    load_ok(write_text("len255_crlf.csv", text), &road);
    assert_int_equal(road.n_samples, 2);
    road_profile_free(&road);

    long_row(row, 256);
    (void)snprintf(text, sizeof text, "0,1\n%s\n", row);
    expect_text_error("len256.csv", text, ":2: line longer than 255 characters");
    (void)snprintf(text, sizeof text, "0,1\n%s\r\n", row);
    expect_text_error("len256_crlf.csv", text, ":2: line longer than 255 characters");
    (void)snprintf(text, sizeof text, "# %s\n", row);
    expect_text_error("len_comment.csv", text, ":1: line longer than 255 characters");
}

static void test_columns(void **state)
{
    (void)state;
    expect_text_error("col_missing.csv", "0,1\n12\n",
                      ":2: missing column: expected 2 columns (distance_m,grade_percent), found 1");
    expect_text_error("col_extra.csv", "0,1,2\n",
                      ":1: extra columns: expected 2 columns (distance_m,grade_percent), found 3");
    expect_text_error("col_trailing.csv", "0,1\n12,1,\n",
                      ":2: extra columns: expected 2 columns (distance_m,grade_percent), found 3");
    expect_text_error("col_semicolon.csv", "0;1\n",
                      ":1: missing column: expected 2 columns (distance_m,grade_percent), found 1");
}

static void test_bad_numbers(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        const char *suffix;
    } cases[] = {
        {"0,1\n12,abc\n", ":2: bad number 'abc' in column 2 (grade_percent)"},
        {"0,1\n12,1.2.3\n", ":2: bad number '1.2.3' in column 2 (grade_percent)"},
        {"0,1\n12,0x10\n", ":2: bad number '0x10' in column 2 (grade_percent)"},
        {"0,1\n12,nan\n", ":2: bad number 'nan' in column 2 (grade_percent)"},
        {"0,1\n12,inf\n", ":2: bad number 'inf' in column 2 (grade_percent)"},
        {"0,1\n12,-Infinity\n", ":2: bad number '-Infinity' in column 2 (grade_percent)"},
        {"0,1\n12,12%\n", ":2: bad number '12%' in column 2 (grade_percent)"},
        {"0,1\n12,1e\n", ":2: bad number '1e' in column 2 (grade_percent)"},
        {"0,1\n12,--1\n", ":2: bad number '--1' in column 2 (grade_percent)"},
        {"0,1\n12,1 2\n", ":2: bad number '1 2' in column 2 (grade_percent)"},
        {"0,1\n12,.\n", ":2: bad number '.' in column 2 (grade_percent)"},
        {"0,1\n12,1e999\n", ":2: bad number '1e999' in column 2 (grade_percent): out of range"},
        {"0,1\n12,\n", ":2: missing value in column 2 (grade_percent)"},
        {"0,1\n12,  \t\n", ":2: missing value in column 2 (grade_percent)"},
        {"0,1\n12m,1\n", ":2: bad number '12m' in column 1 (distance_m)"},
        {"0,1\n,1\n", ":2: missing value in column 1 (distance_m)"},
        {"0,1\n1e999,1\n", ":2: bad number '1e999' in column 1 (distance_m): out of range"},
        {"nan,1\n", ":1: bad number 'nan' in column 1 (distance_m)"},
        {"0,1\ndistance_m,grade_percent\n", ":2: bad number 'distance_m' in column 1 (distance_m)"},
        {"dist,grade\n0,1\n", ":1: unrecognised header 'dist,grade' (expected distance_m,grade_percent)"},
        {"distance_m,grade_percent,x\n0,1\n",
         ":1: unrecognised header 'distance_m,grade_percent,x' (expected distance_m,grade_percent)"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char name[64];
        (void)snprintf(name, sizeof name, "bad_number_%zu.csv", i);
        expect_text_error(name, cases[i].text, cases[i].suffix);
    }
}

static void test_first_distance(void **state)
{
    (void)state;
    road_profile_t road;
    expect_text_error("first5.csv", "5,1\n17,1\n", ":1: first distance is 5 m, must be 0");
    expect_text_error("first_2mm.csv", "# c\n0.002,1\n12,1\n",
                      ":2: first distance is 0.002 m, must be 0");
    expect_text_error("first_neg.csv", "-1,1\n11,1\n", ":1: first distance is -1 m, must be 0");
    /* Within the 1 mm tolerance. */
    load_ok(write_text("first_1mm.csv", "0.001,1\n12.001,1\n"), &road);
    assert_int_equal(road.n_samples, 2);
    road_profile_free(&road);
}

static void test_distance_order_and_spacing(void **state)
{
    (void)state;
    road_profile_t road;
    expect_text_error("dist_equal.csv", "0,1\n12,1\n12,1\n",
                      ":3: distance 12 m is not greater than the previous row's 12 m");
    expect_text_error("dist_decreasing.csv", "0,1\n12,1\n6,1\n",
                      ":3: distance 6 m is not greater than the previous row's 12 m");
    expect_text_error("dist_zero_spacing.csv", "0,1\n0,1\n",
                      ":2: distance 0 m is not greater than the previous row's 0 m");
    expect_text_error("dist_gap.csv", "0,1\n12,1\n24,1\n48,1\n",
                      ":4: non-uniform distance 48 m, expected 36 m "
                      "(spacing 12 m from the first two rows, tolerance 1 mm)");
    expect_text_error("dist_2mm.csv", "0,1\n12,1\n24.001,1\n36.002,1\n",
                      ":4: non-uniform distance 36.002 m, expected 36 m "
                      "(spacing 12 m from the first two rows, tolerance 1 mm)");
    /* Steps each within 1 mm of the spacing, but drifting away from k * spacing. */
    expect_text_error("dist_drift.csv", "0,1\n10,1\n20.0009,1\n30.0018,1\n",
                      ":4: non-uniform distance 30.0018 m, expected 30 m "
                      "(spacing 10 m from the first two rows, tolerance 1 mm)");
    /* 1 mm off either way is accepted. */
    load_ok(write_text("dist_1mm.csv", "0,1\n12,1\n24.001,1\n35.999,1\n"), &road);
    assert_int_equal(road.n_samples, 4);
    ASSERT_EQ(road.spacing_m, 12.0);
    road_profile_free(&road);
}

static void test_grade_range(void **state)
{
    (void)state;
    expect_text_error("grade_high.csv", "0,30.001\n12,1\n",
                      ":1: grade 30.001 % outside [-30, 30] %");
    expect_text_error("grade_low.csv", "0,1\n12,-30.5\n",
                      ":2: grade -30.5 % outside [-30, 30] %");
    expect_text_error("grade_huge.csv", "0,1\n12,1e300\n",
                      ":2: grade 1e+300 % outside [-30, 30] %");
}

static void test_row_limit(void **state)
{
    (void)state;
    const char *path = tmp_path("rows.csv");
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    ASSERT_GE(fputs("distance_m,grade_percent\n", f), 0);
    for (unsigned k = 0; k < 1000000u; k++) {
        ASSERT_GT(fprintf(f, "%u,%u\n", k, k % 3u), 0);
    }
    assert_int_equal(fclose(f), 0);

    road_profile_t road;
    load_ok(path, &road);
    assert_int_equal(road.n_samples, 1000000);
    ASSERT_EQ(road.spacing_m, 1.0);
    ASSERT_EQ(road.grade_percent[999999], 0.0);       /* 999999 % 3 */
    ASSERT_EQ(road.grade_percent[999998], 2.0);
    road_profile_free(&road);

    f = fopen(path, "ab");
    assert_non_null(f);
    ASSERT_GE(fputs("1000000,0\n", f), 0);
    assert_int_equal(fclose(f), 0);
    expect_error(path, ":1000002: too many rows (limit 1000000)");
}

/* ---- API edges --------------------------------------------------------- */

static void test_error_buffer_and_arguments(void **state)
{
    (void)state;
    const char *bad = write_text("errbuf.csv", "0,1\n12,x\n");
    road_profile_t road;

    /* A short buffer gets a truncated, terminated prefix of the message. */
    char err[8];
    memset(err, 0xA5, sizeof err);
    assert_int_equal(road_profile_load(bad, &road, err, sizeof err), -1);
    assert_int_equal(strlen(err), 7);
    assert_memory_equal(err, bad, 7);

    /* No buffer at all. */
    assert_int_equal(road_profile_load(bad, &road, NULL, 0), -1);
    assert_int_equal(road.n_samples, 0);
    assert_null(road.grade_percent);

    char msg[ERR_LEN];
    assert_int_equal(road_profile_load(bad, NULL, msg, sizeof msg), -1);
    ASSERT_GT(strlen(msg), 0u);
    assert_int_equal(road_profile_load(NULL, &road, msg, sizeof msg), -1);
    ASSERT_GT(strlen(msg), 0u);

    /* free is safe on an empty profile, twice, and on NULL. */
    road_profile_free(&road);
    road_profile_free(&road);
    road_profile_free(NULL);
}

static void test_to_ppm(void **state)
{
    (void)state;
    double grades[] = {0.0, 2.0, -3.0, 4.0, 0.0005, -0.0005, 1.2345, 0.137, 30.0, -30.0};
    road_profile_t road = {10u, 12.0, grades};
    int32_t ppm[10];
    uint32_t spacing_mm = 0xA5A5A5A5u;
    char err[ERR_LEN];
    memset(ppm, 0xA5, sizeof ppm);
    assert_int_equal(road_profile_to_ppm(&road, ppm, &spacing_mm, err, sizeof err), 0);
    assert_int_equal(spacing_mm, 12000u);
    assert_int_equal(ppm[0], 0);
    assert_int_equal(ppm[1], 20000);
    assert_int_equal(ppm[2], -30000);
    assert_int_equal(ppm[3], 40000);
    assert_int_equal(ppm[4], 5);
    assert_int_equal(ppm[5], -5);
    assert_int_equal(ppm[6], 12345);
    assert_int_equal(ppm[7], 1370);
    assert_int_equal(ppm[8], 300000);
    assert_int_equal(ppm[9], -300000);

    /* Spacing rounds to the nearest mm. */
    road.spacing_m = 0.3334;
    assert_int_equal(road_profile_to_ppm(&road, ppm, &spacing_mm, err, sizeof err), 0);
    assert_int_equal(spacing_mm, 333u);

    road.spacing_m = 0.0004;
    assert_int_equal(road_profile_to_ppm(&road, ppm, &spacing_mm, err, sizeof err), -1);
    assert_string_equal(err, "spacing 0.0004 m does not round to 1 .. 4294967295 mm");
    road.spacing_m = 5e6;
    assert_int_equal(road_profile_to_ppm(&road, ppm, &spacing_mm, err, sizeof err), -1);
    assert_string_equal(err, "spacing 5000000 m does not round to 1 .. 4294967295 mm");
    road.spacing_m = 12.0;

    grades[3] = 214748.3647;   /* 2147483647 ppm, the int32 maximum */
    grades[4] = -214748.3648;  /* -2147483648 ppm, the int32 minimum */
    assert_int_equal(road_profile_to_ppm(&road, ppm, &spacing_mm, err, sizeof err), 0);
    assert_int_equal(ppm[3], 2147483647);
    assert_int_equal(ppm[4], -2147483647 - 1);

    grades[3] = 214748.3648;
    assert_int_equal(road_profile_to_ppm(&road, ppm, &spacing_mm, err, sizeof err), -1);
    assert_string_equal(err, "sample 3: grade 214748.3648 % does not fit int32 as ppm");
    grades[3] = (double)NAN;
    assert_int_equal(road_profile_to_ppm(&road, ppm, &spacing_mm, err, sizeof err), -1);
    assert_string_equal(err, "sample 3: grade nan % does not fit int32 as ppm");

    assert_int_equal(road_profile_to_ppm(NULL, ppm, &spacing_mm, err, sizeof err), -1);
    assert_int_equal(road_profile_to_ppm(&road, NULL, &spacing_mm, err, sizeof err), -1);
    assert_int_equal(road_profile_to_ppm(&road, ppm, NULL, NULL, 0), -1);
}

/* Byte-level mutations of a good file must load or fail cleanly, never crash;
 * a failure message always starts with the file name. */
static void test_mutations_never_crash(void **state)
{
    (void)state;
    static const char good[] =
        "# road\r\ndistance_m,grade_percent\n0,0.5\n12,1.25\n24,-2\n36,3.999\n48,0\n";
    static const char alphabet[] = "0123456789,.-+eE#\r\n\t x\0";
    uint64_t s = 12345u;
    const char *path = tmp_path("mutant.csv");
    char buf[sizeof good + 8];
    char err[ERR_LEN];
    for (int iter = 0; iter < 3000; iter++) {
        size_t len = sizeof good - 1u;
        memcpy(buf, good, len);
        for (int m = 0; m < 3; m++) {
            s = s * 6364136223846793005u + 1442695040888963407u;
            const uint32_t r = (uint32_t)(s >> 32);
            const size_t pos = r % len;
            const char c = alphabet[(r >> 16) % (sizeof alphabet - 1u)];
            if ((r >> 8) % 3u == 0u && len > 1u) {
                memmove(buf + pos, buf + pos + 1, len - pos - 1u);   /* delete */
                len--;
            } else if ((r >> 8) % 3u == 1u && len < sizeof buf) {
                memmove(buf + pos + 1, buf + pos, len - pos);        /* insert */
                buf[pos] = c;
                len++;
            } else {
                buf[pos] = c;                                        /* replace */
            }
        }
        FILE *f = fopen(path, "wb");
        assert_non_null(f);
        assert_int_equal(fwrite(buf, 1, len, f), len);
        assert_int_equal(fclose(f), 0);
        road_profile_t road;
        const int rc = road_profile_load(path, &road, err, sizeof err);
        if (rc == 0) {
            ASSERT_GE(road.n_samples, 2u);
            ASSERT_GT(road.spacing_m, 0.0);
            for (size_t k = 0; k < road.n_samples; k++) {
                ASSERT_LE(fabs(road.grade_percent[k]), 30.0);
            }
        } else {
            assert_int_equal(rc, -1);
            assert_int_equal(strncmp(err, path, strlen(path)), 0);
            ASSERT_GT(strlen(err), strlen(path) + 2u);
        }
        road_profile_free(&road);
    }
}

/* ---- the committed roads ------------------------------------------------ */

static void need_roads(void)
{
    if (g_roads_dir == NULL || g_roadgen == NULL) {
        fail_msg("committed-road tests need ROADS_DIR and ROADGEN "
                 "(argv: test_road_csv ROADS_DIR ROADGEN, or environment variables)");
    }
}

static const char *road_path(const char *name)
{
    static char path[PATH_LEN];
    const int n = snprintf(path, sizeof path, "%s/%s.csv", g_roads_dir, name);
    ASSERT_GT(n, 0);
    ASSERT_LT(n, (int)sizeof path);
    return path;
}

/* Reads a whole file into a malloc'd buffer. */
static char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        fail_msg("cannot open %s: %s", path, strerror(errno));
    }
    size_t cap = 65536u;
    size_t n = 0u;
    char *buf = malloc(cap);
    assert_non_null(buf);
    for (;;) {
        if (n == cap) {
            cap *= 2u;
            buf = realloc(buf, cap);
            assert_non_null(buf);
        }
        const size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0u) {
            break;
        }
    }
    assert_int_equal(ferror(f), 0);
    assert_int_equal(fclose(f), 0);
    *len = n;
    return buf;
}

static void regenerate_and_compare(const char *name)
{
    need_roads();
    char out_name[64];
    (void)snprintf(out_name, sizeof out_name, "regen_%s.csv", name);
    const char *out = tmp_path(out_name);

    /* posix_spawn takes char *const argv[]: give it writable copies. */
    char a0[512], a1[64], a2[8], a3[512];
    (void)snprintf(a0, sizeof a0, "%s", g_roadgen);
    (void)snprintf(a1, sizeof a1, "%s", name);
    (void)snprintf(a2, sizeof a2, "%s", "--out");
    (void)snprintf(a3, sizeof a3, "%s", out);
    char *argv[] = {a0, a1, a2, a3, NULL};
    pid_t pid;
    const int rc = posix_spawn(&pid, g_roadgen, NULL, NULL, argv, environ);
    if (rc != 0) {
        fail_msg("cannot run %s: %s", g_roadgen, strerror(rc));
    }
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    if (!WIFEXITED(status)) {
        fail_msg("%s did not exit (wait status 0x%x)", g_roadgen, (unsigned)status);
    }
    assert_int_equal(WEXITSTATUS(status), 0);

    size_t len_new = 0u;
    size_t len_old = 0u;
    char *fresh = slurp(out, &len_new);
    char *committed = slurp(road_path(name), &len_old);
    if (len_new != len_old || memcmp(fresh, committed, len_new) != 0) {
        free(fresh);
        free(committed);
        fail_msg("%s differs from roadgen %s: regenerate it", road_path(name), name);
    }
    free(fresh);
    free(committed);
}

static void test_regenerate_flat(void **state)
{
    (void)state;
    regenerate_and_compare("flat");
}

static void test_regenerate_uphill(void **state)
{
    (void)state;
    regenerate_and_compare("uphill");
}

static void test_regenerate_hilly(void **state)
{
    (void)state;
    regenerate_and_compare("hilly");
}

static void test_roads_flat_and_uphill(void **state)
{
    (void)state;
    need_roads();
    road_profile_t road;
    load_ok(road_path("flat"), &road);
    assert_int_equal(road.n_samples, 1000);
    ASSERT_EQ(road.spacing_m, 12.0);
    for (size_t k = 0; k < road.n_samples; k++) {
        ASSERT_EQ(road.grade_percent[k], 0.0);
    }
    road_profile_free(&road);

    load_ok(road_path("uphill"), &road);
    assert_int_equal(road.n_samples, 1000);
    ASSERT_EQ(road.spacing_m, 12.0);
    for (size_t k = 0; k < road.n_samples; k++) {
        ASSERT_EQ(road.grade_percent[k], 2.0);
    }
    road_profile_free(&road);
}

/* The hilly road has the shape it is meant to have: 1000 samples at 12 m,
 * grade from exactly -3 % to exactly +4 % in steps of 0.001 %, grade changing
 * by at most 0.25 % per 12 m, an upgrade of 2 % or more lasting at least
 * 1 km, and at least 3 hill tops. */
static void test_road_hilly_shape(void **state)
{
    (void)state;
    need_roads();
    road_profile_t road;
    load_ok(road_path("hilly"), &road);
    assert_int_equal(road.n_samples, 1000);
    ASSERT_EQ(road.spacing_m, 12.0);

    int32_t ppm[1000];
    uint32_t spacing_mm = 0u;
    char err[ERR_LEN];
    assert_int_equal(road_profile_to_ppm(&road, ppm, &spacing_mm, err, sizeof err), 0);
    assert_int_equal(spacing_mm, 12000u);

    int32_t lo = ppm[0];
    int32_t hi = ppm[0];
    int run = 0;
    int longest = 0;
    int crests = 0;
    for (size_t k = 0; k < 1000u; k++) {
        assert_int_equal(ppm[k] % 10, 0);   /* 3 decimals of a percent */
        lo = (ppm[k] < lo) ? ppm[k] : lo;
        hi = (ppm[k] > hi) ? ppm[k] : hi;
        run = (ppm[k] >= 20000) ? run + 1 : 0;
        longest = (run > longest) ? run : longest;
        if (k > 0u) {
            const int32_t step = ppm[k] - ppm[k - 1u];
            ASSERT_GE(step, -2500);
            ASSERT_LE(step, 2500);
            crests += (ppm[k - 1u] > 0 && ppm[k] <= 0) ? 1 : 0;
        }
    }
    assert_int_equal(lo, -30000);
    assert_int_equal(hi, 40000);
    ASSERT_GE(longest * 12, 1000);
    ASSERT_GE(crests, 3);
    road_profile_free(&road);
}

/* ---- fixture ------------------------------------------------------------ */

static int make_dir(void **state)
{
    (void)state;
    const char *base = getenv("TMPDIR");
    if (base == NULL || base[0] == '\0') {
        base = "/tmp";
    }
    const int n = snprintf(g_dir, sizeof g_dir, "%s/test_road_csv.XXXXXX", base);
    if (n <= 0 || n >= (int)sizeof g_dir || mkdtemp(g_dir) == NULL) {
        fprintf(stderr, "cannot create a temporary directory under %s\n", base);
        return -1;
    }
    return 0;
}

static int remove_dir(void **state)
{
    (void)state;
    for (size_t i = 0; i < g_n_created; i++) {
        (void)remove(g_created[i]);
        free(g_created[i]);
    }
    g_n_created = 0u;
    return rmdir(g_dir) == 0 ? 0 : -1;
}

int main(int argc, char **argv)
{
    g_roads_dir = getenv("ROADS_DIR");
    g_roadgen = getenv("ROADGEN");
    if (argc == 3) {
        g_roads_dir = argv[1];
        g_roadgen = argv[2];
    } else if (argc != 1) {
        fprintf(stderr, "usage: %s [ROADS_DIR ROADGEN]\n", argv[0]);
        return 2;
    }

    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_good_with_header),
        cmocka_unit_test(test_good_without_header_spaces_tabs),
        cmocka_unit_test(test_crlf),
        cmocka_unit_test(test_comments_and_blank_lines),
        cmocka_unit_test(test_bom_and_no_final_newline),
        cmocka_unit_test(test_missing_file),
        cmocka_unit_test(test_directory),
        cmocka_unit_test(test_empty_file),
        cmocka_unit_test(test_too_few_rows),
        cmocka_unit_test(test_nul_byte),
        cmocka_unit_test(test_line_length),
        cmocka_unit_test(test_columns),
        cmocka_unit_test(test_bad_numbers),
        cmocka_unit_test(test_first_distance),
        cmocka_unit_test(test_distance_order_and_spacing),
        cmocka_unit_test(test_grade_range),
        cmocka_unit_test(test_row_limit),
        cmocka_unit_test(test_error_buffer_and_arguments),
        cmocka_unit_test(test_to_ppm),
        cmocka_unit_test(test_mutations_never_crash),
        cmocka_unit_test(test_regenerate_flat),
        cmocka_unit_test(test_regenerate_uphill),
        cmocka_unit_test(test_regenerate_hilly),
        cmocka_unit_test(test_roads_flat_and_uphill),
        cmocka_unit_test(test_road_hilly_shape),
    };
    return cmocka_run_group_tests(tests, make_dir, remove_dir);
}
