/* units.c: the unit table. Units are matched exactly, case-sensitively. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "units.h"

struct unit {
	enum unit_dim dim;
	const char *name;
	double factor;		/* to SI */
};

#define GF 9.80665e-3		/* gram-force in N */

static const struct unit units[] = {
	{ DIM_LENGTH, "m", 1 }, { DIM_LENGTH, "cm", 1e-2 }, { DIM_LENGTH, "mm", 1e-3 },
	{ DIM_LENGTH, "um", 1e-6 },
	{ DIM_TIME, "s", 1 }, { DIM_TIME, "ms", 1e-3 }, { DIM_TIME, "us", 1e-6 },
	{ DIM_AREAL_DENSITY, "kg/m2", 1 }, { DIM_AREAL_DENSITY, "g/m2", 1e-3 },
	{ DIM_AREAL_DENSITY, "gsm", 1e-3 }, { DIM_AREAL_DENSITY, "mg/cm2", 1e-2 },
	{ DIM_PRESSURE, "Pa", 1 }, { DIM_PRESSURE, "kPa", 1e3 }, { DIM_PRESSURE, "MPa", 1e6 },
	{ DIM_PRESSURE, "GPa", 1e9 },
	{ DIM_BENDING, "N*m", 1 }, { DIM_BENDING, "mN*m", 1e-3 }, { DIM_BENDING, "uN*m", 1e-6 },
	/* Kawabata's KES-FB2 reports B in gf*cm2/cm. */
	{ DIM_BENDING, "gf*cm2/cm", GF * 1e-4 / 1e-2 },
	{ DIM_FORCE, "N", 1 }, { DIM_FORCE, "mN", 1e-3 }, { DIM_FORCE, "gf", GF },
	{ DIM_VELOCITY, "m/s", 1 }, { DIM_VELOCITY, "cm/s", 1e-2 }, { DIM_VELOCITY, "mm/s", 1e-3 },
	{ DIM_ACCEL, "m/s2", 1 },
	{ DIM_RATE, "1/s", 1 }, { DIM_RATE, "/s", 1 }, { DIM_RATE, "Hz", 1 },
	{ DIM_BYTES, "B", 1 }, { DIM_BYTES, "kB", 1e3 }, { DIM_BYTES, "MB", 1e6 },
	{ DIM_BYTES, "GB", 1e9 }, { DIM_BYTES, "KiB", 1024.0 }, { DIM_BYTES, "MiB", 1048576.0 },
	{ DIM_BYTES, "GiB", 1073741824.0 },
};

const char *
units_describe(enum unit_dim dim)
{
	switch (dim) {
	case DIM_NONE: return "a number";
	case DIM_LENGTH: return "a length (m, cm, mm, um)";
	case DIM_TIME: return "a time (s, ms, us)";
	case DIM_AREAL_DENSITY: return "a weight per area (g/m2, gsm, mg/cm2, kg/m2)";
	case DIM_PRESSURE: return "a modulus (Pa, kPa, MPa, GPa)";
	case DIM_BENDING: return "a bending rigidity (N*m, mN*m, uN*m, gf*cm2/cm)";
	case DIM_FORCE: return "a force (N, mN, gf)";
	case DIM_VELOCITY: return "a velocity (m/s, cm/s, mm/s)";
	case DIM_ACCEL: return "an acceleration (m/s2)";
	case DIM_RATE: return "a rate (1/s, /s, Hz)";
	case DIM_BYTES: return "a size (B, kB, MB, GB, KiB, MiB, GiB)";
	}
	return "a value";
}

const char *
units_example(enum unit_dim dim, int n)
{
	switch (dim) {
	case DIM_NONE: return NULL;
	case DIM_LENGTH: return n == 1 ? "10 mm" : "0 0.15 0 m";
	case DIM_TIME: return "2 s";
	case DIM_AREAL_DENSITY: return "150 g/m2";
	case DIM_PRESSURE: return "0.45 MPa";
	case DIM_BENDING: return "3 uN*m";
	case DIM_FORCE: return n == 1 ? "0.02 mN" : "0 0 0.02 mN";
	case DIM_VELOCITY: return n == 1 ? "0.25 m/s" : "0 -0.25 0 m/s";
	case DIM_ACCEL: return n == 1 ? "9.80665 m/s2" : "0 -9.80665 0 m/s2";
	case DIM_RATE: return "2 /s";
	case DIM_BYTES: return "512 MB";
	}
	return NULL;
}

