// sdftrace — a mesh converted to a grid (sdft_mesh_to_grid) as mesh2sdf
// converts it (grid.h), and the grid written (output.h), copied out
// densely, or handed to the tracer as NanoVDB (sdft_mesh_grid_*).
#include "mesh_internal.h"

#include "grid_file.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace sdft_mesh_api;

namespace
{

bool endsWith(const std::string &s, const char *tail)
{
    const size_t n = std::strlen(tail);
    return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

// mesh2sdf's ranges for its options (options.cpp).
sdft_error checkGridParams(const sdft_mesh_grid_params &p, char *msg, size_t msg_len)
{
    const char *what = "sdft_mesh_to_grid";
    if (p.voxel_size <= 0 && (p.res < 1 || p.res > mesh2sdf::kMaxResolution))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: res %d is outside 1..%d", what, p.res,
                         mesh2sdf::kMaxResolution);
    if (!(p.voxel_size >= 0 && std::isfinite(p.voxel_size)))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: voxel size %g is not finite and >= 0", what, p.voxel_size);
    if (!(p.band > 0 && p.band <= mesh2sdf::kMaxResolution))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: band %g is outside (0, %d]", what, p.band,
                         mesh2sdf::kMaxResolution);
    if (!(p.padding <= mesh2sdf::kMaxResolution) || std::isnan(p.padding))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: padding %g is above %d", what, p.padding,
                         mesh2sdf::kMaxResolution);
    if (p.threads < 0)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: threads %d is negative", what, p.threads);
    if (p.sign != SDFT_SIGN_WINDING && p.sign != SDFT_SIGN_FLOOD && p.sign != SDFT_SIGN_NONE)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: unknown sign method %d", what, int(p.sign));
    return SDFT_OK;
}

mesh2sdf::Options gridOptions(const sdft_mesh &m, const sdft_mesh_grid_params &p)
{
    mesh2sdf::Options opt;
    opt.input = m.source;
    opt.res = p.res;
    opt.voxelSize = p.voxel_size;
    opt.band = p.band;
    opt.full = p.full != 0;
    opt.padding = p.padding < 0 ? p.band + 1.0 : p.padding;
    opt.sign = p.sign == SDFT_SIGN_FLOOD  ? mesh2sdf::SignMethod::Flood
               : p.sign == SDFT_SIGN_NONE ? mesh2sdf::SignMethod::None
                                          : mesh2sdf::SignMethod::Winding;
    opt.name = p.name ? p.name : m.stem;
    return opt;
}

// Writes one file through its temporary name: write(tmp, error).
template <class Write> sdft_error writeAtomically(const std::string &path, Write &&write, char *msg, size_t msg_len)
{
    mesh2sdf::PendingFile file;
    std::string error;
    if (!mesh2sdf::reserveFile(path, file, error))
        return fail_with(msg, msg_len, SDFT_EIO, "%s", error.c_str());
    if (!write(file.tmp, error) || !mesh2sdf::commitFile(file, error)) {
        mesh2sdf::discardFile(file);
        return fail_with(msg, msg_len, SDFT_EIO, "%s", error.c_str());
    }
    return SDFT_OK;
}

// The .npy and its sidecar, both renamed into place or neither.
sdft_error writeNpyPair(const sdft_mesh_grid &g, const std::string &path, char *msg, size_t msg_len)
{
    if (g.box.voxelCount() > mesh2sdf::kMaxDenseVoxels)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: a dense array of %.0f voxels is above the limit of 2^31",
                         path.c_str(), g.box.voxelCount());
    mesh2sdf::PendingFile npy, json;
    std::string error;
    const size_t slash = path.find_last_of('/');
    const std::string npyName = slash == std::string::npos ? path : path.substr(slash + 1);
    bool ok = mesh2sdf::reserveFile(path, npy, error) &&
              mesh2sdf::reserveFile(mesh2sdf::sidecarPath(path), json, error) &&
              mesh2sdf::writeNpy(*g.grid, g.box, npy.tmp, error) &&
              mesh2sdf::writeNpyJson(g.box, npyName, g.how, g.grid->background(), json.tmp, error) &&
              mesh2sdf::commitFile(npy, error) && mesh2sdf::commitFile(json, error);
    if (!ok) {
        mesh2sdf::discardFile(npy);
        mesh2sdf::discardFile(json);
        return fail_with(msg, msg_len, SDFT_EIO, "%s", error.c_str());
    }
    return SDFT_OK;
}

} // namespace

