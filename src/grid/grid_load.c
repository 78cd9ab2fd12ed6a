/* sdftrace — NanoVDB grids in: `.nvdb` files and in-memory buffers, read in
 * plain C. Every size and offset is checked against the bytes actually
 * present before PNanoVDB.h follows it, so a corrupt or truncated input is
 * an error with a reason, never a wild read. */
#define _POSIX_C_SOURCE 200809L /* fileno, pread */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <omp.h>

#include "grid_choose.h"
#include "grid_internal.h"

/* ---- what a grid holds ------------------------------------------------ */

static int type_is_scalar(uint32_t type)
{
    return type == PNANOVDB_GRID_TYPE_FLOAT || type == PNANOVDB_GRID_TYPE_DOUBLE || type == PNANOVDB_GRID_TYPE_FP4 ||
           type == PNANOVDB_GRID_TYPE_FP8 || type == PNANOVDB_GRID_TYPE_FP16 || type == PNANOVDB_GRID_TYPE_FPN;
}

static const char *type_name(uint32_t type)
{
    static const char *const names[PNANOVDB_GRID_TYPE_END] = {
        "unknown", "float", "double", "int16", "int32", "int64", "vec3f", "vec3d", "mask",  "half",
        "uint32",  "bool",  "rgba8",  "fp4",   "fp8",   "fp16",  "fpN",   "vec4f", "vec4d", "index"};
    return type < PNANOVDB_GRID_TYPE_END ? names[type] : "unknown";
}

static const char *class_name(uint32_t cls)
{
    static const char *const names[PNANOVDB_GRID_CLASS_END] = {"unknown",   "level set",    "fog volume",
                                                               "staggered", "point index",  "point data",
                                                               "topology",  "voxel volume", "index grid"};
    return cls < PNANOVDB_GRID_CLASS_END ? names[cls] : "unknown";
}

/* ---- structural checks ------------------------------------------------- */

typedef struct span {
    uint64_t size; /* bytes of the grid */
} span;

static int fits(span s, uint64_t at, uint64_t len) { return at <= s.size && len <= s.size - at && (at & 3u) == 0; }

/* Bytes of a leaf node: fixed part, plus the variable code table of FpN. */
static uint64_t leaf_bytes(const sdft_grid *g, uint64_t at, span s)
{
    uint64_t fixed = PNANOVDB_GRID_TYPE_GET(g->type, leaf_size);
    if (g->type != PNANOVDB_GRID_TYPE_FPN || !fits(s, at, fixed))
        return fixed;
    uint32_t flags =
        pnanovdb_read_uint32(
            g->buf, pnanovdb_address_offset64((pnanovdb_address_t){0}, at + PNANOVDB_LEAF_OFF_BBOX_DIF_AND_FLAGS)) >>
        24u;
    uint32_t log_bits = flags >> 5u;
    if (log_bits > 4u)
        return UINT64_MAX;
    return fixed + (512u << log_bits) / 8u;
}

/* Walks root -> upper -> lower -> leaf and checks that every child lies
 * wholly inside the grid's bytes. Linear in the node count. */
static sdft_error check_tree(const sdft_grid *g, uint64_t root_at, char *msg, size_t msg_len)
{
    const pnanovdb_grid_type_t t = g->type;
    span s = {g->size};
    uint32_t tiles = pnanovdb_root_get_tile_count(g->buf, g->root);
    uint64_t tile_size = PNANOVDB_GRID_TYPE_GET(t, root_tile_size);
    uint64_t root_size = PNANOVDB_GRID_TYPE_GET(t, root_size);
    if (!fits(s, root_at, root_size + (uint64_t)tiles * tile_size))
        return fail_with(msg, msg_len, SDFT_EFORMAT, "grid '%s' is corrupt: root table runs past the grid", g->name);
    uint64_t upper_size = PNANOVDB_GRID_TYPE_GET(t, upper_size), lower_size = PNANOVDB_GRID_TYPE_GET(t, lower_size);
    for (uint32_t i = 0; i < tiles; i++) {
        pnanovdb_root_tile_handle_t tile = pnanovdb_root_get_tile(t, g->root, i);
        int64_t child = pnanovdb_root_tile_get_child(g->buf, tile);
        if (child == 0)
            continue;
        uint64_t up = root_at + (uint64_t)child;
        if (child < 0 || !fits(s, up, upper_size))
            return fail_with(msg, msg_len, SDFT_EFORMAT, "grid '%s' is corrupt: upper node outside the grid", g->name);
        pnanovdb_upper_handle_t upper = {{up}};
        for (uint32_t n = 0; n < 32768u; n++) {
            if (!pnanovdb_upper_get_child_mask(g->buf, upper, n))
                continue;
            int64_t off = pnanovdb_upper_get_table_child(t, g->buf, upper, n);
            uint64_t lo = up + (uint64_t)off;
            if (off <= 0 || !fits(s, lo, lower_size))
                return fail_with(msg, msg_len, SDFT_EFORMAT, "grid '%s' is corrupt: lower node outside the grid",
                                 g->name);
            pnanovdb_lower_handle_t lower = {{lo}};
            for (uint32_t m = 0; m < 4096u; m++) {
                if (!pnanovdb_lower_get_child_mask(g->buf, lower, m))
                    continue;
                int64_t loff = pnanovdb_lower_get_table_child(t, g->buf, lower, m);
                uint64_t leaf = lo + (uint64_t)loff;
                if (loff <= 0 || !fits(s, leaf, leaf_bytes(g, leaf, s)))
                    return fail_with(msg, msg_len, SDFT_EFORMAT, "grid '%s' is corrupt: leaf node outside the grid",
                                     g->name);
            }
        }
    }
    return SDFT_OK;
}

