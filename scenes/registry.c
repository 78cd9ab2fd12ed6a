/* sdftrace — the registry of procedural scenes: static, read-only data. */
#include <string.h>

#include "scenes.h"

static const sdft_scene *const all_scenes[] = {
    &scene_temple, &scene_figure, &scene_dodecahedron, &scene_city, &scene_jewel,
};

const sdft_scene *const *sdft_scenes(size_t *count)
{
    if (count)
        *count = sizeof all_scenes / sizeof all_scenes[0];
    return all_scenes;
}

const sdft_scene *sdft_scene_find(const char *name)
{
    for (size_t i = 0; name && i < sizeof all_scenes / sizeof all_scenes[0]; i++)
        if (strcmp(all_scenes[i]->name, name) == 0)
            return all_scenes[i];
    return NULL;
}
