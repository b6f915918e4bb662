/* view.c: a scene's obstacles, cloth and marks as triangles and points. */
#include <math.h>

#include "shape.h"
#include "view.h"

#define FLOOR_LINES 7		/* grid lines each way */

/* fewer faces than paint.c's: a cell is coarser than a pixel */
static const struct shape_detail detail = { .slices = 16, .stacks = 8, .segments = 24 };

static void
quad(struct raster *r, const struct camera *cam, vec3 a, vec3 b, vec3 c, vec3 d,
    enum cell_kind kind)
{
	raster_triangle(r, cam, a, b, c, kind);
	raster_triangle(r, cam, a, c, d, kind);
}

struct face_ctx {
	struct raster *r;
	const struct camera *cam;
};

static void
solid_face(void *ctx, const struct shape_face *f)
{
	struct face_ctx *fc = ctx;

	if (f->nv == 4)
		quad(fc->r, fc->cam, f->p[0], f->p[1], f->p[2], f->p[3], CELL_SOLID);
	else
		raster_triangle(fc->r, fc->cam, f->p[0], f->p[1], f->p[2], CELL_SOLID);
}

/* shape_floor's square: blanks that hide what is under it, and a grid of
 * dots on it. */
static void
draw_floor(struct raster *r, const struct camera *cam, vec3 point, vec3 n)
{
	struct shape_floor fl;
	double half, step, slack;
	int i, k, samples = 2 * (r->w + 2 * r->h);

	shape_floor(cam, point, n, &fl);
	half = fl.half;
	step = 2 * half / (FLOOR_LINES - 1);
	/* the dots sit under the surface, with the square, so that a cloth
	 * lying on the floor covers them */
	slack = 0.3 * fl.sink;
	quad(r, cam, fl.corner[0], fl.corner[1], fl.corner[2], fl.corner[3], CELL_FLOOR);
	for (i = 0; i < FLOOR_LINES; i++) {
		for (k = 0; k < samples; k++) {
			double a = -half + i * step, b = -half + 2 * half * k / (samples - 1);

			raster_point(r, cam, v3_madd(v3_madd(fl.under, fl.u, a), fl.w, b), '.',
			    CELL_FLOOR, slack, false);
			raster_point(r, cam, v3_madd(v3_madd(fl.under, fl.u, b), fl.w, a), '.',
			    CELL_FLOOR, slack, false);
		}
	}
}

void
view_frame(const struct scene *sc, const double *x, int n, vec3 *target, double *radius)
{
	vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY), mid;
	size_t k;
	int p;

	for (p = 0; p < n; p++)
		v3_box_grow(&lo, &hi, v3_load(x + 3 * p));
	mid = n > 0 ? v3_scale(v3_add(lo, hi), 0.5) : v3(0, 0, 0);
	for (k = 0; k < sc->nobstacles; k++) {
		const struct obstacle *o = &sc->obstacles[k];
		vec3 olo, ohi;

		if (o->kind == OBSTACLE_PLANE) {
			v3_box_grow(&lo, &hi, v3_madd(mid, o->normal, -v3_dot(v3_sub(mid, o->point),
			    o->normal)));
			continue;
		}
		obstacle_bounds(o, &olo, &ohi);
		if (isfinite(olo.x + olo.y + olo.z + ohi.x + ohi.y + ohi.z)) {
			v3_box_grow(&lo, &hi, olo);
			v3_box_grow(&lo, &hi, ohi);
		}
	}
	if (!(lo.x <= hi.x)) {
		*target = v3(0, 0, 0);
		*radius = 1;
		return;
	}
	*target = v3_scale(v3_add(lo, hi), 0.5);
	*radius = 0.5 * v3_len(v3_sub(hi, lo));
	if (!(*radius > 0))
		*radius = 0.1;
}

void
view_cloth_box(const double *x, int n, vec3 *lo, vec3 *hi)
{
	int p;

	for (p = 0; p < n; p++)
		v3_box_grow(lo, hi, v3_load(x + 3 * p));
}

void
view_frame_cloth(const struct scene *sc, const double *x0, int n, vec3 lo, vec3 hi,
    vec3 *target, double *radius)
{
	vec3 scene_target;
	double scene_radius;

	view_frame(sc, x0, n, &scene_target, &scene_radius);
	/* no node, or one: a point has nothing to frame */
	if (n < 2 || !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) {
		*target = scene_target;
		*radius = scene_radius;
		return;
	}
	*target = v3_scale(v3_add(lo, hi), 0.5);
	*radius = fmax(1.1 * 0.5 * v3_len(v3_sub(hi, lo)), 0.1 * scene_radius);
}

void
view_draw(struct raster *r, const struct camera *cam, const struct scene *sc,
    const double *x, int n, const int *tri, size_t ntri,
    const struct contact_event *ev, size_t nev, int selected)
{
	struct face_ctx fc = { r, cam };
	size_t k;

	raster_clear(r);
	for (k = 0; k < sc->nobstacles; k++) {
		const struct obstacle *o = &sc->obstacles[k];

		if (o->kind == OBSTACLE_PLANE)
			draw_floor(r, cam, o->point, o->normal);
		else
			shape_obstacle(o, &detail, solid_face, &fc);
	}
	for (k = 0; k < ntri; k++)
		raster_triangle(r, cam, v3_load(x + 3 * tri[3 * k]), v3_load(x + 3 * tri[3 * k + 1]),
		    v3_load(x + 3 * tri[3 * k + 2]), CELL_CLOTH);
	for (k = 0; k < nev; k++)
		if (ev[k].node >= 0 && ev[k].node < n)
			raster_point(r, cam, v3_load(x + 3 * ev[k].node), VIEW_MARK_CONTACT,
			    CELL_CONTACT, 0.02 * cam->radius, false);
	if (selected >= 0 && selected < n)
		raster_point(r, cam, v3_load(x + 3 * selected), VIEW_MARK_SELECTED, CELL_SELECTED, 0,
		    true);
}
