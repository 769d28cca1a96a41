/*
 * pfe_codec.h - decode and encode of every J1939 frame the module reads or
 * sends, in firmware units.
 *
 * can_dbc/pfe.dbc is the definition of the frames. pfe_codec_messages[]
 * and pfe_codec_signals[] are generated from it at build time by
 * sim_host/tools/dbc2c.c (build/gen/pfe_dbc.c; dbc2c --help): ids, PGNs,
 * layouts, scales, offsets, ranges, units, periods and value states; and
 * so is the header this one includes (build/gen/pfe_dbc.h): the PGN
 * macros, the received messages' periods, the table indices and each
 * signal's range in the firmware's unit. The
 * codec reads and writes raw values through that table only, and converts
 * them to firmware units with the table's scale in the firmware unit
 * (fw_num / fw_den, fw_offset): a scale, offset, range or unit changed in
 * the DBC changes the conversions with no other edit
 * (tests/codec_gen/codec_gen_test.sh). A host test
 * (tests/host/test_dbc_codec.c) checks the tables against an independent
 * reading of the DBC, both ways.
 *
 * Value states (J1939-71, docs/j1939.md). A decoded signal carries a
 * state next to its value:
 *   - raw in the error range (0xFE.., 2-bit 10b)        PFE_SIG_ERROR
 *   - raw in the not-available range (0xFF.., 2-bit 11b) PFE_SIG_NOT_AVAILABLE
 *   - raw parameter-specific (0xFB..) or reserved (0xFC..0xFD..), or in the
 *     valid area but outside the signal's [min, max]    PFE_SIG_OUT_OF_RANGE
 *   - otherwise                                         PFE_SIG_VALID
 * A value is meaningful only when VALID; decoders write 0 otherwise.
 * Signals without J1939 special ranges (NAME fields, counters of the
 * preview, enumerations whose every code is used) are VALID inside their
 * [min, max] and OUT_OF_RANGE outside.
 *
 * Encoders are the senders' side: a VALID input is converted, rounded to
 * nearest and, when it falls outside the signal's valid range, clamped to it
 * (a sender clamps, J1939-71). An OUT_OF_RANGE input is clamped the same way.
 * NOT_AVAILABLE and ERROR inputs are sent as the J1939 not-available and
 * error codes (all ones for a signal that has none). Unused bits are sent
 * as 1. An encoder returns a bit mask of the signals it clamped (bit n: the
 * message's n-th signal in pfe_codec_signals[] order, which is the DBC's),
 * 0 when none, or a negative error.
 *
 * Decoders check that the frame is extended, carries the message's PGN
 * (priority and source address masked, PDU1 destination masked) and has the
 * message's DLC (8, Request 3); otherwise they return PFE_CODEC_EID or
 * PFE_CODEC_EDLC and mark every output NOT_AVAILABLE.
 *
 * Units: speed mm/s, angles micro-degrees, grade ppm (tan of the angle,
 * 1e6 = 100 %), distances mm, times ms, fuel rate nL/s, fuel volume uL.
 * All functions are reentrant, use no memory but the caller's objects and
 * the stack (at most 112 bytes on the Cortex-M4, in pfe_preview_push()),
 * and run in constant time except pfe_codec_find_message() (O(number of
 * messages)).
 */
#ifndef PFE_CODEC_H
#define PFE_CODEC_H

#include <stdbool.h>
#include <stdint.h>

#include "pfe_can.h"
#include "pfe_dbc.h" /* generated from the DBC: see "messages" below */
#include "pfe_fixed.h"

/* ------------------------------------------------------------ errors */

#define PFE_CODEC_EID (-71)   /* not a 29-bit id, or another message's PGN */
#define PFE_CODEC_EDLC (-90)  /* data length differs from the message's */

/* ------------------------------------------------------------ value states */

