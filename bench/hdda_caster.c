/* hdda_caster — one grid traced two ways from one camera, in one run:
 * NanoVDB's own level-set ray caster (pnanovdb_hdda_zero_crossing: a
 * hierarchical DDA that skips empty tiles and stops at the first sign change
 * between active voxels) and sdftrace's four variants through sdft_render
 * (primary rays only, as the caster), each with the far bound, the tree
 * bound alone and no bound. Prints ms per frame (best of $REPEAT, default 3),
 * ratios to the caster, and how closely the depth maps agree; writes the
 * caster's depth as a PFM.
 *
 * usage: hdda_caster GRID.vdb|GRID.nvdb SCENE [WIDTH HEIGHT [DEPTH.pfm]]
 *        the camera is the scene's (sdftrace scenes lists them). */
#define PNANOVDB_C
#define PNANOVDB_HDDA
#include <nanovdb/PNanoVDB.h>

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sdftrace/grid.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "vdb.h"

typedef struct caster {
    pnanovdb_buf_t buf;
    pnanovdb_root_handle_t root;
    float w2i[9], w2i_t[3];
} caster;

static caster caster_make(const sdft_grid *g)
{
    size_t size;
    const void *data = sdft_grid_data(g, &size);
    caster c;
    c.buf = pnanovdb_make_buf((uint32_t *)data, size / 4);
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

static pnanovdb_vec3_t apply(const float m[9], sdft_vec3 v, const float *t)
{
    pnanovdb_vec3_t r = {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
                         m[6] * v.x + m[7] * v.y + m[8] * v.z};
    if (t)
        r.x += t[0], r.y += t[1], r.z += t[2];
    return r;
}

/* Depth (world t along the unit ray) of every pixel, INFINITY on a miss.
 * The index-space ray is the world ray mapped by the affine transform. */
static double cast(const caster *c, const sdft_camera *cam, int w, int h, float *depth)
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
                depth[(size_t)y * w + x] = hit ? thit / len : INFINITY;
            }
    }
    return (omp_get_wtime() - t0) * 1e3;
}

/* sdftrace's depth alone, as the caster computes it: primary rays through
 * sdft_trace, no normals, no shading. Returns ms; sums the steps. */
