/* bus_ref.c - the reference fed what the module hears (contract in bus_ref.h). */
#include "ref/bus_ref.h"

#include <math.h>
#include <string.h>

#include "firmware/pfe_calib.h"
#include "firmware/pfe_codec.h"
#include "firmware/pfe_platoon.h"

#define SPEED_STALE_US 300000U      /* three CCVS1 periods */
#define GRADE_STALE_US 30000U       /* three SSI periods */
#define CONFIG_STALE_US 3000000U    /* three PFE_PlatoonConfig periods */
#define PI 3.14159265358979323846

/* As the module's configure(): 0, or -1 leaving everything as it was. */
static int configure(bus_ref_t *r, unsigned n, unsigned position, uint32_t gap_mm)
{
    pfe_platoon_config_t pc;
    pfe_platoon_config_uniform(&pc, n, gap_mm, &pfe_default_vehicle, &pfe_default_env,
                               &pfe_default_drag);
    for (unsigned k = 0U; k < pc.n_vehicles; k++) {
        if (r->vehicle_at[k] != NULL) {
            pc.vehicle[k] = r->vehicle_at[k];
        }
    }
    if ((position < pc.n_vehicles) && (r->own_vehicle != NULL)) {
        pc.vehicle[position] = r->own_vehicle;
    }
    ref_platoon_t trial;
    if ((pc.n_vehicles != n) || (position >= n) || (ref_platoon_init(&trial, &pc) != 0)) {
        return -1;
    }
    const double own = r->started ? r->est.pos_fuel_used[r->position] : 0.0;
    const double platoon = r->started ? r->est.fuel_used : 0.0;
    r->pl = trial;
    ref_estimator_init(&r->est, &r->pl);
    r->est.pos_fuel_used[position] = own;
    r->est.fuel_used = platoon;
    r->n_vehicles = n;
    r->position = position;
    r->gap_mm = gap_mm;
    return 0;
}

int bus_ref_init(bus_ref_t *r, unsigned n_vehicles, unsigned position, uint32_t gap_mm)
{
    return bus_ref_init_vehicles(r, n_vehicles, position, gap_mm, NULL, NULL);
}

int bus_ref_init_vehicles(bus_ref_t *r, unsigned n_vehicles, unsigned position, uint32_t gap_mm,
                          const pfe_vehicle_calib_t *own_vehicle,
                          const pfe_vehicle_calib_t *const vehicle_at[PFE_MAX_VEHICLES])
{
    memset(r, 0, sizeof *r);
    r->own_vehicle = own_vehicle;
    for (unsigned k = 0U; (vehicle_at != NULL) && (k < PFE_MAX_VEHICLES); k++) {
        r->vehicle_at[k] = vehicle_at[k];
    }
    if (configure(r, n_vehicles, position, gap_mm) != 0) {
        return -1;
    }
    r->degraded = true;
    r->grade_state = (int)PFE_SIG_NOT_AVAILABLE;
    pfe_input_init(&r->speed_in, PFE_IN_SPEED, PFE_INPUT_NO_SOURCE);
    pfe_input_init(&r->grade_in, PFE_IN_GRADE, PFE_INPUT_NO_SOURCE);
    return 0;
}

static void tick(bus_ref_t *r, uint64_t now_us)
{
    if (!r->speed_seen || ((now_us - r->speed_rx_us) > SPEED_STALE_US)) {
        r->speed_seen = false;
        r->speed_ok = false;
    }
    if (!r->grade_seen || ((now_us - r->grade_rx_us) > GRADE_STALE_US)) {
        r->grade_seen = false;
        r->grade_ok = false;
        r->grade_state = (int)PFE_SIG_NOT_AVAILABLE;
    }
    /* No slope sensor value: the road assumed flat, unless the sensor is
     * in error or out of range (a fault, not an absent sensor). */
    r->grade_flat = !r->grade_ok && (r->grade_state != (int)PFE_SIG_ERROR) &&
                    (r->grade_state != (int)PFE_SIG_OUT_OF_RANGE);
    if (!r->config_seen || ((now_us - r->config_rx_us) > CONFIG_STALE_US)) {
        r->config_seen = false;
        r->config_ok = false;
    }
    if (!r->config_ok) {
        r->degraded = true;
    }
    ref_estimator_step(&r->est, r->speed_m_s, r->speed_ok, r->speed_fresh,
                       r->grade_ok ? r->grade : 0.0, r->grade_ok || r->grade_flat);
    r->speed_fresh = false;
    const unsigned h = (unsigned)(r->ticks % BUS_REF_HISTORY);
    r->own_rate_hist[h] = r->est.pos_fuel_rate[r->position];
    r->platoon_rate_hist[h] = r->est.fuel_rate;
    r->ticks++;
}

bool bus_ref_due(bus_ref_t *r, uint64_t t_us)
{
    if (!r->started) {
        r->started = true;
        r->next_tick_us = t_us + BUS_REF_TICK_US;
        return false;
    }
    return r->next_tick_us <= t_us;
}

uint64_t bus_ref_tick(bus_ref_t *r)
{
    const uint64_t t = r->next_tick_us;
    tick(r, t);
    r->next_tick_us += BUS_REF_TICK_US;
    return t;
}

