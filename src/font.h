/* font.h: a 5 x 7 bitmap font (printable ASCII, after the HD44780's
 * character set) for the labels of a picture: times, legends, names. */
#ifndef DRAPE_FONT_H
#define DRAPE_FONT_H

#include "render.h"

#define FONT_W 5
#define FONT_H 7
#define FONT_ADVANCE 6		/* a glyph and its space */

/* The width in pixels of s at scale (each font pixel a scale x scale
 * square). */
int font_width(const char *s, int scale);

/* Draws s into a w x h RGB image (3 bytes a pixel) with its top left at
 * (x, y); what falls outside is left out. */
void font_draw(unsigned char *rgb, int w, int h, int x, int y, const char *s, int scale,
    struct rgb c);

#endif
