// mesh2sdf — the command line: options, defaults, validation, --help.
#ifndef MESH2SDF_OPTIONS_H
#define MESH2SDF_OPTIONS_H

#include <cstdint>
#include <string>
#include <vector>

#include "sdftrace/mesh.h"

namespace mesh2sdf
{

struct Options {
    std::string input;
    std::string output;    // .vdb (required unless --check-sign)
    std::string nvdb, npy; // optional extra outputs
    // The library's settings, an option each (--res, --band, --seed, ...):
    // their defaults, ranges and descriptions are the library's
    // (sdft_mesh_settings); options.cpp makes the option table of them.
    sdft_mesh_params mesh = sdft_mesh_params_defaults();
    sdft_mesh_grid_params grid = sdft_mesh_grid_params_defaults();
    sdft_mesh_sample_params sample = sdft_mesh_sample_params_defaults(); // --samples N: its count
    bool json = false; // one JSON object of counts on stdout instead of the text lines
    bool fp16 = false; // NanoVDB output as Fp16
    bool quiet = false;
    std::vector<std::string> checkSign; // --check-sign GRID.vdb (repeatable): measure, don't convert
    int checkPoints = 10000;            // points for --check-sign
    // --samples N OUT.npy: training samples instead of a grid (points.h),
    // N in sample.count; a batch's per mesh with --formats samples.
    std::string samplesOut;
    // --query POINTS.npy OUT.npy: signed distances at given points (points.h)
    std::string queryIn, queryOut;
    bool winding = false; // --query: the winding number beside each distance
    // --batch LIST: every mesh of LIST converted into outDir (batch.h).
    std::string batch;
    std::string outDir;
    bool batchVdb = true, batchNvdb = false, batchNpy = false; // --formats
    bool batchSamples = false;                                 // --formats samples: DIR/STEM.samples.npy
    int shard = 0, shards = 1;                                 // --shard K/N: this process does shard K of N
    bool help = false;

    bool samples() const { return !samplesOut.empty(); }
};

/// Parses argv into `opt`. Returns false with a one-line `error` on an
/// unknown flag, a missing or malformed value, or a value out of range.
bool parseOptions(int argc, char **argv, Options &opt, std::string &error);

void printHelp();

/// The name of value `value` of the library's CHOICE setting `name` of
/// params struct `of` ("winding"), as the option takes it.
std::string settingChoice(sdft_mesh_settings_of of, const char *name, int value);

} // namespace mesh2sdf

#endif
