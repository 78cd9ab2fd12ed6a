/* sdftrace — a ray against an axis-aligned box: the slab test that clips
 * every ray to its field's bounds. Portable (portable.h). */
#ifndef SDFTRACE_RAY_BOX_H
#define SDFTRACE_RAY_BOX_H

#include "portable.h"

/* The ray clipped to the box (sdft_aabb_clip): 1 and [t0, t1] (clamped to
 * [tnear, tfar]) where it overlaps, else 0 with t0 and t1 untouched. */
PORT_INLINE int ray_box_clip(sdft_aabb box, sdft_vec3 org, sdft_vec3 dir, float tnear, float tfar, PORT_INOUT(float) t0,
                             PORT_INOUT(float) t1)
{
    const float o[3] = {org.x, org.y, org.z}, d[3] = {dir.x, dir.y, dir.z};
    const float lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
    float a = tnear, b = tfar;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0.0f) {
            if (o[k] < lo[k] || o[k] > hi[k])
                return 0;
            continue;
        }
        float inv = 1.0f / d[k];
        float ta = (lo[k] - o[k]) * inv, tb = (hi[k] - o[k]) * inv;
        if (ta > tb) {
            float tmp = ta;
            ta = tb;
            tb = tmp;
        }
        /* NaN (0 * inf at a slab's plane) leaves a and b as they are. */
        a = ta > a ? ta : a;
        b = tb < b ? tb : b;
    }
    if (a > b)
        return 0;
    PORT_DEREF(t0) = a;
    PORT_DEREF(t1) = b;
    return 1;
}

#endif
