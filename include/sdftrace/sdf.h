/* sdftrace — the SDF toolkit: primitives, operators and point transforms,
 * each a pure function of a point, composed into scenes like a sentence.
 *
 * Conventions. Every primitive is centred on the origin in its own frame;
 * move it by transforming the point (sdft_translate, sdft_rotate, ...), never
 * the shape. Lengths are world units, angles radians. "Exact" means the true
 * Euclidean signed distance (negative inside); "bound" means a 1-Lipschitz
 * function with the right sign whose magnitude never exceeds the true
 * distance, which is all a sphere tracer needs and what sdft_field promises.
 * min/max of bounds are bounds; a 1-Lipschitz function with the right sign
 * everywhere is a bound. Non-uniform scaling breaks both: there is none here. */
#ifndef SDFTRACE_SDF_H
#define SDFTRACE_SDF_H

#include "sdftrace/config.h"
#include "vec3.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- primitives ------------------------------------------------------- */

/* Sphere of radius r. Exact. */
static inline float sdft_sd_sphere(sdft_vec3 p, float r) { return sdft_length(p) - r; }

/* Axis-aligned box with half-extents `half`. Exact. */
static inline float sdft_sd_box(sdft_vec3 p, sdft_vec3 half)
{
    sdft_vec3 q = sdft_sub(sdft_abs3(p), half);
    return sdft_length(sdft_max3(q, 0.0f)) + sdft_minf(sdft_maxcomp(q), 0.0f);
}

/* Box with outer half-extents `half` whose edges are rounded with `radius`
 * (0 <= radius <= smallest half-extent). Exact. */
static inline float sdft_sd_round_box(sdft_vec3 p, sdft_vec3 half, float radius)
{
    return sdft_sd_box(p, sdft_sub(half, sdft_v3(radius, radius, radius))) - radius;
}

/* Torus in the xz plane: ring radius R, tube radius r. Exact. */
static inline float sdft_sd_torus(sdft_vec3 p, float R, float r)
{
    float ring = sqrtf(p.x * p.x + p.z * p.z) - R;
    return sqrtf(ring * ring + p.y * p.y) - r;
}

/* Half-space dot(p, n) + d <= 0, n unit: the plane at signed offset -d along
 * n. Exact. Scenes should intersect it with a box (finite bounds). */
static inline float sdft_sd_plane(sdft_vec3 p, sdft_vec3 n, float d) { return sdft_dot(p, n) + d; }

/* Capped cylinder about the y axis: radius r, half-height h. Exact. */
static inline float sdft_sd_cylinder(sdft_vec3 p, float r, float h)
{
    float dr = sqrtf(p.x * p.x + p.z * p.z) - r, dy = fabsf(p.y) - h;
    float ox = sdft_maxf(dr, 0.0f), oy = sdft_maxf(dy, 0.0f);
    return sqrtf(ox * ox + oy * oy) + sdft_minf(sdft_maxf(dr, dy), 0.0f);
}

/* Capsule: the points within r of segment ab. Exact. */
static inline float sdft_sd_capsule(sdft_vec3 p, sdft_vec3 a, sdft_vec3 b, float r)
{
    sdft_vec3 ab = sdft_sub(b, a), ap = sdft_sub(p, a);
    float t = sdft_minf(sdft_maxf(sdft_dot(ap, ab) / sdft_dot(ab, ab), 0.0f), 1.0f);
    return sdft_length(sdft_sub(ap, sdft_scale(ab, t))) - r;
}

/* Ellipsoid with semi-axes `radii` along x, y, z. A bound, not exact:
 * (|p / radii| - 1) * min(radii) is 1-Lipschitz (its gradient is at most
 * min(radii) / min(radii)) and zero exactly on the ellipsoid. */
static inline float sdft_sd_ellipsoid(sdft_vec3 p, sdft_vec3 radii)
{
    sdft_vec3 q = sdft_v3(p.x / radii.x, p.y / radii.y, p.z / radii.z);
    return (sdft_length(q) - 1.0f) * sdft_minf(radii.x, sdft_minf(radii.y, radii.z));
}

