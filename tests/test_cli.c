/* test_cli.c: the real binary: help and version, rejected scenes (message
 * with file:line, exit 2, nothing simulated), the drape coefficient and
 * hash lines of the summary, blow-up (exit 3), OBJ output, determinism
 * across runs. */
#include <sys/wait.h>
#include <unistd.h>

#include "config.h"
#include "testutil.h"
#include "runbin.h"



static const char *
write_scene(const char *name, const char *text)
{
	static char path[700];
	FILE *f;

	snprintf(path, sizeof path, "%s/%s", dir, name);
	f = fopen(path, "w");
	assert_non_null(f);
	assert_true(fputs(text, f) >= 0);
	assert_int_equal(fclose(f), 0);
	return path;
}

/* Writes a scene and runs "drape run --headless" on it. */
static void
run_text(struct result *r, const char *name, const char *text)
{
	char args[800];

	snprintf(args, sizeof args, "run --headless '%s'", write_scene(name, text));
	drape(r, args);
}


static void
help_and_version(void **state)
{
	struct result r;

	(void)state;
	drape(&r, "--help");
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "usage: drape"));
	assert_non_null(strstr(r.out, "drape run [--headless] [--until T] [--integrator NAME]"));
	drape(&r, "--version");
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "drape " PACKAGE_VERSION));
	drape(&r, "");
	assert_int_equal(r.status, 2);
	drape(&r, "--bogus");
	assert_int_equal(r.status, 2);
	drape(&r, "run");
	assert_int_equal(r.status, 2);
	drape(&r, "run --integrator leapfrog " TOP_SRCDIR "/scenes/hanging.scene");
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "--integrator 'leapfrog'"));
	drape(&r, "run --until -1 " TOP_SRCDIR "/scenes/hanging.scene");
	assert_int_equal(r.status, 2);
	drape(&r, "run --dt 0 " TOP_SRCDIR "/scenes/hanging.scene");
	assert_int_equal(r.status, 2);
	drape(&r, "run --delay 0 " TOP_SRCDIR "/scenes/hanging.scene");
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "--delay '0': expected tenths of a second"));
	drape(&r, "run -d x " TOP_SRCDIR "/scenes/hanging.scene");
	assert_int_equal(r.status, 2);
	drape(&r, "run -d");
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "option '-d' needs a value"));
	/* not on a terminal: headless, and it says so */
	drape(&r, "run -C --paused -d 5 --until 1ms " TOP_SRCDIR "/scenes/hanging.scene");
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.err, "not a terminal: running headless"));
	assert_non_null(strstr(r.out, "state hash"));
	drape(&r, "run --headless --until 1ms " TOP_SRCDIR "/scenes/hanging.scene");
	assert_int_equal(r.status, 0);
	assert_null(strstr(r.err, "not a terminal"));
	drape(&r, "run " TOP_SRCDIR "/scenes/no-such.scene");
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "no-such.scene: cannot open"));
}

#define SIM "[simulation]\nduration = 0.01\n"
#define CLOTH_BODY "spacing = 10 mm\nweight = 100 g/m2\nthickness = 0.3 mm\n" \
	"modulus_warp = 1 MPa\nmodulus_weft = 1 MPa\nshear_modulus = 0\n" \
	"bending_warp = 0\nbending_weft = 0\n"
#define GOOD SIM "[cloth]\nnodes = 4 4\n" CLOTH_BODY

