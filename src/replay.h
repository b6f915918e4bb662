/* replay.h: replay files (drape-replay(5)): a header, then chunks each
 * compressed on its own and guarded by a CRC-32: the scene and its
 * resolved options, frames of float32 positions at the output rate,
 * keyframes of the full double state, every step's statistics and
 * collision events, and a closing index of the keyframes.
 *
 * The writer observes a run from outside the stepper: after each step it
 * is given the state and that step's events and statistics. The reader
 * treats a file as hostile: every length is checked before it is used, a
 * chunk that fails its CRC is counted and skipped, and a file cut anywhere
 * gives its whole chunks. Nothing here prints. */
#ifndef DRAPE_REPLAY_H
#define DRAPE_REPLAY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "err.h"
#include "event.h"
#include "stats.h"

/* Version 2 is version 1 with lossy frames chunks (REPLAY_FRAMES_Q);
 * version 3 writes its frames as chunks of the grid (REPLAY_FRAMES_GRID,
 * REPLAY_FRAMES_GRID_Q); version 4 writes its steps' events as a digest
 * (REPLAY_STEPS_DIGEST) unless asked to store them, and reads every kind;
 * in version 5 a keyframe of a multistep method (bdf2) may also hold the
 * state one step back. */
#define REPLAY_VERSION 5

enum replay_kind {
	REPLAY_META = 1,	/* scene text and resolved options */
	REPLAY_FRAMES = 2,	/* float32 positions at the output rate */
	REPLAY_KEYFRAME = 3,	/* the double state y (and its history), t, step, dt */
	REPLAY_STEPS = 4,	/* statistics and events of consecutive steps */
	REPLAY_INDEX = 5,	/* the keyframes' steps and offsets, at close */
	REPLAY_FRAMES_Q = 6,	/* positions rounded to a grid (--precision) */
	REPLAY_FRAMES_GRID = 7,	/* 2, predicted over the cloth's grid (version 3) */
	REPLAY_FRAMES_GRID_Q = 8,	/* 6, the same way */
	REPLAY_STEPS_DIGEST = 9,	/* 4 with a digest of the events, not them (version 4) */
};
#define REPLAY_KIND_MAX REPLAY_STEPS_DIGEST

/* Steps chunks, whether they store their events or a digest of them. */
static inline int
replay_is_steps(uint32_t kind)
{
	return kind == REPLAY_STEPS || kind == REPLAY_STEPS_DIGEST;
}

/* Frames chunks, exact or rounded: the same count, steps and times. */
static inline int
replay_is_frames(uint32_t kind)
{
	return kind == REPLAY_FRAMES || kind == REPLAY_FRAMES_Q || kind == REPLAY_FRAMES_GRID ||
	    kind == REPLAY_FRAMES_GRID_Q;
}

/* Frames chunks rounded to a grid step (--precision). */
static inline int
replay_frames_lossy(uint32_t kind)
{
	return kind == REPLAY_FRAMES_Q || kind == REPLAY_FRAMES_GRID_Q;
}

/* On-disk structs (little-endian; configure refuses big-endian hosts). */
struct replay_file_header {
	char magic[8];		/* "DRAPERPL" */
	uint32_t version;
	uint32_t flags;		/* REPLAY_CLOSED once closed cleanly, and how
				 * the run ended (REPLAY_END_*) */
	uint32_t nodes, triangles;
	uint64_t index_offset;	/* of the index chunk, 0 until closed */
	uint8_t reserved[28];
	uint32_t crc;		/* CRC-32 of the 60 bytes before it */
};
#define REPLAY_CLOSED 1u
/* With REPLAY_CLOSED: the run recorded stopped before its end time, the
 * file holding it up to there (none of them: it reached its end, or the
 * recording was stopped while the run went on). */
#define REPLAY_END_INTERRUPTED 2u	/* a signal stopped it */
#define REPLAY_END_BLOWUP 4u	/* the simulation diverged */
#define REPLAY_END_ERROR 8u	/* it could not go on: out of memory, the broad phase */
#define REPLAY_END_MASK 14u

struct replay_chunk_header {
	char magic[4];		/* "CHNK" */
	uint32_t kind;
	uint64_t first_step;
	uint32_t count;		/* frames, 1 keyframe, steps, index entries */
	uint32_t comp_len, raw_len;	/* payload, deflated and inflated */
	uint32_t crc;		/* CRC-32 of the 28 bytes before it, then the payload */
};

_Static_assert(sizeof(struct replay_file_header) == 64, "replay header is 64 bytes");
_Static_assert(sizeof(struct replay_chunk_header) == 32, "chunk header is 32 bytes");
_Static_assert(offsetof(struct replay_file_header, index_offset) == 24 &&
    offsetof(struct replay_file_header, crc) == 60, "replay header layout");
