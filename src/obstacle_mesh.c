/* obstacle_mesh.c: obstacles as triangles. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "obstacle_mesh.h"

static int
alloc(struct mesh *m, int nverts, size_t ntri)
{
	memset(m, 0, sizeof *m);
	m->x = malloc(3 * (size_t)nverts * sizeof *m->x);
	m->tri = malloc(3 * ntri * sizeof *m->tri);
	if (m->x == NULL || m->tri == NULL) {
		free(m->x);
		free(m->tri);
		memset(m, 0, sizeof *m);
		return -1;
	}
	m->nverts = nverts;
	m->ntri = ntri;
	return 0;
}

static void
set_vertex(struct mesh *m, int k, vec3 p)
{
	m->x[3 * k] = p.x;
	m->x[3 * k + 1] = p.y;
	m->x[3 * k + 2] = p.z;
}

static void
set_tri(struct mesh *m, size_t t, int a, int b, int c)
{
	m->tri[3 * t] = a;
	m->tri[3 * t + 1] = b;
	m->tri[3 * t + 2] = c;
}

/* A quad a b c d, counter-clockwise from outside, as two triangles. */
static void
set_quad(struct mesh *m, size_t t, int a, int b, int c, int d)
{
	set_tri(m, t, a, b, c);
	set_tri(m, t + 1, a, c, d);
}

static int
box(const struct obstacle *o, struct mesh *m)
{
	/* corner k has hi.x if k & 4, hi.y if k & 2, hi.z if k & 1 */
	static const int face[6][4] = {
		{ 0, 1, 3, 2 }, { 4, 6, 7, 5 }, { 0, 4, 5, 1 },
		{ 2, 3, 7, 6 }, { 0, 2, 6, 4 }, { 1, 5, 7, 3 },
	};
	int k;

	if (alloc(m, 8, 12) != 0)
		return -1;
	for (k = 0; k < 8; k++)
		set_vertex(m, k, v3(k & 4 ? o->hi.x : o->lo.x, k & 2 ? o->hi.y : o->lo.y,
		    k & 1 ? o->hi.z : o->lo.z));
	for (k = 0; k < 6; k++)
		set_quad(m, 2 * (size_t)k, face[k][0], face[k][1], face[k][2], face[k][3]);
	return 0;
}

static int
sphere(const struct obstacle *o, struct mesh *m)
{
	const int L = OBSTACLE_MESH_SLICES, S = OBSTACLE_MESH_STACKS;
	int i, j, top = 0, bottom = 1 + (S - 1) * L;
	size_t t = 0;

	/* the poles, and S - 1 rings of L between them */
	if (alloc(m, 2 + (S - 1) * L, 2 * (size_t)L * (size_t)(S - 1)) != 0)
		return -1;
	set_vertex(m, top, v3_add(o->centre, v3(0, o->radius, 0)));
	set_vertex(m, bottom, v3_add(o->centre, v3(0, -o->radius, 0)));
	for (j = 1; j < S; j++)
		for (i = 0; i < L; i++) {
			double ph = V3_PI * j / S, th = 2 * V3_PI * i / L;

			set_vertex(m, 1 + (j - 1) * L + i, v3_add(o->centre, v3(o->radius * sin(ph) *
			    cos(th), o->radius * cos(ph), o->radius * sin(ph) * sin(th))));
		}
	for (i = 0; i < L; i++) {
		int i1 = (i + 1) % L;

		set_tri(m, t++, top, 1 + i1, 1 + i);
		for (j = 1; j < S - 1; j++)
			set_quad(m, (t += 2) - 2, 1 + (j - 1) * L + i, 1 + (j - 1) * L + i1,
			    1 + j * L + i1, 1 + j * L + i);
		set_tri(m, t++, bottom, 1 + (S - 2) * L + i, 1 + (S - 2) * L + i1);
	}
	return 0;
}

/* A vertical cylinder whose top face is centred on o->centre. */
static int
disc(const struct obstacle *o, struct mesh *m)
{
	const int L = OBSTACLE_MESH_SLICES;
	int i, top = 0, bottom = 1;
	size_t t = 0;

	/* the faces' centres, then the top ring (2 + i), the bottom (2 + L + i) */
	if (alloc(m, 2 + 2 * L, 4 * (size_t)L) != 0)
		return -1;
	set_vertex(m, top, o->centre);
	set_vertex(m, bottom, v3_add(o->centre, v3(0, -o->height, 0)));
	for (i = 0; i < L; i++) {
		double a = 2 * V3_PI * i / L;
		vec3 d = v3(o->radius * cos(a), 0, o->radius * sin(a));

		set_vertex(m, 2 + i, v3_add(o->centre, d));
		set_vertex(m, 2 + L + i, v3_add(v3_add(o->centre, v3(0, -o->height, 0)), d));
	}
	for (i = 0; i < L; i++) {
		int i1 = (i + 1) % L;

		set_tri(m, t++, top, 2 + i1, 2 + i);
		set_tri(m, t++, bottom, 2 + L + i, 2 + L + i1);
		set_quad(m, (t += 2) - 2, 2 + i, 2 + i1, 2 + L + i1, 2 + L + i);
	}
	return 0;
}

static int
plane(const struct obstacle *o, vec3 near, double half, struct mesh *m)
{
	vec3 n = o->normal, a = fabs(n.y) < 0.9 ? v3(0, 1, 0) : v3(1, 0, 0), u, w, c;

	if (alloc(m, 4, 2) != 0)
		return -1;
	u = v3_cross(n, a);
	u = v3_scale(u, 1 / v3_len(u));
	w = v3_cross(n, u);	/* u, w, n right-handed: u then w turns about n */
	c = v3_madd(near, n, -v3_dot(v3_sub(near, o->point), n));
	set_vertex(m, 0, v3_madd(v3_madd(c, u, -half), w, -half));
	set_vertex(m, 1, v3_madd(v3_madd(c, u, half), w, -half));
	set_vertex(m, 2, v3_madd(v3_madd(c, u, half), w, half));
	set_vertex(m, 3, v3_madd(v3_madd(c, u, -half), w, half));
	set_quad(m, 0, 0, 1, 2, 3);
	return 0;
}

static int
copy(const struct mesh *src, struct mesh *m)
{
	if (alloc(m, src->nverts, src->ntri) != 0)
		return -1;
	memcpy(m->x, src->x, 3 * (size_t)src->nverts * sizeof *m->x);
	memcpy(m->tri, src->tri, 3 * src->ntri * sizeof *m->tri);
	return 0;
}

int
obstacle_mesh(const struct obstacle *o, vec3 near, double half, struct mesh *out)
{
	switch (o->kind) {
	case OBSTACLE_PLANE:
		return plane(o, near, half, out);
	case OBSTACLE_BOX:
		return box(o, out);
	case OBSTACLE_SPHERE:
		return sphere(o, out);
	case OBSTACLE_DISC:
		return disc(o, out);
	case OBSTACLE_MESH:
		return copy(&o->mesh, out);
	}
	return -1;
}
