/* sdftrace — termination, refinement and the screen-space candidate,
 * shared by every tracing variant: march_finish (src/portable/march_loop.h),
 * defined here once, out of the loops' way. */
#define MARCH_FINISH_BODY
#include "march.h"
