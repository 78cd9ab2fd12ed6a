// sdftrace — running a mesh reader we do not control (OpenMesh's, assimp)
// in a child process (src/common/isolated_read.h), so that its crash,
// abort, endless loop or runaway allocation on a malformed file becomes one
// line of error instead of ending (or stalling) mesh2sdf.
#ifndef SDFT_MESH_IO_READER_PROCESS_H
#define SDFT_MESH_IO_READER_PROCESS_H

#include "geometry/polygon_soup.h"

#include <functional>
#include <string>

namespace meshsdf
{

/// A reader: fills the soup, or returns false with one line in the error.
using SoupReader = std::function<bool(PolygonSoup &soup, std::string &error)>;

/// Runs `read` on `path` in a forked child, with the time and the memory
/// isolated_read() allows for the file's size, and takes back its soup (its
/// counts and warnings too) or its error. A child that crashes, runs out of
/// time or memory, or answers short gives an error naming `path` and the
/// reader (`reader`: "the glTF importer"), which is at fault then, whatever
/// the file holds. Returns what `read` returned otherwise.
bool readInChildProcess(const SoupReader &read, const std::string &path, const std::string &reader, PolygonSoup &soup,
                        std::string &error);

} // namespace meshsdf

#endif
