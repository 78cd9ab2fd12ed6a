/* sdftrace common — the option table over getopt_long (see cmdline.h). */
#define _GNU_SOURCE /* getopt_long */
#include "cmdline.h"

#include <getopt.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "parse.h"

enum { LONG_BASE = 256 }; /* getopt_long's value of row i's long name: LONG_BASE + i */

static size_t row_count(const cmdline_spec *spec)
{
    size_t n = 0;
    while (spec->rows[n].name || spec->rows[n].letter)
        n++;
    return n;
}

/* The flag as a user writes it: "--name", or "-x" when it has no long name. */
static void flag_text(const cmdline_option *row, char *buf, size_t len)
{
    if (row->name)
        snprintf(buf, len, "--%s", row->name);
    else
        snprintf(buf, len, "-%c", row->letter);
}

static int fail(char *msg, size_t msg_len, const char *fmt, const char *a, const char *b)
{
    snprintf(msg, msg_len, fmt, a, b);
    return CMDLINE_ERROR;
}

/* A number for an INT, UINT64, FLOAT or DOUBLE row, stored in its target. */
static int store_number(const cmdline_option *row, const char *flag, const char *text, char *msg, size_t msg_len)
{
    char range[96], what[160];
    double v = 0.0;
    long n = 0;
    const int integer = row->kind == CMDLINE_INT || row->kind == CMDLINE_UINT64;
    parse_range_text(row->lo, row->hi, row->open, integer ? "%.0f" : "%g", range, sizeof range);
    snprintf(what, sizeof what, "%%s must be %s%s, got '%%s'", integer ? "an integer" : "a finite number", range);
    if (integer ? parse_integer(text, &n) : parse_number(text, &v))
        return fail(msg, msg_len, what, flag, text);
    if (integer)
        v = (double)n;
    if (!parse_in_range(v, row->lo, row->hi, row->open))
        return fail(msg, msg_len, what, flag, text);
    if (row->kind == CMDLINE_INT)
        *(int *)row->target = (int)n;
    else if (row->kind == CMDLINE_UINT64)
        *(uint64_t *)row->target = (uint64_t)n;
    else if (row->kind == CMDLINE_FLOAT)
        *(float *)row->target = (float)v;
    else
        *(double *)row->target = v;
    return CMDLINE_OK;
}

/* `row->value` comma-separated finite numbers (at most 16) as floats. */
static int store_floats(const cmdline_option *row, const char *flag, const char *text, char *msg, size_t msg_len)
{
    double v[16];
    if (row->value > 16 || parse_numbers(text, row->value, v)) {
        char what[96];
        snprintf(what, sizeof what, "%%s needs %d comma-separated finite numbers, got '%%s'", row->value);
        return fail(msg, msg_len, what, flag, text);
    }
    for (int i = 0; i < row->value; i++)
        ((float *)row->target)[i] = (float)v[i];
    return CMDLINE_OK;
}

/* `row->value` comma-separated finite numbers, each in the row's range, as
 * doubles. */
static int store_doubles(const cmdline_option *row, const char *flag, const char *text, char *msg, size_t msg_len)
{
    double v[16];
    int ok = row->value <= 16 && parse_numbers(text, row->value, v) == 0;
    for (int i = 0; ok && i < row->value; i++)
        ok = parse_in_range(v[i], row->lo, row->hi, row->open);
    if (!ok) {
        char range[96], what[160];
        parse_range_text(row->lo, row->hi, row->open, "%g", range, sizeof range);
        snprintf(what, sizeof what, "%%s needs %d comma-separated finite numbers%s, got '%%s'", row->value, range);
        return fail(msg, msg_len, what, flag, text);
    }
    for (int i = 0; i < row->value; i++)
        ((double *)row->target)[i] = v[i];
    return CMDLINE_OK;
}

/* One of the row's choices, by name: its index in the int at target; else
 * "FLAG must be a, b or c, got 'v'". */
static int store_choice(const cmdline_option *row, const char *flag, const char *text, char *msg, size_t msg_len)
{
    const int i = parse_list_index(row->choices, text);
    if (i >= 0) {
        *(int *)row->target = i;
        return CMDLINE_OK;
    }
    char list[256] = "";
    int count = 0;
    const char *name;
    while (parse_list_item(row->choices, count, &name))
        count++;
    for (int i = 0; i < count; i++) {
        const size_t n = parse_list_item(row->choices, i, &name);
        const size_t at = strlen(list);
        snprintf(list + at, sizeof list - at, "%s%.*s", i == 0 ? "" : i + 1 < count ? ", " : " or ", (int)n, name);
    }
    snprintf(msg, msg_len, "%s must be %s, got '%s'", flag, list, text);
    return CMDLINE_ERROR;
}

/* Applies row, whose flag was given with `value` (NULL for a flag) and,
 * for a TEXT row of several words, the words after it. */
