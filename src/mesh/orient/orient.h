// sdftrace — orienting a mesh's faces before its winding number signs the
// grid: one orientation per edge-connected patch, each patch turned to face
// outward. The winding number is only as right as the faces' orientation:
// an inside-out scan sums to -1 inside, and a face flipped against its
// neighbours leaves a hole's worth of error around it.
#ifndef SDFT_MESH_ORIENT_ORIENT_H
#define SDFT_MESH_ORIENT_ORIENT_H

#include "geometry/triangle_mesh.h"

#include <string>
#include <vector>

namespace meshsdf
{

/// What orientMesh found and what it did (all counts after welding).
struct OrientCounts {
    size_t weldedVertices = 0;       // used vertices merged into another at the same position
    size_t duplicateFaces = 0;       // triangles on the same three welded vertices as an earlier one (dropped)
    size_t patches = 0;              // edge-connected patches (across edges two triangles share)
    size_t nonOrientablePatches = 0; // patches no orientation makes consistent (a Moebius strip)
    size_t reorientedFaces = 0;      // triangles whose orientation was reversed, in all
    size_t outwardPatches = 0;       // patches reversed whole to face outward
    size_t cavityPatches = 0;        // inward-facing patches kept: they bound a cavity in a solid
    size_t evidencePatches = 0;      // open patches with no clear outside of their own, oriented by the rest's
                                     // winding number (reversed ones count in outwardPatches too)
    size_t ambiguousPatches = 0;     // open patches with no clear outside (left as the file has them)
    double ambiguousArea = 0;        // their share of the surface area
    std::vector<std::string> notes;  // a line for each of the largest of them: size, share, where
};

/// Welds the mesh's vertices by position (TriangleMesh::welded), drops
/// duplicate triangles, orients each edge-connected patch consistently
/// (the file's orientation where most of the patch's area has it),
/// reverses a patch that faces inward unless it bounds a cavity, and turns
/// an open patch with no clear outside of its own the way the rest of the
/// mesh's winding number says, where it says: the proofs and rules are in
/// orient.cpp. A well-oriented mesh comes out unchanged,
/// its triangles in the same order with the same corners. Recounts the
/// boundary and non-manifold edges on what is left. `simd` is FastWinding's.
OrientCounts orientMesh(TriangleMesh &mesh, bool simd = true);

} // namespace meshsdf

#endif
