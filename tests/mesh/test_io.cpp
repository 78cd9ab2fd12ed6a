// src/mesh/io: each reader and the one dispatcher, on files written here
// whose contents are known: the same tetrahedron as OBJ (a quad for two of
// its faces' worth), OFF, ASCII STL, ASCII and binary PLY (faces and
// triangle strips), glTF through assimp; the loader's checks; the reader
// process's answers, a crash and a short answer among them; the parallel
// OBJ reader against OpenMesh's, soup for soup.
#include "geometry/polygon_soup.h"
#include "io/assimp_read.h"
#include "io/mesh_io.h"
#include "io/obj_read.h"
#include "io/openmesh_read.h"
#include "io/ply_read.h"
#include "io/reader_process.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

// Last: cmocka's macros would rename members of the headers above.
#include "mesh_unit.h"

namespace
{

using meshsdf::PolygonSoup;
using meshsdf::TriangleMesh;

void write(const std::string &path, const std::string &text) { std::ofstream(path, std::ios::binary) << text; }

// Every triangle of `got`, on its points, as a set of corner positions:
// the same as the tetrahedron's, whatever the file's numbering.
void assert_tetrahedron(const TriangleMesh &got)
{
    static const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    static const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    assert_int_equal(got.triangles.size(), 4);
    for (int f = 0; f < 4; ++f) {
        bool found = false;
        for (const auto &t : got.triangles)
            for (int r = 0; r < 3 && !found; ++r) { // the same cycle, any first corner
                bool same = true;
                for (int k = 0; k < 3; ++k)
                    for (int x = 0; x < 3; ++x)
                        same = same && got.points[t[(k + r) % 3]][x] == v[faces[f][k]][x];
                found = same;
            }
        assert_true(found);
    }
    assert_true(got.lo[0] == 0 && got.hi[0] == 1 && got.hi[2] == 1);
}

void each_format(void **)
{
    const std::string obj = unit::tmp("io_tetra.obj"), off = unit::tmp("io_tetra.off"), stl = unit::tmp("io_tetra.stl"),
                      ply = unit::tmp("io_tetra.ply"), strips = unit::tmp("io_strips.ply"),
                      gltf = unit::tmp("io_tetra.gltf");
    write(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    write(off, "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    std::string s = "solid t\n";
    const char *facets[4] = {"0 0 0\n vertex 0 1 0\n vertex 1 0 0", "0 0 0\n vertex 1 0 0\n vertex 0 0 1",
                             "0 0 0\n vertex 0 0 1\n vertex 0 1 0", "1 0 0\n vertex 0 1 0\n vertex 0 0 1"};
    for (const char *f : facets)
        s += std::string("facet normal 0 0 0\n outer loop\n vertex ") + f + "\n endloop\nendfacet\n";
    write(stl, s + "endsolid t\n");
    write(ply, "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
               "element face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
               "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    // One strip, 2 0 1 3 2: (2,0,1), (0,3,1) reversed back to (0,1,3)...,
    // every other triangle reversed so that the strip keeps one orientation.
    write(strips, "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                  "element tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                  "7 2 0 1 3 2 -1 0\n");
    // glTF 2 with its buffer as a data URI: 4 float vec3 positions, 12
    // uint16 indices (base64 of the bytes below).
    const unsigned char bytes[] = {0, 0, 0, 0, 0, 0, 0,   0,  0, 0, 0, 0, 0, 0, 128, 63, 0, 0, 0, 0, 0, 0, 0,   0,
                                   0, 0, 0, 0, 0, 0, 128, 63, 0, 0, 0, 0, 0, 0, 0,   0,  0, 0, 0, 0, 0, 0, 128, 63,
                                   0, 0, 2, 0, 1, 0, 0,   0,  1, 0, 3, 0, 0, 0, 3,   0,  2, 0, 1, 0, 2, 0, 3,   0};
    static const char b64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string data;
    for (size_t i = 0; i < sizeof bytes; i += 3) {
        const unsigned n = unsigned(bytes[i]) << 16 | unsigned(bytes[i + 1]) << 8 | bytes[i + 2];
        for (int k = 3; k >= 0; --k)
            data += b64[(n >> (6 * k)) & 63];
    }
    write(gltf, "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
                "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
                "\"buffers\":[{\"byteLength\":72,\"uri\":\"data:application/octet-stream;base64," +
                    data +
                    "\"}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,"
                    "\"byteLength\":24}],\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,"
                    "\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,1]},{\"bufferView\":1,\"componentType\":5123,"
                    "\"count\":12,\"type\":\"SCALAR\"}]}");
    for (const std::string &path : {obj, off, stl, ply, gltf}) {
        TriangleMesh m;
        std::string error;
        if (!meshsdf::loadMesh(path, m, error))
            fail_msg("%s: %s", path.c_str(), error.c_str());
        assert_tetrahedron(m);
        assert_int_equal(m.health.degenerateFaces, 0);
    }
    PolygonSoup soup;
    std::string error;
    assert_true(meshsdf::readPly(strips, soup, error));
    assert_int_equal(soup.ends.size(), 3);
    const std::vector<uint32_t> corners = {2, 0, 1, 1, 0, 3, 1, 3, 2}; // the middle one reversed
    assert_true(soup.corners == corners);
}

// Polygons are fans, zero-area triangles counted and dropped, a repeated
// corner's polygon left out; refusals are one line naming the file.
void the_loaders_checks(void **)
{
    const std::string quad = unit::tmp("io_quad.obj");
    write(quad, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nf 1 2 3 4\nf 1 2 5\nf 1 1 2\n");
    TriangleMesh m;
    std::string error;
    assert_true(meshsdf::loadMesh(quad, m, error));
    assert_int_equal(m.health.faces, 2); // the third repeats a corner
    assert_int_equal(m.triangles.size(), 2);
    assert_int_equal(m.health.degenerateFaces, 1); // 1 2 5 lies on a line
    const std::vector<std::array<uint32_t, 3>> fan = {{0, 1, 2}, {0, 2, 3}};
    assert_true(m.triangles == fan);

    const struct {
        const char *name, *text, *says;
    } bad[] = {{"io_nan.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n", "non-finite"},
               {"io_none.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"},
               {"io_flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "no non-degenerate"},
               {"io_x.mesh", "v 0 0 0\n", "unknown mesh extension"},
               {"io_bad.ply", "ply\nformat ascii 1.0\nelement vertex 99\nend_header\n", "io_bad.ply"}};
    for (const auto &b : bad) {
        write(unit::tmp(b.name), b.text);
        error.clear();
        assert_false(meshsdf::loadMesh(unit::tmp(b.name), m, error));
        if (error.find(b.says) == std::string::npos || error.find('\n') != std::string::npos)
            fail_msg("%s: '%s'", b.name, error.c_str());
    }
    assert_false(meshsdf::loadMesh(unit::tmp("io_missing.obj"), m, error));
    assert_true(error.rfind("cannot open", 0) == 0);
    assert_true(meshsdf::isMeshExtension("a/B.OBJ") && meshsdf::isMeshExtension("x.glb"));
    assert_false(meshsdf::isMeshExtension("x.obj.txt") || meshsdf::isMeshExtension("obj"));
    assert_true(meshsdf::isAssimpExtension("3mf") && !meshsdf::isAssimpExtension("ply"));
}

// The reader process: a soup comes back whole; a reader that crashes, or
// one that names a point it does not have, is one line of error.
void reader_process(void **)
{
    const std::string path = unit::tmp("io_process.obj");
    write(path, "anything\n");
    PolygonSoup soup;
    std::string error;
    const bool ok = meshsdf::readInChildProcess(
        [](PolygonSoup &s, std::string &) {
            s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
            const uint32_t corners[3] = {0, 1, 2};
            s.addPolygon(corners, 3);
            return true;
        },
        path, "the test reader", soup, error);
    assert_true(ok);
    assert_int_equal(soup.points.size(), 3);
    assert_true(soup.points[1][0] == 1 && soup.ends.size() == 1 && soup.corners[2] == 2);

    assert_false(meshsdf::readInChildProcess(
        [](PolygonSoup &, std::string &) {
            std::abort();
            return true;
        },
        path, "the test reader", soup, error));
    assert_true(error.find("the test reader crashed on it") != std::string::npos &&
                error.find(path) != std::string::npos);

    assert_false(meshsdf::readInChildProcess(
        [](PolygonSoup &s, std::string &) {
            s.points = {{0, 0, 0}};
            const uint32_t corners[3] = {0, 1, 7};
            s.addPolygon(corners, 3);
            return true;
        },
        path, "the test reader", soup, error));
    assert_true(error.find("inconsistent") != std::string::npos);
    assert_true(soup.points.empty());

    assert_false(meshsdf::readInChildProcess(
        [](PolygonSoup &, std::string &e) {
            e = "the reader's own words";
            return false;
        },
        path, "the test reader", soup, error));
    assert_true(error == "the reader's own words");
}

// readObj's soup against OpenMesh's reader's for the file at `path`, bit
// for bit; or the same error. `plain`: whether the parallel parser takes
// the file itself (else it hands it to OpenMesh's reader).
void assert_same_soup(const std::string &path, bool plain)
{
    std::ifstream in(path, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    PolygonSoup parsed, mine, theirs;
    if (meshsdf::parsePlainObj(text.data(), text.size(), parsed) != plain)
        fail_msg("%s: plain should be %d", path.c_str(), int(plain));
    std::string mineError, theirError;
    const bool read = meshsdf::readObj(path, mine, mineError);
    assert_int_equal(read, meshsdf::readOpenMesh(path, "obj", theirs, theirError));
    assert_string_equal(mineError.c_str(), theirError.c_str());
    assert_int_equal(mine.points.size(), theirs.points.size());
    if (!mine.points.empty())
        assert_memory_equal(mine.points.data(), theirs.points.data(), mine.points.size() * sizeof mine.points[0]);
    assert_true(mine.corners == theirs.corners);
    assert_true(mine.ends == theirs.ends);
    if (plain)
        assert_true(parsed.points == mine.points && parsed.corners == mine.corners && parsed.ends == mine.ends);
}

// The test meshes; a file of every form a plain OBJ takes (comments, CRLF,
// tabs and leading blanks, texture and normal indices, negative indices,
// polygons, colours after a point, decimals longer than a float holds),
// long enough to be parsed in many pieces with negative indices across
// their seams; and files the parser leaves to OpenMesh's reader.
void obj_reader_matches_openmesh(void **)
{
    for (const char *name : {"fandisk", "spot", "stanford-bunny", "suzanne", "teapot"})
        assert_same_soup(std::string(SDFT_SOURCE_DIR) + "/tests/data/meshes/" + name + ".obj", true);
    std::string big = "# a grid of rows, each row's faces on the row before it\r\nmtllib none.mtl\no grid\n";
    uint64_t state = 12345;
    auto coordinate = [&state](char *out, size_t n, int row) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        const double r = double(state >> 11) / 9007199254740992.0;
        std::snprintf(out, n, row % 3 ? "%.17g" : "%.6f", (row % 2 ? -1 : 1) * r * 100);
    };
    const int rows = 160, columns = 160;
    char x[40], y[40], z[40], line[200];
    for (int i = 0; i < rows; ++i) {
        for (int j = 0; j < columns; ++j) {
            coordinate(x, sizeof x, i), coordinate(y, sizeof y, i + 1), coordinate(z, sizeof z, i + j);
            std::snprintf(line, sizeof line, j % 7 == 0 ? "v\t%s %s\t%s 0.5 0.5 0.5\r\n" : "  v %s %s %s\n", x, y, z);
            big += line;
        }
        big += i % 2 ? "vt 0.25 0.75\nvn 0 0 1\ng row\ns off\nusemtl none\n" : "# a row\n\n";
        for (int j = 1; i > 0 && j < columns; ++j) {
            // Corners of the quad (i - 1, j - 1) .. (i, j), 1-based; every
            // third face as negative indices from the points so far.
            const int a = (i - 1) * columns + j, b = a + 1, c = b + columns, d = a + columns, n = (i + 1) * columns;
            if (j % 3 == 0)
                std::snprintf(line, sizeof line, "f %d %d %d %d\n", a - n - 1, b - n - 1, c - n - 1, d - n - 1);
            else if (j % 3 == 1)
                std::snprintf(line, sizeof line, "f %d/1/1 %d/1/1 %d/1/1\r\nf\t%d//1 %d//1 %d//1\n", a, b, c, a, c, d);
            else
                std::snprintf(line, sizeof line, "f %d/1 %d/1 %d/1 %d/1 \n", a, b, c, d);
            big += line;
        }
    }
    const std::string path = unit::tmp("io_grid.obj");
    write(path, big);
    assert_true(big.size() > (size_t(1) << 20)); // several pieces of 256 KiB
    assert_same_soup(path, true);

    const char *tetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    const struct {
        const char *name, *faces;
    } others[] = {{"io_obj_range.obj", "f 1 2 9\nf 1 2 3\n"},
                  {"io_obj_zero.obj", "f 0 1 2\nf 1 2 3\n"},
                  {"io_obj_twice.obj", "f 1 1 2 3\nf 1 2 3\n"},
                  {"io_obj_two.obj", "f 1 2\nf 1 2 3\n"},
                  {"io_obj_plus.obj", "f +1 2 3\n"},
                  {"io_obj_text.obj", "f 1 2 3 # face\n"},
                  {"io_obj_vt.obj", "vt 0.5\nf 1 2 3\n"},
                  {"io_obj_nan.obj", "v nan 0 0\nf 1 2 3\n"},
                  {"io_obj_back.obj", "f -9 -1 -2\nf 1 2 3\n"},
                  {"io_obj_none.obj", ""}};
    for (const auto &o : others) {
        write(unit::tmp(o.name), std::string(tetra) + o.faces);
        assert_same_soup(unit::tmp(o.name), false);
    }
}

} // namespace

int main()
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(each_format),
        cmocka_unit_test(the_loaders_checks),
        cmocka_unit_test(reader_process),
        cmocka_unit_test(obj_reader_matches_openmesh),
    };
    return cmocka_run_group_tests_name("mesh_io", tests, nullptr, nullptr);
}
