/* raster.c: projection, z-buffered triangle fill and ASCII shading. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raster.h"

const char *const view_preset_name[VIEW_NPRESETS] = { "front", "side", "top", "iso" };

/* The perspective eye sits this many framed radii in front of the target. */
#define EYE_DISTANCE 3.0
#define EDGE_ON_CHAR '-'

int
view_preset_from_name(const char *name)
{
	int k;

	for (k = 0; k < VIEW_NPRESETS; k++)
		if (strcmp(name, view_preset_name[k]) == 0)
			return k;
	return -1;
}

void
camera_preset(struct camera *cam, enum view_preset preset, vec3 target, double radius)
{
	static const double yaw[VIEW_NPRESETS] = { 0, 90, 0, 35 };
	static const double pitch[VIEW_NPRESETS] = { 0, 0, 90, 30 };

	cam->yaw = yaw[preset] * V3_PI / 180;
	cam->pitch = pitch[preset] * V3_PI / 180;
	cam->zoom = 1;
	cam->pan_x = cam->pan_y = 0;
	cam->perspective = false;
	cam->target = target;
	cam->radius = radius > 0 ? radius : 1;
}

vec3
camera_view(const struct camera *cam, vec3 p)
{
	vec3 d = v3_sub(p, cam->target);
	double cy = cos(cam->yaw), sy = sin(cam->yaw), cp = cos(cam->pitch), sp = sin(cam->pitch);
	double x = cy * d.x - sy * d.z, z = sy * d.x + cy * d.z;

	/* pitch > 0 raises the eye: at 90 degrees it looks straight down */
	return v3(x, cp * d.y - sp * z, sp * d.y + cp * z);
}

void
raster_init(struct raster *r)
{
	memset(r, 0, sizeof *r);
}

void
raster_free(struct raster *r)
{
	free(r->ch);
	free(r->kind);
	free(r->depth);
	raster_init(r);
}

int
raster_resize(struct raster *r, int w, int h)
{
	size_t n = (size_t)w * (size_t)h;

	raster_free(r);
	if (w < 1 || h < 1)
		return -1;
	r->ch = malloc(n);
	r->kind = malloc(n);
	r->depth = malloc(n * sizeof *r->depth);
	if (r->ch == NULL || r->kind == NULL || r->depth == NULL) {
		raster_free(r);
		return -1;
	}
	r->w = w;
	r->h = h;
	raster_clear(r);
	return 0;
}

void
raster_clear(struct raster *r)
{
	size_t n = (size_t)r->w * (size_t)r->h, i;

	memset(r->ch, ' ', n);
	memset(r->kind, CELL_EMPTY, n);
	for (i = 0; i < n; i++)
		r->depth[i] = -INFINITY;
}

bool
camera_project(const struct camera *cam, vec3 p, int w, int h, double aspect, double *col,
    double *row, double *z)
{
	vec3 q = camera_view(cam, p);
	/* cells per metre across */
	double f = 1, s = cam->zoom * fmin((double)w, (double)h * aspect) / (2 * cam->radius);

	if (cam->perspective) {
		double eye = EYE_DISTANCE * cam->radius;

		if (eye - q.z < 0.05 * cam->radius)
			return false;
		f = eye / (eye - q.z);
	}
	*col = 0.5 * w + (q.x * f + cam->pan_x) * s;
	*row = 0.5 * h - (q.y * f + cam->pan_y) * s / aspect;
	*z = q.z;
	return true;
}

bool
raster_project(const struct raster *r, const struct camera *cam, vec3 p, double *col,
    double *row, double *z)
{
	return camera_project(cam, p, r->w, r->h, RASTER_ASPECT, col, row, z);
}

/* The ramp character of a surface with view-space normal n: lit from the
 * viewer's upper left, so that what faces the viewer is never black; the
 * cloth's ramp, or the obstacles'. */
static char
shade(vec3 n, enum cell_kind kind)
{
	static const char cloth[] = RASTER_RAMP, solid[] = RASTER_SOLID_RAMP;
	const char *ramp = kind == CELL_SOLID ? solid : cloth;
	const int len = (int)strlen(ramp);
	vec3 light = RASTER_LIGHT;
	double len_n = v3_len(n), lit;
	int k;

	if (!(len_n > 0))
		return ramp[0];
	lit = 0.15 + 0.85 * fabs(v3_dot(n, light)) / (len_n * v3_len(light));
	k = (int)(lit * len);
	return ramp[k < 0 ? 0 : k >= len ? len - 1 : k];
}

