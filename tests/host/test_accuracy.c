/*
 * Host tests: the fixed-point model against the double-precision reference
 * on the thesis's three roads (sim_host/data/roads), N = 1 and N = 5, 90 km/h.
 *
 *   object model over 12 km: fuel within 0.1 %, speed rms within 0.05 km/h
 *   estimator on the drive as the bus carries it: fuel used within 0.1 %
 *
 * Usage: test_accuracy ROADS_DIR (or PFE_ROADS_DIR in the environment).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "../test_assert.h"

#include "pfe_calib.h"
#include "pfe_estimator.h"
#include "pfe_fixed.h"
#include "pfe_platoon.h"
#include "ref/drive_trace.h"
#include "ref/ref_model.h"
#include "lib/road_csv.h"
#include "ref/sim_compare.h"

static const char *g_roads_dir;

static road_ppm_t load_road(const char *name)
{
    char path[512];
    char err[512];
    snprintf(path, sizeof path, "%s/%s.csv", g_roads_dir, name);
    road_ppm_t r;
    if (road_ppm_load(path, &r, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    return r;
}

static void check_object_model(const char *name, uint32_t n)
{
    road_ppm_t road = load_road(name);
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, n, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    const sim_compare_args_t args = {road.grade_ppm, road.n_samples, road.spacing_mm, &cfg, &pfe_default_cruise,
                                     25000, 10000U, NULL};
    sim_compare_t r;
    char err[256];
    assert_int_equal(sim_compare_run(&args, &r, err, sizeof err), 0);
    print_message("%-6s N=%u  fuel %.4f L (ref %.4f L) error %+.5f %%, speed rms %.5f km/h\n", name,
                  n, r.fixed.fuel_l, r.ref.fuel_l, 100.0 * r.fuel_rel_err, r.speed_rms_kmh);
    road_ppm_free(&road);
    assert_int_equal(r.steps, 1200);
    ASSERT_GT(r.ref.fuel_l, 1.0);
    ASSERT_LE(fabs(r.fuel_rel_err), 0.001);
    ASSERT_LE(r.speed_rms_kmh, 0.05);
}

static void check_estimator(const char *name, uint32_t n)
{
    road_ppm_t road = load_road(name);
    pfe_platoon_config_t cfg;
    pfe_platoon_config_uniform(&cfg, n, 10000U, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    drive_trace_t drive;
    char err[256];
    assert_int_equal(drive_trace_make(road.grade_ppm, road.n_samples, road.spacing_mm, &cfg, 25000, &drive, err,
                                      sizeof err), 0);
    static pfe_platoon_t pl;
    static pfe_estimator_t est;
    static ref_platoon_t rpl;
    static ref_estimator_t ref;
    assert_int_equal(pfe_platoon_init(&pl, &cfg), PFE_OK);
    assert_int_equal(pfe_estimator_init(&est, &pl), PFE_OK);
    assert_int_equal(ref_platoon_init(&rpl, &cfg), 0);
    ref_estimator_init(&ref, &rpl);
    double worst_rate = 0.0;
    for (size_t k = 0U; k < drive.n_ticks; k++) {
        const drive_tick_t *t = &drive.ticks[k];
        const pfe_est_input_t in = {t->speed_mm_s, true, t->speed_fresh, t->grade_ppm, true};
        const pfe_est_output_t *out = pfe_estimator_step(&est, &in);
        ref_estimator_step(&ref, t->speed_mm_s / 1000.0, true, t->speed_fresh, t->grade_ppm / 1e6,
                           true);
        assert_int_equal((out->flags & PFE_EST_VALID) != 0U, ref.valid);
        if (ref.fuel_rate > 1e-3) { /* 1 mL/s: away from fuel cut */
            const double e = fabs((out->fuel_rate_nl_s / 1e9) - ref.fuel_rate) / ref.fuel_rate;
            worst_rate = fmax(worst_rate, e);
        }
    }
    const double fixed_l = (double)pfe_estimator_fuel_used_ul(&est, PFE_EST_PLATOON) / 1e6;
    const double err_total = (fixed_l - ref.fuel_used) / ref.fuel_used;
    double worst_pos = 0.0;
    for (uint32_t i = 0U; i < n; i++) {
        const double f = (double)pfe_estimator_fuel_used_ul(&est, (int32_t)i) / 1e6;
        worst_pos = fmax(worst_pos, fabs(f - ref.pos_fuel_used[i]) / ref.pos_fuel_used[i]);
    }
    print_message("%-6s N=%u  estimator: %zu ticks, fuel %.4f L (ref %.4f L) error %+.5f %%, "
                  "worst position %.5f %%, worst rate %.4f %%\n",
                  name, n, drive.n_ticks, fixed_l, ref.fuel_used, 100.0 * err_total,
                  100.0 * worst_pos, 100.0 * worst_rate);
    drive_trace_free(&drive);
    road_ppm_free(&road);
    ASSERT_LE(fabs(err_total), 0.001);
    ASSERT_LE(worst_pos, 0.001);
    ASSERT_LE(worst_rate, 0.01);
}

static void test_flat(void **state)
{
    (void)state;
    check_object_model("flat", 1U);
    check_object_model("flat", 5U);
    check_estimator("flat", 5U);
}

static void test_uphill(void **state)
{
    (void)state;
    check_object_model("uphill", 1U);
    check_object_model("uphill", 5U);
    check_estimator("uphill", 5U);
}

static void test_hilly(void **state)
{
    (void)state;
    check_object_model("hilly", 1U);
    check_object_model("hilly", 5U);
    check_estimator("hilly", 1U);
    check_estimator("hilly", 5U);
}

int main(int argc, char **argv)
{
    g_roads_dir = (argc > 1) ? argv[1] : getenv("PFE_ROADS_DIR");
    if (g_roads_dir == NULL) {
        fprintf(stderr, "usage: %s ROADS_DIR (or set PFE_ROADS_DIR)\n", argv[0]);
        return 2;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_flat),
        cmocka_unit_test(test_uphill),
        cmocka_unit_test(test_hilly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