static int
number_start(const char *s)
{
	return isdigit((unsigned char)s[0]) || s[0] == '.' ||
	    ((s[0] == '-' || s[0] == '+') && (isdigit((unsigned char)s[1]) || s[1] == '.'));
}

/* The SI unit of a dimension: its unit of factor 1. */
static const char *
si_name(enum unit_dim dim)
{
	size_t i;

	for (i = 0; i < sizeof units / sizeof units[0]; i++)
		if (units[i].dim == dim && units[i].factor == 1)
			return units[i].name;
	return "SI units";
}

/* Not a number at all: the caller's "expected ..., got '...'" says it. */
static void
no_reason(char *why, size_t whylen)
{
	if (whylen > 0)
		why[0] = '\0';
}

int
units_parse(const char *s, enum unit_dim dim, double *out, int n, char *why, size_t whylen)
{
	return units_parse_as(s, dim, UNITS_BARE_SI, out, n, why, whylen) == 0 ? 0 : -1;
}

/* Every number zero: the same in any unit. */
static int
all_zero(const double *v, int n)
{
	int k;

	for (k = 0; k < n; k++)
		if (v[k] != 0)
			return 0;
	return 1;
}

int
units_parse_as(const char *s, enum unit_dim dim, enum units_bare bare, double *out, int n,
    char *why, size_t whylen)
{
	const char *unit = NULL;
	double factor = 1;
	char *end;
	int k;

	for (k = 0; k < n; k++) {
		while (isspace((unsigned char)*s))
			s++;
		if (!number_start(s)) {
			const char *w = s + (*s == '-' || *s == '+');

			if (strncasecmp(w, "nan", 3) == 0 || strncasecmp(w, "inf", 3) == 0)
				snprintf(why, whylen, "not a finite number");
			else if (k > 0)
				snprintf(why, whylen, "%d number%s, not %d", k, k == 1 ? "" : "s", n);
			else
				no_reason(why, whylen);
			return -1;
		}
		out[k] = strtod(s, &end);
		if (!isfinite(out[k])) {
			snprintf(why, whylen, "not a finite number");
			return -1;
		}
		if (*end != '\0' && !isspace((unsigned char)*end) && !isalpha((unsigned char)*end) &&
		    *end != '/' && *end != '*') {
			no_reason(why, whylen);
			return -1;
		}
		s = end;
	}
	while (isspace((unsigned char)*s))
		s++;
	if (*s != '\0') {
		size_t i;

		if (number_start(s)) {
			snprintf(why, whylen, "more than %d number%s", n, n == 1 ? "" : "s");
			return -1;
		}
		for (i = 0; i < sizeof units / sizeof units[0]; i++)
			if (units[i].dim == dim && strcmp(units[i].name, s) == 0)
				break;
		if (i == sizeof units / sizeof units[0]) {
			if (dim == DIM_NONE)
				snprintf(why, whylen, "a number takes no unit, found '%s'", s);
			else
				snprintf(why, whylen, "unknown unit '%s'", s);
			return -1;
		}
		factor = units[i].factor;
		unit = units[i].name;
	} else if (dim != DIM_NONE && bare == UNITS_BARE_REFUSED && !all_zero(out, n)) {
		no_reason(why, whylen);
		return UNITS_NO_UNIT;
	}
	for (k = 0; k < n; k++) {
		double si = out[k] * factor;

		/* 1e308 GPa is a finite number in a unit that is not one in Pa */
		if (!isfinite(si)) {
			snprintf(why, whylen, "%g %s is past the largest number in %s", out[k], unit,
			    si_name(dim));
			return -1;
		}
		out[k] = si;
	}
	return 0;
}
