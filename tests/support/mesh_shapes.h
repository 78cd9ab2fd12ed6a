// Meshes made in code for the winding-number tests: open ones (a cut
// sphere, a scan-like patch, a mesh with faces removed) and assemblies of
// closed parts (touching cubes, nested shells, a gear train). Plain arrays:
// points and triangles, outward-facing where the shape has an outside; as
// mesh_support.h's mesh for its brute-force winding number and distance.
#ifndef SDFT_TESTS_MESH_SHAPES_H
#define SDFT_TESTS_MESH_SHAPES_H

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

extern "C" {
#include "mesh_support.h"
}

namespace shapes
{

struct Soup {
    std::vector<std::array<float, 3>> points;
    std::vector<std::array<uint32_t, 3>> triangles;

    uint32_t add(double x, double y, double z)
    {
        points.push_back({float(x), float(y), float(z)});
        return uint32_t(points.size() - 1);
    }
    void triangle(uint32_t a, uint32_t b, uint32_t c) { triangles.push_back({a, b, c}); }
    void quad(uint32_t a, uint32_t b, uint32_t c, uint32_t d)
    {
        triangle(a, b, c);
        triangle(a, c, d);
    }
    // Appends another soup's triangles on its own vertices.
    void append(const Soup &o)
    {
        const uint32_t base = uint32_t(points.size());
        points.insert(points.end(), o.points.begin(), o.points.end());
        for (const auto &t : o.triangles)
            triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
};

constexpr double kPi = 3.14159265358979323846;

// A sphere of `rings` x `segments` quads (fans at the poles), outward,
// keeping only the rings whose polar angle starts below `maxPolar` (pi: the
// whole sphere, closed). `noise`: each vertex moved radially by up to that
// fraction of the radius (a scan's roughness), the same at the seam.
inline Soup sphere(double cx, double cy, double cz, double radius, int rings, int segments, double maxPolar = kPi,
                   double noise = 0, uint64_t seed = 1)
{
    Soup s;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<uint32_t> grid; // (rings - 1) x segments, then the poles
    for (int r = 1; r < rings; ++r) {
        const double theta = kPi * r / rings;
        for (int k = 0; k < segments; ++k) {
            const double phi = 2 * kPi * k / segments, rr = radius * (1 + noise * u(rng));
            grid.push_back(s.add(cx + rr * std::sin(theta) * std::cos(phi), cy + rr * std::sin(theta) * std::sin(phi),
                                 cz + rr * std::cos(theta)));
        }
    }
    const uint32_t top = s.add(cx, cy, cz + radius), bottom = s.add(cx, cy, cz - radius);
    auto at = [&](int r, int k) { return grid[size_t(r - 1) * segments + size_t((k + segments) % segments)]; };
    for (int k = 0; k < segments; ++k)
        s.triangle(top, at(1, k), at(1, k + 1));
    for (int r = 1; r + 1 < rings; ++r) {
        if (kPi * r / rings >= maxPolar)
            break;
        for (int k = 0; k < segments; ++k)
            s.quad(at(r, k), at(r + 1, k), at(r + 1, k + 1), at(r, k + 1));
    }
    if (maxPolar >= kPi)
        for (int k = 0; k < segments; ++k)
            s.triangle(bottom, at(rings - 1, k + 1), at(rings - 1, k));
    return s;
}

// An axis-aligned box from lo to hi, each face split into n x n quads,
// outward.
inline Soup box(const double lo[3], const double hi[3], int n = 1)
{
    Soup s;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            std::vector<uint32_t> ids;
            for (int i = 0; i <= n; ++i)
                for (int j = 0; j <= n; ++j) {
                    double p[3];
                    p[axis] = side ? hi[axis] : lo[axis];
                    p[u] = lo[u] + (hi[u] - lo[u]) * i / n;
                    p[v] = lo[v] + (hi[v] - lo[v]) * j / n;
                    ids.push_back(s.add(p[0], p[1], p[2]));
                }
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    const uint32_t a = ids[i * (n + 1) + j], b = ids[(i + 1) * (n + 1) + j];
                    const uint32_t c = ids[(i + 1) * (n + 1) + j + 1], d = ids[i * (n + 1) + j + 1];
                    // (u, v, axis) is right-handed: u x v = +axis.
                    if (side)
                        s.quad(a, b, c, d);
                    else
                        s.quad(a, d, c, b);
                }
        }
    return s;
}

