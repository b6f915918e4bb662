/* cloth.h: the particle network of the chapter's §3: nodes on an nu x nv
 * grid of square elements, their lumped masses, the elements that give
 * internal forces, and the triangles (with adjacency) that collision
 * detection uses. i runs along the warp, j along the weft.
 *
 * A shaped cloth (shape = disc) keeps some of the grid's squares. Its nodes
 * are numbered densely, so that everything downstream (forces, integrator,
 * collisions, OBJ output) sees an ordinary network of n nodes and never a
 * hole; grid_node and node_grid translate between the two numberings. The
 * numbering is the grid's order (j, then i) with the missing positions left
 * out, so a square cloth's node (i, j) is number j*nu + i.
 * Built once from a scene; nothing here changes during a run. */
#ifndef DRAPE_CLOTH_H
#define DRAPE_CLOTH_H

#include <stddef.h>

#include "err.h"
#include "scene.h"

/* In-plane stretch along one yarn direction: a linear spring. */
struct spring {
	int a, b;
	double k;		/* N/m */
	double rest;		/* m */
};

/* In-plane shear: the angle at node c between edges c->a (warp) and c->b
 * (weft) of one square, whose rest value is pi/2. */
struct corner {
	int c, a, b;
	double k;		/* N*m per rad^2 */
};

/* Out-of-plane bending: the turning angle at node b of the yarn line a-b-c. */
struct hinge {
	int a, b, c;
	double k;		/* N*m per rad^2 */
};

struct cloth {
	enum cloth_shape shape;
	int nu, nv, n;		/* grid size and node count */
	double h;		/* spacing */
	double *x0;		/* rest positions, 3n */
	double *mass;		/* kg, n */

	struct spring *springs;	/* warp springs first, then weft */
	size_t nsprings;
	struct corner *corners;
	size_t ncorners;
	struct hinge *hinges;	/* warp lines first, then weft */
	size_t nhinges;

	int *tri;		/* 3 nodes per triangle, counter-clockwise about warp x weft */
	size_t ntri;
	int *edge;		/* 2 nodes per triangle edge, a < b */
	size_t nedges;
	/* node -> triangles and node -> edges, compressed: the entries of
	 * node i are [start[i], start[i+1]) */
	int *node_tri_start, *node_tri;
	int *node_edge_start, *node_edge;

	int *grid_node;		/* nu*nv: the node at (i, j) is grid_node[j*nu + i], or -1 */
	int *node_grid;		/* n: node p is at grid position node_grid[p] = j*nu + i */
	size_t nsquares;	/* squares of the grid that are cloth */
};

int cloth_build(struct cloth *cl, const struct scene *sc, struct drape_err *err);

/* Whether grid position (i, j) is a node of a cloth of this shape on an
 * nu x nv grid, before any is built (a disc keeps the corners of its whole
 * squares, as cloth_build does). */
bool cloth_grid_has_node(enum cloth_shape shape, int nu, int nv, int i, int j);
void cloth_free(struct cloth *cl);

/* A hinge whose middle node and one neighbour are held is a clamp: only
 * the free half of its length h can bend, so its stiffness doubles (without
 * this the clamp acts h/2 behind the held edge, an O(h) error). */
void cloth_clamp_hinges(struct cloth *cl, const unsigned char *held);

/* An upper bound on the network's highest angular frequency (rad/s), from
 * Gershgorin's theorem on the rest stiffness over the lightest masses. */
double cloth_omega_bound(const struct cloth *cl);
/* The same for bending alone. */
double cloth_omega_bound_bend(const struct cloth *cl);

/* The node at grid position (i, j), or -1 where the shape has none. */
static inline int
cloth_node(const struct cloth *cl, int i, int j)
{
	return cl->grid_node[j * cl->nu + i];
}

/* The grid position of node p. */
static inline void
cloth_grid_ij(const struct cloth *cl, int p, int *i, int *j)
{
	*i = cl->node_grid[p] % cl->nu;
	*j = cl->node_grid[p] / cl->nu;
}

#endif
