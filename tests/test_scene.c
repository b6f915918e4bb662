/* test_scene.c: units, the scene parser's values and defaults, selectors.
 * (Rejected input is tested through the binary in test_cli.c.) */
#include <math.h>

#include "testutil.h"
#include "prescribed.h"
#include "units.h"

#define MINIMAL \
	"[simulation]\nduration = 1\n" \
	"[cloth]\nnodes = 4 3\nspacing = 10 mm\nweight = 120 g/m2\nthickness = 0.3 mm\n" \
	"modulus_warp = 30 MPa\nmodulus_weft = 20 MPa\nshear_modulus = 0\n" \
	"bending_warp = 0\nbending_weft = derived\n"

static void
units_convert(void **state)
{
	char why[200];
	double v[3];

	(void)state;
	assert_int_equal(units_parse("10 mm", DIM_LENGTH, v, 1, why, sizeof why), 0);
	assert_double_equal(v[0], 0.01, 1e-15);
	assert_int_equal(units_parse("120 g/m2", DIM_AREAL_DENSITY, v, 1, why, sizeof why), 0);
	assert_double_equal(v[0], 0.12, 1e-15);
	assert_int_equal(units_parse("0.1 gf*cm2/cm", DIM_BENDING, v, 1, why, sizeof why), 0);
	assert_double_equal(v[0], 9.80665e-6, 1e-18);
	assert_int_equal(units_parse("1 -2 3.5 m/s", DIM_VELOCITY, v, 3, why, sizeof why), 0);
	assert_double_equal(v[1], -2, 0);
	assert_int_equal(units_parse("2", DIM_TIME, v, 1, why, sizeof why), 0);
	assert_double_equal(v[0], 2, 0);
	assert_int_equal(units_parse("5 kg", DIM_LENGTH, v, 1, why, sizeof why), -1);
	assert_non_null(strstr(why, "unknown unit"));
	assert_int_equal(units_parse("nan", DIM_TIME, v, 1, why, sizeof why), -1);
	assert_int_equal(units_parse("1e999", DIM_TIME, v, 1, why, sizeof why), -1);
	assert_int_equal(units_parse("1 2", DIM_TIME, v, 1, why, sizeof why), -1);
	assert_int_equal(units_parse("1", DIM_TIME, v, 3, why, sizeof why), -1);
	assert_int_equal(units_parse("3 mm", DIM_NONE, v, 1, why, sizeof why), -1);
}

static void
minimal_scene_defaults(void **state)
{
	struct scene sc;

	(void)state;
	parse_text(&sc, MINIMAL);
	assert_string_equal(sc.name, "test");
	assert_int_equal(sc.nu, 4);
	assert_int_equal(sc.nv, 3);
	assert_double_equal(sc.spacing, 0.01, 1e-15);
	assert_int_equal(sc.integrator, INTEG_RK4);
	assert_true(sc.dt == 0);		/* auto */
	assert_double_equal(sc.gravity[1], -9.80665, 1e-12);
	assert_double_equal(sc.mat.weight, 0.12, 1e-15);
	assert_false(sc.mat.bending_derived[0]);
	assert_true(sc.mat.bending_derived[1]);	/* E*t^3/12 */
	assert_double_equal(sc.mat.bending[1], 20e6 * pow(0.3e-3, 3) / 12, 1e-18);
	assert_int_equal(sc.nmotions, 0);
	scene_free(&sc);
}

static void
selectors_blocks(void **state)
{
	struct scene sc;
	const struct node_block *b;

	(void)state;
	parse_text(&sc, MINIMAL "[pin]\nnodes = 0 *, -1 0\n[move]\nnodes = 1..2 -1\n"
	    "velocity = 0 1 0 cm/s\nstart = 0.5 s\n[load]\nnodes = * *\nforce = 0 -1 0 mN\n");
	assert_int_equal(sc.nmotions, 2);
	assert_int_equal(sc.motions[0].kind, MOTION_PIN);
	assert_int_equal(sc.motions[0].nodes.n, 2);
	b = sc.motions[0].nodes.b;
	assert_int_equal(b[0].i0, 0);
	assert_int_equal(b[0].i1, 0);
	assert_int_equal(b[0].j0, 0);
	assert_int_equal(b[0].j1, 2);
	assert_int_equal(b[1].i0, 3);	/* -1 is the last of 4 */
	assert_int_equal(b[1].j1, 0);
	assert_int_equal(sc.motions[1].kind, MOTION_VELOCITY);
	assert_double_equal(sc.motions[1].velocity[1], 0.01, 1e-15);
	assert_double_equal(sc.motions[1].start, 0.5, 0);
	assert_true(isinf(sc.motions[1].stop));
	assert_int_equal(sc.motions[1].nodes.b[0].i0, 1);
	assert_int_equal(sc.motions[1].nodes.b[0].i1, 2);
	assert_int_equal(sc.motions[1].nodes.b[0].j0, 2);
	assert_int_equal(sc.nloads, 1);
	assert_double_equal(sc.loads[0].force[1], -1e-3, 1e-15);
	scene_free(&sc);
}

