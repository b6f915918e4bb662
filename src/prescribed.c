/* prescribed.c: pins and moves. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prescribed.h"
#include "vec3.h"

int
prescribed_build(struct prescribed *pr, const struct scene *sc, const struct cloth *cl,
    struct drape_err *err)
{
	int *owner = NULL, m, total = 0;
	size_t b;

	memset(pr, 0, sizeof *pr);
	pr->motions = sc->motions;
	pr->nmotions = (int)sc->nmotions;
	pr->held = calloc((size_t)cl->n, 1);
	pr->start = malloc(((size_t)pr->nmotions + 1) * sizeof *pr->start);
	owner = malloc((size_t)cl->n * sizeof *owner);
	if (pr->held == NULL || pr->start == NULL || owner == NULL)
		goto oom;
	/* Count first (blocks may overlap within one motion), then fill. */
	for (m = 0; m < pr->nmotions; m++) {
		const struct node_set *s = &sc->motions[m].nodes;

		pr->start[m] = total;
		if (!node_set_fits(s, cl->nu, cl->nv)) {
			err_set(err, "%s:%d: nodes: the set does not fit the %d x %d grid",
			    sc->path, sc->motions[m].line, cl->nu, cl->nv);
			free(owner);
			prescribed_free(pr);
			return -1;
		}
		for (b = 0; b < s->n; b++)
			for (int j = s->b[b].j0; j <= s->b[b].j1; j++)
				for (int i = s->b[b].i0; i <= s->b[b].i1; i++) {
					int p = cloth_node(cl, i, j);

					if (p < 0)
						continue;	/* off the cloth's shape */
					if (pr->held[p] && owner[p] != m) {
						err_set(err, "%s:%d: node %d %d already has its motion "
						    "given by the section at line %d", sc->path,
						    sc->motions[m].line, i, j, sc->motions[owner[p]].line);
						free(owner);
						prescribed_free(pr);
						return -1;
					}
					if (!pr->held[p])
						total++;
					pr->held[p] = 1;
					owner[p] = m;
				}
		if (total == pr->start[m]) {
			err_set(err, "%s:%d: nodes: the set has no node on the %s cloth; expected "
			    "grid positions inside its shape", sc->path, sc->motions[m].line,
			    cloth_shape_name[cl->shape]);
			free(owner);
			prescribed_free(pr);
			return -1;
		}
	}
	pr->start[pr->nmotions] = total;
	pr->nnodes = total;
	if ((pr->node = malloc((size_t)total * sizeof *pr->node + 1)) == NULL)
		goto oom;
	/* Nodes of each motion in ascending order: the order never depends on
	 * how the scene listed them. */
	{
		int *fill = malloc(((size_t)pr->nmotions + 1) * sizeof *fill), p;

		if (fill == NULL)
			goto oom;
		memcpy(fill, pr->start, ((size_t)pr->nmotions + 1) * sizeof *fill);
		for (p = 0; p < cl->n; p++)
			if (pr->held[p])
				pr->node[fill[owner[p]]++] = p;
		free(fill);
	}
	free(owner);
	return 0;
oom:
	free(owner);
	prescribed_free(pr);
	err_set(err, "%s: out of memory", sc->path);
	return -1;
}

void
prescribed_free(struct prescribed *pr)
{
	free(pr->start);
	free(pr->node);
	free(pr->held);
	memset(pr, 0, sizeof *pr);
}

void
prescribed_motion(const struct scene_motion *m, double t, double d[3], double v[3])
{
	int k;

	for (k = 0; k < 3; k++)
		d[k] = v[k] = 0;
	switch (m->kind) {
	case MOTION_PIN:
		break;
	case MOTION_VELOCITY: {
		double active = fmin(fmax(t, m->start), m->stop) - m->start;

		for (k = 0; k < 3; k++) {
			d[k] = m->velocity[k] * active;
			v[k] = t >= m->start && t < m->stop ? m->velocity[k] : 0;
		}
		break;
	}
	case MOTION_PATH: {
		double t0 = 0, p0[3] = { 0, 0, 0 };
		size_t s;

		for (s = 0; s < m->npath; s++) {
			const double *p = m->path + 4 * s;

			if (t < p[0]) {
				double f = (t - t0) / (p[0] - t0);

				for (k = 0; k < 3; k++) {
					v[k] = (p[k + 1] - p0[k]) / (p[0] - t0);
					d[k] = p0[k] + f * (p[k + 1] - p0[k]);
				}
				return;
			}
			t0 = p[0];
			memcpy(p0, p + 1, sizeof p0);
		}
		memcpy(d, p0, sizeof p0);	/* held at the last point */
		break;
	}
	}
}

void
prescribed_apply(const struct prescribed *pr, const struct cloth *cl, double t, double *x,
    double *v)
{
	int m, k;

	for (m = 0; m < pr->nmotions; m++) {
		double d[3], vel[3];

		prescribed_motion(&pr->motions[m], t, d, vel);
		for (k = pr->start[m]; k < pr->start[m + 1]; k++) {
			int p = pr->node[k];

			if (x != NULL)
				v3_store(x + 3 * p, v3_add(v3_load(cl->x0 + 3 * p), v3_load(d)));
			if (v != NULL)
				v3_store(v + 3 * p, v3_load(vel));
		}
	}
}

double
prescribed_max_speed(const struct prescribed *pr)
{
	double best = 0;
	int m;

	for (m = 0; m < pr->nmotions; m++) {
		const struct scene_motion *mo = &pr->motions[m];
		double t0 = 0, p0[3] = { 0, 0, 0 };
		size_t s;

		if (mo->kind == MOTION_VELOCITY)
			best = fmax(best, v3_len(v3_load(mo->velocity)));
		for (s = 0; mo->kind == MOTION_PATH && s < mo->npath; s++) {
			const double *p = mo->path + 4 * s;

			best = fmax(best, v3_len(v3_sub(v3_load(p + 1), v3_load(p0))) / (p[0] - t0));
			t0 = p[0];
			memcpy(p0, p + 1, sizeof p0);
		}
	}
	return best;
}
