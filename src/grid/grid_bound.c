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

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

enum { LANES = 16 }; /* adjacent x lines transformed together: a cache line of values per gather */

/* The squared distances between passes: whole numbers of cells^2 in 32
 * bits, NO_SITE where no site has been seen; above 2^24 clamped there,
 * which only lowers a distance of 4096 cells or more (still a bound; the
 * corners saturate at 4096 voxels anyway). */
#define NO_SITE UINT32_MAX
enum { SQUARED_MOST = 1 << 24 };
static inline uint32_t squared_store(uint64_t v) { return v < SQUARED_MOST ? (uint32_t)v : SQUARED_MOST; }

/* edt_line on whole numbers, for `count` <= LANES lines of at most
 * EXACT_LINE values each, one after the other: f[q LANES + l] is value q
 * of line l, and so is out's. f[p] + p^2 stays below 2^31, and the
 * envelope's breakpoints, rationals (F_q - F_p) / 2(q - p) with F_p = f[p]
 * + p^2, are compared by cross multiplication in 64 bits, exactly, with no
 * division. edt_line's doubles compare the same rationals exactly too
 * (their numerators and denominators are small enough that distinct ones
 * never round together), so both find the same envelope and the same
 * minima. e: scratch for n + 1 parabolas of the envelope. */
enum { EXACT_LINE = 1 << 15 };
typedef struct envelope {
    int32_t *v;       /* apexes */
    int64_t *F;       /* f[v] + v^2 */
    int64_t *zn, *zd; /* where each takes over from the one before: zn / zd (zd > 0) */
} envelope;

static void edt_lanes_exact(const uint32_t *f, uint32_t *out, int n, int count, const envelope *e)
{
    int32_t *v = e->v;
    int64_t *F = e->F, *zn = e->zn, *zd = e->zd;
    for (int l = 0; l < count; l++) {
        int k = -1;
        for (int q = 0; q < n; q++) {
            const uint32_t fq = f[(size_t)q * LANES + l];
            if (fq == NO_SITE)
                continue;
            const int64_t Fq = (int64_t)fq + (int64_t)q * q;
            int64_t sn = 0, sd = 1;
            while (k >= 0) {
                sn = Fq - F[k], sd = 2 * (int64_t)(q - v[k]);
                if (k == 0 || sn * zd[k] > zn[k] * sd) /* s > z[k]; z[0] is -infinity */
                    break;
                k--;
            }
            k++;
            v[k] = q, F[k] = Fq, zn[k] = sn, zd[k] = sd;
        }
        if (k < 0) {
            for (int q = 0; q < n; q++)
                out[(size_t)q * LANES + l] = NO_SITE;
            continue;
        }
        int j = 0;
        for (int q = 0; q < n; q++) {
            while (j < k && zn[j + 1] < (int64_t)q * zd[j + 1]) /* z[j + 1] < q; z[k + 1] is +infinity */
                j++;
            const int64_t d = q - v[j];
            out[(size_t)q * LANES + l] = squared_store((uint64_t)(F[j] - (int64_t)v[j] * v[j] + d * d));
        }
    }
}

/* count <= LANES lines at once, laid out as edt_lanes_exact's: on whole
 * numbers where they are exact, else each through edt_line's doubles
 * (df, dout: scratch of n; z: of n + 1; v: of n). */
static void transform_lines(const uint32_t *f, uint32_t *out, int n, int count, const envelope *env, int *v, double *df,
                            double *dout, double *z)
{
    if (n <= EXACT_LINE) {
        edt_lanes_exact(f, out, n, count, env);
        return;
    }
    for (int l = 0; l < count; l++) {
        for (int q = 0; q < n; q++)
            df[q] = f[(size_t)q * LANES + l] == NO_SITE ? HUGE_VAL : (double)f[(size_t)q * LANES + l];
        edt_line(df, dout, n, v, z);
        for (int q = 0; q < n; q++)
            out[(size_t)q * LANES + l] = dout[q] >= HUGE_VAL ? NO_SITE : squared_store((uint64_t)dout[q]);
    }
}

