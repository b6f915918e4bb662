/* test_collide.c: the chapter's scenes run to rest without intersections,
 * the node stays in the icosahedron, and the grid broad phase misses
 * nothing that the brute one gives the narrow phase. */
#include "testutil.h"

#include "check.h"
#include "broad.h"
#include "ccd.h"
#include "collide.h"
#include "mesh.h"
#include "narrow.h"

static int
has_vt(const struct broad *b, int v, int t)
{
	size_t lo = 0, hi = b->nvt;

	while (lo < hi) {	/* the list is sorted */
		size_t mid = (lo + hi) / 2;

		if (b->vt[mid].v < v || (b->vt[mid].v == v && b->vt[mid].t < t))
			lo = mid + 1;
		else
			hi = mid;
	}
	return lo < b->nvt && b->vt[lo].v == v && b->vt[lo].t == t;
}

static int
has_ee(const struct broad *b, int e1, int e2)
{
	size_t k;

	for (k = 0; k < b->nee; k++)
		if (b->ee[k].a == e1 && b->ee[k].b == e2)
			return 1;
	return 0;
}

/* The pairs brute gives that the narrow phase finds in contact over the
 * motion x0 -> x1 of geometry g (ccd for the vertex paths and edge pairs,
 * the seed test for the segments from a node's neighbours): each must be
 * among grid's pairs for that narrow phase. Returns how many there were. */
static long
grid_covers_brute(const char *name, struct geom g, const double *x0, const double *x1,
    double cell, struct broad *grid, struct broad *grid_seed, struct broad *brute)
{
	struct drape_err err;
	long hits = 0;
	size_t k;

	g.x0 = x0;
	g.x1 = x1;
	g.vbox = NULL;
	if (broad_find(grid, &g, cell, NARROW_CCD, &err) != 0 ||
	    broad_find(grid_seed, &g, cell, NARROW_SEED, &err) != 0 ||
	    broad_find(brute, &g, 0, NARROW_CCD, &err) != 0)
		fail_msg("%s", err.msg);
	for (k = 0; k < brute->nvt; k++) {
		int v = brute->vt[k].v, t = brute->vt[k].t, j, e, hit = 0;
		const int *tn = g.tri + 3 * t;
		vec3 p0[4], p1[4];
		struct seed_hit h;

		p0[0] = v3_load(x0 + 3 * v);
		p1[0] = v3_load(x1 + 3 * v);
		for (j = 0; j < 3; j++) {
			p0[j + 1] = v3_load(x0 + 3 * tn[j]);
			p1[j + 1] = v3_load(x1 + 3 * tn[j]);
		}
		if (ccd_vertex_face(p0, p1, 0, NULL)) {
			hits++;
			if (!has_vt(grid, v, t))
				fail_msg("%s: grid misses node %d against triangle %d", name, v, t);
		}
		for (e = g.vedge_start[v] - 1; !hit && e < g.vedge_start[v + 1]; e++) {
			int f = v;

			if (e >= g.vedge_start[v]) {
				const int *en = g.edge + 2 * g.vedge[e];

				f = en[0] == v ? en[1] : en[0];
				if (tn[0] == f || tn[1] == f || tn[2] == f)
					continue;
			}
			hit = narrow_seed_segment(v3_load(x0 + 3 * f), p1[0], p0[1], p0[2], p0[3],
			    INSIDE_ANGLE, &h);
		}
		if (!hit)
			continue;
		hits++;
		if (!has_vt(grid_seed, v, t))
			fail_msg("%s: grid (seed) misses node %d against triangle %d", name, v, t);
	}
	for (k = 0; k < brute->nee; k++) {
		const int *a = g.edge + 2 * brute->ee[k].a, *b = g.edge + 2 * brute->ee[k].b;
		vec3 p0[4] = { v3_load(x0 + 3 * a[0]), v3_load(x0 + 3 * a[1]),
		    v3_load(x0 + 3 * b[0]), v3_load(x0 + 3 * b[1]) };
		vec3 p1[4] = { v3_load(x1 + 3 * a[0]), v3_load(x1 + 3 * a[1]),
		    v3_load(x1 + 3 * b[0]), v3_load(x1 + 3 * b[1]) };

		if (!ccd_edge_edge(p0, p1, 0, NULL))
			continue;
		hits++;
		if (!has_ee(grid, brute->ee[k].a, brute->ee[k].b))
			fail_msg("%s: grid misses edges %d and %d", name, brute->ee[k].a,
			    brute->ee[k].b);
	}
	return hits;
}

/* One whole run of a scene, and what it showed. */
struct run {
	int audit_every;	/* audit every this many output frames */
	int cover_gap;		/* 0, or check grid against brute over motions of
				 * this many steps, every 4th motion */
	bool may_blow_up;
	long frames, contacts, worst, cover_hits, cover_motions;
	double ke_max, ke_end, t_end;
	bool blew_up;
};

