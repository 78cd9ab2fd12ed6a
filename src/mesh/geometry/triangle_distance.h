// sdftrace — the squared distance from a point to a triangle by its
// closest-point regions, for the winding tree's nearest-triangle search
// (sign/winding.cpp), which the per-point bench query and the off-band clearance
// use. The band and the dense search use distance/packet_rows.h's branch-free form
// instead; the bench's comparison of the two grids is then a check between
// two independent formulas. No OpenVDB here.
#ifndef SDFT_MESH_GEOMETRY_TRIANGLE_DISTANCE_H
#define SDFT_MESH_GEOMETRY_TRIANGLE_DISTANCE_H

namespace meshsdf
{

/// Squared distance from p (3 doubles) to triangle t (9 doubles: corners a,
/// b, c): the closest-point regions of Ericson, "Real-Time Collision
/// Detection", section 5.1.5.
inline double triangleDistance2(const double *t, const double *p)
{
    const double *a = t;
    const double *b = t + 3;
    const double *c = t + 6;
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    for (int k = 0; k < 3; ++k) {
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ap[k] = p[k] - a[k];
        bp[k] = p[k] - b[k];
        cp[k] = p[k] - c[k];
    }
    auto dot = [](const double *u, const double *v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
    // Squared distance from p to base + s * edge.
    auto along = [&](const double *base, const double *edge, double s) {
        double d2 = 0;
        for (int k = 0; k < 3; ++k) {
            const double d = p[k] - (base[k] + s * edge[k]);
            d2 += d * d;
        }
        return d2;
    };
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0)
        return dot(ap, ap);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3)
        return dot(bp, bp);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
        return along(a, ab, d1 / (d1 - d3));
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6)
        return dot(cp, cp);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
        return along(a, ac, d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double bc[3] = {c[0] - b[0], c[1] - b[1], c[2] - b[2]};
        return along(b, bc, (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    const double denom = 1.0 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    double d = 0;
    for (int k = 0; k < 3; ++k) {
        const double e = p[k] - (a[k] + ab[k] * v + ac[k] * w);
        d += e * e;
    }
    return d;
}

} // namespace meshsdf

#endif
