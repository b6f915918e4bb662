/* ccd.c: conservative continuous collision tests, vertex-face and
 * edge-edge, each point moving linearly from x0 (t = 0) to x1 (t = 1).
 *
 * Contact needs the four points coplanar: f(t) = det(A, B, C) = 0 with
 * A, B, C the points 1..3 less point 0, each linear in t. f is a cubic,
 * kept in Bernstein form on [0, 1] because its coefficients bound it (the
 * convex hull property) and halving it (de Casteljau) only averages. A
 * depth-first search halves [0, 1]; an interval is dropped when
 *   - f cannot vanish on it: every coefficient is above r, or every one
 *     below -r, where r bounds the rounding so far, or
 *   - a fixed axis separates the primitives by more than the rounding
 *     slack plus eta at both ends of the interval: the projected gap
 *     between two points is linear in t, so it holds throughout. This is
 *     the inside (vertex-face) or overlap (edge-edge) test, and it accounts
 *     for the motion over the interval exactly.
 * The first interval that survives to the depth limit (or once the budget
 * of intervals is spent) is reported, its start as the time of impact:
 * every earlier time was ruled out.
 *
 * Error bounds, u = 2^-53 the unit roundoff:
 *   - Each term of a coefficient is a product of three coordinate
 *     differences, computed with at most 10 roundings (3 differences, 2
 *     products, the cross product's difference, 2 + 2 sums), so the error
 *     is at most gamma_10 = 10u/(1 - 10u) times the same sum taken over
 *     absolute values (a permanent), which is at most 6 ma mb mc, the
 *     largest coordinates of the three differences. 96u ma mb mc covers
 *     that, the scaling by 1/3 and the rounding of the m's.
 *   - A halving forms three rounds of averages, each within u of the exact
 *     average of its rounded inputs, so it adds at most 3u (1 + u)^3 times
 *     the largest coefficient; 8u is used. Averages do not amplify the
 *     error already in r.
 *   - A point at time t is x0 + t (x1 - x0): within 5.1 u S of exact per
 *     coordinate, S the largest input coordinate magnitude. A projection
 *     n.p adds gamma_3 |n|_1 S, and the gap of two projections one more
 *     rounding: 18.2 u S |n|_1 in all; 24 u S |n|_1 is used.
 *   - Terms of 2^-1060 and DBL_MIN cover underflow; overflow gives
 *     infinities, which never prune, or the early answer 1.
 *   - up() rounds a computed bound up past the roundings in computing it. */
#include <float.h>
#include <math.h>
#include <stddef.h>

#include "ccd.h"

#define U	(DBL_EPSILON / 2)
#define DEPTH	32		/* halvings: a contact time to within 2^-32 */
#define BUDGET	256		/* intervals visited before giving up with 1 */
#define TINY	0x1p-1060	/* underflow, relative to a coordinate */

struct ccd {
	vec3 x0[4], d[4];	/* start and motion over the step */
	int na;			/* points in the first primitive: 1 or 2 */
	double slack;		/* a gap's rounding plus eta, per unit of |n|_1 */
	int budget;
};

/* x * (1 + 2^-50) >= x(1 + 2^-51) after its own rounding: above x by
 * more than the few roundings that produced x. */
static inline double
up(double x)
{
	return x * (1 + 8 * U);
}

/* Not fmin and fmax: those are calls here, in the hot path. */
static inline double
lesser(double a, double b)
{
	return a < b ? a : b;
}

static inline double
greater(double a, double b)
{
	return a > b ? a : b;
}

static inline void
grow(vec3 *lo, vec3 *hi, vec3 p)
{
	*lo = v3(lesser(lo->x, p.x), lesser(lo->y, p.y), lesser(lo->z, p.z));
	*hi = v3(greater(hi->x, p.x), greater(hi->y, p.y), greater(hi->z, p.z));
}

/* Exact: fl(lo - hi) > eta implies lo - hi > eta, since rounding is
 * monotonic and eta is a double. No early exits: random outcomes would
 * mispredict. */
static int
boxes_apart(const vec3 x0[4], const vec3 x1[4], int na, double eta)
{
	vec3 alo = x0[0], ahi = x0[0], blo = x0[3], bhi = x0[3];
	int k;

	for (k = 0; k < na; k++) {
		grow(&alo, &ahi, x0[k]);
		grow(&alo, &ahi, x1[k]);
	}
	for (k = na; k < 4; k++) {
		grow(&blo, &bhi, x0[k]);
		grow(&blo, &bhi, x1[k]);
	}
	return (blo.x - ahi.x > eta) | (alo.x - bhi.x > eta) |
	    (blo.y - ahi.y > eta) | (alo.y - bhi.y > eta) |
	    (blo.z - ahi.z > eta) | (alo.z - bhi.z > eta);
}

