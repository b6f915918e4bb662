/* bdf2.h: the implicit step (integrator = bdf2): the second-order backward
 * differentiation formula over the whole cloth at steps of a frame, each
 * step one minimisation solved by Newton's method.
 *
 * BDF2 for x'' = F/m, with beta = 2h/3,
 *   xhat = (4 x_n - x_n-1)/3,  vhat = (4 v_n - v_n-1)/3,
 *   v_n+1 = (x_n+1 - xhat)/beta,  M (v_n+1 - vhat) = beta F(x_n+1, v_n+1),
 * is the stationary point of the incremental potential
 *   Phi(x) = |x - (xhat + beta vhat)|^2_M / (2 beta^2) + E(x) + D(x) + C(x)
 * (Gast et al. 2015, "Optimization integrator for large time steps";
 * Martin et al. 2011 for the variational form): E the elastic energy with
 * gravity and loads, D the damping's quadratic in v_n+1, C the contacts'
 * penalties and friction. Newton's method with a line search on Phi
 * descends to it whatever the stiffness: the yarns' stretch, shear and
 * bending are taken together, implicitly, with no substep. The first step
 * takes the history of the parabola through the start state (the state
 * one step back at its present acceleration): BDF2 needs it, the step
 * keeps it, and a keyframe holds it. Newton starts from the step's start,
 * which the energy's barriers allow (no hinge folded right back), and the
 * line search keeps every iterate so.
 *
 * BDF2 is L-stable, so the stiff vibrations die within steps, and of
 * second order: over 100 steps it keeps 99.5 % of a mode at h w = 0.1 and
 * 72 % at 0.3 (backward Euler 37 % and 0). At a step of a frame that is
 * still most motion faster than a few hertz, so the step gives back what
 * it took (bdf2_correct_energy): the energy the system had, less the work
 * of its contacts, friction and damping, plus that of its held nodes, is
 * its budget, and the free nodes' velocities are scaled to meet it. No
 * step ends with more; the undamped hanging strip keeps 54 % of RK4's
 * energy above rest at 1 s (7.5 % without).
 *
 * Contacts are terms of Phi, found once a step at its start:
 *   - analytic obstacles: a node within reach of one gets a penalty
 *     k (c - phi(x))^2 / 2 while its distance phi from the plane of the
 *     solid's nearest point at the step's start is under the clearance c
 *     (the solid is convex: all of it lies behind that plane); k is a
 *     multiple of the node's m / beta^2, so the rest penetration under a
 *     pile is microns;
 *   - a box's edges: a cloth edge whose nearest point to a box lies
 *     between its nodes gets the same penalty on its least distance to
 *     the box (taken at each iterate, the box's edges rounded by that
 *     clearance), at half the nodes' clearance, shared by the nodes as
 *     that point's weights (Bridson et al. 2002's edge contact); found at
 *     the step's start and, as the solve moves the cloth, at its end;
 *   - the cloth against itself and against meshes: contacts.h's pairs,
 *     each held a thickness apart on the plane it had at the step's start
 *     by a penalty of the same kind;
 *   - Coulomb friction as Li et al.'s lagged, smoothed dissipative
 *     potential (IPC, 2020): mu lambda f0(|u|) over the tangential
 *     displacement u of the step, with the normal force lambda of the
 *     iterate; below a slip of FRICTION_SLIP h it holds like a stiff spring,
 *     so a cloth resting on a slope stays put instead of creeping.
 * The step's contacts are then collisions of the method's own and are
 * recorded as events with their impulse (beta times their force); the
 * stepper's exact check after the step remains the guarantee.
 *
 * A contact that stops a node is a jump of its velocity, which BDF2's
 * three-point difference would carry into the next step as a rebound
 * ((3 x_n+1 - 4 x_n + x_n-1) / 2h after a sudden stop is half the speed
 * it had, outwards). So along each contact's normal a node's history is
 * made the one of a node that moved at its new velocity all along
 * (bdf2_commit), and a node the exact check moved loses its history
 * altogether. */
#ifndef DRAPE_BDF2_H
#define DRAPE_BDF2_H

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>

#include "blockmat.h"
#include "forces.h"
#include "jacobian.h"
#include "mg.h"
#include "prescribed.h"
#include "scene.h"

struct contacts;
struct collide;

/* A node within reach of an analytic obstacle, for one step. */
struct bdf2_obstacle_contact {
	int node, obstacle;
	double k;		/* N/m: the penalty's stiffness */
	double mu;		/* the obstacle's friction */
	double tan[6];		/* two unit tangents of its surface at the step's start */
	double lambda;		/* N: the normal force of the iterate, for friction */
	double fric;		/* friction's stiffness across: mu lambda f1(s)/s */
	double phi;		/* m: its signed distance at the iterate */
	double n[3], q[3];	/* the surface's normal and nearest point there */
};

/* A cloth edge within reach of a box, for one step: its least distance
 * to the box held over a clearance (bdf2.c edge_gap). The nearest point's
 * t, normal and distance are the iterate's (the last assembly's or
 * end's). */
struct bdf2_edge_contact {
	int edge, a, b, obstacle;	/* the cloth's edge, its nodes */
	double wa, wb;		/* the nearest point's weights, 1 - t and t */
	double k;		/* N/m: the penalty's stiffness */
	double phi;		/* m: the edge's distance to the box */
	double n[3], q[3];	/* the box's normal and point nearest the edge */
	int ab, ba;		/* H's blocks (a, b) and (b, a), or -1 */
	bool smooth;		/* its two nodes' block is in the preconditioner */
	double chol[21];	/* that 6 x 6 block's Cholesky factor, packed by rows */
};

/* A contact pair's terms at the iterate (contacts.h's pair of the same
 * index). */
