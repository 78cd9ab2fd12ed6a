/* sdftrace scene "temple" — a peripteral temple: a six-step platform, a
 * colonnade of 32 fluted columns (6 by 12) around a walled cella, an
 * entablature, a gabled roof of thin overhanging plates, a thin ridge rod,
 * and a fence of thin rods before the front steps, all on a ground slab.
 *
 * Why it is a bound: primitives are exact, unions and intersections are
 * min/max, the mirrors |x|, |z| are 1-Lipschitz, and every repeated part (a
 * column in its 1.6-wide cell, a flute in its 1/16 sector, a fence rod) is
 * mirror-symmetric about its cell's mid-planes and inside its cell, so the
 * folded distances agree across cell walls (continuous, 1-Lipschitz) and
 * have the right sign: see sdft_op_repeat in sdf.h. */
#include "scenes.h"
#include "sdftrace/sdf.h"

#define SPACING 1.6f /* column axis to axis */
#define HALF_X 4.0f  /* |x| of the side rows */
#define HALF_Z 8.8f  /* |z| of the front and back rows */
#define TOP 4.08f    /* top of a column's abacus */
#define RIDGE 6.4f   /* height of the roof ridge */

static sdft_vec3 at(sdft_vec3 p, float x, float y, float z) { return sdft_translate(p, sdft_v3(x, y, z)); }

/* Bounding-volume early-out (sdf.h): the detail is evaluated only within
 * `near` of a volume that encloses it. */
static float within(float bound, float near, float (*detail)(sdft_vec3), sdft_vec3 p)
{
    return bound >= near ? bound : sdft_op_near_bound(bound, detail(p), near);
}

/* A shaft with 16 flutes cut in. Cutting only removes material, so the
 * plain cylinder is a bound on the fluted one. */
static float fluted_shaft(sdft_vec3 p)
{
    const float near = 0.05f;
    float shaft = sdft_sd_cylinder(at(p, 0, 2.0f, 0), 0.3f, 1.85f);
    if (shaft >= near)
        return shaft;
    float flute = sdft_sd_cylinder(at(sdft_op_repeat_angular_y(p, 16), 0.31f, 2.0f, 0), 0.045f, 1.7f);
    return sdft_op_near_bound(shaft, sdft_op_subtract(flute, shaft), near);
}

/* One column standing at the origin: plinth, torus, fluted shaft, capital. */
static float column_detail(sdft_vec3 p)
{
    float plinth = sdft_sd_box(at(p, 0, 0.06f, 0), sdft_v3(0.38f, 0.06f, 0.38f));
    float torus = sdft_sd_torus(at(p, 0, 0.17f, 0), 0.3f, 0.06f);
    float echinus = sdft_sd_cylinder(at(p, 0, 3.86f, 0), 0.36f, 0.06f);
    float abacus = sdft_sd_box(at(p, 0, 4.0f, 0), sdft_v3(0.42f, 0.08f, 0.42f));
    return sdft_minf(sdft_minf(plinth, torus), sdft_minf(fluted_shaft(p), sdft_minf(echinus, abacus)));
}

/* Every part of a column lies in the box |x|, |z| <= 0.42, 0 <= y <= 4.08. */
static float column(sdft_vec3 p)
{
    return within(sdft_sd_box(at(p, 0, 0.5f * TOP, 0), sdft_v3(0.42f, 0.5f * TOP, 0.42f)), 0.1f, column_detail, p);
}

/* Front and back rows of six (x = +-0.8, +-2.4, +-4.0), side rows of five
 * more per half side (|z| = 0.8 .. 7.2). */
static float colonnade(sdft_vec3 p)
{
    sdft_vec3 m = sdft_mirror_z(sdft_mirror_x(p));
    sdft_vec3 front =
        sdft_op_repeat_limited(at(m, 0.5f * SPACING, 0, HALF_Z), sdft_v3(SPACING, 0, 0), sdft_v3(2, 0, 0));
    sdft_vec3 side = sdft_op_repeat_limited(at(m, HALF_X, 0, 0.5f * SPACING), sdft_v3(0, 0, SPACING), sdft_v3(0, 0, 4));
    return sdft_minf(column(front), column(side));
}

/* Six steps of 0.2 rise and 0.25 run down from the platform top at y = 0. */
static float platform(sdft_vec3 p)
{
    float d = INFINITY;
    for (int i = 0; i < 6; i++)
        d = sdft_minf(d, sdft_sd_box(at(p, 0, -0.1f - 0.2f * i, 0), sdft_v3(4.8f + 0.25f * i, 0.1f, 9.6f + 0.25f * i)));
    return d;
}