static inline double
v3_max(vec3 a)
{
	return greater(greater(fabs(a.x), fabs(a.y)), fabs(a.z));
}

/* Bernstein coefficients b of f on [0, 1], and r >= |b_k - exact b_k|.
 * By multilinearity, with A(t) = (1 - t) A0 + t A1 and so on, the
 * coefficient of (1 - t)^(3-k) t^k sums the determinants taking k of
 * A, B, C at t = 1; b_k divides it by binomial(3, k). Each b_k's
 * permanent is at most 6 ma mb mc, the largest coordinates of A, B, C. */
static void
cubic(const vec3 x0[4], const vec3 x1[4], double b[4], double *r)
{
	vec3 a[2], bb[2], cc[2], x[2][2];
	double ma = 0, mb = 0, mc = 0;
	int i, j;

	for (i = 0; i < 2; i++) {
		const vec3 *y = i ? x1 : x0;

		a[i] = v3_sub(y[1], y[0]);
		bb[i] = v3_sub(y[2], y[0]);
		cc[i] = v3_sub(y[3], y[0]);
		ma = greater(ma, v3_max(a[i]));
		mb = greater(mb, v3_max(bb[i]));
		mc = greater(mc, v3_max(cc[i]));
	}
	for (i = 0; i < 2; i++)
		for (j = 0; j < 2; j++)
			x[i][j] = v3_cross(bb[i], cc[j]);
	b[0] = v3_dot(a[0], x[0][0]);
	b[1] = (v3_dot(a[1], x[0][0]) + v3_dot(a[0], x[1][0]) + v3_dot(a[0], x[0][1])) *
	    (1.0 / 3);
	b[2] = (v3_dot(a[0], x[1][1]) + v3_dot(a[1], x[1][0]) + v3_dot(a[1], x[0][1])) *
	    (1.0 / 3);
	b[3] = v3_dot(a[1], x[1][1]);
	*r = up(96 * U * (ma * mb * mc) + TINY * (1 + ma) + DBL_MIN);
}

/* 1 if axis n separates the first na points from the rest by more than
 * the slack at both ends of the interval, p0 and p1. */
static int
apart(const struct ccd *c, vec3 n, const vec3 p0[4], const vec3 p1[4])
{
	double s = up(c->slack * (fabs(n.x) + fabs(n.y) + fabs(n.z)) + DBL_MIN);
	int below = 1, above = 1, e, k;

	for (e = 0; e < 2 && (below || above); e++) {
		const vec3 *p = e ? p1 : p0;
		double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };

		for (k = 0; k < 4; k++) {
			double v = v3_dot(n, p[k]);
			int side = k >= c->na;

			lo[side] = lesser(lo[side], v);
			hi[side] = greater(hi[side], v);
		}
		below &= lo[1] - hi[0] > s;
		above &= lo[0] - hi[1] > s;
	}
	return below || above;
}

/* The separating-axis test over an interval; pm, the points at its middle,
 * give the axes (any axis is sound; these suit small intervals). The axes
 * are the coordinate ones (the swept box), then for a vertex and triangle
 * the normal and the three edges' in-plane normals, and for two edges the
 * normal, each edge's in-plane normal, and for parallel or point-like
 * edges each edge's direction and its normal towards the other edge. */
static int
separated(const struct ccd *c, const vec3 p0[4], const vec3 p1[4], const vec3 pm[4])
{
	vec3 ax[10];
	int k, n = 0;

	ax[n++] = v3(1, 0, 0);
	ax[n++] = v3(0, 1, 0);
	ax[n++] = v3(0, 0, 1);
	if (c->na == 1) {
		vec3 nn = v3_cross(v3_sub(pm[2], pm[1]), v3_sub(pm[3], pm[1]));

		ax[n++] = nn;
		for (k = 1; k <= 3; k++)
			ax[n++] = v3_cross(nn, v3_sub(pm[k % 3 + 1], pm[k]));
	} else {
		vec3 ea = v3_sub(pm[1], pm[0]), eb = v3_sub(pm[3], pm[2]);
		vec3 nn = v3_cross(ea, eb);

		ax[n++] = nn;
		ax[n++] = v3_cross(nn, ea);
		ax[n++] = v3_cross(nn, eb);
		ax[n++] = ea;
		ax[n++] = v3_cross(v3_cross(ea, v3_sub(pm[2], pm[0])), ea);
		ax[n++] = v3_cross(v3_cross(eb, v3_sub(pm[0], pm[2])), eb);
	}
	for (k = 0; k < n; k++)
		if (apart(c, ax[k], p0, p1))
			return 1;
	return 0;
}