typedef enum {
    PFE_SIG_VALID = 0,
    PFE_SIG_NOT_AVAILABLE = 1,
    PFE_SIG_ERROR = 2,
    PFE_SIG_OUT_OF_RANGE = 3
} pfe_sig_state_t;

typedef struct {
    int32_t value;
    pfe_sig_state_t state;
} pfe_sig_i32_t;

typedef struct {
    uint32_t value;
    pfe_sig_state_t state;
} pfe_sig_u32_t;

typedef struct {
    uint64_t value;
    pfe_sig_state_t state;
} pfe_sig_u64_t;

/* ------------------------------------------------------------ messages */

/* PFE_PGN_<MESSAGE> (each message's PGN), PFE_RX_PERIOD_MS_<MESSAGE> (each
 * received message's period), PFE_ECU_RX_FILTERS, pfe_msg_index_t and
 * pfe_sig_index_t come from the DBC: the build writes pfe_dbc.h with dbc2c
 * (its manual: dbc2c --help) and puts its folder on the include path. */

/* The module's default source address (it claims it with AddressClaimed). */
#define PFE_CODEC_DEFAULT_ADDRESS 0x8CU

#define PFE_CODEC_DIR_RX 1U  /* the module reads it */
#define PFE_CODEC_DIR_TX 2U  /* the module sends it */

/* One message of can_dbc/pfe.dbc. */
typedef struct {
    const char *name;        /* DBC message name */
    uint32_t pgn;
    uint8_t priority;        /* 0 .. 7, as sent */
    uint8_t dbc_address;     /* source address in the DBC id (0x00 inputs, 0x8C outputs) */
    uint8_t dlc;
    uint8_t direction;       /* PFE_CODEC_DIR_RX | PFE_CODEC_DIR_TX */
    uint16_t cycle_ms;       /* GenMsgCycleTime; 0: sent on event or request */
    uint8_t first_signal;    /* index in pfe_codec_signals[] */
    uint8_t n_signals;
} pfe_codec_message_t;

extern const pfe_codec_message_t pfe_codec_messages[PFE_MSG_COUNT];

/* The message a received id carries (priority, source and PDU1 destination
 * ignored), or NULL for an 11-bit id or a PGN not in the table. */
const pfe_codec_message_t *pfe_codec_find_message(uint32_t id);

/* ------------------------------------------------------------ signal table */

#define PFE_CODEC_LITTLE_ENDIAN 1U  /* DBC @1 (Intel); the only order J1939 uses */

#define PFE_CODEC_MUX_NONE (-1)     /* in every frame of its message */
#define PFE_CODEC_MUXER (-2)        /* the multiplexer itself (DBC M) */

#define PFE_CODEC_RANGES_NONE 0U    /* every raw value in [raw_min, raw_max] is valid */
#define PFE_CODEC_RANGES_J1939 1U   /* J1939-71 special ranges by length, see top */

/*
 * One signal of can_dbc/pfe.dbc. Physical value (in the DBC's unit):
 *     phys = raw * scale_num / scale_den + offset_num / offset_den
 * both exact rationals; the offset does not depend on raw or on the scale.
 * raw_min, raw_max bound the valid raw values; the DBC's [min|max] is their
 * physical value. In the firmware's unit of the signal (the field it is
 * decoded into: mm/s, udeg, ppm, nL/s, uL, ms, mm, kg, or a count):
 *     value = raw * fw_num / fw_den + fw_offset
 * exact (fw_offset a whole number of firmware units); decoders round the
 * quotient to nearest (halves up), encoders invert it rounded to nearest.
 * ranges is PFE_CODEC_RANGES_J1939 when the DBC's VAL_ names the signal's
 * all-ones code NotAvailable.
 *
 * An image built with PFE_CODEC_NO_NAMES (the Cortex-M4 and STM32 images)
 * keeps only what the firmware reads: the layout, the raw range and the
 * conversion to its unit (28 bytes a signal instead of 64); the names,
 * SPNs, the DBC's own scale and offset and the units are for host tools
 * and tests.
 */
