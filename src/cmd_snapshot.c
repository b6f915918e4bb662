/* cmd_snapshot.c: `drape snapshot`: a scene run N steps headless, its view
 * printed as text, so that a view can be tested, piped and pasted. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmd.h"
#include "raster.h"
#include "scene.h"
#include "stepper.h"
#include "view.h"

#define SNAPSHOT_MAX_SIDE 1000

static int
bad(const char *opt, const char *val, const char *what)
{
	fprintf(stderr, "drape snapshot: %s '%s': expected %s\n", opt, val, what);
	return EXIT_USAGE;
}

/* A scene is text; a replay (gzip, or any binary header) is not. */
static bool
looks_binary(const char *path)
{
	unsigned char b[64];
	size_t n, i;
	FILE *f = fopen(path, "rb");

	if (f == NULL)
		return false;	/* scene_load says why */
	n = fread(b, 1, sizeof b, f);
	fclose(f);
	for (i = 0; i < n; i++)
		if (b[i] == 0 || b[i] == 0x1f || b[i] >= 0x80)
			return true;
	return false;
}

static int
print_grid(const struct raster *r)
{
	int row, len;

	for (row = 0; row < r->h; row++) {
		const char *line = r->ch + (size_t)row * (size_t)r->w;

		for (len = r->w; len > 0 && line[len - 1] == ' '; len--)
			;
		if (fwrite(line, 1, (size_t)len, stdout) != (size_t)len || putchar('\n') == EOF)
			return -1;
	}
	return fflush(stdout) == 0 ? 0 : -1;
}

int
cmd_snapshot(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "step", required_argument, NULL, 's' },
		{ "view", required_argument, NULL, 'v' },
		{ "size", required_argument, NULL, 'z' },
		{ "perspective", no_argument, NULL, 'p' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	long steps = 0;
	int preset = VIEW_ISO, w = 80, h = 24, c, rc = EXIT_OK;
	bool perspective = false;
	struct scene sc;
	struct stepper st;
	struct drape_err err;
	struct blowup bl;
	struct camera cam;
	struct raster r;
	vec3 target;
	double radius;
	char *end, tail;

	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "+h", longopts, NULL)) != -1) {
		switch (c) {
		case 's':
			steps = strtol(optarg, &end, 10);
			if (end == optarg || *end != '\0' || steps < 0)
				return bad("--step", optarg, "a whole number from 0");
			break;
		case 'v':
			if ((preset = view_preset_from_name(optarg)) < 0)
				return bad("--view", optarg, "front, side, top or iso");
			break;
		case 'z':
			if (sscanf(optarg, "%dx%d%c", &w, &h, &tail) != 2 || w < 1 || h < 1 ||
			    w > SNAPSHOT_MAX_SIDE || h > SNAPSHOT_MAX_SIDE)
				return bad("--size", optarg, "WxH, each from 1 to 1000, as 80x24");
			break;
		case 'p':
			perspective = true;
			break;
		case 'h':
			usage(stdout);
			return EXIT_OK;
		default:
			if (optopt != 0)
				fprintf(stderr, "drape snapshot: option '-%c' needs a value or is unknown\n",
				    optopt);
			else
				fprintf(stderr, "drape snapshot: unknown option '%s'\n", argv[optind - 1]);
			usage(stderr);
			return EXIT_USAGE;
		}
	}
	if (optind != argc - 1) {
		fprintf(stderr, "drape snapshot: expected one scene file\n");
		usage(stderr);
		return EXIT_USAGE;
	}
	/* TODO(replay): a replay FILE is seeked to --step here once replay
	 * files exist; until then it is refused. */
	if (looks_binary(argv[optind])) {
		fprintf(stderr, "drape snapshot: %s: not a scene (replay files are not supported "
		    "yet)\n", argv[optind]);
		return EXIT_USAGE;
	}
	if (scene_load(&sc, argv[optind], &err) != 0) {
		fprintf(stderr, "drape: %s\n", err.msg);
		return EXIT_USAGE;
	}
	if (stepper_init(&st, &sc, &err) != 0) {
		fprintf(stderr, "drape: %s\n", err.msg);
		scene_free(&sc);
		return EXIT_USAGE;
	}
	/* framed at the start, as the TUI frames it, so that snapshots of
	 * successive steps line up */
	view_frame(&sc, stepper_x(&st), st.cl.n, &target, &radius);
	camera_preset(&cam, (enum view_preset)preset, target, radius);
	cam.perspective = perspective;
	while (st.step < steps && rc == EXIT_OK) {
		if (stepper_done(&st)) {
			fprintf(stderr, "drape snapshot: --step %ld: %s ends at step %ld\n", steps,
			    sc.path, st.step);
			rc = EXIT_USAGE;
		} else if (stepper_step(&st, &bl) != 0) {
			fprintf(stderr, "drape: %s: blow-up at step %ld (t = %.6g s): %s\n", sc.path,
			    bl.step, bl.t, bl.why);
			rc = EXIT_BLOWUP;
		}
	}
	if (rc == EXIT_OK) {
		raster_init(&r);
		if (raster_resize(&r, w, h) != 0) {
			fprintf(stderr, "drape snapshot: out of memory\n");
			rc = EXIT_RUNTIME;
		} else {
			view_draw(&r, &cam, &sc, stepper_x(&st), st.cl.n, st.cl.tri, st.cl.ntri,
			    steps > 0 ? st.col.ev : NULL, steps > 0 ? st.col.nev : 0, -1);
			if (print_grid(&r) != 0) {
				perror("drape: stdout");
				rc = EXIT_RUNTIME;
			}
		}
		raster_free(&r);
	}
	stepper_free(&st);
	scene_free(&sc);
	return rc;
}
