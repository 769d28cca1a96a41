/*
 * pfe_input.h - one input of the module on a real J1939 bus: which sender
 * it comes from, and whether its value is plausible.
 *
 * A truck's bus often carries several senders of one PGN (the engine and a
 * cab controller both send CCVS1, one of them "not available" where the
 * other has a value), and nodes that misbehave. Every input the module
 * reads (speed, grade, altitude, mass, the engine's fuel rate) goes through
 * the same two steps before the estimator sees it (docs/j1939.md):
 *
 * 1. Sender arbitration. A calibration may name the input's source address
 *    (fixed: frames from every other sender are ignored). Otherwise the
 *    input locks onto the first sender whose value is valid (and inside the
 *    plausible range of step 2), and moves to
 *    another sender only when the locked one has sent no valid value for
 *    PFE_INPUT_STALE_PERIODS periods or has just sent "error". A value that
 *    is not available or error from any sender but the locked one never
 *    replaces a valid value; while no sender is in use, "error" makes the
 *    input ERROR (a sensor that is there and failed is not an absent one)
 *    until a valid sender comes. Frames carrying the module's own source address
 *    never reach this point (the ECU treats them as an address conflict).
 *
 * 2. Plausibility, in the spirit of opendbc's RxCheck: one table
 *    (pfe_input_rules[]) gives each input its PGN, period, plausible range
 *    and largest plausible change per second (plus a fixed margin per frame
 *    for quantisation and sensor noise). A value outside the range, or that
 *    moved from the last accepted one by more than rate * dt + margin, or
 *    that came less than the rule's minimum interval after it (0.6 of the
 *    period of another node's LFE1: two nodes sending with one address, or
 *    a sender gone wild, garbage between the real frames; none for CCVS1
 *    and SSI, whose frames the ECU stamps with its tick's time, so that a
 *    late tick catching up brings real frames closer together than they
 *    came), is rejected and
 *    counted; the input keeps its last accepted value, which ages as usual,
 *    so that a rejected frame changes nothing the estimator sees.
 *    PFE_INPUT_REJECTS_TO_ERROR rejections in a row make the input ERROR
 *    (the ECU then sends its fuel outputs not available), and it stays so
 *    until PFE_INPUT_CONFIRM_FRAMES consecutive frames agree with each other
 *    (each within range, rate and interval of the previous one). The first
 *    value after the input was unused for PFE_INPUT_STALE_PERIODS periods is
 *    taken on its range alone. The limit of any such check: a garbage value
 *    that happens to fall inside the plausible change (for speed about 3 %
 *    of random payloads) is a plausible speed, and is used.
 *
 * Why the speed limits (CCVS1, SPN 84): a truck neither brakes nor
 * accelerates faster than tyre-road friction allows, mu <= 1, so |dv/dt| <=
 * g = 9.81 m/s^2 (a laden truck brakes at 5 to 7 m/s^2 and accelerates at
 * well under 2 m/s^2); the rule allows 10 m/s^2 plus 1 m/s per frame for the
 * 1/256 km/h quantisation, wheel slip and the jitter of a 100 ms period,
 * that is 7.2 km/h between two frames 100 ms apart. The plausible range is
 * 0 to 150 km/h: no truck's limiter allows more (EU trucks: 90 km/h).
 * Grade (SSI pitch, SPN 3318): within the model's +-50 % and a change of at
 * most 20 %/s (a crest's vertical curve of 500 m radius at 25 m/s changes
 * the grade by 5 %/s; body pitch under hard braking by about as much) plus
 * 0.5 % per frame for sensor noise. Altitude (VDS, SPN 580, every second in
 * J1939-71): the signal's range, and a climb of at most 15 m/s (40 m/s at
 * 30 % grade would be 12 m/s) plus 10 m per frame for GNSS jumps, and no
 * minimum interval (a 10 Hz GNSS receiver sends faster than J1939-71 asks). Mass (CVW, SPN 1760): the calibration
 * range PFE_MASS_MIN_KG .. PFE_MASS_MAX_KG, no rate. Engine fuel rate (LFE1,
 * SPN 183): 0 to 250 L/h (a 450 kW engine at full load burns about 110 L/h),
 * no rate (a fuel cut is a step).
 *
 * Time: microseconds of the ECU's clock, passed in. O(1) per frame but for
 * the list of senders seen (at most PFE_INPUT_MAX_SENDERS compares).
 */
#ifndef PFE_INPUT_H
#define PFE_INPUT_H

#include <stdbool.h>
#include <stdint.h>

