/* check.c: the audit of a state, apart from the collision code it checks. */
#include <math.h>

#include "audit.h"
#include "check.h"

/*
 * The least signed distance to the solid along the segment a-b, by golden
 * section: the distance to a convex solid (each analytic obstacle is one)
 * is convex along a line, so the search closes on its one minimum. 60
 * steps shrink the interval 0.618^60 = 3e-13 times, far under a cloth's
 * roundings. The search is the audit's own, written apart from the
 * methods' (pbd.c's depth into a box, bdf2.c's, obstacle.h), which it
 * checks.
 */
static double
least_along(const struct obstacle *ob, vec3 a, vec3 b)
{
	const double g = 0.6180339887498949;
	double lo = 0, hi = 1, t1 = hi - g * (hi - lo), t2 = lo + g * (hi - lo), f1, f2, fe;
	vec3 ab = v3_sub(b, a);
	int k;

	f1 = obstacle_distance(ob, v3_madd(a, ab, t1), NULL, NULL);
	f2 = obstacle_distance(ob, v3_madd(a, ab, t2), NULL, NULL);
	for (k = 0; k < 60; k++) {
		if (f1 <= f2) {
			hi = t2;
			t2 = t1;
			f2 = f1;
			t1 = hi - g * (hi - lo);
			f1 = obstacle_distance(ob, v3_madd(a, ab, t1), NULL, NULL);
		} else {
			lo = t1;
			t1 = t2;
			f1 = f2;
			t2 = lo + g * (hi - lo);
			f2 = obstacle_distance(ob, v3_madd(a, ab, t2), NULL, NULL);
		}
	}
	fe = fmin(obstacle_distance(ob, a, NULL, NULL), obstacle_distance(ob, b, NULL, NULL));
	return fmin(fmin(f1, f2), fe);
}

/* The cloth's edges that go into the analytic obstacle ob, into r. An
 * edge whose box misses the solid's bounds is skipped unsearched. */
static void
edges_into(const struct obstacle *ob, const struct cloth *cl, const double *x,
    struct check_result *r)
{
	vec3 lo, hi;
	size_t e;

	obstacle_bounds(ob, &lo, &hi);
	for (e = 0; e < cl->nedges; e++) {
		vec3 a = v3_load(x + 3 * cl->edge[2 * e]), b = v3_load(x + 3 * cl->edge[2 * e + 1]);
		double d;

		if (fmax(a.x, b.x) < lo.x || fmax(a.y, b.y) < lo.y || fmax(a.z, b.z) < lo.z ||
		    fmin(a.x, b.x) > hi.x || fmin(a.y, b.y) > hi.y || fmin(a.z, b.z) > hi.z)
			continue;
		if ((d = least_along(ob, a, b)) < 0) {
			r->edges_in++;
			r->edge_depth = fmax(r->edge_depth, -d);
		}
	}
}

int
check_state(const struct scene *sc, const struct cloth *cl, const double *x,
    struct check_result *r)
{
	struct audit_result a;
	size_t o;
	int p;

	r->inside = 0;
	r->edges_in = 0;
	r->edge_depth = 0;
	r->first[0] = r->first[1] = -1;
	if (audit_self(x, cl->tri, cl->ntri, r->first, &a) != 0)
		return -1;
	r->pairs = a.pairs;
	r->candidates = a.candidates;
	r->tests = a.tests;
	r->cut = a.cut;
	for (o = 0; o < sc->nobstacles; o++) {
		const struct obstacle *ob = &sc->obstacles[o];

		if (ob->kind == OBSTACLE_MESH) {
			if (audit_cross(x, cl->tri, cl->ntri, ob->mesh.x, ob->mesh.tri,
			    ob->mesh.ntri, &a) != 0)
				return -1;
			r->pairs += a.pairs;
			r->candidates += a.candidates;
			r->tests += a.tests;
			r->cut = r->cut || a.cut;
			continue;	/* a mesh is a surface: crossing it is what counts */
		}
		for (p = 0; p < cl->n; p++)
			if (obstacle_distance(ob, v3_load(x + 3 * p), NULL, NULL) < 0)
				r->inside++;
		edges_into(ob, cl, x, r);
	}
	return 0;
}
