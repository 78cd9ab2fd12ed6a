// sdftrace — baking a field into an OpenVDB level set.
//
// The grid has cubic voxels over the field's bounding box, `res` voxels on
// its longest edge, voxel (i, j, k) centred at lo + (i + 1/2, j + 1/2, k + 1/2) h.
// A narrow-band bake never visits all res^3 voxels: it walks the tree's own
// blocks top down (128^3 blocks, the upper nodes' tiles, then 8^3 blocks, the
// leaves) and evaluates the field once at a block's centre c. Every voxel
// centre of the block lies within its half-diagonal r = sqrt(3) (D - 1) h / 2
// of c, and the field is a distance bound (1-Lipschitz), so when
// |f(c)| > r + band every voxel of the block is farther than the band from
// the surface: the block becomes one inactive tile, +-background by the sign
// of f(c) (only inside tiles are stored; outside is the background). This is
// exactly the invariant the tracer's tree bound relies on (src/grid/grid_sample.c):
// every voxel a tile covers has |s| >= |tile value|. Leaves that survive are
// evaluated voxel by voxel: |f| < band active with f, else inactive +-band.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "atomic_file.h"
#include "sdftrace/grid.h"
#include "vdb_internal.h"

using LeafT = openvdb::FloatTree::LeafNodeType;

namespace
{

struct Tile {
    openvdb::Coord origin;
    openvdb::Index level; // 1: 8^3 (in a lower node), 2: 128^3 (in an upper node)
    float value;
};

struct Baker {
    const sdft_field *f;
    sdft_vec3 lo;
    float h, band; // voxel size and band half-width, world units
    int n[3];
    bool full;

    std::atomic<uint64_t> evaluations{0};

    openvdb::Vec3f centre(const openvdb::Coord &ijk) const
    {
        return {lo.x + (ijk.x() + 0.5f) * h, lo.y + (ijk.y() + 0.5f) * h, lo.z + (ijk.z() + 0.5f) * h};
    }

    float eval(sdft_scratch *s, float x, float y, float z) const { return f->distance(f->ctx, s, sdft_v3(x, y, z)); }

    bool in_domain(const openvdb::Coord &o) const { return o.x() < n[0] && o.y() < n[1] && o.z() < n[2]; }

    // Value at a block of dim D at `o` when the whole block is farther than
    // the band from the surface; 0 when it must be subdivided.
    float skip_value(sdft_scratch *s, const openvdb::Coord &o, int dim) const
    {
        const float half = 0.5f * float(dim - 1);
        float v = eval(s, lo.x + (o.x() + half + 0.5f) * h, lo.y + (o.y() + half + 0.5f) * h,
                       lo.z + (o.z() + half + 0.5f) * h);
        return std::fabs(v) > 1.7320508f * half * h + band ? std::copysign(band, v) : 0.0f;
    }

