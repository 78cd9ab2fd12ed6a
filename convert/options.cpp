// mesh2sdf — command line parsing (see options.h).
#include "options.h"

#include <cstdio>
#include <cstring>

#include "parse.h"

namespace mesh2sdf {

const char* signMethodName(SignMethod m)
{
    switch (m) {
    case SignMethod::Winding: return "winding";
    case SignMethod::Flood: return "flood";
    case SignMethod::None: return "none";
    }
    return "?";
}

namespace {

// The shared strict parsers (src/common/parse.h): the whole text, finite,
// no blanks, no overflow.
bool parseInt(const char* s, long lo, long hi, int& out)
{
    long v;
    if (sdft_parse_integer(s, &v) || v < lo || v > hi)
        return false;
    out = int(v);
    return true;
}

bool parseDouble(const char* s, double& out) { return sdft_parse_number(s, &out) == 0; }

} // namespace

void printHelp()
{
    std::printf(
        "usage: mesh2sdf IN.{obj,ply,off,stl,om} -o OUT.vdb [options]\n"
        "       mesh2sdf IN.obj --check-sign GRID.vdb [--check-sign GRID2.vdb ...] [--samples N]\n"
        "\n"
        "Converts a triangle mesh to a signed distance grid (OpenVDB level set).\n"
        "Polygons are triangulated; zero-area triangles are skipped and counted.\n"
        "\n"
        "  -o, --output OUT.vdb   OpenVDB level set to write (required)\n"
        "  --nvdb OUT.nvdb        also write a NanoVDB grid (default: none)\n"
        "  --npy OUT.npy          also write the padded box densely as float32 NumPy,\n"
        "                         C order, shape (nx, ny, nz): a[i,j,k] is the distance\n"
        "                         at origin + (i,j,k) * voxel_size, z fastest; origin,\n"
        "                         voxel size and shape go to OUT.json (default: none)\n"
        "  --res N                voxels along the longest side of the padded box,\n"
        "                         1..%d (default: 256)\n"
        "  --voxel-size H         voxel size in world units, > 0; overrides --res\n"
        "                         (default: from --res)\n"
        "  --band W               narrow-band half-width in voxels, > 0 (default: 3)\n"
        "  --full                 store a distance in every voxel of the padded box\n"
        "                         (default: narrow band only)\n"
        "  --padding P            voxels between the mesh bounds and the box, >= 0\n"
        "                         (default: band + 1)\n"
        "  --sign METHOD          winding: generalized winding number > 0.5 is inside,\n"
        "                         right on open meshes (default); flood: OpenVDB's\n"
        "                         flood fill, needs a closed mesh; none: unsigned\n"
        "  --orient METHOD        outward: weld the vertices by position, drop duplicate\n"
        "                         faces, orient each edge-connected patch consistently\n"
        "                         and turn it to face outward, so that inside-out,\n"
        "                         flipped and unwelded meshes sign right (default);\n"
        "                         none: the faces as the file orients them\n"
        "  --fp16                 NanoVDB values as Fp16 (default: float)\n"
        "  --name NAME            grid name (default: the mesh's file name stem)\n"
        "  --threads N            worker threads, 0 = all cores (default: 0)\n"
        "  --quiet                no health line, progress bar or summary\n"
        "  --json                 the health counts and the summary as one JSON object\n"
        "                         on stdout, instead of the text lines\n"
        "  --simd LEVEL           vector instructions, chosen at run time: auto (the\n"
        "                         widest the processor has: AVX-512 for the dense\n"
        "                         search, else AVX2; default), avx2 (no AVX-512) or\n"
        "                         none; the same grid to rounding, for comparison\n"
        "                         and testing\n"
        "  --no-simd              the same as --simd none\n"
        "  --check-sign GRID.vdb  do not convert: sample points uniformly in the mesh's\n"
        "                         box grown by 5%%, compute the exact winding number by\n"
        "                         brute force and print, per GRID (repeatable), the\n"
        "                         fraction of clearly inside (> 0.75) or outside\n"
        "                         (< 0.25) points where GRID's sign is wrong\n"
        "  --samples N            points for --check-sign (default: 10000)\n"
        "  -h, --help             this help\n"
        "  --version              the version, sdftrace's\n"
        "\n"
        "Dense outputs (--full, --npy) are limited to 2^31 voxels.\n"
        "Exit status: 0 on success, 1 on bad input or a failed write (one line on\n"
        "stderr; no partial output is left: files are written to a temporary name\n"
        "and renamed).\n",
        kMaxResolution);
}

bool parseOptions(int argc, char** argv, Options& opt, std::string& error)
{
    bool sawRes = false;
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        auto value = [&](const char*& out) {
            if (i + 1 >= argc) {
                error = std::string("option ") + a + " needs a value";
                return false;
            }
            out = argv[++i];
            return true;
        };
        const char* v = nullptr;
        if (!std::strcmp(a, "-h") || !std::strcmp(a, "--help")) {
            opt.help = true;
            return true;
        } else if (!std::strcmp(a, "-o") || !std::strcmp(a, "--output")) {
            if (!value(v))
                return false;
            opt.output = v;
        } else if (!std::strcmp(a, "--nvdb")) {
            if (!value(v))
                return false;
            opt.nvdb = v;
        } else if (!std::strcmp(a, "--npy")) {
            if (!value(v))
                return false;
            opt.npy = v;
        } else if (!std::strcmp(a, "--res")) {
            if (!value(v))
                return false;
            if (!parseInt(v, 1, kMaxResolution, opt.res)) {
                error = std::string("--res must be an integer in 1..") + std::to_string(kMaxResolution) +
                        ", got '" + v + "'";
                return false;
            }
            sawRes = true;
        } else if (!std::strcmp(a, "--voxel-size")) {
            if (!value(v))
                return false;
            if (!parseDouble(v, opt.voxelSize) || opt.voxelSize <= 0) {
                error = std::string("--voxel-size must be a finite number > 0, got '") + v + "'";
                return false;
            }
        } else if (!std::strcmp(a, "--band")) {
            if (!value(v))
                return false;
            if (!parseDouble(v, opt.band) || opt.band <= 0 || opt.band > kMaxResolution) {
                error = std::string("--band must be a number of voxels in (0, 4096], got '") + v + "'";
                return false;
            }
        } else if (!std::strcmp(a, "--padding")) {
            if (!value(v))
                return false;
            if (!parseDouble(v, opt.padding) || opt.padding < 0 || opt.padding > kMaxResolution) {
                error = std::string("--padding must be a number of voxels in [0, 4096], got '") + v + "'";
                return false;
            }
        } else if (!std::strcmp(a, "--sign")) {
            if (!value(v))
                return false;
            if (!std::strcmp(v, "winding"))
                opt.sign = SignMethod::Winding;
            else if (!std::strcmp(v, "flood"))
                opt.sign = SignMethod::Flood;
            else if (!std::strcmp(v, "none"))
                opt.sign = SignMethod::None;
            else {
                error = std::string("--sign must be winding, flood or none, got '") + v + "'";
                return false;
            }
        } else if (!std::strcmp(a, "--orient")) {
            if (!value(v))
                return false;
            if (!std::strcmp(v, "outward"))
                opt.orient = OrientMethod::Outward;
            else if (!std::strcmp(v, "none"))
                opt.orient = OrientMethod::None;
            else {
                error = std::string("--orient must be outward or none, got '") + v + "'";
                return false;
            }
        } else if (!std::strcmp(a, "--json")) {
            opt.json = true;
        } else if (!std::strcmp(a, "--name")) {
            if (!value(v))
                return false;
            opt.name = v;
        } else if (!std::strcmp(a, "--threads")) {
            if (!value(v))
                return false;
            if (!parseInt(v, 0, 1024, opt.threads)) {
                error = std::string("--threads must be an integer in 0..1024, got '") + v + "'";
                return false;
            }
        } else if (!std::strcmp(a, "--check-sign")) {
            if (!value(v))
                return false;
            opt.checkSign.push_back(v);
        } else if (!std::strcmp(a, "--samples")) {
            if (!value(v))
                return false;
            if (!parseInt(v, 1, 100000000, opt.samples)) {
                error = std::string("--samples must be an integer in 1..100000000, got '") + v + "'";
                return false;
            }
        } else if (!std::strcmp(a, "--full")) {
            opt.full = true;
        } else if (!std::strcmp(a, "--fp16")) {
            opt.fp16 = true;
        } else if (!std::strcmp(a, "--quiet")) {
            opt.quiet = true;
        } else if (!std::strcmp(a, "--simd")) {
            if (!value(v))
                return false;
            if (!std::strcmp(v, "auto") || !std::strcmp(v, "avx2") || !std::strcmp(v, "none")) {
                opt.simd = std::strcmp(v, "none") != 0;
                opt.simd512 = !std::strcmp(v, "auto");
            } else {
                error = std::string("--simd must be auto, avx2 or none, got '") + v + "'";
                return false;
            }
        } else if (!std::strcmp(a, "--no-simd")) {
            opt.simd = opt.simd512 = false;
        } else if (a[0] == '-' && a[1] != '\0') {
            error = std::string("unknown option '") + a + "' (see --help)";
            return false;
        } else if (opt.input.empty()) {
            opt.input = a;
        } else {
            error = std::string("unexpected argument '") + a + "' (one input mesh only)";
            return false;
        }
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
