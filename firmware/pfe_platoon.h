/*
 * pfe_platoon.h - the platoon object model (thesis chapter 4).
 *
 * N trucks driven as one point mass. pfe_platoon_init() computes the
 * aggregates once from a per-vehicle configuration, so a step costs the same
 * as one truck whatever N is:
 *
 *   M                 eq. 4.3   sum of m_i (and M + sum mj_i for eq. 3.7)
 *   Pmax_platoon      eq. 4.4   min_i(Pmax_i / m_i) * M (traction likewise)
 *   formation drag    4.4, 5.1.4  the platoon keeps its formation (thesis
 *                     5.1.4): at its force limit it climbs no faster than the
 *                     truck with the most air drag per kilogram, so the
 *                     limit is lowered by c v^2 with
 *                     c = M max_i(k_i / m_i) - sum k_i >= 0 (k_i the drag
 *                     coefficient of position i with its phi_i). Exact for
 *                     trucks of one power-to-mass; with mixed trucks the
 *                     worst power and the worst drag are combined, which
 *                     errs on the slow side. c is 0 for one truck or
 *                     without drag reduction.
 *   Fb_max_platoon    eq. 4.5   sum of Fb_max_i (= N Fb_max for equal trucks)
 *   air drag          eq. 4.6   1/2 rho v^2 sum cw_i Af_i (1 - phi_i(d)/100)
 *   rolling           eq. 4.8   cr M g (cos alpha ~ 1; cr may differ per truck)
 *   grade             eq. 4.10  M g alpha_p (sin alpha ~ alpha ~ grade), one
 *                     grade for the platoon: trucks of a length that keep a
 *                     constant time headway meet every grade at the speed
 *                     the platoon met it, so summed over the platoon's
 *                     passage of a point the grade force is M g alpha there
 *                     (README, "The thesis's claims, checked")
 *   fuel              eq. 4.14  delta (P + sum Paux_i) / (eta_mean rho_d)
 *
 * The aggregate is stored as a pfe_vehicle_t so that the chapter 3 force and
 * fuel functions serve both models. The same init also builds each position's
 * own chapter 3 coefficients (with that position's phi_i), which the
 * estimator uses for per-truck fuel.
 *
 * Memory: sizeof(pfe_platoon_t) is about 64 * (PFE_MAX_VEHICLES + 1) bytes.
 */
#ifndef PFE_PLATOON_H
#define PFE_PLATOON_H

#include <stdint.h>

#include "pfe_calib.h"
#include "pfe_vehicle.h"

/* The largest formation drag c: N trucks' largest air_q32 (< 2^17 each),
 * 32 of them: 2^22. */
#define PFE_FORMATION_AIR_MAX_Q32 4194304U

typedef struct {
    uint32_t n_vehicles;                                /* 1 .. PFE_MAX_VEHICLES */
    uint32_t gap_mm;                                    /* d, the same between every pair (eq. 4.7) */
    const pfe_vehicle_calib_t *vehicle[PFE_MAX_VEHICLES]; /* position 0 = lead; entries may share */
    const pfe_env_calib_t *env;
    const pfe_drag_table_t *drag;
} pfe_platoon_config_t;

typedef struct {
    uint32_t n_vehicles;
    uint32_t gap_mm;
    uint32_t mass_kg;                            /* M */
    uint32_t gravity_um_s2;                      /* g */
    int64_t gravity_q32;                         /* g * 2^32 / 10^6, for g * grade */
    int32_t inv_mass_m;                          /* 10^6 * 2^30 / M (um/s^2 per N, * 2^30)
                                                  * = inv_mass_m * inv_mass_scale, |m| < 2^31
                                                  * (pfe_mantissa_i32()) */
    int32_t inv_mass_scale;                      /* 2^0 .. 2^10 */
    int32_t force_limit_q2;                      /* M * PFE_ACCEL_MAX_UM_S2, N * 2^2 */
    uint32_t formation_air_q32;                  /* c above, N per (mm/s)^2 * 2^32,
                                                  * <= PFE_FORMATION_AIR_MAX_Q32 */
    int64_t roll_force_q32;                      /* cr M g of the object model (eq. 4.8,
                                                  * cos alpha ~ 1), N * 2^32: object.roll_q32
                                                  * (< 2^31) times g (< 2^24), below 2^55;
                                                  * set once here, not in every step */
    uint32_t same_as_previous;                   /* bit i (1 .. n - 1): position i has
                                                  * position i - 1's air, masses, rolling,
                                                  * fuel and auxiliary coefficients, so its
                                                  * fuel rate is the same (the estimator
                                                  * computes it once) */
    pfe_vehicle_t object;                        /* the platoon as one point mass */
    pfe_vehicle_t position[PFE_MAX_VEHICLES];    /* each truck at its position */
} pfe_platoon_t;

/*
 * Fills a configuration of n identical vehicles with the defaults of
 * pfe_calib.h and the given gap. n is clamped to [1, PFE_MAX_VEHICLES].
 */
void pfe_platoon_config_uniform(pfe_platoon_config_t *cfg, uint32_t n_vehicles, uint32_t gap_mm,
                                const pfe_vehicle_calib_t *vehicle, const pfe_env_calib_t *env,
                                const pfe_drag_table_t *drag);

