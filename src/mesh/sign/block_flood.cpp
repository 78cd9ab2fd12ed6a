// sdftrace — a block's joined voxels, flooded on masks (see block_flood.h).
//
// A voxel whose reach exceeds half the longest step (sqrt(3) voxels, with
// the rounding margin the step rule keeps) is joined to each neighbour whose
// reach does too, whatever the step: such pairs flood by shifting whole
// masks. Only the others, the voxels nearer than about 0.87 voxel to the
// mesh, keep a mask of the neighbours the rule joins them to, tested pair by
// pair once.
#include "sign/block_flood.h"

#include <cmath>

namespace meshsdf
{

namespace
{

constexpr uint64_t kNotFirstZ = 0xFEFEFEFEFEFEFEFEull; // bits whose z > 0
constexpr uint64_t kNotLastZ = 0x7F7F7F7F7F7F7F7Full;  // bits whose z < 7

} // namespace

bool VoxelMask::empty() const
{
    uint64_t any = 0;
    for (uint64_t w : word)
        any |= w;
    return any == 0;
}

VoxelMask VoxelMask::operator&(const VoxelMask &o) const
{
    VoxelMask r;
    for (int x = 0; x < kBlockDim; ++x)
        r.word[x] = word[x] & o.word[x];
    return r;
}

VoxelMask VoxelMask::operator|(const VoxelMask &o) const
{
    VoxelMask r;
    for (int x = 0; x < kBlockDim; ++x)
        r.word[x] = word[x] | o.word[x];
    return r;
}

VoxelMask VoxelMask::without(const VoxelMask &o) const
{
    VoxelMask r;
    for (int x = 0; x < kBlockDim; ++x)
        r.word[x] = word[x] & ~o.word[x];
    return r;
}

VoxelMask VoxelMask::dilated() const
{
    uint64_t yz[kBlockDim];
    for (int x = 0; x < kBlockDim; ++x) {
        const uint64_t w = word[x];
        const uint64_t z = w | ((w << 1) & kNotFirstZ) | ((w >> 1) & kNotLastZ);
        yz[x] = z | (z << kBlockDim) | (z >> kBlockDim);
    }
    VoxelMask r;
    for (int x = 0; x < kBlockDim; ++x)
        r.word[x] = yz[x] | (x > 0 ? yz[x - 1] : 0) | (x + 1 < kBlockDim ? yz[x + 1] : 0);
    return r;
}

BlockFlood::BlockFlood(const float *reach, double voxelSize)
{
    // The step rule of WindingSign::signBlock: reach[a] + reach[b] > crossing.
    float crossing[4];
    for (int n = 1; n <= 3; ++n)
        crossing[n] = float(std::sqrt(double(n)) * voxelSize) * (1.0f + 1e-5f);
    // Two reaches above this sum to more than the longest crossing, rounding
    // included (the margin 1e-3 dwarfs float's 6e-8).
    const float clear = 0.5f * crossing[3] * (1.0f + 1e-3f);
    for (int v = 0; v < kBlockSize; ++v) {
        if (reach[v] > clear) {
            mClear.add(v);
            mSlot[v] = -1;
            continue;
        }
        mSlot[v] = mLinkCount;
        VoxelMask &links = mLinks[mLinkCount++];
        links = VoxelMask();
        const int x = v >> (2 * kBlockLog2), y = (v >> kBlockLog2) & (kBlockDim - 1), z = v & (kBlockDim - 1);
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    const int n[3] = {x + dx, y + dy, z + dz};
                    if ((dx == 0 && dy == 0 && dz == 0) || n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= kBlockDim ||
                        n[1] >= kBlockDim || n[2] >= kBlockDim)
                        continue;
                    const int u = (((n[0] << kBlockLog2) | n[1]) << kBlockLog2) | n[2];
                    if (reach[v] + reach[u] > crossing[dx * dx + dy * dy + dz * dz])
                        links.add(u);
                }
    }
}

VoxelMask BlockFlood::flood(int seed, const VoxelMask &within, int maxLayers, int &layers) const
{
    VoxelMask reached, frontier;
    reached.add(seed);
    frontier.add(seed);
    for (layers = 0;; ++layers) {
        // Clear to clear by shifting; from a voxel that is not clear by its
        // links; to one that is not clear from a clear voxel of the frontier
        // by its links (joining is symmetric).
        const VoxelMask clearFrontier = frontier & mClear;
        const VoxelMask around = clearFrontier.dilated();
        VoxelMask next = around & mClear;
        frontier.without(mClear).forEach([&](int v) { next = next | mLinks[mSlot[v]]; });
        (around.without(mClear).without(reached) & within).forEach([&](int u) {
            if (!(mLinks[mSlot[u]] & clearFrontier).empty())
                next.add(u);
        });
        next = (next & within).without(reached);
        if (next.empty())
            return reached;
        if (layers == maxLayers) {
            layers = maxLayers + 1;
            return reached;
        }
        reached = reached | next;
        frontier = next;
    }
}

} // namespace meshsdf
