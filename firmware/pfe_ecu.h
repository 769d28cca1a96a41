/*
 * pfe_ecu.h - the module as a J1939 ECU: the 10 ms loop.
 *
 * Portable and I/O-free: a HAL-side main loop moves frames and time in and
 * out. Every 10 ms tick it
 *   1. drains the bounded receive queue (frames queued by pfe_ecu_receive()),
 *      matching J1939 PGNs with priority and source address masked, and
 *      decodes and validates each input (range, not available, error);
 *      at most PFE_ECU_RX_PER_TICK frames a tick, PFE_ECU_RX_LIGHT while a
 *      platoon is being built (the rest waits for the next tick); of
 *      several PFE_PlatoonConfig in one tick the last wins, decoded once,
 *      and so does the last new mass of the own truck (CVW);
 *      a new platoon is built in place over the next ticks,
 *      PFE_ECU_REBUILD_PER_TICK trucks a tick, then its aggregates in a
 *      tick of their own (32 trucks: 5 ticks), the estimator paused
 *      meanwhile (it starts again on a new platoon anyway: outputs not
 *      available, totals held);
 *   2. ages the inputs: a message older than three of its periods makes its
 *      inputs not available (PFE_ECU_STALE_PERIODS);
 *   3. steps the estimator (pfe_estimator.h);
 *   4. sends each output on its J1939 schedule (can_dbc/pfe.dbc), plus the
 *      answers to requests (PGN 59904) and the address claim (J1939-81);
 *   5. gives the prediction over the grade preview (pfe_predict.h) its
 *      share of the tick, PFE_ECU_PREDICT_UNITS, unless the tick did a
 *      share of a rebuild or decoded more than PFE_ECU_RX_LIGHT frames
 *      (a burst: then it waits a tick, so that a tick's work stays within
 *      20,000 Cortex-M4 instructions, `make bench`): once a second a new
 *      prediction starts from the current speed and the distance travelled
 *      since the preview's header, a new preview or platoon abandons the one
 *      in progress, and PFE_FuelPrediction sends the latest (not available
 *      without one, or when it is older than PFE_ECU_PREDICT_MAX_AGE_US).
 * The main loop reports what it saw go wrong (ticks overrun, frames it could
 * not send or that the bus dropped); the status message carries it. It also
 * says when a value was clamped: GradeClamped for a pitch beyond
 * +-PFE_GRADE_MAX_PPM (as the estimator's own clamp), OutputSaturated for
 * an estimator total or rate at its limit and for an output whose last
 * frame the codec clamped to its signal's range (a total above 4211081.215
 * L, a rate above 3212.75 L/h, a prediction above 642.55 L or 6425.5 s).
 *
 * Total fuel used survives a reset through two NVM slots (pfe_nvm.h): the
 * main loop reads them before pfe_ecu_init(), writes pfe_ecu_nvm_take() to
 * pfe_ecu_nvm_slot() whenever pfe_ecu_nvm_due(), and reports the write's
 * result with pfe_ecu_nvm_written(): only a completed write moves the next
 * save to the other slot, so the slot holding the last completed record is
 * never written while a failing write is retried.
 *
 * Time: microseconds of one monotonic clock, passed in; frames carry their
 * receive time on the same clock. Memory: all in pfe_ecu_t (caller owned).
 */
#ifndef PFE_ECU_H
#define PFE_ECU_H

#include <stdbool.h>
#include <stdint.h>

#include "pfe_altgrade.h"
#include "pfe_calib.h"
#include "pfe_can.h"
#include "pfe_codec.h"
#include "pfe_estimator.h"
#include "pfe_identify.h"
#include "pfe_input.h"
#include "pfe_nvm.h"
#include "pfe_platoon.h"
#include "pfe_predict.h"

