/* ccd.h: continuous collision detection of a vertex and a triangle, or of
 * two edges, each point moving linearly over the step, t in [0, 1].
 *
 * Both tests are conservative in floating point: with eta = 0 they never
 * answer 0 when exact arithmetic on the double inputs would find contact
 * (false positives are allowed and are rare). The method is the
 * coplanarity cubic, its roots isolated by subdivision as intervals whose
 * width accounts for rounding, and a separating-axis test over each such
 * interval; see ccd.c for the error bounds.
 *
 * eta > 0 is a proximity margin, not a full guarantee: the answer is also 1
 * when the primitives are within eta at t = 0 or t = 1, or at a time they
 * are coplanar, but a pass within eta at some other time is not found. */
#ifndef DRAPE_CCD_H
#define DRAPE_CCD_H

#include "vec3.h"

/* x[0] the vertex, x[1..3] the triangle, at t = 0 (x0) and t = 1 (x1).
 * Returns 1 when they may touch (come within eta >= 0) in [0, 1], else 0.
 * On 1, *toi (may be NULL) is a lower bound in [0, 1] on the first contact
 * time; with eta > 0, on the first time the test found them within eta,
 * and 0 when that was at t = 0 or only at t = 1. Inputs must be finite. */
int ccd_vertex_face(const vec3 x0[4], const vec3 x1[4], double eta, double *toi);

/* x[0]-x[1] edge a, x[2]-x[3] edge b; otherwise as ccd_vertex_face. */
int ccd_edge_edge(const vec3 x0[4], const vec3 x1[4], double eta, double *toi);

#endif
