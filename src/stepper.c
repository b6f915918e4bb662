/* stepper.c: the order of one step, and the state it advances. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stepper.h"
#include "vec3.h"

/* dy/dt = (v, a); held nodes follow their prescribed velocity, unforced. */
static void
rhs(void *ctx, double t, const double *y, double *dy)
{
	struct stepper *st = ctx;
	size_t n3 = 3 * (size_t)st->cl.n;
	int k;

	memcpy(dy, y + n3, n3 * sizeof *dy);
	forces_accel(&st->fo, t, y, y + n3, dy + n3);
	if (st->pr.nnodes == 0)
		return;
	prescribed_apply(&st->pr, &st->cl, t, NULL, dy);
	for (k = 0; k < st->pr.nnodes; k++)
		v3_store(dy + n3 + 3 * st->pr.node[k], v3(0, 0, 0));
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
	return 0.5 * limit / lam;
}

int
stepper_init(struct stepper *st, const struct scene *sc, struct drape_err *err)
{
	size_t n3;
	double extent, vscale, tol;
	int p;

	memset(st, 0, sizeof *st);
	st->sc = sc;
	if (cloth_build(&st->cl, sc, err) != 0)
		return -1;
	if (prescribed_build(&st->pr, sc, &st->cl, err) != 0 ||
	    forces_init(&st->fo, sc, &st->cl, err) != 0)
		goto fail;
	cloth_clamp_hinges(&st->cl, st->pr.held);
	n3 = 3 * (size_t)st->cl.n;
	tol = sc->tolerance > 0 ? sc->tolerance : integrator_default_tolerance(sc->integrator);
	if (integrator_init(&st->in, sc->integrator, 2 * n3, tol) != 0 ||
	    (sc->integrator == INTEG_IMPLICIT_EULER &&
	    implicit_init(&st->im, &st->fo, st->pr.held, tol) != 0) ||
	    (st->y = malloc(2 * n3 * sizeof *st->y)) == NULL ||
	    (st->y_next = malloc(2 * n3 * sizeof *st->y_next)) == NULL) {
		err_set(err, "%s: out of memory", sc->path);
		goto fail;
	}
	memcpy(st->y, st->cl.x0, n3 * sizeof *st->y);
	for (p = 0; p < st->cl.n; p++)
		v3_store(st->y + n3 + 3 * p, v3_load(sc->velocity));
	prescribed_apply(&st->pr, &st->cl, 0, st->y, st->y + n3);

	st->t_end = sc->duration;
	st->omega = cloth_omega_bound(&st->cl);

	/* Speeds a run can reach without blowing up: falling over the cloth's
	 * size, prescribed motion, loads while they act; 1000 times that is a
	 * runaway. */
	extent = st->cl.h * hypot(st->cl.nu - 1, st->cl.nv - 1);
	vscale = 1 + sqrt(2 * v3_len(v3_load(sc->gravity)) * extent) +
	    v3_len(v3_load(sc->velocity)) + prescribed_max_speed(&st->pr) +
	    forces_load_speed(&st->fo, sc->duration);
	st->v_limit = 1000 * vscale;

	st->dt_auto = sc->dt == 0;
	st->dt_set = st->dt_auto ? stepper_auto_dt(sc->integrator, st->omega, sc->mat.damping,
	    sc->mat.spring_damping, st->cl.h / vscale) : sc->dt;
	st->dt = st->dt_set;
	if (!(st->dt > 0) || !isfinite(st->dt)) {
		err_set(err, "%s: cannot choose a time step (the stiffness bound is %g rad/s); "
		    "set dt in [simulation]", sc->path, st->omega);
		goto fail;
	}
	if (collide_init(&st->col, sc, &st->cl, st->pr.held, st->dt_set, vscale, err) != 0)
		goto fail;
	return 0;
fail:
	stepper_free(st);
	return -1;
}

