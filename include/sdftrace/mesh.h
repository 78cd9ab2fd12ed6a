/* sdftrace — triangle meshes to signed distances (libsdftrace_mesh; CMake
 * target sdftrace::mesh, pkg-config sdftrace_mesh). The data and its uses
 * apart, as in Open VKL: an sdft_mesh holds a triangle mesh, read from a
 * file or taken from arrays, oriented, with its health report; functions of
 * one job each, as in libigl, then ask it for signed distances and winding
 * numbers at points, for training samples, or for a grid, in memory or
 * written to a file, that the tracer renders (sdftrace/grid.h).
 *
 * Files read, by their extension: .obj, .off, .stl (text and binary) and
 * .om through OpenMesh's readers; .ply (text and both binary byte orders,
 * faces and triangle strips) through the library's own reader; .gltf and
 * .glb (glTF 2), .fbx, .dae (Collada) and .3mf through assimp, each scene
 * flattened: every mesh of every node, moved by the node's transform.
 * Readers that are not the library's run in a child process, so a
 * malformed file is an error, never a crash. Files written: OpenVDB level
 * sets (.vdb), NanoVDB grids (.nvdb), and the grid's box densely as NumPy
 * arrays (.npy) with a sidecar JSON.
 *
 * A C API over a C++17 seam: no exception crosses it (out of memory is
 * SDFT_ENOMEM, any other failure inside a dependency SDFT_EINTERNAL). Errors
 * follow sdftrace/error.h: an sdft_error, and one line in msg. Nothing here
 * prints and nothing is global. An sdft_mesh and an sdft_mesh_grid are
 * immutable once made: any number of threads may use one at once. Work runs
 * on TBB's threads.
 *
 * Distances are in the mesh's units (or, normalized, the unit sphere's),
 * negative inside. Inside is where the winding number of the oriented mesh
 * exceeds 1/2, so open and self-intersecting meshes get a sign too. */
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
typedef struct sdft_mesh_grid sdft_mesh_grid;

/* Told the name of each stage of a long call as it begins ("reading",
 * "orienting", "exact distance, sign", "sign off the band", ...), for a
 * progress display beside sdft_progress_fn's numbers: `stage` is a string
 * of the library's that stays valid while the library is loaded. */
typedef void (*sdft_mesh_stage_fn)(void *user, const char *stage);

/* Limits every call holds to. */
#define SDFT_MESH_MAX_RES 4096                  /* voxels along a grid's side */
#define SDFT_MESH_MAX_DENSE_VOXELS 2147483648.0 /* a dense grid or array: 2^31 voxels (8 GiB of float32) */
#define SDFT_MESH_MAX_SAMPLES 100000000         /* training samples in one call */

/* Element types of the arrays a mesh is made of and queried at. */
typedef enum sdft_mesh_dtype {
    SDFT_MESH_FLOAT32 = 0,
    SDFT_MESH_FLOAT64 = 1,
    SDFT_MESH_INT32 = 2,
    SDFT_MESH_UINT32 = 3,
    SDFT_MESH_INT64 = 4
} sdft_mesh_dtype;

/* Vector instructions for the hierarchies' inner loops: the answers are
 * the same to rounding; only the speed differs. */
typedef enum sdft_mesh_simd {
    SDFT_MESH_SIMD_AUTO = 0, /* the widest the processor has (AVX-512, AVX2) */
    SDFT_MESH_SIMD_AVX2 = 1, /* at most AVX2 */
    SDFT_MESH_SIMD_NONE = 2  /* scalar code */
} sdft_mesh_simd;

/* How inside and outside are told apart in a grid. */
typedef enum sdft_mesh_sign {
    SDFT_MESH_SIGN_WINDING = 0, /* the winding number: open meshes too */
    SDFT_MESH_SIGN_FLOOD = 1,   /* OpenVDB's mesh-to-volume and flood fill: closed meshes only */
    SDFT_MESH_SIGN_NONE = 2     /* unsigned distances */
} sdft_mesh_sign;

