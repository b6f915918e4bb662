/* blockmat.h: a symmetric matrix of 3 x 3 blocks over the cloth's nodes,
 * with the pattern its elements couple: a spring's two ends, a corner's
 * three nodes, a hinge's three (13 blocks a row inside a square grid).
 * The Newton system of the implicit step (bdf2.h) is assembled into one
 * each iteration, then applied and smoothed by its solver (mg.h). Both
 * triangles are stored, by rows, so that a product or a sweep over a row
 * reads one contiguous run of blocks. */
#ifndef DRAPE_BLOCKMAT_H
#define DRAPE_BLOCKMAT_H

#include <stddef.h>

#include "cloth.h"

struct blockmat {
	int n;			/* block rows: the nodes */
	int *start;		/* n + 1: row p's blocks are [start[p], start[p + 1]) */
	int *col;		/* their columns, ascending; every row holds its diagonal */
	int *diag;		/* n: the index of row p's diagonal block */
	double *val;		/* 9 doubles a block, row-major */
	size_t nblocks;
	/* blockmat_init_cloth's: where each element's blocks are, so that an
	 * assembly looks nothing up: a spring's (a, b) and (b, a); a corner's
	 * and a hinge's 3 x 3, row by row in the order (c, a, b) and (a, b,
	 * c). NULL for a general pattern. */
	int *spring_slot, *corner_slot, *hinge_slot;
};

/* The pattern of cl's elements, values zero. 0, or -1 out of memory. */
int blockmat_init_cloth(struct blockmat *A, const struct cloth *cl);
/* A general pattern: n rows, row p's columns cols[start[p] .. start[p+1])
 * in any order, duplicates allowed; the diagonal is added where missing.
 * 0, or -1 out of memory. */
int blockmat_init_pattern(struct blockmat *A, int n, const int *start, const int *cols);
void blockmat_free(struct blockmat *A);	/* a zeroed one is fine */

void blockmat_zero(struct blockmat *A);
/* The index of block (row, col), or -1 outside the pattern. */
int blockmat_find(const struct blockmat *A, int row, int col);
/* y = A x (3n each); y must not alias x. */
void blockmat_mul(const struct blockmat *A, const double *x, double *y);

/* One block b <- b^-1, b symmetric positive definite (the cofactors over
 * the determinant): the block Jacobi preconditioners' setup. */
static inline void
block_invert_spd(double *b)
{
	double c0 = b[4] * b[8] - b[5] * b[7], c1 = b[5] * b[6] - b[3] * b[8];
	double c2 = b[3] * b[7] - b[4] * b[6], det = b[0] * c0 + b[1] * c1 + b[2] * c2;
	double r[9] = { c0, b[2] * b[7] - b[1] * b[8], b[1] * b[5] - b[2] * b[4],
	    c1, b[0] * b[8] - b[2] * b[6], b[2] * b[3] - b[0] * b[5],
	    c2, b[1] * b[6] - b[0] * b[7], b[0] * b[4] - b[1] * b[3] };
	int i;

	for (i = 0; i < 9; i++)
		b[i] = r[i] / det;
}

/* z = b r for one block b (row-major) and 3-vectors r, z. */
static inline void
block_apply(const double *b, const double *r, double *z)
{
	z[0] = b[0] * r[0] + b[1] * r[1] + b[2] * r[2];
	z[1] = b[3] * r[0] + b[4] * r[1] + b[5] * r[2];
	z[2] = b[6] * r[0] + b[7] * r[1] + b[8] * r[2];
}

#endif
