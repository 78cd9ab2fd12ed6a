#define _POSIX_C_SOURCE 200809L /* popen, pclose */
#include "testutil.h"

#include <dirent.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

int tu_run(char *out, size_t out_len, const char *fmt, ...)
{
    char cmd[8192];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    char full[8300];
    snprintf(full, sizeof full, "%s 2>&1", cmd);
    FILE *p = popen(full, "r");
    if (!p)
        return -1;
    size_t n = 0;
    char chunk[4096];
    size_t got;
    while ((got = fread(chunk, 1, sizeof chunk, p)) > 0) {
        if (out && n + 1 < out_len) {
            size_t take = got < out_len - 1 - n ? got : out_len - 1 - n;
            memcpy(out + n, chunk, take);
            n += take;
        }
    }
    if (out && out_len)
        out[n] = '\0';
    int status = pclose(p);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

const char *tu_tmp(char *buf, size_t len, const char *name)
{
    snprintf(buf, len, "%s/%s", SDFT_TEST_TMP, name);
    return buf;
}

int tu_file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

int tu_write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    const int ok = fputs(text, f) >= 0;
    return fclose(f) == 0 && ok ? 0 : -1;
}

int tu_lines(const char *s)
{
    int n = 0;
    for (; *s; s++)
        n += *s == '\n';
    return n;
}

char *tu_slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    const long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (!s) {
        fclose(f);
        return NULL;
    }
    const size_t got = fread(s, 1, (size_t)n, f);
    s[got] = '\0';
    fclose(f);
    return s;
}

int tu_readme_shows(const char *path)
{
    char full[4096];
    snprintf(full, sizeof full, "%s/%s", SDFT_SOURCE_DIR, path);
    char *readme = tu_slurp(SDFT_SOURCE_DIR "/README.md"), *text = tu_slurp(full);
    const int shown = readme && text && strstr(readme, text) != NULL;
    free(readme);
    free(text);
    return shown;
}

int tu_temporaries(const char *dir, const char *name)
{
    char prefix[512];
    snprintf(prefix, sizeof prefix, ".%s.tmp-", name);
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
    closedir(d);
    return n;
}

int tu_file_mode(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (int)(st.st_mode & 07777) : -1;
}

float tu_uniform(tu_rng *r, float lo, float hi)
{
    r->state ^= r->state >> 12;
    r->state ^= r->state << 25;
    r->state ^= r->state >> 27;
    uint64_t x = r->state * 0x2545F4914F6CDD1Dull;
    return lo + (hi - lo) * (float)((x >> 40) * (1.0 / 16777216.0));
}

sdft_error tu_open_nvdb(const char *path, const char *name, sdft_grid **out, char *msg, size_t msg_len)
{
    sdft_grid_options o = sdft_grid_options_defaults();
    o.path = path, o.name = name;
    return sdft_grid_open(&o, out, msg, msg_len);
}

sdft_error tu_open_file(const char *path, const char *name, sdft_quant quant, sdft_grid **out, char *msg,
                        size_t msg_len)
{
    sdft_grid_options o = sdft_grid_options_defaults();
    o.quant = quant;
    return tu_open_with(path, name, &o, out, msg, msg_len);
}

sdft_error tu_open_with(const char *path, const char *name, const sdft_grid_options *o, sdft_grid **out, char *msg,
                        size_t msg_len)
{
    if (!o)
        return sdft_vdb_open(NULL, out, msg, msg_len);
    sdft_grid_options with = *o;
    with.path = path, with.name = name;
    return sdft_vdb_open(&with, out, msg, msg_len);
}

sdft_error tu_open_buffer(const void *data, size_t size, const char *name, sdft_grid_memory memory,
                          void (*release)(void *data), sdft_grid **out, char *msg, size_t msg_len)
{
    sdft_grid_options o = sdft_grid_options_defaults();
    o.data = data, o.size = size, o.name = name, o.memory = memory, o.release = release;
    return sdft_grid_open(&o, out, msg, msg_len);
}
