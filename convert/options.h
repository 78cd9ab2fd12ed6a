// mesh2sdf — the command line: options, defaults, validation, --help.
#ifndef MESH2SDF_OPTIONS_H
#define MESH2SDF_OPTIONS_H

#include <string>
#include <vector>

#include "sdftrace/mesh.h"

namespace mesh2sdf
{

/// --orient: outward (each patch consistent and facing outward,
/// sdft_mesh_params.orient)
/// or none (the faces as the file has them).
enum class OrientMethod { Outward, None };

/// Largest grid side in voxels (--res, or the side --voxel-size implies).
constexpr int kMaxResolution = SDFT_MESH_MAX_RES;
/// Most training samples one run writes (--samples): 1.6 GB of rows.
constexpr double kMaxSamples = SDFT_MESH_MAX_SAMPLES;

struct Options {
    std::string input;
    std::string output;     // .vdb (required unless --check-sign)
    std::string nvdb, npy;  // optional extra outputs
    int res = 256;          // longest side of the padded box, in voxels
    double voxelSize = 0.0; // world units; > 0 overrides res
    double band = 3.0;      // narrow-band half-width, voxels
    bool full = false;      // a distance in every voxel of the padded box
    double padding = -1.0;  // voxels around the mesh bounds; < 0: band + 1
    sdft_mesh_sign sign = SDFT_SIGN_WINDING;
    OrientMethod orient = OrientMethod::Outward;
    bool json = false; // one JSON object of counts on stdout instead of the text lines
    bool fp16 = false; // NanoVDB output as Fp16
    std::string name;  // grid name; empty: the mesh's file stem
    int threads = 0;   // 0: all cores
    bool quiet = false;
    sdft_simd simd = SDFT_SIMD_AUTO;    // --simd
    std::vector<std::string> checkSign; // --check-sign GRID.vdb (repeatable): measure, don't convert
    int checkPoints = 10000;            // points for --check-sign
    // --samples N OUT.npy: training samples instead of a grid (points.h)
    size_t samples = 0;
    std::string samplesOut;
    double nearSigma[2] = {0.070710678118654752, 0.022360679774997897}; // DeepSDF's sqrt(0.005), sqrt(0.0005)
    double uniformShare = 0.06;                                         // DeepSDF's 3/50
    int seed = 1;
    // --query POINTS.npy OUT.npy: signed distances at given points (points.h)
    std::string queryIn, queryOut;
    bool winding = false; // --query: the winding number beside each distance
    bool normalize =
        false; // --samples, --query: the mesh mapped into the unit sphere first (sdft_mesh_params.normalize)
    // --batch LIST: every mesh of LIST converted into outDir (batch.h).
    std::string batch;
    std::string outDir;
    bool batchVdb = true, batchNvdb = false, batchNpy = false; // --formats
    bool batchSamples = false;                                 // --formats samples: DIR/STEM.samples.npy
    int batchSampleCount = 250000;                             // --sample-count N (DeepSDF's count)
    int shard = 0, shards = 1;                                 // --shard K/N: this process does shard K of N
    bool help = false;
};

/// Parses argv into `opt`. Returns false with a one-line `error` on an
/// unknown flag, a missing or malformed value, or a value out of range.
bool parseOptions(int argc, char **argv, Options &opt, std::string &error);

void printHelp();

} // namespace mesh2sdf

#endif
