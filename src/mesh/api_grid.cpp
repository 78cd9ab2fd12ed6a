// sdftrace — a mesh converted to a grid (sdft_mesh_to_grid, grid/build.h), and
// the grid copied out densely or handed to the tracer as NanoVDB
// (sdft_mesh_grid_*). Writing it is api_files.cpp's.
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

// The ranges of the params (mesh2sdf's option table checks the same).
sdft_error checkGridParams(const sdft_mesh_grid_params &p, char *msg, size_t msg_len)
{
    const char *what = "sdft_mesh_to_grid";
    if (p.voxel_size <= 0 && (p.res < 1 || p.res > meshsdf::kMaxResolution))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: res %d is outside 1..%d", what, p.res,
                         meshsdf::kMaxResolution);
    if (!(p.voxel_size >= 0 && std::isfinite(p.voxel_size)))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: voxel size %g is not finite and >= 0", what, p.voxel_size);
    if (!(p.band > 0 && p.band <= meshsdf::kMaxResolution))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: band %g is outside (0, %d]", what, p.band,
                         meshsdf::kMaxResolution);
    if (!(p.padding <= meshsdf::kMaxResolution) || std::isnan(p.padding))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: padding %g is above %d", what, p.padding,
                         meshsdf::kMaxResolution);
    if (p.threads < 0)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: threads %d is negative", what, p.threads);
    const int sign = enumValue(p.sign);
    if (sign != SDFT_SIGN_WINDING && sign != SDFT_SIGN_FLOOD && sign != SDFT_SIGN_NONE)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: unknown sign method %d", what, sign);
    meshsdf::WindingAccuracy accuracy;
    if (!windingAccuracy(p.accuracy, accuracy))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: unknown winding accuracy %d", what, enumValue(p.accuracy));
    return SDFT_OK;
}

meshsdf::GridSettings gridSettings(const sdft_mesh &m, const sdft_mesh_grid_params &p)
{
    meshsdf::GridSettings opt;
    opt.source = m.source;
    opt.res = p.res;
    opt.voxelSize = p.voxel_size;
    opt.band = p.band;
    opt.full = p.full != 0;
    opt.padding = p.padding < 0 ? p.band + 1.0 : p.padding;
    opt.sign = p.sign == SDFT_SIGN_FLOOD  ? meshsdf::SignMethod::Flood
               : p.sign == SDFT_SIGN_NONE ? meshsdf::SignMethod::None
                                          : meshsdf::SignMethod::Winding;
    windingAccuracy(p.accuracy, opt.accuracy);
    opt.simd = m.simd;
    opt.simd512 = m.simd512;
    opt.writesNvdb = (p.writes & SDFT_WRITES_NVDB) != 0;
    opt.writesNpy = (p.writes & SDFT_WRITES_NPY) != 0;
    return opt;
}

// Whether some active voxel is inside, by more than rounding (a voxel on a
// face may come out -1e-17): a grid without one has no zero crossing to trace.
bool hasSurface(const openvdb::FloatGrid &grid)
{
    return grid.activeVoxelCount() > 0 &&
           openvdb::tools::minMax(grid.tree()).min() < -0.01 * float(grid.voxelSize()[0]);
}

// The box of the conversion, and whether it fits: SDFT_EINVAL for a box
// the limits refuse, SDFT_ENOMEM for one this machine's memory does not hold.
sdft_error plan(const sdft_mesh &m, const meshsdf::GridSettings &opt, meshsdf::BoxGeometry &box, char *msg,
                size_t msg_len)
{
    std::string error;
    if (!meshsdf::planBox(m.mesh, opt, box, error))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s", error.c_str());
    if (!meshsdf::conversionFitsMemory(m.mesh, box, opt, error))
        return fail_with(msg, msg_len, SDFT_ENOMEM, "%s", error.c_str());
    return SDFT_OK;
}

// What a box tells before anything is built.
sdft_mesh_box boxOf(const meshsdf::BoxGeometry &geometry, double band)
{
    sdft_mesh_box b{};
    for (int k = 0; k < 3; ++k) {
        b.dims[k] = geometry.dims[k];
        b.origin[k] = geometry.origin[k];
    }
    b.voxel_size = geometry.voxelSize;
    b.background = float(band * geometry.voxelSize);
    return b;
}

} // namespace

