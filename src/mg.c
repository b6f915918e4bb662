/* mg.c: the geometric multigrid V-cycle on the cloth's grid (see mg.h).
 * References: U. Trottenberg, C. Oosterlee, A. Schueller, "Multigrid",
 * Academic Press 2001: line relaxation for anisotropic operators (5.1),
 * operator-dependent interpolation and Galerkin coarsening (5.4, A.2),
 * systems (ch. 8), the symmetric V-cycle as a CG preconditioner (7.8);
 * J. E. Dendy, "Black box multigrid", J. Comput. Phys. 48 (1982) 366,
 * for the interpolation's collapsed stencils; A. George, J. Liu,
 * "Computer Solution of Large Sparse Positive Definite Systems",
 * Prentice-Hall 1981, ch. 4, for the envelope Cholesky. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mg.h"

/* A level of at most this many nodes is the coarsest: its Cholesky
 * (at most 96 unknowns) costs less than a sweep of the level above. */
#define MG_COARSEST 32
/* A level with fewer grid lines than this in either direction is the
 * coarsest too: narrow, its envelope Cholesky along the long direction
 * costs O(n) (the 125 x 3 strip: 1125 unknowns, 26 wide) and solves it
 * exactly, where coarsening along a strip cannot represent its in-plane
 * bending (measured: 16 iterations crumpled, semi-coarsened). */
#define MG_MIN_LINES 5

/* ---- 3 x 3 blocks, row-major ---- */

/* y -= B x */
static inline void
blk_mulsub(const double *b, const double *x, double *y)
{
	y[0] -= b[0] * x[0] + b[1] * x[1] + b[2] * x[2];
	y[1] -= b[3] * x[0] + b[4] * x[1] + b[5] * x[2];
	y[2] -= b[6] * x[0] + b[7] * x[1] + b[8] * x[2];
}

/* y -= B^T x */
static inline void
blk_tmulsub(const double *b, const double *x, double *y)
{
	y[0] -= b[0] * x[0] + b[3] * x[1] + b[6] * x[2];
	y[1] -= b[1] * x[0] + b[4] * x[1] + b[7] * x[2];
	y[2] -= b[2] * x[0] + b[5] * x[1] + b[8] * x[2];
}

/* s -= sum of the blocks val[k] times x[col[k]], k in [k0, k1): the
 * sweeps' and the residual's inner loop, on locals (a store through s
 * each block would wait on the loads, which might alias it). */
static inline void
row_mulsub(const double *val, const int *col, int k0, int k1, const double *x, double *s)
{
	double s0 = s[0], s1 = s[1], s2 = s[2];
	int k;

	for (k = k0; k < k1; k++) {
		const double *b = val + 9 * (size_t)k, *xc = x + 3 * (size_t)col[k];
		double x0 = xc[0], x1 = xc[1], x2 = xc[2];

		s0 -= b[0] * x0 + b[3] * x1 + b[6] * x2;
		s1 -= b[1] * x0 + b[4] * x1 + b[7] * x2;
		s2 -= b[2] * x0 + b[5] * x1 + b[8] * x2;
	}
	s[0] = s0;
	s[1] = s1;
	s[2] = s2;
}

/* y = B x */
static inline void
blk_mul(const double *b, const double *x, double *y)
{
	y[0] = b[0] * x[0] + b[1] * x[1] + b[2] * x[2];
	y[1] = b[3] * x[0] + b[4] * x[1] + b[5] * x[2];
	y[2] = b[6] * x[0] + b[7] * x[1] + b[8] * x[2];
}

/* C -= A B^T, as blk_ab */
static inline void
blk_sub_abt(const double *a, const double *b, double *c)
{
	double a0 = a[0], a1 = a[1], a2 = a[2], a3 = a[3], a4 = a[4], a5 = a[5], a6 = a[6], a7 = a[7], a8 = a[8];
	double b0 = b[0], b1 = b[1], b2 = b[2], b3 = b[3], b4 = b[4], b5 = b[5], b6 = b[6], b7 = b[7], b8 = b[8];

	c[0] -= a0 * b0 + a1 * b1 + a2 * b2;
	c[1] -= a0 * b3 + a1 * b4 + a2 * b5;
	c[2] -= a0 * b6 + a1 * b7 + a2 * b8;
	c[3] -= a3 * b0 + a4 * b1 + a5 * b2;
	c[4] -= a3 * b3 + a4 * b4 + a5 * b5;
	c[5] -= a3 * b6 + a4 * b7 + a5 * b8;
	c[6] -= a6 * b0 + a7 * b1 + a8 * b2;
	c[7] -= a6 * b3 + a7 * b4 + a8 * b5;
	c[8] -= a6 * b6 + a7 * b7 + a8 * b8;
}

/* C = A B (A and B read first: C may alias neither) */
static inline void
blk_ab(const double *a, const double *b, double *c)
{
	double a0 = a[0], a1 = a[1], a2 = a[2], a3 = a[3], a4 = a[4], a5 = a[5], a6 = a[6], a7 = a[7], a8 = a[8];
	double b0 = b[0], b1 = b[1], b2 = b[2], b3 = b[3], b4 = b[4], b5 = b[5], b6 = b[6], b7 = b[7], b8 = b[8];

	c[0] = a0 * b0 + a1 * b3 + a2 * b6;
	c[1] = a0 * b1 + a1 * b4 + a2 * b7;
	c[2] = a0 * b2 + a1 * b5 + a2 * b8;
	c[3] = a3 * b0 + a4 * b3 + a5 * b6;
	c[4] = a3 * b1 + a4 * b4 + a5 * b7;
	c[5] = a3 * b2 + a4 * b5 + a5 * b8;
	c[6] = a6 * b0 + a7 * b3 + a8 * b6;
	c[7] = a6 * b1 + a7 * b4 + a8 * b7;
	c[8] = a6 * b2 + a7 * b5 + a8 * b8;
}

/* C += A B, as blk_ab */
static inline void
blk_add_ab(const double *a, const double *b, double *c)
{
	double a0 = a[0], a1 = a[1], a2 = a[2], a3 = a[3], a4 = a[4], a5 = a[5], a6 = a[6], a7 = a[7], a8 = a[8];
	double b0 = b[0], b1 = b[1], b2 = b[2], b3 = b[3], b4 = b[4], b5 = b[5], b6 = b[6], b7 = b[7], b8 = b[8];

	c[0] += a0 * b0 + a1 * b3 + a2 * b6;
	c[1] += a0 * b1 + a1 * b4 + a2 * b7;
	c[2] += a0 * b2 + a1 * b5 + a2 * b8;
	c[3] += a3 * b0 + a4 * b3 + a5 * b6;
	c[4] += a3 * b1 + a4 * b4 + a5 * b7;
	c[5] += a3 * b2 + a4 * b5 + a5 * b8;
	c[6] += a6 * b0 + a7 * b3 + a8 * b6;
	c[7] += a6 * b1 + a7 * b4 + a8 * b7;
	c[8] += a6 * b2 + a7 * b5 + a8 * b8;
}

