/* jacobian.h: the Jacobian of forces.c's internal forces at one state,
 * kept per element, and its product with a vector.
 *
 * It holds K, a positive semidefinite stand-in for -df/dx, and C = -df/dv:
 *   - a spring's exact stiffness, with its transverse part k(1 - L/l)
 *     clamped at 0 when the spring is shorter than its rest length (a
 *     compressed spring's transverse stiffness is negative, and would make
 *     the system indefinite);
 *   - a corner's and a hinge's Gauss-Newton part k J^T J, with J the
 *     gradient of its cos(phi) or curvature binormal (exact at rest, where
 *     the dropped term vanishes);
 *   - C from the spring dashpots and the mass-proportional damping.
 * Nothing is assembled: a product costs about one force evaluation. */
#ifndef DRAPE_JACOBIAN_H
#define DRAPE_JACOBIAN_H

#include "blockmat.h"
#include "forces.h"

struct jacobian {
	const struct forces *fo;
	double *spring;		/* 5 per spring: unit vector u, k, clamped k(1 - L/l) */
	double *corner;		/* 6 per corner: d cos(phi)/dx at a and at b */
	double *hinge;		/* 10 per hinge: e1, e2, kb, 1/D */
};

int jacobian_init(struct jacobian *jc, const struct forces *fo);
void jacobian_free(struct jacobian *jc);

/* Takes the elements' linearisation at positions x (3n). */
void jacobian_eval(struct jacobian *jc, const double *x);

/* out = (ck*K + cc*C_springs) p for 3n-vectors p: the mass-proportional
 * damping (fo->damping * M) is left to the caller, being diagonal. */
void jacobian_mul(const struct jacobian *jc, double ck, double cc, const double *p, double *out);

/* blocks += the 3 x 3 blocks on the diagonal of ck*K + cc*C_springs, one
 * row-major block of 9 per node (for a preconditioner). */
void jacobian_block_diag(const struct jacobian *jc, double ck, double cc, double *blocks);

/* A += ck*K + cc*C_springs, block by block (A has the pattern of the
 * cloth's elements and their slots, blockmat_init_cloth's): the same
 * matrix jacobian_mul applies, for a solver that needs it assembled. */
void jacobian_assemble(const struct jacobian *jc, double ck, double cc, struct blockmat *A);

#endif
