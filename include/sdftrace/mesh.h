/* sdftrace — triangle meshes to signed distances (libsdftrace_mesh; CMake
 * target sdftrace::mesh, pkg-config sdftrace_mesh): the converter of
 * `mesh2sdf` as a C API. A mesh is read from a file or taken from arrays,
 * oriented as the converter orients it, and then asked for signed distances
 * and winding numbers at points, for training samples, or for a grid that
 * the tracer renders (sdftrace/grid.h) and that can be written as `.vdb`,
 * `.nvdb` or `.npy`, the same bytes as `mesh2sdf` writes for the same
 * options.
 *
 * A C API over a C++17 seam: no exception crosses it (out of memory is
 * SDFT_ENOMEM, any other failure inside a dependency SDFT_EINTERNAL). Errors
 * follow sdftrace/error.h: an sdft_error, and one line in msg. Nothing here
 * prints and nothing is global. An `sdft_mesh` and an `sdft_mesh_grid` are
 * immutable once made: any number of threads may query one at once. Work
 * runs on TBB's threads.
 *
 * Distances are in the mesh's units (or, with normalize, the unit
 * sphere's); negative inside. Inside is where the winding number of the
 * oriented mesh exceeds 1/2, so open and self-intersecting meshes get a
 * sign too. */
#ifndef SDFTRACE_MESH_H
#define SDFTRACE_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "grid.h"
#include "sdftrace/config.h"
#include "sdftrace/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sdft_mesh sdft_mesh;

/* Element types of the arrays a mesh is made of and queried at. */
typedef enum sdft_dtype {
    SDFT_FLOAT32 = 0,
    SDFT_FLOAT64 = 1,
    SDFT_INT32 = 2,
    SDFT_UINT32 = 3,
    SDFT_INT64 = 4
} sdft_dtype;

/* How to take a mesh in. It will grow: make one with
 * sdft_mesh_params_defaults() and set the fields you change. Defaults in
 * brackets. */
typedef struct sdft_mesh_params {
    int orient;                /* 1: each edge-connected patch made consistent and turned outward, as
                                * mesh2sdf --orient outward; 0: the faces as given [1] */
    int normalize;             /* 1: mapped into the unit sphere first, (x - centre) / radius with
                                * DeepSDF's centre and radius (sdft_mesh_info), as --normalize [0] */
    const char *source;        /* what the grids' metadata names as the source mesh; NULL: the
                                * file's path, or "" for arrays. Read during the call [NULL] */
    sdft_progress_fn progress; /* reading and orienting: NULL for no reports [NULL] */
    void *progress_user;
} sdft_mesh_params;

/* Orient, no normalizing, no progress. */
SDFT_API sdft_mesh_params sdft_mesh_params_defaults(void);

/* Reads a mesh file (.obj .ply .off .stl .om) as mesh2sdf does: polygons
 * triangulated (fans), zero-area triangles dropped and counted, vertices
 * welded by position, then normalized and oriented as p says (NULL p: the
 * defaults). *out owns the mesh: free it with sdft_mesh_free. SDFT_EINVAL
 * (NULL path or out), SDFT_EIO (missing, unreadable), SDFT_EFORMAT (an
 * unknown extension, a file its reader rejects, no faces, a non-finite
 * coordinate, a zero-size box), SDFT_ECANCELED, SDFT_ENOMEM,
 * SDFT_EINTERNAL. On failure *out is NULL. */
SDFT_API sdft_error sdft_mesh_load(const char *path, const sdft_mesh_params *p, sdft_mesh **out, char *msg,
                                   size_t msg_len);

/* A mesh from arrays, copied: vertex_count rows of 3 coordinates
 * (SDFT_FLOAT32 or SDFT_FLOAT64, C order, rows packed) and face_count rows
 * of 3 vertex indices (SDFT_INT32, SDFT_UINT32 or SDFT_INT64, C order).
 * Then as sdft_mesh_load. SDFT_EINVAL (NULL arrays or out, a zero count,
 * an unsupported dtype, an index outside [0, vertex_count), more than
 * 2^32 - 1 vertices), SDFT_EFORMAT (a non-finite coordinate, no triangle
 * of non-zero area, a zero-size box), SDFT_ECANCELED, SDFT_ENOMEM. */
SDFT_API sdft_error sdft_mesh_from_arrays(const void *vertices, sdft_dtype vertex_type, size_t vertex_count,
                                          const void *faces, sdft_dtype face_type, size_t face_count,
                                          const sdft_mesh_params *p, sdft_mesh **out, char *msg, size_t msg_len);

/* Frees a mesh; NULL is fine. No query of it may be running. */
SDFT_API void sdft_mesh_free(sdft_mesh *m);

