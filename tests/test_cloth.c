/* test_cloth.c: the network's topology, masses and stiffnesses, and the
 * forces checked against the energy's gradient. */
#include <math.h>

#include "testutil.h"
#include "cloth.h"
#include "forces.h"
#include "vec3.h"

#define CLOTH_WITH(sim, nu, nv, extra) \
	"[simulation]\nduration = 1 s\n" sim "[cloth]\nnodes = " #nu " " #nv "\nspacing = 10 mm\n" \
	"weight = 100 g/m2\nthickness = 0.5 mm\nmodulus_warp = 20 MPa\nmodulus_weft = 10 MPa\n" \
	extra
#define CLOTH(nu, nv, extra) CLOTH_WITH("", nu, nv, extra)

#define FULL "shear_modulus = 0.2 MPa\nbending_warp = 10 uN*m\nbending_weft = 5 uN*m\n"

static void
build(struct cloth *cl, struct scene *sc, const char *text)
{
	struct drape_err err;

	parse_text(sc, text);
	if (cloth_build(cl, sc, &err) != 0)
		fail_msg("%s", err.msg);
}

static void
counts_and_masses(void **state)
{
	struct scene sc;
	struct cloth cl;
	double total = 0;
	int p;

	(void)state;
	build(&cl, &sc, CLOTH(7, 5, FULL));
	assert_int_equal(cl.n, 35);
	assert_int_equal(cl.nsprings, 6 * 5 + 7 * 4);
	assert_int_equal(cl.ncorners, 4 * 6 * 4);
	assert_int_equal(cl.nhinges, 5 * 5 + 7 * 3);
	assert_int_equal(cl.ntri, 2 * 6 * 4);
	assert_int_equal(cl.nedges, 6 * 5 + 7 * 4 + 6 * 4);
	for (p = 0; p < cl.n; p++)
		total += cl.mass[p];
	assert_double_equal(total, 0.1 * 0.06 * 0.04, 1e-15);
	assert_double_equal(cl.mass[cloth_node(&cl, 0, 0)], 0.1 * 0.005 * 0.005, 1e-15);
	assert_double_equal(cl.mass[cloth_node(&cl, 3, 2)], 0.1 * 0.01 * 0.01, 1e-15);
	/* E*t over the tributary width: half on the border lines */
	assert_double_equal(cl.springs[0].k, 20e6 * 0.5e-3 / 2, 1e-9);
	assert_double_equal(cl.springs[6].k, 20e6 * 0.5e-3, 1e-9);	/* j = 1 */
	cloth_free(&cl);
	scene_free(&sc);
}

static void
zero_properties_build_nothing(void **state)
{
	struct scene sc;
	struct cloth cl;

	(void)state;
	build(&cl, &sc, CLOTH(6, 6, "shear_modulus = 0\nbending_warp = 0\nbending_weft = 0\n"));
	assert_int_equal(cl.ncorners, 0);
	assert_int_equal(cl.nhinges, 0);
	assert_null(cl.corners);
	assert_null(cl.hinges);
	cloth_free(&cl);
	scene_free(&sc);
	build(&cl, &sc, CLOTH(6, 6, "shear_modulus = 0\nbending_warp = 1 uN*m\nbending_weft = 0\n"));
	assert_int_equal(cl.nhinges, 4 * 6);	/* warp lines only */
	cloth_free(&cl);
	scene_free(&sc);
}

