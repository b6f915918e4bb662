/* test_summary.c: drape run --summary json and csv through the binary. The
 * JSON is read by the strict reader of json.h (written for this test: the
 * suite needs no python3), which is first shown to refuse what RFC 8259
 * refuses. Each text summary line is rebuilt from the record with the text
 * summary's own formats and must equal the line the text summary printed
 * for the same run (all but the wall time and speed lines, which are the
 * clock's); the CSV header is the record's fields in order, its row their
 * values; a blown-up run still prints its record; --set and --resume. */
#include <inttypes.h>

#include "testutil.h"
#include "runbin.h"
#include "json.h"
#include "stats.h"

static void
parse_or_fail(const char *text, struct jval *v)
{
	const char *why;
	size_t at;

	if (json_parse(text, v, &why, &at) != 0)
		fail_msg("not JSON: %s at byte %zu of '%.200s'", why, at, text);
}

static void
strict_reader(void **state)
{
	static const char *const bad[] = {
		"", "{", "{\"a\":1,}", "[1,]", "{'a':1}", "{\"a\":NaN}", "{\"a\":01}",
		"{\"a\":1.}", "{\"a\":.5}", "{\"a\":1e}", "{\"a\":-}", "{\"a\":1}x",
		"{\"a\":1}{}", "{\"a\":1,\"a\":2}", "{\"a\":\"x\ty\"}", "{\"a\":\"\\x\"}",
		"{\"a\":\"\\ud800\"}", "{\"a\":\"\\udc00\"}", "{\"a\":\"\xff\"}",
		"{\"a\":\"\xc0\xaf\"}", "{\"a\":tru}", "{\"a\" 1}", "{1:2}", "[1 2]",
		"{\"a\":+1}", "{\"a\":Infinity}", "/* c */ {}",
	};
	struct jval v;
	const char *why;
	const struct jval *x;
	size_t i, at;

	(void)state;
	for (i = 0; i < sizeof bad / sizeof bad[0]; i++)
		if (json_parse(bad[i], &v, &why, &at) == 0)
			fail_msg("the reader took '%s'", bad[i]);
	parse_or_fail(" {\"a\": {\"b\": [1, -2.5e-3, true, false, null]}, \"s\": "
	    "\"q\\\"\\\\\\/\\n\\u00e9\\ud83d\\ude00\xc3\xa9\", \"z\": 0} ", &v);
	x = json_get(&v, "a.b");
	assert_non_null(x);
	assert_int_equal(x->t, J_ARR);
	assert_int_equal(x->n, 5);
	assert_double_equal(x->items[1].num, -2.5e-3, 0);
	x = json_get(&v, "s");
	assert_string_equal(x->s, "q\"\\/\n\xc3\xa9\xf0\x9f\x98\x80\xc3\xa9");
	assert_null(json_get(&v, "a.c"));
	json_free(&v);
}

/* ---- the text summary, rebuilt from the record ---- */

static const struct jval *
get(const struct jval *rec, const char *path)
{
	const struct jval *v = json_get(rec, path);

	if (v == NULL)
		fail_msg("the record has no %s", path);
	return v;
}

static double
num(const struct jval *rec, const char *path)
{
	const struct jval *v = get(rec, path);

	if (v->t != J_NUM)
		fail_msg("%s is not a number", path);
	return v->num;
}

static long
lnum(const struct jval *rec, const char *path)
{
	double x = num(rec, path);

	if (x != (double)(long)x)
		fail_msg("%s = %.17g is not a whole number", path, x);
	return (long)x;
}

static const char *
text(const struct jval *rec, const char *path)
{
	const struct jval *v = get(rec, path);

	if (v->t != J_STR)
		fail_msg("%s is not a string", path);
	return v->s;
}

static bool
truth(const struct jval *rec, const char *path)
{
	const struct jval *v = get(rec, path);

	if (v->t != J_BOOL)
		fail_msg("%s is not true or false", path);
	return v->b;
}

static bool
is_null(const struct jval *rec, const char *path)
{
	return get(rec, path)->t == J_NULL;
}

