/* test_set.c: --set SECTION.KEY=VALUE through the binary, on every kind of
 * value (a number with a unit, a node selector, a word, a path), on a key
 * the section lacks, a section the scene lacks and a repeated section;
 * each gives the run that the scene file saying so gives (the same state
 * hash), and a bad one of each is refused with the option named, what was
 * expected, exit 2 and nothing run; the file's own errors keep its line
 * numbers; check and snapshot take --set too, and check refuses a bad
 * one before it prints anything. */
#include "testutil.h"
#include "runbin.h"
#include "json.h"

/* The scene, line by line (the numbers matter to the messages). */
#define L1_16 "[simulation]\nduration = 10 ms\n[cloth]\nnodes = 5 5\nspacing = 10 mm\n" \
	"origin = -0.02 0 -0.02 m\nweight = 100 g/m2\nthickness = 0.3 mm\nmodulus_warp = 1 MPa\n" \
	"modulus_weft = 1 MPa\nshear_modulus = 0\nbending_warp = 1 uN*m\nbending_weft = 1 uN*m\n" \
	"[pin]\nnodes = 0 *\n"
#define PLANES "[plane]\npoint = 0 -0.1 0 m\n[plane]\npoint = 0 -0.0003 0 m\nfriction = 0.1\n"
#define MESH(f) "[mesh]\nfile = " f "\n"
#define COLLISION "[collision]\nself = on\nbroad = grid\n"
#define BASE L1_16 PLANES MESH("a.obj") COLLISION	/* planes at lines 16 and 18 */

static int
setup_files(void **state)
{
	if (setup(state) != 0)
		return -1;
	/* a.obj far below; b.obj a triangle right under the cloth */
	dir_write_text("a.obj", "v 1 -1 1\nv 2 -1 1\nv 1 -1 2\nf 1 2 3\n");
	dir_write_text("b.obj", "v -0.2 -0.0002 -0.2\nv 0.2 -0.0002 -0.2\nv 0 -0.0002 0.3\nf 1 3 2\n");
	dir_write_text("base.scene", BASE);
	return 0;
}

/* The state hash of `drape CMD` with --summary json, which must exit 0. */
static void
hash_of(const char *cmd, char hash[17])
{
	char args[2000];
	struct result r;
	struct jval rec;
	const char *why;
	size_t at;
	const struct jval *h;

	snprintf(args, sizeof args, "run --summary json %s", cmd);
	drape(&r, args);
	if (r.status != 0)
		fail_msg("drape %s: exit %d: %s", args, r.status, r.err);
	if (json_parse(r.out, &rec, &why, &at) != 0)
		fail_msg("not JSON: %s", why);
	h = json_get(&rec, "state_hash");
	assert_non_null(h);
	snprintf(hash, 17, "%s", h->s);
	json_free(&rec);
}

/* --set SET on the base scene runs as the scene TEXT does; changed: and
 * not as the base scene does. */
static void
same_as_file(const char *set, const char *text, bool changed)
{
	char args[1200], a[17], b[17], base[17];

	snprintf(args, sizeof args, "--set '%s' '%s/base.scene'", set, dir);
	hash_of(args, a);
	dir_write_text("edited.scene", text);
	snprintf(args, sizeof args, "'%s/edited.scene'", dir);
	hash_of(args, b);
	if (strcmp(a, b) != 0)
		fail_msg("--set %s: hash %s; the file saying so: %s", set, a, b);
	snprintf(args, sizeof args, "'%s/base.scene'", dir);
	hash_of(args, base);
	if (changed && strcmp(a, base) == 0)
		fail_msg("--set %s changed nothing (hash %s)", set, a);
	print_message("--set %s: hash %s, as the file saying so%s\n", set, a,
	    changed ? ", not the scene's" : "");
}

/* `drape CMD` with the one --set SET on the base scene exits 2, says
 * "--set SET: " and then WANT, and runs nothing. */
