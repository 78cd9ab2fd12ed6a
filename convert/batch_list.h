// mesh2sdf --batch — the list of meshes: LIST read, each mesh given a
// unique output name, and the shard of it this process converts.
#ifndef MESH2SDF_BATCH_LIST_H
#define MESH2SDF_BATCH_LIST_H

#include <cstdint>
#include <string>
#include <vector>

namespace mesh2sdf
{

struct BatchEntry {
    std::string line; // the path as LIST writes it: the report's "mesh"
    std::string path; // the path opened: relative ones taken from LIST's folder
    std::string name; // the outputs' stem in DIR, unique within LIST
    size_t position;  // among LIST's meshes, from 0
    uint64_t bytes;   // the file's size (0 if it cannot be read): largest first under MPI
};

/// Reads LIST: one mesh path a line; blank lines and lines starting with
/// '#' (after spaces) are skipped, spaces around a path are trimmed. A
/// relative path is taken from LIST's folder. Each mesh's name is its file
/// stem, or STEM-2, STEM-3 ... when an earlier line already took it, so that
/// every shard names a mesh the same. Fails with one line when LIST cannot
/// be read or names no mesh.
bool readBatchList(const std::string &list, std::vector<BatchEntry> &entries, std::string &error);

/// Shard k of n: the entries at positions k, k + n, k + 2n ...; every entry
/// is in exactly one shard, and neighbours in LIST (often alike in size)
/// go to different shards.
std::vector<BatchEntry> batchShard(const std::vector<BatchEntry> &entries, int k, int n);

} // namespace mesh2sdf

#endif
