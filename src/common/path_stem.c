/* sdftrace common — a path's stem (see path_stem.h). */
#include "path_stem.h"

#include <string.h>

size_t path_stem(const char *path, const char **start)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    *start = base;
    return dot && dot != base ? (size_t)(dot - base) : strlen(base);
}
