// src/mesh/grid: the box a conversion plans, the grid it builds held to
// mesh_support.h's brute-force signed distance (the band exact, signs the
// winding number's, --full exact everywhere), the memory estimate's
// growth, and the grid's .npy and sidecar files read back here.
#include "grid/build.h"
#include "grid/grid_files.h"
#include "grid/memory_estimate.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

// Last: cmocka's macros would rename members of the headers above.
#include "mesh_unit.h"

namespace
{

using meshsdf::TriangleMesh;

sdft_mesh_grid_params params(int res, double band, bool full)
{
    sdft_mesh_grid_params p = sdft_mesh_grid_params_defaults();
    p.res = res;
    p.band = band;
    p.full = full;
    return p;
}

// res N puts N voxel centres along the padded box's longest side: the
// mesh's box plus `padding` voxels (band + 1 by default) on each side.
void plan(void **)
{
    TriangleMesh m = unit::cube();
    m.points[6] = {2, 1, 1}; // the box is [0, 2] x [0, 1] x [0, 1]
    meshsdf::computeBox(m);
    meshsdf::BoxGeometry box;
    std::string error;
    assert_true(meshsdf::planBox(m, params(33, 3, false), box, error));
    const double h = 2.0 / (33 - 1 - 2 * 4); // padding band + 1 = 4
    assert_true(std::fabs(box.voxelSize - h) < 1e-15);
    assert_int_equal(box.dims[0], 33);
    assert_int_equal(box.dims[1], int(std::ceil(1 / h + 8 - 1e-9)) + 1);
    for (int k = 0; k < 3; ++k)
        assert_true(std::fabs(box.origin[k] - (m.lo[k] - 4 * h)) < 1e-12);
    sdft_mesh_grid_params p = params(33, 3, false);
    p.padding = 0;
    p.voxel_size = 0.5;
    assert_true(meshsdf::planBox(m, p, box, error));
    assert_int_equal(box.dims[0], 5);
    assert_int_equal(box.dims[1], 3);
    assert_false(meshsdf::planBox(m, params(9, 3, false), box, error)); // no room inside the padding
    assert_true(error.find("padding") != std::string::npos);
    p.voxel_size = 1e-4;
    assert_false(meshsdf::planBox(m, p, box, error)); // above 4096 a side
}

// Every voxel of a narrow band and of a dense grid against brute force:
// the distance exact, the sign the winding number's.
void grid_values(void **)
{
    openvdb::initialize();
    TriangleMesh m = unit::sphere({0, 0, 0}, 1, 10);
    mesh truth = unit::truth(m);
    for (bool full : {false, true}) {
        const sdft_mesh_grid_params p = params(24, 2, full);
        meshsdf::BoxGeometry box;
        std::string error;
        assert_true(meshsdf::planBox(m, p, box, error));
        meshsdf::Progress progress(nullptr, nullptr, nullptr);
        meshsdf::BuildStats stats;
        const openvdb::FloatGrid::Ptr grid =
            meshsdf::buildGrid(m, box, p, meshsdf::Simd{}, meshsdf::WindingAccuracy::Fast, progress, stats);
        assert_true(grid->getGridClass() == openvdb::GRID_LEVEL_SET);
        const auto acc = grid->getConstAccessor();
        size_t active = 0;
        for (int i = 0; i < box.dims[0]; ++i)
            for (int j = 0; j < box.dims[1]; ++j)
                for (int k = 0; k < box.dims[2]; ++k) {
                    const double q[3] = {box.origin[0] + i * box.voxelSize, box.origin[1] + j * box.voxelSize,
                                         box.origin[2] + k * box.voxelSize};
                    const double want = mesh_sdf(&truth, q);
                    const openvdb::Coord ijk(i, j, k);
                    const float v = acc.getValue(ijk);
                    if (acc.isValueOn(ijk)) {
                        ++active;
                        assert_true(std::fabs(v - want) <= 1e-5 * (1 + std::fabs(want)));
                    } else {
                        assert_false(full);
                        assert_true(std::fabs(want) >= 2 * box.voxelSize * (1 - 1e-6)); // beyond the band
                        assert_true(std::signbit(v) == std::signbit(want));
                    }
                }
        if (full)
            assert_int_equal(active, size_t(box.voxelCount()));
    }
    mesh_free(&truth);
}

// The estimate grows with the resolution, the band and a dense grid.
void memory_estimate(void **)
{
    TriangleMesh m = unit::sphere({0, 0, 0}, 1, 10);
    auto peak = [&](int res, double band, bool full) {
        meshsdf::BoxGeometry box;
        std::string error;
        const sdft_mesh_grid_params p = params(res, band, full);
        assert_true(meshsdf::planBox(m, p, box, error));
        return meshsdf::conversionPeakBytes(m, box, p);
    };
    assert_true(peak(128, 3, false) > peak(64, 3, false));
    assert_true(peak(128, 6, false) > peak(128, 3, false));
    assert_true(peak(128, 3, true) > peak(128, 3, false));
}

// The .npy is the box densely, C order, z fastest; the sidecar names the
// array and the box; its path replaces a trailing .npy.
void files(void **)
{
    openvdb::initialize();
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(5.0f);
    meshsdf::BoxGeometry box;
    box.voxelSize = 0.5;
    box.origin = {1, 2, 3};
    box.dims = {3, 9, 10}; // across leaves along y and z
    auto acc = grid->getAccessor();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 9; ++j)
            for (int k = 0; k < 10; ++k)
                if ((i + j + k) % 3)
                    acc.setValue(openvdb::Coord(i, j, k), float(i * 100 + j * 10 + k));
    const std::string npy = unit::tmp("grid_files.npy"), json = unit::tmp("grid_files.json");
    std::string error;
    assert_true(meshsdf::writeNpy(*grid, box, npy, error));
    std::ifstream in(npy, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t header = 10 + size_t(uint8_t(bytes[8])) + 256 * size_t(uint8_t(bytes[9]));
    assert_true(bytes.find("'shape': (3, 9, 10)") != std::string::npos);
    assert_int_equal(bytes.size(), header + 3 * 9 * 10 * 4);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 9; ++j)
            for (int k = 0; k < 10; ++k) {
                float v;
                std::memcpy(&v, bytes.data() + header + 4 * size_t((i * 9 + j) * 10 + k), 4);
                assert_true(v == ((i + j + k) % 3 ? float(i * 100 + j * 10 + k) : 5.0f));
            }
    const meshsdf::Provenance how{"src \"mesh\".obj", "winding", 3, false};
    assert_true(meshsdf::writeNpyJson(box, "grid_files.npy", how, 5.0f, json, error));
    std::ifstream side(json);
    std::stringstream text;
    text << side.rdbuf();
    for (const char *line : {"\"array\": \"grid_files.npy\"", "\"shape\": [3, 9, 10]", "\"origin\": [1, 2, 3]",
                             "\"voxel_size\": 0.5", "\"source_mesh\": \"src \\\"mesh\\\".obj\""})
        if (text.str().find(line) == std::string::npos)
            fail_msg("the sidecar lacks %s", line);
    assert_true(meshsdf::sidecarPath("a/b.npy") == "a/b.json");
    assert_true(meshsdf::sidecarPath("a.npy.bin") == "a.npy.bin.json");
}

} // namespace

int main()
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(plan),
        cmocka_unit_test(grid_values),
        cmocka_unit_test(memory_estimate),
        cmocka_unit_test(files),
    };
    return cmocka_run_group_tests_name("mesh_grid", tests, nullptr, nullptr);
}
