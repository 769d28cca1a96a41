/* dbc.c - Vector DBC reader (contract in dbc.h). */
#include "lib/dbc.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DBC_MAX_FILE_BYTES (64L * 1024L * 1024L)
#define DBC_MAX_DLC 64U                      /* CAN FD */
#define DBC_INDEPENDENT_SIG_ID 0xC0000000UL  /* CANdb++'s VECTOR__INDEPENDENT_SIG_MSG */
#define DBC_NUMBER_TEXT_MAX 63U

/* ------------------------------------------------------------ tokens */

typedef enum { T_EOF = 0, T_IDENT, T_NUMBER, T_STRING, T_PUNCT } tkind_t;

typedef struct {
    tkind_t kind;
    const char *s;       /* text (for T_STRING: between the quotes, escapes kept) */
    size_t n;
    int line;
    bool line_start;     /* first character of its line (column 0) */
} token_t;

typedef struct {
    token_t *toks;
    size_t n_toks;
    size_t cap_toks;
    size_t pos;
    dbc_t *dbc;
    dbc_error_t *err;
    bool failed;
    bool oom;
    size_t cur_msg;      /* message SG_ lines attach to; SIZE_MAX: none */
    char desc[64];
} parser_t;

static int fail(parser_t *p, int line, const char *fmt, ...)
{
    if (!p->failed) {
        p->failed = true;
        if (p->err != NULL) {
            va_list ap;
            va_start(ap, fmt);
            p->err->line = line;
            (void)vsnprintf(p->err->message, sizeof p->err->message, fmt, ap);
            va_end(ap);
        }
    }
    return -1;
}

static int fail_oom(parser_t *p)
{
    p->oom = true;
    return fail(p, 0, "out of memory");
}

static const char *describe(parser_t *p, const token_t *t)
{
    switch (t->kind) {
    case T_EOF:
        return "end of file";
    case T_STRING:
        return "a string";
    default: {
        const int n = (t->n > 24U) ? 24 : (int)t->n;
        (void)snprintf(p->desc, sizeof p->desc, "'%.*s%s'", n, t->s, (t->n > 24U) ? "..." : "");
        return p->desc;
    }
    }
}

static int push_token(parser_t *p, const token_t *t)
{
    if (p->n_toks == p->cap_toks) {
        const size_t cap = (p->cap_toks == 0U) ? 256U : (p->cap_toks * 2U);
        if (cap > (SIZE_MAX / sizeof(token_t))) {
            return fail_oom(p);
        }
        token_t *q = realloc(p->toks, cap * sizeof(token_t));
        if (q == NULL) {
            return fail_oom(p);
        }
        p->toks = q;
        p->cap_toks = cap;
    }
    p->toks[p->n_toks++] = *t;
    return 0;
}

static bool is_ident_start(char c)
{
    return (isalpha((unsigned char)c) != 0) || (c == '_');
}

static bool is_ident_char(char c)
{
    return (isalnum((unsigned char)c) != 0) || (c == '_');
}

static bool is_digit_at(const char *text, size_t len, size_t i)
{
    return (i < len) && (isdigit((unsigned char)text[i]) != 0);
}

static int lex(parser_t *p, const char *text, size_t len)
{
    size_t i = 0U;
    size_t line_start = 0U;
    int line = 1;
    while (i < len) {
        const char c = text[i];
        if (c == '\n') {
            if (line == INT_MAX) {
                return fail(p, line, "too many lines");
            }
            line++;
            i++;
            line_start = i;
            continue;
        }
        if ((c == ' ') || (c == '\t') || (c == '\r') || (c == '\f') || (c == '\v')) {
            i++;
            continue;
        }
        if (c == '\0') {
            return fail(p, line, "NUL byte in the input (not a text file?)");
        }
        token_t t = {T_EOF, text + i, 0U, line, i == line_start};
        if (c == '"') {
            const int start_line = line;
            size_t j = i + 1U;
            while ((j < len) && (text[j] != '"')) {
                if (text[j] == '\0') {
                    return fail(p, line, "NUL byte inside a string");
                }
                if ((text[j] == '\\') && ((j + 1U) < len)) {
                    j++;
                }
                if (text[j] == '\n') {
                    line = (line == INT_MAX) ? line : (line + 1);
                    line_start = j + 1U;
                }
                j++;
            }
            if (j >= len) {
                return fail(p, start_line, "unterminated string (no closing '\"')");
            }
            t.kind = T_STRING;
            t.s = text + i + 1U;
            t.n = j - i - 1U;
            i = j + 1U;
        } else if (is_ident_start(c)) {
            size_t j = i + 1U;
            while ((j < len) && is_ident_char(text[j])) {
                j++;
            }
            t.kind = T_IDENT;
            t.n = j - i;
            i = j;
        } else if (is_digit_at(text, len, i) ||
                   (((c == '-') || (c == '+')) &&
                    (is_digit_at(text, len, i + 1U) ||
                     (((i + 2U) < len) && (text[i + 1U] == '.') && is_digit_at(text, len, i + 2U)))) ||
                   ((c == '.') && is_digit_at(text, len, i + 1U))) {
            size_t j = i;
            if ((text[j] == '-') || (text[j] == '+')) {
                j++;
            }
            while (is_digit_at(text, len, j)) {
                j++;
            }
            if ((j < len) && (text[j] == '.')) {
                j++;
                while (is_digit_at(text, len, j)) {
                    j++;
                }
            }
            if ((j < len) && ((text[j] == 'e') || (text[j] == 'E'))) {
                size_t k = j + 1U;
                if ((k < len) && ((text[k] == '-') || (text[k] == '+'))) {
                    k++;
                }
                if (is_digit_at(text, len, k)) {
                    while (is_digit_at(text, len, k)) {
                        k++;
                    }
                    j = k;
                }
            }
            if ((j < len) && (is_ident_char(text[j]) || (text[j] == '.'))) {
                return fail(p, line, "malformed number '%.*s'", (int)((j - i) + 1U), text + i);
            }
            t.kind = T_NUMBER;
            t.n = j - i;
            i = j;
        } else if (strchr(":;|@()[],+-", c) != NULL) {
            t.kind = T_PUNCT;
            t.n = 1U;
            i++;
        } else {
            if (isprint((unsigned char)c) != 0) {
                return fail(p, line, "unexpected character '%c'", c);
            }
            return fail(p, line, "unexpected byte 0x%02X", (unsigned)(unsigned char)c);
        }
        if (push_token(p, &t) != 0) {
            return -1;
        }
    }
    const token_t eof = {T_EOF, text + len, 0U, line, false};
    return push_token(p, &eof);
}

/* ------------------------------------------------------------ token helpers */

static const token_t *peek(const parser_t *p)
{
    return &p->toks[p->pos];
}

