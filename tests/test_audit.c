/* test_audit.c: the intersection audit: exact orientation on inputs that
 * fool plain doubles, triangle pairs with known answers (touching counts),
 * agreement with a second exact test on many degenerate pairs, the
 * sweep against brute force on grid meshes, and a state's cloth edges
 * through the corner of a box and the rim of a disc. */
#include "testutil.h"

#include <time.h>

#include "audit.h"
#include "check.h"
#include "cloth.h"

/* xorshift64*: noise that is the same on every run. */
static double
rnd(uint64_t *s)
{
	*s ^= *s >> 12;
	*s ^= *s << 25;
	*s ^= *s >> 27;
	return (double)((*s * 2685821657736338717ULL) >> 11) * 0x1p-53;
}

static int
sgn_ld(long double v)
{
	return (v > 0) - (v < 0);
}

/* Points near the plane x = y, d off it by i - j units of 2^-53: plain
 * doubles round d - a (about 11.5, ulp 2^-49) and lose the sign. In long
 * double (a significand of 64 bits or more) every step is exact here, so it
 * is the truth, and the truth is also sign(i - j) by construction. */
static void
test_orient3d_near_plane(void **state)
{
	vec3 a = v3(12, 12, 0), b = v3(24, 24, 0), c = v3(12, 12, 1);
	int i, j, wrong = 0;

	(void)state;
	for (i = 0; i < 32; i++)
		for (j = 0; j < 32; j++) {
			vec3 d = v3(0.5 + i * 0x1p-53, 0.5 + j * 0x1p-53, 0.3);
			long double ux = b.x - (long double)a.x, uy = b.y - (long double)a.y;
			long double uz = b.z - (long double)a.z, vx = c.x - (long double)a.x;
			long double vy = c.y - (long double)a.y, vz = c.z - (long double)a.z;
			long double wx = d.x - (long double)a.x, wy = d.y - (long double)a.y;
			long double wz = d.z - (long double)a.z;
			int truth = sgn_ld(wx * (uy * vz - uz * vy) + wy * (uz * vx - ux * vz) +
			    wz * (ux * vy - uy * vx));
			vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
			double naive = v3_dot(v3_sub(d, a), n);

			assert_int_equal(truth, (i > j) - (i < j));
			assert_int_equal(audit_orient3d(a, b, c, d), truth);
			assert_int_equal(audit_orient3d(b, c, a, d), truth);
			assert_int_equal(audit_orient3d(b, a, c, d), -truth);
			wrong += ((naive > 0) - (naive < 0)) != truth;
		}
	print_message("orient3d near x = y: plain doubles wrong on %d of 1024\n", wrong);
	assert_true(wrong > 0);
}

/* Exact integer evaluation, the determinant below 2^124 here. */
static int
orient_i128(const long long a[3], const long long b[3], const long long c[3],
    const long long d[3])
{
	__int128 u[3], v[3], w[3], det;
	int k;

	for (k = 0; k < 3; k++) {
		u[k] = b[k] - a[k];
		v[k] = c[k] - a[k];
		w[k] = d[k] - a[k];
	}
	det = w[0] * (u[1] * v[2] - u[2] * v[1]) + w[1] * (u[2] * v[0] - u[0] * v[2]) +
	    w[2] * (u[0] * v[1] - u[1] * v[0]);
	return (det > 0) - (det < 0);
}

/* Random coplanar quadruples (d = a + m(b - a) + n(c - a)) off by a unit
 * step or not, coordinates below 2^43 (products of two are inexact in
 * doubles), as integers and scaled by 2^-40 (exact, so the signs stay):
 * against 128-bit integer arithmetic. */
