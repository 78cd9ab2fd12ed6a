/* sdftrace — how much memory this process may use, and refusing a size
 * that would need more, before allocating it, with the estimate in the
 * message. Internal header, for the tools and the libraries' C and C++;
 * header-only (static) like fail.h, so that each has its own copy.
 *
 * The limit is the smaller of the machine's physical memory
 * (sysconf(_SC_PHYS_PAGES)) and the address-space limit (getrlimit
 * RLIMIT_AS, `ulimit -v`): past the first the machine swaps or the kernel
 * kills the process; past the second malloc fails. Either way the user
 * waits for nothing, so a size whose estimated peak exceeds it is refused. */
#ifndef SDFTRACE_COMMON_MEMORY_LIMIT_H
#define SDFTRACE_COMMON_MEMORY_LIMIT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <unistd.h>

/* Bytes the machine lets this process use: min(physical memory,
 * RLIMIT_AS). */
static inline uint64_t memory_machine_bytes(void)
{
    uint64_t limit = UINT64_MAX;
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0)
        limit = (uint64_t)pages * (uint64_t)page;
    struct rlimit as;
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY && (uint64_t)as.rlim_cur < limit)
        limit = (uint64_t)as.rlim_cur;
    return limit;
}

/* What the size checks allow: memory_machine_bytes(), lowered by the
 * environment variable SDFT_MEMORY_LIMIT (bytes) where set, so that tests
 * can see a refusal (and its estimate) without a machine's worth of
 * memory. */
static inline uint64_t memory_limit_bytes(void)
{
    uint64_t limit = memory_machine_bytes();
    const char *env = getenv("SDFT_MEMORY_LIMIT");
    unsigned long long forced;
    if (env && sscanf(env, "%llu", &forced) == 1 && forced < limit)
        limit = forced;
    return limit;
}

/* bytes as "37.2 GiB", or "103 MiB" below a GiB, into buf. */
static inline const char *memory_size_text(double bytes, char *buf, size_t len)
{
    const double mib = 1024.0 * 1024.0;
    if (bytes >= 1024.0 * mib)
        snprintf(buf, len, "%.1f GiB", bytes / (1024.0 * mib));
    else
        snprintf(buf, len, "%.0f MiB", bytes / mib);
    return buf;
}

/* 0 when `need` bytes (an estimate of the peak) fit memory_limit_bytes();
 * otherwise -1 with one line in msg: "needs ~37.2 GiB for WHAT; this
 * machine allows 24.0 GiB (...)". `need` is a double so that an
 * overflowing product of sizes stays an honest (huge) estimate. */
static inline int memory_check(double need, const char *what, char *msg, size_t msg_len)
{
    const uint64_t limit = memory_limit_bytes();
    if (need <= (double)limit)
        return 0;
    char a[32], b[32];
    if (msg && msg_len)
        snprintf(msg, msg_len, "needs ~%s for %s; this machine allows %s (physical memory, ulimit -v)",
                 memory_size_text(need, a, sizeof a), what, memory_size_text((double)limit, b, sizeof b));
    return -1;
}

#endif