static const token_t *take(parser_t *p)
{
    const token_t *t = &p->toks[p->pos];
    if (t->kind != T_EOF) {
        p->pos++;
    }
    return t;
}

static bool tok_is(const token_t *t, tkind_t kind, const char *text)
{
    return (t->kind == kind) && (strlen(text) == t->n) && (memcmp(t->s, text, t->n) == 0);
}

static bool tok_punct(const token_t *t, char c)
{
    return (t->kind == T_PUNCT) && (t->s[0] == c);
}

static char *dup_range(parser_t *p, const char *s, size_t n)
{
    if (n == SIZE_MAX) {
        (void)fail_oom(p);
        return NULL;
    }
    char *d = malloc(n + 1U);
    if (d == NULL) {
        (void)fail_oom(p);
        return NULL;
    }
    memcpy(d, s, n);
    d[n] = '\0';
    return d;
}

/* A string token's contents with \" and \\ unescaped. */
static char *dup_string(parser_t *p, const token_t *t)
{
    char *d = dup_range(p, t->s, t->n);
    if (d == NULL) {
        return NULL;
    }
    size_t w = 0U;
    for (size_t r = 0U; r < t->n; r++) {
        if ((d[r] == '\\') && ((r + 1U) < t->n) && ((d[r + 1U] == '"') || (d[r + 1U] == '\\'))) {
            r++;
        }
        d[w++] = d[r];
    }
    d[w] = '\0';
    return d;
}

static int expect_punct(parser_t *p, char c, const char *what)
{
    const token_t *t = take(p);
    if (!tok_punct(t, c)) {
        return fail(p, t->line, "expected '%c' %s, found %s", c, what, describe(p, t));
    }
    return 0;
}

static int expect_ident(parser_t *p, const char *what, const token_t **out)
{
    const token_t *t = take(p);
    if (t->kind != T_IDENT) {
        return fail(p, t->line, "expected %s (a name), found %s", what, describe(p, t));
    }
    *out = t;
    return 0;
}

static int expect_string(parser_t *p, const char *what, char **out)
{
    const token_t *t = take(p);
    if (t->kind != T_STRING) {
        return fail(p, t->line, "expected %s (a quoted string), found %s", what, describe(p, t));
    }
    *out = dup_string(p, t);
    return (*out == NULL) ? -1 : 0;
}

/* Copies a number token into buf for strto*; fails if too long. */
static int number_text(parser_t *p, const token_t *t, char buf[DBC_NUMBER_TEXT_MAX + 1U])
{
    if (t->n > DBC_NUMBER_TEXT_MAX) {
        return fail(p, t->line, "number too long");
    }
    memcpy(buf, t->s, t->n);
    buf[t->n] = '\0';
    return 0;
}

static int parse_u64_token(parser_t *p, const token_t *t, uint64_t max, const char *what, uint64_t *out)
{
    char buf[DBC_NUMBER_TEXT_MAX + 1U];
    if ((t->kind != T_NUMBER) || (number_text(p, t, buf) != 0)) {
        if (p->failed) {
            return -1;
        }
        return fail(p, t->line, "expected %s (a number), found %s", what, describe(p, t));
    }
    for (size_t i = 0U; buf[i] != '\0'; i++) {
        if (isdigit((unsigned char)buf[i]) == 0) {
            return fail(p, t->line, "%s must be a whole number >= 0, found '%s'", what, buf);
        }
    }
    errno = 0;
    const unsigned long long v = strtoull(buf, NULL, 10);
    if ((errno != 0) || (v > max)) {
        return fail(p, t->line, "%s %s is out of range (at most %llu)", what, buf, (unsigned long long)max);
    }
    *out = (uint64_t)v;
    return 0;
}

static int expect_u32(parser_t *p, uint64_t max, const char *what, uint32_t *out)
{
    uint64_t v;
    if (parse_u64_token(p, take(p), max, what, &v) != 0) {
        return -1;
    }
    *out = (uint32_t)v;
    return 0;
}

static int parse_i64_text(parser_t *p, int line, const char *buf, const char *what, int64_t *out)
{
    size_t i = ((buf[0] == '-') || (buf[0] == '+')) ? 1U : 0U;
    if (buf[i] == '\0') {
        return fail(p, line, "%s must be a whole number, found '%s'", what, buf);
    }
    for (; buf[i] != '\0'; i++) {
        if (isdigit((unsigned char)buf[i]) == 0) {
            return fail(p, line, "%s must be a whole number, found '%s'", what, buf);
        }
    }
    errno = 0;
    const long long v = strtoll(buf, NULL, 10);
    if (errno != 0) {
        return fail(p, line, "%s %s is out of range", what, buf);
    }
    *out = (int64_t)v;
    return 0;
}

static int expect_i64(parser_t *p, const char *what, int64_t *out)
{
    char buf[DBC_NUMBER_TEXT_MAX + 1U];
    const token_t *t = take(p);
    if (t->kind != T_NUMBER) {
        return fail(p, t->line, "expected %s (a number), found %s", what, describe(p, t));
    }
    if (number_text(p, t, buf) != 0) {
        return -1;
    }
    return parse_i64_text(p, t->line, buf, what, out);
}

static int parse_double_text(parser_t *p, int line, const char *buf, const char *what, double *out)
{
    char *end = NULL;
    errno = 0;
    const double v = strtod(buf, &end);
    if ((end == buf) || (*end != '\0')) {
        return fail(p, line, "%s: '%s' is not a number", what, buf);
    }
    if ((errno == ERANGE) && ((v > 1.0) || (v < -1.0))) {
        return fail(p, line, "%s %s is out of range", what, buf);
    }
    if (!isfinite(v)) {
        return fail(p, line, "%s %s is not finite", what, buf);
    }
    *out = v;
    return 0;
}

/* A number; *text (if not NULL) receives its text as written. */
static int expect_double(parser_t *p, const char *what, double *out, char **text)
{
    char buf[DBC_NUMBER_TEXT_MAX + 1U];
    const token_t *t = take(p);
    if (t->kind != T_NUMBER) {
        return fail(p, t->line, "expected %s (a number), found %s", what, describe(p, t));
    }
    if ((number_text(p, t, buf) != 0) || (parse_double_text(p, t->line, buf, what, out) != 0)) {
        return -1;
    }
    if (text != NULL) {
        *text = dup_range(p, t->s, t->n);
        if (*text == NULL) {
            return -1;
        }
    }
    return 0;
}

/* Grows *arr (n elements of size elem) by one zeroed element. */
static void *push_elem(parser_t *p, void **arr, size_t *n, size_t elem)
{
    if (*n >= ((SIZE_MAX / elem) - 1U)) {
        (void)fail_oom(p);
        return NULL;
    }
    void *q = realloc(*arr, (*n + 1U) * elem);
    if (q == NULL) {
        (void)fail_oom(p);
        return NULL;
    }
    *arr = q;
    void *e = (char *)q + (*n * elem);
    memset(e, 0, elem);
    (*n)++;
    return e;
}

