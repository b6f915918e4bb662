/* test_mg.c: the multigrid preconditioner (mg.h) inside a plain PCG on
 * the implicit step's Newton matrices H = M/beta^2 + K(x), beta = (2/3) h
 * for h = 10 ms (BDF2): the shipped cloths and the peers' 0.24 m square at
 * three sizes, at rest, crumpled (folded 150 degrees over a line oblique
 * to the grid, plus noise), and crumpled with held nodes and contacts.
 * Iteration counts and times are printed, never asserted for time. */
#include <malloc.h>
#include <math.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "blockmat.h"
#include "clock.h"
#include "jacobian.h"
#include "mg.h"
#include "network.h"
#include "testutil.h"
#include "vec3.h"

#if defined(__SANITIZE_ADDRESS__)
#define UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define UNDER_ASAN 1
#endif
#endif

#define BETA (2.0 / 3.0 * 10e-3)
#define TOL 1e-6
/* The iteration bound every case must meet (the counts measured are
 * printed; 12 at most at the time of writing). */
#define MAX_ITER 25

static vec3
unit(vec3 a)
{
	return v3_scale(a, 1 / v3_len(a));
}

enum state { REST, CRUMPLED, LOADED };
static const char *const state_name[] = { "rest", "crumpled", "loaded" };

/* A network, its state and its Newton matrix. */
struct sys {
	struct scene sc;
	struct network net;
	struct blockmat A;
	double *x;		/* 3n positions */
	double *side;		/* n: signed distance from the fold line */
	unsigned char *held;	/* n */
};

static unsigned rng_state;

static double
rnd(void)			/* uniform in [-1, 1) */
{
	rng_state = rng_state * 1103515245u + 12345u;
	return (double)(rng_state >> 8) / (1u << 23) - 1;
}

static void
build(struct sys *s, const char *text, const char *path)
{
	struct drape_err err;

	memset(s, 0, sizeof *s);
	if (text != NULL)
		parse_text(&s->sc, text);
	else
		load_shipped(&s->sc, path);
	if (network_build(&s->net, &s->sc, &err) != 0)
		fail_msg("network_build: %s", err.msg);
	s->x = malloc(3 * (size_t)s->net.cl.n * sizeof *s->x);
	s->side = calloc((size_t)s->net.cl.n, sizeof *s->side);
	s->held = calloc((size_t)s->net.cl.n, sizeof *s->held);
	assert_true(s->x && s->side && s->held);
	assert_int_equal(blockmat_init_cloth(&s->A, &s->net.cl), 0);
}

static void
sys_free(struct sys *s)
{
	blockmat_free(&s->A);
	network_free(&s->net);
	scene_free(&s->sc);
	free(s->x);
	free(s->side);
	free(s->held);
}

/* The peers' table: a 0.24 m square of N x N nodes, 100 g/m2, E*t = 50
 * N/m, G*t = 5 N/m, B = 1 uN*m, thickness a quarter spacing. */
static void
build_peers(struct sys *s, int N)
{
	char text[1024];
	double h = 0.24 / (N - 1), t = h / 4;

	snprintf(text, sizeof text, "[simulation]\nduration = 1 s\ndt = 1 ms\nintegrator = rk4\n"
	    "[cloth]\nnodes = %d %d\nspacing = %.17g m\norientation = +x +z\nweight = 100 g/m2\n"
	    "thickness = %.17g m\nmodulus_warp = %.17g Pa\nmodulus_weft = %.17g Pa\n"
	    "shear_modulus = %.17g Pa\nbending_warp = 1 uN*m\nbending_weft = 1 uN*m\n",
	    N, N, h, t, 50 / t, 50 / t, 5 / t);
	build(s, text, NULL);
}

