/* test_shadow.c: the shadow's area on the horizontal plane (rasterized
 * union of the projected triangles) and the drape coefficient. */
#include <math.h>

#include "testutil.h"
#include "cloth.h"
#include "shadow.h"

#define CELL 0.5e-3

/* The raster can only miscount the cells the outline crosses. */
static double
bound(double perimeter, double cell)
{
	return perimeter * cell * sqrt(2);
}

static double
area_of(const double *x, const int *tri, size_t ntri, double cell)
{
	double a, used;

	assert_int_equal(shadow_area(x, tri, ntri, cell, &a, &used), 0);
	assert_double_equal(used, cell, 0);
	return a;
}

static void
triangle_and_square(void **state)
{
	/* a right triangle 100 x 50 mm at an odd offset and height, then a
	 * square 100 mm on a side turned by 30 degrees, as two triangles */
	double tri_x[9] = { 0.0123, 0.31, -0.0071, 0.1123, 0.29, -0.0071, 0.0123, 0.33, 0.0429 };
	int one[3] = { 0, 1, 2 }, two[6] = { 0, 1, 2, 0, 2, 3 };
	double c = cos(V3_PI / 6) * 0.1, s = sin(V3_PI / 6) * 0.1;
	double sq[12] = { 0.003, 0.2, 0.001, 0.003 + c, 0.2, 0.001 + s,
		0.003 + c - s, 0.2, 0.001 + s + c, 0.003 - s, 0.2, 0.001 + c };
	int flipped[6] = { 0, 2, 1, 0, 3, 2 };
	double a;

	(void)state;
	a = area_of(tri_x, one, 1, CELL);
	print_message("triangle: %.7f m2, exact 0.0025\n", a);
	assert_double_equal(a, 0.0025, bound(0.1 + 0.05 + hypot(0.1, 0.05), CELL));
	a = area_of(sq, two, 2, CELL);
	print_message("turned square: %.7f m2, exact 0.01\n", a);
	assert_double_equal(a, 0.01, bound(0.4, CELL));
	/* seen from below (clockwise) it casts the same shadow */
	assert_double_equal(area_of(sq, flipped, 2, CELL), a, 0);
}

/* A square of side 0.1 with its corner at (x0, y, z0), as two triangles
 * appended to x and tri. */
static void
add_square(double *x, int *tri, int *nv, size_t *nt, double x0, double y, double z0)
{
	int v = *nv, k;
	double p[12] = { x0, y, z0, x0 + 0.1, y, z0, x0 + 0.1, y, z0 + 0.1, x0, y, z0 + 0.1 };
	int t[6] = { v, v + 1, v + 2, v, v + 2, v + 3 };

	memcpy(x + 3 * v, p, sizeof p);
	for (k = 0; k < 6; k++)
		tri[3 * *nt + (size_t)k] = t[k];
	*nv += 4;
	*nt += 2;
}

static void
overlaps_count_once(void **state)
{
	double x[36];
	int tri[18], nv = 0;
	size_t nt = 0;
	double a;

	(void)state;
	add_square(x, tri, &nv, &nt, 0.0002, 0.1, 0.0003);
	add_square(x, tri, &nv, &nt, 0.0502, 0.12, 0.0503);	/* over a quarter of it */
	a = area_of(x, tri, nt, CELL);
	print_message("two squares overlapping by a quarter: %.7f m2, exact 0.0175\n", a);
	assert_double_equal(a, 0.0175, bound(0.6, CELL));
	add_square(x, tri, &nv, &nt, 0.0002, 0.13, 0.0003);	/* a fold right on the first */
	assert_double_equal(area_of(x, tri, nt, CELL), a, 0);
}

#define DISC_SCENE(orientation) \
	"[simulation]\nduration = 1 s\n[cloth]\nnodes = 31 31\nshape = disc\nspacing = 10 mm\n" \
	"origin = -0.15 0.255 -0.15 m\norientation = " orientation "\nweight = 150 g/m2\n" \
	"thickness = 0.55 mm\nmodulus_warp = 0.45 MPa\nmodulus_weft = 0.3 MPa\n" \
	"shear_modulus = 0\nbending_warp = 0\nbending_weft = 0\n"

static void
flat_disc_has_dc_one(void **state)
{
	struct scene sc;
	struct cloth cl;
	struct drape_err err;
	double shadow, flat, support = V3_PI * 0.09 * 0.09, dc;

	(void)state;
	parse_text(&sc, DISC_SCENE("+x +z"));
	assert_int_equal(cloth_build(&cl, &sc, &err), 0);
	flat = mesh_area(cl.x0, cl.tri, cl.ntri);
	assert_double_equal(flat, (double)cl.nsquares * 1e-4, 1e-12);
	shadow = area_of(cl.x0, cl.tri, cl.ntri, CELL);
	dc = drape_coefficient(shadow, support, flat);
	print_message("flat disc: shadow %.7f m2, specimen %.7f m2, DC %.5f\n", shadow, flat, dc);
	/* its outline is the staircase of the squares: about 4 diameters */
	assert_double_equal(dc, 1, bound(4 * 0.3, CELL) / (flat - support));
	cloth_free(&cl);
	scene_free(&sc);
}