    // All 512 voxels of the leaf at o; null (and maybe a tile) when none is
    // active and all share a sign.
    std::unique_ptr<LeafT> leaf(sdft_scratch *s, const openvdb::Coord &o, std::vector<Tile> &tiles) const
    {
        auto leaf = std::make_unique<LeafT>(o, band, false);
        int active = 0, neg = 0;
        for (openvdb::Index i = 0; i < LeafT::SIZE; i++) {
            const openvdb::Coord ijk = leaf->offsetToGlobalCoord(i);
            const openvdb::Vec3f p = centre(ijk);
            const float v = eval(s, p.x(), p.y(), p.z());
            neg += v < 0.0f;
            if (in_domain(ijk) && (full || std::fabs(v) < band)) {
                leaf->setValueOn(i, v);
                active++;
            } else {
                leaf->setValueOff(i, std::copysign(band, v));
            }
        }
        if (active == 0 && (neg == 0 || neg == int(LeafT::SIZE))) {
            if (neg)
                tiles.push_back({o, 1, -band});
            return nullptr;
        }
        return leaf;
    }
};

// The output file: its temporary file is made before any work, so that an
// unwritable destination fails at once; removed unless committed.
struct Output {
    atomic_file af;
    bool open = false;
    ~Output()
    {
        if (open)
            atomic_file_abort(&af);
    }
    sdft_error begin(const char *path, char *msg, size_t msg_len)
    {
        const sdft_error rc = atomic_file_begin(&af, path, msg, msg_len);
        open = rc == SDFT_OK;
        return rc;
    }
    // Writes the grid and those beside it (.vdb or .nvdb by the target's
    // extension) and renames the file into place.
    sdft_error write(const openvdb::FloatGrid &grid, const std::vector<openvdb::FloatGrid::ConstPtr> &beside, bool fp16,
                     char *msg, size_t msg_len)
    {
        const char *dot = std::strrchr(af.path, '.');
        const bool nvdb = dot && std::strcmp(dot, ".nvdb") == 0;
        if (sdft_error rc = sdft_vdb::write_grids(grid, beside, nvdb, fp16 ? SDFT_QUANT_FP16 : SDFT_QUANT_NONE,
                                                  af.tmp_path, af.path, msg, msg_len))
            return rc;
        open = false;
        return atomic_file_commit(&af, msg, msg_len);
    }
};

// What sdft_bake refuses before any work, or SDFT_OK.
sdft_error check(const sdft_field *f, const sdft_bake_params *p, const char *path, char *msg, size_t msg_len)
{
    if (!f || !f->distance)
        return fail_with(msg, msg_len, SDFT_EINVAL, "no field, or a field without a distance function");
    if (!p)
        return fail_with(msg, msg_len, SDFT_EINVAL, "no bake parameters (NULL)");
    if (p->res < 1 || p->res > SDFT_BAKE_MAX_RES)
        return fail_with(msg, msg_len, SDFT_EINVAL, "resolution must be in 1..%d, got %d", SDFT_BAKE_MAX_RES, p->res);
    if (!p->full && !(p->band > 0.0f && p->band <= 1000.0f))
        return fail_with(msg, msg_len, SDFT_EINVAL, "band must be a number of voxels in (0, 1000]");
    if (p->threads < 0)
        return fail_with(msg, msg_len, SDFT_EINVAL, "threads must be >= 0, got %d", p->threads);
    if (p->materials && !f->material)
        return fail_with(msg, msg_len, SDFT_EINVAL, "the field has no materials to bake (sdft_field.material is NULL)");
    if (p->materials && !path)
        return fail_with(msg, msg_len, SDFT_EINVAL, "materials are baked into a file: give a path");
    if (path) {
        const char *dot = std::strrchr(path, '.');
        if (!dot || (std::strcmp(dot, ".vdb") != 0 && std::strcmp(dot, ".nvdb") != 0))
            return fail_with(msg, msg_len, SDFT_EINVAL, "%s: output must end in .vdb or .nvdb", path);
    }
    const sdft_vec3 ext = sdft_sub(f->bounds.hi, f->bounds.lo);
    if (!sdft_isfinite3(ext) || !sdft_isfinite3(f->bounds.lo) || !(sdft_minf(ext.x, sdft_minf(ext.y, ext.z)) >= 0.0f) ||
        !(sdft_maxcomp(ext) > 0.0f))
        return fail_with(msg, msg_len, SDFT_EINVAL, "the field's bounding box is empty or infinite");
    return SDFT_OK;
}

// 1. Blocks of 128^3: tiles (into tiles, a list per block), or the 8^3
// leaf blocks to evaluate, whose origins it returns in the blocks' order.
std::vector<openvdb::Coord> plan_blocks(const Baker &bk, tbb::task_arena &arena, std::vector<std::vector<Tile>> &tiles,
                                        std::atomic<uint64_t> &evals)
{
    const int nb[3] = {(bk.n[0] + 127) / 128, (bk.n[1] + 127) / 128, (bk.n[2] + 127) / 128};
    const size_t blocks = size_t(nb[0]) * nb[1] * nb[2];
    std::vector<std::vector<openvdb::Coord>> todo(blocks);
    tiles.assign(blocks, std::vector<Tile>());
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks), [&](const tbb::blocked_range<size_t> &r) {
            sdft_scratch s;
            sdft_scratch_init(bk.f, &s);
            uint64_t count = 0;
            for (size_t bi = r.begin(); bi != r.end(); ++bi) {
                const openvdb::Coord o(int(bi % nb[0]) * 128, int(bi / nb[0] % nb[1]) * 128,
                                       int(bi / nb[0] / nb[1]) * 128);
                if (!bk.full) {
                    count++;
                    if (float v = bk.skip_value(&s, o, 128)) {
                        if (v < 0.0f)
                            tiles[bi].push_back({o, 2, v});
                        continue;
                    }
                }
                for (int z = 0; z < 128; z += 8)
                    for (int y = 0; y < 128; y += 8)
                        for (int x = 0; x < 128; x += 8) {
                            const openvdb::Coord lo = o.offsetBy(x, y, z);
                            if (!bk.in_domain(lo))
                                continue;
                            if (!bk.full) {
                                count++;
                                if (float v = bk.skip_value(&s, lo, 8)) {
                                    if (v < 0.0f)
                                        tiles[bi].push_back({lo, 1, v});
                                    continue;
                                }
                            }
                            todo[bi].push_back(lo);
                        }
            }
            evals += count;
        });
    });
    std::vector<openvdb::Coord> leaf_origins;
    for (auto &t : todo) {
        leaf_origins.insert(leaf_origins.end(), t.begin(), t.end());
        std::vector<openvdb::Coord>().swap(t);
    }

    return leaf_origins;
}

