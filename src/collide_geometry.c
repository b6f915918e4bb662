/* collide_geometry.c: the geometry contacts are sought in: the cloth's
 * triangles and edges, then each obstacle mesh's, renumbered into one set
 * of vertices, with vertex -> triangle and vertex -> edge incidence. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collide_impl.h"

static void *
xcalloc(size_t n, size_t size)
{
	return calloc(n ? n : 1, size);
}

/* vertex -> items incidence, compressed (each item has `per` vertices) */
static int
incidence(const int *items, size_t nitems, int per, int nv, int **start, int **list)
{
	size_t i;
	int k, *fill;

	if ((*start = xcalloc((size_t)nv + 1, sizeof **start)) == NULL ||
	    (*list = xcalloc(nitems * (size_t)per, sizeof **list)) == NULL ||
	    (fill = xcalloc((size_t)nv, sizeof *fill)) == NULL)
		return -1;
	for (i = 0; i < nitems * (size_t)per; i++)
		(*start)[items[i] + 1]++;
	for (k = 0; k < nv; k++)
		(*start)[k + 1] += (*start)[k];
	for (i = 0; i < nitems; i++)
		for (k = 0; k < per; k++) {
			int v = items[i * (size_t)per + (size_t)k];

			(*list)[(*start)[v] + fill[v]++] = (int)i;
		}
	free(fill);
	return 0;
}

static int
cmp_edge(const void *pa, const void *pb)
{
	const int *a = pa, *b = pb;

	if (a[0] != b[0])
		return a[0] < b[0] ? -1 : 1;
	return (a[1] > b[1]) - (a[1] < b[1]);
}

/* The cloth's grid for the broad phase's flat patches (broad.h): each
 * triangle's square and each node's place at rest. On a grid of squares
 * of side h, each cut by one diagonal, two primitives that share no vertex
 * are at least h / sqrt 2 apart at rest (a node and the far side of a
 * square's triangle), and a primitive's vertices at most a diagonal. */
static int
grid_geometry(struct collide *c, const struct cloth *cl)
{
	size_t t;
	int p, su = cl->nu - 1;

	if ((c->tri_square = xcalloc(cl->ntri, sizeof *c->tri_square)) == NULL ||
	    (c->uv = xcalloc(2 * (size_t)cl->n, sizeof *c->uv)) == NULL)
		return -1;
	for (p = 0; p < cl->n; p++) {
		int i, j;

		cloth_grid_ij(cl, p, &i, &j);
		c->uv[2 * p] = i * cl->h;
		c->uv[2 * p + 1] = j * cl->h;
	}
	for (t = 0; t < cl->ntri; t++) {
		int i = INT_MAX, j = INT_MAX, k;

		for (k = 0; k < 3; k++) {
			int a, b;

			cloth_grid_ij(cl, cl->tri[3 * t + (size_t)k], &a, &b);
			i = a < i ? a : i;
			j = b < j ? b : j;
		}
		c->tri_square[t] = j * su + i;
	}
	c->g.tri_square = c->tri_square;
	c->g.squares_u = su;
	c->g.squares_v = cl->nv - 1;
	c->g.uv = c->uv;
	c->g.uv_gap = cl->h / sqrt(2);
	c->g.uv_diam = cl->h * sqrt(2);
	return 0;
}

