// sdftrace — taking a mesh in (sdft_mesh_load, sdft_mesh_from_arrays) and
// what it holds (sdft_mesh_get_health, _warnings, _frame, _timings): read or copied,
// its sphere taken, normalized where asked, then oriented.
#include "api.h"

#include "io/mesh_io.h"

#include <cstdio>

using namespace meshsdf::api;

namespace
{

// What every mesh goes through once its triangles are in place, reading
// then orienting on the progress bar's two halves.
void finishMesh(sdft_mesh &m, const sdft_mesh_params &p, meshsdf::Progress &progress)
{
    m.sphere = meshsdf::meshSphere(m.mesh);
    if (p.normalize) {
        meshsdf::normalizeMesh(m.mesh, m.sphere);
        m.normalized = true;
    }
    progress.stage("orienting", 50, 100);
    const auto start = std::chrono::steady_clock::now();
    if (p.orient) {
        m.orient = meshsdf::orientMesh(m.mesh, m.simd.vector);
        m.oriented = true;
        for (const std::string &note : m.orient.notes)
            m.warnings += note + "\n";
    } else {
        meshsdf::countEdges(m.mesh, meshsdf::edgeUses(m.mesh));
    }
    m.orientSeconds = secondsSince(start);
    progress.report(100);
}

// The mesh's share of the cores and its vector instructions, from p.
std::unique_ptr<sdft_mesh> newMesh(const sdft_mesh_params &p)
{
    std::unique_ptr<sdft_mesh> m(new sdft_mesh);
    m->threads = p.threads;
    m->simd.vector = p.simd != SDFT_MESH_SIMD_NONE;
    m->simd.wide = p.simd == SDFT_MESH_SIMD_AUTO;
    return m;
}

// The mesh reader's one line, as an error code: a file that cannot be
// opened is SDFT_EIO, anything else it refuses SDFT_EFORMAT.
sdft_error readError(const std::string &error) { return error.rfind("cannot open", 0) == 0 ? SDFT_EIO : SDFT_EFORMAT; }

} // namespace

namespace
{

// A mesh taken in, the one way for a file and for arrays: p checked,
// `read(mesh, warnings, error)` filling the triangles and the reader's
// doubts (SDFT_OK, or a code and one line in error), timed, then
// finishMesh, all on the mesh's share of the cores. `path`: the file (the
// default source and grid name), or NULL.
template <class Read>
sdft_error takeIn(const char *what, const char *context, const sdft_mesh_params *params, const char *path,
                  sdft_mesh **out, char *msg, size_t msg_len, Read &&read)
{
    const sdft_mesh_params p = params ? *params : sdft_mesh_params_defaults();
    const sdft_error bad = checkSettings(SDFT_MESH_SETTINGS_MESH, &p, what, msg, msg_len);
    if (bad != SDFT_OK)
        return bad;
    return guarded(context, msg, msg_len, [&] {
        Listened listened(p.progress, p.stage, p.progress_user);
        listened.progress.stage("reading", 0, 50);
        std::unique_ptr<sdft_mesh> m = newMesh(p);
        return inArena(p.threads, [&] {
            const auto start = std::chrono::steady_clock::now();
            std::string error;
            std::vector<std::string> doubts;
            const sdft_error e = read(m->mesh, doubts, error);
            if (e != SDFT_OK)
                return fail_with(msg, msg_len, e, "%s", error.c_str());
            if (p.strict && !doubts.empty())
                return fail_with(msg, msg_len, SDFT_EFORMAT, "%s (refused as strict): %s", doubts[0].c_str(),
                                 path ? path : "mesh from arrays");
            for (const std::string &doubt : doubts)
                m->warnings += doubt + "\n";
            m->readSeconds = secondsSince(start);
            listened.progress.report(100);
            m->source = p.source ? p.source : path ? path : "";
            m->stem = path ? fileStem(path) : "mesh";
            finishMesh(*m, p, listened.progress);
            *out = m.release();
            return SDFT_OK;
        });
    });
}

} // namespace

