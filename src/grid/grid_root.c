/* sdftrace — the exact first root of a grid's field along a ray, near the
 * surface: the library's side of src/portable/grid_root.h, the walk
 * specialised per grid type as the grid's sdft_field_accel.root. */
#include "grid_root.h"

int grid_cell_root(const float v[8], const double u0[3], const double du[3], double len, double *s)
{
    return cell_root(v, u0, du, len, s);
}

#define GRID_ROOT(name, type)                                                                                          \
    static int name(const void *ctx, sdft_scratch *s, sdft_vec3 org, sdft_vec3 dir, float t0, float t1, float *t,      \
                    sdft_vec3 *normal, uint32_t *reads)                                                                \
    {                                                                                                                  \
        const sdft_grid *g = ctx;                                                                                      \
        return grid_walk(g, type, accessor(s), org, dir, t0, t1, t, normal, reads);                                    \
    }
GRID_ROOT(grid_root_float, PNANOVDB_GRID_TYPE_FLOAT)
GRID_ROOT(grid_root_fp16, PNANOVDB_GRID_TYPE_FP16)
GRID_ROOT(grid_root_any, g->type)
#undef GRID_ROOT

grid_root_fn grid_root_for(const sdft_grid *g)
{
    return g->type == PNANOVDB_GRID_TYPE_FLOAT  ? grid_root_float
           : g->type == PNANOVDB_GRID_TYPE_FP16 ? grid_root_fp16
                                                : grid_root_any;
}