struct bdf2_pair_term {
	double k;		/* N/m: the penalty's stiffness */
	double gap;		/* m: its separation along n0 at the iterate */
	double lambda;		/* N: its normal force */
	double fric;		/* friction's stiffness across */
	double tan[6];		/* two unit tangents of n0 */
};

struct bdf2 {
	const struct scene *sc;
	const struct forces *fo;
	const struct prescribed *pr;
	struct jacobian jc;
	struct blockmat H;	/* the Newton system, with the pairs' diagonal blocks */
	struct mg mg;		/* its preconditioner */
	bool use_mg;		/* the last setup succeeded (else block Jacobi) */
	long mg_step;		/* the step of its last full setup (-1: none yet) */
	int mg_cg;		/* CG iterations of the first solve after it (-1: none yet) */
	double kmax;		/* N/m: the stiffest spring's */
	double tol;		/* converged when every free node's |dPhi/dx|/m <= tol (m/s^2), */
	double rel;		/* or Newton's step moves no node rel of the step's largest motion */
	int max_newton, max_cg;
	double last_step;	/* m: the last Newton step's largest move */
	/* the state one step back (positions then velocities, 6n), and
	 * whether there is one */
	double *hist;
	bool has_hist;
	double h_hist;		/* s: how far back hist is */
	/* the step's */
	double t1, beta;
	const double *x0;	/* positions at the step's start (the caller's y) */
	double *xhat, *vhat, *target;	/* 3n each */
	double *x, *g, *dx, *xtry, *f;	/* Newton */
	double *r, *z, *p, *q, *pre;	/* conjugate gradients */
	double *udamp;		/* per spring: its unit vector at the step's start */
	struct bdf2_obstacle_contact *oc;
	size_t noc, occap;
	struct bdf2_edge_contact *ec;
	size_t nec, eccap;
	unsigned char *emark;	/* per cloth edge: has a contact this step */
	size_t nsmooth;		/* the edges whose blocks the preconditioner solves */
	struct bdf2_pair_term *pt;
	size_t ptcap;
	/* the pairs that push at the iterate (its system's), and those whose
	 * terms the potential takes (the line search's may push ahead) */
	size_t *act, nact, *live, nlive;
	/* the pairs that may push before the nodes drift (bdf2.c near_pairs) */
	size_t *near, nnear;
	double near_reach, drift;
	bool near_ok;
	struct contacts *ct;	/* the step's pairs, and their geometry */
	/* the normals along which each node's history is made anew at the
	 * commit (up to 3 a node) */
	double *rdir;
	unsigned char *nreset;
	/* the step's energy (J): at its start, at the solve's end, and the
	 * budget (bdf2_correct_energy) */
	double e_start, e_solved, e_budget;
	double last_restored, restored;	/* J: given back, the last step and in all */
	/* Newton's stop on a small decrease (bdf2.c NEWTON_DECREASE, and
	 * NEWTON_DECREASE_CONTACT where a contact pushes; 0 with a scene's
	 * tolerance) and Phi where the last line search went */
	double decrease, decrease_contact, phi_taken;
	/* the forcing term's (bdf2.c CG_REDUCTION_TIGHT): the last solve's
	 * |g| and |g + H dx|, its linear model's */
	double gnorm_last, model_last;
	/* so far */
	long steps, newton, cg, unconverged, cuts;
	int last_newton, last_cg;
	double last_residual;	/* m/s^2, the largest |dPhi/dx|/m at the end */
	const volatile sig_atomic_t *stop;
	bool stopped;
};

/* For a checked scene and its network; tol is the Newton iterations'
 * tolerance (the scene's: a step is done when the next Newton step would
 * move no node by this part of the step's largest motion), 0 for the
 * default (1e-2).
 * Returns 0, or -1 out of memory. */
int bdf2_init(struct bdf2 *b, const struct scene *sc, const struct forces *fo,
    const struct prescribed *pr, double tol);
void bdf2_free(struct bdf2 *b);
void bdf2_set_stop(struct bdf2 *b, const volatile sig_atomic_t *flag);

/* y (positions, velocities at t) to y_out at t + h; ct: the step's
 * contact pairs (contacts_find), or NULL. Held nodes
 * end on their prescribed positions (their velocities are the caller's).
 * Once the stop flag is set it returns early (b->stopped), y_out
 * unfinished. */
void bdf2_step(struct bdf2 *b, double t, double h, const double *y, double *y_out,
    struct contacts *ct);

/* After the exact check: the free nodes' velocities scaled so that the
 * system's energy is the step's budget (bdf2.c energy_budget): its start,
 * the work of the held nodes' motion, of the contacts and the damping, and
 * what the check took away. BDF2's own damping is given back, and no step
 * ends with more than its budget. */
void bdf2_correct_energy(struct bdf2 *b, double *y1);

/* The step's contacts with analytic obstacles as events of col (the
 * pairs' are contacts_events'), at the step's end state y1; and marks the
 * pairs that pushed active. 0, or -1 out of memory. */
int bdf2_events(struct bdf2 *b, struct collide *col, long step, const double *y1);

/* After the step of h is committed: the history of the next one is y0,
 * the state the step started from, made anew along the contacts' normals
 * and wholly for the nodes in moved (the exact check's corrections; may be
 * NULL), then taken h_next back from y1 (bdf2.c respace_history) when
 * the next step is to be another length. */
void bdf2_commit(struct bdf2 *b, double h, const double *y0, const double *y1,
    const unsigned char *moved, double h_next);

/* The history for a restored state: hist (6n), h_hist back from it, or
 * NULL for none. */
void bdf2_set_history(struct bdf2 *b, const double *hist, double h_hist);

#endif
