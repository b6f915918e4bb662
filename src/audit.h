/* audit.h: an independent check that a mesh does not pass through itself
 * or through another mesh. It shares no code with the collision stages it
 * checks: its own broad phase (sweep and prune on boxes) and an exact
 * triangle-triangle test built on exact orientation predicates, so what it
 * reports is a fact about the positions, not about a tolerance.
 *
 * Exact means exact for finite coordinates whose products of three neither
 * overflow nor underflow (any cloth in metres qualifies). NaN or infinite
 * coordinates give a meaningless count, but nothing worse. */
#ifndef DRAPE_AUDIT_H
#define DRAPE_AUDIT_H

#include <stdbool.h>
#include <stddef.h>

#include "vec3.h"

/* The sign (+1, 0, -1) of (d - a) . ((b - a) x (c - a)): +1 when d lies on
 * the side of plane abc that the right-handed normal of a, b, c points to,
 * 0 when the four points are coplanar. */
int audit_orient3d(vec3 a, vec3 b, vec3 c, vec3 d);

/* 1 if the two closed triangles share at least one point (touching counts),
 * else 0. Triangles of zero area are the segments or points they cover. */
int audit_tri_tri(const vec3 p[3], const vec3 q[3]);

/* The audit's work is bounded: a pair of boxes the sweep compares is one
 * unit, an exact test of two triangles AUDIT_TEST_WORK more (their costs
 * here: 4 ns and 150 ns), and an audit of n triangles in all does at most
 * audit_max_work(n) units, AUDIT_WORK_PER_TRIANGLE a triangle and
 * AUDIT_WORK_MIN at least. A cloth, even folded in layers, takes under a
 * hundred a triangle (the shipped scenes: at most 28 comparisons and 2
 * tests); triangles piled on one another make every pair both (80,000
 * coincident ones are 3.2e9 pairs: 16.5 s, and 1e6 of them were not done
 * in 590 s), and the audit stops at its bound, its count of pairs then a
 * lower bound. */
#define AUDIT_TEST_WORK 32
#define AUDIT_WORK_PER_TRIANGLE 2048
#define AUDIT_WORK_MIN 10000000L
long audit_max_work(size_t n);

struct audit_result {
	long pairs;		/* intersecting pairs found */
	long candidates;	/* pairs of boxes compared */
	long tests;		/* exact tests made */
	bool cut;		/* stopped at the bound: pairs is a lower bound */
};

/* Pairs of triangles that share no vertex index and intersect, among ntri
 * triangles (3 node indices each into x, 3 doubles per node), into *r.
 * Returns 0, or -1 when out of memory. If first is not NULL and pairs are
 * found, first[0] < first[1] get the lowest such pair (by first triangle,
 * then second) among those found. */
int audit_self(const double *x, const int *tri, size_t ntri, int first[2],
    struct audit_result *r);

/* Pairs (i of mesh A, j of mesh B) that intersect, the meshes given
 * separately (cloth against an obstacle), into *r; 0 or -1 as above. */
int audit_cross(const double *xa, const int *ta, size_t na, const double *xb, const int *tb,
    size_t nb, struct audit_result *r);

/* The same as counts: the pairs, -1 when out of memory, AUDIT_TOO_MANY
 * when the bound cut the audit short. */
#define AUDIT_TOO_MANY (-2L)
long audit_self_intersections(const double *x, const int *tri, size_t ntri, int first[2]);
long audit_cross_intersections(const double *xa, const int *ta, size_t na,
    const double *xb, const int *tb, size_t nb);

#endif
