/* forces.c: the force model (chapter §3: stretch, shear, bending, gravity,
 * specified forces). Each element's force is minus the gradient of its
 * energy, so forces_energy and forces_accel agree exactly (a test checks
 * them against each other by finite differences). */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "forces.h"
#include "stop.h"
#include "vec3.h"

int
forces_init(struct forces *fo, const struct scene *sc, const struct cloth *cl,
    struct drape_err *err)
{
	size_t l, b;

	memset(fo, 0, sizeof *fo);
	fo->cl = cl;
	memcpy(fo->g, sc->gravity, sizeof fo->g);
	fo->damping = sc->mat.damping;
	fo->spring_damping = sc->mat.spring_damping;
	if (sc->nloads == 0)
		return 0;
	if ((fo->loads = calloc(sc->nloads, sizeof *fo->loads)) == NULL)
		goto oom;
	fo->nloads = (int)sc->nloads;
	for (l = 0; l < sc->nloads; l++) {
		const struct scene_load *sl = &sc->loads[l];
		struct load_group *lg = &fo->loads[l];
		unsigned char *in = calloc((size_t)cl->n, 1);
		int p;

		if (in == NULL)
			goto oom;
		if (!node_set_fits(&sl->nodes, cl->nu, cl->nv)) {
			free(in);
			forces_free(fo);
			err_set(err, "%s:%d: nodes: the set does not fit the %d x %d grid", sc->path,
			    sl->line, cl->nu, cl->nv);
			return -1;
		}
		for (b = 0; b < sl->nodes.n; b++)
			for (int j = sl->nodes.b[b].j0; j <= sl->nodes.b[b].j1; j++)
				for (int i = sl->nodes.b[b].i0; i <= sl->nodes.b[b].i1; i++)
					if (cloth_node(cl, i, j) >= 0)	/* else off the shape */
						in[cloth_node(cl, i, j)] = 1;
		for (p = 0; p < cl->n; p++)
			lg->n += in[p];
		if (lg->n == 0) {
			free(in);
			forces_free(fo);
			err_set(err, "%s:%d: nodes: the set has no node on the %s cloth; expected "
			    "grid positions inside its shape", sc->path, sl->line,
			    cloth_shape_name[cl->shape]);
			return -1;
		}
		if ((lg->node = malloc((size_t)lg->n * sizeof *lg->node)) == NULL) {
			free(in);
			goto oom;
		}
		for (p = 0, lg->n = 0; p < cl->n; p++)
			if (in[p])
				lg->node[lg->n++] = p;
		free(in);
		memcpy(lg->f, sl->force, sizeof lg->f);
		lg->start = sl->start;
		lg->stop = sl->stop;
	}
	return 0;
oom:
	forces_free(fo);
	err_set(err, "%s: out of memory", sc->path);
	return -1;
}

void
forces_free(struct forces *fo)
{
	int l;

	for (l = 0; l < fo->nloads; l++)
		free(fo->loads[l].node);
	free(fo->loads);
	memset(fo, 0, sizeof *fo);
}

void
forces_set_stop(struct forces *fo, const volatile sig_atomic_t *flag)
{
	fo->stop = flag;
}

bool
forces_stopped(const struct forces *fo)
{
	return stop_set(fo->stop);
}

bool
load_active(const struct load_group *lg, double t)
{
	return t >= lg->start && t < lg->stop;
}

/* Stretch: a linear spring along each yarn segment, with an optional
 * dashpot c = spring_damping * k on the relative velocity along it. */
static void
add_stretch(const struct forces *fo, const double *x, const double *v, double *f)
{
	const struct cloth *cl = fo->cl;
	double beta = fo->spring_damping;
	size_t s;

	for (s = 0; s < cl->nsprings; s++) {
		const struct spring *sp = &cl->springs[s];
		vec3 d = v3_sub(v3_load(x + 3 * sp->b), v3_load(x + 3 * sp->a));
		double len = v3_len(d), mag;

		if (forces_poll(fo, s))
			return;
		if (len == 0)
			continue;	/* direction undefined; no energy gradient either way */
		mag = sp->k * (len - sp->rest) / len;
		if (beta > 0) {
			vec3 dv = v3_sub(v3_load(v + 3 * sp->b), v3_load(v + 3 * sp->a));

			mag += beta * sp->k * v3_dot(dv, d) / (len * len);
		}
		v3_addto(f + 3 * sp->a, v3_scale(d, mag));
		v3_addto(f + 3 * sp->b, v3_scale(d, -mag));
	}
}

/* Shear: energy k*cos(phi)^2/2 at each corner, cos(phi) = sin(gamma) for
 * the shear angle gamma = phi - pi/2: the continuum's k*gamma^2/2 to within
 * 1 % up to 10 degrees of shear, with no trigonometry and no singularity
 * when the corner folds flat. d cos(phi)/dx_a = (u2 - cos(phi) u1)/|e1|. */
