/* The mesh component's C API in the tests (see mesh_lib_support.h). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "mesh_lib_support.h"

sdft_mesh *load_with(const char *path, const sdft_mesh_params *p)
{
    sdft_mesh *m = NULL;
    char msg[256] = "";
    assert_int_equal(sdft_mesh_load(path, p, &m, msg, sizeof msg), SDFT_OK);
    return m;
}

sdft_mesh_grid *grid_of(const sdft_mesh *m, int res)
{
    sdft_mesh_grid_params p = sdft_mesh_grid_params_defaults();
    p.res = res;
    sdft_mesh_grid *g = NULL;
    char msg[256] = "";
    assert_int_equal(sdft_mesh_to_grid(m, &p, &g, msg, sizeof msg), SDFT_OK);
    return g;
}
