/* obstacle.c: signed distances, bounds and checks of the obstacles. */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "obstacle.h"

const char *const obstacle_kind_name[] = { "plane", "box", "sphere", "disc", "mesh", NULL };

/* A closest point and an outward normal; either pointer may be NULL. */
static void
put(vec3 *q, vec3 qv, vec3 *normal, vec3 nv)
{
	if (q != NULL)
		*q = qv;
	if (normal != NULL)
		*normal = nv;
}

/* Outside: the distance to q, and the normal from q towards p. */
static double
outside(vec3 p, vec3 qv, vec3 *q, vec3 *normal)
{
	vec3 d = v3_sub(p, qv);
	double len = v3_len(d);

	put(q, qv, normal, v3_scale(d, 1 / len));
	return len;
}

static double
plane_distance(const struct obstacle *o, vec3 p, vec3 *q, vec3 *normal)
{
	double d = v3_dot(o->normal, v3_sub(p, o->point));

	put(q, v3_madd(p, o->normal, -d), normal, o->normal);
	return d;
}

static double
sphere_distance(const struct obstacle *o, vec3 p, vec3 *q, vec3 *normal)
{
	vec3 r = v3_sub(p, o->centre), n = v3(0, 1, 0);
	double len = v3_len(r);

	if (len > 0)
		n = v3_scale(r, 1 / len);
	put(q, v3_madd(o->centre, n, o->radius), normal, n);
	return len - o->radius;
}

static double
clamp(double x, double lo, double hi)
{
	return x < lo ? lo : x > hi ? hi : x;
}

/*
 * Inside, the depth under each face; the shallowest is the way out. The
 * order of the faces breaks ties: the top first (a node on a table's edge
 * goes back up onto it), the bottom last.
 */
static double
box_distance(const struct obstacle *o, vec3 p, vec3 *q, vec3 *normal)
{
	double depth[6], face[6] = { o->hi.y, o->hi.x, o->lo.x, o->hi.z, o->lo.z, o->lo.y };
	static const vec3 out[6] = {
		{ 0, 1, 0 }, { 1, 0, 0 }, { -1, 0, 0 }, { 0, 0, 1 }, { 0, 0, -1 }, { 0, -1, 0 },
	};
	vec3 c = v3(clamp(p.x, o->lo.x, o->hi.x), clamp(p.y, o->lo.y, o->hi.y),
	    clamp(p.z, o->lo.z, o->hi.z));
	int k, best = 0;

	if (c.x != p.x || c.y != p.y || c.z != p.z)
		return outside(p, c, q, normal);
	depth[0] = o->hi.y - p.y;
	depth[1] = o->hi.x - p.x;
	depth[2] = p.x - o->lo.x;
	depth[3] = o->hi.z - p.z;
	depth[4] = p.z - o->lo.z;
	depth[5] = p.y - o->lo.y;
	for (k = 1; k < 6; k++)
		if (depth[k] < depth[best])
			best = k;
	if (out[best].x != 0)
		c.x = face[best];
	else if (out[best].y != 0)
		c.y = face[best];
	else
		c.z = face[best];
	put(q, c, normal, out[best]);
	/* 0 - depth: +0, not -0, on the surface */
	return 0 - depth[best];
}

/* A vertical cylinder: the top face at centre.y, the bottom height below. */
static double
disc_distance(const struct obstacle *o, vec3 p, vec3 *q, vec3 *normal)
{
	double top = o->centre.y, bottom = top - o->height;
	double dx = p.x - o->centre.x, dz = p.z - o->centre.z, r = sqrt(dx * dx + dz * dz);
	double side, up, down;
	vec3 radial = v3(1, 0, 0);

	if (r > 0)
		radial = v3(dx / r, 0, dz / r);
	if (r > o->radius || p.y > top || p.y < bottom) {
		vec3 c = v3_madd(o->centre, radial, fmin(r, o->radius));

		c.y = clamp(p.y, bottom, top);
		return outside(p, c, q, normal);
	}
	up = top - p.y;
	side = o->radius - r;
	down = p.y - bottom;
	if (up <= side && up <= down) {
		put(q, v3(p.x, top, p.z), normal, v3(0, 1, 0));
		return 0 - up;
	}
	if (side <= down) {
		vec3 c = v3_madd(o->centre, radial, o->radius);

		c.y = p.y;
		put(q, c, normal, radial);
		return 0 - side;
	}
	put(q, v3(p.x, bottom, p.z), normal, v3(0, -1, 0));
	return 0 - down;
}