extern "C" {

sdft_mesh_params sdft_mesh_params_defaults(void)
{
    sdft_mesh_params p{};
    fillDefaults(SDFT_MESH_SETTINGS_MESH, &p);
    return p;
}

sdft_error sdft_mesh_load(const char *path, const sdft_mesh_params *params, sdft_mesh **out, char *msg, size_t msg_len)
{
    if (out)
        *out = nullptr;
    if (!path || !out)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_load: %s is NULL", path ? "out" : "path");
    return takeIn("sdft_mesh_load", path, params, path, out, msg, msg_len,
                  [&](meshsdf::TriangleMesh &mesh, std::vector<std::string> &doubts, std::string &error) {
                      return meshsdf::loadMesh(path, mesh, error, &doubts) ? SDFT_OK : readError(error);
                  });
}

sdft_error sdft_mesh_from_arrays(const void *vertices, sdft_mesh_dtype vertex_type, size_t vertex_count,
                                 const void *faces, sdft_mesh_dtype face_type, size_t face_count,
                                 const sdft_mesh_params *params, sdft_mesh **out, char *msg, size_t msg_len)
{
    if (out)
        *out = nullptr;
    if (!vertices || !faces || !out)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_from_arrays: %s is NULL",
                         !vertices ? "vertices"
                         : !faces  ? "faces"
                                   : "out");
    return takeIn("sdft_mesh_from_arrays", "mesh from arrays", params, nullptr, out, msg, msg_len,
                  [&](meshsdf::TriangleMesh &mesh, std::vector<std::string> &, std::string &error) {
                      return meshFromArrays(vertices, vertex_type, vertex_count, faces, face_type, face_count, mesh,
                                            error);
                  });
}

void sdft_mesh_free(sdft_mesh *m) { delete m; }

sdft_error sdft_mesh_get_health(const sdft_mesh *m, sdft_mesh_health *health, char *msg, size_t msg_len)
{
    if (!m || !health)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_get_health: %s is NULL", m ? "health" : "m");
    const meshsdf::MeshHealth &h = m->mesh.health;
    sdft_mesh_health i{};
    i.vertices = h.vertices;
    i.faces = h.faces;
    i.triangles = h.triangles;
    i.degenerate_faces = h.degenerateFaces;
    i.welded_vertices = h.weldedVertices;
    i.boundary_edges = h.boundaryEdges;
    i.non_manifold_edges = h.nonManifoldEdges;
    i.closed = h.closed();
    i.oriented = m->oriented;
    i.duplicate_faces = m->orient.duplicateFaces;
    i.patches = m->orient.patches;
    i.non_orientable_patches = m->orient.nonOrientablePatches;
    i.reoriented_faces = m->orient.reorientedFaces;
    i.outward_patches = m->orient.outwardPatches;
    i.cavity_patches = m->orient.cavityPatches;
    i.ambiguous_patches = m->orient.ambiguousPatches;
    i.ambiguous_area = m->orient.ambiguousArea;
    i.evidence_patches = m->orient.evidencePatches;
    i.skipped_faces = h.skippedFaces;
    *health = i;
    return SDFT_OK;
}

size_t sdft_mesh_warnings(const sdft_mesh *m, char *out, size_t out_len)
{
    if (out && out_len)
        out[0] = '\0';
    if (!m)
        return 0;
    if (out && out_len)
        std::snprintf(out, out_len, "%s", m->warnings.c_str());
    return m->warnings.size();
}

sdft_error sdft_mesh_get_frame(const sdft_mesh *m, sdft_mesh_frame *frame, char *msg, size_t msg_len)
{
    if (!m || !frame)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_get_frame: %s is NULL", m ? "frame" : "m");
    sdft_mesh_frame f{};
    for (int k = 0; k < 3; ++k) {
        f.lo[k] = m->mesh.lo[k];
        f.hi[k] = m->mesh.hi[k];
        f.centre[k] = m->sphere.centre[k];
    }
    f.radius = m->sphere.radius;
    f.normalized = m->normalized;
    *frame = f;
    return SDFT_OK;
}

sdft_error sdft_mesh_get_timings(const sdft_mesh *m, sdft_mesh_timings *t, char *msg, size_t msg_len)
{
    if (!m || !t)
        return fail_with(msg, msg_len, SDFT_EINVAL, "sdft_mesh_get_timings: %s is NULL", m ? "t" : "m");
    *t = sdft_mesh_timings{m->readSeconds, m->orientSeconds, m->indexSeconds()};
    return SDFT_OK;
}

} // extern "C"
