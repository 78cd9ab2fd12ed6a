/* sdftrace common — the strict .npy reader (see npy_read.h). The format
 * (numpy.lib.format): the magic "\x93NUMPY", a major and a minor version
 * byte, the header's length (2 bytes little-endian in version 1, 4 in 2 and
 * 3), the header (a Python dict literal, padded with spaces, ending in a
 * newline), then the data. Only the dict literal that NumPy writes is
 * accepted: quoted keys without escapes, True or False, a tuple of decimal
 * integers. */
#define _POSIX_C_SOURCE 200809L
#include "npy_read.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Longest header read (NumPy's own limit for version 1 is 65535 bytes;
 * later versions write far less than this in practice). */
#define MAX_HEADER (1u << 20)
#define MAX_AXES 32

/* The header dict's fields, as found. */
typedef struct header {
    char descr[64];
    int fortran;
    uint64_t shape[MAX_AXES];
    int axes;
    int seen[3]; /* descr, fortran_order, shape */
} header;

/* A cursor over the header text; each read skips the blanks before it and
 * fails with a sentence in `error`. */
typedef struct dict_reader {
    const char *text;
    size_t len, at;
    char error[160];
} dict_reader;

static void skip(dict_reader *in)
{
    while (in->at < in->len && (in->text[in->at] == ' ' || in->text[in->at] == '\t' || in->text[in->at] == '\n'))
        in->at++;
}

static int fail_at(dict_reader *in, const char *what)
{
    if (!in->error[0])
        snprintf(in->error, sizeof in->error, "%s at byte %zu of the header", what, in->at);
    return 0;
}

static int expect(dict_reader *in, char c)
{
    skip(in);
    if (in->at < in->len && in->text[in->at] == c) {
        in->at++;
        return 1;
    }
    char what[32];
    snprintf(what, sizeof what, "'%c' expected", c);
    return fail_at(in, what);
}

static int peek(dict_reader *in, char c)
{
    skip(in);
    return in->at < in->len && in->text[in->at] == c;
}

/* A quoted string without escapes, of printable ASCII only (keys and
 * dtypes are, and an error message quotes it on its one line), into out
 * (`size` bytes; a longer one is cut, and then matches nothing). */
static int quoted(dict_reader *in, char *out, size_t size)
{
    skip(in);
    if (in->at >= in->len || (in->text[in->at] != '\'' && in->text[in->at] != '"'))
        return fail_at(in, "a quoted string expected");
    const char quote = in->text[in->at++];
    const char *end = memchr(in->text + in->at, quote, in->len - in->at);
    if (!end)
        return fail_at(in, "unterminated string");
    const size_t n = (size_t)(end - (in->text + in->at));
    const char *s = in->text + in->at;
    in->at += n + 1;
    for (size_t i = 0; i < n; i++)
        if (s[i] == '\\')
            return fail_at(in, "escapes in a string");
    for (size_t i = 0; i < n; i++)
        if (s[i] < 0x20 || s[i] > 0x7e)
            return fail_at(in, "a control or non-ASCII byte in a string");
    snprintf(out, size, "%.*s", (int)n, s);
    return 1;
}

static int boolean(dict_reader *in, int *out)
{
    skip(in);
    static const char *const words[] = {"True", "False"};
    for (int i = 0; i < 2; i++) {
        const size_t n = strlen(words[i]);
        if (in->len - in->at >= n && memcmp(in->text + in->at, words[i], n) == 0) {
            *out = i == 0;
            in->at += n;
            return 1;
        }
    }
    return fail_at(in, "True or False expected");
}

/* A decimal integer below 2^62. */
static int integer(dict_reader *in, uint64_t *out)
{
    skip(in);
    *out = 0;
    const size_t from = in->at;
    while (in->at < in->len && in->text[in->at] >= '0' && in->text[in->at] <= '9') {
        if (*out >= ((uint64_t)1 << 62) / 10)
            return fail_at(in, "a dimension too large");
        *out = *out * 10 + (uint64_t)(in->text[in->at++] - '0');
    }
    return in->at > from || fail_at(in, "a dimension expected");
}

/* shape: '(' [int {',' int} [',']] ')' */
static int read_shape(dict_reader *in, header *h)
{
    if (!expect(in, '('))
        return 0;
    while (!peek(in, ')')) {
        uint64_t n;
        if (!integer(in, &n))
            return 0;
        if (h->axes == MAX_AXES)
            return fail_at(in, "more than 32 axes");
        h->shape[h->axes++] = n;
        if (!peek(in, ')') && !expect(in, ','))
            return 0;
    }
    return expect(in, ')');
}

