/*
 * dbc2c - the firmware codec's tables from can_dbc/pfe.dbc: frame ids,
 * PGNs, signal layouts, scales, offsets, ranges, units, periods, value
 * states and the ECU's receive filters, as C source the firmware links
 * (firmware/pfe_codec.h, pfe_ecu.h declare what it defines), and the
 * header of the PGNs, periods and table indices pfe_codec.h includes.
 *
 * The manual (every option, the exit status, examples) is its --help:
 * k_manual below.
 */
#include "lib/dbc.h"

#include <inttypes.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lib/cli_help.h"
#include "lib/out_file.h"

/* The manual: --help prints it whole, a usage error its first lines. */
static const char k_manual[] =
    "usage: dbc2c DBC OUT.c OUT.h\n"
    "\n"
    "Writes the tables of the firmware's codec (firmware/pfe_codec.h) and the\n"
    "ECU's receive filters (firmware/pfe_ecu.h) from the DBC, as C source that\n"
    "every firmware build compiles in, and the header of the names the\n"
    "firmware gives the DBC's values, which firmware/pfe_codec.h includes as\n"
    "\"pfe_dbc.h\" (OUT.h is that file: the build puts its folder on the include\n"
    "path). A change of a PGN, scale, offset, range, unit, layout or period in\n"
    "the DBC changes the firmware with no other edit.\n"
    "\n"
    "OUT.h defines:\n"
    "\n"
    "    PFE_PGN_<MESSAGE>                   each message's PGN, from its id\n"
    "    PFE_RX_PERIOD_MS_<MESSAGE>          each received message's period: its\n"
    "                                        GenMsgCycleTime, or for a message sent\n"
    "                                        on request or on change (cycle time 0)\n"
    "                                        the DBC's PFEInputPeriod, the period the\n"
    "                                        module assumes when it gives up a silent\n"
    "                                        sender of the input; 0 for none\n"
    "    PFE_ECU_RX_FILTERS                  the number of received messages\n"
    "    PFE_CSIG_<SIGNAL>_MIN, _MAX         the [min|max] of each signal with a\n"
    "                                        unit, in the firmware's unit\n"
    "    pfe_msg_index_t, PFE_MSG_COUNT      the messages' indices in the tables\n"
    "    pfe_sig_index_t, PFE_CODEC_SIGNAL_COUNT\n"
    "                                        the signals' indices, message by message\n"
    "\n"
    "OUT.c defines:\n"
    "\n"
    "    pfe_codec_messages[PFE_MSG_COUNT]   per message: PGN, priority, the id's\n"
    "                                        source address, DLC, direction,\n"
    "                                        GenMsgCycleTime, its signals\n"
    "    pfe_codec_signals[PFE_CODEC_SIGNAL_COUNT]\n"
    "                                        per signal: start bit, length, byte\n"
    "                                        order, sign, multiplexing, SPN, scale\n"
    "                                        and offset as exact fractions, the\n"
    "                                        valid raw range of [min|max], the unit,\n"
    "                                        J1939 value states, and the scale and\n"
    "                                        offset in the firmware's unit\n"
    "    pfe_ecu_rx_filters[PFE_ECU_RX_FILTERS]\n"
    "                                        one filter per message the module\n"
    "                                        receives, any source address\n"
    "\n"
    "What the DBC says and the tables carry:\n"
    "  - a message is sent by the module when its transmitter is the node PFE,\n"
    "    and received when its attribute PFEReceivedFrom is AnySourceAddress\n"
    "    (the id's source address stands for any sender);\n"
    "  - a received message's period is its GenMsgCycleTime, or when that is 0\n"
    "    its PFEInputPeriod (0 .. 65535 ms);\n"
    "  - a signal has the J1939-71 value states (error, not available, and for\n"
    "    whole bytes parameter-specific and reserved codes) when its VAL_ names\n"
    "    its all-ones code NotAvailable; an Error entry must then be the J1939\n"
    "    error code (10b, or 0xFE followed by ones);\n"
    "  - the firmware value of a raw count is raw * num / den + offset in the\n"
    "    firmware's unit of that signal (km/h to mm/s, deg to micro- or\n"
    "    milli-degrees, % to ppm, L/h to nL/s, L to uL, s to ms, m to mm, ...),\n"
    "    num / den the DBC's scale times the unit's factor, reduced.\n"
    "\n"
    "Checked, each an error that names the message and signal: every message\n"
    "and signal the firmware decodes or encodes is in the DBC; a layout the\n"
    "firmware reads (Intel byte order, unsigned, 1 to 32 bits inside the DLC);\n"
    "a unit the firmware can convert; min and max that are whole raw counts\n"
    "inside the signal's bits and below the J1939 special codes; firmware values\n"
    "inside the firmware's integer type; a period of 0 to 65535 ms; an input\n"
    "the firmware watches (pfe_input.h: CCVS1, SSI, VDS, CVW, LFE1) with a\n"
    "period. Messages\n"
    "and signals of the DBC the firmware has no use for are left out.\n"
    "\n"
    "Each file is written under a temporary name and renamed, so a failed run\n"
    "leaves no partial file.\n"
    "\n"
    "Exit status: 0 done, 1 the DBC is unreadable, malformed or refused by a\n"
    "check above (the reason on standard error), or OUT.c or OUT.h cannot be\n"
    "written,\n"
    "2 usage error.\n"
    "\n"
    "Example:\n"
    "  dbc2c can_dbc/pfe.dbc build/gen/pfe_dbc.c build/gen/pfe_dbc.h\n";

#define MODULE_NODE "PFE"
#define RX_ATTR "PFEReceivedFrom"
#define RX_ANY 1 /* index of AnySourceAddress in the attribute's ENUM */
#define PERIOD_ATTR "PFEInputPeriod"

