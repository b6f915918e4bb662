/* cloth.c: building the network from a scene.
 *
 * Each element's stiffness is chosen so that the grid stores the continuum
 * energy of the material it stands for (drape-scene(5) gives the formulas):
 * a spring of a yarn direction carries E*t over its tributary width, a square
 * stores G*t*h^2*gamma^2/2 of shear in its four corners, and a hinge stores
 * B*w*theta^2/(2h) of bending, theta/h being the curvature. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cloth.h"
#include "vec3.h"

/* Width of the strip of cloth a node line stands for: half at the border. */
static double
tributary(int k, int n, double h)
{
	return k == 0 || k == n - 1 ? h / 2 : h;
}

static int
build_elements(struct cloth *cl, const struct scene *sc)
{
	const struct material *m = &sc->mat;
	int nu = cl->nu, nv = cl->nv, i, j;
	double h = cl->h;
	size_t ns = 0, nc = 0, nh = 0;

	cl->springs = malloc(((size_t)(nu - 1) * nv + (size_t)nu * (nv - 1)) * sizeof *cl->springs);
	if (cl->springs == NULL)
		return -1;
	for (j = 0; j < nv; j++)
		for (i = 0; i + 1 < nu; i++)
			cl->springs[ns++] = (struct spring){ cloth_node(cl, i, j),
			    cloth_node(cl, i + 1, j), m->modulus[0] * m->thickness *
			    tributary(j, nv, h) / h, h };
	for (j = 0; j + 1 < nv; j++)
		for (i = 0; i < nu; i++)
			cl->springs[ns++] = (struct spring){ cloth_node(cl, i, j),
			    cloth_node(cl, i, j + 1), m->modulus[1] * m->thickness *
			    tributary(i, nu, h) / h, h };
	cl->nsprings = ns;

	/* Nothing is built for a material property that is zero. */
	if (m->shear_modulus > 0) {
		double k = m->shear_modulus * m->thickness * h * h / 4;

		cl->corners = malloc((size_t)4 * (nu - 1) * (nv - 1) * sizeof *cl->corners);
		if (cl->corners == NULL)
			return -1;
		for (j = 0; j + 1 < nv; j++)
			for (i = 0; i + 1 < nu; i++) {
				int p00 = cloth_node(cl, i, j), p10 = cloth_node(cl, i + 1, j);
				int p01 = cloth_node(cl, i, j + 1), p11 = cloth_node(cl, i + 1, j + 1);

				cl->corners[nc++] = (struct corner){ p00, p10, p01, k };
				cl->corners[nc++] = (struct corner){ p10, p00, p11, k };
				cl->corners[nc++] = (struct corner){ p11, p01, p10, k };
				cl->corners[nc++] = (struct corner){ p01, p11, p00, k };
			}
	}
	cl->ncorners = nc;

	if (m->bending[0] > 0 || m->bending[1] > 0) {
		cl->hinges = malloc(((size_t)(nu - 2) * nv + (size_t)nu * (nv - 2) + 1) *
		    sizeof *cl->hinges);
		if (cl->hinges == NULL)
			return -1;
		if (m->bending[0] > 0)
			for (j = 0; j < nv; j++)
				for (i = 1; i + 1 < nu; i++)
					cl->hinges[nh++] = (struct hinge){ cloth_node(cl, i - 1, j),
					    cloth_node(cl, i, j), cloth_node(cl, i + 1, j),
					    m->bending[0] * tributary(j, nv, h) / h };
		if (m->bending[1] > 0)
			for (i = 0; i < nu; i++)
				for (j = 1; j + 1 < nv; j++)
					cl->hinges[nh++] = (struct hinge){ cloth_node(cl, i, j - 1),
					    cloth_node(cl, i, j), cloth_node(cl, i, j + 1),
					    m->bending[1] * tributary(i, nu, h) / h };
	}
	cl->nhinges = nh;
	return 0;
}

/* Compressed node -> item lists from items of `per` nodes each. */
static int
build_adjacency(int n, const int *items, size_t nitems, int per, int **startp, int **listp)
{
	int *start = calloc((size_t)n + 1, sizeof *start), *fill, *list;
	size_t t;
	int k;

	if (start == NULL)
		return -1;
	for (t = 0; t < nitems; t++)
		for (k = 0; k < per; k++)
			start[items[per * t + k] + 1]++;
	for (k = 0; k < n; k++)
		start[k + 1] += start[k];
	list = malloc((size_t)start[n] * sizeof *list + 1);
	fill = malloc((size_t)n * sizeof *fill + 1);
	if (list == NULL || fill == NULL) {
		free(start);
		free(list);
		free(fill);
		return -1;
	}
	memcpy(fill, start, (size_t)n * sizeof *fill);
	for (t = 0; t < nitems; t++)	/* ascending item order within each node */
		for (k = 0; k < per; k++)
			list[fill[items[per * t + k]]++] = (int)t;
	free(fill);
	*startp = start;
	*listp = list;
	return 0;
}

