// sdftrace — the top of the mesh component: the handles and the C++ seam
// of include/sdftrace/mesh.h, which the api_*.cpp files beside this one
// implement over the modules in the folders below (geometry, io, orient,
// distance, sign, samples, grid, progress): what an sdft_mesh and an
// sdft_mesh_grid hold, and the guard that turns every exception into an
// sdft_error.
#ifndef SDFT_MESH_API_H
#define SDFT_MESH_API_H

#include "sdftrace/mesh.h"

#include "atomic_file.h"
#include "fail.h"
#include "geometry/triangle_mesh.h"
#include "geometry/unit_sphere.h"
#include "grid/build.h"
#include "grid/grid_files.h"
#include "orient/orient.h"
#include "progress/progress.h"
#include "samples/query.h"
#include "seam.h"

#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <memory>
#include <mutex>
#include <new>
#include <shared_mutex>
#include <string>
#include <vector>

struct sdft_mesh {
    meshsdf::TriangleMesh mesh; // oriented (or edges counted), normalized where asked
    meshsdf::OrientCounts orient;
    bool oriented = false;
    meshsdf::MeshSphere sphere; // in the input's units
    bool normalized = false;
    std::string warnings; // sdft_mesh_warnings
    std::string source;   // the grids' provenance
    std::string stem;     // the grids' default name
    int threads = 0;      // sdft_mesh_params.threads
    meshsdf::Simd simd;   // sdft_mesh_params.simd
    double readSeconds = 0, orientSeconds = 0;

    // The mesh's sphere where the mesh now is: the unit sphere once
    // normalized.
    meshsdf::MeshSphere frame() const { return normalized ? meshsdf::MeshSphere{} : sphere; }

    // The point queries' hierarchies, built by the first query that needs
    // them (a mesh only converted to grids never pays for them), in the
    // caller's arena.
    const meshsdf::PointQuery &query() const
    {
        std::call_once(mQueryOnce, [this] {
            const auto start = std::chrono::steady_clock::now();
            mQuery.reset(new meshsdf::PointQuery(mesh, simd.vector, simd.wide));
            mIndexSeconds = seam::secondsSince(start);
        });
        return *mQuery;
    }
    double indexSeconds() const { return mIndexSeconds.load(); }

  private:
    mutable std::once_flag mQueryOnce;
    mutable std::unique_ptr<meshsdf::PointQuery> mQuery;
    mutable std::atomic<double> mIndexSeconds{0.0};
};

struct sdft_mesh_grid {
    openvdb::FloatGrid::Ptr grid;
    meshsdf::BoxGeometry box;
    meshsdf::Provenance how;
    meshsdf::BuildStats stats;
    int threads = 0; // for everything done with it
    bool surface = false;
    uint64_t activeVoxels = 0, memoryBytes = 0; // counted once, in its arena
    double seconds = 0;
    // NanoVDB's converter (openToNanoVDB) rewrites the tree's node origins
    // while it runs and restores them after: it takes this lock alone, and
    // every other reader of the tree (the .vdb and .npy writers, the dense
    // copy) shares it.
    mutable std::shared_mutex treeLock;
};

