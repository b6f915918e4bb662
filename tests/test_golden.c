/* test_golden.c: golden state hashes. Short, fixed runs of the shipped
 * scenes (and of one small scene under every integrator) must end in the
 * state hash written here, bit for bit: a refactor changes no result. A
 * change that alters a method's results updates its hashes here in the
 * same commit and says why.
 *
 * GOLDEN_PRINT=1 tests/test_golden prints every case's hash instead of
 * failing, to fill in the table. */
#include "testutil.h"

#include <inttypes.h>

/* A small scene with everything a step can do: self-contact, an analytic
 * box and floor, a mesh obstacle (the icosahedron), a pinned corner, a
 * load, bending, shear and damping. */
static const char small_scene[] =
    "[simulation]\n"
    "name = small\n"
    "duration = 0.1 s\n"
    "dt = 20 us\n"
    "integrator = rk4\n"
    "gravity = 9.80665 m/s2\n"
    "output_rate = 50 Hz\n"
    "[cloth]\n"
    "nodes = 9 9\n"
    "spacing = 10 mm\n"
    "origin = -0.04 0.085 -0.04 m\n"
    "orientation = +x +z\n"
    "weight = 150 g/m2\n"
    "thickness = 0.55 mm\n"
    "modulus_warp = 0.45 MPa\n"
    "modulus_weft = 0.30 MPa\n"
    "shear_modulus = 9 kPa\n"
    "bending_warp = 3 uN*m\n"
    "bending_weft = 2 uN*m\n"
    "damping = 2 /s\n"
    "spring_damping = 50 us\n"
    "[pin]\n"
    "nodes = 0 0\n"
    "[load]\n"
    "nodes = 8 8\n"
    "force = 0 0 0.5 mN\n"
    "stop = 30 ms\n"
    "[box]\n"
    "min = 0 0 -0.05 m\n"
    "max = 0.05 0.06 0.05 m\n"
    "[icosahedron]\n"
    "centre = -0.03 0.04 0 m\n"
    "radius = 0.035 m\n"
    "[plane]\n"
    "point = 0 0 0 m\n"
    "[collision]\n"
    "self = on\n"
    "broad = grid\n"
    "narrow = ccd\n"
    "position = slide\n";

struct golden {
	const char *name;
	const char *scene;	/* a shipped scene's file name, or NULL: small_scene */
	const char *edit[2][2];	/* replacements in its text: from, to */
	const char *integrator;	/* NULL: the scene's */
	double until;		/* s */
	uint64_t hash;
};

#define SEED_KEEP { { "broad = grid\nnarrow = ccd\nposition = slide", \
	"broad = seed\nnarrow = seed\nposition = keep" } }
#define SEED_Q { { "broad = grid\nnarrow = ccd\nposition = slide", \
	"broad = seed\nnarrow = seed\nposition = q" } }
/* the shipped scenes run the fast path with bvh: their chapter's settings */
#define SHIPPED_SEED_KEEP { { "broad = bvh\nnarrow = ccd\nposition = slide", \
	"broad = seed\nnarrow = seed\nposition = keep" } }
#define SHIPPED_SEED_Q { { "broad = bvh\nnarrow = ccd\nposition = slide", \
	"broad = seed\nnarrow = seed\nposition = q" } }
#define SHIPPED_RK4_GRID { { "integrator = fast", "integrator = rk4" }, \
	{ "broad = bvh", "broad = grid" } }

