/* paint.c: a scene's floor, obstacles and cloth as shaded triangles. */
#include <math.h>
#include <stdlib.h>

#include "paint.h"
#include "shape.h"

#define FLOOR_CELLS 8		/* about this many grid squares across */

static const float floor_colour[3] = { 0.93f, 0.93f, 0.91f };
static const float shadow_colour[3] = { 0.80f, 0.80f, 0.78f };
static const struct rgb grid_colour = { 196, 196, 190 };
static const float solid_colour[3] = { 0.60f, 0.66f, 0.74f };
static const struct rgb edge_colour = { 70, 78, 90 };
static const struct shape_detail detail = { .slices = 32, .stacks = 16, .segments = 48 };

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

struct face_ctx {
	struct render *im;
	const struct camera *cam;
	bool cutaway;		/* leave out the faces towards the viewer */
};

/* A solid's face: flat, or lit at each corner by its own normal. */
static void
solid_face(void *ctx, const struct shape_face *f)
{
	struct face_ctx *fc = ctx;
	struct render_vertex v[4];
	int k;

	if (fc->cutaway && view_dir(fc->cam, v3_cross(v3_sub(f->p[1], f->p[0]),
	    v3_sub(f->p[2], f->p[0]))).z > 0)
		return;
	if (!f->smooth) {
		flat(fc->im, fc->cam, f->p[0], f->p[1], f->p[2], solid_colour, 0.35, CELL_SOLID);
		if (f->nv == 4)
			flat(fc->im, fc->cam, f->p[0], f->p[2], f->p[3], solid_colour, 0.35,
			    CELL_SOLID);
		return;
	}
	for (k = 0; k < f->nv; k++)
		v[k] = vertex(fc->cam, f->p[k], f->n[k], solid_colour, 0.35, false);
	render_triangle(fc->im, fc->cam, &v[0], &v[1], &v[2], CELL_SOLID);
	if (f->nv == 4)
		render_triangle(fc->im, fc->cam, &v[0], &v[2], &v[3], CELL_SOLID);
}

/* Cut away (a node inside it): only the faces turned away from the viewer,
 * the inside of the far wall, and every edge. */
static void
draw_mesh(struct render *im, const struct camera *cam, const struct obstacle *o, bool cutaway)
{
	const struct mesh *m = &o->mesh;
	struct face_ctx fc = { im, cam, cutaway };
	double slack = 1e-3 * cam->radius;
	size_t t;
	int k;

	shape_obstacle(o, &detail, solid_face, &fc);
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
	double want = 2 * SHAPE_FLOOR_HALF * cam->radius / cam->zoom / FLOOR_CELLS;
	double p = pow(10, floor(log10(want)));
	int k;

	for (k = 0; k < 3; k++)
		if (steps[k] * p >= want)
			return steps[k] * p;
	return 10 * p;
}

/* shape_floor's square: the floor, the cloth's
 * shadow straight down onto it, and grid lines at multiples of the
 * spacing from the plane's point (fixed in the world, so that frames of
 * one run line up). */
static void
draw_floor(struct render *im, const struct camera *cam, const struct obstacle *o,
    const struct cloth *cl, const double *x)
{
	struct shape_floor fl;
	double half, sink, step = paint_floor_spacing(cam), a, b, cu, cw;
	vec3 n = o->normal, u, w, c, lines;
	size_t t;
	int k;

	shape_floor(cam, o->point, n, &fl);
	half = fl.half, sink = fl.sink, u = fl.u, w = fl.w, c = fl.c;
	plain_quad(im, cam, fl.corner[0], fl.corner[1], fl.corner[2], fl.corner[3], floor_colour,
	    0, CELL_FLOOR);
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
	struct face_ctx fc = { im, cam, false };
	int j, p;

	if (normal == NULL)
		return -1;
	render_clear(im, PAINT_BACKGROUND);
	for (k = 0; k < sc->nobstacles; k++) {
		const struct obstacle *ob = &sc->obstacles[k];

		if (ob->kind == OBSTACLE_PLANE)
			draw_floor(im, cam, ob, cl, x);
		else if (ob->kind == OBSTACLE_MESH)
			draw_mesh(im, cam, ob, holds_a_node(ob, cl, x));
		else
			shape_obstacle(ob, &detail, solid_face, &fc);
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
