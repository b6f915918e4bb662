/* cmd_snapshot.c: `drape snapshot`: a scene run headless, or a replay, to
 * a step or a time; its view printed as text (ASCII, or Unicode braille or
 * half blocks), so that a view can be tested, piped and pasted; or, with
 * --png, rendered as a picture: one frame, or a filmstrip of several
 * (--strip, --frames), coloured by shading, strain or contact. Both kinds
 * of input are read through a source (source.h), as the TUI reads them. */
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cmd.h"
#include "colouring.h"
#include "glyphs.h"
#include "picture.h"
#include "png.h"
#include "raster.h"
#include "replay.h"
#include "scene.h"
#include "source.h"
#include "stepper.h"
#include "units.h"
#include "view.h"

#define SNAPSHOT_MAX_SIDE 1000		/* characters */
#define PICTURE_MIN_SIDE 16		/* pixels */
#define PICTURE_MAX_SIDE 4096
#define PICTURE_MAX_WIDTH 16384		/* of a whole filmstrip */
#define PICTURE_MAX_FRAMES 64
#define PICTURE_W 480
#define PICTURE_H 360
#define PICTURE_SUPERSAMPLE 3

struct target {
	bool by_time;
	long step;
	double t;
};

struct shot {
	double t;
	long step;
	double *x;
	double *field;
};

struct snapshot {
	const char *path;	/* the scene or replay */
	const char *png;	/* or NULL: text */
	int preset;
	bool perspective;
	double zoom;		/* 0: 1 */
	bool centred;
	vec3 centre;		/* of the view, when centred */
	bool frame_scene;	/* --frame scene: the whole scene as it starts, as the
				 * TUI opens; else the cloth in the frames drawn */
	int w, h;		/* characters, or a frame's pixels */
	bool size_given;
	const char *size_arg;
	enum glyphs glyphs;
	enum colouring colouring;
	double range;		/* 0: auto */
	struct target *targets;
	size_t ntargets;
	long frames;		/* --frames K, or 0 */
	bool strip;		/* --strip given */
	bool have_step, have_time;
	const char **sets;	/* --set, for a scene (room for argc of them) */
	size_t nsets;

	/* the input */
	struct source src;
	bool replay;
	struct source_replay sr;
	struct scene sc;
	struct stepper *st;
	struct source_live lv;
	bool open;
};

static int
bad(const char *opt, const char *val, const char *what)
{
	fprintf(stderr, "drape snapshot: %s '%s': expected %s\n", opt, val, what);
	return EXIT_USAGE;
}

/* What a file is, by its first bytes: a replay begins with its magic
 * (drape-replay(5)), and a file shorter than the magic is neither a replay
 * nor a scene; anything else is for the scene parser to judge. */
enum file_kind { FILE_SCENE, FILE_REPLAY, FILE_TOO_SHORT };

static enum file_kind
file_kind(const char *path, size_t *len)
{
	unsigned char b[REPLAY_MAGIC_LEN];
	FILE *f = fopen(path, "rb");
	int bad;

	*len = 0;
	if (f == NULL)
		return FILE_SCENE;	/* scene_load says why */
	*len = fread(b, 1, sizeof b, f);
	bad = ferror(f);
	fclose(f);
	if (bad)
		return FILE_SCENE;
	if (*len < sizeof b)
		return FILE_TOO_SHORT;
	return memcmp(b, REPLAY_MAGIC, sizeof b) == 0 ? FILE_REPLAY : FILE_SCENE;
}

static int
add_target(struct snapshot *sn, bool by_time, long step, double t)
{
	struct target *tg;

	if (sn->ntargets >= PICTURE_MAX_FRAMES) {
		fprintf(stderr, "drape snapshot: at most %d frames\n", PICTURE_MAX_FRAMES);
		return EXIT_USAGE;
	}
	if ((tg = realloc(sn->targets, (sn->ntargets + 1) * sizeof *tg)) == NULL) {
		fprintf(stderr, "drape snapshot: out of memory\n");
		return EXIT_RUNTIME;
	}
	sn->targets = tg;
	tg[sn->ntargets++] = (struct target){ by_time, step, t };
	return EXIT_OK;
}

