/* truck_cal.c - the truck calibration file (contract in truck_cal.h). */
#include "lib/truck_cal.h"

#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define LINE_MAX_CHARS 256U
#define FILE_MAX_BYTES (256U * 1024U)
#define SECTION_OWN (-1)

typedef struct {
    const char *name;
    uint32_t pow10;            /* the field holds value * 10^pow10 */
} unit_t;

typedef struct {
    const char *key;
    size_t offset;             /* in pfe_vehicle_calib_t, a uint32_t */
    uint32_t min, max;         /* in the field's unit */
    unit_t units[2];           /* accepted units; "" is a plain number */
    const char *range;         /* for messages */
} field_t;

#define F(k, member, lo, hi, u0, p0, u1, p1, text) \
    {k, offsetof(pfe_vehicle_calib_t, member), lo, hi, {{u0, p0}, {u1, p1}}, text}

/* Ranges as pfe_calib_check_vehicle() has them (firmware/pfe_calib.c). */
static const field_t k_fields[] = {
    F("mass", mass_kg, PFE_MASS_MIN_KG, PFE_MASS_MAX_KG, "kg", 0U, "t", 3U, "1000 .. 100000 kg"),
    F("rot_mass", rot_mass_kg, 0U, PFE_MASS_MAX_KG, "kg", 0U, "t", 3U, "0 .. 100000 kg, at most mass"),
    F("drag_area", drag_area_mm2, 0U, PFE_DRAG_AREA_MAX_MM2, "m2", 6U, "mm2", 0U, "0 .. 20 m2"),
    F("roll_coef", roll_coef_ppm, 0U, 100000U, "", 6U, "ppm", 0U, "0 .. 0.1 (no unit)"),
    F("power_max", power_max_w, 1U, PFE_POWER_MAX_W, "W", 0U, "kW", 3U, "1 W .. 2000 kW"),
    F("traction_max", traction_max_n, 1U, PFE_FORCE_MAX_N, "N", 0U, "kN", 3U, "1 N .. 1000 kN"),
    F("brake_max", brake_max_n, 0U, PFE_FORCE_MAX_N, "N", 0U, "kN", 3U, "0 .. 1000 kN"),
    F("aux_power", power_aux_w, 0U, 100000U, "W", 0U, "kW", 3U, "0 .. 100 kW"),
    F("eta", eta_ppm, 50000U, 1000000U, "", 6U, "%", 4U, "0.05 .. 1 (no unit) or 5 .. 100 %"),
};
#define N_FIELDS (sizeof k_fields / sizeof k_fields[0])

static const char *const k_source_keys[PFE_IN_COUNT] = {
    "speed_source", "grade_source", "altitude_source", "mass_source", "engine_fuel_source"};

/* Keys seen in the section being read, for duplicates. */
enum { KEY_FLAT = (int)N_FIELDS + (int)PFE_IN_COUNT, KEY_J1939, KEY_COUNT };

typedef struct {
    const char *name;
    uint32_t line;
    char *err;
    uint32_t cap;
} ctx_t;

static int fail(const ctx_t *c, const char *fmt, ...)
{
    if ((c->err == NULL) || (c->cap == 0U)) {
        return -1;
    }
    int n = snprintf(c->err, c->cap, "%s:%lu: ", c->name, (unsigned long)c->line);
    if ((n >= 0) && ((uint32_t)n < c->cap)) {
        va_list ap;
        va_start(ap, fmt);
        (void)vsnprintf(c->err + n, c->cap - (uint32_t)n, fmt, ap);
        va_end(ap);
    }
    return -1;
}

void truck_cal_default(truck_cal_t *cal)
{
    memset(cal, 0, sizeof *cal);
    cal->own = pfe_default_vehicle;
    for (uint32_t k = 0U; k < PFE_MAX_VEHICLES; k++) {
        cal->at[k] = pfe_default_vehicle;
    }
    for (uint32_t k = 0U; k < (uint32_t)PFE_IN_COUNT; k++) {
        cal->source[k] = PFE_INPUT_NO_SOURCE;
    }
    cal->j1939_fuel = PFE_ECU_J1939_FUEL_AUTO;
}