/* Gershgorin: the largest eigenvalue of A^T A is at most its largest
 * absolute row sum, so sqrt of that bounds the spectral norm of A from
 * above (exactly, for a diagonal A). */
static float spectral_bound(const double a[9])
{
    double m[9], worst = 0;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            m[3 * r + c] = a[r] * a[c] + a[3 + r] * a[3 + c] + a[6 + r] * a[6 + c];
    for (int r = 0; r < 3; r++)
        worst = fmax(worst, fabs(m[3 * r]) + fabs(m[3 * r + 1]) + fabs(m[3 * r + 2]));
    return (float)sqrt(worst);
}

/* The header, checked: magic, version, size, a scalar type, a tree whose
 * nodes lie inside the grid, some active voxels. */
static sdft_error decode_header(sdft_grid *g, char *msg, size_t msg_len)
{
    g->buf = pnanovdb_make_buf(g->words, g->size / 4);
    g->grid.address.byte_offset = 0;
    if (g->size < PNANOVDB_GRID_SIZE + PNANOVDB_TREE_SIZE)
        return fail_with(msg, msg_len, SDFT_EFORMAT, "not a NanoVDB grid: only %zu bytes", g->size);
    if (pnanovdb_grid_get_magic(g->buf, g->grid) != PNANOVDB_MAGIC_NUMBER)
        return fail_with(msg, msg_len, SDFT_EFORMAT, "not a NanoVDB grid: bad magic number");
    uint32_t major = pnanovdb_grid_get_version(g->buf, g->grid) >> 21u;
    if (major != PNANOVDB_MAJOR_VERSION_NUMBER)
        return fail_with(msg, msg_len, SDFT_EFORMAT, "NanoVDB grid version %u, this build reads version %u", major,
                         PNANOVDB_MAJOR_VERSION_NUMBER);
    memcpy(g->name, (const char *)g->words + PNANOVDB_GRID_OFF_GRID_NAME, sizeof g->name - 1);
    g->name[sizeof g->name - 1] = '\0';
    uint64_t grid_size = pnanovdb_grid_get_grid_size(g->buf, g->grid);
    if (grid_size > g->size || grid_size < PNANOVDB_GRID_SIZE + PNANOVDB_TREE_SIZE)
        return fail_with(msg, msg_len, SDFT_EFORMAT, "grid '%s' is truncated: %llu of %llu bytes", g->name,
                         (unsigned long long)g->size, (unsigned long long)grid_size);
    g->size = grid_size;
    g->buf = pnanovdb_make_buf(g->words, g->size / 4);
    g->type = pnanovdb_grid_get_grid_type(g->buf, g->grid);
    g->grid_class = pnanovdb_grid_get_grid_class(g->buf, g->grid);
    if (!type_is_scalar(g->type))
        return fail_with(msg, msg_len, SDFT_ENOTSCALAR, "grid '%s' holds %s values, not scalar distances", g->name,
                         type_name(g->type));

    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(g->buf, g->grid);
    uint64_t root_at = PNANOVDB_GRID_SIZE + pnanovdb_tree_get_node_offset_root(g->buf, tree);
    if (!fits((span){g->size}, root_at, PNANOVDB_GRID_TYPE_GET(g->type, root_size)))
        return fail_with(msg, msg_len, SDFT_EFORMAT, "grid '%s' is corrupt: root node outside the grid", g->name);
    g->root = pnanovdb_tree_get_root(g->buf, tree);
    const sdft_error rc = check_tree(g, root_at, msg, msg_len);
    if (rc)
        return rc;
    if (pnanovdb_tree_get_voxel_count(g->buf, tree) == 0)
        return fail_with(msg, msg_len, SDFT_EEMPTY, "grid '%s' is empty: no active voxels", g->name);
    return SDFT_OK;
}

