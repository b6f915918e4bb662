/* integrate.c: explicit one-step methods on flat arrays (implicit Euler is
 * implicit.c's). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "integrate.h"

static const struct {
	const char *name;
	int order;
	double imag_limit;
	int stages;
} methods[INTEG_COUNT] = {
	[INTEG_RK4] = { "rk4", 4, 2.8284271247461903, 4 },
	[INTEG_EULER] = { "euler", 1, 0, 1 },
	[INTEG_SYMPLECTIC_EULER] = { "symplectic-euler", 1, 2, 1 },
	[INTEG_RK2] = { "rk2", 2, 0, 2 },
	/* Its 5th-order solution is neutrally stable only for h*omega < 1. */
	[INTEG_DOPRI5] = { "dopri5", 5, 1.0, 7 },
	[INTEG_IMPLICIT_EULER] = { "implicit-euler", 1, INFINITY, 0 },
	[INTEG_FAST] = { "fast", 1, INFINITY, 0 },
	[INTEG_BDF2] = { "bdf2", 2, INFINITY, 0 },
};

bool
integrator_is_implicit(enum integrator_kind kind)
{
	return kind == INTEG_IMPLICIT_EULER || kind == INTEG_FAST || kind == INTEG_BDF2;
}

bool
integrator_finds_contacts(enum integrator_kind kind)
{
	return kind == INTEG_FAST || kind == INTEG_BDF2;
}

const char *
integrator_name(enum integrator_kind kind)
{
	return (unsigned)kind < INTEG_COUNT ? methods[kind].name : "?";
}

int
integrator_from_name(const char *name, enum integrator_kind *kind)
{
	int k;

	for (k = 0; k < INTEG_COUNT; k++)
		if (strcmp(methods[k].name, name) == 0) {
			*kind = (enum integrator_kind)k;
			return 0;
		}
	return -1;
}

void
integrator_names(char *buf, size_t len)
{
	size_t at = 0;
	int k, n;

	if (len == 0)
		return;
	buf[0] = '\0';
	for (k = 0; k < INTEG_COUNT && at < len; k++) {
		n = snprintf(buf + at, len - at, "%s%s", k == 0 ? "" : k + 1 == INTEG_COUNT ?
		    " or " : ", ", methods[k].name);
		if (n < 0)
			return;
		at += (size_t)n;
	}
}

int
integrator_order(enum integrator_kind kind)
{
	return methods[kind].order;
}

double
integrator_default_tolerance(enum integrator_kind kind)
{
	return kind == INTEG_BDF2 ? 1e-2 : integrator_is_implicit(kind) ? 1e-3 : 1e-6;
}

double
integrator_imag_limit(enum integrator_kind kind)
{
	return methods[kind].imag_limit;
}

int
integrator_init(struct integrator *in, enum integrator_kind kind, size_t n, double tol)
{
	int s;

	memset(in, 0, sizeof *in);
	in->kind = kind;
	in->n = n;
	in->tol = tol;
	for (s = 0; s < methods[kind].stages; s++)
		if ((in->k[s] = malloc(n * sizeof(double))) == NULL)
			goto oom;
	if ((in->tmp = malloc(n * sizeof(double))) == NULL)
		goto oom;
	return 0;
oom:
	integrator_free(in);
	return -1;
}

void
integrator_free(struct integrator *in)
{
	int s;

	for (s = 0; s < 7; s++)
		free(in->k[s]);
	free(in->tmp);
	memset(in, 0, sizeof *in);
}

/* out = y + h * sum_s a[s] k[s] over ns stages. The stage sum is formed
 * first so that each step rounds onto the (large) state only once. */
static void
combine(size_t n, double *out, const double *y, double h, double *const *k, const double *a,
    int ns)
{
	size_t i;
	int s;

	for (i = 0; i < n; i++) {
		double sum = 0;

		for (s = 0; s < ns; s++)
			sum += a[s] * k[s][i];
		out[i] = y[i] + h * sum;
	}
}

#define EVAL(in, f, ctx, t, y, k) do { (f)((ctx), (t), (y), (k)); (in)->nfev++; } while (0)

static void
step_rk4(struct integrator *in, rhs_fn f, void *ctx, double t, const double *y, double *out,
    double h)
{
	static const double a2[] = { 0.5 }, a3[] = { 0, 0.5 }, a4[] = { 0, 0, 1 };
	static const double b[] = { 1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6 };
	size_t n = in->n;

	EVAL(in, f, ctx, t, y, in->k[0]);
	combine(n, in->tmp, y, h, in->k, a2, 1);
	EVAL(in, f, ctx, t + h / 2, in->tmp, in->k[1]);
	combine(n, in->tmp, y, h, in->k, a3, 2);
	EVAL(in, f, ctx, t + h / 2, in->tmp, in->k[2]);
	combine(n, in->tmp, y, h, in->k, a4, 3);
	EVAL(in, f, ctx, t + h, in->tmp, in->k[3]);
	combine(n, out, y, h, in->k, b, 4);
}

