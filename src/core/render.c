/* sdftrace — the whole-image function.
 *
 * Each pixel is independent: a primary ray with the chosen variant, the
 * normal at the hit, and a hard shadow ray to the point light traced with
 * the same variant and parameters (as in the papers' measurements). Tiles of
 * TILE x TILE pixels are handed out dynamically to OpenMP threads; each
 * thread owns one scratch, and statistics are summed per tile, then over the
 * tiles in a fixed order, so the image and the counts do not depend on the
 * thread count. Nothing is allocated per ray. Within a tile, each
 * BLOCK x BLOCK block's primary rays are traced as one stream
 * (sdft_trace_stream: interleaved, so one ray's memory loads overlap
 * another's), then its shadow rays as another; every ray is still traced
 * exactly as alone.
 *
 * With `cones`, each tile's primary rays first march together as one cone
 * (sdft_cone_march), then each BLOCK x BLOCK block's from there, and each
 * ray's own trace starts where its block's cone stopped: the empty space
 * in front of the surface is crossed once per bundle instead of once per
 * ray. Those shared evaluations are counted apart (cone_steps).
 *
 * A field with a hull (sdft_field_accel.hull: a grid's boxes around the cells
 * its surface crosses, each cut to a slab along the surface where the
 * field gives hull_slabs) takes the cones' place: the boxes are binned to
 * the tiles their screen rectangles touch (hull_bin), and each pixel's ray
 * is traced only over its span of the boxes it meets, from its entry into
 * the first to its exit from the last (hull_spans: exact ray-box and
 * ray-slab tests against the ray as traced, no evaluation), a ray that
 * meets none being a miss untraced. The hull holds every first root of a ray that starts where the
 * field is positive, so the picture is the same; the eye is checked
 * (eye_outside), and where it is inside the surface the cones serve. Each
 * ray's entry into the hull is its first evaluation, at memory no earlier
 * ray of the tile touched: the field is told of it (sdft_field_accel.prefetch) a
 * block ahead, so that those loads overlap the block traced in between;
 * a traced tile's pixels in the image are fetched for writing when it
 * begins, so that its stores do not wait on memory one by one; and a miss's
 * planes, written once and not read while the frame renders, bypass the
 * cache (stream_words), so that memory is not first read to be
 * overwritten. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "fail.h"
#include "render_frame.h"
#include "render_whitted.h"
#include "sdftrace/render.h"
#include "secondary.h"

#define RENDER_STR_(x) #x
#define RENDER_STR(x) RENDER_STR_(x)

sdft_render_params sdft_render_defaults(void)
{
    return (sdft_render_params){
        .trace = sdft_trace_defaults(),
        .width = 1280,
        .height = 720,
        .camera = {.from = {0.0f, 1.0f, 5.0f}, .at = {0.0f, 0.0f, 0.0f}, .up = {0.0f, 1.0f, 0.0f}, .fov_deg = 45.0f},
        .light = {5.0f, 10.0f, 5.0f},
        .shadows = 1,
        .screen_space = 0,
        .cones = 1,
        .threads = 0,
        .materials = 0,
        .material = {.colour = RENDER_ALBEDO, .reflectance = 0.0f, .ior = 0.0f},
        .reflect_bounces = 2,
        .refract_bounces = 8,
        .eps_min = 0.0f,
        .smooth_iters = 0,
        .convex = 1,
        .soft_shadows = 0.0f,
        .ao = 0,
    };
}

void sdft_render_papers(sdft_render_params *p)
{
    if (!p)
        return;
    p->cones = 0;
    p->trace.exact_root = 0;
}

/* The pages of a new image's planes faulted in now, in parallel, a byte
 * written per page: a frame writes every pixel, and a first frame would
 * otherwise take those first touches (on some machines as slow as the
 * trace) one store at a time. */
