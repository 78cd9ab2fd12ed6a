/* sdftrace io — the PNG writer shared by the preview and the heatmap.
 * Internal to src/io. */
#ifndef SDFTRACE_PNG_WRITE_H
#define SDFTRACE_PNG_WRITE_H

#include "atomic_file.h"

/* Writes width x height 8-bit RGB rows (row-major, no padding) into the
 * reserved file `to`; srgb tags the file as sRGB. 0, or -1 with msg. */
int io_png_write_rgb8(atomic_file *to, const unsigned char *rgb, int width, int height, int srgb, char *msg,
                      size_t msg_len);

#endif
