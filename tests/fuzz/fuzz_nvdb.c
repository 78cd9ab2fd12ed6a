/* sdftrace fuzzing — NanoVDB grids (`.nvdb` files' bytes) through
 * sdft_grid_open, as a buffer and as a file; a grid it opens is then read
 * across its index box and sampled through its field, since the reader's
 * promise is that a grid it accepts is safe to read anywhere. */
#include <stdint.h>
#include <stdlib.h>

#include "fuzz_input_file.h"
#include "fuzz_read_grid.h"
#include "sdftrace/grid.h"

/* Voxels and field samples across the grid's box. */
static void read_everywhere(const sdft_grid *g)
{
    fuzz_read_voxels(g);
    volatile float sink = 0;
    const sdft_field f = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_scratch s;
    sdft_scratch_init(&f, &s);
    const sdft_aabb b = sdft_grid_world_bounds(g);
    const sdft_vec3 size = {b.hi.x - b.lo.x, b.hi.y - b.lo.y, b.hi.z - b.lo.z};
    for (int n = 0; n < 512; n++) { /* an 8^3 lattice over the box grown by a tenth on each side */
        const float t[3] = {(float)(n % 8) / 7.0f * 1.2f - 0.1f, (float)(n / 8 % 8) / 7.0f * 1.2f - 0.1f,
                            (float)(n / 64) / 7.0f * 1.2f - 0.1f};
        const sdft_vec3 p = {b.lo.x + t[0] * size.x, b.lo.y + t[1] * size.y, b.lo.z + t[2] * size.z};
        sink += sdft_grid_sample(g, SDFT_GRID_BOUND_FAR, &s, p, NULL);
    }
    (void)sink;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char msg[512];
    sdft_grid_options o = sdft_grid_options_defaults();
    o.data = data, o.size = size;
    sdft_grid *g = NULL;
    if (sdft_grid_open(&o, &g, msg, sizeof msg) == SDFT_OK) {
        read_everywhere(g);
        sdft_grid_free(g);
    }
    char path[256];
    if (fuzz_input_file(data, size, ".nvdb", path, sizeof path))
        return 0;
    o = sdft_grid_options_defaults();
    o.path = path;
    if (sdft_grid_open(&o, &g, msg, sizeof msg) == SDFT_OK)
        sdft_grid_free(g);
    unlink(path);
    return 0;
}
