/* stepper.h: a run in progress. The stepper owns the order of a step
 * (the chapter's §4): integrate to the predicted state k+1 from the
 * consistent state k, put held nodes back on their prescribed motion,
 * correct the nodes that collide (self-contact, then obstacles), check for
 * a blow-up, commit. */
#ifndef DRAPE_STEPPER_H
#define DRAPE_STEPPER_H

#include <stdbool.h>
#include <stdint.h>

#include "cloth.h"
#include "collide.h"
#include "err.h"
#include "forces.h"
#include "implicit.h"
#include "integrate.h"
#include "prescribed.h"
#include "scene.h"

struct blowup {
	long step;		/* the step that failed */
	double t;		/* time at its start */
	int node;		/* first bad node, or -1 */
	int i, j;		/* its grid position */
	char why[160];
};

struct stepper {
	const struct scene *sc;
	struct cloth cl;
	struct prescribed pr;
	struct forces fo;
	struct integrator in;	/* the explicit methods */
	struct implicit im;	/* implicit Euler */
	struct collide col;
	double *y, *y_next;	/* positions (3n) then velocities (3n) */
	double t, t_end;
	double dt;		/* the step to try next */
	double dt_set;		/* the scene's (or auto) step: DOPRI5's largest */
	bool dt_auto;
	double omega;		/* bound on the highest angular frequency */
	double v_limit;		/* a node faster than this has blown up */
	long step;
};

/* Builds the network and the initial state from a checked scene; the scene
 * must outlive the stepper. Returns 0, or -1 with a message in err. */
int stepper_init(struct stepper *st, const struct scene *sc, struct drape_err *err);
void stepper_free(struct stepper *st);

/* One step. Returns 0, or 1 on a blow-up (described in *bl); the state is
 * then left at the last good step. */
int stepper_step(struct stepper *st, struct blowup *bl);
bool stepper_done(const struct stepper *st);

static inline double *stepper_x(const struct stepper *st) { return st->y; }
static inline double *stepper_v(const struct stepper *st) { return st->y + 3 * st->cl.n; }

void stepper_energy(const struct stepper *st, struct energy *e);
/* FNV-1a over the state's bytes and the time: equal hashes, equal runs. */
uint64_t stepper_hash(const struct stepper *st);

/* The step `dt = auto` picks for a scene (drape-scene(5) says how);
 * crossing is the time to cross a spacing at the fastest expected speed. */
double stepper_auto_dt(enum integrator_kind kind, double omega, double damping,
    double spring_damping, double crossing);

#endif
