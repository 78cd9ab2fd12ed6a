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

#include <math.h>
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

/* How inside and outside are told apart in a grid. */
typedef enum sdft_mesh_sign {
    SDFT_SIGN_WINDING = 0, /* the winding number: open meshes too */
    SDFT_SIGN_FLOOD = 1,   /* OpenVDB's mesh-to-volume and flood fill: closed meshes only */
    SDFT_SIGN_NONE = 2     /* unsigned distances */
} sdft_mesh_sign;

/* ---- settings -----------------------------------------------------------
 * The settings of the params structs below (sdft_mesh_params,
 * sdft_mesh_grid_params, sdft_sample_params) are written once, as the rows
 * of a table: SDFT_MESH_SETTINGS, SDFT_MESH_GRID_SETTINGS and
 * SDFT_MESH_SAMPLE_SETTINGS. A row declares its struct's member of that
 * name, and holds the member's default, range and meaning: the defaults
 * functions fill the defaults from it, the calls check the ranges against
 * it, and sdft_mesh_settings() lists the rows at run time, so that a
 * front-end (mesh2sdf's options and --help, the Python keywords and
 * docstrings, the documentation's table) is made from them too.
 *
 * A row: X(name, kind, C type, values, (default), lo, hi, flags, choices,
 * automatic, value name, what it does). */

/* What a setting's member holds. */
typedef enum sdft_mesh_setting_kind {
    SDFT_MESH_SETTING_INT,    /* int, whole numbers in [lo, hi] */
    SDFT_MESH_SETTING_COUNT,  /* uint64_t, whole numbers in [lo, hi] */
    SDFT_MESH_SETTING_REAL,   /* double (an array of `count`), finite, in the range */
    SDFT_MESH_SETTING_FLAG,   /* int: 0 off, anything else on */
    SDFT_MESH_SETTING_CHOICE, /* an int-sized enum: value i is the i-th name of `choices` */
    SDFT_MESH_SETTING_TEXT    /* const char *, read during the call; NULL: the default */
} sdft_mesh_setting_kind;

/* sdft_mesh_setting.flags. */
#define SDFT_MESH_SETTING_OPEN_LO 1u /* lo itself is outside the range */
#define SDFT_MESH_SETTING_OPEN_HI 2u /* hi itself is outside the range */
#define SDFT_MESH_SETTING_AUTO 4u    /* the default lies outside the range: the call decides (`automatic` says how) */

/* A setting, as sdft_mesh_settings lists it. */
typedef struct sdft_mesh_setting {
    const char *name; /* the member's: "voxel_size" */
    sdft_mesh_setting_kind kind;
    int count;             /* values the member holds: 1, or 2 (an array) */
    size_t offset;         /* the member's offset in its params struct */
    double def[2];         /* the default, as a number (CHOICE: its index; TEXT: 0, NULL) */
    double lo, hi;         /* the range of INT, COUNT and REAL (hi may be HUGE_VAL) */
    unsigned flags;        /* SDFT_MESH_SETTING_OPEN_LO, _OPEN_HI, _AUTO */
    const char *choices;   /* CHOICE: the names of values 0, 1, ... separated by spaces; else NULL */
    const char *automatic; /* _AUTO, and TEXT: what the default means ("band + 1"); else NULL */
    const char *value;     /* the value's name in a usage line ("N"); NULL for a FLAG */
    const char *doc;       /* what it does, one sentence */
} sdft_mesh_setting;

/* The params struct whose settings sdft_mesh_settings lists. */
typedef enum sdft_mesh_settings_of {
    SDFT_MESH_SETTINGS_MESH = 0,   /* sdft_mesh_params */
    SDFT_MESH_SETTINGS_GRID = 1,   /* sdft_mesh_grid_params */
    SDFT_MESH_SETTINGS_SAMPLES = 2 /* sdft_sample_params */
} sdft_mesh_settings_of;

/* The rows of a params struct's table, in order, into *count; NULL (and 0)
 * for another value of `of`. The array is the library's, valid while it is
 * loaded. */
