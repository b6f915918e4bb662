/* audit.c: exact orientation predicates (a floating-point filter, then
 * expansion arithmetic when the filter cannot tell), the triangle-triangle
 * test of Guigue and Devillers (2003) on their signs alone, and a sweep and
 * prune on boxes, slab by slab, that hands it every pair of triangles whose
 * boxes touch. */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "audit.h"

/*
 * Expansions (Shewchuk 1997): a value held exactly as a sum of doubles,
 * smallest first and no two overlapping, so its sign is that of the last.
 * EXP_MAX covers the longest sum below (6 terms of 32 doubles) plus one.
 */
#define EXP_MAX 200

/* x + y = *s + *e exactly (Knuth's two-sum; round to nearest). */
static void
two_sum(double x, double y, double *s, double *e)
{
	double bv, av;

	*s = x + y;
	bv = *s - x;
	av = *s - bv;
	*e = (x - av) + (y - bv);
}

/* x * y = *p + *e exactly: fma rounds once, so it yields the error. */
static void
two_prod(double x, double y, double *p, double *e)
{
	*p = x * y;
	*e = fma(x, y, -*p);
}

/* e += b in place (e has room for one more). Zeros are dropped, so n == 0
 * is the value 0 and e[n - 1] carries the sign. */
static void
grow(double *e, int *n, double b)
{
	double q = b, s, err;
	int i, k = 0;

	if (b == 0)
		return;
	for (i = 0; i < *n; i++) {
		two_sum(q, e[i], &s, &err);
		q = s;
		if (err != 0)
			e[k++] = err;
	}
	if (q != 0)
		e[k++] = q;
	*n = k;
}

/* A difference of two inputs, exactly: a - b = v[0] + v[1]. */
struct diff {
	double v[2];
};

static struct diff
diff(double a, double b)
{
	struct diff d;

	two_sum(a, -b, &d.v[0], &d.v[1]);
	return d;
}

/* e += s * x * y * z, s = +-1: up to 8 products of three doubles, each 4
 * doubles exactly. Zero parts are skipped; they are the common case, as
 * differences of nearby coordinates are exact and a flat cloth has dz = 0. */
static void
add_prod(double *e, int *n, double s, struct diff x, struct diff y, struct diff z)
{
	double p, pe, h, l;
	int i, j, k;

	for (i = 0; i < 2; i++)
		for (j = 0; j < 2; j++)
			for (k = 0; k < 2; k++) {
				if (x.v[i] == 0 || y.v[j] == 0 || z.v[k] == 0)
					continue;
				two_prod(x.v[i], y.v[j], &p, &pe);
				two_prod(p, z.v[k], &h, &l);
				grow(e, n, s * l);
				grow(e, n, s * h);
				two_prod(pe, z.v[k], &h, &l);
				grow(e, n, s * l);
				grow(e, n, s * h);
			}
}

static int
sign_of(const double *e, int n)
{
	return n == 0 ? 0 : e[n - 1] > 0 ? 1 : -1;
}

/*
 * Filters. With u = 2^-53, a term of the double orient3d below passes
 * through 8 roundings (3 differences, 2 products, a subtraction, 2 sums), so
 * the error is under ((1 + u)^8 - 1) times the sum of the terms' exact
 * magnitudes, which the computed sum underestimates by (1 - u)^9 at most:
 * 9u times the computed sum covers both and the rounding of the bound.
 * orient2d has 4 roundings a term: 5u.
 */
#define U (DBL_EPSILON / 2)
#define O3_BOUND (9 * U)
#define O2_BOUND (5 * U)

static double
at(vec3 a, int k)
{
	return k == 0 ? a.x : k == 1 ? a.y : a.z;
}

