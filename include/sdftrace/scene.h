/* sdftrace — the procedural scenes of scenes/: each is a field, a default
 * camera and a point light. The registry is static, read-only data. Not in
 * libsdftrace: link the static library sdftrace_scenes (CMake component
 * `scenes`, target sdftrace::scenes). */
#ifndef SDFTRACE_SCENE_H
#define SDFTRACE_SCENE_H

#include <stddef.h>

#include "camera.h"
#include "field.h"
#include "sdftrace/config.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sdft_scene {
    const char *name;        /* "temple", "figure", "dodecahedron", "city", "jewel" */
    const char *description; /* one line, for `sdftrace scenes` */
    sdft_field field;        /* procedural: ctx NULL, no scratch */
    sdft_camera camera;      /* default view */
    sdft_vec3 light;         /* point light position, world units */
    int materials;           /* 1: rendered with its materials (field.material) unless told otherwise;
                              * 0: grey unless asked for them (sdft_render_params.materials) */
} sdft_scene;

/* All scenes, in listing order; *count (if not NULL) receives their number.
 * The array and the scenes are static, read-only data: never freed. */
SDFT_API const sdft_scene *const *sdft_scenes(size_t *count);

/* The scene called `name`, or NULL (no such scene, or name NULL): a lookup,
 * not an error. */
SDFT_API const sdft_scene *sdft_scene_find(const char *name);

#ifdef __cplusplus
}
#endif
#endif
