/*
 * pfe_identify.h - the truck's mass and auxiliary power identified from the
 * engine's own measured fuel rate (LFE1, SPN 183).
 *
 * What is identifiable. The chapter 3 fuel model (thesis eq. 3.2 to 3.11,
 * exact trigonometry as pfe_vehicle.h) while the engine is fuelling
 * (delta = 1, eq. 3.9):
 *
 *   eta rho_d fc = Fw v + Paux                                      (3.8, 3.11)
 *   Fw = (m + mj) a + k v^2 + cr m g cos(alpha) + m g sin(alpha)    (3.4 to 3.7)
 *
 * with k = 1/2 rho cw Af (1 - phi/100). Gathering the terms that multiply m:
 *
 *   y = m x + Paux                                                  (1)
 *   x = v (a + g (cr cos(alpha) + sin(alpha)))       specific power, W/kg
 *   y = eta rho_d fc - k v^3 - mj a v                power left, W
 *
 * Linear in (m, Paux), with x and y computed from measured speed, grade and
 * fuel rate and the calibration's eta, rho_d, k, cr, mj. Every term of (3.11)
 * is divided by eta, so eta cannot be told apart from a common scale of m,
 * k and Paux; nor can k be told from Paux at one speed. The module
 * therefore identifies m and Paux and takes eta, k, cr and mj from the
 * calibration (docs/identification.md: what a wrong one does).
 *
 * The method, chosen for noise and for integers:
 *
 * 1. Windows instead of derivatives. (1) is integrated over a window of
 *    PFE_ID_WINDOW_INTERVALS sample intervals (2 s at LFE1's 100 ms) and
 *    divided by its duration T. The integral of v a dt is the change of
 *    v^2 / 2 between the window's first and last speed: no acceleration is
 *    differentiated from 1/256 km/h speed samples (the noise of a 100 ms
 *    difference is 0.2 m/s^2 for 0.05 km/h of speed noise). The other
 *    integrals are trapezoids over the samples.
 *
 * 2. Aux power drops out of the mass regression. x and y of each accepted
 *    window go through the same exponential mean (weight 2^-PFE_ID_MEAN_SHIFT
 *    per window); (1) holds for the means too, so dx = x - mean(x) and
 *    dy = y - mean(y) satisfy dy = m dx + noise whatever Paux is, as long as
 *    Paux changes slowly against the means' memory (16 windows, 32 s).
 *
 * 3. Mass by scalar recursive least squares with forgetting, in information
 *    form: Sxx <- lambda Sxx + dx^2, Sxy <- lambda Sxy + dx dy, lambda =
 *    1 - 2^-PFE_ID_MASS_SHIFT, and
 *        m = (Sxy + I0 m0) / (Sxx + I0)
 *    with a prior of information I0 = PFE_ID_PRIOR_INFO around the seed m0.
 *    The scalar "covariance" sigma^2 / (Sxx + I0) is positive by
 *    construction (Sxx is a sum of squares, I0 > 0); sums are bounded by the
 *    gates below (scaling), so they cannot overflow; a sum found outside
 *    its bound (corrupted state) resets the information to the prior.
 *    Only windows with |dx| >= PFE_ID_EXCITE_MW_KG update the mass (enough
 *    excitation, from acceleration or grade changes). Once the mass has
 *    PFE_ID_OUTLIER_AFTER updates, a window whose residual e = dy - m dx
 *    exceeds 4 max(sigma, PFE_ID_RESIDUAL_FLOOR_W) is an outlier (a load
 *    the model does not know, a gear change inside the window) and goes
 *    neither into the means nor into the mass. sigma^2 is the exponential
 *    mean of the mass updates' e^2 (weight 1/16); an outlier still raises
 *    it as a residual of 4 sigma would, so that residuals that stay large
 *    (the truck changed) are accepted again.
 *
 * 4. Aux power from the means: Paux = mean(y) - m mean(x), bounded to
 *    [0, PFE_ID_AUX_MAX_W]. Before the mass has converged this also absorbs
 *    the mass error at the current operating point.
 *
 * Gating (each sample; a failed sample discards the window in progress):
 * speed, grade and fuel rate valid; speed in [PFE_ID_SPEED_MIN_MM_S,
 * PFE_ID_SPEED_MAX_MM_S]; |grade| <= PFE_ID_GRADE_MAX_PPM; not braking; the
 * engine's fuel power eta rho_d fc in [PFE_ID_FUEL_POWER_MIN_W,
 * PFE_POWER_MAX_W] (fuel cut, idle, motoring and near-zero load are left
 * out, where eq. 3.9's switch and a constant eta do not hold); the time
 * since the previous sample in [PFE_ID_DT_MIN_MS, PFE_ID_DT_MAX_MS] and the
 * speed change no more than PFE_ID_ACCEL_MAX_UM_S2 per second (else a new
 * window starts at this sample, or at the next one for an implausible speed
 * change). Each window: |x| <= PFE_ID_X_MAX_MW_KG and |y| <= PFE_POWER_MAX_W.
 * Every window once the mass has 8 updates: not an outlier. Mass updates:
 * |dx| >= PFE_ID_EXCITE_MW_KG. A constant
 * speed on a constant grade gives dx of noise only: no mass update.
 *
 * Convergence: at least PFE_ID_CONVERGED_UPDATES mass updates since the
 * information was last reset, and the mass's standard error
 * sqrt(sigma^2 / (Sxx + I0)) at most 1 / PFE_ID_CONVERGED_INV_REL of the
 * mass (5 %). A restored "converged" stays set until that many updates
 * have been made, then the criterion decides. A standstill (speed below
 * PFE_ID_STOP_MM_S) of PFE_ID_STOP_RESET_MS or more (loading, unloading)
 * resets the information to a prior around the current estimate and clears
 * convergence; the estimate itself is kept.
 *
 * Scaling (each state field below names its unit); every quantity is
 * bounded by the gates, and the bounds are stated where the arithmetic is
 * (pfe_identify.c). Results: mass kg in [PFE_MASS_MIN_KG, PFE_MASS_MAX_KG],
 * aux power W in [0, PFE_ID_AUX_MAX_W], both saturating (clamped).
 *
 * Cost: one step per LFE1 frame. A sample: the grade split by a series
 * (|grade| <= 8 %, error below 1e-7), a dozen multiplications, one 32-bit
 * division. A window's end, every PFE_ID_WINDOW_INTERVALS samples: two
 * divisions by a 16-bit divisor (three 32-bit divisions each) and, on a
 * mass update, one more after normalising its divisor to 16 bits. Measured
 * on the Cortex-M4 (make bench, a 12 t drive): identify_step_mean 210,
 * identify_step_max 800 instructions (the max is a window's end with a mass
 * update; a sample alone is below 300). No heap, no floating point,
 * reentrant on distinct states; O(1).
 */
