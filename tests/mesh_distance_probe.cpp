// The point distances (src/mesh/distance/wide_tree.h) held to brute force.
// At points near, on, far and very far from a mesh, WideTree's squared
// distance must equal the smallest preparedDistance2 over every triangle bit
// for bit: with AVX2 and with scalar lanes, one point at a time, from a
// seed triangle, in packets of eight, and along the list of points (packets
// where they are close, one at a time elsewhere). With --degenerate the mesh also
// gets triangles of no area (the loaders drop those: they come from the
// arrays here), a segment, a repeated corner and a point. test_point_distance
// runs it and compares the distances it writes with its own brute force (an
// independent formula).
//
// usage: mesh_distance_probe MESH OUT N SEED [--degenerate]
// Writes OUT: N rows of 4 doubles (x, y, z, distance) for the mesh as read
// (without the added triangles), and prints one line
//   points=N triangles=T brute=K scalar=K seeded=K packets=K along=K
// each K the number of points whose answer differs from the brute force's
// in any bit; exits 1 if any is not 0.
#include "distance/packet_rows.h"
#include "distance/wide_tree.h"
#include "io/mesh_io.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

using namespace meshsdf;

namespace
{

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The brute force: the smallest preparedDistance2 over every triangle.
double bruteForce(const std::vector<PreparedTriangle> &all, const double *p)
{
    double best = INFINITY;
    for (const PreparedTriangle &t : all)
        best = std::min(best, preparedDistance2(t, p));
    return best;
}

// Points of every kind around the mesh in its box [lo, lo + size]: a
// sixth each uniform in the box grown threefold, near a random triangle
// (a point of it moved by a Gaussian of 1e-4 to 1e-1 of the size), on a
// triangle (a corner, an edge's midpoint or an inner point), very far
// (1e4 sizes), and clusters of eight around one point, tight and loose.
std::vector<double> points(const TriangleMesh &mesh, int n, unsigned seed)
{
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> uniform(0, 1);
    std::normal_distribution<double> gaussian(0, 1);
    double lo[3], size = 0;
    for (int k = 0; k < 3; ++k) {
        lo[k] = mesh.lo[k];
        size = std::max(size, mesh.hi[k] - mesh.lo[k]);
    }
    auto onTriangle = [&](double *p, int kind) {
        const auto &t = mesh.triangles[random() % mesh.triangles.size()];
        double a = uniform(random), b = uniform(random);
        if (a + b > 1) {
            a = 1 - a;
            b = 1 - b;
        }
        if (kind == 0)
            a = b = 0; // a corner
        else if (kind == 1)
            a = 0.5, b = 0; // an edge's midpoint
        for (int k = 0; k < 3; ++k)
            p[k] = double(mesh.points[t[0]][k]) + a * (double(mesh.points[t[1]][k]) - mesh.points[t[0]][k]) +
                   b * (double(mesh.points[t[2]][k]) - mesh.points[t[0]][k]);
    };
    std::vector<double> xyz(size_t(n) * 3);
    for (int i = 0; i < n; ++i) {
        double *p = &xyz[size_t(i) * 3];
        switch (i / 8 % 6) {
        case 0:
            for (int k = 0; k < 3; ++k)
                p[k] = lo[k] - size + 3 * size * uniform(random);
            break;
        case 1: {
            onTriangle(p, 2);
            const double sigma = size * std::pow(10.0, -4 + 3 * uniform(random));
            for (int k = 0; k < 3; ++k)
                p[k] += sigma * gaussian(random);
            break;
        }
        case 2:
            onTriangle(p, int(random() % 3));
            break;
        case 3:
            for (int k = 0; k < 3; ++k)
                p[k] = lo[k] + size * 1e4 * gaussian(random);
            break;
        default: {
            // eight points around the first of the cluster
            if (i % 8 == 0) {
                onTriangle(p, 2);
                for (int k = 0; k < 3; ++k)
                    p[k] += 0.05 * size * gaussian(random);
            } else {
                const double spread = size * (i / 8 % 6 == 4 ? 1e-3 : 0.2);
                for (int k = 0; k < 3; ++k)
                    p[k] = xyz[size_t(i - i % 8) * 3 + k] + spread * gaussian(random);
            }
        }
        }
    }
    return xyz;
}

} // namespace