// 2. The leaves, voxel by voxel, into leaves (NULL where none is kept), and
// the inside tiles found among them into tiles; once the progress callback
// says stop, the rest are skipped and it returns false.
bool bake_leaves(const Baker &bk, const sdft_bake_params *p, tbb::task_arena &arena,
                 const std::vector<openvdb::Coord> &leaf_origins, std::vector<std::unique_ptr<LeafT>> &leaves,
                 std::vector<std::vector<Tile>> &tiles, std::atomic<uint64_t> &evals)
{
    sdft_vdb::Progress progress;
    progress.fn = p->progress;
    progress.user = p->progress_user;
    progress.total = std::max<uint64_t>(1, leaf_origins.size());
    leaves.resize(leaf_origins.size());
    std::mutex tiles_mutex;
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, leaf_origins.size(), 64),
                          [&](const tbb::blocked_range<size_t> &r) {
                              if (progress.stop)
                                  return;
                              sdft_scratch s;
                              sdft_scratch_init(bk.f, &s);
                              std::vector<Tile> local;
                              for (size_t i = r.begin(); i != r.end(); ++i) {
                                  leaves[i] = bk.leaf(&s, leaf_origins[i], local);
                                  progress.step();
                              }
                              evals += uint64_t(r.size()) * LeafT::SIZE;
                              if (!local.empty()) {
                                  std::lock_guard<std::mutex> lock(tiles_mutex);
                                  tiles.push_back(std::move(local));
                              }
                          });
    });
    return !progress.stop;
}

// 3. The tree: inside tiles, then the leaves (the tree takes them; *kept
// counts them), in cubic voxels of bk.h from b.lo.
openvdb::FloatGrid::Ptr make_tree(const Baker &bk, const sdft_bake_params *p, const sdft_aabb &b,
                                  const std::vector<std::vector<Tile>> &tiles,
                                  std::vector<std::unique_ptr<LeafT>> &leaves, uint64_t *kept)
{
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(bk.band);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(bk.h));
    grid->transform().postTranslate(openvdb::Vec3d(b.lo.x + 0.5 * bk.h, b.lo.y + 0.5 * bk.h, b.lo.z + 0.5 * bk.h));
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    grid->setName(p->grid_name ? p->grid_name : "sdf");
    auto &tree = grid->tree();
    for (auto &list : tiles)
        for (const Tile &t : list)
            tree.addTile(t.level, t.origin, t.value, false);
    for (auto &leaf : leaves)
        if (leaf) {
            tree.addLeaf(leaf.release());
            (*kept)++;
        }
    return grid;
}

