/* record.c: what a run writes into its replay, and when. */
#include <limits.h>
#include <math.h>
#include <string.h>

#include "config.h"
#include "record.h"
#include "network.h"

long
record_default_keyframes(const struct stepper *st)
{
	struct stepper_report r;
	double k;

	stepper_report(st, &r);
	k = floor(0.5 / r.dt_set + 0.5);
	if (k > RECORD_KEYFRAME_MOST)
		k = RECORD_KEYFRAME_MOST;
	return k >= 1 ? (long)k : 1;
}

/* Frame k belongs at t = k / rate; a state within a millionth of a step
 * of that time counts as reaching it (fixed steps land on it up to
 * rounding). */
static long
frames_reached(const struct recorder *rc, const struct stepper_report *r)
{
	double k = floor((r->t + 1e-6 * r->dt_set) * rc->rate);

	/* the scene's checks keep duration * output_rate to SCENE_MAX_FRAMES;
	 * past that (a scene made by hand) the count saturates rather than
	 * overflow a long */
	if (!(k >= 0))
		return 0;
	return k < (double)(LONG_MAX / 2) ? (long)k : LONG_MAX / 2;
}

static int
keyframe(struct recorder *rc, const struct stepper *st, struct drape_err *err)
{
	struct stepper_state s;

	stepper_save(st, &s);
	rc->last_key = s.step;
	return replay_write_keyframe(&rc->w, s.step, s.t, s.dt, s.y, s.hist, s.hash, err);
}

int
record_open(struct recorder *rc, const char *path, const struct stepper *st,
    long keyframe_every, double precision, bool events_stored, struct drape_err *err)
{
	const struct scene *sc = stepper_scene(st);
	const struct cloth *cl = &stepper_network(st)->cl;
	struct stepper_report r;
	struct replay_meta m;

	stepper_report(st, &r);
	memset(rc, 0, sizeof *rc);
	memset(&m, 0, sizeof m);
	m.name = sc->name;
	m.path = sc->path;
	m.text = sc->text;
	m.version = PACKAGE_VERSION;
	m.duration = sc->duration;
	m.dt = sc->dt;
	m.integrator = (int)sc->integrator;
	m.dt_set = r.dt_set;
	m.output_rate = sc->output_rate;
	m.keyframe_every = keyframe_every;
	m.nodes = (uint32_t)cl->n;
	m.width = cl->n == cl->nu * cl->nv ? (uint32_t)cl->nu : (uint32_t)cl->n;
	m.triangles = (uint32_t)cl->ntri;
	m.tri = cl->tri;
	m.precision = precision;
	m.events_stored = events_stored;
	rc->rate = sc->output_rate;
	rc->keyframe_every = keyframe_every;
	rc->last_key = -1;
	if (replay_writer_open(&rc->w, path, &m, err) != 0)
		return -1;
	rc->next_frame = frames_reached(rc, &r) + 1;
	/* the first frame goes out at once: a replay killed at any moment
	 * after this has a frame to show */
	if (keyframe(rc, st, err) != 0 ||
	    replay_write_frame(&rc->w, r.step, r.t, stepper_x(st), err) != 0 ||
	    replay_writer_flush(&rc->w, err) != 0) {
		/* a scene chunk and no frame (a full disk): nothing half-written */
		replay_writer_discard(&rc->w);
		return -1;
	}
	return 0;
}

void
record_step_of(const struct stepper *st, struct replay_step *s)
{
	struct stepper_report r;

	stepper_report(st, &r);
	memset(s, 0, sizeof *s);
	s->step = r.step - 1;	/* the step just taken: its events carry this number */
	s->t = r.t;
	s->dt = r.dt;
	if (r.collisions) {
		s->col = *r.last;
		s->nev = (long)r.nev;
	}
}

int
record_step(struct recorder *rc, const struct stepper *st, struct drape_err *err)
{
	struct stepper_report r;
	struct replay_step s;
	long reached;

	stepper_report(st, &r);
	record_step_of(st, &s);
	if (replay_write_step(&rc->w, &s, r.ev, err) != 0)
		return -1;
	if ((reached = frames_reached(rc, &r)) >= rc->next_frame) {
		rc->next_frame = reached + 1;
		if (replay_write_frame(&rc->w, r.step, r.t, stepper_x(st), err) != 0)
			return -1;
	}
	if (r.step % rc->keyframe_every == 0)
		return keyframe(rc, st, err);
	return 0;
}

void
record_set_end(struct recorder *rc, uint32_t how)
{
	rc->w.end = how & REPLAY_END_MASK;
}

int
record_close(struct recorder *rc, const struct stepper *st, struct drape_err *err)
{
	struct stepper_report r;
	int bad = 0;

	stepper_report(st, &r);
	if (!rc->w.failed && rc->last_key != r.step && keyframe(rc, st, err) != 0)
		bad = 1;
	if (replay_writer_close(&rc->w, bad ? NULL : err) != 0)
		bad = 1;
	return bad ? -1 : 0;
}
