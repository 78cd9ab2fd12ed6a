/* hdda_caster — one grid traced two ways from one camera, in one run:
 * NanoVDB's own level-set ray caster (pnanovdb_hdda_zero_crossing: a
 * hierarchical DDA that skips empty tiles and stops at the first sign change
 * between active voxels) and sdftrace's four variants, as full renders and
 * as depth alone, with and without cones, with each of the grid field's
 * bounds. Prints ms per frame
 * (best of $REPEAT, default 3), ratios to the caster, and how closely the
 * depth maps agree with the caster's and, given the EXR that OpenVDB's
 * vdb_render wrote of the same view with -shader position, with
 * vdb_render's; writes the caster's depth as a PFM.
 *
 * usage: hdda_caster GRID.vdb|GRID.nvdb SCENE [WIDTH HEIGHT [DEPTH.pfm [VDB_RENDER.exr]]]
 *        hdda_caster --view SCENE WIDTH HEIGHT    vdb_render's options for that view
 *        hdda_caster --single GRID.nvdb SCENE|front WIDTH HEIGHT
 *        the camera is the scene's (sdftrace scenes lists them).
 *
 * --single is the caster as a program of its own would run it once: the
 * .nvdb's grid read with one fread into memory (nothing built from it),
 * one frame traced, and a line of JSON: the read, the frame and the wall
 * from the start of main, in ms (bench/scaling.sh times the process). */
#define PNANOVDB_C
#define PNANOVDB_HDDA
#include <nanovdb/PNanoVDB.h>

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image_io.h"
#include "sdftrace/grid.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "sdftrace/vdb.h"

typedef struct caster {
    pnanovdb_buf_t buf;
    pnanovdb_root_handle_t root;
    float w2i[9], w2i_t[3];
} caster;

/* The caster of a NanoVDB grid's bytes. */
static caster caster_of(const void *data, size_t size)
{
    caster c;
    c.buf = pnanovdb_make_buf((uint32_t *)(uintptr_t)data, size / 4);
    pnanovdb_grid_handle_t grid = {{0}};
    c.root = pnanovdb_tree_get_root(c.buf, pnanovdb_grid_get_tree(c.buf, grid));
    pnanovdb_map_handle_t map = pnanovdb_grid_get_map(c.buf, grid);
    for (int i = 0; i < 9; i++)
        c.w2i[i] = pnanovdb_map_get_invmatf(c.buf, map, (uint32_t)i);
    for (int k = 0; k < 3; k++)
        c.w2i_t[k] = -(c.w2i[3 * k] * pnanovdb_map_get_vecf(c.buf, map, 0) +
                       c.w2i[3 * k + 1] * pnanovdb_map_get_vecf(c.buf, map, 1) +
                       c.w2i[3 * k + 2] * pnanovdb_map_get_vecf(c.buf, map, 2));
    return c;
}

static caster caster_make(const sdft_grid *g)
{
    size_t size;
    const void *data = sdft_grid_data(g, &size);
    return caster_of(data, size);
}

static pnanovdb_vec3_t apply(const float m[9], sdft_vec3 v, const float *t)
{
    pnanovdb_vec3_t r = {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
                         m[6] * v.x + m[7] * v.y + m[8] * v.z};
    if (t)
        r.x += t[0], r.y += t[1], r.z += t[2];
    return r;
}

/* The trilinear value at index point x (voxel centres at integers), read
 * through the accessor: the interpolant a refined hit lies on. */
