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

/* Told the name of each stage of a long call as it begins ("reading",
 * "orienting", "exact distance, sign", "sign off the band", ...), for a
 * progress display beside sdft_progress_fn's numbers: `stage` is a string
 * of the library's that stays valid while the library is loaded. */
typedef void (*sdft_stage_fn)(void *user, const char *stage);

/* Limits every call holds to. */
#define SDFT_MESH_MAX_RES 4096                  /* voxels along a grid's side */
#define SDFT_MESH_MAX_DENSE_VOXELS 2147483648.0 /* a dense grid or array: 2^31 voxels (8 GiB of float32) */
#define SDFT_MESH_MAX_SAMPLES 100000000         /* training samples or sign-check points in one call */

/* Element types of the arrays a mesh is made of and queried at. */
typedef enum sdft_dtype {
    SDFT_FLOAT32 = 0,
    SDFT_FLOAT64 = 1,
    SDFT_INT32 = 2,
    SDFT_UINT32 = 3,
    SDFT_INT64 = 4
} sdft_dtype;

/* Vector instructions for the hierarchies' inner loops: the answers are
 * the same to rounding; only the speed differs. */
typedef enum sdft_simd {
    SDFT_SIMD_AUTO = 0, /* the widest the processor has (AVX-512, AVX2) */
    SDFT_SIMD_AVX2 = 1, /* at most AVX2 */
    SDFT_SIMD_NONE = 2  /* scalar code */
} sdft_simd;

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
    void *progress_user;       /* handed to progress and stage */
    int threads;               /* at most this many threads, the caller's included, for the mesh's work:
                                * reading, orienting, and later its queries, samples, grids and their
                                * files (unless their own params say); 0: all cores [0] */
    sdft_simd simd;            /* for all of the mesh's work [SDFT_SIMD_AUTO] */
    sdft_stage_fn stage;       /* NULL: not told [NULL] */
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
    uint64_t triangles;          /* after triangulation, zero-area ones dropped (orienting then drops
                                  * duplicate_faces of them) */
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
    double read_seconds;   /* reading (or copying) and welding, wall clock */
    double orient_seconds; /* orienting, or counting edges without orient */
    double index_seconds;  /* building the point queries' hierarchies; 0 until a query or samples built them */
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

/* How exactly winding numbers, and the inside and outside they decide, are
 * evaluated (the fast winding number's expansions, Barill et al. 2018). */
typedef enum sdft_winding_accuracy {
    SDFT_WINDING_FAST = 0, /* within 5e-3 of the exact sum over every triangle [the default] */
    SDFT_WINDING_EXACT = 1 /* within 1e-5, and inside (above 1/2) exactly where the exact sum is, by
                            * a proven error bound, refined where it does not decide; winding numbers
                            * cost about 15 times the fast ones, signs near 1/2 alone more */
} sdft_winding_accuracy;

/* "fast" or "exact"; "?" for another value. */
SDFT_API const char *sdft_winding_accuracy_name(sdft_winding_accuracy accuracy);

/* What else a query of many points takes. It will grow: zero it, or make
 * one with sdft_query_params_defaults(); NULL for the defaults. */
typedef struct sdft_query_params {
    sdft_progress_fn progress; /* NULL: no reports [NULL]; non-zero from it: SDFT_ECANCELED */
    void *progress_user;
    sdft_winding_accuracy accuracy; /* the winding numbers' and the signs' [SDFT_WINDING_FAST] */
} sdft_query_params;

SDFT_API sdft_query_params sdft_query_params_defaults(void);

/* The signed distance at each point into distance[i] (count floats),
 * exact to the triangles, signed by the winding number (negative inside,
 * where it exceeds 1/2); with winding not NULL, the winding number beside
 * it. What `mesh2sdf --query` writes. In parallel, in the order of a
 * Morton curve through the mesh's cube (the answers do not depend on it).
 * q: progress and cancelling (NULL: none). SDFT_EINVAL (NULL m, pts,
 * pts->data or distance; an unsupported type; a count of 0 is fine),
 * SDFT_ECANCELED, SDFT_ENOMEM. A non-finite point gets NaN. */
SDFT_API sdft_error sdft_mesh_signed_distance(const sdft_mesh *m, const sdft_points *pts, float *distance,
                                              float *winding, const sdft_query_params *q, char *msg, size_t msg_len);

SDFT_API sdft_error sdft_mesh_winding_number(const sdft_mesh *m, const sdft_points *pts, float *winding,
                                             const sdft_query_params *q, char *msg, size_t msg_len);