// k x k x k unit cubes side by side, each closed on its own: every inner
// face is two coincident faces of opposite orientation. `subdivide`: each
// cube's faces split into 1 + (cube index % subdivide) quads a side, so
// that touching faces are meshed differently (T-junctions) when > 1.
inline Soup cubeGrid(int k, int subdivide = 1)
{
    Soup s;
    int index = 0;
    for (int x = 0; x < k; ++x)
        for (int y = 0; y < k; ++y)
            for (int z = 0; z < k; ++z, ++index) {
                const double lo[3] = {double(x), double(y), double(z)}, hi[3] = {x + 1.0, y + 1.0, z + 1.0};
                s.append(box(lo, hi, 1 + index % subdivide));
            }
    return s;
}

// Concentric spheres, all outward: the winding number is the number of
// shells around a point.
inline Soup nestedShells(int count)
{
    Soup s;
    for (int i = 0; i < count; ++i)
        s.append(sphere(0, 0, 0, 1.0 - 0.8 * i / count, 24, 48));
    return s;
}

// A spur gear (closed prism over a toothed outline) centred at (cx, cy),
// `teeth` teeth between radii `root` and `tip`, from z0 to z1, turned by
// `phase` radians.
inline Soup gear(double cx, double cy, int teeth, double root, double tip, double z0, double z1, double phase)
{
    Soup s;
    const int perTooth = 8;
    const int n = teeth * perTooth;
    std::vector<double> ox(n), oy(n);
    for (int i = 0; i < n; ++i) {
        const double a = phase + 2 * kPi * i / n;
        const int step = i % perTooth; // 0-3: tip, 4-7: root, with flanks between
        const double r = step < 3 ? tip : step == 3 || step == 7 ? 0.5 * (root + tip) : root;
        ox[i] = cx + r * std::cos(a);
        oy[i] = cy + r * std::sin(a);
    }
    const uint32_t c0 = s.add(cx, cy, z0), c1 = s.add(cx, cy, z1);
    std::vector<uint32_t> lo(n), hi(n);
    for (int i = 0; i < n; ++i) {
        lo[i] = s.add(ox[i], oy[i], z0);
        hi[i] = s.add(ox[i], oy[i], z1);
    }
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        s.triangle(c1, hi[i], hi[j]);       // top, +z
        s.triangle(c0, lo[j], lo[i]);       // bottom, -z
        s.quad(lo[i], lo[j], hi[j], hi[i]); // side, outward (counter-clockwise outline)
    }
    return s;
}

// Gears in a row on a plate, each gear's teeth reaching into the next's
// (interpenetrating where they mesh), the plate touching every gear's
// bottom face.
inline Soup gearTrain(int count)
{
    Soup s;
    const double root = 0.8, tip = 1.0, spacing = root + tip;
    for (int i = 0; i < count; ++i)
        s.append(gear(i * spacing, 0, 12, root, tip, 0, 0.5, i % 2 ? kPi / 12 : 0));
    const double lo[3] = {-1.2, -1.2, -0.3}, hi[3] = {(count - 1) * spacing + 1.2, 1.2, 0.0};
    s.append(box(lo, hi, 4));
    return s;
}

// A scan-like open patch: a bumpy cap of a sphere (polar angle up to
// 110 degrees), rough like a scan, open at its rim.
inline Soup scanPatch() { return sphere(0, 0, 0, 1, 60, 120, 110 * kPi / 180, 0.01, 7); }

// A cut sphere: the cap above z = 0.5 removed.
inline Soup cutSphere() { return sphere(0, 0, 0, 1, 48, 96, std::acos(-0.5), 0, 1); }