typedef struct {
#ifndef PFE_CODEC_NO_NAMES
    const char *message;     /* DBC message name */
    uint32_t pgn;
    const char *name;        /* DBC signal name */
    uint32_t spn;            /* J1939 SPN; 0 for the module's own signals */
#endif
    uint8_t start_bit;       /* DBC start bit: the least significant bit (Intel) */
    uint8_t length;          /* bits, 1 .. 32 */
    uint8_t byte_order;      /* PFE_CODEC_LITTLE_ENDIAN */
    bool is_signed;          /* false for all: J1939 uses offsets */
    int8_t mux;              /* PFE_CODEC_MUX_NONE, PFE_CODEC_MUXER or the mux value (DBC mN) */
    uint8_t ranges;          /* PFE_CODEC_RANGES_* */
#ifndef PFE_CODEC_NO_NAMES
    int32_t scale_num;
    int32_t scale_den;       /* > 0 */
    int32_t offset_num;
    int32_t offset_den;      /* > 0 */
#endif
    uint32_t raw_min;
    uint32_t raw_max;
#ifndef PFE_CODEC_NO_NAMES
    const char *unit;        /* DBC unit */
#endif
    int32_t fw_num;          /* > 0 */
    int32_t fw_den;          /* > 0 */
    int32_t fw_offset;
} pfe_codec_signal_t;


extern const pfe_codec_signal_t pfe_codec_signals[PFE_CODEC_SIGNAL_COUNT];
extern const uint32_t pfe_codec_signal_count;

/* Raw value of a signal in an 8-byte payload (little endian, start bit = LSB). */
uint32_t pfe_codec_raw_get(const uint8_t data[PFE_CAN_MAX_DLC], const pfe_codec_signal_t *sig);

/* Writes raw (masked to the signal's length) into the payload; other bits unchanged. */
void pfe_codec_raw_put(uint8_t data[PFE_CAN_MAX_DLC], const pfe_codec_signal_t *sig, uint32_t raw);

/* State of a raw value (rules at the top of this file). */
pfe_sig_state_t pfe_codec_raw_state(const pfe_codec_signal_t *sig, uint32_t raw);

/* The raw code a sender writes for a state that is not VALID: the J1939
 * not-available (all ones) or error (0xFE.. / 10b) code; all ones for a
 * signal with PFE_CODEC_RANGES_NONE. VALID and OUT_OF_RANGE give all ones. */
uint32_t pfe_codec_raw_code(const pfe_codec_signal_t *sig, pfe_sig_state_t state);

/*
 * The decoded messages below. Each value is in the unit its name says
 * (mm/s, udeg, ppm, nL/s, uL, ms, mm, kg, ...). Its scale, offset and
 * [min|max] are the DBC's: a decoder gives raw * scale + offset in that
 * unit, rounded to nearest, and the range in that unit is
 * PFE_CSIG_<SIGNAL>_MIN .. PFE_CSIG_<SIGNAL>_MAX (pfe_dbc.h). An encoder
 * inverts it, rounded to nearest.
 */

/* ------------------------------------------------------------ CCVS1 (input) */

typedef struct {
    pfe_sig_i32_t speed_mm_s;   /* SPN 84 */
} pfe_msg_ccvs1_t;

int pfe_codec_decode_ccvs1(const pfe_can_frame_t *frame, pfe_msg_ccvs1_t *out);
int pfe_codec_encode_ccvs1(pfe_can_frame_t *frame, const pfe_msg_ccvs1_t *in, uint8_t source);

/* ------------------------------------------------------------ SSI (input) */

#define PFE_SSI_FOM_FULLY_FUNCTIONAL 0U
#define PFE_SSI_FOM_DEGRADED 1U