static int apply(const cmdline_option *row, const char *value, char **more, char *msg, size_t msg_len)
{
    char flag[64];
    flag_text(row, flag, sizeof flag);
    if (row->seen)
        *row->seen = 1;
    switch (row->kind) {
    case CMDLINE_SET:
        *(int *)row->target = row->value;
        return CMDLINE_OK;
    case CMDLINE_TEXT:
        ((const char **)row->target)[0] = value;
        for (int i = 1; i < row->value; i++)
            ((const char **)row->target)[i] = more[i - 1];
        return CMDLINE_OK;
    case CMDLINE_INT:
    case CMDLINE_UINT64:
    case CMDLINE_FLOAT:
    case CMDLINE_DOUBLE:
        return store_number(row, flag, value, msg, msg_len);
    case CMDLINE_FLOATS:
        return store_floats(row, flag, value, msg, msg_len);
    case CMDLINE_DOUBLES:
        return store_doubles(row, flag, value, msg, msg_len);
    case CMDLINE_CHOICE:
        return store_choice(row, flag, value, msg, msg_len);
    case CMDLINE_CALL:
        return row->handle(row->target, value, msg, msg_len) ? CMDLINE_ERROR : CMDLINE_OK;
    case CMDLINE_HELP:
        return CMDLINE_HELP_ASKED;
    case CMDLINE_NOTE:
        break;
    }
    return fail(msg, msg_len, "%s%s: not an option here", flag, "");
}

/* getopt_long's tables for the rows: long options and the short ones'
 * string ("-:" first: words in order, ':' for a missing value). */
static void make_tables(const cmdline_spec *spec, size_t n, struct option *longs, char *shorts)
{
    size_t nl = 0, ns = 0;
    shorts[ns++] = '-', shorts[ns++] = ':';
    for (size_t i = 0; i < n; i++) {
        const cmdline_option *row = &spec->rows[i];
        if (row->kind == CMDLINE_NOTE)
            continue;
        const int has_arg = row->arg ? required_argument : no_argument;
        if (row->name)
            longs[nl++] = (struct option){row->name, has_arg, NULL, LONG_BASE + (int)i};
        if (row->letter) {
            shorts[ns++] = row->letter;
            if (row->arg)
                shorts[ns++] = ':';
        }
    }
    longs[nl] = (struct option){0};
    shorts[ns] = '\0';
}

/* The row getopt_long's answer c names, or NULL. */
static const cmdline_option *row_of(const cmdline_spec *spec, size_t n, int c)
{
    if (c >= LONG_BASE && (size_t)(c - LONG_BASE) < n)
        return &spec->rows[c - LONG_BASE];
    for (size_t i = 0; c > 0 && c < LONG_BASE && i < n; i++)
        if (spec->rows[i].letter == c && spec->rows[i].kind != CMDLINE_NOTE)
            return &spec->rows[i];
    return NULL;
}

/* Whether `word` names row's long option whole ("--name" or "--name=..."),
 * not by an abbreviation, which getopt_long would take. */
static int whole_name(const cmdline_option *row, const char *word)
{
    const size_t len = strlen(row->name);
    return word && strncmp(word, "--", 2) == 0 && strncmp(word + 2, row->name, len) == 0 &&
           (word[2 + len] == '\0' || word[2 + len] == '=');
}

static int operand(const cmdline_spec *spec, const char *word, char *msg, size_t msg_len)
{
    if (spec->operand)
        return spec->operand(spec->operand_target, word, msg, msg_len) ? CMDLINE_ERROR : CMDLINE_OK;
    return fail(msg, msg_len, "unexpected argument '%s' (try: %s --help)", word, spec->program);
}

/* One word (and its value) of argv: CMDLINE_OK, _HELP_ASKED or _ERROR;
 * *done at the end of the options. */
static int next_option(const cmdline_spec *spec, size_t n, int argc, char **argv, const struct option *longs,
                       const char *shorts, int *done, char *msg, size_t msg_len)
{
    const char *word = optind > 0 && optind < argc ? argv[optind] : argc > 1 ? argv[1] : NULL;
    int li = -1;
    const int c = getopt_long(argc, argv, shorts, longs, &li);
    if (c == -1) {
        *done = 1;
        return CMDLINE_OK;
    }
    if (c == 1)
        return operand(spec, optarg, msg, msg_len);
    if (c == '?' || c == ':') {
        const cmdline_option *row = row_of(spec, n, optopt);
        char flag[64];
        if (row && c == ':') {
            flag_text(row, flag, sizeof flag);
            if (optopt < LONG_BASE)
                snprintf(flag, sizeof flag, "-%c", optopt);
            return fail(msg, msg_len, "%s needs a value%s", flag, "");
        }
        if (optopt > 0 && optopt < LONG_BASE)
            snprintf(flag, sizeof flag, "-%c", optopt);
        else
            snprintf(flag, sizeof flag, "%s", argv[optind - 1]);
        return fail(msg, msg_len, "unknown option '%s' (try: %s --help)", flag, spec->program);
    }
    const cmdline_option *row = row_of(spec, n, c);
    if (li >= 0 && !whole_name(row, word))
        return fail(msg, msg_len, "unknown option '%s' (try: %s --help)", word, spec->program);
    if (row->arg && row->kind == CMDLINE_TEXT && row->value > 1) {
        if (optind + row->value - 1 > argc) {
            char flag[64];
            flag_text(row, flag, sizeof flag);
            return fail(msg, msg_len, "%s needs %s", flag, row->arg);
        }
        char **more = argv + optind;
        optind += row->value - 1;
        return apply(row, optarg, more, msg, msg_len);
    }
    return apply(row, row->arg ? optarg : NULL, NULL, msg, msg_len);
}

