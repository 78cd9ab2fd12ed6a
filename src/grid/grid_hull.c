/* sdftrace — a grid's hull: world boxes that hold every trilinear cell
 * where the field can first reach 0 along a ray (sdft_field_accel.hull), so that
 * a renderer can start each primary ray where it enters the first box and
 * end it where it leaves the last, instead of marching the empty space and
 * the band's far side (render.c).
 *
 * WHY IT HOLDS. Along a ray from a point where the interpolant is positive,
 * the first point where it reaches 0 lies in a MIXED cell: one with a
 * corner <= 0 and a corner > 0 (a cell whose corners are all > 0 is
 * positive throughout). Under the level-set convention the far bound
 * relies on too (grid_bound.c: every inactive voxel c has |s(c)| >= bg,
 * with s's sign; active voxels lie in leaves and hold samples of s), a
 * mixed cell has no inactive corner c when bg > sqrt(3) smax: its corners
 * of opposite signs put a zero of s within a cell's diagonal, sqrt(3)
 * index units, of c, so |s(c)| < bg. So every corner of a mixed cell is an
 * active voxel in a leaf, in particular its lowest corner. Hence the boxes
 * of the mixed cells whose lowest corner lies in each leaf's block, found
 * from the leaf's 8^3 values and the one-voxel apron on its + sides (the
 * next blocks' values, through the leaf directory), hold every first root.
 * The one exception is the active box's faces: a grid that cuts its
 * surface (a baked scene's floor, a clipped terrain) holds values <= 0,
 * in leaves or in tiles, next to the inactive background outside, and the
 * cells between may have both signs with an inactive corner; each patch of
 * a face where that can happen gets its own box (scan_faces). Each box is
 * grown by half a voxel all round for rounding (the world transform, the
 * renderer's ray-box tests). A leaf without a mixed cell gets no box.
 * Each leaf's box comes with a slab along the surface that holds the same
 * cells (THE SLAB, add_leaf), so a ray's part in both is all it needs;
 * a face patch's slab is everywhere.
 *
 * WHERE A RAY STARTS. That covers rays that start where the field is
 * positive. A primary ray starts at the eye, or where it enters the grid's
 * box; the renderer checks the eye, and scan_faces checks that the voxels
 * just outside the active box are all positive (so a ray entering the box
 * starts in a positive cell or in a face patch's box), else there is no
 * hull.
 *
 * WHEN THERE IS NONE. Level sets with a band wider than sqrt(3) voxels,
 * of a type with a leaf directory, loaded whole: a deferred grid's leaves
 * are read only where a ray reaches them, and a hull would read them all
 * (such grids keep the cones, render.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "grid_cell.h"

typedef struct hull_fill {
    const sdft_grid *g;
    sdft_aabb *box;
    sdft_slab *slab;     /* with each box */
    sdft_aabb *gradient; /* with each box */
    size_t most, count;  /* count: atomic */
} hull_fill;

/* Bit z of row[x][y] (x, y, z in 0..8): voxel 8b + (x, y, z) is <= 0
 * (neg) or > 0 (pos); a NaN sets neither. */
typedef struct block_signs {
    uint16_t neg[9][9], pos[9][9];
    float value[9][9][9];
} block_signs;

/* The values of voxels 8b + (x, y, z) for x, y, z in xs, ys, zs (ranges
 * [first, last] of 0..8, all on one side of 8 each: one block's) into
 * value[x][y][z]: from the directory entry w of their block (a leaf's
 * table, or a tile), or, where it has none (w 0), through the accessor. */
static void gather_part(const sdft_grid *g, pnanovdb_readaccessor_t *acc, const int32_t b[3], uint32_t w,
                        const int r[3][2], float value[9][9][9])
{
    for (int x = r[0][0]; x <= r[0][1]; x++)
        for (int y = r[1][0]; y <= r[1][1]; y++)
            for (int z = r[2][0]; z <= r[2][1]; z++) {
                if (w) {
                    value[x][y][z] = entry_value(g, g->type, w,
                                                 64u * (uint32_t)(x & 7) + 8u * (uint32_t)(y & 7) + (uint32_t)(z & 7));
                } else {
                    uint32_t level;
                    value[x][y][z] = read_value(g, g->type, acc,
                                                (pnanovdb_coord_t){8 * b[0] + x, 8 * b[1] + y, 8 * b[2] + z}, &level);
                }
            }
}

/* The values of the voxels of block b and of its apron, and their signs:
 * its own leaf's values (table word w), the next blocks' leaves or tiles
 * through the directory, the accessor where the directory has no entry. */