/* The cloth's triangles and edges, then each obstacle mesh's, renumbered. */
int
collide_build_geometry(struct collide *c, const struct cloth *cl, const unsigned char *held)
{
	size_t o, t, nt = cl->ntri, ne = cl->nedges;
	int nv = cl->n, k;

	for (o = 0; o < c->nobst; o++)
		if (c->obst[o].kind == OBSTACLE_MESH) {
			nv += c->obst[o].mesh.nverts;
			nt += c->obst[o].mesh.ntri;
			ne += 3 * c->obst[o].mesh.ntri;	/* before removing repeats */
		}
	c->ncloth = cl->n;
	c->nv = nv;
	c->ntri_cloth = cl->ntri;
	if ((c->x0 = xcalloc(3 * (size_t)nv, sizeof *c->x0)) == NULL ||
	    (c->x1 = xcalloc(3 * (size_t)nv, sizeof *c->x1)) == NULL ||
	    (c->v1 = xcalloc(3 * (size_t)nv, sizeof *c->v1)) == NULL ||
	    (c->tri = xcalloc(3 * nt, sizeof *c->tri)) == NULL ||
	    (c->edge = xcalloc(2 * ne, sizeof *c->edge)) == NULL ||
	    (c->tri_obstacle = xcalloc(nt, sizeof *c->tri_obstacle)) == NULL ||
	    (c->fixed = xcalloc((size_t)nv, 1)) == NULL ||
	    (c->inv_mass = xcalloc((size_t)nv, sizeof *c->inv_mass)) == NULL ||
	    (c->changed = xcalloc((size_t)nv, 1)) == NULL ||
	    (c->changed_next = xcalloc((size_t)nv, 1)) == NULL ||
	    (c->frozen = xcalloc((size_t)nv, 1)) == NULL ||
	    (c->box = xcalloc(6 * (size_t)nv, sizeof *c->box)) == NULL)
		return -1;
	memcpy(c->tri, cl->tri, 3 * cl->ntri * sizeof *c->tri);
	memcpy(c->edge, cl->edge, 2 * cl->nedges * sizeof *c->edge);
	for (t = 0; t < cl->ntri; t++)
		c->tri_obstacle[t] = -1;
	for (k = 0; k < cl->n; k++) {
		c->fixed[k] = held != NULL && held[k];
		c->inv_mass[k] = c->fixed[k] || !(cl->mass[k] > 0) ? 0 : 1 / cl->mass[k];
	}
	c->ntri = cl->ntri;
	c->nedges = cl->nedges;
	nv = cl->n;
	for (o = 0; o < c->nobst; o++) {
		const struct mesh *m = &c->obst[o].mesh;
		size_t first_edge = c->nedges, i, kept;

		if (c->obst[o].kind != OBSTACLE_MESH)
			continue;
		memcpy(c->x0 + 3 * (size_t)nv, m->x, 3 * (size_t)m->nverts * sizeof *m->x);
		memcpy(c->x1 + 3 * (size_t)nv, m->x, 3 * (size_t)m->nverts * sizeof *m->x);
		for (k = 0; k < m->nverts; k++)
			c->fixed[nv + k] = 1;
		for (t = 0; t < m->ntri; t++) {
			for (k = 0; k < 3; k++) {
				int a = nv + m->tri[3 * t + (size_t)k];
				int b = nv + m->tri[3 * t + (size_t)(k + 1) % 3];

				c->tri[3 * c->ntri + (size_t)k] = a;
				c->edge[2 * c->nedges] = a < b ? a : b;
				c->edge[2 * c->nedges + 1] = a < b ? b : a;
				c->nedges++;
			}
			c->tri_obstacle[c->ntri++] = (int)o;
		}
		/* a closed mesh has each edge twice */
		qsort(c->edge + 2 * first_edge, c->nedges - first_edge, 2 * sizeof *c->edge, cmp_edge);
		for (i = kept = first_edge; i < c->nedges; i++)
			if (kept == first_edge || cmp_edge(c->edge + 2 * i, c->edge + 2 * (kept - 1)) != 0) {
				c->edge[2 * kept] = c->edge[2 * i];
				c->edge[2 * kept + 1] = c->edge[2 * i + 1];
				kept++;
			}
		c->nedges = kept;
		nv += m->nverts;
	}
	if (incidence(c->tri, c->ntri, 3, c->nv, &c->vtri_start, &c->vtri) != 0 ||
	    incidence(c->edge, c->nedges, 2, c->nv, &c->vedge_start, &c->vedge) != 0)
		return -1;
	for (k = c->ncloth; k < c->nv; k++)	/* obstacle vertices stay put */
		for (t = 0; t < 6; t++)
			c->box[6 * k + t] = c->x0[3 * k + t % 3];
	c->g = (struct geom){ c->nv, c->ncloth, c->x0, c->x1, c->tri, c->ntri, c->edge,
	    c->nedges, c->vtri_start, c->vtri, c->vedge_start, c->vedge, c->fixed, NULL,
	    NULL, 0, 0, NULL, 0, 0 };
	return cl->ntri > 0 && cl->nu > 1 && cl->nv > 1 ? grid_geometry(c, cl) : 0;
}
