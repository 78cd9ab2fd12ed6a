/* sample_bench — the cost of one trilinear evaluation of a level set,
 * single-threaded, in ns: sdftrace's grid field beside a dense float array
 * in memory (the limit a sparse layout can approach) and NanoVDB's own
 * sampler over its read accessor, on the same points:
 *   ray   the points sdftrace's tracer evaluates, in its order (a front
 *         view, every ray from the eye), kept where they lie in the band;
 *   band  random points in random leaves, kept where they lie in the band.
 * Each is timed twice: `indep` (the points are independent, so loads
 * overlap: throughput) and `chained` (each point waits for the value before
 * it, as one ray's steps do: latency). `sdftrace-batch` is the field's
 * batch call (sdft_field_distances), which hints each point's memory
 * (sdft_field_accel.prefetch) a few points ahead, the way to evaluate many
 * scattered points (the tracer does not hint its steps: along rays it
 * cost more than it saved). Samplers are interleaved, each timed REPEAT
 * times (default 7), the median reported.
 *
 * usage: sample_bench GRID.vdb|GRID.nvdb [POINTS]   (default 2000000) */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define PNANOVDB_C
#include <nanovdb/PNanoVDB.h>

#include "sample_nano.h"
#include "sdftrace/render.h"
#include "sdftrace/vdb.h"

/* The grid's NanoVDB bytes, read through PNanoVDB.h as an outside program
 * would (the public sdft_grid_data), for the comparisons below. */
typedef struct nano {
    const uint32_t *words;
    pnanovdb_buf_t buf;
    pnanovdb_grid_handle_t grid;
    pnanovdb_root_handle_t root;
    pnanovdb_grid_type_t type;
} nano;

static nano nano_of(const sdft_grid *g)
{
    size_t size = 0;
    nano n = {.words = sdft_grid_data(g, &size)};
    n.buf = pnanovdb_make_buf((uint32_t *)n.words, size / 4);
    n.type = pnanovdb_grid_get_grid_type(n.buf, n.grid);
    n.root = pnanovdb_tree_get_root(n.buf, pnanovdb_grid_get_tree(n.buf, n.grid));
    return n;
}

/* ---- points ------------------------------------------------------------- */

typedef struct points {
    float *xyz;
    size_t n, cap;
    int band; /* every point lies in the band */
} points;

static void push(points *p, sdft_vec3 v)
{
    if (p->n == p->cap) {
        p->cap = p->cap ? 2 * p->cap : 1 << 20;
        p->xyz = realloc(p->xyz, 3 * p->cap * sizeof *p->xyz);
        if (!p->xyz) {
            fprintf(stderr, "sample_bench: out of memory\n");
            exit(1);
        }
    }
    p->xyz[3 * p->n] = v.x, p->xyz[3 * p->n + 1] = v.y, p->xyz[3 * p->n + 2] = v.z;
    p->n++;
}

/* A point lies in the band when the unbounded field there is a leaf's
 * trilinear value below the background. */
static int in_band(const sdft_grid *g, sdft_scratch *s, sdft_vec3 p)
{
    int level;
    const float v = sdft_grid_sample(g, SDFT_GRID_BOUND_NONE, s, p, &level);
    return level == 0 && fabsf(v) < sdft_grid_background(g);
}

/* The tracer's own points: a field that logs every evaluation. */
typedef struct logging {
    sdft_field inner;
    points *log;
} logging;

static float logging_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    const logging *l = ctx;
    push(l->log, p);
    return l->inner.distance(l->inner.ctx, s, p);
}

static void logging_scratch_init(const void *ctx, sdft_scratch *s)
{
    const logging *l = ctx;
    sdft_scratch_init(&l->inner, s);
}

/* Every point the tracer evaluates, in its order, from `sdftrace render`'s
 * default settings (no shadows, depth alone), or only those in the band. */
