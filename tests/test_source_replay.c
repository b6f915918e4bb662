/* test_source_replay.c: the replay source on the shipped tablecloth
 * (2265 steps, keyframes every 1000 steps and at the end, frames at 50 per
 * second): frame, keyframe and step seeking, the step's events and
 * statistics, the history for the inspector, velocities estimated between
 * frames and exact at keyframes, a damaged chunk skipped, a cut file, the
 * status line; and a live run recording itself between record(path) and
 * record(NULL). */
#include <unistd.h>

#include "testutil.h"

#include "record.h"
#include "replay.h"
#include "screen.h"
#include "tui.h"
#include "source.h"

/* the first 0.3 s of the tablecloth under RK4 (2265 steps in 9 steps
 * chunks), as replays/tablecloth.drr shipped before the fast path */
#define TABLECLOTH TOP_SRCDIR "/tests/data/tablecloth-rk4.drr"

static long
cursor(struct source *src)
{
	struct source_state s;

	src->state(src->ctx, &s);
	return s.step;
}

static struct source_position
where(struct source *src)
{
	struct source_position p;

	src->position(src->ctx, &p);
	return p;
}

static void
open_tablecloth(struct source *src, struct source_replay *sr)
{
	struct drape_err err;

	if (source_replay_open(src, sr, TABLECLOTH, &err) != 0)
		fail_msg("source_replay_open: %s", err.msg);
}

/* The history the source gives at cursor step c (every event of the steps
 * before c, per node the latest EVLOG_PER_NODE and the count), against
 * one made from every steps chunk of the file, read whole. */
static void
history_equals_truth(struct source *src, const struct replay *rp, int nodes, long c)
{
	struct evlog got, want;
	struct drape_err err;
	size_t i, k;
	int p;

	assert_int_equal(evlog_init(&got, nodes), 0);
	assert_int_equal(evlog_init(&want, nodes), 0);
	src->history(src->ctx, &got);
	for (i = 0; i < rp->nchunks; i++) {
		struct replay_steps ss;

		if (rp->chunk[i].kind != REPLAY_STEPS)
			continue;
		assert_int_equal(replay_read_steps(rp, i, &ss, &err), 0);
		for (k = 0; k < ss.nev && ss.ev[k].step < c; k++)
			evlog_add(&want, &ss.ev[k], 1);
		replay_steps_free(&ss);
	}
	assert_int_equal(got.total, want.total);
	for (p = 0; p < nodes; p++) {
		int j;

		assert_int_equal(got.count[p], want.count[p]);
		for (j = 0; j < EVLOG_PER_NODE; j++) {
			const struct contact_event *a = evlog_get(&got, p, j), *b = evlog_get(&want, p, j);

			assert_true((a == NULL) == (b == NULL));
			if (a != NULL)
				assert_memory_equal(a, b, sizeof *a);
		}
	}
	evlog_free(&got);
	evlog_free(&want);
}

/* The history is kept as the cursor moves (forward: carried on; back:
 * from the nearest mark, source_replay.c), never all the events at once:
 * at every cursor of a scrambled walk, forward and back, across the
 * steps chunks, it equals the whole file's. */
static void
history_at_any_step(void **state)
{
	static const long walk[] = { 0, 151, 1000, 300, 2265, 2264, 257, 255, 256, 1999, 2000, 5,
	    1500, 0, 2265 };
	struct source src;
	struct source_replay sr;
	struct source_state s;
	struct replay rp;
	struct drape_err err;
	size_t i;

	(void)state;
	open_tablecloth(&src, &sr);
	if (replay_open(&rp, TABLECLOTH, &err) != 0)
		fail_msg("%s", err.msg);
	assert_true(rp.nstep_chunks >= 8);	/* the walk crosses chunks */
	src.state(src.ctx, &s);
	for (i = 0; i < sizeof walk / sizeof walk[0]; i++) {
		assert_true(src.seek(src.ctx, SOURCE_GOTO, walk[i]) || walk[i] == cursor(&src));
		assert_int_equal(cursor(&src), walk[i]);
		history_equals_truth(&src, &rp, s.cl->n, walk[i]);
	}
	replay_close(&rp);
	source_replay_close(&sr);
}

