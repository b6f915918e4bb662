/* narrow.c: the chapter's node-triangle test, eq. 1-10, as written. */
#include <float.h>
#include <math.h>

#include <stddef.h>

#include "narrow.h"

const char *const narrow_mode_name[] = { "seed", "ccd", NULL };
const char *const seed_segments_name[] = { "both", "path", "edges", NULL };
const char *const contact_type_name[CONTACT_NTYPES] = {
	"node-node", "node-edge", "node-face", "edge-edge", "obstacle"
};

/* eq. 9: the angle at q between q->u and q->w, by arccos as the chapter
 * does (the clamp keeps rounding from leaving acos's domain). */
static double
angle_at(vec3 q, vec3 u, vec3 w)
{
	vec3 v1 = v3_sub(u, q), v2 = v3_sub(w, q);
	double d = v3_len(v1) * v3_len(v2), c;

	if (d == 0)
		return 0;
	c = v3_dot(v1, v2) / d;
	return acos(c > 1 ? 1 : c < -1 ? -1 : c);
}

/* eq. 9-10: Q inside by the sum of the angles about it. */
static int
inside_by_angles(vec3 q, const vec3 p[3], struct seed_hit *hit)
{
	double ang[3], sum = 0;
	int e;

	for (e = 0; e < 3; e++) {
		ang[e] = angle_at(q, p[e], p[(e + 1) % 3]);	/* alpha, beta, gamma */
		sum += ang[e];
	}
	/* an angle of pi puts Q on the edge between the two vertices */
	for (e = 0; e < 3; e++)
		if (fabs(ang[e] - V3_PI) <= SEED_EPS) {
			hit->type = CONTACT_NODE_EDGE;
			hit->feature = e;
			return 1;
		}
	if (fabs(sum - 2 * V3_PI) <= SEED_EPS) {
		hit->type = CONTACT_NODE_FACE;
		hit->feature = -1;
		return 1;
	}
	return 0;
}

/* The chapter's alternative to eq. 9-10: in plane axes centred on Q, the
 * positive X axis crosses the perimeter once when Q is inside. An edge
 * crosses the axis where its Y changes sign. */
static int
inside_by_crossing(vec3 q, const vec3 p[3], vec3 n, double tol, struct seed_hit *hit)
{
	vec3 ex = v3_sub(p[1], p[0]), ey;
	double x[3], y[3], len = v3_len(ex);
	int e, crossings = 0;

	ex = v3_scale(ex, 1 / len);
	ey = v3_cross(n, ex);
	for (e = 0; e < 3; e++) {
		vec3 r = v3_sub(p[e], q);

		x[e] = v3_dot(r, ex);
		y[e] = v3_dot(r, ey);
	}
	for (e = 0; e < 3; e++) {
		int f = (e + 1) % 3;
		double dx = x[f] - x[e], dy = y[f] - y[e], l = hypot(dx, dy);

		/* on the edge itself, within rounding: a node-edge contact */
		if (l > 0 && fabs(x[e] * dy - y[e] * dx) <= tol * l &&
		    x[e] * dx + y[e] * dy <= 0 && x[f] * dx + y[f] * dy >= 0) {
			hit->type = CONTACT_NODE_EDGE;
			hit->feature = e;
			return 1;
		}
		if ((y[e] > 0) != (y[f] > 0) && x[e] - y[e] * dx / dy > 0)
			crossings++;
	}
	if (crossings == 1) {
		hit->type = CONTACT_NODE_FACE;
		hit->feature = -1;
		return 1;
	}
	return 0;
}

int
narrow_seed_segment(vec3 f, vec3 d, vec3 a, vec3 b, vec3 c, enum inside_test how,
    struct seed_hit *hit)
{
	vec3 p[3] = { a, b, c }, n, r;
	double len, sf, sd, s, tq, scale, tol;
	int k;

	n = v3_cross(v3_sub(b, a), v3_sub(c, a));
	if ((len = v3_len(n)) == 0 || !isfinite(len))
		return 0;
	n = v3_scale(n, 1 / len);
	/* eq. 1-2: the sides of the plane that F (step k) and D (step k+1) are on */
	sf = v3_dot(v3_sub(f, a), n);
	sd = v3_dot(v3_sub(d, a), n);
	if (!((sf > 0 && sd <= 0) || (sf < 0 && sd >= 0)))
		return 0;
	/* eq. 5-8: Q where the line r through F and D meets the plane;
	 * p = n.F - n.A = sf and s = n.r */
	r = v3_sub(d, f);
	s = v3_dot(n, r);
	tq = -sf / s;
	hit->q = v3_madd(f, r, tq);
	hit->tq = tq;
	hit->n = n;

	/* Q on a vertex, "within the precision of the machine": the tests
	 * below cannot answer there (the angles about Q are undefined) */
	scale = fmax(fmax(v3_len(v3_sub(b, a)), v3_len(v3_sub(c, b))), v3_len(v3_sub(a, c)));
	tol = 64 * DBL_EPSILON * (scale + v3_len(hit->q));
	for (k = 0; k < 3; k++)
		if (v3_len(v3_sub(hit->q, p[k])) <= tol) {
			hit->type = CONTACT_NODE_NODE;
			hit->feature = k;
			return 1;
		}
	if (how == INSIDE_CROSSING)
		return inside_by_crossing(hit->q, p, n, tol, hit);
	return inside_by_angles(hit->q, p, hit);
}
