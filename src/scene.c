/* scene.c: reads a scene file into struct scene, checking every value.
 *
 * The file is first split into lines by ini.c; each section kind has a table
 * of the keys it accepts, so an unknown key, a duplicate and a missing
 * required key are found in one place. Later issues add sections to
 * section_kinds[] and a reader for each. */
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cloth.h"
#include "grow.h"
#include "ini.h"
#include "override.h"
#include "replay.h"
#include "scene.h"
#include "units.h"

#define MAX_GRID 4096		/* nodes along one direction */
#define MAX_NODES (4 << 20)	/* nodes in all */
#define MAX_SCENE_BYTES (16 << 20)

struct group {
	const struct ini *ini;
	size_t first, end;	/* key entries [first, end) */
	const char *section;
	int line;		/* of the header */
};

struct pctx {
	const char *file;
	struct drape_err *err;
	struct scene *sc;
	const struct override_text *ov;	/* the --set overrides, or NULL */
	/* what a number without its unit means: refused in a scene (a bare
	 * weight of 150 was 150 kg/m2), SI in one a replay recorded */
	enum units_bare bare;
	/* raw selectors, resolved once [cloth] has given the grid size */
	struct raw_sel *raw;
	size_t nraw, rawcap;
	int cell_line;		/* of [collision] cell, 0: auto */
	int origin_line;	/* of [cloth] origin, else of [cloth] */
};

/* A node selector kept as text until the grid size is known. Its owner is
 * named by index: the arrays it lives in may still move. */
struct raw_sel {
	int line;
	int is_load;		/* else a motion */
	size_t index;
	char *text;
};

static const char *const simulation_keys[] = {
	"name", "duration", "dt", "integrator", "tolerance", "gravity", "output_rate", NULL
};
static const char *const cloth_keys[] = {
	"nodes", "shape", "spacing", "origin", "orientation", "velocity", "weight", "thickness",
	"modulus_warp", "modulus_weft", "shear_modulus", "bending_warp", "bending_weft",
	"damping", "spring_damping", NULL
};
static const char *const pin_keys[] = { "nodes", NULL };
static const char *const move_keys[] = { "nodes", "velocity", "path", "start", "stop", NULL };
static const char *const load_keys[] = { "nodes", "force", "start", "stop", NULL };
static const char *const collision_keys[] = {
	"self", "broad", "narrow", "inside", "cell", "restitution", "friction", "viscous_friction",
	"position", "obstacle_position", "segments", "keep_velocity", "seed_response", "memory", NULL
};
static const char *const plane_keys[] = { "point", "normal", "friction", NULL };
static const char *const box_keys[] = { "min", "max", "friction", NULL };
static const char *const sphere_keys[] = { "centre", "radius", "friction", NULL };
static const char *const disc_keys[] = { "centre", "radius", "height", "friction", NULL };
static const char *const mesh_keys[] = { "file", "scale", "offset", "friction", NULL };
static const char *const icosahedron_keys[] = { "centre", "radius", "friction", NULL };

static int get_word(struct pctx *, const struct group *, const char *, const char *const *,
    int *);
static int read_simulation(struct pctx *, const struct group *);
static int read_cloth(struct pctx *, const struct group *);
static int read_pin(struct pctx *, const struct group *);
static int read_move(struct pctx *, const struct group *);
static int read_load(struct pctx *, const struct group *);
static int read_collision(struct pctx *, const struct group *);
static int read_obstacle(struct pctx *, const struct group *);

static const struct section_kind {
	const char *name;
	const char *const *keys;
	int once;
	int (*read)(struct pctx *, const struct group *);
} section_kinds[] = {
	{ "simulation", simulation_keys, 1, read_simulation },
	{ "cloth", cloth_keys, 1, read_cloth },
	{ "pin", pin_keys, 0, read_pin },
	{ "move", move_keys, 0, read_move },
	{ "load", load_keys, 0, read_load },
	{ "collision", collision_keys, 1, read_collision },
	{ "plane", plane_keys, 0, read_obstacle },
	{ "box", box_keys, 0, read_obstacle },
	{ "sphere", sphere_keys, 0, read_obstacle },
	{ "disc", disc_keys, 0, read_obstacle },
	{ "mesh", mesh_keys, 0, read_obstacle },
	{ "icosahedron", icosahedron_keys, 0, read_obstacle },
};

const char *const cloth_shape_name[] = { "square", "disc", NULL };
static const char *const inside_test_name[] = { "angle", "crossing", NULL };
static const char *const switch_name[] = { "off", "on", NULL };
#define NSECTION_KINDS (sizeof section_kinds / sizeof section_kinds[0])