static void
keyframes_and_ends(void **state)
{
	struct source src;
	struct source_replay sr;
	struct source_position p;
	char why[200];

	(void)state;
	open_tablecloth(&src, &sr);
	assert_null(src.record);
	p = where(&src);
	assert_int_equal(p.first, 0);
	assert_int_equal(p.last, 2265);
	assert_int_equal(p.frame, 1);
	/* 16 frames, and the keyframes at 1000 and 2000 between them (those at
	 * 0 and 2265 share a frame's step) */
	assert_int_equal(p.frames, 18);
	assert_int_equal(cursor(&src), 0);
	assert_false(src.seek(src.ctx, SOURCE_FRAME_PREV, 0));
	assert_false(src.seek(src.ctx, SOURCE_KEY_PREV, 0));
	assert_true(src.seek(src.ctx, SOURCE_KEY_NEXT, 0));
	assert_int_equal(cursor(&src), 1000);
	assert_true(src.seek(src.ctx, SOURCE_KEY_NEXT, 0));
	assert_int_equal(cursor(&src), 2000);
	assert_true(src.seek(src.ctx, SOURCE_KEY_NEXT, 0));
	assert_int_equal(cursor(&src), 2265);
	assert_false(src.seek(src.ctx, SOURCE_KEY_NEXT, 0));
	assert_false(src.seek(src.ctx, SOURCE_FRAME_NEXT, 0));
	assert_true(src.done(src.ctx));
	assert_int_equal(src.step(src.ctx, why, sizeof why), SOURCE_END);
	assert_int_equal(where(&src).frame, 18);
	assert_true(src.seek(src.ctx, SOURCE_KEY_PREV, 0));
	assert_int_equal(cursor(&src), 2000);
	assert_true(src.seek(src.ctx, SOURCE_FIRST, 0));
	assert_int_equal(cursor(&src), 0);
	assert_false(src.done(src.ctx));
	assert_true(src.seek(src.ctx, SOURCE_LAST, 0));
	assert_int_equal(cursor(&src), 2265);
	assert_false(src.seek(src.ctx, SOURCE_LAST, 0));	/* already there */
	source_replay_close(&sr);
}

static void
frames_and_steps(void **state)
{
	struct source src;
	struct source_replay sr;
	struct source_position p;
	struct source_state s;
	long f, g;
	char why[200];

	(void)state;
	open_tablecloth(&src, &sr);
	/* a frame every 0.02 s of a 0.000132486 s step: 151 steps on */
	assert_int_equal(src.step(src.ctx, why, sizeof why), SOURCE_STEPPED);
	assert_int_equal(cursor(&src), 151);
	assert_true(src.seek(src.ctx, SOURCE_FRAME_NEXT, 0));
	assert_int_equal(cursor(&src), 302);
	assert_true(src.seek(src.ctx, SOURCE_FRAME_PREV, 0));
	assert_int_equal(cursor(&src), 151);
	/* a step between frames: the frame at or before it */
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 1500));
	p = where(&src);
	assert_int_equal(cursor(&src), 1500);
	f = p.frame_step;
	assert_true(f < 1500 && f > 1500 - 152);
	src.state(src.ctx, &s);
	assert_double_equal(s.t, 1500 * sr.rp.meta.dt_set, 1e-9);	/* the step's own time */
	assert_true(src.seek(src.ctx, SOURCE_FRAME_NEXT, 0));
	g = cursor(&src);
	assert_true(g > 1500 && g - f <= 152);
	assert_int_equal(where(&src).frame, p.frame + 1);
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 1500));
	assert_true(src.seek(src.ctx, SOURCE_FRAME_PREV, 0));
	assert_int_equal(cursor(&src), f);
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 1500));
	assert_true(src.seek(src.ctx, SOURCE_KEY_PREV, 0));
	assert_int_equal(cursor(&src), 1000);
	/* clamped */
	assert_true(src.seek(src.ctx, SOURCE_GOTO, -5));
	assert_int_equal(cursor(&src), 0);
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 1L << 40));
	assert_int_equal(cursor(&src), 2265);
	source_replay_close(&sr);
}