/* How exactly winding numbers, and the inside and outside they decide, are
 * evaluated (Barill et al. 2018's fast winding number, src/mesh/sign/winding.h). */
typedef enum sdft_mesh_accuracy {
    SDFT_MESH_ACCURACY_FAST = 0, /* within 5e-3 of the exact sum over every triangle */
    SDFT_MESH_ACCURACY_EXACT = 1 /* within 1e-5, and inside (above 1/2) exactly where the exact sum is, by a
                                  * proven error bound refined until it decides; a winding number costs 10 to 100
                                  * times a fast one, a sign as much only near 1/2 */
} sdft_mesh_accuracy;

/* The files a grid is written as. */
typedef enum sdft_mesh_format {
    SDFT_MESH_FORMAT_VDB = 0,  /* an OpenVDB level set */
    SDFT_MESH_FORMAT_NVDB = 1, /* a NanoVDB grid */
    SDFT_MESH_FORMAT_NPY = 2   /* the box densely, float32, shape (nx, ny, nz), z fastest, as NumPy; with the sidecar
                                * JSON beside it (a trailing .npy replaced by .json, else .json appended): origin,
                                * voxel size, shape, axis order, sign, source */
} sdft_mesh_format;

/* ---- settings ---------------------------------------------------------------
 * The settings of the params structs below (sdft_mesh_params,
 * sdft_mesh_grid_params, sdft_mesh_sample_params) are written once, as the rows
 * of a table: SDFT_MESH_SETTINGS, SDFT_MESH_GRID_SETTINGS and
 * SDFT_MESH_SAMPLE_SETTINGS. A row declares its struct's member of that
 * name, and holds the member's default, range and meaning: the defaults
 * functions fill the defaults from it, the calls check the ranges against
 * it, and sdft_mesh_settings() lists the rows at run time, so that a
 * front-end (a program's options and --help, the Python keywords and
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
    SDFT_MESH_SETTINGS_SAMPLES = 2 /* sdft_mesh_sample_params */
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

/* ---- a mesh -------------------------------------------------------------- */

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
    X(simd, SDFT_MESH_SETTING_CHOICE, sdft_mesh_simd, 1, (SDFT_MESH_SIMD_AUTO), 0, 0, 0, "auto avx2 none", NULL,       \
      "LEVEL",                                                                                                         \
      "vector instructions, chosen at run time: auto, the widest the processor has (AVX-512 for the dense "            \
      "search, else AVX2); avx2, no AVX-512; none; the answers are the same to rounding")                              \
    X(strict, SDFT_MESH_SETTING_FLAG, int, 1, (0), 0, 0, 0, NULL, NULL, NULL,                                          \
      "refuse a file its reader took with a doubt (faces it left out: a corner out of range, fewer than three "        \
      "corners, a corner repeated; a PLY header's free text) instead of taking it with a warning")                     \
    X(accuracy, SDFT_MESH_SETTING_CHOICE, sdft_mesh_accuracy, 1, (SDFT_MESH_ACCURACY_FAST), 0, 0, 0, "fast exact",     \
      NULL, "LEVEL",                                                                                                   \
      "the winding number's, for every sign and winding number of the mesh: fast, within 5e-3 of the exact sum; "      \
      "exact, within 1e-5 and inside exactly where the exact sum exceeds 1/2 (by a proven bound, refined where "       \
      "needed), slower")

/* How to take a mesh in. It will grow: make one with
 * sdft_mesh_params_defaults() and set the members you change. */
typedef struct sdft_mesh_params {
    const char *source;        /* what the grids' metadata names as the source mesh; NULL: the
                                * file's path, or "" for arrays. Read during the call */
    sdft_progress_fn progress; /* reading and orienting: NULL for no reports */
    void *progress_user;       /* handed to progress and stage */
    sdft_mesh_stage_fn stage;  /* NULL: not told */
    SDFT_MESH_SETTINGS(SDFT_MESH_SETTING_MEMBER)
} sdft_mesh_params;