/* ------------------------------------------------------------ what the firmware needs */

/* The messages of pfe_msg_index_t, in its order: the firmware's name of
 * each (PFE_MSG_<name>, PFE_PGN_<name>, PFE_RX_PERIOD_MS_<name>). */
typedef struct {
    const char *c_name;  /* the firmware's name */
    const char *name;    /* DBC message */
    bool watched;        /* an input pfe_input.h watches: it needs a period */
} need_msg_t;

static const need_msg_t k_msgs[] = {
    {"CCVS1", "CCVS1", true},
    {"SSI", "SSI", true},
    {"PLATOON_CONFIG", "PFE_PlatoonConfig", false},
    {"GRADE_PREVIEW", "PFE_GradePreview", false},
    {"LFE1", "LFE1", true},
    {"PLATOON_FUEL", "PFE_PlatoonFuel", false},
    {"HRLFC", "HRLFC", false},
    {"FUEL_PREDICTION", "PFE_FuelPrediction", false},
    {"STATUS", "PFE_Status", false},
    {"ADDRESS_CLAIMED", "AddressClaimed", false},
    {"REQUEST", "Request", false},
    {"VDS", "VDS", true},
    {"CVW", "CVW", true},
    {"OWN_FUEL", "PFE_OwnFuel", false},
    {"INPUT_STATUS", "PFE_InputStatus", false},
    {"DEVICE_STATUS", "PFE_DeviceStatus", false},
};
#define N_MSGS (sizeof k_msgs / sizeof k_msgs[0])

/* The firmware's integer type of a converted value. */
typedef enum { FW_I32, FW_U32, FW_U64 } fw_type_t;

/* The signals of pfe_sig_index_t, in its order (message by message). */
typedef struct {
    const char *index;   /* enumerator of pfe_sig_index_t (OUT.h) */
    unsigned msg;        /* k_msgs[] */
    const char *name;    /* DBC signal */
    const char *fw_unit; /* the unit the firmware converts it to; "" a count or code */
    fw_type_t type;
} need_sig_t;

enum {
    M_CCVS1, M_SSI, M_PC, M_GP, M_LFE1, M_PF, M_HRLFC, M_FP, M_ST, M_AC, M_RQ, M_VDS, M_CVW,
    M_OF, M_IS, M_DS
};