static void
test_orient3d_integer(void **state)
{
	uint64_t s = 42;
	int trial, k, wrong = 0, zeros = 0;

	(void)state;
	for (trial = 0; trial < 20000; trial++) {
		long long p[4][3];
		int m = (int)(rnd(&s) * 9) - 4, n = (int)(rnd(&s) * 9) - 4, truth;
		vec3 v[4], sv[4];
		double naive;

		for (k = 0; k < 3; k++) {
			p[0][k] = (long long)((rnd(&s) - 0.5) * 0x1p39);
			p[1][k] = (long long)((rnd(&s) - 0.5) * 0x1p39);
			p[2][k] = (long long)((rnd(&s) - 0.5) * 0x1p39);
			p[3][k] = p[0][k] + m * (p[1][k] - p[0][k]) + n * (p[2][k] - p[0][k]) +
			    (trial % 2 ? (int)(rnd(&s) * 3) - 1 : 0);
		}
		for (k = 0; k < 4; k++) {
			v[k] = v3((double)p[k][0], (double)p[k][1], (double)p[k][2]);
			sv[k] = v3_scale(v[k], 0x1p-40);
		}
		truth = orient_i128(p[0], p[1], p[2], p[3]);
		zeros += truth == 0;
		assert_int_equal(audit_orient3d(v[0], v[1], v[2], v[3]), truth);
		assert_int_equal(audit_orient3d(sv[0], sv[1], sv[2], sv[3]), truth);
		assert_int_equal(audit_orient3d(v[3], v[2], v[1], v[0]), truth);
		naive = v3_dot(v3_sub(sv[3], sv[0]),
		    v3_cross(v3_sub(sv[1], sv[0]), v3_sub(sv[2], sv[0])));
		wrong += ((naive > 0) - (naive < 0)) != truth;
	}
	print_message("orient3d on integers: %d exactly coplanar, plain doubles wrong on %d"
	    " of 20000\n", zeros, wrong);
	assert_true(zeros > 10000);
}

/* audit_tri_tri(p, q) == want under every order of both triangles'
 * vertices and with p and q exchanged. */
static void
check_pair(const vec3 p[3], const vec3 q[3], int want, const char *what)
{
	static const int perm[6][3] = {
		{ 0, 1, 2 }, { 1, 2, 0 }, { 2, 0, 1 }, { 0, 2, 1 }, { 2, 1, 0 }, { 1, 0, 2 }
	};
	int i, j, k;

	for (i = 0; i < 6; i++)
		for (j = 0; j < 6; j++) {
			vec3 a[3], b[3];

			for (k = 0; k < 3; k++) {
				a[k] = p[perm[i][k]];
				b[k] = q[perm[j][k]];
			}
			if (audit_tri_tri(a, b) != want || audit_tri_tri(b, a) != want)
				fail_msg("%s: expected %d (orders %d, %d)", what, want, i, j);
		}
}

#define T(ax, ay, az, bx, by, bz, cx, cy, cz) \
	{ { ax, ay, az }, { bx, by, bz }, { cx, cy, cz } }

