/* colouring.c: strain and contact per node, and the colour scales: a
 * diverging blue-white-red for signed strains, a yellow-to-red one for
 * magnitudes, two colours for contact. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "colouring.h"

const char *const colouring_name[COLOUR_COUNT] = { "shade", "strain", "warp", "weft", "shear",
	"contact" };
const char *const colouring_title[COLOUR_COUNT] = { "shading", "largest strain",
	"warp strain", "weft strain", "shear angle", "contact" };

int
colouring_from_name(const char *name)
{
	int k;

	for (k = 0; k < COLOUR_COUNT; k++)
		if (strcmp(name, colouring_name[k]) == 0)
			return k;
	return -1;
}

bool
colouring_is_strain(enum colouring c)
{
	return c == COLOUR_STRAIN || c == COLOUR_WARP || c == COLOUR_WEFT || c == COLOUR_SHEAR;
}

bool
colouring_is_signed(enum colouring c)
{
	return c == COLOUR_WARP || c == COLOUR_WEFT || c == COLOUR_SHEAR;
}

static double
dist(const double *x, int a, int b)
{
	return v3_len(v3_sub(v3_load(x + 3 * a), v3_load(x + 3 * b)));
}

/* The mean stretch of each node's springs along the warp (dir 0: the two
 * ends on one grid row) or the weft. */
static void
stretch(const struct cloth *cl, const double *x, int dir, double *out, int *count)
{
	size_t k;
	int p, ia, ja, ib, jb;

	memset(count, 0, (size_t)cl->n * sizeof *count);
	for (p = 0; p < cl->n; p++)
		out[p] = 0;
	for (k = 0; k < cl->nsprings; k++) {
		const struct spring *s = &cl->springs[k];
		double e;

		cloth_grid_ij(cl, s->a, &ia, &ja);
		cloth_grid_ij(cl, s->b, &ib, &jb);
		if ((ja == jb) != (dir == 0) || !(s->rest > 0))
			continue;
		e = dist(x, s->a, s->b) / s->rest - 1;
		out[s->a] += e;
		out[s->b] += e;
		count[s->a]++;
		count[s->b]++;
	}
	for (p = 0; p < cl->n; p++)
		if (count[p] > 0)
			out[p] /= count[p];
}

/* The mean shear angle at each node's corners. */
static void
shear(const struct cloth *cl, const double *x, double *out, int *count)
{
	size_t k;
	int p;

	memset(count, 0, (size_t)cl->n * sizeof *count);
	for (p = 0; p < cl->n; p++)
		out[p] = 0;
	for (k = 0; k < cl->ncorners; k++) {
		const struct corner *c = &cl->corners[k];
		vec3 o = v3_load(x + 3 * c->c);
		vec3 u = v3_sub(v3_load(x + 3 * c->a), o), w = v3_sub(v3_load(x + 3 * c->b), o);
		double lu = v3_len(u), lw = v3_len(w), cosphi;

		if (!(lu > 0 && lw > 0))
			continue;
		cosphi = v3_dot(u, w) / (lu * lw);
		cosphi = cosphi > 1 ? 1 : cosphi < -1 ? -1 : cosphi;
		out[c->c] += V3_PI / 2 - acos(cosphi);
		count[c->c]++;
	}
	for (p = 0; p < cl->n; p++)
		if (count[p] > 0)
			out[p] /= count[p];
}

int
colouring_field(enum colouring c, const struct cloth *cl, const double *x,
    const struct contact_event *ev, size_t nev, double *out)
{
	size_t n = cl->n > 0 ? (size_t)cl->n : 1, k;
	double *tmp = NULL;
	int *count, p;

	for (p = 0; p < cl->n; p++)
		out[p] = 0;
	if (c == COLOUR_SHADE)
		return 0;
	if (c == COLOUR_CONTACT) {
		/* contact with the cloth wins: it is the rarer and the harder */
		for (k = 0; k < nev; k++)
			if (ev[k].node >= 0 && ev[k].node < cl->n &&
			    out[ev[k].node] != TOUCH_CLOTH)
				out[ev[k].node] = ev[k].obstacle < 0 ? TOUCH_CLOTH : TOUCH_OBSTACLE;
		return 0;
	}
	if ((count = malloc(n * sizeof *count)) == NULL)
		return -1;
	switch (c) {
	case COLOUR_WARP:
		stretch(cl, x, 0, out, count);
		break;
	case COLOUR_WEFT:
		stretch(cl, x, 1, out, count);
		break;
	case COLOUR_SHEAR:
		shear(cl, x, out, count);
		break;
	default:
		if ((tmp = malloc(n * sizeof *tmp)) == NULL) {
			free(count);
			return -1;
		}
		stretch(cl, x, 0, out, count);
		for (p = 0; p < cl->n; p++)
			out[p] = fabs(out[p]);
		stretch(cl, x, 1, tmp, count);
		for (p = 0; p < cl->n; p++)
			out[p] = fmax(out[p], fabs(tmp[p]));
		shear(cl, x, tmp, count);
		for (p = 0; p < cl->n; p++)
			out[p] = fmax(out[p], fabs(tmp[p]));
		break;
	}
	free(tmp);
	free(count);
	return 0;
}

