/* paint.h: a scene drawn into a render (render.h): a plane as a floor with
 * a grid fixed in the world and the cloth's shadow on it, boxes, spheres
 * and discs shaded, a mesh obstacle with its edges (cut away, its faces
 * towards the viewer left out, when a node is inside it, as in the
 * icosahedron), and the cloth Gouraud-shaded in the colours of a
 * colouring (colouring.h), its yarn lines where the squares are large
 * enough to show them. What view.c is to the ASCII raster. */
#ifndef DRAPE_PAINT_H
#define DRAPE_PAINT_H

#include <stdbool.h>

#include "cloth.h"
#include "colouring.h"
#include "render.h"
#include "scene.h"

#define PAINT_BACKGROUND ((struct rgb){ 255, 255, 255 })

struct paint_opts {
	enum colouring colouring;
	double range;		/* of a strain scale, > 0 */
	double yarn_px;		/* yarn lines when a square spans this many pixels
				 * (0: never) */
	bool unlit;		/* colours as their scale gives them, the light in
				 * the pixels' lum only (a terminal's colours) */
};

/* Clears im and draws sc with its cloth cl at x; field holds c's value of
 * every node (colouring_field), or is NULL for COLOUR_SHADE. Returns 0, or
 * -1 out of memory. */
int paint_scene(struct render *im, const struct camera *cam, const struct scene *sc,
    const struct cloth *cl, const double *x, const double *field, const struct paint_opts *o);

/* The grid spacing of the floor paint_scene draws for cam (m). */
double paint_floor_spacing(const struct camera *cam);

#endif