static int read_item(dict_reader *in, header *h, char *error, size_t error_len)
{
    char key[64];
    if (!quoted(in, key, sizeof key) || !expect(in, ':'))
        return 0;
    static const char *const keys[] = {"descr", "fortran_order", "shape"};
    int which = -1;
    for (int i = 0; i < 3; i++)
        if (strcmp(key, keys[i]) == 0)
            which = i;
    if (which < 0) {
        snprintf(error, error_len, "unexpected key '%s' in the header", key);
        return 0;
    }
    if (h->seen[which]++) {
        snprintf(error, error_len, "key '%s' twice in the header", key);
        return 0;
    }
    if (which == 0)
        return quoted(in, h->descr, sizeof h->descr);
    if (which == 1)
        return boolean(in, &h->fortran);
    return read_shape(in, h);
}

/* The dict: '{' item {',' item} [','] '}', every key once. */
static int parse_header(const char *text, size_t len, header *h, char *error, size_t error_len)
{
    dict_reader in = {text, len, 0, ""};
    error[0] = '\0';
    int ok = expect(&in, '{');
    while (ok && !peek(&in, '}')) {
        ok = read_item(&in, h, error, error_len);
        if (ok && !peek(&in, '}'))
            ok = expect(&in, ',');
    }
    ok = ok && expect(&in, '}');
    if (ok) {
        skip(&in);
        ok = in.at == in.len || fail_at(&in, "text after the dict");
    }
    if (!ok && !error[0])
        snprintf(error, error_len, "malformed header: %s", in.error);
    if (ok && !(h->seen[0] && h->seen[1] && h->seen[2])) {
        snprintf(error, error_len, "the header lacks 'descr', 'fortran_order' or 'shape'");
        ok = 0;
    }
    return ok;
}

/* Bytes per value of a little-endian float32 or float64 descr; 0 for any other. */
static size_t item_size(const char *descr)
{
    if (strlen(descr) != 3 || !strchr("<|=", descr[0]) || descr[1] != 'f')
        return 0;
    if (descr[0] == '=' && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__)
        return 0;
    return descr[2] == '4' ? 4 : descr[2] == '8' ? 8 : 0;
}

/* The preamble and header of an open file of `size` bytes; *offset is
 * where the data begins. 1, or 0 with the reason in error. */
static int read_preamble(FILE *f, uint64_t size, header *h, uint64_t *offset, char *error, size_t error_len)
{
    unsigned char pre[12];
    if (size < 10 || fread(pre, 1, 10, f) != 10 || memcmp(pre, "\x93NUMPY", 6) != 0) {
        snprintf(error, error_len, "not a NumPy .npy file (no \\x93NUMPY magic)");
        return 0;
    }
    const int major = pre[6], minor = pre[7];
    if (major < 1 || major > 3 || minor != 0) {
        snprintf(error, error_len, "unsupported .npy format version %d.%d", major, minor);
        return 0;
    }
    uint64_t length = pre[8] | (uint64_t)pre[9] << 8;
    *offset = 10;
    if (major >= 2) {
        if (size < 12 || fread(pre + 10, 1, 2, f) != 2) {
            snprintf(error, error_len, "truncated in its preamble");
            return 0;
        }
        length |= (uint64_t)pre[10] << 16 | (uint64_t)pre[11] << 24;
        *offset = 12;
    }
    if (length > MAX_HEADER || length > size - *offset) {
        snprintf(error, error_len, "its header length (%llu bytes) runs past the file's end",
                 (unsigned long long)length);
        return 0;
    }
    char *text = malloc((size_t)length + 1);
    if (!text || fread(text, 1, (size_t)length, f) != (size_t)length) {
        free(text);
        snprintf(error, error_len, "cannot read its header");
        return 0;
    }
    *offset += length;
    int ok = length > 0 && text[length - 1] == '\n';
    if (!ok)
        snprintf(error, error_len, "its header does not end in a newline");
    for (size_t i = 0; ok && i < length; i++) {
        const unsigned char c = (unsigned char)text[i];
        if (c < 0x20 ? c != '\n' && c != '\t' : c > 0x7e) {
            snprintf(error, error_len, "its header is not plain text");
            ok = 0;
        }
    }
    ok = ok && parse_header(text, (size_t)length, h, error, error_len);
    free(text);
    return ok;
}

