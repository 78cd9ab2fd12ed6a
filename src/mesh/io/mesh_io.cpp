// sdftrace — reading a mesh file (see mesh_io.h): the extension picks the
// reader, every reader hands over a polygon soup, and the soup is
// triangulated and checked here the same way for all.
#include "io/mesh_io.h"

#include "io/assimp_read.h"
#include "io/obj_read.h"
#include "io/openmesh_read.h"
#include "io/ply_read.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sys/stat.h>

namespace meshsdf
{

namespace
{

std::string lowerExtension(const std::string &path)
{
    const size_t dot = path.find_last_of('.');
    const size_t slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
        return "";
    std::string ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// Whether a coordinate is one no model has: beyond kAbsurdCoordinate, or
// subnormal (below float's smallest normal number and not zero: the
// integers and pointers a reader that read past its data turns into
// floats look so).
bool absurd(float x)
{
    const float m = std::abs(x);
    return m > kAbsurdCoordinate || (m > 0 && m < std::numeric_limits<float>::min());
}

// The soup's polygons as fans of triangles, zero-area ones skipped and
// counted, the box and the welding: the loader's checks, the same for every
// reader. Corner indices are within soup.points (each reader's promise).
bool finishMesh(const std::string &path, PolygonSoup &soup, TriangleMesh &mesh, std::string &error)
{
    mesh = TriangleMesh{};
    mesh.points = std::move(soup.points);
    mesh.health.vertices = mesh.points.size();
    for (size_t v = 0; v < mesh.points.size(); ++v) {
        const auto &p = mesh.points[v];
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
            error = "mesh has a non-finite coordinate (vertex " + std::to_string(v) + "): " + path;
            return false;
        }
        for (int k = 0; k < 3; ++k)
            if (absurd(p[k])) {
                char value[32];
                std::snprintf(value, sizeof value, "%.3g", double(p[k]));
                error = "mesh has a coordinate of absurd size (vertex " + std::to_string(v) + ": " + value +
                        "; garbage from a broken file or reader?): " + path;
                return false;
            }
    }
    mesh.health.skippedFaces = soup.skippedFaces;
    mesh.health.faces = mesh.health.degenerateFaces = soup.degenerateFaces;
    for (size_t f = 0, begin = 0; f < soup.ends.size(); begin = soup.ends[f++]) {
        const uint32_t *corners = soup.corners.data() + begin;
        const size_t n = soup.ends[f] - begin;
        if (!isPolygon(corners, n)) {
            ++mesh.health.skippedFaces;
            continue;
        }
        ++mesh.health.faces;
        for (size_t k = 1; k + 1 < n; ++k) {
            const std::array<uint32_t, 3> t{corners[0], corners[k], corners[k + 1]};
            if (doubleArea2(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]) <= 0.0) {
                ++mesh.health.degenerateFaces;
                continue;
            }
            mesh.triangles.push_back(t);
        }
    }
    if (mesh.health.faces == 0) {
        error = "mesh has no faces: " + path;
        return false;
    }
    mesh.health.triangles = mesh.triangles.size();
    if (mesh.triangles.empty()) {
        error = "mesh has no non-degenerate triangles: " + path;
        return false;
    }
    if (!finishTriangles(mesh)) {
        error = "mesh bounding box has zero size: " + path;
        return false;
    }
    return true;
}

} // namespace

// True if the n corners are a polygon: three or more, all distinct.
// OpenMesh's importer refuses the others, and every reader is held to that.
// A long polygon is checked sorted, so that a face of a million corners
// costs n log n, not n^2.
bool isPolygon(const uint32_t *corners, size_t n)
{
    if (n < 3)
        return false;
    if (n <= 16) {
        for (size_t i = 0; i < n; ++i)
            for (size_t j = i + 1; j < n; ++j)
                if (corners[i] == corners[j])
                    return false;
        return true;
    }
    std::vector<uint32_t> sorted(corners, corners + n);
    std::sort(sorted.begin(), sorted.end());
    return std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
}

bool isMeshExtension(const std::string &path)
{
    const std::string ext = lowerExtension(path);
    return ext == "obj" || ext == "ply" || ext == "off" || ext == "stl" || ext == "om" || isAssimpExtension(ext);
}

bool loadMesh(const std::string &path, TriangleMesh &mesh, std::string &error, std::vector<std::string> *warnings)
{
    const std::string ext = lowerExtension(path);
    struct stat st;
    if (stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
        error = "mesh is a folder, not a file: " + path;
        return false;
    }
    if (!isMeshExtension(path)) {
        std::string known = std::string("obj ply off stl om ") + kAssimpExtensions;
        for (size_t at = 0; (at = known.find(' ', at)) != std::string::npos; at += 2)
            known.replace(at, 1, " .");
        error = "unknown mesh extension '" + ext + "' (use ." + known + "): " + path;
        return false;
    }
    if (!std::ifstream(path).good()) {
        error = "cannot open mesh: " + path;
        return false;
    }
    PolygonSoup soup;
    try {
        const bool read = ext == "ply"             ? readPly(path, soup, error)
                          : ext == "obj"           ? readObj(path, soup, error)
                          : isAssimpExtension(ext) ? readAssimp(path, soup, error)
                                                   : readOpenMesh(path, ext, soup, error);
        const std::string doubts = soup.warnings;
        if (!read || !finishMesh(path, soup, mesh, error))
            return false;
        if (warnings) {
            warnings->clear();
            for (size_t at = 0, end; (end = doubts.find('\n', at)) != std::string::npos; at = end + 1)
                warnings->push_back(doubts.substr(at, end - at));
            const size_t n = mesh.health.skippedFaces;
            if (n)
                warnings->push_back(std::to_string(n) + (n == 1 ? " face of the file was" : " faces of the file were") +
                                    " left out: a corner out of range, fewer than three corners or a corner "
                                    "repeated");
        }
        return true;
    } catch (const std::bad_alloc &) {
        error = "mesh is larger than memory allows: " + path;
        return false;
    }
}

} // namespace meshsdf
