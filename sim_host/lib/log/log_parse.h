/*
 * log_parse.h - what the format parsers of the CAN log reader share (not a
 * public header: tools include lib/log/log.h). The reader's core
 * (log_core.c: reading lines, numbers, ids, lengths, time, detection) and
 * one file per format: log_candump.c (candump -L, and the writer),
 * log_printed.c (candump's printed output), log_asc.c (Vector ASC).
 *
 * Each log_parse_*_line() parses one line (NUL-terminated, no line end)
 * into *f: 0 for a frame, 1 for a line without one (comment, header,
 * DROPCOUNT), or -reason after log_fail() recorded the message.
 */
#ifndef LOG_PARSE_H
#define LOG_PARSE_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "lib/log/log.h"

/* ------------------------------------------------------------------ characters */

/* Value of a hex digit, or -1. */
static const int8_t log_hexval[256] = {
    ['0'] = 1, ['1'] = 2, ['2'] = 3, ['3'] = 4, ['4'] = 5, ['5'] = 6, ['6'] = 7, ['7'] = 8,
    ['8'] = 9, ['9'] = 10, ['A'] = 11, ['B'] = 12, ['C'] = 13, ['D'] = 14, ['E'] = 15,
    ['F'] = 16, ['a'] = 11, ['b'] = 12, ['c'] = 13, ['d'] = 14, ['e'] = 15, ['f'] = 16,
};
/* The table holds value + 1 so that every other entry can stay 0. */
static inline int hex_digit(char c)
{
    return (int)log_hexval[(unsigned char)c] - 1;
}

static inline bool is_digit(char c)
{
    return (c >= '0') && (c <= '9');
}

static inline bool is_blank(char c)
{
    return (c == ' ') || (c == '\t');
}

/* End of a token: blank or the end of the line (lines are NUL-terminated). */
static inline bool is_end(char c)
{
    return (c == '\0') || is_blank(c);
}

static inline const char *skip_blanks(const char *p)
{
    while (is_blank(*p)) {
        p++;
    }
    return p;
}

static inline const char *token_end(const char *p)
{
    while (!is_end(*p)) {
        p++;
    }
    return p;
}

static inline bool token_is(const char *p, const char *word)
{
    const size_t n = strlen(word);
    return (strncmp(p, word, n) == 0) && is_end(p[n]);
}

static inline bool starts_with(const char *p, const char *prefix)
{
    return strncmp(p, prefix, strlen(prefix)) == 0;
}

static inline bool starts_with_nocase(const char *p, const char *prefix)
{
    for (; *prefix != '\0'; p++, prefix++) {
        char a = *p;
        char b = *prefix;
        if ((a >= 'A') && (a <= 'Z')) {
            a = (char)(a - 'A' + 'a');
        }
        if ((b >= 'A') && (b <= 'Z')) {
            b = (char)(b - 'A' + 'a');
        }
        if (a != b) {
            return false;
        }
    }
    return true;
}


/* ------------------------------------------------------------------ shared by the formats */

/* Records a bad line: message, counters. Returns -reason. */
__attribute__((format(printf, 3, 4))) int log_fail(canlog_reader_t *r, canlog_reason_t reason,
                                                   const char *fmt, ...);
/* A printable form of character C for messages. */
const char *log_show_char(char c, char out[16]);
/* NUL or a control character other than tab, CR, VT, FF in LEN bytes. */
bool log_looks_binary(const char *s, size_t len);
/* SECONDS.FRACTION at *pp (6 or 9 fraction digits) into microseconds. */
int log_parse_seconds(const char **pp, uint64_t *us, int *sec_digits, int *frac_digits);
/* YYYY-MM-DD HH:MM:SS.FRACTION at *pp (candump -t A) into microseconds since the epoch. */
int log_parse_date(const char **pp, uint64_t *us, int *frac_digits);
bool log_fd_len_valid(unsigned len);
int log_check_len(canlog_reader_t *r, bool fd, unsigned len);
int log_make_id(canlog_reader_t *r, int digits, uint32_t v, uint32_t *id);
int log_accept_time(canlog_reader_t *r, canlog_time_base_t tb, uint64_t t, uint64_t *out);
/* The end of a timestamp in parentheses at *pp, its fraction of FRAC_DIGITS
 * digits read: the ')' and 6 or 9 digits, then *pp past the ')' and the
 * blanks after it. 0, or -reason. */
int log_paren_close(canlog_reader_t *r, const char **pp, int frac_digits);
/* "SECONDS.FRACTION)" at *pp (the '(' read): *us, *sec_digits, then as
 * log_paren_close(). 0, or -reason. */
int log_paren_seconds(canlog_reader_t *r, const char **pp, uint64_t *us, int *sec_digits);
int log_take_iface(canlog_reader_t *r, const char *p, const char *e, canlog_frame_t *f);
bool log_is_comment(const char *p);
bool log_note_dropcount(canlog_reader_t *r, const char *p);

int log_parse_log_line(canlog_reader_t *r, const char *line, canlog_frame_t *f);
int log_parse_printed_line(canlog_reader_t *r, const char *line, canlog_frame_t *f);
int log_parse_asc_line(canlog_reader_t *r, const char *line, canlog_frame_t *f);

#endif /* LOG_PARSE_H */