static void
events_stats_and_state(void **state)
{
	struct source src;
	struct source_replay sr;
	struct source_state s;
	struct source_stats ss;
	struct evlog log;
	const struct contact_event *ev;
	size_t nev, k;
	long before;
	vec3 f;

	(void)state;
	open_tablecloth(&src, &sr);
	ev = src.events(src.ctx, &nev);
	assert_int_equal(nev, 0);
	src.stats(src.ctx, &ss);
	assert_true(ss.active);
	assert_int_equal(ss.total->n[STAT_CONTACTS + CONTACT_OBSTACLE], 0);

	/* at step 1000, the events of step 999 (135 on the table) */
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 1000));
	ev = src.events(src.ctx, &nev);
	assert_int_equal(nev, 135);
	for (k = 0; k < nev; k++)
		assert_int_equal(ev[k].step, 999);
	src.stats(src.ctx, &ss);
	assert_int_equal(ss.step->n[STAT_CONTACTS + CONTACT_OBSTACLE], 135);
	assert_true(ss.total->n[STAT_CONTACTS + CONTACT_OBSTACLE] > 135);
	/* a keyframe: the exact state, and so the force */
	src.state(src.ctx, &s);
	assert_null(s.v_note);
	assert_true(src.force(src.ctx, 312, &f));

	assert_int_equal(evlog_init(&log, s.cl->n), 0);
	src.history(src.ctx, &log);
	before = log.total;
	assert_true(before >= 135);
	assert_int_equal(evlog_get(&log, ev[0].node, 0)->step, 999);
	/* every event, at the end */
	assert_true(src.seek(src.ctx, SOURCE_LAST, 0));
	evlog_clear(&log);
	src.history(src.ctx, &log);
	assert_int_equal(log.total, 134076);	/* as drape info counts them */
	evlog_free(&log);

	/* a frame: positions only, velocities their difference */
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 1057));
	src.state(src.ctx, &s);
	assert_non_null(s.v_note);
	assert_false(src.force(src.ctx, 312, &f));
	for (k = 0; k < 3 * (size_t)s.cl->n; k++)
		assert_true(isfinite(s.v[k]));
	source_replay_close(&sr);
}

static void
screen_of_a_replay(void **state)
{
	struct source src;
	struct source_replay sr;
	struct source_state s;
	struct source_position p;
	struct status_info si;
	struct evlog log;
	struct text t;
	char line[TEXT_WIDTH];

	(void)state;
	open_tablecloth(&src, &sr);
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 1500));
	src.state(src.ctx, &s);
	src.position(src.ctx, &p);
	si = (struct status_info){ &s, 0, "replay", "1x", "no", &p };
	screen_status(line, 80, &si);
	assert_true(strlen(line) <= 80);
	assert_non_null(strstr(line, "tablecloth-rk4.drr replay step 1500 "));
	assert_non_null(strstr(line, "frame 11/18@1359"));
	assert_non_null(strstr(line, " 1x"));
	screen_status(line, 150, &si);
	assert_non_null(strstr(line, "step 1500 of 2265"));
	assert_int_equal(evlog_init(&log, s.cl->n), 0);
	text_init(&t, 30);
	screen_node(&t, &s, 312, NULL, &log);
	assert_non_null(strstr(t.line[2], "v~"));
	assert_string_equal(t.line[4], "v: frame differences");
	text_init(&t, 60);
	tui_help(&t, true);
	assert_true(t.n > 10);
	assert_true(t.n <= 24 - 1);	/* all of it at 80 x 24, under the top line */
	evlog_free(&log);
	source_replay_close(&sr);
}

