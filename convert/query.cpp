// mesh2sdf --query, and what it shares with --samples (see query.h).
#include "query.h"

#include "npy_read.h"
#include "orient.h"
#include "output.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdarg>
#include <cstdlib>
#include <cstring>
#include <sys/resource.h>

#include "json.h"

namespace mesh2sdf
{

PointQuery::PointQuery(const TriangleMesh &mesh, bool simd, bool wide)
{
    tbb::parallel_invoke([&] { mNearest.reset(new NearestTriangle(mesh, simd, wide)); },
                         [&] { mWinding.reset(new FastWinding(mesh.points, mesh.triangles, 2.0, simd)); });
}

namespace
{

// Spreads the low 21 bits of x to every third bit (a Morton code's axis).
uint64_t spread(uint64_t x)
{
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    return (x | x << 2) & 0x1249249249249249ull;
}

} // namespace

std::vector<size_t> mortonOrder(const std::vector<double> &xyz, const MeshSphere &cube)
{
    const size_t n = xyz.size() / 3;
    std::vector<std::pair<uint64_t, size_t>> keyed(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
            uint64_t code = 0;
            for (int k = 0; k < 3; ++k) {
                const double at = std::clamp((xyz[i * 3 + k] - cube.centre[k]) / (2 * cube.radius) + 0.5, 0.0, 1.0);
                code |= spread(uint64_t(at * 2097151.0)) << k;
            }
            keyed[i] = {code, i};
        }
    });
    tbb::parallel_sort(keyed.begin(), keyed.end());
    std::vector<size_t> order(n);
    for (size_t j = 0; j < n; ++j)
        order[j] = keyed[j].second;
    return order;
}

bool loadPointMesh(const Options &opt, TriangleMesh &mesh, MeshSphere &sphere, double &orientSeconds,
                   std::string &error)
{
    if (!loadMesh(opt.input, mesh, error))
        return false;
    sphere = meshSphere(mesh);
    if (opt.normalize)
        normalizeMesh(mesh, sphere);
    const auto start = std::chrono::steady_clock::now();
    if (opt.orient == OrientMethod::Outward)
        orientMesh(mesh, opt.simd);
    orientSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return true;
}

bool PointFiles::reserve(const std::string &npy, std::string &error)
{
    return (reserveFile(npy, array, error) && reserveFile(sidecarPath(npy), sidecar, error)) || discard();
}

bool PointFiles::discard()
{
    discardFile(array);
    discardFile(sidecar);
    return false;
}

namespace
{

bool writeSidecar(const std::string &tmp, const std::string &fields, const Options &opt, const MeshSphere &sphere)
{
    FILE *f = std::fopen(tmp.c_str(), "w");
    if (!f)
        return false;
    std::fprintf(f, "{\n%s", fields.c_str());
    std::fprintf(f,
                 "  \"normalized\": %s,\n"
                 "  \"centre\": [%.17g, %.17g, %.17g],\n"
                 "  \"radius\": %.17g,\n",
                 opt.normalize ? "true" : "false", sphere.centre[0], sphere.centre[1], sphere.centre[2], sphere.radius);
    if (opt.normalize)
        std::fprintf(f, "  \"to_mesh_units\": \"point * radius + centre; distance * radius\",\n");
    else
        std::fprintf(f, "  \"to_unit_sphere\": \"(point - centre) / radius; distance / radius\",\n");
    std::fprintf(f,
                 "  \"sign\": \"negative inside: winding number > 0.5\",\n  \"orient\": \"%s\",\n"
                 "  \"source_mesh\": ",
                 opt.orient == OrientMethod::Outward ? "outward" : "none");
    json_put_string(f, opt.input.c_str());
    std::fprintf(f, "\n}\n");
    const bool ok = !std::ferror(f);
    return std::fclose(f) == 0 && ok;
}

} // namespace

