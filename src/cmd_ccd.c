/* cmd_ccd.c: `drape ccd`: runs a narrow-phase test on benchmark queries
 * with exact ground truth (tests/data/ccd-sample-queries/README.md) and
 * counts its misses, false alarms and speed. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ccd.h"
#include "clock.h"
#include "cmd.h"
#include "grow.h"
#include "narrow.h"

#define MIN_TIME 0.05		/* s of timed queries, for a meaningful rate */

enum kind { KIND_UNKNOWN, KIND_VF, KIND_EE };
enum method { METHOD_CCD, METHOD_SEED };

struct query {
	vec3 x0[4], x1[4];	/* in the order of ccd.h */
	int truth;
};

struct qfile {
	const char *path;
	enum kind kind;
	struct query *q;
	size_t n;
};

static void
ccd_usage(FILE *f)
{
	fputs("usage: drape ccd [--method seed|ccd] [--inside angle|crossing] [--kind vf|ee]\n"
	    "                 FILE.csv...\n"
	    "\n"
	    "Runs a narrow-phase test on CCD benchmark queries (8 rows of\n"
	    "xnum,xden,ynum,yden,znum,zden,truth each) and prints, per file,\n"
	    "the queries, positives, true positives, false negatives, false\n"
	    "positives and queries per second. ccd (default) is the conservative\n"
	    "continuous test; seed is the chapter's node-triangle test, with\n"
	    "--inside choosing its angle-sum (default) or crossing test. The kind\n"
	    "is vertex-face or edge-edge as the path says, unless --kind is given.\n", f);
}

/* One row: 7 integers, the numerators and denominators read by strtod
 * (denominators reach 2^66, past long long; a power of two, or an integer
 * below 2^53, converts exactly). Returns a complaint, or NULL. */
static const char *
parse_row(char *line, vec3 *p, int *truth)
{
	double v[7];
	char *s = line, *end;
	int k;

	for (k = 0; k < 7; k++) {
		end = s + (*s == '-' || *s == '+');
		if (*end < '0' || *end > '9')
			return "expected 7 integers xnum,xden,ynum,yden,znum,zden,truth";
		while (*end >= '0' && *end <= '9')
			end++;
		if (*end != (k < 6 ? ',' : '\0'))
			return "expected 7 integers xnum,xden,ynum,yden,znum,zden,truth";
		v[k] = strtod(s, NULL);
		if (!isfinite(v[k]))
			return "expected an integer of at most 308 digits";
		s = end + 1;
	}
	if (v[1] == 0 || v[3] == 0 || v[5] == 0)
		return "expected a denominator other than 0";
	if (v[6] != 0 && v[6] != 1)
		return "expected truth 0 or 1";
	*p = v3(v[0] / v[1], v[2] / v[3], v[4] / v[5]);
	*truth = (int)v[6];
	return NULL;
}

/* Reads a whole file; on error, prints "FILE:LINE: ..." and returns -1. */
static int
load(struct qfile *qf)
{
	FILE *f = fopen(qf->path, "r");
	char *line = NULL;
	size_t cap = 0, nrows = 0, have = 0;
	ssize_t len;
	long lineno = 0;
	int rc = -1;

	if (f == NULL) {
		fprintf(stderr, "drape ccd: %s: cannot open: %s\n", qf->path, strerror(errno));
		return -1;
	}
	while ((len = getline(&line, &cap, f)) != -1) {
		struct query *q;
		const char *why;
		vec3 p;
		int truth, r;

		lineno++;
		while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r'))
			line[--len] = '\0';
		if (len == 0)
			continue;
		if ((why = parse_row(line, &p, &truth)) != NULL) {
			fprintf(stderr, "%s:%ld: %s\n", qf->path, lineno, why);
			goto out;
		}
		if (grow_array((void **)&qf->q, &have, qf->n + 1, sizeof *qf->q) != 0) {
			fprintf(stderr, "drape ccd: %s: out of memory\n", qf->path);
			goto out;
		}
		q = &qf->q[qf->n];
		r = (int)(nrows % 8);
		if (r == 0)
			q->truth = truth;
		else if (truth != q->truth) {
			fprintf(stderr, "%s:%ld: expected truth %d, as on the query's first row\n",
			    qf->path, lineno, q->truth);
			goto out;
		}
		if (r < 4)
			q->x0[r] = p;
		else
			q->x1[r - 4] = p;
		if (++nrows % 8 == 0)
			qf->n++;
	}
	if (ferror(f)) {
		fprintf(stderr, "drape ccd: %s: read error: %s\n", qf->path, strerror(errno));
		goto out;
	}
	if (nrows % 8 != 0) {
		fprintf(stderr, "%s:%ld: expected 8 rows per query, the last has %zu\n",
		    qf->path, lineno, nrows % 8);
		goto out;
	}
	rc = 0;
out:
	free(line);
	fclose(f);
	return rc;
}

/* One pass over the queries; returns the number of positives and counts
 * the true ones. */