static void
add_shear(const struct forces *fo, const double *x, double *f)
{
	const struct cloth *cl = fo->cl;
	size_t s;

	for (s = 0; s < cl->ncorners; s++) {
		const struct corner *co = &cl->corners[s];
		vec3 xc = v3_load(x + 3 * co->c);
		vec3 e1 = v3_sub(v3_load(x + 3 * co->a), xc), e2 = v3_sub(v3_load(x + 3 * co->b), xc);
		double l1s = v3_dot(e1, e1), l2s = v3_dot(e2, e2), q, inv12, c, kc;
		vec3 fa, fb;

		if (forces_poll(fo, s))
			return;
		if (l1s == 0 || l2s == 0)
			continue;
		q = 1 / (l1s * l2s);
		inv12 = sqrt(q);		/* 1/(|e1||e2|) */
		c = v3_dot(e1, e2) * inv12;
		kc = -co->k * c;
		/* (u2 - c u1)/|e1| = e2/(|e1||e2|) - c e1/|e1|^2 */
		fa = v3_scale(v3_madd(v3_scale(e2, inv12), e1, -c * l2s * q), kc);
		fb = v3_scale(v3_madd(v3_scale(e1, inv12), e2, -c * l1s * q), kc);
		v3_addto(f + 3 * co->a, fa);
		v3_addto(f + 3 * co->b, fb);
		v3_addto(f + 3 * co->c, v3_neg(v3_add(fa, fb)));
	}
}

/* Bending: energy k*|kb|^2/2 at each hinge, with the curvature binormal of
 * discrete elastic rods (Bergou et al. 2008), kb = 2 e1 x e2 / D,
 * D = |e1'||e2'| + e1.e2 (rest lengths e'), e1 = b - a, e2 = c - b.
 * |kb| = 2 tan(theta/2) for the turning angle theta: the curvature times the
 * node spacing to within 0.1 % up to 6 degrees a hinge, and growing without
 * bound as the line folds back on itself. dE/de1 = -k (2 kb x e2 +
 * |kb|^2 e2)/D and dE/de2 = k (2 kb x e1 - |kb|^2 e1)/D. */
static void
add_bend(const struct forces *fo, const double *x, const double *v, double *f, double fold,
    double c, bool exact)
{
	const struct cloth *cl = fo->cl;
	double rest2 = cl->h * cl->h, dmin = fold * rest2;
	size_t s;

	for (s = 0; s < cl->nhinges; s++) {
		const struct hinge *hg = &cl->hinges[s];
		vec3 xb = v3_load(x + 3 * hg->b);
		vec3 e1 = v3_sub(xb, v3_load(x + 3 * hg->a)), e2 = v3_sub(v3_load(x + 3 * hg->c), xb);
		double d = rest2 + v3_dot(e1, e2), kd, kb2, kt;
		vec3 kb, ke1, ke2, fa, fc;
		bool held = false;

		if (forces_poll(fo, s))
			return;
		if (!(d > 1e-9 * rest2))
			continue;	/* folded right back: the energy has no gradient */
		if (d < dmin) {
			d = dmin;	/* the fold limiter (forces.h) */
			held = true;
		}
		kd = hg->k / d;
		kb = v3_scale(v3_cross(e1, e2), 2 / d);
		kb2 = v3_dot(kb, kb);
		ke2 = v3_cross(kb, e2);
		ke1 = v3_cross(kb, e1);
		/* |kb|^2's share through D: none where D is held, for the
		 * gradient of the held energy (exact); the fast path keeps it */
		kt = held && exact ? 0 : kb2;
		fa = v3_scale(v3_madd(v3_scale(ke2, 2), e2, kt), -kd);
		fc = v3_scale(v3_madd(v3_scale(ke1, 2), e1, -kt), -kd);
		if (c > 0 && kb2 > 0) {
			/* the dashpot (forces.h). The energy depends on |kb| alone,
			 * so its force is -k |kb| g, g the gradient of |kb|, and the
			 * dashpot's -c k g (g.v) is c (d|kb|/dt)/|kb| times it, with
			 * kb.(d kb/dt) = (2 kb.(d1 x e2 + e1 x d2) - |kb|^2 (d1.e2 +
			 * e1.d2))/D for e1, e2 moving at d1, d2. Its power, -c k
			 * (d|kb|/dt)^2, is never positive, and a turn of the whole
			 * hinge, which changes kb's direction and not its length,
			 * feels none. */
			vec3 vb = v3_load(v + 3 * hg->b);
			vec3 d1 = v3_sub(vb, v3_load(v + 3 * hg->a)), d2 = v3_sub(v3_load(v + 3 * hg->c), vb);
			double rate = (2 * (v3_dot(d2, ke1) - v3_dot(d1, ke2)) -
			    kb2 * (v3_dot(d1, e2) + v3_dot(e1, d2))) / d;
			double scale = 1 + c * rate / kb2;

			fa = v3_scale(fa, scale);
			fc = v3_scale(fc, scale);
		}
		v3_addto(f + 3 * hg->a, fa);
		v3_addto(f + 3 * hg->c, fc);
		v3_addto(f + 3 * hg->b, v3_neg(v3_add(fa, fc)));
	}
}