/* The cloth's plane: warp and weft unit vectors from its rest positions. */
static void
cloth_axes(const struct cloth *cl, vec3 *u, vec3 *v)
{
	int p, i, j, q;

	*u = v3(1, 0, 0);
	*v = v3(0, 0, 1);
	for (p = 0; p < cl->n; p++) {
		cloth_grid_ij(cl, p, &i, &j);
		if (i + 1 < cl->nu && (q = cloth_node(cl, i + 1, j)) >= 0)
			*u = unit(v3_sub(v3_load(cl->x0 + 3 * q), v3_load(cl->x0 + 3 * p)));
		if (j + 1 < cl->nv && (q = cloth_node(cl, i, j + 1)) >= 0)
			*v = unit(v3_sub(v3_load(cl->x0 + 3 * q), v3_load(cl->x0 + 3 * p)));
	}
}

/* The crumpled state's shape: as below, or as bench/mg.sh asks through
 * the environment (MG_FOLD degrees, MG_RADIUS and MG_NOISE spacings). */
static double
knob(const char *name, double dflt)
{
	const char *v = getenv(name);

	return v != NULL && *v != '\0' ? atof(v) : dflt;
}

/* x0 folded by 150 degrees over a line through the centre at 30 degrees
 * to the warp, round a cylinder of radius 3 spacings (each hinge turns by
 * about 19 degrees), plus noise of 0.1 spacing on every coordinate: the
 * springs rotate, some compress. */
static void
crumple(struct sys *s)
{
	const struct cloth *cl = &s->net.cl;
	vec3 u, v, nrm, c = v3(0, 0, 0), along, across;
	double R = knob("MG_RADIUS", 3) * cl->h, tmax = knob("MG_FOLD", 150) * V3_PI / 180;
	double noise = knob("MG_NOISE", 0.1);
	int p, k;

	cloth_axes(cl, &u, &v);
	nrm = unit(v3_cross(u, v));
	along = v3_add(v3_scale(u, cos(V3_PI / 6)), v3_scale(v, sin(V3_PI / 6)));
	across = unit(v3_cross(nrm, along));
	for (p = 0; p < cl->n; p++)
		c = v3_add(c, v3_scale(v3_load(cl->x0 + 3 * p), 1.0 / cl->n));
	for (p = 0; p < cl->n; p++) {
		vec3 x = v3_load(cl->x0 + 3 * p), d = v3_sub(x, c);
		double sd = v3_dot(d, across), th;

		s->side[p] = sd;
		if (sd > 0) {
			vec3 base = v3_sub(x, v3_scale(across, sd));

			th = fmin(sd / R, tmax);
			x = v3_add(base, v3_add(v3_scale(across, R * sin(th)),
			    v3_scale(nrm, R * (1 - cos(th)))));
			if (sd > R * tmax) {
				vec3 dir = v3_add(v3_scale(across, cos(tmax)), v3_scale(nrm, sin(tmax)));

				x = v3_add(x, v3_scale(dir, sd - R * tmax));
			}
		}
		v3_store(s->x + 3 * p, x);
		for (k = 0; k < 3; k++)
			s->x[3 * p + k] += noise * cl->h * rnd();
	}
}

static void
add_diag(struct blockmat *A, int p, const double *b, double scale)
{
	double *d = A->val + 9 * (size_t)A->diag[p];
	int i;

	for (i = 0; i < 9; i++)
		d[i] += scale * b[i];
}

/* Held nodes decoupled: their rows and columns zero but for m/beta^2 I. */
static void
hold(struct sys *s)
{
	const struct cloth *cl = &s->net.cl;
	struct blockmat *A = &s->A;
	int p, k, i;

	for (p = 0; p < cl->n; p++)
		for (k = A->start[p]; k < A->start[p + 1]; k++)
			if (s->held[p] || s->held[A->col[k]])
				memset(A->val + 9 * (size_t)k, 0, 9 * sizeof *A->val);
	for (p = 0; p < cl->n; p++)
		if (s->held[p])
			for (i = 0; i < 3; i++)
				A->val[9 * (size_t)A->diag[p] + 4 * i] = cl->mass[p] / (BETA * BETA);
}