static void
check_adjacency(const char *text)
{
	struct scene sc;
	struct cloth cl;
	size_t t, e, f;
	int p, k;

	build(&cl, &sc, text);
	assert_int_equal(cl.node_tri_start[cl.n], 3 * (int)cl.ntri);
	assert_int_equal(cl.node_edge_start[cl.n], 2 * (int)cl.nedges);
	for (p = 0; p < cl.n; p++) {
		for (k = cl.node_tri_start[p]; k < cl.node_tri_start[p + 1]; k++) {
			const int *tri = cl.tri + 3 * cl.node_tri[k];

			assert_true(tri[0] == p || tri[1] == p || tri[2] == p);
			if (k > cl.node_tri_start[p])	/* ascending */
				assert_true(cl.node_tri[k] > cl.node_tri[k - 1]);
		}
		for (k = cl.node_edge_start[p]; k < cl.node_edge_start[p + 1]; k++) {
			const int *ed = cl.edge + 2 * cl.node_edge[k];

			assert_true(ed[0] == p || ed[1] == p);
		}
	}
	/* every triangle edge is listed once among the edges */
	for (t = 0; t < cl.ntri; t++)
		for (k = 0; k < 3; k++) {
			int a = cl.tri[3 * t + (size_t)k], b = cl.tri[3 * t + (size_t)(k + 1) % 3];
			int found = 0;

			for (e = 0; e < cl.nedges; e++)
				if ((cl.edge[2 * e] == a && cl.edge[2 * e + 1] == b) ||
				    (cl.edge[2 * e] == b && cl.edge[2 * e + 1] == a))
					found++;
			assert_int_equal(found, 1);
		}
	for (e = 0; e < cl.nedges; e++)
		for (f = 0; f < e; f++)
			assert_false(cl.edge[2 * e] == cl.edge[2 * f] &&
			    cl.edge[2 * e + 1] == cl.edge[2 * f + 1]);
	/* at rest every triangle faces along warp x weft (+x cross +z = -y) */
	for (t = 0; t < cl.ntri; t++) {
		vec3 a = v3_load(cl.x0 + 3 * cl.tri[3 * t]);
		vec3 n = v3_cross(v3_sub(v3_load(cl.x0 + 3 * cl.tri[3 * t + 1]), a),
		    v3_sub(v3_load(cl.x0 + 3 * cl.tri[3 * t + 2]), a));

		assert_true(n.y < 0);
		assert_double_equal(v3_len(n), 0.01 * 0.01, 1e-18);
	}
	cloth_free(&cl);
	scene_free(&sc);
}

static void
adjacency_is_consistent(void **state)
{
	(void)state;
	check_adjacency(CLOTH(6, 4, FULL));
	check_adjacency(CLOTH(9, 9, "shape = disc\n" FULL));
}

/* The 5 x 5 disc, by hand: centre (2, 2), radius 2, squares by their
 * centres. The four corner squares' centres lie sqrt(4.5) from the centre,
 * out of the circle; the other 12 are in it. So the cloth is the grid less
 * its four corner nodes: 21 nodes, 12 squares, warp springs 2 + 4 + 4 + 4
 * + 2 = 16 and as many weft, warp hinges 1 + 3 + 3 + 3 + 1 = 11 and as many
 * weft, 24 triangles, 32 + 12 diagonals = 44 edges.
 *
 * The 9 x 9 disc (centre (4, 4), radius 4), o a node in the circle, x a
 * node out of it (the corner of a square whose centre is in it):
 *
 *	  xxoxx        rows of nodes 5, 7, 9, 9, 9, 9, 9, 7, 5:   69 nodes
 *	 xooooox       squares by row 4, 6, 8, 8, 8, 8, 6, 4:     52 squares
 *	xooooooox      warp springs (n - 1 a row)
 *	xooooooox        4 + 6 + 8*5 + 6 + 4:                     60, weft 60
 *	ooooooooo      warp hinges (n - 2 a row)
 *	xooooooox        3 + 5 + 7*5 + 5 + 3:                     51, weft 51
 *	xooooooox
 *	 xooooox
 *	  xxoxx
 */
