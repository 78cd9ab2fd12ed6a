// mesh2sdf --samples: training samples as DeepSDF's preprocessing draws
// them (Park et al. 2019; PreprocessMesh.cpp), for networks that learn a
// signed distance: most points on the surface, at area-weighted random
// triangles with uniform barycentric coordinates, moved off it by a
// Gaussian of one of two standard deviations, half each; the rest uniform
// in the cube around the mesh's sphere (unit_sphere.h). Each point's
// distance is exact to the triangles and its sign the winding number's
// (query.h).
//
// Rows: the near points first, alternating the two sigmas (the first
// sigma on even rows), then the uniform ones, as DeepSDF writes them.
// Reproducible: rows are drawn in fixed chunks of kSampleChunk, each from
// its own generator seeded by the seed and the chunk's index, so any
// thread count gives the same bytes. The generator is std::mt19937_64,
// whose output the C++ standard fixes; uniforms and Gaussians (Box–Muller)
// are made from it here, not by the standard library's distributions,
// whose algorithms differ between libraries.
#ifndef MESH2SDF_SAMPLES_H
#define MESH2SDF_SAMPLES_H

#include "options.h"
#include "query.h"

#include <string>
#include <vector>

namespace mesh2sdf
{

/// Rows drawn from one generator.
constexpr size_t kSampleChunk = 4096;

/// How many rows of each kind (--samples N, --uniform-share S): round(S N)
/// uniform, the rest near, the first sigma's ceil(near / 2).
struct SampleCounts {
    size_t near[2] = {0, 0};
    size_t uniform = 0;
};
SampleCounts sampleCounts(size_t count, double uniformShare);

/// `opt.samples` rows (x, y, z, d) in `rows` (4 floats each) over `mesh`
/// in its frame, whose sphere there is `sphere`: sigmas are
/// opt.nearSigma times its radius, the uniform cube is its centre plus or
/// minus its radius. Runs in parallel.
void drawSamples(const TriangleMesh &mesh, const MeshSphere &sphere, const PointQuery &query, const Options &opt,
                 std::vector<float> &rows);

/// What drawing samples took, for the summary line, --json and a batch's row.
struct SampleRun {
    size_t triangles = 0;
    double orientSeconds = 0, indexSeconds = 0, sampleSeconds = 0, seconds = 0;
};

/// opt.samples rows for opt.input into opt.samplesOut and its OUT.json:
/// reads, orients, draws and writes (each file through a temporary one,
/// both or neither). Prints nothing; false with one line in `error`.
bool sampleMesh(const Options &opt, SampleRun &run, std::string &error);

/// mesh2sdf MESH --samples N OUT.npy: sampleMesh, then the summary line or
/// the --json object with the sampling's time apart.
bool runSamples(const Options &opt, std::string &error);

} // namespace mesh2sdf

#endif
