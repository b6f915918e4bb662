/* record.h: a run recorded into a replay file. The recorder watches the
 * stepper from outside, after each step: frames at the scene's output
 * rate, a keyframe every so many steps (and at the start and the end), and
 * each step's statistics and collision events. It never changes the run. */
#ifndef DRAPE_RECORD_H
#define DRAPE_RECORD_H

#include "replay.h"
#include "stepper.h"

struct recorder {
	struct replay_writer w;
	double rate;		/* frames per second of simulated time */
	long next_frame;	/* the frame number to write next */
	long keyframe_every;
	long last_key;		/* step of the last keyframe, -1: none */
};

/* The default keyframe interval: half a second of the scene's step, at
 * most RECORD_KEYFRAME_MOST steps. A digest's events are recomputed from
 * the keyframe before them (replay_events.h), so the steps between
 * keyframes bound what showing one step's events costs: under rk4 on the
 * tablecloth half a second is 3,774 steps, some 3 s of wall time, and a
 * jump in the terminal interface froze that long; 500 steps take about
 * 0.4 s there, for some 22 KB more a keyframe (the fast path's 50 steps
 * a half second are unchanged). */
#define RECORD_KEYFRAME_MOST 500
long record_default_keyframes(const struct stepper *st);

/* Opens path and writes the scene, a keyframe and a frame of the current
 * state (step 0, or where a resumed run starts); a file that cannot hold
 * them is removed. precision: the frames'
 * grid step in m (replay.h's lossy frames), 0 for exact float32.
 * events_stored: every event written (--events stored), not only their
 * digest, from which a reader recomputes them (replay_events.h). */
int record_open(struct recorder *rc, const char *path, const struct stepper *st,
    long keyframe_every, double precision, bool events_stored, struct drape_err *err);
/* The record of the step st has just taken (its events: the report's),
 * as the recorder writes it and a reader recomputing it compares. */
void record_step_of(const struct stepper *st, struct replay_step *s);

/* After each stepper_step that succeeded. */
int record_step(struct recorder *rc, const struct stepper *st, struct drape_err *err);
/* How the run ended, for the replay's header: REPLAY_END_INTERRUPTED,
 * _BLOWUP or _ERROR, or 0 for a run that reached its end time (the
 * default). Before record_close. */
void record_set_end(struct recorder *rc, uint32_t how);
/* A keyframe of the final state, then closes; frees rc even on error. */
int record_close(struct recorder *rc, const struct stepper *st, struct drape_err *err);

#endif