/* The transform, in floats for the sampler, and the voxel size. */
static sdft_error decode_map(sdft_grid *g, char *msg, size_t msg_len)
{
    pnanovdb_map_handle_t map = pnanovdb_grid_get_map(g->buf, g->grid);
    double mat[9], inv[9];
    for (int i = 0; i < 9; i++) {
        mat[i] = pnanovdb_map_get_matd(g->buf, map, (uint32_t)i);
        inv[i] = pnanovdb_map_get_invmatd(g->buf, map, (uint32_t)i);
        g->i2w[i] = (float)mat[i];
        g->w2i[i] = (float)inv[i];
    }
    /* A diagonal map's inverse is diagonal; a writer that inverts it as a
     * general matrix can leave rounding noise off the diagonal (OpenVDB's
     * 4x4 inverse: 1e-12 beside 6519 on a bunny from mesh2sdf), which would
     * cost every sample the full product. Noise that small is dropped. */
    const int mat_diagonal = mat[1] == 0 && mat[2] == 0 && mat[3] == 0 && mat[5] == 0 && mat[6] == 0 && mat[7] == 0;
    const double inv_scale = fmax(fabs(inv[0]), fmax(fabs(inv[4]), fabs(inv[8])));
    for (int i = 0; mat_diagonal && i < 9; i++)
        if (i % 4 != 0 && fabs(inv[i]) <= 1e-9 * inv_scale)
            inv[i] = 0.0, g->w2i[i] = 0.0f;
    for (int k = 0; k < 3; k++) {
        double v = pnanovdb_map_get_vecd(g->buf, map, (uint32_t)k);
        g->i2w_t[k] = (float)v;
        g->w2i_t[k] = (float)-(inv[3 * k] * pnanovdb_map_get_vecd(g->buf, map, 0) +
                               inv[3 * k + 1] * pnanovdb_map_get_vecd(g->buf, map, 1) +
                               inv[3 * k + 2] * pnanovdb_map_get_vecd(g->buf, map, 2));
    }
    g->diagonal =
        g->w2i[1] == 0 && g->w2i[2] == 0 && g->w2i[3] == 0 && g->w2i[5] == 0 && g->w2i[6] == 0 && g->w2i[7] == 0;
    g->sigma_max = spectral_bound(mat);
    float inv_norm = spectral_bound(inv);
    g->sigma_min = inv_norm > 0 ? 1.0f / inv_norm : 0.0f;
    if (!(g->sigma_min > 0) || !isfinite(g->sigma_max) || !isfinite(g->sigma_min))
        return fail_with(msg, msg_len, SDFT_EFORMAT, "grid '%s' has a singular transform", g->name);
    g->voxel_size = sdft_v3((float)pnanovdb_grid_get_voxel_size(g->buf, g->grid, 0),
                            (float)pnanovdb_grid_get_voxel_size(g->buf, g->grid, 1),
                            (float)pnanovdb_grid_get_voxel_size(g->buf, g->grid, 2));
    return SDFT_OK;
}

/* The background and the active box, in index and world units. */
static sdft_error decode_box(sdft_grid *g, char *msg, size_t msg_len)
{
    pnanovdb_address_t bg =
        pnanovdb_address_offset(g->root.address, PNANOVDB_GRID_TYPE_GET(g->type, root_off_background));
    g->background = g->type == PNANOVDB_GRID_TYPE_DOUBLE ? (float)pnanovdb_read_double(g->buf, bg)
                                                         : pnanovdb_read_float(g->buf, bg);

    pnanovdb_coord_t lo = pnanovdb_root_get_bbox_min(g->buf, g->root), hi = pnanovdb_root_get_bbox_max(g->buf, g->root);
    g->ilo[0] = lo.x, g->ilo[1] = lo.y, g->ilo[2] = lo.z;
    g->ihi[0] = hi.x, g->ihi[1] = hi.y, g->ihi[2] = hi.z;
    if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z)
        return fail_with(msg, msg_len, SDFT_EEMPTY, "grid '%s' is empty: no active bounding box", g->name);
    /* World box of the active cells [lo - 1/2, hi + 1/2]. */
    const float cells_lo[3] = {lo.x - 0.5f, lo.y - 0.5f, lo.z - 0.5f},
                cells_hi[3] = {hi.x + 0.5f, hi.y + 0.5f, hi.z + 0.5f};
    g->bounds = grid_world_box(g, cells_lo, cells_hi);
    return SDFT_OK;
}