/* C += A^T B, as blk_ab */
static inline void
blk_add_atb(const double *a, const double *b, double *c)
{
	double a0 = a[0], a1 = a[1], a2 = a[2], a3 = a[3], a4 = a[4], a5 = a[5], a6 = a[6], a7 = a[7], a8 = a[8];
	double b0 = b[0], b1 = b[1], b2 = b[2], b3 = b[3], b4 = b[4], b5 = b[5], b6 = b[6], b7 = b[7], b8 = b[8];

	c[0] += a0 * b0 + a3 * b3 + a6 * b6;
	c[1] += a0 * b1 + a3 * b4 + a6 * b7;
	c[2] += a0 * b2 + a3 * b5 + a6 * b8;
	c[3] += a1 * b0 + a4 * b3 + a7 * b6;
	c[4] += a1 * b1 + a4 * b4 + a7 * b7;
	c[5] += a1 * b2 + a4 * b5 + a7 * b8;
	c[6] += a2 * b0 + a5 * b3 + a8 * b6;
	c[7] += a2 * b1 + a5 * b4 + a8 * b7;
	c[8] += a2 * b2 + a5 * b5 + a8 * b8;
}

/* inv = D^-1 for D made symmetric ((D + D^T)/2, removing rounding's
 * asymmetry, so that the inverse is exactly symmetric); 0, or -1 when D
 * is not positive definite (its leading minors). */
static int
blk_spd_inverse(const double *d, double *inv)
{
	double a = d[0], b = (d[1] + d[3]) / 2, c = (d[2] + d[6]) / 2;
	double e = d[4], f = (d[5] + d[7]) / 2, i = d[8];
	double c00 = e * i - f * f, c01 = c * f - b * i, c02 = b * f - c * e;
	double det = a * c00 + b * c01 + c * c02;

	if (!(a > 0) || !(a * e - b * b > 0) || !(det > 0) || !isfinite(det))
		return -1;
	inv[0] = c00 / det;
	inv[1] = inv[3] = c01 / det;
	inv[2] = inv[6] = c02 / det;
	inv[4] = (a * i - c * c) / det;
	inv[5] = inv[7] = (b * c - a * f) / det;
	inv[8] = (a * e - b * b) / det;
	return 0;
}

/* inv = D^-1 for a general D whose symmetric part is positive definite;
 * 0, or -1 when it is not (or D is near singular). */
static int
blk_inverse(const double *d, double *inv)
{
	double sym[9], tmp[9], c00 = d[4] * d[8] - d[5] * d[7], c01 = d[5] * d[6] - d[3] * d[8];
	double c02 = d[3] * d[7] - d[4] * d[6], det = d[0] * c00 + d[1] * c01 + d[2] * c02;
	int i, j;

	for (i = 0; i < 3; i++)
		for (j = 0; j < 3; j++)
			sym[3 * i + j] = (d[3 * i + j] + d[3 * j + i]) / 2;
	if (blk_spd_inverse(sym, tmp) != 0 || !(fabs(det) > 0) || !isfinite(det))
		return -1;
	inv[0] = c00 / det;
	inv[3] = c01 / det;
	inv[6] = c02 / det;
	inv[1] = (d[2] * d[7] - d[1] * d[8]) / det;
	inv[4] = (d[0] * d[8] - d[2] * d[6]) / det;
	inv[7] = (d[1] * d[6] - d[0] * d[7]) / det;
	inv[2] = (d[1] * d[5] - d[2] * d[4]) / det;
	inv[5] = (d[2] * d[3] - d[0] * d[5]) / det;
	inv[8] = (d[0] * d[4] - d[1] * d[3]) / det;
	return 0;
}

/* ---- allocation ---- */

/* calloc with room for n = 0; clears *ok on failure, so that a run of
 * allocations is checked once. */
static void *
zalloc(size_t n, size_t size, int *ok)
{
	void *p = calloc(n + 1, size);

	if (p == NULL)
		*ok = 0;
	return p;
}

static void
lines_free(struct mg_lines *ln)
{
	free(ln->start);
	free(ln->order);
	free(ln->inl);
	free(ln->lo);
	free(ln->mid);
	free(ln->hi);
	free(ln->own_col);
	free(ln->src);
	free(ln->own_val);
	free(ln->fac);
	memset(ln, 0, sizeof *ln);
}

static void
level_free(struct mg_level *lv)
{
	free(lv->grid_node);
	free(lv->xu);
	free(lv->xv);
	blockmat_free(&lv->A);
	lines_free(&lv->lines[0]);
	lines_free(&lv->lines[1]);
	free(lv->pstart);
	free(lv->par);
	free(lv->pw);
	free(lv->pb);
	free(lv->lou);
	free(lv->hiu);
	free(lv->lov);
	free(lv->hiv);
	free(lv->where);
	free(lv->tstart);
	free(lv->rec1);
	free(lv->rstart);
	free(lv->rslot);
	free(lv->rdst);
	free(lv->mirror);
	free(lv->rhs);
	free(lv->x);
	free(lv->res);
	free(lv->dz);
	memset(lv, 0, sizeof *lv);
}

void
mg_free(struct mg *m)
{
	int l;

	for (l = 0; l < m->nlevels; l++)
		level_free(&m->lv[l]);
	free(m->lv);
	free(m->band.pos);
	free(m->band.first);
	free(m->band.off);
	free(m->band.val);
	free(m->band.y);
	free(m->line_buf);
	free(m->row_buf);
	memset(m, 0, sizeof *m);
}

/* ---- the hierarchy ---- */

/* One direction's coarsening: of nf grid lines at places x, every other
 * one and the last are kept. For each fine line f: its coarse neighbours
 * lo[f] <= hi[f] (equal on a kept line) and lo's linear weight wlo[f] by
 * place; xc gets the kept lines' places. Returns the coarse count. */
static int
coarsen_dir(int nf, const double *x, int *lo, int *hi, double *wlo, double *xc)
{
	int f, nc = 0;

	for (f = 0; f < nf; f++) {
		lo[f] = -1;
		if (f % 2 == 0 || f == nf - 1) {
			xc[nc] = x[f];
			lo[f] = hi[f] = nc++;
			wlo[f] = 1;
		}
	}
	/* the others lie between kept lines (f - 1)/2 and (f + 1)/2 */
	for (f = 0; f < nf; f++)
		if (lo[f] < 0) {
			lo[f] = (f - 1) / 2;
			hi[f] = lo[f] + 1;
			wlo[f] = (xc[hi[f]] - x[f]) / (xc[hi[f]] - xc[lo[f]]);
		}
	return nc;
}

/* The nearest coarse node to place (x, y), by place; lowest number on a
 * tie. For a fine node whose interpolation stencil the shape empties. */
static int
nearest_coarse(const struct mg_level *c, double x, double y)
{
	int i, j, best = -1;
	double dbest = 0;

	for (j = 0; j < c->nv; j++)
		for (i = 0; i < c->nu; i++) {
			int q = c->grid_node[j * c->nu + i];
			double d = (c->xu[i] - x) * (c->xu[i] - x) + (c->xv[j] - y) * (c->xv[j] - y);

			if (q >= 0 && (best < 0 || d < dbest)) {
				best = q;
				dbest = d;
			}
		}
	return best;
}

/* Interpolation weights of fine node (i, j) of f from c: the bilinear
 * stencil's coarse nodes present, renormalised. Writes up to 4 parents
 * (when par is not NULL) and returns their count. */
