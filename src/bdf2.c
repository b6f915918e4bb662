/* bdf2.c: the implicit step (see bdf2.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bdf2.h"
#include "collide.h"
#include "contacts.h"
#include "grow.h"
#include "mg.h"
#include "obstacle.h"
#include "stop.h"
#include "vec3.h"

/* A penalty's stiffness over the inertia m / beta^2 of what it pushes: at
 * 1000 a node resting on an obstacle sinks g beta^2 / 1000, 0.04 um at a
 * 10 ms step, and the penalty is still a diagonal block the solve takes
 * as easily as the springs. A pair couples four nodes across the
 * cloth, which the preconditioner sees only in its diagonal blocks, so it
 * is softer: 100 gives a layer under the cloth's own weight a sag of
 * 0.4 um, a pile of ten layers 4 um, in a thickness of half a
 * millimetre. */
#define PENALTY_OBSTACLE 1000.0
#define PENALTY_PAIR 100.0

/* A contact the solve ran through is made this much stiffer, up to this
 * many times the stiffest spring (stiffen_overrun). */
#define OVERRUN_STIFFEN 10.0
#define OVERRUN_MOST 100.0

/* A node's clearance over an analytic obstacle, in cloth thicknesses: its
 * penalty holds it this far out, so that the step ends outside. */
#define OBSTACLE_CLEARANCE 0.25

/* A box's edge contact holds the cloth edge's point this part of the
 * nodes' clearance out: half, so that an edge lying along a face, its
 * nodes at the clearance, is never held by it, whatever the roundings
 * (pbd.c's EDGE_CLEARANCE likewise). */
#define EDGE_CLEARANCE 0.5

/* Friction's smoothing (IPC's epsilon_v): below this slip speed (m/s) a
 * contact holds like a stiff spring instead of sliding. */
#define FRICTION_SLIP 1e-3

/* Newton's iterations are also done when the largest residual
 * acceleration left is this part of gravity's (of 1 m/s^2 without
 * gravity): it changes a velocity by beta times it. */
#define RESIDUAL_TOL 1e-3

/* Newton's iterations have converged once the step they ask changes no
 * node's velocity by more than this (m/s; it moves the node that times
 * beta), and that last step is taken; the residual's own tolerance is in
 * accelerations, which a stiff contact's penalty makes large for a
 * displacement of nanometres. Where the cloth buckles (compressed
 * springs, sheared corners) the system's positive stand-in for the
 * stiffness makes the convergence linear, at 0.5 to 0.9 an iteration. */
#define NEWTON_VTOL 1e-4
/* ... or than this part of the largest motion of the step, when the scene
 * sets no tolerance: where a cloth crumples on impact the iterations'
 * linear tail would otherwise take twice as many (peers' table at 25^2,
 * first 0.35 s: 9.8 a step, 1.0e10 instructions; 1.7e10 at 1e-3, 8.9e9
 * at 3e-2, 5.1e9 at 0.1) for corrections of a hundredth of what the step
 * moved. */
#define NEWTON_REL 1e-2

/* ... or once an iteration lowers Phi by at most this part of what the
 * step's iterations have lowered it by: where the cloth buckles (the
 * tail above) the last iterations move a few nodes along folds that cost
 * next to nothing, 0.4 mm an iteration for a millionth of the step's
 * decrease, while the cloth's motion is settled. Tablecloth 8.1 to 6.0
 * iterations a step, peers' table at 25^2 6.5 to 3.8 (first 0.25 s),
 * and each of issue 28's targets as it was (bench/bdf2.sh parts 3-5:
 * the hanging strip 103 % of RK4's energy, the pile 4.7x RK4's, the
 * Cusick drape 0.3083 where it was 0.3110, on the disc cut of then); at
 * 3e-3 the hanging strip keeps 22 %, at 1e-2 the frictionless tablecloth
 * stays on its box. A scene's tolerance turns it off. */
#define NEWTON_DECREASE 1e-3
/* ... or by this part, where a contact pushes at the iterate. There the
 * tail is a landing cloth crumpling against what stopped it, millimetres
 * an iteration for a thousandth of the step's decrease; free motion keeps
 * the tighter stop, its energy being what the step must keep (at 3e-3 for
 * every step the hanging strip kept 22 % of RK4's). Over nine scenes 47.3
 * -> 35.2 Newton iterations a step, every accuracy target as before
 * (bench-history.md, bdf2.sh, 2026-12-07). */
#define NEWTON_DECREASE_CONTACT 1e-2
/* ... and there only once the last step asked no node to change its
 * velocity by more than this (m/s; its move over beta): where contacts
 * switch on and off from one iterate to the next (a cloth crumpling as it
 * lands) an iteration may lower Phi by little while Newton's step still
 * moves a node millimetres. Stopped there, the step left the worst node's
 * velocity 0.098 m/s from the converged step's (median over the steps of
 * the peers' 25^2 table from 0.2001 m; 0.51 at the 90th percentile, 1.3
 * at most), 0.43 m/s at 50^2 as it lands: kicks that kept a pile
 * jittering at 0.2 to 0.8 m/s and the cloth heaped against the cube where
 * RK4's and the converged step's lie on the floor. At 0.02 the
 * errors left are 0.0025 m/s (median; 0.03 at the 90th percentile).
 * bench-history.md, bdf2.sh, 2026-12-07 (stop 46). */
#define NEWTON_VSTOP 0.02

/* The energy correction scales the free nodes' velocities by at most this
 * a step. BDF2 takes most of what it takes in a few steps, as the hanging
 * strip's end starts and stops: at 1.5 the strip keeps 49 % of RK4's
 * energy above rest at 1 s, at 2 and 3 54 %; a step that asks for more
 * than doubling the speeds is the budget's error. */
#define ENERGY_SCALE_MOST 2.0

/* The solve goes on at most this many times with the contacts it found
 * late (late_obstacle_contacts). */
#define LATE_PASSES 3

/* The pairs within this many thicknesses of pushing are kept near (at
 * least; need_near). */
#define NEAR_REACH 2.0

/* A line search may go this far past the Newton step (extrapolate). */
#define EXTRAPOLATE_MOST 4.0

/*
 * A conjugate gradients solve stops when its residual has fallen by the
 * forcing term eta of inexact Newton (Eisenstat and Walker, "Choosing the
 * forcing terms in an inexact Newton method", SIAM J. Sci. Comput. 17(1),
 * 1996, their choice 1): how far the last iteration's linear model missed
 * the gradient it led to, |g_k| - |g_k-1 + H dx_k-1|, over |g_k-1|, kept
 * between CG_REDUCTION_TIGHT and CG_REDUCTION_LOOSE. Where Phi is near its
 * quadratic (a free fall, a cloth swinging) the model holds and the solve
 * is tight; where it does not (the system's stand-in for a buckling
 * cloth's stiffness, jacobian.h; contacts switching on and off; the
 * self-contact pairs, which the multigrid holds only on its diagonal and
 * which make a tight solve dear, 30 iterations with 1000 pairs pushing) a
 * tight solve is waste the next iteration throws away. A step's first
 * solve has no model yet: loose when a contact pushes at the step's start,
 * tight when none does (loose there, a free fall's first solves leave the
 * cloth shearing: 1e-6 J in a 6 x 6 cloth's 0.5 s fall, 18 mm off the
 * parabola). Over sixteen scenes (doc/bench-history.md, 2026-12-05) user
 * CPU 53.7 s at 1e-2 throughout, 38.6 at 0.1 throughout, 39.6 so.
 */
#define CG_REDUCTION_TIGHT 1e-2
#define CG_REDUCTION_LOOSE 1e-1

/* Whether an obstacle contact at distance d has its penalty in the
 * system: within the clearance, or on it as stop_at_planes leaves a node
 * (to its roundings). Such a node is not stopped again: the penalty may
 * hold it inside (the peers' table at 50^2: a node on a plane stopped at
 * it 25 iterations running, its step into it the same 0.435 mm). */
static bool
penalised(double d, double clear)
{
	return d <= clear * (1 + 1e-9);
}

/* The same for a box's edge contact, a little farther out: the search
 * stops an edge on the plane of its nearest point (stop_at_planes), and
 * the box's rounded edge curves away behind that plane, so that the edge
 * ends clear of its clearance by the curve's sag (0.1 um on the peers'
 * table at 25^2), not in the system again, and stopped again: 6 steps
 * unconverged running there, Newton's same step each iteration. */
#define EDGE_ON 0.05

static bool
edge_penalised(double d, double clear)
{
	return d <= clear * (1 + EDGE_ON);
}

