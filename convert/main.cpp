// mesh2sdf — a triangle mesh in, a signed distance grid out. See --help.
// Order of work: options, output folders, mesh, box, health line, grid,
// files (temporary names, renamed at the end), summary. Every failure is one
// line on stderr and exit status 1, with no file left at a destination.
#include "check.h"
#include "grid.h"
#include "memory_estimate.h"
#include "mesh.h"
#include "options.h"
#include "orient.h"
#include "output.h"
#include "progress.h"

#include <openvdb/tools/Count.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <sys/resource.h>

#include "json.h"
#include "sdftrace/error.h"

using namespace mesh2sdf;

namespace
{

int fail(const std::string &error, std::vector<PendingFile *> files = {})
{
    for (PendingFile *f : files)
        discardFile(*f);
    std::fprintf(stderr, "mesh2sdf: %s\n", error.c_str());
    return 1;
}

std::string fileStem(const std::string &path)
{
    const size_t slash = path.find_last_of('/');
    std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
    const size_t dot = base.find_last_of('.');
    return dot == std::string::npos || dot == 0 ? base : base.substr(0, dot);
}

double peakRssMiB()
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_maxrss) / 1024.0; // ru_maxrss is in KiB on Linux
}

void printHealth(const std::string &path, const MeshHealth &h, const OrientCounts *o)
{
    std::printf("mesh %s: %zu vertices, %zu faces (%zu triangles), %zu boundary edges, %zu non-manifold edges, "
                "%zu degenerate faces skipped",
                path.c_str(), h.vertices, h.faces, h.triangles, h.boundaryEdges, h.nonManifoldEdges, h.degenerateFaces);
    if (o) {
        std::printf("; %zu vertices welded, %zu duplicate faces dropped, %zu patches, %zu faces reoriented, %zu "
                    "patches turned outward",
                    o->weldedVertices, o->duplicateFaces, o->patches, o->reorientedFaces, o->outwardPatches);
        if (o->cavityPatches)
            std::printf(", %zu inward patches kept as cavity walls", o->cavityPatches);
        if (o->ambiguousPatches)
            std::printf(", %zu open patches with no clear outside", o->ambiguousPatches);
        if (o->nonOrientablePatches)
            std::printf(", %zu non-orientable patches", o->nonOrientablePatches);
    }
    std::printf("\n");
}

// Whether some active voxel is inside, by more than rounding (a voxel on a
// face may come out -1e-17): a grid without one has no zero crossing to trace.
bool hasSurface(const openvdb::FloatGrid &grid)
{
    return grid.activeVoxelCount() > 0 &&
           openvdb::tools::minMax(grid.tree()).min() < -0.01 * float(grid.voxelSize()[0]);
}

// The --json object: the mesh's health, what orienting did, the grid.
void printJson(const Options &opt, const MeshHealth &h, const OrientCounts *o, double orientSeconds,
               const BoxGeometry &box, const openvdb::FloatGrid &grid, const BuildStats &stats, double seconds,
               bool surface)
{
    std::printf("{\"mesh\": ");
    json_put_string(stdout, opt.input.c_str());
    std::printf(", \"output\": ");
    json_put_string(stdout, opt.output.c_str());
    std::printf(", \"vertices\": %zu, \"faces\": %zu, \"triangles\": %zu, \"degenerate_faces\": %zu, "
                "\"boundary_edges\": %zu, \"non_manifold_edges\": %zu, \"orient\": \"%s\"",
                h.vertices, h.faces, h.triangles, h.degenerateFaces, h.boundaryEdges, h.nonManifoldEdges,
                o ? "outward" : "none");
    if (o)
        std::printf(", \"welded_vertices\": %zu, \"duplicate_faces\": %zu, \"patches\": %zu, "
                    "\"reoriented_faces\": %zu, \"outward_patches\": %zu, \"cavity_patches\": %zu, "
                    "\"ambiguous_patches\": %zu, \"non_orientable_patches\": %zu",
                    o->weldedVertices, o->duplicateFaces, o->patches, o->reorientedFaces, o->outwardPatches,
                    o->cavityPatches, o->ambiguousPatches, o->nonOrientablePatches);
    std::printf(", \"dims\": [%d, %d, %d], \"voxel_size\": %.9g, \"active_voxels\": %llu, \"sign\": \"%s\", "
                "\"ambiguous_voxels\": %llu, \"surface\": %s, \"orient_seconds\": %.6f, \"winding_seconds\": %.6f, "
                "\"seconds\": %.6f, \"peak_mib\": %.1f}\n",
                box.dims[0], box.dims[1], box.dims[2], box.voxelSize,
                static_cast<unsigned long long>(grid.activeVoxelCount()), signMethodName(opt.sign),
                static_cast<unsigned long long>(stats.ambiguousVoxels), surface ? "true" : "false", orientSeconds,
                stats.windingSeconds, seconds, peakRssMiB());
}