/* The squared distance transform, along y, then z, of d (n[0] x n[1] x
 * n[2], x fastest), which holds the transform along x already (sites'
 * squared distances along their row): in place. Along y and z a line's
 * values are a row apart, so LANES lines with adjacent x go together and
 * each gather reads LANES contiguous values; a group of lines without a
 * site is left as it is; lines run in parallel. */
static int edt_yz(uint32_t *d, const int n[3])
{
    const int m = n[0] > n[1] ? (n[0] > n[2] ? n[0] : n[2]) : (n[1] > n[2] ? n[1] : n[2]);
    const size_t stride[3] = {1, (size_t)n[0], (size_t)n[0] * (size_t)n[1]};
    int failed = 0;
#pragma omp parallel reduction(| : failed)
    {
        uint32_t *f = malloc(sizeof(uint32_t) * (size_t)m * LANES), *o = malloc(sizeof(uint32_t) * (size_t)m * LANES);
        const envelope env = {malloc(sizeof(int32_t) * (size_t)(m + 1)), malloc(sizeof(int64_t) * (size_t)(m + 1)),
                              malloc(sizeof(int64_t) * (size_t)(m + 1)), malloc(sizeof(int64_t) * (size_t)(m + 1))};
        const size_t wide = m > EXACT_LINE ? (size_t)m : 1; /* edt_line's doubles, for long lines */
        int *v = malloc(sizeof(int) * wide);
        double *df = malloc(sizeof(double) * wide), *dout = malloc(sizeof(double) * wide),
               *z = malloc(sizeof(double) * (wide + 1));
        failed = !f || !o || !env.v || !env.F || !env.zn || !env.zd || !v || !df || !dout || !z;
        for (int axis = 1; axis < 3; axis++) {
            /* Work items: (line group, other axis' index). */
            const int other = axis == 2 ? 1 : 2;
            const int across = (n[0] + LANES - 1) / LANES, outer = n[other];
#pragma omp for schedule(dynamic, 16)
            for (long item = 0; item < (long)across * outer; item++) {
                if (failed)
                    continue;
                const int i = (int)(item % across), j = (int)(item / across);
                uint32_t *line = d + (size_t)i * LANES + (size_t)j * stride[other];
                const int count = n[0] - i * LANES < LANES ? n[0] - i * LANES : LANES;
                uint32_t seen = NO_SITE;
                for (int q = 0; q < n[axis]; q++)
                    for (int l = 0; l < count; l++) {
                        const uint32_t x = line[(size_t)q * stride[axis] + l];
                        f[(size_t)q * LANES + l] = x;
                        seen &= x;
                    }
                if (seen == NO_SITE) /* no site on any of the lines: they stay as they are */
                    continue;
                transform_lines(f, o, n[axis], count, &env, v, df, dout, z);
                for (int q = 0; q < n[axis]; q++)
                    for (int l = 0; l < count; l++)
                        line[(size_t)q * stride[axis] + l] = o[(size_t)q * LANES + l];
            }
        }
        free(f), free(o), free(env.v), free(env.F), free(env.zn), free(env.zd), free(v), free(df), free(dout), free(z);
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

/* ---- the cells as bits -------------------------------------------------
 * After classification the cells are two bit sets, a row of x per (y, z),
 * bit x % 64 of word x / 64: `pos`, the empty cells whose voxels are all
 * > 0, and `neg`, those all < 0; a cell in neither is occupied. Dilating,
 * marking the sites and the transform's first pass then read 64 cells a
 * word. */
typedef struct cell_bits {
    uint64_t *pos, *neg;
    size_t words; /* per row: (n[0] + 63) / 64 */
    int n[3];
} cell_bits;

static int cell_bits_alloc(cell_bits *b, const int n[3])
{
    b->words = ((size_t)n[0] + 63u) / 64u;
    memcpy(b->n, n, sizeof b->n);
    const size_t bytes = b->words * (size_t)n[1] * (size_t)n[2] * sizeof(uint64_t);
    b->pos = calloc(1, bytes ? bytes : 1), b->neg = calloc(1, bytes ? bytes : 1);
    return b->pos && b->neg ? 0 : -1;
}

static void cell_bits_free(cell_bits *b) { free(b->pos), free(b->neg); }

/* The codes of classify (one byte a cell) as bits; rows in parallel. */
static void codes_to_bits(const int8_t *sign, cell_bits *b)
{
    const int *n = b->n;
#pragma omp parallel for schedule(static)
    for (long row = 0; row < (long)n[1] * n[2]; row++) {
        const int8_t *c = sign + (size_t)row * n[0];
        uint64_t *p = b->pos + (size_t)row * b->words, *m = b->neg + (size_t)row * b->words;
        int x = 0;
#if defined(__SSE2__)
        const __m128i zero = _mm_setzero_si128();
        for (; x + 16 <= n[0]; x += 16) { /* 16 codes at a time: a byte's sign to a bit */
            const __m128i v = _mm_loadu_si128((const __m128i *)(const void *)(c + x));
            const uint64_t pos = (uint16_t)_mm_movemask_epi8(_mm_cmpgt_epi8(v, zero)),
                           neg = (uint16_t)_mm_movemask_epi8(_mm_cmplt_epi8(v, zero));
            p[x >> 6] |= pos << (x & 63), m[x >> 6] |= neg << (x & 63);
        }
#endif
        for (; x < n[0]; x++) {
            p[x >> 6] |= (uint64_t)(c[x] > 0) << (x & 63);
            m[x >> 6] |= (uint64_t)(c[x] < 0) << (x & 63);
        }
    }
}

/* dst = each cell of the row src (`words` words, n bits) or a neighbour
 * along x. */
static void dilate_row_x(const uint64_t *src, uint64_t *dst, size_t words, int n)
{
    for (size_t w = 0; w < words; w++) {
        const uint64_t below = w > 0 ? src[w - 1] >> 63 : 0, above = w + 1 < words ? src[w + 1] << 63 : 0;
        dst[w] = src[w] | src[w] << 1 | below | src[w] >> 1 | above;
    }
    if (n & 63) /* the bit past the last cell, which the shift set */
        dst[words - 1] &= (UINT64_C(1) << (n & 63)) - 1u;
}

/* Unoccupied cells touching an unoccupied cell of the other sign (a level
 * set would put leaves between them) become occupied, so U still holds
 * every sign change: a cell of pos with a neg cell among its 3^3
 * neighbours (those inside the box), or the other way round, both judged
 * on the cells as classified. Rows in parallel. Returns non-zero when out
 * of memory. */
static int dilate_sign_changes(cell_bits *b)
{
    const int *n = b->n;
    const size_t rows = (size_t)n[1] * n[2], bytes = rows * b->words * sizeof(uint64_t);
    uint64_t *px = malloc(bytes ? bytes : 1), *nx = malloc(bytes ? bytes : 1); /* dilated along x */
    uint64_t *pd = malloc(bytes ? bytes : 1), *nd = malloc(bytes ? bytes : 1); /* along x, y and z */
    if (!px || !nx || !pd || !nd) {
        free(px), free(nx), free(pd), free(nd);
        return -1;
    }
    const size_t W = b->words;
#pragma omp parallel
    {
#pragma omp for schedule(static)
        for (long row = 0; row < (long)rows; row++) {
            dilate_row_x(b->pos + (size_t)row * W, px + (size_t)row * W, W, n[0]);
            dilate_row_x(b->neg + (size_t)row * W, nx + (size_t)row * W, W, n[0]);
        }
#pragma omp for schedule(static)
        for (long row = 0; row < (long)rows; row++) {
            const int y = (int)(row % n[1]), z = (int)(row / n[1]);
            uint64_t *p = pd + (size_t)row * W, *m = nd + (size_t)row * W;
            memset(p, 0, W * sizeof *p), memset(m, 0, W * sizeof *m);
            for (int dz = -1; dz <= 1; dz++)
                for (int dy = -1; dy <= 1; dy++) {
                    if (y + dy < 0 || y + dy >= n[1] || z + dz < 0 || z + dz >= n[2])
                        continue;
                    const size_t at = ((size_t)(z + dz) * n[1] + (size_t)(y + dy)) * W;
                    for (size_t w = 0; w < W; w++)
                        p[w] |= px[at + w], m[w] |= nx[at + w];
                }
        }
#pragma omp for schedule(static)
        for (long i = 0; i < (long)(rows * W); i++) {
            const uint64_t pos = b->pos[i], neg = b->neg[i];
            b->pos[i] = pos & ~nd[i], b->neg[i] = neg & ~pd[i];
        }
    }
    free(px), free(nx), free(pd), free(nd);
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

/* block_code of a leaf the directory knows, its value table at word w:
 * what probe and block_sign find through the tree, read from the leaf in
 * place: its value mask (4^3 sub-block `sub`, or the whole leaf when sub <
 * 0), else the sign of the sub-block's first value. */
static int8_t leaf_code(const sdft_grid *g, uint32_t w, int sub)
{
    const uint32_t *mask =
        g->words + w - PNANOVDB_GRID_TYPE_GET(g->type, leaf_off_table) / 4u + PNANOVDB_LEAF_OFF_VALUE_MASK / 4u;
    int active = 0;
    uint32_t first = 0;
    if (sub < 0) {
        for (int i = 0; i < 16; i++)
            active |= mask[i] != 0;
    } else { /* probe's words: x's, the y half, the z half of each byte */
        const uint32_t x0 = 4u * (uint32_t)(sub & 1), yh = (uint32_t)(sub >> 1 & 1);
        const uint32_t zmask = (sub & 4) ? 0xF0F0F0F0u : 0x0F0F0F0Fu;
        for (uint32_t x = x0; x < x0 + 4u; x++)
            active |= (mask[2u * x + yh] & zmask) != 0;
        first = 64u * x0 + 32u * yh + 4u * (uint32_t)(sub >> 2);
    }
    return active ? 0 : sign_of(leaf_value(g, g->type, w, first));
}

/* The code of 8^3 block b (block coordinates), or of its 4^3 sub-block
 * `sub` (bits 0-2: x, y, z halves) when sub >= 0: 0 occupied, else the
 * sign of all its voxels. w: the block's entry in the directory (0 where
 * it has none). */
static int8_t block_code(const sdft_grid *g, pnanovdb_readaccessor_t *acc, uint32_t w, const int32_t b[3], int sub)
{
    if (w == GRID_TILE_POSITIVE || w == GRID_TILE_NEGATIVE)
        return w == GRID_TILE_POSITIVE ? 1 : -1;
    if (w >= GRID_TILE_MARKERS) /* the directory's leaf: read it in place, as the tree walk below would */
        return g->deferred.state ? 0 : leaf_code(g, w, sub);
    const pnanovdb_coord_t o = {b[0] * 8 + (sub >= 0 ? 4 * (sub & 1) : 0),
                                b[1] * 8 + (sub >= 0 ? 4 * (sub >> 1 & 1) : 0),
                                b[2] * 8 + (sub >= 0 ? 4 * (sub >> 2) : 0)};
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

/* The code of cell c (cell coordinates, S voxels an edge, S <= 64) of a
 * region whose chunk of the directory is e: its blocks' codes, or its one
 * 4^3 sub-block's, combined (one code: that; several: 0). */
static int8_t cell_code(const sdft_grid *g, pnanovdb_readaccessor_t *acc, const uint32_t *e, int S, const int32_t c[3])
{
    const int per = S >= 8 ? S / 8 : 1;
    int8_t code = 2; /* not seen yet */
    for (int k = 0; k < per * per * per && code != 0; k++) {
        const int32_t b[3] = {S >= 8 ? c[0] * per + k % per : c[0] >> 1,
                              S >= 8 ? c[1] * per + k / per % per : c[1] >> 1,
                              S >= 8 ? c[2] * per + k / per / per : c[2] >> 1};
        const int sub = S >= 8 ? -1 : (c[0] & 1) | (c[1] & 1) << 1 | (c[2] & 1) << 2;
        const uint32_t local = (uint32_t)(b[0] & 7) + GRID_CHUNK_SIDE * (uint32_t)(b[1] & 7) +
                               GRID_CHUNK_SIDE * GRID_CHUNK_SIDE * (uint32_t)(b[2] & 7);
        const int8_t sg = block_code(g, acc, e ? e[local] : 0u, b, sub);
        code = code == 2 ? sg : (code == sg ? sg : 0);
    }
    return code;
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
        /* Each row of cells, a region's stretch of it at a time: one code
         * for a region decided whole, else cell by cell through its chunk. */
        const int per_region = 64 / S;
#pragma omp for schedule(dynamic, 1)
        for (int cz = 0; cz < n[2]; cz++)
            for (int cy = 0; cy < n[1]; cy++) {
                int8_t *row = sign + ((size_t)cz * n[1] + (size_t)cy) * n[0];
                const int32_t ry = floor_div(far->c0[1] + cy, per_region) - d->r0[1],
                              rz = floor_div(far->c0[2] + cz, per_region) - d->r0[2];
                for (int cx = 0; cx < n[0];) {
                    const int32_t c[3] = {far->c0[0] + cx, far->c0[1] + cy, far->c0[2] + cz};
                    const int32_t rx = floor_div(c[0], per_region);
                    const int end = (int)((rx + 1) * per_region - far->c0[0]) < n[0]
                                        ? (int)((rx + 1) * per_region - far->c0[0])
                                        : n[0];
                    const int32_t ri[3] = {rx - d->r0[0], ry, rz};
                    const int inside = (uint32_t)ri[0] < (uint32_t)d->nr[0] && (uint32_t)ri[1] < (uint32_t)d->nr[1] &&
                                       (uint32_t)ri[2] < (uint32_t)d->nr[2];
                    const size_t at =
                        inside ? ((size_t)ri[2] * d->nr[1] + (size_t)ri[1]) * d->nr[0] + (size_t)ri[0] : 0;
                    const int8_t code = inside ? region[at] : REGION_MIXED;
                    if (code != REGION_MIXED) {
                        memset(row + cx, code, (size_t)(end - cx));
                    } else {
                        const uint32_t chunk = inside ? d->top[at] : 0u;
                        const uint32_t *e = chunk ? d->chunk + (size_t)(chunk - 1u) * GRID_CHUNK_ENTRIES : NULL;
                        for (int x = cx; x < end; x++) {
                            const int32_t cc[3] = {far->c0[0] + x, c[1], c[2]};
                            row[x] = cell_code(g, &acc, e, S, cc);
                        }
                    }
                    cx = end;
                }
            }
    }
    free(region);
    return 0;
}

sdft_error grid_far_build(sdft_grid *g) { return grid_far_build_cells(g, MAX_CELLS); }

/* S, the voxels per cell edge for at most most_cells cells over the index
 * box [lo, hi]: 4, doubled until they fit; n and c0 the cells per axis and
 * the first cell. */
static int far_cells(const int32_t lo[3], const int32_t hi[3], size_t most_cells, int n[3], int32_t c0[3])
{
    for (int S = 4;; S *= 2) {
        size_t cells = 1;
        for (int k = 0; k < 3; k++) {
            c0[k] = floor_div(lo[k], S);
            n[k] = floor_div(hi[k], S) - c0[k] + 1;
            cells *= (size_t)n[k];
        }
        if (cells <= most_cells)
            return S;
    }
}

int grid_far_cell(const int32_t lo[3], const int32_t hi[3])
{
    int n[3];
    int32_t c0[3];
    return far_cells(lo, hi, MAX_CELLS, n, c0);
}

/* The transform's input and its first pass, along x, at once: d2 at each
 * corner of the cells is the squared distance, along its row of corners,
 * to the nearest site (a corner of an occupied cell), NO_SITE on a row
 * without one. A row of corners (y, z) is the corner row of the cell rows
 * (y - 1 or y, z - 1 or z); corner x is a site when cell x - 1 or x of one
 * of them is occupied. Rows in parallel, each written by one thread. */
static int mark_sites_along_x(const cell_bits *b, uint32_t *d2)
{
    const int *n = b->n;
    const int nv[3] = {n[0] + 1, n[1] + 1, n[2] + 1};
    const size_t W = b->words, sw = ((size_t)nv[0] + 63u) / 64u;
    int failed = 0;
#pragma omp parallel reduction(| : failed)
    {
        uint64_t *site = calloc(sw, sizeof *site);
        failed = !site;
#pragma omp for schedule(static)
        for (long row = 0; row < (long)nv[1] * nv[2]; row++) {
            if (failed)
                continue;
            const int y = (int)(row % nv[1]), z = (int)(row / nv[1]);
            memset(site, 0, sw * sizeof *site);
            for (int k = 0; k < 4; k++) {
                const int cy = y - (k & 1), cz = z - (k >> 1);
                if (cy < 0 || cz < 0 || cy >= n[1] || cz >= n[2])
                    continue;
                const size_t at = ((size_t)cz * n[1] + (size_t)cy) * W;
                for (size_t w = 0; w < W; w++) {
                    uint64_t occ = ~(b->pos[at + w] | b->neg[at + w]);
                    if (w + 1 == W && (n[0] & 63))
                        occ &= (UINT64_C(1) << (n[0] & 63)) - 1u; /* only the row's cells */
                    site[w] |= occ | occ << 1;                    /* cell x: corners x and x + 1 */
                    if (w + 1 < sw)
                        site[w + 1] |= occ >> 63;
                }
            }
            uint32_t *out = d2 + (size_t)row * nv[0];
            int last = -1; /* the last site, as the sites are visited in order */
            for (size_t w = 0; w < sw; w++)
                for (uint64_t bits = site[w]; bits; bits &= bits - 1) {
                    const int s = (int)(64 * w) + __builtin_ctzll(bits);
                    for (int x = last + 1; x <= s; x++) {
                        const int64_t d = last < 0 || s - x < x - last ? s - x : x - last;
                        out[x] = squared_store((uint64_t)(d * d));
                    }
                    last = s;
                }
            for (int x = last + 1; x < nv[0]; x++) {
                const int64_t d = x - last;
                out[x] = last < 0 ? NO_SITE : squared_store((uint64_t)(d * d));
            }
        }
        free(site);
    }
    return failed ? -1 : 0;
}

/* Each corner's word from d2 (squared distances in cells of S voxels): its
 * distance, in quarters of a voxel rounded down (truncated: >= 0) and
 * saturated, and, for the lowest corner of a cell, that cell's code. Rows
 * of corners in parallel. */
static void encode_corners(const cell_bits *b, int S, const uint32_t *d2, uint16_t *corner)
{
    const int *n = b->n;
    const int nv[3] = {n[0] + 1, n[1] + 1, n[2] + 1};
    const double most = (double)((1u << FAR_DISTANCE_BITS) - 1u);
#pragma omp parallel for schedule(static)
    for (long row = 0; row < (long)nv[1] * nv[2]; row++) {
        const int y = (int)(row % nv[1]), z = (int)(row / nv[1]);
        const uint32_t *in = d2 + (size_t)row * nv[0];
        uint16_t *out = corner + (size_t)row * nv[0];
        for (int x = 0; x < nv[0]; x++) {
            const double q = in[x] == NO_SITE ? HUGE_VAL : FAR_DISTANCE_SCALE * S * sqrt((double)in[x]);
            out[x] = (uint16_t)(q < most ? q : most);
        }
        if (y >= n[1] || z >= n[2])
            continue;
        const uint64_t *p = b->pos + ((size_t)z * n[1] + (size_t)y) * b->words,
                       *m = b->neg + ((size_t)z * n[1] + (size_t)y) * b->words;
        for (int x = 0; x < n[0]; x++) {
            const unsigned code = (p[x >> 6] >> (x & 63) & 1u)   ? FAR_EMPTY_POSITIVE
                                  : (m[x >> 6] >> (x & 63) & 1u) ? FAR_EMPTY_NEGATIVE
                                                                 : 0u;
            out[x] |= (uint16_t)(code << FAR_DISTANCE_BITS);
        }
    }
}

/* far's cells and constants for g, with at most most_cells cells (no
 * table yet). */
static void far_plan(const sdft_grid *g, size_t most_cells, grid_far *far)
{
    memset(far, 0, sizeof *far);
    far->cell = far_cells(g->ilo, g->ihi, most_cells, far->n, far->c0);
    far->inv_cell = 1.0f / (float)far->cell;
    for (int k = 0; k < 3; k++)
        far->origin[k] = (float)far->c0[k] * (float)far->cell - 0.5f;
    const float bonus = g->background - g->sigma_max * (0.8660254f + 1.4142136f);
    far->bonus = bonus > 0.0f ? bonus : 0.0f;
}

int grid_far_plan(const sdft_grid *g, grid_far *far)
{
    far_plan(g, MAX_CELLS, far);
    return g->grid_class == PNANOVDB_GRID_CLASS_LEVEL_SET && g->background > 0.0f;
}

sdft_error grid_far_build_cells(sdft_grid *g, size_t most_cells)
{
    grid_far *far = &g->far;
    far_plan(g, most_cells, far);
    const int S = far->cell, n[3] = {far->n[0], far->n[1], far->n[2]};
    const int nv[3] = {n[0] + 1, n[1] + 1, n[2] + 1};
    const size_t ncell = (size_t)n[0] * n[1] * n[2], nvert = (size_t)nv[0] * nv[1] * nv[2];
    int8_t *sign = malloc(ncell);
    cell_bits bits = {0};
    uint32_t *d2 = NULL;
    uint16_t *corner = NULL;
    int failed = !sign || cell_bits_alloc(&bits, n);
    if (!failed && g->leaves.top && S <= 64)
        failed = classify_from_directory(g, far, sign);
    else if (!failed)
        classify_by_tree(g, far, sign);
    if (!failed) {
        codes_to_bits(sign, &bits);
        free(sign), sign = NULL;
        failed = dilate_sign_changes(&bits);
    }
    if (!failed) {
        d2 = malloc(sizeof(uint32_t) * nvert);
        failed = !d2 || mark_sites_along_x(&bits, d2) || edt_yz(d2, nv);
    }
    if (!failed) {
        corner = grid_table_alloc(sizeof(uint16_t) * nvert);
        failed = !corner;
    }
    if (!failed)
        encode_corners(&bits, S, d2, corner);
    free(sign), free(d2), cell_bits_free(&bits);
    if (failed) {
        free(corner);
        return SDFT_ENOMEM;
    }
    far->corner = corner;
    return SDFT_OK;
}

void grid_far_free(sdft_grid *g)
{
    if (!g->far.stored)
        free(g->far.corner);
    g->far.corner = NULL, g->far.stored = 0;
}