typedef struct {
    pfe_sig_i32_t pitch_udeg;   /* SPN 3318 */
    pfe_sig_i32_t roll_udeg;    /* SPN 3319 */
    pfe_sig_u32_t pitch_fom;    /* SPN 3323; PFE_SSI_FOM_* (10b ERROR, 11b NOT_AVAILABLE) */
} pfe_msg_ssi_t;

int pfe_codec_decode_ssi(const pfe_can_frame_t *frame, pfe_msg_ssi_t *out);
int pfe_codec_encode_ssi(pfe_can_frame_t *frame, const pfe_msg_ssi_t *in, uint8_t source);

/*
 * Road grade = tan(pitch) in ppm, for a pitch in micro-degrees.
 * Integer only: the angle in radians in Q32, the tangent's Taylor series to
 * x^17 (Horner in x^2, Q31), 32 x 32 -> 64-bit multiplies, no division.
 * Rounded to nearest; error at most 0.501 ppm of the exact tangent for
 * |pitch| <= 26.565051 deg (tan = 0.5), odd (f(-p) = -f(p)) and monotonic
 * in the pitch. Beyond, or whenever the rounded tangent exceeds 500000 ppm
 * in magnitude, the result is +-500000 (PFE_GRADE_MAX_PPM) and *saturated
 * is set to true (false otherwise); saturated may be NULL. O(1): about 50
 * instructions on the Cortex-M4 (inlined in the ECU tick).
 */
int32_t pfe_codec_grade_ppm_from_pitch(int32_t pitch_udeg, bool *saturated);

/* ------------------------------------------------------------ PFE_PlatoonConfig (input) */

typedef struct {
    pfe_sig_u32_t n_vehicles;      /* 1 .. 32 */
    pfe_sig_u32_t own_position;    /* 0 (lead) .. 31; OUT_OF_RANGE when >= a valid n_vehicles */
    pfe_sig_u32_t gap_mm;
    pfe_sig_u32_t time_gap_ms;
    pfe_sig_i32_t set_speed_mm_s;
} pfe_msg_platoon_config_t;

int pfe_codec_decode_platoon_config(const pfe_can_frame_t *frame, pfe_msg_platoon_config_t *out);
int pfe_codec_encode_platoon_config(pfe_can_frame_t *frame, const pfe_msg_platoon_config_t *in,
                                    uint8_t source);

/*
 * The gap the module uses: gap_mm when VALID, else time_gap_ms *
 * set_speed_mm_s / 1000 (rounded) when both are VALID. Returns PFE_SIG_VALID
 * with *gap_mm written, or PFE_SIG_NOT_AVAILABLE (*gap_mm = 0) when neither
 * is usable or an argument is NULL. Result below 4480000 mm.
 */
pfe_sig_state_t pfe_codec_platoon_gap_mm(const pfe_msg_platoon_config_t *cfg, uint32_t *gap_mm);

/* ------------------------------------------------------------ PFE_GradePreview (input) */

#define PFE_PREVIEW_MAX_SAMPLES 1000U
#define PFE_PREVIEW_SAMPLES_PER_FRAME 3U
#define PFE_PREVIEW_FRAME_HEADER 0U
#define PFE_PREVIEW_FRAME_DATA 1U

/* A decoded PFE_GradePreview frame. Signals of the other frame type read
 * NOT_AVAILABLE. */
typedef struct {
    pfe_sig_u32_t frame_type;      /* multiplexer: PFE_PREVIEW_FRAME_* */
    pfe_sig_u32_t preview_id;      /* 0 .. 15 */
    pfe_sig_u32_t sample_count;    /* header: 1 .. 1000 */
    pfe_sig_u32_t spacing_m;       /* header: 1 .. 250 */
    pfe_sig_u32_t first_index;     /* data: 0 .. 999 */
    pfe_sig_i32_t grade_ppm[PFE_PREVIEW_SAMPLES_PER_FRAME]; /* data */
} pfe_msg_grade_preview_t;

