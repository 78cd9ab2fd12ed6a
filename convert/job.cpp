// mesh2sdf — one mesh converted (see job.h). Order of work: outputs
// reserved (an unwritable one fails before any work), mesh read, box
// planned, mesh oriented, grid built, files written under temporary names
// and renamed into place together.
#include "job.h"

#include "output.h"

#include <openvdb/tools/Count.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <chrono>
#include <exception>
#include <new>

namespace mesh2sdf
{

namespace
{

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Whether some active voxel is inside, by more than rounding (a voxel on a
// face may come out -1e-17): a grid without one has no zero crossing to trace.
bool hasSurface(const openvdb::FloatGrid &grid)
{
    return grid.activeVoxelCount() > 0 &&
           openvdb::tools::minMax(grid.tree()).min() < -0.01 * float(grid.voxelSize()[0]);
}

// Every destination, reserved first: nothing is ever written at a
// destination until the end, and the temporaries go when the job fails.
struct Outputs {
    PendingFile vdb, nvdb, npy, json;
    std::vector<PendingFile *> pending;
    bool committed = false;
    ~Outputs()
    {
        if (!committed)
            for (PendingFile *f : pending)
                discardFile(*f);
    }
};

bool reserveOutputs(const Options &opt, Outputs &out, std::string &error)
{
    if (!opt.output.empty()) {
        out.pending.push_back(&out.vdb);
        if (!reserveFile(opt.output, out.vdb, error))
            return false;
    }
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
// (--orient outward) or only its edges counted.
bool prepareMesh(const Options &opt, TriangleMesh &mesh, JobResult &r)
{
    if (!loadMesh(opt.input, mesh, r.error) || !planBox(mesh, opt, r.box, r.error))
        return false;
    const auto start = Clock::now();
    if (opt.orient == OrientMethod::Outward) {
        r.orient = orientMesh(mesh, opt.simd);
        r.oriented = true;
    } else {
        countEdges(mesh, edgeUses(mesh));
    }
    r.orientSeconds = secondsSince(start);
    r.health = mesh.health;
    r.meshRead = true;
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
            gridsWritten = (opt.output.empty() || writeVdb(grid, out.vdb.tmp, gridError)) &&
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
    out.committed = true; // committed or removed, each of them
    for (size_t i = 0; i < out.pending.size(); ++i)
        if (!committed[i]) {
            error = commitErrors[i];
            return false;
        }
    return true;
}

// The conversion itself; exceptions pass through to convertMesh.
bool convert(const Options &opt, Progress &progress, const std::function<void(const JobResult &)> &meshReady,
             JobResult &r)
{
    Outputs out;
    if (!reserveOutputs(opt, out, r.error))
        return false;
    TriangleMesh mesh;
    if (!prepareMesh(opt, mesh, r))
        return false;
    if (meshReady)
        meshReady(r);
    openvdb::FloatGrid::Ptr grid;
    try {
        grid = buildGrid(mesh, r.box, opt, progress, r.stats);
    } catch (const std::exception &e) {
        progress.finish();
        r.error = std::string("conversion failed: ") + e.what();
        return false;
    }
    const Provenance how{opt.input, signMethodName(opt.sign), opt.band, opt.full};
    describeGrid(*grid, opt.name.empty() ? fileStem(opt.input) : opt.name, how);

    // Writing has no progress of its own: the bar waits at its start and
    // shows 100% once every file is in place.
    progress.stage("writing", buildGridEnd(opt), 100);
    if (!writeOutputs(opt, *grid, r.box, how, out, r.error)) {
        progress.finish();
        return false;
    }
    progress.report(100);
    progress.finish();
    r.outputs = jobOutputs(opt);
    r.activeVoxels = grid->activeVoxelCount();
    r.gridMiB = double(grid->memUsage()) / (1024.0 * 1024.0);
    r.surface = hasSurface(*grid); // one pass over the tree
    return true;
}

} // namespace

std::string fileStem(const std::string &path)
{
    const size_t slash = path.find_last_of('/');
    std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
    const size_t dot = base.find_last_of('.');
    return dot == std::string::npos || dot == 0 ? base : base.substr(0, dot);
}

std::vector<std::string> jobOutputs(const Options &opt)
{
    std::vector<std::string> files;
    if (!opt.output.empty())
        files.push_back(opt.output);
    if (!opt.nvdb.empty())
        files.push_back(opt.nvdb);
    if (!opt.npy.empty()) {
        files.push_back(opt.npy);
        files.push_back(sidecarPath(opt.npy));
    }
    return files;
}

JobResult convertMesh(const Options &opt, Progress &progress, const std::function<void(const JobResult &)> &meshReady)
{
    const auto start = Clock::now();
    JobResult r;
    try {
        r.ok = convert(opt, progress, meshReady, r);
    } catch (const std::bad_alloc &) {
        r.ok = false;
        r.error = opt.input + ": out of memory";
    } catch (const std::exception &e) {
        r.ok = false;
        r.error = opt.input + ": " + e.what();
    }
    if (!r.ok)
        progress.finish();
    r.seconds = secondsSince(start);
    return r;
}

} // namespace mesh2sdf
