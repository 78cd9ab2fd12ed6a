// sdftrace — a grid's sign checked against the mesh's (see sign_check.h).
#include "tool/sign_check.h"

#include "sign/winding.h"

#include "isolated_read.h"
#include "memory_limit.h"
#include "vdb_extent.h"

#include <openvdb/openvdb.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstdlib>
#include <random>

namespace meshsdf
{

namespace
{

// The child's side of readFirstFloatGrid's check: the whole read, the way
// the parent reads it; back comes 1, or 0 and OpenVDB's message.
int readInChild(void *ctx, int fd)
{
    std::string answer(1, '\1');
    try {
        openvdb::io::File file(*static_cast<const std::string *>(ctx));
        file.open(false); // every leaf's values now, not when first read
        file.getGrids();
    } catch (const std::exception &e) {
        answer = std::string(1, '\0') + e.what();
    }
    return isolated_write_all(fd, answer.data(), answer.size());
}

openvdb::FloatGrid::Ptr readFirstFloatGrid(const std::string &path, std::string &error)
{
    // OpenVDB's reader is not safe on a corrupt file: a child reads it
    // first (src/common/isolated_read.h), and only a file it read whole is
    // read here.
    char *answer = nullptr, why[160];
    size_t size = 0;
    if (vdb_check_extent(path.c_str(), why, sizeof why) != 0) { // a truncated file, before OpenVDB reads past its end
        error = "cannot read grid " + path + ": " + why;
        return nullptr;
    }
    if (isolated_read(path.c_str(), readInChild, const_cast<std::string *>(&path), &answer, &size, why, sizeof why)) {
        error = "cannot read grid " + path + " (OpenVDB's reader failed on it: " + why + "; a corrupt file?)";
        return nullptr;
    }
    const std::string said(answer, size);
    std::free(answer);
    if (said.empty() || said[0] != 1) {
        error = "cannot read grid " + path + ": " + (said.empty() ? std::string("no answer") : said.substr(1));
        return nullptr;
    }
    try {
        openvdb::io::File file(path);
        file.open(false);
        openvdb::GridPtrVecPtr grids = file.getGrids();
        file.close();
        for (const auto &g : *grids)
            if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g))
                return f;
        error = "no float grid in " + path;
    } catch (const std::exception &e) {
        error = "cannot read grid " + path + ": " + e.what();
    }
    return nullptr;
}

} // namespace

bool checkSign(const TriangleMesh &mesh, const std::vector<std::string> &grids, int samples,
               std::vector<SignCheck> &checks, std::string &error)
{
    std::vector<openvdb::FloatGrid::Ptr> loaded;
    for (const auto &path : grids) {
        loaded.push_back(readFirstFloatGrid(path, error));
        if (!loaded.back())
            return false;
    }
    std::mt19937_64 rng(20240611);
    std::vector<Vec3> points(static_cast<size_t>(samples));
    for (auto &p : points)
        for (int k = 0; k < 3; ++k) {
            const double grow = 0.05 * (mesh.hi[k] - mesh.lo[k]);
            std::uniform_real_distribution<double> u(mesh.lo[k] - grow, mesh.hi[k] + grow);
            p[k] = u(rng);
        }
    const FastWinding soup(mesh.points, mesh.triangles);
    std::vector<double> w(points.size()), dist(points.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 16), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
            w[i] = soup.bruteForce(points[i]);
            dist[i] = soup.distance(points[i]);
        }
    });
    for (size_t g = 0; g < loaded.size(); ++g) {
        const openvdb::FloatGrid &grid = *loaded[g];
        openvdb::FloatGrid::ConstAccessor acc = grid.getConstAccessor();
        const double voxel = grid.voxelSize()[0];
        size_t clear = 0, wrong = 0, wrongFar = 0;
        for (size_t i = 0; i < points.size(); ++i) {
            // Points within a voxel of the surface may round to a voxel
            // across it: that is resolution, not sign, so they are skipped.
            if ((w[i] > 0.25 && w[i] < 0.75) || dist[i] < voxel)
                continue;
            ++clear;
            const openvdb::Coord ijk =
                grid.transform().worldToIndexCellCentered(openvdb::Vec3d(points[i][0], points[i][1], points[i][2]));
            const bool inside = acc.getValue(ijk) < 0.0f;
            if (inside != (w[i] > 0.75)) {
                ++wrong;
                wrongFar += dist[i] >= 3 * voxel;
            }
        }
        checks.push_back(SignCheck{clear, wrong, wrongFar});
    }
    return true;
}

bool checkPointsFitMemory(int points, std::string &error)
{
    // Per point: its position, winding number and distance (doubles), and
    // 40 MiB for the process.
    char line[256];
    const std::string what = std::to_string(points) + " points to check signs at";
    if (memory_check(40.0 * 1024 * 1024 + 40.0 * points, what.c_str(), line, sizeof line) == 0)
        return true;
    error = line;
    return false;
}

} // namespace meshsdf
