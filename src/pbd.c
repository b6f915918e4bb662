/* pbd.c: substeps with the yarns solved along their lines (see pbd.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collide.h"
#include "contacts.h"
#include "obstacle.h"
#include "pbd.h"
#include "vec3.h"

/* A node's clearance over an analytic obstacle, in cloth thicknesses: the
 * substeps keep a node this far out, so that the step ends outside. */
#define OBSTACLE_CLEARANCE 0.25

/* The substep's h*omega_bound for bending, the one stiffness taken
 * explicitly (see pbd_substep). */
#define SUBSTEP_OMEGA 1.8

/*
 * Each hinge's dashpot, c = BEND_DAMPING times the substep (forces.h):
 * the one stiffness taken explicitly is the one whose modes near the
 * substep's scale kept all their energy. The constraint solves damp the
 * stretch's and the shear's there as backward Euler does; symplectic
 * Euler damps nothing, and in a pile the fold limiter's force, which is
 * not a gradient past the limit, feeds them: the strip's bottom layer
 * rang at about 110 Hz (8 substeps, +-0.4 m/s within the substeps), its
 * pile's mean kinetic energy from 2.4 to 3 s 3.99e-6 J, 26 times RK4's,
 * whatever the mass damping (3.82e-6 J at ten times the strip's). A
 * stiffness-proportional dashpot gives a mode of frequency w the
 * damping ratio c w / 2: at 0.25 up to 0.23 for the substep's fastest
 * bending (hs w up to 1.8), 0.009 for a 10 Hz mode of the strip (hs =
 * 1.19 ms), and less as the substep shrinks; at rest it has no force,
 * so the statics are the model's (the cantilever's chord 41.485 degrees
 * either way). It damps the rate of |kb| alone: on kb's whole rate a
 * bent hinge turning as a whole at w would lose c k |kb|^2 w^2 of power.
 * The pile's energy is then 1.39e-7 J, 0.91 times RK4's; and with no
 * damping the fold limiter's gain is gone where it was largest: the
 * tablecloth at most 3.5 % over its start energy (47.8 % before), the
 * peers' table at 25^2 (bench/lib.sh) never over it (438 %). Taken
 * explicitly it is stable while hs^2 w^2 BEND_DAMPING < 2: 0.81 at the
 * substep's bound.
 */
#define BEND_DAMPING 0.25

/* The springs of one family in lines: along the warp (i, j)-(i+1, j), or
 * the weft (i, j)-(i, j+1); a missing spring (the disc's rim) ends a line. */
static int
build_lines(struct pbd_lines *ln, const struct cloth *cl, bool warp)
{
	int *next = malloc(((size_t)cl->n + 1) * sizeof *next), p, outer, inner, a, b, k = 0, l = 0;
	size_t s;

	ln->start = malloc((cl->nsprings + 2) * sizeof *ln->start);
	ln->spring = malloc((cl->nsprings + 1) * sizeof *ln->spring);
	if (next == NULL || ln->start == NULL || ln->spring == NULL) {
		free(next);
		return -1;
	}
	for (p = 0; p < cl->n; p++)
		next[p] = -1;
	for (s = 0; s < cl->nsprings; s++) {
		int ia, ja, ib, jb;

		cloth_grid_ij(cl, cl->springs[s].a, &ia, &ja);
		cloth_grid_ij(cl, cl->springs[s].b, &ib, &jb);
		if ((ja == jb) == warp)
			next[cl->springs[s].a] = (int)s;
	}
	outer = warp ? cl->nv : cl->nu;
	inner = warp ? cl->nu : cl->nv;
	for (a = 0; a < outer; a++) {
		bool open = false;

		for (b = 0; b < inner; b++) {
			int q = warp ? cloth_node(cl, b, a) : cloth_node(cl, a, b);

			if (q < 0 || next[q] < 0) {
				open = false;
				continue;
			}
			if (!open)
				ln->start[l++] = k;
			open = true;
			ln->spring[k++] = next[q];
		}
	}
	ln->start[l] = k;
	ln->nlines = l;
	free(next);
	return 0;
}

static void
free_lines(struct pbd_lines *ln)
{
	free(ln->start);
	free(ln->spring);
	memset(ln, 0, sizeof *ln);
}