static void touch_planes(void *const planes[], const size_t bytes[], int count)
{
    enum { PAGE = 4096 };
    for (int p = 0; p < count; p++) {
        unsigned char *b = planes[p];
        const long pages = (long)((bytes[p] + PAGE - 1) / PAGE);
#pragma omp parallel for schedule(static)
        for (long i = 0; i < pages; i++)
            b[(size_t)i * PAGE] = 0;
    }
}

sdft_error sdft_image_alloc(sdft_image *img, int width, int height, char *msg, size_t msg_len)
{
    if (!img)
        return fail_with(msg, msg_len, SDFT_EINVAL, "no image (NULL)");
    memset(img, 0, sizeof *img);
    if (width < 1 || height < 1)
        return fail_with(msg, msg_len, SDFT_EINVAL, "image size %dx%d: both must be at least 1", width, height);
    if ((size_t)width > SIZE_MAX / 16 / (size_t)height)
        return fail_with(msg, msg_len, SDFT_EINVAL, "image size %dx%d is too large", width, height);
    size_t n = (size_t)width * (size_t)height;
    img->width = width, img->height = height;
    img->rgb = malloc(3 * n * sizeof *img->rgb);
    img->depth = malloc(n * sizeof *img->depth);
    img->normal = malloc(3 * n * sizeof *img->normal);
    img->steps = malloc(n * sizeof *img->steps);
    img->fallbacks = malloc(n * sizeof *img->fallbacks);
    img->primary_steps = malloc(n * sizeof *img->primary_steps);
    img->status = malloc(n * sizeof *img->status);
    if (!img->rgb || !img->depth || !img->normal || !img->steps || !img->fallbacks || !img->primary_steps ||
        !img->status) {
        sdft_image_free(img);
        return fail_with(msg, msg_len, SDFT_ENOMEM, "out of memory for a %dx%d image", width, height);
    }
    void *const planes[] = {img->rgb,       img->depth,         img->normal, img->steps,
                            img->fallbacks, img->primary_steps, img->status};
    const size_t bytes[] = {3 * n * sizeof *img->rgb, n * sizeof *img->depth,     3 * n * sizeof *img->normal,
                            n * sizeof *img->steps,   n * sizeof *img->fallbacks, n * sizeof *img->primary_steps,
                            n * sizeof *img->status};
    touch_planes(planes, bytes, 7);
    return SDFT_OK;
}

void sdft_image_free(sdft_image *img)
{
    if (!img)
        return;
    free(img->rgb);
    free(img->depth);
    free(img->normal);
    free(img->steps);
    free(img->fallbacks);
    free(img->primary_steps);
    free(img->status);
    memset(img, 0, sizeof *img);
}

/* The directions of the tile whose first pixel is (x0, y0) into td, all
 * TILE x TILE of them (a tile at the image's edge has some that are never
 * read): sdft_view_ray's, the same operations in the same order (so the
 * same floats), as a loop the compiler vectorizes. */
static void primary_dirs(const sdft_view *v, int x0, int y0, tile_dirs *td)
{
    const int x1 = x0 + TILE, y1 = y0 + TILE;
    const sdft_vec3 tl = v->top_left, r = v->right_per_px, dn = v->down_per_px;
    for (int y = y0; y < y1; y++) {
        const float py = (float)y + 0.5f;
        float *restrict dx = td->d[0] + (y - y0) * TILE, *restrict dy = td->d[1] + (y - y0) * TILE,
                        *restrict dz = td->d[2] + (y - y0) * TILE;
        for (int i = 0; i < x1 - x0; i++) {
            const sdft_vec3 d = render_view_dir(tl, r, dn, (float)(x0 + i) + 0.5f, py);
            dx[i] = d.x, dy[i] = d.y, dz[i] = d.z;
        }
    }
}

/* A pixel's colour and normal given its primary ray's hit, lit as if the
 * light were visible; 1 when that takes a shadow ray, put in *shadow (its
 * hit then goes to shadow_pixel). */
