/* collide.h: contacts between the step k state and the predicted step k+1
 * state: the cloth against itself, against obstacle meshes (the same
 * narrow phase) and against analytic obstacles. It corrects the predicted
 * positions and velocities of the nodes that would break the network's
 * consistency, and keeps every contact of the step as an event.
 *
 * narrow = seed runs the chapter's procedure once: at the first hit of a
 * node it is corrected (eq. 11-17), then the obstacles are checked for the
 * nodes with no self-contact (§4).
 * narrow = ccd finds every vertex-face and edge-edge contact over the step
 * and answers it with an inelastic impulse shared by both sides (the node
 * and the triangle, or the two edges) by their masses, then tests again
 * the pairs whose nodes moved; from the sixth pass on, a contact still
 * there sticks: its vertices go back to step k (where the network was
 * consistent) at their mean velocity, which ends in at most one pass per
 * node and leaves no crossing behind. */
#ifndef DRAPE_COLLIDE_H
#define DRAPE_COLLIDE_H

#include <stdbool.h>
#include <stddef.h>

#include "broad.h"
#include "cloth.h"
#include "narrow.h"
#include "response.h"
#include "scene.h"

struct contact_event {
	long step;
	int node;		/* the corrected cloth node */
	enum contact_type type;
	int other;		/* triangle or edge (by type) of the geometry, or -1 */
	int obstacle;		/* the scene's obstacle, or -1 for the cloth itself */
	vec3 q, n;		/* contact point and unit normal */
	double vn_before, vn_after;	/* the node's velocity along n */
};

struct collide_stats {
	struct broad_stats broad;
	long narrow_tests;
	long contacts[CONTACT_NTYPES];
	long corrections;	/* node corrections */
	int passes;		/* ccd: detect-and-correct passes */
	long frozen;		/* ccd: nodes put back to step k as a last resort */
	long unresolved;	/* contacts left at the pass limit (prescribed motion) */
};

struct collide {
	struct collision_opts opt;
	const struct obstacle *obst;
	size_t nobst;
	bool active;		/* anything to collide with at all */
	bool pairs;		/* self-contact or obstacle meshes: the broad phase runs */
	double cell;		/* L_ce */

	/* the geometry: cloth nodes, then obstacle mesh vertices */
	int ncloth, nv;
	size_t ntri_cloth;
	double *x0, *x1, *v1;
	const double *v0;	/* the cloth's velocities at step k, during a step */
	int *tri, *edge;
	size_t ntri, nedges;
	int *vtri_start, *vtri, *vedge_start, *vedge;
	int *tri_obstacle;	/* per triangle: its obstacle, or -1 */
	unsigned char *fixed;	/* held nodes and obstacle vertices */
	double *inv_mass;	/* 1/m, 0 for what contacts cannot move */
	struct geom g;
	struct broad br;

	/* per pass */
	unsigned char *changed, *changed_next, *frozen;
	double *box;		/* each vertex's swept box at the start of the step */

	struct contact_event *ev;	/* this step's events */
	size_t nev, evcap;
	struct collide_stats st, total;
};

/* held marks the nodes on prescribed motion (never corrected); dt is the
 * scene's step and vmax the fastest a node is expected to move (eq. 21). */
int collide_init(struct collide *c, const struct scene *sc, const struct cloth *cl,
    const unsigned char *held, double dt, double vmax, struct drape_err *err);
void collide_free(struct collide *c);

/* y0 is the consistent state k, y1 the predicted state k+1 (positions then
 * velocities), corrected in place. Returns 0, or -1 with a message. */
int collide_step(struct collide *c, long step, double dt, const double *y0, double *y1,
    struct drape_err *err);

/* The geometry as the broad phase sees it, for tests. */
static inline const struct geom *collide_geom(const struct collide *c) { return &c->g; }

#endif
