/* sdftrace — the OpenVDB component's C entry points: sdft_vdb_open takes a
 * path by its extension, in C so that opening a `.nvdb` file or a buffer
 * never enters C++, and checks the arguments before vdb_load.cpp does the
 * work. */
#include <string.h>

#include "fail.h"
#include "sdftrace/vdb.h"

/* vdb_load.cpp */
SDFT_INTERNAL sdft_error vdb_open_checked(const char *path, const char *name, const sdft_grid_options *o,
                                          sdft_grid **out, char *msg, size_t msg_len);
SDFT_INTERNAL sdft_error vdb_bounds_checked(const char *path, const char *name, sdft_aabb *box, char *msg,
                                            size_t msg_len);

/* A `.vdb` file's options, checked. */
static sdft_error open_vdb(const sdft_grid_options *o, sdft_grid **out, char *msg, size_t msg_len)
{
    if ((unsigned)o->quant > SDFT_QUANT_FPN)
        return fail_with(msg, msg_len, SDFT_EINVAL, "unknown quantization %d", (int)o->quant);
    if ((unsigned)o->defer > SDFT_DEFER_ALWAYS)
        return fail_with(msg, msg_len, SDFT_EINVAL, "unknown defer %d (0, 1 or 2)", (int)o->defer);
    if (o->defer && (!o->stream || (o->quant != SDFT_QUANT_NONE && o->quant != SDFT_QUANT_FP16)))
        return fail_with(msg, msg_len, SDFT_EINVAL, "deferred leaves need a streamed float or fp16 grid");
    return vdb_open_checked(o->path, o->name, o, out, msg, msg_len);
}

sdft_error sdft_vdb_open(const sdft_grid_options *o, sdft_grid **out, char *msg, size_t msg_len)
{
    if (!out)
        return fail_with(msg, msg_len, SDFT_EINVAL, "no place for the grid (out is NULL)");
    *out = NULL;
    if (!o)
        return fail_with(msg, msg_len, SDFT_EINVAL, "no options (NULL; sdft_grid_options_defaults makes them)");
    if (!o->path)
        return sdft_grid_open(o, out, msg, msg_len);
    const char *dot = strrchr(o->path, '.');
    if (dot && strcmp(dot, ".vdb") == 0)
        return open_vdb(o, out, msg, msg_len);
    if (dot && strcmp(dot, ".nvdb") == 0)
        return sdft_grid_open(o, out, msg, msg_len);
    return fail_with(msg, msg_len, SDFT_EFORMAT, "%s: expected a .vdb or .nvdb file", o->path);
}

sdft_error sdft_vdb_bounds(const char *path, const char *name, sdft_aabb *box, char *msg, size_t msg_len)
{
    if (!path || !box)
        return fail_with(msg, msg_len, SDFT_EINVAL, "no path or no place for the box (NULL)");
    return vdb_bounds_checked(path, name, box, msg, msg_len);
}