static void
disc_counts_and_masses(void **state)
{
	struct scene sc;
	struct cloth cl;
	double total = 0, h2 = 0.01 * 0.01;
	int p, i, j;

	(void)state;
	build(&cl, &sc, CLOTH(5, 5, "shape = disc\n" FULL));
	assert_int_equal(cl.n, 21);
	assert_int_equal(cl.nsquares, 12);
	assert_int_equal(cl.nsprings, 32);
	assert_int_equal(cl.ncorners, 48);
	assert_int_equal(cl.nhinges, 22);
	assert_int_equal(cl.ntri, 24);
	assert_int_equal(cl.nedges, 44);
	assert_int_equal(cloth_node(&cl, 0, 0), -1);
	assert_int_equal(cloth_node(&cl, 4, 4), -1);
	assert_int_equal(cloth_node(&cl, 1, 0), 0);	/* dense, in grid order */
	assert_int_equal(cloth_node(&cl, 0, 2), 8);
	assert_int_equal(cloth_node(&cl, 3, 3), 16);
	cloth_grid_ij(&cl, 5, &i, &j);
	assert_int_equal(i, 2);
	assert_int_equal(j, 1);
	assert_double_equal(cl.x0[3 * 5], 0.02, 1e-15);
	assert_double_equal(cl.x0[3 * 5 + 2], 0.01, 1e-15);
	cloth_free(&cl);
	scene_free(&sc);

	build(&cl, &sc, CLOTH(9, 9, "shape = disc\n" FULL));
	assert_int_equal(cl.n, 69);
	assert_int_equal(cl.nsquares, 52);
	assert_int_equal(cl.nsprings, 120);
	assert_int_equal(cl.ncorners, 4 * 52);
	assert_int_equal(cl.nhinges, 102);
	assert_int_equal(cl.ntri, 104);
	assert_int_equal(cl.nedges, 120 + 52);
	for (p = 0; p < cl.n; p++) {
		assert_true(cl.mass[p] > 0);
		assert_true(cl.node_tri_start[p + 1] > cl.node_tri_start[p]);
		cloth_grid_ij(&cl, p, &i, &j);
		assert_int_equal(cloth_node(&cl, i, j), p);
		total += cl.mass[p];
	}
	assert_double_equal(total, 0.1 * 52 * h2, 1e-15);
	/* a quarter of each square around: 1 at a rim corner, 3 in a notch */
	assert_double_equal(cl.mass[cloth_node(&cl, 2, 0)], 0.1 * h2 / 4, 1e-15);
	assert_double_equal(cl.mass[cloth_node(&cl, 2, 1)], 0.1 * h2 * 3 / 4, 1e-15);
	assert_double_equal(cl.mass[cloth_node(&cl, 4, 4)], 0.1 * h2, 1e-15);
	/* the rim spring (2, 0)-(3, 0) stands for the half square inside it */
	for (p = 0; p < (int)cl.nsprings; p++)
		if (cl.springs[p].a == cloth_node(&cl, 2, 0) &&
		    cl.springs[p].b == cloth_node(&cl, 3, 0))
			break;
	assert_true(p < (int)cl.nsprings);
	assert_double_equal(cl.springs[p].k, 20e6 * 0.5e-3 / 2, 1e-9);
	cloth_free(&cl);
	scene_free(&sc);
}

static double
total_elastic(const struct forces *fo, const double *x, const double *v)
{
	struct energy e;

	forces_energy(fo, 0, x, v, &e);
	return e.stretch + e.shear + e.bend + e.gravity + e.load;
}

/* A uniform number in [-0.5, 0.5) from a 64-bit LCG's state, stepped. */
static double
uniform(uint64_t *rng)
{
	*rng = *rng * 6364136223846793005ULL + 1442695040888963407ULL;
	return (double)(*rng >> 11) / 9007199254740992.0 - 0.5;
}

/* Forces must be minus the gradient of the energy: central differences on
 * a crumpled configuration, every coordinate of every node; with fold > 0
 * through the explicit methods' fold limiter (forces.h), which must then
 * hold some hinge of that configuration for the check to mean anything. */
