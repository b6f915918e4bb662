/* render.c: z-buffered triangles with colours interpolated across them,
 * lines and dots, into an RGB image. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "render.h"

void
render_init(struct render *im)
{
	memset(im, 0, sizeof *im);
	im->aspect = 1;
}

void
render_free(struct render *im)
{
	free(im->rgb);
	free(im->depth);
	free(im->kind);
	free(im->lum);
	render_init(im);
}

int
render_resize(struct render *im, int w, int h, double aspect)
{
	size_t n;

	render_free(im);
	if (w < 1 || h < 1 || !(aspect > 0) || (size_t)w > SIZE_MAX / 16 / (size_t)h)
		return -1;
	n = (size_t)w * (size_t)h;
	im->rgb = malloc(3 * n);
	im->depth = malloc(n * sizeof *im->depth);
	im->kind = malloc(n);
	im->lum = malloc(n * sizeof *im->lum);
	if (im->rgb == NULL || im->depth == NULL || im->kind == NULL || im->lum == NULL) {
		render_free(im);
		return -1;
	}
	im->w = w;
	im->h = h;
	im->aspect = aspect;
	im->bias = 0;
	render_clear(im, (struct rgb){ 0, 0, 0 });
	return 0;
}

void
render_clear(struct render *im, struct rgb bg)
{
	size_t n = (size_t)im->w * (size_t)im->h, i;

	for (i = 0; i < n; i++) {
		im->rgb[3 * i] = bg.r;
		im->rgb[3 * i + 1] = bg.g;
		im->rgb[3 * i + 2] = bg.b;
		im->depth[i] = -INFINITY;
		im->lum[i] = 0;
	}
	memset(im->kind, CELL_EMPTY, n);
}

static unsigned char
byte(double v)
{
	if (!(v > 0))
		return 0;
	if (v >= 1)
		return 255;
	return (unsigned char)(v * 255 + 0.5);
}

struct rgb
render_rgb(const float c[3])
{
	return (struct rgb){ byte(c[0]), byte(c[1]), byte(c[2]) };
}

static bool
project(const struct render *im, const struct camera *cam, vec3 p, double *x, double *y,
    double *z)
{
	return camera_project(cam, p, im->w, im->h, im->aspect, x, y, z);
}

static double
edge(double ax, double ay, double bx, double by, double px, double py)
{
	return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

/* A pixel at index at, if z passes the test. */
static void
put(struct render *im, size_t at, double z, const float c[3], float lum, enum cell_kind kind,
    bool write_depth, double slack)
{
	if (write_depth) {
		if (!(z > im->depth[at]))
			return;
		im->depth[at] = z;
	} else if (z + slack < im->depth[at]) {
		return;
	}
	im->rgb[3 * at] = byte(c[0]);
	im->rgb[3 * at + 1] = byte(c[1]);
	im->rgb[3 * at + 2] = byte(c[2]);
	im->lum[at] = lum;
	im->kind[at] = (unsigned char)kind;
}

/* A line of pixels from (ax, ay, az) to (bx, by, bz), its colour
 * interpolated from ca to cb. */
static void
stroke(struct render *im, const double *a, const double *b, const float *ca, const float *cb,
    float la, float lb, enum cell_kind kind, bool write_depth, double slack)
{
	double len = fmax(fabs(b[0] - a[0]), fabs(b[1] - a[1]));
	int k, n;

	if (!(len < 1e6))
		return;
	n = (int)ceil(len) + 1;
	for (k = 0; k <= n; k++) {
		double s = (double)k / n;
		double x = a[0] + s * (b[0] - a[0]), y = a[1] + s * (b[1] - a[1]);
		double z = a[2] + s * (b[2] - a[2]);
		float c[3];
		int j;

		if (!(x >= 0 && x < im->w && y >= 0 && y < im->h))
			continue;
		for (j = 0; j < 3; j++)
			c[j] = (float)(ca[j] + s * (cb[j] - ca[j]));
		put(im, (size_t)(int)y * (size_t)im->w + (size_t)(int)x, z, c,
		    (float)(la + s * (lb - la)), kind, write_depth, slack);
	}
}

void
render_triangle(struct render *im, const struct camera *cam, const struct render_vertex *a,
    const struct render_vertex *b, const struct render_vertex *c, enum cell_kind kind)
{
	const struct render_vertex *v[3] = { a, b, c };
	double p[3][3], area, longest, lo_x, hi_x, lo_y, hi_y;
	int k, x0, x1, y0, y1, i, j;

	if (im->w < 1)
		return;
	for (k = 0; k < 3; k++)
		if (!project(im, cam, v[k]->p, &p[k][0], &p[k][1], &p[k][2]))
			return;
	for (k = 0; k < 3; k++)
		p[k][2] += im->bias;
	area = edge(p[0][0], p[0][1], p[1][0], p[1][1], p[2][0], p[2][1]);
	if (!isfinite(area))
		return;
	longest = 0;
	for (k = 0; k < 3; k++)
		longest = fmax(longest, hypot(p[(k + 1) % 3][0] - p[k][0],
		    p[(k + 1) % 3][1] - p[k][1]));
	if (fabs(area) < longest) {
		/* thinner than a pixel: it could fall between the pixel
		 * centres, so its edges show */
		for (k = 0; k < 3; k++)
			stroke(im, p[k], p[(k + 1) % 3], v[k]->c, v[(k + 1) % 3]->c, v[k]->lum,
			    v[(k + 1) % 3]->lum, kind, true, 0);
		if (!(fabs(area) > 1e-12))
			return;
	}
	lo_x = fmin(p[0][0], fmin(p[1][0], p[2][0]));
	hi_x = fmax(p[0][0], fmax(p[1][0], p[2][0]));
	lo_y = fmin(p[0][1], fmin(p[1][1], p[2][1]));
	hi_y = fmax(p[0][1], fmax(p[1][1], p[2][1]));
	if (hi_x < 0 || hi_y < 0 || lo_x > im->w || lo_y > im->h)
		return;
	x0 = lo_x < 0 ? 0 : (int)floor(lo_x);
	x1 = hi_x >= im->w ? im->w - 1 : (int)floor(hi_x);
	y0 = lo_y < 0 ? 0 : (int)floor(lo_y);
	y1 = hi_y >= im->h ? im->h - 1 : (int)floor(hi_y);
	for (j = y0; j <= y1; j++) {
		for (i = x0; i <= x1; i++) {
			double px = i + 0.5, py = j + 0.5;
			/* barycentrics; a centre on an edge belongs to the triangle */
			double w0 = edge(p[1][0], p[1][1], p[2][0], p[2][1], px, py) / area;
			double w1 = edge(p[2][0], p[2][1], p[0][0], p[0][1], px, py) / area;
			double w2 = 1 - w0 - w1;
			float col[3];

			if (w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9)
				continue;
			for (k = 0; k < 3; k++)
				col[k] = (float)(w0 * a->c[k] + w1 * b->c[k] + w2 * c->c[k]);
			put(im, (size_t)j * (size_t)im->w + (size_t)i,
			    w0 * p[0][2] + w1 * p[1][2] + w2 * p[2][2], col,
			    (float)(w0 * a->lum + w1 * b->lum + w2 * c->lum), kind, true, 0);
		}
	}
}

