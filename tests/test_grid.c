/* sdftrace tests — discrete grids: trilinear sampling, the tree bound, a
 * grid render against the procedural one, file round trips, every error. */
#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "grid_internal.h"
#include "sdftrace/grid.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "sdftrace/sdf.h"
#include "sdftrace/vdb.h"
#include "testutil.h"

/* ---- fields of our own ---------------------------------------------------- */

/* f(p) = n . p + c with |n| = 1: a plane's exact SDF, linear. */
typedef struct linear {
    sdft_vec3 n;
    float c;
} linear;

static float linear_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)s;
    const linear *l = ctx;
    return sdft_dot(l->n, p) + l->c;
}

/* Union of spheres: exact outside every sphere, a bound inside. */
static const float spheres[4][4] = {
    {0, 0, 0, 0.6f}, {0.7f, 0.2f, 0.1f, 0.35f}, {-0.5f, -0.4f, 0.3f, 0.3f}, {0.1f, 0.6f, -0.5f, 0.25f}};

static float spheres_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    float d = INFINITY;
    for (int i = 0; i < 4; i++)
        d = fminf(d, sdft_length(sdft_sub(p, sdft_v3(spheres[i][0], spheres[i][1], spheres[i][2]))) - spheres[i][3]);
    return d;
}

static sdft_field spheres_field(void)
{
    return (sdft_field){.distance = spheres_distance, .bounds = {{-1.2f, -1.2f, -1.2f}, {1.2f, 1.2f, 1.2f}}};
}

static sdft_grid *bake(const sdft_field *f, int res, int full, const char *path)
{
    sdft_bake_params p = sdft_bake_defaults();
    p.res = res;
    p.full = full;
    sdft_grid *g = NULL;
    char msg[256] = "";
    int rc = sdft_bake(f, &p, path, &g, NULL, msg, sizeof msg);
    if (rc)
        print_error("bake: %s\n", msg);
    assert_int_equal(rc, 0);
    assert_non_null(g);
    return g;
}

/* The spheres baked at res^3, and s prepared for its default field. */
static sdft_grid *spheres_grid_with_scratch(int res, sdft_scratch *s)
{
    sdft_field f = spheres_field();
    sdft_grid *g = bake(&f, res, 0, NULL);
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_scratch_init(&gf, s);
    return g;
}

/* The eight stored values of the cell whose lowest corner is i0, voxel by
 * voxel through the public accessor (v[k]: corner i0 + (k & 1, k >> 1 & 1,
 * k >> 2 & 1)). */
static void cell_corners(const sdft_grid *g, const int32_t i0[3], float v[8])
{
    for (int k = 0; k < 8; k++)
        v[k] = sdft_grid_voxel(g, i0[0] + (k & 1), i0[1] + (k >> 1 & 1), i0[2] + (k >> 2 & 1), NULL);
}

/* World point p in index space, in double through the grid's transform. */
static void index_point(const sdft_grid *g, sdft_vec3 p, double x[3])
{
    for (int k = 0; k < 3; k++)
        x[k] = (double)g->w2i[3 * k] * p.x + (double)g->w2i[3 * k + 1] * p.y + (double)g->w2i[3 * k + 2] * p.z +
               (double)g->w2i_t[k];
}

/* The world gradient of index gradient x: W^T x (d/dp f(W p + t)). */
static void world_of_index_gradient(const sdft_grid *g, const double x[3], double w[3])
{
    for (int k = 0; k < 3; k++)
        w[k] = g->w2i[k] * x[0] + g->w2i[3 + k] * x[1] + g->w2i[6 + k] * x[2];
}

/* The cell holding world point p, in double through the grid's transform:
 * its lowest corner i0, p's coordinates u in it and its eight values. */
static void cell_at(const sdft_grid *g, sdft_vec3 p, int32_t i0[3], double u[3], float v[8])
{
    double x[3];
    index_point(g, p, x);
    for (int k = 0; k < 3; k++) {
        i0[k] = (int32_t)floor(x[k]);
        u[k] = x[k] - i0[k];
    }
    cell_corners(g, i0, v);
}

/* ---- trilinear sampling ----------------------------------------------------- */

static void test_linear_field_is_exact(void **state)
{
    (void)state;
    linear l = {sdft_normalize(sdft_v3(0.3f, -0.5f, 0.8f)), 0.1f};
    sdft_field f = {.distance = linear_distance, .ctx = &l, .bounds = {{-1, -1, -1}, {1, 1, 1}}};
    sdft_grid *g = bake(&f, 32, 1, NULL);
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_scratch s;
    sdft_scratch_init(&gf, &s);
    tu_rng r = tu_rng_seed(1);
    float worst = 0;
    for (int i = 0; i < 20000; i++) {
        /* Stay half a voxel inside the box's voxel centres so all 8 corners exist. */
        sdft_vec3 p = sdft_v3(tu_uniform(&r, -0.9f, 0.9f), tu_uniform(&r, -0.9f, 0.9f), tu_uniform(&r, -0.9f, 0.9f));
        int level;
        float v = sdft_grid_sample(g, SDFT_GRID_BOUND_FAR, &s, p, &level);
        assert_int_equal(level, 0);
        worst = fmaxf(worst, fabsf(v - linear_distance(&l, NULL, p)));
        /* The field, its gradient normal: the plane's normal. */
        sdft_vec3 n = sdft_field_normal(&gf, &s, p);
        assert_true(sdft_dot(n, l.n) > 0.9999f);
    }
    assert_true(worst < 2e-6f);
    sdft_grid_free(g);
}

static float lerpf(float a, float b, float t) { return a + (b - a) * t; }

static void test_trilinear_matches_brute_force(void **state)
{
    (void)state;
    sdft_scratch s;
    sdft_grid *g = spheres_grid_with_scratch(48, &s);
    /* Index = (world - lo) / h - 1/2 for a bake (voxel centres at lo + (i + 1/2) h). */
    const float h = sdft_grid_voxel_size(g).x;
    tu_rng r = tu_rng_seed(2);
    int checked = 0;
    for (int i = 0; i < 20000; i++) {
        sdft_vec3 p = sdft_v3(tu_uniform(&r, -1.1f, 1.1f), tu_uniform(&r, -1.1f, 1.1f), tu_uniform(&r, -1.1f, 1.1f));
        int level;
        float v = sdft_grid_sample(g, SDFT_GRID_BOUND_FAR, &s, p, &level);
        if (level != 0)
            continue;
        float x[3] = {(p.x + 1.2f) / h - 0.5f, (p.y + 1.2f) / h - 0.5f, (p.z + 1.2f) / h - 0.5f};
        int32_t i0[3] = {(int32_t)floorf(x[0]), (int32_t)floorf(x[1]), (int32_t)floorf(x[2])};
        float c[8];
        cell_corners(g, i0, c);
        float t[3] = {x[0] - i0[0], x[1] - i0[1], x[2] - i0[2]};
        float ref = lerpf(lerpf(lerpf(c[0], c[1], t[0]), lerpf(c[2], c[3], t[0]), t[1]),
                          lerpf(lerpf(c[4], c[5], t[0]), lerpf(c[6], c[7], t[0]), t[1]), t[2]);
        assert_true(fabsf(v - ref) < 1e-5f);
        checked++;
    }
    assert_true(checked > 1000);
    sdft_grid_free(g);
}

/* The grid's distance functions are specialised per grid type, transform
 * shape and bound; each gives the generic sampler's value. Clearing a baked
 * grid's diagonal flag sends it through the full 3x3 transform. */
static void test_specialised_fields_agree(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_grid *g = bake(&f, 48, 0, NULL);
    assert_true(g->diagonal);
    sdft_scratch s;
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_scratch_init(&gf, &s);
    enum { N = 4000 };
    static float ref[3][N];
    static const sdft_grid_bound bounds[3] = {SDFT_GRID_BOUND_FAR, SDFT_GRID_BOUND_TREE, SDFT_GRID_BOUND_NONE};
    for (int pass = 0; pass < 2; pass++) {
        g->diagonal = pass == 0;
        for (int b = 0; b < 3; b++) {
            sdft_field bf = sdft_grid_field(g, bounds[b]);
            tu_rng r = tu_rng_seed(7);
            for (int i = 0; i < N; i++) {
                sdft_vec3 p =
                    sdft_v3(tu_uniform(&r, -1.5f, 1.5f), tu_uniform(&r, -1.5f, 1.5f), tu_uniform(&r, -1.5f, 1.5f));
                float v = bf.distance(bf.ctx, &s, p);
                assert_true(v == sdft_grid_sample(g, bounds[b], &s, p, NULL));
                if (pass == 0)
                    ref[b][i] = v;
                else
                    assert_float_equal(v, ref[b][i], 1e-6f * (1.0f + fabsf(ref[b][i])));
            }
        }
    }
    g->diagonal = 1;
    sdft_grid_free(g);
}

/* A writer that inverts a diagonal map as a general matrix can leave
 * rounding noise off the inverse's diagonal: the loader drops noise that
 * small (the grid keeps the diagonal specialisation and samples as the clean
 * grid does, bit for bit), but keeps an entry that is not noise. */
static void test_inverse_map_noise_is_dropped(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_grid *clean = bake(&f, 40, 0, NULL);
    assert_true(clean->diagonal);
    size_t size;
    const void *data = sdft_grid_data(clean, &size);
    void *copy = malloc(size);
    assert_non_null(copy);
    const double scale = (double)clean->w2i[0];
    for (int noisy = 0; noisy < 2; noisy++) {
        memcpy(copy, data, size);
        /* the inverse map's entry (2, 1), in double (what the loader reads) and in float */
        const double off = noisy ? 1e-13 * scale : 1e-3 * scale;
        unsigned char *map = (unsigned char *)copy + PNANOVDB_GRID_OFF_MAP;
        memcpy(map + PNANOVDB_MAP_OFF_INVMATD + 8 * 7, &off, sizeof off);
        const float offf = (float)off;
        memcpy(map + PNANOVDB_MAP_OFF_INVMATF + 4 * 7, &offf, sizeof offf);
        sdft_grid *g;
        char msg[256];
        assert_int_equal(tu_open_buffer(copy, size, NULL, SDFT_GRID_COPY, NULL, &g, msg, sizeof msg), 0);
        assert_int_equal(g->diagonal, noisy);
        assert_true(noisy ? g->w2i[7] == 0.0f : g->w2i[7] != 0.0f);
        if (noisy) {
            sdft_scratch s, sc;
            const sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR),
                             cf = sdft_grid_field(clean, SDFT_GRID_BOUND_FAR);
            assert_ptr_equal(gf.distance, cf.distance);
            sdft_scratch_init(&gf, &s);
            sdft_scratch_init(&cf, &sc);
            tu_rng r = tu_rng_seed(17);
            for (int i = 0; i < 2000; i++) {
                const sdft_vec3 p =
                    sdft_v3(tu_uniform(&r, -1.2f, 1.2f), tu_uniform(&r, -1.2f, 1.2f), tu_uniform(&r, -1.2f, 1.2f));
                assert_true(gf.distance(gf.ctx, &s, p) == cf.distance(cf.ctx, &sc, p));
            }
        }
        sdft_grid_free(g);
    }
    free(copy);
    sdft_grid_free(clean);
}

/* The field read through the leaf directory is the accessor's, bit for
 * bit: at random points of box b, the values (unbounded and with the tree
 * bound) and normals of g equal those of g with its directory taken away.
 * Returns how many points lay in the band. */
static int same_without_directory(sdft_grid *g, sdft_aabb b)
{
    sdft_scratch s;
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_scratch_init(&gf, &s);
    enum { N = 20000 };
    static float value[2][2][N];
    static sdft_vec3 normal[2][N];
    const grid_leaves directory = g->leaves;
    int in_leaves = 0;
    for (int pass = 0; pass < 2; pass++) {
        g->leaves.top = pass == 0 ? directory.top : NULL;
        tu_rng r = tu_rng_seed(11);
        for (int i = 0; i < N; i++) {
            sdft_vec3 p =
                sdft_v3(tu_uniform(&r, b.lo.x, b.hi.x), tu_uniform(&r, b.lo.y, b.hi.y), tu_uniform(&r, b.lo.z, b.hi.z));
            int level;
            value[pass][0][i] = sdft_grid_sample(g, SDFT_GRID_BOUND_NONE, &s, p, &level);
            value[pass][1][i] = sdft_grid_sample(g, SDFT_GRID_BOUND_TREE, &s, p, NULL);
            normal[pass][i] = sdft_field_normal(&gf, &s, p);
            in_leaves += pass == 0 && level == 0 && fabsf(value[0][0][i]) < sdft_grid_background(g);
        }
    }
    g->leaves = directory;
    for (int i = 0; i < N; i++) {
        if (!(value[0][0][i] == value[1][0][i]) || !(value[0][1][i] == value[1][1][i]))
            fail_msg("%s grid, point %d: %.9g / %.9g through the directory, %.9g / %.9g through the accessor",
                     sdft_grid_type_name(g), i, value[0][0][i], value[0][1][i], value[1][0][i], value[1][1][i]);
        assert_memory_equal(&normal[0][i], &normal[1][i], sizeof(sdft_vec3));
    }
    assert_true(in_leaves > 1000);
    return in_leaves;
}

/* The leaf directory (grid_leaves.c) holds every leaf of the tree where
 * it belongs, apron included, and marks the +-background tiles of lower
 * nodes beside them; and the field read through it is the
 * accessor's, bit for bit: the same grid with its directory taken away
 * gives the same values and normals. */
static void test_leaf_directory_matches_accessor(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 96, 0, NULL);
    assert_non_null(g->leaves.top);
    /* Every block of every chunk, against the tree: an entry is the value
     * table of the leaf holding that block, 0 where the tree has none. */
    const grid_leaves *d = &g->leaves;
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(&acc, g->root);
    size_t entries = 0, own = 0, tiles = 0;
    for (int rz = 0; rz < d->nr[2]; rz++)
        for (int ry = 0; ry < d->nr[1]; ry++)
            for (int rx = 0; rx < d->nr[0]; rx++) {
                const uint32_t c = d->top[((size_t)rz * d->nr[1] + ry) * d->nr[0] + rx];
                if (!c)
                    continue;
                for (int l = 0; l < GRID_CHUNK_ENTRIES; l++) {
                    const int lx = l % 9, ly = l / 9 % 9, lz = l / 81;
                    pnanovdb_coord_t ijk = {((d->r0[0] + rx) * 8 + lx) * 8, ((d->r0[1] + ry) * 8 + ly) * 8,
                                            ((d->r0[2] + rz) * 8 + lz) * 8};
                    uint32_t level;
                    pnanovdb_address_t a =
                        pnanovdb_readaccessor_get_value_address_and_level(g->type, g->buf, &acc, &ijk, &level);
                    const float tile = pnanovdb_read_float(g->buf, a), bg = sdft_grid_background(g);
                    const uint32_t want = level == 0 ? (uint32_t)((acc.leaf.address.byte_offset + 96u) / 4u)
                                          : level == 1 && tile == bg  ? (uint32_t)GRID_TILE_POSITIVE
                                          : level == 1 && tile == -bg ? (uint32_t)GRID_TILE_NEGATIVE
                                                                      : 0u;
                    assert_int_equal(d->chunk[(size_t)(c - 1) * GRID_CHUNK_ENTRIES + l], want);
                    entries += level == 0;
                    own += level == 0 && lx < 8 && ly < 8 && lz < 8;
                    tiles += want == GRID_TILE_POSITIVE || want == GRID_TILE_NEGATIVE;
                }
            }
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(g->buf, g->grid);
    assert_int_equal(own, pnanovdb_tree_get_node_count_leaf(g->buf, tree));
    assert_true(entries > own); /* the aprons hold some too */
    assert_true(tiles > own);   /* and the tiles beside the leaves are marked */

    same_without_directory(g, sc->field.bounds);
    sdft_grid_free(g);
}

