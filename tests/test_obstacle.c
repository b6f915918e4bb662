/* test_obstacle.c: obstacle distances, normals, bounds and checks; the
 * icosahedron, the winding number and the OBJ reader. */
#include <errno.h>
#include <unistd.h>

#include "mesh.h"
#include "obstacle.h"
#include "testutil.h"

#define EPS 1e-12

#define assert_vec_equal(a, b, eps) do { \
	vec3 va_ = (a), vb_ = (b); \
	assert_double_equal(va_.x, vb_.x, eps); \
	assert_double_equal(va_.y, vb_.y, eps); \
	assert_double_equal(va_.z, vb_.z, eps); \
} while (0)

/* Distance, closest point and normal at p, as a macro so that a failure
 * names the line of the case. */
#define assert_distance(o, p, d, qw, nw) do { \
	vec3 q_, n_; \
	double d_ = obstacle_distance(o, p, &q_, &n_); \
	assert_double_equal(d_, d, EPS); \
	assert_vec_equal(q_, qw, EPS); \
	assert_vec_equal(n_, nw, EPS); \
} while (0)

static struct obstacle
checked(struct obstacle o)
{
	struct drape_err err;

	if (obstacle_check(&o, &err) != 0)
		fail_msg("obstacle_check: %s", err.msg);
	return o;
}

static struct obstacle
plane(vec3 point, vec3 normal)
{
	struct obstacle o = { .kind = OBSTACLE_PLANE, .point = point, .normal = normal };

	return checked(o);
}

static struct obstacle
box(vec3 lo, vec3 hi)
{
	struct obstacle o = { .kind = OBSTACLE_BOX, .lo = lo, .hi = hi };

	return checked(o);
}

static struct obstacle
sphere(vec3 centre, double radius)
{
	struct obstacle o = { .kind = OBSTACLE_SPHERE, .centre = centre, .radius = radius };

	return checked(o);
}

static struct obstacle
disc(vec3 centre, double radius, double height)
{
	struct obstacle o = { .kind = OBSTACLE_DISC, .centre = centre, .radius = radius,
	    .height = height };

	return checked(o);
}

/* A small generator with its state in the caller. */
static double
uniform(unsigned long *s, double lo, double hi)
{
	*s = *s * 6364136223846793005UL + 1442695040888963407UL;
	return lo + (hi - lo) * (double)(*s >> 11 & ((1UL << 53) - 1)) / (double)(1UL << 53);
}

/* At random points about the solid: the normal is a unit vector, p is q
 * moved d along it, q is on the surface, and the sign agrees with inside(). */
static void
check_consistent(const struct obstacle *o, vec3 lo, vec3 hi, int (*inside)(const struct
    obstacle *, vec3))
{
	unsigned long s = 12345;
	int i;

	for (i = 0; i < 2000; i++) {
		vec3 p = v3(uniform(&s, lo.x, hi.x), uniform(&s, lo.y, hi.y),
		    uniform(&s, lo.z, hi.z)), q, n;
		double d = obstacle_distance(o, p, &q, &n);

		assert_double_equal(v3_len(n), 1, 1e-12);
		assert_vec_equal(v3_madd(q, n, d), p, 1e-12);
		assert_double_equal(obstacle_distance(o, q, NULL, NULL), 0, 1e-12);
		assert_int_equal(d < 0, inside(o, p));
	}
}

static int
inside_box(const struct obstacle *o, vec3 p)
{
	return p.x > o->lo.x && p.x < o->hi.x && p.y > o->lo.y && p.y < o->hi.y &&
	    p.z > o->lo.z && p.z < o->hi.z;
}

static int
inside_sphere(const struct obstacle *o, vec3 p)
{
	return v3_len(v3_sub(p, o->centre)) < o->radius;
}

static int
inside_disc(const struct obstacle *o, vec3 p)
{
	return hypot(p.x - o->centre.x, p.z - o->centre.z) < o->radius &&
	    p.y < o->centre.y && p.y > o->centre.y - o->height;
}

static int
inside_plane(const struct obstacle *o, vec3 p)
{
	return v3_dot(v3_sub(p, o->point), o->normal) < 0;
}

