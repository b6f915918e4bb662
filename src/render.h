/* render.h: a software renderer: an RGB image with a z-buffer, into which
 * triangles (each vertex with its own lit colour: Gouraud shading, or flat
 * when the three are equal), lines and dots are drawn through raster.h's
 * camera. Pixels may be square (a PNG, the 2x4 and 1x2 pixels of a
 * Unicode cell) or as tall as a terminal cell. It knows nothing of scenes
 * (paint.c draws one into it) and nothing of files (png.c writes one). */
#ifndef DRAPE_RENDER_H
#define DRAPE_RENDER_H

#include <stdbool.h>
#include <stddef.h>

#include "raster.h"
#include "vec3.h"

struct rgb {
	unsigned char r, g, b;
};

struct render {
	int w, h;
	double aspect;		/* pixel height over width */
	unsigned char *rgb;	/* 3 per pixel, row by row from the top */
	double *depth;		/* view-space z (larger is nearer), -INFINITY: nothing */
	unsigned char *kind;	/* enum cell_kind */
	float *lum;		/* how lit the surface is, 0..1, without its colour */
	double bias;		/* m added to the depth of what is drawn (0 after a
				 * resize): a surface lying on another wins */
};

/* A vertex of a triangle: where it is, its colour (lit, 0..1 each) and how
 * lit it is (for renderings that have no colour: braille dots). */
struct render_vertex {
	vec3 p;
	float c[3];
	float lum;
};

/* The renderer starts empty (w = h = 0). */
void render_init(struct render *im);
/* Resizes (w, h >= 1) and clears to black. Returns 0, or -1 out of memory
 * (then the image is empty). */
int render_resize(struct render *im, int w, int h, double aspect);
/* Every pixel bg, nothing in the z-buffer. */
void render_clear(struct render *im, struct rgb bg);
void render_free(struct render *im);

/* Fills the pixels whose centres the triangle covers and that it is nearer
 * in, each with the colour interpolated from the vertices. A triangle seen
 * nearly edge-on also draws its edges, so that it never vanishes. */
void render_triangle(struct render *im, const struct camera *cam, const struct render_vertex *a,
    const struct render_vertex *b, const struct render_vertex *c, enum cell_kind kind);

/* A line one pixel wide from a to b, drawn where nothing is nearer than it
 * by more than slack (m); it does not write the z-buffer, so that lines
 * over a surface never hide one another. */
void render_line(struct render *im, const struct camera *cam, vec3 a, vec3 b, struct rgb c,
    double slack, enum cell_kind kind);

/* As render_line, but the pixels under the line keep their colour times
 * factor (0..1): a line that darkens whatever surface it is drawn on. */
void render_line_darken(struct render *im, const struct camera *cam, vec3 a, vec3 b,
    double factor, double slack);

/* A filled disc of radius px pixels at p, drawn where nothing is nearer by
 * more than slack (always: regardless of depth); it writes the z-buffer. */
void render_dot(struct render *im, const struct camera *cam, vec3 p, double px, struct rgb c,
    double slack, bool always, enum cell_kind kind);

/* The pixel at (x, y) (inside the image). */
static inline struct rgb
render_at(const struct render *im, int x, int y)
{
	const unsigned char *p = im->rgb + 3 * ((size_t)y * (size_t)im->w + (size_t)x);

	return (struct rgb){ p[0], p[1], p[2] };
}

static inline void
render_set(struct render *im, int x, int y, struct rgb c)
{
	unsigned char *p = im->rgb + 3 * ((size_t)y * (size_t)im->w + (size_t)x);

	p[0] = c.r;
	p[1] = c.g;
	p[2] = c.b;
}

/* 0..1 floats to a pixel, clamped and rounded. */
struct rgb render_rgb(const float c[3]);

/* A w x h image (3 bytes a pixel) shrunk by an integer factor, each pixel
 * the mean of a factor x factor square (anti-aliasing); out holds
 * (w / factor) x (h / factor) pixels. */
void render_downsample(const unsigned char *in, int w, int h, int factor, unsigned char *out);

#endif
