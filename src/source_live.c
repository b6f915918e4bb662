/* source_live.c: the source of a live run, over a stepper; it records
 * itself into a replay between record(path) and record(NULL). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "source.h"
#include "stepper.h"

static void
live_state(void *ctx, struct source_state *s)
{
	struct source_live *lv = ctx;
	const struct stepper *st = lv->st;
	const struct network *net = stepper_network(st);
	struct stepper_report r;

	stepper_report(st, &r);
	s->sc = stepper_scene(st);
	s->cl = &net->cl;
	s->x = stepper_x(st);
	s->v = stepper_v(st);
	s->held = net->pr.held;
	s->t = r.t;
	s->t_end = r.t_end;
	s->dt = r.dt;
	s->step = r.step;
	s->integrator = integrator_name(s->sc->integrator);
	stepper_energy(st, &s->energy);
	s->v_note = NULL;
	s->ev_note = NULL;
}

/* Closes the recording; 0, or -1 with a message. */
static int
record_stop(struct source_live *lv, struct drape_err *err)
{
	int rc = 0;

	if (!lv->recording)
		return 0;
	lv->recording = false;
	if (record_close(&lv->rec, lv->st, err) != 0)
		rc = -1;
	free(lv->rec_path);
	lv->rec_path = NULL;
	return rc;
}

static enum source_step
live_step(void *ctx, char *why, size_t len)
{
	struct source_live *lv = ctx;
	struct step_failure f;

	if (stepper_done(lv->st))
		return SOURCE_END;
	if (stepper_step(lv->st, &f) != STEP_OK) {
		if (f.status == STEP_STOPPED)
			return SOURCE_STOPPED;
		step_failure_format(&f, why, len);
		return f.status == STEP_BLOWUP ? SOURCE_FAILED : SOURCE_ERROR;
	}
	if (lv->recording) {
		struct drape_err err;

		if (record_step(&lv->rec, lv->st, &err) != 0) {
			struct drape_err ignored;
			struct stepper_report r;

			stepper_report(lv->st, &r);
			snprintf(lv->rec_error, sizeof lv->rec_error, "recording stopped at step %ld: %s",
			    r.step, err.msg);
			lv->rec_error_new = true;
			lv->rec_failed = true;
			record_stop(lv, &ignored);
		}
	}
	return SOURCE_STEPPED;
}

static bool
live_done(void *ctx)
{
	struct source_live *lv = ctx;

	return stepper_done(lv->st);
}

static const struct contact_event *
live_events(void *ctx, size_t *n)
{
	struct source_live *lv = ctx;
	struct stepper_report r;

	stepper_report(lv->st, &r);
	*n = r.nev;
	return r.ev;
}

static void
live_stats(void *ctx, struct source_stats *s)
{
	struct source_live *lv = ctx;
	struct stepper_report r;

	stepper_report(lv->st, &r);
	s->active = r.collisions;
	s->has_hash = r.uses_hash;
	s->broad = broad_mode_name[stepper_scene(lv->st)->col.broad];
	s->step = r.last;
	s->total = r.total;
	s->hash = &r.last->hash;
	s->recomputed = -1;
}

/* One force evaluation for all nodes, kept until the next step. */
static bool
live_force(void *ctx, int node, vec3 *f)
{
	struct source_live *lv = ctx;
	const struct network *net = stepper_network(lv->st);
	struct stepper_report r;

	if (node < 0 || node >= net->cl.n)
		return false;
	if (lv->accel == NULL &&
	    (lv->accel = malloc(3 * (size_t)net->cl.n * sizeof *lv->accel)) == NULL)
		return false;
	stepper_report(lv->st, &r);
	if (lv->accel_step != r.step) {
		forces_accel(&net->fo, r.t, stepper_x(lv->st), stepper_v(lv->st), lv->accel);
		lv->accel_step = r.step;
	}
	*f = v3_scale(v3_load(lv->accel + 3 * node), net->cl.mass[node]);
	return true;
}

static int
live_record(void *ctx, const char *path, char *why, size_t len)
{
	struct source_live *lv = ctx;
	struct drape_err err;
	long every = lv->keyframe_every > 0 ? lv->keyframe_every : record_default_keyframes(lv->st);

	if (path == NULL) {
		if (record_stop(lv, &err) == 0)
			return 0;
		snprintf(why, len, "%s", err.msg);
		return -1;
	}
	if (lv->recording) {
		snprintf(why, len, "already recording into %s", lv->rec_path);
		return -1;
	}
	if ((lv->rec_path = malloc(strlen(path) + 1)) == NULL) {
		snprintf(why, len, "out of memory");
		return -1;
	}
	strcpy(lv->rec_path, path);
	if (record_open(&lv->rec, path, lv->st, every, lv->precision, lv->events_stored,
	    &err) != 0) {
		struct stepper_report r;

		snprintf(why, len, "%s", err.msg);
		/* a recording asked for and not made: said again at the end
		 * (rec_failed), not only in the message line */
		stepper_report(lv->st, &r);
		snprintf(lv->rec_error, sizeof lv->rec_error, "recording from step %ld not made: %s",
		    r.step, err.msg);
		lv->rec_failed = true;
		free(lv->rec_path);
		lv->rec_path = NULL;
		return -1;
	}
	lv->recording = true;
	return 0;
}

static const char *
live_recording(void *ctx, const char **error)
{
	struct source_live *lv = ctx;

	if (error != NULL) {
		*error = lv->rec_error_new ? lv->rec_error : NULL;
		lv->rec_error_new = false;
	}
	return lv->recording ? lv->rec_path : NULL;
}

void
source_live(struct source *src, struct source_live *lv, struct stepper *st)
{
	memset(lv, 0, sizeof *lv);
	memset(src, 0, sizeof *src);
	lv->st = st;
	lv->accel = NULL;
	lv->accel_step = -1;
	src->ctx = lv;
	src->state = live_state;
	src->step = live_step;
	src->done = live_done;
	src->events = live_events;
	src->stats = live_stats;
	src->force = live_force;
	src->record = live_record;
	src->recording = live_recording;
}

void
source_live_free(struct source_live *lv)
{
	struct drape_err ignored;	/* run_tui stops a recording itself, to say why it failed */

	record_stop(lv, &ignored);
	free(lv->accel);
	lv->accel = NULL;
}