static int
fine_parents(const struct mg_level *f, const struct mg_level *c, int i, int j, const int *lou,
    const int *hiu, const double *wu, const int *lov, const int *hiv, const double *wv, int *par,
    double *w)
{
	int cu[2] = { lou[i], hiu[i] }, cv[2] = { lov[j], hiv[j] }, a, b, k = 0;
	double wa[2] = { wu[i], 1 - wu[i] }, wb[2] = { wv[j], 1 - wv[j] }, sum = 0;
	int np[4];
	double nw[4];

	for (b = 0; b < (cv[0] == cv[1] ? 1 : 2); b++)
		for (a = 0; a < (cu[0] == cu[1] ? 1 : 2); a++) {
			int q = c->grid_node[cv[b] * c->nu + cu[a]];
			double wt = (cu[0] == cu[1] ? 1 : wa[a]) * (cv[0] == cv[1] ? 1 : wb[b]);

			if (q >= 0 && wt > 0) {
				np[k] = q;
				nw[k++] = wt;
				sum += wt;
			}
		}
	if (k == 0) {
		np[0] = nearest_coarse(c, f->xu[i], f->xv[j]);
		nw[0] = sum = 1;
		k = 1;
	}
	if (par != NULL)
		for (a = 0; a < k; a++) {
			par[a] = np[a];
			w[a] = nw[a] / sum;
		}
	return k;
}

/* Level c from level f (every other grid line), and f's interpolation
 * from c. 0, or -1 out of memory. */
static int
coarsen_level(struct mg_level *f, struct mg_level *c)
{
	int ok = 1, i, j, p, k;
	int *lou = f->lou = zalloc((size_t)f->nu, sizeof *lou, &ok);
	int *hiu = f->hiu = zalloc((size_t)f->nu, sizeof *hiu, &ok);
	int *lov = f->lov = zalloc((size_t)f->nv, sizeof *lov, &ok);
	int *hiv = f->hiv = zalloc((size_t)f->nv, sizeof *hiv, &ok);
	double *wu = zalloc((size_t)f->nu, sizeof *wu, &ok), *wv = zalloc((size_t)f->nv, sizeof *wv, &ok);

	c->xu = zalloc((size_t)f->nu, sizeof *c->xu, &ok);
	c->xv = zalloc((size_t)f->nv, sizeof *c->xv, &ok);
	if (!ok)
		goto out;
	c->nu = coarsen_dir(f->nu, f->xu, lou, hiu, wu, c->xu);
	c->nv = coarsen_dir(f->nv, f->xv, lov, hiv, wv, c->xv);
	if ((c->grid_node = zalloc((size_t)c->nu * (size_t)c->nv, sizeof *c->grid_node, &ok)) == NULL)
		goto out;
	/* a coarse node where the fine grid has one (the shape's coarse
	 * version), numbered in grid order as the cloth's are */
	for (j = 0; j < c->nv; j++)
		for (i = 0; i < c->nu; i++)
			c->grid_node[j * c->nu + i] = -1;
	for (j = 0, c->n = 0; j < f->nv; j++)
		for (i = 0; i < f->nu; i++)
			if (lou[i] == hiu[i] && lov[j] == hiv[j] && f->grid_node[j * f->nu + i] >= 0)
				c->grid_node[lov[j] * c->nu + lou[i]] = c->n++;
	if ((c->where = zalloc((size_t)c->n, sizeof *c->where, &ok)) == NULL)
		goto out;
	for (p = 0; p < c->nu * c->nv; p++)
		if (c->grid_node[p] >= 0)
			c->where[c->grid_node[p]] = p;

	/* interpolation, by fine node */
	f->pstart = zalloc((size_t)f->n + 1, sizeof *f->pstart, &ok);
	f->par = zalloc(4 * (size_t)f->n, sizeof *f->par, &ok);
	f->pw = zalloc(4 * (size_t)f->n, sizeof *f->pw, &ok);
	f->pb = zalloc(36 * (size_t)f->n, sizeof *f->pb, &ok);
	if (!ok)
		goto out;
	for (j = 0, k = 0; j < f->nv; j++)
		for (i = 0; i < f->nu; i++) {
			if ((p = f->grid_node[j * f->nu + i]) < 0)
				continue;
			f->pstart[p] = k;	/* nodes are numbered in grid order */
			k += fine_parents(f, c, i, j, lou, hiu, wu, lov, hiv, wv, f->par + k, f->pw + k);
		}
	f->pstart[f->n] = k;

out:
	free(wu);
	free(wv);
	return ok ? 0 : -1;
}

/* Row a of A P: its coarse columns (slots, numbered in mark, listed in
 * tcol from tcol[0]) and, when rec1 is not NULL, each (block, parent)
 * pair's slot. Returns the slot count; mark is left as it was (-1). */
static int
ap_row_slots(const struct mg_level *f, int a, int *mark, int *tcol, int *rec1)
{
	int k, e, ns = 0, i = 0;

	for (k = f->A.start[a]; k < f->A.start[a + 1]; k++)
		for (e = f->pstart[f->A.col[k]]; e < f->pstart[f->A.col[k] + 1]; e++) {
			int J = f->par[e];

			if (mark[J] < 0) {
				mark[J] = ns;
				tcol[ns++] = J;
			}
			if (rec1 != NULL)
				rec1[i++] = mark[J];
		}
	for (k = 0; k < ns; k++)
		mark[tcol[k]] = -1;
	return ns;
}

/* The recipe's first half: each row's slots (their coarse columns in
 * tcol, from tstart) and rec1; mark: scratch over the nc coarse nodes.
 * 0, or -1 out of memory. */
static int
recipe_slots(struct mg_level *f, int nc, int *mark, int **tcol)
{
	int ok = 1, a, k, I, nrec1 = 0, nslot = 0;

	for (k = 0; k < f->A.start[f->n]; k++)
		nrec1 += f->pstart[f->A.col[k] + 1] - f->pstart[f->A.col[k]];
	f->tstart = zalloc((size_t)f->n + 1, sizeof *f->tstart, &ok);
	f->rec1 = zalloc((size_t)nrec1, sizeof *f->rec1, &ok);
	*tcol = zalloc((size_t)nrec1, sizeof **tcol, &ok);	/* slots <= pairs */
	if (!ok)
		return -1;
	for (I = 0; I < nc; I++)
		mark[I] = -1;
	for (a = 0, nrec1 = 0; a < f->n; a++) {
		f->tstart[a] = nslot;
		nslot += ap_row_slots(f, a, mark, *tcol + nslot, f->rec1 + nrec1);
		for (k = f->A.start[a]; k < f->A.start[a + 1]; k++)
			nrec1 += f->pstart[f->A.col[k] + 1] - f->pstart[f->A.col[k]];
	}
	f->tstart[f->n] = nslot;
	return 0;
}

/* c's pattern, P^T A P's: row I gets the slots of each row a that it
 * interpolates to. 0, or -1 out of memory. */