static float trilinear(const caster *c, pnanovdb_readaccessor_t *acc, pnanovdb_vec3_t x)
{
    const pnanovdb_coord_t i0 = {(int32_t)floorf(x.x), (int32_t)floorf(x.y), (int32_t)floorf(x.z)};
    const float tx = x.x - (float)i0.x, ty = x.y - (float)i0.y, tz = x.z - (float)i0.z;
    float v[8];
    for (int k = 0; k < 8; k++) {
        pnanovdb_coord_t ijk = {i0.x + (k & 1), i0.y + (k >> 1 & 1), i0.z + (k >> 2 & 1)};
        v[k] = pnanovdb_read_float(
            c->buf, pnanovdb_readaccessor_get_value_address(PNANOVDB_GRID_TYPE_FLOAT, c->buf, acc, &ijk));
    }
    const float x00 = v[0] + (v[1] - v[0]) * tx, x10 = v[2] + (v[3] - v[2]) * tx;
    const float x01 = v[4] + (v[5] - v[4]) * tx, x11 = v[6] + (v[7] - v[6]) * tx;
    const float y0 = x00 + (x10 - x00) * ty, y1 = x01 + (x11 - x01) * ty;
    return y0 + (y1 - y0) * tz;
}

static pnanovdb_vec3_t at(pnanovdb_vec3_t o, pnanovdb_vec3_t d, float t)
{
    return (pnanovdb_vec3_t){o.x + t * d.x, o.y + t * d.y, o.z + t * d.z};
}

/* Sub-voxel refinement of a voxel-granular hit at index t: the interpolant
 * is bracketed by samples a voxel and a half either side, then four
 * Illinois (regula falsi) steps; the voxel hit stays when no bracket. */
static float refine(const caster *c, pnanovdb_readaccessor_t *acc, pnanovdb_vec3_t o, pnanovdb_vec3_t d, float t)
{
    float a = t - 1.5f, b = t + 1.5f;
    float fa = trilinear(c, acc, at(o, d, a)), fb = trilinear(c, acc, at(o, d, b));
    if (!(fa * fb < 0.0f))
        return t;
    int side = 0;
    for (int i = 0; i < 4; i++) {
        const float m = (a * fb - b * fa) / (fb - fa), fm = trilinear(c, acc, at(o, d, m));
        if (fm * fb > 0.0f) {
            b = m, fb = fm;
            if (side == -1)
                fa *= 0.5f;
            side = -1;
        } else {
            a = m, fa = fm;
            if (side == 1)
                fb *= 0.5f;
            side = 1;
        }
    }
    return (a * fb - b * fa) / (fb - fa);
}

/* Depth (world t along the unit ray) of every pixel, INFINITY on a miss:
 * the voxel where NanoVDB's HDDA caster finds the sign change, refined
 * onto the trilinear interpolant when `refined`. The index-space ray is
 * the world ray mapped by the affine transform. */
static double cast(const caster *c, const sdft_camera *cam, int w, int h, int refined, float *depth)
{
    const sdft_view view = sdft_camera_view(cam, w, h);
    double t0 = omp_get_wtime();
#pragma omp parallel
    {
        pnanovdb_readaccessor_t acc;
        pnanovdb_readaccessor_init(&acc, c->root);
#pragma omp for schedule(dynamic, 4)
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                sdft_ray r = sdft_view_ray(&view, (float)x + 0.5f, (float)y + 0.5f);
                /* The caster steps in index units along a unit index-space
                 * direction; its t divided by the direction's length is world t. */
                pnanovdb_vec3_t o = apply(c->w2i, r.org, c->w2i_t), d = apply(c->w2i, r.dir, NULL);
                float len = sqrtf(d.x * d.x + d.y * d.y + d.z * d.z);
                d.x /= len, d.y /= len, d.z /= len;
                float thit = 0.0f, v = 0.0f;
                int hit =
                    pnanovdb_hdda_zero_crossing(PNANOVDB_GRID_TYPE_FLOAT, c->buf, &acc, &o, 0.0f, &d, 1e19f, &thit, &v);
                if (hit && refined)
                    thit = refine(c, &acc, o, d, thit);
                depth[(size_t)y * w + x] = hit ? thit / len : INFINITY;
            }
    }
    return (omp_get_wtime() - t0) * 1e3;
}

static void write_pfm(const char *path, const float *depth, int w, int h)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return;
    fprintf(f, "Pf\n%d %d\n-1.0\n", w, h);
    for (int y = h - 1; y >= 0; y--) /* PFM rows run bottom to top */
        for (int x = 0; x < w; x++) {
            float v = isfinite(depth[(size_t)y * w + x]) ? depth[(size_t)y * w + x] : 0.0f;
            fwrite(&v, sizeof v, 1, f);
        }
    fclose(f);
}