/* Contacts: k_c n n^T with k_c = 1000 m/beta^2 on every fifth node, n
 * the plane's normal on the flat side, a random direction on the folded
 * one (the layers touching). */
static void
add_contacts(struct sys *s)
{
	const struct cloth *cl = &s->net.cl;
	vec3 u, v, nrm;
	int p, i, j;

	cloth_axes(cl, &u, &v);
	nrm = unit(v3_cross(u, v));
	for (p = 0; p < cl->n; p++) {
		double b[9], a[3], kc = 1000 * cl->mass[p] / (BETA * BETA);
		vec3 n = nrm;

		if (s->held[p] || p % 5 != 2)
			continue;
		if (s->side[p] > 0)
			n = unit(v3(rnd(), rnd(), rnd() + 0.1));
		a[0] = n.x;
		a[1] = n.y;
		a[2] = n.z;
		for (i = 0; i < 3; i++)
			for (j = 0; j < 3; j++)
				b[3 * i + j] = a[i] * a[j];
		add_diag(&s->A, p, b, kc);
	}
}

/* H at the state asked: ck = 1, cc = 0, plus M/beta^2; the scene's held
 * nodes always, more (the first weft line and every 37th node) and the
 * contacts when loaded. */
static void
assemble_jiggled(struct sys *s, enum state st, double jiggle)
{
	const struct cloth *cl = &s->net.cl;
	struct jacobian jc;
	int p, i, j;

	rng_state = 2024u + (unsigned)cl->n;
	if (st == REST)
		memcpy(s->x, cl->x0, 3 * (size_t)cl->n * sizeof *s->x);
	else
		crumple(s);
	if (jiggle > 0) {	/* on a stream of its own: the contacts' stay as they were */
		unsigned keep = rng_state;

		rng_state = 31337;
		for (p = 0; p < 3 * cl->n; p++)
			s->x[p] += jiggle * cl->h * rnd();
		rng_state = keep;
	}
	for (p = 0; p < cl->n; p++) {
		cloth_grid_ij(cl, p, &i, &j);
		s->held[p] = s->net.pr.held[p] || (st == LOADED && (i == 0 || p % 37 == 5));
	}
	assert_int_equal(jacobian_init(&jc, &s->net.fo), 0);
	jacobian_eval(&jc, s->x);
	blockmat_zero(&s->A);
	jacobian_assemble(&jc, 1, 0, &s->A);
	jacobian_free(&jc);
	for (p = 0; p < cl->n; p++)
		for (i = 0; i < 3; i++)
			s->A.val[9 * (size_t)s->A.diag[p] + 4 * i] += cl->mass[p] / (BETA * BETA);
	hold(s);
	if (st == LOADED)
		add_contacts(s);
}

static void
assemble(struct sys *s, enum state st)
{
	assemble_jiggled(s, st, 0);
}

static double
dot(const double *a, const double *b, size_t n)
{
	double s = 0;
	size_t i;

	for (i = 0; i < n; i++)
		s += a[i] * b[i];
	return s;
}

/* Plain preconditioned CG from x = 0 until |r| <= TOL |b|; the number of
 * iterations (max + 1 if it did not get there). */