static int skip_to_semicolon(parser_t *p, const token_t *kw)
{
    for (;;) {
        const token_t *t = take(p);
        if (t->kind == T_EOF) {
            return fail(p, kw->line, "'%.*s' statement has no closing ';'", (int)kw->n, kw->s);
        }
        if (tok_punct(t, ';')) {
            return 0;
        }
    }
}

/* ------------------------------------------------------------ freeing */

static void free_attrs(dbc_attr_t *attrs, size_t n)
{
    for (size_t i = 0U; i < n; i++) {
        free(attrs[i].name);
        free(attrs[i].value);
    }
    free(attrs);
}

static void free_signal(dbc_signal_t *s)
{
    free(s->name);
    free(s->factor_text);
    free(s->offset_text);
    free(s->min_text);
    free(s->max_text);
    free(s->unit);
    for (size_t i = 0U; i < s->n_receivers; i++) {
        free(s->receivers[i]);
    }
    free(s->receivers);
    free(s->comment);
    free_attrs(s->attrs, s->n_attrs);
    for (size_t i = 0U; i < s->n_values; i++) {
        free(s->values[i].text);
    }
    free(s->values);
}

void dbc_free(dbc_t *dbc)
{
    if (dbc == NULL) {
        return;
    }
    free(dbc->version);
    for (size_t i = 0U; i < dbc->n_nodes; i++) {
        free(dbc->nodes[i].name);
        free(dbc->nodes[i].comment);
        free_attrs(dbc->nodes[i].attrs, dbc->nodes[i].n_attrs);
    }
    free(dbc->nodes);
    for (size_t i = 0U; i < dbc->n_messages; i++) {
        dbc_message_t *m = &dbc->messages[i];
        free(m->name);
        free(m->transmitter);
        for (size_t k = 0U; k < m->n_signals; k++) {
            free_signal(&m->signals[k]);
        }
        free(m->signals);
        free(m->comment);
        free_attrs(m->attrs, m->n_attrs);
    }
    free(dbc->messages);
    for (size_t i = 0U; i < dbc->n_attr_defs; i++) {
        dbc_attr_def_t *d = &dbc->attr_defs[i];
        free(d->name);
        for (size_t k = 0U; k < d->n_enum_values; k++) {
            free(d->enum_values[k]);
        }
        free(d->enum_values);
        free(d->default_value);
    }
    free(dbc->attr_defs);
    free_attrs(dbc->attrs, dbc->n_attrs);
    free(dbc->comment);
    free(dbc);
}

/* ------------------------------------------------------------ lookups */

static dbc_node_t *find_node(const dbc_t *dbc, const char *name, size_t n)
{
    for (size_t i = 0U; i < dbc->n_nodes; i++) {
        if ((strlen(dbc->nodes[i].name) == n) && (memcmp(dbc->nodes[i].name, name, n) == 0)) {
            return &dbc->nodes[i];
        }
    }
    return NULL;
}

static bool is_node_or_placeholder(const dbc_t *dbc, const char *name)
{
    return (strcmp(name, "Vector__XXX") == 0) || (find_node(dbc, name, strlen(name)) != NULL);
}

static dbc_message_t *find_message(const dbc_t *dbc, uint32_t id)
{
    for (size_t i = 0U; i < dbc->n_messages; i++) {
        if (dbc->messages[i].id == id) {
            return &dbc->messages[i];
        }
    }
    return NULL;
}

static dbc_signal_t *find_signal(const dbc_message_t *m, const char *name, size_t n)
{
    for (size_t i = 0U; i < m->n_signals; i++) {
        if ((strlen(m->signals[i].name) == n) && (memcmp(m->signals[i].name, name, n) == 0)) {
            return &m->signals[i];
        }
    }
    return NULL;
}

const dbc_message_t *dbc_message_by_id(const dbc_t *dbc, uint32_t id)
{
    return (dbc == NULL) ? NULL : find_message(dbc, id);
}

const dbc_message_t *dbc_message_by_name(const dbc_t *dbc, const char *name)
{
    if ((dbc == NULL) || (name == NULL)) {
        return NULL;
    }
    for (size_t i = 0U; i < dbc->n_messages; i++) {
        if (strcmp(dbc->messages[i].name, name) == 0) {
            return &dbc->messages[i];
        }
    }
    return NULL;
}

const dbc_signal_t *dbc_signal_by_name(const dbc_message_t *msg, const char *name)
{
    return ((msg == NULL) || (name == NULL)) ? NULL : find_signal(msg, name, strlen(name));
}

const dbc_attr_def_t *dbc_attr_def(const dbc_t *dbc, dbc_object_t object, const char *name)
{
    if ((dbc == NULL) || (name == NULL)) {
        return NULL;
    }
    for (size_t i = 0U; i < dbc->n_attr_defs; i++) {
        if ((dbc->attr_defs[i].object == object) && (strcmp(dbc->attr_defs[i].name, name) == 0)) {
            return &dbc->attr_defs[i];
        }
    }
    return NULL;
}

/* Message named by a number token (CM_, BA_, VAL_). */
static int ref_message(parser_t *p, const char *stmt, dbc_message_t **out)
{
    uint32_t id;
    const int line = peek(p)->line;
    if (expect_u32(p, UINT32_MAX, "message id", &id) != 0) {
        return -1;
    }
    *out = find_message(p->dbc, id);
    if (*out == NULL) {
        return fail(p, line, "%s refers to message %lu, which no BO_ defines", stmt, (unsigned long)id);
    }
    return 0;
}

static int ref_signal(parser_t *p, const char *stmt, dbc_signal_t **out)
{
    dbc_message_t *m;
    const token_t *t;
    if ((ref_message(p, stmt, &m) != 0) || (expect_ident(p, "signal name", &t) != 0)) {
        return -1;
    }
    *out = find_signal(m, t->s, t->n);
    if (*out == NULL) {
        return fail(p, t->line, "%s refers to signal '%.*s', which message %s does not have", stmt,
                    (int)t->n, t->s, m->name);
    }
    return 0;
}

static int ref_node(parser_t *p, const char *stmt, dbc_node_t **out)
{
    const token_t *t;
    if (expect_ident(p, "node name", &t) != 0) {
        return -1;
    }
    *out = find_node(p->dbc, t->s, t->n);
    if (*out == NULL) {
        return fail(p, t->line, "%s refers to node '%.*s', which BU_ does not list", stmt, (int)t->n, t->s);
    }
    return 0;
}

/* ------------------------------------------------------------ sections */

static int parse_version(parser_t *p, const token_t *kw)
{
    if (p->dbc->version != NULL) {
        return fail(p, kw->line, "second VERSION");
    }
    return expect_string(p, "the version after VERSION", &p->dbc->version);
}

