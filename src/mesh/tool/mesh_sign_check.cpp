// sdftrace — grids' signs checked against a mesh's exact winding number
// (mesh_sign_check, mesh_tool.h; the work is sign_check.h's).
#include "tool/mesh_tool.h"

#include "api.h"
#include "samples/samples.h"
#include "tool/sign_check.h"

#include <cerrno>
#include <cstring>
#include <unistd.h>

using namespace meshsdf::api;

extern "C" {

sdft_error mesh_sign_check(const sdft_mesh *m, const char *const *grid_paths, size_t count, size_t points,
                           mesh_sign_counts *out, char *msg, size_t msg_len)
{
    const char *what = "mesh_sign_check";
    if (!m || !grid_paths || !out)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %s is NULL", what,
                         !m            ? "m"
                         : !grid_paths ? "grid_paths"
                                       : "out");
    if (count == 0)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: no grids", what);
    if (points < 1 || double(points) > meshsdf::kMaxSamples)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %zu points is outside 1..%.0f", what, points,
                         meshsdf::kMaxSamples);
    for (size_t i = 0; i < count; ++i) {
        if (!grid_paths[i])
            return fail_with(msg, msg_len, SDFT_EINVAL, "%s: grid path %zu is NULL", what, i);
        if (access(grid_paths[i], R_OK) != 0)
            return fail_with(msg, msg_len, SDFT_EIO, "cannot read grid %s: %s", grid_paths[i], std::strerror(errno));
    }
    return guarded(what, msg, msg_len, [&] {
        std::string error;
        if (!meshsdf::checkPointsFitMemory(int(points), error))
            return fail_with(msg, msg_len, SDFT_ENOMEM, "%s", error.c_str());
        const std::vector<std::string> paths(grid_paths, grid_paths + count);
        openvdb::initialize();
        std::vector<meshsdf::SignCheck> checks;
        const bool ok =
            inArena(m->threads, [&] { return meshsdf::checkSign(m->mesh, paths, int(points), checks, error); });
        if (!ok)
            return fail_with(msg, msg_len, SDFT_EFORMAT, "%s", error.c_str());
        for (size_t i = 0; i < count; ++i)
            out[i] = mesh_sign_counts{checks[i].clear, checks[i].wrong, checks[i].wrongFar};
        return SDFT_OK;
    });
}

} // extern "C"
