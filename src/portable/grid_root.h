/* sdftrace — the exact first root of a grid's field along a ray, near the
 * surface: the grid's sdft_field_accel.root (field.h, march_loop.h).
 * Portable (portable.h, grid_layout.h): the library's root (grid_root.c)
 * and the shader's walk the same code.
 *
 * THE CUBIC. In the voxel cell with lowest corner i0 (corners at integer
 * index points, values v_abc) the field is the trilinear interpolant
 *     f(u) = sum_abc v_abc X_a(u_x) Y_b(u_y) Z_c(u_z),  X_0 = 1 - u, X_1 = u,
 * with u the cell-local coordinates. Along a ray u(s) = u0 + s du every
 * factor is linear in s, so f(u(s)) is a cubic A + B s + C s^2 + D s^3
 * (Marmitt et al. 2004, "Fast and accurate ray-voxel intersection
 * techniques for iso-surface ray tracing"). Its first root on the segment
 * [0, len] the ray spends in the cell is found with a guarantee. Most
 * cells are settled by the cubic's four Bernstein coefficients on the
 * segment (Farin, "Curves and Surfaces for CAGD", ch. 4: the cubic is
 * their convex combination, and has at most as many roots in the segment
 * as they have sign changes, with the same parity): all > 0, no root;
 * one sign change from > 0 to < 0, one root, bracketed by the segment;
 * where the cubic is a line to within rounding (a plane's interpolant;
 * the argument at THE CHORD, below) the line's root is taken as it is.
 * Otherwise the roots of the derivative (a quadratic) cut the segment into
 * at most three pieces on which the cubic is monotone, and the first piece
 * whose far end is <= 0 brackets the root (its near end is > 0, or the
 * root is its near end). Safeguarded Newton steps close the bracket to
 * 2^-40 of a cell. Everything is in
 * double precision from the float values, so a grazing ray, whose cubic is
 * nearly flat, still gets its root to well under 1e-3 voxel.
 *
 * THE WALK. From t0 the ray visits cells in order (Amanatides and Woo's
 * voxel traversal, in index space: x(t) = x(org) + t W dir for the linear
 * part W of the world-to-index map), solving each segment's cubic. So the
 * root found is the first root of the interpolant on [t0, t]: exactly the
 * surface the grid's field traces, with nothing skipped. The walk stops
 * with "no root before t" where it enters a cell whose eight values are all
 * at least the background (a trilinear cell of such values holds nothing
 * below the background, so the field there is far from 0 and marching is
 * faster), at t1, or after MAX_CELLS cells. Each cell's eight values are
 * one evaluation's worth of reads and are counted as one. */
#ifndef SDFTRACE_GRID_ROOT_H
#define SDFTRACE_GRID_ROOT_H

#include "grid_cell.h"

#define ROOT_MAX_CELLS 64
#define ROOT_MAX_ITERATIONS 100
/* Double constants GLSL has no literal for: 2^-40, 2^-30 and 1e-14. */
#if !defined(SDFT_GLSL)
#define ROOT_BRACKET 0x1p-40
#define ROOT_CHORD 0x1p-30
#define ROOT_FLAT 1e-14
#else
#define ROOT_BRACKET ldexp(1.0lf, -40)
#define ROOT_CHORD ldexp(1.0lf, -30)
#define ROOT_FLAT 1e-14lf
#endif

PORT_INLINE double cubic(const double c[4], double s) { return c[0] + s * (c[1] + s * (c[2] + s * c[3])); }

/* (a0 + a1 s) * (b[0] + b[1] s + ... + b[degree] s^degree): polynomial
 * products, low degree first, into product[0 .. degree + 1]. */
PORT_INLINE void times_linear(const double b[4], int degree, double a0, double a1, PORT_ARRAY_OUT double product[4])
{
    for (int i = 0; i <= degree + 1; i++)
        product[i] = (i <= degree ? a0 * b[i] : 0.0) + (i > 0 ? a1 * b[i - 1] : 0.0);
}