/* Appends a line to buf. */
static void
line(char *buf, size_t len, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

static void
line(char *buf, size_t len, const char *fmt, ...)
{
	size_t n = strlen(buf);
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(buf + n, len - n, fmt, ap);
	va_end(ap);
}

static long
stat_total(const struct jval *rec, int k)
{
	char path[80];

	snprintf(path, sizeof path, "collisions.%s", stat_field[k].name);
	return lnum(rec, path);
}

/* The text summary as the record says it, but the wall time and speed. */
static void
rebuild(const struct jval *rec, char *buf, size_t len)
{
	static const char *const way[2] = { "warp", "weft" };
	const char *integ = text(rec, "integrator.name");
	long steps = lnum(rec, "integrator.steps");
	double st = steps > 0 ? (double)steps : 1;
	char path[80];
	int d, k;

	buf[0] = '\0';
	line(buf, len, "scene        %s (%s)\n", text(rec, "scene.name"), text(rec, "scene.path"));
	if (strcmp(text(rec, "network.shape"), "square") == 0)
		line(buf, len, "network      %ld x %ld nodes", lnum(rec, "network.nu"),
		    lnum(rec, "network.nv"));
	else
		line(buf, len, "network      %s of %ld nodes in a %ld x %ld grid",
		    text(rec, "network.shape"), lnum(rec, "network.nodes"), lnum(rec, "network.nu"),
		    lnum(rec, "network.nv"));
	line(buf, len, ", %ld springs, %ld shear corners, %ld bending hinges, %ld triangles\n",
	    lnum(rec, "network.springs"), lnum(rec, "network.shear_corners"),
	    lnum(rec, "network.hinges"), lnum(rec, "network.triangles"));
	for (d = 0; d < 2; d++) {
		snprintf(path, sizeof path, "bending.%s_derived", way[d]);
		line(buf, len, "bending %s %.4g N*m (%s)\n", way[d],
		    num(rec, d == 0 ? "bending.warp" : "bending.weft"),
		    truth(rec, path) ? "derived: modulus*thickness^3/12" : "given");
	}
	line(buf, len, "integrator   %s, dt %.4g s (%s; omega <= %.4g rad/s)\n", integ,
	    num(rec, "integrator.dt"), truth(rec, "integrator.dt_auto") ? "auto" : "given",
	    num(rec, "integrator.omega"));
	if (strcmp(integ, "implicit-euler") == 0) {
		long solves = lnum(rec, "integrator.solves");

		assert_true(is_null(rec, "integrator.force_evaluations"));
		line(buf, len, "steps        %ld (%ld solves, %.1f CG iterations each, %ld "
		    "unconverged", steps, solves, solves > 0 ?
		    (double)lnum(rec, "integrator.cg_iterations") / (double)solves : 0.0,
		    lnum(rec, "integrator.unconverged"));
	} else if (strcmp(integ, "fast") == 0) {
		long sub = lnum(rec, "integrator.substeps");

		assert_true(is_null(rec, "integrator.force_evaluations"));
		assert_true(is_null(rec, "integrator.solves"));
		line(buf, len, "steps        %ld (%ld substeps of %.3g s at most, %ld contact "
		    "windows", steps, sub, sub > 0 ? num(rec, "time.simulated") / (double)sub : 0.0,
		    lnum(rec, "integrator.windows"));
		assert_true(lnum(rec, "integrator.windows") >= steps);
	} else {
		assert_true(is_null(rec, "integrator.solves"));
		line(buf, len, "steps        %ld (%ld force evaluations", steps,
		    lnum(rec, "integrator.force_evaluations"));
	}
	if (strcmp(integ, "fast") != 0) {
		assert_true(is_null(rec, "integrator.substeps"));
		assert_true(is_null(rec, "integrator.windows"));
	}
	/* the search for contacts inside the step: fast's and bdf2's alone */
	if (truth(rec, "collisions.enabled") &&
	    (strcmp(integ, "fast") == 0 || strcmp(integ, "bdf2") == 0))
		assert_true(num(rec, "time.contacts") > 0 &&
		    num(rec, "time.contacts") < num(rec, "time.stepping"));
	else
		assert_true(is_null(rec, "time.contacts"));
	if (strcmp(integ, "dopri5") == 0)
		line(buf, len, ", %ld steps rejected", lnum(rec, "integrator.rejected"));
	else
		assert_true(is_null(rec, "integrator.rejected"));
	line(buf, len, ")\n");
	line(buf, len, "simulated    %.6g s\n", num(rec, "time.simulated"));
	line(buf, len, "energy       %.6e J (kinetic %.4e, gravity %.4e, stretch %.4e, shear %.4e, "
	    "bend %.4e, load %.4e)\n", num(rec, "energy.total"), num(rec, "energy.kinetic"),
	    num(rec, "energy.gravity"), num(rec, "energy.stretch"), num(rec, "energy.shear"),
	    num(rec, "energy.bend"), num(rec, "energy.load"));
	if (truth(rec, "collisions.enabled")) {
		line(buf, len, "collisions   broad %s, narrow %s, position %s, self %s, cell %.4g m\n",
		    text(rec, "collisions.broad"), text(rec, "collisions.narrow"),
		    text(rec, "collisions.position"), truth(rec, "collisions.self") ? "on" : "off",
		    num(rec, "collisions.cell"));
		line(buf, len, "per step     %.1f node pairs, %.1f vertex-triangle and %.1f "
		    "edge-edge pairs, %.1f narrow tests\n",
		    (double)stat_total(rec, STAT_NODE_PAIRS) / st,
		    (double)stat_total(rec, STAT_VT_PAIRS) / st,
		    (double)stat_total(rec, STAT_EE_PAIRS) / st,
		    (double)stat_total(rec, STAT_NARROW_TESTS) / st);
		line(buf, len, "contacts     ");
		for (k = 0; k < CONTACT_NTYPES; k++)
			line(buf, len, "%s%s %ld", k ? ", " : "", stat_field[STAT_CONTACTS + k].label,
			    stat_total(rec, STAT_CONTACTS + k));
		line(buf, len, "\n");
		line(buf, len, "corrections  %ld (%ld put back to step k; at most %ld passes in a "
		    "step; %ld steps unresolved)\n", stat_total(rec, STAT_CORRECTIONS),
		    stat_total(rec, STAT_FROZEN), stat_total(rec, STAT_PASSES),
		    stat_total(rec, STAT_UNRESOLVED));
		if (lnum(rec, "locks.node_steps") > 0)
			line(buf, len, "locked       %ld node-steps, at most %ld nodes in a step, "
			    "longest %ld steps in a row (%.4g s), kinetic energy of locked nodes at "
			    "most %.4e J\n", lnum(rec, "locks.node_steps"), lnum(rec, "locks.most"),
			    lnum(rec, "locks.longest"),
			    (double)lnum(rec, "locks.longest") * num(rec, "integrator.dt"),
			    num(rec, "locks.kinetic_most"));
		if (!is_null(rec, "hash.items")) {
			line(buf, len, "hash         per fill %.1f items, %.1f cubes (%.1f with >= 2), "
			    "load %.3f, probes mean %.3f max %ld; %ld fills in %ld steps\n",
			    num(rec, "hash.items"), num(rec, "hash.cubes"), num(rec, "hash.shared"),
			    num(rec, "hash.load"), num(rec, "hash.probe_mean"),
			    lnum(rec, "hash.probe_max"), stat_total(rec, STAT_FILLS), steps);
			line(buf, len, "hash histogram");
			for (k = 0; k < HASH_HIST; k++) {
				snprintf(path, sizeof path, "hash.cubes_with_%d%s", k + 1,
				    k + 1 == HASH_HIST ? "_or_more" : "");
				line(buf, len, " %d%s:%ld", k + 1, k + 1 == HASH_HIST ? "+" : "",
				    lnum(rec, path));
			}
			line(buf, len, " (cubes by items, all fills)\n");
		}
	} else {
		assert_true(is_null(rec, "collisions.vt_pairs"));
	}
	if (!is_null(rec, "cusick.coefficient"))
		line(buf, len, "drape coefficient %.4f (shadow %.6f m2, support disc %.6f m2, flat "
		    "specimen %.6f m2; %.2g mm raster)\n", num(rec, "cusick.coefficient"),
		    num(rec, "cusick.shadow_area"), num(rec, "cusick.support_area"),
		    num(rec, "cusick.specimen_area"), num(rec, "cusick.raster") * 1e3);
	if (!is_null(rec, "cusick.coefficient") && !is_null(rec, "cusick.folds"))
		line(buf, len, "drape folds  %.0f\n", num(rec, "cusick.folds"));
	else if (!is_null(rec, "cusick.coefficient"))
		line(buf, len, "drape folds  not counted (the outline does not go round the "
		    "disc)\n");
	else
		assert_true(is_null(rec, "cusick.folds"));
	line(buf, len, "state hash   %s\n", text(rec, "state_hash"));
}

/* The text summary without its wall time and speed lines. */
static void
strip_clock(const char *in, char *out, size_t len)
{
	const char *p = in;

	out[0] = '\0';
	while (*p != '\0') {
		const char *nl = strchr(p, '\n');
		size_t n = nl != NULL ? (size_t)(nl - p + 1) : strlen(p);

		if (strncmp(p, "wall time ", 10) != 0 && strncmp(p, "speed ", 6) != 0 &&
		    strlen(out) + n < len)
			strncat(out, p, n);
		p += n;
	}
}

static void
same_as_text(const char *what, const char *args)
{
	char cmd[1200], want[16384], got[16384];
	const char *q;
	struct result r;
	struct jval rec;
	int lines = 0;

	snprintf(cmd, sizeof cmd, "run --headless %s", args);
	drape(&r, cmd);
	assert_int_equal(r.status, 0);
	strip_clock(r.out, want, sizeof want);
	snprintf(cmd, sizeof cmd, "run --summary json %s", args);
	drape(&r, cmd);
	assert_int_equal(r.status, 0);
	parse_or_fail(r.out, &rec);
	assert_int_equal(lnum(&rec, "exit_status"), 0);
	assert_string_equal(text(&rec, "outcome"), "completed");
	assert_true(is_null(&rec, "failure.message"));
	rebuild(&rec, got, sizeof got);
	if (strcmp(want, got) != 0)
		fail_msg("%s: the record gives\n%s\nthe text summary says\n%s", what, got, want);
	for (q = want; *q != '\0'; q++)
		lines += *q == '\n';
	print_message("%s: the %d lines of the text summary (but wall time and speed) "
	    "rebuilt from the record\n", what, lines);
	json_free(&rec);
}

#define CLOTH "spacing = 10 mm\nweight = 100 g/m2\nthickness = 0.3 mm\n" \
	"modulus_warp = 1 MPa\nmodulus_weft = 1 MPa\nshear_modulus = 0\n" \
	"bending_warp = 1 uN*m\nbending_weft = derived\n"
#define CUSICK "[simulation]\nduration = 30 ms\n[cloth]\nnodes = 11 11\nshape = disc\n" \
	"origin = -0.05 0.102 -0.05 m\n" CLOTH "[disc]\ncentre = 0 0.1 0 m\nradius = 3 cm\n" \
	"height = 0.1 m\n[collision]\nself = on\nbroad = seed\n"

static void
json_equals_text(void **state)
{
	char args[900];

	(void)state;
	snprintf(args, sizeof args, "'%s'", dir_write_text("cusick.scene", CUSICK));
	same_as_text("Cusick disc, seed hash, rk4", args);
	snprintf(args, sizeof args, "--integrator implicit-euler '%s'",
	    dir_write_text("cusick.scene", CUSICK));
	same_as_text("Cusick disc, implicit-euler", args);
	snprintf(args, sizeof args, "--integrator fast '%s'", dir_write_text("cusick.scene", CUSICK));
	same_as_text("Cusick disc, fast", args);
	same_as_text("tablecloth as shipped (fast, bvh), 15 ms", "--until 15ms " TOP_SRCDIR "/scenes/tablecloth.scene");
	/* the cloth reaches the box at 0.09 s: the keep policy locks nodes */
	same_as_text("tablecloth, the chapter's keep, locked nodes",
	    "--until 0.1 --set collision.broad=seed --set collision.narrow=seed "
	    "--set collision.position=keep " TOP_SRCDIR "/scenes/tablecloth.scene");
	same_as_text("cantilever, dopri5, no collisions",
	    "--until 2ms --integrator dopri5 " TOP_SRCDIR "/scenes/cantilever.scene");
}

/* The wall time line of a method that finds its contacts inside the step
 * gives that search's share beside the collision stages'; others' not. */
static void
wall_time_shows_the_contacts(void **state)
{
	struct result r;
	struct jval rec;
	const char *w;

	(void)state;
	drape(&r, "run --headless --until 15ms " TOP_SRCDIR "/scenes/tablecloth.scene");
	assert_int_equal(r.status, 0);
	w = strstr(r.out, "\nwall time ");
	assert_non_null(w);
	assert_non_null(strstr(w, " s; contacts found in the steps "));
	drape(&r, "run --headless --until 2ms --integrator rk4 " TOP_SRCDIR "/scenes/tablecloth.scene");
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "\nwall time "));
	assert_null(strstr(r.out, "contacts found in the steps"));
	/* bdf2 finds them once a step: its record has the time too */
	drape(&r, "run --summary json --until 20ms --integrator bdf2 " TOP_SRCDIR
	    "/scenes/tablecloth.scene");
	assert_int_equal(r.status, 0);
	parse_or_fail(r.out, &rec);
	assert_true(num(&rec, "time.contacts") > 0 &&
	    num(&rec, "time.contacts") < num(&rec, "time.stepping"));
	json_free(&rec);
}

