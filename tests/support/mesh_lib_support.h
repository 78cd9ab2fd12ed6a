/* The mesh component's C API (sdftrace/mesh.h) in the tests that link it:
 * a mesh loaded, a grid converted, each asserted to succeed. */
#ifndef SDFT_TEST_MESH_LIB_SUPPORT_H
#define SDFT_TEST_MESH_LIB_SUPPORT_H

#include "sdftrace/mesh.h"

/* sdft_mesh_load with p (NULL: the defaults). */
sdft_mesh *load_with(const char *path, const sdft_mesh_params *p);

/* sdft_mesh_to_grid at res, the other settings their defaults. */
sdft_mesh_grid *grid_of(const sdft_mesh *m, int res);

#endif
