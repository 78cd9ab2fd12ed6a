// sample_bench's C++ side: NanoVDB's own trilinear sampler (SampleFromVoxels
// of order 1 over a ReadAccessor, as createSampler<1> makes it) and a dense
// float array filled from the grid's leaves: the two samplers sdftrace's
// grid field is measured against.
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include <sys/mman.h>

#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/SampleFromVoxels.h>

#include "sample_nano.h"

extern "C" double sb_nano_sum(const void *grid_bytes, const float *xyz, size_t n, int chained)
{
    const auto *grid = reinterpret_cast<const nanovdb::NanoGrid<float> *>(grid_bytes);
    auto acc = grid->getAccessor();
    auto sampler = nanovdb::createSampler<1>(acc);
    double sum = 0.0;
    float prev = 0.0f;
    for (size_t i = 0; i < n; i++) {
        const float k = chained ? prev * 0.0f : 0.0f; // chained: the next point waits for this value
        const nanovdb::Vec3f p(xyz[3 * i] + k, xyz[3 * i + 1], xyz[3 * i + 2]);
        prev = sampler(grid->worldToIndexF(p));
        sum += prev;
    }
    return sum;
}

extern "C" int sb_dense_make(const void *grid_bytes, sb_dense *d)
{
    const auto *grid = reinterpret_cast<const nanovdb::NanoGrid<float> *>(grid_bytes);
    const auto &tree = grid->tree();
    const auto bbox = grid->indexBBox();
    for (int k = 0; k < 3; k++) {
        d->lo[k] = bbox.min()[k] - 1;
        d->n[k] = bbox.max()[k] - bbox.min()[k] + 3;
    }
    const size_t count = (size_t)d->n[0] * d->n[1] * d->n[2];
    // 2 MiB pages where the kernel has them (transparent huge pages on
    // madvise): the dense array at its best, not bound by TLB misses.
    const size_t bytes = (count * sizeof(float) + (2u << 20) - 1) & ~(size_t)((2u << 20) - 1);
    d->v = static_cast<float *>(std::aligned_alloc(2u << 20, bytes));
    if (!d->v)
        return -1;
    if (getenv("SB_NO_HUGE") == nullptr)
        madvise(d->v, bytes, MADV_HUGEPAGE);
    const float bg = tree.background();
    for (size_t i = 0; i < count; i++)
        d->v[i] = bg;
    // Every voxel of every leaf (inactive ones hold +-background), z fastest.
    const auto *leaf = tree.getFirstNode<0>();
    for (uint32_t l = 0; l < tree.nodeCount(0); l++, leaf++) {
        const nanovdb::Coord o = leaf->origin();
        for (int i = 0; i < 512; i++) {
            const int x = o[0] + (i >> 6) - d->lo[0], y = o[1] + (i >> 3 & 7) - d->lo[1], z = o[2] + (i & 7) - d->lo[2];
            if (x < 0 || y < 0 || z < 0 || x >= d->n[0] || y >= d->n[1] || z >= d->n[2])
                continue;
            d->v[((size_t)x * d->n[1] + y) * d->n[2] + z] = leaf->getValue(i);
        }
    }
    // Tiles inside the box (e.g. the inside of a closed surface): their value.
    auto acc = tree.getAccessor();
    const int a[3] = {d->lo[0] & ~7, d->lo[1] & ~7, d->lo[2] & ~7};
    for (int x = a[0] - d->lo[0]; x < d->n[0]; x += 8)
        for (int y = a[1] - d->lo[1]; y < d->n[1]; y += 8)
            for (int z = a[2] - d->lo[2]; z < d->n[2]; z += 8) {
                const nanovdb::Coord c(x + d->lo[0], y + d->lo[1], z + d->lo[2]);
                if (acc.probeLeaf(c))
                    continue;
                const float v = acc.getValue(c);
                if (v == bg)
                    continue;
                for (int i = x < 0 ? 0 : x; i < x + 8 && i < d->n[0]; i++) // a tile covers the whole aligned 8^3 block
                    for (int j = y < 0 ? 0 : y; j < y + 8 && j < d->n[1]; j++)
                        for (int m = z < 0 ? 0 : z; m < z + 8 && m < d->n[2]; m++)
                            d->v[((size_t)i * d->n[1] + j) * d->n[2] + m] = v;
            }
    const auto &map = grid->map();
    for (int k = 0; k < 9; k++)
        d->w2i[k] = map.mInvMatF[k];
    for (int k = 0; k < 3; k++)
        d->w2i_t[k] = -(map.mInvMatF[3 * k] * map.mVecF[0] + map.mInvMatF[3 * k + 1] * map.mVecF[1] +
                        map.mInvMatF[3 * k + 2] * map.mVecF[2]);
    return 0;
}