/* The settings' defaults (SDFT_MESH_SETTINGS), no source, no callbacks. */
SDFT_API sdft_mesh_params sdft_mesh_params_defaults(void);

/* Reads a mesh file (the formats above): polygons triangulated (fans),
 * zero-area triangles dropped and counted, faces the reader could not take
 * (a corner out of range, fewer than three corners, a corner repeated) left
 * out and counted (sdft_mesh_health.skipped_faces, sdft_mesh_warnings),
 * vertices welded by position, then normalized and oriented as p says (NULL
 * p: the defaults). *out owns the mesh: free it with sdft_mesh_free.
 * SDFT_EINVAL (NULL path or out, a setting out of its range), SDFT_EIO
 * (missing, unreadable), SDFT_EFORMAT (a folder, an unknown extension, a
 * file its reader rejects or crashes on, a scene that fails the importer's
 * validation or reads differently twice, no faces, a coordinate not finite
 * or of absurd size, a zero-size box, a doubt with the strict setting),
 * SDFT_ECANCELED, SDFT_ENOMEM, SDFT_EINTERNAL. On failure *out is NULL. */
SDFT_API sdft_error sdft_mesh_load(const char *path, const sdft_mesh_params *p, sdft_mesh **out, char *msg,
                                   size_t msg_len);

/* A mesh from arrays, copied: vertex_count rows of 3 coordinates
 * (SDFT_MESH_FLOAT32 or SDFT_MESH_FLOAT64, C order, rows packed) and
 * face_count rows of 3 vertex indices (SDFT_MESH_INT32, SDFT_MESH_UINT32 or
 * SDFT_MESH_INT64, C order). Then as sdft_mesh_load. SDFT_EINVAL (NULL
 * arrays or out, a zero count, an unsupported dtype, an index outside
 * [0, vertex_count), more than 2^32 - 2 vertices, a setting out of its
 * range), SDFT_EFORMAT (a non-finite coordinate, no triangle of non-zero
 * area, a zero-size box), SDFT_ECANCELED, SDFT_ENOMEM. */
SDFT_API sdft_error sdft_mesh_from_arrays(const void *vertices, sdft_mesh_dtype vertex_type, size_t vertex_count,
                                          const void *faces, sdft_mesh_dtype face_type, size_t face_count,
                                          const sdft_mesh_params *p, sdft_mesh **out, char *msg, size_t msg_len);

/* Frees a mesh; NULL is fine. No query of it may be running. */
SDFT_API void sdft_mesh_free(sdft_mesh *m);

/* A mesh's health report: what it held and what orienting did (counts
 * after welding). */
typedef struct sdft_mesh_health {
    uint64_t vertices;           /* as given */
    uint64_t faces;              /* polygons as given */
    uint64_t triangles;          /* kept: the polygons' fans, less zero-area ones and (oriented) the
                                  * duplicate_faces */
    uint64_t degenerate_faces;   /* zero-area triangles dropped */
    uint64_t welded_vertices;    /* used vertices at the position of an earlier one */
    uint64_t boundary_edges;     /* edges one triangle uses */
    uint64_t non_manifold_edges; /* edges three or more triangles use */
    int closed;                  /* no boundary and no non-manifold edge */
    int oriented;                /* orientation ran (the orient setting); the counts below then: */
    uint64_t duplicate_faces;    /* triangles on the same welded vertices as an earlier one (dropped) */
    uint64_t patches;            /* edge-connected patches */
    uint64_t non_orientable_patches;
    uint64_t reoriented_faces;  /* triangles reversed, in all */
    uint64_t outward_patches;   /* patches reversed whole to face outward */
    uint64_t cavity_patches;    /* inward-facing patches kept: they bound a cavity */
    uint64_t ambiguous_patches; /* open patches with no clear outside (left as given) */
    double ambiguous_area;      /* their share of the surface area, 0..1 */
    uint64_t evidence_patches;  /* open patches with no clear outside of their own, turned the way the rest
                                 * of the mesh's winding number says (reversed ones count in outward_patches) */
    uint64_t skipped_faces;     /* faces of the file its reader could not take (left out, not in faces) */
} sdft_mesh_health;