static const struct bad_case {
	const char *what;
	const char *text;
	int line;
	const char *expect;	/* a piece of the message */
} bad_cases[] = {
	{ "unknown section", GOOD "[clth]\n", 13, "unknown section [clth]" },
	{ "unknown key", SIM "speed = 3\n" "[cloth]\nnodes = 4 4\n" CLOTH_BODY, 3,
	  "unknown key 'speed' in [simulation]" },
	{ "missing key", SIM "[cloth]\nnodes = 4 4\nweight = 100 g/m2\nthickness = 0.3 mm\n"
	  "modulus_warp = 1 MPa\nmodulus_weft = 1 MPa\nshear_modulus = 0\nbending_warp = 0\n"
	  "bending_weft = 0\n", 3, "[cloth] needs 'spacing'" },
	{ "missing section", SIM, 2, "expected a [cloth] section" },
	{ "malformed value", SIM "[cloth]\nnodes = 4 4\nspacing = ten mm\nweight = 1\n"
	  "thickness = 1 mm\nmodulus_warp = 1\nmodulus_weft = 1\nshear_modulus = 0\n"
	  "bending_warp = 0\nbending_weft = 0\n", 5,
	  "spacing: expected a number" },
	{ "zero spacing", SIM "[cloth]\nnodes = 4 4\nspacing = 0 mm\nweight = 1\nthickness = 1 mm\n"
	  "modulus_warp = 1\nmodulus_weft = 1\nshear_modulus = 0\nbending_warp = 0\n"
	  "bending_weft = 0\n", 5, "spacing: expected a length (m, cm, mm, um) greater than 0" },
	{ "negative mass", SIM "[cloth]\nnodes = 4 4\nspacing = 1 cm\nweight = -100 g/m2\n"
	  "thickness = 1 mm\nmodulus_warp = 1\nmodulus_weft = 1\nshear_modulus = 0\n"
	  "bending_warp = 0\nbending_weft = 0\n", 6, "weight: expected a weight per area" },
	{ "NaN", "[simulation]\nduration = nan\n[cloth]\nnodes = 4 4\n" CLOTH_BODY, 2,
	  "duration: expected a finite number" },
	{ "0 x 1 nodes", SIM "[cloth]\nnodes = 0 1\n" CLOTH_BODY, 4,
	  "nodes: expected two whole numbers nu nv, each from 1" },
	{ "unknown unit", SIM "[cloth]\nnodes = 4 4\nspacing = 1 furlong\nweight = 1\n"
	  "thickness = 1 mm\nmodulus_warp = 1\nmodulus_weft = 1\nshear_modulus = 0\n"
	  "bending_warp = 0\nbending_weft = 0\n", 5, "unknown unit 'furlong'" },
	{ "duplicate key", GOOD "spacing = 2 cm\n", 13, "spacing: already set at line 5" },
	{ "bad integrator", "[simulation]\nduration = 1\nintegrator = verlet\n[cloth]\n"
	  "nodes = 4 4\n" CLOTH_BODY, 3, "integrator: expected rk4, euler" },
	{ "node out of range", GOOD "[pin]\nnodes = 4 0\n", 14, "nodes: index out of range" },
	{ "node held twice", GOOD "[pin]\nnodes = 0 *\n[move]\nnodes = 0 0\nvelocity = 0 1 0\n",
	  15, "node 0 0 already has its motion given by the section at line 13" },
	{ "key before section", "duration = 1\n" GOOD, 1, "expected a [section] header" },
	{ "not key = value", GOOD "[pin]\nnodes\n", 14, "expected 'key = value'" },
	{ "move without motion", GOOD "[move]\nnodes = 0 0\n", 13, "needs either 'velocity'" },
	{ "bad orientation", GOOD "orientation = +x +x\n", 13, "orientation: expected two different" },
	{ "bending missing", SIM "[cloth]\nnodes = 4 4\nspacing = 1 cm\nweight = 1\n"
	  "thickness = 1 mm\nmodulus_warp = 1\nmodulus_weft = 1\nshear_modulus = 0\n"
	  "bending_warp = 0\n", 3, "needs 'bending_weft'" },
	{ "stop before start", GOOD "[load]\nnodes = * *\nforce = 0 1 0\nstart = 2\nstop = 1\n", 17,
	  "stop: expected a time after start" },
	{ "disc not square", SIM "[cloth]\nnodes = 6 5\nshape = disc\n" CLOTH_BODY, 5,
	  "shape = disc: expected a square grid" },
	{ "pin off the disc", SIM "[cloth]\nnodes = 6 6\nshape = disc\n" CLOTH_BODY
	  "[pin]\nnodes = 0 0\n", 14, "nodes: the set has no node on the disc cloth" },
	{ "path not increasing", GOOD "[move]\nnodes = 0 0\npath = 1 0 0 0, 0.5 0 0 0\n", 15,
	  "path: expected times after 0 that increase" },
};

