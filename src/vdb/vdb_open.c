/* sdftrace — the OpenVDB component's C entry points: a grid file by its
 * extension, in C so that opening a `.nvdb` file never enters C++; and the
 * argument checks of sdft_vdb_load, before vdb_load.cpp does the work. */
#include <string.h>

#include "../core/fail.h"
#include "sdftrace/vdb.h"

/* vdb_load.cpp */
SDFT_INTERNAL sdft_error sdft_vdb_load_checked(const char *path, const char *name, sdft_quant quant, sdft_grid **out,
                                               char *msg, size_t msg_len);

sdft_error sdft_vdb_load(const char *path, const char *name, sdft_quant quant, sdft_grid **out, char *msg,
                         size_t msg_len)
{
    if (!out)
        return sdft_fail(msg, msg_len, SDFT_EINVAL, "no place for the grid (out is NULL)");
    *out = NULL;
    if (!path)
        return sdft_fail(msg, msg_len, SDFT_EINVAL, "no path (NULL)");
    if ((unsigned)quant > SDFT_QUANT_FPN)
        return sdft_fail(msg, msg_len, SDFT_EINVAL, "unknown quantization %d", (int)quant);
    return sdft_vdb_load_checked(path, name, quant, out, msg, msg_len);
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