static const struct golden cases[] = {
	{ "small rk4", NULL, { { NULL } }, "rk4", 0.1, 0x10324b96d1333a05 },
	{ "small euler", NULL, { { NULL } }, "euler", 0.1, 0x2f3fef75e6d9d270 },
	{ "small symplectic-euler", NULL, { { NULL } }, "symplectic-euler", 0.1, 0xf297ff88ada7fa1c },
	{ "small rk2", NULL, { { NULL } }, "rk2", 0.1, 0x058f9aea9140e80f },
	{ "small dopri5", NULL, { { NULL } }, "dopri5", 0.1, 0xc879dd0d3d99986b },
	{ "small implicit-euler", NULL, { { NULL } }, "implicit-euler", 0.1, 0x0b6ac3a037ed4c59 },
	/* fast at the scene's step (one substep each), and at its own dt =
	 * auto, where a step of 10 ms takes several substeps */
	{ "small fast", NULL, { { NULL } }, "fast", 0.1, 0xee47dc30db8fa90c },
	{ "small fast dt auto", NULL, { { "dt = 20 us", "dt = auto" } }, "fast", 0.1,
	    0x9218cd4a7b608c53 },
	/* bdf2 at its own dt = auto (10 ms: one Newton solve a step) */
	{ "small bdf2 dt auto", NULL, { { "dt = 20 us", "dt = auto" } }, "bdf2", 0.1, 0xecc0559083ac5bde },
	{ "small seed/seed/keep", NULL, SEED_KEEP, "rk4", 0.1, 0x0db1250a5d12bb1e },
	{ "small seed/seed/q", NULL, SEED_Q, "rk4", 0.06, 0x64f8d153cf62c8b1 },
	{ "small brute/ccd/keep", NULL, { { "broad = grid\nnarrow = ccd\nposition = slide",
	    "broad = brute\nnarrow = ccd\nposition = keep" } }, "rk4", 0.05, 0x76f8ab18bca44351 },
	{ "small grid/ccd/q", NULL, { { "position = slide", "position = q" } }, "rk4", 0.1, 0x4572515caff687f1 },
	{ "strip", "strip.scene", { { NULL } }, NULL, 0.3, 0xdbb97f7dfc936a10 },
	/* the chapter's method, as the scene says it is taken */
	{ "strip rk4 grid", "strip.scene", SHIPPED_RK4_GRID, NULL, 0.3, 0x9e6872369207f259 },
	{ "strip implicit-euler", "strip.scene", { { NULL } }, "implicit-euler", 0.6, 0xdc3057b8a450f8cb },
	{ "strip bdf2", "strip.scene", { { NULL } }, "bdf2", 0.3, 0x708a7b805ea38b62 },
	{ "strip seed/seed/keep", "strip.scene", SHIPPED_SEED_KEEP, "rk4", 0.5, 0xc91c0bf02839046f },
	{ "strip seed/seed/q", "strip.scene", SHIPPED_SEED_Q, "rk4", 0.4, 0x0defcf87776710cd },
	{ "tablecloth", "tablecloth.scene", { { NULL } }, NULL, 0.25, 0xc6a34f19236e875a },
	{ "tablecloth rk4 grid", "tablecloth.scene", SHIPPED_RK4_GRID, NULL, 0.25,
	    0xaec7bb2cc2284c72 },
	{ "tablecloth implicit-euler", "tablecloth.scene", { { NULL } }, "implicit-euler", 0.5,
	    0xad3192b2869fec5e },
	{ "tablecloth bdf2", "tablecloth.scene", { { NULL } }, "bdf2", 0.25, 0xbf920e7bae416508 },
	{ "tablecloth seed/seed/keep", "tablecloth.scene", SHIPPED_SEED_KEEP, "rk4", 0.2,
	    0x5d0b1c7911c0e87e },
	{ "tablecloth seed/seed/q", "tablecloth.scene", SHIPPED_SEED_Q, "rk4", 0.35,
	    0xf49dfe41af544dba },
	{ "icosahedron", "icosahedron.scene", { { NULL } }, NULL, 1, 0xf274d3b988002b31 },
	{ "cantilever", "cantilever.scene", { { NULL } }, NULL, 0.05, 0x83f5f4b212cb3011 },
	{ "hanging", "hanging.scene", { { NULL } }, NULL, 0.1, 0x5cf7a554f8281059 },
	{ "drape", "drape.scene", { { NULL } }, NULL, 0.1, 0xa9f7ca0cad56c6c3 },
};

/* The case's scene text with its edits made. */
static char *
scene_text(const struct golden *g)
{
	char *text, *out;
	size_t n = 0, k;

	if (g->scene == NULL) {
		text = strdup(small_scene);
	} else {
		char path[512];
		FILE *f;

		snprintf(path, sizeof path, "%s%s", SCENE_DIR, g->scene);
		if ((f = fopen(path, "r")) == NULL)
			fail_msg("cannot open %s", path);
		text = malloc(65536);
		assert_non_null(text);
		n = fread(text, 1, 65535, f);
		fclose(f);
		text[n] = '\0';
	}
	assert_non_null(text);
	for (k = 0; k < 2 && g->edit[k][0] != NULL; k++) {
		const char *from = g->edit[k][0], *to = g->edit[k][1];
		char *at = strstr(text, from);

		if (at == NULL)
			fail_msg("%s: no '%s' to replace", g->name, from);
		n = strlen(text) - strlen(from) + strlen(to) + 1;
		out = malloc(n);
		assert_non_null(out);
		snprintf(out, n, "%.*s%s%s", (int)(at - text), text, to, at + strlen(from));
		free(text);
		text = out;
	}
	return text;
}

static uint64_t
run_case(const struct golden *g)
{
	struct scene sc;
	struct stepper *st;
	struct drape_err err;
	char *text = scene_text(g), path[512];
	uint64_t h;

	snprintf(path, sizeof path, "%s", g->scene != NULL ? g->scene : "small.scene");
	if (scene_parse(&sc, path, text, &err) != 0)
		fail_msg("%s: %s", g->name, err.msg);
	free(text);
	sc.duration = g->until;
	if (g->integrator != NULL) {
		enum integrator_kind k;

		assert_int_equal(integrator_from_name(g->integrator, &k), 0);
		sc.integrator = k;
	}
	st = new_stepper(&sc);
	run_to_end(st);
	h = stepper_hash(st);
	stepper_free(st);
	scene_free(&sc);
	return h;
}

static void
test_golden(void **state)
{
	bool print = getenv("GOLDEN_PRINT") != NULL;
	int bad = 0;
	size_t i;

	(void)state;
	setvbuf(stdout, NULL, _IOLBF, 0);
	for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		uint64_t h = run_case(&cases[i]);

		if (print || h != cases[i].hash)
			printf("%-28s 0x%016" PRIx64 "%s\n", cases[i].name, h,
			    h == cases[i].hash ? "" : " (differs)");
		bad += h != cases[i].hash;
	}
	if (bad && !print)
		fail_msg("%d of %zu golden hashes differ", bad, sizeof cases / sizeof cases[0]);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_golden),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
