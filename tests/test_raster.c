/* test_raster.c: the camera and the character grid (a known triangle fills
 * the expected cells, nearer surfaces hide farther ones, a known point
 * lands on the expected cell, cells are twice as tall as wide), and
 * `drape snapshot` through the real binary. */
#include "testutil.h"
#include "runbin.h"
#include "raster.h"
#include "view.h"

/* 20 x 10 cells framing a sphere of radius 1 at the origin: 10 columns
 * and 5 rows per metre, the origin at the corner of cell (10, 5). */
static void
front(struct raster *r, struct camera *cam, enum view_preset p)
{
	raster_init(r);
	assert_int_equal(raster_resize(r, 20, 10), 0);
	camera_preset(cam, p, v3(0, 0, 0), 1);
}

/* The world point at grid position (col, row) of the front view, z = 0. */
static vec3
at_cell(double col, double row)
{
	return v3((col - 10) / 10, (5 - row) / 5, 0);
}

static void
point_projects_to_cell(void **state)
{
	struct raster r;
	struct camera cam;
	double col, row, z;

	(void)state;
	front(&r, &cam, VIEW_FRONT);
	assert_true(raster_project(&r, &cam, v3(0.35, 0.3, 0.2), &col, &row, &z));
	assert_double_equal(col, 13.5, 1e-12);
	assert_double_equal(row, 3.5, 1e-12);
	assert_double_equal(z, 0.2, 1e-12);
	raster_point(&r, &cam, v3(0.35, 0.3, 0.2), 'X', CELL_SELECTED, 0, false);
	assert_int_equal(raster_at(&r, 13, 3), 'X');
	/* from above, -z is up the screen */
	camera_preset(&cam, VIEW_TOP, v3(0, 0, 0), 1);
	assert_true(raster_project(&r, &cam, v3(0.35, -0.2, -0.3), &col, &row, &z));
	assert_double_equal(col, 13.5, 1e-12);
	assert_double_equal(row, 3.5, 1e-12);
	assert_double_equal(z, -0.2, 1e-12);
	/* from the side (+x), -z is to the right */
	camera_preset(&cam, VIEW_SIDE, v3(0, 0, 0), 1);
	assert_true(raster_project(&r, &cam, v3(0, 0.3, -0.35), &col, &row, &z));
	assert_double_equal(col, 13.5, 1e-12);
	/* perspective leaves the target's plane as it is, enlarges what is nearer */
	camera_preset(&cam, VIEW_FRONT, v3(0, 0, 0), 1);
	cam.perspective = true;
	assert_true(raster_project(&r, &cam, v3(0.35, 0.3, 0), &col, &row, &z));
	assert_double_equal(col, 13.5, 1e-12);
	assert_true(raster_project(&r, &cam, v3(0.35, 0.3, 0.5), &col, &row, &z));
	assert_true(col > 13.5);
	assert_false(raster_project(&r, &cam, v3(0, 0, 10), &col, &row, &z));
	/* zoom and pan */
	cam.perspective = false;
	cam.zoom = 2;
	cam.pan_x = 0.1;
	assert_true(raster_project(&r, &cam, v3(0.35, 0.3, 0), &col, &row, &z));
	assert_double_equal(col, 10 + (0.35 + 0.1) * 20, 1e-12);
	assert_double_equal(row, 5 - 0.3 * 10, 1e-12);
	raster_free(&r);
}

static void
triangle_fills_expected_cells(void **state)
{
	struct raster r;
	struct camera cam;
	int i, j, filled = 0;

	(void)state;
	front(&r, &cam, VIEW_FRONT);
	/* corners at grid positions (2, 2), (10, 2), (2, 6): a cell is in when
	 * its centre is, i >= 2, j >= 2 and i + 2j <= 12 */
	raster_triangle(&r, &cam, at_cell(2, 2), at_cell(10, 2), at_cell(2, 6), CELL_CLOTH);
	for (j = 0; j < r.h; j++) {
		for (i = 0; i < r.w; i++) {
			bool in = i >= 2 && j >= 2 && i + 2 * j <= 12;
			char ch = raster_at(&r, i, j);

			if (in != (ch != ' '))
				fail_msg("cell (%d, %d) is '%c', expected %s", i, j, ch,
				    in ? "filled" : "blank");
			if (in) {
				assert_non_null(strchr(RASTER_RAMP, ch));
				assert_int_equal(r.kind[j * r.w + i], CELL_CLOTH);
				filled++;
			}
		}
	}
	assert_int_equal(filled, 7 + 5 + 3 + 1);
	/* the same triangle wound the other way fills the same cells */
	raster_clear(&r);
	raster_triangle(&r, &cam, at_cell(2, 2), at_cell(2, 6), at_cell(10, 2), CELL_CLOTH);
	for (j = 0, filled = 0; j < r.h; j++)
		for (i = 0; i < r.w; i++)
			filled += raster_at(&r, i, j) != ' ';
	assert_int_equal(filled, 16);
	raster_free(&r);
}