static int
coarse_pattern(const struct mg_level *f, struct mg_level *c, const int *tcol)
{
	int ok = 1, a, e, s, I, r;
	int *cnt = zalloc((size_t)c->n + 1, sizeof *cnt, &ok), *cols = NULL;

	if (!ok)
		return -1;
	for (a = 0; a < f->n; a++)
		for (e = f->pstart[a]; e < f->pstart[a + 1]; e++)
			cnt[f->par[e] + 1] += f->tstart[a + 1] - f->tstart[a];
	for (I = 0; I < c->n; I++)
		cnt[I + 1] += cnt[I];
	if ((cols = zalloc((size_t)cnt[c->n], sizeof *cols, &ok)) == NULL) {
		free(cnt);
		return -1;
	}
	for (a = 0; a < f->n; a++)
		for (e = f->pstart[a]; e < f->pstart[a + 1]; e++)
			for (s = f->tstart[a]; s < f->tstart[a + 1]; s++)
				cols[cnt[f->par[e]]++] = tcol[s];
	for (I = c->n; I > 0; I--)	/* cnt[I] had moved to row I's end */
		cnt[I] = cnt[I - 1];
	cnt[0] = 0;
	r = blockmat_init_pattern(&c->A, c->n, cnt, cols);
	free(cnt);
	free(cols);
	return r;
}

/* The recipe's second half: for each interpolation entry, the slots it
 * takes into the upper triangle (I <= J), and c's mirror. 0, or -1 out of
 * memory. */
static int
recipe_pairs(struct mg_level *f, struct mg_level *c, const int *tcol)
{
	int ok = 1, a, e, s, I, k, nr = 0, r = 0;

	for (a = 0; a < f->n; a++)
		for (e = f->pstart[a]; e < f->pstart[a + 1]; e++)
			for (s = f->tstart[a]; s < f->tstart[a + 1]; s++)
				nr += f->par[e] <= tcol[s];
	f->rstart = zalloc((size_t)f->pstart[f->n] + 1, sizeof *f->rstart, &ok);
	f->rslot = zalloc((size_t)nr, sizeof *f->rslot, &ok);
	f->rdst = zalloc((size_t)nr, sizeof *f->rdst, &ok);
	c->mirror = zalloc(c->A.nblocks, sizeof *c->mirror, &ok);
	if (!ok)
		return -1;
	for (a = 0; a < f->n; a++)
		for (e = f->pstart[a]; e < f->pstart[a + 1]; e++) {
			f->rstart[e] = r;
			for (s = f->tstart[a]; s < f->tstart[a + 1]; s++)
				if (f->par[e] <= tcol[s]) {
					f->rslot[r] = s - f->tstart[a];
					f->rdst[r++] = blockmat_find(&c->A, f->par[e], tcol[s]);
				}
		}
	f->rstart[f->pstart[f->n]] = r;
	for (I = 0; I < c->n; I++)
		for (k = c->A.start[I]; k < c->A.start[I + 1]; k++)
			c->mirror[k] = c->A.col[k] < I ? blockmat_find(&c->A, c->A.col[k], I) : -1;
	return 0;
}

/* c's pattern, P^T A P's, and the recipe of its values (see struct
 * mg_level); mark: scratch, c->n. 0, or -1 out of memory. */
static int
galerkin_recipe(struct mg_level *f, struct mg_level *c, int *mark)
{
	int *tcol = NULL, r;

	r = recipe_slots(f, c->n, mark, &tcol) != 0 || coarse_pattern(f, c, tcol) != 0 ||
	    recipe_pairs(f, c, tcol) != 0 ? -1 : 0;
	free(tcol);
	return r;
}

/* Sorts one line's nodes into lines[dir] and notes, for each node, its
 * position and line. */
static void
collect_lines(const struct mg_level *lv, int dir, struct mg_lines *ln, int *pos, int *lineid)
{
	int outer = dir == 0 ? lv->nv : lv->nu, inner = dir == 0 ? lv->nu : lv->nv, a, b, t = 0;

	ln->nlines = 0;
	for (a = 0; a < outer; a++) {
		int t0 = t;

		for (b = 0; b < inner; b++) {
			int p = dir == 0 ? lv->grid_node[a * lv->nu + b] : lv->grid_node[b * lv->nu + a];

			if (p < 0)
				continue;
			ln->order[t] = p;
			pos[p] = t++;
			lineid[p] = ln->nlines;
		}
		if (t > t0)
			ln->start[++ln->nlines] = t;
	}
	ln->start[0] = 0;
}

/* Lists the off-line blocks of position t's row (node p, line l): the
 * earlier lines' first, then the later lines'; n counts them, and they
 * are noted (src, own_col) once the arrays exist. The sweeps read their
 * copies in this order, one stream (the matrix's rows, read in place,
 * would be read in runs with gaps, and the weft lines' rows strided). */
static void
list_off_line(struct mg_lines *ln, const struct blockmat *A, int t, int l, const int *lineid,
    size_t *n)
{
	int p = ln->order[t], k, later;

	ln->lo[t] = (int)*n;
	for (later = 0; later < 2; later++) {
		if (later)
			ln->mid[t] = ln->hi[t] = (int)*n;
		for (k = A->start[p]; k < A->start[p + 1]; k++) {
			int q = A->col[k];

			if (lineid[q] != l && (lineid[q] > l) == later) {
				if (ln->src != NULL) {
					ln->src[*n] = k;
					ln->own_col[*n] = q;
				}
				(*n)++;
			}
		}
	}
}

/* lines[dir] of level lv: the nodes in lines, the band, the blocks on and
 * off each line; *longest gets the longest line. 0, or -1 out of memory. */
static int
build_lines(struct mg_level *lv, int dir, int *longest)
{
	struct mg_lines *ln = &lv->lines[dir];
	const struct blockmat *A = &lv->A;
	int ok = 1, n = lv->n, t, k, l, nb, pass;
	int *pos = zalloc((size_t)n, sizeof *pos, &ok), *lineid = zalloc((size_t)n, sizeof *lineid, &ok);
	size_t noff = 0;

	ln->start = zalloc((size_t)(dir == 0 ? lv->nv : lv->nu) + 1, sizeof *ln->start, &ok);
	ln->order = zalloc((size_t)n, sizeof *ln->order, &ok);
	ln->lo = zalloc((size_t)n + 1, sizeof *ln->lo, &ok);
	ln->mid = zalloc((size_t)n, sizeof *ln->mid, &ok);
	ln->hi = zalloc((size_t)n, sizeof *ln->hi, &ok);
	if (!ok)
		goto out;
	collect_lines(lv, dir, ln, pos, lineid);
	ln->band = 0;
	for (l = 0; l < ln->nlines; l++)
		if (ln->start[l + 1] - ln->start[l] > *longest)
			*longest = ln->start[l + 1] - ln->start[l];
	for (t = 0; t < n; t++) {
		int p = ln->order[t];

		for (k = A->start[p]; k < A->start[p + 1]; k++)
			if (lineid[A->col[k]] == lineid[p] && abs(pos[A->col[k]] - t) > ln->band)
				ln->band = abs(pos[A->col[k]] - t);
	}
	nb = ln->band;
	ln->inl = zalloc((size_t)n * (size_t)(nb + 1), sizeof *ln->inl, &ok);
	ln->fac = zalloc(9 * (size_t)n * (size_t)(nb + 1), sizeof *ln->fac, &ok);
	if (!ok)
		goto out;
	/* two passes: count the off-line blocks, then list them */
	for (pass = 0; pass < 2; pass++) {
		if (pass == 1) {
			ln->src = zalloc(noff, sizeof *ln->src, &ok);
			ln->own_col = zalloc(noff, sizeof *ln->own_col, &ok);
			ln->own_val = zalloc(9 * noff, sizeof *ln->own_val, &ok);
			if (!ok)
				goto out;
		}
		for (l = 0, noff = 0; l < ln->nlines; l++)
			for (t = ln->start[l]; t < ln->start[l + 1]; t++)
				list_off_line(ln, A, t, l, lineid, &noff);
	}
	ln->lo[n] = (int)noff;
	for (l = 0; l < ln->nlines; l++)
		for (t = ln->start[l]; t < ln->start[l + 1]; t++)
			for (k = 0; k <= nb; k++)
				ln->inl[t * (nb + 1) + k] = t - k >= ln->start[l] ?
				    blockmat_find(A, ln->order[t], ln->order[t - k]) : -1;
out:
	free(pos);
	free(lineid);
	return ok ? 0 : -1;
}

