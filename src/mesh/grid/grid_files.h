// sdftrace — writing a converted grid: OpenVDB (.vdb), NanoVDB (.nvdb), dense NumPy
// (.npy) with a sidecar JSON. Every file is written under a temporary name
// in its destination folder and renamed at the end, so a failure never
// leaves a half-written file at the destination: sdftrace's one atomic
// writer (src/common/atomic_file.h), and its one grid-file writer
// (src/gridfile/grid_file.h) for .vdb and .nvdb.
#ifndef SDFT_MESH_GRID_GRID_FILES_H
#define SDFT_MESH_GRID_GRID_FILES_H

#include "grid/build.h"

#include <openvdb/openvdb.h>

#include <cstdio>
#include <string>

#include "atomic_file.h"

namespace meshsdf
{

/// A destination and the temporary file reserved next to it (`tmp`).
struct PendingFile {
    atomic_file file{};
    std::string tmp;
};

/// Creates the temporary file (proving the folder is writable). Fails with
/// one line if the folder is missing or unwritable, or `path` is a folder.
bool reserveFile(const std::string &path, PendingFile &file, std::string &error);
/// Flushes the temporary file and renames it onto the destination.
bool commitFile(PendingFile &file, std::string &error);
/// Removes the temporary file, if any.
void discardFile(PendingFile &file);

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
