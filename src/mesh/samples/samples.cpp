// sdftrace — training samples (see samples.h).
#include "samples/samples.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>

namespace meshsdf
{

SampleCounts sampleCounts(size_t count, double uniformShare)
{
    SampleCounts c;
    c.uniform = std::min(count, size_t(std::floor(uniformShare * double(count) + 0.5)));
    const size_t near = count - c.uniform;
    c.near[0] = (near + 1) / 2;
    c.near[1] = near / 2;
    return c;
}

namespace
{

// One chunk's generator: uniforms in [0, 1) from the top 53 bits, Gaussians
// by Box–Muller, both from the mt19937_64 stream alone.
class ChunkRandom
{
  public:
    ChunkRandom(uint64_t seed, uint64_t chunk) : mBits(mix(seed * 0x9e3779b97f4a7c15ull + chunk)) {}

    double uniform() { return double(mBits() >> 11) * 0x1p-53; }

    // A standard normal value: a pair from two uniforms, the second kept.
    double gaussian()
    {
        if (mHasSpare) {
            mHasSpare = false;
            return mSpare;
        }
        const double u = 1.0 - uniform(), v = uniform(); // u in (0, 1]
        const double r = std::sqrt(-2.0 * std::log(u)), a = 6.283185307179586 * v;
        mSpare = r * std::sin(a);
        mHasSpare = true;
        return r * std::cos(a);
    }

  private:
    // SplitMix64's finalizer: neighbouring chunks get unrelated seeds.
    static uint64_t mix(uint64_t z)
    {
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    std::mt19937_64 mBits;
    double mSpare = 0;
    bool mHasSpare = false;
};

// The running sum of the triangles' areas, to pick one by area.
std::vector<double> areaSums(const TriangleMesh &mesh)
{
    std::vector<double> sums(mesh.triangles.size());
    double total = 0;
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto &tri = mesh.triangles[t];
        total += std::sqrt(doubleArea2(mesh.points[tri[0]], mesh.points[tri[1]], mesh.points[tri[2]]));
        sums[t] = total;
    }
    return sums;
}

// A point on the mesh: a triangle by area, then uniform barycentric
// coordinates (1 - sqrt(r1), sqrt(r1) (1 - r2), sqrt(r1) r2).
void surfacePoint(const TriangleMesh &mesh, const std::vector<double> &sums, ChunkRandom &random, double *p)
{
    const double at = random.uniform() * sums.back();
    const size_t t = std::min(size_t(std::upper_bound(sums.begin(), sums.end(), at) - sums.begin()), sums.size() - 1);
    const double s = std::sqrt(random.uniform()), r2 = random.uniform();
    const double wa = 1 - s, wb = s * (1 - r2), wc = s * r2;
    const auto &a = mesh.points[mesh.triangles[t][0]], &b = mesh.points[mesh.triangles[t][1]],
               &c = mesh.points[mesh.triangles[t][2]];
    for (int k = 0; k < 3; ++k)
        p[k] = wa * a[k] + wb * b[k] + wc * c[k];
}

} // namespace

void drawSamples(const TriangleMesh &mesh, const MeshSphere &sphere, const PointQuery &query,
                 const sdft_mesh_sample_params &p, float *rows, Progress &progress)
{
    const SampleCounts counts = sampleCounts(size_t(p.count), p.uniform_share);
    const size_t near = counts.near[0] + counts.near[1], n = size_t(p.count);
    const std::vector<double> sums = areaSums(mesh);
    const double sigma[2] = {p.near_sigma[0] * sphere.radius, p.near_sigma[1] * sphere.radius};
    // The points, chunk by chunk.
    std::vector<double> points(n * 3);
    const size_t chunks = (n + kSampleChunk - 1) / kSampleChunk;
    tbb::parallel_for(size_t(0), chunks, [&](size_t chunk) {
        ChunkRandom random(p.seed, chunk);
        for (size_t i = chunk * kSampleChunk; i < std::min(n, (chunk + 1) * kSampleChunk); ++i) {
            double *p = &points[i * 3];
            if (i < near) {
                surfacePoint(mesh, sums, random, p);
                for (int k = 0; k < 3; ++k)
                    p[k] += sigma[i % 2] * random.gaussian();
            } else {
                for (int k = 0; k < 3; ++k)
                    p[k] = sphere.centre[k] + sphere.radius * (2 * random.uniform() - 1);
            }
        }
    });
    // Each row's value is the same in any order; in Morton order each
    // search starts from the nearest triangle of the point before.
    const std::vector<size_t> order = mortonOrder(points, sphere);
    // Progress per block of rows evaluated (a cancelled one throws out).
    std::atomic<size_t> evaluated{0};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t> &r) {
        query.evaluate(points.data(), order.data(), r.begin(), r.end(), {true, false}, [&](size_t i, double d, double) {
            float *row = &rows[i * 4];
            for (int k = 0; k < 3; ++k)
                row[k] = float(points[i * 3 + k]);
            row[3] = float(d);
        });
        progress.report(int(100 * (evaluated += r.size()) / n));
    });
}

} // namespace meshsdf