// Every destination, reserved first: an unwritable output fails before any
// work, and nothing is ever written at a destination until the end.
struct Outputs {
    PendingFile vdb, nvdb, npy, json;
    std::vector<PendingFile *> pending;
};

bool reserveOutputs(const Options &opt, Outputs &out, std::string &error)
{
    out.pending = {&out.vdb};
    if (!reserveFile(opt.output, out.vdb, error))
        return false;
    if (!opt.nvdb.empty()) {
        out.pending.push_back(&out.nvdb);
        if (!reserveFile(opt.nvdb, out.nvdb, error))
            return false;
    }
    if (!opt.npy.empty()) {
        out.pending.push_back(&out.npy);
        out.pending.push_back(&out.json);
        if (!reserveFile(opt.npy, out.npy, error) || !reserveFile(sidecarPath(opt.npy), out.json, error))
            return false;
    }
    return true;
}

// The mesh as the conversion takes it: read, its box planned, oriented
// (--orient outward) or only its edges counted, and what that found.
struct PreparedMesh {
    TriangleMesh mesh;
    BoxGeometry box;
    OrientCounts counts;
    const OrientCounts *oriented = nullptr; // &counts, or none with --orient none
    double orientSeconds = 0;
};

bool prepareMesh(const Options &opt, PreparedMesh &m, std::string &error)
{
    if (!loadMesh(opt.input, m.mesh, error) || !planBox(m.mesh, opt, m.box, error))
        return false;
    const auto start = std::chrono::steady_clock::now();
    if (opt.orient == OrientMethod::Outward) {
        m.counts = orientMesh(m.mesh, opt.simd);
        m.oriented = &m.counts;
    } else {
        countEdges(m.mesh, edgeUses(m.mesh));
    }
    m.orientSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return true;
}

// The grid files and the dense array written side by side (each reads the
// finished tree only, and OpenVDB's writer runs on one thread), then renamed
// into place side by side too (replacing a large old file frees its blocks
// within rename()).
bool writeOutputs(const Options &opt, const openvdb::FloatGrid &grid, const BoxGeometry &box, const Provenance &how,
                  Outputs &out, std::string &error)
{
    const size_t slash = opt.npy.find_last_of('/');
    const std::string npyName = slash == std::string::npos ? opt.npy : opt.npy.substr(slash + 1);
    std::string gridError, arrayError;
    bool gridsWritten = false, arrayWritten = false;
    tbb::parallel_invoke(
        [&] {
            gridsWritten = writeVdb(grid, out.vdb.tmp, gridError) &&
                           (opt.nvdb.empty() || writeNvdb(grid, opt.fp16, out.nvdb.tmp, gridError));
        },
        [&] {
            arrayWritten =
                opt.npy.empty() || (writeNpy(grid, box, out.npy.tmp, arrayError) &&
                                    writeNpyJson(box, npyName, how, grid.background(), out.json.tmp, arrayError));
        });
    if (!gridsWritten || !arrayWritten) {
        error = gridsWritten ? arrayError : gridError;
        return false;
    }
    std::vector<std::string> commitErrors(out.pending.size());
    std::vector<char> committed(out.pending.size(), 0);
    tbb::parallel_for(size_t(0), out.pending.size(),
                      [&](size_t i) { committed[i] = commitFile(*out.pending[i], commitErrors[i]); });
    for (size_t i = 0; i < out.pending.size(); ++i)
        if (!committed[i]) {
            error = commitErrors[i];
            return false;
        }
    return true;
}

