/* stepper.c: the order of one step, and the state it advances. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bdf2.h"
#include "clock.h"
#include "collide.h"
#include "contacts.h"
#include "implicit.h"
#include "network.h"
#include "pbd.h"
#include "stepper.h"
#include "stop.h"
#include "vec3.h"

struct stepper {
	const struct scene *sc;
	struct network net;
	struct integrator in;	/* the explicit methods */
	struct implicit im;	/* implicit Euler */
	struct pbd pb;		/* the fast path */
	struct bdf2 bd;		/* BDF2 */
	struct contacts ct;	/* their contacts inside a step */
	struct collide col;
	double *y, *y_next;	/* positions (3n) then velocities (3n) */
	double *y_window;	/* fast: a window's start state (fast_step swaps it with y_next) */
	long windows;		/* fast: the windows its steps took */
	double t, t_end;
	double dt;		/* the step to try next */
	double dt_set;		/* the scene's (or auto) step: DOPRI5's largest */
	bool dt_auto;
	double omega;		/* bound on the highest angular frequency */
	double v_limit;		/* a node faster than this has blown up */
	long step;
	/* locked nodes (struct lock_stats): per node, the steps in a row it
	 * has been put back at step k; and which nodes the step corrected */
	long *lock_run;
	unsigned char *corrected;
	struct lock_stats locks;
	double step_wall, collide_wall;	/* s, over the committed steps */
	double contacts_wall, contacts_now;	/* fast_contacts: the same, and this step's */
	const volatile sig_atomic_t *stop;	/* stepper_set_stop's flag, or NULL */
};

/* dy/dt = (v, a); held nodes follow their prescribed velocity, unforced. */
static void
rhs(void *ctx, double t, const double *y, double *dy)
{
	struct stepper *st = ctx;
	const struct prescribed *pr = &st->net.pr;
	size_t n3 = 3 * (size_t)st->net.cl.n;
	int k;

	memcpy(dy, y + n3, n3 * sizeof *dy);
	forces_accel(&st->net.fo, t, y, y + n3, dy + n3);
	if (pr->nnodes == 0)
		return;
	prescribed_apply(pr, &st->net.cl, t, NULL, dy);
	for (k = 0; k < pr->nnodes; k++)
		v3_store(dy + n3 + 3 * pr->node[k], v3(0, 0, 0));
}

double
stepper_auto_dt(enum integrator_kind kind, double omega, double damping, double spring_damping,
    double crossing)
{
	/* The fastest mode's eigenvalue is at most omega in the imaginary
	 * direction plus the damping rates on the real axis. Take half the
	 * method's stability interval: sqrt 8 for RK4, 2 for the others
	 * (their real-axis limit; explicit Euler and RK2 have none on the
	 * imaginary axis, so undamped they grow slowly at any step). */
	double lam = omega + damping + spring_damping * omega * omega;
	double limit = kind == INTEG_RK4 ? integrator_imag_limit(kind) : 2;

	/* Implicit Euler is stable at any step: what bounds it is that a
	 * node should move no more than half a spacing in one, so that the
	 * contacts of a step stay few and local. */
	if (kind == INTEG_IMPLICIT_EULER)
		return 0.5 * crossing;
	/* The fast path: a step of the order of a frame, whatever the
	 * stiffness (its solve is preconditioned along the yarns) */
	if (kind == INTEG_FAST)
		return STEPPER_FAST_DT;
	if (kind == INTEG_BDF2)
		return STEPPER_BDF2_DT;
	return 0.5 * limit / lam;
}

static void
stage(const struct stepper_progress *pg, const char *what)
{
	if (pg != NULL && pg->stage != NULL)
		pg->stage(pg->ctx, what);
}

struct stepper *
stepper_new(const struct scene *sc, struct drape_err *err)
{
	return stepper_new_progress(sc, NULL, err);
}

/* The integrator stage: the method's workspace and the initial state (the
 * cloth at rest where the scene puts it, at its initial velocity, held
 * nodes on their prescribed motion). */
static int
init_state(struct stepper *st, struct drape_err *err)
{
	const struct scene *sc = st->sc;
	const struct cloth *cl = &st->net.cl;
	size_t n3 = 3 * (size_t)cl->n;
	double tol = sc->tolerance > 0 ? sc->tolerance : integrator_default_tolerance(sc->integrator);
	int p;

	if (integrator_init(&st->in, sc->integrator, 2 * n3, tol) != 0 ||
	    (sc->integrator == INTEG_IMPLICIT_EULER &&
	    implicit_init(&st->im, &st->net.fo, st->net.pr.held, tol) != 0) ||
	    (st->y = malloc(2 * n3 * sizeof *st->y)) == NULL ||
	    (st->y_next = malloc(2 * n3 * sizeof *st->y_next)) == NULL ||
	    (sc->integrator == INTEG_FAST &&
	    (st->y_window = malloc(2 * n3 * sizeof *st->y_window)) == NULL)) {
		err_set(err, "%s: out of memory", sc->path);
		return -1;
	}
	memcpy(st->y, cl->x0, n3 * sizeof *st->y);
	for (p = 0; p < cl->n; p++)
		v3_store(st->y + n3 + 3 * p, v3_load(sc->velocity));
	prescribed_apply(&st->net.pr, cl, 0, st->y, st->y + n3);
	return 0;
}

