/* sdftrace — one error convention for every component.
 *
 * Every function that can fail returns an sdft_error (SDFT_OK, 0, on
 * success) and takes a buffer for one line saying why, `msg` of `msg_len`
 * bytes, last: the line is written NUL-terminated and cut to fit, never
 * with a newline. `msg` may be NULL (or msg_len 0) when the reason is not
 * wanted. The buffer stays the caller's; nothing is kept, nothing global is
 * set, and the library never prints. */
#ifndef SDFTRACE_ERROR_H
#define SDFTRACE_ERROR_H

#include "sdftrace/config.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sdft_error {
    SDFT_OK = 0,
    SDFT_EINVAL,     /* an argument is NULL, out of range, or inconsistent with another */
    SDFT_EIO,        /* a file cannot be opened, read or written */
    SDFT_EFORMAT,    /* not the file format or buffer layout expected, or corrupt or truncated */
    SDFT_ENOTSCALAR, /* the chosen grid does not hold scalar values */
    SDFT_ENOTFOUND,  /* no grid of the given name, or no grid at all */
    SDFT_EEMPTY,     /* a grid or a bake holds no active voxel */
    SDFT_ENOMEM,     /* out of memory */
    SDFT_ECANCELED,  /* a progress callback asked to stop */
    SDFT_EINTERNAL   /* an unexpected failure inside a dependency (e.g. an OpenVDB exception) */
} sdft_error;

/* The code's name, e.g. "SDFT_EINVAL"; "SDFT_E?" for a value outside the
 * enum. A static string. */
SDFT_API const char *sdft_error_name(sdft_error e);

/* The library's version, SDFT_VERSION of the headers it was built with. */
SDFT_API int sdft_version(void);

#ifdef __cplusplus
}
#endif
#endif