/*
 * The shear sweep's order. In the cloth's own order a square's four
 * corners come one after another, each reading the nodes the one before
 * has just moved: a chain of square roots and divisions that the
 * processor cannot overlap (a quarter of the strip's time). Sorted by the
 * colour of the corner's square, (i mod 2, j mod 2), then by which of the
 * square's corners it is, neighbours in the sweep belong to squares two
 * apart, which share no node, so one corner's work overlaps the next's.
 * It is still a Gauss-Seidel sweep, each corner seeing every move before
 * it, in another order (the graph colouring of Fratarcangeli et al. 2016,
 * "Vivace", used here for one core's pipeline rather than for threads).
 */
static int
corner_class(const struct cloth *cl, const struct corner *co)
{
	int ia, ja, ib, jb, ic, jc, i, j;

	cloth_grid_ij(cl, co->a, &ia, &ja);
	cloth_grid_ij(cl, co->b, &ib, &jb);
	cloth_grid_ij(cl, co->c, &ic, &jc);
	i = ia < ib ? ia : ib;
	i = ic < i ? ic : i;
	j = ja < jb ? ja : jb;
	j = jc < j ? jc : j;
	/* the square is (i, j); the corner sits at one of its four nodes */
	return 4 * ((i & 1) + 2 * (j & 1)) + (ic - i) + 2 * (jc - j);
}

/* A counting sort on corner_class, stable, so the order is fixed. */
static int
order_corners(struct pbd *pb, const struct cloth *cl)
{
	size_t start[17] = { 0 }, s;
	int k;

	pb->corner_order = malloc((cl->ncorners + 1) * sizeof *pb->corner_order);
	if (pb->corner_order == NULL)
		return -1;
	for (s = 0; s < cl->ncorners; s++)
		start[corner_class(cl, &cl->corners[s]) + 1]++;
	for (k = 1; k < 17; k++)
		start[k] += start[k - 1];
	for (s = 0; s < cl->ncorners; s++)
		pb->corner_order[start[corner_class(cl, &cl->corners[s])]++] = s;
	return 0;
}

double
pbd_substep(const struct forces *fo, double dt)
{
	double omega = cloth_omega_bound_bend(fo->cl), damp = fo->damping;
	/* symplectic Euler is stable for h*omega < 2 and a rate h*c < 2; the
	 * Gershgorin bound is above the highest frequency at rest by a factor
	 * of about 1.5 to 3, and the fold limiter keeps a bent hinge within it
	 * (pbd_step) */
	double h = dt;

	if (omega > 0 && SUBSTEP_OMEGA / omega < h)
		h = SUBSTEP_OMEGA / omega;
	if (damp > 0 && 1 / damp < h)
		h = 1 / damp;
	return h;
}

int
pbd_init(struct pbd *pb, const struct scene *sc, const struct forces *fo,
    const struct prescribed *pr, double dt)
{
	const struct cloth *cl = fo->cl;
	size_t n3 = 3 * (size_t)cl->n, ns = cl->nsprings + 1;
	int p;

	memset(pb, 0, sizeof *pb);
	pb->sc = sc;
	pb->fo = fo;
	pb->pr = pr;
	pb->substep = pbd_substep(fo, dt);
	pb->omega_bend = cloth_omega_bound_bend(cl);
	if (build_lines(&pb->line[0], cl, true) != 0 || build_lines(&pb->line[1], cl, false) != 0 ||
	    (pb->w = malloc(((size_t)cl->n + 1) * sizeof *pb->w)) == NULL ||
	    (pb->a = malloc(n3 * sizeof *pb->a)) == NULL ||
	    (pb->xprev = malloc(n3 * sizeof *pb->xprev)) == NULL ||
	    (pb->xs = malloc(n3 * sizeof *pb->xs)) == NULL ||
	    (pb->vs = malloc(n3 * sizeof *pb->vs)) == NULL ||
	    (pb->diag = malloc(ns * sizeof *pb->diag)) == NULL ||
	    (pb->off = malloc(ns * sizeof *pb->off)) == NULL ||
	    (pb->rhs = malloc(ns * sizeof *pb->rhs)) == NULL ||
	    (pb->dir = malloc(3 * ns * sizeof *pb->dir)) == NULL ||
	    (pb->row = malloc(((size_t)cl->n + 1) * sizeof *pb->row)) == NULL ||
	    (pb->touch = malloc(((size_t)cl->n + 1) * sizeof *pb->touch)) == NULL ||
	    (pb->touch_at = malloc((6 * (size_t)cl->n + 1) * sizeof *pb->touch_at)) == NULL ||
	    (pb->edge_near = malloc((cl->nedges + 1) * sizeof *pb->edge_near)) == NULL ||
	    order_corners(pb, cl) != 0) {
		pbd_free(pb);
		return -1;
	}
	for (p = 0; p < cl->n; p++) {
		pb->w[p] = pr->held[p] || !(cl->mass[p] > 0) ? 0 : 1 / cl->mass[p];
		pb->touch[p] = -1;
	}
	return 0;
}

