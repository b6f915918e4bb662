/* test_collide.c: the chapter's scenes run to rest without intersections,
 * the node stays in the icosahedron, and the grid broad phase misses
 * nothing that the brute one gives the narrow phase. */
#include "testutil.h"

#include "check.h"
#include "broad.h"
#include "broad_impl.h"	/* white-box: the held pairs and flat patches */
#include "ccd.h"
#include "collide.h"
#include "contacts.h"
#include "mesh.h"
#include "narrow.h"

static struct broad *
new_broad(enum broad_mode mode)
{
	struct broad *b = broad_new(mode);

	assert_non_null(b);
	return b;
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

/* The pairs brute gives that the narrow phase finds in contact over the
 * motion x0 -> x1 of geometry g (ccd for the vertex paths and edge pairs,
 * the seed test for the segments from a node's neighbours): each must be
 * among grid's pairs for that narrow phase. Returns how many there were. */
static long
grid_covers_brute(const char *name, struct geom g, const double *x0, const double *x1,
    double cell, struct broad *grid, struct broad *grid_seed, struct broad *brute)
{
	struct broad_want ccd = collide_broad_want(NARROW_CCD, true);
	struct broad_want seed = collide_broad_want(NARROW_SEED, true);
	struct drape_err err;
	long hits = 0;
	size_t k;

	g.x0 = x0;
	g.x1 = x1;
	g.vbox = NULL;
	if (broad_find(grid, &g, cell, &ccd, &err) != 0 ||
	    broad_find(grid_seed, &g, cell, &seed, &err) != 0 ||
	    broad_find(brute, &g, 0, &ccd, &err) != 0)
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

	assert_int_equal(check_state(stepper_scene(st), cloth_of(st), stepper_x(st), &r), 0);
	*inside = r.inside;
	return r.pairs;
}

/* Runs sc to its end (or a blow-up, if allowed), auditing every
 * r->audit_every-th output frame for intersecting pairs and nodes inside
 * obstacles (r->worst: the worst frame's sum). */
static void
run_checked(struct scene *sc, struct run *r)
{
	struct stepper *st;
	struct step_failure bl;
	struct broad *grid = NULL, *grid_seed = NULL, *brute = NULL;
	double frame = 1 / sc->output_rate, next = 0, *x0 = NULL;
	long k = 0, motion = 0;
	size_t nx;
	struct energy e;

	st = new_stepper(sc);
	nx = 3 * (size_t)stepper_geom(st)->nv;
	r->frames = r->contacts = r->worst = r->cover_hits = r->cover_motions = 0;
	r->ke_max = 0;
	r->blew_up = false;
	if (r->cover_gap > 0) {
		x0 = malloc(nx * sizeof *x0);
		assert_non_null(x0);
		grid = new_broad(BROAD_GRID);
		grid_seed = new_broad(BROAD_GRID);
		brute = new_broad(BROAD_BRUTE);
		memcpy(x0, stepper_geom(st)->x0, nx * sizeof *x0);	/* obstacle vertices */
	}
	for (;;) {
		if (report_of(st).t >= next - 1e-12 || stepper_done(st)) {
			long inside, bad = audit_state(st, &inside);

			if (bad + inside > r->worst) {
				print_message("  %s: t = %.3f s, %ld intersecting pairs, %ld nodes in "
				    "obstacles\n", sc->name, report_of(st).t, bad, inside);
				r->worst = bad + inside;
			}
			r->frames++;
			k++;
			next = (double)(k * r->audit_every) * frame;
		}
		if (r->cover_gap > 0 && report_of(st).step % r->cover_gap == 0) {
			const struct geom *g = stepper_geom(st);
			double *x1 = malloc(nx * sizeof *x1);

			assert_non_null(x1);
			memcpy(x1, x0, nx * sizeof *x1);
			memcpy(x1, stepper_x(st), 3 * (size_t)cloth_of(st)->n * sizeof *x1);
			if (report_of(st).step > 0 && motion++ % 4 == 0) {
				r->cover_hits += grid_covers_brute(sc->name, *g, x0, x1, report_of(st).cell,
				    grid, grid_seed, brute);
				r->cover_motions++;
			}
			free(x0);
			x0 = x1;
		}
		stepper_energy(st, &e);
		r->ke_max = fmax(r->ke_max, e.kinetic);
		r->ke_end = e.kinetic;
		if (stepper_done(st))
			break;
		if (stepper_step(st, &bl) != STEP_OK) {
			if (!r->may_blow_up)
				fail_msg("%s blew up at step %ld: %s", sc->name, bl.step, bl.why);
			print_message("  %s blew up at step %ld, t = %.4f s: %s\n", sc->name,
			    bl.step, bl.t, bl.why);
			r->blew_up = true;
			break;
		}
		for (int t = 0; t < CONTACT_NTYPES; t++)
			r->contacts += report_of(st).last->n[STAT_CONTACTS + t];
	}
	r->t_end = report_of(st).t;
	if (r->cover_gap > 0) {
		broad_free(grid);
		broad_free(grid_seed);
		broad_free(brute);
	}
	free(x0);
	stepper_free(st);
}

/* A shipped scene, the whole run: no intersecting pair and no node inside
 * an obstacle at every 10th frame, grid's pairs hold every contact brute's
 * give, and it ends at rest (its kinetic energy under 0.5 % of its peak,
 * 5 % for the fast path).
 * integrator: -1 the scene's own (fast, whose broad phases test_fast
 * compares), or another; rk4 is the chapter's method as the scenes say
 * it is taken, with the grid. */
static void
shipped_clean(const char *name, int integrator)
{
	struct scene sc;
	struct run r = { .audit_every = 10, .cover_gap = 200 };
	char path[512];

	snprintf(path, sizeof path, SCENE_DIR "%s", name);
	load_shipped(&sc, path);
	if (integrator == INTEG_RK4) {
		sc.integrator = INTEG_RK4;
		sc.col.broad = BROAD_GRID;
	} else if (integrator >= 0) {
		sc.integrator = (enum integrator_kind)integrator;
		/* about as many motions at its longer step; bdf2's (10 to
		 * 20 ms) sampled four times as often: at 20 the tablecloth
		 * gave two motions, with no contact in either on one path */
		r.cover_gap = integrator == INTEG_BDF2 ? 5 : 20;
	}
	if (sc.integrator == INTEG_FAST)
		r.cover_gap = 0;
	run_checked(&sc, &r);
	print_message("%s (%s): %.2f s, %ld audited frames, worst %ld; %ld contacts; grid held all "
	    "%ld contacting pairs of brute over %ld motions; kinetic energy %.3g J at the end, "
	    "peak %.3g J\n", name, integrator_name(sc.integrator), r.t_end, r.frames, r.worst, r.contacts, r.cover_hits,
	    r.cover_motions, r.ke_end, r.ke_max);
	assert_double_equal(r.t_end, sc.duration, 1e-9);
	assert_true(r.frames > 5);
	assert_true(r.contacts > 0);
	assert_int_equal(r.worst, 0);
	if (r.cover_gap > 0)
		assert_true(r.cover_hits > 100);
	/* the fast path's piles keep a jitter from their contacts' projections
	 * (the strip: 3.7e-6 to 4.5e-6 J over its last 0.6 s, 4.2 to 5.1 % of
	 * its peak, 2.8e-6 to 3.8e-6 before the shear sweep's colour order;
	 * RK4 ends at 3e-8 J); a strip still moving as it is fed is near it */
	assert_true(r.ke_end < (sc.integrator == INTEG_FAST ? 0.1 : 5e-3) * r.ke_max);
	scene_free(&sc);
}

/* bdf2's pairs are those that close along their normals over the step
 * (contacts.h): the tablecloth crumpling on its floor stays clean. */
static void
test_tablecloth_bdf2_clean(void **state)
{
	(void)state;
	shipped_clean("tablecloth.scene", INTEG_BDF2);
}

/* The pairs' keep rule: a vertex 5 mm over a triangle, the sides parting
 * by up to 6 mm over the step, thickness 1 mm. Any way (fast's), every
 * pair that motion might close is kept; closing (bdf2's), only those
 * whose separation closes along its normal, or that are near already. */
static void
test_contacts_closing(void **state)
{
	vec3 d = v3(0, 5e-3, 0), up = v3(0, 6e-3, 0), down = v3(0, -6e-3, 0);
	vec3 across = v3(6e-3, 0, 0);

	(void)state;
	assert_true(contacts_may_reach(d, up, 6e-3, 1e-3, false));
	assert_true(contacts_may_reach(d, across, 6e-3, 1e-3, false));
	assert_false(contacts_may_reach(d, up, 6e-3, 1e-3, true));	/* parting */
	assert_false(contacts_may_reach(d, across, 6e-3, 1e-3, true));	/* sliding past */
	assert_true(contacts_may_reach(d, down, 6e-3, 1e-3, true));	/* closing */
	assert_true(contacts_may_reach(v3(0, 1e-3, 0), up, 6e-3, 1e-3, true));	/* near */
	/* the slack: parting, 1.25 + 0.5 * 6 = 4.25 mm */
	assert_true(contacts_may_reach(v3(0, 4.2e-3, 0), up, 6e-3, 1e-3, true));
	assert_false(contacts_may_reach(v3(0, 4.3e-3, 0), up, 6e-3, 1e-3, true));
	/* nothing moving: within CONTACTS_REACH thicknesses, either rule */
	assert_true(contacts_may_reach(v3(0, 1.2e-3, 0), v3(0, 0, 0), 0, 1e-3, true));
	assert_false(contacts_may_reach(v3(0, 1.3e-3, 0), v3(0, 0, 0), 0, 1e-3, false));
}

static void test_strip_clean(void **state) { (void)state; shipped_clean("strip.scene", INTEG_RK4); }
static void test_tablecloth_clean(void **state) { (void)state; shipped_clean("tablecloth.scene", INTEG_RK4); }
static void test_strip_fast_clean(void **state) { (void)state; shipped_clean("strip.scene", -1); }
static void
test_tablecloth_fast_clean(void **state)
{
	(void)state;
	shipped_clean("tablecloth.scene", -1);
}
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

	for (s = 0; s < cloth_of(st)->nsprings; s++) {
		const struct spring *sp = &cloth_of(st)->springs[s];
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
	struct stepper *st;
	struct step_failure bl;
	double worst = 0;

	(void)state;
	load_shipped(&sc, SCENE_DIR "tablecloth.scene");
	sc.integrator = INTEG_IMPLICIT_EULER;
	sc.duration = 0.3;
	st = new_stepper(&sc);
	while (!stepper_done(st)) {
		assert_int_equal(stepper_step(st, &bl), STEP_OK);
		if (report_of(st).t > 0.1)		/* on the box from about 0.08 s */
			worst = fmax(worst, max_strain(st));
	}
	print_message("implicit Euler at %.3g s on the box: the largest strain after 0.1 s is "
	    "%.2f %%\n", report_of(st).dt_set, 100 * worst);
	assert_true(report_of(st).total->n[STAT_CONTACTS + CONTACT_OBSTACLE] > 1000);
	assert_true(worst < 0.10);	/* RK4: about 2 % */
	stepper_free(st);
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
	load_shipped_with(&sc, path, "broad = bvh\nnarrow = ccd\nposition = slide",
	    "broad = seed\nnarrow = seed\nposition = keep");
	sc.integrator = INTEG_RK4;
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
	struct stepper *st;
	struct step_failure bl;
	const struct mesh *m;
	long contacts = 0;

	(void)state;
	load_shipped(&sc, SCENE_DIR "icosahedron.scene");
	assert_int_equal(sc.nobstacles, 1);
	m = &sc.obstacles[0].mesh;
	st = new_stepper(&sc);
	while (!stepper_done(st)) {
		double w;

		if (stepper_step(st, &bl) != STEP_OK)
			fail_msg("blew up at step %ld: %s", bl.step, bl.why);
		contacts += (long)report_of(st).nev;
		w = mesh_winding_number(m, v3_load(stepper_x(st)));
		if (fabs(w - 1) > 1e-6)
			fail_msg("step %ld: the node is out (winding number %g)", report_of(st).step, w);
	}
	print_message("icosahedron: %ld steps, %ld contacts\n", report_of(st).step, contacts);
	assert_int_equal(report_of(st).step, 100000);
	assert_true(contacts > 10);
	stepper_free(st);
	scene_free(&sc);
}

/* The fail-safe on its own: a strip folded as an accordion into twelve
 * layers a tenth of a spacing apart on the floor (consistent at step k),
 * pressed down by 0.7 spacings in one step. The layers pass the impulses
 * down to the floor and back, so the ccd passes reach the pass limit and
 * from pass COLLIDE_FAILSAFE_PASS on contacts stick: what stuck is back at
 * its step k position, no node gained speed (a stuck group moves at its
 * mean velocity), nothing was left unresolved, no node is below the floor,
 * and no vertex-face or edge-edge pair crosses over the corrected motion. */
static void
test_failsafe_jam(void **state)
{
	static const char text[] =
	    "[simulation]\nduration = 1 s\ngravity = 0\n"
	    "[cloth]\nnodes = 25 3\nspacing = 10 mm\norientation = +x +z\nweight = 150 g/m2\n"
	    "thickness = 0.5 mm\nmodulus_warp = 0.45 MPa\nmodulus_weft = 0.3 MPa\n"
	    "shear_modulus = 9 kPa\nbending_warp = 3 uN*m\nbending_weft = 2 uN*m\n"
	    "[plane]\npoint = 0 0 0\n"
	    "[collision]\nself = on\nbroad = grid\nnarrow = ccd\nposition = slide\n";
	struct scene sc;
	struct network net;
	struct collide c;
	struct drape_err err;
	const double dt = 1e-3, gap = 0.1, press = 0.7;
	double *y0, *y1, vmax = 0;
	size_t n3, i, e, f;
	int v, k, frozen = 0;

	(void)state;
	parse_text(&sc, text);
	if (network_build(&net, &sc, &err) != 0 ||
	    collide_init(&c, &sc, &net.cl, net.pr.held, dt, 1, &err) != 0)
		fail_msg("%s", err.msg);
	n3 = 3 * (size_t)net.cl.n;
	y0 = calloc(2 * n3, sizeof *y0);
	y1 = calloc(2 * n3, sizeof *y1);
	assert_true(y0 != NULL && y1 != NULL);
	for (v = 0; v < net.cl.n; v++) {
		int ci = v % net.cl.nu, cj = v / net.cl.nu, layer = ci / 2, along = ci % 2;
		double h = net.cl.h, x = layer % 2 == 0 ? along * h : (2 - along) * h;

		y0[3 * v] = y1[3 * v] = x;
		y0[3 * v + 1] = (layer + 1) * gap * h;
		y1[3 * v + 1] = y0[3 * v + 1] - press * h;
		y0[3 * v + 2] = y1[3 * v + 2] = cj * h;
	}
	for (i = 0; i < n3; i++)
		y1[n3 + i] = (y1[i] - y0[i]) / dt;
	for (v = 0; v < net.cl.n; v++)
		vmax = fmax(vmax, v3_len(v3_load(y1 + n3 + 3 * v)));
	assert_int_equal(collide_step(&c, 0, dt, y0, y1, &err), 0);
	print_message("jam: %ld passes, %ld nodes put back to step k, %ld corrections\n",
	    c.st.n[STAT_PASSES], c.st.n[STAT_FROZEN], c.st.n[STAT_CORRECTIONS]);
	assert_true(c.st.n[STAT_PASSES] > COLLIDE_FAILSAFE_PASS);
	assert_true(c.st.n[STAT_FROZEN] > 0);
	assert_int_equal(c.st.n[STAT_UNRESOLVED], 0);
	for (v = 0; v < net.cl.n; v++) {
		if (c.frozen[v]) {
			frozen++;
			for (k = 0; k < 3; k++)
				assert_true(y1[3 * v + k] == y0[3 * v + k]);
		}
		assert_true(v3_len(v3_load(y1 + n3 + 3 * v)) <= vmax * (1 + 1e-12));
		assert_true(y1[3 * v + 1] >= 0);
	}
	assert_int_equal(frozen, c.st.n[STAT_FROZEN]);
	for (v = 0; v < net.cl.n; v++)
		for (i = 0; i < net.cl.ntri; i++) {
			const int *tn = net.cl.tri + 3 * i;
			vec3 p0[4], p1[4];

			if (tn[0] == v || tn[1] == v || tn[2] == v)
				continue;
			p0[0] = v3_load(y0 + 3 * v);
			p1[0] = v3_load(y1 + 3 * v);
			for (k = 0; k < 3; k++) {
				p0[k + 1] = v3_load(y0 + 3 * tn[k]);
				p1[k + 1] = v3_load(y1 + 3 * tn[k]);
			}
			if (ccd_vertex_face(p0, p1, 0, NULL))
				fail_msg("node %d still crosses triangle %zu", v, i);
		}
	for (e = 0; e < net.cl.nedges; e++)
		for (f = e + 1; f < net.cl.nedges; f++) {
			const int *a = net.cl.edge + 2 * e, *b = net.cl.edge + 2 * f;
			vec3 p0[4], p1[4];

			if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1])
				continue;
			for (k = 0; k < 2; k++) {
				p0[k] = v3_load(y0 + 3 * a[k]);
				p1[k] = v3_load(y1 + 3 * a[k]);
				p0[k + 2] = v3_load(y0 + 3 * b[k]);
				p1[k + 2] = v3_load(y1 + 3 * b[k]);
			}
			if (ccd_edge_edge(p0, p1, 0, NULL))
				fail_msg("edges %zu and %zu still cross", e, f);
		}
	free(y0);
	free(y1);
	collide_free(&c);
	network_free(&net);
	scene_free(&sc);
}

