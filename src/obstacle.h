/* obstacle.h: the solids the cloth meets. Planes, boxes, spheres and discs
 * are answered analytically by a signed distance; a mesh goes through the
 * simulator's triangle narrow phase like the cloth itself. */
#ifndef DRAPE_OBSTACLE_H
#define DRAPE_OBSTACLE_H

#include "err.h"
#include "mesh.h"
#include "vec3.h"

enum obstacle_kind {
	OBSTACLE_PLANE,
	OBSTACLE_BOX,
	OBSTACLE_SPHERE,
	OBSTACLE_DISC,
	OBSTACLE_MESH,
};

struct obstacle {
	enum obstacle_kind kind;
	int line;		/* of its section in the scene file */
	double friction;	/* Coulomb coefficient mu, >= 0 */
	vec3 point, normal;	/* plane: a point and the unit normal pointing out
				 * of the solid half-space */
	vec3 lo, hi;		/* box: axis-aligned corners, lo < hi on every axis */
	vec3 centre;		/* sphere: centre; disc: centre of its top face */
	double radius;		/* sphere, disc */
	double height;		/* disc: a vertical (y) cylinder of this height under
				 * its top face (the Cusick drape tester's support
				 * disc on its pedestal) */
	struct mesh mesh;	/* mesh: handled by the simulator's triangle narrow
				 * phase, not analytically */
	char *file;		/* mesh: the OBJ file it was read from, as opened
				 * (an input, which no output may overwrite), or
				 * NULL */
};

/* "plane", "box", "sphere", "disc", "mesh", then NULL; by kind. */
extern const char *const obstacle_kind_name[];

/*
 * Signed distance from p to the solid's surface, negative inside. *q (may be
 * NULL) gets the closest point of the surface, *normal (may be NULL) the
 * outward unit normal there. A point inside a box or disc leaves through the
 * nearest face; on a tie the top (+y) face wins, then x, then z, then the
 * bottom, so a node on a table's edge goes back up onto it. A point on the
 * axis of a sphere or disc, where the direction is undefined, gets +y or +x.
 *
 * Analytic kinds are cheap (no allocation, no trig): this runs for every
 * node every step. A mesh costs a pass over its triangles and the winding
 * number (one atan2 each): the distance to the nearest triangle, negative
 * when the winding number is 0.5 or more.
 */
double obstacle_distance(const struct obstacle *o, vec3 p, vec3 *q, vec3 *normal);

/* The solid's bounding box. A plane's is infinite (+-INFINITY) except on an
 * axis its normal lies along. */
void obstacle_bounds(const struct obstacle *o, vec3 *lo, vec3 *hi);

/* The deepest point of segment a-b into the axis-aligned box [lo, hi]:
 * the depth of a point is its distance inside the nearest face, negative
 * outside (then the most any face's plane has it out, which is no more
 * than its distance). Returns the segment's greatest depth, its t in
 * [0, 1] (the first on a tie) and the outward normal of the face it is
 * deepest under. A box's edge cut by a cloth edge whose ends are outside
 * is found exactly (pbd.c, bdf2.c keep edges out of boxes by it;
 * obstacle_segment_nearest takes a box's deepest point from it). */
double obstacle_box_segment_depth(vec3 lo, vec3 hi, vec3 a, vec3 b, double *t, vec3 *normal);

/* The least signed distance to an analytic solid along segment a-b, and
 * its t in [0, 1] (an end when the least is there). A box's exactly (a
 * few of obstacle_distance's cost); the others' by a search of about 50
 * calls of obstacle_distance. */
double obstacle_segment_nearest(const struct obstacle *o, vec3 a, vec3 b, double *t);

/* Checks the shape and normalises a plane's normal. Returns 0, or -1 with
 * "what is wrong" in err, without a file:line prefix (the caller knows it):
 * a zero or non-finite plane normal, a box with min >= max on an axis, a
 * radius or height <= 0 or not finite, a mesh without triangles, friction
 * < 0. */
int obstacle_check(struct obstacle *o, struct drape_err *err);

/* Frees the mesh if any. */
void obstacle_free(struct obstacle *o);

#endif