static void
step_rk2(struct integrator *in, rhs_fn f, void *ctx, double t, const double *y, double *out,
    double h)
{
	static const double a2[] = { 0.5 }, b[] = { 0, 1 };

	EVAL(in, f, ctx, t, y, in->k[0]);
	combine(in->n, in->tmp, y, h, in->k, a2, 1);
	EVAL(in, f, ctx, t + h / 2, in->tmp, in->k[1]);
	combine(in->n, out, y, h, in->k, b, 2);
}

/* v += h a(x, v); x += h v_new. Held nodes are put back on their
 * prescribed motion by the caller after the step. */
static void
step_symplectic(struct integrator *in, rhs_fn f, void *ctx, double t, const double *y,
    double *out, double h)
{
	size_t half = in->n / 2, i;
	const double *k = in->k[0];

	EVAL(in, f, ctx, t, y, in->k[0]);
	for (i = 0; i < half; i++) {
		double vnew = y[half + i] + h * k[half + i];

		out[half + i] = vnew;
		out[i] = y[i] + h * vnew;
	}
}

static int
step_dopri5(struct integrator *in, rhs_fn f, void *ctx, double t, const double *y, double *out,
    double *dt, double *dt_next)
{
	static const double c[] = { 0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1, 1 };
	static const double a[7][6] = {
		{ 0 },
		{ 1.0 / 5 },
		{ 3.0 / 40, 9.0 / 40 },
		{ 44.0 / 45, -56.0 / 15, 32.0 / 9 },
		{ 19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729 },
		{ 9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656 },
		{ 35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84 },
	};
	/* 5th-order weights minus the embedded 4th-order ones. */
	static const double e[] = { 71.0 / 57600, 0, -71.0 / 16695, 71.0 / 1920,
		-17253.0 / 339200, 22.0 / 525, -1.0 / 40 };
	size_t n = in->n, i;
	double h = *dt;
	int s;

	EVAL(in, f, ctx, t, y, in->k[0]);
	for (;;) {
		double sum = 0, err, fac;

		for (s = 1; s < 7; s++) {
			combine(n, s == 6 ? out : in->tmp, y, h, in->k, a[s], s);
			EVAL(in, f, ctx, t + c[s] * h, s == 6 ? out : in->tmp, in->k[s]);
		}
		for (i = 0; i < n; i++) {
			double est = 0, sc = in->tol * (1 + fmax(fabs(y[i]), fabs(out[i])));

			for (s = 0; s < 7; s++)
				est += e[s] * in->k[s][i];
			est *= h / sc;
			sum += est * est;
		}
		err = sqrt(sum / (double)n);
		fac = err > 0 ? 0.9 * pow(err, -0.2) : 5;
		fac = fmin(5, fmax(0.2, fac));
		if (err <= 1) {
			*dt = h;
			*dt_next = h * fac;
			return 0;
		}
		in->rejected++;
		h *= fmin(1, fac);
		if (h <= 1e-14 * fmax(fabs(t), 1e-6))
			return -1;
	}
}

int
integrator_step(struct integrator *in, rhs_fn f, void *ctx, double t, const double *y,
    double *y_out, double *dt, double *dt_next)
{
	switch (in->kind) {
	case INTEG_RK4:
		step_rk4(in, f, ctx, t, y, y_out, *dt);
		break;
	case INTEG_EULER: {
		static const double b[] = { 1 };

		EVAL(in, f, ctx, t, y, in->k[0]);
		combine(in->n, y_out, y, *dt, in->k, b, 1);
		break;
	}
	case INTEG_SYMPLECTIC_EULER:
		step_symplectic(in, f, ctx, t, y, y_out, *dt);
		break;
	case INTEG_RK2:
		step_rk2(in, f, ctx, t, y, y_out, *dt);
		break;
	case INTEG_DOPRI5:
		return step_dopri5(in, f, ctx, t, y, y_out, dt, dt_next);
	case INTEG_IMPLICIT_EULER:
	case INTEG_FAST:
	case INTEG_BDF2:
	case INTEG_COUNT:
		return -1;
	}
	*dt_next = *dt;
	return 0;
}
