// The winding tree (src/mesh/sign/winding.h) measured: its error against the
// sum over every triangle, the time a point of its three evaluations takes
// (the fast value, the sign, the sign at the exact accuracy, the exact value), the time its tree takes to
// build with 1 and more threads, and instructions a point under callgrind.
// bench/winding.sh runs it and writes bench/results/winding.md.
//
// usage: winding MESH accuracy [NEAR UNIFORM]     errors (Markdown row cells)
//        winding MESH time ROUNDS [NEAR UNIFORM]  per round: "fast side side-exact exact" us a point
//        winding MESH build ROUNDS THREADS...     per round: seconds per thread count
//        winding MESH count MODE [POINTS]         MODE's queries alone, for callgrind (no AVX2)
//        winding SHAPE obj OUT.obj                a generated mesh as OBJ
// MESH: a file mesh2sdf reads, or a shape made in code: cut-sphere,
// scan-patch, nested-shells, cube-block, gear-train. Points: NEAR on the
// surface moved along the normal by 1e-4 to 5e-2 of the size (both ways),
// UNIFORM in the box grown to three times its size (tests/support/mesh_shapes.h). One thread (TBB) for
// the queries. The reference sum uses the tree's own solid angle (atan to
// 1e-9 rad): its error is far below the fast evaluation's, and at most the
// triangles times 1.6e-10 for the exact one's.
#include "sign/winding.h"
#include "io/mesh_io.h"

#include "../tests/support/mesh_shapes.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#endif

#include <algorithm>
#include <chrono>
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

bool shape(const std::string &name, shapes::Soup &s)
{
    if (name == "cut-sphere")
        s = shapes::cutSphere();
    else if (name == "scan-patch")
        s = shapes::scanPatch();
    else if (name == "nested-shells")
        s = shapes::nestedShells(4);
    else if (name == "cube-block")
        s = shapes::cubeGrid(6, 3);
    else if (name == "gear-train")
        s = shapes::gearTrain(6);
    else
        return false;
    return true;
}

shapes::Soup load(const std::string &name)
{
    shapes::Soup s;
    if (shape(name, s))
        return s;
    TriangleMesh mesh;
    std::string error;
    if (!loadMesh(name, mesh, error)) {
        std::fprintf(stderr, "winding: %s\n", error.c_str());
        std::exit(1);
    }
    s.points = mesh.points;
    s.triangles = mesh.triangles;
    return s;
}

std::vector<Vec3> points(const shapes::Soup &s, int near, int uniform)
{
    std::vector<Vec3> out = shapes::nearPoints(s, near, 1);
    const std::vector<Vec3> far = shapes::farPoints(s, uniform, 2);
    out.insert(out.end(), far.begin(), far.end());
    return out;
}

double seconds(std::chrono::steady_clock::time_point since)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Largest and median error of `eval` against the reference sum.
template <class Eval> void errors(const std::vector<double> &truth, const std::vector<Vec3> &q, Eval eval)
{
    std::vector<double> e(q.size());
    for (size_t i = 0; i < q.size(); ++i)
        e[i] = std::abs(eval(q[i]) - truth[i]);
    std::sort(e.begin(), e.end());
    std::printf(" %.1e | %.1e |", e[e.size() / 2], e.back());
}

} // namespace

