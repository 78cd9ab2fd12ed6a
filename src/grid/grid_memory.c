/* sdftrace — memory for a grid's big tables: the NanoVDB buffer, the leaf
 * directory and the far bound, 64-byte aligned (a cache line).
 *
 * Not on huge pages: they cut a 1024^3 grid's ns per random sample by a
 * few percent, but on this project's virtual machine the first touch of a
 * page asked for with madvise(MADV_HUGEPAGE) cost 3.6 times a 4 KiB one
 * (compaction, then the host backing 2 MiB at once): 9.8 s against 2.7 s
 * for 1 GiB, far more than a frame saves. */
#include <stdlib.h>

#include "grid_internal.h"

void *grid_table_alloc(size_t bytes)
{
    const size_t padded = (bytes + 63u) & ~(size_t)63u;
    return aligned_alloc(64, padded ? padded : 64);
}