/* Regular dodecahedron with inradius r (centre to face), faces normal to
 * (0, +-1, +-phi) and its cyclic permutations. Akleman–Chen's generalized
 * distance in its max form: max_i |p . n_i| - r over the six face-normal
 * directions. Exact inside and along face normals; outside near edges and
 * vertices it underestimates: a bound (a max of 1-Lipschitz plane distances,
 * each at most the distance to the convex polytope). */
static inline float sdft_sd_dodecahedron(sdft_vec3 p, float r)
{
    const float phi = 1.6180340f, inv_len = 0.5257311f; /* golden ratio, 1 / sqrt(1 + phi^2) */
    sdft_vec3 a = sdft_abs3(p);                         /* |p . n| maximised over the sign choices of each normal */
    return sdft_maxf(a.y + phi * a.z, sdft_maxf(a.z + phi * a.x, a.x + phi * a.y)) * inv_len - r;
}

/* ---- combining distances ---------------------------------------------- */

/* Union of two shapes. Exact outside when both are; a bound inside. */
static inline float sdft_op_union(float a, float b) { return sdft_minf(a, b); }

/* Shape b with shape a carved out of it. A bound. */
static inline float sdft_op_subtract(float a, float b) { return sdft_maxf(-a, b); }

/* Overlap of two shapes. A bound. */
static inline float sdft_op_intersect(float a, float b) { return sdft_maxf(a, b); }

/* Union blended over a fillet of width k > 0 (polynomial smooth minimum).
 * Never above min(a, b), at most k/4 below; its gradient is h*grad(a) +
 * (1-h)*grad(b) with h in [0, 1], so bounds stay bounds. */
static inline float sdft_op_smooth_union(float a, float b, float k)
{
    float h = sdft_minf(sdft_maxf(0.5f + 0.5f * (b - a) / k, 0.0f), 1.0f);
    return b + h * (a - b) - k * h * (1.0f - h);
}

/* Bounding-volume early-out, continuous form. With `bound` a bound to a
 * volume enclosing the detail, use `bound >= k ? bound : sdft_op_near_bound(
 * bound, detail, k)`: far away the volume's own bound (the detail is no
 * nearer), near and inside it the detail, capped at 2k - bound. At bound == k
 * the cap is k <= detail, so both branches meet; the cap grows with the depth
 * inside the volume, so rays crossing it are not held to short steps. A
 * bound (never above the detail), 1-Lipschitz when both inputs are. */
static inline float sdft_op_near_bound(float bound, float detail, float k)
{
    return sdft_maxf(bound, sdft_minf(detail, 2.0f * k - bound));
}

/* ---- point transforms (apply to p, then call a primitive) ------------- */

/* Shape moved by `offset`. Exact (an isometry). */
static inline sdft_vec3 sdft_translate(sdft_vec3 p, sdft_vec3 offset) { return sdft_sub(p, offset); }

/* A rotation, row-major: world = m * local. */
typedef struct sdft_mat3 {
    float m[3][3];
} sdft_mat3;

/* Rotation by `angle` about the unit `axis` (right-handed). */
SDFT_API sdft_mat3 sdft_mat3_rotation(sdft_vec3 axis, float angle);

/* m * v: a local direction or point into world. */
static inline sdft_vec3 sdft_mat3_apply(const sdft_mat3 *r, sdft_vec3 v)
{
    return sdft_v3(r->m[0][0] * v.x + r->m[0][1] * v.y + r->m[0][2] * v.z,
                   r->m[1][0] * v.x + r->m[1][1] * v.y + r->m[1][2] * v.z,
                   r->m[2][0] * v.x + r->m[2][1] * v.y + r->m[2][2] * v.z);
}

/* Shape rotated by `r`: the point goes through the inverse, transpose(r) * p.
 * Exact (an isometry). */
static inline sdft_vec3 sdft_rotate(sdft_vec3 p, const sdft_mat3 *r)
{
    return sdft_v3(r->m[0][0] * p.x + r->m[1][0] * p.y + r->m[2][0] * p.z,
                   r->m[0][1] * p.x + r->m[1][1] * p.y + r->m[2][1] * p.z,
                   r->m[0][2] * p.x + r->m[1][2] * p.y + r->m[2][2] * p.z);
}