#include "pfe_codec.h"

/* The inputs, in the order of pfe_input_rules[]. */
typedef enum {
    PFE_IN_SPEED = 0,       /* CCVS1 WheelBasedVehicleSpeed, mm/s */
    PFE_IN_GRADE = 1,       /* SSI PitchAngle as road grade, ppm */
    PFE_IN_ALTITUDE = 2,    /* VDS Altitude, mm */
    PFE_IN_MASS = 3,        /* CVW GrossCombinationVehicleWeight, kg */
    PFE_IN_ENGINE_FUEL = 4, /* another node's LFE1 EngineFuelRate, nL/s */
    PFE_IN_COUNT = 5
} pfe_input_kind_t;

#define PFE_INPUT_NO_SOURCE 0xFFU      /* no sender in use */
#define PFE_INPUT_MAX_SENDERS 15U      /* distinct senders counted (PFE_InputStatus) */
#define PFE_INPUT_STALE_PERIODS 3U
#define PFE_INPUT_REJECTS_TO_ERROR 3U
#define PFE_INPUT_CONFIRM_FRAMES 3U

/* One row of the plausibility table. */
typedef struct {
    uint32_t pgn;
    uint32_t period_us;           /* the sender's period, the DBC's (PFE_RX_PERIOD_MS_*); staleness is PFE_INPUT_STALE_PERIODS of it */
    int32_t min;                  /* plausible range, in the input's unit */
    int32_t max;
    uint32_t max_rate_per_s;      /* largest plausible change per second; 0: not checked */
    uint32_t margin;              /* allowed on top of rate * dt, per frame */
    uint32_t min_interval_us;     /* a frame sooner after the last accepted is rejected; 0: none */
} pfe_input_rule_t;

extern const pfe_input_rule_t pfe_input_rules[PFE_IN_COUNT];

/* What pfe_input_take() decided about one frame. */
typedef enum {
    PFE_INPUT_IGNORED = 0,        /* another sender's, or not available/error from a non-locked one */
    PFE_INPUT_ACCEPTED = 1,       /* the input's new value (or its new not-available/error state) */
    PFE_INPUT_REJECTED = 2,       /* the locked sender's value failed plausibility */
    PFE_INPUT_CONFIRMING = 3      /* plausible, but the input is still confirming after an error */
} pfe_input_verdict_t;

typedef struct {
    pfe_input_kind_t kind;
    bool fixed;                   /* the calibration names the sender */
    uint8_t locked;               /* sender in use, PFE_INPUT_NO_SOURCE for none */
    uint64_t locked_valid_us;     /* last valid value from the locked sender */
    /* plausibility */
    bool have_ref;                /* last_value is a reference for the rate check */
    int32_t last_value;           /* last accepted (or confirming) value */
    uint64_t last_us;
    uint8_t rejects_in_row;
    uint8_t confirm_left;         /* > 0: in error, frames still to agree */
    bool error;                   /* persistent rejection */
    /* what the input is now */
    pfe_sig_state_t state;        /* state of the last accepted frame (ERROR while in error) */
    int32_t value;                /* last accepted value, meaningful when state is VALID */
    uint64_t rx_us;               /* receive time of the last accepted frame */
    /* senders seen */
    uint8_t senders[PFE_INPUT_MAX_SENDERS];
    uint8_t n_senders;
    uint32_t rejected;            /* frames rejected, saturating */
} pfe_input_t;

/* Empties the input. fixed_source: the calibration's sender, or
 * PFE_INPUT_NO_SOURCE to let the module choose. */
void pfe_input_init(pfe_input_t *in, pfe_input_kind_t kind, uint8_t fixed_source);

/*
 * One decoded frame from `source` whose value is `value` in `state`, received
 * at rx_us. Arbitrates, checks plausibility and updates in->state, value and
 * rx_us when the frame is the input's. Returns the verdict.
 */
pfe_input_verdict_t pfe_input_take(pfe_input_t *in, uint8_t source, pfe_sig_state_t state,
                                   int32_t value, uint64_t rx_us);

/*
 * Ages the input at now_us: a value older than PFE_INPUT_STALE_PERIODS
 * periods makes it NOT_AVAILABLE (and forgets the rate reference). Returns
 * true when the input holds a VALID value.
 */
bool pfe_input_age(pfe_input_t *in, uint64_t now_us);

/* The sender in use, PFE_INPUT_NO_SOURCE for none. */
uint8_t pfe_input_source(const pfe_input_t *in);

#endif /* PFE_INPUT_H */
