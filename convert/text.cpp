// mesh2sdf — text chores (see text.h).
#include "text.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <sys/resource.h>

#include "json.h"
#include "mesh_tool.h"

namespace mesh2sdf
{

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
        throw std::bad_alloc();
    json_put_string(f, text.c_str());
    std::fclose(f);
    std::string out(buffer, length);
    std::free(buffer);
    return out;
}

double peakMiB()
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_maxrss) / 1024.0; // ru_maxrss is in KiB on Linux
}

std::string sidecarPath(const std::string &npyPath)
{
    std::string path(mesh_sidecar_path(npyPath.c_str(), nullptr, 0), '\0');
    mesh_sidecar_path(npyPath.c_str(), &path[0], path.size() + 1);
    return path;
}

} // namespace mesh2sdf
