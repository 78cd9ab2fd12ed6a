// sdftrace fuzzing — mesh2sdf's mesh reader (convert/mesh.cpp's loadMesh)
// on every format it takes. The input's first byte picks the extension
// (.obj .off .stl .om .ply: its value modulo 5), the rest is the file. The
// environment variable SDFT_FUZZ_MESH_FORMATS ("obj,off,stl") restricts
// the formats (the others' inputs are skipped), to fuzz some while
// another's reader is being replaced.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "fuzz_input_file.h"
#include "mesh.h"

namespace
{

const char *const kFormats[] = {"obj", "off", "stl", "om", "ply"};

// Per format: whether SDFT_FUZZ_MESH_FORMATS (or its absence) takes it.
std::vector<bool> enabled()
{
    const char *only = std::getenv("SDFT_FUZZ_MESH_FORMATS");
    std::vector<bool> out;
    for (const char *f : kFormats)
        out.push_back(!only || (std::string(",") + only + ",").find(std::string(",") + f + ",") != std::string::npos);
    return out;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const std::vector<bool> on = enabled();
    const size_t format = size ? data[0] % 5 : 0;
    if (size == 0 || !on[format])
        return 0;
    const std::string ext = std::string(".") + kFormats[format];
    char path[256];
    if (fuzz_input_file(data + 1, size - 1, ext.c_str(), path, sizeof path))
        return 0;
    mesh2sdf::TriangleMesh mesh;
    std::string error;
    if (mesh2sdf::loadMesh(path, mesh, error))
        mesh2sdf::countEdges(mesh, mesh2sdf::edgeUses(mesh));
    unlink(path);
    return 0;
}
