/* source.h: what the TUI watches, behind a small interface: the current
 * state, one step forward, this step's contact events and collision
 * statistics, and a node's force. Two sources: a live run (source_live.c,
 * over a stepper, which may record itself into a replay) and a replay file
 * (source_replay.c, whose step is the next frame and which seeks). The
 * optional ops say what a source can do: a NULL seek is a live run, whose
 * keys do not seek; a NULL record is a replay, which does not record. */
#ifndef DRAPE_SOURCE_H
#define DRAPE_SOURCE_H

#include <stdbool.h>
#include <stddef.h>

#include "cloth.h"
#include "event.h"
#include "evlog.h"
#include "forces.h"
#include "network.h"
#include "record.h"
#include "replay_events.h"
#include "scene.h"
#include "stats.h"
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
	/* NULL: v is the state's own; else how it was estimated (a replay's
	 * frames hold positions only) */
	const char *v_note;
	/* NULL: the events shown are the run's; else why some of them are
	 * not (a replay's digest that did not recompute: replay_events.h) */
	const char *ev_note;
};

struct source_stats {
	bool active;		/* anything to collide with */
	bool has_hash;		/* the broad phase fills a spatial hash */
	const char *broad;	/* its name */
	const struct collide_stats *step, *total;
	const struct hash_stats *hash;	/* its latest fill */
	/* A replay's: the steps run again so far to recompute its digest's
	 * events (what makes a first seek into a part of it slow); -1 live. */
	long recomputed;
};

/* Where a replay goes. */
enum source_seek {
	SOURCE_FRAME_NEXT,
	SOURCE_FRAME_PREV,
	SOURCE_KEY_NEXT,	/* the next keyframe */
	SOURCE_KEY_PREV,
	SOURCE_GOTO,		/* a step */
	SOURCE_FIRST,
	SOURCE_LAST,
};

/* Where a replay is: the step shown is a state step (after that many
 * steps); its positions are those of the frame at or before it. */
struct source_position {
	const char *file;
	long frame, frames;	/* from 1; of the frames and keyframes */
	long frame_step;	/* the step of the frame shown */
	long first, last;	/* the steps it can go to */
};

/* What a step did. */
enum source_step {
	SOURCE_STEPPED,
	SOURCE_END,		/* nothing after this step */
	SOURCE_FAILED,		/* a blow-up: the state stays at the last good step */
	SOURCE_ERROR,		/* the run cannot go on (out of memory): the same */
	SOURCE_STOPPED,		/* a signal gave the step up: the state is unchanged */
};

struct source {
	void *ctx;
	void (*state)(void *ctx, struct source_state *s);
	/* why gets a message on SOURCE_FAILED and SOURCE_ERROR */
	enum source_step (*step)(void *ctx, char *why, size_t len);
	/* Nothing after the current state: the next step would be SOURCE_END. */
	bool (*done)(void *ctx);
	const struct contact_event *(*events)(void *ctx, size_t *n);
	void (*stats)(void *ctx, struct source_stats *s);
	/* The net force on a node at the current state; false when the source
	 * cannot tell (a replay without forces) or out of memory. */
	bool (*force)(void *ctx, int node, vec3 *f);

	/* Replays only (NULL in a live run). seek returns false when it cannot
	 * move (at an end, no keyframe that way); step is for SOURCE_GOTO. */
	bool (*seek)(void *ctx, enum source_seek how, long step);
	/* Where seek would go from step from, without going: a step, or -1
	 * when it could not move; so that keys typed during a slow seek make
	 * one seek to where the last of them leads. */
	long (*target)(void *ctx, enum source_seek how, long step, long from);
	void (*position)(void *ctx, struct source_position *p);
	/* Logs the events of every step before the current state. */
	void (*history)(void *ctx, struct evlog *log);

	/* Live runs only (NULL in a replay). record starts recording into path,
	 * or stops (path NULL); 0, or -1 with a message. recording is the file
	 * being recorded or NULL; *error, if not NULL, gets why a recording
	 * stopped by itself (a write failed), once. */
	int (*record)(void *ctx, const char *path, char *why, size_t len);
	const char *(*recording)(void *ctx, const char **error);
};