/*
 * A decimal number without sign, at most 15 digits, times 10^pow10, exact:
 * 0 and *out, 1 when it is finer than the unit, -1 when it is no number,
 * 2 when it exceeds UINT32_MAX.
 */
static int decimal_scaled(const char *s, uint32_t pow10, uint64_t *out)
{
    uint64_t m = 0U;
    unsigned digits = 0U, frac = 0U;
    bool dot = false;
    for (const char *p = s; *p != '\0'; p++) {
        if ((*p == '.') && !dot) {
            dot = true;
        } else if ((*p >= '0') && (*p <= '9')) {
            if (++digits > 15U) {
                return 2;
            }
            m = (m * 10U) + (uint64_t)(*p - '0');
            frac += dot ? 1U : 0U;
        } else {
            return -1;
        }
    }
    if ((digits == 0U) || (dot && (frac == 0U))) {
        return -1;
    }
    while (frac > pow10) {
        if ((m % 10U) != 0U) {
            return 1;
        }
        m /= 10U;
        frac--;
    }
    for (uint32_t k = frac; k < pow10; k++) {
        m *= 10U;
        if (m > UINT32_MAX) {
            return 2;
        }
    }
    if (m > UINT32_MAX) {
        return 2;
    }
    *out = m;
    return 0;
}

static const char *units_text(const field_t *f, char *buf, size_t cap)
{
    snprintf(buf, cap, "%s%s%s", (f->units[0].name[0] != '\0') ? f->units[0].name : "no unit",
             ", ", (f->units[1].name[0] != '\0') ? f->units[1].name : "no unit");
    return buf;
}

static int set_field(const ctx_t *c, const field_t *f, const char *value, const char *unit,
                     pfe_vehicle_calib_t *v)
{
    char ut[48];
    const unit_t *u = NULL;
    for (unsigned k = 0U; k < 2U; k++) {
        if (strcmp(f->units[k].name, (unit != NULL) ? unit : "") == 0) {
            u = &f->units[k];
        }
    }
    if (u == NULL) {
        if (unit == NULL) {
            return fail(c, "%s %s: a unit is needed (%s)", f->key, value, units_text(f, ut, sizeof ut));
        }
        return fail(c, "%s: unknown unit '%s' (%s)", f->key, unit, units_text(f, ut, sizeof ut));
    }
    uint64_t x = 0U;
    const int rc = decimal_scaled(value, u->pow10, &x);
    if (rc < 0) {
        return fail(c, "%s: '%s' is not a number (decimal, no sign)", f->key, value);
    }
    if (rc == 1) {
        return fail(c, "%s: %s%s%s is finer than the calibration holds (range %s)", f->key, value,
                    (unit != NULL) ? " " : "", (unit != NULL) ? unit : "", f->range);
    }
    if ((rc == 2) || (x < f->min) || (x > f->max)) {
        return fail(c, "%s: %s%s%s is out of range %s", f->key, value, (unit != NULL) ? " " : "",
                    (unit != NULL) ? unit : "", f->range);
    }
    uint32_t *dst = (uint32_t *)(void *)((unsigned char *)v + f->offset);
    *dst = (uint32_t)x;
    return 0;
}