static void gather_signs(const sdft_grid *g, pnanovdb_readaccessor_t *acc, const int32_t b[3], uint32_t w,
                         block_signs *s)
{
    const int32_t c0[3] = {8 * b[0], 8 * b[1], 8 * b[2]};
    uint32_t local = 0;
    const uint32_t *e = NULL;
    if (!directory_chunk(g, c0, &local, &e))
        e = NULL;
    if (g->type == PNANOVDB_GRID_TYPE_FLOAT) { /* the leaf's own 512 floats, rows of 8 along z */
        const uint32_t *v = g->words + w;
        for (int x = 0; x < 8; x++)
            for (int y = 0; y < 8; y++)
                memcpy(s->value[x][y], v + 64 * x + 8 * y, 8 * sizeof(float));
    } else {
        const int own[3][2] = {{0, 7}, {0, 7}, {0, 7}};
        gather_part(g, acc, b, w, own, s->value);
    }
    for (int k = 1; k < 8; k++) { /* the apron: the chunk holds the next blocks too */
        const int ax = k & 1, ay = k >> 1 & 1, az = k >> 2;
        const int r[3][2] = {{ax ? 8 : 0, ax ? 8 : 7}, {ay ? 8 : 0, ay ? 8 : 7}, {az ? 8 : 0, az ? 8 : 7}};
        const uint32_t entry = e ? e[local + (uint32_t)ax + GRID_CHUNK_SIDE * (uint32_t)ay +
                                     GRID_CHUNK_SIDE * GRID_CHUNK_SIDE * (uint32_t)az]
                                 : 0u;
        gather_part(g, acc, b, entry, r, s->value);
    }
    for (int x = 0; x < 9; x++)
        for (int y = 0; y < 9; y++) {
            uint16_t neg = 0, pos = 0;
            for (int z = 0; z < 9; z++) {
                const float v = s->value[x][y][z];
                neg |= (uint16_t)((v <= 0.0f) << z); /* NaN: neither, so its cells count as mixed */
                pos |= (uint16_t)((v > 0.0f) << z);
            }
            s->neg[x][y] = neg, s->pos[x][y] = pos;
        }
}

/* The block's values' slope: the sum of v (x - 4, y - 4, z - 4) over its
 * 9^3 finite values, in that order (the sums' rounding is the hull's). */
static void block_slope(const block_signs *s, double slope[3])
{
    slope[0] = slope[1] = slope[2] = 0.0;
    for (int x = 0; x < 9; x++)
        for (int y = 0; y < 9; y++)
            for (int z = 0; z < 9; z++) {
                const float v = s->value[x][y][z];
                if (isfinite(v))
                    slope[0] += v * (x - 4), slope[1] += v * (y - 4), slope[2] += v * (z - 4);
            }
}

/* A box for the cells whose lowest corners span [first, last]: those
 * cells, half a voxel more all round, in world units; with the slab
 * {x : lo <= n . x <= hi} of index space in world units (n . x = n . (A w
 * + t) = (A^T n) . w + n . t for the world-to-index map x = A w + t), or
 * with the slab that is everywhere (n NULL); and with the box of index
 * gradients [g_lo, g_hi] in world units (a world gradient is A^T times the
 * index one: the box's centre maps to the centre, its half-widths through
 * |A^T|, widened by a millionth for rounding), or every gradient (g_lo
 * NULL, or a bound that is not finite). */
