/* pfe_codec.c - J1939 frames of can_dbc/pfe.dbc (contract in pfe_codec.h). */
#include "pfe_codec.h"

#include <stddef.h>
#include <string.h>

#include "pfe_calib.h"

/* The encoders' per-signal steps (payload_put(), enc_put()) are forced
 * inline: at each call the signal is a constant entry of pfe_codec_signals[],
 * so its position, length and limits fold into a few instructions, and the
 * image gets smaller rather than larger. On the Cortex-M4 (GCC 12, -O2 -flto)
 * the ECU's PFE_Status, twelve signals, took about 640 instructions with
 * calls and takes about 170 inlined. */
#define ALWAYS_INLINE PFE_ALWAYS_INLINE

/* ------------------------------------------------------------ tables */

/* pfe_codec_messages[] and pfe_codec_signals[] are written from
 * can_dbc/pfe.dbc at build time by sim_host/tools/dbc2c.c (build/gen/pfe_dbc.c). */

const uint32_t pfe_codec_signal_count = (uint32_t)PFE_CODEC_SIGNAL_COUNT;

const pfe_codec_message_t *pfe_codec_find_message(uint32_t id)
{
    if ((id & PFE_CAN_EFF_FLAG) == 0U) {
        return NULL;
    }
    const uint32_t pgn = pfe_j1939_pgn(id & PFE_CAN_ID_MASK);
    for (uint32_t m = 0U; m < (uint32_t)PFE_MSG_COUNT; m++) {
        if (pfe_codec_messages[m].pgn == pgn) {
            return &pfe_codec_messages[m];
        }
    }
    return NULL;
}

/* ------------------------------------------------------------ raw access */

/* A payload as two 32-bit words, bytes 0..3 and 4..7, each little endian:
 * the Cortex-M4 shifts a 32-bit word in one instruction, a 64-bit one in
 * about eight. */
typedef struct {
    uint32_t lo;
    uint32_t hi;
} payload_t;

/* Written out byte by byte, so that the order is the DBC's on any host; GCC
 * merges each word into one load or store on a little-endian target (seen on
 * the Cortex-M4 with GCC 12). */
static payload_t payload_load(const uint8_t data[PFE_CAN_MAX_DLC])
{
    const payload_t p = {
        (uint32_t)data[0] | ((uint32_t)data[1] << 8) | ((uint32_t)data[2] << 16) |
            ((uint32_t)data[3] << 24),
        (uint32_t)data[4] | ((uint32_t)data[5] << 8) | ((uint32_t)data[6] << 16) |
            ((uint32_t)data[7] << 24)};
    return p;
}

static void payload_store(uint8_t data[PFE_CAN_MAX_DLC], payload_t p)
{
    data[0] = (uint8_t)p.lo;
    data[1] = (uint8_t)(p.lo >> 8);
    data[2] = (uint8_t)(p.lo >> 16);
    data[3] = (uint8_t)(p.lo >> 24);
    data[4] = (uint8_t)p.hi;
    data[5] = (uint8_t)(p.hi >> 8);
    data[6] = (uint8_t)(p.hi >> 16);
    data[7] = (uint8_t)(p.hi >> 24);
}

static bool sig_fits(const pfe_codec_signal_t *sig)
{
    return (sig->length >= 1U) && (sig->length <= 32U) &&
           (((uint32_t)sig->start_bit + (uint32_t)sig->length) <= 64U);
}

static uint32_t sig_mask(const pfe_codec_signal_t *sig)
{
    return (sig->length >= 32U) ? UINT32_MAX : (((uint32_t)1U << sig->length) - 1U);
}

/* The signal's bits of a payload; the signal fits (sig_fits()). Every shift
 * count is 0 .. 31. Inlined: with a table entry named by a constant index
 * its tests fold away. */
static ALWAYS_INLINE uint32_t payload_get(payload_t p, const pfe_codec_signal_t *sig)
{
    const uint32_t start = sig->start_bit;
    uint32_t v;
    if (start >= 32U) {
        v = p.hi >> (start - 32U);
    } else if (start == 0U) {
        v = p.lo;
    } else {
        v = (p.lo >> start) | (p.hi << (32U - start)); /* straddles, or bits of lo only */
    }
    return v & sig_mask(sig);
}

/* Writes raw (masked to the length) into the signal's bits; the signal fits
 * (sig_fits()). Every shift count is 0 .. 31. */
static ALWAYS_INLINE void payload_put(payload_t *p, const pfe_codec_signal_t *sig, uint32_t raw)
{
    const uint32_t start = sig->start_bit;
    const uint32_t m = sig_mask(sig);
    const uint32_t v = raw & m;
    if (start >= 32U) {
        const uint32_t s = start - 32U;
        p->hi = (p->hi & ~(m << s)) | (v << s);
    } else {
        /* bits start .. 31 of lo; any higher bits go to the bottom of hi */
        p->lo = (p->lo & ~(m << start)) | (v << start);
        if ((start + (uint32_t)sig->length) > 32U) {
            const uint32_t s = 32U - start; /* 1 .. 31: start is not 0 here */
            p->hi = (p->hi & ~(m >> s)) | (v >> s);
        }
    }
}

uint32_t pfe_codec_raw_get(const uint8_t data[PFE_CAN_MAX_DLC], const pfe_codec_signal_t *sig)
{
    if ((data == NULL) || (sig == NULL) || !sig_fits(sig)) {
        return 0U;
    }
    return payload_get(payload_load(data), sig);
}

void pfe_codec_raw_put(uint8_t data[PFE_CAN_MAX_DLC], const pfe_codec_signal_t *sig, uint32_t raw)
{
    if ((data == NULL) || (sig == NULL) || !sig_fits(sig)) {
        return;
    }
    payload_t p = payload_load(data);
    payload_put(&p, sig, raw);
    payload_store(data, p);
}

/* pfe_codec_raw_state() for a signal that is not NULL; inlined, as
 * payload_get(). */
static ALWAYS_INLINE pfe_sig_state_t raw_state_of(const pfe_codec_signal_t *sig, uint32_t raw)
{
    if (sig->ranges == PFE_CODEC_RANGES_J1939) {
        if (sig->length == 2U) {
            if (raw == 3U) {
                return PFE_SIG_NOT_AVAILABLE;
            }
            if (raw == 2U) {
                return PFE_SIG_ERROR;
            }
        } else if ((sig->length >= 8U) && (sig->length <= 32U) && ((sig->length % 8U) == 0U)) {
            /* The most significant byte selects the range (J1939-71). */
            const uint32_t top = raw >> (sig->length - 8U);
            if (top == 0xFFU) {
                return PFE_SIG_NOT_AVAILABLE;
            }
            if (top == 0xFEU) {
                return PFE_SIG_ERROR;
            }
            if (top >= 0xFBU) {
                return PFE_SIG_OUT_OF_RANGE; /* parameter-specific or reserved */
            }
        } else {
            /* no other lengths carry J1939 ranges in this table */
        }
    }
    if ((raw < sig->raw_min) || (raw > sig->raw_max)) {
        return PFE_SIG_OUT_OF_RANGE;
    }
    return PFE_SIG_VALID;
}

pfe_sig_state_t pfe_codec_raw_state(const pfe_codec_signal_t *sig, uint32_t raw)
{
    if (sig == NULL) {
        return PFE_SIG_NOT_AVAILABLE;
    }
    return raw_state_of(sig, raw);
}

uint32_t pfe_codec_raw_code(const pfe_codec_signal_t *sig, pfe_sig_state_t state)
{
    if (sig == NULL) {
        return UINT32_MAX;
    }
    const uint32_t ones = sig_mask(sig);
    if ((state == PFE_SIG_ERROR) && (sig->ranges == PFE_CODEC_RANGES_J1939)) {
        if (sig->length == 2U) {
            return 2U;
        }
        if ((sig->length >= 8U) && ((sig->length % 8U) == 0U)) {
            /* 0xFE in the top byte, the rest (don't care) as ones */
            return ones & ~((uint32_t)1U << (sig->length - 8U));
        }
    }
    return ones;
}

/* ------------------------------------------------------------ helpers */

/* num / den rounded to nearest, halves toward +infinity; den > 0, |num| < 2^61. */
static int64_t div_round_i64(int64_t num, int64_t den)
{
    const int64_t n2 = (2 * num) + den;
    const int64_t d2 = 2 * den;
    int64_t q = n2 / d2;
    if (((n2 % d2) != 0) && (n2 < 0)) {
        q -= 1; /* floor */
    }
    return q;
}

static int check_frame(const pfe_can_frame_t *frame, pfe_msg_index_t msg)
{
    if (frame == NULL) {
        return PFE_EINVAL;
    }
    if (((frame->id & PFE_CAN_EFF_FLAG) == 0U) ||
        (pfe_j1939_pgn(frame->id & PFE_CAN_ID_MASK) != pfe_codec_messages[msg].pgn)) {
        return PFE_CODEC_EID;
    }
    if (frame->dlc != pfe_codec_messages[msg].dlc) {
        return PFE_CODEC_EDLC;
    }
    return PFE_OK;
}

/* Raw value and state of one signal of a received frame. */
static pfe_sig_state_t get_raw(const pfe_can_frame_t *frame, pfe_sig_index_t i, uint32_t *raw)
{
    *raw = pfe_codec_raw_get(frame->data, &pfe_codec_signals[i]);
    return pfe_codec_raw_state(&pfe_codec_signals[i], *raw);
}

/* Firmware value of a valid raw count (raw <= raw_max): raw * fw_num /
 * fw_den rounded to nearest, halves up, plus fw_offset (pfe_codec.h). At
 * each call the signal is a constant entry of pfe_codec_signals[], so the
 * branches fold: a count is the raw value itself, a scale whose products
 * stay below 2^32 (speed, angles, grades) takes 32-bit arithmetic, a larger
 * one (fuel rate) a 64-bit product and division. */