/* One bvh search of g with boxes hull(xa, xb) widened by pad, on b; and
 * the same on a fresh bvh, which has no pairs held and traverses: the
 * lists must be the same, in the same order. Returns 1 if b took its
 * pairs from held ones. */
static int
held_search(struct broad *b, struct geom g, const double *xa, const double *xb, double pad,
    double cell, double near)
{
	struct broad_want want = collide_broad_want(NARROW_CCD, true);
	struct broad *fresh;
	struct drape_err err;
	double *box = malloc(6 * (size_t)g.nv * sizeof *box);
	long uses = b->bvh.held_uses;
	int v, k, served;

	assert_non_null(box);
	for (v = 0; v < g.nv; v++)
		for (k = 0; k < 3; k++) {
			box[6 * v + k] = fmin(xa[3 * v + k], xb[3 * v + k]) - pad;
			box[6 * v + 3 + k] = fmax(xa[3 * v + k], xb[3 * v + k]) + pad;
		}
	g.x0 = xa;
	g.x1 = xb;
	g.vbox = box;
	want.near = near;
	want.near_motion = 1.5;
	fresh = new_broad(BROAD_BVH);
	if (broad_find(b, &g, cell, &want, &err) != 0 || broad_find(fresh, &g, cell, &want, &err) != 0)
		fail_msg("%s", err.msg);
	served = b->bvh.held_uses > uses;
	assert_int_equal(b->nvt, fresh->nvt);
	assert_int_equal(b->nee, fresh->nee);
	assert_true(b->nvt == 0 || memcmp(b->vt, fresh->vt, b->nvt * sizeof *b->vt) == 0);
	assert_true(b->nee == 0 || memcmp(b->ee, fresh->ee, b->nee * sizeof *b->ee) == 0);
	broad_free(fresh);
	free(box);
	return served;
}