static void add_cells(hull_fill *h, const int32_t first[3], const int32_t last[3], const double *n, double lo_n,
                      double hi_n, const double *g_lo, const double *g_hi)
{
    float lo[3], hi[3];
    for (int k = 0; k < 3; k++)
        lo[k] = (float)first[k] - 0.5f, hi[k] = (float)last[k] + 1.5f;
    const float *a = h->g->w2i, *t = h->g->w2i_t;
    sdft_slab slab = {{0.0f, 0.0f, 0.0f}, -INFINITY, INFINITY};
    if (n) {
        double w[3], nt = 0.0;
        for (int c = 0; c < 3; c++)
            w[c] = n[0] * a[c] + n[1] * a[3 + c] + n[2] * a[6 + c], nt += n[c] * t[c];
        slab = (sdft_slab){{(float)w[0], (float)w[1], (float)w[2]}, (float)(lo_n - nt), (float)(hi_n - nt)};
    }
    sdft_aabb gradient = {{-INFINITY, -INFINITY, -INFINITY}, {INFINITY, INFINITY, INFINITY}};
    int bounded = g_lo != NULL;
    for (int k = 0; k < 3 && bounded; k++)
        bounded = isfinite(g_lo[k]) && isfinite(g_hi[k]);
    if (bounded) {
        float glo[3], ghi[3];
        for (int c = 0; c < 3; c++) {
            double centre = 0.0, half = 0.0;
            for (int k = 0; k < 3; k++)
                centre += a[3 * k + c] * 0.5 * (g_lo[k] + g_hi[k]),
                    half += fabs(a[3 * k + c]) * 0.5 * (g_hi[k] - g_lo[k]);
            half += 1e-6 * (fabs(centre) + half);
            glo[c] = (float)(centre - half), ghi[c] = (float)(centre + half);
        }
        gradient = (sdft_aabb){{glo[0], glo[1], glo[2]}, {ghi[0], ghi[1], ghi[2]}};
    }
    const size_t i = __atomic_fetch_add(&h->count, 1, __ATOMIC_RELAXED);
    if (i < h->most)
        h->box[i] = grid_world_box(h->g, lo, hi), h->slab[i] = slab, h->gradient[i] = gradient;
}

/* THE GRADIENT. In cell (x, y, z) the interpolant's derivative along index
 * axis k is the bilinear blend, over the cell's other two coordinates, of
 * its four k edges' differences (cell_edges), so at every point of the
 * closed cell it lies between the least and the greatest of the four.
 * Over the mixed cells (mixed[x][y], bit z), [lo, hi] on each axis is
 * the least and the greatest difference along an edge of one of them,
 * each edge taken once; a NaN there leaves the axis unbounded. */
static void gradient_bounds(const block_signs *s, const uint8_t mixed[8][8], double lo[3], double hi[3])
{
    /* For each axis k, edges (a, a + e_k) with a_k in 0..7 and the other
     * two coordinates in 0..8; an edge belongs to the cells c with c_k =
     * a_k and each other c_p in {a_p - 1, a_p}. The loops go over (u, w), u
     * the first axis that is not k (0..8) and w the edge's k coordinate,
     * with the cells of each such row as bits over the last axis. t[x][z]:
     * mixed's bits turned to run over y, for edges along z. */
    uint16_t t[8][8] = {{0}};
    for (int x = 0; x < 8; x++)
        for (int y = 0; y < 8; y++)
            for (int z = 0; z < 8; z++)
                t[x][z] |= (uint16_t)((mixed[x][y] >> z & 1u) << y);
    for (int k = 0; k < 3; k++) {
        double l = INFINITY, h = -INFINITY;
        int nan = 0;
        for (int w = 0; w < 8; w++)
            for (int u = 0; u < 9; u++) {
                unsigned cells = 0; /* over the last axis: cells at u - 1 and u */
                for (int c = u - 1; c <= u; c++)
                    if (c >= 0 && c < 8)
                        cells |= k == 0 ? mixed[w][c] : k == 1 ? mixed[c][w] : t[c][w];
                const unsigned edges = cells | cells << 1;
                for (int v = 0; v < 9; v++) {
                    if (!(edges >> v & 1u))
                        continue;
                    /* (x, y, z) of the edge's start: k = 0: (w, u, v); 1: (u, w, v); 2: (u, v, w). */
                    const int x = k == 0 ? w : u, y = k == 0 ? u : k == 1 ? w : v, z = k == 2 ? w : v;
                    const double d =
                        (double)s->value[x + (k == 0)][y + (k == 1)][z + (k == 2)] - (double)s->value[x][y][z];
                    nan |= d != d;
                    l = d < l ? d : l, h = d > h ? d : h;
                }
            }
        lo[k] = nan ? -INFINITY : l, hi[k] = nan ? INFINITY : h;
    }
}

/* Bit z: cell (x, y, z) of the block is mixed, its eight corners (rows
 * x..x+1 by y..y+1, bits z..z+1) neither all <= 0 nor all > 0. */
static unsigned mixed_cells(const block_signs *s, int x, int y)
{
    const unsigned all_neg = (unsigned)(s->neg[x][y] & s->neg[x + 1][y] & s->neg[x][y + 1] & s->neg[x + 1][y + 1]),
                   all_pos = (unsigned)(s->pos[x][y] & s->pos[x + 1][y] & s->pos[x][y + 1] & s->pos[x + 1][y + 1]);
    return ~((all_neg & all_neg >> 1) | (all_pos & all_pos >> 1)) & 0xFFu;
}

