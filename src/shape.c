/* shape.c: an obstacle's surface as quads and triangles, walked once for
 * the character raster (view.c) and the picture (paint.c). */
#include <math.h>

#include "shape.h"

static void
emit(shape_face_fn *fn, void *ctx, int nv, vec3 a, vec3 b, vec3 c, vec3 d)
{
	struct shape_face f = { .nv = nv, .smooth = false, .p = { a, b, c, d } };

	fn(ctx, &f);
}

static void
box(vec3 lo, vec3 hi, shape_face_fn *fn, void *ctx)
{
	static const int face[6][4] = {
		{ 0, 1, 3, 2 }, { 4, 6, 7, 5 }, { 0, 4, 5, 1 },
		{ 2, 3, 7, 6 }, { 0, 2, 6, 4 }, { 1, 5, 7, 3 },
	};
	vec3 p[8];
	int k;

	for (k = 0; k < 8; k++)
		p[k] = v3(k & 4 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 1 ? hi.z : lo.z);
	for (k = 0; k < 6; k++)
		emit(fn, ctx, 4, p[face[k][0]], p[face[k][1]], p[face[k][2]], p[face[k][3]]);
}

/* From the centre to a point of a sphere of radius rad (also its normal). */
static vec3
on_sphere(double rad, int slice, int stack, const struct shape_detail *d)
{
	double th = 2 * V3_PI * slice / d->slices, ph = V3_PI * stack / d->stacks;

	return v3(rad * sin(ph) * cos(th), rad * cos(ph), rad * sin(ph) * sin(th));
}

static void
sphere(vec3 c, double rad, const struct shape_detail *d, shape_face_fn *fn, void *ctx)
{
	struct shape_face f = { .nv = 4, .smooth = true };
	int i, j, k;

	for (j = 0; j < d->stacks; j++)
		for (i = 0; i < d->slices; i++) {
			f.n[0] = on_sphere(rad, i, j, d);
			f.n[1] = on_sphere(rad, i + 1, j, d);
			f.n[2] = on_sphere(rad, i + 1, j + 1, d);
			f.n[3] = on_sphere(rad, i, j + 1, d);
			for (k = 0; k < 4; k++)
				f.p[k] = v3_add(c, f.n[k]);
			fn(ctx, &f);
		}
}

/* A vertical cylinder whose top face is centred on c: per segment the
 * top's triangle, the bottom's, then the side. */
static void
disc(vec3 c, double rad, double height, const struct shape_detail *d, shape_face_fn *fn,
    void *ctx)
{
	vec3 bottom = v3(c.x, c.y - height, c.z), none = v3(0, 0, 0);
	struct shape_face f = { .nv = 4, .smooth = true };
	int k;

	for (k = 0; k < d->segments; k++) {
		double a0 = 2 * V3_PI * k / d->segments, a1 = 2 * V3_PI * (k + 1) / d->segments;
		vec3 d0 = v3(rad * cos(a0), 0, rad * sin(a0)), d1 = v3(rad * cos(a1), 0, rad * sin(a1));
		/* the rim's y is c's or bottom's as it is (not + 0: a -0 stays) */
		vec3 t0 = v3(c.x + d0.x, c.y, c.z + d0.z), t1 = v3(c.x + d1.x, c.y, c.z + d1.z);
		vec3 b0 = v3(t0.x, bottom.y, t0.z), b1 = v3(t1.x, bottom.y, t1.z);

		emit(fn, ctx, 3, c, t0, t1, none);
		emit(fn, ctx, 3, bottom, b1, b0, none);
		f.p[0] = t0, f.p[1] = b0, f.p[2] = b1, f.p[3] = t1;
		f.n[0] = d0, f.n[1] = d0, f.n[2] = d1, f.n[3] = d1;
		fn(ctx, &f);
	}
}

static void
mesh(const struct mesh *m, shape_face_fn *fn, void *ctx)
{
	vec3 none = v3(0, 0, 0);
	size_t t;

	for (t = 0; t < m->ntri; t++)
		emit(fn, ctx, 3, v3_load(m->x + 3 * m->tri[3 * t]), v3_load(m->x + 3 * m->tri[3 * t + 1]),
		    v3_load(m->x + 3 * m->tri[3 * t + 2]), none);
}

void
shape_obstacle(const struct obstacle *o, const struct shape_detail *d, shape_face_fn *fn,
    void *ctx)
{
	switch (o->kind) {
	case OBSTACLE_PLANE:
		break;
	case OBSTACLE_BOX:
		box(o->lo, o->hi, fn, ctx);
		break;
	case OBSTACLE_SPHERE:
		sphere(o->centre, o->radius, d, fn, ctx);
		break;
	case OBSTACLE_DISC:
		disc(o->centre, o->radius, o->height, d, fn, ctx);
		break;
	case OBSTACLE_MESH:
		mesh(&o->mesh, fn, ctx);
		break;
	}
}

void
shape_floor(const struct camera *cam, vec3 point, vec3 n, struct shape_floor *f)
{
	double h = SHAPE_FLOOR_HALF * cam->radius;

	f->half = h;
	f->sink = 2e-3 * cam->radius;
	f->c = v3_madd(cam->target, n, -v3_dot(v3_sub(cam->target, point), n));
	f->under = v3_madd(f->c, n, -f->sink);
	v3_tangents(n, &f->u, &f->w);
	f->corner[0] = v3_madd(v3_madd(f->under, f->u, -h), f->w, -h);
	f->corner[1] = v3_madd(v3_madd(f->under, f->u, h), f->w, -h);
	f->corner[2] = v3_madd(v3_madd(f->under, f->u, h), f->w, h);
	f->corner[3] = v3_madd(v3_madd(f->under, f->u, -h), f->w, h);
}
