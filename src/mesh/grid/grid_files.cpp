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

namespace meshsdf
{

bool reserveFile(const std::string &path, PendingFile &file, std::string &error)
{
    char msg[512];
    if (atomic_file_begin(&file.file, path.c_str(), msg, sizeof msg)) {
        error = msg;
        return false;
    }
    file.tmp = file.file.tmp_path;
    return true;
}

bool commitFile(PendingFile &file, std::string &error)
{
    if (file.tmp.empty())
        return true;
    char msg[512];
    file.tmp.clear();
    if (atomic_file_commit(&file.file, msg, sizeof msg)) {
        error = msg;
        return false;
    }
    return true;
}

void discardFile(PendingFile &file)
{
    if (!file.tmp.empty())
        atomic_file_abort(&file.file);
    file.tmp.clear();
}

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
    FILE *f = std::fopen(tmp.c_str(), "w");
    if (!f) {
        error = "cannot write " + tmp + ": " + std::strerror(errno);
        return false;
    }
    std::fprintf(f, "{\n  \"array\": ");
    json_put_string(f, npyName.c_str());
    std::fprintf(f,
                 ",\n"
                 "  \"dtype\": \"float32\",\n"
                 "  \"shape\": [%d, %d, %d],\n"
                 "  \"axis_order\": \"a[i, j, k] is the distance at origin + (i, j, k) * voxel_size (x, y, z); C "
                 "order, k fastest\",\n"
                 "  \"origin\": [%.17g, %.17g, %.17g],\n"
                 "  \"voxel_size\": %.17g,\n"
                 "  \"units\": \"world units of the mesh; negative inside\",\n"
                 "  \"background\": %.9g,\n"
                 "  \"band_voxels\": %.17g,\n"
                 "  \"full\": %s,\n"
                 "  \"sign\": ",
                 box.dims[0], box.dims[1], box.dims[2], box.origin[0], box.origin[1], box.origin[2], box.voxelSize,
                 double(background), how.band, how.full ? "true" : "false");
    json_put_string(f, how.sign.c_str());
    std::fprintf(f, ",\n  \"source_mesh\": ");
    json_put_string(f, how.source.c_str());
    std::fprintf(f, "\n}\n");
    const bool bad = std::ferror(f) != 0;
    const bool ok = (std::fclose(f) == 0) && !bad;
    if (!ok)
        error = "cannot write " + tmp + ": " + std::strerror(errno);
    return ok;
}

std::string sidecarPath(const std::string &npyPath)
{
    const size_t n = npyPath.size();
    const bool npy = n > 4 && npyPath.compare(n - 4, 4, ".npy") == 0;
    return (npy ? npyPath.substr(0, n - 4) : npyPath) + ".json";
}

} // namespace meshsdf
