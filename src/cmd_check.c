/* cmd_check.c: `drape check SCENE|OBJ... [--every N]`, the independent
 * intersection audit: for an OBJ, its intersecting pairs of non-adjacent
 * triangles; for a scene, the same and the nodes inside obstacles at every
 * Nth output frame of a headless run. */
#include <getopt.h>
#include <stdlib.h>
#include <string.h>

#include "audit.h"
#include "check.h"
#include "cmd.h"
#include "mesh.h"
#include "network.h"
#include "stepper.h"

static int
ends_with(const char *s, const char *tail)
{
	size_t n = strlen(s), k = strlen(tail);

	return n >= k && strcmp(s + n - k, tail) == 0;
}

/* An audit its bound cut short (audit.h), said with what it had found. */
static void
say_cut(const char *path, const char *when, long candidates, long tests, long pairs,
    size_t ntri)
{
	fprintf(stderr, "drape check: %s%s: the audit stopped at its bound for %zu triangles "
	    "(%ld pairs of boxes compared, %ld exact tests: triangles lying on one another); %s\n",
	    path, when, ntri, candidates, tests, pairs > 0 ? "the pairs counted are a lower "
	    "bound" : "none intersected so far, which proves nothing");
}

static int
check_obj(const char *path)
{
	struct mesh m;
	struct drape_err err;
	struct audit_result r;
	int first[2];

	if (mesh_load_obj(&m, path, &err) != 0) {
		fprintf(stderr, "drape check: %s\n", err.msg);
		return EXIT_USAGE;
	}
	if (audit_self(m.x, m.tri, m.ntri, first, &r) != 0) {
		mesh_free(&m);
		fprintf(stderr, "drape check: %s: out of memory\n", path);
		return EXIT_RUNTIME;
	}
	printf("%s\tobj\t-\t-\t%ld\t-\t-\t-\n", path, r.pairs);
	if (r.cut)
		say_cut(path, "", r.candidates, r.tests, r.pairs, m.ntri);
	mesh_free(&m);
	/* cut short with nothing found is no answer: an error */
	return r.pairs > 0 ? EXIT_FOUND : r.cut ? EXIT_RUNTIME : EXIT_OK;
}

static int
check_scene(const char *path, long every, const char *const *sets, size_t nsets)
{
	struct scene sc;
	struct stepper *st;
	struct stepper_report rep;
	struct drape_err err;
	struct step_failure fail;
	struct check_result r;
	double frame, next = 0;
	long k = 0, frames = 0, worst_pairs = 0, worst_inside = 0, bad_frames = 0, worst_edges = 0;
	double deepest = 0;
	bool cut = false;
	int rc = EXIT_OK;

	if (scene_load_set(&sc, path, sets, nsets, &err) != 0) {
		fprintf(stderr, "drape check: %s\n", err.msg);
		return EXIT_USAGE;
	}
	if ((st = cmd_stepper_new(&sc, &err)) == NULL) {
		fprintf(stderr, "drape check: %s\n", err.msg);
		scene_free(&sc);
		return EXIT_USAGE;
	}
	frame = 1 / sc.output_rate;
	for (;;) {
		stepper_report(st, &rep);
		if (rep.t >= next - 1e-12 * frame || stepper_done(st)) {
			if (check_state(&sc, &stepper_network(st)->cl, stepper_x(st), &r) != 0) {
				fprintf(stderr, "drape check: %s: out of memory\n", path);
				rc = EXIT_RUNTIME;
				break;
			}
			frames++;
			if (r.cut) {
				char when[64];

				snprintf(when, sizeof when, " at t = %.6g s", rep.t);
				say_cut(path, when, r.candidates, r.tests, r.pairs,
				    stepper_network(st)->cl.ntri);
				cut = true;
			}
			if (r.pairs > 0 || r.inside > 0) {
				bad_frames++;
				printf("%s\tt=%.6g\tstep=%ld\t-\t%ld\t%ld\t%ld\t%.3f\n", path, rep.t,
				    rep.step, r.pairs, r.inside, r.edges_in, r.edge_depth * 1e3);
			}
			worst_pairs = r.pairs > worst_pairs ? r.pairs : worst_pairs;
			worst_inside = r.inside > worst_inside ? r.inside : worst_inside;
			worst_edges = r.edges_in > worst_edges ? r.edges_in : worst_edges;
			deepest = r.edge_depth > deepest ? r.edge_depth : deepest;
			k++;
			next = (double)k * (double)every * frame;
		}
		if (stepper_done(st))
			break;
		if (stepper_step(st, &fail) != STEP_OK) {
			rc = cmd_step_failed("check", path, &fail);
			break;
		}
	}
	if (rc == EXIT_OK || rc == EXIT_BLOWUP)
		printf("%s\tscene\t%ld\t%ld\t%ld\t%ld\t%ld\t%.3f\n", path, frames, bad_frames,
		    worst_pairs, worst_inside, worst_edges, deepest * 1e3);
	if (rc == EXIT_OK && bad_frames > 0)
		rc = EXIT_FOUND;
	else if (rc == EXIT_OK && cut)
		rc = EXIT_RUNTIME;	/* a frame not audited whole, and nothing found */
	stepper_free(st);
	scene_free(&sc);
	return rc;
}

