/* broad.h: the broad phase: which vertex-triangle and edge-edge pairs the
 * narrow phase tests this step.
 *
 * - seed: the chapter's spatial enumeration (§3.3): nodes hashed by their
 *   predicted position (eq. 18-20); two nodes in one cube give the pairs
 *   (node A, triangles of B) and (node B, triangles of A), and the edges of
 *   A against the edges of B. Nodes in different cubes are never tested.
 * - grid: swept boxes; never misses what the narrow phase would find.
 * - brute: every pair, the ground truth.
 * - bvh: grid's pairs from a tree of boxes, less those inside a patch of
 *   the cloth proven flat over the step (broad.c, "flat patches"), which
 *   cannot touch. */
#ifndef DRAPE_BROAD_H
#define DRAPE_BROAD_H

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>

#include "err.h"
#include "hash.h"

/* The geometry contacts are sought in: the cloth's nodes first, then the
 * vertices of obstacle meshes (which never move); the same for triangles
 * and edges. x0 is the consistent state k, x1 the predicted state k+1. */
enum broad_mode { BROAD_SEED, BROAD_GRID, BROAD_BRUTE, BROAD_BVH };
extern const char *const broad_mode_name[];	/* NULL-terminated, for the parser */

/* 1 if the mode fills a spatial hash (seed with nodes, grid with boxes);
 * bvh finds grid's pairs with a tree of boxes instead (broad.c). */
bool broad_uses_hash(enum broad_mode mode);

/* 1 if the mode finds, for a broad_want without near, exactly the pairs
 * whose boxes overlap (bvh; with near, those of them that pass it); the
 * others find more (grid: whatever shares a cube; brute: all). */
bool broad_boxes_exact(enum broad_mode mode);

struct geom {
	int nv, ncloth;		/* vertices; the first ncloth are cloth nodes */
	const double *x0, *x1;
	const int *tri;
	size_t ntri;
	const int *edge;
	size_t nedges;
	/* vertex -> triangles and vertex -> edges, as in struct cloth */
	const int *vtri_start, *vtri, *vedge_start, *vedge;
	const unsigned char *fixed;	/* 1: never moved by a contact */
	/* Optional (NULL: the box of x0 and x1): per vertex, 6 doubles (lo,
	 * hi), a box holding wherever the vertex may be during the step,
	 * including after the corrections the caller may make. The pairs
	 * found stay sound for any path inside these boxes. */
	const double *vbox;
	/* Optional (NULL: none): the cloth's grid, which lets bvh leave out
	 * the pairs of flat patches (broad.c). Per cloth triangle the square
	 * it lies in (j * squares_u + i, of squares_u x squares_v), per cloth
	 * vertex its place on the cloth at rest (u, v; 2 doubles); uv_gap the
	 * least distance at rest between two primitives that share no vertex,
	 * uv_diam the largest between two vertices of one primitive. */
	const int *tri_square;
	int squares_u, squares_v;
	const double *uv;
	double uv_gap, uv_diam;
};

/* What a caller needs found, beside each cloth node against the triangles
 * near it. */
struct broad_want {
	bool self;		/* the cloth against itself (else against the meshes only;
				 * bvh only: the others find all and leave the choice) */
	bool edges;		/* edge-edge pairs */
	bool mesh_vertices;	/* obstacle mesh vertices against the triangles too */
	/* a node's box includes the segments from its neighbours at step k to
	 * it (the seed test's sliding case, end of §3.2) */
	bool neighbour_paths;
	/* near > 0: of the pairs whose boxes overlap, only those that may lie
	 * within near plus near_motion times their relative motion of the step
	 * (x1 - x0 of g) at its start are needed (bvh leaves the others out;
	 * the other modes find them all and leave the choice) */
	double near, near_motion;
};

struct bvh_node {
	double box[6];
	double size;		/* the box's width + height + depth: which side to descend */
	int left, right;	/* children, or -1 for a leaf */
	int tri;		/* a leaf's triangle */
	/* the triangles under it: leaf_tri[first .. first + count) */
	int first, count;
	bool patch;		/* a whole rectangle of the cloth's grid (a flat patch
				 * may be left out; broad.c) */
};

struct vt_pair {
	int v, t;
};

struct ee_pair {
	int a, b;		/* edge numbers, a < b */
};

struct broad_stats {
	double cell;		/* L_ce this step, m */
	struct hash_stats hash;	/* zero for brute */
	long node_pairs;	/* seed: pairs of nodes sharing a cube */
	long vt_pairs, ee_pairs;	/* what the narrow phase gets */
	bool rebuilt;		/* grid: the pairs were found anew this step (else
				 * the last step's still hold; hash is that fill's) */
	long big;		/* grid: boxes kept out of the hash for their size */
};

struct broad {
	enum broad_mode mode;
	/* what a step may take: the bytes of its hash fills and pair lists
	 * (0: no limit), and a flag that stops it (NULL: none), polled in the
	 * long loops so that a signal is honoured within the step */
	double memory_limit;
	const volatile sig_atomic_t *stop;
	bool stopped;		/* the last broad_find gave up for stop */
	bool over_memory;	/* or for the memory limit */
	struct spatial_hash hash;	/* seed: nodes; grid: triangles */
	struct spatial_hash hash_edges;	/* grid with ccd: edges */
	struct vt_pair *vt;
	size_t nvt, vtcap;
	struct ee_pair *ee;
	size_t nee, eecap;
	int *stamp;		/* per triangle or edge: the last vertex or edge that took it */
	size_t stampcap;
	double *box;		/* grid: swept boxes of triangles then edges, 6 each */
	size_t boxcap;
	double *allowed;	/* grid: per vertex, the widened box its pairs hold for */
	size_t allowedcap;
	/* bvh: a tree of boxes over the cloth's triangles and one over the
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
	int bvh_nv;		/* the geometry the tree was built for */
	size_t bvh_ntri;
	int *big;		/* grid: triangles, then edges, too big for the hash */
	size_t nbig_tri, nbig, bigcap;
	unsigned char *is_big;	/* per box */
	size_t is_bigcap;
	/* bvh: the pairs of the last search with a near test (a step's
	 * contacts), before that test, and each vertex's box they were found
	 * for; a later search whose vertices' boxes lie inside takes its pairs
	 * from them (broad.c, find_held). held_valid: there are such pairs. */
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
	bool valid;		/* grid: the pairs may be kept (see broad.c) */
	struct broad_want valid_want;
	double valid_cell;
	int valid_nv;
	struct broad_stats st;
};

void broad_init(struct broad *b, enum broad_mode mode);
void broad_free(struct broad *b);

/* Fills b->vt, and b->ee if want->edges, sorted by vertex (edge) then
 * triangle (edge), without duplicates: every pair a narrow phase may find a
 * contact in over the motion of g. cell is L_ce. Returns 0, or -1 with a
 * message (out of memory, or a cell too small for the scene's extent). */
int broad_find(struct broad *b, const struct geom *g, double cell, const struct broad_want *want,
    struct drape_err *err);

/* After the caller moved the ends (x1 of g) of the vertices marked in
 * changed, within their boxes: the patches the last search left out as
 * flat that are no longer give their pairs back (b->vt, b->ee, sorted
 * again). 1 if pairs were added, 0 if none, -1 out of memory or stopped. */
int broad_recheck(struct broad *b, const struct geom *g, const unsigned char *changed);

#endif