bool PointFiles::write(const std::string &shape, const std::vector<float> &values, const std::string &fields,
                       const Options &opt, const MeshSphere &sphere, std::string &error)
{
    if (!writeNpyArray(array.tmp, shape, values.data(), values.size(), error))
        return discard();
    if (!writeSidecar(sidecar.tmp, fields, opt, sphere)) {
        error = "cannot write " + sidecar.tmp + ": " + std::strerror(errno);
        return discard();
    }
    return (commitFile(array, error) && commitFile(sidecar, error)) || discard();
}

std::string format(const char *fmt, ...)
{
    va_list args, again;
    va_start(args, fmt);
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, fmt, args);
    va_end(args);
    std::string out(size_t(std::max(n, 0)) + 1, '\0');
    std::vsnprintf(&out[0], out.size(), fmt, again);
    va_end(again);
    out.resize(out.size() - 1);
    return out;
}

std::string jsonString(const std::string &text)
{
    char *buffer = nullptr;
    size_t length = 0;
    FILE *f = open_memstream(&buffer, &length);
    if (!f)
        return "\"\"";
    json_put_string(f, text.c_str());
    std::fclose(f);
    std::string out(buffer, length);
    std::free(buffer);
    return out;
}

std::string arrayField(const std::string &path)
{
    const size_t slash = path.find_last_of('/');
    return "  \"array\": " + jsonString(slash == std::string::npos ? path : path.substr(slash + 1)) + ",\n";
}

double peakMiB()
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_maxrss) / 1024.0; // KiB on Linux
}

bool runQuery(const Options &opt, std::string &error)
{
    const auto t0 = std::chrono::steady_clock::now();
    PointFiles files;
    if (!files.reserve(opt.queryOut, error))
        return false;
    std::vector<double> xyz;
    TriangleMesh mesh;
    MeshSphere sphere;
    double orientSeconds = 0;
    if (!readNpyPoints(opt.queryIn, xyz, error) || !loadPointMesh(opt, mesh, sphere, orientSeconds, error))
        return files.discard();
    const PointQuery query(mesh, opt.simd, opt.simd512);
    const size_t count = xyz.size() / 3, columns = opt.winding ? 2 : 1;
    std::vector<float> out(count * columns);
    const auto t1 = std::chrono::steady_clock::now();
    const std::vector<size_t> order = mortonOrder(xyz, opt.normalize ? MeshSphere{} : sphere);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t j = r.begin(); j != r.end(); ++j) {
            const size_t i = order[j];
            double w;
            out[i * columns] = float(query.signedDistance(&xyz[i * 3], INFINITY, &w));
            if (opt.winding)
                out[i * columns + 1] = float(w);
        }
    });
    const double querySeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    const std::string shape = "(" + std::to_string(count) + (opt.winding ? ", 2)" : ",)");
    const std::string fields =
        arrayField(opt.queryOut) +
        format("  \"points\": %s,\n  \"dtype\": \"float32\",\n  \"shape\": [%zu%s],\n  \"columns\": [%s],\n",
               jsonString(opt.queryIn).c_str(), count, opt.winding ? ", 2" : "",
               opt.winding ? "\"distance\", \"winding\"" : "\"distance\"");
    if (!files.write(shape, out, fields, opt, sphere, error))
        return false;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (opt.json) {
        std::printf("{\"mesh\": ");
        json_put_string(stdout, opt.input.c_str());
        std::printf(", \"points\": ");
        json_put_string(stdout, opt.queryIn.c_str());
        std::printf(", \"output\": ");
        json_put_string(stdout, opt.queryOut.c_str());
        std::printf(", \"count\": %zu, \"triangles\": %zu, \"orient_seconds\": %.6f, \"query_seconds\": %.6f, "
                    "\"points_per_second\": %.0f, \"seconds\": %.6f, \"peak_mib\": %.1f}\n",
                    count, mesh.triangles.size(), orientSeconds, querySeconds, double(count) / querySeconds, seconds,
                    peakMiB());
    } else if (!opt.quiet) {
        std::printf("wrote %s: %zu signed distances%s, %.2f s, queries %.3f s (%.0f points/s)\n", opt.queryOut.c_str(),
                    count, opt.winding ? " and winding numbers" : "", seconds, querySeconds,
                    double(count) / querySeconds);
    }
    return true;
}

} // namespace mesh2sdf
