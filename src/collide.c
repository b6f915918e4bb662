/* collide.c: the collision stages of a step, in the order of the chapter's
 * §4: broad phase, narrow phase, response, obstacles; and the step's
 * events and statistics. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "collide_impl.h"
#include "grow.h"

/* Self-contact or obstacle meshes: the broad phase has pairs to find. */
double
collide_default_memory(void)
{
	long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);

	/* half the machine; 4 GB where it cannot tell */
	return pages > 0 && size > 0 ? 0.5 * (double)pages * (double)size : 4e9;
}

/* ccd tests every vertex (the meshes' too) against the triangles, and the
 * edges against each other; the seed test draws segments to each node
 * from its neighbours, and the node's box must hold them. */
struct broad_want
collide_broad_want(enum narrow_mode narrow, bool self)
{
	bool ccd = narrow == NARROW_CCD;

	return (struct broad_want){ .self = self, .edges = ccd, .mesh_vertices = ccd,
	    .neighbour_paths = !ccd };
}

int
collide_init(struct collide *c, const struct scene *sc, const struct cloth *cl,
    const unsigned char *held, double dt, double vmax, struct drape_err *err)
{
	memset(c, 0, sizeof *c);
	c->opt = sc->col;
	c->obst = sc->obstacles;
	c->nobst = sc->nobstacles;
	c->pad = 2;
	c->slide_gap = INFINITY;
	c->pairs = collide_broad_runs(sc);
	c->active = collide_active(sc);
	if ((c->br = broad_new(c->opt.broad)) == NULL) {
		err_set(err, "%s: out of memory", sc->path);
		return -1;
	}
	broad_set_memory_limit(c->br, c->opt.memory > 0 ? c->opt.memory : collide_default_memory());
	if (!c->active)
		return 0;
	if (collide_build_geometry(c, cl, held) != 0) {
		collide_free(c);
		err_set(err, "%s: out of memory", sc->path);
		return -1;
	}
	/* eq. 21: L_ce > V_max dt, and comparable with the triangles (§3.3);
	 * the grid's cost, not its answer, depends on it */
	c->cell = c->opt.cell > 0 ? c->opt.cell :
	    c->opt.broad == BROAD_SEED ? fmax(cl->h, 1.5 * vmax * dt) : cl->h;
	return 0;
}

void
collide_free(struct collide *c)
{
	broad_free(c->br);
	free(c->x0);
	free(c->x1);
	free(c->v1);
	free(c->tri);
	free(c->edge);
	free(c->vtri_start);
	free(c->vtri);
	free(c->vedge_start);
	free(c->vedge);
	free(c->tri_obstacle);
	free(c->tri_square);
	free(c->uv);
	free(c->fixed);
	free(c->inv_mass);
	free(c->changed);
	free(c->changed_next);
	free(c->frozen);
	free(c->box);
	free(c->ev);
	memset(c, 0, sizeof *c);
}

void
collide_set_pad(struct collide *c, double pad)
{
	c->pad = pad;
}

void
collide_set_slide_gap(struct collide *c, double gap)
{
	c->slide_gap = gap;
}

void
collide_set_stop(struct collide *c, const volatile sig_atomic_t *flag)
{
	c->stop = flag;
}

/* Whether the boxes of the pair's two sides overlap: each vertex's box of
 * the step (collide_candidates: its predicted path, widened), a side's the
 * union of its vertices'. Every broad phase finds at least the pairs whose
 * boxes overlap, some more (grid: whatever shares a cube); the pairs kept
 * are those in reach among these, so that which broad phase found them
 * does not change the run. */
static bool
boxes_overlap(const struct collide *c, const struct collide_pair *cp)
{
	int first = cp->other >= 0 ? 1 : 2, k, a;
	double lo[2][3], hi[2][3];

	for (k = 0; k < 4; k++) {
		const double *b = c->box + 6 * (size_t)cp->vert[k];
		int side = k >= first;

		for (a = 0; a < 3; a++) {
			if (k == 0 || k == first) {
				lo[side][a] = b[a];
				hi[side][a] = b[3 + a];
			} else {	/* not fmin and fmax: library calls */
				lo[side][a] = b[a] < lo[side][a] ? b[a] : lo[side][a];
				hi[side][a] = b[3 + a] > hi[side][a] ? b[3 + a] : hi[side][a];
			}
		}
	}
	for (a = 0; a < 3; a++)
		if (lo[0][a] > hi[1][a] || lo[1][a] > hi[0][a])
			return false;
	return true;
}

