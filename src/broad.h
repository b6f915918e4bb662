/* broad.h: the broad phase: which vertex-triangle and edge-edge pairs the
 * narrow phase tests this step.
 *
 * - seed: the chapter's spatial enumeration (§3.3): nodes hashed by their
 *   predicted position (eq. 18-20); two nodes in one cube give the pairs
 *   (node A, triangles of B) and (node B, triangles of A), and the edges of
 *   A against the edges of B. Nodes in different cubes are never tested.
 * - grid: swept boxes; never misses what the narrow phase would find.
 * - brute: every pair, the ground truth. */
#ifndef DRAPE_BROAD_H
#define DRAPE_BROAD_H

#include <stdbool.h>
#include <stddef.h>

#include "err.h"
#include "hash.h"
#include "scene.h"

/* The geometry contacts are sought in: the cloth's nodes first, then the
 * vertices of obstacle meshes (which never move); the same for triangles
 * and edges. x0 is the consistent state k, x1 the predicted state k+1. */
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
};

struct broad {
	enum broad_mode mode;
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
	bool valid;		/* grid: the pairs may be kept (see broad.c) */
	enum narrow_mode valid_narrow;
	double valid_cell;
	int valid_nv;
	struct broad_stats st;
};

void broad_init(struct broad *b, enum broad_mode mode);
void broad_free(struct broad *b);

/* Fills b->vt, and for the ccd narrow phase b->ee, sorted by vertex (edge)
 * then triangle (edge), without duplicates: the pairs that narrow phase may
 * find a contact in. cell is L_ce. Returns 0, or -1 with a message (out of
 * memory, or a cell too small for the scene's extent). */
int broad_find(struct broad *b, const struct geom *g, double cell, enum narrow_mode narrow,
    struct drape_err *err);

#endif