static void
test_plane(void **state)
{
	struct obstacle o = plane(v3(0, 1, 0), v3(0, 2, 0)), t;
	double h = sqrt(0.5);

	(void)state;
	assert_vec_equal(o.normal, v3(0, 1, 0), 0);
	assert_distance(&o, v3(3, 4, 5), 3, v3(3, 1, 5), v3(0, 1, 0));
	assert_distance(&o, v3(1, 0, 2), -1, v3(1, 1, 2), v3(0, 1, 0));
	assert_distance(&o, v3(1, 1, 2), 0, v3(1, 1, 2), v3(0, 1, 0));
	/* NULL q and normal */
	assert_double_equal(obstacle_distance(&o, v3(0, 0.5, 0), NULL, NULL), -0.5, EPS);

	t = plane(v3(0, 0, 0), v3(1, 1, 0));
	assert_vec_equal(t.normal, v3(h, h, 0), EPS);
	assert_distance(&t, v3(1, 1, 7), sqrt(2), v3(0, 0, 7), v3(h, h, 0));
	assert_distance(&t, v3(-1, 0, 0), -h, v3(-0.5, 0.5, 0), v3(h, h, 0));
	check_consistent(&t, v3(-2, -2, -2), v3(2, 2, 2), inside_plane);
}

static void
test_sphere(void **state)
{
	struct obstacle o = sphere(v3(1, 2, 3), 0.5);

	(void)state;
	assert_distance(&o, v3(1, 4, 3), 1.5, v3(1, 2.5, 3), v3(0, 1, 0));
	assert_distance(&o, v3(-2, 2, 3), 2.5, v3(0.5, 2, 3), v3(-1, 0, 0));
	assert_distance(&o, v3(1.2, 2, 3), -0.3, v3(1.5, 2, 3), v3(1, 0, 0));
	assert_distance(&o, v3(1, 2, 3.5), 0, v3(1, 2, 3.5), v3(0, 0, 1));
	/* the centre has no direction: +y */
	assert_distance(&o, v3(1, 2, 3), -0.5, v3(1, 2.5, 3), v3(0, 1, 0));
	assert_distance(&o, v3(1.3, 2.4, 3), 0, v3(1.3, 2.4, 3), v3(0.6, 0.8, 0));
	check_consistent(&o, v3(0, 1, 2), v3(2, 3, 4), inside_sphere);
}

static void
test_box(void **state)
{
	struct obstacle o = box(v3(0, 0, 0), v3(2, 1, 4)), c;
	double r3 = 1 / sqrt(3);

	(void)state;
	/* outside a face, an edge, a corner */
	assert_distance(&o, v3(1, 3, 2), 2, v3(1, 1, 2), v3(0, 1, 0));
	assert_distance(&o, v3(-0.5, 0.5, 1), 0.5, v3(0, 0.5, 1), v3(-1, 0, 0));
	assert_distance(&o, v3(1, 0.5, 4.25), 0.25, v3(1, 0.5, 4), v3(0, 0, 1));
	assert_distance(&o, v3(5, 5, 2), 5, v3(2, 1, 2), v3(0.6, 0.8, 0));
	assert_distance(&o, v3(3, 2, 5), sqrt(3), v3(2, 1, 4), v3(r3, r3, r3));
	assert_distance(&o, v3(-1, -1, -1), sqrt(3), v3(0, 0, 0), v3(-r3, -r3, -r3));

	/* inside: out through the nearest face */
	assert_distance(&o, v3(1, 0.9, 2), -0.1, v3(1, 1, 2), v3(0, 1, 0));
	assert_distance(&o, v3(1, 0.1, 2), -0.1, v3(1, 0, 2), v3(0, -1, 0));
	assert_distance(&o, v3(0.1, 0.5, 2), -0.1, v3(0, 0.5, 2), v3(-1, 0, 0));
	assert_distance(&o, v3(1.875, 0.5, 2), -0.125, v3(2, 0.5, 2), v3(1, 0, 0));
	assert_distance(&o, v3(1, 0.5, 3.75), -0.25, v3(1, 0.5, 4), v3(0, 0, 1));
	assert_distance(&o, v3(1, 0.5, 0.0625), -0.0625, v3(1, 0.5, 0), v3(0, 0, -1));

	/* on a face: exactly 0 */
	assert_distance(&o, v3(1, 1, 2), 0, v3(1, 1, 2), v3(0, 1, 0));
	assert_distance(&o, v3(0, 0.5, 2), 0, v3(0, 0.5, 2), v3(-1, 0, 0));
	assert_false(signbit(obstacle_distance(&o, v3(1, 1, 2), NULL, NULL)));

	/* on an edge or corner: top, then x, then z, then bottom */
	assert_distance(&o, v3(2, 1, 2), 0, v3(2, 1, 2), v3(0, 1, 0));
	assert_distance(&o, v3(0, 1, 4), 0, v3(0, 1, 4), v3(0, 1, 0));
	assert_distance(&o, v3(2, 0.5, 4), 0, v3(2, 0.5, 4), v3(1, 0, 0));
	assert_distance(&o, v3(0, 0, 2), 0, v3(0, 0, 2), v3(-1, 0, 0));
	assert_distance(&o, v3(1, 0, 0), 0, v3(1, 0, 0), v3(0, 0, -1));
	assert_distance(&o, v3(0, 0, 0), 0, v3(0, 0, 0), v3(-1, 0, 0));

	/* ties inside a cube */
	c = box(v3(-1, -1, -1), v3(1, 1, 1));
	assert_distance(&c, v3(0, 0, 0), -1, v3(0, 1, 0), v3(0, 1, 0));
	assert_distance(&c, v3(0.5, 0.5, 0), -0.5, v3(0.5, 1, 0), v3(0, 1, 0));
	assert_distance(&c, v3(0.5, 0, 0.5), -0.5, v3(1, 0, 0.5), v3(1, 0, 0));
	assert_distance(&c, v3(0, -0.5, -0.5), -0.5, v3(0, -0.5, -1), v3(0, 0, -1));

	check_consistent(&o, v3(-1, -1, -1), v3(3, 2, 5), inside_box);
}

