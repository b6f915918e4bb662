/* cloth.c: building the network from a scene.
 *
 * Each element's stiffness is chosen so that the grid stores the continuum
 * energy of the material it stands for (drape-scene(5) gives the formulas):
 * a spring of a yarn direction carries E*t over its tributary width, a square
 * stores G*t*h^2*gamma^2/2 of shear in its four corners, and a hinge stores
 * B*w*theta^2/(2h) of bending, theta/h being the curvature. */
#include <math.h>
#include <stdbool.h>
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

/*
 * The shape is a set of whole squares: a disc keeps the squares whose
 * centres lie in the circle inscribed in the grid, and its nodes are the
 * corners of those squares. Keeping squares rather than nodes gives every
 * node a mass (the squares around it) and every node a triangle (what
 * collisions need). Taking a square by its centre puts the staircase
 * outline as much outside the circle as inside, so the cloth's area is the
 * circle's to a few squares (716 of 707 on a 30 cm disc of 10 mm squares,
 * 2828 of 2827 on 5 mm); the squares wholly inside would leave a rim two
 * thirds of a square short all round (648 and 2700), a shorter overhang
 * that drapes less. The widths and areas below come from the squares
 * present, so a spring, hinge or node of the disc's rim stands for the
 * cloth on its inner side only, as one of a square cloth's border does.
 */
static int
square_at(const struct cloth *cl, const unsigned char *sq, int i, int j)
{
	return i >= 0 && j >= 0 && i + 1 < cl->nu && j + 1 < cl->nv && sq[j * (cl->nu - 1) + i];
}

/* A square cloth keeps tributary(), so that a cloth one node wide still
 * counts as h/2 wide; on a cloth two nodes wide or more both rules agree,
 * bit for bit. */
static double
warp_width(const struct cloth *cl, const unsigned char *sq, int i, int j)
{
	if (cl->shape == SHAPE_SQUARE)
		return tributary(j, cl->nv, cl->h);
	return cl->h / 2 * (square_at(cl, sq, i, j - 1) + square_at(cl, sq, i, j));
}

static double
weft_width(const struct cloth *cl, const unsigned char *sq, int i, int j)
{
	if (cl->shape == SHAPE_SQUARE)
		return tributary(i, cl->nu, cl->h);
	return cl->h / 2 * (square_at(cl, sq, i - 1, j) + square_at(cl, sq, i, j));
}

/* A node's mass: the weight of a quarter of each square around it. */
static double
node_mass(const struct cloth *cl, const unsigned char *sq, double weight, int i, int j)
{
	double h = cl->h;

	if (cl->shape == SHAPE_SQUARE)
		return weight * tributary(i, cl->nu, h) * tributary(j, cl->nv, h);
	return weight * (h / 2) * (h / 2) * (square_at(cl, sq, i - 1, j - 1) +
	    square_at(cl, sq, i, j - 1) + square_at(cl, sq, i - 1, j) + square_at(cl, sq, i, j));
}

/* The square (i, j)..(i + 1, j + 1) of a disc: its centre in the circle. */
static bool
disc_square(int nu, int nv, int i, int j)
{
	long di = 2L * i + 1 - (nu - 1), dj = 2L * j + 1 - (nv - 1), r = nu - 1;

	return i >= 0 && j >= 0 && i + 1 < nu && j + 1 < nv && di * di + dj * dj <= r * r;
}

bool
cloth_grid_has_node(enum cloth_shape shape, int nu, int nv, int i, int j)
{
	return shape == SHAPE_SQUARE || disc_square(nu, nv, i - 1, j - 1) ||
	    disc_square(nu, nv, i, j - 1) || disc_square(nu, nv, i - 1, j) ||
	    disc_square(nu, nv, i, j);
}

/* The squares that are cloth (sq, (nu-1)*(nv-1) flags), then the nodes
 * that are, numbered densely in grid order. */
