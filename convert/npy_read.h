// mesh2sdf — reading the points of --query from a NumPy .npy file,
// strictly: nothing in the file is trusted (it may be truncated, hostile or
// another array), and every flaw is one line naming the file.
#ifndef MESH2SDF_NPY_READ_H
#define MESH2SDF_NPY_READ_H

#include <string>
#include <vector>

namespace mesh2sdf
{

/// Reads an (N, 3) float32 or float64 array, C or Fortran order, little-
/// endian, format version 1.0, 2.0 or 3.0, N >= 1, into `xyz` as N rows of
/// x, y, z (doubles). Checks the magic, the header's length, its dict
/// (exactly the keys 'descr', 'fortran_order' and 'shape', once each), the
/// data's length against the file's size before allocating, and that every
/// coordinate is finite. Fails with one line in `error` naming `path`.
bool readNpyPoints(const std::string &path, std::vector<double> &xyz, std::string &error);

} // namespace mesh2sdf

#endif
