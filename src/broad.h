/* broad.h: the broad phase: which vertex-triangle and edge-edge pairs the
 * narrow phase tests this step, by one of four modes, a file each:
 *
 * - bvh (broad_bvh.c), the shipped scenes' (tablecloth, strip): grid's
 *   pairs from a tree of boxes, less those inside a patch of the cloth
 *   proven flat over the step (broad_flat.c), which cannot touch, and
 *   held from one search to the next (broad_held.c);
 * - seed (broad_seed.c): the chapter's spatial enumeration (§3.3): nodes
 *   hashed by their predicted position (eq. 18-20); two nodes in one cube
 *   give the pairs (node A, triangles of B) and (node B, triangles of A),
 *   and the edges of A against the edges of B. Nodes in different cubes
 *   are never tested;
 * - grid (broad_grid.c), a scene's without `broad =`: swept boxes in
 *   the hash; never misses what the narrow phase would find;
 * - brute (broad_brute.c): every pair, the ground truth.
 * broad.c holds what they share: the pair lists, the search and its
 * errors. */
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
 * bvh finds grid's pairs with a tree of boxes instead. */
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
	 * the pairs of flat patches (broad_bvh.c). Per cloth triangle the square
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

/* A broad phase and its state between steps (its parts' trees, hash
 * fills and held pairs: broad_impl.h). */
struct broad;

/* NULL out of memory. */
struct broad *broad_new(enum broad_mode mode);
void broad_free(struct broad *b);	/* NULL is fine */

/* What a step may take: the bytes of its hash fills and pair lists (0: no
 * limit), and a flag that stops it (NULL: none), polled in the long loops
 * so that a signal is honoured within the step. */
void broad_set_memory_limit(struct broad *b, double bytes);
void broad_set_stop(struct broad *b, const volatile sig_atomic_t *flag);

/* Finds the pairs (broad_vt, and broad_ee if want->edges), sorted by vertex (edge) then
 * triangle (edge), without duplicates: every pair a narrow phase may find a
 * contact in over the motion of g. cell is L_ce. Returns 0, or -1 with a
 * message (out of memory, or a cell too small for the scene's extent). */
int broad_find(struct broad *b, const struct geom *g, double cell, const struct broad_want *want,
    struct drape_err *err);

/* After the caller moved the ends (x1 of g) of the vertices marked in
 * changed, within their boxes: the patches the last search left out as
 * flat that are no longer give their pairs back (broad_vt, broad_ee,
 * sorted again). 1 if pairs were added, 0 if none, -1 out of memory or stopped. */
int broad_recheck(struct broad *b, const struct geom *g, const unsigned char *changed);

/* The pairs of the last search, sorted: valid until the next call on b. */
const struct vt_pair *broad_vt(const struct broad *b, size_t *n);
const struct ee_pair *broad_ee(const struct broad *b, size_t *n);
/* Forgets them (a step with nothing to search). */
void broad_clear(struct broad *b);
/* The last search gave up for the stop flag. */
bool broad_stopped(const struct broad *b);
const struct broad_stats *broad_stats(const struct broad *b);

#endif