#define PFE_ECU_TICK_US 10000U
#define PFE_ECU_RX_QUEUE_LEN 64U       /* frames between two ticks; more are dropped and counted */
#define PFE_ECU_RX_PER_TICK 32U        /* frames one tick decodes at most; the rest waits a tick */
#define PFE_ECU_RX_LIGHT 16U           /* a tick that decodes more skips the rebuild's and the
                                        * prediction's share; while a rebuild runs, the most a tick decodes */
#define PFE_ECU_REBUILD_PER_TICK 8U    /* platoon positions a tick builds (pfe_platoon_init_positions()) */
#define PFE_ECU_TX_MAX 16U             /* frames one tick may send at most */
#define PFE_ECU_STALE_PERIODS 3U
#define PFE_ECU_CLAIM_WAIT_US 250000U  /* J1939-81: wait after claiming before sending */
#define PFE_ECU_DEFAULT_ADDRESS 0x8CU
#define PFE_ECU_PREDICT_UNITS 36U      /* prediction work per tick (pfe_predict_run()) */
#define PFE_ECU_PREDICT_PERIOD_US 1000000U /* a new prediction from the current position */
#define PFE_ECU_PREDICT_MAX_AGE_US 3000000U /* an older prediction is sent as not available */
#define PFE_ECU_DEFAULT_SET_SPEED_MM_S 25000 /* 90 km/h, until PFE_PlatoonConfig gives one */
#define PFE_ECU_NVM_FAILING_AFTER 3U   /* failed NVM writes in a row that set nvm_failing */
#define PFE_ECU_RECLAIM_MIN_US 1000000U /* an address conflict re-claims at most once a second */

/* Whether the module sends LFE1 and HRLFC, the PGNs the engine itself sends
 * (its own-truck estimate always goes out as PFE_OwnFuel). */
typedef enum {
    PFE_ECU_J1939_FUEL_AUTO = 0,       /* each only while no other node sends it (can_dbc/pfe.dbc) */
    PFE_ECU_J1939_FUEL_ALWAYS = 1,     /* a truck without fuel reporting of its own */
    PFE_ECU_J1939_FUEL_NEVER = 2
} pfe_ecu_j1939_fuel_t;

/* What the module is and how it starts. */
typedef struct {
    uint8_t preferred_address;         /* source address claimed at start-up */
    uint64_t name;                     /* J1939 NAME (pfe_j1939_name_pack()); bit 63: arbitrary address capable */
    uint32_t save_interval_ms;         /* NVM save period, 1000 .. 3600000 */
    const pfe_vehicle_calib_t *vehicle;/* calibration of every truck */
    const pfe_env_calib_t *env;
    const pfe_drag_table_t *drag;
    /* Platoon until a PFE_PlatoonConfig arrives (the module then runs degraded). */
    uint32_t default_vehicles;
    uint32_t default_position;
    uint32_t default_gap_mm;
    /* Prediction over the grade preview: the cruise control simulated (NULL:
     * pfe_default_cruise) and its set speed until PFE_PlatoonConfig gives
     * one (0: PFE_ECU_DEFAULT_SET_SPEED_MM_S). */
    const pfe_cruise_calib_t *cruise;
    int32_t default_set_speed_mm_s;
    /* The truck the module runs on (NULL: vehicle) and, by platoon position
     * (0 = lead), the others (NULL entries: vehicle). CVW's mass replaces
     * the own truck's mass while it is valid (pfe_ecu_t.own_calib). */
    const pfe_vehicle_calib_t *own_vehicle;
    const pfe_vehicle_calib_t *vehicle_at[PFE_MAX_VEHICLES];
    /* A real bus (docs/j1939.md); zero is the default of each. */
    bool input_source_fixed[PFE_IN_COUNT]; /* the calibration names the sender of an input */
    uint8_t input_source[PFE_IN_COUNT];    /* that sender's source address */
    bool flat_grade_forbidden;         /* no grade source: no estimate (else the road is assumed flat) */
    pfe_ecu_j1939_fuel_t j1939_fuel;
    /* Identification of the own truck's mass and auxiliary power from the
     * engine's LFE1 (pfe_identify.h): off, or only on a measured grade (SSI
     * or altitude; else the assumed flat road is used as well). */
    bool identification_off;
    bool identification_needs_grade;
} pfe_ecu_config_t;

