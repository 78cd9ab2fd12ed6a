/* sdftrace common — the command line of every program (sdftrace render
 * and bake, mesh2sdf, bench/study): one table of options, read by
 * getopt_long and printed as --help, so that a flag, its value's name, its
 * default and its description are written once. Values are parsed
 * strictly (parse.h) and checked against their range; every error is one
 * line. Internal header (C and C++).
 *
 * A program builds its table over the struct its options fill (for
 * --help, over a struct holding the defaults, which the help then shows):
 *
 *     const cmdline_option rows[] = {
 *         {"width", 0, "W", "image width, pixels", CMDLINE_INT, &o->width, .lo = 1, .hi = 16384},
 *         {"quiet", 0, NULL, "no progress line", CMDLINE_SET, &o->quiet, .value = 1, .def = ""},
 *         {0},
 *     };
 */
#ifndef SDFTRACE_COMMON_CMDLINE_H
#define SDFTRACE_COMMON_CMDLINE_H

#include <stddef.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum cmdline_kind {
    CMDLINE_SET,     /* a flag: stores `value` in the int at target */
    CMDLINE_TEXT,    /* the value as given, in the const char * at target; with value n > 1, the n words
                      * that follow the flag, in const char *target[n] */
    CMDLINE_INT,     /* an int in [lo, hi] */
    CMDLINE_FLOAT,   /* a finite float in [lo, hi] (open ends: open) */
    CMDLINE_DOUBLE,  /* a finite double in [lo, hi] (open ends: open) */
    CMDLINE_FLOATS,  /* `value` comma-separated finite numbers, in float target[value] */
    CMDLINE_UINT64,  /* a uint64_t in [lo, hi] */
    CMDLINE_DOUBLES, /* `value` comma-separated finite numbers, each in [lo, hi], in double target[value] */
    CMDLINE_CHOICE,  /* one of the space-separated names of `choices`: its index, in the int at target */
    CMDLINE_CALL,    /* handle(target, the value or NULL for a flag, msg, msg_len) */
    CMDLINE_HELP,    /* -h, --help: the parser returns CMDLINE_HELP_ASKED */
    CMDLINE_NOTE,    /* listed by the help, left to the program (mesh2sdf's --version) */
} cmdline_kind;

enum { CMDLINE_OPEN_LO = 1, CMDLINE_OPEN_HI = 2 }; /* parse.h's PARSE_OPEN_LO, _HI */

/* A CMDLINE_CALL option: 0, or -1 with one line in msg. */
typedef int (*cmdline_handler)(void *target, const char *value, char *msg, size_t msg_len);

typedef struct cmdline_option {
    const char *name; /* long name, without the dashes; NULL: the short flag alone */
    char letter;      /* short flag, or 0 */
    const char *arg;  /* the value's name in the help ("N", "FILE"); NULL for a flag */
    const char *help; /* what it does; '\n' goes on, indented; NULL: not listed */
    cmdline_kind kind;
    void *target;
    double lo, hi;          /* CMDLINE_INT, _FLOAT, _DOUBLE: the range; -inf, +inf for none */
    int open;               /* CMDLINE_OPEN_LO | CMDLINE_OPEN_HI: an end excluded */
    int value;              /* CMDLINE_SET: the value stored; CMDLINE_FLOATS, _TEXT: how many */
    const char *def;        /* the default, as the help shows it; NULL: the target's value; "": none */
    cmdline_handler handle; /* CMDLINE_CALL */
    int *seen;              /* set to 1 when the option is given, or NULL */
    const char *choices;    /* CMDLINE_CHOICE: the names of values 0, 1, ... separated by spaces */
} cmdline_option;

typedef struct cmdline_spec {
    const char *program;        /* "sdftrace render": named by "(try: PROGRAM --help)" */
    const char *usage;          /* printed before the options */
    const char *footer;         /* printed after them, or NULL */
    const cmdline_option *rows; /* ends with a row of neither name nor letter */
    int column;                 /* where the descriptions start */
    const char *default_format; /* how a default is shown; NULL: "(default %s)" */
    int width;                  /* the help's lines wrapped at this column; 0: as the rows write them */
    /* A word that is not an option (mesh2sdf's input mesh): 0, or -1 with
     * msg. NULL: such a word is an error. */
    cmdline_handler operand;
    void *operand_target;
} cmdline_spec;

enum { CMDLINE_OK = 0, CMDLINE_HELP_ASKED = 1, CMDLINE_ERROR = -1 };

/* Reads argv[1..argc-1] in order into the rows' targets. CMDLINE_OK;
 * CMDLINE_HELP_ASKED at -h or --help (nothing printed); CMDLINE_ERROR with
 * one line in msg: an unknown option, a missing or malformed value, a
 * value out of range, an unexpected word. Long options are matched whole
 * (no abbreviations); "--name=value" is accepted. */
int cmdline_parse(const cmdline_spec *spec, int argc, char **argv, char *msg, size_t msg_len);

/* Prints the usage, every listed option with its value's name, description
 * and default, and the footer. */
void cmdline_help(const cmdline_spec *spec, FILE *out);

#ifdef __cplusplus
}
#endif
#endif
