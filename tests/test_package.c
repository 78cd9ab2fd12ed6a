/* sdftrace tests — the library as others get it: every public header
 * compiles alone as C11 and as C++17 (-pedantic-errors); the shared
 * libraries export exactly the functions the headers mark SDFT_API (the
 * scenes' none: they are a static component of their own), the static
 * ones define sdft_ names only for those and module-prefixed names for the
 * rest, and no installed header includes a private one; the core needs nothing but
 * OpenMP, libm and libc, and configures and builds with every other part
 * off; and an install, moved to another folder, serves an outside project
 * through find_package and through pkg-config, which build the README's
 * example and a grid loader, and run them. */
#define _POSIX_C_SOURCE 200809L /* strtok_r */
#include <ctype.h>
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sdftrace/config.h"
#include "testutil.h"

static char out[1 << 18];

/* ---- names ------------------------------------------------------------------- */

typedef struct names {
    char (*name)[128];
    size_t n, cap;
} names;

static void names_add(names *s, const char *name, size_t len)
{
    if (s->n == s->cap) {
        s->cap = s->cap ? 2 * s->cap : 256;
        s->name = realloc(s->name, s->cap * sizeof *s->name);
        assert_non_null(s->name);
    }
    snprintf(s->name[s->n++], sizeof s->name[0], "%.*s", (int)len, name);
}

static int names_has(const names *s, const char *name)
{
    for (size_t i = 0; i < s->n; i++)
        if (strcmp(s->name[i], name) == 0)
            return 1;
    return 0;
}

/* The public headers, from the folder itself (so a new one is covered). */
static names public_headers(void)
{
    names h = {0};
    DIR *d = opendir(SDFT_SOURCE_DIR "/include/sdftrace");
    assert_non_null(d);
    for (struct dirent *e; (e = readdir(d));) {
        size_t len = strlen(e->d_name);
        if (len > 2 && strcmp(e->d_name + len - 2, ".h") == 0)
            names_add(&h, e->d_name, len);
    }
    closedir(d);
    names_add(&h, "config.h", 8); /* generated from config.h.in */
    assert_true(h.n >= 10);
    return h;
}

/* The functions a header marks SDFT_API: the identifier before the first
 * '(' after each SDFT_API outside comments and #define lines. */
static void api_functions(const char *header, names *fns)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/include/sdftrace/%s", SDFT_SOURCE_DIR, header);
    char *text = tu_slurp(path);
    assert_non_null(text);
    for (char *c = text; *c; c++) { /* blank out comments */
        if (c[0] == '/' && c[1] == '*') {
            char *end = strstr(c + 2, "*/");
            assert_non_null(end);
            memset(c, ' ', (size_t)(end + 2 - c));
        }
    }
    for (const char *at = text; (at = strstr(at, "SDFT_API")); at += 8) {
        const char *line = at;
        while (line > text && line[-1] != '\n')
            line--;
        if (*line == '#')
            continue;
        const char *paren = strchr(at, '(');
        assert_non_null(paren);
        const char *end = paren;
        while (end > at && isspace((unsigned char)end[-1]))
            end--;
        const char *start = end;
        while (start > at && (isalnum((unsigned char)start[-1]) || start[-1] == '_'))
            start--;
        names_add(fns, start, (size_t)(end - start));
    }
    free(text);
}

/* ---- headers ----------------------------------------------------------------- */