/* Quantized grids (NanoVDB's Fp16, Fp8, Fp4 and variable-rate FpN leaves,
 * made by its own converter from a baked .vdb) sample within their codes'
 * error of the float grid. A leaf of FpB codes its values as min + k q,
 * q = (max - min) / (2^B - 1), rounded to the nearest k, so each is off by
 * at most q / 2, and a level set's leaf spans at most twice the background;
 * trilinear weights sum to 1, so the sample is off by no more. Fp16 is a
 * half float: relative error 2^-11. FpN picks each leaf's bit depth to meet
 * NanoVDB's default tolerance for level sets, a tenth of a voxel
 * (OpenToNanoVDB.h). Each renders the float grid's picture too. */
static void test_quantized_grids(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    char path[512], msg[256];
    tu_tmp(path, sizeof path, "quantized.vdb");
    remove(path);
    sdft_grid *ref = bake(&sc->field, 64, 0, path);
    const float bg = sdft_grid_background(ref), h = sdft_grid_voxel_size(ref).x;
    const struct {
        sdft_quant quant;
        const char *type;
        float error; /* most a sample may be off, world units */
    } kinds[] = {
        {SDFT_QUANT_FP16, "fp16", bg / 2048.0f},
        {SDFT_QUANT_FP8, "fp8", bg / 255.0f},
        {SDFT_QUANT_FP4, "fp4", bg / 15.0f},
        {SDFT_QUANT_FPN, "fpN", 0.1f * h},
    };
    sdft_render_params rp = sdft_render_defaults();
    rp.width = 160, rp.height = 90, rp.camera = sc->camera, rp.light = sc->light, rp.shadows = 0;
    sdft_image want, got;
    assert_int_equal(sdft_image_alloc(&want, rp.width, rp.height, NULL, 0), 0);
    assert_int_equal(sdft_image_alloc(&got, rp.width, rp.height, NULL, 0), 0);
    sdft_field rf = sdft_grid_field(ref, SDFT_GRID_BOUND_FAR);
    assert_int_equal(sdft_render(&rf, &rp, &want, NULL, msg, sizeof msg), 0);
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        sdft_grid *q = NULL;
        int rc = tu_open_file(path, NULL, kinds[k].quant, &q, msg, sizeof msg);
        if (rc)
            print_error("%s\n", msg);
        assert_int_equal(rc, 0);
        assert_string_equal(sdft_grid_type_name(q), kinds[k].type);
        /* Fp16, Fp8 and Fp4 leaves are read through the directory. */
        assert_true((q->leaves.top != NULL) == (kinds[k].quant != SDFT_QUANT_FPN));
        same_without_directory(q, sc->field.bounds);
        sdft_scratch s, sq;
        sdft_field qf = sdft_grid_field(q, SDFT_GRID_BOUND_FAR);
        sdft_scratch_init(&rf, &s);
        sdft_scratch_init(&qf, &sq);
        tu_rng r = tu_rng_seed(12);
        float worst = 0.0f;
        int checked = 0;
        for (int i = 0; i < 20000; i++) {
            sdft_vec3 p = sdft_v3(tu_uniform(&r, sc->field.bounds.lo.x, sc->field.bounds.hi.x),
                                  tu_uniform(&r, sc->field.bounds.lo.y, sc->field.bounds.hi.y),
                                  tu_uniform(&r, sc->field.bounds.lo.z, sc->field.bounds.hi.z));
            int la, lb;
            float a = sdft_grid_sample(ref, SDFT_GRID_BOUND_NONE, &s, p, &la);
            float b = sdft_grid_sample(q, SDFT_GRID_BOUND_NONE, &sq, p, &lb);
            if (la != 0 || lb != 0)
                continue;
            checked++;
            const float allowed = kinds[k].error + 1e-6f;
            worst = fmaxf(worst, fabsf(a - b));
            if (fabsf(a - b) > allowed)
                fail_msg("%s: %g against %g at (%g, %g, %g), more than %g", kinds[k].type, b, a, p.x, p.y, p.z,
                         allowed);
        }
        print_message("%s: worst sample error %g voxels over %d points\n", kinds[k].type, worst / h, checked);
        assert_true(checked > 1000);
        assert_true(worst > 0.0f || kinds[k].quant == SDFT_QUANT_FP16); /* quantized for real */
        assert_int_equal(sdft_render(&qf, &rp, &got, NULL, msg, sizeof msg), 0);
        size_t both = 0, close = 0, one = 0;
        for (size_t i = 0; i < (size_t)rp.width * rp.height; i++) {
            const int hw = isfinite(want.depth[i]), hg = isfinite(got.depth[i]);
            both += hw && hg;
            close += hw && hg && fabsf(want.depth[i] - got.depth[i]) <= 1.5f * h;
            one += hw != hg;
        }
        print_message("%s: %zu of %zu depths within 1.5 voxels, %zu pixels hit by one only\n", kinds[k].type, close,
                      both, one);
        assert_true(both > 1000);
        assert_true(close >= 0.99 * both);
        assert_true(one <= 0.005 * rp.width * rp.height);
        sdft_grid_free(q);
    }
    sdft_image_free(&want);
    sdft_image_free(&got);
    sdft_grid_free(ref);
}

/* ---- the tree bound ----------------------------------------------------------- */

/* For a scene whose SDF is only a bound (it may underestimate the distance):
 * the ball of radius r around p holds no point of the other side, judged at
 * 2 x 256 points of its surface and half-radius sphere. */
static int empty_sphere(const sdft_field *truth, sdft_vec3 p, float r, int outside)
{
    for (int k = 0; k < 512; k++) {
        float z = 1.0f - (2.0f * (float)(k % 256) + 1.0f) / 256.0f, rho = sqrtf(1.0f - z * z),
              phi = 2.3999632f * (float)k;
        float rr = k < 256 ? r : 0.5f * r;
        sdft_vec3 q = sdft_madd(p, sdft_v3(rho * cosf(phi), rho * sinf(phi), z), rr);
        float d = truth->distance(truth->ctx, NULL, q);
        if (outside ? d < 0.0f : d > 0.0f)
            return 0;
    }
    return 1;
}

/* Wherever the field answers from a tile or the background, |value| must not
 * exceed the distance to the surface and the sign must be the side. Points
 * range over the box grown by `margin` of its size on each side: a grid only
 * knows the surface inside the box it was baked over, so a scene whose
 * surface leaves its box (a ground plane) is checked inside it. */
static void check_bound(const sdft_field *truth, const sdft_grid *g, sdft_grid_bound bound, float margin,
                        int exact_inside, int bound_only, uint64_t seed, int *tiles_seen)
{
    sdft_field gf = sdft_grid_field(g, bound);
    sdft_scratch s;
    sdft_scratch_init(&gf, &s);
    sdft_aabb b = truth->bounds;
    sdft_vec3 e = sdft_sub(b.hi, b.lo);
    tu_rng r = tu_rng_seed(seed);
    for (int i = 0; i < 200000; i++) {
        sdft_vec3 p = sdft_v3(tu_uniform(&r, b.lo.x - margin * e.x, b.hi.x + margin * e.x),
                              tu_uniform(&r, b.lo.y - margin * e.y, b.hi.y + margin * e.y),
                              tu_uniform(&r, b.lo.z - margin * e.z, b.hi.z + margin * e.z));
        int level;
        float v = sdft_grid_sample(g, bound, &s, p, &level);
        if (level == 0)
            continue;
        float d = truth->distance(truth->ctx, NULL, p);
        (*tiles_seen)++;
        if (!(d * v > 0.0f) || (fabsf(v) > fabsf(d) * (1 + 1e-6f) && (d > 0 || exact_inside) &&
                                !(bound_only && empty_sphere(truth, p, fabsf(v), v > 0.0f))))
            fail_msg("%s bound %g at (%g, %g, %g), level %d, exceeds the distance %g",
                     bound == SDFT_GRID_BOUND_FAR ? "far" : "tree", v, p.x, p.y, p.z, level, d);
    }
}

static void test_tree_bound_never_exceeds_distance(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_grid *g = bake(&f, 128, 0, NULL);
    int tiles = 0;
    check_bound(&f, g, SDFT_GRID_BOUND_TREE, 0.5f, 0, 0, 3, &tiles); /* far outside the band and the box */
    assert_true(tiles > 10000);
    sdft_grid_free(g);
}

static void test_tree_bound_on_a_scene(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 96, 0, NULL);
    int tiles = 0;
    check_bound(&sc->field, g, SDFT_GRID_BOUND_TREE, 0.0f, 1, 0, 4, &tiles);
    assert_true(tiles > 10000);
    sdft_grid_free(g);
}

/* ---- the far bound --------------------------------------------------------------- */

static void test_far_bound_never_exceeds_distance(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_grid *g = bake(&f, 128, 0, NULL);
    int far = 0;
    check_bound(&f, g, SDFT_GRID_BOUND_FAR, 0.5f, 0, 0, 5, &far); /* far outside the band and the box */
    assert_true(far > 10000);
    sdft_grid_free(g);
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    g = bake(&sc->field, 96, 0, NULL);
    far = 0;
    /* figure's SDF underestimates far from its parts (a bound, not exact):
     * where the far bound exceeds it, check the ball is empty instead. */
    check_bound(&sc->field, g, SDFT_GRID_BOUND_FAR, 0.0f, 1, 1, 6, &far);
    assert_true(far > 10000);
    sdft_grid_free(g);
}

/* The far bound tests' grids: a scene's (the figure at 96^3) and a union of
 * spheres at 128^3. */
static void bake_far_bound_grids(sdft_grid *grids[2])
{
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_field spheres = spheres_field();
    grids[0] = bake(&sc->field, 96, 0, NULL);
    grids[1] = bake(&spheres, 128, 0, NULL);
}

/* The far bound's cells, classified through the leaf directory (regions
 * without leaves whole, blocks by their masks and tile markers), are the
 * cells the tree walk finds: the same corner table, bit for bit, for a
 * scene's grid and a union of spheres, at 4-voxel cells and at coarser
 * ones (as a big grid gets). */
static void test_far_cells_from_directory_match_tree(void **state)
{
    (void)state;
    sdft_grid *grids[2];
    bake_far_bound_grids(grids);
    for (int i = 0; i < 2; i++)
        for (size_t most = 1u << 24; most >= 128; most /= 16) { /* 4-voxel cells, then 8, 16 */
            sdft_grid *g = grids[i];
            grid_far_free(g);
            assert_int_equal(grid_far_build_cells(g, most), 0);
            const grid_far a = g->far;
            const size_t corners = (size_t)(a.n[0] + 1) * (a.n[1] + 1) * (a.n[2] + 1);
            g->far.corner = NULL;
            const grid_leaves directory = g->leaves;
            g->leaves.top = NULL; /* the tree walk */
            assert_int_equal(grid_far_build_cells(g, most), 0);
            g->leaves = directory;
            assert_int_equal(g->far.cell, a.cell);
            assert_memory_equal(g->far.corner, a.corner, corners * sizeof *a.corner);
            size_t occupied = 0;
            for (size_t k = 0; k < corners; k++)
                occupied += (a.corner[k] >> FAR_DISTANCE_BITS) == 0;
            print_message("cells of %d voxels: %zu corners, %zu of occupied cells\n", a.cell, corners, occupied);
            assert_true(occupied > 10);
            free(a.corner);
        }
    for (int i = 0; i < 2; i++)
        sdft_grid_free(grids[i]);
}

/* The far bound's corner distances are the Euclidean distances, in cells,
 * from each corner to the nearest corner of an occupied cell, found here by
 * brute force over every such corner, and stored as the table stores them:
 * quarters of a voxel, rounded down, saturated. For a scene's grid and a
 * union of spheres (lines of corners between two shells, whose nearest site
 * may lie ahead or behind), at 4-voxel cells and at coarser ones. */
static void test_far_corner_distances_match_brute_force(void **state)
{
    (void)state;
    sdft_grid *grids[2];
    bake_far_bound_grids(grids);
    size_t ahead_seen = 0;
    for (int i = 0; i < 2; i++)
        for (size_t most = 1u << 24; most >= 1u << 12; most >>= 12) {
            sdft_grid *g = grids[i];
            grid_far_free(g);
            assert_int_equal(grid_far_build_cells(g, most), 0);
            const grid_far *f = &g->far;
            const int nv[3] = {f->n[0] + 1, f->n[1] + 1, f->n[2] + 1};
            const size_t corners = (size_t)nv[0] * nv[1] * nv[2];
            unsigned char *site = calloc(corners, 1);
            int(*sites)[3] = malloc(corners * sizeof *sites);
            assert_non_null(site);
            assert_non_null(sites);
            size_t count = 0;
            for (int z = 0; z < f->n[2]; z++)
                for (int y = 0; y < f->n[1]; y++)
                    for (int x = 0; x < f->n[0]; x++)
                        if ((f->corner[((size_t)z * nv[1] + y) * nv[0] + x] >> FAR_DISTANCE_BITS) == 0)
                            for (int k = 0; k < 8; k++) /* an occupied cell: its corners are sites */
                                site[((size_t)(z + (k >> 2)) * nv[1] + (size_t)(y + (k >> 1 & 1))) * nv[0] +
                                     (size_t)(x + (k & 1))] = 1;
            for (int z = 0; z < nv[2]; z++)
                for (int y = 0; y < nv[1]; y++)
                    for (int x = 0; x < nv[0]; x++)
                        if (site[((size_t)z * nv[1] + y) * nv[0] + x])
                            sites[count][0] = x, sites[count][1] = y, sites[count][2] = z, count++;
            assert_true(count > 10);
            const double most_code = (double)((1u << FAR_DISTANCE_BITS) - 1u);
            size_t ahead = 0; /* corners whose nearest site along x lies ahead of them, not behind */
            for (int z = 0; z < nv[2]; z++)
                for (int y = 0; y < nv[1]; y++)
                    for (int x = 0; x < nv[0]; x++) {
                        long best = LONG_MAX;
                        for (size_t j = 0; j < count; j++) {
                            const long dx = x - sites[j][0], dy = y - sites[j][1], dz = z - sites[j][2];
                            const long d2 = dx * dx + dy * dy + dz * dz;
                            best = d2 < best ? d2 : best;
                        }
                        const double q = FAR_DISTANCE_SCALE * f->cell * sqrt((double)best);
                        const unsigned want = (unsigned)(q < most_code ? q : most_code);
                        const unsigned got =
                            f->corner[((size_t)z * nv[1] + y) * nv[0] + x] & ((1u << FAR_DISTANCE_BITS) - 1u);
                        if (got != want)
                            fail_msg("cells of %d voxels, corner (%d, %d, %d): distance %u, brute force %u", f->cell, x,
                                     y, z, got, want);
                        int behind = -1, after = -1;
                        for (int b = x - 1; b >= 0 && behind < 0; b--)
                            behind = site[((size_t)z * nv[1] + y) * nv[0] + b] ? x - b : -1;
                        for (int a = x + 1; a < nv[0] && after < 0; a++)
                            after = site[((size_t)z * nv[1] + y) * nv[0] + a] ? a - x : -1;
                        ahead +=
                            behind > 0 && after > 0 && after < behind && !site[((size_t)z * nv[1] + y) * nv[0] + x];
                    }
            print_message("cells of %d voxels: %zu corners, %zu sites, %zu nearer a site ahead\n", f->cell, corners,
                          count, ahead);
            ahead_seen += ahead;
            free(site);
            free(sites);
        }
    assert_true(ahead_seen > 100); /* between the spheres */
    for (int i = 0; i < 2; i++)
        sdft_grid_free(grids[i]);
}

