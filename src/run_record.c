/* run_record.c: a run's record, and its machine-readable forms.
 *
 * One function lists the fields (visit), in groups, each with its name and
 * value; the JSON writer nests the groups as objects, the CSV writer names
 * its columns GROUP.NAME. Both thus print the same fields in the same
 * order, and a field added to visit is in both. */
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "config.h"
#include "run_record.h"
#include "network.h"
#include "shadow.h"
#include "stats.h"
#include "vec3.h"

#define DRAPE_RASTER 0.5e-3	/* m: the shadow's cells, 1/600 of a 30 cm specimen */

const char *const run_outcome_name[] = { "completed", "blowup", "error", "interrupted", NULL };

/* The Cusick drape test, for a disc-shaped specimen on the scene's first
 * [disc]. */
static void
fill_drape(struct run_record *rec, const double *x)
{
	const struct scene *sc = rec->sc;
	const struct cloth *cl = rec->cl;
	const struct obstacle *disc = NULL;
	size_t o;

	for (o = 0; o < sc->nobstacles && disc == NULL; o++)
		if (sc->obstacles[o].kind == OBSTACLE_DISC)
			disc = &sc->obstacles[o];
	if (disc == NULL || cl->shape != SHAPE_DISC)
		return;
	if (shadow_area(x, cl->tri, cl->ntri, DRAPE_RASTER, &rec->shadow, &rec->raster) != 0) {
		rec->drape = -1;
		return;
	}
	rec->support = V3_PI * disc->radius * disc->radius;
	rec->flat = mesh_area(cl->x0, cl->tri, cl->ntri);
	rec->dc = drape_coefficient(rec->shadow, rec->support, rec->flat);
	/* a lobe counts from a thirtieth of the specimen's radius out (5 mm
	 * on the standard 30 cm specimen), and at least a square: the flat
	 * disc's staircase rim is ragged by under one */
	rec->folds = drape_folds(x, cl->edge, cl->nedges, disc->centre.x, disc->centre.z,
	    DRAPE_RASTER, fmax(sqrt(rec->flat / V3_PI) / 30, cl->h));
	rec->drape = 1;
}

void
run_record_fill(struct run_record *rec, const struct stepper *st, double wall)
{
	memset(rec, 0, sizeof *rec);
	rec->sc = stepper_scene(st);
	rec->cl = &stepper_network(st)->cl;
	stepper_report(st, &rec->r);
	stepper_energy(st, &rec->e);
	rec->wall = wall;
	rec->hash = stepper_hash(st);
	fill_drape(rec, stepper_x(st));
	rec->outcome = RUN_COMPLETED;
}

/* ---- the fields ---- */

enum kind { K_NULL, K_NUM, K_INT, K_STR, K_BOOL, K_LIST };

struct value {
	enum kind kind;
	double num;
	long i;
	const char *s;
	bool b;
	const char *const *list;
	size_t n;
};

struct writer {
	FILE *f;
	void (*field)(struct writer *w, const char *group, const char *name,
	    const struct value *v);
	const char *group;	/* the open group (JSON), or NULL */
	int fields;		/* written so far in the open object */
	int top;		/* written so far at the top */
	bool header;		/* CSV: names, not values */
};

static void
put(struct writer *w, const char *group, const char *name, struct value v)
{
	w->field(w, group, name, &v);
}

static void
num(struct writer *w, const char *g, const char *n, bool have, double x)
{
	put(w, g, n, (struct value){ .kind = have && isfinite(x) ? K_NUM : K_NULL, .num = x });
}

static void
integer(struct writer *w, const char *g, const char *n, bool have, long x)
{
	put(w, g, n, (struct value){ .kind = have ? K_INT : K_NULL, .i = x });
}

static void
str(struct writer *w, const char *g, const char *n, const char *s)
{
	put(w, g, n, (struct value){ .kind = s != NULL ? K_STR : K_NULL, .s = s });
}

static void
boolean(struct writer *w, const char *g, const char *n, bool have, bool b)
{
	put(w, g, n, (struct value){ .kind = have ? K_BOOL : K_NULL, .b = b });
}