static void add_leaf(void *ctx, const int32_t b[3], uint64_t at, uint32_t word)
{
    (void)at;
    hull_fill *h = ctx;
    const sdft_grid *g = h->g;
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(&acc, g->root);
    block_signs s;
    gather_signs(g, &acc, b, word, &s);
    uint8_t mixed[8][8];
    unsigned any = 0;
    for (int x = 0; x < 8; x++)
        for (int y = 0; y < 8; y++)
            any |= mixed[x][y] = (uint8_t)mixed_cells(&s, x, y);
    if (!any)
        return;
    /* THE SLAB. With n the unit vector along the block's values' slope (the
     * least-squares gradient of a linear field over the 9^3 voxels), cell
     * (x, y, z) spans n . (x, y, z) + [sum of n's negative components, sum
     * of its positive ones] along n; over the mixed cells, and half a voxel
     * more each way for rounding, as the box. The slab holds every mixed
     * cell whatever n is; n along the surface makes it thinner than the
     * box where the surface runs aslant of the axes. No slope (all values
     * equal, or not finite): the box alone. */
    double slope[3];
    block_slope(&s, slope);
    const double len = sqrt(slope[0] * slope[0] + slope[1] * slope[1] + slope[2] * slope[2]);
    const int sloped = len > 0.0 && isfinite(len);
    const double n[3] = {sloped ? slope[0] / len : 0.0, sloped ? slope[1] / len : 0.0, sloped ? slope[2] / len : 0.0};
    int lo[3] = {8, 8, 8}, hi[3] = {-1, -1, -1};
    double p_lo = INFINITY, p_hi = -INFINITY, g_lo[3], g_hi[3];
    for (int x = 0; x < 8; x++)
        for (int y = 0; y < 8; y++) {
            const unsigned m = mixed[x][y];
            if (!m)
                continue;
            const int z0 = __builtin_ctz(m), z1 = 31 - __builtin_clz(m);
            lo[0] = x < lo[0] ? x : lo[0], hi[0] = x > hi[0] ? x : hi[0];
            lo[1] = y < lo[1] ? y : lo[1], hi[1] = y > hi[1] ? y : hi[1];
            lo[2] = z0 < lo[2] ? z0 : lo[2], hi[2] = z1 > hi[2] ? z1 : hi[2];
            const double at = n[0] * x + n[1] * y, a0 = at + n[2] * z0, a1 = at + n[2] * z1;
            p_lo = fmin(p_lo, fmin(a0, a1)), p_hi = fmax(p_hi, fmax(a0, a1));
        }
    gradient_bounds(&s, mixed, g_lo, g_hi);
    int32_t first[3], last[3];
    for (int k = 0; k < 3; k++)
        first[k] = 8 * b[k] + lo[k], last[k] = 8 * b[k] + hi[k];
    double reach_lo = 0.0, reach_hi = 0.0;
    for (int k = 0; k < 3; k++)
        reach_lo += n[k] < 0.0 ? n[k] : 0.0, reach_hi += n[k] > 0.0 ? n[k] : 0.0;
    const double origin = n[0] * (8.0 * b[0]) + n[1] * (8.0 * b[1]) + n[2] * (8.0 * b[2]);
    add_cells(h, first, last, sloped ? n : NULL, origin + p_lo + reach_lo - 0.5, origin + p_hi + reach_hi + 0.5, g_lo,
              g_hi);
}

/* The blocks along axis k that a face's patches span: the active box and
 * a voxel more on each side. */
static int32_t first_patch(const sdft_grid *g, int k) { return (g->ilo[k] - 1) >> 3; }
static int32_t last_patch(const sdft_grid *g, int k) { return (g->ihi[k] + 1) >> 3; }

/* The active box's faces, by 8 x 8 patches of voxels aligned to blocks:
 * for each face, the layer just outside the box (`at` = ilo - 1 or ihi + 1
 * across axis k) must be all > 0, and each patch of the layer just inside
 * (ilo or ihi) that holds a voxel <= 0 (or NaN) gets a box around the
 * cells between the two layers there: the box cuts the surface, and those
 * cells may have both signs with an inactive corner outside, which the
 * leaves' boxes do not promise to hold (a leaf's or a tile's patch alike).
 * A patch inside one tile is read once. Returns 0 when an outside voxel is
 * <= 0 (or NaN): then no hull. */