static void
test_tri_tri_cases(void **state)
{
	static const vec3 p[3] = T(0, 0, 0, 2, 0, 0, 0, 2, 0);
	static const struct {
		vec3 q[3];
		int want;
		const char *what;
	} c[] = {
		{ T(0.5, 0.5, -1, 0.5, 0.5, 1, -1, -1, 0), 1, "crossing" },
		{ T(0.5, 0.5, 1, 1, 0.5, 1, 0.5, 1, 2), 0, "above" },
		{ T(3, 3, -1, 3, 3, 1, 4, 4, 0), 0, "planes cross, triangles apart" },
		{ T(1.5, 1.5, -1, 1.5, 1.5, 1, 2, 0.5, 0), 0, "past the hypotenuse" },
		{ T(0.5, 0.5, 0, 0.5, 0.5, 1, 1, 0.8, 1), 1, "vertex on the face" },
		{ T(2, 0, 0, 3, 0, 1, 3, 1, 1), 1, "vertex on vertex" },
		{ T(2 + 0x1p-51, 0, 0, 3, 0, 1, 3, 1, 1), 0, "one ulp past the vertex" },
		{ T(1, 1, 0, 1, 1, 1, 2, 2, 1), 1, "vertex on the hypotenuse" },
		{ T(1, 1 + 0x1p-52, 0, 1, 1, 1, 2, 2, 1), 0, "one ulp off the hypotenuse" },
		{ T(0, 0, 0, 2, 0, 0, 1, 0, 1), 1, "common edge, upright" },
		{ T(1, 0, 0, 3, 0, 0, 2, 0, 1), 1, "edges overlapping" },
		{ T(2.5, 0, 0, 3, 0, 0, 2.7, 0, 1), 0, "edges on one line, apart" },
		{ T(1, -1, -1, 1, -1, 1, 1, 1, 0), 1, "edge through the face" },
		{ T(0.5, 0.5, 0, 3, 0.5, 0, 0.5, 3, 0), 1, "coplanar overlapping" },
		{ T(0.2, 0.2, 0, 0.4, 0.2, 0, 0.2, 0.4, 0), 1, "coplanar inside" },
		{ T(-1, -1, 0, 4, -1, 0, -1, 4, 0), 1, "coplanar around" },
		{ T(1, 1, 0, 3, 1, 0, 1, 3, 0), 1, "coplanar, touching at a vertex" },
		{ T(1.5, 1.5, 0, 3, 1.5, 0, 1.5, 3, 0), 0, "coplanar apart" },
		{ T(-1, 1, 0, -1, 3, 0, -2, 2, 0), 0, "coplanar apart, beside" },
		{ T(0.5, 0.5, -1, 0.5, 0.5, 1, 0.5, 0.5, 1), 1, "segment through" },
		{ T(0.5, 0.5, -1, 0.5, 0.5, -0.5, 0.5, 0.5, -0.7), 0, "segment short of it" },
		{ T(3, 3, -1, 3, 3, 1, 3, 3, 0), 0, "segment beside" },
		{ T(-1, 1, 0, 3, 1, 0, 1, 1, 0), 1, "segment in the plane, across" },
		{ T(0.5, 0.5, 0, 0.5, 0.5, 0, 0.5, 0.5, 0), 1, "point on it" },
		{ T(0.5, 0.5, 1e-17, 0.5, 0.5, 1e-17, 0.5, 0.5, 1e-17), 0, "point just above" },
		{ T(2, 0, 0, 2, 0, 0, 2, 0, 0), 1, "point on its vertex" },
	};
	/* both of no area: a segment, and segments and points against it */
	static const vec3 s[3] = T(0, 0, 0, 2, 2, 0, 1, 1, 0);
	static const struct {
		vec3 q[3];
		int want;
		const char *what;
	} d[] = {
		{ T(0, 2, 0, 2, 0, 0, 2, 0, 0), 1, "segments crossing" },
		{ T(0, 2, 1, 2, 0, 1, 2, 0, 1), 0, "segments skew" },
		{ T(1.5, 1.5, 0, 3, 3, 0, 4, 4, 0), 1, "segments overlapping on a line" },
		{ T(2.5, 2.5, 0, 3, 3, 0, 4, 4, 0), 0, "segments on a line, apart" },
		{ T(2, 2, 0, 3, 3, 0, 4, 4, 0), 1, "segments end to end" },
		{ T(0, 2, 0, 0.5, 1.5, 0, 0.75, 1.25, 0), 0, "segments coplanar, short" },
		{ T(1, 1, 0, 1, 1, 0, 1, 1, 0), 1, "point on the segment" },
		{ T(1, 1 + 0x1p-52, 0, 1, 1 + 0x1p-52, 0, 1, 1 + 0x1p-52, 0), 0,
		    "point off the segment by an ulp" },
	};
	static const vec3 pt[3] = T(1, 2, 3, 1, 2, 3, 1, 2, 3);
	static const vec3 pt2[3] = T(1, 2, 3 + 0x1p-51, 1, 2, 3 + 0x1p-51, 1, 2, 3 + 0x1p-51);
	size_t i;

	(void)state;
	for (i = 0; i < sizeof c / sizeof c[0]; i++)
		check_pair(p, c[i].q, c[i].want, c[i].what);
	for (i = 0; i < sizeof d / sizeof d[0]; i++)
		check_pair(s, d[i].q, d[i].want, d[i].what);
	check_pair(pt, pt, 1, "a point and itself");
	check_pair(pt, pt2, 0, "two points an ulp apart");
}

