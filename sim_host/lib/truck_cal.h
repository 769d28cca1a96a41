/*
 * truck_cal.h - the truck a module runs on, from a small text file with
 * units: the vehicle calibration (firmware/pfe_calib.h) and the module
 * options that belong with the truck (firmware/pfe_ecu.h), for every host
 * tool that runs the model (--calib FILE) and for the generator of the
 * Cortex-M4 image's calibration (sim_host/tools/cal2c.c).
 *
 *   # truck.cal: a 12 t rigid truck
 *   mass            12000 kg
 *   power_max       350 kW
 *   eta             0.42
 *   drag_area       5.6 m2        # cw * Af
 *   roll_coef       0.006
 *   aux_power       4 kW
 *   speed_source    0x00          # CCVS1 from the engine only
 *   flat_grade      allow
 *   j1939_fuel      auto
 *   [position 0]                  # another truck of the platoon, the lead
 *   mass            40000 kg
 *
 * One "key value [unit]" per line; '#' starts a comment; blank lines are
 * skipped. Keys before the first section describe the truck the module runs
 * on (pfe_ecu_config_t.own_vehicle); a "[position N]" section (N = 0 ..
 * PFE_MAX_VEHICLES - 1, 0 the lead) describes the truck at that platoon
 * position (vehicle_at[N]) and may hold vehicle keys only. A vehicle key not
 * given keeps the default calibration's value (pfe_default_vehicle); a truck
 * without a section is the default calibration.
 *
 * Vehicle keys (pfe_vehicle_calib_t field, units accepted, range):
 *   mass          mass_kg          kg, t        1 .. 100 t (PFE_MASS_*_KG)
 *   rot_mass      rot_mass_kg      kg, t        0 .. mass
 *   drag_area     drag_area_mm2    m2, mm2      0 .. 20 m2 (PFE_DRAG_AREA_MAX_MM2)
 *   roll_coef     roll_coef_ppm    (none), ppm  0 .. 0.1
 *   power_max     power_max_w      W, kW        1 W .. 2000 kW (PFE_POWER_MAX_W)
 *   traction_max  traction_max_n   N, kN        1 N .. 1000 kN (PFE_FORCE_MAX_N)
 *   brake_max     brake_max_n      N, kN        0 .. 1000 kN (PFE_FORCE_MAX_N)
 *   aux_power     power_aux_w      W, kW        0 .. 100 kW
 *   eta           eta_ppm          (none), %    0.05 .. 1
 * (the ranges of pfe_calib_check_vehicle(), which also checks each truck
 * once its section is read). Numbers are decimal, with a fraction no finer
 * than the field's unit ("5.6 m2" is 5600000 mm2; "12000.5 kg" is refused).
 * Module keys (own truck only):
 *   speed_source, grade_source, altitude_source, mass_source,
 *   engine_fuel_source   SA 0 .. 253 (decimal or 0x hex), or "auto": the
 *                        sender of CCVS1, SSI, VDS, CVW, the engine's LFE1
 *                        (pfe_ecu_config_t.input_source[]); auto lets the
 *                        module choose (firmware/pfe_input.h)
 *   flat_grade           allow | forbid (flat_grade_forbidden)
 *   j1939_fuel           auto | always | never (pfe_ecu_j1939_fuel_t)
 * Unknown keys, missing or unknown units, values out of range, a key given
 * twice in one section, a section given twice, and a file that cannot be
 * read are errors: truck_cal_load() names the file, the line, and the
 * allowed range and units.
 */
#ifndef TRUCK_CAL_H
#define TRUCK_CAL_H

#include <stdbool.h>
#include <stdint.h>

#include "firmware/pfe_calib.h"
#include "firmware/pfe_ecu.h"

typedef struct {
    pfe_vehicle_calib_t own;
    bool own_set;                              /* some vehicle key was given for the own truck */
    pfe_vehicle_calib_t at[PFE_MAX_VEHICLES];
    bool at_set[PFE_MAX_VEHICLES];             /* a [position N] section was given */
    bool source_fixed[PFE_IN_COUNT];
    uint8_t source[PFE_IN_COUNT];
    bool flat_grade_forbidden;
    pfe_ecu_j1939_fuel_t j1939_fuel;
} truck_cal_t;

#define TRUCK_CAL_ERR_MAX 320U   /* bytes of an error message, NUL included */

/* The default calibration, every option at its default. */
void truck_cal_default(truck_cal_t *cal);

/* Reads path into *cal (truck_cal_default() first). Returns 0, or -1 with
 * one line of English in err ("FILE:LINE: ..."; at most cap bytes). */
int truck_cal_load(const char *path, truck_cal_t *cal, char *err, uint32_t cap);

/* The same from text in memory, name standing for the file in messages. */
int truck_cal_parse(const char *text, const char *name, truck_cal_t *cal, char *err,
                    uint32_t cap);

/* Points cfg's own_vehicle and vehicle_at[] into *cal (which must outlive
 * cfg) and sets the module options. */
void truck_cal_apply(const truck_cal_t *cal, pfe_ecu_config_t *cfg);

/* The calibration of platoon position k for a simulation in which the own
 * truck is at own_position: the own truck's, a section's, or the default. */
const pfe_vehicle_calib_t *truck_cal_vehicle(const truck_cal_t *cal, uint32_t k,
                                             uint32_t own_position);

/*
 * Host tools: removes "--calib FILE" from argv (argc updated, order kept)
 * and loads FILE into *cal; without the option, *cal is the default.
 * Returns 0 (found is set to whether it was given), or -1 with a message in
 * err (a missing FILE argument, a second --calib, or truck_cal_load()'s).
 */
int truck_cal_take_arg(int *argc, char **argv, truck_cal_t *cal, bool *found, char *err,
                       uint32_t cap);

#endif /* TRUCK_CAL_H */
