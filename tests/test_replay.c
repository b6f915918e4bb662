/* test_replay.c: replay files: the frame codec; a round trip (keyframes
 * bit for bit, frames within float32 rounding, the same events and
 * statistics); a small replay cut at every byte and with a bit flipped in
 * every chunk; resuming from every keyframe gives the original state hash,
 * and a state or replay that does not match is refused;
 * and, through the binary: info, events --node, PC2 export, resume, a
 * SIGTERM mid-run, bad arguments, and the shipped replays. */
#include <math.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "frame_codec.h"
#include "record.h"
#include "replay.h"
#include "replay_events.h"
#include "replay_run.h"
#include "testutil.h"
#include "runbin.h"

/* A 4 x 4 cloth dropped onto the floor, and what it collides with. */
#define TINY_CLOTH \
    "[cloth]\nnodes = 4 4\nspacing = 10 mm\norigin = 0 3 0 mm\norientation = +x +z\n" \
    "weight = 150 g/m2\nthickness = 0.55 mm\nmodulus_warp = 0.45 MPa\n" \
    "modulus_weft = 0.30 MPa\nshear_modulus = 9 kPa\nbending_warp = 3 uN*m\n" \
    "bending_weft = 2 uN*m\nvelocity = 0 -0.3 0 m/s\n" \
    "[plane]\npoint = 0 0 0 m\n" \
    "[collision]\nself = on\nbroad = grid\nnarrow = ccd\nposition = slide\n"

static const char tiny_scene[] =
    "# A 4 x 4 cloth dropped onto the floor: a small replay for the tests.\n"
    "[simulation]\nname = tiny\nduration = 25 ms\ndt = auto\noutput_rate = 200 Hz\n" TINY_CLOTH;

#define KEY_EVERY 40

/* Everything a recorded run did, kept in memory to compare with. */
struct truth {
	long nsteps;		/* steps taken */
	double *y;		/* the state after each step, (nsteps + 1) * 6n */
	struct contact_event *ev;
	size_t nev;
	struct collide_stats *st;	/* per step */
	uint64_t hash;		/* at the end */
	int n;
};

static char replay_path[700], lossy_path[700], stored_path[700];

/* Recordings store their events (--events stored) rather than a digest;
 * their steps chunks hold this many steps at most (0: the writer's). */
static bool rec_stored;
static size_t rec_steps_per_chunk;

/* The tiny run as round_trip recorded it: what every chunk recomputed
 * from a file of it must give (read_all), or nothing. */
static struct truth tiny_truth;

static void
path_in_dir(char *out, size_t len, const char *name)
{
	snprintf(out, len, "%s/%s", dir, name);
}

/* The fast path on the same cloth: 60 steps of 5 ms, so that its keyframes
 * are several and its contacts with the floor and itself many. */
static const char tiny_fast_scene[] =
    "[simulation]\nname = tiny-fast\nduration = 0.3 s\ndt = 5 ms\nintegrator = fast\n"
    "output_rate = 200 Hz\n" TINY_CLOTH;

static void record_text_p(struct truth *tr, const char *path, const char *text, int key_every,
    double precision);

static void
record_text(struct truth *tr, const char *path, const char *text, int key_every)
{
	record_text_p(tr, path, text, key_every, 0);
}

static void
record_tiny(struct truth *tr, const char *path)
{
	record_text(tr, path, tiny_scene, KEY_EVERY);
}

static void
record_text_p(struct truth *tr, const char *path, const char *text, int key_every,
    double precision)
{
	struct scene sc;
	struct stepper *st;
	struct recorder rec;
	struct drape_err err;
	struct step_failure bl;
	size_t n6, cap = 0;

	parse_text(&sc, text);
	st = new_stepper(&sc);
	memset(tr, 0, sizeof *tr);
	tr->n = cloth_of(st)->n;
	n6 = 6 * (size_t)cloth_of(st)->n;
	tr->y = malloc(n6 * sizeof *tr->y);
	assert_non_null(tr->y);
	memcpy(tr->y, state_y(st), n6 * sizeof *tr->y);
	if (record_open(&rec, path, st, key_every, precision, rec_stored, &err) != 0)
		fail_msg("record_open: %s", err.msg);
	if (rec_steps_per_chunk > 0)
		rec.w.steps_per_chunk = rec_steps_per_chunk;
	while (!stepper_done(st)) {
		if (stepper_step(st, &bl) != STEP_OK)
			fail_msg("blow-up: %s", bl.why);
		tr->nsteps++;
		tr->y = realloc(tr->y, (size_t)(tr->nsteps + 1) * n6 * sizeof *tr->y);
		tr->st = realloc(tr->st, (size_t)tr->nsteps * sizeof *tr->st);
		assert_true(tr->y != NULL && tr->st != NULL);
		memcpy(tr->y + (size_t)tr->nsteps * n6, state_y(st), n6 * sizeof *tr->y);
		tr->st[tr->nsteps - 1] = *report_of(st).last;
		if (tr->nev + report_of(st).nev > cap) {
			cap = 2 * (tr->nev + report_of(st).nev);
			tr->ev = realloc(tr->ev, cap * sizeof *tr->ev);
			assert_non_null(tr->ev);
		}
		if (report_of(st).nev > 0)
			memcpy(tr->ev + tr->nev, report_of(st).ev, report_of(st).nev * sizeof *tr->ev);
		tr->nev += report_of(st).nev;
		if (record_step(&rec, st, &err) != 0)
			fail_msg("record_step: %s", err.msg);
	}
	if (record_close(&rec, st, &err) != 0)
		fail_msg("record_close: %s", err.msg);
	tr->hash = stepper_hash(st);
	stepper_free(st);
	scene_free(&sc);
}

static void
truth_free(struct truth *tr)
{
	free(tr->y);
	free(tr->ev);
	free(tr->st);
}

static unsigned char *
slurp_file(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	unsigned char *buf;
	long n;

	assert_non_null(f);
	assert_int_equal(fseek(f, 0, SEEK_END), 0);
	n = ftell(f);
	assert_true(n > 0);
	rewind(f);
	buf = malloc((size_t)n + 1);	/* a NUL after the bytes: text is read as a string */
	assert_non_null(buf);
	assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
	buf[n] = '\0';
	fclose(f);
	*len = (size_t)n;
	return buf;
}

static void
codec_round_trip(void **state)
{
	float x[2 * 9], back[2 * 9];
	uint32_t tmp[2 * 9];
	unsigned char packed[4 * 2 * 9];
	size_t i;

	(void)state;
	for (i = 0; i < 18; i++)
		x[i] = (float)((double)i * 0.37 - 2.5 + (i % 5 == 0 ? -1e-30 : 0));
	x[4] = -0.0f;
	frames_encode(x, 2, 9, tmp, packed);
	frames_decode(packed, 2, 9, tmp, back);
	assert_memory_equal(x, back, sizeof x);
}

/* A frames chunk of the grid that says its grid is 0 nodes wide (the
 * fuzz corpus's bad-width.drr, its CRC made again) is refused with what
 * was expected; the file's other chunks read. */
static void
grid_width_refused(void **state)
{
	struct replay r;
	struct replay_frames fr;
	struct drape_err err;
	size_t i, good = 0, bad = 0;

	(void)state;
	if (replay_open(&r, TOP_SRCDIR "/tests/fuzz/corpus/bad-width.drr", &err) != 0)
		fail_msg("%s", err.msg);
	for (i = 0; i < r.nchunks; i++) {
		if (!replay_is_frames(r.chunk[i].kind))
			continue;
		assert_int_equal(r.chunk[i].kind, REPLAY_FRAMES_GRID);
		if (replay_read_frames(&r, i, &fr, &err) == 0) {
			replay_frames_free(&fr);
			good++;
			continue;
		}
		assert_non_null(strstr(err.msg, "frames of a grid 0 nodes wide: expected 1 to 9"));
		bad++;
	}
	assert_int_equal(bad, 1);
	assert_true(good >= 1);
	replay_close(&r);
}

/* The grid's codec gives back any words, whatever the width (each node's
 * neighbours, a row's start, one row, one column), exact and rounded:
 * random bit patterns (NaNs and infinities among them), smooth motion,
 * and words whose differences cross 2^31 either way. */
static void
codec_grid_round_trip(void **state)
{
	enum { F = 4, N = 35, W = 3 * F * N };
	static float x[W], back[W];
	static int32_t q[W], qback[W];
	static uint32_t tmp[W];
	static unsigned char packed[4 * W];
	static const size_t widths[] = { 1, 2, 5, 7, 34, 35 };
	uint32_t rng = 7;
	size_t i, w, trial;

	(void)state;
	for (trial = 0; trial < 3; trial++) {
		for (i = 0; i < W; i++) {
			uint32_t u;

			rng = rng * 1664525u + 1013904223u;
			if (trial == 0)
				u = rng;
			else if (trial == 1)
				memcpy(&u, &(float){ (float)(0.01 * (double)(i % (3 * N)) +
				    0.003 * (double)(i / (3 * N)) - 0.2) }, 4);
			else
				u = (i & 1) ? 0x7fffffffu + (rng & 3) : 0x80000000u - (rng & 3);
			memcpy(&x[i], &u, 4);
			memcpy(&q[i], &u, 4);
		}
		for (w = 0; w < sizeof widths / sizeof widths[0]; w++) {
			frames_encode_grid(x, F, N, widths[w], tmp, packed);
			frames_decode_grid(packed, F, N, widths[w], tmp, back);
			assert_memory_equal(x, back, sizeof x);
			frames_encode_grid_q(q, F, N, widths[w], tmp, packed);
			frames_decode_grid_q(packed, F, N, widths[w], tmp, qback);
			assert_memory_equal(q, qback, sizeof q);
		}
	}
}

