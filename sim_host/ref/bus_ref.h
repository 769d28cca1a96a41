/*
 * bus_ref.h - the double-precision reference fed what the module hears.
 *
 * Judging a module from a capture of its bus (sim_host/lib/capture.h) needs the
 * answer it should have given: the reference estimator (sim_host/ref/ref_model.h)
 * stepped every 10 ms on the same input frames, handled as the module
 * handles them (firmware/pfe_ecu.c):
 *   - CCVS1 speed and SSI pitch (grade = tan(pitch)) as last received, not
 *     available once older than three periods (300 ms, 30 ms) or when the
 *     frame says not available or error;
 *   - each of the two from one sender, as the module arbitrates them
 *     (firmware/pfe_input.h): the first sender whose value is valid, left
 *     for another only once it has sent no valid value for three periods
 *     or has sent error; not available or error from any other sender is
 *     ignored (a cab controller's "not available" speed beside the
 *     engine's). The module's plausibility checks are not modelled;
 *   - without a valid SSI pitch the road is assumed flat (grade 0), unless
 *     the slope sensor in use sends error or out of range (then no
 *     estimate), as the module does when it has no altitude either (the
 *     module's grade from VDS altitude is not modelled);
 *   - PFE_PlatoonConfig: the platoon (N trucks, own position, gap: Gap, else
 *     TimeGap x SetSpeed) changes when a valid frame differs from the one in
 *     use, or is the first after none or a stale one (3 s): the estimator
 *     restarts (warm-up), fuel used carries over, the own truck's to its new
 *     position;
 *   - every other frame, and frames from the module's source address, are
 *     ignored.
 * Until a PFE_PlatoonConfig arrives it runs the default platoon given to
 * bus_ref_init(), as the module runs the one it was started with.
 *
 * The module's tick phase is not in a capture: the reference ticks every
 * 10 ms from the first input frame; a frame is used from the first tick
 * strictly after it. The last BUS_REF_HISTORY ticks' fuel rates are kept,
 * so that a module's answer can be matched to the tick it most likely
 * comes from (bus_ref_nearest()).
 *
 * The caller owns the object (about 8 KB, it points into itself: do not copy
 * it). Time: microseconds of the capture's clock, never decreasing.
 */
#ifndef BUS_REF_H
#define BUS_REF_H

#include <stdbool.h>
#include <stdint.h>

#include "firmware/pfe_can.h"
#include "firmware/pfe_input.h"
#include "ref/ref_model.h"

#define BUS_REF_HISTORY 6U
#define BUS_REF_TICK_US 10000U

typedef struct {
    /* the trucks' calibrations (bus_ref_init_vehicles(); NULL: default) */
    const pfe_vehicle_calib_t *own_vehicle;
    const pfe_vehicle_calib_t *vehicle_at[PFE_MAX_VEHICLES];
    /* platoon in use */
    unsigned n_vehicles, position;
    uint32_t gap_mm;
    bool degraded;                  /* no valid PFE_PlatoonConfig in use */
    unsigned reconfigurations;      /* platoon changes from frames */
    ref_platoon_t pl;
    ref_estimator_t est;
    /* inputs */
    /* which frames are the inputs: the module's own gate, sender arbitration
     * and plausibility (firmware/pfe_input.h, integer logic, not a model),
     * so that the reference computes from exactly the values the module took */
    pfe_input_t speed_in, grade_in;
    int grade_state;                /* pfe_sig_state_t of the grade in use */
    bool grade_flat;                /* the last tick assumed a flat road */
    double speed_m_s, grade;
    bool speed_ok, speed_fresh, grade_ok, config_ok;
    bool speed_seen, grade_seen, config_seen;
    uint64_t speed_rx_us, grade_rx_us, config_rx_us;
    /* clock */
    bool started;
    uint64_t next_tick_us;
    uint64_t ticks;
    double own_rate_hist[BUS_REF_HISTORY];     /* L/s, newest at ticks % HISTORY - 1 */
    double platoon_rate_hist[BUS_REF_HISTORY];
} bus_ref_t;

/* Starts with a default platoon of n_vehicles, the own truck at position,
 * gap_mm apart. Returns 0, or -1 when that platoon is invalid. */
int bus_ref_init(bus_ref_t *r, unsigned n_vehicles, unsigned position, uint32_t gap_mm);

/* The same with the trucks' calibrations, as the module's
 * pfe_ecu_config_t own_vehicle and vehicle_at[] (sim_host/lib/truck_cal.h): the
 * own truck's at its position, vehicle_at[k] (NULL: pfe_default_vehicle) at
 * position k; own_vehicle NULL is the default. The calibrations must
 * outlive *r. */
int bus_ref_init_vehicles(bus_ref_t *r, unsigned n_vehicles, unsigned position, uint32_t gap_mm,
                          const pfe_vehicle_calib_t *own_vehicle,
                          const pfe_vehicle_calib_t *const vehicle_at[PFE_MAX_VEHICLES]);

/* Steps every tick due at or before t_us. The first call starts the clock
 * (first tick at t_us + 10 ms). */
void bus_ref_advance(bus_ref_t *r, uint64_t t_us);

/* The same one tick at a time, for a caller that looks at every tick: the
 * first call of bus_ref_due() starts the clock as bus_ref_advance() does;
 * it returns whether a tick is due at or before t_us, and bus_ref_tick()
 * then steps it and returns its time. */
bool bus_ref_due(bus_ref_t *r, uint64_t t_us);
uint64_t bus_ref_tick(bus_ref_t *r);

/* Crosses a silence in one jump: the next tick moves on by a whole number
 * of ticks to the last one at or before t_us, none of them stepped (the
 * inputs are stale by then, as the module's are when pfe_ecu_replay skips
 * the same silence, hal/replay/hal_replay_ecu.h). Returns the ticks
 * skipped (0 before the clock started or when t_us is not ahead). */
uint64_t bus_ref_skip_to(bus_ref_t *r, uint64_t t_us);

/* Takes one input frame received at t_us; call bus_ref_advance(r, t_us)
 * first. */
void bus_ref_input(bus_ref_t *r, const pfe_can_frame_t *f, uint64_t t_us);

/* At the last tick, L/s and L: the own truck (chapter 3 model at its
 * position) and the platoon (object model). */
double bus_ref_own_rate(const bus_ref_t *r);
double bus_ref_own_used(const bus_ref_t *r);
double bus_ref_platoon_rate(const bus_ref_t *r);
double bus_ref_platoon_used(const bus_ref_t *r);
/* The estimate is valid at the last tick (inputs fresh, warmed up). */
bool bus_ref_valid(const bus_ref_t *r);

/*
 * What a module whose tick fell at now_us would answer: a tick at now_us on
 * a copy of *r (which is left as it was), with every input taken so far.
 * The module's tick phase, and the jitter of frames around it, decide which
 * grade sample is the latest at its tick; the reference's own ticks may
 * never see that combination, a tick at the module's instant does. The
 * filter's state does not depend on the phase (a speed sample counts the
 * 100 ms periods since the last one, rounded). Fills own and platoon (L/s)
 * and returns whether the estimate is valid. O(size of *r): about 4 KB
 * copied.
 */
bool bus_ref_peek(const bus_ref_t *r, uint64_t now_us, double *own_l_s, double *platoon_l_s);

/* Of the last BUS_REF_HISTORY ticks' rates (own truck, or the platoon when
 * platoon is true), the one nearest to got_l_s; 0 before the first tick. */
double bus_ref_nearest(const bus_ref_t *r, bool platoon, double got_l_s);

#endif /* BUS_REF_H */
