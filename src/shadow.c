/* shadow.c: rasterizing the projected triangles onto one bitmap; the union
 * comes free, since a cell is marked once however many triangles cover it. */
#include <math.h>
#include <stdlib.h>

#include "shadow.h"
#include "vec3.h"

/* Twice the signed area of (a, b, p) in the x-z plane: > 0 when p is to the
 * left of a->b seen with x to the right and z up. */
static double
orient(const double *a, const double *b, double px, double pz)
{
	return (b[0] - a[0]) * (pz - a[2]) - (b[2] - a[2]) * (px - a[0]);
}

/* The first and last cell whose centre lo + (k + 1/2) cell lies in [a, b],
 * clamped to [0, n). */
static void
cell_span(double a, double b, double lo, double cell, long n, long *k0, long *k1)
{
	double f0 = ceil((a - lo) / cell - 0.5), f1 = floor((b - lo) / cell - 0.5);

	*k0 = f0 < 0 ? 0 : (long)f0;
	*k1 = f1 >= (double)n ? n - 1 : (long)f1;
}

static void
mark_triangle(unsigned char *raster, long nx, long nz, double lox, double loz, double cell,
    const double *a, const double *b, const double *c)
{
	double area2 = orient(a, b, c[0], c[2]);
	long i0, i1, k0, k1, i, k;

	if (area2 == 0)
		return;		/* edge-on: no shadow */
	if (area2 < 0) {	/* counter-clockwise, so that inside is >= 0 */
		const double *t = b;

		b = c;
		c = t;
	}
	cell_span(fmin(a[0], fmin(b[0], c[0])), fmax(a[0], fmax(b[0], c[0])), lox, cell, nx,
	    &i0, &i1);
	cell_span(fmin(a[2], fmin(b[2], c[2])), fmax(a[2], fmax(b[2], c[2])), loz, cell, nz,
	    &k0, &k1);
	for (k = k0; k <= k1; k++) {
		double pz = loz + ((double)k + 0.5) * cell;

		for (i = i0; i <= i1; i++) {
			double px = lox + ((double)i + 0.5) * cell;

			if (orient(a, b, px, pz) >= 0 && orient(b, c, px, pz) >= 0 &&
			    orient(c, a, px, pz) >= 0)
				raster[k * nx + i] = 1;
		}
	}
}

int
shadow_area(const double *x, const int *tri, size_t ntri, double cell, double *area,
    double *cell_used)
{
	double lox = INFINITY, hix = -INFINITY, loz = INFINITY, hiz = -INFINITY, w, d;
	unsigned char *raster;
	long nx, nz, count = 0, c;
	size_t t;

	*area = 0;
	if (cell_used != NULL)
		*cell_used = cell;
	for (t = 0; t < 3 * ntri; t++) {
		const double *p = x + 3 * tri[t];

		if (!isfinite(p[0]) || !isfinite(p[2])) {
			*area = NAN;
			return 0;
		}
		lox = fmin(lox, p[0]);
		hix = fmax(hix, p[0]);
		loz = fmin(loz, p[2]);
		hiz = fmax(hiz, p[2]);
	}
	if (ntri == 0)
		return 0;
	w = hix - lox;
	d = hiz - loz;
	if (!(cell > 0) || !isfinite(cell)) {
		*area = NAN;
		return 0;
	}
	while ((floor(w / cell) + 1) * (floor(d / cell) + 1) > (double)SHADOW_MAX_CELLS)
		cell *= 2;
	nx = (long)floor(w / cell) + 1;
	nz = (long)floor(d / cell) + 1;
	if ((raster = calloc((size_t)(nx * nz), 1)) == NULL)
		return -1;
	for (t = 0; t < ntri; t++)
		mark_triangle(raster, nx, nz, lox, loz, cell, x + 3 * tri[3 * t],
		    x + 3 * tri[3 * t + 1], x + 3 * tri[3 * t + 2]);
	for (c = 0; c < nx * nz; c++)
		count += raster[c];
	free(raster);
	*area = (double)count * cell * cell;
	if (cell_used != NULL)
		*cell_used = cell;
	return 0;
}