/* pfe_calib_check_vehicle() on a finished section. */
static int check_section(const ctx_t *c, const pfe_vehicle_calib_t *v, int section,
                         uint32_t section_line)
{
    if (pfe_calib_check_vehicle(v) == PFE_OK) {
        return 0;
    }
    ctx_t at = *c;
    at.line = section_line;
    char who[32];
    if (section == SECTION_OWN) {
        snprintf(who, sizeof who, "the own truck");
    } else {
        snprintf(who, sizeof who, "[position %d]", section);
    }
    if (v->rot_mass_kg > v->mass_kg) {
        return fail(&at, "%s: rot_mass %lu kg exceeds mass %lu kg (rot_mass must be at most mass)",
                    who, (unsigned long)v->rot_mass_kg, (unsigned long)v->mass_kg);
    }
    return fail(&at, "%s: refused by pfe_calib_check_vehicle()", who);
}

/* Splits a line into at most 3 words, comments cut; returns the count, or
 * 4 for more words than 3. */
static unsigned split_words(char *line, char *w[3])
{
    char *hash = strchr(line, '#');
    if (hash != NULL) {
        *hash = '\0';
    }
    unsigned n = 0U;
    char *p = line;
    for (;;) {
        while ((*p == ' ') || (*p == '\t') || (*p == '\r')) {
            *p++ = '\0';
        }
        if (*p == '\0') {
            return n;
        }
        if (n == 3U) {
            return 4U;
        }
        w[n++] = p;
        while ((*p != ' ') && (*p != '\t') && (*p != '\r') && (*p != '\0')) {
            p++;
        }
    }
}

/* "[position N]" (the text between the brackets in inner). */
static int parse_section(const ctx_t *c, char *line, int *section)
{
    char *hash = strchr(line, '#');
    if (hash != NULL) {
        *hash = '\0';
    }
    char *open = strchr(line, '[');
    char *close = strchr(line, ']');
    if ((open == NULL) || (close == NULL) || (close < open)) {
        return fail(c, "section header must be '[position N]'");
    }
    for (const char *p = close + 1; *p != '\0'; p++) {
        if ((*p != ' ') && (*p != '\t') && (*p != '\r')) {
            return fail(c, "text after the section header '%s'", close + 1);
        }
    }
    *close = '\0';
    char word[16];
    char num[16];
    char extra[2];
    if ((sscanf(open + 1, " %15s %15s %1s", word, num, extra) != 2) ||
        (strcmp(word, "position") != 0)) {
        return fail(c, "section header must be '[position N]', N = 0 .. %u",
                    (unsigned)(PFE_MAX_VEHICLES - 1U));
    }
    uint64_t n = 0U;
    if ((decimal_scaled(num, 0U, &n) != 0) || (strchr(num, '.') != NULL) ||
        (n >= PFE_MAX_VEHICLES)) {
        return fail(c, "[position %s]: N must be 0 .. %u", num, (unsigned)(PFE_MAX_VEHICLES - 1U));
    }
    *section = (int)n;
    return 0;
}

static int parse_source(const ctx_t *c, const char *key, const char *value, bool *fixed,
                        uint8_t *sa)
{
    if (strcmp(value, "auto") == 0) {
        *fixed = false;
        *sa = PFE_INPUT_NO_SOURCE;
        return 0;
    }
    char *end = NULL;
    errno = 0;
    const unsigned long v = strtoul(value, &end, 0);
    if ((errno != 0) || (end == value) || (*end != '\0') || (value[0] == '-') || (value[0] == '+') ||
        (v > 253U)) {
        return fail(c, "%s: '%s' is not a source address 0 .. 253 (or 0x00 .. 0xFD) nor auto", key,
                    value);
    }
    *fixed = true;
    *sa = (uint8_t)v;
    return 0;
}