/* A frames chunk with a flipped byte: the rest shows. */
static void
damaged_chunk(void **state)
{
	struct replay rp;
	struct drape_err err;
	struct source src;
	struct source_replay sr;
	char path[] = "/tmp/drape-test-XXXXXX";
	unsigned char *buf;
	long len;
	size_t i;
	uint64_t at = 0;
	FILE *f;
	int fd;

	(void)state;
	assert_int_equal(replay_open(&rp, TABLECLOTH, &err), 0);
	for (i = 0; i < rp.nchunks && at == 0; i++)
		if (rp.chunk[i].kind == REPLAY_FRAMES)
			at = rp.chunk[i].offset + 32 + rp.chunk[i].comp_len / 2;
	replay_close(&rp);
	assert_true(at > 0);
	assert_non_null(f = fopen(TABLECLOTH, "rb"));
	assert_int_equal(fseek(f, 0, SEEK_END), 0);
	assert_true((len = ftell(f)) > 0);
	rewind(f);
	assert_non_null(buf = malloc((size_t)len));
	assert_int_equal(fread(buf, 1, (size_t)len, f), (size_t)len);
	fclose(f);
	buf[at] ^= 0x40;
	assert_true((fd = mkstemp(path)) >= 0);
	assert_non_null(f = fdopen(fd, "wb"));
	assert_int_equal(fwrite(buf, 1, (size_t)len, f), (size_t)len);
	assert_int_equal(fclose(f), 0);
	free(buf);

	if (source_replay_open(&src, &sr, path, &err) != 0)
		fail_msg("a damaged frames chunk: %s", err.msg);
	assert_int_equal(sr.rp.nbad, 1);
	assert_true(where(&src).frames < 18);
	assert_true(src.seek(src.ctx, SOURCE_LAST, 0));
	assert_int_equal(cursor(&src), 2265);
	assert_true(src.seek(src.ctx, SOURCE_KEY_PREV, 0));
	assert_int_equal(cursor(&src), 2000);
	source_replay_close(&sr);
	unlink(path);
}

/* Cut in the middle, as a killed run leaves it: the whole chunks show. */
static void
cut_file(void **state)
{
	struct drape_err err;
	struct source src;
	struct source_replay sr;
	struct source_position p;
	char path[] = "/tmp/drape-test-XXXXXX";
	unsigned char *buf;
	long len;
	FILE *f;
	int fd;

	(void)state;
	assert_non_null(f = fopen(TABLECLOTH, "rb"));
	assert_int_equal(fseek(f, 0, SEEK_END), 0);
	assert_true((len = ftell(f)) > 0);
	rewind(f);
	assert_non_null(buf = malloc((size_t)len));
	assert_int_equal(fread(buf, 1, (size_t)len, f), (size_t)len);
	fclose(f);
	assert_true((fd = mkstemp(path)) >= 0);
	assert_non_null(f = fdopen(fd, "wb"));
	assert_int_equal(fwrite(buf, 1, (size_t)len / 2, f), (size_t)len / 2);
	assert_int_equal(fclose(f), 0);
	free(buf);

	if (source_replay_open(&src, &sr, path, &err) != 0)
		fail_msg("a cut replay: %s", err.msg);
	assert_true(sr.rp.cut);
	p = where(&src);
	assert_int_equal(p.first, 0);
	assert_true(p.last > 0 && p.last < 2265);
	assert_true(src.seek(src.ctx, SOURCE_LAST, 0));
	assert_int_equal(cursor(&src), p.last);
	/* its frames were still pending: the keyframes at 0 and 1000 show */
	assert_int_equal(p.frames, 2);
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 500));
	assert_int_equal(where(&src).frame_step, 0);
	assert_true(src.seek(src.ctx, SOURCE_FRAME_NEXT, 0));
	assert_int_equal(cursor(&src), 1000);
	assert_true(src.seek(src.ctx, SOURCE_FRAME_NEXT, 0));	/* the steps after it */
	assert_int_equal(cursor(&src), p.last);
	assert_int_equal(where(&src).frame_step, 1000);
	source_replay_close(&sr);
	unlink(path);
}