bool same_material(const sdft_material &a, const sdft_material &b)
{
    return a.colour.x == b.colour.x && a.colour.y == b.colour.y && a.colour.z == b.colour.z &&
           a.reflectance == b.reflectance && a.ior == b.ior;
}

// The index of m in table, appended if new.
float material_index(std::vector<sdft_material> &table, const sdft_material &m)
{
    for (size_t k = 0; k < table.size(); k++)
        if (same_material(table[k], m))
            return float(k);
    table.push_back(m);
    return float(table.size() - 1);
}

// 4. The surface's materials (sdftrace/grid.h's convention): the grid of
// indices, active where the surface's voxels are and within 3 voxels of
// it, each the index of f's material at the voxel's centre in the table of
// the distinct materials, numbered as first met in the tree's leaf order
// (so any thread count writes the same file); and the table as a grid.
// SDFT_OK, or SDFT_EINVAL when there are too many distinct materials.
sdft_error bake_materials(const Baker &bk, const sdft_bake_params *p, tbb::task_arena &arena,
                          const openvdb::FloatGrid &surface, std::vector<openvdb::FloatGrid::ConstPtr> &out, char *msg,
                          size_t msg_len)
{
    std::vector<const LeafT *> from;
    for (auto it = surface.tree().cbeginLeaf(); it; ++it)
        from.push_back(it.getLeaf());
    const float reach = std::min(bk.band, 3.0f * bk.h);
    std::vector<std::unique_ptr<LeafT>> ids(from.size());
    std::vector<std::vector<sdft_material>> local(from.size()); // each leaf's materials, its values index them
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, from.size(), 64), [&](const tbb::blocked_range<size_t> &r) {
            for (size_t i = r.begin(); i != r.end(); ++i) {
                auto leaf = std::make_unique<LeafT>(from[i]->origin(), -1.0f, false);
                for (auto v = from[i]->cbeginValueOn(); v; ++v)
                    if (std::fabs(*v) < reach) {
                        const openvdb::Vec3f c = bk.centre(v.getCoord());
                        const sdft_material m = bk.f->material(bk.f->ctx, sdft_v3(c.x(), c.y(), c.z()));
                        leaf->setValueOn(v.pos(), material_index(local[i], m));
                    }
                if (leaf->onVoxelCount())
                    ids[i] = std::move(leaf);
            }
        });
    });
    std::vector<sdft_material> table;
    std::vector<float> remap;
    for (size_t i = 0; i < from.size(); i++) {
        if (!ids[i])
            continue;
        remap.clear();
        for (const sdft_material &m : local[i])
            remap.push_back(material_index(table, m));
        if (table.size() > SDFT_GRID_MAX_MATERIALS)
            return fail_with(msg, msg_len, SDFT_EINVAL, "the field has more than %d distinct materials",
                             SDFT_GRID_MAX_MATERIALS);
        for (auto v = ids[i]->beginValueOn(); v; ++v)
            v.setValue(remap[size_t(*v)]);
    }
    const std::string name = p->grid_name ? p->grid_name : "sdf";
    openvdb::FloatGrid::Ptr idg = openvdb::FloatGrid::create(-1.0f);
    idg->setTransform(surface.transform().copy());
    idg->setName(name + ".material_ids");
    for (auto &leaf : ids)
        if (leaf)
            idg->tree().addLeaf(leaf.release());
    openvdb::FloatGrid::Ptr tg = openvdb::FloatGrid::create(0.0f);
    tg->setName(name + ".material_table");
    auto acc = tg->getAccessor();
    for (size_t k = 0; k < table.size(); k++) {
        const float v[5] = {table[k].colour.x, table[k].colour.y, table[k].colour.z, table[k].reflectance,
                            table[k].ior};
        for (int c = 0; c < 5; c++)
            acc.setValueOn(openvdb::Coord(int(k), c, 0), v[c]);
    }
    out = {idg, tg};
    return SDFT_OK;
}

