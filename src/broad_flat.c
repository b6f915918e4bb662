/* broad_flat.c: bvh's flat patches: a rectangle of the cloth's grid
 * proven to stay one sheet over the step, whose pairs cannot touch and
 * are left out of the search (the proof below). */
#include <limits.h>

#include "broad_impl.h"

/*
 * ---- flat patches ----
 *
 * A cloth's neighbours in its plane overlap at every level of the tree,
 * whatever the motion, so a traversal of a flat cloth against itself
 * finds thousands of pairs the narrow phase then rules out one by one
 * (a falling tablecloth: some 3,900 a step, 85 % of its instructions).
 * A patch that stays flat cannot touch itself, and that can be proven
 * for the patch at once. Let f map the patch's rectangle on the cloth at
 * rest (convex) to space, linear on each triangle with deformation F
 * (3 x 2), and Q (2 x 3) project onto a plane. If the symmetric part of
 * Q F has its eigenvalues at least sigma > 0 on every triangle, then for
 * any two points p != q of the rectangle, integrating along the segment
 * between them (inside the rectangle, since it is convex),
 *   (Q f(q) - Q f(p)) . (q - p) >= sigma |q - p|^2,
 * so |f(q) - f(p)| >= sigma |q - p|: the patch is one sheet over the plane,
 * no two of its points meet, and two primitives that share no vertex
 * (uv_gap apart at rest) are at least sigma uv_gap apart. (This is the
 * contour condition of Volino & Magnenat-Thalmann 1994 made to hold by
 * construction: a rectangle's image under such a map cannot fold over.)
 * Over a step each vertex moves linearly, so F is linear in time, and the
 * matrices whose symmetric part is at least sigma form a convex set:
 * checking both ends of the step proves it throughout.
 *
 * What the searches need of a patch they leave out:
 *   - the check (exact ccd, no margin): sigma > 0 at both ends, so no
 *     pair of the patch can meet in the step;
 *   - a step's contacts (near > 0): no pair of the patch may be kept
 *     (contacts.h: separation at the start less near_motion times the
 *     relative motion of its vertices under near). The separation is at
 *     least sigma_0 d for primitives d apart at rest (d >= uv_gap), and
 *     the relative motion at most L (d + 2 uv_diam), L the largest norm of
 *     the motion's gradient x1 - x0 on the patch's triangles; so the patch
 *     is out of reach if sigma_0 > near_motion L and
 *     (sigma_0 - near_motion L) uv_gap >= near + near_motion L 2 uv_diam
 *     (the first follows from the second: the worst d is uv_gap).
 * The projection is the patch's mean directions along u and along v,
 * made orthonormal; any fixed one is sound. A patch left out by one
 * search is judged again by every later one that takes the held pairs,
 * and by broad_recheck when the check moves its vertices.
 */

/* Cloth triangle t's deformation at x0 (k = 0) or x1 (k = 1), into tdef. */
void
bvh_tri_deform(struct broad *b, const struct geom *g, int t, int k)
{
	const double *x = k ? g->x1 : g->x0, *m = b->bvh.dminv + 4 * t;
	const int *v = g->tri + 3 * t;
	double *f = b->bvh.tdef + 12 * t + 6 * k;
	int d;

	for (d = 0; d < 3; d++) {
		double e1 = x[3 * v[1] + d] - x[3 * v[0] + d];
		double e2 = x[3 * v[2] + d] - x[3 * v[0] + d];

		f[d] = e1 * m[0] + e2 * m[2];
		f[3 + d] = e1 * m[1] + e2 * m[3];
	}
}

/* Each node's F at x0 and x1 summed over its triangles, for the nodes
 * [x, end) of the cloth's tree, children first. */
void
bvh_node_sums(struct broad *b, int x, int end)
{
	int i, k;

	for (i = end - 1; i >= x; i--) {
		const struct bvh_node *n = &b->bvh.node[i];
		double *s = b->bvh.nsum + 6 * i;

		if (bvh_leaf(n)) {
			const double *f = b->bvh.tdef + 12 * n->tri;

			for (k = 0; k < 6; k++)
				s[k] = f[k] + f[6 + k];
		} else {
			for (k = 0; k < 6; k++)
				s[k] = b->bvh.nsum[6 * n->left + k] + b->bvh.nsum[6 * n->right + k];
		}
	}
}

/* Each cloth triangle's deformations, and the least eigenvalue taken as
 * positive: far above the roundings of F's entries (a few units in the
 * last place of the coordinates, over the spacing). */
