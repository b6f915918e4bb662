/* picture.c: frames into tiles, labels and the legend band. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "font.h"
#include "paint.h"
#include "picture.h"

static const struct rgb ink = { 50, 50, 50 }, gap_colour = { 225, 225, 225 };

/* The font's scale for frames w pixels wide. */
static int
font_scale(const struct picture_opts *o)
{
	return o->w >= 400 ? 2 : 1;
}

static void
fill(unsigned char *rgb, int w, int h, int x0, int y0, int x1, int y1, struct rgb c)
{
	int x, y;

	for (y = y0 < 0 ? 0 : y0; y < y1 && y < h; y++)
		for (x = x0 < 0 ? 0 : x0; x < x1 && x < w; x++) {
			unsigned char *p = rgb + 3 * ((size_t)y * (size_t)w + (size_t)x);

			p[0] = c.r;
			p[1] = c.g;
			p[2] = c.b;
		}
}

/* Text ending at x (right-aligned); returns where it starts. */
static int
text_left_of(unsigned char *rgb, int w, int h, int x, int y, const char *s, int sc)
{
	int start = x - font_width(s, sc);

	font_draw(rgb, w, h, start, y, s, sc, ink);
	return start;
}

static struct rgb
colour_of(enum colouring c, double v, double range)
{
	float f[3];

	colouring_colour(c, v, range, f);
	return render_rgb(f);
}

/* A swatch and its name, ending at x; returns where they start. */
static int
swatch(unsigned char *rgb, int w, int h, int x, int y, int sc, struct rgb c, const char *name)
{
	x = text_left_of(rgb, w, h, x, y, name, sc) - 3 * sc;
	fill(rgb, w, h, x - FONT_H * sc, y, x, y + FONT_H * sc, c);
	return x - FONT_H * sc;
}

/* The band's left text: the scene's name and the floor grid's spacing. */
static void
band_name(const struct scene *sc, const struct camera *cam, const struct picture_opts *o,
    char *buf, size_t len)
{
	bool floor = false;
	size_t i;

	for (i = 0; i < sc->nobstacles; i++)
		floor = floor || sc->obstacles[i].kind == OBSTACLE_PLANE;
	buf[0] = '\0';
	if (o->title != NULL)
		snprintf(buf, len, "%s", o->title);
	if (floor) {
		double g = paint_floor_spacing(cam);

		snprintf(buf + strlen(buf), len - strlen(buf), "%sgrid %g %s",
		    buf[0] != '\0' ? "   " : "", g >= 1 ? g : g >= 0.01 ? 100 * g : 1000 * g,
		    g >= 1 ? "m" : g >= 0.01 ? "cm" : "mm");
	}
}

/* The colouring's legend ending at x on row y; returns where it starts.
 * With w and h 0 nothing is drawn (font_draw and fill clip it all away),
 * so that the same code measures it. compact: shorter words and a shorter
 * bar, for a picture too narrow for the whole legend. */
static int
legend(unsigned char *rgb, int w, int h, int x, int y, const struct picture_opts *o,
    bool compact)
{
	int s = font_scale(o), k;
	enum colouring c = o->colouring;
	char lo[32], hi[32];

	switch (c) {
	case COLOUR_SHADE:
		x = swatch(rgb, w, h, x, y, s, colour_of(c, -1, 1), "back") - 8 * s;
		return swatch(rgb, w, h, x, y, s, colour_of(c, 1, 1), "front");
	case COLOUR_CONTACT:
		x = swatch(rgb, w, h, x, y, s, colour_of(c, TOUCH_CLOTH, 1),
		    compact ? "cloth" : "with the cloth") - 8 * s;
		x = swatch(rgb, w, h, x, y, s, colour_of(c, TOUCH_OBSTACLE, 1),
		    compact ? "obstacle" : "with an obstacle") - 8 * s;
		return text_left_of(rgb, w, h, x, y, compact ? "contact:" : "in contact:", s);
	default: {
		int bar = (compact ? 40 : 100) * s, lo_v = colouring_is_signed(c) ? -1 : 0;

		colouring_label(c, lo_v * o->range, lo, sizeof lo);
		colouring_label(c, o->range, hi, sizeof hi);
		x = text_left_of(rgb, w, h, x, y, hi, s) - 3 * s;
		for (k = 0; k < bar; k++) {
			double v = o->range * (lo_v + (1.0 - lo_v) * (k + 0.5) / bar);

			fill(rgb, w, h, x - bar + k, y, x - bar + k + 1, y + FONT_H * s,
			    colour_of(c, v, o->range));
		}
		x = text_left_of(rgb, w, h, x - bar - 3 * s, y, lo, s) - 6 * s;
		return text_left_of(rgb, w, h, x, y,
		    compact ? colouring_name[c] : colouring_title[c], s);
	}
	}
}

/* The frames and their gaps, side by side. */
static int
frames_width(const struct picture_opts *o, size_t nfr)
{
	return (int)nfr * o->w + (int)(nfr > 0 ? nfr - 1 : 0) * PICTURE_GAP;
}

static int
picture_width(const struct picture_opts *o, size_t nfr)
{
	int w = frames_width(o, nfr);

	return o->width > w ? o->width : w;
}

