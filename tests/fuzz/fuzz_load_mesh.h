// sdftrace fuzzing — one mesh input for the mesh harnesses (fuzz_mesh,
// fuzz_scene): the first byte picks the extension among `formats` (its
// value modulo their count), the rest is the file, read by mesh2sdf's
// loader (src/mesh/io/mesh_io.h: loadMesh) and its edges counted.
#ifndef SDFT_FUZZ_LOAD_MESH_H
#define SDFT_FUZZ_LOAD_MESH_H

#include <cstdint>
#include <string>

#include "fuzz_input_file.h"
#include "io/mesh_io.h"

// `enabled`, when given, says per format whether to read its inputs (the
// others are skipped).
inline void fuzz_load_mesh(const uint8_t *data, size_t size, const char *const *formats, size_t count,
                           const bool *enabled = nullptr)
{
    const size_t format = size ? data[0] % count : 0;
    if (size == 0 || (enabled && !enabled[format]))
        return;
    const std::string ext = std::string(".") + formats[format];
    char path[256];
    if (fuzz_input_file(data + 1, size - 1, ext.c_str(), path, sizeof path))
        return;
    meshsdf::TriangleMesh mesh;
    std::string error;
    if (meshsdf::loadMesh(path, mesh, error))
        meshsdf::countEdges(mesh, meshsdf::edgeUses(mesh));
    unlink(path);
}

#endif