int
audit_orient3d(vec3 a, vec3 b, vec3 c, vec3 d)
{
	double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
	double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
	double wx = d.x - a.x, wy = d.y - a.y, wz = d.z - a.z;
	double det, perm, e[EXP_MAX];
	struct diff u[3], v[3], w[3];
	int k, n = 0;

	det = wx * (uy * vz - uz * vy) + wy * (uz * vx - ux * vz) + wz * (ux * vy - uy * vx);
	perm = fabs(wx) * (fabs(uy * vz) + fabs(uz * vy)) +
	    fabs(wy) * (fabs(uz * vx) + fabs(ux * vz)) +
	    fabs(wz) * (fabs(ux * vy) + fabs(uy * vx));
	if (det > O3_BOUND * perm)
		return 1;
	if (-det > O3_BOUND * perm)
		return -1;
	if (perm == 0)		/* every term has a difference 0 as a factor */
		return 0;

	/* too close to call: the same sum, exactly */
	for (k = 0; k < 3; k++) {
		u[k] = diff(at(b, k), at(a, k));
		v[k] = diff(at(c, k), at(a, k));
		w[k] = diff(at(d, k), at(a, k));
	}
	add_prod(e, &n, 1, w[0], u[1], v[2]);
	add_prod(e, &n, -1, w[0], u[2], v[1]);
	add_prod(e, &n, 1, w[1], u[2], v[0]);
	add_prod(e, &n, -1, w[1], u[0], v[2]);
	add_prod(e, &n, 1, w[2], u[0], v[1]);
	add_prod(e, &n, -1, w[2], u[1], v[0]);
	return sign_of(e, n);
}

/* A point of a coordinate plane. */
struct pt {
	double x, y;
};

/* Drops coordinate k and keeps the other two in cyclic order, so that
 * orient2d of a projected triangle has the sign of its normal's k. */
static struct pt
proj(vec3 a, int k)
{
	return k == 0 ? (struct pt){ a.y, a.z } : k == 1 ? (struct pt){ a.z, a.x } :
	    (struct pt){ a.x, a.y };
}

/* Sign of (b - a) x (c - a): +1 when a, b, c turn counter-clockwise. */
static int
orient2d(struct pt a, struct pt b, struct pt c)
{
	const struct diff one = { { 1, 0 } };
	double l = (b.x - a.x) * (c.y - a.y), r = (b.y - a.y) * (c.x - a.x);
	double det = l - r, e[EXP_MAX];
	int n = 0;

	if (det > O2_BOUND * (fabs(l) + fabs(r)))
		return 1;
	if (-det > O2_BOUND * (fabs(l) + fabs(r)))
		return -1;
	if (l == 0 && r == 0)
		return 0;
	add_prod(e, &n, 1, diff(b.x, a.x), diff(c.y, a.y), one);
	add_prod(e, &n, -1, diff(b.y, a.y), diff(c.x, a.x), one);
	return sign_of(e, n);
}

/* c, collinear with a and b, lies on the closed segment ab. */
static int
on_seg2(struct pt a, struct pt b, struct pt c)
{
	return fmin(a.x, b.x) <= c.x && c.x <= fmax(a.x, b.x) &&
	    fmin(a.y, b.y) <= c.y && c.y <= fmax(a.y, b.y);
}

/* Closed segments ab and cd share a point; either may be a point. */
static int
seg_seg2(struct pt a, struct pt b, struct pt c, struct pt d)
{
	int d1 = orient2d(a, b, c), d2 = orient2d(a, b, d);
	int d3 = orient2d(c, d, a), d4 = orient2d(c, d, b);

	if (d1 * d2 < 0 && d3 * d4 < 0)
		return 1;
	return (d1 == 0 && on_seg2(a, b, c)) || (d2 == 0 && on_seg2(a, b, d)) ||
	    (d3 == 0 && on_seg2(c, d, a)) || (d4 == 0 && on_seg2(c, d, b));
}

/* The line of an edge of t (a triangle with area, nt = 3, or a segment,
 * nt = 2) has all nu points of u strictly outside t (for a segment: on one
 * side). Two convex polygons that do not meet are parted by the line of an
 * edge of one of them, so this decides coplanar triangles and segments. */
static int
apart2(const struct pt *t, int nt, const struct pt *u, int nu)
{
	int o = nt == 3 ? orient2d(t[0], t[1], t[2]) : 0, i, j, s;

	for (i = 0; i < (nt == 3 ? 3 : 1); i++) {
		s = orient2d(t[i], t[(i + 1) % nt], u[0]);
		if (s == 0 || (o != 0 && s != -o))
			continue;
		for (j = 1; j < nu; j++)
			if (orient2d(t[i], t[(i + 1) % nt], u[j]) != s)
				break;
		if (j == nu)
			return 1;
	}
	return 0;
}