static void
refused(const char *cmd, const char *set, const char *want)
{
	char args[1200], head[600];
	struct result r;

	snprintf(args, sizeof args, "%s --set '%s' '%s/base.scene'", cmd, set, dir);
	drape(&r, args);
	snprintf(head, sizeof head, "--set %s: ", set);
	if (r.status != 2 || strstr(r.err, want) == NULL ||
	    (strstr(r.err, head) == NULL && strstr(r.err, "--set '") == NULL) ||
	    ((strcmp(cmd, "run --headless") == 0 || strcmp(cmd, "check") == 0) &&
	    r.out[0] != '\0'))
		fail_msg("drape %s: exit %d, stderr '%s', stdout '%.60s'; expected 2 and '%s'",
		    args, r.status, r.err, r.out, want);
	print_message("refused: %s", r.err);
}

static void
number_with_unit(void **state)
{
	(void)state;
	same_as_file("cloth.bending_warp=40 uN*m", "[simulation]\nduration = 10 ms\n[cloth]\n"
	    "nodes = 5 5\nspacing = 10 mm\norigin = -0.02 0 -0.02 m\nweight = 100 g/m2\n"
	    "thickness = 0.3 mm\nmodulus_warp = 1 MPa\nmodulus_weft = 1 MPa\nshear_modulus = 0\n"
	    "bending_warp = 40 uN*m\nbending_weft = 1 uN*m\n[pin]\nnodes = 0 *\n" PLANES
	    MESH("a.obj") COLLISION, true);
	refused("run --headless", "cloth.bending_warp=4 kg", "bending_warp: expected a bending "
	    "rigidity (N*m, mN*m, uN*m, gf*cm2/cm), got '4 kg' (unknown unit 'kg')");
	refused("run --headless", "cloth.bending_warp=-4 uN*m",
	    "bending_warp: expected a bending rigidity");
	refused("run --headless", "cloth.spacing=0 mm",
	    "spacing: expected a length (m, cm, mm, um) greater than 0, got '0 mm'");
	/* issue 30: a bare number was SI here as in a file (150 kg/m2) */
	refused("run --headless", "cloth.weight=150", "--set cloth.weight=150: weight: expected a "
	    "weight per area (g/m2, gsm, mg/cm2, kg/m2) with its unit, such as 'weight = 150 g/m2'; "
	    "got '150', with no unit");
	refused("snapshot", "cloth.spacing=10", "spacing: expected a length (m, cm, mm, um) with "
	    "its unit, such as 'spacing = 10 mm'; got '10', with no unit");
	refused("check", "plane#2.point=0 -0.5 0", "point: expected 3 numbers and the unit of a "
	    "length (m, cm, mm, um), such as 'point = 0 0.15 0 m'; got '0 -0.5 0', with no unit");
	same_as_file("cloth.bending_warp=0", "[simulation]\nduration = 10 ms\n[cloth]\n"
	    "nodes = 5 5\nspacing = 10 mm\norigin = -0.02 0 -0.02 m\nweight = 100 g/m2\n"
	    "thickness = 0.3 mm\nmodulus_warp = 1 MPa\nmodulus_weft = 1 MPa\nshear_modulus = 0\n"
	    "bending_warp = 0 N*m\nbending_weft = 1 uN*m\n[pin]\nnodes = 0 *\n" PLANES
	    MESH("a.obj") COLLISION, true);
}

static void
selector(void **state)
{
	(void)state;
	same_as_file("pin.nodes=-1 *", "[simulation]\nduration = 10 ms\n[cloth]\nnodes = 5 5\n"
	    "spacing = 10 mm\norigin = -0.02 0 -0.02 m\nweight = 100 g/m2\nthickness = 0.3 mm\n"
	    "modulus_warp = 1 MPa\nmodulus_weft = 1 MPa\nshear_modulus = 0\n"
	    "bending_warp = 1 uN*m\nbending_weft = 1 uN*m\n[pin]\nnodes = -1 *\n" PLANES
	    MESH("a.obj") COLLISION, true);
	refused("run --headless", "pin.nodes=7 0", "nodes: index out of range in '7 0'");
	refused("run --headless", "pin.nodes=0 0 0", "nodes: expected pairs 'I J'");
}