static void
accel(const struct forces *fo, double t, const double *x, const double *v, double *a,
    bool stretch, bool shear, double fold, double bend_damping, bool exact)
{
	const struct cloth *cl = fo->cl;
	vec3 g = v3_load(fo->g);
	int p, l, k;

	memset(a, 0, (size_t)cl->n * 3 * sizeof *a);
	if (stretch)
		add_stretch(fo, x, v, a);
	if (shear && cl->ncorners > 0 && !forces_stopped(fo))
		add_shear(fo, x, a);
	if (cl->nhinges > 0 && !forces_stopped(fo))
		add_bend(fo, x, v, a, fold, bend_damping, exact);
	for (l = 0; l < fo->nloads; l++)
		if (load_active(&fo->loads[l], t))
			for (k = 0; k < fo->loads[l].n; k++)
				v3_addto(a + 3 * fo->loads[l].node[k], v3_load(fo->loads[l].f));
	if (fo->damping > 0) {
		for (p = 0; p < cl->n; p++)
			v3_store(a + 3 * p, v3_madd(v3_madd(g, v3_load(a + 3 * p), 1 / cl->mass[p]),
			    v3_load(v + 3 * p), -fo->damping));
	} else {
		for (p = 0; p < cl->n; p++)
			v3_store(a + 3 * p, v3_madd(g, v3_load(a + 3 * p), 1 / cl->mass[p]));
	}
}

void
forces_accel(const struct forces *fo, double t, const double *x, const double *v, double *a)
{
	accel(fo, t, x, v, a, true, true, fo->fold, 0, true);
}

void
forces_accel_bending(const struct forces *fo, double t, const double *x, const double *v,
    double *a, double fold, double c)
{
	accel(fo, t, x, v, a, false, false, fold, c, false);
}

double
forces_fold_limit(double s)
{
	/* a hinge of turning angle theta has stiffness k sec^2(theta/2)
	 * (3 sec^2(theta/2) - 2) along theta, and sec^2(theta/2) = 2 rest^2/D:
	 * with u = rest^2/D, 12 u^2 - 4 u = s */
	double u = (4 + sqrt(16 + 48 * s)) / 24;

	return 1 / u;
}

double
forces_explicit_fold(const struct cloth *cl)
{
	double wb = cloth_omega_bound_bend(cl), w = cloth_omega_bound(cl);

	if (cl->nhinges == 0 || !(wb > 0))
		return 0;
	return forces_fold_limit(fmax(w * w / (wb * wb), 2));
}

void
forces_energy(const struct forces *fo, double t, const double *x, const double *v,
    struct energy *e)
{
	const struct cloth *cl = fo->cl;
	vec3 g = v3_load(fo->g);
	size_t s;
	int p, l, k;

	memset(e, 0, sizeof *e);
	for (p = 0; p < cl->n; p++) {
		vec3 vp = v3_load(v + 3 * p);

		e->kinetic += 0.5 * cl->mass[p] * v3_dot(vp, vp);
		e->gravity -= cl->mass[p] * v3_dot(g, v3_load(x + 3 * p));
	}
	for (s = 0; s < cl->nsprings; s++) {
		const struct spring *sp = &cl->springs[s];
		double d = v3_len(v3_sub(v3_load(x + 3 * sp->b), v3_load(x + 3 * sp->a))) - sp->rest;

		e->stretch += 0.5 * sp->k * d * d;
	}
	for (s = 0; s < cl->ncorners; s++) {
		const struct corner *co = &cl->corners[s];
		vec3 xc = v3_load(x + 3 * co->c);
		vec3 e1 = v3_sub(v3_load(x + 3 * co->a), xc), e2 = v3_sub(v3_load(x + 3 * co->b), xc);
		double c = v3_dot(e1, e2) / sqrt(v3_dot(e1, e1) * v3_dot(e2, e2));

		e->shear += 0.5 * co->k * c * c;
	}
	for (s = 0; s < cl->nhinges; s++) {
		const struct hinge *hg = &cl->hinges[s];
		vec3 xb = v3_load(x + 3 * hg->b);
		vec3 e1 = v3_sub(xb, v3_load(x + 3 * hg->a)), e2 = v3_sub(v3_load(x + 3 * hg->c), xb);
		double rest2 = cl->h * cl->h, d = rest2 + v3_dot(e1, e2);
		vec3 kb;

		if (fo->fold > 0) {	/* as forces_accel's limiter (add_bend) */
			if (!(d > 1e-9 * rest2))
				continue;
			d = fmax(d, fo->fold * rest2);
		}
		kb = v3_scale(v3_cross(e1, e2), 2 / d);
		e->bend += 0.5 * hg->k * v3_dot(kb, kb);
	}
	for (l = 0; l < fo->nloads; l++)
		if (load_active(&fo->loads[l], t))
			for (k = 0; k < fo->loads[l].n; k++)
				e->load -= v3_dot(v3_load(fo->loads[l].f),
				    v3_load(x + 3 * fo->loads[l].node[k]));
}

