/* check.h: the independent audit of one state: intersecting pairs of the
 * cloth's non-adjacent triangles and of the cloth against obstacle meshes
 * (audit.h's exact tests), nodes inside analytic obstacles (a mesh is a
 * surface, which may be a container: crossing it is what counts), and the
 * cloth's edges that pass into an analytic obstacle between their nodes:
 * a cloth draped over a box's edge or a disc's rim can cut its corner with
 * both nodes outside, which the nodes' count does not see. */
#ifndef DRAPE_CHECK_H
#define DRAPE_CHECK_H

#include "cloth.h"
#include "scene.h"

struct check_result {
	long pairs;		/* intersecting triangle pairs */
	long inside;		/* nodes inside an obstacle */
	long edges_in;		/* cloth edges some point of which is inside a
				 * plane, box, sphere or disc, their nodes maybe not */
	double edge_depth;	/* the deepest any of them goes, m (0: none) */
	int first[2];		/* the lowest cloth-cloth pair, when pairs > 0 */
	long candidates;	/* pairs of boxes the audits compared */
	long tests;		/* and the exact tests they made */
	bool cut;		/* an audit stopped at its bound (audit.h):
				 * pairs is a lower bound */
};

/* x holds the cloth's node positions. Returns 0, or -1 when out of memory. */
int check_state(const struct scene *sc, const struct cloth *cl, const double *x,
    struct check_result *r);

#endif