static points traced_points(const sdft_grid *g, size_t want, int band_only)
{
    points all = {0}, kept = {0};
    logging l = {sdft_grid_field(g, SDFT_GRID_BOUND_FAR), &all};
    sdft_field f = l.inner;
    /* Every callback of a wrapped field takes the wrapper's ctx; the
     * grid's accel (its exact root, hints and hull) keeps its own and is
     * kept as it is, as the distance is the grid's. */
    f.distance = logging_distance, f.scratch_init = logging_scratch_init, f.normal = NULL, f.ctx = &l;
    sdft_render_params rp = sdft_render_defaults();
    rp.camera = sdft_camera_front(f.bounds, rp.width, rp.height, 40.0f);
    rp.shadows = 0, rp.depth_only = 1, rp.threads = 1;
    if (band_only)
        sdft_render_papers(&rp); /* every ray from the eye: more points near the surface */
    sdft_image img;
    char msg[256];
    if (sdft_image_alloc(&img, rp.width, rp.height, msg, sizeof msg) ||
        sdft_render(&f, &rp, &img, NULL, msg, sizeof msg)) {
        fprintf(stderr, "sample_bench: cannot render the front view\n");
        exit(1);
    }
    sdft_image_free(&img);
    sdft_scratch s;
    sdft_scratch_init(&l.inner, &s);
    for (size_t i = 0; i < all.n && kept.n < want; i++) {
        const sdft_vec3 p = sdft_v3(all.xyz[3 * i], all.xyz[3 * i + 1], all.xyz[3 * i + 2]);
        if (!band_only || in_band(g, &s, p))
            push(&kept, p);
    }
    free(all.xyz);
    return kept;
}

static uint64_t rng_next(uint64_t *s)
{
    *s ^= *s >> 12, *s ^= *s << 25, *s ^= *s >> 27;
    return *s * 0x2545F4914F6CDD1Dull;
}

static float rng_unit(uint64_t *s) { return (float)(rng_next(s) >> 40) / (float)(1 << 24); }

static points band_points(const sdft_grid *g, size_t want)
{
    points kept = {0};
    const nano nv = nano_of(g);
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(nv.buf, nv.grid);
    const uint64_t count = pnanovdb_tree_get_node_count_leaf(nv.buf, tree);
    const uint64_t first = PNANOVDB_GRID_SIZE + pnanovdb_tree_get_node_offset_leaf(nv.buf, tree);
    const uint64_t stride = PNANOVDB_GRID_TYPE_GET(nv.type, leaf_size);
    sdft_scratch s;
    sdft_field f = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_scratch_init(&f, &s);
    uint64_t r = 88172645463325252ull;
    while (kept.n < want) {
        pnanovdb_leaf_handle_t leaf = {{first + (rng_next(&r) % count) * stride}};
        const pnanovdb_coord_t o = pnanovdb_leaf_get_bbox_min(nv.buf, leaf);
        pnanovdb_vec3_t x = {(float)(o.x & ~7) + 8.0f * rng_unit(&r), (float)(o.y & ~7) + 8.0f * rng_unit(&r),
                             (float)(o.z & ~7) + 8.0f * rng_unit(&r)};
        const pnanovdb_vec3_t w = pnanovdb_grid_index_to_worldf(nv.buf, nv.grid, &x);
        const sdft_vec3 p = sdft_v3(w.x, w.y, w.z);
        if (in_band(g, &s, p))
            push(&kept, p);
    }
    return kept;
}

/* ---- samplers ------------------------------------------------------------ */

typedef double (*sampler_fn)(const void *ctx, const float *xyz, size_t n, int chained);

/* sdftrace's field, through its distance callback as the tracer calls it. */
static double run_field(const void *ctx, const float *xyz, size_t n, int chained)
{
    const sdft_field *f = ctx;
    sdft_scratch s;
    sdft_scratch_init(f, &s);
    double sum = 0.0;
    float prev = 0.0f;
    for (size_t i = 0; i < n; i++) {
        const float k = chained ? prev * 0.0f : 0.0f;
        prev = f->distance(f->ctx, &s, sdft_v3(xyz[3 * i] + k, xyz[3 * i + 1], xyz[3 * i + 2]));
        sum += prev;
    }
    return sum;
}

/* sdftrace's field through its batch call (sdft_field_distances: each
 * point's memory hinted a few points ahead), a block of points at a time.
 * A chain has nothing to hint ahead: it runs as run_field. */