static int
events_equal(const struct contact_event *a, const struct contact_event *b)
{
	return a->step == b->step && a->node == b->node && a->type == b->type &&
	    a->other == b->other && a->obstacle == b->obstacle &&
	    memcmp(&a->q, &b->q, sizeof a->q) == 0 && memcmp(&a->n, &b->n, sizeof a->n) == 0 &&
	    memcmp(&a->vn_before, &b->vn_before, sizeof a->vn_before) == 0 &&
	    memcmp(&a->vn_after, &b->vn_after, sizeof a->vn_after) == 0;
}

/* Steps chunk i's events, stored or recomputed: they must be there. */
static void
chunk_events(struct replay_events *re, size_t i, struct replay_steps *ss)
{
	struct drape_err err;
	int rc = replay_events_read(re, i, ss, &err);

	if (rc != 0)
		fail_msg("chunk %zu: %d: %s", i, rc, err.msg);
}

/* The tiny run recorded with its events stored and with their digest:
 * the same statistics and events read back from either, the stored kind
 * and the digest kind each where it belongs. */
static void
round_trip_of(const char *path, bool stored, struct truth *tr)
{
	struct replay r;
	struct replay_events re;
	struct drape_err err;
	size_t i, j, n6, nev = 0, nkey = 0, nframes = 0;
	long steps = 0;

	rec_stored = stored;
	record_tiny(tr, path);
	rec_stored = false;
	assert_true(tr->nev > 100);	/* the floor is hit */
	n6 = 6 * (size_t)tr->n;
	if (replay_open(&r, path, &err) != 0)
		fail_msg("replay_open: %s", err.msg);
	replay_events_init(&re, &r, path);
	assert_int_equal(r.hdr.version, REPLAY_VERSION);
	assert_true(r.hdr.flags & REPLAY_CLOSED);
	assert_int_equal(r.nbad, 0);
	assert_false(r.cut);
	assert_int_equal(r.meta.nodes, tr->n);
	assert_string_equal(r.meta.text, tiny_scene);
	assert_string_equal(r.meta.name, "tiny");
	assert_int_equal(r.last_step, tr->nsteps - 1);
	/* the header points at the index chunk, from the file's start */
	assert_int_equal(r.chunk[r.nchunks - 1].kind, REPLAY_INDEX);
	assert_int_equal(r.hdr.index_offset, r.chunk[r.nchunks - 1].offset);
	for (i = 0; i < r.nchunks; i++) {
		const struct replay_chunk *c = &r.chunk[i];

		if (c->kind == REPLAY_KEYFRAME) {
			struct replay_keyframe kf;

			if (replay_read_keyframe(&r, i, &kf, &err) != 0)
				fail_msg("%s", err.msg);
			assert_true(kf.step >= 0 && kf.step <= tr->nsteps);
			assert_true(kf.step % KEY_EVERY == 0 || kf.step == tr->nsteps);
			assert_memory_equal(kf.y, tr->y + (size_t)kf.step * n6, n6 * sizeof *kf.y);
			replay_keyframe_free(&kf);
			nkey++;
		} else if (c->kind == REPLAY_FRAMES_GRID) {
			struct replay_frames fr;

			if (replay_read_frames(&r, i, &fr, &err) != 0)
				fail_msg("%s", err.msg);
			for (j = 0; j < fr.count; j++) {
				const double *y = tr->y + (size_t)fr.step[j] * n6;
				size_t k;

				for (k = 0; k < n6 / 2; k++) {
					assert_true(fr.x[j * n6 / 2 + k] == (float)y[k]);
					assert_true(fabs(fr.x[j * n6 / 2 + k] - y[k]) <=
					    fabs(y[k]) * 0x1p-24 + 1e-45);
				}
				/* frame k at t = k / rate, the first step reaching it */
				assert_true(fr.t[j] * 200 >= (double)nframes - 1e-6);
				nframes++;
			}
			replay_frames_free(&fr);
		} else if (replay_is_steps(c->kind)) {
			struct replay_steps ss;

			assert_int_equal(c->kind, stored ? REPLAY_STEPS : REPLAY_STEPS_DIGEST);
			chunk_events(&re, i, &ss);
			assert_int_equal(ss.has_digest, !stored);
			for (j = 0; j < ss.count; j++) {
				const struct collide_stats *a = &ss.s[j].col;
				const struct collide_stats *b = &tr->st[ss.s[j].step];

				assert_int_equal(ss.s[j].step, steps);
				assert_memory_equal(a->n, b->n, sizeof a->n);
				assert_memory_equal(&a->hash, &b->hash, sizeof a->hash);
				assert_true(a->cell == b->cell);
				steps++;
			}
			for (j = 0; j < ss.nev; j++)
				assert_true(events_equal(&ss.ev[j], &tr->ev[nev + j]));
			nev += ss.nev;
			replay_steps_free(&ss);
		}
	}
	assert_int_equal(steps, tr->nsteps);
	assert_int_equal(nev, tr->nev);
	assert_int_equal(nkey, r.nkeyframes);
	assert_int_equal(nkey,
	    (size_t)(tr->nsteps / KEY_EVERY) + 1 + (tr->nsteps % KEY_EVERY != 0));
	assert_int_equal(nframes, r.nframes);
	assert_int_equal(nframes, 6);	/* 0, 5, ..., 25 ms */
	/* read in order, the chunks were stepped through once */
	assert_true(re.steps <= (stored ? 0 : tr->nsteps));
	replay_events_free(&re);
	replay_close(&r);
}

static void
round_trip(void **state)
{
	struct truth stored;

	(void)state;
	path_in_dir(replay_path, sizeof replay_path, "tiny.drr");
	path_in_dir(stored_path, sizeof stored_path, "tiny-stored.drr");
	/* chunks of 24 steps: several, some across a keyframe (every 40) */
	rec_steps_per_chunk = 24;
	round_trip_of(replay_path, false, &tiny_truth);
	round_trip_of(stored_path, true, &stored);
	rec_steps_per_chunk = 0;
	assert_int_equal(stored.nev, tiny_truth.nev);
	truth_free(&stored);
}

/*
 * --precision: the tiny run recorded with its frames on a 20 um grid.
 * Every coordinate of every frame is within half the grid step of the
 * run's (plus float32's own rounding of the result), the file says version
 * 3 and its frames chunks are the lossy kind, and everything else (steps,
 * events, keyframes) is as exact as without. A cloth whose coordinates
 * do not fit 32 bits of a 1 nm grid (5 m away) gets exact frames instead.
 */
static void
lossy_round_trip(void **state)
{
	static const double grid = 20e-6;
	struct truth tr, far;
	struct replay r;
	struct replay_events re;
	struct drape_err err;
	size_t i, j, k, n3, frames = 0, nev = 0, lossy = 0;
	double worst = 0;
	char text[4096], path[700];
	const char *at;

	(void)state;
	path_in_dir(lossy_path, sizeof lossy_path, "tiny-lossy.drr");
	rec_steps_per_chunk = 24;
	record_text_p(&tr, lossy_path, tiny_scene, KEY_EVERY, grid);
	rec_steps_per_chunk = 0;
	if (replay_open(&r, lossy_path, &err) != 0)
		fail_msg("replay_open: %s", err.msg);
	assert_int_equal(r.hdr.version, REPLAY_VERSION);
	replay_events_init(&re, &r, lossy_path);
	n3 = 3 * (size_t)tr.n;
	for (i = 0; i < r.nchunks; i++) {
		struct replay_frames fr;
		struct replay_steps ss;

		if (replay_is_steps(r.chunk[i].kind)) {
			chunk_events(&re, i, &ss);
			for (j = 0; j < ss.nev; j++)
				assert_true(events_equal(&ss.ev[j], &tr.ev[nev + j]));
			nev += ss.nev;
			replay_steps_free(&ss);
		}
		if (!replay_is_frames(r.chunk[i].kind))
			continue;
		assert_int_equal(r.chunk[i].kind, REPLAY_FRAMES_GRID_Q);
		if (replay_read_frames(&r, i, &fr, &err) != 0)
			fail_msg("%s", err.msg);
		assert_true(fr.precision == grid);
		for (j = 0; j < fr.count; j++) {
			const double *y = tr.y + (size_t)fr.step[j] * 2 * n3;

			for (k = 0; k < n3; k++) {
				double e = fabs(fr.x[j * n3 + k] - y[k]);

				if (e > grid / 2 + fabs(y[k]) * 0x1p-23)
					fail_msg("frame at step %ld, coordinate %zu: %.9g for %.9g, "
					    "%.3g m off; the bound is %.3g m", fr.step[j], k,
					    fr.x[j * n3 + k], y[k], e, grid / 2);
				worst = fmax(worst, e);
			}
			frames++;
		}
		lossy++;
		replay_frames_free(&fr);
	}
	print_message("%zu frames on a %g m grid: at most %.3g m off\n", frames, grid, worst);
	assert_int_equal(frames, 6);
	assert_true(lossy > 0);
	assert_true(worst > grid / 20);	/* it did round */
	assert_int_equal(nev, tr.nev);
	replay_events_free(&re);
	replay_close(&r);
	truth_free(&tr);

	/* 5 m away on a 1 nm grid: 5e9 steps, more than an int32 holds */
	assert_non_null(at = strstr(tiny_scene, "origin = 0 3 0 mm"));
	snprintf(text, sizeof text, "%.*sorigin = 5000 3 0 mm%s", (int)(at - tiny_scene),
	    tiny_scene, at + strlen("origin = 0 3 0 mm"));
	path_in_dir(path, sizeof path, "tiny-far.drr");
	record_text_p(&far, path, text, KEY_EVERY, 1e-9);
	if (replay_open(&r, path, &err) != 0)
		fail_msg("replay_open: %s", err.msg);
	for (i = 0, frames = 0; i < r.nchunks; i++) {
		struct replay_frames fr;

		if (!replay_is_frames(r.chunk[i].kind))
			continue;
		assert_int_equal(r.chunk[i].kind, REPLAY_FRAMES_GRID);
		if (replay_read_frames(&r, i, &fr, &err) != 0)
			fail_msg("%s", err.msg);
		for (j = 0; j < fr.count; j++, frames++)
			for (k = 0; k < n3; k++)
				assert_true(fr.x[j * n3 + k] == (float)far.y[(size_t)fr.step[j] * 2 * n3 + k]);
		replay_frames_free(&fr);
	}
	assert_int_equal(frames, 6);
	replay_close(&r);
	truth_free(&far);
}

