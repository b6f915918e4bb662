/* collide.h: contacts between the step k state and the predicted step k+1
 * state: the cloth against itself, against obstacle meshes (the same
 * narrow phase) and against analytic obstacles. It corrects the predicted
 * positions and velocities of the nodes that would break the network's
 * consistency, and keeps every contact of the step as an event.
 *
 * A step runs the broad phase (broad.h) over the geometry
 * (collide_geometry.c), then one of two narrow phases:
 * - narrow = seed (collide_seed.c) runs the chapter's procedure once: at
 *   the first hit of a node it is corrected (eq. 11-17), then the
 *   obstacles are checked for the nodes with no self-contact (§4);
 * - narrow = ccd (collide_ccd.c) finds every vertex-face and edge-edge
 *   contact over the step and answers it with an inelastic impulse shared
 *   by both sides (the node and the triangle, or the two edges) by their
 *   masses, then tests again the pairs whose nodes moved; from pass
 *   COLLIDE_FAILSAFE_PASS on, a contact still there sticks: its vertices go
 *   back to step k (where the network was consistent) at their mean
 *   velocity, which ends in at most one pass per node and leaves no
 *   crossing behind.
 * The analytic obstacles are collide_obstacle.c's; where a corrected node
 * goes is response_position's (response.h). */
#ifndef DRAPE_COLLIDE_H
#define DRAPE_COLLIDE_H

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>

#include "broad.h"
#include "cloth.h"
#include "narrow.h"
#include "response.h"
#include "scene.h"
#include "stats.h"

#define COLLIDE_FAILSAFE_PASS 5	/* ccd: from this pass on, a hit node goes back to step k */

struct collide {
	struct collision_opts opt;
	const struct obstacle *obst;
	size_t nobst;
	bool active;		/* anything to collide with at all */
	bool pairs;		/* self-contact or obstacle meshes: the broad phase runs */
	double cell;		/* L_ce */
	/* ccd: each vertex's box of the step is its swept box widened by pad
	 * times the step's largest motion (see collide_step, collide_set_pad) */
	double pad;
	/* ccd, position = slide: the most of step k's gap a correction
	 * restores (collide_set_slide_gap) */
	double slide_gap;

	/* the geometry: cloth nodes, then obstacle mesh vertices */
	int ncloth, nv;
	size_t ntri_cloth;
	double *x0, *x1, *v1;
	const double *v0;	/* the cloth's velocities at step k, during a step */
	int *tri, *edge;
	size_t ntri, nedges;
	int *vtri_start, *vtri, *vedge_start, *vedge;
	int *tri_obstacle;	/* per triangle: its obstacle, or -1 */
	int *tri_square;	/* per cloth triangle: its square of the grid */
	double *uv;		/* per cloth node: its place on the cloth at rest */
	unsigned char *fixed;	/* held nodes and obstacle vertices */
	double *inv_mass;	/* 1/m, 0 for what contacts cannot move */
	struct geom g;
	struct broad *br;

	/* per pass */
	unsigned char *changed, *changed_next, *frozen;
	double *box;		/* each vertex's swept box at the start of the step */

	const volatile sig_atomic_t *stop;	/* set: give the step up (NULL: never) */
	bool stopped;			/* the last step was given up for stop */

	struct contact_event *ev;	/* this step's events */
	size_t nev, evcap;
	struct collide_stats st, total;
};

/* What `[collision] memory = auto` allows the stages: half the machine's. */
double collide_default_memory(void);

/* What the broad phase must find for a narrow phase. */
struct broad_want collide_broad_want(enum narrow_mode narrow, bool self);

/* held marks the nodes on prescribed motion (never corrected); dt is the
 * scene's step and vmax the fastest a node is expected to move (eq. 21). */
int collide_init(struct collide *c, const struct scene *sc, const struct cloth *cl,
    const unsigned char *held, double dt, double vmax, struct drape_err *err);
void collide_free(struct collide *c);

/* ccd: each vertex's box of a step is its swept box widened by pad times
 * the step's largest motion. collide_init's 2 holds every correction but
 * the rare one that is clamped; a method whose own contacts make the
 * corrections few and small may take less. */
void collide_set_pad(struct collide *c, double pad);

/* ccd with position = slide: a correction restores step k's gap along the
 * contact's normal, or gap if that is less (INFINITY, as collide_init
 * sets it: all of it). At a step of milliseconds the gap at step k is a
 * few microns; at a step of a frame it may be centimetres, and restoring
 * it all throws the two sides that far apart. */
void collide_set_slide_gap(struct collide *c, double gap);

/* Polls *flag in the broad phase and the ccd passes: once it is set, the
 * step is given up (c->stopped). NULL: never. */
void collide_set_stop(struct collide *c, const volatile sig_atomic_t *flag);

/* y0 is the consistent state k, y1 the predicted state k+1 (positions then
 * velocities), corrected in place. Returns 0, or -1 with a message. */
int collide_step(struct collide *c, long step, double dt, const double *y0, double *y1,
    struct drape_err *err);

/* collide_step is collide_begin (no events, statistics zero), then
 * collide_check, then collide_end (the step's statistics into the run's),
 * so that a step may add events of its own in between, or check more than
 * once (the fast path's windows): the step's statistics sum its checks'
 * (their passes: the most). */
void collide_begin(struct collide *c);
int collide_check(struct collide *c, long step, double dt, const double *y0, double *y1,
    struct drape_err *err);
void collide_end(struct collide *c);

/* The broad phase's pairs (in c's broad phase) for the motion the state
 * y0 would make over h at its velocities, each node's box (c->box)
 * widened by margin and share of its own motion, of which only those that
 * may lie within near plus near_motion times their relative motion at the
 * start are needed (broad_want): the fast path's contacts are taken from
 * them at a step's start (contacts.h). 0, or -1 with a message. */
int collide_candidates(struct collide *c, const double *y0, double h, double margin, double share,
    double near, double near_motion, struct drape_err *err);

/* A pair of collide_candidates, as the fast path's contacts take it: a
 * vertex then a triangle's three vertices (other: the triangle), or two
 * edges' (other: -1 - the second edge); the mesh's obstacle, or -1 for
 * cloth on cloth, and the friction between the two. */
struct collide_pair {
	int vert[4];
	int other;
	int obstacle;
	double mu;
};

/* Calls fn on each pair of the last collide_candidates that the scene
 * collides (cloth on cloth with self-contact only, never two meshes) and
 * whose two sides' boxes overlap, in the broad phase's order. 0; 1 when
 * the stop flag is set (the step is given up); else fn's first nonzero. */
int collide_each_pair(const struct collide *c, int (*fn)(void *ctx, const struct collide_pair *p),
    void *ctx);

/* Records a contact of the step as an event (and a correction); 0, or -1
 * out of memory. */
int collide_add_event(struct collide *c, long step, int node, enum contact_type type, int other,
    int obstacle, vec3 q, vec3 n, double vn_before, double vn_after);

/* The friction of a contact with the scene's obstacle, or of cloth on
 * cloth (obstacle -1). */
struct friction collide_friction(const struct collide *c, int obstacle);

/* The geometry as the broad phase sees it, for tests. */
static inline const struct geom *collide_geom(const struct collide *c) { return &c->g; }

#endif