/* Of the pixels both hit, the share within tol of each other; and the share
 * of all pixels hit by one only. */
static void agree(const float *a, const float *b, size_t n, float tol, double *close, double *one)
{
    size_t both = 0, near = 0, single = 0;
    for (size_t i = 0; i < n; i++) {
        int ha = isfinite(a[i]), hb = isfinite(b[i]);
        if (ha && hb) {
            both++;
            near += fabsf(a[i] - b[i]) <= tol;
        } else if (ha != hb) {
            single++;
        }
    }
    *close = both ? (double)near / (double)both : 0.0;
    *one = (double)single / (double)n;
}

/* One row of the table: a tracer's time, its ratio to the caster's, its
 * hit fraction, how its depth agrees with the caster's and vdb_render's
 * (NULL: not given), steps per pixel (NaN: not counted). */
typedef struct table {
    size_t n;
    float voxel;
    double caster_ms;
    const float *caster, *vdb_render;
} table;

static void print_row(const table *t, const char *label, double ms, const float *depth, double steps)
{
    size_t hits = 0;
    for (size_t i = 0; i < t->n; i++)
        hits += isfinite(depth[i]);
    if (isnan(ms))
        printf("%-30s %10s %8s %8.4f |", label, "-", "-", (double)hits / t->n);
    else
        printf("%-30s %10.1f %8.2f %8.4f |", label, ms, ms / t->caster_ms, (double)hits / t->n);
    double close, close3, one;
    if (depth != t->caster) {
        agree(depth, t->caster, t->n, 1.5f * t->voxel, &close, &one);
        agree(depth, t->caster, t->n, 3.0f * t->voxel, &close3, &one);
        printf(" %7.4f %7.4f %9.4f |", close, close3, one);
    } else {
        printf(" %7s %7s %9s |", "-", "-", "-");
    }
    if (t->vdb_render && depth != t->vdb_render) {
        agree(depth, t->vdb_render, t->n, 1.5f * t->voxel, &close, &one);
        printf(" %7.4f %8.4f |", close, one);
    } else {
        printf(" %7s %8s |", "-", "-");
    }
    if (isnan(steps))
        printf(" %8s\n", "-");
    else
        printf(" %8.1f\n", steps);
}

/* The same view as vdb_render's options; its fov is horizontal. */
static void print_view(const sdft_camera *cam, int w, int h)
{
    float hfov =
        2.0f * atanf(tanf(0.5f * cam->fov_deg * 3.14159265f / 180.0f) * (float)w / (float)h) * 180.0f / 3.14159265f;
    printf("-translate %g,%g,%g -lookat %g,%g,%g -up %g,%g,%g -fov %g -res %dx%d\n", cam->from.x, cam->from.y,
           cam->from.z, cam->at.x, cam->at.y, cam->at.z, cam->up.x, cam->up.y, cam->up.z, hfov, w, h);
}

/* vdb_render's depth from its -shader position EXR: colour (p - lo) / (hi -
 * lo) over the world box [lo, hi] of the active voxel centres, black on a
 * miss (its film's fill; a hit is black only at the corner lo); depth
 * |p - eye|. NULL (and a line on stderr) if it cannot be read. */
