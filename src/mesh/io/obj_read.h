// sdftrace — Wavefront .obj files into a polygon soup, parsed in parallel.
#ifndef SDFT_MESH_IO_OBJ_READ_H
#define SDFT_MESH_IO_OBJ_READ_H

#include "geometry/polygon_soup.h"

#include <string>

namespace meshsdf
{

/// Reads the .obj file `path` into `soup`: every "v" line's point and every
/// "f" line's polygon on them, in the file's order. The file is read whole
/// and its lines parsed in pieces side by side (TBB, in the caller's
/// arena), then joined in order, so that the soup is the same for any
/// thread count. A file this parser does not take whole as plain (a
/// coordinate that is not a finite float, a corner index that is not an
/// integer or that points past the points, a face of fewer than three
/// corners or with one repeated, a malformed "vt" line) goes to
/// OpenMesh's reader instead (openmesh_read.h), which reads it as it
/// always has (the same soup for the plain files: their points parsed to
/// the same correctly rounded floats, their faces on the same numbering)
/// and says what is wrong with it. Returns false with one line naming
/// `path` in `error`.
bool readObj(const std::string &path, PolygonSoup &soup, std::string &error);

/// The soup of an .obj file's text as readObj parses it, or false, with
/// `soup` empty, when the text is not plain (OpenMesh's reader then reads
/// the file).
bool parsePlainObj(const char *text, size_t size, PolygonSoup &soup);

} // namespace meshsdf

#endif
