/* broad_brute.c: every pair, the ground truth the other modes are tested
 * against. */
#include "broad_impl.h"

int
broad_find_brute(struct broad *b, const struct geom *g, const struct broad_want *want)
{
	size_t t, e, f;
	int v;

	for (v = 0; v < g->nv; v++) {
		if (v >= g->ncloth && !want->mesh_vertices)
			break;
		if (stop_set(b->stop))
			return -1;
		for (t = 0; t < g->ntri; t++)
			if (!tri_has(g, (int)t, v) && !vt_static(g, v, (int)t) &&
			    push_vt(b, v, (int)t) != 0)
				return -1;
	}
	for (e = 0; want->edges && e < g->nedges; e++) {
		if (stop_set(b->stop))
			return -1;
		for (f = e + 1; f < g->nedges; f++)
			if (!ee_skip(g, (int)e, (int)f) && push_ee(b, (int)e, (int)f) != 0)
				return -1;
	}
	return 0;
}
