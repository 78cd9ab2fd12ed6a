// sdftrace — output files (see grid_files.h).
#include "grid/grid_files.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include <tbb/parallel_for.h>

#include "grid_file.h"
#include "json.h"
#include "npy_write.h"
#include "seam.h"

namespace meshsdf
{

void describeGrid(openvdb::FloatGrid &grid, const std::string &name, const Provenance &how)
{
    grid.setName(name);
    grid.insertMeta("mesh2sdf_source", openvdb::StringMetadata(how.source));
    grid.insertMeta("mesh2sdf_sign", openvdb::StringMetadata(how.sign));
    grid.insertMeta("mesh2sdf_band_voxels", openvdb::DoubleMetadata(how.band));
    grid.insertMeta("mesh2sdf_full", openvdb::BoolMetadata(how.full));
}

namespace
{

// The shared grid-file writer, its one line into `error`.
bool writeGrid(const openvdb::FloatGrid &grid, bool nvdb, sdft_quant quant, const std::string &tmp, std::string &error)
{
    char msg[1024];
    if (sdft_vdb::write_grid(grid, nvdb, quant, tmp, tmp, msg, sizeof msg)) {
        error = msg;
        return false;
    }
    return true;
}

} // namespace

bool writeVdb(const openvdb::FloatGrid &grid, const std::string &tmp, std::string &error)
{
    return writeGrid(grid, false, SDFT_QUANT_NONE, tmp, error);
}

bool writeNvdb(const openvdb::FloatGrid &grid, bool fp16, const std::string &tmp, std::string &error)
{
    return writeGrid(grid, true, fp16 ? SDFT_QUANT_FP16 : SDFT_QUANT_NONE, tmp, error);
}

bool writeNpy(const openvdb::FloatGrid &grid, const BoxGeometry &box, const std::string &tmp, std::string &error)
{
    FILE *f = std::fopen(tmp.c_str(), "wb");
    if (!f) {
        error = "cannot write " + tmp + ": " + std::strerror(errno);
        return false;
    }
    const std::string shape = "(" + std::to_string(box.dims[0]) + ", " + std::to_string(box.dims[1]) + ", " +
                              std::to_string(box.dims[2]) + ")";
    bool ok = npy_write_header(f, shape.c_str()) == 0;
    // A slab of Leaf::DIM planes of x at a time: its leaf-sized blocks
    // copied in parallel from their leaves (or the tile holding them), the
    // slab then written whole. Leaves are aligned to Leaf::DIM, and voxel
    // (0, 0, 0) of the box is the grid's index origin.
    using Leaf = openvdb::FloatTree::LeafNodeType;
    constexpr int n = int(Leaf::DIM);
    const openvdb::FloatTree &tree = grid.tree();
    const size_t ny = size_t(box.dims[1]), nz = size_t(box.dims[2]);
    const int blocksY = (box.dims[1] + n - 1) / n, blocksZ = (box.dims[2] + n - 1) / n;
    std::vector<float> slab(size_t(n) * ny * nz);
    for (int x0 = 0; ok && x0 < box.dims[0]; x0 += n) {
        const int planes = std::min(n, box.dims[0] - x0);
        tbb::parallel_for(0, blocksY * blocksZ, [&](int b) {
            const int y0 = b / blocksZ * n, z0 = b % blocksZ * n;
            const int ys = std::min(n, box.dims[1] - y0), zs = std::min(n, box.dims[2] - z0);
            const openvdb::Coord at(x0, y0, z0);
            const Leaf *leaf = tree.probeConstLeaf(at);
            const float *values = leaf ? leaf->buffer().data() : nullptr;
            const float tile = leaf ? 0.0f : tree.getValue(at);
            for (int i = 0; i < planes; ++i)
                for (int j = 0; j < ys; ++j) {
                    float *row = slab.data() + (size_t(i) * ny + size_t(y0 + j)) * nz + size_t(z0);
                    if (values)
                        std::copy_n(values + Leaf::coordToOffset(openvdb::Coord(i, j, 0)), zs, row);
                    else
                        std::fill_n(row, zs, tile);
                }
        });
        const size_t count = size_t(planes) * ny * nz;
        ok = std::fwrite(slab.data(), sizeof(float), count, f) == count;
    }
    ok = (std::fclose(f) == 0) && ok;
    if (!ok)
        error = "cannot write " + tmp + ": " + std::strerror(errno);
    return ok;
}

bool writeNpyJson(const BoxGeometry &box, const std::string &npyName, const Provenance &how, float background,
                  const std::string &tmp, std::string &error)
{
    const std::string shape = seam::format("[%d, %d, %d]", box.dims[0], box.dims[1], box.dims[2]),
                      origin = seam::format("[%.17g, %.17g, %.17g]", box.origin[0], box.origin[1], box.origin[2]),
                      voxel = seam::format("%.17g", box.voxelSize), back = seam::format("%.9g", double(background)),
                      band = seam::format("%.17g", how.band);
    const json_member members[] = {
        {"array", npyName.c_str(), 0},
        {"dtype", "float32", 0},
        {"shape", shape.c_str(), 1},
        {"axis_order", "a[i, j, k] is the distance at origin + (i, j, k) * voxel_size (x, y, z); C order, k fastest",
         0},
        {"origin", origin.c_str(), 1},
        {"voxel_size", voxel.c_str(), 1},
        {"units", "world units of the mesh; negative inside", 0},
        {"background", back.c_str(), 1},
        {"band_voxels", band.c_str(), 1},
        {"full", how.full ? "true" : "false", 1},
        {"sign", how.sign.c_str(), 0},
        {"source_mesh", how.source.c_str(), 0},
    };
    char msg[512];
    if (json_write_object(tmp.c_str(), members, sizeof members / sizeof *members, msg, sizeof msg) == 0)
        return true;
    error = msg;
    return false;
}

std::string sidecarPath(const std::string &npyPath)
{
    const size_t n = npyPath.size();
    const bool npy = n > 4 && npyPath.compare(n - 4, 4, ".npy") == 0;
    return (npy ? npyPath.substr(0, n - 4) : npyPath) + ".json";
}

} // namespace meshsdf