/* A coordinate whose dropping leaves triangle p its area, trying the
 * normal's largest component first; -1 if p has no area. */
static int
flat_axis(const vec3 p[3])
{
	vec3 nrm = v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]));
	int i, k = 2;

	if (fabs(nrm.x) >= fabs(nrm.y) && fabs(nrm.x) >= fabs(nrm.z))
		k = 0;
	else if (fabs(nrm.y) >= fabs(nrm.z))
		k = 1;
	for (i = 0; i < 3; i++, k = (k + 1) % 3)
		if (orient2d(proj(p[0], k), proj(p[1], k), proj(p[2], k)) != 0)
			return k;
	return -1;
}

/* The segment [*s, *t] a triangle without area covers (*s == *t for a
 * point): its extreme vertices along a coordinate on which they differ. */
static void
span(const vec3 p[3], vec3 *s, vec3 *t)
{
	int i, k, lo = 0, hi = 0;

	for (k = 0; k < 3 && lo == hi; k++)
		for (i = 1; i < 3; i++) {
			if (at(p[i], k) < at(p[lo], k))
				lo = i;
			if (at(p[i], k) > at(p[hi], k))
				hi = i;
		}
	*s = p[lo];
	*t = p[hi];
}

/* Closed segment ab (or point, a == b) against triangle t, which has area. */
static int
seg_tri(const vec3 t[3], vec3 a, vec3 b)
{
	int oa = audit_orient3d(t[0], t[1], t[2], a), ob = audit_orient3d(t[0], t[1], t[2], b);
	int s[3], i, k, pos = 0, neg = 0;

	if (oa * ob > 0)
		return 0;
	if (oa == 0 && ob == 0) {
		struct pt q[3], e[2];

		k = flat_axis(t);
		for (i = 0; i < 3; i++)
			q[i] = proj(t[i], k);
		e[0] = proj(a, k);
		e[1] = proj(b, k);
		return !apart2(q, 3, e, 2) && !apart2(e, 2, q, 3);
	}
	/* ab meets the plane at one point X. The plane through ab and an edge
	 * has X on its inner or outer side as the edge has, up to a factor
	 * common to all three edges: X is in t unless the signs disagree. */
	for (i = 0; i < 3; i++) {
		s[i] = audit_orient3d(a, b, t[i], t[(i + 1) % 3]);
		pos |= s[i] > 0;
		neg |= s[i] < 0;
	}
	return !(pos && neg);
}

/* Closed segments (or points) ab and cd. Coplanar ones meet iff their
 * projections on all three coordinate planes meet: a projection never
 * parts what touches, and one of the three is one-to-one on their plane. */
static int
seg_seg(vec3 a, vec3 b, vec3 c, vec3 d)
{
	int k;

	if (audit_orient3d(a, b, c, d) != 0)
		return 0;
	for (k = 0; k < 3; k++)
		if (!seg_seg2(proj(a, k), proj(b, k), proj(c, k), proj(d, k)))
			return 0;
	return 1;
}

/* Coplanar triangles, or ones at least one of which has no area. */
static int
tri_tri_flat(const vec3 p[3], const vec3 q[3])
{
	int kp = flat_axis(p), kq = flat_axis(q), i;
	vec3 s, t, s2, t2;
	struct pt a[3], b[3];

	if (kp < 0 && kq < 0) {
		span(p, &s, &t);
		span(q, &s2, &t2);
		return seg_seg(s, t, s2, t2);
	}
	if (kp < 0 || kq < 0) {
		span(kp < 0 ? p : q, &s, &t);
		return seg_tri(kp < 0 ? q : p, s, t);
	}
	/* both have area in one plane, so both keep it when dropping kp */
	for (i = 0; i < 3; i++) {
		a[i] = proj(p[i], kp);
		b[i] = proj(q[i], kp);
	}
	return !apart2(a, 3, b, 3) && !apart2(b, 3, a, 3);
}

