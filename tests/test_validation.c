/* test_validation.c: static shapes against their closed-form or ODE
 * answers: the Peirce cantilever (heavy elastica) and the catenary. */
#include <math.h>

#include "testutil.h"
#include "vec3.h"

#define DEG (180 / V3_PI)

/*
 * The heavy elastica in units of the overhang l: theta'' = -lam (1 - s)
 * cos(theta), theta(0) = 0, lam = q l^3 / B, theta measured downwards.
 * Integrates from s = 0 with theta'(0) = k0 by RK4 over n steps; returns
 * theta'(1) and the tip's (x, y) (y downwards).
 */
static double
elastica_shoot(double lam, double k0, double *x, double *y)
{
	const int n = 4000;
	double h = 1.0 / n, th = 0, w = k0, s = 0;
	int i;

	*x = *y = 0;
	for (i = 0; i < n; i++) {
		double k[4][4], st[4] = { th, w, 0, 0 };
		int r, c;

		for (r = 0; r < 4; r++) {
			static const double cr[4] = { 0, 0.5, 0.5, 1 };
			double tth = th, tw = w, ss = s + cr[r] * h;

			if (r > 0) {
				tth = th + cr[r] * h * k[r - 1][0];
				tw = w + cr[r] * h * k[r - 1][1];
			}
			k[r][0] = tw;
			k[r][1] = -lam * (1 - ss) * cos(tth);
			k[r][2] = cos(tth);
			k[r][3] = sin(tth);
		}
		for (c = 0; c < 4; c++)
			st[c] = h / 6 * (k[0][c] + 2 * k[1][c] + 2 * k[2][c] + k[3][c]);
		th += st[0];
		w += st[1];
		*x += st[2];
		*y += st[3];
		s += h;
	}
	return w;
}

/* The chord angle (degrees below horizontal, clamp to tip) of the elastica
 * with theta'(1) = 0, found by bisection on theta'(0) in [0, lam/2]. */
static double
elastica_chord(double lam)
{
	double lo = 0, hi = lam / 2, x, y;
	int it;

	for (it = 0; it < 60; it++) {
		double mid = (lo + hi) / 2;

		if (elastica_shoot(lam, mid, &x, &y) < 0)
			lo = mid;
		else
			hi = mid;
	}
	elastica_shoot(lam, lo, &x, &y);
	return atan2(y, x) * DEG;
}

/* lam whose elastica droops to the given chord angle (it grows with lam). */
static double
elastica_lambda(double chord_deg)
{
	double lo = 0.01, hi = 1000;
	int it;

	for (it = 0; it < 60; it++) {
		double mid = sqrt(lo * hi);

		if (elastica_chord(mid) < chord_deg)
			lo = mid;
		else
			hi = mid;
	}
	return sqrt(lo * hi);
}

static void
elastica_solver(void **state)
{
	(void)state;
	/* l = 2c, the overhang ASTM D1388 reads c at: 41.5 degrees */
	print_message("elastica: l = 2c droops to %.3f degrees\n", elastica_chord(8));
	assert_double_equal(elastica_chord(8), 41.5, 0.05);
	assert_double_equal(elastica_lambda(elastica_chord(3)), 3, 1e-6);
	assert_true(elastica_chord(0.01) < 0.1);
}

/*
 * The shipped cantilever, two nodes wide instead of five and with a tensile
 * modulus ten times lower so that it runs 6x faster: bending is per unit
 * width, and the strain under the strip's weight stays below 1e-4.
 */
static void
cantilever_with(enum integrator_kind integrator)
{
	struct scene sc;
	struct stepper *st;
	struct energy e;
	int clamp, tip;
	double q, l, c_true, lam, chord, chord_ref, c_inferred, c_peirce, th;

	load_shipped_with(&sc, SCENE_DIR "cantilever.scene", "nodes = 22 5", "nodes = 22 2");
	sc.mat.modulus[0] /= 10;
	sc.mat.modulus[1] /= 10;
	sc.integrator = integrator;
	st = new_stepper(&sc);
	run_to_end(st);
	stepper_energy(st, &e);
	assert_true(e.kinetic < 1e-12);		/* at rest */

	clamp = cloth_node(cloth_of(st), 1, 0);	/* the ledge's edge */
	tip = cloth_node(cloth_of(st), cloth_of(st)->nu - 1, 0);
	q = sc.mat.weight * v3_len(v3_load(sc.gravity));
	l = (cloth_of(st)->nu - 2) * cloth_of(st)->h;
	c_true = cbrt(sc.mat.bending[0] / q);
	lam = q * l * l * l / sc.mat.bending[0];
	chord = atan2(stepper_x(st)[3 * clamp + 1] - stepper_x(st)[3 * tip + 1],
	    stepper_x(st)[3 * tip] - stepper_x(st)[3 * clamp]) * DEG;
	chord_ref = elastica_chord(lam);
	c_inferred = l / cbrt(elastica_lambda(chord));
	th = chord / DEG;
	c_peirce = l * cbrt(cos(th / 2) / (8 * tan(th)));
	print_message("cantilever (%s, %ld steps): l = %.1f mm, c = %.3f mm (l/c = %.3f)\n",
	    integrator_name(integrator), report_of(st).step, l * 1e3, c_true * 1e3, l / c_true);
	print_message("  chord angle %.3f deg, elastica %.3f deg: error %.3f deg\n", chord,
	    chord_ref, chord - chord_ref);
	print_message("  bending length from the droop %.3f mm: error %.3f %%\n", c_inferred * 1e3,
	    100 * (c_inferred / c_true - 1));
	print_message("  Peirce's closed form gives c = %.3f mm: %+.2f %% (not asserted)\n",
	    c_peirce * 1e3, 100 * (c_peirce / c_true - 1));
	assert_double_equal(chord, chord_ref, 0.5);
	assert_double_equal(c_inferred / c_true, 1, 0.01);
	assert_double_equal(l / c_true, 2, 0.01);	/* the scene is the ASTM case */
	assert_double_equal(chord, 41.5, 0.5);
	stepper_free(st);
	scene_free(&sc);
}