int pfe_codec_decode_grade_preview(const pfe_can_frame_t *frame, pfe_msg_grade_preview_t *out);
/* Writes the signals of in->frame_type's frame only; frame_type must be VALID
 * and 0 or 1 (else PFE_EINVAL). */
int pfe_codec_encode_grade_preview(pfe_can_frame_t *frame, const pfe_msg_grade_preview_t *in,
                                   uint8_t source);

/*
 * Preview reassembly. The caller owns the object (about 2 KB) and feeds it
 * every PFE_GradePreview frame in bus order. A header starts a new preview
 * and drops whatever was held; data frames must then follow with
 * SampleIndex 0, 3, 6 ... and the header's PreviewId, until SampleCount
 * samples have arrived. Any other frame is rejected: a preview still being
 * received is dropped (the receiver waits for the next header), while a
 * complete preview stays until a valid header replaces it.
 *
 * Samples are kept as received (raw, 2 bytes each) so that a sample the
 * sender marked not available stays so; read them with
 * pfe_preview_grade_ppm(), which reads sample i with the scale, offset and
 * range of the signal it came in (GradeSample0, 1 or 2: slot i % 3).
 */
typedef enum {
    PFE_PREVIEW_EMPTY = 0,      /* nothing held: waiting for a header */
    PFE_PREVIEW_RECEIVING = 1,  /* header seen, data frames arriving */
    PFE_PREVIEW_READY = 2       /* every sample received */
} pfe_preview_phase_t;

typedef struct {
    pfe_preview_phase_t phase;
    uint8_t preview_id;
    uint8_t spacing_m;
    uint16_t sample_count;
    uint16_t next_index;        /* first sample of the next data frame expected */
    uint16_t unusable_samples;  /* samples received that are not VALID */
    uint32_t frames_rejected;   /* saturating at UINT32_MAX */
    uint16_t raw[PFE_PREVIEW_MAX_SAMPLES];
} pfe_preview_t;

/* Results of pfe_preview_push() (>= 0: the frame was accepted). */
#define PFE_PREVIEW_INCOMPLETE 0  /* accepted; more frames expected (also: first header) */
#define PFE_PREVIEW_COMPLETE 1    /* accepted; the preview is complete */
#define PFE_PREVIEW_RESTARTED 2   /* a header replaced a preview (in progress or complete) */
/* Rejections (< 0), besides PFE_CODEC_EID, PFE_CODEC_EDLC and PFE_EINVAL: */
#define PFE_PREVIEW_EGAP (-201)     /* data frame ahead of the next expected: one is missing */
#define PFE_PREVIEW_EORDER (-202)   /* data frame behind the next expected: repeated or late */
#define PFE_PREVIEW_ENOHEADER (-203) /* data frame with no preview in progress, or of another PreviewId */
#define PFE_PREVIEW_ECOUNT (-204)   /* header count or spacing invalid, or data beyond the count */
#define PFE_PREVIEW_EFIELD (-205)   /* frame type or PreviewId not valid */

/* Empties the object. */
void pfe_preview_init(pfe_preview_t *pv);

/* Takes one PFE_GradePreview frame; returns a result above. O(1). */
int pfe_preview_push(pfe_preview_t *pv, const pfe_can_frame_t *frame);

/* Sample index (0 .. sample_count - 1) of a READY preview in ppm. Returns the
 * sample's state (PFE_SIG_NOT_AVAILABLE for an index past the count or a
 * preview not READY); *grade_ppm is 0 unless VALID. */
pfe_sig_state_t pfe_preview_grade_ppm(const pfe_preview_t *pv, uint32_t index, int32_t *grade_ppm);

/* Samples first .. first + count - 1 (fewer at the end) of a READY preview
 * whose every sample is VALID (unusable_samples 0) into grade_ppm, in ppm
 * as pfe_preview_grade_ppm() gives them, without its per-sample check.
 * Returns how many, 0 when the preview is not such. */