/* The least signed distance along a segment to a box (exact, from the
 * slabs' breakpoints) against a dense sampling of the segment: never
 * above the sampling's least, and no further below it than the
 * sampling's step allows; the t returned is where that distance is. */
static void
test_box_segment_nearest(void **state)
{
	struct obstacle o = box(v3(0, 0, 0), v3(2, 1, 4));
	unsigned long seed = 12345;
	double t, f;
	int i, k;

	(void)state;
	/* flat above the top: the lowest t, an end */
	f = obstacle_segment_nearest(&o, v3(0.5, 1.5, 1), v3(1.5, 1.5, 3), &t);
	assert_double_equal(f, 0.5, EPS);
	assert_double_equal(t, 0, EPS);
	/* past a vertical edge, nearest a quarter of x and z off it */
	f = obstacle_segment_nearest(&o, v3(3.5, 0.5, 3), v3(1.5, 0.5, 5), &t);
	assert_double_equal(f, sqrt(0.125), EPS);
	assert_double_equal(t, 0.625, EPS);
	/* through the box: its deepest point, under the top and the faces
	 * x = 0 and x = 2 alike (depth 0.5 at x = 1) */
	f = obstacle_segment_nearest(&o, v3(-1, 0.5, 2), v3(3, 0.5, 2), &t);
	assert_double_equal(f, -0.5, EPS);
	assert_double_equal(t, 0.5, 1e-12);
	/* one end inside: there */
	f = obstacle_segment_nearest(&o, v3(1, 0.5, 3.5), v3(1, 3, 3.5), &t);
	assert_double_equal(f, -0.5, EPS);
	assert_double_equal(t, 0, EPS);
	for (i = 0; i < 2000; i++) {
		double best = INFINITY, at;
		vec3 a = v3(uniform(&seed, -1.5, 5.5), uniform(&seed, -2.5, 4.5), uniform(&seed, -1.5, 5.5));
		vec3 b = v3(uniform(&seed, -1.5, 5.5), uniform(&seed, -2.5, 4.5), uniform(&seed, -1.5, 5.5));

		f = obstacle_segment_nearest(&o, a, b, &t);
		for (k = 0; k <= 4000; k++)
			best = fmin(best, obstacle_distance(&o, v3_madd(a, v3_sub(b, a), k / 4000.0), NULL, NULL));
		at = obstacle_distance(&o, v3_madd(a, v3_sub(b, a), t), NULL, NULL);
		assert_true(t >= 0 && t <= 1);
		assert_double_equal(f, at, EPS);
		assert_true(f <= best + 1e-12);
		assert_true(f >= best - v3_len(v3_sub(b, a)) / 4000);
	}
}