int main(int argc, char **argv)
{
    if (argc < 5) {
        std::fprintf(stderr, "usage: mesh_distance_probe MESH OUT N SEED [--degenerate]\n");
        return 2;
    }
    TriangleMesh mesh;
    std::string error;
    if (!loadMesh(argv[1], mesh, error)) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 2;
    }
    const int n = std::max(8, std::atoi(argv[3]) / 8 * 8);
    const std::vector<double> xyz = points(mesh, n, unsigned(std::atoi(argv[4])));
    const size_t asRead = mesh.triangles.size();
    if (argc > 5 && std::strcmp(argv[5], "--degenerate") == 0) {
        // A segment (three points on a line), a repeated corner, a point,
        // each on a corner of the mesh so that some points are near them.
        const uint32_t first = uint32_t(mesh.points.size());
        // A copy: the corner moves when the points grow.
        const std::array<float, 3> c = mesh.points[mesh.triangles[0][0]];
        const float step = float(0.25 * (mesh.hi[0] - mesh.lo[0]));
        mesh.points.push_back({c[0] + step, c[1], c[2]});
        mesh.points.push_back({c[0] + 2 * step, c[1], c[2]});
        mesh.triangles.push_back({mesh.triangles[0][0], first, first + 1});
        mesh.triangles.push_back({first, first, mesh.triangles[0][1]});
        mesh.triangles.push_back({first + 1, first + 1, first + 1});
    }
    std::vector<PreparedTriangle> all(mesh.triangles.size());
    for (size_t t = 0; t < all.size(); ++t) {
        double corner[3][3];
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k)
                corner[v][k] = mesh.points[mesh.triangles[t][v]][k];
        all[t] = prepareTriangle(corner[0], corner[1], corner[2]);
    }
    const WideTree simd(mesh, true), scalar(mesh, false);

    int brute = 0, lanes = 0, seeded = 0, packets = 0, along = 0;
    std::vector<const double *> list(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
        list[size_t(i)] = &xyz[size_t(i) * 3];
    std::vector<WideTree::Nearest> runs(static_cast<size_t>(n));
    uint32_t near = WideTree::kNone;
    simd.nearestAlong(list.data(), size_t(n), runs.data(), &near);
    std::vector<double> rows(size_t(n) * 4);
    std::mt19937 pick(7);
    for (int i = 0; i < n; i += 8) {
        const double *p[8];
        WideTree::Nearest io[8];
        for (int j = 0; j < 8; ++j) {
            p[j] = &xyz[size_t(i + j) * 3];
            io[j] = j % 2 ? simd.seed(p[j], uint32_t(pick() % mesh.triangles.size())) : WideTree::Nearest{};
        }
        simd.nearestPacket(p, 8, io);
        for (int j = 0; j < 8; ++j) {
            const double truth = bruteForce(all, p[j]);
            const double d2 = simd.nearest(p[j]).d2;
            brute += !same(d2, truth);
            lanes += !same(scalar.nearest(p[j]).d2, truth);
            const WideTree::Nearest start = simd.seed(p[j], uint32_t(pick() % mesh.triangles.size()));
            seeded += !same(simd.nearest(p[j], start).d2, truth);
            packets += !same(io[j].d2, truth);
            along += !same(runs[size_t(i + j)].d2, truth);
            // the file's rows measure the mesh as read, for the independent brute force
            for (int k = 0; k < 3; ++k)
                rows[size_t(i + j) * 4 + k] = p[j][k];
            rows[size_t(i + j) * 4 + 3] =
                std::sqrt(asRead == all.size() ? d2 : bruteForce({all.begin(), all.begin() + long(asRead)}, p[j]));
        }
    }
    FILE *out = std::fopen(argv[2], "wb");
    if (!out || std::fwrite(rows.data(), sizeof(double), rows.size(), out) != rows.size() || std::fclose(out) != 0) {
        std::fprintf(stderr, "cannot write %s\n", argv[2]);
        return 2;
    }
    std::printf("points=%d triangles=%zu brute=%d scalar=%d seeded=%d packets=%d along=%d\n", n, mesh.triangles.size(),
                brute, lanes, seeded, packets, along);
    return brute || lanes || seeded || packets || along ? 1 : 0;
}