/* bvh holds a traversal's pairs and serves later searches from them
 * (broad_held.c): what they give must be exactly a traversal's.
 * The motions of a real run (the tablecloth falling on an icosahedron's
 * mesh and on itself), searched as the fast path does (a search with a
 * near test, whose pairs are not held, then the check's over the motion
 * made, with some vertices thrown out of their boxes), and as short steps
 * do (small motions: the skin). */
static void
test_bvh_held_pairs(void **state)
{
	struct scene sc;
	struct stepper *st;
	struct step_failure f;
	struct broad *b;
	double *xa, *xb, *xc;
	size_t nx;
	long served = 0, searches = 0, skinned = 0, step;
	unsigned rng = 12345;
	int v, k, j;

	(void)state;
	load_shipped_with(&sc, SCENE_DIR "tablecloth.scene", "[box]\nmin = 0 0 -0.08 m\n"
	    "max = 0.14 0.12 0.06 m", "[icosahedron]\ncentre = 0.03 0.05 -0.02 m\nradius = 0.07 m");
	sc.duration = 1;
	st = new_stepper(&sc);
	nx = 3 * (size_t)stepper_geom(st)->nv;
	xa = malloc(nx * sizeof *xa);
	xb = malloc(nx * sizeof *xb);
	xc = malloc(nx * sizeof *xc);
	assert_true(xa != NULL && xb != NULL && xc != NULL);
	assert_true(stepper_geom(st)->nv > cloth_of(st)->n);	/* the mesh's vertices */
	memcpy(xa, stepper_geom(st)->x0, nx * sizeof *xa);
	b = new_broad(BROAD_BVH);
	for (step = 0; !stepper_done(st); step++) {
		const struct geom *g = stepper_geom(st);
		double cell = report_of(st).cell;

		if (stepper_step(st, &f) != STEP_OK)
			fail_msg("step %ld: %s", f.step, f.why);
		memcpy(xb, xa, nx * sizeof *xb);
		memcpy(xb, stepper_x(st), 3 * (size_t)cloth_of(st)->n * sizeof *xb);
		if (step % 5 == 0) {
			/* the step's contacts, then its check with a few vertices
			 * (one in 40) moved up to 5 mm beyond */
			held_search(b, *g, xa, xb, 0.8e-3, cell, 0.7e-3);
			memcpy(xc, xb, nx * sizeof *xc);
			for (v = 0; v < cloth_of(st)->n; v++) {
				rng = rng * 1103515245u + 12345u;
				if ((rng >> 16) % 40 == 0)
					for (k = 0; k < 3; k++) {
						rng = rng * 1103515245u + 12345u;
						xc[3 * v + k] += 5e-3 * ((double)((rng >> 16) % 2001) / 1000 - 1);
					}
			}
			served += held_search(b, *g, xa, xc, 0, cell, 0);
			/* short steps: a search of the cloth moved 10 mm (the
			 * check's traversal served none, so this one takes the
			 * skin), then motions of a hundredth of a millimetre */
			for (j = 0; j < 1; j++) {
				memcpy(xc, xb, nx * sizeof *xc);
				for (v = 0; v < cloth_of(st)->n; v++)
					xc[3 * v + 1] += 1e-2 * (j + 1);
				held_search(b, *g, xc, xc, 0, cell, 0);
			}
			skinned += b->bvh.held_skin > 0;
			memcpy(xb, xc, nx * sizeof *xb);
			for (j = 0; j < 4; j++) {
				for (v = 0; v < cloth_of(st)->n; v++)
					xc[3 * v + 1] -= 1e-5;
				served += held_search(b, *g, xb, xc, 0, cell, 0);
				memcpy(xb, xc, nx * sizeof *xb);
			}
			searches += 5;
		}
		memcpy(xa, stepper_x(st), 3 * (size_t)cloth_of(st)->n * sizeof *xa);
	}
	print_message("held pairs: %ld of %ld searches served from them (%ld held with a skin), "
	    "each as a traversal's\n", served, searches, skinned);
	assert_true(served > searches / 2);
	assert_true(skinned > 0);
	broad_free(b);
	free(xa);
	free(xb);
	free(xc);
	stepper_free(st);
	scene_free(&sc);
}

