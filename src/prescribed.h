/* prescribed.h: specified displacements: pinned nodes and nodes moved with a
 * velocity or along a path. Such a node's position and velocity come from
 * here, never from its forces. */
#ifndef DRAPE_PRESCRIBED_H
#define DRAPE_PRESCRIBED_H

#include <stdbool.h>

#include "cloth.h"
#include "err.h"
#include "scene.h"

struct prescribed {
	const struct scene_motion *motions;
	int nmotions;
	int *start;		/* nodes of motion m are node[start[m] .. start[m+1]) */
	int *node;
	int nnodes;
	unsigned char *held;	/* per cloth node: 1 if its motion is prescribed */
};

/* Returns 0, or -1 with "FILE:LINE: ..." if a node is given two motions. */
int prescribed_build(struct prescribed *pr, const struct scene *sc, const struct cloth *cl,
    struct drape_err *err);
void prescribed_free(struct prescribed *pr);

/* Displacement from the start position, and velocity, of motion m at time t. */
void prescribed_motion(const struct scene_motion *m, double t, double d[3], double v[3]);

/* Writes the prescribed positions (if x) and velocities (if v) at time t. */
void prescribed_apply(const struct prescribed *pr, const struct cloth *cl, double t, double *x,
    double *v);

/* The fastest prescribed speed over the whole run, for scales. */
double prescribed_max_speed(const struct prescribed *pr);

#endif