static int shade_pixel(const frame *fr, sdft_scratch *s, sdft_ray ray, sdft_hit h, pixel_result *out, sdft_ray *shadow)
{
    const sdft_field *f = fr->f;
    const sdft_render_params *rp = fr->rp;
    const sdft_trace_params *tp = &fr->tp;
    *out = (pixel_result){.depth = INFINITY,
                          .steps = h.steps,
                          .fallbacks = h.fallbacks,
                          .rays = 1,
                          .primary_steps = h.steps,
                          .primary_fallbacks = h.fallbacks,
                          .status = h.status};
    /* A non-converged ray is shaded as a hit only with the screen-space
     * criterion, whose best candidate is meant to be used (Keinert §3.2). */
    int surface = h.status == SDFT_HIT || (h.status == SDFT_NOT_CONVERGED && tp->pixel_radius > 0.0f);
    if (!surface) {
        out->rgb = render_miss_colour(rp, ray.dir.y);
        return 0;
    }
    out->depth = h.t;
    if (rp->depth_only)
        return 0;
    sdft_vec3 p = sdft_madd(ray.org, ray.dir, h.t);
    /* The exact root's own normal where the trace has one (sdft_hit.normal). */
    const sdft_vec3 n =
        render_facing_normal(render_has_normal(h.normal) ? h.normal : sdft_field_normal(f, s, p), ray.dir);
    out->normal = n;

    sdft_vec3 l = sdft_normalize(sdft_sub(rp->light, p));
    float diffuse = sdft_maxf(sdft_dot(n, l), 0.0f);
    out->rgb = render_lit(diffuse);
    return diffuse > 0.0f && rp->shadows &&
           render_shadow_ray(p, n, render_shadow_lift(*tp, h.t, fr->feature), rp->light, shadow);
}

/* The shadow ray's hit: its counts, and ambient light alone if it hit. */
static void shadow_pixel(sdft_hit h, pixel_result *out)
{
    out->steps += h.steps;
    out->shadow_steps += h.steps;
    out->fallbacks += h.fallbacks;
    out->rays++;
    if (h.status == SDFT_HIT)
        out->rgb = render_lit(0.0f);
}

