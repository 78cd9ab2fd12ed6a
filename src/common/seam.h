// sdftrace common — what the C++ on either side of the C seams shares
// (libsdftrace_vdb, libsdftrace_mesh, mesh2sdf): the guard that keeps every
// exception inside an extern "C" function, printf into a string, a path's
// stem as a string, and the seconds since a moment. Internal header, C++
// only.
#ifndef SDFTRACE_COMMON_SEAM_H
#define SDFTRACE_COMMON_SEAM_H

#include <chrono>
#include <cstdarg>
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "fail.h"
#include "path_stem.h"
#include "sdftrace/error.h"

namespace seam
{

/// Thrown out of a long call (out of TBB's loops too) when its progress
/// callback asked to stop.
struct Cancelled : std::exception {
    const char *what() const noexcept override { return "canceled"; }
};

/// Runs body() and returns its code; an exception becomes a code and one
/// line, "WHAT: reason", in msg, so that none leaves an extern "C"
/// function: Cancelled is SDFT_ECANCELED, out of memory SDFT_ENOMEM, any
/// other exception SDFT_EINTERNAL.
template <typename Body> sdft_error guarded(const char *what, char *msg, size_t msg_len, Body &&body) noexcept
{
    try {
        return body();
    } catch (const Cancelled &) {
        return fail_with(msg, msg_len, SDFT_ECANCELED, "%s: canceled by the progress callback", what);
    } catch (const std::bad_alloc &) {
        return fail_with(msg, msg_len, SDFT_ENOMEM, "%s: out of memory", what);
    } catch (const std::exception &e) {
        return fail_with(msg, msg_len, SDFT_EINTERNAL, "%s: %s", what, e.what());
    } catch (...) {
        return fail_with(msg, msg_len, SDFT_EINTERNAL, "%s: an unknown exception", what);
    }
}

/// printf into a std::string.
inline std::string format(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
inline std::string format(const char *fmt, ...)
{
    va_list args, again;
    va_start(args, fmt);
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, fmt, args);
    va_end(args);
    std::string out(size_t(n > 0 ? n : 0) + 1, '\0');
    std::vsnprintf(&out[0], out.size(), fmt, again);
    va_end(again);
    out.resize(out.size() - 1);
    return out;
}

/// Wall-clock seconds since `start`.
inline double secondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// A path's file name without its folder and last extension (path_stem.h).
inline std::string fileStem(const std::string &path)
{
    const char *start;
    const size_t length = path_stem(path.c_str(), &start);
    return std::string(start, length);
}

} // namespace seam

#endif