/* The options into *every and sets; an exit status, or -1 after --help. */
static int
check_options(int argc, char **argv, long *every, const char **sets, size_t *nsets)
{
	static const struct option longopts[] = {
		{ "every", required_argument, NULL, 'e' },
		{ "set", required_argument, NULL, 's' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	int ch, i;

	optind = 1;
	opterr = 0;
	while ((ch = getopt_long(argc, argv, "e:h", longopts, NULL)) != -1) {
		switch (ch) {
		case 'e':
			/* past SCENE_MAX_FRAMES it is every frame's first alone */
			if (cmd_parse_long(optarg, 1, (long)SCENE_MAX_FRAMES, every) != 0) {
				fprintf(stderr, "drape check: --every '%s': expected a whole number "
				    "from 1 to %ld\n", optarg, (long)SCENE_MAX_FRAMES);
				return EXIT_USAGE;
			}
			break;
		case 's':
			sets[(*nsets)++] = optarg;
			break;
		case 'h':
			printf("usage: drape check [--every N] [--set SECTION.KEY=VALUE]... "
			    "SCENE|OBJ...\n");
			return -1;
		default:
			return cmd_option_error("check", argv);
		}
	}
	if (optind >= argc) {
		return cmd_usage_error("check", "expected scene or OBJ files");
	}
	for (i = optind; i < argc; i++)
		if (*nsets > 0 && ends_with(argv[i], ".obj")) {
			fprintf(stderr, "drape check: --set '%s': %s is an OBJ, which has no "
			    "values to set; expected scene files\n", sets[0], argv[i]);
			return EXIT_USAGE;
		}
	return EXIT_OK;
}

/* The --set options against every scene before anything is printed, so
 * that a bad one is a usage error with nothing on stdout, as it is for
 * run and snapshot: each scene is parsed with them, and an error that
 * names an option (override.h: "--set SPEC: ...") stops the command. A
 * scene's own errors are left to its turn, after the header, as without
 * --set. EXIT_OK, or EXIT_USAGE once the error is said. */
static int
check_sets(int argc, char **argv, const char *const *sets, size_t nsets)
{
	struct scene sc;
	struct drape_err err;
	int i;

	for (i = optind; nsets > 0 && i < argc; i++) {
		if (ends_with(argv[i], ".obj"))
			continue;
		if (scene_load_set(&sc, argv[i], sets, nsets, &err) == 0) {
			scene_free(&sc);
			continue;
		}
		if (strncmp(err.msg, "--set ", 6) == 0) {
			fprintf(stderr, "drape check: %s\n", err.msg);
			return EXIT_USAGE;
		}
	}
	return EXIT_OK;
}

int
cmd_check(int argc, char **argv)
{
	long every = 10;
	const char **sets;
	size_t nsets = 0;
	int i, rc;

	if ((sets = calloc((size_t)argc, sizeof *sets)) == NULL) {
		fprintf(stderr, "drape check: out of memory\n");
		return EXIT_RUNTIME;
	}
	if ((rc = check_options(argc, argv, &every, sets, &nsets)) != EXIT_OK) {
		free(sets);
		return rc < 0 ? EXIT_OK : rc;
	}
	if ((rc = check_sets(argc, argv, sets, nsets)) != EXIT_OK) {
		free(sets);
		return rc;
	}
	/* columns: file, kind, frames audited, frames with a fault, the most
	 * intersecting pairs in one frame, the most nodes inside obstacles,
	 * the most edges into them and the deepest edge (reported, not a
	 * fault yet: drape(1), check) */
	printf("file\tkind\tframes\tbad_frames\tpairs\tinside\tedges_in\tedge_depth_mm\n");
	for (i = optind; i < argc; i++) {
		int r = ends_with(argv[i], ".obj") ? check_obj(argv[i]) :
		    check_scene(argv[i], every, sets, nsets);

		if (r != EXIT_OK && (rc == EXIT_OK || rc == EXIT_FOUND))
			rc = r;
	}
	free(sets);
	if (fflush(stdout) != 0 || ferror(stdout)) {
		fprintf(stderr, "drape check: cannot write the output\n");
		return EXIT_RUNTIME;
	}
	return rc;
}
