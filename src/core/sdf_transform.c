/* sdftrace — the SDF toolkit's helpers too long to inline: building a
 * rotation, limited and angular repetition, locating a point in its cell. */
#include <math.h>

#include "sdftrace/sdf.h"

sdft_mat3 sdft_mat3_rotation(sdft_vec3 axis, float angle)
{
    /* Rodrigues: R = cI + s[axis]x + (1 - c) axis axis^T. */
    float c = cosf(angle), s = sinf(angle), k = 1.0f - c;
    float x = axis.x, y = axis.y, z = axis.z;
    return (sdft_mat3){{{c + k * x * x, k * x * y - s * z, k * x * z + s * y},
                        {k * y * x + s * z, c + k * y * y, k * y * z - s * x},
                        {k * z * x - s * y, k * z * y + s * x, c + k * z * z}}};
}

/* One axis of a (limited) repetition: the cell index of x and its offset
 * from the cell centre; *wall receives the distance to the nearer wall that
 * has a cell behind it. count < 0: unlimited; period <= 0: not repeated. */
static float cell_axis(float x, float period, float count, int *index, float *wall)
{
    if (!(period > 0.0f)) {
        *index = 0, *wall = INFINITY;
        return x;
    }
    float c = roundf(x / period);
    if (count >= 0.0f)
        c = sdft_minf(sdft_maxf(c, -count), count);
    float q = x - period * c, half = 0.5f * period;
    int below = count < 0.0f || c > -count, above = count < 0.0f || c < count;
    *wall = sdft_minf(below ? q + half : INFINITY, above ? half - q : INFINITY);
    *index = (int)c;
    return q;
}

sdft_cell sdft_cell_locate(sdft_vec3 p, sdft_vec3 period, sdft_vec3 count)
{
    sdft_cell c;
    float wx, wy, wz;
    c.q.x = cell_axis(p.x, period.x, count.x, &c.ix, &wx);
    c.q.y = cell_axis(p.y, period.y, count.y, &c.iy, &wy);
    c.q.z = cell_axis(p.z, period.z, count.z, &c.iz, &wz);
    c.wall = sdft_minf(wx, sdft_minf(wy, wz));
    return c;
}

sdft_vec3 sdft_op_repeat_limited(sdft_vec3 p, sdft_vec3 period, sdft_vec3 count)
{
    return sdft_cell_locate(p, period, sdft_max3(count, 0.0f)).q;
}

sdft_vec3 sdft_op_repeat_angular_y(sdft_vec3 p, int n)
{
    const float sector = 6.2831853f / (float)n;
    float k = roundf(atan2f(p.z, p.x) / sector);
    return sdft_rotate_y(p, -k * sector); /* turns the point back by k sectors */
}
