/* sdftrace — the far bound of a grid: a coarse distance transform of the
 * tree's leaves, built once at load time, so that a ray far from the surface
 * steps by its distance to the nearest leaf instead of by one tile.
 *
 * THE CELLS. Index space is cut into cubes of S = 4 * 2^k voxels (S = 4: an
 * eighth of a leaf; k > 0 only when the grid is too big for the cap below),
 * aligned to multiples of S. Cell j is the region [jS - 1/2, jS + S - 1/2)^3:
 * exactly the points whose nearest voxel centre (each coordinate rounded)
 * lies in the S^3 block of voxels [jS, jS + S - 1]^3. A cell is OCCUPIED
 * when its block holds an active voxel (or inactive values of both signs); U
 * is the union of occupied cells, over the domain D: the cells covering the
 * active voxels' index box.
 *
 * THE BOUND. Level-set convention (as for the tree bound, grid_sample.c):
 * every inactive voxel c (in a tile, or inactive in a leaf) has |s(c)| >=
 * bg, the background, and the sign of its value; the active voxels lie in D
 * by D's definition. Then
 *   1. Every point y outside U rounds to an inactive voxel centre c at most
 *      sqrt(3)/2 index units away, so |s(y)| >= r0 = bg - smax
 *      sqrt(3)/2 > 0 (smax, smin: the transform's singular-value bounds):
 *      the surface Z lies inside U.
 *   2. Let x lie outside U, at index distance e(x) from U, and let y be its
 *      nearest surface point. The segment x -> y enters U's closure at some
 *      z with |x - z| >= e(x) index units, and |s(z)| >= r0 by continuity, so
 *      |x - y| = |x - z| + |z - y| >= smin e(x) + r0 in world units.
 *   3. The traced surface is the zero set Zt of the trilinear interpolant. A
 *      sign change in a trilinear cell means a sign change along one of its
 *      edges (the cube's edges connect its corners); with the stored values
 *      the samples of s at the corners (a bake), s has a zero on that edge,
 *      at most sqrt(2) index units from any point of the cell (inactive
 *      values carry s's sign, which is all this uses). So every point
 *      of Zt lies within smax sqrt(2) of Z, and
 *          dist(x, Zt) >= smin e(x) + bg - smax (sqrt(3)/2 + sqrt(2)),
 *      which bounds dist(x, Z) too. We use the right side (the band bonus
 *      clamped at 0: 0.72 voxels for the default 3-voxel band).
 * e(x) comes from the lattice of cell corners: a corner's distance to U is
 * its Euclidean distance to the nearest corner of an occupied cell (the
 * nearest point of an axis-aligned lattice box to a lattice point is one of
 * its corners), found exactly by a separable distance transform (the lower
 * envelope of parabolas along each axis in turn). Between corners, with d_i
 * the corners' distances and w_i the trilinear weights of x in its cell,
 *     e(x) >= d_i - |x - v_i| for each i (e is 1-Lipschitz), so
 *     e(x) >= sum w_i d_i - sum w_i |x - v_i|
 *          >= sum w_i d_i - sqrt(sum w_i |x - v_i|^2)        (Jensen)
 *           = trilerp(d)(x) - S sqrt(sum_k t_k (1 - t_k)),
 * since the weights factor per axis and the axis-k term is the variance
 * S^2 t_k (1 - t_k) of a two-point law. The bound is continuous (the
 * correction vanishes on the cell faces where a weight does) and costs
 * eight 16-bit corner reads and one square root: no tree walk far from the
 * surface, and no jumps to upset enhanced and auto sphere tracing's slope
 * estimates. The sign is the cell's tile sign, read from the tree here. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "grid_cell.h"

enum { MAX_CELLS = 1 << 24 }; /* 16M cells: ~34 MiB of corners (distance and sign) */

