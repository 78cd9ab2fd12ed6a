// sdftrace — the PLY reader: ascii, binary_little_endian and
// binary_big_endian, faces as polygons and as triangle strips.
#ifndef SDFT_MESH_IO_PLY_READ_H
#define SDFT_MESH_IO_PLY_READ_H

#include "geometry/polygon_soup.h"

#include <string>

namespace meshsdf
{

/// Reads `path` as PLY into `soup`: the `vertex` element's x, y, z (any
/// scalar type, rounded to float) in the file's order, and faces in the
/// file's order from the `face` element's vertex_indices (or vertex_index)
/// list and from the `tristrips` element's lists, where -1 restarts a strip
/// and every other triangle of a strip is reversed so that the strip keeps
/// one orientation (its zero-area stitches, triangles with a corner
/// repeated, left out). Every other property and element is skipped.
/// Polygons are handed on as the file gives them (fewer than three corners
/// or a repeated corner included: the loader decides); a face or strip
/// triangle with a vertex index out of range is left out and counted in
/// soup.skippedFaces. A header line that is no PLY keyword is read as a
/// comment, with a line in soup.warnings. Returns false and sets `error` to
/// one line naming `path` on a malformed header, counts the file's length
/// cannot hold, a body that ends early or holds a malformed number; nothing
/// is allocated beyond what the file's length can back.
bool readPly(const std::string &path, PolygonSoup &soup, std::string &error);

} // namespace meshsdf

#endif