double
forces_elastic(const struct forces *fo, const double *x, double *f)
{
	const struct cloth *cl = fo->cl;
	double rest2 = cl->h * cl->h, e = 0;
	size_t s;

	if (f != NULL)
		memset(f, 0, (size_t)cl->n * 3 * sizeof *f);
	for (s = 0; s < cl->nsprings; s++) {
		const struct spring *sp = &cl->springs[s];
		vec3 d = v3_sub(v3_load(x + 3 * sp->b), v3_load(x + 3 * sp->a));
		double len = v3_len(d), ext = len - sp->rest;

		e += 0.5 * sp->k * ext * ext;
		if (f != NULL && len > 0) {
			vec3 fa = v3_scale(d, sp->k * ext / len);

			v3_addto(f + 3 * sp->a, fa);
			v3_addto(f + 3 * sp->b, v3_neg(fa));
		}
	}
	for (s = 0; s < cl->ncorners; s++) {
		const struct corner *co = &cl->corners[s];
		vec3 xc = v3_load(x + 3 * co->c);
		vec3 e1 = v3_sub(v3_load(x + 3 * co->a), xc), e2 = v3_sub(v3_load(x + 3 * co->b), xc);
		double l1s = v3_dot(e1, e1), l2s = v3_dot(e2, e2), q, inv12, c, kc;
		vec3 fa, fb;

		if (l1s == 0 || l2s == 0)
			continue;
		q = 1 / (l1s * l2s);
		inv12 = sqrt(q);
		c = v3_dot(e1, e2) * inv12;
		e += 0.5 * co->k * c * c;
		if (f == NULL)
			continue;
		kc = -co->k * c;	/* as add_shear */
		fa = v3_scale(v3_madd(v3_scale(e2, inv12), e1, -c * l2s * q), kc);
		fb = v3_scale(v3_madd(v3_scale(e1, inv12), e2, -c * l1s * q), kc);
		v3_addto(f + 3 * co->a, fa);
		v3_addto(f + 3 * co->b, fb);
		v3_addto(f + 3 * co->c, v3_neg(v3_add(fa, fb)));
	}
	for (s = 0; s < cl->nhinges; s++) {
		const struct hinge *hg = &cl->hinges[s];
		vec3 xb = v3_load(x + 3 * hg->b);
		vec3 e1 = v3_sub(xb, v3_load(x + 3 * hg->a)), e2 = v3_sub(v3_load(x + 3 * hg->c), xb);
		double d = rest2 + v3_dot(e1, e2), kd, kb2;
		vec3 kb, fa, fc;

		if (!(d > 1e-9 * rest2)) {
			/* folded right back: the barrier, and no gradient, as
			 * add_bend; the other elements' forces are still given */
			e = INFINITY;
			continue;
		}
		kb = v3_scale(v3_cross(e1, e2), 2 / d);
		kb2 = v3_dot(kb, kb);
		e += 0.5 * hg->k * kb2;
		if (f == NULL)
			continue;
		kd = hg->k / d;		/* as add_bend */
		fa = v3_scale(v3_madd(v3_scale(v3_cross(kb, e2), 2), e2, kb2), -kd);
		fc = v3_scale(v3_madd(v3_scale(v3_cross(kb, e1), 2), e1, -kb2), -kd);
		v3_addto(f + 3 * hg->a, fa);
		v3_addto(f + 3 * hg->c, fc);
		v3_addto(f + 3 * hg->b, v3_neg(v3_add(fa, fc)));
	}
	return e;
}

double
energy_total(const struct energy *e)
{
	return e->kinetic + e->gravity + e->stretch + e->shear + e->bend + e->load;
}

double
forces_load_speed(const struct forces *fo, double duration)
{
	double best = 0;
	int l, k;

	for (l = 0; l < fo->nloads; l++) {
		const struct load_group *lg = &fo->loads[l];
		double m = INFINITY, t = fmin(lg->stop, duration) - fmax(lg->start, 0);

		for (k = 0; k < lg->n; k++)
			m = fmin(m, fo->cl->mass[lg->node[k]]);
		if (t > 0)
			best += v3_len(v3_load(lg->f)) / m * t;
	}
	return best;
}
