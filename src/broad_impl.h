/* broad_impl.h: what the broad phases share, inside the broad module only
 * (broad.c runs a search; broad_brute.c, broad_seed.c, broad_grid.c and
 * broad_bvh.c with broad_flat.c and broad_held.c are its modes, each with
 * a part of struct broad its own). */
#ifndef DRAPE_BROAD_IMPL_H
#define DRAPE_BROAD_IMPL_H

#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "broad.h"
#include "grow.h"
#include "hash.h"
#include "stop.h"

struct bvh_node {
	double box[6];
	double size;		/* the box's width + height + depth: which side to descend */
	int left, right;	/* children, or -1 for a leaf */
	int tri;		/* a leaf's triangle */
	/* the triangles under it: leaf_tri[first .. first + count) */
	int first, count;
	bool patch;		/* a whole rectangle of the cloth's grid (a flat patch
				 * may be left out; broad_flat.c) */
};

/* seed: the nodes' hash */
struct broad_seed {
	struct spatial_hash hash;
};

/* grid: swept boxes in a hash */
struct broad_grid {
	struct spatial_hash hash;	/* triangles */
	struct spatial_hash hash_edges;	/* with ccd: edges */
	int *stamp;		/* per triangle or edge: the last vertex or edge that took it */
	size_t stampcap;
	double *box;		/* swept boxes of triangles then edges, 6 each */
	size_t boxcap;
	int *big;		/* triangles, then edges, too big for the hash */
	size_t nbig_tri, nbig, bigcap;
	unsigned char *is_big;	/* per box */
	size_t is_bigcap;
	bool valid;		/* the pairs may be kept (broad_grid_holds) */
	struct broad_want valid_want;
	double valid_cell;
	int valid_nv;
};

/* bvh: the trees, the flat patches and the held pairs */
struct broad_bvh {
	/* a tree of boxes over the cloth's triangles and one over the
	 * meshes', built once (the topology is fixed) and refitted; each
	 * vertex and edge is found through one of its triangles only */
	struct bvh_node *node;
	int nnodes, cloth_root, mesh_root;
	int *rep_vertex, *rep_edge;	/* the triangle standing for each */
	/* per triangle t, the vertices and edges it stands for:
	 * rep_list[rep_start[t] .. rep_start[t] + rep_nv[t]) vertices, then
	 * edges up to rep_start[t + 1] */
	int *rep_start, *rep_list;
	unsigned char *rep_nv;
	double *ebox;		/* per edge: its box */
	size_t eboxcap;
	int *stack;
	size_t stackcap;
	double *qbox;		/* per vertex: the box it is looked up with */
	size_t qboxcap;
	/* near: per vertex its position at the start and its motion (3 each);
	 * per edge and per triangle the boxes of those (6 each) */
	double *vnear, *enear, *tnear;
	size_t vnearcap, enearcap, tnearcap;
	/* per tree node the same two boxes over the triangles under it, for
	 * the near test of a pair of subtrees (bvh_traverse) */
	double *nnear;
	size_t nnearcap;
	int bvh_nv;		/* the geometry the tree was built for */
	size_t bvh_ntri;
	/* the pairs of the last traversal without a near test (a step's
	 * check; broad_held.c near_traversal holds none), and each vertex's
	 * box they were found for; a later search whose vertices' boxes lie
	 * inside takes its pairs from them (find_held). held_valid: there
	 * are such pairs. */
	struct vt_pair *held_vt;
	size_t held_nvt, held_vtcap;
	struct ee_pair *held_ee;
	size_t held_nee, held_eecap;
	double *held_box;
	size_t held_boxcap;
	unsigned char *dirty;	/* per vertex: out of its held box */
	size_t dirtycap;
	int *found;		/* a query's leaves */
	size_t foundcap;
	int *dlist;		/* the dirty vertices, triangles and edges */
	size_t dlistcap;
	double *tbox;		/* per triangle: its box, for the held pairs */
	size_t tboxcap;
	bool held_valid;
	struct broad_want held_want;
	int held_nv;
	double held_skin;	/* the held boxes' widening */
	long held_uses;		/* searches the held pairs served */
	/* bvh over a cloth's grid: the triangles in the order of the tree's
	 * leaves; per cloth triangle its rest map's inverse (4) and its
	 * deformation at x0 and x1 (12); the patches the last search left
	 * out as flat, and those of the held pairs' traversal */
	int *leaf_tri;
	double *dminv, *tdef;
	size_t tdefcap;
	double *nsum;		/* per cloth node of the tree: its F's summed (6) */
	size_t nsumcap;
	int *cull, *held_cull;
	unsigned char *held_mark;	/* per node: left out by the held traversal */
	int *tri_cull;		/* per triangle: the patch left out holding it, or -1 */
	int *witness;		/* per node: where its last flat test failed (leaf_tri) */
	size_t ncull, cullcap, held_ncull, held_cullcap;
	bool cull_on;		/* this traversal may leave patches out */
	bool leaf_tbox;		/* leaves' boxes from tbox (the tree's are stale) */
	bool tree_covers;	/* the tree's boxes hold this search's (else they are
				 * the held ones, and a dirty vertex may be out) */
	struct broad_want cull_want;	/* the search the patches are judged for */
	double cull_tol;	/* the least eigenvalue taken as positive */
};