/* ---- flat patches (broad_flat.c): what bvh leaves out must be harmless ---- */

#define PI 3.14159265358979323846

static double
point_segment(vec3 p, vec3 a, vec3 b)
{
	vec3 d = v3_sub(b, a);
	double dd = v3_dot(d, d), s = dd > 0 ? v3_dot(v3_sub(p, a), d) / dd : 0;

	s = fmin(fmax(s, 0), 1);
	return v3_len(v3_sub(p, v3_madd(a, d, s)));
}

/* The distance from p to triangle abc: to the plane where p projects
 * inside, else to the nearest edge. */
static double
point_triangle(vec3 p, vec3 a, vec3 b, vec3 c)
{
	vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
	double nn = v3_dot(n, n);

	if (nn > 0) {
		double h = v3_dot(v3_sub(p, a), n) / nn;
		vec3 q = v3_madd(p, n, -h);
		double u = v3_dot(v3_cross(v3_sub(b, q), v3_sub(c, q)), n);
		double v = v3_dot(v3_cross(v3_sub(c, q), v3_sub(a, q)), n);
		double w = v3_dot(v3_cross(v3_sub(a, q), v3_sub(b, q)), n);

		if (u >= 0 && v >= 0 && w >= 0)
			return fabs(h) * sqrt(nn);
	}
	return fmin(point_segment(p, a, b), fmin(point_segment(p, b, c), point_segment(p, c, a)));
}