/* What the sampler and the renderer read besides the grid's bytes: a
 * deferred grid's leaf states (or its leaves, filled now where deferring
 * would loosen the far bound), the leaf directory, the far bound, the hull,
 * and the accel that points to them. */
static sdft_error build_tables(sdft_grid *g, char *msg, size_t msg_len)
{
    if (g->deferred.fill) {
        if (g->type != PNANOVDB_GRID_TYPE_FLOAT && g->type != PNANOVDB_GRID_TYPE_FP16)
            return fail_with(msg, msg_len, SDFT_EINVAL, "grid '%s' holds %s values: deferred leaves need float or fp16",
                             g->name, type_name(g->type));
        const sdft_error drc = grid_deferred_init(g);
        if (drc)
            return fail_with(msg, msg_len, drc, "grid '%s': %s", g->name,
                             drc == SDFT_ENOMEM ? "out of memory for its leaves' states" : "its leaf array is corrupt");
        /* A grid that sdft_grid_defers says is not deferred is filled now,
         * whole, and is then a grid like any other. */
        if (!sdft_grid_defers(g->deferred.how, g->grid_class == PNANOVDB_GRID_CLASS_LEVEL_SET, g->background, g->ilo,
                              g->ihi)) {
            const double t0 = omp_get_wtime();
            const uint64_t failed = grid_deferred_fill_now(g);
            g->phases.fill_ms = 1e3 * (omp_get_wtime() - t0);
            if (failed)
                return fail_with(msg, msg_len, SDFT_EIO, "grid '%s': %llu leaves could not be read", g->name,
                                 (unsigned long long)failed);
        }
    }
    /* The directory first: the far bound reads the cells' signs through it. */
    double t0 = omp_get_wtime();
    if (grid_leaves_build(g))
        return fail_with(msg, msg_len, SDFT_ENOMEM, "grid '%s': out of memory for its leaf directory", g->name);
    double t1 = omp_get_wtime();
    g->phases.directory_ms = 1e3 * (t1 - t0);
    grid_tables_take(g); /* what the grid stores of the rest */
    t0 = omp_get_wtime();
    g->phases.tables_ms = 1e3 * (t0 - t1);
    g->phases.far_stored = g->far.stored, g->phases.hull_stored = g->hull_stored;
    if (!g->far.corner && g->grid_class == PNANOVDB_GRID_CLASS_LEVEL_SET && g->background > 0.0f && grid_far_build(g))
        return fail_with(msg, msg_len, SDFT_ENOMEM, "grid '%s': out of memory for its far bound", g->name);
    t1 = omp_get_wtime();
    g->phases.far_ms = 1e3 * (t1 - t0);
    if (!g->hull_stored && grid_hull_build(g))
        return fail_with(msg, msg_len, SDFT_ENOMEM, "grid '%s': out of memory for its hull", g->name);
    g->phases.hull_ms = 1e3 * (omp_get_wtime() - t1);
    grid_accel_init(g);
    return SDFT_OK;
}

sdft_error grid_init(sdft_grid *g, char *msg, size_t msg_len)
{
    const double t0 = omp_get_wtime();
    sdft_error rc = decode_header(g, msg, msg_len);
    g->phases.check_ms = 1e3 * (omp_get_wtime() - t0);
    if (!rc)
        rc = decode_map(g, msg, msg_len);
    if (!rc)
        rc = decode_box(g, msg, msg_len);
    return rc ? rc : build_tables(g, msg, msg_len);
}

/* ---- choosing a grid --------------------------------------------------- */

typedef struct grid_entry {
    uint64_t offset, size; /* where its bytes start in the source, how many */
    uint32_t type, grid_class;
    char name[256];
} grid_entry;