static int parse_ns(parser_t *p, const token_t *kw)
{
    if (expect_punct(p, ':', "after NS_") != 0) {
        return -1;
    }
    /* The list runs over the NS_ line and the indented lines below it. */
    while ((peek(p)->kind != T_EOF) && ((peek(p)->line == kw->line) || !peek(p)->line_start)) {
        (void)take(p);
    }
    return 0;
}

static int parse_bs(parser_t *p, const token_t *kw)
{
    if (expect_punct(p, ':', "after BS_") != 0) {
        return -1;
    }
    while ((peek(p)->kind != T_EOF) && (peek(p)->line == kw->line)) {
        (void)take(p);
    }
    return 0;
}

static int parse_bu(parser_t *p, const token_t *kw)
{
    if (expect_punct(p, ':', "after BU_") != 0) {
        return -1;
    }
    while ((peek(p)->kind == T_IDENT) && (peek(p)->line == kw->line)) {
        const token_t *t = take(p);
        if (find_node(p->dbc, t->s, t->n) != NULL) {
            return fail(p, t->line, "node '%.*s' listed twice in BU_", (int)t->n, t->s);
        }
        dbc_node_t *node = push_elem(p, (void **)&p->dbc->nodes, &p->dbc->n_nodes, sizeof *node);
        if (node == NULL) {
            return -1;
        }
        node->name = dup_range(p, t->s, t->n);
        if (node->name == NULL) {
            return -1;
        }
    }
    if ((peek(p)->kind != T_EOF) && (peek(p)->line == kw->line)) {
        return fail(p, peek(p)->line, "expected a node name in BU_, found %s", describe(p, peek(p)));
    }
    return 0;
}

static int parse_bo(parser_t *p, const token_t *kw)
{
    uint32_t id;
    uint32_t dlc;
    const token_t *name;
    const token_t *tx;
    const int id_line = peek(p)->line;
    if ((expect_u32(p, UINT32_MAX, "message id after BO_", &id) != 0) ||
        (expect_ident(p, "message name", &name) != 0) ||
        (expect_punct(p, ':', "after the message name") != 0)) {
        return -1;
    }
    const int dlc_line = peek(p)->line;
    if ((expect_u32(p, UINT32_MAX, "DLC", &dlc) != 0) || (expect_ident(p, "transmitter", &tx) != 0)) {
        return -1;
    }
    (void)kw;
    if (dlc > DBC_MAX_DLC) {
        return fail(p, dlc_line, "DLC %lu of message %.*s is larger than %u bytes", (unsigned long)dlc,
                    (int)name->n, name->s, DBC_MAX_DLC);
    }
    const dbc_message_t *prev = find_message(p->dbc, id);
    if (prev != NULL) {
        return fail(p, id_line, "message id %lu already used by %s (line %d)", (unsigned long)id,
                    prev->name, prev->line);
    }
    for (size_t i = 0U; i < p->dbc->n_messages; i++) {
        const char *other = p->dbc->messages[i].name;
        if ((strlen(other) == name->n) && (memcmp(other, name->s, name->n) == 0)) {
            return fail(p, name->line, "message name %s already used (line %d)", other,
                        p->dbc->messages[i].line);
        }
    }
    dbc_message_t *m = push_elem(p, (void **)&p->dbc->messages, &p->dbc->n_messages, sizeof *m);
    if (m == NULL) {
        return -1;
    }
    m->id = id;
    m->dlc = dlc;
    m->line = id_line;
    m->name = dup_range(p, name->s, name->n);
    m->transmitter = dup_range(p, tx->s, tx->n);
    if ((m->name == NULL) || (m->transmitter == NULL)) {
        return -1;
    }
    if (!is_node_or_placeholder(p->dbc, m->transmitter)) {
        return fail(p, tx->line, "transmitter '%s' of %s is not a node of BU_", m->transmitter, m->name);
    }
    p->cur_msg = p->dbc->n_messages - 1U;
    return 0;
}

/* Highest bit (0 .. 8*dlc-1 numbering) a Motorola signal reaches, or -1 when
 * it runs off the top of the payload. */
static int64_t motorola_last_bit(uint32_t start, uint32_t length)
{
    int64_t bit = (int64_t)start;
    for (uint32_t i = 1U; i < length; i++) {
        if ((bit % 8) == 0) {
            bit += 15;
        } else {
            bit--;
        }
    }
    return bit;
}

static int parse_mux_indicator(parser_t *p, const token_t *t, dbc_signal_t *s)
{
    if (tok_is(t, T_IDENT, "M")) {
        s->mux_kind = DBC_MUX_MULTIPLEXOR;
        return 0;
    }
    if ((t->n >= 2U) && (t->s[0] == 'm')) {
        size_t i = 1U;
        uint64_t v = 0U;
        while ((i < t->n) && (isdigit((unsigned char)t->s[i]) != 0)) {
            v = (v * 10U) + (uint64_t)(t->s[i] - '0');
            if (v > UINT32_MAX) {
                return fail(p, t->line, "multiplexer value in '%.*s' is too large", (int)t->n, t->s);
            }
            i++;
        }
        if ((i > 1U) && (i == t->n)) {
            s->mux_kind = DBC_MUX_MULTIPLEXED;
            s->mux_value = (uint32_t)v;
            return 0;
        }
        if ((i > 1U) && (i + 1U == t->n) && (t->s[i] == 'M')) {
            return fail(p, t->line, "extended multiplexing ('%.*s') is not supported", (int)t->n, t->s);
        }
    }
    return fail(p, t->line, "bad multiplexer indicator '%.*s' (expected M or m<number>)", (int)t->n, t->s);
}

