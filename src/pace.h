/* pace.h: how fast the terminal interface plays a run or a replay: a
 * multiple of real time (1x by default, 1/64x to 64x by halves and
 * doubles), or as fast as it can; and the simulated time a frame should
 * reach at a wall time. The caller reads the clock: this is plain
 * arithmetic, tested on its own. */
#ifndef DRAPE_PACE_H
#define DRAPE_PACE_H

#include <stdbool.h>
#include <stddef.h>

#define PACE_MIN_LOG2 (-6)	/* 1/64 of real time */
#define PACE_MAX_LOG2 6		/* 64 times */

struct pace {
	int log2;		/* the multiple of real time: 2^log2 */
	bool flat_out;		/* as fast as it can, the multiple kept for after */
	double anchor_wall, anchor_t;	/* simulated time anchor_t at wall time anchor_wall */
};

/* Real time, anchored at (wall, t). */
void pace_init(struct pace *p, double wall, double t);
/* From here on the pace runs from simulated time t at wall time wall
 * (a start, a pause ended, a change of pace, a seek). */
void pace_anchor(struct pace *p, double wall, double t);
/* The multiple of real time, or 0 when flat out. */
double pace_factor(const struct pace *p);
/* The simulated time to reach by wall time wall; +infinity flat out. */
double pace_target(const struct pace *p, double wall);
/* A run that cannot keep up (more than slack wall seconds of simulated
 * time behind) is anchored where it is: it does not run ahead later to
 * make up what it could not do then. */
void pace_keep_up(struct pace *p, double wall, double t, double slack);
/* Twice or half as fast (dir > 0 or < 0), from flat out back to the
 * multiple; false at the limit (1/64x, 64x). */
bool pace_change(struct pace *p, int dir);
/* Flat out, or back to the multiple it had. */
void pace_toggle_flat_out(struct pace *p);
/* "1x", "4x", "1/2x", or "max". */
void pace_label(const struct pace *p, char *buf, size_t len);

#endif