/* "(3, 4)", "(5,)". */
static void shape_text(const header *h, char *buf, size_t len)
{
    size_t at = (size_t)snprintf(buf, len, "(");
    for (int i = 0; i < h->axes && at < len; i++)
        at += (size_t)snprintf(buf + at, len - at, "%s%llu", i ? ", " : "", (unsigned long long)h->shape[i]);
    if (at < len)
        snprintf(buf + at, len - at, "%s", h->axes == 1 ? ",)" : ")");
}

/* Fills values from the data: `count` rows of `columns`, `item` bytes per
 * value. 1, or 0 with the reason in error. */
static int read_values(FILE *f, const header *h, size_t item, uint64_t count, size_t columns, double *values,
                       char *error, size_t error_len)
{
    const size_t bytes = (size_t)count * columns * item;
    unsigned char *raw = malloc(bytes ? bytes : 1);
    if (!raw || fread(raw, 1, bytes, f) != bytes) {
        free(raw);
        snprintf(error, error_len, raw ? "cannot read its data" : "out of memory for its data");
        return 0;
    }
    for (uint64_t i = 0; i < count; i++)
        for (size_t k = 0; k < columns; k++) {
            /* C order: row by row; Fortran order: column by column. */
            const size_t at = h->fortran ? k * (size_t)count + (size_t)i : (size_t)i * columns + k;
            double v;
            if (item == 4) {
                float x;
                memcpy(&x, raw + at * 4, 4);
                v = x;
            } else {
                memcpy(&v, raw + at * 8, 8);
            }
            if (!isfinite(v)) {
                snprintf(error, error_len, "row %llu has a value that is not finite", (unsigned long long)i);
                free(raw);
                return 0;
            }
            values[(size_t)i * columns + k] = v;
        }
    free(raw);
    return 1;
}

/* "points PATH: WHY" into msg; -1. */
static int refuse(char *msg, size_t msg_len, const char *path, const char *fmt, ...)
{
    char why[512];
    va_list args;
    va_start(args, fmt);
    vsnprintf(why, sizeof why, fmt, args);
    va_end(args);
    snprintf(msg, msg_len, "points %s: %s", path, why);
    return -1;
}

int npy_read_rows(const char *path, size_t columns, double **values, size_t *rows, char *msg, size_t msg_len)
{
    *values = NULL;
    *rows = 0;
    struct stat st;
    if (stat(path, &st) != 0) {
        snprintf(msg, msg_len, "cannot read points %s: %s", path, strerror(errno));
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        snprintf(msg, msg_len, "cannot read points %s: not a regular file", path);
        return -1;
    }
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(msg, msg_len, "cannot read points %s: %s", path, strerror(errno));
        return -1;
    }
    const uint64_t size = (uint64_t)st.st_size;
    header h;
    memset(&h, 0, sizeof h);
    uint64_t offset = 0;
    char why[400], shape[400];
    int rc = -1;
    if (!read_preamble(f, size, &h, &offset, why, sizeof why)) {
        rc = refuse(msg, msg_len, path, "%s", why);
        goto done;
    }
    const size_t item = item_size(h.descr);
    shape_text(&h, shape, sizeof shape);
    if (item == 0) {
        rc = refuse(msg, msg_len, path, "dtype '%s' is not float32 or float64 ('<f4' or '<f8')", h.descr);
        goto done;
    }
    if (h.axes != 2 || h.shape[1] != columns || h.shape[0] == 0) {
        rc = refuse(msg, msg_len, path, "shape %s is not (N, %zu) with N >= 1", shape, columns);
        goto done;
    }
    const uint64_t count = h.shape[0], data = size - offset, row = columns * item;
    /* count < 2^62: count * row could wrap; compare by division first. */
    if (count > data / row || count * row != data) {
        if (count > data / row)
            rc = refuse(msg, msg_len, path, "the shape %s needs more than %llu bytes of data, the file has %llu", shape,
                        (unsigned long long)data, (unsigned long long)data);
        else
            rc = refuse(msg, msg_len, path, "the shape %s needs %llu bytes of data, the file has %llu", shape,
                        (unsigned long long)(count * row), (unsigned long long)data);
        goto done;
    }
    double *out = malloc((size_t)count * columns * sizeof *out);
    if (!out) {
        rc = refuse(msg, msg_len, path, "out of memory for %llu rows", (unsigned long long)count);
        goto done;
    }
    if (!read_values(f, &h, item, count, columns, out, why, sizeof why)) {
        free(out);
        rc = refuse(msg, msg_len, path, "%s", why);
        goto done;
    }
    *values = out;
    *rows = (size_t)count;
    rc = 0;
done:
    fclose(f);
    return rc;
}