/* Whether a pair the reference found and bvh left out is harmless: for
 * the check (near 0), ccd finds no contact over x0 -> x1; for a step's
 * contacts, the pair is out of the kept criterion's reach (contacts.h). */
static void
assert_harmless(const struct geom *g, const int *vert, int nvert_a, double near, double share)
{
	vec3 p0[4], p1[4];
	double dist, rel = 0;
	int k, l;

	for (k = 0; k < 4; k++) {
		p0[k] = v3_load(g->x0 + 3 * vert[k]);
		p1[k] = v3_load(g->x1 + 3 * vert[k]);
	}
	if (near == 0) {
		int hit = nvert_a == 1 ? ccd_vertex_face(p0, p1, 0, NULL) :
		    ccd_edge_edge(p0, p1, 0, NULL);

		if (hit)
			fail_msg("left out a pair in contact: %d %d %d %d", vert[0], vert[1], vert[2],
			    vert[3]);
		return;
	}
	if (nvert_a == 1) {
		dist = point_triangle(p0[0], p0[1], p0[2], p0[3]);
	} else {
		double s, u;

		v3_closest_on_segments(p0[0], p0[1], p0[2], p0[3], &s, &u);
		dist = v3_len(v3_sub(v3_madd(p0[0], v3_sub(p0[1], p0[0]), s),
		    v3_madd(p0[2], v3_sub(p0[3], p0[2]), u)));
	}
	for (k = 0; k < nvert_a; k++)
		for (l = nvert_a; l < 4; l++)
			rel = fmax(rel, v3_len(v3_sub(v3_sub(p1[k], p0[k]), v3_sub(p1[l], p0[l]))));
	if (!(dist - share * rel >= near))
		fail_msg("left out a pair within reach: %d %d %d %d, %g m apart, relative "
		    "motion %g m", vert[0], vert[1], vert[2], vert[3], dist, rel);
}

/* One search of g (x0 -> x1, boxes padded by pad) by bvh and by a
 * reference without the cloth's grid (so without flat patches); bvh's
 * pairs must be among the reference's and the rest harmless. Returns how
 * many pairs bvh left out. */