static float *vdb_render_depth(const char *path, const sdft_grid *g, sdft_vec3 eye, int w, int h)
{
    static const char *const names[3] = {"R", "G", "B"};
    float *rgb[3];
    int ew, eh;
    char msg[512];
    if (io_read_exr_floats(path, 3, names, rgb, &ew, &eh, msg, sizeof msg) || ew != w || eh != h) {
        fprintf(stderr, "hdda_caster: %s\n", ew != w || eh != h ? "vdb_render's image has another size" : msg);
        return NULL;
    }
    const sdft_vec3 half = sdft_scale(sdft_grid_voxel_size(g), 0.5f);
    const sdft_aabb b = sdft_grid_world_bounds(g); /* the cells' box: half a voxel beyond the centres */
    const sdft_vec3 lo = sdft_add(b.lo, half), ext = sdft_sub(sdft_sub(b.hi, half), lo);
    float *depth = malloc((size_t)w * h * sizeof *depth);
    for (size_t i = 0; depth && i < (size_t)w * h; i++) {
        const sdft_vec3 c = sdft_v3(rgb[0][i], rgb[1][i], rgb[2][i]);
        const sdft_vec3 p = sdft_v3(lo.x + c.x * ext.x, lo.y + c.y * ext.y, lo.z + c.z * ext.z);
        depth[i] = c.x != 0.0f || c.y != 0.0f || c.z != 0.0f ? sdft_length(sdft_sub(p, eye)) : INFINITY;
    }
    for (int c = 0; c < 3; c++)
        free(rgb[c]);
    return depth;
}

/* The view: a scene's camera, or `front` (sdft_camera_front, what `sdftrace
 * render --grid` frames without a scene). 0 if the name is unknown. */
static int view_of(const char *name, const sdft_grid *g, int w, int h, sdft_camera *cam)
{
    if (strcmp(name, "front") == 0) {
        *cam = sdft_camera_front(sdft_grid_world_bounds(g), w, h, 40.0f);
        return 1;
    }
    const sdft_scene *sc = sdft_scene_find(name);
    if (sc)
        *cam = sc->camera;
    return sc != NULL;
}

/* One sdftrace configuration of the table. */
typedef struct config {
    const char *label;
    sdft_render_params rp;
    sdft_grid_bound bound;
    double ms;
    sdft_render_stats st;
    float *depth;
} config;

static int add_config(config *c, int *n, const char *label, sdft_render_params rp, sdft_grid_bound bound)
{
    c[*n] = (config){.label = label, .rp = rp, .bound = bound, .ms = INFINITY};
    c[*n].depth = malloc((size_t)rp.width * rp.height * sizeof(float));
    if (!c[*n].depth)
        return -1;
    (*n)++;
    return 0;
}

enum { MAX_CONFIGS = 40 };

/* The rows: ROWS=targets (default) sdftrace as `sdftrace render` runs it
 * (its defaults, no shadows), depth alone, without the exact last-cell
 * root, and the papers' counting (every ray from the eye, every step to
 * eps); ROWS=variants every variant as a full render and
 * depth alone, at constant eps and with the screen-space criterion, with
 * each bound. */
static int make_configs(const sdft_camera *cam, int w, int h, config *c, int *n)
{
    static char labels[MAX_CONFIGS][64];
    sdft_render_params base = sdft_render_defaults();
    base.width = w, base.height = h, base.camera = *cam, base.shadows = 0;
    base.light = sdft_add(cam->from, sdft_v3(0, 10, 0));
    const char *rows = getenv("ROWS");
    *n = 0;
    if (!rows || strcmp(rows, "variants") != 0) {
        sdft_render_params depth = base, no_root = base, papers = base;
        depth.depth_only = 1;
        no_root.trace.exact_root = 0;
        sdft_render_papers(&papers);
        return add_config(c, n, "sdftrace-render", base, SDFT_GRID_BOUND_FAR) ||
               add_config(c, n, "sdftrace-depth", depth, SDFT_GRID_BOUND_FAR) ||
               add_config(c, n, "sdftrace-render-no-exact-root", no_root, SDFT_GRID_BOUND_FAR) ||
               add_config(c, n, "sdftrace-render-papers", papers, SDFT_GRID_BOUND_FAR);
    }
    static const char *const bound_suffix[] = {"", "-treebound", "-nobound"};
    static const struct {
        int depth_only, screen_space, cones;
    } kinds[] = {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}, {1, 1, 1}};
    const char *nb = getenv("BOUNDS");
    const int bounds = nb && atoi(nb) >= 1 && atoi(nb) <= 3 ? atoi(nb) : 3;
    for (int b = 0; b < bounds; b++)
        for (int row = 0; row < (b == 0 ? 5 : 1) * SDFT_METHOD_COUNT; row++) {
            const sdft_method m = (sdft_method)(row % SDFT_METHOD_COUNT);
            const int k = row / SDFT_METHOD_COUNT;
            sdft_render_params rp = base;
            sdft_render_papers(&rp);
            rp.trace.method = m;
            rp.trace.omega = sdft_default_omega(m);
            rp.depth_only = kinds[k].depth_only;
            rp.screen_space = kinds[k].screen_space;
            rp.cones = kinds[k].cones;
            char *label = labels[*n];
            snprintf(label, 64, "sdftrace-%s-%s%s%s%s", rp.depth_only ? "depth" : "render", sdft_method_name(m),
                     rp.screen_space ? "-ss" : "", rp.cones ? "-cones" : "", bound_suffix[b]);
            if (add_config(c, n, label, rp, (sdft_grid_bound)b))
                return -1;
        }
    return 0;
}

