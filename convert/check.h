// mesh2sdf --check-sign: how often a grid's sign is wrong, against the exact
// winding number computed by brute force over every triangle.
#ifndef MESH2SDF_CHECK_H
#define MESH2SDF_CHECK_H

#include "mesh.h"

#include <string>
#include <vector>

namespace mesh2sdf
{

/// Samples `samples` points uniformly (fixed seed) in the mesh's bounding box
/// grown by 5% per side, keeps those whose exact winding number is > 0.75
/// (inside) or < 0.25 (outside) and that lie at least one voxel from the
/// surface (nearer, the nearest voxel may lie across it), and prints for each grid one line:
///   GRID  clear=N wrong=K wrong_fraction=F wrong_far=J
/// (J: the wrong ones 3 or more voxels from the surface)
/// A grid is read from its first float grid; its value at the nearest voxel
/// (active or not) < 0 means inside. Returns false with one line in `error`
/// if a grid cannot be read.
bool checkSign(const TriangleMesh &mesh, const std::vector<std::string> &grids, int samples, std::string &error);

} // namespace mesh2sdf

#endif
