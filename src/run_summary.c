/* run_summary.c: the summary of a headless run, as text. */
#include <inttypes.h>

#include "run_summary.h"
#include "stats.h"

static void
network_summary(FILE *f, const struct scene *sc, const struct cloth *cl)
{
	static const char *dir[2] = { "warp", "weft" };
	int d;

	fprintf(f, "scene        %s (%s)\n", sc->name, sc->path);
	if (cl->shape == SHAPE_SQUARE)
		fprintf(f, "network      %d x %d nodes", cl->nu, cl->nv);
	else
		fprintf(f, "network      %s of %d nodes in a %d x %d grid",
		    cloth_shape_name[cl->shape], cl->n, cl->nu, cl->nv);
	fprintf(f, ", %zu springs, %zu shear corners, %zu bending hinges, %zu triangles\n",
	    cl->nsprings, cl->ncorners, cl->nhinges, cl->ntri);
	for (d = 0; d < 2; d++)
		fprintf(f, "bending %s %.4g N*m (%s)\n", dir[d], sc->mat.bending[d],
		    sc->mat.bending_derived[d] ? "derived: modulus*thickness^3/12" : "given");
}

static void
integrator_summary(FILE *f, const struct scene *sc, const struct stepper_report *r, double wall)
{
	fprintf(f, "integrator   %s, dt %.4g s (%s; omega <= %.4g rad/s)\n",
	    integrator_name(sc->integrator), r->dt_set, r->dt_auto ? "auto" : "given", r->omega);
	if (sc->integrator == INTEG_FAST)
		fprintf(f, "steps        %ld (%ld substeps of %.3g s at most, %ld contact windows",
		    r->step, r->substeps, r->substeps > 0 ? r->t / (double)r->substeps : 0.0,
		    r->windows);
	else if (sc->integrator == INTEG_BDF2)
		fprintf(f, "steps        %ld (%.2f Newton iterations and %.1f CG iterations a step, "
		    "%ld unconverged", r->step, r->solves > 0 ? (double)r->newton / (double)r->solves : 0.0,
		    r->solves > 0 ? (double)r->iters / (double)r->solves : 0.0, r->unconverged);
	else if (sc->integrator == INTEG_IMPLICIT_EULER)
		fprintf(f, "steps        %ld (%ld solves, %.1f CG iterations each, %ld unconverged",
		    r->step, r->solves, r->solves > 0 ? (double)r->iters / (double)r->solves : 0.0,
		    r->unconverged);
	else
		fprintf(f, "steps        %ld (%ld force evaluations", r->step, r->nfev);
	if (sc->integrator == INTEG_DOPRI5)
		fprintf(f, ", %ld steps rejected", r->rejected);
	fprintf(f, ")\n");
	fprintf(f, "simulated    %.6g s\n", r->t);
	fprintf(f, "wall time    %.3f s", wall);
	if (r->collisions && r->step_wall > 0) {
		fprintf(f, " (collision stages %.3f s, %.1f %% of the steps' %.3f s",
		    r->collide_wall, 100 * r->collide_wall / r->step_wall, r->step_wall);
		if (integrator_finds_contacts(sc->integrator))
			fprintf(f, "; contacts found in the steps %.3f s, %.1f %%", r->contacts_wall,
			    100 * r->contacts_wall / r->step_wall);
		fprintf(f, ")");
	}
	fprintf(f, "\n");
	fprintf(f, "speed        %.4g x real time, %.0f steps/s\n", wall > 0 ? r->t / wall : 0,
	    wall > 0 ? (double)r->step / wall : 0);
}

/* The spatial hash's statistics, as means over its fills (seed fills it
 * every step; grid when its pairs no longer hold). */