static int scan_faces(const sdft_grid *g, hull_fill *h)
{
    int ok = 1;
    for (int face = 0; face < 6; face++) {
        const int k = face >> 1, high = face & 1, u = (k + 1) % 3, v = (k + 2) % 3;
        const int32_t inner = high ? g->ihi[k] : g->ilo[k], outer = high ? inner + 1 : inner - 1;
        const int32_t a0 = first_patch(g, u), a1 = last_patch(g, u), c0 = first_patch(g, v), c1 = last_patch(g, v);
#pragma omp parallel for schedule(dynamic, 4) reduction(& : ok)
        for (int32_t pa = a0; pa <= a1; pa++) {
            pnanovdb_readaccessor_t acc;
            pnanovdb_readaccessor_init(&acc, g->root);
            for (int32_t pc = c0; pc <= c1 && ok; pc++)
                for (int layer = 0; layer < 2; layer++) {
                    const int32_t at = layer ? inner : outer;
                    int any = 0;
                    for (int q = 0; q < 64 && !any; q++) {
                        int32_t p[3];
                        p[k] = at, p[u] = 8 * pa + (q >> 3), p[v] = 8 * pc + (q & 7);
                        uint32_t level;
                        const float val = read_value(g, g->type, &acc, (pnanovdb_coord_t){p[0], p[1], p[2]}, &level);
                        any = !(val > 0.0f);
                        if (level > 0 && q == 0 && !any)
                            break; /* the patch lies in one tile (or the background), all > 0 */
                    }
                    if (!any)
                        continue;
                    if (!layer) {
                        ok = 0;
                        break;
                    }
                    /* Cells with lowest corner between the layers, and a voxel round the patch. */
                    int32_t first[3], last[3];
                    first[k] = last[k] = high ? inner : outer;
                    first[u] = 8 * pa - 1, last[u] = 8 * pa + 7;
                    first[v] = 8 * pc - 1, last[v] = 8 * pc + 7;
                    add_cells(h, first, last, NULL, 0.0, 0.0, NULL, NULL);
                }
        }
    }
    return ok;
}

int grid_hull_wanted(const sdft_grid *g)
{
    return g->grid_class == PNANOVDB_GRID_CLASS_LEVEL_SET && g->background > 1.7320508f * g->sigma_max &&
           g->leaves.top && !g->deferred.state &&
           pnanovdb_tree_get_node_count_leaf(g->buf, pnanovdb_grid_get_tree(g->buf, g->grid)) > 0;
}

uint64_t grid_hull_most(const sdft_grid *g)
{
    uint64_t most = pnanovdb_tree_get_node_count_leaf(g->buf, pnanovdb_grid_get_tree(g->buf, g->grid));
    for (int k = 0; k < 3; k++) { /* a box per leaf and per face patch at most */
        const int u = (k + 1) % 3, v = (k + 2) % 3;
        most += 2 * (uint64_t)(last_patch(g, u) - first_patch(g, u) + 1) *
                (uint64_t)(last_patch(g, v) - first_patch(g, v) + 1);
    }
    return most;
}

sdft_error grid_hull_build(sdft_grid *g)
{
    g->hull = NULL, g->hull_slab = NULL, g->hull_gradient = NULL, g->hull_count = 0, g->hull_stored = 0;
    if (!grid_hull_wanted(g))
        return SDFT_OK;
    const uint64_t most = grid_hull_most(g);
    if (most > SIZE_MAX / sizeof(sdft_aabb))
        return SDFT_OK;
    hull_fill h = {g,
                   malloc((size_t)most * sizeof(sdft_aabb)),
                   malloc((size_t)most * sizeof(sdft_slab)),
                   malloc((size_t)most * sizeof(sdft_aabb)),
                   (size_t)most,
                   0};
    if (!h.box || !h.slab || !h.gradient) {
        free(h.box), free(h.slab), free(h.gradient);
        return SDFT_ENOMEM;
    }
    if (!scan_faces(g, &h)) { /* the box cuts the surface where outside is not positive: no hull */
        free(h.box), free(h.slab), free(h.gradient);
        return SDFT_OK;
    }
    grid_each_leaf(g, add_leaf, &h);
    g->hull = h.box, g->hull_slab = h.slab, g->hull_gradient = h.gradient;
    g->hull_count = h.count < h.most ? h.count : h.most;
    return SDFT_OK;
}

void grid_hull_free(sdft_grid *g)
{
    if (!g->hull_stored)
        free(g->hull), free(g->hull_slab), free(g->hull_gradient);
    g->hull = NULL, g->hull_slab = NULL, g->hull_gradient = NULL, g->hull_count = 0, g->hull_stored = 0;
}
