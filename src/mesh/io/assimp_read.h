// sdftrace — reading the interchange formats (glTF, FBX, Collada, 3MF and
// others) through assimp, flattened into one polygon soup in world space.
#ifndef SDFT_MESH_IO_ASSIMP_READ_H
#define SDFT_MESH_IO_ASSIMP_READ_H

#include "geometry/polygon_soup.h"

#include <string>

namespace meshsdf
{

/// The extensions readAssimp takes, lower case without the dot, separated
/// by spaces.
extern const char *const kAssimpExtensions;

/// True if `ext` (lower case, no dot) is one of kAssimpExtensions.
bool isAssimpExtension(const std::string &ext);

/// Reads `path` through assimp into `soup`: every mesh under every node of
/// the scene, once per node that holds it, its vertices moved by the node's
/// accumulated transform (the file's coordinates otherwise: no unit or up
/// axis conversion), its polygons as the file gives them; points and lines
/// are left out. Returns false and sets `error` to one line naming `path`
/// when assimp cannot read the file or the scene is malformed.
bool readAssimp(const std::string &path, PolygonSoup &soup, std::string &error);

} // namespace meshsdf

#endif