/* grid_choose.h's rule over what the source's headers say. */
static sdft_error choose(const grid_entry *e, size_t n, const char *name, const char *what, size_t *pick, char *msg,
                         size_t msg_len)
{
    grid_candidate seen[64];
    for (size_t i = 0; i < n && i < 64; i++)
        seen[i] = (grid_candidate){.name = e[i].name,
                                   .type = type_name(e[i].type),
                                   .scalar = type_is_scalar(e[i].type),
                                   .level_set = e[i].grid_class == PNANOVDB_GRID_CLASS_LEVEL_SET};
    return grid_choose(seen, n, name, what, pick, msg, msg_len);
}

static sdft_grid *grid_alloc(uint64_t size)
{
    sdft_grid *g = calloc(1, sizeof *g);
    if (!g)
        return NULL;
    size_t padded = (size_t)((size + 63u) & ~(uint64_t)63u);
    g->words = padded ? grid_table_alloc(padded) : NULL;
    if (!g->words) {
        free(g);
        return NULL;
    }
    memset((char *)g->words + size, 0, padded - size);
    g->size = (size_t)size;
    g->owned = 1;
    return g;
}

void sdft_grid_free(sdft_grid *g)
{
    if (g) {
        grid_hull_free(g);
        grid_far_free(g);
        grid_leaves_free(g);
        grid_deferred_free(g);
        free(g->material_table);
        if (g->owned)
            free(g->words);
        if (g->release)
            g->release(g->release_data);
        free(g);
    }
}

static sdft_error finish(sdft_grid *g, sdft_grid **out, char *msg, size_t msg_len)
{
    const sdft_error rc = grid_init(g, msg, msg_len);
    if (rc) {
        sdft_grid_free(g);
        return rc;
    }
    *out = g;
    return SDFT_OK;
}

/* The grids of a GridHandle's buffer, back to back, each with its own size,
 * and the one chosen. */
static sdft_error scan_buffer(const unsigned char *bytes, size_t size, const char *name, grid_entry *entries,
                              size_t *pick, char *msg, size_t msg_len)
{
    size_t n = 0;
    for (uint64_t at = 0; at < size && n < 64;) {
        if (size - at < PNANOVDB_GRID_SIZE)
            return fail_with(msg, msg_len, SDFT_EFORMAT, "buffer is truncated: %zu bytes after grid %zu",
                             (size_t)(size - at), n);
        uint64_t magic, gsize;
        uint32_t type, cls;
        memcpy(&magic, bytes + at + PNANOVDB_GRID_OFF_MAGIC, 8);
        memcpy(&gsize, bytes + at + PNANOVDB_GRID_OFF_GRID_SIZE, 8);
        memcpy(&type, bytes + at + PNANOVDB_GRID_OFF_GRID_TYPE, 4);
        memcpy(&cls, bytes + at + PNANOVDB_GRID_OFF_GRID_CLASS, 4);
        if (magic != PNANOVDB_MAGIC_NUMBER)
            return fail_with(msg, msg_len, SDFT_EFORMAT, "not a NanoVDB buffer: bad magic number");
        if (gsize < PNANOVDB_GRID_SIZE || gsize > size - at)
            return fail_with(msg, msg_len, SDFT_EFORMAT, "buffer is truncated: grid %zu needs %llu bytes", n,
                             (unsigned long long)gsize);
        entries[n] = (grid_entry){.offset = at, .size = gsize, .type = type, .grid_class = cls};
        memcpy(entries[n].name, bytes + at + PNANOVDB_GRID_OFF_GRID_NAME, 255);
        entries[n].name[255] = '\0';
        n++;
        at += gsize;
    }
    return choose(entries, n, name, "buffer", pick, msg, msg_len);
}

/* The checks both buffer entry points share, then the chosen grid's entry. */
static sdft_error buffer_grid(const void *data, size_t size, const char *name, sdft_grid **out, grid_entry *chosen,
                              char *msg, size_t msg_len)
{
    if (!out)
        return fail_with(msg, msg_len, SDFT_EINVAL, "no place for the grid (out is NULL)");
    *out = NULL;
    if (!data || size == 0)
        return fail_with(msg, msg_len, SDFT_EINVAL, "no buffer (NULL data or size 0)");
    grid_entry entries[64];
    size_t pick;
    const sdft_error rc = scan_buffer(data, size, name, entries, &pick, msg, msg_len);
    if (!rc)
        *chosen = entries[pick];
    return rc;
}

/* A grid from a buffer's chosen grid: its bytes copied into the grid, or
 * (borrow) read in place, which needs NanoVDB's 32-byte alignment. */
