/* source_replay.c: the source of a replay file. The cursor is a state step;
 * the positions shown are those of the frame (or keyframe) at or before
 * it, the events and statistics those of the step that led to it. Frames
 * hold float32 positions only: there the velocities are the difference to
 * the previous frame and the force is not known; a keyframe has both
 * exactly. Chunks that would not decode are skipped: what is intact shows.
 *
 * Memory is bounded by a few chunks, not by the run: a long run's events
 * are most of its file (6 million, 160 MB, on the 2 s tablecloth), and
 * keeping them all decoded took 576 MB to show one frame of it. The open
 * reads the frames and keyframes and only the head of each steps chunk:
 * the steps' statistics (for the totals at any step; a few hundred bytes
 * a step), not their events. The cursor's events are read from their
 * chunk (the last one kept); the inspector's history (every event before
 * the cursor, per node the latest few) is carried forward as the cursor
 * moves forward, and going back restarts it from the nearest mark: the
 * history at the first step of every so many chunks, taken as the history
 * first passes there, at most MARK_BYTES in all.
 * Frames and keyframes are read when shown, the last frames chunk kept. */
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grow.h"
#include "replay_run.h"
#include "source.h"

/* Steps beyond this are a hostile file's, not a run's: left out, so that
 * the cursor's arithmetic never overflows. */
#define STEP_MAX (LONG_MAX / 4)

/* The history marks' memory, in all: about 60 marks of the tablecloth's
 * 625 nodes, so that a step back reads at most a chunk or two again. */
#define MARK_BYTES ((size_t)16 << 20)

struct replay_view {
	long step;
	double t;
	size_t chunk;		/* in rp.chunk */
	size_t k;		/* the frame in its chunk */
	bool key;		/* a keyframe: the double state */
};

static int
view_order(const void *a, const void *b)
{
	const struct replay_view *p = a, *q = b;

	if (p->step != q->step)
		return p->step < q->step ? -1 : 1;
	return (int)q->key - (int)p->key;	/* the keyframe first: it is exact */
}

static int
steps_order(const void *a, const void *b)
{
	const struct replay_stepchunk *p = a, *q = b;
	long s = p->s[0].step, t = q->s[0].step;

	return s < t ? -1 : s > t;
}

static int
add_view(struct source_replay *sr, size_t *cap, long step, double t, size_t chunk, size_t k,
    bool key)
{
	if (step < 0 || step > STEP_MAX)
		return 0;
	if (grow_array((void **)&sr->view, cap, sr->nviews + 1, sizeof *sr->view) != 0)
		return -1;
	sr->view[sr->nviews++] = (struct replay_view){ step, t, chunk, k, key };
	return 0;
}

static void
drop_marks(struct source_replay *sr)
{
	size_t i;

	for (i = 0; sr->mark != NULL && i < sr->nsteps; i++)
		evlog_free(&sr->mark[i]);
	free(sr->mark);
	sr->mark = NULL;
	sr->mark_every = 0;
}

/* Room for a mark at every mark_every-th steps chunk, where the chunks
 * are in step order and do not overlap (drape writes them so); no marks
 * otherwise. 0, or -1 out of memory. */
static int
plan_marks(struct source_replay *sr)
{
	size_t snap = (size_t)sr->net.cl.n *
	    (EVLOG_PER_NODE * sizeof(struct contact_event) + sizeof(long));
	size_t most = MARK_BYTES / snap > 0 ? MARK_BYTES / snap : 1, j;

	for (j = 1; j < sr->nsteps; j++)
		if (sr->steps[j].s[0].step <= sr->steps[j - 1].s[sr->steps[j - 1].count - 1].step)
			return 0;
	if (sr->nsteps == 0 || (sr->mark = calloc(sr->nsteps, sizeof *sr->mark)) == NULL)
		return sr->nsteps == 0 ? 0 : -1;
	sr->mark_every = (sr->nsteps + most - 1) / most;
	return 0;
}