/* Input states in PFE_Status (can_dbc/pfe.dbc VAL_). */
typedef enum {
    PFE_ECU_ADDR_CLAIMING = 0,         /* claim sent, waiting PFE_ECU_CLAIM_WAIT_US */
    PFE_ECU_ADDR_CLAIMED = 1,
    PFE_ECU_ADDR_LOST = 2,             /* cannot claim: silent but for "cannot claim" */
} pfe_ecu_addr_state_t;

/* One input message: its last decoded state, whether it is new, and when it
 * came (NOT_AVAILABLE also when it never came or is older than
 * PFE_ECU_STALE_PERIODS periods). */
typedef struct {
    pfe_sig_state_t state;
    bool fresh;                        /* a new value since the last tick */
    uint64_t rx_us;                    /* receive time of the last frame */
    bool seen;
} pfe_ecu_input_t;

/* The CAN controller as a HAL backend sees it (pfe_ecu_note_bus_state()). */
typedef struct {
    uint32_t rx_overruns;              /* frames the controller's receive FIFOs lost, saturating */
    uint32_t bus_off_events;           /* times the controller went bus-off, saturating */
    uint8_t tx_error_counter;          /* TEC, 0 .. 255 */
    uint8_t rx_error_counter;          /* REC, 0 .. 255 */
    bool error_warning;
    bool error_passive;
    bool bus_off;
} pfe_ecu_bus_state_t;

/* Cause of the last reset, as the HAL reads it at start (PFE_DeviceStatus ResetCause). */
typedef enum {
    PFE_RESET_POWER_ON = 0,
    PFE_RESET_WATCHDOG = 1,
    PFE_RESET_SOFTWARE = 2,
    PFE_RESET_OTHER = 3
} pfe_reset_cause_t;

/* Counters that only count up (saturating). */
typedef struct {
    uint32_t rx_frames;
    uint32_t rx_dropped;               /* receive queue full, or reported by the HAL */
    uint32_t rx_rejected;              /* wrong length, unknown PGN */
    uint32_t tx_frames;
    uint32_t tx_dropped;               /* reported by the main loop */
    uint32_t overruns;                 /* ticks the main loop reported late */
    uint32_t requests_answered;
    uint32_t claims_lost;
    uint32_t nvm_write_failures;       /* NVM writes the main loop reported failed */
} pfe_ecu_counters_t;