/* --strip T1,T2,...: times from 0, each with an optional unit. */
static int
parse_strip(struct snapshot *sn, const char *arg)
{
	char buf[64], why[160];
	const char *p = arg;
	int rc;

	if (*arg == '\0')
		return bad("--strip", arg, "times separated by commas, as 0,0.1,0.2 or 0,50ms");
	for (;;) {
		size_t len = strcspn(p, ",");
		double t;

		if (len == 0 || len >= sizeof buf)
			return bad("--strip", arg, "times separated by commas, as 0,0.1,0.2 or 0,50ms");
		memcpy(buf, p, len);
		buf[len] = '\0';
		if (units_parse(buf, DIM_TIME, &t, 1, why, sizeof why) != 0 || !(t >= 0))
			return bad("--strip", arg, "times from 0 separated by commas, as 0,0.1,0.2");
		if ((rc = add_target(sn, true, 0, t)) != EXIT_OK)
			return rc;
		if (p[len] == '\0')
			return EXIT_OK;
		p += len + 1;
	}
}

/* --centre X,Y,Z: a point, each coordinate with an optional unit. */
static int
parse_centre(struct snapshot *sn, const char *arg)
{
	char buf[128], why[160], *q;
	double v[3];

	snprintf(buf, sizeof buf, "%s", arg);
	for (q = buf; *q != '\0'; q++)
		if (*q == ',')
			*q = ' ';
	if (units_parse(buf, DIM_LENGTH, v, 3, why, sizeof why) != 0)
		return bad("--centre", arg, "a point X,Y,Z in m, or with a unit, as 0,60,0mm");
	sn->centre = v3(v[0], v[1], v[2]);
	sn->centred = true;
	return EXIT_OK;
}