/* Every intact chunk decoded once: the frames' and keyframes' steps and
 * times, the steps' statistics, and the history marks. */
static int
index_chunks(struct source_replay *sr, struct drape_err *err)
{
	size_t i, k, vcap = 0, scap = 0, j;
	struct drape_err ignored;

	for (i = 0; i < sr->rp.nchunks; i++) {
		const struct replay_chunk *c = &sr->rp.chunk[i];
		struct replay_frames fr;
		struct replay_keyframe kf;
		struct replay_steps ss;

		if (replay_is_frames(c->kind)) {
			if (replay_read_frames(&sr->rp, i, &fr, &ignored) != 0) {
				sr->nskipped++;
				continue;
			}
			for (k = 0; k < fr.count; k++)
				if (add_view(sr, &vcap, fr.step[k], fr.t[k], i, k, false) != 0) {
					replay_frames_free(&fr);
					goto oom;
				}
			replay_frames_free(&fr);
		} else if (c->kind == REPLAY_KEYFRAME) {
			if (replay_read_keyframe(&sr->rp, i, &kf, &ignored) != 0) {
				sr->nskipped++;
				continue;
			}
			if (add_view(sr, &vcap, kf.step, kf.t, i, 0, true) != 0) {
				replay_keyframe_free(&kf);
				goto oom;
			}
			replay_keyframe_free(&kf);
		} else if (replay_is_steps(c->kind)) {
			if (replay_read_step_stats(&sr->rp, i, &ss, &ignored) != 0) {
				sr->nskipped++;
				continue;
			}
			if (ss.count == 0 || ss.s[ss.count - 1].step > STEP_MAX) {
				replay_steps_free(&ss);
				continue;
			}
			if (grow_array((void **)&sr->steps, &scap, sr->nsteps + 1,
			    sizeof *sr->steps) != 0) {
				replay_steps_free(&ss);
				goto oom;
			}
			/* the statistics kept */
			sr->steps[sr->nsteps++] = (struct replay_stepchunk){ i, ss.count, ss.s };
			ss.s = NULL;
			replay_steps_free(&ss);
		}
	}
	if (sr->nviews == 0) {
		err_set(err, "%s: no intact frame or keyframe to show", sr->file);
		return -1;
	}
	qsort(sr->view, sr->nviews, sizeof *sr->view, view_order);
	for (i = 1, j = 0; i < sr->nviews; i++)	/* one view a step, the exact one */
		if (sr->view[i].step != sr->view[j].step)
			sr->view[++j] = sr->view[i];
	sr->nviews = j + 1;
	if (sr->nsteps > 0)
		qsort(sr->steps, sr->nsteps, sizeof *sr->steps, steps_order);
	if (plan_marks(sr) != 0)
		goto oom;
	sr->hist_at = LONG_MIN;	/* nothing logged yet */
	return 0;
oom:
	err_set(err, "%s: out of memory", sr->file);
	return -1;
}

/* The positions of view i into x (3n), and its velocities into v when it
 * is a keyframe (v may be NULL). */
static int
load_view(struct source_replay *sr, size_t i, double *x, double *v)
{
	const struct replay_view *vw = &sr->view[i];
	size_t n3 = 3 * (size_t)sr->net.cl.n, j;
	struct drape_err ignored;

	if (vw->key) {
		struct replay_keyframe kf;

		if (replay_read_keyframe(&sr->rp, vw->chunk, &kf, &ignored) != 0)
			return -1;
		memcpy(x, kf.y, n3 * sizeof *x);
		if (v != NULL)
			memcpy(v, kf.y + n3, n3 * sizeof *v);
		replay_keyframe_free(&kf);
		return 0;
	}
	if (!sr->fr_loaded || sr->fr_chunk != vw->chunk) {
		if (sr->fr_loaded)
			replay_frames_free(&sr->fr);
		sr->fr_loaded = false;
		if (replay_read_frames(&sr->rp, vw->chunk, &sr->fr, &ignored) != 0)
			return -1;
		sr->fr_loaded = true;
		sr->fr_chunk = vw->chunk;
	}
	if (vw->k >= sr->fr.count)
		return -1;
	for (j = 0; j < n3; j++)
		x[j] = sr->fr.x[vw->k * n3 + j];
	return 0;
}