int cmdline_parse(const cmdline_spec *spec, int argc, char **argv, char *msg, size_t msg_len)
{
    const size_t n = row_count(spec);
    struct option *longs = calloc(n + 1, sizeof *longs);
    char *shorts = calloc(2 * n + 3, 1);
    int rc = longs && shorts ? CMDLINE_OK : fail(msg, msg_len, "out of memory%s%s", "", "");
    if (rc == CMDLINE_OK)
        make_tables(spec, n, longs, shorts);
    optind = 0; /* glibc: start afresh */
    opterr = 0; /* our messages, not getopt's */
    for (int done = 0; rc == CMDLINE_OK && !done;)
        rc = next_option(spec, n, argc, argv, longs, shorts, &done, msg, msg_len);
    /* After "--", the rest are operands. */
    for (int i = optind; rc == CMDLINE_OK && i < argc; i++)
        rc = operand(spec, argv[i], msg, msg_len);
    free(longs);
    free(shorts);
    return rc;
}

/* ---- help ---------------------------------------------------------------- */

/* The default as shown: row->def, else the target's value. */
static void default_text(const cmdline_option *row, char *buf, size_t len)
{
    buf[0] = '\0';
    if (row->def)
        snprintf(buf, len, "%s", row->def);
    else if (row->kind == CMDLINE_INT)
        snprintf(buf, len, "%d", *(const int *)row->target);
    else if (row->kind == CMDLINE_FLOAT)
        snprintf(buf, len, "%g", (double)*(const float *)row->target);
    else if (row->kind == CMDLINE_DOUBLE)
        snprintf(buf, len, "%g", *(const double *)row->target);
    else if (row->kind == CMDLINE_UINT64)
        snprintf(buf, len, "%llu", (unsigned long long)*(const uint64_t *)row->target);
    else if (row->kind == CMDLINE_DOUBLES)
        for (int i = 0; i < row->value; i++) {
            const size_t at = strlen(buf);
            snprintf(buf + at, len - at, "%s%g", i ? "," : "", ((const double *)row->target)[i]);
        }
    else if (row->kind == CMDLINE_CHOICE) {
        const char *name;
        const size_t n = parse_list_item(row->choices, *(const int *)row->target, &name);
        snprintf(buf, len, "%.*s", (int)n, name);
    } else if (row->kind == CMDLINE_TEXT && row->value <= 1)
        snprintf(buf, len, "%s", *(const char *const *)row->target ? *(const char *const *)row->target : "none");
}

/* Prints `text` from column `at`: a '\n' goes on at the description's
 * column, and so does a word that would pass spec->width (when set). */
static void put_wrapped(const cmdline_spec *spec, const char *text, int at, FILE *out)
{
    for (const char *c = text; *c; c++) {
        const int word = (int)strcspn(c + 1, " \n");
        if (*c == '\n' || (*c == ' ' && spec->width > 0 && at + 1 + word > spec->width)) {
            fprintf(out, "\n%*s", spec->column, "");
            at = spec->column;
        } else {
            fputc(*c, out);
            at++;
        }
    }
}

static void help_row(const cmdline_spec *spec, const cmdline_option *row, FILE *out)
{
    char flag[64], left[192], def[256], shown[320];
    flag_text(row, flag, sizeof flag);
    if (row->letter && row->name)
        snprintf(left, sizeof left, "-%c, %s%s%s", row->letter, flag, row->arg ? " " : "", row->arg ? row->arg : "");
    else
        snprintf(left, sizeof left, "%s%s%s", flag, row->arg ? " " : "", row->arg ? row->arg : "");
    const int width = spec->column - 4 > 0 ? spec->column - 4 : 1;
    fprintf(out, "  %-*s  ", width, left);
    const int at = 4 + ((int)strlen(left) > width ? (int)strlen(left) : width);
    default_text(row, def, sizeof def);
    shown[0] = '\0';
    if (def[0]) {
        /* a description ending in '\n' puts the default on a line of its own */
        const int own_line = *row->help && row->help[strlen(row->help) - 1] == '\n';
        shown[0] = own_line ? '\0' : ' ';
        snprintf(shown + !own_line, sizeof shown - 1, spec->default_format ? spec->default_format : "(default %s)",
                 def);
    }
    const size_t n = strlen(row->help) + strlen(shown) + 1;
    char *text = malloc(n);
    if (text) {
        snprintf(text, n, "%s%s", row->help, shown);
        put_wrapped(spec, text, at, out);
        free(text);
    }
    fputc('\n', out);
}

void cmdline_help(const cmdline_spec *spec, FILE *out)
{
    fputs(spec->usage, out);
    for (const cmdline_option *row = spec->rows; row->name || row->letter; row++)
        if (row->help)
            help_row(spec, row, out);
    if (spec->footer)
        fputs(spec->footer, out);
}