_Static_assert(offsetof(struct replay_chunk_header, first_step) == 8 &&
    offsetof(struct replay_chunk_header, crc) == 28, "chunk header layout");

/* What a run was made of: enough to make it again. */
struct replay_meta {
	char *name, *path, *text;	/* scene name, its path when recorded, its text */
	char *version;		/* of the drape that recorded it */
	double duration;	/* resolved --until */
	double dt;		/* resolved --dt: 0 for auto */
	int integrator;		/* enum integrator_kind */
	double dt_set;		/* the step it resolved to */
	double output_rate;	/* frames per second of simulated time */
	long keyframe_every;	/* steps between keyframes */
	uint32_t nodes, triangles;
	int *tri;		/* 3 per triangle, the cloth's, as OBJ faces */
	/* The writer's: node i's neighbours across the cloth are i - 1 and
	 * i - width (its grid's rows), for the frames' prediction; 0 for
	 * none. Not in the scene chunk: each frames chunk says its own. */
	uint32_t width;
	/* The writer's: frames rounded to this grid step (m), 0 for exact
	 * float32. Not in the scene chunk: each frames chunk says its own. */
	double precision;
	/* The writer's: store every event (REPLAY_STEPS) rather than their
	 * digest (REPLAY_STEPS_DIGEST), which a reader recomputes them
	 * against (replay_events.h). */
	bool events_stored;
};

/* Per step: what struct collide_stats says, and when. */
struct replay_step {
	long step;
	double t, dt;		/* after the step, and the step to try next */
	struct collide_stats col;
	long nev;		/* events of this step */
};

struct replay_writer {
	FILE *f;
	char *path;
	uint32_t nodes, triangles;
	uint32_t width;		/* the frames' grid (struct replay_meta) */
	long keyframe_every;
	bool events_stored;	/* struct replay_meta */
	bool failed;		/* a write failed: stop writing, and do not
				 * mark the file closed */
	uint32_t end;		/* REPLAY_END_*: how the run ended, set by its
				 * caller before the close */
	/* pending frames: float32, and when precision > 0 the same rounded to
	 * whole grid steps, while every value fits (q_fits) */
	double precision;
	float *fx;
	int32_t *fq;
	bool q_fits;
	uint64_t *fstep;
	double *ft;
	size_t nframes, frames_per_chunk;
	/* pending steps */
	struct replay_step *steps;
	size_t nsteps, steps_per_chunk;
	struct contact_event *ev;	/* stored events only */
	size_t nev, evcap;
	uint64_t digest;	/* of the pending steps' events */
	/* keyframes written, for the index */
	uint64_t *kstep, *koff;
	size_t nkey, keycap;
	unsigned char *buf;	/* scratch, grown as needed */
	size_t bufcap;
	/* the chunks being deflated beside the run, written in order a few
	 * chunks later, at a flush or at close (replay_writer.c write_chunk) */
	struct replay_jobs *jobs;
	long next_key;		/* the keyframe the next chunk is, or -1 */
	bool next_provisional;	/* the next chunk is (see flush_every) */
	uint64_t bytes;		/* the file's position: the chunks before it */
	/* Pending frames and steps are also written out once flush_every
	 * seconds of clock() have passed since they last were, so that a
	 * crash loses at most about twice that much of the run: as
	 * provisional chunks at the file's end (from prov_at on, 0 for
	 * none), which the next chunk the run's data makes is written over
	 * (the file cut after it), so that the file's bytes do not depend on
	 * the clock. Open sets REPLAY_FLUSH_SECONDS and the monotonic clock;
	 * a test may set others. */
	double flush_every;
	double (*clock)(void);
	double last_flush;
	uint64_t prov_at;
	bool cut_due;		/* the file to be cut after the next chunk */
};

#define REPLAY_FLUSH_SECONDS 1.0

/* A file that begins with these 8 bytes is a replay (drape-replay(5)). */
#define REPLAY_MAGIC "DRAPERPL"
#define REPLAY_MAGIC_LEN 8

int replay_writer_open(struct replay_writer *w, const char *path, const struct replay_meta *m,
    struct drape_err *err);
/* x is the positions of the nodes (3 doubles each), y the whole state. */
int replay_write_frame(struct replay_writer *w, long step, double t, const double *x,
    struct drape_err *err);
/* hist: the state one step back (6 * nodes doubles) of a multistep
 * method, or NULL. */
int replay_write_keyframe(struct replay_writer *w, long step, double t, double dt,
    const double *y, const double *hist, uint64_t hash, struct drape_err *err);
int replay_write_step(struct replay_writer *w, const struct replay_step *s,
    const struct contact_event *ev, struct drape_err *err);