int truck_cal_parse(const char *text, const char *name, truck_cal_t *cal, char *err,
                    uint32_t cap)
{
    truck_cal_default(cal);
    ctx_t c = {name, 0U, err, cap};
    int section = SECTION_OWN;
    uint32_t section_line = 1U;
    bool seen[KEY_COUNT] = {false};
    bool section_seen[PFE_MAX_VEHICLES] = {false};
    const char *p = text;
    while (*p != '\0') {
        c.line++;
        const char *nl = strchr(p, '\n');
        const size_t len = (nl != NULL) ? (size_t)(nl - p) : strlen(p);
        if (len >= LINE_MAX_CHARS) {
            return fail(&c, "line longer than %u characters", LINE_MAX_CHARS - 1U);
        }
        char line[LINE_MAX_CHARS];
        memcpy(line, p, len);
        line[len] = '\0';
        p += len + ((nl != NULL) ? 1U : 0U);
        if (memchr(line, '\0', len) != NULL) {
            return fail(&c, "a NUL byte in the line");
        }
        const char *first = line + strspn(line, " \t\r");
        if (*first == '[') {
            pfe_vehicle_calib_t *done = (section == SECTION_OWN) ? &cal->own : &cal->at[section];
            if (check_section(&c, done, section, section_line) != 0) {
                return -1;
            }
            int next = 0;
            if (parse_section(&c, line, &next) != 0) {
                return -1;
            }
            if (section_seen[next]) {
                return fail(&c, "[position %d] given twice", next);
            }
            section_seen[next] = true;
            cal->at_set[next] = true;
            section = next;
            section_line = c.line;
            memset(seen, 0, sizeof seen);
            continue;
        }
        char *w[3] = {NULL, NULL, NULL};
        const unsigned n = split_words(line, w);
        if (n == 0U) {
            continue;
        }
        if (n == 1U) {
            return fail(&c, "%s: a value is needed", w[0]);
        }
        if (n > 3U) {
            return fail(&c, "%s: expected 'key value [unit]', got more words", w[0]);
        }
        int key = -1;
        for (unsigned k = 0U; k < N_FIELDS; k++) {
            if (strcmp(w[0], k_fields[k].key) == 0) {
                key = (int)k;
            }
        }
        for (unsigned k = 0U; k < (unsigned)PFE_IN_COUNT; k++) {
            if (strcmp(w[0], k_source_keys[k]) == 0) {
                key = (int)N_FIELDS + (int)k;
            }
        }
        key = (strcmp(w[0], "flat_grade") == 0) ? KEY_FLAT : key;
        key = (strcmp(w[0], "j1939_fuel") == 0) ? KEY_J1939 : key;
        if (key < 0) {
            return fail(&c, "unknown key '%s' (vehicle: mass rot_mass drag_area roll_coef "
                            "power_max traction_max brake_max aux_power eta; module: *_source "
                            "flat_grade j1939_fuel)", w[0]);
        }
        if (seen[key]) {
            return fail(&c, "%s given twice in %s", w[0],
                        (section == SECTION_OWN) ? "the own truck's keys" : "this section");
        }
        seen[key] = true;
        if (key < (int)N_FIELDS) {
            pfe_vehicle_calib_t *v = (section == SECTION_OWN) ? &cal->own : &cal->at[section];
            if (set_field(&c, &k_fields[key], w[1], w[2], v) != 0) {
                return -1;
            }
            cal->own_set = cal->own_set || (section == SECTION_OWN);
            continue;
        }
        if (section != SECTION_OWN) {
            return fail(&c, "%s: a module option, only before the first [position N] section", w[0]);
        }
        if (w[2] != NULL) {
            return fail(&c, "%s %s: takes no unit (got '%s')", w[0], w[1], w[2]);
        }
        if (key < KEY_FLAT) {
            const unsigned in = (unsigned)key - (unsigned)N_FIELDS;
            if (parse_source(&c, w[0], w[1], &cal->source_fixed[in], &cal->source[in]) != 0) {
                return -1;
            }
        } else if (key == KEY_FLAT) {
            if ((strcmp(w[1], "allow") != 0) && (strcmp(w[1], "forbid") != 0)) {
                return fail(&c, "flat_grade: '%s' is neither allow nor forbid", w[1]);
            }
            cal->flat_grade_forbidden = strcmp(w[1], "forbid") == 0;
        } else {
            if (strcmp(w[1], "auto") == 0) {
                cal->j1939_fuel = PFE_ECU_J1939_FUEL_AUTO;
            } else if (strcmp(w[1], "always") == 0) {
                cal->j1939_fuel = PFE_ECU_J1939_FUEL_ALWAYS;
            } else if (strcmp(w[1], "never") == 0) {
                cal->j1939_fuel = PFE_ECU_J1939_FUEL_NEVER;
            } else {
                return fail(&c, "j1939_fuel: '%s' is none of auto, always, never", w[1]);
            }
        }
    }
    c.line++;
    const pfe_vehicle_calib_t *last = (section == SECTION_OWN) ? &cal->own : &cal->at[section];
    return check_section(&c, last, section, section_line);
}

