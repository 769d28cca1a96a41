/*
 * test_truck_cal - the truck calibration file (sim_host/lib/truck_cal.h): every
 * field with its units, the module options, the per-position sections, and
 * every error named with its line and range.
 *
 *   test_truck_cal DIR   (DIR: sim_host/data/trucks, the bundled calibrations)
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "lib/truck_cal.h"

static const char *g_dir = "sim_host/data/trucks";

static void assert_error(const char *text, const char *expect)
{
    truck_cal_t cal;
    char err[TRUCK_CAL_ERR_MAX];
    memset(err, 0, sizeof err);
    const int rc = truck_cal_parse(text, "t.cal", &cal, err, sizeof err);
    if ((rc != -1) || (strstr(err, expect) == NULL)) {
        print_error("text:\n%s\nexpected an error with '%s', got rc %d, '%s'\n", text, expect, rc,
                    err);
        fail();
    }
}

static void test_every_field_and_unit(void **state)
{
    (void)state;
    truck_cal_t cal;
    memset(&cal, 0xA5, sizeof cal);
    char err[TRUCK_CAL_ERR_MAX] = "";
    const char *text = "# a 12 t truck\n"
                       "mass            12 t\n"
                       "rot_mass        400 kg\n"
                       "drag_area       5.6 m2        # cw * Af\n"
                       "roll_coef       0.006\n"
                       "power_max       350 kW\n"
                       "traction_max    80.5 kN\n"
                       "brake_max       45000 N\n"
                       "aux_power       4.25 kW\n"
                       "eta             42 %\n"
                       "\n";
    assert_int_equal(truck_cal_parse(text, "t.cal", &cal, err, sizeof err), 0);
    assert_string_equal(err, "");
    assert_int_equal(cal.own.mass_kg, 12000);
    assert_int_equal(cal.own.rot_mass_kg, 400);
    assert_int_equal(cal.own.drag_area_mm2, 5600000);
    assert_int_equal(cal.own.roll_coef_ppm, 6000);
    assert_int_equal(cal.own.power_max_w, 350000);
    assert_int_equal(cal.own.traction_max_n, 80500);
    assert_int_equal(cal.own.brake_max_n, 45000);
    assert_int_equal(cal.own.power_aux_w, 4250);
    assert_int_equal(cal.own.eta_ppm, 420000);
    assert_true(cal.own_set);
    for (unsigned k = 0U; k < PFE_MAX_VEHICLES; k++) {
        assert_false(cal.at_set[k]);
    }
    for (unsigned k = 0U; k < (unsigned)PFE_IN_COUNT; k++) {
        assert_false(cal.source_fixed[k]);
    }
    assert_false(cal.flat_grade_forbidden);
    assert_int_equal(cal.j1939_fuel, PFE_ECU_J1939_FUEL_AUTO);
}

static void test_other_units(void **state)
{
    (void)state;
    truck_cal_t cal;
    char err[TRUCK_CAL_ERR_MAX] = "";
    assert_int_equal(truck_cal_parse("drag_area 5600000 mm2\nroll_coef 6000 ppm\neta 0.4\n"
                                     "power_max 250000 W\nmass 40000 kg\nrot_mass 1.2 t\n",
                                     "t.cal", &cal, err, sizeof err), 0);
    assert_int_equal(cal.own.drag_area_mm2, 5600000);
    assert_int_equal(cal.own.roll_coef_ppm, 6000);
    assert_int_equal(cal.own.eta_ppm, 400000);
    assert_int_equal(cal.own.power_max_w, 250000);
    assert_int_equal(cal.own.rot_mass_kg, 1200);
}

static void test_defaults_kept(void **state)
{
    (void)state;
    truck_cal_t cal;
    char err[TRUCK_CAL_ERR_MAX] = "";
    assert_int_equal(truck_cal_parse("mass 60 t\n", "t.cal", &cal, err, sizeof err), 0);
    assert_int_equal(cal.own.mass_kg, 60000);
    /* the rest: pfe_default_vehicle (firmware/pfe_calib.c) */
    assert_int_equal(cal.own.drag_area_mm2, 6000000);
    assert_int_equal(cal.own.power_max_w, 250000);
    assert_int_equal(cal.own.eta_ppm, 400000);
    assert_int_equal(truck_cal_parse("", "t.cal", &cal, err, sizeof err), 0);
    assert_false(cal.own_set);
    assert_memory_equal(&cal.own, &pfe_default_vehicle, sizeof cal.own);
}