/* Speeds a run can reach without blowing up: falling over the cloth's
 * size, prescribed motion, loads while they act; 1000 times that is a
 * runaway. */
static double
speed_scale(const struct stepper *st)
{
	const struct scene *sc = st->sc;
	const struct cloth *cl = &st->net.cl;
	double extent = cl->h * hypot(cl->nu - 1, cl->nv - 1);

	return 1 + sqrt(2 * v3_len(v3_load(sc->gravity)) * extent) +
	    v3_len(v3_load(sc->velocity)) + prescribed_max_speed(&st->net.pr) +
	    forces_load_speed(&st->net.fo, sc->duration);
}

/* The fast path's step is cut into substeps of bending's and damping's
 * (pbd_substep): at most PBD_MAX_SUBSTEPS of them, so that one step's work
 * is bounded as the other methods' is (damping = 1e9/s asked 1e7 a step,
 * 1e12/s overflowed an int). Refused at dt's line, with the step that
 * would do. */
static int
fast_substeps_bounded(const struct stepper *st, struct drape_err *err)
{
	const struct scene *sc = st->sc;
	const struct forces *fo = &st->net.fo;
	double sub = pbd_substep(fo, st->dt_set), n = ceil(st->dt_set / sub * (1 - 1e-12));
	double omega = cloth_omega_bound_bend(fo->cl);
	char why[120];

	if (n <= PBD_MAX_SUBSTEPS)
		return 0;
	if (fo->damping > 0 && !(1 / fo->damping > sub))
		snprintf(why, sizeof why, "the damping rate, %g /s", fo->damping);
	else
		snprintf(why, sizeof why, "bending's highest frequency, %.3g rad/s", omega);
	err_set(err, "%s:%d: dt%s: the fast path's substeps here are %.3g s long at most (%s), so "
	    "a step of %g s takes %.3g of them; expected at most %d a step: a dt of at most %.3g s",
	    sc->path, sc->dt_line, st->dt_auto ? " = auto" : "", sub, why, st->dt_set, n,
	    PBD_MAX_SUBSTEPS, sub * PBD_MAX_SUBSTEPS);
	return -1;
}

/* The integrator stage's step: the scene's dt, or dt = auto's for the
 * method, the stiffness bound and the speed scale; refused when it is not
 * a step, takes more than SCENE_MAX_STEPS steps or, on the fast path,
 * more than PBD_MAX_SUBSTEPS substeps a step. */
static int
choose_dt(struct stepper *st, double vscale, struct drape_err *err)
{
	const struct scene *sc = st->sc;

	st->dt_auto = sc->dt == 0;
	st->dt_set = st->dt_auto ? stepper_auto_dt(sc->integrator, st->omega, sc->mat.damping,
	    sc->mat.spring_damping, st->net.cl.h / vscale) : sc->dt;
	st->dt = st->dt_set;
	if (!(st->dt > 0) || !isfinite(st->dt)) {
		err_set(err, "%s:%d: dt%s: cannot choose a time step (the stiffness bound is %g "
		    "rad/s); expected a dt in [simulation]", sc->path, sc->dt_line,
		    st->dt_auto ? " = auto" : "", st->omega);
		return -1;
	}
	if (scene_steps(sc->duration, st->dt_set) > SCENE_MAX_STEPS) {
		err_set(err, "%s:%d: dt%s: a step of %.3g s takes %.3g steps to cover the duration "
		    "(%g s); expected at most %.0e", sc->path, sc->dt_line,
		    st->dt_auto ? " = auto" : "", st->dt_set,
		    scene_steps(sc->duration, st->dt_set), sc->duration, SCENE_MAX_STEPS);
		return -1;
	}
	return sc->integrator == INTEG_FAST ? fast_substeps_bounded(st, err) : 0;
}

/* The collision geometry stage: the collision stages, and the fast path's
 * contacts and solver. */