static size_t
pass(const struct qfile *qf, enum method m, enum inside_test how, size_t *truepos)
{
	size_t i, pos = 0;

	*truepos = 0;
	for (i = 0; i < qf->n; i++) {
		const struct query *q = &qf->q[i];
		struct seed_hit hit;
		int r;

		if (m == METHOD_SEED)
			r = narrow_seed_segment(q->x0[0], q->x1[0], q->x0[1], q->x0[2], q->x0[3],
			    how, &hit);
		else if (qf->kind == KIND_VF)
			r = ccd_vertex_face(q->x0, q->x1, 0, NULL);
		else
			r = ccd_edge_edge(q->x0, q->x1, 0, NULL);
		pos += r != 0;
		*truepos += r != 0 && q->truth;
	}
	return pos;
}

static void
report(const struct qfile *qf, enum method m, enum inside_test how)
{
	const char *name = m == METHOD_SEED ? "seed" : "ccd";
	size_t i, truth = 0, pos, tp, tp2, runs;
	double t0, dt;

	if (m == METHOD_SEED && qf->kind == KIND_EE) {
		printf("%s\t%s\t%zu\tn/a\tn/a\tn/a\tn/a\tn/a\n", qf->path, name, qf->n);
		fprintf(stderr, "drape ccd: %s: n/a: the chapter has no edge-edge primitive "
		    "test, only node-triangle\n", qf->path);
		return;
	}
	for (i = 0; i < qf->n; i++)
		truth += qf->q[i].truth != 0;
	/* the first pass counts; repeats only make the rate meaningful */
	t0 = clock_seconds();
	pos = pass(qf, m, how, &tp);
	for (runs = 1; (dt = clock_seconds() - t0) < MIN_TIME && qf->n > 0; runs++)
		(void)pass(qf, m, how, &tp2);
	printf("%s\t%s\t%zu\t%zu\t%zu\t%zu\t%zu\t%.0f\n", qf->path, name, qf->n, pos, tp,
	    truth - tp, pos - tp, dt > 0 ? (double)(runs * qf->n) / dt : 0);
}

static int
bad_option(const char *opt, const char *val, const char *what)
{
	fprintf(stderr, "drape ccd: %s '%s': expected %s\n", opt, val, what);
	return EXIT_USAGE;
}

int
cmd_ccd(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "method", required_argument, NULL, 'm' },
		{ "inside", required_argument, NULL, 'i' },
		{ "kind", required_argument, NULL, 'k' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	enum method m = METHOD_CCD;
	enum inside_test how = INSIDE_ANGLE;
	enum kind kind = KIND_UNKNOWN;
	struct qfile *qf;
	int c, i, n, rc = EXIT_OK;

	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "+h", longopts, NULL)) != -1) {
		switch (c) {
		case 'm':
			if (strcmp(optarg, "ccd") == 0)
				m = METHOD_CCD;
			else if (strcmp(optarg, "seed") == 0)
				m = METHOD_SEED;
			else
				return bad_option("--method", optarg, "seed or ccd");
			break;
		case 'i':
			if (strcmp(optarg, "angle") == 0)
				how = INSIDE_ANGLE;
			else if (strcmp(optarg, "crossing") == 0)
				how = INSIDE_CROSSING;
			else
				return bad_option("--inside", optarg, "angle or crossing");
			break;
		case 'k':
			if (strcmp(optarg, "vf") == 0)
				kind = KIND_VF;
			else if (strcmp(optarg, "ee") == 0)
				kind = KIND_EE;
			else
				return bad_option("--kind", optarg, "vf or ee");
			break;
		case 'h':
			ccd_usage(stdout);
			return EXIT_OK;
		default:
			return cmd_option_error("ccd", argv);
		}
	}
	if (optind >= argc) {
		return cmd_usage_error("ccd", "expected at least one FILE.csv");
	}
	n = argc - optind;
	if ((qf = calloc((size_t)n, sizeof *qf)) == NULL) {
		fputs("drape ccd: out of memory\n", stderr);
		return EXIT_RUNTIME;
	}
	/* everything is read and checked before any result is printed */
	for (i = 0; i < n && rc == EXIT_OK; i++) {
		const char *path = argv[optind + i];
		int vf = strstr(path, "vertex-face") != NULL, ee = strstr(path, "edge-edge") != NULL;

		qf[i].path = path;
		qf[i].kind = kind != KIND_UNKNOWN ? kind : vf && !ee ? KIND_VF :
		    ee && !vf ? KIND_EE : KIND_UNKNOWN;
		if (qf[i].kind == KIND_UNKNOWN) {
			fprintf(stderr, "drape ccd: %s: cannot tell vertex-face from edge-edge "
			    "by the path; give --kind vf or --kind ee\n", path);
			rc = EXIT_USAGE;
		} else if (load(&qf[i]) != 0)
			rc = EXIT_USAGE;
	}
	if (rc == EXIT_OK) {
		printf("file\tmethod\tqueries\tpositives\ttrue_pos\tfalse_neg\tfalse_pos\t"
		    "queries_per_s\n");
		for (i = 0; i < n; i++)
			report(&qf[i], m, how);
		if (ferror(stdout) | (fclose(stdout) != 0)) {
			perror("drape ccd: stdout");
			rc = EXIT_RUNTIME;
		}
	}
	for (i = 0; i < n; i++)
		free(qf[i].q);
	free(qf);
	return rc;
}
