/* contacts.c: the fast path's contacts inside a step (see contacts.h). */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "collide.h"
#include "contacts.h"
#include "grow.h"
#include "vec3.h"

void
contacts_init(struct contacts *ct, double thickness)
{
	memset(ct, 0, sizeof *ct);
	ct->thickness = thickness;
}

void
contacts_free(struct contacts *ct)
{
	free(ct->pair);
	memset(ct, 0, sizeof *ct);
}

void
contacts_clear(struct contacts *ct)
{
	ct->n = 0;
}

/* Where vertex v of the pairs' geometry is: a cloth node's in x, a
 * mesh's where contacts_find saw it (they never move). */
static vec3
at(const struct contacts *ct, const double *x, int v)
{
	return v3_load(v < ct->ncloth ? x + 3 * v : ct->xmesh + 3 * v);
}

/* The point of triangle abc nearest p, as barycentric weights (Ericson,
 * Real-Time Collision Detection, 5.1.5). */
static void
closest_on_triangle(vec3 p, vec3 a, vec3 b, vec3 c, double w[3])
{
	vec3 ab = v3_sub(b, a), ac = v3_sub(c, a), ap = v3_sub(p, a), bp, cp;
	double d1 = v3_dot(ab, ap), d2 = v3_dot(ac, ap), d3, d4, d5, d6, va, vb, vc, den;

	w[0] = 1;
	w[1] = w[2] = 0;
	if (d1 <= 0 && d2 <= 0)
		return;
	bp = v3_sub(p, b);
	d3 = v3_dot(ab, bp);
	d4 = v3_dot(ac, bp);
	if (d3 >= 0 && d4 <= d3) {
		w[0] = 0;
		w[1] = 1;
		return;
	}
	vc = d1 * d4 - d3 * d2;
	if (vc <= 0 && d1 >= 0 && d3 <= 0) {
		double v = d1 / (d1 - d3);

		w[0] = 1 - v;
		w[1] = v;
		return;
	}
	cp = v3_sub(p, c);
	d5 = v3_dot(ab, cp);
	d6 = v3_dot(ac, cp);
	if (d6 >= 0 && d5 <= d6) {
		w[0] = 0;
		w[2] = 1;
		return;
	}
	vb = d5 * d2 - d1 * d6;
	if (vb <= 0 && d2 >= 0 && d6 <= 0) {
		double v = d2 / (d2 - d6);

		w[0] = 1 - v;
		w[2] = v;
		return;
	}
	va = d3 * d6 - d5 * d4;
	if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
		double v = (d4 - d3) / ((d4 - d3) + (d5 - d6));

		w[0] = 0;
		w[1] = 1 - v;
		w[2] = v;
		return;
	}
	den = va + vb + vc;
	if (!(den > 0) || !isfinite(den))	/* degenerate: the first vertex */
		return;
	w[1] = vb / den;
	w[2] = vc / den;
	w[0] = 1 - w[1] - w[2];
}

/* The pair's four vertices at positions x. */
static void
points(const struct contact_pair *cp, const struct contacts *ct, const double *x, vec3 p[4])
{
	int k;

	for (k = 0; k < 4; k++)
		p[k] = at(ct, x, cp->vert[k]);
}

/* The pair's weights on its four vertices at points p: the separation is
 * sum w[k] p[k], from the second side to the first. */
static void
weights(const struct contact_pair *cp, const vec3 p[4], double w[4])
{
	if (cp->other >= 0) {	/* a vertex and a triangle */
		double b[3];

		closest_on_triangle(p[0], p[1], p[2], p[3], b);
		w[0] = 1;
		w[1] = -b[0];
		w[2] = -b[1];
		w[3] = -b[2];
	} else {
		double s, u;

		v3_closest_on_segments(p[0], p[1], p[2], p[3], &s, &u);
		w[0] = 1 - s;
		w[1] = s;
		w[2] = -(1 - u);
		w[3] = -u;
	}
}

static vec3
separation(const vec3 p[4], const double w[4])
{
	vec3 d = v3(0, 0, 0);
	int k;

	for (k = 0; k < 4; k++)
		d = v3_madd(d, p[k], w[k]);
	return d;
}