/* Splits a CSV line into fields (quotes, doubled quotes; no line breaks). */
static size_t
split_csv(const char *s, char fields[][600], size_t max)
{
	size_t n = 0, len = 0;
	bool q = false;

	for (;; s++) {
		if (n >= max)
			fail_msg("more than %zu CSV fields", max);
		if (q) {
			if (*s == '\0')
				fail_msg("an unterminated quoted CSV field");
			if (*s == '"' && s[1] == '"')
				fields[n][len++] = *s++;
			else if (*s == '"')
				q = false;
			else
				fields[n][len++] = *s;
		} else if (*s == '"' && len == 0) {
			q = true;
		} else if (*s == ',' || *s == '\0' || *s == '\n') {
			fields[n++][len] = '\0';
			len = 0;
			if (*s != ',')
				return n;
		} else {
			fields[n][len++] = *s;
		}
		if (len >= 599)
			fail_msg("a CSV field too long");
	}
}

/* The record's fields in order, as the CSV names them, with their values
 * as the CSV would show them. */
static size_t
flatten(const struct jval *v, const char *prefix, char names[][600], char values[][600],
    size_t n, size_t max)
{
	size_t k, j;

	for (k = 0; k < v->n; k++) {
		const struct jval *x = &v->items[k];

		if (x->t == J_OBJ) {
			n = flatten(x, v->keys[k], names, values, n, max);
			continue;
		}
		assert_true(n < max);
		snprintf(names[n], 600, "%s%s%s", prefix, *prefix ? "." : "", v->keys[k]);
		values[n][0] = '\0';
		switch (x->t) {
		case J_NULL: break;
		case J_BOOL: snprintf(values[n], 600, "%s", x->b ? "true" : "false"); break;
		case J_NUM: snprintf(values[n], 600, "%.17g", x->num); break;
		case J_STR: snprintf(values[n], 600, "%s", x->s); break;
		case J_ARR:
			for (j = 0; j < x->n; j++) {
				strcat(values[n], j ? ";" : "");
				strcat(values[n], x->items[j].s);
			}
			break;
		case J_OBJ: break;
		}
		n++;
	}
	return n;
}

