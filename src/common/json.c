/* sdftrace common — JSON string literals (see json.h). */
#include "json.h"

#include <errno.h>
#include <string.h>

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

int json_write_object(const char *path, const json_member *members, size_t count, char *msg, size_t msg_len)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        snprintf(msg, msg_len, "cannot write %s: %s", path, strerror(errno));
        return -1;
    }
    fputs("{\n", f);
    for (size_t i = 0; i < count; i++) {
        fprintf(f, "  \"%s\": ", members[i].key);
        if (members[i].raw)
            fputs(members[i].value, f);
        else
            json_put_string(f, members[i].value);
        fputs(i + 1 < count ? ",\n" : "\n", f);
    }
    fputs("}\n", f);
    const int bad = ferror(f);
    const int err = errno;
    if (fclose(f) != 0 || bad) {
        snprintf(msg, msg_len, "cannot write %s: %s", path, strerror(bad ? err : errno));
        return -1;
    }
    return 0;
}
