/* Tests of a grid's materials (src/grid/grid_material.c, `sdftrace bake
 * --materials`, `render --grid`): the jewel baked with its materials holds
 * the materials the scene's own material function gives, the grid's field
 * answers that function's material at every surface point clear of a
 * material's edge, and the jewel rendered from the grid looks like the
 * procedural one; the convex optimization is refused on a grid. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <math.h>

#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "sdftrace/vdb.h"
#include "testutil.h"

static char out[16384];
enum { RES = 384 };

static int same_material(sdft_material a, sdft_material b)
{
    return a.colour.x == b.colour.x && a.colour.y == b.colour.y && a.colour.z == b.colour.z &&
           a.reflectance == b.reflectance && a.ior == b.ior;
}

/* The jewel baked with its materials into `file` (once per run), and its
 * three grids opened: the surface with its materials set. */
typedef struct baked {
    sdft_grid *surface, *ids, *table;
    sdft_material materials[SDFT_GRID_MAX_MATERIALS];
    size_t count;
    float voxel;
} baked;

static void open_baked(baked *b, const char *file)
{
    char path[512], msg[256];
    tu_tmp(path, sizeof path, file);
    const sdft_scene *sc = sdft_scene_find("jewel");
    if (!tu_file_exists(path)) {
        sdft_bake_params p = sdft_bake_defaults();
        p.res = RES, p.materials = 1, p.grid_name = "jewel";
        if (sdft_bake(&sc->field, &p, path, NULL, NULL, msg, sizeof msg))
            fail_msg("bake: %s", msg);
    }
    memset(b, 0, sizeof *b);
    assert_int_equal(tu_open_file(path, "jewel", SDFT_QUANT_NONE, &b->surface, msg, sizeof msg), SDFT_OK);
    assert_int_equal(tu_open_file(path, "jewel.material_ids", SDFT_QUANT_NONE, &b->ids, msg, sizeof msg), SDFT_OK);
    assert_int_equal(tu_open_file(path, "jewel.material_table", SDFT_QUANT_NONE, &b->table, msg, sizeof msg), SDFT_OK);
    assert_int_equal(
        sdft_grid_material_table(b->table, b->materials, SDFT_GRID_MAX_MATERIALS, &b->count, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_grid_set_materials(b->surface, b->ids, b->materials, b->count, msg, sizeof msg), SDFT_OK);
    b->voxel = sdft_grid_voxel_size(b->surface).x;
}

static void close_baked(baked *b)
{
    sdft_grid_free(b->surface);
    sdft_grid_free(b->ids);
    sdft_grid_free(b->table);
}

/* Points on the jewel's surface: primary hits of its camera's rays through
 * random pixels, traced on the procedural field. */
static int surface_points(sdft_vec3 *p, int most, uint64_t seed)
{
    const sdft_scene *sc = sdft_scene_find("jewel");
    sdft_scratch s;
    sdft_scratch_init(&sc->field, &s);
    const sdft_trace_params tp = sdft_trace_defaults();
    tu_rng rng = tu_rng_seed(seed);
    int n = 0;
    for (int k = 0; k < 4 * most && n < most; k++) {
        const sdft_ray ray = sdft_camera_ray(&sc->camera, 640, 360, tu_uniform(&rng, 0, 640), tu_uniform(&rng, 0, 360));
        const sdft_hit h = sdft_trace(&sc->field, &s, &ray, &tp);
        if (h.status == SDFT_HIT)
            p[n++] = sdft_madd(ray.org, ray.dir, h.t);
    }
    return n;
}

/* The table holds exactly the distinct materials the scene's function
 * gives on its surface. */
static void test_table_is_the_scenes_materials(void **state)
{
    (void)state;
    baked b;
    open_baked(&b, "jewel-materials.nvdb");
    const sdft_scene *sc = sdft_scene_find("jewel");
    enum { N = 4000 };
    static sdft_vec3 p[N];
    const int n = surface_points(p, N, 3);
    sdft_material seen[16];
    int kinds = 0;
    for (int i = 0; i < n; i++) {
        const sdft_material m = sc->field.material(sc->field.ctx, p[i]);
        int k = 0;
        while (k < kinds && !same_material(seen[k], m))
            k++;
        if (k == kinds && kinds < 16)
            seen[kinds++] = m;
    }
    assert_int_equal(kinds, 5); /* glass, the red bead, the mirror, the checker's two squares */
    assert_int_equal(b.count, (size_t)kinds);
    for (int k = 0; k < kinds; k++) {
        size_t j = 0;
        while (j < b.count && !same_material(b.materials[j], seen[k]))
            j++;
        if (j == b.count)
            fail_msg("the table lacks material %d (colour %g %g %g)", k, seen[k].colour.x, seen[k].colour.y,
                     seen[k].colour.z);
    }
    close_baked(&b);
}

/* Wherever the scene's material is the same over the cube of a voxel
 * around a surface point (so no edge of a material passes within a voxel),
 * the grid's field answers it. */
static void test_material_at_surface_points(void **state)
{
    (void)state;
    baked b;
    open_baked(&b, "jewel-materials.nvdb");
    const sdft_scene *sc = sdft_scene_find("jewel");
    const sdft_field f = sdft_grid_field(b.surface, SDFT_GRID_BOUND_FAR);
    assert_non_null(f.material);
    enum { N = 3000 };
    static sdft_vec3 p[N];
    const int n = surface_points(p, N, 5);
    int clear = 0, edges = 0;
    for (int i = 0; i < n; i++) {
        const sdft_material m = sc->field.material(sc->field.ctx, p[i]);
        int uniform = 1;
        for (int d = 0; d < 27 && uniform; d++) {
            const sdft_vec3 q = sdft_add(
                p[i], sdft_scale(sdft_v3((float)(d % 3 - 1), (float)(d / 3 % 3 - 1), (float)(d / 9 - 1)), b.voxel));
            uniform = same_material(sc->field.material(sc->field.ctx, q), m);
        }
        if (!uniform) {
            edges++;
            continue;
        }
        clear++;
        const sdft_material g = f.material(f.ctx, p[i]);
        if (!same_material(g, m))
            fail_msg("at (%g, %g, %g): the grid gives colour %g %g %g, the scene %g %g %g", p[i].x, p[i].y, p[i].z,
                     g.colour.x, g.colour.y, g.colour.z, m.colour.x, m.colour.y, m.colour.z);
    }
    print_message("%d surface points clear of a material's edge agree, %d near one skipped\n", clear, edges);
    assert_true(clear > n * 3 / 4);
    close_baked(&b);
}

/* The sRGB byte of a linear value, as the PNG preview writes it. */
static int srgb8(float linear)
{
    const float c = fminf(fmaxf(linear, 0.0f), 1.0f);
    const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * powf(c, 1.0f / 2.4f) - 0.055f;
    return (int)(255.0f * s + 0.5f);
}

/* The share of pixels of f's image, rendered with its materials, that
 * differ from the procedural jewel's by more than 16/255 in a channel. */
static double share_changed(const sdft_field *f)
{
    const sdft_scene *sc = sdft_scene_find("jewel");
    sdft_render_params p = sdft_render_defaults();
    p.width = 96, p.height = 54, p.camera = sc->camera, p.light = sc->light, p.materials = 1, p.threads = 2;
    sdft_image a, g;
    char msg[256];
    assert_int_equal(sdft_image_alloc(&a, p.width, p.height, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_image_alloc(&g, p.width, p.height, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_render(&sc->field, &p, &a, NULL, msg, sizeof msg), SDFT_OK);
    assert_int_equal(sdft_render(f, &p, &g, NULL, msg, sizeof msg), SDFT_OK);
    int changed = 0;
    for (int i = 0; i < p.width * p.height; i++) {
        int d = 0;
        for (int c = 0; c < 3; c++)
            d = (int)fmax(d, abs(srgb8(a.rgb[3 * i + c]) - srgb8(g.rgb[3 * i + c])));
        changed += d > 16;
    }
    sdft_image_free(&a);
    sdft_image_free(&g);
    return (double)changed / (p.width * p.height);
}

/* The jewel from its grid, shaded with the grid's materials, differs from
 * the procedural jewel only where a 384^3 grid rounds its edges; without
 * them (one grey surface) most of the picture differs. */
static void test_jewel_renders_from_its_grid(void **state)
{
    (void)state;
    baked b;
    open_baked(&b, "jewel-materials.nvdb");
    const sdft_field with = sdft_grid_field(b.surface, SDFT_GRID_BOUND_FAR);
    const double near = share_changed(&with);
    char msg[256];
    assert_int_equal(sdft_grid_set_materials(b.surface, NULL, NULL, 0, msg, sizeof msg), SDFT_OK);
    const sdft_field without = sdft_grid_field(b.surface, SDFT_GRID_BOUND_FAR);
    assert_null(without.material);
    const double far = share_changed(&without);
    print_message("pixels beyond 16/255 of the procedural jewel: %.2f%% with the grid's materials, %.2f%% without\n",
                  100.0 * near, 100.0 * far);
    assert_true(near < 0.06);
    assert_true(far > 0.4);
    close_baked(&b);
}

static void test_bad_arguments(void **state)
{
    (void)state;
    baked b;
    open_baked(&b, "jewel-materials.nvdb");
    char msg[256];
    sdft_material m[2] = {b.materials[0], b.materials[0]};
    assert_int_equal(sdft_grid_set_materials(NULL, b.ids, m, 1, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_grid_set_materials(b.surface, b.ids, NULL, 1, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_grid_set_materials(b.surface, b.ids, m, 0, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_grid_set_materials(b.surface, b.ids, m, SDFT_GRID_MAX_MATERIALS + 1, msg, sizeof msg),
                     SDFT_EINVAL);
    m[1].ior = 0.5f;
    assert_int_equal(sdft_grid_set_materials(b.surface, b.ids, m, 2, msg, sizeof msg), SDFT_EINVAL);
    assert_non_null(strstr(msg, "material 1"));
    m[1].ior = 0.0f, m[1].colour.y = 1.5f;
    assert_int_equal(sdft_grid_set_materials(b.surface, b.ids, m, 2, msg, sizeof msg), SDFT_EINVAL);
    size_t count;
    assert_int_equal(sdft_grid_material_table(NULL, m, 2, &count, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_grid_material_table(b.table, m, 2, &count, msg, sizeof msg), SDFT_EINVAL); /* 5 > 2 */
    /* The surface itself is no table: its voxel (0, 0, 0) is outside the band. */
    assert_int_equal(sdft_grid_material_table(b.surface, m, 2, &count, msg, sizeof msg), SDFT_EFORMAT);
    /* Baking materials needs a field that has them, and a file. */
    const sdft_scene *figure = sdft_scene_find("figure"), *jewel = sdft_scene_find("jewel");
    sdft_bake_params p = sdft_bake_defaults();
    p.res = 16, p.materials = 1;
    char path[512];
    tu_tmp(path, sizeof path, "figure-materials.nvdb");
    assert_int_equal(sdft_bake(&figure->field, &p, path, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    assert_int_equal(sdft_bake(&jewel->field, &p, NULL, NULL, NULL, msg, sizeof msg), SDFT_EINVAL);
    assert_false(tu_file_exists(path));
    close_baked(&b);
}

/* From the command line: bake --materials, render --grid shades with them
 * (as it reports), --no-materials does not, and --no-convex is refused on
 * a grid, which declares no convex parts (the JSON says none was used). */
static void test_command_line(void **state)
{
    (void)state;
    char vdb[512], exr[512];
    tu_tmp(vdb, sizeof vdb, "jewel-materials.vdb");
    tu_tmp(exr, sizeof exr, "jewel-materials.exr");
    assert_int_equal(
        tu_run(out, sizeof out, "%s bake --scene jewel --res 96 --materials --grid-name gem -o %s", SDFT_CLI, vdb), 0);
    assert_non_null(strstr(out, "with its materials"));
    assert_int_equal(tu_run(out, sizeof out,
                            "%s render --grid %s --scene jewel --width 32 --height 18 -o %s --json "
                            "--quiet",
                            SDFT_CLI, vdb, exr),
                     0);
    assert_non_null(strstr(out, "\"materials\": true"));
    assert_non_null(strstr(out, "\"convex\": false"));
    assert_int_equal(tu_run(out, sizeof out,
                            "%s render --grid %s --width 32 --height 18 -o %s --json --quiet "
                            "--no-materials",
                            SDFT_CLI, vdb, exr),
                     0);
    assert_non_null(strstr(out, "\"materials\": false"));
    remove(exr);
    assert_int_equal(
        tu_run(out, sizeof out, "%s render --grid %s --width 32 --height 18 -o %s --no-convex", SDFT_CLI, vdb, exr), 2);
    assert_int_equal(tu_lines(out), 1);
    assert_non_null(strstr(out, "no convex parts"));
    assert_false(tu_file_exists(exr));
    assert_int_equal(
        tu_run(out, sizeof out, "%s render --scene temple --width 8 --height 8 -o %s --no-convex", SDFT_CLI, exr), 2);
    assert_int_equal(tu_lines(out), 1);
    assert_int_equal(tu_run(out, sizeof out,
                            "%s render --scene jewel --width 8 --height 8 -o %s --no-convex --json "
                            "--quiet",
                            SDFT_CLI, exr),
                     0);
    assert_non_null(strstr(out, "\"convex\": false"));
    assert_int_equal(tu_run(out, sizeof out, "%s bake --scene figure --res 16 --materials -o %s", SDFT_CLI, vdb), 2);
    assert_int_equal(tu_lines(out), 1);
    assert_non_null(strstr(out, "no materials"));
    remove(vdb), remove(exr);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table_is_the_scenes_materials),
        cmocka_unit_test(test_material_at_surface_points),
        cmocka_unit_test(test_jewel_renders_from_its_grid),
        cmocka_unit_test(test_bad_arguments),
        cmocka_unit_test(test_command_line),
    };
    return cmocka_run_group_tests_name("grid_material", tests, NULL, NULL);
}
