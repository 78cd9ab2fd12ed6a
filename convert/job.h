// mesh2sdf — one mesh converted over the library (sdftrace/mesh.h): its
// outputs reserved, the mesh read and oriented, the grid built and every
// file renamed into place, or nothing left at any destination. Prints
// nothing and never exits: what happened comes back as a JobResult, for
// the command line (main.cpp) and a batch (batch.h) to report as they see
// fit.
#ifndef MESH2SDF_JOB_H
#define MESH2SDF_JOB_H

#include "options.h"
#include "progress_view.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "mesh_tool.h"
#include "sdftrace/mesh.h"

namespace mesh2sdf
{

/// What converting one mesh did. `error` is one line (no program name)
/// when !ok; the counts are filled as far as the conversion got.
struct JobResult {
    bool ok = false;
    std::string error;
    bool meshRead = false;             // the mesh's reports below describe it
    sdft_mesh_health health{};         // what the mesh held, what orienting did
    std::vector<std::string> warnings; // what taking it in did with a doubt, a line each (sdft_mesh_warnings)
    sdft_mesh_frame frame{};           // its box and sphere
    sdft_mesh_timings meshTimes{};     // reading and orienting
    bool gridBuilt = false;            // the grid's reports below describe the grid written
    sdft_mesh_grid_box box{};          // its box
    sdft_mesh_grid_stats stats{};      // voxel counts, surface, memory
    sdft_mesh_grid_timings gridTimes{};
    size_t samples = 0;               // training samples written (a batch's --formats samples)
    double writeSeconds = 0;          // writing the grid's files, wall clock
    double seconds = 0;               // the whole job, wall clock
    std::vector<std::string> outputs; // the files in place, in the order reserved
};

/// Frees a library handle when it goes out of scope.
struct MeshFree {
    void operator()(sdft_mesh *m) const { sdft_mesh_free(m); }
    void operator()(sdft_mesh_grid *g) const { sdft_mesh_grid_free(g); }
    void operator()(mesh_files *f) const { mesh_files_free(f); }
};
using MeshPtr = std::unique_ptr<sdft_mesh, MeshFree>;

/// Removes the temporary files a killed run left beside `path` (and beside
/// its sidecar, for an .npy): those of no running writer
/// (atomic_file_sweep). Nothing for an empty path.
void sweepTemporaries(const std::string &path);

/// The grid files a conversion writes: opt.output (.vdb), opt.nvdb, and
/// opt.npy with its sidecar JSON, each where given (a batch may leave out
/// the .vdb). A batch asks whether all of them exist before converting a
/// mesh again.
std::vector<std::string> jobOutputs(const Options &opt);

/// The grid files of `opt` reserved (mesh_files_reserve): none when
/// it names none. False with one line in `error`.
bool reserveGridFiles(const Options &opt, std::unique_ptr<mesh_files, MeshFree> &files, std::string &error);

/// opt.input read and oriented as `opt` says (--orient, --normalize,
/// --threads, --simd, --strict), on `progress` from `from` to `to` percent.
/// Fills its reports, r.warnings and r.meshRead, or r.error.
MeshPtr loadJobMesh(const Options &opt, ProgressView &progress, int from, int to, JobResult &r);

/// Converts `mesh` as `opt` says and writes it into `files` (reserved by
/// reserveGridFiles); fills the grid's reports, r.gridBuilt and r.outputs,
/// or r.error.
bool convertJobMesh(const Options &opt, const sdft_mesh *mesh, mesh_files *files, ProgressView &progress, JobResult &r);

/// The whole conversion of opt.input: reserveGridFiles, loadJobMesh, the
/// box planned (mesh_grid_plan), `meshReady` (if given: the command
/// line prints the health line then), convertJobMesh. Never throws: a failure (a missing, corrupt or empty
/// mesh, non-finite coordinates, an unwritable output, out of memory) is a
/// result with ok false and one line in error.
JobResult convertMesh(const Options &opt, ProgressView &progress,
                      const std::function<void(const JobResult &)> &meshReady = {});

/// The health report of a mesh that was read, as JSON fields after a comma
/// (", \"vertices\": ..."): mesh2sdf --json's and a batch report's
/// (sdft_mesh_health_json).
std::string healthJsonFields(const JobResult &r);

} // namespace mesh2sdf

#endif
