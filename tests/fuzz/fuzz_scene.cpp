// sdftrace fuzzing — mesh2sdf's reader of the interchange formats (assimp,
// in a child process: convert/mesh_assimp.cpp through loadMesh). The
// input's first byte picks the extension (.glb .gltf .dae .3mf .fbx: its
// value modulo 5), the rest is the file. assimp runs in the child, where
// the fuzzer sees no coverage: this harness holds our side (the child's
// answer taken apart and checked, the loader after it) to every file.
#include <cstdint>
#include <string>

#include "fuzz_input_file.h"
#include "mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const kFormats[] = {"glb", "gltf", "dae", "3mf", "fbx"};
    if (size == 0)
        return 0;
    const std::string ext = std::string(".") + kFormats[data[0] % 5];
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
