/* forces.h: accelerations and energy of the network: internal forces
 * (stretch, shear, bending, damping) and external ones (gravity, loads). */
#ifndef DRAPE_FORCES_H
#define DRAPE_FORCES_H

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>

#include "cloth.h"
#include "err.h"
#include "scene.h"

struct load_group {
	int *node;
	int n;
	double f[3];
	double start, stop;
};

/* Whether load group lg acts at time t: over [start, stop). */
bool load_active(const struct load_group *lg, double t);

struct forces {
	const struct cloth *cl;
	double g[3];		/* m/s2 */
	double damping;		/* 1/s */
	double spring_damping;	/* s */
	struct load_group *loads;
	int nloads;
	/* forces_accel's and forces_energy's fold limiter (0: none; see
	 * forces_explicit_fold): a hinge's D taken as at least fold * rest^2 */
	double fold;
	/* polled in the element loops (NULL: never): once set, a call
	 * returns early, its result unfinished, for the caller to drop */
	const volatile sig_atomic_t *stop;
};

struct energy {
	double kinetic, gravity, stretch, shear, bend, load;
};

int forces_init(struct forces *fo, const struct scene *sc, const struct cloth *cl,
    struct drape_err *err);
void forces_free(struct forces *fo);
void forces_set_stop(struct forces *fo, const volatile sig_atomic_t *flag);
/* 1 once the stop flag is set. */
bool forces_stopped(const struct forces *fo);

/* For the loops over elements (here and in jacobian.c): 1 when the flag is
 * set, looked at once every FORCES_POLL_EVERY elements (i counts them).
 * On the largest cloth (2048 x 2048) a pass over an element kind takes
 * tenths of a second. */
#define FORCES_POLL_EVERY 65536
static inline bool
forces_poll(const struct forces *fo, size_t i)
{
	return (i + 1) % FORCES_POLL_EVERY == 0 && forces_stopped(fo);
}

/* a = F/m for every node, from positions x and velocities v (3n each):
 * minus the gradient of forces_energy's, fo->fold's limiter included. */
void forces_accel(const struct forces *fo, double t, const double *x, const double *v, double *a);
/* The same without the stretch springs and their dashpots and without
 * the shear corners (the fast path solves both as constraints), and with
 * the fold limiter: a hinge's D (add_bend in forces.c: rest^2 (1 + cos theta)
 * for a turning angle theta) is taken as at least fold * rest^2, so that
 * its stiffness, k at rest and growing as sec^4(theta/2) towards a fold
 * right back, stays within what an explicit substep integrates (0: none;
 * forces_fold_limit gives it); and with a dashpot on each hinge's rate
 * of bending, force -c k g (g.v) for its stiffness k and g the gradient
 * of |kb| (c in seconds, 0 for none): stiffness-proportional damping of
 * the bending alone, which a turn of the whole hinge does not feel
 * (pbd.c BEND_DAMPING says why). */
void forces_accel_bending(const struct forces *fo, double t, const double *x, const double *v,
    double *a, double fold, double c);
/* The fold at which a hinge is s times as stiff as at rest (s >= 1). */
double forces_fold_limit(double s);
/* The fold limiter of an explicit integrator's forces (fo->fold): a
 * hinge's stiffness, k at rest and growing as sec^4(theta/2) towards a
 * fold right back, held where its frequency reaches the network's bound
 * at rest (cloth_omega_bound, which sets the explicit step), and at least
 * twice its stiffness at rest. Past it the hinge's energy is k |kb|^2 / 2
 * with D held there, whose forces stay its gradient. Without it RK4 blew
 * up as the peers' table landed (bench-history.md, stop 48). 0 where the
 * cloth has no hinges. */
double forces_explicit_fold(const struct cloth *cl);

void forces_energy(const struct forces *fo, double t, const double *x, const double *v,
    struct energy *e);

/* The elastic energy (stretch, shear, bending) at positions x, and, when
 * f is not NULL, its forces, minus its gradient, into f (3n, overwritten):
 * the potential an implicit step minimises (bdf2.c), in one pass. No
 * dashpots, no fold limiter, no gravity or loads. +INFINITY where a hinge
 * has folded right back (its energy's barrier). */
double forces_elastic(const struct forces *fo, const double *x, double *f);
double energy_total(const struct energy *e);

/* The speed the loads could give a node on its own over the run's first
 * `duration` seconds (each set's force over its lightest node's mass, for
 * as long as it acts), in m/s: a scale for the speeds a run reaches. */
double forces_load_speed(const struct forces *fo, double duration);

#endif
