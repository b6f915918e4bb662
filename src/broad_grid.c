/* broad_grid.c: swept boxes of the triangles and edges in a spatial hash,
 * each vertex's box looked up in it; the pairs are kept while every vertex
 * stays inside the box they were found for. */
#include "broad_impl.h"

static void
cube_range(const struct spatial_hash *h, const double *bx, int lo[3], int hi[3])
{
	hash_cube_of(h, v3_load(bx), lo);
	hash_cube_of(h, v3_load(bx + 3), hi);
}


/* grid: 1 if every vertex is still inside the box its pairs were found
 * for, so that they still hold. */
static int
still_allowed(const struct broad *b, const struct geom *g)
{
	int v, k;

	for (v = 0; v < g->nv; v++) {
		double bx[6];
		const double *a = b->allowed + 6 * v;

		box_empty(bx);
		vertex_box(bx, g, v);
		for (k = 0; k < 3; k++)
			if (bx[k] < a[k] || bx[3 + k] > a[3 + k])
				return 0;
	}
	return 1;
}

bool
broad_grid_holds(const struct broad *b, const struct geom *g, double cell,
    const struct broad_want *want)
{
	const struct broad_grid *gr = &b->grid;

	return gr->valid && gr->valid_want.edges == want->edges && gr->valid_want.self == want->self &&
	    gr->valid_want.mesh_vertices == want->mesh_vertices &&
	    gr->valid_want.neighbour_paths == want->neighbour_paths &&
	    gr->valid_cell == cell && gr->valid_nv == g->nv && still_allowed(b, g);
}

void
broad_grid_keep(struct broad *b, const struct geom *g, double cell, const struct broad_want *want)
{
	b->grid.valid = true;
	b->grid.valid_want = *want;
	b->grid.valid_cell = cell;
	b->grid.valid_nv = g->nv;
}

void
broad_grid_free(struct broad *b)
{
	hash_free(&b->grid.hash);
	hash_free(&b->grid.hash_edges);
	free(b->grid.stamp);
	free(b->grid.box);
	free(b->grid.big);
	free(b->grid.is_big);
}

/* The cubes box bx spans in h's fill, saturating. */
static size_t
span(const struct spatial_hash *h, const double *bx)
{
	int lo[3], hi[3];
	double n;

	cube_range(h, bx, lo, hi);
	n = (double)(hi[0] - lo[0] + 1) * (double)(hi[1] - lo[1] + 1) * (double)(hi[2] - lo[2] + 1);
	return n < (double)SIZE_MAX / 2 ? (size_t)n : SIZE_MAX / 2;
}

/*
 * The hash's memory and time go as the cubes the boxes span, which a box
 * much larger than a cube (a fast node, a mesh triangle metres wide) could
 * make anything at all. So a fill takes at most GRID_CUBES_PER_BOX cubes a
 * box on the whole: the largest boxes beyond that budget are kept out of
 * the hash, in a list that every query tests directly, which costs them
 * O(queries) each, as their geometry and not their extent says. The pairs
 * found are the same either way (box overlap decides, and they are
 * sorted), so only the cost changes.
 */
#define GRID_CUBES_PER_BOX 64
#define GRID_CUBES_SLACK 4096

/* The largest span that keeps boxes [first, first + count) within the
 * budget: boxes spanning more go to the big list. */
static size_t
span_limit(const struct spatial_hash *h, const double *box, size_t first, size_t count)
{
	size_t budget = GRID_CUBES_PER_BOX * count + GRID_CUBES_SLACK, limit = SIZE_MAX / 2, i;

	for (;;) {
		size_t total = 0, biggest = 0;

		for (i = first; i < first + count; i++) {
			size_t n = span(h, box + 6 * i);

			if (n <= limit) {
				total += n;
				biggest = n > biggest ? n : biggest;
			}
		}
		if (total <= budget || biggest <= 1)
			return limit;
		limit = biggest / 2;
	}
}

/* A fill of h with the boxes [first, first + count) that span at most
 * limit cubes, each in every cube it overlaps; the others are appended to
 * b->grid.big and marked in b->grid.is_big. */