static int
pcg(const struct blockmat *A, struct mg *m, const double *b, double *x, int max)
{
	size_t n3 = 3 * (size_t)A->n, i;
	double *r = malloc(n3 * sizeof *r), *z = malloc(n3 * sizeof *z);
	double *p = malloc(n3 * sizeof *p), *q = malloc(n3 * sizeof *q);
	double rz, bn = sqrt(dot(b, b, n3));
	int it;

	assert_true(r && z && p && q);
	memset(x, 0, n3 * sizeof *x);
	memcpy(r, b, n3 * sizeof *r);
	mg_apply(m, r, z);
	memcpy(p, z, n3 * sizeof *p);
	rz = dot(r, z, n3);
	for (it = 1; it <= max; it++) {
		double alpha, rz1;

		blockmat_mul(A, p, q);
		alpha = rz / dot(p, q, n3);
		for (i = 0; i < n3; i++) {
			x[i] += alpha * p[i];
			r[i] -= alpha * q[i];
		}
		if (sqrt(dot(r, r, n3)) <= TOL * bn)
			break;
		mg_apply(m, r, z);
		rz1 = dot(r, z, n3);
		for (i = 0; i < n3; i++)
			p[i] = z[i] + rz1 / rz * p[i];
		rz = rz1;
	}
	/* the true residual agrees with the recurrence's */
	blockmat_mul(A, x, q);
	for (i = 0; i < n3; i++)
		q[i] -= b[i];
	if (it <= max)
		assert_true(sqrt(dot(q, q, n3)) <= 10 * TOL * bn);
	free(r);
	free(z);
	free(p);
	free(q);
	return it;
}

static void
random_vector(double *b, size_t n)
{
	size_t i;

	for (i = 0; i < n; i++)
		b[i] = rnd();
}

struct result {
	int iters, levels;
	double t_setup, t_update, t_apply, t_mul;	/* seconds, the least of MG_REPS */
	double bytes;				/* mg's memory a node, or 0 unknown */
};

/* The heap in use (glibc's count), to tell mg's memory; 0 elsewhere. */
static size_t
heap_in_use(void)
{
#if defined(__GLIBC__) && (__GLIBC__ > 2 || __GLIBC_MINOR__ >= 33)
	struct mallinfo2 mi = mallinfo2();

	return mi.uordblks + mi.hblkhd;
#else
	return 0;
#endif
}

/* The least time of reps calls of what(m, s, b, x) (timings print, never
 * assert: the machine may be shared). */
static double
least_time(int reps, void (*what)(struct mg *, struct sys *, const double *, double *),
    struct mg *m, struct sys *s, const double *b, double *x)
{
	double best = HUGE_VAL;
	int rep;

	for (rep = 0; rep < reps; rep++) {
		double t0 = clock_seconds();

		what(m, s, b, x);
		best = fmin(best, clock_seconds() - t0);
	}
	return best;
}

static void
do_setup(struct mg *m, struct sys *s, const double *b, double *x)
{
	(void)b;
	(void)x;
	assert_int_equal(mg_setup(m, &s->A), 0);
}

static void
do_update(struct mg *m, struct sys *s, const double *b, double *x)
{
	(void)b;
	(void)x;
	assert_int_equal(mg_update_fine(m, &s->A), 0);
}

static void
do_apply(struct mg *m, struct sys *s, const double *b, double *x)
{
	(void)s;
	mg_apply(m, b, x);
}

static void
do_mul(struct mg *m, struct sys *s, const double *b, double *x)
{
	(void)m;
	blockmat_mul(&s->A, b, x);
}

/* PCG + MG on s's matrix at one state, for a random right side; times
 * and memory. */
static struct result
solve_case(struct sys *s, enum state st)
{
	size_t n3 = 3 * (size_t)s->net.cl.n, heap;
	double *b = malloc(n3 * sizeof *b), *x = malloc(n3 * sizeof *x);
	int reps = (int)knob("MG_REPS", n3 < 15000 ? 3 : 1);
	struct mg m;
	struct result res;

	assert_true(b && x);
	assemble(s, st);
	heap = heap_in_use();
	assert_int_equal(mg_init(&m, &s->net.cl), 0);
	res.bytes = heap > 0 ? (double)(heap_in_use() - heap) / s->net.cl.n : 0;
	res.levels = m.nlevels;
	res.t_setup = least_time(reps, do_setup, &m, s, b, x);
	rng_state = 99;
	random_vector(b, n3);
	res.iters = pcg(&s->A, &m, b, x, 100);
	res.t_apply = least_time(reps, do_apply, &m, s, b, x);
	res.t_mul = least_time(reps, do_mul, &m, s, b, x);
	res.t_update = least_time(reps, do_update, &m, s, b, x);
	mg_free(&m);
	free(b);
	free(x);
	return res;
}

