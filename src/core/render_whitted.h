/* sdftrace — shading a primary hit the Whitted way (render_whitted.c).
 * Internal header. */
#ifndef SDFTRACE_RENDER_WHITTED_H
#define SDFTRACE_RENDER_WHITTED_H

#include "render_frame.h"

/* 1 when params ask for anything beyond one hard shadow ray and the grey
 * surface: then every hit is shaded by render_whitted_pixel. */
int render_whitted_wanted(const sdft_render_params *rp);

/* The pixel of primary ray `ray` with hit h: its colour from the hit's
 * material, lights, reflections and refractions, each secondary ray traced
 * with the frame's variant, and its counts, primary, shadow and secondary
 * apart. */
void render_whitted_pixel(const frame *fr, sdft_scratch *s, sdft_ray ray, sdft_hit h, pixel_result *out);

#endif
