// mesh2sdf — one mesh converted (see job.h). Order of work: outputs
// reserved (an unwritable one fails before any work), mesh read and
// oriented, grid built, files written under temporary names and renamed
// into place together, each step a call into sdftrace/mesh.h.
#include "job.h"

#include "text.h"

#include <chrono>
#include <cstring>
#include <exception>
#include <new>

#include "atomic_file.h"
#include "seam.h"

namespace mesh2sdf
{

void sweepTemporaries(const std::string &path)
{
    if (path.empty())
        return;
    for (const std::string &file :
         {path, path.size() > 4 && path.compare(path.size() - 4, 4, ".npy") == 0 ? sidecarPath(path) : std::string()}) {
        if (file.empty())
            continue;
        const size_t slash = file.find_last_of('/');
        const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : file.substr(0, slash);
        atomic_file_sweep(dir.c_str(), file.c_str() + (slash == std::string::npos ? 0 : slash + 1), nullptr);
    }
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

bool reserveGridFiles(const Options &opt, std::unique_ptr<mesh_files, MeshFree> &files, std::string &error)
{
    std::vector<mesh_file> want;
    if (!opt.output.empty())
        want.push_back({opt.output.c_str(), SDFT_MESH_FORMAT_VDB});
    if (!opt.nvdb.empty())
        want.push_back({opt.nvdb.c_str(), SDFT_MESH_FORMAT_NVDB});
    if (!opt.npy.empty())
        want.push_back({opt.npy.c_str(), SDFT_MESH_FORMAT_NPY});
    files.reset();
    if (want.empty())
        return true;
    char msg[1024];
    mesh_files *reserved = nullptr;
    if (mesh_files_reserve(want.data(), want.size(), &reserved, msg, sizeof msg) != SDFT_OK) {
        error = msg;
        return false;
    }
    files.reset(reserved);
    return true;
}

MeshPtr loadJobMesh(const Options &opt, ProgressView &progress, int from, int to, JobResult &r)
{
    sdft_mesh_params p = opt.mesh;
    p.progress = ProgressView::report;
    p.stage = ProgressView::named;
    p.progress_user = &progress;
    progress.stage("reading", from, to);
    char msg[1024];
    sdft_mesh *mesh = nullptr;
    if (sdft_mesh_load(opt.input.c_str(), &p, &mesh, msg, sizeof msg) != SDFT_OK) {
        r.error = msg;
        return nullptr;
    }
    sdft_mesh_get_health(mesh, &r.health, nullptr, 0);
    sdft_mesh_get_frame(mesh, &r.frame, nullptr, 0);
    sdft_mesh_get_timings(mesh, &r.meshTimes, nullptr, 0);
    std::string warnings(sdft_mesh_warnings(mesh, nullptr, 0) + 1, '\0');
    sdft_mesh_warnings(mesh, &warnings[0], warnings.size());
    r.warnings.clear();
    for (size_t at = 0, end; (end = warnings.find('\n', at)) != std::string::npos; at = end + 1)
        r.warnings.push_back(warnings.substr(at, end - at));
    r.meshRead = true;
    return MeshPtr(mesh);
}

namespace
{

// The grid params of `opt`, reporting on `progress`.
sdft_mesh_grid_params gridParams(const Options &opt, ProgressView &progress)
{
    sdft_mesh_grid_params p = opt.grid;
    p.formats =
        (opt.nvdb.empty() ? 0u : (1u << SDFT_MESH_FORMAT_NVDB)) | (opt.npy.empty() ? 0u : (1u << SDFT_MESH_FORMAT_NPY));
    p.progress = ProgressView::report;
    p.stage = ProgressView::named;
    p.progress_user = &progress;
    return p;
}

} // namespace

bool convertJobMesh(const Options &opt, const sdft_mesh *mesh, mesh_files *files, ProgressView &progress, JobResult &r)
{
    const sdft_mesh_grid_params p = gridParams(opt, progress);
    // Writing has no progress of its own: the bar waits at its start and
    // is cleared once every file is in place.
    const int written = opt.grid.full ? 95 : 90;
    progress.stage("converting", 15, written);
    char msg[1024];
    sdft_mesh_grid *grid = nullptr;
    if (sdft_mesh_to_grid(mesh, &p, &grid, msg, sizeof msg) != SDFT_OK) {
        r.error = msg;
        return false;
    }
    const std::unique_ptr<sdft_mesh_grid, MeshFree> owned(grid);
    if (interruptSignal()) { // after the last progress report: nothing is written
        r.error = interruptReason();
        return false;
    }
    progress.stage("writing", written, 100);
    progress.show(0);
    const auto writeStart = std::chrono::steady_clock::now();
    if (files && mesh_files_write_grid(files, grid, opt.fp16, msg, sizeof msg) != SDFT_OK) {
        r.error = msg;
        return false;
    }
    r.writeSeconds = seam::secondsSince(writeStart);
    progress.show(1);
    sdft_mesh_grid_get_box(grid, &r.box, nullptr, 0);
    sdft_mesh_grid_get_stats(grid, &r.stats, nullptr, 0);
    sdft_mesh_grid_get_timings(grid, &r.gridTimes, nullptr, 0);
    r.gridBuilt = true;
    r.outputs = jobOutputs(opt);
    return true;
}

JobResult convertMesh(const Options &opt, ProgressView &progress,
                      const std::function<void(const JobResult &)> &meshReady)
{
    const auto start = std::chrono::steady_clock::now();
    JobResult r;
    try {
        std::unique_ptr<mesh_files, MeshFree> files;
        if (reserveGridFiles(opt, files, r.error)) {
            const MeshPtr mesh = loadJobMesh(opt, progress, 0, 15, r);
            // The box planned before the health line: a size that is
            // refused is the one line the run prints.
            const sdft_mesh_grid_params p = gridParams(opt, progress);
            sdft_mesh_grid_box planned;
            char msg[1024];
            if (mesh && mesh_grid_plan(mesh.get(), &p, &planned, msg, sizeof msg) != SDFT_OK)
                r.error = msg;
            else if (mesh) {
                progress.finish(); // the bar's line cleared for the health line
                if (meshReady)
                    meshReady(r);
                r.ok = convertJobMesh(opt, mesh.get(), files.get(), progress, r);
            }
        }
    } catch (const std::bad_alloc &) { // the program's own strings and lists
        r.ok = false;
        r.error = opt.input + ": out of memory";
    }
    progress.finish();
    r.seconds = seam::secondsSince(start);
    return r;
}

std::string healthJsonFields(const JobResult &r)
{
    std::string fields(sdft_mesh_health_json(&r.health, nullptr, 0) + 1, '\0');
    sdft_mesh_health_json(&r.health, &fields[0], fields.size());
    fields.pop_back();
    fields = ", " + fields + ", \"warnings\": [";
    for (size_t i = 0; i < r.warnings.size(); ++i)
        fields += (i ? ", " : "") + jsonString(r.warnings[i]);
    return fields + "]";
}

} // namespace mesh2sdf