static void
visit_failure(struct writer *w, const struct run_record *rec)
{
	const struct step_failure *f = &rec->failure;
	bool have = rec->failed, node = have && f->node >= 0;
	char msg[600];

	if (have)
		step_failure_format(f, msg, sizeof msg);
	integer(w, "failure", "step", have, f->step);
	num(w, "failure", "t", have, f->t);
	integer(w, "failure", "node", node, f->node);
	integer(w, "failure", "i", node, f->i);
	integer(w, "failure", "j", node, f->j);
	str(w, "failure", "message", have ? msg : NULL);
}

static void
visit_network(struct writer *w, const struct run_record *rec)
{
	const struct cloth *cl = rec->cl;
	const struct material *m = &rec->sc->mat;

	str(w, "network", "shape", cloth_shape_name[cl->shape]);
	integer(w, "network", "nu", true, cl->nu);
	integer(w, "network", "nv", true, cl->nv);
	integer(w, "network", "nodes", true, cl->n);
	integer(w, "network", "springs", true, (long)cl->nsprings);
	integer(w, "network", "shear_corners", true, (long)cl->ncorners);
	integer(w, "network", "hinges", true, (long)cl->nhinges);
	integer(w, "network", "triangles", true, (long)cl->ntri);
	num(w, "bending", "warp", true, m->bending[0]);
	num(w, "bending", "weft", true, m->bending[1]);
	boolean(w, "bending", "warp_derived", true, m->bending_derived[0]);
	boolean(w, "bending", "weft_derived", true, m->bending_derived[1]);
}

static void
visit_integrator(struct writer *w, const struct run_record *rec)
{
	const struct stepper_report *r = &rec->r;
	enum integrator_kind k = rec->sc->integrator;
	bool implicit = k == INTEG_IMPLICIT_EULER;
	double wall = rec->wall;

	str(w, "integrator", "name", integrator_name(k));
	num(w, "integrator", "dt", true, r->dt_set);
	boolean(w, "integrator", "dt_auto", true, r->dt_auto);
	num(w, "integrator", "omega", true, r->omega);
	integer(w, "integrator", "steps", true, r->step);
	/* fast counts substeps, not force evaluations (its nfev stays 0) */
	integer(w, "integrator", "force_evaluations", !integrator_is_implicit(k), r->nfev);
	integer(w, "integrator", "rejected", k == INTEG_DOPRI5, r->rejected);
	integer(w, "integrator", "solves", implicit, r->solves);
	integer(w, "integrator", "cg_iterations", implicit, r->iters);
	integer(w, "integrator", "unconverged", implicit, r->unconverged);
	integer(w, "integrator", "substeps", k == INTEG_FAST, r->substeps);
	integer(w, "integrator", "windows", k == INTEG_FAST, r->windows);
	num(w, "time", "simulated", true, r->t);
	num(w, "time", "end", true, r->t_end);
	num(w, "time", "wall", true, wall);
	num(w, "time", "speed", true, wall > 0 ? r->t / wall : 0);
	num(w, "time", "steps_per_s", true, wall > 0 ? (double)r->step / wall : 0);
	num(w, "time", "stepping", true, r->step_wall);
	num(w, "time", "collisions", r->collisions, r->collide_wall);
	num(w, "time", "contacts", r->collisions && integrator_finds_contacts(k), r->contacts_wall);
}

static void
visit_energy(struct writer *w, const struct run_record *rec)
{
	const struct energy *e = &rec->e;

	num(w, "energy", "total", true, energy_total(e));
	num(w, "energy", "kinetic", true, e->kinetic);
	num(w, "energy", "gravity", true, e->gravity);
	num(w, "energy", "stretch", true, e->stretch);
	num(w, "energy", "shear", true, e->shear);
	num(w, "energy", "bend", true, e->bend);
	num(w, "energy", "load", true, e->load);
}

/* The collision stages and their counters, all of the table's. */
static void
visit_collisions(struct writer *w, const struct run_record *rec)
{
	const struct collision_opts *o = &rec->sc->col;
	const struct stepper_report *r = &rec->r;
	bool on = r->collisions;
	int k;

	boolean(w, "collisions", "enabled", true, on);
	str(w, "collisions", "broad", on ? broad_mode_name[o->broad] : NULL);
	str(w, "collisions", "narrow", on ? narrow_mode_name[o->narrow] : NULL);
	str(w, "collisions", "position", on ? position_policy_name[o->position] : NULL);
	boolean(w, "collisions", "self", on, o->self);
	num(w, "collisions", "cell", on, r->cell);
	for (k = 0; k < STAT_COUNT; k++)
		integer(w, "collisions", stat_field[k].name, on, on ? r->total->n[k] : 0);
	integer(w, "locks", "node_steps", on, r->locks->node_steps);
	integer(w, "locks", "most", on, r->locks->most);
	integer(w, "locks", "longest", on, r->locks->longest);
	num(w, "locks", "kinetic_most", on, r->locks->ke_most);
}

