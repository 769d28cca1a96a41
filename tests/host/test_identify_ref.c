/* Host test: the firmware's identification (pfe_identify) against its
 * double-precision reference (sim_host/identify_ref) on the same samples,
 * and both against the truth of the double-precision chapter 3 model
 * (sim_host/ref_model) driven by id_drive: trucks of 12, 40 and 60 t, the
 * calibration's 40 t as the seed, speed noise 0.05 km/h at 1/256 km/h,
 * pitch noise 0.02 deg at 0.002 deg, fuel noise 2 % at LFE1's 0.05 L/h. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>

#include <cmocka.h>

#include "identify_ref.h"
#include "pfe_calib.h"
#include "pfe_fixed.h"
#include "pfe_identify.h"

#define assert_signed_range(v, lo, hi) check_range((double)(v), (lo), (hi), #v, __LINE__)
static void check_range(double v, double lo, double hi, const char *what, int line)
{
    if ((v < lo) || (v > hi)) {
        fail_msg("line %d: %s = %.4f is not within [%.4f, %.4f]", line, what, v, lo, hi);
    }
}

typedef struct {
    double mass_err_pct, ref_mass_err_pct, fuel_err_pct;
    double max_mass_diff_kg, max_aux_diff_w;
    bool converged, ref_converged;
} run_t;

/* 10 minutes of identification, then 5 minutes predicted with the
 * identified mass and aux power against the truth. */
static run_t run(unsigned mass_kg, unsigned power_max_w, double noise, uint64_t seed)
{
    pfe_vehicle_calib_t truck = pfe_default_vehicle;
    truck.mass_kg = mass_kg;
    truck.power_max_w = power_max_w;
    id_drive_t d;
    id_drive_init(&d, &truck, &pfe_default_env, 0.05 * noise, 0.02 * noise, 0.02 * noise, seed);
    pfe_identify_t id;
    identify_ref_t r;
    assert_int_equal(pfe_identify_init(&id, &pfe_default_vehicle, &pfe_default_env), PFE_OK);
    identify_ref_init(&r, &pfe_default_vehicle, &pfe_default_env);
    run_t out = {0};
    pfe_identify_sample_t s;
    for (unsigned k = 0U; k < 6000U; k++) {
        id_drive_advance(&d, &s);
        (void)pfe_identify_step(&id, &s);
        identify_ref_step(&r, &s);
        out.max_mass_diff_kg = fmax(out.max_mass_diff_kg, fabs(pfe_identify_mass_kg(&id) - r.mass));
        out.max_aux_diff_w = fmax(out.max_aux_diff_w, fabs(pfe_identify_aux_power_w(&id) - r.aux));
    }
    const double m = pfe_identify_mass_kg(&id);
    const double aux = pfe_identify_aux_power_w(&id);
    double truth = 0.0;
    double model = 0.0;
    for (unsigned k = 0U; k < 3000U; k++) {
        id_drive_advance(&d, &s);
        truth += d.fuel_rate * 0.1;
        model += id_drive_fuel_rate_with(&d, m, aux) * 0.1;
    }
    out.mass_err_pct = 100.0 * ((m / mass_kg) - 1.0);
    out.ref_mass_err_pct = 100.0 * ((r.mass / mass_kg) - 1.0);
    out.fuel_err_pct = 100.0 * ((model / truth) - 1.0);
    out.converged = pfe_identify_converged(&id);
    out.ref_converged = r.converged;
    printf("identify_ref %2u t noise x%.0f: mass %+.2f %% (double %+.2f %%), aux %.0f W, "
           "next 5 min fuel %+.2f %%; firmware - double at most %.1f kg, %.1f W; "
           "mass updates %u, windows %u\n",
           mass_kg / 1000U, noise, out.mass_err_pct, out.ref_mass_err_pct, aux, out.fuel_err_pct,
           out.max_mass_diff_kg, out.max_aux_diff_w, (unsigned)id.counters.mass_updates,
           (unsigned)id.counters.windows_used);
    /* A gate's decision at its threshold (|dx| against 1 W/kg, a residual
     * against 4 sigma) may fall the other way after rounding: the counts
     * agree within 3 %, the windows within 1 %. */
    assert_signed_range((double)id.counters.mass_updates - (double)r.mass_updates,
                        -0.03 * (double)r.mass_updates, 0.03 * (double)r.mass_updates);
    assert_signed_range((double)id.counters.windows_used - (double)r.windows_used,
                        -0.01 * (double)r.windows_used, 0.01 * (double)r.windows_used);
    return out;
}

static void check(const run_t *o)
{
    assert_signed_range(o->mass_err_pct, -15.0, 15.0);
    assert_signed_range(o->fuel_err_pct, -10.0, 10.0);
    /* The firmware's integers against the double reference: within 0.05 %
     * of the mass (20 kg at 40 t) and 100 W of aux power at every sample. */
    assert_signed_range(o->max_mass_diff_kg, 0.0, 0.0005 * 60000.0);
    assert_signed_range(o->max_aux_diff_w, 0.0, 100.0);
    assert_true(o->converged);
    assert_int_equal(o->converged, o->ref_converged);
}

static void test_12t(void **state)
{
    (void)state;
    const run_t o = run(12000U, 300000U, 1.0, 101U);
    check(&o);
}

static void test_40t(void **state)
{
    (void)state;
    const run_t o = run(40000U, 350000U, 1.0, 102U);
    check(&o);
}

static void test_60t(void **state)
{
    (void)state;
    const run_t o = run(60000U, 450000U, 1.0, 103U);
    check(&o);
}

/* Twice the sensor noise: the speed noise's bias (errors in the regressor)
 * grows with its square, and stays inside the bounds. */
static void test_60t_noisier(void **state)
{
    (void)state;
    const run_t o = run(60000U, 450000U, 2.0, 104U);
    check(&o);
}

/* No noise at all: the method itself, exact up to the gates. */
static void test_noise_free(void **state)
{
    (void)state;
    const unsigned masses[] = {12000U, 40000U, 60000U};
    for (unsigned k = 0U; k < 3U; k++) {
        const run_t o = run(masses[k], 450000U, 0.0, 105U + k);
        check(&o);
        assert_signed_range(o.mass_err_pct, -1.0, 1.0);
        assert_signed_range(o.fuel_err_pct, -0.5, 0.5);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_12t),
        cmocka_unit_test(test_40t),
        cmocka_unit_test(test_60t),
        cmocka_unit_test(test_60t_noisier),
        cmocka_unit_test(test_noise_free),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