/* A digest chunk's events recomputed: either unavailable, or exactly
 * tr's events of its steps (never wrong). */
static void
check_recomputed(struct replay_events *re, size_t i, const struct truth *tr, size_t *nok,
    size_t *nout)
{
	const struct replay_chunk *c = &re->rp->chunk[i];
	struct replay_steps ss;
	struct drape_err err;
	size_t at = 0, j;
	int rc = replay_events_read(re, i, &ss, &err);

	if (rc == REPLAY_EVENTS_UNAVAILABLE) {
		assert_null(ss.ev);
		assert_non_null(strstr(err.msg, "unavailable"));
		replay_steps_free(&ss);
		(*nout)++;
		return;
	}
	if (rc != 0)
		fail_msg("chunk %zu: %s", i, err.msg);
	while (at < tr->nev && tr->ev[at].step < (long)c->first_step)
		at++;
	assert_true(at + ss.nev <= tr->nev);
	for (j = 0; j < ss.nev; j++)
		assert_true(events_equal(&ss.ev[j], &tr->ev[at + j]));
	assert_true(at + ss.nev == tr->nev ||
	    tr->ev[at + ss.nev].step >= (long)(c->first_step + c->count));
	replay_steps_free(&ss);
	(*nok)++;
}

/* Every chunk of a file read back: no crash, and each one decodes; with
 * tr (the run it is of), digest chunks' events recomputed, each exact or
 * unavailable. */
static void
read_all_of(const struct replay *r, const struct truth *tr, size_t *nok, size_t *nout)
{
	struct replay_events re;
	struct drape_err err;
	size_t i;

	replay_events_init(&re, r, "hostile.drr");
	for (i = 0; i < r->nchunks; i++) {
		struct replay_frames fr;
		struct replay_keyframe kf;
		struct replay_steps ss;
		int rc = 0;

		if (replay_is_frames(r->chunk[i].kind) &&
		    (rc = replay_read_frames(r, i, &fr, &err)) == 0)
			replay_frames_free(&fr);
		if (r->chunk[i].kind == REPLAY_KEYFRAME &&
		    (rc = replay_read_keyframe(r, i, &kf, &err)) == 0)
			replay_keyframe_free(&kf);
		if (r->chunk[i].kind == REPLAY_STEPS && (rc = replay_read_steps(r, i, &ss, &err)) == 0) {
			struct replay_steps head;

			/* the statistics alone, as the viewer reads them: the same */
			if ((rc = replay_read_step_stats(r, i, &head, &err)) == 0) {
				assert_int_equal(head.count, ss.count);
				assert_int_equal(head.nev, ss.nev);
				assert_null(head.ev);
				for (size_t j = 0; j < ss.count; j++) {
					assert_int_equal(head.s[j].step, ss.s[j].step);
					assert_int_equal(head.s[j].nev, ss.s[j].nev);
					assert_true(head.s[j].t == ss.s[j].t && head.s[j].dt == ss.s[j].dt);
					assert_memory_equal(head.s[j].col.n, ss.s[j].col.n,
					    sizeof ss.s[j].col.n);
				}
				replay_steps_free(&head);
			}
			replay_steps_free(&ss);
		}
		if (r->chunk[i].kind == REPLAY_STEPS_DIGEST) {
			struct replay_steps head;

			/* statistics and digest; the events are not there to read */
			if ((rc = replay_read_step_stats(r, i, &head, &err)) == 0) {
				assert_true(head.has_digest);
				assert_null(head.ev);
				replay_steps_free(&head);
				assert_int_equal(replay_read_steps(r, i, &head, &err), -1);
				assert_non_null(strstr(err.msg, "not stored"));
				assert_null(head.s);
				if (tr != NULL)
					check_recomputed(&re, i, tr, nok, nout);
			}
		}
		if (rc != 0)
			fail_msg("chunk %zu: %s", i, err.msg);
	}
	replay_events_free(&re);
}

static void
read_all(const struct replay *r, const struct truth *tr)
{
	size_t nok = 0, nout = 0;

	read_all_of(r, tr, &nok, &nout);
}

/* path (a file of the tiny run) cut at every byte; the digest chunks
 * recomputed each time the whole chunks change. */
static void
cut_file(const char *path)
{
	struct replay whole, r;
	struct drape_err err;
	unsigned char *buf;
	size_t len, L, i, *ends, nends, meta_end, last_whole = 0, nok = 0, nout = 0;

	buf = slurp_file(path, &len);
	if (replay_open_mem(&whole, buf, len, &err) != 0)
		fail_msg("%s", err.msg);
	nends = whole.nchunks;
	ends = malloc(nends * sizeof *ends);
	assert_non_null(ends);
	for (i = 0; i < nends; i++)
		ends[i] = (size_t)whole.chunk[i].offset + sizeof(struct replay_chunk_header) +
		    whole.chunk[i].comp_len;
	assert_int_equal(ends[nends - 1], len);
	assert_int_equal(whole.chunk[0].kind, REPLAY_META);
	meta_end = ends[0];
	for (L = 0; L <= len; L++) {
		size_t whole_chunks = 0;

		while (whole_chunks < nends && ends[whole_chunks] <= L)
			whole_chunks++;
		if (replay_open_mem(&r, buf, L, &err) != 0) {
			assert_true(L < meta_end);
			continue;
		}
		assert_true(L >= meta_end);
		assert_int_equal(r.nchunks, whole_chunks);
		assert_int_equal(r.nbad, 0);
		assert_int_equal(r.cut, L != ends[whole_chunks - 1]);
		read_all_of(&r, whole_chunks != last_whole ? &tiny_truth : NULL, &nok, &nout);
		last_whole = whole_chunks;
		replay_close(&r);
	}
	/* whole chunks of a cut file recompute as recorded: the keyframe
	 * before a steps chunk is written before it */
	assert_int_equal(nout, 0);
	print_message("%s: cut at every byte: digest chunks recomputed %zu times\n", path, nok);
	replay_close(&whole);
	free(ends);
	free(buf);
}

/* The tiny replay and its lossy twin (lossy_round_trip) cut at every byte. */
static void
cut_at_every_byte(void **state)
{
	(void)state;
	cut_file(replay_path);
	cut_file(lossy_path);
	cut_file(stored_path);
}

static void
flip_file(const char *path)
{
	struct replay whole, r;
	struct drape_err err;
	unsigned char *buf, *bad;
	size_t len, i, j, at, flips = 0, nok = 0, nout = 0;

	buf = slurp_file(path, &len);
	bad = malloc(len);
	assert_non_null(bad);
	if (replay_open_mem(&whole, buf, len, &err) != 0)
		fail_msg("%s", err.msg);
	/* the header: refused */
	for (at = 0; at < sizeof(struct replay_file_header); at += 5) {
		memcpy(bad, buf, len);
		bad[at] ^= (unsigned char)(1u << (at % 8));
		assert_int_equal(replay_open_mem(&r, bad, len, &err), -1);
	}
	for (i = 0; i < whole.nchunks; i++) {
		const struct replay_chunk *c = &whole.chunk[i];
		size_t size = sizeof(struct replay_chunk_header) + c->comp_len;

		for (at = 0; at < size; at += 1 + size / 64) {
			memcpy(bad, buf, len);
			bad[c->offset + at] ^= (unsigned char)(1u << ((at + i) % 8));
			flips++;
			if (replay_open_mem(&r, bad, len, &err) != 0) {
				assert_int_equal(c->kind, REPLAY_META);	/* only the scene is vital */
				continue;
			}
			/* every other chunk intact, the flipped one not trusted */
			assert_int_equal(r.nchunks, whole.nchunks - 1);
			assert_true(r.nbad == 1 || (r.cut && i == whole.nchunks - 1));
			for (j = 0; j < r.nchunks; j++)
				assert_true(r.chunk[j].offset != c->offset);
			read_all_of(&r, &tiny_truth, &nok, &nout);
			replay_close(&r);
		}
	}
	assert_true(flips > 100);
	print_message("%s: %zu bit flips: digest chunks recomputed %zu times, unavailable %zu "
	    "times\n", path, flips, nok, nout);
	/* a damaged keyframe is passed over for the one before it */
	{
		long last = replay_find_keyframe(&whole, -1), before;
		const struct replay_chunk *c = &whole.chunk[last];

		assert_true(last >= 0);
		memcpy(bad, buf, len);
		bad[c->offset + sizeof(struct replay_chunk_header) + c->comp_len / 2] ^= 1;
		assert_int_equal(replay_open_mem(&r, bad, len, &err), 0);
		before = replay_find_keyframe(&r, -1);
		assert_true(before >= 0);
		assert_true(r.chunk[before].first_step < c->first_step);
		replay_close(&r);
	}
	replay_close(&whole);
	free(bad);
	free(buf);
}

