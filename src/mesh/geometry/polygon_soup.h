// sdftrace — what a mesh reader hands to the loader: the file's vertices and
// its faces as polygons on them, before triangulation and checks.
#ifndef SDFT_MESH_GEOMETRY_POLYGON_SOUP_H
#define SDFT_MESH_GEOMETRY_POLYGON_SOUP_H

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace meshsdf
{

struct PolygonSoup {
    std::vector<std::array<float, 3>> points;
    std::vector<uint32_t> corners; // every face's corners, face after face, indices into points
    std::vector<size_t> ends;      // where each face's corners end
    // Faces of the file the reader left out: malformed ones (a corner out of
    // range, fewer than three corners, a corner repeated), and zero-area ones
    // it could not hand over (an STL facet whose corners coincide).
    size_t skippedFaces = 0, degenerateFaces = 0;
    std::string warnings; // what the reader took with a doubt, one line each, '\n' after each

    void addPolygon(const uint32_t *first, size_t n)
    {
        corners.insert(corners.end(), first, first + n);
        ends.push_back(corners.size());
    }
};

} // namespace meshsdf

#endif