static const need_sig_t k_sigs[] = {
    {"PFE_CSIG_CCVS1_WHEEL_BASED_VEHICLE_SPEED", M_CCVS1, "WheelBasedVehicleSpeed", "mm/s", FW_I32},
    {"PFE_CSIG_SSI_PITCH_ANGLE", M_SSI, "PitchAngle", "udeg", FW_I32},
    {"PFE_CSIG_SSI_ROLL_ANGLE", M_SSI, "RollAngle", "udeg", FW_I32},
    {"PFE_CSIG_SSI_PITCH_ANGLE_FOM", M_SSI, "PitchAngleFigureOfMerit", "", FW_U32},
    {"PFE_CSIG_PC_NUMBER_OF_VEHICLES", M_PC, "NumberOfVehicles", "", FW_U32},
    {"PFE_CSIG_PC_OWN_POSITION", M_PC, "OwnPosition", "", FW_U32},
    {"PFE_CSIG_PC_GAP", M_PC, "Gap", "mm", FW_U32},
    {"PFE_CSIG_PC_TIME_GAP", M_PC, "TimeGap", "ms", FW_U32},
    {"PFE_CSIG_PC_SET_SPEED", M_PC, "SetSpeed", "mm/s", FW_I32},
    {"PFE_CSIG_GP_FRAME_TYPE", M_GP, "PreviewFrameType", "", FW_U32},
    {"PFE_CSIG_GP_PREVIEW_ID", M_GP, "PreviewId", "", FW_U32},
    {"PFE_CSIG_GP_SAMPLE_COUNT", M_GP, "SampleCount", "", FW_U32},
    {"PFE_CSIG_GP_SAMPLE_SPACING", M_GP, "SampleSpacing", "m", FW_U32},
    {"PFE_CSIG_GP_SAMPLE_INDEX", M_GP, "SampleIndex", "", FW_U32},
    {"PFE_CSIG_GP_GRADE_SAMPLE0", M_GP, "GradeSample0", "ppm", FW_I32},
    {"PFE_CSIG_GP_GRADE_SAMPLE1", M_GP, "GradeSample1", "ppm", FW_I32},
    {"PFE_CSIG_GP_GRADE_SAMPLE2", M_GP, "GradeSample2", "ppm", FW_I32},
    {"PFE_CSIG_LFE1_ENGINE_FUEL_RATE", M_LFE1, "EngineFuelRate", "nL/s", FW_U32},
    {"PFE_CSIG_PF_PLATOON_FUEL_RATE", M_PF, "PlatoonFuelRate", "nL/s", FW_U32},
    {"PFE_CSIG_PF_PLATOON_TOTAL_FUEL_USED", M_PF, "PlatoonTotalFuelUsed", "uL", FW_U64},
    {"PFE_CSIG_HRLFC_TRIP_FUEL", M_HRLFC, "HighResolutionEngineTripFuel", "uL", FW_U64},
    {"PFE_CSIG_HRLFC_TOTAL_FUEL_USED", M_HRLFC, "HighResolutionEngineTotalFuelUsed", "uL", FW_U64},
    {"PFE_CSIG_FP_PREDICTED_FUEL", M_FP, "PredictedFuel", "uL", FW_U32},
    {"PFE_CSIG_FP_PREDICTED_FUEL_LOWER", M_FP, "PredictedFuelLowerBound", "uL", FW_U32},
    {"PFE_CSIG_FP_PREDICTED_FUEL_UPPER", M_FP, "PredictedFuelUpperBound", "uL", FW_U32},
    {"PFE_CSIG_FP_PREDICTED_TIME", M_FP, "PredictedTime", "ms", FW_U32},
    {"PFE_CSIG_ST_SPEED_INPUT", M_ST, "SpeedInputState", "", FW_U32},
    {"PFE_CSIG_ST_GRADE_INPUT", M_ST, "GradeInputState", "", FW_U32},
    {"PFE_CSIG_ST_PLATOON_CONFIG_INPUT", M_ST, "PlatoonConfigInputState", "", FW_U32},
    {"PFE_CSIG_ST_GRADE_PREVIEW_INPUT", M_ST, "GradePreviewInputState", "", FW_U32},
    {"PFE_CSIG_ST_DEGRADED_MODE", M_ST, "DegradedMode", "", FW_U32},
    {"PFE_CSIG_ST_RX_FRAMES_DROPPED", M_ST, "RxFramesDropped", "", FW_U32},
    {"PFE_CSIG_ST_TICK_OVERRUNS", M_ST, "TickOverruns", "", FW_U32},
    {"PFE_CSIG_ST_TX_FRAMES_DROPPED", M_ST, "TxFramesDropped", "", FW_U32},
    {"PFE_CSIG_ST_WARMING_UP", M_ST, "WarmingUp", "", FW_U32},
    {"PFE_CSIG_ST_SPEED_CLAMPED", M_ST, "SpeedClamped", "", FW_U32},
    {"PFE_CSIG_ST_GRADE_CLAMPED", M_ST, "GradeClamped", "", FW_U32},
    {"PFE_CSIG_ST_OUTPUT_SATURATED", M_ST, "OutputSaturated", "", FW_U32},
    {"PFE_CSIG_ST_INPUTS_REJECTED", M_ST, "InputsRejected", "", FW_U32},
    {"PFE_CSIG_ST_ADDRESS_CONFLICTS", M_ST, "AddressConflicts", "", FW_U32},
    {"PFE_CSIG_AC_IDENTITY_NUMBER", M_AC, "IdentityNumber", "", FW_U32},
    {"PFE_CSIG_AC_MANUFACTURER_CODE", M_AC, "ManufacturerCode", "", FW_U32},
    {"PFE_CSIG_AC_ECU_INSTANCE", M_AC, "EcuInstance", "", FW_U32},
    {"PFE_CSIG_AC_FUNCTION_INSTANCE", M_AC, "FunctionInstance", "", FW_U32},
    {"PFE_CSIG_AC_FUNCTION", M_AC, "Function", "", FW_U32},
    {"PFE_CSIG_AC_RESERVED", M_AC, "NameReserved", "", FW_U32},
    {"PFE_CSIG_AC_VEHICLE_SYSTEM", M_AC, "VehicleSystem", "", FW_U32},
    {"PFE_CSIG_AC_VEHICLE_SYSTEM_INSTANCE", M_AC, "VehicleSystemInstance", "", FW_U32},
    {"PFE_CSIG_AC_INDUSTRY_GROUP", M_AC, "IndustryGroup", "", FW_U32},
    {"PFE_CSIG_AC_ARBITRARY_ADDRESS_CAPABLE", M_AC, "ArbitraryAddressCapable", "", FW_U32},
    {"PFE_CSIG_RQST_REQUESTED_PGN", M_RQ, "RequestedPGN", "", FW_U32},
    {"PFE_CSIG_VDS_COMPASS_BEARING", M_VDS, "CompassBearing", "mdeg", FW_U32},
    {"PFE_CSIG_VDS_NAV_SPEED", M_VDS, "NavigationBasedVehicleSpeed", "mm/s", FW_I32},
    {"PFE_CSIG_VDS_PITCH", M_VDS, "Pitch", "mdeg", FW_I32},
    {"PFE_CSIG_VDS_ALTITUDE", M_VDS, "Altitude", "mm", FW_I32},
    {"PFE_CSIG_CVW_POWERED_VEHICLE_WEIGHT", M_CVW, "PoweredVehicleWeight", "kg", FW_U32},
    {"PFE_CSIG_CVW_GROSS_COMBINATION_WEIGHT", M_CVW, "GrossCombinationVehicleWeight", "kg", FW_U32},
    {"PFE_CSIG_OF_OWN_FUEL_RATE", M_OF, "OwnFuelRate", "nL/s", FW_U32},
    {"PFE_CSIG_OF_OWN_TOTAL_FUEL_USED", M_OF, "OwnTotalFuelUsed", "uL", FW_U64},
    {"PFE_CSIG_OF_MODEL_IDENTIFIED", M_OF, "ModelIdentified", "", FW_U32},
    {"PFE_CSIG_IS_SPEED_SOURCE", M_IS, "SpeedSourceAddress", "", FW_U32},
    {"PFE_CSIG_IS_GRADE_SOURCE_ADDRESS", M_IS, "GradeSourceAddress", "", FW_U32},
    {"PFE_CSIG_IS_FUEL_RATE_SOURCE", M_IS, "FuelRateSourceAddress", "", FW_U32},
    {"PFE_CSIG_IS_SPEED_SENDERS", M_IS, "SpeedSenders", "", FW_U32},
    {"PFE_CSIG_IS_GRADE_SENDERS", M_IS, "GradeSenders", "", FW_U32},
    {"PFE_CSIG_IS_GRADE_SOURCE", M_IS, "GradeSource", "", FW_U32},
    {"PFE_CSIG_IS_MASS_SOURCE", M_IS, "MassSource", "", FW_U32},
    {"PFE_CSIG_IS_IDENTIFICATION_STATE", M_IS, "IdentificationState", "", FW_U32},
    {"PFE_CSIG_IS_VEHICLE_MASS", M_IS, "VehicleMass", "kg", FW_U32},
    {"PFE_CSIG_DS_RX_FIFO_OVERRUNS", M_DS, "RxFifoOverruns", "", FW_U32},
    {"PFE_CSIG_DS_BUS_OFF_EVENTS", M_DS, "BusOffEvents", "", FW_U32},
    {"PFE_CSIG_DS_ERROR_WARNING", M_DS, "ErrorWarning", "", FW_U32},
    {"PFE_CSIG_DS_ERROR_PASSIVE", M_DS, "ErrorPassive", "", FW_U32},
    {"PFE_CSIG_DS_BUS_OFF", M_DS, "BusOff", "", FW_U32},
    {"PFE_CSIG_DS_NVM_WRITE_FAILING", M_DS, "NvmWriteFailing", "", FW_U32},
    {"PFE_CSIG_DS_RESET_CAUSE", M_DS, "ResetCause", "", FW_U32},
    {"PFE_CSIG_DS_TX_ERROR_COUNTER", M_DS, "TxErrorCounter", "", FW_U32},
    {"PFE_CSIG_DS_RX_ERROR_COUNTER", M_DS, "RxErrorCounter", "", FW_U32},
    {"PFE_CSIG_DS_NVM_WRITE_FAILURES", M_DS, "NvmWriteFailures", "", FW_U32},
};
#define N_SIGS (sizeof k_sigs / sizeof k_sigs[0])

