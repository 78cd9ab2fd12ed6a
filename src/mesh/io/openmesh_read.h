// sdftrace — the formats OpenMesh reads (.obj .off .stl .om), into a
// polygon soup.
#ifndef SDFT_MESH_IO_OPENMESH_READ_H
#define SDFT_MESH_IO_OPENMESH_READ_H

#include "geometry/polygon_soup.h"

#include <string>

namespace meshsdf
{

/// Reads `path` (its lower-case extension `ext`: obj, off, stl or om)
/// through OpenMesh's readers into `soup`: every vertex and every face as
/// the file gives them, whatever their orientation. The readers trust the
/// file (byte-mutated .om files crash them, make them loop or allocate what
/// a count claims), so they run in a child process (reader_process.h) where
/// a crash, a loop or an allocation past the limits becomes one line in
/// `error`; text coordinates that OpenMesh would silently misread (NaN,
/// Inf, 1e999) and OFF counts the file's length cannot hold are refused
/// before. Returns false with one line naming `path` in `error`.
bool readOpenMesh(const std::string &path, const std::string &ext, PolygonSoup &soup, std::string &error);

} // namespace meshsdf

#endif