/* cl's pattern, blockmat_init_cloth's, alone: its values are the
 * caller's, its element slots are the caller's assembly's. 0, or -1 out
 * of memory. */
static int
finest_pattern(struct blockmat *P, const struct cloth *cl)
{
	struct blockmat full;
	int r;

	if (blockmat_init_cloth(&full, cl) != 0)
		return -1;
	r = blockmat_init_pattern(P, full.n, full.start, full.col);
	blockmat_free(&full);
	if (r == 0) {
		free(P->val);
		P->val = NULL;
	}
	return r;
}

/* Level 0: cl's grid and pattern (its values are the caller's). */
static int
finest_level(struct mg_level *lv, const struct cloth *cl)
{
	int ok = 1, i;

	lv->nu = cl->nu;
	lv->nv = cl->nv;
	lv->n = cl->n;
	lv->grid_node = zalloc((size_t)cl->nu * (size_t)cl->nv, sizeof *lv->grid_node, &ok);
	lv->xu = zalloc((size_t)cl->nu, sizeof *lv->xu, &ok);
	lv->xv = zalloc((size_t)cl->nv, sizeof *lv->xv, &ok);
	if (!ok)
		return -1;
	memcpy(lv->grid_node, cl->grid_node, (size_t)cl->nu * (size_t)cl->nv * sizeof *lv->grid_node);
	if ((lv->where = zalloc((size_t)cl->n, sizeof *lv->where, &ok)) == NULL)
		return -1;
	memcpy(lv->where, cl->node_grid, (size_t)cl->n * sizeof *lv->where);
	for (i = 0; i < cl->nu; i++)
		lv->xu[i] = i;
	for (i = 0; i < cl->nv; i++)
		lv->xv[i] = i;
	return finest_pattern(&lv->A, cl);
}

static int
is_coarsest(const struct mg_level *lv)
{
	return lv->n <= MG_COARSEST || lv->nu < MG_MIN_LINES || lv->nv < MG_MIN_LINES;
}

/* The levels' grids and interpolations, coarsening until the coarsest.
 * 0, or -1 out of memory. */
static int
build_levels(struct mg *m, const struct cloth *cl)
{
	int l, cap = 4;

	if ((m->lv = calloc((size_t)cap, sizeof *m->lv)) == NULL)
		return -1;
	m->nlevels = 1;
	if (finest_level(&m->lv[0], cl) != 0)
		return -1;
	for (l = 0; !is_coarsest(&m->lv[l]); l++) {
		if (m->nlevels == cap) {
			struct mg_level *more = realloc(m->lv, 2 * (size_t)cap * sizeof *more);

			if (more == NULL)
				return -1;
			memset(more + cap, 0, (size_t)cap * sizeof *more);
			m->lv = more;
			cap *= 2;
		}
		m->nlevels++;
		if (coarsen_level(&m->lv[l], &m->lv[l + 1]) != 0)
			return -1;
	}
	return 0;
}

/* The coarsest level's envelope: its nodes ordered along the longer grid
 * direction (cross-section after cross-section), each row's first
 * column. 0, or -1 out of memory. */
static int
band_init(struct mg_band *b, const struct mg_level *lv)
{
	int ok = 1, i, j, t = 0, p, k, r, along_i = lv->nu >= lv->nv;
	size_t total = 0;

	b->N = 3 * lv->n;
	b->pos = zalloc((size_t)lv->n, sizeof *b->pos, &ok);
	b->first = zalloc((size_t)b->N, sizeof *b->first, &ok);
	b->off = zalloc((size_t)b->N + 1, sizeof *b->off, &ok);
	b->y = zalloc((size_t)b->N, sizeof *b->y, &ok);
	if (!ok)
		return -1;
	for (i = 0; i < (along_i ? lv->nu : lv->nv); i++)
		for (j = 0; j < (along_i ? lv->nv : lv->nu); j++)
			if ((p = along_i ? lv->grid_node[j * lv->nu + i] : lv->grid_node[i * lv->nu + j]) >= 0)
				b->pos[p] = t++;
	for (p = 0; p < lv->n; p++) {
		int lo = b->pos[p];

		for (k = lv->A.start[p]; k < lv->A.start[p + 1]; k++)
			lo = b->pos[lv->A.col[k]] < lo ? b->pos[lv->A.col[k]] : lo;
		for (r = 0; r < 3; r++)
			b->first[3 * b->pos[p] + r] = 3 * lo;
	}
	for (r = 0; r < b->N; r++) {
		b->off[r] = total;
		total += (size_t)(r - b->first[r] + 1);
	}
	b->off[b->N] = total;
	b->val = zalloc(total, sizeof *b->val, &ok);
	return ok ? 0 : -1;
}

/* The coarse levels' patterns and Galerkin recipes, every level's lines,
 * the work arrays. 0, or -1 out of memory. */
static int
build_operators(struct mg *m)
{
	int ok = 1, l, longest = 1, slots = 1, maxc = 1, a;
	int *mark;
	size_t n3;

	for (l = 1; l < m->nlevels; l++)
		maxc = m->lv[l].n > maxc ? m->lv[l].n : maxc;
	if ((mark = zalloc((size_t)maxc, sizeof *mark, &ok)) == NULL)
		return -1;
	for (l = 0; ok && l + 1 < m->nlevels; l++) {
		struct mg_level *f = &m->lv[l];

		if (galerkin_recipe(f, &m->lv[l + 1], mark) != 0 || build_lines(f, 0, &longest) != 0 ||
		    build_lines(f, 1, &longest) != 0)
			ok = 0;
		for (a = 0; ok && a < f->n; a++)
			if (f->tstart[a + 1] - f->tstart[a] > slots)
				slots = f->tstart[a + 1] - f->tstart[a];
	}
	free(mark);
	for (l = 0; ok && l < m->nlevels; l++) {
		n3 = 3 * (size_t)m->lv[l].n;
		m->lv[l].rhs = zalloc(n3, sizeof *m->lv[l].rhs, &ok);
		m->lv[l].x = zalloc(n3, sizeof *m->lv[l].x, &ok);
		m->lv[l].res = zalloc(n3, sizeof *m->lv[l].res, &ok);
		m->lv[l].dz = zalloc(n3, sizeof *m->lv[l].dz, &ok);
	}
	if (!ok)
		return -1;
	if (band_init(&m->band, &m->lv[m->nlevels - 1]) != 0)
		return -1;
	m->line_buf = zalloc(3 * (size_t)longest, sizeof *m->line_buf, &ok);
	m->row_buf = zalloc(9 * (size_t)slots, sizeof *m->row_buf, &ok);
	return ok ? 0 : -1;
}