/* A DBC unit in a firmware unit: firmware = DBC * num / den. */
typedef struct {
    const char *dbc;
    const char *fw;
    int64_t num;
    int64_t den;
} unit_t;

static const unit_t k_units[] = {
    {"km/h", "mm/s", 2500, 9},   {"m/s", "mm/s", 1000, 1},    {"mph", "mm/s", 11176, 25},
    {"deg", "udeg", 1000000, 1}, {"deg", "mdeg", 1000, 1},    {"%", "ppm", 10000, 1},
    {"m", "mm", 1000, 1},        {"cm", "mm", 10, 1},         {"km", "m", 1000, 1},
    {"m", "m", 1, 1},            {"s", "ms", 1000, 1},        {"ms", "ms", 1, 1},
    {"L/h", "nL/s", 2500000, 9}, {"mL/s", "nL/s", 1000000, 1}, {"L", "uL", 1000000, 1},
    {"mL", "uL", 1000, 1},       {"kg", "kg", 1, 1},          {"t", "kg", 1000, 1},
    {"", "", 1, 1},              {"frames", "", 1, 1},        {"ticks", "", 1, 1},
};

/* ------------------------------------------------------------ exact arithmetic */

typedef struct {
    int64_t num;
    int64_t den; /* > 0 */
} frac_t;

/* n / d reduced; false when it does not fit 62 bits. */
static bool frac_make(__int128 n, __int128 d, frac_t *out)
{
    if (d < 0) {
        n = -n;
        d = -d;
    }
    __int128 a = (n < 0) ? -n : n;
    __int128 b = d;
    while (b != 0) {
        const __int128 t = a % b;
        a = b;
        b = t;
    }
    if (a == 0) {
        a = 1;
    }
    n /= a;
    d /= a;
    const __int128 lim = (__int128)1 << 62;
    if ((n >= lim) || (n <= -lim) || (d >= lim) || (d == 0)) {
        return false;
    }
    out->num = (int64_t)n;
    out->den = (int64_t)d;
    return true;
}

static bool frac_of_text(const char *text, frac_t *out)
{
    int64_t n;
    int64_t d;
    if (dbc_decimal_to_rational(text, &n, &d) != 0) {
        return false;
    }
    return frac_make(n, d, out);
}

/* ------------------------------------------------------------ errors */

static const char *g_dbc_path;

