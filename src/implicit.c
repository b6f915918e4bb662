/* implicit.c: the linearly implicit Euler step (see implicit.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "blockmat.h"
#include "implicit.h"
#include "stop.h"
#include "vec3.h"

int
implicit_init(struct implicit *im, const struct forces *fo, const unsigned char *held,
    double tol)
{
	size_t n3 = 3 * (size_t)fo->cl->n;
	double **v[] = { &im->a, &im->b, &im->dv, &im->r, &im->z, &im->p, &im->q };
	size_t i;

	memset(im, 0, sizeof *im);
	im->fo = fo;
	im->held = held;
	im->tol = tol;
	/* CG needs at most n3 iterations in exact arithmetic; a stiff, badly
	 * scaled system may need its fill of them */
	im->max_iter = n3 < 1000 ? (int)n3 : 1000;
	if (jacobian_init(&im->jc, fo) != 0)
		return -1;
	for (i = 0; i < sizeof v / sizeof v[0]; i++)
		if ((*v[i] = malloc(n3 * sizeof(double))) == NULL)
			goto oom;
	if ((im->cdir = malloc(3 * n3 * sizeof *im->cdir)) == NULL ||
	    (im->cmu = malloc(n3 * sizeof *im->cmu)) == NULL ||
	    (im->cjn = malloc(n3 * sizeof *im->cjn)) == NULL ||
	    (im->pre = malloc(3 * n3 * sizeof *im->pre)) == NULL ||
	    (im->ncon = calloc((size_t)fo->cl->n, 1)) == NULL)
		goto oom;
	return 0;
oom:
	implicit_free(im);
	return -1;
}

void
implicit_set_stop(struct implicit *im, const volatile sig_atomic_t *flag)
{
	im->stop = flag;
}

void
implicit_free(struct implicit *im)
{
	jacobian_free(&im->jc);
	free(im->a);
	free(im->b);
	free(im->dv);
	free(im->r);
	free(im->z);
	free(im->p);
	free(im->q);
	free(im->pre);
	free(im->cdir);
	free(im->cmu);
	free(im->cjn);
	free(im->ncon);
	memset(im, 0, sizeof *im);
}

void
implicit_constrain(struct implicit *im, int p, const double n[3], double mu)
{
	vec3 d = v3_load(n);
	double len;
	int k;

	if (im->ncon[p] >= 3)
		return;
	for (k = 0; k < im->ncon[p]; k++) {	/* Gram-Schmidt */
		vec3 e = v3_load(im->cdir + 9 * p + 3 * k);

		d = v3_madd(d, e, -v3_dot(d, e));
	}
	if ((len = v3_len(d)) < 0.1)
		return;		/* (nearly) one already constrained */
	im->cmu[3 * p + im->ncon[p]] = mu;
	v3_store(im->cdir + 9 * p + 3 * im->ncon[p]++, v3_scale(d, 1 / len));
}

/* The filter: a held node's components, and a constrained node's along
 * its constrained directions, take no part in the solve. */
static void
filter(const struct implicit *im, double *w)
{
	int p, k, n = im->fo->cl->n;

	for (p = 0; p < n; p++) {
		if (im->held != NULL && im->held[p]) {
			w[3 * p] = w[3 * p + 1] = w[3 * p + 2] = 0;
			continue;
		}
		for (k = 0; k < im->ncon[p]; k++) {
			vec3 e = v3_load(im->cdir + 9 * p + 3 * k);

			v3_store(w + 3 * p, v3_madd(v3_load(w + 3 * p), e, -v3_dot(v3_load(w + 3 * p), e)));
		}
	}
}

/* Drops the constraints that the forces b pull the node away from (the
 * node leaves the obstacle), and keeps for the others the impulse the
 * obstacle takes, for friction. */
static void
release(struct implicit *im, const double *b)
{
	int p, k, n = im->fo->cl->n;

	for (p = 0; p < n; p++)
		for (k = 0; k < im->ncon[p]; k++) {
			double *e = im->cdir + 9 * p + 3 * k;
			double bn = v3_dot(v3_load(e), v3_load(b + 3 * p));
			int rest = im->ncon[p] - k - 1;

			if (bn > 0) {
				memmove(e, e + 3, (size_t)rest * 3 * sizeof *e);
				memmove(im->cmu + 3 * p + k, im->cmu + 3 * p + k + 1,
				    (size_t)rest * sizeof *im->cmu);
				im->ncon[p]--;
				k--;
				continue;
			}
			/* the impulse the obstacle takes: the step's push into it
			 * (its first-order part; the solve's coupling is left out) */
			im->cjn[3 * p + k] = -bn;
		}
}

/*
 * Coulomb friction on the constrained nodes' sliding (eq. 11-12 in the
 * chapter's terms, at velocity level): each constraint's normal impulse
 * jn allows a tangential change of velocity of at most mu jn / m; a node
 * whose sliding is slower than that sticks. The position follows the new
 * velocity, as backward Euler's x' = x + h v' says.
 */
