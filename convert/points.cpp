// mesh2sdf --samples and --query (see points.h).
#include "points.h"

#include "mesh_tool.h"
#include "options.h"
#include "text.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "json.h"
#include "memory_limit.h"
#include "npy_read.h"
#include "npy_write.h"
#include "seam.h"

namespace mesh2sdf
{

namespace
{

using Clock = std::chrono::steady_clock;

bool writeArray(const char *tmp, const std::string &shape, const float *values, size_t count)
{
    FILE *f = std::fopen(tmp, "wb");
    if (!f)
        return false;
    bool ok = npy_write_header(f, shape.c_str()) == 0 && std::fwrite(values, sizeof(float), count, f) == count;
    return std::fclose(f) == 0 && ok;
}

// The file name of `path`.
std::string fileName(const std::string &path)
{
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

// One line in `error` from the library's message; false.
bool failed(const char *msg, std::string &error)
{
    error = msg;
    return false;
}

} // namespace

bool PointFiles::reserve(const std::string &npy, std::string &error)
{
    const std::string sidecar = sidecarPath(npy);
    const char *paths[2] = {npy.c_str(), sidecar.c_str()};
    char msg[1024];
    if (atomic_files_begin(mFiles, paths, 2, msg, sizeof msg) != SDFT_OK)
        return failed(msg, error);
    mReserved = true;
    return true;
}

bool PointFiles::discard()
{
    if (mReserved)
        atomic_files_abort(mFiles, 2);
    mReserved = false;
    return false;
}

bool PointFiles::write(const std::string &shape, const float *values, size_t count, std::vector<Member> members,
                       const Options &opt, const sdft_mesh_frame &frame, bool oriented, std::string &error)
{
    // The members of every sidecar after the caller's: the mesh's frame,
    // how to map the points back, the sign, the orientation, the source.
    members.insert(members.begin(), {"array", fileName(mFiles[0].path), false});
    members.push_back({"normalized", frame.normalized ? "true" : "false", true});
    members.push_back(
        {"centre", format("[%.17g, %.17g, %.17g]", frame.centre[0], frame.centre[1], frame.centre[2]), true});
    members.push_back({"radius", format("%.17g", frame.radius), true});
    if (frame.normalized)
        members.push_back({"to_mesh_units", "point * radius + centre; distance * radius", false});
    else
        members.push_back({"to_unit_sphere", "(point - centre) / radius; distance / radius", false});
    members.push_back({"sign", "negative inside: winding number > 0.5", false});
    members.push_back({"orient", settingChoice(SDFT_MESH_SETTINGS_MESH, "orient", oriented), false});
    members.push_back({"source_mesh", opt.input, false});
    std::vector<json_member> json;
    for (const Member &m : members)
        json.push_back({m.key.c_str(), m.value.c_str(), m.raw});
    char msg[1024];
    if (!writeArray(mFiles[0].tmp_path, shape, values, count)) {
        error = std::string("cannot write ") + mFiles[0].path + ": " + std::strerror(errno);
        return discard();
    }
    if (json_write_object(mFiles[1].tmp_path, json.data(), json.size(), msg, sizeof msg) != 0) {
        error = msg;
        return discard();
    }
    mReserved = false; // committed or removed, either way
    return atomic_files_commit(mFiles, 2, msg, sizeof msg) == SDFT_OK || failed(msg, error);
}

bool trainingSamplesFitMemory(size_t count, std::string &error)
{
    // Per row: the float32 row (16 bytes), the point and its distance bound
    // as doubles while drawing (32), its place in Morton order (8), and a
    // little for the order's keys (3,000,000 samples of spot: 206 MiB
    // measured, 212 estimated); 40 MiB besides.
    char line[256];
    const std::string what = std::to_string(count) + " training samples";
    if (memory_check(40.0 * 1024 * 1024 + 60.0 * double(count), what.c_str(), line, sizeof line) == 0)
        return true;
    error = line;
    return false;
}

bool writeSamples(const Options &opt, const sdft_mesh *mesh, PointFiles &files, ProgressView &progress, SampleRun &run,
                  std::string &error)
{
    sdft_mesh_sample_params p = opt.sample;
    p.progress = ProgressView::report;
    p.stage = ProgressView::named;
    p.progress_user = &progress;
    const size_t count = size_t(p.count);
    std::vector<float> rows(count * 4);
    char msg[1024];
    sdft_mesh_timings before;
    sdft_mesh_get_timings(mesh, &before, nullptr, 0);
    const auto t0 = Clock::now();
    if (sdft_mesh_samples(mesh, &p, rows.data(), rows.size(), msg, sizeof msg) != SDFT_OK)
        return failed(msg, error);
    const double seconds = seam::secondsSince(t0);
    if (interruptSignal())
        return failed("interrupted", error);
    sdft_mesh_timings after;
    sdft_mesh_get_timings(mesh, &after, nullptr, 0);
    run.indexSeconds = after.index_seconds - before.index_seconds; // built by this call, or before it
    run.sampleSeconds = seconds - run.indexSeconds;
    mesh_sample_counts(&p, &run.near[0], &run.near[1], &run.uniform);
    const std::vector<PointFiles::Member> members = {
        {"dtype", "float32", false},
        {"shape", format("[%zu, 4]", count), true},
        {"columns", "[\"x\", \"y\", \"z\", \"distance\"]", true},
        {"rows", "near the surface first, alternating the two sigmas, then uniform", false},
        {"near_samples", format("[%zu, %zu]", run.near[0], run.near[1]), true},
        {"uniform_samples", format("%zu", run.uniform), true},
        {"near_sigma", format("[%.17g, %.17g]", p.near_sigma[0], p.near_sigma[1]), true},
        {"near_sigma_units", "times the sphere's radius", false},
        {"uniform_share", format("%.17g", p.uniform_share), true},
        {"uniform_region", "centre +- radius on each axis", false},
        {"seed", format("%llu", (unsigned long long)p.seed), true},
    };
    sdft_mesh_frame frame;
    sdft_mesh_health health;
    sdft_mesh_get_frame(mesh, &frame, nullptr, 0);
    sdft_mesh_get_health(mesh, &health, nullptr, 0);
    const auto writeStart = Clock::now();
    const bool ok = files.write("(" + std::to_string(count) + ", 4)", rows.data(), rows.size(), members, opt, frame,
                                health.oriented, error);
    run.writeSeconds = seam::secondsSince(writeStart);
    return ok;
}

bool runSamples(const Options &opt, std::string &error)
{
    const auto t0 = Clock::now();
    PointFiles files;
    const size_t count = size_t(opt.sample.count);
    if (!trainingSamplesFitMemory(count, error) || !files.reserve(opt.samplesOut, error))
        return false;
    ProgressView progress(!opt.quiet && !opt.json);
    JobResult r;
    const MeshPtr mesh = loadJobMesh(opt, progress, 0, 30, r);
    if (!mesh)
        return failed(r.error.c_str(), error);
    SampleRun run;
    progress.stage("samples", 30, 100);
    const bool ok = !interruptSignal() && writeSamples(opt, mesh.get(), files, progress, run, error);
    progress.finish();
    if (!ok)
        return false;
    const double seconds = seam::secondsSince(t0);
    const double rate = double(count) / run.sampleSeconds;
    if (opt.json) {
        std::printf("{\"mesh\": ");
        json_put_string(stdout, opt.input.c_str());
        std::printf(", \"output\": ");
        json_put_string(stdout, opt.samplesOut.c_str());
        std::printf(
            ", \"samples\": %zu, \"near_samples\": [%zu, %zu], \"uniform_samples\": %zu, \"triangles\": %llu, "
            "\"normalized\": %s, \"read_seconds\": %.6f, \"orient_seconds\": %.6f, \"index_seconds\": %.6f, "
            "\"samples_seconds\": %.6f, \"write_seconds\": %.6f, \"samples_per_second\": %.0f, \"seconds\": %.6f, "
            "\"peak_mib\": %.1f}\n",
            count, run.near[0], run.near[1], run.uniform, (unsigned long long)r.health.triangles,
            opt.mesh.normalize ? "true" : "false", r.meshTimes.read_seconds, r.meshTimes.orient_seconds,
            run.indexSeconds, run.sampleSeconds, run.writeSeconds, rate, seconds, peakMiB());
    } else if (!opt.quiet) {
        std::printf("wrote %s: %zu samples, %.2f s, sampling %.3f s (%.0f samples/s)\n", opt.samplesOut.c_str(), count,
                    seconds, run.sampleSeconds, rate);
    }
    return true;
}

bool runQuery(const Options &opt, std::string &error)
{
    const auto t0 = Clock::now();
    PointFiles files;
    if (!files.reserve(opt.queryOut, error))
        return false;
    char why[1024];
    double *values = nullptr;
    size_t count = 0;
    if (npy_read_rows(opt.queryIn.c_str(), 3, &values, &count, why, sizeof why) != 0)
        return failed(why, error);
    const std::vector<double> xyz(values, values + count * 3);
    std::free(values);
    ProgressView progress(!opt.quiet && !opt.json);
    JobResult r;
    const MeshPtr mesh = loadJobMesh(opt, progress, 0, 50, r);
    if (!mesh)
        return failed(r.error.c_str(), error);
    const size_t columns = opt.winding ? 2 : 1;
    std::vector<float> distance(count), winding(opt.winding ? count : 0);
    sdft_mesh_points pts{};
    pts.data = xyz.data();
    pts.type = SDFT_MESH_FLOAT64;
    pts.count = count;
    sdft_mesh_query_params q = sdft_mesh_query_params_defaults();
    q.progress = ProgressView::report; // Ctrl-C stops it too
    q.progress_user = &progress;
    progress.stage("points", 50, 100);
    char msg[1024];
    const auto t1 = Clock::now();
    if (sdft_mesh_signed_distance(mesh.get(), &pts, distance.data(), opt.winding ? winding.data() : nullptr, &q, msg,
                                  sizeof msg) != SDFT_OK)
        return failed(msg, error); // the files are removed on the way out
    progress.finish();
    const double querySeconds = seam::secondsSince(t1);
    std::vector<float> out(count * columns);
    for (size_t i = 0; i < count; ++i) {
        out[i * columns] = distance[i];
        if (opt.winding)
            out[i * columns + 1] = winding[i];
    }
    const std::string shape = "(" + std::to_string(count) + (opt.winding ? ", 2)" : ",)");
    const std::vector<PointFiles::Member> members = {
        {"points", opt.queryIn, false},
        {"dtype", "float32", false},
        {"shape", format("[%zu%s]", count, opt.winding ? ", 2" : ""), true},
        {"columns", opt.winding ? "[\"distance\", \"winding\"]" : "[\"distance\"]", true},
    };
    if (!files.write(shape, out.data(), out.size(), members, opt, r.frame, r.health.oriented, error))
        return false;
    const double seconds = seam::secondsSince(t0);
    if (opt.json) {
        std::printf("{\"mesh\": ");
        json_put_string(stdout, opt.input.c_str());
        std::printf(", \"points\": ");
        json_put_string(stdout, opt.queryIn.c_str());
        std::printf(", \"output\": ");
        json_put_string(stdout, opt.queryOut.c_str());
        std::printf(", \"count\": %zu, \"triangles\": %llu, \"orient_seconds\": %.6f, \"query_seconds\": %.6f, "
                    "\"points_per_second\": %.0f, \"seconds\": %.6f, \"peak_mib\": %.1f}\n",
                    count, (unsigned long long)r.health.triangles, r.meshTimes.orient_seconds, querySeconds,
                    double(count) / querySeconds, seconds, peakMiB());
    } else if (!opt.quiet) {
        std::printf("wrote %s: %zu signed distances%s, %.2f s, queries %.3f s (%.0f points/s)\n", opt.queryOut.c_str(),
                    count, opt.winding ? " and winding numbers" : "", seconds, querySeconds,
                    double(count) / querySeconds);
    }
    return true;
}

} // namespace mesh2sdf