static sdft_error grid_of_buffer(const void *data, size_t size, const char *name, int borrow,
                                 const grid_deferred *deferred, double read_ms, double serial_ms, sdft_grid **out,
                                 char *msg, size_t msg_len)
{
    grid_entry e;
    const sdft_error rc = buffer_grid(data, size, name, out, &e, msg, msg_len);
    if (rc)
        return rc;
    const unsigned char *at = (const unsigned char *)data + e.offset;
    if (borrow && (uintptr_t)at % 32u != 0)
        return fail_with(msg, msg_len, SDFT_EINVAL, "grid '%s' does not start 32-byte aligned: copy it instead",
                         e.name);
    sdft_grid *g = borrow ? calloc(1, sizeof *g) : grid_alloc(e.size);
    if (!g)
        return fail_with(msg, msg_len, SDFT_ENOMEM, "out of memory for a %llu-byte grid", (unsigned long long)e.size);
    if (borrow)
        g->words = (uint32_t *)(uintptr_t)at, g->size = (size_t)e.size; /* read only: PNanoVDB's type is not const */
    else
        memcpy(g->words, at, e.size);
    if (deferred)
        g->deferred = *deferred; /* grid_init completes it */
    g->phases.read_ms = read_ms, g->phases.serial_ms = serial_ms;
    return finish(g, out, msg, msg_len);
}

/* ---- .nvdb files --------------------------------------------------------
 * As nanovdb/util/IO.h writes them: one or more segments, each
 *   header   magic u64, version u32, grid count u16, codec u16   (16 bytes)
 *   metadata per grid: 176 bytes (IO.h's MetaData) + its name
 *   the grids' bytes, each `fileSize` long (== gridSize when uncompressed). */

enum { NVDB_HEADER = 16, NVDB_META = 176 };

static int read_exact(FILE *f, void *dst, size_t n) { return fread(dst, 1, n, f) == n; }

/* The segment of a .nvdb file at byte *at (f positioned there): its
 * header, and each grid's metadata into entries[*n], (*n)++, with the
 * offset of its bytes in the file; then *at and f past the segment. `end`:
 * the file's size. */
static sdft_error read_segment(FILE *f, const char *path, uint64_t end, grid_entry *entries, size_t *n, uint64_t *at,
                               char *msg, size_t msg_len)
{
    unsigned char head[NVDB_HEADER];
    uint64_t magic;
    uint32_t version;
    uint16_t count, codec;
    if (!read_exact(f, head, sizeof head))
        return fail_with(msg, msg_len, SDFT_EFORMAT, "%s is truncated: incomplete segment header", path);
    memcpy(&magic, head, 8), memcpy(&version, head + 8, 4), memcpy(&count, head + 12, 2), memcpy(&codec, head + 14, 2);
    if (magic != PNANOVDB_MAGIC_NUMBER)
        return fail_with(msg, msg_len, SDFT_EFORMAT, "%s is not a NanoVDB file (bad magic number)", path);
    if (version >> 21u != PNANOVDB_MAJOR_VERSION_NUMBER)
        return fail_with(msg, msg_len, SDFT_EFORMAT, "%s is NanoVDB version %u; this build reads %u", path,
                         version >> 21u, PNANOVDB_MAJOR_VERSION_NUMBER);
    if (codec != 0)
        return fail_with(msg, msg_len, SDFT_EFORMAT, "%s is compressed (codec %u); write it uncompressed", path, codec);
    *at += NVDB_HEADER;
    const size_t first = *n;
    for (uint16_t i = 0; i < count; i++) {
        unsigned char meta[NVDB_META];
        uint32_t name_size;
        if (*n == 64)
            return fail_with(msg, msg_len, SDFT_EFORMAT, "%s holds more than 64 grids", path);
        if (!read_exact(f, meta, sizeof meta))
            return fail_with(msg, msg_len, SDFT_EFORMAT, "%s is truncated: incomplete grid metadata", path);
        grid_entry *e = &entries[*n];
        memset(e, 0, sizeof *e);
        uint64_t file_size;
        memcpy(&e->size, meta, 8), memcpy(&file_size, meta + 8, 8);
        memcpy(&e->type, meta + 32, 4), memcpy(&e->grid_class, meta + 36, 4);
        memcpy(&name_size, meta + 136, 4);
        if (file_size != e->size || name_size == 0 || name_size > 1u << 20)
            return fail_with(msg, msg_len, SDFT_EFORMAT, "%s is corrupt: bad sizes in grid metadata", path);
        char tmp[256];
        size_t keep = name_size < sizeof tmp ? name_size : sizeof tmp;
        if (!read_exact(f, tmp, keep) || fseek(f, (long)(name_size - keep), SEEK_CUR) != 0)
            return fail_with(msg, msg_len, SDFT_EFORMAT, "%s is truncated: incomplete grid name", path);
        tmp[keep - 1] = '\0';
        memcpy(e->name, tmp, keep);
        *at += NVDB_META + name_size;
        (*n)++;
    }
    for (size_t i = first; i < *n; i++) {
        entries[i].offset = *at;
        /* *at may already be past the end (a name longer than the file is
         * skipped by fseek): then end - *at would wrap and pass any size. */
        if (*at > end || entries[i].size > end - *at)
            return fail_with(msg, msg_len, SDFT_EFORMAT, "%s is truncated: grid '%s' needs %llu bytes, %llu left", path,
                             entries[i].name, (unsigned long long)entries[i].size, (unsigned long long)(end - *at));
        *at += entries[i].size;
    }
    if (fseek(f, (long)*at, SEEK_SET) != 0)
        return fail_with(msg, msg_len, SDFT_EIO, "cannot seek in %s", path);
    return SDFT_OK;
}

