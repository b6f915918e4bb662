/* check.c: the audit of a state, apart from the collision code it checks. */
#include "audit.h"
#include "check.h"

int
check_state(const struct scene *sc, const struct cloth *cl, const double *x,
    struct check_result *r)
{
	struct audit_result a;
	size_t o;
	int p;

	r->inside = 0;
	r->first[0] = r->first[1] = -1;
	if (audit_self(x, cl->tri, cl->ntri, r->first, &a) != 0)
		return -1;
	r->pairs = a.pairs;
	r->candidates = a.candidates;
	r->tests = a.tests;
	r->cut = a.cut;
	for (o = 0; o < sc->nobstacles; o++) {
		const struct obstacle *ob = &sc->obstacles[o];

		if (ob->kind == OBSTACLE_MESH) {
			if (audit_cross(x, cl->tri, cl->ntri, ob->mesh.x, ob->mesh.tri,
			    ob->mesh.ntri, &a) != 0)
				return -1;
			r->pairs += a.pairs;
			r->candidates += a.candidates;
			r->tests += a.tests;
			r->cut = r->cut || a.cut;
			continue;	/* a mesh is a surface: crossing it is what counts */
		}
		for (p = 0; p < cl->n; p++)
			if (obstacle_distance(ob, v3_load(x + 3 * p), NULL, NULL) < 0)
				r->inside++;
	}
	return 0;
}