/* The distance from p to the farthest corner of box b. */
static float farthest_corner(sdft_aabb b, sdft_vec3 p)
{
    float far = 0.0f;
    for (int k = 0; k < 8; k++)
        far = sdft_maxf(
            far, sdft_length(sdft_sub(
                     sdft_v3((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z), p)));
    return far;
}

/* Sums over one tile, added up in tile order after the parallel loop. */
typedef struct tile_stats {
    uint64_t rays, steps, fallbacks, hits, nonconverged;
    uint64_t primary_steps, primary_fallbacks;
    uint64_t shadow_steps, secondary_steps, secondary_rays;
    uint64_t eps_hits, eps_from_f, self_hits;
    uint32_t cone_steps;
} tile_stats;

/* Stores pixel (x, y) into img and the tile's sums. */
static void store_pixel(const frame *fr, int x, int y, const pixel_result *px, sdft_image *img, tile_stats *ts)
{
    size_t i = (size_t)y * (size_t)fr->rp->width + (size_t)x;
    img->rgb[3 * i + 0] = px->rgb.x, img->rgb[3 * i + 1] = px->rgb.y, img->rgb[3 * i + 2] = px->rgb.z;
    img->normal[3 * i + 0] = px->normal.x, img->normal[3 * i + 1] = px->normal.y;
    img->normal[3 * i + 2] = px->normal.z;
    img->depth[i] = px->depth;
    img->steps[i] = px->steps;
    img->fallbacks[i] = px->fallbacks;
    img->primary_steps[i] = px->primary_steps;
    img->status[i] = (uint8_t)px->status;
    ts->rays += px->rays, ts->steps += px->steps, ts->fallbacks += px->fallbacks;
    ts->primary_steps += px->primary_steps, ts->primary_fallbacks += px->primary_fallbacks;
    ts->shadow_steps += px->shadow_steps;
    ts->secondary_steps += px->secondary_steps, ts->secondary_rays += px->secondary_rays;
    ts->eps_hits += px->eps_hits, ts->eps_from_f += px->eps_from_f, ts->self_hits += px->self_hits;
    ts->hits += px->status == SDFT_HIT;
    ts->nonconverged += px->status == SDFT_NOT_CONVERGED;
}

/* Where the primary rays through pixels [x0, x1) x [y0, y1) may start:
 * with cones, as far as sdft_cone_march takes their bundle from `t`. */
static float block_start(const frame *fr, sdft_scratch *s, int x0, int y0, int x1, int y1, float t, tile_stats *ts)
{
    if (!fr->rp->cones)
        return t;
    sdft_vec3 axis;
    const float spread = sdft_view_cone(&fr->view, (float)x0, (float)y0, (float)x1, (float)y1, &axis);
    return sdft_cone_march(fr->f, s, fr->rp->camera.from, axis, spread, t, fr->cone_tfar, &ts->cone_steps);
}

/* Pixels [x0, x1) x [y0, y1), at most BLOCK x BLOCK, primary rays from
 * tnear (or, with span, each on its own [span[0][i], span[1][i]], i its
 * index in the tile whose first pixel is (tx, ty)): their primary rays are traced
 * as one stream (interleaved), then each pixel shaded, then their shadow
 * rays traced as one stream. */
static void render_block(const frame *fr, sdft_scratch *s, int x0, int y0, int x1, int y1, float tnear,
                         const tile_dirs *td, float (*span)[TILE * TILE], int tx, int ty, sdft_image *img,
                         tile_stats *ts)
{
    enum { MOST = BLOCK * BLOCK };
    sdft_ray rays[MOST], shadows[MOST];
    sdft_hit hits[MOST];
    pixel_result px[MOST];
    size_t shadow_of[MOST]; /* the pixel of each shadow ray */
    size_t n = 0, m = 0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++, n++) {
            const int i = (y - ty) * TILE + (x - tx);
            rays[n] = (sdft_ray){.org = fr->view.from,
                                 .tnear = span ? span[0][i] : tnear,
                                 .dir = sdft_v3(td->d[0][i], td->d[1][i], td->d[2][i]),
                                 .tfar = span ? span[1][i] : INFINITY};
        }
    if (n == 0) /* never, as blocks are not empty; saying so spares GCC a false "may be uninitialized" */
        return;
    sdft_trace_stream(fr->f, s, rays, hits, n, &fr->tp);
    if (fr->whitted) {
        for (size_t k = 0; k < n; k++)
            render_whitted_pixel(fr, s, rays[k], hits[k], &px[k]);
    } else {
        for (size_t k = 0; k < n; k++)
            if (shade_pixel(fr, s, rays[k], hits[k], &px[k], &shadows[m]))
                shadow_of[m++] = k;
        sdft_trace_stream(fr->f, s, shadows, hits, m, &fr->tp);
        for (size_t j = 0; j < m; j++)
            shadow_pixel(hits[j], &px[shadow_of[j]]);
    }
    n = 0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++, n++)
            store_pixel(fr, x, y, &px[n], img, ts);
}

/* 0 when no ray from the eye through the image rectangle [x0, x1] x [y0,
 * y1] (pixel units) can meet box b (render_rect_sees_box). */
static int rect_sees_box(const sdft_view *v, float x0, float y0, float x1, float y1, sdft_aabb b)
{
    const sdft_vec3 c = sdft_view_ray(v, 0.5f * (x0 + x1), 0.5f * (y0 + y1)).dir;
    const sdft_vec3 d[4] = {sdft_view_ray(v, x0, y0).dir, sdft_view_ray(v, x1, y0).dir, sdft_view_ray(v, x1, y1).dir,
                            sdft_view_ray(v, x0, y1).dir};
    return render_rect_sees_box(v->from, d, c, b);
}