extern "C" {

const char *sdft_mesh_sign_name(sdft_mesh_sign sign)
{
    switch (enumValue(sign)) {
    case SDFT_SIGN_WINDING:
        return meshsdf::signMethodName(meshsdf::SignMethod::Winding);
    case SDFT_SIGN_FLOOD:
        return meshsdf::signMethodName(meshsdf::SignMethod::Flood);
    case SDFT_SIGN_NONE:
        return meshsdf::signMethodName(meshsdf::SignMethod::None);
    }
    return "?";
}

sdft_mesh_grid_params sdft_mesh_grid_params_defaults(void)
{
    const meshsdf::GridSettings cli;
    sdft_mesh_grid_params p{};
    p.res = cli.res;
    p.voxel_size = cli.voxelSize;
    p.band = cli.band;
    p.full = cli.full;
    p.padding = -1;
    p.sign = SDFT_SIGN_WINDING;
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
    const sdft_error bad = checkGridParams(p, msg, msg_len);
    if (bad != SDFT_OK)
        return bad;
    return guarded("sdft_mesh_to_grid", msg, msg_len, [&] {
        const auto start = std::chrono::steady_clock::now();
        openvdb::initialize();
        const meshsdf::GridSettings opt = gridSettings(*m, p);
        std::unique_ptr<sdft_mesh_grid> g(new sdft_mesh_grid);
        g->threads = p.threads > 0 ? p.threads : m->threads;
        const sdft_error unplanned = plan(*m, opt, g->box, msg, msg_len);
        if (unplanned != SDFT_OK)
            return unplanned;
        Listened listened(p.progress, p.stage, p.progress_user);
        inArena(g->threads, [&] {
            g->grid = meshsdf::buildGrid(m->mesh, g->box, opt, listened.progress, g->stats);
            g->surface = hasSurface(*g->grid); // one pass over the tree
            g->activeVoxels = g->grid->activeVoxelCount();
            g->memoryBytes = g->grid->memUsage();
        });
        if (listened.progress.cancelled())
            throw meshsdf::Cancelled();
        listened.progress.done();
        g->how = meshsdf::Provenance{opt.source, meshsdf::signMethodName(opt.sign), opt.band, opt.full};
        meshsdf::describeGrid(*g->grid, p.name ? p.name : m->stem, g->how);
        g->seconds = secondsSince(start);
        *out = g.release();
        return SDFT_OK;
    });
}

sdft_error sdft_mesh_grid_plan(const sdft_mesh *m, const sdft_mesh_grid_params *params, sdft_mesh_box *box, char *msg,
                               size_t msg_len)
{
    if (!m || !box)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_grid_plan: %s is NULL", m ? "box" : "m");
    const sdft_mesh_grid_params p = params ? *params : sdft_mesh_grid_params_defaults();
    const sdft_error bad = checkGridParams(p, msg, msg_len);
    if (bad != SDFT_OK)
        return bad;
    return guarded("sdft_mesh_grid_plan", msg, msg_len, [&] {
        const meshsdf::GridSettings opt = gridSettings(*m, p);
        meshsdf::BoxGeometry geometry;
        const sdft_error unplanned = plan(*m, opt, geometry, msg, msg_len);
        if (unplanned == SDFT_OK)
            *box = boxOf(geometry, opt.band);
        return unplanned;
    });
}

void sdft_mesh_grid_free(sdft_mesh_grid *g) { delete g; }

sdft_error sdft_mesh_grid_get_box(const sdft_mesh_grid *g, sdft_mesh_box *box, char *msg, size_t msg_len)
{
    if (!g || !box)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_grid_get_box: %s is NULL", g ? "box" : "g");
    sdft_mesh_box b = boxOf(g->box, 0);
    b.background = g->grid->background();
    b.active_voxels = g->activeVoxels;
    b.ambiguous_voxels = g->stats.ambiguousVoxels;
    b.surface = g->surface;
    b.memory_bytes = g->memoryBytes;
    b.seconds = g->seconds;
    b.winding_seconds = g->stats.windingSeconds;
    *box = b;
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
        nanovdb::GridHandle<> handle =
            inArena(g->threads, [&] { return sdft_vdb::nano_handle(*g->grid, SDFT_QUANT_NONE); });
        sdft_grid_options o = sdft_grid_options_defaults();
        o.data = handle.data();
        o.size = handle.size();
        return sdft_grid_open(&o, out, msg, msg_len);
    });
}

} // extern "C"