/* The interpolant of v along u0 + s du as a cubic's coefficients c[0..3]. */
PORT_INLINE void cell_cubic(const float v[8], const double u0[3], const double du[3], PORT_ARRAY_OUT double c[4])
{
    double zline[2][4];
    for (int z = 0; z < 2; z++) {
        double yline[2][4];
        for (int y = 0; y < 2; y++) {
            /* Along x: v0 (1 - u) + v1 u, u = u0 + s du. */
            const double v0 = v[2 * y + 4 * z], v1 = v[1 + 2 * y + 4 * z];
            const double line[4] = {v0 + (v1 - v0) * u0[0], (v1 - v0) * du[0], 0.0, 0.0};
            times_linear(line, 1, y != 0 ? u0[1] : 1.0 - u0[1], y != 0 ? du[1] : -du[1], yline[y]);
        }
        double sum[4];
        for (int i = 0; i < 3; i++)
            sum[i] = yline[0][i] + yline[1][i];
        sum[3] = 0.0;
        times_linear(sum, 2, z != 0 ? u0[2] : 1.0 - u0[2], z != 0 ? du[2] : -du[2], zline[z]);
    }
    for (int i = 0; i < 4; i++)
        c[i] = zline[0][i] + zline[1][i];
}

/* The roots of c0 + c1 s + c2 s^2 in (0, len), ascending, in r[0 .. n);
 * n. */
PORT_INLINE int quadratic_roots(double c0, double c1, double c2, double len, PORT_ARRAY_OUT double r[2])
{
    int n = 0;
    double x[2];
    const double scale = fabs(c0) + fabs(c1) * len + fabs(c2) * len * len;
    if (fabs(c2) * len * len <= ROOT_FLAT * scale) { /* linear */
        if (c1 != 0.0)
            x[n++] = -c0 / c1;
    } else {
        const double disc = c1 * c1 - 4.0 * c2 * c0;
        if (disc >= 0.0) {
            const double q = -0.5 * (c1 + copysign(sqrt(disc), c1)); /* no cancellation */
            x[n++] = q / c2;
            if (q != 0.0)
                x[n++] = c0 / q;
        }
    }
    int kept = 0;
    for (int i = 0; i < n; i++)
        if (x[i] > 0.0 && x[i] < len)
            r[kept++] = x[i];
    if (kept == 2 && r[0] > r[1]) {
        const double t = r[0];
        r[0] = r[1];
        r[1] = t;
    }
    return kept;
}

/* The root of the cubic in [a, b], given f(a) > 0 >= f(b): Newton steps
 * from the secant's point, each kept inside the shrinking bracket (a
 * bisection where Newton would leave it), until the bracket or the step is
 * below 2^-40 of the cell. Quadratic convergence near the root, bisection's
 * guarantee away from it. */
PORT_INLINE double bracketed_root(const double c[4], double a, double fa, double b, double fb)
{
    const double tol = ROOT_BRACKET * (1.0 + b - a);
    double x = a + (b - a) * fa / (fa - fb);
    for (int i = 0; i < ROOT_MAX_ITERATIONS && b - a > tol; i++) {
        const double fx = cubic(c, x);
        if (fx > 0.0)
            a = x;
        else
            b = x;
        if (fx == 0.0)
            return x;
        const double slope = c[1] + x * (2.0 * c[2] + x * 3.0 * c[3]);
        double next = slope != 0.0 ? x - fx / slope : 0.5 * (a + b);
        if (!(next > a && next < b))
            next = 0.5 * (a + b);
        if (fabs(next - x) <= tol)
            return fx > 0.0 ? next : x;
        x = next;
    }
    return b;
}

/* The first root in [0, len] of the trilinear interpolant of cell values v
 * (v[k] at corner (k & 1, k >> 1 & 1, k >> 2 & 1)) along u0 + s du in
 * cell-local coordinates: 1 and *s, or 0. */