static void
test_disc(void **state)
{
	/* a 0.2 m disc on a 0.5 m pedestal standing on the floor */
	struct obstacle o = disc(v3(0, 0.5, 0), 0.2, 0.5), f;

	(void)state;
	/* outside: above, beside, below, beyond the rim */
	assert_distance(&o, v3(0.1, 0.7, 0), 0.2, v3(0.1, 0.5, 0), v3(0, 1, 0));
	assert_distance(&o, v3(0, 0.3, -0.5), 0.3, v3(0, 0.3, -0.2), v3(0, 0, -1));
	assert_distance(&o, v3(0.05, -0.1, 0), 0.1, v3(0.05, 0, 0), v3(0, -1, 0));
	assert_distance(&o, v3(0.5, 0.9, 0), 0.5, v3(0.2, 0.5, 0), v3(0.6, 0.8, 0));
	assert_distance(&o, v3(0.3, 0.9, 0.4), 0.5, v3(0.12, 0.5, 0.16), v3(0.36, 0.8, 0.48));
	assert_distance(&o, v3(0.3, -0.4, 0.4), 0.5, v3(0.12, 0, 0.16), v3(0.36, -0.8, 0.48));

	/* inside: out through the top, the side, the bottom */
	assert_distance(&o, v3(0.05, 0.45, 0), -0.05, v3(0.05, 0.5, 0), v3(0, 1, 0));
	assert_distance(&o, v3(0, 0.2, 0.18), -0.02, v3(0, 0.2, 0.2), v3(0, 0, 1));
	assert_distance(&o, v3(0.09, 0.3, 0.12), -0.05, v3(0.12, 0.3, 0.16), v3(0.6, 0, 0.8));
	assert_distance(&o, v3(0, 0.05, 0), -0.05, v3(0, 0, 0), v3(0, -1, 0));
	/* on the axis, nearest the side: +x */
	assert_distance(&o, v3(0, 0.25, 0), -0.2, v3(0.2, 0.25, 0), v3(1, 0, 0));

	/* on the surface and the rim: the top wins, then the side */
	assert_distance(&o, v3(0, 0.5, 0), 0, v3(0, 0.5, 0), v3(0, 1, 0));
	assert_distance(&o, v3(0.2, 0.3, 0), 0, v3(0.2, 0.3, 0), v3(1, 0, 0));
	assert_distance(&o, v3(0.2, 0.5, 0), 0, v3(0.2, 0.5, 0), v3(0, 1, 0));
	assert_distance(&o, v3(0.12, 0.5, 0.16), 0, v3(0.12, 0.5, 0.16), v3(0, 1, 0));
	assert_distance(&o, v3(0, 0, -0.2), 0, v3(0, 0, -0.2), v3(0, 0, -1));

	check_consistent(&o, v3(-0.4, -0.2, -0.4), v3(0.4, 0.8, 0.4), inside_disc);
	/* a flat one, as on a Cusick tester */
	f = disc(v3(1, 2, 3), 0.09, 0.005);
	check_consistent(&f, v3(0.8, 1.9, 2.8), v3(1.2, 2.1, 3.2), inside_disc);
}

static void
test_bounds(void **state)
{
	struct obstacle o;
	vec3 lo, hi;

	(void)state;
	o = plane(v3(0, 1, 0), v3(0, 1, 0));
	obstacle_bounds(&o, &lo, &hi);
	/* inf - inf is NaN: compared, not subtracted */
	assert_true(lo.x == -INFINITY && lo.y == -INFINITY && lo.z == -INFINITY);
	assert_true(hi.x == INFINITY && hi.z == INFINITY);
	assert_double_equal(hi.y, 1, 0);

	o = plane(v3(2, 0, 0), v3(-3, 0, 0));
	obstacle_bounds(&o, &lo, &hi);
	assert_double_equal(lo.x, 2, 0);
	assert_true(lo.y == -INFINITY && lo.z == -INFINITY);
	assert_true(hi.x == INFINITY && hi.y == INFINITY && hi.z == INFINITY);

	o = plane(v3(0, 0, 0), v3(0, 1, 1));
	obstacle_bounds(&o, &lo, &hi);
	assert_true(lo.x == -INFINITY && lo.y == -INFINITY && lo.z == -INFINITY);
	assert_true(hi.x == INFINITY && hi.y == INFINITY && hi.z == INFINITY);

	o = box(v3(0, 0, 0), v3(2, 1, 4));
	obstacle_bounds(&o, &lo, &hi);
	assert_vec_equal(lo, v3(0, 0, 0), 0);
	assert_vec_equal(hi, v3(2, 1, 4), 0);

	o = sphere(v3(1, 2, 3), 0.5);
	obstacle_bounds(&o, &lo, &hi);
	assert_vec_equal(lo, v3(0.5, 1.5, 2.5), 0);
	assert_vec_equal(hi, v3(1.5, 2.5, 3.5), 0);

	o = disc(v3(0, 0.5, 0), 0.2, 0.5);
	obstacle_bounds(&o, &lo, &hi);
	assert_vec_equal(lo, v3(-0.2, 0, -0.2), 0);
	assert_vec_equal(hi, v3(0.2, 0.5, 0.2), 0);

	memset(&o, 0, sizeof o);
	o.kind = OBSTACLE_MESH;
	assert_int_equal(mesh_icosahedron(&o.mesh, v3(0, 0, 0), 1), 0);
	obstacle_bounds(&o, &lo, &hi);
	assert_double_equal(hi.x, (1 + sqrt(5)) / 2 / sqrt(1 + pow((1 + sqrt(5)) / 2, 2)),
	    EPS);
	assert_vec_equal(lo, v3_neg(hi), EPS);
	obstacle_free(&o);
}

