/* paint.c: a scene's floor, obstacles and cloth as shaded triangles. */
#include <math.h>
#include <stdlib.h>

#include "paint.h"

#define SPHERE_SLICES 32
#define SPHERE_STACKS 16
#define DISC_SEGMENTS 48
#define FLOOR_HALF 1.5		/* of the framed radius, each way */
#define FLOOR_CELLS 8		/* about this many grid squares across */

static const float floor_colour[3] = { 0.93f, 0.93f, 0.91f };
static const float shadow_colour[3] = { 0.80f, 0.80f, 0.78f };
static const struct rgb grid_colour = { 196, 196, 190 };
static const float solid_colour[3] = { 0.60f, 0.66f, 0.74f };
static const struct rgb edge_colour = { 70, 78, 90 };

/* The light, in view space (raster.h's), as a unit vector. */
static vec3
light(void)
{
	vec3 l = RASTER_LIGHT;

	return v3_scale(l, 1 / v3_len(l));
}

/* A world direction in view space. */
static vec3
view_dir(const struct camera *cam, vec3 d)
{
	return camera_view(cam, v3_add(cam->target, d));
}

/* A vertex at p with world normal n (any length; zero: unlit), its colour
 * base lit with ambient light amb; two-sided: lit whichever way n faces
 * the light. */
static struct render_vertex
vertex(const struct camera *cam, vec3 p, vec3 n, const float *base, double amb, bool two_sided)
{
	/* amb < 0: unlit */
	struct render_vertex v;
	vec3 nv = view_dir(cam, n);
	double len = v3_len(nv), lam = 0;
	int k;

	if (len > 0) {
		lam = v3_dot(nv, light()) / len;
		lam = two_sided ? fabs(lam) : fmax(0, lam);
	}
	v.p = p;
	for (k = 0; k < 3; k++)
		v.c[k] = (float)(amb < 0 ? base[k] : base[k] * (amb + (1 - amb) * lam));
	v.lum = (float)(0.15 + 0.85 * lam);
	return v;
}

static void
flat(struct render *im, const struct camera *cam, vec3 a, vec3 b, vec3 c, const float *base,
    double amb, enum cell_kind kind)
{
	vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
	struct render_vertex va = vertex(cam, a, n, base, amb, true), vb = va, vc = va;

	vb.p = b;
	vc.p = c;
	render_triangle(im, cam, &va, &vb, &vc, kind);
}

static void
flat_quad(struct render *im, const struct camera *cam, vec3 a, vec3 b, vec3 c, vec3 d,
    const float *base, double amb, enum cell_kind kind)
{
	flat(im, cam, a, b, c, base, amb, kind);
	flat(im, cam, a, c, d, base, amb, kind);
}

/* Unlit: every vertex the same colour. */
static void
plain_quad(struct render *im, const struct camera *cam, vec3 a, vec3 b, vec3 c, vec3 d,
    const float *col, float lum, enum cell_kind kind)
{
	struct render_vertex v[4];
	vec3 p[4] = { a, b, c, d };
	int k;

	for (k = 0; k < 4; k++) {
		v[k].p = p[k];
		v[k].c[0] = col[0];
		v[k].c[1] = col[1];
		v[k].c[2] = col[2];
		v[k].lum = lum;
	}
	render_triangle(im, cam, &v[0], &v[1], &v[2], kind);
	render_triangle(im, cam, &v[0], &v[2], &v[3], kind);
}

static void
draw_box(struct render *im, const struct camera *cam, vec3 lo, vec3 hi)
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
		flat_quad(im, cam, p[face[k][0]], p[face[k][1]], p[face[k][2]], p[face[k][3]],
		    solid_colour, 0.35, CELL_SOLID);
}

static vec3
on_sphere(double rad, int slice, int stack)
{
	double th = 2 * V3_PI * slice / SPHERE_SLICES, ph = V3_PI * stack / SPHERE_STACKS;

	return v3(rad * sin(ph) * cos(th), rad * cos(ph), rad * sin(ph) * sin(th));
}

static void
draw_sphere(struct render *im, const struct camera *cam, vec3 c, double rad)
{
	int i, j, k;

	for (j = 0; j < SPHERE_STACKS; j++)
		for (i = 0; i < SPHERE_SLICES; i++) {
			vec3 d[4] = { on_sphere(rad, i, j), on_sphere(rad, i + 1, j),
				on_sphere(rad, i + 1, j + 1), on_sphere(rad, i, j + 1) };
			struct render_vertex v[4];

			for (k = 0; k < 4; k++)
				v[k] = vertex(cam, v3_add(c, d[k]), d[k], solid_colour, 0.35, false);
			render_triangle(im, cam, &v[0], &v[1], &v[2], CELL_SOLID);
			render_triangle(im, cam, &v[0], &v[2], &v[3], CELL_SOLID);
		}
}

