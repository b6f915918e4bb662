/* broad_seed.c: the chapter's spatial enumeration (§3.3): nodes hashed by
 * their predicted position, the pairs of the nodes that share a cube. */
#include "broad_impl.h"

/* The node pairs (A, B) the chapter tests: A against the triangles that
 * have B as a vertex, and B against those of A. */
static int
seed_pair(struct broad *b, const struct geom *g, int na, int nb, const struct broad_want *want)
{
	int k, l, pass;

	for (pass = 0; pass < 2; pass++) {
		int v = pass ? nb : na, w = pass ? na : nb;

		for (k = g->vtri_start[w]; k < g->vtri_start[w + 1]; k++) {
			int t = g->vtri[k];

			if (!tri_has(g, t, v) && !vt_static(g, v, t) && push_vt(b, v, t) != 0)
				return -1;
		}
	}
	if (!want->edges)
		return 0;
	for (k = g->vedge_start[na]; k < g->vedge_start[na + 1]; k++)
		for (l = g->vedge_start[nb]; l < g->vedge_start[nb + 1]; l++)
			if (!ee_skip(g, g->vedge[k], g->vedge[l]) &&
			    push_ee(b, g->vedge[k], g->vedge[l]) != 0)
				return -1;
	return 0;
}

int
broad_find_seed(struct broad *b, const struct geom *g, double cell, const struct broad_want *want,
    bool *too_small)
{
	struct spatial_hash *h = &b->seed.hash;
	double bx[6];
	size_t i;
	int v, e, f, d[3];

	box_empty(bx);
	for (v = 0; v < g->nv; v++)
		box_add(bx, g->x1 + 3 * v);
	if (hash_begin(h, cell, v3_load(bx), v3_load(bx + 3), (size_t)g->nv) != 0) {
		*too_small = true;
		return -1;
	}
	/* the hash table is filled with every node's predicted position */
	for (v = 0; v < g->nv; v++) {
		if (stop_poll(v, b->stop))
			return -1;
		hash_cube_of(h, v3_load(g->x1 + 3 * v), d);
		if (hash_insert(h, hash_key(h, d[0], d[1], d[2]), v) != 0)
			return -1;
	}
	/* only nodes that share a cube are tested */
	for (i = 0; i < h->nfilled; i++) {
		const struct hash_cube *c = &h->slot[h->filled[i]];

		if (c->count < 2)
			continue;
		if (stop_poll(i, b->stop))
			return -1;
		for (e = c->head; e >= 0; e = h->next[e])
			for (f = h->next[e]; f >= 0; f = h->next[f]) {
				b->st.node_pairs++;
				if (h->item[e] >= g->ncloth && h->item[f] >= g->ncloth)
					continue;
				if (seed_pair(b, g, h->item[e], h->item[f], want) != 0)
					return -1;
			}
	}
	hash_stats(h, &b->st.hash);
	return 0;
}

