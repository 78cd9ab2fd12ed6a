// sdftrace — a converted grid written (grid/grid_files.h): a set of files reserved
// before the work and renamed into place together (sdft_mesh_files_*), and
// one file by its extension (sdft_mesh_grid_write).
#include "api.h"

#include <tbb/parallel_for.h>

#include <cstdio>
#include <cstring>
#include <vector>

using namespace meshsdf::api;

struct sdft_mesh_files {
    struct Entry {
        std::string path;
        sdft_file_format format;
        meshsdf::PendingFile file, sidecar; // the sidecar: an .npy's JSON
    };
    std::vector<Entry> entries;
    bool spent = false;

    // Removes every temporary file still there.
    void discard()
    {
        for (Entry &e : entries) {
            meshsdf::discardFile(e.file);
            meshsdf::discardFile(e.sidecar);
        }
    }
    ~sdft_mesh_files() { discard(); }
};

namespace
{

bool endsWith(const char *s, const char *tail)
{
    const size_t n = std::strlen(s), t = std::strlen(tail);
    return n >= t && std::strcmp(s + n - t, tail) == 0;
}

// Entry e of a reserved set written from g into its temporary file(s).
bool writeEntry(const sdft_mesh_files::Entry &e, const sdft_mesh_grid &g, int fp16, std::string &error)
{
    switch (e.format) {
    case SDFT_FILE_VDB:
        return meshsdf::writeVdb(*g.grid, e.file.tmp, error);
    case SDFT_FILE_NVDB:
        return meshsdf::writeNvdb(*g.grid, fp16 != 0, e.file.tmp, error);
    case SDFT_FILE_NPY: {
        const size_t slash = e.path.find_last_of('/');
        const std::string name = slash == std::string::npos ? e.path : e.path.substr(slash + 1);
        return meshsdf::writeNpy(*g.grid, g.box, e.file.tmp, error) &&
               meshsdf::writeNpyJson(g.box, name, g.how, g.grid->background(), e.sidecar.tmp, error);
    }
    }
    error = "unknown format";
    return false;
}

// Every file of the set written side by side (each reads the finished tree
// only, and OpenVDB's writer runs on one thread), then renamed into place
// side by side too (replacing a large old file frees its blocks within
// rename()).
sdft_error writeAll(sdft_mesh_files &f, const sdft_mesh_grid &g, int fp16, char *msg, size_t msg_len)
{
    const size_t n = f.entries.size();
    std::vector<std::string> errors(n);
    std::vector<char> ok(n, 0);
    tbb::parallel_for(size_t(0), n, [&](size_t i) { ok[i] = writeEntry(f.entries[i], g, fp16, errors[i]); });
    for (size_t i = 0; i < n; ++i)
        if (!ok[i])
            return fail_with(msg, msg_len, SDFT_EIO, "%s", errors[i].c_str());
    std::vector<meshsdf::PendingFile *> pending;
    for (sdft_mesh_files::Entry &e : f.entries) {
        pending.push_back(&e.file);
        if (e.format == SDFT_FILE_NPY)
            pending.push_back(&e.sidecar);
    }
    errors.assign(pending.size(), std::string());
    ok.assign(pending.size(), 0);
    tbb::parallel_for(size_t(0), pending.size(),
                      [&](size_t i) { ok[i] = meshsdf::commitFile(*pending[i], errors[i]); });
    for (size_t i = 0; i < pending.size(); ++i)
        if (!ok[i])
            return fail_with(msg, msg_len, SDFT_EIO, "%s", errors[i].c_str());
    return SDFT_OK;
}

} // namespace

