/* broad.c: candidate pairs for the narrow phase, by the chapter's hash
 * (seed), by swept boxes in the same hash (grid), or all of them (brute). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "broad.h"

void
broad_init(struct broad *b, enum broad_mode mode)
{
	memset(b, 0, sizeof *b);
	b->mode = mode;
	hash_init(&b->hash);
	hash_init(&b->hash_edges);
}

void
broad_free(struct broad *b)
{
	hash_free(&b->hash);
	hash_free(&b->hash_edges);
	free(b->vt);
	free(b->ee);
	free(b->stamp);
	free(b->box);
	free(b->allowed);
	memset(b, 0, sizeof *b);
}

static int
grow(void **p, size_t *cap, size_t need, size_t size)
{
	void *np;
	size_t n = *cap ? *cap : 256;

	if (need <= *cap)
		return 0;
	while (n < need)
		n *= 2;
	if ((np = realloc(*p, n * size)) == NULL)
		return -1;
	*p = np;
	*cap = n;
	return 0;
}

static int
push_vt(struct broad *b, int v, int t)
{
	if (b->nvt == b->vtcap && grow((void **)&b->vt, &b->vtcap, b->nvt + 1, sizeof *b->vt) != 0)
		return -1;
	b->vt[b->nvt].v = v;
	b->vt[b->nvt++].t = t;
	return 0;
}

static int
push_ee(struct broad *b, int e1, int e2)
{
	if (b->nee == b->eecap && grow((void **)&b->ee, &b->eecap, b->nee + 1, sizeof *b->ee) != 0)
		return -1;
	b->ee[b->nee].a = e1 < e2 ? e1 : e2;
	b->ee[b->nee++].b = e1 < e2 ? e2 : e1;
	return 0;
}

static int
tri_has(const struct geom *g, int t, int v)
{
	const int *n = g->tri + 3 * t;

	return n[0] == v || n[1] == v || n[2] == v;
}

/* A vertex and a triangle (or two edges) that are all obstacle: never. */
static int
vt_static(const struct geom *g, int v, int t)
{
	return v >= g->ncloth && g->tri[3 * t] >= g->ncloth;
}

static int
ee_skip(const struct geom *g, int e1, int e2)
{
	const int *a = g->edge + 2 * e1, *b = g->edge + 2 * e2;

	return a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1] ||
	    (a[0] >= g->ncloth && b[0] >= g->ncloth);
}

static int
cmp_vt(const void *pa, const void *pb)
{
	const struct vt_pair *a = pa, *b = pb;

	if (a->v != b->v)
		return a->v < b->v ? -1 : 1;
	return (a->t > b->t) - (a->t < b->t);
}

static int
cmp_ee(const void *pa, const void *pb)
{
	const struct ee_pair *a = pa, *b = pb;

	if (a->a != b->a)
		return a->a < b->a ? -1 : 1;
	return (a->b > b->b) - (a->b < b->b);
}

/* Sorts the pairs of each run of one vertex (edge) by triangle (edge):
 * grid finds them vertex by vertex, in a few pairs a run, so insertion sort
 * beats a global sort. */
static void
sort_runs(struct broad *b)
{
	size_t i, j, k;

	for (i = 0; i < b->nvt; i = j) {
		for (j = i + 1; j < b->nvt && b->vt[j].v == b->vt[i].v; j++)
			;
		for (k = i + 1; k < j; k++) {
			struct vt_pair x = b->vt[k];
			size_t m = k;

			for (; m > i && b->vt[m - 1].t > x.t; m--)
				b->vt[m] = b->vt[m - 1];
			b->vt[m] = x;
		}
	}
	for (i = 0; i < b->nee; i = j) {
		for (j = i + 1; j < b->nee && b->ee[j].a == b->ee[i].a; j++)
			;
		for (k = i + 1; k < j; k++) {
			struct ee_pair x = b->ee[k];
			size_t m = k;

			for (; m > i && b->ee[m - 1].b > x.b; m--)
				b->ee[m] = b->ee[m - 1];
			b->ee[m] = x;
		}
	}
}

/* Sorted and without repeats, so that the narrow phase's order, and with it
 * the run, does not depend on how the pairs were found. */
