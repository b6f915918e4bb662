/* units.h: numbers with their unit, converted to SI. A scene's
 * dimensional keys require the unit (a bare 150 for a weight was read as
 * 150 kg/m2); a command line's times and lengths may go without one. */
#ifndef DRAPE_UNITS_H
#define DRAPE_UNITS_H

#include <stddef.h>

enum unit_dim {
	DIM_NONE,		/* a pure number: no unit accepted */
	DIM_LENGTH,		/* m */
	DIM_TIME,		/* s */
	DIM_AREAL_DENSITY,	/* kg/m2 */
	DIM_PRESSURE,		/* Pa */
	DIM_BENDING,		/* N*m (bending rigidity per unit width) */
	DIM_FORCE,		/* N */
	DIM_VELOCITY,		/* m/s */
	DIM_ACCEL,		/* m/s2 */
	DIM_RATE,		/* 1/s */
	DIM_BYTES,		/* B */
};

/* What numbers without a unit mean. */
enum units_bare {
	UNITS_BARE_SI,		/* SI units: a command line's --until 2 */
	UNITS_BARE_REFUSED,	/* nothing: the unit is required, but for zeros
				 * (0 is 0 in every unit of a dimension, all of
				 * them being factors) */
};

#define UNITS_NO_UNIT (-2)	/* units_parse_as: numbers that needed a unit */

/*
 * Parses exactly n finite numbers followed by a unit of dimension dim; a
 * missing unit is taken as bare says (DIM_NONE takes none). A value that
 * is not finite once in SI units (1e308 GPa) is refused. Returns 0,
 * UNITS_NO_UNIT when the numbers were right but their unit was required,
 * or -1 with why set to what a message may add to "expected ..., got
 * '...'", as a phrase ("unknown unit 'kg'", "not a finite number"), or
 * empty when the text is simply not the numbers expected.
 */
int units_parse_as(const char *s, enum unit_dim dim, enum units_bare bare, double *out, int n,
    char *why, size_t whylen);

/* units_parse_as with UNITS_BARE_SI: 0 or -1. */
int units_parse(const char *s, enum unit_dim dim, double *out, int n, char *why, size_t whylen);

/* "a length (m, cm, mm, um)" and the like, for error messages. */
const char *units_describe(enum unit_dim dim);

/* A value of dim with its unit, one number or three ("150 g/m2",
 * "0 0.15 0 m"), for error messages; NULL for DIM_NONE. */
const char *units_example(enum unit_dim dim, int n);

#endif