static int
fail(struct pctx *c, int line, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

static int
fail(struct pctx *c, int line, const char *fmt, ...)
{
	char msg[400];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(msg, sizeof msg, fmt, ap);
	va_end(ap);
	if (c->ov != NULL) {	/* the file's line, or the --set that made it */
		char where[300];

		override_where(c->ov, c->file, line, where, sizeof where);
		err_set(c->err, "%s: %s", where, msg);
	} else {
		err_set(c->err, "%s:%d: %s", c->file, line, msg);
	}
	return -1;
}

static const struct ini_entry *
find(const struct group *g, const char *key)
{
	size_t i;

	for (i = g->first; i < g->end; i++)
		if (strcmp(g->ini->e[i].key, key) == 0)
			return &g->ini->e[i];
	return NULL;
}

static void
join_keys(char *buf, size_t len, const char *const *keys)
{
	size_t off = 0;

	buf[0] = '\0';
	for (; *keys != NULL && off < len; keys++)
		off += (size_t)snprintf(buf + off, len - off, "%s%s", off ? ", " : "", *keys);
}

/* Unknown and repeated keys, before any value is read. */
static int
check_keys(struct pctx *c, const struct group *g, const char *const *keys)
{
	size_t i, j;

	for (i = g->first; i < g->end; i++) {
		const struct ini_entry *e = &g->ini->e[i];
		const char *const *k;

		for (k = keys; *k != NULL; k++)
			if (strcmp(*k, e->key) == 0)
				break;
		if (*k == NULL) {
			char list[300];

			join_keys(list, sizeof list, keys);
			return fail(c, e->line, "unknown key '%s' in [%s]; expected one of: %s",
			    e->key, g->section, list);
		}
		for (j = g->first; j < i; j++)
			if (strcmp(g->ini->e[j].key, e->key) == 0)
				return fail(c, e->line, "%s: already set at line %d",
				    e->key, g->ini->e[j].line);
	}
	return 0;
}

static int
missing(struct pctx *c, const struct group *g, const char *key, const char *what)
{
	return fail(c, g->line, "[%s] needs '%s' (%s)", g->section, key, what);
}

enum bound { ANY, POSITIVE, NONNEGATIVE };

/* units_parse's reason, if it gave one, as " (why)": three arguments for
 * "%s%s%s" */
#define REASON(why) (why)[0] != '\0' ? " (" : "", (why), (why)[0] != '\0' ? ")" : ""

/* Examples for the keys whose dimension's own would read oddly. */
static const struct {
	const char *key, *example;
} key_examples[] = {
	{ "output_rate", "50 Hz" }, { "dt", "0.1 ms" }, { "spring_damping", "1 ms" },
	{ "thickness", "0.55 mm" }, { "origin", "-0.12 0.15 -0.12 m" },
};

/* A key's value with its unit, for a message. */
static const char *
example_of(const char *key, enum unit_dim dim, int n)
{
	size_t i;

	for (i = 0; i < sizeof key_examples / sizeof key_examples[0]; i++)
		if (strcmp(key_examples[i].key, key) == 0)
			return key_examples[i].example;
	return units_example(dim, n);
}

/* "a length (m, cm, mm, um)", or "3 numbers and the unit of a length
 * (...)", or "2 numbers" */
static void
expected_numbers(char *buf, size_t len, enum unit_dim dim, int n)
{
	if (n == 1)
		snprintf(buf, len, "%s", units_describe(dim));
	else if (dim == DIM_NONE)
		snprintf(buf, len, "%d numbers", n);
	else
		snprintf(buf, len, "%d numbers and the unit of %s", n, units_describe(dim));
}

/* Numbers given without the unit their key needs. */
static int
no_unit(struct pctx *c, const struct ini_entry *e, enum unit_dim dim, int n)
{
	char what[160];

	expected_numbers(what, sizeof what, dim, n);
	return fail(c, e->line, "%s: expected %s%s, such as '%s = %s'; got '%s', with no unit",
	    e->key, what, n == 1 ? " with its unit" : "", e->key, example_of(e->key, dim, n),
	    e->value);
}

/*
 * Reads n numbers of dimension dim. Returns 1 if the key was there, 0 if it
 * is absent and optional, -1 on error (absent and required, or malformed).
 */
static int
get_numbers(struct pctx *c, const struct group *g, const char *key, enum unit_dim dim, int n,
    enum bound bound, int required, double *out)
{
	const struct ini_entry *e = find(g, key);
	char why[200], what[160];
	int k, rc;

	expected_numbers(what, sizeof what, dim, n);
	if (e == NULL)
		return required ? missing(c, g, key, what) : 0;
	if ((rc = units_parse_as(e->value, dim, c->bare, out, n, why, sizeof why)) == UNITS_NO_UNIT)
		return no_unit(c, e, dim, n);
	if (rc != 0)
		return fail(c, e->line, "%s: expected %s, got '%s'%s%s%s", key, what, e->value,
		    REASON(why));
	for (k = 0; k < n; k++) {
		if (dim == DIM_LENGTH && !(fabs(out[k]) <= SCENE_MAX_COORD))
			return fail(c, e->line, "%s: expected %s of at most %g m either way, got '%s'",
			    key, n > 1 ? "coordinates" : "a length", SCENE_MAX_COORD, e->value);
		if (bound == POSITIVE && !(out[k] > 0))
			return fail(c, e->line, "%s: expected %s greater than 0, got '%s'", key,
			    units_describe(dim), e->value);
		if (bound == NONNEGATIVE && !(out[k] >= 0))
			return fail(c, e->line, "%s: expected %s of 0 or more, got '%s'", key,
			    units_describe(dim), e->value);
	}
	return 1;
}

static char *
xstrdup(const char *s)
{
	size_t n = strlen(s) + 1;
	char *d = malloc(n);

	if (d != NULL)
		memcpy(d, s, n);
	return d;
}

/* ---- [simulation] ---- */

static int
read_simulation(struct pctx *c, const struct group *g)
{
	struct scene *sc = c->sc;
	const struct ini_entry *e;
	double gv[3];

	if (get_numbers(c, g, "duration", DIM_TIME, 1, POSITIVE, 1, &sc->duration) < 0)
		return -1;
	if ((e = find(g, "name")) != NULL) {
		free(sc->name);
		if ((sc->name = xstrdup(e->value)) == NULL)
			return fail(c, e->line, "out of memory");
	}
	sc->dt_line = g->line;
	if ((e = find(g, "dt")) != NULL)
		sc->dt_line = e->line;
	if (e != NULL && strcmp(e->value, "auto") != 0) {
		char why[200];
		int rc;

		why[0] = '\0';
		if ((rc = units_parse_as(e->value, DIM_TIME, c->bare, &sc->dt, 1, why,
		    sizeof why)) == UNITS_NO_UNIT)
			return no_unit(c, e, DIM_TIME, 1);
		if (rc != 0 || !(sc->dt > 0))
			return fail(c, e->line, "dt: expected 'auto' or %s greater than 0, got "
			    "'%s'%s%s%s", units_describe(DIM_TIME), e->value, REASON(why));
		if (scene_steps(sc->duration, sc->dt) > SCENE_MAX_STEPS)
			return fail(c, e->line, "dt: expected a step that covers the duration (%g s) "
			    "in at most %.0e steps, got '%s' (%.3g steps)", sc->duration,
			    SCENE_MAX_STEPS, e->value, scene_steps(sc->duration, sc->dt));
	}
	if ((e = find(g, "integrator")) != NULL &&
	    integrator_from_name(e->value, &sc->integrator) != 0) {
		char names[200];

		integrator_names(names, sizeof names);
		return fail(c, e->line, "integrator: expected %s, got '%s'", names, e->value);
	}
	if (get_numbers(c, g, "tolerance", DIM_NONE, 1, POSITIVE, 0, &sc->tolerance) < 0)
		return -1;
	if ((e = find(g, "gravity")) != NULL) {
		char why[200];
		int one, three = -1;

		/* One value is a magnitude pointing down -y; three are a vector. */
		if ((one = units_parse_as(e->value, DIM_ACCEL, c->bare, gv, 1, why, sizeof why)) == 0) {
			sc->gravity[0] = 0;
			sc->gravity[1] = -gv[0];
			sc->gravity[2] = 0;
		} else if ((three = units_parse_as(e->value, DIM_ACCEL, c->bare, gv, 3, why,
		    sizeof why)) == 0) {
			memcpy(sc->gravity, gv, sizeof gv);
		} else if (one == UNITS_NO_UNIT || three == UNITS_NO_UNIT) {
			return no_unit(c, e, DIM_ACCEL, one == UNITS_NO_UNIT ? 1 : 3);
		} else {
			return fail(c, e->line, "gravity: expected a magnitude (pointing down -y) or "
			    "a vector gx gy gz, as %s, got '%s'", units_describe(DIM_ACCEL), e->value);
		}
	}
	if (get_numbers(c, g, "output_rate", DIM_RATE, 1, POSITIVE, 0, &sc->output_rate) < 0)
		return -1;
	if (scene_frames(sc->duration, sc->output_rate) > SCENE_MAX_FRAMES) {
		if ((e = find(g, "output_rate")) == NULL)
			return fail(c, find(g, "duration")->line, "duration: expected at most %.0e "
			    "frames at the output rate (%g per second), so at most %.4g s, got '%s'",
			    SCENE_MAX_FRAMES, sc->output_rate, SCENE_MAX_FRAMES / sc->output_rate,
			    find(g, "duration")->value);
		return fail(c, e->line, "output_rate: expected at most %.0e frames over the "
		    "duration (%g s), so at most %.4g per second, got '%s' (%.3g frames)",
		    SCENE_MAX_FRAMES, sc->duration, SCENE_MAX_FRAMES / sc->duration, e->value,
		    scene_frames(sc->duration, sc->output_rate));
	}
	return 0;
}

double
scene_steps(double duration, double dt)
{
	return duration / dt;
}

double
scene_frames(double duration, double output_rate)
{
	return duration * output_rate;
}

/* ---- [cloth] ---- */

static int
parse_axis(const char *s, double out[3])
{
	int sign = 1;

	if (*s == '+' || *s == '-')
		sign = *s++ == '-' ? -1 : 1;
	if (s[0] == '\0' || s[1] != '\0' || s[0] < 'x' || s[0] > 'z')
		return -1;
	out[0] = out[1] = out[2] = 0;
	out[s[0] - 'x'] = sign;
	return 0;
}

static int
read_orientation(struct pctx *c, const struct ini_entry *e)
{
	struct scene *sc = c->sc;
	char a[8], b[8], extra[2];

	if (sscanf(e->value, "%7s %7s %1s", a, b, extra) != 2 ||
	    parse_axis(a, sc->warp_axis) != 0 || parse_axis(b, sc->weft_axis) != 0)
		return fail(c, e->line, "orientation: expected the warp and weft axes, such as "
		    "'+x +z' (horizontal) or '+x -y' (hanging), got '%s'", e->value);
	if (fabs(sc->warp_axis[0] * sc->weft_axis[0] + sc->warp_axis[1] * sc->weft_axis[1] +
	    sc->warp_axis[2] * sc->weft_axis[2]) > 0)
		return fail(c, e->line, "orientation: expected two different axes, got '%s'",
		    e->value);
	return 0;
}

static int
read_bending(struct pctx *c, const struct group *g, const char *key, int dir)
{
	struct material *m = &c->sc->mat;
	const struct ini_entry *e = find(g, key);

	if (e == NULL)
		return missing(c, g, key, "a bending rigidity such as 5 uN*m, 0 for none, or "
		    "'derived' for modulus*thickness^3/12");
	if (strcmp(e->value, "derived") == 0) {
		m->bending_derived[dir] = true;
		return 0;
	}
	return get_numbers(c, g, key, DIM_BENDING, 1, NONNEGATIVE, 1, &m->bending[dir]) < 0 ? -1 : 0;
}

/* A disc is the circle inscribed in a square grid; under 4 x 4 nodes it
 * would hold no whole square (cloth.c keeps the squares inside it). */
static int
read_shape(struct pctx *c, const struct group *g)
{
	struct scene *sc = c->sc;
	int shape = SHAPE_SQUARE;

	if (get_word(c, g, "shape", cloth_shape_name, &shape) < 0)
		return -1;
	sc->shape = (enum cloth_shape)shape;
	if (sc->shape == SHAPE_DISC && (sc->nu != sc->nv || sc->nu < 4))
		return fail(c, find(g, "shape")->line, "shape = disc: expected a square grid of "
		    "at least 4 x 4 nodes (nodes = n n), got %d x %d", sc->nu, sc->nv);
	return 0;
}

static int
read_cloth(struct pctx *c, const struct group *g)
{
	struct scene *sc = c->sc;
	struct material *m = &sc->mat;
	const struct ini_entry *e;
	double nodes[2];
	char why[200];
	int dir;

	if ((e = find(g, "nodes")) == NULL)
		return missing(c, g, "nodes", "the nodes along the warp and the weft, such as "
		    "'nodes = 25 25'");
	if (units_parse(e->value, DIM_NONE, nodes, 2, why, sizeof why) != 0)
		return fail(c, e->line, "nodes: expected two whole numbers, the nodes along the "
		    "warp and along the weft, such as 'nodes = 25 25', got '%s'%s%s%s", e->value,
		    REASON(why));
	if (nodes[0] != floor(nodes[0]) || nodes[1] != floor(nodes[1]) || nodes[0] < 1 ||
	    nodes[1] < 1 || nodes[0] > MAX_GRID || nodes[1] > MAX_GRID ||
	    nodes[0] * nodes[1] > MAX_NODES)
		return fail(c, e->line, "nodes: expected two whole numbers nu nv, each from 1 to %d "
		    "(%d nodes at most), got '%s'", MAX_GRID, MAX_NODES, e->value);
	sc->nu = (int)nodes[0];
	sc->nv = (int)nodes[1];
	if (read_shape(c, g) != 0)
		return -1;

	if (get_numbers(c, g, "spacing", DIM_LENGTH, 1, POSITIVE, 1, &sc->spacing) < 0 ||
	    get_numbers(c, g, "origin", DIM_LENGTH, 3, ANY, 0, sc->origin) < 0 ||
	    get_numbers(c, g, "velocity", DIM_VELOCITY, 3, ANY, 0, sc->velocity) < 0 ||
	    get_numbers(c, g, "weight", DIM_AREAL_DENSITY, 1, POSITIVE, 1, &m->weight) < 0 ||
	    get_numbers(c, g, "thickness", DIM_LENGTH, 1, POSITIVE, 1, &m->thickness) < 0 ||
	    get_numbers(c, g, "modulus_warp", DIM_PRESSURE, 1, POSITIVE, 1, &m->modulus[0]) < 0 ||
	    get_numbers(c, g, "modulus_weft", DIM_PRESSURE, 1, POSITIVE, 1, &m->modulus[1]) < 0 ||
	    get_numbers(c, g, "shear_modulus", DIM_PRESSURE, 1, NONNEGATIVE, 1,
		&m->shear_modulus) < 0 ||
	    read_bending(c, g, "bending_warp", 0) < 0 ||
	    read_bending(c, g, "bending_weft", 1) < 0 ||
	    get_numbers(c, g, "damping", DIM_RATE, 1, NONNEGATIVE, 0, &m->damping) < 0 ||
	    get_numbers(c, g, "spring_damping", DIM_TIME, 1, NONNEGATIVE, 0,
		&m->spring_damping) < 0)
		return -1;
	if ((e = find(g, "orientation")) != NULL && read_orientation(c, e) != 0)
		return -1;
	c->origin_line = (e = find(g, "origin")) != NULL ? e->line : g->line;
	for (dir = 0; dir < 3; dir++) {
		double far = sc->origin[dir] + sc->spacing * ((sc->nu - 1) * sc->warp_axis[dir] +
		    (sc->nv - 1) * sc->weft_axis[dir]);

		if (!(fabs(far) <= SCENE_MAX_COORD))
			return fail(c, find(g, "spacing")->line, "spacing: the cloth reaches %g m "
			    "from the origin along %c; expected all of it within %g m", fabs(far),
			    "xyz"[dir], SCENE_MAX_COORD);
	}
	for (dir = 0; dir < 2; dir++)
		if (m->bending_derived[dir])	/* a plate's E*t^3/12, Poisson ignored */
			m->bending[dir] = m->modulus[dir] * pow(m->thickness, 3) / 12;
	return 0;
}

/* ---- node sets: "I J, I J, ..." with I, J an index, a..b or * ---- */

static int
add_raw(struct pctx *c, int line, int is_load, size_t index, const char *text)
{
	if (grow_array((void **)&c->raw, &c->rawcap, c->nraw + 1, sizeof *c->raw) != 0)
		return fail(c, line, "out of memory");
	c->raw[c->nraw] = (struct raw_sel){ line, is_load, index, xstrdup(text) };
	if (c->raw[c->nraw].text == NULL)
		return fail(c, line, "out of memory");
	c->nraw++;
	return 0;
}

static int
parse_index(const char **sp, int n, int *out)
{
	char *end;
	long v;

	errno = 0;
	v = strtol(*sp, &end, 10);
	if (end == *sp || errno != 0)
		return -1;
	*sp = end;
	if (v < 0)
		v += n;		/* -1 is the last node */
	if (v < 0 || v >= n)
		return -2;
	*out = (int)v;
	return 0;
}

/* One of "*", "K" or "A..B" into [lo, hi]. */
static int
parse_range(const char **sp, int n, int *lo, int *hi)
{
	const char *s = *sp;
	int r;

	while (isspace((unsigned char)*s))
		s++;
	if (*s == '*') {
		*lo = 0;
		*hi = n - 1;
		*sp = s + 1;
		return 0;
	}
	if ((r = parse_index(&s, n, lo)) != 0)
		return r;
	*hi = *lo;
	if (s[0] == '.' && s[1] == '.') {
		s += 2;
		if ((r = parse_index(&s, n, hi)) != 0)
			return r;
		if (*hi < *lo)
			return -1;
	}
	*sp = s;
	return 0;
}

static int
resolve_selector(struct pctx *c, const struct raw_sel *r)
{
	struct node_set *set = r->is_load ? &c->sc->loads[r->index].nodes :
	    &c->sc->motions[r->index].nodes;
	const char *s = r->text;

	for (;;) {
		struct node_block b;
		struct node_block *nb;
		int e1, e2 = 0;

		if ((e1 = parse_range(&s, c->sc->nu, &b.i0, &b.i1)) == 0)
			e2 = parse_range(&s, c->sc->nv, &b.j0, &b.j1);
		while (isspace((unsigned char)*s))
			s++;
		if (e1 == -2 || e2 == -2)
			return fail(c, r->line, "nodes: index out of range in '%s'; the grid is "
			    "%d x %d (i from 0 to %d, j from 0 to %d; -1 is the last)", r->text,
			    c->sc->nu, c->sc->nv, c->sc->nu - 1, c->sc->nv - 1);
		if (e1 != 0 || e2 != 0 || (*s != ',' && *s != '\0'))
			return fail(c, r->line, "nodes: expected pairs 'I J' separated by commas, "
			    "each an index, a range A..B or *, such as '0 *, -1 0', got '%s'", r->text);
		if ((nb = realloc(set->b, (set->n + 1) * sizeof *nb)) == NULL)
			return fail(c, r->line, "out of memory");
		set->b = nb;
		set->b[set->n++] = b;
		if (*s == '\0')
			return 0;
		s++;
	}
}

static int
read_nodes(struct pctx *c, const struct group *g, int is_load, size_t index)
{
	const struct ini_entry *e = find(g, "nodes");

	if (e == NULL)
		return missing(c, g, "nodes", "node pairs 'I J' such as '0 *'");
	return add_raw(c, e->line, is_load, index, e->value);
}

static int
read_window(struct pctx *c, const struct group *g, double *start, double *stop)
{
	*start = 0;
	*stop = INFINITY;
	if (get_numbers(c, g, "start", DIM_TIME, 1, NONNEGATIVE, 0, start) < 0 ||
	    get_numbers(c, g, "stop", DIM_TIME, 1, NONNEGATIVE, 0, stop) < 0)
		return -1;
	if (!(*stop > *start))
		return fail(c, find(g, "stop")->line, "stop: expected a time after start (%g s)",
		    *start);
	return 0;
}

/* ---- [pin], [move], [load] ---- */

static struct scene_motion *
new_motion(struct pctx *c, const struct group *g)
{
	struct scene *sc = c->sc;
	struct scene_motion *m = realloc(sc->motions, (sc->nmotions + 1) * sizeof *m);

	if (m == NULL) {
		fail(c, g->line, "out of memory");
		return NULL;
	}
	sc->motions = m;
	m = &sc->motions[sc->nmotions++];
	memset(m, 0, sizeof *m);
	m->line = g->line;
	m->stop = INFINITY;
	return m;
}

static int
read_pin(struct pctx *c, const struct group *g)
{
	struct scene_motion *m = new_motion(c, g);

	if (m == NULL)
		return -1;
	m->kind = MOTION_PIN;
	return read_nodes(c, g, 0, c->sc->nmotions - 1);
}

/*
 * A path's point "T DX DY DZ": the time with its unit, then the
 * displacement's three numbers with theirs ("0.3 s -0.1 0 0 m"). The time's
 * unit is the word after its number, so that a recorded scene's bare
 * "0.3 -0.1 0 0" still reads. 0, -1, or UNITS_NO_UNIT.
 */
static int
parse_path_point(const char *point, enum units_bare bare, double p[4], char *why, size_t len)
{
	const char *s = point, *unit_end;
	char time[64];
	char *end;
	int rc;

	if (len > 0)
		why[0] = '\0';
	while (isspace((unsigned char)*s))
		s++;
	(void)strtod(s, &end);
	if (end == s)
		return -1;
	unit_end = end;
	while (isspace((unsigned char)*unit_end))
		unit_end++;
	if (isalpha((unsigned char)*unit_end) || *unit_end == '/')
		while (*unit_end != '\0' && !isspace((unsigned char)*unit_end))
			unit_end++;
	else
		unit_end = end;
	if ((size_t)(unit_end - s) >= sizeof time)
		return -1;
	memcpy(time, s, (size_t)(unit_end - s));
	time[unit_end - s] = '\0';
	if ((rc = units_parse_as(time, DIM_TIME, bare, p, 1, why, len)) != 0)
		return rc;
	return units_parse_as(unit_end, DIM_LENGTH, bare, p + 1, 3, why, len);
}

static int
read_path(struct pctx *c, const struct ini_entry *e, struct scene_motion *m)
{
	const char *s = e->value;
	double prev = 0;

	for (;;) {
		const char *comma = strchr(s, ',');
		size_t len = comma ? (size_t)(comma - s) : strlen(s);
		char point[256], why[200];
		double *p;
		int rc;

		if (len >= sizeof point)
			return fail(c, e->line, "path: point too long");
		memcpy(point, s, len);
		point[len] = '\0';
		if ((p = realloc(m->path, (m->npath + 1) * 4 * sizeof *p)) == NULL)
			return fail(c, e->line, "out of memory");
		m->path = p;
		p += 4 * m->npath;
		if ((rc = parse_path_point(point, c->bare, p, why, sizeof why)) != 0)
			return fail(c, e->line, "path: expected points 'T DX DY DZ', a time and a "
			    "displacement each with its unit, separated by commas, such as "
			    "'path = 0.3 s -0.1 0 0 m, 1 s -0.1 0.05 0 m'; got '%s'%s%s%s", point,
			    rc == UNITS_NO_UNIT ? " (no unit)" : why[0] != '\0' ? " (" : "",
			    rc == UNITS_NO_UNIT ? "" : why, rc != UNITS_NO_UNIT && why[0] != '\0' ?
			    ")" : "");
		if (!(p[0] > prev))
			return fail(c, e->line, "path: expected times after 0 that increase, got "
			    "%g after %g", p[0], prev);
		if (!(fabs(p[1]) <= SCENE_MAX_COORD && fabs(p[2]) <= SCENE_MAX_COORD &&
		    fabs(p[3]) <= SCENE_MAX_COORD))
			return fail(c, e->line, "path: expected displacements of at most %g m either "
			    "way, got '%s'", SCENE_MAX_COORD, point);
		prev = p[0];
		m->npath++;
		if (comma == NULL)
			return 0;
		s = comma + 1;
	}
}

static int
read_move(struct pctx *c, const struct group *g)
{
	struct scene_motion *m = new_motion(c, g);
	const struct ini_entry *vel, *path;
	int r;

	if (m == NULL || read_nodes(c, g, 0, c->sc->nmotions - 1) < 0 ||
	    read_window(c, g, &m->start, &m->stop) < 0)
		return -1;
	vel = find(g, "velocity");
	path = find(g, "path");
	if ((vel == NULL) == (path == NULL))
		return fail(c, g->line, "[move] needs either 'velocity' (vx vy vz) or 'path' "
		    "(t dx dy dz, ...), not %s", vel ? "both" : "neither");
	if (vel != NULL) {
		m->kind = MOTION_VELOCITY;
		r = get_numbers(c, g, "velocity", DIM_VELOCITY, 3, ANY, 1, m->velocity);
		return r < 0 ? -1 : 0;
	}
	if (find(g, "start") || find(g, "stop"))
		return fail(c, g->line, "[move]: a path sets its own times; expected no start or stop");
	m->kind = MOTION_PATH;
	return read_path(c, path, m);
}

static int
read_load(struct pctx *c, const struct group *g)
{
	struct scene *sc = c->sc;
	struct scene_load *l = realloc(sc->loads, (sc->nloads + 1) * sizeof *l);

	if (l == NULL)
		return fail(c, g->line, "out of memory");
	sc->loads = l;
	l = &sc->loads[sc->nloads++];
	memset(l, 0, sizeof *l);
	l->line = g->line;
	if (read_nodes(c, g, 1, sc->nloads - 1) < 0 || read_window(c, g, &l->start, &l->stop) < 0 ||
	    get_numbers(c, g, "force", DIM_FORCE, 3, ANY, 1, l->force) < 0)
		return -1;
	return 0;
}

/* ---- [collision] and the obstacles ---- */

/* A word out of a NULL-terminated list: 1 and *out its index if the key is
 * there, 0 if absent, -1 if not one of them. */
static int
get_word(struct pctx *c, const struct group *g, const char *key, const char *const *names,
    int *out)
{
	const struct ini_entry *e = find(g, key);
	char list[200];
	int k;

	if (e == NULL)
		return 0;
	for (k = 0; names[k] != NULL; k++)
		if (strcmp(names[k], e->value) == 0) {
			*out = k;
			return 1;
		}
	join_keys(list, sizeof list, names);
	return fail(c, e->line, "%s: expected one of %s, got '%s'", key, list, e->value);
}

static int
read_collision(struct pctx *c, const struct group *g)
{
	struct collision_opts *o = &c->sc->col;
	const struct ini_entry *e;
	int self = 1, broad = o->broad, narrow = o->narrow, inside = o->inside;
	int position = o->position, segments = o->segments, keep_velocity = o->keep_velocity;
	int seed_response = o->seed_response;
	/* obstacle_position: a policy's name, or "position" (the default) */
	static const char *const obstacle_position_name[] = { "keep", "q", "slide", "position",
	    NULL };
	int obstacle_position = o->obstacle_position < 0 ? 3 : o->obstacle_position;

	_Static_assert(POSITION_KEEP == 0 && POSITION_Q == 1 && POSITION_SLIDE == 2,
	    "obstacle_position_name lists the policies in their order");
	if (get_word(c, g, "self", switch_name, &self) < 0 ||
	    get_word(c, g, "broad", broad_mode_name, &broad) < 0 ||
	    get_word(c, g, "narrow", narrow_mode_name, &narrow) < 0 ||
	    get_word(c, g, "inside", inside_test_name, &inside) < 0 ||
	    get_word(c, g, "position", position_policy_name, &position) < 0 ||
	    get_word(c, g, "obstacle_position", obstacle_position_name, &obstacle_position) < 0 ||
	    get_word(c, g, "segments", seed_segments_name, &segments) < 0 ||
	    get_word(c, g, "keep_velocity", keep_velocity_name, &keep_velocity) < 0 ||
	    get_word(c, g, "seed_response", seed_response_name, &seed_response) < 0)
		return -1;
	o->seed_response = seed_response;
	o->keep_velocity = keep_velocity;
	o->obstacle_position = obstacle_position == 3 ? -1 : obstacle_position;
	o->segments = segments;
	o->self = self;
	o->broad = broad;
	o->narrow = narrow;
	o->inside = inside;
	o->position = position;
	if ((e = find(g, "cell")) != NULL && strcmp(e->value, "auto") != 0) {
		if (get_numbers(c, g, "cell", DIM_LENGTH, 1, POSITIVE, 1, &o->cell) < 0)
			return -1;
		c->cell_line = e->line;
	}
	if ((e = find(g, "memory")) != NULL && strcmp(e->value, "auto") != 0 &&
	    get_numbers(c, g, "memory", DIM_BYTES, 1, POSITIVE, 1, &o->memory) < 0)
		return -1;
	if (o->memory != 0 && o->memory < 1e6)
		return fail(c, e->line, "memory: expected 'auto' or at least 1 MB, got %g B",
		    o->memory);
	if (get_numbers(c, g, "restitution", DIM_NONE, 1, NONNEGATIVE, 0, &o->restitution) < 0 ||
	    get_numbers(c, g, "friction", DIM_NONE, 1, NONNEGATIVE, 0, &o->friction) < 0 ||
	    get_numbers(c, g, "viscous_friction", DIM_RATE, 1, NONNEGATIVE, 0, &o->viscous) < 0)
		return -1;
	if (o->restitution > 1)
		return fail(c, find(g, "restitution")->line, "restitution: expected a number "
		    "from 0 (perfectly inelastic) to 1, got %g", o->restitution);
	return 0;
}

static int
get_vec(struct pctx *c, const struct group *g, const char *key, int required, vec3 *v)
{
	double p[3];
	int rc = get_numbers(c, g, key, DIM_LENGTH, 3, ANY, required, p);

	if (rc == 1)
		*v = v3_load(p);
	return rc;
}

/* Every vertex, scaled and offset, within SCENE_MAX_COORD of the origin;
 * the line blamed is the scale's, else the offset's, else the file's. */
static int
check_mesh_reach(struct pctx *c, const struct group *g, const struct mesh *m)
{
	const struct ini_entry *e = find(g, "scale");
	int v, k;

	if (e == NULL && (e = find(g, "offset")) == NULL)
		e = find(g, "file");
	for (v = 0; v < m->nverts; v++)
		for (k = 0; k < 3; k++)
			if (!(fabs(m->x[3 * v + k]) <= SCENE_MAX_COORD))
				return fail(c, e->line, "%s: the mesh reaches %g m from the origin "
				    "along %c (vertex %d); expected all of it within %g m", e->key,
				    fabs(m->x[3 * v + k]), "xyz"[k], v + 1, SCENE_MAX_COORD);
	return 0;
}

/* A mesh file is found beside the scene file unless its path is absolute. */
static int
read_mesh(struct pctx *c, const struct group *g, struct obstacle *o)
{
	const struct ini_entry *e = find(g, "file");
	const char *slash = strrchr(c->file, '/');
	double scale = 1;
	vec3 offset = v3(0, 0, 0);
	struct drape_err merr;
	char *path;
	size_t dir;

	if (e == NULL)
		return missing(c, g, "file", "the path of a Wavefront OBJ file");
	dir = e->value[0] != '/' && slash != NULL ? (size_t)(slash - c->file) + 1 : 0;
	if ((path = malloc(dir + strlen(e->value) + 1)) == NULL)
		return fail(c, e->line, "out of memory");
	memcpy(path, c->file, dir);
	strcpy(path + dir, e->value);
	if (mesh_load_obj(&o->mesh, path, &merr) != 0) {
		free(path);
		return fail(c, e->line, "file: %s", merr.msg);
	}
	o->file = path;		/* freed with the obstacle */
	if (get_numbers(c, g, "scale", DIM_NONE, 1, POSITIVE, 0, &scale) < 0 ||
	    get_vec(c, g, "offset", 0, &offset) < 0)
		return -1;
	mesh_transform(&o->mesh, scale, offset);
	return check_mesh_reach(c, g, &o->mesh);
}

static int
read_obstacle(struct pctx *c, const struct group *g)
{
	struct scene *sc = c->sc;
	struct obstacle *o, *no;
	struct drape_err oerr;

	if ((no = realloc(sc->obstacles, (sc->nobstacles + 1) * sizeof *no)) == NULL)
		return fail(c, g->line, "out of memory");
	sc->obstacles = no;
	o = &sc->obstacles[sc->nobstacles++];
	memset(o, 0, sizeof *o);
	o->line = g->line;
	if (get_numbers(c, g, "friction", DIM_NONE, 1, NONNEGATIVE, 0, &o->friction) < 0)
		return -1;
	if (strcmp(g->section, "plane") == 0) {
		o->kind = OBSTACLE_PLANE;
		if (get_vec(c, g, "point", 1, &o->point) < 0)
			return -1;
		o->normal = v3(0, 1, 0);
		if (find(g, "normal") != NULL) {
			double nv[3];

			if (get_numbers(c, g, "normal", DIM_NONE, 3, ANY, 1, nv) < 0)
				return -1;
			/* a subnormal vector's direction is known to a few bits, and
			 * its squares vanish */
			if (!(fmax(fabs(nv[0]), fmax(fabs(nv[1]), fabs(nv[2]))) >= DBL_MIN))
				return fail(c, find(g, "normal")->line, "normal: expected a direction, a "
				    "vector with a component of at least %g either way, got '%s'", DBL_MIN,
				    find(g, "normal")->value);
			o->normal = v3_load(nv);
		}
	} else if (strcmp(g->section, "box") == 0) {
		o->kind = OBSTACLE_BOX;
		if (get_vec(c, g, "min", 1, &o->lo) < 0 || get_vec(c, g, "max", 1, &o->hi) < 0)
			return -1;
	} else if (strcmp(g->section, "sphere") == 0 || strcmp(g->section, "disc") == 0) {
		o->kind = g->section[0] == 's' ? OBSTACLE_SPHERE : OBSTACLE_DISC;
		if (get_vec(c, g, "centre", 1, &o->centre) < 0 ||
		    get_numbers(c, g, "radius", DIM_LENGTH, 1, ANY, 1, &o->radius) < 0 ||
		    (o->kind == OBSTACLE_DISC &&
		    get_numbers(c, g, "height", DIM_LENGTH, 1, ANY, 1, &o->height) < 0))
			return -1;
	} else if (strcmp(g->section, "icosahedron") == 0) {
		o->kind = OBSTACLE_MESH;
		if (get_vec(c, g, "centre", 1, &o->centre) < 0 ||
		    get_numbers(c, g, "radius", DIM_LENGTH, 1, POSITIVE, 1, &o->radius) < 0)
			return -1;
		if (mesh_icosahedron(&o->mesh, o->centre, o->radius) != 0)
			return fail(c, g->line, "out of memory");
	} else {
		o->kind = OBSTACLE_MESH;
		if (read_mesh(c, g, o) != 0)
			return -1;
	}
	if (obstacle_check(o, &oerr) != 0)
		return fail(c, g->line, "[%s]: %s", g->section, oerr.msg);
	return 0;
}

/* ---- the whole file ---- */

/* The cubes of edge cell that [lo, hi] spans along each axis (as hash.c
 * counts them) and in all: the first axis past SCENE_MAX_CELLS, 3 if the
 * product is past SCENE_MAX_BOX_CELLS, or -1. */
static int
too_many_cells(vec3 lo, vec3 hi, double cell, double *cubes)
{
	double ext[3] = { hi.x - lo.x, hi.y - lo.y, hi.z - lo.z }, all = 1;
	int k;

	for (k = 0; k < 3; k++) {
		*cubes = floor(ext[k] / cell) + 1;
		if (!(*cubes <= SCENE_MAX_CELLS))
			return k;
		all *= *cubes;
	}
	*cubes = all;
	return all <= SCENE_MAX_BOX_CELLS ? -1 : 3;
}

/* "along x", or "in all" */
static const char *
cells_where(int axis)
{
	static const char *const where[] = { "along x", "along y", "along z", "in its box" };

	return where[axis];
}

/*
 * The spatial hash numbers its cubes along each axis by int and the cubes
 * of its box by int64 (hash.h): the cloth as it starts and the obstacle
 * meshes, which the broad phase puts in it, must span at most
 * SCENE_MAX_CELLS cubes along an axis and SCENE_MAX_BOX_CELLS in all, so
 * that the box can grow a thousandfold in volume as the run goes before
 * its keys overflow. The cube is the [collision] cell, or the spacing when
 * it is auto (the seed broad phase's is larger: eq. 21).
 */
static int
check_hash_extent(struct pctx *c)
{
	const struct scene *sc = c->sc;
	double p[3], cell = sc->col.cell > 0 ? sc->col.cell : sc->spacing, cubes;
	vec3 lo, hi;
	size_t o;
	int k, v, axis;

	/* the run's own rule, so that a mode without a hash (brute, bvh) is
	 * never refused for its bound */
	if (!collide_uses_hash(sc))
		return 0;
	for (k = 0; k < 3; k++)
		p[k] = sc->origin[k] + sc->spacing * ((sc->nu - 1) * sc->warp_axis[k] +
		    (sc->nv - 1) * sc->weft_axis[k]);
	lo = hi = v3_load(sc->origin);
	v3_box_grow(&lo, &hi, v3_load(p));
	if ((axis = too_many_cells(lo, hi, cell, &cubes)) >= 0)
		return fail(c, c->cell_line, "cell: the cloth spans %.3g cubes of %g m %s; "
		    "expected at most %d along an axis and %.4g in all (the spatial hash's "
		    "bound): a larger cell", cubes, cell, cells_where(axis), SCENE_MAX_CELLS,
		    SCENE_MAX_BOX_CELLS);
	for (o = 0; o < sc->nobstacles; o++) {
		const struct obstacle *ob = &sc->obstacles[o];

		if (ob->kind != OBSTACLE_MESH)
			continue;
		for (v = 0; v < ob->mesh.nverts; v++)
			v3_box_grow(&lo, &hi, v3_load(ob->mesh.x + 3 * v));
		if ((axis = too_many_cells(lo, hi, cell, &cubes)) >= 0)
			return fail(c, ob->line, "with this mesh the cloth and the obstacles span "
			    "%.3g cubes of %g m (%s) %s; expected at most %d along an axis and %.4g "
			    "in all (the spatial hash's bound): a smaller scale, or a larger "
			    "[collision] cell", cubes, cell, sc->col.cell > 0 ?
			    "the [collision] cell" : "the cloth's spacing", cells_where(axis),
			    SCENE_MAX_CELLS, SCENE_MAX_BOX_CELLS);
	}
	return 0;
}

/* A node is inside a solid past this depth (m): a cloth laid on a box's
 * top to the last bit stays out. */
#define START_INSIDE_DEPTH 1e-9

/* The cloth's node at grid position (i, j) as it starts. */
static vec3
start_node(const struct scene *sc, int i, int j)
{
	return v3_madd(v3_madd(v3_load(sc->origin), v3_load(sc->warp_axis), i * sc->spacing),
	    v3_load(sc->weft_axis), j * sc->spacing);
}

/* Whether a solid may hold a node of the cloth as it starts: its box meets
 * the flat cloth's, and a plane (whose distance is affine) holds a corner. */
static bool
may_hold_cloth(const struct scene *sc, const struct obstacle *o)
{
	vec3 corner[4], lo, hi, clo, chi;
	int k;

	for (k = 0; k < 4; k++)
		corner[k] = start_node(sc, k & 1 ? sc->nu - 1 : 0, k & 2 ? sc->nv - 1 : 0);
	if (o->kind == OBSTACLE_PLANE) {
		for (k = 0; k < 4; k++)
			if (obstacle_distance(o, corner[k], NULL, NULL) < -START_INSIDE_DEPTH)
				return true;
		return false;
	}
	clo = chi = corner[0];
	for (k = 1; k < 4; k++) {
		clo = v3(fmin(clo.x, corner[k].x), fmin(clo.y, corner[k].y), fmin(clo.z, corner[k].z));
		chi = v3(fmax(chi.x, corner[k].x), fmax(chi.y, corner[k].y), fmax(chi.z, corner[k].z));
	}
	obstacle_bounds(o, &lo, &hi);
	return clo.x <= hi.x && chi.x >= lo.x && clo.y <= hi.y && chi.y >= lo.y &&
	    clo.z <= hi.z && chi.z >= lo.z;
}

/*
 * A cloth that starts inside a solid obstacle is refused, at its origin:
 * the first step would throw its nodes out (a run said "the network
 * tore"). Meshes are left out: the cloth meets them as surfaces, from
 * either side (the icosahedron's node lives inside one).
 */
static int
check_start_outside(struct pctx *c)
{
	const struct scene *sc = c->sc;
	size_t o;
	int i, j;

	for (o = 0; o < sc->nobstacles; o++) {
		const struct obstacle *ob = &sc->obstacles[o];
		long count = 0;
		int fi = 0, fj = 0;
		double depth = 0;

		if (ob->kind == OBSTACLE_MESH || !may_hold_cloth(sc, ob))
			continue;
		for (j = 0; j < sc->nv; j++)
			for (i = 0; i < sc->nu; i++) {
				double d;

				if (!cloth_grid_has_node(sc->shape, sc->nu, sc->nv, i, j) ||
				    !((d = obstacle_distance(ob, start_node(sc, i, j), NULL, NULL)) <
				    -START_INSIDE_DEPTH))
					continue;
				if (count++ == 0) {
					fi = i;
					fj = j;
					depth = -d;
				}
			}
		if (count > 0) {
			vec3 p = start_node(sc, fi, fj);
			char more[48] = "";

			if (count > 1)
				snprintf(more, sizeof more, " (%ld nodes in all)", count);
			return fail(c, c->origin_line, "origin: the cloth starts inside the [%s] of "
			    "line %d: its node at i %d, j %d, (%g, %g, %g) m, is %.3g mm inside%s; "
			    "expected the whole cloth outside the obstacles as it starts",
			    obstacle_kind_name[ob->kind], ob->line, fi, fj, p.x, p.y, p.z,
			    depth * 1e3, more);
		}
	}
	return 0;
}

static void
set_defaults(struct scene *sc)
{
	sc->dt = 0;
	sc->integrator = INTEG_RK4;
	sc->tolerance = 0;	/* the integrator's default */
	sc->gravity[1] = -9.80665;
	sc->output_rate = 50;
	sc->warp_axis[0] = 1;
	sc->weft_axis[2] = 1;
	/* no [collision]: the cloth does not meet itself; with one, the
	 * defaults are those that never miss */
	sc->col.self = false;
	sc->col.broad = BROAD_GRID;
	sc->col.narrow = NARROW_CCD;
	sc->col.inside = INSIDE_ANGLE;
	sc->col.position = POSITION_SLIDE;
	sc->col.obstacle_position = -1;
	sc->col.segments = SEGMENTS_BOTH;
}

static char *
default_name(const char *path)
{
	const char *base = strrchr(path, '/');
	char *name, *dot;

	name = xstrdup(base != NULL ? base + 1 : path);
	if (name != NULL && (dot = strrchr(name, '.')) != NULL && dot != name)
		*dot = '\0';
	return name;
}

int
scene_section_repeats(const char *name)
{
	size_t s;

	for (s = 0; s < NSECTION_KINDS; s++)
		if (strcmp(section_kinds[s].name, name) == 0)
			return !section_kinds[s].once;
	return -1;
}

/* text (with its overrides, if ov) into sc. */
static int
parse_text(struct scene *sc, const char *path, const char *text, const struct override_text *ov,
    enum units_bare bare, struct drape_err *err)
{
	struct pctx c = { path, err, sc, ov, bare, NULL, 0, 0, 0, 0 };
	int seen[NSECTION_KINDS] = { 0 };
	struct ini ini;
	size_t i, k;
	int rc = -1;

	memset(sc, 0, sizeof *sc);
	set_defaults(sc);
	if ((sc->path = xstrdup(path)) == NULL || (sc->text = xstrdup(text)) == NULL ||
	    (sc->name = default_name(path)) == NULL) {
		err_set(err, "%s: out of memory", path);
		scene_free(sc);
		return -1;
	}
	if (strlen(text) > MAX_SCENE_BYTES) {
		err_set(err, "%s:1: expected a scene of at most %d bytes", path, MAX_SCENE_BYTES);
		scene_free(sc);
		return -1;
	}
	if (strncmp(text, "\xef\xbb\xbf", 3) == 0) {
		err_set(err, "%s:1: expected plain text, found a UTF-8 byte order mark (EF BB BF) "
		    "at the start: save the file as UTF-8 without BOM", path);
		scene_free(sc);
		return -1;
	}
	if (ini_parse(&ini, path, text, err) != 0) {
		scene_free(sc);
		return -1;
	}

	for (i = 0; i < ini.n; i = k) {
		const struct ini_entry *h = &ini.e[i];
		struct group g = { &ini, i + 1, i + 1, h->section, h->line };
		size_t s;

		for (k = i + 1; k < ini.n && ini.e[k].key != NULL; k++)
			;
		g.end = k;
		for (s = 0; s < NSECTION_KINDS; s++)
			if (strcmp(section_kinds[s].name, h->section) == 0)
				break;
		if (s == NSECTION_KINDS) {
			fail(&c, h->line, "unknown section [%s]; expected [simulation], [cloth], "
			    "[pin], [move], [load], [collision], [plane], [box], [sphere], "
			    "[disc], [mesh] or [icosahedron]", h->section);
			goto out;
		}
		if (section_kinds[s].once && seen[s]) {
			fail(&c, h->line, "[%s] given twice; expected it once", h->section);
			goto out;
		}
		seen[s] = h->line;
		if (check_keys(&c, &g, section_kinds[s].keys) != 0 ||
		    section_kinds[s].read(&c, &g) != 0)
			goto out;
	}
	for (i = 0; i < 2; i++)		/* [simulation] and [cloth] */
		if (!seen[i]) {
			fail(&c, ini.last_line > 0 ? ini.last_line : 1,
			    "expected a [%s] section", section_kinds[i].name);
			goto out;
		}
	for (i = 0; i < c.nraw; i++)
		if (resolve_selector(&c, &c.raw[i]) != 0)
			goto out;
	if (check_hash_extent(&c) != 0)
		goto out;
	if (bare == UNITS_BARE_REFUSED && check_start_outside(&c) != 0)
		goto out;
	rc = 0;
out:
	for (i = 0; i < c.nraw; i++)
		free(c.raw[i].text);
	free(c.raw);
	ini_free(&ini);
	if (rc != 0)
		scene_free(sc);
	return rc;
}

int
scene_parse(struct scene *sc, const char *path, const char *text, struct drape_err *err)
{
	return parse_text(sc, path, text, NULL, UNITS_BARE_REFUSED, err);
}

int
scene_parse_recorded(struct scene *sc, const char *path, const char *text, struct drape_err *err)
{
	return parse_text(sc, path, text, NULL, UNITS_BARE_SI, err);
}

int
scene_parse_set(struct scene *sc, const char *path, const char *text, const char *const *sets,
    size_t nsets, struct drape_err *err)
{
	struct override_text ov;
	int rc;

	if (nsets == 0)
		return parse_text(sc, path, text, NULL, UNITS_BARE_REFUSED, err);
	memset(sc, 0, sizeof *sc);
	if (override_apply(&ov, path, text, sets, nsets, err) != 0)
		return -1;
	rc = parse_text(sc, path, ov.text, &ov, UNITS_BARE_REFUSED, err);
	override_free(&ov);
	return rc;
}

int
scene_load(struct scene *sc, const char *path, struct drape_err *err)
{
	return scene_load_set(sc, path, NULL, 0, err);
}

int
scene_load_set(struct scene *sc, const char *path, const char *const *sets, size_t nsets,
    struct drape_err *err)
{
	/* room for one byte past the bound, so that a longer file shows it */
	const size_t most = (size_t)MAX_SCENE_BYTES + 1;
	FILE *f;
	char *buf = NULL;
	size_t len = 0, cap = 0, got;
	int rc;

	memset(sc, 0, sizeof *sc);
	if ((f = fopen(path, "rb")) == NULL) {
		err_set(err, "%s: cannot open: %s", path, strerror(errno));
		return -1;
	}
	do {
		if (len == cap) {
			size_t want = cap == 0 ? 16384 : cap < most / 2 ? 2 * cap : most;
			char *nb;

			if (cap == most)
				break;
			if ((nb = realloc(buf, want)) == NULL) {
				err_set(err, "%s: out of memory", path);
				free(buf);
				fclose(f);
				return -1;
			}
			buf = nb;
			cap = want;
		}
		got = fread(buf + len, 1, cap - len, f);
		len += got;
	} while (got > 0);
	if (ferror(f)) {
		err_set(err, "%s: read error: %s", path, strerror(errno));
		free(buf);
		fclose(f);
		return -1;
	}
	fclose(f);
	/* scene_parse_bytes_set refuses more than MAX_SCENE_BYTES */
	rc = scene_parse_bytes_set(sc, path, buf, len, sets, nsets, err);
	free(buf);
	return rc;
}

int
scene_parse_bytes(struct scene *sc, const char *path, const void *data, size_t len,
    struct drape_err *err)
{
	return scene_parse_bytes_set(sc, path, data, len, NULL, 0, err);
}

int
scene_parse_bytes_set(struct scene *sc, const char *path, const void *data, size_t len,
    const char *const *sets, size_t nsets, struct drape_err *err)
{
	const char *nul, *p;
	char *text;
	int line = 1, rc;

	memset(sc, 0, sizeof *sc);
	if (len >= REPLAY_MAGIC_LEN && memcmp(data, REPLAY_MAGIC, REPLAY_MAGIC_LEN) == 0) {
		err_set(err, "%s:1: expected a scene, found a drape replay (drape replay, info, "
		    "events, export, snapshot and run --resume read replays)", path);
		return -1;
	}
	if (len > MAX_SCENE_BYTES) {
		err_set(err, "%s:1: expected a scene of at most %d bytes", path, MAX_SCENE_BYTES);
		return -1;
	}
	if ((nul = memchr(data, '\0', len)) != NULL) {
		for (p = data; p < nul; p++)
			line += *p == '\n';
		err_set(err, "%s:%d: expected a text file, found a NUL byte", path, line);
		return -1;
	}
	if ((text = malloc(len + 1)) == NULL) {
		err_set(err, "%s: out of memory", path);
		return -1;
	}
	memcpy(text, data, len);
	text[len] = '\0';
	rc = scene_parse_set(sc, path, text, sets, nsets, err);
	free(text);
	return rc;
}

int
node_set_fits(const struct node_set *set, int nu, int nv)
{
	size_t b;

	for (b = 0; b < set->n; b++)
		if (set->b[b].i0 < 0 || set->b[b].i1 >= nu || set->b[b].i0 > set->b[b].i1 ||
		    set->b[b].j0 < 0 || set->b[b].j1 >= nv || set->b[b].j0 > set->b[b].j1)
			return 0;
	return 1;
}

void
scene_free(struct scene *sc)
{
	size_t i;

	for (i = 0; i < sc->nmotions; i++) {
		free(sc->motions[i].nodes.b);
		free(sc->motions[i].path);
	}
	for (i = 0; i < sc->nloads; i++)
		free(sc->loads[i].nodes.b);
	for (i = 0; i < sc->nobstacles; i++)
		obstacle_free(&sc->obstacles[i]);
	free(sc->obstacles);
	free(sc->motions);
	free(sc->loads);
	free(sc->path);
	free(sc->name);
	free(sc->text);
	memset(sc, 0, sizeof *sc);
}

bool
collide_broad_runs(const struct scene *sc)
{
	size_t o;

	for (o = 0; o < sc->nobstacles; o++)
		if (sc->obstacles[o].kind == OBSTACLE_MESH)
			return true;
	return sc->col.self;
}

bool
collide_active(const struct scene *sc)
{
	return collide_broad_runs(sc) || sc->nobstacles > 0;
}

bool
collide_uses_hash(const struct scene *sc)
{
	return collide_broad_runs(sc) && broad_uses_hash(sc->col.broad);
}
