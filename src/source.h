/* source.h: what the TUI watches, behind a small interface: the current
 * state, one step forward, this step's contact events and collision
 * statistics, and a node's force. A live run (source_live.c, over a
 * stepper) is the only source now; a replay file will be a second one,
 * whose step reads the next frame, with seeking added to this interface
 * for the replay keys (frames, keyframes, go to a step, Home, End). */
#ifndef DRAPE_SOURCE_H
#define DRAPE_SOURCE_H

#include <stdbool.h>
#include <stddef.h>

#include "cloth.h"
#include "collide.h"
#include "forces.h"
#include "scene.h"
#include "vec3.h"

struct source_state {
	const struct scene *sc;
	const struct cloth *cl;	/* nodes, triangles, masses */
	const double *x, *v;	/* 3n each */
	const unsigned char *held;	/* n, or NULL: nodes on prescribed motion */
	double t, t_end, dt;
	long step;
	const char *integrator;
	struct energy energy;
};

struct source_stats {
	bool active;		/* anything to collide with */
	bool has_hash;		/* the broad phase fills a spatial hash */
	const char *broad;	/* its name */
	const struct collide_stats *step, *total;
	const struct hash_stats *hash;	/* its latest fill */
};

/* What a step did. */
enum source_step {
	SOURCE_STEPPED,
	SOURCE_END,		/* nothing after this step */
	SOURCE_FAILED,		/* a blow-up: the state stays at the last good step */
};

struct source {
	void *ctx;
	void (*state)(void *ctx, struct source_state *s);
	/* why gets a message on SOURCE_FAILED */
	enum source_step (*step)(void *ctx, char *why, size_t len);
	/* Nothing after the current state: the next step would be SOURCE_END. */
	bool (*done)(void *ctx);
	const struct contact_event *(*events)(void *ctx, size_t *n);
	void (*stats)(void *ctx, struct source_stats *s);
	/* The net force on a node at the current state; false when the source
	 * cannot tell (a replay without forces) or out of memory. */
	bool (*force)(void *ctx, int node, vec3 *f);
};

/* A live run: the stepper's own state. */
struct stepper;
struct source_live {
	struct stepper *st;
	double *accel;		/* 3n scratch, for force */
	long accel_step;	/* the step accel is of, -1: none */
};

/* st must outlive src; source_live_free frees what the source allocated. */
void source_live(struct source *src, struct source_live *lv, struct stepper *st);
void source_live_free(struct source_live *lv);

#endif
