/* broad.c: candidate pairs for the narrow phase, by the chapter's hash
 * (seed), by swept boxes in the same hash (grid), or all of them (brute). */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "broad.h"

const char *const broad_mode_name[] = { "seed", "grid", "brute", "bvh", NULL };

bool
broad_uses_hash(enum broad_mode mode)
{
	return mode == BROAD_SEED || mode == BROAD_GRID;
}

bool
broad_boxes_exact(enum broad_mode mode)
{
	return mode == BROAD_BVH;
}

void
broad_init(struct broad *b, enum broad_mode mode)
{
	memset(b, 0, sizeof *b);
	b->mode = mode;
	hash_init(&b->hash);
	hash_init(&b->hash_edges);
}

static void bvh_drop(struct broad *b);

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
	free(b->big);
	free(b->is_big);
	bvh_drop(b);
	free(b->stack);
	free(b->qbox);
	free(b->ebox);
	free(b->vnear);
	free(b->enear);
	free(b->tnear);
	free(b->held_vt);
	free(b->held_ee);
	free(b->held_box);
	free(b->dirty);
	free(b->found);
	free(b->dlist);
	free(b->tbox);
	free(b->tdef);
	free(b->nsum);
	free(b->cull);
	free(b->held_cull);
	memset(b, 0, sizeof *b);
}

static bool
stop_asked(const struct broad *b)
{
	return b->stop != NULL && *b->stop;
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
	if (n > SIZE_MAX / size || (np = realloc(*p, n * size)) == NULL)
		return -1;
	*p = np;
	*cap = n;
	return 0;
}

/* The pair lists' bytes, for the memory limit. */
static double
pair_bytes(const struct broad *b)
{
	return (double)(b->vtcap + b->held_vtcap) * sizeof *b->vt +
	    (double)(b->eecap + b->held_eecap) * sizeof *b->ee;
}

/* A pair list grown to hold need entries, within the memory limit. */
static int
grow_pairs(struct broad *b, void **p, size_t *cap, size_t need, size_t size)
{
	if (need > *cap && b->memory_limit > 0 &&
	    pair_bytes(b) + (double)*cap * (double)size > b->memory_limit) {
		b->over_memory = true;
		return -1;
	}
	return grow(p, cap, need, size);
}

static int
push_vt(struct broad *b, int v, int t)
{
	if (b->nvt == b->vtcap &&
	    grow_pairs(b, (void **)&b->vt, &b->vtcap, b->nvt + 1, sizeof *b->vt) != 0)
		return -1;
	b->vt[b->nvt].v = v;
	b->vt[b->nvt++].t = t;
	return 0;
}

