/* sdftrace tests — files from strangers and hostile sizes. For every format
 * the tools read (.vdb, .nvdb through `sdftrace render --grid`; OBJ, PLY
 * ASCII and binary, OFF, STL ASCII and binary, .om, GLB, glTF, Collada,
 * 3MF, FBX through mesh2sdf; .npy query points through --query): a
 * zero-length file, the file cut at every 1/16 of its length and a header
 * claiming absurd counts each give one line on stderr naming the file, a
 * non-zero exit and no output file (a cut text mesh may still be a whole
 * mesh: then it converts). Sizes that would need more memory than the
 * machine allows are refused with the estimate; the estimates are held
 * against the measured peak (/usr/bin/time) within 25%. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include <cmocka.h>

#include "memory_limit.h"
#include "testutil.h"

static char out[1 << 16];

typedef struct format {
    const char *name;
    const char *seed; /* under tests/fuzz/corpus */
    int prefixed;     /* the mesh harness's leading format byte */
    const char *ext;
    int text; /* a cut file may still be a whole mesh */
} format;

static const format FORMATS[] = {
    {"vdb", "vdb/dodecahedron_res6.vdb", 0, ".vdb", 0},
    {"vdb-half", "vdb/figure_res6_half.vdb", 0, ".vdb", 0},
    {"nvdb", "nvdb/dodecahedron_res4.nvdb", 0, ".nvdb", 0},
    {"obj", "mesh/suzanne.obj", 1, ".obj", 1},
    {"ply-ascii", "mesh/suzanne_ascii.ply", 1, ".ply", 1},
    {"ply-binary", "mesh/suzanne_binary.ply", 1, ".ply", 0},
    {"off", "mesh/suzanne.off", 1, ".off", 1},
    {"stl-ascii", "mesh/suzanne_ascii.stl", 1, ".stl", 1},
    {"stl-binary", "mesh/suzanne_binary.stl", 1, ".stl", 0},
    {"om", "mesh/suzanne.om", 1, ".om", 0},
    {"glb", "../seeds/tetra.glb", 0, ".glb", 0},
    {"gltf", "../seeds/tetra.gltf", 0, ".gltf", 0},
    {"dae", "../seeds/tetra.dae", 0, ".dae", 0},
    {"3mf", "../seeds/tetra.3mf", 0, ".3mf", 0},
    {"fbx", "../seeds/boxes.fbx", 0, ".fbx", 1},
    {"npy", "npy/points_f4_C_v1.npy", 0, ".npy", 0},
};

/* The seed's bytes (without the harness's prefix); *size set. */
static unsigned char *seed_bytes(const format *f, size_t *size)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/fuzz/corpus/%s", SDFT_SOURCE_DIR, f->seed);
    FILE *in = fopen(path, "rb");
    assert_non_null(in);
    fseek(in, 0, SEEK_END);
    const long n = ftell(in);
    fseek(in, 0, SEEK_SET);
    unsigned char *data = malloc((size_t)n + 1);
    assert_int_equal(fread(data, 1, (size_t)n, in), (size_t)n);
    fclose(in);
    *size = (size_t)n - (size_t)f->prefixed;
    if (f->prefixed)
        memmove(data, data + 1, *size);
    return data;
}

static void write_file(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(size ? fwrite(data, 1, size, f) : 0, size);
    assert_int_equal(fclose(f), 0);
}

static int is_grid(const format *f) { return strstr(f->ext, "vdb") != NULL; }
static int is_points(const format *f) { return strcmp(f->ext, ".npy") == 0; }

/* Runs the format's tool on `in`; its exit status, output in `out`. */
static int run_tool(const format *f, const char *in, const char *result)
{
    remove(result);
    if (is_grid(f))
        return tu_run(out, sizeof out, "%s render --grid '%s' -o '%s' --width 16 --height 12 --quiet 2>&1", SDFT_CLI,
                      in, result);
    if (is_points(f)) /* query points for a mesh */
        return tu_run(out, sizeof out, "%s '%s/spot.obj' --query '%s' '%s' --quiet 2>&1", SDFT_MESH2SDF, SDFT_MESH_DIR,
                      in, result);
    return tu_run(out, sizeof out, "%s '%s' -o '%s' --res 16 --quiet 2>&1", SDFT_MESH2SDF, in, result);
}

/* A clean refusal: non-zero exit, one line naming the file, no output. */
static void assert_clean_error(int rc, const char *in, const char *result, const char *what)
{
    if (rc == 0 || tu_lines(out) != 1 || !strstr(out, in) || tu_file_exists(result))
        fail_msg("%s: exit %d, output %s, message: %s", what, rc, tu_file_exists(result) ? "written" : "none", out);
}