/* Fills *h. SDFT_EINVAL for a NULL argument. */
SDFT_API sdft_error sdft_mesh_get_health(const sdft_mesh *m, sdft_mesh_health *h, char *msg, size_t msg_len);

/* The report in words, into out as snprintf writes (out may be NULL with
 * out_len 0; returns the length): "5856 vertices, 5856 faces (5856
 * triangles), 0 boundary edges, 0 non-manifold edges, 0 degenerate faces
 * skipped", and when oriented "; 0 vertices welded, ..." with what orienting
 * did. */
SDFT_API size_t sdft_mesh_health_text(const sdft_mesh_health *h, char *out, size_t out_len);

/* The report as the members of a JSON object, without its braces, into out
 * as snprintf writes: "\"vertices\": 5856, \"faces\": 5856, ..., \"orient\":
 * \"outward\"" and, when oriented, what orienting did. */
SDFT_API size_t sdft_mesh_health_json(const sdft_mesh_health *h, char *out, size_t out_len);

/* What taking the mesh in did with a doubt, a line each, each ending in
 * '\n' ("" for none), into out as snprintf writes: faces the reader left
 * out, a PLY header's free text, and the largest open patches orienting
 * left as given (how much of the surface, where). */
SDFT_API size_t sdft_mesh_warnings(const sdft_mesh *m, char *out, size_t out_len);

/* Where a mesh is. */
typedef struct sdft_mesh_frame {
    double lo[3], hi[3];      /* the box of the used vertices, in the mesh's frame (normalized or not) */
    double centre[3], radius; /* the sphere normalize maps onto the unit sphere, in the input's units:
                               * the box's centre, 1.03 times the farthest used vertex (DeepSDF's) */
    int normalized;           /* the mesh was mapped into that sphere (the normalize setting) */
} sdft_mesh_frame;

/* Fills *f. SDFT_EINVAL for a NULL argument. */
SDFT_API sdft_error sdft_mesh_get_frame(const sdft_mesh *m, sdft_mesh_frame *f, char *msg, size_t msg_len);

/* How long a mesh's stages took, wall clock. */
typedef struct sdft_mesh_timings {
    double read_seconds;   /* reading (or copying) and welding */
    double orient_seconds; /* orienting, or counting edges without orient */
    double index_seconds;  /* building the point queries' hierarchies; 0 until a query or samples built them */
} sdft_mesh_timings;

/* Fills *t. SDFT_EINVAL for a NULL argument. */
SDFT_API sdft_error sdft_mesh_get_timings(const sdft_mesh *m, sdft_mesh_timings *t, char *msg, size_t msg_len);

/* ---- distances and winding numbers at points ------------------------------ */

/* Points to query: `count` points, point i's coordinate k at byte offset
 * i * stride[0] + k * stride[1] from data (C order of float32: 12, 4;
 * Fortran order of an (n, 3) float64 array: 8, 8n). */
typedef struct sdft_mesh_points {
    const void *data;
    sdft_mesh_dtype type; /* SDFT_MESH_FLOAT32 or SDFT_MESH_FLOAT64 */
    size_t count;
    ptrdiff_t stride[2]; /* bytes; 0, 0: packed rows */
} sdft_mesh_points;

/* What else a query of many points takes. It will grow: zero it, or make
 * one with sdft_mesh_query_params_defaults(); NULL for the defaults. */
typedef struct sdft_mesh_query_params {
    sdft_progress_fn progress; /* NULL: no reports; non-zero from it: SDFT_ECANCELED */
    void *progress_user;
    int threads; /* at most this many threads, the caller's included, in [0, 1024]; 0: the mesh's */
} sdft_mesh_query_params;