static char hnames[200][600], hrow[200][600], jnames[200][600], jvalues[200][600];

static void
csv_equals_json(void **state)
{
	char args[900];
	const char *scene = dir_write_text("cusick.scene", CUSICK);
	struct result r;
	struct jval rec;
	const char *nl;
	size_t nh, nr, nj, k;

	(void)state;
	snprintf(args, sizeof args, "run --summary csv --set 'cloth.bending_warp=2 uN*m' "
	    "--set collision.broad=grid '%s'", scene);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	nl = strchr(r.out, '\n');
	assert_non_null(nl);
	assert_non_null(strchr(nl + 1, '\n'));
	assert_string_equal(strchr(nl + 1, '\n'), "\n");	/* two lines */
	nh = split_csv(r.out, hnames, 200);
	nr = split_csv(nl + 1, hrow, 200);
	assert_int_equal(nh, nr);
	snprintf(args, sizeof args, "run --summary json --set 'cloth.bending_warp=2 uN*m' "
	    "--set collision.broad=grid '%s'", scene);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	parse_or_fail(r.out, &rec);
	nj = flatten(&rec, "", jnames, jvalues, 0, 200);
	assert_int_equal(nj, nh);
	for (k = 0; k < nh; k++) {
		assert_string_equal(hnames[k], jnames[k]);
		if (strncmp(hnames[k], "time.", 5) == 0)
			continue;	/* the clock's */
		if (strchr("-0123456789", hrow[k][0]) != NULL && hrow[k][0] != '\0' &&
		    strspn(hrow[k], "-+.0123456789e") == strlen(hrow[k]))
			assert_double_equal(strtod(hrow[k], NULL), strtod(jvalues[k], NULL), 0);
		else if (strcmp(hrow[k], jvalues[k]) != 0)
			fail_msg("%s: CSV '%s', JSON '%s'", hnames[k], hrow[k], jvalues[k]);
	}
	print_message("CSV: %zu fields, the JSON record's in order\n", nh);
	/* the collision counters are the statistics table's, every one */
	for (k = 0; k < STAT_COUNT; k++) {
		char path[80];

		snprintf(path, sizeof path, "collisions.%s", stat_field[k].name);
		assert_non_null(json_get(&rec, path));
	}
	assert_int_equal(get(&rec, "scene.overrides")->n, 2);
	assert_string_equal(get(&rec, "scene.overrides")->items[0].s, "cloth.bending_warp=2 uN*m");
	assert_double_equal(num(&rec, "bending.warp"), 2e-6, 1e-20);
	json_free(&rec);
}

