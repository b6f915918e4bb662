/* shape.h: an obstacle's surface as quads and triangles, for both renderers */
#ifndef DRAPE_SHAPE_H
#define DRAPE_SHAPE_H

#include <stdbool.h>

#include "obstacle.h"
#include "raster.h"
#include "vec3.h"

#define SHAPE_FLOOR_HALF 1.5	/* the floor's half width, of the framed radius */

/* A face: a triangle (nv 3) or a quad (nv 4, drawn as a b c and a c d).
 * smooth: n holds a normal at each corner (a curved surface); else the
 * face is flat and n is left unset. */
struct shape_face {
	int nv;
	bool smooth;
	vec3 p[4], n[4];
};

typedef void shape_face_fn(void *ctx, const struct shape_face *f);

/* How finely the curved obstacles are cut: the character raster needs
 * fewer faces than the picture. */
struct shape_detail {
	int slices, stacks;	/* a sphere's */
	int segments;		/* a disc's, round its rim */
};

/* The faces of a box, sphere, disc or mesh obstacle, one call each, in an
 * order fixed so that the pictures do not change; a plane has none (each
 * renderer draws its own floor about shape_floor's square). */
void shape_obstacle(const struct obstacle *o, const struct shape_detail *d, shape_face_fn *fn,
    void *ctx);

/* The floor's square: a plane's part about the framed target, a little
 * under the surface (so that a cloth lying on it covers it). */
struct shape_floor {
	vec3 c;			/* the target projected onto the plane */
	vec3 u, w;		/* the plane's tangents */
	double half;		/* m, each way from c */
	double sink;		/* m, the square's depth under the plane */
	vec3 under;		/* c, sunk */
	vec3 corner[4];		/* the square, round its edge */
};

void shape_floor(const struct camera *cam, vec3 point, vec3 n, struct shape_floor *f);

#endif