/* What a mesh held and what orienting did (counts after welding). */
typedef struct sdft_mesh_info {
    uint64_t vertices;           /* as given */
    uint64_t faces;              /* polygons as given */
    uint64_t triangles;          /* kept: after triangulation, zero-area and duplicate ones dropped */
    uint64_t degenerate_faces;   /* zero-area triangles dropped */
    uint64_t welded_vertices;    /* used vertices at the position of an earlier one */
    uint64_t boundary_edges;     /* edges one triangle uses */
    uint64_t non_manifold_edges; /* edges three or more triangles use */
    int closed;                  /* no boundary and no non-manifold edge */
    int oriented;                /* orientation ran (sdft_mesh_params.orient); the counts below then: */
    uint64_t duplicate_faces;    /* triangles on the same welded vertices as an earlier one (dropped) */
    uint64_t patches;            /* edge-connected patches */
    uint64_t non_orientable_patches;
    uint64_t reoriented_faces;  /* triangles reversed, in all */
    uint64_t outward_patches;   /* patches reversed whole to face outward */
    uint64_t cavity_patches;    /* inward-facing patches kept: they bound a cavity */
    uint64_t ambiguous_patches; /* open patches with no clear outside (left as given) */
    double lo[3], hi[3];        /* the box of the used vertices, in the mesh's frame (normalized or not) */
    double centre[3], radius;   /* the sphere normalize maps onto the unit sphere, in the input's units */
    int normalized;
} sdft_mesh_info;

/* Fills *info. SDFT_EINVAL for a NULL argument. */
SDFT_API sdft_error sdft_mesh_get_info(const sdft_mesh *m, sdft_mesh_info *info, char *msg, size_t msg_len);

/* Points to query: `count` points, point i's coordinate k at byte offset
 * i * stride[0] + k * stride[1] from data (C order of float32: 12, 4;
 * Fortran order of an (n, 3) float64 array: 8, 8n). */
typedef struct sdft_points {
    const void *data;
    sdft_dtype type; /* SDFT_FLOAT32 or SDFT_FLOAT64 */
    size_t count;
    ptrdiff_t stride[2]; /* bytes; 0, 0: packed rows */
} sdft_points;

/* The signed distance at each point into distance[i] (count floats),
 * exact to the triangles, signed by the winding number (negative inside,
 * where it exceeds 1/2); with winding not NULL, the winding number beside
 * it. What `mesh2sdf --query` writes. In parallel. SDFT_EINVAL (NULL m,
 * pts, pts->data or distance; an unsupported type; a count of 0 is fine),
 * SDFT_ENOMEM. A non-finite point gets NaN. */
SDFT_API sdft_error sdft_mesh_signed_distance(const sdft_mesh *m, const sdft_points *pts, float *distance,
                                              float *winding, char *msg, size_t msg_len);

/* The generalized winding number at each point into winding[i]: 1 inside
 * a closed outward mesh, 0 outside, 1/2 on it; fractional near holes.
 * Errors as sdft_mesh_signed_distance's. */
SDFT_API sdft_error sdft_mesh_winding_number(const sdft_mesh *m, const sdft_points *pts, float *winding, char *msg,
                                             size_t msg_len);

/* Training samples as `mesh2sdf --samples` draws them (DeepSDF's
 * distribution). It will grow: make one with sdft_sample_params_defaults(). */
typedef struct sdft_sample_params {
    size_t count;              /* rows, 1..1e8 [250000] */
    uint64_t seed;             /* the same seed, the same rows, for any thread count [1] */
    double near_sigma[2];      /* the two Gaussians' sigmas, per axis, in units of the sphere's radius
                                * [0.0707, 0.0224: DeepSDF's] */
    double uniform_share;      /* the share of uniform points in the sphere's cube, 0..1 [0.06] */
    sdft_progress_fn progress; /* NULL: no reports [NULL] */
    void *progress_user;
} sdft_sample_params;

SDFT_API sdft_sample_params sdft_sample_params_defaults(void);

/* p->count rows (x, y, z, d) into rows (rows_len floats, at least 4 count):
 * the near points first, alternating the two sigmas, then the uniform
 * ones; d exact, signed by the winding number. The bytes `mesh2sdf MESH
 * --samples N OUT.npy --seed S` writes after the header, for a mesh loaded
 * with the same normalize. SDFT_EINVAL (a NULL argument, count 0 or above
 * 1e8, rows_len too small, a sigma not positive and finite, a share outside
 * [0, 1], a seed above 2^31 - 1), SDFT_ECANCELED, SDFT_ENOMEM. */
SDFT_API sdft_error sdft_mesh_samples(const sdft_mesh *m, const sdft_sample_params *p, float *rows, size_t rows_len,
                                      char *msg, size_t msg_len);

