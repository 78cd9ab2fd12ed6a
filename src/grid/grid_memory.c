/* sdftrace — memory for a grid's big tables: the NanoVDB buffer, the leaf
 * directory and the far bound. A trace reads them at scattered addresses,
 * and on 4 KiB pages nearly every read of a big grid also misses the TLB
 * (on a virtual machine a miss walks two page tables); so where the kernel
 * offers transparent huge pages on request (madvise), tables of 2 MiB and
 * more are aligned to 2 MiB and asked for them. Contents are unchanged. */
#define _DEFAULT_SOURCE /* madvise */
#include <stdlib.h>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "grid_internal.h"

enum { HUGE_PAGE = 2u << 20 };

void *sdft_grid_table_alloc(size_t bytes)
{
    if (bytes < HUGE_PAGE) {
        const size_t padded = (bytes + 63u) & ~(size_t)63u;
        return aligned_alloc(64, padded ? padded : 64);
    }
    const size_t padded = (bytes + HUGE_PAGE - 1u) & ~(size_t)(HUGE_PAGE - 1u);
    void *p = aligned_alloc(HUGE_PAGE, padded);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (p)
        madvise(p, padded, MADV_HUGEPAGE); /* a hint: failure leaves 4 KiB pages */
#endif
    return p;
}
