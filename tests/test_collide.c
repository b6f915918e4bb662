/* test_collide.c: the chapter's scenes end without intersections, the
 * node stays in the icosahedron, and the grid broad phase misses nothing
 * that the brute one gives the narrow phase. */
#include "testutil.h"

#include "check.h"
#include "broad.h"
#include "ccd.h"
#include "collide.h"
#include "mesh.h"
#include "narrow.h"

/* Work in progress: the whole runs take minutes until the broad phase is
 * faster, so the scene tests stop here for now (issue 3's note says so). */
#define RUN_LIMIT 0.3

static long
audit_state(const struct stepper *st, long *inside)
{
	struct check_result r;

	assert_int_equal(check_state(st->sc, &st->cl, stepper_x(st), &r), 0);
	*inside = r.inside;
	return r.pairs;
}

/* Runs a scene to its end, auditing every `every`-th output frame; returns
 * the worst count of intersecting pairs plus nodes inside obstacles. */
static long
run_audited(struct scene *sc, int every, long *frames, long *contacts, bool may_blow_up)
{
	struct stepper st;
	struct blowup bl;
	double frame = 1 / sc->output_rate, next = 0;
	long worst = 0, k = 0;

	init_stepper(&st, sc);
	*frames = 0;
	*contacts = 0;
	for (;;) {
		if (st.t >= next - 1e-12 || stepper_done(&st)) {
			long inside, bad = audit_state(&st, &inside);

			if (bad + inside > worst) {
				print_message("  %s: t = %.3f s, %ld intersecting pairs, %ld nodes in "
				    "obstacles\n", sc->name, st.t, bad, inside);
				worst = bad + inside;
			}
			(*frames)++;
			k++;
			next = (double)(k * every) * frame;
		}
		if (stepper_done(&st))
			break;
		if (stepper_step(&st, &bl) != 0) {
			if (!may_blow_up)
				fail_msg("%s blew up at step %ld: %s", sc->name, bl.step, bl.why);
			print_message("  %s blew up at step %ld, t = %.4f s: %s\n", sc->name,
			    bl.step, bl.t, bl.why);
			break;
		}
		for (int t = 0; t < CONTACT_NTYPES; t++)
			*contacts += st.col.st.contacts[t];
	}
	stepper_free(&st);
	return worst;
}

static void
shipped_clean(const char *name)
{
	struct scene sc;
	long frames, contacts, bad;
	char path[512];

	snprintf(path, sizeof path, SCENE_DIR "%s", name);
	load_shipped(&sc, path);
	sc.duration = RUN_LIMIT;
	bad = run_audited(&sc, 10, &frames, &contacts, false);
	print_message("%s: %ld audited frames, %ld contacts, worst %ld\n", name, frames, contacts,
	    bad);
	assert_true(frames > 1);
	assert_true(contacts > 0);
	assert_int_equal(bad, 0);
	scene_free(&sc);
}

static void test_strip_clean(void **state) { (void)state; shipped_clean("strip.scene"); }
static void test_tablecloth_clean(void **state) { (void)state; shipped_clean("tablecloth.scene"); }