/* obstacle_check refuses o, saying something with `word` in it. */
static void
rejects(struct obstacle o, const char *word)
{
	struct drape_err err = { "" };

	if (obstacle_check(&o, &err) == 0)
		fail_msg("obstacle_check accepted a bad %s (%s)", obstacle_kind_name[o.kind], word);
	if (strstr(err.msg, word) == NULL)
		fail_msg("'%s' does not mention '%s'", err.msg, word);
	if (strchr(err.msg, ':') != NULL && strstr(err.msg, word) != err.msg)
		fail_msg("'%s' looks like it has a file:line prefix", err.msg);
}

static void
test_check(void **state)
{
	struct obstacle p = { .kind = OBSTACLE_PLANE, .normal = { 0, 1, 0 } };
	struct obstacle b = { .kind = OBSTACLE_BOX, .lo = { 0, 0, 0 }, .hi = { 1, 1, 1 } };
	struct obstacle s = { .kind = OBSTACLE_SPHERE, .radius = 1 };
	struct obstacle d = { .kind = OBSTACLE_DISC, .radius = 1, .height = 0.1 };
	struct obstacle m = { .kind = OBSTACLE_MESH }, t;
	struct drape_err err;

	(void)state;
	t = p;
	t.normal = v3(0, 3, 4);
	assert_int_equal(obstacle_check(&t, &err), 0);
	assert_vec_equal(t.normal, v3(0, 0.6, 0.8), EPS);
	t.normal = v3(1e-200, 0, 0);
	assert_int_equal(obstacle_check(&t, &err), 0);
	assert_vec_equal(t.normal, v3(1, 0, 0), 0);
	t = b;
	t.friction = 0.4;
	assert_int_equal(obstacle_check(&t, &err), 0);

	t = p;
	t.normal = v3(0, 0, 0);
	rejects(t, "normal");
	t.normal = v3(0, NAN, 1);
	rejects(t, "normal");
	t.normal = v3(0, INFINITY, 0);
	rejects(t, "normal");
	t = p;
	t.friction = -0.1;
	rejects(t, "friction");
	t.friction = NAN;
	rejects(t, "friction");

	t = b;
	t.hi.x = 0;
	rejects(t, "min");
	t = b;
	t.lo.y = 2;
	rejects(t, "min");
	t = b;
	t.hi.z = INFINITY;
	rejects(t, "min");

	t = s;
	t.radius = 0;
	rejects(t, "radius");
	t.radius = -1;
	rejects(t, "radius");
	t.radius = INFINITY;
	rejects(t, "radius");
	t.radius = NAN;
	rejects(t, "radius");

	t = d;
	t.radius = 0;
	rejects(t, "radius");
	t = d;
	t.height = 0;
	rejects(t, "height");
	t.height = -0.1;
	rejects(t, "height");
	t.height = INFINITY;
	rejects(t, "height");

	rejects(m, "triangle");
	assert_int_equal(mesh_icosahedron(&m.mesh, v3(0, 0, 0), 1), 0);
	assert_int_equal(obstacle_check(&m, &err), 0);
	m.friction = -1;
	rejects(m, "friction");
	obstacle_free(&m);
	assert_null(m.mesh.x);
	assert_null(m.mesh.tri);
}

static vec3
vertex(const struct mesh *m, int v)
{
	return v3_load(m->x + 3 * v);
}

static vec3
centroid(const struct mesh *m, size_t t)
{
	const int *i = m->tri + 3 * t;

	return v3_scale(v3_add(vertex(m, i[0]), v3_add(vertex(m, i[1]), vertex(m, i[2]))),
	    1.0 / 3);
}