static void
canonical(struct broad *b)
{
	size_t i, k;

	if (b->nvt > 0)		/* qsort may not take a null array */
		qsort(b->vt, b->nvt, sizeof *b->vt, cmp_vt);
	for (i = k = 0; i < b->nvt; i++)
		if (k == 0 || b->vt[i].v != b->vt[k - 1].v || b->vt[i].t != b->vt[k - 1].t)
			b->vt[k++] = b->vt[i];
	b->nvt = k;
	if (b->nee > 0)
		qsort(b->ee, b->nee, sizeof *b->ee, cmp_ee);
	for (i = k = 0; i < b->nee; i++)
		if (k == 0 || b->ee[i].a != b->ee[k - 1].a || b->ee[i].b != b->ee[k - 1].b)
			b->ee[k++] = b->ee[i];
	b->nee = k;
}

/* Not fmin and fmax: those are library calls, in the hot path. */
static void
box_add(double *bx, const double *p)
{
	int k;

	for (k = 0; k < 3; k++) {
		bx[k] = p[k] < bx[k] ? p[k] : bx[k];
		bx[3 + k] = p[k] > bx[3 + k] ? p[k] : bx[3 + k];
	}
}

static void
box_empty(double *bx)
{
	bx[0] = bx[1] = bx[2] = INFINITY;
	bx[3] = bx[4] = bx[5] = -INFINITY;
}

static int
box_overlap(const double *a, const double *b)
{
	return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] &&
	    a[2] <= b[5] && b[2] <= a[5];
}

/* The node pairs (A, B) the chapter tests: A against the triangles that
 * have B as a vertex, and B against those of A. */
static int
seed_pair(struct broad *b, const struct geom *g, int na, int nb, bool want_ee)
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
	if (!want_ee)
		return 0;
	for (k = g->vedge_start[na]; k < g->vedge_start[na + 1]; k++)
		for (l = g->vedge_start[nb]; l < g->vedge_start[nb + 1]; l++)
			if (!ee_skip(g, g->vedge[k], g->vedge[l]) &&
			    push_ee(b, g->vedge[k], g->vedge[l]) != 0)
				return -1;
	return 0;
}

static int
find_seed(struct broad *b, const struct geom *g, double cell, bool want_ee, struct drape_err *err)
{
	struct spatial_hash *h = &b->hash;
	double bx[6];
	size_t i;
	int v, e, f, d[3];

	box_empty(bx);
	for (v = 0; v < g->nv; v++)
		box_add(bx, g->x1 + 3 * v);
	if (hash_begin(h, cell, v3_load(bx), v3_load(bx + 3), (size_t)g->nv) != 0) {
		err_set(err, "spatial hash: out of memory, or %g m cubes are too small for "
		    "the scene's extent", cell);
		return -1;
	}
	/* the hash table is filled with every node's predicted position */
	for (v = 0; v < g->nv; v++) {
		hash_cube_of(h, v3_load(g->x1 + 3 * v), d);
		if (hash_insert(h, hash_key(h, d[0], d[1], d[2]), v) != 0) {
			err_set(err, "spatial hash: out of memory");
			return -1;
		}
	}
	/* only nodes that share a cube are tested */
	for (i = 0; i < h->nfilled; i++) {
		const struct hash_cube *c = &h->slot[h->filled[i]];

		if (c->count < 2)
			continue;
		for (e = c->head; e >= 0; e = h->next[e])
			for (f = h->next[e]; f >= 0; f = h->next[f]) {
				b->st.node_pairs++;
				if (h->item[e] >= g->ncloth && h->item[f] >= g->ncloth)
					continue;
				if (seed_pair(b, g, h->item[e], h->item[f], want_ee) != 0) {
					err_set(err, "broad phase: out of memory");
					return -1;
				}
			}
	}
	hash_stats(h, &b->st.hash);
	return 0;
}

static void
cube_range(const struct spatial_hash *h, const double *bx, int lo[3], int hi[3])
{
	hash_cube_of(h, v3_load(bx), lo);
	hash_cube_of(h, v3_load(bx + 3), hi);
}

