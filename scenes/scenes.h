/* sdftrace — the scenes the registry lists, one per scenes/<name>.c.
 * Internal header. */
#ifndef SDFTRACE_SCENES_H
#define SDFTRACE_SCENES_H

#include "sdftrace/scene.h"

extern const sdft_scene scene_temple;
extern const sdft_scene scene_figure;
extern const sdft_scene scene_dodecahedron;
extern const sdft_scene scene_city;
extern const sdft_scene scene_jewel;

/* The renderer's grey, opaque (materials.c). */
sdft_material scene_grey(void);

/* A checker floor of `square`-wide squares, light and dark, at p (x, z). */
sdft_material scene_checker(sdft_vec3 p, float square);

#endif