int truck_cal_load(const char *path, truck_cal_t *cal, char *err, uint32_t cap)
{
    truck_cal_default(cal);
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        if ((err != NULL) && (cap > 0U)) {
            snprintf(err, cap, "%s: cannot read: %s", path, strerror(errno));
        }
        return -1;
    }
    static char text[FILE_MAX_BYTES + 1U];
    const size_t got = fread(text, 1U, FILE_MAX_BYTES + 1U, f);
    const bool bad = ferror(f) != 0;
    fclose(f);
    if (bad || (got > FILE_MAX_BYTES)) {
        if ((err != NULL) && (cap > 0U)) {
            snprintf(err, cap, "%s: %s", path,
                     bad ? "read error" : "longer than 256 KiB: not a calibration file");
        }
        return -1;
    }
    if (memchr(text, '\0', got) != NULL) {
        if ((err != NULL) && (cap > 0U)) {
            snprintf(err, cap, "%s: a NUL byte: not a text file", path);
        }
        return -1;
    }
    text[got] = '\0';
    return truck_cal_parse(text, path, cal, err, cap);
}

void truck_cal_apply(const truck_cal_t *cal, pfe_ecu_config_t *cfg)
{
    cfg->own_vehicle = &cal->own;
    for (uint32_t k = 0U; k < PFE_MAX_VEHICLES; k++) {
        cfg->vehicle_at[k] = cal->at_set[k] ? &cal->at[k] : NULL;
    }
    for (uint32_t k = 0U; k < (uint32_t)PFE_IN_COUNT; k++) {
        cfg->input_source_fixed[k] = cal->source_fixed[k];
        cfg->input_source[k] = cal->source_fixed[k] ? cal->source[k] : 0U;
    }
    cfg->flat_grade_forbidden = cal->flat_grade_forbidden;
    cfg->j1939_fuel = cal->j1939_fuel;
}

const pfe_vehicle_calib_t *truck_cal_vehicle(const truck_cal_t *cal, uint32_t k,
                                             uint32_t own_position)
{
    if (k == own_position) {
        return &cal->own;
    }
    return ((k < PFE_MAX_VEHICLES) && cal->at_set[k]) ? &cal->at[k] : &pfe_default_vehicle;
}

int truck_cal_take_arg(int *argc, char **argv, truck_cal_t *cal, bool *found, char *err,
                       uint32_t cap)
{
    truck_cal_default(cal);
    *found = false;
    int w = 1;
    for (int i = 1; i < *argc; i++) {
        if (strcmp(argv[i], "--calib") != 0) {
            argv[w++] = argv[i];
            continue;
        }
        if ((i + 1) >= *argc) {
            snprintf(err, cap, "--calib needs a FILE");
            return -1;
        }
        if (*found) {
            snprintf(err, cap, "--calib given twice");
            return -1;
        }
        *found = true;
        if (truck_cal_load(argv[i + 1], cal, err, cap) != 0) {
            return -1;
        }
        i++;
    }
    for (int i = w; i < *argc; i++) {
        argv[i] = NULL;
    }
    *argc = w;
    return 0;
}