uint32_t pfe_preview_copy_ppm(const pfe_preview_t *pv, uint32_t first, uint32_t count,
                              int32_t *grade_ppm);

/* ------------------------------------------------------------ LFE1 (output) */

typedef struct {
    pfe_sig_u32_t fuel_rate_nl_s;  /* SPN 183 */
} pfe_msg_lfe1_t;

int pfe_codec_decode_lfe1(const pfe_can_frame_t *frame, pfe_msg_lfe1_t *out);
int pfe_codec_encode_lfe1(pfe_can_frame_t *frame, const pfe_msg_lfe1_t *in, uint8_t source);

/* ------------------------------------------------------------ PFE_PlatoonFuel (output) */

typedef struct {
    pfe_sig_u32_t fuel_rate_nl_s;
    pfe_sig_u64_t fuel_used_ul;
} pfe_msg_platoon_fuel_t;

int pfe_codec_decode_platoon_fuel(const pfe_can_frame_t *frame, pfe_msg_platoon_fuel_t *out);
int pfe_codec_encode_platoon_fuel(pfe_can_frame_t *frame, const pfe_msg_platoon_fuel_t *in,
                                  uint8_t source);

/* ------------------------------------------------------------ HRLFC (output) */

typedef struct {
    pfe_sig_u64_t trip_fuel_ul;    /* SPN 5053; the module sends it not available */
    pfe_sig_u64_t total_fuel_ul;   /* SPN 5054 */
} pfe_msg_hrlfc_t;

int pfe_codec_decode_hrlfc(const pfe_can_frame_t *frame, pfe_msg_hrlfc_t *out);
int pfe_codec_encode_hrlfc(pfe_can_frame_t *frame, const pfe_msg_hrlfc_t *in, uint8_t source);

/* ------------------------------------------------------------ PFE_FuelPrediction (output) */

typedef struct {
    pfe_sig_u32_t fuel_ul;
    pfe_sig_u32_t fuel_lower_ul;
    pfe_sig_u32_t fuel_upper_ul;
    pfe_sig_u32_t time_ms;
} pfe_msg_fuel_prediction_t;

int pfe_codec_decode_fuel_prediction(const pfe_can_frame_t *frame, pfe_msg_fuel_prediction_t *out);
int pfe_codec_encode_fuel_prediction(pfe_can_frame_t *frame, const pfe_msg_fuel_prediction_t *in,
                                     uint8_t source);

/* ------------------------------------------------------------ PFE_Status (output) */

/* Wire codes of an input state (J1939 2-bit convention for 10b and 11b). */
#define PFE_STATUS_INPUT_VALID 0U
#define PFE_STATUS_INPUT_OUT_OF_RANGE 1U
#define PFE_STATUS_INPUT_ERROR 2U
#define PFE_STATUS_INPUT_NOT_AVAILABLE 3U  /* also: timed out */

#define PFE_MODE_NORMAL 0U       /* every input valid */
#define PFE_MODE_DEGRADED 1U     /* estimate available; platoon config or preview missing */
#define PFE_MODE_NO_ESTIMATE 2U  /* speed or grade missing: fuel outputs not available */

/* Counters are sent up to 250 (0xFA, the top of J1939's valid range) and
 * hold there; a larger input is clamped (and reported so). */
#define PFE_STATUS_COUNTER_MAX 250U

typedef struct {
    pfe_sig_state_t speed_input;           /* always a plain state: never "not available" itself */
    pfe_sig_state_t grade_input;
    pfe_sig_state_t platoon_config_input;
    pfe_sig_state_t grade_preview_input;
    pfe_sig_u32_t mode;                    /* PFE_MODE_* */
    pfe_sig_u32_t rx_frames_dropped;
    pfe_sig_u32_t tick_overruns;
    pfe_sig_u32_t tx_frames_dropped;
    pfe_sig_u32_t warming_up;              /* 0 off, 1 on */
    pfe_sig_u32_t speed_clamped;
    pfe_sig_u32_t grade_clamped;
    pfe_sig_u32_t output_saturated;
    pfe_sig_u32_t inputs_rejected;         /* counter, 0 .. PFE_STATUS_COUNTER_MAX */
    pfe_sig_u32_t address_conflicts;       /* counter, 0 .. PFE_STATUS_COUNTER_MAX */
} pfe_msg_status_t;