/* Steps chunk i's events (of sr->rp.chunk) into ss: 0, or -1 if they
 * no longer decode (out of memory) or are unavailable (then ev_why says
 * why, for the screen). */
static int
read_events(struct source_replay *sr, size_t i, struct replay_steps *ss)
{
	struct drape_err err;
	int rc = replay_events_read(&sr->re, i, ss, &err);

	if (rc == REPLAY_EVENTS_UNAVAILABLE) {
		snprintf(sr->ev_why, sizeof sr->ev_why, "%s", err.msg);
		replay_steps_free(ss);
	}
	return rc == 0 ? 0 : -1;
}

/* Steps chunk j's events, kept among the last few read: their slot in
 * sr->evs, or SIZE_MAX if they no longer decode or are unavailable. The
 * cursor's slot is not the one replaced. */
static size_t
load_events(struct source_replay *sr, size_t j)
{
	size_t k, slot = SIZE_MAX;

	for (k = 0; k < SOURCE_EVENT_CHUNKS; k++)
		if (sr->evs_of[k] == j) {
			sr->evs_used[k] = ++sr->evs_clock;
			return k;
		}
	for (k = 0; k < SOURCE_EVENT_CHUNKS; k++)
		if (k != sr->evs_cursor && (slot == SIZE_MAX || sr->evs_used[k] < sr->evs_used[slot]))
			slot = k;
	replay_steps_free(&sr->evs[slot]);
	sr->evs_of[slot] = SIZE_MAX;
	if (read_events(sr, sr->steps[j].chunk, &sr->evs[slot]) != 0)
		return SIZE_MAX;
	sr->evs_of[slot] = j;
	sr->evs_used[slot] = ++sr->evs_clock;
	return slot;
}

/* The step record numbered step, or NULL; *ev and *nev get its events
 * (none if its chunk no longer decodes). */
static const struct replay_step *
find_step(struct source_replay *sr, long step, const struct contact_event **ev, size_t *nev)
{
	size_t i, j, at, slot;

	*ev = NULL;
	*nev = 0;
	sr->evs_cursor = SIZE_MAX;
	for (i = 0; i < sr->nsteps; i++) {
		const struct replay_stepchunk *sc = &sr->steps[i];

		if (step < sc->s[0].step || step > sc->s[sc->count - 1].step)
			continue;
		for (j = 0, at = 0; j < sc->count && sc->s[j].step != step; j++)
			at += (size_t)sc->s[j].nev;
		if (j == sc->count)
			continue;
		if (sc->s[j].nev > 0 && (slot = load_events(sr, i)) != SIZE_MAX &&
		    at + (size_t)sc->s[j].nev <= sr->evs[slot].nev) {
			*ev = sr->evs[slot].ev + at;
			*nev = (size_t)sc->s[j].nev;
			sr->evs_cursor = slot;
		}
		return &sc->s[j];
	}
	return NULL;
}

/* The last view at or before step (the first view when none is). */
static size_t
view_at(const struct source_replay *sr, long step)
{
	size_t lo = 0, hi = sr->nviews;

	while (hi - lo > 1) {
		size_t mid = lo + (hi - lo) / 2;

		if (sr->view[mid].step <= step)
			lo = mid;
		else
			hi = mid;
	}
	return lo;
}