static vec3
face_normal(const struct mesh *m, size_t t)
{
	const int *i = m->tri + 3 * t;
	vec3 a = vertex(m, i[0]);
	vec3 n = v3_cross(v3_sub(vertex(m, i[1]), a), v3_sub(vertex(m, i[2]), a));

	return v3_scale(n, 1 / v3_len(n));
}

static void
test_icosahedron(void **state)
{
	vec3 c = v3(0.3, -0.2, 1);
	double r = 0.7, edge = -1;
	struct mesh m;
	size_t t;
	int k, uses[12][12] = { { 0 } };

	(void)state;
	assert_int_equal(mesh_icosahedron(&m, c, r), 0);
	assert_int_equal(m.nverts, 12);
	assert_int_equal(m.ntri, 20);
	for (k = 0; k < 12; k++)
		assert_double_equal(v3_len(v3_sub(vertex(&m, k), c)), r, EPS);
	for (t = 0; t < m.ntri; t++) {
		vec3 g = centroid(&m, t), n = face_normal(&m, t);

		for (k = 0; k < 3; k++) {
			int a = m.tri[3 * t + k], b = m.tri[3 * t + (k + 1) % 3];
			double len = v3_len(v3_sub(vertex(&m, a), vertex(&m, b)));

			if (edge < 0)
				edge = len;
			assert_double_equal(len, edge, EPS);
			uses[a][b]++;
		}
		/* outward: along the centre -> centroid direction */
		assert_double_equal(v3_dot(n, v3_sub(g, c)), v3_len(v3_sub(g, c)), EPS);
		/* just inside and just outside the face */
		assert_double_equal(mesh_winding_number(&m, v3_madd(g, n, -1e-6)), 1, 1e-9);
		assert_double_equal(mesh_winding_number(&m, v3_madd(g, n, 1e-6)), 0, 1e-9);
	}
	/* the edge of a regular icosahedron of circumradius r */
	assert_double_equal(edge, r * 4 / sqrt(10 + 2 * sqrt(5)), EPS);
	/* closed and consistently oriented: each edge once each way */
	for (k = 0; k < 144; k++) {
		int a = k / 12, b = k % 12;

		assert_int_equal(uses[a][b], uses[b][a]);
		assert_true(uses[a][b] <= 1);
	}
	assert_double_equal(mesh_winding_number(&m, c), 1, 1e-12);
	for (k = 0; k < 12; k++) {
		vec3 v = vertex(&m, k);

		assert_double_equal(mesh_winding_number(&m, v3_madd(c, v3_sub(v, c), 0.999)), 1,
		    1e-9);
		assert_double_equal(mesh_winding_number(&m, v3_madd(c, v3_sub(v, c), 1.001)), 0,
		    1e-9);
	}
	assert_double_equal(mesh_winding_number(&m, v3(100, -50, 30)), 0, 1e-12);
	assert_double_equal(mesh_winding_number(&m, v3_add(c, v3(0, 2 * r, 0))), 0, 1e-12);
	mesh_free(&m);
	assert_null(m.x);
	assert_int_equal(m.nverts, 0);
}

/* An icosahedron as a mesh obstacle: the distance to its faces, signed. */
static void
test_mesh_distance(void **state)
{
	struct obstacle o = { .kind = OBSTACLE_MESH };
	vec3 c = v3(1, 2, 3), q, n;
	double d;
	size_t t;

	(void)state;
	assert_int_equal(mesh_icosahedron(&o.mesh, c, 2), 0);
	for (t = 0; t < o.mesh.ntri; t++) {
		vec3 g = centroid(&o.mesh, t), fn = face_normal(&o.mesh, t);
		double in = v3_len(v3_sub(g, c));

		assert_distance(&o, v3_madd(g, fn, 0.5), 0.5, g, fn);
		assert_distance(&o, v3_madd(g, fn, -0.25), -0.25, g, fn);
		d = obstacle_distance(&o, g, &q, &n);
		assert_double_equal(d, 0, 1e-12);
		assert_vec_equal(n, fn, 1e-12);
		/* from the centre every face is as far */
		assert_double_equal(obstacle_distance(&o, c, NULL, NULL), -in, 1e-12);
	}
	/* beyond a vertex: the vertex is nearest */
	q = vertex(&o.mesh, 0);
	assert_distance(&o, v3_madd(c, v3_sub(q, c), 1.5), 1, q, v3_scale(v3_sub(q, c), 0.5));
	obstacle_free(&o);
}

