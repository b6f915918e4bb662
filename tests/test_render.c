/* test_render.c: pictures. The PNG writer's output read back by a reader
 * of this test's own (signature, IHDR, every chunk's CRC, IDAT inflated to
 * the right size and unfiltered to the pixels written); a known triangle
 * lands on the pixels it should and a nearer one hides a farther one
 * whichever is drawn first; strain colouring gives a uniformly stretched
 * sheet one colour and a relaxed one another, contact colouring the nodes
 * of a step's events theirs; the band's legend stays clear of the name and
 * the frames' time labels say their times; the braille view of a known
 * triangle sets the expected dots; and through the real binary: the same
 * replay frame renders to the same bytes twice, a filmstrip has the size
 * it should, and bad --size, bad --strip and an output that cannot be
 * written are refused (exit 2, exit 1, nothing left behind); drape plot
 * says so without gnuplot, and with it writes its charts (skipped where
 * gnuplot is not installed). */
#include <dirent.h>
#include <sys/stat.h>
#include <zlib.h>

#include "testutil.h"
#include "runbin.h"
#include "cloth.h"
#include "colouring.h"
#include "font.h"
#include "glyphs.h"
#include "paint.h"
#include "picture.h"
#include "png.h"
#include "render.h"

/* ---- a PNG reader for 8-bit truecolour, no interlace ---- */

struct png_image {
	int w, h;
	unsigned char *rgb;
	int nchunks;
};