double
mesh_area(const double *x, const int *tri, size_t ntri)
{
	double sum = 0;
	size_t t;

	for (t = 0; t < ntri; t++) {
		vec3 a = v3_load(x + 3 * tri[3 * t]);
		vec3 ab = v3_sub(v3_load(x + 3 * tri[3 * t + 1]), a);
		vec3 ac = v3_sub(v3_load(x + 3 * tri[3 * t + 2]), a);

		sum += v3_len(v3_cross(ab, ac)) / 2;
	}
	return sum;
}

double
drape_coefficient(double shadow, double support, double flat)
{
	return flat > support ? (shadow - support) / (flat - support) : NAN;
}

/*
 * The folds, as a drape tester counts its shadow's lobes: the outline's
 * largest horizontal distance from the axis in each of SHADOW_FOLD_BINS
 * sectors, smoothed 1-2-1, and the maxima that stand at least prom over
 * the lowest sector on each side before the next maximum (a lone bump of
 * a ragged outline does not). The outline is sampled along the edges,
 * every cell or closer, so that a coarse cloth fills every sector its
 * skirt crosses; a sector left empty (a cloth that does not go round the
 * axis) gives -1.
 */
int
drape_folds(const double *x, const int *edge, size_t nedges, double cx, double cz,
    double cell, double prom)
{
	double r[SHADOW_FOLD_BINS], s[SHADOW_FOLD_BINS];
	int max[SHADOW_FOLD_BINS], nmax = 0, folds = 0, k, j;
	size_t e;

	for (k = 0; k < SHADOW_FOLD_BINS; k++)
		r[k] = -1;
	for (e = 0; e < nedges; e++) {
		const double *a = x + 3 * edge[2 * e], *b = x + 3 * edge[2 * e + 1];
		double len = hypot(b[0] - a[0], b[2] - a[2]);
		long m = (long)fmin(ceil(len / cell), 1e6), i;

		for (i = 0; i <= m; i++) {
			double t = m > 0 ? (double)i / (double)m : 0;
			double px = a[0] + t * (b[0] - a[0]) - cx, pz = a[2] + t * (b[2] - a[2]) - cz;
			double rho = hypot(px, pz), f = (atan2(pz, px) / (2 * V3_PI) + 0.5) * SHADOW_FOLD_BINS;

			if (!(f >= 0))
				return -1;	/* not finite */
			k = (int)f % SHADOW_FOLD_BINS;
			r[k] = fmax(r[k], rho);
		}
	}
	for (k = 0; k < SHADOW_FOLD_BINS; k++)
		if (r[k] < 0)
			return -1;
	for (k = 0; k < SHADOW_FOLD_BINS; k++)
		s[k] = (r[(k + SHADOW_FOLD_BINS - 1) % SHADOW_FOLD_BINS] + 2 * r[k] +
		    r[(k + 1) % SHADOW_FOLD_BINS]) / 4;
	for (k = 0; k < SHADOW_FOLD_BINS; k++)
		if (s[k] > s[(k + SHADOW_FOLD_BINS - 1) % SHADOW_FOLD_BINS] &&
		    s[k] >= s[(k + 1) % SHADOW_FOLD_BINS])
			max[nmax++] = k;
	for (j = 0; nmax > 1 && j < nmax; j++) {
		int at = max[j], before = max[(j + nmax - 1) % nmax], after = max[(j + 1) % nmax];
		double low_before = s[at], low_after = s[at];

		for (k = before; k != at; k = (k + 1) % SHADOW_FOLD_BINS)
			low_before = fmin(low_before, s[k]);
		for (k = at; k != after; k = (k + 1) % SHADOW_FOLD_BINS)
			low_after = fmin(low_after, s[k]);
		folds += s[at] - low_before >= prom && s[at] - low_after >= prom;
	}
	return folds;
}