/* The far bound is continuous: points a hundredth of a voxel apart differ
 * by far less than a voxel (the tree bound jumps by the band at every tile
 * edge). The corner correction's square root is steep only right at cell
 * edges, so allow a few hundredths there. */
static void test_far_bound_is_continuous(void **state)
{
    (void)state;
    sdft_scratch s;
    sdft_grid *g = spheres_grid_with_scratch(128, &s);
    const float h = sdft_grid_voxel_size(g).x, step = 0.01f * h;
    tu_rng r = tu_rng_seed(7);
    int pairs = 0;
    for (int i = 0; i < 20000; i++) {
        sdft_vec3 p = sdft_v3(tu_uniform(&r, -1.8f, 1.8f), tu_uniform(&r, -1.8f, 1.8f), tu_uniform(&r, -1.8f, 1.8f));
        sdft_vec3 d = sdft_normalize(sdft_v3(tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)));
        int la, lb;
        float a = sdft_grid_sample(g, SDFT_GRID_BOUND_FAR, &s, p, &la),
              b = sdft_grid_sample(g, SDFT_GRID_BOUND_FAR, &s, sdft_madd(p, d, step), &lb);
        if (la != 5 || lb != 5)
            continue;
        pairs++;
        if (fabsf(a - b) > 0.25f * h)
            fail_msg("far bound jumps by %g over %g at (%g, %g, %g)", fabsf(a - b), step, p.x, p.y, p.z);
    }
    assert_true(pairs > 5000);
    sdft_grid_free(g);
}

/* 1 when the eight voxels of p's trilinear cell all lie in leaves of g's
 * tree (PNanoVDB's accessor, not the leaf directory), 0 when not, -1 when
 * p lies within 1e-3 voxel of a cell face (float rounding may pick the
 * neighbour). */
static int cell_in_leaves(const sdft_grid *g, sdft_vec3 p)
{
    double x[3];
    int32_t i0[3];
    for (int k = 0; k < 3; k++) {
        x[k] = (double)g->w2i[3 * k] * p.x + (double)g->w2i[3 * k + 1] * p.y + (double)g->w2i[3 * k + 2] * p.z +
               (double)g->w2i_t[k];
        i0[k] = (int32_t)floor(x[k]);
        if (x[k] - i0[k] < 1e-3 || x[k] - i0[k] > 1.0 - 1e-3)
            return -1;
    }
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(&acc, g->root);
    for (int k = 0; k < 8; k++) {
        pnanovdb_coord_t c = {i0[0] + (k & 1), i0[1] + (k >> 1 & 1), i0[2] + (k >> 2 & 1)};
        uint32_t level;
        pnanovdb_readaccessor_get_value_address_and_level(g->type, g->buf, &acc, &c, &level);
        if (level != 0)
            return 0;
    }
    return 1;
}

/* Inside leaves the default field is the trilinear value alone, the
 * background included: where the eight voxels of a point's cell lie in
 * leaves and the trilinear value there is the background, the FAR field
 * returns that very value at level 0, without the far bound (which used
 * to raise it in empty 4^3 cells of a leaf); outside leaves the far bound
 * still raises the field. */
static void test_far_bound_is_not_asked_in_leaves(void **state)
{
    (void)state;
    sdft_scratch s;
    sdft_grid *g = spheres_grid_with_scratch(128, &s);
    const float bg = sdft_grid_background(g);
    tu_rng r = tu_rng_seed(11);
    int at_background = 0, raised = 0;
    for (int i = 0; i < 200000; i++) {
        sdft_vec3 p = sdft_v3(tu_uniform(&r, -1.8f, 1.8f), tu_uniform(&r, -1.8f, 1.8f), tu_uniform(&r, -1.8f, 1.8f));
        int tree_level, far_level;
        const float tree = sdft_grid_sample(g, SDFT_GRID_BOUND_TREE, &s, p, &tree_level);
        const float far = sdft_grid_sample(g, SDFT_GRID_BOUND_FAR, &s, p, &far_level);
        const int in_leaves = cell_in_leaves(g, p);
        if (in_leaves == 1 && fabsf(tree) >= bg) {
            at_background++;
            if (far != tree || far_level != 0)
                fail_msg("in leaves at (%g, %g, %g): FAR %g (level %d), trilinear %g", p.x, p.y, p.z, far, far_level,
                         tree);
        }
        raised += in_leaves == 0 && far_level == 5 && fabsf(far) > fabsf(tree);
    }
    assert_true(at_background > 1000);
    assert_true(raised > 1000);
    sdft_grid_free(g);
}

/* A ray from outside box b towards a random point of its middle (within
 * `spread` of the box's size of the centre), in a random direction. */
static sdft_ray ray_into(sdft_aabb b, float spread, tu_rng *r)
{
    const sdft_vec3 c = sdft_scale(sdft_add(b.lo, b.hi), 0.5f), e = sdft_sub(b.hi, b.lo);
    const float reach = 2.0f * sdft_length(e);
    sdft_vec3 dir = sdft_normalize(sdft_v3(tu_uniform(r, -1, 1), tu_uniform(r, -1, 1), tu_uniform(r, -1, 1)));
    sdft_vec3 aim = sdft_v3(c.x + tu_uniform(r, -spread, spread) * e.x, c.y + tu_uniform(r, -spread, spread) * e.y,
                            c.z + tu_uniform(r, -spread, spread) * e.z);
    return (sdft_ray){.org = sdft_madd(aim, dir, -reach), .tnear = 0.0f, .dir = dir, .tfar = 2.0f * reach};
}

/* No variant, with any bound, ever hits beyond the first sign change of the
 * grid's trilinear field along the ray, found by brute-force marching in
 * steps of a twentieth of a voxel. */
static void test_grid_trace_is_safe(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 96, 0, NULL);
    const float h = sdft_grid_voxel_size(g).x;
    sdft_field plain = sdft_grid_field(g, SDFT_GRID_BOUND_NONE);
    sdft_scratch s;
    sdft_scratch_init(&plain, &s);
    sdft_aabb b = sdft_grid_world_bounds(g);
    tu_rng r = tu_rng_seed(8);
    int hits = 0;
    for (int i = 0; i < 300; i++) {
        const sdft_ray ray = ray_into(b, 0.4f, &r);
        float t0, t1, first = INFINITY;
        if (sdft_aabb_clip(b, ray.org, ray.dir, ray.tnear, ray.tfar, &t0, &t1))
            for (float t = t0; t <= t1; t += 0.05f * h)
                if (plain.distance(plain.ctx, &s, sdft_madd(ray.org, ray.dir, t)) <= 0.0f) {
                    first = t;
                    break;
                }
        for (int bound = 0; bound < 3; bound++) {
            sdft_field gf = sdft_grid_field(g, (sdft_grid_bound)bound);
            for (int m = 0; m < SDFT_METHOD_COUNT; m++) {
                sdft_trace_params tp = sdft_trace_defaults();
                tp.method = (sdft_method)m;
                tp.omega = sdft_default_omega((sdft_method)m);
                sdft_hit hit = sdft_trace(&gf, &s, &ray, &tp);
                if (hit.status == SDFT_HIT && hit.t > first + 0.1f * h)
                    fail_msg("%s (bound %d) hits at t %g, beyond the first sign change at %g",
                             sdft_method_name(tp.method), bound, hit.t, first);
                if (isfinite(first) && hit.status == SDFT_MISS)
                    fail_msg("%s (bound %d) misses a ray that crosses the surface at t %g", sdft_method_name(tp.method),
                             bound, first);
                hits += hit.status == SDFT_HIT;
            }
        }
    }
    assert_true(hits > 300);
    sdft_grid_free(g);
}

/* ---- the exact last-cell root ---------------------------------------------------- */

/* The trilinear interpolant of v at cell-local u, in double: the truth the
 * cubic root finder is held to. */
static double trilinear_d(const float v[8], const double u[3])
{
    double f = 0.0;
    for (int k = 0; k < 8; k++)
        f += v[k] * ((k & 1) ? u[0] : 1.0 - u[0]) * ((k >> 1 & 1) ? u[1] : 1.0 - u[1]) *
             ((k >> 2 & 1) ? u[2] : 1.0 - u[2]);
    return f;
}

/* The world gradient of the interpolant of cell values v at cell-local u
 * (which may lie a little outside the cell: the cell's own polynomial), by
 * central differences in double, exact up to rounding as the interpolant
 * is linear along each axis; returns its length. */
static double interpolant_gradient(const sdft_grid *g, const float v[8], const double u[3], double world[3])
{
    double grad[3];
    for (int k = 0; k < 3; k++) {
        double a[3] = {u[0], u[1], u[2]}, b[3] = {u[0], u[1], u[2]};
        a[k] += 1e-3, b[k] -= 1e-3;
        grad[k] = (trilinear_d(v, a) - trilinear_d(v, b)) / 2e-3;
    }
    world_of_index_gradient(g, grad, world);
    return sqrt(world[0] * world[0] + world[1] * world[1] + world[2] * world[2]);
}

/* Brute force: the first s in [0, len] where f(u0 + s du) <= 0, by samples
 * 1/20000 of the way apart and bisection between the last two; -1 if none. */
static double brute_root(const float v[8], const double u0[3], const double du[3], double len)
{
    enum { SAMPLES = 20000 };
    double prev = 0.0;
    for (int i = 0; i <= SAMPLES; i++) {
        const double s = len * i / SAMPLES, u[3] = {u0[0] + s * du[0], u0[1] + s * du[1], u0[2] + s * du[2]};
        if (trilinear_d(v, u) <= 0.0) {
            if (i == 0)
                return 0.0;
            double lo = prev, hi = s;
            for (int k = 0; k < 60; k++) {
                const double mid = 0.5 * (lo + hi),
                             um[3] = {u0[0] + mid * du[0], u0[1] + mid * du[1], u0[2] + mid * du[2]};
                if (trilinear_d(v, um) <= 0.0)
                    hi = mid;
                else
                    lo = mid;
            }
            return hi;
        }
        prev = s;
    }
    return -1.0;
}

/* The distance along unit du from u inside the unit cube to its boundary
 * (backwards when sign < 0). */
static double to_boundary(const double u[3], const double du[3], double sign)
{
    double best = INFINITY;
    for (int k = 0; k < 3; k++) {
        const double d = sign * du[k];
        if (d > 0.0)
            best = fmin(best, (1.0 - u[k]) / d);
        else if (d < 0.0)
            best = fmin(best, -u[k] / d);
    }
    return best;
}

/* The solver and brute force on the ray along du (normalised here) across
 * the whole cell through q, from where it enters: the solver's answer
 * (*s when 1), brute force's root in *want (-1: none); -1 for a du too
 * short to aim with. u0 gets the entry point (cell-local). */
static int cell_root_across(const float v[8], const double q[3], double du[3], double shortest, double u0[3], double *s,
                            double *want)
{
    const double len = sqrt(du[0] * du[0] + du[1] * du[1] + du[2] * du[2]);
    if (!(len > shortest))
        return -1;
    for (int k = 0; k < 3; k++)
        du[k] /= len;
    const double back = to_boundary(q, du, -1.0), across = back + to_boundary(q, du, 1.0);
    for (int k = 0; k < 3; k++)
        u0[k] = q[k] - back * du[k];
    *want = brute_root(v, u0, du, across);
    return grid_cell_root(v, u0, du, across, s);
}

/* grid_cell_root against brute force on random cells and rays across
 * them: half aimed through a point of the surface along its tangent
 * plane (grazing, tilted by at most 3 degrees), the rest in random
 * directions. Roots agree to 1e-3 of a voxel; where brute force sees none,
 * the solver's root is a touch (the interpolant there is ~0). */
static void test_cell_root_against_brute_force(void **state)
{
    (void)state;
    tu_rng r = tu_rng_seed(21);
    int roots = 0, grazing = 0;
    for (int i = 0; i < 6000; i++) {
        float v[8];
        for (int k = 0; k < 8; k++)
            v[k] = tu_uniform(&r, -1.0f, 1.0f);
        double q[3] = {tu_uniform(&r, 0.05f, 0.95f), tu_uniform(&r, 0.05f, 0.95f), tu_uniform(&r, 0.05f, 0.95f)};
        double du[3] = {tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)};
        if (i % 2 == 0) {
            /* Move q onto the surface along a random line, then aim along
             * its tangent plane: n x (random), tilted a little along n. */
            double lo = -2.0, hi = 2.0, base[3] = {q[0], q[1], q[2]};
            double fl, fh;
            {
                const double a[3] = {base[0] + lo * du[0], base[1] + lo * du[1], base[2] + lo * du[2]},
                             b[3] = {base[0] + hi * du[0], base[1] + hi * du[1], base[2] + hi * du[2]};
                fl = trilinear_d(v, a), fh = trilinear_d(v, b);
            }
            if (fl * fh >= 0.0)
                continue;
            for (int k = 0; k < 80; k++) {
                const double mid = 0.5 * (lo + hi),
                             m[3] = {base[0] + mid * du[0], base[1] + mid * du[1], base[2] + mid * du[2]};
                if ((trilinear_d(v, m) > 0.0) == (fl > 0.0))
                    lo = mid;
                else
                    hi = mid;
            }
            for (int k = 0; k < 3; k++)
                q[k] = base[k] + lo * du[k];
            if (q[0] < 0.02 || q[0] > 0.98 || q[1] < 0.02 || q[1] > 0.98 || q[2] < 0.02 || q[2] > 0.98)
                continue;
            double n[3];
            for (int k = 0; k < 3; k++) {
                double a[3] = {q[0], q[1], q[2]}, b[3] = {q[0], q[1], q[2]};
                a[k] -= 1e-6, b[k] += 1e-6;
                n[k] = (trilinear_d(v, b) - trilinear_d(v, a)) / 2e-6;
            }
            const double w[3] = {tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)};
            const double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), tilt = tu_uniform(&r, -0.05f, 0.05f);
            double tg[3] = {n[1] * w[2] - n[2] * w[1], n[2] * w[0] - n[0] * w[2], n[0] * w[1] - n[1] * w[0]};
            const double tl = sqrt(tg[0] * tg[0] + tg[1] * tg[1] + tg[2] * tg[2]);
            if (!(tl > 1e-6) || !(nn > 1e-6))
                continue;
            for (int k = 0; k < 3; k++)
                du[k] = tg[k] / tl + tilt * n[k] / nn;
            grazing++;
        }
        double u0[3], s, want;
        const int found = cell_root_across(v, q, du, 1e-9, u0, &s, &want);
        if (found < 0)
            continue;
        if (want >= 0.0) {
            if (!found || fabs(s - want) > 1e-3)
                fail_msg("cell %d: root %s%g, brute force %g", i, found ? "" : "none, ", found ? s : 0.0, want);
            roots++;
        } else if (found) {
            const double u[3] = {u0[0] + s * du[0], u0[1] + s * du[1], u0[2] + s * du[2]};
            if (fabs(trilinear_d(v, u)) > 1e-6)
                fail_msg("cell %d: root at %g where brute force sees none, f = %g", i, s, trilinear_d(v, u));
        }
    }
    print_message("%d cells with a root, %d rays grazing\n", roots, grazing);
    assert_true(roots > 2000);
    assert_true(grazing > 500);
}