static void
gradient_check(const struct scene *sc, const struct cloth *cl, double fold)
{
	struct forces fo;
	struct drape_err err;
	double *x, *v, *a, worst = 0, scale = 0;
	uint64_t rng = 12345;
	int p, k, held = 0;
	size_t s;

	assert_int_equal(forces_init(&fo, sc, cl, &err), 0);
	fo.fold = fold;
	x = malloc(3 * (size_t)cl->n * sizeof *x);
	v = calloc(3 * (size_t)cl->n, sizeof *v);
	a = malloc(3 * (size_t)cl->n * sizeof *a);
	assert_non_null(x);
	assert_non_null(v);
	assert_non_null(a);
	for (k = 0; k < 3 * cl->n; k++) {	/* up to 40 % of h off the grid */
		x[k] = cl->x0[k] + 0.008 * uniform(&rng);
	}
	for (s = 0; s < cl->nhinges; s++) {
		const struct hinge *hg = &cl->hinges[s];
		double e1e2 = 0;

		for (k = 0; k < 3; k++)
			e1e2 += (x[3 * hg->b + k] - x[3 * hg->a + k]) * (x[3 * hg->c + k] - x[3 * hg->b + k]);
		held += cl->h * cl->h + e1e2 < fold * cl->h * cl->h;
	}
	if (fold > 0) {
		print_message("%d of %zu hinges held by the fold limiter\n", held, cl->nhinges);
		assert_true(held > 0 && held < (int)cl->nhinges);
	}
	forces_accel(&fo, 0, x, v, a);
	for (p = 0; p < cl->n; p++)
		for (k = 0; k < 3; k++) {
			double save = x[3 * p + k], h = 1e-7, ep, em, f_num, f;

			x[3 * p + k] = save + h;
			ep = total_elastic(&fo, x, v);
			x[3 * p + k] = save - h;
			em = total_elastic(&fo, x, v);
			x[3 * p + k] = save;
			f_num = -(ep - em) / (2 * h);
			f = a[3 * p + k] * cl->mass[p];
			worst = fmax(worst, fabs(f - f_num));
			scale = fmax(scale, fabs(f));
		}
	print_message("largest force %.3e N, largest |F + dE/dx| %.3e N\n", scale, worst);
	assert_true(scale > 1e-3);
	assert_true(worst < 1e-6 * scale);
	free(x);
	free(v);
	free(a);
	forces_free(&fo);
}

/* A disc is the circle to a few squares, with no bias that would leave
 * its rim short (keeping only the squares wholly inside gave 8 % too
 * little at 31 x 31, 4.5 % at 61 x 61), and it keeps the square grid's
 * symmetries: the same under a mirror across either axis or a diagonal. */
static void
disc_area_is_the_circles(void **state)
{
	static const char *const grids[] = {
		CLOTH(31, 31, "shape = disc\n" FULL), CLOTH(61, 61, "shape = disc\n" FULL),
		CLOTH(121, 121, "shape = disc\n" FULL),
	};
	static const int sides[] = { 31, 61, 121 };
	static const double within[] = { 0.015, 0.001, 0.001 };
	struct scene sc;
	struct cloth cl;
	size_t g;

	(void)state;
	for (g = 0; g < sizeof grids / sizeof *grids; g++) {
		int n = sides[g], i, j;
		double r = (n - 1) * 0.01 / 2, circle = V3_PI * r * r, area;

		build(&cl, &sc, grids[g]);
		area = cl.nsquares * 0.01 * 0.01;
		print_message("%d x %d disc: %zu squares, %.4f of the circle\n", n, n,
		    cl.nsquares, area / circle);
		assert_true(fabs(area / circle - 1) <= within[g]);
		for (j = 0; j < n; j++)
			for (i = 0; i < n; i++) {
				int here = cloth_node(&cl, i, j) >= 0;

				assert_int_equal(here, cloth_node(&cl, n - 1 - i, j) >= 0);
				assert_int_equal(here, cloth_node(&cl, i, n - 1 - j) >= 0);
				assert_int_equal(here, cloth_node(&cl, j, i) >= 0);
			}
		cloth_free(&cl);
		scene_free(&sc);
	}
}

