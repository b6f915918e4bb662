/* stepper.h: a run in progress, and the only way into one. The stepper
 * owns the order of a step (the chapter's §4): integrate to the predicted
 * state k+1 from the consistent state k, put held nodes back on their
 * prescribed motion, correct the nodes that collide (self-contact, then
 * obstacles), check for a blow-up, commit.
 *
 * Its state is private (stepper.c): a run is made from a checked scene,
 * stepped, read through a report and the state's positions and
 * velocities, saved and restored; recording, the TUI's sources, --resume
 * and the commands use nothing else. */
#ifndef DRAPE_STEPPER_H
#define DRAPE_STEPPER_H

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "integrate.h"	/* enum integrator_kind */

/* What the interface names by pointer only: a caller that reads one
 * includes its header (scene.h, network.h, forces.h, broad.h, stats.h,
 * event.h, err.h), and no caller sees the stages' state. */
struct collide_stats;
struct contact_event;
struct drape_err;
struct energy;
struct geom;
struct network;
struct scene;

struct stepper;

/* How a step ended. A blow-up is the simulation's: it diverged (exit 3).
 * An error is not: the run cannot go on for want of memory or because the
 * scene's extent does not fit the broad phase (exit 1). */
enum step_status {
	STEP_OK,
	STEP_BLOWUP,
	STEP_ERROR,
	STEP_STOPPED,		/* given up for stepper_set_stop's flag: no failure */
};

struct step_failure {
	enum step_status status;
	long step;		/* the step that failed */
	double t;		/* time at its start */
	int node;		/* a blow-up's first bad node, or -1 */
	int i, j;		/* its grid position */
	char why[400];
};

/* The one wording of a failure: "blow-up at step S (t = T s): node N (i I,
 * j J): WHY", or "step S (t = T s): WHY" for an error. */
void step_failure_format(const struct step_failure *f, char *buf, size_t len);

/* Builds the network and the initial state from a checked scene; the scene
 * must outlive the stepper. NULL with a message in err (also when the
 * duration would take more than SCENE_MAX_STEPS steps). */
struct stepper *stepper_new(const struct scene *sc, struct drape_err *err);

/* The same, telling pg's stage (when not NULL) the name of each stage of
 * the setup as it begins ("the network", "the integrator", "the collision
 * geometry"): for a command that shows progress. */
struct stepper_progress {
	void (*stage)(void *ctx, const char *what);
	void *ctx;
};
struct stepper *stepper_new_progress(const struct scene *sc, const struct stepper_progress *pg,
    struct drape_err *err);
void stepper_free(struct stepper *st);	/* NULL is fine */

/* Polls *flag in the long loops of a step (the broad phase, the ccd passes,
 * the implicit solve) and once more before the step is committed: once it
 * is set, the step is given up (STEP_STOPPED) with the state at the last
 * good step, so that a signal is honoured within a step. NULL: never. */
void stepper_set_stop(struct stepper *st, const volatile sig_atomic_t *flag);

/* One step. On a failure (described in *f) the state stays at the last
 * good step. */
enum step_status stepper_step(struct stepper *st, struct step_failure *f);
bool stepper_done(const struct stepper *st);

const struct scene *stepper_scene(const struct stepper *st);
const struct network *stepper_network(const struct stepper *st);
const double *stepper_x(const struct stepper *st);	/* 3n positions */
const double *stepper_v(const struct stepper *st);	/* 3n velocities */
void stepper_energy(const struct stepper *st, struct energy *e);
/* FNV-1a over the state's bytes and the time, and a multistep method's
 * history after them: equal hashes, equal runs. */
uint64_t stepper_hash(const struct stepper *st);
/* The same of a state y (6 * nodes doubles) at time t, with hist (the
 * same size) or NULL. */
uint64_t stepper_state_hash(const double *y, const double *hist, size_t nodes, double t);

/* The geometry the collision stages see (cloth nodes, then obstacle mesh
 * vertices), for tests and audits. */
const struct geom *stepper_geom(const struct stepper *st);

/* Nodes locked in place: put back exactly where they were at step k by the
 * collision stages (`position = keep`, or ccd's last resort), so that the
 * step moved them not at all. The chapter's §3.2 names the locking ("a
 * node to get locked in place along a surface where it should slide");
 * these say how many, for how long, and what kinetic energy they hold
 * while their position cannot change. Counted over the committed steps
 * (a resumed run counts from its resume). */
struct lock_stats {
	/* the last step's */
	int now;		/* nodes locked at it */
	double ke_now;		/* J: their kinetic energy after the correction */
	long run_now;		/* steps in a row the longest-locked of them has been locked */
	/* the run's */
	long node_steps;	/* nodes locked, summed over the steps */
	int most;		/* the most nodes locked at one step */
	long longest;		/* the most steps in a row a node stayed locked */
	double ke_most;		/* J: the most kinetic energy the locked nodes held at one step */
};

/* What a run has done, as of its last step (read-only; the pointers are
 * valid until the next step). */
struct stepper_report {
	long step;
	double t, t_end;
	double dt;		/* the step to try next */
	double dt_set;		/* the scene's (or auto) step: DOPRI5's largest */
	bool dt_auto;
	double omega;		/* the bound on the highest angular frequency */
	long nfev, rejected;	/* explicit methods: force evaluations, rejected steps */
	long solves, iters, unconverged;	/* implicit Euler, bdf2: solves, CG iterations */
	long newton;		/* bdf2: Newton iterations */
	long substeps;		/* fast: its substeps */
	long windows;		/* fast: its contact windows (a step or more each) */
	bool collisions;	/* anything to collide with */
	bool uses_hash;		/* the broad phase fills a spatial hash */
	double cell;		/* L_ce */
	const struct collide_stats *last, *total;	/* the last step's, and the run's */
	const struct contact_event *ev;	/* the last step's events */
	size_t nev;
	const struct lock_stats *locks;
	/* s of wall time over the committed steps: all of each step, its
	 * collision stages (broad and narrow phases and response), and the
	 * search for its contacts inside the integration (fast, bdf2) */
	double step_wall, collide_wall, contacts_wall;
};
void stepper_report(const struct stepper *st, struct stepper_report *r);

/* A saved state, as a keyframe holds it, and the run it is a state of (a
 * replay's header holds those). */
struct stepper_state {
	long step;
	double t, dt;		/* dt: the step to try next */
	const double *y;	/* positions (3n) then velocities (3n) */
	/* a multistep method's (bdf2): the state one step back, as y, or
	 * NULL (the first step, and the other methods) */
	const double *hist;
	uint64_t hash;		/* stepper_hash of it */
	size_t nodes;		/* the run's node count (n) */
	double dt_set;		/* and its scene's (or auto) step */
};

/* s points into st until its next step. */
void stepper_save(const struct stepper *st, struct stepper_state *s);
/* Puts st in state s; st is unchanged by a refusal. 0; -1 with a message
 * when s is not a state of this run ("its scene now gives N nodes and dt
 * D, expected the recorded N' and D'": the node count or dt_set differ);
 * -2 with a message when s is not the state its hash was taken of. */
int stepper_restore(struct stepper *st, const struct stepper_state *s, struct drape_err *err);

#define STEPPER_FAST_DT 0.01	/* s: dt = auto for the fast path */
#define STEPPER_BDF2_DT 0.01	/* s: and for bdf2 */

/* The step `dt = auto` picks for a scene (drape-scene(5) says how);
 * crossing is the time to cross a spacing at the fastest expected speed. */
double stepper_auto_dt(enum integrator_kind kind, double omega, double damping,
    double spring_damping, double crossing);

#endif