static void
bad_scenes_exit_2(void **state)
{
	size_t i;

	(void)state;
	for (i = 0; i < sizeof bad_cases / sizeof bad_cases[0]; i++) {
		const struct bad_case *c = &bad_cases[i];
		const char *path = write_scene("bad.scene", c->text);
		char args[800], where[800];
		struct result r;

		snprintf(args, sizeof args, "run --headless '%s'", path);
		drape(&r, args);
		snprintf(where, sizeof where, "%s:%d: ", path, c->line);
		if (r.status != 2 || strstr(r.err, where) == NULL || strstr(r.err, c->expect) == NULL ||
		    r.out[0] != '\0')
			fail_msg("%s: status %d, stderr '%s', stdout '%.80s'; expected 2 and '%s%s'",
			    c->what, r.status, r.err, r.out, where, c->expect);
	}
}

static void
good_scene_runs(void **state)
{
	struct result r;

	(void)state;
	run_text(&r, "good.scene", GOOD);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "state hash"));
	assert_non_null(strstr(r.out, "simulated    0.01 s"));
}

/* A small Cusick test: an 11 x 11 disc falling onto a support disc. */
#define CUSICK(broad) \
	"[simulation]\nduration = 30 ms\n[cloth]\nnodes = 11 11\nshape = disc\n" \
	"origin = -0.05 0.102 -0.05 m\n" CLOTH_BODY "[disc]\ncentre = 0 0.1 0\nradius = 3 cm\n" \
	"height = 0.1\n[collision]\nself = on\nbroad = " broad "\n"

static void
drape_coefficient_and_hash(void **state)
{
	struct result r;
	const char *at;
	double dc;
	int k;

	(void)state;
	run_text(&r, "cusick.scene", CUSICK("grid"));
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "network      disc of 77 nodes in a 11 x 11 grid"));
	at = strstr(r.out, "drape coefficient ");
	assert_non_null(at);
	assert_int_equal(sscanf(at, "drape coefficient %lf", &dc), 1);
	print_message("drape coefficient after 30 ms: %.4f\n", dc);
	assert_true(dc > 0.9 && dc <= 1.01);	/* barely started to fall */
	assert_non_null(strstr(r.out, "hash         per fill "));
	at = strstr(r.out, "hash histogram ");
	assert_non_null(at);
	for (k = 1; k <= HASH_HIST; k++) {
		char bucket[16];

		snprintf(bucket, sizeof bucket, " %d%s:", k, k == HASH_HIST ? "+" : "");
		assert_non_null(strstr(at, bucket));
	}
	/* no hash for brute force; no coefficient for a square cloth */
	run_text(&r, "cusick.scene", CUSICK("brute"));
	assert_int_equal(r.status, 0);
	assert_null(strstr(r.out, "\nhash "));
	assert_non_null(strstr(r.out, "drape coefficient "));
	run_text(&r, "good.scene", GOOD "[disc]\ncentre = 0 -0.1 0\nradius = 3 cm\nheight = 0.1\n");
	assert_int_equal(r.status, 0);
	assert_null(strstr(r.out, "drape coefficient"));
}

static void
blowup_exits_3(void **state)
{
	struct result r;

	(void)state;
	run_text(&r, "stiff.scene", "[simulation]\nduration = 1\ndt = 5 ms\n"
	    "[cloth]\nnodes = 6 6\nspacing = 1 cm\nweight = 100 g/m2\nthickness = 0.3 mm\n"
	    "modulus_warp = 30 MPa\nmodulus_weft = 30 MPa\nshear_modulus = 0\n"
	    "bending_warp = 0\nbending_weft = 0\n[pin]\nnodes = 0 0\n");
	assert_int_equal(r.status, 3);
	assert_non_null(strstr(r.err, "blow-up at step"));
	assert_non_null(strstr(r.err, ": node "));
}

