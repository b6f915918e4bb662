/* broad_held.c: bvh's held pairs: a traversal's pairs kept with the
 * boxes they were found for, from which a later search takes those of
 * the vertices still inside and looks up only the others (a Verlet list). */
#include <limits.h>

#include "broad_impl.h"

/*
 * ---- held pairs ----
 *
 * A traversal of a cloth against itself costs the same whatever the
 * motion: its neighbours in the plane overlap at every level of the tree
 * (some 40,000 node pairs a traversal on the tablecloth). Yet from one
 * search to the next most vertices' boxes barely move: the slow
 * integrators' steps are short (the search for a step's contacts, with a
 * near test, traverses on its own: near_traversal). So a traversal is
 * made with every vertex's box widened by a skin, and its pairs held with
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

	if (grow_array((void **)&b->bvh.stack, &b->bvh.stackcap, 8, sizeof *b->bvh.stack) != 0)
		return -1;
	if (b->bvh.cloth_root >= 0)
		b->bvh.stack[top++] = b->bvh.cloth_root;
	if (b->bvh.mesh_root >= 0)
		b->bvh.stack[top++] = b->bvh.mesh_root;
	while (top > 0) {
		const struct bvh_node *p = &b->bvh.node[b->bvh.stack[--top]];

		if (!box_overlap(p->box, bx))
			continue;
		if (bvh_leaf(p)) {
			if (n == b->bvh.foundcap &&
			    grow_array((void **)&b->bvh.found, &b->bvh.foundcap, n + 1, sizeof *b->bvh.found) != 0)
				return -1;
			b->bvh.found[n++] = p->tri;
			continue;
		}
		if (top + 2 > b->bvh.stackcap &&
		    grow_array((void **)&b->bvh.stack, &b->bvh.stackcap, top + 2, sizeof *b->bvh.stack) != 0)
			return -1;
		b->bvh.stack[top++] = p->left;
		b->bvh.stack[top++] = p->right;
	}
	return (long)n;
}

/* Each triangle's box of this search. */
int
bvh_fill_tri_boxes(struct broad *b, const struct geom *g)
{
	size_t t;

	if (grow_array((void **)&b->bvh.tbox, &b->bvh.tboxcap, 6 * (g->ntri + 1), sizeof *b->bvh.tbox) != 0)
		return -1;
	for (t = 0; t < g->ntri; t++)
		bvh_tri_box(b->bvh.tbox + 6 * t, b, g, (int)t);
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

	if (grow_array((void **)&b->bvh.dlist, &b->bvh.dlistcap, (size_t)g->nv + g->ntri + g->nedges + 1,
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
		if (stop_poll(j, b->stop))
			return -1;
		if (held_query_triangle(b, g, want, dt[j]) != 0)
			return -1;
	}
	for (i = 0; i < ne; i++) {
		if (stop_poll(i, b->stop))
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
void
bvh_unique_pairs(struct broad *b)
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
int
bvh_judge_patch(struct broad *b, const struct geom *g, const struct broad_want *want, int x)
{
	bool saved = b->bvh.leaf_tbox;
	int rc;

	if (bvh_patch_flat(b, g, &b->bvh.node[x]))
		return bvh_push_cull(b, x) != 0 ? -1 : 1;
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

	if (bvh_leaf(p))
		return 0;
	if (b->bvh.held_mark[x]) {
		rc = bvh_judge_patch(b, g, want, x);
		*given |= rc == 0;
		return rc < 0 ? -1 : 0;
	}
	if (p->patch && bvh_patch_flat(b, g, p))
		return bvh_push_cull(b, x);
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
	if (bvh_fill_tri_boxes(b, g) != 0)
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
		bvh_unique_pairs(b);
	return 0;
}

/* A search's pairs from the held ones: 0, 1 when too many vertices left
 * their boxes, -1 out of memory or stopped. */
static int
find_held(struct broad *b, const struct geom *g, const struct broad_want *want)
{
	int v, ndirty = 0;

	if (grow_array((void **)&b->bvh.dirty, &b->bvh.dirtycap, (size_t)g->nv, 1) != 0)
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
void
bvh_fill_query_boxes(struct broad *b, const struct geom *g, const struct broad_want *want,
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
/* Both trees against the cloth's for want, refitted to its boxes (qbox,
 * ebox), the pairs sorted: 0, or -1 out of memory or stopped. */
static int
traverse_trees(struct broad *b, const struct geom *g, const struct broad_want *want)
{
	bvh_refit(b, g);
	b->nvt = b->nee = 0;
	if (b->bvh.cloth_root >= 0 && want->self &&
	    bvh_traverse(b, g, want, b->bvh.cloth_root, b->bvh.cloth_root) != 0)
		return -1;
	if (b->bvh.cloth_root >= 0 && b->bvh.mesh_root >= 0 &&
	    bvh_traverse(b, g, want, b->bvh.cloth_root, b->bvh.mesh_root) != 0)
		return -1;
	return bvh_sort(b, g);
}

/* for a search with no near test (near_traversal has those) */
static int
hold_traversal(struct broad *b, const struct geom *g, const struct broad_want *want,
    double skin)
{
	size_t e;

	if (!b->bvh.held_valid)
		skin = 0;
	else if (b->bvh.held_skin > 0 ? b->bvh.held_uses < HELD_SKIN_USES : b->bvh.held_uses > 0)
		skin = 0;
	b->bvh.held_valid = false;
	b->bvh.held_skin = skin;
	b->bvh.held_uses = 0;
	bvh_fill_query_boxes(b, g, want, skin);
	if (traverse_trees(b, g, want) != 0 ||
	    grow_pairs(b, (void **)&b->bvh.held_vt, &b->bvh.held_vtcap, b->nvt + 1, sizeof *b->vt) != 0 ||
	    grow_pairs(b, (void **)&b->bvh.held_ee, &b->bvh.held_eecap, b->nee + 1, sizeof *b->ee) != 0 ||
	    grow_array((void **)&b->bvh.held_box, &b->bvh.held_boxcap, 6 * (size_t)g->nv,
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
	if (grow_array((void **)&b->bvh.held_cull, &b->bvh.held_cullcap, b->bvh.ncull + 1, sizeof *b->bvh.held_cull) != 0)
		return -1;
	if (b->bvh.ncull > 0)
		memcpy(b->bvh.held_cull, b->bvh.cull, b->bvh.ncull * sizeof *b->bvh.cull);
	b->bvh.held_ncull = b->bvh.ncull;
	if (b->bvh.held_mark != NULL) {
		memset(b->bvh.held_mark, 0, (size_t)b->bvh.nnodes);
		for (e = 0; e < b->bvh.ncull; e++)
			b->bvh.held_mark[b->bvh.cull[e]] = 1;
	}
	b->bvh.held_want = *want;
	b->bvh.held_nv = g->nv;
	b->bvh.held_valid = true;
	if (skin == 0)
		return 0;	/* the pairs found are the search's */
	/* the search's own from the skinned ones: none is out of its box */
	bvh_fill_query_boxes(b, g, want, 0);
	if (grow_array((void **)&b->bvh.dirty, &b->bvh.dirtycap, (size_t)g->nv, 1) != 0)
		return -1;
	memset(b->bvh.dirty, 0, (size_t)g->nv);
	return take_held(b, g, want, 0, false);
}

/*
 * A traversal with the near test on the way down (bvh_traverse), its
 * pairs not held: a step's contacts (contacts.h) are those of its
 * predicted motion within reach. Held, they served the step's check,
 * whose boxes lie inside theirs; but they had to be every pair of the
 * motion's boxes, and a cloth that lands fast, whose nodes move by a
 * spacing or two a window, gives hundreds of pairs a node for a few
 * within reach: at 100^2 nodes (the peers' table, first 0.25 s) 555,000
 * pairs a window, 0.3 % of them kept, their traversal, sorting, test and
 * the check's taking of its own from them three fifths of the run. The
 * check now traverses for its own boxes, which hold few pairs.
 */
static int
near_traversal(struct broad *b, const struct geom *g, const struct broad_want *want)
{
	b->bvh.held_valid = false;	/* the tree takes this search's boxes */
	bvh_fill_query_boxes(b, g, want, 0);
	return traverse_trees(b, g, want);
}

int
bvh_held_find(struct broad *b, const struct geom *g, const struct broad_want *want, double cell)
{
	int rc = 1;

	if (held_serves(b, g, want))
		rc = find_held(b, g, want);
	b->bvh.tree_covers = rc == 1;	/* a traversal refits the tree */
	if (rc == 1)
		rc = want->near > 0 ? near_traversal(b, g, want) :
		    hold_traversal(b, g, want, HELD_SKIN * cell);
	return rc != 0 ? -1 : 0;
}