static void
blowup_still_prints_its_record(void **state)
{
	char args[900];
	const char *scene = dir_write_text("stiff.scene", "[simulation]\nduration = 1 s\ndt = 5 ms\n"
	    "[cloth]\nnodes = 6 6\nspacing = 1 cm\nweight = 100 g/m2\nthickness = 0.3 mm\n"
	    "modulus_warp = 30 MPa\nmodulus_weft = 30 MPa\nshear_modulus = 0\n"
	    "bending_warp = 0\nbending_weft = 0\n[pin]\nnodes = 0 0\n");
	struct result r;
	struct jval rec;

	(void)state;
	snprintf(args, sizeof args, "run --summary json '%s'", scene);
	drape(&r, args);
	assert_int_equal(r.status, 3);
	assert_non_null(strstr(r.err, "blow-up at step"));
	parse_or_fail(r.out, &rec);
	assert_int_equal(lnum(&rec, "exit_status"), 3);
	assert_string_equal(text(&rec, "outcome"), "blowup");
	assert_true(lnum(&rec, "failure.step") > 0);
	assert_true(lnum(&rec, "failure.node") >= 0);
	assert_non_null(strstr(text(&rec, "failure.message"), "blow-up at step"));
	assert_non_null(strstr(r.err, text(&rec, "failure.message")));
	/* the state is the last good step's */
	assert_int_equal(lnum(&rec, "integrator.steps"), lnum(&rec, "failure.step"));
	json_free(&rec);
	snprintf(args, sizeof args, "run --summary csv '%s'", scene);
	drape(&r, args);
	assert_int_equal(r.status, 3);
	assert_non_null(strstr(r.out, ",blowup,"));
	/* a bad scene: no run, no record, exit 2 */
	snprintf(args, sizeof args, "run --summary json --set cloth.spacing=0 '%s'", scene);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_string_equal(r.out, "");
	drape(&r, "run --summary yaml x.scene");
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "--summary 'yaml': expected text, json or csv"));
}