/* Cells whose values are a plane's, to within eta (0 to 1e-6): the
 * interpolant along a ray is a line plus at most eta, so the solver may
 * take the chord's root (grid_root.c) where that is provably within
 * 2^-30 of the segment, and must step on where it is not. Roots agree
 * with brute force to 1e-9 of a voxel. */
static void test_cell_root_on_near_planar_cells(void **state)
{
    (void)state;
    tu_rng r = tu_rng_seed(23);
    static const double etas[4] = {0.0, 1e-12, 1e-9, 1e-6};
    int roots = 0;
    for (int i = 0; i < 4000; i++) {
        const double eta = etas[i % 4];
        const double n[3] = {tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)};
        const double q[3] = {tu_uniform(&r, 0.1f, 0.9f), tu_uniform(&r, 0.1f, 0.9f), tu_uniform(&r, 0.1f, 0.9f)};
        float v[8];
        for (int k = 0; k < 8; k++) { /* the plane through q with normal n, plus up to eta */
            const double c[3] = {k & 1, k >> 1 & 1, k >> 2 & 1};
            v[k] = (float)(n[0] * (c[0] - q[0]) + n[1] * (c[1] - q[1]) + n[2] * (c[2] - q[2]) +
                           eta * tu_uniform(&r, -1, 1));
        }
        double du[3] = {tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)};
        double u0[3], s, want;
        const int found = cell_root_across(v, q, du, 1e-3, u0, &s, &want);
        if (found < 0)
            continue;
        if (want > 0.0) {
            if (!found || fabs(s - want) > 1e-9)
                fail_msg("cell %d (eta %g): root %s%.12g, brute force %.12g", i, eta, found ? "" : "none, ",
                         found ? s : 0.0, want);
            roots++;
        }
    }
    print_message("%d near-planar cells with a root\n", roots);
    assert_true(roots > 1000);
}

/* A grid's ray hits the first root of its interpolant exactly: the
 * interpolant, in double from the stored voxels, changes sign within 1e-3
 * of a voxel around the hit (or touches 0 there), and is positive on a
 * fine sampling of the two voxels before it; and the hit's normal is the
 * interpolant's gradient there, in the cell the ray reaches it from
 * (central differences in double, taken to world space), where the hit
 * is an exact root, and none where it is not. */
static double grid_interpolant(const sdft_grid *g, sdft_vec3 p)
{
    int32_t i0[3];
    double u[3];
    float v[8];
    cell_at(g, p, i0, u, v);
    return trilinear_d(v, u);
}

static void test_exact_root_on_a_grid(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 96, 0, NULL);
    const float h = sdft_grid_voxel_size(g).x;
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    assert_non_null(gf.accel->root);
    sdft_scratch s;
    sdft_scratch_init(&gf, &s);
    tu_rng r = tu_rng_seed(22);
    int hits = 0, exact = 0;
    for (int i = 0; i < 400; i++) {
        const sdft_ray ray = ray_into(sdft_grid_world_bounds(g), 0.3f, &r);
        for (int m = 0; m < SDFT_METHOD_COUNT; m++) {
            sdft_trace_params tp = sdft_trace_defaults();
            tp.method = (sdft_method)m;
            tp.omega = sdft_default_omega((sdft_method)m);
            sdft_hit hit = sdft_trace(&gf, &s, &ray, &tp);
            if (hit.status != SDFT_HIT)
                continue;
            hits++;
            if (hit.distance != 0.0f) { /* the root walk gave up (none within its cells): refined as before */
                assert_true(hit.normal.x == 0.0f && hit.normal.y == 0.0f && hit.normal.z == 0.0f);
                continue;
            }
            exact++;
            int32_t i0[3];
            double u[3], x[3], world[3];
            float v[8];
            cell_at(g, sdft_madd(ray.org, ray.dir, hit.t - 1e-3f * h), i0, u, v);
            index_point(g, sdft_madd(ray.org, ray.dir, hit.t), x);
            for (int k = 0; k < 3; k++) /* the hit's coordinates in that cell */
                u[k] = x[k] - i0[k];
            const double len = interpolant_gradient(g, v, u, world);
            const double cosine = (hit.normal.x * world[0] + hit.normal.y * world[1] + hit.normal.z * world[2]) / len;
            if (!(cosine > 0.9999 && fabsf(sdft_length(hit.normal) - 1.0f) < 1e-5f))
                fail_msg("%s: ray %d, normal (%g, %g, %g) at its exact hit, the interpolant's gradient (%g, %g, %g)",
                         sdft_method_name(tp.method), i, hit.normal.x, hit.normal.y, hit.normal.z, world[0] / len,
                         world[1] / len, world[2] / len);
            const double before = grid_interpolant(g, sdft_madd(ray.org, ray.dir, hit.t - 1e-3f * h));
            const double after = grid_interpolant(g, sdft_madd(ray.org, ray.dir, hit.t + 1e-3f * h));
            const double at = grid_interpolant(g, sdft_madd(ray.org, ray.dir, hit.t));
            if (!(before > 0.0 && after <= 0.0) && !(fabs(at) < 1e-4 * h))
                fail_msg("%s: ray %d hits at %g, interpolant %g / %g / %g around it", sdft_method_name(tp.method), i,
                         hit.t, before, at, after);
            for (int k = 1; k <= 200; k++) {
                const float t = hit.t - 1e-3f * h - 2.0f * h * (float)k / 200.0f;
                if (grid_interpolant(g, sdft_madd(ray.org, ray.dir, t)) <= 0.0)
                    fail_msg("%s: ray %d hits at %g, beyond an earlier root near %g", sdft_method_name(tp.method), i,
                             hit.t, t);
            }
        }
    }
    print_message("%d hits, %d of them exact roots\n", hits, exact);
    assert_true(exact > 300);
    assert_true(exact > hits * 9 / 10);
    sdft_grid_free(g);
}

/* A ray that passes within eps of a grid's surface without meeting it:
 * stepping to eps calls it a hit (the papers' rule), the exact root does
 * not, having walked the cells to the ray's end, and brute-force sampling
 * of the interpolant finds no root on it; a ray that does cross the
 * surface hits at the root either way. Rays passing the spheres' largest
 * at 0.2 to 1.6 voxels from it, and a few through it, with eps two voxels, so that the march
 * lands within eps before the exact root is due (on the interpolant alone,
 * whose values outside the band are the background's three voxels). */
static void test_exact_root_passes_a_near_miss(void **state)
{
    (void)state;
    sdft_scratch s;
    sdft_grid *g = spheres_grid_with_scratch(48, &s);
    const sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_NONE); /* the interpolant alone: the far bound's values
                                                                     * can be below two voxels */
    sdft_scratch_init(&gf, &s);
    const float h = sdft_grid_voxel_size(g).x;
    int passed = 0, papers_hit = 0, crossed = 0;
    for (int i = 0; i < 40; i++) {
        /* Towards -x, at height y above the sphere of radius 0.6 round the
         * origin, in the plane z = -0.2 (clear of the other spheres). */
        const float z = -0.2f, miss = (i < 35 ? 0.2f + 0.04f * (float)i : -0.5f - 0.1f * (float)(i - 35)) * h;
        const float y = sqrtf((0.6f + miss) * (0.6f + miss) - z * z);
        const sdft_ray ray = {.org = {1.3f, y, z}, .tnear = 0.0f, .dir = {-1.0f, 0.0f, 0.0f}, .tfar = 1.3f};
        sdft_trace_params tp = sdft_trace_defaults();
        tp.eps = 2.0f * h;
        const sdft_hit exact = sdft_trace(&gf, &s, &ray, &tp);
        tp.exact_root = 0;
        const sdft_hit stepped = sdft_trace(&gf, &s, &ray, &tp);
        float root = INFINITY;
        for (float t = 0.0f; t <= ray.tfar && root == INFINITY; t += 0.01f * h)
            if (grid_interpolant(g, sdft_madd(ray.org, ray.dir, t)) <= 0.0)
                root = t;
        if (root == INFINITY) {
            if (exact.status != SDFT_MISS)
                fail_msg("ray %d passes %g voxels from the sphere: status %d at t = %g with the exact root", i,
                         miss / h, exact.status, exact.t);
            passed++;
            papers_hit += stepped.status == SDFT_HIT;
        } else {
            assert_int_equal(exact.status, SDFT_HIT);
            assert_true(fabsf(exact.t - root) <= 0.02f * h);
            crossed++;
        }
    }
    print_message("%d rays pass the sphere by (%d of them hits when stepping to eps), %d cross it\n", passed,
                  papers_hit, crossed);
    assert_true(passed >= 30 && papers_hit >= 20 && crossed >= 3);
    sdft_grid_free(g);
}

/* ---- normals ---------------------------------------------------------------------- */

/* A grid's normal is the gradient of the interpolant it traces, in the cell
 * holding the point (OpenVDB's BoxStencil gradient), taken to world space by
 * the transform: held to central differences of that interpolant in double,
 * read voxel by voxel (exact up to rounding, as the interpolant is linear
 * along each axis), on points of cells the surface crosses. */
static void test_normal_is_the_interpolant_gradient(void **state)
{
    (void)state;
    sdft_scratch s;
    sdft_grid *g = spheres_grid_with_scratch(48, &s);
    const sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    tu_rng r = tu_rng_seed(31);
    int checked = 0;
    double worst = 1.0;
    for (int i = 0; i < 20000; i++) {
        const sdft_vec3 p =
            sdft_v3(tu_uniform(&r, -1.1f, 1.1f), tu_uniform(&r, -1.1f, 1.1f), tu_uniform(&r, -1.1f, 1.1f));
        int32_t i0[3];
        double u[3];
        float v[8];
        cell_at(g, p, i0, u, v);
        int inside = 1, negative = 0;
        for (int k = 0; k < 3; k++) /* clear of the cell's faces, where float rounding could cross */
            inside &= u[k] > 0.01 && u[k] < 0.99;
        for (int k = 0; k < 8; k++)
            negative += v[k] < 0.0f;
        if (!inside || negative == 0 || negative == 8)
            continue;
        double world[3];
        const double len = interpolant_gradient(g, v, u, world);
        const sdft_vec3 n = sdft_field_normal(&gf, &s, p);
        const double cosine = (n.x * world[0] + n.y * world[1] + n.z * world[2]) / len;
        worst = fmin(worst, cosine);
        if (!(cosine > 0.99999))
            fail_msg("normal (%g, %g, %g) at (%g, %g, %g), the interpolant's gradient (%g, %g, %g)", n.x, n.y, n.z, p.x,
                     p.y, p.z, world[0] / len, world[1] / len, world[2] / len);
        checked++;
    }
    print_message("%d normals in cells the surface crosses, worst cosine %.8f\n", checked, worst);
    assert_true(checked > 500);
    sdft_grid_free(g);
}

/* ---- a grid renders like its scene ------------------------------------------------ */

static void test_grid_render_matches_procedural(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 256, 0, NULL);
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    const float h = sdft_grid_voxel_size(g).x;

    sdft_render_params rp = sdft_render_defaults();
    rp.width = 240, rp.height = 135;
    rp.camera = sc->camera;
    rp.light = sc->light;
    rp.shadows = 0;
    char msg[256];
    sdft_image a, b;
    assert_int_equal(sdft_image_alloc(&a, rp.width, rp.height, NULL, 0), 0);
    assert_int_equal(sdft_image_alloc(&b, rp.width, rp.height, NULL, 0), 0);
    assert_int_equal(sdft_render(&sc->field, &rp, &a, NULL, msg, sizeof msg), 0);
    assert_int_equal(sdft_render(&gf, &rp, &b, NULL, msg, sizeof msg), 0);
    int both = 0, close = 0, one = 0, n = rp.width * rp.height;
    for (int i = 0; i < n; i++) {
        int ha = a.status[i] == SDFT_HIT, hb = b.status[i] == SDFT_HIT;
        if (ha && hb) {
            both++;
            close += fabsf(a.depth[i] - b.depth[i]) <= 1.5f * h;
        } else if (ha != hb) {
            one++;
        }
    }
    print_message("grid vs procedural: %d of %d both-hit pixels within 1.5 voxels, %d hit in one only\n", close, both,
                  one);
    assert_true(both > n / 20);
    assert_true(close >= 0.99 * both);
    assert_true(one <= 0.005 * n);
    sdft_image_free(&a);
    sdft_image_free(&b);
    sdft_grid_free(g);
}

/* ---- the hull ---------------------------------------------------------------------- */

/* p in hull box i and, where the field gives slabs, in slab i. */
static int in_hull_part(const sdft_field *f, size_t i, sdft_vec3 p)
{
    const sdft_aabb b = f->accel->hull[i];
    if (!(p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y && p.y <= b.hi.y && p.z >= b.lo.z && p.z <= b.hi.z))
        return 0;
    if (!f->accel->hull_slabs)
        return 1;
    const sdft_slab sl = f->accel->hull_slabs[i];
    const float d = sdft_dot(sl.n, p);
    return d >= sl.lo && d <= sl.hi;
}

/* The least of d . g over g in hull box i's gradient bounds: > 0 when a
 * ray along d rises wherever it crosses the box's cells. */
static float least_slope(const sdft_field *f, size_t i, sdft_vec3 d)
{
    const sdft_aabb gb = f->accel->hull_gradients[i];
    return fminf(d.x * gb.lo.x, d.x * gb.hi.x) + fminf(d.y * gb.lo.y, d.y * gb.hi.y) +
           fminf(d.z * gb.lo.z, d.z * gb.hi.z);
}

/* p in a part of the hull (box and slab) where a ray along d may first
 * reach 0: one whose gradient bounds do not rise along d. */
static int in_hull(const sdft_field *f, sdft_vec3 p, sdft_vec3 d)
{
    for (size_t i = 0; i < f->accel->hull_count; i++)
        if (in_hull_part(f, i, p) && !(least_slope(f, i, d) > 0.0f))
            return 1;
    return 0;
}

/* World gradient g (index gradient x through the grid's transform: W^T x)
 * in hull box i's gradient bounds, to a millionth of their size. */
static int in_gradient_bounds(const sdft_grid *g, const sdft_field *f, size_t i, const double x[3])
{
    const sdft_aabb gb = f->accel->hull_gradients[i];
    const float lo[3] = {gb.lo.x, gb.lo.y, gb.lo.z}, hi[3] = {gb.hi.x, gb.hi.y, gb.hi.z};
    double w[3];
    world_of_index_gradient(g, x, w);
    for (int k = 0; k < 3; k++) {
        const double slack = 1e-6 * (fabs(lo[k]) + fabs(hi[k]));
        if (!(w[k] >= lo[k] - slack && w[k] <= hi[k] + slack))
            return 0;
    }
    return 1;
}

