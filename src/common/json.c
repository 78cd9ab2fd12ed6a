/* sdftrace common — JSON string literals (see json.h). */
#include "json.h"

int json_put_string(FILE *out, const char *s)
{
    if (!s)
        return fputs("null", out) < 0 ? -1 : 0;
    putc('"', out);
    for (; *s; s++) {
        const unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(out, "\\%c", c);
        else if (c < 0x20)
            fprintf(out, "\\u%04x", c);
        else
            putc(c, out);
    }
    putc('"', out);
    return ferror(out) ? -1 : 0;
}
