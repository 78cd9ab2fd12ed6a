// sdftrace — OpenVDB's band and flood-fill sign (see flood_grid.h).
#include "grid/flood_grid.h"

#include <openvdb/tools/MeshToVolume.h>

namespace meshsdf
{

namespace
{

// The mesh as OpenVDB's MeshDataAdapter wants it: triangles with points in
// the grid's index space, converted on the fly in double precision.
class IndexSpaceMesh
{
  public:
    IndexSpaceMesh(const TriangleMesh &mesh, const BoxGeometry &box) : mMesh(mesh), mBox(box) {}
    size_t polygonCount() const { return mMesh.triangles.size(); }
    size_t pointCount() const { return mMesh.points.size(); }
    size_t vertexCount(size_t) const { return 3; }
    void getIndexSpacePoint(size_t n, size_t v, openvdb::Vec3d &pos) const
    {
        const auto &p = mMesh.points[mMesh.triangles[n][v]];
        for (int k = 0; k < 3; ++k)
            pos[k] = (double(p[k]) - mBox.origin[k]) / mBox.voxelSize;
    }

  private:
    const TriangleMesh &mMesh;
    const BoxGeometry &mBox;
};

} // namespace

openvdb::FloatGrid::Ptr floodGrid(const TriangleMesh &mesh, const BoxGeometry &box,
                                  const openvdb::math::Transform &xform, float band, Progress &progress)
{
    IndexSpaceMesh adapter(mesh, box);
    return openvdb::tools::meshToVolume<openvdb::FloatGrid>(progress, adapter, xform, band, band, 0);
}

} // namespace meshsdf