static vec3
closest_on_segment(vec3 p, vec3 a, vec3 b)
{
	vec3 ab = v3_sub(b, a);
	double l2 = v3_dot(ab, ab);

	if (!(l2 > 0))
		return a;
	return v3_madd(a, ab, clamp(v3_dot(v3_sub(p, a), ab) / l2, 0, 1));
}

static double
dist2(vec3 a, vec3 b)
{
	vec3 d = v3_sub(a, b);

	return v3_dot(d, d);
}

/* A triangle of no area: the nearest of its edges. */
static vec3
closest_on_edges(vec3 p, vec3 a, vec3 b, vec3 c)
{
	vec3 best = closest_on_segment(p, a, b), x;

	if (dist2(p, x = closest_on_segment(p, b, c)) < dist2(p, best))
		best = x;
	if (dist2(p, x = closest_on_segment(p, c, a)) < dist2(p, best))
		best = x;
	return best;
}

/* Ericson, Real-Time Collision Detection, 5.1.5: the Voronoi regions of
 * the vertices, then the edges, then the face. */
static vec3
closest_on_triangle(vec3 p, vec3 a, vec3 b, vec3 c)
{
	vec3 ab = v3_sub(b, a), ac = v3_sub(c, a), n = v3_cross(ab, ac);
	vec3 ap = v3_sub(p, a), bp = v3_sub(p, b), cp = v3_sub(p, c);
	double d1, d2, d3, d4, d5, d6, va, vb, vc, den;

	if (v3_dot(n, n) == 0)
		return closest_on_edges(p, a, b, c);
	d1 = v3_dot(ab, ap);
	d2 = v3_dot(ac, ap);
	if (d1 <= 0 && d2 <= 0)
		return a;
	d3 = v3_dot(ab, bp);
	d4 = v3_dot(ac, bp);
	if (d3 >= 0 && d4 <= d3)
		return b;
	vc = d1 * d4 - d3 * d2;
	if (vc <= 0 && d1 >= 0 && d3 <= 0)
		return v3_madd(a, ab, d1 / (d1 - d3));
	d5 = v3_dot(ab, cp);
	d6 = v3_dot(ac, cp);
	if (d6 >= 0 && d5 <= d6)
		return c;
	vb = d5 * d2 - d1 * d6;
	if (vb <= 0 && d2 >= 0 && d6 <= 0)
		return v3_madd(a, ac, d2 / (d2 - d6));
	va = d3 * d6 - d5 * d4;
	if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
		return v3_madd(b, v3_sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
	/* rounding on a sliver can leave no face region */
	if (!((den = va + vb + vc) > 0))
		return closest_on_edges(p, a, b, c);
	return v3_add(a, v3_add(v3_scale(ab, vb / den), v3_scale(ac, vc / den)));
}

static double
mesh_distance(const struct obstacle *o, vec3 p, vec3 *q, vec3 *normal)
{
	const struct mesh *m = &o->mesh;
	double best = INFINITY, d, sign;
	vec3 qb = p, face = v3(0, 1, 0);
	size_t t;

	for (t = 0; t < m->ntri; t++) {
		const int *i = m->tri + 3 * t;
		vec3 a = v3_load(m->x + 3 * i[0]), b = v3_load(m->x + 3 * i[1]);
		vec3 c = v3_load(m->x + 3 * i[2]), x = closest_on_triangle(p, a, b, c);

		if ((d = dist2(p, x)) < best) {
			best = d;
			qb = x;
			face = v3_cross(v3_sub(b, a), v3_sub(c, a));
		}
	}
	if (m->ntri == 0) {
		put(q, p, normal, face);
		return INFINITY;
	}
	sign = mesh_winding_number(m, p) >= 0.5 ? -1 : 1;
	d = sqrt(best);
	/* on the surface p - q is rounding noise: the face's own normal */
	if (d > 1e-12 * (fabs(qb.x) + fabs(qb.y) + fabs(qb.z) + sqrt(v3_len(face))))
		put(q, qb, normal, v3_scale(v3_sub(p, qb), sign / d));
	else
		put(q, qb, normal, v3_scale(face, 1 / v3_len(face)));
	return sign * d;
}

double
obstacle_distance(const struct obstacle *o, vec3 p, vec3 *q, vec3 *normal)
{
	switch (o->kind) {
	case OBSTACLE_PLANE:
		return plane_distance(o, p, q, normal);
	case OBSTACLE_BOX:
		return box_distance(o, p, q, normal);
	case OBSTACLE_SPHERE:
		return sphere_distance(o, p, q, normal);
	case OBSTACLE_DISC:
		return disc_distance(o, p, q, normal);
	case OBSTACLE_MESH:
		break;
	}
	return mesh_distance(o, p, q, normal);
}

void
obstacle_bounds(const struct obstacle *o, vec3 *lo, vec3 *hi)
{
	vec3 r;

	switch (o->kind) {
	case OBSTACLE_PLANE:
		*lo = v3(-INFINITY, -INFINITY, -INFINITY);
		*hi = v3(INFINITY, INFINITY, INFINITY);
		/* along an axis the solid ends at the point */
		if (o->normal.y == 0 && o->normal.z == 0) {
			if (o->normal.x > 0)
				hi->x = o->point.x;
			else
				lo->x = o->point.x;
		} else if (o->normal.x == 0 && o->normal.z == 0) {
			if (o->normal.y > 0)
				hi->y = o->point.y;
			else
				lo->y = o->point.y;
		} else if (o->normal.x == 0 && o->normal.y == 0) {
			if (o->normal.z > 0)
				hi->z = o->point.z;
			else
				lo->z = o->point.z;
		}
		return;
	case OBSTACLE_BOX:
		*lo = o->lo;
		*hi = o->hi;
		return;
	case OBSTACLE_SPHERE:
		r = v3(o->radius, o->radius, o->radius);
		*lo = v3_sub(o->centre, r);
		*hi = v3_add(o->centre, r);
		return;
	case OBSTACLE_DISC:
		*lo = v3(o->centre.x - o->radius, o->centre.y - o->height, o->centre.z - o->radius);
		*hi = v3(o->centre.x + o->radius, o->centre.y, o->centre.z + o->radius);
		return;
	case OBSTACLE_MESH:
		break;
	}
	mesh_bounds(&o->mesh, lo, hi);
}

static int
finite3(vec3 v)
{
	return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

static int
check_mesh(const struct mesh *m, struct drape_err *err)
{
	size_t t;
	int v;

	if (m->ntri == 0) {
		err_set(err, "expected a mesh of at least one triangle, got none");
		return -1;
	}
	for (v = 0; v < m->nverts; v++)
		if (!finite3(v3_load(m->x + 3 * v))) {
			err_set(err, "expected finite vertex coordinates, got vertex %d at "
			    "%g %g %g", v + 1, m->x[3 * v], m->x[3 * v + 1], m->x[3 * v + 2]);
			return -1;
		}
	for (t = 0; t < 3 * m->ntri; t++)
		if (m->tri[t] < 0 || m->tri[t] >= m->nverts) {
			err_set(err, "expected vertex indices below %d, got %d", m->nverts,
			    m->tri[t]);
			return -1;
		}
	return 0;
}

static int
check_length(const char *key, double x, struct drape_err *err)
{
	if (!(x > 0) || !isfinite(x)) {
		err_set(err, "%s: expected a finite length greater than 0, got %g", key, x);
		return -1;
	}
	return 0;
}

int
obstacle_check(struct obstacle *o, struct drape_err *err)
{
	static const char axis[] = "xyz";
	double lo[3], hi[3], big;
	int k;

	if (!(o->friction >= 0) || !isfinite(o->friction)) {
		err_set(err, "friction: expected a finite number of 0 or more, got %g",
		    o->friction);
		return -1;
	}
	switch (o->kind) {
	case OBSTACLE_PLANE:
		if (!finite3(o->point)) {
			err_set(err, "point: expected finite coordinates, got %g %g %g",
			    o->point.x, o->point.y, o->point.z);
			return -1;
		}
		/* by the largest component first, so that no square under- or
		 * overflows */
		big = fmax(fabs(o->normal.x), fmax(fabs(o->normal.y), fabs(o->normal.z)));
		/* not subnormal: 1 / big would overflow */
		if (!finite3(o->normal) || !(big >= DBL_MIN)) {
			err_set(err, "normal: expected a finite vector with a component of at least "
			    "%g either way, got %g %g %g", DBL_MIN, o->normal.x, o->normal.y,
			    o->normal.z);
			return -1;
		}
		o->normal = v3_scale(o->normal, 1 / big);
		o->normal = v3_scale(o->normal, 1 / v3_len(o->normal));
		return 0;
	case OBSTACLE_BOX:
		v3_store(lo, o->lo);
		v3_store(hi, o->hi);
		for (k = 0; k < 3; k++)
			if (!isfinite(lo[k]) || !isfinite(hi[k]) || !(lo[k] < hi[k])) {
				err_set(err, "min, max: expected finite values with min < max on "
				    "every axis, got %g and %g on %c", lo[k], hi[k], axis[k]);
				return -1;
			}
		return 0;
	case OBSTACLE_SPHERE:
	case OBSTACLE_DISC:
		if (!finite3(o->centre)) {
			err_set(err, "centre: expected finite coordinates, got %g %g %g",
			    o->centre.x, o->centre.y, o->centre.z);
			return -1;
		}
		if (check_length("radius", o->radius, err) != 0 ||
		    (o->kind == OBSTACLE_DISC && check_length("height", o->height, err) != 0))
			return -1;
		return 0;
	case OBSTACLE_MESH:
		break;
	}
	return check_mesh(&o->mesh, err);
}

void
obstacle_free(struct obstacle *o)
{
	mesh_free(&o->mesh);
	free(o->file);
	o->file = NULL;
}

/* The depth is the least of six functions linear in t (one a face), so
 * its maximum over [0, 1] lies at an end or where two of them cross: 17
 * candidates, no search. */
double
obstacle_box_segment_depth(vec3 lo, vec3 hi, vec3 a, vec3 b, double *tp, vec3 *n)
{
	double pa[3], pb[3], l[3], h[3], al[6], be[6], cand[17], best = -INFINITY, nv[3] = { 0 };
	int k, j, nc = 0, face = 0;

	v3_store(pa, a);
	v3_store(pb, b);
	v3_store(l, lo);
	v3_store(h, hi);
	for (k = 0; k < 3; k++) {
		al[2 * k] = pa[k] - l[k];	/* over the low face */
		be[2 * k] = pb[k] - pa[k];
		al[2 * k + 1] = h[k] - pa[k];	/* under the high face */
		be[2 * k + 1] = pa[k] - pb[k];
	}
	cand[nc++] = 0;
	cand[nc++] = 1;
	for (k = 0; k < 6; k++)
		for (j = k + 1; j < 6; j++)
			if (be[k] != be[j]) {
				double t = (al[j] - al[k]) / (be[k] - be[j]);

				if (t > 0 && t < 1)
					cand[nc++] = t;
			}
	for (j = 0; j < nc; j++) {
		double d = INFINITY;
		int f = 0;

		for (k = 0; k < 6; k++)
			if (al[k] + be[k] * cand[j] < d) {
				d = al[k] + be[k] * cand[j];
				f = k;
			}
		if (d > best) {
			best = d;
			*tp = cand[j];
			face = f;
		}
	}
	nv[face / 2] = face % 2 ? 1 : -1;
	*n = v3_load(nv);
	return best;
}

/*
 * A box's nearest point along a-b, exactly: outside, the squared distance
 * is a sum of the axes' gaps squared, each gap linear in t between the
 * points where the segment crosses the box's slabs (at most six), so it
 * is a quadratic on each piece, least at its vertex or an end of the
 * piece (the lowest t where it is flat); where that least is 0 the
 * segment reaches the box, and its deepest point is
 * obstacle_box_segment_depth's. The golden section below gives the same
 * to 1e-6 in t for some ten times the cost, which bdf2's edge contacts
 * pay at every Phi (bench-history.md, bdf2.sh, stop 47).
 */
static double
box_segment_nearest(const struct obstacle *o, vec3 a, vec3 b)
{
	double pa[3], ab[3], l[3], h[3], cut[8], best = INFINITY, bt = 0, tmp;
	int k, i, j, nc = 0;
	vec3 n;

	v3_store(pa, a);
	v3_store(ab, v3_sub(b, a));
	v3_store(l, o->lo);
	v3_store(h, o->hi);
	cut[nc++] = 0;
	for (k = 0; k < 3; k++)
		if (ab[k] != 0) {
			double t0 = (l[k] - pa[k]) / ab[k], t1 = (h[k] - pa[k]) / ab[k];

			if (t0 > 0 && t0 < 1)
				cut[nc++] = t0;
			if (t1 > 0 && t1 < 1)
				cut[nc++] = t1;
		}
	cut[nc++] = 1;
	for (i = 1; i < nc; i++)	/* insertion sort: at most 8 */
		for (j = i; j > 0 && cut[j] < cut[j - 1]; j--) {
			tmp = cut[j];
			cut[j] = cut[j - 1];
			cut[j - 1] = tmp;
		}
	for (i = 0; i + 1 < nc; i++) {
		double tm = 0.5 * (cut[i] + cut[i + 1]), c[3], sdd = 0, scd = 0, t, d2 = 0;

		for (k = 0; k < 3; k++) {	/* the gap on this piece: c + ab t */
			double p = pa[k] + ab[k] * tm;

			c[k] = p < l[k] ? pa[k] - l[k] : p > h[k] ? pa[k] - h[k] : 0;
			if (c[k] != 0) {
				sdd += ab[k] * ab[k];
				scd += c[k] * ab[k];
			}
		}
		t = sdd > 0 ? -scd / sdd : cut[i];
		t = t < cut[i] ? cut[i] : t > cut[i + 1] ? cut[i + 1] : t;
		for (k = 0; k < 3; k++)
			if (c[k] != 0)
				d2 += (c[k] + ab[k] * t) * (c[k] + ab[k] * t);
		if (d2 < best) {
			best = d2;
			bt = t;
		}
	}
	if (!(best > 0))
		obstacle_box_segment_depth(o->lo, o->hi, a, b, &bt, &n);
	return bt;
}

/* Golden section: the signed distance to a convex solid (each analytic
 * obstacle is one) is convex along a line, so the search closes on its
 * one minimum; 48 steps shrink [0, 1] 0.618^48 = 1e-10 times. A box's is
 * exact (box_segment_nearest). */
double
obstacle_segment_nearest(const struct obstacle *o, vec3 a, vec3 b, double *tp)
{
	const double g = 0.6180339887498949;
	double lo = 0, hi = 1, t1 = hi - g, t2 = g, f1, f2, t, f, fa, fb;
	vec3 ab = v3_sub(b, a);
	int k;

	if (o->kind == OBSTACLE_BOX) {
		t = box_segment_nearest(o, a, b);
		f = obstacle_distance(o, v3_madd(a, ab, t), NULL, NULL);
		goto ends;
	}
	f1 = obstacle_distance(o, v3_madd(a, ab, t1), NULL, NULL);
	f2 = obstacle_distance(o, v3_madd(a, ab, t2), NULL, NULL);
	for (k = 0; k < 48; k++)
		if (f1 <= f2) {
			hi = t2;
			t2 = t1;
			f2 = f1;
			t1 = hi - g * (hi - lo);
			f1 = obstacle_distance(o, v3_madd(a, ab, t1), NULL, NULL);
		} else {
			lo = t1;
			t1 = t2;
			f1 = f2;
			t2 = lo + g * (hi - lo);
			f2 = obstacle_distance(o, v3_madd(a, ab, t2), NULL, NULL);
		}
	t = f1 <= f2 ? t1 : t2;
	f = f1 <= f2 ? f1 : f2;
ends:
	/* the ends, which the search only nears */
	fa = obstacle_distance(o, a, NULL, NULL);
	fb = obstacle_distance(o, b, NULL, NULL);
	if (fa <= f && fa <= fb) {
		t = 0;
		f = fa;
	} else if (fb < f) {
		t = 1;
		f = fb;
	}
	*tp = t;
	return f;
}
