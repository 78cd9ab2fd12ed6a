/* sdftrace — writing an error's one line into the caller's buffer.
 * Internal header, for the C and C++ code of every component. Header-only
 * (static), so that each library has its own copy and no symbol. */
#ifndef SDFTRACE_COMMON_FAIL_H
#define SDFTRACE_COMMON_FAIL_H

#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include "sdftrace/error.h"

#if defined(__GNUC__)
#define SDFT_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define SDFT_PRINTF(fmt, args)
#endif

/* An internal function that one library's files share: never exported,
 * whatever the file's default visibility (the OpenVDB seam's is default). */
#if defined(__GNUC__)
#define SDFT_INTERNAL __attribute__((visibility("hidden")))
#else
#define SDFT_INTERNAL
#endif

/* printf into msg (when msg and msg_len), on one line whatever a path in it
 * holds; returns code. */
static inline sdft_error fail_with(char *msg, size_t msg_len, sdft_error code, const char *fmt, ...) SDFT_PRINTF(4, 5);
static inline sdft_error fail_with(char *msg, size_t msg_len, sdft_error code, const char *fmt, ...)
{
    if (msg && msg_len) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg, msg_len, fmt, ap);
        va_end(ap);
        for (char *c = msg; *c; c++)
            if (*c == '\n' || *c == '\r')
                *c = ' ';
    }
    return code;
}

#endif
