/* implicit.h: one linearly implicit (backward) Euler step of the network,
 * after Baraff & Witkin (1998): a single Newton iteration of backward Euler,
 *
 *   (M + h C + h^2 K) dv = h (f(x, v) - h K v),  v' = v + dv,  x' = x + h v',
 *
 * with K and C from jacobian.h, solved by conjugate gradients with a
 * block-diagonal (Jacobi) preconditioner. Held nodes keep their velocity
 * through the solve (the caller puts them on their prescribed motion
 * afterwards).
 *
 * A node resting on an obstacle is constrained (Baraff & Witkin's filter):
 * its velocity along the obstacle's normal does not change in the solve,
 * as long as the forces push it into the obstacle, and its sliding along
 * the obstacle is slowed by Coulomb friction on the impulse the constraint
 * takes (at most mu times it; a node slower than that stops). Without
 * this, the solve
 * would spend a stiff spring's pull on motion into the obstacle, which the
 * collision stage then takes away, and the springs at a table's edge would
 * stay stretched by tens of percent at steps of milliseconds.
 *
 * It is stable at any step for a linear network, where the explicit
 * methods need h*omega below a few: at the cost of first-order accuracy and
 * a numerical damping that grows with h*omega, so the stiff stretching
 * vibrations die out and the slow motion is kept. */
#ifndef DRAPE_IMPLICIT_H
#define DRAPE_IMPLICIT_H

#include <signal.h>
#include <stdbool.h>

#include "forces.h"
#include "jacobian.h"

struct implicit {
	const struct forces *fo;
	const unsigned char *held;	/* n flags, or NULL */
	struct jacobian jc;
	double tol;			/* CG: |r| <= tol*|b| */
	int max_iter;
	double *a, *b, *dv, *r, *z, *p, *q;
	double *pre;			/* per node: its 3 x 3 block of the system, inverted */
	double *cdir;			/* per node: up to 3 orthonormal constrained directions */
	double *cmu;			/* per node and direction: the obstacle's friction */
	double *cjn;			/* per node and direction: the step's normal impulse */
	unsigned char *ncon;		/* per node: how many */
	long solves, iters;		/* so far */
	long unconverged;		/* solves that ended above the tolerance */
	const volatile sig_atomic_t *stop;	/* set: give the solve up (NULL: never) */
	bool stopped;			/* the last solve was given up for stop */
	int last_iters;
};

int implicit_init(struct implicit *im, const struct forces *fo, const unsigned char *held,
    double tol);
void implicit_free(struct implicit *im);

/* Polls *flag in the solve: once it is set, the step is given up
 * (im->stopped). NULL: never. */
void implicit_set_stop(struct implicit *im, const volatile sig_atomic_t *flag);

/* Constrains node p along the unit normal n for the next step only; mu:
 * the obstacle's Coulomb friction on the node's sliding along it. */
void implicit_constrain(struct implicit *im, int p, const double n[3], double mu);

/* y = positions (3n) then velocities (3n) at time t; sets y_out to the
 * state at t + h, and drops the constraints. */
void implicit_step(struct implicit *im, double t, double h, const double *y, double *y_out);

#endif