void
pbd_free(struct pbd *pb)
{
	free_lines(&pb->line[0]);
	free_lines(&pb->line[1]);
	free(pb->w);
	free(pb->a);
	free(pb->xprev);
	free(pb->xs);
	free(pb->vs);
	free(pb->diag);
	free(pb->off);
	free(pb->rhs);
	free(pb->dir);
	free(pb->row);
	free(pb->corner_order);
	free(pb->touch);
	free(pb->touch_at);
	free(pb->edge_near);
	memset(pb, 0, sizeof *pb);
}

/* Lines solved side by side in Thomas's passes (thomas_lines). */
#define LINES_TOGETHER 4

/* Line l's system: directions, diagonal, right-hand side and coupling. */
static void
line_system(struct pbd *pb, const struct pbd_lines *ln, int l, double h, double g, const double *x)
{
	const struct cloth *cl = pb->fo->cl;
	int lo = ln->start[l], hi = ln->start[l + 1], k;

	for (k = lo; k < hi; k++) {
		const struct spring *sp = &cl->springs[ln->spring[k]];
		vec3 d = v3_sub(v3_load(x + 3 * sp->b), v3_load(x + 3 * sp->a));
		double len = v3_len(d), c;
		vec3 u = len > 0 ? v3_scale(d, 1 / len) : v3(0, 0, 0);

		v3_store(pb->dir + 3 * k, u);
		c = len - sp->rest;
		if (g > 0) {
			vec3 dd = v3_sub(v3_sub(v3_load(x + 3 * sp->b), v3_load(pb->xprev + 3 * sp->b)),
			    v3_sub(v3_load(x + 3 * sp->a), v3_load(pb->xprev + 3 * sp->a)));

			c += g * v3_dot(u, dd);
		}
		pb->diag[k] = pb->w[sp->a] + pb->w[sp->b] + 1 / (sp->k * h * h * (1 + g));
		pb->rhs[k] = -c / (1 + g);
	}
	/* consecutive springs share a node: the coupling */
	for (k = lo; k + 1 < hi; k++)
		pb->off[k] = -pb->w[cl->springs[ln->spring[k]].b] *
		    v3_dot(v3_load(pb->dir + 3 * k), v3_load(pb->dir + 3 * (k + 1)));
}

/*
 * Thomas's passes over lines [l0, l1) side by side: element k of each in
 * turn. A line's pass is a chain of divisions, each waiting for the one
 * before; the lines' chains are independent, so taken together the
 * processor overlaps them. Each line's arithmetic is what it would be
 * alone, in the same order.
 */
static void
thomas_lines(struct pbd *pb, const struct pbd_lines *ln, int l0, int l1)
{
	int l, k, most = 0;

	for (l = l0; l < l1; l++) {
		int len = ln->start[l + 1] - ln->start[l];

		most = len > most ? len : most;
	}
	for (k = 1; k < most; k++)
		for (l = l0; l < l1; l++) {
			int at = ln->start[l] + k;
			double m;

			if (at >= ln->start[l + 1])
				continue;
			m = pb->off[at - 1] / pb->diag[at - 1];
			pb->diag[at] -= m * pb->off[at - 1];
			pb->rhs[at] -= m * pb->rhs[at - 1];
		}
	for (l = l0; l < l1; l++)
		if (ln->start[l + 1] > ln->start[l])
			pb->rhs[ln->start[l + 1] - 1] /= pb->diag[ln->start[l + 1] - 1];
	for (k = most - 2; k >= 0; k--)
		for (l = l0; l < l1; l++) {
			int at = ln->start[l] + k;

			if (at + 1 >= ln->start[l + 1])
				continue;
			pb->rhs[at] = (pb->rhs[at] - pb->off[at] * pb->rhs[at + 1]) / pb->diag[at];
		}
}