static void
hash_summary(FILE *f, const struct collide_stats *c, long steps)
{
	const struct hash_stats *h = &c->hash;
	long fills = c->n[STAT_FILLS];
	double n = fills > 0 ? (double)fills : 1;
	int k;

	fprintf(f, "hash         per fill %.1f items, %.1f cubes (%.1f with >= 2), load %.3f, "
	    "probes mean %.3f max %d; %ld fills in %ld steps\n", (double)h->entries / n,
	    (double)h->cubes / n, (double)h->shared / n, h->load / n, h->probe_mean / n,
	    h->probe_max, fills, steps);
	fprintf(f, "hash histogram");
	for (k = 0; k < HASH_HIST; k++)
		fprintf(f, " %d%s:%ld", k + 1, k + 1 == HASH_HIST ? "+" : "", h->hist[k]);
	fprintf(f, " (cubes by items, all fills)\n");
}

static void
collision_summary(FILE *f, const struct scene *sc, const struct stepper_report *r)
{
	const long *n = r->total->n;
	double steps = r->step > 0 ? (double)r->step : 1;
	int k;

	fprintf(f, "collisions   broad %s, narrow %s, position %s, self %s, cell %.4g m\n",
	    broad_mode_name[sc->col.broad], narrow_mode_name[sc->col.narrow],
	    position_policy_name[sc->col.position], sc->col.self ? "on" : "off", r->cell);
	fprintf(f, "per step     %.1f node pairs, %.1f vertex-triangle and %.1f edge-edge "
	    "pairs, %.1f narrow tests\n", (double)n[STAT_NODE_PAIRS] / steps,
	    (double)n[STAT_VT_PAIRS] / steps, (double)n[STAT_EE_PAIRS] / steps,
	    (double)n[STAT_NARROW_TESTS] / steps);
	fprintf(f, "contacts     ");
	for (k = 0; k < CONTACT_NTYPES; k++)
		fprintf(f, "%s%s %ld", k ? ", " : "", contact_type_name[k], n[STAT_CONTACTS + k]);
	fprintf(f, "\n");
	fprintf(f, "corrections  %ld (%ld put back to step k; at most %ld passes in a step; "
	    "%ld steps unresolved)\n", n[STAT_CORRECTIONS], n[STAT_FROZEN], n[STAT_PASSES],
	    n[STAT_UNRESOLVED]);
	if (r->locks->node_steps > 0)
		fprintf(f, "locked       %ld node-steps, at most %d nodes in a step, longest %ld "
		    "steps in a row (%.4g s), kinetic energy of locked nodes at most %.4e J\n",
		    r->locks->node_steps, r->locks->most, r->locks->longest,
		    (double)r->locks->longest * r->dt_set, r->locks->ke_most);
	if (r->uses_hash)
		hash_summary(f, r->total, r->step);
}

/* The Cusick drape test's coefficient, for a disc-shaped specimen on the
 * scene's first [disc]. */
static void
drape_summary(FILE *f, const struct run_record *rec)
{
	if (rec->drape == 0)
		return;
	if (rec->drape < 0) {
		fprintf(f, "drape coefficient: not computed (out of memory for its shadow)\n");
		return;
	}
	fprintf(f, "drape coefficient %.4f (shadow %.6f m2, support disc %.6f m2, flat specimen "
	    "%.6f m2; %.2g mm raster)\n", rec->dc, rec->shadow, rec->support, rec->flat,
	    rec->raster * 1e3);
	if (rec->folds >= 0)
		fprintf(f, "drape folds  %d\n", rec->folds);
	else
		fprintf(f, "drape folds  not counted (the outline does not go round the disc)\n");
}

void
run_summary(FILE *f, const struct run_record *rec)
{
	const struct energy *e = &rec->e;

	network_summary(f, rec->sc, rec->cl);
	integrator_summary(f, rec->sc, &rec->r, rec->wall);
	fprintf(f, "energy       %.6e J (kinetic %.4e, gravity %.4e, stretch %.4e, shear %.4e, "
	    "bend %.4e, load %.4e)\n", energy_total(e), e->kinetic, e->gravity, e->stretch,
	    e->shear, e->bend, e->load);
	if (rec->r.collisions)
		collision_summary(f, rec->sc, &rec->r);
	drape_summary(f, rec);
	fprintf(f, "state hash   %016" PRIx64 "\n", rec->hash);
}
