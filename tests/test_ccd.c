/* test_ccd.c: the continuous tests on hand-built cases, on contacts built
 * to be exact in double arithmetic (never missed, toi never late), and
 * `drape ccd` on the benchmark queries and on malformed files. */
#include <sys/wait.h>
#include <unistd.h>

#include "testutil.h"
#include "runbin.h"
#include "ccd.h"

#define QUERIES TOP_SRCDIR "/tests/data/ccd-sample-queries/unit-tests/"

/* The unit triangle in z = 0, still; the vertex moves from p to q. */
static int
vf(vec3 p, vec3 q, double eta, double *toi)
{
	vec3 x0[4] = { p, v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0) };
	vec3 x1[4] = { q, v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0) };

	return ccd_vertex_face(x0, x1, eta, toi);
}

/* Edge a from (0,0,0) to (1,0,0), still; edge b moves from b0-b1 to c0-c1. */
static int
ee(vec3 b0, vec3 b1, vec3 c0, vec3 c1, double *toi)
{
	vec3 x0[4] = { v3(0, 0, 0), v3(1, 0, 0), b0, b1 };
	vec3 x1[4] = { v3(0, 0, 0), v3(1, 0, 0), c0, c1 };

	return ccd_edge_edge(x0, x1, 0, toi);
}

static void
through_face(void **state)
{
	double toi = -1;

	(void)state;
	assert_int_equal(vf(v3(0.2, 0.2, 1), v3(0.2, 0.2, -1), 0, &toi), 1);
	assert_true(toi <= 0.5 && toi > 0.5 - 1e-6);
	/* the triangle moving onto a still vertex instead */
	{
		vec3 x0[4] = { v3(0.3, 0.3, 0), v3(0, 0, -1), v3(1, 0, -1), v3(0, 1, -1) };
		vec3 x1[4] = { v3(0.3, 0.3, 0), v3(0, 0, 3), v3(1, 0, 3), v3(0, 1, 3) };

		assert_int_equal(ccd_vertex_face(x0, x1, 0, &toi), 1);
		assert_true(toi <= 0.25 && toi > 0.25 - 1e-6);
	}
	/* NULL toi is allowed */
	assert_int_equal(vf(v3(0.2, 0.2, 1), v3(0.2, 0.2, -1), 0, NULL), 1);
}

static void
near_miss_outside_edge(void **state)
{
	double d = 1e-6;

	(void)state;
	/* across the plane just outside, and just inside, the edge x + y = 1 */
	assert_int_equal(vf(v3(0.5 + d, 0.5, 1), v3(0.5 + d, 0.5, -1), 0, NULL), 0);
	assert_int_equal(vf(v3(0.5 - d, 0.5, 1), v3(0.5 - d, 0.5, -1), 0, NULL), 1);
	/* outside edge y = 0, moving obliquely */
	assert_int_equal(vf(v3(0.2, -d, 1), v3(0.4, -d, -1), 0, NULL), 0);
	/* stops just short of the face */
	assert_int_equal(vf(v3(0.2, 0.2, 1), v3(0.2, 0.2, d), 0, NULL), 0);
}

static void
contact_at_the_ends(void **state)
{
	double toi = -1;

	(void)state;
	assert_int_equal(vf(v3(0.25, 0.25, 1), v3(0.25, 0.25, 0), 0, &toi), 1);
	assert_true(toi <= 1 && toi > 1 - 1e-6);
	assert_int_equal(vf(v3(0.5, 0, 1), v3(0.5, 0, 0), 0, NULL), 1);	/* on an edge */
	assert_int_equal(vf(v3(1, 0, 1), v3(1, 0, 0), 0, NULL), 1);	/* on a vertex */
	assert_int_equal(vf(v3(0.25, 0.25, 0), v3(0.25, 0.25, 1), 0, &toi), 1);
	assert_double_equal(toi, 0, 0);
	/* two edges meeting at an end point at t = 1 */
	assert_int_equal(ee(v3(1, 1, 0), v3(1, 2, 0), v3(1, 0, 0), v3(1, 1, 0), &toi), 1);
	assert_true(toi <= 1);
}