/* The cella: a walled room with a door recess facing +z. */
static float cella(sdft_vec3 p)
{
    float walls = sdft_sd_box(at(p, 0, 0.5f * TOP, 0), sdft_v3(2.6f, 0.5f * TOP, 6.4f));
    float door = sdft_sd_box(at(p, 0, 1.4f, 6.4f), sdft_v3(0.7f, 1.4f, 0.3f));
    return sdft_op_subtract(door, walls);
}

/* Architrave and a thin cornice over the columns, the pediment under a
 * gable, and the roof: two 6 cm plates overhanging the pediment by 20 cm. */
static float roof(sdft_vec3 p)
{
    float architrave = sdft_sd_box(at(p, 0, TOP + 0.3f, 0), sdft_v3(4.45f, 0.3f, 9.25f));
    float cornice = sdft_sd_box(at(p, 0, TOP + 0.66f, 0), sdft_v3(4.65f, 0.06f, 9.45f));
    sdft_vec3 slope = sdft_normalize(sdft_v3(1.6f, 4.7f, 0)); /* from the ridge down to |x| = 4.7 at y = 4.8 */
    float under_gable = sdft_sd_plane(at(sdft_mirror_x(p), 0, RIDGE, 0), slope, 0);
    float pediment = sdft_op_intersect(under_gable, sdft_sd_box(at(p, 0, 5.6f, 0), sdft_v3(4.7f, 0.8f, 9.3f)));
    float plate = fabsf(under_gable - 0.03f) - 0.03f;
    float tiles = sdft_op_intersect(plate, sdft_sd_box(at(p, 0, 5.6f, 0), sdft_v3(4.9f, 0.9f, 9.5f)));
    float ridge_rod = sdft_sd_capsule(p, sdft_v3(0, RIDGE + 0.06f, -9.5f), sdft_v3(0, RIDGE + 0.06f, 9.5f), 0.015f);
    return sdft_minf(sdft_minf(architrave, cornice), sdft_minf(sdft_minf(pediment, tiles), ridge_rod));
}

/* A fence of thin rods, 30 cm apart, 1 m tall, with a top rail, across the
 * front of the ground 2.5 m before the lowest step. */
static float fence(sdft_vec3 p)
{
    sdft_vec3 q = at(p, 0, -1.2f, 13.35f);
    sdft_vec3 r = sdft_op_repeat_limited(q, sdft_v3(0.3f, 0, 0), sdft_v3(20, 0, 0));
    float rods = sdft_sd_cylinder(at(r, 0, 0.5f, 0), 0.012f, 0.5f);
    float rail = sdft_sd_capsule(q, sdft_v3(-6.0f, 1.0f, 0), sdft_v3(6.0f, 1.0f, 0), 0.02f);
    return sdft_minf(rods, rail);
}

static float ground(sdft_vec3 p) { return sdft_sd_box(at(p, 0, -1.3f, 0), sdft_v3(14.0f, 0.1f, 18.0f)); }

static float building(sdft_vec3 p)
{
    return sdft_minf(sdft_minf(platform(p), colonnade(p)), sdft_minf(cella(p), roof(p)));
}

static float temple_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    /* The building (lowest step to roof plates) lies in |x| <= 6.1,
     * -1.2 <= y <= 6.6, |z| <= 10.9; the fence in |x| <= 6.02, -1.2 <= y <=
     * -0.18, |z - 13.35| <= 0.02. */
    float building_box = sdft_sd_box(at(p, 0, 2.7f, 0), sdft_v3(6.2f, 4.0f, 11.0f));
    float fence_box = sdft_sd_box(at(p, 0, -0.7f, 13.35f), sdft_v3(6.1f, 0.55f, 0.1f));
    return sdft_minf(sdft_minf(within(building_box, 0.5f, building, p), within(fence_box, 0.2f, fence, p)), ground(p));
}

/* With materials: the ground a checker floor, the rest grey. */
static sdft_material temple_material(const void *ctx, sdft_vec3 p)
{
    return ground(p) <= temple_distance(ctx, NULL, p) ? scene_checker(p, 1.0f) : scene_grey();
}

const sdft_scene scene_temple = {
    .name = "temple",
    .description = "a temple of 32 fluted columns, stairs, a gabled roof, thin plates, rods and a fence",
    .field = {.distance = temple_distance,
              .bounds = {{-14.02f, -1.42f, -18.02f}, {14.02f, RIDGE + 0.2f, 18.02f}},
              .feature_size = 1e-3f,
              .material = temple_material},
    .camera = {.from = {12.0f, 3.0f, 24.0f}, .at = {0.0f, 2.0f, 0.0f}, .up = {0, 1, 0}, .fov_deg = 42.0f},
    .light = {20.0f, 30.0f, 25.0f},
};