static int
target_order(const void *a, const void *b)
{
	const struct target *p = a, *q = b;
	double s = p->by_time ? p->t : (double)p->step, t = q->by_time ? q->t : (double)q->step;

	return s < t ? -1 : s > t;
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

static int
print_glyphs(const struct glyphs_grid *g)
{
	size_t len = 3 * (size_t)g->w + 4;
	char *buf = malloc(len);
	int row;

	if (buf == NULL)
		return -1;
	for (row = 0; row < g->h; row++) {
		glyphs_row(g, row, buf, len);
		if (fputs(buf, stdout) == EOF || putchar('\n') == EOF) {
			free(buf);
			return -1;
		}
	}
	free(buf);
	return fflush(stdout) == 0 ? 0 : -1;
}

static void
close_input(struct snapshot *sn)
{
	if (!sn->open)
		return;
	if (sn->replay) {
		source_replay_close(&sn->sr);
	} else {
		source_live_free(&sn->lv);
		stepper_free(sn->st);
		scene_free(&sn->sc);
	}
	sn->open = false;
}

static int
open_input(struct snapshot *sn)
{
	struct drape_err err;
	size_t len;
	enum file_kind kind = file_kind(sn->path, &len);

	if (kind == FILE_TOO_SHORT) {
		fprintf(stderr, "drape snapshot: %s: %zu bytes: expected a scene or a replay "
		    "(a replay begins with the 8 bytes 'DRAPERPL')\n", sn->path, len);
		return EXIT_USAGE;
	}
	sn->replay = kind == FILE_REPLAY;
	if (sn->replay && sn->nsets > 0) {
		fprintf(stderr, "drape snapshot: --set '%s': %s is a replay, which runs its "
		    "recorded scene; expected a scene file\n", sn->sets[0], sn->path);
		return EXIT_USAGE;
	}
	if (sn->replay) {
		if (source_replay_open(&sn->src, &sn->sr, sn->path, &err) != 0) {
			fprintf(stderr, "drape snapshot: %s\n", err.msg);
			return EXIT_USAGE;
		}
		sn->open = true;
		return EXIT_OK;
	}
	if (scene_load_set(&sn->sc, sn->path, sn->sets, sn->nsets, &err) != 0) {
		fprintf(stderr, "drape: %s\n", err.msg);
		return EXIT_USAGE;
	}
	if ((sn->st = cmd_stepper_new(&sn->sc, &err)) == NULL) {
		fprintf(stderr, "drape: %s\n", err.msg);
		scene_free(&sn->sc);
		return EXIT_USAGE;
	}
	source_live(&sn->src, &sn->lv, sn->st);
	sn->open = true;
	return EXIT_OK;
}

/* A live run one step on; an exit status. */
static int
step_live(struct snapshot *sn, const char *what)
{
	char why[400];
	struct source_state s;

	switch (sn->src.step(sn->src.ctx, why, sizeof why)) {
	case SOURCE_STEPPED:
		return EXIT_OK;
	case SOURCE_END:
		sn->src.state(sn->src.ctx, &s);
		fprintf(stderr, "drape snapshot: %s: %s ends at step %ld (t = %.6g s)\n", what,
		    sn->path, s.step, s.t);
		return EXIT_USAGE;
	case SOURCE_FAILED:
		fprintf(stderr, "drape: %s: %s\n", sn->path, why);
		return EXIT_BLOWUP;
	case SOURCE_ERROR:
		fprintf(stderr, "drape: %s: %s\n", sn->path, why);
		return EXIT_RUNTIME;
	case SOURCE_STOPPED:
		return EXIT_INTERRUPTED;
	}
	return EXIT_RUNTIME;
}

/* The replay's frame nearest time t (the earlier of two as near). */
static int
replay_to_time(struct snapshot *sn, double t, const char *what)
{
	struct source_state s;
	struct source_position p;
	double best;
	long at;

	sn->src.position(sn->src.ctx, &p);
	sn->src.seek(sn->src.ctx, SOURCE_LAST, 0);
	sn->src.state(sn->src.ctx, &s);
	if (t > s.t * (1 + 1e-9) + 1e-12) {
		fprintf(stderr, "drape snapshot: %s: %s ends at t = %.6g s (step %ld)\n", what,
		    sn->path, s.t, s.step);
		return EXIT_USAGE;
	}
	/* from the frame before the cursor, frame by frame */
	if (!sn->src.seek(sn->src.ctx, SOURCE_GOTO, p.frame_step))
		return EXIT_RUNTIME;
	sn->src.state(sn->src.ctx, &s);
	if (s.t > t)
		sn->src.seek(sn->src.ctx, SOURCE_FIRST, 0);
	sn->src.state(sn->src.ctx, &s);
	best = fabs(s.t - t);
	at = s.step;
	while (sn->src.seek(sn->src.ctx, SOURCE_FRAME_NEXT, 0)) {
		sn->src.state(sn->src.ctx, &s);
		if (!(fabs(s.t - t) < best))
			break;
		best = fabs(s.t - t);
		at = s.step;
	}
	return sn->src.seek(sn->src.ctx, SOURCE_GOTO, at) ? EXIT_OK : EXIT_RUNTIME;
}

/* The input at target tg; an exit status. */
static int
go_to(struct snapshot *sn, const struct target *tg)
{
	struct source_state s;
	struct source_position p;
	char what[64];
	int rc;

	if (tg->by_time)
		snprintf(what, sizeof what, "t = %.6g s", tg->t);
	else
		snprintf(what, sizeof what, "--step %ld", tg->step);
	if (sn->replay) {
		if (tg->by_time) {
			if ((rc = replay_to_time(sn, tg->t, what)) != EXIT_OK) {
				if (rc == EXIT_RUNTIME)
					fprintf(stderr, "drape snapshot: %s: out of memory\n", sn->path);
				return rc;
			}
			return EXIT_OK;
		}
		sn->src.position(sn->src.ctx, &p);
		if (tg->step > p.last) {
			fprintf(stderr, "drape snapshot: --step %ld: %s ends at step %ld\n", tg->step,
			    sn->path, p.last);
			return EXIT_USAGE;
		}
		if (!sn->src.seek(sn->src.ctx, SOURCE_GOTO, tg->step)) {
			fprintf(stderr, "drape snapshot: %s: out of memory\n", sn->path);
			return EXIT_RUNTIME;
		}
		sn->src.position(sn->src.ctx, &p);
		if (p.frame_step != tg->step)
			fprintf(stderr, "drape snapshot: %s: step %ld shows the frame of step %ld\n",
			    sn->path, tg->step, p.frame_step);
		return EXIT_OK;
	}
	for (;;) {
		sn->src.state(sn->src.ctx, &s);
		/* by time: the first step at or after it */
		if (tg->by_time ? !(s.t < tg->t - 1e-12) : s.step >= tg->step)
			return EXIT_OK;
		if ((rc = step_live(sn, what)) != EXIT_OK)
			return rc;
	}
}

/* The camera: by default on the cloth in the frames drawn (its box over
 * all of them, lo to hi: a filmstrip's frames line up); with --frame
 * scene as the TUI frames a run, at its start, so that separate pictures
 * of successive steps line up too. */
static void
frame_camera(const struct snapshot *sn, vec3 lo, vec3 hi, struct camera *cam)
{
	struct source_state s;
	vec3 target;
	double radius;

	sn->src.state(sn->src.ctx, &s);
	if (sn->frame_scene)
		view_frame(s.sc, s.cl->x0, s.cl->n, &target, &radius);
	else
		view_frame_cloth(s.sc, s.cl->x0, s.cl->n, lo, hi, &target, &radius);
	camera_preset(cam, (enum view_preset)sn->preset, sn->centred ? sn->centre : target, radius);
	cam->perspective = sn->perspective;
	if (sn->zoom > 0)
		cam->zoom = sn->zoom;
}

/* The text view at the first target; an exit status. */
static int
snapshot_text(struct snapshot *sn)
{
	struct source_state s;
	struct camera cam;
	const struct contact_event *ev;
	vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
	size_t nev;
	int rc;

	if (sn->ntargets > 0 && (rc = go_to(sn, &sn->targets[0])) != EXIT_OK)
		return rc;
	sn->src.state(sn->src.ctx, &s);
	view_cloth_box(s.x, s.cl->n, &lo, &hi);
	frame_camera(sn, lo, hi, &cam);
	ev = sn->src.events(sn->src.ctx, &nev);
	if (s.step == 0) {
		ev = NULL;
		nev = 0;
	}
	if (sn->glyphs == GLYPHS_ASCII) {
		struct raster r;

		raster_init(&r);
		if (raster_resize(&r, sn->w, sn->h) != 0) {
			fprintf(stderr, "drape snapshot: out of memory\n");
			return EXIT_RUNTIME;
		}
		view_draw(&r, &cam, s.sc, s.x, s.cl->n, s.cl->tri, s.cl->ntri, ev, nev, -1);
		rc = print_grid(&r);
		raster_free(&r);
	} else {
		struct glyphs_grid g;
		struct paint_opts po = { COLOUR_SHADE, 1, 0, true };

		glyphs_init(&g);
		if (glyphs_resize(&g, sn->glyphs, sn->w, sn->h) != 0 ||
		    glyphs_draw(&g, &cam, s.sc, s.cl, s.x, NULL, &po, ev, nev, -1) != 0) {
			glyphs_free(&g);
			fprintf(stderr, "drape snapshot: out of memory\n");
			return EXIT_RUNTIME;
		}
		rc = print_glyphs(&g);
		glyphs_free(&g);
	}
	if (rc != 0) {
		perror("drape: stdout");
		return EXIT_RUNTIME;
	}
	return EXIT_OK;
}

/* Can a file be made beside path? Said before a long run, not after. */
static int
check_writable(const char *path)
{
	const char *slash = strrchr(path, '/');
	char dir[4096];
	size_t len = slash == NULL ? 1 : slash == path ? 1 : (size_t)(slash - path);

	if (slash == NULL)
		strcpy(dir, ".");
	else if (len >= sizeof dir)
		return 0;	/* the write will say */
	else {
		memcpy(dir, path, len);
		dir[len] = '\0';
	}
	if (access(dir, W_OK | X_OK) != 0) {
		fprintf(stderr, "drape snapshot: --png %s: cannot write in %s: %s\n", path, dir,
		    strerror(errno));
		return EXIT_RUNTIME;
	}
	return EXIT_OK;
}

static void
free_shots(struct shot *sh, size_t n)
{
	size_t k;

	for (k = 0; k < n; k++) {
		free(sh[k].x);
		free(sh[k].field);
	}
	free(sh);
}

/* The picture of every target; an exit status. */
/* The largest magnitude of strain colouring c over every intact frame of
 * the replay, so that its pictures share one scale by default (each set
 * its own from the frames it drew: two pictures of one run could not be
 * compared); 0 when none could be read, -1 out of memory. */
static double
replay_field_max(struct snapshot *sn, const struct cloth *cl, enum colouring c)
{
	const struct replay *rp = &sn->sr.rp;
	size_t n3 = 3 * (size_t)cl->n, i, k, j;
	double *x = malloc((n3 > 0 ? n3 : 1) * sizeof *x), m = 0;
	double *field = malloc((cl->n > 0 ? (size_t)cl->n : 1) * sizeof *field);
	struct drape_err err;

	if (x == NULL || field == NULL) {
		free(x);
		free(field);
		return -1;
	}
	for (i = 0; i < rp->nchunks && m >= 0; i++) {
		struct replay_frames fr;

		/* a damaged chunk is passed over, as the viewer does */
		if (!replay_is_frames(rp->chunk[i].kind) || replay_read_frames(rp, i, &fr, &err) != 0)
			continue;
		for (k = 0; k < fr.count && m >= 0; k++) {
			for (j = 0; j < n3; j++)
				x[j] = fr.x[k * n3 + j];
			if (colouring_field(c, cl, x, NULL, 0, field) != 0)
				m = -1;
			for (j = 0; m >= 0 && j < (size_t)cl->n; j++)
				m = fmax(m, fabs(field[j]));
		}
		replay_frames_free(&fr);
	}
	free(x);
	free(field);
	return m;
}

static int
snapshot_png(struct snapshot *sn)
{
	struct source_state s;
	struct camera cam;
	struct shot *sh;
	struct picture_frame *fr = NULL;
	struct picture_opts po;
	struct drape_err err;
	unsigned char *rgb = NULL;
	vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
	size_t k, n3;
	double m = 0;
	int rc = EXIT_OK, w, h, p;

	if ((rc = check_writable(sn->png)) != EXIT_OK)
		return rc;
	/* the input, and for a scene its meshes: a picture over them would
	 * destroy them */
	if (cmd_output_spares("snapshot", "--png", sn->png, sn->path, sn->replay ? "the replay" :
	    "the scene") != EXIT_OK || (!sn->replay && cmd_output_spares_scene("snapshot", "--png",
	    sn->png, &sn->sc, false) != EXIT_OK))
		return EXIT_USAGE;
	if (sn->ntargets == 0 && (rc = add_target(sn, false, 0, 0)) != EXIT_OK)
		return rc;
	qsort(sn->targets, sn->ntargets, sizeof *sn->targets, target_order);
	sn->src.state(sn->src.ctx, &s);
	n3 = 3 * (size_t)s.cl->n;
	if ((sh = calloc(sn->ntargets, sizeof *sh)) == NULL) {
		fprintf(stderr, "drape snapshot: out of memory\n");
		return EXIT_RUNTIME;
	}
	for (k = 0; k < sn->ntargets; k++) {
		const struct contact_event *ev;
		size_t nev;

		if ((rc = go_to(sn, &sn->targets[k])) != EXIT_OK)
			goto done;
		sn->src.state(sn->src.ctx, &s);
		ev = sn->src.events(sn->src.ctx, &nev);
		sh[k].t = s.t;
		sh[k].step = s.step;
		sh[k].x = malloc((n3 > 0 ? n3 : 1) * sizeof *sh[k].x);
		sh[k].field = malloc((s.cl->n > 0 ? (size_t)s.cl->n : 1) * sizeof *sh[k].field);
		if (sh[k].x == NULL || sh[k].field == NULL ||
		    colouring_field(sn->colouring, s.cl, s.x, s.step > 0 ? ev : NULL,
		    s.step > 0 ? nev : 0, sh[k].field) != 0) {
			fprintf(stderr, "drape snapshot: out of memory\n");
			rc = EXIT_RUNTIME;
			goto done;
		}
		memcpy(sh[k].x, s.x, n3 * sizeof *sh[k].x);
		view_cloth_box(s.x, s.cl->n, &lo, &hi);
		for (p = 0; p < s.cl->n; p++)
			m = fmax(m, fabs(sh[k].field[p]));
	}
	frame_camera(sn, lo, hi, &cam);
	if ((fr = calloc(sn->ntargets, sizeof *fr)) == NULL) {
		fprintf(stderr, "drape snapshot: out of memory\n");
		rc = EXIT_RUNTIME;
		goto done;
	}
	for (k = 0; k < sn->ntargets; k++)
		fr[k] = (struct picture_frame){ sh[k].t, sh[k].x,
			sn->colouring == COLOUR_SHADE ? NULL : sh[k].field };
	memset(&po, 0, sizeof po);
	po.w = sn->w;
	po.h = sn->h;
	po.colouring = sn->colouring;
	/* a replay's default scale is its whole run's, a scene's the frames
	 * drawn (it is run only so far) */
	if (sn->range <= 0 && sn->replay && colouring_is_strain(sn->colouring)) {
		double all = replay_field_max(sn, s.cl, sn->colouring);

		if (all < 0) {
			fprintf(stderr, "drape snapshot: out of memory\n");
			rc = EXIT_RUNTIME;
			goto done;
		}
		m = fmax(m, all);
	}
	/* --range is in the legend's unit: percent, or degrees of shear (it
	 * was taken as a bare strain: '--range 20' drew a scale to 2000 %) */
	po.range = sn->range > 0 ? sn->range * colouring_unit(sn->colouring) :
	    colouring_range(sn->colouring, m);
	po.title = s.sc->name;
	po.supersample = PICTURE_SUPERSAMPLE;
	/* --size is the whole picture's: the band under the frames within it */
	if (sn->size_given && picture_fit(s.sc, &cam, &po, sn->ntargets, sn->w, sn->h,
	    PICTURE_MIN_SIDE) != 0) {
		fprintf(stderr, "drape snapshot: --size %s: the band under the frames takes %d "
		    "rows of the %d, leaving frames of %d x %d pixels; expected at least %d x %d: "
		    "a larger --size\n", sn->size_arg, sn->h - po.h, sn->h, po.w, po.h,
		    PICTURE_MIN_SIDE, PICTURE_MIN_SIDE);
		rc = EXIT_USAGE;
		goto done;
	}
	if (picture_strip(s.sc, s.cl, &cam, fr, sn->ntargets, &po, &rgb, &w, &h, &err) != 0 ||
	    png_write(sn->png, rgb, w, h, &err) != 0) {
		fprintf(stderr, "drape snapshot: %s\n", err.msg);
		rc = EXIT_RUNTIME;
	}
done:
	free(rgb);
	free(fr);
	free_shots(sh, sn->ntargets);
	return rc;
}

/* --frames K: K times from the start to the end of the run. */
static int
add_frames(struct snapshot *sn)
{
	struct source_state s;
	double end;
	long k;
	int rc;

	if (sn->frames == 0)
		return EXIT_OK;
	if (sn->replay) {
		struct source_position p;

		sn->src.position(sn->src.ctx, &p);
		sn->src.seek(sn->src.ctx, SOURCE_LAST, 0);
		sn->src.state(sn->src.ctx, &s);
		end = s.t;
		sn->src.seek(sn->src.ctx, SOURCE_FIRST, 0);
	} else {
		sn->src.state(sn->src.ctx, &s);
		end = s.t_end;
	}
	for (k = 0; k < sn->frames; k++)
		if ((rc = add_target(sn, true, 0, end * (double)k / (double)(sn->frames - 1))) !=
		    EXIT_OK)
			return rc;
	return EXIT_OK;
}

/* WxH, each from 1 to PICTURE_MAX_WIDTH (each kind's bounds are checked
 * later); 0, or -1. */
static int
parse_size(const char *arg, int *w, int *h)
{
	const char *x = strchr(arg, 'x');
	char side[32];
	long lw, lh;

	if (x == NULL || (size_t)(x - arg) >= sizeof side)
		return -1;
	memcpy(side, arg, (size_t)(x - arg));
	side[x - arg] = '\0';
	if (cmd_parse_long(side, 1, PICTURE_MAX_WIDTH, &lw) != 0 ||
	    cmd_parse_long(x + 1, 1, PICTURE_MAX_WIDTH, &lh) != 0)
		return -1;
	*w = (int)lw;
	*h = (int)lh;
	return 0;
}

/* One option's value into sn; an exit status. */
static int
take_option(struct snapshot *sn, int c, const char *arg)
{
	char *end, why[160];
	long steps;
	double t;
	int w = 0, h = 0;

	switch (c) {
	case 's':
		sn->have_step = true;
		if (cmd_parse_long(arg, 0, LONG_MAX, &steps) != 0)
			return bad("--step", arg, "a whole number from 0");
		return add_target(sn, false, steps, 0);
	case 't':
		sn->have_time = true;
		if (units_parse(arg, DIM_TIME, &t, 1, why, sizeof why) != 0 || !(t >= 0))
			return bad("--time", arg, "a time from 0, as 0.5 or 200ms");
		return add_target(sn, true, 0, t);
	case 'v':
		if ((sn->preset = view_preset_from_name(arg)) < 0)
			return bad("--view", arg, "front, side, top or iso");
		return EXIT_OK;
	case 'z':
		/* not sscanf's %d, whose overflow is undefined */
		if (parse_size(arg, &w, &h) != 0)
			return bad("--size", arg, "WxH, as 80x24 (characters) or 480x360 "
			    "(pixels, with --png)");
		sn->w = w;
		sn->h = h;
		sn->size_given = true;
		sn->size_arg = arg;
		return EXIT_OK;
	case 'p':
		sn->perspective = true;
		return EXIT_OK;
	case 'Z':
		sn->zoom = strtod(arg, &end);
		if (end == arg || *end != '\0' || !(sn->zoom >= 0.01 && sn->zoom <= 1000))
			return bad("--zoom", arg, "a factor from 0.01 to 1000 (1 frames the scene)");
		return EXIT_OK;
	case 'C':
		return parse_centre(sn, arg);
	case 'f':
		if (strcmp(arg, "cloth") != 0 && strcmp(arg, "scene") != 0)
			return bad("--frame", arg, "cloth or scene");
		sn->frame_scene = strcmp(arg, "scene") == 0;
		return EXIT_OK;
	case 'o':
		if (*arg == '\0')
			return bad("--png", arg, "a file name");
		sn->png = arg;
		return EXIT_OK;
	case 'S':
		sn->strip = true;
		return parse_strip(sn, arg);
	case 'F':
		if (cmd_parse_long(arg, 2, PICTURE_MAX_FRAMES, &sn->frames) != 0)
			return bad("--frames", arg, "a whole number of frames from 2 to 64");
		return EXIT_OK;
	case 'c':
		if ((c = colouring_from_name(arg)) < 0)
			return bad("--color", arg, "shade, strain, warp, weft, shear or contact");
		sn->colouring = (enum colouring)c;
		return EXIT_OK;
	case 'r':
		sn->range = strtod(arg, &end);
		if (end == arg || *end != '\0' || !(sn->range > 0) || !isfinite(sn->range))
			return bad("--range", arg, "a number above 0: percent of strain, or degrees "
			    "of shear");
		return EXIT_OK;
	case 'A': sn->glyphs = GLYPHS_ASCII; return EXIT_OK;
	case 'U': sn->glyphs = GLYPHS_BRAILLE; return EXIT_OK;
	case 'B': sn->glyphs = GLYPHS_BLOCKS; return EXIT_OK;
	case 'X': sn->sets[sn->nsets++] = arg; return EXIT_OK;
	}
	return EXIT_OK;
}

/* The options that go together, and the size for the kind of output
 * (given, or its default); an exit status. */
static int
check_options(struct snapshot *sn)
{
	bool strip = sn->strip || sn->frames > 0;
	long nframes = (long)sn->ntargets + sn->frames;

	if (sn->have_step + sn->have_time + strip > 1 ||
	    ((sn->have_step || sn->have_time) && sn->ntargets > 1)) {
		fprintf(stderr, "drape snapshot: give one --step or one --time, or a strip "
		    "(--strip, --frames)\n");
		return EXIT_USAGE;
	}
	if (sn->png == NULL && (strip || sn->colouring != COLOUR_SHADE || sn->range > 0)) {
		fprintf(stderr, "drape snapshot: --strip, --frames, --color and --range make a "
		    "picture: they need --png FILE\n");
		return EXIT_USAGE;
	}
	if (sn->png != NULL && sn->glyphs != GLYPHS_AUTO) {
		/* said, not ignored: the picture would not be what was asked */
		fprintf(stderr, "drape snapshot: --ascii, --unicode and --blocks choose the text "
		    "view's characters: not with --png\n");
		return EXIT_USAGE;
	}
	if (sn->range > 0 && !colouring_is_strain(sn->colouring)) {
		fprintf(stderr, "drape snapshot: --range is the scale of --color strain, warp, "
		    "weft or shear\n");
		return EXIT_USAGE;
	}
	if (sn->size_given && (sn->png == NULL ?
	    sn->w > SNAPSHOT_MAX_SIDE || sn->h > SNAPSHOT_MAX_SIDE :
	    sn->w < PICTURE_MIN_SIDE || sn->h < PICTURE_MIN_SIDE || sn->h > PICTURE_MAX_SIDE))
		return bad("--size", sn->size_arg, sn->png == NULL ?
		    "WxH, each from 1 to 1000 characters, as 80x24" :
		    "WxH, the whole picture's, from 16 to 16384 pixels wide and from 16 to 4096 "
		    "high, as 640x480");
	if (!sn->size_given) {
		sn->w = sn->png != NULL ? PICTURE_W : 80;
		sn->h = sn->png != NULL ? PICTURE_H : 24;
	}
	if (nframes < 1)
		nframes = 1;
	/* a given size is the whole picture's: its frames share the width */
	if (sn->png != NULL && sn->size_given && nframes <= PICTURE_MAX_FRAMES &&
	    (sn->w - (nframes - 1) * PICTURE_GAP) / nframes < PICTURE_MIN_SIDE) {
		fprintf(stderr, "drape snapshot: --size %s: %ld frames side by side leave each "
		    "under %d pixels wide: fewer frames, or a wider --size\n", sn->size_arg,
		    nframes, PICTURE_MIN_SIDE);
		return EXIT_USAGE;
	}
	if (sn->png != NULL && (nframes > PICTURE_MAX_FRAMES || (!sn->size_given &&
	    nframes * (sn->w + PICTURE_GAP) > PICTURE_MAX_WIDTH))) {
		fprintf(stderr, "drape snapshot: %ld frames of %d pixels are wider than %d "
		    "pixels: fewer frames, or a smaller --size\n", nframes, sn->w,
		    PICTURE_MAX_WIDTH);
		return EXIT_USAGE;
	}
	return EXIT_OK;
}

/* Fills sn from the command line; an exit status, or -1 after --help. */
static int
parse_options(int argc, char **argv, struct snapshot *sn)
{
	static const struct option longopts[] = {
		{ "step", required_argument, NULL, 's' },
		{ "time", required_argument, NULL, 't' },
		{ "view", required_argument, NULL, 'v' },
		{ "size", required_argument, NULL, 'z' },
		{ "perspective", no_argument, NULL, 'p' },
		{ "zoom", required_argument, NULL, 'Z' },
		{ "centre", required_argument, NULL, 'C' },
		{ "frame", required_argument, NULL, 'f' },
		{ "center", required_argument, NULL, 'C' },
		{ "png", required_argument, NULL, 'o' },
		{ "strip", required_argument, NULL, 'S' },
		{ "frames", required_argument, NULL, 'F' },
		{ "color", required_argument, NULL, 'c' },
		{ "range", required_argument, NULL, 'r' },
		{ "ascii", no_argument, NULL, 'A' },
		{ "unicode", no_argument, NULL, 'U' },
		{ "blocks", no_argument, NULL, 'B' },
		{ "set", required_argument, NULL, 'X' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	int c, rc;

	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "+h", longopts, NULL)) != -1) {
		if (c == 'h') {
			usage(stdout);
			return -1;
		}
		if (c == '?' || c == ':')
			return cmd_option_error("snapshot", argv);
		if ((rc = take_option(sn, c, optarg)) != EXIT_OK)
			return rc;
	}
	if (optind != argc - 1) {
		return cmd_usage_error("snapshot", "expected one scene or replay file");
	}
	sn->path = argv[optind];
	return check_options(sn);
}