static void
at(const struct ccd *c, double t, vec3 p[4])
{
	int k;

	for (k = 0; k < 4; k++)
		p[k] = v3_madd(c->x0[k], c->d[k], t);
}

/* Searches [t0, t1], where f has coefficients b within r, and the points
 * are p0 and p1 at the ends. Returns 1 with *toi = t0 at the first
 * interval that could not be ruled out. */
static int
search(struct ccd *c, double t0, double t1, const double b[4], double r,
    const vec3 p0[4], const vec3 p1[4], int depth, double *toi)
{
	double lo = lesser(lesser(b[0], b[1]), lesser(b[2], b[3]));
	double hi = greater(greater(b[0], b[1]), greater(b[2], b[3]));
	double tm = (t0 + t1) / 2, l[4], h[4], m, rr;
	vec3 pm[4];

	if (lo > r || hi < -r)
		return 0;
	at(c, tm, pm);
	if (separated(c, p0, p1, pm))
		return 0;
	if (depth == DEPTH || --c->budget < 0) {
		*toi = t0;
		return 1;
	}
	l[0] = b[0];
	l[1] = (b[0] + b[1]) / 2;
	m = (b[1] + b[2]) / 2;
	h[2] = (b[2] + b[3]) / 2;
	l[2] = (l[1] + m) / 2;
	h[1] = (m + h[2]) / 2;
	l[3] = h[0] = (l[2] + h[1]) / 2;
	h[3] = b[3];
	rr = up(r + 8 * U * greater(-lo, hi) + DBL_MIN);
	return search(c, t0, tm, l, rr, p0, pm, depth + 1, toi) ||
	    search(c, tm, t1, h, rr, pm, p1, depth + 1, toi);
}

static int
ccd(const vec3 x0[4], const vec3 x1[4], int na, double eta, double *toi)
{
	struct ccd c;
	double b[4], r, s = 0, t;
	int k;

	if (toi == NULL)
		toi = &t;
	if (!(eta > 0))
		eta = 0;	/* a negative or NaN margin would reject contacts */
	if (boxes_apart(x0, x1, na, eta))
		return 0;
	cubic(x0, x1, b, &r);
	/* the common answer: never coplanar in [0, 1] */
	if (eta == 0 && ((b[0] > r) & (b[1] > r) & (b[2] > r) & (b[3] > r)))
		return 0;
	if (eta == 0 && ((b[0] < -r) & (b[1] < -r) & (b[2] < -r) & (b[3] < -r)))
		return 0;
	for (k = 0; k < 4; k++)
		s = greater(s, greater(v3_max(x0[k]), v3_max(x1[k])));
	/* too large (or not finite) to bound: the boxes overlap, so 1 */
	if (!(r < 0x1p1000 && s < 0x1p1000)) {
		*toi = 0;
		return 1;
	}
	for (k = 0; k < 4; k++) {
		c.x0[k] = x0[k];
		c.d[k] = v3_sub(x1[k], x0[k]);
	}
	c.na = na;
	c.slack = up(24 * U * s + eta + TINY * (1 + s));
	c.budget = BUDGET;
	if (eta > 0 && !separated(&c, x0, x0, x0)) {
		*toi = 0;
		return 1;
	}
	if (search(&c, 0, 1, b, r, x0, x1, 0, toi))
		return 1;
	/* within eta at the end: the first such time is not known */
	if (eta > 0 && !separated(&c, x1, x1, x1)) {
		*toi = 0;
		return 1;
	}
	return 0;
}

int
ccd_vertex_face(const vec3 x0[4], const vec3 x1[4], double eta, double *toi)
{
	return ccd(x0, x1, 1, eta, toi);
}

int
ccd_edge_edge(const vec3 x0[4], const vec3 x1[4], double eta, double *toi)
{
	return ccd(x0, x1, 2, eta, toi);
}