/* In the plane z = 0, a point d near the line y = x (as in the first
 * test) against a triangle below that line, and a triangle above it that
 * reaches down to d: they meet iff d is on or below the line. */
static void
test_tri_tri_near_edge(void **state)
{
	static const vec3 p[3] = T(-12, -12, 0, 24, -12, 0, 24, 24, 0);
	int i, j;

	(void)state;
	for (i = 0; i < 32; i++)
		for (j = 0; j < 32; j++) {
			vec3 d = v3(0.5 + i * 0x1p-53, 0.5 + j * 0x1p-53, 0);
			vec3 pt[3] = { d, d, d }, q[3] = { d, v3(d.x - 1, d.y + 2, 0),
				v3(d.x - 2, d.y + 1, 0) };

			assert_int_equal(audit_tri_tri(p, pt), j <= i);
			assert_int_equal(audit_tri_tri(q, p), j <= i);
		}
}

/* A second exact test, by other routes: closed triangles meet iff an edge
 * of one meets the other (the ends of their common part lie on edges).
 * Edges go in as triangles of no area, through the segment paths. */
static int
by_edges(const vec3 p[3], const vec3 q[3])
{
	const vec3 *t[2] = { p, q };
	int i, k;

	for (k = 0; k < 2; k++)
		for (i = 0; i < 3; i++) {
			vec3 e[3] = { t[k][i], t[k][(i + 1) % 3], t[k][(i + 1) % 3] };

			if (audit_tri_tri(e, t[1 - k]))
				return 1;
		}
	return 0;
}

/* Random pairs on a 4 x 4 x 4 lattice, as given and scaled by 0.1 (then
 * not quite a lattice): coplanar, touching and degenerate pairs abound. */
static void
test_tri_tri_against_edges(void **state)
{
	uint64_t s = 7;
	int trial, k, hits = 0;

	(void)state;
	for (trial = 0; trial < 100000; trial++) {
		vec3 v[6], *p = v, *q = v + 3;
		double scale = trial % 2 ? 0.1 : 1;
		int got, want;

		for (k = 0; k < 6; k++)
			v[k] = v3(scale * (int)(rnd(&s) * 4), scale * (int)(rnd(&s) * 4),
			    scale * (int)(rnd(&s) * 4));
		got = audit_tri_tri(p, q);
		want = by_edges(p, q);
		if (got != want)
			fail_msg("trial %d: tri_tri %d, by edges %d", trial, got, want);
		assert_int_equal(audit_tri_tri(q, p), got);
		hits += got;
	}
	print_message("tri_tri on a lattice: %d of 100000 pairs meet, all agree\n", hits);
}

/* nu x nv nodes spaced h in the plane z = 0, two triangles per square. */
static void
grid(int nu, int nv, double h, double **x, int **tri, size_t *ntri)
{
	int i, j, t = 0;

	*x = malloc((size_t)nu * nv * 3 * sizeof **x);
	*tri = malloc((size_t)(nu - 1) * (nv - 1) * 6 * sizeof **tri);
	if (*x == NULL || *tri == NULL)
		fail_msg("out of memory");
	for (j = 0; j < nv; j++)
		for (i = 0; i < nu; i++)
			v3_store(*x + 3 * (j * nu + i), v3(i * h, j * h, 0));
	for (j = 0; j + 1 < nv; j++)
		for (i = 0; i + 1 < nu; i++) {
			int n00 = j * nu + i, n10 = n00 + 1, n01 = n00 + nu, n11 = n01 + 1;
			int *f = *tri + 6 * t++;

			f[0] = n00, f[1] = n10, f[2] = n11;
			f[3] = n00, f[4] = n11, f[5] = n01;
		}
	*ntri = (size_t)t * 2;
}

static void
corners(const double *x, const int *tri, size_t t, vec3 v[3])
{
	int i;

	for (i = 0; i < 3; i++)
		v[i] = v3_load(x + 3 * tri[3 * t + i]);
}