enum { BATCH = 4096 };
_Static_assert(sizeof(sdft_vec3) == 3 * sizeof(float), "points are packed x y z");
static double run_batch(const void *ctx, const float *xyz, size_t n, int chained)
{
    const sdft_field *f = ctx;
    if (chained)
        return run_field(ctx, xyz, n, chained);
    sdft_scratch s;
    sdft_scratch_init(f, &s);
    /* xyz holds n sdft_vec3 (three floats, no padding), x y z each. */
    const sdft_vec3 *p = (const sdft_vec3 *)(const void *)xyz;
    float d[BATCH];
    double sum = 0.0;
    for (size_t i = 0; i < n; i += BATCH) {
        const size_t m = n - i < BATCH ? n - i : BATCH;
        sdft_field_distances(f, &s, p + i, m, d);
        for (size_t k = 0; k < m; k++)
            sum += d[k];
    }
    return sum;
}

static inline float lerp(float a, float b, float t) { return a + (b - a) * t; }

static inline float trilerp(const float v[8], float tx, float ty, float tz)
{
    const float x00 = lerp(v[0], v[1], tx), x10 = lerp(v[2], v[3], tx);
    const float x01 = lerp(v[4], v[5], tx), x11 = lerp(v[6], v[7], tx);
    return lerp(lerp(x00, x10, ty), lerp(x01, x11, ty), tz);
}

static inline int32_t ifloor(float x)
{
    const int32_t i = (int32_t)x;
    return i - (x < (float)i);
}

/* The dense array: the same trilinear arithmetic as sdftrace's sampler. */
static double run_dense(const void *ctx, const float *xyz, size_t n, int chained)
{
    const sb_dense *d = ctx;
    const size_t sy = (size_t)d->n[2], sx = (size_t)d->n[1] * sy;
    double sum = 0.0;
    float prev = 0.0f;
    for (size_t i = 0; i < n; i++) {
        const float k = chained ? prev * 0.0f : 0.0f;
        const float p[3] = {xyz[3 * i] + k, xyz[3 * i + 1], xyz[3 * i + 2]};
        float x[3];
        for (int a = 0; a < 3; a++)
            x[a] = d->w2i[3 * a] * p[0] + d->w2i[3 * a + 1] * p[1] + d->w2i[3 * a + 2] * p[2] + d->w2i_t[a];
        const int32_t i0[3] = {ifloor(x[0]), ifloor(x[1]), ifloor(x[2])};
        const float *c =
            d->v + (size_t)(i0[0] - d->lo[0]) * sx + (size_t)(i0[1] - d->lo[1]) * sy + (size_t)(i0[2] - d->lo[2]);
        const float v[8] = {c[0], c[sx], c[sy], c[sx + sy], c[1], c[sx + 1], c[sy + 1], c[sx + sy + 1]};
        prev = trilerp(v, x[0] - (float)i0[0], x[1] - (float)i0[1], x[2] - (float)i0[2]);
        sum += prev;
    }
    return sum;
}

/* An experiment, not sdftrace's layout: bricks of 9^3 floats, each leaf's
 * 8^3 values plus a one-voxel apron on the + sides (GVDB's and Hansson
 * Soderlund et al.'s bricked layout), found through a dense block table:
 * every trilinear cell is one table load and eight loads in one brick. */
typedef struct bricks {
    uint32_t *block; /* per 8^3 block of the box: brick index + 1, 0 none */
    float *value;    /* bricks x 729, x fastest */
    int32_t b0[3];
    int n[3];
    float w2i[9], w2i_t[3];
} bricks;