/* ---- --single: one read, one frame ------------------------------------------------- */

static double wall_ms(void) { return 1e3 * omp_get_wtime(); }

/* The first grid of the .nvdb file at path (NanoVDB's uncompressed
 * layout: a 16-byte segment header, 176 bytes of metadata, the name, the
 * grid) read with one fread into 64-byte aligned memory; NULL on a
 * failure, with a line on stderr. */
static void *read_first_grid(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    unsigned char head[16 + 176];
    uint64_t grid_size, file_size;
    uint32_t name_size;
    if (!f || fread(head, 1, sizeof head, f) != sizeof head) {
        fprintf(stderr, "hdda_caster: cannot read %s\n", path);
        if (f)
            fclose(f);
        return NULL;
    }
    memcpy(&grid_size, head + 16, 8), memcpy(&file_size, head + 24, 8), memcpy(&name_size, head + 16 + 136, 4);
    void *grid = grid_size == file_size && grid_size > 0 ? aligned_alloc(64, (grid_size + 63) & ~(uint64_t)63) : NULL;
    if (!grid || fseek(f, (long)name_size, SEEK_CUR) != 0 || fread(grid, 1, grid_size, f) != grid_size) {
        fprintf(stderr, "hdda_caster: %s is not an uncompressed NanoVDB file it can read\n", path);
        free(grid);
        fclose(f);
        return NULL;
    }
    fclose(f);
    *size = (size_t)grid_size;
    return grid;
}

/* The world box of the grid's active voxels' cells, through its map: the
 * box sdft_grid_world_bounds gives, so that `front` frames it as `sdftrace
 * render` does. */
static sdft_aabb caster_bounds(const caster *c)
{
    pnanovdb_grid_handle_t grid = {{0}};
    const pnanovdb_coord_t lo = pnanovdb_root_get_bbox_min(c->buf, c->root),
                           hi = pnanovdb_root_get_bbox_max(c->buf, c->root);
    pnanovdb_map_handle_t map = pnanovdb_grid_get_map(c->buf, grid);
    sdft_vec3 wlo = sdft_v3(INFINITY, INFINITY, INFINITY), whi = sdft_scale(wlo, -1.0f);
    for (int k = 0; k < 8; k++) {
        const float x[3] = {(k & 1) ? hi.x + 0.5f : lo.x - 0.5f, (k & 2) ? hi.y + 0.5f : lo.y - 0.5f,
                            (k & 4) ? hi.z + 0.5f : lo.z - 0.5f};
        float w[3];
        for (int r = 0; r < 3; r++)
            w[r] = (float)pnanovdb_map_get_matd(c->buf, map, 3u * (uint32_t)r) * x[0] +
                   (float)pnanovdb_map_get_matd(c->buf, map, 3u * (uint32_t)r + 1u) * x[1] +
                   (float)pnanovdb_map_get_matd(c->buf, map, 3u * (uint32_t)r + 2u) * x[2] +
                   (float)pnanovdb_map_get_vecd(c->buf, map, (uint32_t)r);
        const sdft_vec3 p = sdft_v3(w[0], w[1], w[2]);
        wlo = sdft_min_v(wlo, p), whi = sdft_max_v(whi, p);
    }
    return (sdft_aabb){wlo, whi};
}