#ifndef PFE_IDENTIFY_H
#define PFE_IDENTIFY_H

#include <stdbool.h>
#include <stdint.h>

#include "pfe_calib.h"

#define PFE_ID_WINDOW_INTERVALS 20U      /* sample intervals per window: 2 s of LFE1 */
#define PFE_ID_DT_MIN_MS 50U             /* sample interval accepted (LFE1: 100 ms) */
#define PFE_ID_DT_MAX_MS 250U
#define PFE_ID_SPEED_MIN_MM_S 8000       /* 28.8 km/h: below, gear changes and clutch slip */
#define PFE_ID_SPEED_MAX_MM_S 36000      /* 129.6 km/h */
#define PFE_ID_GRADE_MAX_PPM 80000       /* 8 % */
#define PFE_ID_ACCEL_MAX_UM_S2 2000000   /* 2 m/s^2 between successive samples */
#define PFE_ID_FUEL_POWER_MIN_W 20000U   /* eta rho_d fc: 5 L/h at eta 0.4, above idle */
#define PFE_ID_X_MAX_MW_KG 100000        /* |x| of a window, 100 W/kg */
#define PFE_ID_AUX_MAX_W 100000U         /* as pfe_calib_check_vehicle */
#define PFE_ID_MEAN_SHIFT 4U             /* means: weight 1/16 per window */
#define PFE_ID_MEAN_RESTART_MS 60000U    /* no accepted window for this long: means restart */
#define PFE_ID_MASS_SHIFT 8U             /* lambda = 1 - 1/256 per mass update */
#define PFE_ID_EXCITE_MW_KG 1000         /* |dx| for a mass update: 1 W/kg */
#define PFE_ID_PRIOR_INFO 4000000LL      /* I0, (mW/kg)^2: four updates at 1 W/kg */
#define PFE_ID_OUTLIER_AFTER 8U          /* mass updates before outliers are rejected */
#define PFE_ID_RESIDUAL_FLOOR_W 1000     /* sigma's floor in the outlier test */
#define PFE_ID_CONVERGED_UPDATES 30U
#define PFE_ID_CONVERGED_INV_REL 20U     /* standard error <= mass / 20 */
#define PFE_ID_STOP_MM_S 500             /* standstill */
#define PFE_ID_STOP_RESET_MS 120000U     /* a stop this long may have changed the load */

