/* mesh.c: triangle meshes: the OBJ reader, the icosahedron, the winding
 * number. */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grow.h"
#include "mesh.h"

#define TOKEN_SHOWN 40		/* characters of a bad token put in a message */

struct reader {
	const char *path;
	int line;
	struct drape_err *err;
	struct mesh *m;
	size_t xcap, tricap;	/* in vertices and triangles */
	uint64_t bytes;		/* read so far */
	int binary_line;	/* the first line with a byte no text holds, 0: none */
	int binary_byte;
	unsigned char blk[65536];	/* the file, a block at a time */
	size_t pos, len;
	bool eof;
};

static int
read_fail(struct reader *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static int
read_fail(struct reader *r, const char *fmt, ...)
{
	char msg[400];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(msg, sizeof msg, fmt, ap);
	va_end(ap);
	err_set(r->err, "%s:%d: %s", r->path, r->line, msg);
	return -1;
}

static size_t
token_len(const char *s)
{
	size_t n = 0;

	while (s[n] != '\0' && !isspace((unsigned char)s[n]))
		n++;
	return n;
}

static const char *
skip_space(const char *s)
{
	while (isspace((unsigned char)*s))
		s++;
	return s;
}

/* A number that fills the token at *s; *s moves past it. */
static int
read_number(struct reader *r, const char **s, const char *what, double *out)
{
	const char *tok = skip_space(*s);
	size_t len = token_len(tok);
	char *end;

	if (len == 0)
		return read_fail(r, "expected 3 numbers after 'v', got no %s", what);
	*out = strtod(tok, &end);
	if ((size_t)(end - tok) != len || !isfinite(*out))
		return read_fail(r, "expected a finite number for %s, got '%.*s'", what,
		    (int)(len < TOKEN_SHOWN ? len : TOKEN_SHOWN), tok);
	*s = tok + len;
	return 0;
}

static int
read_vertex(struct reader *r, const char *s)
{
	static const char *const coord[] = { "x", "y", "z" };
	struct mesh *m = r->m;
	double v[3], extra;
	int k;

	for (k = 0; k < 3; k++)
		if (read_number(r, &s, coord[k], &v[k]) != 0)
			return -1;
	/* w, or the colour some exporters append: checked, not kept */
	while (*(s = skip_space(s)) != '\0')
		if (read_number(r, &s, "an extra vertex value", &extra) != 0)
			return -1;
	if (m->nverts == OBJ_MAX_VERTICES)
		return read_fail(r, "expected at most %d vertices", OBJ_MAX_VERTICES);
	if (grow_array((void **)&m->x, &r->xcap, (size_t)m->nverts + 1, 3 * sizeof *m->x) != 0)
		return read_fail(r, "out of memory");
	memcpy(m->x + 3 * (size_t)m->nverts, v, sizeof v);
	m->nverts++;
	return 0;
}

/* One v, v/vt, v//vn or v/vt/vn: the vertex, 0-based. vt and vn are only
 * checked to be integers. */
static int
read_index(struct reader *r, const char *tok, size_t len, int *out)
{
	const char *p;
	char *end;
	long v;
	int slashes = 0, n = r->m->nverts;

	errno = 0;
	v = strtol(tok, &end, 10);
	/* then /vt, //vn or /vt/vn: only their shape is checked */
	p = end;
	if (end != tok && *p == '/') {
		for (p++; p < tok + len; p++)
			if (*p == '/') {
				if (++slashes > 1)
					break;
			} else if (!isdigit((unsigned char)*p) && !(*p == '-' && p[-1] == '/'))
				break;
	}
	if (end == tok || p != tok + len)
		return read_fail(r, "expected a vertex index, v, v/vt, v//vn or v/vt/vn, "
		    "got '%.*s'", (int)(len < TOKEN_SHOWN ? len : TOKEN_SHOWN), tok);
	if (n == 0)
		return read_fail(r, "expected vertices ('v' lines) before a face, got "
		    "index '%.*s'", (int)(len < TOKEN_SHOWN ? len : TOKEN_SHOWN), tok);
	if (errno == ERANGE || v == 0 || v > n || v < -(long)n)
		return read_fail(r, "expected a vertex index from 1 to %d or from -%d to -1, "
		    "got '%.*s'", n, n, (int)(end - tok), tok);
	*out = v > 0 ? (int)v - 1 : n + (int)v;
	return 0;
}

/* A polygon, cut into a fan about its first vertex as it is read. */
static int
read_face(struct reader *r, const char *s)
{
	struct mesh *m = r->m;
	int first = 0, prev = 0, cur = 0, k = 0;

	for (; *(s = skip_space(s)) != '\0'; s += token_len(s), k++) {
		if (read_index(r, s, token_len(s), &cur) != 0)
			return -1;
		if (k >= 2) {
			int *t;

			if (m->ntri == OBJ_MAX_TRIANGLES)
				return read_fail(r, "expected at most %d triangles (a polygon of n "
				    "vertices makes n - 2)", OBJ_MAX_TRIANGLES);
			if (grow_array((void **)&m->tri, &r->tricap, m->ntri + 1, 3 * sizeof *t) != 0)
				return read_fail(r, "out of memory");
			t = m->tri + 3 * m->ntri++;
			t[0] = first;
			t[1] = prev;
			t[2] = cur;
		}
		if (k == 0)
			first = cur;
		prev = cur;
	}
	if (k < 3)
		return read_fail(r, "expected a face of 3 or more vertices, got %d", k);
	return 0;
}

static int
read_line(struct reader *r, char *line, size_t n)
{
	char *hash;
	const char *s;
	size_t len;

	if (n == 0)
		return 0;
	if ((hash = memchr(line, '#', n)) != NULL)
		*hash = '\0';
	s = skip_space(line);
	len = token_len(s);
	if (len == 1 && s[0] == 'v')
		return read_vertex(r, s + 1);
	if (len == 1 && s[0] == 'f')
		return read_face(r, s + 1);
	return 0;
}

/* A byte that no text file holds (the whitespace controls aside). */
static int
not_text(int c)
{
	return (c < 0x20 && c != '\t' && c != '\r' && c != '\v' && c != '\f') || c == 0x7f;
}

/* The next line of f into line (OBJ_MAX_LINE + 1 bytes), its newline
 * dropped: 1, 0 at the end of the file, -1 with err set. The file is read
 * a block at a time into r->blk. */
static int
next_line(struct reader *r, FILE *f, char *line, size_t *len)
{
	size_t n = 0, i;
	bool nl = false;

	r->line++;
	while (!nl) {
		const unsigned char *p, *stop;
		size_t k;

		if (r->pos == r->len) {
			if (r->eof)
				break;
			r->pos = 0;
			r->len = fread(r->blk, 1, sizeof r->blk, f);
			if (r->len < sizeof r->blk) {
				r->eof = true;
				if (ferror(f)) {
					err_set(r->err, "%s: read failed: %s", r->path, strerror(errno));
					return -1;
				}
			}
			if ((r->bytes += r->len) > OBJ_MAX_BYTES)
				return read_fail(r, "expected a file of at most %d MiB",
				    OBJ_MAX_BYTES >> 20);
			continue;
		}
		p = r->blk + r->pos;
		stop = *p == '\n' ? p : memchr(p, '\n', r->len - r->pos);
		k = stop != NULL ? (size_t)(stop - p) : r->len - r->pos;
		nl = stop != NULL;
		r->pos += k + nl;
		if (k > OBJ_MAX_LINE - n)
			return read_fail(r, "expected a line of at most %d bytes", OBJ_MAX_LINE);
		for (i = 0; i < k; i++)
			if (not_text(p[i])) {
				if (p[i] == '\0')
					return read_fail(r, "expected text (a Wavefront OBJ file), found "
					    "a NUL byte");
				if (r->binary_line == 0) {
					r->binary_line = r->line;
					r->binary_byte = p[i];
				}
			}
		memcpy(line + n, p, k);
		n += k;
	}
	line[n] = '\0';
	*len = n;
	if (r->line == 1 && n >= 3 && memcmp(line, "\xef\xbb\xbf", 3) == 0)
		return read_fail(r, "expected plain text, found a UTF-8 byte order mark (EF BB BF) "
		    "at the start: save the file as UTF-8 without BOM");
	return nl || n > 0 ? 1 : 0;
}

int
mesh_read_obj(struct mesh *m, FILE *f, const char *name, struct drape_err *err)
{
	struct reader r;
	char *line;
	size_t n = 0;
	int rc;

	memset(m, 0, sizeof *m);
	memset(&r, 0, sizeof r);
	r.path = name;
	r.err = err;
	r.m = m;
	if ((line = malloc(OBJ_MAX_LINE + 1)) == NULL) {
		err_set(err, "%s: out of memory", name);
		return -1;
	}
	while ((rc = next_line(&r, f, line, &n)) == 1 && (rc = read_line(&r, line, n)) == 0)
		;
	free(line);
	if (rc == 0 && m->ntri == 0) {
		if (r.binary_line > 0)
			err_set(err, "%s: expected at least one face ('f' line), found none: it is "
			    "not a text file (byte 0x%02x on line %d)", name, r.binary_byte,
			    r.binary_line);
		else
			err_set(err, "%s: expected at least one face ('f' line), found none", name);
		rc = -1;
	}
	if (rc != 0)
		mesh_free(m);
	return rc;
}

int
mesh_load_obj(struct mesh *m, const char *path, struct drape_err *err)
{
	FILE *f;
	int rc;

	memset(m, 0, sizeof *m);
	if ((f = fopen(path, "r")) == NULL) {
		err_set(err, "%s: cannot open: %s", path, strerror(errno));
		return -1;
	}
	rc = mesh_read_obj(m, f, path, err);
	if (fclose(f) != 0 && rc == 0) {
		err_set(err, "%s: read failed: %s", path, strerror(errno));
		mesh_free(m);
		rc = -1;
	}
	return rc;
}

int
mesh_icosahedron(struct mesh *m, vec3 centre, double radius)
{
	/* the golden rectangles (0, +-1, +-g), (+-1, +-g, 0), (+-g, 0, +-1) */
	static const signed char vert[12][3] = {
		{ -1, 2, 0 }, { 1, 2, 0 }, { -1, -2, 0 }, { 1, -2, 0 },
		{ 0, -1, 2 }, { 0, 1, 2 }, { 0, -1, -2 }, { 0, 1, -2 },
		{ 2, 0, -1 }, { 2, 0, 1 }, { -2, 0, -1 }, { -2, 0, 1 },
	};
	static const int face[20][3] = {
		{ 0, 11, 5 }, { 0, 5, 1 }, { 0, 1, 7 }, { 0, 7, 10 }, { 0, 10, 11 },
		{ 1, 5, 9 }, { 5, 11, 4 }, { 11, 10, 2 }, { 10, 7, 6 }, { 7, 1, 8 },
		{ 3, 9, 4 }, { 3, 4, 2 }, { 3, 2, 6 }, { 3, 6, 8 }, { 3, 8, 9 },
		{ 4, 9, 5 }, { 2, 4, 11 }, { 6, 2, 10 }, { 8, 6, 7 }, { 9, 8, 1 },
	};
	double g = (1 + sqrt(5.0)) / 2, s = radius / sqrt(1 + g * g), c[3];
	int v, k;

	memset(m, 0, sizeof *m);
	if ((m->x = malloc(3 * 12 * sizeof *m->x)) == NULL ||
	    (m->tri = malloc(sizeof face)) == NULL) {
		mesh_free(m);
		return -1;
	}
	v3_store(c, centre);
	for (v = 0; v < 12; v++)
		for (k = 0; k < 3; k++)
			m->x[3 * v + k] = c[k] + s * (vert[v][k] == 2 ? g :
			    vert[v][k] == -2 ? -g : vert[v][k]);
	memcpy(m->tri, face, sizeof face);
	m->nverts = 12;
	m->ntri = 20;
	return 0;
}

void
mesh_transform(struct mesh *m, double scale, vec3 offset)
{
	int v;

	for (v = 0; v < m->nverts; v++)
		v3_store(m->x + 3 * v, v3_madd(offset, v3_load(m->x + 3 * v), scale));
}

double
mesh_winding_number(const struct mesh *m, vec3 p)
{
	double sum = 0;
	size_t t;

	for (t = 0; t < m->ntri; t++) {
		const int *i = m->tri + 3 * t;
		vec3 a = v3_sub(v3_load(m->x + 3 * i[0]), p);
		vec3 b = v3_sub(v3_load(m->x + 3 * i[1]), p);
		vec3 c = v3_sub(v3_load(m->x + 3 * i[2]), p);
		double la = v3_len(a), lb = v3_len(b), lc = v3_len(c);
		double num = v3_dot(a, v3_cross(b, c));
		double den = la * lb * lc + v3_dot(a, b) * lc + v3_dot(a, c) * lb +
		    v3_dot(b, c) * la;

		/* tan(omega / 2) = num / den; atan2 keeps the half-angle's
		 * quadrant, so omega spans (-2 pi, 2 pi] */
		sum += 2 * atan2(num, den);
	}
	return sum / (4 * V3_PI);
}

void
mesh_bounds(const struct mesh *m, vec3 *lo, vec3 *hi)
{
	int v;

	*lo = v3(INFINITY, INFINITY, INFINITY);
	*hi = v3(-INFINITY, -INFINITY, -INFINITY);
	for (v = 0; v < m->nverts; v++) {
		vec3 x = v3_load(m->x + 3 * v);

		v3_box_grow(lo, hi, x);
	}
}

void
mesh_free(struct mesh *m)
{
	free(m->x);
	free(m->tri);
	memset(m, 0, sizeof *m);
}