static int single_call(int argc, char **argv, double start)
{
    if (argc != 6) {
        fprintf(stderr, "usage: hdda_caster --single GRID.nvdb SCENE|front WIDTH HEIGHT\n");
        return 2;
    }
    const int w = atoi(argv[4]), h = atoi(argv[5]);
    const sdft_scene *sc = sdft_scene_find(argv[3]);
    if (w < 1 || h < 1 || (!sc && strcmp(argv[3], "front") != 0)) {
        fprintf(stderr, "hdda_caster: unknown view or size\n");
        return 2;
    }
    size_t size = 0;
    const double t0 = wall_ms();
    void *bytes = read_first_grid(argv[2], &size);
    if (!bytes)
        return 1;
    const double t1 = wall_ms();
    const caster c = caster_of(bytes, size);
    if (pnanovdb_grid_get_grid_type(c.buf, (pnanovdb_grid_handle_t){{0}}) != PNANOVDB_GRID_TYPE_FLOAT) {
        fprintf(stderr, "hdda_caster: NanoVDB's caster reads float grids\n");
        return 1;
    }
    const sdft_camera cam = sc ? sc->camera : sdft_camera_front(caster_bounds(&c), w, h, 40.0f);
    float *depth = malloc((size_t)w * (size_t)h * sizeof *depth);
    if (!depth) {
        fprintf(stderr, "hdda_caster: out of memory\n");
        return 1;
    }
    const double frame = cast(&c, &cam, w, h, 0, depth);
    size_t hits = 0;
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++)
        hits += isfinite(depth[i]);
    printf("{\"grid_bytes\": %zu, \"threads\": %d, \"read_ms\": %.3f, \"frame_ms\": %.3f, \"hit_fraction\": %.6f, "
           "\"wall_ms\": %.3f}\n",
           size, omp_get_max_threads(), t1 - t0, frame, (double)hits / ((double)w * h), wall_ms() - start);
    free(depth);
    free(bytes);
    return 0;
}

