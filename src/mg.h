/* mg.h: a geometric multigrid preconditioner for the implicit step's
 * Newton system H dx = -g, H = M/beta^2 + K (+ damping, + contact blocks),
 * on the cloth's grid: one V-cycle per call, a symmetric positive definite
 * approximation of H^-1 for conjugate gradients.
 *
 * Why: the springs make H stiff (k beta^2/m of 750 on the tablecloth, 3800
 * on a 100^2 cloth, growing as 1/spacing^2, bending's as 1/spacing^4), so
 * block Jacobi leaves CG hundreds of iterations, and a sparse Cholesky
 * costs n^1.5 to refactor. A V-cycle costs O(n) and its iteration counts
 * do not grow under refinement.
 *
 * The method (U. Trottenberg, C. Oosterlee, A. Schueller, "Multigrid",
 * Academic Press 2001, ch. 2, 5.1 and 7.7 for the vector case):
 *   - levels: the grid coarsened by taking every other grid line (and the
 *     last), in both directions, or in one alone when the other has fewer
 *     than 5 lines (semi-coarsening: the 125 x 3 strip), down to 32 nodes
 *     or fewer, where a dense Cholesky solves exactly;
 *   - prolongation P: bilinear interpolation in grid (i, j) space, 3 x 3
 *     identity blocks times the weights; where the shape leaves coarse
 *     nodes out (a disc) the weights of those present are renormalised,
 *     and a node with none takes the nearest coarse node's value;
 *   - coarse operators: Galerkin, A_c = P^T A P;
 *   - smoother: block line Gauss-Seidel. The stiffness is anisotropic
 *     but always along the grid lines (warp springs along i, weft along
 *     j, whatever the cloth's 3D shape), where point relaxation stalls;
 *     each warp line's (fixed j) banded system of 3 x 3 blocks (springs,
 *     and hinges 2 apart) is solved exactly, line after line, then each
 *     weft line's (fixed i). Before the coarse correction warp then weft
 *     lines, forwards; after it weft then warp lines, backwards: the
 *     adjoint, so that the V-cycle is symmetric (and, Gauss-Seidel
 *     converging on an SPD matrix, positive definite). The lines' block
 *     LDL^T factors are made once per setup.
 * For context, R. Tamstorf, T. Jones, S. McCormick, "Smoothed aggregation
 * multigrid for cloth simulation", ACM TOG 34(6) 2015, solve the same
 * systems on unstructured meshes; the grid lets us use its lines instead.
 *
 * Costs: mg_init O(n) (patterns, lines, interpolation); mg_setup O(n)
 * (Galerkin products, line factors, the coarsest Cholesky); mg_apply O(n),
 * about 8 products with A on the finest level and a third more below.
 * Everything is deterministic (fixed loop orders, no threads, no global
 * state); nothing here prints. */
#ifndef DRAPE_MG_H
#define DRAPE_MG_H

#include "blockmat.h"
#include "cloth.h"

/* One direction's block line relaxation on one level: the level's nodes
 * in lines (dir 0: warp lines, fixed j; dir 1: weft lines, fixed i), the
 * blocks coupling each line to the others, the line systems' banded block
 * LDL^T factors. "Position" t numbers the nodes in line order (for warp
 * lines the nodes' own order: they are numbered j-major). */
struct mg_lines {
	int nlines;
	int *start;		/* nlines + 1: line l is positions [start[l], start[l+1]) */
	int *order;		/* n: the node at each position */
	int band;		/* the farthest coupling along a line, in positions */
	int *inl;		/* n * (band + 1): the level matrix's blocks (t, t - k), k = 0..band; -1 none */
	/* position t's blocks off its line, in col and val: the earlier
	 * lines' [lo[t], mid[t]), the later lines' [hi[t], lo[t + 1]) */
	int *lo, *mid, *hi;
	const int *col;		/* warp lines: the level matrix's own; weft lines: own_col */
	const double *val;	/* the same for the values (set by mg_setup) */
	/* weft lines: their off-line blocks copied in line order (contiguous
	 * for the sweeps, which would stride through the matrix's rows), and
	 * each one's block in the level matrix */
	int *own_col, *src;
	double *own_val;
	double *fac;		/* n * (band + 1) * 9: per position L(t, t - k), k = 1..band, then D_t^-1 */
};

struct mg_level {
	int nu, nv, n;		/* the level's grid and node count */
	int *grid_node;		/* nu * nv: node at (i, j) = grid_node[j*nu + i], or -1 */
	double *xu, *xv;	/* nu, nv: each grid line's place, in finest spacings */
	/* the level's matrix: on coarse levels P^T A P; on the finest the
	 * pattern alone (val NULL), the values being the caller's */
	struct blockmat A;
	const double *val;	/* the values in use: A.val, or the caller's */
	struct mg_lines lines[2];
	/* interpolation from the next coarser level: node p's value is the
	 * sum of pw[k] times coarse node par[k]'s, k in [pstart[p], pstart[p+1]) */
	int *pstart, *par;
	double *pw;
	/* the Galerkin product into the next coarser level's matrix, row by
	 * row of this level: row a of A P has tstart[a+1] - tstart[a] blocks
	 * (slots); each block k of A's row and parent of its column adds to
	 * slot rec1[...] (in that order); each entry e of row a's
	 * interpolation then adds pw[e] times slot rslot[r] to the coarse
	 * block rdst[r], r in [rstart[e], rstart[e+1]) (the upper triangle:
	 * the lower is its mirror) */
	int *tstart, *rec1, *rstart, *rslot, *rdst;
	int *mirror;		/* coarse levels: block (I, J), I > J: the block (J, I); else -1 */
	double *rhs, *x, *res;	/* 3n each: right side, iterate, residual */
	double *dz;		/* 3n: the change of x in a sweep, for the residual */
};

struct mg {
	int nlevels;		/* 1 or more; level 0 is the cloth's grid */
	struct mg_level *lv;
	double *chol;		/* the coarsest level's dense Cholesky factor, 3n x 3n */
	int ncoarse;		/* its node count */
	double *line_buf;	/* 3 * the longest line, for the line solves */
	double *row_buf;	/* a row of A P (the Galerkin product), 9 * the longest */
	int ready;		/* mg_setup succeeded since mg_init */
};

/* The hierarchy of cl's grid, with every pattern and array sized: mg_setup
 * and mg_apply allocate nothing. 0, or -1 out of memory (m zeroed, or
 * freeable). cl must outlive m. */
int mg_init(struct mg *m, const struct cloth *cl);
void mg_free(struct mg *m);	/* a zeroed one is fine */

/* For an SPD matrix A on cl's pattern (blockmat_init_cloth's): the
 * Galerkin coarse operators, the line factors, the coarsest Cholesky.
 * A is read again by mg_apply: it must stay unchanged until the next
 * setup. 0; -1 when A's pattern is not cl's or a pivot is not positive
 * (A not positive definite), m then unusable until a setup succeeds. */
int mg_setup(struct mg *m, const struct blockmat *A);

/* The finest level's line factors alone from A (same pattern as the last
 * mg_setup's), the coarse levels kept from the last mg_setup: stale but
 * cheap, for a Newton iteration whose matrix changed a little. Still
 * symmetric positive definite. 0, or -1 as mg_setup. */
int mg_update_fine(struct mg *m, const struct blockmat *A);

/* z = B r for 3n-vectors (z must not alias r): one V-cycle from z = 0,
 * B symmetric positive definite, B ~ A^-1. */
void mg_apply(struct mg *m, const double *r, double *z);

#endif