static void
test_transform(void **state)
{
	struct mesh m;
	vec3 lo, hi;

	(void)state;
	assert_int_equal(mesh_icosahedron(&m, v3(0, 0, 0), 1), 0);
	mesh_bounds(&m, &lo, &hi);
	mesh_transform(&m, 2, v3(1, -1, 3));
	{
		vec3 lo2, hi2;

		mesh_bounds(&m, &lo2, &hi2);
		assert_vec_equal(lo2, v3_add(v3_scale(lo, 2), v3(1, -1, 3)), EPS);
		assert_vec_equal(hi2, v3_add(v3_scale(hi, 2), v3(1, -1, 3)), EPS);
	}
	assert_double_equal(mesh_winding_number(&m, v3(1, -1, 3)), 1, 1e-12);
	mesh_free(&m);
	mesh_bounds(&m, &lo, &hi);
	assert_true(lo.x > hi.x);
}

/* Text into a new temporary file; its name into path. */
static void
write_obj(char *path, size_t len, const char *text)
{
	FILE *f;
	int fd;

	snprintf(path, len, "%s/test_obstacle-XXXXXX", TOP_BUILDDIR);
	if ((fd = mkstemp(path)) < 0)
		fail_msg("mkstemp %s failed", path);
	if ((f = fdopen(fd, "w")) == NULL) {
		close(fd);
		fail_msg("fdopen failed");
	}
	if (fputs(text, f) < 0)
		fail_msg("write to %s failed", path);
	assert_int_equal(fclose(f), 0);
}

static void
load_text(struct mesh *m, const char *text)
{
	struct drape_err err;
	char path[512];
	int rc;

	write_obj(path, sizeof path, text);
	rc = mesh_load_obj(m, path, &err);
	remove(path);
	if (rc != 0)
		fail_msg("mesh_load_obj: %s", err.msg);
}

static const char cube_obj[] =
	"# a unit cube, faces written every way\n"
	"mtllib cube.mtl\n"
	"o cube\n"
	"v 0 0 0\n"
	"v 1 0 0\n"
	"v 1 1 0\n"
	"v 0 1 0\n"
	"v 0 0 1\n"
	"v 1.0 0e0 1\n"
	"  v\t1 1 1   # a comment after it\n"
	"v 0 1 1 1.0\n"
	"\n"
	"vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
	"vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\n"
	"g sides\n"
	"s off\n"
	"usemtl white\n"
	"f -8 -5 -6 -7\n"		/* z = 0: 1 4 3 2 */
	"f 5/1 6/2 7/3 8/4\n"		/* z = 1 */
	"f 1//3 2//3 6//3 5//3\n"	/* y = 0 */
	"f 4/1/2 8/2/2 7/3/2 3/4/2\n"	/* y = 1 */
	"f 1 5 8 4\r\n"			/* x = 0 */
	"f\t2/-4/-1 3/-3/-1 7/-2/-1 6/-1/-1\n";	/* x = 1 */

static void
test_load_obj(void **state)
{
	struct mesh m;
	vec3 lo, hi;
	size_t t;

	(void)state;
	load_text(&m, cube_obj);
	assert_int_equal(m.nverts, 8);
	assert_int_equal(m.ntri, 12);
	assert_vec_equal(vertex(&m, 5), v3(1, 0, 1), 0);
	/* the fan of 1 4 3 2 */
	assert_int_equal(m.tri[0], 0);
	assert_int_equal(m.tri[1], 3);
	assert_int_equal(m.tri[2], 2);
	assert_int_equal(m.tri[3], 0);
	assert_int_equal(m.tri[4], 2);
	assert_int_equal(m.tri[5], 1);
	mesh_bounds(&m, &lo, &hi);
	assert_vec_equal(lo, v3(0, 0, 0), 0);
	assert_vec_equal(hi, v3(1, 1, 1), 0);
	/* every face points out of the cube */
	for (t = 0; t < m.ntri; t++)
		assert_true(v3_dot(face_normal(&m, t), v3_sub(centroid(&m, t), v3(0.5, 0.5, 0.5)))
		    > 0.1);
	assert_double_equal(mesh_winding_number(&m, v3(0.5, 0.5, 0.5)), 1, 1e-12);
	assert_double_equal(mesh_winding_number(&m, v3(0.1, 0.9, 0.2)), 1, 1e-12);
	assert_double_equal(mesh_winding_number(&m, v3(1.5, 0.5, 0.5)), 0, 1e-12);
	mesh_free(&m);

	/* a pentagon's fan; negative indices count from the vertices so far */
	load_text(&m, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0\n"
	    "f 1 2 3 4 5\nf -3 -2 -1\nv 0 0 1\nf -1 -2 -3\n");
	assert_int_equal(m.nverts, 6);
	assert_int_equal(m.ntri, 5);
	{
		static const int want[15] = { 0, 1, 2, 0, 2, 3, 0, 3, 4, 2, 3, 4, 5, 4, 3 };

		assert_memory_equal(m.tri, want, sizeof want);
	}
	mesh_free(&m);
}

