// sdftrace — the exact narrow band (see band.h).
//
// Each triangle is binned to every block that has a voxel within the
// half-width r of it, tested conservatively: the block's centre lies within
// r + (half the block's diagonal) of the triangle. Each block then takes, at
// each voxel, the minimum distance over its triangles. Why that is the band,
// exactly: if a voxel v has d(v) < r, the triangle T it is nearest to was
// binned to v's block, so v's minimum is at most dist(v, T) = d(v); and it
// is never below d(v), being a minimum of true distances. A voxel with no
// triangle within r keeps +inf. So a triangle may lower more voxels of its
// blocks than those within r of it, and does: it takes the distances of
// whole rows of four voxels along z at once (packet_rows.h, with AVX2 where
// the processor has it).
#include "distance/band.h"

#include "distance/packet_rows.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <vector>

namespace meshsdf
{

namespace
{

// A block is keyed by its index (voxel index >> 3) per axis, offset to be
// non-negative, 21 bits each; sorting by key groups a block's triangles.
constexpr int kKeyBits = 21;
constexpr int kKeyOffset = 1 << (kKeyBits - 1);
constexpr uint64_t kKeyMask = (uint64_t(1) << kKeyBits) - 1;

uint64_t blockKey(int bx, int by, int bz)
{
    return (uint64_t(bx + kKeyOffset) << (2 * kKeyBits)) | (uint64_t(by + kKeyOffset) << kKeyBits) |
           uint64_t(bz + kKeyOffset);
}

std::array<int, 3> blockOrigin(uint64_t key)
{
    return {(int((key >> (2 * kKeyBits)) & kKeyMask) - kKeyOffset) * kBlockDim,
            (int((key >> kKeyBits) & kKeyMask) - kKeyOffset) * kBlockDim,
            (int(key & kKeyMask) - kKeyOffset) * kBlockDim};
}

struct Binned {
    uint64_t block;
    uint32_t triangle;
    bool operator<(const Binned &o) const { return block != o.block ? block < o.block : triangle < o.triangle; }
};

// A triangle in index space (voxel centres at integer coordinates) with the
// voxels its r-neighbourhood can reach.
struct IndexTriangle {
    PreparedTriangle prepared;
    int lo[3], hi[3]; // inclusive voxel range of the bounding box grown by r
};

IndexTriangle indexTriangle(const TriangleMesh &mesh, size_t t, const std::array<double, 3> &origin, double voxelSize,
                            double r)
{
    IndexTriangle it;
    double c[9];
    for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 3; ++k)
            c[v * 3 + k] = (double(mesh.points[mesh.triangles[t][v]][k]) - origin[k]) / voxelSize;
    it.prepared = prepareTriangle(c, c + 3, c + 6);
    for (int k = 0; k < 3; ++k) {
        const double lo = std::min({c[k], c[3 + k], c[6 + k]});
        const double hi = std::max({c[k], c[3 + k], c[6 + k]});
        it.lo[k] = int(std::ceil(lo - r));
        it.hi[k] = int(std::floor(hi + r));
    }
    return it;
}

// Lowers d2[] (squared distances in voxels, OpenVDB's leaf order) of the
// block at `origin` to the triangle's, in rows of four voxels along z that
// hold a voxel within r of it. A row whose four voxels all lie farther than
// r from the triangle's plane, on one side, is skipped: they are farther
// than r from the triangle too. (A triangle without a reliable normal,
// packet_rows.h, has normal 0 and skips no row.)
template <class Rows>
void lowerByTriangle(const IndexTriangle &t, const std::array<int, 3> &origin, double r2, const double *z, double *d2)
{
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = std::max(t.lo[k], origin[k]) - origin[k];
        hi[k] = std::min(t.hi[k], origin[k] + kBlockDim - 1) - origin[k];
        if (lo[k] > hi[k])
            return;
    }
    const double *n = t.prepared.normal, *a = t.prepared.corner[0];
    const double offset = n[0] * a[0] + n[1] * a[1] + n[2] * a[2];
    // Plane test with a relative margin, so that rounding never skips a voxel
    // of the band.
    const double slab = std::sqrt(r2) * (1 + 1e-6);
    for (int x = lo[0]; x <= hi[0]; ++x)
        for (int y = lo[1]; y <= hi[1]; ++y) {
            const double px = origin[0] + x, py = origin[1] + y;
            const double rowPlane = n[0] * px + n[1] * py - offset;
            double *row = d2 + ((x << kBlockLog2) + y) * kBlockDim;
            for (int c = lo[2] & ~3; c <= hi[2]; c += 4) {
                const double first = rowPlane + n[2] * z[c], last = rowPlane + n[2] * z[c + 3];
                if ((first > slab && last > slab) || (first < -slab && last < -slab))
                    continue;
                alignas(32) double d[4];
                Rows::distances(t.prepared, px, py, z + c, d);
                Rows::lower(d, row + c);
            }
        }
}

