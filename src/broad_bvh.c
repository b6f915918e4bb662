/* broad_bvh.c: grid's pairs from a tree of boxes over the triangles, less
 * those inside a patch of the cloth proven flat over the step, and held
 * between the searches of a step while its vertices stay in their boxes. */
#include <limits.h>

#include "broad_impl.h"


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
		pv[a] = pv[3 + a] = b->bvh.vnear[6 * v + a];
		mv[a] = mv[3 + a] = b->bvh.vnear[6 * v + 3 + a];
	}
	return near_overlap(pv, mv, b->bvh.tnear + 12 * t, b->bvh.tnear + 12 * t + 6, want->near,
	    want->near_motion);
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

	b->bvh.node[at].left = b->bvh.node[at].right = -1;
	b->bvh.node[at].tri = tri[lo];
	b->bvh.node[at].patch = false;
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
	b->bvh.node[at].left = bvh_build(b, g, tri, key, lo, mid, next);
	b->bvh.node[at].right = bvh_build(b, g, tri, key, mid, hi, next);
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

	b->bvh.node[at].left = b->bvh.node[at].right = -1;
	b->bvh.node[at].tri = t;
	b->bvh.node[at].patch = false;
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
		b->bvh.node[at].left = grid_leaf(b, sq[2 * (j0 * su + i0)], next);
		b->bvh.node[at].right = grid_leaf(b, sq[2 * (j0 * su + i0) + 1], next);
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
		b->bvh.node[at].left = bvh_build_grid(b, sq, su, l0, l1, k0, k1, next);
		b->bvh.node[at].right = bvh_build_grid(b, sq, su, r0, r1, h0, h1, next);
	}
	b->bvh.node[at].tri = -1;
	b->bvh.node[at].patch = n == 2 * (i1 - i0) * (j1 - j0);
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
		struct bvh_node *n = &b->bvh.node[i];

		n->count = n->left < 0 ? 1 : b->bvh.node[n->left].count + b->bvh.node[n->right].count;
	}
	b->bvh.node[root].first = first;
	for (i = root; i < end; i++) {
		struct bvh_node *n = &b->bvh.node[i];

		if (n->left < 0) {
			b->bvh.leaf_tri[n->first] = n->tri;
			continue;
		}
		b->bvh.node[n->left].first = n->first;
		b->bvh.node[n->right].first = n->first + b->bvh.node[n->left].count;
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
	if ((b->bvh.dminv = malloc(4 * ncloth_tri * sizeof *b->bvh.dminv)) == NULL ||
	    (b->bvh.tri_cull = malloc(g->ntri * sizeof *b->bvh.tri_cull)) == NULL ||
	    (b->bvh.held_mark = calloc(2 * g->ntri, 1)) == NULL ||
	    (b->bvh.witness = calloc(2 * g->ntri, sizeof *b->bvh.witness)) == NULL)
		return -1;
	for (t = 0; t < ncloth_tri; t++) {
		const int *n = g->tri + 3 * t;
		double a = g->uv[2 * n[1]] - g->uv[2 * n[0]], c = g->uv[2 * n[2]] - g->uv[2 * n[0]];
		double bb = g->uv[2 * n[1] + 1] - g->uv[2 * n[0] + 1];
		double d = g->uv[2 * n[2] + 1] - g->uv[2 * n[0] + 1], det = a * d - c * bb;
		double *m = b->bvh.dminv + 4 * t;

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
	free(b->bvh.node);
	free(b->bvh.rep_vertex);
	free(b->bvh.rep_edge);
	free(b->bvh.rep_start);
	free(b->bvh.rep_list);
	free(b->bvh.rep_nv);
	free(b->bvh.leaf_tri);
	free(b->bvh.dminv);
	free(b->bvh.tri_cull);
	free(b->bvh.held_mark);
	free(b->bvh.witness);
	b->bvh.node = NULL;
	b->bvh.rep_vertex = b->bvh.rep_edge = b->bvh.rep_start = b->bvh.rep_list = NULL;
	b->bvh.rep_nv = NULL;
	b->bvh.leaf_tri = b->bvh.tri_cull = b->bvh.witness = NULL;
	b->bvh.dminv = NULL;
	b->bvh.held_mark = NULL;
}

void
broad_bvh_free(struct broad *b)
{
	bvh_drop(b);
	free(b->bvh.stack);
	free(b->bvh.qbox);
	free(b->bvh.ebox);
	free(b->bvh.vnear);
	free(b->bvh.enear);
	free(b->bvh.tnear);
	free(b->bvh.held_vt);
	free(b->bvh.held_ee);
	free(b->bvh.held_box);
	free(b->bvh.dirty);
	free(b->bvh.found);
	free(b->bvh.dlist);
	free(b->bvh.tbox);
	free(b->bvh.tdef);
	free(b->bvh.nsum);
	free(b->bvh.cull);
	free(b->bvh.held_cull);
}

/* The trees and the representatives, for geometry g; once. */
static int
bvh_prepare(struct broad *b, const struct geom *g)
{
	size_t t, ncloth_tri = 0;
	int *tri = NULL, v, next = 0, e;
	double *key = NULL;

	if (b->bvh.node != NULL && b->bvh.bvh_nv == g->nv && b->bvh.bvh_ntri == g->ntri)
		return 0;
	b->bvh.held_valid = false;	/* their queries need the tree they were found in */
	b->bvh.ncull = b->bvh.held_ncull = 0;
	bvh_drop(b);
	if (g->ntri == 0 || g->ntri > (size_t)INT_MAX / 2)
		return g->ntri == 0 ? 0 : -1;
	b->bvh.node = malloc((2 * g->ntri) * sizeof *b->bvh.node);
	b->bvh.rep_vertex = malloc(((size_t)g->nv + 1) * sizeof *b->bvh.rep_vertex);
	b->bvh.rep_edge = malloc((g->nedges + 1) * sizeof *b->bvh.rep_edge);
	b->bvh.rep_start = calloc(g->ntri + 1, sizeof *b->bvh.rep_start);
	b->bvh.rep_list = malloc(((size_t)g->nv + g->nedges + 1) * sizeof *b->bvh.rep_list);
	b->bvh.rep_nv = calloc(g->ntri, sizeof *b->bvh.rep_nv);
	tri = malloc((g->ntri + 2 * (size_t)g->squares_u * g->squares_v) * sizeof *tri);
	key = malloc(g->ntri * sizeof *key);
	b->bvh.leaf_tri = malloc(g->ntri * sizeof *b->bvh.leaf_tri);
	if (b->bvh.node == NULL || b->bvh.rep_vertex == NULL || b->bvh.rep_edge == NULL || b->bvh.leaf_tri == NULL ||
	    b->bvh.rep_start == NULL || b->bvh.rep_list == NULL ||
	    b->bvh.rep_nv == NULL || tri == NULL || key == NULL)
		goto fail;
	for (t = 0; t < g->ntri; t++) {
		tri[t] = (int)t;
		ncloth_tri += g->tri[3 * t] < g->ncloth;	/* cloth triangles come first */
	}
	b->bvh.cloth_root = b->bvh.mesh_root = -1;
	if (ncloth_tri > 0 && g->tri_square != NULL && g->uv != NULL) {
		/* per square its two triangles, after the triangles' list */
		int *sq = tri + g->ntri, su = g->squares_u;

		for (t = 0; t < 2 * (size_t)su * g->squares_v; t++)
			sq[t] = -1;
		for (t = 0; t < ncloth_tri; t++) {
			int *slot = sq + 2 * g->tri_square[t];

			slot[slot[0] >= 0] = (int)t;
		}
		b->bvh.cloth_root = bvh_build_grid(b, sq, su, 0, su, 0, g->squares_v, &next);
		if (bvh_rest_maps(b, g, ncloth_tri) != 0)
			goto fail;
	} else if (ncloth_tri > 0) {
		b->bvh.cloth_root = bvh_build(b, g, tri, key, 0, (int)ncloth_tri, &next);
	}
	if (ncloth_tri < g->ntri)
		b->bvh.mesh_root = bvh_build(b, g, tri, key, (int)ncloth_tri, (int)g->ntri, &next);
	b->bvh.nnodes = next;
	bvh_spans(b, b->bvh.cloth_root, b->bvh.mesh_root >= 0 ? b->bvh.mesh_root : next, 0);
	bvh_spans(b, b->bvh.mesh_root, next, (int)ncloth_tri);
	for (v = 0; v < g->nv; v++)
		b->bvh.rep_vertex[v] = g->vtri_start[v] < g->vtri_start[v + 1] ?
		    g->vtri[g->vtri_start[v]] : -1;
	for (e = 0; e < (int)g->nedges; e++) {
		int a = g->edge[2 * e], c = g->edge[2 * e + 1], k;

		b->bvh.rep_edge[e] = -1;
		for (k = g->vtri_start[a]; k < g->vtri_start[a + 1] && b->bvh.rep_edge[e] < 0; k++)
			if (tri_has(g, g->vtri[k], c))
				b->bvh.rep_edge[e] = g->vtri[k];
	}
	/* the lists each leaf stands for: counts, starts, then the entries
	 * (vertices first, in order, then edges) */
	for (v = 0; v < g->nv; v++)
		if (b->bvh.rep_vertex[v] >= 0)
			b->bvh.rep_start[b->bvh.rep_vertex[v] + 1]++, b->bvh.rep_nv[b->bvh.rep_vertex[v]]++;
	for (e = 0; e < (int)g->nedges; e++)
		if (b->bvh.rep_edge[e] >= 0)
			b->bvh.rep_start[b->bvh.rep_edge[e] + 1]++;
	for (t = 0; t < g->ntri; t++)
		b->bvh.rep_start[t + 1] += b->bvh.rep_start[t];
	memcpy(tri, b->bvh.rep_start, g->ntri * sizeof *tri);	/* the next free entry */
	for (v = 0; v < g->nv; v++)
		if (b->bvh.rep_vertex[v] >= 0)
			b->bvh.rep_list[tri[b->bvh.rep_vertex[v]]++] = v;
	for (e = 0; e < (int)g->nedges; e++)
		if (b->bvh.rep_edge[e] >= 0)
			b->bvh.rep_list[tri[b->bvh.rep_edge[e]]++] = e;
	b->bvh.bvh_nv = g->nv;
	b->bvh.bvh_ntri = g->ntri;
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
	const int *la = b->bvh.rep_list + b->bvh.rep_start[ta], *lb = b->bvh.rep_list + b->bvh.rep_start[tb];
	int nva = b->bvh.rep_nv[ta], nvb = b->bvh.rep_nv[tb];
	int nea = b->bvh.rep_start[ta + 1] - b->bvh.rep_start[ta] - nva;
	int neb = b->bvh.rep_start[tb + 1] - b->bvh.rep_start[tb] - nvb;
	int k, l, pass;

	for (pass = 0; pass < 2; pass++) {
		const int *lv = pass ? lb : la;
		int o = pass ? ta : tb, nvv = pass ? nvb : nva;
		const double *ob = pass ? ba : bb;

		for (k = 0; k < nvv; k++) {
			int v = lv[k];

			if ((v >= g->ncloth && !want->mesh_vertices) || tri_has(g, o, v) ||
			    vt_static(g, v, o) || !box_overlap(b->bvh.qbox + 6 * v, ob) ||
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
		const double *eba = b->bvh.ebox + 6 * ea;

		for (l = 0; l < neb; l++) {
			int eb = lb[nvb + l];

			if (!box_overlap(eba, b->bvh.ebox + 6 * eb) || ee_skip(g, ea, eb) ||
			    (want->near > 0 && !near_overlap(b->bvh.enear + 12 * ea, b->bvh.enear + 12 * ea + 6,
			    b->bvh.enear + 12 * eb, b->bvh.enear + 12 * eb + 6, want->near, want->near_motion)))
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
	const double *x = k ? g->x1 : g->x0, *m = b->bvh.dminv + 4 * t;
	const int *v = g->tri + 3 * t;
	double *f = b->bvh.tdef + 12 * t + 6 * k;
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
		const struct bvh_node *n = &b->bvh.node[i];
		double *s = b->bvh.nsum + 6 * i;

		if (leaf(n)) {
			const double *f = b->bvh.tdef + 12 * n->tri;

			for (k = 0; k < 6; k++)
				s[k] = f[k] + f[6 + k];
		} else {
			for (k = 0; k < 6; k++)
				s[k] = b->bvh.nsum[6 * n->left + k] + b->bvh.nsum[6 * n->right + k];
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

	b->bvh.cull_on = false;
	b->bvh.ncull = 0;
	if (b->bvh.dminv == NULL || b->bvh.cloth_root < 0 || !want->self || !(g->uv_gap > 0))
		return 0;
	n = b->bvh.node[b->bvh.cloth_root].count;
	if (grow((void **)&b->bvh.tdef, &b->bvh.tdefcap, 12 * (size_t)n, sizeof *b->bvh.tdef) != 0 ||
	    grow((void **)&b->bvh.nsum, &b->bvh.nsumcap, 6 * (size_t)(2 * n), sizeof *b->bvh.nsum) != 0)
		return -1;
	for (t = 0; t < n; t++) {
		tri_deform(b, g, t, 0);
		tri_deform(b, g, t, 1);
	}
	node_sums(b, b->bvh.cloth_root, b->bvh.cloth_root + 2 * n - 1);
	for (k = 0; k < 3 * g->ncloth; k++)
		big = fmax(big, fmax(fabs(g->x0[k]), fabs(g->x1[k])));
	b->bvh.cull_on = true;
	b->bvh.cull_want = *want;
	b->bvh.cull_tol = 1e-6 + 1e-12 * big / g->uv_gap;
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
	const struct broad_want *want = &b->bvh.cull_want;
	int x = (int)(p - b->bvh.node), i, k, ends = want->near > 0 ? 1 : 2, w = b->bvh.witness[x];
	const double *s = b->bvh.nsum + 6 * x;
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
		f = b->bvh.tdef + 12 * b->bvh.leaf_tri[at];
		for (k = 0; k < ends; k++)
			st = fmin(st, least_eigen(q1, q2, f + 6 * k));
		st -= b->bvh.cull_tol;
		if (ends == 1) {
			for (k = 0; k < 6; k++)
				gg += (f[6 + k] - f[k]) * (f[6 + k] - f[k]);
			/* this triangle's sigma and L alone */
			room = (st * g->uv_gap - want->near) / ((1 + 1e-9) * span);
			if (!(room > 0 && gg <= room * room)) {
				b->bvh.witness[x] = at;
				return 0;
			}
		} else if (!(st > 0)) {
			b->bvh.witness[x] = at;
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
	if (b->bvh.ncull == b->bvh.cullcap &&
	    grow((void **)&b->bvh.cull, &b->bvh.cullcap, b->bvh.ncull + 1, sizeof *b->bvh.cull) != 0)
		return -1;
	b->bvh.cull[b->bvh.ncull++] = x;
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

	if (grow((void **)&b->bvh.stack, &b->bvh.stackcap, 8, sizeof *b->bvh.stack) != 0)
		return -1;
	st = b->bvh.stack;
	st[top++] = x;
	st[top++] = y;
	while (top > 0) {
		const struct bvh_node *p, *q;

		if (top + 6 > b->bvh.stackcap) {
			if (grow((void **)&b->bvh.stack, &b->bvh.stackcap, top + 6, sizeof *b->bvh.stack) != 0)
				return -1;
			st = b->bvh.stack;
		}
		y = st[--top];
		x = st[--top];
		p = &b->bvh.node[x];
		q = &b->bvh.node[y];
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
			if (b->bvh.cull_on && p->patch && patch_flat(b, g, p)) {
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
			if (bvh_leaves(b, g, want, p->tri, b->bvh.leaf_tbox ? b->bvh.tbox + 6 * p->tri : p->box,
			    q->tri, b->bvh.leaf_tbox ? b->bvh.tbox + 6 * q->tri : q->box) != 0)
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
		box_add(bx, b->bvh.qbox + 6 * g->tri[3 * t + k]);
		box_add(bx, b->bvh.qbox + 6 * g->tri[3 * t + k] + 3);
	}
}

/* Refits the trees to the vertices' boxes (qbox), children after parents:
 * from the last node back. */
static void
bvh_refit(struct broad *b, const struct geom *g)
{
	int i;

	for (i = b->bvh.nnodes - 1; i >= 0; i--) {
		struct bvh_node *n = &b->bvh.node[i];

		if (leaf(n)) {
			tri_box(n->box, b, g, n->tri);
		} else {
			box_empty(n->box);
			box_add(n->box, b->bvh.node[n->left].box);
			box_add(n->box, b->bvh.node[n->left].box + 3);
			box_add(n->box, b->bvh.node[n->right].box);
			box_add(n->box, b->bvh.node[n->right].box + 3);
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

/* The leaves of both trees whose boxes overlap bx, into b->bvh.found: how
 * many, or -1 out of memory. */
static long
bvh_query(struct broad *b, const double *bx)
{
	size_t top = 0, n = 0;

	if (grow((void **)&b->bvh.stack, &b->bvh.stackcap, 8, sizeof *b->bvh.stack) != 0)
		return -1;
	if (b->bvh.cloth_root >= 0)
		b->bvh.stack[top++] = b->bvh.cloth_root;
	if (b->bvh.mesh_root >= 0)
		b->bvh.stack[top++] = b->bvh.mesh_root;
	while (top > 0) {
		const struct bvh_node *p = &b->bvh.node[b->bvh.stack[--top]];

		if (!box_overlap(p->box, bx))
			continue;
		if (leaf(p)) {
			if (n == b->bvh.foundcap &&
			    grow((void **)&b->bvh.found, &b->bvh.foundcap, n + 1, sizeof *b->bvh.found) != 0)
				return -1;
			b->bvh.found[n++] = p->tri;
			continue;
		}
		if (top + 2 > b->bvh.stackcap &&
		    grow((void **)&b->bvh.stack, &b->bvh.stackcap, top + 2, sizeof *b->bvh.stack) != 0)
			return -1;
		b->bvh.stack[top++] = p->left;
		b->bvh.stack[top++] = p->right;
	}
	return (long)n;
}

/* Each triangle's box of this search. */
static int
fill_tri_boxes(struct broad *b, const struct geom *g)
{
	size_t t;

	if (grow((void **)&b->bvh.tbox, &b->bvh.tboxcap, 6 * (g->ntri + 1), sizeof *b->bvh.tbox) != 0)
		return -1;
	for (t = 0; t < g->ntri; t++)
		tri_box(b->bvh.tbox + 6 * t, b, g, (int)t);
	return 0;
}

static int
tri_dirty(const struct broad *b, const struct geom *g, int t)
{
	const int *n = g->tri + 3 * t;

	return b->bvh.dirty[n[0]] | b->bvh.dirty[n[1]] | b->bvh.dirty[n[2]];
}

static int
edge_dirty(const struct broad *b, const struct geom *g, int e)
{
	return b->bvh.dirty[g->edge[2 * e]] | b->bvh.dirty[g->edge[2 * e + 1]];
}

/* Whether a traversal leaves out the pairs of triangles ta and tb (a
 * vertex's or an edge's, its representative): both in one flat patch. */
static int
culled(const struct broad *b, int ta, int tb)
{
	return b->bvh.ncull > 0 && ta >= 0 && tb >= 0 && b->bvh.tri_cull[ta] >= 0 &&
	    b->bvh.tri_cull[ta] == b->bvh.tri_cull[tb];
}

/* The held pairs of clean vertices, by this search's box test. */
static int
held_clean(struct broad *b, const struct geom *g)
{
	size_t i;

	for (i = 0; i < b->bvh.held_nvt; i++) {
		int v = b->bvh.held_vt[i].v, t = b->bvh.held_vt[i].t;

		if (b->bvh.dirty[v] || tri_dirty(b, g, t) ||
		    !box_overlap(b->bvh.qbox + 6 * v, b->bvh.tbox + 6 * t) || culled(b, b->bvh.rep_vertex[v], t))
			continue;
		if (push_vt(b, v, t) != 0)
			return -1;
	}
	for (i = 0; i < b->bvh.held_nee; i++) {
		int e = b->bvh.held_ee[i].a, f = b->bvh.held_ee[i].b;

		if (edge_dirty(b, g, e) || edge_dirty(b, g, f) ||
		    !box_overlap(b->bvh.ebox + 6 * e, b->bvh.ebox + 6 * f) ||
		    culled(b, b->bvh.rep_edge[e], b->bvh.rep_edge[f]))
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
	long n = bvh_query(b, b->bvh.qbox + 6 * v), k;

	for (k = 0; k < n; k++) {
		int t = b->bvh.found[k];

		if (tri_dirty(b, g, t) || tri_has(g, t, v) || vt_static(g, v, t) ||
		    !vt_wanted(g, want, v, t) || !box_overlap(b->bvh.qbox + 6 * v, b->bvh.tbox + 6 * t) ||
		    culled(b, b->bvh.rep_vertex[v], t))
			continue;
		if (push_vt(b, v, t) != 0)
			return -1;
	}
	return n < 0 ? -1 : 0;
}

static int
held_query_triangle(struct broad *b, const struct geom *g, const struct broad_want *want, int t)
{
	const double *tb = b->bvh.tbox + 6 * t;
	long n = bvh_query(b, tb), k;
	int j;

	for (k = 0; k < n; k++) {
		const int *l = b->bvh.rep_list + b->bvh.rep_start[b->bvh.found[k]];

		for (j = 0; j < b->bvh.rep_nv[b->bvh.found[k]]; j++) {
			int u = l[j];

			if (b->bvh.dirty[u] || tri_has(g, t, u) || vt_static(g, u, t) ||
			    !vt_wanted(g, want, u, t) || !box_overlap(b->bvh.qbox + 6 * u, tb) ||
			    culled(b, b->bvh.rep_vertex[u], t))
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
	const double *eb = b->bvh.ebox + 6 * e;
	long n = bvh_query(b, eb), k;
	int j;

	for (k = 0; k < n; k++) {
		int o = b->bvh.found[k];

		for (j = b->bvh.rep_start[o] + b->bvh.rep_nv[o]; j < b->bvh.rep_start[o + 1]; j++) {
			int f = b->bvh.rep_list[j];

			if (edge_dirty(b, g, f) || ee_skip(g, e, f) || !ee_wanted(g, want, e, f) ||
			    !box_overlap(eb, b->bvh.ebox + 6 * f) || culled(b, b->bvh.rep_edge[e], b->bvh.rep_edge[f]))
				continue;
			if (push_ee(b, e, f) != 0)
				return -1;
		}
	}
	return n < 0 ? -1 : 0;
}

/* Every pair that touches a dirty vertex: against the clean side from the
 * tree, dirty against dirty by testing each pair of the lists of dirty
 * vertices, triangles and edges (b->bvh.dlist). */
static int
held_dirty(struct broad *b, const struct geom *g, const struct broad_want *want)
{
	size_t nv = 0, nt = 0, ne = 0, t, e, i, j;
	int *dv, *dt, *de;
	int v;

	if (grow((void **)&b->bvh.dlist, &b->bvh.dlistcap, (size_t)g->nv + g->ntri + g->nedges + 1,
	    sizeof *b->bvh.dlist) != 0)
		return -1;
	dv = b->bvh.dlist;
	for (v = 0; v < g->nv; v++)
		if (b->bvh.dirty[v] && (v < g->ncloth || want->mesh_vertices))
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
			    box_overlap(b->bvh.qbox + 6 * dv[i], b->bvh.tbox + 6 * (size_t)dt[j]) &&
			    !culled(b, b->bvh.rep_vertex[dv[i]], dt[j]) && push_vt(b, dv[i], dt[j]) != 0)
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
			    box_overlap(b->bvh.ebox + 6 * (size_t)de[i], b->bvh.ebox + 6 * (size_t)de[j]) &&
			    !culled(b, b->bvh.rep_edge[de[i]], b->bvh.rep_edge[de[j]]) &&
			    push_ee(b, de[i], de[j]) != 0)
				return -1;
	}
	return 0;
}

/* Whether the held pairs can serve a search for want. */
static int
held_serves(const struct broad *b, const struct geom *g, const struct broad_want *want)
{
	const struct broad_want *h = &b->bvh.held_want;

	return b->bvh.held_valid && b->bvh.held_nv == g->nv && !want->neighbour_paths &&
	    (b->bvh.held_ncull == 0 || b->bvh.cull_on) &&
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
	bool saved = b->bvh.leaf_tbox;
	int rc;

	if (patch_flat(b, g, &b->bvh.node[x]))
		return push_cull(b, x) != 0 ? -1 : 1;
	b->bvh.leaf_tbox = true;
	rc = bvh_traverse(b, g, want, x, x);
	b->bvh.leaf_tbox = saved;
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
	const struct bvh_node *p = &b->bvh.node[x];
	int rc;

	if (leaf(p))
		return 0;
	if (b->bvh.held_mark[x]) {
		rc = judge_patch(b, g, want, x);
		*given |= rc == 0;
		return rc < 0 ? -1 : 0;
	}
	if (p->patch && patch_flat(b, g, p))
		return push_cull(b, x);
	return judge_held(b, g, want, p->left, given) != 0 ||
	    judge_held(b, g, want, p->right, given) != 0 ? -1 : 0;
}

/* The search's pairs, sorted, from the held ones, with b->bvh.dirty marking
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
		b->bvh.ncull = 0;
		if (b->bvh.cull_on && judge_held(b, g, want, b->bvh.cloth_root, &given) != 0)
			return -1;
	}
	if (b->bvh.ncull > 0) {
		for (i = 0; i < g->ntri; i++)
			b->bvh.tri_cull[i] = -1;
		for (i = 0; i < b->bvh.ncull; i++) {
			const struct bvh_node *p = &b->bvh.node[b->bvh.cull[i]];
			int j;

			for (j = p->first; j < p->first + p->count; j++)
				b->bvh.tri_cull[b->bvh.leaf_tri[j]] = b->bvh.cull[i];
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

	if (grow((void **)&b->bvh.dirty, &b->bvh.dirtycap, (size_t)g->nv, 1) != 0)
		return -1;
	for (v = 0; v < g->nv; v++) {
		const double *a = b->allowed + 6 * v, *h = b->bvh.held_box + 6 * v;

		b->bvh.dirty[v] = a[0] < h[0] || a[1] < h[1] || a[2] < h[2] ||
		    a[3] > h[3] || a[4] > h[4] || a[5] > h[5];
		ndirty += b->bvh.dirty[v];
	}
	if (ndirty > g->nv / HELD_DIRTY_SHARE)
		return 1;
	b->bvh.held_uses++;
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
		memcpy(b->bvh.qbox, b->allowed, 6 * (size_t)g->nv * sizeof *b->bvh.qbox);
	for (v = 0; want->neighbour_paths && v < g->nv; v++) {
		double *q = b->bvh.qbox + 6 * v;

		box_empty(q);
		allowed_box(q, b, v);
		for (k = g->vedge_start[v]; k < g->vedge_start[v + 1]; k++) {
			const int *en = g->edge + 2 * g->vedge[k];

			allowed_box(q, b, en[0] == v ? en[1] : en[0]);
		}
	}
	for (e = 0; e < g->nedges; e++) {
		double *eb = b->bvh.ebox + 6 * e;
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
	if (!b->bvh.held_valid)
		skin = 0;
	else if (b->bvh.held_skin > 0 ? b->bvh.held_uses < HELD_SKIN_USES : b->bvh.held_uses > 0)
		skin = 0;
	b->bvh.held_valid = false;
	b->bvh.held_skin = skin;
	b->bvh.held_uses = 0;
	fill_query_boxes(b, g, want, skin);
	bvh_refit(b, g);
	b->nvt = b->nee = 0;
	if (b->bvh.cloth_root >= 0 && want->self &&
	    bvh_traverse(b, g, &all, b->bvh.cloth_root, b->bvh.cloth_root) != 0)
		return -1;
	if (b->bvh.cloth_root >= 0 && b->bvh.mesh_root >= 0 &&
	    bvh_traverse(b, g, &all, b->bvh.cloth_root, b->bvh.mesh_root) != 0)
		return -1;
	if (bvh_sort(b, g) != 0 ||
	    grow_pairs(b, (void **)&b->bvh.held_vt, &b->bvh.held_vtcap, b->nvt + 1, sizeof *b->vt) != 0 ||
	    grow_pairs(b, (void **)&b->bvh.held_ee, &b->bvh.held_eecap, b->nee + 1, sizeof *b->ee) != 0 ||
	    grow((void **)&b->bvh.held_box, &b->bvh.held_boxcap, 6 * (size_t)g->nv,
	    sizeof *b->bvh.held_box) != 0)
		return -1;
	/* none found (a flat cloth's lists may never have been made):
	 * memcpy from NULL is undefined even for no bytes */
	if (b->nvt > 0)
		memcpy(b->bvh.held_vt, b->vt, b->nvt * sizeof *b->vt);
	if (b->nee > 0)
		memcpy(b->bvh.held_ee, b->ee, b->nee * sizeof *b->ee);
	b->bvh.held_nvt = b->nvt;
	b->bvh.held_nee = b->nee;
	memcpy(b->bvh.held_box, b->allowed, 6 * (size_t)g->nv * sizeof *b->allowed);
	if (grow((void **)&b->bvh.held_cull, &b->bvh.held_cullcap, b->bvh.ncull + 1, sizeof *b->bvh.held_cull) != 0)
		return -1;
	if (b->bvh.ncull > 0)
		memcpy(b->bvh.held_cull, b->bvh.cull, b->bvh.ncull * sizeof *b->bvh.cull);
	b->bvh.held_ncull = b->bvh.ncull;
	if (b->bvh.held_mark != NULL) {
		memset(b->bvh.held_mark, 0, (size_t)b->bvh.nnodes);
		for (e = 0; e < b->bvh.ncull; e++)
			b->bvh.held_mark[b->bvh.cull[e]] = 1;
	}
	b->bvh.held_want = all;
	b->bvh.held_nv = g->nv;
	b->bvh.held_valid = true;
	if (skin == 0)
		return 0;	/* the pairs found are the search's */
	/* the search's own from the skinned ones: none is out of its box */
	fill_query_boxes(b, g, want, 0);
	if (grow((void **)&b->bvh.dirty, &b->bvh.dirtycap, (size_t)g->nv, 1) != 0)
		return -1;
	memset(b->bvh.dirty, 0, (size_t)g->nv);
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
		const double *p = b->bvh.enear + 12 * b->ee[i].a, *q = b->bvh.enear + 12 * b->ee[i].b;

		if (near_overlap(p, p + 6, q, q + 6, want->near, want->near_motion))
			b->ee[k++] = b->ee[i];
	}
	b->nee = k;
}

int
broad_find_bvh(struct broad *b, const struct geom *g, double cell, const struct broad_want *want)
{
	int v, k, rc = 1;
	size_t e, t;

	if (bvh_prepare(b, g) != 0 ||
	    grow((void **)&b->allowed, &b->allowedcap, 6 * (size_t)g->nv, sizeof *b->allowed) != 0 ||
	    grow((void **)&b->bvh.qbox, &b->bvh.qboxcap, 6 * (size_t)g->nv, sizeof *b->bvh.qbox) != 0 ||
	    grow((void **)&b->bvh.ebox, &b->bvh.eboxcap, 6 * (g->nedges + 1), sizeof *b->bvh.ebox) != 0)
		return -1;
	b->st.cell = cell;
	fill_query_boxes(b, g, want, 0);
	if (want->near > 0) {
		if (grow((void **)&b->bvh.vnear, &b->bvh.vnearcap, 6 * (size_t)g->nv, sizeof *b->bvh.vnear) != 0 ||
		    grow((void **)&b->bvh.enear, &b->bvh.enearcap, 12 * (g->nedges + 1), sizeof *b->bvh.enear) != 0 ||
		    grow((void **)&b->bvh.tnear, &b->bvh.tnearcap, 12 * (g->ntri + 1), sizeof *b->bvh.tnear) != 0)
			return -1;
		for (v = 0; v < g->nv; v++)
			for (k = 0; k < 3; k++) {
				b->bvh.vnear[6 * v + k] = g->x0[3 * v + k];
				b->bvh.vnear[6 * v + 3 + k] = g->x1[3 * v + k] - g->x0[3 * v + k];
			}
		for (e = 0; e < g->nedges; e++)
			near_boxes(b->bvh.enear + 12 * e, b->bvh.vnear, g->edge + 2 * e, 2);
		for (t = 0; t < g->ntri; t++)
			near_boxes(b->bvh.tnear + 12 * t, b->bvh.vnear, g->tri + 3 * t, 3);
	}
	if (b->bvh.node == NULL)
		return 0;
	if (cull_prepare(b, g, want) != 0)
		return -1;
	if (held_serves(b, g, want))
		rc = find_held(b, g, want);
	b->bvh.tree_covers = rc == 1;	/* a traversal refits the tree */
	if (rc == 1)
		rc = hold_traversal(b, g, want, HELD_SKIN * cell);
	if (rc != 0)
		return -1;
	if (want->near > 0)
		near_filter(b, want);
	return 0;
}

int
broad_recheck(struct broad *b, const struct geom *g, const unsigned char *changed)
{
	size_t n = b->bvh.ncull, i;
	int *old, given = 0, rc = 0, j, k;
	bool boxes = false;

	if (b->mode != BROAD_BVH || n == 0 || !b->bvh.cull_on)
		return 0;
	if ((old = malloc(n * sizeof *old)) == NULL)
		return -1;
	memcpy(old, b->bvh.cull, n * sizeof *old);
	b->bvh.ncull = 0;
	for (i = 0; i < n && rc >= 0; i++) {
		const struct bvh_node *p = &b->bvh.node[old[i]];
		bool moved = false;

		for (j = p->first; j < p->first + p->count && !moved; j++)
			for (k = 0; k < 3; k++)
				moved |= changed[g->tri[3 * b->bvh.leaf_tri[j] + k]] != 0;
		if (!moved) {
			rc = push_cull(b, old[i]);
			continue;
		}
		for (j = p->first; j < p->first + p->count; j++)
			tri_deform(b, g, b->bvh.leaf_tri[j], 1);
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
		if (!b->bvh.tree_covers) {
			bvh_refit(b, g);
			b->bvh.tree_covers = true;
			b->bvh.held_valid = false;
		}
		rc = judge_patch(b, g, &b->bvh.cull_want, old[i]);
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