void
stepper_free(struct stepper *st)
{
	collide_free(&st->col);
	integrator_free(&st->in);
	implicit_free(&st->im);
	forces_free(&st->fo);
	prescribed_free(&st->pr);
	cloth_free(&st->cl);
	free(st->y);
	free(st->y_next);
	memset(st, 0, sizeof *st);
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
	size_t n3 = 3 * (size_t)st->cl.n;
	double lim2 = st->v_limit * st->v_limit;
	int p;

	for (p = 0; p < st->cl.n; p++) {
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

	for (s = 0; s < st->cl.nsprings; s++) {
		const struct spring *sp = &st->cl.springs[s];
		vec3 d = v3_sub(v3_load(y + 3 * sp->b), v3_load(y + 3 * sp->a));

		if (v3_dot(d, d) > TORN * TORN * sp->rest * sp->rest) {
			snprintf(why, len, "the network tore: its spring to node %d is %.3g times its "
			    "rest length", sp->b, v3_len(d) / sp->rest);
			return sp->a;
		}
	}
	return -1;
}

/* Fills bl for node `bad` (bl->why is set); returns 1. */
static int
blown_up(const struct stepper *st, struct blowup *bl, int bad)
{
	bl->step = st->step;
	bl->t = st->t;
	bl->node = bad;
	cloth_grid_ij(&st->cl, bad, &bl->i, &bl->j);
	return 1;
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
		for (p = 0; p < st->cl.n; p++) {
			vec3 n;
			double nn[3];

			if (st->pr.held[p] ||
			    obstacle_distance(ob, v3_load(st->y + 3 * p), NULL, &n) >= rest)
				continue;
			v3_store(nn, n);
			implicit_constrain(&st->im, p, nn);
		}
	}
}

int
stepper_step(struct stepper *st, struct blowup *bl)
{
	size_t n3 = 3 * (size_t)st->cl.n;
	double h = st->dt, h_next, remaining = st->t_end - st->t, t_new;
	int last = 0, bad;
	double *swap;
	struct drape_err cerr;

	if (h >= remaining * (1 - 1e-12)) {	/* land on the end exactly */
		h = remaining;
		last = 1;
	}
	/* 1. integrate: consistent state k -> predicted state k+1 */
	if (st->in.kind == INTEG_IMPLICIT_EULER) {
		constrain_resting(st, h);
		implicit_step(&st->im, st->t, h, st->y, st->y_next);
		h_next = h;
	} else if (integrator_step(&st->in, rhs, st, st->t, st->y, st->y_next, &h, &h_next) != 0) {
		bl->step = st->step;
		bl->t = st->t;
		bl->node = bl->i = bl->j = -1;
		snprintf(bl->why, sizeof bl->why, "the adaptive step fell below %g s", h);
		return 1;
	}
	/* A fixed step's time is a product, not a sum of rounded steps, so
	 * that t stays as exact as the positions it goes with. */
	if (last && h == remaining)
		t_new = st->t_end;
	else if (st->in.kind != INTEG_DOPRI5)
		t_new = (double)(st->step + 1) * st->dt_set;
	else
		t_new = st->t + h;
	/* 2. specified displacements */
	prescribed_apply(&st->pr, &st->cl, t_new, st->y_next, st->y_next + n3);
	/* 3. collisions: self-contact, obstacles; not on a state that has
	 * already blown up, whose extent no broad phase could cut into cubes */
	if ((bad = find_blowup(st, st->y_next, bl->why, sizeof bl->why)) >= 0)
		return blown_up(st, bl, bad);
	if (collide_step(&st->col, st->step, h, st->y, st->y_next, &cerr) != 0) {
		bl->step = st->step;
		bl->t = st->t;
		bl->node = bl->i = bl->j = -1;
		snprintf(bl->why, sizeof bl->why, "%.*s", (int)sizeof bl->why - 1, cerr.msg);
		return 1;
	}
	/* 4. blow-up check before anything is committed */
	if ((bad = find_blowup(st, st->y_next, bl->why, sizeof bl->why)) >= 0 ||
	    (bad = find_torn(st, st->y_next, bl->why, sizeof bl->why)) >= 0)
		return blown_up(st, bl, bad);
	/* 5. commit */
	swap = st->y;
	st->y = st->y_next;
	st->y_next = swap;
	st->t = t_new;
	st->step++;
	st->dt = st->in.kind == INTEG_DOPRI5 ? fmin(h_next, st->dt_set) : st->dt_set;
	return 0;
}

void
stepper_energy(const struct stepper *st, struct energy *e)
{
	forces_energy(&st->fo, st->t, stepper_x(st), stepper_v(st), e);
}

uint64_t
stepper_hash(const struct stepper *st)
{
	const unsigned char *b = (const unsigned char *)st->y;
	size_t len = 6 * (size_t)st->cl.n * sizeof *st->y, i;
	uint64_t h = 0xcbf29ce484222325ULL;

	for (i = 0; i < len; i++)
		h = (h ^ b[i]) * 0x100000001b3ULL;
	b = (const unsigned char *)&st->t;
	for (i = 0; i < sizeof st->t; i++)
		h = (h ^ b[i]) * 0x100000001b3ULL;
	return h;
}
