/* narrow.h: the chapter's node-triangle test (§3.1, eq. 1-10).
 *
 * A segment r from F (a node at the consistent step k) to D (a node at the
 * predicted step k+1) is tested against a triangle ABC at step k. F is D
 * itself at step k for a node's own path (the icosahedron test), or the
 * other end of an edge that holds D (edge-edge and sliding contact, end of
 * §3.2). The continuous test that never misses is in ccd.h. */
#ifndef DRAPE_NARROW_H
#define DRAPE_NARROW_H

#include "event.h"
#include "vec3.h"

/* Which narrow phase a scene runs: the chapter's test (below) once a
 * step, or the continuous one of ccd.h, repeated until no contact is left. */
enum narrow_mode { NARROW_SEED, NARROW_CCD };
extern const char *const narrow_mode_name[];	/* NULL-terminated, for the parser */

/* How eq. 9-10's question "is Q inside ABC?" is answered. */
enum inside_test {
	INSIDE_ANGLE,		/* angle sum 2*pi within eps = 2*pi/100 (eq. 9-10) */
	INSIDE_CROSSING,	/* crossings of a ray from Q with the edges */
};

/* Which lines r the seed test draws to a node D at step k+1 (narrow =
 * seed): its own path from step k (§3.1, the icosahedron's test), the
 * edges F-D of its triangles from each neighbour F at step k (eq. 5-6;
 * §3.2's sliding case, "the intersecting line r to be along the edge of
 * the triangle containing the colliding node"), or both, in that order. */
enum seed_segments { SEGMENTS_BOTH, SEGMENTS_PATH, SEGMENTS_EDGES };
extern const char *const seed_segments_name[];	/* NULL-terminated, for the parser */

struct seed_hit {
	vec3 q;			/* eq. 8 */
	double tq;		/* eq. 7, in [0, 1] along F -> D */
	vec3 n;			/* unit normal of ABC, (B-A) x (C-A) */
	enum contact_type type;	/* node-node, node-edge or node-face */
	int feature;		/* the vertex (0..2) or the edge (0 AB, 1 BC, 2 CA) */
};

/* Epsilon of eq. 10. */
#define SEED_EPS (2 * V3_PI / 100)

/* 1 if r = F -> D crosses the plane of ABC (eq. 1-2, signs of opposite
 * sense, or D on the plane) at a Q inside the triangle (eq. 3-10); 0 if not
 * or if the triangle is degenerate. */
int narrow_seed_segment(vec3 f, vec3 d, vec3 a, vec3 b, vec3 c,
    enum inside_test how, struct seed_hit *hit);

#endif