extern "C" {

sdft_error sdft_mesh_files_reserve(const sdft_mesh_file *files, size_t count, sdft_mesh_files **out, char *msg,
                                   size_t msg_len)
{
    const char *what = "sdft_mesh_files_reserve";
    if (out)
        *out = nullptr;
    if (!files || !out)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %s is NULL", what, files ? "out" : "files");
    if (count == 0)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: no files", what);
    for (size_t i = 0; i < count; ++i) {
        if (!files[i].path)
            return fail_with(msg, msg_len, SDFT_EINVAL, "%s: path %zu is NULL", what, i);
        const int format = enumValue(files[i].format);
        if (format != SDFT_FILE_VDB && format != SDFT_FILE_NVDB && format != SDFT_FILE_NPY)
            return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %s: unknown format %d", what, files[i].path, format);
    }
    return guarded(what, msg, msg_len, [&] {
        std::unique_ptr<sdft_mesh_files> set(new sdft_mesh_files);
        set->entries.resize(count);
        std::string error;
        for (size_t i = 0; i < count; ++i) {
            sdft_mesh_files::Entry &e = set->entries[i];
            e.path = files[i].path;
            e.format = files[i].format;
            if (!meshsdf::reserveFile(e.path, e.file, error) ||
                (e.format == SDFT_FILE_NPY && !meshsdf::reserveFile(meshsdf::sidecarPath(e.path), e.sidecar, error)))
                return fail_with(msg, msg_len, SDFT_EIO, "%s", error.c_str()); // the set's destructor cleans up
        }
        *out = set.release();
        return SDFT_OK;
    });
}

sdft_error sdft_mesh_files_write_grid(sdft_mesh_files *f, const sdft_mesh_grid *g, int fp16, char *msg, size_t msg_len)
{
    const char *what = "sdft_mesh_files_write_grid";
    if (!f || !g)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %s is NULL", what, f ? "g" : "f");
    if (f->spent)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: the files were written already", what);
    f->spent = true;
    for (const sdft_mesh_files::Entry &e : f->entries)
        if (e.format == SDFT_FILE_NPY && g->box.voxelCount() > meshsdf::kMaxDenseVoxels) {
            f->discard();
            return fail_with(msg, msg_len, SDFT_EINVAL, "%s: a dense array of %.0f voxels is above the limit of 2^31",
                             e.path.c_str(), g->box.voxelCount());
        }
    const sdft_error e = guarded(
        what, msg, msg_len, [&] { return inArena(g->threads, [&] { return writeAll(*f, *g, fp16, msg, msg_len); }); });
    f->discard(); // whatever was not renamed into place
    return e;
}

void sdft_mesh_files_free(sdft_mesh_files *f) { delete f; }

size_t sdft_mesh_sidecar_path(const char *npy_path, char *out, size_t out_len)
{
    // By hand, no allocation: nothing may throw out of here.
    const char *path = npy_path ? npy_path : "";
    const size_t n = std::strlen(path);
    const size_t stem = n > 4 && std::strcmp(path + n - 4, ".npy") == 0 ? n - 4 : n;
    if (out && out_len)
        std::snprintf(out, out_len, "%.*s.json", int(stem), path);
    return stem + 5;
}

sdft_error sdft_mesh_grid_write(const sdft_mesh_grid *g, const char *path, int fp16, char *msg, size_t msg_len)
{
    if (!g || !path)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_grid_write: %s is NULL", g ? "path" : "g");
    sdft_mesh_file file{path, SDFT_FILE_VDB};
    if (endsWith(path, ".nvdb"))
        file.format = SDFT_FILE_NVDB;
    else if (endsWith(path, ".npy"))
        file.format = SDFT_FILE_NPY;
    else if (!endsWith(path, ".vdb"))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: unknown extension (use .vdb, .nvdb or .npy)", path);
    sdft_mesh_files *set = nullptr;
    sdft_error e = sdft_mesh_files_reserve(&file, 1, &set, msg, msg_len);
    if (e == SDFT_OK)
        e = sdft_mesh_files_write_grid(set, g, fp16, msg, msg_len);
    sdft_mesh_files_free(set);
    return e;
}

} // extern "C"