int main(int argc, char **argv)
{
    if (argc < 3) {
        std::fprintf(stderr, "usage: winding MESH accuracy|time|build|count|obj ...\n");
        return 2;
    }
    const std::string mode = argv[2];
    if (mode == "obj") {
        shapes::Soup s;
        if (argc < 4 || !shape(argv[1], s))
            return 2;
        FILE *f = std::fopen(argv[3], "w");
        if (!f)
            return 1;
        for (const auto &p : s.points)
            std::fprintf(f, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
        for (const auto &t : s.triangles)
            std::fprintf(f, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
        return std::fclose(f) == 0 ? 0 : 1;
    }
    const shapes::Soup s = load(argv[1]);
    if (mode == "build") {
        // Rounds of one build per thread count, in turns.
        const int rounds = argc > 3 ? std::atoi(argv[3]) : 5;
        for (int r = 0; r < rounds; ++r) {
            for (int a = 4; a < argc; ++a) {
                tbb::task_arena arena(std::atoi(argv[a]));
                const auto start = std::chrono::steady_clock::now();
                arena.execute([&] { FastWinding tree(s.points, s.triangles); });
                std::printf("%s%.6f", a > 4 ? " " : "", seconds(start));
            }
            std::printf("\n");
        }
        return 0;
    }
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    // Without AVX2 for callgrind, which does not run every AVX2 instruction.
    const FastWinding tree(s.points, s.triangles, mode != "count");
    if (mode == "count") {
        const std::string what = argc > 3 ? argv[3] : "fast";
        const std::vector<Vec3> q = points(s, argc > 4 ? std::atoi(argv[4]) : 2000, 0);
        double sum = 0;
        CALLGRIND_START_INSTRUMENTATION;
        for (const Vec3 &p : q)
            sum += what == "side"         ? tree.side(p).w
                   : what == "side-exact" ? tree.side(p, WindingAccuracy::Exact).w
                   : what == "exact"      ? tree.exact(p).w
                                          : tree(p);
        CALLGRIND_STOP_INSTRUMENTATION;
        std::printf("%zu points, sum %g\n", q.size(), sum);
        return 0;
    }
    const int near = argc > 4 ? std::atoi(argv[argc - 2]) : 1000, uniform = argc > 4 ? std::atoi(argv[argc - 1]) : 500;
    const std::vector<Vec3> q = points(s, near, uniform);
    if (mode == "accuracy") {
        // | triangles | fast median | fast max | exact median | exact max |
        // exact's largest proven bound | signs wrong (fast, exact) |
        std::vector<double> truth(q.size());
        for (size_t i = 0; i < q.size(); ++i)
            truth[i] = tree.bruteForce(q[i]);
        std::printf("%zu |", s.triangles.size());
        errors(truth, q, [&](const Vec3 &p) { return tree(p); });
        errors(truth, q, [&](const Vec3 &p) { return tree.exact(p).w; });
        double bound = 0;
        int wrong = 0, wrongExact = 0;
        for (size_t i = 0; i < q.size(); ++i) {
            bound = std::max(bound, tree.exact(q[i]).bound);
            wrong += std::abs(truth[i] - 0.5) > 5e-3 && (tree.side(q[i]).w > 0.5) != (truth[i] > 0.5);
            wrongExact += std::abs(truth[i] - 0.5) > 1e-6 &&
                          (tree.side(q[i], WindingAccuracy::Exact).w > 0.5) != (truth[i] > 0.5);
        }
        std::printf(" %.1e | %d, %d |\n", bound, wrong, wrongExact);
        return 0;
    }
    if (mode == "time") {
        const int rounds = std::atoi(argv[3]);
        double sink = 0;
        for (int r = 0; r < rounds; ++r) {
            auto start = std::chrono::steady_clock::now();
            for (const Vec3 &p : q)
                sink += tree(p);
            const double fast = seconds(start);
            start = std::chrono::steady_clock::now();
            for (const Vec3 &p : q)
                sink += tree.side(p).w;
            const double side = seconds(start);
            start = std::chrono::steady_clock::now();
            for (const Vec3 &p : q)
                sink += tree.side(p, WindingAccuracy::Exact).w;
            const double sideExact = seconds(start);
            start = std::chrono::steady_clock::now();
            for (const Vec3 &p : q)
                sink += tree.exact(p).w;
            const double exact = seconds(start);
            const double n = double(q.size()) * 1e-6;
            std::printf("%.4f %.4f %.4f %.4f\n", fast / n, side / n, sideExact / n, exact / n);
        }
        return sink == 12345.678; // keeps the sums
    }
    std::fprintf(stderr, "winding: unknown mode %s\n", mode.c_str());
    return 2;
}