static int
init_collisions(struct stepper *st, double vscale, struct drape_err *err)
{
	const struct scene *sc = st->sc;

	if (collide_init(&st->col, sc, &st->net.cl, st->net.pr.held, st->dt_set, vscale,
	    err) != 0)
		return -1;
	if ((st->lock_run = calloc((size_t)st->net.cl.n, sizeof *st->lock_run)) == NULL ||
	    (st->corrected = calloc((size_t)st->net.cl.n, 1)) == NULL) {
		err_set(err, "%s: out of memory", sc->path);
		return -1;
	}
	/* the fast path's long steps: a vertex's box is its own motion's.
	 * Its substeps have held its contacts a thickness apart, so the
	 * check's corrections are few and small, and a clamped one is taken
	 * up by the next pass; a pad of the step's largest motion, which at
	 * 10 ms is a spacing, gave every resting node in a pile the boxes of
	 * the falling ones: 4.7 times the narrow tests, 1.6 times the time,
	 * the same corrections and no fewer passes (the tablecloth's first
	 * second, 0.25 against 0) */
	if (sc->integrator == INTEG_FAST || sc->integrator == INTEG_BDF2)
		collide_set_pad(&st->col, 0);
	if (sc->integrator == INTEG_BDF2)
		collide_set_slide_gap(&st->col, sc->mat.thickness);
	contacts_init(&st->ct, sc->mat.thickness);
	if ((sc->integrator == INTEG_FAST && pbd_init(&st->pb, sc, &st->net.fo, &st->net.pr,
	    st->dt_set) != 0) ||
	    (sc->integrator == INTEG_BDF2 && bdf2_init(&st->bd, sc, &st->net.fo, &st->net.pr,
	    sc->tolerance) != 0)) {
		err_set(err, "%s: out of memory", sc->path);
		return -1;
	}
	return 0;
}

struct stepper *
stepper_new_progress(const struct scene *sc, const struct stepper_progress *pg,
    struct drape_err *err)
{
	struct stepper *st = calloc(1, sizeof *st);
	double vscale;

	if (st == NULL) {
		err_set(err, "%s: out of memory", sc->path);
		return NULL;
	}
	st->sc = sc;
	stage(pg, "the network");
	if (network_build(&st->net, sc, err) != 0) {
		free(st);
		return NULL;
	}
	stage(pg, "the integrator");
	if (init_state(st, err) != 0)
		goto fail;
	st->t_end = sc->duration;
	st->omega = cloth_omega_bound(&st->net.cl);
	vscale = speed_scale(st);
	st->v_limit = 1000 * vscale;
	if (choose_dt(st, vscale, err) != 0)
		goto fail;
	stage(pg, "the collision geometry");
	if (init_collisions(st, vscale, err) != 0)
		goto fail;
	return st;
fail:
	stepper_free(st);
	return NULL;
}

void
stepper_free(struct stepper *st)
{
	if (st == NULL)
		return;
	collide_free(&st->col);
	integrator_free(&st->in);
	implicit_free(&st->im);
	pbd_free(&st->pb);
	bdf2_free(&st->bd);
	contacts_free(&st->ct);
	network_free(&st->net);
	free(st->lock_run);
	free(st->corrected);
	free(st->y);
	free(st->y_next);
	free(st->y_window);
	free(st);
}

bool
stepper_done(const struct stepper *st)
{
	return st->t >= st->t_end;
}

#define TORN 10	/* a spring this many times its rest length has torn */

/* The first node (lowest number) that is not finite or too fast. */
static int
find_blowup(const struct stepper *st, const double *y, char *why, size_t len)
{
	size_t n3 = 3 * (size_t)st->net.cl.n;
	double lim2 = st->v_limit * st->v_limit;
	int p;

	for (p = 0; p < st->net.cl.n; p++) {
		vec3 x = v3_load(y + 3 * p), v = v3_load(y + n3 + 3 * p);
		double v2 = v3_dot(v, v);

		if (!isfinite(v3_dot(x, x)) || !isfinite(v2)) {
			snprintf(why, len, "its position or velocity is not finite");
			return p;
		}
		if (v2 > lim2) {
			snprintf(why, len, "runaway energy: it moves at %.3g m/s, over the %.3g m/s "
			    "this scene can reach", sqrt(v2), st->v_limit);
			return p;
		}
	}
	return -1;
}

/* A step too long for its method can also end slow but torn apart
 * (implicit Euler's one linear solve at a step of seconds): no cloth
 * stretches a yarn segment to ten times its length. Returns the first end
 * of the first torn spring, or -1. */
static int
find_torn(const struct stepper *st, const double *y, char *why, size_t len)
{
	size_t s;

	for (s = 0; s < st->net.cl.nsprings; s++) {
		const struct spring *sp = &st->net.cl.springs[s];
		vec3 d = v3_sub(v3_load(y + 3 * sp->b), v3_load(y + 3 * sp->a));

		if (v3_dot(d, d) > TORN * TORN * sp->rest * sp->rest) {
			snprintf(why, len, "the network tore: its spring to node %d is %.3g times its "
			    "rest length", sp->b, v3_len(d) / sp->rest);
			return sp->a;
		}
	}
	return -1;
}

