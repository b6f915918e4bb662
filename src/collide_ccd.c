/* collide_ccd.c: narrow = ccd: every vertex-face and edge-edge contact
 * over the step (ccd.h), answered by an inelastic impulse shared by both
 * sides by their masses, then the pairs whose vertices moved tested again,
 * pass after pass, until none is left. From the COLLIDE_FAILSAFE_PASS-th pass on
 * a contact still there sticks: its vertices go back to step k (where the
 * network was consistent) at their mean velocity, which ends in at most
 * one pass per node and leaves no crossing behind. */
#include <string.h>

#include "ccd.h"
#include "collide_impl.h"

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
		c->st.n[STAT_FROZEN]++;
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
	struct friction fr = collide_friction(c, obstacle);
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
	/* < 0: closer than at step k (or than the gap that slide keeps, at
	 * most), or crossed */
	g1 -= g0 > 0 ? (g0 < c->slide_gap ? g0 : c->slide_gap) : 0;
	for (k = 0; k < nvert; k++) {
		int p = vert[k];
		double sgn = w[k] > 0 ? 1 : -1;
		vec3 x0, x1, slid;

		if (im[k] == 0)
			continue;
		x0 = X0(c, p);
		x1 = X1(c, p);
		slid = g1 < 0 ? collide_clamp_box(c, p, v3_madd(x1, n, -w[k] * im[k] * g1 / den)) : x1;
		v3_store(c->v1 + 3 * p, v[k]);
		v3_store(c->x1 + 3 * p, response_position(c->opt.position, x0, lerp(x0, x1, toi), slid));
		c->changed_next[p] = 1;
		if (collide_add_event(c, step, p, type, other, obstacle, q, v3_scale(n, sgn),
		    sgn * v3_dot(v_before[k], n), sgn * v3_dot(v[k], n)) != 0)
			return -1;
	}
	return 0;
}

/*
 * The last resort, for a contact still there after COLLIDE_FAILSAFE_PASS passes:
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
		if (collide_add_event(c, step, v, type, other, obstacle, q, n, v3_dot(vn_before[k], n),
		    v3_dot(vm, n)) != 0)
			return -1;
	}
	return 0;
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

	collide_barycentric(p, a, b, cc, bw);
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
	if (pass >= COLLIDE_FAILSAFE_PASS)
		return stick(c, step, 4, vert, CONTACT_NODE_FACE, t, c->tri_obstacle[t], q, n);
	return contact_impulse(c, step, dt, toi, 4, vert, w, n, g0, CONTACT_NODE_FACE, t,
	    c->tri_obstacle[t], q);
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
	v3_closest_on_segments(pa0, pa1, pb0, pb1, &s, &u);
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
	if (pass >= COLLIDE_FAILSAFE_PASS)
		return stick(c, step, 4, vert, CONTACT_EDGE_EDGE, eb, obstacle, q, n);
	return contact_impulse(c, step, dt, toi, 4, vert, w, n, v3_dot(sep, n), CONTACT_EDGE_EDGE, eb,
	    obstacle, q);
}

int
collide_ccd_passes(struct collide *c, long step, double dt)
{
	int pass, v, max_pass = c->ncloth + COLLIDE_FAILSAFE_PASS + 1;
	size_t i, nvt, nee;
	const struct vt_pair *vt;
	const struct ee_pair *ee;

	memset(c->frozen, 0, (size_t)c->nv);
	memset(c->changed, 1, (size_t)c->nv);
	for (pass = 0; pass < max_pass; pass++) {
		long before = c->st.n[STAT_CORRECTIONS];

		memset(c->changed_next, 0, (size_t)c->nv);
		if (stop_set(c->stop)) {
			c->stopped = true;	/* a signal: collide_step gives the step up */
			return 0;
		}
		/* the flat patches the broad phase left out, judged again where
		 * the last pass moved their nodes */
		if (pass > 0 && c->pairs && broad_recheck(c->br, &c->g, c->changed) < 0) {
			if (!broad_stopped(c->br))
				return -1;
			c->stopped = true;
			return 0;
		}
		vt = broad_vt(c->br, &nvt);
		ee = broad_ee(c->br, &nee);
		for (i = 0; c->pairs && i < nvt; i++) {
			int vv = vt[i].v, t = vt[i].t;

			if (stop_poll(i, c->stop)) {
				c->stopped = true;
				return 0;
			}
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
			c->st.n[STAT_NARROW_TESTS]++;
			if (ccd_vertex_face(x0, x1, 0, &toi) &&
			    ccd_vertex_triangle(c, step, dt, vv, t, toi, pass) != 0)
				return -1;
		}
		for (i = 0; c->pairs && i < nee; i++) {
			int ea = ee[i].a, eb = ee[i].b, k;
			const int *na = c->edge + 2 * ea, *nb = c->edge + 2 * eb;
			vec3 x0[4], x1[4];
			double toi;

			if (stop_poll(i, c->stop)) {
				c->stopped = true;
				return 0;
			}
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
			c->st.n[STAT_NARROW_TESTS]++;
			if (ccd_edge_edge(x0, x1, 0, &toi) &&
			    ccd_edges(c, step, dt, ea, eb, toi, pass) != 0)
				return -1;
		}
		for (v = 0; v < c->ncloth; v++) {
			int r;

			if (!c->changed[v] || c->fixed[v] || c->frozen[v])
				continue;
			if ((r = collide_obstacles_node(c, step, dt, v, true)) < 0)
				return -1;
			if (r && pass >= COLLIDE_FAILSAFE_PASS)
				freeze(c, v);
		}
		if (c->st.n[STAT_PASSES] < pass + 1)	/* a step's most over its checks */
			c->st.n[STAT_PASSES] = pass + 1;
		if (c->st.n[STAT_CORRECTIONS] == before)
			return 0;
		memcpy(c->changed, c->changed_next, (size_t)c->nv);
	}
	c->st.n[STAT_UNRESOLVED] = 1;	/* a step unresolved, in one check or more */
	return 0;
}