void
picture_band(const struct scene *sc, const struct camera *cam, const struct picture_opts *o,
    size_t nfr, struct picture_band *b)
{
	int s = font_scale(o), w = picture_width(o, nfr);
	char name[96];

	band_name(sc, cam, o, name, sizeof name);
	b->name_w = font_width(name, s);
	b->compact = false;
	b->legend_w = -legend(NULL, 0, 0, 0, 0, o, false);
	if (b->legend_w > w - 12 * s) {
		b->compact = true;
		b->legend_w = -legend(NULL, 0, 0, 0, 0, o, true);
	}
	b->y_name = 5 * s;
	/* the legend beside the name where both fit with a gap, else under it */
	if (b->name_w == 0 || 6 * s + b->name_w + 12 * s <= w - 6 * s - b->legend_w) {
		b->lines = 1;
		b->y_legend = b->y_name;
	} else {
		b->lines = 2;
		b->y_legend = b->y_name + (FONT_H + 5) * s;
	}
	b->h = b->y_legend + (FONT_H + 5) * s;	/* 5 * s - 1 rows under the text */
}

void
picture_size(const struct scene *sc, const struct camera *cam, const struct picture_opts *o,
    size_t nfr, int *w, int *h)
{
	struct picture_band b;

	picture_band(sc, cam, o, nfr, &b);
	*w = picture_width(o, nfr);
	*h = o->h + b.h;
}

int
picture_fit(const struct scene *sc, const struct camera *cam, struct picture_opts *o,
    size_t nfr, int w, int h, int min_side)
{
	struct picture_band b;
	int k = nfr > 0 ? (int)nfr : 1;

	o->width = w;
	o->w = (w - (k - 1) * PICTURE_GAP) / k;	/* what is left over: margins */
	picture_band(sc, cam, o, nfr, &b);	/* its height follows o->w's font */
	o->h = h - b.h;
	return o->w >= min_side && o->h >= min_side ? 0 : -1;
}

/* The band under the frames, at row y0. */
static void
band(unsigned char *rgb, int w, int h, int y0, const struct scene *sc,
    const struct camera *cam, const struct picture_opts *o, size_t nfr)
{
	struct picture_band b;
	int s = font_scale(o);
	char name[96];

	picture_band(sc, cam, o, nfr, &b);
	band_name(sc, cam, o, name, sizeof name);
	font_draw(rgb, w, h, 6 * s, y0 + b.y_name, name, s, ink);
	legend(rgb, w, h, w - 6 * s, y0 + b.y_legend, o, b.compact);
}

int
picture_time_decimals(const double *t, size_t n)
{
	double gap = 1e30, tol;
	size_t f;
	int d;

	/* as many decimals as tell the frames apart */
	for (f = 1; f < n; f++)
		if (t[f] - t[f - 1] > 0 && t[f] - t[f - 1] < gap)
			gap = t[f] - t[f - 1];
	d = gap < 1e30 ? (int)ceil(-log10(gap) - 1e-6) : 3;
	d = d < 0 ? 0 : d > 6 ? 6 : d;
	/* and more while a time is not what its label says: a replay's frame
	 * nearest 0.15 s of a strip 0,0.15,0.3 is at 0.14 s, not "0.1" */
	tol = 0.1 * pow(10, -d);
	for (; d < 6; d++) {
		double scale = pow(10, d);

		for (f = 0; f < n; f++)
			if (fabs(t[f] - round(t[f] * scale) / scale) > tol)
				break;
		if (f == n)
			break;
	}
	return d;
}

int
picture_strip(const struct scene *sc, const struct cloth *cl, const struct camera *cam,
    const struct picture_frame *fr, size_t nfr, const struct picture_opts *o,
    unsigned char **rgb, int *w, int *h, struct drape_err *err)
{
	struct render im;
	struct paint_opts po = { o->colouring, o->range, 4.0 * o->supersample, false };
	int ss = o->supersample < 1 ? 1 : o->supersample, s = font_scale(o), y, fx, decimals, x0;
	unsigned char *tile = NULL, *out;
	double *times;
	size_t f;

	picture_size(sc, cam, o, nfr, w, h);
	*rgb = NULL;
	render_init(&im);
	out = malloc(3 * (size_t)*w * (size_t)*h);
	tile = malloc(3 * (size_t)o->w * (size_t)o->h);
	times = calloc(nfr > 0 ? nfr : 1, sizeof *times);
	if (out == NULL || tile == NULL || times == NULL ||
	    render_resize(&im, o->w * ss, o->h * ss, 1) != 0)
		goto oom;
	fill(out, *w, *h, 0, 0, *w, *h, PAINT_BACKGROUND);
	x0 = (*w - frames_width(o, nfr)) / 2;	/* a fitted picture's margins */
	for (f = 0; f < nfr; f++)
		times[f] = fr[f].t;
	decimals = picture_time_decimals(times, nfr);
	for (f = 0; f < nfr; f++) {
		char label[64];

		if (paint_scene(&im, cam, sc, cl, fr[f].x, fr[f].field, &po) != 0)
			goto oom;
		render_downsample(im.rgb, im.w, im.h, ss, tile);
		fx = x0 + (int)f * (o->w + PICTURE_GAP);
		for (y = 0; y < o->h; y++)
			memcpy(out + 3 * ((size_t)y * (size_t)*w + (size_t)fx),
			    tile + 3 * (size_t)y * (size_t)o->w, 3 * (size_t)o->w);
		if (f + 1 < nfr)
			fill(out, *w, *h, fx + o->w, 0, fx + o->w + PICTURE_GAP, o->h, gap_colour);
		snprintf(label, sizeof label, "t = %.*f s", decimals, fr[f].t);
		font_draw(out, *w, *h, fx + 5 * s, 5 * s, label, s, ink);
	}
	fill(out, *w, *h, 0, o->h, *w, o->h + 1, gap_colour);
	band(out, *w, *h, o->h + 1, sc, cam, o, nfr);
	render_free(&im);
	free(tile);
	free(times);
	*rgb = out;
	return 0;
oom:
	render_free(&im);
	free(tile);
	free(times);
	free(out);
	err_set(err, "out of memory for a picture of %d x %d pixels", *w, *h);
	return -1;
}