static void
final_obj(void **state)
{
	struct result r;
	char args[1400], obj[700], text[16384], *p;
	int nv = 0, nf = 0, maxi = 0;

	(void)state;
	snprintf(obj, sizeof obj, "%s/final.obj", dir);
	snprintf(args, sizeof args, "run --headless --until 2ms --final-obj '%s' '%s'", obj,
	    TOP_SRCDIR "/scenes/cantilever.scene");
	drape(&r, args);
	assert_int_equal(r.status, 0);
	slurp(obj, text, sizeof text);
	for (p = strtok(text, "\n"); p != NULL; p = strtok(NULL, "\n")) {
		int a, b, c;

		if (p[0] == 'v' && p[1] == ' ')
			nv++;
		if (sscanf(p, "f %d %d %d", &a, &b, &c) == 3) {
			nf++;
			assert_true(a >= 1 && b >= 1 && c >= 1);
			maxi = a > maxi ? a : maxi;
			maxi = b > maxi ? b : maxi;
			maxi = c > maxi ? c : maxi;
		}
	}
	assert_int_equal(nv, 22 * 5);
	assert_int_equal(nf, 2 * 21 * 4);
	assert_int_equal(maxi, 22 * 5);		/* 1-based: the last node is used */
	/* an unwritable path: exit 1, and nothing half-written left behind */
	snprintf(args, sizeof args, "run --until 1ms --final-obj '%s/none/x.obj' '%s'", dir,
	    TOP_SRCDIR "/scenes/cantilever.scene");
	drape(&r, args);
	assert_int_equal(r.status, 1);
	assert_non_null(strstr(r.err, "none/x.obj"));
}

static void
two_runs_same_hash(void **state)
{
	struct result a, b;
	const char *args = "run --headless --until 5ms " TOP_SRCDIR "/scenes/hanging.scene";

	(void)state;
	drape(&a, args);
	drape(&b, args);
	assert_int_equal(a.status, 0);
	assert_int_equal(b.status, 0);
	assert_non_null(strstr(a.out, "state hash"));
	assert_string_equal(strstr(a.out, "state hash"), strstr(b.out, "state hash"));
}

/* A replay's snapshot at its last step (a keyframe, exact) is the scene's
 * at that step; a step between frames shows the frame before it. */
static void
snapshot_of_a_replay(void **state)
{
	struct result r;
	char args[1024], path[256], *scene_view;
	const char *scene = TOP_SRCDIR "/scenes/hanging.scene", *at;
	long steps;

	(void)state;
	snprintf(path, sizeof path, "%s/snap.drr", dir);
	snprintf(args, sizeof args, "run --headless --until 5ms --record '%s' '%s'", path, scene);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(at = strstr(r.out, "steps        "));
	steps = strtol(at + 13, NULL, 10);
	assert_true(steps > 2);
	snprintf(args, sizeof args, "snapshot --step %ld --size 60x20 '%s'", steps, scene);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(scene_view = strdup(r.out));
	snprintf(args, sizeof args, "snapshot --step %ld --size 60x20 '%s'", steps, path);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_string_equal(r.out, scene_view);
	assert_string_equal(r.err, "");
	free(scene_view);
	/* the frames are 20 ms apart: step 1 shows step 0's */
	snprintf(args, sizeof args, "snapshot --step 1 --size 60x20 '%s'", path);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.err, "step 1 shows the frame of step 0"));
	snprintf(args, sizeof args, "snapshot --step %ld '%s'", steps + 1, path);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "ends at step"));
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(help_and_version),
		cmocka_unit_test(bad_scenes_exit_2),
		cmocka_unit_test(good_scene_runs),
		cmocka_unit_test(drape_coefficient_and_hash),
		cmocka_unit_test(blowup_exits_3),
		cmocka_unit_test(final_obj),
		cmocka_unit_test(two_runs_same_hash),
		cmocka_unit_test(snapshot_of_a_replay),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
