// mesh2sdf — a triangle mesh in, a signed distance grid out. See --help.
// Order of work: options, output folders, mesh, box, health line, grid,
// files (temporary names, renamed at the end), summary. Every failure is one
// line on stderr and exit status 1, with no file left at a destination.
#include "check.h"
#include "grid.h"
#include "mesh.h"
#include "options.h"
#include "output.h"
#include "progress.h"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <sys/resource.h>

#include "sdftrace/error.h"

using namespace mesh2sdf;

namespace {

int fail(const std::string& error, std::vector<PendingFile*> files = {})
{
    for (PendingFile* f : files)
        discardFile(*f);
    std::fprintf(stderr, "mesh2sdf: %s\n", error.c_str());
    return 1;
}

std::string fileStem(const std::string& path)
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

void printHealth(const std::string& path, const MeshHealth& h)
{
    std::printf("mesh %s: %zu vertices, %zu faces (%zu triangles), %zu boundary edges, %zu non-manifold edges, "
                "%zu degenerate faces skipped\n",
                path.c_str(), h.vertices, h.faces, h.triangles, h.boundaryEdges, h.nonManifoldEdges,
                h.degenerateFaces);
}

} // namespace

int main(int argc, char** argv)
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
    std::vector<PendingFile*> pending{&vdbFile};
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
    if (!opt.quiet)
        printHealth(opt.input, mesh.health);
    if (!mesh.health.closed() && opt.sign == SignMethod::Flood)
        std::fprintf(stderr,
                     "mesh2sdf: warning: the mesh is not closed (%zu boundary, %zu non-manifold edges) and --sign "
                     "flood assumes it is: inside and outside may be wrong; --sign winding handles open meshes\n",
                     mesh.health.boundaryEdges, mesh.health.nonManifoldEdges);

    Progress progress(!opt.quiet);
    BuildStats stats;
    openvdb::FloatGrid::Ptr grid;
    try {
        grid = buildGrid(mesh, box, opt, progress, stats);
    } catch (const std::exception& e) {
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
            arrayWritten = opt.npy.empty() ||
                           (writeNpy(*grid, box, npyFile.tmp, arrayError) &&
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

    if (!opt.quiet) {
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("wrote %s: %dx%dx%d box, voxel size %.6g, %llu active voxels, grid %.1f MiB, peak memory "
                    "%.1f MiB, %.2f s, sign %s",
                    opt.output.c_str(), box.dims[0], box.dims[1], box.dims[2], box.voxelSize,
                    static_cast<unsigned long long>(grid->activeVoxelCount()),
                    double(grid->memUsage()) / (1024.0 * 1024.0), peakRssMiB(), secs, signMethodName(opt.sign));
        if (opt.sign == SignMethod::Winding)
            std::printf(" (%.2f s)", stats.windingSeconds);
        std::printf("\n");
    }
    return 0;
}