/*
 * One family's lines, each solved at once. For line springs k = 0..m-1
 * between nodes n_k and n_k+1, direction u_k and violation C_k, the XPBD
 * update (lambda starts at 0 every substep) solves
 *   (J W J' + a~/(1 + g)) dl = -(C + g J dx)/(1 + g),
 * a~ = 1/(k h^2) the compliance, g = spring_damping/h the dashpot's share
 * (Macklin et al. 2016, eq. 26, its rows divided by 1 + g so that the
 * system stays symmetric), dx the motion since the substep began: J W J'
 * is tridiagonal, w_a + w_b on the diagonal and -w(n_k+1) u_k.u_k+1 beside
 * it. Then x += W J' dl. A family's lines share no node, so four at a
 * time have their systems built, solved side by side (thomas_lines) and
 * then applied.
 */
static void
solve_family(struct pbd *pb, const struct pbd_lines *ln, double h, double *x)
{
	const struct cloth *cl = pb->fo->cl;
	double g = pb->fo->spring_damping / h;
	int l0, l;

	for (l0 = 0; l0 < ln->nlines; l0 += LINES_TOGETHER) {
		int l1 = l0 + LINES_TOGETHER < ln->nlines ? l0 + LINES_TOGETHER : ln->nlines;

		if ((l0 & 63) == 0 && forces_stopped(pb->fo))
			return;		/* the step is dropped (pbd_step) */
		for (l = l0; l < l1; l++)
			line_system(pb, ln, l, h, g, x);
		thomas_lines(pb, ln, l0, l1);
		for (l = l0; l < l1; l++) {
			int k;

			for (k = ln->start[l]; k < ln->start[l + 1]; k++) {
				const struct spring *sp = &cl->springs[ln->spring[k]];
				vec3 du = v3_scale(v3_load(pb->dir + 3 * k), pb->rhs[k]);

				v3_store(x + 3 * sp->a, v3_madd(v3_load(x + 3 * sp->a), du, -pb->w[sp->a]));
				v3_store(x + 3 * sp->b, v3_madd(v3_load(x + 3 * sp->b), du, pb->w[sp->b]));
			}
		}
	}
}

/*
 * Shear as compliant constraints, one Gauss-Seidel sweep over the corners
 * a substep in colour order (order_corners); XPBD, Macklin et al. 2016: a
 * corner's energy k c^2/2, c the cosine of its angle (forces.c add_shear),
 * is the constraint C = c with compliance 1/k, so that (lambda starting at
 * 0) dl = -c / (sum w |grad c|^2 + 1/(k h^2)) and x += w grad(c) dl. Taken
 * explicitly, shear set the substep: its frequency is 8.6 times bending's
 * on the shipped tablecloth (1975 against 231 rad/s, Gershgorin), so 11
 * substeps a 10 ms step where bending alone needs 2. At a substep of
 * milliseconds k h^2 |grad c|^2 / m is below one on cotton jersey (0.2-0.4
 * on the tablecloth at 1.6 ms: the shear is soft beside the stretch, whose
 * is some 40), where one sweep a substep resolves it well, and the statics
 * are the energy's: at rest every corner's sweep leaves it where its
 * compliance balances the other forces.
 */