static void
bit_flips(void **state)
{
	(void)state;
	flip_file(replay_path);
	flip_file(lossy_path);
	flip_file(stored_path);
}

/* buf (len bytes) with chunk c's payload inflated, changed by change,
 * deflated again and its CRC made again: a file whose every chunk is
 * intact and says something else. Returns the new file (*out_len). */
static unsigned char *
rewrite_chunk(const unsigned char *buf, size_t len, const struct replay_chunk *c,
    void (*change)(unsigned char *raw, size_t n, void *ctx), void *ctx, size_t *out_len)
{
	struct replay_chunk_header h;
	size_t at = (size_t)c->offset, rest = at + sizeof h + c->comp_len;
	uLongf raw_len = c->raw_len, z_len = compressBound(c->raw_len);
	unsigned char *raw = malloc(c->raw_len + 1), *out = malloc(len + z_len + 64);
	uint32_t crc;

	assert_true(raw != NULL && out != NULL);
	memcpy(&h, buf + at, sizeof h);
	assert_int_equal(uncompress(raw, &raw_len, buf + at + sizeof h, c->comp_len), Z_OK);
	assert_int_equal(raw_len, c->raw_len);
	change(raw, raw_len, ctx);
	memcpy(out, buf, at);
	assert_int_equal(compress2(out + at + sizeof h, &z_len, raw, raw_len, 6), Z_OK);
	h.comp_len = (uint32_t)z_len;
	crc = (uint32_t)crc32(crc32(0, Z_NULL, 0), (const Bytef *)&h,
	    offsetof(struct replay_chunk_header, crc));
	h.crc = (uint32_t)crc32(crc, out + at + sizeof h, (uInt)z_len);
	memcpy(out + at, &h, sizeof h);
	memcpy(out + at + sizeof h + z_len, buf + rest, len - rest);
	*out_len = at + sizeof h + z_len + len - rest;
	free(raw);
	return out;
}

/* A digest chunk's digest, one bit of it flipped. */
static void
flip_digest(unsigned char *raw, size_t n, void *ctx)
{
	(void)ctx;
	assert_true(n > 16);
	raw[8] ^= 1;
}

/* A keyframe 0.1 mm off in one coordinate, its hash made to match:
 * restore takes it, and the run from it is another. */
static void
move_keyframe(unsigned char *raw, size_t n, void *ctx)
{
	const struct replay_keyframe *kf = ctx;
	size_t n6 = (n - 32) / 8;
	double *y = malloc(n6 * sizeof *y);
	uint64_t hash;

	assert_non_null(y);
	memcpy(y, kf->y, n6 * sizeof *y);
	y[1] += 1e-4;
	hash = stepper_state_hash(y, NULL, n6 / 6, kf->t);
	memcpy(raw + 24, &hash, 8);
	/* the doubles are byte-shuffled: byte b of double j at b * n6 + j */
	for (size_t b = 0; b < 8; b++)
		raw[32 + b * n6 + 1] = ((const unsigned char *)&y[1])[b];
	free(y);
}

/* The events of every steps chunk of the file buf read in order, against
 * tr: how many chunks were exact and how many unavailable (never wrong);
 * *why gets the first unavailable one's message. */
static void
read_tampered(const unsigned char *buf, size_t len, const struct truth *tr, size_t *nok,
    size_t *nout, char *why, size_t whylen)
{
	struct replay r;
	struct replay_events re;
	struct drape_err err;
	size_t i;

	*nok = *nout = 0;
	if (replay_open_mem(&r, buf, len, &err) != 0)
		fail_msg("%s", err.msg);
	assert_int_equal(r.nbad, 0);
	assert_false(r.cut);
	replay_events_init(&re, &r, "tampered.drr");
	why[0] = '\0';
	for (i = 0; i < r.nchunks; i++) {
		size_t before = *nout;
		struct replay_steps ss;

		if (r.chunk[i].kind != REPLAY_STEPS_DIGEST)
			continue;
		check_recomputed(&re, i, tr, nok, nout);
		if (*nout > before && why[0] == '\0') {
			/* the same again, for its message */
			replay_events_free(&re);
			replay_events_init(&re, &r, "tampered.drr");
			assert_int_equal(replay_events_read(&re, i, &ss, &err),
			    REPLAY_EVENTS_UNAVAILABLE);
			replay_steps_free(&ss);
			snprintf(why, whylen, "%s", err.msg);
		}
	}
	replay_events_free(&re);
	replay_close(&r);
}

/*
 * A digest chunk whose events do not recompute as recorded gives
 * "unavailable", never other events: its digest changed (and its CRC
 * made again); a keyframe moved 0.1 mm with its hash made to match, so
 * that the run resumed from it is another (the chunks after it, and the
 * chunk before it, which steps onto it, are unavailable; those before
 * are exact). drape events lists the rest, names the steps and exits 1.
 */
static void
digest_mismatch(void **state)
{
	struct truth tr;
	struct replay r;
	struct drape_err err;
	struct replay_keyframe kf;
	struct result res;
	unsigned char *buf, *bad;
	size_t len, blen, i, nok, nout, ndigest = 0, second = 0;
	long key = -1, lo, hi;
	char path[700], why[600], args[1600], steps[100];

	(void)state;
	path_in_dir(path, sizeof path, "tamper.drr");
	rec_steps_per_chunk = 24;
	record_tiny(&tr, path);
	rec_steps_per_chunk = 0;
	buf = slurp_file(path, &len);
	if (replay_open_mem(&r, buf, len, &err) != 0)
		fail_msg("%s", err.msg);
	/* the chunk tampered with: the first with events after the first */
	for (i = 0; i < r.nchunks; i++) {
		struct replay_steps ss;

		if (r.chunk[i].kind == REPLAY_STEPS_DIGEST && ++ndigest >= 2 && second == 0) {
			assert_int_equal(replay_read_step_stats(&r, i, &ss, &err), 0);
			if (ss.nev > 0)
				second = i;
			replay_steps_free(&ss);
		}
		if (r.chunk[i].kind == REPLAY_KEYFRAME && r.chunk[i].first_step == KEY_EVERY)
			key = (long)i;
	}
	assert_true(ndigest >= 4 && second > 0 && key > 0);
	/* as shown: the step from state k to k + 1 is step k + 1 */
	lo = step_shown((long)r.chunk[second].first_step);
	hi = lo + (long)r.chunk[second].count - 1;
	snprintf(steps, sizeof steps, "the events of steps %ld to %ld are unavailable", lo, hi);
	read_tampered(buf, len, &tr, &nok, &nout, why, sizeof why);
	assert_int_equal(nok, ndigest);
	assert_int_equal(nout, 0);

	/* the second chunk's digest */
	bad = rewrite_chunk(buf, len, &r.chunk[second], flip_digest, NULL, &blen);
	read_tampered(bad, blen, &tr, &nok, &nout, why, sizeof why);
	print_message("digest flipped: %zu chunks exact, %zu unavailable: %s\n", nok, nout, why);
	assert_int_equal(nout, 1);
	assert_int_equal(nok, ndigest - 1);
	assert_non_null(strstr(why, steps));
	assert_non_null(strstr(why, "digest differs"));
	dir_write("tamper-digest.drr", bad, blen);
	free(bad);
	/* drape events: every other event listed, those steps named */
	snprintf(args, sizeof args, "'%s' events '%s/tamper-digest.drr' >'%s/ev-t.tsv' "
	    "2>'%s/ev-t.err'", DRAPE, dir, dir, dir);
	i = (size_t)system(args);
	assert_true(WIFEXITED((int)i) && WEXITSTATUS((int)i) == 1);
	snprintf(args, sizeof args, "%s/ev-t.err", dir);
	slurp(args, res.err, sizeof res.err);
	assert_non_null(strstr(res.err, steps));
	assert_non_null(strstr(res.err, "tamper-digest.drr: the events of steps"));
	assert_non_null(strstr(res.err, "unavailable: the events recomputed are not the recorded"));
	{
		size_t n = 0, inside = 0, lines = 0, tlen;
		char *text, *line, *save = NULL;

		snprintf(args, sizeof args, "%s/ev-t.tsv", dir);
		text = (char *)slurp_file(args, &tlen);
		text = realloc(text, tlen + 1);
		assert_non_null(text);
		text[tlen] = '\0';
		for (line = strtok_r(text, "\n", &save); line != NULL;
		    line = strtok_r(NULL, "\n", &save), lines++) {
			long step;

			if (lines > 0 && sscanf(line, "%ld", &step) == 1)
				inside += step >= lo && step <= hi;
		}
		free(text);
		for (i = 0; i < tr.nev; i++)
			n += step_shown(tr.ev[i].step) < lo || step_shown(tr.ev[i].step) > hi;
		assert_int_equal(inside, 0);
		assert_int_equal(lines, 1 + n);
		assert_true(n > 0 && n < tr.nev);
	}
	/* info counts the events from the statistics: all of them */
	snprintf(args, sizeof args, "info '%s/tamper-digest.drr'", dir);
	drape(&res, args);
	assert_int_equal(res.status, 0);
	snprintf(why, sizeof why, "events       %zu (a digest", tr.nev);
	assert_non_null(strstr(res.out, why));

	/* the keyframe at step 40 */
	if (replay_read_keyframe(&r, (size_t)key, &kf, &err) != 0)
		fail_msg("%s", err.msg);
	bad = rewrite_chunk(buf, len, &r.chunk[key], move_keyframe, &kf, &blen);
	replay_keyframe_free(&kf);
	read_tampered(bad, blen, &tr, &nok, &nout, why, sizeof why);
	print_message("keyframe moved: %zu chunks exact, %zu unavailable: %s\n", nok, nout, why);
	assert_true(nok >= 1 && nout >= 2);
	/* steps 25 to 48 (as shown: from states 24 to 47) step onto the
	 * keyframe at state 40 from the one at 0 */
	assert_non_null(strstr(why, "the events of steps 25 to 48 are unavailable: the state "
	    "recomputed at step 40 is not the keyframe's"));
	free(bad);
	replay_close(&r);
	free(buf);
	truth_free(&tr);
}