/* A vertical cylinder whose top face is centred on c. */
static void
draw_disc(struct render *im, const struct camera *cam, vec3 c, double rad, double height)
{
	vec3 bottom = v3(c.x, c.y - height, c.z);
	int k;

	for (k = 0; k < DISC_SEGMENTS; k++) {
		double a0 = 2 * V3_PI * k / DISC_SEGMENTS, a1 = 2 * V3_PI * (k + 1) / DISC_SEGMENTS;
		vec3 d0 = v3(rad * cos(a0), 0, rad * sin(a0)), d1 = v3(rad * cos(a1), 0, rad * sin(a1));
		vec3 t0 = v3_add(c, d0), t1 = v3_add(c, d1);
		vec3 b0 = v3_add(bottom, d0), b1 = v3_add(bottom, d1);
		struct render_vertex v[4] = {
			vertex(cam, t0, d0, solid_colour, 0.35, false),
			vertex(cam, b0, d0, solid_colour, 0.35, false),
			vertex(cam, b1, d1, solid_colour, 0.35, false),
			vertex(cam, t1, d1, solid_colour, 0.35, false),
		};

		flat(im, cam, c, t0, t1, solid_colour, 0.35, CELL_SOLID);
		flat(im, cam, bottom, b1, b0, solid_colour, 0.35, CELL_SOLID);
		render_triangle(im, cam, &v[0], &v[1], &v[2], CELL_SOLID);
		render_triangle(im, cam, &v[0], &v[2], &v[3], CELL_SOLID);
	}
}

/* Cut away (a node inside it): only the faces turned away from the viewer,
 * the inside of the far wall, and every edge. */
static void
draw_mesh(struct render *im, const struct camera *cam, const struct mesh *m, bool cutaway)
{
	double slack = 1e-3 * cam->radius;
	size_t t;
	int k;

	for (t = 0; t < m->ntri; t++) {
		vec3 p[3];

		for (k = 0; k < 3; k++)
			p[k] = v3_load(m->x + 3 * m->tri[3 * t + (size_t)k]);
		if (cutaway && view_dir(cam, v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]))).z > 0)
			continue;
		flat(im, cam, p[0], p[1], p[2], solid_colour, 0.35, CELL_SOLID);
	}
	for (t = 0; t < m->ntri; t++)
		for (k = 0; k < 3; k++)
			render_line(im, cam, v3_load(m->x + 3 * m->tri[3 * t + (size_t)k]),
			    v3_load(m->x + 3 * m->tri[3 * t + (size_t)(k + 1) % 3]), edge_colour,
			    cutaway ? INFINITY : slack, CELL_SOLID);
}

double
paint_floor_spacing(const struct camera *cam)
{
	static const double steps[] = { 1, 2, 5 };
	double want = 2 * FLOOR_HALF * cam->radius / cam->zoom / FLOOR_CELLS;
	double p = pow(10, floor(log10(want)));
	int k;

	for (k = 0; k < 3; k++)
		if (steps[k] * p >= want)
			return steps[k] * p;
	return 10 * p;
}

/* A square of the plane about the framed target, a little under the
 * surface (so that a cloth lying on it covers it): the floor, the cloth's
 * shadow straight down onto it, and grid lines at multiples of the
 * spacing from the plane's point (fixed in the world, so that frames of
 * one run line up). */
static void
draw_floor(struct render *im, const struct camera *cam, const struct obstacle *o,
    const struct cloth *cl, const double *x)
{
	double half = FLOOR_HALF * cam->radius, sink = 2e-3 * cam->radius;
	double step = paint_floor_spacing(cam), a, b;
	vec3 n = o->normal, u, w;
	vec3 c = v3_madd(cam->target, n, -v3_dot(v3_sub(cam->target, o->point), n));
	vec3 under = v3_madd(c, n, -sink), lines;
	double cu, cw;
	size_t t;
	int k;

	v3_tangents(n, &u, &w);
	plain_quad(im, cam, v3_madd(v3_madd(under, u, -half), w, -half),
	    v3_madd(v3_madd(under, u, half), w, -half), v3_madd(v3_madd(under, u, half), w, half),
	    v3_madd(v3_madd(under, u, -half), w, half), floor_colour, 0, CELL_FLOOR);
	for (t = 0; t < cl->ntri; t++) {
		struct render_vertex v[3];

		for (k = 0; k < 3; k++) {
			vec3 p = v3_load(x + 3 * cl->tri[3 * t + (size_t)k]);
			double up = v3_dot(v3_sub(p, o->point), n);

			if (up < 0)	/* under the floor: no shadow */
				break;
			v[k].p = v3_madd(p, n, -up - 0.7 * sink);
			v[k].c[0] = shadow_colour[0];
			v[k].c[1] = shadow_colour[1];
			v[k].c[2] = shadow_colour[2];
			v[k].lum = 0;	/* no dots: the floor is blank */
		}
		if (k == 3)
			render_triangle(im, cam, &v[0], &v[1], &v[2], CELL_FLOOR);
	}
	lines = v3_madd(c, n, -0.65 * sink);
	cu = v3_dot(v3_sub(c, o->point), u);
	cw = v3_dot(v3_sub(c, o->point), w);
	for (a = ceil((cu - half) / step) * step; a <= cu + half; a += step)
		render_line(im, cam, v3_madd(v3_madd(lines, u, a - cu), w, -half),
		    v3_madd(v3_madd(lines, u, a - cu), w, half), grid_colour, 0.1 * sink, CELL_FLOOR);
	for (b = ceil((cw - half) / step) * step; b <= cw + half; b += step)
		render_line(im, cam, v3_madd(v3_madd(lines, w, b - cw), u, -half),
		    v3_madd(v3_madd(lines, w, b - cw), u, half), grid_colour, 0.1 * sink, CELL_FLOOR);
}