SDFT_API const sdft_mesh_setting *sdft_mesh_settings(sdft_mesh_settings_of of, size_t *count);

/* A row's member, declared by the table (an array of `values`). */
#define SDFT_MESH_SETTING_MEMBER(name, kind, type, values, def, lo, hi, flags, choices, automatic, value, doc)         \
    type name SDFT_MESH_SETTING_EXTENT_##values;
#define SDFT_MESH_SETTING_EXTENT_1
#define SDFT_MESH_SETTING_EXTENT_2 [2]

/* The settings of taking a mesh in (sdft_mesh_params). */
#define SDFT_MESH_SETTINGS(X)                                                                                          \
    X(orient, SDFT_MESH_SETTING_CHOICE, int, 1, (1), 0, 0, 0, "none outward", NULL, "METHOD",                          \
      "outward: weld the vertices by position, drop duplicate faces, orient each edge-connected patch "                \
      "consistently and turn it to face outward, so that inside-out, flipped and unwelded meshes sign right; "         \
      "none: the faces as given")                                                                                      \
    X(normalize, SDFT_MESH_SETTING_FLAG, int, 1, (0), 0, 0, 0, NULL, NULL, NULL,                                       \
      "map the mesh into the unit sphere first, (x - centre) / radius with DeepSDF's centre (the bounding "            \
      "box's) and radius (1.03 times the farthest vertex)")                                                            \
    X(threads, SDFT_MESH_SETTING_INT, int, 1, (0), 0, 1024, 0, NULL, NULL, "N",                                        \
      "at most this many threads, the caller's included, for the mesh's work (reading, orienting, and later its "      \
      "queries, samples, grids and files); 0: all cores")                                                              \
    X(simd, SDFT_MESH_SETTING_CHOICE, sdft_simd, 1, (SDFT_SIMD_AUTO), 0, 0, 0, "auto avx2 none", NULL, "LEVEL",        \
      "vector instructions, chosen at run time: auto, the widest the processor has (AVX-512 for the dense "            \
      "search, else AVX2); avx2, no AVX-512; none; the answers are the same to rounding")

/* How to take a mesh in. It will grow: make one with
 * sdft_mesh_params_defaults() and set the members you change. */
typedef struct sdft_mesh_params {
    const char *source;        /* what the grids' metadata names as the source mesh; NULL: the
                                * file's path, or "" for arrays. Read during the call */
    sdft_progress_fn progress; /* reading and orienting: NULL for no reports */
    void *progress_user;       /* handed to progress and stage */
    sdft_stage_fn stage;       /* NULL: not told */
    SDFT_MESH_SETTINGS(SDFT_MESH_SETTING_MEMBER)
} sdft_mesh_params;

/* The settings' defaults (SDFT_MESH_SETTINGS), no source, no callbacks. */
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

/* What else a query of many points takes. It will grow: zero it, or make
 * one with sdft_query_params_defaults(); NULL for the defaults. */