SDFT_API sdft_mesh_query_params sdft_mesh_query_params_defaults(void);

/* The signed distance at each point into distance[i] (count floats),
 * exact to the triangles, signed by the winding number (negative inside,
 * where it exceeds 1/2); with winding not NULL, the winding number beside
 * it. In parallel, in the order of a Morton curve through the mesh's cube
 * (the answers do not depend on it). q: progress, cancelling and threads
 * (NULL: none, the mesh's). SDFT_EINVAL (NULL m, pts, pts->data or distance;
 * an unsupported type; q->threads out of its range; a count of 0 is fine), SDFT_ECANCELED, SDFT_ENOMEM. A non-finite
 * point gets NaN. */
SDFT_API sdft_error sdft_mesh_signed_distance(const sdft_mesh *m, const sdft_mesh_points *pts, float *distance,
                                              float *winding, const sdft_mesh_query_params *q, char *msg,
                                              size_t msg_len);

/* The winding number alone at each point, as sdft_mesh_signed_distance. */
SDFT_API sdft_error sdft_mesh_winding_number(const sdft_mesh *m, const sdft_mesh_points *pts, float *winding,
                                             const sdft_mesh_query_params *q, char *msg, size_t msg_len);

/* ---- training samples ----------------------------------------------------- */

/* The settings of a draw of training samples (sdft_mesh_sample_params). */
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
      "(DeepSDF's: 3/50)")                                                                                             \
    X(threads, SDFT_MESH_SETTING_INT, int, 1, (0), 0, 1024, 0, NULL, NULL, "N",                                        \
      "at most this many threads, the caller's included, for this draw; 0: the mesh's")

/* Training samples drawn as DeepSDF draws them. It will grow: make one
 * with sdft_mesh_sample_params_defaults(). */
typedef struct sdft_mesh_sample_params {
    sdft_progress_fn progress; /* NULL: no reports */
    void *progress_user;       /* handed to progress and stage */
    sdft_mesh_stage_fn stage;  /* NULL: not told */
    SDFT_MESH_SAMPLE_SETTINGS(SDFT_MESH_SETTING_MEMBER)
} sdft_mesh_sample_params;

/* The settings' defaults (SDFT_MESH_SAMPLE_SETTINGS), no callbacks. */
SDFT_API sdft_mesh_sample_params sdft_mesh_sample_params_defaults(void);

/* p->count rows (x, y, z, d) into rows (rows_len floats, at least 4 count),
 * DeepSDF's distribution in the mesh's frame: the near points first (on
 * area-weighted random triangles, moved by a Gaussian of either sigma,
 * alternating), then the uniform ones in the cube around the mesh's sphere;
 * d exact to the triangles, signed by the winding number. The same rows for
 * any thread count. SDFT_EINVAL (a NULL argument, rows_len too small, a
 * setting out of its range), SDFT_ECANCELED, SDFT_ENOMEM. */
SDFT_API sdft_error sdft_mesh_samples(const sdft_mesh *m, const sdft_mesh_sample_params *p, float *rows,
                                      size_t rows_len, char *msg, size_t msg_len);

/* ---- a grid --------------------------------------------------------------- */

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
    X(sign, SDFT_MESH_SETTING_CHOICE, sdft_mesh_sign, 1, (SDFT_MESH_SIGN_WINDING), 0, 0, 0, "winding flood none",      \
      NULL, "METHOD",                                                                                                  \
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
    sdft_mesh_stage_fn stage;  /* NULL: not told */
    unsigned formats;          /* the files the grid will be written as, a bit (1u << format) each of
                                * sdft_mesh_format: their limits and memory are checked before the grid is
                                * built, not after */
    SDFT_MESH_GRID_SETTINGS(SDFT_MESH_SETTING_MEMBER)
} sdft_mesh_grid_params;

