// sdftrace — orienting a mesh's faces (see orient.h).
//
// THE STEPS
// 1. Weld (loadMesh already did: TriangleMesh::welded) and drop duplicate
//    triangles: a second triangle on the same three welded vertices adds
//    nothing to the surface, and with the opposite orientation it cancels
//    the first one's solid angle, a hole in the winding number.
// 2. Patches: triangles joined across edges that exactly two of them share
//    (an edge of one is open, of three or more is a seam between patches).
//    Breadth first from each patch's first triangle, a neighbour is reversed
//    when it runs the shared edge in the same direction; so every manifold
//    edge of a patch is run once each way, which is what makes the winding
//    number jump by exactly 1 across the patch. Of the patch's two
//    orientations the one that keeps most of its area as the file has it is
//    chosen (ties: the file's first triangle), so a well-oriented patch is
//    left as it is. A patch whose breadth-first walk meets a contradiction is
//    non-orientable (a Moebius strip): it keeps the walk's orientation.
// 3. Outward: each patch P's flux
//        F(P) = sum over its triangles t of (c_t - o) . N_t,
//    c_t the centroid, N_t the area vector (half the cross product, along
//    the orientation), o the area-weighted centroid of P.
//
//    CLAIM. For a closed patch (every edge shared by exactly two of its
//    triangles), F(P) = 3 * integral of w_P over space, w_P the patch's own
//    winding number, whatever o is. So F(P) > 0 when P faces outward.
//    PROOF. x - o has divergence 3, so by the divergence theorem applied to
//    each region where w_P is constant (w_P jumps by 1 across P and is 0 far
//    away: a closed surface is the boundary of sum_k (regions of winding
//    k), counted k times), integral of 3 w_P = flux of x - o through P. On a
//    flat triangle (x - o) . n is linear, so its integral is the value at the
//    centroid times the area: the flux is F(P). For an embedded surface
//    facing outward w_P is 1 inside and 0 outside, so F > 0; facing inward,
//    -1 inside, so F < 0. The sum of N_t over a closed surface is 0, which is
//    why o does not matter.
//
//    For an open patch (a scan with holes, a shell with open ends) there is
//    no theorem: F(P) changes with o by o . sum N_t, the holes' area vectors.
//    Measured from the patch's own centroid it still says which side the
//    surface bulges to (a hemisphere: every term positive; a tube: every
//    term its radius), and its cancellation says how clearly:
//        clarity = |F(P)| / sum over t of |(c_t - o) . N_t|,
//    1 when every triangle faces away from o, 0 for a flat or saddle-shaped
//    patch. A patch flat to rounding (every |(c_t - o) . N_t| below kFlat
//    times |c_t - o| |N_t| in sum) has none either: its terms, and so their
//    ratio, are rounding noise. An open patch with clarity < kOpenClarity has no clear outside
//    and is left as the file has it (counted, and reported with the voxels
//    its winding number leaves ambiguous); a closed one needs only a flux
//    clear of rounding (kClosedClarity).
// 4. Cavities: a patch that faces inward is reversed unless it is the
//    inner wall of a solid, where facing inward is right (a hollow ball's
//    inner sphere). The test is the winding number of the whole mesh as
//    oriented so far, just off the patch on both sides at up to kProbes of
//    its triangles (chosen along its cumulative area): a cavity wall sees 0
//    in front of it and 1 behind it, as every correctly oriented face does;
//    a reversed one in empty space sees -1 in front and 0 behind (the test
//    weighs both choices' misfits, turnsOutward). Only a patch the file
//    orients consistently (kCavityShare of its area) and that lies within
//    another patch's bounds is asked: faces reversed at random are no
//    evidence of a cavity, and a wall lies inside the solid around it. Only
//    meshes with such a patch pay for the test (one winding tree); a
//    well-oriented mesh never gets here.
// 5. Open patches with no clear outside of their own (step 3: a flat cap,
//    a saddle) ask the rest of the mesh: the winding number w_R of the
//    patches steps 3 and 4 decided, at points a tenth of the patch's
//    diagonal (kEvidenceReach) in front of and behind it at its probes
//    (evidenceSide). A face of a solid has the solid behind it: w_R is
//    larger behind than in front (a lid on a cup: the cup's w_R is about
//    1/2 at the lid, more below it, less above), and the patch is turned so
//    where the mean difference exceeds kEvidence. Just off the patch, as in
//    step 4, would not do: there w_R is about 1/2 on both sides of a lid,
//    and the lid's own +-1/2 fits a solid either way round. The patches
//    still undecided are left out of w_R, so that the file's orientation of
//    one never decides another's: two files of one model whose open patches
//    are oriented differently (an OFF and an STL copy) get one orientation
//    wherever the evidence decides. A patch alone in space (a sheet) has no
//    rest to ask, and keeps the file's orientation.
//
// What is not decided: a patch facing outward inside another solid is kept
// (a part inside a part, the winding number 2 there is still inside); a
// whole inside-out hollow ball becomes a solid ball with a solid core (its
// outer wall is turned outward, its inner wall then faces outward too and
// is kept). Patches that neither step 3 nor step 5 decides are left as they
// are, counted, and the largest named (OrientCounts::notes).
#include "orient/orient.h"

