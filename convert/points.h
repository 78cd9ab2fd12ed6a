// mesh2sdf --samples and --query: training samples and signed distances at
// given points, computed by the library (sdft_mesh_samples,
// sdft_mesh_signed_distance) and written as OUT.npy with OUT.json beside
// it, which says what the rows are and the frame they are in.
#ifndef MESH2SDF_POINTS_H
#define MESH2SDF_POINTS_H

#include "job.h"
#include "options.h"

#include <string>
#include <vector>

#include "atomic_file.h"

namespace mesh2sdf
{

/// OUT.npy and OUT.json of --samples and --query: reserved before any work
/// and renamed into place together at the end, or removed
/// (src/common/atomic_file.h's sets); the JSON through the one sidecar
/// writer (src/common/json.h).
class PointFiles
{
  public:
    /// A member of the sidecar: its value JSON text when `raw`, else a
    /// string.
    struct Member {
        std::string key, value;
        bool raw;
    };

    PointFiles() = default;
    PointFiles(const PointFiles &) = delete;
    PointFiles &operator=(const PointFiles &) = delete;
    ~PointFiles() { discard(); }

    bool reserve(const std::string &npy, std::string &error);
    /// The float32 array of `shape` ("(n, 4)") and the sidecar: "array"
    /// (the array's file name), `members`, then the mesh's frame: whether
    /// the points are normalized, the sphere, how to map a point and a
    /// distance back, the sign, the orientation and the source mesh. On
    /// failure, removes both.
    bool write(const std::string &shape, const float *values, size_t count, std::vector<Member> members,
               const Options &opt, const sdft_mesh_frame &frame, bool oriented, std::string &error);
    /// Removes both temporary files; returns false.
    bool discard();

  private:
    atomic_file mFiles[2]{}; // the array, its sidecar
    bool mReserved = false;
};

/// What drawing samples took and made, for the summary line, --json and
/// the sidecar.
struct SampleRun {
    double indexSeconds = 0, sampleSeconds = 0, writeSeconds = 0;
    size_t near[2] = {0, 0}, uniform = 0; // rows of each kind (mesh_sample_counts)
};

/// The memory `count` training samples need, checked before any work:
/// false with one line ("needs ~...") when it does not fit.
bool trainingSamplesFitMemory(size_t count, std::string &error);

/// opt.samples rows of `mesh` written into `files` (reserved for
/// opt.samplesOut), drawn on `progress`. False with one line in `error`.
bool writeSamples(const Options &opt, const sdft_mesh *mesh, PointFiles &files, ProgressView &progress, SampleRun &run,
                  std::string &error);

/// mesh2sdf MESH --samples N OUT.npy: reserves, reads, draws and writes,
/// then prints the summary line or the --json object.
bool runSamples(const Options &opt, std::string &error);

/// mesh2sdf MESH --query POINTS.npy OUT.npy [--winding] [--normalize]:
/// reads the points, evaluates them, writes OUT.npy and OUT.json and
/// prints the summary line or --json object.
bool runQuery(const Options &opt, std::string &error);

} // namespace mesh2sdf

#endif
