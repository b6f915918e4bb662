/* vec3.h: inline 3-vector arithmetic on a small value type. State arrays stay
 * flat doubles (x0 y0 z0 x1 ...); v3_load/v3_store move between the two. */
#ifndef DRAPE_VEC3_H
#define DRAPE_VEC3_H

#include <math.h>

#define V3_PI 3.14159265358979323846

typedef struct vec3 {
	double x, y, z;
} vec3;

static inline vec3 v3(double x, double y, double z) { return (vec3){ x, y, z }; }
static inline vec3 v3_load(const double *p) { return (vec3){ p[0], p[1], p[2] }; }
static inline void v3_store(double *p, vec3 a) { p[0] = a.x; p[1] = a.y; p[2] = a.z; }
static inline void v3_addto(double *p, vec3 a) { p[0] += a.x; p[1] += a.y; p[2] += a.z; }
static inline vec3 v3_add(vec3 a, vec3 b) { return (vec3){ a.x + b.x, a.y + b.y, a.z + b.z }; }
static inline vec3 v3_sub(vec3 a, vec3 b) { return (vec3){ a.x - b.x, a.y - b.y, a.z - b.z }; }
static inline vec3 v3_scale(vec3 a, double s) { return (vec3){ a.x * s, a.y * s, a.z * s }; }
static inline vec3 v3_neg(vec3 a) { return (vec3){ -a.x, -a.y, -a.z }; }
static inline double v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b)
{
	return (vec3){ a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x };
}
static inline double v3_len(vec3 a) { return sqrt(v3_dot(a, a)); }
/* a + s*b, the workhorse of the integrators and force loops. */
static inline vec3 v3_madd(vec3 a, vec3 b, double s)
{
	return (vec3){ a.x + s * b.x, a.y + s * b.y, a.z + s * b.z };
}

/* x clamped to [0, 1], NaN to 0 as fmin(fmax(x, 0), 1) takes it; inline,
 * where those are library calls (the contacts' edge pairs call this some
 * hundred thousand times a step in a pile). */
static inline double
v3_clamp01(double x)
{
	return x > 0 ? (x < 1 ? x : 1) : 0;
}

/* The closest points of segments p0-p1 and q0-q1, as their parameters s
 * and u (0 to 1 along each), after Ericson's Real-Time Collision
 * Detection, 5.1.9; a degenerate segment is taken at its start. */
static inline void
v3_closest_on_segments(vec3 p0, vec3 p1, vec3 q0, vec3 q1, double *s, double *u)
{
	vec3 d1 = v3_sub(p1, p0), d2 = v3_sub(q1, q0), r = v3_sub(p0, q0);
	double a = v3_dot(d1, d1), e = v3_dot(d2, d2), f = v3_dot(d2, r);
	double c = v3_dot(d1, r), b = v3_dot(d1, d2), den = a * e - b * b;

	*s = den > 0 ? v3_clamp01((b * f - c * e) / den) : 0;
	*u = e > 0 ? (b * *s + f) / e : 0;
	if (*u < 0 || *u > 1) {
		*u = v3_clamp01(*u);
		*s = a > 0 ? v3_clamp01((b * *u - c) / a) : 0;
	}
}

/* The box [*lo, *hi] grown to hold p; fmin and fmax pass over a NaN
 * coordinate, so that a blown-up node leaves the box as it was (start
 * from +INFINITY and -INFINITY). ccd.c keeps ternaries of its own, in its
 * hot path, where a NaN must spoil the box. */
static inline void
v3_box_grow(vec3 *lo, vec3 *hi, vec3 p)
{
	*lo = v3(fmin(lo->x, p.x), fmin(lo->y, p.y), fmin(lo->z, p.z));
	*hi = v3(fmax(hi->x, p.x), fmax(hi->y, p.y), fmax(hi->z, p.z));
}

/* Two unit vectors across the plane of normal n (the pictures' and the
 * terminal's floor grids). */
static inline void
v3_tangents(vec3 n, vec3 *u, vec3 *w)
{
	vec3 a = fabs(n.y) < 0.9 ? v3(0, 1, 0) : v3(1, 0, 0);

	*u = v3_cross(n, a);
	*u = v3_scale(*u, 1 / v3_len(*u));
	*w = v3_cross(n, *u);
}

#endif