// The soup's bounding box and its longest side.
struct Bounds {
    double lo[3], hi[3], size;
};
inline Bounds boundsOf(const Soup &s)
{
    Bounds b{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}, 0};
    for (const auto &t : s.triangles)
        for (uint32_t v : t)
            for (int k = 0; k < 3; ++k) {
                b.lo[k] = std::min(b.lo[k], double(s.points[v][k]));
                b.hi[k] = std::max(b.hi[k], double(s.points[v][k]));
            }
    for (int k = 0; k < 3; ++k)
        b.size = std::max(b.size, b.hi[k] - b.lo[k]);
    return b;
}

using Point = std::array<double, 3>;

// Points near the surface: on random triangles (by area), moved along the
// normal by 1e-4 to 5e-2 of the soup's size, log-uniform, either way (the
// inside of an open scan too).
inline std::vector<Point> nearPoints(const Soup &s, int count, uint64_t seed)
{
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    auto normal = [&](const std::array<uint32_t, 3> &t, double *e1, double *e2, double *n) {
        for (int k = 0; k < 3; ++k) {
            e1[k] = s.points[t[1]][k] - s.points[t[0]][k];
            e2[k] = s.points[t[2]][k] - s.points[t[0]][k];
        }
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        return std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    };
    std::vector<double> sums;
    double total = 0, e1[3], e2[3], n[3];
    for (const auto &t : s.triangles)
        sums.push_back(total += normal(t, e1, e2, n));
    const double size = boundsOf(s).size;
    std::vector<Point> points;
    while (int(points.size()) < count) {
        const size_t i = std::min(size_t(std::lower_bound(sums.begin(), sums.end(), u(rng) * total) - sums.begin()),
                                  sums.size() - 1);
        const auto &t = s.triangles[i];
        double a = u(rng), b = u(rng);
        if (a + b > 1) {
            a = 1 - a;
            b = 1 - b;
        }
        const double len = normal(t, e1, e2, n);
        if (!(len > 0))
            continue;
        const double offset = size * std::pow(10.0, -4 + 2.7 * u(rng)) * (u(rng) < 0.5 ? -1 : 1);
        Point p;
        for (int k = 0; k < 3; ++k)
            p[k] = s.points[t[0]][k] + a * e1[k] + b * e2[k] + offset * n[k] / len;
        points.push_back(p);
    }
    return points;
}

// Points uniform in the soup's box grown to three times its size.
inline std::vector<Point> farPoints(const Soup &s, int count, uint64_t seed)
{
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const Bounds b = boundsOf(s);
    std::vector<Point> points(static_cast<size_t>(count));
    for (Point &p : points)
        for (int k = 0; k < 3; ++k)
            p[k] = b.lo[k] - (b.hi[k] - b.lo[k]) + 3 * (b.hi[k] - b.lo[k]) * u(rng);
    return points;
}

// A soup as mesh_support.h's mesh (brute force: winding, mesh_distance),
// freed with it.
struct Brute {
    mesh m{};
    explicit Brute(const Soup &s)
    {
        for (const auto &p : s.points)
            mesh_vertex(&m, p[0], p[1], p[2]);
        for (const auto &t : s.triangles)
            mesh_triangle(&m, int(t[0]), int(t[1]), int(t[2]));
    }
    ~Brute() { mesh_free(&m); }
    Brute(const Brute &) = delete;
    Brute &operator=(const Brute &) = delete;
    double winding(const double *q) const { return ::winding(&m, q); }
    double distance(const double *q) const { return mesh_distance(&m, q); }
};

// The soup without every `every`-th triangle (holes all over it).
inline Soup withoutFaces(const Soup &in, int every)
{
    Soup s;
    s.points = in.points;
    for (size_t i = 0; i < in.triangles.size(); ++i)
        if (i % size_t(every) != 0)
            s.triangles.push_back(in.triangles[i]);
    return s;
}

} // namespace shapes

#endif