int
cmd_snapshot(int argc, char **argv)
{
	struct snapshot sn;
	int rc;

	memset(&sn, 0, sizeof sn);
	sn.preset = VIEW_ISO;
	sn.glyphs = GLYPHS_AUTO;
	sn.colouring = COLOUR_SHADE;
	if ((sn.sets = calloc((size_t)argc, sizeof *sn.sets)) == NULL) {
		fprintf(stderr, "drape snapshot: out of memory\n");
		return EXIT_RUNTIME;
	}
	if ((rc = parse_options(argc, argv, &sn)) != EXIT_OK) {
		free(sn.targets);
		free(sn.sets);
		return rc < 0 ? EXIT_OK : rc;
	}
	/* Unicode on a UTF-8 terminal; piped or pasted text stays ASCII unless
	 * asked for */
	if (sn.glyphs == GLYPHS_AUTO)
		sn.glyphs = glyphs_resolve(GLYPHS_AUTO, isatty(STDOUT_FILENO) && glyphs_locale_utf8());
	if ((rc = open_input(&sn)) == EXIT_OK && (rc = add_frames(&sn)) == EXIT_OK)
		rc = sn.png != NULL ? snapshot_png(&sn) : snapshot_text(&sn);
	close_input(&sn);
	free(sn.targets);
	free(sn.sets);
	return rc;
}