/* Cells with corners of both signs, at random in g's active box: all
 * eight corners of each lie in one box of the hull and its slab, and the
 * box's gradient bounds hold every gradient of the cell's interpolant
 * (along each index axis the derivative lies between the least and the
 * greatest of that axis's four edge differences, so every gradient lies in
 * their box, whose eight corners, taken to world space, must lie in the
 * bounds). The slabs' mean thickness, in voxels; *narrow: the share of
 * boxes whose gradient bounds leave out 0 (those a view can drop). */
static double mixed_cells_in_hull(const sdft_grid *g, const sdft_field *f, int tries, int *mixed, double *narrow)
{
    int32_t lo[3], hi[3];
    sdft_grid_index_bounds(g, lo, hi);
    tu_rng r = tu_rng_seed(43);
    *mixed = 0;
    for (int i = 0; i < tries; i++) {
        int32_t c[3];
        for (int k = 0; k < 3; k++)
            c[k] = lo[k] + (int32_t)(tu_uniform(&r, 0.0f, 0.999f) * (float)(hi[k] - lo[k]));
        float v[8];
        cell_corners(g, c, v);
        int neg = 0;
        for (int k = 0; k < 8; k++)
            neg += v[k] <= 0.0f;
        if (neg == 0 || neg == 8)
            continue;
        (*mixed)++;
        sdft_vec3 w[8];
        for (int k = 0; k < 8; k++) {
            const float x[3] = {(float)(c[0] + (k & 1)), (float)(c[1] + (k >> 1 & 1)), (float)(c[2] + (k >> 2 & 1))};
            w[k] = grid_index_to_world(g, x);
        }
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int k = 0; k < 8; k++)
            for (int a = 0; a < 3; a++) {
                const int step = 1 << a;
                if (k & step)
                    continue;
                const double e = (double)v[k + step] - (double)v[k];
                lo[a] = fmin(lo[a], e), hi[a] = fmax(hi[a], e);
            }
        int held = 0;
        for (size_t b = 0; b < f->accel->hull_count && !held; b++) {
            held = 1;
            for (int k = 0; k < 8 && held; k++)
                held = in_hull_part(f, b, w[k]);
            for (int k = 0; k < 8 && held; k++) {
                const double x[3] = {k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]};
                held = in_gradient_bounds(g, f, b, x);
            }
        }
        if (!held)
            fail_msg("mixed cell (%d, %d, %d) lies in no hull box and its slab with its gradients", c[0], c[1], c[2]);
    }
    size_t without_zero = 0;
    for (size_t b = 0; b < f->accel->hull_count; b++) {
        const sdft_aabb gb = f->accel->hull_gradients[b];
        without_zero +=
            gb.lo.x > 0.0f || gb.hi.x < 0.0f || gb.lo.y > 0.0f || gb.hi.y < 0.0f || gb.lo.z > 0.0f || gb.hi.z < 0.0f;
    }
    *narrow = (double)without_zero / (double)f->accel->hull_count;
    double thick = 0.0;
    size_t slabs = 0;
    const float h = sdft_grid_voxel_size(g).x;
    for (size_t b = 0; b < f->accel->hull_count; b++) {
        const sdft_slab sl = f->accel->hull_slabs[b];
        const float n = sdft_length(sl.n);
        if (n > 0.0f && isfinite(sl.hi - sl.lo))
            thick += (sl.hi - sl.lo) / n / h, slabs++;
    }
    return slabs ? thick / (double)slabs : INFINITY;
}

/* A slab 0.6 thick, much wider than its box, which cuts it on four sides:
 * the grid holds values <= 0 (leaves and tiles) against the background
 * outside. */
static float cut_slab_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    return sdft_sd_box(p, sdft_v3(2.0f, 0.3f, 2.0f));
}

/* Every ray's first root of the interpolant, found by brute-force marching
 * in steps of a twentieth of a voxel from where the ray enters the grid's
 * box, lies in a box of the grid's hull: on the figure, whose hull is a
 * thin shell, not the box, and on a slab its box cuts, where the first
 * roots of rays entering through the cut faces are their entry points. */
static void test_hull_holds_every_first_root(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    const sdft_field slab = {.distance = cut_slab_distance, .bounds = {{-0.5f, -0.4f, -0.5f}, {0.5f, 0.4f, 0.5f}}};
    sdft_grid *grids[2] = {bake(&sc->field, 96, 0, NULL), bake(&slab, 128, 0, NULL)};
    for (int gi = 0; gi < 2; gi++) {
        sdft_grid *g = grids[gi];
        const float h = sdft_grid_voxel_size(g).x;
        const sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
        assert_true(gf.accel->hull_count > 100);
        const sdft_aabb bounds = sdft_grid_world_bounds(g);
        double hull_volume = 0.0;
        for (size_t i = 0; i < gf.accel->hull_count; i++) {
            const sdft_vec3 e = sdft_sub(gf.accel->hull[i].hi, gf.accel->hull[i].lo);
            hull_volume += (double)e.x * e.y * e.z;
        }
        const sdft_vec3 be = sdft_sub(bounds.hi, bounds.lo);
        print_message("%s: %zu hull boxes, %.1f%% of the box's volume\n", gi ? "cut slab" : "figure",
                      gf.accel->hull_count, 100.0 * hull_volume / ((double)be.x * be.y * be.z));
        if (gi == 0) {
            assert_true(hull_volume < 0.25 * (double)be.x * be.y * be.z);
            assert_non_null(gf.accel->hull_slabs);
            assert_non_null(gf.accel->hull_gradients);
            int mixed;
            double narrow;
            const double thick = mixed_cells_in_hull(g, &gf, 200000, &mixed, &narrow);
            print_message("%d mixed cells, each in a hull box and its slab with its gradients; slabs %.2f voxels "
                          "thick on average; %.1f%% of the gradient bounds leave out 0\n",
                          mixed, thick, 100.0 * narrow);
            assert_true(mixed > 1000);
            assert_true(thick < 5.0);
            assert_true(narrow > 0.3); /* a coarse grid: leaves of 8 voxels hold much of its curvature */
        }
        sdft_scratch s;
        sdft_scratch_init(&gf, &s);
        tu_rng r = tu_rng_seed(41);
        int roots = 0, at_entry = 0;
        for (int i = 0; i < 600; i++) {
            const sdft_ray ray = ray_into(bounds, 0.4f, &r);
            float t0, t1;
            if (!sdft_aabb_clip(bounds, ray.org, ray.dir, 0.0f, ray.tfar, &t0, &t1))
                continue;
            for (float t = t0; t <= t1; t += 0.05f * h) {
                const sdft_vec3 p = sdft_madd(ray.org, ray.dir, t);
                if (sdft_grid_sample(g, SDFT_GRID_BOUND_NONE, &s, p, NULL) <= 0.0f) {
                    if (!in_hull(&gf, p, ray.dir))
                        fail_msg("ray %d: first root near t = %g, (%g, %g, %g), in no hull box that may hold it", i, t,
                                 p.x, p.y, p.z);
                    roots++;
                    at_entry += t == t0;
                    break;
                }
            }
        }
        print_message("%d first roots (%d where the ray enters the box), all in the hull\n", roots, at_entry);
        assert_true(roots > 200);
        if (gi == 1)
            assert_true(at_entry > 50);
        sdft_grid_free(g);
    }
}

/* The default render starts each primary ray at the hull: the same image
 * as with every ray from the eye (cones off), exact roots included, for
 * fewer evaluations, and the same as with every box of the hull (its far
 * side's too, which the gradient bounds leave out); with the eye inside the surface, where the hull
 * promises nothing, the same image too (every ray hits at the eye); and
 * through a lens so narrow that every box projects billions of pixels off
 * the image, nothing hit and nothing written outside the tiles' bins. */
static void test_render_from_the_hull(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 128, 0, NULL);
    sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    const float h = sdft_grid_voxel_size(g).x;
    sdft_render_params rp = sdft_render_defaults();
    rp.width = 160, rp.height = 90;
    rp.camera = sc->camera;
    rp.shadows = 0, rp.depth_only = 1;
    for (int view = 0; view < 3; view++) {
        const int inside = view == 1;
        if (view == 2) { /* 80 degrees to the left through a 1e-5-degree lens: every box in front, billions of
                          * pixels to the right of the image */
            const sdft_vec3 d = sdft_normalize(sdft_sub(sc->camera.at, sc->camera.from));
            const sdft_vec3 left = sdft_normalize(sdft_cross(sc->camera.up, d));
            rp.camera = sc->camera, rp.camera.fov_deg = 1e-5f;
            rp.camera.at = sdft_add(rp.camera.from, sdft_add(sdft_scale(d, 0.17f), sdft_scale(left, 0.98f)));
        }
        if (inside) { /* a point of the figure's interior, found by the field itself */
            sdft_scratch s;
            sdft_scratch_init(&gf, &s);
            tu_rng r = tu_rng_seed(43);
            sdft_vec3 p;
            do
                p = sdft_v3(tu_uniform(&r, gf.bounds.lo.x, gf.bounds.hi.x),
                            tu_uniform(&r, gf.bounds.lo.y, gf.bounds.hi.y),
                            tu_uniform(&r, gf.bounds.lo.z, gf.bounds.hi.z));
            while (!(sdft_field_distance(&gf, &s, p) < -2.0f * h));
            rp.camera.from = p;
        }
        sdft_image a, b;
        sdft_render_stats sa, sb;
        char msg[256];
        assert_int_equal(sdft_image_alloc(&a, rp.width, rp.height, NULL, 0), 0);
        assert_int_equal(sdft_image_alloc(&b, rp.width, rp.height, NULL, 0), 0);
        assert_int_equal(sdft_render(&gf, &rp, &a, &sa, msg, sizeof msg), 0);
        sdft_render_params off = rp;
        off.cones = 0;
        assert_int_equal(sdft_render(&gf, &off, &b, &sb, msg, sizeof msg), 0);
        int n = rp.width * rp.height, hits = 0, same = 0, differ = 0;
        for (int i = 0; i < n; i++) {
            if ((a.status[i] == SDFT_HIT) != (b.status[i] == SDFT_HIT)) {
                differ++;
                continue;
            }
            if (a.status[i] != SDFT_HIT)
                continue;
            hits++;
            same += fabsf(a.depth[i] - b.depth[i]) <= 1e-3f * h;
        }
        print_message("%s: %d hits, %d at the same depth, %d hit in one only; evaluations %llu against %llu\n",
                      view == 0   ? "eye outside"
                      : view == 1 ? "eye inside"
                                  : "looking aside",
                      hits, same, differ, (unsigned long long)(sa.steps + sa.cone_steps), (unsigned long long)sb.steps);
        assert_true(view == 2 ? hits == 0 : hits > n / (inside ? 1 : 10) - 1);
        assert_true(same >= 0.995 * hits);
        assert_true(differ <= n / 1000);
        if (view == 0) {
            assert_true(2 * (sa.steps + sa.cone_steps) < sb.steps);
            /* Without the gradient bounds every box of the hull counts, the
             * far side's too: the same image, no fewer evaluations. */
            sdft_field all_boxes = gf;
            sdft_field_accel no_gradients = *gf.accel;
            no_gradients.hull_gradients = NULL;
            all_boxes.accel = &no_gradients;
            assert_int_equal(sdft_render(&all_boxes, &rp, &b, &sb, msg, sizeof msg), 0);
            int changed = 0;
            for (int i = 0; i < n; i++)
                changed += a.status[i] != b.status[i] || (a.status[i] == SDFT_HIT && a.depth[i] != b.depth[i]);
            print_message("without the gradient bounds: %d pixels differ; evaluations %llu against %llu\n", changed,
                          (unsigned long long)sb.steps, (unsigned long long)sa.steps);
            assert_int_equal(changed, 0);
            assert_true(sa.steps <= sb.steps);
        }
        sdft_image_free(&a);
        sdft_image_free(&b);
    }
    sdft_grid_free(g);
}

/* The points sdft_render hinted at (sdft_field_accel.prefetch), one thread. */
enum { MOST_HINTS = 1 << 16 };
static sdft_vec3 hints[MOST_HINTS];
static int hint_count;

static void record_hint(const void *ctx, sdft_vec3 p)
{
    (void)ctx;
    if (hint_count < MOST_HINTS)
        hints[hint_count] = p;
    hint_count++;
}

/* The distance from p to the nearest face of a hull box's part (the box
 * and its slab) that holds it (INFINITY when none does). */
static float hull_face_distance(const sdft_field *f, sdft_vec3 p)
{
    float best = INFINITY;
    for (size_t i = 0; i < f->accel->hull_count; i++) {
        const sdft_aabb b = f->accel->hull[i];
        const sdft_vec3 in = sdft_min_v(sdft_sub(p, b.lo), sdft_sub(b.hi, p));
        float depth = sdft_minf(in.x, sdft_minf(in.y, in.z));
        if (f->accel->hull_slabs && sdft_length(f->accel->hull_slabs[i].n) > 0.0f) {
            const sdft_slab sl = f->accel->hull_slabs[i];
            const float d = sdft_dot(sl.n, p), n = sdft_length(sl.n);
            depth = sdft_minf(depth, sdft_minf(d - sl.lo, sl.hi - d) / n);
        }
        if (depth >= -1e-5f)
            best = sdft_minf(best, fabsf(depth));
    }
    return best;
}

/* With the hull, the render hints the field at each traced ray's entry
 * into it: every hit pixel's ray has a hinted point on it, on a hull box's
 * face, before its hit; and the image is the one rendered without hints. */
static void test_render_hints_hull_entries(void **state)
{
    (void)state;
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *g = bake(&sc->field, 128, 0, NULL);
    const sdft_field gf = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
    sdft_field hinted = gf, plain = gf;
    sdft_field_accel hinting = *gf.accel, silent = *gf.accel;
    hinting.prefetch = record_hint, silent.prefetch = NULL;
    hinted.accel = &hinting, plain.accel = &silent;
    const float h = sdft_grid_voxel_size(g).x;
    sdft_render_params rp = sdft_render_defaults();
    rp.width = 96, rp.height = 54, rp.threads = 1;
    rp.camera = sc->camera;
    rp.shadows = 0;
    sdft_image a, b;
    char msg[256];
    assert_int_equal(sdft_image_alloc(&a, rp.width, rp.height, NULL, 0), 0);
    assert_int_equal(sdft_image_alloc(&b, rp.width, rp.height, NULL, 0), 0);
    hint_count = 0;
    assert_int_equal(sdft_render(&hinted, &rp, &a, NULL, msg, sizeof msg), 0);
    assert_int_equal(sdft_render(&plain, &rp, &b, NULL, msg, sizeof msg), 0);
    assert_true(hint_count > 0 && hint_count <= MOST_HINTS);
    const int n = rp.width * rp.height;
    assert_memory_equal(a.rgb, b.rgb, 3 * (size_t)n * sizeof *a.rgb);
    assert_memory_equal(a.depth, b.depth, (size_t)n * sizeof *a.depth);
    int hits = 0;
    for (int i = 0; i < n; i++) {
        if (a.status[i] != SDFT_HIT)
            continue;
        hits++;
        const sdft_ray ray = sdft_camera_ray(&rp.camera, rp.width, rp.height, (float)(i % rp.width) + 0.5f,
                                             (float)(i / rp.width) + 0.5f);
        int found = 0;
        for (int k = 0; k < hint_count && !found; k++) {
            const sdft_vec3 q = sdft_sub(hints[k], ray.org);
            const float t = sdft_dot(q, ray.dir);
            found = sdft_length(sdft_cross(q, ray.dir)) <= 1e-4f * h && t <= a.depth[i] &&
                    hull_face_distance(&gf, hints[k]) <= 1e-3f * h;
        }
        if (!found)
            fail_msg("pixel %d: no hint at its ray's entry into the hull", i);
    }
    print_message("%d hints, %d hit pixels, each hinted at its entry\n", hint_count, hits);
    assert_true(hits > n / 10);
    assert_true(hint_count < 2 * n);
    sdft_image_free(&a);
    sdft_image_free(&b);
    sdft_grid_free(g);
}