/* Fills f for a failure of the current step at node (or -1); f->why is
 * set. Returns the status. */
static enum step_status
failed(const struct stepper *st, struct step_failure *f, enum step_status status, int node)
{
	f->status = status;
	f->step = st->step;
	f->t = st->t;
	f->node = node;
	f->i = f->j = -1;
	if (node >= 0)
		cloth_grid_ij(&st->net.cl, node, &f->i, &f->j);
	return status;
}

/* A failure of the collision stages (the broad phase, the narrow phase, the
 * fast path's contacts): given up for the stop flag, or an error whose why
 * is cerr's message, or out of memory when cerr is NULL. The one place
 * that words them for fast_contacts and stepper_step alike. */
static enum step_status
collisions_failed(const struct stepper *st, struct step_failure *f, const struct drape_err *cerr)
{
	snprintf(f->why, sizeof f->why, "%.*s", (int)sizeof f->why - 1,
	    cerr != NULL ? cerr->msg : "collisions: out of memory");
	return failed(st, f, cerr != NULL && st->col.stopped ? STEP_STOPPED : STEP_ERROR, -1);
}

void
step_failure_format(const struct step_failure *f, char *buf, size_t len)
{
	if (f->status == STEP_BLOWUP && f->node >= 0)
		snprintf(buf, len, "blow-up at step %ld (t = %.6g s): node %d (i %d, j %d): %s",
		    f->step, f->t, f->node, f->i, f->j, f->why);
	else if (f->status == STEP_BLOWUP)
		snprintf(buf, len, "blow-up at step %ld (t = %.6g s): %s", f->step, f->t, f->why);
	else
		snprintf(buf, len, "step %ld (t = %.6g s): %s", f->step, f->t, f->why);
}

/* Implicit Euler: the nodes within rest distance of an analytic obstacle
 * are constrained along its normal (implicit.h says why). The distance is
 * the cloth's thickness, or the fall of two steps under gravity if that is
 * more: a node put back at step k's clearance rests about that high. It
 * comes from the state alone, so that a resumed run steps the same. */
static void
constrain_resting(struct stepper *st, double h)
{
	const struct scene *sc = st->sc;
	double rest = fmax(sc->mat.thickness, 2 * v3_len(v3_load(sc->gravity)) * h * h);
	size_t o;
	int p;

	for (o = 0; o < sc->nobstacles; o++) {
		const struct obstacle *ob = &sc->obstacles[o];

		if (ob->kind == OBSTACLE_MESH)
			continue;
		for (p = 0; p < st->net.cl.n; p++) {
			vec3 n;
			double nn[3];

			if (st->net.pr.held[p] ||
			    obstacle_distance(ob, v3_load(st->y + 3 * p), NULL, &n) >= rest)
				continue;
			v3_store(nn, n);
			implicit_constrain(&st->im, p, nn, ob->friction);
		}
	}
}

/* The fast path's and bdf2's contacts from state y over the next h: the
 * broad phase's pairs for the predicted motion, each node's box widened
 * by one and a half thicknesses and half its own motion (an allowance for
 * the step's accelerations), and of those the ones within reach (for
 * bdf2, which holds a pair only along its normal, those that close along
 * it: contacts.h). */
static enum step_status
find_contacts(struct stepper *st, const double *y, double h, struct step_failure *f)
{
	bool closing = st->in.kind == INTEG_BDF2;
	struct drape_err cerr;

	contacts_clear(&st->ct);
	if (!st->col.active || !st->col.pairs)
		return STEP_OK;
	if (collide_candidates(&st->col, y, h, 1.5 * st->sc->mat.thickness, 0.5,
	    CONTACTS_REACH * st->sc->mat.thickness, CONTACTS_REACH_MOTION, &cerr) != 0)
		return collisions_failed(st, f, &cerr);
	switch (contacts_find(&st->ct, &st->col, y, h, closing)) {
	case 0:
		return STEP_OK;
	case 1:
		snprintf(f->why, sizeof f->why, "stopped by a signal");
		return failed(st, f, STEP_STOPPED, -1);
	default:
		return collisions_failed(st, f, NULL);
	}
}

/* find_contacts, its time counted: the search is inside the integration,
 * where the collision stages' time (stepper_report) does not see it, and
 * on a fine cloth landing it is most of a step's (bench-history.md,
 * fast.sh). */
static enum step_status
fast_contacts(struct stepper *st, const double *y, double h, struct step_failure *f)
{
	double t0 = clock_seconds();
	enum step_status s = find_contacts(st, y, h, f);

	st->contacts_now += clock_seconds() - t0;
	return s;
}

