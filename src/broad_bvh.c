/* broad_bvh.c: bvh: grid's pairs from a tree of boxes over the
 * triangles, built once and refitted, and its traversal; what a search
 * leaves out as flat is broad_flat.c's, the pairs it holds from one
 * search to the next broad_held.c's. */
#include <limits.h>
#include <math.h>

#include "broad_impl.h"


/*
 * Whether two sets of points, in boxes of positions pa and pb at the step's
 * start (lo then hi, 6 each), moving by motions in boxes ma and mb, may lie
 * within near plus share times their relative motion (a broad_want's
 * near): the distance between the position boxes (the root of their
 * gaps' squares along the axes) is at most their points', and the
 * Minkowski difference of the motion boxes bounds their relative motion.
 * Two parts of a cloth that move together, whose boxes of the step overlap
 * by as much as they move, are tested as if at rest. The boxes' distance
 * rather than their largest gap along an axis (up to 1.7 times less, for
 * a square beside a node diagonally): 2.6 % fewer instructions in the
 * peers' table's first 0.25 s at 25^2 under bdf2 (callgrind), the same
 * pairs. Shrunk by a part in 1e12, so that no pair the contacts' own
 * test would keep (contacts.c, its distance rounded otherwise) is lost.
 */
static int
near_overlap(const double *pa, const double *ma, const double *pb, const double *mb, double near,
    double share)
{
	double gap = 0, m2 = 0, r;
	int k;

	for (k = 0; k < 3; k++) {
		double g1 = pb[k] - pa[3 + k], g2 = pa[k] - pb[3 + k], g = g1 > g2 ? g1 : g2;

		if (g > 0)
			gap += g * g;
	}
	gap = sqrt(gap) * (1 - 1e-12);
	/* boxes within reach at the start, as neighbours in a cloth are at
	 * every level of the trees: no need of the motion */
	if ((r = gap - near) <= 0)
		return 1;
	for (k = 0; k < 3; k++) {
		double lo = ma[k] - mb[3 + k], hi = ma[3 + k] - mb[k];
		double m = -lo > hi ? -lo : hi;

		m2 += m * m;
	}
	return r * r <= share * share * m2;
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
	free(b->bvh.nnear);
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

/* Every pair of leaves, one under x and one under y (x == y: a subtree
 * against itself, each pair of distinct leaves once), whose boxes overlap.
 * The stack of node pairs grows before each pop's at most three pushes. */
int
bvh_traverse(struct broad *b, const struct geom *g, const struct broad_want *want, int x, int y)
{
	size_t top = 0;
	long visits = 0;
	int *st;

	if (grow_array((void **)&b->bvh.stack, &b->bvh.stackcap, 8, sizeof *b->bvh.stack) != 0)
		return -1;
	st = b->bvh.stack;
	st[top++] = x;
	st[top++] = y;
	while (top > 0) {
		const struct bvh_node *p, *q;

		if (top + 6 > b->bvh.stackcap) {
			if (grow_array((void **)&b->bvh.stack, &b->bvh.stackcap, top + 6, sizeof *b->bvh.stack) != 0)
				return -1;
			st = b->bvh.stack;
		}
		y = st[--top];
		x = st[--top];
		p = &b->bvh.node[x];
		q = &b->bvh.node[y];
		if (stop_poll(++visits, b->stop))
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
			if (bvh_leaf(p))
				continue;	/* one triangle: nothing */
			if (b->bvh.cull_on && p->patch && bvh_patch_flat(b, g, p)) {
				if (bvh_push_cull(b, x) != 0)
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
		/* the near test of two subtrees holds for any pair of leaves
		 * under them that passes it: their boxes of positions and of
		 * motions hold the leaves', so the gap is no larger and the
		 * relative motion no smaller (and rounding is monotone). A
		 * cloth that moves as a whole, as it falls, has its subtrees
		 * within reach only where they are a thickness apart, where
		 * their boxes of the motion meet wherever it moved by more
		 * than a spacing: at 100^2 a step's contacts were 0.3 % of
		 * the 555,000 pairs those boxes gave, and their traversal and
		 * test two fifths of the run (bench/fast.sh). */
		if (want->near > 0 && !near_overlap(b->bvh.nnear + 12 * x, b->bvh.nnear + 12 * x + 6,
		    b->bvh.nnear + 12 * y, b->bvh.nnear + 12 * y + 6, want->near, want->near_motion))
			continue;
		if (bvh_leaf(p) && bvh_leaf(q)) {
			if (bvh_leaves(b, g, want, p->tri, b->bvh.leaf_tbox ? b->bvh.tbox + 6 * p->tri : p->box,
			    q->tri, b->bvh.leaf_tbox ? b->bvh.tbox + 6 * q->tri : q->box) != 0)
				return -1;
		} else if (bvh_leaf(q) || (!bvh_leaf(p) && p->size >= q->size)) {
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
int
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
void
bvh_tri_box(double *bx, const struct broad *b, const struct geom *g, int t)
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
void
bvh_refit(struct broad *b, const struct geom *g)
{
	int i;

	for (i = b->bvh.nnodes - 1; i >= 0; i--) {
		struct bvh_node *n = &b->bvh.node[i];

		if (bvh_leaf(n)) {
			bvh_tri_box(n->box, b, g, n->tri);
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

/* Each tree node's boxes of positions and motions (nnear), from its
 * triangles' (tnear): children after parents, from the last node back. */
static void
near_nodes(struct broad *b)
{
	int i, k;

	for (i = b->bvh.nnodes - 1; i >= 0; i--) {
		const struct bvh_node *n = &b->bvh.node[i];
		double *o = b->bvh.nnear + 12 * i;

		if (bvh_leaf(n)) {
			memcpy(o, b->bvh.tnear + 12 * n->tri, 12 * sizeof *o);
			continue;
		}
		box_empty(o);
		box_empty(o + 6);
		for (k = 0; k < 2; k++) {
			const double *c = b->bvh.nnear + 12 * (k ? n->right : n->left);

			box_add(o, c);
			box_add(o, c + 3);
			box_add(o + 6, c + 6);
			box_add(o + 6, c + 9);
		}
	}
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
	int v, k;
	size_t e, t;

	if (bvh_prepare(b, g) != 0 ||
	    grow_array((void **)&b->allowed, &b->allowedcap, 6 * (size_t)g->nv, sizeof *b->allowed) != 0 ||
	    grow_array((void **)&b->bvh.qbox, &b->bvh.qboxcap, 6 * (size_t)g->nv, sizeof *b->bvh.qbox) != 0 ||
	    grow_array((void **)&b->bvh.ebox, &b->bvh.eboxcap, 6 * (g->nedges + 1), sizeof *b->bvh.ebox) != 0)
		return -1;
	b->st.cell = cell;
	bvh_fill_query_boxes(b, g, want, 0);
	if (want->near > 0) {
		if (grow_array((void **)&b->bvh.vnear, &b->bvh.vnearcap, 6 * (size_t)g->nv, sizeof *b->bvh.vnear) != 0 ||
		    grow_array((void **)&b->bvh.enear, &b->bvh.enearcap, 12 * (g->nedges + 1), sizeof *b->bvh.enear) != 0 ||
		    grow_array((void **)&b->bvh.tnear, &b->bvh.tnearcap, 12 * (g->ntri + 1), sizeof *b->bvh.tnear) != 0)
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
	if (want->near > 0) {
		if (grow_array((void **)&b->bvh.nnear, &b->bvh.nnearcap, 12 * (size_t)b->bvh.nnodes,
		    sizeof *b->bvh.nnear) != 0)
			return -1;
		near_nodes(b);
	}
	if (bvh_cull_prepare(b, g, want) != 0)
		return -1;
	if (bvh_held_find(b, g, want, cell) != 0)
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
			rc = bvh_push_cull(b, old[i]);
			continue;
		}
		for (j = p->first; j < p->first + p->count; j++)
			bvh_tri_deform(b, g, b->bvh.leaf_tri[j], 1);
		bvh_node_sums(b, old[i], old[i] + 2 * p->count - 1);
		if (bvh_patch_flat(b, g, p)) {
			rc = bvh_push_cull(b, old[i]);
			continue;
		}
		/* its pairs: found in a tree that holds this search's boxes.
		 * A search served by the held pairs left the tree with the held
		 * boxes, which a dirty vertex's may exceed (its pairs came from
		 * queries, which left this patch out): refit it, and let the
		 * next search traverse, as the held pairs' queries need the
		 * held boxes. A fold is rare; this costs a traversal when one
		 * comes. */
		if (!boxes && bvh_fill_tri_boxes(b, g) != 0) {
			rc = -1;
			break;
		}
		boxes = true;
		if (!b->bvh.tree_covers) {
			bvh_refit(b, g);
			b->bvh.tree_covers = true;
			b->bvh.held_valid = false;
		}
		rc = bvh_judge_patch(b, g, &b->bvh.cull_want, old[i]);
		given |= rc == 0;
	}
	free(old);
	if (rc >= 0 && given && bvh_sort(b, g) != 0)
		rc = -1;
	if (rc < 0) {
		b->stopped = stop_set(b->stop);
		return -1;
	}
	if (given)
		bvh_unique_pairs(b);
	return given;
}

