// sdftrace — what a mesh reader hands to the loader: the file's vertices and
// its faces as polygons on them, before triangulation and checks.
#ifndef SDFT_MESH_GEOMETRY_POLYGON_SOUP_H
#define SDFT_MESH_GEOMETRY_POLYGON_SOUP_H

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace meshsdf
{

struct PolygonSoup {
    std::vector<std::array<float, 3>> points;
    std::vector<uint32_t> corners; // every face's corners, face after face, indices into points
    std::vector<size_t> ends;      // where each face's corners end

    void addPolygon(const uint32_t *first, size_t n)
    {
        corners.insert(corners.end(), first, first + n);
        ends.push_back(corners.size());
    }
};

} // namespace meshsdf

#endif
