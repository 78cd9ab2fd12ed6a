// sdftrace — a mesh converted to a grid (sdft_mesh_to_grid, grid/build.h),
// what it holds (sdft_mesh_grid_get_*), and the grid copied out densely or
// handed to the tracer as NanoVDB. Writing it is api_write.cpp's.
#include "api.h"

#include "grid/memory_estimate.h"
#include "grid_file.h"

#include <openvdb/tools/Count.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace meshsdf::api;

namespace
{

// Whether some active voxel is inside, by more than rounding (a voxel on a
// face may come out -1e-17): a grid without one has no zero crossing to trace.
bool hasSurface(const openvdb::FloatGrid &grid)
{
    return grid.activeVoxelCount() > 0 &&
           openvdb::tools::minMax(grid.tree()).min() < -0.01 * float(grid.voxelSize()[0]);
}

} // namespace

namespace meshsdf::api
{

sdft_error planGrid(const char *what, const sdft_mesh &m, const sdft_mesh_grid_params &p, meshsdf::BoxGeometry &box,
                    char *msg, size_t msg_len)
{
    const sdft_error bad = checkSettings(SDFT_MESH_SETTINGS_GRID, &p, what, msg, msg_len);
    if (bad != SDFT_OK)
        return bad;
    std::string error;
    if (!meshsdf::planBox(m.mesh, p, box, error))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s", error.c_str());
    if (!meshsdf::conversionFitsMemory(m.mesh, box, p, error))
        return fail_with(msg, msg_len, SDFT_ENOMEM, "%s", error.c_str());
    return SDFT_OK;
}

sdft_mesh_grid_box boxOf(const meshsdf::BoxGeometry &geometry, double band)
{
    sdft_mesh_grid_box b{};
    for (int k = 0; k < 3; ++k) {
        b.dims[k] = geometry.dims[k];
        b.origin[k] = geometry.origin[k];
    }
    b.voxel_size = geometry.voxelSize;
    b.background = float(band * geometry.voxelSize);
    return b;
}

} // namespace meshsdf::api

