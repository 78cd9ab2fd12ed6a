// mesh2sdf — mesh loading and health check (see mesh.h).
#include "mesh.h"

// GCC 12 with sanitizers flags OpenMesh's property vectors (VectorT copies
// in PropertyT::push_back) as maybe-uninitialized; a false positive in its
// headers, silenced for this file only.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <unordered_map>

namespace mesh2sdf
{

namespace
{

using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

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

// Twice the squared area of a triangle, in double.
double doubleArea2(const std::array<float, 3> &a, const std::array<float, 3> &b, const std::array<float, 3> &c)
{
    const double e1[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
    const double e2[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    const double x = e1[1] * e2[2] - e1[2] * e2[1], y = e1[2] * e2[0] - e1[0] * e2[2],
                 z = e1[0] * e2[1] - e1[1] * e2[0];
    return x * x + y * y + z * z;
}

// TriangleMesh::welded for `points`.
std::vector<uint32_t> weldByPosition(const std::vector<std::array<float, 3>> &points)
{
    struct Key {
        float x, y, z;
        bool operator==(const Key &o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct KeyHash {
        size_t operator()(const Key &k) const
        {
            uint32_t b[3];
            std::memcpy(b, &k, sizeof b);
            return (size_t(b[0]) * 73856093u) ^ (size_t(b[1]) * 19349663u) ^ (size_t(b[2]) * 83492791u);
        }
    };
    std::unordered_map<Key, uint32_t, KeyHash> first;
    first.reserve(points.size());
    std::vector<uint32_t> welded(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        const auto &p = points[i];
        // + 0.0f makes -0 +0, so that equal keys hash alike.
        welded[i] = first.emplace(Key{p[0] + 0.0f, p[1] + 0.0f, p[2] + 0.0f}, uint32_t(i)).first->second;
    }
    return welded;
}

// Boundary and non-manifold edge counts on the welded vertices.
void countEdges(TriangleMesh &mesh)
{
    const std::vector<uint32_t> &id = mesh.welded;
    std::unordered_map<uint64_t, uint32_t> uses;
    uses.reserve(mesh.triangles.size() * 2);
    for (const auto &t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            uint64_t a = id[t[k]], b = id[t[(k + 1) % 3]];
            if (a > b)
                std::swap(a, b);
            ++uses[(a << 32) | b];
        }
    for (const auto &e : uses) {
        if (e.second == 1)
            ++mesh.health.boundaryEdges;
        else if (e.second > 2)
            ++mesh.health.nonManifoldEdges;
    }
}

// `word` as a number, the way strtod reads it: true, with *value, when
// strtod takes the whole word. std::from_chars first (several times
// faster, the same correctly rounded value for the decimal numbers it
// takes), strtod for what it does not take whole (a leading '+', hex).
bool wholeNumber(const std::string &word, double *value)
{
    const char *first = word.data(), *last = first + word.size();
    const auto [stopped, ec] = std::from_chars(first, last, *value);
    if (ec == std::errc() && stopped == last)
        return true;
    char *end = nullptr;
    *value = std::strtod(word.c_str(), &end);
    return end != word.c_str() && *end == '\0';
}

// True if `word` is a whole number that is not finite ("nan", "inf", 1e999).
bool nonFiniteNumber(const std::string &word)
{
    double v;
    return wholeNumber(word, &v) && !std::isfinite(v);
}

// The words of one line (runs of characters that are not white space, as
// a stream's >> reads them), one at a time into a reused string.
class LineWords
{
  public:
    LineWords(const char *begin, const char *end) : mAt(begin), mEnd(end) {}
    bool next(std::string &word)
    {
        while (mAt < mEnd && std::isspace(static_cast<unsigned char>(*mAt)))
            ++mAt;
        if (mAt == mEnd)
            return false;
        const char *start = mAt;
        while (mAt < mEnd && !std::isspace(static_cast<unsigned char>(*mAt)))
            ++mAt;
        word.assign(start, mAt);
        return true;
    }

  private:
    const char *mAt, *mEnd;
};

bool startsWith(const char *begin, const char *end, const char *prefix)
{
    const size_t n = std::strlen(prefix);
    return size_t(end - begin) >= n && std::memcmp(begin, prefix, n) == 0;
}

// OpenMesh's text readers do not report a coordinate they cannot parse
// ("nan", "inf", 1e999): the OBJ reader drops the vertex line, shifting
// every later index, the OFF and PLY readers stop and find no faces, the STL
// reader goes on with a wrong vertex. So the coordinates of text files are
// checked here first: OBJ "v" lines, every number after OFF's keyword line
// or PLY's end_header, and STL "vertex" lines. Binary formats carry NaN and
// Inf through and are caught after reading. Each line's words are scanned
// in place (a string stream per line cost more than the reading).
bool checkTextCoordinates(const std::string &path, const std::string &ext, std::string &error)
{
    if (ext != "obj" && ext != "off" && ext != "ply" && ext != "stl")
        return true;
    std::ifstream in(path);
    std::string text, word; // a line at a time: a binary file is left after its header
    bool data = false;      // OFF, PLY: past the header
    for (size_t number = 1; std::getline(in, text); ++number) {
        const char *line = text.data(), *end = line + text.size();
        if (ext == "off") { // comments run from '#' to the end of the line
            const char *hash = static_cast<const char *>(std::memchr(line, '#', text.size()));
            if (hash)
                end = hash;
        }
        LineWords words(line, end);
        int check = 0; // words to check on this line; -1: all
        if (ext == "obj") {
            if (end - line < 2 || line[0] != 'v' || (line[1] != ' ' && line[1] != '\t'))
                continue;
            words.next(word); // "v"
            for (int k = 0; k < 3; ++k) {
                if (!words.next(word)) {
                    error = "mesh has a malformed coordinate (line " + std::to_string(number) + "): " + path;
                    return false;
                }
                double v;
                if (!wholeNumber(word, &v) || !std::isfinite(v)) {
                    error =
                        "mesh has a non-finite or malformed coordinate (line " + std::to_string(number) + "): " + path;
                    return false;
                }
            }
            continue;
        } else if (ext == "off") {
            if (!data) { // the keyword line: OFF, COFF, NOFF ...; binary OFF is checked after reading
                if (!words.next(word))
                    continue;
                if (word.find("OFF") == std::string::npos || text.find("BINARY") != std::string::npos)
                    return true;
                data = true;
            }
            check = -1;
        } else if (ext == "ply") {
            if (!data) {
                if (startsWith(line, end, "format") && text.find("ascii") == std::string::npos)
                    return true; // binary
                data = startsWith(line, end, "end_header");
                continue;
            }
            check = -1;
        } else { // stl
            if (!words.next(word) || word != "vertex")
                continue;
            check = 3;
        }
        for (int k = 0; (check < 0 || k < check) && words.next(word); ++k)
            if (nonFiniteNumber(word)) {
                error = "mesh has a non-finite coordinate (line " + std::to_string(number) + "): " + path;
                return false;
            }
    }
    return true;
}

} // namespace

bool isMeshExtension(const std::string &path)
{
    const std::string ext = lowerExtension(path);
    return ext == "obj" || ext == "ply" || ext == "off" || ext == "stl" || ext == "om";
}

bool loadMesh(const std::string &path, TriangleMesh &mesh, std::string &error)
{
    if (!isMeshExtension(path)) {
        error = "unknown mesh extension '" + lowerExtension(path) + "' (use .obj .ply .off .stl .om): " + path;
        return false;
    }
    if (!std::ifstream(path).good()) {
        error = "cannot open mesh: " + path;
        return false;
    }
    if (!checkTextCoordinates(path, lowerExtension(path), error))
        return false;
    // OpenMesh reports complex edges and parse problems on its own streams;
    // the health line below says what matters, once.
    omerr().disable();
    omlog().disable();
    omout().disable();

    PolyMesh poly;
    OpenMesh::IO::Options options;
    if (!OpenMesh::IO::read_mesh(poly, path, options)) {
        error = "cannot read mesh (not a valid " + lowerExtension(path) + " file?): " + path;
        return false;
    }
    mesh = TriangleMesh{};
    mesh.health.vertices = poly.n_vertices();
    mesh.health.faces = poly.n_faces();
    if (poly.n_faces() == 0) {
        error = "mesh has no faces: " + path;
        return false;
    }
    mesh.points.resize(poly.n_vertices());
    for (const auto vh : poly.vertices()) {
        const auto &p = poly.point(vh);
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
            error = "mesh has a non-finite coordinate (vertex " + std::to_string(vh.idx()) + "): " + path;
            return false;
        }
        mesh.points[vh.idx()] = {p[0], p[1], p[2]};
    }
    std::vector<uint32_t> corners;
    for (const auto fh : poly.faces()) {
        corners.clear();
        for (const auto vh : poly.fv_range(fh))
            corners.push_back(uint32_t(vh.idx()));
        for (size_t k = 1; k + 1 < corners.size(); ++k) {
            const std::array<uint32_t, 3> t{corners[0], corners[k], corners[k + 1]};
            if (doubleArea2(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]) <= 0.0) {
                ++mesh.health.degenerateFaces;
                continue;
            }
            mesh.triangles.push_back(t);
        }
    }
    mesh.health.triangles = mesh.triangles.size();
    if (mesh.triangles.empty()) {
        error = "mesh has no non-degenerate triangles: " + path;
        return false;
    }
    mesh.lo = {INFINITY, INFINITY, INFINITY};
    mesh.hi = {-INFINITY, -INFINITY, -INFINITY};
    for (const auto &t : mesh.triangles)
        for (uint32_t v : t)
            for (int k = 0; k < 3; ++k) {
                mesh.lo[k] = std::min(mesh.lo[k], double(mesh.points[v][k]));
                mesh.hi[k] = std::max(mesh.hi[k], double(mesh.points[v][k]));
            }
    const double extent = std::max({mesh.hi[0] - mesh.lo[0], mesh.hi[1] - mesh.lo[1], mesh.hi[2] - mesh.lo[2]});
    if (!(extent > 0.0)) {
        error = "mesh bounding box has zero size: " + path;
        return false;
    }
    mesh.welded = weldByPosition(mesh.points);
    countEdges(mesh);
    return true;
}

} // namespace mesh2sdf