static long
audit_state(const struct stepper *st, long *inside)
{
	struct check_result r;

	assert_int_equal(check_state(st->sc, &st->cl, stepper_x(st), &r), 0);
	*inside = r.inside;
	return r.pairs;
}

/* Runs sc to its end (or a blow-up, if allowed), auditing every
 * r->audit_every-th output frame for intersecting pairs and nodes inside
 * obstacles (r->worst: the worst frame's sum). */
static void
run_checked(struct scene *sc, struct run *r)
{
	struct stepper st;
	struct blowup bl;
	struct broad grid, grid_seed, brute;
	double frame = 1 / sc->output_rate, next = 0, *x0 = NULL;
	long k = 0, motion = 0;
	size_t nx;
	struct energy e;

	init_stepper(&st, sc);
	nx = 3 * (size_t)collide_geom(&st.col)->nv;
	r->frames = r->contacts = r->worst = r->cover_hits = r->cover_motions = 0;
	r->ke_max = 0;
	r->blew_up = false;
	if (r->cover_gap > 0) {
		x0 = malloc(nx * sizeof *x0);
		assert_non_null(x0);
		broad_init(&grid, BROAD_GRID);
		broad_init(&grid_seed, BROAD_GRID);
		broad_init(&brute, BROAD_BRUTE);
		memcpy(x0, collide_geom(&st.col)->x0, nx * sizeof *x0);	/* obstacle vertices */
	}
	for (;;) {
		if (st.t >= next - 1e-12 || stepper_done(&st)) {
			long inside, bad = audit_state(&st, &inside);

			if (bad + inside > r->worst) {
				print_message("  %s: t = %.3f s, %ld intersecting pairs, %ld nodes in "
				    "obstacles\n", sc->name, st.t, bad, inside);
				r->worst = bad + inside;
			}
			r->frames++;
			k++;
			next = (double)(k * r->audit_every) * frame;
		}
		if (r->cover_gap > 0 && st.step % r->cover_gap == 0) {
			const struct geom *g = collide_geom(&st.col);
			double *x1 = malloc(nx * sizeof *x1);

			assert_non_null(x1);
			memcpy(x1, x0, nx * sizeof *x1);
			memcpy(x1, stepper_x(&st), 3 * (size_t)st.cl.n * sizeof *x1);
			if (st.step > 0 && motion++ % 4 == 0) {
				r->cover_hits += grid_covers_brute(sc->name, *g, x0, x1, st.col.cell,
				    &grid, &grid_seed, &brute);
				r->cover_motions++;
			}
			free(x0);
			x0 = x1;
		}
		stepper_energy(&st, &e);
		r->ke_max = fmax(r->ke_max, e.kinetic);
		r->ke_end = e.kinetic;
		if (stepper_done(&st))
			break;
		if (stepper_step(&st, &bl) != 0) {
			if (!r->may_blow_up)
				fail_msg("%s blew up at step %ld: %s", sc->name, bl.step, bl.why);
			print_message("  %s blew up at step %ld, t = %.4f s: %s\n", sc->name,
			    bl.step, bl.t, bl.why);
			r->blew_up = true;
			break;
		}
		for (int t = 0; t < CONTACT_NTYPES; t++)
			r->contacts += st.col.st.contacts[t];
	}
	r->t_end = st.t;
	if (r->cover_gap > 0) {
		broad_free(&grid);
		broad_free(&grid_seed);
		broad_free(&brute);
	}
	free(x0);
	stepper_free(&st);
}

/* A shipped scene at its own settings, the whole run: no intersecting pair
 * and no node inside an obstacle at every 10th frame, grid's pairs hold
 * every contact brute's give, and it ends at rest (its kinetic energy under
 * 0.5 % of its peak). */
static void
shipped_clean(const char *name, int integrator)
{
	struct scene sc;
	struct run r = { .audit_every = 10, .cover_gap = 200 };
	char path[512];

	snprintf(path, sizeof path, SCENE_DIR "%s", name);
	load_shipped(&sc, path);
	if (integrator >= 0) {
		sc.integrator = (enum integrator_kind)integrator;
		r.cover_gap = 20;	/* about as many motions at its longer step */
	}
	run_checked(&sc, &r);
	print_message("%s (%s): %.2f s, %ld audited frames, worst %ld; %ld contacts; grid held all "
	    "%ld contacting pairs of brute over %ld motions; kinetic energy %.3g J at the end, "
	    "peak %.3g J\n", name, integrator_name(sc.integrator), r.t_end, r.frames, r.worst, r.contacts, r.cover_hits,
	    r.cover_motions, r.ke_end, r.ke_max);
	assert_double_equal(r.t_end, sc.duration, 1e-9);
	assert_true(r.frames > 5);
	assert_true(r.contacts > 0);
	assert_int_equal(r.worst, 0);
	assert_true(r.cover_hits > 100);
	assert_true(r.ke_end < 5e-3 * r.ke_max);
	scene_free(&sc);
}