/* For the signs d of a triangle's vertices against the other's plane, not
 * all equal: the vertex *i alone on its side, and *f = -1 if that plane must
 * turn over to put it on the positive side. Then f d[i] >= 0 >= the other
 * two, and each edge from *i meets the plane once (d[i] != 0 or neither of
 * the others is 0). */
static void
lone(const int d[3], int *i, int *f)
{
	for (*i = 0; *i < 3; (*i)++)
		for (*f = 1; *f >= -1; *f -= 2) {
			int s = *f * d[*i], s1 = *f * d[(*i + 1) % 3], s2 = *f * d[(*i + 2) % 3];

			if (s >= 0 && s1 <= 0 && s2 <= 0 && (s > 0 || (s1 < 0 && s2 < 0)))
				return;
		}
}

int
audit_tri_tri(const vec3 p[3], const vec3 q[3])
{
	vec3 a[3], b[3], tmp;
	int dp[3], dq[3], i, j, fp, fq, k;

	for (k = 0; k < 3; k++)
		dq[k] = audit_orient3d(p[0], p[1], p[2], q[k]);
	if (dq[0] == 0 && dq[1] == 0 && dq[2] == 0)
		return tri_tri_flat(p, q);
	if (dq[0] == dq[1] && dq[1] == dq[2])
		return 0;
	/* p has area now; if q has none, all of dp are 0 */
	for (k = 0; k < 3; k++)
		dp[k] = audit_orient3d(q[0], q[1], q[2], p[k]);
	if (dp[0] == 0 && dp[1] == 0 && dp[2] == 0)
		return tri_tri_flat(p, q);
	if (dp[0] == dp[1] && dp[1] == dp[2])
		return 0;

	/* Guigue and Devillers: turn each triangle so that its lone vertex
	 * comes first and lies on the positive side of the other's plane.
	 * Each cuts the line of the two planes in an interval; the intervals
	 * overlap iff two orientations say so. */
	lone(dp, &i, &fq);
	lone(dq, &j, &fp);
	for (k = 0; k < 3; k++) {
		a[k] = p[(i + k) % 3];
		b[k] = q[(j + k) % 3];
	}
	if (fp < 0) {
		tmp = a[1], a[1] = a[2], a[2] = tmp;
	}
	if (fq < 0) {
		tmp = b[1], b[1] = b[2], b[2] = tmp;
	}
	return audit_orient3d(a[0], a[1], b[0], b[1]) <= 0 &&
	    audit_orient3d(a[0], a[2], b[2], b[0]) <= 0;
}

/*
 * The broad phase: space is cut into slabs across the scene's second
 * longest axis, about one triangle thick, and in each slab the boxes, sorted
 * along the longest axis, are swept: each is tested against those that
 * start before it ends. A pair whose boxes meet is tested in one slab only,
 * the one holding the low end of their common part. The sort's ties are
 * broken by mesh and triangle, so all is deterministic.
 */
struct mesh {
	const double *x;
	const int *tri;
	size_t n;
};

struct box {
	double lo[3], hi[3];
	double key;		/* lo along the sweep axis */
	size_t s0, s1;		/* the slabs it spans */
	size_t t;
	int m;			/* 0: mesh A, 1: mesh B */
};

/* The slabs: width w from lo along axis k; n of them. */
struct slabs {
	int k;
	double lo, w;
	size_t n;
};

static int
cmp_box(const void *va, const void *vb)
{
	const struct box *a = va, *b = vb;

	/* NaN first, so that the order stays total */
	if (a->key < b->key || (isnan(a->key) && !isnan(b->key)))
		return -1;
	if (b->key < a->key || (isnan(b->key) && !isnan(a->key)))
		return 1;
	if (a->m != b->m)
		return a->m - b->m;
	return (a->t > b->t) - (a->t < b->t);
}

static void
corners(const struct mesh *m, size_t t, vec3 v[3])
{
	int i;

	for (i = 0; i < 3; i++)
		v[i] = v3_load(m->x + 3 * (size_t)m->tri[3 * t + i]);
}