/*
 * How many windows the fast path cuts a step of h into, each its own step
 * for the collisions: contacts found from its start (fast_contacts), the
 * check over its motion (collide_check), the fail-safe's put-back to its
 * start. A step's contacts are the pairs that its predicted motion may
 * bring within reach: a node moving s spacings in it meets some s^2 of
 * the cloth's triangles around its path, and a pair of nodes whose
 * predictions part (one side stopped by the box, the other still
 * falling) is held all the step. So the pairs, and the broad phase's
 * candidates, grow as the square of the motion over the spacing: the
 * peers' table at 50^2 nodes (4.9 mm squares, 2 m/s as it lands) held
 * 200,000 to 300,000 pairs a 10 ms step at 2,500 nodes, two thirds of the
 * run's time in finding and holding them. And the check's straight path
 * over a whole step is not the path the substeps took: at 100^2 (2.4 mm
 * squares, 8 of them a step) it saw crossings on it that the cloth never
 * made, put nodes back a whole step's fall, and the cloth tore. A window
 * moves no node more than FAST_WINDOW_SPACINGS spacings at its start's
 * speeds, the rule of implicit Euler's step (stepper_auto_dt), so a
 * node's contacts stay bounded however fine the cloth, and the substeps
 * are as many as before. Only where the cloth has pairs to find
 * (self-contact, meshes), and at most FAST_WINDOWS_MOST, a bound on a
 * step's work as PBD_MAX_SUBSTEPS is. Frames, events and the step's
 * number stay the scene's: the windows are inside a step.
 */
#define FAST_WINDOW_SPACINGS 2.0
#define FAST_WINDOWS_MOST 64

/* The fastest node's speed in state y (0 for NaN: find_blowup's). */
static double
fastest_speed(const struct cloth *cl, const double *y)
{
	size_t n3 = 3 * (size_t)cl->n;
	double most = 0;
	int p;

	for (p = 0; p < cl->n; p++) {
		vec3 v = v3_load(y + n3 + 3 * p);
		double s2 = v3_dot(v, v);

		most = s2 > most ? s2 : most;
	}
	return sqrt(most);
}

static int
fast_windows(const struct stepper *st, double h)
{
	const struct cloth *cl = &st->net.cl;
	double want;

	if (!st->col.active || !st->col.pairs)
		return 1;
	want = ceil(fastest_speed(cl, st->y) * h / (FAST_WINDOW_SPACINGS * cl->h) * (1 - 1e-12));
	return want >= FAST_WINDOWS_MOST ? FAST_WINDOWS_MOST : want >= 1 ? (int)want : 1;
}

/* The fast path's step of h from st->y into st->y_next, window by window
 * (fast_windows), each window's contacts and obstacle contacts recorded as
 * events of the step and every window but the last checked here; the last
 * window's start and length into *from and *h_last, for the step's own
 * check (stepper_step). */
static enum step_status
fast_step(struct stepper *st, double h, const double **from, double *h_last,
    struct step_failure *f)
{
	int nwin = fast_windows(st, h), w, bad;
	double hw = h / nwin;
	struct drape_err cerr;

	st->windows += nwin;
	collide_begin(&st->col);
	*from = st->y;
	*h_last = h - (nwin - 1) * hw;
	for (w = 0; w < nwin; w++) {
		/* the window's start: the step's, or the last window's end */
		const double *y0 = st->y;
		double hs = w + 1 == nwin ? *h_last : hw;
		enum step_status s;

		if (w > 0) {	/* the last window's end becomes this one's start */
			double *swap = st->y_window;

			st->y_window = st->y_next;
			st->y_next = swap;
			y0 = *from = st->y_window;
		}
		if ((s = fast_contacts(st, y0, hs, f)) != STEP_OK)
			return s;
		pbd_step(&st->pb, st->t + w * hw, hs, y0, st->y_next, &st->ct);
		if (forces_stopped(&st->net.fo))
			return STEP_OK;	/* stepper_step gives the step up */
		if (pbd_events(&st->pb, &st->col, st->step, y0, st->y_next) != 0 ||
		    contacts_events(&st->ct, &st->col, st->step, st->y_next) != 0)
			return collisions_failed(st, f, NULL);
		if (w + 1 == nwin)
			break;
		if ((bad = find_blowup(st, st->y_next, f->why, sizeof f->why)) >= 0)
			return failed(st, f, STEP_BLOWUP, bad);
		if (collide_check(&st->col, st->step, hs, y0, st->y_next, &cerr) != 0)
			return collisions_failed(st, f, &cerr);
	}
	return STEP_OK;
}

/* The step's locked nodes into l (the run's figures carried over from
 * st->locks): a free node the collision stages corrected (events from
 * `first` on) and left exactly where it was at step k. Exact equality is
 * what keep does (it copies step k's position); a node the integrator
 * moved by any amount is not locked. */
