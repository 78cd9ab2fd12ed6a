// sdftrace — a converted grid's files: OpenVDB (.vdb), NanoVDB (.nvdb),
// dense NumPy (.npy) with a sidecar JSON, each written by name into a file
// its caller reserved (the API's GridFiles: temporary files renamed into
// place together, src/common/atomic_file.h). .vdb and .nvdb through
// sdftrace's one grid-file writer (src/gridfile/grid_file.h), the sidecar
// through its one sidecar writer (src/common/json.h).
#ifndef SDFT_MESH_GRID_GRID_FILES_H
#define SDFT_MESH_GRID_GRID_FILES_H

#include "grid/build.h"

#include <openvdb/openvdb.h>

#include <string>

namespace meshsdf
{

/// What the metadata records about the conversion.
struct Provenance {
    std::string source; // input mesh path
    std::string sign;   // sign method name
    double band = 0;    // half-width, voxels
    bool full = false;
};

/// Names the grid, attaches metadata naming the source mesh and sign method.
void describeGrid(openvdb::FloatGrid &grid, const std::string &name, const Provenance &how);

bool writeVdb(const openvdb::FloatGrid &grid, const std::string &tmp, std::string &error);
/// NanoVDB through openToNanoVDB, float or (fp16) Fp16 values.
bool writeNvdb(const openvdb::FloatGrid &grid, bool fp16, const std::string &tmp, std::string &error);
/// The box densely, float32, C order, shape (nx, ny, nz): z varies fastest.
bool writeNpy(const openvdb::FloatGrid &grid, const BoxGeometry &box, const std::string &tmp, std::string &error);
/// Sidecar JSON: origin (world centre of voxel [0,0,0]), voxel size, shape,
/// axis order and provenance. `npyName` is the array's final file name.
bool writeNpyJson(const BoxGeometry &box, const std::string &npyName, const Provenance &how, float background,
                  const std::string &tmp, std::string &error);

/// OUT.npy -> OUT.json (any other name: name + ".json").
std::string sidecarPath(const std::string &npyPath);

} // namespace meshsdf

#endif
