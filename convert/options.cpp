// mesh2sdf — command line parsing (see options.h).
#include "options.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <iterator>

#include "cmdline.h"
#include "parse.h"
#include "text.h"

namespace mesh2sdf
{

namespace
{

// The rows of the option table (src/common/cmdline.h): the flag, its
// value's name, its description and default for --help, and what it sets.
cmdline_option row(const char *name, char letter, const char *arg, const char *help, cmdline_kind kind, void *target,
                   const char *def = "")
{
    cmdline_option r{};
    r.name = name, r.letter = letter, r.arg = arg, r.help = help, r.kind = kind, r.target = target, r.def = def;
    return r;
}

// A value handled by `set` (a std::string, an enum, ...).
cmdline_option call(const char *name, char letter, const char *arg, const char *help, cmdline_handler set, void *target,
                    const char *def = "")
{
    cmdline_option r = row(name, letter, arg, help, CMDLINE_CALL, target, def);
    r.handle = set;
    return r;
}

// A number in [lo, hi] (open ends: open), parsed strictly (src/common/parse.h);
// the help shows the target's default unless `def` says otherwise.
cmdline_option number(const char *name, const char *arg, const char *help, cmdline_kind kind, void *target, double lo,
                      double hi, int open = 0, const char *def = nullptr)
{
    cmdline_option r = row(name, 0, arg, help, kind, target, def);
    r.lo = lo, r.hi = hi, r.open = open;
    return r;
}

int setString(void *target, const char *value, char *, size_t)
{
    static_cast<std::string *>(target)->assign(value);
    return 0;
}

int addString(void *target, const char *value, char *, size_t)
{
    static_cast<std::vector<std::string> *>(target)->push_back(value);
    return 0;
}

int setTrue(void *target, const char *, char *, size_t)
{
    *static_cast<bool *>(target) = true;
    return 0;
}

// --formats vdb,nvdb,npy: the files a batch writes per mesh.
int setFormats(void *target, const char *v, char *msg, size_t len)
{
    Options &o = *static_cast<Options *>(target);
    o.batchVdb = o.batchNvdb = o.batchNpy = o.batchSamples = false;
    std::string list = v;
    for (size_t at = 0; at <= list.size();) {
        size_t comma = list.find(',', at);
        if (comma == std::string::npos)
            comma = list.size();
        const std::string word = list.substr(at, comma - at);
        bool &format = word == "vdb"    ? o.batchVdb
                       : word == "nvdb" ? o.batchNvdb
                       : word == "npy"  ? o.batchNpy
                                        : o.batchSamples;
        if (word != "vdb" && word != "nvdb" && word != "npy" && word != "samples") {
            std::snprintf(msg, len, "--formats takes vdb, nvdb, npy and samples, comma-separated, got '%s'", v);
            return -1;
        }
        format = true;
        at = comma + 1;
    }
    return 0;
}

// --shard K/N: 0 <= K < N.
int setShard(void *target, const char *v, char *msg, size_t len)
{
    Options &o = *static_cast<Options *>(target);
    int k = -1, n = 0, end = 0;
    if (std::sscanf(v, "%d/%d%n", &k, &n, &end) != 2 || v[end] != '\0' || n < 1 || k < 0 || k >= n ||
        !std::isdigit(static_cast<unsigned char>(v[0]))) {
        std::snprintf(msg, len, "--shard takes K/N with 0 <= K < N (K from 0, as SLURM_ARRAY_TASK_ID), got '%s'", v);
        return -1;
    }
    o.shard = k;
    o.shards = n;
    return 0;
}

// The input mesh: the one word that is not an option.
int setInput(void *target, const char *v, char *msg, size_t len)
{
    std::string &input = *static_cast<std::string *>(target);
    if (!input.empty()) {
        std::snprintf(msg, len, "unexpected argument '%s' (one input mesh only)", v);
        return -1;
    }
    input = v;
    return 0;
}

// The words after --samples and --query, checked by parseOptions.
struct PointWords {
    const char *samples[2] = {nullptr, nullptr}; // N, OUT.npy
    const char *query[2] = {nullptr, nullptr};   // POINTS.npy, OUT.npy
    int sampleFlags = 0;                         // an option of the samples' settings given (--seed ...)
    std::string sampleFlagNames;                 // those options, for a message: "--seed, --near-sigma" ...
};

// A row of two words (CMDLINE_TEXT with value 2).
cmdline_option twoWords(const char *name, const char *arg, const char *help, const char **target)
{
    cmdline_option r = row(name, 0, arg, help, CMDLINE_TEXT, target, "");
    r.value = 2;
    return r;
}

// The library's setting `name` of the params struct of kind `of`.
const sdft_mesh_setting &setting(sdft_mesh_settings_of of, const char *name)
{
    size_t count = 0;
    const sdft_mesh_setting *settings = sdft_mesh_settings(of, &count);
    const sdft_mesh_setting *s = settings;
    while (s + 1 < settings + count && std::strcmp(s->name, name) != 0)
        ++s;
    return *s;
}

// The rows of the option table and the text they point into.
struct Table {
    std::vector<cmdline_option> rows;
    std::deque<std::string> text; // flags and help lines (a deque keeps them in place)

