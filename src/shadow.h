/* shadow.h: the shadow a cloth casts on the horizontal (x-z) plane, the
 * drape coefficient of the Cusick drape test (BS 5058, ISO 9073-9, AATCC
 * TM 219) computed from it, and the folds of its outline.
 *
 * The shadow is the union of the cloth's triangles projected along y. It is
 * found on a raster of square cells, a cell counting when its centre lies in
 * some projected triangle, so that folds lying over one another count once,
 * as they do in the drape tester's shadow. Nothing here allocates more than
 * the raster or keeps anything between calls. */
#ifndef DRAPE_SHADOW_H
#define DRAPE_SHADOW_H

#include <stddef.h>

/* The raster holds at most this many cells; a larger shadow gets coarser. */
#define SHADOW_MAX_CELLS (1L << 24)

/*
 * The area (m^2) of the union of triangles tri (3 vertex numbers each, into
 * x, 3 coordinates per vertex) projected on the x-z plane, rasterized with
 * cells of side cell (> 0). Only cells the shadow's outline crosses can be
 * miscounted, so the error is at most about perimeter * cell * sqrt(2).
 * A triangle seen edge-on (projected area 0) casts no shadow.
 * *cell_used (may be NULL) gets the cell side used: cell, doubled as often
 * as needed to keep the raster within SHADOW_MAX_CELLS.
 * Returns 0, or -1 if out of memory. A vertex that is not finite gives NaN.
 */
int shadow_area(const double *x, const int *tri, size_t ntri, double cell, double *area,
    double *cell_used);

/* The sum of the triangles' areas in space: the flat specimen's area when x
 * is the rest shape. */
double mesh_area(const double *x, const int *tri, size_t ntri);

/* DC = (A_s - A_d) / (A_0 - A_d) for the shadow A_s, the support disc A_d and
 * the flat specimen A_0: 1 for a specimen that stays flat, near 0 for one
 * that hangs straight down. NaN when A_0 <= A_d (nothing overhangs). */
double drape_coefficient(double shadow, double support, double flat);

/* The outline's sectors for drape_folds: 5 degrees each. */
#define SHADOW_FOLD_BINS 72

/*
 * The folds of a draped specimen, seen from above: the lobes of its
 * outline around the vertical axis through (cx, cz), each standing at
 * least prom (m) out from the outline on both sides between it and the
 * next lobe. x holds the vertices (3 coordinates each), edge the nedges
 * edges (2 vertex numbers each), sampled every cell (m, > 0) or closer.
 * -1 when the outline does not go all round the axis or a vertex is not
 * finite.
 */
int drape_folds(const double *x, const int *edge, size_t nedges, double cx, double cz,
    double cell, double prom);

#endif