/* What pfe_identify_step() did with a sample. */
typedef enum {
    PFE_ID_USED = 0,        /* in a window */
    PFE_ID_REJ_INVALID,     /* NULL, or an input not valid */
    PFE_ID_REJ_SPEED,       /* speed outside the range */
    PFE_ID_REJ_GRADE,       /* |grade| too large */
    PFE_ID_REJ_FUEL,        /* fuel cut, idle or implausible fuel rate */
    PFE_ID_REJ_BRAKE,       /* braking */
    PFE_ID_REJ_TIME,        /* interval outside the range or time going back: window restarted here */
    PFE_ID_REJ_ACCEL        /* implausible speed change */
} pfe_id_result_t;

/* One sample, at each LFE1 frame of the engine (every 100 ms). */
typedef struct {
    uint64_t now_us;          /* time of the sample (monotonic) */
    int32_t speed_mm_s;       /* wheel-based speed (CCVS1 SPN 84), latest */
    int32_t grade_ppm;        /* road grade, tan(pitch), ppm; measured, never assumed */
    uint32_t fuel_rate_nl_s;  /* the engine's fuel rate (LFE1 SPN 183) */
    bool speed_valid;
    bool grade_valid;
    bool fuel_valid;
    bool braking;             /* service brake or retarder active; false when unknown */
} pfe_identify_sample_t;

typedef struct {
    uint32_t samples_used;      /* samples in windows */
    uint32_t samples_rejected;  /* every other sample */
    uint32_t windows_used;      /* windows in the means */
    uint32_t windows_rejected;  /* windows out of bounds, and mass outliers */
    uint32_t mass_updates;      /* since init (saturating, as every counter) */
} pfe_identify_counters_t;