static int
share(const int *tri, size_t s, size_t t)
{
	int i, j;

	for (i = 0; i < 3; i++)
		for (j = 0; j < 3; j++)
			if (tri[3 * s + i] == tri[3 * t + j])
				return 1;
	return 0;
}

/* Every pair, in order: the count and the first pair. */
static long
brute_self(const double *x, const int *tri, size_t n, int first[2])
{
	size_t s, t;
	long count = 0;

	for (s = 0; s < n; s++)
		for (t = s + 1; t < n; t++) {
			vec3 p[3], q[3];

			if (share(tri, s, t))
				continue;
			corners(x, tri, s, p);
			corners(x, tri, t, q);
			if (audit_tri_tri(p, q) && count++ == 0) {
				first[0] = (int)s;
				first[1] = (int)t;
			}
		}
	return count;
}

static void
test_self_flat_and_shared(void **state)
{
	/* two triangles through each other, with and without a common node */
	double x[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, -1, 0.3, 0.3, 1, 0, 0, 0 };
	int shared[] = { 0, 1, 2, 0, 3, 4 }, apart[] = { 0, 1, 2, 5, 3, 4 };
	int first[2] = { -1, -1 }, *tri;
	double *g;
	size_t ntri, i;

	(void)state;
	grid(20, 20, 0.01, &g, &tri, &ntri);
	assert_int_equal(audit_self_intersections(g, tri, ntri, first), 0);
	assert_int_equal(first[0], -1);
	/* the same turned upright and off the axes: no longer exactly flat */
	for (i = 0; i < 400; i++) {
		vec3 r = v3_load(g + 3 * i);

		v3_store(g + 3 * i, v3(0.6 * r.x + 0.1, 0.8 * r.x - 0.3, r.y + 0.7));
	}
	assert_int_equal(audit_self_intersections(g, tri, ntri, first), 0);
	assert_int_equal(audit_self_intersections(g, tri, 0, first), 0);
	free(g);
	free(tri);

	assert_int_equal(audit_self_intersections(x, shared, 2, first), 0);
	assert_int_equal(audit_self_intersections(x, apart, 2, first), 1);
	assert_int_equal(first[0], 0);
	assert_int_equal(first[1], 1);
}

/* A grid folded over onto itself (fold at column f, the top layer a height
 * d above the bottom), then one top node pushed down through the bottom. */
static void
test_self_pushed_through(void **state)
{
	const int f = 6, nu = 2 * f + 1, nv = 9;
	const double h = 0.01, d = 0.01;
	int first[2], brute[2], i, j, pushed = 4 * nu + f + 2, k, incident = 0, bottom = 1;
	int *tri;
	double *x;
	size_t ntri;
	long n;

	(void)state;
	grid(nu, nv, h, &x, &tri, &ntri);
	for (j = 0; j < nv; j++)
		for (i = f + 1; i < nu; i++)
			v3_store(x + 3 * (j * nu + i), v3((2 * f - i) * h, j * h, d));
	assert_int_equal(audit_self_intersections(x, tri, ntri, first), 0);

	x[3 * pushed + 2] = -d;
	n = audit_self_intersections(x, tri, ntri, first);
	print_message("pushed through: %ld pairs, first %d %d\n", n, first[0], first[1]);
	assert_true(n > 0);
	assert_int_equal(brute_self(x, tri, ntri, brute), n);
	assert_int_equal(first[0], brute[0]);
	assert_int_equal(first[1], brute[1]);
	assert_true(first[0] < first[1]);
	/* one of the pair holds the pushed node, the other is all bottom layer */
	for (k = 0; k < 2; k++) {
		const int *t = tri + 3 * first[k];

		if (t[0] == pushed || t[1] == pushed || t[2] == pushed)
			incident++;
		else
			for (i = 0; i < 3; i++)
				bottom &= t[i] % nu <= f;
	}
	assert_int_equal(incident, 1);
	assert_true(bottom);
	free(x);
	free(tri);
}