static int parse_sg(parser_t *p, const token_t *kw)
{
    if (p->cur_msg == SIZE_MAX) {
        return fail(p, kw->line, "SG_ outside a message (no BO_ right before it)");
    }
    dbc_message_t *m = &p->dbc->messages[p->cur_msg];
    const token_t *name;
    if (expect_ident(p, "signal name after SG_", &name) != 0) {
        return -1;
    }
    if (find_signal(m, name->s, name->n) != NULL) {
        return fail(p, name->line, "signal %.*s appears twice in message %s", (int)name->n, name->s, m->name);
    }
    dbc_signal_t *s = push_elem(p, (void **)&m->signals, &m->n_signals, sizeof *s);
    if (s == NULL) {
        return -1;
    }
    s->line = kw->line;
    s->name = dup_range(p, name->s, name->n);
    if (s->name == NULL) {
        return -1;
    }
    if ((peek(p)->kind == T_IDENT) && (parse_mux_indicator(p, take(p), s) != 0)) {
        return -1;
    }
    if ((expect_punct(p, ':', "after the signal name") != 0) ||
        (expect_u32(p, 511U, "start bit", &s->start_bit) != 0) ||
        (expect_punct(p, '|', "between start bit and length") != 0) ||
        (expect_u32(p, 64U, "signal length", &s->length) != 0) ||
        (expect_punct(p, '@', "before the byte order") != 0)) {
        return -1;
    }
    const token_t *order = take(p);
    if (tok_is(order, T_NUMBER, "1")) {
        s->little_endian = true;
    } else if (tok_is(order, T_NUMBER, "0")) {
        s->little_endian = false;
    } else {
        return fail(p, order->line, "byte order must be 0 (Motorola) or 1 (Intel), found %s",
                    describe(p, order));
    }
    const token_t *sign = take(p);
    if (tok_punct(sign, '+') || tok_punct(sign, '-')) {
        s->is_signed = tok_punct(sign, '-');
    } else {
        return fail(p, sign->line, "expected '+' or '-' after the byte order, found %s", describe(p, sign));
    }
    if ((expect_punct(p, '(', "before the factor") != 0) ||
        (expect_double(p, "factor", &s->factor, &s->factor_text) != 0) ||
        (expect_punct(p, ',', "between factor and offset") != 0) ||
        (expect_double(p, "offset", &s->offset, &s->offset_text) != 0) ||
        (expect_punct(p, ')', "after the offset") != 0) ||
        (expect_punct(p, '[', "before the minimum") != 0) ||
        (expect_double(p, "minimum", &s->min, &s->min_text) != 0) ||
        (expect_punct(p, '|', "between minimum and maximum") != 0) ||
        (expect_double(p, "maximum", &s->max, &s->max_text) != 0) ||
        (expect_punct(p, ']', "after the maximum") != 0) ||
        (expect_string(p, "unit", &s->unit) != 0)) {
        return -1;
    }
    /* Receivers: node names after the unit, on its line, separated by ',' (or blanks). */
    const int unit_line = p->toks[p->pos - 1U].line;
    for (;;) {
        const token_t *r = peek(p);
        if ((r->kind != T_IDENT) || (r->line != unit_line)) {
            return fail(p, r->line, "expected a receiver (node name or Vector__XXX) for signal %s, found %s",
                        s->name, describe(p, r));
        }
        (void)take(p);
        char **slot = push_elem(p, (void **)&s->receivers, &s->n_receivers, sizeof *slot);
        if (slot == NULL) {
            return -1;
        }
        *slot = dup_range(p, r->s, r->n);
        if (*slot == NULL) {
            return -1;
        }
        if (!is_node_or_placeholder(p->dbc, *slot)) {
            return fail(p, r->line, "receiver '%s' of signal %s is not a node of BU_", *slot, s->name);
        }
        if (tok_punct(peek(p), ',')) {
            (void)take(p);
        } else if ((peek(p)->kind != T_IDENT) || (peek(p)->line != unit_line)) {
            break;
        }
    }
    if (s->length == 0U) {
        return fail(p, s->line, "signal %s has length 0", s->name);
    }
    if (m->id != DBC_INDEPENDENT_SIG_ID) {
        const uint64_t bits = (uint64_t)m->dlc * 8U;
        bool inside;
        if (s->little_endian) {
            inside = ((uint64_t)s->start_bit + s->length) <= bits;
        } else {
            const int64_t last = motorola_last_bit(s->start_bit, s->length);
            inside = (s->start_bit < bits) && (last >= 0) && ((uint64_t)last < bits);
        }
        if (!inside) {
            return fail(p, s->line, "signal %s (start %lu, length %lu) does not fit in the %lu bytes of %s",
                        s->name, (unsigned long)s->start_bit, (unsigned long)s->length,
                        (unsigned long)m->dlc, m->name);
        }
    }
    return 0;
}

static int parse_cm(parser_t *p, const token_t *kw)
{
    const token_t *t = peek(p);
    char **slot = NULL;
    char *ignored = NULL;
    if (t->kind == T_STRING) {
        slot = &p->dbc->comment;
    } else if (tok_is(t, T_IDENT, "BU_")) {
        dbc_node_t *node;
        (void)take(p);
        if (ref_node(p, "CM_ BU_", &node) != 0) {
            return -1;
        }
        slot = &node->comment;
    } else if (tok_is(t, T_IDENT, "BO_")) {
        dbc_message_t *m;
        (void)take(p);
        if (ref_message(p, "CM_ BO_", &m) != 0) {
            return -1;
        }
        slot = &m->comment;
    } else if (tok_is(t, T_IDENT, "SG_")) {
        dbc_signal_t *s;
        (void)take(p);
        if (ref_signal(p, "CM_ SG_", &s) != 0) {
            return -1;
        }
        slot = &s->comment;
    } else if (tok_is(t, T_IDENT, "EV_")) {
        const token_t *ev;
        (void)take(p);
        if (expect_ident(p, "environment variable", &ev) != 0) {
            return -1;
        }
        slot = &ignored;
    } else {
        return fail(p, t->line, "expected a string or BU_, BO_, SG_, EV_ after CM_, found %s", describe(p, t));
    }
    char *text;
    if (expect_string(p, "comment", &text) != 0) {
        return -1;
    }
    free(*slot);
    *slot = text;
    free(ignored);
    (void)kw;
    return expect_punct(p, ';', "after the comment");
}

static bool object_keyword(const token_t *t, dbc_object_t *obj)
{
    if (tok_is(t, T_IDENT, "BU_")) {
        *obj = DBC_OBJ_NODE;
    } else if (tok_is(t, T_IDENT, "BO_")) {
        *obj = DBC_OBJ_MESSAGE;
    } else if (tok_is(t, T_IDENT, "SG_")) {
        *obj = DBC_OBJ_SIGNAL;
    } else if (tok_is(t, T_IDENT, "EV_")) {
        *obj = DBC_OBJ_ENV;
    } else {
        return false;
    }
    return true;
}

static const char *object_name(dbc_object_t obj)
{
    switch (obj) {
    case DBC_OBJ_NODE:
        return "nodes (BU_)";
    case DBC_OBJ_MESSAGE:
        return "messages (BO_)";
    case DBC_OBJ_SIGNAL:
        return "signals (SG_)";
    case DBC_OBJ_ENV:
        return "environment variables (EV_)";
    default:
        return "the network";
    }
}