struct broad {
	enum broad_mode mode;
	/* what a step may take (broad_set_memory_limit, broad_set_stop) */
	double memory_limit;
	const volatile sig_atomic_t *stop;
	bool stopped;		/* the last broad_find gave up for stop */
	bool over_memory;	/* or for the memory limit */
	struct vt_pair *vt;
	size_t nvt, vtcap;
	struct ee_pair *ee;
	size_t nee, eecap;
	double *allowed;	/* grid, bvh: per vertex, the widened box its pairs hold for */
	size_t allowedcap;
	struct broad_seed seed;
	struct broad_grid grid;
	struct broad_bvh bvh;
	struct broad_stats st;
};

/* The phases. Each fills b->vt and b->ee (and b->st's counts of its own);
 * 0, or -1 out of memory, over the memory limit or stopped. seed's
 * too_small: the cell is too small for the scene's extent. */
int broad_find_brute(struct broad *b, const struct geom *g, const struct broad_want *want);
int broad_find_seed(struct broad *b, const struct geom *g, double cell, const struct broad_want *want,
    bool *too_small);
int broad_find_grid(struct broad *b, const struct geom *g, double cell, const struct broad_want *want);
int broad_find_bvh(struct broad *b, const struct geom *g, double cell, const struct broad_want *want);
/* grid: the last search's pairs hold for this one (every vertex is still
 * inside the box they were found for); broad_grid_keep marks them so. */
bool broad_grid_holds(const struct broad *b, const struct geom *g, double cell,
    const struct broad_want *want);
void broad_grid_keep(struct broad *b, const struct geom *g, double cell, const struct broad_want *want);
void broad_grid_free(struct broad *b);
void broad_bvh_free(struct broad *b);

/* bvh's parts: the trees (broad_bvh.c), the flat patches (broad_flat.c)
 * and the held pairs (broad_held.c). */
static inline int bvh_leaf(const struct bvh_node *n) { return n->left < 0; }
/* broad_bvh.c: every pair of leaves under x and y (x == y: a subtree
 * against itself) whose boxes overlap; the pairs sorted (a radix sort);
 * triangle t's box from its vertices' query boxes; the trees refitted to
 * those boxes. 0, or -1 out of memory or stopped. */
int bvh_traverse(struct broad *b, const struct geom *g, const struct broad_want *want, int x, int y);
int bvh_sort(struct broad *b, const struct geom *g);
void bvh_tri_box(double *bx, const struct broad *b, const struct geom *g, int t);
void bvh_refit(struct broad *b, const struct geom *g);
/* broad_flat.c: triangle t's deformation at x0 (k = 0) or x1 (k = 1); the
 * nodes [x, end)'s sums of them; each triangle's for a search; whether
 * patch p is flat enough for it (the proof there); a patch left out. */