static int
build_shape(struct cloth *cl, unsigned char **sqp)
{
	int nu = cl->nu, nv = cl->nv, i, j, p;
	size_t nsq = (size_t)(nu > 1 ? nu - 1 : 0) * (size_t)(nv > 1 ? nv - 1 : 0);
	unsigned char *sq = malloc(nsq + 1);

	*sqp = sq;
	cl->grid_node = malloc((size_t)nu * nv * sizeof *cl->grid_node);
	if (sq == NULL || cl->grid_node == NULL)
		return -1;
	cl->nsquares = 0;
	for (j = 0; j + 1 < nv; j++)
		for (i = 0; i + 1 < nu; i++) {
			int k = j * (nu - 1) + i;

			sq[k] = cl->shape == SHAPE_SQUARE || disc_square(nu, nv, i, j);
			cl->nsquares += sq[k];
		}
	for (j = 0, p = 0; j < nv; j++)
		for (i = 0; i < nu; i++) {
			int keep = cl->shape == SHAPE_SQUARE || square_at(cl, sq, i - 1, j - 1) ||
			    square_at(cl, sq, i, j - 1) || square_at(cl, sq, i - 1, j) ||
			    square_at(cl, sq, i, j);

			cl->grid_node[j * nu + i] = keep ? p++ : -1;
		}
	cl->n = p;
	cl->node_grid = malloc((size_t)cl->n * sizeof *cl->node_grid + 1);
	if (cl->node_grid == NULL)
		return -1;
	for (p = 0; p < nu * nv; p++)
		if (cl->grid_node[p] >= 0)
			cl->node_grid[cl->grid_node[p]] = p;
	return 0;
}

/* The node at (i, j), or -1 off the grid or off the shape. */
static int
node_at(const struct cloth *cl, int i, int j)
{
	return i >= 0 && j >= 0 && i < cl->nu && j < cl->nv ? cloth_node(cl, i, j) : -1;
}