/* The continued run from each keyframe ends with the recorded run's hash. */
static void
resume_every_keyframe_of(const char *text, int key_every)
{
	struct truth tr;
	struct replay r;
	struct drape_err err;
	size_t i, tried = 0;

	record_text(&tr, replay_path, text, key_every);
	if (replay_open(&r, replay_path, &err) != 0)
		fail_msg("%s", err.msg);
	for (i = 0; i < r.nchunks; i++) {
		struct replay_keyframe kf;
		struct scene sc;
		struct stepper *st;

		if (r.chunk[i].kind != REPLAY_KEYFRAME)
			continue;
		if (replay_read_keyframe(&r, i, &kf, &err) != 0)
			fail_msg("%s", err.msg);
		if (replay_scene(&r, replay_path, 0, &sc, &err) != 0)
			fail_msg("%s", err.msg);
		if ((st = replay_resume(&r, replay_path, &sc, kf.step, &err)) == NULL)
			fail_msg("%s", err.msg);
		assert_int_equal(report_of(st).step, kf.step);
		assert_true(stepper_hash(st) == kf.hash);
		run_to_end(st);
		assert_int_equal(report_of(st).step, tr.nsteps);
		assert_true(stepper_hash(st) == tr.hash);
		stepper_free(st);
		scene_free(&sc);
		replay_keyframe_free(&kf);
		tried++;
	}
	assert_true(tried >= 3);
	replay_close(&r);
	truth_free(&tr);
}

static void
resume_every_keyframe(void **state)
{
	(void)state;
	resume_every_keyframe_of(tiny_scene, KEY_EVERY);
}

/* The fast path keeps nothing from one step to the next but the state
 * (its contacts are found at each step's start), so it resumes exactly. */
static void
resume_every_keyframe_fast(void **state)
{
	(void)state;
	resume_every_keyframe_of(tiny_fast_scene, 15);
}

/* bdf2 keeps the state one step back, which its keyframes hold (replay
 * version 5), so it resumes exactly from each: at steps 0 (no history
 * yet), 5, 10, ... of a cloth landing on the floor with self-contact. */
static void
resume_every_keyframe_bdf2(void **state)
{
	(void)state;
	resume_every_keyframe_of("[simulation]\nname = tiny-bdf2\nduration = 0.1 s\ndt = auto\n"
	    "integrator = bdf2\noutput_rate = 50 Hz\n" TINY_CLOTH, 5);
}

/* ... and where its steps are two ticks (a cloth lying on the floor, at
 * dt = auto: stepper.c bdf2_next_dt), whose keyframes hold the history
 * taken for the next step's length, from each of them too. */
static const char tiny_bdf2_rest[] =
    "[simulation]\nname = tiny-bdf2-rest\nduration = 0.2 s\ndt = auto\nintegrator = bdf2\n"
    "output_rate = 50 Hz\n[cloth]\nnodes = 4 4\nspacing = 10 mm\norigin = 0 0.1375 0 mm\n"
    "orientation = +x +z\nweight = 150 g/m2\nthickness = 0.55 mm\nmodulus_warp = 0.45 MPa\n"
    "modulus_weft = 0.30 MPa\nshear_modulus = 9 kPa\nbending_warp = 3 uN*m\n"
    "bending_weft = 2 uN*m\ndamping = 2 /s\n[plane]\npoint = 0 0 0 m\n[collision]\nself = on\n";

static void
resume_every_keyframe_bdf2_long_steps(void **state)
{
	struct truth tr;

	(void)state;
	record_text(&tr, replay_path, tiny_bdf2_rest, 3);
	assert_true(tr.nsteps < 15);	/* of 20 ticks of 10 ms */
	truth_free(&tr);
	resume_every_keyframe_of(tiny_bdf2_rest, 3);
}

/* What a restore checks: a saved state is taken only whole and only into
 * its own run (stepper_restore: the node count, dt_set, the hash, and st
 * untouched by a refusal), so a replay resumes only into the scene it was
 * recorded with (replay_resume, through stepper_restore: the node count
 * and dt_set, with the replay's name). */
static void
restore_checks(void **state)
{
	struct truth tr;
	struct replay r;
	struct scene sc;
	struct stepper *st, *other;
	struct stepper_state s;
	struct drape_err err;
	size_t n6;
	uint64_t before;
	double *y;

	(void)state;
	parse_text(&sc, tiny_scene);
	st = new_stepper(&sc);
	other = new_stepper(&sc);
	step_n(st, 7);
	n6 = 6 * (size_t)cloth_of(st)->n;
	stepper_save(st, &s);
	assert_int_equal(s.step, 7);
	assert_true(s.hash == stepper_hash(st));
	y = malloc(n6 * sizeof *y);
	assert_non_null(y);
	memcpy(y, s.y, n6 * sizeof *y);
	s.y = y;
	before = stepper_hash(other);

	assert_true(s.nodes == (size_t)cloth_of(st)->n);
	s.nodes++;	/* a state of another network */
	assert_int_equal(stepper_restore(other, &s, &err), -1);
	assert_non_null(strstr(err.msg, "nodes"));
	assert_non_null(strstr(err.msg, "expected the recorded"));
	s.nodes--;
	s.dt_set *= 2;	/* a state of a run with another step */
	assert_int_equal(stepper_restore(other, &s, &err), -1);
	assert_non_null(strstr(err.msg, "expected the recorded"));
	s.dt_set /= 2;
	y[3] += 1e-9;	/* a state that is not the one hashed */
	assert_int_equal(stepper_restore(other, &s, &err), -2);
	assert_non_null(strstr(err.msg, "does not match its hash"));
	assert_true(stepper_hash(other) == before);
	assert_int_equal(report_of(other).step, 0);
	y[3] -= 1e-9;
	assert_int_equal(stepper_restore(other, &s, &err), 0);
	assert_int_equal(report_of(other).step, 7);
	assert_true(stepper_hash(other) == stepper_hash(st));
	step_once(st);
	step_once(other);
	assert_true(stepper_hash(other) == stepper_hash(st));
	free(y);
	stepper_free(other);
	stepper_free(st);
	scene_free(&sc);

	record_tiny(&tr, replay_path);
	if (replay_open(&r, replay_path, &err) != 0)
		fail_msg("%s", err.msg);
	if (replay_scene(&r, replay_path, 0, &sc, &err) != 0)
		fail_msg("%s", err.msg);
	r.meta.dt_set *= 2;	/* recorded with another step */
	assert_null(replay_resume(&r, replay_path, &sc, -1, &err));
	assert_non_null(strstr(err.msg, "expected the recorded"));
	r.meta.dt_set /= 2;
	r.meta.nodes++;
	assert_null(replay_resume(&r, replay_path, &sc, -1, &err));
	assert_non_null(strstr(err.msg, "expected the recorded"));
	r.meta.nodes--;
	if ((st = replay_resume(&r, replay_path, &sc, -1, &err)) == NULL)
		fail_msg("%s", err.msg);
	stepper_free(st);
	scene_free(&sc);
	replay_close(&r);
	truth_free(&tr);
}

/* ---- through the binary ---- */

static const char *
tiny_scene_file(void)
{
	static char path[700];
	FILE *f;

	path_in_dir(path, sizeof path, "tiny.scene");
	f = fopen(path, "w");
	assert_non_null(f);
	assert_true(fputs(tiny_scene, f) >= 0);
	assert_int_equal(fclose(f), 0);
	return path;
}

static const char *
hash_of(const char *out)
{
	const char *h = strstr(out, "state hash   ");

	assert_non_null(h);
	return h + 13;
}