int pfe_codec_decode_status(const pfe_can_frame_t *frame, pfe_msg_status_t *out);
/* An input state outside the enumeration gives PFE_EINVAL. */
int pfe_codec_encode_status(pfe_can_frame_t *frame, const pfe_msg_status_t *in, uint8_t source);

/* ------------------------------------------------------------ NAME, AddressClaimed */

/* The J1939-81 NAME, least significant field first. */
typedef struct {
    uint32_t identity_number;       /* 21 bits, SPN 2837 */
    uint16_t manufacturer_code;     /* 11 bits, SPN 2838 */
    uint8_t ecu_instance;           /*  3 bits, SPN 2840 */
    uint8_t function_instance;      /*  5 bits, SPN 2839 */
    uint8_t function;               /*  8 bits, SPN 2841 */
    uint8_t reserved;               /*  1 bit, 0 when sent */
    uint8_t vehicle_system;         /*  7 bits, SPN 2842 */
    uint8_t vehicle_system_instance; /* 4 bits, SPN 2843 */
    uint8_t industry_group;         /*  3 bits, SPN 2846 */
    bool arbitrary_address_capable; /*  1 bit, SPN 2844 */
} pfe_j1939_name_t;

/* NAME as the 64-bit number J1939-81 compares (lower wins arbitration).
 * PFE_EINVAL when a field does not fit its width or an argument is NULL. */
int pfe_j1939_name_pack(const pfe_j1939_name_t *name, uint64_t *out);
void pfe_j1939_name_unpack(uint64_t value, pfe_j1939_name_t *out);

/* AddressClaimed to the global address from source. */
int pfe_codec_encode_address_claimed(pfe_can_frame_t *frame, const pfe_j1939_name_t *name,
                                     uint8_t source);
/* The claimant is pfe_j1939_source(frame->id). */
int pfe_codec_decode_address_claimed(const pfe_can_frame_t *frame, pfe_j1939_name_t *out);

/* ------------------------------------------------------------ Request */

typedef struct {
    pfe_sig_u32_t pgn;              /* SPN 2540; OUT_OF_RANGE above 0x3FFFF */
    uint8_t destination;            /* from the id: the module's address or PFE_J1939_ADDR_GLOBAL */
    uint8_t source;
} pfe_msg_request_t;

int pfe_codec_decode_request(const pfe_can_frame_t *frame, pfe_msg_request_t *out);
/* 3-byte Request for pgn (<= 0x3FFFF, else PFE_EINVAL), priority 6. */
int pfe_codec_encode_request(pfe_can_frame_t *frame, uint32_t pgn, uint8_t destination,
                             uint8_t source);

/* ------------------------------------------------------------ VDS (input) */

typedef struct {
    pfe_sig_u32_t bearing_mdeg;     /* SPN 165 */
    pfe_sig_i32_t nav_speed_mm_s;   /* SPN 517 */
    pfe_sig_i32_t pitch_mdeg;       /* SPN 583 */
    pfe_sig_i32_t altitude_mm;      /* SPN 580 */
} pfe_msg_vds_t;

int pfe_codec_decode_vds(const pfe_can_frame_t *frame, pfe_msg_vds_t *out);
int pfe_codec_encode_vds(pfe_can_frame_t *frame, const pfe_msg_vds_t *in, uint8_t source);

/* ------------------------------------------------------------ CVW (input) */

