// sdftrace — the split every bounding volume hierarchy here uses (the
// winding tree, sign/winding.cpp, the dense grids' nearest-triangle tree,
// distance/nearest_triangle.cpp, and the points' wide tree,
// distance/wide_tree.cpp): at a centroid along the longest axis of the
// centroids' bounds, the median or a given position.
#ifndef SDFT_MESH_GEOMETRY_MEDIAN_SPLIT_H
#define SDFT_MESH_GEOMETRY_MEDIAN_SPLIT_H

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace meshsdf
{

/// Reorders order[first, first + count) so that its first `at` triangles
/// have centroids no further along the longest axis than the rest
/// (0 < at < count).
inline void splitAt(std::vector<uint32_t> &order, uint32_t first, uint32_t count, uint32_t at,
                    const std::vector<std::array<double, 3>> &centroids)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = first; i < first + count; ++i)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], centroids[order[i]][k]);
            hi[k] = std::max(hi[k], centroids[order[i]][k]);
        }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (hi[k] - lo[k] > hi[axis] - lo[axis])
            axis = k;
    std::nth_element(order.begin() + first, order.begin() + first + at, order.begin() + first + count,
                     [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
}

/// splitAt the median: returns count / 2.
inline uint32_t splitAtMedian(std::vector<uint32_t> &order, uint32_t first, uint32_t count,
                              const std::vector<std::array<double, 3>> &centroids)
{
    const uint32_t half = count / 2;
    splitAt(order, first, count, half, centroids);
    return half;
}

} // namespace meshsdf

#endif