static long
flat_search(struct broad *b, struct geom g, const double *x0, const double *x1, double pad,
    double near)
{
	struct broad_want want = collide_broad_want(NARROW_CCD, true);
	struct broad *ref;
	struct geom plain = g;
	struct drape_err err;
	double *box = malloc(6 * (size_t)g.nv * sizeof *box);
	size_t i, j;
	long out = 0;
	int v, k;

	assert_non_null(box);
	for (v = 0; v < g.nv; v++)
		for (k = 0; k < 3; k++) {
			box[6 * v + k] = fmin(x0[3 * v + k], x1[3 * v + k]) - pad;
			box[6 * v + 3 + k] = fmax(x0[3 * v + k], x1[3 * v + k]) + pad;
		}
	g.x0 = plain.x0 = x0;
	g.x1 = plain.x1 = x1;
	g.vbox = plain.vbox = box;
	plain.tri_square = NULL;
	plain.uv = NULL;
	want.near = near;
	want.near_motion = 1.5;
	ref = new_broad(BROAD_BVH);
	if (broad_find(b, &g, 0.01, &want, &err) != 0 || broad_find(ref, &plain, 0.01, &want, &err) != 0)
		fail_msg("%s", err.msg);
	for (i = j = 0; i < ref->nvt; i++) {
		if (j < b->nvt && b->vt[j].v == ref->vt[i].v && b->vt[j].t == ref->vt[i].t) {
			j++;
			continue;
		}
		{
			const int *t = g.tri + 3 * ref->vt[i].t;
			int vert[4] = { ref->vt[i].v, t[0], t[1], t[2] };

			assert_harmless(&g, vert, 1, near, 1.5);
			out++;
		}
	}
	assert_int_equal(j, b->nvt);	/* bvh's are the reference's, in order */
	for (i = j = 0; i < ref->nee; i++) {
		if (j < b->nee && b->ee[j].a == ref->ee[i].a && b->ee[j].b == ref->ee[i].b) {
			j++;
			continue;
		}
		{
			const int *ea = g.edge + 2 * ref->ee[i].a, *eb = g.edge + 2 * ref->ee[i].b;
			int vert[4] = { ea[0], ea[1], eb[0], eb[1] };

			assert_harmless(&g, vert, 2, near, 1.5);
			out++;
		}
	}
	assert_int_equal(j, b->nee);
	broad_free(ref);
	free(box);
	return out;
}

/* The cloth at rest coordinates (u, v) put in space by shape kind with
 * parameter a (m), then turned by angle about y and moved by off. */
static vec3
shaped(int kind, double a, double u, double v, double turn, vec3 off)
{
	vec3 p;

	switch (kind) {
	case 0:		/* flat */
		p = v3(u, 0, v);
		break;
	case 1:		/* wrapped round a cylinder of radius a (layers meet past a turn) */
		p = v3(a * sin(u / a), a * (1 - cos(u / a)), v);
		break;
	case 2:		/* folded over at u = 0.1 m, a bend of radius a */
		if (u < 0.1) {
			p = v3(u, 0, v);
		} else if (u < 0.1 + PI * a) {
			double th = (u - 0.1) / a;

			p = v3(0.1 + a * sin(th), a * (1 - cos(th)), v);
		} else {
			p = v3(0.1 - (u - 0.1 - PI * a), 2 * a, v);
		}
		break;
	case 3:		/* waves of amplitude a, 20 mm long */
		p = v3(u, a * sin(2 * PI * u / 0.02) * cos(2 * PI * v / 0.03), v);
		break;
	default:	/* pressed along u to a fraction a / 0.01 of its length */
		p = v3(u * a / 0.01, 0, v);
		break;
	}
	return v3_add(v3(p.x * cos(turn) + p.z * sin(turn), p.y, -p.x * sin(turn) + p.z * cos(turn)),
	    off);
}

/* Whether pair (triangles ta, tb: a vertex's or edge's representative and
 * the other) lies inside one patch b leaves out. */
static int
in_culled(const struct broad *b, int ta, int tb)
{
	size_t k;

	for (k = 0; k < b->bvh.ncull; k++) {
		const struct bvh_node *p = &b->bvh.node[b->bvh.cull[k]];
		int i, a = 0, c = 0;

		for (i = p->first; i < p->first + p->count; i++) {
			a |= b->bvh.leaf_tri[i] == ta;
			c |= b->bvh.leaf_tri[i] == tb;
		}
		if (a && c)
			return 1;
	}
	return 0;
}

/* A check served by the held pairs, with vertices out of their held boxes
 * (their pairs come from queries, which leave a flat patch out), whose
 * correction then folds the patch: broad_recheck must give back every
 * pair a traversal would find, those of the vertices out of their held
 * boxes too, though the tree was refitted to the held boxes. */
