// mesh2sdf — running a mesh reader we do not control in a child process,
// so that its crash, abort or endless loop on a malformed file becomes one
// line of error instead of ending (or stalling) mesh2sdf.
#ifndef MESH2SDF_READER_PROCESS_H
#define MESH2SDF_READER_PROCESS_H

#include "polygon_soup.h"

#include <functional>
#include <string>

namespace mesh2sdf
{

/// A reader: fills the soup, or returns false with one line in the error.
using SoupReader = std::function<bool(PolygonSoup &soup, std::string &error)>;

/// Runs `read` in a forked child (its stderr silenced) and takes back its
/// soup or its error through a pipe. A child that dies by a signal, exits
/// without an answer, or takes longer than `seconds` (then killed) gives an
/// error naming `path`. Returns what `read` returned otherwise.
bool readInChildProcess(const SoupReader &read, double seconds, const std::string &path, PolygonSoup &soup,
                        std::string &error);

} // namespace mesh2sdf

#endif