/* n bytes of the file fd from byte `at` into dst: chunks read in
 * parallel, so that each thread copies its part from the page cache and
 * takes the first touches of its part of dst. 0, or -1 on a read error or
 * a short file. */
static int read_parallel(int fd, void *dst, uint64_t n, uint64_t at)
{
    enum { CHUNK = 4 << 20 };
    const long chunks = (long)((n + CHUNK - 1) / CHUNK);
    int failed = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(| : failed)
    for (long c = 0; c < chunks; c++) {
        uint64_t off = (uint64_t)c * CHUNK, len = n - off < CHUNK ? n - off : CHUNK;
        while (len && !failed) {
            const ssize_t r = pread(fd, (char *)dst + off, (size_t)len, (off_t)(at + off));
            if (r < 0 && errno == EINTR)
                continue;
            if (r <= 0)
                failed = 1;
            else
                off += (uint64_t)r, len -= (uint64_t)r;
        }
    }
    return failed ? -1 : 0;
}

/* The grid `name` (chosen as grid.h says) of the .nvdb file at path: its
 * headers read in turn, then its bytes in parallel (read_parallel). */
static sdft_error load_nvdb(const char *path, const char *name, sdft_grid **out, char *msg, size_t msg_len)
{
    const double t0 = omp_get_wtime();
    FILE *f = fopen(path, "rb");
    if (!f)
        return fail_with(msg, msg_len, SDFT_EIO, "cannot open %s: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode) || fseek(f, 0, SEEK_END) != 0) {
        fclose(f);
        return fail_with(msg, msg_len, SDFT_EIO, "cannot read %s: not a regular file", path);
    }
    long end = ftell(f);
    rewind(f);
    grid_entry entries[64];
    size_t n = 0;
    sdft_error rc = SDFT_OK;
    for (uint64_t at = 0; at < (uint64_t)end && !rc;)
        rc = read_segment(f, path, (uint64_t)end, entries, &n, &at, msg, msg_len);
    size_t pick = 0;
    if (!rc)
        rc = choose(entries, n, name, path, &pick, msg, msg_len);
    sdft_grid *g = NULL;
    if (!rc && !(g = grid_alloc(entries[pick].size)))
        rc = fail_with(msg, msg_len, SDFT_ENOMEM, "out of memory for a %llu-byte grid",
                       (unsigned long long)entries[pick].size);
    const double t1 = omp_get_wtime();
    if (!rc && read_parallel(fileno(f), g->words, g->size, entries[pick].offset))
        rc = fail_with(msg, msg_len, SDFT_EIO, "cannot read grid '%s' from %s", entries[pick].name, path);
    fclose(f);
    if (g)
        g->phases.read_ms = 1e3 * (omp_get_wtime() - t0), g->phases.serial_ms = 1e3 * (t1 - t0);
    if (rc) {
        sdft_grid_free(g);
        return rc;
    }
    return finish(g, out, msg, msg_len);
}

/* ---- the one way in ------------------------------------------------------ */

sdft_grid_options sdft_grid_options_defaults(void)
{
    sdft_grid_options o;
    memset(&o, 0, sizeof o);
    o.memory = SDFT_GRID_COPY;
    o.defer = SDFT_DEFER_NONE;
    o.quant = SDFT_QUANT_NONE;
    o.stream = 1;
    return o;
}

/* A buffer in memory, as o says: copied, borrowed or adopted, its leaves
 * there or deferred. */
