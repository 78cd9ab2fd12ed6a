// mesh2sdf — the small text chores of its reports: printf into a string,
// a JSON string literal, the peak memory.
#ifndef MESH2SDF_TEXT_H
#define MESH2SDF_TEXT_H

#include <string>

namespace mesh2sdf
{

/// printf into a std::string.
std::string format(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/// `text` as a quoted JSON string, quotes included (json.h).
std::string jsonString(const std::string &text);

/// Peak resident memory of the process so far, MiB.
double peakMiB();

/// The sidecar JSON beside an .npy file (mesh_sidecar_path, mesh_tool.h).
std::string sidecarPath(const std::string &npyPath);

} // namespace mesh2sdf

#endif
