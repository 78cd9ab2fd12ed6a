// mesh2sdf --batch under Open MPI's mpirun: the meshes handed out one at a
// time to whichever rank is free, largest file first, every rank (rank 0
// too) converting, and rank 0 alone writing the report as rows come in.
// Compiled only where CMake finds MPI; MPI_Init runs only under mpirun, so
// a plain run pays nothing.
#ifndef MESH2SDF_MPI_BATCH_H
#define MESH2SDF_MPI_BATCH_H

#include "options.h"

namespace mesh2sdf
{

/// Whether mpirun started this process (Open MPI sets OMPI_COMM_WORLD_SIZE
/// in every rank's environment).
bool mpiLaunched();

/// The batch `opt` describes across the ranks of MPI_COMM_WORLD; rank 0's
/// exit status is runBatch's, the other ranks return 0 (or 1 when they
/// could not set up). Every rank calls it with the same options.
int runMpiBatch(const Options &opt);

} // namespace mesh2sdf

#endif