/* floor(a / b) for b > 0. */
static int32_t floor_div(int32_t a, int32_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

/* One line of the exact 1-D squared distance transform (Felzenszwalb and
 * Huttenlocher's lower envelope of parabolas): out[q] = min_p (q - p)^2 +
 * f[p]. f may hold HUGE_VAL for "no site". v, z: scratch of n and n + 1. */
static void edt_line(const double *f, double *out, int n, int *v, double *z)
{
    int k = -1;
    for (int q = 0; q < n; q++) {
        if (f[q] >= HUGE_VAL)
            continue;
        double s = -HUGE_VAL;
        while (k >= 0) {
            s = ((f[q] + (double)q * q) - (f[v[k]] + (double)v[k] * v[k])) / (2.0 * (q - v[k]));
            if (s > z[k])
                break;
            k--;
        }
        k++;
        v[k] = q;
        z[k] = k == 0 ? -HUGE_VAL : s;
        z[k + 1] = HUGE_VAL;
    }
    if (k < 0) {
        for (int q = 0; q < n; q++)
            out[q] = HUGE_VAL;
        return;
    }
    int j = 0;
    for (int q = 0; q < n; q++) {
        while (z[j + 1] < q)
            j++;
        out[q] = (double)(q - v[j]) * (q - v[j]) + f[v[j]];
    }
}

enum { LANES = 16 }; /* adjacent x lines transformed together: a cache line of floats per gather */

/* The squared distances are stored as floats between passes (half the
 * memory of doubles): sums of squared integers, exact below 2^24 cells^2;
 * above, clamped there, which only lowers a distance of 4096 cells or more
 * (still a bound; the corners saturate at 4096 voxels anyway). No site
 * stays infinite. */
#define SQUARED_MOST 16777216.0
static inline float squared_store(double v)
{
    return v < SQUARED_MOST ? (float)v : v >= HUGE_VAL ? INFINITY : (float)SQUARED_MOST;
}

/* The first pass, along x, of a transform whose input is sites (0) and no
 * site (INFINITY): each value's squared distance to the nearest site on its
 * line, in place. That is the lower envelope of edt_line for such input (the
 * parabolas all have f = 0), found by two sweeps: the distance to the last
 * site before, then to the next site after. */
static void nearest_site_line(float *line, int n)
{
    int last = -1;
    for (int q = 0; q < n; q++) {
        if (line[q] == 0.0f)
            last = q;
        line[q] = last >= 0 ? (float)(q - last) : INFINITY;
    }
    int next = -1;
    for (int q = n - 1; q >= 0; q--) {
        if (line[q] == 0.0f)
            next = q;
        const float after = next >= 0 ? (float)(next - q) : INFINITY;
        const float nearest = line[q] < after ? line[q] : after;
        line[q] = squared_store((double)nearest * nearest);
    }
}

/* Squared distance transform of d (n[0] x n[1] x n[2], x fastest), in
 * place, for input d = 0 at the sites and INFINITY elsewhere: the 1-D
 * transform along x (nearest_site_line), then y, then z. Along y and z a
 * line's values are a row apart, so LANES lines with adjacent x go
 * together and each gather reads LANES contiguous values; lines run in
 * parallel. */
static int edt3(float *d, const int n[3])
{
    const int m = n[0] > n[1] ? (n[0] > n[2] ? n[0] : n[2]) : (n[1] > n[2] ? n[1] : n[2]);
    const size_t stride[3] = {1, (size_t)n[0], (size_t)n[0] * (size_t)n[1]};
    int failed = 0;
#pragma omp parallel reduction(| : failed)
    {
        double *f = malloc(sizeof(double) * (size_t)m * LANES), *o = malloc(sizeof(double) * (size_t)m * LANES);
        double *z = malloc(sizeof(double) * (size_t)(m + 1));
        int *v = malloc(sizeof(int) * (size_t)m);
        failed = !f || !o || !z || !v;
        for (int axis = 0; axis < 3; axis++) {
            /* Work items: (line group, other axis' index); x lines are single. */
            const int other = axis == 2 ? 1 : 2;
            const int across = axis == 0 ? n[1] : (n[0] + LANES - 1) / LANES, outer = axis == 0 ? n[2] : n[other];
#pragma omp for schedule(dynamic, 16)
            for (long item = 0; item < (long)across * outer; item++) {
                if (failed)
                    continue;
                const int i = (int)(item % across), j = (int)(item / across);
                if (axis == 0) {
                    nearest_site_line(d + (size_t)i * stride[1] + (size_t)j * stride[2], n[0]);
                    continue;
                }
                float *line = d + (size_t)i * LANES + (size_t)j * stride[other];
                const int count = n[0] - i * LANES < LANES ? n[0] - i * LANES : LANES;
                for (int q = 0; q < n[axis]; q++)
                    for (int l = 0; l < count; l++)
                        f[(size_t)l * m + q] = line[(size_t)q * stride[axis] + l];
                for (int l = 0; l < count; l++)
                    edt_line(f + (size_t)l * m, o + (size_t)l * m, n[axis], v, z);
                for (int q = 0; q < n[axis]; q++)
                    for (int l = 0; l < count; l++)
                        line[(size_t)q * stride[axis] + l] = squared_store(o[(size_t)l * m + q]);
            }
        }
        free(f), free(o), free(z), free(v);
    }
    return failed ? -1 : 0;
}

/* The value of voxel ijk, its tree level, and (in a leaf) whether any voxel
 * of the 4^3 block holding ijk is active. */
static float probe(const sdft_grid *g, pnanovdb_readaccessor_t *acc, pnanovdb_coord_t ijk, uint32_t *level, int *active)
{
    pnanovdb_address_t a = pnanovdb_readaccessor_get_value_address_and_level(g->type, g->buf, acc, &ijk, level);
    *active = 0;
    if (*level == 0 && g->deferred.state) { /* a deferred leaf, maybe not filled: occupied (grid_deferred.c) */
        *active = 1;
        return 0.0f;
    }
    if (*level == 0) {
        /* Mask word w holds leaf offsets 32w..32w+31: x = w / 2, y = 4 (w & 1)
         * + bit / 8, z = bit % 8 (offset = 64 x + 8 y + z). */
        const uint32_t x0 = (uint32_t)ijk.x & 4u, yh = (uint32_t)ijk.y >> 2 & 1u;
        const uint32_t zmask = ((uint32_t)ijk.z & 4u) ? 0xF0F0F0F0u : 0x0F0F0F0Fu;
        pnanovdb_address_t mask = pnanovdb_address_offset(acc->leaf.address, PNANOVDB_LEAF_OFF_VALUE_MASK);
        for (uint32_t x = x0; x < x0 + 4u; x++)
            *active |= (pnanovdb_read_uint32(g->buf, pnanovdb_address_offset(mask, 4u * (2u * x + yh))) & zmask) != 0;
        return 0.0f; /* the leaf's values: block_sign */
    }
    /* Tiles hold floats (doubles in a double grid), quantized grids too. */
    return g->type == PNANOVDB_GRID_TYPE_DOUBLE ? (float)pnanovdb_read_double(g->buf, a)
                                                : pnanovdb_read_float(g->buf, a);
}

/* The sign of the voxels of the inactive 4^3 block at o, which lies in the
 * leaf `acc` holds: +1 or -1, the sign of its first voxel. All its voxels
 * share it under the level-set convention this bound rests on: two
 * adjacent voxels of opposite signs have the surface between them, so one
 * of them lies within half a voxel of it, nearer than the background, and
 * would be active. (Reading one value instead of 64 makes the far bound of
 * a 4096^3 grid an order of magnitude quicker to build.) */
static int8_t block_sign(const sdft_grid *g, pnanovdb_readaccessor_t *acc, pnanovdb_coord_t o)
{
    uint32_t level;
    pnanovdb_address_t a = pnanovdb_readaccessor_get_value_address_and_level(g->type, g->buf, acc, &o, &level);
    float v;
    switch (g->type) {
    case PNANOVDB_GRID_TYPE_FLOAT:
        v = pnanovdb_read_float(g->buf, a);
        break;
    case PNANOVDB_GRID_TYPE_DOUBLE:
        v = (float)pnanovdb_read_double(g->buf, a);
        break;
    case PNANOVDB_GRID_TYPE_FP16:
        v = pnanovdb_root_fp16_read_float(g->buf, a, &o, level);
        break;
    case PNANOVDB_GRID_TYPE_FP8:
        v = pnanovdb_root_fp8_read_float(g->buf, a, &o, level);
        break;
    case PNANOVDB_GRID_TYPE_FP4:
        v = pnanovdb_root_fp4_read_float(g->buf, a, &o, level);
        break;
    default:
        v = pnanovdb_root_fpn_read_float(g->buf, a, &o, level);
    }
    return v < 0.0f ? -1 : 1;
}

static inline int8_t pick(int8_t a, int8_t b, int max) { return max ? (a > b ? a : b) : (a < b ? a : b); }

/* dst = the min (or max, if `max`) of src over each cell and its two
 * neighbours along `axis` (n[0] x n[1] x n[2] cells, x fastest), a row of
 * x at a time: along y and z the neighbours are whole rows. */
static void extreme3(int8_t *dst, const int8_t *src, const int n[3], int axis, int max)
{
#pragma omp parallel for schedule(static)
    for (int z = 0; z < n[2]; z++)
        for (int y = 0; y < n[1]; y++) {
            const size_t row = ((size_t)z * n[1] + (size_t)y) * n[0];
            const int8_t *in = src + row;
            int8_t *out = dst + row;
            if (axis == 0) {
                for (int x = 0; x < n[0]; x++) {
                    int8_t e = in[x];
                    if (x > 0)
                        e = pick(e, in[x - 1], max);
                    if (x + 1 < n[0])
                        e = pick(e, in[x + 1], max);
                    out[x] = e;
                }
                continue;
            }
            const int c = axis == 1 ? y : z, len = n[axis];
            const size_t s = axis == 1 ? (size_t)n[0] : (size_t)n[0] * n[1];
            const int8_t *before = c > 0 ? in - s : in, *after = c + 1 < len ? in + s : in;
            for (int x = 0; x < n[0]; x++)
                out[x] = pick(pick(before[x], in[x], max), after[x], max);
        }
}

/* The cells' signs: 0 occupied (an active voxel, or tiles or inactive voxels
 * of both signs), else +1 / -1 the sign of all its voxels. Returns non-zero
 * when out of memory. */
static void classify_by_tree(const sdft_grid *g, grid_far *far, int8_t *sign)
{
    static const int log2_dim[5] = {2, 3, 7, 12, 12}; /* a leaf is probed per 4^3 block */
    const int S = far->cell, per = S / 4;
    const int *n = far->n;
    const size_t cells = (size_t)n[0] * n[1] * n[2];
    memset(sign, 2, cells); /* 2: not seen yet */
    /* Each thread probes whole z slabs of cells, so writes never meet. */
#pragma omp parallel
    {
        pnanovdb_readaccessor_t acc;
        pnanovdb_readaccessor_init(&acc, g->root);
#pragma omp for schedule(dynamic, 1)
        for (int cz = 0; cz < n[2]; cz++)
            for (int cy = 0; cy < n[1]; cy++)
                for (int bz = 0; bz < per; bz++)
                    for (int by = 0; by < per; by++) {
                        const int32_t z = (far->c0[2] + cz) * S + 4 * bz, y = (far->c0[1] + cy) * S + 4 * by;
                        const int32_t x0 = far->c0[0] * S, xend = (far->c0[0] + n[0]) * S;
                        int32_t x = x0;
                        while (x < xend) {
                            uint32_t level;
                            int active;
                            pnanovdb_coord_t ijk = {x, y, z};
                            float v = probe(g, &acc, ijk, &level, &active);
                            /* The node of `level` holding (x, y, z) has one value up to its x end. */
                            const int32_t dim = 1 << log2_dim[level];
                            int32_t next = (int32_t)(((int64_t)x & ~(int64_t)(dim - 1)) + dim);
                            if (next > xend)
                                next = xend;
                            int8_t sg = v < 0.0f ? -1 : 1;
                            if (level == 0)
                                sg = active ? 0 : block_sign(g, &acc, ijk);
                            for (int32_t cx = (x - x0) / S; cx * S + x0 < next; cx++) {
                                int8_t *c = &sign[((size_t)cz * n[1] + (size_t)cy) * n[0] + (size_t)cx];
                                *c = *c == 2 ? sg : (*c == sg ? sg : 0);
                            }
                            x = next;
                        }
                    }
    }
}

/* Unoccupied cells touching an unoccupied cell of the other sign (a level
 * set would put leaves between them) become occupied, so U still holds
 * every sign change: a cell of sign +1 whose 3^3 neighbourhood's minimum
 * is -1, or of sign -1 whose maximum is +1. Min and max filters are
 * separable: three passes of three cells each. Returns non-zero when out
 * of memory. */
static int dilate_sign_changes(const int n[3], int8_t *sign)
{
    const size_t cells = (size_t)n[0] * n[1] * n[2];
    int8_t *lo = malloc(cells), *hi = malloc(cells), *tmp = malloc(cells);
    if (!lo || !hi || !tmp) {
        free(lo), free(hi), free(tmp);
        return -1;
    }
    extreme3(lo, sign, n, 0, 0), extreme3(tmp, lo, n, 1, 0), extreme3(lo, tmp, n, 2, 0);
    extreme3(hi, sign, n, 0, 1), extreme3(tmp, hi, n, 1, 1), extreme3(hi, tmp, n, 2, 1);
#pragma omp parallel for schedule(static)
    for (long i = 0; i < (long)cells; i++)
        if ((sign[i] > 0 && lo[i] < 0) || (sign[i] < 0 && hi[i] > 0))
            sign[i] = 0;
    free(lo), free(hi), free(tmp);
    return 0;
}

/* ---- the cells' signs from the leaf directory ------------------------------
 * The same classification as classify(), read from the leaf directory
 * (grid_leaves.c) instead of walking the tree row by row: a 64^3 region
 * without leaves is decided whole (one tile of the upper level, or the
 * 512 tiles of its lower node), and only cells in regions with leaves
 * look at their blocks: a leaf's value mask (any active voxel: occupied),
 * else the sign of one of its values (an inactive block has one sign
 * under the level-set convention, as block_sign argues), or a tile
 * marker's sign. A 4096^3 grid's cells are classified in a fraction of a
 * second this way. */

enum { REGION_MIXED = 2 }; /* a region's code when its cells must look at their blocks */

/* The sign of a stored value: +1 or -1. */
static int8_t sign_of(float v) { return v < 0.0f ? -1 : 1; }

/* A region without leaves (every block a tile): +1 / -1 when all its
 * tiles share a sign, else REGION_MIXED. r: region coordinates. */
static int8_t tile_region(const sdft_grid *g, pnanovdb_readaccessor_t *acc, const int32_t r[3])
{
    pnanovdb_coord_t o = {r[0] * 64, r[1] * 64, r[2] * 64};
    uint32_t level;
    pnanovdb_address_t a = pnanovdb_readaccessor_get_value_address_and_level(g->type, g->buf, acc, &o, &level);
    if (level >= 2) /* an upper-node or root tile covers the region */
        return sign_of(g->type == PNANOVDB_GRID_TYPE_DOUBLE ? (float)pnanovdb_read_double(g->buf, a)
                                                            : pnanovdb_read_float(g->buf, a));
    if (level == 0)
        return REGION_MIXED;
    int8_t code = 0;
    for (uint32_t n = 0; n < 512u; n++) { /* the region's 8^3 tiles of its lower node */
        pnanovdb_coord_t b = {o.x + (int32_t)(8u * (n & 7u)), o.y + (int32_t)(8u * (n >> 3 & 7u)),
                              o.z + (int32_t)(8u * (n >> 6))};
        const uint32_t i = pnanovdb_lower_coord_to_offset(&b);
        if (pnanovdb_lower_get_child_mask(g->buf, acc->lower, i))
            return REGION_MIXED;
        const int8_t sg =
            sign_of(pnanovdb_read_float(g->buf, pnanovdb_lower_get_table_address(g->type, g->buf, acc->lower, i)));
        if (code && sg != code)
            return REGION_MIXED;
        code = sg;
    }
    return code;
}

/* The code of 8^3 block b (block coordinates), or of its 4^3 sub-block
 * `sub` (bits 0-2: x, y, z halves) when sub >= 0: 0 occupied, else the
 * sign of all its voxels. */
static int8_t block_code(const sdft_grid *g, pnanovdb_readaccessor_t *acc, const int32_t b[3], int sub)
{
    const int32_t first_voxel[3] = {b[0] * 8, b[1] * 8, b[2] * 8};
    uint32_t local;
    const uint32_t *e;
    const uint32_t w = directory_chunk(g, first_voxel, &local, &e) ? e[local] : 0u;
    const pnanovdb_coord_t o = {b[0] * 8 + (sub >= 0 ? 4 * (sub & 1) : 0),
                                b[1] * 8 + (sub >= 0 ? 4 * (sub >> 1 & 1) : 0),
                                b[2] * 8 + (sub >= 0 ? 4 * (sub >> 2) : 0)};
    if (w == GRID_TILE_POSITIVE || w == GRID_TILE_NEGATIVE)
        return w == GRID_TILE_POSITIVE ? 1 : -1;
    uint32_t level;
    int active;
    const float v = probe(g, acc, o, &level, &active); /* no marker: the tree, as classify() asks it */
    if (level > 0)
        return sign_of(v);
    if (sub < 0) { /* the whole leaf: any active voxel */
        pnanovdb_address_t mask = pnanovdb_address_offset(acc->leaf.address, PNANOVDB_LEAF_OFF_VALUE_MASK);
        for (uint32_t i = 0; i < 16u && !active; i++)
            active = pnanovdb_read_uint32(g->buf, pnanovdb_address_offset(mask, 4u * i)) != 0;
    }
    return active ? 0 : block_sign(g, acc, o);
}

/* classify(), through the directory; needs S <= 64 and the directory. */
static int classify_from_directory(const sdft_grid *g, grid_far *far, int8_t *sign)
{
    const int S = far->cell, *n = far->n;
    const grid_leaves *d = &g->leaves;
    const size_t regions = (size_t)d->nr[0] * d->nr[1] * d->nr[2];
    int8_t *region = malloc(regions);
    if (!region)
        return -1;
#pragma omp parallel
    {
        pnanovdb_readaccessor_t acc;
        pnanovdb_readaccessor_init(&acc, g->root);
#pragma omp for schedule(dynamic, 64)
        for (long i = 0; i < (long)regions; i++) {
            const int32_t r[3] = {d->r0[0] + (int32_t)(i % d->nr[0]), d->r0[1] + (int32_t)(i / d->nr[0] % d->nr[1]),
                                  d->r0[2] + (int32_t)(i / d->nr[0] / d->nr[1])};
            region[i] = d->top[i] ? REGION_MIXED : tile_region(g, &acc, r);
        }
#pragma omp for schedule(dynamic, 1)
        for (int cz = 0; cz < n[2]; cz++)
            for (int cy = 0; cy < n[1]; cy++)
                for (int cx = 0; cx < n[0]; cx++) {
                    const int32_t c[3] = {far->c0[0] + cx, far->c0[1] + cy, far->c0[2] + cz};
                    int32_t ri[3];
                    int inside = 1;
                    for (int k = 0; k < 3; k++) {
                        ri[k] = floor_div(c[k] * S, 64) - d->r0[k];
                        inside &= (uint32_t)ri[k] < (uint32_t)d->nr[k];
                    }
                    int8_t code = inside ? region[((size_t)ri[2] * d->nr[1] + (size_t)ri[1]) * d->nr[0] + (size_t)ri[0]]
                                         : REGION_MIXED;
                    if (code == REGION_MIXED) { /* the cell's blocks, or its one 4^3 sub-block */
                        const int per = S >= 8 ? S / 8 : 1;
                        code = 2; /* not seen yet */
                        for (int k = 0; k < per * per * per && code != 0; k++) {
                            const int32_t b[3] = {S >= 8 ? c[0] * per + k % per : c[0] >> 1,
                                                  S >= 8 ? c[1] * per + k / per % per : c[1] >> 1,
                                                  S >= 8 ? c[2] * per + k / per / per : c[2] >> 1};
                            const int sub = S >= 8 ? -1 : (c[0] & 1) | (c[1] & 1) << 1 | (c[2] & 1) << 2;
                            const int8_t sg = block_code(g, &acc, b, sub);
                            code = code == 2 ? sg : (code == sg ? sg : 0);
                        }
                    }
                    sign[((size_t)cz * n[1] + (size_t)cy) * n[0] + (size_t)cx] = code;
                }
    }
    free(region);
    return 0;
}

sdft_error grid_far_build(sdft_grid *g) { return grid_far_build_cells(g, MAX_CELLS); }

/* S, the voxels per cell edge for at most most_cells cells over the
 * active box: 4, doubled until they fit; n and c0 the cells per axis and
 * the first cell. */
static int far_cells(const sdft_grid *g, size_t most_cells, int n[3], int32_t c0[3])
{
    for (int S = 4;; S *= 2) {
        size_t cells = 1;
        for (int k = 0; k < 3; k++) {
            c0[k] = floor_div(g->ilo[k], S);
            n[k] = floor_div(g->ihi[k], S) - c0[k] + 1;
            cells *= (size_t)n[k];
        }
        if (cells <= most_cells)
            return S;
    }
}

int grid_far_cell(const sdft_grid *g)
{
    int n[3];
    int32_t c0[3];
    return far_cells(g, MAX_CELLS, n, c0);
}

/* d2 at the corners of the cells (n per axis, signs in sign): 0 at the
 * sites, the corners of occupied cells, INFINITY elsewhere, for edt3.
 * A row of corners (y, z) is the corner row of the cell rows (y - 1 or y,
 * z - 1 or z); corner x is a site when cell x - 1 or x of one of them is
 * occupied. Rows in parallel, each written by one thread. */
static void mark_sites(const int n[3], const int8_t *sign, float *d2)
{
    const int nv[3] = {n[0] + 1, n[1] + 1, n[2] + 1};
#pragma omp parallel for schedule(static)
    for (long row = 0; row < (long)nv[1] * nv[2]; row++) {
        const int y = (int)(row % nv[1]), z = (int)(row / nv[1]);
        float *out = d2 + (size_t)row * nv[0];
        for (int x = 0; x < nv[0]; x++)
            out[x] = INFINITY;
        for (int k = 0; k < 4; k++) {
            const int cy = y - (k & 1), cz = z - (k >> 1);
            if (cy < 0 || cz < 0 || cy >= n[1] || cz >= n[2])
                continue;
            const int8_t *cells = sign + ((size_t)cz * n[1] + (size_t)cy) * n[0];
            for (int x = 0; x < n[0]; x++)
                if (cells[x] == 0)
                    out[x] = out[x + 1] = 0.0f;
        }
    }
}

/* Each corner's word from d2 (squared distances in cells of S voxels): its
 * distance, in quarters of a voxel rounded down (truncated: >= 0) and
 * saturated, and, for the lowest corner of a cell, that cell's code. Rows
 * of corners in parallel. */
static void encode_corners(const int n[3], int S, const int8_t *sign, const float *d2, uint16_t *corner)
{
    const int nv[3] = {n[0] + 1, n[1] + 1, n[2] + 1};
    const double most = (double)((1u << FAR_DISTANCE_BITS) - 1u);
#pragma omp parallel for schedule(static)
    for (long row = 0; row < (long)nv[1] * nv[2]; row++) {
        const int y = (int)(row % nv[1]), z = (int)(row / nv[1]);
        const float *in = d2 + (size_t)row * nv[0];
        uint16_t *out = corner + (size_t)row * nv[0];
        for (int x = 0; x < nv[0]; x++) {
            const double q = FAR_DISTANCE_SCALE * S * sqrt((double)in[x]);
            out[x] = (uint16_t)(q < most ? q : most);
        }
        if (y >= n[1] || z >= n[2])
            continue;
        const int8_t *cells = sign + ((size_t)z * n[1] + (size_t)y) * n[0];
        for (int x = 0; x < n[0]; x++) {
            const unsigned code = cells[x] > 0 ? FAR_EMPTY_POSITIVE : cells[x] < 0 ? FAR_EMPTY_NEGATIVE : 0;
            out[x] |= (uint16_t)(code << FAR_DISTANCE_BITS);
        }
    }
}

sdft_error grid_far_build_cells(sdft_grid *g, size_t most_cells)
{
    grid_far *far = &g->far;
    memset(far, 0, sizeof *far);
    int n[3];
    const int S = far_cells(g, most_cells, n, far->c0);
    far->cell = S;
    memcpy(far->n, n, sizeof n);
    const int nv[3] = {n[0] + 1, n[1] + 1, n[2] + 1};
    const size_t ncell = (size_t)n[0] * n[1] * n[2], nvert = (size_t)nv[0] * nv[1] * nv[2];
    int8_t *sign = malloc(ncell);
    float *d2 = malloc(sizeof(float) * nvert);
    uint16_t *corner = grid_table_alloc(sizeof(uint16_t) * nvert);
    if (!sign || !d2 || !corner) {
        free(sign), free(d2), free(corner);
        return SDFT_ENOMEM;
    }
    int failed;
    if (g->leaves.top && S <= 64) {
        failed = classify_from_directory(g, far, sign);
    } else {
        classify_by_tree(g, far, sign);
        failed = 0;
    }
    if (failed || dilate_sign_changes(n, sign)) {
        free(sign), free(d2), free(corner);
        return SDFT_ENOMEM;
    }
    mark_sites(n, sign, d2);
    if (edt3(d2, nv)) {
        free(sign), free(d2), free(corner);
        return SDFT_ENOMEM;
    }
    encode_corners(n, S, sign, d2, corner);
    free(d2);
    free(sign);
    far->corner = corner;
    far->inv_cell = 1.0f / (float)S;
    for (int k = 0; k < 3; k++)
        far->origin[k] = (float)far->c0[k] * (float)S - 0.5f;
    const float bonus = g->background - g->sigma_max * (0.8660254f + 1.4142136f);
    far->bonus = bonus > 0.0f ? bonus : 0.0f;
    return SDFT_OK;
}

void grid_far_free(sdft_grid *g)
{
    free(g->far.corner);
    g->far.corner = NULL;
}
