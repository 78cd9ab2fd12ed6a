// mesh2sdf — one mesh converted: its outputs reserved, the mesh read and
// oriented, the grid built and every file renamed into place, or nothing
// left at any destination. Prints nothing and never exits: what happened
// comes back as a JobResult, for the command line (main.cpp), a batch
// (batch.h) and, later, a library to report as they see fit.
#ifndef MESH2SDF_JOB_H
#define MESH2SDF_JOB_H

#include "grid.h"
#include "mesh.h"
#include "options.h"
#include "orient.h"
#include "progress.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace mesh2sdf
{

/// What converting one mesh did. `error` is one line (no program name)
/// when !ok; the counts are filled as far as the conversion got.
struct JobResult {
    bool ok = false;
    std::string error;
    MeshHealth health;                // read and counted (mesh.h)
    OrientCounts orient;              // what orienting did, when `oriented`
    bool oriented = false;            // --orient outward ran
    double orientSeconds = 0;         // welding and orienting
    bool meshRead = false;            // health (and orient) describe the mesh
    BoxGeometry box;                  // the padded box, once planned
    uint64_t activeVoxels = 0;        // in the written grid
    double gridMiB = 0;               // the grid's memory
    BuildStats stats;                 // winding time, ambiguous voxels
    bool surface = false;             // some active voxel is inside (a zero crossing)
    double seconds = 0;               // the whole job, wall clock
    std::vector<std::string> outputs; // the files in place, in the order reserved
};

/// A path's file name without its folder and last extension: the grid's
/// name unless --name gives one, and a batch's output name.
std::string fileStem(const std::string &path);

/// The files a conversion writes: opt.output (.vdb), opt.nvdb, and opt.npy
/// with its sidecar JSON, each where given (a batch may leave out the .vdb).
/// Each kind of output is a path in Options: a new kind is reserved,
/// written and listed here, and a batch names it in meshOptions (batch.cpp). A batch asks whether all of
/// them exist before converting a mesh again.
std::vector<std::string> jobOutputs(const Options &opt);

/// Converts opt.input into the outputs named by `opt` (see jobOutputs),
/// showing its stages on `progress`. `meshReady`, if given, is called once
/// the mesh is read and oriented, before the grid is built (the command
/// line prints its health line then). Never throws: a failure (a missing,
/// corrupt or empty mesh, non-finite coordinates, an unwritable output, out
/// of memory) is a result with ok false and one line in error.
JobResult convertMesh(const Options &opt, Progress &progress,
                      const std::function<void(const JobResult &)> &meshReady = {});

} // namespace mesh2sdf

#endif
