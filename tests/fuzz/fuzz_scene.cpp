// sdftrace fuzzing — mesh2sdf's reader of the interchange formats (assimp,
// in a child process: convert/mesh_assimp.cpp through loadMesh). The
// input's first byte picks the extension (.glb .gltf .dae .3mf .fbx: its
// value modulo 5), the rest is the file. assimp runs in the child, where
// the fuzzer sees no coverage: this harness holds our side (the child's
// answer taken apart and checked, the loader after it) to every file.
#include "fuzz_load_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const kFormats[] = {"glb", "gltf", "dae", "3mf", "fbx"};
    fuzz_load_mesh(data, size, kFormats, sizeof kFormats / sizeof kFormats[0]);
    return 0;
}
