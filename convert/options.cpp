// mesh2sdf — command line parsing (see options.h).
#include "options.h"

#include <cmath>
#include <cstdio>
#include <cstring>

#include "cmdline.h"

namespace mesh2sdf
{

const char *signMethodName(SignMethod m)
{
    switch (m) {
    case SignMethod::Winding:
        return "winding";
    case SignMethod::Flood:
        return "flood";
    case SignMethod::None:
        return "none";
    }
    return "?";
}

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

// r, noting in *flag whether it was given.
cmdline_option seen(cmdline_option r, int *flag)
{
    r.seen = flag;
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

// v as names[i], stored as E(i) (names in E's order); else one line,
// "FLAG must be a, b or c, got 'v'".
template <typename E, size_t n>
int pick(const char *flag, const char *const (&names)[n], const char *v, void *target, char *msg, size_t len)
{
    std::string list;
    for (size_t i = 0; i < n; ++i) {
        if (!std::strcmp(v, names[i])) {
            *static_cast<E *>(target) = E(i);
            return 0;
        }
        list += std::string(i == 0 ? "" : i + 1 < n ? ", " : " or ") + names[i];
    }
    std::snprintf(msg, len, "%s must be %s, got '%s'", flag, list.c_str(), v);
    return -1;
}

int setSign(void *target, const char *v, char *msg, size_t len)
{
    static const char *const names[] = {"winding", "flood", "none"};
    return pick<SignMethod>("--sign", names, v, target, msg, len);
}

int setOrient(void *target, const char *v, char *msg, size_t len)
{
    static const char *const names[] = {"outward", "none"};
    return pick<OrientMethod>("--orient", names, v, target, msg, len);
}

int setSimd(void *target, const char *v, char *msg, size_t len)
{
    Options &o = *static_cast<Options *>(target);
    if (std::strcmp(v, "auto") && std::strcmp(v, "avx2") && std::strcmp(v, "none")) {
        std::snprintf(msg, len, "--simd must be auto, avx2 or none, got '%s'", v);
        return -1;
    }
    o.simd = std::strcmp(v, "none") != 0;
    o.simd512 = !std::strcmp(v, "auto");
    return 0;
}

int setNoSimd(void *target, const char *, char *, size_t)
{
    Options &o = *static_cast<Options *>(target);
    o.simd = o.simd512 = false;
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

const std::string kResHelp = "voxels along the longest side of the padded box,\n1.." + std::to_string(kMaxResolution);

// Every option of mesh2sdf, over `o` (for --help, over the defaults);
// *sawRes: --res given.
std::vector<cmdline_option> optionRows(Options &o, int *sawRes)
{
    const double inf = HUGE_VAL, maxRes = kMaxResolution;
    std::vector<cmdline_option> rows = {
        call("output", 'o', "OUT.vdb", "OpenVDB level set to write (required)", setString, &o.output),
        call("nvdb", 0, "OUT.nvdb", "also write a NanoVDB grid", setString, &o.nvdb, "none"),
        call("npy", 0, "OUT.npy",
             "also write the padded box densely as float32 NumPy,\n"
             "C order, shape (nx, ny, nz): a[i,j,k] is the distance\n"
             "at origin + (i,j,k) * voxel_size, z fastest; origin,\n"
             "voxel size and shape go to OUT.json",
             setString, &o.npy, "none"),
        seen(number("res", "N", kResHelp.c_str(), CMDLINE_INT, &o.res, 1, maxRes), sawRes),
        number("voxel-size", "H", "voxel size in world units, > 0; overrides --res\n", CMDLINE_DOUBLE, &o.voxelSize, 0,
               inf, CMDLINE_OPEN_LO, "from --res"),
        number("band", "W", "narrow-band half-width in voxels, > 0", CMDLINE_DOUBLE, &o.band, 0, maxRes,
               CMDLINE_OPEN_LO),
        call("full", 0, nullptr, "store a distance in every voxel of the padded box\n", setTrue, &o.full,
             "narrow band only"),
        number("padding", "P", "voxels between the mesh bounds and the box, >= 0\n", CMDLINE_DOUBLE, &o.padding, 0,
               maxRes, 0, "band + 1"),
        call("sign", 0, "METHOD",
             "winding: generalized winding number > 0.5 is inside,\n"
             "right on open meshes (default); flood: OpenVDB's\n"
             "flood fill, needs a closed mesh; none: unsigned",
             setSign, &o.sign),
        call("orient", 0, "METHOD",
             "outward: weld the vertices by position, drop duplicate\n"
             "faces, orient each edge-connected patch consistently\n"
             "and turn it to face outward, so that inside-out,\n"
             "flipped and unwelded meshes sign right (default);\n"
             "none: the faces as the file orients them",
             setOrient, &o.orient),
        call("fp16", 0, nullptr, "NanoVDB values as Fp16", setTrue, &o.fp16, "float"),
        call("name", 0, "NAME", "grid name", setString, &o.name, "the mesh's file name stem"),
        number("threads", "N", "worker threads, 0 = all cores", CMDLINE_INT, &o.threads, 0, 1024),
        call("quiet", 0, nullptr, "no health line, progress bar or summary", setTrue, &o.quiet),
        call("json", 0, nullptr,
             "the health counts and the summary as one JSON object\n"
             "on stdout, instead of the text lines",
             setTrue, &o.json),
        call("simd", 0, "LEVEL",
             "vector instructions, chosen at run time: auto (the\n"
             "widest the processor has: AVX-512 for the dense\n"
             "search, else AVX2; default), avx2 (no AVX-512) or\n"
             "none; the same grid to rounding, for comparison\n"
             "and testing",
             setSimd, &o),
        call("no-simd", 0, nullptr, "the same as --simd none", setNoSimd, &o),
        call("check-sign", 0, "GRID.vdb",
             "do not convert: sample points uniformly in the mesh's\n"
             "box grown by 5%, compute the exact winding number by\n"
             "brute force and print, per GRID (repeatable), the\n"
             "fraction of clearly inside (> 0.75) or outside\n"
             "(< 0.25) points where GRID's sign is wrong",
             addString, &o.checkSign),
        number("samples", "N", "points for --check-sign", CMDLINE_INT, &o.samples, 1, 100000000),
        row("help", 'h', nullptr, "this help", CMDLINE_HELP, nullptr),
        row("version", 0, nullptr, "the version, sdftrace's", CMDLINE_NOTE, nullptr), // main.cpp answers it
    };
    rows.push_back(cmdline_option{});
    return rows;
}

cmdline_spec optionSpec(const std::vector<cmdline_option> &rows, Options &o)
{
    cmdline_spec spec{};
    spec.program = "mesh2sdf";
    spec.usage = "usage: mesh2sdf IN.{obj,ply,off,stl,om,gltf,glb,fbx,dae,3mf} -o OUT.vdb [options]\n"
                 "       mesh2sdf IN.obj --check-sign GRID.vdb [--check-sign GRID2.vdb ...] [--samples N]\n"
                 "\n"
                 "Converts a triangle mesh to a signed distance grid (OpenVDB level set).\n"
                 "Polygons are triangulated; zero-area triangles are skipped and counted.\n"
                 "PLY faces may be polygons or tristrips; glTF, FBX, Collada and 3MF scenes\n"
                 "are flattened: every mesh of every node, moved by the node's transform.\n"
                 "\n";
    spec.footer = "\n"
                  "Dense outputs (--full, --npy) are limited to 2^31 voxels.\n"
                  "Exit status: 0 on success, 1 on bad input or a failed write (one line on\n"
                  "stderr; no partial output is left: files are written to a temporary name\n"
                  "and renamed).\n";
    spec.rows = rows.data();
    spec.column = 25;
    spec.default_format = "(default: %s)";
    spec.operand = setInput;
    spec.operand_target = &o.input;
    return spec;
}

} // namespace

void printHelp()
{
    Options defaults;
    int sawRes = 0;
    const std::vector<cmdline_option> rows = optionRows(defaults, &sawRes);
    const cmdline_spec spec = optionSpec(rows, defaults);
    cmdline_help(&spec, stdout);
}

bool parseOptions(int argc, char **argv, Options &opt, std::string &error)
{
    int sawRes = 0;
    const std::vector<cmdline_option> rows = optionRows(opt, &sawRes);
    const cmdline_spec spec = optionSpec(rows, opt);
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
    if (opt.input.empty()) {
        error = "no input mesh (see --help)";
        return false;
    }
    if (opt.checkSign.empty() && opt.output.empty()) {
        error = "no output: give -o OUT.vdb (see --help)";
        return false;
    }
    if (sawRes && opt.voxelSize > 0) {
        error = "give --res or --voxel-size, not both";
        return false;
    }
    if (opt.padding < 0)
        opt.padding = opt.band + 1.0;
    return true;
}

} // namespace mesh2sdf