namespace meshsdf::api
{

// The seams' one guard (src/common/seam.h): a cancelled progress is
// SDFT_ECANCELED, out of memory SDFT_ENOMEM, any other exception
// SDFT_EINTERNAL, each with `what` and the reason in msg.
using seam::guarded;

// Runs body() on at most `threads` worker threads (0: all cores), in an
// arena of its own: TBB's loops inside it, OpenVDB's too, stay there.
template <class Body> auto inArena(int threads, Body &&body) -> decltype(body())
{
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    return arena.execute(std::forward<Body>(body));
}

using seam::secondsSince;

// The value a caller stored in one of the API's enums, read as an int: a C
// caller may store any int there, and C++ may not load one outside the
// enum's range as the enum.
template <class Enum> int enumValue(const Enum &e)
{
    static_assert(sizeof(Enum) == sizeof(int), "the API's enums are ints");
    int v;
    std::memcpy(&v, &e, sizeof v);
    return v;
}

using seam::fileStem;

// The rows of a params struct's settings table (sdft_mesh_settings).
struct Settings {
    const sdft_mesh_setting *rows;
    size_t count;
};
Settings settingsOf(sdft_mesh_settings_of of);

// Every setting of `params`, a struct of kind `of`, set to its default.
void fillDefaults(sdft_mesh_settings_of of, void *params);

// Every setting of `params` checked against its range: SDFT_OK, or
// SDFT_EINVAL with "WHAT: NAME must be in RANGE, got VALUE" in msg.
sdft_error checkSettings(sdft_mesh_settings_of of, const void *params, const char *what, char *msg, size_t msg_len);

// The name of value `value` of a CHOICE setting ("winding"), or "?".
std::string choiceName(sdft_mesh_settings_of of, const char *setting, int value);

// The same without allocating: its length, with *name at it in the
// library's table (not NUL-terminated there); 0 for none.
size_t choiceText(sdft_mesh_settings_of of, const char *setting, int value, const char **name) noexcept;

// The box of the conversion of m with p, after p's settings are checked,
// and whether it fits: SDFT_EINVAL for a setting out of its range or a box
// the limits refuse, SDFT_ENOMEM for one this machine's memory does not
// hold; one line in msg, prefixed by `what` for a setting.
sdft_error planGrid(const char *what, const sdft_mesh &m, const sdft_mesh_grid_params &p, meshsdf::BoxGeometry &box,
                    char *msg, size_t msg_len);

// What a box tells before anything is built.
sdft_mesh_grid_box boxOf(const meshsdf::BoxGeometry &geometry, double band);

// The files one grid is written as, together and whole or not at all:
// reserved before the work (a temporary file beside each, and beside an
// .npy's sidecar JSON, so that a missing or read-only folder fails first),
// written side by side, then renamed into place together; whatever was not
// renamed is removed.
class GridFiles
{
  public:
    struct File {
        std::string path;
        sdft_mesh_format format;
    };
    GridFiles() = default;
    GridFiles(const GridFiles &) = delete;
    GridFiles &operator=(const GridFiles &) = delete;
    ~GridFiles() { discard(); }

    // SDFT_OK, or SDFT_EIO with one line (and nothing left behind).
    sdft_error reserve(const std::vector<File> &files, char *msg, size_t msg_len);
    // Writes g into every file in its format (fp16: NanoVDB Fp16 leaves),
    // then renames them all: SDFT_OK, or SDFT_EINVAL (a dense array over
    // the limit), SDFT_EIO with one line. Removes what is left either way.
    sdft_error write(const sdft_mesh_grid &g, bool fp16, char *msg, size_t msg_len);
    // Removes every temporary file still there.
    void discard();

  private:
    std::vector<File> mFiles;
    std::vector<atomic_file> mTargets; // each file's, an .npy's sidecar after it
    std::vector<size_t> mFirst;        // mFiles[i]'s first of mTargets
    bool mOpen = false;                // mTargets hold temporary files
};

// The Progress of a call whose params carry these callbacks.
struct Listened {
    meshsdf::Progress progress;
    Listened(sdft_progress_fn fn, sdft_mesh_stage_fn stages, void *user) : progress(fn, stages, user) {}
};

// The triangles of vertex and face arrays, as loadMesh makes them of a
// file's (sdftrace/mesh.h, sdft_mesh_from_arrays): SDFT_OK, or the code
// and one line in `error`.
sdft_error meshFromArrays(const void *vertices, sdft_mesh_dtype vertexType, size_t vertexCount, const void *faces,
                          sdft_mesh_dtype faceType, size_t faceCount, meshsdf::TriangleMesh &mesh, std::string &error);

} // namespace meshsdf::api

#endif
