/* jacobian.c: forces.c's elements linearised (see jacobian.h). Each
 * element's formulas follow its force in forces.c. */
#include <stdlib.h>
#include <string.h>

#include "jacobian.h"
#include "vec3.h"

int
jacobian_init(struct jacobian *jc, const struct forces *fo)
{
	const struct cloth *cl = fo->cl;

	memset(jc, 0, sizeof *jc);
	jc->fo = fo;
	if ((jc->spring = malloc((cl->nsprings + 1) * 5 * sizeof *jc->spring)) == NULL ||
	    (jc->corner = malloc((cl->ncorners + 1) * 6 * sizeof *jc->corner)) == NULL ||
	    (jc->hinge = malloc((cl->nhinges + 1) * 10 * sizeof *jc->hinge)) == NULL) {
		jacobian_free(jc);
		return -1;
	}
	return 0;
}

void
jacobian_free(struct jacobian *jc)
{
	free(jc->spring);
	free(jc->corner);
	free(jc->hinge);
	memset(jc, 0, sizeof *jc);
}

void
jacobian_eval(struct jacobian *jc, const double *x)
{
	const struct cloth *cl = jc->fo->cl;
	double rest2 = cl->h * cl->h;
	size_t s;

	for (s = 0; s < cl->nsprings; s++) {
		if (forces_poll(jc->fo, s))
			return;
		const struct spring *sp = &cl->springs[s];
		vec3 d = v3_sub(v3_load(x + 3 * sp->b), v3_load(x + 3 * sp->a));
		double len = v3_len(d), *e = jc->spring + 5 * s;

		if (len == 0) {		/* no direction: forces.c gives no force either */
			memset(e, 0, 5 * sizeof *e);
			continue;
		}
		v3_store(e, v3_scale(d, 1 / len));
		e[3] = sp->k;
		e[4] = len > sp->rest ? sp->k * (1 - sp->rest / len) : 0;
	}
	for (s = 0; s < cl->ncorners; s++) {
		if (forces_poll(jc->fo, s))
			return;
		const struct corner *co = &cl->corners[s];
		vec3 xc = v3_load(x + 3 * co->c);
		vec3 e1 = v3_sub(v3_load(x + 3 * co->a), xc), e2 = v3_sub(v3_load(x + 3 * co->b), xc);
		double l1s = v3_dot(e1, e1), l2s = v3_dot(e2, e2), q, inv12, c, *e = jc->corner + 6 * s;

		if (l1s == 0 || l2s == 0) {
			memset(e, 0, 6 * sizeof *e);
			continue;
		}
		q = 1 / (l1s * l2s);
		inv12 = sqrt(q);
		c = v3_dot(e1, e2) * inv12;
		v3_store(e, v3_madd(v3_scale(e2, inv12), e1, -c * l2s * q));
		v3_store(e + 3, v3_madd(v3_scale(e1, inv12), e2, -c * l1s * q));
	}
	for (s = 0; s < cl->nhinges; s++) {
		if (forces_poll(jc->fo, s))
			return;
		const struct hinge *hg = &cl->hinges[s];
		vec3 xb = v3_load(x + 3 * hg->b);
		vec3 e1 = v3_sub(xb, v3_load(x + 3 * hg->a)), e2 = v3_sub(v3_load(x + 3 * hg->c), xb);
		double d = rest2 + v3_dot(e1, e2), *e = jc->hinge + 10 * s;

		if (!(d > 1e-9 * rest2)) {	/* as forces.c: no gradient */
			memset(e, 0, 10 * sizeof *e);
			continue;
		}
		v3_store(e, e1);
		v3_store(e + 3, e2);
		v3_store(e + 6, v3_scale(v3_cross(e1, e2), 2 / d));
		e[9] = 1 / d;
	}
}

/* The change of a hinge's kb = 2 e1 x e2 / D for changes de1, de2 of its
 * edges (D = L^2 + e1.e2). */