PORT_INLINE int cell_root(const float v[8], const double u0[3], const double du[3], double len, PORT_OUT(double) s)
{
    double c[4], split[4];
    cell_cubic(v, u0, du, c);
    /* The Bernstein coefficients b0..b3 on [0, len] (the header), times 3
     * (so no division; the signs are b's): b0 = c0, b1 = b0 + a1 / 3, b2 =
     * b1 + (a1 + a2) / 3, b3 = b0 + a1 + a2 + a3, with a_k = c_k len^k. */
    const double a1 = c[1] * len, a2 = c[2] * len * len, a3 = c[3] * len * len * len;
    const double b0 = 3.0 * c[0], b1 = b0 + a1, b2 = b1 + a1 + a2, b3 = b0 + 3.0 * (a1 + a2 + a3);
    if (b0 > 0.0 && b1 > 0.0 && b2 > 0.0 && b3 > 0.0)
        return 0;
    /* Signs + + + -, + + - - or + - - -: one change (a zero coefficient
     * goes the general way). */
    if (b0 > 0.0 && b3 < 0.0 && (b1 > 0.0 ? b2 != 0.0 : b1 < 0.0 && b2 < 0.0)) {
        /* THE CHORD. The line from (0, b0) to (len, b3) has the Bernstein
         * coefficients b0, (2 b0 + b3) / 3, (b0 + 2 b3) / 3, b3; the cubic
         * minus the line has the differences, so |cubic - line| <= delta,
         * the larger of the middle two, on all of [0, len]. The root, where
         * the cubic is 0, is where the line lies in [-delta, delta]: within
         * delta len / (b0 - b3) of the line's own root, the secant point.
         * When that is below 2^-30 of the segment (a plane's interpolant is
         * linear, so delta is rounding), the secant point is the root.
         * With the b here three times those, 9 delta is the larger of
         * |3 b1 - 2 b0 - b3| and |3 b2 - b0 - 2 b3|, and 9 (b0 - b3) is
         * 3 (b0 - b3). */
        const double d1 = fabs(3.0 * b1 - 2.0 * b0 - b3), d2 = fabs(3.0 * b2 - b0 - 2.0 * b3);
        PORT_DEREF(s) = (d1 > d2 ? d1 : d2) <= ROOT_CHORD * 3.0 * (b0 - b3)
                            ? len * b0 / (b0 - b3)
                            : bracketed_root(c, 0.0, c[0], len, c[0] + a1 + a2 + a3);
        return 1;
    }
    double roots[2];
    const int kept = quadratic_roots(c[1], 2.0 * c[2], 3.0 * c[3], len, roots);
    for (int k = 0; k < kept; k++)
        split[1 + k] = roots[k];
    const int pieces = 1 + kept;
    split[0] = 0.0;
    split[pieces] = len;
    double a = 0.0, fa = cubic(c, 0.0);
    if (fa <= 0.0) {
        PORT_DEREF(s) = 0.0;
        return 1;
    }
    for (int k = 1; k <= pieces; k++) {
        const double b = split[k], fb = cubic(c, b);
        if (fb <= 0.0) { /* f(a) > 0 >= f(b), f monotone between: one root */
            PORT_DEREF(s) = bracketed_root(c, a, fa, b, fb);
            return 1;
        }
        a = b;
        fa = fb;
    }
    return 0;
}

/* The walk of the header, for grids of `type`: 1 with t_out the root and
 * normal the unit normal there ((0, 0, 0) where the gradient is too flat),
 * or 0 with t_out the t up to which the ray is free; reads counts the cells
 * read. */