static int bricks_make(const sdft_grid *g, const sb_dense *dense, bricks *k)
{
    size_t blocks = 1, count = 0;
    const nano nv = nano_of(g);
    int32_t ilo[3], ihi[3];
    sdft_grid_index_bounds(g, ilo, ihi);
    for (int a = 0; a < 3; a++) {
        k->b0[a] = ilo[a] >> 3;
        k->n[a] = (ihi[a] >> 3) - k->b0[a] + 1;
        blocks *= (size_t)k->n[a];
    }
    /* The dense array's transform: NanoVDB's own floats. */
    memcpy(k->w2i, dense->w2i, sizeof k->w2i);
    memcpy(k->w2i_t, dense->w2i_t, sizeof k->w2i_t);
    k->block = calloc(blocks, sizeof *k->block);
    if (!k->block)
        return -1;
    for (int z = 0; z < k->n[2]; z++)
        for (int y = 0; y < k->n[1]; y++)
            for (int x = 0; x < k->n[0]; x++) {
                int active;
                sdft_grid_voxel(g, (k->b0[0] + x) * 8, (k->b0[1] + y) * 8, (k->b0[2] + z) * 8, &active);
                pnanovdb_readaccessor_t acc;
                pnanovdb_readaccessor_init(&acc, nv.root);
                pnanovdb_coord_t ijk = {(k->b0[0] + x) * 8, (k->b0[1] + y) * 8, (k->b0[2] + z) * 8};
                uint32_t level;
                pnanovdb_readaccessor_get_value_address_and_level(nv.type, nv.buf, &acc, &ijk, &level);
                if (level == 0)
                    k->block[((size_t)z * k->n[1] + y) * k->n[0] + x] = (uint32_t)++count;
            }
    k->value = malloc(count * 729 * sizeof *k->value);
    if (!k->value)
        return -1;
    for (int z = 0; z < k->n[2]; z++)
        for (int y = 0; y < k->n[1]; y++)
            for (int x = 0; x < k->n[0]; x++) {
                const uint32_t b = k->block[((size_t)z * k->n[1] + y) * k->n[0] + x];
                if (!b)
                    continue;
                float *v = k->value + (size_t)(b - 1) * 729;
                for (int i = 0; i < 729; i++)
                    v[i] = sdft_grid_voxel(g, (k->b0[0] + x) * 8 + i % 9, (k->b0[1] + y) * 8 + i / 9 % 9,
                                           (k->b0[2] + z) * 8 + i / 81, NULL);
            }
    return 0;
}

static double run_bricks(const void *ctx, const float *xyz, size_t n, int chained)
{
    const bricks *k = ctx;
    double sum = 0.0;
    float prev = 0.0f;
    for (size_t i = 0; i < n; i++) {
        const float c = chained ? prev * 0.0f : 0.0f;
        const float p[3] = {xyz[3 * i] + c, xyz[3 * i + 1], xyz[3 * i + 2]};
        float x[3];
        for (int a = 0; a < 3; a++)
            x[a] = k->w2i[3 * a] * p[0] + k->w2i[3 * a + 1] * p[1] + k->w2i[3 * a + 2] * p[2] + k->w2i_t[a];
        const int32_t i0[3] = {ifloor(x[0]), ifloor(x[1]), ifloor(x[2])};
        const uint32_t bx = (uint32_t)((i0[0] >> 3) - k->b0[0]), by = (uint32_t)((i0[1] >> 3) - k->b0[1]),
                       bz = (uint32_t)((i0[2] >> 3) - k->b0[2]);
        float v[8] = {0};
        if (bx < (uint32_t)k->n[0] && by < (uint32_t)k->n[1] && bz < (uint32_t)k->n[2]) {
            const uint32_t b = k->block[((size_t)bz * k->n[1] + by) * k->n[0] + bx];
            if (b) {
                const float *c0 = k->value + (size_t)(b - 1) * 729 + (i0[2] & 7) * 81 + (i0[1] & 7) * 9 + (i0[0] & 7);
                for (int j = 0; j < 8; j++)
                    v[j] = c0[(j & 1) + (j >> 1 & 1) * 9 + (j >> 2) * 81];
            }
        }
        prev = trilerp(v, x[0] - (float)i0[0], x[1] - (float)i0[1], x[2] - (float)i0[2]);
        sum += prev;
    }
    return sum;
}

static double run_nano(const void *ctx, const float *xyz, size_t n, int chained)
{
    return sb_nano_sum(ctx, xyz, n, chained);
}

/* ---- timing --------------------------------------------------------------- */

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

enum { MAX_SAMPLERS = 8, MAX_REPEAT = 31, SETS = 3 };

typedef struct sampler {
    const char *name;
    sampler_fn run;
    const void *ctx;
    int anywhere; /* samples any point, not only points in the band */
} sampler;

