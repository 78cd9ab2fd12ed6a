/* sdftrace — the materials the scenes share: the renderer's grey, and a
 * checker floor (the primer's), whose squares make discontinuities and
 * refraction visible. */
#include <math.h>

#include "scenes.h"

sdft_material scene_grey(void)
{
    return (sdft_material){.colour = {0.80f, 0.76f, 0.70f}, .reflectance = 0.0f, .ior = 0.0f};
}

sdft_material scene_checker(sdft_vec3 p, float square)
{
    const int odd = ((int)floorf(p.x / square) + (int)floorf(p.z / square)) & 1;
    const float v = odd ? 0.25f : 0.85f;
    return (sdft_material){.colour = {v, v, v}, .reflectance = 0.0f, .ior = 0.0f};
}