static void check_bytes(const format *f, const unsigned char *data, size_t size, const char *what, int may_succeed)
{
    char in[1024], result[1024], name[64];
    snprintf(name, sizeof name, "untrusted%s", f->ext);
    tu_tmp(in, sizeof in, name);
    tu_tmp(result, sizeof result,
           is_grid(f)     ? "untrusted_out.exr"
           : is_points(f) ? "untrusted_out.npy"
                          : "untrusted_out.vdb");
    write_file(in, data, size);
    const int rc = run_tool(f, in, result);
    if (rc == 0 && may_succeed && tu_file_exists(result))
        return;
    assert_clean_error(rc, in, result, what);
}

/* The seed itself converts: a refusal below is the cut's doing. */
static void test_seeds_convert(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof FORMATS / sizeof FORMATS[0]; i++) {
        size_t size;
        unsigned char *data = seed_bytes(&FORMATS[i], &size);
        char in[1024], result[1024], name[64];
        snprintf(name, sizeof name, "seed%s", FORMATS[i].ext);
        tu_tmp(in, sizeof in, name);
        tu_tmp(result, sizeof result, is_grid(&FORMATS[i]) ? "seed_out.exr" : "seed_out.vdb");
        write_file(in, data, size);
        if (run_tool(&FORMATS[i], in, result) != 0 || !tu_file_exists(result))
            fail_msg("%s: the seed does not convert: %s", FORMATS[i].name, out);
        free(data);
    }
}

static void test_zero_length_and_cut_files(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof FORMATS / sizeof FORMATS[0]; i++) {
        const format *f = &FORMATS[i];
        size_t size;
        unsigned char *data = seed_bytes(f, &size);
        for (int k = 0; k < 16; k++) {
            char what[64];
            snprintf(what, sizeof what, "%s cut at %d/16", f->name, k);
            check_bytes(f, data, size * (size_t)k / 16, what, k > 0 && f->text);
        }
        free(data);
    }
}

/* Headers claiming 2^40 elements (or a grid of 2^40 bytes), each refused
 * at once: the run must end well before such an allocation could. */
static void test_absurd_counts(void **state)
{
    (void)state;
    static const char *const text[][2] = {
        {"ply-ascii", "ply\nformat ascii 1.0\nelement vertex 1099511627776\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"ply-binary", "ply\nformat binary_little_endian 1.0\nelement vertex 1099511627776\nproperty float x\n"
                       "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                       "end_header\n"},
        {"off", "OFF\n1099511627776 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1099511627776\n"},
    };
    for (size_t i = 0; i < sizeof FORMATS / sizeof FORMATS[0]; i++) {
        const format *f = &FORMATS[i];
        for (size_t t = 0; t < sizeof text / sizeof text[0]; t++)
            if (strcmp(text[t][0], f->name) == 0)
                check_bytes(f, (const unsigned char *)text[t][1], strlen(text[t][1]), f->name, 0);
        size_t size;
        unsigned char *data = seed_bytes(f, &size);
        int patched = 1;
        if (strcmp(f->name, "stl-binary") == 0) /* the triangle count after the 80-byte header */
            memset(data + 80, 0xFF, 4);
        else if (strcmp(f->name, "om") == 0) /* vertex, face and edge counts after the 4-byte preamble */
            memset(data + 4, 0x7F, 12);
        else if (strcmp(f->name, "nvdb") == 0) /* the grid's and the file's byte sizes after the file header */
            memset(data + 16, 0x7F, 16);
        else if (is_grid(f)) /* the metadata count after the 57-byte file header */
            memset(data + 57, 0x7F, 4);
        else
            patched = 0;
        if (patched)
            check_bytes(f, data, size, f->name, 0);
        free(data);
    }
}

/* mesh2sdf --check-sign reads .vdb files too: each input that crashed
 * OpenVDB's reader is one line and a non-zero exit. */
static void test_check_sign_on_corrupt_grids(void **state)
{
    (void)state;
    static const char *const names[] = {"openvdb-segfault-1", "openvdb-segfault-2", "openvdb-huge-allocation",
                                        "openvdb-assert-delayed-load-mask", "openvdb-huge-metadata-string"};
    char mesh[1024];
    snprintf(mesh, sizeof mesh, "%s/suzanne.obj", SDFT_MESH_DIR);
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        const int rc =
            tu_run(out, sizeof out, "%s '%s' --check-sign '%s/tests/fuzz/regressions/vdb/%s' --check-points 100 2>&1",
                   SDFT_MESH2SDF, mesh, SDFT_SOURCE_DIR, names[i]);
        if (rc != 0 && tu_lines(out) != 1)
            fail_msg("--check-sign %s: exit %d: %s", names[i], rc, out);
        if (rc == 0 && strstr(out, "wrong=") == NULL) /* a mutation OpenVDB reads through is a grid */
            fail_msg("--check-sign %s: exit 0 without a result: %s", names[i], out);
    }
}