static uint32_t
rd32(const unsigned char *p)
{
	return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static int
paeth(int a, int b, int c)
{
	int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);

	return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* Reads buf (len bytes) into im, failing the test on anything wrong. */
static void
png_read(const unsigned char *buf, size_t len, struct png_image *im)
{
	static const unsigned char sig[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
	unsigned char *idat = NULL, *raw;
	size_t at = 8, nidat = 0, stride, i;
	uLongf rawlen;
	bool ihdr = false, iend = false;
	int y;

	memset(im, 0, sizeof *im);
	assert_true(len > 8);
	assert_memory_equal(buf, sig, 8);
	while (at < len) {
		uint32_t n, crc;
		const unsigned char *type, *data;

		assert_true(len - at >= 12);
		n = rd32(buf + at);
		assert_true(n <= len - at - 12);
		type = buf + at + 4;
		data = buf + at + 8;
		crc = (uint32_t)crc32(crc32(0L, Z_NULL, 0), type, n + 4);
		if (crc != rd32(data + n))
			fail_msg("chunk %.4s: CRC %08x, stored %08x", (const char *)type, crc,
			    rd32(data + n));
		assert_false(iend);	/* nothing after IEND */
		if (memcmp(type, "IHDR", 4) == 0) {
			assert_false(ihdr);
			assert_int_equal(im->nchunks, 0);	/* first */
			assert_int_equal(n, 13);
			im->w = (int)rd32(data);
			im->h = (int)rd32(data + 4);
			assert_true(im->w > 0 && im->h > 0);
			assert_int_equal(data[8], 8);	/* bit depth */
			assert_int_equal(data[9], 2);	/* truecolour */
			assert_int_equal(data[10], 0);
			assert_int_equal(data[11], 0);
			assert_int_equal(data[12], 0);
			ihdr = true;
		} else if (memcmp(type, "IDAT", 4) == 0) {
			assert_true(ihdr);
			assert_non_null(idat = realloc(idat, nidat + n + 1));
			memcpy(idat + nidat, data, n);
			nidat += n;
		} else if (memcmp(type, "IEND", 4) == 0) {
			assert_int_equal(n, 0);
			iend = true;
		} else {
			assert_true(type[0] & 0x20);	/* only ancillary chunks besides */
		}
		im->nchunks++;
		at += 12 + n;
	}
	assert_true(ihdr && iend && nidat > 0);
	stride = 3 * (size_t)im->w;
	rawlen = (stride + 1) * (size_t)im->h;
	assert_non_null(raw = malloc(rawlen + 1));
	{
		uLongf got = rawlen + 1;

		assert_int_equal(uncompress(raw, &got, idat, nidat), Z_OK);
		assert_int_equal(got, rawlen);	/* exactly the rows, each with its filter byte */
	}
	assert_non_null(im->rgb = malloc(stride * (size_t)im->h));
	for (y = 0; y < im->h; y++) {
		const unsigned char *in = raw + (size_t)y * (stride + 1);
		unsigned char *row = im->rgb + (size_t)y * stride;
		const unsigned char *up = y > 0 ? row - stride : NULL;

		assert_true(in[0] <= 4);
		for (i = 0; i < stride; i++) {
			int a = i >= 3 ? row[i - 3] : 0, b = up != NULL ? up[i] : 0;
			int c = i >= 3 && up != NULL ? up[i - 3] : 0;
			int pred = in[0] == 1 ? a : in[0] == 2 ? b : in[0] == 3 ? (a + b) / 2 :
			    in[0] == 4 ? paeth(a, b, c) : 0;

			row[i] = (unsigned char)(in[1 + i] + pred);
		}
	}
	free(raw);
	free(idat);
}

static unsigned char *
slurp_file(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	unsigned char *buf;
	long n;

	if (f == NULL)
		fail_msg("cannot open %s", path);
	assert_int_equal(fseek(f, 0, SEEK_END), 0);
	n = ftell(f);
	assert_true(n > 0);
	rewind(f);
	assert_non_null(buf = malloc((size_t)n));
	assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
	fclose(f);
	*len = (size_t)n;
	return buf;
}

/* ---- the renderer ---- */

/* 40 x 40 square pixels framing a sphere of radius 1 at the origin from
 * the front: 20 pixels a metre, the origin at the corner of pixel (20, 20). */
static void
front(struct render *im, struct camera *cam)
{
	render_init(im);
	assert_int_equal(render_resize(im, 40, 40, 1), 0);
	render_clear(im, (struct rgb){ 255, 255, 255 });
	camera_preset(cam, VIEW_FRONT, v3(0, 0, 0), 1);
}

/* The world point at pixel position (x, y) of the front view, at depth z. */
static vec3
at_px(double x, double y, double z)
{
	return v3((x - 20) / 20, (20 - y) / 20, z);
}

static void
flat_triangle(struct render *im, const struct camera *cam, vec3 a, vec3 b, vec3 c,
    struct rgb col, enum cell_kind kind)
{
	struct render_vertex v[3];
	vec3 p[3] = { a, b, c };
	int k;

	for (k = 0; k < 3; k++) {
		v[k].p = p[k];
		v[k].c[0] = col.r / 255.0f;
		v[k].c[1] = col.g / 255.0f;
		v[k].c[2] = col.b / 255.0f;
		v[k].lum = 1;
	}
	render_triangle(im, cam, &v[0], &v[1], &v[2], kind);
}

static bool
same(struct rgb a, struct rgb b)
{
	return a.r == b.r && a.g == b.g && a.b == b.b;
}

/* Corners at pixel positions (4, 4), (20, 4), (4, 12): a pixel is in when
 * its centre is, x >= 4, y >= 4 and (x + 0.5) + 2 (y + 0.5) <= 28. */
static bool
in_triangle(int x, int y)
{
	return x >= 4 && y >= 4 && (x + 0.5) + 2 * (y + 0.5) <= 28;
}

static void
check_triangle_pixels(const unsigned char *rgb, int w, struct rgb red)
{
	int x, y, n = 0;

	for (y = 0; y < 40; y++)
		for (x = 0; x < 40; x++) {
			const unsigned char *p = rgb + 3 * ((size_t)y * (size_t)w + (size_t)x);
			struct rgb got = { p[0], p[1], p[2] };
			bool in = in_triangle(x, y);

			if (in != same(got, red))
				fail_msg("pixel (%d, %d) is %d %d %d, expected %s", x, y, got.r, got.g,
				    got.b, in ? "the triangle's" : "the background");
			n += in;
		}
	/* rows 4..11 hold 15, 13, ..., 1 pixels */
	assert_int_equal(n, 15 + 13 + 11 + 9 + 7 + 5 + 3 + 1);
}

static void
triangle_lands_on_its_pixels(void **state)
{
	struct render im;
	struct camera cam;
	struct drape_err err;
	struct png_image rd;
	struct rgb red = { 200, 30, 40 };
	unsigned char *png;
	size_t len;

	(void)state;
	front(&im, &cam);
	flat_triangle(&im, &cam, at_px(4, 4, 0), at_px(20, 4, 0), at_px(4, 12, 0), red,
	    CELL_CLOTH);
	check_triangle_pixels(im.rgb, im.w, red);
	assert_int_equal(im.kind[5 * 40 + 5], CELL_CLOTH);
	assert_int_equal(im.kind[0], CELL_EMPTY);
	assert_double_equal(im.depth[5 * 40 + 5], 0, 1e-12);
	/* and through the PNG writer and this test's reader */
	assert_int_equal(png_encode(im.rgb, im.w, im.h, &png, &len, &err), 0);
	png_read(png, len, &rd);
	assert_int_equal(rd.w, 40);
	assert_int_equal(rd.h, 40);
	assert_int_equal(rd.nchunks, 3);
	check_triangle_pixels(rd.rgb, rd.w, red);
	assert_memory_equal(rd.rgb, im.rgb, 3 * 40 * 40);
	free(rd.rgb);
	free(png);
	/* wound the other way: the same pixels */
	render_clear(&im, (struct rgb){ 255, 255, 255 });
	flat_triangle(&im, &cam, at_px(4, 4, 0), at_px(4, 12, 0), at_px(20, 4, 0), red,
	    CELL_CLOTH);
	check_triangle_pixels(im.rgb, im.w, red);
	render_free(&im);
}

/* Two overlapping squares, the blue one nearer: blue wherever both are,
 * whichever was drawn first. */
static void
nearer_hides_farther(void **state)
{
	struct render im;
	struct camera cam;
	struct rgb red = { 200, 30, 40 }, blue = { 30, 40, 200 };
	int order, x, y;

	(void)state;
	for (order = 0; order < 2; order++) {
		front(&im, &cam);
		for (x = 0; x < 2; x++) {
			bool near = (x == 0) == (order == 0);
			double lo = near ? 10 : 4, hi = near ? 30 : 24, z = near ? 0.2 : -0.1;
			struct rgb c = near ? blue : red;

			flat_triangle(&im, &cam, at_px(lo, lo, z), at_px(hi, lo, z), at_px(hi, hi, z), c,
			    near ? CELL_CLOTH : CELL_SOLID);
			flat_triangle(&im, &cam, at_px(lo, lo, z), at_px(hi, hi, z), at_px(lo, hi, z), c,
			    near ? CELL_CLOTH : CELL_SOLID);
		}
		for (y = 0; y < 40; y++)
			for (x = 0; x < 40; x++) {
				bool in_near = x >= 10 && x < 30 && y >= 10 && y < 30;
				bool in_far = x >= 4 && x < 24 && y >= 4 && y < 24;
				struct rgb want = in_near ? blue : in_far ? red :
				    (struct rgb){ 255, 255, 255 };

				if (!same(render_at(&im, x, y), want))
					fail_msg("order %d: pixel (%d, %d) is wrong", order, x, y);
			}
		assert_int_equal(im.kind[15 * 40 + 15], CELL_CLOTH);
		assert_double_equal(im.depth[15 * 40 + 15], 0.2, 1e-12);
		assert_double_equal(im.depth[5 * 40 + 5], -0.1, 1e-12);
		render_free(&im);
	}
}

static void
png_rejects_bad_sizes_and_writes_whole(void **state)
{
	unsigned char px[3] = { 1, 2, 3 }, *png, *back;
	struct drape_err err;
	struct png_image rd;
	char path[600];
	size_t len, blen;

	(void)state;
	assert_int_equal(png_encode(px, 0, 1, &png, &len, &err), -1);
	assert_non_null(strstr(err.msg, "must be 1 to"));
	snprintf(path, sizeof path, "%s/one.png", dir);
	assert_int_equal(png_write(path, px, 1, 1, &err), 0);
	back = slurp_file(path, &blen);
	png_read(back, blen, &rd);
	assert_int_equal(rd.w, 1);
	assert_memory_equal(rd.rgb, px, 3);
	free(rd.rgb);
	free(back);
	/* a directory in the way: an error, the directory untouched, no
	 * temporary file left beside it */
	snprintf(path, sizeof path, "%s/adir", dir);
	assert_int_equal(mkdir(path, 0755), 0);
	assert_int_equal(png_write(path, px, 1, 1, &err), -1);
	assert_non_null(strstr(err.msg, path));
	{
		DIR *d = opendir(dir);
		struct dirent *e;

		assert_non_null(d);
		while ((e = readdir(d)) != NULL)
			assert_null(strstr(e->d_name, ".tmp-"));
		closedir(d);
	}
}

/* ---- strain colouring ---- */

static const char SHEET[] =
	"[simulation]\nduration = 1 s\ndt = auto\n"
	"[cloth]\nnodes = 6 6\nspacing = 10 mm\norigin = -0.025 0 -0.025 m\n"
	"orientation = +x +z\nweight = 100 g/m2\nthickness = 0.3 mm\n"
	"modulus_warp = 0.5 MPa\nmodulus_weft = 0.5 MPa\nshear_modulus = 10 kPa\n"
	"bending_warp = 0\nbending_weft = 0\n";

/* The colours of the cloth's pixels seen from above, the sheet scaled by
 * s about its centre, coloured by c. Returns how many colours there are,
 * the first in *one. */
static int
sheet_colours(const struct scene *sc, const struct cloth *cl, double s, enum colouring c,
    struct rgb *one)
{
	struct render im;
	struct camera cam;
	struct paint_opts po = { c, 0.05, 0, false };
	double *x = malloc(3 * (size_t)cl->n * sizeof *x), *field = malloc((size_t)cl->n * sizeof *field);
	struct rgb seen[8];
	int p, i, n = 0, cloth_px = 0;

	assert_non_null(x);
	assert_non_null(field);
	for (p = 0; p < 3 * cl->n; p++)
		x[p] = cl->x0[p] * (p % 3 == 1 ? 1 : s);
	assert_int_equal(colouring_field(c, cl, x, NULL, 0, field), 0);
	for (p = 0; p < cl->n; p++)
		assert_double_equal(field[p], c == COLOUR_SHEAR ? 0 : s - 1, 1e-12);
	render_init(&im);
	assert_int_equal(render_resize(&im, 64, 64, 1), 0);
	camera_preset(&cam, VIEW_TOP, v3(0, 0, 0), 0.05);
	assert_int_equal(paint_scene(&im, &cam, sc, cl, x, field, &po), 0);
	for (i = 0; i < 64 * 64; i++) {
		struct rgb got = { im.rgb[3 * i], im.rgb[3 * i + 1], im.rgb[3 * i + 2] };
		int k;

		if (im.kind[i] != CELL_CLOTH)
			continue;
		cloth_px++;
		for (k = 0; k < n && !same(seen[k], got); k++)
			;
		if (k == n && n < 8)
			seen[n++] = got;
	}
	assert_true(cloth_px > 1000);	/* the sheet fills most of the picture */
	*one = seen[0];
	render_free(&im);
	free(x);
	free(field);
	return n;
}

static void
strain_colours_a_stretched_sheet(void **state)
{
	struct scene sc;
	struct cloth cl;
	struct drape_err err;
	struct rgb relaxed, stretched, stretched_all;

	(void)state;
	parse_text(&sc, SHEET);
	assert_int_equal(cloth_build(&cl, &sc, &err), 0);
	/* 2 % along warp and weft, on a scale of 5 %: one colour, a warm one */
	assert_int_equal(sheet_colours(&sc, &cl, 1.02, COLOUR_WARP, &stretched), 1);
	assert_int_equal(sheet_colours(&sc, &cl, 1.0, COLOUR_WARP, &relaxed), 1);
	assert_false(same(stretched, relaxed));
	assert_true(stretched.r > stretched.b + 40);
	/* relaxed: the middle of the diverging scale, a grey */
	assert_true(abs(relaxed.r - relaxed.g) <= 2 && abs(relaxed.g - relaxed.b) <= 2);
	/* compressed: cool */
	assert_int_equal(sheet_colours(&sc, &cl, 0.98, COLOUR_WEFT, &stretched), 1);
	assert_true(stretched.b > stretched.r + 40);
	/* the largest strain: one colour each, different */
	assert_int_equal(sheet_colours(&sc, &cl, 1.02, COLOUR_STRAIN, &stretched_all), 1);
	assert_int_equal(sheet_colours(&sc, &cl, 1.0, COLOUR_STRAIN, &relaxed), 1);
	assert_false(same(stretched_all, relaxed));
	/* a uniform stretch has no shear */
	assert_int_equal(sheet_colours(&sc, &cl, 1.02, COLOUR_SHEAR, &stretched), 1);
	cloth_free(&cl);
	scene_free(&sc);
}

/* Contact colouring: the nodes of this step's events, orange with an
 * obstacle and red with the cloth (the cloth winning a node with both);
 * the pixels around such a node take its colour, and a step without
 * events leaves the sheet in its plain colour. */
static void
contact_colours_the_nodes_in_contact(void **state)
{
	struct scene sc;
	struct cloth cl;
	struct drape_err err;
	struct render im;
	struct camera cam;
	struct paint_opts po = { COLOUR_CONTACT, 1, 0, false };
	struct contact_event ev[3];
	double *field;
	float f[3];
	struct rgb obst, self;
	int i, n_obst = 0, n_self = 0, p;

	(void)state;
	parse_text(&sc, SHEET);
	assert_int_equal(cloth_build(&cl, &sc, &err), 0);
	assert_non_null(field = malloc((size_t)cl.n * sizeof *field));
	memset(ev, 0, sizeof ev);
	ev[0].node = 0;		/* a corner on an obstacle */
	ev[0].obstacle = 0;
	ev[1].node = 14;	/* a middle node on the cloth and an obstacle */
	ev[1].obstacle = -1;
	ev[2].node = 14;
	ev[2].obstacle = 0;
	assert_int_equal(colouring_field(COLOUR_CONTACT, &cl, cl.x0, ev, 3, field), 0);
	for (p = 0; p < cl.n; p++)
		assert_double_equal(field[p], p == 0 ? TOUCH_OBSTACLE : p == 14 ? TOUCH_CLOTH :
		    TOUCH_NONE, 0);
	colouring_colour(COLOUR_CONTACT, TOUCH_OBSTACLE, 1, f);
	obst = render_rgb(f);
	colouring_colour(COLOUR_CONTACT, TOUCH_CLOTH, 1, f);
	self = render_rgb(f);
	assert_false(same(obst, self));
	render_init(&im);
	assert_int_equal(render_resize(&im, 64, 64, 1), 0);
	camera_preset(&cam, VIEW_TOP, v3(0, 0, 0), 0.05);
	assert_int_equal(paint_scene(&im, &cam, &sc, &cl, cl.x0, field, &po), 0);
	/* unlit colours, seen from above under a light: compare the hue's
	 * order (orange: red over green over blue; the red: red far over both) */
	for (i = 0; i < 64 * 64; i++) {
		const unsigned char *c = im.rgb + 3 * i;

		if (im.kind[i] != CELL_CLOTH)
			continue;
		n_obst += c[0] > c[2] + 60 && c[1] > c[2] + 30;
		n_self += c[0] > c[1] + 60 && c[0] > c[2] + 40 && c[1] < c[2] + 30;
	}
	assert_true(n_obst > 0);
	assert_true(n_self > 0);
	/* no events: none */
	assert_int_equal(colouring_field(COLOUR_CONTACT, &cl, cl.x0, NULL, 0, field), 0);
	assert_int_equal(paint_scene(&im, &cam, &sc, &cl, cl.x0, field, &po), 0);
	for (i = 0, n_obst = 0; i < 64 * 64; i++) {
		const unsigned char *c = im.rgb + 3 * i;

		n_obst += im.kind[i] == CELL_CLOTH && c[0] > c[2] + 60;
	}
	assert_int_equal(n_obst, 0);
	render_free(&im);
	free(field);
	cloth_free(&cl);
	scene_free(&sc);
}

static void
scales_are_round(void **state)
{
	char buf[32];

	(void)state;
	assert_double_equal(colouring_range(COLOUR_WARP, 0.023), 0.05, 1e-15);
	assert_double_equal(colouring_range(COLOUR_WARP, 0.02), 0.02, 1e-15);
	assert_double_equal(colouring_range(COLOUR_STRAIN, 0.0012), 0.002, 1e-15);
	assert_double_equal(colouring_range(COLOUR_STRAIN, 0), 0.01, 1e-15);
	/* rounding at rest is not strain: the default scale, not one of 1e-16 */
	assert_double_equal(colouring_range(COLOUR_STRAIN, 3e-16), 0.01, 1e-15);
	assert_double_equal(colouring_range(COLOUR_WARP, 9e-5), 0.01, 1e-15);
	assert_double_equal(colouring_range(COLOUR_WARP, 1.5e-4), 2e-4, 1e-15);
	assert_double_equal(colouring_range(COLOUR_SHEAR, 1e-6), V3_PI / 180, 1e-15);
	assert_double_equal(colouring_range(COLOUR_SHEAR, 3 * V3_PI / 180), 5 * V3_PI / 180, 1e-15);
	colouring_label(COLOUR_WARP, 0.05, buf, sizeof buf);
	assert_string_equal(buf, "+5%");
	colouring_label(COLOUR_SHEAR, -2 * V3_PI / 180, buf, sizeof buf);
	assert_string_equal(buf, "-2 deg");
	assert_int_equal(colouring_from_name("contact"), COLOUR_CONTACT);
	assert_int_equal(colouring_from_name("stress"), -1);
}

/* ---- the picture's band and labels ---- */

/* Whether row y of rgb (w wide) from x0 to x1 holds only the band's
 * background and its ink: no colour bar, no swatch. */
static bool
only_ink(const unsigned char *rgb, int w, int y, int x0, int x1)
{
	int x;

	for (x = x0; x < x1; x++) {
		const unsigned char *p = rgb + 3 * ((size_t)y * (size_t)w + (size_t)x);

		if (!(p[0] == 255 && p[1] == 255 && p[2] == 255) &&
		    !(p[0] == 50 && p[1] == 50 && p[2] == 50))
			return false;
	}
	return true;
}

/* A legend that does not fit beside the name goes under it, clear of it
 * (it was drawn over the name at 480 pixels); one that fits stays beside. */
static void
legend_clear_of_the_name(void **state)
{
	struct scene sc;
	struct cloth cl;
	struct drape_err err;
	struct camera cam;
	struct picture_band b;
	struct picture_frame fr;
	struct picture_opts po = { 480, 120, COLOUR_WARP, 0.05, "a scene of a rather long name",
		1, 0 };
	unsigned char *rgb;
	int w, h, y, s = 2, coloured = 0, x;

	(void)state;
	parse_text(&sc, SHEET);
	assert_int_equal(cloth_build(&cl, &sc, &err), 0);
	camera_preset(&cam, VIEW_TOP, v3(0, 0, 0), 0.05);
	fr = (struct picture_frame){ 0, cl.x0, NULL };
	picture_band(&sc, &cam, &po, 1, &b);
	assert_int_equal(b.lines, 2);
	assert_int_equal(picture_strip(&sc, &cl, &cam, &fr, 1, &po, &rgb, &w, &h, &err), 0);
	assert_int_equal(w, 480);
	assert_int_equal(h, 120 + b.h);
	for (y = 120 + 1 + b.y_name; y < 120 + 1 + b.y_name + FONT_H * s; y++)
		if (!only_ink(rgb, w, y, 0, w))
			fail_msg("row %d of the name's line holds more than text", y);
	for (y = 120 + 1 + b.y_legend; y < 120 + 1 + b.y_legend + FONT_H * s; y++)
		for (x = 0; x < w; x++) {
			const unsigned char *p = rgb + 3 * ((size_t)y * (size_t)w + (size_t)x);

			coloured += p[0] != p[2];
		}
	assert_true(coloured > 100);	/* the scale's bar is on the second line */
	free(rgb);
	/* three frames wide: room for both on one line */
	picture_band(&sc, &cam, &po, 3, &b);
	assert_int_equal(b.lines, 1);
	assert_false(b.compact);
	assert_true(6 * s + b.name_w < 3 * 480 + 2 * PICTURE_GAP - 6 * s - b.legend_w);
	/* narrower than the whole legend: the compact one */
	po.w = 200;
	po.colouring = COLOUR_CONTACT;
	picture_band(&sc, &cam, &po, 1, &b);
	assert_true(b.compact);
	assert_true(b.legend_w <= 200 - 12);
	cloth_free(&cl);
	scene_free(&sc);
}

static void
time_labels_say_the_time(void **state)
{
	static const double strip[] = { 0, 0.14, 0.3 }, six[] = { 0, 0.06, 0.12, 0.18 },
		even[] = { 0, 0.1999999, 0.4 }, one[] = { 0.0500631 }, asked[] = { 0, 0.15 };

	(void)state;
	/* the frame nearest 0.15 s of a replay at 50 frames a second: 0.14,
	 * not "0.1" */
	assert_int_equal(picture_time_decimals(strip, 3), 2);
	assert_int_equal(picture_time_decimals(six, 4), 2);
	assert_int_equal(picture_time_decimals(even, 3), 1);
	assert_int_equal(picture_time_decimals(one, 1), 3);
	assert_int_equal(picture_time_decimals(asked, 2), 2);
}

/* ---- the braille view ---- */

static void
braille_dots_of_a_triangle(void **state)
{
	struct glyphs_grid g;
	struct camera cam;
	char row[64];

	(void)state;
	glyphs_init(&g);
	/* 10 x 5 cells: 20 x 20 square pixels, 10 a metre */
	assert_int_equal(glyphs_resize(&g, GLYPHS_BRAILLE, 10, 5), 0);
	assert_int_equal(g.im.w, 20);
	assert_int_equal(g.im.h, 20);
	assert_double_equal(g.im.aspect, 1, 0);
	camera_preset(&cam, VIEW_FRONT, v3(0, 0, 0), 1);
	render_clear(&g.im, (struct rgb){ 0, 0, 0 });
	/* corners at pixels (0, 0), (8, 0), (0, 8): pixel (i, j) is in when
	 * i + j <= 7 */
	flat_triangle(&g.im, &cam, v3(-1, 1, 0), v3(-0.2, 1, 0), v3(-1, 0.2, 0),
	    (struct rgb){ 255, 255, 255 }, CELL_CLOTH);
	glyphs_convert(&g);
	assert_int_equal(g.bits[0], 0xFF);		/* cell (0, 0): every dot */
	assert_int_equal(g.cp[0], 0x28FF);
	assert_int_equal(g.bits[1 * 10 + 1], 0x0B);	/* (1, 1): dots 1, 2, 4 */
	assert_int_equal(g.bits[3], 0x0B);		/* (3, 0): the same */
	assert_int_equal(g.bits[1 * 10 + 0], 0x7F);	/* (0, 1): all but dot 8 */
	assert_int_equal(g.bits[4], 0);			/* (4, 0): past the hypotenuse */
	assert_int_equal(g.cp[4], ' ');
	assert_int_equal(g.kind[0], CELL_CLOTH);
	glyphs_row(&g, 0, row, sizeof row);
	/* ⣿⣿⡿⠋: cell (2, 0) lacks its pixel (5, 3), dot 8 */
	assert_string_equal(row, "\xe2\xa3\xbf\xe2\xa3\xbf\xe2\xa1\xbf\xe2\xa0\x8b");
	/* a farther solid drawn over the same place changes nothing */
	flat_triangle(&g.im, &cam, v3(-1, 1, -0.5), v3(-0.2, 1, -0.5), v3(-1, 0.2, -0.5),
	    (struct rgb){ 255, 255, 255 }, CELL_SOLID);
	glyphs_convert(&g);
	assert_int_equal(g.kind[0], CELL_CLOTH);
	assert_int_equal(g.bits[1 * 10 + 1], 0x0B);
	/* a nearer one does */
	flat_triangle(&g.im, &cam, v3(-1, 1, 0.5), v3(1, 1, 0.5), v3(-1, -1, 0.5),
	    (struct rgb){ 255, 255, 255 }, CELL_SOLID);
	glyphs_convert(&g);
	assert_int_equal(g.kind[1 * 10 + 1], CELL_SOLID);
	/* hatched, every other row of pixels (issue 30: without colour a
	 * box and the cloth on it took the same dots): dots 1, 3, 4, 6 */
	assert_int_equal(g.bits[1 * 10 + 1], 0x2D);
	/* half blocks: 1 x 2 pixels a cell */
	assert_int_equal(glyphs_resize(&g, GLYPHS_BLOCKS, 10, 5), 0);
	assert_int_equal(g.im.h, 10);
	render_clear(&g.im, (struct rgb){ 0, 0, 0 });
	flat_triangle(&g.im, &cam, v3(-1, 1, 0), v3(0, 1, 0), v3(-1, 0, 0),
	    (struct rgb){ 255, 255, 255 }, CELL_CLOTH);
	glyphs_convert(&g);
	assert_int_equal(g.cp[0], 0x2588);		/* both halves */
	assert_int_equal(g.cp[9], ' ');
	/* an obstacle's cells are upper halves: hatched */
	flat_triangle(&g.im, &cam, v3(-1, 1, 0.5), v3(1, 1, 0.5), v3(-1, -1, 0.5),
	    (struct rgb){ 255, 255, 255 }, CELL_SOLID);
	glyphs_convert(&g);
	assert_int_equal(g.kind[0], CELL_SOLID);
	assert_int_equal(g.cp[0], 0x2580);
	glyphs_free(&g);
}

/* ---- through the binary ---- */

/* The cloth's cells (its ramp and the marks) in a text snapshot. */
static int
cloth_cells(const char *out)
{
	int n = 0;

	for (; *out != '\0'; out++)
		n += strchr(RASTER_RAMP "oX", *out) != NULL && *out != '.';
	return n;
}

/* Issue 30: at the strip's end its pile was a speck in the scene's
 * framing; a snapshot frames the cloth in the frames drawn by default
 * (--frame scene: as before). */
static void
snapshot_frames_the_cloth(void **state)
{
	struct result r;
	int cloth, scene;

	(void)state;
	drape(&r, "snapshot --time 3 --size 80x24 '" TOP_SRCDIR "/replays/strip.drr'");
	assert_int_equal(r.status, 0);
	cloth = cloth_cells(r.out);
	drape(&r, "snapshot --time 3 --size 80x24 --frame scene '" TOP_SRCDIR
	    "/replays/strip.drr'");
	assert_int_equal(r.status, 0);
	scene = cloth_cells(r.out);
	print_message("the strip's pile at 3 s: %d cells framed, %d in the scene's view\n",
	    cloth, scene);
	assert_true(cloth >= 3 * scene);
	drape(&r, "snapshot --frame all '" TOP_SRCDIR "/replays/strip.drr'");
	assert_int_equal(r.status, 2);
	assert_non_null(strstr(r.err, "--frame 'all': expected cloth or scene"));
}

static void
same_frame_same_bytes(void **state)
{
	struct result r;
	char args[1200], a[600], b[600];
	unsigned char *pa, *pb;
	size_t la, lb;
	struct png_image rd;

	(void)state;
	snprintf(a, sizeof a, "%s/a.png", dir);
	snprintf(b, sizeof b, "%s/b.png", dir);
	snprintf(args, sizeof args, "snapshot --png '%s' --step 1000 --size 160x120 --color strain "
	    "'" TOP_SRCDIR "/tests/data/tablecloth-rk4.drr'", a);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	snprintf(args, sizeof args, "snapshot --png '%s' --step 1000 --size 160x120 --color strain "
	    "'" TOP_SRCDIR "/tests/data/tablecloth-rk4.drr'", b);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	pa = slurp_file(a, &la);
	pb = slurp_file(b, &lb);
	assert_int_equal(la, lb);
	assert_memory_equal(pa, pb, la);
	png_read(pa, la, &rd);
	assert_int_equal(rd.w, 160);
	assert_int_equal(rd.h, 120);	/* the frame and the legend's band, as asked */
	free(rd.rgb);
	free(pa);
	free(pb);
	/* a filmstrip of three frames, side by side */
	snprintf(args, sizeof args, "snapshot --png '%s' --strip 0,0.1,0.2 --size 308x80 "
	    "--color contact '" TOP_SRCDIR "/tests/data/tablecloth-rk4.drr'", a);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	pa = slurp_file(a, &la);
	png_read(pa, la, &rd);
	assert_int_equal(rd.w, 3 * 100 + 2 * PICTURE_GAP);
	assert_int_equal(rd.h, 80);
	free(rd.rgb);
	free(pa);
	/* a scene, stepped to a time */
	snprintf(args, sizeof args, "snapshot --png '%s' --time 5ms --size 64x48 "
	    "'" TOP_SRCDIR "/scenes/hanging.scene'", a);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	pa = slurp_file(a, &la);
	png_read(pa, la, &rd);
	assert_int_equal(rd.w, 64);
	free(rd.rgb);
	free(pa);
}

/* Issue 30: the strain scale changed between pictures of one run (each
 * took the round number above the largest strain of the frames it drew),
 * so two pictures could not be compared. A replay's pictures now share
 * the scale of its whole run by default: the legends of two times are
 * the same pixels (the frames' are not); --range still fixes it. */
static void
one_scale_for_a_replay(void **state)
{
	static const char *const times[2] = { "0.1", "1.0" };
	struct result r;
	char args[1200], path[2][200];
	struct png_image im[2];
	unsigned char *buf, *buf1;
	size_t len, len1, row;
	int k, y, differ = 0;

	(void)state;
	for (k = 0; k < 2; k++) {
		snprintf(path[k], sizeof path[k], "%s/scale%d.png", dir, k);
		snprintf(args, sizeof args, "snapshot --png '%s' --time %s --color strain "
		    "--frame scene --size 480x400 '" TOP_SRCDIR "/replays/tablecloth.drr'",
		    path[k], times[k]);
		drape(&r, args);
		assert_int_equal(r.status, 0);
		buf = slurp_file(path[k], &len);
		png_read(buf, len, &im[k]);
		free(buf);
		assert_int_equal(im[k].w, 480);
		assert_int_equal(im[k].h, 400);
	}
	row = 3 * (size_t)im[0].w;
	/* the band's last 40 rows: the legend, its scale and its labels */
	for (y = 360; y < 400; y++)
		if (memcmp(im[0].rgb + row * (size_t)y, im[1].rgb + row * (size_t)y, row) != 0)
			fail_msg("the legends of t = 0.1 s and 1.0 s differ at row %d", y);
	for (y = 0; y < 300; y++)
		differ += memcmp(im[0].rgb + row * (size_t)y, im[1].rgb + row * (size_t)y, row) != 0;
	assert_true(differ > 0);
	free(im[0].rgb);
	free(im[1].rgb);
	/* --range in percent: the run's round scale, 50 % (it was taken as a
	 * bare strain, 5000 %), gives the default's bytes */
	snprintf(args, sizeof args, "snapshot --png '%s' --time 0.1 --color strain --range 50 "
	    "--frame scene --size 480x400 '" TOP_SRCDIR "/replays/tablecloth.drr'", path[1]);
	drape(&r, args);
	assert_int_equal(r.status, 0);
	buf = slurp_file(path[0], &len);
	buf1 = slurp_file(path[1], &len1);
	assert_int_equal(len, len1);
	assert_memory_equal(buf, buf1, len);
	free(buf);
	free(buf1);
}

static void
unicode_snapshot(void **state)
{
	struct result r;
	int lines = 0;
	const char *p;

	(void)state;
	drape(&r, "snapshot --unicode --size 40x12 --step 1000 '" TOP_SRCDIR
	    "/tests/data/tablecloth-rk4.drr'");
	assert_int_equal(r.status, 0);
	for (p = r.out; *p != '\0'; p++)
		lines += *p == '\n';
	assert_int_equal(lines, 12);
	assert_non_null(strstr(r.out, "\xe2\xa3\xbf"));	/* a full braille cell */
	/* not a terminal and not asked for: ASCII, whatever the locale */
	drape(&r, "snapshot --size 40x12 --step 1000 '" TOP_SRCDIR "/tests/data/tablecloth-rk4.drr'");
	assert_int_equal(r.status, 0);
	for (p = r.out; *p != '\0'; p++)
		assert_true((unsigned char)*p < 0x80);
}

static void
bad_arguments(void **state)
{
	struct result r;
	char args[1200], out[600];
	struct stat st;
	const char *rp = "'" TOP_SRCDIR "/tests/data/tablecloth-rk4.drr'";

	(void)state;
	snprintf(out, sizeof out, "%s/bad.png", dir);
#define TRY(code, want, ...) do { \
	snprintf(args, sizeof args, __VA_ARGS__); \
	drape(&r, args); \
	assert_int_equal(r.status, code); \
	if (strstr(r.err, want) == NULL) \
		fail_msg("drape %s: stderr '%s', expected '%s'", args, r.err, want); \
} while (0)
	TRY(2, "--size '8x8'", "snapshot --png '%s' --size 8x8 %s", out, rp);
	TRY(2, "from 16 to 16384 pixels wide", "snapshot --png '%s' --size 10x100 %s", out, rp);
	TRY(2, "--size '20000x100'", "snapshot --png '%s' --size 20000x100 %s", out, rp);
	TRY(2, "from 16 to 4096 high", "snapshot --png '%s' --size 100x5000 %s", out, rp);
	TRY(2, "--size '300x'", "snapshot --png '%s' --size 300x %s", out, rp);
	TRY(2, "1 to 1000 characters", "snapshot --size 2000x10 %s", rp);
	TRY(2, "--strip '0,,1'", "snapshot --png '%s' --strip 0,,1 %s", out, rp);
	TRY(2, "--strip 'a,b'", "snapshot --png '%s' --strip a,b %s", out, rp);
	TRY(2, "--strip '-1'", "snapshot --png '%s' --strip -1 %s", out, rp);
	TRY(2, "--strip ''", "snapshot --png '%s' --strip '' %s", out, rp);
	TRY(2, "ends at t = 0.3", "snapshot --png '%s' --strip 0,5 %s", out, rp);
	TRY(2, "need --png", "snapshot --strip 0,0.1 %s", rp);
	TRY(2, "one --step or one --time", "snapshot --png '%s' --step 5 --strip 0,0.1 %s", out, rp);
	TRY(2, "--frames '1'", "snapshot --png '%s' --frames 1 %s", out, rp);
	TRY(2, "wider than 16384", "snapshot --png '%s' --frames 40 %s", out, rp);
	TRY(2, "40 frames side by side leave each under 16 pixels wide", "snapshot --png '%s' "
	    "--frames 40 --size 500x100 %s", out, rp);
	TRY(2, "--color 'stress'", "snapshot --png '%s' --color stress %s", out, rp);
	TRY(2, "--range is the scale", "snapshot --png '%s' --range 5 %s", out, rp);
	TRY(2, "not with --png", "snapshot --png '%s' --unicode %s", out, rp);
	TRY(2, "not with --png", "snapshot --png '%s' --ascii %s", out, rp);
	assert_int_equal(stat(out, &st), -1);	/* nothing was written */
	/* outputs that cannot be written: exit 1, nothing left */
	TRY(1, "cannot write in /nonexistent-drape-dir", "snapshot --png "
	    "/nonexistent-drape-dir/x.png %s", rp);
	TRY(1, "/dev/null/x.png", "snapshot --png /dev/null/x.png %s", rp);
	snprintf(out, sizeof out, "%s/adir2", dir);
	assert_int_equal(mkdir(out, 0755), 0);
	TRY(1, out, "snapshot --png '%s' %s", out, rp);
	{
		DIR *d = opendir(dir);
		struct dirent *e;

		assert_non_null(d);
		while ((e = readdir(d)) != NULL)
			assert_null(strstr(e->d_name, ".tmp-"));
		closedir(d);
	}
#undef TRY
}

static bool
have_gnuplot(void)
{
	return system("command -v gnuplot >/dev/null 2>&1") == 0;
}

static void
plot_charts(void **state)
{
	struct result r;
	char args[1200], out[600];
	unsigned char *p;
	size_t len;
	struct png_image rd;

	(void)state;
	snprintf(out, sizeof out, "%s/plot.png", dir);
	/* without gnuplot: said, exit 1, nothing written */
	assert_int_equal(setenv("GNUPLOT", "/nonexistent/gnuplot", 1), 0);
	snprintf(args, sizeof args, "plot --png '%s' '" TOP_SRCDIR "/tests/data/tablecloth-rk4.drr'", out);
	drape(&r, args);
	assert_int_equal(r.status, 1);
	assert_non_null(strstr(r.err, "gnuplot not found"));
	assert_int_equal(unsetenv("GNUPLOT"), 0);
	drape(&r, "plot");
	assert_int_equal(r.status, 2);
	if (!have_gnuplot()) {
		printf("gnuplot not found: the charts themselves are not checked (skipped)\n");
		skip();
	}
	drape(&r, args);
	assert_int_equal(r.status, 0);
	assert_non_null(strstr(r.out, "energy (J)"));
	assert_non_null(strstr(r.out, "contacts per step"));
	assert_non_null(strstr(r.out, "obstacle"));
	p = slurp_file(out, &len);
	png_read(p, len, &rd);
	assert_true(rd.w >= 600 && rd.h >= 600);
	free(rd.rgb);
	free(p);
	snprintf(args, sizeof args, "plot '" TOP_SRCDIR "/scenes/hanging.scene'");
	drape(&r, args);
	assert_int_equal(r.status, 2);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(triangle_lands_on_its_pixels),
		cmocka_unit_test(nearer_hides_farther),
		cmocka_unit_test(png_rejects_bad_sizes_and_writes_whole),
		cmocka_unit_test(strain_colours_a_stretched_sheet),
		cmocka_unit_test(contact_colours_the_nodes_in_contact),
		cmocka_unit_test(scales_are_round),
		cmocka_unit_test(legend_clear_of_the_name),
		cmocka_unit_test(time_labels_say_the_time),
		cmocka_unit_test(braille_dots_of_a_triangle),
		cmocka_unit_test(same_frame_same_bytes),
		cmocka_unit_test(snapshot_frames_the_cloth),
		cmocka_unit_test(one_scale_for_a_replay),
		cmocka_unit_test(unicode_snapshot),
		cmocka_unit_test(bad_arguments),
		cmocka_unit_test(plot_charts),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
