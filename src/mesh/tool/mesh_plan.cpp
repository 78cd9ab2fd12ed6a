// sdftrace — a conversion planned, and a draw of samples counted, before
// the work (mesh_grid_plan, mesh_sample_counts: mesh_tool.h): the
// library's own plan and counts.
#include "tool/mesh_tool.h"

#include "api.h"
#include "samples/samples.h"

#include <algorithm>

using namespace meshsdf::api;

extern "C" {

sdft_error mesh_grid_plan(const sdft_mesh *m, const sdft_mesh_grid_params *params, sdft_mesh_grid_box *box, char *msg,
                          size_t msg_len)
{
    if (!m || !box)
        return fail_with(msg, msg_len, SDFT_EINVAL, "mesh_grid_plan: %s is NULL", m ? "box" : "m");
    const sdft_mesh_grid_params p = params ? *params : sdft_mesh_grid_params_defaults();
    return guarded("mesh_grid_plan", msg, msg_len, [&] {
        meshsdf::BoxGeometry geometry;
        const sdft_error e = planGrid("mesh_grid_plan", *m, p, geometry, msg, msg_len);
        if (e == SDFT_OK)
            *box = boxOf(geometry, p.band);
        return e;
    });
}

void mesh_sample_counts(const sdft_mesh_sample_params *p, size_t *near_first, size_t *near_second, size_t *uniform)
{
    const meshsdf::SampleCounts c =
        p ? meshsdf::sampleCounts(size_t(p->count), p->uniform_share > 0 ? std::min(p->uniform_share, 1.0) : 0.0)
          : meshsdf::SampleCounts{}; // a share outside [0, 1] clamped, NaN as 0
    if (near_first)
        *near_first = c.near[0];
    if (near_second)
        *near_second = c.near[1];
    if (uniform)
        *uniform = c.uniform;
}

} // extern "C"