static void
bound(const struct mesh *m, size_t t, int which, struct box *b)
{
	vec3 v[3];
	int i, k;

	corners(m, t, v);
	for (k = 0; k < 3; k++) {
		b->lo[k] = b->hi[k] = at(v[0], k);
		for (i = 1; i < 3; i++) {
			if (at(v[i], k) < b->lo[k])
				b->lo[k] = at(v[i], k);
			if (at(v[i], k) > b->hi[k])
				b->hi[k] = at(v[i], k);
		}
	}
	b->t = t;
	b->m = which;
}

static size_t
slab_of(const struct slabs *s, double v)
{
	double i = s->w > 0 ? floor((v - s->lo) / s->w) : 0;

	return i < (double)s->n ? (size_t)i : s->n - 1;
}

/* The sweep axis (the scene's longest), and slabs across the next longest
 * as thick as the mean box, but no more of them than boxes. */
static int
cut(const struct box *box, size_t n, struct slabs *s)
{
	double lo[3], hi[3], len[3], ext = 0;
	size_t i;
	int k, ax;

	for (k = 0; k < 3; k++) {
		lo[k] = box[0].lo[k];
		hi[k] = box[0].hi[k];
		for (i = 1; i < n; i++) {
			if (box[i].lo[k] < lo[k])
				lo[k] = box[i].lo[k];
			if (box[i].hi[k] > hi[k])
				hi[k] = box[i].hi[k];
		}
		len[k] = hi[k] - lo[k];
	}
	ax = len[1] > len[0] ? 1 : 0;
	if (len[2] > len[ax])
		ax = 2;
	k = (ax + 1) % 3;
	s->k = len[(ax + 2) % 3] > len[k] ? (ax + 2) % 3 : k;
	for (i = 0; i < n; i++)
		ext += box[i].hi[s->k] - box[i].lo[s->k];
	s->lo = lo[s->k];
	s->w = fmax(ext / n, len[s->k] / n);
	s->n = s->w > 0 ? (size_t)fmin(len[s->k] / s->w, n) + 1 : 1;
	return ax;
}

static int
meet(const struct box *u, const struct box *w)
{
	int k;

	for (k = 0; k < 3; k++)
		if (u->lo[k] > w->hi[k] || w->lo[k] > u->hi[k])
			return 0;
	return 1;
}

static int
share_vertex(const struct mesh *m, size_t s, size_t t)
{
	int i, j;

	for (i = 0; i < 3; i++)
		for (j = 0; j < 3; j++)
			if (m->tri[3 * s + i] == m->tri[3 * t + j])
				return 1;
	return 0;
}

/* 1 if the triangles of boxes u and w intersect, 0 if not, -1 if the pair
 * does not count (neighbours, or one mesh's own in a cross audit: no exact
 * test made); (*s, *t) is the pair, the lower triangle first within a
 * mesh, else mesh A's. */
static int
test_pair(const struct mesh *ms[2], int self, const struct box *u, const struct box *w,
    size_t *s, size_t *t)
{
	vec3 p[3], q[3];

	if (self ? share_vertex(ms[0], u->t, w->t) : u->m == w->m)
		return -1;
	if (self ? u->t < w->t : u->m == 0)
		*s = u->t, *t = w->t;
	else
		*s = w->t, *t = u->t;
	corners(ms[0], *s, p);
	corners(ms[1], *t, q);
	return audit_tri_tri(p, q);
}

long
audit_max_work(size_t n)
{
	double most = (double)AUDIT_WORK_PER_TRIANGLE * (double)n;

	return most < AUDIT_WORK_MIN ? AUDIT_WORK_MIN :
	    most < (double)(LONG_MAX / 2) ? (long)most : LONG_MAX / 2;
}

/* Intersecting pairs within a (b == NULL; pairs sharing a vertex skipped)
 * or between a and b into *r; the lowest pair into first if not NULL. 0,
 * or -1 out of memory. */