static void
friction(const struct implicit *im, double h, const double *x, double *y_out)
{
	const struct cloth *cl = im->fo->cl;
	size_t n3 = 3 * (size_t)cl->n;
	int p, k;

	for (p = 0; p < cl->n; p++) {
		vec3 v, vt;
		double cut = 0, slip;

		if (im->ncon[p] == 0 || !(cl->mass[p] > 0))
			continue;
		for (k = 0; k < im->ncon[p]; k++)
			cut += im->cmu[3 * p + k] * im->cjn[3 * p + k];
		if (!(cut > 0))
			continue;
		cut /= cl->mass[p];
		v = vt = v3_load(y_out + n3 + 3 * p);
		for (k = 0; k < im->ncon[p]; k++) {
			vec3 e = v3_load(im->cdir + 9 * p + 3 * k);

			vt = v3_madd(vt, e, -v3_dot(vt, e));
		}
		if ((slip = v3_len(vt)) == 0)
			continue;
		v = v3_madd(v, vt, -(slip <= cut ? 1 : cut / slip));
		v3_store(y_out + n3 + 3 * p, v);
		v3_store(y_out + 3 * p, v3_madd(v3_load(x + 3 * p), v, h));
	}
}

/* out = (M (1 + h damping) + h C + h^2 K) w */
static void
system_mul(const struct implicit *im, double h, const double *w, double *out)
{
	const struct cloth *cl = im->fo->cl;
	double md = 1 + h * im->fo->damping;
	size_t i, n3 = 3 * (size_t)cl->n;

	jacobian_mul(&im->jc, h * h, h, w, out);
	for (i = 0; i < n3; i++)
		out[i] += md * cl->mass[i / 3] * w[i];
	filter(im, out);
}

/* z = P r, the filter applied after: a block can turn r off the
 * constraints */
static void
precondition(const struct implicit *im, const double *r, double *z)
{
	int p, n = im->fo->cl->n;

	for (p = 0; p < n; p++)
		block_apply(im->pre + 9 * p, r + 3 * p, z + 3 * p);
	filter(im, z);
}

static double
dot(const double *a, const double *b, size_t n)
{
	double s = 0;
	size_t i;

	for (i = 0; i < n; i++)
		s += a[i] * b[i];
	return s;
}

/* The stop flag is set: the step is given up (the caller drops it). */
static bool
give_up(struct implicit *im)
{
	if (im->stop == NULL || !*im->stop)
		return false;
	im->stopped = true;
	memset(im->ncon, 0, (size_t)im->fo->cl->n);
	return true;
}

void
implicit_step(struct implicit *im, double t, double h, const double *y, double *y_out)
{
	const struct cloth *cl = im->fo->cl;
	size_t i, n3 = 3 * (size_t)cl->n;
	const double *x = y, *v = y + n3;
	double md = 1 + h * im->fo->damping, rr, rz, stop2;
	int it;

	im->stopped = false;
	/* b = h (f - h K v); on the largest cloths each of these passes takes
	 * tens of milliseconds, so a signal is looked for between them */
	forces_accel(im->fo, t, x, v, im->a);
	if (give_up(im))
		return;
	jacobian_eval(&im->jc, x);
	if (give_up(im))
		return;
	jacobian_mul(&im->jc, 1, 0, v, im->q);
	for (i = 0; i < n3; i++)
		im->b[i] = h * (cl->mass[i / 3] * im->a[i] - h * im->q[i]);
	release(im, im->b);
	filter(im, im->b);

	if (give_up(im))
		return;
	/* block Jacobi: each node's 3 x 3 block of the system, inverted */
	memset(im->pre, 0, 3 * n3 * sizeof *im->pre);
	jacobian_block_diag(&im->jc, h * h, h, im->pre);
	for (i = 0; i < (size_t)cl->n; i++) {
		double *b = im->pre + 9 * i;

		b[0] += md * cl->mass[i];
		b[4] += md * cl->mass[i];
		b[8] += md * cl->mass[i];
		block_invert_spd(b);
	}

	/* preconditioned CG from dv = 0 */
	memset(im->dv, 0, n3 * sizeof *im->dv);
	memcpy(im->r, im->b, n3 * sizeof *im->r);
	rr = dot(im->b, im->b, n3);
	stop2 = im->tol * im->tol * rr;
	precondition(im, im->r, im->z);
	memcpy(im->p, im->z, n3 * sizeof *im->p);
	rz = dot(im->r, im->z, n3);
	for (it = 0; it < im->max_iter && rr > stop2; it++) {
		double pq, alpha, rz_new, beta;

		if (stop_set(im->stop)) {
			im->stopped = true;	/* the caller drops this step */
			break;
		}
		system_mul(im, h, im->p, im->q);
		pq = dot(im->p, im->q, n3);
		if (!(pq > 0))
			break;	/* p is 0 (solved) or the system lost definiteness */
		alpha = rz / pq;
		for (i = 0, rr = 0; i < n3; i++) {
			im->dv[i] += alpha * im->p[i];
			im->r[i] -= alpha * im->q[i];
			rr += im->r[i] * im->r[i];
		}
		precondition(im, im->r, im->z);
		rz_new = dot(im->r, im->z, n3);
		beta = rz_new / rz;
		rz = rz_new;
		for (i = 0; i < n3; i++)
			im->p[i] = im->z[i] + beta * im->p[i];
	}
	im->solves++;
	im->iters += it;
	im->last_iters = it;
	if (rr > stop2)		/* out of iterations, or p went flat */
		im->unconverged++;
	if (give_up(im))	/* a product cut short may have ended the loop */
		return;

	for (i = 0; i < n3; i++) {
		y_out[n3 + i] = v[i] + im->dv[i];
		y_out[i] = x[i] + h * y_out[n3 + i];
	}
	friction(im, h, x, y_out);
	memset(im->ncon, 0, (size_t)cl->n);
}
