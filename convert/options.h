// mesh2sdf — the command line: options, defaults, validation, --help.
#ifndef MESH2SDF_OPTIONS_H
#define MESH2SDF_OPTIONS_H

#include <string>
#include <vector>

namespace mesh2sdf
{

enum class SignMethod { Winding, Flood, None };
const char *signMethodName(SignMethod m);

/// --orient: outward (each patch consistent and facing outward, orient.h)
/// or none (the faces as the file has them).
enum class OrientMethod { Outward, None };

/// Largest grid side in voxels (--res, or the side --voxel-size implies).
constexpr int kMaxResolution = 4096;
/// Largest dense output (--full, --npy) in voxels: 2^31 (8 GiB of float32).
constexpr double kMaxDenseVoxels = 2147483648.0;
/// Most training samples one run writes (--samples): 1.6 GB of rows.
constexpr double kMaxSamples = 1e8;

struct Options {
    std::string input;
    std::string output;     // .vdb (required unless --check-sign)
    std::string nvdb, npy;  // optional extra outputs
    int res = 256;          // longest side of the padded box, in voxels
    double voxelSize = 0.0; // world units; > 0 overrides res
    double band = 3.0;      // narrow-band half-width, voxels
    bool full = false;      // a distance in every voxel of the padded box
    double padding = -1.0;  // voxels around the mesh bounds; < 0: band + 1
    SignMethod sign = SignMethod::Winding;
    OrientMethod orient = OrientMethod::Outward;
    bool json = false; // one JSON object of counts on stdout instead of the text lines
    bool fp16 = false; // NanoVDB output as Fp16
    std::string name;  // grid name; empty: the mesh's file stem
    int threads = 0;   // 0: all cores
    bool quiet = false;
    bool simd = true;                   // vector instructions where the processor has them
    bool simd512 = true;                // and AVX-512 among them (--simd auto)
    std::vector<std::string> checkSign; // --check-sign GRID.vdb (repeatable): measure, don't convert
    int checkPoints = 10000;            // points for --check-sign
    // --samples N OUT.npy: training samples instead of a grid (samples.h)
    size_t samples = 0;
    std::string samplesOut;
    double nearSigma[2] = {0.070710678118654752, 0.022360679774997897}; // DeepSDF's sqrt(0.005), sqrt(0.0005)
    double uniformShare = 0.06;                                         // DeepSDF's 3/50
    int seed = 1;
    // --query POINTS.npy OUT.npy: signed distances at given points (query.h)
    std::string queryIn, queryOut;
    bool winding = false;   // --query: the winding number beside each distance
    bool normalize = false; // --samples, --query: the mesh mapped into the unit sphere first (unit_sphere.h)
    // --batch LIST: every mesh of LIST converted into outDir (batch.h).
    std::string batch;
    std::string outDir;
    bool batchVdb = true, batchNvdb = false, batchNpy = false; // --formats
    int shard = 0, shards = 1;                                 // --shard K/N: this process does shard K of N
    bool help = false;
};

/// Parses argv into `opt`. Returns false with a one-line `error` on an
/// unknown flag, a missing or malformed value, or a value out of range.
bool parseOptions(int argc, char **argv, Options &opt, std::string &error);

void printHelp();

} // namespace mesh2sdf

#endif