extern "C" {

sdft_mesh_grid_params sdft_mesh_grid_params_defaults(void)
{
    const mesh2sdf::Options cli;
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
        openvdb::initialize();
        const mesh2sdf::Options opt = gridOptions(*m, p);
        std::unique_ptr<sdft_mesh_grid> g(new sdft_mesh_grid);
        std::string error;
        if (!mesh2sdf::planBox(m->mesh, opt, g->box, error))
            return fail_with(msg, msg_len, SDFT_EINVAL, "%s", error.c_str());
        Listened listened(p.progress, p.progress_user);
        // The caller's share of the cores: an arena of its own, or TBB's default one.
        tbb::task_arena arena(p.threads > 0 ? p.threads : tbb::task_arena::automatic);
        arena.execute([&] { g->grid = mesh2sdf::buildGrid(m->mesh, g->box, opt, listened.progress, g->stats); });
        if (listened.progress.cancelled())
            throw mesh2sdf::Cancelled();
        listened.progress.stage("done", 100, 100);
        g->how = mesh2sdf::Provenance{opt.input, mesh2sdf::signMethodName(opt.sign), opt.band, opt.full};
        mesh2sdf::describeGrid(*g->grid, opt.name, g->how);
        *out = g.release();
        return SDFT_OK;
    });
}

void sdft_mesh_grid_free(sdft_mesh_grid *g) { delete g; }

sdft_error sdft_mesh_grid_get_box(const sdft_mesh_grid *g, sdft_mesh_box *box, char *msg, size_t msg_len)
{
    if (!g || !box)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_grid_get_box: %s is NULL", g ? "box" : "g");
    sdft_mesh_box b{};
    for (int k = 0; k < 3; ++k) {
        b.dims[k] = g->box.dims[k];
        b.origin[k] = g->box.origin[k];
    }
    b.voxel_size = g->box.voxelSize;
    b.background = g->grid->background();
    b.active_voxels = g->grid->activeVoxelCount();
    b.ambiguous_voxels = g->stats.ambiguousVoxels;
    *box = b;
    return SDFT_OK;
}

sdft_error sdft_mesh_grid_write(const sdft_mesh_grid *g, const char *path, int fp16, char *msg, size_t msg_len)
{
    if (!g || !path)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_grid_write: %s is NULL", g ? "path" : "g");
    const std::string to = path;
    return guarded(path, msg, msg_len, [&] {
        if (endsWith(to, ".vdb"))
            return writeAtomically(
                to, [&](const std::string &tmp, std::string &e) { return mesh2sdf::writeVdb(*g->grid, tmp, e); }, msg,
                msg_len);
        if (endsWith(to, ".nvdb"))
            return writeAtomically(
                to, [&](const std::string &tmp, std::string &e) { return mesh2sdf::writeNvdb(*g->grid, fp16, tmp, e); },
                msg, msg_len);
        if (endsWith(to, ".npy"))
            return writeNpyPair(*g, to, msg, msg_len);
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: unknown extension (use .vdb, .nvdb or .npy)", path);
    });
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
        nanovdb::GridHandle<> handle = sdft_vdb::nano_handle(*g->grid, SDFT_QUANT_NONE);
        sdft_grid_options o = sdft_grid_options_defaults();
        o.data = handle.data();
        o.size = handle.size();
        return sdft_grid_open(&o, out, msg, msg_len);
    });
}

} // extern "C"