static int parse_ba_def(parser_t *p, const token_t *kw)
{
    dbc_object_t obj = DBC_OBJ_NETWORK;
    if (object_keyword(peek(p), &obj)) {
        (void)take(p);
    }
    const int name_line = peek(p)->line;
    char *name;
    if (expect_string(p, "attribute name", &name) != 0) {
        return -1;
    }
    if (dbc_attr_def(p->dbc, obj, name) != NULL) {
        (void)fail(p, name_line, "attribute \"%s\" defined twice for %s", name, object_name(obj));
        free(name);
        return -1;
    }
    dbc_attr_def_t *d = push_elem(p, (void **)&p->dbc->attr_defs, &p->dbc->n_attr_defs, sizeof *d);
    if (d == NULL) {
        free(name);
        return -1;
    }
    d->name = name;
    d->object = obj;
    const token_t *type = take(p);
    if (tok_is(type, T_IDENT, "INT") || tok_is(type, T_IDENT, "HEX")) {
        int64_t lo;
        int64_t hi;
        d->type = tok_is(type, T_IDENT, "INT") ? DBC_ATTR_INT : DBC_ATTR_HEX;
        if ((expect_i64(p, "attribute minimum", &lo) != 0) || (expect_i64(p, "attribute maximum", &hi) != 0)) {
            return -1;
        }
        d->min = (double)lo;
        d->max = (double)hi;
    } else if (tok_is(type, T_IDENT, "FLOAT")) {
        d->type = DBC_ATTR_FLOAT;
        if ((expect_double(p, "attribute minimum", &d->min, NULL) != 0) ||
            (expect_double(p, "attribute maximum", &d->max, NULL) != 0)) {
            return -1;
        }
    } else if (tok_is(type, T_IDENT, "STRING")) {
        d->type = DBC_ATTR_STRING;
    } else if (tok_is(type, T_IDENT, "ENUM")) {
        d->type = DBC_ATTR_ENUM;
        for (;;) {
            char **slot = push_elem(p, (void **)&d->enum_values, &d->n_enum_values, sizeof *slot);
            if ((slot == NULL) || (expect_string(p, "enumeration value", slot) != 0)) {
                return -1;
            }
            if (!tok_punct(peek(p), ',')) {
                break;
            }
            (void)take(p);
        }
    } else {
        return fail(p, type->line, "expected INT, HEX, FLOAT, STRING or ENUM for attribute \"%s\", found %s",
                    d->name, describe(p, type));
    }
    (void)kw;
    return expect_punct(p, ';', "after the attribute definition");
}

/* Checks a value (text as written) against a definition. */
static int check_attr_value(parser_t *p, int line, const dbc_attr_def_t *d, const char *value, bool is_string)
{
    switch (d->type) {
    case DBC_ATTR_STRING:
        if (!is_string) {
            return fail(p, line, "attribute \"%s\" is a STRING: its value must be quoted", d->name);
        }
        return 0;
    case DBC_ATTR_ENUM:
        if (is_string) {
            for (size_t i = 0U; i < d->n_enum_values; i++) {
                if (strcmp(d->enum_values[i], value) == 0) {
                    return 0;
                }
            }
            return fail(p, line, "\"%s\" is not a value of the enumeration \"%s\"", value, d->name);
        } else {
            int64_t v;
            if (parse_i64_text(p, line, value, "enumeration index", &v) != 0) {
                return -1;
            }
            if ((v < 0) || ((uint64_t)v >= d->n_enum_values)) {
                return fail(p, line, "index %s is outside the enumeration \"%s\" (0 .. %lu)", value, d->name,
                            (unsigned long)d->n_enum_values - 1UL);
            }
            return 0;
        }
    case DBC_ATTR_INT:
    case DBC_ATTR_HEX:
    case DBC_ATTR_FLOAT: {
        double v;
        if (is_string) {
            return fail(p, line, "attribute \"%s\" takes a number, found a string", d->name);
        }
        if (d->type != DBC_ATTR_FLOAT) {
            int64_t iv;
            if (parse_i64_text(p, line, value, d->name, &iv) != 0) {
                return -1;
            }
            v = (double)iv;
        } else if (parse_double_text(p, line, value, d->name, &v) != 0) {
            return -1;
        }
        if ((d->min < d->max) && ((v < d->min) || (v > d->max))) {
            return fail(p, line, "value %s of attribute \"%s\" is outside [%.17g, %.17g]", value, d->name,
                        d->min, d->max);
        }
        return 0;
    }
    default:
        return fail(p, line, "attribute \"%s\" has an unknown type", d->name);
    }
}

/* Reads an attribute value token: a number or a string. */
static int take_attr_value(parser_t *p, char **value, bool *is_string, int *line)
{
    const token_t *t = take(p);
    *line = t->line;
    if (t->kind == T_STRING) {
        *is_string = true;
        *value = dup_string(p, t);
    } else if (t->kind == T_NUMBER) {
        *is_string = false;
        *value = dup_range(p, t->s, t->n);
    } else {
        return fail(p, t->line, "expected an attribute value (number or string), found %s", describe(p, t));
    }
    return (*value == NULL) ? -1 : 0;
}

static int parse_ba_def_def(parser_t *p, const token_t *kw)
{
    const int name_line = peek(p)->line;
    char *name = NULL;
    char *value = NULL;
    bool is_string = false;
    int line = 0;
    int rc = -1;
    if ((expect_string(p, "attribute name", &name) != 0) ||
        (take_attr_value(p, &value, &is_string, &line) != 0)) {
        goto out;
    }
    bool found = false;
    for (size_t i = 0U; i < p->dbc->n_attr_defs; i++) {
        dbc_attr_def_t *d = &p->dbc->attr_defs[i];
        if (strcmp(d->name, name) != 0) {
            continue;
        }
        found = true;
        if (check_attr_value(p, line, d, value, is_string) != 0) {
            goto out;
        }
        char *copy = dup_range(p, value, strlen(value));
        if (copy == NULL) {
            goto out;
        }
        free(d->default_value);
        d->default_value = copy;
        d->default_is_string = is_string;
    }
    if (!found) {
        (void)fail(p, name_line, "BA_DEF_DEF_ for attribute \"%s\", which no BA_DEF_ defines", name);
        goto out;
    }
    (void)kw;
    rc = expect_punct(p, ';', "after the attribute default");
out:
    free(name);
    free(value);
    return rc;
}

static int set_attr(parser_t *p, dbc_attr_t **attrs, size_t *n, char **name, char **value, bool is_string,
                    int line)
{
    for (size_t i = 0U; i < *n; i++) {
        if (strcmp((*attrs)[i].name, *name) == 0) {
            free((*attrs)[i].value);
            (*attrs)[i].value = *value;
            (*attrs)[i].is_string = is_string;
            (*attrs)[i].line = line;
            *value = NULL;
            return 0;
        }
    }
    dbc_attr_t *a = push_elem(p, (void **)attrs, n, sizeof *a);
    if (a == NULL) {
        return -1;
    }
    a->name = *name;
    a->value = *value;
    a->is_string = is_string;
    a->line = line;
    *name = NULL;
    *value = NULL;
    return 0;
}

