/* sdftrace docs — docs/mesh-settings.md, made from the mesh component's
 * tables of settings (sdftrace/mesh.h, sdft_mesh_settings), so that the
 * page cannot say another default or range than the library holds.
 *
 *   settings_table OUT.md          writes the page (make docs)
 *   settings_table --check PAGE.md exits 1, naming the command, when the
 *                                  page is not what it would write (a ctest)
 */
#define _POSIX_C_SOURCE 200809L /* open_memstream */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "parse.h" /* src/common: the names of a choice */
#include "sdftrace/mesh.h"

/* The shortest decimal that reads back as v; a whole number whole. */
static void shortest(double v, char *buf, size_t len)
{
    if (v == (double)(long long)v && v > -1e18 && v < 1e18) {
        snprintf(buf, len, "%lld", (long long)v);
        return;
    }
    for (int digits = 1; digits <= 17; digits++) {
        snprintf(buf, len, "%.*g", digits, v);
        if (strtod(buf, NULL) == v)
            return;
    }
}

static void row(FILE *out, const sdft_mesh_setting *s)
{
    char def[96] = "", range[96] = "", type[128] = "", a[40], b[40];
    const char *name;
    switch (s->kind) {
    case SDFT_MESH_SETTING_INT:
        snprintf(type, sizeof type, "int");
        break;
    case SDFT_MESH_SETTING_COUNT:
        snprintf(type, sizeof type, "uint64_t");
        break;
    case SDFT_MESH_SETTING_REAL:
        snprintf(type, sizeof type, s->count > 1 ? "double[%d]" : "double", s->count);
        break;
    case SDFT_MESH_SETTING_FLAG:
        snprintf(type, sizeof type, "flag (0 or 1)");
        break;
    case SDFT_MESH_SETTING_CHOICE:
        snprintf(type, sizeof type, "one of: %s", s->choices);
        break;
    case SDFT_MESH_SETTING_TEXT:
        snprintf(type, sizeof type, "text");
        break;
    }
    if (s->kind == SDFT_MESH_SETTING_CHOICE) {
        const int n = (int)parse_list_item(s->choices, (int)s->def[0], &name);
        snprintf(def, sizeof def, "%.*s", n, name);
    } else if (s->kind != SDFT_MESH_SETTING_TEXT)
        for (int k = 0; k < s->count; k++) {
            shortest(s->def[k], a, sizeof a);
            snprintf(def + strlen(def), sizeof def - strlen(def), "%s%s", k ? ", " : "", a);
        }
    if (s->automatic)
        snprintf(def + strlen(def), sizeof def - strlen(def), "%s%s", def[0] ? ": " : "", s->automatic);
    if (s->kind == SDFT_MESH_SETTING_INT || s->kind == SDFT_MESH_SETTING_COUNT || s->kind == SDFT_MESH_SETTING_REAL) {
        shortest(s->lo, a, sizeof a);
        shortest(s->hi, b, sizeof b);
        if (s->hi == HUGE_VAL)
            snprintf(range, sizeof range, "%s %s", s->flags & SDFT_MESH_SETTING_OPEN_LO ? ">" : ">=", a);
        else
            snprintf(range, sizeof range, "%c%s, %s%c", s->flags & SDFT_MESH_SETTING_OPEN_LO ? '(' : '[', a, b,
                     s->flags & SDFT_MESH_SETTING_OPEN_HI ? ')' : ']');
    }
    fprintf(out, "| `%s` | %s | %s | %s | %s |\n", s->name, type, def, range, s->doc);
}

static void table(FILE *out, sdft_mesh_settings_of of, const char *title)
{
    size_t n = 0;
    const sdft_mesh_setting *s = sdft_mesh_settings(of, &n);
    fprintf(out, "\n## %s\n\n| setting | type | default | range | what it does |\n|---|---|---|---|---|\n", title);
    for (size_t i = 0; i < n; i++)
        row(out, &s[i]);
}

static void page(FILE *out)
{
    fputs("# The mesh component's settings\n"
          "\n"
          "Every setting of the mesh component, as the tables of `include/sdftrace/mesh.h`\n"
          "hold it: the params structs' members, their defaults (`sdft_mesh_params_defaults`\n"
          "and its kin) and their ranges, which the calls check. `mesh2sdf` takes each as an\n"
          "option named for it, with dashes for underscores (`--voxel-size`), and Python's\n"
          "`sdftrace` as a keyword of the same name (`Mesh(...)`, `Mesh.to_grid`,\n"
          "`Mesh.sample_near_surface`), with these defaults. Only a grid's `threads` has no\n"
          "option of its own (it follows `--threads`, the mesh's), and the samples' `count`\n"
          "is `--samples N` (`--sample-count N` in a batch; Python's `n`).\n"
          "\n"
          "This page is written by `make docs` (`docs/settings_table.c`) from the library\n"
          "itself; `make test` fails while it differs.\n",
          out);
    table(out, SDFT_MESH_SETTINGS_MESH, "Taking a mesh in: `sdft_mesh_params`");
    table(out, SDFT_MESH_SETTINGS_GRID, "Converting to a grid: `sdft_mesh_grid_params`");
    table(out, SDFT_MESH_SETTINGS_SAMPLES, "Drawing training samples: `sdft_mesh_sample_params`");
}

int main(int argc, char **argv)
{
    const int check = argc == 3 && strcmp(argv[1], "--check") == 0;
    if (argc != 2 && !check) {
        fprintf(stderr, "usage: settings_table OUT.md | settings_table --check PAGE.md\n");
        return 2;
    }
    char *made = NULL;
    size_t made_len = 0;
    FILE *mem = open_memstream(&made, &made_len);
    if (!mem)
        return 2;
    page(mem);
    fclose(mem);
    const char *path = check ? argv[2] : argv[1];
    if (check) {
        FILE *f = fopen(path, "rb");
        char *have = calloc(made_len + 2, 1);
        const size_t got = f && have ? fread(have, 1, made_len + 1, f) : 0;
        const int same = got == made_len && memcmp(have, made, made_len) == 0;
        if (f)
            fclose(f);
        free(have);
        free(made);
        if (!same)
            fprintf(stderr, "%s is not what the library's settings make: run `make docs`\n", path);
        return same ? 0 : 1;
    }
    FILE *f = fopen(path, "wb");
    const int ok = f && fwrite(made, 1, made_len, f) == made_len;
    if (f && fclose(f) != 0)
        return 1;
    free(made);
    return ok ? 0 : 1;
}
