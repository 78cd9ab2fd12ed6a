// sdftrace — how often a grid's sign is wrong, against the exact
// winding number computed by brute force over every triangle.
#ifndef SDFT_MESH_TOOL_SIGN_CHECK_H
#define SDFT_MESH_TOOL_SIGN_CHECK_H

#include "geometry/triangle_mesh.h"

#include <string>
#include <vector>

namespace meshsdf
{

/// One grid's count of clear points and of those it signs wrong.
struct SignCheck {
    size_t clear = 0, wrong = 0, wrongFar = 0;
};

/// Samples `points` points uniformly (fixed seed) in the mesh's bounding
/// box grown by 5% per side, keeps those whose exact winding number is >
/// 0.75 (inside) or < 0.25 (outside) and that lie at least one voxel from
/// the surface (nearer, the nearest voxel may lie across it), and counts,
/// for each grid, those its nearest voxel (active or not; < 0 inside) signs
/// wrong, and those of them 3 or more voxels from the surface. A grid is
/// the first float grid of its .vdb file. False with one line in `error`
/// if a grid cannot be read (then no point was drawn).
bool checkSign(const TriangleMesh &mesh, const std::vector<std::string> &grids, int points,
               std::vector<SignCheck> &checks, std::string &error);

/// False with one line in error ("needs ~...") when `points` points to
/// check signs at do not fit this machine's memory (memory_limit.h).
bool checkPointsFitMemory(int points, std::string &error);

} // namespace meshsdf

#endif