extern "C" {

sdft_mesh_grid_params sdft_mesh_grid_params_defaults(void)
{
    sdft_mesh_grid_params p{};
    fillDefaults(SDFT_MESH_SETTINGS_GRID, &p);
    return p;
}

sdft_error sdft_mesh_to_grid(const sdft_mesh *m, const sdft_mesh_grid_params *params, sdft_mesh_grid **out, char *msg,
                             size_t msg_len)
{
    if (out)
        *out = nullptr;
    if (!m || !out)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_to_grid: %s is NULL", m ? "out" : "m");
    const sdft_mesh_grid_params p = params ? *params : sdft_mesh_grid_params_defaults();
    return guarded("sdft_mesh_to_grid", msg, msg_len, [&] {
        const auto start = std::chrono::steady_clock::now();
        openvdb::initialize();
        std::unique_ptr<sdft_mesh_grid> g(new sdft_mesh_grid);
        g->threads = p.threads > 0 ? p.threads : m->threads;
        const sdft_error unplanned = planGrid("sdft_mesh_to_grid", *m, p, g->box, msg, msg_len);
        if (unplanned != SDFT_OK)
            return unplanned;
        Listened listened(p.progress, p.stage, p.progress_user);
        inArena(g->threads, [&] {
            g->grid = meshsdf::buildGrid(m->mesh, g->box, p, m->simd, m->accuracy, listened.progress, g->stats);
            g->surface = hasSurface(*g->grid); // one pass over the tree
            g->activeVoxels = g->grid->activeVoxelCount();
            g->memoryBytes = g->grid->memUsage();
        });
        if (listened.progress.cancelled())
            throw meshsdf::Cancelled();
        listened.progress.done();
        g->how =
            meshsdf::Provenance{m->source, choiceName(SDFT_MESH_SETTINGS_GRID, "sign", p.sign), p.band, p.full != 0};
        meshsdf::describeGrid(*g->grid, p.name ? p.name : m->stem, g->how);
        g->seconds = secondsSince(start);
        *out = g.release();
        return SDFT_OK;
    });
}

void sdft_mesh_grid_free(sdft_mesh_grid *g) { delete g; }

sdft_error sdft_mesh_grid_get_box(const sdft_mesh_grid *g, sdft_mesh_grid_box *box, char *msg, size_t msg_len)
{
    if (!g || !box)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_grid_get_box: %s is NULL", g ? "box" : "g");
    *box = boxOf(g->box, 0);
    box->background = g->grid->background();
    return SDFT_OK;
}

sdft_error sdft_mesh_grid_get_stats(const sdft_mesh_grid *g, sdft_mesh_grid_stats *stats, char *msg, size_t msg_len)
{
    if (!g || !stats)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_grid_get_stats: %s is NULL", g ? "stats" : "g");
    sdft_mesh_grid_stats s{};
    s.active_voxels = g->activeVoxels;
    s.ambiguous_voxels = g->stats.ambiguousVoxels;
    s.surface = g->surface;
    s.memory_bytes = g->memoryBytes;
    *stats = s;
    return SDFT_OK;
}

sdft_error sdft_mesh_grid_get_timings(const sdft_mesh_grid *g, sdft_mesh_grid_timings *t, char *msg, size_t msg_len)
{
    if (!g || !t)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_grid_get_timings: %s is NULL", g ? "t" : "g");
    *t = sdft_mesh_grid_timings{g->seconds, g->stats.windingSeconds, g->stats.indexSeconds};
    return SDFT_OK;
}

sdft_error sdft_mesh_grid_dense(const sdft_mesh_grid *g, float *values, size_t count, char *msg, size_t msg_len)
{
    if (!g || !values)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_grid_dense: %s is NULL", g ? "values" : "g");
    const auto &d = g->box.dims;
    const size_t nx = size_t(d[0]), ny = size_t(d[1]), nz = size_t(d[2]);
    if (count / ny / nz < nx)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_grid_dense: %zu values, the box has %zu x %zu x %zu",
                         count, nx, ny, nz);
    return guarded("sdft_mesh_grid_dense", msg, msg_len, [&] {
        std::shared_lock<std::shared_mutex> reading(g->treeLock); // no NanoVDB conversion meanwhile
        // Leaf-sized blocks in parallel, each copied from its leaf or
        // filled with the tile's value; voxel (0, 0, 0) of the box is the
        // grid's index origin and leaves are aligned to Leaf::DIM.
        using Leaf = openvdb::FloatTree::LeafNodeType;
        constexpr int n = int(Leaf::DIM);
        const openvdb::FloatTree &tree = g->grid->tree();
        const int bx = (d[0] + n - 1) / n, by = (d[1] + n - 1) / n, bz = (d[2] + n - 1) / n;
        inArena(g->threads, [&] {
            tbb::parallel_for(0, bx * by * bz, [&](int b) {
                const openvdb::Coord at(b / (by * bz) * n, b / bz % by * n, b % bz * n);
                const Leaf *leaf = tree.probeConstLeaf(at);
                const float tile = leaf ? 0.0f : tree.getValue(at);
                for (int i = 0; i < n && at[0] + i < d[0]; ++i)
                    for (int j = 0; j < n && at[1] + j < d[1]; ++j) {
                        const int zs = std::min(n, d[2] - at[2]);
                        float *row = values + (size_t(at[0] + i) * ny + size_t(at[1] + j)) * nz + size_t(at[2]);
                        if (leaf)
                            std::copy_n(leaf->buffer().data() + Leaf::coordToOffset(openvdb::Coord(i, j, 0)), zs, row);
                        else
                            std::fill_n(row, zs, tile);
                    }
            });
        });
        return SDFT_OK;
    });
}

sdft_error sdft_mesh_grid_nano(const sdft_mesh_grid *g, sdft_grid **out, char *msg, size_t msg_len)
{
    if (out)
        *out = nullptr;
    if (!g || !out)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_grid_nano: %s is NULL", g ? "out" : "g");
    return guarded("sdft_mesh_grid_nano", msg, msg_len, [&] {
        std::unique_lock<std::shared_mutex> alone(g->treeLock); // the converter rewrites the tree for a while
        nanovdb::GridHandle<> handle =
            inArena(g->threads, [&] { return sdft_vdb::nano_handle(*g->grid, SDFT_QUANT_NONE); });
        alone.unlock();
        sdft_grid_options o = sdft_grid_options_defaults();
        o.data = handle.data();
        o.size = handle.size();
        return sdft_grid_open(&o, out, msg, msg_len);
    });
}

} // extern "C"
