// mesh2sdf — a triangle mesh in, a signed distance grid out. See --help.
// Options, then the conversion (job.h) and what it found, printed: the
// health line once the mesh is read, the summary at the end. Every failure
// is one line on stderr and exit status 1, with no file left at a
// destination.
#include "batch.h"
#include "check.h"
#include "job.h"
#include "memory_estimate.h"
#include "options.h"
#include "query.h"
#include "samples.h"
#include "text.h"

#include <tbb/global_control.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <sys/resource.h>

#include "json.h"
#include "sdftrace/error.h"

using namespace mesh2sdf;

namespace
{

int fail(const std::string &error)
{
    std::fprintf(stderr, "mesh2sdf: %s\n", error.c_str());
    return 1;
}

void printHealth(const std::string &path, const JobResult &r)
{
    const MeshHealth &h = r.health;
    std::printf("mesh %s: %zu vertices, %zu faces (%zu triangles), %zu boundary edges, %zu non-manifold edges, "
                "%zu degenerate faces skipped",
                path.c_str(), h.vertices, h.faces, h.triangles, h.boundaryEdges, h.nonManifoldEdges, h.degenerateFaces);
    if (r.oriented) {
        const OrientCounts *o = &r.orient;
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

// The --json object: the mesh's health, what orienting did, the grid.
void printJson(const Options &opt, const JobResult &r)
{
    const MeshHealth &h = r.health;
    std::printf("{\"mesh\": ");
    json_put_string(stdout, opt.input.c_str());
    std::printf(", \"output\": ");
    json_put_string(stdout, opt.output.c_str());
    std::printf(", \"vertices\": %zu, \"faces\": %zu, \"triangles\": %zu, \"degenerate_faces\": %zu, "
                "\"boundary_edges\": %zu, \"non_manifold_edges\": %zu, \"orient\": \"%s\"",
                h.vertices, h.faces, h.triangles, h.degenerateFaces, h.boundaryEdges, h.nonManifoldEdges,
                r.oriented ? "outward" : "none");
    if (r.oriented) {
        const OrientCounts *o = &r.orient;
        std::printf(", \"welded_vertices\": %zu, \"duplicate_faces\": %zu, \"patches\": %zu, "
                    "\"reoriented_faces\": %zu, \"outward_patches\": %zu, \"cavity_patches\": %zu, "
                    "\"ambiguous_patches\": %zu, \"non_orientable_patches\": %zu",
                    o->weldedVertices, o->duplicateFaces, o->patches, o->reorientedFaces, o->outwardPatches,
                    o->cavityPatches, o->ambiguousPatches, o->nonOrientablePatches);
    }
    std::printf(", \"dims\": [%d, %d, %d], \"voxel_size\": %.9g, \"active_voxels\": %llu, \"sign\": \"%s\", "
                "\"ambiguous_voxels\": %llu, \"surface\": %s, \"orient_seconds\": %.6f, \"winding_seconds\": %.6f, "
                "\"seconds\": %.6f, \"peak_mib\": %.1f}\n",
                r.box.dims[0], r.box.dims[1], r.box.dims[2], r.box.voxelSize,
                static_cast<unsigned long long>(r.activeVoxels), signMethodName(opt.sign),
                static_cast<unsigned long long>(r.stats.ambiguousVoxels), r.surface ? "true" : "false", r.orientSeconds,
                r.stats.windingSeconds, r.seconds, peakMiB());
}

// The closing line, or with --json the object; then, on stderr, what stays
// uncertain: said, not written silently.
void report(const Options &opt, const JobResult &r)
{
    if (opt.json) {
        printJson(opt, r);
    } else if (!opt.quiet) {
        std::printf("wrote %s: %dx%dx%d box, voxel size %.6g, %llu active voxels, grid %.1f MiB, peak memory "
                    "%.1f MiB, %.2f s, sign %s",
                    opt.output.c_str(), r.box.dims[0], r.box.dims[1], r.box.dims[2], r.box.voxelSize,
                    static_cast<unsigned long long>(r.activeVoxels), r.gridMiB, peakMiB(), r.seconds,
                    signMethodName(opt.sign));
        if (opt.sign == SignMethod::Winding)
            std::printf(" (%.2f s), %llu voxels signed from an ambiguous winding number", r.stats.windingSeconds,
                        static_cast<unsigned long long>(r.stats.ambiguousVoxels));
        std::printf("\n");
    }
    if (opt.sign != SignMethod::Winding)
        return;
    if (r.oriented && r.orient.ambiguousPatches)
        std::fprintf(stderr,
                     "mesh2sdf: warning: %zu open patches have no clear outside and keep the file's "
                     "orientation; %llu voxels were signed from a winding number between 0.25 and 0.75\n",
                     r.orient.ambiguousPatches, static_cast<unsigned long long>(r.stats.ambiguousVoxels));
    if (!r.surface)
        std::fprintf(stderr, "mesh2sdf: warning: no voxel of the band is inside the mesh, so the grid has no "
                             "surface (an open sheet, or a mesh whose inside could not be told)\n");
}

// Once the mesh is read: its health line, and a warning when the sign
// method assumes a closed mesh and this one is not.
void meshReady(const Options &opt, const JobResult &r)
{
    if (!opt.quiet && !opt.json)
        printHealth(opt.input, r);
    if (!r.health.closed() && opt.sign == SignMethod::Flood)
        std::fprintf(stderr,
                     "mesh2sdf: warning: the mesh is not closed (%zu boundary, %zu non-manifold edges) and --sign "
                     "flood assumes it is: inside and outside may be wrong; --sign winding handles open meshes\n",
                     r.health.boundaryEdges, r.health.nonManifoldEdges);
}

// One mesh, the command line's way: its lines on stdout, its failure as
// one line on stderr and exit status 1.
int convertOne(const Options &opt)
{
    Progress progress(!opt.quiet && !opt.json);
    const JobResult r = convertMesh(opt, progress, [&](const JobResult &ready) { meshReady(opt, ready); });
    if (!r.ok)
        return fail(r.error);
    report(opt, r);
    return 0;
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
    if (!opt.checkSign.empty()) {
        TriangleMesh mesh;
        if (!checkPointsFitMemory(opt.checkPoints, error) || !loadMesh(opt.input, mesh, error) ||
            !checkSign(mesh, opt.checkSign, opt.checkPoints, error))
            return fail(error);
        return 0;
    }
    if (opt.samples > 0 || !opt.queryOut.empty())
        return (opt.samples > 0 ? runSamples(opt, error) : runQuery(opt, error)) ? 0 : fail(error);

    return opt.batch.empty() ? convertOne(opt) : runBatch(opt);
}
