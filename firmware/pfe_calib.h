/*
 * pfe_calib.h - calibration of the platoon fuel model.
 *
 * A calibration is a set of const structs owned by the integrator: one per
 * vehicle (chapter 3 parameters of the thesis), the environment (air density,
 * gravity, diesel energy density), the air-drag reduction table phi_i(d)
 * (eq. 3.4) and the cruise controller. The defaults are those of
 * docs/model.md, "The default calibration" (a 40 t tractor-semitrailer,
 * each value with its source); several are estimates
 * that a user replaces with measured values.
 *
 * pfe_calib_check_*() validate ranges before a model is built from a
 * calibration; the ranges are the ones inside which the integer arithmetic of
 * the model is proven not to overflow (see each model's header).
 */
#ifndef PFE_CALIB_H
#define PFE_CALIB_H

#include <stdint.h>

/* Largest platoon the module handles; sizes every per-position array. */
#define PFE_MAX_VEHICLES 32U

/* Per-vehicle limits accepted by pfe_calib_check_vehicle(). */
#define PFE_MASS_MIN_KG 1000U
#define PFE_MASS_MAX_KG 100000U
#define PFE_POWER_MAX_W 2000000U        /* wheel power of one vehicle */
#define PFE_FORCE_MAX_N 1000000U        /* brake or traction force of one vehicle */
#define PFE_DRAG_AREA_MAX_MM2 20000000U /* cw * Af, 20 m^2 */

/* Speed range of the model: J1939 SPN 84 ends at 250.996 km/h. */
#define PFE_SPEED_MAX_MM_S 70000
/* Road grade range of the model, parts per million (500000 = 50 %). */
#define PFE_GRADE_MAX_PPM 500000

/* One vehicle (thesis chapter 3; defaults in docs/model.md). */
typedef struct {
    uint32_t mass_kg;           /* m */
    uint32_t rot_mass_kg;       /* mj, equivalent mass of rotating parts (eq. 3.7) */
    uint32_t drag_area_mm2;     /* cw * Af (eq. 3.4) */
    uint32_t roll_coef_ppm;     /* cr, rolling resistance coefficient (eq. 3.5) */
    uint32_t power_max_w;       /* Pmax at the wheels: Fw <= Pmax / v */
    uint32_t traction_max_n;    /* Fw <= this at any speed: the limit of Pmax / v as v -> 0 */
    uint32_t brake_max_n;       /* Fb_max: Fw >= -Fb_max */
    uint32_t power_aux_w;       /* Paux (eq. 3.11) */
    uint32_t eta_ppm;           /* eta_eng, mean combustion efficiency (eq. 3.11) */
} pfe_vehicle_calib_t;

/* Surroundings shared by the platoon. */
typedef struct {
    uint32_t air_density_g_m3;  /* rho_air */
    uint32_t gravity_um_s2;     /* g */
    uint32_t fuel_energy_j_ml;  /* rho_d, energy density of the fuel per mL (= J/cm^3) */
} pfe_env_calib_t;

/*
 * Air-drag reduction phi_i(d) in 0.01 % (eq. 3.4), linear between the
 * points, held constant outside them. Row 0 is the lead vehicle (d = gap to
 * its follower), row 1 the second, row 2 the third and every later position.
 */
#define PFE_DRAG_POINTS 11U
#define PFE_DRAG_ROWS 3U
typedef struct {
    uint32_t gap_mm[PFE_DRAG_POINTS];                    /* strictly increasing */
    uint16_t reduction_bp[PFE_DRAG_ROWS][PFE_DRAG_POINTS]; /* 0 .. 10000 */
} pfe_drag_table_t;

/*
 * Cruise controller gains, per unit mass so that one tuning fits any
 * platoon: wheel force = M * (kp * e + ki * integral(e dt)), e = set speed -
 * speed. Defaults give a critically damped speed loop (time constant about
 * 3 s), chosen for this model; the thesis does not publish its gains.
 */
typedef struct {
    uint32_t kp_milli_per_s;    /* kp in 1/s, times 1000 */
    uint32_t ki_milli_per_s2;   /* ki in 1/s^2, times 1000 */
} pfe_cruise_calib_t;

extern const pfe_vehicle_calib_t pfe_default_vehicle;
extern const pfe_env_calib_t pfe_default_env;
extern const pfe_drag_table_t pfe_default_drag;
extern const pfe_drag_table_t pfe_no_drag_reduction;
extern const pfe_cruise_calib_t pfe_default_cruise;

/* Each returns PFE_OK or PFE_EINVAL. NULL is invalid. */
int pfe_calib_check_vehicle(const pfe_vehicle_calib_t *v);
int pfe_calib_check_env(const pfe_env_calib_t *env);
int pfe_calib_check_drag(const pfe_drag_table_t *drag);
int pfe_calib_check_cruise(const pfe_cruise_calib_t *cruise);

/*
 * phi_i(d) in 0.01 % for position (0 = lead) at gap_mm, by linear
 * interpolation in the table (eq. 3.4); positions past the third use the
 * third's row. n_vehicles == 1 gives 0: a lone truck has no slipstream.
 * Rounds to nearest. The table must have passed pfe_calib_check_drag().
 */
uint32_t pfe_drag_reduction_bp(const pfe_drag_table_t *drag, uint32_t position,
                               uint32_t n_vehicles, uint32_t gap_mm);

#endif /* PFE_CALIB_H */
