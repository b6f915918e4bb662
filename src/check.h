/* check.h: the independent audit of one state: intersecting pairs of the
 * cloth's non-adjacent triangles and of the cloth against obstacle meshes
 * (audit.h's exact tests), and nodes inside analytic obstacles (a mesh is
 * a surface, which may be a container: crossing it is what counts). */
#ifndef DRAPE_CHECK_H
#define DRAPE_CHECK_H

#include "cloth.h"
#include "scene.h"

struct check_result {
	long pairs;		/* intersecting triangle pairs */
	long inside;		/* nodes inside an obstacle */
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