static int fail(const dbc_message_t *m, const dbc_signal_t *s, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

static int fail(const dbc_message_t *m, const dbc_signal_t *s, const char *fmt, ...)
{
    const int line = (s != NULL) ? s->line : ((m != NULL) ? m->line : 0);
    fprintf(stderr, "dbc2c: %s:%d: ", g_dbc_path, line);
    if (m != NULL) {
        fprintf(stderr, "%s%s%s: ", m->name, (s != NULL) ? "." : "", (s != NULL) ? s->name : "");
    }
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    return -1;
}

/* ------------------------------------------------------------ one signal */

typedef struct {
    const dbc_signal_t *dbc;
    frac_t scale;
    frac_t offset;
    uint32_t raw_min;
    uint32_t raw_max;
    bool j1939;
    uint32_t spn;
    int mux;              /* -1 none, -2 the multiplexer, else its value */
    frac_t fw_scale;      /* firmware units per count */
    int64_t fw_offset;    /* firmware units */
} sig_out_t;

typedef struct {
    const dbc_message_t *dbc;
    uint32_t pgn;
    uint32_t priority;
    uint32_t address;
    uint32_t cycle_ms;
    uint32_t rx_period_ms; /* received: the cycle, or PFEInputPeriod when it is 0; else 0 */
    bool rx;
    bool tx;
    unsigned first;
    unsigned count;
} msg_out_t;

static uint64_t ones(uint32_t length)
{
    return (length >= 64U) ? UINT64_MAX : ((UINT64_C(1) << length) - 1U);
}

/* The J1939 error code a sender writes: 10b, or 0xFE then ones. */
static uint64_t j1939_error_code(uint32_t length)
{
    return (length == 2U) ? 2U : (ones(length) & ~(UINT64_C(1) << (length - 8U)));
}

/* A limit of [min|max] as a raw count: (phys - offset) / scale, a whole number. */
static int raw_of_limit(const dbc_message_t *m, const dbc_signal_t *s, const sig_out_t *o,
                        const char *text, const char *what, uint32_t *raw)
{
    frac_t phys;
    if (!frac_of_text(text, &phys)) {
        return fail(m, s, "%s '%s' is not an exact decimal number", what, text);
    }
    /* (pn/pd - on/od) / (sn/sd) = (pn od - on pd) sd / (pd od sn) */
    const __int128 n = ((__int128)phys.num * o->offset.den - (__int128)o->offset.num * phys.den) *
                       o->scale.den;
    const __int128 d = (__int128)phys.den * o->offset.den * o->scale.num;
    if ((d == 0) || ((n % d) != 0)) {
        return fail(m, s, "%s %s is not a whole number of raw counts of scale %s", what, text,
                    s->factor_text);
    }
    const __int128 r = n / d;
    if ((r < 0) || ((uint64_t)r > ones(s->length))) {
        return fail(m, s, "%s %s is raw %lld, outside the signal's %u bits", what, text,
                    (long long)r, (unsigned)s->length);
    }
    *raw = (uint32_t)r;
    return 0;
}

static const unit_t *unit_of(const char *dbc_unit, const char *fw_unit)
{
    for (size_t k = 0U; k < sizeof k_units / sizeof k_units[0]; k++) {
        if ((strcmp(k_units[k].dbc, dbc_unit) == 0) && (strcmp(k_units[k].fw, fw_unit) == 0)) {
            return &k_units[k];
        }
    }
    return NULL;
}

static int read_signal(const dbc_t *dbc, const dbc_message_t *m, const need_sig_t *need,
                       sig_out_t *o)
{
    const dbc_signal_t *s = dbc_signal_by_name(m, need->name);
    if (s == NULL) {
        return fail(m, NULL, "no signal %s, which the firmware reads or writes (%s)", need->name,
                    need->index);
    }
    o->dbc = s;
    if (!s->little_endian) {
        return fail(m, s, "Motorola byte order (@0): the firmware reads Intel (@1) only");
    }
    if (s->is_signed) {
        return fail(m, s, "signed (-): the firmware reads unsigned signals with an offset only");
    }
    if ((s->length < 1U) || (s->length > 32U) || ((s->start_bit + s->length) > (8U * m->dlc))) {
        return fail(m, s, "%u bits from bit %u: the firmware reads 1 to 32 bits inside the %u-byte DLC",
                    (unsigned)s->length, (unsigned)s->start_bit, (unsigned)m->dlc);
    }
    if (!frac_of_text(s->factor_text, &o->scale) || (o->scale.num <= 0)) {
        return fail(m, s, "scale '%s' is not a positive exact decimal", s->factor_text);
    }
    if (!frac_of_text(s->offset_text, &o->offset)) {
        return fail(m, s, "offset '%s' is not an exact decimal", s->offset_text);
    }
    if ((raw_of_limit(m, s, o, s->min_text, "min", &o->raw_min) != 0) ||
        (raw_of_limit(m, s, o, s->max_text, "max", &o->raw_max) != 0)) {
        return -1;
    }
    if (o->raw_min > o->raw_max) {
        return fail(m, s, "min %s above max %s", s->min_text, s->max_text);
    }
    /* J1939 value states: named by the VAL_ of the all-ones code */
    o->j1939 = false;
    bool has_error = false;
    uint64_t error_value = 0U;
    for (size_t k = 0U; k < s->n_values; k++) {
        if ((strcmp(s->values[k].text, "NotAvailable") == 0) &&
            ((uint64_t)s->values[k].value == ones(s->length))) {
            o->j1939 = true;
        }
        if (strcmp(s->values[k].text, "Error") == 0) {
            has_error = true;
            error_value = (uint64_t)s->values[k].value;
        }
    }
    if (o->j1939) {
        if ((s->length != 2U) && ((s->length % 8U) != 0U)) {
            return fail(m, s, "J1939 value states (VAL_ NotAvailable) on %u bits: 2 bits or whole bytes only",
                        (unsigned)s->length);
        }
        if (has_error && (error_value != j1939_error_code(s->length))) {
            return fail(m, s, "VAL_ Error is %" PRIu64 ", not the J1939 error code %" PRIu64, error_value,
                        j1939_error_code(s->length));
        }
        const uint64_t first_special = (s->length == 2U) ? 2U : (UINT64_C(0xFB) << (s->length - 8U));
        if ((uint64_t)o->raw_max >= first_special) {
            return fail(m, s, "max %s is raw %" PRIu32 ", inside the J1939 special codes (from %" PRIu64 ")",
                        s->max_text, o->raw_max, first_special);
        }
    }
    int64_t spn = 0;
    if ((dbc_attr_def(dbc, DBC_OBJ_SIGNAL, "SPN") != NULL) &&
        (dbc_signal_attr_int(dbc, s, "SPN", &spn) != 0)) {
        spn = 0;
    }
    if ((spn < 0) || (spn > 524287)) {
        return fail(m, s, "SPN %lld outside 0 .. 524287", (long long)spn);
    }
    o->spn = (uint32_t)spn;
    if (s->mux_kind == DBC_MUX_MULTIPLEXOR) {
        o->mux = -2;
    } else if (s->mux_kind == DBC_MUX_MULTIPLEXED) {
        if (s->mux_value > 127U) {
            return fail(m, s, "multiplexer value %u above 127", (unsigned)s->mux_value);
        }
        o->mux = (int)s->mux_value;
    } else {
        o->mux = -1;
    }
    /* the firmware's unit */
    const unit_t *u = unit_of(s->unit, need->fw_unit);
    if (u == NULL) {
        return fail(m, s, "unit \"%s\": the firmware converts this signal to %s%s%s and knows no factor for it",
                    s->unit, (need->fw_unit[0] == '\0') ? "a count" : "\"",
                    need->fw_unit, (need->fw_unit[0] == '\0') ? "" : "\"");
    }
    frac_t off_fw;
    if (!frac_make((__int128)o->scale.num * u->num, (__int128)o->scale.den * u->den, &o->fw_scale) ||
        !frac_make((__int128)o->offset.num * u->num, (__int128)o->offset.den * u->den, &off_fw)) {
        return fail(m, s, "scale or offset too large in %s", need->fw_unit);
    }
    if (off_fw.den != 1) {
        return fail(m, s, "offset %s %s is not a whole number of %s", s->offset_text, s->unit,
                    need->fw_unit);
    }
    o->fw_offset = off_fw.num;
    if ((o->fw_scale.num > INT32_MAX) || (o->fw_scale.den > INT32_MAX) ||
        (o->fw_offset > INT32_MAX) || (o->fw_offset < INT32_MIN)) {
        return fail(m, s, "scale %s %s is %" PRId64 "/%" PRId64 " %s: beyond 32 bits", s->factor_text,
                    s->unit, o->fw_scale.num, o->fw_scale.den, need->fw_unit);
    }
    /* every valid raw count's firmware value inside the firmware's type */
    const __int128 lo = ((__int128)o->raw_min * o->fw_scale.num) / o->fw_scale.den + o->fw_offset;
    const __int128 hi = ((__int128)o->raw_max * o->fw_scale.num + o->fw_scale.den) / o->fw_scale.den +
                        o->fw_offset;
    const __int128 tmin = (need->type == FW_I32) ? INT32_MIN : 0;
    const __int128 tmax = (need->type == FW_I32) ? INT32_MAX
                          : (need->type == FW_U32) ? (__int128)UINT32_MAX
                                                   : (__int128)INT64_MAX;
    if ((lo < tmin) || (hi > tmax)) {
        return fail(m, s, "[%s|%s] %s is beyond the firmware's %s in %s", s->min_text, s->max_text, s->unit,
                    (need->type == FW_I32) ? "int32" : (need->type == FW_U32) ? "uint32" : "uint64",
                    need->fw_unit);
    }
    return 0;
}

static uint32_t pgn_of_id(uint32_t id)
{
    const uint32_t pf = (id >> 16) & 0xFFU;
    return (pf < 240U) ? ((id >> 8) & 0x3FF00U) : ((id >> 8) & 0x3FFFFU);
}

/* A message's integer attribute, or 0 when the DBC does not define it or
 * gives it no integer value (the defaults of every attribute read here). */
static int64_t message_attr(const dbc_t *dbc, const dbc_message_t *m, const char *name)
{
    int64_t v = 0;
    if ((dbc_attr_def(dbc, DBC_OBJ_MESSAGE, name) == NULL) || (dbc_message_attr_int(dbc, m, name, &v) != 0)) {
        return 0;
    }
    return v;
}

static int read_message(const dbc_t *dbc, unsigned k, msg_out_t *o)
{
    const dbc_message_t *m = dbc_message_by_name(dbc, k_msgs[k].name);
    if (m == NULL) {
        fprintf(stderr, "dbc2c: %s: no message %s, which the firmware reads or sends (PFE_MSG_%s)\n",
                g_dbc_path, k_msgs[k].name, k_msgs[k].c_name);
        return -1;
    }
    o->dbc = m;
    if ((m->id & DBC_EXTENDED_ID_FLAG) == 0U) {
        return fail(m, NULL, "an 11-bit id: J1939 messages have 29-bit ids");
    }
    if ((m->dlc < 1U) || (m->dlc > 8U)) {
        return fail(m, NULL, "DLC %u: classical CAN, 1 to 8 bytes", (unsigned)m->dlc);
    }
    const uint32_t id = m->id & 0x1FFFFFFFU;
    o->pgn = pgn_of_id(id);
    o->priority = (id >> 26) & 7U;
    o->address = id & 0xFFU;
    const int64_t cycle = message_attr(dbc, m, "GenMsgCycleTime");
    if ((cycle < 0) || (cycle > 65535)) {
        return fail(m, NULL, "GenMsgCycleTime %lld outside 0 .. 65535 ms", (long long)cycle);
    }
    o->cycle_ms = (uint32_t)cycle;
    const int64_t rx = message_attr(dbc, m, RX_ATTR);
    o->rx = rx == RX_ANY;
    o->tx = strcmp(m->transmitter, MODULE_NODE) == 0;
    if (!o->rx && !o->tx) {
        return fail(m, NULL, "neither sent by %s nor received (%s AnySourceAddress)", MODULE_NODE, RX_ATTR);
    }
    const int64_t assumed = message_attr(dbc, m, PERIOD_ATTR);
    if ((assumed < 0) || (assumed > 65535)) {
        return fail(m, NULL, "%s %lld outside 0 .. 65535 ms", PERIOD_ATTR, (long long)assumed);
    }
    o->rx_period_ms = o->rx ? ((o->cycle_ms != 0U) ? o->cycle_ms : (uint32_t)assumed) : 0U;
    if (k_msgs[k].watched && (!o->rx || (o->rx_period_ms == 0U))) {
        return fail(m, NULL, "an input the firmware watches needs %s AnySourceAddress and a period "
                    "(GenMsgCycleTime, or %s when it is sent on request or on change)", RX_ATTR, PERIOD_ATTR);
    }
    return 0;
}

/* ------------------------------------------------------------ output */

static void put_signal_comment(FILE *f, const sig_out_t *o)
{
    fprintf(f, "        /* %s: %s %s, offset %s; [%s|%s] */\n", o->dbc->name, o->dbc->factor_text,
            o->dbc->unit, o->dbc->offset_text, o->dbc->min_text, o->dbc->max_text);
}

typedef struct {
    const char *dbc_path;
    const msg_out_t *msgs;
    const sig_out_t *sigs;
} tables_t;

static int write_source(FILE *f, const void *ctx)
{
    const tables_t *t = ctx;
    const char *dbc_path = t->dbc_path;
    const msg_out_t *msgs = t->msgs;
    const sig_out_t *sigs = t->sigs;
    fprintf(f,
            "/*\n"
            " * The codec's tables and the ECU's receive filters, written by dbc2c from\n"
            " * %s: change the DBC, not this file. Declared in firmware/pfe_codec.h\n"
            " * and firmware/pfe_ecu.h; the manual is dbc2c --help.\n"
            " */\n"
            "#include <stdbool.h>\n"
            "#include <stdint.h>\n"
            "\n"
            "#include \"pfe_codec.h\"\n"
            "#include \"pfe_ecu.h\"\n"
            "\n",
            dbc_path);
    fputs("/* Names only host tools and tests read: an image built with\n"
            " * PFE_CODEC_NO_NAMES keeps the tables without them. */\n"
            "#ifdef PFE_CODEC_NO_NAMES\n"
            "#define DBC_TEXT(s) \"\"\n"
            "#define DBC_HOST(...)\n"
            "#else\n"
            "#define DBC_TEXT(s) (s)\n"
            "#define DBC_HOST(...) __VA_ARGS__\n"
            "#endif\n"
            "\n"
          "const pfe_codec_message_t pfe_codec_messages[PFE_MSG_COUNT] = {\n",
          f);
    for (unsigned k = 0U; k < N_MSGS; k++) {
        const msg_out_t *m = &msgs[k];
        const char *dir = (m->rx && m->tx) ? "PFE_CODEC_DIR_RX | PFE_CODEC_DIR_TX"
                          : m->rx          ? "PFE_CODEC_DIR_RX"
                                           : "PFE_CODEC_DIR_TX";
        fprintf(f,
                "    [PFE_MSG_%s] = {.name = DBC_TEXT(\"%s\"), .pgn = %" PRIu32 "UL, .priority = %" PRIu32 "U,\n"
                "        .dbc_address = 0x%02" PRIX32 "U, .dlc = %uU, .direction = %s,\n"
                "        .cycle_ms = %" PRIu32 "U, .first_signal = (uint8_t)%s, .n_signals = %uU},\n",
                k_msgs[k].c_name, m->dbc->name, m->pgn, m->priority, m->address, (unsigned)m->dbc->dlc,
                dir, m->cycle_ms, k_sigs[m->first].index, m->count);
    }
    fputs("};\n\nconst pfe_codec_signal_t pfe_codec_signals[PFE_CODEC_SIGNAL_COUNT] = {\n", f);
    for (unsigned i = 0U; i < N_SIGS; i++) {
        const sig_out_t *o = &sigs[i];
        const msg_out_t *m = &msgs[k_sigs[i].msg];
        char mux[32];
        if (o->mux == -1) {
            (void)snprintf(mux, sizeof mux, "PFE_CODEC_MUX_NONE");
        } else if (o->mux == -2) {
            (void)snprintf(mux, sizeof mux, "PFE_CODEC_MUXER");
        } else {
            (void)snprintf(mux, sizeof mux, "%d", o->mux);
        }
        put_signal_comment(f, o);
        fprintf(f,
                "    [%s] = {DBC_HOST(.message = \"%s\", .pgn = %" PRIu32 "UL,\n"
                "        .name = \"%s\", .spn = %" PRIu32 "U,) .start_bit = %uU, .length = %uU,\n"
                "        .byte_order = PFE_CODEC_LITTLE_ENDIAN, .is_signed = false, .mux = %s,\n"
                "        .ranges = %s,\n"
                "        DBC_HOST(.scale_num = %" PRId64 ", .scale_den = %" PRId64 ", .offset_num = %" PRId64
                ", .offset_den = %" PRId64 ",)\n"
                "        .raw_min = %" PRIu32 "UL, .raw_max = %" PRIu32 "UL, DBC_HOST(.unit = \"%s\",)\n"
                "        .fw_num = %" PRId64 ", .fw_den = %" PRId64 ", .fw_offset = %" PRId64 "},\n",
                k_sigs[i].index, m->dbc->name, m->pgn, o->dbc->name, o->spn, (unsigned)o->dbc->start_bit,
                (unsigned)o->dbc->length, mux, o->j1939 ? "PFE_CODEC_RANGES_J1939" : "PFE_CODEC_RANGES_NONE",
                o->scale.num, o->scale.den, o->offset.num, o->offset.den, o->raw_min, o->raw_max,
                o->dbc->unit, o->fw_scale.num, o->fw_scale.den, o->fw_offset);
    }
    fputs("};\n\n"
          "/* Every received message from any source address; a PDU1 PGN to any destination. */\n"
          "const pfe_ecu_filter_t pfe_ecu_rx_filters[PFE_ECU_RX_FILTERS] = {\n",
          f);
    for (unsigned k = 0U; k < N_MSGS; k++) {
        if (msgs[k].rx) {
            const bool pdu1 = ((msgs[k].pgn >> 8) & 0xFFU) < 240U;
            fprintf(f, "    {PFE_CAN_EFF_FLAG | (%" PRIu32 "UL << 8), PFE_CAN_EFF_FLAG | 0x%08" PRIX32 "UL}, /* %s */\n",
                    msgs[k].pgn, pdu1 ? 0x03FF0000U : 0x03FFFF00U, k_msgs[k].name);
        }
    }
    return (fputs("};\n", f) == EOF) ? -1 : 0;
}

/* The firmware value of a raw count, as the codec decodes it
 * (firmware/pfe_codec.c fw_of_raw: raw * num / den rounded to nearest, plus
 * the offset). */
static int64_t fw_value(const sig_out_t *o, uint32_t raw)
{
    const __int128 den = o->fw_scale.den;
    return (int64_t)(((__int128)raw * o->fw_scale.num + den / 2) / den) + o->fw_offset;
}

static int write_header(FILE *f, const void *ctx)
{
    const tables_t *t = ctx;
    const msg_out_t *msgs = t->msgs;
    fprintf(f,
            "/*\n"
            " * The DBC's values under the firmware's names, written by dbc2c from\n"
            " * %s: change the DBC, not this file. Included by firmware/pfe_codec.h;\n"
            " * the manual is dbc2c --help.\n"
            " */\n"
            "#ifndef PFE_DBC_H\n"
            "#define PFE_DBC_H\n"
            "\n"
            "/* Each message's PGN, from its id. */\n",
            t->dbc_path);
    for (unsigned k = 0U; k < N_MSGS; k++) {
        fprintf(f, "#define PFE_PGN_%s %" PRIu32 "UL /* 0x%04" PRIX32 ", %s */\n", k_msgs[k].c_name,
                msgs[k].pgn, msgs[k].pgn, msgs[k].dbc->name);
    }
    fputs("\n/* Each received message's period, ms: GenMsgCycleTime, or for one sent on\n"
          " * request or on change (GenMsgCycleTime 0) its PFEInputPeriod, the period\n"
          " * the module assumes before it gives up a silent sender; 0: none. */\n",
          f);
    unsigned n_rx = 0U;
    for (unsigned k = 0U; k < N_MSGS; k++) {
        if (msgs[k].rx) {
            fprintf(f, "#define PFE_RX_PERIOD_MS_%s %" PRIu32 "U\n", k_msgs[k].c_name, msgs[k].rx_period_ms);
            n_rx++;
        }
    }
    fprintf(f,
            "\n/* Messages the module receives (PFEReceivedFrom AnySourceAddress): one\n"
            " * receive filter each (pfe_ecu_rx_filters[]). */\n"
            "#define PFE_ECU_RX_FILTERS %uU\n"
            "\n"
            "/* Index of each message in pfe_codec_messages[]. */\n"
            "typedef enum {\n",
            n_rx);
    for (unsigned k = 0U; k < N_MSGS; k++) {
        fprintf(f, "    PFE_MSG_%s = %u, /* %s */\n", k_msgs[k].c_name, k, msgs[k].dbc->name);
    }
    fprintf(f,
            "    PFE_MSG_COUNT = %u\n"
            "} pfe_msg_index_t;\n"
            "\n"
            "/* Index of each signal in pfe_codec_signals[], message by message. */\n"
            "typedef enum {\n",
            (unsigned)N_MSGS);
    for (unsigned i = 0U; i < N_SIGS; i++) {
        fprintf(f, "    %s = %u, /* %s.%s */\n", k_sigs[i].index, i, msgs[k_sigs[i].msg].dbc->name,
                t->sigs[i].dbc->name);
    }
    fprintf(f,
            "    PFE_CODEC_SIGNAL_COUNT = %u\n"
            "} pfe_sig_index_t;\n"
            "\n"
            "/* The [min|max] of each signal with a unit, in the firmware's unit (as\n"
            " * the codec decodes raw min and raw max: rounded to nearest). */\n",
            (unsigned)N_SIGS);
    for (unsigned i = 0U; i < N_SIGS; i++) {
        const sig_out_t *o = &t->sigs[i];
        if (k_sigs[i].fw_unit[0] == '\0') {
            continue;
        }
        const char *suffix = (k_sigs[i].type == FW_I32) ? "" : (k_sigs[i].type == FW_U32) ? "U" : "ULL";
        const int64_t lim[2] = {fw_value(o, o->raw_min), fw_value(o, o->raw_max)};
        for (unsigned j = 0U; j < 2U; j++) {
            fprintf(f, "#define %s_%s %s%" PRId64 "%s%s /* %s %s */\n", k_sigs[i].index, (j == 0U) ? "MIN" : "MAX",
                    (lim[j] < 0) ? "(" : "", lim[j], suffix, (lim[j] < 0) ? ")" : "",
                    (j == 0U) ? o->dbc->min_text : o->dbc->max_text, o->dbc->unit);
        }
    }
    fputs("\n#endif /* PFE_DBC_H */\n", f);
    return ferror(f) ? -1 : 0;
}

int main(int argc, char **argv)
{
    if (cli_help_asked(argc, argv)) {
        cli_help(k_manual);
        return 0;
    }
    if (argc != 4) {
        cli_usage(stderr, k_manual, "dbc2c");
        return 2;
    }
    g_dbc_path = argv[1];
    const char *out_path = argv[2];
    const char *header_path = argv[3];
    dbc_t *dbc = NULL;
    dbc_error_t err;
    if (dbc_parse_file(g_dbc_path, &dbc, &err) != 0) {
        fprintf(stderr, "dbc2c: %s:%d: %s\n", g_dbc_path, err.line, err.message);
        return 1;
    }
    static msg_out_t msgs[N_MSGS];
    static sig_out_t sigs[N_SIGS];
    int rc = 0;
    for (unsigned k = 0U; (k < N_MSGS) && (rc == 0); k++) {
        rc = read_message(dbc, k, &msgs[k]);
        msgs[k].count = 0U;
    }
    for (unsigned i = 0U; (i < N_SIGS) && (rc == 0); i++) {
        msg_out_t *m = &msgs[k_sigs[i].msg];
        if (m->count == 0U) {
            m->first = i;
        }
        m->count++;
        rc = read_signal(dbc, m->dbc, &k_sigs[i], &sigs[i]);
    }
    if (rc != 0) {
        dbc_free(dbc);
        return 1;
    }

    const tables_t tables = {g_dbc_path, msgs, sigs};
    rc = ((out_file_write(out_path, "dbc2c", write_source, &tables) == 0) &&
          (out_file_write(header_path, "dbc2c", write_header, &tables) == 0))
             ? 0
             : 1;
    dbc_free(dbc);
    return rc;
}
