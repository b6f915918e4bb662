/* mg.c: the geometric multigrid V-cycle on the cloth's grid (see mg.h).
 * References: Trottenberg, Oosterlee & Schueller, "Multigrid" (2001):
 * line relaxation for anisotropic operators (5.1), Galerkin coarsening
 * (A.2 and 7.7), the symmetric V-cycle as a CG preconditioner (7.8). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mg.h"

/* A level this small, or one neither of whose directions coarsens, is
 * solved by a dense Cholesky: 96 unknowns at most cost ~10^4 flops a
 * solve, less than a sweep of the level above. */
#define MG_COARSEST 32
/* A direction with fewer grid lines than this is not coarsened (the
 * strip's 3 across): coarsening it would halve little and make the
 * coarse operator's stencil wider for nothing. */
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

		s0 -= b[0] * x0 + b[1] * x1 + b[2] * x2;
		s1 -= b[3] * x0 + b[4] * x1 + b[5] * x2;
		s2 -= b[6] * x0 + b[7] * x1 + b[8] * x2;
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

/* C -= A B^T */
static void
blk_sub_abt(const double *a, const double *b, double *c)
{
	int i, j;

	for (i = 0; i < 3; i++)
		for (j = 0; j < 3; j++)
			c[3 * i + j] -= a[3 * i] * b[3 * j] + a[3 * i + 1] * b[3 * j + 1] +
			    a[3 * i + 2] * b[3 * j + 2];
}