static void
coplanar_sliding(void **state)
{
	double toi = -1;

	(void)state;
	/* in the triangle's plane all step long: f is identically 0 */
	assert_int_equal(vf(v3(-1, 0.25, 0), v3(0.25, 0.25, 0), 0, &toi), 1);
	assert_true(toi <= 0.8 && toi > 0.8 - 1e-6);
	assert_int_equal(vf(v3(-1, -0.5, 0), v3(2, -0.5, 0), 0, NULL), 0);
	assert_int_equal(vf(v3(-1, 0.25, 0), v3(-1e-9, 0.25, 0), 0, NULL), 0);
	assert_int_equal(vf(v3(-1, 0.25, 0), v3(0, 0.25, 0), 0, NULL), 1);
	/* coplanar edges: sliding past the end of a, then across it */
	assert_int_equal(ee(v3(-1, -1, 0), v3(-1, 1, 0), v3(-1e-6, -1, 0), v3(-1e-6, 1, 0), NULL),
	    0);
	assert_int_equal(ee(v3(0.5, 1, 0), v3(0.5, 2, 0), v3(0.5, -1, 0), v3(0.5, 0.5, 0), &toi),
	    1);
	assert_true(toi <= 0.5 && toi > 0.5 - 1e-6);
}

static void
crossing_and_parallel_edges(void **state)
{
	double toi = -1;

	(void)state;
	assert_int_equal(ee(v3(0.5, -1, 1), v3(0.5, 1, 1), v3(0.5, -1, -1), v3(0.5, 1, -1), &toi),
	    1);
	assert_true(toi <= 0.5 && toi > 0.5 - 1e-6);
	/* past the end of edge a */
	assert_int_equal(ee(v3(1 + 1e-6, -1, 1), v3(1 + 1e-6, 1, 1), v3(1 + 1e-6, -1, -1),
	    v3(1 + 1e-6, 1, -1), NULL), 0);
	/* parallel edges, always coplanar: overlapping when they meet ... */
	assert_int_equal(ee(v3(0.5, 0, 1), v3(2, 0, 1), v3(0.5, 0, -1), v3(2, 0, -1), &toi), 1);
	assert_true(toi <= 0.5 && toi > 0.5 - 1e-6);
	/* ... not when they pass 0.2 apart, or collinear end to end 0.1 apart */
	assert_int_equal(ee(v3(0, 1, 1), v3(1, 1, 1), v3(0, -1, -0.5), v3(1, -1, -0.5), NULL), 0);
	assert_int_equal(ee(v3(1.5, 0, 1), v3(2.5, 0, 1), v3(0.7, 0, -1), v3(1.7, 0, -1), NULL), 0);
}

static void
degenerate(void **state)
{
	vec3 x0[4] = { v3(0.5, 0.5, -1), v3(0, 0, 0), v3(1, 1, 0), v3(2, 2, 0) };
	vec3 x1[4] = { v3(0.5, 0.5, 1), v3(0, 0, 0), v3(1, 1, 0), v3(2, 2, 0) };
	double toi = -1;

	(void)state;
	/* a collinear triangle the vertex passes through, then misses */
	assert_int_equal(ccd_vertex_face(x0, x1, 0, &toi), 1);
	assert_true(toi <= 0.5);
	x0[0] = v3(5, 0.5, -1);
	x1[0] = v3(5, 0.5, 1);
	assert_int_equal(ccd_vertex_face(x0, x1, 0, NULL), 0);
	/* all three corners at one point */
	x0[0] = v3(0, 0, -1);
	x1[0] = v3(0, 0, 1);
	x0[2] = x0[3] = x1[2] = x1[3] = v3(0, 0, 0);
	assert_int_equal(ccd_vertex_face(x0, x1, 0, NULL), 1);
	/* a zero-length edge through another edge */
	assert_int_equal(ee(v3(0.5, 0, 1), v3(0.5, 0, 1), v3(0.5, 0, -1), v3(0.5, 0, -1), NULL),
	    1);
	/* a still vertex on a still triangle */
	assert_int_equal(vf(v3(0.2, 0.2, 0), v3(0.2, 0.2, 0), 0, NULL), 1);
}

static void
eta_margin(void **state)
{
	double toi = -1;

	(void)state;
	/* resting 0.01 above the face, and passing 0.01 beside an edge */
	assert_int_equal(vf(v3(0.2, 0.2, 0.01), v3(0.2, 0.2, 0.01), 0, NULL), 0);
	assert_int_equal(vf(v3(0.2, 0.2, 0.01), v3(0.2, 0.2, 0.01), 0.02, &toi), 1);
	assert_double_equal(toi, 0, 0);
	assert_int_equal(vf(v3(0.2, 0.2, 0.01), v3(0.2, 0.2, 0.01), 0.005, NULL), 0);
	assert_int_equal(vf(v3(0.2, -0.01, 1), v3(0.2, -0.01, -1), 0.02, NULL), 1);
	assert_int_equal(vf(v3(0.2, -0.01, 1), v3(0.2, -0.01, -1), 0.005, NULL), 0);
}

/* Local state: a test's own generator, xorshift64. */
static int
rnd(uint64_t *s, int lo, int hi)
{
	*s ^= *s << 13;
	*s ^= *s >> 7;
	*s ^= *s << 17;
	return lo + (int)(*s % (uint64_t)(hi - lo + 1));
}