/* The spatial hash's means per fill, and its histogram over all fills. */
static void
visit_hash(struct writer *w, const struct run_record *rec)
{
	const struct stepper_report *r = &rec->r;
	bool on = r->collisions && r->uses_hash;
	const struct hash_stats *h = on ? &r->total->hash : NULL;
	long fills = on ? r->total->n[STAT_FILLS] : 0;
	double n = fills > 0 ? (double)fills : 1;
	char name[40];
	int k;

	num(w, "hash", "items", on, on ? (double)h->entries / n : 0);
	num(w, "hash", "cubes", on, on ? (double)h->cubes / n : 0);
	num(w, "hash", "shared", on, on ? (double)h->shared / n : 0);
	num(w, "hash", "load", on, on ? h->load / n : 0);
	num(w, "hash", "probe_mean", on, on ? h->probe_mean / n : 0);
	integer(w, "hash", "probe_max", on, on ? h->probe_max : 0);
	for (k = 0; k < HASH_HIST; k++) {
		snprintf(name, sizeof name, "cubes_with_%d%s", k + 1,
		    k + 1 == HASH_HIST ? "_or_more" : "");
		integer(w, "hash", name, on, on ? h->hist[k] : 0);
	}
}

static void
visit(struct writer *w, const struct run_record *rec)
{
	bool dc = rec->drape > 0;
	char hash[17];

	str(w, NULL, "drape_version", PACKAGE_VERSION);
	integer(w, NULL, "exit_status", true, rec->exit_status);
	str(w, NULL, "outcome", run_outcome_name[rec->outcome]);
	visit_failure(w, rec);
	str(w, "scene", "name", rec->sc->name);
	str(w, "scene", "path", rec->sc->path);
	put(w, "scene", "overrides", (struct value){ .kind = K_LIST, .list = rec->sets,
	    .n = rec->nsets });
	visit_network(w, rec);
	visit_integrator(w, rec);
	visit_energy(w, rec);
	visit_collisions(w, rec);
	visit_hash(w, rec);
	num(w, "cusick", "coefficient", dc, rec->dc);
	num(w, "cusick", "shadow_area", dc, rec->shadow);
	num(w, "cusick", "support_area", dc, rec->support);
	num(w, "cusick", "specimen_area", dc, rec->flat);
	num(w, "cusick", "raster", dc, rec->raster);
	integer(w, "cusick", "folds", dc && rec->folds >= 0, rec->folds);
	snprintf(hash, sizeof hash, "%016" PRIx64, rec->hash);
	str(w, NULL, "state_hash", hash);
}

/* The shortest of %.15g, %.16g and %.17g that reads back as x. */
static void
put_number(FILE *f, double x)
{
	char buf[40];
	int prec;

	for (prec = 15; prec < 17; prec++) {
		snprintf(buf, sizeof buf, "%.*g", prec, x);
		if (strtod(buf, NULL) == x)
			break;
	}
	if (prec == 17)
		snprintf(buf, sizeof buf, "%.17g", x);
	fputs(buf, f);
}

/* ---- JSON ---- */

/* The length of a well-formed UTF-8 sequence at s, or 0. */
static size_t
utf8_len(const unsigned char *s)
{
	size_t n, k;
	unsigned long c;

	if (s[0] < 0x80)
		return 1;
	if (s[0] >= 0xc2 && s[0] <= 0xdf)
		n = 2, c = s[0] & 0x1f;
	else if (s[0] >= 0xe0 && s[0] <= 0xef)
		n = 3, c = s[0] & 0x0f;
	else if (s[0] >= 0xf0 && s[0] <= 0xf4)
		n = 4, c = s[0] & 0x07;
	else
		return 0;
	for (k = 1; k < n; k++) {
		if ((s[k] & 0xc0) != 0x80)
			return 0;
		c = c << 6 | (s[k] & 0x3f);
	}
	if ((n == 3 && c < 0x800) || (n == 4 && (c < 0x10000 || c > 0x10ffff)) ||
	    (c >= 0xd800 && c <= 0xdfff))
		return 0;
	return n;
}