static vec3
hinge_dkb(const double *e, vec3 de1, vec3 de2)
{
	vec3 e1 = v3_load(e), e2 = v3_load(e + 3), kb = v3_load(e + 6);
	vec3 w = v3_scale(v3_add(v3_cross(de1, e2), v3_cross(e1, de2)), 2);

	return v3_scale(v3_madd(w, kb, -(v3_dot(e2, de1) + v3_dot(e1, de2))), e[9]);
}

void
jacobian_mul(const struct jacobian *jc, double ck, double cc, const double *p, double *out)
{
	const struct cloth *cl = jc->fo->cl;
	double beta = cc * jc->fo->spring_damping;
	size_t s;

	memset(out, 0, (size_t)cl->n * 3 * sizeof *out);
	for (s = 0; s < cl->nsprings; s++) {
		if (forces_poll(jc->fo, s))
			return;
		const struct spring *sp = &cl->springs[s];
		const double *e = jc->spring + 5 * s;
		vec3 u = v3_load(e), dp = v3_sub(v3_load(p + 3 * sp->a), v3_load(p + 3 * sp->b));
		double along = v3_dot(u, dp);
		/* k u u^T along the spring (with its dashpot beta*k), the
		 * clamped k(1 - L/l) across it */
		vec3 f = v3_madd(v3_scale(dp, ck * e[4]), u, along * ((ck + beta) * e[3] - ck * e[4]));

		v3_addto(out + 3 * sp->a, f);
		v3_addto(out + 3 * sp->b, v3_neg(f));
	}
	for (s = 0; s < cl->ncorners; s++) {
		if (forces_poll(jc->fo, s))
			return;
		const struct corner *co = &cl->corners[s];
		const double *e = jc->corner + 6 * s;
		vec3 ga = v3_load(e), gb = v3_load(e + 3);
		double dc = v3_dot(ga, v3_sub(v3_load(p + 3 * co->a), v3_load(p + 3 * co->c))) +
		    v3_dot(gb, v3_sub(v3_load(p + 3 * co->b), v3_load(p + 3 * co->c)));
		double w = ck * co->k * dc;

		v3_addto(out + 3 * co->a, v3_scale(ga, w));
		v3_addto(out + 3 * co->b, v3_scale(gb, w));
		v3_addto(out + 3 * co->c, v3_scale(v3_add(ga, gb), -w));
	}
	for (s = 0; s < cl->nhinges; s++) {
		if (forces_poll(jc->fo, s))
			return;
		const struct hinge *hg = &cl->hinges[s];
		const double *e = jc->hinge + 10 * s;
		vec3 pb = v3_load(p + 3 * hg->b);
		vec3 w = hinge_dkb(e, v3_sub(pb, v3_load(p + 3 * hg->a)),
		    v3_sub(v3_load(p + 3 * hg->c), pb));
		vec3 e1 = v3_load(e), e2 = v3_load(e + 3), kb = v3_load(e + 6);
		double kw = v3_dot(kb, w), s2 = 2 * e[9];
		/* J^T w: the gradients of kb.w over e1 and over e2 */
		vec3 g1 = v3_madd(v3_scale(v3_cross(e2, w), s2), e2, -kw * e[9]);
		vec3 g2 = v3_madd(v3_scale(v3_cross(w, e1), s2), e1, -kw * e[9]);
		double k = ck * hg->k;

		v3_addto(out + 3 * hg->a, v3_scale(g1, -k));
		v3_addto(out + 3 * hg->b, v3_scale(v3_sub(g1, g2), k));
		v3_addto(out + 3 * hg->c, v3_scale(g2, k));
	}
}

/* b += s * u u^T */
static void
add_outer(double *b, vec3 u, double s)
{
	double a[3] = { u.x, u.y, u.z };
	int i, j;

	for (i = 0; i < 3; i++)
		for (j = 0; j < 3; j++)
			b[3 * i + j] += s * a[i] * a[j];
}