/* C = A B */
static void
blk_ab(const double *a, const double *b, double *c)
{
	int i, j;

	for (i = 0; i < 3; i++)
		for (j = 0; j < 3; j++)
			c[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
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
	free(m->chol);
	free(m->line_buf);
	free(m->row_buf);
	memset(m, 0, sizeof *m);
}

/* ---- the hierarchy ---- */

/* One direction's coarsening: of nf grid lines at places x, every other
 * one and the last are kept (all of them when `coarsen` is 0). For each
 * fine line f: its coarse neighbours lo[f] <= hi[f] (equal on a kept
 * line) and lo's linear weight wlo[f] by place; xc gets the kept lines'
 * places. Returns the coarse count. */
static int
coarsen_dir(int nf, const double *x, int coarsen, int *lo, int *hi, double *wlo, double *xc)
{
	int f, nc = 0;

	for (f = 0; f < nf; f++) {
		lo[f] = -1;
		if (!coarsen || f % 2 == 0 || f == nf - 1) {
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

/* Level c from level f (the grid coarsened in the directions asked), and
 * f's interpolation from c. 0, or -1 out of memory. */
static int
coarsen_level(struct mg_level *f, struct mg_level *c, int cu_dir, int cv_dir)
{
	int ok = 1, i, j, p, k;
	int *lou = zalloc((size_t)f->nu, sizeof *lou, &ok), *hiu = zalloc((size_t)f->nu, sizeof *hiu, &ok);
	int *lov = zalloc((size_t)f->nv, sizeof *lov, &ok), *hiv = zalloc((size_t)f->nv, sizeof *hiv, &ok);
	double *wu = zalloc((size_t)f->nu, sizeof *wu, &ok), *wv = zalloc((size_t)f->nv, sizeof *wv, &ok);

	c->xu = zalloc((size_t)f->nu, sizeof *c->xu, &ok);
	c->xv = zalloc((size_t)f->nv, sizeof *c->xv, &ok);
	if (!ok)
		goto out;
	c->nu = coarsen_dir(f->nu, f->xu, cu_dir, lou, hiu, wu, c->xu);
	c->nv = coarsen_dir(f->nv, f->xv, cv_dir, lov, hiv, wv, c->xv);
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

	/* interpolation, by fine node */
	f->pstart = zalloc((size_t)f->n + 1, sizeof *f->pstart, &ok);
	f->par = zalloc(4 * (size_t)f->n, sizeof *f->par, &ok);
	f->pw = zalloc(4 * (size_t)f->n, sizeof *f->pw, &ok);
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
	free(lou);
	free(hiu);
	free(lov);
	free(hiv);
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

/* c's pattern, P^T A P's (row I: the slots of the rows of I's children),
 * and the recipe of its values (see struct mg_level). 0, or -1 out of
 * memory. */
static int
galerkin_recipe(struct mg_level *f, struct mg_level *c, int *mark)
{
	int ok = 1, a, e, s, I, k, nrec1 = 0, nslot = 0, npair = 0, nr = 0, r;
	int *tcol = NULL, *cnt = zalloc((size_t)c->n + 1, sizeof *cnt, &ok), *cols = NULL;

	f->tstart = zalloc((size_t)f->n + 1, sizeof *f->tstart, &ok);
	f->rstart = zalloc((size_t)f->pstart[f->n] + 1, sizeof *f->rstart, &ok);
	if (!ok)
		goto out;
	for (I = 0; I < c->n; I++)
		mark[I] = -1;
	for (k = 0; k < f->A.start[f->n]; k++)
		nrec1 += f->pstart[f->A.col[k] + 1] - f->pstart[f->A.col[k]];
	if ((tcol = zalloc((size_t)nrec1, sizeof *tcol, &ok)) == NULL ||
	    (f->rec1 = zalloc((size_t)nrec1, sizeof *f->rec1, &ok)) == NULL)
		goto out;
	/* the slots of every row, one after the other in tcol */
	for (a = 0, nrec1 = 0; a < f->n; a++) {
		f->tstart[a] = nslot;
		nslot += ap_row_slots(f, a, mark, tcol + nslot, f->rec1 + nrec1);
		for (k = f->A.start[a]; k < f->A.start[a + 1]; k++)
			nrec1 += f->pstart[f->A.col[k] + 1] - f->pstart[f->A.col[k]];
	}
	f->tstart[f->n] = nslot;
	/* the pattern: row I gets the slots of each row a it interpolates to */
	for (a = 0; a < f->n; a++)
		for (e = f->pstart[a]; e < f->pstart[a + 1]; e++)
			cnt[f->par[e] + 1] += f->tstart[a + 1] - f->tstart[a];
	for (I = 0; I < c->n; I++)
		cnt[I + 1] += cnt[I];
	npair = cnt[c->n];
	if ((cols = zalloc((size_t)npair, sizeof *cols, &ok)) == NULL)
		goto out;
	for (a = 0; a < f->n; a++)
		for (e = f->pstart[a]; e < f->pstart[a + 1]; e++)
			for (s = f->tstart[a]; s < f->tstart[a + 1]; s++)
				cols[cnt[f->par[e]]++] = tcol[s];
	for (I = c->n; I > 0; I--)	/* cnt[I] had moved to row I's end */
		cnt[I] = cnt[I - 1];
	cnt[0] = 0;
	if (blockmat_init_pattern(&c->A, c->n, cnt, cols) != 0) {
		ok = 0;
		goto out;
	}
	/* the recipe's second half: the upper triangle's (I <= J) pairs */
	for (a = 0; a < f->n; a++)
		for (e = f->pstart[a]; e < f->pstart[a + 1]; e++)
			for (s = f->tstart[a]; s < f->tstart[a + 1]; s++)
				nr += f->par[e] <= tcol[s];
	f->rslot = zalloc((size_t)nr, sizeof *f->rslot, &ok);
	f->rdst = zalloc((size_t)nr, sizeof *f->rdst, &ok);
	c->mirror = zalloc(c->A.nblocks, sizeof *c->mirror, &ok);
	if (!ok)
		goto out;
	for (a = 0, r = 0; a < f->n; a++)
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
out:
	free(tcol);
	free(cnt);
	free(cols);
	return ok ? 0 : -1;
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

/* The off-line blocks of position t's row (node p, line l): the earlier
 * lines' first, then the later lines'. Warp lines use the level matrix's
 * rows as they are (a line's nodes are consecutive, so its blocks are one
 * run in the sorted row, and the positions are the nodes); weft lines
 * (copy) a copy, listed here (n: how many so far). */
static void
list_off_line(struct mg_lines *ln, const struct blockmat *A, int copy, int t, int l,
    const int *lineid, size_t *n)
{
	int p = ln->order[t], k, later;

	if (!copy) {
		ln->lo[t] = A->start[p];
		for (k = A->start[p]; k < A->start[p + 1] && lineid[A->col[k]] < l; k++)
			;
		ln->mid[t] = k;
		for (; k < A->start[p + 1] && lineid[A->col[k]] == l; k++)
			;
		ln->hi[t] = k;
		return;
	}
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
	int ok = 1, n = lv->n, t, k, l, nb, pass, copy = dir != 0;
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
	for (t = 0; t < n; t++)
		copy |= ln->order[t] != t;	/* not so on our numbering: kept general */
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
	/* two passes for the weft lines: count their off-line blocks, then
	 * list them */
	for (pass = 0; pass < (copy ? 2 : 1); pass++) {
		if (pass == 1) {
			ln->src = zalloc(noff, sizeof *ln->src, &ok);
			ln->own_col = zalloc(noff, sizeof *ln->own_col, &ok);
			ln->own_val = zalloc(9 * noff, sizeof *ln->own_val, &ok);
			if (!ok)
				goto out;
		}
		for (l = 0, noff = 0; l < ln->nlines; l++)
			for (t = ln->start[l]; t < ln->start[l + 1]; t++)
				list_off_line(ln, A, copy, t, l, lineid, &noff);
	}
	ln->lo[n] = copy ? (int)noff : A->start[n];
	ln->col = copy ? ln->own_col : A->col;
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
	for (i = 0; i < cl->nu; i++)
		lv->xu[i] = i;
	for (i = 0; i < cl->nv; i++)
		lv->xv[i] = i;
	if (blockmat_init_cloth(&lv->A, cl) != 0)
		return -1;
	/* the pattern alone: mg_setup reads the caller's values */
	free(lv->A.val);
	lv->A.val = NULL;
	return 0;
}

/* Whether level lv is the coarsest, and if not which directions coarsen. */
static int
is_coarsest(const struct mg_level *lv, int *cu, int *cv)
{
	*cu = lv->nu >= MG_MIN_LINES;
	*cv = lv->nv >= MG_MIN_LINES;
	return lv->n <= MG_COARSEST || (!*cu && !*cv);
}

/* The levels' grids and interpolations, coarsening until the coarsest.
 * 0, or -1 out of memory. */
static int
build_levels(struct mg *m, const struct cloth *cl)
{
	int l, cu, cv, cap = 4;

	if ((m->lv = calloc((size_t)cap, sizeof *m->lv)) == NULL)
		return -1;
	m->nlevels = 1;
	if (finest_level(&m->lv[0], cl) != 0)
		return -1;
	for (l = 0; !is_coarsest(&m->lv[l], &cu, &cv); l++) {
		if (m->nlevels == cap) {
			struct mg_level *more = realloc(m->lv, 2 * (size_t)cap * sizeof *more);

			if (more == NULL)
				return -1;
			memset(more + cap, 0, (size_t)cap * sizeof *more);
			m->lv = more;
			cap *= 2;
		}
		m->nlevels++;
		if (coarsen_level(&m->lv[l], &m->lv[l + 1], cu, cv) != 0)
			return -1;
	}
	return 0;
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
	m->ncoarse = m->lv[m->nlevels - 1].n;
	m->chol = zalloc(9 * (size_t)m->ncoarse * (size_t)m->ncoarse, sizeof *m->chol, &ok);
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

			for (e = f->pstart[b]; e < f->pstart[b + 1]; e++) {
				double *d = buf + 9 * (size_t)f->rec1[q++], w = f->pw[e];

				for (i = 0; i < 9; i++)
					d[i] += w * src[i];
			}
		}
		for (e = f->pstart[a]; e < f->pstart[a + 1]; e++)
			for (r = f->rstart[e]; r < f->rstart[e + 1]; r++) {
				const double *s = buf + 9 * (size_t)f->rslot[r];
				double *d = c->A.val + 9 * (size_t)f->rdst[r], w = f->pw[e];

				for (i = 0; i < 9; i++)
					d[i] += w * s[i];
			}
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

/* lines[dir]'s values: the off-line blocks (copied for weft lines), and
 * the block LDL^T of each line (banded, 3 x 3 blocks): with
 * C(t, s) = L(t, s) D_s,
 *   C(t, t-k) = A(t, t-k) - sum_{k' > k} C(t, t-k') L(t-k, t-k')^T,
 *   D_t = A(t, t) - sum_k L(t, t-k) C(t, t-k)^T.
 * 0, or -1 when a pivot is not positive definite. */
static int
factor_lines(struct mg_level *lv, int dir)
{
	struct mg_lines *ln = &lv->lines[dir];
	int nb = ln->band, l, t, k, k2, i;
	size_t e, stride = 9 * (size_t)(nb + 1);

	if (ln->own_val != NULL) {
		for (e = 0; e < (size_t)ln->lo[lv->n]; e++)
			memcpy(ln->own_val + 9 * e, lv->val + 9 * (size_t)ln->src[e], 9 * sizeof *ln->own_val);
		ln->val = ln->own_val;
	} else {
		ln->val = lv->val;
	}
	for (l = 0; l < ln->nlines; l++)
		for (t = ln->start[l]; t < ln->start[l + 1]; t++) {
			int kmax = t - ln->start[l] < nb ? t - ln->start[l] : nb;
			const int *inl = ln->inl + (size_t)t * (size_t)(nb + 1);
			double *lt = ln->fac + stride * (size_t)t, d[9], c[9];

			for (k = kmax; k >= 1; k--) {
				double *ck = lt + 9 * (k - 1);
				const double *ls = ln->fac + stride * (size_t)(t - k);

				if (inl[k] >= 0)
					memcpy(ck, lv->val + 9 * (size_t)inl[k], 9 * sizeof *ck);
				else
					memset(ck, 0, 9 * sizeof *ck);
				for (k2 = k + 1; k2 <= kmax; k2++)
					blk_sub_abt(lt + 9 * (k2 - 1), ls + 9 * (k2 - k - 1), ck);
			}
			memcpy(d, lv->val + 9 * (size_t)inl[0], sizeof d);
			for (k = 1; k <= kmax; k++) {
				double *ck = lt + 9 * (k - 1);

				blk_ab(ck, ln->fac + stride * (size_t)(t - k) + 9 * (size_t)nb, c);
				blk_sub_abt(c, ck, d);
				for (i = 0; i < 9; i++)
					ck[i] = c[i];
			}
			if (blk_spd_inverse(d, lt + 9 * (size_t)nb) != 0)
				return -1;
		}
	return 0;
}

/* The coarsest level's dense Cholesky, lower triangle, row-major. */
static int
dense_factor(struct mg *m)
{
	const struct mg_level *lv = &m->lv[m->nlevels - 1];
	int N = 3 * lv->n, p, k, i, j, r;
	double *a = m->chol;

	memset(a, 0, (size_t)N * (size_t)N * sizeof *a);
	for (p = 0; p < lv->n; p++)
		for (k = lv->A.start[p]; k < lv->A.start[p + 1]; k++)
			for (i = 0; i < 3; i++)
				for (j = 0; j < 3; j++)
					a[(size_t)(3 * p + i) * N + 3 * lv->A.col[k] + j] =
					    lv->val[9 * (size_t)k + 3 * i + j];
	for (j = 0; j < N; j++) {
		double s = a[(size_t)j * N + j];

		for (k = 0; k < j; k++)
			s -= a[(size_t)j * N + k] * a[(size_t)j * N + k];
		if (!(s > 0) || !isfinite(s))
			return -1;
		a[(size_t)j * N + j] = sqrt(s);
		for (r = j + 1; r < N; r++) {
			double t = a[(size_t)r * N + j];

			/* the lower triangle from the upper's mirror: symmetric input */
			t = (t + a[(size_t)j * N + r]) / 2;
			for (k = 0; k < j; k++)
				t -= a[(size_t)r * N + k] * a[(size_t)j * N + k];
			a[(size_t)r * N + j] = t / a[(size_t)j * N + j];
		}
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

int
mg_setup(struct mg *m, const struct blockmat *A)
{
	int l;

	m->ready = 0;
	if (!same_pattern(&m->lv[0].A, A))
		return -1;
	m->lv[0].val = A->val;
	for (l = 0; l + 1 < m->nlevels; l++) {
		galerkin_values(&m->lv[l], &m->lv[l + 1], m->row_buf);
		if (factor_lines(&m->lv[l], 0) != 0 || factor_lines(&m->lv[l], 1) != 0)
			return -1;
	}
	if (dense_factor(m) != 0)
		return -1;
	m->ready = 1;
	return 0;
}

int
mg_update_fine(struct mg *m, const struct blockmat *A)
{
	if (!m->ready || m->nlevels == 1)
		return mg_setup(m, A);
	m->ready = 0;
	if (!same_pattern(&m->lv[0].A, A))
		return -1;
	m->lv[0].val = A->val;
	if (factor_lines(&m->lv[0], 0) != 0 || factor_lines(&m->lv[0], 1) != 0)
		return -1;
	m->ready = 1;
	return 0;
}

/* ---- apply ---- */

static void
dense_solve(const struct mg *m, const double *b, double *x)
{
	int N = 3 * m->ncoarse, i, k;
	const double *a = m->chol;

	for (i = 0; i < N; i++) {
		double s = b[i];

		for (k = 0; k < i; k++)
			s -= a[(size_t)i * N + k] * x[k];
		x[i] = s / a[(size_t)i * N + i];
	}
	for (i = N - 1; i >= 0; i--) {
		double s = x[i];

		for (k = i + 1; k < N; k++)
			s -= a[(size_t)k * N + i] * x[k];
		x[i] = s / a[(size_t)i * N + i];
	}
}

/* One line's Gauss-Seidel step: its nodes' z from the line's system with
 * the other lines' current z on the right (the later lines' left out on
 * a first sweep from z = 0: they are zero). */
static void
relax_line(const struct mg_lines *ln, int l, const double *r, double *z, int from_zero, double *y)
{
	int t0 = ln->start[l], t1 = ln->start[l + 1], nb = ln->band, t, k;
	size_t stride = 9 * (size_t)(nb + 1);
	const double *val = ln->val;
	const int *col = ln->col;

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

		row_mulsub(ln->val, ln->col, ln->hi[t], ln->lo[t + 1], dz, s);
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
			double *d = rc + 3 * f->par[e], w = f->pw[e];

			d[0] += w * res[3 * p];
			d[1] += w * res[3 * p + 1];
			d[2] += w * res[3 * p + 2];
		}
}

/* z += P zc */
static void
prolong_add(const struct mg_level *f, const double *zc, double *z)
{
	int p, e;

	for (p = 0; p < f->n; p++)
		for (e = f->pstart[p]; e < f->pstart[p + 1]; e++) {
			const double *s = zc + 3 * f->par[e];
			double w = f->pw[e];

			z[3 * p] += w * s[0];
			z[3 * p + 1] += w * s[1];
			z[3 * p + 2] += w * s[2];
		}
}

static void
vcycle(struct mg *m, int l, const double *r, double *z)
{
	struct mg_level *lv = &m->lv[l], *c;
	size_t i;

	if (l == m->nlevels - 1) {
		dense_solve(m, r, z);
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
	vcycle(m, 0, r, z);
}