#include "sign/winding.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

namespace meshsdf
{

namespace
{

constexpr double kOpenClarity = 0.25;   // see THE STEPS, 3
constexpr double kClosedClarity = 1e-6; // relative rounding of a closed patch's flux
constexpr double kFlat = 1e-9;          // terms this small against |c_t - o| |N_t| are rounding
constexpr int kProbes = 16;             // see THE STEPS, 4
constexpr double kCavityShare = 0.9;    // see THE STEPS, 4
constexpr double kProbeOffset = 1e-2;   // of a triangle's size: how far off it a probe stands
constexpr double kEvidence = 0.1;       // see THE STEPS, 5: the least mean difference that decides
constexpr double kEvidenceReach = 0.1;  // see THE STEPS, 5: how far off a patch, of its diagonal
constexpr uint32_t kNone = UINT32_MAX;

using Vec = std::array<double, 3>;

Vec corner(const TriangleMesh &mesh, uint32_t t, int k)
{
    const auto &p = mesh.points[mesh.triangles[t][k]];
    return {p[0], p[1], p[2]};
}

// Half the cross product of the triangle's edges, along its orientation.
Vec areaVector(const TriangleMesh &mesh, uint32_t t)
{
    const Vec a = corner(mesh, t, 0), b = corner(mesh, t, 1), c = corner(mesh, t, 2);
    const Vec e1{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    return {0.5 * (e1[1] * e2[2] - e1[2] * e2[1]), 0.5 * (e1[2] * e2[0] - e1[0] * e2[2]),
            0.5 * (e1[0] * e2[1] - e1[1] * e2[0])};
}

Vec centroid(const TriangleMesh &mesh, uint32_t t)
{
    const Vec a = corner(mesh, t, 0), b = corner(mesh, t, 1), c = corner(mesh, t, 2);
    return {(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3};
}

double dot(const Vec &a, const Vec &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec &a) { return std::sqrt(dot(a, a)); }

// Step 1: drops every triangle on the same welded vertices as an earlier
// one (such triangles share all three edges, so they meet in the runs of
// `edges`). Returns how many were dropped; `edges` is recomputed.
size_t dropDuplicates(TriangleMesh &mesh, std::vector<EdgeUse> &edges)
{
    auto third = [&](uint32_t h) { return mesh.welded[mesh.triangles[h / 3][(h % 3 + 2) % 3]]; };
    std::vector<char> drop(mesh.triangles.size(), 0);
    std::vector<std::pair<uint32_t, uint32_t>> run; // (third vertex, triangle)
    for (size_t i = 0, j; i < edges.size(); i = j) {
        for (j = i + 1; j < edges.size() && edges[j].key == edges[i].key;)
            ++j;
        if (j - i < 2)
            continue;
        if (j - i == 2) { // a manifold edge, most of them: no sort
            if (third(edges[i].halfEdge) == third(edges[i + 1].halfEdge))
                drop[std::max(edges[i].halfEdge, edges[i + 1].halfEdge) / 3] = 1;
            continue;
        }
        run.clear();
        for (size_t k = i; k < j; ++k)
            run.emplace_back(third(edges[k].halfEdge), edges[k].halfEdge / 3);
        std::sort(run.begin(), run.end());
        for (size_t k = 1; k < run.size(); ++k)
            if (run[k].first == run[k - 1].first)
                drop[run[k].second] = 1; // the later triangle of the two
    }
    size_t dropped = 0;
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
        if (!drop[t])
            mesh.triangles[t - dropped] = mesh.triangles[t];
        else
            ++dropped;
    if (dropped) {
        mesh.triangles.resize(mesh.triangles.size() - dropped);
        edges = edgeUses(mesh);
    }
    return dropped;
}

struct Patches {
    std::vector<uint32_t> of;      // per triangle, its patch
    std::vector<uint8_t> reversed; // per triangle, 1: reverse it
    std::vector<uint32_t> start;   // triangles of patch p: order[start[p] .. start[p + 1])
    std::vector<uint32_t> order;   // triangles by patch, each patch in triangle order
    std::vector<uint8_t> closed;   // per patch
    std::vector<uint8_t> orientable;
    std::vector<double> fileShare; // per patch, the share of its area the file orients as chosen
    size_t count() const { return start.size() - 1; }
};

// Step 2.
Patches findPatches(const TriangleMesh &mesh, const std::vector<EdgeUse> &edges, const std::vector<double> &area)
{
    const uint32_t n = uint32_t(mesh.triangles.size());
    std::vector<uint32_t> partner(size_t(n) * 3, kNone); // the other half-edge of a manifold edge
    std::vector<uint8_t> open(n, 0);                     // on an edge not shared by exactly two
    for (size_t i = 0, j; i < edges.size(); i = j) {
        for (j = i + 1; j < edges.size() && edges[j].key == edges[i].key;)
            ++j;
        if (j - i == 2) {
            partner[edges[i].halfEdge] = edges[i + 1].halfEdge;
            partner[edges[i + 1].halfEdge] = edges[i].halfEdge;
        } else {
            for (size_t k = i; k < j; ++k)
                open[edges[k].halfEdge / 3] = 1;
        }
    }
    Patches p;
    p.of.assign(n, kNone);
    p.reversed.assign(n, 0);
    p.order.reserve(n);
    std::vector<uint32_t> queue;
    for (uint32_t seed = 0; seed < n; ++seed) {
        if (p.of[seed] != kNone)
            continue;
        const uint32_t id = uint32_t(p.closed.size());
        p.start.push_back(uint32_t(p.order.size()));
        bool closed = true, orientable = true;
        queue.assign(1, seed);
        p.of[seed] = id;
        for (size_t next = 0; next < queue.size(); ++next) {
            const uint32_t t = queue[next];
            closed = closed && !open[t];
            for (uint32_t k = 0; k < 3; ++k) {
                const uint32_t h = partner[t * 3 + k];
                if (h == kNone)
                    continue;
                const uint32_t u = h / 3;
                // The same direction on both sides: u must turn relative to t.
                const bool same = edgeFrom(mesh, t * 3 + k) == edgeFrom(mesh, h);
                const uint8_t want = uint8_t(p.reversed[t] ^ same);
                if (p.of[u] == kNone) {
                    p.of[u] = id;
                    p.reversed[u] = want;
                    queue.push_back(u);
                } else if (p.reversed[u] != want) {
                    orientable = false;
                }
            }
        }
        // Of the two orientations, the one that keeps most of the area.
        double kept = 0, turned = 0;
        for (uint32_t t : queue)
            (p.reversed[t] ? turned : kept) += area[t];
        if (turned > kept)
            for (uint32_t t : queue)
                p.reversed[t] ^= 1;
        p.fileShare.push_back(std::max(kept, turned) / std::max(kept + turned, 1e-300));
        std::sort(queue.begin(), queue.end());
        p.order.insert(p.order.end(), queue.begin(), queue.end());
        p.closed.push_back(closed);
        p.orientable.push_back(orientable);
    }
    p.start.push_back(n);
    return p;
}

// Step 3: +1 the patch faces outward, -1 inward, 0 no clear outside.
int outwardSide(const TriangleMesh &mesh, const Patches &p, uint32_t id, const std::vector<Vec> &areaVec,
                const std::vector<double> &area)
{
    double total = 0;
    Vec o{0, 0, 0};
    for (uint32_t i = p.start[id]; i < p.start[id + 1]; ++i) {
        const uint32_t t = p.order[i];
        const Vec c = centroid(mesh, t);
        for (int k = 0; k < 3; ++k)
            o[k] += area[t] * c[k];
        total += area[t];
    }
    for (int k = 0; k < 3; ++k)
        o[k] /= total;
    double flux = 0, magnitude = 0, scale = 0;
    for (uint32_t i = p.start[id]; i < p.start[id + 1]; ++i) {
        const uint32_t t = p.order[i];
        const Vec c = centroid(mesh, t), r{c[0] - o[0], c[1] - o[1], c[2] - o[2]};
        const double term = dot(r, areaVec[t]) * (p.reversed[t] ? -1 : 1);
        flux += term;
        magnitude += std::abs(term);
        scale += norm(r) * area[t];
    }
    // Flat to rounding: every term is rounding noise, and so is their ratio.
    if (!(magnitude > kFlat * scale))
        return 0;
    const double clarity = p.closed[id] ? kClosedClarity : kOpenClarity;
    if (!(std::abs(flux) > clarity * magnitude))
        return 0;
    return flux > 0 ? 1 : -1;
}

// Points in front of and behind up to kProbes of patch `id`'s triangles
// (front, back, front, back, ...), as the patch is oriented now, chosen
// along its cumulative area: `reach` (world units) off each centroid along
// its normal, or, for reach 0, just off it (kProbeOffset of its size).
std::vector<Vec> patchProbes(const TriangleMesh &mesh, const Patches &p, uint32_t id, const std::vector<Vec> &areaVec,
                             const std::vector<double> &area, double reach = 0)
{
    const uint32_t first = p.start[id], last = p.start[id + 1];
    double total = 0;
    for (uint32_t i = first; i < last; ++i)
        total += area[p.order[i]];
    std::vector<Vec> probes;
    double reached = 0;
    for (uint32_t i = first; i < last && probes.size() < 2 * kProbes; ++i) {
        const uint32_t t = p.order[i];
        reached += area[t];
        // The triangle where the cumulative area passes (probe + 1/2) / kProbes.
        if (reached < (probes.size() / 2 + 0.5) / kProbes * total)
            continue;
        const Vec c = centroid(mesh, t);
        const double offset =
            (reach > 0 ? reach / area[t] : kProbeOffset / std::sqrt(area[t])) * (p.reversed[t] ? -1 : 1);
        Vec front, back;
        for (int k = 0; k < 3; ++k) {
            front[k] = c[k] + offset * areaVec[t][k];
            back[k] = c[k] - offset * areaVec[t][k];
        }
        probes.push_back(front);
        probes.push_back(back);
    }
    return probes;
}

// Triangle t's corners as the patches orient it now.
std::array<uint32_t, 3> orientedTriangle(const TriangleMesh &mesh, const Patches &p, uint32_t t)
{
    std::array<uint32_t, 3> tri = mesh.triangles[t];
    if (p.reversed[t])
        std::swap(tri[1], tri[2]);
    return tri;
}

// How unlike a solid's the whole mesh's winding number looks just off a
// patch, kept as it is and reversed: a solid's faces see 0 in front of them
// and 1 behind. `whole` is the whole mesh's winding (the patch as oriented
// now) and `own` the patch's own at the probes (front, back, ...).
// Reversing the patch subtracts twice its own winding number and swaps
// front and back. The squared misfits of both choices, summed.
struct Misfits {
    double keep = 0, turn = 0;
};
Misfits solidMisfits(const std::vector<double> &whole, const std::vector<double> &own)
{
    Misfits m;
    for (size_t q = 0; q + 1 < whole.size(); q += 2) {
        const double front = whole[q], back = whole[q + 1];
        m.keep += front * front + (back - 1) * (back - 1);
        const double newFront = back - 2 * own[q + 1], newBack = front - 2 * own[q];
        m.turn += newFront * newFront + (newBack - 1) * (newBack - 1);
    }
    return m;
}

// Step 4: whether reversing the inward-facing patch `id` makes the whole
// mesh's winding number (`winding`, as oriented now) look more like a
// solid's just off the patch (solidMisfits). The patch's own winding number
// is summed by brute force over the patch, or, when the patch is most of
// the mesh, taken as the whole mesh's less the rest's (the fewer triangles
// either way).
bool turnsOutward(const TriangleMesh &mesh, const Patches &p, uint32_t id, const std::vector<Vec> &areaVec,
                  const std::vector<double> &area, const FastWinding &winding)
{
    const uint32_t first = p.start[id], last = p.start[id + 1];
    const std::vector<Vec> probes = patchProbes(mesh, p, id, areaVec, area);
    const bool most = 2 * size_t(last - first) > mesh.triangles.size();
    std::vector<double> whole(probes.size()), own(probes.size(), 0.0);
    for (size_t q = 0; q < probes.size(); ++q)
        whole[q] = winding(probes[q]);
    auto add = [&](uint32_t t) {
        const Vec a = corner(mesh, t, 0), b = corner(mesh, t, p.reversed[t] ? 2 : 1),
                  c = corner(mesh, t, p.reversed[t] ? 1 : 2);
        for (size_t q = 0; q < probes.size(); ++q)
            own[q] += triangleWinding(a, b, c, probes[q]);
    };
    if (!most)
        for (uint32_t i = first; i < last; ++i)
            add(p.order[i]);
    else {
        for (uint32_t t = 0; t < mesh.triangles.size(); ++t)
            if (p.of[t] != id)
                add(t);
        for (size_t q = 0; q < probes.size(); ++q)
            own[q] = whole[q] - own[q];
    }
    const Misfits m = solidMisfits(whole, own);
    return m.turn < m.keep;
}

// Step 5: the side the rest of the mesh gives an open patch with no clear
// outside of its own: the winding number of the decided patches (`rest`,
// as oriented, no undecided patch in it), a reach of kEvidenceReach of the
// patch's diagonal in front of and behind it at its probes. A solid's face
// has more of the solid behind it than in front: +1 keep the patch as it
// is, -1 reverse it, 0 when the mean difference is within kEvidence.
int evidenceSide(const TriangleMesh &mesh, const Patches &p, uint32_t id, const std::vector<Vec> &areaVec,
                 const std::vector<double> &area, const Vec &diagonal, const FastWinding &rest)
{
    const std::vector<Vec> probes = patchProbes(mesh, p, id, areaVec, area, kEvidenceReach * norm(diagonal));
    double behind = 0;
    for (size_t q = 0; q + 1 < probes.size(); q += 2)
        behind += rest(probes[q + 1]) - rest(probes[q]);
    behind /= std::max<double>(1, probes.size() / 2);
    return behind > kEvidence ? 1 : behind < -kEvidence ? -1 : 0;
}

struct Box {
    Vec lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
};

std::vector<Box> patchBounds(const TriangleMesh &mesh, const Patches &p)
{
    std::vector<Box> bounds(p.count());
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c) {
            const Vec v = corner(mesh, t, c);
            Box &b = bounds[p.of[t]];
            for (int k = 0; k < 3; ++k) {
                b.lo[k] = std::min(b.lo[k], v[k]);
                b.hi[k] = std::max(b.hi[k], v[k]);
            }
        }
    return bounds;
}

// Whether patch `id`'s bounds lie within another patch's.
bool withinAnother(const std::vector<Box> &bounds, uint32_t id)
{
    for (uint32_t other = 0; other < bounds.size(); ++other) {
        bool inside = other != id;
        for (int k = 0; k < 3 && inside; ++k)
            inside = bounds[other].lo[k] <= bounds[id].lo[k] && bounds[id].hi[k] <= bounds[other].hi[k];
        if (inside)
            return true;
    }
    return false;
}

// "(0.5, 0.25, 1)".
std::string pointText(const Vec &v)
{
    char text[96];
    std::snprintf(text, sizeof text, "(%.4g, %.4g, %.4g)", v[0], v[1], v[2]);
    return text;
}

// Step 5 for the patches with no clear outside of their own (`undecided`):
// each one the rest of the mesh decides (evidenceSide) is turned as it
// says; the others are left as the file has them, counted, with their
// share of the area and a line each for the largest (counts.notes).
void orientByEvidence(const TriangleMesh &mesh, Patches &p, const std::vector<uint32_t> &undecided,
                      const std::vector<Vec> &areaVec, const std::vector<double> &area, const std::vector<Box> &bounds,
                      bool simd, OrientCounts &counts)
{
    std::vector<uint8_t> open(p.count(), 0);
    for (uint32_t id : undecided)
        open[id] = 1;
    std::vector<std::array<uint32_t, 3>> rest;
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t)
        if (!open[p.of[t]])
            rest.push_back(orientedTriangle(mesh, p, t));
    std::vector<uint32_t> left;
    if (rest.empty())
        left = undecided;
    else {
        const FastWinding tree(mesh.points, rest, 2.0, simd);
        for (uint32_t id : undecided) {
            const Vec diagonal{bounds[id].hi[0] - bounds[id].lo[0], bounds[id].hi[1] - bounds[id].lo[1],
                               bounds[id].hi[2] - bounds[id].lo[2]};
            const int side = evidenceSide(mesh, p, id, areaVec, area, diagonal, tree);
            if (side == 0) {
                left.push_back(id);
                continue;
            }
            ++counts.evidencePatches;
            if (side < 0) {
                ++counts.outwardPatches;
                for (uint32_t i = p.start[id]; i < p.start[id + 1]; ++i)
                    p.reversed[p.order[i]] ^= 1;
            }
        }
    }
    counts.ambiguousPatches = left.size();
    if (left.empty())
        return;
    double total = 0;
    std::vector<double> patchArea(p.count(), 0.0);
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        total += area[t];
        patchArea[p.of[t]] += area[t];
    }
    std::sort(left.begin(), left.end(), [&](uint32_t a, uint32_t b) {
        return patchArea[a] > patchArea[b] || (patchArea[a] == patchArea[b] && a < b);
    });
    double leftArea = 0;
    for (uint32_t id : left)
        leftArea += patchArea[id];
    counts.ambiguousArea = total > 0 ? leftArea / total : 0;
    constexpr size_t kNamed = 3;
    for (size_t i = 0; i < left.size() && i < kNamed; ++i) {
        const uint32_t id = left[i];
        const Box &b = bounds[id];
        char share[32];
        std::snprintf(share, sizeof share, "%.3g%%", 100 * patchArea[id] / total);
        counts.notes.push_back("an open patch of " + std::to_string(p.start[id + 1] - p.start[id]) + " triangles (" +
                               share + " of the surface area, from " + pointText(b.lo) + " to " + pointText(b.hi) +
                               ") keeps the file's orientation: no side of it is clearly out");
    }
    if (left.size() > kNamed) {
        double rest = 0;
        for (size_t i = kNamed; i < left.size(); ++i)
            rest += patchArea[left[i]];
        char share[32];
        std::snprintf(share, sizeof share, "%.3g%%", 100 * rest / total);
        counts.notes.push_back(std::to_string(left.size() - kNamed) + " smaller open patches (" + share +
                               " of the surface area in all) keep the file's orientation too");
    }
}

} // namespace