/* Training samples as `mesh2sdf --samples` draws them (DeepSDF's
 * distribution). It will grow: make one with sdft_sample_params_defaults(). */
typedef struct sdft_sample_params {
    size_t count;                   /* rows, 1..1e8 [250000] */
    uint64_t seed;                  /* the same seed, the same rows, for any thread count [1] */
    double near_sigma[2];           /* the two Gaussians' sigmas, per axis, in units of the sphere's radius
                                     * [0.0707, 0.0224: DeepSDF's] */
    double uniform_share;           /* the share of uniform points in the sphere's cube, 0..1 [0.06] */
    sdft_progress_fn progress;      /* NULL: no reports [NULL] */
    void *progress_user;            /* handed to progress and stage */
    sdft_stage_fn stage;            /* NULL: not told [NULL] */
    sdft_winding_accuracy accuracy; /* the signs' [SDFT_WINDING_FAST] */
} sdft_sample_params;

SDFT_API sdft_sample_params sdft_sample_params_defaults(void);

/* How many of p->count rows are of each kind: *uniform = round(share *
 * count) (a share outside [0, 1] taken as the nearer end, NaN as 0), the
 * rest near, the first sigma's ceil(near / 2) and the second's
 * floor(near / 2). Any output may be NULL. */
SDFT_API void sdft_sample_counts(const sdft_sample_params *p, size_t *near_first, size_t *near_second, size_t *uniform);

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

/* "winding", "flood" or "none"; "?" for another value. */
SDFT_API const char *sdft_mesh_sign_name(sdft_mesh_sign sign);

/* How to convert, mesh2sdf's options. It will grow: make one with
 * sdft_mesh_grid_params_defaults(). */
typedef struct sdft_mesh_grid_params {
    int res;                        /* voxel centres along the padded box's longest side, --res [256] */
    double voxel_size;              /* world units; > 0 overrides res, --voxel-size [0] */
    double band;                    /* narrow-band half-width in voxels, --band [3] */
    int full;                       /* 1: a distance in every voxel of the padded box, --full [0] */
    double padding;                 /* voxels around the mesh's box; < 0: band + 1, --padding [-1] */
    sdft_mesh_sign sign;            /* --sign [SDFT_SIGN_WINDING] */
    const char *name;               /* the grid's name; NULL: the mesh file's stem ("mesh" for arrays) [NULL] */
    sdft_progress_fn progress;      /* NULL: no reports [NULL] */
    void *progress_user;            /* handed to progress and stage */
    int threads;                    /* at most this many threads, the caller's included, for the grid and
                                     * what is done with it later; 0: the mesh's (sdft_mesh_params) [0] */
    unsigned writes;                /* the files the grid will be written as (SDFT_WRITES_*): their limits and
                                     * memory are checked before the grid is built, not after [0] */
    sdft_stage_fn stage;            /* NULL: not told [NULL] */
    sdft_winding_accuracy accuracy; /* the winding sign's [SDFT_WINDING_FAST] */
} sdft_mesh_grid_params;

/* sdft_mesh_grid_params.writes: */
#define SDFT_WRITES_NVDB 1u /* a NanoVDB copy will be made */
#define SDFT_WRITES_NPY 2u  /* a dense array will be made: at most 2^31 voxels */

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
    int surface;               /* some active voxel is inside (by more than rounding): the grid has a
                                * zero crossing to trace */
    uint64_t memory_bytes;     /* the grid's memory */
    double seconds;            /* building it, wall clock */
    double winding_seconds;    /* of which the winding numbers' sign (SDFT_SIGN_WINDING) */
} sdft_mesh_box;

/* Converts m as mesh2sdf converts its mesh with the same options into *out
 * (sdft_mesh_grid_free). SDFT_EINVAL (a NULL argument; res, voxel size,
 * band or padding out of mesh2sdf's ranges; a box over 4096 voxels a side,
 * or a dense one over 2^31 voxels), SDFT_ECANCELED, SDFT_ENOMEM (the
 * estimated peak does not fit this machine's memory, refused before any
 * work; or an allocation failed), SDFT_EINTERNAL. */
SDFT_API sdft_error sdft_mesh_to_grid(const sdft_mesh *m, const sdft_mesh_grid_params *p, sdft_mesh_grid **out,
                                      char *msg, size_t msg_len);

/* The box sdft_mesh_to_grid would convert m into with p, through the same
 * checks, without building anything: dims, origin, voxel_size and
 * background are filled, the rest is 0. SDFT_EINVAL (as sdft_mesh_to_grid),
 * SDFT_ENOMEM (the conversion would not fit this machine's memory: the
 * estimate in msg). */