/* A live run: the stepper's own state. */
struct stepper;
struct source_live {
	struct stepper *st;
	double *accel;		/* 3n scratch, for force */
	long accel_step;	/* the step accel is of, -1: none */
	long keyframe_every;	/* for recordings; 0: record_default_keyframes */
	double precision;	/* for recordings: record_open's */
	bool events_stored;	/* and its events_stored */
	bool recording;
	struct recorder rec;
	char *rec_path;
	char rec_error[600];	/* why the last recording that failed did */
	bool rec_error_new;
	bool rec_failed;	/* a recording stopped by itself, or could not
				 * start, at some point: the run's end says so */
};

/* st must outlive src; source_live_free closes a recording and frees what
 * the source allocated. */
void source_live(struct source *src, struct source_live *lv, struct stepper *st);
void source_live_free(struct source_live *lv);

/* A replay, its scene's network built from the recorded scene. The struct
 * must not move once open (the network points into it). */
struct replay_view;
/* A replay's steps chunk as its viewer keeps it: statistics only. */
#define SOURCE_EVENT_CHUNKS 4	/* steps chunks whose events a replay keeps */
struct replay_stepchunk {
	size_t chunk;		/* in rp.chunk */
	size_t count;
	struct replay_step *s;	/* count steps, each with its number of events */
};

struct source_replay {
	struct replay rp;
	char *file;
	struct scene sc;
	bool built;		/* sc and net are */
	struct network net;
	double *y;		/* the state shown: positions (3n) then velocities */
	long step;		/* its step, time and the step that followed */
	double t, dt;
	struct replay_view *view;	/* frames and keyframes, by step */
	size_t nviews;
	/* The intact steps chunks, by first step: their statistics kept from
	 * the open, their events read again when needed (source_replay.c). */
	struct replay_stepchunk *steps;
	size_t nsteps;
	struct replay_events re;	/* the steps' events, read or recomputed */
	char ev_why[512];	/* why some events since the cursor last moved are unavailable */
	/* The events of the steps chunks read last (recomputing a digest's
	 * runs a chunk's steps again: stepping across a chunk boundary and
	 * back recomputed both chunks each time, 0.12 s a frame), the least
	 * recently used replaced, never the cursor's (ev points into it). */
	struct replay_steps evs[SOURCE_EVENT_CHUNKS];
	size_t evs_of[SOURCE_EVENT_CHUNKS];	/* their indices in steps, or SIZE_MAX */
	unsigned long evs_used[SOURCE_EVENT_CHUNKS], evs_clock;
	size_t evs_cursor;	/* the slot of the cursor's events, or SIZE_MAX */
	struct evlog hist;	/* every event of the steps before hist_at */
	long hist_at;
	struct evlog *mark;	/* per steps chunk: hist at its first step, or empty */
	size_t mark_every;	/* chunks between marks; 0: none */
	size_t nskipped;	/* chunks that would not decode */
	long first, last;	/* the steps the cursor goes to */
	long cursor;		/* the state step shown */
	size_t cur;		/* its view: the last at or before the cursor */
	const struct replay_step *rec;	/* the step that led to the cursor, or NULL */
	const struct contact_event *ev;	/* its events */
	size_t nev;
	struct collide_stats total, none;
	bool exact;		/* v is a keyframe's */
	double *prev;		/* 3n: the previous view's positions */
	double *accel;		/* 3n scratch for force */
	struct replay_frames fr;	/* the frames chunk decoded last */
	size_t fr_chunk;
	bool fr_loaded;
};

/* Opens path and goes to its first frame. Returns 0, or -1 with a message
 * (not a replay, no intact frame, its scene does not parse). */
int source_replay_open(struct source *src, struct source_replay *sr, const char *path,
    struct drape_err *err);
void source_replay_close(struct source_replay *sr);

#endif
