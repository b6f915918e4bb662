/* replay_events.h: a steps chunk's statistics and collision events,
 * whatever its kind. A chunk that stores its events (REPLAY_STEPS) is
 * read; a digest chunk (REPLAY_STEPS_DIGEST) has its events recomputed:
 * the recorded run is stepped again from the last intact keyframe at or
 * before the chunk's first step (replay_resume), its steps' events
 * gathered, and each step's statistics, the events' digest and any
 * keyframe stepped past compared with the file's. Anything that differs
 * (another build, a machine that rounds otherwise, a damaged keyframe)
 * makes the chunk's events unavailable, with why: never a wrong event.
 *
 * Chunks asked for in step order (a whole file's events) are stepped
 * through once: the stepper is kept at the end of the last chunk
 * recomputed and goes on from there while no keyframe lies between. */
#ifndef DRAPE_REPLAY_EVENTS_H
#define DRAPE_REPLAY_EVENTS_H

#include <stdbool.h>

#include "replay.h"
#include "scene.h"
#include "stepper.h"

struct replay_events {
	const struct replay *rp;
	const char *file;	/* for messages */
	struct scene sc;	/* the replay's, once needed */
	bool have_scene;
	bool scene_bad;		/* its scene does not run here: why in scene_err */
	struct drape_err scene_err;
	struct stepper *st;	/* at the end of the last chunk that verified, or NULL */
	long steps;		/* steps taken in recomputing, for tests and measures */
	char why[512];		/* the last unavailable chunk's reason alone */
};

/* rp and file must outlive re; nothing is read until asked. */
void replay_events_init(struct replay_events *re, const struct replay *rp, const char *file);
void replay_events_free(struct replay_events *re);

#define REPLAY_EVENTS_UNAVAILABLE (-2)

/* Steps chunk i of re->rp with its events in ss (replay_steps_free it).
 * 0; -1 with a message when the chunk does not decode (as
 * replay_read_steps); REPLAY_EVENTS_UNAVAILABLE when its events cannot
 * be recomputed as recorded: err says "the events of steps A to B are
 * unavailable: WHY" (re->why the WHY alone), and ss holds the statistics
 * alone (ss->ev NULL). */
int replay_events_read(struct replay_events *re, size_t i, struct replay_steps *ss,
    struct drape_err *err);

#endif