static int
fill_boxes(struct broad *b, struct spatial_hash *h, size_t first, size_t count, double cell,
    const double *region, size_t limit)
{
	const double *box = b->grid.box;
	size_t i, total = 0;
	int lo[3], hi[3], x, y, z;

	for (i = first; i < first + count; i++) {
		size_t n = span(&b->grid.hash, box + 6 * i);	/* the same cubes as h's */

		b->grid.is_big[i] = n > limit;
		if (n <= limit)
			total += n;
		else if (grow_array((void **)&b->grid.big, &b->grid.bigcap, b->grid.nbig + 1, sizeof *b->grid.big) != 0)
			return -1;
		else
			b->grid.big[b->grid.nbig++] = (int)i;
	}
	/* an entry and a next link a cube item, two slots a cube at most */
	if (b->memory_limit > 0 && pair_bytes(b) + (double)total * (2 * sizeof(int) +
	    2 * sizeof(struct hash_cube)) > b->memory_limit) {
		b->over_memory = true;
		return -1;
	}
	if (hash_begin(h, cell, v3_load(region), v3_load(region + 3), total) != 0)
		return -1;
	for (i = first; i < first + count; i++) {
		if (b->grid.is_big[i])
			continue;
		if (stop_poll(i, b->stop))
			return -1;
		cube_range(h, box + 6 * i, lo, hi);
		for (y = lo[1]; y <= hi[1]; y++)
			for (z = lo[2]; z <= hi[2]; z++)
				for (x = lo[0]; x <= hi[0]; x++)
					if (hash_insert(h, hash_key(h, x, y, z), (int)i) != 0)
						return -1;
	}
	return 0;
}

/* grid: each vertex's box is widened by this fraction of the cube edge when
 * the pairs are found, and they are kept for the next steps as long as
 * every vertex stays inside its widened box (a Verlet list's skin) */
#define GRID_SKIN 0.1

/* Vertex v's pair with triangle t, if their boxes overlap. */
static int
try_vt(struct broad *b, const struct geom *g, int v, int t, const double *qb)
{
	if (b->grid.stamp[t] == v)
		return 0;
	b->grid.stamp[t] = v;
	if (!tri_has(g, t, v) && !vt_static(g, v, t) && box_overlap(qb, b->grid.box + 6 * t))
		return push_vt(b, v, t);
	return 0;
}

/* Edge i's pair with edge o > i, if their boxes overlap. */
static int
try_ee(struct broad *b, const struct geom *g, size_t i, size_t o, const double *eb)
{
	size_t it = g->ntri + o;

	if (o <= i || b->grid.stamp[it] == (int)i)
		return 0;
	b->grid.stamp[it] = (int)i;
	if (!ee_skip(g, (int)i, (int)o) && box_overlap(eb, b->grid.box + 6 * it))
		return push_ee(b, (int)i, (int)o);
	return 0;
}

/* The triangles near vertex v (query box qb): through the hash, or all of
 * them when qb spans more than limit cubes; and the big ones. */
static int
query_triangles(struct broad *b, const struct geom *g, int v, const double *qb, size_t limit)
{
	const struct spatial_hash *h = &b->grid.hash;
	int lo[3], hi[3], x, y, z, e;
	size_t k;

	if (span(h, qb) > limit) {
		for (k = 0; k < g->ntri; k++)
			if (try_vt(b, g, v, (int)k, qb) != 0)
				return -1;
		return 0;
	}
	cube_range(h, qb, lo, hi);
	for (y = lo[1]; y <= hi[1]; y++)
		for (z = lo[2]; z <= hi[2]; z++)
			for (x = lo[0]; x <= hi[0]; x++) {
				const struct hash_cube *c = hash_find(h, hash_key(h, x, y, z));

				for (e = c != NULL ? c->head : -1; e >= 0; e = h->next[e])
					if ((size_t)h->item[e] < g->ntri &&
					    try_vt(b, g, v, h->item[e], qb) != 0)
						return -1;
			}
	for (k = 0; k < b->grid.nbig_tri; k++)
		if (try_vt(b, g, v, b->grid.big[k], qb) != 0)
			return -1;
	return 0;
}

/* The edges after edge i near it: the same way. */
static int
query_edges(struct broad *b, const struct geom *g, size_t i, size_t limit)
{
	const struct spatial_hash *he = &b->grid.hash_edges;
	const double *eb = b->grid.box + 6 * (g->ntri + i);
	int lo[3], hi[3], x, y, z, e;
	size_t k;

	if (b->grid.is_big[g->ntri + i]) {
		for (k = i + 1; k < g->nedges; k++)
			if (try_ee(b, g, i, k, eb) != 0)
				return -1;
		return 0;
	}
	(void)limit;
	cube_range(he, eb, lo, hi);
	for (y = lo[1]; y <= hi[1]; y++)
		for (z = lo[2]; z <= hi[2]; z++)
			for (x = lo[0]; x <= hi[0]; x++) {
				const struct hash_cube *c = hash_find(he, hash_key(he, x, y, z));

				for (e = c != NULL ? c->head : -1; e >= 0; e = he->next[e])
					if (try_ee(b, g, i, (size_t)he->item[e] - g->ntri, eb) != 0)
						return -1;
			}
	for (k = b->grid.nbig_tri; k < b->grid.nbig; k++)
		if (try_ee(b, g, i, (size_t)b->grid.big[k] - g->ntri, eb) != 0)
			return -1;
	return 0;
}