static int
build_triangles(struct cloth *cl)
{
	int nu = cl->nu, nv = cl->nv, i, j;
	size_t nt = 0, ne = 0;

	cl->ntri = (size_t)2 * (nu - 1) * (nv - 1);
	cl->nedges = (size_t)(nu - 1) * nv + (size_t)nu * (nv - 1) + (size_t)(nu - 1) * (nv - 1);
	cl->tri = malloc(3 * cl->ntri * sizeof *cl->tri);
	cl->edge = malloc(2 * cl->nedges * sizeof *cl->edge);
	if (cl->tri == NULL || cl->edge == NULL)
		return -1;

	for (j = 0; j + 1 < nv; j++)
		for (i = 0; i + 1 < nu; i++) {
			int a = cloth_node(cl, i, j), b = cloth_node(cl, i + 1, j);
			int c = cloth_node(cl, i + 1, j + 1), d = cloth_node(cl, i, j + 1);
			int t[6], k;

			/* Diagonals alternate like a chequerboard, so that the mesh
			 * has no preferred diagonal direction. */
			if ((i + j) % 2 == 0) {
				int u[6] = { a, b, c, a, c, d };

				memcpy(t, u, sizeof t);
				cl->edge[2 * ne] = a, cl->edge[2 * ne + 1] = c, ne++;
			} else {
				int u[6] = { a, b, d, b, c, d };

				memcpy(t, u, sizeof t);
				cl->edge[2 * ne] = b, cl->edge[2 * ne + 1] = d, ne++;
			}
			for (k = 0; k < 6; k++)
				cl->tri[3 * nt + (size_t)k] = t[k];
			nt += 2;
		}
	for (j = 0; j < nv; j++)
		for (i = 0; i + 1 < nu; i++)
			cl->edge[2 * ne] = cloth_node(cl, i, j),
			cl->edge[2 * ne + 1] = cloth_node(cl, i + 1, j), ne++;
	for (j = 0; j + 1 < nv; j++)
		for (i = 0; i < nu; i++)
			cl->edge[2 * ne] = cloth_node(cl, i, j),
			cl->edge[2 * ne + 1] = cloth_node(cl, i, j + 1), ne++;

	if (build_adjacency(cl->n, cl->tri, cl->ntri, 3, &cl->node_tri_start, &cl->node_tri) != 0 ||
	    build_adjacency(cl->n, cl->edge, cl->nedges, 2, &cl->node_edge_start,
		&cl->node_edge) != 0)
		return -1;
	return 0;
}

int
cloth_build(struct cloth *cl, const struct scene *sc, struct drape_err *err)
{
	vec3 o = v3_load(sc->origin), wu = v3_load(sc->warp_axis), wv = v3_load(sc->weft_axis);
	int i, j;

	memset(cl, 0, sizeof *cl);
	cl->nu = sc->nu;
	cl->nv = sc->nv;
	cl->n = sc->nu * sc->nv;
	cl->h = sc->spacing;
	cl->x0 = malloc((size_t)cl->n * 3 * sizeof *cl->x0);
	cl->mass = malloc((size_t)cl->n * sizeof *cl->mass);
	if (cl->x0 == NULL || cl->mass == NULL)
		goto oom;
	for (j = 0; j < cl->nv; j++)
		for (i = 0; i < cl->nu; i++) {
			int p = cloth_node(cl, i, j);

			v3_store(cl->x0 + 3 * p, v3_madd(v3_madd(o, wu, i * cl->h), wv, j * cl->h));
			cl->mass[p] = sc->mat.weight * tributary(i, cl->nu, cl->h) *
			    tributary(j, cl->nv, cl->h);
		}
	if (build_elements(cl, sc) != 0 || build_triangles(cl) != 0)
		goto oom;
	return 0;
oom:
	cloth_free(cl);
	err_set(err, "%s: out of memory for a %d x %d cloth", sc->path, sc->nu, sc->nv);
	return -1;
}

void
cloth_free(struct cloth *cl)
{
	free(cl->x0);
	free(cl->mass);
	free(cl->springs);
	free(cl->corners);
	free(cl->hinges);
	free(cl->tri);
	free(cl->edge);
	free(cl->node_tri_start);
	free(cl->node_tri);
	free(cl->node_edge_start);
	free(cl->node_edge);
	memset(cl, 0, sizeof *cl);
}

void
cloth_clamp_hinges(struct cloth *cl, const unsigned char *held)
{
	size_t e;

	for (e = 0; e < cl->nhinges; e++) {
		struct hinge *hg = &cl->hinges[e];

		if (held[hg->b] && held[hg->a] != held[hg->c])
			hg->k *= 2;
	}
}

double
cloth_omega_bound(const struct cloth *cl)
{
	/* Row sums of |K| per node: for an element of stiffness k whose
	 * generalised coordinate has gradient norms g_a at its nodes, node a
	 * gets k * g_a * sum(g). At rest a spring has g = (1, 1); a shear
	 * corner (1, 1, sqrt 2)/h at its outer nodes and corner; a hinge
	 * (1, 2, 1)/h. */
	double *row = calloc((size_t)cl->n, sizeof *row), h = cl->h, w2 = 0;
	size_t e;
	int i;

	if (row == NULL)
		return NAN;
	for (e = 0; e < cl->nsprings; e++) {
		row[cl->springs[e].a] += 2 * cl->springs[e].k;
		row[cl->springs[e].b] += 2 * cl->springs[e].k;
	}
	for (e = 0; e < cl->ncorners; e++) {
		double s = (2 + sqrt(2)) / h, k = cl->corners[e].k;

		row[cl->corners[e].a] += k * s / h;
		row[cl->corners[e].b] += k * s / h;
		row[cl->corners[e].c] += k * s * sqrt(2) / h;
	}
	for (e = 0; e < cl->nhinges; e++) {
		double k = cl->hinges[e].k / (h * h);

		row[cl->hinges[e].a] += 4 * k;
		row[cl->hinges[e].b] += 8 * k;
		row[cl->hinges[e].c] += 4 * k;
	}
	for (i = 0; i < cl->n; i++)
		if (row[i] / cl->mass[i] > w2)
			w2 = row[i] / cl->mass[i];
	free(row);
	return sqrt(w2);
}