static void
word(void **state)
{
	char a[17], b[17], args[800];

	(void)state;
	same_as_file("collision.broad=seed", L1_16 PLANES MESH("a.obj")
	    "[collision]\nself = on\nbroad = seed\n", false);	/* no contact yet */
	refused("run --headless", "collision.broad=fast",
	    "broad: expected one of seed, grid, brute, bvh, got 'fast'");
	refused("run --headless", "cloth.shape=hexagon", "shape: expected one of square, disc");
	/* a key the section lacks: added to it */
	snprintf(args, sizeof args, "--set simulation.integrator=implicit-euler '%s/base.scene'",
	    dir);
	hash_of(args, a);
	snprintf(args, sizeof args, "--integrator implicit-euler '%s/base.scene'", dir);
	hash_of(args, b);
	assert_string_equal(a, b);
	refused("run --headless", "simulation.integrator=verlet", "integrator: expected rk4, euler, "
	    "symplectic-euler, rk2, dopri5, implicit-euler, fast or bdf2, got 'verlet'");
}

static void
path(void **state)
{
	(void)state;
	same_as_file("mesh.file=b.obj", L1_16 PLANES MESH("b.obj") COLLISION, true);
	refused("run --headless", "mesh.file=nope.obj", "file: ");
	refused("run --headless", "mesh.file=nope.obj", "nope.obj");
}

static void
sections(void **state)
{
	char args[800], a[17], b[17];
	const char *plain = "[simulation]\nduration = 10 ms\n[cloth]\nnodes = 5 5\n"
	    "spacing = 10 mm\norigin = -0.02 0 -0.02 m\nweight = 100 g/m2\nthickness = 0.3 mm\n"
	    "modulus_warp = 1 MPa\nmodulus_weft = 1 MPa\nshear_modulus = 0\n"
	    "bending_warp = 1 uN*m\nbending_weft = 1 uN*m\n" PLANES;

	(void)state;
	/* a repeated section: by its place, and plain only when alone */
	same_as_file("plane#2.friction=0.5", L1_16 "[plane]\npoint = 0 -0.1 0 m\n[plane]\n"
	    "point = 0 -0.0003 0 m\nfriction = 0.5\n" MESH("a.obj") COLLISION, false);
	same_as_file("plane#1.friction=0.2", L1_16 "[plane]\npoint = 0 -0.1 0 m\nfriction = 0.2\n"
	    "[plane]\npoint = 0 -0.0003 0 m\nfriction = 0.1\n" MESH("a.obj") COLLISION, false);
	refused("run --headless", "plane.friction=0.3", "the scene has 2 [plane] sections "
	    "(lines 16, 18); expected plane#1.friction to plane#2.friction");
	refused("run --headless", "plane#3.friction=0.3",
	    "expected plane#1.friction to plane#2.friction");
	same_as_file("mesh.scale=1", L1_16 PLANES "[mesh]\nfile = a.obj\nscale = 1\n" COLLISION,
	    false);
	refused("run --headless", "box.min=0 0 0", "the scene has no [box] section");
	/* a section the scene lacks, which it may have once: added */
	dir_write_text("plain.scene", plain);
	snprintf(args, sizeof args, "--set collision.self=on --set collision.broad=seed "
	    "'%s/plain.scene'", dir);
	hash_of(args, a);
	dir_write_text("plain2.scene", "[simulation]\nduration = 10 ms\n[cloth]\nnodes = 5 5\n"
	    "spacing = 10 mm\norigin = -0.02 0 -0.02 m\nweight = 100 g/m2\nthickness = 0.3 mm\n"
	    "modulus_warp = 1 MPa\nmodulus_weft = 1 MPa\nshear_modulus = 0\n"
	    "bending_warp = 1 uN*m\nbending_weft = 1 uN*m\n" PLANES
	    "[collision]\nself = on\nbroad = seed\n");
	snprintf(args, sizeof args, "'%s/plain2.scene'", dir);
	hash_of(args, b);
	assert_string_equal(a, b);
}

static void
malformed(void **state)
{
	(void)state;
	refused("run --headless", "cloth.spacing", "expected SECTION.KEY=VALUE");
	refused("run --headless", "spacing=1mm", "expected SECTION.KEY=VALUE");
	refused("run --headless", "cloth.spacing=", "expected a value after '='");
	refused("run --headless", "plane#0.friction=1", "after '#'");
	refused("run --headless", "cloth.spacing=1 mm # x", "without '#'");
	refused("run --headless", "cloth.colour=red", "unknown key 'colour' in [cloth]");
	refused("run --headless", "clth.spacing=1mm", "unknown section [clth]");
	refused("run --headless", "cloth#2.spacing=1mm", "the scene has one [cloth] section");
}

