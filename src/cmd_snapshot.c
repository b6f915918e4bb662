/* cmd_snapshot.c: `drape snapshot`: a scene run N steps headless, or a
 * replay at the frame at or before step N, its view printed as text, so
 * that a view can be tested, piped and pasted. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmd.h"
#include "raster.h"
#include "scene.h"
#include "source.h"
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

/* The view drawn and printed; an exit status. */
static int
draw_and_print(const struct camera *cam, int w, int h, const struct scene *sc, const double *x,
    const struct cloth *cl, const struct contact_event *ev, size_t nev)
{
	struct raster r;
	int rc = EXIT_OK;

	raster_init(&r);
	if (raster_resize(&r, w, h) != 0) {
		fprintf(stderr, "drape snapshot: out of memory\n");
		rc = EXIT_RUNTIME;
	} else {
		view_draw(&r, cam, sc, x, cl->n, cl->tri, cl->ntri, ev, nev, -1);
		if (print_grid(&r) != 0) {
			perror("drape: stdout");
			rc = EXIT_RUNTIME;
		}
	}
	raster_free(&r);
	return rc;
}

/* A replay at step: the frame at or before it, the step's events marked. */
static int
snapshot_replay(const char *path, long step, int preset, bool perspective, int w, int h)
{
	struct source src;
	struct source_replay sr;
	struct source_state s;
	struct source_position p;
	struct drape_err err;
	struct camera cam;
	const struct contact_event *ev;
	size_t nev;
	vec3 target;
	double radius;
	int rc;

	if (source_replay_open(&src, &sr, path, &err) != 0) {
		fprintf(stderr, "drape snapshot: %s\n", err.msg);
		return EXIT_USAGE;
	}
	src.position(src.ctx, &p);
	if (step > p.last) {
		fprintf(stderr, "drape snapshot: --step %ld: %s ends at step %ld\n", step, path,
		    p.last);
		source_replay_close(&sr);
		return EXIT_USAGE;
	}
	if (!src.seek(src.ctx, SOURCE_GOTO, step)) {
		fprintf(stderr, "drape snapshot: %s: out of memory\n", path);
		source_replay_close(&sr);
		return EXIT_RUNTIME;
	}
	src.state(src.ctx, &s);
	src.position(src.ctx, &p);
	if (p.frame_step != step)
		fprintf(stderr, "drape snapshot: %s: step %ld shows the frame of step %ld\n", path,
		    step, p.frame_step);
	/* framed at the start, as the TUI frames it */
	view_frame(s.sc, s.cl->x0, s.cl->n, &target, &radius);
	camera_preset(&cam, (enum view_preset)preset, target, radius);
	cam.perspective = perspective;
	ev = src.events(src.ctx, &nev);
	rc = draw_and_print(&cam, w, h, s.sc, s.x, s.cl, ev, nev);
	source_replay_close(&sr);
	return rc;
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
			return cmd_option_error("snapshot", argv);
		}
	}
	if (optind != argc - 1) {
		fprintf(stderr, "drape snapshot: expected one scene file\n");
		usage(stderr);
		return EXIT_USAGE;
	}
	if (looks_binary(argv[optind]))
		return snapshot_replay(argv[optind], steps, preset, perspective, w, h);
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
	if (rc == EXIT_OK)
		rc = draw_and_print(&cam, w, h, &sc, stepper_x(&st), &st.cl,
		    steps > 0 ? st.col.ev : NULL, steps > 0 ? st.col.nev : 0);
	stepper_free(&st);
	scene_free(&sc);
	return rc;
}