/* The cursor at step (clamped); 0, or -1 out of memory (nothing changed). */
static int
set_cursor(struct source_replay *sr, long step)
{
	size_t n3 = 3 * (size_t)sr->net.cl.n, i, j;
	double *y;
	const struct replay_view *vw;

	if (step < sr->first)
		step = sr->first;
	if (step > sr->last)
		step = sr->last;
	i = view_at(sr, step);
	vw = &sr->view[i];
	if ((y = malloc(2 * n3 * sizeof *y)) == NULL)
		return -1;
	if (load_view(sr, i, y, y + n3) != 0)
		goto fail;
	if (!vw->key) {
		/* the backward difference; the forward one at the first frame */
		size_t other = i > 0 ? i - 1 : i + 1;
		double dt;

		memset(y + n3, 0, n3 * sizeof *y);
		if (other < sr->nviews) {
			if (load_view(sr, other, sr->prev, NULL) != 0)
				goto fail;
			dt = vw->t - sr->view[other].t;
			for (j = 0; j < n3 && dt != 0; j++)
				y[n3 + j] = (y[j] - sr->prev[j]) / dt;
		}
	}
	memcpy(sr->y, y, 2 * n3 * sizeof *y);
	free(y);
	sr->cursor = step;
	sr->cur = i;
	sr->exact = vw->key;
	sr->ev_why[0] = '\0';
	sr->rec = find_step(sr, step - 1, &sr->ev, &sr->nev);
	sr->step = step;
	sr->t = sr->rec != NULL ? sr->rec->t : vw->t;
	sr->dt = sr->rec != NULL ? sr->rec->dt : sr->rp.meta.dt_set;
	memset(&sr->total, 0, sizeof sr->total);
	for (i = 0; i < sr->nsteps; i++)
		for (j = 0; j < sr->steps[i].count && sr->steps[i].s[j].step < step; j++)
			stats_add(&sr->total, &sr->steps[i].s[j].col);
	return 0;
fail:
	free(y);
	return -1;
}

static void
replay_state(void *ctx, struct source_state *s)
{
	struct source_replay *sr = ctx;
	size_t n3 = 3 * (size_t)sr->net.cl.n;

	s->sc = &sr->sc;
	s->cl = &sr->net.cl;
	s->x = sr->y;
	s->v = sr->y + n3;
	s->held = sr->net.pr.held;
	s->t = sr->t;
	s->t_end = sr->sc.duration;
	s->dt = sr->dt;
	s->step = sr->step;
	s->integrator = integrator_name(sr->sc.integrator);
	forces_energy(&sr->net.fo, sr->t, s->x, s->v, &s->energy);
	s->v_note = sr->exact ? NULL : "v: frame differences";
	s->ev_note = sr->ev_why[0] != '\0' ? sr->ev_why : NULL;
}

/* The step of the next (dir > 0) or previous view after or before step
 * from, keyframes only if asked; -1 for none. */
static long
neighbour(const struct source_replay *sr, long from, int dir, bool keys)
{
	size_t i;

	if (dir > 0) {
		for (i = 0; i < sr->nviews; i++)
			if (sr->view[i].step > from && (!keys || sr->view[i].key))
				return sr->view[i].step;
	} else {
		for (i = sr->nviews; i-- > 0;)
			if (sr->view[i].step < from && (!keys || sr->view[i].key))
				return sr->view[i].step;
	}
	return -1;
}

/* Where a seek from step from goes: a step, or -1 for nowhere (an end, no
 * keyframe that way). Nothing is read. */
static long
replay_target(void *ctx, enum source_seek how, long step, long from)
{
	struct source_replay *sr = ctx;
	long to = -1;

	switch (how) {
	case SOURCE_FRAME_NEXT:
		/* past the last frame, the last step with statistics */
		if ((to = neighbour(sr, from, 1, false)) < 0 && from < sr->last)
			to = sr->last;
		break;
	case SOURCE_FRAME_PREV:
		to = neighbour(sr, from, -1, false);
		break;
	case SOURCE_KEY_NEXT:
		to = neighbour(sr, from, 1, true);
		break;
	case SOURCE_KEY_PREV:
		to = neighbour(sr, from, -1, true);
		break;
	case SOURCE_GOTO:
		to = step < sr->first ? sr->first : step > sr->last ? sr->last : step;
		break;
	case SOURCE_FIRST:
		to = sr->first;
		break;
	case SOURCE_LAST:
		to = sr->last;
		break;
	}
	return to < 0 || (to == from && how != SOURCE_GOTO) ? -1 : to;
}