typedef struct {
    pfe_sig_u32_t powered_vehicle_kg;     /* SPN 1585 */
    pfe_sig_u32_t gross_combination_kg;   /* SPN 1760 */
} pfe_msg_cvw_t;

int pfe_codec_decode_cvw(const pfe_can_frame_t *frame, pfe_msg_cvw_t *out);
int pfe_codec_encode_cvw(pfe_can_frame_t *frame, const pfe_msg_cvw_t *in, uint8_t source);

/* ------------------------------------------------------------ PFE_OwnFuel (output) */

typedef struct {
    pfe_sig_u32_t fuel_rate_nl_s;
    pfe_sig_u64_t fuel_used_ul;
    pfe_sig_u32_t model_identified; /* 0 calibrated, 1 identified */
} pfe_msg_own_fuel_t;

int pfe_codec_decode_own_fuel(const pfe_can_frame_t *frame, pfe_msg_own_fuel_t *out);
int pfe_codec_encode_own_fuel(pfe_can_frame_t *frame, const pfe_msg_own_fuel_t *in, uint8_t source);

/* ------------------------------------------------------------ PFE_InputStatus (output) */

#define PFE_GRADE_SOURCE_SLOPE_SENSOR 0U
#define PFE_GRADE_SOURCE_ALTITUDE 1U
#define PFE_GRADE_SOURCE_ASSUMED_FLAT 2U
#define PFE_GRADE_SOURCE_NONE 3U

#define PFE_MASS_SOURCE_CALIBRATION 0U
#define PFE_MASS_SOURCE_CVW 1U
#define PFE_MASS_SOURCE_IDENTIFIED 2U

#define PFE_INPUT_SENDERS_MAX 15U

typedef struct {
    pfe_sig_u32_t speed_source;     /* source address 0 .. 253; NOT_AVAILABLE: none */
    pfe_sig_u32_t grade_source_address;
    pfe_sig_u32_t fuel_rate_source;
    pfe_sig_u32_t speed_senders;    /* 0 .. PFE_INPUT_SENDERS_MAX */
    pfe_sig_u32_t grade_senders;
    pfe_sig_u32_t grade_source;     /* PFE_GRADE_SOURCE_* */
    pfe_sig_u32_t mass_source;      /* PFE_MASS_SOURCE_* */
    pfe_sig_u32_t identification;   /* 0 learning, 1 converged */
    pfe_sig_u32_t vehicle_mass_kg;
} pfe_msg_input_status_t;

int pfe_codec_decode_input_status(const pfe_can_frame_t *frame, pfe_msg_input_status_t *out);
int pfe_codec_encode_input_status(pfe_can_frame_t *frame, const pfe_msg_input_status_t *in,
                                  uint8_t source);

/* ------------------------------------------------------------ PFE_DeviceStatus (output) */

typedef struct {
    pfe_sig_u32_t rx_fifo_overruns;   /* counter, 0 .. PFE_STATUS_COUNTER_MAX */
    pfe_sig_u32_t bus_off_events;     /* counter */
    pfe_sig_u32_t error_warning;      /* 0 off, 1 on */
    pfe_sig_u32_t error_passive;
    pfe_sig_u32_t bus_off;
    pfe_sig_u32_t nvm_write_failing;
    pfe_sig_u32_t reset_cause;        /* 0 power-on, 1 watchdog, 2 software, 3 other */
    pfe_sig_u32_t tx_error_counter;   /* 0 .. 250 */
    pfe_sig_u32_t rx_error_counter;
    pfe_sig_u32_t nvm_write_failures; /* counter */
} pfe_msg_device_status_t;

int pfe_codec_decode_device_status(const pfe_can_frame_t *frame, pfe_msg_device_status_t *out);
int pfe_codec_encode_device_status(pfe_can_frame_t *frame, const pfe_msg_device_status_t *in,
                                   uint8_t source);

#endif /* PFE_CODEC_H */