/* Writes n 32-bit words from src to dst, or n copies of *src when `fill`,
 * bypassing the cache where it can (SSE2's non-temporal stores, dst
 * 16-byte aligned, n a multiple of 4): a miss's planes are written once and
 * not read again while the frame renders, and a plain store would first
 * read each line from memory. The caller fences (stream_fence) before
 * another thread may read them. */
static void stream_words(void *dst, const void *src, size_t n, int fill)
{
    uint32_t w;
    memcpy(&w, src, sizeof w);
#if defined(__SSE2__)
    if (((uintptr_t)dst & 15u) == 0 && (n & 3u) == 0) {
        __m128i *d = dst;
        const __m128i copies = _mm_set1_epi32((int32_t)w);
        for (size_t i = 0; i < n / 4; i++)
            _mm_stream_si128(d + i, fill ? copies : _mm_loadu_si128((const __m128i *)src + i));
        return;
    }
#endif
    if (!fill) {
        memcpy(dst, src, 4 * n);
        return;
    }
    unsigned char *d = dst;
    for (size_t i = 0; i < n; i++)
        memcpy(d + 4 * i, &w, sizeof w);
}

/* Orders this thread's non-temporal stores before what follows. */
static void stream_fence(void)
{
#if defined(__SSE2__)
    _mm_sfence();
#endif
}

/* Pixels [x0, x1) x [y0, y1) of the tile whose first pixel is (tx, ty),
 * directions td, whose rays all miss the field's box: what a trace gives
 * them, without one (sky, or black for depth alone). */
static void miss_rect(const frame *fr, const tile_dirs *td, int tx, int ty, int x0, int y0, int x1, int y1,
                      sdft_image *img)
{
    const int w = fr->rp->width;
    const size_t n = (size_t)(x1 - x0);
    const float inf = INFINITY, zero = 0.0f;
    for (int y = y0; y < y1; y++) {
        const size_t row = (size_t)y * (size_t)w + (size_t)x0;
        const float *restrict dy = td->d[1] + (y - ty) * TILE + (x0 - tx);
        float rgb[3 * TILE];
        for (size_t i = 0; i < n; i++) {
            const sdft_vec3 c = render_miss_colour(fr->rp, dy[i]);
            rgb[3 * i] = c.x, rgb[3 * i + 1] = c.y, rgb[3 * i + 2] = c.z;
        }
        stream_words(img->rgb + 3 * row, rgb, 3 * n, 0);
        stream_words(img->depth + row, &inf, n, 1);
        stream_words(img->normal + 3 * row, &zero, 3 * n, 1);
        stream_words(img->steps + row, &zero, n, 1);
        stream_words(img->fallbacks + row, &zero, n, 1);
        stream_words(img->primary_steps + row, &zero, n, 1);
        memset(img->status + row, SDFT_MISS, n * sizeof *img->status);
    }
}

/* Hints the field (sdft_field_accel.prefetch) at where each ray of the tile's
 * pixels [x0, x1) x [y0, y1) (tile coordinates) enters the hull: its first
 * evaluation, a point no earlier ray of the tile is near, so its memory is
 * mostly far away. Given a block ahead of its trace, the loads overlap the
 * block traced in between. */
static void prefetch_entries(const frame *fr, const tile_dirs *td, float (*span)[TILE * TILE], int x0, int y0, int x1,
                             int y1)
{
    const sdft_vec3 o = fr->view.from;
    const sdft_field_accel *a = fr->f->accel;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            const int i = y * TILE + x;
            if (span[0][i] < INFINITY)
                a->prefetch(a->ctx, sdft_madd(o, sdft_v3(td->d[0][i], td->d[1][i], td->d[2][i]), span[0][i]));
        }
}

/* Starts fetching, for writing, the cache lines of pixels [x0, x1) x [y0,
 * y1) in each plane of img: a tile's stores then find their lines there
 * rather than each waiting for its own. */