typedef struct {
    pfe_ecu_config_t cfg;
    /* receive queue */
    pfe_can_frame_t rxq[PFE_ECU_RX_QUEUE_LEN];
    uint64_t rxq_us[PFE_ECU_RX_QUEUE_LEN];
    uint32_t rxq_head;
    uint32_t rxq_count;
    /* network management */
    pfe_ecu_addr_state_t addr_state;
    uint8_t address;
    uint64_t claim_us;
    bool claim_pending;                /* send our Address Claimed on the next tick */
    uint32_t request_pending;          /* bit per output message asked for by a request */
    bool cannot_claim_pending;         /* answer with "cannot claim" (source 254) */
    /* inputs: arbitrated and checked (pfe_input.h) */
    pfe_input_t in[PFE_IN_COUNT];
    bool speed_fresh;                  /* a new accepted speed since the last tick */
    uint32_t conflicts;                /* frames from another node with our address, and claims of it */
    uint64_t reclaim_us;               /* last re-claim after a conflict */
    bool reclaimed;
    /* grade source chain: SSI pitch, else VDS altitude over distance, else flat */
    pfe_altgrade_t altgrade;
    uint64_t odometer_um;              /* distance travelled, from the speed in use */
    uint8_t grade_source;              /* PFE_GRADE_SOURCE_* of the last tick */
    /* the own truck's model */
    pfe_vehicle_calib_t own_calib;     /* in use: calibration, CVW's mass, identified values */
    uint8_t mass_source;               /* PFE_MASS_SOURCE_* */
    bool cvw_mass;                     /* a valid CVW has given the mass */
    bool aux_identified;               /* own_calib.power_aux_w is the identified one */
    pfe_identify_t identify;
    uint64_t remodel_us;               /* last rebuild for identified values */
    bool remodelled;
    /* other nodes' LFE1 and HRLFC: the module does not shadow them */
    uint64_t other_lfe1_us;
    uint64_t other_hrlfc_us;
    bool other_lfe1_seen;
    bool other_hrlfc_seen;
    uint64_t start_us;
    pfe_ecu_input_t config;
    pfe_ecu_input_t preview;
    int32_t speed_mm_s;                /* speed in use (valid when in[PFE_IN_SPEED] is) */
    int32_t grade_ppm;                 /* grade in use (valid when grade_source < NONE) */
    bool grade_saturated;              /* the last pitch was beyond +-PFE_GRADE_MAX_PPM */
    pfe_msg_platoon_config_t platoon_msg;
    /* the tick's last PFE_PlatoonConfig, decoded and applied once after the queue */
    pfe_can_frame_t config_frame;
    uint64_t config_frame_us;
    bool config_frame_pending;
    pfe_preview_t preview_buf;
    /* model */
    pfe_platoon_t platoon;
    /* a platoon being built in place over ticks (PFE_ECU_REBUILD_PER_TICK trucks a tick) */
    bool platoon_building;
    uint32_t build_n;
    uint32_t build_position;
    uint32_t build_gap_mm;
    uint32_t build_done;               /* positions built; build_n: the aggregates next */
    uint64_t build_own_ul;             /* totals at the build's start, held during it */
    uint64_t build_platoon_ul;
    uint32_t build_old_n;              /* the platoon before, for a build that fails */
    uint32_t build_old_position;
    uint32_t build_old_gap_mm;
    /* the tick's last new mass of the own truck (CVW), applied once after the queue */
    uint32_t mass_next_kg;
    bool mass_next_pending;
    pfe_estimator_t est;
    /* prediction over the preview */
    pfe_predict_t predict;
    uint64_t preview_travelled_um;     /* since the preview's header */
    bool preview_new;                  /* completed since the last prediction started */
    uint32_t preview_serial;           /* counts completed previews */
    uint64_t predict_start_us;
    uint64_t predict_result_us;        /* when the last prediction was published */
    uint32_t predict_generation;
    uint32_t own_position;
    bool degraded;                     /* running on the default platoon */
    const pfe_est_output_t *out;
    /* schedule and time */
    uint64_t now_us;
    uint32_t tick;
    uint64_t last_save_us;
    uint32_t nvm_sequence;             /* of the last completed NVM write */
    int nvm_last_slot;                 /* slot of the last completed write, -1 for none */
    uint32_t nvm_fail_streak;          /* failed writes since the last completed one */
    bool nvm_failing;                  /* PFE_ECU_NVM_FAILING_AFTER failures in a row, until a write
                                        * completes (PFE_DeviceStatus NvmWriteFailing) */
    uint32_t outputs_clamped;          /* bit per output whose last frame the codec clamped */
    /* device health from the HAL (PFE_DeviceStatus); not available until reported */
    pfe_ecu_bus_state_t bus;
    bool bus_known;
    pfe_reset_cause_t reset_cause;
    bool reset_cause_known;
    pfe_ecu_counters_t count;
} pfe_ecu_t;

/* The frames the ECU reads, as CAN filters (hal_can_add_filter()): a frame
 * is for the ECU when (id & mask) == (filter id & mask) for one of them. The
 * J1939 PGN with priority and source masked, and for the PDU1 PGNs
 * (request, address claimed) the destination too. A HAL that installs them
 * keeps other traffic from costing the ECU anything. One per message the
 * DBC says the module receives: PFE_ECU_RX_FILTERS (pfe_dbc.h). */