PORT_INLINE int grid_walk(GRID_REF g, pnanovdb_grid_type_t type, PNANOVDB_INOUT(pnanovdb_readaccessor_t) acc,
                          sdft_vec3 org, sdft_vec3 dir, float t0, float t1, PORT_OUT(float) t_out,
                          PORT_INOUT(sdft_vec3) normal, PORT_INOUT(uint32_t) reads)
{
    const double o[3] = {org.x, org.y, org.z}, d[3] = {dir.x, dir.y, dir.z};
    double x0[3], xd[3], t_next[3], t_delta[3];
    int32_t cell[3], step[3];
    for (int k = 0; k < 3; k++) {
        xd[k] = PORT_DOUBLE(GRID(g).w2i[3 * k]) * d[0] + PORT_DOUBLE(GRID(g).w2i[3 * k + 1]) * d[1] +
                PORT_DOUBLE(GRID(g).w2i[3 * k + 2]) * d[2];
        x0[k] = PORT_DOUBLE(GRID(g).w2i[3 * k]) * o[0] + PORT_DOUBLE(GRID(g).w2i[3 * k + 1]) * o[1] +
                PORT_DOUBLE(GRID(g).w2i[3 * k + 2]) * o[2] + PORT_DOUBLE(GRID(g).w2i_t[k]) + PORT_DOUBLE(t0) * xd[k];
        if (!(fabs(x0[k]) < 1e9)) {
            PORT_DEREF(t_out) = t0;
            return 0;
        }
        cell[k] = PORT_INT(x0[k]) - PORT_INT(x0[k] < PORT_DOUBLE(PORT_INT(x0[k]))); /* floor, |x0| < 1e9 */
        step[k] = xd[k] > 0.0 ? 1 : -1;
        const double boundary = xd[k] > 0.0 ? PORT_DOUBLE(cell[k]) + 1.0 : PORT_DOUBLE(cell[k]);
        const double per_index = 1.0 / xd[k]; /* one division per axis */
        t_next[k] = xd[k] != 0.0 ? PORT_DOUBLE(t0) + (boundary - x0[k]) * per_index : PORT_DOUBLE(INFINITY);
        t_delta[k] = xd[k] != 0.0 ? fabs(per_index) : PORT_DOUBLE(INFINITY);
    }
    double ta = t0;
    for (int n = 0; n < ROOT_MAX_CELLS; n++) {
        const int k = t_next[0] <= t_next[1] ? (t_next[0] <= t_next[2] ? 0 : 2) : (t_next[1] <= t_next[2] ? 1 : 2);
        const double tb = t_next[k] < PORT_DOUBLE(t1) ? t_next[k] : PORT_DOUBLE(t1);
        float v[8];
        cell_values(g, type, acc, grid_coord(cell[0], cell[1], cell[2]), v);
        PORT_DEREF(reads)++;
        float low = v[0];
        for (int i = 1; i < 8; i++)
            low = sdft_minf(low, v[i]);
        if (low >= GRID(g).background)
            break;         /* nothing below the background here: march on from ta */
        if (low <= 0.0f) { /* a trilinear cell of positive values is positive throughout */
            double u0[3], s;
            for (int i = 0; i < 3; i++)
                u0[i] = x0[i] + (ta - PORT_DOUBLE(t0)) * xd[i] - PORT_DOUBLE(cell[i]);
            /* The gradient along the segment, ready before its root (so the
             * normal there is not a long chain after it). */
            double q[3][3];
            cell_gradient_along(v, u0, xd, q);
            if (cell_root(v, u0, xd, tb - ta, PORT_REF(s)) != 0) {
                PORT_DEREF(t_out) = PORT_FLOAT(ta + s);
                /* The normal: the gradient at the root, in the cell; none where
                 * it is too flat (gradient_is_flat), and normal_of, which falls
                 * back to differences there, decides. */
                float dg[3];
                for (int i = 0; i < 3; i++)
                    dg[i] = PORT_FLOAT(q[0][i] + s * (q[1][i] + s * q[2][i]));
                PORT_DEREF(normal) = gradient_is_flat(g, dg) ? sdft_v3(0.0f, 0.0f, 0.0f) : world_normal(g, dg);
                return 1;
            }
        }
        ta = tb;
        if (tb >= PORT_DOUBLE(t1)) { /* none up to the end */
            PORT_DEREF(t_out) = t1;
            return 0;
        }
        cell[k] += step[k];
        t_next[k] += t_delta[k];
    }
    /* Free up to ta, short of t1; rounded down, so that marching resumes on the near side. */
    PORT_DEREF(t_out) = sdft_maxf(t0, nextafterf(PORT_FLOAT(ta), -INFINITY));
    return 0;
}

#endif