static void
recheck_after_held(const struct geom *g0, const struct cloth *cl)
{
	struct broad_want want = collide_broad_want(NARROW_CCD, true);
	struct broad *b, *ref;
	struct geom g = *g0, plain;
	struct drape_err err;
	int n = cl->n, p, i, j, k, fold = -1, wide = 0;
	double *x0 = malloc(3 * (size_t)n * sizeof *x0), *x1 = malloc(3 * (size_t)n * sizeof *x1);
	double *box = malloc(6 * (size_t)n * sizeof *box);
	unsigned char *changed = calloc((size_t)n, 1);
	long uses;
	size_t m;

	assert_true(x0 != NULL && x1 != NULL && box != NULL && changed != NULL);
	/* pressed to 2 mm along u, at rest: flat, and a few millimetres
	 * cross it; the held boxes are the points themselves */
	for (p = 0; p < n; p++) {
		cloth_grid_ij(cl, p, &i, &j);
		v3_store(x0 + 3 * p, v3(0.2 * i * cl->h, 0.1, j * cl->h));
		v3_store(x1 + 3 * p, v3(0.2 * i * cl->h, 0.1, j * cl->h));
		for (k = 0; k < 6; k++)
			box[6 * p + k] = x0[3 * p + k % 3];
	}
	g.x0 = x0;
	g.x1 = x1;
	g.vbox = box;
	b = new_broad(BROAD_BVH);
	if (broad_find(b, &g, 0.01, &want, &err) != 0)	/* a short step's check: held */
		fail_msg("%s", err.msg);
	/* the check: the nodes near (12, 12) may go 15 mm (a correction's
	 * room), out of their held boxes; the cloth is still flat */
	for (p = 0; p < n; p++) {
		cloth_grid_ij(cl, p, &i, &j);
		if (abs(i - 12) <= 1 && abs(j - 12) <= 1) {
			for (k = 0; k < 6; k++)
				box[6 * p + k] += k < 3 ? -15e-3 : 15e-3;
			wide++;
		}
		if (i == 12 && j == 12)
			fold = p;
	}
	want.near = 0;
	uses = b->bvh.held_uses;
	if (broad_find(b, &g, 0.01, &want, &err) != 0)
		fail_msg("%s", err.msg);
	assert_true(b->bvh.held_uses > uses);	/* served by the held pairs */
	assert_int_equal(b->bvh.ncull, 1);
	/* a correction folds a node over its neighbours, inside its box */
	x1[3 * fold] -= 2.9e-3;
	x1[3 * fold + 1] -= 1e-3;
	changed[fold] = 1;
	assert_int_equal(broad_recheck(b, &g, changed), 1);
	plain = g;
	plain.tri_square = NULL;
	plain.uv = NULL;
	ref = new_broad(BROAD_BVH);
	if (broad_find(ref, &plain, 0.01, &want, &err) != 0)
		fail_msg("%s", err.msg);
	for (m = 0; m < ref->nvt; m++)
		if (!has_vt(b, ref->vt[m].v, ref->vt[m].t) &&
		    !in_culled(b, b->bvh.rep_vertex[ref->vt[m].v], ref->vt[m].t))
			fail_msg("after the fold, vertex %d and triangle %d are missing",
			    ref->vt[m].v, ref->vt[m].t);
	for (m = 0; m < ref->nee; m++)
		if (!has_ee(b, ref->ee[m].a, ref->ee[m].b) &&
		    !in_culled(b, b->bvh.rep_edge[ref->ee[m].a], b->bvh.rep_edge[ref->ee[m].b]))
			fail_msg("after the fold, edges %d and %d are missing", ref->ee[m].a,
			    ref->ee[m].b);
	print_message("flat patches: a fold after a check served by the held pairs (%d nodes "
	    "out of their held boxes): %zu + %zu pairs, every one a traversal finds outside "
	    "the patches still left out\n", wide, b->nvt, b->nee);
	broad_free(ref);
	broad_free(b);
	free(x0);
	free(x1);
	free(box);
	free(changed);
}

/* Flat patches: a flat cloth moving as a whole gives no self pairs at all
 * (the cull works); cloths bent, wrapped, folded, waved and pressed,
 * moving as other shapes of their kind with noise, give only pairs the
 * reference gives, and leave out only harmless ones, for the check and
 * for a step's contacts. Then a check whose corrections fold a flat
 * patch through itself gets the patch's pairs back (broad_recheck). */
