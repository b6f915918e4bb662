/* check.c: the audit of a state, apart from the collision code it checks. */
#include "audit.h"
#include "check.h"

int
check_state(const struct scene *sc, const struct cloth *cl, const double *x,
    struct check_result *r)
{
	size_t o;
	int p;

	r->inside = 0;
	r->first[0] = r->first[1] = -1;
	if ((r->pairs = audit_self_intersections(x, cl->tri, cl->ntri, r->first)) < 0)
		return -1;
	for (o = 0; o < sc->nobstacles; o++) {
		const struct obstacle *ob = &sc->obstacles[o];

		if (ob->kind == OBSTACLE_MESH) {
			long k = audit_cross_intersections(x, cl->tri, cl->ntri, ob->mesh.x,
			    ob->mesh.tri, ob->mesh.ntri);

			if (k < 0)
				return -1;
			r->pairs += k;
			continue;	/* a mesh is a surface: crossing it is what counts */
		}
		for (p = 0; p < cl->n; p++)
			if (obstacle_distance(ob, v3_load(x + 3 * p), NULL, NULL) < 0)
				r->inside++;
	}
	return 0;
}