/* A mesh vertex's obstacle: that of its first triangle. */
static int
vertex_obstacle(const struct collide *c, int v)
{
	return c->tri_obstacle[c->vtri[c->vtri_start[v]]];
}

/* The pair to fn, unless a broad phase whose pairs are exactly those
 * whose boxes overlap (bvh) found it: no test again, it was 5 % of a fast
 * run's instructions. */
static int
each_pair_one(const struct collide *c, struct collide_pair *p,
    int (*fn)(void *ctx, const struct collide_pair *p), void *ctx)
{
	if (!broad_boxes_exact(c->opt.broad) && !boxes_overlap(c, p))
		return 0;
	p->mu = collide_friction(c, p->obstacle).mu;
	return fn(ctx, p);
}

int
collide_each_pair(const struct collide *c, int (*fn)(void *ctx, const struct collide_pair *p),
    void *ctx)
{
	size_t i, nvt, nee;
	const struct vt_pair *vt = broad_vt(c->br, &nvt);
	const struct ee_pair *ee = broad_ee(c->br, &nee);
	int rc;

	for (i = 0; i < nvt; i++) {
		int v = vt[i].v, t = vt[i].t, obst = c->tri_obstacle[t];
		struct collide_pair p;

		if (stop_poll(i, c->stop))
			return 1;
		if (obst < 0 && v < c->ncloth && !c->opt.self)
			continue;
		if (v >= c->ncloth && obst >= 0)
			continue;	/* both the meshes' */
		if (v >= c->ncloth)
			obst = vertex_obstacle(c, v);
		p = (struct collide_pair){ .vert = { v, c->tri[3 * t], c->tri[3 * t + 1],
		    c->tri[3 * t + 2] }, .other = t, .obstacle = obst };
		if ((rc = each_pair_one(c, &p, fn, ctx)) != 0)
			return rc;
	}
	for (i = 0; i < nee; i++) {
		const int *a = c->edge + 2 * ee[i].a, *b = c->edge + 2 * ee[i].b;
		int obst = -1;
		struct collide_pair p;

		if (stop_poll(i, c->stop))
			return 1;
		if (b[0] >= c->ncloth)
			obst = vertex_obstacle(c, b[0]);
		else if (a[0] >= c->ncloth)
			obst = vertex_obstacle(c, a[0]);
		if (obst < 0 && !c->opt.self)
			continue;
		p = (struct collide_pair){ .vert = { a[0], a[1], b[0], b[1] }, .other = -1 - ee[i].b,
		    .obstacle = obst };
		if ((rc = each_pair_one(c, &p, fn, ctx)) != 0)
			return rc;
	}
	return 0;
}

int
collide_add_event(struct collide *c, long step, int node, enum contact_type type, int other,
    int obstacle, vec3 q, vec3 n, double vn_before, double vn_after)
{
	struct contact_event *e;

	if (grow_array((void **)&c->ev, &c->evcap, c->nev + 1, sizeof *c->ev) != 0)
		return -1;
	e = &c->ev[c->nev++];
	*e = (struct contact_event){ step, node, type, other, obstacle, q, n, vn_before, vn_after };
	c->st.n[STAT_CONTACTS + type]++;
	c->st.n[STAT_CORRECTIONS]++;
	return 0;
}

struct friction
collide_friction(const struct collide *c, int obstacle)
{
	struct friction f = { c->opt.friction, c->opt.viscous };

	if (obstacle >= 0)
		f.mu = c->obst[obstacle].friction;
	return f;
}

void
collide_begin(struct collide *c)
{
	c->nev = 0;
	c->stopped = false;
	broad_set_stop(c->br, c->stop);
	memset(&c->st, 0, sizeof c->st);
}

/* The pairs for the motion from y0 over h at its velocities: each node's
 * box from x to x + h v, widened by margin. */