uint64_t bus_ref_skip_to(bus_ref_t *r, uint64_t t_us)
{
    if (!r->started || (t_us <= r->next_tick_us)) {
        return 0U;
    }
    const uint64_t n = (t_us - r->next_tick_us) / BUS_REF_TICK_US;
    r->next_tick_us += n * BUS_REF_TICK_US;
    return n;
}

void bus_ref_advance(bus_ref_t *r, uint64_t t_us)
{
    while (bus_ref_due(r, t_us)) {
        (void)bus_ref_tick(r);
    }
}

static void on_config(bus_ref_t *r, const pfe_can_frame_t *f, uint64_t t_us)
{
    pfe_msg_platoon_config_t m;
    if (pfe_codec_decode_platoon_config(f, &m) < 0) {
        return;
    }
    uint32_t gap_mm = 0U;
    bool ok = (m.n_vehicles.state == PFE_SIG_VALID) && (m.own_position.state == PFE_SIG_VALID) &&
              (pfe_codec_platoon_gap_mm(&m, &gap_mm) == PFE_SIG_VALID);
    r->config_seen = true;
    r->config_rx_us = t_us;
    if (ok) {
        const bool changed = r->degraded || (m.n_vehicles.value != r->n_vehicles) ||
                             (m.own_position.value != r->position) || (gap_mm != r->gap_mm);
        if (changed) {
            if (configure(r, m.n_vehicles.value, m.own_position.value, gap_mm) == 0) {
                r->degraded = false;
                r->reconfigurations++;
            } else {
                ok = false;
            }
        }
    }
    r->config_ok = ok;
}

void bus_ref_input(bus_ref_t *r, const pfe_can_frame_t *f, uint64_t t_us)
{
    if ((f->id & PFE_CAN_EFF_FLAG) == 0U) {
        return;
    }
    const uint32_t pgn = pfe_j1939_pgn(f->id);
    if (pgn == PFE_PGN_CCVS1) {
        pfe_msg_ccvs1_t m;
        if (pfe_codec_decode_ccvs1(f, &m) < 0) {
            return;
        }
        const pfe_input_verdict_t v = pfe_input_take(&r->speed_in, pfe_j1939_source(f->id),
                                                     m.speed_mm_s.state, m.speed_mm_s.value, t_us);
        if (r->speed_in.error) {
            r->speed_ok = false; /* rejected again and again: an error, as the module says */
        }
        if (v != PFE_INPUT_ACCEPTED) {
            return;
        }
        r->speed_ok = m.speed_mm_s.state == PFE_SIG_VALID;
        r->speed_m_s = m.speed_mm_s.value / 1000.0;
        r->speed_fresh = true;
        r->speed_seen = true;
        r->speed_rx_us = t_us;
    } else if (pgn == PFE_PGN_SSI) {
        pfe_msg_ssi_t m;
        if (pfe_codec_decode_ssi(f, &m) < 0) {
            return;
        }
        /* the gate judges the grade as the module computes it; the model uses tan() */
        const int32_t grade_ppm = pfe_codec_grade_ppm_from_pitch(m.pitch_udeg.value, NULL);
        const pfe_input_verdict_t v = pfe_input_take(&r->grade_in, pfe_j1939_source(f->id),
                                                     m.pitch_udeg.state, grade_ppm, t_us);
        if (r->grade_in.error) {
            r->grade_state = (int)PFE_SIG_ERROR;
            r->grade_ok = false;
        }
        if (v != PFE_INPUT_ACCEPTED) {
            return;
        }
        r->grade_state = (int)m.pitch_udeg.state;
        r->grade_ok = m.pitch_udeg.state == PFE_SIG_VALID;
        r->grade = tan(m.pitch_udeg.value / 1e6 * PI / 180.0);
        r->grade_seen = true;
        r->grade_rx_us = t_us;
    } else if (pgn == PFE_PGN_PLATOON_CONFIG) {
        on_config(r, f, t_us);
    }
}

bool bus_ref_peek(const bus_ref_t *r, uint64_t now_us, double *own_l_s, double *platoon_l_s)
{
    bus_ref_t copy = *r;
    copy.est.pl = &r->pl; /* the copy's platoon is the same */
    tick(&copy, now_us);
    *own_l_s = copy.est.pos_fuel_rate[copy.position];
    *platoon_l_s = copy.est.fuel_rate;
    return copy.est.valid;
}

double bus_ref_own_rate(const bus_ref_t *r)
{
    return r->est.pos_fuel_rate[r->position];
}

double bus_ref_own_used(const bus_ref_t *r)
{
    return r->est.pos_fuel_used[r->position];
}

double bus_ref_platoon_rate(const bus_ref_t *r)
{
    return r->est.fuel_rate;
}

double bus_ref_platoon_used(const bus_ref_t *r)
{
    return r->est.fuel_used;
}

bool bus_ref_valid(const bus_ref_t *r)
{
    return r->est.valid;
}

double bus_ref_nearest(const bus_ref_t *r, bool platoon, double got_l_s)
{
    const double *h = platoon ? r->platoon_rate_hist : r->own_rate_hist;
    const uint64_t n = (r->ticks < BUS_REF_HISTORY) ? r->ticks : BUS_REF_HISTORY;
    double best = 0.0, best_d = INFINITY;
    for (uint64_t k = 0U; k < n; k++) {
        const double d = fabs(got_l_s - h[k]);
        if (d < best_d) {
            best_d = d;
            best = h[k];
        }
    }
    return best;
}