static void
count_locks(struct stepper *st, size_t first, struct lock_stats *l)
{
	const struct cloth *cl = &st->net.cl;
	size_t n3 = 3 * (size_t)cl->n, e;
	int p;

	*l = st->locks;
	l->now = 0;
	l->ke_now = 0;
	l->run_now = 0;
	memset(st->corrected, 0, (size_t)cl->n);
	for (e = first; e < st->col.nev; e++)
		if (st->col.ev[e].node >= 0 && st->col.ev[e].node < cl->n)
			st->corrected[st->col.ev[e].node] = 1;
	for (p = 0; p < cl->n; p++) {
		const double *a = st->y + 3 * p, *b = st->y_next + 3 * p;
		vec3 v = v3_load(st->y_next + n3 + 3 * p);

		if (st->net.pr.held[p] || !st->corrected[p] || a[0] != b[0] || a[1] != b[1] ||
		    a[2] != b[2]) {
			st->lock_run[p] = 0;
			continue;
		}
		st->lock_run[p]++;
		l->now++;
		l->ke_now += 0.5 * cl->mass[p] * v3_dot(v, v);
		l->run_now = st->lock_run[p] > l->run_now ? st->lock_run[p] : l->run_now;
	}
	l->node_steps += l->now;
	l->most = l->now > l->most ? l->now : l->most;
	l->longest = l->run_now > l->longest ? l->run_now : l->longest;
	l->ke_most = fmax(l->ke_most, l->ke_now);
}

/*
 * bdf2's next step at dt = auto, from the state y at t: STEPPER_BDF2_DT
 * (a tick) while the cloth moves, BDF2_TICKS_MOST ticks while its fastest
 * node would move at most BDF2_GROW_MOTION spacings in them at its
 * present speed. A cloth at rest costs a Newton iteration a step whatever
 * the step, one that lands or crumples 6 to 10 (bdf2.c NEWTON_VSTOP), so
 * the long step is taken where it is cheap: over twelve drops of the
 * peers' 25^2 table (2 s) the stepping's median 4.14 -> 3.33 s, every
 * cloth ending where it did (its gravity energy within 1.1 %; the landing
 * keeps one tick). The motion's bound is implicit Euler's rule, which
 * keeps a step's contacts few and local (stepper_auto_dt). A step ends on
 * every frame it reaches, none inside it, so that a frame is the state of
 * its time; ticks keep t a product, as a fixed step's. bdf2 takes its
 * history anew for the step's length (bdf2.c respace_history).
 */
#define BDF2_TICKS_MOST 2
#define BDF2_GROW_MOTION 0.25

static double
bdf2_next_dt(const struct stepper *st, double t, const double *y)
{
	const struct cloth *cl = &st->net.cl;
	double most, frame = 1 / st->sc->output_rate, left;
	int k = BDF2_TICKS_MOST;

	if (!st->dt_auto)
		return st->dt_set;
	most = fastest_speed(cl, y);
	while (k > 1 && !(most * k * st->dt_set <= BDF2_GROW_MOTION * cl->h))
		k--;
	/* the ticks to the next frame */
	left = ((floor(t / frame + 1e-6 * st->dt_set / frame) + 1) * frame - t) / st->dt_set;
	while (k > 1 && k > left + 1e-6)
		k--;
	return k * st->dt_set;
}