static int
add_pair(struct contacts *ct, const struct contact_pair *cp)
{
	if (grow_array((void **)&ct->pair, &ct->cap, ct->n + 1, sizeof *ct->pair) != 0)
		return -1;
	ct->pair[ct->n++] = *cp;
	return 0;
}

/*
 * Closing, only a pair's motion towards the other side counts in full: a
 * pair whose sides move apart, or past each other, along its normal
 * cannot push on that plane, and a solver that holds pairs there (bdf2)
 * needs it only within the slack. Where a
 * landing cloth parts (one side stopped on the box, the other falling
 * 15 mm a step) the full rule keeps every triangle within 22 mm of each
 * node of the band: 700,000 pairs a step on the peers' 100^2 table,
 * scanned at every Newton iteration; the closing rule keeps those within
 * 7.5 mm that do not close: that table's first 0.25 s 11.7 -> 7.5 s, its
 * check's corrections 13,407 -> 12,966, none put back (bench-history.md,
 * 2026-12-05). The stepper's exact check stays the guarantee.
 */
bool
contacts_may_reach(vec3 d, vec3 moved, double rel, double thickness, bool closing)
{
	double dist = v3_len(d);

	if (closing && dist > 0)
		return dist - fmax(0, -v3_dot(moved, d) / dist) - CONTACTS_REACH_SLACK * rel <
		    CONTACTS_REACH * thickness;
	return dist - CONTACTS_REACH_MOTION * rel < CONTACTS_REACH * thickness;
}

/* Keeps the pair if it may come within the thickness during the step. */
static int
consider(struct contacts *ct, struct contact_pair *cp, const double *y0, double h, bool closing)
{
	size_t n3 = 3 * (size_t)ct->ncloth;
	double w[4], dist, rel = 0;
	vec3 d, p[4], disp[4], moved = v3(0, 0, 0);	/* moved: the separation's own motion */
	int k, l, first = cp->other >= 0 ? 1 : 2;

	points(cp, ct, y0, p);
	weights(cp, p, w);
	d = separation(p, w);
	dist = v3_len(d);
	for (k = 0; k < 4; k++)
		disp[k] = cp->vert[k] < ct->ncloth ?
		    v3_scale(v3_load(y0 + n3 + 3 * cp->vert[k]), h) : v3(0, 0, 0);
	/* first side's vertices against the second's: the vertex against the
	 * triangle's three, or edge against edge; the largest of the squares,
	 * then one root (the same number: a correctly rounded root is
	 * monotonic) */
	for (k = 0; k < first; k++)
		for (l = first; l < 4; l++) {
			vec3 r = v3_sub(disp[k], disp[l]);
			double r2 = v3_dot(r, r);

			rel = r2 > rel ? r2 : rel;
		}
	rel = sqrt(rel);
	for (k = 0; k < 4; k++)
		moved = v3_madd(moved, disp[k], w[k]);
	if (!contacts_may_reach(d, moved, rel, ct->thickness, closing))
		return 0;
	memcpy(cp->w, w, sizeof cp->w);
	if (dist > 1e-12 * (1 + v3_len(p[0]))) {
		v3_store(cp->n0, v3_scale(d, 1 / dist));
	} else {	/* touching already: against the relative motion */
		v3_store(cp->n0, v3_len(moved) > 0 ? v3_scale(moved, -1 / v3_len(moved)) : v3(0, 1, 0));
	}
	cp->active = false;
	{
		vec3 rv = v3(0, 0, 0);

		for (k = 0; k < 4; k++)
			rv = v3_madd(rv, disp[k], w[k] / h);
		cp->vn_before = v3_dot(rv, v3_load(cp->n0));
	}
	return add_pair(ct, cp);
}

struct find_ctx {
	struct contacts *ct;
	const double *y0;
	double h;
	bool closing;
};

static int
find_one(void *ctx, const struct collide_pair *p)
{
	struct find_ctx *f = ctx;
	struct contact_pair cp = { .nv = 4, .other = p->other, .obstacle = p->obstacle, .mu = p->mu };

	memcpy(cp.vert, p->vert, sizeof cp.vert);
	return consider(f->ct, &cp, f->y0, f->h, f->closing);
}