/* The batch call (sdft_field_distances) on a grid: every point is hinted
 * before its evaluation, in order; the values are the ones sdft_field_distance
 * gives one call at a time, bit for bit (NaN and far points included), and
 * without the bound they are the trilinear interpolant of the stored voxels
 * (brute force through the public accessor). On a field without hints, the
 * analytic distances. */
static sdft_field batch_inner;
static size_t batch_evaluated, batch_hinted_then[1100];

static float batch_logging_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    if (batch_evaluated < 1100)
        batch_hinted_then[batch_evaluated] = (size_t)hint_count;
    batch_evaluated++;
    return batch_inner.distance(ctx, s, p);
}

static void test_field_distances_batch(void **state)
{
    (void)state;
    sdft_scratch s;
    sdft_grid *g = spheres_grid_with_scratch(48, &s);
    enum { N = 1100 };
    static sdft_vec3 p[N];
    static float batch[N], one[N];
    tu_rng r = tu_rng_seed(31);
    for (int i = 0; i < N; i++) /* the box and beyond it */
        p[i] = sdft_v3(tu_uniform(&r, -1.6f, 1.6f), tu_uniform(&r, -1.6f, 1.6f), tu_uniform(&r, -1.6f, 1.6f));
    p[7] = sdft_v3(NAN, 0.0f, 0.0f), p[8] = sdft_v3(1e30f, -1e30f, 0.0f);
    static const size_t counts[] = {0, 1, SDFT_FIELD_DISTANCES_AHEAD, SDFT_FIELD_DISTANCES_AHEAD + 1, N};
    for (int bound = 0; bound < 2; bound++) {
        const sdft_field gf =
            bound ? sdft_grid_field(g, SDFT_GRID_BOUND_FAR) : sdft_grid_field(g, SDFT_GRID_BOUND_NONE);
        assert_non_null(gf.accel->prefetch);
        sdft_field logged = gf;
        sdft_field_accel hinting = *gf.accel;
        hinting.prefetch = record_hint;
        batch_inner = gf;
        logged.distance = batch_logging_distance, logged.accel = &hinting;
        for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++) {
            const size_t n = counts[c];
            hint_count = 0, batch_evaluated = 0;
            memset(batch, 0xff, sizeof batch);
            sdft_field_distances(&logged, &s, p, n, batch);
            assert_int_equal(batch_evaluated, n);
            assert_int_equal(hint_count, n);
            for (size_t i = 0; i < n; i++) {
                assert_memory_equal(&hints[i], &p[i], sizeof p[i]);
                assert_true(batch_hinted_then[i] > i); /* p[i] hinted before its evaluation */
                one[i] = sdft_field_distance(&gf, &s, p[i]);
            }
            assert_memory_equal(batch, one, n * sizeof *batch);
            if (c == 4 || bound)
                continue;
            int inside = 0;
            for (size_t i = 0; i < n; i++) {
                int32_t i0[3];
                double u[3];
                float v[8];
                if (!(fabsf(p[i].x) <= 1.1f && fabsf(p[i].y) <= 1.1f && fabsf(p[i].z) <= 1.1f))
                    continue;
                cell_at(g, p[i], i0, u, v);
                const double x00 = v[0] + (v[1] - v[0]) * u[0], x10 = v[2] + (v[3] - v[2]) * u[0];
                const double x01 = v[4] + (v[5] - v[4]) * u[0], x11 = v[6] + (v[7] - v[6]) * u[0];
                const double y0 = x00 + (x10 - x00) * u[1], y1 = x01 + (x11 - x01) * u[1];
                assert_float_equal(batch[i], y0 + (y1 - y0) * u[2], 2e-6);
                inside++;
            }
            assert_true(n < 100 || inside > (int)n / 4);
        }
    }
    /* A field without hints: the analytic distance of the union of spheres. */
    const sdft_field sf = spheres_field();
    sdft_field_distances(&sf, &s, p, N, batch);
    for (int i = 9; i < N; i++) {
        double d = INFINITY;
        for (int k = 0; k < 4; k++) {
            const double dx = p[i].x - spheres[k][0], dy = p[i].y - spheres[k][1], dz = p[i].z - spheres[k][2];
            d = fmin(d, sqrt(dx * dx + dy * dy + dz * dz) - spheres[k][3]);
        }
        assert_float_equal(batch[i], d, 1e-5);
    }
    sdft_grid_free(g);
}

/* ---- round trips ------------------------------------------------------------------- */

static void same_voxels(const sdft_grid *a, const sdft_grid *b)
{
    int32_t lo[3], hi[3], lo2[3], hi2[3];
    sdft_grid_index_bounds(a, lo, hi);
    sdft_grid_index_bounds(b, lo2, hi2);
    assert_memory_equal(lo, lo2, sizeof lo);
    assert_memory_equal(hi, hi2, sizeof hi);
    assert_int_equal(sdft_grid_active_voxels(a), sdft_grid_active_voxels(b));
    assert_true(sdft_grid_background(a) == sdft_grid_background(b));
    for (int32_t k = lo[2] - 2; k <= hi[2] + 2; k++)
        for (int32_t j = lo[1] - 2; j <= hi[1] + 2; j++)
            for (int32_t i = lo[0] - 2; i <= hi[0] + 2; i++) {
                int aa, ab;
                float va = sdft_grid_voxel(a, i, j, k, &aa), vb = sdft_grid_voxel(b, i, j, k, &ab);
                if (va != vb || aa != ab)
                    fail_msg("voxel (%d, %d, %d): %g/%d in memory, %g/%d from the file", i, j, k, va, aa, vb, ab);
            }
}

static void round_trip(const char *file)
{
    char path[512], msg[256];
    tu_tmp(path, sizeof path, file);
    remove(path);
    sdft_field f = spheres_field();
    sdft_grid *mem = bake(&f, 40, 0, path);
    assert_true(tu_file_exists(path));
    sdft_grid *disk = NULL;
    int rc = tu_open_file(path, NULL, SDFT_QUANT_NONE, &disk, msg, sizeof msg);
    if (rc)
        print_error("%s\n", msg);
    assert_int_equal(rc, 0);
    assert_string_equal(sdft_grid_name(disk), "sdf");
    assert_true(sdft_grid_is_level_set(disk));
    same_voxels(mem, disk);
    sdft_grid_free(mem);
    sdft_grid_free(disk);
}

/* The figure baked at res^3 into the .vdb at `name` (a temporary path in
 * path), then opened twice with quant: g[0] with options `first`, g[1]
 * with `second`. */
static void open_figure_twice(const char *name, int res, sdft_quant quant, sdft_grid_options first,
                              sdft_grid_options second, char *path, size_t path_len, sdft_grid *g[2])
{
    char msg[256];
    tu_tmp(path, path_len, name);
    if (!tu_file_exists(path)) {
        const sdft_scene *sc = sdft_scene_find("figure");
        assert_non_null(sc);
        sdft_grid_free(bake(&sc->field, res, 0, path));
    }
    const sdft_grid_options o[2] = {first, second};
    for (int k = 0; k < 2; k++) {
        sdft_grid_options ok = o[k];
        ok.quant = quant;
        const int rc = tu_open_with(path, NULL, &ok, &g[k], msg, sizeof msg);
        if (rc)
            print_error("%s\n", msg);
        assert_int_equal(rc, 0);
    }
}

/* A .vdb streamed into NanoVDB leaf by leaf (vdb_stream.cpp, the default)
 * is the grid NanoVDB's own converter makes of it: the same voxels and
 * active states everywhere (tiles and background included), as float and
 * as Fp16 (the same codes), and the same samples. A grid of several
 * thousand leaves, so that the stream runs in several batches. */
static void test_streamed_load_matches_nanovdb_converter(void **state)
{
    (void)state;
    char path[512];
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    tu_tmp(path, sizeof path, "streamed.vdb");
    remove(path);
    static const sdft_quant quants[2] = {SDFT_QUANT_NONE, SDFT_QUANT_FP16};
    for (int q = 0; q < 2; q++) {
        sdft_grid *g[2] = {NULL, NULL}; /* converted, streamed */
        sdft_grid_options converted = sdft_grid_options_defaults(), streamed = converted;
        converted.stream = 0;
        open_figure_twice("streamed.vdb", 256, quants[q], converted, streamed, path, sizeof path, g);
        pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(g[1]->buf, g[1]->grid);
        print_message("%s: %llu leaves, %zu bytes streamed, %zu converted\n", sdft_grid_type_name(g[1]),
                      (unsigned long long)pnanovdb_tree_get_node_count_leaf(g[1]->buf, tree), g[1]->size, g[0]->size);
        assert_true(pnanovdb_tree_get_node_count_leaf(g[1]->buf, tree) > 2048);
        assert_string_equal(sdft_grid_type_name(g[1]), sdft_grid_type_name(g[0]));
        assert_int_equal(g[1]->size, g[0]->size);
        assert_string_equal(sdft_grid_name(g[1]), sdft_grid_name(g[0]));
        assert_memory_equal(g[1]->w2i, g[0]->w2i, sizeof g[0]->w2i);
        same_voxels(g[0], g[1]);
        sdft_scratch s0, s1;
        sdft_field f0 = sdft_grid_field(g[0], SDFT_GRID_BOUND_FAR), f1 = sdft_grid_field(g[1], SDFT_GRID_BOUND_FAR);
        sdft_scratch_init(&f0, &s0);
        sdft_scratch_init(&f1, &s1);
        tu_rng r = tu_rng_seed(31);
        for (int i = 0; i < 20000; i++) {
            sdft_vec3 p = sdft_v3(tu_uniform(&r, sc->field.bounds.lo.x, sc->field.bounds.hi.x),
                                  tu_uniform(&r, sc->field.bounds.lo.y, sc->field.bounds.hi.y),
                                  tu_uniform(&r, sc->field.bounds.lo.z, sc->field.bounds.hi.z));
            assert_true(f0.distance(f0.ctx, &s0, p) == f1.distance(f1.ctx, &s1, p));
        }
        sdft_grid_free(g[0]);
        sdft_grid_free(g[1]);
    }
}

/* ---- deferred leaves --------------------------------------------------------------- */

/* A .vdb opened with deferred leaves (sdft_grid_options.defer) reads nothing
 * of a leaf until something samples it, and then reads exactly what the
 * whole load holds: every voxel equal, trilinear samples equal, renders
 * (2 threads filling leaves at once) equal within a thousandth of a voxel
 * and with the same hits, the far bound never larger than the whole
 * grid's (it counts unread leaves as occupied), and once every leaf is
 * filled (sdft_grid_data) the very same bytes, float and Fp16. */
static void test_deferred_leaves_match_whole_load(void **state)
{
    (void)state;
    char path[512], msg[256];
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    tu_tmp(path, sizeof path, "deferred.vdb");
    remove(path);
    static const sdft_quant quants[2] = {SDFT_QUANT_NONE, SDFT_QUANT_FP16};
    for (int q = 0; q < 2; q++) {
        sdft_grid *g[2] = {NULL, NULL}; /* whole, deferred */
        sdft_grid_options loaded = sdft_grid_options_defaults(), deferred = loaded;
        deferred.defer = 2; /* always: a grid this small would otherwise load whole (below) */
        open_figure_twice("deferred.vdb", 160, quants[q], loaded, deferred, path, sizeof path, g);
        uint64_t leaves, filled, failed, whole_leaves, whole_filled;
        sdft_grid_leaf_counts(g[0], &whole_leaves, &whole_filled, &failed);
        assert_int_equal(whole_filled, whole_leaves);
        assert_int_equal(failed, 0);
        sdft_grid_leaf_counts(g[1], &leaves, &filled, &failed);
        assert_int_equal(leaves, whole_leaves);
        assert_true(leaves > 1000);
        assert_int_equal(filled, 0); /* loading read no leaf */
        assert_int_equal(sdft_grid_size(g[1]), sdft_grid_size(g[0]));

        /* Samples from two threads at once, against the whole grid's. */
        enum { N = 20000 };
        static sdft_vec3 p[N];
        static float whole[N], whole_none[N];
        static int whole_level[N];
        tu_rng r = tu_rng_seed(77);
        sdft_scratch s0;
        sdft_field f0 = sdft_grid_field(g[0], SDFT_GRID_BOUND_FAR);
        sdft_scratch_init(&f0, &s0);
        for (int i = 0; i < N; i++) {
            p[i] = sdft_v3(tu_uniform(&r, sc->field.bounds.lo.x, sc->field.bounds.hi.x),
                           tu_uniform(&r, sc->field.bounds.lo.y, sc->field.bounds.hi.y),
                           tu_uniform(&r, sc->field.bounds.lo.z, sc->field.bounds.hi.z));
            whole[i] = sdft_grid_sample(g[0], SDFT_GRID_BOUND_FAR, &s0, p[i], &whole_level[i]);
            whole_none[i] = sdft_grid_sample(g[0], SDFT_GRID_BOUND_NONE, &s0, p[i], NULL);
        }
        int bad = 0;
        const sdft_field f1 = sdft_grid_field(g[1], SDFT_GRID_BOUND_FAR);
#pragma omp parallel num_threads(2) reduction(+ : bad)
        {
            sdft_scratch s1;
            sdft_scratch_init(&f1, &s1);
#pragma omp for schedule(dynamic, 64)
            for (int i = 0; i < N; i++) {
                int level;
                const float v = sdft_grid_sample(g[1], SDFT_GRID_BOUND_FAR, &s1, p[i], &level);
                const float none = sdft_grid_sample(g[1], SDFT_GRID_BOUND_NONE, &s1, p[i], NULL);
                bad += none != whole_none[i]; /* the same voxels, the same interpolant */
                /* A looser far bound: on the same side, and never above the whole grid's bounds (its
                 * trilinear band values, level 0, are no bounds to compare with). */
                bad += level == 5 &&
                       ((v < 0.0f) != (whole[i] < 0.0f) || (whole_level[i] != 0 && fabsf(v) > fabsf(whole[i])));
            }
        }
        assert_int_equal(bad, 0);
        sdft_grid_leaf_counts(g[1], NULL, &filled, NULL);
        print_message("%s: %llu of %llu leaves read by %d samples\n", sdft_grid_type_name(g[1]),
                      (unsigned long long)filled, (unsigned long long)leaves, N);
        assert_true(filled > 0 && filled < leaves);

        /* A render with two threads filling leaves as its rays reach them. */
        sdft_render_params rp = sdft_render_defaults();
        rp.width = 160, rp.height = 90, rp.threads = 2, rp.camera = sc->camera, rp.light = sc->light;
        sdft_image img[2];
        sdft_render_stats st[2];
        for (int d = 0; d < 2; d++) {
            const sdft_field f = sdft_grid_field(g[d], SDFT_GRID_BOUND_FAR);
            assert_int_equal(sdft_image_alloc(&img[d], rp.width, rp.height, msg, sizeof msg), 0);
            assert_int_equal(sdft_render(&f, &rp, &img[d], &st[d], msg, sizeof msg), 0);
        }
        const float voxel = sdft_grid_voxel_size(g[0]).x;
        assert_true(st[0].hits > 1000);
        assert_int_equal(st[1].hits, st[0].hits);
        for (int i = 0; i < rp.width * rp.height; i++) {
            assert_int_equal(img[1].status[i], img[0].status[i]);
            if (img[0].status[i] == SDFT_HIT && !(fabsf(img[1].depth[i] - img[0].depth[i]) <= 1e-3f * voxel))
                fail_msg("pixel %d: depth %g deferred, %g whole", i, img[1].depth[i], img[0].depth[i]);
        }
        sdft_image_free(&img[0]);
        sdft_image_free(&img[1]);

        /* Every leaf filled: the bytes of the whole load. */
        size_t n0, n1;
        const void *b0 = sdft_grid_data(g[0], &n0), *b1 = sdft_grid_data(g[1], &n1);
        sdft_grid_leaf_counts(g[1], NULL, &filled, &failed);
        assert_int_equal(filled, leaves);
        assert_int_equal(failed, 0);
        assert_int_equal(n1, n0);
        assert_memory_equal(b1, b0, n0);
        same_voxels(g[0], g[1]);
        sdft_grid_free(g[0]);
        sdft_grid_free(g[1]);
    }
    remove(path);
}