static vec3
rnd_point(uint64_t *s, int big, int flat)
{
	return v3(rnd(s, -big, big), rnd(s, -big, big), flat ? 0 : rnd(s, -big, big));
}

/* Contacts at a known time ts, exact in doubles: integers of up to 28
 * bits (so the cubic and the projections round), weights in sixteenths,
 * ts = 0, 1, 2^-m or 1 - 2^-m, scales 2^-30 .. 2^30, and edge, vertex,
 * coplanar and degenerate cases. Each must be found with toi <= ts. */
static void
exact_contacts_never_missed(void **state)
{
	uint64_t s = 0x9e3779b97f4a7c15u;
	int i, k;

	(void)state;
	for (i = 0; i < 20000; i++) {
		int edges = i & 1, flat = rnd(&s, 0, 4) == 0, m = rnd(&s, 0, 12);
		int w = rnd(&s, 0, 16), w2 = rnd(&s, 0, 16 - w), when = rnd(&s, 0, 3);
		int big = 1 << rnd(&s, 2, 28);
		double sc = ldexp(1, rnd(&s, -30, 30)), ts, toi = -1;
		vec3 p[4], x0[4], x1[4], dp;
		int rigid;

		for (k = 0; k < 4; k++)
			p[k] = rnd_point(&s, big, flat);
		if (rnd(&s, 0, 9) == 0)
			p[3] = v3_sub(v3_scale(p[2], 2), p[1]);	/* collinear */
		if (!edges)	/* the vertex at weights w, w2, 16 - w - w2 */
			p[0] = v3_scale(v3_add(v3_add(v3_scale(p[1], w), v3_scale(p[2], w2)),
			    v3_scale(p[3], 16 - w - w2)), 1.0 / 16);
		else		/* edge b's midpoint on edge a */
			p[3] = v3_sub(v3_scale(v3_add(v3_scale(p[0], w), v3_scale(p[1], 16 - w)),
			    2.0 / 16), p[2]);
		ts = when == 0 ? 0 : when == 1 ? 1 : when == 2 ? ldexp(1, -m) : 1 - ldexp(1, -m);
		dp = rnd_point(&s, big, flat);
		rigid = rnd(&s, 0, 2);	/* 1: the second primitive translates, 2: all do */
		for (k = 0; k < 4; k++) {
			vec3 r = rnd_point(&s, big, flat), far;

			if (rigid > (k < 1 + edges))
				r = v3_add(p[k], dp);
			far = v3_add(r, v3_scale(v3_sub(p[k], r), ldexp(1, m)));

			x0[k] = v3_scale(when == 0 ? p[k] : when == 1 ? r : when == 2 ? r : far, sc);
			x1[k] = v3_scale(when == 0 ? r : when == 1 ? p[k] : when == 2 ? far : r, sc);
		}
		if ((edges ? ccd_edge_edge(x0, x1, 0, &toi) : ccd_vertex_face(x0, x1, 0, &toi)) != 1 ||
		    !(toi >= 0 && toi <= ts))
			fail_msg("case %d (%s): missed, or toi %.17g after %.17g", i,
			    edges ? "edge-edge" : "vertex-face", toi, ts);
	}
}

/* ---- the binary ---- */


#define FILES QUERIES "vertex-face/data_0_0.csv " QUERIES "vertex-face/data_0_1.csv " \
	QUERIES "edge-edge/data_0_0.csv " QUERIES "edge-edge/data_0_1.csv"

static void
benchmark_queries(void **state)
{
	static const struct { const char *name; long n, truth; } expect[4] = {
		{ "vertex-face/data_0_0.csv", 125, 35 }, { "vertex-face/data_0_1.csv", 125, 89 },
		{ "edge-edge/data_0_0.csv", 54, 21 }, { "edge-edge/data_0_1.csv", 20, 15 },
	};
	struct result r;
	char *line, *save = NULL;
	int i = 0;

	(void)state;
	drape(&r, "ccd --method ccd " FILES);
	assert_int_equal(r.status, 0);
	print_message("%s", r.out);
	line = strtok_r(r.out, "\n", &save);
	assert_non_null(line);
	assert_string_equal(line, "file\tmethod\tqueries\tpositives\ttrue_pos\tfalse_neg\t"
	    "false_pos\tqueries_per_s");
	while ((line = strtok_r(NULL, "\n", &save)) != NULL) {
		char file[1024], method[16];
		long n, pos, tp, fn, fp;
		double rate;

		assert_true(i < 4);
		if (sscanf(line, "%1023s %15s %ld %ld %ld %ld %ld %lf", file, method, &n, &pos, &tp,
		    &fn, &fp, &rate) != 8)
			fail_msg("cannot read '%s'", line);
		assert_non_null(strstr(file, expect[i].name));
		assert_string_equal(method, "ccd");
		assert_int_equal(n, expect[i].n);
		assert_int_equal(fn, 0);
		assert_int_equal(tp + fn, expect[i].truth);
		assert_int_equal(pos, tp + fp);
		assert_true(rate > 0);
		i++;
	}
	assert_int_equal(i, 4);
	/* the chapter's test: figures shown, not asserted */
	drape(&r, "ccd --method seed " FILES);
	assert_int_equal(r.status, 0);
	print_message("%s%s", r.out, r.err);
	assert_non_null(strstr(r.out, "edge-edge/data_0_0.csv\tseed\t54\tn/a"));
}