void
jacobian_block_diag(const struct jacobian *jc, double ck, double cc, double *blocks)
{
	const struct cloth *cl = jc->fo->cl;
	double beta = cc * jc->fo->spring_damping;
	size_t s;
	int i, end;

	for (s = 0; s < cl->nsprings; s++) {
		if (forces_poll(jc->fo, s))
			return;
		const struct spring *sp = &cl->springs[s];
		const double *e = jc->spring + 5 * s;
		int node[2] = { sp->a, sp->b };

		for (end = 0; end < 2; end++) {
			double *b = blocks + 9 * node[end];

			for (i = 0; i < 3; i++)
				b[4 * i] += ck * e[4];
			add_outer(b, v3_load(e), (ck + beta) * e[3] - ck * e[4]);
		}
	}
	for (s = 0; s < cl->ncorners; s++) {
		if (forces_poll(jc->fo, s))
			return;
		const struct corner *co = &cl->corners[s];
		const double *e = jc->corner + 6 * s;
		double k = ck * co->k;

		add_outer(blocks + 9 * co->a, v3_load(e), k);
		add_outer(blocks + 9 * co->b, v3_load(e + 3), k);
		add_outer(blocks + 9 * co->c, v3_add(v3_load(e), v3_load(e + 3)), k);
	}
	for (s = 0; s < cl->nhinges; s++) {
		if (forces_poll(jc->fo, s))
			return;
		const struct hinge *hg = &cl->hinges[s];
		const double *e = jc->hinge + 10 * s;
		double k = ck * hg->k;
		vec3 z = v3(0, 0, 0), w[3][3];	/* w[node][axis]: J's columns */
		int node[3] = { hg->a, hg->b, hg->c }, m, j;

		for (i = 0; i < 3; i++) {
			vec3 u = v3(i == 0, i == 1, i == 2);

			w[0][i] = hinge_dkb(e, v3_neg(u), z);
			w[1][i] = hinge_dkb(e, u, v3_neg(u));
			w[2][i] = hinge_dkb(e, z, u);
		}
		for (m = 0; m < 3; m++)
			for (i = 0; i < 3; i++)
				for (j = 0; j < 3; j++)
					blocks[9 * node[m] + 3 * i + j] += k * v3_dot(w[m][i], w[m][j]);
	}
}

/* b1 += a c^T, and b2 += c a^T unless NULL (3 x 3 row-major blocks),
 * written out: the assembly's inner loop, which at -O2 was mostly loop. */
static inline void
add_outer_block(double *b1, double *b2, const double *a, const double *c)
{
	double v0 = a[0] * c[0], v1 = a[0] * c[1], v2 = a[0] * c[2];
	double v3 = a[1] * c[0], v4 = a[1] * c[1], v5 = a[1] * c[2];
	double v6 = a[2] * c[0], v7 = a[2] * c[1], v8 = a[2] * c[2];

	b1[0] += v0; b1[1] += v1; b1[2] += v2;
	b1[3] += v3; b1[4] += v4; b1[5] += v5;
	b1[6] += v6; b1[7] += v7; b1[8] += v8;
	if (b2 == NULL)
		return;
	b2[0] += v0; b2[1] += v3; b2[2] += v6;
	b2[3] += v1; b2[4] += v4; b2[5] += v7;
	b2[6] += v2; b2[7] += v5; b2[8] += v8;
}

/* A hinge's d kb / dx as 3 rows of 9 (nodes a, b, c, 3 columns each),
 * from hinge_dkb's formula written out: node a's columns are
 * (2 [e2]x + kb e2^T) / D, node c's (2 [e1]x - kb e1^T) / D ([v]x the
 * matrix of v x), node b's minus their sum. */
