/*
 * cli_help.h - a host tool's manual is its --help: one text, whose first
 * paragraph (up to the first empty line) is the synopsis that a usage error
 * prints. tests/host/doc_options.py holds the docs to it.
 */
#ifndef CLI_HELP_H
#define CLI_HELP_H

#include <stdbool.h>
#include <stdio.h>
#include <string.h>

/* Whether an argument is --help or -h. */
static inline bool cli_help_asked(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        if ((strcmp(argv[i], "--help") == 0) || (strcmp(argv[i], "-h") == 0)) {
            return true;
        }
    }
    return false;
}

/* The whole manual, on standard output. */
static inline void cli_help(const char *manual)
{
    fputs(manual, stdout);
}

/* The synopsis to f, and where the manual is. */
static inline void cli_usage(FILE *f, const char *manual, const char *prog)
{
    const char *end = strstr(manual, "\n\n");
    const int len = (end != NULL) ? (int)(end - manual + 1) : (int)strlen(manual);
    fprintf(f, "%.*s%s --help: the manual\n", len, manual, prog);
}

#endif /* CLI_HELP_H */
