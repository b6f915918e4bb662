/* replay_events.c: a steps chunk's events, read or recomputed. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config.h"
#include "grow.h"
#include "record.h"
#include "replay_events.h"
#include "replay_run.h"

void
replay_events_init(struct replay_events *re, const struct replay *rp, const char *file)
{
	memset(re, 0, sizeof *re);
	re->rp = rp;
	re->file = file;
}

void
replay_events_free(struct replay_events *re)
{
	stepper_free(re->st);
	if (re->have_scene)
		scene_free(&re->sc);
	memset(re, 0, sizeof *re);
}

/* Where the recomputation can part from the recording: said with every
 * mismatch, since a replay recorded by another drape is the usual cause. */
static void
mismatch(const struct replay_events *re, struct drape_err *err, const char *what)
{
	const char *v = re->rp->meta.version;

	if (strcmp(v, PACKAGE_VERSION) != 0)
		err_set(err, "%s (recorded by drape %s, this is drape %s)", what, v, PACKAGE_VERSION);
	else
		err_set(err, "%s (this build or machine computes the run otherwise, or the file "
		    "was changed)", what);
}

/* If the state st has reached is a keyframe's (an intact one), whether
 * its hash is the recorded one: 0, or -1 with a message. */
static int
check_keyframe(struct replay_events *re, struct drape_err *err)
{
	const struct replay *rp = re->rp;
	struct stepper_report r;
	struct replay_keyframe kf;
	struct drape_err kerr;
	char what[160];
	size_t i;

	stepper_report(re->st, &r);
	for (i = 0; i < rp->nchunks; i++) {
		if (rp->chunk[i].kind != REPLAY_KEYFRAME || rp->chunk[i].first_step != (uint64_t)r.step)
			continue;
		if (replay_read_keyframe(rp, i, &kf, &kerr) != 0)
			continue;	/* a damaged keyframe checks nothing */
		if (kf.hash != stepper_hash(re->st)) {
			replay_keyframe_free(&kf);
			snprintf(what, sizeof what, "the state recomputed at step %ld is not the "
			    "keyframe's", r.step);
			mismatch(re, err, what);
			return -1;
		}
		replay_keyframe_free(&kf);
	}
	return 0;
}

/* One step of re->st; 0, or -1 with a message. */
static int
step_once(struct replay_events *re, struct drape_err *err)
{
	struct step_failure f;
	char why[600];

	if (stepper_done(re->st)) {
		err_set(err, "the recorded run ends before these steps");
		return -1;
	}
	if (stepper_step(re->st, &f) != STEP_OK) {
		step_failure_format(&f, why, sizeof why);
		err_set(err, "recomputing: %s", why);
		return -1;
	}
	re->steps++;
	return check_keyframe(re, err);
}

/* re->st at the state before step `first`, from the kept stepper if it
 * is there or can go on to it without passing a keyframe it could start
 * from, else from the keyframe at or before it. 0, or -1 with a message. */
static int
reach(struct replay_events *re, long first, struct drape_err *err)
{
	const struct replay *rp = re->rp;
	struct stepper_report r;
	struct drape_err e;
	long k = replay_find_keyframe(rp, first);

	if (!re->have_scene && !re->scene_bad) {
		if (replay_scene(rp, re->file, 0, &re->sc, &e) == 0)
			re->have_scene = true;
		else {
			re->scene_bad = true;
			re->scene_err = e;
		}
	}
	if (re->scene_bad) {
		*err = re->scene_err;
		return -1;
	}
	if (re->st != NULL) {
		stepper_report(re->st, &r);
		if (r.step > first || (k >= 0 && (long)rp->chunk[k].first_step > r.step)) {
			stepper_free(re->st);
			re->st = NULL;
		}
	}
	if (re->st == NULL && (re->st = replay_resume(rp, re->file, &re->sc, first, err)) == NULL)
		return -1;
	for (;;) {
		stepper_report(re->st, &r);
		if (r.step >= first)
			return 0;
		if (step_once(re, err) != 0)
			return -1;
	}
}

/* The events of steps chunk i recomputed into ss, which holds its stored
 * statistics and digest: 0, or -1 with why they are not the recorded. */
static int
recompute(struct replay_events *re, size_t i, struct replay_steps *ss, struct drape_err *err)
{
	const struct replay_chunk *c = &re->rp->chunk[i];
	struct contact_event *ev = NULL;
	size_t nev = 0, cap = 0, j;
	struct stepper_report r;
	struct replay_step s;
	char what[200];

	if (reach(re, (long)c->first_step, err) != 0)
		goto fail;
	for (j = 0; j < ss->count; j++) {
		if (step_once(re, err) != 0)
			goto fail;
		record_step_of(re->st, &s);
		stepper_report(re->st, &r);
		if (!replay_step_same(&s, &ss->s[j])) {
			snprintf(what, sizeof what, "step %ld recomputed does not give the recorded "
			    "statistics", step_shown(ss->s[j].step));
			mismatch(re, err, what);
			goto fail;
		}
		if (grow_array((void **)&ev, &cap, nev + (size_t)s.nev, sizeof *ev) != 0) {
			err_set(err, "out of memory");
			goto fail;
		}
		if (s.nev > 0)
			memcpy(ev + nev, r.ev, (size_t)s.nev * sizeof *ev);
		nev += (size_t)s.nev;
	}
	if (nev != ss->nev || replay_digest_events(REPLAY_DIGEST_SEED, ev, nev) != ss->digest) {
		mismatch(re, err, "the events recomputed are not the recorded (their digest differs)");
		goto fail;
	}
	ss->ev = ev != NULL ? ev : malloc(sizeof *ev);	/* not NULL: read */
	if (ss->ev == NULL) {
		err_set(err, "out of memory");
		return -1;
	}
	return 0;
fail:
	free(ev);
	/* the stepper is not the recorded run's: it is not gone on from */
	stepper_free(re->st);
	re->st = NULL;
	return -1;
}

int
replay_events_read(struct replay_events *re, size_t i, struct replay_steps *ss,
    struct drape_err *err)
{
	const struct replay_chunk *c = &re->rp->chunk[i];
	struct drape_err why;

	if (c->kind != REPLAY_STEPS_DIGEST)
		return replay_read_steps(re->rp, i, ss, err);
	if (replay_read_step_stats(re->rp, i, ss, err) != 0)
		return -1;
	if (recompute(re, i, ss, &why) != 0) {
		size_t n = strlen(re->file);
		const char *msg = why.msg;

		/* replay_resume's messages name the file, which the caller does */
		if (strncmp(msg, re->file, n) == 0 && strncmp(msg + n, ": ", 2) == 0)
			msg += n + 2;
		snprintf(re->why, sizeof re->why, "%s", msg);
		err_set(err, "the events of steps %ld to %ld are unavailable: %s",
		    step_shown((long)c->first_step), step_shown((long)(c->first_step + c->count - 1)),
		    msg);
		return REPLAY_EVENTS_UNAVAILABLE;
	}
	return 0;
}