static ALWAYS_INLINE int64_t fw_of_raw(const pfe_codec_signal_t *sig, uint32_t raw)
{
    const uint32_t num = (uint32_t)sig->fw_num;
    const uint32_t den = (uint32_t)sig->fw_den;
    const uint64_t num64 = num;
    const uint64_t den64 = den;
    uint64_t v;
    if (den == 1U) {
        v = (num == 1U) ? (uint64_t)raw : ((uint64_t)raw * num64);
    } else if ((((uint64_t)sig->raw_max * num64) + (den64 / 2U)) <= UINT32_MAX) {
        const uint32_t q = ((raw * num) + (den / 2U)) / den;
        v = q;
    } else {
        v = (((uint64_t)raw * num64) + (den64 / 2U)) / den64;
    }
    return (int64_t)v + sig->fw_offset; /* dbc2c: the result fits the field's type */
}

static ALWAYS_INLINE pfe_sig_u32_t dec_u32(const pfe_can_frame_t *frame, pfe_sig_index_t i)
{
    uint32_t raw;
    const pfe_sig_state_t st = get_raw(frame, i, &raw);
    const pfe_sig_u32_t out = {(st == PFE_SIG_VALID) ? (uint32_t)fw_of_raw(&pfe_codec_signals[i], raw) : 0U,
                               st};
    return out;
}

static ALWAYS_INLINE pfe_sig_i32_t dec_i32(const pfe_can_frame_t *frame, pfe_sig_index_t i)
{
    uint32_t raw;
    const pfe_sig_state_t st = get_raw(frame, i, &raw);
    const pfe_sig_i32_t out = {(st == PFE_SIG_VALID) ? (int32_t)fw_of_raw(&pfe_codec_signals[i], raw) : 0, st};
    return out;
}

/* dec_u32() and dec_i32() of a payload loaded once, every step inlined: for
 * the frames of every tick (SSI, CCVS1), where the generic path's calls
 * cost more than the decoding. Same results. */
static ALWAYS_INLINE pfe_sig_state_t raw_at(payload_t p, pfe_sig_index_t i, uint32_t *raw)
{
    *raw = payload_get(p, &pfe_codec_signals[i]);
    return raw_state_of(&pfe_codec_signals[i], *raw);
}
static ALWAYS_INLINE pfe_sig_u32_t dec_u32_at(payload_t p, pfe_sig_index_t i)
{
    uint32_t raw;
    const pfe_sig_state_t st = raw_at(p, i, &raw);
    const pfe_sig_u32_t out = {(st == PFE_SIG_VALID) ? (uint32_t)fw_of_raw(&pfe_codec_signals[i], raw) : 0U,
                               st};
    return out;
}
static ALWAYS_INLINE pfe_sig_i32_t dec_i32_at(payload_t p, pfe_sig_index_t i)
{
    uint32_t raw;
    const pfe_sig_state_t st = raw_at(p, i, &raw);
    const pfe_sig_i32_t out = {(st == PFE_SIG_VALID) ? (int32_t)fw_of_raw(&pfe_codec_signals[i], raw) : 0, st};
    return out;
}

static ALWAYS_INLINE pfe_sig_u64_t dec_u64(const pfe_can_frame_t *frame, pfe_sig_index_t i)
{
    uint32_t raw;
    const pfe_sig_state_t st = get_raw(frame, i, &raw);
    const pfe_sig_u64_t out = {(st == PFE_SIG_VALID) ? (uint64_t)fw_of_raw(&pfe_codec_signals[i], raw) : 0U,
                               st};
    return out;
}

static const pfe_sig_u32_t u32_na = {0U, PFE_SIG_NOT_AVAILABLE};
static const pfe_sig_i32_t i32_na = {0, PFE_SIG_NOT_AVAILABLE};
static const pfe_sig_u64_t u64_na = {0U, PFE_SIG_NOT_AVAILABLE};

/* Encoding: one message's payload, built in a register and stored once by
 * enc_end(), and the mask of clamped signals. */
typedef struct {
    pfe_can_frame_t *frame;
    payload_t payload;
    uint32_t first;
    uint32_t clamped;
} enc_t;

static int enc_begin(enc_t *e, pfe_can_frame_t *frame, pfe_msg_index_t msg, uint8_t destination,
                     uint8_t source)
{
    if (frame == NULL) {
        return PFE_EINVAL;
    }
    const pfe_codec_message_t *m = &pfe_codec_messages[msg];
    frame->id = pfe_j1939_id(m->priority, m->pgn, destination, source);
    frame->dlc = m->dlc;
    e->frame = frame;
    e->payload.lo = UINT32_MAX; /* unused bits are sent as 1 */
    e->payload.hi = UINT32_MAX;
    e->first = m->first_signal;
    e->clamped = 0U;
    return PFE_OK;
}

/* Writes a value already in raw counts (any int64), clamped to the valid
 * range, or the code for a NOT_AVAILABLE or ERROR state. */
static ALWAYS_INLINE void enc_put(enc_t *e, pfe_sig_index_t i, pfe_sig_state_t state, int64_t raw)
{
    const pfe_codec_signal_t *sig = &pfe_codec_signals[i];
    if ((state == PFE_SIG_NOT_AVAILABLE) || (state == PFE_SIG_ERROR)) {
        payload_put(&e->payload, sig, pfe_codec_raw_code(sig, state));
        return;
    }
    int64_t r = raw;
    if ((r < (int64_t)sig->raw_min) || (r > (int64_t)sig->raw_max)) {
        r = (r < (int64_t)sig->raw_min) ? (int64_t)sig->raw_min : (int64_t)sig->raw_max;
        e->clamped |= (uint32_t)1U << ((uint32_t)i - e->first);
    }
    payload_put(&e->payload, sig, (uint32_t)r);
}

/* Every encoder ends here: the only write of the payload. */
static int enc_end(const enc_t *e)
{
    payload_store(e->frame->data, e->payload);
    return (int)e->clamped;
}

/* Raw count of a signed firmware value: (value - fw_offset) * fw_den /
 * fw_num rounded to nearest, halves up; |product| < 2^63. */
static ALWAYS_INLINE int64_t raw_of_i32(pfe_sig_index_t i, int32_t value)
{
    const pfe_codec_signal_t *sig = &pfe_codec_signals[i];
    return div_round_i64(((int64_t)value - sig->fw_offset) * sig->fw_den, sig->fw_num);
}

/* Dividing n by a constant above PFE_UDIV_SMALL_MAX that is a multiple of
 * 1000 (0.05 L/h is 125000/9 nL/s) takes two cheap divisions, by 1000 and
 * by the rest: floor(floor(n / a) / b) = floor(n / (a b)). */
#define SPLIT_DIVISOR 1000U

/* Raw count of an unsigned firmware value, as raw_of_i32(); a value below
 * the offset gives -1 and one whose raw count passes INT64_MAX gives
 * INT64_MAX (both clamped by enc_put()). */
static ALWAYS_INLINE int64_t raw_of_u64(pfe_sig_index_t i, uint64_t value)
{
    const pfe_codec_signal_t *sig = &pfe_codec_signals[i];
    const uint64_t num = (uint64_t)(uint32_t)sig->fw_num;
    const uint64_t den = (uint64_t)(uint32_t)sig->fw_den;
    uint64_t x = value;
    bool below = false;
    if (sig->fw_offset > 0) {
        const uint64_t off = (uint64_t)(uint32_t)sig->fw_offset;
        below = x < off;
        x = below ? 0U : (x - off);
    } else if (sig->fw_offset < 0) {
        const uint64_t off = (uint64_t)(-(int64_t)sig->fw_offset);
        x = (x > (UINT64_MAX - off)) ? UINT64_MAX : (x + off);
    } else {
        /* no offset */
    }
    uint64_t q;
    if ((num == 1U) && (den == 1U)) {
        q = x;
    } else if (den == 1U) {
        q = pfe_udiv_round_u64(x, num);
    } else if (x > ((UINT64_MAX - num) / den)) {
        q = UINT64_MAX;
    } else {
        const uint64_t n = (x * den) + (num / 2U);
        if ((num > PFE_UDIV_SMALL_MAX) && ((num % SPLIT_DIVISOR) == 0U) &&
            ((num / SPLIT_DIVISOR) <= PFE_UDIV_SMALL_MAX)) {
            q = pfe_udiv_u64(pfe_udiv_u64(n, SPLIT_DIVISOR, NULL), num / SPLIT_DIVISOR, NULL);
        } else {
            q = pfe_udiv_u64(n, num, NULL);
        }
    }
    int64_t raw = (q > (uint64_t)INT64_MAX) ? INT64_MAX : (int64_t)q;
    if (below) {
        raw = -1;
    }
    return raw;
}

/* ------------------------------------------------------------ CCVS1 */

int pfe_codec_decode_ccvs1(const pfe_can_frame_t *frame, pfe_msg_ccvs1_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->speed_mm_s = i32_na;
    const int rc = check_frame(frame, PFE_MSG_CCVS1);
    if (rc != PFE_OK) {
        return rc;
    }
    out->speed_mm_s = dec_i32_at(payload_load(frame->data), PFE_CSIG_CCVS1_WHEEL_BASED_VEHICLE_SPEED); /* CCVS1.WheelBasedVehicleSpeed (SPN 84) */
    return PFE_OK;
}