static void
twice_and_file_lines(void **state)
{
	char args[900];
	struct result r;
	const char *p;

	(void)state;
	snprintf(args, sizeof args, "run --set cloth.spacing=9mm --set cloth#1.spacing=8mm "
	    "'%s/base.scene'", dir);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "--set cloth#1.spacing=8mm: cloth.spacing is already set "
	    "by --set cloth.spacing=9mm"));
	/* a line added before a bad line of the file: the file's line number */
	p = dir_write_text("bad.scene", L1_16 "[plane]\npoint = 0 -0.1 0 m\nfriction = -1\n");
	snprintf(args, sizeof args, "run --set 'cloth.damping=1 /s' '%s'", p);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	if (strstr(r.err, "bad.scene:18: friction: expected a number of 0 or more") == NULL)
		fail_msg("stderr '%s'; expected bad.scene:18", r.err);
}

static void
check_and_snapshot(void **state)
{
	char args[1200], want[16384];
	struct result r;

	(void)state;
	refused("check", "cloth.bending_warp=4 kg", "bending_warp: expected a bending rigidity "
	    "(N*m, mN*m, uN*m, gf*cm2/cm), got '4 kg' (unknown unit 'kg')");
	refused("check", "cloth.spacing=0mm", "spacing: expected a length");
	refused("check", "nosuch.key=1", "unknown section [nosuch]");
	/* a --set bad for the second scene only: refused before the first
	 * is checked, nothing on stdout (not even the header) */
	dir_write_text("one-plane.scene", L1_16 "[plane]\npoint = 0 -0.1 0 m\n" COLLISION);
	snprintf(args, sizeof args, "check --set plane#2.friction=0.2 '%s/base.scene' "
	    "'%s/one-plane.scene'", dir, dir);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_string_equal(r.out, "");
	if (strstr(r.err, "drape check: --set plane#2.friction=0.2: ") != r.err ||
	    strchr(r.err, '\n') != r.err + strlen(r.err) - 1)
		fail_msg("stderr '%s'; expected one line, drape check: --set plane#2...", r.err);
	/* a scene's own error still comes in its turn, after the header */
	dir_write_text("bad-own.scene", L1_16 "[plane]\npoint = 0 -0.1 0 m\nfriction = -1\n");
	snprintf(args, sizeof args, "check --set collision.broad=seed '%s/bad-own.scene'", dir);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.out, "file\tkind\t"));
	assert_non_null(strstr(r.err, "bad-own.scene:18: friction"));
	snprintf(args, sizeof args, "check --every 1 --set collision.broad=seed '%s/base.scene'",
	    dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "\tscene\t"));
	refused("snapshot", "collision.broad=fast", "broad: expected one of");
	dir_write_text("edited.scene", L1_16 PLANES MESH("b.obj") COLLISION);
	snprintf(args, sizeof args, "snapshot --step 20 --size 40x12 --view side '%s/edited.scene'",
	    dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	snprintf(want, sizeof want, "%s", r.out);
	snprintf(args, sizeof args, "snapshot --step 20 --size 40x12 --view side "
	    "--set mesh.file=b.obj '%s/base.scene'", dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_string_equal(r.out, want);
	/* a replay runs its recorded scene */
	snprintf(args, sizeof args, "run --until 2ms --record '%s/r.drr' '%s/base.scene'", dir, dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	snprintf(args, sizeof args, "snapshot --set collision.broad=seed '%s/r.drr'", dir);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "is a replay, which runs its recorded scene"));
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(number_with_unit),
		cmocka_unit_test(selector),
		cmocka_unit_test(word),
		cmocka_unit_test(path),
		cmocka_unit_test(sections),
		cmocka_unit_test(malformed),
		cmocka_unit_test(twice_and_file_lines),
		cmocka_unit_test(check_and_snapshot),
	};

	return cmocka_run_group_tests(tests, setup_files, teardown);
}