/* A live run records itself between record(path) and record(NULL); the
 * replay then plays from the step it started at to the step it stopped. */
static void
live_run_records(void **state)
{
	struct scene sc;
	struct stepper *st;
	struct drape_err err;
	struct source live, src;
	struct source_live lv;
	struct source_replay sr;
	char path[] = "/tmp/drape-test-XXXXXX", why[600];
	const char *error;
	int k, fd;

	(void)state;
	assert_true((fd = mkstemp(path)) >= 0);
	close(fd);
	load_shipped(&sc, SCENE_DIR "hanging.scene");
	assert_non_null(st = stepper_new(&sc, &err));
	source_live(&live, &lv, st);
	assert_null(live.seek);
	assert_int_equal(live.step(live.ctx, why, sizeof why), SOURCE_STEPPED);
	assert_null(live.recording(live.ctx, NULL));
	assert_int_equal(live.record(live.ctx, path, why, sizeof why), 0);
	assert_string_equal(live.recording(live.ctx, &error), path);
	assert_null(error);
	assert_int_equal(live.record(live.ctx, path, why, sizeof why), -1);
	assert_non_null(strstr(why, "already recording"));
	for (k = 0; k < 5; k++)
		assert_int_equal(live.step(live.ctx, why, sizeof why), SOURCE_STEPPED);
	assert_int_equal(live.record(live.ctx, NULL, why, sizeof why), 0);
	assert_null(live.recording(live.ctx, NULL));
	assert_int_equal(live.step(live.ctx, why, sizeof why), SOURCE_STEPPED);
	source_live_free(&lv);
	stepper_free(st);
	scene_free(&sc);

	if (source_replay_open(&src, &sr, path, &err) != 0)
		fail_msg("the live run's replay: %s", err.msg);
	assert_true((sr.rp.hdr.flags & REPLAY_CLOSED) != 0);
	assert_int_equal(sr.rp.nbad, 0);
	assert_int_equal(where(&src).first, 1);
	assert_int_equal(where(&src).last, 6);
	assert_true(src.seek(src.ctx, SOURCE_KEY_NEXT, 0));	/* the keyframe at the stop */
	assert_int_equal(cursor(&src), 6);
	source_replay_close(&sr);
	unlink(path);
}

/* Steps st to its end, each step recorded by rec, which is then closed. */
static void
record_to_end(struct recorder *rec, struct stepper *st)
{
	struct drape_err err;

	while (!stepper_done(st)) {
		step_once(st);
		if (record_step(rec, st, &err) != 0)
			fail_msg("%s", err.msg);
	}
	if (record_close(rec, st, &err) != 0)
		fail_msg("%s", err.msg);
}

/* The statistics a replay's viewer adds up from the recorded steps equal
 * the live run's totals, counter for counter (and the hash's sums), on the
 * tablecloth's first 0.15 s. */