/* Caller-owned state. Read it through the functions below. */
typedef struct {
    bool ready;               /* init succeeded */
    /* from the calibration, at init */
    uint32_t fuel_power_q24;  /* mW per nL/s, * 2^24: eta rho_d; < 2^30 */
    uint32_t air_full_q32;    /* N per (mm/s)^2 * 2^32, no drag reduction; < 2^17 */
    uint32_t air_q32;         /* the same with (1 - phi/100) */
    uint32_t roll_q32;        /* cr * 2^32; < 2^29 */
    uint32_t gravity_um_s2;
    uint32_t rot_mass_kg;     /* mj */
    int64_t mass0_kg;         /* prior: the seed, restored or last estimate */
    /* last sample */
    bool have_time;
    uint64_t last_us;
    uint32_t frac_us;         /* sub-millisecond rest carried between intervals */
    bool have_prev;           /* the last sample anchors an interval */
    int32_t prev_speed_mm_s;
    int64_t prev_fuel_mw;     /* eta rho_d fc, mW, <= 2^31 */
    int64_t prev_air_mw;      /* k v^3, mW, < 2^31 */
    int64_t prev_spec_uw_kg;  /* v g (cr cos + sin), uW/kg, |.| < 2^27 */
    /* window in progress: sums of (previous + this) * dt, twice the trapezoid */
    uint32_t win_n;           /* intervals */
    uint32_t win_ms;          /* T, ms, <= PFE_ID_WINDOW_INTERVALS * PFE_ID_DT_MAX_MS */
    int32_t win_v0_mm_s;      /* speed at the window's start */
    int64_t win_fuel2_uj;     /* uJ * 2, < 2^45 */
    int64_t win_air2_uj;      /* uJ * 2, < 2^45 */
    int64_t win_spec2_nj_kg;  /* nJ/kg * 2, |.| < 2^40 */
    /* exponential means of the windows */
    bool have_mean;
    int64_t mean_x_q4;        /* mW/kg * 16 */
    int64_t mean_y_q4;        /* W * 16 */
    uint32_t since_window_ms; /* time since the last accepted window, saturating */
    /* mass, information form */
    int64_t sxx;              /* (mW/kg)^2, [0, 2^44] */
    int64_t sxy;              /* W * mW/kg, |.| < 2^49 */
    int64_t var_w2;           /* sigma^2, W^2, [0, 2^44] */
    uint32_t n_mass;          /* mass updates since the information was reset */
    uint32_t stop_ms;         /* standstill so far */
    /* outputs */
    uint32_t mass_kg;
    uint32_t aux_w;
    bool converged;
    pfe_identify_counters_t counters;
} pfe_identify_t;

/*
 * Starts from the seed calibration: mass and aux power as the seed's,
 * eta, mj, cw Af, cr from the seed and rho_air, g, rho_d from env, no
 * drag reduction (a lone truck), not converged, counters zero.
 * Returns PFE_OK, or PFE_EINVAL for a NULL argument or a calibration that
 * fails pfe_calib_check_vehicle / _env (id then reads as the default
 * vehicle's mass and aux power, not converged, and rejects every sample).
 * Uses 64-bit divisions: call at configuration time.
 */
int pfe_identify_init(pfe_identify_t *id, const pfe_vehicle_calib_t *seed,
                      const pfe_env_calib_t *env);

/*
 * The drag reduction phi_i(d) of the truck's position in 0.01 % (from
 * pfe_drag_reduction_bp()), when the platoon changes: the air power removed
 * from y uses it. Returns PFE_OK, or PFE_EINVAL (NULL, an id whose init
 * failed, reduction_bp > 10000; nothing changed). 64-bit division:
 * configuration time.
 */
int pfe_identify_set_drag_reduction(pfe_identify_t *id, uint32_t reduction_bp);

/*
 * One sample (call at each LFE1 frame of the engine, about every 100 ms).
 * Returns what was done with it (counted in the counters). s == NULL counts
 * as an invalid sample. Bounded time, see the file's header.
 */
pfe_id_result_t pfe_identify_step(pfe_identify_t *id, const pfe_identify_sample_t *s);

/* Identified mass, kg, in [PFE_MASS_MIN_KG, PFE_MASS_MAX_KG]; 0 for NULL. */
uint32_t pfe_identify_mass_kg(const pfe_identify_t *id);
/* Identified aux power, W, in [0, PFE_ID_AUX_MAX_W]; 0 for NULL. */
uint32_t pfe_identify_aux_power_w(const pfe_identify_t *id);
/* Whether the mass has converged (criterion above); false for NULL. */
bool pfe_identify_converged(const pfe_identify_t *id);
/* Counters; NULL for NULL. */
const pfe_identify_counters_t *pfe_identify_counters(const pfe_identify_t *id);

/*
 * Restores a saved state (mass, aux power, converged: the three values to
 * keep in NVM, read with the functions above): they become the outputs and
 * the prior; the information restarts from the prior. Returns PFE_OK, or
 * PFE_EINVAL for NULL, an id whose init failed, a mass outside
 * [PFE_MASS_MIN_KG, PFE_MASS_MAX_KG] or aux power above PFE_ID_AUX_MAX_W
 * (nothing changed).
 */
int pfe_identify_restore(pfe_identify_t *id, uint32_t mass_kg, uint32_t aux_w, bool converged);

#endif /* PFE_IDENTIFY_H */
