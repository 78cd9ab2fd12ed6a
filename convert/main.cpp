// mesh2sdf — a triangle mesh in, a signed distance grid out. See --help.
// Order of work: options, output folders, mesh, box, health line, grid,
// files (temporary names, renamed at the end), summary. Every failure is one
// line on stderr and exit status 1, with no file left at a destination.
#include "check.h"
#include "grid.h"
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
               const BoxGeometry &box, const openvdb::FloatGrid &grid, const BuildStats &stats, double seconds)
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
                static_cast<unsigned long long>(stats.ambiguousVoxels), hasSurface(grid) ? "true" : "false",
                orientSeconds, stats.windingSeconds, seconds, peakRssMiB());
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
        if (!loadMesh(opt.input, mesh, error) || !checkSign(mesh, opt.checkSign, opt.samples, error))
            return fail(error);
        return 0;
    }

    // Reserve every destination first: an unwritable output fails before
    // any work, and nothing is ever written at a destination until the end.
    PendingFile vdbFile, nvdbFile, npyFile, jsonFile;
    std::vector<PendingFile *> pending{&vdbFile};
    if (!reserveFile(opt.output, vdbFile, error))
        return fail(error);
    if (!opt.nvdb.empty()) {
        pending.push_back(&nvdbFile);
        if (!reserveFile(opt.nvdb, nvdbFile, error))
            return fail(error, pending);
    }
    if (!opt.npy.empty()) {
        pending.push_back(&npyFile);
        pending.push_back(&jsonFile);
        if (!reserveFile(opt.npy, npyFile, error) || !reserveFile(sidecarPath(opt.npy), jsonFile, error))
            return fail(error, pending);
    }

    TriangleMesh mesh;
    BoxGeometry box;
    if (!loadMesh(opt.input, mesh, error) || !planBox(mesh, opt, box, error))
        return fail(error, pending);
    OrientCounts orientCounts;
    const OrientCounts *oriented = nullptr;
    const auto orientStart = std::chrono::steady_clock::now();
    if (opt.orient == OrientMethod::Outward) {
        orientCounts = orientMesh(mesh, opt.simd);
        oriented = &orientCounts;
    } else {
        countEdges(mesh, edgeUses(mesh));
    }
    const double orientSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - orientStart).count();
    if (!opt.quiet && !opt.json)
        printHealth(opt.input, mesh.health, oriented);
    if (!mesh.health.closed() && opt.sign == SignMethod::Flood)
        std::fprintf(stderr,
                     "mesh2sdf: warning: the mesh is not closed (%zu boundary, %zu non-manifold edges) and --sign "
                     "flood assumes it is: inside and outside may be wrong; --sign winding handles open meshes\n",
                     mesh.health.boundaryEdges, mesh.health.nonManifoldEdges);

    Progress progress(!opt.quiet && !opt.json);
    BuildStats stats;
    openvdb::FloatGrid::Ptr grid;
    try {
        grid = buildGrid(mesh, box, opt, progress, stats);
    } catch (const std::exception &e) {
        progress.finish();
        return fail(std::string("conversion failed: ") + e.what(), pending);
    }
    Provenance how{opt.input, signMethodName(opt.sign), opt.band, opt.full};
    describeGrid(*grid, opt.name.empty() ? fileStem(opt.input) : opt.name, how);

    // Writing has no progress of its own: the bar waits at its start and
    // shows 100% once every file is in place.
    progress.stage("writing", buildGridEnd(opt), 100);
    const size_t slash = opt.npy.find_last_of('/');
    const std::string npyName = slash == std::string::npos ? opt.npy : opt.npy.substr(slash + 1);
    // The grid files and the dense array side by side: each reads the
    // finished tree only, and OpenVDB's writer runs on one thread.
    std::string gridError, arrayError;
    bool gridsWritten = false, arrayWritten = false;
    tbb::parallel_invoke(
        [&] {
            gridsWritten = writeVdb(*grid, vdbFile.tmp, gridError) &&
                           (opt.nvdb.empty() || writeNvdb(*grid, opt.fp16, nvdbFile.tmp, gridError));
        },
        [&] {
            arrayWritten =
                opt.npy.empty() || (writeNpy(*grid, box, npyFile.tmp, arrayError) &&
                                    writeNpyJson(box, npyName, how, grid->background(), jsonFile.tmp, arrayError));
        });
    const bool written = gridsWritten && arrayWritten;
    error = gridsWritten ? arrayError : gridError;
    if (!written) {
        progress.finish();
        return fail(error, pending);
    }
    // Renamed side by side too: replacing a large old file frees its blocks
    // within rename().
    std::vector<std::string> commitErrors(pending.size());
    std::vector<char> committed(pending.size(), 0);
    tbb::parallel_for(size_t(0), pending.size(),
                      [&](size_t i) { committed[i] = commitFile(*pending[i], commitErrors[i]); });
    for (size_t i = 0; i < pending.size(); ++i)
        if (!committed[i]) {
            progress.finish();
            return fail(commitErrors[i], pending);
        }
    progress.report(100);
    progress.finish();

    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (opt.json) {
        printJson(opt, mesh.health, oriented, orientSeconds, box, *grid, stats, secs);
    } else if (!opt.quiet) {
        std::printf("wrote %s: %dx%dx%d box, voxel size %.6g, %llu active voxels, grid %.1f MiB, peak memory "
                    "%.1f MiB, %.2f s, sign %s",
                    opt.output.c_str(), box.dims[0], box.dims[1], box.dims[2], box.voxelSize,
                    static_cast<unsigned long long>(grid->activeVoxelCount()),
                    double(grid->memUsage()) / (1024.0 * 1024.0), peakRssMiB(), secs, signMethodName(opt.sign));
        if (opt.sign == SignMethod::Winding)
            std::printf(" (%.2f s), %llu voxels signed from an ambiguous winding number", stats.windingSeconds,
                        static_cast<unsigned long long>(stats.ambiguousVoxels));
        std::printf("\n");
    }
    // Uncertain answers are said, not written silently.
    if (opt.sign == SignMethod::Winding) {
        if (oriented && oriented->ambiguousPatches)
            std::fprintf(stderr,
                         "mesh2sdf: warning: %zu open patches have no clear outside and keep the file's "
                         "orientation; %llu voxels were signed from a winding number between 0.25 and 0.75\n",
                         oriented->ambiguousPatches, static_cast<unsigned long long>(stats.ambiguousVoxels));
        if (!hasSurface(*grid))
            std::fprintf(stderr, "mesh2sdf: warning: no voxel of the band is inside the mesh, so the grid has no "
                                 "surface (an open sheet, or a mesh whose inside could not be told)\n");
    }
    return 0;
}