static void
vertical_cloth_casts_no_shadow(void **state)
{
	struct scene sc;
	struct cloth cl;
	struct drape_err err;
	double a;

	(void)state;
	parse_text(&sc, DISC_SCENE("+x -y"));
	assert_int_equal(cloth_build(&cl, &sc, &err), 0);
	a = area_of(cl.x0, cl.tri, cl.ntri, CELL);
	assert_double_equal(a, 0, 1e-12);
	assert_double_equal(drape_coefficient(a, 0.0254, 0.0648), -0.0254 / (0.0648 - 0.0254),
	    1e-12);
	assert_true(mesh_area(cl.x0, cl.tri, cl.ntri) > 0.06);
	cloth_free(&cl);
	scene_free(&sc);
}

static void
edge_cases(void **state)
{
	double big[9] = { 0, 0, 0, 100, 0, 0, 0, 0, 100 }, nan_x[9] = { 0, 0, 0, NAN, 0, 0, 0, 0, 1 };
	int one[3] = { 0, 1, 2 };
	double a, used;

	(void)state;
	/* a shadow 100 m wide gets coarser cells, not 4e10 of them */
	assert_int_equal(shadow_area(big, one, 1, CELL, &a, &used), 0);
	assert_true(used > CELL);
	assert_true((100 / used + 1) * (100 / used + 1) <= (double)SHADOW_MAX_CELLS);
	assert_double_equal(a, 5000, bound(100 + 100 + hypot(100, 100), used));
	assert_int_equal(shadow_area(nan_x, one, 1, CELL, &a, NULL), 0);
	assert_true(isnan(a));
	assert_int_equal(shadow_area(big, one, 0, CELL, &a, NULL), 0);
	assert_double_equal(a, 0, 0);
	assert_int_equal(shadow_area(big, one, 1, 0, &a, NULL), 0);
	assert_true(isnan(a));
	assert_true(isnan(drape_coefficient(0.03, 0.03, 0.02)));	/* nothing overhangs */
}

/*
 * A ring of n points, radius r0 + a cos(k theta) about (0.3, -0.2) (off
 * the origin: the axis is the disc's), joined by edges: a skirt of k
 * lobes, each standing 2a out from the troughs beside it.
 */
static int
ring_folds(int k, double a, double noise, double gap)
{
	enum { N = 400 };
	static double x[3 * N];
	static int edge[2 * N];
	int i, ne = 0;

	for (i = 0; i < N; i++) {
		double th = 2 * V3_PI * i / N, r = 0.12 + a * cos(k * th) + noise * sin(37.0 * i);

		x[3 * i] = 0.3 + r * cos(th);
		x[3 * i + 1] = 0.1;
		x[3 * i + 2] = -0.2 + r * sin(th);
		/* a gap leaves out the edges of that part of the turn */
		if (th >= gap) {
			edge[2 * ne] = i;
			edge[2 * ne + 1] = (i + 1) % N;
			ne++;
		}
	}
	return drape_folds(x, edge, (size_t)ne, 0.3, -0.2, 0.5e-3, 0.005);
}

static void
folds_of_an_outline(void **state)
{
	int k;

	(void)state;
	for (k = 3; k <= 14; k++)
		assert_int_equal(ring_folds(k, 0.01, 0, 0), k);
	/* lobes whose rise (2a, a tenth less once the sectors smooth it) is
	 * under the 5 mm asked for are no folds */
	assert_int_equal(ring_folds(8, 0.002, 0, 0), 0);
	assert_int_equal(ring_folds(8, 0.0032, 0, 0), 8);
	assert_int_equal(ring_folds(0, 0, 0, 0), 0);	/* a circle */
	/* a ragged outline: ripples of 1 mm on 9 lobes */
	assert_int_equal(ring_folds(9, 0.01, 0.001, 0), 9);
	/* an outline that does not go round: half of it left out */
	assert_int_equal(ring_folds(6, 0.01, 0, V3_PI), -1);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(triangle_and_square),
		cmocka_unit_test(overlaps_count_once),
		cmocka_unit_test(flat_disc_has_dc_one),
		cmocka_unit_test(vertical_cloth_casts_no_shadow),
		cmocka_unit_test(edge_cases),
		cmocka_unit_test(folds_of_an_outline),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