int main(int argc, char **argv)
{
    const double start = wall_ms();
    if (argc >= 2 && strcmp(argv[1], "--single") == 0)
        return single_call(argc, argv, start);
    if (argc == 6 && strcmp(argv[1], "--view") == 0) {
        /* A .vdb's bounds from its metadata: no need to load a big grid. */
        char msg[512];
        sdft_aabb b;
        sdft_camera cam;
        const int w = atoi(argv[4]), h = atoi(argv[5]);
        const sdft_scene *sc = sdft_scene_find(argv[3]);
        if (w < 1 || h < 1 || (!sc && strcmp(argv[3], "front") != 0)) {
            fprintf(stderr, "hdda_caster: unknown view or size\n");
            return 2;
        }
        if (sc) {
            cam = sc->camera;
        } else if (sdft_vdb_bounds(argv[2], NULL, &b, msg, sizeof msg) == 0) {
            cam = sdft_camera_front(b, w, h, 40.0f);
        } else {
            fprintf(stderr, "hdda_caster: %s\n", msg);
            return 1;
        }
        print_view(&cam, w, h);
        return 0;
    }
    if (argc < 3) {
        fprintf(stderr,
                "usage: hdda_caster GRID.vdb|GRID.nvdb SCENE|front [WIDTH HEIGHT [DEPTH.pfm [VDB_RENDER.exr]]]\n"
                "       hdda_caster --view GRID SCENE|front WIDTH HEIGHT\n"
                "       hdda_caster --single GRID.nvdb SCENE|front WIDTH HEIGHT\n");
        return 2;
    }
    const char *rep = getenv("REPEAT");
    const int repeat = rep && atoi(rep) > 0 ? atoi(rep) : 3;
    int w = argc > 4 ? atoi(argv[3]) : 1280, h = argc > 4 ? atoi(argv[4]) : 720;
    char msg[512];
    sdft_grid *g = NULL;
    if (w < 1 || h < 1) {
        fprintf(stderr, "hdda_caster: bad size\n");
        return 2;
    }
    sdft_grid_options go = sdft_grid_options_defaults();
    go.path = argv[1];
    if (sdft_vdb_open(&go, &g, msg, sizeof msg)) {
        fprintf(stderr, "hdda_caster: %s\n", msg);
        return 1;
    }
    sdft_camera cam;
    if (!view_of(argv[2], g, w, h, &cam)) {
        fprintf(stderr, "hdda_caster: unknown scene '%s' (a scene's name or front)\n", argv[2]);
        return 2;
    }
    if (strcmp(sdft_grid_type_name(g), "float") != 0) {
        fprintf(stderr, "hdda_caster: NanoVDB's caster reads float grids, this one is %s\n", sdft_grid_type_name(g));
        return 1;
    }
    const float voxel = sdft_grid_voxel_size(g).x;
    const size_t n = (size_t)w * h;
    float *hdda = malloc(n * sizeof *hdda), *refined = malloc(n * sizeof *refined);
    config cf[MAX_CONFIGS];
    int configs = 0;
    sdft_image img;
    if (!hdda || !refined || make_configs(&cam, w, h, cf, &configs) || sdft_image_alloc(&img, w, h, msg, sizeof msg)) {
        fprintf(stderr, "hdda_caster: out of memory\n");
        return 1;
    }
    caster c = caster_make(g);
    /* Every tracer once per round, REPEAT rounds, the best of each: machine
     * noise then falls on all of them alike. */
    double best = INFINITY, best_refined = INFINITY;
    for (int i = 0; i < repeat; i++) {
        best = fmin(best, cast(&c, &cam, w, h, 0, hdda));
        best_refined = fmin(best_refined, cast(&c, &cam, w, h, 1, refined));
        for (int k = 0; k < configs; k++) {
            const sdft_field f = sdft_grid_field(g, cf[k].bound);
            if (sdft_render(&f, &cf[k].rp, &img, &cf[k].st, msg, sizeof msg)) {
                fprintf(stderr, "hdda_caster: %s\n", msg);
                return 1;
            }
            cf[k].ms = fmin(cf[k].ms, cf[k].st.ms);
            memcpy(cf[k].depth, img.depth, n * sizeof *img.depth);
        }
    }
    if (argc > 5)
        write_pfm(argv[5], hdda, w, h);
    printf("grid %s (%s, voxel %g), %dx%d, %d threads, best of %d\n", sdft_grid_name(g), sdft_grid_type_name(g), voxel,
           w, h, omp_get_max_threads(), repeat);
    printf("# vdb_render ");
    print_view(&cam, w, h);
    float *vr = argc > 6 ? vdb_render_depth(argv[6], g, cam.from, w, h) : NULL;
    if (argc > 6 && !vr)
        return 1;
    printf("%-30s %10s %8s %8s | %-25s | %-16s | %8s\n", "", "", "", "", "agrees with the caster", "with vdb_render",
           "");
    printf("%-30s %10s %8s %8s | %7s %7s %9s | %7s %8s | %8s\n", "tracer", "ms/frame", "ratio", "hit", "1.5vox", "3vox",
           "one-only", "1.5vox", "one-only", "evals/px");
    const table tab = {n, voxel, best, hdda, vr};
    print_row(&tab, "nanovdb-hdda", best, hdda, NAN);
    print_row(&tab, "nanovdb-hdda-refined", best_refined, refined, NAN);
    if (vr)
        print_row(&tab, "openvdb-vdb_render", NAN, vr, NAN);
    for (int k = 0; k < configs; k++) {
        print_row(&tab, cf[k].label, cf[k].ms, cf[k].depth, (double)(cf[k].st.steps + cf[k].st.cone_steps) / (double)n);
        free(cf[k].depth);
    }
    free(vr);
    sdft_image_free(&img);
    free(hdda);
    free(refined);
    sdft_grid_free(g);
    return 0;
}