/* A square of side s in metres covers twice as many columns as rows. */
/* Issue 30: without colour the cloth and a box it lay on took the same
 * characters; the obstacles have their own, and the floor its dots. */
static void
obstacles_have_their_own_characters(void **state)
{
	struct raster r;
	struct camera cam;
	const char *c;
	char cloth, solid;

	(void)state;
	for (c = RASTER_SOLID_RAMP; *c != '\0'; c++)
		if (strchr(RASTER_RAMP, *c) != NULL || *c == '.' || *c == ' ')
			fail_msg("'%c' is the cloth's, the floor's or a blank", *c);
	front(&r, &cam, VIEW_FRONT);
	raster_triangle(&r, &cam, at_cell(2, 2), at_cell(10, 2), at_cell(2, 6), CELL_CLOTH);
	raster_triangle(&r, &cam, at_cell(12, 2), at_cell(20, 2), at_cell(12, 6), CELL_SOLID);
	cloth = raster_at(&r, 3, 3);
	solid = raster_at(&r, 13, 3);
	assert_non_null(strchr(RASTER_RAMP, cloth));
	assert_non_null(strchr(RASTER_SOLID_RAMP, solid));
	assert_int_equal(r.kind[3 * r.w + 13], CELL_SOLID);
	raster_free(&r);
}

static void
cells_are_twice_as_tall(void **state)
{
	struct raster r;
	struct camera cam;
	int i, j, cols = 0, rows = 0;

	(void)state;
	front(&r, &cam, VIEW_FRONT);
	raster_triangle(&r, &cam, v3(0, 0, 0), v3(0.4, 0, 0), v3(0.4, 0.4, 0), CELL_SOLID);
	raster_triangle(&r, &cam, v3(0, 0, 0), v3(0.4, 0.4, 0), v3(0, 0.4, 0), CELL_SOLID);
	for (i = 0; i < r.w; i++)
		cols += raster_at(&r, i, 4) != ' ';
	for (j = 0; j < r.h; j++)
		rows += raster_at(&r, 11, j) != ' ';
	assert_int_equal(cols, 4);
	assert_int_equal(rows, 2);
	raster_free(&r);
}

static void
draw_pair(struct raster *r, const struct camera *cam, bool near_first)
{
	/* the near square (z = 0.5) over columns 4..11, the far one (z = -0.5)
	 * over columns 8..15, both over rows 2..7 */
	vec3 n[4] = { at_cell(4, 2), at_cell(12, 2), at_cell(12, 8), at_cell(4, 8) };
	vec3 f[4] = { at_cell(8, 2), at_cell(16, 2), at_cell(16, 8), at_cell(8, 8) };
	int k, pass;

	for (k = 0; k < 4; k++) {
		n[k].z = 0.5;
		f[k].z = -0.5;
	}
	for (pass = 0; pass < 2; pass++) {
		if ((pass == 0) == near_first) {
			raster_triangle(r, cam, n[0], n[1], n[2], CELL_SOLID);
			raster_triangle(r, cam, n[0], n[2], n[3], CELL_SOLID);
		} else {
			raster_triangle(r, cam, f[0], f[1], f[2], CELL_CLOTH);
			raster_triangle(r, cam, f[0], f[2], f[3], CELL_CLOTH);
		}
	}
}

