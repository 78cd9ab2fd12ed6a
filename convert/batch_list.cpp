// mesh2sdf --batch — the list of meshes (see batch_list.h).
#include "batch_list.h"

#include "job.h"

#include <fstream>
#include <set>
#include <sys/stat.h>

#include "seam.h"

namespace mesh2sdf
{

namespace
{

std::string trim(const std::string &s)
{
    const size_t first = s.find_first_not_of(" \t\r");
    if (first == std::string::npos)
        return "";
    return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

uint64_t fileBytes(const std::string &path)
{
    struct stat st;
    return stat(path.c_str(), &st) == 0 ? uint64_t(st.st_size) : 0;
}

// STEM, or STEM-2, STEM-3 ... the first that `taken` does not hold yet.
std::string uniqueName(const std::string &stem, std::set<std::string> &taken)
{
    std::string name = stem;
    for (int n = 2; !taken.insert(name).second; ++n)
        name = stem + "-" + std::to_string(n);
    return name;
}

} // namespace

bool readBatchList(const std::string &list, std::vector<BatchEntry> &entries, std::string &error)
{
    std::ifstream in(list);
    if (!in) {
        error = "cannot read the batch list " + list;
        return false;
    }
    const size_t slash = list.find_last_of('/');
    const std::string folder = slash == std::string::npos ? "" : list.substr(0, slash + 1);
    std::set<std::string> taken;
    std::string text;
    while (std::getline(in, text)) {
        const std::string line = trim(text);
        if (line.empty() || line[0] == '#')
            continue;
        BatchEntry e;
        e.line = line;
        e.path = line[0] == '/' ? line : folder + line;
        e.name = uniqueName(seam::fileStem(line), taken);
        e.position = entries.size();
        e.bytes = fileBytes(e.path);
        entries.push_back(e);
    }
    if (in.bad()) {
        error = "cannot read the batch list " + list;
        return false;
    }
    if (entries.empty()) {
        error = "the batch list " + list + " names no mesh";
        return false;
    }
    return true;
}

std::vector<BatchEntry> batchShard(const std::vector<BatchEntry> &entries, int k, int n)
{
    std::vector<BatchEntry> shard;
    for (size_t i = size_t(k); i < entries.size(); i += size_t(n))
        shard.push_back(entries[i]);
    return shard;
}

} // namespace mesh2sdf