/* A JSON string; a byte that is not UTF-8 becomes U+FFFD. */
static void
json_string(FILE *f, const char *s)
{
	const unsigned char *p = (const unsigned char *)s;

	fputc('"', f);
	while (*p != '\0') {
		size_t n = utf8_len(p);

		if (n == 0) {
			fputs("\\ufffd", f);
			p++;
		} else if (*p == '"' || *p == '\\') {
			fprintf(f, "\\%c", *p++);
		} else if (*p == '\n') {
			fputs("\\n", f);
			p++;
		} else if (*p == '\t') {
			fputs("\\t", f);
			p++;
		} else if (*p < 0x20 || *p == 0x7f) {
			fprintf(f, "\\u%04x", *p++);
		} else {
			fwrite(p, 1, n, f);
			p += n;
		}
	}
	fputc('"', f);
}

static void
json_field(struct writer *w, const char *group, const char *name, const struct value *v)
{
	FILE *f = w->f;
	size_t k;

	if (w->group != NULL && (group == NULL || strcmp(group, w->group) != 0)) {
		fputc('}', f);
		w->group = NULL;
	}
	if (group != NULL && w->group == NULL) {
		fputs(w->top++ ? ", " : "", f);
		json_string(f, group);
		fputs(": {", f);
		w->group = group;
		w->fields = 0;
	}
	if (group != NULL)
		fputs(w->fields++ ? ", " : "", f);
	else
		fputs(w->top++ ? ", " : "", f);
	json_string(f, name);
	fputs(": ", f);
	switch (v->kind) {
	case K_NULL: fputs("null", f); break;
	case K_NUM: put_number(f, v->num); break;
	case K_INT: fprintf(f, "%ld", v->i); break;
	case K_STR: json_string(f, v->s); break;
	case K_BOOL: fputs(v->b ? "true" : "false", f); break;
	case K_LIST:
		fputc('[', f);
		for (k = 0; k < v->n; k++) {
			fputs(k ? ", " : "", f);
			json_string(f, v->list[k]);
		}
		fputc(']', f);
		break;
	}
}

int
run_record_json(FILE *f, const struct run_record *rec)
{
	struct writer w = { f, json_field, NULL, 0, 0, false };

	fputc('{', f);
	visit(&w, rec);
	if (w.group != NULL)
		fputc('}', f);
	fputs("}\n", f);
	return ferror(f) ? -1 : 0;
}

/* ---- CSV (RFC 4180) ---- */

/* s between quotes, its quotes doubled. */
static void
csv_quoted(FILE *f, const char *s)
{
	for (; *s != '\0'; s++) {
		if (*s == '"')
			fputc('"', f);
		fputc(*s, f);
	}
}

static void
csv_string(FILE *f, const char *s)
{
	if (strpbrk(s, ",\"\r\n") == NULL && s[0] != ' ' && (s[0] == '\0' ||
	    s[strlen(s) - 1] != ' ')) {
		fputs(s, f);
		return;
	}
	fputc('"', f);
	csv_quoted(f, s);
	fputc('"', f);
}

static void
csv_field(struct writer *w, const char *group, const char *name, const struct value *v)
{
	FILE *f = w->f;
	size_t k;

	fputs(w->top++ ? "," : "", f);
	if (w->header) {
		if (group != NULL)
			fprintf(f, "%s.", group);
		fputs(name, f);
		return;
	}
	switch (v->kind) {
	case K_NULL: break;
	case K_NUM: put_number(f, v->num); break;
	case K_INT: fprintf(f, "%ld", v->i); break;
	case K_STR: csv_string(f, v->s); break;
	case K_BOOL: fputs(v->b ? "true" : "false", f); break;
	case K_LIST:	/* one field, quoted, the items joined by ';' */
		if (v->n == 0)
			break;
		fputc('"', f);
		for (k = 0; k < v->n; k++) {
			fputs(k ? ";" : "", f);
			csv_quoted(f, v->list[k]);
		}
		fputc('"', f);
		break;
	}
}

int
run_record_csv(FILE *f, const struct run_record *rec, bool header)
{
	struct writer w = { f, csv_field, NULL, 0, 0, true };

	if (header) {
		visit(&w, rec);
		fputc('\n', f);
	}
	w.top = 0;
	w.header = false;
	visit(&w, rec);
	fputc('\n', f);
	return ferror(f) ? -1 : 0;
}