static void
report(const char *name, const struct sys *s, enum state st, const struct result *r)
{
	print_message("%-16s %5d nodes %-8s %d levels %2d iterations | us: setup %6.0f, "
	    "update_fine %5.0f, apply %5.0f, A x %4.0f | %4.0f bytes/node\n", name, s->net.cl.n,
	    state_name[st], r->levels, r->iters, 1e6 * r->t_setup, 1e6 * r->t_update,
	    1e6 * r->t_apply, 1e6 * r->t_mul, r->bytes);
}

static void
check_cloth(struct sys *s, const char *name, int *iters)
{
	enum state st;

	for (st = REST; st <= LOADED; st++) {
		struct result r = solve_case(s, st);

		report(name, s, st, &r);
		assert_true(r.iters <= MAX_ITER);
		if (iters != NULL)
			iters[st] = r.iters;
	}
}

/* (a), (c), (d): the shipped cloths (and a wider strip). */
static void
shipped_cloths_converge(void **state)
{
	static const struct {
		const char *name, *path, *from, *to;
	} cases[] = {
		{ "tablecloth 25x25", SCENE_DIR "tablecloth.scene", NULL, NULL },
		{ "strip 125x3", SCENE_DIR "strip.scene", NULL, NULL },
		{ "strip 41x3", SCENE_DIR "strip.scene", "nodes = 125 3", "nodes = 41 3" },
		/* coarsened once, to a 63 x 3 strip solved directly */
		{ "strip 125x5", SCENE_DIR "strip.scene", "nodes = 125 3", "nodes = 125 5" },
		{ "disc 31x31", SCENE_DIR "drape.scene", NULL, NULL },
	};
	size_t c;

	(void)state;
	for (c = 0; c < sizeof cases / sizeof *cases; c++) {
		struct sys s;

		memset(&s, 0, sizeof s);
		if (cases[c].from == NULL) {
			build(&s, NULL, cases[c].path);
		} else {
			struct drape_err err;

			load_shipped_with(&s.sc, cases[c].path, cases[c].from, cases[c].to);
			if (network_build(&s.net, &s.sc, &err) != 0)
				fail_msg("network_build: %s", err.msg);
			s.x = malloc(3 * (size_t)s.net.cl.n * sizeof *s.x);
			s.side = calloc((size_t)s.net.cl.n, sizeof *s.side);
			s.held = calloc((size_t)s.net.cl.n, sizeof *s.held);
			assert_true(s.x && s.side && s.held);
			assert_int_equal(blockmat_init_cloth(&s.A, &s.net.cl), 0);
		}
		check_cloth(&s, cases[c].name, NULL);
		sys_free(&s);
	}
}

/* (b): the peers' square at 25^2, 50^2, 100^2: the counts bounded, and
 * not growing with refinement by more than 1.5x (+2). */
static void
peers_iterations_do_not_grow(void **state)
{
	static const int sizes[] = { 25, 50, 100 };
	int it[3][3], k, st;

	(void)state;
	for (k = 0; k < 3; k++) {
		struct sys s;
		char name[32];

		snprintf(name, sizeof name, "peers %dx%d", sizes[k], sizes[k]);
		build_peers(&s, sizes[k]);
		check_cloth(&s, name, it[k]);
		sys_free(&s);
	}
	for (k = 1; k < 3; k++)
		for (st = REST; st <= LOADED; st++)
			assert_true(2 * it[k][st] <= 3 * it[0][st] + 4);
}

/* B is symmetric and positive: r1.B r2 == r2.B r1, r.B r > 0, on the
 * crumpled tablecloth with held nodes and contacts and on the disc. */
