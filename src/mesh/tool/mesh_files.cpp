// sdftrace — mesh2sdf's grid files (mesh_files_*, mesh_tool.h): the
// library's GridFiles (api.h) behind a C handle, spent once written.
#include "tool/mesh_tool.h"

#include "api.h"

#include <cstdio>
#include <cstring>

using namespace meshsdf::api;

struct mesh_files {
    GridFiles files;
    bool spent = false;
};

extern "C" {

sdft_error mesh_files_reserve(const mesh_file *files, size_t count, mesh_files **out, char *msg, size_t msg_len)
{
    const char *what = "mesh_files_reserve";
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
        if (format != SDFT_MESH_FORMAT_VDB && format != SDFT_MESH_FORMAT_NVDB && format != SDFT_MESH_FORMAT_NPY)
            return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %s: unknown format %d", what, files[i].path, format);
    }
    return guarded(what, msg, msg_len, [&] {
        std::unique_ptr<mesh_files> set(new mesh_files);
        std::vector<GridFiles::File> list;
        for (size_t i = 0; i < count; ++i)
            list.push_back({files[i].path, files[i].format});
        const sdft_error e = set->files.reserve(list, msg, msg_len);
        if (e == SDFT_OK)
            *out = set.release();
        return e;
    });
}

sdft_error mesh_files_write_grid(mesh_files *f, const sdft_mesh_grid *g, int fp16, char *msg, size_t msg_len)
{
    const char *what = "mesh_files_write_grid";
    if (!f || !g)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %s is NULL", what, f ? "g" : "f");
    if (f->spent)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: the files were written already", what);
    f->spent = true;
    const sdft_error e = guarded(what, msg, msg_len, [&] { return f->files.write(*g, fp16 != 0, msg, msg_len); });
    f->files.discard(); // whatever was not renamed into place
    return e;
}

void mesh_files_free(mesh_files *f) { delete f; }

size_t mesh_sidecar_path(const char *npy_path, char *out, size_t out_len)
{
    try {
        const std::string path = meshsdf::sidecarPath(npy_path ? npy_path : "");
        if (out && out_len)
            std::snprintf(out, out_len, "%s", path.c_str());
        return path.size();
    } catch (...) { // out of memory: nothing written
        if (out && out_len)
            out[0] = '\0';
        return 0;
    }
}

} // extern "C"