static void
replay_totals_equal_live(void **state)
{
	struct scene sc;
	struct stepper *st;
	struct recorder rec;
	struct drape_err err;
	struct collide_stats live;
	struct source src;
	struct source_replay sr;
	struct source_stats ss;
	char path[] = "/tmp/drape-totals-XXXXXX";
	int fd, k;

	(void)state;
	assert_true((fd = mkstemp(path)) >= 0);
	close(fd);
	load_shipped(&sc, SCENE_DIR "tablecloth.scene");
	sc.integrator = INTEG_RK4;	/* the chapter's method: thousands of contacts */
	sc.col.broad = BROAD_GRID;
	sc.duration = 0.15;
	st = new_stepper(&sc);
	if (record_open(&rec, path, st, 500, 0, false, &err) != 0)
		fail_msg("%s", err.msg);
	record_to_end(&rec, st);
	live = *report_of(st).total;
	assert_true(live.n[STAT_CONTACTS + CONTACT_OBSTACLE] > 1000);
	assert_true(live.n[STAT_FILLS] > 10);

	if (source_replay_open(&src, &sr, path, &err) != 0)
		fail_msg("%s", err.msg);
	assert_true(src.seek(src.ctx, SOURCE_LAST, 0));
	assert_int_equal(cursor(&src), report_of(st).step);
	src.stats(src.ctx, &ss);
	for (k = 0; k < STAT_COUNT; k++)
		if (ss.total->n[k] != live.n[k])
			fail_msg("%s: the replay's total is %ld, the live run's %ld",
			    stat_field[k].name, ss.total->n[k], live.n[k]);
	assert_memory_equal(&ss.total->hash, &live.hash, sizeof live.hash);
	print_message("tablecloth 0.15 s: %ld steps, %ld corrections, %ld fills; the replay's "
	    "totals are the live run's\n", report_of(st).step, live.n[STAT_CORRECTIONS],
	    live.n[STAT_FILLS]);
	source_replay_close(&sr);
	stepper_free(st);
	scene_free(&sc);
	unlink(path);
}

/* The tablecloth's first 0.6 s (the fast path: 60 steps) recorded into
 * path, its events stored or their digest, in steps chunks of 16 steps
 * and keyframes every 25 steps: chunks across keyframes. */
static void
record_tablecloth(const char *path, bool stored)
{
	struct scene sc;
	struct stepper *st;
	struct recorder rec;
	struct drape_err err;

	load_shipped(&sc, SCENE_DIR "tablecloth.scene");
	sc.duration = 0.6;
	st = new_stepper(&sc);
	if (record_open(&rec, path, st, 25, 0, stored, &err) != 0)
		fail_msg("%s", err.msg);
	rec.w.steps_per_chunk = 16;
	record_to_end(&rec, st);
	stepper_free(st);
	scene_free(&sc);
}

/* The inspector on a replay whose events are a digest: at every cursor
 * of a scrambled walk, the step's events and the history are those of
 * the same run recorded with its events stored (recomputed from the
 * keyframe before, or carried on from the last chunk), and no event is
 * said unavailable. */