int
mg_init(struct mg *m, const struct cloth *cl)
{
	memset(m, 0, sizeof *m);
	if (build_levels(m, cl) != 0 || build_operators(m) != 0) {
		mg_free(m);
		return -1;
	}
	return 0;
}

/* ---- setup: the numbers ---- */

/* The entry of node a's interpolation from coarse node q, or -1. */
static int
entry_of(const struct mg_level *f, int a, int q)
{
	int e;

	for (e = f->pstart[a]; e < f->pstart[a + 1]; e++)
		if (f->par[e] == q)
			return e;
	return -1;
}

/* Node a's weights: the bilinear ones times I. */
static void
bilinear_block(struct mg_level *f, int a)
{
	int e, i;

	for (e = f->pstart[a]; e < f->pstart[a + 1]; e++) {
		double *w = f->pb + 9 * (size_t)e;

		memset(w, 0, 9 * sizeof *w);
		for (i = 0; i < 3; i++)
			w[4 * i] = f->pw[e];
	}
}

/* Whether weights w (9 * n) are sane: none above 8. Bilinear ones are
 * at most 1; the operator's reach a few times that where a node's
 * springs are rotated or compressed (on the crumpled test cloths 98 % of
 * the nodes' stay below 2 and 0.05 % pass 8), and would reach any value
 * from a collapsed pivot near singular. */
static int
weights_sane(const double *w, int n)
{
	int i;

	for (i = 0; i < 9 * n; i++)
		if (!(fabs(w[i]) <= 8))
			return 0;
	return 1;
}

/* Node a between two coarse nodes along one direction (dir 0: i): its
 * row collapsed onto that direction (Dendy's black box multigrid: the
 * other direction's couplings move with it), the blocks 2 away lumped
 * onto the coarse neighbours 1 away; P_aL = -D^-1 N_L, P_aR = -D^-1 N_R.
 * 0, or -1 when that fails. */
static int
edge_weights(struct mg_level *f, int a, int dir)
{
	double S[5][9], D[9], Di[9], N[2][9];
	int at = f->where[a], i0 = at % f->nu, j0 = at / f->nu, k, s, m;
	int lo = dir == 0 ? f->lou[i0] : f->lov[j0], hi = dir == 0 ? f->hiu[i0] : f->hiv[j0];
	int cl, ch;
	const struct mg_level *c = f + 1;	/* the levels are an array */

	memset(S, 0, sizeof S);
	for (k = f->A.start[a]; k < f->A.start[a + 1]; k++) {
		int bt = f->where[f->A.col[k]], d = dir == 0 ? bt % f->nu - i0 : bt / f->nu - j0;

		d = d < -2 ? -2 : d > 2 ? 2 : d;
		for (m = 0; m < 9; m++)
			S[d + 2][m] += f->val[9 * (size_t)k + m];
	}
	for (m = 0; m < 9; m++) {
		D[m] = S[2][m];
		N[0][m] = S[0][m] + S[1][m];
		N[1][m] = S[3][m] + S[4][m];
	}
	if (blk_inverse(D, Di) != 0)
		return -1;
	cl = dir == 0 ? c->grid_node[f->lov[j0] * c->nu + lo] : c->grid_node[lo * c->nu + f->lou[i0]];
	ch = dir == 0 ? c->grid_node[f->lov[j0] * c->nu + hi] : c->grid_node[hi * c->nu + f->lou[i0]];
	for (s = 0; s < 2; s++) {
		int e = entry_of(f, a, s == 0 ? cl : ch);
		double *w = e >= 0 ? f->pb + 9 * (size_t)e : NULL;

		if (w == NULL)
			continue;
		blk_ab(Di, N[s], w);
		for (m = 0; m < 9; m++)
			w[m] = -w[m];
	}
	return weights_sane(f->pb + 9 * (size_t)f->pstart[a], f->pstart[a + 1] - f->pstart[a]) ? 0 : -1;
}

/* Node a inside a coarse cell: -D^-1 times its couplings to the 8 around
 * it (those farther lumped onto them), each of those interpolated. 0, or
 * -1 when that fails. */
static int
centre_weights(struct mg_level *f, int a)
{
	double acc[4][9], Di[9], tmp[9];
	int at = f->where[a], i0 = at % f->nu, j0 = at / f->nu, k, e, et, m;

	memset(acc, 0, sizeof acc);
	if (blk_inverse(f->val + 9 * (size_t)f->A.diag[a], Di) != 0)
		return -1;
	for (k = f->A.start[a]; k < f->A.start[a + 1]; k++) {
		int bt = f->where[f->A.col[k]], di = bt % f->nu - i0, dj = bt / f->nu - j0, t;

		if (k == f->A.diag[a])
			continue;
		di = di < -1 ? -1 : di > 1 ? 1 : di;
		dj = dj < -1 ? -1 : dj > 1 ? 1 : dj;
		if ((t = f->grid_node[(j0 + dj) * f->nu + i0 + di]) < 0)
			continue;
		for (et = f->pstart[t]; et < f->pstart[t + 1]; et++)
			if ((e = entry_of(f, a, f->par[et])) >= 0)
				blk_add_ab(f->val + 9 * (size_t)k, f->pb + 9 * (size_t)et, acc[e - f->pstart[a]]);
	}
	for (e = 0; e < f->pstart[a + 1] - f->pstart[a]; e++) {
		blk_ab(Di, acc[e], tmp);
		for (m = 0; m < 9; m++)
			f->pb[9 * (size_t)(f->pstart[a] + e) + m] = -tmp[m];
	}
	return weights_sane(f->pb + 9 * (size_t)f->pstart[a], f->pstart[a + 1] - f->pstart[a]) ? 0 : -1;
}

/* f's interpolation weights from its matrix: operator-dependent (Dendy's
 * black box multigrid, with 3 x 3 blocks, so that an interpolated node
 * follows its springs' directions, rotated or compressed), the bilinear
 * ones where that fails (a pivot not positive definite). The edges
 * first: a centre's weights use theirs. */
static void
block_weights(struct mg_level *f)
{
	int a, pass;

	for (pass = 0; pass < 2; pass++)
		for (a = 0; a < f->n; a++) {
			int at = f->where[a], i0 = at % f->nu, j0 = at / f->nu, r;
			int on_u = f->lou[i0] == f->hiu[i0], on_v = f->lov[j0] == f->hiv[j0];
			int centre = !on_u && !on_v;

			if (centre != pass)
				continue;
			bilinear_block(f, a);
			if (on_u && on_v)	/* a coarse node: I */
				continue;
			r = centre ? centre_weights(f, a) : edge_weights(f, a, on_u ? 1 : 0);
			if (r != 0)
				bilinear_block(f, a);
		}
}

/* c's values: P^T A P, A being f's, by f's recipe: row a of A P into
 * buf (blocks), then its share of each coarse row it interpolates to;
 * the lower triangle mirrors the upper (A is symmetric). */
