/* integrate.h: one step of an ODE y' = f(t, y) by a chosen method.
 *
 * y holds positions then velocities (two halves of n/2), and f returns
 * velocities then accelerations; symplectic Euler relies on that split.
 * Nothing here knows about cloth. */
#ifndef DRAPE_INTEGRATE_H
#define DRAPE_INTEGRATE_H

#include <stdbool.h>
#include <stddef.h>

enum integrator_kind {
	INTEG_RK4,		/* classic 4th order Runge-Kutta: the chapter's */
	INTEG_EULER,		/* explicit (forward) Euler */
	INTEG_SYMPLECTIC_EULER,	/* v then x (semi-implicit Euler) */
	INTEG_RK2,		/* explicit midpoint */
	INTEG_DOPRI5,		/* Dormand-Prince 5(4), adaptive */
	/* Linearly implicit Euler: named and numbered here, but stepped by
	 * implicit.c, which needs the forces' Jacobian and not only f. */
	INTEG_IMPLICIT_EULER,
	/* The fast path: implicit Euler at steps of a frame, its solve
	 * preconditioned along the yarns (hess.h); implicit.c steps it too. */
	INTEG_FAST,
	/* BDF2 over the whole cloth, a Newton solve a step (bdf2.h); stepped
	 * by bdf2.c */
	INTEG_BDF2,
	INTEG_COUNT
};

typedef void (*rhs_fn)(void *ctx, double t, const double *y, double *dydt);

struct integrator {
	enum integrator_kind kind;
	size_t n;
	double tol;		/* DOPRI5 only: absolute and relative */
	double *k[7];
	double *tmp;
	long nfev;		/* evaluations of f so far */
	long rejected;		/* DOPRI5 steps tried and refused */
};

const char *integrator_name(enum integrator_kind kind);
/* implicit-euler, fast and bdf2: stepped by implicit.c, pbd.c, bdf2.c. */
bool integrator_is_implicit(enum integrator_kind kind);
/* fast and bdf2: they find their contacts inside the step, before the
 * collision stages. */
bool integrator_finds_contacts(enum integrator_kind kind);
int integrator_from_name(const char *name, enum integrator_kind *kind);
/* "rk4, euler, ... or fast" into buf (cut to len): every name, from the
 * table, for the messages that say what was expected, so that none of
 * them can leave an integrator out. */
void integrator_names(char *buf, size_t len);

/* Order of accuracy, and the largest h*omega for which an undamped
 * oscillator of angular frequency omega stays bounded (0 for methods that
 * grow for any step: explicit Euler and explicit midpoint; infinite for
 * implicit Euler). */
int integrator_order(enum integrator_kind kind);
/* The tolerance a scene that sets none gets: DOPRI5's local error (1e-6),
 * implicit Euler's CG residual relative to its right-hand side (1e-3),
 * bdf2's Newton tolerance, a step done when the next Newton step would
 * move no node by that part of the step's largest motion (1e-2); the
 * others take none. */
double integrator_default_tolerance(enum integrator_kind kind);
double integrator_imag_limit(enum integrator_kind kind);

int integrator_init(struct integrator *in, enum integrator_kind kind, size_t n, double tol);
void integrator_free(struct integrator *in);

/*
 * Sets y_out to y(t + *dt). DOPRI5 may shrink *dt until the local error is
 * within tolerance; every method sets *dt_next to the step it proposes next.
 * Returns 0, or -1 if DOPRI5's step fell below what t can resolve (or for
 * INTEG_IMPLICIT_EULER, which this cannot step).
 */
int integrator_step(struct integrator *in, rhs_fn f, void *ctx, double t, const double *y,
    double *y_out, double *dt, double *dt_next);

#endif