static int
push_ee(struct broad *b, int e1, int e2)
{
	if (b->nee == b->eecap &&
	    grow_pairs(b, (void **)&b->ee, &b->eecap, b->nee + 1, sizeof *b->ee) != 0)
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

/* Pairs sorted between two polls of the stop flag: a few milliseconds. */
#define SORT_POLL_PAIRS 16384

/* Sorts the pairs of each run of one vertex (edge) by triangle (edge):
 * grid finds them vertex by vertex, in a few pairs a run, so insertion sort
 * beats a global sort. -1 when a signal asks to stop: a fast cloth's
 * millions of pairs take a quarter of a second to sort, too long to wait
 * for. */
static int
sort_runs(struct broad *b)
{
	size_t i, j, k, poll = 0;

	for (i = 0; i < b->nvt; i = j) {
		if (i >= poll) {
			if (stop_asked(b))
				return -1;
			poll = i + SORT_POLL_PAIRS;
		}
		for (j = i + 1; j < b->nvt && b->vt[j].v == b->vt[i].v; j++)
			;
		if (j - i > 32) {	/* a fast node's run: no quadratic sort */
			qsort(b->vt + i, j - i, sizeof *b->vt, cmp_vt);
			continue;
		}
		for (k = i + 1; k < j; k++) {
			struct vt_pair x = b->vt[k];
			size_t m = k;

			for (; m > i && b->vt[m - 1].t > x.t; m--)
				b->vt[m] = b->vt[m - 1];
			b->vt[m] = x;
		}
	}
	for (i = 0, poll = 0; i < b->nee; i = j) {
		if (i >= poll) {
			if (stop_asked(b))
				return -1;
			poll = i + SORT_POLL_PAIRS;
		}
		for (j = i + 1; j < b->nee && b->ee[j].a == b->ee[i].a; j++)
			;
		if (j - i > 32) {
			qsort(b->ee + i, j - i, sizeof *b->ee, cmp_ee);
			continue;
		}
		for (k = i + 1; k < j; k++) {
			struct ee_pair x = b->ee[k];
			size_t m = k;

			for (; m > i && b->ee[m - 1].b > x.b; m--)
				b->ee[m] = b->ee[m - 1];
			b->ee[m] = x;
		}
	}
	return 0;
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

/* Not fmin and fmax: those are library calls, in the hot path; unrolled
 * and inline, as the refit makes some 10,000 of these a traversal (gcc
 * -O2 kept it a call: 6 % of a fast run's instructions). */
static inline void
box_add(double *bx, const double *p)
{
	bx[0] = p[0] < bx[0] ? p[0] : bx[0];
	bx[1] = p[1] < bx[1] ? p[1] : bx[1];
	bx[2] = p[2] < bx[2] ? p[2] : bx[2];
	bx[3] = p[0] > bx[3] ? p[0] : bx[3];
	bx[4] = p[1] > bx[4] ? p[1] : bx[4];
	bx[5] = p[2] > bx[5] ? p[2] : bx[5];
}

static void
box_empty(double *bx)
{
	bx[0] = bx[1] = bx[2] = INFINITY;
	bx[3] = bx[4] = bx[5] = -INFINITY;
}

/* All six comparisons, without a branch between them: in a traversal the
 * outcome is a coin toss, and a mispredicted branch a comparison cost a
 * quarter of the tree's time. */
static int
box_overlap(const double *a, const double *b)
{
	return (a[0] <= b[3]) & (b[0] <= a[3]) & (a[1] <= b[4]) & (b[1] <= a[4]) &
	    (a[2] <= b[5]) & (b[2] <= a[5]);
}

/*
 * Whether two sets of points, in boxes of positions pa and pb at the step's
 * start (lo then hi, 6 each), moving by motions in boxes ma and mb, may lie
 * within near plus share times their relative motion (a broad_want's
 * near): the largest gap between the position boxes along an axis is at
 * most their distance, and the Minkowski difference of the motion boxes
 * bounds their relative motion. Two parts of a cloth that move together,
 * whose boxes of the step overlap by as much as they move, are tested as
 * if at rest.
 */
static int
near_overlap(const double *pa, const double *ma, const double *pb, const double *mb, double near,
    double share)
{
	double gap = 0, m2 = 0, r;
	int k;

	for (k = 0; k < 3; k++) {
		double g1 = pb[k] - pa[3 + k], g2 = pa[k] - pb[3 + k];
		double lo = ma[k] - mb[3 + k], hi = ma[3 + k] - mb[k];
		double m = -lo > hi ? -lo : hi;

		gap = g1 > gap ? g1 : gap;
		gap = g2 > gap ? g2 : gap;
		m2 += m * m;
	}
	r = gap - near;
	return r <= 0 || r * r <= share * share * m2;
}

/* The boxes (6 doubles each) of the positions and of the motions of the
 * nv vertices vert, from vnear's 6 a vertex, into out (12). */
static void
near_boxes(double *out, const double *vnear, const int *vert, int nv)
{
	int k;

	box_empty(out);
	box_empty(out + 6);
	for (k = 0; k < nv; k++) {
		box_add(out, vnear + 6 * vert[k]);
		box_add(out + 6, vnear + 6 * vert[k] + 3);
	}
}

/* The near test of vertex v against triangle t. */
static int
near_vt(const struct broad *b, const struct broad_want *want, int v, int t)
{
	double pv[6], mv[6];
	int a;

	for (a = 0; a < 3; a++) {
		pv[a] = pv[3 + a] = b->vnear[6 * v + a];
		mv[a] = mv[3 + a] = b->vnear[6 * v + 3 + a];
	}
	return near_overlap(pv, mv, b->tnear + 12 * t, b->tnear + 12 * t + 6, want->near,
	    want->near_motion);
}

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

static int
find_seed(struct broad *b, const struct geom *g, double cell, const struct broad_want *want,
    bool *too_small)
{
	struct spatial_hash *h = &b->hash;
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
		if ((v & 1023) == 0 && stop_asked(b))
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
		if ((i & 255) == 0 && stop_asked(b))
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

/* Each vertex's box of the step, widened by skin on every side. */
static void
fill_allowed(struct broad *b, const struct geom *g, double skin)
{
	int v, k;

	for (v = 0; v < g->nv; v++) {
		double *a = b->allowed + 6 * v;

		if (g->vbox != NULL) {	/* a box already (lo <= hi) */
			memcpy(a, g->vbox + 6 * v, 6 * sizeof *a);
		} else {
			box_empty(a);
			vertex_box(a, g, v);
		}
		for (k = 0; skin != 0 && k < 3; k++) {
			a[k] -= skin;
			a[3 + k] += skin;
		}
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
 * b->big and marked in b->is_big. */
static int
fill_boxes(struct broad *b, struct spatial_hash *h, size_t first, size_t count, double cell,
    const double *region, size_t limit)
{
	const double *box = b->box;
	size_t i, total = 0;
	int lo[3], hi[3], x, y, z;

	for (i = first; i < first + count; i++) {
		size_t n = span(&b->hash, box + 6 * i);	/* the same cubes as h's */

		b->is_big[i] = n > limit;
		if (n <= limit)
			total += n;
		else if (grow((void **)&b->big, &b->bigcap, b->nbig + 1, sizeof *b->big) != 0)
			return -1;
		else
			b->big[b->nbig++] = (int)i;
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
		if (b->is_big[i])
			continue;
		if ((i & 255) == 0 && stop_asked(b))
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
	if (b->stamp[t] == v)
		return 0;
	b->stamp[t] = v;
	if (!tri_has(g, t, v) && !vt_static(g, v, t) && box_overlap(qb, b->box + 6 * t))
		return push_vt(b, v, t);
	return 0;
}

/* Edge i's pair with edge o > i, if their boxes overlap. */
static int
try_ee(struct broad *b, const struct geom *g, size_t i, size_t o, const double *eb)
{
	size_t it = g->ntri + o;

	if (o <= i || b->stamp[it] == (int)i)
		return 0;
	b->stamp[it] = (int)i;
	if (!ee_skip(g, (int)i, (int)o) && box_overlap(eb, b->box + 6 * it))
		return push_ee(b, (int)i, (int)o);
	return 0;
}

/* The triangles near vertex v (query box qb): through the hash, or all of
 * them when qb spans more than limit cubes; and the big ones. */
static int
query_triangles(struct broad *b, const struct geom *g, int v, const double *qb, size_t limit)
{
	const struct spatial_hash *h = &b->hash;
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
	for (k = 0; k < b->nbig_tri; k++)
		if (try_vt(b, g, v, b->big[k], qb) != 0)
			return -1;
	return 0;
}

/* The edges after edge i near it: the same way. */
static int
query_edges(struct broad *b, const struct geom *g, size_t i, size_t limit)
{
	const struct spatial_hash *he = &b->hash_edges;
	const double *eb = b->box + 6 * (g->ntri + i);
	int lo[3], hi[3], x, y, z, e;
	size_t k;

	if (b->is_big[g->ntri + i]) {
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
	for (k = b->nbig_tri; k < b->nbig; k++)
		if (try_ee(b, g, i, (size_t)b->big[k] - g->ntri, eb) != 0)
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
static int
find_grid(struct broad *b, const struct geom *g, double cell, const struct broad_want *want)
{
	struct spatial_hash *h = &b->hash;
	size_t nbox = g->ntri + (want->edges ? g->nedges : 0), i, tri_limit, edge_limit = 0;
	double region[6], qb[6], skin = GRID_SKIN * cell;
	int v, k;

	if (grow((void **)&b->box, &b->boxcap, 6 * nbox, sizeof *b->box) != 0 ||
	    grow((void **)&b->stamp, &b->stampcap, nbox, sizeof *b->stamp) != 0 ||
	    grow((void **)&b->is_big, &b->is_bigcap, nbox, sizeof *b->is_big) != 0 ||
	    grow((void **)&b->allowed, &b->allowedcap, 6 * (size_t)g->nv, sizeof *b->allowed) != 0)
		return -1;
	fill_allowed(b, g, skin);
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
			return -1;
	}
	b->st.cell = cell;
	/* triangles and edges in hashes of their own, on the same cubes: a
	 * node looks for triangles only, an edge for edges only */
	b->nbig = 0;
	tri_limit = span_limit(h, b->box, 0, g->ntri);
	if (fill_boxes(b, h, 0, g->ntri, cell, region, tri_limit) != 0)
		return -1;
	b->nbig_tri = b->nbig;
	if (want->edges) {
		edge_limit = span_limit(h, b->box, g->ntri, g->nedges);	/* h: the same cubes */
		if (fill_boxes(b, &b->hash_edges, g->ntri, g->nedges, cell, region, edge_limit) != 0)
			return -1;
	}
	b->st.big = (long)b->nbig;

	/* each node's swept box, widened if asked to the segments from its
	 * neighbours at step k to the node */
	for (v = 0; v < g->nv; v++) {
		if (v >= g->ncloth && !want->mesh_vertices)
			break;
		if ((v & 255) == 0 && stop_asked(b))
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
		if ((i & 255) == 0 && stop_asked(b))
			return -1;
		if (query_edges(b, g, i, edge_limit) != 0)
			return -1;
	}
	hash_stats(h, &b->st.hash);
	return 0;
}

/* ---- bvh ----
 *
 * The grid's pairs, found with a tree of boxes over the triangles instead
 * of a hash: a box a vertex (its swept box, widened by the skin as the
 * grid's), a triangle the box of its vertices', a node of the tree the
 * box of its children. The tree is built once by halving the triangles
 * along their longest extent (a cloth's topology is fixed, so the tree
 * stays coherent: neighbours in it are neighbours on the cloth) and
 * refitted each fill in O(n); the cloth's tree is traversed against itself
 * and against the meshes' (static) tree. Each vertex and each edge is
 * looked up through one of its triangles only, its representative, so
 * every pair comes once from the one pair of leaves that holds it; a
 * vertex's box lies in its representative's, so no pair the grid finds is
 * missed, and checking the vertex's (edge's) own box against the other
 * triangle's (edge's) gives exactly the grid's set, sorted the same: the
 * results are the grid's, only the cost differs (no cubes, no edge hash,
 * no duplicates). */

/* Builds the subtree of triangles tri[lo, hi) at node index *next on,
 * depth first; returns its root. */
static int
bvh_build(struct broad *b, const struct geom *g, int *tri, double *key, int lo, int hi,
    int *next)
{
	int at = (*next)++, k, mid, axis = 0;
	double bx[6];

	b->node[at].left = b->node[at].right = -1;
	b->node[at].tri = tri[lo];
	b->node[at].patch = false;
	if (hi - lo == 1)
		return at;
	box_empty(bx);
	for (k = lo; k < hi; k++) {
		const int *n = g->tri + 3 * tri[k];
		double c[3] = { 0, 0, 0 };
		int j, d;

		for (j = 0; j < 3; j++)
			for (d = 0; d < 3; d++)
				c[d] += g->x0[3 * n[j] + d] / 3;
		box_add(bx, c);
	}
	for (k = 1; k < 3; k++)
		if (bx[3 + k] - bx[k] > bx[3 + axis] - bx[axis])
			axis = k;
	/* a stable split at the median by centroid along axis: keys, then an
	 * insertion-free partition by sorting (ties by triangle number) */
	for (k = lo; k < hi; k++) {
		const int *n = g->tri + 3 * tri[k];

		key[k] = g->x0[3 * n[0] + axis] + g->x0[3 * n[1] + axis] + g->x0[3 * n[2] + axis];
	}
	mid = lo + (hi - lo) / 2;
	{
		/* selection by repeated partition (quickselect with the middle
		 * element as pivot), deterministic */
		int l = lo, r = hi - 1;

		while (l < r) {
			double pk = key[(l + r) / 2];
			int pt = tri[(l + r) / 2], i = l, j = r;

			while (i <= j) {
				while (key[i] < pk || (key[i] == pk && tri[i] < pt))
					i++;
				while (key[j] > pk || (key[j] == pk && tri[j] > pt))
					j--;
				if (i <= j) {
					double tk = key[i];
					int tt = tri[i];

					key[i] = key[j];
					tri[i] = tri[j];
					key[j] = tk;
					tri[j] = tt;
					i++;
					j--;
				}
			}
			if (mid <= j)
				r = j;
			else if (mid >= i)
				l = i;
			else
				break;
		}
	}
	b->node[at].left = bvh_build(b, g, tri, key, lo, mid, next);
	b->node[at].right = bvh_build(b, g, tri, key, mid, hi, next);
	return at;
}

/* The triangles of the squares [i0, i1) x [j0, j1) of the cloth's grid
 * (sq: per square its two triangles, -1 where missing). */
static int
grid_count(const int *sq, int su, int i0, int i1, int j0, int j1)
{
	int i, j, n = 0;

	for (j = j0; j < j1; j++)
		for (i = i0; i < i1; i++)
			n += (sq[2 * (j * su + i)] >= 0) + (sq[2 * (j * su + i) + 1] >= 0);
	return n;
}

static int
grid_leaf(struct broad *b, int t, int *next)
{
	int at = (*next)++;

	b->node[at].left = b->node[at].right = -1;
	b->node[at].tri = t;
	b->node[at].patch = false;
	return at;
}

/* The cloth's tree over its grid rather than over space: each node a
 * rectangle of squares, halved across its longer side, so that a node's
 * triangles are a rectangle of the cloth (a patch, if no square of it is
 * missing) whose flatness can be judged (below). On the cloth at rest it
 * is the spatial tree's shape; the pairs are the same either way. Returns
 * the subtree's root, or -1 if the rectangle holds no triangle. */
static int
bvh_build_grid(struct broad *b, const int *sq, int su, int i0, int i1, int j0, int j1,
    int *next)
{
	int n = grid_count(sq, su, i0, i1, j0, j1), at, m;

	if (n == 0)
		return -1;
	if (n == 1) {
		int i, j;

		for (j = j0; j < j1; j++)
			for (i = i0; i < i1; i++)
				for (m = 0; m < 2; m++)
					if (sq[2 * (j * su + i) + m] >= 0)
						return grid_leaf(b, sq[2 * (j * su + i) + m], next);
	}
	if (i1 - i0 == 1 && j1 - j0 == 1) {	/* one square, two triangles */
		at = (*next)++;
		b->node[at].left = grid_leaf(b, sq[2 * (j0 * su + i0)], next);
		b->node[at].right = grid_leaf(b, sq[2 * (j0 * su + i0) + 1], next);
	} else {
		int l0 = i0, l1 = i1, k0 = j0, k1 = j1, r0 = i0, r1 = i1, h0 = j0, h1 = j1;

		if (i1 - i0 >= j1 - j0)
			l1 = r0 = i0 + (i1 - i0) / 2;
		else
			k1 = h0 = j0 + (j1 - j0) / 2;
		if (grid_count(sq, su, l0, l1, k0, k1) == 0)
			return bvh_build_grid(b, sq, su, r0, r1, h0, h1, next);
		if (grid_count(sq, su, r0, r1, h0, h1) == 0)
			return bvh_build_grid(b, sq, su, l0, l1, k0, k1, next);
		at = (*next)++;
		b->node[at].left = bvh_build_grid(b, sq, su, l0, l1, k0, k1, next);
		b->node[at].right = bvh_build_grid(b, sq, su, r0, r1, h0, h1, next);
	}
	b->node[at].tri = -1;
	b->node[at].patch = n == 2 * (i1 - i0) * (j1 - j0);
	return at;
}

/* Each node's span of leaf_tri, for the tree of nodes [root, end):
 * children follow their parent, the left subtree before the right, so
 * one pass back gives the counts and one forward the firsts. */
static void
bvh_spans(struct broad *b, int root, int end, int first)
{
	int i;

	if (root < 0)
		return;
	for (i = end - 1; i >= root; i--) {
		struct bvh_node *n = &b->node[i];

		n->count = n->left < 0 ? 1 : b->node[n->left].count + b->node[n->right].count;
	}
	b->node[root].first = first;
	for (i = root; i < end; i++) {
		struct bvh_node *n = &b->node[i];

		if (n->left < 0) {
			b->leaf_tri[n->first] = n->tri;
			continue;
		}
		b->node[n->left].first = n->first;
		b->node[n->right].first = n->first + b->node[n->left].count;
	}
}

/* Per cloth triangle the inverse of its rest map [uv1 - uv0, uv2 - uv0]
 * (so that the deformation F = [x1 - x0, x2 - x0] times it), or NULL
 * for a cloth without a grid. */
static int
bvh_rest_maps(struct broad *b, const struct geom *g, size_t ncloth_tri)
{
	size_t t;

	if (g->tri_square == NULL || g->uv == NULL || ncloth_tri == 0)
		return 0;
	if ((b->dminv = malloc(4 * ncloth_tri * sizeof *b->dminv)) == NULL ||
	    (b->tri_cull = malloc(g->ntri * sizeof *b->tri_cull)) == NULL ||
	    (b->held_mark = calloc(2 * g->ntri, 1)) == NULL ||
	    (b->witness = calloc(2 * g->ntri, sizeof *b->witness)) == NULL)
		return -1;
	for (t = 0; t < ncloth_tri; t++) {
		const int *n = g->tri + 3 * t;
		double a = g->uv[2 * n[1]] - g->uv[2 * n[0]], c = g->uv[2 * n[2]] - g->uv[2 * n[0]];
		double bb = g->uv[2 * n[1] + 1] - g->uv[2 * n[0] + 1];
		double d = g->uv[2 * n[2] + 1] - g->uv[2 * n[0] + 1], det = a * d - c * bb;
		double *m = b->dminv + 4 * t;

		if (!(fabs(det) > 0))
			return -1;
		m[0] = d / det;
		m[1] = -c / det;
		m[2] = -bb / det;
		m[3] = a / det;
	}
	return 0;
}

/* Frees the trees and what was built with them. */
static void
bvh_drop(struct broad *b)
{
	free(b->node);
	free(b->rep_vertex);
	free(b->rep_edge);
	free(b->rep_start);
	free(b->rep_list);
	free(b->rep_nv);
	free(b->leaf_tri);
	free(b->dminv);
	free(b->tri_cull);
	free(b->held_mark);
	free(b->witness);
	b->node = NULL;
	b->rep_vertex = b->rep_edge = b->rep_start = b->rep_list = NULL;
	b->rep_nv = NULL;
	b->leaf_tri = b->tri_cull = b->witness = NULL;
	b->dminv = NULL;
	b->held_mark = NULL;
}

/* The trees and the representatives, for geometry g; once. */
static int
bvh_prepare(struct broad *b, const struct geom *g)
{
	size_t t, ncloth_tri = 0;
	int *tri = NULL, v, next = 0, e;
	double *key = NULL;

	if (b->node != NULL && b->bvh_nv == g->nv && b->bvh_ntri == g->ntri)
		return 0;
	b->held_valid = false;	/* their queries need the tree they were found in */
	b->ncull = b->held_ncull = 0;
	bvh_drop(b);
	if (g->ntri == 0 || g->ntri > (size_t)INT_MAX / 2)
		return g->ntri == 0 ? 0 : -1;
	b->node = malloc((2 * g->ntri) * sizeof *b->node);
	b->rep_vertex = malloc(((size_t)g->nv + 1) * sizeof *b->rep_vertex);
	b->rep_edge = malloc((g->nedges + 1) * sizeof *b->rep_edge);
	b->rep_start = calloc(g->ntri + 1, sizeof *b->rep_start);
	b->rep_list = malloc(((size_t)g->nv + g->nedges + 1) * sizeof *b->rep_list);
	b->rep_nv = calloc(g->ntri, sizeof *b->rep_nv);
	tri = malloc((g->ntri + 2 * (size_t)g->squares_u * g->squares_v) * sizeof *tri);
	key = malloc(g->ntri * sizeof *key);
	b->leaf_tri = malloc(g->ntri * sizeof *b->leaf_tri);
	if (b->node == NULL || b->rep_vertex == NULL || b->rep_edge == NULL || b->leaf_tri == NULL ||
	    b->rep_start == NULL || b->rep_list == NULL ||
	    b->rep_nv == NULL || tri == NULL || key == NULL)
		goto fail;
	for (t = 0; t < g->ntri; t++) {
		tri[t] = (int)t;
		ncloth_tri += g->tri[3 * t] < g->ncloth;	/* cloth triangles come first */
	}
	b->cloth_root = b->mesh_root = -1;
	if (ncloth_tri > 0 && g->tri_square != NULL && g->uv != NULL) {
		/* per square its two triangles, after the triangles' list */
		int *sq = tri + g->ntri, su = g->squares_u;

		for (t = 0; t < 2 * (size_t)su * g->squares_v; t++)
			sq[t] = -1;
		for (t = 0; t < ncloth_tri; t++) {
			int *slot = sq + 2 * g->tri_square[t];

			slot[slot[0] >= 0] = (int)t;
		}
		b->cloth_root = bvh_build_grid(b, sq, su, 0, su, 0, g->squares_v, &next);
		if (bvh_rest_maps(b, g, ncloth_tri) != 0)
			goto fail;
	} else if (ncloth_tri > 0) {
		b->cloth_root = bvh_build(b, g, tri, key, 0, (int)ncloth_tri, &next);
	}
	if (ncloth_tri < g->ntri)
		b->mesh_root = bvh_build(b, g, tri, key, (int)ncloth_tri, (int)g->ntri, &next);
	b->nnodes = next;
	bvh_spans(b, b->cloth_root, b->mesh_root >= 0 ? b->mesh_root : next, 0);
	bvh_spans(b, b->mesh_root, next, (int)ncloth_tri);
	for (v = 0; v < g->nv; v++)
		b->rep_vertex[v] = g->vtri_start[v] < g->vtri_start[v + 1] ?
		    g->vtri[g->vtri_start[v]] : -1;
	for (e = 0; e < (int)g->nedges; e++) {
		int a = g->edge[2 * e], c = g->edge[2 * e + 1], k;

		b->rep_edge[e] = -1;
		for (k = g->vtri_start[a]; k < g->vtri_start[a + 1] && b->rep_edge[e] < 0; k++)
			if (tri_has(g, g->vtri[k], c))
				b->rep_edge[e] = g->vtri[k];
	}
	/* the lists each leaf stands for: counts, starts, then the entries
	 * (vertices first, in order, then edges) */
	for (v = 0; v < g->nv; v++)
		if (b->rep_vertex[v] >= 0)
			b->rep_start[b->rep_vertex[v] + 1]++, b->rep_nv[b->rep_vertex[v]]++;
	for (e = 0; e < (int)g->nedges; e++)
		if (b->rep_edge[e] >= 0)
			b->rep_start[b->rep_edge[e] + 1]++;
	for (t = 0; t < g->ntri; t++)
		b->rep_start[t + 1] += b->rep_start[t];
	memcpy(tri, b->rep_start, g->ntri * sizeof *tri);	/* the next free entry */
	for (v = 0; v < g->nv; v++)
		if (b->rep_vertex[v] >= 0)
			b->rep_list[tri[b->rep_vertex[v]]++] = v;
	for (e = 0; e < (int)g->nedges; e++)
		if (b->rep_edge[e] >= 0)
			b->rep_list[tri[b->rep_edge[e]]++] = e;
	b->bvh_nv = g->nv;
	b->bvh_ntri = g->ntri;
	free(tri);
	free(key);
	return 0;
fail:
	free(tri);
	free(key);
	bvh_drop(b);
	return -1;
}

static int
leaf(const struct bvh_node *n)
{
	return n->left < 0;
}

/* The pairs a pair of leaves (triangles ta and tb, their boxes ba and bb)
 * holds: the vertices each stands for against the other triangle, and the
 * edges each stands for against the other's. A cloth's leaves meet their
 * neighbours' at every step, so this runs some ten thousand times a
 * traversal: the lists of what each stands for (bvh_prepare) keep it to
 * the one vertex and one or two edges a triangle of a grid has. */
static int
bvh_leaves(struct broad *b, const struct geom *g, const struct broad_want *want, int ta,
    const double *ba, int tb, const double *bb)
{
	const int *la = b->rep_list + b->rep_start[ta], *lb = b->rep_list + b->rep_start[tb];
	int nva = b->rep_nv[ta], nvb = b->rep_nv[tb];
	int nea = b->rep_start[ta + 1] - b->rep_start[ta] - nva;
	int neb = b->rep_start[tb + 1] - b->rep_start[tb] - nvb;
	int k, l, pass;

	for (pass = 0; pass < 2; pass++) {
		const int *lv = pass ? lb : la;
		int o = pass ? ta : tb, nvv = pass ? nvb : nva;
		const double *ob = pass ? ba : bb;

		for (k = 0; k < nvv; k++) {
			int v = lv[k];

			if ((v >= g->ncloth && !want->mesh_vertices) || tri_has(g, o, v) ||
			    vt_static(g, v, o) || !box_overlap(b->qbox + 6 * v, ob) ||
			    (want->near > 0 && !near_vt(b, want, v, o)))
				continue;
			if (push_vt(b, v, o) != 0)
				return -1;
		}
	}
	if (!want->edges)
		return 0;
	for (k = 0; k < nea; k++) {
		int ea = la[nva + k];
		const double *eba = b->ebox + 6 * ea;

		for (l = 0; l < neb; l++) {
			int eb = lb[nvb + l];

			if (!box_overlap(eba, b->ebox + 6 * eb) || ee_skip(g, ea, eb) ||
			    (want->near > 0 && !near_overlap(b->enear + 12 * ea, b->enear + 12 * ea + 6,
			    b->enear + 12 * eb, b->enear + 12 * eb + 6, want->near, want->near_motion)))
				continue;
			if (push_ee(b, ea, eb) != 0)
				return -1;
		}
	}
	return 0;
}

/*
 * ---- flat patches ----
 *
 * A cloth's neighbours in its plane overlap at every level of the tree,
 * whatever the motion, so a traversal of a flat cloth against itself
 * finds thousands of pairs the narrow phase then rules out one by one
 * (a falling tablecloth: some 3,900 a step, 85 % of its instructions).
 * A patch that stays flat cannot touch itself, and that can be proven
 * for the patch at once. Let f map the patch's rectangle on the cloth at
 * rest (convex) to space, linear on each triangle with deformation F
 * (3 x 2), and Q (2 x 3) project onto a plane. If the symmetric part of
 * Q F has its eigenvalues at least sigma > 0 on every triangle, then for
 * any two points p != q of the rectangle, integrating along the segment
 * between them (inside the rectangle, since it is convex),
 *   (Q f(q) - Q f(p)) . (q - p) >= sigma |q - p|^2,
 * so |f(q) - f(p)| >= sigma |q - p|: the patch is one sheet over the plane,
 * no two of its points meet, and two primitives that share no vertex
 * (uv_gap apart at rest) are at least sigma uv_gap apart. (This is the
 * contour condition of Volino & Magnenat-Thalmann 1994 made to hold by
 * construction: a rectangle's image under such a map cannot fold over.)
 * Over a step each vertex moves linearly, so F is linear in time, and the
 * matrices whose symmetric part is at least sigma form a convex set:
 * checking both ends of the step proves it throughout.
 *
 * What the searches need of a patch they leave out:
 *   - the check (exact ccd, no margin): sigma > 0 at both ends, so no
 *     pair of the patch can meet in the step;
 *   - a step's contacts (near > 0): no pair of the patch may be kept
 *     (contacts.h: separation at the start less near_motion times the
 *     relative motion of its vertices under near). The separation is at
 *     least sigma_0 d for primitives d apart at rest (d >= uv_gap), and
 *     the relative motion at most L (d + 2 uv_diam), L the largest norm of
 *     the motion's gradient x1 - x0 on the patch's triangles; so the patch
 *     is out of reach if sigma_0 > near_motion L and
 *     (sigma_0 - near_motion L) uv_gap >= near + near_motion L 2 uv_diam
 *     (the first follows from the second: the worst d is uv_gap).
 * The projection is the patch's mean directions along u and along v,
 * made orthonormal; any fixed one is sound. A patch left out by one
 * search is judged again by every later one that takes the held pairs,
 * and by broad_recheck when the check moves its vertices.
 */

/* Cloth triangle t's deformation at x0 (k = 0) or x1 (k = 1), into tdef. */
static void
tri_deform(struct broad *b, const struct geom *g, int t, int k)
{
	const double *x = k ? g->x1 : g->x0, *m = b->dminv + 4 * t;
	const int *v = g->tri + 3 * t;
	double *f = b->tdef + 12 * t + 6 * k;
	int d;

	for (d = 0; d < 3; d++) {
		double e1 = x[3 * v[1] + d] - x[3 * v[0] + d];
		double e2 = x[3 * v[2] + d] - x[3 * v[0] + d];

		f[d] = e1 * m[0] + e2 * m[2];
		f[3 + d] = e1 * m[1] + e2 * m[3];
	}
}

/* Each node's F at x0 and x1 summed over its triangles, for the nodes
 * [x, end) of the cloth's tree, children first. */
static void
node_sums(struct broad *b, int x, int end)
{
	int i, k;

	for (i = end - 1; i >= x; i--) {
		const struct bvh_node *n = &b->node[i];
		double *s = b->nsum + 6 * i;

		if (leaf(n)) {
			const double *f = b->tdef + 12 * n->tri;

			for (k = 0; k < 6; k++)
				s[k] = f[k] + f[6 + k];
		} else {
			for (k = 0; k < 6; k++)
				s[k] = b->nsum[6 * n->left + k] + b->nsum[6 * n->right + k];
		}
	}
}

/* Each cloth triangle's deformations, and the least eigenvalue taken as
 * positive: far above the roundings of F's entries (a few units in the
 * last place of the coordinates, over the spacing). */
static int
cull_prepare(struct broad *b, const struct geom *g, const struct broad_want *want)
{
	int t, n, k;
	double big = 0;

	b->cull_on = false;
	b->ncull = 0;
	if (b->dminv == NULL || b->cloth_root < 0 || !want->self || !(g->uv_gap > 0))
		return 0;
	n = b->node[b->cloth_root].count;
	if (grow((void **)&b->tdef, &b->tdefcap, 12 * (size_t)n, sizeof *b->tdef) != 0 ||
	    grow((void **)&b->nsum, &b->nsumcap, 6 * (size_t)(2 * n), sizeof *b->nsum) != 0)
		return -1;
	for (t = 0; t < n; t++) {
		tri_deform(b, g, t, 0);
		tri_deform(b, g, t, 1);
	}
	node_sums(b, b->cloth_root, b->cloth_root + 2 * n - 1);
	for (k = 0; k < 3 * g->ncloth; k++)
		big = fmax(big, fmax(fabs(g->x0[k]), fabs(g->x1[k])));
	b->cull_on = true;
	b->cull_want = *want;
	b->cull_tol = 1e-6 + 1e-12 * big / g->uv_gap;
	return 0;
}

/* The least eigenvalue of the symmetric part of Q F, Q's rows q1, q2. */
static double
least_eigen(const double *q1, const double *q2, const double *f)
{
	double a = q1[0] * f[0] + q1[1] * f[1] + q1[2] * f[2];
	double c = q2[0] * f[3] + q2[1] * f[4] + q2[2] * f[5];
	double s = (q1[0] * f[3] + q1[1] * f[4] + q1[2] * f[5] +
	    q2[0] * f[0] + q2[1] * f[1] + q2[2] * f[2]) / 2;

	return (a + c) / 2 - sqrt((a - c) * (a - c) / 4 + s * s);
}

/* Whether patch p is flat enough for the search cull_want (see above).
 * For a step's contacts the condition reads, with c = near_motion,
 *   (sigma_0 - tol) uv_gap - near >= c L (uv_gap + 2 uv_diam),
 * sigma_0 the least eigenvalue and L the largest gradient of the motion
 * over the patch; so each triangle alone must pass it, and a patch that
 * failed usually fails again at the same triangle (a fold lasts, a flap
 * goes on flapping), which is tried first: a failing patch then costs one
 * triangle, not a scan up to it. The order changes nothing but the cost. */
static int
patch_flat(struct broad *b, const struct geom *g, const struct bvh_node *p)
{
	const struct broad_want *want = &b->cull_want;
	int x = (int)(p - b->node), i, k, ends = want->near > 0 ? 1 : 2, w = b->witness[x];
	const double *s = b->nsum + 6 * x;
	double q1[3], q2[3], len, d, sigma = INFINITY, lip2 = 0;
	double span = want->near_motion * (g->uv_gap + 2 * g->uv_diam);

	len = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
	if (!(len > 0))
		return 0;
	for (k = 0; k < 3; k++)
		q1[k] = s[k] / len;
	d = s[3] * q1[0] + s[4] * q1[1] + s[5] * q1[2];
	for (k = 0; k < 3; k++)
		q2[k] = s[3 + k] - d * q1[k];
	len = sqrt(q2[0] * q2[0] + q2[1] * q2[1] + q2[2] * q2[2]);
	if (!(len > 0))
		return 0;
	for (k = 0; k < 3; k++)
		q2[k] /= len;
	for (i = p->first - 1; i < p->first + p->count; i++) {
		int at = i < p->first ? w : i;
		const double *f;
		double st = INFINITY, gg = 0, room;

		if (at < p->first || at >= p->first + p->count)
			continue;	/* no witness in this patch */
		f = b->tdef + 12 * b->leaf_tri[at];
		for (k = 0; k < ends; k++)
			st = fmin(st, least_eigen(q1, q2, f + 6 * k));
		st -= b->cull_tol;
		if (ends == 1) {
			for (k = 0; k < 6; k++)
				gg += (f[6 + k] - f[k]) * (f[6 + k] - f[k]);
			/* this triangle's sigma and L alone */
			room = (st * g->uv_gap - want->near) / ((1 + 1e-9) * span);
			if (!(room > 0 && gg <= room * room)) {
				b->witness[x] = at;
				return 0;
			}
		} else if (!(st > 0)) {
			b->witness[x] = at;
			return 0;
		}
		sigma = fmin(sigma, st);
		lip2 = fmax(lip2, gg);
	}
	if (ends == 2)
		return 1;
	return (sigma * g->uv_gap - want->near) >=
	    (1 + 1e-9) * span * sqrt(lip2) + 1e-300;
}

static int
push_cull(struct broad *b, int x)
{
	if (b->ncull == b->cullcap &&
	    grow((void **)&b->cull, &b->cullcap, b->ncull + 1, sizeof *b->cull) != 0)
		return -1;
	b->cull[b->ncull++] = x;
	return 0;
}

/* Every pair of leaves, one under x and one under y (x == y: a subtree
 * against itself, each pair of distinct leaves once), whose boxes overlap.
 * The stack of node pairs grows before each pop's at most three pushes. */
static int
bvh_traverse(struct broad *b, const struct geom *g, const struct broad_want *want, int x, int y)
{
	size_t top = 0;
	long visits = 0;
	int *st;

	if (grow((void **)&b->stack, &b->stackcap, 8, sizeof *b->stack) != 0)
		return -1;
	st = b->stack;
	st[top++] = x;
	st[top++] = y;
	while (top > 0) {
		const struct bvh_node *p, *q;

		if (top + 6 > b->stackcap) {
			if (grow((void **)&b->stack, &b->stackcap, top + 6, sizeof *b->stack) != 0)
				return -1;
			st = b->stack;
		}
		y = st[--top];
		x = st[--top];
		p = &b->node[x];
		q = &b->node[y];
		if ((++visits & 4095) == 0 && stop_asked(b))
			return -1;
		/* A subtree against itself: every pair of its leaves, unless it
		 * is a flat patch (above). A normal cone alone does not prune
		 * it: a patch whose normals stay within a cone cannot touch
		 * itself only if its contour does not overlap itself (Volino &
		 * Magnenat-Thalmann 1994), and the layers of a pile face the
		 * same way a thickness apart (a cone cull missed them: the
		 * peers' table tore at 0.48 s after 4 pairs crossed at 0.21 s).
		 * The flat test proves the contour's part by construction, on
		 * both ends of the step, and the check's corrections are judged
		 * again (broad_recheck). */
		if (x == y) {
			if (leaf(p))
				continue;	/* one triangle: nothing */
			if (b->cull_on && p->patch && patch_flat(b, g, p)) {
				if (push_cull(b, x) != 0)
					return -1;
				continue;
			}
			st[top++] = p->left;
			st[top++] = p->left;
			st[top++] = p->right;
			st[top++] = p->right;
			st[top++] = p->left;
			st[top++] = p->right;
			continue;
		}
		if (!box_overlap(p->box, q->box))
			continue;
		if (leaf(p) && leaf(q)) {
			if (bvh_leaves(b, g, want, p->tri, b->leaf_tbox ? b->tbox + 6 * p->tri : p->box,
			    q->tri, b->leaf_tbox ? b->tbox + 6 * q->tri : q->box) != 0)
				return -1;
		} else if (leaf(q) || (!leaf(p) && p->size >= q->size)) {
			st[top++] = p->left;
			st[top++] = y;
			st[top++] = p->right;
			st[top++] = y;
		} else {
			st[top++] = x;
			st[top++] = q->left;
			st[top++] = x;
			st[top++] = q->right;
		}
	}
	return 0;
}

/* Pairs sorted by vertex (edge a), then by triangle (edge b): two counting
 * sorts, by the second element and then, stably, by the first (a radix
 * sort on the two keys). A run of one vertex's pairs is dozens long at a
 * fast step, where insertion sort is quadratic and qsort allocates; this
 * is linear in the pairs and the keys. */
static int
bvh_sort(struct broad *b, const struct geom *g)
{
	size_t n = b->nvt > b->nee ? b->nvt : b->nee, i;
	size_t keys = (size_t)g->nv > g->nedges ? (size_t)g->nv : g->nedges;
	size_t *count = malloc(((keys > g->ntri ? keys : g->ntri) + 1) * sizeof *count);
	void *tmp = malloc((n ? n : 1) * sizeof(struct vt_pair));
	struct vt_pair *tv = tmp;
	struct ee_pair *te = tmp;

	_Static_assert(sizeof(struct vt_pair) == sizeof(struct ee_pair), "one scratch for both");
	if (count == NULL || tmp == NULL) {
		free(count);
		free(tmp);
		return -1;
	}
#define COUNTING_PASS(src, dst, n, field, nkeys) do {				\
		memset(count, 0, ((nkeys) + 1) * sizeof *count);		\
		for (i = 0; i < (n); i++)					\
			count[(size_t)(src)[i].field + 1]++;			\
		for (i = 1; i <= (nkeys); i++)					\
			count[i] += count[i - 1];				\
		for (i = 0; i < (n); i++)					\
			(dst)[count[(src)[i].field]++] = (src)[i];		\
	} while (0)
	COUNTING_PASS(b->vt, tv, b->nvt, t, g->ntri);
	COUNTING_PASS(tv, b->vt, b->nvt, v, (size_t)g->nv);
	COUNTING_PASS(b->ee, te, b->nee, b, g->nedges);
	COUNTING_PASS(te, b->ee, b->nee, a, g->nedges);
#undef COUNTING_PASS
	free(count);
	free(tmp);
	return 0;
}

/* Triangle t's box: its vertices' query boxes'. */
static void
tri_box(double *bx, const struct broad *b, const struct geom *g, int t)
{
	int k;

	box_empty(bx);
	for (k = 0; k < 3; k++) {
		box_add(bx, b->qbox + 6 * g->tri[3 * t + k]);
		box_add(bx, b->qbox + 6 * g->tri[3 * t + k] + 3);
	}
}

/* Refits the trees to the vertices' boxes (qbox), children after parents:
 * from the last node back. */
static void
bvh_refit(struct broad *b, const struct geom *g)
{
	int i;

	for (i = b->nnodes - 1; i >= 0; i--) {
		struct bvh_node *n = &b->node[i];

		if (leaf(n)) {
			tri_box(n->box, b, g, n->tri);
		} else {
			box_empty(n->box);
			box_add(n->box, b->node[n->left].box);
			box_add(n->box, b->node[n->left].box + 3);
			box_add(n->box, b->node[n->right].box);
			box_add(n->box, b->node[n->right].box + 3);
		}
		n->size = n->box[3] - n->box[0] + n->box[4] - n->box[1] + n->box[5] - n->box[2];
	}
}

/*
 * ---- held pairs ----
 *
 * A traversal of a cloth against itself costs the same whatever the
 * motion: its neighbours in the plane overlap at every level of the tree
 * (some 40,000 node pairs a traversal on the tablecloth). Yet from one
 * search to the next most vertices' boxes barely move: the fast path
 * searches twice a step, at its start for the pairs its predicted motion
 * may bring within reach, and at its end for the check over the motion it
 * made, and the slow integrators' steps are short. So a traversal is made
 * with every vertex's box widened by a skin, and its pairs are held with
 * those boxes (a Verlet list); a later search takes from them the pairs of
 * vertices whose boxes still lie inside their held ones ("clean"), by its
 * own box test, and looks up only what touches the others ("dirty"): one
 * query of the tree a dirty vertex, triangle and edge, whose boxes are
 * still the held ones (they hold every clean vertex's box), and the pairs
 * among dirty ones by testing each against each. When more than one
 * vertex in HELD_DIRTY_SHARE is dirty, a traversal again. The flat
 * patches are judged again for the search, top down as a traversal
 * judges them: the held pairs inside those left out are dropped, and a
 * patch the held traversal left out that is no longer flat is traversed.
 * The pairs are exactly a traversal's of the search's own boxes (the same
 * test on every pair, and sorted): only the cost differs.
 */

/* The skin, as a fraction of the cube edge L_ce (the grid's is 0.1). It
 * pays where the searches' boxes move little from one to the next (rk4's
 * short steps: a quarter fewer instructions on the tablecloth's first
 * 0.05 s), and costs where a traversal serves one search more at most
 * (the fast path's step: its check; +3 % with 0.05, +18 % with 0.3, for
 * the larger boxes). So a traversal takes the skin when the last one
 * without it served no later search, and keeps it while a skinned one
 * serves at least HELD_SKIN_USES. */
#define HELD_SKIN 0.05
#define HELD_SKIN_USES 2
/* Above one vertex in HELD_DIRTY_SHARE out of its held box, a traversal. */
#define HELD_DIRTY_SHARE 8

/* Whether the trees' traversals pair vertex v with triangle t at all (the
 * cloth with itself only if asked, never mesh with mesh). */
static int
vt_wanted(const struct geom *g, const struct broad_want *want, int v, int t)
{
	int vc = v < g->ncloth, tc = g->tri[3 * t] < g->ncloth;

	if (vc && tc)
		return want->self;
	return vc || (tc && want->mesh_vertices);
}

static int
ee_wanted(const struct geom *g, const struct broad_want *want, int e, int f)
{
	int ec = g->edge[2 * e] < g->ncloth, fc = g->edge[2 * f] < g->ncloth;

	return ec && fc ? want->self : ec || fc;
}

/* The leaves of both trees whose boxes overlap bx, into b->found: how
 * many, or -1 out of memory. */
static long
bvh_query(struct broad *b, const double *bx)
{
	size_t top = 0, n = 0;

	if (grow((void **)&b->stack, &b->stackcap, 8, sizeof *b->stack) != 0)
		return -1;
	if (b->cloth_root >= 0)
		b->stack[top++] = b->cloth_root;
	if (b->mesh_root >= 0)
		b->stack[top++] = b->mesh_root;
	while (top > 0) {
		const struct bvh_node *p = &b->node[b->stack[--top]];

		if (!box_overlap(p->box, bx))
			continue;
		if (leaf(p)) {
			if (n == b->foundcap &&
			    grow((void **)&b->found, &b->foundcap, n + 1, sizeof *b->found) != 0)
				return -1;
			b->found[n++] = p->tri;
			continue;
		}
		if (top + 2 > b->stackcap &&
		    grow((void **)&b->stack, &b->stackcap, top + 2, sizeof *b->stack) != 0)
			return -1;
		b->stack[top++] = p->left;
		b->stack[top++] = p->right;
	}
	return (long)n;
}

/* Each triangle's box of this search. */
static int
fill_tri_boxes(struct broad *b, const struct geom *g)
{
	size_t t;

	if (grow((void **)&b->tbox, &b->tboxcap, 6 * (g->ntri + 1), sizeof *b->tbox) != 0)
		return -1;
	for (t = 0; t < g->ntri; t++)
		tri_box(b->tbox + 6 * t, b, g, (int)t);
	return 0;
}

static int
tri_dirty(const struct broad *b, const struct geom *g, int t)
{
	const int *n = g->tri + 3 * t;

	return b->dirty[n[0]] | b->dirty[n[1]] | b->dirty[n[2]];
}

static int
edge_dirty(const struct broad *b, const struct geom *g, int e)
{
	return b->dirty[g->edge[2 * e]] | b->dirty[g->edge[2 * e + 1]];
}

/* Whether a traversal leaves out the pairs of triangles ta and tb (a
 * vertex's or an edge's, its representative): both in one flat patch. */
static int
culled(const struct broad *b, int ta, int tb)
{
	return b->ncull > 0 && ta >= 0 && tb >= 0 && b->tri_cull[ta] >= 0 &&
	    b->tri_cull[ta] == b->tri_cull[tb];
}

/* The held pairs of clean vertices, by this search's box test. */
static int
held_clean(struct broad *b, const struct geom *g)
{
	size_t i;

	for (i = 0; i < b->held_nvt; i++) {
		int v = b->held_vt[i].v, t = b->held_vt[i].t;

		if (b->dirty[v] || tri_dirty(b, g, t) ||
		    !box_overlap(b->qbox + 6 * v, b->tbox + 6 * t) || culled(b, b->rep_vertex[v], t))
			continue;
		if (push_vt(b, v, t) != 0)
			return -1;
	}
	for (i = 0; i < b->held_nee; i++) {
		int e = b->held_ee[i].a, f = b->held_ee[i].b;

		if (edge_dirty(b, g, e) || edge_dirty(b, g, f) ||
		    !box_overlap(b->ebox + 6 * e, b->ebox + 6 * f) ||
		    culled(b, b->rep_edge[e], b->rep_edge[f]))
			continue;
		if (push_ee(b, e, f) != 0)
			return -1;
	}
	return 0;
}

/* A dirty vertex (edge) against the clean triangles (edges) of the trees,
 * and a dirty triangle against the clean vertices. */
static int
held_query_vertex(struct broad *b, const struct geom *g, const struct broad_want *want, int v)
{
	long n = bvh_query(b, b->qbox + 6 * v), k;

	for (k = 0; k < n; k++) {
		int t = b->found[k];

		if (tri_dirty(b, g, t) || tri_has(g, t, v) || vt_static(g, v, t) ||
		    !vt_wanted(g, want, v, t) || !box_overlap(b->qbox + 6 * v, b->tbox + 6 * t) ||
		    culled(b, b->rep_vertex[v], t))
			continue;
		if (push_vt(b, v, t) != 0)
			return -1;
	}
	return n < 0 ? -1 : 0;
}

static int
held_query_triangle(struct broad *b, const struct geom *g, const struct broad_want *want, int t)
{
	const double *tb = b->tbox + 6 * t;
	long n = bvh_query(b, tb), k;
	int j;

	for (k = 0; k < n; k++) {
		const int *l = b->rep_list + b->rep_start[b->found[k]];

		for (j = 0; j < b->rep_nv[b->found[k]]; j++) {
			int u = l[j];

			if (b->dirty[u] || tri_has(g, t, u) || vt_static(g, u, t) ||
			    !vt_wanted(g, want, u, t) || !box_overlap(b->qbox + 6 * u, tb) ||
			    culled(b, b->rep_vertex[u], t))
				continue;
			if (push_vt(b, u, t) != 0)
				return -1;
		}
	}
	return n < 0 ? -1 : 0;
}

static int
held_query_edge(struct broad *b, const struct geom *g, const struct broad_want *want, int e)
{
	const double *eb = b->ebox + 6 * e;
	long n = bvh_query(b, eb), k;
	int j;

	for (k = 0; k < n; k++) {
		int o = b->found[k];

		for (j = b->rep_start[o] + b->rep_nv[o]; j < b->rep_start[o + 1]; j++) {
			int f = b->rep_list[j];

			if (edge_dirty(b, g, f) || ee_skip(g, e, f) || !ee_wanted(g, want, e, f) ||
			    !box_overlap(eb, b->ebox + 6 * f) || culled(b, b->rep_edge[e], b->rep_edge[f]))
				continue;
			if (push_ee(b, e, f) != 0)
				return -1;
		}
	}
	return n < 0 ? -1 : 0;
}

/* Every pair that touches a dirty vertex: against the clean side from the
 * tree, dirty against dirty by testing each pair of the lists of dirty
 * vertices, triangles and edges (b->dlist). */
static int
held_dirty(struct broad *b, const struct geom *g, const struct broad_want *want)
{
	size_t nv = 0, nt = 0, ne = 0, t, e, i, j;
	int *dv, *dt, *de;
	int v;

	if (grow((void **)&b->dlist, &b->dlistcap, (size_t)g->nv + g->ntri + g->nedges + 1,
	    sizeof *b->dlist) != 0)
		return -1;
	dv = b->dlist;
	for (v = 0; v < g->nv; v++)
		if (b->dirty[v] && (v < g->ncloth || want->mesh_vertices))
			dv[nv++] = v;
	dt = dv + nv;
	for (t = 0; t < g->ntri; t++)
		if (tri_dirty(b, g, (int)t))
			dt[nt++] = (int)t;
	de = dt + nt;
	for (e = 0; want->edges && e < g->nedges; e++)
		if (edge_dirty(b, g, (int)e))
			de[ne++] = (int)e;
	for (i = 0; i < nv; i++) {
		if (held_query_vertex(b, g, want, dv[i]) != 0)
			return -1;
		for (j = 0; j < nt; j++)
			if (!tri_has(g, dt[j], dv[i]) && !vt_static(g, dv[i], dt[j]) &&
			    vt_wanted(g, want, dv[i], dt[j]) &&
			    box_overlap(b->qbox + 6 * dv[i], b->tbox + 6 * (size_t)dt[j]) &&
			    !culled(b, b->rep_vertex[dv[i]], dt[j]) && push_vt(b, dv[i], dt[j]) != 0)
				return -1;
	}
	for (j = 0; j < nt; j++) {
		if ((j & 255) == 255 && stop_asked(b))
			return -1;
		if (held_query_triangle(b, g, want, dt[j]) != 0)
			return -1;
	}
	for (i = 0; i < ne; i++) {
		if ((i & 255) == 255 && stop_asked(b))
			return -1;
		if (held_query_edge(b, g, want, de[i]) != 0)
			return -1;
		for (j = i + 1; j < ne; j++)
			if (!ee_skip(g, de[i], de[j]) && ee_wanted(g, want, de[i], de[j]) &&
			    box_overlap(b->ebox + 6 * (size_t)de[i], b->ebox + 6 * (size_t)de[j]) &&
			    !culled(b, b->rep_edge[de[i]], b->rep_edge[de[j]]) &&
			    push_ee(b, de[i], de[j]) != 0)
				return -1;
	}
	return 0;
}

/* Whether the held pairs can serve a search for want. */
static int
held_serves(const struct broad *b, const struct geom *g, const struct broad_want *want)
{
	const struct broad_want *h = &b->held_want;

	return b->held_valid && b->held_nv == g->nv && !want->neighbour_paths &&
	    (b->held_ncull == 0 || b->cull_on) &&
	    !h->neighbour_paths && h->self == want->self && h->edges == want->edges &&
	    h->mesh_vertices == want->mesh_vertices;
}

/* Drops repeats from the sorted lists: a patch given back may hold pairs
 * a dirty vertex's query found already. */
static void
unique_pairs(struct broad *b)
{
	size_t i, k;

	for (i = k = 0; i < b->nvt; i++)
		if (k == 0 || b->vt[i].v != b->vt[k - 1].v || b->vt[i].t != b->vt[k - 1].t)
			b->vt[k++] = b->vt[i];
	b->nvt = k;
	for (i = k = 0; i < b->nee; i++)
		if (k == 0 || b->ee[i].a != b->ee[k - 1].a || b->ee[i].b != b->ee[k - 1].b)
			b->ee[k++] = b->ee[i];
	b->nee = k;
}

/* Patch x judged for this search: left out again if still flat (1), or
 * its pairs found, with the triangles' boxes from tbox (the tree's may be
 * older than this search's), 0; -1 out of memory or stopped. */
static int
judge_patch(struct broad *b, const struct geom *g, const struct broad_want *want, int x)
{
	bool saved = b->leaf_tbox;
	int rc;

	if (patch_flat(b, g, &b->node[x]))
		return push_cull(b, x) != 0 ? -1 : 1;
	b->leaf_tbox = true;
	rc = bvh_traverse(b, g, want, x, x);
	b->leaf_tbox = saved;
	return rc;
}

/* The patches a traversal would leave out now, judged top down from x as
 * it judges them; a patch the held traversal left out that is no longer
 * flat gives its pairs (they are not among the held ones). *given: some
 * did. 0, or -1 out of memory or stopped. */
static int
judge_held(struct broad *b, const struct geom *g, const struct broad_want *want, int x,
    int *given)
{
	const struct bvh_node *p = &b->node[x];
	int rc;

	if (leaf(p))
		return 0;
	if (b->held_mark[x]) {
		rc = judge_patch(b, g, want, x);
		*given |= rc == 0;
		return rc < 0 ? -1 : 0;
	}
	if (p->patch && patch_flat(b, g, p))
		return push_cull(b, x);
	return judge_held(b, g, want, p->left, given) != 0 ||
	    judge_held(b, g, want, p->right, given) != 0 ? -1 : 0;
}

/* The search's pairs, sorted, from the held ones, with b->dirty marking
 * the ndirty vertices out of their held boxes. The patches left out are
 * those a traversal would leave out: judged again for this search (unless
 * judge is false: the held traversal's were judged for this very search),
 * the held pairs inside them dropped. */
static int
take_held(struct broad *b, const struct geom *g, const struct broad_want *want, int ndirty,
    bool judge)
{
	size_t i;
	int given = 0;

	b->nvt = b->nee = 0;
	if (fill_tri_boxes(b, g) != 0)
		return -1;
	if (judge) {
		b->ncull = 0;
		if (b->cull_on && judge_held(b, g, want, b->cloth_root, &given) != 0)
			return -1;
	}
	if (b->ncull > 0) {
		for (i = 0; i < g->ntri; i++)
			b->tri_cull[i] = -1;
		for (i = 0; i < b->ncull; i++) {
			const struct bvh_node *p = &b->node[b->cull[i]];
			int j;

			for (j = p->first; j < p->first + p->count; j++)
				b->tri_cull[b->leaf_tri[j]] = b->cull[i];
		}
	}
	if (held_clean(b, g) != 0 || (ndirty > 0 && held_dirty(b, g, want) != 0))
		return -1;
	if (ndirty == 0 && !given)
		return 0;	/* the held order is kept */
	if (bvh_sort(b, g) != 0)
		return -1;
	if (given)
		unique_pairs(b);
	return 0;
}

/* A search's pairs from the held ones: 0, 1 when too many vertices left
 * their boxes, -1 out of memory or stopped. */
static int
find_held(struct broad *b, const struct geom *g, const struct broad_want *want)
{
	int v, ndirty = 0;

	if (grow((void **)&b->dirty, &b->dirtycap, (size_t)g->nv, 1) != 0)
		return -1;
	for (v = 0; v < g->nv; v++) {
		const double *a = b->allowed + 6 * v, *h = b->held_box + 6 * v;

		b->dirty[v] = a[0] < h[0] || a[1] < h[1] || a[2] < h[2] ||
		    a[3] > h[3] || a[4] > h[4] || a[5] > h[5];
		ndirty += b->dirty[v];
	}
	if (ndirty > g->nv / HELD_DIRTY_SHARE)
		return 1;
	b->held_uses++;
	return take_held(b, g, want, ndirty, true);
}

/* Each vertex's query box and each edge's box, from the vertices' boxes
 * of the step widened by skin (b->allowed). */
static void
fill_query_boxes(struct broad *b, const struct geom *g, const struct broad_want *want,
    double skin)
{
	size_t e;
	int v, k;

	fill_allowed(b, g, skin);
	/* a vertex's query box, widened if asked to the segments from its
	 * neighbours at step k (as the grid's) */
	if (!want->neighbour_paths)
		memcpy(b->qbox, b->allowed, 6 * (size_t)g->nv * sizeof *b->qbox);
	for (v = 0; want->neighbour_paths && v < g->nv; v++) {
		double *q = b->qbox + 6 * v;

		box_empty(q);
		allowed_box(q, b, v);
		for (k = g->vedge_start[v]; k < g->vedge_start[v + 1]; k++) {
			const int *en = g->edge + 2 * g->vedge[k];

			allowed_box(q, b, en[0] == v ? en[1] : en[0]);
		}
	}
	for (e = 0; e < g->nedges; e++) {
		double *eb = b->ebox + 6 * e;
		const double *p = b->allowed + 6 * (size_t)g->edge[2 * e];
		const double *q = b->allowed + 6 * (size_t)g->edge[2 * e + 1];

		for (k = 0; k < 3; k++) {
			eb[k] = p[k] < q[k] ? p[k] : q[k];
			eb[3 + k] = p[3 + k] > q[3 + k] ? p[3 + k] : q[3 + k];
		}
	}
}

/* A traversal with every box widened by skin (if it pays, see HELD_SKIN),
 * whose pairs (sorted) and boxes become the held ones, and the search's
 * pairs: 0, or -1 out of memory or stopped. The tree keeps these boxes
 * until the next traversal: the held pairs' queries rely on it. */
static int
hold_traversal(struct broad *b, const struct geom *g, const struct broad_want *want,
    double skin)
{
	struct broad_want all = *want;
	size_t e;

	all.near = 0;
	if (!b->held_valid)
		skin = 0;
	else if (b->held_skin > 0 ? b->held_uses < HELD_SKIN_USES : b->held_uses > 0)
		skin = 0;
	b->held_valid = false;
	b->held_skin = skin;
	b->held_uses = 0;
	fill_query_boxes(b, g, want, skin);
	bvh_refit(b, g);
	b->nvt = b->nee = 0;
	if (b->cloth_root >= 0 && want->self &&
	    bvh_traverse(b, g, &all, b->cloth_root, b->cloth_root) != 0)
		return -1;
	if (b->cloth_root >= 0 && b->mesh_root >= 0 &&
	    bvh_traverse(b, g, &all, b->cloth_root, b->mesh_root) != 0)
		return -1;
	if (bvh_sort(b, g) != 0 ||
	    grow_pairs(b, (void **)&b->held_vt, &b->held_vtcap, b->nvt + 1, sizeof *b->vt) != 0 ||
	    grow_pairs(b, (void **)&b->held_ee, &b->held_eecap, b->nee + 1, sizeof *b->ee) != 0 ||
	    grow((void **)&b->held_box, &b->held_boxcap, 6 * (size_t)g->nv,
	    sizeof *b->held_box) != 0)
		return -1;
	/* none found (a flat cloth's lists may never have been made):
	 * memcpy from NULL is undefined even for no bytes */
	if (b->nvt > 0)
		memcpy(b->held_vt, b->vt, b->nvt * sizeof *b->vt);
	if (b->nee > 0)
		memcpy(b->held_ee, b->ee, b->nee * sizeof *b->ee);
	b->held_nvt = b->nvt;
	b->held_nee = b->nee;
	memcpy(b->held_box, b->allowed, 6 * (size_t)g->nv * sizeof *b->allowed);
	if (grow((void **)&b->held_cull, &b->held_cullcap, b->ncull + 1, sizeof *b->held_cull) != 0)
		return -1;
	if (b->ncull > 0)
		memcpy(b->held_cull, b->cull, b->ncull * sizeof *b->cull);
	b->held_ncull = b->ncull;
	if (b->held_mark != NULL) {
		memset(b->held_mark, 0, (size_t)b->nnodes);
		for (e = 0; e < b->ncull; e++)
			b->held_mark[b->cull[e]] = 1;
	}
	b->held_want = all;
	b->held_nv = g->nv;
	b->held_valid = true;
	if (skin == 0)
		return 0;	/* the pairs found are the search's */
	/* the search's own from the skinned ones: none is out of its box */
	fill_query_boxes(b, g, want, 0);
	if (grow((void **)&b->dirty, &b->dirtycap, (size_t)g->nv, 1) != 0)
		return -1;
	memset(b->dirty, 0, (size_t)g->nv);
	return take_held(b, g, want, 0, false);
}

/* The pairs that pass want's near test, in order. */
static void
near_filter(struct broad *b, const struct broad_want *want)
{
	size_t i, k;

	for (i = k = 0; i < b->nvt; i++)
		if (near_vt(b, want, b->vt[i].v, b->vt[i].t))
			b->vt[k++] = b->vt[i];
	b->nvt = k;
	for (i = k = 0; i < b->nee; i++) {
		const double *p = b->enear + 12 * b->ee[i].a, *q = b->enear + 12 * b->ee[i].b;

		if (near_overlap(p, p + 6, q, q + 6, want->near, want->near_motion))
			b->ee[k++] = b->ee[i];
	}
	b->nee = k;
}

static int
find_bvh(struct broad *b, const struct geom *g, double cell, const struct broad_want *want)
{
	int v, k, rc = 1;
	size_t e, t;

	if (bvh_prepare(b, g) != 0 ||
	    grow((void **)&b->allowed, &b->allowedcap, 6 * (size_t)g->nv, sizeof *b->allowed) != 0 ||
	    grow((void **)&b->qbox, &b->qboxcap, 6 * (size_t)g->nv, sizeof *b->qbox) != 0 ||
	    grow((void **)&b->ebox, &b->eboxcap, 6 * (g->nedges + 1), sizeof *b->ebox) != 0)
		return -1;
	b->st.cell = cell;
	fill_query_boxes(b, g, want, 0);
	if (want->near > 0) {
		if (grow((void **)&b->vnear, &b->vnearcap, 6 * (size_t)g->nv, sizeof *b->vnear) != 0 ||
		    grow((void **)&b->enear, &b->enearcap, 12 * (g->nedges + 1), sizeof *b->enear) != 0 ||
		    grow((void **)&b->tnear, &b->tnearcap, 12 * (g->ntri + 1), sizeof *b->tnear) != 0)
			return -1;
		for (v = 0; v < g->nv; v++)
			for (k = 0; k < 3; k++) {
				b->vnear[6 * v + k] = g->x0[3 * v + k];
				b->vnear[6 * v + 3 + k] = g->x1[3 * v + k] - g->x0[3 * v + k];
			}
		for (e = 0; e < g->nedges; e++)
			near_boxes(b->enear + 12 * e, b->vnear, g->edge + 2 * e, 2);
		for (t = 0; t < g->ntri; t++)
			near_boxes(b->tnear + 12 * t, b->vnear, g->tri + 3 * t, 3);
	}
	if (b->node == NULL)
		return 0;
	if (cull_prepare(b, g, want) != 0)
		return -1;
	if (held_serves(b, g, want))
		rc = find_held(b, g, want);
	b->tree_covers = rc == 1;	/* a traversal refits the tree */
	if (rc == 1)
		rc = hold_traversal(b, g, want, HELD_SKIN * cell);
	if (rc != 0)
		return -1;
	if (want->near > 0)
		near_filter(b, want);
	return 0;
}

static int
find_brute(struct broad *b, const struct geom *g, const struct broad_want *want)
{
	size_t t, e, f;
	int v;

	for (v = 0; v < g->nv; v++) {
		if (v >= g->ncloth && !want->mesh_vertices)
			break;
		if (stop_asked(b))
			return -1;
		for (t = 0; t < g->ntri; t++)
			if (!tri_has(g, (int)t, v) && !vt_static(g, v, (int)t) &&
			    push_vt(b, v, (int)t) != 0)
				return -1;
	}
	for (e = 0; want->edges && e < g->nedges; e++) {
		if (stop_asked(b))
			return -1;
		for (f = e + 1; f < g->nedges; f++)
			if (!ee_skip(g, (int)e, (int)f) && push_ee(b, (int)e, (int)f) != 0)
				return -1;
	}
	return 0;
}

int
broad_find(struct broad *b, const struct geom *g, double cell, const struct broad_want *want,
    struct drape_err *err)
{
	bool too_small = false;
	int rc;

	if (b->mode == BROAD_GRID && b->valid &&
	    b->valid_want.edges == want->edges && b->valid_want.self == want->self &&
	    b->valid_want.mesh_vertices == want->mesh_vertices &&
	    b->valid_want.neighbour_paths == want->neighbour_paths &&
	    b->valid_cell == cell && b->valid_nv == g->nv && still_allowed(b, g)) {
		b->st.rebuilt = false;
		return 0;
	}
	b->valid = false;
	b->stopped = b->over_memory = false;
	b->nvt = b->nee = 0;
	memset(&b->st, 0, sizeof b->st);
	b->st.rebuilt = true;
	b->st.cell = b->mode == BROAD_BRUTE ? 0 : cell;
	switch (b->mode) {
	case BROAD_SEED:
		rc = find_seed(b, g, cell, want, &too_small);
		break;
	case BROAD_GRID:
		rc = find_grid(b, g, cell, want);
		break;
	case BROAD_BVH:
		rc = find_bvh(b, g, cell, want);
		break;
	default:
		rc = find_brute(b, g, want);
		break;
	}
	if (rc == 0 && b->mode == BROAD_GRID)
		rc = sort_runs(b);	/* found vertex by vertex, each triangle once */
	if (rc != 0) {
		b->nvt = b->nee = 0;
		if (stop_asked(b)) {
			b->stopped = true;
			err_set(err, "broad phase: stopped by a signal");
		} else if (b->over_memory) {
			err_set(err, "broad phase: this step needs more than the %.0f MB that "
			    "[collision] memory allows (the scene's motion spans too much space "
			    "for its cubes, or the memory limit is too low)", b->memory_limit / 1e6);
		} else if (too_small) {
			err_set(err, "spatial hash: out of memory, or %g m cubes are too small for "
			    "the scene's extent", cell);
		} else {
			err_set(err, "broad phase: out of memory");
		}
		return -1;
	}
	if (b->mode == BROAD_SEED)
		canonical(b);
	b->st.vt_pairs = (long)b->nvt;
	b->st.ee_pairs = (long)b->nee;
	if (b->mode == BROAD_GRID) {
		b->valid = true;
		b->valid_want = *want;
		b->valid_cell = cell;
		b->valid_nv = g->nv;
	}
	return 0;
}

int
broad_recheck(struct broad *b, const struct geom *g, const unsigned char *changed)
{
	size_t n = b->ncull, i;
	int *old, given = 0, rc = 0, j, k;
	bool boxes = false;

	if (b->mode != BROAD_BVH || n == 0 || !b->cull_on)
		return 0;
	if ((old = malloc(n * sizeof *old)) == NULL)
		return -1;
	memcpy(old, b->cull, n * sizeof *old);
	b->ncull = 0;
	for (i = 0; i < n && rc >= 0; i++) {
		const struct bvh_node *p = &b->node[old[i]];
		bool moved = false;

		for (j = p->first; j < p->first + p->count && !moved; j++)
			for (k = 0; k < 3; k++)
				moved |= changed[g->tri[3 * b->leaf_tri[j] + k]] != 0;
		if (!moved) {
			rc = push_cull(b, old[i]);
			continue;
		}
		for (j = p->first; j < p->first + p->count; j++)
			tri_deform(b, g, b->leaf_tri[j], 1);
		node_sums(b, old[i], old[i] + 2 * p->count - 1);
		if (patch_flat(b, g, p)) {
			rc = push_cull(b, old[i]);
			continue;
		}
		/* its pairs: found in a tree that holds this search's boxes.
		 * A search served by the held pairs left the tree with the held
		 * boxes, which a dirty vertex's may exceed (its pairs came from
		 * queries, which left this patch out): refit it, and let the
		 * next search traverse, as the held pairs' queries need the
		 * held boxes. A fold is rare; this costs a traversal when one
		 * comes. */
		if (!boxes && fill_tri_boxes(b, g) != 0) {
			rc = -1;
			break;
		}
		boxes = true;
		if (!b->tree_covers) {
			bvh_refit(b, g);
			b->tree_covers = true;
			b->held_valid = false;
		}
		rc = judge_patch(b, g, &b->cull_want, old[i]);
		given |= rc == 0;
	}
	free(old);
	if (rc >= 0 && given && bvh_sort(b, g) != 0)
		rc = -1;
	if (rc < 0) {
		b->stopped = stop_asked(b);
		return -1;
	}
	if (given)
		unique_pairs(b);
	return given;
}