static void
forces_are_energy_gradient(void **state)
{
	struct scene sc;
	struct cloth cl;

	(void)state;
	build(&cl, &sc, CLOTH(5, 4, FULL "[load]\nnodes = 2 2\nforce = 0.01 0 0 N\n"));
	gradient_check(&sc, &cl, 0);
	/* the explicit methods' fold limiter, here where a hinge turns by 35
	 * degrees (a fold of 1.82): the held energy's gradient too */
	gradient_check(&sc, &cl, 1 + cos(35 * V3_PI / 180));
	cloth_free(&cl);
	scene_free(&sc);
	/* a disc: its rim has the half-width springs and hinges */
	build(&cl, &sc, CLOTH(9, 9, "shape = disc\n" FULL "[load]\nnodes = 4 4\nforce = 0.01 0 0 N\n"));
	gradient_check(&sc, &cl, 0);
	cloth_free(&cl);
	scene_free(&sc);
}

/* Rigid motions store no energy and produce no internal force. */
static void
rigid_motion_is_free(void **state)
{
	struct scene sc;
	struct cloth cl;
	struct forces fo;
	struct drape_err err;
	struct energy e;
	double *x, *v, *a, c = cos(0.7), s = sin(0.7);
	int p;

	(void)state;
	build(&cl, &sc, CLOTH_WITH("gravity = 0\n", 5, 5, FULL));
	assert_int_equal(forces_init(&fo, &sc, &cl, &err), 0);
	x = malloc(3 * (size_t)cl.n * sizeof *x);
	v = calloc(3 * (size_t)cl.n, sizeof *v);
	a = malloc(3 * (size_t)cl.n * sizeof *a);
	assert_non_null(x);
	assert_non_null(v);
	assert_non_null(a);
	for (p = 0; p < cl.n; p++) {	/* rotate about y then z, and shift */
		vec3 q = v3_load(cl.x0 + 3 * p), r = v3(c * q.x + s * q.z, q.y, -s * q.x + c * q.z);

		v3_store(x + 3 * p, v3(c * r.x - s * r.y + 0.3, s * r.x + c * r.y - 1, r.z + 2));
	}
	forces_accel(&fo, 0, x, v, a);
	forces_energy(&fo, 0, x, v, &e);
	for (p = 0; p < 3 * cl.n; p++)
		assert_true(fabs(a[p]) < 1e-6);
	assert_true(e.stretch + e.shear + e.bend < 1e-20);
	free(x);
	free(v);
	free(a);
	forces_free(&fo);
	cloth_free(&cl);
	scene_free(&sc);
}


/* |kb| of hinge s at x (forces.c add_bend's, D unclamped). */
static double
hinge_kb(const struct cloth *cl, const struct hinge *hg, const double *x)
{
	vec3 xb = v3_load(x + 3 * hg->b);
	vec3 e1 = v3_sub(xb, v3_load(x + 3 * hg->a)), e2 = v3_sub(v3_load(x + 3 * hg->c), xb);

	return v3_len(v3_scale(v3_cross(e1, e2), 2 / (cl->h * cl->h + v3_dot(e1, e2))));
}

/* The fast path's hinge dashpots (forces_accel_bending's c): their power
 * is -c k (d|kb|/dt)^2 summed over the hinges, with the rate taken by
 * central differences; a rigid motion of the bent cloth, and rest, get
 * no force from them. */