int pfe_codec_encode_ccvs1(pfe_can_frame_t *frame, const pfe_msg_ccvs1_t *in, uint8_t source)
{
    enc_t e;
    if ((in == NULL) || (enc_begin(&e, frame, PFE_MSG_CCVS1, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_CCVS1_WHEEL_BASED_VEHICLE_SPEED, in->speed_mm_s.state,
            raw_of_i32(PFE_CSIG_CCVS1_WHEEL_BASED_VEHICLE_SPEED, in->speed_mm_s.value));
    return enc_end(&e);
}

/* ------------------------------------------------------------ SSI */

int pfe_codec_decode_ssi(const pfe_can_frame_t *frame, pfe_msg_ssi_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->pitch_udeg = i32_na;
    out->roll_udeg = i32_na;
    out->pitch_fom = u32_na;
    const int rc = check_frame(frame, PFE_MSG_SSI);
    if (rc != PFE_OK) {
        return rc;
    }
    const payload_t p = payload_load(frame->data);
    out->pitch_udeg = dec_i32_at(p, PFE_CSIG_SSI_PITCH_ANGLE);          /* SSI.PitchAngle (SPN 3318) */
    out->roll_udeg = dec_i32_at(p, PFE_CSIG_SSI_ROLL_ANGLE);            /* SSI.RollAngle (SPN 3319) */
    out->pitch_fom = dec_u32_at(p, PFE_CSIG_SSI_PITCH_ANGLE_FOM);       /* SSI.PitchAngleFigureOfMerit (SPN 3323) */
    return PFE_OK;
}

int pfe_codec_encode_ssi(pfe_can_frame_t *frame, const pfe_msg_ssi_t *in, uint8_t source)
{
    enc_t e;
    if ((in == NULL) || (enc_begin(&e, frame, PFE_MSG_SSI, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_SSI_PITCH_ANGLE, in->pitch_udeg.state,
            raw_of_i32(PFE_CSIG_SSI_PITCH_ANGLE, in->pitch_udeg.value));
    enc_put(&e, PFE_CSIG_SSI_ROLL_ANGLE, in->roll_udeg.state,
            raw_of_i32(PFE_CSIG_SSI_ROLL_ANGLE, in->roll_udeg.value));
    enc_put(&e, PFE_CSIG_SSI_PITCH_ANGLE_FOM, in->pitch_fom.state,
            raw_of_u64(PFE_CSIG_SSI_PITCH_ANGLE_FOM, in->pitch_fom.value));
    return enc_end(&e);
}

/* Beyond 26.6 deg the tangent (0.50076) is past the limit whatever the rounding. */
#define PITCH_SATURATED_UDEG 26600000U
/* pi / 180e6 * 2^57, rounded (2515284534.05): micro-degrees times 2^7 to
 * radians in Q32 by a high-half product. Its rounding moves x by at most
 * 1.1e-11 rad. */
#define UDEG_TO_RAD_Q57 2515284534U
/* tan x = x (1 + x^2/3 + 2x^4/15 + 17x^6/315 + 62x^8/2835 + 1382x^10/155925
 *          + 21844x^12/6081075 + 929569x^14/638512875
 *          + 6404582x^16/10854718875 + ...)
 * (Taylor series; every term positive): the coefficients in Q31, rounded.
 * Cut after x^17, the next terms add less than 0.00013 ppm at 26.6 deg. */
#define TAN_Q31_C0 2147483648U /* 1 */
#define TAN_Q31_C1 715827883U  /* 1/3 */
#define TAN_Q31_C2 286331153U  /* 2/15 */
#define TAN_Q31_C3 115895943U  /* 17/315 */
#define TAN_Q31_C4 46964369U   /* 62/2835 */
#define TAN_Q31_C5 19033653U   /* 1382/155925 */
#define TAN_Q31_C6 7714036U    /* 21844/6081075 */
#define TAN_Q31_C7 3126381U    /* 929569/638512875 */
#define TAN_Q31_C8 1267074U    /* 6404582/10854718875 */

/* High 32 bits of a * b, truncated: one UMULL on the Cortex-M4. */
static uint32_t mul_hi32(uint32_t a, uint32_t b)
{
    return (uint32_t)(((uint64_t)a * b) >> 32);
}

/*
 * Scaling, for mag <= 26.6e6 udeg (< 2^25):
 *   x = mag * pi / 180e6 in Q32, unsigned, truncated:
 *     (mag * 2^7) * UDEG_TO_RAD_Q57 / 2^32, x <= 0.46426 * 2^32 < 2^31;
 *   u = x^2 in Q32, truncated, u < 0.2156 * 2^32;
 *   p = tan x / x in Q31 by Horner in u, 1 <= p < 1.079 * 2^31 < 2^32;
 *     each step truncates by less than 2^-31;
 *   t = x p = tan x in Q31, truncated, t < 0.5008 * 2^31;
 *   ppm = (2 t) * 1e6 / 2^32, rounded.
 * Every truncation is below 2^-31 (5e-4 ppm). Worst error before the final
 * rounding, measured against long double tanl() at every micro-degree of
 * 0 .. 26565051: 0.0012 ppm; after it 0.5010 ppm.
 * 32 x 32 -> 64-bit unsigned products only: no division, no 64-bit shift,
 * the same bits on every target.
 */
int32_t pfe_codec_grade_ppm_from_pitch(int32_t pitch_udeg, bool *saturated)
{
    const bool negative = pitch_udeg < 0;
    const uint32_t mag = negative ? (0U - (uint32_t)pitch_udeg) : (uint32_t)pitch_udeg;
    bool sat = false;
    uint32_t ppm;
    if (mag > PITCH_SATURATED_UDEG) {
        sat = true;
        ppm = (uint32_t)PFE_GRADE_MAX_PPM;
    } else {
        const uint32_t x = mul_hi32(mag << 7, UDEG_TO_RAD_Q57);
        const uint32_t u = mul_hi32(x, x);
        uint32_t p = TAN_Q31_C8;
        p = TAN_Q31_C7 + mul_hi32(u, p);
        p = TAN_Q31_C6 + mul_hi32(u, p);
        p = TAN_Q31_C5 + mul_hi32(u, p);
        p = TAN_Q31_C4 + mul_hi32(u, p);
        p = TAN_Q31_C3 + mul_hi32(u, p);
        p = TAN_Q31_C2 + mul_hi32(u, p);
        p = TAN_Q31_C1 + mul_hi32(u, p);
        p = TAN_Q31_C0 + mul_hi32(u, p);
        const uint32_t t = mul_hi32(x, p);
        ppm = (uint32_t)((((uint64_t)(t << 1) * 1000000U) + ((uint64_t)1 << 31)) >> 32);
        if (ppm > (uint32_t)PFE_GRADE_MAX_PPM) {
            sat = true;
            ppm = (uint32_t)PFE_GRADE_MAX_PPM;
        }
    }
    if (saturated != NULL) {
        *saturated = sat;
    }
    return negative ? -(int32_t)ppm : (int32_t)ppm;
}

/* ------------------------------------------------------------ PFE_PlatoonConfig */

int pfe_codec_decode_platoon_config(const pfe_can_frame_t *frame, pfe_msg_platoon_config_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->n_vehicles = u32_na;
    out->own_position = u32_na;
    out->gap_mm = u32_na;
    out->time_gap_ms = u32_na;
    out->set_speed_mm_s = i32_na;
    const int rc = check_frame(frame, PFE_MSG_PLATOON_CONFIG);
    if (rc != PFE_OK) {
        return rc;
    }
    out->n_vehicles = dec_u32(frame, PFE_CSIG_PC_NUMBER_OF_VEHICLES);       /* PFE_PlatoonConfig.NumberOfVehicles */
    out->own_position = dec_u32(frame, PFE_CSIG_PC_OWN_POSITION);           /* PFE_PlatoonConfig.OwnPosition */
    out->gap_mm = dec_u32(frame, PFE_CSIG_PC_GAP);               /* PFE_PlatoonConfig.Gap */
    out->time_gap_ms = dec_u32(frame, PFE_CSIG_PC_TIME_GAP);                /* PFE_PlatoonConfig.TimeGap */
    out->set_speed_mm_s = dec_i32(frame, PFE_CSIG_PC_SET_SPEED);          /* PFE_PlatoonConfig.SetSpeed */
    if ((out->n_vehicles.state == PFE_SIG_VALID) && (out->own_position.state == PFE_SIG_VALID) &&
        (out->own_position.value >= out->n_vehicles.value)) {
        out->own_position = (pfe_sig_u32_t){0U, PFE_SIG_OUT_OF_RANGE};     /* no such position */
    }
    return PFE_OK;
}

int pfe_codec_encode_platoon_config(pfe_can_frame_t *frame, const pfe_msg_platoon_config_t *in,
                                    uint8_t source)
{
    enc_t e;
    if ((in == NULL) ||
        (enc_begin(&e, frame, PFE_MSG_PLATOON_CONFIG, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_PC_NUMBER_OF_VEHICLES, in->n_vehicles.state,
            raw_of_u64(PFE_CSIG_PC_NUMBER_OF_VEHICLES, in->n_vehicles.value));
    enc_put(&e, PFE_CSIG_PC_OWN_POSITION, in->own_position.state,
            raw_of_u64(PFE_CSIG_PC_OWN_POSITION, in->own_position.value));
    enc_put(&e, PFE_CSIG_PC_GAP, in->gap_mm.state,
            raw_of_u64(PFE_CSIG_PC_GAP, in->gap_mm.value));
    enc_put(&e, PFE_CSIG_PC_TIME_GAP, in->time_gap_ms.state,
            raw_of_u64(PFE_CSIG_PC_TIME_GAP, in->time_gap_ms.value));
    enc_put(&e, PFE_CSIG_PC_SET_SPEED, in->set_speed_mm_s.state,
            raw_of_i32(PFE_CSIG_PC_SET_SPEED, in->set_speed_mm_s.value));
    return enc_end(&e);
}

pfe_sig_state_t pfe_codec_platoon_gap_mm(const pfe_msg_platoon_config_t *cfg, uint32_t *gap_mm)
{
    if (gap_mm == NULL) {
        return PFE_SIG_NOT_AVAILABLE;
    }
    *gap_mm = 0U;
    if (cfg == NULL) {
        return PFE_SIG_NOT_AVAILABLE;
    }
    if (cfg->gap_mm.state == PFE_SIG_VALID) {
        *gap_mm = cfg->gap_mm.value;
        return PFE_SIG_VALID;
    }
    if ((cfg->time_gap_ms.state == PFE_SIG_VALID) && (cfg->set_speed_mm_s.state == PFE_SIG_VALID) &&
        (cfg->set_speed_mm_s.value >= 0)) {
        /* <= 64255 ms * 69723 mm/s: 64-bit */
        *gap_mm = (uint32_t)pfe_udiv_round_u64(
            (uint64_t)cfg->time_gap_ms.value * (uint64_t)cfg->set_speed_mm_s.value, 1000U);
        return PFE_SIG_VALID;
    }
    return PFE_SIG_NOT_AVAILABLE;
}

/* ------------------------------------------------------------ PFE_GradePreview */

int pfe_codec_decode_grade_preview(const pfe_can_frame_t *frame, pfe_msg_grade_preview_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->frame_type = u32_na;
    out->preview_id = u32_na;
    out->sample_count = u32_na;
    out->spacing_m = u32_na;
    out->first_index = u32_na;
    for (uint32_t k = 0U; k < PFE_PREVIEW_SAMPLES_PER_FRAME; k++) {
        out->grade_ppm[k] = i32_na;
    }
    const int rc = check_frame(frame, PFE_MSG_GRADE_PREVIEW);
    if (rc != PFE_OK) {
        return rc;
    }
    out->frame_type = dec_u32(frame, PFE_CSIG_GP_FRAME_TYPE);                 /* PFE_GradePreview.PreviewFrameType (M) */
    out->preview_id = dec_u32(frame, PFE_CSIG_GP_PREVIEW_ID);                 /* PFE_GradePreview.PreviewId */
    if (out->frame_type.state != PFE_SIG_VALID) {
        return PFE_OK;
    }
    if (out->frame_type.value == PFE_PREVIEW_FRAME_HEADER) {
        out->sample_count = dec_u32(frame, PFE_CSIG_GP_SAMPLE_COUNT);         /* PFE_GradePreview.SampleCount (m0) */
        out->spacing_m = dec_u32(frame, PFE_CSIG_GP_SAMPLE_SPACING);          /* PFE_GradePreview.SampleSpacing (m0) */
    } else {
        out->first_index = dec_u32(frame, PFE_CSIG_GP_SAMPLE_INDEX);          /* PFE_GradePreview.SampleIndex (m1) */
        out->grade_ppm[0] = dec_i32(frame, PFE_CSIG_GP_GRADE_SAMPLE0);      /* PFE_GradePreview.GradeSample0 (m1) */
        out->grade_ppm[1] = dec_i32(frame, PFE_CSIG_GP_GRADE_SAMPLE1);      /* PFE_GradePreview.GradeSample1 (m1) */
        out->grade_ppm[2] = dec_i32(frame, PFE_CSIG_GP_GRADE_SAMPLE2);      /* PFE_GradePreview.GradeSample2 (m1) */
    }
    return PFE_OK;
}

int pfe_codec_encode_grade_preview(pfe_can_frame_t *frame, const pfe_msg_grade_preview_t *in,
                                   uint8_t source)
{
    enc_t e;
    if ((in == NULL) || (in->frame_type.state != PFE_SIG_VALID) ||
        (in->frame_type.value > PFE_PREVIEW_FRAME_DATA) ||
        (enc_begin(&e, frame, PFE_MSG_GRADE_PREVIEW, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_GP_FRAME_TYPE, PFE_SIG_VALID,
            raw_of_u64(PFE_CSIG_GP_FRAME_TYPE, in->frame_type.value));
    enc_put(&e, PFE_CSIG_GP_PREVIEW_ID, in->preview_id.state,
            raw_of_u64(PFE_CSIG_GP_PREVIEW_ID, in->preview_id.value));
    if (in->frame_type.value == PFE_PREVIEW_FRAME_HEADER) {
        enc_put(&e, PFE_CSIG_GP_SAMPLE_COUNT, in->sample_count.state,
            raw_of_u64(PFE_CSIG_GP_SAMPLE_COUNT, in->sample_count.value));
        enc_put(&e, PFE_CSIG_GP_SAMPLE_SPACING, in->spacing_m.state,
            raw_of_u64(PFE_CSIG_GP_SAMPLE_SPACING, in->spacing_m.value));
    } else {
        enc_put(&e, PFE_CSIG_GP_SAMPLE_INDEX, in->first_index.state,
            raw_of_u64(PFE_CSIG_GP_SAMPLE_INDEX, in->first_index.value));
        enc_put(&e, PFE_CSIG_GP_GRADE_SAMPLE0, in->grade_ppm[0].state,
            raw_of_i32(PFE_CSIG_GP_GRADE_SAMPLE0, in->grade_ppm[0].value));
        enc_put(&e, PFE_CSIG_GP_GRADE_SAMPLE1, in->grade_ppm[1].state,
            raw_of_i32(PFE_CSIG_GP_GRADE_SAMPLE1, in->grade_ppm[1].value));
        enc_put(&e, PFE_CSIG_GP_GRADE_SAMPLE2, in->grade_ppm[2].state,
            raw_of_i32(PFE_CSIG_GP_GRADE_SAMPLE2, in->grade_ppm[2].value));
    }
    return enc_end(&e);
}

void pfe_preview_init(pfe_preview_t *pv)
{
    if (pv == NULL) {
        return;
    }
    (void)memset(pv, 0, sizeof *pv);
    pv->phase = PFE_PREVIEW_EMPTY;
}

/* A rejected frame drops a preview in progress; a complete one stays. */
static int preview_reject(pfe_preview_t *pv, int rc)
{
    if (pv->phase == PFE_PREVIEW_RECEIVING) {
        pv->phase = PFE_PREVIEW_EMPTY;
    }
    if (pv->frames_rejected < UINT32_MAX) {
        pv->frames_rejected++;
    }
    return rc;
}

/* The signal each sample of a data frame is carried in: sample i of a
 * preview came in slot i % 3 of its frame (frames start at SampleIndex 0,
 * 3, 6 ...), and is read with that signal's scale, offset and range. */
static const pfe_sig_index_t k_sample_sig[PFE_PREVIEW_SAMPLES_PER_FRAME] = {
    PFE_CSIG_GP_GRADE_SAMPLE0, PFE_CSIG_GP_GRADE_SAMPLE1, PFE_CSIG_GP_GRADE_SAMPLE2};

int pfe_preview_push(pfe_preview_t *pv, const pfe_can_frame_t *frame)
{
    if (pv == NULL) {
        return PFE_EINVAL;
    }
    pfe_msg_grade_preview_t m;
    const int rc = pfe_codec_decode_grade_preview(frame, &m);
    if (rc != PFE_OK) {
        return preview_reject(pv, rc);
    }
    if ((m.frame_type.state != PFE_SIG_VALID) || (m.preview_id.state != PFE_SIG_VALID)) {
        return preview_reject(pv, PFE_PREVIEW_EFIELD);
    }
    if (m.frame_type.value == PFE_PREVIEW_FRAME_HEADER) {
        if ((m.sample_count.state != PFE_SIG_VALID) || (m.spacing_m.state != PFE_SIG_VALID)) {
            return preview_reject(pv, PFE_PREVIEW_ECOUNT);
        }
        const bool replaced = pv->phase != PFE_PREVIEW_EMPTY;
        pv->phase = PFE_PREVIEW_RECEIVING;
        pv->preview_id = (uint8_t)m.preview_id.value;
        pv->sample_count = (uint16_t)m.sample_count.value;
        pv->spacing_m = (uint8_t)m.spacing_m.value;
        pv->next_index = 0U;
        pv->unusable_samples = 0U;
        return replaced ? PFE_PREVIEW_RESTARTED : PFE_PREVIEW_INCOMPLETE;
    }
    if ((pv->phase == PFE_PREVIEW_EMPTY) || (m.preview_id.value != pv->preview_id)) {
        return preview_reject(pv, PFE_PREVIEW_ENOHEADER);
    }
    if (pv->phase == PFE_PREVIEW_READY) {
        return preview_reject(pv, PFE_PREVIEW_EORDER); /* every sample is in: a repeat */
    }
    if ((m.first_index.state != PFE_SIG_VALID) || (m.first_index.value >= pv->sample_count)) {
        return preview_reject(pv, PFE_PREVIEW_ECOUNT);
    }
    if (m.first_index.value > pv->next_index) {
        return preview_reject(pv, PFE_PREVIEW_EGAP);
    }
    if (m.first_index.value < pv->next_index) {
        return preview_reject(pv, PFE_PREVIEW_EORDER);
    }
    uint32_t index = m.first_index.value;
    for (uint32_t k = 0U; (k < PFE_PREVIEW_SAMPLES_PER_FRAME) && (index < pv->sample_count); k++) {
        uint32_t raw;
        if (get_raw(frame, k_sample_sig[k], &raw) != PFE_SIG_VALID) { /* PFE_GradePreview.GradeSampleN */
            pv->unusable_samples++;
        }
        pv->raw[index] = (uint16_t)raw;
        index++;
    }
    pv->next_index = (uint16_t)index;
    if (index >= pv->sample_count) {
        pv->phase = PFE_PREVIEW_READY;
        return PFE_PREVIEW_COMPLETE;
    }
    return PFE_PREVIEW_INCOMPLETE;
}

pfe_sig_state_t pfe_preview_grade_ppm(const pfe_preview_t *pv, uint32_t index, int32_t *grade_ppm)
{
    if (grade_ppm != NULL) {
        *grade_ppm = 0;
    }
    if ((pv == NULL) || (pv->phase != PFE_PREVIEW_READY) || (index >= pv->sample_count)) {
        return PFE_SIG_NOT_AVAILABLE;
    }
    const uint32_t raw = pv->raw[index];
    const pfe_codec_signal_t *sig = &pfe_codec_signals[k_sample_sig[index % PFE_PREVIEW_SAMPLES_PER_FRAME]];
    const pfe_sig_state_t st = pfe_codec_raw_state(sig, raw);
    if ((st == PFE_SIG_VALID) && (grade_ppm != NULL)) {
        *grade_ppm = (int32_t)fw_of_raw(sig, raw);
    }
    return st;
}

/* grade_ppm[k] for k = k0, k0 + 3, ... below n: samples first + k, all
 * carried in signal sig. */
static ALWAYS_INLINE void copy_every_third(const pfe_preview_t *pv, uint32_t first, uint32_t n, uint32_t k0,
                                           pfe_sig_index_t sig, int32_t *grade_ppm)
{
    for (uint32_t k = k0; k < n; k += PFE_PREVIEW_SAMPLES_PER_FRAME) {
        grade_ppm[k] = (int32_t)fw_of_raw(&pfe_codec_signals[sig], pv->raw[first + k]);
    }
}

uint32_t pfe_preview_copy_ppm(const pfe_preview_t *pv, uint32_t first, uint32_t count,
                              int32_t *grade_ppm)
{
    if ((pv == NULL) || (grade_ppm == NULL) || (pv->phase != PFE_PREVIEW_READY) ||
        (pv->unusable_samples != 0U) || (first > pv->sample_count)) {
        return 0U;
    }
    const uint32_t n = ((pv->sample_count - first) < count) ? (pv->sample_count - first) : count;
    /* sample first + k came in slot (first + k) % 3: GradeSample s holds
     * k = (s - first) mod 3, 3 + that, ... Each pass names its signal as a
     * constant, so that its scale folds into the loop as it did for one. */
    const uint32_t slot = first % PFE_PREVIEW_SAMPLES_PER_FRAME;
    copy_every_third(pv, first, n, (3U - slot) % 3U, PFE_CSIG_GP_GRADE_SAMPLE0, grade_ppm);
    copy_every_third(pv, first, n, (4U - slot) % 3U, PFE_CSIG_GP_GRADE_SAMPLE1, grade_ppm);
    copy_every_third(pv, first, n, (5U - slot) % 3U, PFE_CSIG_GP_GRADE_SAMPLE2, grade_ppm);
    return n;
}

/* ------------------------------------------------------------ LFE1 */

int pfe_codec_decode_lfe1(const pfe_can_frame_t *frame, pfe_msg_lfe1_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->fuel_rate_nl_s = u32_na;
    const int rc = check_frame(frame, PFE_MSG_LFE1);
    if (rc != PFE_OK) {
        return rc;
    }
    out->fuel_rate_nl_s = dec_u32(frame, PFE_CSIG_LFE1_ENGINE_FUEL_RATE); /* LFE1.EngineFuelRate (SPN 183) */
    return PFE_OK;
}

int pfe_codec_encode_lfe1(pfe_can_frame_t *frame, const pfe_msg_lfe1_t *in, uint8_t source)
{
    enc_t e;
    if ((in == NULL) || (enc_begin(&e, frame, PFE_MSG_LFE1, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_LFE1_ENGINE_FUEL_RATE, in->fuel_rate_nl_s.state,
            raw_of_u64(PFE_CSIG_LFE1_ENGINE_FUEL_RATE, in->fuel_rate_nl_s.value));
    return enc_end(&e);
}

/* ------------------------------------------------------------ PFE_PlatoonFuel */

int pfe_codec_decode_platoon_fuel(const pfe_can_frame_t *frame, pfe_msg_platoon_fuel_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->fuel_rate_nl_s = u32_na;
    out->fuel_used_ul = u64_na;
    const int rc = check_frame(frame, PFE_MSG_PLATOON_FUEL);
    if (rc != PFE_OK) {
        return rc;
    }
    out->fuel_rate_nl_s = dec_u32(frame, PFE_CSIG_PF_PLATOON_FUEL_RATE);          /* PFE_PlatoonFuel.PlatoonFuelRate */
    out->fuel_used_ul = dec_u64(frame, PFE_CSIG_PF_PLATOON_TOTAL_FUEL_USED); /* PFE_PlatoonFuel.PlatoonTotalFuelUsed */
    return PFE_OK;
}

int pfe_codec_encode_platoon_fuel(pfe_can_frame_t *frame, const pfe_msg_platoon_fuel_t *in,
                                  uint8_t source)
{
    enc_t e;
    if ((in == NULL) ||
        (enc_begin(&e, frame, PFE_MSG_PLATOON_FUEL, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_PF_PLATOON_FUEL_RATE, in->fuel_rate_nl_s.state,
            raw_of_u64(PFE_CSIG_PF_PLATOON_FUEL_RATE, in->fuel_rate_nl_s.value));
    enc_put(&e, PFE_CSIG_PF_PLATOON_TOTAL_FUEL_USED, in->fuel_used_ul.state,
            raw_of_u64(PFE_CSIG_PF_PLATOON_TOTAL_FUEL_USED, in->fuel_used_ul.value));
    return enc_end(&e);
}

/* ------------------------------------------------------------ HRLFC */

int pfe_codec_decode_hrlfc(const pfe_can_frame_t *frame, pfe_msg_hrlfc_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->trip_fuel_ul = u64_na;
    out->total_fuel_ul = u64_na;
    const int rc = check_frame(frame, PFE_MSG_HRLFC);
    if (rc != PFE_OK) {
        return rc;
    }
    out->trip_fuel_ul = dec_u64(frame, PFE_CSIG_HRLFC_TRIP_FUEL);        /* HRLFC.HighResolutionEngineTripFuel (SPN 5053) */
    out->total_fuel_ul = dec_u64(frame, PFE_CSIG_HRLFC_TOTAL_FUEL_USED); /* HRLFC.HighResolutionEngineTotalFuelUsed (SPN 5054) */
    return PFE_OK;
}

int pfe_codec_encode_hrlfc(pfe_can_frame_t *frame, const pfe_msg_hrlfc_t *in, uint8_t source)
{
    enc_t e;
    if ((in == NULL) || (enc_begin(&e, frame, PFE_MSG_HRLFC, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_HRLFC_TRIP_FUEL, in->trip_fuel_ul.state,
            raw_of_u64(PFE_CSIG_HRLFC_TRIP_FUEL, in->trip_fuel_ul.value));
    enc_put(&e, PFE_CSIG_HRLFC_TOTAL_FUEL_USED, in->total_fuel_ul.state,
            raw_of_u64(PFE_CSIG_HRLFC_TOTAL_FUEL_USED, in->total_fuel_ul.value));
    return enc_end(&e);
}

/* ------------------------------------------------------------ PFE_FuelPrediction */

int pfe_codec_decode_fuel_prediction(const pfe_can_frame_t *frame, pfe_msg_fuel_prediction_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->fuel_ul = u32_na;
    out->fuel_lower_ul = u32_na;
    out->fuel_upper_ul = u32_na;
    out->time_ms = u32_na;
    const int rc = check_frame(frame, PFE_MSG_FUEL_PREDICTION);
    if (rc != PFE_OK) {
        return rc;
    }
    out->fuel_ul = dec_u32(frame, PFE_CSIG_FP_PREDICTED_FUEL);             /* PFE_FuelPrediction.PredictedFuel */
    out->fuel_lower_ul = dec_u32(frame, PFE_CSIG_FP_PREDICTED_FUEL_LOWER); /* PFE_FuelPrediction.PredictedFuelLowerBound */
    out->fuel_upper_ul = dec_u32(frame, PFE_CSIG_FP_PREDICTED_FUEL_UPPER); /* PFE_FuelPrediction.PredictedFuelUpperBound */
    out->time_ms = dec_u32(frame, PFE_CSIG_FP_PREDICTED_TIME);               /* PFE_FuelPrediction.PredictedTime */
    return PFE_OK;
}

int pfe_codec_encode_fuel_prediction(pfe_can_frame_t *frame, const pfe_msg_fuel_prediction_t *in,
                                     uint8_t source)
{
    enc_t e;
    if ((in == NULL) ||
        (enc_begin(&e, frame, PFE_MSG_FUEL_PREDICTION, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_FP_PREDICTED_FUEL, in->fuel_ul.state,
            raw_of_u64(PFE_CSIG_FP_PREDICTED_FUEL, in->fuel_ul.value));
    enc_put(&e, PFE_CSIG_FP_PREDICTED_FUEL_LOWER, in->fuel_lower_ul.state,
            raw_of_u64(PFE_CSIG_FP_PREDICTED_FUEL_LOWER, in->fuel_lower_ul.value));
    enc_put(&e, PFE_CSIG_FP_PREDICTED_FUEL_UPPER, in->fuel_upper_ul.state,
            raw_of_u64(PFE_CSIG_FP_PREDICTED_FUEL_UPPER, in->fuel_upper_ul.value));
    enc_put(&e, PFE_CSIG_FP_PREDICTED_TIME, in->time_ms.state,
            raw_of_u64(PFE_CSIG_FP_PREDICTED_TIME, in->time_ms.value));
    return enc_end(&e);
}

/* ------------------------------------------------------------ PFE_Status */

static pfe_sig_state_t input_state_of_code(uint32_t code)
{
    switch (code) {
    case PFE_STATUS_INPUT_VALID:
        return PFE_SIG_VALID;
    case PFE_STATUS_INPUT_OUT_OF_RANGE:
        return PFE_SIG_OUT_OF_RANGE;
    case PFE_STATUS_INPUT_ERROR:
        return PFE_SIG_ERROR;
    default:
        return PFE_SIG_NOT_AVAILABLE;
    }
}

/* UINT32_MAX for a value outside the enumeration. */
static uint32_t code_of_input_state(pfe_sig_state_t state)
{
    switch (state) {
    case PFE_SIG_VALID:
        return PFE_STATUS_INPUT_VALID;
    case PFE_SIG_OUT_OF_RANGE:
        return PFE_STATUS_INPUT_OUT_OF_RANGE;
    case PFE_SIG_ERROR:
        return PFE_STATUS_INPUT_ERROR;
    case PFE_SIG_NOT_AVAILABLE:
        return PFE_STATUS_INPUT_NOT_AVAILABLE;
    default:
        return UINT32_MAX;
    }
}

static pfe_sig_state_t dec_input_state(const pfe_can_frame_t *frame, pfe_sig_index_t i)
{
    return input_state_of_code(pfe_codec_raw_get(frame->data, &pfe_codec_signals[i]));
}

int pfe_codec_decode_status(const pfe_can_frame_t *frame, pfe_msg_status_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->speed_input = PFE_SIG_NOT_AVAILABLE;
    out->grade_input = PFE_SIG_NOT_AVAILABLE;
    out->platoon_config_input = PFE_SIG_NOT_AVAILABLE;
    out->grade_preview_input = PFE_SIG_NOT_AVAILABLE;
    out->mode = u32_na;
    out->rx_frames_dropped = u32_na;
    out->tick_overruns = u32_na;
    out->tx_frames_dropped = u32_na;
    out->warming_up = u32_na;
    out->speed_clamped = u32_na;
    out->grade_clamped = u32_na;
    out->output_saturated = u32_na;
    out->inputs_rejected = u32_na;
    out->address_conflicts = u32_na;
    const int rc = check_frame(frame, PFE_MSG_STATUS);
    if (rc != PFE_OK) {
        return rc;
    }
    out->speed_input = dec_input_state(frame, PFE_CSIG_ST_SPEED_INPUT);                   /* PFE_Status.SpeedInputState */
    out->grade_input = dec_input_state(frame, PFE_CSIG_ST_GRADE_INPUT);                   /* PFE_Status.GradeInputState */
    out->platoon_config_input = dec_input_state(frame, PFE_CSIG_ST_PLATOON_CONFIG_INPUT); /* PFE_Status.PlatoonConfigInputState */
    out->grade_preview_input = dec_input_state(frame, PFE_CSIG_ST_GRADE_PREVIEW_INPUT);   /* PFE_Status.GradePreviewInputState */
    out->mode = dec_u32(frame, PFE_CSIG_ST_DEGRADED_MODE);                                /* PFE_Status.DegradedMode */
    out->rx_frames_dropped = dec_u32(frame, PFE_CSIG_ST_RX_FRAMES_DROPPED);               /* PFE_Status.RxFramesDropped */
    out->tick_overruns = dec_u32(frame, PFE_CSIG_ST_TICK_OVERRUNS);                       /* PFE_Status.TickOverruns */
    out->tx_frames_dropped = dec_u32(frame, PFE_CSIG_ST_TX_FRAMES_DROPPED);               /* PFE_Status.TxFramesDropped */
    out->warming_up = dec_u32(frame, PFE_CSIG_ST_WARMING_UP);                             /* PFE_Status.WarmingUp */
    out->speed_clamped = dec_u32(frame, PFE_CSIG_ST_SPEED_CLAMPED);                       /* PFE_Status.SpeedClamped */
    out->grade_clamped = dec_u32(frame, PFE_CSIG_ST_GRADE_CLAMPED);                       /* PFE_Status.GradeClamped */
    out->output_saturated = dec_u32(frame, PFE_CSIG_ST_OUTPUT_SATURATED);                 /* PFE_Status.OutputSaturated */
    out->inputs_rejected = dec_u32(frame, PFE_CSIG_ST_INPUTS_REJECTED);                   /* PFE_Status.InputsRejected */
    out->address_conflicts = dec_u32(frame, PFE_CSIG_ST_ADDRESS_CONFLICTS);               /* PFE_Status.AddressConflicts */
    return PFE_OK;
}

int pfe_codec_encode_status(pfe_can_frame_t *frame, const pfe_msg_status_t *in, uint8_t source)
{
    enc_t e;
    if (in == NULL) {
        return PFE_EINVAL;
    }
    const uint32_t codes[4] = {
        code_of_input_state(in->speed_input), code_of_input_state(in->grade_input),
        code_of_input_state(in->platoon_config_input), code_of_input_state(in->grade_preview_input)};
    for (uint32_t k = 0U; k < 4U; k++) {
        if (codes[k] == UINT32_MAX) {
            return PFE_EINVAL;
        }
    }
    if (enc_begin(&e, frame, PFE_MSG_STATUS, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_ST_SPEED_INPUT, PFE_SIG_VALID, (int64_t)codes[0]);
    enc_put(&e, PFE_CSIG_ST_GRADE_INPUT, PFE_SIG_VALID, (int64_t)codes[1]);
    enc_put(&e, PFE_CSIG_ST_PLATOON_CONFIG_INPUT, PFE_SIG_VALID, (int64_t)codes[2]);
    enc_put(&e, PFE_CSIG_ST_GRADE_PREVIEW_INPUT, PFE_SIG_VALID, (int64_t)codes[3]);
    enc_put(&e, PFE_CSIG_ST_DEGRADED_MODE, in->mode.state,
            raw_of_u64(PFE_CSIG_ST_DEGRADED_MODE, in->mode.value));
    enc_put(&e, PFE_CSIG_ST_RX_FRAMES_DROPPED, in->rx_frames_dropped.state,
            raw_of_u64(PFE_CSIG_ST_RX_FRAMES_DROPPED, in->rx_frames_dropped.value));
    enc_put(&e, PFE_CSIG_ST_TICK_OVERRUNS, in->tick_overruns.state,
            raw_of_u64(PFE_CSIG_ST_TICK_OVERRUNS, in->tick_overruns.value));
    enc_put(&e, PFE_CSIG_ST_TX_FRAMES_DROPPED, in->tx_frames_dropped.state,
            raw_of_u64(PFE_CSIG_ST_TX_FRAMES_DROPPED, in->tx_frames_dropped.value));
    enc_put(&e, PFE_CSIG_ST_WARMING_UP, in->warming_up.state,
            raw_of_u64(PFE_CSIG_ST_WARMING_UP, in->warming_up.value));
    enc_put(&e, PFE_CSIG_ST_SPEED_CLAMPED, in->speed_clamped.state,
            raw_of_u64(PFE_CSIG_ST_SPEED_CLAMPED, in->speed_clamped.value));
    enc_put(&e, PFE_CSIG_ST_GRADE_CLAMPED, in->grade_clamped.state,
            raw_of_u64(PFE_CSIG_ST_GRADE_CLAMPED, in->grade_clamped.value));
    enc_put(&e, PFE_CSIG_ST_OUTPUT_SATURATED, in->output_saturated.state,
            raw_of_u64(PFE_CSIG_ST_OUTPUT_SATURATED, in->output_saturated.value));
    enc_put(&e, PFE_CSIG_ST_INPUTS_REJECTED, in->inputs_rejected.state,
            raw_of_u64(PFE_CSIG_ST_INPUTS_REJECTED, in->inputs_rejected.value));
    enc_put(&e, PFE_CSIG_ST_ADDRESS_CONFLICTS, in->address_conflicts.state,
            raw_of_u64(PFE_CSIG_ST_ADDRESS_CONFLICTS, in->address_conflicts.value));
    return enc_end(&e);
}

/* ------------------------------------------------------------ NAME, AddressClaimed */

int pfe_j1939_name_pack(const pfe_j1939_name_t *name, uint64_t *out)
{
    if ((name == NULL) || (out == NULL)) {
        return PFE_EINVAL;
    }
    if ((name->identity_number > 0x1FFFFFUL) || (name->manufacturer_code > 0x7FFU) ||
        (name->ecu_instance > 7U) || (name->function_instance > 31U) || (name->reserved > 1U) ||
        (name->vehicle_system > 127U) || (name->vehicle_system_instance > 15U) ||
        (name->industry_group > 7U)) {
        return PFE_EINVAL;
    }
    *out = (uint64_t)name->identity_number | ((uint64_t)name->manufacturer_code << 21) |
           ((uint64_t)name->ecu_instance << 32) | ((uint64_t)name->function_instance << 35) |
           ((uint64_t)name->function << 40) | ((uint64_t)name->reserved << 48) |
           ((uint64_t)name->vehicle_system << 49) | ((uint64_t)name->vehicle_system_instance << 56) |
           ((uint64_t)name->industry_group << 60) |
           ((uint64_t)(name->arbitrary_address_capable ? 1U : 0U) << 63);
    return PFE_OK;
}

void pfe_j1939_name_unpack(uint64_t value, pfe_j1939_name_t *out)
{
    if (out == NULL) {
        return;
    }
    out->identity_number = (uint32_t)(value & 0x1FFFFFU);
    out->manufacturer_code = (uint16_t)((value >> 21) & 0x7FFU);
    out->ecu_instance = (uint8_t)((value >> 32) & 7U);
    out->function_instance = (uint8_t)((value >> 35) & 31U);
    out->function = (uint8_t)((value >> 40) & 0xFFU);
    out->reserved = (uint8_t)((value >> 48) & 1U);
    out->vehicle_system = (uint8_t)((value >> 49) & 127U);
    out->vehicle_system_instance = (uint8_t)((value >> 56) & 15U);
    out->industry_group = (uint8_t)((value >> 60) & 7U);
    out->arbitrary_address_capable = ((value >> 63) & 1U) != 0U;
}

int pfe_codec_encode_address_claimed(pfe_can_frame_t *frame, const pfe_j1939_name_t *name,
                                     uint8_t source)
{
    uint64_t packed;
    enc_t e;
    if ((pfe_j1939_name_pack(name, &packed) != PFE_OK) ||
        (enc_begin(&e, frame, PFE_MSG_ADDRESS_CLAIMED, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_AC_IDENTITY_NUMBER, PFE_SIG_VALID, (int64_t)name->identity_number);
    enc_put(&e, PFE_CSIG_AC_MANUFACTURER_CODE, PFE_SIG_VALID, (int64_t)name->manufacturer_code);
    enc_put(&e, PFE_CSIG_AC_ECU_INSTANCE, PFE_SIG_VALID, (int64_t)name->ecu_instance);
    enc_put(&e, PFE_CSIG_AC_FUNCTION_INSTANCE, PFE_SIG_VALID, (int64_t)name->function_instance);
    enc_put(&e, PFE_CSIG_AC_FUNCTION, PFE_SIG_VALID, (int64_t)name->function);
    enc_put(&e, PFE_CSIG_AC_RESERVED, PFE_SIG_VALID, (int64_t)name->reserved);
    enc_put(&e, PFE_CSIG_AC_VEHICLE_SYSTEM, PFE_SIG_VALID, (int64_t)name->vehicle_system);
    enc_put(&e, PFE_CSIG_AC_VEHICLE_SYSTEM_INSTANCE, PFE_SIG_VALID, (int64_t)name->vehicle_system_instance);
    enc_put(&e, PFE_CSIG_AC_INDUSTRY_GROUP, PFE_SIG_VALID, (int64_t)name->industry_group);
    enc_put(&e, PFE_CSIG_AC_ARBITRARY_ADDRESS_CAPABLE, PFE_SIG_VALID,
            name->arbitrary_address_capable ? 1 : 0);
    return enc_end(&e); /* fields were checked by the pack: never clamps */
}

static uint8_t dec_field8(const pfe_can_frame_t *frame, pfe_sig_index_t i)
{
    return (uint8_t)pfe_codec_raw_get(frame->data, &pfe_codec_signals[i]);
}

int pfe_codec_decode_address_claimed(const pfe_can_frame_t *frame, pfe_j1939_name_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    (void)memset(out, 0, sizeof *out);
    const int rc = check_frame(frame, PFE_MSG_ADDRESS_CLAIMED);
    if (rc != PFE_OK) {
        return rc;
    }
    out->identity_number = pfe_codec_raw_get(frame->data, &pfe_codec_signals[PFE_CSIG_AC_IDENTITY_NUMBER]); /* AddressClaimed.IdentityNumber (SPN 2837) */
    out->manufacturer_code = (uint16_t)pfe_codec_raw_get(frame->data, &pfe_codec_signals[PFE_CSIG_AC_MANUFACTURER_CODE]); /* AddressClaimed.ManufacturerCode (SPN 2838) */
    out->ecu_instance = dec_field8(frame, PFE_CSIG_AC_ECU_INSTANCE);                       /* AddressClaimed.EcuInstance (SPN 2840) */
    out->function_instance = dec_field8(frame, PFE_CSIG_AC_FUNCTION_INSTANCE);             /* AddressClaimed.FunctionInstance (SPN 2839) */
    out->function = dec_field8(frame, PFE_CSIG_AC_FUNCTION);                               /* AddressClaimed.Function (SPN 2841) */
    out->reserved = dec_field8(frame, PFE_CSIG_AC_RESERVED);                               /* AddressClaimed.NameReserved */
    out->vehicle_system = dec_field8(frame, PFE_CSIG_AC_VEHICLE_SYSTEM);                   /* AddressClaimed.VehicleSystem (SPN 2842) */
    out->vehicle_system_instance = dec_field8(frame, PFE_CSIG_AC_VEHICLE_SYSTEM_INSTANCE); /* AddressClaimed.VehicleSystemInstance (SPN 2843) */
    out->industry_group = dec_field8(frame, PFE_CSIG_AC_INDUSTRY_GROUP);                   /* AddressClaimed.IndustryGroup (SPN 2846) */
    out->arbitrary_address_capable = dec_field8(frame, PFE_CSIG_AC_ARBITRARY_ADDRESS_CAPABLE) != 0U; /* AddressClaimed.ArbitraryAddressCapable (SPN 2844) */
    return PFE_OK;
}

/* ------------------------------------------------------------ Request */

int pfe_codec_decode_request(const pfe_can_frame_t *frame, pfe_msg_request_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->pgn = u32_na;
    out->destination = PFE_J1939_ADDR_GLOBAL;
    out->source = PFE_J1939_ADDR_NULL;
    const int rc = check_frame(frame, PFE_MSG_REQUEST);
    if (rc != PFE_OK) {
        return rc;
    }
    out->pgn = dec_u32(frame, PFE_CSIG_RQST_REQUESTED_PGN); /* Request.RequestedPGN (SPN 2540) */
    out->destination = pfe_j1939_destination(frame->id);
    out->source = pfe_j1939_source(frame->id);
    return PFE_OK;
}

int pfe_codec_encode_request(pfe_can_frame_t *frame, uint32_t pgn, uint8_t destination,
                             uint8_t source)
{
    enc_t e;
    if ((pgn > 0x3FFFFUL) ||
        (enc_begin(&e, frame, PFE_MSG_REQUEST, destination, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_RQST_REQUESTED_PGN, PFE_SIG_VALID, (int64_t)pgn);
    return enc_end(&e);
}

/* ------------------------------------------------------------ VDS */

int pfe_codec_decode_vds(const pfe_can_frame_t *frame, pfe_msg_vds_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->bearing_mdeg = u32_na;
    out->nav_speed_mm_s = i32_na;
    out->pitch_mdeg = i32_na;
    out->altitude_mm = i32_na;
    const int rc = check_frame(frame, PFE_MSG_VDS);
    if (rc != PFE_OK) {
        return rc;
    }
    out->bearing_mdeg = dec_u32(frame, PFE_CSIG_VDS_COMPASS_BEARING);   /* VDS.CompassBearing (SPN 165) */
    out->nav_speed_mm_s = dec_i32(frame, PFE_CSIG_VDS_NAV_SPEED);       /* VDS.NavigationBasedVehicleSpeed (SPN 517) */
    out->pitch_mdeg = dec_i32(frame, PFE_CSIG_VDS_PITCH);               /* VDS.Pitch (SPN 583) */
    out->altitude_mm = dec_i32(frame, PFE_CSIG_VDS_ALTITUDE);           /* VDS.Altitude (SPN 580) */
    return PFE_OK;
}

int pfe_codec_encode_vds(pfe_can_frame_t *frame, const pfe_msg_vds_t *in, uint8_t source)
{
    enc_t e;
    if ((in == NULL) || (enc_begin(&e, frame, PFE_MSG_VDS, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_VDS_COMPASS_BEARING, in->bearing_mdeg.state,
            raw_of_u64(PFE_CSIG_VDS_COMPASS_BEARING, in->bearing_mdeg.value));
    enc_put(&e, PFE_CSIG_VDS_NAV_SPEED, in->nav_speed_mm_s.state,
            raw_of_i32(PFE_CSIG_VDS_NAV_SPEED, in->nav_speed_mm_s.value));
    enc_put(&e, PFE_CSIG_VDS_PITCH, in->pitch_mdeg.state,
            raw_of_i32(PFE_CSIG_VDS_PITCH, in->pitch_mdeg.value));
    enc_put(&e, PFE_CSIG_VDS_ALTITUDE, in->altitude_mm.state,
            raw_of_i32(PFE_CSIG_VDS_ALTITUDE, in->altitude_mm.value));
    return enc_end(&e);
}

/* ------------------------------------------------------------ CVW */

int pfe_codec_decode_cvw(const pfe_can_frame_t *frame, pfe_msg_cvw_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->powered_vehicle_kg = u32_na;
    out->gross_combination_kg = u32_na;
    const int rc = check_frame(frame, PFE_MSG_CVW);
    if (rc != PFE_OK) {
        return rc;
    }
    out->powered_vehicle_kg = dec_u32(frame, PFE_CSIG_CVW_POWERED_VEHICLE_WEIGHT);     /* CVW.PoweredVehicleWeight (SPN 1585) */
    out->gross_combination_kg = dec_u32(frame, PFE_CSIG_CVW_GROSS_COMBINATION_WEIGHT); /* CVW.GrossCombinationVehicleWeight (SPN 1760) */
    return PFE_OK;
}

int pfe_codec_encode_cvw(pfe_can_frame_t *frame, const pfe_msg_cvw_t *in, uint8_t source)
{
    enc_t e;
    if ((in == NULL) || (enc_begin(&e, frame, PFE_MSG_CVW, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_CVW_POWERED_VEHICLE_WEIGHT, in->powered_vehicle_kg.state,
            raw_of_u64(PFE_CSIG_CVW_POWERED_VEHICLE_WEIGHT, in->powered_vehicle_kg.value));
    enc_put(&e, PFE_CSIG_CVW_GROSS_COMBINATION_WEIGHT, in->gross_combination_kg.state,
            raw_of_u64(PFE_CSIG_CVW_GROSS_COMBINATION_WEIGHT, in->gross_combination_kg.value));
    return enc_end(&e);
}

/* ------------------------------------------------------------ PFE_OwnFuel */

int pfe_codec_decode_own_fuel(const pfe_can_frame_t *frame, pfe_msg_own_fuel_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->fuel_rate_nl_s = u32_na;
    out->fuel_used_ul = u64_na;
    out->model_identified = u32_na;
    const int rc = check_frame(frame, PFE_MSG_OWN_FUEL);
    if (rc != PFE_OK) {
        return rc;
    }
    out->fuel_rate_nl_s = dec_u32(frame, PFE_CSIG_OF_OWN_FUEL_RATE);               /* PFE_OwnFuel.OwnFuelRate */
    out->fuel_used_ul = dec_u64(frame, PFE_CSIG_OF_OWN_TOTAL_FUEL_USED);    /* PFE_OwnFuel.OwnTotalFuelUsed */
    out->model_identified = dec_u32(frame, PFE_CSIG_OF_MODEL_IDENTIFIED);                /* PFE_OwnFuel.ModelIdentified */
    return PFE_OK;
}

int pfe_codec_encode_own_fuel(pfe_can_frame_t *frame, const pfe_msg_own_fuel_t *in, uint8_t source)
{
    enc_t e;
    if ((in == NULL) ||
        (enc_begin(&e, frame, PFE_MSG_OWN_FUEL, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_OF_OWN_FUEL_RATE, in->fuel_rate_nl_s.state,
            raw_of_u64(PFE_CSIG_OF_OWN_FUEL_RATE, in->fuel_rate_nl_s.value));
    enc_put(&e, PFE_CSIG_OF_OWN_TOTAL_FUEL_USED, in->fuel_used_ul.state,
            raw_of_u64(PFE_CSIG_OF_OWN_TOTAL_FUEL_USED, in->fuel_used_ul.value));
    enc_put(&e, PFE_CSIG_OF_MODEL_IDENTIFIED, in->model_identified.state,
            raw_of_u64(PFE_CSIG_OF_MODEL_IDENTIFIED, in->model_identified.value));
    return enc_end(&e);
}

/* ------------------------------------------------------------ PFE_InputStatus */

int pfe_codec_decode_input_status(const pfe_can_frame_t *frame, pfe_msg_input_status_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->speed_source = u32_na;
    out->grade_source_address = u32_na;
    out->fuel_rate_source = u32_na;
    out->speed_senders = u32_na;
    out->grade_senders = u32_na;
    out->grade_source = u32_na;
    out->mass_source = u32_na;
    out->identification = u32_na;
    out->vehicle_mass_kg = u32_na;
    const int rc = check_frame(frame, PFE_MSG_INPUT_STATUS);
    if (rc != PFE_OK) {
        return rc;
    }
    out->speed_source = dec_u32(frame, PFE_CSIG_IS_SPEED_SOURCE);                 /* PFE_InputStatus.SpeedSourceAddress */
    out->grade_source_address = dec_u32(frame, PFE_CSIG_IS_GRADE_SOURCE_ADDRESS); /* PFE_InputStatus.GradeSourceAddress */
    out->fuel_rate_source = dec_u32(frame, PFE_CSIG_IS_FUEL_RATE_SOURCE);         /* PFE_InputStatus.FuelRateSourceAddress */
    out->speed_senders = dec_u32(frame, PFE_CSIG_IS_SPEED_SENDERS);               /* PFE_InputStatus.SpeedSenders */
    out->grade_senders = dec_u32(frame, PFE_CSIG_IS_GRADE_SENDERS);               /* PFE_InputStatus.GradeSenders */
    out->grade_source = dec_u32(frame, PFE_CSIG_IS_GRADE_SOURCE);                 /* PFE_InputStatus.GradeSource */
    out->mass_source = dec_u32(frame, PFE_CSIG_IS_MASS_SOURCE);                   /* PFE_InputStatus.MassSource */
    out->identification = dec_u32(frame, PFE_CSIG_IS_IDENTIFICATION_STATE);       /* PFE_InputStatus.IdentificationState */
    out->vehicle_mass_kg = dec_u32(frame, PFE_CSIG_IS_VEHICLE_MASS);   /* PFE_InputStatus.VehicleMass */
    return PFE_OK;
}

int pfe_codec_encode_input_status(pfe_can_frame_t *frame, const pfe_msg_input_status_t *in,
                                  uint8_t source)
{
    enc_t e;
    if ((in == NULL) ||
        (enc_begin(&e, frame, PFE_MSG_INPUT_STATUS, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_IS_SPEED_SOURCE, in->speed_source.state,
            raw_of_u64(PFE_CSIG_IS_SPEED_SOURCE, in->speed_source.value));
    enc_put(&e, PFE_CSIG_IS_GRADE_SOURCE_ADDRESS, in->grade_source_address.state,
            raw_of_u64(PFE_CSIG_IS_GRADE_SOURCE_ADDRESS, in->grade_source_address.value));
    enc_put(&e, PFE_CSIG_IS_FUEL_RATE_SOURCE, in->fuel_rate_source.state,
            raw_of_u64(PFE_CSIG_IS_FUEL_RATE_SOURCE, in->fuel_rate_source.value));
    enc_put(&e, PFE_CSIG_IS_SPEED_SENDERS, in->speed_senders.state,
            raw_of_u64(PFE_CSIG_IS_SPEED_SENDERS, in->speed_senders.value));
    enc_put(&e, PFE_CSIG_IS_GRADE_SENDERS, in->grade_senders.state,
            raw_of_u64(PFE_CSIG_IS_GRADE_SENDERS, in->grade_senders.value));
    enc_put(&e, PFE_CSIG_IS_GRADE_SOURCE, in->grade_source.state,
            raw_of_u64(PFE_CSIG_IS_GRADE_SOURCE, in->grade_source.value));
    enc_put(&e, PFE_CSIG_IS_MASS_SOURCE, in->mass_source.state,
            raw_of_u64(PFE_CSIG_IS_MASS_SOURCE, in->mass_source.value));
    enc_put(&e, PFE_CSIG_IS_IDENTIFICATION_STATE, in->identification.state,
            raw_of_u64(PFE_CSIG_IS_IDENTIFICATION_STATE, in->identification.value));
    enc_put(&e, PFE_CSIG_IS_VEHICLE_MASS, in->vehicle_mass_kg.state,
            raw_of_u64(PFE_CSIG_IS_VEHICLE_MASS, in->vehicle_mass_kg.value));
    return enc_end(&e);
}

/* ------------------------------------------------------------ PFE_DeviceStatus */

int pfe_codec_decode_device_status(const pfe_can_frame_t *frame, pfe_msg_device_status_t *out)
{
    if (out == NULL) {
        return PFE_EINVAL;
    }
    out->rx_fifo_overruns = u32_na;
    out->bus_off_events = u32_na;
    out->error_warning = u32_na;
    out->error_passive = u32_na;
    out->bus_off = u32_na;
    out->nvm_write_failing = u32_na;
    out->reset_cause = u32_na;
    out->tx_error_counter = u32_na;
    out->rx_error_counter = u32_na;
    out->nvm_write_failures = u32_na;
    const int rc = check_frame(frame, PFE_MSG_DEVICE_STATUS);
    if (rc != PFE_OK) {
        return rc;
    }
    out->rx_fifo_overruns = dec_u32(frame, PFE_CSIG_DS_RX_FIFO_OVERRUNS);     /* PFE_DeviceStatus.RxFifoOverruns */
    out->bus_off_events = dec_u32(frame, PFE_CSIG_DS_BUS_OFF_EVENTS);         /* PFE_DeviceStatus.BusOffEvents */
    out->error_warning = dec_u32(frame, PFE_CSIG_DS_ERROR_WARNING);           /* PFE_DeviceStatus.ErrorWarning */
    out->error_passive = dec_u32(frame, PFE_CSIG_DS_ERROR_PASSIVE);           /* PFE_DeviceStatus.ErrorPassive */
    out->bus_off = dec_u32(frame, PFE_CSIG_DS_BUS_OFF);                       /* PFE_DeviceStatus.BusOff */
    out->nvm_write_failing = dec_u32(frame, PFE_CSIG_DS_NVM_WRITE_FAILING);   /* PFE_DeviceStatus.NvmWriteFailing */
    out->reset_cause = dec_u32(frame, PFE_CSIG_DS_RESET_CAUSE);               /* PFE_DeviceStatus.ResetCause */
    out->tx_error_counter = dec_u32(frame, PFE_CSIG_DS_TX_ERROR_COUNTER);     /* PFE_DeviceStatus.TxErrorCounter */
    out->rx_error_counter = dec_u32(frame, PFE_CSIG_DS_RX_ERROR_COUNTER);     /* PFE_DeviceStatus.RxErrorCounter */
    out->nvm_write_failures = dec_u32(frame, PFE_CSIG_DS_NVM_WRITE_FAILURES); /* PFE_DeviceStatus.NvmWriteFailures */
    return PFE_OK;
}

int pfe_codec_encode_device_status(pfe_can_frame_t *frame, const pfe_msg_device_status_t *in,
                                   uint8_t source)
{
    enc_t e;
    if ((in == NULL) ||
        (enc_begin(&e, frame, PFE_MSG_DEVICE_STATUS, PFE_J1939_ADDR_GLOBAL, source) != PFE_OK)) {
        return PFE_EINVAL;
    }
    enc_put(&e, PFE_CSIG_DS_RX_FIFO_OVERRUNS, in->rx_fifo_overruns.state,
            raw_of_u64(PFE_CSIG_DS_RX_FIFO_OVERRUNS, in->rx_fifo_overruns.value));
    enc_put(&e, PFE_CSIG_DS_BUS_OFF_EVENTS, in->bus_off_events.state,
            raw_of_u64(PFE_CSIG_DS_BUS_OFF_EVENTS, in->bus_off_events.value));
    enc_put(&e, PFE_CSIG_DS_ERROR_WARNING, in->error_warning.state,
            raw_of_u64(PFE_CSIG_DS_ERROR_WARNING, in->error_warning.value));
    enc_put(&e, PFE_CSIG_DS_ERROR_PASSIVE, in->error_passive.state,
            raw_of_u64(PFE_CSIG_DS_ERROR_PASSIVE, in->error_passive.value));
    enc_put(&e, PFE_CSIG_DS_BUS_OFF, in->bus_off.state,
            raw_of_u64(PFE_CSIG_DS_BUS_OFF, in->bus_off.value));
    enc_put(&e, PFE_CSIG_DS_NVM_WRITE_FAILING, in->nvm_write_failing.state,
            raw_of_u64(PFE_CSIG_DS_NVM_WRITE_FAILING, in->nvm_write_failing.value));
    enc_put(&e, PFE_CSIG_DS_RESET_CAUSE, in->reset_cause.state,
            raw_of_u64(PFE_CSIG_DS_RESET_CAUSE, in->reset_cause.value));
    enc_put(&e, PFE_CSIG_DS_TX_ERROR_COUNTER, in->tx_error_counter.state,
            raw_of_u64(PFE_CSIG_DS_TX_ERROR_COUNTER, in->tx_error_counter.value));
    enc_put(&e, PFE_CSIG_DS_RX_ERROR_COUNTER, in->rx_error_counter.state,
            raw_of_u64(PFE_CSIG_DS_RX_ERROR_COUNTER, in->rx_error_counter.value));
    enc_put(&e, PFE_CSIG_DS_NVM_WRITE_FAILURES, in->nvm_write_failures.state,
            raw_of_u64(PFE_CSIG_DS_NVM_WRITE_FAILURES, in->nvm_write_failures.value));
    return enc_end(&e);
}
