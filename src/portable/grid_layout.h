/* sdftrace — how the portable sampler (grid_cell.h, grid_sample.h,
 * grid_root.h) reaches a grid: the constants of its leaf directory and far
 * bound, and the few accessors whose spelling differs. In C a grid is
 * const sdft_grid * (grid_internal.h) and its tables are its pointers; in
 * the shader it is the frame's grid_shape (grid_shape.h), the tables buffer
 * references, and the `g` the functions pass along is a placeholder.
 * Portable (portable.h). */
#ifndef SDFTRACE_GRID_LAYOUT_H
#define SDFTRACE_GRID_LAYOUT_H

#include "portable.h"

/* The far bound's corner words (grid_bound.c): bits 0-13 the index
 * distance x FAR_DISTANCE_SCALE, bits 14-15 the cell's code. */
#define FAR_DISTANCE_BITS 14
#define FAR_EMPTY_POSITIVE 1
#define FAR_EMPTY_NEGATIVE 2
#define FAR_DISTANCE_SCALE 4.0f /* corner words per index unit */

/* The leaf directory's chunks (grid_leaves.c): 9^3 entries, each a leaf's
 * value table's word, or a marker below any such word. */
#define GRID_CHUNK_SIDE 9
#define GRID_CHUNK_ENTRIES (9 * 9 * 9)
#define GRID_TILE_POSITIVE 1
#define GRID_TILE_NEGATIVE 2
#define GRID_TILE_MARKERS 3

#if !defined(SDFT_GLSL)
#define GRID_REF const sdft_grid *
#define GRID(g) (*(g))
#define GRID_WORD(g, w) ((g)->words[w])
#define GRID_TOP(g, i) ((g)->leaves.top[i])
/* A place in the directory's chunks and in the far bound's corner table:
 * a pointer (as the library always had it: the same code); entry i from
 * there; the place n entries from the table's start. */
#define GRID_CHUNK_REF const uint32_t *
#define GRID_CHUNK_AT(g, e, i) ((e)[i])
#define GRID_CHUNK_BASE(g, n) ((g)->leaves.chunk + (n))
#define GRID_FAR_REF const uint16_t *
#define GRID_FAR_AT(g, d, i) ((d)[i])
#define GRID_FAR_BASE(g, n) ((g)->far.corner + (n))
#define GRID_HAS_DIRECTORY(g) ((g)->leaves.top != NULL)
#define GRID_HAS_FAR(g) ((g)->far.corner != NULL)
/* A deferred grid's leaf filled before it is read (grid_deferred.c). */
#define GRID_LEAF_READY(g, at, ijk) grid_leaf_ready(g, at, ijk)
#else
/* The shader defines GRID_SHAPE, its grid_shape, before including this. */
#define GRID_REF uint
#define GRID(g) GRID_SHAPE
#define GRID_WORD(g, w) GRID_SHAPE.buf.data[w]
#define GRID_TOP(g, i) GRID_SHAPE.top.data[i]
#define GRID_CHUNK_REF uint
#define GRID_CHUNK_AT(g, e, i) GRID_SHAPE.chunk.data[(e) + (i)]
#define GRID_CHUNK_BASE(g, n) (n)
#define GRID_FAR_REF uint /* 16-bit words, two a 32-bit one */
#define GRID_FAR_AT(g, d, i) (GRID_SHAPE.far_corner.data[((d) + (i)) >> 1u] >> ((((d) + (i)) & 1u) << 4u) & 0xFFFFu)
#define GRID_FAR_BASE(g, n) (n)
#define GRID_HAS_DIRECTORY(g) (GRID_SHAPE.has_directory != 0)
#define GRID_HAS_FAR(g) (GRID_SHAPE.has_far != 0)
#define GRID_LEAF_READY(g, at, ijk) /* the GPU's grids are loaded whole */
#endif

#endif