/* Writes the pending frames and steps now, as chunks of their own. */
int replay_writer_flush(struct replay_writer *w, struct drape_err *err);
/* Writes what is pending, the index and the closed flag (with w->end);
 * frees w. Returns 0, or -1 with a message (the file is then readable up
 * to what was written). After an error of any writing function the file
 * is not marked closed: it may lack what was being written. */
int replay_writer_close(struct replay_writer *w, struct drape_err *err);
/* Gives the file up: closes it and removes it if it is a regular file
 * (what open made, not a device it was given); frees w. For a recording
 * that failed before it held anything of the run. */
void replay_writer_discard(struct replay_writer *w);

/* ---- reading ---- */

struct replay_chunk {
	uint32_t kind;
	uint64_t first_step;
	uint32_t count, comp_len, raw_len;
	uint64_t offset;	/* of its header */
	size_t ordinal;		/* its place among the file's chunks, from 0 */
};

struct replay_keyframe {
	long step;
	double t, dt;
	uint64_t hash;		/* stepper_hash at the time */
	double *y;		/* 6 * nodes */
	double *hist;		/* 6 * nodes, the state one step back; NULL for none */
};

struct replay_frames {
	double precision;	/* the grid step (m) of a lossy chunk, 0 if exact */
	size_t count;
	long *step;
	double *t;
	float *x;		/* count * 3 * nodes */
};

struct replay_steps {
	size_t count, nev;
	struct replay_step *s;
	struct contact_event *ev;
	bool has_digest;	/* a digest chunk: ev not stored, digest of them */
	uint64_t digest;
};

/* The digest of a steps chunk's events (REPLAY_STEPS_DIGEST): h starts at
 * REPLAY_DIGEST_SEED and takes each event's fields in turn, in the
 * chunk's order. It tells a different computation from the same one; it
 * is no defence against forgery. */
#define REPLAY_DIGEST_SEED UINT64_C(0xcbf29ce484222325)
uint64_t replay_digest_events(uint64_t h, const struct contact_event *ev, size_t nev);

/* Whether two records of a step say it did the same: its time and next
 * step, bit for bit, its events, contacts by type, corrections, passes,
 * nodes put back and whether it was left unresolved. Not the broad
 * phase's counters (its fills, pairs, tests, the hash's figures): they
 * depend on what it kept from earlier steps, which a keyframe does not
 * hold (the grid keeps its pairs while they hold: a run resumed from a
 * keyframe fills again where the recorded one had kept them), and the
 * same state gives the same contacts either way. */
bool replay_step_same(const struct replay_step *a, const struct replay_step *b);

struct replay {
	FILE *f;		/* or mem, len */
	const unsigned char *mem;
	uint64_t len;
	struct replay_file_header hdr;
	struct replay_meta meta;
	struct replay_chunk *chunk;	/* the intact chunks, in file order */
	size_t nchunks;
	size_t seen;		/* chunks found, intact or not */
	size_t nbad;		/* chunks that failed their CRC or checks */
	uint64_t bad_ordinal[8];	/* the first few of them */
	bool cut;		/* the file ends inside a chunk */
	uint64_t cut_offset;	/* where the last whole chunk ends */
	size_t nframes, nkeyframes, nstep_chunks;
	long last_step;		/* the last step with statistics, -1 for none */
	long nevents;
	double last_t;
};

/* Both return 0, or -1 with a message (no scene chunk, not a replay). A
 * file with bad or missing chunks opens; see nbad and cut. */
int replay_open(struct replay *r, const char *path, struct drape_err *err);
int replay_open_mem(struct replay *r, const void *buf, size_t len, struct drape_err *err);
void replay_close(struct replay *r);

/* Chunk i (of r->chunk) decoded; each returns 0 or -1 with a message. */
int replay_read_frames(const struct replay *r, size_t i, struct replay_frames *fr,
    struct drape_err *err);
int replay_read_keyframe(const struct replay *r, size_t i, struct replay_keyframe *kf,
    struct drape_err *err);
/* A steps chunk with its events; a digest chunk is refused (its events
 * are recomputed: replay_events.h). */
int replay_read_steps(const struct replay *r, size_t i, struct replay_steps *ss,
    struct drape_err *err);
void replay_frames_free(struct replay_frames *fr);
void replay_keyframe_free(struct replay_keyframe *kf);
/* A steps chunk's statistics only (ss->ev NULL, ss->nev its count), of
 * either kind (a digest chunk's digest with them): the head of the chunk
 * inflated, not its events, which are most of a run's file. The events
 * are checked when replay_read_steps reads them. */
int replay_read_step_stats(const struct replay *r, size_t i, struct replay_steps *ss,
    struct drape_err *err);
void replay_steps_free(struct replay_steps *ss);

/* The intact keyframe chunk with the largest step <= step (step < 0: the
 * last), or -1 for none. */
long replay_find_keyframe(const struct replay *r, long step);

#endif