/* Deferring where it is exact (sdft_grid_options.defer 1, render's way): a
 * level set this small has far-bound cells narrower than a leaf, so it is
 * filled whole at load, and a render counts exactly what the whole load's
 * counts. An unknown way to defer is refused. */
static void test_deferred_where_exact_loads_small_grids_whole(void **state)
{
    (void)state;
    char path[512], msg[256];
    sdft_grid *g[2] = {NULL, NULL}; /* whole, deferred where exact */
    sdft_grid_options loaded = sdft_grid_options_defaults(), deferred = loaded;
    deferred.defer = 1;
    open_figure_twice("deferred-exact.vdb", 96, SDFT_QUANT_NONE, loaded, deferred, path, sizeof path, g);
    uint64_t leaves, filled, failed;
    sdft_grid_leaf_counts(g[1], &leaves, &filled, &failed);
    assert_true(leaves > 100);
    assert_int_equal(filled, leaves);
    assert_int_equal(failed, 0);
    const sdft_scene *sc = sdft_scene_find("figure");
    sdft_render_params rp = sdft_render_defaults();
    rp.width = 96, rp.height = 54, rp.threads = 2, rp.camera = sc->camera, rp.light = sc->light;
    sdft_render_stats st[2];
    for (int d = 0; d < 2; d++) {
        sdft_image img;
        const sdft_field f = sdft_grid_field(g[d], SDFT_GRID_BOUND_FAR);
        assert_int_equal(sdft_image_alloc(&img, rp.width, rp.height, msg, sizeof msg), 0);
        assert_int_equal(sdft_render(&f, &rp, &img, &st[d], msg, sizeof msg), 0);
        sdft_image_free(&img);
    }
    assert_true(st[0].hits > 100);
    assert_int_equal(st[1].steps, st[0].steps);
    assert_int_equal(st[1].cone_steps, st[0].cone_steps);
    assert_int_equal(st[1].hits, st[0].hits);
    sdft_grid_free(g[0]);
    sdft_grid_free(g[1]);
    sdft_grid *none = NULL;
    deferred.defer = 3;
    assert_int_equal(tu_open_with(path, NULL, &deferred, &none, msg, sizeof msg), SDFT_EINVAL);
    assert_null(none);
    remove(path);
}

/* What a deferred grid's loader is handed: a reference grid's bytes to
 * copy leaves from, the leaf whose read fails, and a count of fills per
 * leaf. */
typedef struct fill_source {
    const unsigned char *bytes;
    uint64_t first, stride, failing;
    int *calls;
    int released;
} fill_source;

static int fill_from(void *user, uint64_t index, void *leaf)
{
    fill_source *src = user;
    __atomic_add_fetch(&src->calls[index], 1, __ATOMIC_RELAXED);
    memcpy(leaf, src->bytes + src->first + index * src->stride, src->stride);
    if (index != src->failing)
        return 0;
    float *values = (float *)((unsigned char *)leaf + PNANOVDB_GRID_TYPE_GET(PNANOVDB_GRID_TYPE_FLOAT, leaf_off_table));
    for (int i = 0; i < 512; i++)
        values[i] = NAN; /* as a loader writes a leaf it cannot read */
    return 1;
}

static void release_source(void *user) { ((fill_source *)user)->released++; }

/* A 64-byte aligned copy of n bytes, for a grid to adopt (release_buffer frees it). */
static unsigned char *aligned_copy(const unsigned char *bytes, size_t n)
{
    unsigned char *copy = aligned_alloc(64, (n + 63) & ~(size_t)63);
    assert_non_null(copy);
    memcpy(copy, bytes, n);
    return copy;
}
static int released_buffers;
static void release_buffer(void *data) { free(data), released_buffers++; }

/* sdft_grid_open adopting buf, n bytes, whose leaves fill fills from user
 * as `how` defers them; release_buffer and release_source release them. */
static sdft_error open_deferred(void *buf, size_t n, sdft_leaf_fill_fn fill, void *user, sdft_defer how, sdft_grid **g,
                                char *msg, size_t msg_len)
{
    sdft_grid_options o = sdft_grid_options_defaults();
    o.data = buf, o.size = n, o.memory = SDFT_GRID_ADOPT, o.release = release_buffer;
    o.fill = fill, o.fill_user = user, o.fill_release = release_source, o.defer = how;
    return sdft_grid_open(&o, g, msg, msg_len);
}

/* Deferred leaves from C: a buffer whose leaves are garbage until
 * filled; each leaf filled exactly once however many threads read it; a
 * leaf whose fill fails reads NaN and is counted; the rest read as the
 * reference; the loader's user released once, with the grid or on a
 * refusal. */
static void test_deferred_fill_and_failure(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_grid *ref = bake(&f, 64, 0, NULL);
    size_t n;
    const unsigned char *bytes = sdft_grid_data(ref, &n);
    uint64_t leaves;
    sdft_grid_leaf_counts(ref, &leaves, NULL, NULL);
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(ref->buf, ref->grid);
    fill_source src = {.bytes = bytes,
                       .first = PNANOVDB_GRID_SIZE + pnanovdb_tree_get_node_offset_leaf(ref->buf, tree),
                       .stride = PNANOVDB_GRID_TYPE_GET(PNANOVDB_GRID_TYPE_FLOAT, leaf_size),
                       .failing = leaves / 2,
                       .calls = calloc(leaves, sizeof(int))};
    assert_non_null(src.calls);
    unsigned char *buf = aligned_copy(bytes, n);
    memset(buf + src.first, 0xA5, n - src.first); /* the leaves: not there yet */
    char msg[256];
    sdft_grid *g = NULL;
    released_buffers = 0;
    assert_int_equal(open_deferred(buf, n, fill_from, &src, SDFT_DEFER_ALWAYS, &g, msg, sizeof msg), SDFT_OK);
    uint64_t filled, failed;
    sdft_grid_leaf_counts(g, NULL, &filled, &failed);
    assert_int_equal(filled, 0);

    /* The failing leaf's voxels read NaN; every other voxel as the reference. */
    const uint64_t at = src.first + src.failing * src.stride;
    /* Its first active voxel, in the leaf whose voxels go NaN. */
    const pnanovdb_coord_t origin = pnanovdb_leaf_get_bbox_min(ref->buf, (pnanovdb_leaf_handle_t){{at}});
    int32_t lo[3], hi[3];
    sdft_grid_index_bounds(ref, lo, hi);
    int bad = 0, nan_voxels = 0, in_leaf = 0;
#pragma omp parallel for num_threads(2) reduction(+ : bad, nan_voxels, in_leaf) schedule(dynamic, 1)
    for (int32_t k = lo[2] - 1; k <= hi[2] + 1; k++)
        for (int32_t j = lo[1] - 1; j <= hi[1] + 1; j++)
            for (int32_t i = lo[0] - 1; i <= hi[0] + 1; i++) {
                const float v = sdft_grid_voxel(g, i, j, k, NULL), want = sdft_grid_voxel(ref, i, j, k, NULL);
                const int in_failing =
                    (i & ~7) == (origin.x & ~7) && (j & ~7) == (origin.y & ~7) && (k & ~7) == (origin.z & ~7);
                in_leaf += in_failing;
                nan_voxels += in_failing && isnan(v);
                bad += in_failing ? !isnan(v) : v != want;
            }
    assert_int_equal(bad, 0);
    assert_true(in_leaf > 0);
    assert_int_equal(nan_voxels, in_leaf);
    sdft_grid_leaf_counts(g, NULL, &filled, &failed);
    assert_int_equal(filled, leaves);
    assert_int_equal(failed, 1);
    for (uint64_t i = 0; i < leaves; i++)
        assert_int_equal(src.calls[i], 1);
    assert_int_equal(src.released, 0);
    sdft_grid_free(g);
    assert_int_equal(src.released, 1);
    assert_int_equal(released_buffers, 1);

    /* Refusals release what they were given, once. */
    assert_int_equal(open_deferred(aligned_copy(bytes, n), n, NULL, &src, SDFT_DEFER_ALWAYS, &g, msg, sizeof msg),
                     SDFT_EINVAL);
    assert_null(g);
    assert_int_equal(src.released, 2);
    assert_int_equal(released_buffers, 2);
    assert_int_equal(open_deferred(aligned_copy(bytes, n), n, fill_from, &src, (sdft_defer)7, &g, msg, sizeof msg),
                     SDFT_EINVAL);
    assert_int_equal(src.released, 3);
    assert_int_equal(released_buffers, 3);
    unsigned char *bad_bytes = aligned_alloc(64, 64);
    assert_non_null(bad_bytes);
    memset(bad_bytes, 0, 64);
    assert_int_equal(open_deferred(bad_bytes, 64, fill_from, &src, SDFT_DEFER_ALWAYS, &g, msg, sizeof msg),
                     SDFT_EFORMAT);
    assert_int_equal(src.released, 4);
    assert_int_equal(released_buffers, 4);
    free(src.calls);
    sdft_grid_free(ref);

    /* Deferred leaves need a streamed float or Fp16 grid. */
    char path[512];
    tu_tmp(path, sizeof path, "deferred-errors.vdb");
    sdft_grid_free(bake(&f, 24, 0, path));
    sdft_grid_options o = sdft_grid_options_defaults();
    o.defer = 1;
    o.quant = SDFT_QUANT_FP8;
    assert_int_equal(tu_open_with(path, NULL, &o, &g, msg, sizeof msg), SDFT_EINVAL);
    assert_non_null(strstr(msg, "deferred"));
    o.quant = SDFT_QUANT_NONE, o.stream = 0;
    assert_int_equal(tu_open_with(path, NULL, &o, &g, msg, sizeof msg), SDFT_EINVAL);
    remove(path);
}

static void test_round_trip_vdb(void **state)
{
    (void)state;
    round_trip("roundtrip.vdb");
}

static void test_round_trip_nvdb(void **state)
{
    (void)state;
    round_trip("roundtrip.nvdb");
}

/* ---- a scratch remembers its grid ------------------------------------------------ */

/* A scratch prepared for one grid is refused by every entry point given
 * another grid's field, never read through the first grid's cached
 * accessor; fields of the same grid with another bound share it. */
static void test_scratch_remembers_its_grid(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    const sdft_scene *sc = sdft_scene_find("figure");
    assert_non_null(sc);
    sdft_grid *a = bake(&f, 32, 0, NULL), *b = bake(&sc->field, 40, 0, NULL);
    sdft_field fa = sdft_grid_field(a, SDFT_GRID_BOUND_FAR), fb = sdft_grid_field(b, SDFT_GRID_BOUND_FAR),
               fa_tree = sdft_grid_field(a, SDFT_GRID_BOUND_TREE);
    sdft_scratch s;
    sdft_scratch_init(&fa, &s);
    const sdft_trace_params p = sdft_trace_defaults();
    sdft_ray rays[4];
    for (int k = 0; k < 4; k++)
        rays[k] = (sdft_ray){.org = {0.1f * k, 0.05f, 4}, .tnear = 0, .dir = {0, 0, -1}, .tfar = INFINITY};
    sdft_hit hits[4];
    char msg[256];

    assert_int_equal(sdft_trace(&fa, &s, &rays[0], &p).status, SDFT_HIT);
    assert_int_equal(sdft_trace(&fa_tree, &s, &rays[0], &p).status, SDFT_HIT); /* the same grid */
    sdft_hit wrong = sdft_trace(&fb, &s, &rays[0], &p);
    assert_int_equal(wrong.status, SDFT_INVALID);
    assert_int_equal(wrong.steps, 0);
    sdft_trace_stream(&fb, &s, rays, hits, 4, &p);
    for (int k = 0; k < 4; k++)
        assert_int_equal(hits[k].status, SDFT_INVALID);
    uint32_t steps = 0;
    assert_true(sdft_cone_march(&fb, &s, rays[0].org, rays[0].dir, 0.01f, 0.0f, 10.0f, &steps) == 0.0f);
    assert_int_equal(steps, 0);
    assert_int_equal(sdft_trace_check(&fb, &s, &p, msg, sizeof msg), SDFT_EINVAL);
    assert_non_null(strstr(msg, "another field"));
    int level = 0;
    assert_true(isnan(sdft_grid_sample(b, SDFT_GRID_BOUND_FAR, &s, sdft_v3(0, 0, 0), &level)));
    assert_int_equal(level, -1);
    assert_false(isnan(sdft_grid_sample(a, SDFT_GRID_BOUND_FAR, &s, sdft_v3(0, 0, 0), &level)));

    /* Prepared for b, it serves b and no longer a. */
    sdft_scratch_init(&fb, &s);
    assert_int_not_equal(sdft_trace(&fb, &s, &rays[0], &p).status, SDFT_INVALID);
    assert_int_equal(sdft_trace(&fa, &s, &rays[0], &p).status, SDFT_INVALID);
    /* A procedural field keeps no state: it takes any scratch, and its own
     * scratch serves no grid. */
    assert_int_equal(sdft_trace(&f, &s, &rays[0], &p).status, SDFT_HIT);
    sdft_scratch_init(&f, &s);
    assert_int_equal(sdft_trace(&fa, &s, &rays[0], &p).status, SDFT_INVALID);
    sdft_grid_free(a);
    sdft_grid_free(b);
}

/* ---- borrowed buffers ----------------------------------------------------------- */

