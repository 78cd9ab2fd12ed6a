// sdftrace — the voxels of one 8^3 block (distance/band.h) that steps between
// neighbours can join without crossing the mesh, flooded one layer of steps
// at a time on 512-bit masks. Two voxels a, b, neighbours in the
// 26-neighbourhood, are joined when d(a) + d(b) > |a - b| (their lower bounds
// on the distance to the mesh; winding_sign.cpp gives the argument): the
// segment between them then holds no mesh point. No OpenVDB here.
#ifndef SDFT_MESH_SIGN_BLOCK_FLOOD_H
#define SDFT_MESH_SIGN_BLOCK_FLOOD_H

#include "distance/band.h"

#include <cstdint>

namespace meshsdf
{

/// A set of a block's voxels: bit y * 8 + z of word x is voxel (x, y, z),
/// distance/band.h's voxel v = (x * 8 + y) * 8 + z.
struct VoxelMask {
    uint64_t word[kBlockDim] = {};

    bool has(int v) const { return (word[v >> 6] >> (v & 63)) & 1; }
    void add(int v) { word[v >> 6] |= uint64_t(1) << (v & 63); }
    bool empty() const;
    VoxelMask operator&(const VoxelMask &o) const;
    VoxelMask operator|(const VoxelMask &o) const;
    VoxelMask without(const VoxelMask &o) const; // this minus o
    /// The set and every 26-neighbour of it within the block.
    VoxelMask dilated() const;
    /// Calls visit(v) for each voxel v of the set, in increasing order.
    template <typename Visit> void forEach(Visit &&visit) const
    {
        for (int x = 0; x < kBlockDim; ++x)
            for (uint64_t bits = word[x]; bits; bits &= bits - 1)
                visit(x * 64 + __builtin_ctzll(bits));
    }
};

class BlockFlood
{
  public:
    /// `reach[v]` (kBlockSize): a lower bound, in world units, on voxel v's
    /// distance to the mesh; `voxelSize` in world units. Two neighbours a, b
    /// at distance |a - b| are joined when reach[a] + reach[b] exceeds
    /// |a - b| with a margin for rounding (the rule WindingSign's walk uses).
    BlockFlood(const float *reach, double voxelSize);

    /// The voxels of `within` that steps through `within` join to `seed`
    /// (which must be in `within`), found in layers: `layers` receives the
    /// largest number of steps any of them needs. Stops early, returning the
    /// voxels found so far with layers = maxLayers + 1, once more than
    /// `maxLayers` layers would be needed.
    VoxelMask flood(int seed, const VoxelMask &within, int maxLayers, int &layers) const;

  private:
    // Voxels farther than half the longest step's length (with a margin):
    // any two neighbours among them are joined.
    VoxelMask mClear;
    // Each voxel that is not clear, and the neighbours it is joined to.
    int mSlot[kBlockSize]; // index into mLinks, or -1 for a clear voxel
    VoxelMask mLinks[kBlockSize];
    int mLinkCount = 0;
};

} // namespace meshsdf

#endif
