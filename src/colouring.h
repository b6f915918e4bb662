/* colouring.h: what a view colours the cloth by, as a value per node: its
 * stretch strain along the warp or the weft ((l - rest) / rest, the mean
 * over the node's springs of that direction), its shear (pi/2 minus the
 * angle of its squares' corners at the node, radians, the mean), the
 * largest of the three, or whether it is in contact this step (with an
 * obstacle or with the cloth); and the colour scales of those values. No
 * drawing here: paint.c (pictures, Unicode views) and tui.c (the ASCII
 * view's colours) use it. */
#ifndef DRAPE_COLOURING_H
#define DRAPE_COLOURING_H

#include <stdbool.h>
#include <stddef.h>

#include "cloth.h"
#include "event.h"

enum colouring {
	COLOUR_SHADE,		/* the cloth's own colour, front and back, shaded */
	COLOUR_STRAIN,		/* the largest of |warp|, |weft| and |shear| */
	COLOUR_WARP,
	COLOUR_WEFT,
	COLOUR_SHEAR,
	COLOUR_CONTACT,		/* nodes in contact this step */
	COLOUR_COUNT,
};

/* Per-node values of COLOUR_CONTACT. */
enum { TOUCH_NONE, TOUCH_OBSTACLE, TOUCH_CLOTH };

/* "shade", "strain", "warp", "weft", "shear", "contact", by colouring. */
extern const char *const colouring_name[COLOUR_COUNT];
/* What the legend calls it: "warp strain", ... */
extern const char *const colouring_title[COLOUR_COUNT];

/* The colouring of that name, or -1. */
int colouring_from_name(const char *name);

/* A strain colouring: a value per node on a scale from 0 (or -range) to
 * range. */
bool colouring_is_strain(enum colouring c);
/* Its scale runs from -range to range (warp, weft, shear), else from 0. */
bool colouring_is_signed(enum colouring c);

/* The value of every node (n of out) for c at positions x; ev (nev) are
 * this step's contact events. COLOUR_SHADE gives zeros. Returns 0, or -1
 * out of memory. */
int colouring_field(enum colouring c, const struct cloth *cl, const double *x,
    const struct contact_event *ev, size_t nev, double *out);

/* The unit a strain scale is given and labelled in (--range, the legend):
 * a percent of strain, or a degree of shear, in c's own values. */
double colouring_unit(enum colouring c);

/* The range of c's scale that holds magnitudes up to m: 1, 2 or 5 times a
 * power of ten at or above m (in %, or for shear in degrees); 1 % (1
 * degree) when m is under 0.01 % (0.01 degree: rounding, not strain) or
 * not finite. */
double colouring_range(enum colouring c, double m);

/* The colour (0..1 each) of value v on c's scale of that range, unlit; for
 * COLOUR_SHADE the cloth's front (v >= 0) or back (v < 0) colour. */
void colouring_colour(enum colouring c, double v, double range, float out[3]);

/* The value v as the legend writes it: "+2%", "-1.5 deg", "0". */
void colouring_label(enum colouring c, double v, char *buf, size_t len);

/* The band (0 to levels - 1) of v on c's scale, for a terminal's few
 * colours: levels bands from -range (or 0) to range. */
int colouring_band(enum colouring c, double v, double range, int levels);

#endif
