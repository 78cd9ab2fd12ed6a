/* sdftrace scene "figure" — a smoothly blended standing character on a
 * round pedestal: ellipsoids for torso, hips, skirt, head, hair and feet, capsules for
 * neck and limbs, all joined by smooth unions. Ellipsoids are the 1-Lipschitz
 * bound of sdf.h, the limbs are drawn for x >= 0 and mirrored (|x| is
 * 1-Lipschitz), smooth unions keep bounds bounds: the whole is a bound. */
#include "scenes.h"
#include "sdftrace/sdf.h"

static float ellipsoid_at(sdft_vec3 p, float x, float y, float z, sdft_vec3 radii)
{
    return sdft_sd_ellipsoid(sdft_translate(p, sdft_v3(x, y, z)), radii);
}

static float limb(sdft_vec3 p, sdft_vec3 a, sdft_vec3 b, float r) { return sdft_sd_capsule(p, a, b, r); }

/* Torso on hips and a bell of a skirt, neck, head with nose, hair and bun. */
static float body(sdft_vec3 p)
{
    float torso = ellipsoid_at(p, 0.0f, 1.17f, 0.0f, sdft_v3(0.19f, 0.27f, 0.12f));
    float hips = ellipsoid_at(p, 0.0f, 0.9f, 0.0f, sdft_v3(0.18f, 0.14f, 0.12f));
    float neck = limb(p, sdft_v3(0, 1.38f, 0), sdft_v3(0, 1.52f, 0.01f), 0.045f);
    float head = ellipsoid_at(p, 0.0f, 1.63f, 0.015f, sdft_v3(0.095f, 0.12f, 0.105f));
    float nose = sdft_sd_sphere(sdft_translate(p, sdft_v3(0, 1.615f, 0.12f)), 0.018f);
    float hair = ellipsoid_at(p, 0.0f, 1.66f, -0.025f, sdft_v3(0.105f, 0.115f, 0.105f));
    float bun = sdft_sd_sphere(sdft_translate(p, sdft_v3(0, 1.72f, -0.1f)), 0.055f);
    float bell = ellipsoid_at(p, 0.0f, 0.56f, 0.0f, sdft_v3(0.27f, 0.4f, 0.24f));
    float skirt = sdft_op_intersect(bell, 0.56f - p.y); /* the upper half of the bell, hem at y = 0.56 */
    float trunk = sdft_op_smooth_union(sdft_op_smooth_union(torso, hips, 0.08f), skirt, 0.05f);
    float top =
        sdft_op_smooth_union(sdft_op_smooth_union(head, nose, 0.02f), sdft_op_smooth_union(hair, bun, 0.04f), 0.02f);
    return sdft_op_smooth_union(sdft_op_smooth_union(trunk, neck, 0.05f), top, 0.04f);
}

/* One arm and one leg, for x >= 0 (the caller mirrors them). */
static float limbs(sdft_vec3 p)
{
    sdft_vec3 shoulder = {0.17f, 1.34f, 0.0f}, elbow = {0.29f, 1.1f, -0.02f}, wrist = {0.33f, 0.87f, 0.08f};
    float arm = sdft_op_smooth_union(limb(p, shoulder, elbow, 0.045f), limb(p, elbow, wrist, 0.036f), 0.02f);
    float hand = ellipsoid_at(p, 0.34f, 0.8f, 0.1f, sdft_v3(0.028f, 0.06f, 0.042f));
    sdft_vec3 hip = {0.09f, 0.86f, 0.0f}, knee = {0.1f, 0.48f, 0.03f}, ankle = {0.1f, 0.09f, -0.01f};
    float leg = sdft_op_smooth_union(limb(p, hip, knee, 0.075f), limb(p, knee, ankle, 0.05f), 0.03f);
    float foot = ellipsoid_at(p, 0.1f, 0.045f, 0.05f, sdft_v3(0.048f, 0.04f, 0.11f));
    return sdft_minf(sdft_op_smooth_union(arm, hand, 0.03f), sdft_op_smooth_union(leg, foot, 0.04f));
}

static float pedestal(sdft_vec3 p) { return sdft_sd_cylinder(sdft_translate(p, sdft_v3(0, -0.04f, 0)), 1.1f, 0.04f); }

static float figure_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    (void)ctx, (void)s;
    float character = sdft_op_smooth_union(body(p), limbs(sdft_mirror_x(p)), 0.06f);
    return sdft_minf(character, pedestal(p));
}

const sdft_scene scene_figure = {
    .name = "figure",
    .description = "a smoothly blended standing character on a round pedestal (the papers' Girl)",
    .field = {.distance = figure_distance,
              .bounds = {{-1.11f, -0.09f, -1.11f}, {1.11f, 1.8f, 1.11f}},
              .feature_size = 2e-4f},
    .camera = {.from = {0.8f, 1.45f, 2.5f}, .at = {0.0f, 0.92f, 0.0f}, .up = {0, 1, 0}, .fov_deg = 40.0f},
    .light = {2.0f, 4.0f, 3.0f},
};