// The distances of the block at `origin` from its binned triangles
// entries[first, last) (squared, in voxels, at most r2).
template <class Rows>
void lowerBlock(const std::vector<IndexTriangle> &tris, const std::vector<Binned> &entries, size_t first, size_t last,
                const std::array<int, 3> &origin, double r2, double *d2)
{
    alignas(32) double z[kBlockDim];
    for (int c = 0; c < kBlockDim; ++c)
        z[c] = origin[2] + c;
    std::fill(d2, d2 + kBlockSize, r2);
    for (size_t i = first; i < last; ++i)
        lowerByTriangle<Rows>(tris[entries[i].triangle], origin, r2, z, d2);
}

#ifdef SDFT_MESH_ROWS_AVX2
// lowerBlock compiled for AVX2 and FMA, everything it calls inlined.
__attribute__((target("avx2,fma"), flatten)) void lowerBlockAvx2(const std::vector<IndexTriangle> &tris,
                                                                 const std::vector<Binned> &entries, size_t first,
                                                                 size_t last, const std::array<int, 3> &origin,
                                                                 double r2, double *d2)
{
    lowerBlock<Avx2Rows>(tris, entries, first, last, origin, r2, d2);
}
#endif

} // namespace

void exactBand(const TriangleMesh &mesh, const std::array<double, 3> &origin, double voxelSize, double halfWidth,
               const BandBlockSink &sink, const std::function<void(int)> &progress, bool simd)
{
    const bool vectorized = simd && rowsVectorizable();
    const size_t count = mesh.triangles.size();
    const double r = halfWidth, r2 = r * r;
    std::vector<IndexTriangle> tris(count);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1024), [&](const tbb::blocked_range<size_t> &range) {
        for (size_t t = range.begin(); t != range.end(); ++t)
            tris[t] = indexTriangle(mesh, t, origin, voxelSize, r);
    });

    // Bin: (block, triangle) for every block with a voxel possibly within r.
    const double reach = r + 0.5 * (kBlockDim - 1) * std::sqrt(3.0);
    tbb::enumerable_thread_specific<std::vector<Binned>> perThread;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t> &range) {
        std::vector<Binned> &out = perThread.local();
        for (size_t t = range.begin(); t != range.end(); ++t) {
            const IndexTriangle &it = tris[t];
            int blo[3], bhi[3];
            for (int k = 0; k < 3; ++k) {
                blo[k] = it.lo[k] >> kBlockLog2; // arithmetic shift: floor for negatives too
                bhi[k] = it.hi[k] >> kBlockLog2;
            }
            for (int bx = blo[0]; bx <= bhi[0]; ++bx)
                for (int by = blo[1]; by <= bhi[1]; ++by)
                    for (int bz = blo[2]; bz <= bhi[2]; ++bz) {
                        const double centre[3] = {bx * kBlockDim + 0.5 * (kBlockDim - 1),
                                                  by * kBlockDim + 0.5 * (kBlockDim - 1),
                                                  bz * kBlockDim + 0.5 * (kBlockDim - 1)};
                        if (preparedDistance2(it.prepared, centre) < reach * reach)
                            out.push_back({blockKey(bx, by, bz), uint32_t(t)});
                    }
        }
    });
    std::vector<Binned> binned;
    for (const auto &part : perThread)
        binned.insert(binned.end(), part.begin(), part.end());
    perThread.clear();
    tbb::parallel_sort(binned.begin(), binned.end());
    std::vector<size_t> starts; // first entry of each block, and the end
    for (size_t i = 0; i < binned.size(); ++i)
        if (i == 0 || binned[i].block != binned[i - 1].block)
            starts.push_back(i);
    starts.push_back(binned.size());

    const size_t blocks = starts.size() - 1;
    const float limit = float(halfWidth * voxelSize);
    std::atomic<size_t> done{0};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks, 16), [&](const tbb::blocked_range<size_t> &range) {
        alignas(32) double d2[kBlockSize];
        float distance[kBlockSize];
        for (size_t b = range.begin(); b != range.end(); ++b) {
            const std::array<int, 3> at = blockOrigin(binned[starts[b]].block);
#ifdef SDFT_MESH_ROWS_AVX2
            if (vectorized)
                lowerBlockAvx2(tris, binned, starts[b], starts[b + 1], at, r2, d2);
            else
#endif
                lowerBlock<ScalarRows>(tris, binned, starts[b], starts[b + 1], at, r2, d2);
            bool any = false;
            for (int v = 0; v < kBlockSize; ++v) {
                const float d = float(std::sqrt(d2[v]) * voxelSize);
                distance[v] = d < limit ? d : INFINITY;
                any = any || d < limit;
            }
            if (any)
                sink(at, distance);
        }
        const size_t d = done.fetch_add(range.size()) + range.size();
        if (progress)
            progress(int(100.0 * double(d) / double(blocks)));
    });
}

} // namespace meshsdf