static void
symmetric_positive_definite(void **state)
{
	static const char *const paths[] = { SCENE_DIR "tablecloth.scene", SCENE_DIR "drape.scene" };
	size_t c;

	(void)state;
	for (c = 0; c < 2; c++) {
		struct sys s;
		struct mg m;
		size_t n3;
		double *r1, *r2, *z1, *z2, a, b, aa, bb;
		int k;

		build(&s, NULL, paths[c]);
		assemble(&s, LOADED);
		n3 = 3 * (size_t)s.net.cl.n;
		r1 = malloc(n3 * sizeof *r1);
		r2 = malloc(n3 * sizeof *r2);
		z1 = malloc(n3 * sizeof *z1);
		z2 = malloc(n3 * sizeof *z2);
		assert_true(r1 && r2 && z1 && z2);
		assert_int_equal(mg_init(&m, &s.net.cl), 0);
		assert_int_equal(mg_setup(&m, &s.A), 0);
		rng_state = 7;
		for (k = 0; k < 5; k++) {
			random_vector(r1, n3);
			random_vector(r2, n3);
			mg_apply(&m, r1, z1);
			mg_apply(&m, r2, z2);
			a = dot(r1, z2, n3);
			b = dot(r2, z1, n3);
			aa = dot(r1, z1, n3);
			bb = dot(r2, z2, n3);
			assert_true(aa > 0 && bb > 0);
			assert_double_equal(a, b, 1e-10 * sqrt(aa * bb));
		}
		print_message("%s: r1.B r2 - r2.B r1 = %.1e of sqrt(r1.B r1 r2.B r2)\n",
		    paths[c] + strlen(SCENE_DIR), fabs(a - b) / sqrt(aa * bb));
		/* the same with the coarse levels stale */
		assemble(&s, CRUMPLED);
		assert_int_equal(mg_update_fine(&m, &s.A), 0);
		mg_apply(&m, r1, z1);
		mg_apply(&m, r2, z2);
		assert_double_equal(dot(r1, z2, n3), dot(r2, z1, n3),
		    1e-10 * sqrt(dot(r1, z1, n3) * dot(r2, z2, n3)));
		assert_true(dot(r1, z1, n3) > 0);
		mg_free(&m);
		sys_free(&s);
		free(r1);
		free(r2);
		free(z1);
		free(z2);
	}
}

/* A grid too small or too narrow to coarsen (2 x 2, 4 x 4, a 3 x 9 and a
 * 40 x 2 strip) is one level, solved exactly by the envelope Cholesky:
 * A B r = r. */
static void
exact_on_one_level(void **state)
{
	static const char *const sizes[] = { "2 2", "4 4", "3 9", "40 2" };
	size_t c, i;

	(void)state;
	for (c = 0; c < sizeof sizes / sizeof *sizes; c++) {
		char text[600];
		struct sys s;
		struct mg m;
		size_t n3;
		double *r, *z, *az, err = 0, scale = 0;

		snprintf(text, sizeof text, "[simulation]\nduration = 1 s\ndt = 1 ms\nintegrator = rk4\n"
		    "[cloth]\nnodes = %s\nspacing = 10 mm\nweight = 150 g/m2\nthickness = 0.55 mm\n"
		    "modulus_warp = 0.45 MPa\nmodulus_weft = 0.3 MPa\nshear_modulus = 9 kPa\n"
		    "bending_warp = 3 uN*m\nbending_weft = 2 uN*m\n", sizes[c]);
		build(&s, text, NULL);
		assemble(&s, CRUMPLED);
		n3 = 3 * (size_t)s.net.cl.n;
		r = malloc(n3 * sizeof *r);
		z = malloc(n3 * sizeof *z);
		az = malloc(n3 * sizeof *az);
		assert_true(r && z && az);
		assert_int_equal(mg_init(&m, &s.net.cl), 0);
		assert_int_equal(m.nlevels, 1);
		assert_int_equal(mg_levels(&m), 1);	/* what bdf2 asks */
		assert_int_equal(mg_setup(&m, &s.A), 0);
		random_vector(r, n3);
		mg_apply(&m, r, z);
		blockmat_mul(&s.A, z, az);
		for (i = 0; i < n3; i++) {
			err = fmax(err, fabs(az[i] - r[i]));
			scale = fmax(scale, fabs(r[i]));
		}
		assert_true(err <= 1e-10 * scale);
		mg_free(&m);
		sys_free(&s);
		free(r);
		free(z);
		free(az);
	}
}