/*
 * grid: the chapter's hash holds triangles (and edges) instead of nodes,
 * each in every cube its swept box (step k to k+1) overlaps, and each
 * node's swept box is looked up in every cube it overlaps (Teschner et al.
 * 2003). Why it never misses: every narrow test, seed or ccd, can only
 * report a contact at a point that lies in both the node's swept box (its
 * path for ccd; for seed also the segments F_k -> D_k+1 from its
 * neighbours) and the
 * triangle's swept box. Two boxes that share a point share a cube, since
 * both were put in every cube they overlap, whatever the cube size; the
 * cube size only sets the cost. Edges the same way. The pairs are found
 * for boxes widened by a skin and kept while each vertex's box of the step
 * stays inside its widened one: two boxes of a later step that share a
 * point lie in widened boxes that share it, whose pair was found.
 */
int
broad_find_grid(struct broad *b, const struct geom *g, double cell, const struct broad_want *want)
{
	struct spatial_hash *h = &b->grid.hash;
	size_t nbox = g->ntri + (want->edges ? g->nedges : 0), i, tri_limit, edge_limit = 0;
	double region[6], qb[6], skin = GRID_SKIN * cell;
	int v, k;

	if (grow_array((void **)&b->grid.box, &b->grid.boxcap, 6 * nbox, sizeof *b->grid.box) != 0 ||
	    grow_array((void **)&b->grid.stamp, &b->grid.stampcap, nbox, sizeof *b->grid.stamp) != 0 ||
	    grow_array((void **)&b->grid.is_big, &b->grid.is_bigcap, nbox, sizeof *b->grid.is_big) != 0 ||
	    grow_array((void **)&b->allowed, &b->allowedcap, 6 * (size_t)g->nv, sizeof *b->allowed) != 0)
		return -1;
	fill_allowed(b, g, skin);
	box_empty(region);
	for (i = 0; i < nbox; i++) {
		const int *n = i < g->ntri ? g->tri + 3 * i : g->edge + 2 * (i - g->ntri);
		int nn = i < g->ntri ? 3 : 2;
		double *bx = b->grid.box + 6 * i;

		box_empty(bx);
		for (k = 0; k < nn; k++)
			allowed_box(bx, b, n[k]);
		box_add(region, bx);
		box_add(region, bx + 3);
		b->grid.stamp[i] = -1;
	}
	if (nbox == 0)
		return 0;
	for (;;) {
		if (hash_begin(h, cell, v3_load(region), v3_load(region + 3), 1) == 0)
			break;
		if ((cell *= 2) > 1e300)
			return -1;
	}
	b->st.cell = cell;
	/* triangles and edges in hashes of their own, on the same cubes: a
	 * node looks for triangles only, an edge for edges only */
	b->grid.nbig = 0;
	tri_limit = span_limit(h, b->grid.box, 0, g->ntri);
	if (fill_boxes(b, h, 0, g->ntri, cell, region, tri_limit) != 0)
		return -1;
	b->grid.nbig_tri = b->grid.nbig;
	if (want->edges) {
		edge_limit = span_limit(h, b->grid.box, g->ntri, g->nedges);	/* h: the same cubes */
		if (fill_boxes(b, &b->grid.hash_edges, g->ntri, g->nedges, cell, region, edge_limit) != 0)
			return -1;
	}
	b->st.big = (long)b->grid.nbig;

	/* each node's swept box, widened if asked to the segments from its
	 * neighbours at step k to the node */
	for (v = 0; v < g->nv; v++) {
		if (v >= g->ncloth && !want->mesh_vertices)
			break;
		if (stop_poll(v, b->stop))
			return -1;
		box_empty(qb);
		allowed_box(qb, b, v);
		for (k = g->vedge_start[v]; want->neighbour_paths && k < g->vedge_start[v + 1]; k++) {
			const int *en = g->edge + 2 * g->vedge[k];

			allowed_box(qb, b, en[0] == v ? en[1] : en[0]);
		}
		if (query_triangles(b, g, v, qb, tri_limit > GRID_CUBES_PER_BOX ? tri_limit :
		    GRID_CUBES_PER_BOX) != 0)
			return -1;
	}
	for (i = 0; want->edges && i < g->nedges; i++) {
		if (stop_poll(i, b->stop))
			return -1;
		if (query_edges(b, g, i, edge_limit) != 0)
			return -1;
	}
	hash_stats(h, &b->st.hash);
	return 0;
}