static bool
replay_seek(void *ctx, enum source_seek how, long step)
{
	struct source_replay *sr = ctx;
	long to = replay_target(ctx, how, step, sr->cursor);

	return to >= 0 && set_cursor(sr, to) == 0;
}

static enum source_step
replay_step(void *ctx, char *why, size_t len)
{
	struct source_replay *sr = ctx;

	if (sr->cursor >= sr->last)
		return SOURCE_END;
	if (!replay_seek(ctx, SOURCE_FRAME_NEXT, 0)) {
		snprintf(why, len, "%s: out of memory for the frame after step %ld", sr->file,
		    sr->cursor);
		return SOURCE_FAILED;
	}
	return SOURCE_STEPPED;
}

static bool
replay_done(void *ctx)
{
	struct source_replay *sr = ctx;

	return sr->cursor >= sr->last;
}

static const struct contact_event *
replay_events(void *ctx, size_t *n)
{
	struct source_replay *sr = ctx;

	*n = sr->nev;
	return sr->ev;
}

static void
replay_stats(void *ctx, struct source_stats *s)
{
	struct source_replay *sr = ctx;

	s->active = collide_active(&sr->sc);
	s->has_hash = collide_uses_hash(&sr->sc);
	s->broad = broad_mode_name[sr->sc.col.broad];
	s->step = sr->rec != NULL ? &sr->rec->col : &sr->none;
	s->total = &sr->total;
	s->hash = &s->step->hash;
	s->recomputed = sr->re.steps;
}

/* Known at a keyframe only, whose velocities are exact. */
static bool
replay_force(void *ctx, int node, vec3 *f)
{
	struct source_replay *sr = ctx;
	const struct cloth *cl = &sr->net.cl;

	if (!sr->exact || node < 0 || node >= cl->n)
		return false;
	forces_accel(&sr->net.fo, sr->view[sr->cur].t, sr->y, sr->y + 3 * (size_t)cl->n,
	    sr->accel);
	*f = v3_scale(v3_load(sr->accel + 3 * node), cl->mass[node]);
	return true;
}

static void
replay_position(void *ctx, struct source_position *p)
{
	struct source_replay *sr = ctx;

	p->file = sr->file;
	p->frame = (long)sr->cur + 1;
	p->frames = (long)sr->nviews;
	p->frame_step = sr->view[sr->cur].step;
	p->first = sr->first;
	p->last = sr->last;
}

/* Logs the events of the steps from hist_at to before step `to`, from the
 * chunks that hold them, into the history. */
static void
advance_history(struct source_replay *sr, long to)
{
	size_t j, n;

	for (j = 0; j < sr->nsteps; j++) {
		const struct replay_stepchunk *sc = &sr->steps[j];
		const struct replay_steps *use;
		size_t slot;

		if (sc->s[sc->count - 1].step < sr->hist_at || sc->s[0].step >= to)
			continue;
		/* the chunks before this one are logged to its first step: a
		 * mark, if one is due here (and memory allows) */
		if (sr->mark_every > 0 && j % sr->mark_every == 0 && sr->mark[j].n == 0 &&
		    sc->s[0].step >= sr->hist_at && evlog_init(&sr->mark[j], sr->net.cl.n) == 0)
			evlog_copy(&sr->mark[j], &sr->hist);
		if ((slot = load_events(sr, j)) == SIZE_MAX)
			continue;
		use = &sr->evs[slot];
		/* a chunk's events are in step order */
		for (n = 0; n < use->nev && use->ev[n].step < to; n++)
			if (use->ev[n].step >= sr->hist_at)
				evlog_add(&sr->hist, &use->ev[n], 1);
	}
	sr->hist_at = to;
}

