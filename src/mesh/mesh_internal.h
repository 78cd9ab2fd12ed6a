// sdftrace — the mesh component's handles and its C++ seam (see
// include/sdftrace/mesh.h): what an sdft_mesh and an sdft_mesh_grid hold,
// and the guard that turns every exception into an sdft_error.
#ifndef SDFTRACE_MESH_INTERNAL_H
#define SDFTRACE_MESH_INTERNAL_H

#include "sdftrace/mesh.h"

#include "fail.h"
#include "grid.h"
#include "mesh.h"
#include "orient.h"
#include "output.h"
#include "progress.h"
#include "query.h"
#include "unit_sphere.h"

#include <memory>
#include <mutex>
#include <new>
#include <string>

struct sdft_mesh {
    mesh2sdf::TriangleMesh mesh; // oriented (or edges counted), normalized where asked
    mesh2sdf::OrientCounts orient;
    bool oriented = false;
    mesh2sdf::MeshSphere sphere; // in the input's units
    bool normalized = false;
    std::string source; // the grids' provenance
    std::string stem;   // the grids' default name

    // The point queries' hierarchies, built by the first query that needs
    // them (a mesh only converted to grids never pays for them).
    const mesh2sdf::PointQuery &query() const
    {
        std::call_once(mQueryOnce, [this] { mQuery.reset(new mesh2sdf::PointQuery(mesh, true, true)); });
        return *mQuery;
    }

  private:
    mutable std::once_flag mQueryOnce;
    mutable std::unique_ptr<mesh2sdf::PointQuery> mQuery;
};

struct sdft_mesh_grid {
    openvdb::FloatGrid::Ptr grid;
    mesh2sdf::BoxGeometry box;
    mesh2sdf::Provenance how;
    mesh2sdf::BuildStats stats;
};

namespace sdft_mesh_api
{

// Runs body() (returning an sdft_error) so that no exception leaves it: a
// cancelled progress is SDFT_ECANCELED, out of memory SDFT_ENOMEM, any
// other exception SDFT_EINTERNAL, each with `what` and the reason in msg.
template <class Body> sdft_error guarded(const char *what, char *msg, size_t msg_len, Body &&body)
{
    try {
        return body();
    } catch (const mesh2sdf::Cancelled &) {
        return fail_with(msg, msg_len, SDFT_ECANCELED, "%s: canceled by the progress callback", what);
    } catch (const std::bad_alloc &) {
        return fail_with(msg, msg_len, SDFT_ENOMEM, "%s: out of memory", what);
    } catch (const std::exception &e) {
        return fail_with(msg, msg_len, SDFT_EINTERNAL, "%s: %s", what, e.what());
    } catch (...) {
        return fail_with(msg, msg_len, SDFT_EINTERNAL, "%s: an unknown exception", what);
    }
}

// A Progress that draws nothing and tells `fn` (when not NULL).
struct Listened {
    mesh2sdf::Progress progress{false};
    Listened(sdft_progress_fn fn, void *user)
    {
        if (fn)
            progress.listen(fn, user);
    }
};

// The triangles of vertex and face arrays, as loadMesh makes them of a
// file's (sdftrace/mesh.h, sdft_mesh_from_arrays): SDFT_OK, or the code
// and one line in `error`.
sdft_error meshFromArrays(const void *vertices, sdft_dtype vertexType, size_t vertexCount, const void *faces,
                          sdft_dtype faceType, size_t faceCount, mesh2sdf::TriangleMesh &mesh, std::string &error);

} // namespace sdft_mesh_api

#endif
