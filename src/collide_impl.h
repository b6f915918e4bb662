/* collide_impl.h: what the collision stages share, inside the collide
 * module only (collide.c runs a step; collide_geometry.c, collide_seed.c,
 * collide_ccd.c and collide_obstacle.c are its stages). */
#ifndef DRAPE_COLLIDE_IMPL_H
#define DRAPE_COLLIDE_IMPL_H

#include <math.h>

#include "collide.h"
#include "stop.h"

static inline vec3 X0(const struct collide *c, int v) { return v3_load(c->x0 + 3 * v); }
static inline vec3 X1(const struct collide *c, int v) { return v3_load(c->x1 + 3 * v); }
static inline vec3 V1(const struct collide *c, int v) { return v3_load(c->v1 + 3 * v); }


/* Keeps a corrected position inside the node's box of this step (its swept
 * box, widened: see collide_step), so that the broad phase's pairs still
 * cover it. */
static inline vec3
collide_clamp_box(const struct collide *c, int v, vec3 p)
{
	const double *b = c->box + 6 * v;

	return v3(fmin(fmax(p.x, b[0]), b[3]), fmin(fmax(p.y, b[1]), b[4]),
	    fmin(fmax(p.z, b[2]), b[5]));
}

/* Barycentric coordinates of p's projection on triangle abc, clamped to
 * the triangle (a conservative test may report a point just outside). */
static inline void
collide_barycentric(vec3 p, vec3 a, vec3 b, vec3 cc, double bw[3])
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

/* The stages. Each returns 0, or -1 out of memory. */
int collide_build_geometry(struct collide *c, const struct cloth *cl, const unsigned char *held);
int collide_seed_pass(struct collide *c, long step, double dt, unsigned char *hit);
int collide_ccd_passes(struct collide *c, long step, double dt);
/* Node v against the analytic obstacles: 1 if one corrected it. ccd: the
 * correction stays in the node's box of the step. */
int collide_obstacles_node(struct collide *c, long step, double dt, int v, bool ccd);

#endif