static void prefetch_pixels(const sdft_image *img, int x0, int y0, int x1, int y1)
{
    const size_t w = (size_t)img->width, n = (size_t)(x1 - x0);
    for (int y = y0; y < y1; y++) {
        const size_t i = (size_t)y * w + (size_t)x0;
        const char *const from[] = {(const char *)(img->rgb + 3 * i),   (const char *)(img->normal + 3 * i),
                                    (const char *)(img->depth + i),     (const char *)(img->steps + i),
                                    (const char *)(img->fallbacks + i), (const char *)(img->primary_steps + i),
                                    (const char *)(img->status + i)};
        const size_t bytes[] = {3 * n * sizeof *img->rgb, 3 * n * sizeof *img->normal, n * sizeof *img->depth,
                                n * sizeof *img->steps,   n * sizeof *img->fallbacks,  n * sizeof *img->primary_steps,
                                n * sizeof *img->status};
        for (int p = 0; p < 7; p++) {
            const uintptr_t first = (uintptr_t)from[p] & ~(uintptr_t)63, last = (uintptr_t)from[p] + bytes[p] - 1;
            for (uintptr_t a = first; a <= last; a += 64)
                __builtin_prefetch((const void *)a, 1);
        }
    }
}

static void render_tile(const frame *fr, sdft_scratch *s, int tile, sdft_image *img, tile_stats *ts)
{
    const sdft_render_params *rp = fr->rp;
    int tiles_x = (rp->width + TILE - 1) / TILE;
    int x0 = (tile % tiles_x) * TILE, y0 = (tile / tiles_x) * TILE;
    int x1 = x0 + TILE < rp->width ? x0 + TILE : rp->width;
    int y1 = y0 + TILE < rp->height ? y0 + TILE : rp->height;
    *ts = (tile_stats){0};
    tile_dirs td;
    primary_dirs(&fr->view, x0, y0, &td);
    /* A tile whose rays all pass the field's box by, or that no hull box
     * may cover: nothing to trace. */
    if ((fr->bins && fr->bins->first[tile] == fr->bins->first[tile + 1]) ||
        !rect_sees_box(&fr->view, (float)x0, (float)y0, (float)x1, (float)y1, fr->f->bounds)) {
        ts->rays = (uint64_t)(x1 - x0) * (uint64_t)(y1 - y0);
        miss_rect(fr, &td, x0, y0, x0, y0, x1, y1, img);
        return;
    }
    prefetch_pixels(img, x0, y0, x1, y1);
    /* With the hull, each ray on its own span of it; else the tile's
     * bundle, then each BLOCK x BLOCK bundle from there, then each ray
     * from there (all start at 0 without cones). */
    float span[2][TILE * TILE], (*spans)[TILE * TILE] = NULL, t_tile = 0.0f;
    if (fr->bins)
        render_hull_spans(fr->bins, fr->f->accel, fr->rp->camera.from, tile, &td, x0, y0, x1, y1, span), spans = span;
    else
        t_tile = block_start(fr, s, x0, y0, x1, y1, fr->cone_tnear, ts);
    const int hint = spans && fr->f->accel->prefetch;
    if (hint)
        prefetch_entries(fr, &td, spans, 0, 0, BLOCK < x1 - x0 ? BLOCK : x1 - x0, BLOCK < y1 - y0 ? BLOCK : y1 - y0);
    for (int by = y0; by < y1; by += BLOCK)
        for (int bx = x0; bx < x1; bx += BLOCK) {
            const int bx1 = bx + BLOCK < x1 ? bx + BLOCK : x1, by1 = by + BLOCK < y1 ? by + BLOCK : y1;
            if (hint) { /* the next block's */
                const int nx = bx1 < x1 ? bx1 : x0, ny = bx1 < x1 ? by : by1;
                if (ny < y1)
                    prefetch_entries(fr, &td, spans, nx - x0, ny - y0, (nx + BLOCK < x1 ? nx + BLOCK : x1) - x0,
                                     (ny + BLOCK < y1 ? ny + BLOCK : y1) - y0);
            }
            if (spans && !render_block_meets_hull(spans, bx - x0, by - y0, bx1 - x0, by1 - y0)) {
                ts->rays += (uint64_t)(bx1 - bx) * (uint64_t)(by1 - by);
                miss_rect(fr, &td, x0, y0, bx, by, bx1, by1, img);
                continue;
            }
            const float t_block = spans ? 0.0f : block_start(fr, s, bx, by, bx1, by1, t_tile, ts);
            render_block(fr, s, bx, by, bx1, by1, t_block, &td, spans, x0, y0, img, ts);
        }
}

