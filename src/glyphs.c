/* glyphs.c: pixels to braille cells and half blocks. */
#include <langinfo.h>
#include <locale.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "glyphs.h"
#include "view.h"

const char *const glyphs_name[GLYPHS_COUNT] = { "auto", "ascii", "braille", "blocks" };

bool
glyphs_locale_utf8(void)
{
	const char *cs;

	if (setlocale(LC_CTYPE, "") == NULL)
		return false;
	cs = nl_langinfo(CODESET);
	return cs != NULL && (strcasecmp(cs, "UTF-8") == 0 || strcasecmp(cs, "utf8") == 0);
}

enum glyphs
glyphs_resolve(enum glyphs g, bool utf8)
{
	if (g == GLYPHS_AUTO)
		return utf8 ? GLYPHS_BRAILLE : GLYPHS_ASCII;
	return g;
}

void
glyphs_init(struct glyphs_grid *g)
{
	memset(g, 0, sizeof *g);
	render_init(&g->im);
}

void
glyphs_free(struct glyphs_grid *g)
{
	render_free(&g->im);
	free(g->cp);
	free(g->bits);
	free(g->kind);
	free(g->colour);
	glyphs_init(g);
}

int
glyphs_resize(struct glyphs_grid *g, enum glyphs mode, int w, int h)
{
	size_t n;

	glyphs_free(g);
	if (w < 1 || h < 1 || (mode != GLYPHS_BRAILLE && mode != GLYPHS_BLOCKS))
		return -1;
	g->mode = mode;
	g->px = mode == GLYPHS_BRAILLE ? 2 : 1;
	g->py = mode == GLYPHS_BRAILLE ? 4 : 2;
	n = (size_t)w * (size_t)h;
	g->cp = malloc(n * sizeof *g->cp);
	g->bits = malloc(n);
	g->kind = malloc(n);
	g->colour = malloc(n * sizeof *g->colour);
	/* a cell is RASTER_ASPECT times as tall as wide: its pixels are square */
	if (g->cp == NULL || g->bits == NULL || g->kind == NULL || g->colour == NULL ||
	    render_resize(&g->im, w * g->px, h * g->py, RASTER_ASPECT * g->px / g->py) != 0) {
		glyphs_free(g);
		return -1;
	}
	g->w = w;
	g->h = h;
	glyphs_convert(g);
	return 0;
}

/* Which kind a cell shows when its pixels differ: marks, then the cloth,
 * then solids, then the floor. */
static int
rank(int kind)
{
	static const int r[] = { 0, 3, 2, 1, 5, 4 };

	return kind >= 0 && kind <= CELL_SELECTED ? r[kind] : 0;
}

void
glyphs_convert(struct glyphs_grid *g)
{
	/* an ordered dither: the light a pixel needs to be lit, by its place
	 * in a 2 x 4 cell (Bayer's matrix, column by column) */
	static const double need[4][2] = {
		{ 0.5 / 8, 4.5 / 8 }, { 6.5 / 8, 2.5 / 8 }, { 1.5 / 8, 5.5 / 8 }, { 7.5 / 8, 3.5 / 8 },
	};
	/* braille dots 1-8 by pixel (column, row) */
	static const unsigned char dot[4][2] = {
		{ 0x01, 0x08 }, { 0x02, 0x10 }, { 0x04, 0x20 }, { 0x40, 0x80 },
	};
	const struct render *im = &g->im;
	int cx, cy, i, j;

	for (cy = 0; cy < g->h; cy++)
		for (cx = 0; cx < g->w; cx++) {
			size_t cell = (size_t)cy * (size_t)g->w + (size_t)cx;
			unsigned bits = 0, sum[3] = { 0, 0, 0 }, count = 0;
			int best = CELL_EMPTY;

			for (j = 0; j < g->py; j++)
				for (i = 0; i < g->px; i++) {
					size_t at = (size_t)(cy * g->py + j) * (size_t)im->w +
					    (size_t)(cx * g->px + i);
					double t = g->mode == GLYPHS_BRAILLE ? need[j][i] :
					    need[(2 * (cy & 1) + j) & 3][cx & 1];

					if (im->kind[at] == CELL_EMPTY || !(im->lum[at] > t))
						continue;
					/* the floor's grid dotted, lighter than what
					 * stands on it; the obstacles hatched, every
					 * other row of pixels, so that without colour
					 * the cloth on a box stands out from it */
					if (im->kind[at] == CELL_FLOOR &&
					    ((cx * g->px + i + cy * g->py + j) & 1))
						continue;
					if (im->kind[at] == CELL_SOLID && ((cy * g->py + j) & 1))
						continue;
					bits |= g->mode == GLYPHS_BRAILLE ? dot[j][i] : 1u << j;
					if (rank(im->kind[at]) > rank(best)) {
						best = im->kind[at];
						sum[0] = sum[1] = sum[2] = count = 0;
					}
					if (im->kind[at] == best) {
						sum[0] += im->rgb[3 * at];
						sum[1] += im->rgb[3 * at + 1];
						sum[2] += im->rgb[3 * at + 2];
						count++;
					}
				}
			g->bits[cell] = (unsigned char)bits;
			g->kind[cell] = (unsigned char)best;
			if (count > 0)
				g->colour[cell] = (struct rgb){ (unsigned char)(sum[0] / count),
					(unsigned char)(sum[1] / count), (unsigned char)(sum[2] / count) };
			else
				g->colour[cell] = (struct rgb){ 0, 0, 0 };
			if (bits == 0)
				g->cp[cell] = ' ';
			else if (g->mode == GLYPHS_BRAILLE)
				g->cp[cell] = 0x2800 + bits;
			else
				g->cp[cell] = bits == 3 ? 0x2588 : bits == 1 ? 0x2580 : 0x2584;
		}
}

