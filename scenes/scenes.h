/* sdftrace — the scenes the registry lists, one per scenes/<name>.c.
 * Internal header. */
#ifndef SDFTRACE_SCENES_H
#define SDFTRACE_SCENES_H

#include "sdftrace/scene.h"

extern const sdft_scene scene_temple;
extern const sdft_scene scene_figure;
extern const sdft_scene scene_dodecahedron;
extern const sdft_scene scene_city;

#endif