/* What is wrong with the shading beyond the hard shadow, or NULL. */
static const char *shading_problem(const sdft_render_params *rp)
{
    const sdft_material *m = &rp->material;
    if (rp->reflect_bounces < 0 || rp->reflect_bounces > SDFT_MAX_BOUNCES || rp->refract_bounces < 0 ||
        rp->refract_bounces > SDFT_MAX_BOUNCES)
        return "reflect and refract bounces must be in [0, " RENDER_STR(SDFT_MAX_BOUNCES) "]";
    if (!(rp->eps_min >= 0.0f) || !isfinite(rp->eps_min))
        return "eps_min must be a finite number >= 0";
    if (rp->smooth_iters < 0 || rp->smooth_iters > SDFT_MAX_SMOOTH_ITERS)
        return "smoothing iterations must be in [0, " RENDER_STR(SDFT_MAX_SMOOTH_ITERS) "]";
    if (!(rp->soft_shadows >= 0.0f) || !isfinite(rp->soft_shadows))
        return "the soft shadows' k must be a finite number >= 0";
    if (!(sdft_minf(m->colour.x, sdft_minf(m->colour.y, m->colour.z)) >= 0.0f) ||
        !(sdft_maxf(m->colour.x, sdft_maxf(m->colour.y, m->colour.z)) <= 1.0f))
        return "the material's colour must be in [0, 1]";
    if (!(m->reflectance >= 0.0f && m->reflectance <= 1.0f))
        return "the material's reflectance must be in [0, 1]";
    if (!(m->ior == 0.0f || (m->ior >= 1.0f && isfinite(m->ior))))
        return "the material's index of refraction must be 0 (opaque) or a finite number >= 1";
    return NULL;
}

static const char *render_params_problem(const sdft_field *f, const sdft_render_params *rp)
{
    if (!f || !f->distance)
        return "no field, or a field without a distance function";
    if (!rp)
        return "no render parameters (NULL)";
    const sdft_camera *c = &rp->camera;
    if (rp->width < 1 || rp->height < 1)
        return "width and height must be at least 1";
    if (!sdft_isfinite3(c->from) || !sdft_isfinite3(c->at) || !sdft_isfinite3(c->up))
        return "camera from, at and up must be finite";
    if (!(sdft_length(sdft_sub(c->at, c->from)) > 0.0f))
        return "camera from and at must differ";
    if (!(c->fov_deg > 0.0f && c->fov_deg < 180.0f))
        return "field of view must be in (0, 180) degrees";
    if (!sdft_isfinite3(rp->light))
        return "light position must be finite";
    if (rp->threads < 0)
        return "threads must be >= 0";
    return shading_problem(rp);
}

/* The trace parameters of a frame: params' own, with the screen-space
 * criterion's pixel radius where it is asked for. */
static sdft_trace_params frame_trace(const sdft_render_params *params)
{
    sdft_trace_params tp = params->trace;
    if (params->screen_space)
        tp.pixel_radius = sdft_camera_pixel_radius(&params->camera, params->height);
    return tp;
}

sdft_error sdft_render_params_check(const sdft_field *f, const sdft_render_params *params, char *msg, size_t msg_len)
{
    const char *why = render_params_problem(f, params);
    if (why)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s", why);
    const sdft_trace_params tp = frame_trace(params);
    return sdft_trace_params_check(&tp, msg, msg_len);
}

