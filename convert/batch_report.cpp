// mesh2sdf --batch — the report (see batch_report.h).
#include "batch_report.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <new>

#include "atomic_file.h"
#include "json.h"

namespace mesh2sdf
{

namespace
{

std::string jsonList(const std::vector<std::string> &items)
{
    std::string list = "[";
    for (size_t i = 0; i < items.size(); ++i)
        list += (i ? ", " : "") + jsonString(items[i]);
    return list + "]";
}

// The escaped "mesh" of a row this report wrote: the text between the
// quotes after {"mesh": , or "" for a line of another shape.
std::string rowMesh(const std::string &row)
{
    static const std::string head = "{\"mesh\": \"";
    if (row.compare(0, head.size(), head) != 0)
        return "";
    for (size_t i = head.size(); i < row.size(); ++i) {
        if (row[i] == '\\')
            ++i;
        else if (row[i] == '"')
            return row.substr(head.size() - 1, i - head.size() + 2);
    }
    return "";
}

} // namespace

BatchRow jobRow(const BatchEntry &entry, const JobResult &r, const std::string &options)
{
    BatchRow row;
    row.status = r.ok ? RowStatus::Ok : RowStatus::Failed;
    row.json = "{\"mesh\": " + jsonString(entry.line) + ", \"status\": \"" + (r.ok ? "ok" : "failed") +
               "\", \"error\": " + (r.ok ? "null" : jsonString(r.error)) + ", \"options\": " + jsonString(options) +
               format(", \"seconds\": %.3f", r.seconds);
    const bool grid = r.ok && r.gridBuilt; // a grid was written, not samples alone
    if (grid)
        row.json += format(", \"voxels\": %llu, \"dims\": [%d, %d, %d], \"voxel_size\": %.9g, \"ambiguous_voxels\": "
                           "%llu, \"surface\": %s",
                           static_cast<unsigned long long>(r.stats.active_voxels), r.box.dims[0], r.box.dims[1],
                           r.box.dims[2], r.box.voxel_size, static_cast<unsigned long long>(r.stats.ambiguous_voxels),
                           r.stats.surface ? "true" : "false");
    if (r.ok && r.samples)
        row.json += format(", \"samples\": %zu", r.samples);
    if (r.meshRead)
        row.json += healthJsonFields(r);
    row.json += ", \"outputs\": " + jsonList(r.outputs) + "}";
    const std::string what =
        (grid ? format("%llu active voxels", static_cast<unsigned long long>(r.stats.active_voxels)) : std::string()) +
        (grid && r.samples ? ", " : "") + (r.samples ? format("%zu samples", r.samples) : "");
    row.text = r.ok ? format("ok %s: %s, %.2f s", entry.line.c_str(), what.c_str(), r.seconds)
                    : "failed " + entry.line + ": " + r.error;
    return row;
}

bool rowMadeWith(const std::string &row, const std::string &options)
{
    // Rows are written by jobRow: the status and the options appear once,
    // as these exact fields (the mesh's own name comes first and is escaped,
    // so it cannot hold them).
    return row.find(", \"status\": \"ok\", ") != std::string::npos &&
           row.find(", \"options\": " + jsonString(options) + ", ") != std::string::npos;
}

BatchRow skippedRow(const BatchEntry &entry, const std::vector<std::string> &outputs, const std::string &earlier)
{
    BatchRow row;
    row.status = RowStatus::Skipped;
    row.json = !earlier.empty()
                   ? earlier
                   : "{\"mesh\": " + jsonString(entry.line) +
                         ", \"status\": \"skipped\", \"error\": null, \"outputs\": " + jsonList(outputs) + "}";
    row.text = "skipped " + entry.line + ": its outputs are there";
    return row;
}

BatchReport::BatchReport(std::string path, size_t slots) : mPath(std::move(path)), mRows(slots) {}

bool BatchReport::loadEarlier(std::string &error)
{
    std::ifstream in(mPath);
    if (!in)
        return true; // no earlier run
    std::string line;
    while (std::getline(in, line)) {
        const std::string mesh = rowMesh(line);
        if (!mesh.empty())
            mEarlier[mesh] = line;
    }
    if (in.bad()) {
        error = "cannot read the earlier report " + mPath;
        return false;
    }
    return true;
}

std::string BatchReport::earlier(const std::string &line) const
{
    const auto row = mEarlier.find(jsonString(line));
    return row == mEarlier.end() ? "" : row->second;
}

void BatchReport::set(size_t slot, const std::string &json)
{
    mRows[slot] = json;
    mDirty = true;
}

bool BatchReport::write(bool now, std::string &error)
{
    const auto t = std::chrono::steady_clock::now();
    if (!now && (!mDirty || t - mWritten < std::chrono::seconds(1)))
        return true;
    atomic_file file;
    char msg[512];
    if (atomic_file_begin(&file, mPath.c_str(), msg, sizeof msg)) {
        error = msg;
        return false;
    }
    FILE *f = std::fopen(file.tmp_path, "w");
    bool written = f != nullptr;
    for (size_t i = 0; written && i < mRows.size(); ++i)
        if (!mRows[i].empty())
            written = std::fprintf(f, "%s\n", mRows[i].c_str()) >= 0;
    if (f && std::fclose(f) != 0)
        written = false;
    if (!written) {
        atomic_file_abort(&file);
        error = "cannot write the report " + mPath;
        return false;
    }
    if (atomic_file_commit(&file, msg, sizeof msg)) {
        error = msg;
        return false;
    }
    mWritten = t;
    mDirty = false;
    return true;
}

} // namespace mesh2sdf