static void
hinge_jacobian(const double *e, double id, double J[3][9])
{
	const double *e1 = e, *e2 = e + 3, *kb = e + 6;
	int r, c;

	for (r = 0; r < 3; r++)
		for (c = 0; c < 3; c++) {
			J[r][c] = kb[r] * e2[c] * id;
			J[r][6 + c] = -kb[r] * e1[c] * id;
		}
	/* [v]x = ((0, -v2, v1), (v2, 0, -v0), (-v1, v0, 0)) */
	J[0][1] -= 2 * e2[2] * id; J[0][2] += 2 * e2[1] * id;
	J[1][0] += 2 * e2[2] * id; J[1][2] -= 2 * e2[0] * id;
	J[2][0] -= 2 * e2[1] * id; J[2][1] += 2 * e2[0] * id;
	J[0][7] -= 2 * e1[2] * id; J[0][8] += 2 * e1[1] * id;
	J[1][6] += 2 * e1[2] * id; J[1][8] -= 2 * e1[0] * id;
	J[2][6] -= 2 * e1[1] * id; J[2][7] += 2 * e1[0] * id;
	for (r = 0; r < 3; r++)
		for (c = 0; c < 3; c++)
			J[r][3 + c] = -J[r][c] - J[r][6 + c];
}

/* Block k of A += s * the 3 x 3 matrix m (row-major). */
static void
add_block(struct blockmat *A, int k, const double *m, double s)
{
	double *b = A->val + 9 * (size_t)k;
	int i;

	for (i = 0; i < 9; i++)
		b[i] += s * m[i];
}

void
jacobian_assemble(const struct jacobian *jc, double ck, double cc, struct blockmat *A)
{
	const struct cloth *cl = jc->fo->cl;
	double beta = cc * jc->fo->spring_damping;
	size_t s;
	int i, m, l;

	for (s = 0; s < cl->nsprings; s++) {
		const struct spring *sp = &cl->springs[s];
		const double *e = jc->spring + 5 * s;
		double k[9] = { 0 };

		/* as jacobian_mul: the clamped transverse part everywhere, the
		 * rest of k (and the dashpot) along u */
		for (i = 0; i < 3; i++)
			k[4 * i] = ck * e[4];
		add_outer(k, v3_load(e), (ck + beta) * e[3] - ck * e[4]);
		add_block(A, A->diag[sp->a], k, 1);
		add_block(A, A->diag[sp->b], k, 1);
		add_block(A, A->spring_slot[2 * s], k, -1);
		add_block(A, A->spring_slot[2 * s + 1], k, -1);
	}
	for (s = 0; s < cl->ncorners; s++) {
		const double *e = jc->corner + 6 * s;
		double g[3][3] = { { -e[0] - e[3], -e[1] - e[4], -e[2] - e[5] }, { e[0], e[1], e[2] },
		    { e[3], e[4], e[5] } }, kc = ck * cl->corners[s].k;
		const int *slot = A->corner_slot + 9 * s;

		/* k g_m g_l^T: the upper blocks, mirrored */
		for (m = 0; m < 3; m++) {
			double a[3] = { kc * g[m][0], kc * g[m][1], kc * g[m][2] };

			add_outer_block(A->val + 9 * (size_t)slot[4 * m], NULL, a, g[m]);
			for (l = m + 1; l < 3; l++)
				add_outer_block(A->val + 9 * (size_t)slot[3 * m + l],
				    A->val + 9 * (size_t)slot[3 * l + m], a, g[l]);
		}
	}
	for (s = 0; s < cl->nhinges; s++) {
		const double *e = jc->hinge + 10 * s;
		const int *slot = A->hinge_slot + 9 * s;
		double kh = ck * cl->hinges[s].k, J[3][9], id = e[9];

		hinge_jacobian(e, id, J);
		/* k J_m^T J_l = k sum over J's rows r of J_rm J_rl^T, the upper
		 * blocks mirrored */
		for (m = 0; m < 3; m++)
			for (l = m; l < 3; l++) {
				double *b1 = A->val + 9 * (size_t)slot[3 * m + l];
				double *b2 = l == m ? NULL : A->val + 9 * (size_t)slot[3 * l + m];
				int r;

				for (r = 0; r < 3; r++) {
					double a[3] = { kh * J[r][3 * m], kh * J[r][3 * m + 1], kh * J[r][3 * m + 2] };

					add_outer_block(b1, b2, a, J[r] + 3 * l);
				}
			}
	}
}
