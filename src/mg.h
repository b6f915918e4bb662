/* mg.h: a geometric multigrid preconditioner for the implicit step's
 * Newton system H dx = -g, H = M/beta^2 + K (+ damping, + contact blocks),
 * on the cloth's grid: one V-cycle per call, a symmetric positive definite
 * approximation of H^-1 for conjugate gradients.
 *
 * Why: the springs make H stiff (k beta^2/m of 750 on the tablecloth, 3800
 * on a 100^2 cloth, growing as 1/spacing^2, bending's as 1/spacing^4), so
 * block Jacobi leaves CG hundreds of iterations, and a sparse Cholesky
 * costs n^1.5 to refactor. A V-cycle costs O(n), and PCG's iteration
 * counts do not grow under refinement.
 *
 * The method (U. Trottenberg, C. Oosterlee, A. Schueller, "Multigrid",
 * Academic Press 2001; J. E. Dendy, "Black box multigrid", J. Comput.
 * Phys. 48, 1982):
 *   - levels: the grid coarsened by taking every other grid line (and the
 *     last) in both directions, down to 32 nodes or to a grid fewer than
 *     5 lines wide (a strip), whose envelope Cholesky along its long
 *     direction costs O(n) and solves it exactly: the 125 x 3 strip is
 *     one level, and PCG converges in one iteration;
 *   - interpolation P, 3 x 3 blocks: operator-dependent (Dendy's, for
 *     blocks): a node between two coarse nodes along a line takes
 *     -D^-1 N from its matrix row collapsed onto that line, a node inside
 *     a coarse cell -A_aa^-1 times its couplings to its interpolated
 *     neighbours; so that it follows its springs' directions, rotated or
 *     compressed (bilinear weights, times I, leave a crumpled cloth's
 *     coarse space stiff: 14 iterations where these give 9). Bilinear
 *     where that fails. Only coarse nodes the shape keeps (a disc) are
 *     parents; a held node (row and column decoupled) gets none;
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
 *     LDL^T factors are made in the setup.
 * For context, R. Tamstorf, T. Jones, S. McCormick, "Smoothed aggregation
 * multigrid for cloth simulation", ACM TOG 34(6) 2015, solve the same
 * systems on unstructured meshes; the grid lets us use its lines instead.
 *
 * Costs, all O(n) in flops: mg_init (patterns, lines, Galerkin recipes);
 * mg_setup (interpolation, Galerkin products, line factors, the coarsest
 * factor), the time of about 32 products with A at 25^2; mg_update_fine
 * about 6; mg_apply about 9 (4 on the finest level's sweeps). Beyond the
 * caches (100^2) memory traffic makes them 1.5 to 2 times that. Memory:
 * about 4.5 KB a node besides A's 0.95 KB (0.8 KB on a strip). bench/mg.sh
 * measures them. Deterministic (fixed loop orders, no threads, no global
 * state); nothing here prints. */
#ifndef DRAPE_MG_H
#define DRAPE_MG_H

#include "blockmat.h"
#include "cloth.h"

/* One direction's block line relaxation on one level: the level's nodes
 * in lines (dir 0: warp lines, fixed j; dir 1: weft lines, fixed i), the
 * blocks coupling each line to the others, the line systems' banded block
 * LDL^T factors. "Position" t numbers the nodes in line order. */
struct mg_lines {
	int nlines;
	int *start;		/* nlines + 1: line l is positions [start[l], start[l+1]) */
	int *order;		/* n: the node at each position */
	int band;		/* the farthest coupling along a line, in positions */
	int *inl;		/* n * (band + 1): the level matrix's blocks (t, t - k), k = 0..band; -1 none */
	/* position t's blocks off its line, copied in line order (one stream
	 * for the sweeps): the earlier lines' [lo[t], mid[t]), the later
	 * lines' [hi[t], lo[t + 1]) of own_col (their columns), own_val
	 * (their values, each block transposed: column after column, so that
	 * the compiler pairs two rows' products) and src (their blocks in the
	 * level's matrix) */
	int *lo, *mid, *hi;
	int *own_col, *src;
	double *own_val;
	double *fac;		/* n * (band + 1) * 9: per position L(t, t - k), k = 1..band, then D_t^-1 */
};