static double
edge(double ax, double ay, double bx, double by, double px, double py)
{
	return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

/* A line of EDGE_ON_CHAR cells from grid position a to b, depth-tested. */
static void
edge_line(struct raster *r, double ax, double ay, double az, double bx, double by, double bz,
    enum cell_kind kind)
{
	double len = fmax(fabs(bx - ax), fabs(by - ay));
	int k, n = len < 1e6 ? (int)ceil(len) + 1 : 0;

	for (k = 0; k <= n; k++) {
		double s = n > 0 ? (double)k / n : 0;
		double x = ax + s * (bx - ax), y = ay + s * (by - ay), z = az + s * (bz - az);
		size_t at;

		if (!(x >= 0 && x < r->w && y >= 0 && y < r->h))
			continue;
		at = (size_t)(int)y * (size_t)r->w + (size_t)(int)x;
		if (z > r->depth[at]) {
			r->depth[at] = z;
			r->ch[at] = EDGE_ON_CHAR;
			r->kind[at] = (unsigned char)kind;
		}
	}
}

void
raster_triangle(struct raster *r, const struct camera *cam, vec3 a, vec3 b, vec3 c,
    enum cell_kind kind)
{
	double x[3], y[3], z[3], area, longest, lo_x, hi_x, lo_y, hi_y;
	vec3 n = v3_cross(v3_sub(camera_view(cam, b), camera_view(cam, a)),
	    v3_sub(camera_view(cam, c), camera_view(cam, a)));
	char ch = kind == CELL_FLOOR ? ' ' : shade(n, kind);
	int c0, c1, r0, r1, i, j;

	if (r->w < 1 || !raster_project(r, cam, a, &x[0], &y[0], &z[0]) ||
	    !raster_project(r, cam, b, &x[1], &y[1], &z[1]) ||
	    !raster_project(r, cam, c, &x[2], &y[2], &z[2]))
		return;
	area = edge(x[0], y[0], x[1], y[1], x[2], y[2]);
	if (!isfinite(area))
		return;
	longest = fmax(hypot(x[1] - x[0], y[1] - y[0]),
	    fmax(hypot(x[2] - x[1], y[2] - y[1]), hypot(x[0] - x[2], y[0] - y[2])));
	if (fabs(area) < 0.1 * longest * longest) {
		/* thin (nearly edge-on): it could vanish, so
		 * its edges show as a line too */
		if (kind != CELL_FLOOR)
			for (i = 0; i < 3; i++)
				edge_line(r, x[i], y[i], z[i], x[(i + 1) % 3], y[(i + 1) % 3],
				    z[(i + 1) % 3], kind);
		if (!(fabs(area) > 1e-12))
			return;
	}
	lo_x = fmin(x[0], fmin(x[1], x[2]));
	hi_x = fmax(x[0], fmax(x[1], x[2]));
	lo_y = fmin(y[0], fmin(y[1], y[2]));
	hi_y = fmax(y[0], fmax(y[1], y[2]));
	if (hi_x < 0 || hi_y < 0 || lo_x > r->w || lo_y > r->h)
		return;
	c0 = lo_x < 0 ? 0 : (int)floor(lo_x);
	c1 = hi_x >= r->w ? r->w - 1 : (int)floor(hi_x);
	r0 = lo_y < 0 ? 0 : (int)floor(lo_y);
	r1 = hi_y >= r->h ? r->h - 1 : (int)floor(hi_y);
	for (j = r0; j <= r1; j++) {
		for (i = c0; i <= c1; i++) {
			double px = i + 0.5, py = j + 0.5;
			/* barycentrics; a centre on an edge belongs to the triangle */
			double w0 = edge(x[1], y[1], x[2], y[2], px, py) / area;
			double w1 = edge(x[2], y[2], x[0], y[0], px, py) / area;
			double w2 = 1 - w0 - w1, d;
			size_t at = (size_t)j * (size_t)r->w + (size_t)i;

			if (w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9)
				continue;
			d = w0 * z[0] + w1 * z[1] + w2 * z[2];
			if (d > r->depth[at]) {
				r->depth[at] = d;
				r->ch[at] = ch;
				r->kind[at] = (unsigned char)kind;
			}
		}
	}
}

void
raster_point(struct raster *r, const struct camera *cam, vec3 p, char ch,
    enum cell_kind kind, double slack, bool always)
{
	double x, y, z;
	int i, j;
	size_t at;

	if (r->w < 1 || !raster_project(r, cam, p, &x, &y, &z) || !(x >= 0 && x < r->w) ||
	    !(y >= 0 && y < r->h))
		return;
	i = (int)floor(x);
	j = (int)floor(y);
	at = (size_t)j * (size_t)r->w + (size_t)i;
	if (!always && z + slack < r->depth[at])
		return;
	if (z > r->depth[at])
		r->depth[at] = z;
	r->ch[at] = ch;
	r->kind[at] = (unsigned char)kind;
}

char
raster_at(const struct raster *r, int col, int row)
{
	if (col < 0 || row < 0 || col >= r->w || row >= r->h)
		return ' ';
	return r->ch[(size_t)row * (size_t)r->w + (size_t)col];
}