/* ch on the cell of p unless something nearer by more than slack covers
 * it there (always: regardless). */
static void
mark(struct glyphs_grid *g, const struct camera *cam, vec3 p, char ch, enum cell_kind kind,
    double slack, bool always)
{
	double x, y, z;
	size_t at, cell;

	if (!camera_project(cam, p, g->im.w, g->im.h, g->im.aspect, &x, &y, &z) ||
	    !(x >= 0 && x < g->im.w && y >= 0 && y < g->im.h))
		return;
	at = (size_t)(int)y * (size_t)g->im.w + (size_t)(int)x;
	if (!always && z + slack < g->im.depth[at])
		return;
	cell = (size_t)((int)y / g->py) * (size_t)g->w + (size_t)((int)x / g->px);
	g->cp[cell] = (unsigned char)ch;
	g->kind[cell] = (unsigned char)kind;
}

int
glyphs_draw(struct glyphs_grid *g, const struct camera *cam, const struct scene *sc,
    const struct cloth *cl, const double *x, const double *field, const struct paint_opts *o,
    const struct contact_event *ev, size_t nev, int selected)
{
	size_t k;

	if (g->w < 1 || paint_scene(&g->im, cam, sc, cl, x, field, o) != 0)
		return -1;
	glyphs_convert(g);
	for (k = 0; k < nev; k++)
		if (ev[k].node >= 0 && ev[k].node < cl->n)
			mark(g, cam, v3_load(x + 3 * ev[k].node), VIEW_MARK_CONTACT, CELL_CONTACT,
			    0.02 * cam->radius, false);
	if (selected >= 0 && selected < cl->n)
		mark(g, cam, v3_load(x + 3 * selected), VIEW_MARK_SELECTED, CELL_SELECTED, 0, true);
	return 0;
}

int
glyphs_utf8(uint32_t cp, char out[4])
{
	if (cp < 0x80) {
		out[0] = (char)cp;
		out[1] = '\0';
		return 1;
	}
	if (cp < 0x800) {
		out[0] = (char)(0xC0 | (cp >> 6));
		out[1] = (char)(0x80 | (cp & 0x3F));
		out[2] = '\0';
		return 2;
	}
	out[0] = (char)(0xE0 | ((cp >> 12) & 0x0F));
	out[1] = (char)(0x80 | ((cp >> 6) & 0x3F));
	out[2] = (char)(0x80 | (cp & 0x3F));
	out[3] = '\0';
	return 3;
}

void
glyphs_row(const struct glyphs_grid *g, int row, char *buf, size_t len)
{
	const uint32_t *cp = g->cp + (size_t)row * (size_t)g->w;
	int n = g->w, i;
	size_t at = 0;

	while (n > 0 && cp[n - 1] == ' ')
		n--;
	for (i = 0; i < n && at + 4 <= len; i++)
		at += (size_t)glyphs_utf8(cp[i], buf + at);
	if (len > 0)
		buf[at < len ? at : len - 1] = '\0';
}