static int
sweep(const struct mesh *a, const struct mesh *b, int first[2], struct audit_result *r)
{
	const struct mesh *ms[2] = { a, b != NULL ? b : a };
	size_t nb = b != NULL ? b->n : 0, n, i, j, k, s, t, *start = NULL;
	struct box *box, *ent = NULL;
	struct slabs sl;
	long most, work = 0;
	int ax, rc = -1, hit;

	memset(r, 0, sizeof *r);
	if (nb > SIZE_MAX / sizeof *box || a->n > SIZE_MAX / sizeof *box - nb)
		return -1;
	if ((n = a->n + nb) == 0)
		return 0;
	most = audit_max_work(n);
	if ((box = malloc(n * sizeof *box)) == NULL)
		return -1;
	for (i = 0; i < n; i++)
		bound(i < a->n ? a : b, i < a->n ? i : i - a->n, i >= a->n, &box[i]);
	ax = cut(box, n, &sl);
	for (i = 0; i < n; i++) {
		box[i].key = box[i].lo[ax];
		box[i].s0 = slab_of(&sl, box[i].lo[sl.k]);
		box[i].s1 = slab_of(&sl, box[i].hi[sl.k]);
	}
	qsort(box, n, sizeof *box, cmp_box);

	/* copies of the boxes by slab, each slab in sweep order (a counting
	 * sort): slab k is ent[start[k - 1] .. start[k]), start[-1] being 0 */
	if ((start = calloc(sl.n + 1, sizeof *start)) == NULL)
		goto out;
	for (i = 0; i < n; i++)
		for (k = box[i].s0; k <= box[i].s1; k++)
			start[k + 1]++;
	for (k = 0; k < sl.n; k++)
		start[k + 1] += start[k];
	if ((ent = malloc(start[sl.n] * sizeof *ent)) == NULL)
		goto out;
	for (i = 0; i < n; i++)
		for (k = box[i].s0; k <= box[i].s1; k++)
			ent[start[k]++] = box[i];

	/* every pair the sweep looks at is work, and an exact test is
	 * AUDIT_TEST_WORK more: triangles piled on one another make every
	 * pair one of each, and the audit stops at its bound */
	for (k = 0; k < sl.n && !r->cut; k++)
		for (i = k > 0 ? start[k - 1] : 0; i < start[k] && !r->cut; i++)
			for (j = i + 1; j < start[k] && ent[j].key <= ent[i].hi[ax]; j++) {
				/* room for this pair and its test: never past most */
				if (work > most - 1 - AUDIT_TEST_WORK) {
					r->cut = true;
					break;
				}
				work++;
				r->candidates++;
				/* the pair's first common slab is k (s0 < k for neither) */
				if ((ent[i].s0 < k && ent[j].s0 < k) || !meet(&ent[i], &ent[j]) ||
				    (hit = test_pair(ms, b == NULL, &ent[i], &ent[j], &s, &t)) < 0)
					continue;
				work += AUDIT_TEST_WORK;
				r->tests++;
				if (!hit)
					continue;
				if (first != NULL && (r->pairs == 0 || (int)s < first[0] ||
				    ((int)s == first[0] && (int)t < first[1]))) {
					first[0] = (int)s;
					first[1] = (int)t;
				}
				r->pairs++;
			}
	rc = 0;
out:
	free(ent);
	free(start);
	free(box);
	return rc;
}

int
audit_self(const double *x, const int *tri, size_t ntri, int first[2], struct audit_result *r)
{
	struct mesh m = { x, tri, ntri };

	return sweep(&m, NULL, first, r);
}

int
audit_cross(const double *xa, const int *ta, size_t na, const double *xb, const int *tb,
    size_t nb, struct audit_result *r)
{
	struct mesh a = { xa, ta, na }, b = { xb, tb, nb };

	return sweep(&a, &b, NULL, r);
}

long
audit_self_intersections(const double *x, const int *tri, size_t ntri, int first[2])
{
	struct audit_result r;

	if (audit_self(x, tri, ntri, first, &r) != 0)
		return -1;
	return r.cut ? AUDIT_TOO_MANY : r.pairs;
}

long
audit_cross_intersections(const double *xa, const int *ta, size_t na,
    const double *xb, const int *tb, size_t nb)
{
	struct audit_result r;

	if (audit_cross(xa, ta, na, xb, tb, nb, &r) != 0)
		return -1;
	return r.cut ? AUDIT_TOO_MANY : r.pairs;
}