int
contacts_find(struct contacts *ct, const struct collide *col, const double *y0, double h,
    bool closing)
{
	struct find_ctx f = { ct, y0, h, closing };
	int rc;

	ct->n = 0;
	ct->ncloth = collide_geom(col)->ncloth;
	ct->xmesh = collide_geom(col)->x0;
	if ((rc = collide_each_pair(col, find_one, &f)) != 0)
		return rc > 0 ? 1 : -1;
	ct->found += (long)ct->n;
	return 0;
}

/*
 * A substep holds each pair on the plane it had at the step's start: the
 * separation sum w x along n0, with the weights of its closest points then,
 * kept at least a thickness. Planes fixed over the step make a projection
 * a few products (the closest points are not sought again each substep);
 * a contact that slides far enough to leave them is the step's check's.
 */
void
contacts_project(struct contacts *ct, const double *w_node, double *x, const double *xprev)
{
	size_t i;

	for (i = 0; i < ct->n; i++) {
		struct contact_pair *cp = &ct->pair[i];
		const double *w = cp->w;
		double im[4], den = 0, gap = 0, push, lam, slip, cut;
		vec3 n = v3_load(cp->n0), rel = v3(0, 0, 0), tan, p[4];
		int k;

		if (cp->obstacle < 0) {	/* cloth on cloth: all in x */
			for (k = 0; k < 4; k++) {
				p[k] = v3_load(x + 3 * cp->vert[k]);
				gap += w[k] * v3_dot(n, p[k]);
			}
		} else {
			for (k = 0; k < 4; k++) {
				p[k] = at(ct, x, cp->vert[k]);
				gap += w[k] * v3_dot(n, p[k]);
			}
		}
		if (gap >= ct->thickness)
			continue;
		for (k = 0; k < 4; k++) {
			int v = cp->vert[k];

			im[k] = v < ct->ncloth ? w_node[v] : 0;
			den += w[k] * w[k] * im[k];
		}
		if (!(den > 0))
			continue;
		push = ct->thickness - gap;
		lam = push / den;
		for (k = 0; k < 4; k++) {
			int v = cp->vert[k];

			if (im[k] == 0)
				continue;
			p[k] = v3_madd(p[k], n, w[k] * im[k] * lam);
			v3_store(x + 3 * v, p[k]);
		}
		/* Coulomb: the sliding of the substep, held while under mu times
		 * the push, else cut by that much */
		if (cp->mu > 0) {
			for (k = 0; k < 4; k++) {
				int v = cp->vert[k];

				if (v < ct->ncloth)
					rel = v3_madd(rel, v3_sub(p[k], v3_load(xprev + 3 * v)), w[k]);
			}
			tan = v3_madd(rel, n, -v3_dot(rel, n));
			slip = v3_len(tan);
			cut = cp->mu * push;
			if (slip > 0) {
				vec3 corr = v3_scale(tan, (slip <= cut ? 1 : cut / slip) / den);

				for (k = 0; k < 4; k++)
					if (im[k] > 0)
						v3_store(x + 3 * cp->vert[k], v3_madd(p[k], corr, -w[k] * im[k]));
			}
		}
		cp->active = true;
	}
}

int
contacts_events(struct contacts *ct, struct collide *col, long step, const double *y1)
{
	size_t n3 = 3 * (size_t)ct->ncloth, i;

	for (i = 0; i < ct->n; i++) {
		const struct contact_pair *cp = &ct->pair[i];
		double w[4];
		vec3 d, n, q = v3(0, 0, 0), rv = v3(0, 0, 0), p[4];
		bool tri = cp->other >= 0;
		int k;

		if (!cp->active)
			continue;
		points(cp, ct, y1, p);
		weights(cp, p, w);
		d = separation(p, w);
		n = v3_len(d) > 0 ? v3_scale(d, 1 / v3_len(d)) : v3_load(cp->n0);
		for (k = 0; k < 4; k++) {
			int v = cp->vert[k];

			if (w[k] < 0)
				q = v3_madd(q, p[k], -w[k]);
			if (v < ct->ncloth)
				rv = v3_madd(rv, v3_load(y1 + n3 + 3 * v), w[k]);
		}
		if (collide_add_event(col, step, cp->vert[0], tri ? CONTACT_NODE_FACE : CONTACT_EDGE_EDGE,
		    tri ? cp->other : -1 - cp->other, cp->obstacle, q, n, cp->vn_before,
		    v3_dot(rv, n)) != 0)
			return -1;
		ct->active++;
	}
	return 0;
}