void
render_line(struct render *im, const struct camera *cam, vec3 a, vec3 b, struct rgb c,
    double slack, enum cell_kind kind)
{
	double pa[3], pb[3];
	float f[3] = { c.r / 255.0f, c.g / 255.0f, c.b / 255.0f };

	if (im->w < 1 || !project(im, cam, a, &pa[0], &pa[1], &pa[2]) ||
	    !project(im, cam, b, &pb[0], &pb[1], &pb[2]))
		return;
	pa[2] += im->bias;
	pb[2] += im->bias;
	stroke(im, pa, pb, f, f, 1, 1, kind, false, slack);
}

void
render_line_darken(struct render *im, const struct camera *cam, vec3 a, vec3 b,
    double factor, double slack)
{
	double pa[3], pb[3], len;
	size_t last = SIZE_MAX;
	int k, n;

	if (im->w < 1 || !project(im, cam, a, &pa[0], &pa[1], &pa[2]) ||
	    !project(im, cam, b, &pb[0], &pb[1], &pb[2]))
		return;
	len = fmax(fabs(pb[0] - pa[0]), fabs(pb[1] - pa[1]));
	if (!(len < 1e6))
		return;
	n = (int)ceil(len) + 1;
	for (k = 0; k <= n; k++) {
		double s = (double)k / n;
		double x = pa[0] + s * (pb[0] - pa[0]), y = pa[1] + s * (pb[1] - pa[1]);
		double z = pa[2] + s * (pb[2] - pa[2]) + im->bias;
		size_t at;
		int j;

		if (!(x >= 0 && x < im->w && y >= 0 && y < im->h))
			continue;
		at = (size_t)(int)y * (size_t)im->w + (size_t)(int)x;
		if (at == last || z + slack < im->depth[at] || im->kind[at] == CELL_EMPTY)
			continue;
		last = at;
		for (j = 0; j < 3; j++)
			im->rgb[3 * at + (size_t)j] = (unsigned char)(im->rgb[3 * at + (size_t)j] * factor + 0.5);
	}
}

void
render_dot(struct render *im, const struct camera *cam, vec3 p, double px, struct rgb c,
    double slack, bool always, enum cell_kind kind)
{
	double x, y, z, r2 = px * px;
	float f[3] = { c.r / 255.0f, c.g / 255.0f, c.b / 255.0f };
	int i, j, x0, x1, y0, y1;

	if (im->w < 1 || !project(im, cam, p, &x, &y, &z) || !isfinite(x + y))
		return;
	z += im->bias;
	if (x + px < 0 || y + px < 0 || x - px > im->w || y - px > im->h)
		return;
	x0 = (int)fmax(0, floor(x - px));
	x1 = (int)fmin(im->w - 1, floor(x + px));
	y0 = (int)fmax(0, floor(y - px));
	y1 = (int)fmin(im->h - 1, floor(y + px));
	for (j = y0; j <= y1; j++)
		for (i = x0; i <= x1; i++) {
			double dx = i + 0.5 - x, dy = j + 0.5 - y;
			size_t at = (size_t)j * (size_t)im->w + (size_t)i;

			/* the pixel under p is always in, however small the dot */
			if (dx * dx + dy * dy > r2 && !(i == (int)floor(x) && j == (int)floor(y)))
				continue;
			if (!always && z + slack < im->depth[at])
				continue;
			if (z > im->depth[at])
				im->depth[at] = z;
			put(im, at, z, f, 1, kind, false, INFINITY);
		}
}

void
render_downsample(const unsigned char *in, int w, int h, int factor, unsigned char *out)
{
	int ow = w / factor, oh = h / factor, x, y, i, j, k;
	unsigned n = (unsigned)(factor * factor);

	for (y = 0; y < oh; y++)
		for (x = 0; x < ow; x++)
			for (k = 0; k < 3; k++) {
				unsigned sum = 0;

				for (j = 0; j < factor; j++)
					for (i = 0; i < factor; i++)
						sum += in[3 * ((size_t)(y * factor + j) * (size_t)w +
						    (size_t)(x * factor + i)) + (size_t)k];
				out[3 * ((size_t)y * (size_t)ow + (size_t)x) + (size_t)k] =
				    (unsigned char)((sum + n / 2) / n);
			}
}
