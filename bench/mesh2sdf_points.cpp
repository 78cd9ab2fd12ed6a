// The per-point signed distance query that libigl-style tools pay at every
// point of a dense grid: for each point, its nearest triangle through a
// bounding volume hierarchy (FastWinding::distance, searched from the root)
// and the sign of the fast winding number (FastWinding), with nothing
// shared between points. mesh2sdf's --full used exactly this per voxel
// before its dense grids were built block by block; bench/mesh2sdf.sh runs
// it on the voxels of a mesh2sdf --full --npy grid, beside mesh2sdf, and
// compares the two.
//
// usage: mesh2sdf_points MESH GRID.npy [THREADS]
//        mesh2sdf_points MESH --samples SAMPLES.npy [THREADS]
// Reads GRID.json (origin, voxel size, shape) beside GRID.npy, evaluates
// every voxel centre with all cores (or THREADS) and prints one line:
//   points=N seconds=S max_error_voxels=E sign_disagreements=K clear=C
// seconds: the queries alone (not loading or building the hierarchy);
// max_error_voxels: the largest |value - per-point value| over the points
// whose signs agree; sign_disagreements: points where the winding number is
// clearly on one side (below 0.25 or above 0.75) and the grid's sign is not.
// With --samples, the points are the rows (x, y, z, d) of mesh2sdf
// --samples, and the line has max_error (in the mesh's units) instead.
#include "io/mesh_io.h"
#include "npy_read.h"
#include "sign/winding.h"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

using namespace meshsdf;

namespace
{

// The number after "key": in the sidecar JSON, `index` entries into a list.
double jsonNumber(const std::string &json, const char *key, int index)
{
    size_t at = json.find(key);
    if (at == std::string::npos)
        return NAN;
    at = json.find(':', at) + 1;
    while (json[at] == ' ' || json[at] == '[')
        ++at;
    for (int i = 0; i < index; ++i)
        at = json.find(',', at) + 1;
    return std::atof(json.c_str() + at);
}

bool readNpy(const std::string &path, size_t count, std::vector<float> &values)
{
    std::ifstream in(path, std::ios::binary);
    char preamble[10];
    if (!in.read(preamble, 10))
        return false;
    const size_t header = size_t((unsigned char)preamble[8]) | size_t((unsigned char)preamble[9]) << 8;
    in.seekg(std::streamoff(10 + header));
    values.resize(count);
    return bool(in.read(reinterpret_cast<char *>(values.data()), std::streamsize(count * sizeof(float))));
}

} // namespace

// The per-point query at `count` points (point(i, q) fills q), timed, and
// compared with `expected` (the grid's or the samples' values): the line.
template <class Point>
void compare(const TriangleMesh &mesh, size_t count, Point point, const std::vector<float> &expected, double unit,
             const char *errorName)
{
    const FastWinding tree(mesh.points, mesh.triangles);
    std::vector<float> value(count);
    std::vector<float> winding(count);
    const auto t0 = std::chrono::steady_clock::now();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1024), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
            Vec3 q;
            point(i, q);
            const double w = tree(q);
            const float d = float(tree.distance(q));
            value[i] = w > 0.5 ? -d : d;
            winding[i] = float(w);
        }
    });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    double worst = 0;
    size_t disagree = 0, clear = 0;
    for (size_t i = 0; i < count; ++i) {
        const bool sure = winding[i] < 0.25f || winding[i] > 0.75f;
        clear += sure;
        // Sign bits: a voxel on the surface holds -0 when it is inside.
        if (std::signbit(expected[i]) != std::signbit(value[i])) {
            disagree += sure;
            continue;
        }
        worst = std::max(worst, std::abs(double(expected[i]) - value[i]) / unit);
    }
    std::printf("points=%zu seconds=%.3f %s=%.3g sign_disagreements=%zu clear=%zu\n", count, seconds, errorName, worst,
                disagree, clear);
}

int main(int argc, char **argv)
{
    const bool samples = argc > 2 && std::string(argv[2]) == "--samples";
    if (argc < 3 || (samples && argc < 4)) {
        std::fprintf(stderr, "usage: mesh2sdf_points MESH GRID.npy [THREADS]\n"
                             "       mesh2sdf_points MESH --samples SAMPLES.npy [THREADS]\n");
        return 2;
    }
    const int threadArg = samples ? 4 : 3;
    std::unique_ptr<tbb::global_control> threads;
    if (argc > threadArg && std::atoi(argv[threadArg]) > 0)
        threads.reset(
            new tbb::global_control(tbb::global_control::max_allowed_parallelism, size_t(std::atoi(argv[threadArg]))));
    TriangleMesh mesh;
    std::string error;
    if (!loadMesh(argv[1], mesh, error)) {
        std::fprintf(stderr, "mesh2sdf_points: %s\n", error.c_str());
        return 1;
    }
    if (samples) {
        double *values = nullptr;
        size_t count = 0;
        char why[1024];
        if (npy_read_rows(argv[3], 4, &values, &count, why, sizeof why) != 0) {
            std::fprintf(stderr, "mesh2sdf_points: %s\n", why);
            return 1;
        }
        const std::vector<double> rows(values, values + count * 4);
        std::free(values);
        std::vector<float> d(count);
        for (size_t i = 0; i < count; ++i)
            d[i] = float(rows[i * 4 + 3]);
        compare(
            mesh, count,
            [&](size_t i, Vec3 &q) {
                q = {rows[i * 4], rows[i * 4 + 1], rows[i * 4 + 2]};
            },
            d, 1.0, "max_error");
        return 0;
    }
    const std::string npy = argv[2];
    std::ifstream sidecar(npy.substr(0, npy.size() - 4) + ".json");
    std::stringstream text;
    text << sidecar.rdbuf();
    const std::string json = text.str();
    double origin[3], h = jsonNumber(json, "\"voxel_size\"", 0);
    int n[3];
    for (int k = 0; k < 3; ++k) {
        origin[k] = jsonNumber(json, "\"origin\"", k);
        n[k] = int(jsonNumber(json, "\"shape\"", k));
    }
    const size_t count = size_t(n[0]) * n[1] * n[2];
    std::vector<float> grid;
    if (!(h > 0) || !readNpy(npy, count, grid)) {
        std::fprintf(stderr, "mesh2sdf_points: cannot read %s and its .json\n", npy.c_str());
        return 1;
    }
    compare(
        mesh, count,
        [&](size_t i, Vec3 &q) {
            const size_t x = i / (size_t(n[1]) * n[2]), y = i / n[2] % n[1], z = i % n[2];
            q = {origin[0] + x * h, origin[1] + y * h, origin[2] + z * h};
        },
        grid, h, "max_error_voxels");
    return 0;
}
