// mesh2sdf — reading the points of --query from a NumPy .npy file,
// strictly: nothing in the file is trusted (it may be truncated, hostile or
// another array), and every flaw is one line naming the file.
#ifndef MESH2SDF_NPY_READ_H
#define MESH2SDF_NPY_READ_H

#include <string>
#include <vector>

namespace mesh2sdf
{

/// Reads an (N, columns) float32 or float64 array, C or Fortran order,
/// little-endian, format version 1.0, 2.0 or 3.0, N >= 1, into `values` as
/// N rows (doubles). Checks the magic, the header's length, its dict
/// (exactly the keys 'descr', 'fortran_order' and 'shape', once each), the
/// data's length against the file's size before allocating, and that every
/// value is finite. Fails with one line in `error` naming `path`.
bool readNpyRows(const std::string &path, size_t columns, std::vector<double> &values, std::string &error);

/// The points of --query: readNpyRows with 3 columns, x, y, z.
inline bool readNpyPoints(const std::string &path, std::vector<double> &xyz, std::string &error)
{
    return readNpyRows(path, 3, xyz, error);
}

} // namespace mesh2sdf

#endif