static int parse_ba(parser_t *p, const token_t *kw)
{
    const int name_line = peek(p)->line;
    char *name = NULL;
    char *value = NULL;
    bool is_string = false;
    int line = 0;
    int rc = -1;
    dbc_object_t obj = DBC_OBJ_NETWORK;
    dbc_attr_t **attrs = &p->dbc->attrs;
    size_t *n_attrs = &p->dbc->n_attrs;
    if (expect_string(p, "attribute name", &name) != 0) {
        goto out;
    }
    if (object_keyword(peek(p), &obj)) {
        (void)take(p);
        if (obj == DBC_OBJ_NODE) {
            dbc_node_t *node;
            if (ref_node(p, "BA_", &node) != 0) {
                goto out;
            }
            attrs = &node->attrs;
            n_attrs = &node->n_attrs;
        } else if (obj == DBC_OBJ_MESSAGE) {
            dbc_message_t *m;
            if (ref_message(p, "BA_", &m) != 0) {
                goto out;
            }
            attrs = &m->attrs;
            n_attrs = &m->n_attrs;
        } else if (obj == DBC_OBJ_SIGNAL) {
            dbc_signal_t *s;
            if (ref_signal(p, "BA_", &s) != 0) {
                goto out;
            }
            attrs = &s->attrs;
            n_attrs = &s->n_attrs;
        } else {
            const token_t *ev;
            if (expect_ident(p, "environment variable", &ev) != 0) {
                goto out;
            }
            attrs = NULL; /* environment variables are not kept */
        }
    }
    if (take_attr_value(p, &value, &is_string, &line) != 0) {
        goto out;
    }
    const dbc_attr_def_t *d = dbc_attr_def(p->dbc, obj, name);
    if (d == NULL) {
        (void)fail(p, name_line, "attribute \"%s\" is not defined for %s (no BA_DEF_)", name, object_name(obj));
        goto out;
    }
    if ((check_attr_value(p, line, d, value, is_string) != 0) ||
        (expect_punct(p, ';', "after the attribute value") != 0)) {
        goto out;
    }
    if ((attrs != NULL) && (set_attr(p, attrs, n_attrs, &name, &value, is_string, kw->line) != 0)) {
        goto out;
    }
    rc = 0;
out:
    free(name);
    free(value);
    return rc;
}

static int parse_val(parser_t *p, const token_t *kw)
{
    if (peek(p)->kind == T_IDENT) {
        return skip_to_semicolon(p, kw); /* values of an environment variable */
    }
    dbc_signal_t *s;
    if (ref_signal(p, "VAL_", &s) != 0) {
        return -1;
    }
    while (!tok_punct(peek(p), ';')) {
        int64_t v;
        char *text;
        if (expect_i64(p, "value", &v) != 0) {
            return -1;
        }
        if (expect_string(p, "value description", &text) != 0) {
            return -1;
        }
        dbc_value_desc_t *d = push_elem(p, (void **)&s->values, &s->n_values, sizeof *d);
        if (d == NULL) {
            free(text);
            return -1;
        }
        d->value = v;
        d->text = text;
    }
    (void)take(p);
    return 0;
}

/* Keywords whose statements this reader skips up to their ';'. */
static const char *const skipped_keywords[] = {
    "VAL_TABLE_", "SIG_VALTYPE_", "BO_TX_BU_", "EV_", "ENVVAR_DATA_", "SGTYPE_", "SGTYPE_VAL_",
    "SIG_GROUP_", "SIG_TYPE_REF_", "SIGTYPE_VALTYPE_", "BA_DEF_SGTYPE_", "BA_SGTYPE_",
    "BA_DEF_REL_", "BA_REL_", "BA_DEF_DEF_REL_", "BU_SG_REL_", "BU_EV_REL_", "BU_BO_REL_",
    "SG_MUL_VAL_", "CAT_DEF_", "CAT_", "FILTER", "EV_DATA_", "NS_DESC_",
};

typedef int (*section_fn)(parser_t *p, const token_t *kw);

static const struct {
    const char *keyword;
    section_fn fn;
} sections[] = {
    {"VERSION", parse_version}, {"NS_", parse_ns}, {"BS_", parse_bs}, {"BU_", parse_bu},
    {"BO_", parse_bo}, {"SG_", parse_sg}, {"CM_", parse_cm}, {"BA_DEF_", parse_ba_def},
    {"BA_DEF_DEF_", parse_ba_def_def}, {"BA_", parse_ba}, {"VAL_", parse_val},
};

static int check_multiplexing(parser_t *p)
{
    for (size_t i = 0U; i < p->dbc->n_messages; i++) {
        const dbc_message_t *m = &p->dbc->messages[i];
        const dbc_signal_t *muxer = NULL;
        const dbc_signal_t *muxed = NULL;
        for (size_t k = 0U; k < m->n_signals; k++) {
            const dbc_signal_t *s = &m->signals[k];
            if (s->mux_kind == DBC_MUX_MULTIPLEXOR) {
                if (muxer != NULL) {
                    return fail(p, s->line, "message %s has a second multiplexer (%s; first %s)", m->name,
                                s->name, muxer->name);
                }
                muxer = s;
            } else if ((s->mux_kind == DBC_MUX_MULTIPLEXED) && (muxed == NULL)) {
                muxed = s;
            } else {
                /* plain signal */
            }
        }
        if ((muxed != NULL) && (muxer == NULL)) {
            return fail(p, muxed->line, "signal %s of %s is multiplexed (m%lu) but the message has no multiplexer (M)",
                        muxed->name, m->name, (unsigned long)muxed->mux_value);
        }
    }
    return 0;
}

static int parse_all(parser_t *p)
{
    while (peek(p)->kind != T_EOF) {
        const token_t *kw = take(p);
        if (kw->kind != T_IDENT) {
            return fail(p, kw->line, "expected a keyword (BO_, SG_, CM_ ...), found %s", describe(p, kw));
        }
        section_fn fn = NULL;
        for (size_t i = 0U; i < (sizeof sections / sizeof sections[0]); i++) {
            if (tok_is(kw, T_IDENT, sections[i].keyword)) {
                fn = sections[i].fn;
            }
        }
        if ((fn != parse_sg) && (fn != parse_bo)) {
            p->cur_msg = SIZE_MAX; /* SG_ lines must follow their BO_ directly */
        }
        if (fn != NULL) {
            if (fn(p, kw) != 0) {
                return -1;
            }
            continue;
        }
        bool skipped = false;
        for (size_t i = 0U; i < (sizeof skipped_keywords / sizeof skipped_keywords[0]); i++) {
            if (tok_is(kw, T_IDENT, skipped_keywords[i])) {
                skipped = true;
            }
        }
        if (!skipped) {
            return fail(p, kw->line, "unknown keyword %s", describe(p, kw));
        }
        if (skip_to_semicolon(p, kw) != 0) {
            return -1;
        }
    }
    return check_multiplexing(p);
}

