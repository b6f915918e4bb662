/* contacts.h: the fast path's contacts inside a step, between parts of the
 * cloth and between the cloth and obstacle meshes.
 *
 * Found once a step, at its start: the broad phase's pairs for the motion
 * the step is predicted to make (collide_candidates), kept where the two
 * sides' boxes of that motion overlap (so that every broad phase gives the
 * same pairs) and the sides are within reach of the cloth's thickness
 * during the step. Each
 * substep (pbd.h) then holds every kept pair at least a thickness apart,
 * on the side it was on at the step's start, pushing both sides by their
 * masses, with Coulomb friction on their relative sliding; a resting or
 * sliding contact costs one detection a step and a projection a substep,
 * not the repeated detect-and-correct passes the exact test needs at the
 * end of a long step, which remains (collide_step) as the guarantee. */
#ifndef DRAPE_CONTACTS_H
#define DRAPE_CONTACTS_H

#include <stdbool.h>
#include <stddef.h>

#include "vec3.h"

struct collide;

/* A pair is kept if its boxes overlap and its separation at the step's
 * start, less CONTACTS_REACH_MOTION times its predicted relative motion
 * (an allowance for the step's accelerations), is under CONTACTS_REACH
 * thicknesses; or, for a solver that holds a pair only along its
 * normal n0 (contacts_find's closing), less what that motion closes along
 * n0 and CONTACTS_REACH_SLACK times the motion. */
#define CONTACTS_REACH 1.25
#define CONTACTS_REACH_MOTION 1.5
#define CONTACTS_REACH_SLACK 0.5

struct contact_pair {
	int nv;			/* 4: a vertex against a triangle, or two edges */
	int vert[4];		/* vertex 0 (edge a), then the triangle (edge b) */
	int other;		/* the triangle or edge b, for the events */
	int obstacle;		/* the mesh's obstacle, or -1 for cloth on cloth */
	double n0[3];		/* at the step's start: from the second side to the first */
	double w[4];		/* the closest points' weights then (see contacts.c) */
	double mu;
	bool active;		/* it pushed in some substep */
	double vn_before;	/* the relative normal velocity at the start */
};

struct contacts {
	struct contact_pair *pair;
	size_t n, cap;
	double thickness;	/* the separation held */
	/* the pairs' geometry: vertices below ncloth are the cloth's nodes
	 * (in the caller's positions), the others the meshes' (at xmesh,
	 * which never move) */
	int ncloth;
	const double *xmesh;
	long found, active;	/* so far */
};

void contacts_init(struct contacts *ct, double thickness);
void contacts_free(struct contacts *ct);

/* No pairs this step (nothing to collide with). */
void contacts_clear(struct contacts *ct);

/* Whether a pair at separation d (from its second side to its first at
 * the step's start), whose vertices part by at most rel over the step and
 * its separation by moved (its weights' sum of their motions), may come
 * within reach (CONTACTS_REACH above; closing or not). */
bool contacts_may_reach(vec3 d, vec3 moved, double rel, double thickness, bool closing);

/* The pairs of the step from y0 (positions, velocities) and its length h:
 * the broad phase's candidates (found by collide_candidates into col)
 * kept where they may come within the thickness (closing: along their
 * normal, CONTACTS_REACH_SLACK). 0, 1 when col's stop flag is set (a
 * signal: the step is given up), or -1 out of memory. */
int contacts_find(struct contacts *ct, const struct collide *col, const double *y0, double h,
    bool closing);

/* One substep's projection of every pair, on cloth positions x (3n; the
 * meshes' vertices are where contacts_find saw them) moved from xprev in
 * the substep; w: the cloth nodes' inverse masses (0 held). */
void contacts_project(struct contacts *ct, const double *w, double *x, const double *xprev);

/* The step's active pairs as events of col, at step's end positions and
 * velocities y1. 0, or -1 out of memory. */
int contacts_events(struct contacts *ct, struct collide *col, long step, const double *y1);

#endif
