/* sdftrace fuzzing — `.vdb` files through the library's public calls, as
 * the tools make them: sdft_vdb_open whole and streamed (mesh2sdf's and the
 * library's default), deferred (render's: leaves read from the file as
 * voxels are asked for), and sdft_vdb_bounds. Whatever the bytes, each
 * call returns a code; a grid it opens answers every voxel query. */
#include <stdint.h>
#include <stdlib.h>

#include "fuzz_input_file.h"
#include "fuzz_read_grid.h"
#include "sdftrace/vdb.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[256], msg[512];
    if (fuzz_input_file(data, size, ".vdb", path, sizeof path))
        return 0;
    for (int mode = 0; mode < 2; mode++) {
        sdft_grid_options o = sdft_grid_options_defaults();
        o.path = path;
        o.defer = mode ? SDFT_DEFER_ALWAYS : SDFT_DEFER_NONE;
        sdft_grid *g = NULL;
        if (sdft_vdb_open(&o, &g, msg, sizeof msg) != SDFT_OK)
            break; /* the deferred load reads the same bytes first */
        fuzz_read_voxels(g);
        sdft_grid_free(g);
    }
    sdft_aabb box;
    (void)sdft_vdb_bounds(path, NULL, &box, msg, sizeof msg);
    unlink(path);
    return 0;
}