enum step_status
stepper_step(struct stepper *st, struct step_failure *f)
{
	size_t n3 = 3 * (size_t)st->net.cl.n;
	double h = st->dt, h_next, remaining = st->t_end - st->t, t_new;
	int last = 0, bad;
	double *swap, t0 = clock_seconds(), c0;
	struct drape_err cerr;
	struct lock_stats locks;
	size_t own = 0;		/* the events before the check's: the method's own */
	const double *from = NULL;	/* fast: its last window's start, and length */
	double h_from = 0;

	st->contacts_now = 0;
	if (h >= remaining * (1 - 1e-12)) {	/* land on the end exactly */
		h = remaining;
		last = 1;
	}
	/* 1. integrate: consistent state k -> predicted state k+1 */
	if (st->in.kind == INTEG_FAST) {
		enum step_status s = fast_step(st, h, &from, &h_from, f);

		if (s != STEP_OK)
			return s;
		h_next = h;
	} else if (st->in.kind == INTEG_BDF2) {
		enum step_status s;

		collide_begin(&st->col);
		if ((s = fast_contacts(st, st->y, h, f)) != STEP_OK)
			return s;
		bdf2_step(&st->bd, st->t, h, st->y, st->y_next, &st->ct);
		h_next = h;
		if (st->bd.stopped) {
			snprintf(f->why, sizeof f->why, "stopped by a signal");
			return failed(st, f, STEP_STOPPED, -1);
		}
	} else if (st->in.kind == INTEG_IMPLICIT_EULER) {
		constrain_resting(st, h);
		implicit_step(&st->im, st->t, h, st->y, st->y_next);
		h_next = h;
		if (st->im.stopped) {
			snprintf(f->why, sizeof f->why, "stopped by a signal");
			return failed(st, f, STEP_STOPPED, -1);
		}
	} else if (integrator_step(&st->in, rhs, st, st->t, st->y, st->y_next, &h, &h_next) != 0 &&
	    !forces_stopped(&st->net.fo)) {
		snprintf(f->why, sizeof f->why, "the adaptive step fell below %g s", h);
		return failed(st, f, STEP_BLOWUP, -1);
	}
	/* the force loops give up on a signal (forces_set_stop), leaving the
	 * prediction unfinished (and an adaptive step's error estimate): the
	 * step is dropped */
	if (forces_stopped(&st->net.fo)) {
		snprintf(f->why, sizeof f->why, "stopped by a signal");
		return failed(st, f, STEP_STOPPED, -1);
	}
	/* A fixed step's time is a product, not a sum of rounded steps, so
	 * that t stays as exact as the positions it goes with. */
	if (last && h == remaining)
		t_new = st->t_end;
	else if (st->in.kind == INTEG_BDF2)
		t_new = (double)(llround(st->t / st->dt_set) + llround(h / st->dt_set)) * st->dt_set;
	else if (st->in.kind != INTEG_DOPRI5)
		t_new = (double)(st->step + 1) * st->dt_set;
	else
		t_new = st->t + h;
	/* 2. specified displacements */
	prescribed_apply(&st->net.pr, &st->net.cl, t_new, st->y_next, st->y_next + n3);
	/* 3. collisions: self-contact, obstacles; not on a state that has
	 * already blown up, whose extent no broad phase could cut into cubes */
	if ((bad = find_blowup(st, st->y_next, f->why, sizeof f->why)) >= 0)
		return failed(st, f, STEP_BLOWUP, bad);
	if (st->in.kind == INTEG_FAST) {
		own = st->col.nev;	/* recorded window by window (fast_step) */
	} else if (st->in.kind == INTEG_BDF2) {
		if (bdf2_events(&st->bd, &st->col, st->step, st->y_next) != 0 ||
		    contacts_events(&st->ct, &st->col, st->step, st->y_next) != 0)
			return collisions_failed(st, f, NULL);
		own = st->col.nev;
	} else {
		collide_begin(&st->col);
	}
	c0 = clock_seconds();
	if (collide_check(&st->col, st->step, from != NULL ? h_from : h,
	    from != NULL ? from : st->y, st->y_next, &cerr) != 0)
		return collisions_failed(st, f, &cerr);
	collide_end(&st->col);
	if (st->in.kind == INTEG_BDF2)
		bdf2_correct_energy(&st->bd, st->y_next);
	c0 = clock_seconds() - c0;
	/* 4. blow-up check before anything is committed */
	if ((bad = find_blowup(st, st->y_next, f->why, sizeof f->why)) >= 0 ||
	    (bad = find_torn(st, st->y_next, f->why, sizeof f->why)) >= 0)
		return failed(st, f, STEP_BLOWUP, bad);
	/* a signal since the long loops last looked (the checks above take a
	 * third of a second on 590,000 nodes under the sanitizers): the step
	 * is still under way, so it is given up as theirs would be */
	if (stop_set(st->stop)) {
		snprintf(f->why, sizeof f->why, "stopped by a signal");
		return failed(st, f, STEP_STOPPED, -1);
	}
	/* 5. commit; BDF2's history is the state the step began from */
	count_locks(st, own, &locks);
	st->locks = locks;
	if (st->in.kind == INTEG_BDF2) {
		h_next = bdf2_next_dt(st, t_new, st->y_next);
		bdf2_commit(&st->bd, h, st->y, st->y_next, st->corrected, h_next);
	}
	swap = st->y;
	st->y = st->y_next;
	st->y_next = swap;
	st->t = t_new;
	st->step++;
	st->dt = st->in.kind == INTEG_DOPRI5 ? fmin(h_next, st->dt_set) :
	    st->in.kind == INTEG_BDF2 ? h_next : st->dt_set;
	st->collide_wall += c0;
	st->contacts_wall += st->contacts_now;
	st->step_wall += clock_seconds() - t0;
	return STEP_OK;
}

void
stepper_set_stop(struct stepper *st, const volatile sig_atomic_t *flag)
{
	st->stop = flag;
	collide_set_stop(&st->col, flag);
	implicit_set_stop(&st->im, flag);
	bdf2_set_stop(&st->bd, flag);
	forces_set_stop(&st->net.fo, flag);
}