#define ROW "1,2,3,4,-5,8,1\n"
#define ROWS4 ROW ROW ROW ROW

static void
malformed_files(void **state)
{
	static const struct { const char *text; int line; const char *expect; } bad[] = {
		{ ROW ROW "1,2,x,4,5,8,1\n" ROW ROWS4, 3, "expected 7 integers" },
		{ ROW ROW ROW ROW "1,2,3,0,5,8,1\n" ROW ROW ROW, 5, "denominator other than 0" },
		{ ROWS4 ROW ROW ROW, 7, "expected 8 rows per query" },
		{ ROWS4 ROWS4 ROW "1,2,3,4,5,8\n", 10, "expected 7 integers" },
		{ ROWS4 ROW ROW ROW "1,2,3,4,5,8,0\n", 8, "expected truth 1" },
		{ ROWS4 ROWS4 "1,2,3,4,5,8,2\n", 9, "expected truth 0 or 1" },
	};
	struct result r;
	char args[900], where[800];
	size_t i;

	(void)state;
	for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		const char *path = dir_write_text("vertex-face-bad.csv", bad[i].text);

		snprintf(args, sizeof args, "ccd '%s'", path);
		drape(&r, args);
		snprintf(where, sizeof where, "%s:%d: ", path, bad[i].line);
		if (r.status != 2 || strstr(r.err, where) == NULL ||
		    strstr(r.err, bad[i].expect) == NULL || r.out[0] != '\0')
			fail_msg("case %zu: status %d, stderr '%s'; expected 2 and '%s%s'", i,
			    r.status, r.err, where, bad[i].expect);
	}
	/* a good file is read; the kind must be known */
	snprintf(args, sizeof args, "ccd --kind vf '%s'", dir_write_text("q.csv", ROWS4 ROWS4));
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "\tccd\t1\t"));
	snprintf(args, sizeof args, "ccd '%s'", dir_write_text("q.csv", ROWS4 ROWS4));
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "--kind"));
}

static void
options(void **state)
{
	struct result r;

	(void)state;
	drape(&r, "ccd --help");
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "usage: drape ccd"));
	drape(&r, "ccd");
	assert_int_equal(r.status, 2);
	drape(&r, "ccd --method exact " QUERIES "edge-edge/data_0_1.csv");
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "--method 'exact'"));
	drape(&r, "ccd --inside sideways " QUERIES "edge-edge/data_0_1.csv");
	assert_int_equal(r.status, 2);
	drape(&r, "ccd --kind tt " QUERIES "edge-edge/data_0_1.csv");
	assert_int_equal(r.status, 2);
	drape(&r, "ccd --bogus " QUERIES "edge-edge/data_0_1.csv");
	assert_int_equal(r.status, 2);
	drape(&r, "ccd " QUERIES "edge-edge/no-such.csv");
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "no-such.csv: cannot open"));
	assert_string_equal(r.out, "");
	drape(&r, "ccd --method seed --inside crossing " QUERIES "vertex-face/data_0_1.csv");
	assert_int_equal(r.status, 0);
	/* stdout that cannot be written */
	if (access("/dev/full", W_OK) == 0) {
		int st = system("'" DRAPE "' ccd " QUERIES "edge-edge/data_0_1.csv >/dev/full "
		    "2>/dev/null");

		assert_true(st != -1 && WIFEXITED(st));
		assert_int_equal(WEXITSTATUS(st), 1);
	}
}


int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(through_face),
		cmocka_unit_test(near_miss_outside_edge),
		cmocka_unit_test(contact_at_the_ends),
		cmocka_unit_test(coplanar_sliding),
		cmocka_unit_test(crossing_and_parallel_edges),
		cmocka_unit_test(degenerate),
		cmocka_unit_test(eta_margin),
		cmocka_unit_test(exact_contacts_never_missed),
		cmocka_unit_test(benchmark_queries),
		cmocka_unit_test(malformed_files),
		cmocka_unit_test(options),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
