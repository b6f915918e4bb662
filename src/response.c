/* response.c: eq. 11-17. */
#include <math.h>
#include <stddef.h>

#include "response.h"

const char *const position_policy_name[] = { "keep", "q", "slide", NULL };
const char *const keep_velocity_name[] = { "eq16", "surface", NULL };
const char *const seed_response_name[] = { "node", "shared", NULL };

vec3
response_position(enum position_policy p, vec3 x0, vec3 touch, vec3 slid)
{
	switch (p) {
	case POSITION_Q:
		return touch;
	case POSITION_SLIDE:
		return slid;
	default:
		return x0;
	}
}

vec3
response_point_velocity(vec3 a, vec3 b, vec3 c, vec3 va, vec3 vb, vec3 vc, vec3 q)
{
	vec3 ab = v3_sub(b, a), ac = v3_sub(c, a);
	double lab = v3_len(ab), lac = v3_len(ac), lk;
	vec3 i, w, k, j, vi, vw, vk, vj, cr, omega;

	if (lab == 0 || lac == 0)
		return va;
	/* eq. 13: the frame fixed to the triangle and its rates */
	i = v3_scale(ab, 1 / lab);
	vi = v3_scale(v3_sub(vb, va), 1 / lab);
	w = v3_scale(ac, 1 / lac);
	vw = v3_scale(v3_sub(vc, va), 1 / lac);
	cr = v3_cross(i, w);
	if ((lk = v3_len(cr)) == 0)
		return va;
	k = v3_scale(cr, 1 / lk);
	vk = v3_scale(v3_add(v3_cross(vi, w), v3_cross(i, vw)), 1 / lk);
	j = v3_cross(k, i);
	vj = v3_add(v3_cross(vk, i), v3_cross(k, vi));
	/* eq. 14 */
	omega = v3_add(v3_add(v3_scale(i, v3_dot(vj, k)), v3_scale(j, v3_dot(vk, i))),
	    v3_scale(k, v3_dot(vi, j)));
	/* eq. 15 */
	return v3_add(va, v3_cross(omega, v3_sub(q, a)));
}

vec3
response_node_velocity(vec3 vd, vec3 n, vec3 vq, double e, const struct friction *fr, double dt)
{
	double vdn = v3_dot(vd, n), vqn = v3_dot(vq, n);
	/* eq. 11: along the normal k' the node takes -e v_D + (1+e) v_Q;
	 * e = 0 is eq. 12, the node takes Q's normal velocity */
	double vn_after = -e * vdn + (1 + e) * vqn;
	/* eq. 17: the tangential part, untouched by the impact */
	vec3 vt = v3_madd(vd, n, -vdn);

	if (fr != NULL && (fr->mu > 0 || fr->viscous > 0)) {
		/* friction acts on the sliding velocity, relative to Q's */
		vec3 vqt = v3_madd(vq, n, -vqn), rel = v3_sub(vt, vqt);
		double s = v3_len(rel), keep = 1;

		if (s > 0) {
			if (fr->mu > 0)
				keep = fmax(0, 1 - fr->mu * fabs(vn_after - vdn) / s);
			if (fr->viscous > 0)
				keep *= exp(-fr->viscous * dt);
			vt = v3_madd(vqt, rel, keep);
		}
	}
	/* eq. 16: v_D+ = v_D- - v_Dk'- + v_Qk' (with e) */
	return v3_madd(vt, n, vn_after);
}

double
response_shared(int nvert, const double *w, const double *inv_mass, vec3 *v, vec3 n,
    double e, const struct friction *fr, double dt)
{
	double den = 0, vr, j, st;
	vec3 rel = v3(0, 0, 0), vt;
	int k;

	for (k = 0; k < nvert; k++) {
		den += w[k] * w[k] * inv_mass[k];
		rel = v3_madd(rel, v[k], w[k]);
	}
	if (!(den > 0))
		return -1;
	vr = v3_dot(rel, n);
	/* eq. 11 between the two sides: the relative normal velocity becomes
	 * -e vr; each vertex takes its share of the impulse j */
	j = vr < 0 ? -(1 + e) * vr / den : 0;
	for (k = 0; k < nvert; k++)
		v[k] = v3_madd(v[k], n, w[k] * inv_mass[k] * j);
	/* eq. 17: the sliding velocity, less friction */
	vt = v3_madd(rel, n, -vr);
	st = v3_len(vt);
	if (fr != NULL && st > 0 && (fr->mu > 0 || fr->viscous > 0)) {
		double keep = 1;
		vec3 u = v3_scale(vt, 1 / st);

		if (fr->mu > 0)	/* the tangential impulse is at most mu j */
			keep = fmax(0, 1 - fr->mu * j * den / st);
		if (fr->viscous > 0)
			keep *= exp(-fr->viscous * dt);
		for (k = 0; k < nvert; k++)
			v[k] = v3_madd(v[k], u, -w[k] * inv_mass[k] * (1 - keep) * st / den);
	}
	return j;
}