/* A renderer's own NanoVDB bytes, borrowed in place: the grid reads them
 * (its data pointer is the caller's), samples and traces exactly as a
 * copy, picks a grid of a multi-grid buffer by name, and leaves the bytes
 * to their owner when freed (they sit inside a larger allocation, so a
 * free() of them would be an error AddressSanitizer reports). */
static void test_borrowed_buffer(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_grid *first = bake(&f, 32, 0, NULL), *second = bake(&f, 24, 1, NULL);
    size_t n1, n2;
    const void *b1 = sdft_grid_data(first, &n1), *b2 = sdft_grid_data(second, &n2);
    assert_int_equal(n1 % 32, 0);
    unsigned char *block = aligned_alloc(32, 64 + n1 + n2);
    assert_non_null(block);
    unsigned char *mine = block + 64;
    memcpy(mine, b1, n1);
    memcpy(mine + n1, b2, n2);
    /* Grid names: both "sdf"; rename the second in its header to pick it. */
    memcpy(mine + n1 + PNANOVDB_GRID_OFF_GRID_NAME, "second", 7);

    char msg[256];
    sdft_grid *lent = NULL, *lent2 = NULL;
    assert_int_equal(tu_open_buffer(mine, n1 + n2, NULL, SDFT_GRID_BORROW, NULL, &lent, msg, sizeof msg), SDFT_OK);
    assert_int_equal(tu_open_buffer(mine, n1 + n2, "second", SDFT_GRID_BORROW, NULL, &lent2, msg, sizeof msg), SDFT_OK);
    size_t got;
    assert_ptr_equal(sdft_grid_data(lent, &got), mine);
    assert_int_equal(got, n1);
    assert_ptr_equal(sdft_grid_data(lent2, &got), mine + n1);
    assert_string_equal(sdft_grid_name(lent2), "second");
    same_voxels(first, lent);
    same_voxels(second, lent2);

    sdft_field fc = sdft_grid_field(first, SDFT_GRID_BOUND_FAR), fl = sdft_grid_field(lent, SDFT_GRID_BOUND_FAR);
    sdft_scratch sc, sl;
    sdft_scratch_init(&fc, &sc);
    sdft_scratch_init(&fl, &sl);
    const sdft_trace_params p = sdft_trace_defaults();
    tu_rng r = tu_rng_seed(21);
    int hits = 0;
    for (int i = 0; i < 200; i++) {
        sdft_vec3 d = sdft_normalize(sdft_v3(tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)));
        sdft_ray ray = {.org = sdft_scale(d, -3.0f), .tnear = 0, .dir = d, .tfar = INFINITY};
        ray.org.x += tu_uniform(&r, -0.3f, 0.3f);
        sdft_hit hc = sdft_trace(&fc, &sc, &ray, &p), hl = sdft_trace(&fl, &sl, &ray, &p);
        assert_memory_equal(&hc, &hl, sizeof hc);
        hits += hc.status == SDFT_HIT;
    }
    assert_true(hits > 100);
    sdft_grid_free(lent);
    sdft_grid_free(lent2);
    assert_memory_equal(mine, b1, n1); /* untouched, still the caller's */
    free(block);
    sdft_grid_free(first);
    sdft_grid_free(second);
}

/* ---- which grid: .vdb and .nvdb alike ----------------------------------------------- */

/* Files written by OpenVDB's vdb_tool and converted by NanoVDB's
 * nanovdb_convert, each grid in the same order: every selection gives the
 * same code and the same grid from both loaders, and the grid the rule
 * (include/sdftrace/grid.h) names. */
static void test_grid_selection_is_the_same_for_vdb_and_nvdb(void **state)
{
    (void)state;
    char vdb[512], nvdb[512], cmd_out[4096];
    static const struct {
        const char *tool_args; /* vdb_tool writes its stack top first */
        struct {
            const char *name; /* NULL: the default choice */
            sdft_error code;
            const char *picked;
        } cases[5];
    } files[2] = {
        {"-sphere radius=1 dim=32 name=ball -grad keep=1 -sphere radius=0.5 dim=32 name=s0 -ls2fog keep=0",
         /* ls2fog_s0 (fog), grad_ball (vec3), ball (level set) */
         {{NULL, SDFT_OK, "ball"},
          {"ls2fog_s0", SDFT_OK, "ls2fog_s0"},
          {"ball", SDFT_OK, "ball"},
          {"grad_ball", SDFT_ENOTSCALAR, NULL},
          {"nosuch", SDFT_ENOTFOUND, NULL}}},
        {"-sphere radius=1 dim=32 name=b -grad keep=0 -sphere radius=0.5 dim=32 name=s0 -ls2fog keep=0",
         /* ls2fog_s0 (fog), grad_b (vec3): no level set, the first scalar grid */
         {{NULL, SDFT_OK, "ls2fog_s0"},
          {"grad_b", SDFT_ENOTSCALAR, NULL},
          {"", SDFT_ENOTFOUND, NULL},
          {"ls2fog_s0", SDFT_OK, "ls2fog_s0"},
          {"b", SDFT_ENOTFOUND, NULL}}},
    };
    for (int k = 0; k < 2; k++) {
        tu_tmp(vdb, sizeof vdb, k ? "choose2.vdb" : "choose1.vdb");
        tu_tmp(nvdb, sizeof nvdb, k ? "choose2.nvdb" : "choose1.nvdb");
        remove(vdb), remove(nvdb);
        int rc = tu_run(cmd_out, sizeof cmd_out, "vdb_tool -quiet %s -o %s && nanovdb_convert -f %s %s",
                        files[k].tool_args, vdb, vdb, nvdb);
        if (rc)
            print_error("%s\n", cmd_out);
        assert_int_equal(rc, 0);
        for (int c = 0; c < 5; c++) {
            const char *name = files[k].cases[c].name;
            sdft_grid *gv = NULL, *gn = NULL;
            char mv[256] = "", mn[256] = "";
            const sdft_error rv = tu_open_file(vdb, name, SDFT_QUANT_NONE, &gv, mv, sizeof mv);
            const sdft_error rn = tu_open_nvdb(nvdb, name, &gn, mn, sizeof mn);
            print_message("%s '%s': .vdb %s %s | .nvdb %s %s\n", k ? "choose2" : "choose1", name ? name : "(null)",
                          sdft_error_name(rv), gv ? sdft_grid_name(gv) : mv, sdft_error_name(rn),
                          gn ? sdft_grid_name(gn) : mn);
            assert_int_equal(rv, files[k].cases[c].code);
            assert_int_equal(rn, files[k].cases[c].code);
            if (files[k].cases[c].picked) {
                assert_string_equal(sdft_grid_name(gv), files[k].cases[c].picked);
                assert_string_equal(sdft_grid_name(gn), files[k].cases[c].picked);
                assert_int_equal(sdft_grid_active_voxels(gv), sdft_grid_active_voxels(gn));
            }
            sdft_grid_free(gv);
            sdft_grid_free(gn);
        }
    }
}

/* ---- errors -------------------------------------------------------------------------- */

static void expect_error(const char *path, const char *name, int code, const char *needle)
{
    sdft_grid *g = (sdft_grid *)1;
    char msg[512] = "";
    int rc = tu_open_file(path, name, SDFT_QUANT_NONE, &g, msg, sizeof msg);
    print_message("%s -> %d: %s\n", path, rc, msg);
    assert_int_equal(rc, code);
    assert_null(g);
    assert_null(strchr(msg, '\n'));
    assert_non_null(strstr(msg, needle));
}

/* Writes the first `keep` bytes of src to dst, or garbage when keep is 0. */
static void copy_prefix(const char *src, const char *dst, long keep, int garble)
{
    FILE *in = fopen(src, "rb"), *out = fopen(dst, "wb");
    assert_non_null(in);
    assert_non_null(out);
    fseek(in, 0, SEEK_END);
    long size = ftell(in);
    rewind(in);
    char *buf = malloc((size_t)size);
    assert_int_equal(fread(buf, 1, (size_t)size, in), (size_t)size);
    if (garble)
        for (long i = keep; i < size; i += 7)
            buf[i] ^= 0x5a;
    fwrite(buf, 1, (size_t)(garble ? size : keep), out);
    free(buf);
    fclose(in);
    fclose(out);
}

static void test_errors(void **state)
{
    (void)state;
    char good_vdb[512], good_nvdb[512], bad[512], cmd_out[4096];
    sdft_field f = spheres_field();
    sdft_grid_free(bake(&f, 32, 0, tu_tmp(good_vdb, sizeof good_vdb, "good.vdb")));
    sdft_grid_free(bake(&f, 32, 0, tu_tmp(good_nvdb, sizeof good_nvdb, "good.nvdb")));

    expect_error(tu_tmp(bad, sizeof bad, "missing.vdb"), NULL, SDFT_EIO, "cannot open");
    expect_error(tu_tmp(bad, sizeof bad, "missing.nvdb"), NULL, SDFT_EIO, "cannot open");
    expect_error(good_vdb, "nosuch", SDFT_ENOTFOUND, "no grid named 'nosuch'");
    expect_error(good_nvdb, "nosuch", SDFT_ENOTFOUND, "no grid named 'nosuch'");

    copy_prefix(good_vdb, tu_tmp(bad, sizeof bad, "truncated.vdb"), 600, 0);
    expect_error(bad, NULL, SDFT_EFORMAT, "cannot read");
    copy_prefix(good_vdb, tu_tmp(bad, sizeof bad, "corrupt.vdb"), 0, 1);
    expect_error(bad, NULL, SDFT_EFORMAT, "cannot read");
    copy_prefix(good_nvdb, tu_tmp(bad, sizeof bad, "truncated.nvdb"), 2000, 0);
    expect_error(bad, NULL, SDFT_EFORMAT, "truncated");
    copy_prefix(good_nvdb, tu_tmp(bad, sizeof bad, "header.nvdb"), 100, 0);
    expect_error(bad, NULL, SDFT_EFORMAT, "truncated");
    copy_prefix(good_nvdb, tu_tmp(bad, sizeof bad, "corrupt.nvdb"), 0, 1);
    expect_error(bad, NULL, SDFT_EFORMAT, "");

    /* A Vec3f grid (the sphere's gradient), written by OpenVDB's own tools. */
    char vec[512], vecn[512];
    tu_tmp(vec, sizeof vec, "vec3.vdb");
    tu_tmp(vecn, sizeof vecn, "vec3.nvdb");
    remove(vec), remove(vecn);
    int rc = tu_run(cmd_out, sizeof cmd_out,
                    "vdb_tool -quiet -sphere radius=1 dim=32 name=ball -grad keep=0 -o %s && "
                    "nanovdb_convert -f %s %s",
                    vec, vec, vecn);
    if (rc)
        print_error("%s\n", cmd_out);
    assert_int_equal(rc, 0);
    expect_error(vec, NULL, SDFT_ENOTSCALAR, "no scalar grid");
    expect_error(vecn, NULL, SDFT_ENOTSCALAR, "no scalar grid");

    /* An empty level set: a sphere eroded away. */
    char empty[512];
    tu_tmp(empty, sizeof empty, "empty.vdb");
    remove(empty);
    rc = tu_run(cmd_out, sizeof cmd_out,
                "vdb_tool -quiet -sphere radius=0.1 voxel=0.05 name=gone -erode radius=4 -o %s", empty);
    assert_int_equal(rc, 0);
    expect_error(empty, NULL, SDFT_EEMPTY, "empty");

    sdft_grid *g = NULL;
    char msg[256];
    assert_int_not_equal(tu_open_file("plain.txt", NULL, SDFT_QUANT_NONE, &g, msg, sizeof msg), 0);
}

static void test_bake_errors(void **state)
{
    (void)state;
    sdft_field f = spheres_field();
    sdft_bake_params p = sdft_bake_defaults();
    char msg[256], path[512];
    tu_tmp(path, sizeof path, "never.vdb");
    remove(path);
    p.res = 0;
    assert_int_not_equal(sdft_bake(&f, &p, path, NULL, NULL, msg, sizeof msg), 0);
    assert_non_null(strstr(msg, "resolution"));
    p.res = 1025;
    assert_int_not_equal(sdft_bake(&f, &p, path, NULL, NULL, msg, sizeof msg), 0);
    p.res = 16;
    assert_int_not_equal(sdft_bake(&f, &p, "/nonexistent-dir/x.vdb", NULL, NULL, msg, sizeof msg), 0);
    assert_non_null(strstr(msg, "cannot write"));
    assert_int_not_equal(sdft_bake(&f, &p, tu_tmp(path, sizeof path, "x.exr"), NULL, NULL, msg, sizeof msg), 0);
    assert_false(tu_file_exists(path));
    /* A box holding no surface bakes nothing, and says so. */
    sdft_field far = f;
    far.bounds = (sdft_aabb){{5, 5, 5}, {6, 6, 6}};
    tu_tmp(path, sizeof path, "never.vdb");
    assert_int_equal(sdft_bake(&far, &p, path, NULL, NULL, msg, sizeof msg), SDFT_EEMPTY);
    assert_false(tu_file_exists(path));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_linear_field_is_exact),
        cmocka_unit_test(test_trilinear_matches_brute_force),
        cmocka_unit_test(test_specialised_fields_agree),
        cmocka_unit_test(test_inverse_map_noise_is_dropped),
        cmocka_unit_test(test_leaf_directory_matches_accessor),
        cmocka_unit_test(test_quantized_grids),
        cmocka_unit_test(test_tree_bound_never_exceeds_distance),
        cmocka_unit_test(test_tree_bound_on_a_scene),
        cmocka_unit_test(test_far_bound_never_exceeds_distance),
        cmocka_unit_test(test_far_bound_is_continuous),
        cmocka_unit_test(test_far_bound_is_not_asked_in_leaves),
        cmocka_unit_test(test_far_cells_from_directory_match_tree),
        cmocka_unit_test(test_far_corner_distances_match_brute_force),
        cmocka_unit_test(test_grid_trace_is_safe),
        cmocka_unit_test(test_cell_root_against_brute_force),
        cmocka_unit_test(test_cell_root_on_near_planar_cells),
        cmocka_unit_test(test_exact_root_on_a_grid),
        cmocka_unit_test(test_exact_root_passes_a_near_miss),
        cmocka_unit_test(test_normal_is_the_interpolant_gradient),
        cmocka_unit_test(test_grid_render_matches_procedural),
        cmocka_unit_test(test_hull_holds_every_first_root),
        cmocka_unit_test(test_render_from_the_hull),
        cmocka_unit_test(test_render_hints_hull_entries),
        cmocka_unit_test(test_field_distances_batch),
        cmocka_unit_test(test_streamed_load_matches_nanovdb_converter),
        cmocka_unit_test(test_round_trip_vdb),
        cmocka_unit_test(test_round_trip_nvdb),
        cmocka_unit_test(test_scratch_remembers_its_grid),
        cmocka_unit_test(test_borrowed_buffer),
        cmocka_unit_test(test_deferred_leaves_match_whole_load),
        cmocka_unit_test(test_deferred_fill_and_failure),
        cmocka_unit_test(test_deferred_where_exact_loads_small_grids_whole),
        cmocka_unit_test(test_grid_selection_is_the_same_for_vdb_and_nvdb),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_bake_errors),
    };
    return cmocka_run_group_tests_name("grid", tests, NULL, NULL);
}