static void test_strip_clean(void **state) { (void)state; shipped_clean("strip.scene", -1); }
static void test_tablecloth_clean(void **state) { (void)state; shipped_clean("tablecloth.scene", -1); }
static void
test_tablecloth_implicit_clean(void **state)
{
	(void)state;
	shipped_clean("tablecloth.scene", INTEG_IMPLICIT_EULER);
}

static double
max_strain(const struct stepper *st)
{
	double worst = 0;
	size_t s;

	for (s = 0; s < st->cl.nsprings; s++) {
		const struct spring *sp = &st->cl.springs[s];
		double l = v3_len(v3_sub(v3_load(stepper_x(st) + 3 * sp->b),
		    v3_load(stepper_x(st) + 3 * sp->a)));

		worst = fmax(worst, l / sp->rest - 1);
	}
	return worst;
}

/* Implicit Euler at its own step, on the box: the nodes resting on its top
 * are constrained in the solve, so the springs over its edge are not left
 * stretched: 6.9 % at most, and 32 % without the constraint. */
static void
test_implicit_resting_on_box(void **state)
{
	struct scene sc;
	struct stepper st;
	struct blowup bl;
	double worst = 0;

	(void)state;
	load_shipped(&sc, SCENE_DIR "tablecloth.scene");
	sc.integrator = INTEG_IMPLICIT_EULER;
	sc.duration = 0.3;
	init_stepper(&st, &sc);
	while (!stepper_done(&st)) {
		assert_int_equal(stepper_step(&st, &bl), 0);
		if (st.t > 0.1)		/* on the box from about 0.08 s */
			worst = fmax(worst, max_strain(&st));
	}
	print_message("implicit Euler at %.3g s on the box: the largest strain after 0.1 s is "
	    "%.2f %%\n", st.dt_set, 100 * worst);
	assert_true(st.col.total.contacts[CONTACT_OBSTACLE] > 1000);
	assert_true(worst < 0.10);	/* RK4: about 2 % */
	stepper_free(&st);
	scene_free(&sc);
}

/* The chapter's own settings: printed, not asserted. */
static void
seed_figures(const char *name)
{
	struct scene sc;
	struct run r = { .audit_every = 10, .may_blow_up = true };
	char path[512];

	snprintf(path, sizeof path, SCENE_DIR "%s", name);
	load_shipped_with(&sc, path, "broad = grid\nnarrow = ccd\nposition = slide",
	    "broad = seed\nnarrow = seed\nposition = keep");
	assert_int_equal(sc.col.narrow, NARROW_SEED);
	run_checked(&sc, &r);
	print_message("%s with seed/seed/keep: %s at t = %.3f s; %ld audited frames, %ld "
	    "contacts, worst frame %ld intersecting pairs + nodes in obstacles (printed, not "
	    "asserted)\n", name, r.blew_up ? "blew up" : "ran to the end", r.t_end, r.frames,
	    r.contacts, r.worst);
	scene_free(&sc);
}

static void test_seed_figures(void **state)
{
	(void)state;
	seed_figures("tablecloth.scene");
	seed_figures("strip.scene");
}

/* 10^5 steps; the node's winding number about the icosahedron stays 1. */
static void
test_icosahedron(void **state)
{
	struct scene sc;
	struct stepper st;
	struct blowup bl;
	const struct mesh *m;
	long contacts = 0;

	(void)state;
	load_shipped(&sc, SCENE_DIR "icosahedron.scene");
	assert_int_equal(sc.nobstacles, 1);
	m = &sc.obstacles[0].mesh;
	init_stepper(&st, &sc);
	while (!stepper_done(&st)) {
		double w;

		if (stepper_step(&st, &bl) != 0)
			fail_msg("blew up at step %ld: %s", bl.step, bl.why);
		contacts += (long)st.col.nev;
		w = mesh_winding_number(m, v3_load(stepper_x(&st)));
		if (fabs(w - 1) > 1e-6)
			fail_msg("step %ld: the node is out (winding number %g)", st.step, w);
	}
	print_message("icosahedron: %ld steps, %ld contacts\n", st.step, contacts);
	assert_int_equal(st.step, 100000);
	assert_true(contacts > 10);
	stepper_free(&st);
	scene_free(&sc);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_icosahedron),
		cmocka_unit_test(test_tablecloth_clean),
		cmocka_unit_test(test_strip_clean),
		cmocka_unit_test(test_tablecloth_implicit_clean),
		cmocka_unit_test(test_implicit_resting_on_box),
		cmocka_unit_test(test_seed_figures),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
