/* collide_obstacle.c: the analytic obstacles (plane, box, sphere, disc)
 * by signed distance, as §4 says for regular surfaces. The obstacles are
 * convex, so the plane through step k's closest surface point q0, normal
 * to x0 - q0, has the whole solid behind it: the node is put on that plane
 * at Q (q), at step k's clearance above it (slide), or back at step k
 * (keep), and is outside in each case. Mesh obstacles go through the
 * narrow phases with the cloth instead. */
#include "collide_impl.h"

int
collide_obstacles_node(struct collide *c, long step, double dt, int v, bool ccd)
{
	size_t o;
	/* §4 may answer the regular surfaces otherwise than the cloth */
	enum position_policy pol = c->opt.obstacle_position >= 0 ?
	    (enum position_policy)c->opt.obstacle_position : c->opt.position;

	for (o = 0; o < c->nobst; o++) {
		const struct obstacle *ob = &c->obst[o];
		struct friction fr = collide_friction(c, (int)o);
		vec3 q, n, q0, n0, p, vd = V1(c, v), vn;
		double d0;

		if (ob->kind == OBSTACLE_MESH || obstacle_distance(ob, X1(c, v), &q, &n) >= 0)
			continue;
		if ((d0 = obstacle_distance(ob, X0(c, v), &q0, &n0)) >= 0) {
			n = n0;
			q = v3_madd(X1(c, v), n, -v3_dot(v3_sub(X1(c, v), q0), n));
		}
		vn = response_node_velocity(vd, n, v3(0, 0, 0), c->opt.restitution, &fr, dt);
		/* a node already inside at step k goes to the surface */
		p = d0 < 0 ? q : response_position(pol, X0(c, v), q, v3_madd(q, n, d0));
		/* put back, it moves with the obstacle, which is at rest */
		if (d0 >= 0 && pol == POSITION_KEEP && c->opt.keep_velocity == KEEP_VELOCITY_SURFACE)
			vn = v3(0, 0, 0);
		if (ccd && c->pairs)
			p = collide_clamp_box(c, v, p);
		if (obstacle_distance(ob, p, NULL, NULL) < 0) {
			/* the clamp pushed it back in: stay at step k, at rest on
			 * the surface, so that no speed builds up in place */
			p = d0 >= 0 ? X0(c, v) : q;
			vn = v3(0, 0, 0);
		}
		v3_store(c->v1 + 3 * v, vn);
		v3_store(c->x1 + 3 * v, p);
		c->changed_next[v] = 1;
		if (collide_add_event(c, step, v, CONTACT_OBSTACLE, -1, (int)o, q, n, v3_dot(vd, n),
		    v3_dot(vn, n)) != 0)
			return -1;
		return 1;
	}
	return 0;
}
