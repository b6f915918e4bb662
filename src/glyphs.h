/* glyphs.h: the sharper terminal view: a scene rendered (paint.h) into
 * square pixels, 2 x 4 to a character cell as Unicode braille or 1 x 2 as
 * half blocks, each pixel lit or not by its surface's light through an
 * ordered dither, the floor's grid and the marks (contacts, the selected
 * node) as the ASCII raster has them. The ASCII raster (raster.h) stays
 * the view where the locale is not UTF-8. No ncurses here. */
#ifndef DRAPE_GLYPHS_H
#define DRAPE_GLYPHS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "cloth.h"
#include "event.h"
#include "paint.h"
#include "raster.h"
#include "render.h"
#include "scene.h"

enum glyphs {
	GLYPHS_AUTO,		/* braille where the locale is UTF-8, else ASCII */
	GLYPHS_ASCII,
	GLYPHS_BRAILLE,		/* 2 x 4 pixels a cell */
	GLYPHS_BLOCKS,		/* 1 x 2 pixels a cell: half blocks */
	GLYPHS_COUNT,
};

/* "auto", "ascii", "braille", "blocks", by mode. */
extern const char *const glyphs_name[GLYPHS_COUNT];

/* Whether the locale's character set is UTF-8: sets LC_CTYPE (only) from
 * the environment and asks nl_langinfo(CODESET). */
bool glyphs_locale_utf8(void);

/* GLYPHS_AUTO resolved for a locale that is (or is not) UTF-8. */
enum glyphs glyphs_resolve(enum glyphs g, bool utf8);

struct glyphs_grid {
	enum glyphs mode;	/* braille or blocks */
	int w, h;		/* character cells */
	int px, py;		/* pixels a cell */
	struct render im;	/* w*px x h*py square pixels */
	uint32_t *cp;		/* per cell: a code point, ' ' for nothing */
	unsigned char *bits;	/* per cell: its pixels lit, bit k for braille dot k+1
				 * (a half block: 1 the top, 2 the bottom) */
	unsigned char *kind;	/* per cell: the enum cell_kind it shows most */
	struct rgb *colour;	/* per cell: the mean colour of that kind's pixels */
};

void glyphs_init(struct glyphs_grid *g);
/* mode braille or blocks, w x h cells >= 1. Returns 0, or -1 out of memory
 * (the grid is then empty). */
int glyphs_resize(struct glyphs_grid *g, enum glyphs mode, int w, int h);
void glyphs_free(struct glyphs_grid *g);

/* The cells from the pixels of g->im (however they were drawn). */
void glyphs_convert(struct glyphs_grid *g);

/* paint_scene into the pixels, the cells from them, then the marks: VIEW_MARK_CONTACT
 * on the nodes of ev, VIEW_MARK_SELECTED on selected (or -1). Returns 0,
 * or -1 out of memory. */
int glyphs_draw(struct glyphs_grid *g, const struct camera *cam, const struct scene *sc,
    const struct cloth *cl, const double *x, const double *field, const struct paint_opts *o,
    const struct contact_event *ev, size_t nev, int selected);

/* Writes the UTF-8 of code point cp (< 0x10000) into out (4 bytes with
 * the terminator); returns its length. */
int glyphs_utf8(uint32_t cp, char out[4]);

/* Row row of the grid as UTF-8 without its trailing blanks, into buf of
 * len bytes (3 a cell and one more suffice). */
void glyphs_row(const struct glyphs_grid *g, int row, char *buf, size_t len);

#endif