typedef struct {
    uint32_t id;
    uint32_t mask;
} pfe_ecu_filter_t;
extern const pfe_ecu_filter_t pfe_ecu_rx_filters[PFE_ECU_RX_FILTERS];

/*
 * Starts the ECU at now_us: claims cfg->preferred_address, restores fuel
 * totals from `restored` (NULL or the result of pfe_nvm_pick(), whose slot
 * index is restored_slot, -1 for none). Returns PFE_OK or PFE_EINVAL.
 */
int pfe_ecu_init(pfe_ecu_t *ecu, const pfe_ecu_config_t *cfg, const pfe_nvm_state_t *restored,
                 int restored_slot, uint64_t now_us);

/* Queues one received frame for the next tick. O(1); a full queue drops the
 * frame and counts it. */
void pfe_ecu_receive(pfe_ecu_t *ecu, const pfe_can_frame_t *frame, uint64_t rx_us);

/* One tick at now_us (call every PFE_ECU_TICK_US). Writes the frames to send
 * into tx (at most tx_cap, PFE_ECU_TX_MAX is always enough) and returns how
 * many. */
uint32_t pfe_ecu_tick(pfe_ecu_t *ecu, uint64_t now_us, pfe_can_frame_t *tx, uint32_t tx_cap);

/* Reports from the main loop. */
void pfe_ecu_note_overrun(pfe_ecu_t *ecu, uint32_t ticks);
void pfe_ecu_note_tx_dropped(pfe_ecu_t *ecu, uint32_t frames);
void pfe_ecu_note_rx_dropped(pfe_ecu_t *ecu, uint32_t frames);
/* The CAN controller's state, from a backend that has one (sent in
 * PFE_DeviceStatus; its signals are not available until the first call). */
void pfe_ecu_note_bus_state(pfe_ecu_t *ecu, const pfe_ecu_bus_state_t *bus);
/* Cause of the last reset, once after pfe_ecu_init() (a cause outside the
 * enumeration is taken as PFE_RESET_OTHER). */
void pfe_ecu_note_reset_cause(pfe_ecu_t *ecu, pfe_reset_cause_t cause);

/*
 * NVM save path, in this order on one tick:
 *   pfe_ecu_nvm_due()      true once the save interval has run since the last
 *                          completed write (and so again on every tick after
 *                          a failed one: the retry);
 *   pfe_ecu_nvm_slot()     the slot to write: the other one than the last
 *                          completed write's; unchanged by a failure;
 *   pfe_ecu_nvm_take()     fills the record: the totals now, the sequence
 *                          after the last completed write's; changes nothing;
 *   pfe_ecu_nvm_written()  the write's result: 0 commits it (sequence and
 *                          slot advance, the interval restarts, nvm_failing
 *                          clears); anything else counts
 *                          count.nvm_write_failures, keeps slot, sequence and
 *                          interval, and the PFE_ECU_NVM_FAILING_AFTER-th
 *                          failure in a row sets nvm_failing.
 * A reset before pfe_ecu_nvm_written() loses nothing but the write: the boot
 * restores the last completed record. Each O(1).
 */
bool pfe_ecu_nvm_due(const pfe_ecu_t *ecu);
uint32_t pfe_ecu_nvm_slot(const pfe_ecu_t *ecu);
void pfe_ecu_nvm_take(const pfe_ecu_t *ecu, pfe_nvm_state_t *out);
void pfe_ecu_nvm_written(pfe_ecu_t *ecu, int result);

/* Fuel used so far, uL: own vehicle and platoon. */
uint64_t pfe_ecu_own_fuel_ul(const pfe_ecu_t *ecu);
uint64_t pfe_ecu_platoon_fuel_ul(const pfe_ecu_t *ecu);

#endif /* PFE_ECU_H */