/* mesh_load_obj refuses text, with the path, `where` and `word` in the
 * message, and leaves nothing allocated. */
static void
obj_rejects(const char *text, const char *where, const char *word)
{
	struct drape_err err = { "" };
	struct mesh m = { (double *)&m, 1, (int *)&m, 1 };
	char path[512], prefix[540];
	int rc;

	write_obj(path, sizeof path, text);
	rc = mesh_load_obj(&m, path, &err);
	remove(path);
	if (rc == 0)
		fail_msg("mesh_load_obj accepted %s", text);
	snprintf(prefix, sizeof prefix, "%s%s", path, where);
	if (strncmp(err.msg, prefix, strlen(prefix)) != 0 || strstr(err.msg, word) == NULL)
		fail_msg("'%s' does not start '%s' and mention '%s'", err.msg, prefix, word);
	assert_null(m.x);
	assert_null(m.tri);
	assert_int_equal(m.nverts, 0);
	assert_int_equal(m.ntri, 0);
}

static void
test_load_obj_errors(void **state)
{
	static const char tri[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
	struct drape_err err;
	struct mesh m;
	char text[256], path[] = TOP_BUILDDIR "/no-such-mesh.obj";

	(void)state;
	assert_int_equal(mesh_load_obj(&m, path, &err), -1);
	assert_true(strncmp(err.msg, path, strlen(path)) == 0);
	assert_non_null(strstr(err.msg, ": cannot open: "));
	assert_non_null(strstr(err.msg, strerror(ENOENT)));
	assert_null(m.x);

	obj_rejects("v 0 0 0\nv 1 x 0\n", ":2: ", "'x'");
	obj_rejects("# c\nv 0 0 0.5.5\n", ":2: ", "'0.5.5'");
	obj_rejects("v 0 0 nan\n", ":1: ", "finite");
	obj_rejects("v 0 1e999 0\n", ":1: ", "finite");
	obj_rejects("v 0 0\n", ":1: ", "3 numbers");
	obj_rejects("v 0 0 0 w\n", ":1: ", "'w'");

	snprintf(text, sizeof text, "%sf 1 2 4\n", tri);
	obj_rejects(text, ":4: ", "from 1 to 3");
	snprintf(text, sizeof text, "%sf 1 2 0\n", tri);
	obj_rejects(text, ":4: ", "got '0'");
	snprintf(text, sizeof text, "%sf -4 -2 -1\n", tri);
	obj_rejects(text, ":4: ", "from -3 to -1");
	snprintf(text, sizeof text, "%sf 1 2 99999999999999999999\n", tri);
	obj_rejects(text, ":4: ", "from 1 to 3");
	obj_rejects("f 1 2 3\nv 0 0 0\n", ":1: ", "before");
	snprintf(text, sizeof text, "%sf 1 2 3.5\n", tri);
	obj_rejects(text, ":4: ", "'3.5'");
	snprintf(text, sizeof text, "%sf 1/1/1/1 2 3\n", tri);
	obj_rejects(text, ":4: ", "'1/1/1/1'");
	snprintf(text, sizeof text, "%sf 1/x 2 3\n", tri);
	obj_rejects(text, ":4: ", "'1/x'");

	snprintf(text, sizeof text, "%sf 1 2 3\nf 1 2\n", tri);
	obj_rejects(text, ":5: ", "3 or more");
	snprintf(text, sizeof text, "%sf\n", tri);
	obj_rejects(text, ":4: ", "3 or more");

	obj_rejects(tri, ": ", "face");
	obj_rejects("", ": ", "face");
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_plane),
		cmocka_unit_test(test_sphere),
		cmocka_unit_test(test_box),
		cmocka_unit_test(test_box_segment_nearest),
		cmocka_unit_test(test_disc),
		cmocka_unit_test(test_bounds),
		cmocka_unit_test(test_check),
		cmocka_unit_test(test_icosahedron),
		cmocka_unit_test(test_mesh_distance),
		cmocka_unit_test(test_transform),
		cmocka_unit_test(test_load_obj),
		cmocka_unit_test(test_load_obj_errors),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
