/* forces.h: accelerations and energy of the network: internal forces
 * (stretch, shear, bending, damping) and external ones (gravity, loads). */
#ifndef DRAPE_FORCES_H
#define DRAPE_FORCES_H

#include "cloth.h"
#include "err.h"
#include "scene.h"

struct load_group {
	int *node;
	int n;
	double f[3];
	double start, stop;
};

struct forces {
	const struct cloth *cl;
	double g[3];		/* m/s2 */
	double damping;		/* 1/s */
	double spring_damping;	/* s */
	struct load_group *loads;
	int nloads;
};

struct energy {
	double kinetic, gravity, stretch, shear, bend, load;
};

int forces_init(struct forces *fo, const struct scene *sc, const struct cloth *cl,
    struct drape_err *err);
void forces_free(struct forces *fo);

/* a = F/m for every node, from positions x and velocities v (3n each). */
void forces_accel(const struct forces *fo, double t, const double *x, const double *v, double *a);

void forces_energy(const struct forces *fo, double t, const double *x, const double *v,
    struct energy *e);
double energy_total(const struct energy *e);

/* The speed the loads could give a node on its own over the run's first
 * `duration` seconds (each set's force over its lightest node's mass, for
 * as long as it acts), in m/s: a scale for the speeds a run reaches. */
double forces_load_speed(const struct forces *fo, double duration);

#endif
