/* An outside program on the OpenVDB component: with --bake, bakes a ball
 * into OUT (.vdb or .nvdb) first; then opens the level set, says what it
 * holds, and traces one ray down through its middle. tests/test_package.c
 * builds and runs it against an install. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sdftrace/trace.h"
#include "sdftrace/vdb.h"

static float ball(const void *ctx, sdft_scratch *scratch, sdft_vec3 p)
{
    (void)ctx, (void)scratch;
    return sdft_length(p) - 1.0f;
}

int main(int argc, char **argv)
{
    if (!(argc == 2 || (argc == 3 && strcmp(argv[1], "--bake") == 0))) {
        fprintf(stderr, "usage: my_grid [--bake] GRID.vdb|GRID.nvdb\n");
        return 2;
    }
    const char *path = argv[argc - 1];
    char msg[256];
    sdft_error err = SDFT_OK;
    if (argc == 3) {
        sdft_field sphere = sdft_field_defaults();
        sphere.distance = ball;
        sphere.bounds = (sdft_aabb){{-1.1f, -1.1f, -1.1f}, {1.1f, 1.1f, 1.1f}};
        sdft_bake_params bake = sdft_bake_defaults();
        bake.res = 32;
        err = sdft_bake(&sphere, &bake, path, NULL, NULL, msg, sizeof msg);
    }
    sdft_grid *grid = NULL;
    sdft_grid_options open = sdft_grid_options_defaults();
    open.path = path;
    if (!err)
        err = sdft_vdb_open(&open, &grid, msg, sizeof msg);
    if (err) {
        fprintf(stderr, "my_grid: %s: %s\n", sdft_error_name(err), msg);
        return 1;
    }
    sdft_field field = sdft_grid_field(grid, SDFT_GRID_BOUND_FAR);
    sdft_scratch scratch;
    sdft_scratch_init(&field, &scratch);
    sdft_aabb box = sdft_grid_world_bounds(grid);
    sdft_vec3 mid = sdft_scale(sdft_add(box.lo, box.hi), 0.5f);
    sdft_ray ray = {.org = {mid.x, box.hi.y + 1.0f, mid.z}, .tnear = 0, .dir = {0, -1, 0}, .tfar = INFINITY};
    sdft_trace_params params = sdft_trace_defaults();
    sdft_hit hit = sdft_trace(&field, &scratch, &ray, &params);
    printf("grid '%s': %s, %llu active voxels; the ray down the middle %s at y = %.4f\n", sdft_grid_name(grid),
           sdft_grid_type_name(grid), (unsigned long long)sdft_grid_active_voxels(grid),
           hit.status == SDFT_HIT ? "hits" : "misses", ray.org.y - hit.t);
    sdft_grid_free(grid);
    return hit.status == SDFT_HIT ? 0 : 1;
}
