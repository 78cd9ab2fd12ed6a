// mesh2sdf --batch (see batch.h).
#include "batch.h"

#include "interrupt.h"
#include "job.h"
#include "points.h"
#include "text.h"

#include "atomic_file.h"
#ifdef MESH2SDF_WITH_MPI
#include "mpi_batch.h"
#endif

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <sys/stat.h>

#include "seam.h"

namespace mesh2sdf
{

namespace
{

// The options of one mesh: the batch's, with the input and DIR/NAME.* as
// --formats asks.
Options meshOptions(const Options &opt, const BatchEntry &entry)
{
    Options one = opt;
    const std::string base = opt.outDir + "/" + entry.name;
    one.input = entry.path;
    one.output = opt.batchVdb ? base + ".vdb" : "";
    one.nvdb = opt.batchNvdb ? base + ".nvdb" : "";
    one.npy = opt.batchNpy ? base + ".npy" : "";
    one.samplesOut = opt.batchSamples ? base + ".samples.npy" : "";
    return one;
}

// Every file one mesh of the batch writes: the conversion's (job.h), then
// the training samples and their sidecar.
std::vector<std::string> entryOutputs(const Options &one)
{
    std::vector<std::string> files = jobOutputs(one);
    if (!one.samplesOut.empty()) {
        files.push_back(one.samplesOut);
        files.push_back(sidecarPath(one.samplesOut));
    }
    return files;
}

bool allExist(const std::vector<std::string> &files)
{
    struct stat st;
    for (const std::string &f : files)
        if (stat(f.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
            return false;
    return true;
}

bool makeFolder(const std::string &dir, std::string &error)
{
    struct stat st;
    if (mkdir(dir.c_str(), 0777) == 0 || (errno == EEXIST && stat(dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode)))
        return true;
    error = "cannot create the output folder " + dir + ": " + std::strerror(errno == EEXIST ? ENOTDIR : errno);
    return false;
}

} // namespace

namespace
{

// The settings of params struct `params` (of kind `of`) as "name=value"
// words, the library's table's rows in order, less those that change only
// the speed (threads, simd).
std::string settingWords(sdft_mesh_settings_of of, const void *params)
{
    size_t count = 0;
    const sdft_mesh_setting *rows = sdft_mesh_settings(of, &count);
    std::string words;
    for (size_t i = 0; i < count; ++i) {
        const sdft_mesh_setting &row = rows[i];
        if (std::strcmp(row.name, "threads") == 0 || std::strcmp(row.name, "simd") == 0)
            continue;
        const char *at = static_cast<const char *>(params) + row.offset;
        words += std::string(" ") + row.name + "=";
        for (int k = 0; k < row.count; ++k) {
            int number;
            uint64_t whole;
            double real;
            const char *text;
            switch (row.kind) {
            case SDFT_MESH_SETTING_INT:
            case SDFT_MESH_SETTING_FLAG:
            case SDFT_MESH_SETTING_CHOICE:
                std::memcpy(&number, at, sizeof number);
                words += std::to_string(number);
                break;
            case SDFT_MESH_SETTING_COUNT:
                std::memcpy(&whole, at, sizeof whole);
                words += std::to_string(whole);
                break;
            case SDFT_MESH_SETTING_REAL:
                std::memcpy(&real, at + k * sizeof real, sizeof real);
                words += format("%s%.17g", k ? "," : "", real);
                break;
            case SDFT_MESH_SETTING_TEXT:
                std::memcpy(&text, at, sizeof text);
                words += text ? jsonString(text) : "null";
                break;
            }
        }
    }
    return words;
}

} // namespace

// The settings that change what a mesh's outputs hold (every setting of
// the library's tables but the speed's, --fp16, --formats), as text,
// hashed (FNV-1a, 64 bits) for the report: a rerun with other settings
// converts again. The paths are left out (the rows are per mesh).
std::string outputOptions(const Options &opt)
{
    const std::string text = settingWords(SDFT_MESH_SETTINGS_MESH, &opt.mesh) +
                             settingWords(SDFT_MESH_SETTINGS_GRID, &opt.grid) +
                             format(" fp16=%d formats=%d%d%d%d", int(opt.fp16), int(opt.batchVdb), int(opt.batchNvdb),
                                    int(opt.batchNpy), int(opt.batchSamples)) +
                             (opt.batchSamples ? settingWords(SDFT_MESH_SETTINGS_SAMPLES, &opt.sample) : std::string());
    uint64_t hash = 14695981039346656037ull;
    for (unsigned char c : text)
        hash = (hash ^ c) * 1099511628211ull;
    return format("%016llx", static_cast<unsigned long long>(hash));
}

namespace
{

std::string reportPath(const Options &opt)
{
    if (opt.shards == 1)
        return opt.outDir + "/report.jsonl";
    return opt.outDir + "/report." + std::to_string(opt.shard) + "-of-" + std::to_string(opt.shards) + ".jsonl";
}

// "1:05" or "2:03:07".
std::string clock(double seconds)
{
    const long s = long(seconds + 0.5);
    char text[32];
    if (s >= 3600)
        std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
    else
        std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
    return text;
}

// A batch that cannot run: its line, and with --json its object.
int fail(const Options &opt, const std::string &error)
{
    if (opt.json)
        std::printf("{\"batch\": %s, \"status\": \"failed\", \"error\": %s}\n", jsonString(opt.batch).c_str(),
                    jsonString(error).c_str());
    std::fprintf(stderr, "mesh2sdf: %s\n", error.c_str());
    return 1;
}

} // namespace

bool planBatch(const Options &opt, bool withReport, BatchPlan &plan, std::string &error)
{
    std::vector<BatchEntry> all;
    if (!readBatchList(opt.batch, all, error) || !makeFolder(opt.outDir, error))
        return false;
    plan.entries = batchShard(all, opt.shard, opt.shards);
    if (!withReport)
        return true; // the rank that reports decides what is pending
    // The temporary files of runs into DIR that were killed (not those of
    // runs still writing there: other shards).
    static const char *const ours[] = {".vdb", ".nvdb", ".npy", ".json", ".jsonl", nullptr};
    atomic_file_sweep(opt.outDir.c_str(), nullptr, ours);
    plan.options = outputOptions(opt);
    plan.report.reset(new BatchReport(reportPath(opt), plan.entries.size()));
    if (!plan.report->loadEarlier(error))
        return false;
    // Done already: every output there, and the earlier row says it was
    // converted with these options.
    for (size_t i = 0; i < plan.entries.size(); ++i)
        if (!allExist(entryOutputs(meshOptions(opt, plan.entries[i]))) ||
            !rowMadeWith(plan.report->earlier(plan.entries[i].line), plan.options))
            plan.pending.push_back(i);
    return true;
}

int batchInterrupted()
{
    std::fprintf(stderr, "mesh2sdf: %s; the report has the meshes done so far, and a rerun resumes\n",
                 interruptReason().c_str());
    return endInterrupted();
}

BatchRow convertEntry(const Options &opt, const BatchEntry &entry)
{
    // One read of the mesh for all its outputs: the grid files and the
    // samples are reserved, the mesh read and oriented once, then each
    // written from it. With --normalize the samples are in the unit
    // sphere and the grids are not: the samples get a mesh of their own.
    const Options one = meshOptions(opt, entry);
    const auto start = std::chrono::steady_clock::now();
    ProgressView quiet(false);
    JobResult r;
    try {
        std::unique_ptr<mesh_files, MeshFree> files;
        PointFiles samples;
        Options gridOpt = one;
        gridOpt.mesh.normalize = 0;
        if ((!one.samples() || trainingSamplesFitMemory(size_t(one.sample.count), r.error)) &&
            reserveGridFiles(one, files, r.error) && (!one.samples() || samples.reserve(one.samplesOut, r.error))) {
            const MeshPtr mesh = loadJobMesh(files ? gridOpt : one, quiet, 0, 15, r);
            r.ok = mesh && (!files || convertJobMesh(one, mesh.get(), files.get(), quiet, r));
            if (r.ok && one.samples()) {
                MeshPtr normalized;
                if (files && one.mesh.normalize)
                    r.ok = bool(normalized = loadJobMesh(one, quiet, 0, 15, r));
                SampleRun run;
                r.ok =
                    r.ok && writeSamples(one, normalized ? normalized.get() : mesh.get(), samples, quiet, run, r.error);
                if (r.ok) {
                    r.outputs.push_back(one.samplesOut);
                    r.outputs.push_back(sidecarPath(one.samplesOut));
                    r.samples = size_t(one.sample.count);
                }
            }
        }
    } catch (const std::bad_alloc &) { // the rows, the program's own strings
        r.ok = false;
        r.error = entry.path + ": out of memory";
    }
    if (!r.ok && interruptSignal())
        r.error = interruptReason();
    r.seconds = seam::secondsSince(start);
    return jobRow(entry, r, outputOptions(opt));
}

BatchSink::BatchSink(const Options &opt, BatchPlan &plan)
    : mOpt(opt), mPlan(plan), mProgress(!opt.quiet && !opt.json), mStart(std::chrono::steady_clock::now())
{
    for (size_t i : plan.pending)
        mBytesTotal += plan.entries[i].bytes;
}

bool BatchSink::start(std::string &error)
{
    size_t next = 0; // in pending
    for (size_t i = 0; i < mPlan.entries.size(); ++i) {
        if (next < mPlan.pending.size() && mPlan.pending[next] == i) {
            ++next;
            continue;
        }
        const BatchEntry &e = mPlan.entries[i];
        const BatchRow row = skippedRow(e, entryOutputs(meshOptions(mOpt, e)), mPlan.report->earlier(e.line));
        mPlan.report->set(i, row.json);
        ++mSkipped;
        show(row);
    }
    showProgress();
    return mPlan.report->write(true, error);
}

bool BatchSink::add(size_t index, const BatchRow &row, std::string &error)
{
    mPlan.report->set(index, row.json);
    ++mDone;
    mBytesDone += mPlan.entries[index].bytes;
    ++(row.status == RowStatus::Ok ? mConverted : mFailed);
    mProgress.finish();
    show(row);
    showProgress();
    return mPlan.report->write(false, error);
}

void BatchSink::show(const BatchRow &row)
{
    if (row.status == RowStatus::Failed)
        std::fprintf(stderr, "mesh2sdf: %s\n", row.text.c_str());
    if (mOpt.json)
        std::printf("%s\n", row.json.c_str());
    else if (!mOpt.quiet && row.status != RowStatus::Failed)
        std::printf("%s\n", row.text.c_str());
    std::fflush(stdout);
}

// "12/40 meshes, 3:10 left": the time so far, scaled by the bytes of mesh
// still to convert over those converted.
void BatchSink::showProgress()
{
    const size_t total = mPlan.pending.size();
    if (total == 0 || mDone == total)
        return;
    const double elapsed = seam::secondsSince(mStart);
    mLabel = std::to_string(mDone) + "/" + std::to_string(total) + " meshes";
    if (mBytesDone > 0)
        mLabel += ", " + clock(elapsed * double(mBytesTotal - mBytesDone) / double(mBytesDone)) + " left";
    const int percent = int(100 * mDone / total);
    mProgress.stage(mLabel.c_str(), percent, percent);
    mProgress.show(0);
}

int BatchSink::finish()
{
    mProgress.finish();
    std::string error;
    if (!mPlan.report->write(true, error))
        return fail(mOpt, error);
    const double seconds = seam::secondsSince(mStart);
    if (!mOpt.quiet && !mOpt.json)
        std::printf("batch: %zu meshes, %zu converted, %zu skipped, %zu failed, %.2f s; report %s\n",
                    mPlan.entries.size(), mConverted, mSkipped, mFailed, seconds, mPlan.report->path().c_str());
    return mFailed ? kBatchSomeFailed : 0;
}

int runBatch(const Options &opt)
{
#ifdef MESH2SDF_WITH_MPI
    if (mpiLaunched())
        return runMpiBatch(opt);
#else
    const char *ranks = std::getenv("OMPI_COMM_WORLD_SIZE");
    if (ranks && std::atoi(ranks) > 1)
        return fail(opt, "this mesh2sdf was built without MPI, so its ranks would each convert the whole list: run "
                         "one process, or give each --shard $OMPI_COMM_WORLD_RANK/$OMPI_COMM_WORLD_SIZE");
#endif
    BatchPlan plan;
    std::string error;
    if (!planBatch(opt, true, plan, error))
        return fail(opt, error);
    BatchSink sink(opt, plan);
    if (!sink.start(error))
        return fail(opt, error);
    for (size_t i : plan.pending) {
        if (interruptSignal())
            break;
        if (!sink.add(i, convertEntry(opt, plan.entries[i]), error))
            return fail(opt, error);
    }
    const int status = sink.finish();
    return interruptSignal() ? batchInterrupted() : status;
}

} // namespace mesh2sdf