sdft_error sdft_render(const sdft_field *f, const sdft_render_params *params, sdft_image *img, sdft_render_stats *stats,
                       char *msg, size_t msg_len)
{
    const sdft_error rc = sdft_render_params_check(f, params, msg, msg_len);
    if (rc)
        return rc;
    if (!img || img->width != params->width || img->height != params->height || !img->rgb)
        return fail_with(msg, msg_len, SDFT_EINVAL, "the image is not allocated at the render size");
    const sdft_trace_params tp = frame_trace(params);

    int tiles_x = (params->width + TILE - 1) / TILE, tiles_y = (params->height + TILE - 1) / TILE;
    int tiles = tiles_x * tiles_y;
    tile_stats *per_tile = malloc((size_t)tiles * sizeof *per_tile);
    if (!per_tile)
        return fail_with(msg, msg_len, SDFT_ENOMEM, "out of memory for %d tiles", tiles);
    frame fr = {.f = f,
                .rp = params,
                .tp = tp,
                .feature = sdft_field_feature_size(f),
                .view = sdft_camera_view(&params->camera, params->width, params->height),
                .cone_tfar = farthest_corner(f->bounds, params->camera.from),
                .cone_tnear = render_box_distance(f->bounds, params->camera.from)};
    const sdft_field inside = secondary_inside(f);
    fr.whitted = render_whitted_wanted(params);
    fr.inside = &inside;
    fr.ao_reach = 0.02f * sdft_length(sdft_sub(f->bounds.hi, f->bounds.lo));
    int threads = params->threads > 0 ? params->threads : omp_get_max_threads();

    double t0 = omp_get_wtime();
    hull_bins bins = {0};
    if (params->cones && f->accel && f->accel->hull_count &&
        render_eye_outside(f, params->camera.from, fr.cone_tnear)) {
        if (render_hull_bin(f->accel, &fr.view, params->width, params->height, threads, &bins) == 0)
            fr.bins = &bins;
        else /* no memory for the bins: the cones serve, the same picture */
            render_hull_bins_free(&bins);
    }
#pragma omp parallel num_threads(threads)
    {
        sdft_scratch scratch;
        sdft_scratch_init(f, &scratch);
#pragma omp for schedule(dynamic, 1)
        for (int tile = 0; tile < tiles; tile++) {
            /* Summed on the stack, stored once: neighbouring tiles' sums
             * share cache lines, and other threads render those tiles. */
            tile_stats ts;
            render_tile(&fr, &scratch, tile, img, &ts);
            per_tile[tile] = ts;
        }
        stream_fence();
    }
    double t1 = omp_get_wtime();
    render_hull_bins_free(&bins);

    sdft_render_stats st = {.ms = 1000.0 * (t1 - t0),
                            .primary_rays = (uint64_t)params->width * (uint64_t)params->height};
    for (int tile = 0; tile < tiles; tile++) {
        st.rays += per_tile[tile].rays;
        st.steps += per_tile[tile].steps;
        st.fallbacks += per_tile[tile].fallbacks;
        st.primary_steps += per_tile[tile].primary_steps;
        st.primary_fallbacks += per_tile[tile].primary_fallbacks;
        st.hits += per_tile[tile].hits;
        st.nonconverged += per_tile[tile].nonconverged;
        st.cone_steps += per_tile[tile].cone_steps;
        st.shadow_steps += per_tile[tile].shadow_steps;
        st.secondary_steps += per_tile[tile].secondary_steps;
        st.secondary_rays += per_tile[tile].secondary_rays;
        st.dynamic_eps_hits += per_tile[tile].eps_hits;
        st.dynamic_eps_from_f += per_tile[tile].eps_from_f;
        st.secondary_self_hits += per_tile[tile].self_hits;
    }
    free(per_tile);
    if (stats)
        *stats = st;
    return SDFT_OK;
}