static void test_module_options(void **state)
{
    (void)state;
    truck_cal_t cal;
    char err[TRUCK_CAL_ERR_MAX] = "";
    assert_int_equal(truck_cal_parse("speed_source 0x00\ngrade_source 42\naltitude_source 0x1C\n"
                                     "mass_source auto\nengine_fuel_source 0\n"
                                     "flat_grade forbid\nj1939_fuel never\n",
                                     "t.cal", &cal, err, sizeof err), 0);
    assert_true(cal.source_fixed[PFE_IN_SPEED]);
    assert_int_equal(cal.source[PFE_IN_SPEED], 0x00);
    assert_true(cal.source_fixed[PFE_IN_GRADE]);
    assert_int_equal(cal.source[PFE_IN_GRADE], 42);
    assert_int_equal(cal.source[PFE_IN_ALTITUDE], 0x1C);
    assert_false(cal.source_fixed[PFE_IN_MASS]);
    assert_true(cal.source_fixed[PFE_IN_ENGINE_FUEL]);
    assert_true(cal.flat_grade_forbidden);
    assert_int_equal(cal.j1939_fuel, PFE_ECU_J1939_FUEL_NEVER);
    assert_int_equal(truck_cal_parse("j1939_fuel always\nflat_grade allow\n", "t.cal", &cal, err,
                                     sizeof err), 0);
    assert_int_equal(cal.j1939_fuel, PFE_ECU_J1939_FUEL_ALWAYS);
    assert_false(cal.flat_grade_forbidden);

    pfe_ecu_config_t cfg;
    memset(&cfg, 0xA5, sizeof cfg);
    assert_int_equal(truck_cal_parse("mass 12 t\nspeed_source 0x00\nflat_grade forbid\n"
                                     "[position 2]\nmass 30 t\n", "t.cal", &cal, err, sizeof err), 0);
    truck_cal_apply(&cal, &cfg);
    assert_ptr_equal(cfg.own_vehicle, &cal.own);
    assert_ptr_equal(cfg.vehicle_at[2], &cal.at[2]);
    assert_null(cfg.vehicle_at[0]);
    assert_null(cfg.vehicle_at[PFE_MAX_VEHICLES - 1U]);
    assert_true(cfg.input_source_fixed[PFE_IN_SPEED]);
    assert_int_equal(cfg.input_source[PFE_IN_SPEED], 0);
    assert_false(cfg.input_source_fixed[PFE_IN_GRADE]);
    assert_true(cfg.flat_grade_forbidden);
    assert_int_equal(cfg.j1939_fuel, PFE_ECU_J1939_FUEL_AUTO);
}

static void test_sections(void **state)
{
    (void)state;
    truck_cal_t cal;
    char err[TRUCK_CAL_ERR_MAX] = "";
    assert_int_equal(truck_cal_parse("mass 12000 kg\n[position 0]    # the lead\nmass 40000 kg\n"
                                     "  [ position 31 ]\nmass 8 t\ndrag_area 4 m2\n",
                                     "t.cal", &cal, err, sizeof err), 0);
    assert_int_equal(cal.own.mass_kg, 12000);
    assert_true(cal.at_set[0]);
    assert_int_equal(cal.at[0].mass_kg, 40000);
    assert_int_equal(cal.at[0].drag_area_mm2, 6000000);
    assert_true(cal.at_set[31]);
    assert_int_equal(cal.at[31].mass_kg, 8000);
    assert_int_equal(cal.at[31].drag_area_mm2, 4000000);
    assert_false(cal.at_set[1]);
    assert_ptr_equal(truck_cal_vehicle(&cal, 1U, 1U), &cal.own);
    assert_ptr_equal(truck_cal_vehicle(&cal, 0U, 1U), &cal.at[0]);
    assert_ptr_equal(truck_cal_vehicle(&cal, 2U, 1U), &pfe_default_vehicle);
}

