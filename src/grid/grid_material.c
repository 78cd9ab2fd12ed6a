/* sdftrace — a grid's surface materials: a second grid of material
 * indices (`sdftrace bake --materials` writes it beside the surface, with
 * the table), read at the voxel nearest the shaded point. Shading reads it
 * a few times a pixel, so a lookup is a plain walk from the root, with no
 * per-thread state. */
#include <stdlib.h>
#include <string.h>

#include "grid_internal.h"

/* The index point of world point p in grid g. */
static void world_to_index(const sdft_grid *g, sdft_vec3 p, float x[3])
{
    const float *m = g->w2i;
    x[0] = m[0] * p.x + m[1] * p.y + m[2] * p.z + g->w2i_t[0];
    x[1] = m[3] * p.x + m[4] * p.y + m[5] * p.z + g->w2i_t[1];
    x[2] = m[6] * p.x + m[7] * p.y + m[8] * p.z + g->w2i_t[2];
}

/* The table's entry for a stored index: rounded, clamped into the table. */
static sdft_material entry(const sdft_grid *g, float v)
{
    const float top = (float)(g->material_count - 1);
    const float k = isfinite(v) ? sdft_minf(sdft_maxf(roundf(v), 0.0f), top) : 0.0f;
    return g->material_table[(size_t)k];
}

sdft_material grid_material(const void *ctx, sdft_vec3 p)
{
    const sdft_grid *g = ctx, *ids = g->material_ids;
    float x[3];
    world_to_index(ids, p, x);
    const int32_t c[3] = {(int32_t)floorf(x[0] + 0.5f), (int32_t)floorf(x[1] + 0.5f), (int32_t)floorf(x[2] + 0.5f)};
    int active;
    float v = sdft_grid_voxel(ids, c[0], c[1], c[2], &active);
    if (active)
        return entry(g, v);
    /* The nearest voxel lies off the stored band: the nearest active one of its 26 neighbours. */
    float best = INFINITY, best_v = 0.0f;
    for (int n = 0; n < 27; n++) {
        const int32_t d[3] = {n % 3 - 1, n / 3 % 3 - 1, n / 9 - 1};
        const float w = sdft_grid_voxel(ids, c[0] + d[0], c[1] + d[1], c[2] + d[2], &active);
        const float e[3] = {(float)(c[0] + d[0]) - x[0], (float)(c[1] + d[1]) - x[1], (float)(c[2] + d[2]) - x[2]};
        const float r = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        if (active && r < best)
            best = r, best_v = w;
    }
    return entry(g, best_v);
}

/* Why material m cannot be shaded, or NULL. */
static const char *bad_material(const sdft_material *m)
{
    const float c[3] = {m->colour.x, m->colour.y, m->colour.z};
    for (int k = 0; k < 3; k++)
        if (!(c[k] >= 0.0f && c[k] <= 1.0f))
            return "a colour component outside [0, 1]";
    if (!(m->reflectance >= 0.0f && m->reflectance <= 1.0f))
        return "a reflectance outside [0, 1]";
    if (!(m->ior == 0.0f || (m->ior >= 1.0f && isfinite(m->ior))))
        return "an index of refraction neither 0 (opaque) nor a finite number >= 1";
    return NULL;
}

sdft_error sdft_grid_set_materials(sdft_grid *g, const sdft_grid *ids, const sdft_material *table, size_t count,
                                   char *msg, size_t msg_len)
{
    if (!g)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_grid_set_materials: NULL grid");
    if (!ids) {
        free(g->material_table);
        g->material_ids = NULL, g->material_table = NULL, g->material_count = 0;
        return SDFT_OK;
    }
    if (!table || count == 0 || count > SDFT_GRID_MAX_MATERIALS)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_grid_set_materials: %s",
                         !table       ? "NULL table"
                         : count == 0 ? "an empty table"
                                      : "more materials than SDFT_GRID_MAX_MATERIALS");
    for (size_t k = 0; k < count; k++) {
        const char *why = bad_material(&table[k]);
        if (why)
            return fail_with(msg, msg_len, SDFT_EINVAL, "material %zu: %s", k, why);
    }
    sdft_material *copy = malloc(count * sizeof *copy);
    if (!copy)
        return fail_with(msg, msg_len, SDFT_ENOMEM, "out of memory for %zu materials", count);
    memcpy(copy, table, count * sizeof *copy);
    free(g->material_table);
    g->material_ids = ids, g->material_table = copy, g->material_count = count;
    return SDFT_OK;
}

sdft_error sdft_grid_material_table(const sdft_grid *t, sdft_material *table, size_t most, size_t *count, char *msg,
                                    size_t msg_len)
{
    if (!t || !table || !count)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_grid_material_table: NULL %s",
                         !t       ? "grid"
                         : !table ? "table"
                                  : "count");
    /* Material k is the row of voxels (k, 0..4, 0): red, green, blue, reflectance, index of refraction. */
    size_t n = 0;
    int active;
    for (; n < most && (sdft_grid_voxel(t, (int32_t)n, 0, 0, &active), active); n++) {
        float v[5];
        for (int c = 0; c < 5; c++) {
            v[c] = sdft_grid_voxel(t, (int32_t)n, c, 0, &active);
            if (!active)
                return fail_with(msg, msg_len, SDFT_EFORMAT, "%s: material %zu lacks component %d", t->name, n, c);
        }
        table[n] = (sdft_material){.colour = {v[0], v[1], v[2]}, .reflectance = v[3], .ior = v[4]};
        const char *why = bad_material(&table[n]);
        if (why)
            return fail_with(msg, msg_len, SDFT_EFORMAT, "%s: material %zu has %s", t->name, n, why);
    }
    if (n == 0)
        return fail_with(msg, msg_len, SDFT_EFORMAT, "%s holds no material (voxel (0, 0, 0) is inactive)", t->name);
    (void)sdft_grid_voxel(t, (int32_t)n, 0, 0, &active);
    if (active)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s holds more than %zu materials", t->name, most);
    *count = n;
    return SDFT_OK;
}