/* How inside and outside are told apart in a grid (mesh2sdf --sign). */
typedef enum sdft_mesh_sign {
    SDFT_SIGN_WINDING = 0, /* the winding number: open meshes too [the default] */
    SDFT_SIGN_FLOOD = 1,   /* OpenVDB's mesh-to-volume and flood fill: closed meshes only */
    SDFT_SIGN_NONE = 2     /* unsigned distances */
} sdft_mesh_sign;

/* How to convert, mesh2sdf's options. It will grow: make one with
 * sdft_mesh_grid_params_defaults(). */
typedef struct sdft_mesh_grid_params {
    int res;                   /* voxel centres along the padded box's longest side, --res [256] */
    double voxel_size;         /* world units; > 0 overrides res, --voxel-size [0] */
    double band;               /* narrow-band half-width in voxels, --band [3] */
    int full;                  /* 1: a distance in every voxel of the padded box, --full [0] */
    double padding;            /* voxels around the mesh's box; < 0: band + 1, --padding [-1] */
    sdft_mesh_sign sign;       /* --sign [SDFT_SIGN_WINDING] */
    const char *name;          /* the grid's name; NULL: the mesh file's stem ("mesh" for arrays) [NULL] */
    sdft_progress_fn progress; /* NULL: no reports [NULL] */
    void *progress_user;
    int threads; /* at most this many worker threads; 0: TBB's default (all cores) [0] */
} sdft_mesh_grid_params;

SDFT_API sdft_mesh_grid_params sdft_mesh_grid_params_defaults(void);

/* A converted grid: an OpenVDB level set over a box of voxels, immutable. */
typedef struct sdft_mesh_grid sdft_mesh_grid;

/* The box of a converted grid: voxel (i, j, k), 0 <= i < dims[0] ..., has
 * its centre at origin + (i, j, k) voxel_size, and is voxel (i, j, k) of
 * the grid's index space. */
typedef struct sdft_mesh_box {
    int dims[3];
    double origin[3];
    double voxel_size;
    float background; /* band * voxel_size: the value beyond the band */
    uint64_t active_voxels;
    uint64_t ambiguous_voxels; /* signed from a winding number in (0.25, 0.75) */
} sdft_mesh_box;

/* Converts m as mesh2sdf converts its mesh with the same options into *out
 * (sdft_mesh_grid_free). SDFT_EINVAL (a NULL argument; res, voxel size,
 * band or padding out of mesh2sdf's ranges; a box over 4096 voxels a side,
 * or a dense one over 2^31 voxels), SDFT_ECANCELED, SDFT_ENOMEM,
 * SDFT_EINTERNAL. */
SDFT_API sdft_error sdft_mesh_to_grid(const sdft_mesh *m, const sdft_mesh_grid_params *p, sdft_mesh_grid **out,
                                      char *msg, size_t msg_len);

SDFT_API void sdft_mesh_grid_free(sdft_mesh_grid *g);

/* Fills *box. SDFT_EINVAL for a NULL argument. */
SDFT_API sdft_error sdft_mesh_grid_get_box(const sdft_mesh_grid *g, sdft_mesh_box *box, char *msg, size_t msg_len);

/* Writes the grid as mesh2sdf does, by the path's extension: `.vdb`
 * (OpenVDB), `.nvdb` (NanoVDB; fp16 1: Fp16 leaves, as --fp16) or `.npy`
 * (the box densely, float32, shape (nx, ny, nz), z fastest, with the
 * sidecar JSON beside it, as --npy); whole or not at all (temporary files,
 * renamed). SDFT_EINVAL (a NULL argument, another extension), SDFT_EIO,
 * SDFT_ENOMEM, SDFT_EINTERNAL. */
SDFT_API sdft_error sdft_mesh_grid_write(const sdft_mesh_grid *g, const char *path, int fp16, char *msg,
                                         size_t msg_len);

/* The box densely into values (count floats, at least dims[0] dims[1]
 * dims[2]), C order, z fastest: the array of the `.npy` file. SDFT_EINVAL
 * (a NULL argument, count too small). */
SDFT_API sdft_error sdft_mesh_grid_dense(const sdft_mesh_grid *g, float *values, size_t count, char *msg,
                                         size_t msg_len);

/* The grid as the tracer's sdft_grid (NanoVDB, float leaves), into *out,
 * the caller's (sdft_grid_free): sdft_grid_field renders it, and
 * sdft_grid_sample samples it. Errors as sdft_grid_open's. */
SDFT_API sdft_error sdft_mesh_grid_nano(const sdft_mesh_grid *g, sdft_grid **out, char *msg, size_t msg_len);

#ifdef __cplusplus
}
#endif

#endif
