// sdftrace fuzzing — mesh2sdf's mesh reader (convert/mesh.cpp's loadMesh)
// on every format it takes. The input's first byte picks the extension
// (.obj .off .stl .om .ply: its value modulo 5), the rest is the file. The
// environment variable SDFT_FUZZ_MESH_FORMATS ("obj,off,stl") restricts
// the formats (the others' inputs are skipped), to fuzz some while
// another's reader is being replaced.
#include <cstdlib>
#include <string>

#include "fuzz_load_mesh.h"

namespace
{

const char *const kFormats[] = {"obj", "off", "stl", "om", "ply"};
constexpr size_t kCount = sizeof kFormats / sizeof kFormats[0];

// Per format: whether SDFT_FUZZ_MESH_FORMATS (or its absence) takes it.
struct Enabled {
    bool on[kCount];
    Enabled()
    {
        const char *only = std::getenv("SDFT_FUZZ_MESH_FORMATS");
        for (size_t f = 0; f < kCount; ++f)
            on[f] = !only ||
                    (std::string(",") + only + ",").find(std::string(",") + kFormats[f] + ",") != std::string::npos;
    }
};

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const Enabled enabled;
    fuzz_load_mesh(data, size, kFormats, kCount, enabled.on);
    return 0;
}
