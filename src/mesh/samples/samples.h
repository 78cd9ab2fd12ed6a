// sdftrace — training samples as DeepSDF's preprocessing draws
// them (Park et al. 2019; PreprocessMesh.cpp), for networks that learn a
// signed distance: most points on the surface, at area-weighted random
// triangles with uniform barycentric coordinates, moved off it by a
// Gaussian of one of two standard deviations, half each; the rest uniform
// in the cube around the mesh's sphere (geometry/unit_sphere.h). Each point's
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
#ifndef SDFT_MESH_SAMPLES_SAMPLES_H
#define SDFT_MESH_SAMPLES_SAMPLES_H

#include "progress/progress.h"
#include "samples/query.h"
#include "sdftrace/mesh.h"

#include <string>
#include <vector>

namespace meshsdf
{

/// Most training samples one draw makes: 1.6 GB of rows.
constexpr double kMaxSamples = SDFT_MESH_MAX_SAMPLES;

/// Rows drawn from one generator.
constexpr size_t kSampleChunk = 4096;

/// How many rows of each kind (--samples N, --uniform-share S): round(S N)
/// uniform, the rest near, the first sigma's ceil(near / 2).
struct SampleCounts {
    size_t near[2] = {0, 0};
    size_t uniform = 0;
};
SampleCounts sampleCounts(size_t count, double uniformShare);

/// `p.count` rows (x, y, z, d) into `rows` (4 floats each) over `mesh`
/// in its frame, whose sphere there is `sphere`: sigmas are
/// p.near_sigma times its radius, the uniform cube is its centre plus or
/// minus its radius. Runs in parallel, reporting the rows evaluated on
/// `progress` (which throws Cancelled out of it when told to stop).
void drawSamples(const TriangleMesh &mesh, const MeshSphere &sphere, const PointQuery &query,
                 const sdft_mesh_sample_params &p, float *rows, Progress &progress);

} // namespace meshsdf

#endif