/* Adds to bx where vertex v may be during the step. */
static void
vertex_box(double *bx, const struct geom *g, int v)
{
	if (g->vbox != NULL) {
		box_add(bx, g->vbox + 6 * v);
		box_add(bx, g->vbox + 6 * v + 3);
	} else {
		box_add(bx, g->x0 + 3 * v);
		box_add(bx, g->x1 + 3 * v);
	}
}

static void
allowed_box(double *bx, const struct broad *b, int v)
{
	box_add(bx, b->allowed + 6 * v);
	box_add(bx, b->allowed + 6 * v + 3);
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

/* A fill of h with the boxes [first, first + count), each in every cube it
 * overlaps. */
static int
fill_boxes(struct spatial_hash *h, const double *box, size_t first, size_t count, double cell,
    const double *region)
{
	size_t i, total = 0;
	int lo[3], hi[3], x, y, z;

	if (hash_begin(h, cell, v3_load(region), v3_load(region + 3), 1) != 0)
		return -1;
	for (i = first; i < first + count; i++) {
		cube_range(h, box + 6 * i, lo, hi);
		total += (size_t)(hi[0] - lo[0] + 1) * (size_t)(hi[1] - lo[1] + 1) *
		    (size_t)(hi[2] - lo[2] + 1);
	}
	if (hash_begin(h, cell, v3_load(region), v3_load(region + 3), total) != 0)
		return -1;
	for (i = first; i < first + count; i++) {
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
static int
find_grid(struct broad *b, const struct geom *g, double cell, bool want_ee, struct drape_err *err)
{
	struct spatial_hash *h = &b->hash, *he = &b->hash_edges;
	size_t nbox = g->ntri + (want_ee ? g->nedges : 0), i;
	double region[6], qb[6], skin = GRID_SKIN * cell;
	int lo[3], hi[3], x, y, z, v, k;

	if (grow((void **)&b->box, &b->boxcap, 6 * nbox, sizeof *b->box) != 0 ||
	    grow((void **)&b->stamp, &b->stampcap, nbox, sizeof *b->stamp) != 0 ||
	    grow((void **)&b->allowed, &b->allowedcap, 6 * (size_t)g->nv, sizeof *b->allowed) != 0)
		goto oom;
	for (v = 0; v < g->nv; v++) {
		double *a = b->allowed + 6 * v;

		box_empty(a);
		vertex_box(a, g, v);
		for (k = 0; k < 3; k++) {
			a[k] -= skin;
			a[3 + k] += skin;
		}
	}
	box_empty(region);
	for (i = 0; i < nbox; i++) {
		const int *n = i < g->ntri ? g->tri + 3 * i : g->edge + 2 * (i - g->ntri);
		int nn = i < g->ntri ? 3 : 2;
		double *bx = b->box + 6 * i;

		box_empty(bx);
		for (k = 0; k < nn; k++)
			allowed_box(bx, b, n[k]);
		box_add(region, bx);
		box_add(region, bx + 3);
		b->stamp[i] = -1;
	}
	if (nbox == 0)
		return 0;
	for (;;) {
		if (hash_begin(h, cell, v3_load(region), v3_load(region + 3), 1) == 0)
			break;
		if ((cell *= 2) > 1e300)
			goto oom;
	}
	b->st.cell = cell;
	/* triangles and edges in hashes of their own, on the same cubes: a
	 * node looks for triangles only, an edge for edges only */
	if (fill_boxes(h, b->box, 0, g->ntri, cell, region) != 0 ||
	    (want_ee && fill_boxes(&b->hash_edges, b->box, g->ntri, g->nedges, cell, region) != 0))
		goto oom;

	/* each node's swept box; for the seed narrow phase, widened to the
	 * segments from its neighbours at step k that it draws to the node */
	for (v = 0; v < g->nv; v++) {
		if (v >= g->ncloth && !want_ee)
			break;
		box_empty(qb);
		allowed_box(qb, b, v);
		for (k = g->vedge_start[v]; !want_ee && k < g->vedge_start[v + 1]; k++) {
			const int *en = g->edge + 2 * g->vedge[k];

			allowed_box(qb, b, en[0] == v ? en[1] : en[0]);
		}
		cube_range(h, qb, lo, hi);
		for (y = lo[1]; y <= hi[1]; y++)
			for (z = lo[2]; z <= hi[2]; z++)
				for (x = lo[0]; x <= hi[0]; x++) {
					const struct hash_cube *c = hash_find(h, hash_key(h, x, y, z));
					int e;

					for (e = c != NULL ? c->head : -1; e >= 0; e = h->next[e]) {
						int t = h->item[e];

						if ((size_t)t >= g->ntri || b->stamp[t] == v)
							continue;
						b->stamp[t] = v;
						if (!tri_has(g, t, v) && !vt_static(g, v, t) &&
						    box_overlap(qb, b->box + 6 * t) &&
						    push_vt(b, v, t) != 0)
							goto oom;
					}
				}
	}
	for (i = 0; want_ee && i < g->nedges; i++) {
		const double *eb = b->box + 6 * (g->ntri + i);

		cube_range(he, eb, lo, hi);
		for (y = lo[1]; y <= hi[1]; y++)
			for (z = lo[2]; z <= hi[2]; z++)
				for (x = lo[0]; x <= hi[0]; x++) {
					const struct hash_cube *c = hash_find(he, hash_key(he, x, y, z));
					int e;

					for (e = c != NULL ? c->head : -1; e >= 0; e = he->next[e]) {
						size_t it = (size_t)he->item[e], o = it - g->ntri;

						if (o <= i || b->stamp[it] == (int)i)
							continue;
						b->stamp[it] = (int)i;
						if (!ee_skip(g, (int)i, (int)o) &&
						    box_overlap(eb, b->box + 6 * it) &&
						    push_ee(b, (int)i, (int)o) != 0)
							goto oom;
					}
				}
	}
	hash_stats(h, &b->st.hash);
	return 0;
oom:
	err_set(err, "broad phase: out of memory");
	return -1;
}

static int
find_brute(struct broad *b, const struct geom *g, bool want_ee, struct drape_err *err)
{
	size_t t, e, f;
	int v;

	for (v = 0; v < g->nv; v++) {
		if (v >= g->ncloth && !want_ee)
			break;
		for (t = 0; t < g->ntri; t++)
			if (!tri_has(g, (int)t, v) && !vt_static(g, v, (int)t) &&
			    push_vt(b, v, (int)t) != 0)
				goto oom;
	}
	for (e = 0; want_ee && e < g->nedges; e++)
		for (f = e + 1; f < g->nedges; f++)
			if (!ee_skip(g, (int)e, (int)f) && push_ee(b, (int)e, (int)f) != 0)
				goto oom;
	return 0;
oom:
	err_set(err, "broad phase: out of memory");
	return -1;
}

int
broad_find(struct broad *b, const struct geom *g, double cell, enum narrow_mode narrow,
    struct drape_err *err)
{
	bool want_ee = narrow == NARROW_CCD;
	int rc;

	if (b->mode == BROAD_GRID && b->valid && b->valid_narrow == narrow &&
	    b->valid_cell == cell && b->valid_nv == g->nv && still_allowed(b, g)) {
		b->st.rebuilt = false;
		return 0;
	}
	b->valid = false;
	b->nvt = b->nee = 0;
	memset(&b->st, 0, sizeof b->st);
	b->st.rebuilt = true;
	b->st.cell = b->mode == BROAD_BRUTE ? 0 : cell;
	switch (b->mode) {
	case BROAD_SEED:
		rc = find_seed(b, g, cell, want_ee, err);
		break;
	case BROAD_GRID:
		rc = find_grid(b, g, cell, want_ee, err);
		break;
	default:
		rc = find_brute(b, g, want_ee, err);
		break;
	}
	if (rc != 0)
		return -1;
	if (b->mode == BROAD_SEED)
		canonical(b);
	else if (b->mode == BROAD_GRID)
		sort_runs(b);	/* found vertex by vertex, each triangle once */
	b->st.vt_pairs = (long)b->nvt;
	b->st.ee_pairs = (long)b->nee;
	if (b->mode == BROAD_GRID) {
		b->valid = true;
		b->valid_narrow = narrow;
		b->valid_cell = cell;
		b->valid_nv = g->nv;
	}
	return 0;
}
