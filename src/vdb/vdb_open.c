/* sdftrace — the OpenVDB component's C entry points: a grid file by its
 * extension, in C so that opening a `.nvdb` file never enters C++; and the
 * argument checks of sdft_vdb_load, before vdb_load.cpp does the work. */
#include <string.h>

#include "fail.h"
#include "sdftrace/vdb.h"

/* vdb_load.cpp */
SDFT_INTERNAL sdft_error sdft_vdb_open_checked(const char *path, const char *name, const sdft_vdb_options *o,
                                               sdft_grid **out, char *msg, size_t msg_len);
SDFT_INTERNAL sdft_error sdft_vdb_bounds_checked(const char *path, const char *name, sdft_aabb *box, char *msg,
                                                 size_t msg_len);

sdft_vdb_options sdft_vdb_options_defaults(void)
{
    sdft_vdb_options o;
    memset(&o, 0, sizeof o);
    o.quant = SDFT_QUANT_NONE;
    o.stream = 1;
    return o;
}

sdft_error sdft_vdb_open(const char *path, const char *name, const sdft_vdb_options *o, sdft_grid **out, char *msg,
                         size_t msg_len)
{
    if (!out)
        return sdft_fail(msg, msg_len, SDFT_EINVAL, "no place for the grid (out is NULL)");
    *out = NULL;
    if (!path)
        return sdft_fail(msg, msg_len, SDFT_EINVAL, "no path (NULL)");
    if (!o)
        return sdft_fail(msg, msg_len, SDFT_EINVAL, "no options (NULL; sdft_vdb_options_defaults makes them)");
    if ((unsigned)o->quant > SDFT_QUANT_FPN)
        return sdft_fail(msg, msg_len, SDFT_EINVAL, "unknown quantization %d", (int)o->quant);
    if ((unsigned)o->defer > 2)
        return sdft_fail(msg, msg_len, SDFT_EINVAL, "unknown defer %d (0, 1 or 2)", o->defer);
    if (o->defer && (!o->stream || (o->quant != SDFT_QUANT_NONE && o->quant != SDFT_QUANT_FP16)))
        return sdft_fail(msg, msg_len, SDFT_EINVAL, "deferred leaves need a streamed float or fp16 grid");
    return sdft_vdb_open_checked(path, name, o, out, msg, msg_len);
}

sdft_error sdft_vdb_load(const char *path, const char *name, sdft_quant quant, sdft_grid **out, char *msg,
                         size_t msg_len)
{
    sdft_vdb_options o = sdft_vdb_options_defaults();
    o.quant = quant;
    return sdft_vdb_open(path, name, &o, out, msg, msg_len);
}

sdft_error sdft_vdb_bounds(const char *path, const char *name, sdft_aabb *box, char *msg, size_t msg_len)
{
    if (!path || !box)
        return sdft_fail(msg, msg_len, SDFT_EINVAL, "no path or no place for the box (NULL)");
    return sdft_vdb_bounds_checked(path, name, box, msg, msg_len);
}

sdft_error sdft_grid_open(const char *path, const char *name, sdft_grid **out, char *msg, size_t msg_len)
{
    if (!out)
        return sdft_fail(msg, msg_len, SDFT_EINVAL, "no place for the grid (out is NULL)");
    *out = NULL;
    if (!path)
        return sdft_fail(msg, msg_len, SDFT_EINVAL, "no path (NULL)");
    const char *dot = strrchr(path, '.');
    if (dot && strcmp(dot, ".nvdb") == 0)
        return sdft_grid_load_nvdb(path, name, out, msg, msg_len);
    if (dot && strcmp(dot, ".vdb") == 0)
        return sdft_vdb_load(path, name, SDFT_QUANT_NONE, out, msg, msg_len);
    return sdft_fail(msg, msg_len, SDFT_EFORMAT, "%s: expected a .vdb or .nvdb file", path);
}