/* On the disc every node of every level but the coarsest has a parent,
 * among the coarse nodes the shape keeps, with bilinear weights summing
 * to 1; a held node that is not a coarse node gets zero weights from the
 * operator (its row and column are decoupled). */
static void
interpolation_covers_the_shape(void **state)
{
	struct sys s;
	struct mg m;
	int l, p, e, i;

	(void)state;
	build(&s, NULL, SCENE_DIR "drape.scene");
	assemble(&s, LOADED);
	assert_int_equal(mg_init(&m, &s.net.cl), 0);
	assert_int_equal(mg_setup(&m, &s.A), 0);
	assert_true(m.nlevels >= 3);
	assert_int_equal(mg_levels(&m), m.nlevels);
	for (l = 0; l + 1 < m.nlevels; l++)
		for (p = 0; p < m.lv[l].n; p++) {
			const struct mg_level *f = &m.lv[l];
			double sum = 0, most = 0;

			assert_true(f->pstart[p + 1] > f->pstart[p]);
			for (e = f->pstart[p]; e < f->pstart[p + 1]; e++) {
				assert_true(f->par[e] >= 0 && f->par[e] < m.lv[l + 1].n);
				sum += f->pw[e];
				for (i = 0; i < 9; i++)
					most = fmax(most, fabs(f->pb[9 * (size_t)e + i]));
			}
			assert_double_equal(sum, 1, 1e-12);
			if (l == 0 && s.held[p] && f->pstart[p + 1] - f->pstart[p] > 1)
				assert_true(most == 0);
		}
	mg_free(&m);
	sys_free(&s);
}

/* mg_setup refuses a matrix on another pattern and one not positive
 * definite, and works again after. */
static void
setup_refuses(void **state)
{
	struct sys s, other;
	struct mg m;

	(void)state;
	build(&s, NULL, SCENE_DIR "tablecloth.scene");
	build(&other, NULL, SCENE_DIR "drape.scene");
	assemble(&s, REST);
	assemble(&other, REST);
	assert_int_equal(mg_init(&m, &s.net.cl), 0);
	assert_int_equal(mg_setup(&m, &other.A), -1);
	s.A.val[9 * (size_t)s.A.diag[100]] = -1;	/* a negative pivot */
	assert_int_equal(mg_setup(&m, &s.A), -1);
	assemble(&s, REST);
	assert_int_equal(mg_setup(&m, &s.A), 0);
	mg_free(&m);
	mg_free(&m);		/* a zeroed one is fine */
	sys_free(&s);
	sys_free(&other);
}

/* The Newton loop's use: mg_setup at its first iterate, mg_update_fine at
 * the next (here every node moved by up to 0.05 spacing, more than a
 * Newton step moves it): still a good preconditioner. Not across a
 * change of the held nodes or the contacts: the coarse levels would not
 * know them (the crumpled state's under the loaded one's take 31). */
static void
stale_coarse_levels(void **state)
{
	struct sys s;
	struct mg m;
	size_t n3;
	double *b, *x;
	int fresh, stale;

	(void)state;
	build_peers(&s, 50);
	n3 = 3 * (size_t)s.net.cl.n;
	b = malloc(n3 * sizeof *b);
	x = malloc(n3 * sizeof *x);
	assert_true(b && x);
	assert_int_equal(mg_init(&m, &s.net.cl), 0);
	assemble(&s, LOADED);
	assert_int_equal(mg_setup(&m, &s.A), 0);
	assemble_jiggled(&s, LOADED, 0.05);
	rng_state = 5;
	random_vector(b, n3);
	assert_int_equal(mg_update_fine(&m, &s.A), 0);
	stale = pcg(&s.A, &m, b, x, 100);
	assert_int_equal(mg_setup(&m, &s.A), 0);
	fresh = pcg(&s.A, &m, b, x, 100);
	print_message("peers 50x50 loaded, moved 0.05 spacing: %d iterations with fresh "
	    "coarse levels, %d with stale ones\n", fresh, stale);
	assert_true(stale <= MAX_ITER);
	mg_free(&m);
	sys_free(&s);
	free(b);
	free(x);
}