/* The settings' defaults (SDFT_MESH_GRID_SETTINGS), no callbacks, formats 0. */
SDFT_API sdft_mesh_grid_params sdft_mesh_grid_params_defaults(void);

/* Converts m into *out (sdft_mesh_grid_free): an OpenVDB level set over the
 * mesh's padded box. SDFT_EINVAL (a NULL argument; a setting out of its
 * range; a box over SDFT_MESH_MAX_RES voxels a side, or a dense one over
 * SDFT_MESH_MAX_DENSE_VOXELS), SDFT_ECANCELED, SDFT_ENOMEM (the estimated
 * peak does not fit this machine's memory, refused before any work; or an
 * allocation failed), SDFT_EINTERNAL. */
SDFT_API sdft_error sdft_mesh_to_grid(const sdft_mesh *m, const sdft_mesh_grid_params *p, sdft_mesh_grid **out,
                                      char *msg, size_t msg_len);

SDFT_API void sdft_mesh_grid_free(sdft_mesh_grid *g);

/* The box of a converted grid: voxel (i, j, k), 0 <= i < dims[0] ..., has
 * its centre at origin + (i, j, k) voxel_size, and is voxel (i, j, k) of
 * the grid's index space. */
typedef struct sdft_mesh_grid_box {
    int dims[3];
    double origin[3];
    double voxel_size;
    float background; /* band * voxel_size: the value beyond the band */
} sdft_mesh_grid_box;

/* Fills *box. SDFT_EINVAL for a NULL argument. */
SDFT_API sdft_error sdft_mesh_grid_get_box(const sdft_mesh_grid *g, sdft_mesh_grid_box *box, char *msg, size_t msg_len);

/* What a converted grid holds. */
typedef struct sdft_mesh_grid_stats {
    uint64_t active_voxels;
    uint64_t ambiguous_voxels; /* signed from a winding number in (0.25, 0.75) */
    int surface;               /* some active voxel is inside (by more than rounding): the grid has a
                                * zero crossing to trace */
    uint64_t memory_bytes;     /* the grid's memory */
} sdft_mesh_grid_stats;

/* Fills *stats. SDFT_EINVAL for a NULL argument. */
SDFT_API sdft_error sdft_mesh_grid_get_stats(const sdft_mesh_grid *g, sdft_mesh_grid_stats *stats, char *msg,
                                             size_t msg_len);

/* How long building a grid took, wall clock. */
typedef struct sdft_mesh_grid_timings {
    double seconds;         /* building it */
    double winding_seconds; /* of which the winding numbers' sign (SDFT_MESH_SIGN_WINDING) */
    double index_seconds;   /* of which the hierarchies built before the first distance: the winding
                             * tree and the open edges for the sign, the nearest-triangle tree with full */
} sdft_mesh_grid_timings;

/* Fills *t. SDFT_EINVAL for a NULL argument. */
SDFT_API sdft_error sdft_mesh_grid_get_timings(const sdft_mesh_grid *g, sdft_mesh_grid_timings *t, char *msg,
                                               size_t msg_len);

/* Writes the grid to `path` as `format` (fp16 1: NanoVDB Fp16 leaves), whole
 * or not at all: temporary files beside it, renamed into place (with an
 * .npy, its sidecar JSON too); new files get the mode the umask gives.
 * SDFT_EINVAL (a NULL argument, an unknown format, a dense array over
 * SDFT_MESH_MAX_DENSE_VOXELS), SDFT_EIO, SDFT_ENOMEM, SDFT_EINTERNAL. */
SDFT_API sdft_error sdft_mesh_grid_write(const sdft_mesh_grid *g, const char *path, sdft_mesh_format format, int fp16,
                                         char *msg, size_t msg_len);

/* The box densely into values (count floats, at least dims[0] dims[1]
 * dims[2]), C order, z fastest: the array of an .npy file. SDFT_EINVAL (a
 * NULL argument, count too small). */
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