typedef struct sdft_query_params {
    sdft_progress_fn progress; /* NULL: no reports [NULL]; non-zero from it: SDFT_ECANCELED */
    void *progress_user;
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

/* The settings of a draw of training samples (sdft_sample_params). */
#define SDFT_MESH_SAMPLE_SETTINGS(X)                                                                                   \
    X(count, SDFT_MESH_SETTING_COUNT, uint64_t, 1, (250000), 1, SDFT_MESH_MAX_SAMPLES, 0, NULL, NULL, "N",             \
      "rows to draw (DeepSDF's count)")                                                                                \
    X(seed, SDFT_MESH_SETTING_COUNT, uint64_t, 1, (1), 0, 2147483647, 0, NULL, NULL, "N",                              \
      "the random seed: the same seed gives the same rows, for any thread count")                                      \
    X(near_sigma, SDFT_MESH_SETTING_REAL, double, 2, (0.070710678118654752, 0.022360679774997897), 0, HUGE_VAL,        \
      SDFT_MESH_SETTING_OPEN_LO, NULL, NULL, "A,B",                                                                    \
      "the two Gaussians' standard deviations per axis, in units of the mesh sphere's radius (DeepSDF's: the "         \
      "square roots of 0.005 and 0.0005)")                                                                             \
    X(uniform_share, SDFT_MESH_SETTING_REAL, double, 1, (0.06), 0, 1, 0, NULL, NULL, "S",                              \
      "the share of points uniform in the cube around the mesh's sphere; the rest lie near the surface "               \
      "(DeepSDF's: 3/50)")

/* Training samples drawn as DeepSDF draws them. It will grow: make one
 * with sdft_sample_params_defaults(). */
typedef struct sdft_sample_params {
    sdft_progress_fn progress; /* NULL: no reports */
    void *progress_user;       /* handed to progress and stage */
    sdft_stage_fn stage;       /* NULL: not told */
    SDFT_MESH_SAMPLE_SETTINGS(SDFT_MESH_SETTING_MEMBER)
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

/* "winding", "flood" or "none"; "?" for another value. */
SDFT_API const char *sdft_mesh_sign_name(sdft_mesh_sign sign);

/* The settings of a conversion to a grid (sdft_mesh_grid_params). */
#define SDFT_MESH_GRID_SETTINGS(X)                                                                                     \
    X(res, SDFT_MESH_SETTING_INT, int, 1, (256), 1, SDFT_MESH_MAX_RES, 0, NULL, NULL, "N",                             \
      "voxel centres along the padded box's longest side")                                                             \
    X(band, SDFT_MESH_SETTING_REAL, double, 1, (3), 0, SDFT_MESH_MAX_RES, SDFT_MESH_SETTING_OPEN_LO, NULL, NULL, "W",  \
      "narrow-band half-width in voxels")                                                                              \
    X(full, SDFT_MESH_SETTING_FLAG, int, 1, (0), 0, 0, 0, NULL, NULL, NULL,                                            \
      "a distance in every voxel of the padded box, not only in the band")                                             \
    X(voxel_size, SDFT_MESH_SETTING_REAL, double, 1, (0), 0, HUGE_VAL,                                                 \
      SDFT_MESH_SETTING_OPEN_LO | SDFT_MESH_SETTING_AUTO, NULL, "from res", "H",                                       \
      "voxel size in world units; overrides res")                                                                      \
    X(padding, SDFT_MESH_SETTING_REAL, double, 1, (-1), 0, SDFT_MESH_MAX_RES, SDFT_MESH_SETTING_AUTO, NULL,            \
      "band + 1", "P", "voxels between the mesh's box and the grid's")                                                 \
    X(sign, SDFT_MESH_SETTING_CHOICE, sdft_mesh_sign, 1, (SDFT_SIGN_WINDING), 0, 0, 0, "winding flood none", NULL,     \
      "METHOD",                                                                                                        \
      "winding: inside where the generalized winding number exceeds 1/2, right on open meshes too; flood: "            \
      "OpenVDB's flood fill, for closed meshes only; none: unsigned distances")                                        \
    X(name, SDFT_MESH_SETTING_TEXT, const char *, 1, (0), 0, 0, 0, NULL, "the mesh file's stem, mesh for arrays",      \
      "NAME", "the grid's name")                                                                                       \
    X(threads, SDFT_MESH_SETTING_INT, int, 1, (0), 0, 1024, 0, NULL, NULL, "N",                                        \
      "at most this many threads, the caller's included, for the grid and what is done with it later; 0: the "         \
      "mesh's")

/* How to convert a mesh to a grid. It will grow: make one with
 * sdft_mesh_grid_params_defaults(). */
typedef struct sdft_mesh_grid_params {
    sdft_progress_fn progress; /* NULL: no reports */
    void *progress_user;       /* handed to progress and stage */
    sdft_stage_fn stage;       /* NULL: not told */
    unsigned writes;           /* the files the grid will be written as (SDFT_WRITES_*): their limits and
                                * memory are checked before the grid is built, not after [0] */
    SDFT_MESH_GRID_SETTINGS(SDFT_MESH_SETTING_MEMBER)
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