/* The process's address space now, in bytes. */
static size_t
address_space(void)
{
	unsigned long pages = 0;
	FILE *f = fopen("/proc/self/statm", "r");

	if (f == NULL)
		return 0;
	if (fscanf(f, "%lu", &pages) != 1)
		pages = 0;
	fclose(f);
	return (size_t)pages * (size_t)sysconf(_SC_PAGESIZE);
}

/* Takes (and leaks: a child's) what the heap has free, so that what a
 * call allocates next must grow the address space. */
static void
eat_free_heap(void)
{
	static const size_t sizes[] = { 1 << 20, 1 << 16, 1 << 12, 256, 16 };
	size_t i;

	for (i = 0; i < sizeof sizes / sizeof *sizes; i++)
		while (malloc(sizes[i]) != NULL)
			;
}

/* Out of memory, mg_init returns -1 and leaves nothing to crash on: in a
 * child under an address space limit (as test_cli's ulimit -v), its
 * heap's free memory taken first, at limits from nothing to enough, so
 * that each allocation fails in some child. Not under AddressSanitizer,
 * which reserves terabytes before main, nor under valgrind, which runs
 * out of room itself. */
static void
out_of_memory_is_an_error(void **state)
{
	struct sys s;
	size_t extra;
	int failed = 0, passed = 0;

	(void)state;
#ifdef UNDER_ASAN
	skip();
#endif
	if (address_space() == 0 ||
	    (getenv("LD_PRELOAD") != NULL && strstr(getenv("LD_PRELOAD"), "vgpreload") != NULL))
		skip();
	build_peers(&s, 50);
	assemble(&s, REST);
	for (extra = 0; extra < ((size_t)64 << 20); extra = extra * 5 / 4 + 4096) {
		pid_t pid = fork();
		int st;

		assert_true(pid >= 0);
		if (pid == 0) {
			struct rlimit rl;
			struct mg m;
			int r;

			if (getrlimit(RLIMIT_AS, &rl) != 0)
				_exit(3);
			rl.rlim_cur = address_space();
			if (setrlimit(RLIMIT_AS, &rl) != 0)
				_exit(3);
			eat_free_heap();
			rl.rlim_cur = address_space() + extra;
			if (setrlimit(RLIMIT_AS, &rl) != 0)
				_exit(3);
			r = mg_init(&m, &s.net.cl);
			if (r == 0 && mg_setup(&m, &s.A) != 0)
				_exit(2);
			if (r == 0)
				mg_free(&m);
			_exit(r == 0 ? 0 : 1);
		}
		assert_int_equal(waitpid(pid, &st, 0), pid);
		if (!WIFEXITED(st) || WEXITSTATUS(st) > 1)
			fail_msg("limit +%zu bytes: status %d", extra, st);
		failed += WEXITSTATUS(st) == 1;
		passed += WEXITSTATUS(st) == 0;
	}
	print_message("out of memory: %d limits failed cleanly, %d passed\n", failed, passed);
	assert_true(failed > 0 && passed > 0);
	sys_free(&s);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(shipped_cloths_converge),
		cmocka_unit_test(peers_iterations_do_not_grow),
		cmocka_unit_test(symmetric_positive_definite),
		cmocka_unit_test(exact_on_one_level),
		cmocka_unit_test(interpolation_covers_the_shape),
		cmocka_unit_test(setup_refuses),
		cmocka_unit_test(stale_coarse_levels),
		cmocka_unit_test(out_of_memory_is_an_error),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
