/* view.c: a scene's obstacles, cloth and marks as triangles and points. */
#include <math.h>

#include "view.h"

#define SPHERE_SLICES 16
#define SPHERE_STACKS 8
#define DISC_SEGMENTS 24
#define FLOOR_LINES 7		/* grid lines each way */

static void
quad(struct raster *r, const struct camera *cam, vec3 a, vec3 b, vec3 c, vec3 d,
    enum cell_kind kind)
{
	raster_triangle(r, cam, a, b, c, kind);
	raster_triangle(r, cam, a, c, d, kind);
}

static void
draw_box(struct raster *r, const struct camera *cam, vec3 lo, vec3 hi)
{
	vec3 p[8];
	static const int face[6][4] = {
		{ 0, 1, 3, 2 }, { 4, 6, 7, 5 }, { 0, 4, 5, 1 },
		{ 2, 3, 7, 6 }, { 0, 2, 6, 4 }, { 1, 5, 7, 3 },
	};
	int k;

	for (k = 0; k < 8; k++)
		p[k] = v3(k & 4 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 1 ? hi.z : lo.z);
	for (k = 0; k < 6; k++)
		quad(r, cam, p[face[k][0]], p[face[k][1]], p[face[k][2]], p[face[k][3]], CELL_SOLID);
}

static vec3
on_sphere(vec3 c, double rad, int slice, int stack)
{
	double th = 2 * V3_PI * slice / SPHERE_SLICES, ph = V3_PI * stack / SPHERE_STACKS;

	return v3(c.x + rad * sin(ph) * cos(th), c.y + rad * cos(ph), c.z + rad * sin(ph) * sin(th));
}

static void
draw_sphere(struct raster *r, const struct camera *cam, vec3 c, double rad)
{
	int i, j;

	for (j = 0; j < SPHERE_STACKS; j++)
		for (i = 0; i < SPHERE_SLICES; i++)
			quad(r, cam, on_sphere(c, rad, i, j), on_sphere(c, rad, i + 1, j),
			    on_sphere(c, rad, i + 1, j + 1), on_sphere(c, rad, i, j + 1), CELL_SOLID);
}

/* A vertical cylinder whose top face is centred on c. */
static void
draw_disc(struct raster *r, const struct camera *cam, vec3 c, double rad, double height)
{
	vec3 bottom = v3(c.x, c.y - height, c.z);
	int k;

	for (k = 0; k < DISC_SEGMENTS; k++) {
		double a0 = 2 * V3_PI * k / DISC_SEGMENTS, a1 = 2 * V3_PI * (k + 1) / DISC_SEGMENTS;
		vec3 t0 = v3(c.x + rad * cos(a0), c.y, c.z + rad * sin(a0));
		vec3 t1 = v3(c.x + rad * cos(a1), c.y, c.z + rad * sin(a1));
		vec3 b0 = v3(t0.x, bottom.y, t0.z), b1 = v3(t1.x, bottom.y, t1.z);

		raster_triangle(r, cam, c, t0, t1, CELL_SOLID);
		raster_triangle(r, cam, bottom, b1, b0, CELL_SOLID);
		quad(r, cam, t0, b0, b1, t1, CELL_SOLID);
	}
}

/* A square of the plane about the framed target: blanks that hide what is
 * under it, and a grid of dots on it. */
static void
draw_floor(struct raster *r, const struct camera *cam, vec3 point, vec3 n)
{
	double half = 1.5 * cam->radius, step = 2 * half / (FLOOR_LINES - 1);
	/* the dots sit a little under the surface, so that a cloth lying on
	 * the floor covers them */
	double sink = 2e-3 * cam->radius, slack = 0.3 * sink;
	vec3 u, w, c = v3_madd(cam->target, n, -v3_dot(v3_sub(cam->target, point), n));
	vec3 under = v3_madd(c, n, -sink);
	int i, k, samples = 2 * (r->w + 2 * r->h);

	v3_tangents(n, &u, &w);
	quad(r, cam, v3_madd(v3_madd(under, u, -half), w, -half),
	    v3_madd(v3_madd(under, u, half), w, -half), v3_madd(v3_madd(under, u, half), w, half),
	    v3_madd(v3_madd(under, u, -half), w, half), CELL_FLOOR);
	for (i = 0; i < FLOOR_LINES; i++) {
		for (k = 0; k < samples; k++) {
			double a = -half + i * step, b = -half + 2 * half * k / (samples - 1);

			raster_point(r, cam, v3_madd(v3_madd(under, u, a), w, b), '.', CELL_FLOOR,
			    slack, false);
			raster_point(r, cam, v3_madd(v3_madd(under, u, b), w, a), '.', CELL_FLOOR,
			    slack, false);
		}
	}
}

static void
draw_mesh(struct raster *r, const struct camera *cam, const struct mesh *m)
{
	size_t t;

	for (t = 0; t < m->ntri; t++)
		raster_triangle(r, cam, v3_load(m->x + 3 * m->tri[3 * t]),
		    v3_load(m->x + 3 * m->tri[3 * t + 1]), v3_load(m->x + 3 * m->tri[3 * t + 2]),
		    CELL_SOLID);
}

static void
grow(vec3 *lo, vec3 *hi, vec3 p)
{
	*lo = v3(fmin(lo->x, p.x), fmin(lo->y, p.y), fmin(lo->z, p.z));
	*hi = v3(fmax(hi->x, p.x), fmax(hi->y, p.y), fmax(hi->z, p.z));
}

void
view_frame(const struct scene *sc, const double *x, int n, vec3 *target, double *radius)
{
	vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY), mid;
	size_t k;
	int p;

	for (p = 0; p < n; p++)
		grow(&lo, &hi, v3_load(x + 3 * p));
	mid = n > 0 ? v3_scale(v3_add(lo, hi), 0.5) : v3(0, 0, 0);
	for (k = 0; k < sc->nobstacles; k++) {
		const struct obstacle *o = &sc->obstacles[k];
		vec3 olo, ohi;

		if (o->kind == OBSTACLE_PLANE) {
			grow(&lo, &hi, v3_madd(mid, o->normal, -v3_dot(v3_sub(mid, o->point),
			    o->normal)));
			continue;
		}
		obstacle_bounds(o, &olo, &ohi);
		if (isfinite(olo.x + olo.y + olo.z + ohi.x + ohi.y + ohi.z)) {
			grow(&lo, &hi, olo);
			grow(&lo, &hi, ohi);
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
		grow(lo, hi, v3_load(x + 3 * p));
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
	size_t k;

	raster_clear(r);
	for (k = 0; k < sc->nobstacles; k++) {
		const struct obstacle *o = &sc->obstacles[k];

		switch (o->kind) {
		case OBSTACLE_PLANE:
			draw_floor(r, cam, o->point, o->normal);
			break;
		case OBSTACLE_BOX:
			draw_box(r, cam, o->lo, o->hi);
			break;
		case OBSTACLE_SPHERE:
			draw_sphere(r, cam, o->centre, o->radius);
			break;
		case OBSTACLE_DISC:
			draw_disc(r, cam, o->centre, o->radius, o->height);
			break;
		case OBSTACLE_MESH:
			draw_mesh(r, cam, &o->mesh);
			break;
		}
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