/* Crumpled grids: sweep and brute force agree. Then the timing. */
static void
test_self_noisy(void **state)
{
	uint64_t s = 3;
	int trial, *tri, first[2], brute[2];
	double *x, t0, t1;
	size_t ntri, i;
	struct timespec a, b;
	long n, total = 0;

	(void)state;
	for (trial = 0; trial < 8; trial++) {
		grid(12, 12, 0.01, &x, &tri, &ntri);
		for (i = 0; i < 144 * 3; i++)
			x[i] += 0.01 * (rnd(&s) - 0.5) * (i % 3 == 2 ? 4 : 1);
		n = audit_self_intersections(x, tri, ntri, first);
		assert_int_equal(brute_self(x, tri, ntri, brute), n);
		if (n > 0) {
			assert_int_equal(first[0], brute[0]);
			assert_int_equal(first[1], brute[1]);
		}
		total += n;
		free(x);
		free(tri);
	}
	print_message("crumpled 12 x 12 grids: %ld pairs in all, as brute force\n", total);
	assert_true(total > 0);

	grid(100, 100, 0.01, &x, &tri, &ntri);
	for (i = 0; i < 10000 * 3; i++)
		x[i] += 0.001 * (rnd(&s) - 0.5);
	clock_gettime(CLOCK_MONOTONIC, &a);
	n = audit_self_intersections(x, tri, ntri, first);
	clock_gettime(CLOCK_MONOTONIC, &b);
	t0 = (b.tv_sec - a.tv_sec) * 1e3 + (b.tv_nsec - a.tv_nsec) * 1e-6;
	for (i = 0; i < 10000; i++)
		x[3 * i + 2] = 0;
	clock_gettime(CLOCK_MONOTONIC, &a);
	assert_int_equal(audit_self_intersections(x, tri, ntri, first), 0);
	clock_gettime(CLOCK_MONOTONIC, &b);
	t1 = (b.tv_sec - a.tv_sec) * 1e3 + (b.tv_nsec - a.tv_nsec) * 1e-6;
	print_message("100 x 100 grid, %zu triangles: noisy %.1f ms (%ld pairs), "
	    "flat z = 0 %.1f ms\n", ntri, t0, n, t1);
	free(x);
	free(tri);
}

static long
brute_cross(const double *xa, const int *ta, size_t na, const double *xb, const int *tb,
    size_t nb)
{
	size_t s, t;
	long count = 0;

	for (s = 0; s < na; s++)
		for (t = 0; t < nb; t++) {
			vec3 p[3], q[3];

			corners(xa, ta, s, p);
			corners(xb, tb, t, q);
			count += audit_tri_tri(p, q);
		}
	return count;
}

/* A cloth and a tetrahedron through it, above it, and resting on it. */
static void
test_cross(void **state)
{
	static const int tet[] = { 0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2 };
	const double base[] = { 0.45, 0.45, -0.2, 0.7, 0.4, 0.2, 0.3, 0.7, 0.2, 0.35, 0.3, 0.2 };
	const double lift[] = { 0, 0.3, 0.2 };
	long want[] = { 1, 0, 1 }, n;
	double *x, y[12];
	int *tri, k, i;
	size_t ntri;

	(void)state;
	grid(10, 10, 0.1, &x, &tri, &ntri);
	for (k = 0; k < 3; k++) {
		for (i = 0; i < 12; i++)
			y[i] = base[i] + (i % 3 == 2 ? lift[k] : 0);
		n = audit_cross_intersections(x, tri, ntri, y, tet, 4);
		assert_int_equal(n, brute_cross(x, tri, ntri, y, tet, 4));
		assert_int_equal(n > 0, want[k]);
		assert_int_equal(audit_cross_intersections(y, tet, 4, x, tri, ntri), n);
	}
	assert_int_equal(audit_cross_intersections(x, tri, ntri, y, tet, 0), 0);
	free(x);
	free(tri);
}

