// sdftrace — a converted grid written (grid/grid_files.h): the files of one
// grid reserved before the work and renamed into place together
// (GridFiles, api.h), and one file whole or not at all
// (sdft_mesh_grid_write).
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
    mEntries.clear();
    std::string error;
    for (const File &f : files) {
        mEntries.push_back(Entry{f, {}, {}});
        Entry &e = mEntries.back();
        if (!meshsdf::reserveFile(f.path, e.data, error) ||
            (f.format == SDFT_MESH_FORMAT_NPY &&
             !meshsdf::reserveFile(meshsdf::sidecarPath(f.path), e.sidecar, error))) {
            discard();
            mEntries.clear();
            return fail_with(msg, msg_len, SDFT_EIO, "%s", error.c_str());
        }
    }
    return SDFT_OK;
}

void GridFiles::discard()
{
    for (Entry &e : mEntries) {
        meshsdf::discardFile(e.data);
        meshsdf::discardFile(e.sidecar);
    }
}

namespace
{

// Entry e's file(s) written from g into its temporary file(s).
bool writeEntry(const meshsdf::api::GridFiles::File &f, const meshsdf::PendingFile &data,
                const meshsdf::PendingFile &sidecar, const sdft_mesh_grid &g, bool fp16, std::string &error)
{
    switch (f.format) {
    case SDFT_MESH_FORMAT_VDB:
        return meshsdf::writeVdb(*g.grid, data.tmp, error);
    case SDFT_MESH_FORMAT_NVDB:
        return meshsdf::writeNvdb(*g.grid, fp16, data.tmp, error);
    case SDFT_MESH_FORMAT_NPY: {
        const size_t slash = f.path.find_last_of('/');
        const std::string name = slash == std::string::npos ? f.path : f.path.substr(slash + 1);
        return meshsdf::writeNpy(*g.grid, g.box, data.tmp, error) &&
               meshsdf::writeNpyJson(g.box, name, g.how, g.grid->background(), sidecar.tmp, error);
    }
    }
    error = "unknown format";
    return false;
}

} // namespace

sdft_error GridFiles::write(const sdft_mesh_grid &g, bool fp16, char *msg, size_t msg_len)
{
    for (const Entry &e : mEntries)
        if (e.file.format == SDFT_MESH_FORMAT_NPY && g.box.voxelCount() > meshsdf::kMaxDenseVoxels) {
            discard();
            return fail_with(msg, msg_len, SDFT_EINVAL, "%s: a dense array of %.0f voxels is above the limit of 2^31",
                             e.file.path.c_str(), g.box.voxelCount());
        }
    // Every file side by side (each reads the finished tree only, and
    // OpenVDB's writer runs on one thread), then renamed into place side by
    // side too (replacing a large old file frees its blocks within
    // rename()).
    const size_t n = mEntries.size();
    std::vector<std::string> errors(n);
    std::vector<char> ok(n, 0);
    inArena(g.threads, [&] {
        tbb::parallel_for(size_t(0), n, [&](size_t i) {
            const Entry &e = mEntries[i];
            ok[i] = writeEntry(e.file, e.data, e.sidecar, g, fp16, errors[i]);
        });
    });
    for (size_t i = 0; i < n; ++i)
        if (!ok[i]) {
            discard();
            return fail_with(msg, msg_len, SDFT_EIO, "%s", errors[i].c_str());
        }
    std::vector<meshsdf::PendingFile *> pending;
    for (Entry &e : mEntries) {
        pending.push_back(&e.data);
        if (e.file.format == SDFT_MESH_FORMAT_NPY)
            pending.push_back(&e.sidecar);
    }
    errors.assign(pending.size(), std::string());
    ok.assign(pending.size(), 0);
    inArena(g.threads, [&] {
        tbb::parallel_for(size_t(0), pending.size(),
                          [&](size_t i) { ok[i] = meshsdf::commitFile(*pending[i], errors[i]); });
    });
    discard(); // whatever was not renamed into place
    for (size_t i = 0; i < pending.size(); ++i)
        if (!ok[i])
            return fail_with(msg, msg_len, SDFT_EIO, "%s", errors[i].c_str());
    return SDFT_OK;
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
