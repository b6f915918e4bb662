/* picture.h: a picture of a run: one or more frames side by side, as the
 * chapter's figures lay them out, each rendered (paint.h) with its time
 * written on it, and under them a band with the scene's name, the floor
 * grid's spacing and the legend of the colouring with its scale. */
#ifndef DRAPE_PICTURE_H
#define DRAPE_PICTURE_H

#include <stddef.h>

#include "cloth.h"
#include "colouring.h"
#include "err.h"
#include "raster.h"
#include "scene.h"

#define PICTURE_GAP 4		/* pixels between frames */

struct picture_frame {
	double t;
	const double *x;	/* 3n positions */
	const double *field;	/* the colouring's value of each node, or NULL */
};

struct picture_opts {
	int w, h;		/* of a frame, pixels */
	enum colouring colouring;
	double range;		/* of a strain scale, > 0 */
	const char *title;	/* the scene's name, or NULL */
	int supersample;	/* rendered this many times larger, then averaged */
	int width;		/* of the picture, when wider than its frames and
				 * gaps (picture_fit): the frames centred; 0 none */
};

/* The band under nfr frames: the name (and the floor grid's spacing) at
 * its left and the legend at its right on one line where both fit, else
 * the legend on a second line under the name; rows from the band's top.
 * A legend wider than the picture is made compact (shorter words, a
 * shorter bar). */
struct picture_band {
	int lines;		/* 1 or 2 */
	bool compact;
	int name_w, legend_w;	/* pixels */
	int y_name, y_legend;	/* the text's top rows */
	int h;			/* the band's height, with the line above it */
};
void picture_band(const struct scene *sc, const struct camera *cam,
    const struct picture_opts *o, size_t nfr, struct picture_band *b);

/* The picture's size for nfr frames. */
void picture_size(const struct scene *sc, const struct camera *cam,
    const struct picture_opts *o, size_t nfr, int *w, int *h);

/* The frames' size (o->w, o->h, and o->width) that makes the picture of
 * nfr frames exactly w x h pixels, the band under them included (o's
 * colouring, range and title as they will be drawn). Returns 0, or -1
 * when a frame would be under min_side pixels either way (o->w and o->h
 * then say how small). */
int picture_fit(const struct scene *sc, const struct camera *cam, struct picture_opts *o,
    size_t nfr, int w, int h, int min_side);

/* The decimals of the frames' time labels (t, n of them, in time order):
 * enough to tell them apart, and more while a time differs from its label
 * by more than a tenth of that label's last digit. */
int picture_time_decimals(const double *t, size_t n);

/* Renders the frames through cam into *rgb (malloc'd, 3 bytes a pixel,
 * *w x *h as picture_size says). Returns 0, or -1 out of memory with a
 * message. */
int picture_strip(const struct scene *sc, const struct cloth *cl, const struct camera *cam,
    const struct picture_frame *fr, size_t nfr, const struct picture_opts *o,
    unsigned char **rgb, int *w, int *h, struct drape_err *err);

#endif
