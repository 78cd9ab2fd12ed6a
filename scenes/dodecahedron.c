/* sdftrace scene "dodecahedron" — Keinert et al. Fig. 11: a convex
 * dodecahedron (Akleman–Chen bound) inside its bounding sphere, floating over
 * a ground slab, three spheres beside it. The dodecahedron is a convex part
 * in that sphere (3.5); with materials it is glass, the spheres red, blue
 * and a mirror, the ground a checker floor. */
#include "scenes.h"
#include "sdftrace/sdf.h"

#define INRADIUS 1.0f
#define CIRCUMRADIUS (1.2584f * INRADIUS) /* sqrt(3) / (phi^2 / sqrt(phi + 2)) */
#define CENTRE_Y 1.45f

/* The bounding sphere answers alone while it is farther than 0.25 (the
 * dodecahedron lies inside it, so is no nearer); closer, the dodecahedron,
 * joined continuously (sdft_op_near_bound). */
static sdft_vec3 gem_frame(sdft_vec3 p)
{
    return sdft_rotate_y(sdft_translate(p, sdft_v3(0.0f, CENTRE_Y, 0.0f)), 0.35f);
}

/* The dodecahedron alone: the convex part. */
static float dodecahedron_part(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    return sdft_sd_dodecahedron(gem_frame(p), INRADIUS);
}

static float gem(sdft_vec3 p)
{
    sdft_vec3 q = gem_frame(p);
    float sphere = sdft_sd_sphere(q, CIRCUMRADIUS + 0.01f);
    return sphere > 0.25f ? sphere : sdft_op_near_bound(sphere, sdft_sd_dodecahedron(q, INRADIUS), 0.25f);
}

static float beads(sdft_vec3 p)
{
    float a = sdft_sd_sphere(sdft_translate(p, sdft_v3(2.3f, 0.5f, 0.7f)), 0.5f);
    float b = sdft_sd_sphere(sdft_translate(p, sdft_v3(-2.0f, 0.35f, 1.1f)), 0.35f);
    float c = sdft_sd_sphere(sdft_translate(p, sdft_v3(-2.6f, 0.7f, -1.5f)), 0.7f);
    return sdft_minf(a, sdft_minf(b, c));
}

static float ground(sdft_vec3 p) { return sdft_sd_box(sdft_translate(p, sdft_v3(0, -0.05f, 0)), sdft_v3(6, 0.05f, 6)); }

static float dodecahedron_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    return sdft_minf(gem(p), sdft_minf(beads(p), ground(p)));
}

static sdft_material dodecahedron_material(const void *ctx, sdft_vec3 p)
{
    (void)ctx;
    const float g = gem(p), a = sdft_sd_sphere(sdft_translate(p, sdft_v3(2.3f, 0.5f, 0.7f)), 0.5f),
                b = sdft_sd_sphere(sdft_translate(p, sdft_v3(-2.0f, 0.35f, 1.1f)), 0.35f),
                c = sdft_sd_sphere(sdft_translate(p, sdft_v3(-2.6f, 0.7f, -1.5f)), 0.7f);
    const float nearest = sdft_minf(sdft_minf(g, a), sdft_minf(b, c));
    if (ground(p) < nearest)
        return scene_checker(p, 0.5f);
    if (g == nearest)
        return (sdft_material){.colour = {0.92f, 0.96f, 1.0f}, .reflectance = 0.0f, .ior = 1.5f};
    if (a == nearest)
        return (sdft_material){.colour = {0.80f, 0.15f, 0.12f}, .reflectance = 0.0f, .ior = 0.0f};
    if (b == nearest)
        return (sdft_material){.colour = {0.15f, 0.30f, 0.85f}, .reflectance = 0.0f, .ior = 0.0f};
    return (sdft_material){.colour = {0.90f, 0.90f, 0.90f}, .reflectance = 0.8f, .ior = 0.0f};
}

static const sdft_convex_part convex_parts[] = {
    {.distance = dodecahedron_part, .centre = {0.0f, CENTRE_Y, 0.0f}, .radius = CIRCUMRADIUS + 0.01f},
};

static const sdft_field_accel dodecahedron_accel = {.convex = convex_parts, .convex_count = 1};

const sdft_scene scene_dodecahedron = {
    .name = "dodecahedron",
    .description = "a dodecahedron in its bounding sphere and three spheres over a ground slab (Keinert Fig. 11)",
    .field = {.distance = dodecahedron_distance,
              .bounds = {{-6.02f, -0.12f, -6.02f}, {6.02f, CENTRE_Y + CIRCUMRADIUS + 0.05f, 6.02f}},
              .feature_size = 1e-3f,
              .accel = &dodecahedron_accel,
              .material = dodecahedron_material},
    .camera = {.from = {0.6f, 2.6f, 6.4f}, .at = {0.0f, 0.9f, 0.0f}, .up = {0, 1, 0}, .fov_deg = 40.0f},
    .light = {4.0f, 8.0f, 5.0f},
};