static void
solve_shear(struct pbd *pb, double h, double *x)
{
	const struct cloth *cl = pb->fo->cl;
	size_t s;

	for (s = 0; s < cl->ncorners; s++) {
		const struct corner *co = &cl->corners[pb->corner_order[s]];
		double wa = pb->w[co->a], wb = pb->w[co->b], wc = pb->w[co->c];
		vec3 xc, e1, e2, ga, gb, gc;
		double l1s, l2s, q, inv12, c, den, dl;

		if (forces_poll(pb->fo, s))
			return;		/* the step is dropped (pbd_step) */
		if (wa + wb + wc == 0 || !(co->k > 0))
			continue;
		xc = v3_load(x + 3 * co->c);
		e1 = v3_sub(v3_load(x + 3 * co->a), xc);
		e2 = v3_sub(v3_load(x + 3 * co->b), xc);
		l1s = v3_dot(e1, e1);
		l2s = v3_dot(e2, e2);
		if (l1s == 0 || l2s == 0)
			continue;
		q = 1 / (l1s * l2s);
		inv12 = sqrt(q);		/* 1/(|e1||e2|) */
		c = v3_dot(e1, e2) * inv12;
		/* grad_a c = e2/(|e1||e2|) - c e1/|e1|^2, grad_b alike, grad_c
		 * their negated sum */
		ga = v3_madd(v3_scale(e2, inv12), e1, -c * l2s * q);
		gb = v3_madd(v3_scale(e1, inv12), e2, -c * l1s * q);
		gc = v3_neg(v3_add(ga, gb));
		/* |ga|^2 = (1 - c^2)/|e1|^2, |gb|^2 = (1 - c^2)/|e2|^2 and
		 * ga.gb = -c (1 - c^2)/(|e1||e2|): from the scalars, beside the
		 * gradients rather than after them (5 % of a run's time) */
		den = (1 - c * c) * ((wa + wc) * l2s * q + (wb + wc) * l1s * q - 2 * wc * c * inv12) +
		    1 / (co->k * h * h);
		dl = -c / den;
		v3_store(x + 3 * co->a, v3_madd(v3_load(x + 3 * co->a), ga, wa * dl));
		v3_store(x + 3 * co->b, v3_madd(v3_load(x + 3 * co->b), gb, wb * dl));
		v3_store(x + 3 * co->c, v3_madd(xc, gc, wc * dl));
	}
}

/*
 * A cloth edge over a box's edge can cut its corner with both its nodes
 * kept out: the tablecloth's edges went up to 4.2 mm into its box (drape
 * check, which searches along the edges), a cloth 0.55 mm thick. So each
 * substep also takes the edges near a box, and one whose deepest point
 * comes nearer than half the nodes' clearance is moved out along the
 * box's face normal there by what it lacks, its two nodes by their
 * inverse masses and their shares of that point: the edge's own contact
 * (Bridson, Fedkiw and Anderson 2002, sec. 7.1), as contacts_project does
 * for edge pairs. Half the clearance, so that an edge lying along a face
 * (its nodes at the clearance) is never a candidate, whatever the
 * roundings. No friction on the edge's point: Coulomb's cut, taken as for
 * a node, threw the peers' table's cloth (mu 0.1) to 9 times its energy
 * undamped; the nodes' own contacts hold it. Boxes only: on the Cusick
 * disc's rim (a ternary search along the edge) the undamped drape slid
 * off and its energy spiked to 1760 J at 1.5 s. The tablecloth: 75
 * edges 4.18 mm into its box at most before, 1 and 0.08 mm now.
 */
#define EDGE_CLEARANCE 0.5
#define EDGE_PASSES 4

