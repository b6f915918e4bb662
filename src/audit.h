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

#include <stddef.h>

#include "vec3.h"

/* The sign (+1, 0, -1) of (d - a) . ((b - a) x (c - a)): +1 when d lies on
 * the side of plane abc that the right-handed normal of a, b, c points to,
 * 0 when the four points are coplanar. */
int audit_orient3d(vec3 a, vec3 b, vec3 c, vec3 d);

/* 1 if the two closed triangles share at least one point (touching counts),
 * else 0. Triangles of zero area are the segments or points they cover. */
int audit_tri_tri(const vec3 p[3], const vec3 q[3]);

/* Pairs of triangles that share no vertex index and intersect, among ntri
 * triangles (3 node indices each into x, 3 doubles per node). Returns the
 * count, or -1 when out of memory. If first is not NULL and the count is
 * positive, first[0] < first[1] get the lowest such pair (by first
 * triangle, then second). */
long audit_self_intersections(const double *x, const int *tri, size_t ntri, int first[2]);

/* Pairs (i of mesh A, j of mesh B) that intersect, the meshes given
 * separately (cloth against an obstacle). Returns the count, or -1 when out
 * of memory. */
long audit_cross_intersections(const double *xa, const int *ta, size_t na,
    const double *xb, const int *tb, size_t nb);

#endif
