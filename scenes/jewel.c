/* sdftrace scene "jewel" — after Keinert et al.'s jewel scene (Fig. 1): a
 * round brilliant of glass, tilted, floating over a checker floor, a red
 * bead and a mirror ball beside it. Rendered with its materials: the gem
 * shows the floor refracted through it, bent and broken up by its facets.
 *
 * The gem is a generalized distance function (Akleman and Chen), as the
 * dodecahedron: the max over its facets' planes of the signed distance
 * to each, an intersection of half-spaces, so convex; exact inside and
 * along the facets' normals, below the true distance near edges and
 * corners outside: a bound. Its eight crown and eight pavilion facets and
 * sixteen girdle facets repeat around its axis; folding a point into its
 * sector (sdft_op_repeat_angular_y) leaves the nearest plane of each kind
 * in the sector, and the max over the sector's planes is the max over all,
 * since a plane's value falls with the angle between point and facet. */
#include "scenes.h"
#include "sdftrace/sdf.h"

#define CENTRE_Y 1.45f
#define RADIUS 1.0f    /* the girdle's, to its facets */
#define CIRCUM 1.035f  /* a girdle corner's distance from the centre, the farthest point: 1 / cos(pi / 16), y 0.03 */
#define TOP 0.6f       /* above the centre, the tilted gem's highest point (0.53, a corner of its table) and a margin */
#define TILT_C 0.9397f /* cos and sin of the gem's 20 degree tilt about x */
#define TILT_S 0.3420f

/* The gem's own frame: centred, its axis upright. */
static sdft_vec3 gem_frame(sdft_vec3 p)
{
    const sdft_vec3 q = sdft_translate(p, sdft_v3(0.0f, CENTRE_Y, 0.0f));
    return sdft_v3(q.x, TILT_C * q.y + TILT_S * q.z, -TILT_S * q.y + TILT_C * q.z);
}

/* A facet whose normal leans out from the axis by (s, c) (sine, cosine
 * from the vertical), at distance d from the centre, for q in its sector. */
static float facet(sdft_vec3 q, float s, float c, float d) { return s * q.x + c * q.y - d; }

static float brilliant(sdft_vec3 p)
{
    const sdft_vec3 q = gem_frame(p);
    const float table = q.y - 0.35f;
    const sdft_vec3 c8 = sdft_op_repeat_angular_y(q, 8);
    const float crown = facet(c8, 0.5664f, 0.8241f, 0.5911f); /* 34.5 degrees, through the girdle's top edge */
    const sdft_vec3 p8 = sdft_op_repeat_angular_y(sdft_rotate_y(q, 0.3927f), 8); /* offset by half a sector */
    const float pavilion = facet(p8, 0.6528f, -0.7576f, 0.6755f); /* 40.75 degrees, through its bottom edge */
    const float girdle = sdft_op_repeat_angular_y(q, 16).x - RADIUS;
    return sdft_maxf(sdft_maxf(table, crown), sdft_maxf(pavilion, girdle));
}

static float gem_part(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    return brilliant(p);
}

/* The bounding sphere answers alone while it is farther than 0.25. */
static float gem(sdft_vec3 p)
{
    const float sphere = sdft_sd_sphere(sdft_translate(p, sdft_v3(0.0f, CENTRE_Y, 0.0f)), CIRCUM + 0.01f);
    return sphere > 0.25f ? sphere : sdft_op_near_bound(sphere, brilliant(p), 0.25f);
}

static float red_bead(sdft_vec3 p) { return sdft_sd_sphere(sdft_translate(p, sdft_v3(1.9f, 0.45f, -0.8f)), 0.45f); }
static float mirror_ball(sdft_vec3 p) { return sdft_sd_sphere(sdft_translate(p, sdft_v3(-1.8f, 0.6f, -1.3f)), 0.6f); }
static float floor_slab(sdft_vec3 p)
{
    return sdft_sd_box(sdft_translate(p, sdft_v3(0, -0.05f, 0)), sdft_v3(5, 0.05f, 5));
}

static float jewel_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    return sdft_minf(sdft_minf(gem(p), floor_slab(p)), sdft_minf(red_bead(p), mirror_ball(p)));
}

static sdft_material jewel_material(const void *ctx, sdft_vec3 p)
{
    (void)ctx;
    const float g = gem(p), r = red_bead(p), m = mirror_ball(p);
    const float nearest = sdft_minf(g, sdft_minf(r, m));
    if (floor_slab(p) < nearest)
        return scene_checker(p, 0.5f);
    if (g == nearest)
        return (sdft_material){.colour = {0.90f, 0.97f, 1.0f}, .reflectance = 0.0f, .ior = 1.7f};
    if (r == nearest)
        return (sdft_material){.colour = {0.85f, 0.12f, 0.10f}, .reflectance = 0.15f, .ior = 0.0f};
    return (sdft_material){.colour = {0.95f, 0.95f, 0.95f}, .reflectance = 0.85f, .ior = 0.0f};
}

static const sdft_convex_part convex_parts[] = {
    {.distance = gem_part, .centre = {0.0f, CENTRE_Y, 0.0f}, .radius = CIRCUM + 0.01f},
};

static const sdft_field_accel jewel_accel = {.convex = convex_parts, .convex_count = 1};

const sdft_scene scene_jewel = {
    .name = "jewel",
    .description = "a glass brilliant over a checker floor, a red bead and a mirror ball (Keinert Fig. 1)",
    .field = {.distance = jewel_distance,
              .bounds = {{-5.02f, -0.12f, -5.02f}, {5.02f, CENTRE_Y + TOP, 5.02f}},
              .feature_size = 1e-3f,
              .accel = &jewel_accel,
              .material = jewel_material},
    .camera = {.from = {0.0f, 3.2f, 5.2f}, .at = {0.0f, 1.0f, 0.0f}, .up = {0, 1, 0}, .fov_deg = 38.0f},
    .light = {4.0f, 8.0f, 5.0f},
    .materials = 1,
};
