/* source_live.c: the source of a live run, over a stepper. */
#include <stdio.h>
#include <stdlib.h>

#include "source.h"
#include "stepper.h"

static void
live_state(void *ctx, struct source_state *s)
{
	struct source_live *lv = ctx;
	const struct stepper *st = lv->st;

	s->sc = st->sc;
	s->cl = &st->cl;
	s->x = stepper_x(st);
	s->v = stepper_v(st);
	s->held = st->pr.held;
	s->t = st->t;
	s->t_end = st->t_end;
	s->dt = st->dt;
	s->step = st->step;
	s->integrator = integrator_name(st->sc->integrator);
	stepper_energy(st, &s->energy);
}

static enum source_step
live_step(void *ctx, char *why, size_t len)
{
	struct source_live *lv = ctx;
	struct blowup bl;

	if (stepper_done(lv->st))
		return SOURCE_END;
	if (stepper_step(lv->st, &bl) != 0) {
		if (bl.node >= 0)
			snprintf(why, len, "blow-up at step %ld (t = %.6g s): node %d (i %d, j %d): %s",
			    bl.step, bl.t, bl.node, bl.i, bl.j, bl.why);
		else
			snprintf(why, len, "blow-up at step %ld (t = %.6g s): %s", bl.step, bl.t,
			    bl.why);
		return SOURCE_FAILED;
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

	*n = lv->st->col.nev;
	return lv->st->col.ev;
}

static void
live_stats(void *ctx, struct source_stats *s)
{
	struct source_live *lv = ctx;
	const struct stepper *st = lv->st;

	s->active = st->col.active;
	s->has_hash = st->col.active && st->col.pairs &&
	    (st->sc->col.broad == BROAD_SEED || st->sc->col.broad == BROAD_GRID);
	s->broad = broad_mode_name[st->sc->col.broad];
	s->step = &st->col.st;
	s->total = &st->col.total;
	s->hash = &st->col.st.broad.hash;
}

/* One force evaluation for all nodes, kept until the next step. */
static bool
live_force(void *ctx, int node, vec3 *f)
{
	struct source_live *lv = ctx;
	struct stepper *st = lv->st;

	if (node < 0 || node >= st->cl.n)
		return false;
	if (lv->accel == NULL &&
	    (lv->accel = malloc(3 * (size_t)st->cl.n * sizeof *lv->accel)) == NULL)
		return false;
	if (lv->accel_step != st->step) {
		forces_accel(&st->fo, st->t, stepper_x(st), stepper_v(st), lv->accel);
		lv->accel_step = st->step;
	}
	*f = v3_scale(v3_load(lv->accel + 3 * node), st->cl.mass[node]);
	return true;
}

void
source_live(struct source *src, struct source_live *lv, struct stepper *st)
{
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
}

void
source_live_free(struct source_live *lv)
{
	free(lv->accel);
	lv->accel = NULL;
}