int dbc_parse_text(const char *text, size_t len, dbc_t **out, dbc_error_t *err)
{
    parser_t p;
    memset(&p, 0, sizeof p);
    p.err = err;
    p.cur_msg = SIZE_MAX;
    if (err != NULL) {
        err->line = 0;
        err->message[0] = '\0';
    }
    if (out == NULL) {
        return fail(&p, 0, "no output given");
    }
    *out = NULL;
    if ((text == NULL) && (len > 0U)) {
        return fail(&p, 0, "no input given");
    }
    p.dbc = calloc(1U, sizeof *p.dbc);
    if (p.dbc == NULL) {
        return fail_oom(&p);
    }
    int rc = lex(&p, (text == NULL) ? "" : text, len);
    if (rc == 0) {
        rc = parse_all(&p);
    }
    free(p.toks);
    if (rc != 0) {
        dbc_free(p.dbc);
        return -1;
    }
    *out = p.dbc;
    return 0;
}

int dbc_parse_file(const char *path, dbc_t **out, dbc_error_t *err)
{
    if (err != NULL) {
        err->line = 0;
        err->message[0] = '\0';
    }
    if (out != NULL) {
        *out = NULL;
    }
    if ((path == NULL) || (out == NULL)) {
        if (err != NULL) {
            (void)snprintf(err->message, sizeof err->message, "no file or output given");
        }
        return -1;
    }
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        if (err != NULL) {
            (void)snprintf(err->message, sizeof err->message, "cannot open %s: %s", path, strerror(errno));
        }
        return -1;
    }
    char *buf = NULL;
    size_t len = 0U;
    size_t cap = 0U;
    int rc = 0;
    for (;;) {
        if (len == cap) {
            if (cap >= (size_t)DBC_MAX_FILE_BYTES) {
                if (err != NULL) {
                    (void)snprintf(err->message, sizeof err->message, "%s is larger than %ld bytes", path,
                                   DBC_MAX_FILE_BYTES);
                }
                rc = -1;
                break;
            }
            cap = (cap == 0U) ? 65536U : (cap * 2U);
            char *q = realloc(buf, cap);
            if (q == NULL) {
                if (err != NULL) {
                    (void)snprintf(err->message, sizeof err->message, "out of memory");
                }
                rc = -1;
                break;
            }
            buf = q;
        }
        const size_t got = fread(buf + len, 1U, cap - len, f);
        len += got;
        if (got == 0U) {
            if (ferror(f) != 0) {
                if (err != NULL) {
                    (void)snprintf(err->message, sizeof err->message, "cannot read %s", path);
                }
                rc = -1;
            }
            break;
        }
    }
    (void)fclose(f);
    if (rc == 0) {
        rc = dbc_parse_text(buf, len, out, err);
    }
    free(buf);
    return rc;
}

/* ------------------------------------------------------------ attribute values */

static int attr_int(const dbc_t *dbc, dbc_object_t obj, const dbc_attr_t *attrs, size_t n, const char *name,
                    int64_t *out)
{
    const dbc_attr_def_t *d = dbc_attr_def(dbc, obj, name);
    if ((d == NULL) || (out == NULL) ||
        ((d->type != DBC_ATTR_INT) && (d->type != DBC_ATTR_HEX) && (d->type != DBC_ATTR_ENUM))) {
        return -1;
    }
    const char *value = d->default_value;
    bool is_string = d->default_is_string;
    for (size_t i = 0U; i < n; i++) {
        if (strcmp(attrs[i].name, name) == 0) {
            value = attrs[i].value;
            is_string = attrs[i].is_string;
        }
    }
    if (value == NULL) {
        return -1;
    }
    if (is_string) {
        for (size_t i = 0U; i < d->n_enum_values; i++) {
            if (strcmp(d->enum_values[i], value) == 0) {
                *out = (int64_t)i;
                return 0;
            }
        }
        return -1;
    }
    char *end = NULL;
    errno = 0;
    const long long v = strtoll(value, &end, 10);
    if ((errno != 0) || (end == value) || (*end != '\0')) {
        return -1;
    }
    *out = (int64_t)v;
    return 0;
}

int dbc_message_attr_int(const dbc_t *dbc, const dbc_message_t *msg, const char *name, int64_t *out)
{
    return ((dbc == NULL) || (msg == NULL)) ? -1
                                            : attr_int(dbc, DBC_OBJ_MESSAGE, msg->attrs, msg->n_attrs, name, out);
}

int dbc_signal_attr_int(const dbc_t *dbc, const dbc_signal_t *sig, const char *name, int64_t *out)
{
    return ((dbc == NULL) || (sig == NULL)) ? -1
                                            : attr_int(dbc, DBC_OBJ_SIGNAL, sig->attrs, sig->n_attrs, name, out);
}

int dbc_node_attr_int(const dbc_t *dbc, const dbc_node_t *node, const char *name, int64_t *out)
{
    return ((dbc == NULL) || (node == NULL)) ? -1
                                             : attr_int(dbc, DBC_OBJ_NODE, node->attrs, node->n_attrs, name, out);
}

/* ------------------------------------------------------------ exact decimals */

int dbc_decimal_to_rational(const char *text, int64_t *num, int64_t *den)
{
    if ((text == NULL) || (num == NULL) || (den == NULL)) {
        return -1;
    }
    const char *c = text;
    bool negative = false;
    if ((*c == '-') || (*c == '+')) {
        negative = *c == '-';
        c++;
    }
    int64_t mant = 0;
    int digits = 0;
    int frac = 0;
    bool any = false;
    bool in_frac = false;
    for (; (*c != '\0') && (*c != 'e') && (*c != 'E'); c++) {
        if (*c == '.') {
            if (in_frac) {
                return -1;
            }
            in_frac = true;
            continue;
        }
        if (isdigit((unsigned char)*c) == 0) {
            return -1;
        }
        any = true;
        if ((mant != 0) || (*c != '0')) {
            digits++;
        }
        if (digits > 18) {
            return -1;
        }
        mant = (mant * 10) + (int64_t)(*c - '0');
        if (in_frac) {
            frac++;
        }
    }
    if (!any) {
        return -1;
    }
    long exp10 = 0;
    if ((*c == 'e') || (*c == 'E')) {
        char *end = NULL;
        errno = 0;
        exp10 = strtol(c + 1, &end, 10);
        if ((errno != 0) || (end == (c + 1)) || (*end != '\0') || (exp10 > 18) || (exp10 < -18)) {
            return -1;
        }
    }
    long scale = (long)frac - exp10; /* value = mant / 10^scale */
    int64_t d = 1;
    while (scale < 0) {
        if (mant > (INT64_MAX / 10)) {
            return -1;
        }
        mant *= 10;
        scale++;
    }
    while (scale > 0) {
        if (d > (INT64_MAX / 10)) {
            return -1;
        }
        d *= 10;
        scale--;
    }
    while (((mant % 10) == 0) && (d > 1)) {
        mant /= 10;
        d /= 10;
    }
    *num = negative ? -mant : mant;
    *den = d;
    return 0;
}
