// sdftrace — the conversion's peak memory (see memory_estimate.h).
//
// THE MODEL, from what the conversion holds at its peak, each term's
// constant measured with /usr/bin/time's maximum resident set on the
// repository's meshes (spot, the Stanford bunny) at --res 64 to 1024:
//  - the process with OpenVDB, TBB and the libraries loaded: about 40 MiB;
//  - the mesh: its points, triangles, welded numbering, edge uses and the
//    winding number's tree, about kBytesPerTriangle each;
//  - a narrow band: the leaves (8^3 voxels) the band crosses. A band of
//    half-width b voxels around a surface of area A crosses about
//    A / (8 h)^2 * (2 b / 8 + 1) leaves, each holding its values, masks and
//    the nearest triangle of each voxel while it is built: kBytesPerLeaf;
//  - --full: every voxel of the box, as full leaves: kBytesPerDenseVoxel;
//  - --nvdb: the NanoVDB copy made while writing, about a leaf's values
//    again per leaf.
// --npy streams the dense array in slabs and adds little.
#include "grid/memory_estimate.h"

#include "memory_limit.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace meshsdf
{

namespace
{

constexpr double kBaseBytes = 40.0 * 1024 * 1024;
constexpr double kBytesPerTriangle = 600.0;
constexpr double kBytesPerLeaf = 2.6 * 1024;
constexpr double kBytesPerDenseVoxel = 4.5;
constexpr double kNanoBytesPerLeaf = 2.2 * 1024;

double surfaceArea(const TriangleMesh &mesh)
{
    double area = 0;
    for (const auto &t : mesh.triangles) {
        const auto &a = mesh.points[t[0]], &b = mesh.points[t[1]], &c = mesh.points[t[2]];
        const double e1[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
        const double e2[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
        const double x = e1[1] * e2[2] - e1[2] * e2[1], y = e1[2] * e2[0] - e1[0] * e2[2],
                     z = e1[0] * e2[1] - e1[1] * e2[0];
        area += 0.5 * std::sqrt(x * x + y * y + z * z);
    }
    return area;
}

} // namespace

double conversionPeakBytes(const TriangleMesh &mesh, const BoxGeometry &box, const sdft_mesh_grid_params &p)
{
    const double h = box.voxelSize;
    const double bandLeaves = surfaceArea(mesh) / (64.0 * h * h) * (2.0 * p.band / 8.0 + 1.0);
    // The band cannot cross more leaves than the box has.
    const double boxLeaves = std::ceil(box.dims[0] / 8.0) * std::ceil(box.dims[1] / 8.0) * std::ceil(box.dims[2] / 8.0);
    const double leaves = p.full ? boxLeaves : std::min(bandLeaves, boxLeaves);
    double bytes = kBaseBytes + kBytesPerTriangle * double(mesh.triangles.size());
    bytes += p.full ? kBytesPerDenseVoxel * box.voxelCount() : kBytesPerLeaf * leaves;
    if (p.formats & (1u << SDFT_MESH_FORMAT_NVDB))
        bytes += kNanoBytesPerLeaf * leaves;
    return bytes;
}

bool conversionFitsMemory(const TriangleMesh &mesh, const BoxGeometry &box, const sdft_mesh_grid_params &p,
                          std::string &error)
{
    char line[256];
    const std::string what = "a " + std::to_string(box.dims[0]) + "x" + std::to_string(box.dims[1]) + "x" +
                             std::to_string(box.dims[2]) + (p.full ? " dense grid" : " box's narrow band");
    if (memory_check(conversionPeakBytes(mesh, box, p), what.c_str(), line, sizeof line) == 0)
        return true;
    error = line;
    return false;
}

} // namespace meshsdf