/* Shape rotated by `angle` about +y (x towards -z). Exact. */
static inline sdft_vec3 sdft_rotate_y(sdft_vec3 p, float angle)
{
    float c = cosf(angle), s = sinf(angle);
    return sdft_v3(c * p.x - s * p.z, p.y, s * p.x + c * p.z);
}

/* Uniform scale by s > 0, the f(p / s) * s pattern in two halves:
 * d = sdft_scaled_distance(sdft_sd_xxx(sdft_scaled_point(p, s), ...), s).
 * Keeps exact exact and bounds bounds. (Non-uniform scale would not.) */
static inline sdft_vec3 sdft_scaled_point(sdft_vec3 p, float s) { return sdft_scale(p, 1.0f / s); }
static inline float sdft_scaled_distance(float d, float s) { return d * s; }

/* Mirror across the plane x = 0: |x|. The shape drawn for x >= 0 appears on
 * both sides. 1-Lipschitz; exact when the shape stays in x >= 0. */
static inline sdft_vec3 sdft_mirror_x(sdft_vec3 p) { return sdft_v3(fabsf(p.x), p.y, p.z); }
static inline sdft_vec3 sdft_mirror_z(sdft_vec3 p) { return sdft_v3(p.x, p.y, fabsf(p.z)); }

/* ---- domain repetition ------------------------------------------------ */

/* Coordinate x folded into the cell of width `period` centred on the
 * nearest multiple of it; period <= 0 leaves x alone. */
static inline float sdft_repeat1(float x, float period) { return period > 0.0f ? x - period * roundf(x / period) : x; }

/* Infinite repetition with cells of size `period` (per axis; <= 0: none),
 * centred on multiples of it. Exact when the shape lies inside its cell and
 * is mirror-symmetric about the cell's mid-planes; otherwise use sdft_cell_locate. */
static inline sdft_vec3 sdft_op_repeat(sdft_vec3 p, sdft_vec3 period)
{
    return sdft_v3(sdft_repeat1(p.x, period.x), sdft_repeat1(p.y, period.y), sdft_repeat1(p.z, period.z));
}

/* Limited repetition: copies at cells -count..count per axis (whole
 * numbers); points beyond the last cell see the last copy. Same exactness as
 * sdft_op_repeat. */
SDFT_API sdft_vec3 sdft_op_repeat_limited(sdft_vec3 p, sdft_vec3 period, sdft_vec3 count);

/* N copies around the y axis: the point turned into the sector centred on
 * +x (angle 0). Exact for shapes inside the sector and symmetric about z=0. */
SDFT_API sdft_vec3 sdft_op_repeat_angular_y(sdft_vec3 p, int n);

/* A point located in a (limited) repetition, for copies that differ per cell
 * (e.g. heights by hash). The cell-wall bound: if every cell's shape lies at
 * least `margin` inside its own cell, then min(d_own, wall + margin) is a
 * bound for the union of all cells (sdft_cell_bound). Any other copy is
 * reached only after leaving this cell (at least `wall`) and then entering
 * the other copy's cell and crossing its margin. At a shared wall both sides
 * give `margin` (d_own >= margin there), so it is also continuous. */
typedef struct sdft_cell {
    sdft_vec3 q;    /* p in the cell's frame, centred on the cell */
    int ix, iy, iz; /* cell index per axis, 0 on axes not repeated */
    float wall;     /* distance to the nearest wall shared with another cell; INFINITY if none */
} sdft_cell;

/* Locates p among cells -count..count (count < 0: unlimited) of size
 * `period` (<= 0: that axis is not repeated). */
SDFT_API sdft_cell sdft_cell_locate(sdft_vec3 p, sdft_vec3 period, sdft_vec3 count);

/* The cell-wall bound of a shape lying `margin` inside its cell. */
static inline float sdft_cell_bound(const sdft_cell *c, float d_own, float margin)
{
    return sdft_minf(d_own, c->wall + margin);
}

#ifdef __cplusplus
}
#endif
#endif