sdft_error bake(const sdft_field *f, const sdft_bake_params *p, const char *path, sdft_grid **grid_out,
                sdft_bake_stats *stats, char *msg, size_t msg_len)
{
    Output out;
    if (path)
        if (sdft_error rc = out.begin(path, msg, msg_len))
            return rc;
    const sdft_aabb b = f->bounds;
    const sdft_vec3 ext = sdft_sub(b.hi, b.lo);
    const auto t0 = std::chrono::steady_clock::now();
    Baker bk;
    bk.f = f;
    bk.lo = b.lo;
    bk.h = sdft_maxcomp(ext) / float(p->res);
    bk.band = (p->full ? 3.0f : p->band) * bk.h;
    bk.full = p->full != 0;
    const float e[3] = {ext.x, ext.y, ext.z};
    for (int k = 0; k < 3; k++)
        bk.n[k] = std::clamp(int(std::ceil(e[k] / bk.h - 1e-3f)), 1, p->res);

    std::vector<std::vector<Tile>> tiles;
    std::atomic<uint64_t> evals{0};
    tbb::task_arena arena(p->threads > 0 ? p->threads : tbb::task_arena::automatic);
    const std::vector<openvdb::Coord> leaf_origins = plan_blocks(bk, arena, tiles, evals);
    std::vector<std::unique_ptr<LeafT>> leaves;
    if (!bake_leaves(bk, p, arena, leaf_origins, leaves, tiles, evals))
        return fail_with(msg, msg_len, SDFT_ECANCELED, "bake stopped by its progress callback");
    uint64_t kept = 0;
    openvdb::FloatGrid::Ptr grid = make_tree(bk, p, b, tiles, leaves, &kept);
    const auto &tree = grid->tree();
    const auto t1 = std::chrono::steady_clock::now();

    if (stats) {
        stats->ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
        stats->evaluations = evals.load();
        stats->leaves = kept;
        stats->active_voxels = tree.activeVoxelCount();
        std::memcpy(stats->dims, bk.n, sizeof bk.n);
        stats->voxel_size = bk.h;
    }
    if (tree.activeVoxelCount() == 0)
        return fail_with(msg, msg_len, SDFT_EEMPTY, "the bake holds no surface: no voxel within the band");
    std::vector<openvdb::FloatGrid::ConstPtr> beside;
    if (p->materials)
        if (sdft_error rc = bake_materials(bk, p, arena, *grid, beside, msg, msg_len))
            return rc;
    if (path)
        if (sdft_error rc = out.write(*grid, beside, p->fp16 != 0, msg, msg_len))
            return rc;
    if (grid_out)
        return sdft_vdb::to_nano(*grid, p->fp16 ? SDFT_QUANT_FP16 : SDFT_QUANT_NONE, grid_out, msg, msg_len);
    return SDFT_OK;
}

} // namespace

extern "C" sdft_bake_params sdft_bake_defaults(void)
{
    sdft_bake_params p;
    std::memset(&p, 0, sizeof p);
    p.res = 256;
    p.band = 3.0f;
    return p;
}

extern "C" sdft_error sdft_bake(const sdft_field *f, const sdft_bake_params *p, const char *path, sdft_grid **grid_out,
                                sdft_bake_stats *stats, char *msg, size_t msg_len)
{
    if (grid_out)
        *grid_out = nullptr;
    if (sdft_error rc = check(f, p, path, msg, msg_len))
        return rc;
    return sdft_vdb::guarded("bake", msg, msg_len, [&] { return bake(f, p, path, grid_out, stats, msg, msg_len); });
}