static void
edges_out(struct pbd *pb, double *x, int o, const struct obstacle *ob, double margin)
{
	const struct cloth *cl = pb->fo->cl;
	vec3 lo = v3_sub(ob->lo, v3(margin, margin, margin));
	vec3 hi = v3_add(ob->hi, v3(margin, margin, margin));
	size_t e, k, ncand = 0;
	int pass, moved = 1;

	for (e = 0; e < cl->nedges; e++) {
		vec3 a = v3_load(x + 3 * cl->edge[2 * e]), b = v3_load(x + 3 * cl->edge[2 * e + 1]);

		/* both ends beyond one face of the grown box: the edge too */
		if (!((a.x < lo.x && b.x < lo.x) || (a.y < lo.y && b.y < lo.y) ||
		    (a.z < lo.z && b.z < lo.z) || (a.x > hi.x && b.x > hi.x) ||
		    (a.y > hi.y && b.y > hi.y) || (a.z > hi.z && b.z > hi.z)))
			pb->edge_near[ncand++] = e;
	}
	/* an edge's push moves its neighbours' nodes: a few passes, until one
	 * moves nothing (one left the tablecloth's edges 0.70 mm in) */
	for (pass = 0; pass < EDGE_PASSES && moved; pass++)
		for (k = 0, moved = 0; k < ncand; k++) {
			int pa = cl->edge[2 * pb->edge_near[k]], pb_ = cl->edge[2 * pb->edge_near[k] + 1];
			vec3 a = v3_load(x + 3 * pa), b = v3_load(x + 3 * pb_), n, q;
			double wa = pb->w[pa], wb = pb->w[pb_], t = 0, lack, den;

			lack = obstacle_box_segment_depth(lo, hi, a, b, &t, &n);
			/* an end lacking it is the nodes' contact, not the edge's */
			if (!(lack > 0) || t <= 0 || t >= 1)
				continue;
			den = wa * (1 - t) * (1 - t) + wb * t * t;
			if (!(den > 0))
				continue;
			/* the box's face under the edge's point */
			q = v3_madd(v3_madd(a, v3_sub(b, a), t), n, lack - margin);
			lack /= den;
			v3_store(x + 3 * pa, v3_madd(a, n, wa * (1 - t) * lack));
			v3_store(x + 3 * pb_, v3_madd(b, n, wb * t * lack));
			/* the event goes to the node with the larger share */
			pa = t < 0.5 ? pa : pb_;
			if (pb->touch[pa] < 0) {
				pb->touch[pa] = o;
				v3_store(pb->touch_at + 6 * pa, q);
				v3_store(pb->touch_at + 6 * pa + 3, n);
			}
			moved = 1;
		}
}

/*
 * The face of a box (grown by the clearance c) through which a node moving
 * from a to b went in: the slabs' test of a ray against a box, the face
 * of the last slab entered, if the segment enters the box by it. Into *q
 * and *n the point of the box's face it goes back out to and the face's
 * normal; 0 when a was already inside (the nearest face then) or the
 * segment meets the box nowhere. A node that the substep before left on a
 * grown face, to its roundings, is outside it: its velocity still points
 * in. The nearest face is the wrong one for a node that came down on a
 * box's edge: the tablecloth's row at z = -0.08 m lies on the box's side
 * plane, and a substep that took it 3 mm below the top put it back beside
 * the box, 3 mm low, stretching its springs to the row on the top; the
 * springs then threw the cloth up off the box. Undamped, the tablecloth's
 * energy rose 56 % above its start (10 % in the step at 0.08 s), the
 * peers' table's 8.1 %; with the entry face 3.5 % and 0.
 */
static int
box_entry(const struct obstacle *ob, double c, vec3 a, vec3 b, vec3 *q, vec3 *n)
{
	double lo[3] = { ob->lo.x - c, ob->lo.y - c, ob->lo.z - c };
	double hi[3] = { ob->hi.x + c, ob->hi.y + c, ob->hi.z + c };
	double pa[3] = { a.x, a.y, a.z }, pb[3] = { b.x, b.y, b.z }, slack = 1e-6 * c;
	double enter = -INFINITY, leave = INFINITY, at[3], out[3] = { 0, 0, 0 };
	int k, axis = -1;

	for (k = 0; k < 3; k++) {
		double d = pb[k] - pa[k], t0, t1;

		if (d == 0) {
			if (pa[k] < lo[k] - slack || pa[k] > hi[k] + slack)
				return 0;
			continue;
		}
		t0 = (lo[k] - pa[k]) / d;
		t1 = (hi[k] - pa[k]) / d;
		if (t0 > t1) {
			double tt = t0;

			t0 = t1;
			t1 = tt;
		}
		/* entered this slab last, at t0: by its face, unless a was
		 * within it from the start (more than slack inside) */
		if (t0 > enter) {
			enter = t0;
			axis = t0 * fabs(d) > -slack ? k : -1;
		}
		leave = fmin(leave, t1);
	}
	if (axis < 0 || enter > leave || enter > 1)
		return 0;
	for (k = 0; k < 3; k++)		/* where it entered */
		at[k] = k == axis ? (pb[axis] > pa[axis] ? lo[k] : hi[k]) : pa[k] + enter * (pb[k] - pa[k]);
	out[axis] = pb[axis] > pa[axis] ? -1 : 1;
	*n = v3(out[0], out[1], out[2]);
	*q = v3_madd(v3(at[0], at[1], at[2]), *n, -c);
	return 1;
}

