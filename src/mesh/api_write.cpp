// sdftrace — a converted grid written (grid/grid_files.h): the files of one
// grid reserved before the work and renamed into place together
// (GridFiles, api.h, over src/common/atomic_file.h's sets), and one file
// whole or not at all (sdft_mesh_grid_write).
#include "api.h"

#include <tbb/parallel_for.h>

#include <cstring>
#include <vector>

using namespace meshsdf::api;

namespace meshsdf::api
{

sdft_error GridFiles::reserve(const std::vector<File> &files, char *msg, size_t msg_len)
{
    discard();
    mFiles = files;
    mFirst.clear();
    std::vector<std::string> paths;
    for (const File &f : files) {
        mFirst.push_back(paths.size());
        paths.push_back(f.path);
        if (f.format == SDFT_MESH_FORMAT_NPY)
            paths.push_back(meshsdf::sidecarPath(f.path));
    }
    std::vector<const char *> names;
    for (const std::string &p : paths)
        names.push_back(p.c_str());
    mTargets.assign(paths.size(), atomic_file{});
    const sdft_error e = atomic_files_begin(mTargets.data(), names.data(), names.size(), msg, msg_len);
    mOpen = e == SDFT_OK;
    return e;
}

void GridFiles::discard()
{
    if (mOpen)
        atomic_files_abort(mTargets.data(), mTargets.size());
    mOpen = false;
}

namespace
{

// File f written from g into its temporary file (an .npy's sidecar into
// the next).
bool writeFile(const GridFiles::File &f, const atomic_file *to, const sdft_mesh_grid &g, bool fp16, std::string &error)
{
    switch (f.format) {
    case SDFT_MESH_FORMAT_VDB:
        return meshsdf::writeVdb(*g.grid, to[0].tmp_path, error);
    case SDFT_MESH_FORMAT_NVDB:
        return meshsdf::writeNvdb(*g.grid, fp16, to[0].tmp_path, error);
    case SDFT_MESH_FORMAT_NPY: {
        const size_t slash = f.path.find_last_of('/');
        const std::string name = slash == std::string::npos ? f.path : f.path.substr(slash + 1);
        return meshsdf::writeNpy(*g.grid, g.box, to[0].tmp_path, error) &&
               meshsdf::writeNpyJson(g.box, name, g.how, g.grid->background(), to[1].tmp_path, error);
    }
    }
    error = "unknown format";
    return false;
}

} // namespace

sdft_error GridFiles::write(const sdft_mesh_grid &g, bool fp16, char *msg, size_t msg_len)
{
    for (const File &f : mFiles)
        if (f.format == SDFT_MESH_FORMAT_NPY && g.box.voxelCount() > meshsdf::kMaxDenseVoxels) {
            discard();
            return fail_with(msg, msg_len, SDFT_EINVAL, "%s: a dense array of %.0f voxels is above the limit of 2^31",
                             f.path.c_str(), g.box.voxelCount());
        }
    // The NanoVDB files first, one at a time (the converter rewrites the
    // tree while it runs: api.h's treeLock); then every other file side by
    // side, each only reading the tree (and OpenVDB's writer runs on one
    // thread); then all flushed and renamed into place.
    const size_t n = mFiles.size();
    std::vector<std::string> errors(n);
    std::vector<char> ok(n, 0);
    inArena(g.threads, [&] {
        std::unique_lock<std::shared_mutex> alone(g.treeLock);
        for (size_t i = 0; i < n; ++i)
            if (mFiles[i].format == SDFT_MESH_FORMAT_NVDB)
                ok[i] = writeFile(mFiles[i], &mTargets[mFirst[i]], g, fp16, errors[i]);
        alone.unlock();
        std::shared_lock<std::shared_mutex> reading(g.treeLock);
        tbb::parallel_for(size_t(0), n, [&](size_t i) {
            if (mFiles[i].format != SDFT_MESH_FORMAT_NVDB)
                ok[i] = writeFile(mFiles[i], &mTargets[mFirst[i]], g, fp16, errors[i]);
        });
    });
    for (size_t i = 0; i < n; ++i)
        if (!ok[i]) {
            discard();
            return fail_with(msg, msg_len, SDFT_EIO, "%s", errors[i].c_str());
        }
    mOpen = false; // committed or removed, either way
    return atomic_files_commit(mTargets.data(), mTargets.size(), msg, msg_len);
}

} // namespace meshsdf::api

extern "C" sdft_error sdft_mesh_grid_write(const sdft_mesh_grid *g, const char *path, sdft_mesh_format format, int fp16,
                                           char *msg, size_t msg_len)
{
    const char *what = "sdft_mesh_grid_write";
    if (!g || !path)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %s is NULL", what, g ? "path" : "g");
    const int f = enumValue(format);
    if (f != SDFT_MESH_FORMAT_VDB && f != SDFT_MESH_FORMAT_NVDB && f != SDFT_MESH_FORMAT_NPY)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %s: unknown format %d", what, path, f);
    return guarded(what, msg, msg_len, [&] {
        GridFiles files;
        const sdft_error e = files.reserve({{path, format}}, msg, msg_len);
        return e != SDFT_OK ? e : files.write(*g, fp16 != 0, msg, msg_len);
    });
}