/* The coarsest level's Cholesky factor, its nodes ordered along the
 * grid's longer direction so that the factor is banded: an envelope
 * (skyline) by rows of the 3n unknowns. */
struct mg_band {
	int N;			/* unknowns: 3 per node */
	int *pos;		/* n: node -> place in the order */
	int *first;		/* N: row r's first column */
	size_t *off;		/* N + 1: row r's entries first[r]..r are val[off[r]..off[r+1]) */
	double *val;
	double *y;		/* N: the solve's work */
};

struct mg_level {
	int nu, nv, n;		/* the level's grid and node count */
	int *grid_node;		/* nu * nv: node at (i, j) = grid_node[j*nu + i], or -1 */
	double *xu, *xv;	/* nu, nv: each grid line's place, in finest spacings */
	/* the level's matrix: on coarse levels P^T A P; on the finest the
	 * pattern alone (val NULL), the values being the caller's */
	struct blockmat A;
	const double *val;	/* the values: A.val, or during a setup the caller's */
	struct mg_lines lines[2];
	int *where;		/* n: node p is at grid position where[p] = j*nu + i */
	/* interpolation from the next coarser level: node p's value is the
	 * sum of the blocks pb[9k..] times coarse node par[k]'s, k in
	 * [pstart[p], pstart[p+1]) (the bilinear stencil's coarse nodes) */
	int *pstart, *par;
	double *pw;		/* bilinear weights, the fallback */
	double *pb;		/* 9 per entry: the weights in use (mg_setup's) */
	int *lou, *hiu, *lov, *hiv;	/* nu, nv: each grid line's coarse neighbours (equal on a coarse line) */
	/* the Galerkin product into the next coarser level's matrix, row by
	 * row of this level: row a of A P has tstart[a+1] - tstart[a] blocks
	 * (slots); each block k of A's row and parent of its column adds to
	 * slot rec1[...] (in that order); each entry e of row a's
	 * interpolation then adds pb[e]^T times slot rslot[r] to the coarse
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
	struct mg_band band;	/* the coarsest level's direct solver */
	double *line_buf;	/* 3 * the longest line, for the line solves */
	double *row_buf;	/* a row of A P (the Galerkin product), 9 * the longest */
	int ready;		/* mg_setup succeeded since mg_init */
};

/* The hierarchy of cl's grid, with every pattern and array sized: mg_setup
 * and mg_apply allocate nothing. 0, or -1 out of memory (m then freed and
 * zeroed). */
int mg_init(struct mg *m, const struct cloth *cl);
void mg_free(struct mg *m);	/* a zeroed one is fine */

/* For an SPD matrix A on cl's pattern (blockmat_init_cloth's): the
 * interpolation, the Galerkin coarse operators, the line factors, the
 * coarsest Cholesky. What mg_apply needs is copied: A may change (be
 * reassembled) after. 0; -1 when A's pattern is not cl's or a pivot is
 * not positive (A not positive definite), mg_apply then giving z = r
 * until a setup succeeds. */
int mg_setup(struct mg *m, const struct blockmat *A);

/* The finest level's line factors alone from A, the interpolation and
 * coarse levels kept from the last mg_setup: stale but cheap (a sixth of
 * a setup), for a Newton iteration whose matrix changed a little. What
 * the coarse levels do not know (contacts switched, nodes held since)
 * costs CG iterations, not correctness: still symmetric positive
 * definite. A full setup when there was none. 0, or -1 as mg_setup. */
int mg_update_fine(struct mg *m, const struct blockmat *A);

/* How many levels: 1 where the band Cholesky of the finest is the whole
 * of it (a strip, a small cloth), and mg_update_fine a full setup. */
int mg_levels(const struct mg *m);

/* z = B r for 3n-vectors (z must not alias r): one V-cycle from z = 0,
 * B symmetric positive definite, B ~ A^-1 (z = r until a setup has
 * succeeded). */
void mg_apply(struct mg *m, const double *r, double *z);

#endif