/* Is any node of the cloth inside the obstacle? */
static bool
holds_a_node(const struct obstacle *o, const struct cloth *cl, const double *x)
{
	int p;

	if ((double)cl->n * (double)o->mesh.ntri > 2e7)
		return false;
	for (p = 0; p < cl->n; p++)
		if (obstacle_distance(o, v3_load(x + 3 * p), NULL, NULL) < 0)
			return true;
	return false;
}

int
paint_scene(struct render *im, const struct camera *cam, const struct scene *sc,
    const struct cloth *cl, const double *x, const double *field, const struct paint_opts *o)
{
	size_t n = cl->n > 0 ? (size_t)cl->n : 1, k, t;
	vec3 *normal = calloc(n, sizeof *normal);
	double amb = o->unlit ? -1 : o->colouring == COLOUR_SHADE ? 0.30 : 0.55;
	double px = cam->zoom * fmin((double)im->w, im->h * im->aspect) / (2 * cam->radius);
	int j, p;

	if (normal == NULL)
		return -1;
	render_clear(im, PAINT_BACKGROUND);
	for (k = 0; k < sc->nobstacles; k++) {
		const struct obstacle *ob = &sc->obstacles[k];

		switch (ob->kind) {
		case OBSTACLE_PLANE:
			draw_floor(im, cam, ob, cl, x);
			break;
		case OBSTACLE_BOX:
			draw_box(im, cam, ob->lo, ob->hi);
			break;
		case OBSTACLE_SPHERE:
			draw_sphere(im, cam, ob->centre, ob->radius);
			break;
		case OBSTACLE_DISC:
			draw_disc(im, cam, ob->centre, ob->radius, ob->height);
			break;
		case OBSTACLE_MESH:
			draw_mesh(im, cam, &ob->mesh, holds_a_node(ob, cl, x));
			break;
		}
	}
	/* the cloth, a little nearer than it is: a coarse cloth lying on a
	 * solid cuts through its edges (a straight triangle over a corner),
	 * which would show the solid through it */
	im->bias = cl->h;
	/* normals at the nodes, from their triangles */
	for (t = 0; t < cl->ntri; t++) {
		const int *tri = cl->tri + 3 * t;
		vec3 a = v3_load(x + 3 * tri[0]);
		vec3 nt = v3_cross(v3_sub(v3_load(x + 3 * tri[1]), a), v3_sub(v3_load(x + 3 * tri[2]), a));

		for (j = 0; j < 3; j++)
			normal[tri[j]] = v3_add(normal[tri[j]], nt);
	}
	for (t = 0; t < cl->ntri; t++) {
		const int *tri = cl->tri + 3 * t;
		vec3 a = v3_load(x + 3 * tri[0]);
		vec3 nt = v3_cross(v3_sub(v3_load(x + 3 * tri[1]), a), v3_sub(v3_load(x + 3 * tri[2]), a));
		/* the side seen: the front (warp x weft) or the back */
		double side = view_dir(cam, nt).z >= 0 ? 1 : -1;
		struct render_vertex v[3];

		for (j = 0; j < 3; j++) {
			float base[3];
			vec3 nv = v3_scale(normal[tri[j]], side);

			if (v3_dot(nv, nt) * side < 0)	/* a fold's edge: the face's own */
				nv = v3_scale(nt, side);
			colouring_colour(o->colouring, field != NULL && o->colouring != COLOUR_SHADE ?
			    field[tri[j]] : side, o->range, base);
			v[j] = vertex(cam, v3_load(x + 3 * tri[j]), nv, base, amb, false);
		}
		render_triangle(im, cam, &v[0], &v[1], &v[2], CELL_CLOTH);
	}
	if (o->yarn_px > 0 && cl->h * px >= o->yarn_px)
		for (k = 0; k < cl->nsprings; k++)
			render_line_darken(im, cam, v3_load(x + 3 * cl->springs[k].a),
			    v3_load(x + 3 * cl->springs[k].b), 0.82, 1e-3 * cam->radius);
	if (cl->ntri == 0) {
		/* a cloth of single nodes (the icosahedron's): dots */
		double r = fmax(2, 0.012 * fmin(im->w, im->h * im->aspect));

		for (p = 0; p < cl->n; p++) {
			float base[3];

			colouring_colour(o->colouring, field != NULL && o->colouring != COLOUR_SHADE ?
			    field[p] : 1, o->range, base);
			render_dot(im, cam, v3_load(x + 3 * p), r, render_rgb(base), 0, false, CELL_CLOTH);
		}
	}
	im->bias = 0;
	free(normal);
	return 0;
}
