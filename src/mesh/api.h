// sdftrace — the top of the mesh component: the handles and the C++ seam
// of include/sdftrace/mesh.h, which the api_*.cpp files beside this one
// implement over the modules in the folders below (geometry, io, orient,
// distance, sign, samples, grid, progress): what an sdft_mesh and an
// sdft_mesh_grid hold, and the guard that turns every exception into an
// sdft_error.
#ifndef SDFT_MESH_API_H
#define SDFT_MESH_API_H

#include "sdftrace/mesh.h"

#include "fail.h"
#include "geometry/triangle_mesh.h"
#include "geometry/unit_sphere.h"
#include "grid/build.h"
#include "grid/grid_files.h"
#include "orient/orient.h"
#include "progress/progress.h"
#include "samples/query.h"

#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <memory>
#include <mutex>
#include <new>
#include <string>

struct sdft_mesh {
    meshsdf::TriangleMesh mesh; // oriented (or edges counted), normalized where asked
    meshsdf::OrientCounts orient;
    bool oriented = false;
    meshsdf::MeshSphere sphere; // in the input's units
    bool normalized = false;
    std::string source; // the grids' provenance
    std::string stem;   // the grids' default name
    int threads = 0;    // sdft_mesh_params.threads
    bool simd = true, simd512 = true;
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
            mQuery.reset(new meshsdf::PointQuery(mesh, simd));
            mIndexSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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
};

namespace meshsdf::api
{

// Runs body() (returning an sdft_error) so that no exception leaves it: a
// cancelled progress is SDFT_ECANCELED, out of memory SDFT_ENOMEM, any
// other exception SDFT_EINTERNAL, each with `what` and the reason in msg.
template <class Body> sdft_error guarded(const char *what, char *msg, size_t msg_len, Body &&body)
{
    try {
        return body();
    } catch (const meshsdf::Cancelled &) {
        return fail_with(msg, msg_len, SDFT_ECANCELED, "%s: canceled by the progress callback", what);
    } catch (const std::bad_alloc &) {
        return fail_with(msg, msg_len, SDFT_ENOMEM, "%s: out of memory", what);
    } catch (const std::exception &e) {
        return fail_with(msg, msg_len, SDFT_EINTERNAL, "%s: %s", what, e.what());
    } catch (...) {
        return fail_with(msg, msg_len, SDFT_EINTERNAL, "%s: an unknown exception", what);
    }
}

// Runs body() on at most `threads` worker threads (0: all cores), in an
// arena of its own: TBB's loops inside it, OpenVDB's too, stay there.
template <class Body> auto inArena(int threads, Body &&body) -> decltype(body())
{
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    return arena.execute(std::forward<Body>(body));
}

double secondsSince(std::chrono::steady_clock::time_point start);

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

// A path's file name without its folder and last extension: a grid's
// default name.
std::string fileStem(const std::string &path);

// The Progress of a call whose params carry these callbacks.
struct Listened {
    meshsdf::Progress progress;
    Listened(sdft_progress_fn fn, sdft_stage_fn stages, void *user) : progress(fn, stages, user) {}
};

// The triangles of vertex and face arrays, as loadMesh makes them of a
// file's (sdftrace/mesh.h, sdft_mesh_from_arrays): SDFT_OK, or the code
// and one line in `error`.
sdft_error meshFromArrays(const void *vertices, sdft_dtype vertexType, size_t vertexCount, const void *faces,
                          sdft_dtype faceType, size_t faceCount, meshsdf::TriangleMesh &mesh, std::string &error);

} // namespace meshsdf::api

#endif