/*
 * Builds the aggregates. Returns PFE_OK, or PFE_EINVAL for a NULL argument,
 * n_vehicles outside [1, PFE_MAX_VEHICLES], a NULL vehicle entry, or any
 * calibration that fails its check. On error *pl is unspecified.
 * Uses 64-bit divisions: configuration time only.
 */
int pfe_platoon_init(pfe_platoon_t *pl, const pfe_platoon_config_t *cfg);

/*
 * pfe_platoon_init() in pieces, for a caller that spreads the work over its
 * ticks (about 600 Cortex-M4 instructions a position, 2,000 the rest):
 * begin checks cfg (n_vehicles, env, drag) and touches nothing; positions
 * builds the trucks first .. first + count - 1 (those below n_vehicles);
 * finish builds the aggregates from them. begin, positions over every
 * position in any order, then finish, all with the same cfg, give the same
 * *pl as pfe_platoon_init(); each returns PFE_OK or PFE_EINVAL as it would.
 */
int pfe_platoon_init_begin(const pfe_platoon_config_t *cfg);
int pfe_platoon_init_positions(pfe_platoon_t *pl, const pfe_platoon_config_t *cfg, uint32_t first,
                               uint32_t count);
int pfe_platoon_init_finish(pfe_platoon_t *pl, const pfe_platoon_config_t *cfg);

/* The object model's largest wheel force at a speed v (0 .. PFE_SPEED_MAX_MM_S)
 * with v2 = v * v at hand, for the platoon's object and formation drag c
 * (formation_air_q32, at most PFE_FORMATION_AIR_MAX_Q32): min(Pmax_platoon /
 * v, traction) - c v^2, rounded N, never below -brake_max. c <= 2^22 times
 * v2 < 2^33 stays below 2^55; with the rounding half added, the high word
 * is the product / 2^32. The result lies within [-Fb_max, traction_max],
 * both within +-2^26 (32 trucks of PFE_FORCE_MAX_N at most). Inline: the
 * simulation calls it in every step, with c held in its own state. */
static inline int32_t pfe_platoon_force_max_v2_n(const pfe_vehicle_t *obj, uint32_t formation_q32,
                                                 int32_t speed_mm_s, uint64_t v2)
{
    const uint64_t drag = (v2 * formation_q32) + 2147483648U;
    const int32_t f = pfe_wheel_force_max_n(obj->power_max_w, obj->traction_max_n, speed_mm_s) -
                      (int32_t)(uint32_t)(drag >> 32);
    const int32_t lo = -(int32_t)obj->brake_max_n;
    return (f < lo) ? lo : f;
}

/* The same for a speed alone, clamped to 0 .. PFE_SPEED_MAX_MM_S. */
int32_t pfe_platoon_force_max_n(const pfe_platoon_t *pl, int32_t speed_mm_s);

/* Small-angle gravity of the object model (eq. 4.8, 4.10): along = g * grade,
 * normal = g. grade_ppm is clamped to +-PFE_GRADE_MAX_PPM. */
void pfe_platoon_grade_accel(const pfe_platoon_t *pl, int32_t grade_ppm, pfe_grade_accel_t *out);

/*
 * Fw of the object model, eq. 3.7 with 4.6 to 4.10 (small-angle grade):
 * the same result as pfe_vehicle_fuel_force_n() for the object with the
 * gravity split of pfe_platoon_grade_accel() (along_um_s2 from there), for
 * a caller that holds v2 = v * v, v in [0, PFE_SPEED_MAX_MM_S], and an
 * acceleration already within +-PFE_ACCEL_MAX_UM_S2. Its rolling part is
 * roll_force_q32, made at configuration time. One sum below 2^60
 * (pfe_vehicle.c), rounded once: its rounded high word is the force.
 * Inline: the estimator calls it every 10 ms.
 */
static inline int32_t pfe_platoon_fuel_force_n(const pfe_platoon_t *pl, uint64_t v2,
                                               int32_t accel_um_s2, int32_t along_um_s2)
{
    const pfe_vehicle_t *obj = &pl->object;
    /* the object's air_q32, a sum of 32 positions' below 2^17, is below
     * 2^22: an unsigned 32 x 64 bit product with v2 < 2^33 */
    const uint64_t air = (uint64_t)(uint32_t)obj->air_q32 * v2;
    const int64_t sum = (obj->mass_fuel_q32 * accel_um_s2) + pl->roll_force_q32 +
                        (obj->mass_q32 * along_um_s2) + (int64_t)air;
    return (int32_t)pfe_rshift_round(sum, 32U);
}

/* Platoon acceleration for a net force in N * 2^2, eq. 4.3: a = F / M in
 * um/s^2, rounded; the force is first clamped to M * PFE_ACCEL_MAX_UM_S2, so
 * the result lies within +-PFE_ACCEL_MAX_UM_S2. 1/M is held in Q30 as a
 * 32-bit mantissa and a power of two: relative resolution 3e-6 for the
 * largest platoon (3200 t), 1e-9 for one 40 t truck. One 32 x 32 -> 64 bit
 * multiply and fixed shifts: this runs in every simulation step. */
int32_t pfe_platoon_accel_um_s2(const pfe_platoon_t *pl, int32_t net_force_q2);

#endif /* PFE_PLATOON_H */