static void test_errors(void **state)
{
    (void)state;
    assert_error("mass 12000 kg\nmasss 3 t\n", "t.cal:2: unknown key 'masss'");
    assert_error("mass 12000 lb\n", "t.cal:1: mass: unknown unit 'lb' (kg, t)");
    assert_error("mass 12000\n", "t.cal:1: mass 12000: a unit is needed (kg, t)");
    assert_error("eta 0.4 kg\n", "t.cal:1: eta: unknown unit 'kg' (no unit, %)");
    assert_error("mass 200 t\n", "t.cal:1: mass: 200 t is out of range 1000 .. 100000 kg");
    assert_error("mass 999 kg\n", "out of range 1000 .. 100000 kg");
    assert_error("eta 0.04\n", "t.cal:1: eta: 0.04 is out of range 0.05 .. 1");
    assert_error("drag_area 20.000001 m2\n", "out of range 0 .. 20 m2");
    assert_error("power_max 0 kW\n", "power_max: 0 kW is out of range 1 W .. 2000 kW");
    assert_error("power_max 99999999999999999 W\n", "out of range");
    assert_error("mass 12000.5 kg\n", "t.cal:1: mass: 12000.5 kg is finer than");
    assert_error("mass -12 t\n", "mass: '-12' is not a number");
    assert_error("mass 1e4 kg\n", "mass: '1e4' is not a number");
    assert_error("mass 12. t\n", "is not a number");
    assert_error("mass 12 t\nmass 13 t\n", "t.cal:2: mass given twice");
    assert_error("mass 12 t extra\n", "t.cal:1: mass: expected 'key value [unit]'");
    assert_error("mass\n", "t.cal:1: mass: a value is needed");
    assert_error("[position 0]\nmass 10 t\n[position 0]\n", "t.cal:3: [position 0] given twice");
    assert_error("[position 32]\n", "t.cal:1: [position 32]: N must be 0 .. 31");
    assert_error("[truck 1]\n", "t.cal:1: section header must be '[position N]'");
    assert_error("[position 1\n", "section header");
    assert_error("[position 1] mass\n", "text after the section header");
    assert_error("[position 1]\nspeed_source 0\n", "t.cal:2: speed_source: a module option");
    assert_error("speed_source 254\n", "speed_source: '254' is not a source address 0 .. 253");
    assert_error("speed_source 0x00 kg\n", "takes no unit");
    assert_error("flat_grade maybe\n", "flat_grade: 'maybe' is neither allow nor forbid");
    assert_error("j1939_fuel sometimes\n", "j1939_fuel: 'sometimes' is none of auto, always, never");
    /* pfe_calib_check_vehicle() on the finished section, at its first line */
    assert_error("mass 2 t\nrot_mass 3 t\n[position 1]\n",
                 "t.cal:1: the own truck: rot_mass 3000 kg exceeds mass 2000 kg");
    assert_error("[position 4]\nmass 1 t\nrot_mass 1.5 t\n",
                 "t.cal:1: [position 4]: rot_mass 1500 kg exceeds mass 1000 kg");
}

static void test_files(void **state)
{
    (void)state;
    truck_cal_t cal;
    char err[TRUCK_CAL_ERR_MAX] = "";
    char path[512];
    snprintf(path, sizeof path, "%s/truck12t.cal", g_dir);
    assert_int_equal(truck_cal_load(path, &cal, err, sizeof err), 0);
    assert_int_equal(cal.own.mass_kg, 12000);
    snprintf(path, sizeof path, "%s/truck60t.cal", g_dir);
    assert_int_equal(truck_cal_load(path, &cal, err, sizeof err), 0);
    assert_int_equal(cal.own.mass_kg, 60000);
    snprintf(path, sizeof path, "%s/no-such.cal", g_dir);
    assert_int_equal(truck_cal_load(path, &cal, err, sizeof err), -1);
    if (strstr(err, "no-such.cal: cannot read: No such file") == NULL) {
        print_error("got '%s'\n", err);
        fail();
    }
}

static void test_take_arg(void **state)
{
    (void)state;
    truck_cal_t cal;
    char err[TRUCK_CAL_ERR_MAX] = "";
    char path[512];
    snprintf(path, sizeof path, "%s/truck12t.cal", g_dir);
    char *argv[] = {"tool", "--log", "x", "--calib", path, "--record", "y", NULL};
    int argc = 7;
    bool found = false;
    assert_int_equal(truck_cal_take_arg(&argc, argv, &cal, &found, err, sizeof err), 0);
    assert_true(found);
    assert_int_equal(argc, 5);
    assert_string_equal(argv[3], "--record");
    assert_string_equal(argv[4], "y");
    assert_null(argv[5]);
    assert_int_equal(cal.own.mass_kg, 12000);
    char *argv2[] = {"tool", "--calib", NULL};
    argc = 2;
    assert_int_equal(truck_cal_take_arg(&argc, argv2, &cal, &found, err, sizeof err), -1);
    assert_string_equal(err, "--calib needs a FILE");
    char *argv3[] = {"tool", "--calib", path, "--calib", path, NULL};
    argc = 5;
    assert_int_equal(truck_cal_take_arg(&argc, argv3, &cal, &found, err, sizeof err), -1);
    assert_string_equal(err, "--calib given twice");
    char *argv4[] = {"tool", "--log", "x", NULL};
    argc = 3;
    assert_int_equal(truck_cal_take_arg(&argc, argv4, &cal, &found, err, sizeof err), 0);
    assert_false(found);
    assert_int_equal(argc, 3);
    assert_memory_equal(&cal.own, &pfe_default_vehicle, sizeof cal.own);
}

int main(int argc, char **argv)
{
    if (argc > 1) {
        g_dir = argv[1];
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_field_and_unit),
        cmocka_unit_test(test_other_units),
        cmocka_unit_test(test_defaults_kept),
        cmocka_unit_test(test_module_options),
        cmocka_unit_test(test_sections),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_files),
        cmocka_unit_test(test_take_arg),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