static void
nearer_hides_farther(void **state)
{
	struct raster r;
	struct camera cam;
	int order, i, j;

	(void)state;
	front(&r, &cam, VIEW_FRONT);
	for (order = 0; order < 2; order++) {
		raster_clear(&r);
		draw_pair(&r, &cam, order == 0);
		for (j = 2; j < 8; j++) {
			for (i = 4; i < 16; i++) {
				int want = i < 12 ? CELL_SOLID : CELL_CLOTH;

				if (r.kind[j * r.w + i] != want)
					fail_msg("order %d: cell (%d, %d) has kind %d, expected %d", order,
					    i, j, r.kind[j * r.w + i], want);
			}
		}
		/* a point behind the near square is hidden unless it must show */
		raster_point(&r, &cam, v3(-0.35, 0, 0), 'o', CELL_CONTACT, 0, false);
		assert_int_equal(r.kind[5 * r.w + 6], CELL_SOLID);
		raster_point(&r, &cam, v3(-0.35, 0, 0), 'X', CELL_SELECTED, 0, true);
		assert_int_equal(raster_at(&r, 6, 5), 'X');
	}
	/* seen from behind (yaw 180), the far square is the near one */
	cam.yaw = V3_PI;
	raster_clear(&r);
	draw_pair(&r, &cam, true);
	assert_int_equal(r.kind[5 * r.w + 20 - 1 - 10], CELL_CLOTH);
	raster_free(&r);
}

static void
presets_by_name(void **state)
{
	(void)state;
	assert_int_equal(view_preset_from_name("front"), VIEW_FRONT);
	assert_int_equal(view_preset_from_name("side"), VIEW_SIDE);
	assert_int_equal(view_preset_from_name("top"), VIEW_TOP);
	assert_int_equal(view_preset_from_name("iso"), VIEW_ISO);
	assert_int_equal(view_preset_from_name("back"), -1);
}

#define SMALL "[simulation]\nduration = 0.2 s\ndt = 0.2 ms\n[cloth]\nnodes = 6 6\n" \
	"spacing = 20 mm\norigin = -0.05 0.05 -0.05 m\norientation = +x +z\nweight = 100 g/m2\n" \
	"thickness = 0.3 mm\nmodulus_warp = 1 MPa\nmodulus_weft = 1 MPa\nshear_modulus = 0\n" \
	"bending_warp = 0\nbending_weft = 0\n[plane]\npoint = 0 0 0\n"

static int
count_lines(const char *s, int *widest)
{
	int n = 0, w = 0;

	*widest = 0;
	for (; *s; s++) {
		if (*s == '\n') {
			n++;
			w = 0;
		} else if (++w > *widest) {
			*widest = w;
		}
	}
	return n;
}

static void
snapshot_prints_the_grid(void **state)
{
	struct result r;
	char args[900];
	const char *scene = dir_write("small.scene", SMALL, strlen(SMALL));
	int lines, widest;

	(void)state;
	snprintf(args, sizeof args, "snapshot --size 40x12 --view top '%s'", scene);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	lines = count_lines(r.out, &widest);
	assert_int_equal(lines, 12);
	assert_true(widest <= 40);
	/* the flat cloth seen from above shows in one shade, in the middle */
	assert_non_null(strpbrk(r.out, RASTER_RAMP));
	snprintf(args, sizeof args, "snapshot --step 900 --view iso --size 60x20 '%s'", scene);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_int_equal(count_lines(r.out, &widest), 20);
	/* after 0.1 s it has reached the floor: contacts are marked */
	assert_non_null(strchr(r.out, VIEW_MARK_CONTACT));

	snprintf(args, sizeof args, "snapshot --size 0x10 '%s'", scene);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "--size '0x10'"));
	snprintf(args, sizeof args, "snapshot --view back '%s'", scene);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "front, side, top or iso"));
	snprintf(args, sizeof args, "snapshot --step 2000 '%s'", scene);
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "ends at step 1000"));
	snprintf(args, sizeof args, "snapshot '%s'", dir_write("run.replay", "\x1f\x8b\x08\0", 4));
	drape(&r, args);
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "drape snapshot: "));	/* read as a replay, and refused */
	drape(&r, "snapshot");
	assert_int_equal(r.status, 2);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(point_projects_to_cell),
		cmocka_unit_test(triangle_fills_expected_cells),
		cmocka_unit_test(cells_are_twice_as_tall),
		cmocka_unit_test(obstacles_have_their_own_characters),
		cmocka_unit_test(nearer_hides_farther),
		cmocka_unit_test(presets_by_name),
		cmocka_unit_test(snapshot_prints_the_grid),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