const struct scene *stepper_scene(const struct stepper *st) { return st->sc; }
const struct network *stepper_network(const struct stepper *st) { return &st->net; }
const double *stepper_x(const struct stepper *st) { return st->y; }
const double *stepper_v(const struct stepper *st) { return st->y + 3 * st->net.cl.n; }
const struct geom *stepper_geom(const struct stepper *st) { return collide_geom(&st->col); }

void
stepper_energy(const struct stepper *st, struct energy *e)
{
	forces_energy(&st->net.fo, st->t, stepper_x(st), stepper_v(st), e);
}

void
stepper_report(const struct stepper *st, struct stepper_report *r)
{
	memset(r, 0, sizeof *r);
	r->step = st->step;
	r->t = st->t;
	r->t_end = st->t_end;
	r->dt = st->dt;
	r->dt_set = st->dt_set;
	r->dt_auto = st->dt_auto;
	r->omega = st->omega;
	r->nfev = st->in.nfev;
	r->rejected = st->in.rejected;
	r->solves = st->im.solves;
	r->substeps = st->pb.substeps;
	r->windows = st->windows;
	r->iters = st->im.iters;
	r->unconverged = st->im.unconverged;
	if (st->in.kind == INTEG_BDF2) {
		r->solves = st->bd.steps;
		r->newton = st->bd.newton;
		r->iters = st->bd.cg;
		r->unconverged = st->bd.unconverged;
	}
	r->collisions = st->col.active;
	r->uses_hash = collide_uses_hash(st->sc);
	r->cell = st->col.cell;
	r->last = &st->col.st;
	r->total = &st->col.total;
	r->ev = st->col.ev;
	r->nev = st->col.nev;
	r->locks = &st->locks;
	r->step_wall = st->step_wall;
	r->collide_wall = st->collide_wall;
	r->contacts_wall = st->contacts_wall;
}

/* The state one step back of a multistep method, or NULL. */
static const double *
stepper_history(const struct stepper *st)
{
	return st->in.kind == INTEG_BDF2 && st->bd.has_hist ? st->bd.hist : NULL;
}

void
stepper_save(const struct stepper *st, struct stepper_state *s)
{
	s->step = st->step;
	s->t = st->t;
	s->dt = st->dt;
	s->y = st->y;
	s->hist = stepper_history(st);
	s->hash = stepper_hash(st);
	s->nodes = (size_t)st->net.cl.n;
	s->dt_set = st->dt_set;
}

int
stepper_restore(struct stepper *st, const struct stepper_state *s, struct drape_err *err)
{
	double *keep = st->y, t = st->t;

	/* a state of another run: its steps would not be this run's */
	if (s->nodes != (size_t)st->net.cl.n || s->dt_set != st->dt_set) {
		err_set(err, "its scene now gives %d nodes and dt %.17g, expected the recorded "
		    "%zu and %.17g", st->net.cl.n, st->dt_set, s->nodes, s->dt_set);
		return -1;
	}
	/* tried in the scratch state, so that a mismatch leaves st as it was */
	memcpy(st->y_next, s->y, 6 * (size_t)st->net.cl.n * sizeof *st->y);
	st->y = st->y_next;
	st->t = s->t;
	if (stepper_state_hash(st->y, s->hist, (size_t)st->net.cl.n, st->t) != s->hash ||
	    (s->hist != NULL && st->in.kind != INTEG_BDF2)) {
		st->y = keep;
		st->t = t;
		err_set(err, "the state saved at step %ld does not match its hash", s->step);
		return -2;
	}
	st->y_next = keep;
	st->step = s->step;
	st->dt = s->dt;
	if (st->in.kind == INTEG_BDF2)
		bdf2_set_history(&st->bd, s->hist, s->dt);
	/* the locks are counted from here: a keyframe holds no lock runs */
	memset(st->lock_run, 0, (size_t)st->net.cl.n * sizeof *st->lock_run);
	memset(&st->locks, 0, sizeof st->locks);
	return 0;
}

static uint64_t
fnv1a(uint64_t h, const void *p, size_t len)
{
	const unsigned char *b = p;
	size_t i;

	for (i = 0; i < len; i++)
		h = (h ^ b[i]) * 0x100000001b3ULL;
	return h;
}

uint64_t
stepper_state_hash(const double *y, const double *hist, size_t nodes, double t)
{
	uint64_t h = fnv1a(0xcbf29ce484222325ULL, y, 6 * nodes * sizeof *y);

	h = fnv1a(h, &t, sizeof t);
	return hist != NULL ? fnv1a(h, hist, 6 * nodes * sizeof *hist) : h;
}

uint64_t
stepper_hash(const struct stepper *st)
{
	return stepper_state_hash(st->y, stepper_history(st), (size_t)st->net.cl.n, st->t);
}
