/* pbd.h: the fast path's step (integrator = fast): substeps of position-
 * based dynamics with the yarns' stretch solved exactly along each yarn.
 *
 * At a step of a frame the cloth's stretch springs are a thousand times
 * stiffer than its inertia (h*omega of about 80 on cotton jersey), and
 * every solver whose cost per iteration is a few force evaluations needs
 * tens of iterations a step to resolve that (implicit Euler's CG: over a
 * hundred at 10 ms with block Jacobi, 15-40 preconditioned along lines):
 * the stiff springs couple the whole network, the soft forces do not.
 * So the two are split, after Macklin et al. 2019 ("small steps"):
 *   - the step is cut into substeps short enough for bending, the one
 *     stiffness taken explicitly (with a dashpot on each hinge's
 *     curvature rate that damps its modes near the substep's scale,
 *     pbd.c BEND_DAMPING), with gravity, loads and damping,
 *     v += h_s F/m, x* = x + h_s v, and for the sideways swing of taut
 *     yarns (their tension's geometric stiffness, which the line solves
 *     below follow only from substep to substep): pbd.c tension_omega2;
 *   - the stretch springs are compliant constraints (XPBD, Macklin et al.
 *     2016: C = |x_b - x_a| - l, compliance 1/k, which is backward Euler
 *     of the spring energy), and instead of Gauss-Seidel over springs,
 *     whose stiffness collapses to m/h_s^2 on a chain of nodes, each warp
 *     line and then each weft line is solved at once: along a line the
 *     system in the springs' multipliers is tridiagonal (consecutive
 *     springs share a node), so one Thomas pass solves it exactly; across
 *     lines the springs meet at right angles at rest and the coupling is
 *     the shear angle's cosine, left to the alternation of the two
 *     families (one each a substep);
 *   - the shear corners are compliant constraints too, one Gauss-Seidel
 *     sweep a substep in colour order, corners next to each other sharing
 *     no node (C = cos of the corner's angle, compliance 1/k):
 *     taken explicitly they set the substep, 8.6 times shorter than
 *     bending's on the shipped tablecloth;
 *   - held nodes follow their prescribed motion; nodes inside an analytic
 *     obstacle go back to its surface, with Coulomb friction;
 *   - v = (x - x_prev)/h_s.
 * Statics are the model's: at rest the explicit forces are the bending
 * energy's gradient and the constraint solves give each spring and corner
 * the force its compliance says. The substep is set by bending's highest
 * frequency and the yarns' tension, not by the springs' stiffness. The step's contacts
 * between parts of the cloth and with meshes are the collision stages'
 * (collide.h), after the step, from its start and end states. */
#ifndef DRAPE_PBD_H
#define DRAPE_PBD_H

#include <stdbool.h>

#include "forces.h"
#include "prescribed.h"
#include "scene.h"

struct pbd_lines {
	int nlines;
	int *start;		/* line l's springs are spring[start[l] .. start[l+1]) */
	int *spring;		/* in order along the line */
};

struct pbd {
	const struct scene *sc;
	const struct forces *fo;
	const struct prescribed *pr;
	double substep;		/* s, the largest */
	double omega_bend;	/* rad/s: the bending's own bound at rest */
	struct pbd_lines line[2];	/* warp, weft */
	double *w;		/* per node: 1/m, 0 when held */
	double *a, *xprev, *xs, *vs;	/* 3n scratch */
	double *diag, *off, *rhs, *dir;	/* per spring: the line system */
	double *row;		/* per node: the tension's stiffness (pbd.c) */
	size_t *corner_order;	/* the shear sweep's order (pbd.c order_corners) */
	/* per node, the step's last push out of an analytic obstacle: its
	 * index (-1 for none), the surface's nearest point and normal */
	int *touch;
	double *touch_at;	/* 6 a node: q, n */
	size_t *edge_near;	/* the edges near a box (pbd.c edges_out) */
	long substeps;		/* so far */
};

/* For a checked scene and its network; dt is the step. Returns 0, or -1
 * out of memory. */
int pbd_init(struct pbd *pb, const struct scene *sc, const struct forces *fo,
    const struct prescribed *pr, double dt);
void pbd_free(struct pbd *pb);

/* The longest substep for a scene: about half the explicit limit of its
 * bending's highest frequency, at most dt (a step may take shorter ones
 * for its yarns' tension). */
double pbd_substep(const struct forces *fo, double dt);

/* The most substeps one step takes, so that a step's work is bounded as
 * rk4's four evaluations are: stepper_new refuses a scene whose own
 * substep (pbd_substep) asks more, and a step whose yarns' tension asks
 * more takes this many (the blow-up check answers a runaway). The shipped
 * scenes take at most 70 (the cantilever). */
#define PBD_MAX_SUBSTEPS 10000

/* y (positions, velocities at t) to y_out at t + h; ct: the step's
 * contacts between parts of the cloth and with meshes (contacts_find),
 * held each substep, or NULL. Once the forces' stop flag is set
 * (forces_set_stop) it returns early, y_out unfinished. */
struct contacts;
struct collide;
void pbd_step(struct pbd *pb, double t, double h, const double *y, double *y_out,
    struct contacts *ct);

/* The step's contacts with analytic obstacles as events of col, one a node
 * that a substep pushed out of one (the last it did): at the surface's
 * point and normal of that push, with the node's velocity along the normal
 * at the step's start (y0) and end (y1). Substeps hold these contacts, so
 * that the collision stages never see them. 0, or -1 out of memory. */
int pbd_events(const struct pbd *pb, struct collide *col, long step, const double *y0,
    const double *y1);

#endif