/* Nodes inside an analytic obstacle (or nearer than the clearance) back
 * on it, their motion along it held by Coulomb friction: static while the
 * tangential motion of the substep is under mu times the push out, else
 * cut by that much. */
static void
obstacles(struct pbd *pb, double *x)
{
	const struct scene *sc = pb->sc;
	const struct cloth *cl = pb->fo->cl;
	double clear = OBSTACLE_CLEARANCE * sc->mat.thickness;
	size_t o;
	int p;

	for (o = 0; o < sc->nobstacles; o++) {
		const struct obstacle *ob = &sc->obstacles[o];
		vec3 lo, hi;

		if (ob->kind == OBSTACLE_MESH)
			continue;
		/* a node farther than the clearance from the solid's bounds,
		 * with a margin over the distance's roundings, is farther from
		 * the solid: most nodes, most substeps, for a test of six
		 * comparisons where the distance costs some 70 instructions */
		obstacle_bounds(ob, &lo, &hi);
		lo = v3_sub(lo, v3(clear, clear, clear));
		hi = v3_add(hi, v3(clear, clear, clear));
		lo = v3_sub(lo, v3_scale(v3(fabs(lo.x), fabs(lo.y), fabs(lo.z)), 1e-9));
		hi = v3_add(hi, v3_scale(v3(fabs(hi.x), fabs(hi.y), fabs(hi.z)), 1e-9));
		for (p = 0; p < cl->n; p++) {
			vec3 xp = v3_load(x + 3 * p), q, n, dx, dt;
			double d, push, slip;

			if (pb->w[p] == 0 || xp.x < lo.x || xp.y < lo.y || xp.z < lo.z ||
			    xp.x > hi.x || xp.y > hi.y || xp.z > hi.z ||
			    (d = obstacle_distance(ob, xp, &q, &n)) >= clear)
				continue;
			if (ob->kind == OBSTACLE_BOX &&
			    box_entry(ob, clear, v3_load(pb->xprev + 3 * p), xp, &q, &n)) {
				d = v3_dot(v3_sub(xp, q), n);	/* along the face it came in by */
				if (d >= clear)
					continue;
			}
			push = clear - d;
			xp = v3_madd(xp, n, push);
			dx = v3_sub(xp, v3_load(pb->xprev + 3 * p));
			dt = v3_madd(dx, n, -v3_dot(dx, n));
			slip = v3_len(dt);
			if (ob->friction > 0 && slip > 0) {
				double cut = ob->friction * push;

				xp = v3_madd(xp, dt, -(slip <= cut ? 1 : cut / slip));
			}
			v3_store(x + 3 * p, xp);
			pb->touch[p] = (int)o;
			v3_store(pb->touch_at + 6 * p, q);
			v3_store(pb->touch_at + 6 * p + 3, n);
		}
		if (ob->kind == OBSTACLE_BOX)
			edges_out(pb, x, (int)o, ob, EDGE_CLEARANCE * clear);
	}
}

/*
 * The substep a state allows, beside bending's: the line solves move each
 * node along its springs' present directions, so a taut yarn's sideways
 * motion (its stiffness T/l per spring, the geometric stiffness of the
 * tension T) is taken explicitly. Its bound is Gershgorin's, 2 T/l a
 * spring at each end, over the node's mass; a hanging catenary at a 10 ms
 * substep tore, and the tablecloth's impacts crumpled it, where this
 * bound holds them. Without it the substep was shear's, which is solved
 * as a constraint now (solve_shear).
 */
static double
tension_omega2(const struct pbd *pb, const double *x)
{
	const struct cloth *cl = pb->fo->cl;
	double w2 = 0;
	size_t s;
	int p;

	for (p = 0; p < cl->n; p++)
		pb->row[p] = 0;
	for (s = 0; s < cl->nsprings; s++) {
		const struct spring *sp = &cl->springs[s];
		double len = v3_len(v3_sub(v3_load(x + 3 * sp->b), v3_load(x + 3 * sp->a)));
		double tension = sp->k * (len - sp->rest);

		if (tension > 0 && len > 0) {
			pb->row[sp->a] += 2 * tension / len;
			pb->row[sp->b] += 2 * tension / len;
		}
	}
	for (p = 0; p < cl->n; p++)
		if (pb->row[p] * pb->w[p] > w2)
			w2 = pb->row[p] * pb->w[p];
	return w2;
}