static double trace_depth(const sdft_field *f, const sdft_trace_params *tp, const sdft_camera *cam, int w, int h,
                          float *depth, uint64_t *steps)
{
    const sdft_view view = sdft_camera_view(cam, w, h);
    uint64_t total = 0;
    double t0 = omp_get_wtime();
#pragma omp parallel reduction(+ : total)
    {
        sdft_scratch s;
        f->scratch_init(f->ctx, &s);
#pragma omp for schedule(dynamic, 4)
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                sdft_ray r = sdft_view_ray(&view, (float)x + 0.5f, (float)y + 0.5f);
                sdft_hit hit = sdft_trace(f, &s, &r, tp);
                total += hit.steps;
                int surface = hit.status == SDFT_HIT || (hit.status == SDFT_NOT_CONVERGED && tp->pixel_radius > 0.0f);
                depth[(size_t)y * w + x] = surface ? hit.t : INFINITY;
            }
    }
    *steps = total;
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

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: hdda_caster GRID.vdb|GRID.nvdb SCENE [WIDTH HEIGHT [DEPTH.pfm]]\n");
        return 2;
    }
    const sdft_scene *sc = sdft_scene_find(argv[2]);
    const char *rep = getenv("REPEAT");
    const int repeat = rep && atoi(rep) > 0 ? atoi(rep) : 3;
    int w = argc > 4 ? atoi(argv[3]) : 1280, h = argc > 4 ? atoi(argv[4]) : 720;
    if (!sc || w < 1 || h < 1) {
        fprintf(stderr, "hdda_caster: unknown scene or bad size\n");
        return 2;
    }
    char msg[512];
    sdft_grid *g = NULL;
    if (sdft_grid_open(argv[1], NULL, &g, msg, sizeof msg)) {
        fprintf(stderr, "hdda_caster: %s\n", msg);
        return 1;
    }
    if (strcmp(sdft_grid_type_name(g), "float") != 0) {
        fprintf(stderr, "hdda_caster: NanoVDB's caster reads float grids, this one is %s\n", sdft_grid_type_name(g));
        return 1;
    }
    const float voxel = sdft_grid_voxel_size(g).x;
    const size_t n = (size_t)w * h;
    float *hdda = malloc(n * sizeof *hdda);
    caster c = caster_make(g);
    double best = INFINITY;
    for (int i = 0; i < repeat; i++)
        best = fmin(best, cast(&c, &sc->camera, w, h, hdda));
    if (argc > 5)
        write_pfm(argv[5], hdda, w, h);
    size_t hits = 0;
    for (size_t i = 0; i < n; i++)
        hits += isfinite(hdda[i]);
    printf("grid %s (%s, voxel %g), %dx%d, %d threads, best of %d\n", sdft_grid_name(g), sdft_grid_type_name(g), voxel,
           w, h, omp_get_max_threads(), repeat);
    /* The same view for OpenVDB's vdb_render, whose fov is horizontal. */
    const sdft_camera *cam = &sc->camera;
    float hfov =
        2.0f * atanf(tanf(0.5f * cam->fov_deg * 3.14159265f / 180.0f) * (float)w / (float)h) * 180.0f / 3.14159265f;
    printf("# vdb_render -translate %g,%g,%g -lookat %g,%g,%g -up %g,%g,%g -fov %g -res %dx%d\n", cam->from.x,
           cam->from.y, cam->from.z, cam->at.x, cam->at.y, cam->at.z, cam->up.x, cam->up.y, cam->up.z, hfov, w, h);
    printf("%-30s %10s %8s %8s %11s %11s %9s %9s\n", "tracer", "ms/frame", "ratio", "hit", "agree1.5vox", "agree3vox",
           "one-only", "steps/px");
    printf("%-30s %10.1f %8.2f %8.4f %11s %11s %9s %9s\n", "nanovdb-hdda", best, 1.0, (double)hits / n, "-", "-", "-",
           "-");

    sdft_field f = sdft_grid_field(g);
    sdft_render_params rp = sdft_render_defaults();
    rp.width = w, rp.height = h, rp.camera = sc->camera, rp.light = sc->light, rp.shadows = 0;
    sdft_image img;
    if (sdft_image_alloc(&img, w, h))
        return 1;
    static const char *const bound_suffix[] = {"", "-treebound", "-nobound"};
    /* $BOUNDS=1 keeps only the far-bound rows (2: and the tree bound's). */
    const char *nb = getenv("BOUNDS");
    const int bounds = nb && atoi(nb) >= 1 && atoi(nb) <= 3 ? atoi(nb) : 3;
    const float pixel_radius = sdft_camera_pixel_radius(&sc->camera, h);
    float *depth = malloc(n * sizeof *depth);
    if (!depth)
        return 1;
    /* Rows: with the far bound, each variant as a full render (normals and
     * shading, what `sdftrace render` does) and as depth alone (what the
     * caster does), each with the constant eps and with Keinert's
     * screen-space criterion (-ss: converged within half a pixel's
     * footprint); with the other bounds, full renders at the constant eps. */
    for (int b = 0; b < bounds; b++) {
        const sdft_grid_bound bound = (sdft_grid_bound)b;
        f = sdft_grid_field_with(g, bound);
        for (int row = 0; row < (b == 0 ? 4 : 1) * SDFT_METHOD_COUNT; row++) {
            const sdft_method m = (sdft_method)(row % SDFT_METHOD_COUNT);
            const int depth_only = row / SDFT_METHOD_COUNT % 2, screen_space = row / (2 * SDFT_METHOD_COUNT);
            rp.trace.method = m;
            rp.trace.omega = sdft_default_omega(m);
            rp.screen_space = screen_space;
            sdft_trace_params tp = rp.trace;
            tp.pixel_radius = screen_space ? pixel_radius : 0.0f;
            double ms = INFINITY;
            uint64_t steps = 0, hits = 0;
            for (int i = 0; i < repeat; i++) {
                if (depth_only) {
                    ms = fmin(ms, trace_depth(&f, &tp, &sc->camera, w, h, depth, &steps));
                    continue;
                }
                sdft_render_stats st;
                if (sdft_render(&f, &rp, &img, &st, msg, sizeof msg)) {
                    fprintf(stderr, "hdda_caster: %s\n", msg);
                    return 1;
                }
                ms = fmin(ms, st.ms);
                steps = st.steps;
            }
            const float *d = depth_only ? depth : img.depth;
            for (size_t i = 0; i < n; i++)
                hits += isfinite(d[i]);
            double close, close3, one;
            agree(d, hdda, n, 1.5f * voxel, &close, &one);
            agree(d, hdda, n, 3.0f * voxel, &close3, &one);
            char label[64];
            snprintf(label, sizeof label, "sdftrace-%s-%s%s%s", depth_only ? "depth" : "render", sdft_method_name(m),
                     screen_space ? "-ss" : "", bound_suffix[bound]);
            printf("%-30s %10.1f %8.2f %8.4f %11.4f %11.4f %9.4f %9.1f\n", label, ms, ms / best, (double)hits / n,
                   close, close3, one, (double)steps / (double)n);
        }
    }
    free(depth);
    sdft_image_free(&img);
    free(hdda);
    sdft_grid_free(g);
    return 0;
}