static sdft_error open_buffer(const sdft_grid_options *o, sdft_grid **out, char *msg, size_t msg_len)
{
    if ((unsigned)o->memory > SDFT_GRID_ADOPT)
        return fail_with(msg, msg_len, SDFT_EINVAL, "unknown memory %d (copy, borrow or adopt)", (int)o->memory);
    if ((unsigned)o->defer > SDFT_DEFER_ALWAYS)
        return fail_with(msg, msg_len, SDFT_EINVAL, "unknown way to defer %d", (int)o->defer);
    if (o->memory == SDFT_GRID_ADOPT && !o->release)
        return fail_with(msg, msg_len, SDFT_EINVAL, "no release function (NULL): borrow the buffer instead");
    if (!o->fill != !o->defer || (o->fill && o->memory != SDFT_GRID_ADOPT))
        return fail_with(msg, msg_len, SDFT_EINVAL,
                         "deferred leaves need a fill function, a way to defer and an "
                         "adopted buffer");
    const grid_deferred d = {.fill = o->fill, .user = o->fill_user, .how = o->defer};
    const sdft_error rc = grid_of_buffer(o->data, o->size, o->name, o->memory != SDFT_GRID_COPY, o->fill ? &d : NULL,
                                         o->read_ms, o->read_serial_ms, out, msg, msg_len);
    if (!rc && o->memory == SDFT_GRID_ADOPT) {
        (*out)->release = o->release;
        (*out)->release_data = (void *)(uintptr_t)o->data;
        (*out)->deferred.user = o->fill_user; /* released with the grid, deferred or not */
        (*out)->deferred.release_user = o->fill_release;
    }
    return rc;
}

/* The owners of what an adopting call was handed, told once it refuses. */
static sdft_error refuse(const sdft_grid_options *o, sdft_error rc)
{
    if (rc && o->memory == SDFT_GRID_ADOPT && !o->path) {
        if (o->release && o->data)
            o->release((void *)(uintptr_t)o->data);
        if (o->fill_release)
            o->fill_release(o->fill_user);
    }
    return rc;
}

sdft_error sdft_grid_open(const sdft_grid_options *o, sdft_grid **out, char *msg, size_t msg_len)
{
    if (!o)
        return fail_with(msg, msg_len, SDFT_EINVAL, "no options (NULL; sdft_grid_options_defaults makes them)");
    if (!out)
        return refuse(o, fail_with(msg, msg_len, SDFT_EINVAL, "no place for the grid (out is NULL)"));
    *out = NULL;
    if (!o->path)
        return refuse(o, open_buffer(o, out, msg, msg_len));
    const char *dot = strrchr(o->path, '.');
    if (dot && strcmp(dot, ".vdb") == 0)
        return fail_with(msg, msg_len, SDFT_EFORMAT,
                         "%s is a .vdb file: the OpenVDB component's sdft_vdb_open reads it", o->path);
    return load_nvdb(o->path, o->name, out, msg, msg_len);
}

/* ---- queries ------------------------------------------------------------ */

const char *sdft_grid_name(const sdft_grid *g) { return g->name; }
const char *sdft_grid_type_name(const sdft_grid *g) { return type_name(g->type); }
const char *sdft_grid_class_name(const sdft_grid *g) { return class_name(g->grid_class); }
int sdft_grid_is_level_set(const sdft_grid *g) { return g->grid_class == PNANOVDB_GRID_CLASS_LEVEL_SET; }
sdft_vec3 sdft_grid_voxel_size(const sdft_grid *g) { return g->voxel_size; }
float sdft_grid_background(const sdft_grid *g) { return g->background; }
sdft_aabb sdft_grid_world_bounds(const sdft_grid *g) { return g->bounds; }

uint64_t sdft_grid_active_voxels(const sdft_grid *g)
{
    return pnanovdb_tree_get_voxel_count(g->buf, pnanovdb_grid_get_tree(g->buf, g->grid));
}

void sdft_grid_index_bounds(const sdft_grid *g, int32_t lo[3], int32_t hi[3])
{
    memcpy(lo, g->ilo, sizeof g->ilo);
    memcpy(hi, g->ihi, sizeof g->ihi);
}

size_t sdft_grid_size(const sdft_grid *g) { return g->size; }

void sdft_grid_load_phases(const sdft_grid *g, sdft_grid_phases *phases) { *phases = g->phases; }

const void *sdft_grid_data(const sdft_grid *g, size_t *size)
{
    grid_fill_all(g);
    if (size)
        *size = g->size;
    return g->words;
}
