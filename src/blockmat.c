/* blockmat.c: the block sparse matrix (see blockmat.h). */
#include <stdlib.h>
#include <string.h>

#include "blockmat.h"

static int
cmp_int(const void *a, const void *b)
{
	int x = *(const int *)a, y = *(const int *)b;

	return (x > y) - (x < y);
}

int
blockmat_init_pattern(struct blockmat *A, int n, const int *start, const int *cols)
{
	size_t total = 0;
	int p;

	memset(A, 0, sizeof *A);
	A->n = n;
	if ((A->start = malloc(((size_t)n + 1) * sizeof *A->start)) == NULL ||
	    (A->diag = malloc(((size_t)n + 1) * sizeof *A->diag)) == NULL ||
	    (A->col = malloc(((size_t)start[n] + (size_t)n + 1) * sizeof *A->col)) == NULL)
		goto oom;
	/* each row: its columns and its diagonal, sorted, duplicates dropped */
	for (p = 0; p < n; p++) {
		int *row = A->col + total, m = 0, i;
		size_t len = (size_t)(start[p + 1] - start[p]);

		memcpy(row, cols + start[p], len * sizeof *row);
		row[len] = p;
		qsort(row, len + 1, sizeof *row, cmp_int);
		for (i = 0; i <= (int)len; i++)
			if (m == 0 || row[i] != row[m - 1])
				row[m++] = row[i];
		A->start[p] = (int)total;
		for (i = 0; i < m; i++)
			if (row[i] == p)
				A->diag[p] = (int)total + i;
		total += (size_t)m;
	}
	A->start[n] = (int)total;
	A->nblocks = total;
	if ((A->val = calloc(9 * (total + 1), sizeof *A->val)) == NULL)
		goto oom;
	return 0;
oom:
	blockmat_free(A);
	return -1;
}

/* Each element's nodes, pairwise: a row's entries before sorting. */
static void
couple(int *cnt, int *start, int *cols, const int *node, int k)
{
	int i, j;

	for (i = 0; i < k; i++)
		for (j = 0; j < k; j++) {
			if (i == j)
				continue;
			if (cols != NULL)
				cols[start[node[i]] + cnt[node[i]]] = node[j];
			cnt[node[i]]++;
		}
}

/* Each element's blocks, looked up once. 0, or -1 out of memory. */
static int
find_slots(struct blockmat *A, const struct cloth *cl)
{
	size_t e;
	int i, j;

	if ((A->spring_slot = malloc((2 * cl->nsprings + 1) * sizeof *A->spring_slot)) == NULL ||
	    (A->corner_slot = malloc((9 * cl->ncorners + 1) * sizeof *A->corner_slot)) == NULL ||
	    (A->hinge_slot = malloc((9 * cl->nhinges + 1) * sizeof *A->hinge_slot)) == NULL)
		return -1;
	for (e = 0; e < cl->nsprings; e++) {
		A->spring_slot[2 * e] = blockmat_find(A, cl->springs[e].a, cl->springs[e].b);
		A->spring_slot[2 * e + 1] = blockmat_find(A, cl->springs[e].b, cl->springs[e].a);
	}
	for (e = 0; e < cl->ncorners; e++) {
		int node[3] = { cl->corners[e].c, cl->corners[e].a, cl->corners[e].b };

		for (i = 0; i < 3; i++)
			for (j = 0; j < 3; j++)
				A->corner_slot[9 * e + 3 * i + j] = blockmat_find(A, node[i], node[j]);
	}
	for (e = 0; e < cl->nhinges; e++) {
		int node[3] = { cl->hinges[e].a, cl->hinges[e].b, cl->hinges[e].c };

		for (i = 0; i < 3; i++)
			for (j = 0; j < 3; j++)
				A->hinge_slot[9 * e + 3 * i + j] = blockmat_find(A, node[i], node[j]);
	}
	return 0;
}

int
blockmat_init_cloth(struct blockmat *A, const struct cloth *cl)
{
	int n = cl->n, *cnt = calloc((size_t)n + 1, sizeof *cnt);
	int *start = malloc(((size_t)n + 1) * sizeof *start), *cols = NULL, pass, p, r;
	size_t e;

	if (cnt == NULL || start == NULL)
		goto oom;
	/* two passes: count each row's entries, then fill them */
	for (pass = 0; pass < 2; pass++) {
		memset(cnt, 0, ((size_t)n + 1) * sizeof *cnt);
		for (e = 0; e < cl->nsprings; e++) {
			int node[2] = { cl->springs[e].a, cl->springs[e].b };

			couple(cnt, start, cols, node, 2);
		}
		for (e = 0; e < cl->ncorners; e++) {
			int node[3] = { cl->corners[e].c, cl->corners[e].a, cl->corners[e].b };

			couple(cnt, start, cols, node, 3);
		}
		for (e = 0; e < cl->nhinges; e++) {
			int node[3] = { cl->hinges[e].a, cl->hinges[e].b, cl->hinges[e].c };

			couple(cnt, start, cols, node, 3);
		}
		if (pass == 1)
			break;
		start[0] = 0;
		for (p = 0; p < n; p++)
			start[p + 1] = start[p] + cnt[p];
		if ((cols = malloc(((size_t)start[n] + 1) * sizeof *cols)) == NULL)
			goto oom;
	}
	r = blockmat_init_pattern(A, n, start, cols);
	free(cnt);
	free(start);
	free(cols);
	if (r == 0 && find_slots(A, cl) != 0) {
		blockmat_free(A);
		return -1;
	}
	return r;
oom:
	free(cnt);
	free(start);
	free(cols);
	memset(A, 0, sizeof *A);
	return -1;
}

void
blockmat_free(struct blockmat *A)
{
	free(A->start);
	free(A->col);
	free(A->diag);
	free(A->val);
	free(A->spring_slot);
	free(A->corner_slot);
	free(A->hinge_slot);
	memset(A, 0, sizeof *A);
}

void
blockmat_zero(struct blockmat *A)
{
	memset(A->val, 0, 9 * A->nblocks * sizeof *A->val);
}

int
blockmat_find(const struct blockmat *A, int row, int col)
{
	int lo = A->start[row], hi = A->start[row + 1] - 1;

	while (lo <= hi) {
		int mid = lo + (hi - lo) / 2;

		if (A->col[mid] == col)
			return mid;
		if (A->col[mid] < col)
			lo = mid + 1;
		else
			hi = mid - 1;
	}
	return -1;
}

void
blockmat_mul(const struct blockmat *A, const double *x, double *y)
{
	int p, k;

	for (p = 0; p < A->n; p++) {
		double s0 = 0, s1 = 0, s2 = 0;

		for (k = A->start[p]; k < A->start[p + 1]; k++) {
			const double *b = A->val + 9 * (size_t)k, *xc = x + 3 * (size_t)A->col[k];

			s0 += b[0] * xc[0] + b[1] * xc[1] + b[2] * xc[2];
			s1 += b[3] * xc[0] + b[4] * xc[1] + b[5] * xc[2];
			s2 += b[6] * xc[0] + b[7] * xc[1] + b[8] * xc[2];
		}
		y[3 * p] = s0;
		y[3 * p + 1] = s1;
		y[3 * p + 2] = s2;
	}
}