OrientCounts orientMesh(TriangleMesh &mesh, bool simd)
{
    OrientCounts counts;
    counts.weldedVertices = mesh.health.weldedVertices;
    std::vector<EdgeUse> edges = edgeUses(mesh);
    counts.duplicateFaces = dropDuplicates(mesh, edges);
    countEdges(mesh, edges);

    const uint32_t n = uint32_t(mesh.triangles.size());
    std::vector<Vec> areaVec(n);
    std::vector<double> area(n);
    for (uint32_t t = 0; t < n; ++t) {
        areaVec[t] = areaVector(mesh, t);
        area[t] = norm(areaVec[t]);
    }
    Patches p = findPatches(mesh, edges, area);
    counts.patches = p.count();
    std::vector<uint32_t> inward, undecided;
    for (uint32_t id = 0; id < p.count(); ++id) {
        counts.nonOrientablePatches += !p.orientable[id];
        const int side = outwardSide(mesh, p, id, areaVec, area);
        if (side == 0)
            undecided.push_back(id);
        if (side < 0)
            inward.push_back(id);
    }
    // The cavity test asks only of a patch that the file orients
    // consistently and that lies within another patch's bounds (a cavity's
    // wall lies inside the solid around it); the winding tree is built for
    // the first such patch.
    const std::vector<Box> bounds = patchBounds(mesh, p);
    std::unique_ptr<FastWinding> winding;
    for (uint32_t id : inward) {
        bool cavity = false;
        if (p.fileShare[id] >= kCavityShare && withinAnother(bounds, id)) {
            if (!winding) {
                std::vector<std::array<uint32_t, 3>> oriented = mesh.triangles; // as oriented so far
                for (uint32_t t = 0; t < n; ++t)
                    if (p.reversed[t])
                        std::swap(oriented[t][1], oriented[t][2]);
                winding.reset(new FastWinding(mesh.points, oriented, 2.0, simd));
            }
            cavity = !turnsOutward(mesh, p, id, areaVec, area, *winding);
        }
        if (cavity) {
            ++counts.cavityPatches;
            continue;
        }
        ++counts.outwardPatches;
        for (uint32_t i = p.start[id]; i < p.start[id + 1]; ++i)
            p.reversed[p.order[i]] ^= 1;
    }
    if (!undecided.empty())
        orientByEvidence(mesh, p, undecided, areaVec, area, bounds, simd, counts);
    for (uint32_t t = 0; t < n; ++t)
        if (p.reversed[t]) {
            std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
            ++counts.reorientedFaces;
        }
    mesh.health.triangles = mesh.triangles.size();
    return counts;
}

} // namespace meshsdf