static void
gravity_forms(void **state)
{
	struct scene sc;

	(void)state;
	parse_text(&sc, "[simulation]\nduration = 1\ngravity = 0 0 -9.81 m/s2\n"
	    "[cloth]\nnodes = 2 2\nspacing = 1 cm\nweight = 0.1\nthickness = 1 mm\n"
	    "modulus_warp = 1 MPa\nmodulus_weft = 1 MPa\nshear_modulus = 0\n"
	    "bending_warp = 0\nbending_weft = 0\norientation = +x -y\n");
	assert_double_equal(sc.gravity[2], -9.81, 1e-15);
	assert_double_equal(sc.gravity[1], 0, 0);
	assert_double_equal(sc.weft_axis[1], -1, 0);
	scene_free(&sc);
}

static void
path_motion(void **state)
{
	struct scene sc;
	double d[3], v[3];

	(void)state;
	parse_text(&sc, MINIMAL "[move]\nnodes = 0 0\npath = 1 0 0.1 0, 2 0 0.1 0.2\n");
	assert_int_equal(sc.motions[0].kind, MOTION_PATH);
	assert_int_equal(sc.motions[0].npath, 2);
	prescribed_motion(&sc.motions[0], 0.5, d, v);
	assert_double_equal(d[1], 0.05, 1e-15);
	assert_double_equal(v[1], 0.1, 1e-15);
	prescribed_motion(&sc.motions[0], 1.5, d, v);
	assert_double_equal(d[1], 0.1, 1e-15);
	assert_double_equal(d[2], 0.1, 1e-15);
	assert_double_equal(v[2], 0.2, 1e-15);
	prescribed_motion(&sc.motions[0], 5, d, v);	/* held at the end */
	assert_double_equal(d[2], 0.2, 1e-15);
	assert_double_equal(v[2], 0, 0);
	scene_free(&sc);
}

#define DISC_CLOTH(nodes, shape) \
	"[simulation]\nduration = 1\n[cloth]\nnodes = " nodes "\nshape = " shape "\n" \
	"spacing = 10 mm\nweight = 120 g/m2\nthickness = 0.3 mm\nmodulus_warp = 30 MPa\n" \
	"modulus_weft = 20 MPa\nshear_modulus = 0\nbending_warp = 0\nbending_weft = 0\n"

/* Fails unless text is rejected with "test.scene:LINE: ...expect...". */
static void
rejected(const char *text, int line, const char *expect)
{
	struct scene sc;
	struct drape_err err;
	char where[64];

	snprintf(where, sizeof where, "test.scene:%d: ", line);
	if (scene_parse(&sc, "test.scene", text, &err) == 0) {
		scene_free(&sc);
		fail_msg("accepted; expected '%s%s'", where, expect);
	}
	if (strncmp(err.msg, where, strlen(where)) != 0 || strstr(err.msg, expect) == NULL)
		fail_msg("'%s'; expected '%s%s'", err.msg, where, expect);
}

static void
cloth_shape(void **state)
{
	struct scene sc;

	(void)state;
	parse_text(&sc, MINIMAL);
	assert_int_equal(sc.shape, SHAPE_SQUARE);
	scene_free(&sc);
	parse_text(&sc, DISC_CLOTH("5 5", "disc"));
	assert_int_equal(sc.shape, SHAPE_DISC);
	scene_free(&sc);
	rejected(DISC_CLOTH("5 6", "disc"), 5, "shape = disc: expected a square grid of at "
	    "least 4 x 4 nodes (nodes = n n), got 5 x 6");
	rejected(DISC_CLOTH("3 3", "disc"), 5, "got 3 x 3");
	rejected(DISC_CLOTH("5 5", "circle"), 5, "shape: expected one of square, disc, got "
	    "'circle'");
}

/* On a disc, a selector's grid positions off the disc are skipped; a set
 * left with none is an error at its section. */
static void
selectors_on_a_disc(void **state)
{
	struct scene sc;
	struct stepper *st;
	struct drape_err err;

	(void)state;
	parse_text(&sc, DISC_CLOTH("5 5", "disc") "[pin]\nnodes = * 1\n");
	st = new_stepper(&sc);
	assert_int_equal(stepper_network(st)->pr.nnodes, 3);	/* (1..3, 1) */
	stepper_free(st);
	scene_free(&sc);
	parse_text(&sc, DISC_CLOTH("5 5", "disc") "[pin]\nnodes = 0 *\n");
	assert_null(stepper_new(&sc, &err));
	assert_non_null(strstr(err.msg, "test.scene:14: nodes: the set has no node on the disc"));
	scene_free(&sc);
	parse_text(&sc, DISC_CLOTH("5 5", "disc") "[load]\nnodes = 2 0\nforce = 0 1 0\n");
	assert_null(stepper_new(&sc, &err));
	assert_non_null(strstr(err.msg, "test.scene:14: nodes: the set has no node on the disc"));
	scene_free(&sc);
}

static void
every_shipped_scene_parses(void **state)
{
	static const char *names[] = { "cantilever", "hanging", "free-fall", "drape" };
	size_t i;

	(void)state;
	for (i = 0; i < sizeof names / sizeof names[0]; i++) {
		char path[512];
		struct scene sc;

		snprintf(path, sizeof path, SCENE_DIR "%s.scene", names[i]);
		load_shipped(&sc, path);
		assert_string_equal(sc.name, names[i]);
		stepper_free(new_stepper(&sc));
		scene_free(&sc);
	}
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(units_convert),
		cmocka_unit_test(minimal_scene_defaults),
		cmocka_unit_test(selectors_blocks),
		cmocka_unit_test(gravity_forms),
		cmocka_unit_test(path_motion),
		cmocka_unit_test(cloth_shape),
		cmocka_unit_test(selectors_on_a_disc),
		cmocka_unit_test(every_shipped_scene_parses),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