static void cantilever_matches_elastica(void **state) { (void)state; cantilever_with(INTEG_RK4); }

/* Implicit Euler comes to the same rest at its far longer step. */
static void
cantilever_implicit(void **state)
{
	(void)state;
	cantilever_with(INTEG_IMPLICIT_EULER);
}

/* The shipped hanging strip, two nodes wide instead of three. */
static void
catenary_with(enum integrator_kind integrator)
{
	struct scene sc;
	struct stepper *st;
	double span, length, arc = 0, lo = 1e-3, hi = 100, a, sag, sag_ref, top;
	int i, mid;

	load_shipped_with(&sc, SCENE_DIR "hanging.scene", "nodes = 41 3", "nodes = 41 2");
	sc.integrator = integrator;
	st = new_stepper(&sc);
	run_to_end(st);
	span = stepper_x(st)[3 * cloth_node(cloth_of(st), cloth_of(st)->nu - 1, 0)] - stepper_x(st)[0];
	length = (cloth_of(st)->nu - 1) * cloth_of(st)->h;
	for (i = 0; i + 1 < cloth_of(st)->nu; i++)
		arc += v3_len(v3_sub(v3_load(stepper_x(st) + 3 * (i + 1)),
		    v3_load(stepper_x(st) + 3 * i)));
	/* L = 2 a sinh(S / 2a): bisection on a (L/S falls as a grows) */
	for (i = 0; i < 200; i++) {
		a = sqrt(lo * hi);
		if (2 * a * sinh(span / (2 * a)) > length)
			lo = a;
		else
			hi = a;
	}
	a = sqrt(lo * hi);
	sag_ref = a * (cosh(span / (2 * a)) - 1);
	mid = cloth_node(cloth_of(st), cloth_of(st)->nu / 2, 0);
	top = stepper_x(st)[1];
	sag = top - stepper_x(st)[3 * mid + 1];
	print_message("catenary (%s, %ld steps): span %.4f m, length %.4f m (mean strain %.2e), "
	    "a = %.4f m\n", integrator_name(integrator), report_of(st).step, span, length, arc / length - 1, a);
	print_message("  sag %.5f m, catenary %.5f m: error %.3f %%\n", sag, sag_ref,
	    100 * (sag / sag_ref - 1));
	assert_double_equal(span, 0.4, 1e-12);
	assert_true(fabs(arc / length - 1) < 1e-3);	/* inextensible enough */
	assert_double_equal(sag / sag_ref, 1, 0.01);
	stepper_free(st);
	scene_free(&sc);
}

static void hanging_strip_is_a_catenary(void **state) { (void)state; catenary_with(INTEG_RK4); }
static void catenary_implicit(void **state) { (void)state; catenary_with(INTEG_IMPLICIT_EULER); }
static void cantilever_fast(void **state) { (void)state; cantilever_with(INTEG_FAST); }
static void catenary_fast(void **state) { (void)state; catenary_with(INTEG_FAST); }
static void cantilever_bdf2(void **state) { (void)state; cantilever_with(INTEG_BDF2); }
static void catenary_bdf2(void **state) { (void)state; catenary_with(INTEG_BDF2); }

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(elastica_solver),
		cmocka_unit_test(cantilever_matches_elastica),
		cmocka_unit_test(hanging_strip_is_a_catenary),
		cmocka_unit_test(cantilever_implicit),
		cmocka_unit_test(catenary_implicit),
		cmocka_unit_test(cantilever_fast),
		cmocka_unit_test(catenary_fast),
		cmocka_unit_test(cantilever_bdf2),
		cmocka_unit_test(catenary_bdf2),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