static void
cli_record_resume(void **state)
{
	struct result r;
	char args[2000], hash[17];

	(void)state;
	snprintf(args, sizeof args, "run --record '%s/cli.drr' --keyframe-every 50 '%s'", dir,
	    tiny_scene_file());
	drape(&r, args);
	assert_int_equal(r.status, 0);
	memcpy(hash, hash_of(r.out), 16);
	hash[16] = '\0';
	snprintf(args, sizeof args, "run --resume '%s/cli.drr@120'", dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "resumed      from"));
	assert_non_null(strstr(r.out, "at step 100 "));
	assert_memory_equal(hash_of(r.out), hash, 16);
	/* resume and record again: the copy resumes too */
	snprintf(args, sizeof args, "run --resume '%s/cli.drr@50' --record '%s/cli2.drr'", dir,
	    dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_memory_equal(hash_of(r.out), hash, 16);
	snprintf(args, sizeof args, "run --resume '%s/cli2.drr@100'", dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_memory_equal(hash_of(r.out), hash, 16);

	/* the adaptive integrator: its next step is part of the keyframe */
	snprintf(args, sizeof args, "run --integrator dopri5 --dt 1ms --until 20ms --record "
	    "'%s/dopri5.drr' --keyframe-every 5 '%s'", dir, tiny_scene_file());
	drape(&r, args);
	assert_int_equal(r.status, 0);
	memcpy(hash, hash_of(r.out), 16);
	snprintf(args, sizeof args, "run --resume '%s/dopri5.drr@12'", dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "at step 10 "));
	assert_non_null(strstr(r.out, "integrator   dopri5"));
	assert_non_null(strstr(r.out, "simulated    0.02 s"));
	assert_memory_equal(hash_of(r.out), hash, 16);

	/* implicit Euler on the box: its contact constraints come from the
	 * state, so a keyframe is all it needs */
	snprintf(args, sizeof args, "run --integrator implicit-euler --until 0.15 --record "
	    "'%s/implicit.drr' --keyframe-every 20 '" SCENE_DIR "tablecloth.scene'", dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	memcpy(hash, hash_of(r.out), 16);
	snprintf(args, sizeof args, "run --resume '%s/implicit.drr@70'", dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "at step 60 "));
	assert_non_null(strstr(r.out, "integrator   implicit-euler"));
	assert_memory_equal(hash_of(r.out), hash, 16);

	snprintf(args, sizeof args, "info '%s/cli.drr'", dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "scene        tiny"));
	assert_non_null(strstr(r.out, "nodes        16"));
	assert_non_null(strstr(r.out, "frames       6 at 200"));
	assert_non_null(strstr(r.out, "integrity    whole"));
	assert_non_null(strstr(r.out, "closed cleanly"));
}

static void
cli_events_node(void **state)
{
	struct result r;
	struct replay rp;
	struct replay_events re;
	struct drape_err err;
	char args[2000], *line, *save = NULL;
	size_t i, e, expect = 0, got = 0;
	const int node = 5;

	(void)state;
	if (replay_open(&rp, replay_path, &err) != 0)
		fail_msg("%s", err.msg);
	replay_events_init(&re, &rp, replay_path);
	for (i = 0; i < rp.nchunks; i++) {
		struct replay_steps ss;

		if (!replay_is_steps(rp.chunk[i].kind))
			continue;
		chunk_events(&re, i, &ss);
		for (e = 0; e < ss.nev; e++)
			expect += ss.ev[e].node == node;
		replay_steps_free(&ss);
	}
	replay_events_free(&re);
	replay_close(&rp);
	assert_true(expect > 10);
	/* the options may follow the file */
	snprintf(args, sizeof args, "'%s' events '%s' --node %d >'%s/ev.tsv'", DRAPE, replay_path,
	    node, dir);
	assert_int_equal(system(args), 0);
	snprintf(args, sizeof args, "%s/ev.tsv", dir);
	{
		size_t len;
		char *text = (char *)slurp_file(args, &len);

		text = realloc(text, len + 1);
		assert_non_null(text);
		text[len] = '\0';
		line = strtok_r(text, "\n", &save);
		assert_non_null(line);
		assert_string_equal(line, "step\tnode\ttype\tother\tobstacle\tqx\tqy\tqz\tnx\tny\tnz"
		    "\tvn_before\tvn_after");
		while ((line = strtok_r(NULL, "\n", &save)) != NULL) {
			long step;
			int n;

			assert_int_equal(sscanf(line, "%ld\t%d\t", &step, &n), 2);
			assert_int_equal(n, node);
			got++;
		}
		free(text);
	}
	assert_int_equal(got, expect);
	snprintf(args, sizeof args, "events --type obstacle --from 100 --to 100 '%s'", replay_path);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "\n100\t"));
	assert_null(strstr(r.out, "\n101\t"));
	assert_null(strstr(r.out, "\n99\t"));
}

static void
cli_pc2(void **state)
{
	struct result r;
	struct replay rp;
	struct drape_err err;
	char args[2000], path[700];
	unsigned char *pc2;
	size_t len, i, frame = 0, n3;
	int32_t v;
	float f;
	struct stat sb;

	(void)state;
	snprintf(args, sizeof args, "export '%s' --pc2 '%s/out.pc2' --obj '%s/rest.obj' "
	    "--obj-seq '%s/seq'", replay_path, dir, dir, dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	if (replay_open(&rp, replay_path, &err) != 0)
		fail_msg("%s", err.msg);
	n3 = 3 * (size_t)rp.meta.nodes;
	path_in_dir(path, sizeof path, "out.pc2");
	pc2 = slurp_file(path, &len);
	assert_memory_equal(pc2, "POINTCACHE2\0", 12);
	memcpy(&v, pc2 + 12, 4);
	assert_int_equal(v, 1);
	memcpy(&v, pc2 + 16, 4);
	assert_int_equal(v, (int32_t)rp.meta.nodes);
	memcpy(&f, pc2 + 20, 4);
	assert_true(f == 0.0f);
	memcpy(&f, pc2 + 24, 4);
	assert_true(f == 1.0f);
	memcpy(&v, pc2 + 28, 4);
	assert_int_equal(v, (int32_t)rp.nframes);
	assert_int_equal(len, 32 + 12 * rp.meta.nodes * rp.nframes);
	for (i = 0; i < rp.nchunks; i++) {
		struct replay_frames fr;
		size_t k;

		if (!replay_is_frames(rp.chunk[i].kind))
			continue;
		assert_int_equal(replay_read_frames(&rp, i, &fr, &err), 0);
		for (k = 0; k < fr.count; k++, frame++)
			assert_memory_equal(pc2 + 32 + 12 * rp.meta.nodes * frame, fr.x + k * n3,
			    n3 * sizeof(float));
		replay_frames_free(&fr);
	}
	free(pc2);
	path_in_dir(path, sizeof path, "rest.obj");
	assert_int_equal(stat(path, &sb), 0);
	snprintf(path, sizeof path, "%s/seq/frame_%05zu.obj", dir, rp.nframes - 1);
	assert_int_equal(stat(path, &sb), 0);
	path_in_dir(path, sizeof path, "out.pc2.tmp");
	assert_int_equal(stat(path, &sb), -1);
	replay_close(&rp);
}

/* info on a cut file and on one with a flipped bit says so; events and
 * export still work on what is whole. */
static void
cli_info_damaged(void **state)
{
	struct result r;
	char args[2000], path[700];
	unsigned char *buf;
	size_t len;
	FILE *f;

	(void)state;
	buf = slurp_file(replay_path, &len);
	path_in_dir(path, sizeof path, "cut.drr");
	f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(fwrite(buf, 1, len - 100, f), len - 100);
	assert_int_equal(fclose(f), 0);
	snprintf(args, sizeof args, "info '%s'", path);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "closed cleanly, then cut short"));
	assert_non_null(strstr(r.out, "whole chunks; cut at chunk"));
	snprintf(args, sizeof args, "export '%s' --pc2 '%s/cut.pc2'", path, dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.err, "cut short"));

	buf[len / 2] ^= 4;
	path_in_dir(path, sizeof path, "flipped.drr");
	f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(fwrite(buf, 1, len, f), len);
	assert_int_equal(fclose(f), 0);
	snprintf(args, sizeof args, "info '%s'", path);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "1 chunks with a bad CRC"));
	snprintf(args, sizeof args, "events '%s' --node 0", path);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.err, "some with a bad CRC"));
	free(buf);
}

/* SIGTERM mid-run: the replay is closed properly and plays. */
static void
cli_sigterm(void **state)
{
	char cmd[3000], path[700];
	struct result r;
	FILE *f;
	int code = -1;

	(void)state;
	/* rk4: a run of some 20 s (the scene's fast path ends in about one) */
	snprintf(cmd, sizeof cmd, "'%s' run --integrator rk4 --record '%s/term.drr' "
	    "'%s/scenes/tablecloth.scene' "
	    ">/dev/null 2>'%s/term.err' & pid=$!; sleep 1.5; kill -TERM $pid; wait $pid; "
	    "echo $? >'%s/term.rc'", DRAPE, dir, TOP_SRCDIR, dir, dir);
	assert_int_equal(system(cmd), 0);
	path_in_dir(path, sizeof path, "term.rc");
	f = fopen(path, "r");
	assert_non_null(f);
	assert_int_equal(fscanf(f, "%d", &code), 1);
	fclose(f);
	assert_int_equal(code, 130);
	snprintf(cmd, sizeof cmd, "info '%s/term.drr'", dir);
	drape(&r, cmd);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "closed cleanly"));
	assert_non_null(strstr(r.out, "integrity    whole"));
}

/* --precision through the binary: a lossy recording says so in drape info
 * and exports; a bad length is refused with exit 2, naming the option. */