/* A truncated .vdb is refused before OpenVDB reads past its end (where it
 * would read lengths it never got, and fail differently on each run): by
 * --check-sign as by the loader, the same line every time. */
static void test_check_sign_on_truncated_grid(void **state)
{
    (void)state;
    char mesh[1024], whole[1024], cut[1024];
    snprintf(mesh, sizeof mesh, "%s/suzanne.obj", SDFT_MESH_DIR);
    tu_tmp(whole, sizeof whole, "check-sign-whole.vdb");
    tu_tmp(cut, sizeof cut, "check-sign-cut.vdb");
    assert_int_equal(tu_run(out, sizeof out, "%s '%s' -o '%s' --res 32 --quiet 2>&1 && head -c 600 '%s' > '%s'",
                            SDFT_MESH2SDF, mesh, whole, whole, cut),
                     0);
    for (int run = 0; run < 2; run++) {
        const int rc =
            tu_run(out, sizeof out, "%s '%s' --check-sign '%s' --check-points 100 2>&1", SDFT_MESH2SDF, mesh, cut);
        if (rc == 0 || tu_lines(out) != 1 || !strstr(out, "but the file ends at byte 600"))
            fail_msg("--check-sign on a truncated .vdb: exit %d: %s", rc, out);
    }
}

/* Sizes past the machine: each refused before allocating, the estimate in
 * the line. SDFT_MEMORY_LIMIT stands in for a small machine. */
static void test_hostile_sizes_refused(void **state)
{
    (void)state;
    char in[1024], result[1024];
    snprintf(in, sizeof in, "%s/suzanne.obj", SDFT_MESH_DIR);
    tu_tmp(result, sizeof result, "hostile.vdb");
    const char *const mesh_cases[] = {"--res 4096", "--res 1024 --full", "--voxel-size 0.001", "--res 1024 --band 100"};
    for (size_t i = 0; i < sizeof mesh_cases / sizeof mesh_cases[0]; i++) {
        remove(result);
        const int rc = tu_run(out, sizeof out, "SDFT_MEMORY_LIMIT=200000000 %s '%s' -o '%s' %s --quiet 2>&1",
                              SDFT_MESH2SDF, in, result, mesh_cases[i]);
        if (rc == 0 || tu_lines(out) != 1 || !strstr(out, "needs ~") || tu_file_exists(result))
            fail_msg("mesh2sdf %s: exit %d: %s", mesh_cases[i], rc, out);
    }
    int rc = tu_run(out, sizeof out,
                    "SDFT_MEMORY_LIMIT=200000000 %s '%s' --check-sign /dev/null --check-points 100000000 2>&1",
                    SDFT_MESH2SDF, in);
    if (rc == 0 || tu_lines(out) != 1 || !strstr(out, "needs ~"))
        fail_msg("--check-points: exit %d: %s", rc, out);
    tu_tmp(result, sizeof result, "hostile.npy");
    remove(result);
    rc = tu_run(out, sizeof out, "SDFT_MEMORY_LIMIT=200000000 %s '%s' --samples 100000000 '%s' 2>&1", SDFT_MESH2SDF, in,
                result);
    if (rc == 0 || tu_lines(out) != 1 || !strstr(out, "needs ~") || tu_file_exists(result))
        fail_msg("--samples: exit %d: %s", rc, out);
    tu_tmp(result, sizeof result, "hostile.exr");
    remove(result);
    rc = tu_run(out, sizeof out,
                "SDFT_MEMORY_LIMIT=1000000000 %s render --scene dodecahedron --width 8000 --height 8000 -o '%s' 2>&1",
                SDFT_CLI, result);
    if (rc == 0 || tu_lines(out) != 1 || !strstr(out, "needs ~3.9 GiB") || tu_file_exists(result))
        fail_msg("render 8000x8000: exit %d: %s", rc, out);
    tu_tmp(result, sizeof result, "hostile.nvdb");
    remove(result);
    rc = tu_run(out, sizeof out, "SDFT_MEMORY_LIMIT=200000000 %s bake --scene city --res 1024 --full -o '%s' 2>&1",
                SDFT_CLI, result);
    if (rc == 0 || tu_lines(out) != 1 || !strstr(out, "needs ~") || tu_file_exists(result))
        fail_msg("bake --res 1024 --full: exit %d: %s", rc, out);
}