// The closing line, or with --json the object; then, on stderr, what stays
// uncertain: said, not written silently.
void report(const Options &opt, const PreparedMesh &m, const openvdb::FloatGrid &grid, const BuildStats &stats,
            double seconds)
{
    const bool surface = hasSurface(grid); // one pass over the tree, for the object and the warning
    if (opt.json) {
        printJson(opt, m.mesh.health, m.oriented, m.orientSeconds, m.box, grid, stats, seconds, surface);
    } else if (!opt.quiet) {
        std::printf("wrote %s: %dx%dx%d box, voxel size %.6g, %llu active voxels, grid %.1f MiB, peak memory "
                    "%.1f MiB, %.2f s, sign %s",
                    opt.output.c_str(), m.box.dims[0], m.box.dims[1], m.box.dims[2], m.box.voxelSize,
                    static_cast<unsigned long long>(grid.activeVoxelCount()),
                    double(grid.memUsage()) / (1024.0 * 1024.0), peakRssMiB(), seconds, signMethodName(opt.sign));
        if (opt.sign == SignMethod::Winding)
            std::printf(" (%.2f s), %llu voxels signed from an ambiguous winding number", stats.windingSeconds,
                        static_cast<unsigned long long>(stats.ambiguousVoxels));
        std::printf("\n");
    }
    if (opt.sign != SignMethod::Winding)
        return;
    if (m.oriented && m.oriented->ambiguousPatches)
        std::fprintf(stderr,
                     "mesh2sdf: warning: %zu open patches have no clear outside and keep the file's "
                     "orientation; %llu voxels were signed from a winding number between 0.25 and 0.75\n",
                     m.oriented->ambiguousPatches, static_cast<unsigned long long>(stats.ambiguousVoxels));
    if (!surface)
        std::fprintf(stderr, "mesh2sdf: warning: no voxel of the band is inside the mesh, so the grid has no "
                             "surface (an open sheet, or a mesh whose inside could not be told)\n");
}

} // namespace

int main(int argc, char **argv)
{
    if (argc == 2 && std::strcmp(argv[1], "--version") == 0) {
        const int v = sdft_version();
        std::printf("mesh2sdf %d.%d.%d\n", v / 10000, v / 100 % 100, v % 100);
        return 0;
    }
    Options opt;
    std::string error;
    if (!parseOptions(argc, argv, opt, error)) {
        if (opt.help) {
            printHelp();
            return 0;
        }
        return fail(error);
    }
    if (opt.help) {
        printHelp();
        return 0;
    }
    std::unique_ptr<tbb::global_control> threads;
    if (opt.threads > 0)
        threads.reset(new tbb::global_control(tbb::global_control::max_allowed_parallelism, size_t(opt.threads)));
    openvdb::initialize();
    const auto t0 = std::chrono::steady_clock::now();

    if (!opt.checkSign.empty()) {
        TriangleMesh mesh;
        if (!samplesFitMemory(opt.samples, error) || !loadMesh(opt.input, mesh, error) ||
            !checkSign(mesh, opt.checkSign, opt.samples, error))
            return fail(error);
        return 0;
    }

    Outputs out;
    if (!reserveOutputs(opt, out, error))
        return fail(error, out.pending);
    PreparedMesh m;
    if (!prepareMesh(opt, m, error))
        return fail(error, out.pending);
    if (!opt.quiet && !opt.json)
        printHealth(opt.input, m.mesh.health, m.oriented);
    if (!m.mesh.health.closed() && opt.sign == SignMethod::Flood)
        std::fprintf(stderr,
                     "mesh2sdf: warning: the mesh is not closed (%zu boundary, %zu non-manifold edges) and --sign "
                     "flood assumes it is: inside and outside may be wrong; --sign winding handles open meshes\n",
                     m.mesh.health.boundaryEdges, m.mesh.health.nonManifoldEdges);

    Progress progress(!opt.quiet && !opt.json);
    BuildStats stats;
    openvdb::FloatGrid::Ptr grid;
    try {
        grid = buildGrid(m.mesh, m.box, opt, progress, stats);
    } catch (const std::exception &e) {
        progress.finish();
        return fail(std::string("conversion failed: ") + e.what(), out.pending);
    }
    const Provenance how{opt.input, signMethodName(opt.sign), opt.band, opt.full};
    describeGrid(*grid, opt.name.empty() ? fileStem(opt.input) : opt.name, how);

    // Writing has no progress of its own: the bar waits at its start and
    // shows 100% once every file is in place.
    progress.stage("writing", buildGridEnd(opt), 100);
    if (!writeOutputs(opt, *grid, m.box, how, out, error)) {
        progress.finish();
        return fail(error, out.pending);
    }
    progress.report(100);
    progress.finish();
    report(opt, m, *grid, stats, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return 0;
}