static double
norm3(const double *a)
{
	return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

int
bdf2_init(struct bdf2 *b, const struct scene *sc, const struct forces *fo,
    const struct prescribed *pr, double tol)
{
	const struct cloth *cl = fo->cl;
	size_t n3 = 3 * (size_t)cl->n;
	double **v3s[] = { &b->xhat, &b->vhat, &b->target, &b->x, &b->g, &b->dx, &b->xtry, &b->f,
	    &b->r, &b->z, &b->p, &b->q };
	double gmag = v3_len(v3_load(sc->gravity));
	size_t i;

	memset(b, 0, sizeof *b);
	b->sc = sc;
	b->fo = fo;
	b->pr = pr;
	b->tol = RESIDUAL_TOL * (gmag > 0 ? gmag : 1);
	b->rel = tol > 0 ? tol : NEWTON_REL;
	b->decrease = tol > 0 ? 0 : NEWTON_DECREASE;
	b->decrease_contact = tol > 0 ? 0 : NEWTON_DECREASE_CONTACT;
	b->max_newton = 40;
	b->mg_step = -1;
	b->mg_cg = -1;
	b->max_cg = 400;
	for (i = 0; i < cl->nsprings; i++)
		b->kmax = cl->springs[i].k > b->kmax ? cl->springs[i].k : b->kmax;
	if (jacobian_init(&b->jc, fo) != 0 || blockmat_init_cloth(&b->H, cl) != 0 ||
	    mg_init(&b->mg, cl) != 0)
		goto oom;
	for (i = 0; i < sizeof v3s / sizeof v3s[0]; i++)
		if ((*v3s[i] = malloc((n3 + 1) * sizeof(double))) == NULL)
			goto oom;
	if ((b->hist = malloc((2 * n3 + 1) * sizeof *b->hist)) == NULL ||
	    (b->pre = malloc((3 * n3 + 1) * sizeof *b->pre)) == NULL ||
	    (b->rdir = malloc((3 * n3 + 1) * sizeof *b->rdir)) == NULL ||
	    (b->nreset = calloc((size_t)cl->n + 1, 1)) == NULL ||
	    (b->emark = calloc(cl->nedges + 1, 1)) == NULL ||
	    (b->udamp = malloc((3 * cl->nsprings + 1) * sizeof *b->udamp)) == NULL)
		goto oom;
	return 0;
oom:
	bdf2_free(b);
	return -1;
}

void
bdf2_free(struct bdf2 *b)
{
	double *v[] = { b->xhat, b->vhat, b->target, b->x, b->g, b->dx, b->xtry, b->f, b->r, b->z,
	    b->p, b->q, b->hist, b->pre, b->rdir, b->udamp };
	size_t i;

	jacobian_free(&b->jc);
	blockmat_free(&b->H);
	mg_free(&b->mg);
	for (i = 0; i < sizeof v / sizeof v[0]; i++)
		free(v[i]);
	free(b->nreset);
	free(b->oc);
	free(b->ec);
	free(b->emark);
	free(b->pt);
	free(b->act);
	free(b->live);
	free(b->near);
	memset(b, 0, sizeof *b);
}

void
bdf2_set_stop(struct bdf2 *b, const volatile sig_atomic_t *flag)
{
	b->stop = flag;
}

static bool
held(const struct bdf2 *b, int p)
{
	return b->pr->held != NULL && b->pr->held[p];
}

/* Two unit vectors across n. */
static void
tangents(vec3 n, double *t)
{
	vec3 a = fabs(n.x) < 0.6 ? v3(1, 0, 0) : v3(0, 1, 0), t1, t2;

	t1 = v3_madd(a, n, -v3_dot(a, n));
	t1 = v3_scale(t1, 1 / v3_len(t1));
	t2 = v3_cross(n, t1);
	v3_store(t, t1);
	v3_store(t + 3, t2);
}

/* ---- the step's setup ---- */

/* A history for a state that has none (a run's start, a state restored
 * without it): the state one step back on the parabola through it with
 * its present acceleration from the forces, x - h v + h^2 a / 2 and
 * v - h a. BDF2 is exact on such a motion (free fall to rounding) where
 * backward Euler, the usual first step, leaves the cloth g h^2 / 2 low. */
static void
start_history(struct bdf2 *b, double h, const double *y)
{
	const struct cloth *cl = b->fo->cl;
	size_t n3 = 3 * (size_t)cl->n, i;

	forces_accel(b->fo, b->t1 - h, y, y + n3, b->hist + n3);
	for (i = 0; i < n3; i++) {
		double a = b->hist[n3 + i];

		b->hist[i] = y[i] - h * y[n3 + i] + 0.5 * h * h * a;
		b->hist[n3 + i] = y[n3 + i] - h * a;
	}
	b->has_hist = true;
	b->h_hist = h;
}

/*
 * The history taken h back from the state y instead of b->h_hist, for a
 * step of another length: positions on the parabola through the state
 * with its velocity and the history's position, velocities on the line
 * through the two velocities. BDF2's formula then keeps its constant
 * coefficients (Nordsieck's way of changing the step of a multistep
 * method, by interpolating its history, rather than the variable-step
 * formula's coefficients): what a keyframe holds stays the state one
 * step back, whatever the steps were.
 */
static void
respace_history(struct bdf2 *b, double h, const double *y)
{
	size_t n3 = 3 * (size_t)b->fo->cl->n, i;
	double r = h / b->h_hist;

	for (i = 0; i < n3; i++) {
		double x = y[i], v = y[n3 + i], xo = b->hist[i], vo = b->hist[n3 + i];

		b->hist[i] = x - h * v + r * r * (xo - x + b->h_hist * v);
		b->hist[n3 + i] = v + r * (vo - v);
	}
	b->h_hist = h;
}

/* The formula's terms: beta, xhat, vhat and the inertial target xhat +
 * beta vhat. */
static void
set_formula(struct bdf2 *b, double h, const double *y)
{
	size_t n3 = 3 * (size_t)b->fo->cl->n, i;
	const double *xp = b->hist, *vp = b->hist + n3;

	if (!b->has_hist)
		start_history(b, h, y);
	else if (h != b->h_hist)
		respace_history(b, h, y);
	b->beta = b->has_hist ? 2 * h / 3 : h;
	for (i = 0; i < n3; i++) {
		if (b->has_hist) {
			b->xhat[i] = (4 * y[i] - xp[i]) / 3;
			b->vhat[i] = (4 * y[n3 + i] - vp[i]) / 3;
		} else {
			b->xhat[i] = y[i];
			b->vhat[i] = y[n3 + i];
		}
		b->target[i] = b->xhat[i] + b->beta * b->vhat[i];
	}
}

static int
add_obstacle_contact(struct bdf2 *b, const struct bdf2_obstacle_contact *c)
{
	if (grow_array((void **)&b->oc, &b->occap, b->noc + 1, sizeof *b->oc) != 0)
		return -1;
	b->oc[b->noc++] = *c;
	return 0;
}

/* A contact of node p with obstacle o, on the plane of the solid's
 * nearest point to x0 (the step's start). */
static int
add_plane(struct bdf2 *b, int p, size_t o, const double *x0)
{
	const struct obstacle *ob = &b->sc->obstacles[o];
	struct bdf2_obstacle_contact c;
	vec3 q, n;

	obstacle_distance(ob, v3_load(x0 + 3 * p), &q, &n);
	memset(&c, 0, sizeof c);
	c.node = p;
	c.obstacle = (int)o;
	/* the plane through the nearest point, across the line to it: the
	 * solid is convex, so all of it lies behind */
	v3_store(c.n, n);
	v3_store(c.q, q);
	c.k = PENALTY_OBSTACLE * b->fo->cl->mass[p] / (b->beta * b->beta);
	c.mu = ob->friction;
	tangents(n, c.tan);
	return add_obstacle_contact(b, &c);
}

/* The nodes within reach of an analytic obstacle over the step: nearer
 * at its start than the clearance and a thickness, with twice the motion
 * the target asks for. Their surface's tangents there are friction's. */
static int
find_obstacle_contacts(struct bdf2 *b, const double *x0)
{
	const struct scene *sc = b->sc;
	const struct cloth *cl = b->fo->cl;
	double clear = OBSTACLE_CLEARANCE * sc->mat.thickness;
	size_t o;
	int p;

	b->noc = 0;
	for (o = 0; o < sc->nobstacles; o++) {
		const struct obstacle *ob = &sc->obstacles[o];
		vec3 lo, hi;

		if (ob->kind == OBSTACLE_MESH)
			continue;
		obstacle_bounds(ob, &lo, &hi);
		for (p = 0; p < cl->n; p++) {
			vec3 xp = v3_load(x0 + 3 * p);
			double move = v3_len(v3_sub(v3_load(b->target + 3 * p), xp));
			double reach = clear + sc->mat.thickness + 2 * move;

			if (held(b, p) || xp.x < lo.x - reach || xp.y < lo.y - reach ||
			    xp.z < lo.z - reach || xp.x > hi.x + reach || xp.y > hi.y + reach ||
			    xp.z > hi.z + reach)
				continue;
			if (obstacle_distance(ob, xp, NULL, NULL) >= reach)
				continue;
			if (add_plane(b, p, o, x0) != 0)
				return -1;
		}
	}
	return 0;
}

/*
 * The nodes the solve took nearer an analytic obstacle than its clearance
 * without a contact with it: the motion the step's start predicted missed
 * them (a node sent sideways by its springs into a box's side). Each gets
 * its plane, and the solve goes on; without this the exact check pushed
 * them out afterwards, folding hinges right back (the undamped tablecloth
 * at 0.53 s: 2.6 J of bending for a step). Returns the contacts added, or
 * -1 out of memory.
 */
static int
late_obstacle_contacts(struct bdf2 *b, const double *x0, const double *x)
{
	const struct scene *sc = b->sc;
	const struct cloth *cl = b->fo->cl;
	double clear = OBSTACLE_CLEARANCE * sc->mat.thickness;
	size_t o, i, before = b->noc;
	int p;

	for (o = 0; o < sc->nobstacles; o++) {
		const struct obstacle *ob = &sc->obstacles[o];
		vec3 lo, hi;

		if (ob->kind == OBSTACLE_MESH)
			continue;
		obstacle_bounds(ob, &lo, &hi);
		memset(b->nreset, 0, (size_t)cl->n);	/* as a mark: has one */
		for (i = 0; i < before; i++)
			if (b->oc[i].obstacle == (int)o)
				b->nreset[b->oc[i].node] = 1;
		for (p = 0; p < cl->n; p++) {
			vec3 xp = v3_load(x + 3 * p);

			if (held(b, p) || b->nreset[p] || xp.x < lo.x - clear || xp.y < lo.y - clear ||
			    xp.z < lo.z - clear || xp.x > hi.x + clear || xp.y > hi.y + clear ||
			    xp.z > hi.z + clear || obstacle_distance(ob, xp, NULL, NULL) >= clear)
				continue;
			if (add_plane(b, p, o, x0) != 0)
				return -1;
		}
	}
	memset(b->nreset, 0, (size_t)cl->n);
	return (int)(b->noc - before);
}

/*
 * A cloth edge over a box's edge can cut its corner with both its nodes
 * held out by their own contacts: on the tablecloth 73 edges went up to
 * 3.4 mm into the box (drape check), in a cloth 0.55 mm thick. So an edge
 * near a box whose nearest point to it lies between its nodes gets a
 * contact of its own: a penalty k (c - D(x))^2 / 2 on its least distance
 * D to the box, at c = EDGE_CLEARANCE of the nodes' clearance, its force
 * shared by the weights of that point (Bridson, Fedkiw and Anderson 2002,
 * sec. 7.1, as contacts.h's edge pairs). No friction on it: the nodes'
 * own contacts hold the cloth (pbd.c found Coulomb's cut on the edge's
 * point threw the cloth off). Only boxes: their edges are where a
 * straight segment between two nodes outside goes in.
 */
static double
edge_clearance(const struct bdf2 *b)
{
	return EDGE_CLEARANCE * OBSTACLE_CLEARANCE * b->sc->mat.thickness;
}

/*
 * The edge's least distance to its box at x, D(x) = min over t of the
 * distance of (1 - t) x_a + t x_b, with its t, and the box's normal and
 * nearest point there (each may be NULL). At the least the distance does
 * not change with t, so D's gradient is the normal times the weights
 * 1 - t and t (the envelope theorem): the point follows the box's edge as
 * the cloth slides over it. A plane fixed at the step's start, as the
 * nodes have, held the sliding cloth up on its tangent beyond the box's
 * edge (the peers' cloth at 25^2 stopped on the cube's edge:
 * doc/bench-history.md, bdf2.sh, 2026-12-05).
 */
static double
edge_gap(const struct bdf2 *b, const struct bdf2_edge_contact *c, const double *x, double *tp,
    vec3 *n, vec3 *q)
{
	struct obstacle in = b->sc->obstacles[c->obstacle];
	vec3 xa = v3_load(x + 3 * c->a), xb = v3_load(x + 3 * c->b), nn, qq;
	double r = edge_clearance(b), t, d;

	/* the box rounded by r: its distance is smooth a depth r into it,
	 * where the nearest face of a point inside jumps from one side of an
	 * edge to the other (Newton then went round a cloth edge pulled into
	 * the peers' cube's corner, never converging); outside, the rounded
	 * box is the farther, so D >= c keeps the edge out of the box */
	if (in.hi.x - in.lo.x > 2 * r && in.hi.y - in.lo.y > 2 * r && in.hi.z - in.lo.z > 2 * r) {
		in.lo = v3_add(in.lo, v3(r, r, r));
		in.hi = v3_sub(in.hi, v3(r, r, r));
	} else {
		r = 0;
	}
	obstacle_segment_nearest(&in, xa, xb, &t);
	d = obstacle_distance(&in, v3_madd(xa, v3_sub(xb, xa), t), &qq, &nn);
	if (tp != NULL)
		*tp = t;
	if (n != NULL)
		*n = nn;
	if (q != NULL)
		*q = v3_madd(qq, nn, r);
	return d - r;
}

/* edge_gap at x, kept in the contact (its weights, normal, point and
 * distance). */
static double
edge_update(const struct bdf2 *b, struct bdf2_edge_contact *c, const double *x)
{
	double t;
	vec3 n, q;

	c->phi = edge_gap(b, c, x, &t, &n, &q);
	c->wa = 1 - t;
	c->wb = t;
	v3_store(c->n, n);
	v3_store(c->q, q);
	return c->phi;
}

/* Whether segment a-c lies wholly beyond one face of box [lo, hi]. */
static bool
beyond_a_face(vec3 a, vec3 c, vec3 lo, vec3 hi)
{
	return (a.x < lo.x && c.x < lo.x) || (a.y < lo.y && c.y < lo.y) ||
	    (a.z < lo.z && c.z < lo.z) || (a.x > hi.x && c.x > hi.x) ||
	    (a.y > hi.y && c.y > hi.y) || (a.z > hi.z && c.z > hi.z);
}

/* The cloth's edges in b->emark that have a contact with obstacle o. */
static void
mark_edges(struct bdf2 *b, size_t o)
{
	size_t i;

	memset(b->emark, 0, b->fo->cl->nedges);
	for (i = 0; i < b->nec; i++)
		if (b->ec[i].obstacle == (int)o)
			b->emark[b->ec[i].edge] = 1;
}

/* A contact of cloth edge e with box o, as it is at x. */
static int
add_edge(struct bdf2 *b, size_t e, size_t o, const double *x)
{
	const struct cloth *cl = b->fo->cl;
	struct bdf2_edge_contact *c;

	if (grow_array((void **)&b->ec, &b->eccap, b->nec + 1, sizeof *b->ec) != 0)
		return -1;
	c = &b->ec[b->nec++];
	memset(c, 0, sizeof *c);
	c->edge = (int)e;
	c->a = cl->edge[2 * e];
	c->b = cl->edge[2 * e + 1];
	c->obstacle = (int)o;
	edge_update(b, c, x);
	/* as a node's, by the edge's mass at the point */
	c->k = PENALTY_OBSTACLE * (c->wa * cl->mass[c->a] + c->wb * cl->mass[c->b]) /
	    (b->beta * b->beta);
	c->ab = blockmat_find(&b->H, c->a, c->b);
	c->ba = blockmat_find(&b->H, c->b, c->a);
	return 0;
}

/*
 * The cloth edges that come within `reach` of a box at x between their
 * nodes (at the step's start, with their nodes' motion to the target
 * and a thickness more), and that have no contact with it yet: each gets
 * one. Returns how many, or -1 out of memory.
 */
static int
edge_contacts_at(struct bdf2 *b, const double *x, bool start, double reach)
{
	const struct scene *sc = b->sc;
	const struct cloth *cl = b->fo->cl;
	size_t o, e, before = b->nec;

	for (o = 0; o < sc->nobstacles; o++) {
		const struct obstacle *ob = &sc->obstacles[o];

		if (ob->kind != OBSTACLE_BOX)
			continue;
		mark_edges(b, o);
		for (e = 0; e < cl->nedges; e++) {
			int pa = cl->edge[2 * e], pb = cl->edge[2 * e + 1];
			vec3 a = v3_load(x + 3 * pa), c = v3_load(x + 3 * pb), n, lo, hi;
			double r = reach, t = 0;

			if (b->emark[e] || (held(b, pa) && held(b, pb)))
				continue;
			if (start)
				r += sc->mat.thickness + 2 * fmax(
				    v3_len(v3_sub(v3_load(b->target + 3 * pa), a)),
				    v3_len(v3_sub(v3_load(b->target + 3 * pb), c)));
			lo = v3_sub(ob->lo, v3(r, r, r));
			hi = v3_add(ob->hi, v3(r, r, r));
			/* the bounds, then the box's depth (exact and cheap, no
			 * more than the distance), then the nearest point */
			if (beyond_a_face(a, c, lo, hi) ||
			    !(obstacle_box_segment_depth(lo, hi, a, c, &t, &n) > 0) ||
			    obstacle_segment_nearest(ob, a, c, &t) >= r || t <= 0 || t >= 1)
				continue;
			if (add_edge(b, e, o, x) != 0)
				return -1;
		}
	}
	return (int)(b->nec - before);
}

/* The edges within reach of a box over the step, from its start. */
static int
find_edge_contacts(struct bdf2 *b, const double *x0)
{
	b->nec = 0;
	return edge_contacts_at(b, x0, true, edge_clearance(b)) < 0 ? -1 : 0;
}

/* The edges the solve took within their clearance of a box without a
 * contact: their motion at the step's start missed them. Returns how
 * many, or -1 out of memory. */
static int
late_edge_contacts(struct bdf2 *b, const double *x)
{
	return edge_contacts_at(b, x, false, edge_clearance(b));
}

/* Whether edge c at x comes within `clear` of its box's bounds. */
static bool
near_box(const struct bdf2 *b, const struct bdf2_edge_contact *c, const double *x, double clear)
{
	const struct obstacle *ob = &b->sc->obstacles[c->obstacle];

	return !beyond_a_face(v3_load(x + 3 * c->a), v3_load(x + 3 * c->b),
	    v3_sub(ob->lo, v3(clear, clear, clear)), v3_add(ob->hi, v3(clear, clear, clear)));
}

/* The box's edge contacts' penalties at x. */
static double
edge_terms(const struct bdf2 *b, const double *x, double *g)
{
	double clear = edge_clearance(b), e = 0;
	size_t i;

	for (i = 0; i < b->nec; i++) {
		const struct bdf2_edge_contact *c = &b->ec[i];
		double t, d;
		vec3 f, n;

		/* the box's bounds, grown by the clearance, first: most edges
		 * are clear of them, and the search costs some 50 distances */
		if (!near_box(b, c, x, clear) || !((d = edge_gap(b, c, x, &t, &n, NULL)) < clear))
			continue;
		e += 0.5 * c->k * (clear - d) * (clear - d);
		if (g == NULL)
			continue;
		f = v3_scale(n, -c->k * (clear - d));
		v3_addto(g + 3 * c->a, v3_scale(f, 1 - t));
		v3_addto(g + 3 * c->b, v3_scale(f, t));
	}
	return e;
}


/* The pairs' terms: a penalty stiffness by the pair's mass and tangents
 * of its plane. */
static int
set_pairs(struct bdf2 *b)
{
	const struct cloth *cl = b->fo->cl;
	size_t i;

	if (b->ct == NULL)
		return 0;
	if (b->ct->n > b->ptcap) {
		struct bdf2_pair_term *p = realloc(b->pt, b->ct->n * sizeof *p);
		size_t *a, *l;

		if (p == NULL)
			return -1;
		b->pt = p;
		if ((a = realloc(b->act, b->ct->n * sizeof *a)) == NULL)
			return -1;
		b->act = a;
		if ((l = realloc(b->live, b->ct->n * sizeof *l)) == NULL)
			return -1;
		b->live = l;
		if ((l = realloc(b->near, b->ct->n * sizeof *l)) == NULL)
			return -1;
		b->near = l;
		b->ptcap = b->ct->n;
	}
	for (i = 0; i < b->ct->n; i++) {
		const struct contact_pair *cp = &b->ct->pair[i];
		double inv = 0;
		int k;

		for (k = 0; k < 4; k++)
			if (cp->vert[k] < b->ct->ncloth && !held(b, cp->vert[k]))
				inv += cp->w[k] * cp->w[k] / cl->mass[cp->vert[k]];
		memset(&b->pt[i], 0, sizeof b->pt[i]);
		b->pt[i].k = inv > 0 ? PENALTY_PAIR / (inv * b->beta * b->beta) : 0;
		tangents(v3_load(cp->n0), b->pt[i].tan);
	}
	return 0;
}

/* ---- the potential ---- */

/* Where vertex v of the pairs' geometry is: a cloth node's in x, a
 * mesh's where contacts_find saw it (they never move). */
static vec3
vertex(const struct bdf2 *b, const double *x, int v)
{
	return v3_load(v < b->ct->ncloth ? x + 3 * v : b->ct->xmesh + 3 * v);
}

/* A pair's separation sum w x along n0, and its relative motion over the
 * step sum w (x - x0). */
static double
pair_gap(const struct bdf2 *b, const struct contact_pair *cp, const double *x, const double *x0,
    vec3 *rel)
{
	vec3 n = v3_load(cp->n0), s = v3(0, 0, 0), m = v3(0, 0, 0);
	int k;

	for (k = 0; k < 4; k++) {
		vec3 p = vertex(b, x, cp->vert[k]);

		s = v3_madd(s, p, cp->w[k]);
		if (cp->vert[k] < b->ct->ncloth)
			m = v3_madd(m, v3_sub(p, v3_load(x0 + 3 * cp->vert[k])), cp->w[k]);
	}
	if (rel != NULL)
		*rel = m;
	return v3_dot(s, n);
}

/* IPC's f0 (the smoothed |u|) and f1(s)/s, for a slip s over eps. */
static double
friction_f0(double s, double eps)
{
	return s >= eps ? s : -s * s * s / (3 * eps * eps) + s * s / eps + eps / 3;
}

static double
friction_f1_over_s(double s, double eps)
{
	return s >= eps ? 1 / s : -s / (eps * eps) + 2 / eps;
}

/* An obstacle contact's distance at x, from the plane of its surface at
 * the step's start. */
static double
plane_distance(const struct bdf2_obstacle_contact *c, const double *x)
{
	return v3_dot(v3_sub(v3_load(x + 3 * c->node), v3_load(c->q)), v3_load(c->n));
}

/*
 * The pairs near enough to matter. A step's pairs are those that may come
 * within reach over it (contacts.h), tens of thousands on a crumpled
 * cloth, most never pushing: their gaps were 18 % of a 100^2 cloth's
 * time, taken at every iterate. A pair's gap sum w x . n0 changes by at
 * most twice the farthest any node has moved (the |w| sum to 2), so the
 * pairs whose gap at some iterate was over the thickness by more than
 * `reach` stay out of reach while the nodes have drifted less than half
 * of it since: near_pairs lists the others, and need_near makes the list
 * anew when the drift since leaves less than `want` of it.
 */
static void
near_pairs(struct bdf2 *b, const double *x, double reach)
{
	size_t i;

	b->nnear = 0;
	for (i = 0; i < b->ct->n; i++) {
		double gap = pair_gap(b, &b->ct->pair[i], x, b->x0, NULL);

		b->pt[i].gap = gap;
		if (gap < b->ct->thickness + reach)
			b->near[b->nnear++] = i;
	}
	b->near_reach = reach;
	b->drift = 0;
	b->near_ok = true;
}

static void
need_near(struct bdf2 *b, const double *x, double want)
{
	if (!b->near_ok || b->near_reach - 2 * b->drift < want)
		near_pairs(b, x, fmax(NEAR_REACH * b->ct->thickness, 2 * want));
}

/* The normal forces of the iterate x, which friction takes as given
 * (lagged) while the line search looks along a direction. */
static void
lag_normal_forces(struct bdf2 *b, const double *x)
{
	const struct scene *sc = b->sc;
	double clear = OBSTACLE_CLEARANCE * sc->mat.thickness;
	size_t i, j;

	for (i = 0; i < b->noc; i++) {
		struct bdf2_obstacle_contact *c = &b->oc[i];
		double d = plane_distance(c, x);

		c->lambda = d < clear ? c->k * (clear - d) : 0;
	}
	b->nlive = b->nact = 0;
	if (b->ct == NULL)
		return;
	need_near(b, x, 0);
	for (j = 0; j < b->nnear; j++) {
		size_t q = b->near[j];
		double gap = pair_gap(b, &b->ct->pair[q], x, b->x0, NULL);

		b->pt[q].gap = gap;
		b->pt[q].lambda = gap < b->ct->thickness ? b->pt[q].k * (b->ct->thickness - gap) : 0;
		if (gap < b->ct->thickness)
			b->act[b->nact++] = q;
	}
	/* at x itself, only the pairs that push have terms */
	memcpy(b->live, b->act, b->nact * sizeof *b->live);
	b->nlive = b->nact;
}

/* The dashpots (spring_damping): each spring's relative velocity along its
 * direction at the step's start, (x - xhat)/beta for v, a quadratic in x
 * whose gradient is the dashpot force C v. */
static double
dashpots(const struct bdf2 *b, const double *x, double *g)
{
	const struct cloth *cl = b->fo->cl;
	double c = b->fo->spring_damping / b->beta, e = 0;
	size_t s;

	if (!(b->fo->spring_damping > 0))
		return 0;
	for (s = 0; s < cl->nsprings; s++) {
		const struct spring *sp = &cl->springs[s];
		vec3 u = v3_load(b->udamp + 3 * s);
		vec3 da = v3_sub(v3_load(x + 3 * sp->a), v3_load(b->xhat + 3 * sp->a));
		vec3 db = v3_sub(v3_load(x + 3 * sp->b), v3_load(b->xhat + 3 * sp->b));
		double rel = v3_dot(u, v3_sub(db, da)), k = c * sp->k;

		e += 0.5 * k * rel * rel;
		if (g != NULL) {
			v3_addto(g + 3 * sp->b, v3_scale(u, k * rel));
			v3_addto(g + 3 * sp->a, v3_scale(u, -k * rel));
		}
	}
	return e;
}

/* The analytic obstacles' penalties and friction at x. */
static double
obstacle_terms(struct bdf2 *b, const double *x, double *g)
{
	const struct scene *sc = b->sc;
	double clear = OBSTACLE_CLEARANCE * sc->mat.thickness, eps = FRICTION_SLIP * b->beta, e = 0;
	size_t i;

	for (i = 0; i < b->noc; i++) {
		struct bdf2_obstacle_contact *c = &b->oc[i];
		vec3 xp = v3_load(x + 3 * c->node), n = v3_load(c->n), du;
		double d = plane_distance(c, x);

		if (d < clear) {
			e += 0.5 * c->k * (clear - d) * (clear - d);
			if (g != NULL)
				v3_addto(g + 3 * c->node, v3_scale(n, -c->k * (clear - d)));
		}
		if (c->mu > 0 && c->lambda > 0) {
			double u0, u1, s, ml = c->mu * c->lambda;

			du = v3_sub(xp, v3_load(b->x0 + 3 * c->node));
			u0 = v3_dot(du, v3_load(c->tan));
			u1 = v3_dot(du, v3_load(c->tan + 3));
			s = sqrt(u0 * u0 + u1 * u1);
			e += ml * friction_f0(s, eps);
			if (g != NULL) {
				double f = ml * friction_f1_over_s(s, eps);

				v3_addto(g + 3 * c->node, v3_add(v3_scale(v3_load(c->tan), f * u0),
				    v3_scale(v3_load(c->tan + 3), f * u1)));
			}
		}
	}
	return e;
}

/* The live pairs' penalties and friction at x (b->live: those that can
 * push at x; the others have no terms there). */
static double
pair_terms(struct bdf2 *b, const double *x, double *g)
{
	double eps = FRICTION_SLIP * b->beta, e = 0;
	size_t j;

	if (b->ct == NULL)
		return 0;
	for (j = 0; j < b->nlive; j++) {
		size_t i = b->live[j];
		const struct contact_pair *cp = &b->ct->pair[i];
		struct bdf2_pair_term *pt = &b->pt[i];
		vec3 rel, n = v3_load(cp->n0), push = v3(0, 0, 0);
		double gap = pair_gap(b, cp, x, b->x0, &rel), u0, u1, s;
		int k;

		if (gap < b->ct->thickness) {
			double over = b->ct->thickness - gap;

			e += 0.5 * pt->k * over * over;
			push = v3_scale(n, -pt->k * over);
		}
		if (cp->mu > 0 && pt->lambda > 0) {
			double ml = cp->mu * pt->lambda, f;

			u0 = v3_dot(rel, v3_load(pt->tan));
			u1 = v3_dot(rel, v3_load(pt->tan + 3));
			s = sqrt(u0 * u0 + u1 * u1);
			e += ml * friction_f0(s, eps);
			f = ml * friction_f1_over_s(s, eps);
			push = v3_add(push, v3_add(v3_scale(v3_load(pt->tan), f * u0),
			    v3_scale(v3_load(pt->tan + 3), f * u1)));
		}
		if (g == NULL)
			continue;
		for (k = 0; k < 4; k++)
			if (cp->vert[k] < b->ct->ncloth)
				v3_addto(g + 3 * cp->vert[k], v3_scale(push, cp->w[k]));
	}
	return e;
}

/* Phi at x, and its gradient into g when g is not NULL (held nodes' parts
 * zero: they do not move in the solve). */
static double
potential(struct bdf2 *b, const double *x, double *g)
{
	const struct forces *fo = b->fo;
	const struct cloth *cl = fo->cl;
	double ib2 = 1 / (b->beta * b->beta), cd = fo->damping / b->beta, e;
	vec3 grav = v3_load(fo->g);
	int p, l, k;

	e = forces_elastic(fo, x, g);	/* g holds the elastic forces for now */
	if (g != NULL)
		for (p = 0; p < 3 * cl->n; p++)
			g[p] = -g[p];
	for (p = 0; p < cl->n; p++) {
		vec3 xp = v3_load(x + 3 * p), d = v3_sub(xp, v3_load(b->target + 3 * p));
		vec3 dh = v3_sub(xp, v3_load(b->xhat + 3 * p));
		double m = cl->mass[p];

		e += 0.5 * m * ib2 * v3_dot(d, d) + 0.5 * m * cd * v3_dot(dh, dh) -
		    m * v3_dot(grav, xp);
		if (g != NULL)
			v3_addto(g + 3 * p, v3_sub(v3_add(v3_scale(d, m * ib2), v3_scale(dh, m * cd)),
			    v3_scale(grav, m)));
	}
	for (l = 0; l < fo->nloads; l++) {
		const struct load_group *lg = &fo->loads[l];

		if (!load_active(lg, b->t1))
			continue;
		for (k = 0; k < lg->n; k++) {
			e -= v3_dot(v3_load(lg->f), v3_load(x + 3 * lg->node[k]));
			if (g != NULL)
				v3_addto(g + 3 * lg->node[k], v3_neg(v3_load(lg->f)));
		}
	}
	e += dashpots(b, x, g);
	e += obstacle_terms(b, x, g);
	e += edge_terms(b, x, g);
	e += pair_terms(b, x, g);
	if (g != NULL)
		for (p = 0; p < cl->n; p++)
			if (held(b, p))
				g[3 * p] = g[3 * p + 1] = g[3 * p + 2] = 0;
	return e;
}

/* ---- the Newton system ---- */

/* H's diagonal block of node p += s a b^T. */
static void
add_diag(struct bdf2 *b, int p, vec3 u, vec3 w, double s)
{
	double *blk = b->H.val + 9 * (size_t)b->H.diag[p], a[3] = { u.x, u.y, u.z };
	double c[3] = { w.x, w.y, w.z };
	int i, j;

	for (i = 0; i < 3; i++)
		for (j = 0; j < 3; j++)
			blk[3 * i + j] += s * a[i] * c[j];
}

/* Friction's stiffness across a contact at slip (u0, u1): mu lambda
 * f1(s)/s on the tangent plane, the positive semidefinite part of its
 * Hessian (IPC's). */
static double
friction_stiffness(double ml, double u0, double u1, double eps)
{
	return ml > 0 ? ml * friction_f1_over_s(sqrt(u0 * u0 + u1 * u1), eps) : 0;
}

/* The contacts' stiffness at the iterate x: the obstacles' blocks into H,
 * the pairs' kept by pair (their diagonal blocks into H too, for the
 * preconditioner; pair_mul adds the rest). */
static void
assemble_contacts(struct bdf2 *b, const double *x)
{
	const struct scene *sc = b->sc;
	double clear = OBSTACLE_CLEARANCE * sc->mat.thickness, eps = FRICTION_SLIP * b->beta;
	double eclear = edge_clearance(b);
	size_t i, j;
	int k;

	for (i = 0; i < b->noc; i++) {
		struct bdf2_obstacle_contact *c = &b->oc[i];
		vec3 xp = v3_load(x + 3 * c->node), n = v3_load(c->n), du, t0 = v3_load(c->tan);
		vec3 t1 = v3_load(c->tan + 3);
		double d = plane_distance(c, x);

		if (penalised(d, clear))
			add_diag(b, c->node, n, n, c->k);
		du = v3_sub(xp, v3_load(b->x0 + 3 * c->node));
		c->fric = friction_stiffness(c->mu * c->lambda, v3_dot(du, t0), v3_dot(du, t1), eps);
		if (c->fric > 0) {
			add_diag(b, c->node, t0, t0, c->fric);
			add_diag(b, c->node, t1, t1, c->fric);
		}
	}
	for (i = 0; i < b->nec; i++) {
		struct bdf2_edge_contact *c = &b->ec[i];
		int slot[2] = { c->ab, c->ba }, s2, u, v;
		vec3 n;

		if (!near_box(b, c, x, eclear * (1 + EDGE_ON))) {
			c->phi = INFINITY;
			continue;
		}
		if (!edge_penalised(edge_update(b, c, x), eclear))
			continue;
		n = v3_load(c->n);
		/* k w w^T n n^T over the edge's two nodes, all of it in H */
		add_diag(b, c->a, n, n, c->k * c->wa * c->wa);
		add_diag(b, c->b, n, n, c->k * c->wb * c->wb);
		for (s2 = 0; s2 < 2; s2++) {
			double *blk, nv[3] = { n.x, n.y, n.z };

			if (slot[s2] < 0)
				continue;
			blk = b->H.val + 9 * (size_t)slot[s2];
			for (u = 0; u < 3; u++)
				for (v = 0; v < 3; v++)
					blk[3 * u + v] += c->k * c->wa * c->wb * nv[u] * nv[v];
		}
	}
	if (b->ct == NULL)
		return;
	for (j = 0; j < b->nact; j++) {
		const struct contact_pair *cp = &b->ct->pair[b->act[j]];
		struct bdf2_pair_term *pt = &b->pt[b->act[j]];
		vec3 rel, n = v3_load(cp->n0), t0 = v3_load(pt->tan), t1 = v3_load(pt->tan + 3);

		pt->gap = pair_gap(b, cp, x, b->x0, &rel);
		pt->fric = friction_stiffness(cp->mu * pt->lambda, v3_dot(rel, t0), v3_dot(rel, t1), eps);
		for (k = 0; k < 4; k++) {
			int v = cp->vert[k];
			double w2 = cp->w[k] * cp->w[k];

			if (v >= b->ct->ncloth || held(b, v))
				continue;
			if (pt->gap < b->ct->thickness)
				add_diag(b, v, n, n, pt->k * w2);
			if (pt->fric > 0) {
				add_diag(b, v, t0, t0, pt->fric * w2);
				add_diag(b, v, t1, t1, pt->fric * w2);
			}
		}
	}
}

/* The dashpots' blocks: (spring_damping k / beta) u u^T a spring. */
static void
assemble_dashpots(struct bdf2 *b)
{
	const struct cloth *cl = b->fo->cl;
	double c = b->fo->spring_damping / b->beta;
	size_t s;

	if (!(b->fo->spring_damping > 0))
		return;
	for (s = 0; s < cl->nsprings; s++) {
		const struct spring *sp = &cl->springs[s];
		vec3 u = v3_load(b->udamp + 3 * s);
		int ends[2] = { sp->a, sp->b }, e;

		for (e = 0; e < 2; e++) {
			double *d = b->H.val + 9 * (size_t)b->H.diag[ends[e]];
			double *o = b->H.val + 9 * (size_t)b->H.spring_slot[2 * s + e];
			double a[3] = { u.x, u.y, u.z };
			int i, j;

			for (i = 0; i < 3; i++)
				for (j = 0; j < 3; j++) {
					d[3 * i + j] += c * sp->k * a[i] * a[j];
					o[3 * i + j] -= c * sp->k * a[i] * a[j];
				}
		}
	}
}

/* H at x: the elements' stiffness, the inertia and mass damping on the
 * diagonal, the dashpots, the contacts; a held node's row and column
 * decoupled (its diagonal block the inertia alone). */
static void
assemble(struct bdf2 *b, const double *x)
{
	const struct cloth *cl = b->fo->cl;
	double ib = 1 / (b->beta * b->beta) + b->fo->damping / b->beta;
	int p, k, i;

	blockmat_zero(&b->H);
	jacobian_eval(&b->jc, x);
	jacobian_assemble(&b->jc, 1, 0, &b->H);
	assemble_dashpots(b);
	for (p = 0; p < cl->n; p++) {
		double *d = b->H.val + 9 * (size_t)b->H.diag[p];

		for (i = 0; i < 3; i++)
			d[4 * i] += cl->mass[p] * ib;
	}
	assemble_contacts(b, x);
	if (b->pr->nnodes == 0)
		return;
	for (p = 0; p < cl->n; p++)
		for (k = b->H.start[p]; k < b->H.start[p + 1]; k++) {
			double *blk = b->H.val + 9 * (size_t)k;

			if (!held(b, p) && !held(b, b->H.col[k]))
				continue;
			memset(blk, 0, 9 * sizeof *blk);
			if (b->H.col[k] == p)
				for (i = 0; i < 3; i++)
					blk[4 * i] = cl->mass[p] / (b->beta * b->beta);
		}
}

/* out += the pairs' coupling between different nodes (their diagonal
 * blocks are in H): k a a^T for the penalty, a = (w_k n0), and the same
 * across the tangents for friction. */
static void
pair_mul(const struct bdf2 *b, const double *p, double *out)
{
	size_t j;
	int k;

	if (b->ct == NULL)
		return;
	for (j = 0; j < b->nact; j++) {
		size_t i = b->act[j];
		const struct contact_pair *cp = &b->ct->pair[i];
		const struct bdf2_pair_term *pt = &b->pt[i];
		vec3 n = v3_load(cp->n0), t0 = v3_load(pt->tan), t1 = v3_load(pt->tan + 3);
		double kn = pt->gap < b->ct->thickness ? pt->k : 0, sn = 0, s0 = 0, s1 = 0;

		if (kn == 0 && pt->fric == 0)
			continue;
		for (k = 0; k < 4; k++) {
			int v = cp->vert[k];
			vec3 pv;

			if (v >= b->ct->ncloth || held(b, v))
				continue;
			pv = v3_load(p + 3 * v);
			sn += cp->w[k] * v3_dot(n, pv);
			s0 += cp->w[k] * v3_dot(t0, pv);
			s1 += cp->w[k] * v3_dot(t1, pv);
		}
		for (k = 0; k < 4; k++) {
			int v = cp->vert[k];
			vec3 pv, o;
			double w = cp->w[k];

			if (v >= b->ct->ncloth || held(b, v))
				continue;
			pv = v3_load(p + 3 * v);
			/* the whole product less the node's own block */
			o = v3_scale(n, kn * w * (sn - w * v3_dot(n, pv)));
			o = v3_madd(o, t0, pt->fric * w * (s0 - w * v3_dot(t0, pv)));
			o = v3_madd(o, t1, pt->fric * w * (s1 - w * v3_dot(t1, pv)));
			v3_addto(out + 3 * v, o);
		}
	}
}

static void
system_mul(const struct bdf2 *b, const double *p, double *out)
{
	blockmat_mul(&b->H, p, out);
	pair_mul(b, p, out);
}

/*
 * A box's edge contact is a stiffness k w w^T n n^T over its two nodes, of
 * rank one: it holds their weighted mean along n and leaves their
 * difference free. A block at a time it holds each node, and the
 * V-cycle's lines take it whole only for an edge along them, not for a
 * triangle's diagonal. So each pushing edge's two nodes are also solved
 * together, their 6 x 6 block of H, before and after the V-cycle: a
 * symmetric block Gauss-Seidel around it (multiplicative Schwarz), a few
 * dozen blocks at most where the pairs would be hundreds. Over nine
 * scenes (doc/bench-history.md) the CG iterations without it were of the
 * same order, the fold patterns differing, but 2 steps of the peers'
 * table at 25^2 without friction went unconverged; with it none.
 */
static void
edge_block(const struct bdf2 *b, const struct bdf2_edge_contact *c, double *k6)
{
	const double *blk[4] = { b->H.val + 9 * (size_t)b->H.diag[c->a], b->H.val + 9 * (size_t)c->ab,
	    b->H.val + 9 * (size_t)c->ba, b->H.val + 9 * (size_t)b->H.diag[c->b] };
	int i, j;

	for (i = 0; i < 6; i++)
		for (j = 0; j < 6; j++)
			k6[6 * i + j] = blk[2 * (i / 3) + j / 3][3 * (i % 3) + j % 3];
}

/* Packed Cholesky of a 6 x 6 block: L by rows, L[i][j] at i (i + 1) / 2 + j.
 * false when it is not positive definite. */
static bool
chol6(const double *k6, double *l)
{
	int i, j, m;

	for (i = 0; i < 6; i++)
		for (j = 0; j <= i; j++) {
			double sum = k6[6 * i + j];

			for (m = 0; m < j; m++)
				sum -= l[i * (i + 1) / 2 + m] * l[j * (j + 1) / 2 + m];
			if (i == j) {
				if (!(sum > 0))
					return false;
				l[i * (i + 1) / 2 + i] = sqrt(sum);
			} else {
				l[i * (i + 1) / 2 + j] = sum / l[j * (j + 1) / 2 + j];
			}
		}
	return true;
}

static void
chol6_solve(const double *l, double *x)
{
	int i, m;

	for (i = 0; i < 6; i++) {
		for (m = 0; m < i; m++)
			x[i] -= l[i * (i + 1) / 2 + m] * x[m];
		x[i] /= l[i * (i + 1) / 2 + i];
	}
	for (i = 5; i >= 0; i--) {
		for (m = i + 1; m < 6; m++)
			x[i] -= l[m * (m + 1) / 2 + i] * x[m];
		x[i] /= l[i * (i + 1) / 2 + i];
	}
}

static void
edge_blocks_setup(struct bdf2 *b)
{
	double clear = edge_clearance(b), k6[36];
	size_t i;

	b->nsmooth = 0;
	for (i = 0; i < b->nec; i++) {
		struct bdf2_edge_contact *c = &b->ec[i];

		c->smooth = edge_penalised(c->phi, clear) && c->ab >= 0 && c->ba >= 0 &&
		    !held(b, c->a) && !held(b, c->b);
		if (c->smooth) {
			edge_block(b, c, k6);
			c->smooth = chol6(k6, c->chol);
		}
		b->nsmooth += c->smooth;
	}
}

/* (r - H z) at node p, into out. */
static void
row_residual(const struct bdf2 *b, int p, const double *r, const double *z, double *out)
{
	int k, i;

	for (i = 0; i < 3; i++)
		out[i] = r[3 * p + i];
	for (k = b->H.start[p]; k < b->H.start[p + 1]; k++) {
		const double *blk = b->H.val + 9 * (size_t)k, *zc = z + 3 * (size_t)b->H.col[k];

		for (i = 0; i < 3; i++)
			out[i] -= blk[3 * i] * zc[0] + blk[3 * i + 1] * zc[1] + blk[3 * i + 2] * zc[2];
	}
}

/* One Gauss-Seidel sweep of the pushing edges' blocks on H z = r, forward
 * or backward. */
static void
edge_sweep(const struct bdf2 *b, const double *r, double *z, bool backward)
{
	size_t q;

	for (q = 0; q < b->nec; q++) {
		const struct bdf2_edge_contact *c = &b->ec[backward ? b->nec - 1 - q : q];
		double d[6];
		int i;

		if (!c->smooth)
			continue;
		row_residual(b, c->a, r, z, d);
		row_residual(b, c->b, r, z, d + 3);
		chol6_solve(c->chol, d);
		for (i = 0; i < 3; i++) {
			z[3 * c->a + i] += d[i];
			z[3 * c->b + i] += d[3 + i];
		}
	}
}

/*
 * The preconditioner of H: its multigrid, or where that fails (H not
 * positive definite to it) its 3 x 3 diagonal blocks inverted. A step's
 * first iteration sets the multigrid up whole; a later one refreshes the
 * finest level's lines alone (mg_update_fine: the coarse levels' Galerkin
 * products are most of a setup) while its solves take no more CG
 * iterations than the first after the last full setup did, and sets up
 * whole after one that takes more. Stale coarse levels cost iterations,
 * never the answer (the V-cycle stays SPD, its smoothers on the current
 * H). Kept within a step, so that a resumed run sets up as the run did.
 * At one level (a strip: the band Cholesky is all of it) the last factor
 * is kept by the same rule, but only where a contact pushes: kept in free
 * motion it cost the undamped hanging strip a fifth of its energy.
 * Figures: bench-history.md, bdf2.sh, stop 47.
 */
static bool pushing(const struct bdf2 *b);

static void
precondition_setup(struct bdf2 *b)
{
	int p;

	if (b->use_mg && b->mg_step == b->steps && b->mg_cg >= 0 && b->last_cg <= b->mg_cg &&
	    (mg_levels(&b->mg) > 1 ? mg_update_fine(&b->mg, &b->H) == 0 : pushing(b))) {
		edge_blocks_setup(b);
		return;
	}
	b->mg_step = b->steps;
	b->mg_cg = -1;
	if ((b->use_mg = mg_setup(&b->mg, &b->H) == 0)) {
		edge_blocks_setup(b);
		return;
	}

	for (p = 0; p < b->H.n; p++) {
		memcpy(b->pre + 9 * p, b->H.val + 9 * (size_t)b->H.diag[p], 9 * sizeof *b->pre);
		block_invert_spd(b->pre + 9 * p);
	}
}

static void
precondition(struct bdf2 *b, const double *r, double *z)
{
	int p;

	if (b->use_mg && b->nsmooth == 0) {
		mg_apply(&b->mg, r, z);
		return;
	}
	if (b->use_mg) {	/* the edges' blocks around the V-cycle */
		size_t n3 = 3 * (size_t)b->H.n, i;
		double *hz = b->pre, *rest = b->pre + n3, *zc = b->pre + 2 * n3;

		memset(z, 0, n3 * sizeof *z);
		edge_sweep(b, r, z, false);
		blockmat_mul(&b->H, z, hz);
		for (i = 0; i < n3; i++)
			rest[i] = r[i] - hz[i];
		mg_apply(&b->mg, rest, zc);
		for (i = 0; i < n3; i++)
			z[i] += zc[i];
		edge_sweep(b, r, z, true);
		return;
	}

	for (p = 0; p < b->H.n; p++)
		block_apply(b->pre + 9 * p, r + 3 * p, z + 3 * p);
}

static double
dot(const double *a, const double *c, size_t n)
{
	double s = 0;
	size_t i;

	for (i = 0; i < n; i++)
		s += a[i] * c[i];
	return s;
}

static bool
stop_asked(struct bdf2 *b)
{
	if (stop_set(b->stop))
		b->stopped = true;
	return b->stopped;
}

/*
 * dx = -H^-1 g by preconditioned conjugate gradients, until |g + H dx|
 * is at most eta |g| (Euclidean norms: inexact Newton's own condition,
 * the one the forcing term is chosen for); b->r is left the linear
 * residual -(g + H dx). Returns the iterations. Tested on r before it is
 * preconditioned, the stop spares the V-cycle that a test in the
 * preconditioner's norm (r.z) needs after the last update, a third of a
 * short solve (bench-history.md, bdf2.sh, stop 47).
 */
static int
solve(struct bdf2 *b, double eta)
{
	size_t n3 = 3 * (size_t)b->fo->cl->n, i;
	double rz, stop2;
	int it;

	memset(b->dx, 0, n3 * sizeof *b->dx);
	for (i = 0; i < n3; i++)
		b->r[i] = -b->g[i];
	stop2 = eta * eta * dot(b->r, b->r, n3);
	if (!(stop2 > 0))	/* g = 0: dx = 0 */
		return 0;
	precondition(b, b->r, b->z);
	memcpy(b->p, b->z, n3 * sizeof *b->p);
	rz = dot(b->r, b->z, n3);
	for (it = 0; it < b->max_cg; it++) {
		double pq, alpha, rz_new, beta;

		if ((it & 15) == 15 && stop_asked(b))
			break;
		system_mul(b, b->p, b->q);
		pq = dot(b->p, b->q, n3);
		if (!(pq > 0)) {
			/* negative curvature (Steihaug): the iterate so far, or
			 * the preconditioned gradient on the first */
			if (it == 0)
				memcpy(b->dx, b->z, n3 * sizeof *b->dx);
			break;
		}
		alpha = rz / pq;
		for (i = 0; i < n3; i++) {
			b->dx[i] += alpha * b->p[i];
			b->r[i] -= alpha * b->q[i];
		}
		if (dot(b->r, b->r, n3) <= stop2) {
			it++;
			break;
		}
		precondition(b, b->r, b->z);
		rz_new = dot(b->r, b->z, n3);
		beta = rz_new / rz;
		rz = rz_new;
		for (i = 0; i < n3; i++)
			b->p[i] = b->z[i] + beta * b->p[i];
	}
	return it;
}

/* The largest residual acceleration |g_p| / m_p over the free nodes. */
static double
residual(const struct bdf2 *b)
{
	const struct cloth *cl = b->fo->cl;
	double worst = 0;
	int p;

	for (p = 0; p < cl->n; p++) {
		double a = norm3(b->g + 3 * p) / cl->mass[p];

		worst = a > worst ? a : worst;
	}
	return worst;
}

/* ---- the step ---- */

/* The largest of n 3-vectors' lengths. */
static double
max_node_norm(const double *a, size_t n)
{
	double worst = 0;
	size_t p;

	for (p = 0; p < n; p++) {
		double l = norm3(a + 3 * p);

		worst = l > worst ? l : worst;
	}
	return worst;
}

/* The pairs that may push somewhere along dx (up to EXTRAPOLATE_MOST of
 * it) from x: a pair's gap sum w x n0 is linear in x, so along x + a dx it
 * is its gap plus a times its rate sum w n0 . dx, exactly. The near pairs
 * hold every pair that can: a gap moves by at most twice the farthest any
 * node moves. */
static void
live_pairs(struct bdf2 *b)
{
	size_t j, n = (size_t)b->fo->cl->n;

	if (b->ct == NULL)
		return;
	need_near(b, b->x, 2 * EXTRAPOLATE_MOST * max_node_norm(b->dx, n));
	b->nlive = 0;
	for (j = 0; j < b->nnear; j++) {
		const struct contact_pair *cp = &b->ct->pair[b->near[j]];
		double rate = 0;
		int k;

		for (k = 0; k < 4; k++)
			if (cp->vert[k] < b->ct->ncloth)
				rate += cp->w[k] * v3_dot(v3_load(cp->n0), v3_load(b->dx + 3 * cp->vert[k]));
		if (b->pt[b->near[j]].gap + EXTRAPOLATE_MOST * fmin(rate, 0) < b->ct->thickness ||
		    b->pt[b->near[j]].lambda > 0)
			b->live[b->nlive++] = b->near[j];
	}
}

/*
 * The nodes that a move from x to xt takes past an obstacle contact's
 * clearance, being clear of it at x, stopped on it: the penalty is not in
 * the system at x for them, so Newton's step runs them into the obstacle
 * as if it were not there, and Armijo's rule then cuts the whole cloth's
 * step to keep those few out. The active set grew a layer an iteration:
 * the peers' table landing on its cube, 60 to 242 contacts over 29
 * iterations a step. Stopped on it, the next system has its penalty
 * (assemble_contacts takes d <= clear): Bertsekas' projected search, the
 * obstacles' planes taken as bounds. Peers' table at 25^2, first 0.25 s:
 * 7.6 to 6.0 iterations a step; tablecloth 8.8 to 8.1.
 */
static void
stop_at_planes(const struct bdf2 *b, const double *x, double *xt)
{
	double clear = OBSTACLE_CLEARANCE * b->sc->mat.thickness;
	size_t i;

	for (i = 0; i < b->noc; i++) {
		const struct bdf2_obstacle_contact *c = &b->oc[i];
		double d;

		if (penalised(plane_distance(c, x), clear) || (d = plane_distance(c, xt)) >= clear)
			continue;
		v3_store(xt + 3 * c->node, v3_madd(v3_load(xt + 3 * c->node), v3_load(c->n), clear - d));
	}
	/* and the box's edges, on the plane of their nearest point at x (as
	 * the nodes' are fixed for the search, so that the stop is the same
	 * map of xt along it: with the plane of the nearest point at xt the
	 * search went round, the peers' table at 25^2 with friction 0.3
	 * unconverged 86 steps running), their nodes moved by the least that
	 * puts the point on it (a held node not at all) */
	clear = edge_clearance(b);
	for (i = 0; i < b->nec; i++) {
		const struct bdf2_edge_contact *c = &b->ec[i];
		double d, t, wa, wb, s;
		vec3 n, q, p;

		if (!near_box(b, c, xt, clear) || edge_penalised(edge_gap(b, c, x, &t, &n, &q), clear))
			continue;
		p = v3_add(v3_scale(v3_load(xt + 3 * c->a), 1 - t), v3_scale(v3_load(xt + 3 * c->b), t));
		if ((d = v3_dot(v3_sub(p, q), n)) >= clear)
			continue;
		wa = held(b, c->a) ? 0 : 1 - t;
		wb = held(b, c->b) ? 0 : t;
		if (!(wa * wa + wb * wb > 0))
			continue;
		s = (clear - d) / (wa * (1 - t) + wb * t);
		v3_store(xt + 3 * c->a, v3_madd(v3_load(xt + 3 * c->a), n, s * wa));
		v3_store(xt + 3 * c->b, v3_madd(v3_load(xt + 3 * c->b), n, s * wb));
	}
}

/* A full step taken, Phi fell to phi1 along dx: where the parabola through
 * phi0 (slope g.dx) and phi1 has its least is farther on when the
 * system's stand-in overstates the curvature along dx, as it does where
 * the cloth buckles (its compressed springs and sheared corners soften
 * there, jacobian.h). There, up to EXTRAPOLATE_MOST times the step is
 * tried, and taken into xtry if it lowers Phi more. */
static void
extrapolate(struct bdf2 *b, double phi0, double slope, double phi1)
{
	size_t n3 = 3 * (size_t)b->fo->cl->n, i;
	double curv = 2 * (phi1 - phi0 - slope), best, phi;

	if (!(curv > 0) || (best = -slope / curv) < 1.25)
		return;
	best = best < EXTRAPOLATE_MOST ? best : EXTRAPOLATE_MOST;
	for (i = 0; i < n3; i++)
		b->r[i] = b->x[i] + best * b->dx[i];
	stop_at_planes(b, b->x, b->r);
	if ((phi = potential(b, b->r, NULL)) < phi1)
		memcpy(b->xtry, b->r, n3 * sizeof *b->xtry);
}

/* Along dx from x (where Phi is phi0, its slope g.dx): the longest step
 * of 1, 1/2, 1/4, ... that lowers Phi enough (Armijo's rule), into x.
 * false, x unchanged, when none does. */
static bool
line_search(struct bdf2 *b, double phi0)
{
	size_t n3 = 3 * (size_t)b->fo->cl->n, i;
	double slope = dot(b->g, b->dx, n3), alpha = 1, phi;
	int cut;

	live_pairs(b);
	if (!(slope < 0)) {	/* not downhill (roundoff): the preconditioned gradient */
		precondition(b, b->g, b->dx);
		for (i = 0; i < n3; i++)
			b->dx[i] = -b->dx[i];
		slope = dot(b->g, b->dx, n3);
	}
	for (cut = 0; cut < 30; cut++, alpha *= 0.5) {
		for (i = 0; i < n3; i++)
			b->xtry[i] = b->x[i] + alpha * b->dx[i];
		stop_at_planes(b, b->x, b->xtry);
		phi = potential(b, b->xtry, NULL);
		if (phi <= phi0 + 1e-4 * alpha * slope) {
			if (cut == 0)
				extrapolate(b, phi0, slope, phi);
			for (i = 0; i < n3; i++)	/* the move, for need_near */
				b->r[i] = b->xtry[i] - b->x[i];
			b->drift += max_node_norm(b->r, n3 / 3);
			memcpy(b->x, b->xtry, n3 * sizeof *b->x);
			b->cuts += cut;
			b->phi_taken = phi;
			return true;
		}
	}
	b->cuts += cut;
	return false;
}

/* The reset directions: every contact that pushes at the step's end
 * state, its normal, for the node (or the pair's cloth nodes). */
static void
add_reset(struct bdf2 *b, int p, vec3 n)
{
	double len;
	int k;

	if (b->nreset[p] >= 3)
		return;
	for (k = 0; k < b->nreset[p]; k++) {	/* Gram-Schmidt */
		vec3 e = v3_load(b->rdir + 9 * p + 3 * k);

		n = v3_madd(n, e, -v3_dot(n, e));
	}
	if ((len = v3_len(n)) < 0.1)
		return;
	v3_store(b->rdir + 9 * p + 3 * b->nreset[p]++, v3_scale(n, 1 / len));
}

static void
find_resets(struct bdf2 *b)
{
	const struct scene *sc = b->sc;
	double clear = OBSTACLE_CLEARANCE * sc->mat.thickness;
	size_t i, j;
	int k;

	memset(b->nreset, 0, (size_t)b->fo->cl->n);
	for (i = 0; i < b->noc; i++) {
		struct bdf2_obstacle_contact *c = &b->oc[i];

		c->phi = plane_distance(c, b->x);
		if (c->phi < clear)
			add_reset(b, c->node, v3_load(c->n));
	}
	for (i = 0; i < b->nec; i++) {
		struct bdf2_edge_contact *c = &b->ec[i];

		if (!near_box(b, c, b->x, edge_clearance(b))) {
			c->phi = INFINITY;
			continue;
		}
		if (!(edge_update(b, c, b->x) < edge_clearance(b)))
			continue;
		if (!held(b, c->a))
			add_reset(b, c->a, v3_load(c->n));
		if (!held(b, c->b))
			add_reset(b, c->b, v3_load(c->n));
	}
	b->nlive = 0;
	if (b->ct == NULL)
		return;
	need_near(b, b->x, 0);
	for (j = 0; j < b->nnear; j++) {
		size_t q = b->near[j];
		const struct contact_pair *cp = &b->ct->pair[q];

		b->pt[q].gap = pair_gap(b, cp, b->x, b->x0, NULL);
		if (b->pt[q].gap >= b->ct->thickness)
			continue;
		b->live[b->nlive++] = q;
		for (k = 0; k < 4; k++)
			if (cp->vert[k] < b->ct->ncloth && !held(b, cp->vert[k]) && cp->w[k] != 0)
				add_reset(b, cp->vert[k], v3_load(cp->n0));
	}
}

/* The largest distance a node has moved from the step's start. */
static double
step_motion(const struct bdf2 *b, const double *y)
{
	const struct cloth *cl = b->fo->cl;
	double worst = 0;
	int p;

	for (p = 0; p < cl->n; p++) {
		double d = v3_len(v3_sub(v3_load(b->x + 3 * p), v3_load(y + 3 * p)));

		worst = d > worst ? d : worst;
	}
	return worst;
}

/* ---- the energy ---- */

/* The energy of the cloth as a system whose held nodes are its boundary:
 * the free nodes' kinetic energy, and the potential of all (elastic,
 * gravity, the loads acting at t1); f (3n, may be NULL) gets the
 * potential's forces. */
static double
system_energy(struct bdf2 *b, const double *y, double *f)
{
	const struct forces *fo = b->fo;
	const struct cloth *cl = fo->cl;
	size_t n3 = 3 * (size_t)cl->n;
	vec3 grav = v3_load(fo->g);
	double e = forces_elastic(fo, y, f);
	int p, l, k;

	for (p = 0; p < cl->n; p++) {
		vec3 v = v3_load(y + n3 + 3 * p);

		e -= cl->mass[p] * v3_dot(grav, v3_load(y + 3 * p));
		if (f != NULL)
			v3_addto(f + 3 * p, v3_scale(grav, cl->mass[p]));
		if (!held(b, p))
			e += 0.5 * cl->mass[p] * v3_dot(v, v);
	}
	for (l = 0; l < fo->nloads; l++) {
		const struct load_group *lg = &fo->loads[l];

		if (!load_active(lg, b->t1))
			continue;
		for (k = 0; k < lg->n; k++) {
			e -= v3_dot(v3_load(lg->f), v3_load(y + 3 * lg->node[k]));
			if (f != NULL)
				v3_addto(f + 3 * lg->node[k], v3_load(lg->f));
		}
	}
	return e;
}

/*
 * The step's energy budget: what the system had at its start, plus the
 * work its boundary did (the held nodes' motion against the potential's
 * forces on them, by the trapezoidal rule), and the work of its contacts'
 * and its damping's forces (at the step's end, over its displacement:
 * the rectangle rule, which makes them dissipate the more). What the step
 * ends with below that is BDF2's own dissipation, which it damps the
 * stiff vibrations by and, at a step of a frame, most motion faster than
 * a few hertz: the hanging strip's energy above rest at 1 s would be 7.5
 * % of RK4's (bench/fast.sh part 7). bdf2_correct_energy gives it back.
 */
static void
energy_budget(struct bdf2 *b, const double *y0, const double *y1)
{
	const struct cloth *cl = b->fo->cl;
	size_t n3 = 3 * (size_t)cl->n, i;
	double w = 0;
	int p;

	b->e_start = system_energy(b, y0, b->pr->nnodes > 0 ? b->r : NULL);
	b->e_solved = system_energy(b, y1, b->pr->nnodes > 0 ? b->z : NULL);
	for (p = 0; p < b->pr->nnodes; p++) {
		int q = b->pr->node[p];
		vec3 d = v3_sub(v3_load(y1 + 3 * q), v3_load(y0 + 3 * q));

		/* the forces pull the node; the mechanism holds it against them */
		w -= 0.5 * v3_dot(v3_add(v3_load(b->r + 3 * q), v3_load(b->z + 3 * q)), d);
	}
	/* the contacts and the damping: the gradient of their terms at the end */
	memset(b->f, 0, n3 * sizeof *b->f);
	obstacle_terms(b, y1, b->f);
	edge_terms(b, y1, b->f);
	pair_terms(b, y1, b->f);
	dashpots(b, y1, b->f);
	for (i = 0; i < n3; i++)
		if (!held(b, (int)(i / 3)))
			w -= (b->f[i] + b->fo->damping * cl->mass[i / 3] * y1[n3 + i]) * (y1[i] - y0[i]);
	b->e_budget = b->e_start + w;
}

/*
 * The contacts the solve ran through: a penalty that holds a layer under
 * the cloth's own weight can be overrun by its stiff springs (the
 * tablecloth's folds at impact: pairs ending 1.5 mm past their plane in a
 * thickness of 0.55 mm), and the exact check's correction then throws
 * nodes into the box. Each pair that ends past its plane, and each node
 * past its obstacle's, gets OVERRUN_STIFFEN times its stiffness (at most
 * OVERRUN_MOST times the stiffest spring's) and the solve goes on: the
 * few such contacts, not all, make the system stiffer. Returns how many.
 */
static int
stiffen_overrun(struct bdf2 *b)
{
	double most = OVERRUN_MOST * b->kmax;
	size_t i, j;
	int n = 0;

	for (i = 0; i < b->noc; i++) {
		struct bdf2_obstacle_contact *c = &b->oc[i];

		if (plane_distance(c, b->x) < 0 && c->k < most) {
			c->k = fmin(c->k * OVERRUN_STIFFEN, most);
			n++;
		}
	}
	for (i = 0; i < b->nec; i++) {
		struct bdf2_edge_contact *c = &b->ec[i];

		if (near_box(b, c, b->x, 0) && edge_gap(b, c, b->x, NULL, NULL, NULL) < 0 &&
		    c->k < most) {
			c->k = fmin(c->k * OVERRUN_STIFFEN, most);
			n++;
		}
	}
	if (b->ct == NULL)
		return n;
	need_near(b, b->x, 0);
	for (j = 0; j < b->nnear; j++) {
		struct bdf2_pair_term *pt = &b->pt[b->near[j]];

		if (pair_gap(b, &b->ct->pair[b->near[j]], b->x, b->x0, NULL) < 0 && pt->k < most) {
			pt->k = fmin(pt->k * OVERRUN_STIFFEN, most);
			n++;
		}
	}
	return n;
}

/* Whether a contact pushes at the iterate (lag_normal_forces'). */
static bool
pushing(const struct bdf2 *b)
{
	size_t i;

	if (b->nact > 0)
		return true;
	for (i = 0; i < b->noc; i++)
		if (b->oc[i].lambda > 0)
			return true;
	return false;
}

/* The forcing term of the next solve (CG_REDUCTION_TIGHT above), g being
 * the iterate's gradient; first: the step's first solve. */
static double
forcing_term(struct bdf2 *b, bool first, size_t n3)
{
	double gnorm = sqrt(dot(b->g, b->g, n3)), eta = CG_REDUCTION_TIGHT;

	if (first) {
		if (pushing(b))
			eta = CG_REDUCTION_LOOSE;
	} else if (b->gnorm_last > 0) {
		/* (E and W's safeguard against a sudden tightening after
		 * loose solves, eta at least eta_last^1.618 where that is over
		 * 0.1, never acts under CG_REDUCTION_LOOSE) */
		eta = fabs(gnorm - b->model_last) / b->gnorm_last;
	}
	eta = fmin(fmax(eta, CG_REDUCTION_TIGHT), CG_REDUCTION_LOOSE);
	b->gnorm_last = gnorm;
	return eta;
}

/*
 * A step in flight (no node held, no contact pushing at its start) first
 * goes where inertia, mass damping, gravity and loads alone would take
 * each node (the least of Phi without the cloth's own energy and
 * contacts), searched along from x as a Newton step is. A free fall's step
 * is exactly that, and Newton stops at its first residual with no solve.
 * Where something holds the cloth the move runs it into its support (more
 * iterations on a resting cloth, energy lost on the pinned hanging strip:
 * bench-history.md, bdf2.sh, 2026-12-07), hence the conditions. false when
 * there is no such step or the search takes none.
 */
static bool
flight_step(struct bdf2 *b, double phi)
{
	const struct forces *fo = b->fo;
	const struct cloth *cl = fo->cl;
	size_t n3 = 3 * (size_t)cl->n;
	double ib2 = 1 / (b->beta * b->beta), cd = fo->damping / b->beta;
	int p, l, k;

	if (pushing(b) || b->pr->nnodes > 0)
		return false;
	for (p = 0; p < cl->n; p++) {
		vec3 w = v3_add(v3_add(v3_scale(v3_load(b->target + 3 * p), ib2),
		    v3_scale(v3_load(b->xhat + 3 * p), cd)), v3_load(fo->g));

		v3_store(b->dx + 3 * p, v3_sub(v3_scale(w, 1 / (ib2 + cd)), v3_load(b->x + 3 * p)));
	}
	for (l = 0; l < fo->nloads; l++) {
		const struct load_group *lg = &fo->loads[l];

		if (!load_active(lg, b->t1))
			continue;
		for (k = 0; k < lg->n; k++)
			v3_addto(b->dx + 3 * lg->node[k], v3_scale(v3_load(lg->f),
			    1 / (cl->mass[lg->node[k]] * (ib2 + cd))));
	}
	/* not downhill: no search (its fallback would use the last step's
	 * preconditioner, which a resumed run has not) */
	if (!(dot(b->g, b->dx, n3) < 0))
		return false;
	return line_search(b, phi);
}

/* Newton's iterations from b->x; y is the step's start, *phi_first Phi
 * at the step's first iterate (NAN before it: set here). The decrease
 * that stops them is a part of the whole step's, not of this pass's: a
 * pass after late contacts starts near the solution, and its own
 * decrease took 4 to 5 iterations to fall below its thousandth
 * (corrections of 0.1 to 0.3 mm on a step moving 16 mm; the peers'
 * table at 50^2, first 0.25 s: 6.7 to 5.1 iterations a step). 0, or -1
 * when the stop flag asks (b->stopped). */
static int
newton(struct bdf2 *b, const double *y, double *phi_first)
{
	size_t n3 = 3 * (size_t)b->fo->cl->n, i;
	bool converged = false, flown = false, contact;
	double phi;
	int it;

	for (it = 0; it < b->max_newton; it++) {
		if (stop_asked(b))
			return -1;
		lag_normal_forces(b, b->x);
		phi = potential(b, b->x, b->g);
		b->last_residual = residual(b);
		if (b->last_residual <= b->tol) {
			converged = true;
			break;
		}
		if (!flown && isnan(*phi_first)) {	/* no solve yet this step */
			flown = true;
			if (flight_step(b, phi)) {
				it--;	/* not an iteration: no solve */
				continue;
			}
		}
		assemble(b, b->x);
		precondition_setup(b);
		b->last_cg = solve(b, forcing_term(b, isnan(*phi_first), n3));
		if (b->mg_cg < 0)
			b->mg_cg = b->last_cg;
		b->cg += b->last_cg;
		b->model_last = sqrt(dot(b->r, b->r, n3));
		if (stop_asked(b))
			return -1;
		b->last_step = max_node_norm(b->dx, n3 / 3);
		if (b->last_step <= NEWTON_VTOL * b->beta ||
		    b->last_step <= b->rel * step_motion(b, y)) {
			for (i = 0; i < n3; i++)	/* too small to search along */
				b->x[i] += b->dx[i];
			b->drift += b->last_step;
			converged = true;
			it++;
			break;
		}
		if (isnan(*phi_first))
			*phi_first = phi;
		if (!line_search(b, phi))
			break;	/* no descent left: as far as roundoff allows */
		contact = pushing(b);
		if (phi - b->phi_taken <= (contact ? b->decrease_contact : b->decrease) *
		    (*phi_first - b->phi_taken) &&
		    (!contact || b->last_step <= NEWTON_VSTOP * b->beta)) {
			converged = true;
			it++;
			break;
		}
	}
	b->last_newton = it;
	b->newton += it;
	if (!converged)
		b->unconverged++;
	return 0;
}

void
bdf2_step(struct bdf2 *b, double t, double h, const double *y, double *y_out,
    struct contacts *ct)
{
	const struct cloth *cl = b->fo->cl;
	size_t n3 = 3 * (size_t)cl->n, s, i;
	double phi_first = NAN;
	int pass;

	b->stopped = false;
	b->t1 = t + h;
	b->x0 = y;
	b->ct = ct != NULL && ct->n > 0 ? ct : NULL;
	set_formula(b, h, y);
	for (s = 0; s < cl->nsprings; s++) {	/* the dashpots' directions */
		const struct spring *sp = &cl->springs[s];
		vec3 d = v3_sub(v3_load(y + 3 * sp->b), v3_load(y + 3 * sp->a));
		double len = v3_len(d);

		v3_store(b->udamp + 3 * s, len > 0 ? v3_scale(d, 1 / len) : v3(0, 0, 0));
	}
	if (find_obstacle_contacts(b, y) != 0 || find_edge_contacts(b, y) != 0 ||
	    set_pairs(b) != 0) {
		b->stopped = true;	/* out of memory: the caller sees a step given up */
		return;
	}
	b->near_ok = false;
	/*
	 * From the step's start, not the inertial target: the start is a
	 * state the barriers allow (no hinge folded right back, where its
	 * energy is infinite), and the line search keeps every iterate so.
	 * The target may lie past a barrier, a hinge folded through, and
	 * Newton then settles on its far side: the undamped tablecloth at
	 * 0.53 s, 2.6 J of bending for a step (Li et al. start IPC's
	 * iterations from the last state for the same reason). From the
	 * start the iterations are as many (7.4 a step against 7.8 on the
	 * tablecloth, 4.7 against 4.3 on the strip); the held nodes go where
	 * they go.
	 */
	memcpy(b->x, y, n3 * sizeof *b->x);
	prescribed_apply(b->pr, cl, b->t1, b->x, NULL);
	for (pass = 0; pass < LATE_PASSES; pass++) {
		int late, edges;

		if (newton(b, y, &phi_first) != 0)
			return;
		if ((late = late_obstacle_contacts(b, y, b->x)) < 0 ||
		    (edges = late_edge_contacts(b, b->x)) < 0) {
			b->stopped = true;
			return;
		}
		late += edges;
		late += stiffen_overrun(b);
		if (late == 0)
			break;
	}
	b->steps++;
	find_resets(b);
	for (i = 0; i < n3; i++) {
		y_out[i] = b->x[i];
		y_out[n3 + i] = (b->x[i] - b->xhat[i]) / b->beta;
	}
	energy_budget(b, y, y_out);
}

/* Whether a contact pushes at the step's end (find_resets has its
 * distances). */
static bool
touching(const struct bdf2 *b)
{
	double clear = OBSTACLE_CLEARANCE * b->sc->mat.thickness;
	size_t i;

	for (i = 0; i < b->noc; i++)
		if (b->oc[i].phi < clear)
			return true;
	return b->nlive > 0;
}

void
bdf2_correct_energy(struct bdf2 *b, double *y1)
{
	const struct cloth *cl = b->fo->cl;
	size_t n3 = 3 * (size_t)cl->n;
	double now = system_energy(b, y1, NULL), target, kinetic = 0, s;
	int p;

	/* what the exact check changed since is the contacts': kept if it
	 * took energy away, not if it gave some */
	target = b->e_budget + fmin(0, now - b->e_solved);
	/* With a contact pushing, nothing is given back: a penalty is a stiff
	 * spring whose vibration BDF2 damps, and giving that back kept a
	 * cloth resting on a plane trembling (1e-11 J at 0.6 s, where RK4's
	 * is at rest); the budget still takes away any gain. */
	if (touching(b) || now != b->e_solved)
		target = fmin(target, now);
	for (p = 0; p < cl->n; p++)
		if (!held(b, p)) {
			vec3 v = v3_load(y1 + n3 + 3 * p);

			kinetic += 0.5 * cl->mass[p] * v3_dot(v, v);
		}
	b->last_restored = 0;
	if (!(kinetic > 0) || target == now)
		return;
	s = 1 + (target - now) / kinetic;
	s = sqrt(s > 0 ? s : 0);
	s = s < ENERGY_SCALE_MOST ? s : ENERGY_SCALE_MOST;
	for (p = 0; p < cl->n; p++)
		if (!held(b, p))
			v3_store(y1 + n3 + 3 * p, v3_scale(v3_load(y1 + n3 + 3 * p), s));
	b->last_restored = (s * s - 1) * kinetic;
	b->restored += b->last_restored;
}

int
bdf2_events(struct bdf2 *b, struct collide *col, long step, const double *y1)
{
	const struct cloth *cl = b->fo->cl;
	double clear = OBSTACLE_CLEARANCE * b->sc->mat.thickness;
	size_t n3 = 3 * (size_t)cl->n, i;

	for (i = 0; i < b->noc; i++) {
		const struct bdf2_obstacle_contact *c = &b->oc[i];
		vec3 n = v3_load(c->n);
		double after, force;

		if (!(c->phi < clear))
			continue;
		/* the penalty's force acted over the step through beta (the
		 * formula's v = vhat + beta F/m): that is its impulse */
		force = c->k * (clear - c->phi);
		after = v3_dot(v3_load(y1 + n3 + 3 * c->node), n);
		if (collide_add_event(col, step, c->node, CONTACT_OBSTACLE, -1, c->obstacle,
		    v3_load(c->q), n, after - b->beta * force / cl->mass[c->node], after) != 0)
			return -1;
	}
	for (i = 0; i < b->nec; i++) {
		const struct bdf2_edge_contact *c = &b->ec[i];
		vec3 n = v3_load(c->n);
		/* the event goes to the free node with the larger share */
		int p = (c->wa >= c->wb && !held(b, c->a)) || held(b, c->b) ? c->a : c->b;
		double w = p == c->a ? c->wa : c->wb, after, force;

		if (!(c->phi < edge_clearance(b)))
			continue;
		force = c->k * (edge_clearance(b) - c->phi) * w;
		after = v3_dot(v3_load(y1 + n3 + 3 * p), n);
		if (collide_add_event(col, step, p, CONTACT_OBSTACLE, -1, c->obstacle,
		    v3_load(c->q), n, after - b->beta * force / cl->mass[p], after) != 0)
			return -1;
	}
	if (b->ct != NULL) {
		for (i = 0; i < b->ct->n; i++)
			b->ct->pair[i].active = false;
		for (i = 0; i < b->nlive; i++)	/* find_resets': those that push */
			b->ct->pair[b->live[i]].active = true;
	}
	return 0;
}

void
bdf2_commit(struct bdf2 *b, double h, const double *y0, const double *y1,
    const unsigned char *moved, double h_next)
{
	const struct cloth *cl = b->fo->cl;
	size_t n3 = 3 * (size_t)cl->n;
	double *xp = b->hist, *vp = b->hist + n3;
	int p, k;

	memcpy(b->hist, y0, 2 * n3 * sizeof *b->hist);
	for (p = 0; p < cl->n; p++) {
		vec3 x1 = v3_load(y1 + 3 * p), v1 = v3_load(y1 + n3 + 3 * p);
		vec3 back = v3_madd(x1, v1, -h);	/* where it was at its new velocity */

		if (moved != NULL && moved[p]) {
			v3_store(xp + 3 * p, back);
			v3_store(vp + 3 * p, v1);
			continue;
		}
		for (k = 0; k < b->nreset[p]; k++) {
			vec3 e = v3_load(b->rdir + 9 * p + 3 * k), xo = v3_load(xp + 3 * p);
			vec3 vo = v3_load(vp + 3 * p);

			v3_store(xp + 3 * p, v3_madd(xo, e, v3_dot(v3_sub(back, xo), e)));
			v3_store(vp + 3 * p, v3_madd(vo, e, v3_dot(v3_sub(v1, vo), e)));
		}
	}
	b->has_hist = true;
	b->h_hist = h;
	if (h_next != h)
		respace_history(b, h_next, y1);
}

void
bdf2_set_history(struct bdf2 *b, const double *hist, double h_hist)
{
	b->has_hist = hist != NULL;
	b->h_hist = h_hist;
	if (hist != NULL)
		memcpy(b->hist, hist, 6 * (size_t)b->fo->cl->n * sizeof *b->hist);
}
