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
#include "stepper.h"

static int
ends_with(const char *s, const char *tail)
{
	size_t n = strlen(s), k = strlen(tail);

	return n >= k && strcmp(s + n - k, tail) == 0;
}

static int
check_obj(const char *path)
{
	struct mesh m;
	struct drape_err err;
	int first[2];
	long n;

	if (mesh_load_obj(&m, path, &err) != 0) {
		fprintf(stderr, "drape check: %s\n", err.msg);
		return EXIT_USAGE;
	}
	n = audit_self_intersections(m.x, m.tri, m.ntri, first);
	mesh_free(&m);
	if (n < 0) {
		fprintf(stderr, "drape check: %s: out of memory\n", path);
		return EXIT_RUNTIME;
	}
	printf("%s\tobj\t-\t-\t%ld\t-\n", path, n);
	return n > 0 ? EXIT_FOUND : EXIT_OK;
}

static int
check_scene(const char *path, long every)
{
	struct scene sc;
	struct stepper st;
	struct drape_err err;
	struct blowup bl;
	struct check_result r;
	double frame, next = 0;
	long k = 0, frames = 0, worst_pairs = 0, worst_inside = 0, bad_frames = 0;
	int rc = EXIT_OK;

	if (scene_load(&sc, path, &err) != 0) {
		fprintf(stderr, "drape check: %s\n", err.msg);
		return EXIT_USAGE;
	}
	if (stepper_init(&st, &sc, &err) != 0) {
		fprintf(stderr, "drape check: %s\n", err.msg);
		scene_free(&sc);
		return EXIT_USAGE;
	}
	frame = 1 / sc.output_rate;
	for (;;) {
		if (st.t >= next - 1e-12 * frame || stepper_done(&st)) {
			if (check_state(&sc, &st.cl, stepper_x(&st), &r) != 0) {
				fprintf(stderr, "drape check: %s: out of memory\n", path);
				rc = EXIT_RUNTIME;
				break;
			}
			frames++;
			if (r.pairs > 0 || r.inside > 0) {
				bad_frames++;
				printf("%s\tt=%.6g\tstep=%ld\t-\t%ld\t%ld\n", path, st.t, st.step,
				    r.pairs, r.inside);
			}
			worst_pairs = r.pairs > worst_pairs ? r.pairs : worst_pairs;
			worst_inside = r.inside > worst_inside ? r.inside : worst_inside;
			k++;
			next = (double)(k * every) * frame;
		}
		if (stepper_done(&st))
			break;
		if (stepper_step(&st, &bl) != 0) {
			fprintf(stderr, "drape check: %s: blow-up at step %ld (t = %.6g s): %s\n",
			    path, bl.step, bl.t, bl.why);
			rc = EXIT_BLOWUP;
			break;
		}
	}
	if (rc == EXIT_OK || rc == EXIT_BLOWUP)
		printf("%s\tscene\t%ld\t%ld\t%ld\t%ld\n", path, frames, bad_frames, worst_pairs,
		    worst_inside);
	if (rc == EXIT_OK && bad_frames > 0)
		rc = EXIT_FOUND;
	stepper_free(&st);
	scene_free(&sc);
	return rc;
}

int
cmd_check(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "every", required_argument, NULL, 'e' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	long every = 10;
	char *end;
	int ch, i, rc = EXIT_OK;

	optind = 1;
	while ((ch = getopt_long(argc, argv, "e:h", longopts, NULL)) != -1) {
		switch (ch) {
		case 'e':
			every = strtol(optarg, &end, 10);
			if (*optarg == '\0' || *end != '\0' || every < 1) {
				fprintf(stderr, "drape check: --every '%s': expected a whole number "
				    "of 1 or more\n", optarg);
				return EXIT_USAGE;
			}
			break;
		case 'h':
			printf("usage: drape check [--every N] SCENE|OBJ...\n");
			return EXIT_OK;
		default:
			fprintf(stderr, "usage: drape check [--every N] SCENE|OBJ...\n");
			return EXIT_USAGE;
		}
	}
	if (optind >= argc) {
		fprintf(stderr, "drape check: expected scene or OBJ files\n");
		return EXIT_USAGE;
	}
	/* columns: file, kind, frames audited, frames with a fault, the most
	 * intersecting pairs in one frame, the most nodes inside obstacles */
	printf("file\tkind\tframes\tbad_frames\tpairs\tinside\n");
	for (i = optind; i < argc; i++) {
		int r = ends_with(argv[i], ".obj") ? check_obj(argv[i]) :
		    check_scene(argv[i], every);

		if (r != EXIT_OK && (rc == EXIT_OK || rc == EXIT_FOUND))
			rc = r;
	}
	if (fflush(stdout) != 0 || ferror(stdout)) {
		fprintf(stderr, "drape check: cannot write the output\n");
		return EXIT_RUNTIME;
	}
	return rc;
}