/* The chapter's own settings: printed, not asserted. */
static void
seed_figures(const char *name)
{
	struct scene sc;
	long frames, contacts, bad;
	char path[512];

	snprintf(path, sizeof path, SCENE_DIR "%s", name);
	load_shipped_with(&sc, path, "broad = grid\nnarrow = ccd\nposition = slide",
	    "broad = seed\nnarrow = seed\nposition = keep");
	assert_int_equal(sc.col.narrow, NARROW_SEED);
	sc.duration = RUN_LIMIT;
	bad = run_audited(&sc, 10, &frames, &contacts, true);
	print_message("%s with seed/seed/keep: %ld audited frames, %ld contacts, worst frame "
	    "%ld intersecting pairs + nodes in obstacles (printed, not asserted)\n", name, frames,
	    contacts, bad);
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

/* Every pair that brute gives and the narrow phase (seed or ccd) finds in
 * contact is among grid's pairs, over motions of `gap` steps of the run. */
static void
grid_covers_brute(const char *name, int gap)
{
	struct scene sc;
	struct stepper st;
	struct blowup bl;
	struct broad grid, grid_seed, brute;
	struct drape_err err;
	struct geom g;
	double *x0, *x1;
	long checked = 0, hits = 0;
	char path[512];
	int round;

	snprintf(path, sizeof path, SCENE_DIR "%s", name);
	load_shipped(&sc, path);
	sc.duration = RUN_LIMIT;
	init_stepper(&st, &sc);
	g = *collide_geom(&st.col);
	x0 = malloc(3 * (size_t)g.nv * sizeof *x0);
	x1 = malloc(3 * (size_t)g.nv * sizeof *x1);
	assert_non_null(x0);
	assert_non_null(x1);
	memcpy(x0, g.x0, 3 * (size_t)g.nv * sizeof *x0);	/* obstacle vertices */
	memcpy(x1, g.x0, 3 * (size_t)g.nv * sizeof *x1);
	g.x0 = x0;
	g.x1 = x1;
	broad_init(&grid, BROAD_GRID);
	broad_init(&grid_seed, BROAD_GRID);
	broad_init(&brute, BROAD_BRUTE);
	for (round = 0; !stepper_done(&st); round++) {
		size_t k;
		int s;

		memcpy(x0, stepper_x(&st), 3 * (size_t)st.cl.n * sizeof *x0);
		for (s = 0; s < gap && !stepper_done(&st); s++)
			if (stepper_step(&st, &bl) != 0)
				fail_msg("blew up: %s", bl.why);
		memcpy(x1, stepper_x(&st), 3 * (size_t)st.cl.n * sizeof *x1);
		if (round % 4 != 0)
			continue;
		if (broad_find(&grid, &g, st.col.cell, NARROW_CCD, &err) != 0 ||
		    broad_find(&grid_seed, &g, st.col.cell, NARROW_SEED, &err) != 0 ||
		    broad_find(&brute, &g, 0, NARROW_CCD, &err) != 0)
			fail_msg("%s", err.msg);
		for (k = 0; k < brute.nvt; k++) {
			int v = brute.vt[k].v, t = brute.vt[k].t, j, e;
			const int *tn = g.tri + 3 * t;
			vec3 p0[4], p1[4];
			struct seed_hit h;
			int hit = 0;

			p0[0] = v3_load(x0 + 3 * v);
			p1[0] = v3_load(x1 + 3 * v);
			for (j = 0; j < 3; j++) {
				p0[j + 1] = v3_load(x0 + 3 * tn[j]);
				p1[j + 1] = v3_load(x1 + 3 * tn[j]);
			}
			if (ccd_vertex_face(p0, p1, 0, NULL)) {
				hits++;
				if (!has_vt(&grid, v, t))
					fail_msg("%s: grid misses node %d against triangle %d", name,
					    v, t);
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
			if (!has_vt(&grid_seed, v, t))
				fail_msg("%s: grid (seed) misses node %d against triangle %d", name,
				    v, t);
		}
		for (k = 0; k < brute.nee; k++) {
			const int *a = g.edge + 2 * brute.ee[k].a, *b = g.edge + 2 * brute.ee[k].b;
			vec3 p0[4] = { v3_load(x0 + 3 * a[0]), v3_load(x0 + 3 * a[1]),
			    v3_load(x0 + 3 * b[0]), v3_load(x0 + 3 * b[1]) };
			vec3 p1[4] = { v3_load(x1 + 3 * a[0]), v3_load(x1 + 3 * a[1]),
			    v3_load(x1 + 3 * b[0]), v3_load(x1 + 3 * b[1]) };

			if (!ccd_edge_edge(p0, p1, 0, NULL))
				continue;
			hits++;
			if (!has_ee(&grid, brute.ee[k].a, brute.ee[k].b))
				fail_msg("%s: grid misses edges %d and %d", name, brute.ee[k].a,
				    brute.ee[k].b);
		}
		checked++;
	}
	print_message("%s: grid held all %ld contacting pairs of brute over %ld motions of %d "
	    "steps\n", name, hits, checked, gap);
	assert_true(hits > 0);
	broad_free(&grid);
	broad_free(&grid_seed);
	broad_free(&brute);
	free(x0);
	free(x1);
	stepper_free(&st);
	scene_free(&sc);
}

static void
test_grid_covers_brute(void **state)
{
	(void)state;
	grid_covers_brute("tablecloth.scene", 200);
	grid_covers_brute("strip.scene", 200);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_icosahedron),
		cmocka_unit_test(test_tablecloth_clean),
		cmocka_unit_test(test_strip_clean),
		cmocka_unit_test(test_grid_covers_brute),
		cmocka_unit_test(test_seed_figures),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
