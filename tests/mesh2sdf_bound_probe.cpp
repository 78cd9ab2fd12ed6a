// The bounds on the winding number's gradient that mesh2sdf's sign rests on
// (convert/winding_sign.cpp), held to the brute-force winding number of a
// mesh at random points near its open edges. test_mesh2sdf runs it.
//
// usage: mesh2sdf_bound_probe MESH [SAMPLES]   (any mesh mesh2sdf reads)
// Prints one line per bound with the largest ratio of the measured change to
// the bound (must stay <= 1), and exits 1 if any exceeds it.
#include "io/mesh_io.h"
#include "sign/winding.h"
#include "sign/winding_sign.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

using namespace meshsdf;

namespace
{

double norm(const double *v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

} // namespace

int main(int argc, char **argv)
{
    if (argc < 2)
        return 2;
    TriangleMesh mesh;
    std::string error;
    if (!loadMesh(argv[1], mesh, error)) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 2;
    }
    const int samples = argc > 2 ? std::atoi(argv[2]) : 300;
    const double *lo = mesh.lo.data(), *hi = mesh.hi.data();
    const double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    const FastWinding winding(mesh.points, mesh.triangles);
    const EdgeField field(mesh);
    if (field.edges().empty()) {
        std::printf("no open edges\n");
        return 0;
    }
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(0, 1);
    auto w = [&](const double *p) { return winding.bruteForce({p[0], p[1], p[2]}); };
    auto clearance = [&](const double *p) { return winding.distance({p[0], p[1], p[2]}); };
    // A point near a random open edge, at up to `spread` times the mesh's size.
    auto nearEdge = [&](double spread, double *p) {
        const OpenEdge &e = field.edges()[size_t(unit(rng) * double(field.edges().size())) % field.edges().size()];
        const double t = unit(rng), r = spread * size * std::pow(unit(rng), 2);
        for (int k = 0; k < 3; ++k)
            p[k] = e.a[k] + t * (e.b[k] - e.a[k]) + r * (2 * unit(rng) - 1);
    };
    // Central differences of the brute-force w; `delta` tiny against the
    // distances kept from the mesh, so their error is far below the margins.
    const double delta = 1e-6 * size;
    auto gradient = [&](const double *p, double *g) {
        for (int k = 0; k < 3; ++k) {
            double a[3] = {p[0], p[1], p[2]}, b[3] = {p[0], p[1], p[2]};
            a[k] -= delta;
            b[k] += delta;
            g[k] = (w(b) - w(a)) / (2 * delta);
        }
    };
    double worstField = 0, worstBox = 0, worstStep = 0;
    int fieldCount = 0, boxCount = 0, stepCount = 0;
    for (int s = 0; s < samples; ++s) {
        // The exact field: |B| against the measured gradient, both ways.
        double p[3], g[3], B[3];
        nearEdge(0.05, p);
        if (clearance(p) > 1e-3 * size) {
            gradient(p, g);
            field.field(p, B);
            double diff[3], sum[3];
            for (int k = 0; k < 3; ++k) {
                diff[k] = g[k] - B[k];
                sum[k] = g[k] + B[k];
            }
            const double ratio = std::min(norm(diff), norm(sum)) / (1e-3 * norm(g) + 1e-10 / delta);
            if (getenv("PROBE_VERBOSE") && ratio > 1)
                std::printf("g %g %g %g B %g %g %g clearance %g\n", g[0], g[1], g[2], B[0], B[1], B[2],
                            clearance(p) / size);
            worstField = std::max(worstField, ratio);
            ++fieldCount;
        }
        // The bound over a box, inflated, at points of it: near the edges
        // (edge by edge) and far from them (whole groups of edges).
        const bool far = s % 2;
        double c[3], half = (far ? 0.01 : 0.03) * size * unit(rng), inflate = 0.01 * size * unit(rng), blo[3], bhi[3];
        nearEdge(far ? 1.0 : 0.1, c);
        for (int k = 0; k < 3; ++k) {
            blo[k] = c[k] - half;
            bhi[k] = c[k] + half;
        }
        const double bound = field.overBox(blo, bhi, inflate);
        for (int i = 0; i < 4; ++i) {
            double x[3];
            for (int k = 0; k < 3; ++k)
                x[k] = blo[k] - inflate / std::sqrt(3.0) + unit(rng) * (bhi[k] - blo[k] + 2 * inflate / std::sqrt(3.0));
            if (clearance(x) < 1e-3 * size)
                continue;
            gradient(x, g);
            worstBox = std::max(worstBox, norm(g) / (bound * (1 + 1e-4)));
            ++boxCount;
        }
        // The trapezoid rule along a step that crosses no mesh point.
        double a[3], b[3], Ba[3], Bb[3];
        nearEdge(0.05, a);
        const double length = 0.02 * size * unit(rng);
        double dir[3] = {2 * unit(rng) - 1, 2 * unit(rng) - 1, 2 * unit(rng) - 1};
        const double n = norm(dir);
        for (int k = 0; k < 3; ++k)
            b[k] = a[k] + length * dir[k] / n;
        if (!(clearance(a) + clearance(b) > length * (1 + 1e-6)) || clearance(a) < 1e-4 * size)
            continue;
        field.field(a, Ba);
        field.field(b, Bb);
        double dot = 0;
        for (int k = 0; k < 3; ++k)
            dot += (Ba[k] + Bb[k]) * (b[k] - a[k]);
        const double K = std::max(field.curvature(a, length / 2), field.curvature(b, length / 2));
        const double stepBound = std::abs(dot) / 2 + length * length * length / 12 * K;
        worstStep = std::max(worstStep, std::abs(w(b) - w(a)) / (stepBound * (1 + 1e-4) + 1e-9));
        ++stepCount;
    }
    // Far from every open edge, where overBox bounds them by groups (their
    // chord and their dipole-like remainder), not edge by edge: points at 2
    // to 20 times the radius R of all the open edges' ends around their
    // centroid (log-uniform), each in a tiny box. Around one small hole the
    // bound is within a few times the field there, so a weakened remainder
    // shows.
    double centroid[3] = {0, 0, 0}, radius = 0;
    for (const OpenEdge &e : field.edges())
        for (int k = 0; k < 3; ++k)
            centroid[k] += 0.5 * (e.a[k] + e.b[k]) / double(field.edges().size());
    for (const OpenEdge &e : field.edges()) {
        const double da[3] = {e.a[0] - centroid[0], e.a[1] - centroid[1], e.a[2] - centroid[2]};
        const double db[3] = {e.b[0] - centroid[0], e.b[1] - centroid[1], e.b[2] - centroid[2]};
        radius = std::max({radius, norm(da), norm(db)});
    }
    double worstFar = 0;
    int farCount = 0;
    for (int s = 0; s < samples; ++s) {
        double u[3] = {2 * unit(rng) - 1, 2 * unit(rng) - 1, 2 * unit(rng) - 1}, p[3], lo[3], hi[3], g[3];
        const double n = norm(u), distance = radius * 2 * std::pow(10.0, unit(rng)), half = 1e-4 * size;
        for (int k = 0; k < 3; ++k) {
            p[k] = centroid[k] + distance * u[k] / n;
            lo[k] = p[k] - half;
            hi[k] = p[k] + half;
        }
        if (clearance(p) < 1e-2 * size)
            continue;
        gradient(p, g);
        worstFar = std::max(worstFar, norm(g) / (field.overBox(lo, hi, 0) * (1 + 1e-4)));
        ++farCount;
    }
    std::printf("field: %d points, largest error / tolerance %.4f\n", fieldCount, worstField);
    std::printf("far bound: %d points, largest |grad w| / bound %.4f\n", farCount, worstFar);
    std::printf("box bound: %d points, largest |grad w| / bound %.4f\n", boxCount, worstBox);
    std::printf("step bound: %d steps, largest |change of w| / bound %.4f\n", stepCount, worstStep);
    return worstField <= 1 && worstBox <= 1 && worstStep <= 1 && worstFar <= 1 && fieldCount > samples / 4 &&
                   boxCount > samples && stepCount > samples / 10 && farCount > samples / 4
               ? 0
               : 1;
}