static void
digest_events_as_stored(void **state)
{
	static const long walk[] = { 0, 40, 17, 60, 59, 33, 16, 15, 1, 50, 26, 25, 60 };
	char dpath[] = "/tmp/drape-digest-XXXXXX", spath[] = "/tmp/drape-stored-XXXXXX";
	struct source src, srcs;
	struct source_replay sr, srs;
	struct source_state s;
	struct replay rp;
	struct drape_err err;
	const struct contact_event *ed, *es;
	size_t i, k, nd, ns, kinds = 0;
	int fd;

	(void)state;
	assert_true((fd = mkstemp(dpath)) >= 0);
	close(fd);
	assert_true((fd = mkstemp(spath)) >= 0);
	close(fd);
	record_tablecloth(dpath, false);
	record_tablecloth(spath, true);
	if (source_replay_open(&src, &sr, dpath, &err) != 0 ||
	    source_replay_open(&srcs, &srs, spath, &err) != 0)
		fail_msg("%s", err.msg);
	for (k = 0; k < sr.rp.nchunks; k++)
		kinds += sr.rp.chunk[k].kind == REPLAY_STEPS_DIGEST;
	assert_true(kinds >= 4);
	if (replay_open(&rp, spath, &err) != 0)
		fail_msg("%s", err.msg);
	src.state(src.ctx, &s);
	for (i = 0; i < sizeof walk / sizeof walk[0]; i++) {
		assert_true(src.seek(src.ctx, SOURCE_GOTO, walk[i]) || walk[i] == cursor(&src));
		assert_true(srcs.seek(srcs.ctx, SOURCE_GOTO, walk[i]) || walk[i] == cursor(&srcs));
		assert_int_equal(cursor(&src), walk[i]);
		ed = src.events(src.ctx, &nd);
		es = srcs.events(srcs.ctx, &ns);
		assert_int_equal(nd, ns);
		if (nd > 0)
			assert_memory_equal(ed, es, nd * sizeof *ed);
		history_equals_truth(&src, &rp, s.cl->n, walk[i]);
		src.state(src.ctx, &s);
		assert_null(s.ev_note);
	}
	replay_close(&rp);
	source_replay_close(&sr);

	/* the first keyframe damaged: the steps before the next one have
	 * no keyframe to be recomputed from, and the screen says so */
	{
		FILE *f = fopen(dpath, "r+b");
		const struct replay_chunk *c;

		if (replay_open(&rp, dpath, &err) != 0)
			fail_msg("%s", err.msg);
		c = &rp.chunk[replay_find_keyframe(&rp, 0)];
		assert_int_equal(c->first_step, 0);
		assert_non_null(f);
		assert_int_equal(fseek(f, (long)c->offset + 40, SEEK_SET), 0);
		assert_int_equal(fputc(0x5a ^ 0xff, f), 0x5a ^ 0xff);
		assert_int_equal(fclose(f), 0);
		replay_close(&rp);
	}
	if (source_replay_open(&src, &sr, dpath, &err) != 0)
		fail_msg("%s", err.msg);
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 14));
	assert_true(srcs.seek(srcs.ctx, SOURCE_GOTO, 14));
	srcs.events(srcs.ctx, &ns);
	assert_true(ns > 0);	/* the cloth reaches the table */
	src.events(src.ctx, &nd);
	assert_int_equal(nd, 0);
	src.state(src.ctx, &s);
	assert_non_null(s.ev_note);
	assert_non_null(strstr(s.ev_note, "the events of steps 1 to 16 are unavailable: no "
	    "intact keyframe at or before step 0"));
	/* steps 48 to 59 from the keyframe at 25: there */
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 55));
	assert_true(srcs.seek(srcs.ctx, SOURCE_GOTO, 55));
	ed = src.events(src.ctx, &nd);
	es = srcs.events(srcs.ctx, &ns);
	assert_int_equal(nd, ns);
	assert_true(nd > 0);
	assert_memory_equal(ed, es, nd * sizeof *ed);
	source_replay_close(&sr);
	source_replay_close(&srs);
	unlink(dpath);
	unlink(spath);
}

#define SHIPPED_TABLECLOTH TOP_SRCDIR "/replays/tablecloth.drr"

/* Issue 30: a seek took 0.3-0.6 s: stepping across a steps chunk's
 * boundary and back recomputed both chunks' events (a digest's) at every
 * step, 0.12 s a frame; the last few chunks are kept. */
static void
seeks_keep_the_events_recomputed(void **state)
{
	struct source src;
	struct source_replay sr;
	struct drape_err err;
	struct source_state s;
	long before;
	int k;

	(void)state;
	if (source_replay_open(&src, &sr, SHIPPED_TABLECLOTH, &err) != 0)
		fail_msg("%s", err.msg);
	/* 150 is the first step of a steps chunk: 149's events are the last
	 * of the one before */
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 150));
	assert_true(src.seek(src.ctx, SOURCE_FRAME_NEXT, 0));
	before = sr.re.steps;
	for (k = 0; k < 10; k++)
		assert_true(src.seek(src.ctx, k % 2 ? SOURCE_FRAME_NEXT : SOURCE_FRAME_PREV, 0));
	src.state(src.ctx, &s);
	assert_int_equal(s.step, 152);
	print_message("10 frames across a chunk's boundary: %ld steps recomputed\n",
	    sr.re.steps - before);
	assert_int_equal(sr.re.steps, before);
	/* where a seek goes, without going */
	assert_int_equal(src.target(src.ctx, SOURCE_FRAME_NEXT, 0, 150), 152);
	assert_int_equal(src.target(src.ctx, SOURCE_FRAME_NEXT, 0, 152), 154);
	assert_int_equal(src.target(src.ctx, SOURCE_LAST, 0, 3), 200);
	assert_int_equal(src.target(src.ctx, SOURCE_FRAME_PREV, 0, 0), -1);
	assert_int_equal(src.target(src.ctx, SOURCE_GOTO, 99, 0), 99);
	src.state(src.ctx, &s);
	assert_int_equal(s.step, 152);	/* unmoved */
	source_replay_close(&sr);
}

