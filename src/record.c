/* record.c: what a run writes into its replay, and when. */
#include <math.h>
#include <string.h>

#include "config.h"
#include "record.h"

long
record_default_keyframes(const struct stepper *st)
{
	double k = floor(0.5 / st->dt_set + 0.5);

	return k >= 1 && k < 1e9 ? (long)k : 1;
}

/* Frame k belongs at t = k / rate; a state within a millionth of a step
 * of that time counts as reaching it (fixed steps land on it up to
 * rounding). */
static long
frames_reached(const struct recorder *rc, const struct stepper *st)
{
	return (long)floor((st->t + 1e-6 * st->dt_set) * rc->rate);
}

static int
keyframe(struct recorder *rc, const struct stepper *st, struct drape_err *err)
{
	rc->last_key = st->step;
	return replay_write_keyframe(&rc->w, st->step, st->t, st->dt, st->y, stepper_hash(st), err);
}

int
record_open(struct recorder *rc, const char *path, const struct stepper *st,
    long keyframe_every, struct drape_err *err)
{
	const struct scene *sc = st->sc;
	struct replay_meta m;

	memset(rc, 0, sizeof *rc);
	memset(&m, 0, sizeof m);
	m.name = sc->name;
	m.path = sc->path;
	m.text = sc->text;
	m.version = PACKAGE_VERSION;
	m.duration = sc->duration;
	m.dt = sc->dt;
	m.integrator = (int)sc->integrator;
	m.dt_set = st->dt_set;
	m.output_rate = sc->output_rate;
	m.keyframe_every = keyframe_every;
	m.nodes = (uint32_t)st->cl.n;
	m.triangles = (uint32_t)st->cl.ntri;
	m.tri = st->cl.tri;
	rc->rate = sc->output_rate;
	rc->keyframe_every = keyframe_every;
	rc->last_key = -1;
	if (replay_writer_open(&rc->w, path, &m, err) != 0)
		return -1;
	rc->next_frame = frames_reached(rc, st) + 1;
	if (keyframe(rc, st, err) != 0 ||
	    replay_write_frame(&rc->w, st->step, st->t, stepper_x(st), err) != 0) {
		replay_writer_close(&rc->w, NULL);
		return -1;
	}
	return 0;
}

int
record_step(struct recorder *rc, const struct stepper *st, struct drape_err *err)
{
	struct replay_step s;
	long reached;

	memset(&s, 0, sizeof s);
	s.step = st->step - 1;	/* the step just taken: its events carry this number */
	s.t = st->t;
	s.dt = st->dt;
	s.col = st->col.st;
	s.nev = (long)st->col.nev;
	if (!st->col.active) {
		memset(&s.col, 0, sizeof s.col);
		s.nev = 0;
	}
	if (replay_write_step(&rc->w, &s, st->col.ev, err) != 0)
		return -1;
	if ((reached = frames_reached(rc, st)) >= rc->next_frame) {
		rc->next_frame = reached + 1;
		if (replay_write_frame(&rc->w, st->step, st->t, stepper_x(st), err) != 0)
			return -1;
	}
	if (st->step % rc->keyframe_every == 0)
		return keyframe(rc, st, err);
	return 0;
}

int
record_close(struct recorder *rc, const struct stepper *st, struct drape_err *err)
{
	int bad = 0;

	if (!rc->w.failed && rc->last_key != st->step && keyframe(rc, st, err) != 0)
		bad = 1;
	if (replay_writer_close(&rc->w, bad ? NULL : err) != 0)
		bad = 1;
	return bad ? -1 : 0;
}