static void test_headers_compile_alone_as_c_and_cxx(void **state)
{
    (void)state;
    names h = public_headers();
    for (size_t i = 0; i < h.n; i++) {
        char src[512];
        snprintf(src, sizeof src, "%s/header_%s.c", SDFT_TEST_TMP, h.name[i]);
        FILE *f = fopen(src, "w");
        assert_non_null(f);
        fprintf(f, "#include <sdftrace/%s>\nint main(void) { return 0; }\n", h.name[i]);
        fclose(f);
        static const char *const modes[2][2] = {{SDFT_CC, "-x c -std=c11"}, {SDFT_CXX, "-x c++ -std=c++17"}};
        for (int m = 0; m < 2; m++) {
            int rc = tu_run(out, sizeof out,
                            "%s %s -pedantic-errors -Wall -Wextra -Werror -fsyntax-only -I%s/include -I%s/include %s",
                            modes[m][0], modes[m][1], SDFT_SOURCE_DIR, SDFT_BUILD_DIR, src);
            if (rc)
                fail_msg("sdftrace/%s alone as %s: %s", h.name[i], modes[m][1], out);
        }
    }
    free(h.name);
}

/* ---- symbols ----------------------------------------------------------------- */

/* The dynamic symbols a shared library defines. */
static names exported(const char *lib)
{
    names s = {0};
    assert_int_equal(tu_run(out, sizeof out, "nm -D --defined-only %s", lib), 0);
    char *save = NULL;
    for (char *line = strtok_r(out, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        const char *name = strrchr(line, ' ');
        assert_non_null(name);
        names_add(&s, name + 1, strlen(name + 1));
    }
    return s;
}

/* Every function a public header declares at file scope (a line that
 * starts a declaration and names sdft_something followed by '(', not a
 * static inline definition or a typedef) carries SDFT_API, so that the
 * shared libraries export it: a declaration without it links against the
 * static library and fails against the shared one. */
static void test_every_declared_function_is_marked(void **state)
{
    (void)state;
    names h = public_headers();
    int declarations = 0;
    for (size_t i = 0; i < h.n; i++) {
        if (strcmp(h.name[i], "config.h") == 0)
            continue;
        char path[1024];
        snprintf(path, sizeof path, "%s/include/sdftrace/%s", SDFT_SOURCE_DIR, h.name[i]);
        char *text = tu_slurp(path);
        assert_non_null(text);
        for (char *c = text; *c; c++) /* blank out comments, keeping the lines */
            if (c[0] == '/' && c[1] == '*') {
                char *end = strstr(c + 2, "*/");
                assert_non_null(end);
                for (; c < end + 2; c++)
                    if (*c != '\n')
                        *c = ' ';
                c--;
            }
        char *save = NULL;
        for (char *line = strtok_r(text, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
            if (!isalpha((unsigned char)line[0]) || strncmp(line, "static", 6) == 0 || strncmp(line, "typedef", 7) == 0)
                continue;
            for (const char *at = line; (at = strstr(at, "sdft_")); at += 5) {
                if (at > line && (isalnum((unsigned char)at[-1]) || at[-1] == '_'))
                    continue;
                const char *end = at;
                while (isalnum((unsigned char)*end) || *end == '_')
                    end++;
                while (*end == ' ')
                    end++;
                if (*end != '(')
                    continue;
                declarations++;
                if (!strstr(line, "SDFT_API"))
                    fail_msg("sdftrace/%s declares %.*s without SDFT_API", h.name[i], (int)(strchr(at, '(') - at), at);
                break;
            }
        }
        free(text);
    }
    print_message("%d declarations, all marked\n", declarations);
    assert_true(declarations > 40);
    free(h.name);
}

static void test_shared_libraries_export_the_api(void **state)
{
    (void)state;
    names h = public_headers(), core_api = {0}, vdb_api = {0}, mesh_api = {0}, gpu_api = {0}, scene_api = {0};
    for (size_t i = 0; i < h.n; i++)
        if (strcmp(h.name[i], "config.h") != 0)
            api_functions(h.name[i], strcmp(h.name[i], "vdb.h") == 0     ? &vdb_api
                                     : strcmp(h.name[i], "mesh.h") == 0  ? &mesh_api
                                     : strcmp(h.name[i], "gpu.h") == 0   ? &gpu_api
                                     : strcmp(h.name[i], "scene.h") == 0 ? &scene_api
                                                                         : &core_api);
    assert_true(core_api.n > 40);
    assert_true(vdb_api.n >= 4);
    assert_true(mesh_api.n >= 10);
    assert_true(gpu_api.n >= 6);
    assert_true(scene_api.n >= 2); /* the scenes component's (static only): in neither shared library */
    char libs[] = SDFT_SHARED_LIBS;
    char *save = NULL;
    char *core_lib = strtok_r(libs, " ", &save), *vdb_lib = strtok_r(NULL, " ", &save);
    char *mesh_lib = strtok_r(NULL, " ", &save), *gpu_lib = strtok_r(NULL, " ", &save); /* NULL: no Vulkan */
    assert_non_null(mesh_lib);
    const struct {
        const char *lib;
        names *api;
    } pairs[4] = {{core_lib, &core_api}, {vdb_lib, &vdb_api}, {mesh_lib, &mesh_api}, {gpu_lib, &gpu_api}};
    for (int k = 0; k < 4 && pairs[k].lib; k++) {
        names e = exported(pairs[k].lib);
        for (size_t i = 0; i < e.n; i++)
            if (!names_has(pairs[k].api, e.name[i]))
                fail_msg("%s exports %s, which no public header marks SDFT_API", pairs[k].lib, e.name[i]);
        for (size_t i = 0; i < pairs[k].api->n; i++)
            if (!names_has(&e, pairs[k].api->name[i]))
                fail_msg("%s does not export %s", pairs[k].lib, pairs[k].api->name[i]);
        for (size_t i = 0; i < scene_api.n; i++)
            if (names_has(&e, scene_api.name[i]))
                fail_msg("%s exports %s: the scenes are a library of their own", pairs[k].lib, scene_api.name[i]);
        print_message("%s: %zu symbols, all public API\n", pairs[k].lib, e.n);
        free(e.name);
    }
    free(h.name), free(core_api.name), free(vdb_api.name), free(mesh_api.name), free(gpu_api.name),
        free(scene_api.name);
}

/* What an internal name may start with: its module. sdft_ is the public
 * API's alone. */
static const char *const internal_prefixes[] = {"grid_", "march_", "render_", "secondary_",  "vdb_",
                                                "gpu_",  "scene_", "fail_",   "atomic_file_"};

static int has_internal_prefix(const char *name)
{
    for (size_t i = 0; i < sizeof internal_prefixes / sizeof *internal_prefixes; i++)
        if (strncmp(name, internal_prefixes[i], strlen(internal_prefixes[i])) == 0)
            return 1;
    return 0;
}

/* Strong global symbols of the static libraries (weak ones are C++ template
 * instantiations from other projects' headers): an sdft_ name is a function
 * a public header marks SDFT_API; any other carries its module's prefix
 * (C++: lives in the sdft_vdb namespace). AddressSanitizer adds an
 * "__odr_asan." twin of each global, which is its instrumentation, not
 * ours. */
static void test_static_libraries_name_their_symbols(void **state)
{
    (void)state;
    names h = public_headers(), api = {0};
    for (size_t i = 0; i < h.n; i++)
        if (strcmp(h.name[i], "config.h") != 0)
            api_functions(h.name[i], &api);
    char libs[] = SDFT_STATIC_LIBS;
    int seen = 0, internal = 0;
    char *save_lib = NULL;
    for (char *lib = strtok_r(libs, " ", &save_lib); lib; lib = strtok_r(NULL, " ", &save_lib)) {
        assert_int_equal(tu_run(out, sizeof out, "nm -g -C --defined-only %s", lib), 0);
        char *save = NULL;
        for (char *line = strtok_r(out, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
            char addr[64], type[8];
            int used = 0;
            if (sscanf(line, "%63s %7s %n", addr, type, &used) != 2 || !used)
                continue; /* "member.o:" headers and blank lines */
            const char *name = line + used;
            if (strchr("WwVvu", type[0]) || strncmp(name, "__odr_asan.", 11) == 0)
                continue;
            seen++;
            if (strncmp(name, "sdft_vdb::", 10) == 0)
                continue;
            if (strncmp(name, "sdft_", 5) == 0) {
                if (!names_has(&api, name))
                    fail_msg("%s defines '%s' (%s): sdft_ is public, but no header marks it SDFT_API", lib, name, type);
            } else if (has_internal_prefix(name)) {
                internal++;
            } else {
                fail_msg("%s defines '%s' (%s), neither sdft_ nor a module's prefix", lib, name, type);
            }
        }
    }
    print_message("%d symbols, %d of them internal\n", seen, internal);
    assert_true(seen > 60);
    free(h.name), free(api.name);
}

/* An installed header includes only the C library's headers and its
 * siblings (sdftrace/NAME.h or "NAME.h" of include/sdftrace), never one of
 * src/: what it names must be installed too. */
static void test_installed_headers_include_only_installed_ones(void **state)
{
    (void)state;
    names h = public_headers();
    int includes = 0;
    for (size_t i = 0; i < h.n; i++) {
        char path[1024];
        if (strcmp(h.name[i], "config.h") == 0)
            snprintf(path, sizeof path, "%s/include/sdftrace/config.h.in", SDFT_SOURCE_DIR);
        else
            snprintf(path, sizeof path, "%s/include/sdftrace/%s", SDFT_SOURCE_DIR, h.name[i]);
        char *text = tu_slurp(path);
        assert_non_null(text);
        for (const char *at = text; (at = strstr(at, "#include")); at += 8) {
            const char *p = at + 8;
            while (*p == ' ')
                p++;
            const char close = *p == '<' ? '>' : '"';
            const char *end = strchr(p + 1, close);
            assert_non_null(end);
            char target[256];
            snprintf(target, sizeof target, "%.*s", (int)(end - p - 1), p + 1);
            includes++;
            if (close == '>') {
                if (strchr(target, '/'))
                    fail_msg("sdftrace/%s includes <%s>: only the C library's headers", h.name[i], target);
                continue;
            }
            const char *base = strncmp(target, "sdftrace/", 9) == 0 ? target + 9 : target;
            if (strchr(base, '/') || !names_has(&h, base))
                fail_msg("sdftrace/%s includes \"%s\", which is not installed", h.name[i], target);
        }
        free(text);
    }
    print_message("%d includes, all installed or the C library's\n", includes);
    assert_true(includes > 10);
    free(h.name);
}

/* libsdftrace.so needs OpenMP, libm and libc (and the sanitizers' runtimes
 * in a sanitized build), nothing else. */
static void test_core_needs_only_openmp_and_libm(void **state)
{
    (void)state;
    char libs[] = SDFT_SHARED_LIBS;
    char *save = NULL;
    const char *core = strtok_r(libs, " ", &save);
    assert_int_equal(tu_run(out, sizeof out, "readelf -d %s", core), 0);
    int needed = 0;
    for (char *line = strtok_r(out, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        const char *lib = strstr(line, "Shared library: [");
        if (!lib)
            continue;
        lib += strlen("Shared library: [");
        needed++;
        const int allowed =
            !strncmp(lib, "libgomp.so", 10) || !strncmp(lib, "libm.so", 7) || !strncmp(lib, "libc.so", 7) ||
            (SDFT_SANITIZE_FLAGS[0] && (!strncmp(lib, "libasan.so", 10) || !strncmp(lib, "libubsan.so", 11)));
        if (!allowed)
            fail_msg("libsdftrace.so needs %s", lib);
    }
    assert_true(needed >= 3);
}

/* With every optional part off, the project configures without looking for
 * OpenVDB, OpenEXR, libpng, OpenMesh or cmocka, and builds the core. */
static void test_core_builds_alone(void **state)
{
    (void)state;
    const char *dir = SDFT_TEST_TMP "/core-only";
    tu_run(NULL, 0, "rm -rf %s", dir);
    int rc =
        tu_run(out, sizeof out,
               "%s -S %s -B %s -DCMAKE_BUILD_TYPE=Debug -DSDFT_WITH_OPENVDB=OFF -DSDFT_WITH_IMAGES=OFF "
               "-DSDFT_WITH_OPENMESH=OFF -DSDFT_WITH_VULKAN=OFF -DSDFT_BUILD_TESTS=OFF && %s --build %s -j2 --target "
               "sdftrace sdftrace_static",
               SDFT_CMAKE, SDFT_SOURCE_DIR, dir, SDFT_CMAKE, dir);
    if (rc)
        fail_msg("core-only build: %s", out);
    char cache[512];
    snprintf(cache, sizeof cache, "%s/CMakeCache.txt", dir);
    char *text = tu_slurp(cache);
    assert_non_null(text);
    static const char *const never[] = {"\nOpenVDB_", "\nOpenEXR_DIR", "\nOpenMesh_DIR",
                                        "\nPNG_",     "\ncmocka_DIR",  "\nSDFT_WITH_VULKAN:BOOL=ON"};
    for (size_t i = 0; i < sizeof never / sizeof never[0]; i++)
        if (strstr(text, never[i]))
            fail_msg("the core-only configuration looked for %s", never[i] + 1);
    free(text);
    tu_run(NULL, 0, "rm -rf %s", dir);
}

/* ---- install and consume ------------------------------------------------------- */

/* The project's version, read from CMakeLists.txt: "project(sdftrace VERSION x.y.z". */
static void project_version(char *v, size_t len)
{
    char *text = tu_slurp(SDFT_SOURCE_DIR "/CMakeLists.txt");
    assert_non_null(text);
    const char *at = strstr(text, "project(sdftrace VERSION ");
    assert_non_null(at);
    at += strlen("project(sdftrace VERSION ");
    size_t n = strspn(at, "0123456789.");
    snprintf(v, len, "%.*s", (int)n, at);
    free(text);
}

/* Runs the command fmt (on a, b, c); fails with `what` and the output when
 * it fails or its output lacks `needle` (NULL: anything). */
static void must_run(const char *what, const char *needle, const char *fmt, const char *a, const char *b, const char *c)
{
    int rc = tu_run(out, sizeof out, fmt, a, b, c);
    if (rc || (needle && !strstr(out, needle)))
        fail_msg("%s (exit %d): %s", what, rc, out);
}

/* Configures and builds the outside project in `src` against the install
 * at `prefix`, into `build`, with this build's sanitizers. */
static void build_consumer(const char *src, const char *build, const char *prefix)
{
    char cmd[4 * 4096]; /* three paths of up to 4096 bytes and the flags */
    const int n = snprintf(cmd, sizeof cmd,
                           "%s -S %s -B %s -DCMAKE_BUILD_TYPE=Debug -DCMAKE_PREFIX_PATH=%s '-DCMAKE_C_FLAGS=%s' "
                           "'-DCMAKE_CXX_FLAGS=%s' '-DCMAKE_EXE_LINKER_FLAGS=%s' && %s --build %s",
                           SDFT_CMAKE, src, build, prefix, SDFT_SANITIZE_FLAGS, SDFT_SANITIZE_FLAGS,
                           SDFT_SANITIZE_FLAGS, SDFT_CMAKE, build);
    assert_true(n > 0 && (size_t)n < sizeof cmd);
    must_run("build the consumer", NULL, "%s%s%s", cmd, "", "");
}

/* A program linked without libsdftrace*.so: the static libraries served. */
static void linked_statically(const char *program)
{
    must_run("readelf", NULL, "readelf -d %s%s%s", program, "", "");
    if (strstr(out, "libsdftrace"))
        fail_msg("%s needs a shared sdftrace: %s", program, out);
}

static void test_install_and_consume(void **state)
{
    (void)state;
    const char *tmp = SDFT_TEST_TMP "/package";
    char first[512], moved[512], cmd[4096], version[32], soname[64];
    snprintf(first, sizeof first, "%s/first", tmp);
    snprintf(moved, sizeof moved, "%s/moved", tmp);
    tu_run(NULL, 0, "rm -rf %s && mkdir -p %s", tmp, tmp);
    project_version(version, sizeof version);

    /* Install from this build, then move the whole tree: a relocatable
     * package works from wherever it lands. */
    must_run("install", NULL, "%s --install %s --prefix %s", SDFT_CMAKE, SDFT_BUILD_DIR, first);
    must_run("move", NULL, "mv %s %s%s", first, moved, "");
    names h = public_headers();
    for (size_t i = 0; i < h.n; i++) {
        snprintf(cmd, sizeof cmd, "%s/include/sdftrace/%s", moved, h.name[i]);
        if (!tu_file_exists(cmd))
            fail_msg("not installed: %s", cmd);
    }
    free(h.name);
    /* The soname: libsdftrace.so.MAJOR, or .0.MINOR while MAJOR is 0. */
    int major = atoi(version), minor = atoi(strchr(version, '.') + 1);
    if (major == 0)
        snprintf(soname, sizeof soname, "libsdftrace.so.0.%d", minor);
    else
        snprintf(soname, sizeof soname, "libsdftrace.so.%d", major);
    static const char *const files[] = {"lib/libsdftrace.a",
                                        "lib/libsdftrace.so",
                                        "lib/libsdftrace_vdb.a",
                                        "lib/libsdftrace_vdb.so",
                                        "lib/libsdftrace_scenes.a",
                                        "lib/cmake/sdftrace/sdftraceConfig.cmake",
                                        "lib/pkgconfig/sdftrace.pc",
                                        "lib/pkgconfig/sdftrace_vdb.pc",
                                        "bin/sdftrace",
                                        "bin/mesh2sdf"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        snprintf(cmd, sizeof cmd, "%s/%s", moved, files[i]);
        if (!tu_file_exists(cmd))
            fail_msg("not installed: %s", cmd);
    }
    snprintf(cmd, sizeof cmd, "Library soname: [%s]", soname);
    must_run("soname", cmd, "readelf -d %s/lib/libsdftrace.so%s%s", moved, "", "");
    snprintf(cmd, sizeof cmd, "%s/lib/%s", moved, soname);
    assert_true(tu_file_exists(cmd));
    /* The OpenVDB component finds the core beside itself. */
    must_run("runpath", "[$ORIGIN]", "readelf -d %s/lib/libsdftrace_vdb.so%s%s", moved, "", "");

    /* The installed tools say the project's version. */
    static const char *const tools[] = {"sdftrace", "mesh2sdf"};
    for (int t = 0; t < 2; t++) {
        char want[64];
        snprintf(want, sizeof want, "%s %s\n", tools[t], version);
        must_run("--version", want, "%s/bin/%s --version%s", moved, tools[t], "");
    }
    /* A grid for the loader, baked by the installed tool. */
    must_run("bake", NULL, "%s/bin/sdftrace bake --scene dodecahedron --res 32 -o %s/dodeca.vdb%s", moved, tmp, "");

    /* find_package: tests/consumer, with the README's example as my_sdf.c;
     * the shared OpenVDB component loads, and bakes (a ball of radius 1:
     * the ray meets it at y = 1, within a voxel of 2.2 / 32). */
    must_run("copy the consumer", NULL, "cp -r %s/tests/consumer %s/consumer%s", SDFT_SOURCE_DIR, tmp, "");
    must_run("copy the example", NULL, "cp %s/tests/readme_example.c %s/consumer/my_sdf.c%s", SDFT_SOURCE_DIR, tmp, "");
    snprintf(cmd, sizeof cmd, "%s/consumer", tmp);
    char build[512];
    snprintf(build, sizeof build, "%s/consumer-build", tmp);
    build_consumer(cmd, build, moved);
    must_run("my_sdf (find_package)", "t = 1.9861 after", "%s/my_sdf%s%s", build, "", "");
    must_run("my_grid (find_package)", "hits", "%s/my_grid %s/dodeca.vdb%s", build, tmp, "");
    must_run("my_grid --bake (find_package)", "hits at y = ", "%s/my_grid --bake %s/ball.vdb%s", build, tmp, "");
    assert_true(fabs(atof(strstr(out, "hits at y = ") + 12) - 1.0) <= 0.07);

    /* The static component: OpenVDB found through find_dependency. */
    snprintf(cmd, sizeof cmd, "%s/consumer/static", tmp);
    snprintf(build, sizeof build, "%s/static-build", tmp);
    build_consumer(cmd, build, moved);
    must_run("my_grid_static --bake", "hits", "%s/my_grid_static --bake %s/ball_static.nvdb%s", build, tmp, "");
    snprintf(cmd, sizeof cmd, "%s/my_grid_static", build);
    linked_statically(cmd);

    /* pkg-config: the same programs, the command lines of the README, plus
     * the sanitizers when this build has them and an rpath to the install;
     * and the core linked statically (--static adds OpenMP). */
    snprintf(
        cmd, sizeof cmd,
        "export PKG_CONFIG_PATH=%s/lib/pkgconfig && cd %s/consumer && "
        "cc %s -std=c11 my_sdf.c $(pkg-config --cflags --libs sdftrace) -lm -Wl,-rpath,%s/lib -o my_sdf_pc && "
        "cc %s -std=c11 my_grid.c $(pkg-config --cflags --libs sdftrace_vdb) -Wl,-rpath,%s/lib -o my_grid_pc && "
        "cc %s -std=c11 my_sdf.c $(pkg-config --cflags sdftrace) $(pkg-config --libs-only-L sdftrace) "
        "-Wl,-Bstatic -lsdftrace -Wl,-Bdynamic $(pkg-config --static --libs-only-other sdftrace) -lm -o my_sdf_static",
        moved, tmp, SDFT_SANITIZE_FLAGS, moved, SDFT_SANITIZE_FLAGS, moved, SDFT_SANITIZE_FLAGS);
    must_run("pkg-config consumer", NULL, "%s%s%s", cmd, "", "");
    must_run("my_sdf (pkg-config)", "t = 1.9861 after", "%s/consumer/my_sdf_pc%s%s", tmp, "", "");
    must_run("my_grid --bake (pkg-config)", "hits", "%s/consumer/my_grid_pc --bake %s/ball.nvdb%s", tmp, tmp, "");
    must_run("my_sdf (static)", "t = 1.9861 after", "%s/consumer/my_sdf_static%s%s", tmp, "", "");
    snprintf(cmd, sizeof cmd, "%s/consumer/my_sdf_static", tmp);
    linked_statically(cmd);
    tu_run(NULL, 0, "rm -rf %s", tmp);
}

/* The README shows the consumer's CMakeLists.txt as it is. */
static void test_readme_shows_the_consumer(void **state)
{
    (void)state;
    assert_true(tu_readme_shows("tests/consumer/CMakeLists.txt"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_headers_compile_alone_as_c_and_cxx),
        cmocka_unit_test(test_every_declared_function_is_marked),
        cmocka_unit_test(test_shared_libraries_export_the_api),
        cmocka_unit_test(test_static_libraries_name_their_symbols),
        cmocka_unit_test(test_installed_headers_include_only_installed_ones),
        cmocka_unit_test(test_core_needs_only_openmp_and_libm),
        cmocka_unit_test(test_core_builds_alone),
        cmocka_unit_test(test_install_and_consume),
        cmocka_unit_test(test_readme_shows_the_consumer),
    };
    return cmocka_run_group_tests_name("package", tests, NULL, NULL);
}
