// Grids of assemblies of closed parts, touching or interpenetrating (a
// block of cubes whose touching faces are the same triangles, one whose
// faces are meshed differently, nested shells, a gear train on a plate)
// and of an open mesh with the exact accuracy, through the C API
// (sdftrace/mesh.h): every voxel clear of 1/2 has the sign of the
// brute-force winding number of the parts as given, and the touching faces
// are kept (they cancel in pairs: dropping one would open both parts).
#include "mesh_shapes.h"
#include "sdftrace/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

using shapes::Soup;

namespace
{

struct Checked {
    int voxels = 0, wrong = 0;
    sdft_mesh_health health{};
    sdft_mesh_grid_box box{};
    sdft_mesh_grid_stats stats{};
};

// Converts the soup at `res` with the winding sign and `accuracy`, and
// compares the sign of `samples` random voxels with brute force wherever
// the winding number is farther than `clear` from 1/2.
Checked convert(const char *name, const Soup &s, int res, sdft_mesh_accuracy accuracy, int samples, double clear)
{
    char msg[512];
    sdft_mesh *m = nullptr;
    sdft_mesh_params mp = sdft_mesh_params_defaults();
    mp.accuracy = accuracy;
    const sdft_error loaded =
        sdft_mesh_from_arrays(s.points.data(), SDFT_MESH_FLOAT32, s.points.size(), s.triangles.data(), SDFT_MESH_UINT32,
                              s.triangles.size(), &mp, &m, msg, sizeof msg);
    if (loaded != SDFT_OK)
        fail_msg("%s: %s", name, msg);
    Checked c;
    assert_int_equal(sdft_mesh_get_health(m, &c.health, msg, sizeof msg), SDFT_OK);
    sdft_mesh_grid_params p = sdft_mesh_grid_params_defaults();
    p.res = res;
    sdft_mesh_grid *g = nullptr;
    assert_int_equal(sdft_mesh_to_grid(m, &p, &g, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_grid_get_box(g, &c.box, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_mesh_grid_get_stats(g, &c.stats, msg, sizeof msg), SDFT_OK);
    const size_t count = size_t(c.box.dims[0]) * c.box.dims[1] * c.box.dims[2];
    std::vector<float> values(count);
    assert_int_equal(sdft_mesh_grid_dense(g, values.data(), count, msg, sizeof msg), SDFT_OK);
    const shapes::Brute brute(s);
    std::mt19937_64 rng(17);
    std::uniform_int_distribution<size_t> pick(0, count - 1);
    for (int i = 0; i < samples; ++i) {
        const size_t v = pick(rng);
        const size_t x = v / (size_t(c.box.dims[1]) * c.box.dims[2]), y = v / c.box.dims[2] % c.box.dims[1],
                     z = v % c.box.dims[2];
        const double q[3] = {c.box.origin[0] + double(x) * c.box.voxel_size,
                             c.box.origin[1] + double(y) * c.box.voxel_size,
                             c.box.origin[2] + double(z) * c.box.voxel_size};
        const double w = brute.winding(q);
        if (!(std::abs(w - 0.5) > clear))
            continue;
        ++c.voxels;
        if (std::signbit(values[v]) != (w > 0.5)) { // -0: on a face, inside
            ++c.wrong;
            print_message("%s: voxel (%zu, %zu, %zu) has %g, winding number %.6f\n", name, x, y, z, values[v], w);
        }
    }
    print_message("%-18s %6zu triangles, %s: %d voxels checked, %d wrong; %llu duplicate faces dropped, "
                  "%llu voxels ambiguous\n",
                  name, s.triangles.size(), accuracy == SDFT_MESH_ACCURACY_EXACT ? "exact" : "fast", c.voxels, c.wrong,
                  (unsigned long long)c.health.duplicate_faces, (unsigned long long)c.stats.ambiguous_voxels);
    sdft_mesh_grid_free(g);
    sdft_mesh_free(m);
    return c;
}

void test_touching_cubes(void **)
{
    // Touching faces on the same vertices: kept in pairs, none dropped.
    const Checked same = convert("cube block", shapes::cubeGrid(4), 64, SDFT_MESH_ACCURACY_FAST, 3000, 0.01);
    assert_int_equal(same.health.duplicate_faces, 0);
    assert_true(same.voxels > 2000);
    assert_int_equal(same.wrong, 0);
    // Touching faces meshed differently (T-junctions) beside equal ones.
    const Checked mixed = convert("mixed cube block", shapes::cubeGrid(4, 3), 64, SDFT_MESH_ACCURACY_FAST, 3000, 0.01);
    assert_int_equal(mixed.health.duplicate_faces, 0);
    assert_int_equal(mixed.wrong, 0);
}

void test_nested_and_interpenetrating(void **)
{
    const Checked shells = convert("nested shells", shapes::nestedShells(4), 64, SDFT_MESH_ACCURACY_FAST, 2000, 0.01);
    assert_int_equal(shells.wrong, 0);
    assert_int_equal(shells.stats.ambiguous_voxels, 0);
    const Checked gears = convert("gear train", shapes::gearTrain(4), 80, SDFT_MESH_ACCURACY_FAST, 3000, 0.01);
    assert_int_equal(gears.wrong, 0);
}

// A genuine duplicate stays dropped: a closed surface with one face again
// reversed is closed again without it, and the same face twice in the
// same orientation counts once.
void test_duplicates_still_dropped(void **)
{
    Soup s = shapes::sphere(0, 0, 0, 1, 16, 32);
    const auto face = s.triangles[40];
    s.triangles.push_back({face[0], face[2], face[1]}); // reversed
    s.triangles.push_back(s.triangles[41]);             // the same again
    const Checked c = convert("sphere, copies", s, 40, SDFT_MESH_ACCURACY_FAST, 1000, 0.01);
    assert_int_equal(c.health.duplicate_faces, 2);
    assert_int_equal(c.health.boundary_edges, 0);
    assert_int_equal(c.health.non_manifold_edges, 0);
}

// With the exact accuracy the grid's sign is the exact winding number's at
// every voxel the arithmetic can tell, open meshes included: the cut
// sphere's rim and the holes of a holed one put voxels near 1/2.
void test_exact_signs(void **)
{
    const Checked cut = convert("cut sphere", shapes::cutSphere(), 48, SDFT_MESH_ACCURACY_EXACT, 3000, 1e-5);
    assert_int_equal(cut.wrong, 0);
    const Checked holed = convert("holed sphere", shapes::withoutFaces(shapes::sphere(0, 0, 0, 1, 20, 40), 5), 48,
                                  SDFT_MESH_ACCURACY_EXACT, 3000, 1e-5);
    assert_int_equal(holed.wrong, 0);
}

} // namespace

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_touching_cubes),
        cmocka_unit_test(test_nested_and_interpenetrating),
        cmocka_unit_test(test_duplicates_still_dropped),
        cmocka_unit_test(test_exact_signs),
    };
    return cmocka_run_group_tests_name("mesh_assemblies", tests, nullptr, nullptr);
}