int
collide_candidates(struct collide *c, const double *y0, double h, double margin, double share,
    double near, double near_motion, struct drape_err *err)
{
	size_t n3 = 3 * (size_t)c->ncloth, k;
	struct broad_want want = collide_broad_want(NARROW_CCD, c->opt.self);
	int v;

	want.near = near;
	want.near_motion = near_motion;

	broad_set_stop(c->br, c->stop);
	if (!c->active || !c->pairs) {
		broad_clear(c->br);
		return 0;
	}
	memcpy(c->x0, y0, n3 * sizeof *c->x0);
	for (k = 0; k < n3; k++)
		c->x1[k] = y0[k] + h * y0[n3 + k];
	for (v = 0; v < c->ncloth; v++) {
		double *b = c->box + 6 * v;
		double m = margin + share * v3_len(v3_sub(X1(c, v), X0(c, v)));

		for (k = 0; k < 3; k++) {
			b[k] = fmin(c->x0[3 * v + k], c->x1[3 * v + k]) - m;
			b[3 + k] = fmax(c->x0[3 * v + k], c->x1[3 * v + k]) + m;
		}
	}
	c->g.vbox = c->box;
	if (broad_find(c->br, &c->g, c->cell, &want, err) != 0) {
		c->stopped = broad_stopped(c->br);
		return -1;
	}
	return 0;
}

int
collide_step(struct collide *c, long step, double dt, const double *y0, double *y1,
    struct drape_err *err)
{
	int r;

	collide_begin(c);
	if ((r = collide_check(c, step, dt, y0, y1, err)) == 0)
		collide_end(c);
	return r;
}

void
collide_end(struct collide *c)
{
	stats_add(&c->total, &c->st);
}

int
collide_check(struct collide *c, long step, double dt, const double *y0, double *y1,
    struct drape_err *err)
{
	size_t n3 = 3 * (size_t)c->ncloth, k;
	double pad = 0;
	int v;

	if (!c->active)
		return 0;
	memcpy(c->x0, y0, n3 * sizeof *c->x0);
	c->v0 = y0 + n3;
	memcpy(c->x1, y1, n3 * sizeof *c->x1);
	memcpy(c->v1, y1 + n3, n3 * sizeof *c->v1);
	/* ccd: where each node may go this step. A correction moves a node by
	 * at most the relative motion of the two sides, so the swept box
	 * widened by twice the step's largest motion holds every correction
	 * but the rare one clamp_box cuts short, and the broad phase's pairs
	 * hold for every path inside it. */
	for (v = 0; c->opt.narrow == NARROW_CCD && v < c->ncloth; v++)
		pad = fmax(pad, v3_len(v3_sub(X1(c, v), X0(c, v))));
	pad *= c->pad;
	for (v = 0; c->opt.narrow == NARROW_CCD && v < c->ncloth; v++) {
		double *b = c->box + 6 * v;

		for (k = 0; k < 3; k++) {
			b[k] = fmin(c->x0[3 * v + k], c->x1[3 * v + k]) - pad;
			b[3 + k] = fmax(c->x0[3 * v + k], c->x1[3 * v + k]) + pad;
		}
	}
	c->g.vbox = c->opt.narrow == NARROW_CCD ? c->box : NULL;
	if (c->pairs) {
		struct broad_want want = collide_broad_want(c->opt.narrow, c->opt.self);
		const struct broad_stats *bs = broad_stats(c->br);

		if (broad_find(c->br, &c->g, c->cell, &want, err) != 0) {
			c->stopped = broad_stopped(c->br);
			return -1;
		}
		/* summed over a step's checks (the fast path's windows) */
		c->st.n[STAT_NODE_PAIRS] += bs->node_pairs;
		c->st.n[STAT_VT_PAIRS] += bs->vt_pairs;
		c->st.n[STAT_EE_PAIRS] += bs->ee_pairs;
		c->st.n[STAT_FILLS] += bs->rebuilt;
		c->st.cell = bs->cell;
		c->st.hash = bs->hash;
	}
	if (c->opt.narrow == NARROW_SEED) {
		memset(c->changed, 0, (size_t)c->nv);
		if (c->pairs && collide_seed_pass(c, step, dt, c->changed) != 0)
			goto oom;
		/* §4: the obstacles, for the nodes with no self-contact */
		for (v = 0; v < c->ncloth; v++)
			if (!c->changed[v] && !c->fixed[v] &&
			    collide_obstacles_node(c, step, dt, v, false) < 0)
				goto oom;
		c->st.n[STAT_PASSES] = c->st.n[STAT_PASSES] > 1 ? c->st.n[STAT_PASSES] : 1;
	} else if (collide_ccd_passes(c, step, dt) != 0) {
		goto oom;
	}
	if (c->stopped) {
		err_set(err, "collisions: stopped by a signal");
		return -1;
	}
	memcpy(y1, c->x1, n3 * sizeof *y1);
	memcpy(y1 + n3, c->v1, n3 * sizeof *y1);
	return 0;
oom:
	err_set(err, "collisions: out of memory");
	return -1;
}