void
pbd_step(struct pbd *pb, double t, double h, const double *y, double *y_out, struct contacts *ct)
{
	const struct cloth *cl = pb->fo->cl;
	size_t n3 = 3 * (size_t)cl->n, i;
	double hs, fold = 0, w2 = tension_omega2(pb, y), sub = pb->substep, want;
	int nsub, s;

	/* the two bounds' rows add: omega^2 at most the sum of theirs */
	if (w2 > 0)
		sub = fmin(sub, SUBSTEP_OMEGA / sqrt(w2 + pb->omega_bend * pb->omega_bend));
	/* counted in a double, bounded before it is an int (PBD_MAX_SUBSTEPS;
	 * NaN, from a state already blown up, is one) */
	want = ceil(h / sub * (1 - 1e-12));
	nsub = want >= PBD_MAX_SUBSTEPS ? PBD_MAX_SUBSTEPS : want >= 1 ? (int)want : 1;
	hs = h / nsub;
	/* the fold limiter: a hinge at most as stiff as the substep's bound
	 * hs omega < SUBSTEP_OMEGA allows, and at least twice its stiffness at
	 * rest (Gershgorin's bound is above the true frequency by 1.5 to 3,
	 * pbd_substep) */
	if (pb->omega_bend > 0) {
		double share = pow(SUBSTEP_OMEGA / (hs * pb->omega_bend), 2);

		fold = forces_fold_limit(fmax(share, 2));
	}
	memcpy(pb->xs, y, n3 * sizeof *pb->xs);
	memcpy(pb->vs, y + n3, n3 * sizeof *pb->vs);
	for (i = 0; i < (size_t)cl->n; i++)
		pb->touch[i] = -1;
	for (s = 0; s < nsub && !forces_stopped(pb->fo); s++) {
		double ts = t + s * hs, te = s + 1 == nsub ? t + h : t + (s + 1) * hs;

		forces_accel_bending(pb->fo, ts, pb->xs, pb->vs, pb->a, fold, BEND_DAMPING * hs);
		memcpy(pb->xprev, pb->xs, n3 * sizeof *pb->xs);
		for (i = 0; i < n3; i++) {
			if (pb->w[i / 3] == 0)
				continue;
			pb->vs[i] += hs * pb->a[i];
			pb->xs[i] += hs * pb->vs[i];
		}
		prescribed_apply(pb->pr, cl, te, pb->xs, NULL);
		/* the solids before the line solves as well as after: with them
		 * after only, the solves drew the cloth into the box's edge
		 * and the push back out came back as motion (the undamped
		 * tablecloth 3.5 % over its start, 6.2 % with its edges kept
		 * out; 0 both ways now) */
		obstacles(pb, pb->xs);
		solve_shear(pb, hs, pb->xs);
		solve_family(pb, &pb->line[0], hs, pb->xs);
		solve_family(pb, &pb->line[1], hs, pb->xs);
		if (ct != NULL)
			contacts_project(ct, pb->w, pb->xs, pb->xprev);
		obstacles(pb, pb->xs);
		for (i = 0; i < n3; i++)
			pb->vs[i] = (pb->xs[i] - pb->xprev[i]) / hs;
		prescribed_apply(pb->pr, cl, te, NULL, pb->vs);
		pb->substeps++;
	}
	memcpy(y_out, pb->xs, n3 * sizeof *y_out);
	memcpy(y_out + n3, pb->vs, n3 * sizeof *y_out);
}

int
pbd_events(const struct pbd *pb, struct collide *col, long step, const double *y0,
    const double *y1)
{
	size_t n3 = 3 * (size_t)pb->fo->cl->n;
	int p;

	for (p = 0; p < pb->fo->cl->n; p++) {
		vec3 n;

		if (pb->touch[p] < 0)
			continue;
		n = v3_load(pb->touch_at + 6 * p + 3);
		if (collide_add_event(col, step, p, CONTACT_OBSTACLE, -1, pb->touch[p],
		    v3_load(pb->touch_at + 6 * p), n, v3_dot(v3_load(y0 + n3 + 3 * p), n),
		    v3_dot(v3_load(y1 + n3 + 3 * p), n)) != 0)
			return -1;
	}
	return 0;
}