static void
galerkin_values(const struct mg_level *f, struct mg_level *c, double *buf)
{
	int a, k, e, r, i, j, q = 0;

	blockmat_zero(&c->A);
	for (a = 0; a < f->n; a++) {
		memset(buf, 0, 9 * (size_t)(f->tstart[a + 1] - f->tstart[a]) * sizeof *buf);
		for (k = f->A.start[a]; k < f->A.start[a + 1]; k++) {
			const double *src = f->val + 9 * (size_t)k;
			int b = f->A.col[k];

			for (e = f->pstart[b]; e < f->pstart[b + 1]; e++)
				blk_add_ab(src, f->pb + 9 * (size_t)e, buf + 9 * (size_t)f->rec1[q++]);
		}
		for (e = f->pstart[a]; e < f->pstart[a + 1]; e++)
			for (r = f->rstart[e]; r < f->rstart[e + 1]; r++)
				blk_add_atb(f->pb + 9 * (size_t)e, buf + 9 * (size_t)f->rslot[r],
				    c->A.val + 9 * (size_t)f->rdst[r]);
	}
	for (k = 0; k < (int)c->A.nblocks; k++)
		if (c->mirror[k] >= 0) {
			const double *s = c->A.val + 9 * (size_t)c->mirror[k];
			double *d = c->A.val + 9 * (size_t)k;

			for (i = 0; i < 3; i++)
				for (j = 0; j < 3; j++)
					d[3 * i + j] = s[3 * j + i];
		}
	c->val = c->A.val;
}

/* Position t's row of the level's matrix, read once (the weft lines
 * read the rows strided): its off-line blocks into own_val, its in-line
 * blocks (t, t - k) into fac's slots, where they are factored. */
static void
copy_row(struct mg_lines *ln, const double *val, int t)
{
	int nb = ln->band, k, e;
	const int *inl = ln->inl + (size_t)t * (size_t)(nb + 1);
	double *ft = ln->fac + 9 * (size_t)(nb + 1) * (size_t)t;

	for (e = ln->lo[t]; e < ln->lo[t + 1]; e++) {
		const double *b = val + 9 * (size_t)ln->src[e];
		double *d = ln->own_val + 9 * (size_t)e;

		d[0] = b[0], d[1] = b[3], d[2] = b[6];
		d[3] = b[1], d[4] = b[4], d[5] = b[7];
		d[6] = b[2], d[7] = b[5], d[8] = b[8];
	}
	for (k = 0; k <= nb; k++) {
		double *slot = ft + 9 * (size_t)(k == 0 ? nb : k - 1);

		if (inl[k] >= 0)
			memcpy(slot, val + 9 * (size_t)inl[k], 9 * sizeof *val);
		else
			memset(slot, 0, 9 * sizeof *val);
	}
}

/* Position t's step of its line's block LDL^T (banded, 3 x 3 blocks; t0
 * the line's first position), in place on the blocks copy_row left: with
 * C(t, s) = L(t, s) D_s,
 *   C(t, t-k) = A(t, t-k) - sum_{k' > k} C(t, t-k') L(t-k, t-k')^T,
 *   D_t = A(t, t) - sum_k L(t, t-k) C(t, t-k)^T,
 * then L(t, t-k) = C(t, t-k) D_{t-k}^-1 and D_t^-1 stored. 0, or -1 when
 * D_t is not positive definite. */
static int
factor_position(struct mg_lines *ln, int t, int t0)
{
	int nb = ln->band, kmax = t - t0 < nb ? t - t0 : nb, k, k2;
	size_t stride = 9 * (size_t)(nb + 1);
	double *lt = ln->fac + stride * (size_t)t, *d = lt + 9 * (size_t)nb, c[9];

	for (k = kmax; k >= 1; k--)
		for (k2 = k + 1; k2 <= kmax; k2++)
			blk_sub_abt(lt + 9 * (k2 - 1), ln->fac + stride * (size_t)(t - k) + 9 * (k2 - k - 1),
			    lt + 9 * (k - 1));
	for (k = 1; k <= kmax; k++) {
		double *ck = lt + 9 * (k - 1);

		blk_ab(ck, ln->fac + stride * (size_t)(t - k) + 9 * (size_t)nb, c);
		blk_sub_abt(c, ck, d);
		memcpy(ck, c, sizeof c);
	}
	memcpy(c, d, sizeof c);
	return blk_spd_inverse(c, d);
}

/* lines[dir]'s numbers from the level's matrix: the off-line copies and
 * the line factors. 0, or -1 when a pivot is not positive definite. */
static int
factor_lines(struct mg_level *lv, int dir)
{
	struct mg_lines *ln = &lv->lines[dir];
	int l, t;

	for (l = 0; l < ln->nlines; l++)
		for (t = ln->start[l]; t < ln->start[l + 1]; t++) {
			copy_row(ln, lv->val, t);
			if (factor_position(ln, t, ln->start[l]) != 0)
				return -1;
		}
	return 0;
}

/* The coarsest level's matrix into the envelope (its lower triangle),
 * then factored in place: L L^T, row by row (the envelope holds L's). */
static int
band_factor(struct mg_band *b, const struct mg_level *lv)
{
	int p, k, u, v, r, c, q;

	memset(b->val, 0, b->off[b->N] * sizeof *b->val);
	for (p = 0; p < lv->n; p++)
		for (k = lv->A.start[p]; k < lv->A.start[p + 1]; k++)
			for (u = 0; u < 3; u++)
				for (v = 0; v < 3; v++) {
					r = 3 * b->pos[p] + u;
					c = 3 * b->pos[lv->A.col[k]] + v;
					if (c <= r)
						b->val[b->off[r] + (size_t)(c - b->first[r])] =
						    lv->val[9 * (size_t)k + 3 * u + v];
				}
	for (r = 0; r < b->N; r++) {
		double *lr = b->val + b->off[r] - b->first[r], s;

		for (c = b->first[r]; c < r; c++) {
			const double *lc = b->val + b->off[c] - b->first[c];

			s = lr[c];
			for (q = b->first[r] > b->first[c] ? b->first[r] : b->first[c]; q < c; q++)
				s -= lr[q] * lc[q];
			lr[c] = s / lc[c];
		}
		s = lr[r];
		for (q = b->first[r]; q < r; q++)
			s -= lr[q] * lr[q];
		if (!(s > 0) || !isfinite(s))
			return -1;
		lr[r] = sqrt(s);
	}
	return 0;
}

/* Level 0's pattern is A's. */
static int
same_pattern(const struct blockmat *P, const struct blockmat *A)
{
	return A->n == P->n && A->nblocks == P->nblocks &&
	    memcmp(A->start, P->start, ((size_t)A->n + 1) * sizeof *A->start) == 0 &&
	    memcmp(A->col, P->col, A->nblocks * sizeof *A->col) == 0;
}

/* All the levels' numbers from A's, or (fine_only) the finest level's
 * line factors alone. */
static int
setup_levels(struct mg *m, const struct blockmat *A, int fine_only)
{
	int l, r = 0;

	m->ready = 0;
	if (!same_pattern(&m->lv[0].A, A))
		return -1;
	m->lv[0].val = A->val;
	for (l = 0; r == 0 && l + 1 < m->nlevels && (l == 0 || !fine_only); l++) {
		if (!fine_only) {
			block_weights(&m->lv[l]);
			galerkin_values(&m->lv[l], &m->lv[l + 1], m->row_buf);
		}
		if (factor_lines(&m->lv[l], 0) != 0 || factor_lines(&m->lv[l], 1) != 0)
			r = -1;
	}
	if (r == 0 && !fine_only && band_factor(&m->band, &m->lv[m->nlevels - 1]) != 0)
		r = -1;
	m->lv[0].val = NULL;	/* copied where needed: A may change */
	m->ready = r == 0;
	return r;
}

