// sdftrace — what a conversion and a draw of training samples are asked
// for, inside the mesh component: sdft_mesh_grid_params and
// sdft_sample_params (sdftrace/mesh.h) as the converter's C++ takes them,
// with the limits both the library and mesh2sdf hold to.
#ifndef CONVERTER_SETTINGS_H
#define CONVERTER_SETTINGS_H

#include "sdftrace/mesh.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace converter
{

enum class SignMethod { Winding, Flood, None };
const char *signMethodName(SignMethod m);

/// Largest grid side in voxels (res, or the side a voxel size implies).
constexpr int kMaxResolution = SDFT_MESH_MAX_RES;
/// Largest dense output (full, .npy) in voxels.
constexpr double kMaxDenseVoxels = SDFT_MESH_MAX_DENSE_VOXELS;
/// Most training samples one draw makes: 1.6 GB of rows.
constexpr double kMaxSamples = SDFT_MESH_MAX_SAMPLES;

/// A grid to build (grid.h).
struct GridSettings {
    std::string source;     // the mesh the grid's metadata names
    int res = 256;          // longest side of the padded box, in voxels
    double voxelSize = 0.0; // world units; > 0 overrides res
    double band = 3.0;      // narrow-band half-width, voxels
    bool full = false;      // a distance in every voxel of the padded box
    double padding = 4.0;   // voxels around the mesh bounds
    SignMethod sign = SignMethod::Winding;
    bool simd = true;        // vector instructions where the processor has them
    bool simd512 = true;     // and AVX-512 among them
    bool writesNpy = false;  // a dense array will be made of it (its size limit applies)
    bool writesNvdb = false; // a NanoVDB copy will be made of it (its memory counts)
};

/// Training samples to draw (samples.h); DeepSDF's distribution by default.
struct SampleSettings {
    size_t count = 250000;
    double nearSigma[2] = {0.070710678118654752, 0.022360679774997897}; // sqrt(0.005), sqrt(0.0005)
    double uniformShare = 0.06;                                         // 3/50
    uint64_t seed = 1;
};

} // namespace converter

#endif