double
colouring_unit(enum colouring c)
{
	return c == COLOUR_SHEAR ? V3_PI / 180 : 0.01;
}

double
colouring_range(enum colouring c, double m)
{
	static const double steps[] = { 1, 2, 5 };
	/* the unit the legend writes: degrees, or percent */
	double unit = colouring_unit(c), p;
	int k;

	m /= unit;
	/* below a hundredth of the unit is rounding (positions at rest, float
	 * frames), not strain: a scale fitted to it would paint the noise */
	if (!(m >= 0.01) || !isfinite(m))
		return unit;
	p = pow(10, floor(log10(m)));
	for (;;) {
		for (k = 0; k < 3; k++)
			if (steps[k] * p >= m * (1 - 1e-9))
				return steps[k] * p * unit;
		p *= 10;
	}
}

static void
mix(const float *a, const float *b, double s, float *out)
{
	int k;

	for (k = 0; k < 3; k++)
		out[k] = (float)(a[k] + s * (b[k] - a[k]));
}

/* Piecewise linear through n stops, s from 0 to 1. */
static void
ramp(const float (*stop)[3], int n, double s, float *out)
{
	double at;
	int k;

	s = s < 0 ? 0 : s > 1 ? 1 : s;
	at = s * (n - 1);
	k = (int)floor(at);
	if (k >= n - 1)
		k = n - 2;
	mix(stop[k], stop[k + 1], at - k, out);
}

void
colouring_colour(enum colouring c, double v, double range, float out[3])
{
	/* after Moreland's cool-warm and ColorBrewer's YlOrRd */
	static const float cool_warm[5][3] = {
		{ 0.23f, 0.30f, 0.75f }, { 0.55f, 0.69f, 0.99f }, { 0.87f, 0.87f, 0.87f },
		{ 0.96f, 0.60f, 0.48f }, { 0.71f, 0.02f, 0.15f },
	};
	static const float yellow_red[5][3] = {
		{ 0.99f, 0.98f, 0.80f }, { 1.00f, 0.85f, 0.46f }, { 0.99f, 0.55f, 0.24f },
		{ 0.89f, 0.10f, 0.11f }, { 0.50f, 0.00f, 0.15f },
	};
	static const float front[3] = { 0.80f, 0.38f, 0.26f }, back[3] = { 0.93f, 0.76f, 0.50f };
	static const float plain[3] = { 0.80f, 0.80f, 0.80f };
	static const float on_obstacle[3] = { 0.95f, 0.55f, 0.05f };
	static const float on_cloth[3] = { 0.78f, 0.05f, 0.30f };
	const float *p;

	switch (c) {
	case COLOUR_SHADE:
		p = v >= 0 ? front : back;
		break;
	case COLOUR_CONTACT:
		p = v >= TOUCH_CLOTH - 0.5 ? on_cloth : v >= TOUCH_OBSTACLE - 0.5 ? on_obstacle :
		    plain;
		break;
	default:
		if (!(range > 0))
			range = 1;
		if (colouring_is_signed(c))
			ramp(cool_warm, 5, 0.5 + 0.5 * v / range, out);
		else
			ramp(yellow_red, 5, v / range, out);
		return;
	}
	memcpy(out, p, 3 * sizeof *out);
}

void
colouring_label(enum colouring c, double v, char *buf, size_t len)
{
	double shown = c == COLOUR_SHEAR ? v * 180 / V3_PI : 100 * v;
	const char *unit = c == COLOUR_SHEAR ? " deg" : "%";

	if (fabs(shown) < 1e-12)
		snprintf(buf, len, "0");
	else
		snprintf(buf, len, "%s%.3g%s", shown > 0 && colouring_is_signed(c) ? "+" : "",
		    shown, unit);
}

int
colouring_band(enum colouring c, double v, double range, int levels)
{
	double s;
	int k;

	if (c == COLOUR_CONTACT)
		return v >= TOUCH_CLOTH - 0.5 ? 2 : v >= TOUCH_OBSTACLE - 0.5 ? 1 : 0;
	if (!colouring_is_strain(c) || levels < 1)
		return 0;
	if (!(range > 0))
		range = 1;
	s = colouring_is_signed(c) ? 0.5 + 0.5 * v / range : v / range;
	if (!(s > 0))
		return 0;
	k = (int)(s * levels);
	return k >= levels ? levels - 1 : k;
}