int
bvh_cull_prepare(struct broad *b, const struct geom *g, const struct broad_want *want)
{
	int t, n, k;
	double big = 0;

	b->bvh.cull_on = false;
	b->bvh.ncull = 0;
	if (b->bvh.dminv == NULL || b->bvh.cloth_root < 0 || !want->self || !(g->uv_gap > 0))
		return 0;
	n = b->bvh.node[b->bvh.cloth_root].count;
	if (grow_array((void **)&b->bvh.tdef, &b->bvh.tdefcap, 12 * (size_t)n, sizeof *b->bvh.tdef) != 0 ||
	    grow_array((void **)&b->bvh.nsum, &b->bvh.nsumcap, 6 * (size_t)(2 * n), sizeof *b->bvh.nsum) != 0)
		return -1;
	for (t = 0; t < n; t++) {
		bvh_tri_deform(b, g, t, 0);
		bvh_tri_deform(b, g, t, 1);
	}
	bvh_node_sums(b, b->bvh.cloth_root, b->bvh.cloth_root + 2 * n - 1);
	for (k = 0; k < 3 * g->ncloth; k++)
		big = fmax(big, fmax(fabs(g->x0[k]), fabs(g->x1[k])));
	b->bvh.cull_on = true;
	b->bvh.cull_want = *want;
	b->bvh.cull_tol = 1e-6 + 1e-12 * big / g->uv_gap;
	return 0;
}

/* The least eigenvalue of the symmetric part of Q F, Q's rows q1, q2. */
static double
least_eigen(const double *q1, const double *q2, const double *f)
{
	double a = q1[0] * f[0] + q1[1] * f[1] + q1[2] * f[2];
	double c = q2[0] * f[3] + q2[1] * f[4] + q2[2] * f[5];
	double s = (q1[0] * f[3] + q1[1] * f[4] + q1[2] * f[5] +
	    q2[0] * f[0] + q2[1] * f[1] + q2[2] * f[2]) / 2;

	return (a + c) / 2 - sqrt((a - c) * (a - c) / 4 + s * s);
}

/* Whether patch p is flat enough for the search cull_want (see above).
 * For a step's contacts the condition reads, with c = near_motion,
 *   (sigma_0 - tol) uv_gap - near >= c L (uv_gap + 2 uv_diam),
 * sigma_0 the least eigenvalue and L the largest gradient of the motion
 * over the patch; so each triangle alone must pass it, and a patch that
 * failed usually fails again at the same triangle (a fold lasts, a flap
 * goes on flapping), which is tried first: a failing patch then costs one
 * triangle, not a scan up to it. The order changes nothing but the cost. */
int
bvh_patch_flat(struct broad *b, const struct geom *g, const struct bvh_node *p)
{
	const struct broad_want *want = &b->bvh.cull_want;
	int x = (int)(p - b->bvh.node), i, k, ends = want->near > 0 ? 1 : 2, w = b->bvh.witness[x];
	const double *s = b->bvh.nsum + 6 * x;
	double q1[3], q2[3], len, d, sigma = INFINITY, lip2 = 0;
	double span = want->near_motion * (g->uv_gap + 2 * g->uv_diam);

	len = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
	if (!(len > 0))
		return 0;
	for (k = 0; k < 3; k++)
		q1[k] = s[k] / len;
	d = s[3] * q1[0] + s[4] * q1[1] + s[5] * q1[2];
	for (k = 0; k < 3; k++)
		q2[k] = s[3 + k] - d * q1[k];
	len = sqrt(q2[0] * q2[0] + q2[1] * q2[1] + q2[2] * q2[2]);
	if (!(len > 0))
		return 0;
	for (k = 0; k < 3; k++)
		q2[k] /= len;
	for (i = p->first - 1; i < p->first + p->count; i++) {
		int at = i < p->first ? w : i;
		const double *f;
		double st = INFINITY, gg = 0, room;

		if (at < p->first || at >= p->first + p->count)
			continue;	/* no witness in this patch */
		f = b->bvh.tdef + 12 * b->bvh.leaf_tri[at];
		for (k = 0; k < ends; k++)
			st = fmin(st, least_eigen(q1, q2, f + 6 * k));
		st -= b->bvh.cull_tol;
		if (ends == 1) {
			for (k = 0; k < 6; k++)
				gg += (f[6 + k] - f[k]) * (f[6 + k] - f[k]);
			/* this triangle's sigma and L alone */
			room = (st * g->uv_gap - want->near) / ((1 + 1e-9) * span);
			if (!(room > 0 && gg <= room * room)) {
				b->bvh.witness[x] = at;
				return 0;
			}
		} else if (!(st > 0)) {
			b->bvh.witness[x] = at;
			return 0;
		}
		sigma = fmin(sigma, st);
		lip2 = fmax(lip2, gg);
	}
	if (ends == 2)
		return 1;
	return (sigma * g->uv_gap - want->near) >=
	    (1 + 1e-9) * span * sqrt(lip2) + 1e-300;
}

int
bvh_push_cull(struct broad *b, int x)
{
	if (b->bvh.ncull == b->bvh.cullcap &&
	    grow_array((void **)&b->bvh.cull, &b->bvh.cullcap, b->bvh.ncull + 1, sizeof *b->bvh.cull) != 0)
		return -1;
	b->bvh.cull[b->bvh.ncull++] = x;
	return 0;
}