static int
build_elements(struct cloth *cl, const struct scene *sc, const unsigned char *sq)
{
	const struct material *m = &sc->mat;
	int nu = cl->nu, nv = cl->nv, i, j;
	double h = cl->h;
	size_t ns = 0, nc = 0, nh = 0, grid = (size_t)nu * nv;

	/* Sized for the whole grid; a shape uses part of it. */
	cl->springs = malloc(2 * grid * sizeof *cl->springs);
	if (cl->springs == NULL)
		return -1;
	for (j = 0; j < nv; j++)
		for (i = 0; i + 1 < nu; i++) {
			int a = node_at(cl, i, j), b = node_at(cl, i + 1, j);
			double w = warp_width(cl, sq, i, j);

			if (a >= 0 && b >= 0 && w > 0)
				cl->springs[ns++] = (struct spring){ a, b,
				    m->modulus[0] * m->thickness * w / h, h };
		}
	for (j = 0; j + 1 < nv; j++)
		for (i = 0; i < nu; i++) {
			int a = node_at(cl, i, j), b = node_at(cl, i, j + 1);
			double w = weft_width(cl, sq, i, j);

			if (a >= 0 && b >= 0 && w > 0)
				cl->springs[ns++] = (struct spring){ a, b,
				    m->modulus[1] * m->thickness * w / h, h };
		}
	cl->nsprings = ns;

	/* Nothing is built for a material property that is zero. */
	if (m->shear_modulus > 0) {
		double k = m->shear_modulus * m->thickness * h * h / 4;

		cl->corners = malloc(4 * grid * sizeof *cl->corners);
		if (cl->corners == NULL)
			return -1;
		for (j = 0; j + 1 < nv; j++)
			for (i = 0; i + 1 < nu; i++) {
				int p00 = cloth_node(cl, i, j), p10 = cloth_node(cl, i + 1, j);
				int p01 = cloth_node(cl, i, j + 1), p11 = cloth_node(cl, i + 1, j + 1);

				if (!square_at(cl, sq, i, j))
					continue;
				cl->corners[nc++] = (struct corner){ p00, p10, p01, k };
				cl->corners[nc++] = (struct corner){ p10, p00, p11, k };
				cl->corners[nc++] = (struct corner){ p11, p01, p10, k };
				cl->corners[nc++] = (struct corner){ p01, p11, p00, k };
			}
	}
	cl->ncorners = nc;

	/* A hinge needs both its segments, and bends the width they stand for. */
	if (m->bending[0] > 0 || m->bending[1] > 0) {
		cl->hinges = malloc((2 * grid + 1) * sizeof *cl->hinges);
		if (cl->hinges == NULL)
			return -1;
		if (m->bending[0] > 0)
			for (j = 0; j < nv; j++)
				for (i = 1; i + 1 < nu; i++) {
					int a = node_at(cl, i - 1, j), b = node_at(cl, i, j);
					int c = node_at(cl, i + 1, j);
					double w1 = warp_width(cl, sq, i - 1, j);
					double w2 = warp_width(cl, sq, i, j);

					if (a >= 0 && b >= 0 && c >= 0 && w1 > 0 && w2 > 0)
						cl->hinges[nh++] = (struct hinge){ a, b, c,
						    m->bending[0] * ((w1 + w2) / 2) / h };
				}
		if (m->bending[1] > 0)
			for (i = 0; i < nu; i++)
				for (j = 1; j + 1 < nv; j++) {
					int a = node_at(cl, i, j - 1), b = node_at(cl, i, j);
					int c = node_at(cl, i, j + 1);
					double w1 = weft_width(cl, sq, i, j - 1);
					double w2 = weft_width(cl, sq, i, j);

					if (a >= 0 && b >= 0 && c >= 0 && w1 > 0 && w2 > 0)
						cl->hinges[nh++] = (struct hinge){ a, b, c,
						    m->bending[1] * ((w1 + w2) / 2) / h };
				}
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
build_triangles(struct cloth *cl, const unsigned char *sq)
{
	int nu = cl->nu, nv = cl->nv, i, j;
	size_t nt = 0, ne = 0, grid = (size_t)nu * nv;

	/* Sized for the whole grid; a shape uses part of it. */
	cl->tri = malloc(3 * 2 * grid * sizeof *cl->tri);
	cl->edge = malloc(2 * 3 * grid * sizeof *cl->edge);
	if (cl->tri == NULL || cl->edge == NULL)
		return -1;

	for (j = 0; j + 1 < nv; j++)
		for (i = 0; i + 1 < nu; i++) {
			int a = cloth_node(cl, i, j), b = cloth_node(cl, i + 1, j);
			int c = cloth_node(cl, i + 1, j + 1), d = cloth_node(cl, i, j + 1);
			int t[6], k;

			if (!square_at(cl, sq, i, j))
				continue;
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
	/* The yarn segments: those of the springs (a square cloth one node
	 * wide has segments but no triangles). */
	for (j = 0; j < nv; j++)
		for (i = 0; i + 1 < nu; i++)
			if (node_at(cl, i, j) >= 0 && node_at(cl, i + 1, j) >= 0 &&
			    warp_width(cl, sq, i, j) > 0)
				cl->edge[2 * ne] = cloth_node(cl, i, j),
				cl->edge[2 * ne + 1] = cloth_node(cl, i + 1, j), ne++;
	for (j = 0; j + 1 < nv; j++)
		for (i = 0; i < nu; i++)
			if (node_at(cl, i, j) >= 0 && node_at(cl, i, j + 1) >= 0 &&
			    weft_width(cl, sq, i, j) > 0)
				cl->edge[2 * ne] = cloth_node(cl, i, j),
				cl->edge[2 * ne + 1] = cloth_node(cl, i, j + 1), ne++;
	cl->ntri = nt;
	cl->nedges = ne;

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
	unsigned char *sq = NULL;
	int p;

	memset(cl, 0, sizeof *cl);
	cl->shape = sc->shape;
	cl->nu = sc->nu;
	cl->nv = sc->nv;
	cl->h = sc->spacing;
	if (build_shape(cl, &sq) != 0)
		goto oom;
	cl->x0 = malloc((size_t)cl->n * 3 * sizeof *cl->x0 + 1);
	cl->mass = malloc((size_t)cl->n * sizeof *cl->mass + 1);
	if (cl->x0 == NULL || cl->mass == NULL)
		goto oom;
	for (p = 0; p < cl->n; p++) {
		int i, j;

		cloth_grid_ij(cl, p, &i, &j);
		v3_store(cl->x0 + 3 * p, v3_madd(v3_madd(o, wu, i * cl->h), wv, j * cl->h));
		cl->mass[p] = node_mass(cl, sq, sc->mat.weight, i, j);
	}
	if (build_elements(cl, sc, sq) != 0 || build_triangles(cl, sq) != 0)
		goto oom;
	free(sq);
	return 0;
oom:
	free(sq);
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
	free(cl->grid_node);
	free(cl->node_grid);
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

static double
omega_bound(const struct cloth *cl, bool springs, bool corners)
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
	for (e = 0; springs && e < cl->nsprings; e++) {
		row[cl->springs[e].a] += 2 * cl->springs[e].k;
		row[cl->springs[e].b] += 2 * cl->springs[e].k;
	}
	for (e = 0; corners && e < cl->ncorners; e++) {
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

double
cloth_omega_bound(const struct cloth *cl)
{
	return omega_bound(cl, true, true);
}

double
cloth_omega_bound_bend(const struct cloth *cl)
{
	return omega_bound(cl, false, false);
}
