// src/mesh/orient: each patch made consistent and turned outward, judged by
// the independent truth of mesh_support.h's brute-force winding number
// (1 inside a closed outward surface, 0 outside) and by the signed volume
// computed here from the triangles; a well-oriented mesh passes unchanged.
#include "orient/orient.h"

#include <cmath>

// Last: cmocka's macros would rename members of the headers above.
#include "mesh_unit.h"

namespace
{

using meshsdf::TriangleMesh;

// Six times the signed volume the triangles enclose (divergence theorem):
// positive when they face outward.
double signedVolume6(const TriangleMesh &m)
{
    double v = 0;
    for (const auto &t : m.triangles) {
        const auto &a = m.points[t[0]], &b = m.points[t[1]], &c = m.points[t[2]];
        v += double(a[0]) * (double(b[1]) * c[2] - double(b[2]) * c[1]) -
             double(a[1]) * (double(b[0]) * c[2] - double(b[2]) * c[0]) +
             double(a[2]) * (double(b[0]) * c[1] - double(b[1]) * c[0]);
    }
    return v;
}

// The brute-force winding number at the cube's centre and outside it.
void assert_outward(const TriangleMesh &m)
{
    mesh b = unit::truth(m);
    const double inside[3] = {0.5, 0.4, 0.6}, outside[3] = {1.7, 0.5, 0.5};
    assert_true(std::fabs(winding(&b, inside) - 1) < 1e-9);
    assert_true(std::fabs(winding(&b, outside)) < 1e-9);
    mesh_free(&b);
    assert_true(signedVolume6(m) > 0);
}

void reverse(TriangleMesh &m, size_t t) { std::swap(m.triangles[t][1], m.triangles[t][2]); }

// A well-oriented mesh comes out unchanged, triangle for triangle.
void well_oriented_unchanged(void **)
{
    TriangleMesh m = unit::cube();
    const auto before = m.triangles;
    const meshsdf::OrientCounts c = meshsdf::orientMesh(m, true);
    assert_true(m.triangles == before);
    assert_int_equal(c.patches, 1);
    assert_int_equal(c.reorientedFaces, 0);
    assert_int_equal(c.outwardPatches, 0);
    assert_outward(m);
}

// Inside out: every face reversed, the one patch turned outward.
void inside_out(void **)
{
    TriangleMesh m = unit::cube();
    for (size_t t = 0; t < m.triangles.size(); ++t)
        reverse(m, t);
    assert_true(signedVolume6(m) < 0);
    const meshsdf::OrientCounts c = meshsdf::orientMesh(m, false);
    assert_int_equal(c.reorientedFaces, 12);
    assert_int_equal(c.outwardPatches, 1);
    assert_outward(m);
}

// Faces flipped at random against their neighbours: made consistent with
// the orientation most of the area has, here the outward one.
void partly_flipped(void **)
{
    TriangleMesh m = unit::cube();
    for (size_t t : {1u, 4u, 9u})
        reverse(m, t);
    const meshsdf::OrientCounts c = meshsdf::orientMesh(m, true);
    assert_int_equal(c.reorientedFaces, 3);
    assert_int_equal(c.nonOrientablePatches, 0);
    assert_outward(m);
}

// Unwelded seams join: each face of the cube on vertices of its own (24
// vertices for 8 positions), then inside out. And a duplicate face, given
// reversed, is dropped.
void unwelded_and_duplicates(void **)
{
    const TriangleMesh cube = unit::cube();
    std::vector<std::array<float, 3>> points;
    std::vector<std::array<uint32_t, 3>> tris;
    for (size_t t = 0; t < cube.triangles.size(); ++t) {
        const uint32_t base = uint32_t(points.size());
        for (int k = 0; k < 3; ++k)
            points.push_back(cube.points[cube.triangles[t][k]]);
        tris.push_back({base, base + 2, base + 1}); // reversed
    }
    tris.push_back({tris[0][0], tris[0][2], tris[0][1]}); // face 0 again, reversed back
    TriangleMesh m = unit::makeMesh(points, tris);
    assert_int_equal(m.health.weldedVertices, 36 - 8);
    const meshsdf::OrientCounts c = meshsdf::orientMesh(m, true);
    assert_int_equal(c.duplicateFaces, 1);
    assert_int_equal(m.triangles.size(), 12);
    assert_int_equal(c.patches, 1);
    assert_int_equal(m.health.boundaryEdges, 0);
    assert_outward(m);
}

// Two shells, one inside the other, both facing outward: the inner one
// bounds a cavity when its faces are turned inward, and orienting keeps
// that (the whole mesh's winding number behind it is 1, in front 0); the
// shell between them is inside.
void cavity_kept(void **)
{
    const TriangleMesh outer = unit::cube();
    std::vector<std::array<float, 3>> points = outer.points;
    std::vector<std::array<uint32_t, 3>> tris = outer.triangles;
    for (const auto &p : outer.points)
        points.push_back({0.25f + 0.5f * p[0], 0.25f + 0.5f * p[1], 0.25f + 0.5f * p[2]});
    for (const auto &t : outer.triangles)
        tris.push_back({t[0] + 8, t[2] + 8, t[1] + 8}); // the inner wall faces the cavity
    TriangleMesh m = unit::makeMesh(points, tris);
    const meshsdf::OrientCounts c = meshsdf::orientMesh(m, true);
    assert_int_equal(c.patches, 2);
    assert_int_equal(c.cavityPatches, 1);
    assert_int_equal(c.reorientedFaces, 0);
    mesh b = unit::truth(m);
    const double shell[3] = {0.1, 0.5, 0.5}, cavity[3] = {0.5, 0.5, 0.5};
    assert_true(std::fabs(winding(&b, shell) - 1) < 1e-9);
    assert_true(std::fabs(winding(&b, cavity)) < 1e-9);
    mesh_free(&b);
}

} // namespace

int main()
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(well_oriented_unchanged), cmocka_unit_test(inside_out),  cmocka_unit_test(partly_flipped),
        cmocka_unit_test(unwelded_and_duplicates), cmocka_unit_test(cavity_kept),
    };
    return cmocka_run_group_tests_name("mesh_orient", tests, nullptr, nullptr);
}
