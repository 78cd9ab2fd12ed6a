/* sdftrace — the error codes' names and the library's version. */
#include "sdftrace/error.h"

const char *sdft_error_name(sdft_error e)
{
    static const char *const names[] = {"SDFT_OK",         "SDFT_EINVAL",    "SDFT_EIO",    "SDFT_EFORMAT",
                                        "SDFT_ENOTSCALAR", "SDFT_ENOTFOUND", "SDFT_EEMPTY", "SDFT_ENOMEM",
                                        "SDFT_ECANCELED",  "SDFT_EINTERNAL"};
    return (unsigned)e < sizeof names / sizeof names[0] ? names[e] : "SDFT_E?";
}

int sdft_version(void) { return SDFT_VERSION; }