int
mg_setup(struct mg *m, const struct blockmat *A)
{
	return setup_levels(m, A, 0);
}

int
mg_update_fine(struct mg *m, const struct blockmat *A)
{
	return setup_levels(m, A, m->ready && m->nlevels > 1);
}

int
mg_levels(const struct mg *m)
{
	return m->nlevels;
}

/* ---- apply ---- */

/* x = (L L^T)^-1 r on the coarsest level (r, x by node). */
static void
band_solve(const struct mg_band *b, int n, const double *r, double *x)
{
	double *y = b->y;
	int p, i, q;

	for (p = 0; p < n; p++)
		for (i = 0; i < 3; i++)
			y[3 * b->pos[p] + i] = r[3 * p + i];
	for (i = 0; i < b->N; i++) {
		const double *li = b->val + b->off[i] - b->first[i];
		double s = y[i];

		for (q = b->first[i]; q < i; q++)
			s -= li[q] * y[q];
		y[i] = s / li[i];
	}
	for (i = b->N - 1; i >= 0; i--) {
		const double *li = b->val + b->off[i] - b->first[i];

		y[i] /= li[i];
		for (q = b->first[i]; q < i; q++)
			y[q] -= li[q] * y[i];
	}
	for (p = 0; p < n; p++)
		for (i = 0; i < 3; i++)
			x[3 * p + i] = y[3 * b->pos[p] + i];
}

/* One line's Gauss-Seidel step: its nodes' z from the line's system with
 * the other lines' current z on the right (the later lines' left out on
 * a first sweep from z = 0: they are zero). */
static void
relax_line(const struct mg_lines *ln, int l, const double *r, double *z, int from_zero, double *y)
{
	int t0 = ln->start[l], t1 = ln->start[l + 1], nb = ln->band, t, k;
	size_t stride = 9 * (size_t)(nb + 1);
	const double *val = ln->own_val;
	const int *col = ln->own_col;

	/* forward substitution, the right side made as it goes */
	for (t = t0; t < t1; t++) {
		int p = ln->order[t], kmax = t - t0 < nb ? t - t0 : nb;
		const double *lt = ln->fac + stride * (size_t)t;
		double *yt = y + 3 * (t - t0);

		double s[3] = { r[3 * p], r[3 * p + 1], r[3 * p + 2] };

		row_mulsub(val, col, ln->lo[t], ln->mid[t], z, s);
		if (!from_zero)
			row_mulsub(val, col, ln->hi[t], ln->lo[t + 1], z, s);
		for (k = 1; k <= kmax; k++)
			blk_mulsub(lt + 9 * (k - 1), yt - 3 * k, s);
		memcpy(yt, s, sizeof s);
	}
	/* back substitution, into z */
	for (t = t1 - 1; t >= t0; t--) {
		int kmax = t1 - 1 - t < nb ? t1 - 1 - t : nb;
		double *yt = y + 3 * (t - t0), x[3];

		blk_mul(ln->fac + stride * (size_t)t + 9 * (size_t)nb, yt, x);
		for (k = 1; k <= kmax; k++)
			blk_tmulsub(ln->fac + stride * (size_t)(t + k) + 9 * (size_t)(k - 1), yt + 3 * k, x);
		memcpy(yt, x, sizeof x);
		memcpy(z + 3 * (size_t)ln->order[t], x, sizeof x);
	}
}

static void
sweep(const struct mg *m, const struct mg_level *lv, int dir, int backward, int from_zero,
    const double *r, double *z)
{
	const struct mg_lines *ln = &lv->lines[dir];
	int q;

	for (q = 0; q < ln->nlines; q++)
		relax_line(ln, backward ? ln->nlines - 1 - q : q, r, z, from_zero, m->line_buf);
}

/* The residual r - A z after a forward sweep of lines[dir] that changed z
 * by -dz: line l's equations held with the later lines' old values, so
 * its residual is sum_{m > l} A_lm dz_m (a third of a product with A). */
static void
residual_after_sweep(const struct mg_level *lv, int dir, const double *dz, double *res)
{
	const struct mg_lines *ln = &lv->lines[dir];
	int t;

	for (t = 0; t < lv->n; t++) {
		double s[3] = { 0, 0, 0 };

		row_mulsub(ln->own_val, ln->own_col, ln->hi[t], ln->lo[t + 1], dz, s);
		res[3 * (size_t)ln->order[t]] = -s[0];
		res[3 * (size_t)ln->order[t] + 1] = -s[1];
		res[3 * (size_t)ln->order[t] + 2] = -s[2];
	}
}

/* rc = P^T res */
static void
restrict_residual(const struct mg_level *f, const struct mg_level *c, const double *res, double *rc)
{
	int p, e;

	memset(rc, 0, 3 * (size_t)c->n * sizeof *rc);
	for (p = 0; p < f->n; p++)
		for (e = f->pstart[p]; e < f->pstart[p + 1]; e++) {
			const double *w = f->pb + 9 * (size_t)e, *x = res + 3 * p;
			double *d = rc + 3 * f->par[e];

			d[0] += w[0] * x[0] + w[3] * x[1] + w[6] * x[2];
			d[1] += w[1] * x[0] + w[4] * x[1] + w[7] * x[2];
			d[2] += w[2] * x[0] + w[5] * x[1] + w[8] * x[2];
		}
}

/* z += P zc */
static void
prolong_add(const struct mg_level *f, const double *zc, double *z)
{
	int p, e;

	for (p = 0; p < f->n; p++)
		for (e = f->pstart[p]; e < f->pstart[p + 1]; e++) {
			const double *w = f->pb + 9 * (size_t)e, *x = zc + 3 * f->par[e];

			z[3 * p] += w[0] * x[0] + w[1] * x[1] + w[2] * x[2];
			z[3 * p + 1] += w[3] * x[0] + w[4] * x[1] + w[5] * x[2];
			z[3 * p + 2] += w[6] * x[0] + w[7] * x[1] + w[8] * x[2];
		}
}

static void
vcycle(struct mg *m, int l, const double *r, double *z)
{
	struct mg_level *lv = &m->lv[l], *c;
	size_t i;

	if (l == m->nlevels - 1) {
		band_solve(&m->band, lv->n, r, z);
		return;
	}
	c = &m->lv[l + 1];
	sweep(m, lv, 0, 0, 1, r, z);
	memcpy(lv->dz, z, 3 * (size_t)lv->n * sizeof *z);
	sweep(m, lv, 1, 0, 0, r, z);
	for (i = 0; i < 3 * (size_t)lv->n; i++)
		lv->dz[i] -= z[i];
	residual_after_sweep(lv, 1, lv->dz, lv->res);
	restrict_residual(lv, c, lv->res, c->rhs);
	vcycle(m, l + 1, c->rhs, c->x);
	prolong_add(lv, c->x, z);
	sweep(m, lv, 1, 1, 0, r, z);
	sweep(m, lv, 0, 1, 0, r, z);
}

void
mg_apply(struct mg *m, const double *r, double *z)
{
	if (!m->ready) {	/* no setup (or a failed one): the identity */
		memcpy(z, r, 3 * (size_t)m->lv[0].n * sizeof *z);
		return;
	}
	vcycle(m, 0, r, z);
}