static void
replay_history(void *ctx, struct evlog *log)
{
	struct source_replay *sr = ctx;
	size_t i;

	if (sr->cursor < sr->hist_at) {
		/* back: from the last mark at or before the cursor */
		for (i = sr->nsteps; i-- > 0;)
			if (sr->mark != NULL && sr->mark[i].n > 0 &&
			    sr->steps[i].s[0].step <= sr->cursor)
				break;
		if (i < sr->nsteps) {
			evlog_copy(&sr->hist, &sr->mark[i]);
			sr->hist_at = sr->steps[i].s[0].step;
		} else {
			evlog_clear(&sr->hist);
			sr->hist_at = LONG_MIN;
		}
	}
	if (sr->cursor > sr->hist_at)
		advance_history(sr, sr->cursor);
	evlog_copy(log, &sr->hist);
}

int
source_replay_open(struct source *src, struct source_replay *sr, const char *path,
    struct drape_err *err)
{
	size_t n3, i;

	memset(sr, 0, sizeof *sr);
	memset(src, 0, sizeof *src);
	if ((sr->file = malloc(strlen(path) + 1)) == NULL) {
		err_set(err, "%s: out of memory", path);
		return -1;
	}
	strcpy(sr->file, path);
	if (replay_open(&sr->rp, path, err) != 0) {
		free(sr->file);
		sr->file = NULL;
		return -1;
	}
	if (replay_scene(&sr->rp, path, 0, &sr->sc, err) != 0)
		goto fail;
	if (replay_network(&sr->rp, path, &sr->sc, &sr->net, err) != 0) {
		scene_free(&sr->sc);
		goto fail;
	}
	sr->built = true;
	replay_events_init(&sr->re, &sr->rp, sr->file);
	n3 = 3 * (size_t)sr->net.cl.n;
	for (i = 0; i < SOURCE_EVENT_CHUNKS; i++)
		sr->evs_of[i] = SIZE_MAX;
	sr->evs_cursor = SIZE_MAX;
	if ((sr->y = malloc(2 * n3 * sizeof *sr->y)) == NULL ||
	    (sr->prev = malloc(n3 * sizeof *sr->prev)) == NULL ||
	    (sr->accel = malloc(n3 * sizeof *sr->accel)) == NULL ||
	    evlog_init(&sr->hist, sr->net.cl.n) != 0) {
		err_set(err, "%s: out of memory", path);
		goto fail;
	}
	if (index_chunks(sr, err) != 0)
		goto fail;
	sr->first = sr->view[0].step;
	sr->last = sr->view[sr->nviews - 1].step;
	for (i = 0; i < sr->nsteps; i++) {
		long after = sr->steps[i].s[sr->steps[i].count - 1].step + 1;

		if (after > sr->last)
			sr->last = after;
	}
	if (set_cursor(sr, sr->first) != 0) {
		err_set(err, "%s: out of memory", path);
		goto fail;
	}
	src->ctx = sr;
	src->state = replay_state;
	src->step = replay_step;
	src->done = replay_done;
	src->events = replay_events;
	src->stats = replay_stats;
	src->force = replay_force;
	src->seek = replay_seek;
	src->target = replay_target;
	src->position = replay_position;
	src->history = replay_history;
	return 0;
fail:
	source_replay_close(sr);
	return -1;
}

void
source_replay_close(struct source_replay *sr)
{
	size_t i;

	if (sr->built) {
		replay_events_free(&sr->re);
		network_free(&sr->net);
		scene_free(&sr->sc);
	}
	free(sr->y);
	for (i = 0; i < sr->nsteps; i++)
		free(sr->steps[i].s);
	free(sr->steps);
	for (i = 0; i < SOURCE_EVENT_CHUNKS; i++)
		replay_steps_free(&sr->evs[i]);
	evlog_free(&sr->hist);
	drop_marks(sr);
	free(sr->view);
	free(sr->prev);
	free(sr->accel);
	if (sr->fr_loaded)
		replay_frames_free(&sr->fr);
	if (sr->file != NULL)
		replay_close(&sr->rp);
	free(sr->file);
	memset(sr, 0, sizeof *sr);
}
