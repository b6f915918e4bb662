/* collide_seed.c: narrow = seed: the chapter's procedure, once a step.
 * Each cloth node's segments (its own path, and the edges to it from its
 * neighbours at step k: the sliding case of §3.2) are tested against the
 * triangles the broad phase gave it (eq. 1-10); at the first hit the node
 * is corrected (eq. 11-17) and the procedure stops for it. */
#include "collide_impl.h"

/* Node v corrected against a surface point q of normal n moving at vq:
 * its velocity by eq. 11-17, its position by the scene's policy, where
 * slide keeps step k's offset along n plus the surface's own normal
 * motion over the step, with this step's tangential motion. */
static int
correct_node(struct collide *c, long step, double dt, int v, enum contact_type type, int other,
    int obstacle, vec3 q, vec3 n, vec3 vq)
{
	struct friction fr = collide_friction(c, obstacle);
	vec3 vd = V1(c, v), vn = response_node_velocity(vd, n, vq, c->opt.restitution, &fr, dt);
	vec3 p0 = X0(c, v), d = v3_sub(X1(c, v), p0);
	vec3 slid = v3_madd(v3_add(p0, v3_madd(d, n, -v3_dot(d, n))), n, v3_dot(vq, n) * dt);
	vec3 p = response_position(c->opt.position, p0, q, slid);

	if (c->opt.position == POSITION_KEEP && c->opt.keep_velocity == KEEP_VELOCITY_SURFACE)
		vn = vq;	/* put back, it moves with the surface (response.h) */

	v3_store(c->v1 + 3 * v, vn);
	v3_store(c->x1 + 3 * v, p);
	c->changed_next[v] = 1;
	return collide_add_event(c, step, v, type, other, obstacle, q, n, v3_dot(vd, n),
	    v3_dot(vn, n));
}

/* seed_response = shared (response.h): node v against triangle t of the
 * cloth at Q, the impact of eq. 11 shared with the triangle's vertices by
 * Q's barycentric weights and their masses; n is turned towards the
 * node's side at step k. The node's position follows the policy; with
 * keep the triangle's vertices go back to step k too. */
static int
correct_shared(struct collide *c, long step, double dt, int v, int t, enum contact_type type,
    vec3 q, vec3 n)
{
	const int *tn = c->tri + 3 * t;
	struct friction fr = collide_friction(c, -1);
	int vert[4] = { v, tn[0], tn[1], tn[2] }, k;
	double bw[3], w[4], im[4];
	vec3 vel[4], vd = V1(c, v), p0 = X0(c, v), d = v3_sub(X1(c, v), p0), vq = v3(0, 0, 0);
	vec3 slid;

	collide_barycentric(q, X0(c, tn[0]), X0(c, tn[1]), X0(c, tn[2]), bw);
	if (v3_dot(v3_sub(p0, q), n) < 0)
		n = v3_scale(n, -1);
	w[0] = 1;
	for (k = 0; k < 4; k++) {
		if (k > 0)
			w[k] = -bw[k - 1];
		im[k] = c->inv_mass[vert[k]];
		vel[k] = V1(c, vert[k]);
	}
	if (response_shared(4, w, im, vel, n, c->opt.restitution, &fr, dt) < 0)
		return 0;
	for (k = 1; k < 4; k++)
		vq = v3_madd(vq, vel[k], bw[k - 1]);
	slid = v3_madd(v3_add(p0, v3_madd(d, n, -v3_dot(d, n))), n, v3_dot(vq, n) * dt);
	for (k = 0; k < 4; k++) {
		int p = vert[k];

		if (im[k] == 0)
			continue;
		v3_store(c->v1 + 3 * p, vel[k]);
		if (k == 0)
			v3_store(c->x1 + 3 * p, response_position(c->opt.position, p0, q, slid));
		else if (c->opt.position == POSITION_KEEP)
			v3_store(c->x1 + 3 * p, X0(c, p));
		c->changed_next[p] = 1;
	}
	return collide_add_event(c, step, v, type, t, -1, q, n, v3_dot(vd, n), v3_dot(vel[0], n));
}

int
collide_seed_pass(struct collide *c, long step, double dt, unsigned char *hit)
{
	size_t i = 0, j, nvt;
	const struct vt_pair *vt = broad_vt(c->br, &nvt);

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

				if ((s < 0 && c->opt.segments == SEGMENTS_EDGES) ||
				    (s >= 0 && c->opt.segments == SEGMENTS_PATH))
					continue;
				if (s >= 0) {
					const int *en = c->edge + 2 * c->vedge[c->vedge_start[v] + s];

					f = en[0] == v ? en[1] : en[0];
					/* an edge that touches the triangle is adjacent to it */
					if (tn[0] == f || tn[1] == f || tn[2] == f)
						continue;
				}
				c->st.n[STAT_NARROW_TESTS]++;
				if (!narrow_seed_segment(X0(c, f), d, a, b, cc, c->opt.inside, &h))
					continue;
				vq = response_point_velocity(a, b, cc, V1(c, tn[0]), V1(c, tn[1]),
				    V1(c, tn[2]), h.q);
				if (c->opt.seed_response == SEED_RESPONSE_SHARED && c->tri_obstacle[t] < 0)
					k = correct_shared(c, step, dt, v, t,
					    s < 0 ? h.type : CONTACT_EDGE_EDGE, h.q, h.n);
				else
					k = correct_node(c, step, dt, v,
					    s < 0 ? h.type : CONTACT_EDGE_EDGE, t, c->tri_obstacle[t],
					    h.q, h.n, vq);
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
