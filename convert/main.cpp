// mesh2sdf — a triangle mesh in, a signed distance grid out. See --help.
// Options, then the conversion (job.h) and what it found, printed: the
// health line once the mesh is read, the summary at the end. Every failure
// is one line on stderr and exit status 1, with no file left at a
// destination.
#include "batch.h"
#include "interrupt.h"
#include "job.h"
#include "options.h"
#include "points.h"
#include "text.h"

#include <cstdio>
#include <cstring>
#include <memory>
#include <new>
#include <vector>

#include "json.h"
#include "sdftrace/error.h"

using namespace mesh2sdf;

namespace
{

// The one line of a failure, and its exit status; an interrupted run's
// says so (the library's cancellation is how the interrupt stopped it).
// With --json, stdout gets the object a failed run answers with: the mesh
// and the error.
int fail(const Options &opt, const std::string &error)
{
    const std::string line = interruptSignal() ? interruptReason() + "; nothing was written" : error;
    if (opt.json) {
        std::printf("{\"mesh\": %s, \"status\": \"failed\", \"error\": %s}\n",
                    opt.input.empty() ? "null" : jsonString(opt.input).c_str(), jsonString(line).c_str());
        std::fflush(stdout);
    }
    std::fprintf(stderr, "mesh2sdf: %s\n", line.c_str());
    return interruptSignal() ? endInterrupted() : 1;
}

void printHealth(const std::string &path, const JobResult &r)
{
    std::vector<char> text(sdft_mesh_health_text(&r.health, nullptr, 0) + 1);
    sdft_mesh_health_text(&r.health, text.data(), text.size());
    std::printf("mesh %s: %s\n", path.c_str(), text.data());
}

// The --json object: the mesh's health, what orienting did, the grid.
void printJson(const Options &opt, const JobResult &r)
{
    const sdft_mesh_grid_stats &g = r.stats;
    std::printf("{\"mesh\": ");
    json_put_string(stdout, opt.input.c_str());
    std::printf(", \"status\": \"ok\", \"output\": ");
    json_put_string(stdout, opt.output.c_str());
    std::printf("%s", healthJsonFields(r).c_str());
    std::printf(", \"dims\": [%d, %d, %d], \"voxel_size\": %.9g, \"active_voxels\": %llu, \"sign\": \"%s\", "
                "\"ambiguous_voxels\": %llu, \"surface\": %s, \"read_seconds\": %.6f, \"orient_seconds\": %.6f, "
                "\"index_seconds\": %.6f, \"sweep_seconds\": %.6f, \"write_seconds\": %.6f, \"winding_seconds\": %.6f, "
                "\"seconds\": %.6f, \"peak_mib\": %.1f}\n",
                r.box.dims[0], r.box.dims[1], r.box.dims[2], r.box.voxel_size, (unsigned long long)g.active_voxels,
                settingChoice(SDFT_MESH_SETTINGS_GRID, "sign", opt.grid.sign).c_str(),
                (unsigned long long)g.ambiguous_voxels, g.surface ? "true" : "false", r.meshTimes.read_seconds,
                r.meshTimes.orient_seconds, r.gridTimes.index_seconds, r.gridTimes.seconds - r.gridTimes.index_seconds,
                r.writeSeconds, r.gridTimes.winding_seconds, r.seconds, peakMiB());
}

// The closing line, or with --json the object; then, on stderr, what stays
// uncertain: said, not written silently. The reader's doubts and the
// patches orienting left undecided come here too, at the end, not when the
// mesh is read: a run that fails prints its one line only.
void report(const Options &opt, const JobResult &r)
{
    const sdft_mesh_grid_stats &g = r.stats;
    if (opt.json) {
        printJson(opt, r);
    } else if (!opt.quiet) {
        std::printf("wrote %s: %dx%dx%d box, voxel size %.6g, %llu active voxels, grid %.1f MiB, peak memory "
                    "%.1f MiB, %.2f s, sign %s",
                    opt.output.c_str(), r.box.dims[0], r.box.dims[1], r.box.dims[2], r.box.voxel_size,
                    (unsigned long long)g.active_voxels, double(g.memory_bytes) / (1024.0 * 1024.0), peakMiB(),
                    r.seconds, settingChoice(SDFT_MESH_SETTINGS_GRID, "sign", opt.grid.sign).c_str());
        if (opt.grid.sign == SDFT_MESH_SIGN_WINDING)
            std::printf(" (%.2f s), %llu voxels signed from an ambiguous winding number", r.gridTimes.winding_seconds,
                        (unsigned long long)g.ambiguous_voxels);
        std::printf("\n");
    }
    for (const std::string &line : r.warnings)
        std::fprintf(stderr, "mesh2sdf: warning: %s\n", line.c_str());
    if (opt.grid.sign != SDFT_MESH_SIGN_WINDING)
        return;
    if (r.health.oriented && r.health.ambiguous_patches)
        std::fprintf(stderr,
                     "mesh2sdf: warning: %llu open patches have no clear outside and keep the file's orientation "
                     "(%.3g%% of the surface area: the sign near them follows the file's faces); %llu of the %llu "
                     "active voxels were signed from a winding number between 0.25 and 0.75\n",
                     (unsigned long long)r.health.ambiguous_patches, 100 * r.health.ambiguous_area,
                     (unsigned long long)g.ambiguous_voxels, (unsigned long long)g.active_voxels);
    if (!g.surface)
        std::fprintf(stderr, "mesh2sdf: warning: no voxel of the band is inside the mesh, so the grid has no "
                             "surface (an open sheet, or a mesh whose inside could not be told)\n");
}

// Once the mesh is read: its health line, and a warning when the sign
// method assumes a closed mesh and this one is not.
void meshReady(const Options &opt, const JobResult &r)
{
    if (!opt.quiet && !opt.json)
        printHealth(opt.input, r);
    if (!r.health.closed && opt.grid.sign == SDFT_MESH_SIGN_FLOOD)
        std::fprintf(stderr,
                     "mesh2sdf: warning: the mesh is not closed (%llu boundary, %llu non-manifold edges) and --sign "
                     "flood assumes it is: inside and outside may be wrong; --sign winding handles open meshes\n",
                     (unsigned long long)r.health.boundary_edges, (unsigned long long)r.health.non_manifold_edges);
}

// --check-sign: the truth is the mesh oriented as --orient says, the way a
// conversion with the same options orients it (outward by default: a grid
// converted from an inside-out file is judged against the inside, not the
// file's reversed faces); each grid's line names that orientation.
int checkSigns(const Options &opt)
{
    Options truth = opt;
    truth.mesh.normalize = 0;
    ProgressView progress(false);
    JobResult r;
    const MeshPtr mesh = loadJobMesh(truth, progress, 0, 100, r);
    if (!mesh)
        return fail(opt, r.error);
    std::vector<const char *> paths;
    for (const std::string &g : opt.checkSign)
        paths.push_back(g.c_str());
    std::vector<mesh_sign_counts> checks(paths.size());
    char msg[1024];
    if (mesh_sign_check(mesh.get(), paths.data(), paths.size(), opt.checkPoints, checks.data(), msg, sizeof msg) !=
        SDFT_OK)
        return fail(opt, msg);
    const std::string orient = settingChoice(SDFT_MESH_SETTINGS_MESH, "orient", opt.mesh.orient);
    if (opt.json)
        std::printf("{\"mesh\": %s, \"status\": \"ok\", \"orient\": \"%s\", \"grids\": [",
                    jsonString(opt.input).c_str(), orient.c_str());
    for (size_t i = 0; i < checks.size(); ++i) {
        const double fraction = checks[i].clear ? double(checks[i].wrong) / double(checks[i].clear) : 0.0;
        if (opt.json)
            std::printf("%s{\"grid\": %s, \"clear\": %llu, \"wrong\": %llu, \"wrong_fraction\": %.6f, "
                        "\"wrong_far\": %llu}",
                        i ? ", " : "", jsonString(paths[i]).c_str(), (unsigned long long)checks[i].clear,
                        (unsigned long long)checks[i].wrong, fraction, (unsigned long long)checks[i].wrong_far);
        else
            std::printf("%s clear=%llu wrong=%llu wrong_fraction=%.6f wrong_far=%llu orient=%s\n", paths[i],
                        (unsigned long long)checks[i].clear, (unsigned long long)checks[i].wrong, fraction,
                        (unsigned long long)checks[i].wrong_far, orient.c_str());
    }
    if (opt.json)
        std::printf("]}\n");
    return 0;
}

// One mesh, the command line's way: its lines on stdout, its failure as
// one line on stderr and exit status 1.
int convertOne(const Options &opt)
{
    ProgressView progress(!opt.quiet && !opt.json);
    const JobResult r = convertMesh(opt, progress, [&](const JobResult &ready) { meshReady(opt, ready); });
    if (!r.ok)
        return fail(opt, r.error);
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
        return fail(opt, error);
    }
    if (opt.help) {
        printHelp();
        return 0;
    }
    // The library answers out of memory with a code; what the program
    // allocates itself (rows, points, lists) is caught here, after the
    // files it reserved were removed on the way out.
    try {
        if (!opt.checkSign.empty())
            return checkSigns(opt); // writes nothing: Ctrl-C may end it as it is
        catchInterrupts();
        // What a killed run left beside the outputs (its temporary files);
        // a batch sweeps its folder once, itself.
        if (opt.batch.empty())
            for (const std::string &out : {opt.output, opt.nvdb, opt.npy, opt.samplesOut, opt.queryOut})
                sweepTemporaries(out);
        if (opt.samples() || !opt.queryOut.empty())
            return (opt.samples() ? runSamples(opt, error) : runQuery(opt, error)) ? 0 : fail(opt, error);
        return opt.batch.empty() ? convertOne(opt) : runBatch(opt);
    } catch (const std::bad_alloc &) {
        return fail(opt, "out of memory");
    }
}