static void
test_flat_patches(void **state)
{
	struct scene sc;
	struct stepper *st;
	struct broad *b;
	const struct geom *g;
	const struct cloth *cl;
	double *x0, *x1, a[5][3] = { { 0, 0, 0 }, { 2e-3, 8e-3, 0.05 },
	    { 0.1e-3, 1e-3, 5e-3 }, { 0.5e-3, 3e-3, 8e-3 }, { 0.7e-3, 2e-3, 0.01 } };
	unsigned rng = 777;
	long out = 0, searches = 0, in_contact = 0;
	int kind, i, j, p, n, e;
	size_t k;

	(void)state;
	load_shipped(&sc, SCENE_DIR "tablecloth.scene");
	st = new_stepper(&sc);
	g = stepper_geom(st);
	cl = cloth_of(st);
	assert_non_null(g->tri_square);
	n = cl->n;
	assert_int_equal(g->nv, n);
	x0 = malloc(3 * (size_t)n * sizeof *x0);
	x1 = malloc(3 * (size_t)n * sizeof *x1);
	assert_true(x0 != NULL && x1 != NULL);
	b = new_broad(BROAD_BVH);

	/* flat, moving as a whole: nothing to test at all */
	for (p = 0; p < n; p++) {
		cloth_grid_ij(cl, p, &i, &j);
		v3_store(x0 + 3 * p, shaped(0, 0, i * cl->h, j * cl->h, 0.3, v3(0, 0.1, 0)));
		v3_store(x1 + 3 * p, shaped(0, 0, i * cl->h, j * cl->h, 0.35, v3(0.004, 0.09, 0)));
	}
	for (e = 0; e < 2; e++) {
		long left = flat_search(b, *g, x0, x1, e ? 1e-3 : 0, e ? 0.6875e-3 : 0);

		print_message("flat patches: a flat cloth moving as a whole, %s: none of the "
		    "reference's %ld pairs\n", e ? "contacts" : "check", left);
		assert_int_equal(b->nvt + b->nee, 0);
		assert_int_equal(b->bvh.ncull, 1);	/* the whole cloth, at once */
		assert_true(e || left > 1000);
	}
	/* bent every way */
	for (kind = 1; kind < 5; kind++)
		for (e = 0; e < 3; e++) {
			double noise = e == 0 ? 0 : e == 1 ? 1e-4 : 2e-3;
			double turn = 0.1 * kind, s = 1 + 0.1 * e;

			for (p = 0; p < n; p++) {
				vec3 q;

				cloth_grid_ij(cl, p, &i, &j);
				v3_store(x0 + 3 * p, shaped(kind, a[kind][e], i * cl->h, j * cl->h, turn,
				    v3(0, 0.1, 0)));
				q = shaped(kind, a[kind][e] * s, i * cl->h, j * cl->h, turn + 0.02,
				    v3(0, 0.1 - 0.003 * e, 0));
				for (k = 0; k < 3; k++) {
					rng = rng * 1103515245u + 12345u;
					q.x += noise * ((double)((rng >> 16) % 2001) / 1000 - 1) / 3;
				}
				v3_store(x1 + 3 * p, q);
			}
			out += flat_search(b, *g, x0, x1, 0, 0);
			out += flat_search(b, *g, x0, x1, 1e-3, 0.6875e-3);
			out += flat_search(b, *g, x0, x0, 0, 0.6875e-3);
			searches += 3;
		}
	/* flat at the start, folded through itself at the end */
	for (p = 0; p < n; p++) {
		cloth_grid_ij(cl, p, &i, &j);
		v3_store(x0 + 3 * p, v3(i * cl->h, 0.1, j * cl->h));
		v3_store(x1 + 3 * p, i <= 12 ? v3(i * cl->h, 0.099, j * cl->h) :
		    v3((24 - i) * cl->h + 0.3e-3, 0.098, j * cl->h + 0.2e-3));
	}
	out += flat_search(b, *g, x0, x1, 0, 0);
	searches++;
	print_message("flat patches: %ld pairs left out in %ld searches of bent cloths, each "
	    "harmless\n", out, searches);
	assert_true(out > 10000);

	/* the check's corrections fold a flat cloth's half through the other */
	for (p = 0; p < n; p++) {
		cloth_grid_ij(cl, p, &i, &j);
		v3_store(x0 + 3 * p, v3(i * cl->h, 0.1, j * cl->h));
		v3_store(x1 + 3 * p, v3(i * cl->h, 0.099, j * cl->h));
	}
	{
		struct broad_want want = collide_broad_want(NARROW_CCD, true);
		struct geom gg = *g;
		struct drape_err err;
		unsigned char *changed = calloc((size_t)n, 1);
		double *box = malloc(6 * (size_t)n * sizeof *box);

		assert_true(changed != NULL && box != NULL);
		for (p = 0; p < n; p++)
			for (k = 0; k < 6; k++)
				box[6 * p + k] = x0[3 * p + k % 3] + (k < 3 ? -0.3 : 0.3);
		gg.x0 = x0;
		gg.x1 = x1;
		gg.vbox = box;
		if (broad_find(b, &gg, 0.01, &want, &err) != 0)
			fail_msg("%s", err.msg);
		assert_int_equal(b->nvt + b->nee, 0);
		for (p = 0; p < n; p++) {
			cloth_grid_ij(cl, p, &i, &j);
			if (i <= 12)
				continue;
			/* under the other half, and past it */
			v3_store(x1 + 3 * p, v3((24 - i) * cl->h + 0.3e-3, 0.098, j * cl->h + 0.2e-3));
			changed[p] = 1;
		}
		assert_int_equal(broad_recheck(b, &gg, changed), 1);
		{
			struct broad *ref;
			struct geom plain = gg;

			plain.tri_square = NULL;
			plain.uv = NULL;
			ref = new_broad(BROAD_BVH);
			if (broad_find(ref, &plain, 0.01, &want, &err) != 0)
				fail_msg("%s", err.msg);
			for (k = 0; k < ref->nvt; k++) {
				const int *t = gg.tri + 3 * ref->vt[k].t;
				vec3 q0[4], q1[4];
				int vert[4] = { ref->vt[k].v, t[0], t[1], t[2] }, m;

				for (m = 0; m < 4; m++) {
					q0[m] = v3_load(x0 + 3 * vert[m]);
					q1[m] = v3_load(x1 + 3 * vert[m]);
				}
				if (!ccd_vertex_face(q0, q1, 0, NULL))
					continue;
				in_contact++;
				if (!has_vt(b, ref->vt[k].v, ref->vt[k].t))
					fail_msg("a pair in contact after the fold is missing");
			}
			broad_free(ref);
		}
		print_message("flat patches: %ld vertex-triangle pairs in contact after a fold, "
		    "all given back\n", in_contact);
		assert_true(in_contact > 20);
		free(changed);
		free(box);
	}
	recheck_after_held(g, cl);
	broad_free(b);
	free(x0);
	free(x1);
	stepper_free(st);
	scene_free(&sc);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_failsafe_jam),
		cmocka_unit_test(test_bvh_held_pairs),
		cmocka_unit_test(test_flat_patches),
		cmocka_unit_test(test_icosahedron),
		cmocka_unit_test(test_tablecloth_clean),
		cmocka_unit_test(test_strip_fast_clean),
		cmocka_unit_test(test_tablecloth_fast_clean),
		cmocka_unit_test(test_strip_clean),
		cmocka_unit_test(test_tablecloth_implicit_clean),
		cmocka_unit_test(test_tablecloth_bdf2_clean),
		cmocka_unit_test(test_contacts_closing),
		cmocka_unit_test(test_implicit_resting_on_box),
		cmocka_unit_test(test_seed_figures),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