/*
 * One cloth edge laid across a solid's corner with both its nodes outside:
 * the nodes' count sees nothing, the edges' count sees the edge and how
 * deep it goes, and nothing once the edge is lifted clear. The box's
 * corner at x = y = 0.1 m: the edge from (0.094, 0.103) to (0.103, 0.094)
 * goes deepest at its middle, (0.0985, 0.0985), 1.5 mm under both faces.
 * The disc's rim at r = 0.05 m, y = 0.1 m: the edge from (0.046, 0.103)
 * to (0.052, 0.095) is 0.008 t - 0.003 under the top and 0.004 - 0.006 t
 * inside the side, deepest at t = 1/2, 1 mm.
 */
static void
test_edges_through_solids(void **state)
{
	static const struct {
		const char *solid;
		vec3 a, b, lifted;
		double depth;
	} cases[] = {
		{ "[box]\nmin = 0 0 0 m\nmax = 0.1 0.1 0.1 m\n", { 0.094, 0.103, 0.05 },
		  { 0.103, 0.094, 0.05 }, { 0.103, 0.104, 0.05 }, 1.5e-3 },
		{ "[disc]\ncentre = 0 0.1 0 m\nradius = 5 cm\nheight = 0.1 m\n", { 0.046, 0.103, 0 },
		  { 0.052, 0.095, 0 }, { 0.052, 0.104, 0 }, 1e-3 },
	};
	size_t c;

	(void)state;
	for (c = 0; c < sizeof cases / sizeof cases[0]; c++) {
		char text[1024];
		struct scene sc;
		struct cloth cl;
		struct drape_err err;
		struct check_result r;
		double *x;
		int a, b, p;

		snprintf(text, sizeof text, "[simulation]\nduration = 1 s\n[cloth]\nnodes = 3 3\n"
		    "spacing = 10 mm\nweight = 100 g/m2\nthickness = 0.5 mm\nmodulus_warp = 1 MPa\n"
		    "modulus_weft = 1 MPa\nshear_modulus = 0.1 MPa\nbending_warp = 1 uN*m\n"
		    "bending_weft = 1 uN*m\n%s", cases[c].solid);
		parse_text(&sc, text);
		if (cloth_build(&cl, &sc, &err) != 0)
			fail_msg("%s", err.msg);
		x = malloc(3 * (size_t)cl.n * sizeof *x);
		assert_non_null(x);
		/* every node far beside the solid, but the first edge's two */
		for (p = 0; p < cl.n; p++)
			v3_store(x + 3 * p, v3(0.5 + 0.01 * p, 1, 0.5));
		a = cl.edge[0];
		b = cl.edge[1];
		v3_store(x + 3 * a, cases[c].a);
		v3_store(x + 3 * b, cases[c].b);
		assert_int_equal(check_state(&sc, &cl, x, &r), 0);
		print_message("%s: %ld nodes inside, %ld edges in, deepest %.6f mm\n",
		    c == 0 ? "box" : "disc", r.inside, r.edges_in, r.edge_depth * 1e3);
		assert_int_equal(r.pairs, 0);
		assert_int_equal(r.inside, 0);
		assert_int_equal(r.edges_in, 1);
		assert_double_equal(r.edge_depth, cases[c].depth, 1e-9);
		v3_store(x + 3 * b, cases[c].lifted);
		assert_int_equal(check_state(&sc, &cl, x, &r), 0);
		assert_int_equal(r.edges_in, 0);
		assert_true(r.edge_depth == 0);
		free(x);
		cloth_free(&cl);
		scene_free(&sc);
	}
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_orient3d_near_plane),
		cmocka_unit_test(test_orient3d_integer),
		cmocka_unit_test(test_tri_tri_cases),
		cmocka_unit_test(test_tri_tri_near_edge),
		cmocka_unit_test(test_tri_tri_against_edges),
		cmocka_unit_test(test_self_flat_and_shared),
		cmocka_unit_test(test_self_pushed_through),
		cmocka_unit_test(test_self_noisy),
		cmocka_unit_test(test_cross),
		cmocka_unit_test(test_edges_through_solids),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
