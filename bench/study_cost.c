/* study — what a frame would cost a GPU, from its per-pixel counts
 * (study.h: study_wavefront_cost). Bán and Valasek timed a GPU, where the
 * lanes of a wavefront step in lock-step and each of its loops lasts as
 * long as its slowest lane; a CPU core pays each ray's own evaluations. */
#include <stddef.h>

#include "study.h"

double study_wavefront_cost(const uint32_t *primary, const uint32_t *total, int width, int height, int tile_w,
                            int tile_h)
{
    if (width < 1 || height < 1 || tile_w < 1 || tile_h < 1)
        return 0.0;
    double sum = 0.0;
    size_t tiles = 0;
    for (int ty = 0; ty < height; ty += tile_h)
        for (int tx = 0; tx < width; tx += tile_w) {
            uint32_t most_primary = 0, most_shadow = 0;
            for (int y = ty; y < ty + tile_h && y < height; y++)
                for (int x = tx; x < tx + tile_w && x < width; x++) {
                    const size_t i = (size_t)y * (size_t)width + (size_t)x;
                    const uint32_t p = primary[i], s = total ? total[i] - primary[i] : 0;
                    most_primary = p > most_primary ? p : most_primary;
                    most_shadow = s > most_shadow ? s : most_shadow;
                }
            sum += (double)most_primary + (double)most_shadow;
            tiles++;
        }
    return sum / (double)tiles;
}