static void
cli_precision(void **state)
{
	static const char *const bad[] = { "0", "-1um", "5 kg", "2 m", "0.1 nm", "x" };
	struct result r;
	char args[3000], scene[700], out[700];
	size_t i;

	(void)state;
	snprintf(scene, sizeof scene, "%s", dir_write_text("tiny-cli.scene", tiny_scene));
	path_in_dir(out, sizeof out, "tiny-cli-lossy.drr");
	snprintf(args, sizeof args, "run --headless --precision 10um --record '%s' '%s'", out, scene);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	snprintf(args, sizeof args, "info '%s'", out);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "(version 5, closed cleanly)"));
	assert_non_null(strstr(r.out, "6 at 200 per second, rounded to 1e-05 m (within 5e-06 m"));
	snprintf(args, sizeof args, "export --pc2 '%s/lossy.pc2' '%s'", dir, out);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	/* exact frames: no rounding said */
	snprintf(args, sizeof args, "info '%s'", replay_path);
	drape(&r, args);
	assert_non_null(strstr(r.out, "(version 5, closed cleanly)"));
	assert_null(strstr(r.out, "rounded"));
	for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		snprintf(args, sizeof args, "run --headless --precision '%s' --record '%s/bad.drr' '%s'",
		    bad[i], dir, scene);
		drape(&r, args);
		if (r.status != 2 || strstr(r.err, "--precision") == NULL ||
		    strstr(r.err, "a length from 1 nm to 1 m") == NULL)
			fail_msg("--precision '%s': status %d, stderr '%s'", bad[i], r.status, r.err);
	}
}

/* The lines of an OBJ file that begin with key (such as "vt "), each
 * parsed as up to 3 numbers into v (3 per line); their count. */
static size_t
obj_lines(const char *text, const char *key, double *v, size_t max)
{
	const char *p = text;
	size_t n = 0, len = strlen(key);

	while ((p = strstr(p, key)) != NULL) {
		if (p == text || p[-1] == '\n') {
			if (n < max) {
				v[3 * n] = v[3 * n + 1] = v[3 * n + 2] = NAN;
				(void)sscanf(p + len, "%lf %lf %lf", &v[3 * n], &v[3 * n + 1],
				    &v[3 * n + 2]);
			}
			n++;
		}
		p += len;
	}
	return n;
}

#define SHIPPED_TABLECLOTH TOP_SRCDIR "/replays/tablecloth.drr"

/* Issue 30, Blender: the OBJs had no texture coordinates (which textures
 * need) nor normals, the obstacles were not exported, and the frames
 * came at the recorded 50 a second only. The grid's (i, j) give the
 * texture coordinates, the frames of --obj-seq their normals, --obstacles
 * the scene's obstacles, and --fps resamples. */
static void
cli_export_for_blender(void **state)
{
	static double v[3 * 700];
	struct result r;
	struct replay rp;
	struct replay_frames fr;
	struct drape_err err;
	char args[2000], path[700], *text;
	unsigned char *pc2;
	size_t len, n, i, k, frame, n3;
	int32_t samples;
	float f;

	(void)state;
	snprintf(args, sizeof args, "export '%s' --obj '%s/bl-rest.obj' --obj-seq '%s/bl-seq' "
	    "--obstacles '%s/bl-obstacles.obj'", SHIPPED_TABLECLOTH, dir, dir, dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	/* the rest mesh: a vt per node, node (i, j) of the 25 x 25 grid at
	 * (i / 24, j / 24); faces name them; no normals */
	path_in_dir(path, sizeof path, "bl-rest.obj");
	text = (char *)slurp_file(path, &len);
	n = obj_lines(text, "vt ", v, 700);
	assert_int_equal(n, 625);
	assert_true(v[0] == 0 && v[1] == 0);
	assert_true(v[3 * 1] == 1.0 / 24 && v[3 * 1 + 1] == 0);
	assert_true(v[3 * 25] == 0 && v[3 * 25 + 1] == 1.0 / 24);
	assert_true(v[3 * 624] == 1 && v[3 * 624 + 1] == 1);
	assert_int_equal(obj_lines(text, "vn ", v, 0), 0);
	assert_non_null(strstr(text, "\nf 1/1 2/2 27/27\n"));
	free(text);
	/* a frame: a unit normal per node, the flat cloth's straight up */
	snprintf(path, sizeof path, "%s/bl-seq/frame_00000.obj", dir);
	text = (char *)slurp_file(path, &len);
	n = obj_lines(text, "vn ", v, 700);
	assert_int_equal(n, 625);
	for (i = 0; i < n; i++)
		assert_double_equal(fabs(v[3 * i + 1]), 1, 1e-9);
	assert_non_null(strstr(text, "\nf 1/1/1 2/2/2 27/27/27\n"));
	free(text);
	/* the obstacles: the box's 8 corners, then the floor, a square on y = 0 */
	path_in_dir(path, sizeof path, "bl-obstacles.obj");
	text = (char *)slurp_file(path, &len);
	assert_non_null(strstr(text, "\no box_43\n"));
	assert_non_null(strstr(text, "\no plane_47\n"));
	n = obj_lines(text, "v ", v, 700);
	assert_int_equal(n, 12);
	for (i = 0; i < 8; i++) {
		assert_true(v[3 * i] == 0 || v[3 * i] == 0.14);
		assert_true(v[3 * i + 1] == 0 || v[3 * i + 1] == 0.12);
		assert_true(v[3 * i + 2] == -0.08 || v[3 * i + 2] == 0.06);
	}
	for (i = 8; i < 12; i++)
		assert_true(v[3 * i + 1] == 0 && fabs(v[3 * i]) > 1);
	/* the floor's face turns up (counter-clockwise seen from above) */
	assert_non_null(strstr(text, "\nf 9 10 11\n"));
	assert_true((v[3 * 9] - v[3 * 8]) * (v[3 * 10 + 2] - v[3 * 8 + 2]) -
	    (v[3 * 9 + 2] - v[3 * 8 + 2]) * (v[3 * 10] - v[3 * 8]) < 0);
	free(text);

	/* --fps 25 of 50 a second: every other frame, exactly */
	snprintf(args, sizeof args, "export --fps 25 --pc2 '%s/bl25.pc2' '%s'", dir,
	    SHIPPED_TABLECLOTH);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	if (replay_open(&rp, SHIPPED_TABLECLOTH, &err) != 0)
		fail_msg("%s", err.msg);
	n3 = 3 * (size_t)rp.meta.nodes;
	path_in_dir(path, sizeof path, "bl25.pc2");
	pc2 = slurp_file(path, &len);
	memcpy(&samples, pc2 + 28, 4);
	assert_int_equal(samples, (int32_t)(rp.nframes + 1) / 2);
	memcpy(&f, pc2 + 24, 4);
	assert_true(f == 1.0f);
	for (i = 0, frame = 0; i < rp.nchunks; i++) {
		if (!replay_is_frames(rp.chunk[i].kind))
			continue;
		assert_int_equal(replay_read_frames(&rp, i, &fr, &err), 0);
		for (k = 0; k < fr.count; k++, frame++)
			if (frame % 2 == 0)
				assert_memory_equal(pc2 + 32 + 12 * rp.meta.nodes * (frame / 2),
				    fr.x + k * n3, n3 * sizeof(float));
		replay_frames_free(&fr);
	}
	free(pc2);
	replay_close(&rp);
	/* bad rates */
	snprintf(args, sizeof args, "export --fps 0 --pc2 '%s/x.pc2' '%s'", dir,
	    SHIPPED_TABLECLOTH);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "--fps '0': expected frames a second"));
	snprintf(args, sizeof args, "export --fps 24fps --pc2 '%s/x.pc2' '%s'", dir,
	    SHIPPED_TABLECLOTH);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	path_in_dir(path, sizeof path, "x.pc2");
	assert_int_equal(access(path, F_OK), -1);
}

static void
cli_bad(void **state)
{
	struct result r;
	char args[2000];
	FILE *f;

	(void)state;
	drape(&r, "info");
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "expected one replay file"));
	drape(&r, "info /no/such.drr");
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "/no/such.drr: cannot open"));
	drape(&r, "info " TOP_SRCDIR "/scenes/strip.scene");
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "strip.scene: not a drape replay"));
	snprintf(args, sizeof args, "%s/short.drr", dir);
	f = fopen(args, "wb");
	assert_non_null(f);
	assert_int_equal(fwrite("DRAPERPL", 1, 8, f), 8);
	assert_int_equal(fclose(f), 0);
	snprintf(args, sizeof args, "info '%s/short.drr'", dir);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "shorter than its 64-byte header"));
	snprintf(args, sizeof args, "events --node x '%s'", replay_path);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "--node 'x'"));
	snprintf(args, sizeof args, "events --node 999 '%s'", replay_path);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "expected a node below 16"));
	snprintf(args, sizeof args, "events --type bogus '%s'", replay_path);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	snprintf(args, sizeof args, "events --from -3 '%s'", replay_path);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	snprintf(args, sizeof args, "export '%s'", replay_path);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "expected --pc2"));
	drape(&r, "export --pc2 x.pc2 /no/such.drr");
	assert_int_equal(r.status, 2);
	drape(&r, "run --resume /no/such.drr");
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "/no/such.drr: cannot open"));
	snprintf(args, sizeof args, "run --resume '%s' " TOP_SRCDIR "/scenes/strip.scene",
	    replay_path);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	snprintf(args, sizeof args, "run --resume '%s' --dt 1ms", replay_path);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	snprintf(args, sizeof args, "run --resume '%s@40' --record '%s'", replay_path, replay_path);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "would overwrite the replay being resumed"));
	drape(&r, "run --keyframe-every 0 " TOP_SRCDIR "/scenes/strip.scene");
	assert_int_equal(r.status, 2);
	/* an output that cannot be written: exit 1 with the file named */
	snprintf(args, sizeof args, "run --record /no/such/dir/x.drr '%s'", tiny_scene_file());
	drape(&r, args);
	assert_int_equal(r.status, 1);
	assert_non_null(strstr(r.err, "/no/such/dir/x.drr: cannot create"));
	/* a full disk (a file size limit here): the run stops with a message,
	 * and what was written stays readable */
	snprintf(args, sizeof args, "trap '' XFSZ; ulimit -f 100; '%s' run --until 0.3 --record "
	    "'%s/full.drr' '%s/scenes/tablecloth.scene' >/dev/null 2>'%s/full.err'; echo $? "
	    ">'%s/full.rc'", DRAPE, dir, TOP_SRCDIR, dir, dir);
	assert_int_equal(system(args), 0);
	snprintf(args, sizeof args, "%s/full.rc", dir);
	slurp(args, r.out, sizeof r.out);
	assert_string_equal(r.out, "1\n");
	snprintf(args, sizeof args, "%s/full.err", dir);
	slurp(args, r.err, sizeof r.err);
	assert_non_null(strstr(r.err, "full.drr: write failed: File too large"));
	snprintf(args, sizeof args, "info '%s/full.drr'", dir);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "not closed"));
}