void bvh_tri_deform(struct broad *b, const struct geom *g, int t, int k);
void bvh_node_sums(struct broad *b, int x, int end);
int bvh_cull_prepare(struct broad *b, const struct geom *g, const struct broad_want *want);
int bvh_patch_flat(struct broad *b, const struct geom *g, const struct bvh_node *p);
int bvh_push_cull(struct broad *b, int x);
/* broad_held.c: the search's pairs from the held ones, or a traversal
 * that holds them (0, or -1 out of memory or stopped); each triangle's
 * box of the search; the sorted lists without repeats; patch x judged
 * for the search (1: left out again, 0: its pairs found, -1); the query
 * boxes, widened by skin. */
int bvh_held_find(struct broad *b, const struct geom *g, const struct broad_want *want, double cell);
int bvh_fill_tri_boxes(struct broad *b, const struct geom *g);
void bvh_unique_pairs(struct broad *b);
int bvh_judge_patch(struct broad *b, const struct geom *g, const struct broad_want *want, int x);
void bvh_fill_query_boxes(struct broad *b, const struct geom *g, const struct broad_want *want,
    double skin);

/* The pair lists' bytes, for the memory limit. */
static inline double
pair_bytes(const struct broad *b)
{
	return (double)(b->vtcap + b->bvh.held_vtcap) * sizeof *b->vt +
	    (double)(b->eecap + b->bvh.held_eecap) * sizeof *b->ee;
}

/* A pair list grown to hold need entries, within the memory limit. */
static inline int
grow_pairs(struct broad *b, void **p, size_t *cap, size_t need, size_t size)
{
	if (need > *cap && b->memory_limit > 0 &&
	    pair_bytes(b) + (double)*cap * (double)size > b->memory_limit) {
		b->over_memory = true;
		return -1;
	}
	return grow_array(p, cap, need, size);
}

static inline int
push_vt(struct broad *b, int v, int t)
{
	if (b->nvt == b->vtcap &&
	    grow_pairs(b, (void **)&b->vt, &b->vtcap, b->nvt + 1, sizeof *b->vt) != 0)
		return -1;
	b->vt[b->nvt].v = v;
	b->vt[b->nvt++].t = t;
	return 0;
}

static inline int
push_ee(struct broad *b, int e1, int e2)
{
	if (b->nee == b->eecap &&
	    grow_pairs(b, (void **)&b->ee, &b->eecap, b->nee + 1, sizeof *b->ee) != 0)
		return -1;
	b->ee[b->nee].a = e1 < e2 ? e1 : e2;
	b->ee[b->nee++].b = e1 < e2 ? e2 : e1;
	return 0;
}

static inline int
tri_has(const struct geom *g, int t, int v)
{
	const int *n = g->tri + 3 * t;

	return n[0] == v || n[1] == v || n[2] == v;
}

/* A vertex and a triangle (or two edges) that are all obstacle: never. */
static inline int
vt_static(const struct geom *g, int v, int t)
{
	return v >= g->ncloth && g->tri[3 * t] >= g->ncloth;
}

static inline int
ee_skip(const struct geom *g, int e1, int e2)
{
	const int *a = g->edge + 2 * e1, *b = g->edge + 2 * e2;

	return a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1] ||
	    (a[0] >= g->ncloth && b[0] >= g->ncloth);
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

static inline void
box_empty(double *bx)
{
	bx[0] = bx[1] = bx[2] = INFINITY;
	bx[3] = bx[4] = bx[5] = -INFINITY;
}

/* All six comparisons, without a branch between them: in a traversal the
 * outcome is a coin toss, and a mispredicted branch a comparison cost a
 * quarter of the tree's time. */
static inline int
box_overlap(const double *a, const double *b)
{
	return (a[0] <= b[3]) & (b[0] <= a[3]) & (a[1] <= b[4]) & (b[1] <= a[4]) &
	    (a[2] <= b[5]) & (b[2] <= a[5]);
}
/* Adds to bx where vertex v may be during the step. */
static inline void
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
static inline void
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

static inline void
allowed_box(double *bx, const struct broad *b, int v)
{
	box_add(bx, b->allowed + 6 * v);
	box_add(bx, b->allowed + 6 * v + 3);
}

#endif