/* The address-space limit (ulimit -v) counts as the machine's size. */
static void test_limit_follows_rlimit_as(void **state)
{
    (void)state;
    struct rlimit old;
    assert_int_equal(getrlimit(RLIMIT_AS, &old), 0);
    const rlim_t three = (rlim_t)3 << 30;
    if (old.rlim_max != RLIM_INFINITY && old.rlim_max < three)
        skip();
    struct rlimit lower = {three, old.rlim_max};
    assert_int_equal(setrlimit(RLIMIT_AS, &lower), 0);
    const uint64_t seen = memory_limit_bytes(); /* nothing allocated while the limit is low */
    assert_int_equal(setrlimit(RLIMIT_AS, &old), 0);
    assert_true(seen <= (uint64_t)three); /* equal, or the physical memory where that is smaller */
    assert_true(seen > 0);
}

/* The estimate a tool states (forced out with a 1-byte limit), in bytes. */
static double stated_estimate(const char *command)
{
    tu_run(out, sizeof out, "SDFT_MEMORY_LIMIT=1 %s 2>&1", command);
    const char *at = strstr(out, "needs ~");
    assert_non_null(at);
    double v;
    char unit[8];
    assert_int_equal(sscanf(at, "needs ~%lf %3s", &v, unit), 2);
    return v * (strcmp(unit, "GiB") == 0 ? 1024.0 * 1024.0 * 1024.0 : 1024.0 * 1024.0);
}

/* The peak resident set /usr/bin/time measures for command, in bytes. */
static double measured_peak(const char *command)
{
    char file[1024];
    tu_tmp(file, sizeof file, "peak.txt");
    assert_int_equal(tu_run(NULL, 0, "/usr/bin/time -f %%M -o '%s' %s >/dev/null 2>&1", file, command), 0);
    char *text = tu_slurp(file);
    assert_non_null(text);
    const double kib = atof(text);
    free(text);
    return kib * 1024.0;
}

/* Each tool's estimate within 25% of the peak it reaches. Sanitizers
 * (make test) change every allocation's size: there the check is skipped. */
static void test_estimates_match_measured_peaks(void **state)
{
    (void)state;
    if (SDFT_SANITIZE_FLAGS[0] || !tu_file_exists("/usr/bin/time"))
        skip();
    char mesh[1024], vdb[1024], exr[1024], cmd[4][4096];
    snprintf(mesh, sizeof mesh, "%s/spot.obj", SDFT_MESH_DIR);
    tu_tmp(vdb, sizeof vdb, "peak.vdb");
    tu_tmp(exr, sizeof exr, "peak.exr");
    snprintf(cmd[0], sizeof cmd[0],
             "%s render --scene dodecahedron --width 2048 --height 2048 --max-steps 4 -o '%s' --quiet", SDFT_CLI, exr);
    snprintf(cmd[1], sizeof cmd[1], "%s '%s' -o '%s' --res 1024 --quiet", SDFT_MESH2SDF, mesh, vdb);
    snprintf(cmd[2], sizeof cmd[2], "%s '%s' -o '%s' --res 256 --full --quiet", SDFT_MESH2SDF, mesh, vdb);
    snprintf(cmd[3], sizeof cmd[3], "%s bake --scene dodecahedron --res 512 --full -o '%s' --quiet", SDFT_CLI, vdb);
    for (int i = 0; i < 4; i++) {
        const double stated = stated_estimate(cmd[i]), peak = measured_peak(cmd[i]);
        print_message("estimate %.0f MiB, measured %.0f MiB: %s\n", stated / 1048576.0, peak / 1048576.0, cmd[i]);
        if (stated < 0.75 * peak || stated > 1.25 * peak)
            fail_msg("estimate %.0f MiB against a measured peak of %.0f MiB: %s", stated / 1048576.0, peak / 1048576.0,
                     cmd[i]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_seeds_convert),
        cmocka_unit_test(test_zero_length_and_cut_files),
        cmocka_unit_test(test_absurd_counts),
        cmocka_unit_test(test_check_sign_on_corrupt_grids),
        cmocka_unit_test(test_check_sign_on_truncated_grid),
        cmocka_unit_test(test_hostile_sizes_refused),
        cmocka_unit_test(test_limit_follows_rlimit_as),
        cmocka_unit_test(test_estimates_match_measured_peaks),
    };
    return cmocka_run_group_tests_name("untrusted", tests, NULL, NULL);
}
