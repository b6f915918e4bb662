/* units.h: numbers with an optional unit, converted to SI. */
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

/*
 * Parses exactly n finite numbers followed by an optional unit of dimension
 * dim (a missing unit means SI); a value that is not finite once in SI
 * units (1e308 GPa) is refused. Returns 0, or -1 with why set to what a
 * message may add to "expected ..., got '...'", as a phrase ("unknown unit
 * 'kg'", "not a finite number"), or empty when the text is simply not the
 * numbers expected.
 */
int units_parse(const char *s, enum unit_dim dim, double *out, int n, char *why, size_t whylen);

/* "a length (m, cm, mm, um)" and the like, for error messages. */
const char *units_describe(enum unit_dim dim);

#endif