    const char *keep(std::string t)
    {
        text.push_back(std::move(t));
        return text.back().c_str();
    }
};

// How a setting of the library becomes an option: --NAME with dashes for
// underscores, unless said here otherwise. The grid's threads follow the
// mesh's (--threads), and the samples' count is --samples N or, per mesh
// of a batch, --sample-count N.
struct Renamed {
    sdft_mesh_settings_of of;
    const char *setting, *flag, *help; // flag NULL: not an option of its own
};
const Renamed kRenamed[] = {{SDFT_MESH_SETTINGS_GRID, "threads", nullptr, nullptr},
                            {SDFT_MESH_SETTINGS_SAMPLES, "count", "sample-count", "--batch --formats samples: "}};

// The options of the settings of one params struct `params` of kind `of`,
// in the table's order: their values' names, ranges, defaults and
// descriptions the library's (sdft_mesh_settings). `seen`, when given, is
// set by every one of them.
void settingRows(Table &t, sdft_mesh_settings_of of, void *params, int *seen = nullptr)
{
    size_t count = 0;
    const sdft_mesh_setting *settings = sdft_mesh_settings(of, &count);
    for (size_t i = 0; i < count; ++i) {
        const sdft_mesh_setting &s = settings[i];
        std::string flag = s.name, help = s.doc;
        for (const Renamed &r : kRenamed)
            if (r.of == of && flag == r.setting) {
                flag = r.flag ? r.flag : "";
                help = std::string(r.help ? r.help : "") + help;
            }
        if (flag.empty())
            continue;
        for (char &c : flag)
            c = c == '_' ? '-' : c;
        cmdline_option r = row(t.keep(flag), 0, s.value, nullptr, CMDLINE_TEXT, static_cast<char *>(params) + s.offset);
        r.lo = s.lo, r.hi = s.hi, r.seen = seen;
        r.open = int(s.flags & (SDFT_MESH_SETTING_OPEN_LO | SDFT_MESH_SETTING_OPEN_HI));
        r.def = s.automatic; // the default in words, where it is not a value; else the member's
        char range[96] = "";
        switch (s.kind) {
        case SDFT_MESH_SETTING_INT:
            r.kind = CMDLINE_INT;
            break;
        case SDFT_MESH_SETTING_COUNT:
            r.kind = CMDLINE_UINT64;
            break;
        case SDFT_MESH_SETTING_REAL:
            r.kind = s.count > 1 ? CMDLINE_DOUBLES : CMDLINE_DOUBLE;
            r.value = s.count;
            break;
        case SDFT_MESH_SETTING_FLAG:
            r.kind = CMDLINE_SET;
            r.value = 1;
            r.def = "";
            break;
        case SDFT_MESH_SETTING_CHOICE:
            r.kind = CMDLINE_CHOICE;
            r.choices = s.choices;
            break;
        case SDFT_MESH_SETTING_TEXT:
            r.kind = CMDLINE_TEXT;
            break;
        }
        if (s.kind == SDFT_MESH_SETTING_INT || s.kind == SDFT_MESH_SETTING_COUNT || s.kind == SDFT_MESH_SETTING_REAL)
            parse_range_text(s.lo, s.hi, r.open, s.kind == SDFT_MESH_SETTING_REAL ? "%g" : "%.0f", range, sizeof range);
        r.help = t.keep(help + (range[0] ? "," : "") + range);
        t.rows.push_back(r);
    }
}

// r with `value` set (what a flag stores; how many words or numbers).
cmdline_option valued(cmdline_option r, int value)
{
    r.value = value;
    return r;
}

// Every option of mesh2sdf, over `o` (for --help, over the defaults), into
// t; *sawRes: --res given; `words`: the values of --samples and --query.
void optionRows(Table &t, Options &o, int *sawRes, PointWords &words)
{
    std::vector<cmdline_option> &rows = t.rows;
    rows = {
        call("output", 'o', "OUT.vdb", "OpenVDB level set to write (required)", setString, &o.output),
        call("nvdb", 0, "OUT.nvdb", "also write a NanoVDB grid", setString, &o.nvdb, "none"),
        call("npy", 0, "OUT.npy",
             "also write the padded box densely as float32 NumPy,\n"
             "C order, shape (nx, ny, nz): a[i,j,k] is the distance\n"
             "at origin + (i,j,k) * voxel_size, z fastest; origin,\n"
             "voxel size and shape go to OUT.json",
             setString, &o.npy, "none"),
    };
    settingRows(t, SDFT_MESH_SETTINGS_GRID, &o.grid);
    for (cmdline_option &r : rows)
        if (std::strcmp(r.name, "res") == 0)
            r.seen = sawRes;
    settingRows(t, SDFT_MESH_SETTINGS_MESH, &o.mesh);
    const cmdline_option middle[] = {
        valued(row("no-simd", 0, nullptr, "the same as --simd none", CMDLINE_SET, &o.mesh.simd, ""),
               SDFT_MESH_SIMD_NONE),
        call("fp16", 0, nullptr, "NanoVDB values as Fp16", setTrue, &o.fp16, "float"),
        call("quiet", 0, nullptr, "no health line, progress bar or summary", setTrue, &o.quiet),
        call("json", 0, nullptr,
             "the health counts and the summary as one JSON object\n"
             "on stdout, instead of the text lines (a failed run's:\n"
             "the mesh and the error)",
             setTrue, &o.json),
        call("check-sign", 0, "GRID.vdb",
             "do not convert: sample points uniformly in the mesh's\n"
             "box grown by 5%, compute the exact winding number by\n"
             "brute force and print, per GRID (repeatable), the\n"
             "fraction of clearly inside (> 0.75) or outside\n"
             "(< 0.25) points where GRID's sign is wrong; the truth\n"
             "is the mesh oriented as --orient says (give the\n"
             "conversion's), named on each line",
             addString, &o.checkSign),
        number("check-points", "N", "points for --check-sign", CMDLINE_INT, &o.checkPoints, 1, 100000000),
        twoWords("samples", "N OUT.npy",
                 "do not convert: write N training samples, float32\n"
                 "rows (x, y, z, d), shape (N, 4), as DeepSDF samples\n"
                 "them: a share of uniform points in the cube of the\n"
                 "mesh's sphere (centre and radius as --normalize\n"
                 "takes them), the rest on the surface (area-weighted\n"
                 "random triangles) moved by a Gaussian of either\n"
                 "sigma, half each; d exact to the triangles, signed\n"
                 "by the winding number; OUT.json gets the sphere\n"
                 "and the settings; the same bytes for any --threads",
                 words.samples),
    };
    rows.insert(rows.end(), std::begin(middle), std::end(middle));
    const size_t sampleRows = rows.size();
    settingRows(t, SDFT_MESH_SETTINGS_SAMPLES, &o.sample, &words.sampleFlags);
    // --sample-count is a batch's: it goes with the batch's options, and
    // does not count among the flags that need --samples.
    const auto count = std::find_if(rows.begin(), rows.end(),
                                    [](const cmdline_option &r) { return !std::strcmp(r.name, "sample-count"); });
    cmdline_option sampleCount = *count;
    sampleCount.seen = nullptr;
    rows.erase(count);
    for (size_t i = sampleRows; i < rows.size(); ++i)
        words.sampleFlagNames += std::string(i > sampleRows ? ", --" : "--") + rows[i].name;
    const cmdline_option last[] = {
        twoWords("query", "POINTS.npy OUT.npy",
                 "do not convert: the signed distance at each point of\n"
                 "POINTS.npy, shape (N, 3), float32 or float64, C or\n"
                 "Fortran order; OUT.npy is float32, shape (N,), or\n"
                 "(N, 2) with --winding",
                 words.query),
        call("winding", 0, nullptr, "--query: each row d, w: the winding number beside\nthe distance", setTrue,
             &o.winding, "distance only"),
        call("batch", 0, "LIST",
             "convert every mesh LIST names (one path a line,\n"
             "relative to LIST's folder; blank lines and # comments\n"
             "skipped) into --out-dir, with the other options;\n"
             "meshes that fail are reported and skipped; under\n"
             "mpirun, spread over the ranks. A rerun resumes: a\n"
             "mesh whose outputs are all there and whose report row\n"
             "records the same output options (all but --threads,\n"
             "--simd and the paths) is skipped; any other is\n"
             "converted again",
             setString, &o.batch, "none"),
        call("out-dir", 0, "DIR",
             "--batch: the folder for the outputs and report.jsonl\n"
             "(created if missing); a mesh writes DIR/STEM.vdb ...,\n"
             "STEM its file name stem (STEM-2, -3 ... for a stem\n"
             "met again in LIST)",
             setString, &o.outDir),
        call("formats", 0, "KINDS",
             "--batch: what to write per mesh, comma-separated:\n"
             "vdb, nvdb, npy (with its .json), samples (training\n"
             "samples as --samples writes them, STEM.samples.npy\n"
             "and its .json)",
             setFormats, &o, "vdb"),
        sampleCount,
        call("shard", 0, "K/N",
             "--batch: convert only shard K of N (K from 0 to N-1):\n"
             "the meshes at positions K, K+N, K+2N ... of LIST;\n"
             "its report is DIR/report.K-of-N.jsonl",
             setShard, &o, "all"),
        row("help", 'h', nullptr, "this help", CMDLINE_HELP, nullptr),
        row("version", 0, nullptr, "the version, sdftrace's", CMDLINE_NOTE, nullptr), // main.cpp answers it
        cmdline_option{},
    };
    rows.insert(rows.end(), std::begin(last), std::end(last));
}

// --samples and --query: their words, and the options that go with them.
bool pointModes(Options &opt, const PointWords &words, std::string &error)
{
    if (words.samples[0]) {
        const sdft_mesh_setting &count = setting(SDFT_MESH_SETTINGS_SAMPLES, "count");
        double n;
        if (parse_number(words.samples[0], &n) || n != std::floor(n) || n < count.lo || n > count.hi) {
            error = format("--samples N must be a whole number from %.0f to %.0f, got '%s'", count.lo, count.hi,
                           words.samples[0]);
            return false;
        }
        opt.sample.count = uint64_t(n);
        opt.samplesOut = words.samples[1];
    }
    if (words.query[0]) {
        opt.queryIn = words.query[0];
        opt.queryOut = words.query[1];
    }
    const bool points = words.samples[0] || words.query[0];
    const bool batchSamples = !opt.batch.empty() && opt.batchSamples;
    if (!opt.batch.empty() && points)
        error = "--batch writes samples with --formats samples (and --sample-count N), points with no --query";
    else if (opt.batch.empty() && opt.batchSamples)
        error = "--formats goes with --batch";
    else if (words.samples[0] && words.query[0])
        error = "give --samples or --query, not both";
    else if (points && (!opt.output.empty() || !opt.nvdb.empty() || !opt.npy.empty() || !opt.checkSign.empty()))
        error = std::string(words.samples[0] ? "--samples" : "--query") +
                " writes its own OUT.npy: give no -o, --nvdb, --npy or --check-sign";
    else if (points && opt.grid.sign != SDFT_MESH_SIGN_WINDING)
        error = "--samples and --query sign by the winding number: --sign does not apply";
    else if (words.sampleFlags && !words.samples[0] && !batchSamples)
        error = "the samples' options (" + words.sampleFlagNames + ") go with --samples (or --batch --formats samples)";
    else if (opt.winding && !words.query[0])
        error = "--winding goes with --query";
    else if (opt.mesh.normalize && !points && !batchSamples)
        error = "--normalize goes with --samples, --query or --batch --formats samples";
    return error.empty();
}

cmdline_spec optionSpec(const Table &t, Options &o)
{
    cmdline_spec spec{};
    spec.program = "mesh2sdf";
    spec.usage = "usage: mesh2sdf IN.{obj,ply,off,stl,om,gltf,glb,fbx,dae,3mf} -o OUT.vdb [options]\n"
                 "       mesh2sdf --batch LIST --out-dir DIR [--formats vdb,nvdb,npy,samples] [--shard K/N] [options]\n"
                 "       mpirun -np N mesh2sdf --batch LIST --out-dir DIR [options]\n"
                 "       mesh2sdf IN.obj --samples N OUT.npy [--near-sigma A,B] [--uniform-share S] [--seed N]\n"
                 "                       [--normalize]\n"
                 "       mesh2sdf IN.obj --query POINTS.npy OUT.npy [--winding] [--normalize]\n"
                 "       mesh2sdf IN.obj --check-sign GRID.vdb [--check-sign GRID2.vdb ...] [--check-points N]\n"
                 "\n"
                 "Converts a triangle mesh to a signed distance grid (OpenVDB level set).\n"
                 "Polygons are triangulated; zero-area triangles are skipped and counted.\n"
                 "PLY faces may be polygons or tristrips; glTF, FBX, Collada and 3MF scenes\n"
                 "are flattened: every mesh of every node, moved by the node's transform.\n"
                 "\n";
    spec.footer = "\n"
                  "Dense outputs (--full, --npy) are limited to 2^31 voxels.\n"
                  "Exit status: 0 on success, 1 on bad input or a failed write (one line on\n"
                  "stderr, and with --json an object with the error on stdout; no partial\n"
                  "output is left: files are written to a temporary name and renamed, and\n"
                  "the temporary files a killed run left are removed by the next run into\n"
                  "that folder). --batch: 0 when every mesh was converted or skipped (its\n"
                  "outputs were there, made with the same options), 2 when some failed (each\n"
                  "has its row in the report), 1 when the batch could not run (bad options,\n"
                  "unreadable LIST, unwritable DIR).\n";
    spec.rows = t.rows.data();
    spec.column = 25;
    spec.width = 79;
    spec.default_format = "(default: %s)";
    spec.operand = setInput;
    spec.operand_target = &o.input;
    return spec;
}

// --batch and its options: together, and without the one-mesh outputs.
bool checkBatch(const Options &opt, std::string &error)
{
    const bool batchOnly = !opt.outDir.empty() || opt.shards > 1 || opt.batchNvdb || opt.batchNpy || !opt.batchVdb;
    if (opt.batch.empty()) {
        if (batchOnly)
            error = "--out-dir, --formats and --shard go with --batch LIST";
        return !batchOnly;
    }
    if (!opt.input.empty() || !opt.output.empty() || !opt.nvdb.empty() || !opt.npy.empty() || opt.grid.name ||
        !opt.checkSign.empty())
        error = "--batch takes its meshes from LIST and names the outputs itself: no mesh, -o, --nvdb, --npy, "
                "--name or --check-sign beside it";
    else if (opt.outDir.empty())
        error = "--batch needs --out-dir DIR";
    return error.empty();
}

} // namespace

std::string settingChoice(sdft_mesh_settings_of of, const char *name, int value)
{
    const char *text;
    const size_t n = parse_list_item(setting(of, name).choices, value, &text);
    return n ? std::string(text, n) : "?";
}

void printHelp()
{
    Options defaults;
    int sawRes = 0;
    PointWords words;
    Table t;
    optionRows(t, defaults, &sawRes, words);
    const cmdline_spec spec = optionSpec(t, defaults);
    cmdline_help(&spec, stdout);
}

bool parseOptions(int argc, char **argv, Options &opt, std::string &error)
{
    int sawRes = 0;
    PointWords words;
    Table t;
    optionRows(t, opt, &sawRes, words);
    const cmdline_spec spec = optionSpec(t, opt);
    char msg[512];
    const int parsed = cmdline_parse(&spec, argc, argv, msg, sizeof msg);
    if (parsed == CMDLINE_HELP_ASKED) {
        opt.help = true;
        return true;
    }
    if (parsed != CMDLINE_OK) {
        error = msg;
        return false;
    }
    if (!checkBatch(opt, error))
        return false;
    if (opt.input.empty() && opt.batch.empty()) {
        error = "no input mesh (see --help)";
        return false;
    }
    if (!pointModes(opt, words, error))
        return false;
    if (opt.checkSign.empty() && opt.output.empty() && opt.batch.empty() && opt.samplesOut.empty() &&
        opt.queryOut.empty()) {
        error = "no output: give -o OUT.vdb (see --help)";
        return false;
    }
    if (sawRes && opt.grid.voxel_size > 0) {
        error = "give --res or --voxel-size, not both";
        return false;
    }
    while (opt.outDir.size() > 1 && opt.outDir.back() == '/') // DIR/ names DIR/NAME.vdb, not DIR//NAME.vdb
        opt.outDir.pop_back();
    return true;
}

} // namespace mesh2sdf
