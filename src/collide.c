/* collide.c: the collision stages of a step, in the order of the chapter's
 * §4: broad phase, narrow phase, response, obstacles. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ccd.h"
#include "collide.h"

#define FAILSAFE_PASS 5		/* ccd: from this pass on, a hit node goes back to step k */

static void *
xcalloc(size_t n, size_t size)
{
	return calloc(n ? n : 1, size);
}

/* vertex -> items incidence, compressed (each item has `per` vertices) */
static int
incidence(const int *items, size_t nitems, int per, int nv, int **start, int **list)
{
	size_t i;
	int k, *fill;

	if ((*start = xcalloc((size_t)nv + 1, sizeof **start)) == NULL ||
	    (*list = xcalloc(nitems * (size_t)per, sizeof **list)) == NULL ||
	    (fill = xcalloc((size_t)nv, sizeof *fill)) == NULL)
		return -1;
	for (i = 0; i < nitems * (size_t)per; i++)
		(*start)[items[i] + 1]++;
	for (k = 0; k < nv; k++)
		(*start)[k + 1] += (*start)[k];
	for (i = 0; i < nitems; i++)
		for (k = 0; k < per; k++) {
			int v = items[i * (size_t)per + (size_t)k];

			(*list)[(*start)[v] + fill[v]++] = (int)i;
		}
	free(fill);
	return 0;
}

static int
cmp_edge(const void *pa, const void *pb)
{
	const int *a = pa, *b = pb;

	if (a[0] != b[0])
		return a[0] < b[0] ? -1 : 1;
	return (a[1] > b[1]) - (a[1] < b[1]);
}

/* The cloth's triangles and edges, then each obstacle mesh's, renumbered. */
static int
build_geometry(struct collide *c, const struct cloth *cl, const unsigned char *held)
{
	size_t o, t, nt = cl->ntri, ne = cl->nedges;
	int nv = cl->n, k;

	for (o = 0; o < c->nobst; o++)
		if (c->obst[o].kind == OBSTACLE_MESH) {
			nv += c->obst[o].mesh.nverts;
			nt += c->obst[o].mesh.ntri;
			ne += 3 * c->obst[o].mesh.ntri;	/* before removing repeats */
		}
	c->ncloth = cl->n;
	c->nv = nv;
	c->ntri_cloth = cl->ntri;
	if ((c->x0 = xcalloc(3 * (size_t)nv, sizeof *c->x0)) == NULL ||
	    (c->x1 = xcalloc(3 * (size_t)nv, sizeof *c->x1)) == NULL ||
	    (c->v1 = xcalloc(3 * (size_t)nv, sizeof *c->v1)) == NULL ||
	    (c->tri = xcalloc(3 * nt, sizeof *c->tri)) == NULL ||
	    (c->edge = xcalloc(2 * ne, sizeof *c->edge)) == NULL ||
	    (c->tri_obstacle = xcalloc(nt, sizeof *c->tri_obstacle)) == NULL ||
	    (c->fixed = xcalloc((size_t)nv, 1)) == NULL ||
	    (c->inv_mass = xcalloc((size_t)nv, sizeof *c->inv_mass)) == NULL ||
	    (c->changed = xcalloc((size_t)nv, 1)) == NULL ||
	    (c->changed_next = xcalloc((size_t)nv, 1)) == NULL ||
	    (c->frozen = xcalloc((size_t)nv, 1)) == NULL ||
	    (c->box = xcalloc(6 * (size_t)nv, sizeof *c->box)) == NULL)
		return -1;
	memcpy(c->tri, cl->tri, 3 * cl->ntri * sizeof *c->tri);
	memcpy(c->edge, cl->edge, 2 * cl->nedges * sizeof *c->edge);
	for (t = 0; t < cl->ntri; t++)
		c->tri_obstacle[t] = -1;
	for (k = 0; k < cl->n; k++) {
		c->fixed[k] = held != NULL && held[k];
		c->inv_mass[k] = c->fixed[k] || !(cl->mass[k] > 0) ? 0 : 1 / cl->mass[k];
	}
	c->ntri = cl->ntri;
	c->nedges = cl->nedges;
	nv = cl->n;
	for (o = 0; o < c->nobst; o++) {
		const struct mesh *m = &c->obst[o].mesh;
		size_t first_edge = c->nedges, i, kept;

		if (c->obst[o].kind != OBSTACLE_MESH)
			continue;
		memcpy(c->x0 + 3 * (size_t)nv, m->x, 3 * (size_t)m->nverts * sizeof *m->x);
		memcpy(c->x1 + 3 * (size_t)nv, m->x, 3 * (size_t)m->nverts * sizeof *m->x);
		for (k = 0; k < m->nverts; k++)
			c->fixed[nv + k] = 1;
		for (t = 0; t < m->ntri; t++) {
			for (k = 0; k < 3; k++) {
				int a = nv + m->tri[3 * t + (size_t)k];
				int b = nv + m->tri[3 * t + (size_t)(k + 1) % 3];

				c->tri[3 * c->ntri + (size_t)k] = a;
				c->edge[2 * c->nedges] = a < b ? a : b;
				c->edge[2 * c->nedges + 1] = a < b ? b : a;
				c->nedges++;
			}
			c->tri_obstacle[c->ntri++] = (int)o;
		}
		/* a closed mesh has each edge twice */
		qsort(c->edge + 2 * first_edge, c->nedges - first_edge, 2 * sizeof *c->edge, cmp_edge);
		for (i = kept = first_edge; i < c->nedges; i++)
			if (kept == first_edge || cmp_edge(c->edge + 2 * i, c->edge + 2 * (kept - 1)) != 0) {
				c->edge[2 * kept] = c->edge[2 * i];
				c->edge[2 * kept + 1] = c->edge[2 * i + 1];
				kept++;
			}
		c->nedges = kept;
		nv += m->nverts;
	}
	if (incidence(c->tri, c->ntri, 3, c->nv, &c->vtri_start, &c->vtri) != 0 ||
	    incidence(c->edge, c->nedges, 2, c->nv, &c->vedge_start, &c->vedge) != 0)
		return -1;
	for (k = c->ncloth; k < c->nv; k++)	/* obstacle vertices stay put */
		for (t = 0; t < 6; t++)
			c->box[6 * k + t] = c->x0[3 * k + t % 3];
	c->g = (struct geom){ c->nv, c->ncloth, c->x0, c->x1, c->tri, c->ntri, c->edge,
	    c->nedges, c->vtri_start, c->vtri, c->vedge_start, c->vedge, c->fixed, NULL };
	return 0;
}