/* ns per evaluation of each sampler on one point set, interleaved. */
static void measure(const sampler *s, int count, const points *p, int chained, int repeat, double *ns, double *sums)
{
    double t[MAX_SAMPLERS][MAX_REPEAT];
    for (int r = 0; r < repeat; r++)
        for (int k = 0; k < count; k++) {
            if (!s[k].anywhere && !p->band) {
                sums[k] = t[k][r] = NAN;
                continue;
            }
            const double t0 = now();
            sums[k] = s[k].run(s[k].ctx, p->xyz, p->n, chained);
            t[k][r] = (now() - t0) * 1e9 / (double)p->n;
        }
    for (int k = 0; k < count; k++) {
        qsort(t[k], (size_t)repeat, sizeof t[k][0], cmp_double);
        ns[k] = t[k][repeat / 2];
    }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: sample_bench GRID.vdb|GRID.nvdb [POINTS]\n");
        return 2;
    }
    const size_t want = argc > 2 ? (size_t)atol(argv[2]) : 2000000;
    const char *rep = getenv("REPEAT");
    int repeat = rep && atoi(rep) > 0 ? atoi(rep) : 7;
    if (repeat > MAX_REPEAT)
        repeat = MAX_REPEAT;
    char msg[512];
    sdft_grid *g = NULL;
    sdft_grid_options go = sdft_grid_options_defaults();
    go.path = argv[1];
    if (sdft_vdb_open(&go, &g, msg, sizeof msg)) {
        fprintf(stderr, "sample_bench: %s\n", msg);
        return 1;
    }
    const nano nv = nano_of(g);
    if (nv.type != PNANOVDB_GRID_TYPE_FLOAT) {
        fprintf(stderr, "sample_bench: a float grid, please (this one is %s)\n", sdft_grid_type_name(g));
        return 1;
    }
    sb_dense dense;
    if (sb_dense_make(nv.words, &dense)) {
        fprintf(stderr, "sample_bench: out of memory for the dense array\n");
        return 1;
    }
    bricks brick;
    if (bricks_make(g, &dense, &brick)) {
        fprintf(stderr, "sample_bench: out of memory for the bricks\n");
        return 1;
    }
    points sets[3] = {traced_points(g, want, 1), band_points(g, want), traced_points(g, want, 0)};
    sets[0].band = sets[1].band = 1;
    static const char *const set_names[3] = {"ray", "band", "trace"};

    const sdft_field far = sdft_grid_field(g, SDFT_GRID_BOUND_FAR), plain = sdft_grid_field(g, SDFT_GRID_BOUND_NONE);
    const sampler s[] = {
        {"dense-array", run_dense, &dense, 0},      {"nanovdb-accessor", run_nano, nv.words, 1},
        {"sdftrace-sampler", run_field, &plain, 1}, {"sdftrace-field", run_field, &far, 1},
        {"sdftrace-batch", run_batch, &far, 1},     {"bricks-9^3", run_bricks, &brick, 0},
    };
    const int count = (int)(sizeof s / sizeof s[0]);
    printf("grid %s: %llu leaves, index box %d x %d x %d; dense array %.0f MiB; median of %d, 1 thread\n",
           sdft_grid_name(g),
           (unsigned long long)pnanovdb_tree_get_node_count_leaf(nv.buf, pnanovdb_grid_get_tree(nv.buf, nv.grid)),
           dense.n[0] - 2, dense.n[1] - 2, dense.n[2] - 2,
           (double)dense.n[0] * dense.n[1] * dense.n[2] * 4.0 / 1048576.0, repeat);
    printf("%-18s", "ns/evaluation");
    for (int set = 0; set < SETS; set++)
        printf(" %5s-indep %5s-chain", set_names[set], set_names[set]);
    printf("   (x dense: indep chain, per set)\n");
    double ns[SETS][2][MAX_SAMPLERS], sums[SETS][2][MAX_SAMPLERS];
    for (int set = 0; set < SETS; set++)
        for (int chained = 0; chained < 2; chained++)
            measure(s, count, &sets[set], chained, repeat, ns[set][chained], sums[set][chained]);
    for (int k = 0; k < count; k++) {
        printf("%-18s", s[k].name);
        for (int set = 0; set < SETS; set++)
            printf(" %11.2f %11.2f", ns[set][0][k], ns[set][1][k]);
        printf("   ");
        for (int set = 0; set < SETS; set++)
            printf(" %5.2f %5.2f", ns[set][0][k] / ns[set][0][0], ns[set][1][k] / ns[set][1][0]);
        printf("\n");
    }
    for (int set = 0; set < SETS; set++) {
        printf("%s: %zu points; mean value per sampler:", set_names[set], sets[set].n);
        for (int k = 0; k < count; k++)
            printf(" %.9g", sums[set][0][k] / (double)sets[set].n);
        printf("\n");
    }
    free(sets[0].xyz), free(sets[1].xyz), free(sets[2].xyz), free(dense.v), free(brick.block), free(brick.value);
    sdft_grid_free(g);
    return 0;
}
