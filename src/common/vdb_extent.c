/* sdftrace — a `.vdb` file's extent, walked before OpenVDB reads it.
 *
 * WHY. OpenVDB's readers do not look at the stream's state: readString,
 * readGridCount and Metadata::read take a length or a count from
 * is.read() and use it whether or not the read succeeded. Past the end
 * of a truncated file that value is whatever the variable held, so the
 * same truncated file makes OpenVDB allocate gigabytes on one run, loop
 * on the next and fail cleanly on a third (the child process of
 * vdb_isolate.cpp stops it, but only after its time limit). A truncated
 * download is the commonest bad file there is, so it is caught here, in a
 * few hundred bytes of reads, with an answer that is the same every time.
 *
 * WHAT. Only what decides where OpenVDB reads next is walked, in the
 * layout of OpenVDB's io::Archive (the header), MetaMap (the file's
 * metadata) and io::GridDescriptor (one per grid):
 *
 *   int64 magic 0x56444220; uint32 file version v;
 *   v >= 211: uint32 library major, minor;  v >= 212: char has offsets;
 *   220 <= v < 222: char compressed;  v >= 218: 36 chars of UUID;
 *   uint32 n, then n times: string name, string type, uint32 k, k bytes;
 *   int32 grids, then each grid: string name, string type,
 *   v >= 216: string instance parent; int64 grid, block and end
 *   positions; the next descriptor starts at the end position;
 *
 * where a string is a uint32 length and that many bytes. Every length is
 * checked against the bytes left before it is skipped, and every grid
 * must start after its descriptor and end by the end of the file. Files
 * older than version 218 or written without grid offsets (a stream) are
 * left to OpenVDB: there is no end position to check. Corruption inside
 * the grids (masks, compressed values) is the child process's to meet. */
#define _POSIX_C_SOURCE 200809L /* fseeko, fileno */
#include "vdb_extent.h"

#include <stdint.h>
#include <stdio.h>
#include <sys/stat.h>

#define VDB_MAGIC 0x56444220
#define UUID_CHARS 36

typedef struct walk {
    FILE *f;
    uint64_t size; /* the file's bytes */
    uint64_t at;   /* where the next read starts */
} walk;

/* n bytes at the walk's position into out; 0 when the file has them. */
static int take(walk *w, void *out, uint64_t n)
{
    if (n > w->size - w->at || fread(out, 1, (size_t)n, w->f) != n)
        return -1;
    w->at += n;
    return 0;
}

/* Moves the walk n bytes on, or to `to`: 0 when that is within the file. */
static int skip_to(walk *w, uint64_t to)
{
    if (to > w->size || fseeko(w->f, (off_t)to, SEEK_SET) != 0)
        return -1;
    w->at = to;
    return 0;
}

static int skip(walk *w, uint64_t n) { return n > w->size - w->at ? -1 : skip_to(w, w->at + n); }

/* A string: its length, then that many bytes; the first `keep` - 1 of
 * them into `kept` (NULL: none). */
static int skip_string(walk *w, char *kept, size_t keep)
{
    uint32_t n;
    if (take(w, &n, sizeof n))
        return -1;
    if (kept && keep) {
        const uint64_t k = n < keep - 1 ? n : keep - 1;
        if (take(w, kept, k))
            return -1;
        kept[k] = '\0';
        n -= (uint32_t)k;
    }
    return skip(w, n);
}

/* The file's metadata: a count, then each entry's name, type and value. */
static int skip_metadata(walk *w)
{
    uint32_t entries;
    if (take(w, &entries, sizeof entries))
        return -1;
    for (uint32_t i = 0; i < entries; i++) {
        uint32_t bytes;
        if (skip_string(w, NULL, 0) || skip_string(w, NULL, 0) || take(w, &bytes, sizeof bytes) || skip(w, bytes))
            return -1;
    }
    return 0;
}

/* Every grid's descriptor, from the walk's position (the grid count). */
static int check_grids(walk *w, uint32_t version, char *why, size_t why_len)
{
    int32_t grids;
    if (take(w, &grids, sizeof grids))
        return snprintf(why, why_len, "it ends within its header, at byte %llu", (unsigned long long)w->size), -1;
    if (grids < 0)
        return snprintf(why, why_len, "it says it holds %d grids", (int)grids), -1;
    for (int32_t g = 0; g < grids; g++) {
        char name[64];
        int64_t pos[3]; /* the grid's start, its leaf values' start, its end */
        if (skip_string(w, name, sizeof name) || skip_string(w, NULL, 0) ||
            (version >= 216 && skip_string(w, NULL, 0)) || take(w, pos, sizeof pos))
            return snprintf(why, why_len, "it ends within grid %d's descriptor, at byte %llu", (int)g + 1,
                            (unsigned long long)w->size),
                   -1;
        if (pos[2] > 0 && (uint64_t)pos[2] > w->size)
            return snprintf(why, why_len, "grid '%s' runs to byte %lld, but the file ends at byte %llu", name,
                            (long long)pos[2], (unsigned long long)w->size),
                   -1;
        if (pos[0] < 0 || (uint64_t)pos[0] < w->at || pos[2] < pos[0] || pos[1] < 0 || pos[1] > pos[2])
            return snprintf(why, why_len, "grid '%s' has impossible offsets (%lld, %lld, %lld)", name,
                            (long long)pos[0], (long long)pos[1], (long long)pos[2]),
                   -1;
        if (skip_to(w, (uint64_t)pos[2]))
            return snprintf(why, why_len, "cannot seek to byte %lld", (long long)pos[2]), -1;
    }
    return 0;
}

static int check_open(walk *w, char *why, size_t why_len)
{
    int64_t magic;
    uint32_t version, library[2];
    char offsets = 0, compressed;
    if (take(w, &magic, sizeof magic) || magic != VDB_MAGIC)
        return snprintf(why, why_len, "not a .vdb file (its first bytes are not OpenVDB's magic number)"), -1;
    if (take(w, &version, sizeof version) || (version >= 211 && take(w, library, sizeof library)) ||
        (version >= 212 && take(w, &offsets, 1)) || (version >= 220 && version < 222 && take(w, &compressed, 1)))
        return snprintf(why, why_len, "it ends within its header, at byte %llu", (unsigned long long)w->size), -1;
    if (version < 218 || !offsets)
        return 0;
    if (skip(w, UUID_CHARS) || skip_metadata(w))
        return snprintf(why, why_len, "it ends within its file metadata, at byte %llu", (unsigned long long)w->size),
               -1;
    return check_grids(w, version, why, why_len);
}

int vdb_check_extent(const char *path, char *why, size_t why_len)
{
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode))
        return 0; /* the reader says why it cannot open it */
    walk w = {fopen(path, "rb"), 0, 0};
    if (!w.f)
        return 0;
    int rc = 0;
    if (fstat(fileno(w.f), &st) == 0)
        w.size = (uint64_t)st.st_size, rc = check_open(&w, why, why_len);
    fclose(w.f);
    return rc;
}
