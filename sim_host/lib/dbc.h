/*
 * dbc.h - a Vector DBC reader for the host tools and tests.
 *
 * Reads the subset of the DBC format that describes a J1939 network:
 * VERSION, NS_, BS_, BU_, BO_ and SG_ (Intel or Motorola, signed or not,
 * simple multiplexing with M and mN), CM_ (network, node, message, signal),
 * BA_DEF_, BA_DEF_DEF_ and BA_ (INT, HEX, FLOAT, STRING, ENUM on the
 * network, nodes, messages and signals), VAL_ on signals. Other sections a
 * DBC editor writes (VAL_TABLE_, SIG_VALTYPE_, BO_TX_BU_, EV_, SIG_GROUP_,
 * the relation attributes, ...) are recognised and skipped up to their ';'.
 *
 * Malformed input is refused with the line of the offending token and a
 * sentence saying what was expected; the reader never reads past its input
 * and frees everything it allocated on failure. Checks beyond the syntax:
 * a signal must lie inside its message's DLC (0..64 bytes) and be 1..64 bits
 * long; ids, message names, node names and signal names within a message
 * are unique; a multiplexed signal (mN) needs exactly one multiplexer (M) in
 * its message, and extended multiplexing (mNM) is refused; transmitters and
 * receivers are nodes of BU_ (or Vector__XXX); CM_, BA_ and VAL_ refer to
 * existing objects; BA_ names a defined attribute of the right object kind,
 * with a value of its type inside its range.
 *
 * Uses malloc; not for the firmware. No global state: reentrant.
 */
#ifndef DBC_H
#define DBC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define DBC_EXTENDED_ID_FLAG 0x80000000UL /* BO_ id bit 31: a 29-bit identifier */

typedef enum {
    DBC_MUX_NONE = 0,      /* in every frame */
    DBC_MUX_MULTIPLEXOR,   /* M */
    DBC_MUX_MULTIPLEXED    /* mN: present when the multiplexer reads N */
} dbc_mux_kind_t;

typedef enum {
    DBC_OBJ_NETWORK = 0,
    DBC_OBJ_NODE,          /* BU_ */
    DBC_OBJ_MESSAGE,       /* BO_ */
    DBC_OBJ_SIGNAL,        /* SG_ */
    DBC_OBJ_ENV            /* EV_ (definitions only; values are skipped) */
} dbc_object_t;

typedef enum {
    DBC_ATTR_INT = 0,
    DBC_ATTR_HEX,
    DBC_ATTR_FLOAT,
    DBC_ATTR_STRING,
    DBC_ATTR_ENUM
} dbc_attr_type_t;

/* An attribute value as written: a number's text, or a string's contents. */
typedef struct {
    char *name;
    char *value;
    bool is_string;
    int line;
} dbc_attr_t;

typedef struct {
    int64_t value;
    char *text;
} dbc_value_desc_t;

typedef struct {
    char *name;
    int line;
    uint32_t start_bit;
    uint32_t length;
    bool little_endian;        /* @1 (Intel); @0 is Motorola */
    bool is_signed;            /* - */
    double factor;
    double offset;
    double min;
    double max;
    char *factor_text;         /* the numbers as written, for exact comparisons */
    char *offset_text;
    char *min_text;
    char *max_text;
    char *unit;
    dbc_mux_kind_t mux_kind;
    uint32_t mux_value;        /* for DBC_MUX_MULTIPLEXED */
    char **receivers;
    size_t n_receivers;
    char *comment;             /* NULL if none */
    dbc_attr_t *attrs;
    size_t n_attrs;
    dbc_value_desc_t *values;  /* VAL_ */
    size_t n_values;
} dbc_signal_t;

typedef struct {
    uint32_t id;               /* as written: DBC_EXTENDED_ID_FLAG set for 29-bit ids */
    char *name;
    uint32_t dlc;
    char *transmitter;
    int line;
    dbc_signal_t *signals;
    size_t n_signals;
    char *comment;
    dbc_attr_t *attrs;
    size_t n_attrs;
} dbc_message_t;

typedef struct {
    char *name;
    char *comment;
    dbc_attr_t *attrs;
    size_t n_attrs;
} dbc_node_t;

typedef struct {
    char *name;
    dbc_object_t object;
    dbc_attr_type_t type;
    double min;                /* INT, HEX, FLOAT */
    double max;
    char **enum_values;
    size_t n_enum_values;
    char *default_value;       /* BA_DEF_DEF_, NULL if none */
    bool default_is_string;
} dbc_attr_def_t;

typedef struct {
    char *version;
    dbc_node_t *nodes;
    size_t n_nodes;
    dbc_message_t *messages;
    size_t n_messages;
    dbc_attr_def_t *attr_defs;
    size_t n_attr_defs;
    dbc_attr_t *attrs;         /* network attributes */
    size_t n_attrs;
    char *comment;             /* network comment */
} dbc_t;

typedef struct {
    int line;                  /* 1-based; 0 when the error has no line (file, memory) */
    char message[256];         /* one sentence, without the line */
} dbc_error_t;

/* Parses text[0 .. len). On success returns 0 and *out (free it with
 * dbc_free()); on failure returns -1, *out = NULL and fills *err (err may
 * be NULL). */
int dbc_parse_text(const char *text, size_t len, dbc_t **out, dbc_error_t *err);

/* Reads and parses a file (at most 64 MiB). Same contract. */
int dbc_parse_file(const char *path, dbc_t **out, dbc_error_t *err);

void dbc_free(dbc_t *dbc);

const dbc_message_t *dbc_message_by_id(const dbc_t *dbc, uint32_t id);
const dbc_message_t *dbc_message_by_name(const dbc_t *dbc, const char *name);
const dbc_signal_t *dbc_signal_by_name(const dbc_message_t *msg, const char *name);
const dbc_attr_def_t *dbc_attr_def(const dbc_t *dbc, dbc_object_t object, const char *name);

/*
 * Integer value of attribute name on an object: its own BA_ value, else the
 * BA_DEF_DEF_ default. ENUM values come out as their index. Returns 0 and
 * *out, or -1 if the attribute is not defined for that kind of object, has
 * no value, or is not INT, HEX or ENUM.
 */
int dbc_message_attr_int(const dbc_t *dbc, const dbc_message_t *msg, const char *name, int64_t *out);
int dbc_signal_attr_int(const dbc_t *dbc, const dbc_signal_t *sig, const char *name, int64_t *out);
int dbc_node_attr_int(const dbc_t *dbc, const dbc_node_t *node, const char *name, int64_t *out);

/*
 * A decimal number as written in a DBC ("0.00390625", "-64", "1E-3") as
 * the exact fraction num / den with den a power of ten. Returns 0, or -1
 * if the text is not a plain decimal number or does not fit in 18 digits.
 */
int dbc_decimal_to_rational(const char *text, int64_t *num, int64_t *den);

#endif /* DBC_H */
