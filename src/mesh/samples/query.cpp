// sdftrace — signed distances at points (see query.h).
#include "samples/query.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>

#include <algorithm>

namespace meshsdf
{

PointQuery::PointQuery(const TriangleMesh &mesh, bool simd, WindingAccuracy accuracy) : mAccuracy(accuracy)
{
    tbb::parallel_invoke([&] { mDistance.reset(new WideTree(mesh, simd)); },
                         [&] { mWinding.reset(new FastWinding(mesh.points, mesh.triangles, simd)); });
}

namespace
{

// Spreads the low 21 bits of x to every third bit (a Morton code's axis).
uint64_t spread(uint64_t x)
{
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    return (x | x << 2) & 0x1249249249249249ull;
}

} // namespace

std::vector<size_t> mortonOrder(const std::vector<double> &xyz, const MeshSphere &cube)
{
    // One 64-bit key a point: its Morton code above its index, the code as
    // fine as the bits the index leaves (14 a coordinate for a million
    // points), so that the keys are distinct and sort as plain integers.
    const size_t n = xyz.size() / 3;
    int indexBits = 1;
    while (indexBits < 64 && (uint64_t(n) - 1) >> indexBits)
        ++indexBits;
    const int axisBits = std::min(21, (64 - indexBits) / 3);
    const double cells = double((uint64_t(1) << axisBits) - 1);
    static_assert(sizeof(size_t) == sizeof(uint64_t), "a key is a size_t, and becomes the order in place");
    std::vector<size_t> keys(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
            uint64_t code = 0;
            for (int k = 0; k < 3; ++k) {
                const double t = (xyz[i * 3 + k] - cube.centre[k]) / (2 * cube.radius) + 0.5;
                const double at = t >= 0 ? std::min(t, 1.0) : 0.0; // NaN too: a cast of NaN is undefined
                code |= spread(uint64_t(at * cells)) << k;
            }
            keys[i] = axisBits > 0 ? code << indexBits | i : i;
        }
    });
    tbb::parallel_sort(keys.begin(), keys.end());
    const uint64_t index = indexBits < 64 ? (uint64_t(1) << indexBits) - 1 : ~uint64_t(0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t j = r.begin(); j != r.end(); ++j)
            keys[j] &= index;
    });
    return keys;
}

} // namespace meshsdf