/*
 * drape events on a run recorded with its events' digest (the default)
 * prints, byte for byte, what it prints on the same run recorded with
 * --events stored: the tablecloth's first 0.6 s (the fast path) and the
 * strip's first second; info says how the events are held; --events
 * takes only stored or digest.
 */
static void
cli_events_digest_as_stored(void **state)
{
	static const char *const runs[][2] = { { "tablecloth", "0.6" }, { "strip", "1" } };
	struct result r;
	char args[3000], a[700], b[700];
	unsigned char *ta, *tb;
	size_t i, la, lb;

	(void)state;
	for (i = 0; i < 2; i++) {
		snprintf(args, sizeof args, "run --headless --until %s --record '%s/%s-d.drr' "
		    "'%s/scenes/%s.scene'", runs[i][1], dir, runs[i][0], TOP_SRCDIR, runs[i][0]);
		drape(&r, args);
		assert_int_equal(r.status, 0);
		snprintf(args, sizeof args, "run --headless --until %s --events stored --record "
		    "'%s/%s-s.drr' '%s/scenes/%s.scene'", runs[i][1], dir, runs[i][0], TOP_SRCDIR,
		    runs[i][0]);
		drape(&r, args);
		assert_int_equal(r.status, 0);
		snprintf(args, sizeof args, "'%s' events '%s/%s-d.drr' >'%s/ev-d.tsv' && "
		    "'%s' events '%s/%s-s.drr' >'%s/ev-s.tsv'", DRAPE, dir, runs[i][0], dir, DRAPE,
		    dir, runs[i][0], dir);
		assert_int_equal(system(args), 0);
		path_in_dir(a, sizeof a, "ev-d.tsv");
		path_in_dir(b, sizeof b, "ev-s.tsv");
		ta = slurp_file(a, &la);
		tb = slurp_file(b, &lb);
		assert_int_equal(la, lb);
		assert_memory_equal(ta, tb, la);
		assert_true(la > 100000);	/* thousands of events */
		print_message("%s to %s s: drape events gives the same %zu bytes from either\n",
		    runs[i][0], runs[i][1], la);
		free(ta);
		free(tb);
		snprintf(args, sizeof args, "info '%s/%s-d.drr'", dir, runs[i][0]);
		drape(&r, args);
		assert_non_null(strstr(r.out, " (a digest: recomputed when read)\n"));
		snprintf(args, sizeof args, "info '%s/%s-s.drr'", dir, runs[i][0]);
		drape(&r, args);
		assert_non_null(strstr(r.out, " (stored)\n"));
	}
	snprintf(args, sizeof args, "run --headless --events all --record '%s/x.drr' "
	    "'%s/scenes/strip.scene'", dir, TOP_SRCDIR);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "--events 'all': expected stored or digest"));
}

/* The replays that ship still open, whole, with the current reader. */
static void
shipped_replays(void **state)
{
	static const char *const names[] = { "tablecloth.drr", "strip.drr" };
	struct replay r;
	struct drape_err err;
	char path[700];
	size_t i;

	(void)state;
	for (i = 0; i < 2; i++) {
		snprintf(path, sizeof path, "%s/replays/%s", TOP_SRCDIR, names[i]);
		if (replay_open(&r, path, &err) != 0)
			fail_msg("%s", err.msg);
		assert_int_equal(r.nbad, 0);
		assert_false(r.cut);
		assert_true(r.hdr.flags & REPLAY_CLOSED);
		assert_true(r.nframes > 10 && r.nkeyframes >= 2);
		read_all(&r, NULL);
		replay_close(&r);
	}
}

/*
 * The shipped tablecloth and strip, whole (their fast path takes about a
 * second each): every event and every step's statistics the replay gives
 * back are the live run's, field for field, bit for bit, in order.
 */
static void
shipped_runs_events_equal_live(void **state)
{
	static const char *const names[] = { "tablecloth", "strip" };
	size_t i;

	(void)state;
	for (i = 0; i < 2; i++) {
		char path[700], *text;
		struct truth tr;
		struct replay r;
		struct replay_events re;
		struct drape_err err;
		size_t len, c, j, nev = 0;
		long steps = 0;

		snprintf(path, sizeof path, "%s/scenes/%s.scene", TOP_SRCDIR, names[i]);
		text = (char *)slurp_file(path, &len);
		text = realloc(text, len + 1);
		assert_non_null(text);
		text[len] = '\0';
		path_in_dir(path, sizeof path, "shipped.drr");
		record_text(&tr, path, text, 50);
		free(text);
		if (replay_open(&r, path, &err) != 0)
			fail_msg("%s", err.msg);
		replay_events_init(&re, &r, path);
		for (c = 0; c < r.nchunks; c++) {
			struct replay_steps ss;

			if (!replay_is_steps(r.chunk[c].kind))
				continue;
			/* a digest recomputed, in order: the run stepped once */
			assert_int_equal(r.chunk[c].kind, REPLAY_STEPS_DIGEST);
			chunk_events(&re, c, &ss);
			for (j = 0; j < ss.count; j++) {
				assert_int_equal(ss.s[j].step, steps);
				assert_memory_equal(ss.s[j].col.n, tr.st[steps].n, sizeof ss.s[j].col.n);
				steps++;
			}
			for (j = 0; j < ss.nev; j++)
				assert_true(events_equal(&ss.ev[j], &tr.ev[nev + j]));
			nev += ss.nev;
			replay_steps_free(&ss);
		}
		print_message("%s: %ld steps, %zu events, the replay's are the live run's\n",
		    names[i], steps, nev);
		assert_int_equal(re.steps, tr.nsteps);
		replay_events_free(&re);
		assert_int_equal(steps, tr.nsteps);
		assert_int_equal(nev, tr.nev);
		assert_true(nev > 10000);
		replay_close(&r);
		truth_free(&tr);
	}
}

/* The recorder's default keyframe interval: half a second of the step, at
 * most RECORD_KEYFRAME_MOST steps, which bounds what recomputing a
 * digest's events costs (a step far from its keyframe under rk4 took 5 s
 * at half a second, 3,774 steps). */
static void
keyframe_default_bounded(void **state)
{
	static const struct {
		const char *dt;
		long want;
	} c[] = {
		{ "10 ms", 50 },
		{ "1 ms", 500 },
		{ "0.1 ms", RECORD_KEYFRAME_MOST },
		{ "1 s", 1 },
	};
	char text[4096];
	size_t i;

	(void)state;
	for (i = 0; i < sizeof c / sizeof c[0]; i++) {
		struct scene sc;
		struct stepper *st;
		const char *at = strstr(tiny_scene, "dt = auto");

		assert_non_null(at);
		snprintf(text, sizeof text, "%.*sdt = %s%s", (int)(at - tiny_scene), tiny_scene,
		    c[i].dt, at + strlen("dt = auto"));
		parse_text(&sc, text);
		st = new_stepper(&sc);
		assert_int_equal(record_default_keyframes(st), c[i].want);
		stepper_free(st);
		scene_free(&sc);
	}
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(codec_round_trip),
		cmocka_unit_test(codec_grid_round_trip),
		cmocka_unit_test(grid_width_refused),
		cmocka_unit_test(keyframe_default_bounded),
		cmocka_unit_test(round_trip),
		cmocka_unit_test(lossy_round_trip),
		cmocka_unit_test(cut_at_every_byte),
		cmocka_unit_test(bit_flips),
		cmocka_unit_test(digest_mismatch),
		cmocka_unit_test(resume_every_keyframe),
		cmocka_unit_test(resume_every_keyframe_fast),
		cmocka_unit_test(resume_every_keyframe_bdf2),
		cmocka_unit_test(resume_every_keyframe_bdf2_long_steps),
		cmocka_unit_test(restore_checks),
		cmocka_unit_test(cli_record_resume),
		cmocka_unit_test(cli_events_node),
		cmocka_unit_test(cli_pc2),
		cmocka_unit_test(cli_info_damaged),
		cmocka_unit_test(cli_precision),
		cmocka_unit_test(cli_export_for_blender),
		cmocka_unit_test(cli_bad),
		cmocka_unit_test(cli_sigterm),
		cmocka_unit_test(cli_events_digest_as_stored),
		cmocka_unit_test(shipped_replays),
		cmocka_unit_test(shipped_runs_events_equal_live),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