static void
resume_keeps_stdout_for_the_record(void **state)
{
	char args[1200], drr[700];
	const char *scene = dir_write_text("cusick.scene", CUSICK);
	struct result r;
	struct jval rec;
	char hash[17];

	(void)state;
	snprintf(drr, sizeof drr, "%s/s.drr", dir);
	snprintf(args, sizeof args, "run --summary json --set 'cloth.bending_warp=2 uN*m' "
	    "--record '%s' --keyframe-every 20 '%s'", drr, scene);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	parse_or_fail(r.out, &rec);
	snprintf(hash, sizeof hash, "%s", text(&rec, "state_hash"));
	json_free(&rec);
	snprintf(args, sizeof args, "run --summary json --resume '%s@100'", drr);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.err, "resumed      from"));
	parse_or_fail(r.out, &rec);
	assert_string_equal(text(&rec, "state_hash"), hash);	/* the text that was run */
	json_free(&rec);
	snprintf(args, sizeof args, "run --resume '%s' --set collision.broad=seed", drr);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "--set 'collision.broad=seed': --resume runs the recorded"));
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(strict_reader),
		cmocka_unit_test(json_equals_text),
		cmocka_unit_test(wall_time_shows_the_contacts),
		cmocka_unit_test(csv_equals_json),
		cmocka_unit_test(blowup_still_prints_its_record),
		cmocka_unit_test(resume_keeps_stdout_for_the_record),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