SDFT_API sdft_error sdft_mesh_grid_plan(const sdft_mesh *m, const sdft_mesh_grid_params *p, sdft_mesh_box *box,
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

/* Files written together, whole or not at all, and reserved before the
 * work that fills them: sdft_mesh_files_reserve creates a temporary file
 * beside each destination now (so that a missing or read-only folder fails
 * before minutes of converting), sdft_mesh_files_write_grid writes each
 * and renames all of them into place; freeing the set before that removes
 * the temporary files. Destinations that are devices or pipes (/dev/null)
 * are written in place. New files get the mode the umask gives. */
typedef struct sdft_mesh_files sdft_mesh_files;

/* What a reserved file is written as. */
typedef enum sdft_file_format {
    SDFT_FILE_VDB = 0,  /* OpenVDB */
    SDFT_FILE_NVDB = 1, /* NanoVDB */
    SDFT_FILE_NPY = 2   /* the box densely, float32, with its sidecar JSON (.json in place of a trailing
                         * .npy, or appended) */
} sdft_file_format;

typedef struct sdft_mesh_file {
    const char *path;
    sdft_file_format format;
} sdft_mesh_file;

/* The sidecar JSON's path of an `.npy` file: a trailing `.npy` replaced by
 * `.json`, else `.json` appended. Written into out as snprintf does (out
 * may be NULL with out_len 0); returns the path's length. */
SDFT_API size_t sdft_mesh_sidecar_path(const char *npy_path, char *out, size_t out_len);

/* Reserves `count` destinations into *out (sdft_mesh_files_free); the
 * paths are copied. SDFT_EINVAL (a NULL argument or path, count 0, an
 * unknown format), SDFT_EIO (a folder missing or read-only, a destination
 * that is a folder), SDFT_ENOMEM. On failure *out is NULL and nothing is
 * left behind. */
SDFT_API sdft_error sdft_mesh_files_reserve(const sdft_mesh_file *files, size_t count, sdft_mesh_files **out, char *msg,
                                            size_t msg_len);

/* Writes g into every reserved file in its format (fp16 1: NanoVDB Fp16
 * leaves, as --fp16), side by side, then renames all into place. Once: a
 * set is spent after the call, whatever it returns. SDFT_EINVAL (a NULL
 * argument, a spent set, a dense array over 2^31 voxels), SDFT_EIO (a
 * write or a rename failed, or a writer ran out of memory: the reason in
 * msg), SDFT_ENOMEM, SDFT_EINTERNAL; on failure no destination was
 * replaced by a partial file and no temporary file is left. */
SDFT_API sdft_error sdft_mesh_files_write_grid(sdft_mesh_files *f, const sdft_mesh_grid *g, int fp16, char *msg,
                                               size_t msg_len);

/* Removes what was reserved and not written; NULL is fine. */
SDFT_API void sdft_mesh_files_free(sdft_mesh_files *f);

/* How often a grid's sign disagrees with the mesh's exact winding number
 * (mesh2sdf --check-sign). */
typedef struct sdft_sign_check {
    uint64_t clear;     /* points whose exact winding number is clearly in (> 0.75) or out (< 0.25), a voxel
                         * or more from the surface */
    uint64_t wrong;     /* of them, where the grid's nearest voxel has the other sign */
    uint64_t wrong_far; /* of them, 3 or more voxels from the surface */
} sdft_sign_check;

/* Draws `points` points uniformly (a fixed seed) in the mesh's box grown
 * by 5% a side and computes each one's winding number exactly (over every
 * triangle, of the mesh as it is: load it with orient 0 to check against
 * the file's own faces); then, for each of the `count` `.vdb` files in
 * grid_paths, compares those signs with its first float grid's nearest
 * voxel (active or not, < 0 inside) into out[i]. Every grid is read (each
 * first in a child process: a corrupt file fails, never crashes) before
 * any point is drawn. SDFT_EINVAL (a NULL argument, count 0, points outside
 * 1..1e8), SDFT_EIO (a file missing or not readable), SDFT_EFORMAT (a
 * corrupt file, no float grid), SDFT_ENOMEM (the points do not fit this
 * machine). */
SDFT_API sdft_error sdft_mesh_sign_check(const sdft_mesh *m, const char *const *grid_paths, size_t count, size_t points,
                                         sdft_sign_check *out, char *msg, size_t msg_len);

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
