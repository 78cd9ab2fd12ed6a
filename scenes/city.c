/* sdftrace scene "city" — Keinert's city: 81 x 81 blocks of buildings with
 * heights and footprints drawn by a hash of the block, towers with setbacks
 * and thin antennas, streets between them, receding to the horizon from a
 * camera at street level, where most rays graze facades and the ground.
 *
 * Why it is a bound: buildings differ per cell, so folding space into one
 * cell alone would not be (the neighbour's building may be nearer than this
 * cell's). Every building lies at least MARGIN inside its 2 m cell, so the
 * cell-wall bound min(d_own, wall + MARGIN) of sdf.h holds: any other
 * building is reached only after leaving this cell and then crossing that
 * building's margin. d_own is an exact union of boxes and capsules, >= MARGIN
 * at every wall, so the bound is also continuous across walls. */
#include <stdint.h>

#include "scenes.h"
#include "sdftrace/sdf.h"

#define CELL 2.0f   /* block pitch, metres */
#define BLOCKS 40   /* cells -40..40 along x and z */
#define MARGIN 0.3f /* half street: CELL / 2 - widest half footprint */
#define EXTENT ((BLOCKS + 0.5f) * CELL)
#define TALLEST 10.2f /* 0.5 + 2.5 + 4 storeys of tower, 30% setback, 1 m antenna */

/* Three numbers in [0, 1) per block, from an integer hash of its index. */
static float block_hash(int ix, int iz, unsigned salt)
{
    uint32_t h = (uint32_t)ix * 0x8da6b343u ^ (uint32_t)iz * 0xd8163841u ^ salt * 0xcb1ab31fu;
    h ^= h >> 16, h *= 0x7feb352du, h ^= h >> 15, h *= 0x846ca68bu, h ^= h >> 16;
    return (float)(h >> 8) * (1.0f / 16777216.0f);
}

/* The building of block (ix, iz) in the block's own frame; INFINITY for an
 * empty lot. Footprint half-widths 0.45..0.7 (<= CELL / 2 - MARGIN). */
static float building(sdft_vec3 q, int ix, int iz)
{
    float h = block_hash(ix, iz, 1), wx = 0.45f + 0.25f * block_hash(ix, iz, 2),
          wz = 0.45f + 0.25f * block_hash(ix, iz, 3);
    if (h < 0.06f)
        return INFINITY;
    float height = 0.5f + 2.5f * h + (h > 0.93f ? 4.0f : 0.0f);
    float d = sdft_sd_box(sdft_translate(q, sdft_v3(0, 0.5f * height, 0)), sdft_v3(wx, 0.5f * height, wz));
    if (height > 2.5f) {
        float top = 0.15f * height;
        sdft_vec3 setback = sdft_translate(q, sdft_v3(0, height + top, 0));
        d = sdft_minf(d, sdft_sd_box(setback, sdft_v3(0.6f * wx, top, 0.6f * wz)));
        if (height > 4.0f)
            d = sdft_minf(d, sdft_sd_capsule(q, sdft_v3(0, height, 0), sdft_v3(0, 1.3f * height + 1.0f, 0), 0.02f));
    }
    return d;
}

static float buildings(sdft_vec3 p)
{
    sdft_cell c = sdft_cell_locate(p, sdft_v3(CELL, 0, CELL), sdft_v3(BLOCKS, 0, BLOCKS));
    return sdft_cell_bound(&c, building(c.q, c.ix, c.iz), MARGIN);
}

static float ground(sdft_vec3 p)
{
    return sdft_sd_box(sdft_translate(p, sdft_v3(0, -0.05f, 0)), sdft_v3(EXTENT, 0.05f, EXTENT));
}

static float city_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    return sdft_minf(buildings(p), ground(p));
}

/* With materials: the ground a checker floor, the rest grey. */
static sdft_material city_material(const void *ctx, sdft_vec3 p)
{
    return ground(p) <= city_distance(ctx, NULL, p) ? scene_checker(p, 1.0f) : scene_grey();
}

const sdft_scene scene_city = {
    .name = "city",
    .description = "81 x 81 blocks of hashed-height buildings receding to the horizon, seen from a street",
    .field = {.distance = city_distance,
              .bounds = {{-EXTENT - 0.02f, -0.12f, -EXTENT - 0.02f}, {EXTENT + 0.02f, TALLEST, EXTENT + 0.02f}},
              .feature_size = 1e-3f,
              .material = city_material},
    .camera = {.from = {1.0f, 4.2f, 79.0f}, .at = {1.0f, 2.0f, 0.0f}, .up = {0, 1, 0}, .fov_deg = 50.0f},
    .light = {60.0f, 120.0f, 90.0f},
};