int
collide_init(struct collide *c, const struct scene *sc, const struct cloth *cl,
    const unsigned char *held, double dt, double vmax, struct drape_err *err)
{
	size_t o;
	bool meshes = false;

	memset(c, 0, sizeof *c);
	c->opt = sc->col;
	c->obst = sc->obstacles;
	c->nobst = sc->nobstacles;
	for (o = 0; o < c->nobst; o++)
		meshes |= c->obst[o].kind == OBSTACLE_MESH;
	c->pairs = c->opt.self || meshes;
	c->active = c->pairs || c->nobst > 0;
	broad_init(&c->br, c->opt.broad);
	if (!c->active)
		return 0;
	if (build_geometry(c, cl, held) != 0) {
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
	broad_free(&c->br);
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
	free(c->fixed);
	free(c->inv_mass);
	free(c->changed);
	free(c->changed_next);
	free(c->frozen);
	free(c->box);
	free(c->ev);
	memset(c, 0, sizeof *c);
}

static vec3 X0(const struct collide *c, int v) { return v3_load(c->x0 + 3 * v); }
static vec3 X1(const struct collide *c, int v) { return v3_load(c->x1 + 3 * v); }
static vec3 V1(const struct collide *c, int v) { return v3_load(c->v1 + 3 * v); }

static int
add_event(struct collide *c, long step, int node, enum contact_type type, int other,
    int obstacle, vec3 q, vec3 n, double vn_before, double vn_after)
{
	struct contact_event *e;

	if (c->nev == c->evcap) {
		size_t cap = c->evcap ? 2 * c->evcap : 64;
		struct contact_event *ne = realloc(c->ev, cap * sizeof *ne);

		if (ne == NULL)
			return -1;
		c->ev = ne;
		c->evcap = cap;
	}
	e = &c->ev[c->nev++];
	*e = (struct contact_event){ step, node, type, other, obstacle, q, n, vn_before, vn_after };
	c->st.contacts[type]++;
	c->st.corrections++;
	return 0;
}

static struct friction
friction_of(const struct collide *c, int obstacle)
{
	struct friction f = { c->opt.friction, c->opt.viscous };

	if (obstacle >= 0)
		f.mu = c->obst[obstacle].friction;
	return f;
}

/* Keeps a corrected position inside the node's box of this step (its swept
 * box, widened: see collide_step), so that the broad phase's pairs still
 * cover it. */
static vec3
clamp_box(const struct collide *c, int v, vec3 p)
{
	const double *b = c->box + 6 * v;

	return v3(fmin(fmax(p.x, b[0]), b[3]), fmin(fmax(p.y, b[1]), b[4]),
	    fmin(fmax(p.z, b[2]), b[5]));
}

/*
 * The position policy of §3.2 for node v hit along n: keep step k's
 * position (the chapter's choice, after Volino et al.), move to Q, or slide:
 * step k's offset along n plus the surface's own normal motion dqn, with
 * this step's tangential motion (the chapter notes that keeping the whole
 * position can lock a node that should slide).
 */
static vec3
place(const struct collide *c, int v, vec3 q, vec3 n, double dqn)
{
	vec3 p0 = X0(c, v), d = v3_sub(X1(c, v), p0);

	switch (c->opt.position) {
	case POSITION_Q:
		return q;
	case POSITION_SLIDE:
		return v3_madd(v3_add(p0, v3_madd(d, n, -v3_dot(d, n))), n, dqn);
	default:
		return p0;
	}
}

/* Node v corrected against a surface point q moving at vq. */
static int
correct_node(struct collide *c, long step, double dt, int v, enum contact_type type, int other,
    int obstacle, vec3 q, vec3 n, vec3 vq, bool ccd)
{
	struct friction fr = friction_of(c, obstacle);
	vec3 vd = V1(c, v), vn = response_node_velocity(vd, n, vq, c->opt.restitution, &fr, dt);
	vec3 p = place(c, v, q, n, v3_dot(vq, n) * dt);

	if (ccd)
		p = clamp_box(c, v, p);
	v3_store(c->v1 + 3 * v, vn);
	v3_store(c->x1 + 3 * v, p);
	c->changed_next[v] = 1;
	return add_event(c, step, v, type, other, obstacle, q, n, v3_dot(vd, n), v3_dot(vn, n));
}

/* ---- narrow = seed: the chapter's procedure, once ---- */

static int
seed_pass(struct collide *c, long step, double dt, unsigned char *hit)
{
	const struct vt_pair *vt = c->br.vt;
	size_t i = 0, j, nvt = c->br.nvt;

	while (i < nvt) {
		int v = vt[i].v, done = 0;

		for (j = i; j < nvt && vt[j].v == v; j++)
			;
		for (; i < j && !done && v < c->ncloth && !c->fixed[v]; i++) {
			int t = vt[i].t, k, s;
			const int *tn = c->tri + 3 * t;
			vec3 a = X0(c, tn[0]), b = X0(c, tn[1]), cc = X0(c, tn[2]), d = X1(c, v);
			struct seed_hit h;

			if (!c->opt.self && c->tri_obstacle[t] < 0)
				continue;
			/* the node's own path, then the edges of its triangles
			 * (the sliding case at the end of §3.2) */
			for (s = -1; s < c->vedge_start[v + 1] - c->vedge_start[v]; s++) {
				int f = v;
				vec3 vq;

				if (s >= 0) {
					const int *en = c->edge + 2 * c->vedge[c->vedge_start[v] + s];

					f = en[0] == v ? en[1] : en[0];
					/* an edge that touches the triangle is adjacent to it */
					if (tn[0] == f || tn[1] == f || tn[2] == f)
						continue;
				}
				c->st.narrow_tests++;
				if (!narrow_seed_segment(X0(c, f), d, a, b, cc, c->opt.inside, &h))
					continue;
				vq = response_point_velocity(a, b, cc, V1(c, tn[0]), V1(c, tn[1]),
				    V1(c, tn[2]), h.q);
				k = correct_node(c, step, dt, v, s < 0 ? h.type : CONTACT_EDGE_EDGE, t,
				    c->tri_obstacle[t], h.q, h.n, vq, false);
				if (k != 0)
					return -1;
				hit[v] = 1;
				done = 1;	/* "at the first detected collision, the procedure stops" */
				break;
			}
		}
		i = j;
	}
	return 0;
}

/* ---- narrow = ccd ---- */

static vec3
lerp(vec3 a, vec3 b, double t)
{
	return v3_madd(a, v3_sub(b, a), t);
}

static bool
moves(const struct collide *c, int v)
{
	const double *a = c->x0 + 3 * v, *b = c->x1 + 3 * v;

	return a[0] != b[0] || a[1] != b[1] || a[2] != b[2];
}

/* Puts a movable node back to step k: the last resort. */
static void
freeze(struct collide *c, int v)
{
	if (v >= c->ncloth || c->fixed[v])
		return;
	if (!c->frozen[v]) {
		c->frozen[v] = 1;
		c->st.frozen++;
	}
	if (moves(c, v)) {
		memcpy(c->x1 + 3 * v, c->x0 + 3 * v, 3 * sizeof *c->x1);
		c->changed_next[v] = 1;
	}
	/* and step k's velocity: a node held in place must not gather speed
	 * from forces it is not allowed to follow */
	memcpy(c->v1 + 3 * v, c->v0 + 3 * v, 3 * sizeof *c->v1);
}

static vec3
unit_or(vec3 a, vec3 fallback)
{
	double l = v3_len(a);

	return l > 0 && isfinite(l) ? v3_scale(a, 1 / l) : fallback;
}

/*
 * ccd: the response to a contact between two pieces of the network, or the
 * network and a mesh. The chapter's response (eq. 11-17) corrects the node
 * alone, as if the triangle were much heavier (M >> m); between two layers
 * of the same cloth the masses are alike, and a node made to follow a
 * triangle that does not feel it in turn keeps a pile of layers chattering.
 * So here the inelastic impulse is shared by mass between both sides and
 * conserves momentum (an obstacle's vertices have no inverse mass: against
 * a mesh it is the chapter's response, with Q's velocity interpolated from
 * the vertices instead of eq. 15's rigid frame).
 *
 * The contact is given by its points: vert[k] with weight w[k], positive on
 * one side (the node, edge a), negative on the other (the triangle, edge
 * b), so that sum w[k] x[k] is the separation and n points from the
 * negative side to the positive one at step k; g0 is that separation along
 * n at step k. The velocities are response_shared's. The positions
 * follow the scene's policy: keep puts the vertices back at step k (the
 * chapter's choice), q at the contact (toi, where the two touch), and slide
 * restores step k's gap along n, each side moving as its mass says, and
 * leaves the sliding motion alone (keeping the whole position locks
 * sliding surfaces, as the chapter notes).
 */
static int
contact_impulse(struct collide *c, long step, double dt, double toi, int nvert, const int *vert,
    const double *w, vec3 n, double g0, enum contact_type type, int other, int obstacle, vec3 q)
{
	struct friction fr = friction_of(c, obstacle);
	double den = 0, g1 = 0, im[4];
	vec3 v[4], v_before[4];
	int k;

	for (k = 0; k < nvert; k++) {
		im[k] = c->inv_mass[vert[k]];
		den += w[k] * w[k] * im[k];
		g1 += w[k] * v3_dot(X1(c, vert[k]), n);
		v[k] = v_before[k] = V1(c, vert[k]);
	}
	if (response_shared(nvert, w, im, v, n, c->opt.restitution, &fr, dt) < 0)
		return 0;	/* nothing here can move */
	g1 -= g0 > 0 ? g0 : 0;	/* < 0: closer than at step k, or crossed */
	for (k = 0; k < nvert; k++) {
		int p = vert[k];
		double sgn = w[k] > 0 ? 1 : -1;

		if (im[k] == 0)
			continue;
		v3_store(c->v1 + 3 * p, v[k]);
		if (c->opt.position == POSITION_KEEP)
			v3_store(c->x1 + 3 * p, X0(c, p));
		else if (c->opt.position == POSITION_Q)
			v3_store(c->x1 + 3 * p, lerp(X0(c, p), X1(c, p), toi));
		else if (g1 < 0)
			v3_store(c->x1 + 3 * p, clamp_box(c, p, v3_madd(X1(c, p), n,
			    -w[k] * im[k] * g1 / den)));
		c->changed_next[p] = 1;
		if (add_event(c, step, p, type, other, obstacle, q, v3_scale(n, sgn),
		    sgn * v3_dot(v_before[k], n), sgn * v3_dot(v[k], n)) != 0)
			return -1;
	}
	return 0;
}

/*
 * The last resort, for a contact still there after FAILSAFE_PASS passes:
 * its vertices go back to step k, where the network was consistent, and
 * move on together, at their mass-weighted mean velocity (or that of the
 * ones that cannot move): a perfectly inelastic impact in every direction.
 * Keeping each its own velocity instead would let a node jammed between
 * layers keep a speed that neither its forces nor damping can change.
 */
static int
stick(struct collide *c, long step, int nvert, const int *vert, enum contact_type type, int other,
    int obstacle, vec3 q, vec3 n)
{
	vec3 p = v3(0, 0, 0), pf = v3(0, 0, 0), vm, vn_before[4];
	double m = 0;
	int k, nfixed = 0;

	for (k = 0; k < nvert; k++) {
		double im = c->inv_mass[vert[k]];

		vn_before[k] = V1(c, vert[k]);
		if (im == 0) {
			pf = v3_add(pf, V1(c, vert[k]));
			nfixed++;
		} else {
			p = v3_madd(p, V1(c, vert[k]), 1 / im);
			m += 1 / im;
		}
	}
	vm = nfixed > 0 ? v3_scale(pf, 1.0 / nfixed) : v3_scale(p, 1 / m);
	for (k = 0; k < nvert; k++) {
		int v = vert[k];

		if (c->inv_mass[v] == 0)
			continue;
		freeze(c, v);
		v3_store(c->v1 + 3 * v, vm);
		if (add_event(c, step, v, type, other, obstacle, q, n, v3_dot(vn_before[k], n),
		    v3_dot(vm, n)) != 0)
			return -1;
	}
	return 0;
}

/* Barycentric coordinates of p's projection on triangle abc, clamped to
 * the triangle (a conservative test may report a point just outside). */
static void
barycentric(vec3 p, vec3 a, vec3 b, vec3 cc, double bw[3])
{
	vec3 e0 = v3_sub(b, a), e1 = v3_sub(cc, a), d = v3_sub(p, a);
	double d00 = v3_dot(e0, e0), d01 = v3_dot(e0, e1), d11 = v3_dot(e1, e1);
	double d20 = v3_dot(d, e0), d21 = v3_dot(d, e1), den = d00 * d11 - d01 * d01, sum;
	int k;

	if (!(den > 0)) {
		bw[0] = bw[1] = bw[2] = 1.0 / 3;
		return;
	}
	bw[1] = (d11 * d20 - d01 * d21) / den;
	bw[2] = (d00 * d21 - d01 * d20) / den;
	bw[0] = 1 - bw[1] - bw[2];
	for (k = 0, sum = 0; k < 3; k++)
		sum += bw[k] = fmax(bw[k], 0);
	for (k = 0; k < 3; k++)
		bw[k] = sum > 0 ? bw[k] / sum : 1.0 / 3;
}

static int
ccd_vertex_triangle(struct collide *c, long step, double dt, int v, int t, double toi, int pass)
{
	const int *tn = c->tri + 3 * t;
	vec3 p = lerp(X0(c, v), X1(c, v), toi), a = lerp(X0(c, tn[0]), X1(c, tn[0]), toi);
	vec3 b = lerp(X0(c, tn[1]), X1(c, tn[1]), toi), cc = lerp(X0(c, tn[2]), X1(c, tn[2]), toi);
	vec3 n = v3_cross(v3_sub(b, a), v3_sub(cc, a)), q, sep0 = X0(c, v);
	double bw[3], w[4], g0;
	int vert[4] = { v, tn[0], tn[1], tn[2] }, k;

	barycentric(p, a, b, cc, bw);
	w[0] = 1;
	for (k = 0; k < 3; k++) {
		w[k + 1] = -bw[k];
		sep0 = v3_madd(sep0, X0(c, tn[k]), -bw[k]);
	}
	n = unit_or(n, unit_or(sep0, v3(0, 1, 0)));
	/* n towards the node's side at step k; with no side then, against
	 * the relative motion */
	g0 = v3_dot(sep0, n);
	if (g0 < 0 || (g0 == 0 && v3_dot(v3_sub(v3_sub(X1(c, v), X0(c, v)),
	    v3_sub(lerp(X1(c, tn[0]), X1(c, tn[1]), 0.5), lerp(X0(c, tn[0]), X0(c, tn[1]), 0.5))),
	    n) > 0)) {
		n = v3_neg(n);
		g0 = -g0;
	}
	q = v3_madd(p, n, -v3_dot(v3_sub(p, a), n));
	if (pass >= FAILSAFE_PASS)
		return stick(c, step, 4, vert, CONTACT_NODE_FACE, t, c->tri_obstacle[t], q, n);
	return contact_impulse(c, step, dt, toi, 4, vert, w, n, g0, CONTACT_NODE_FACE, t,
	    c->tri_obstacle[t], q);
}

/* Closest points of segments p0-p1 and q0-q1: parameters s and u. */
static void
segment_params(vec3 p0, vec3 p1, vec3 q0, vec3 q1, double *s, double *u)
{
	vec3 d1 = v3_sub(p1, p0), d2 = v3_sub(q1, q0), r = v3_sub(p0, q0);
	double a = v3_dot(d1, d1), e = v3_dot(d2, d2), f = v3_dot(d2, r);
	double cc = v3_dot(d1, r), b = v3_dot(d1, d2), den = a * e - b * b;

	*s = den > 0 ? fmin(fmax((b * f - cc * e) / den, 0), 1) : 0;
	*u = e > 0 ? (b * *s + f) / e : 0;
	if (*u < 0 || *u > 1) {
		*u = fmin(fmax(*u, 0), 1);
		*s = a > 0 ? fmin(fmax((b * *u - cc) / a, 0), 1) : 0;
	}
}

static int
ccd_edges(struct collide *c, long step, double dt, int ea, int eb, double toi, int pass)
{
	const int *na = c->edge + 2 * ea, *nb = c->edge + 2 * eb;
	vec3 pa0, pa1, pb0, pb1, n, q, sep;
	double s, u, w[4];
	int vert[4] = { na[0], na[1], nb[0], nb[1] }, obstacle = -1;

	if (nb[0] >= c->ncloth)	/* an obstacle's edge: its vertex's first triangle says which */
		obstacle = c->tri_obstacle[c->vtri[c->vtri_start[nb[0]]]];
	else if (na[0] >= c->ncloth)
		obstacle = c->tri_obstacle[c->vtri[c->vtri_start[na[0]]]];
	pa0 = lerp(X0(c, na[0]), X1(c, na[0]), toi);
	pa1 = lerp(X0(c, na[1]), X1(c, na[1]), toi);
	pb0 = lerp(X0(c, nb[0]), X1(c, nb[0]), toi);
	pb1 = lerp(X0(c, nb[1]), X1(c, nb[1]), toi);
	segment_params(pa0, pa1, pb0, pb1, &s, &u);
	q = lerp(pb0, pb1, u);
	/* The normal: from edge b to edge a at step k, where the two were
	 * apart. The cross product of the edges is no normal for nearly
	 * parallel edges (two layers of cloth lying on each other), where it
	 * points anywhere; it serves only when the step k points coincide. */
	sep = v3_sub(lerp(X0(c, na[0]), X0(c, na[1]), s), lerp(X0(c, nb[0]), X0(c, nb[1]), u));
	n = unit_or(sep, unit_or(v3_cross(v3_sub(pa1, pa0), v3_sub(pb1, pb0)), v3(0, 1, 0)));
	if (v3_dot(n, sep) < 0)
		n = v3_neg(n);
	w[0] = 1 - s;
	w[1] = s;
	w[2] = -(1 - u);
	w[3] = -u;
	if (pass >= FAILSAFE_PASS)
		return stick(c, step, 4, vert, CONTACT_EDGE_EDGE, eb, obstacle, q, n);
	return contact_impulse(c, step, dt, toi, 4, vert, w, n, v3_dot(sep, n), CONTACT_EDGE_EDGE, eb,
	    obstacle, q);
}

/* Analytic obstacles for node v; returns 1 if one corrected it. The
 * obstacles are convex, so the plane through step k's closest surface
 * point q0, normal to x0 - q0, has the whole solid behind it: the node is
 * put on that plane at Q (q), at step k's clearance above it (slide), or
 * back at step k (keep), and is outside in each case. */
static int
obstacles_node(struct collide *c, long step, double dt, int v, bool ccd)
{
	size_t o;

	for (o = 0; o < c->nobst; o++) {
		const struct obstacle *ob = &c->obst[o];
		struct friction fr = friction_of(c, (int)o);
		vec3 q, n, q0, n0, p, vd = V1(c, v), vn;
		double d0;

		if (ob->kind == OBSTACLE_MESH || obstacle_distance(ob, X1(c, v), &q, &n) >= 0)
			continue;
		if ((d0 = obstacle_distance(ob, X0(c, v), &q0, &n0)) >= 0) {
			n = n0;
			q = v3_madd(X1(c, v), n, -v3_dot(v3_sub(X1(c, v), q0), n));
		}
		vn = response_node_velocity(vd, n, v3(0, 0, 0), c->opt.restitution, &fr, dt);
		p = c->opt.position == POSITION_Q || d0 < 0 ? q :
		    c->opt.position == POSITION_SLIDE ? v3_madd(q, n, d0) : X0(c, v);
		if (ccd && c->pairs)
			p = clamp_box(c, v, p);
		if (obstacle_distance(ob, p, NULL, NULL) < 0) {
			/* the clamp pushed it back in: stay at step k, at rest on
			 * the surface, so that no speed builds up in place */
			p = d0 >= 0 ? X0(c, v) : q;
			vn = v3(0, 0, 0);
		}
		v3_store(c->v1 + 3 * v, vn);
		v3_store(c->x1 + 3 * v, p);
		c->changed_next[v] = 1;
		if (add_event(c, step, v, CONTACT_OBSTACLE, -1, (int)o, q, n, v3_dot(vd, n),
		    v3_dot(vn, n)) != 0)
			return -1;
		return 1;
	}
	return 0;
}

static int
ccd_passes(struct collide *c, long step, double dt)
{
	int pass, v, max_pass = c->ncloth + FAILSAFE_PASS + 1;
	size_t i;

	memset(c->frozen, 0, (size_t)c->nv);
	memset(c->changed, 1, (size_t)c->nv);
	for (pass = 0; pass < max_pass; pass++) {
		long before = c->st.corrections;

		memset(c->changed_next, 0, (size_t)c->nv);
		for (i = 0; c->pairs && i < c->br.nvt; i++) {
			int vv = c->br.vt[i].v, t = c->br.vt[i].t;
			const int *tn = c->tri + 3 * t;
			vec3 x0[4], x1[4];
			double toi;
			int k;

			if (!c->opt.self && c->tri_obstacle[t] < 0 && vv < c->ncloth)
				continue;
			if (!c->changed[vv] && !c->changed[tn[0]] && !c->changed[tn[1]] &&
			    !c->changed[tn[2]])
				continue;
			if (!moves(c, vv) && !moves(c, tn[0]) && !moves(c, tn[1]) && !moves(c, tn[2]))
				continue;
			x0[0] = X0(c, vv);
			x1[0] = X1(c, vv);
			for (k = 0; k < 3; k++) {
				x0[k + 1] = X0(c, tn[k]);
				x1[k + 1] = X1(c, tn[k]);
			}
			c->st.narrow_tests++;
			if (ccd_vertex_face(x0, x1, 0, &toi) &&
			    ccd_vertex_triangle(c, step, dt, vv, t, toi, pass) != 0)
				return -1;
		}
		for (i = 0; c->pairs && i < c->br.nee; i++) {
			int ea = c->br.ee[i].a, eb = c->br.ee[i].b, k;
			const int *na = c->edge + 2 * ea, *nb = c->edge + 2 * eb;
			vec3 x0[4], x1[4];
			double toi;

			if (!c->opt.self && na[0] < c->ncloth && nb[0] < c->ncloth)
				continue;
			if (!c->changed[na[0]] && !c->changed[na[1]] && !c->changed[nb[0]] &&
			    !c->changed[nb[1]])
				continue;
			if (!moves(c, na[0]) && !moves(c, na[1]) && !moves(c, nb[0]) && !moves(c, nb[1]))
				continue;
			for (k = 0; k < 2; k++) {
				x0[k] = X0(c, na[k]);
				x1[k] = X1(c, na[k]);
				x0[k + 2] = X0(c, nb[k]);
				x1[k + 2] = X1(c, nb[k]);
			}
			c->st.narrow_tests++;
			if (ccd_edge_edge(x0, x1, 0, &toi) &&
			    ccd_edges(c, step, dt, ea, eb, toi, pass) != 0)
				return -1;
		}
		for (v = 0; v < c->ncloth; v++) {
			int r;

			if (!c->changed[v] || c->fixed[v] || c->frozen[v])
				continue;
			if ((r = obstacles_node(c, step, dt, v, true)) < 0)
				return -1;
			if (r && pass >= FAILSAFE_PASS)
				freeze(c, v);
		}
		c->st.passes = pass + 1;
		if (c->st.corrections == before)
			return 0;
		memcpy(c->changed, c->changed_next, (size_t)c->nv);
	}
	c->st.unresolved++;
	return 0;
}

int
collide_step(struct collide *c, long step, double dt, const double *y0, double *y1,
    struct drape_err *err)
{
	size_t n3 = 3 * (size_t)c->ncloth, k;
	double pad = 0;
	int v;

	c->nev = 0;
	memset(&c->st, 0, sizeof c->st);
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
	pad *= 2;
	for (v = 0; c->opt.narrow == NARROW_CCD && v < c->ncloth; v++) {
		double *b = c->box + 6 * v;

		for (k = 0; k < 3; k++) {
			b[k] = fmin(c->x0[3 * v + k], c->x1[3 * v + k]) - pad;
			b[3 + k] = fmax(c->x0[3 * v + k], c->x1[3 * v + k]) + pad;
		}
	}
	c->g.vbox = c->opt.narrow == NARROW_CCD ? c->box : NULL;
	if (c->pairs && broad_find(&c->br, &c->g, c->cell, c->opt.narrow, err) != 0)
		return -1;
	c->st.broad = c->br.st;
	if (c->opt.narrow == NARROW_SEED) {
		memset(c->changed, 0, (size_t)c->nv);
		if (c->pairs && seed_pass(c, step, dt, c->changed) != 0)
			goto oom;
		/* §4: the obstacles, for the nodes with no self-contact */
		for (v = 0; v < c->ncloth; v++)
			if (!c->changed[v] && !c->fixed[v] && obstacles_node(c, step, dt, v, false) < 0)
				goto oom;
		c->st.passes = 1;
	} else if (ccd_passes(c, step, dt) != 0) {
		goto oom;
	}
	memcpy(y1, c->x1, n3 * sizeof *y1);
	memcpy(y1 + n3, c->v1, n3 * sizeof *y1);

	c->total.narrow_tests += c->st.narrow_tests;
	for (k = 0; k < CONTACT_NTYPES; k++)
		c->total.contacts[k] += c->st.contacts[k];
	c->total.corrections += c->st.corrections;
	c->total.frozen += c->st.frozen;
	c->total.unresolved += c->st.unresolved;
	c->total.broad.node_pairs += c->st.broad.node_pairs;
	c->total.broad.vt_pairs += c->st.broad.vt_pairs;
	c->total.broad.ee_pairs += c->st.broad.ee_pairs;
	c->total.passes = c->st.passes > c->total.passes ? c->st.passes : c->total.passes;
	return 0;
oom:
	err_set(err, "collisions: out of memory");
	return -1;
}