static void
hinge_dashpots_damp_bending_alone(void **state)
{
	struct scene sc;
	struct cloth cl;
	struct forces fo;
	struct drape_err err;
	double *x, *v, *a0, *a1, *xp, *xm, c = 2e-4, power = 0, want = 0, big = 0, worst = 0;
	uint64_t rng = 777;
	size_t s;
	int p, k, round;

	(void)state;
	build(&cl, &sc, CLOTH_WITH("gravity = 0\n", 5, 4, FULL));
	assert_int_equal(forces_init(&fo, &sc, &cl, &err), 0);
	x = malloc(3 * (size_t)cl.n * sizeof *x);
	v = malloc(3 * (size_t)cl.n * sizeof *v);
	a0 = malloc(3 * (size_t)cl.n * sizeof *a0);
	a1 = malloc(3 * (size_t)cl.n * sizeof *a1);
	xp = malloc(3 * (size_t)cl.n * sizeof *xp);
	xm = malloc(3 * (size_t)cl.n * sizeof *xm);
	assert_true(x && v && a0 && a1 && xp && xm);
	for (k = 0; k < 3 * cl.n; k++) {	/* crumpled, moving at random */
		x[k] = cl.x0[k] + 0.008 * uniform(&rng);
		v[k] = 0.2 * uniform(&rng);
	}
	forces_accel_bending(&fo, 0, x, v, a0, 0, 0);
	forces_accel_bending(&fo, 0, x, v, a1, 0, c);
	for (p = 0; p < cl.n; p++)
		for (k = 0; k < 3; k++)
			power += cl.mass[p] * (a1[3 * p + k] - a0[3 * p + k]) * v[3 * p + k];
	for (k = 0; k < 3 * cl.n; k++) {
		xp[k] = x[k] + 1e-7 * v[k];
		xm[k] = x[k] - 1e-7 * v[k];
	}
	for (s = 0; s < cl.nhinges; s++) {
		double rate = (hinge_kb(&cl, &cl.hinges[s], xp) - hinge_kb(&cl, &cl.hinges[s], xm)) / 2e-7;

		want -= c * cl.hinges[s].k * rate * rate;
	}
	print_message("dashpots' power %.6e W, -c sum k (d|kb|/dt)^2 %.6e W\n", power, want);
	assert_true(want < 0);
	assert_true(fabs(power - want) < 1e-5 * fabs(want));
	/* rigid: turning about (1, 2, 3) at 3 rad/s and moving; then at rest */
	for (round = 0; round < 2; round++) {
		vec3 w = v3(3 / sqrt(14.0), 6 / sqrt(14.0), 9 / sqrt(14.0));

		for (p = 0; p < cl.n; p++) {
			big = fmax(big, v3_len(v3_sub(v3_load(a1 + 3 * p), v3_load(a0 + 3 * p))));
			v3_store(v + 3 * p, round == 0 ? v3_add(v3_cross(w, v3_load(x + 3 * p)),
			    v3(0.1, -0.2, 0.05)) : v3(0, 0, 0));
		}
		forces_accel_bending(&fo, 0, x, v, a0, 0, 0);
		forces_accel_bending(&fo, 0, x, v, a1, 0, c);
		for (p = 0; p < cl.n; p++)
			worst = fmax(worst, v3_len(v3_sub(v3_load(a1 + 3 * p), v3_load(a0 + 3 * p))));
	}
	print_message("dashpots' largest acceleration: %.3e m/s^2 moving, %.3e rigid or at rest\n",
	    big, worst);
	assert_true(big > 0);
	assert_true(worst < 1e-9 * big);
	free(x);
	free(v);
	free(a0);
	free(a1);
	free(xp);
	free(xm);
	forces_free(&fo);
	cloth_free(&cl);
	scene_free(&sc);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(counts_and_masses),
		cmocka_unit_test(zero_properties_build_nothing),
		cmocka_unit_test(adjacency_is_consistent),
		cmocka_unit_test(disc_counts_and_masses),
		cmocka_unit_test(disc_area_is_the_circles),
		cmocka_unit_test(forces_are_energy_gradient),
		cmocka_unit_test(rigid_motion_is_free),
		cmocka_unit_test(hinge_dashpots_damp_bending_alone),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