/* Issue 30: at step 36 the inspector said "none yet" of a node that
 * drape events gave events in step 36; and a live run's inspector and
 * its replay's labelled steps one apart from the status line. The step
 * from state k to k + 1 is now step k + 1 everywhere: in the inspector,
 * drape events and the status line once it is done. */
static void
step_labels_agree(void **state)
{
	struct source src, live;
	struct source_replay sr;
	struct source_live lv;
	struct drape_err err;
	struct source_state s;
	struct scene sc;
	struct stepper *st;
	struct evlog log;
	struct text t;
	const struct contact_event *ev;
	char why[300];
	size_t n, i;
	int k;

	(void)state;
	if (source_replay_open(&src, &sr, SHIPPED_TABLECLOTH, &err) != 0)
		fail_msg("%s", err.msg);
	load_shipped(&sc, SCENE_DIR "tablecloth.scene");
	st = new_stepper(&sc);
	source_live(&live, &lv, st);
	for (k = 1; k <= 43; k++) {
		assert_int_equal(live.step(live.ctx, why, sizeof why), SOURCE_STEPPED);
		assert_true(src.seek(src.ctx, SOURCE_GOTO, k));
		live.state(live.ctx, &s);
		assert_int_equal(s.step, k);
		ev = live.events(live.ctx, &n);
		for (i = 0; i < n; i++)
			assert_int_equal(step_shown(ev[i].step), k);
		ev = src.events(src.ctx, &n);
		for (i = 0; i < n; i++)
			assert_int_equal(step_shown(ev[i].step), k);
	}
	/* node 538: edge-edge contacts in step 42; in 43 a node-face
	 * contact and then five edge-edge ones, of which the log keeps the
	 * latest EVLOG_PER_NODE: four edge-edge listed, no node-face */
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 42));
	src.state(src.ctx, &s);
	assert_int_equal(evlog_init(&log, s.cl->n), 0);
	src.history(src.ctx, &log);
	text_init(&t, 40);
	screen_node(&t, &s, 538, NULL, &log);
	for (i = 0; i < (size_t)t.n && strstr(t.line[i], "42 e-e") == NULL; i++)
		;
	if (i == (size_t)t.n)
		fail_msg("step 42: node 538's edge-edge contact of step 42 is not listed");
	assert_true(src.seek(src.ctx, SOURCE_GOTO, 43));
	src.state(src.ctx, &s);
	evlog_clear(&log);
	src.history(src.ctx, &log);
	text_init(&t, 40);
	screen_node(&t, &s, 538, NULL, &log);
	for (i = 0, k = 0; i < (size_t)t.n; i++)
		k += strstr(t.line[i], "43 n-f") != NULL;
	assert_int_equal(k, 0);
	for (i = 0, k = 0; i < (size_t)t.n; i++)
		k += strstr(t.line[i], "43 e-e") != NULL;
	assert_int_equal(k, 4);
	evlog_free(&log);
	source_live_free(&lv);
	stepper_free(st);
	scene_free(&sc);
	source_replay_close(&sr);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(keyframes_and_ends),
		cmocka_unit_test(history_at_any_step),
		cmocka_unit_test(frames_and_steps),
		cmocka_unit_test(events_stats_and_state),
		cmocka_unit_test(screen_of_a_replay),
		cmocka_unit_test(damaged_chunk),
		cmocka_unit_test(cut_file),
		cmocka_unit_test(live_run_records),
		cmocka_unit_test(replay_totals_equal_live),
		cmocka_unit_test(digest_events_as_stored),
		cmocka_unit_test(seeks_keep_the_events_recomputed),
		cmocka_unit_test(step_labels_agree),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
